"""Impossible scenes are refused, implausible ones warn (exdex.PlausibilityWarning).

References are hand geometry of a 15 cm cube (half side 0.075 m): a patch
centre at x = 0.3 m is 0.3 - 0.075 = 0.225 m outside its face; a disc pad of
radius 1 cm overlaps the face iff its centre is within 0.085 m of the face
(along x at y = 0); the cube's density is m / 0.15^3.
"""
import math
import warnings

import numpy as np
import pytest

import exdex
from exdex.scene import DENSITY_RANGE

SIDE = 0.15
CUBE = exdex.Body.box(0.5, (SIDE, SIDE, SIDE))     # 148 kg/m^3


def scene(patch=None, pad=None, body=CUBE, **kw):
    grasp = exdex.Grasp(mu=0.5, grip_force=5.0, patch=patch or exdex.Patch.rectangle(0.02, 0.02), pad=pad)
    return exdex.Scene(body=body, grasp=grasp, **kw)


def no_warnings(make):
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        return make()


def test_patch_centre_outside_the_face_is_refused():
    with pytest.raises(ValueError, match=r"Grasp\.patch\.center = \(0\.3, 0\) m lies 0\.225 m outside the object's "
                                         r"contact face.*Body\.size"):
        scene(exdex.Patch.rectangle(0.02, 0.02, center=(0.3, 0.0)))
    with pytest.raises(ValueError, match=r"Grasp\.patch\.center.*outside.*Body\.outline_radius"):
        scene(exdex.Patch.disc(0.005, center=(0.0, 0.031)), body=exdex.Body.cylinder(0.1, 0.03, 0.02))
    for dof in ("translation", "rotation", "planar"):
        no_warnings(lambda: scene(exdex.Patch.rectangle(0.02, 0.02, center=(0.065, -0.065)), dof=dof))
        no_warnings(lambda: scene(exdex.Patch(e_r=0.01, center=(0.075, 0.075)), dof=dof))   # on the corner
    no_warnings(lambda: exdex.Scene(body=exdex.Body(0.5), grasp=exdex.Grasp(0.5, 5.0, patch=exdex.Patch(
        e_r=0.01, center=(3.0, 0.0)))))                 # a body without a face: nothing to check


def test_pad_that_misses_the_face_is_refused():
    miss = dict(dof="planar")
    with pytest.raises(ValueError, match=r"Grasp\.pad \(a disc of radius 0\.01 m about \(0\.0851, 0\) m.*misses "
                                         r"the object's contact face.*Scene\.q0"):
        scene(pad=exdex.Pad.disc(0.01, center=(0.0851, 0.0)), **miss)
    no_warnings(lambda: scene(pad=exdex.Pad.disc(0.01, center=(0.0849, 0.0)), **miss))
    with pytest.raises(ValueError, match=r"Grasp\.pad \(a polygon"):
        scene(pad=exdex.Pad.rectangle(0.02, 0.02, center=(0.0, 0.0851)), **miss)
    no_warnings(lambda: scene(pad=exdex.Pad.rectangle(0.02, 0.02, center=(0.0, 0.0849)), **miss))
    # the face follows Scene.q0: moved by 0.1 m and turned by 45 deg, the corner reaches 0.1 + 0.075 sqrt(2)
    q0 = (0.1, 0.0, math.pi / 4)
    reach = 0.1 + 0.075 * math.sqrt(2.0)
    no_warnings(lambda: scene(pad=exdex.Pad.disc(0.01, center=(reach + 0.0099, 0.0)), q0=q0, **miss))
    with pytest.raises(ValueError, match="misses"):
        scene(pad=exdex.Pad.disc(0.01, center=(reach + 0.0101, 0.0)), q0=q0, **miss)
    # a pad larger than the face holds the whole face: an ordinary grasp
    no_warnings(lambda: scene(pad=exdex.Pad.rectangle(0.5, 0.5), **miss))


def test_density_far_outside_solids_warns_naming_the_field():
    with pytest.warns(exdex.PlausibilityWarning, match=r"Body\.mass = 200 kg .*density of 5\.926e\+04 kg/m\^3, "
                                                       r"outside the 10 \.\. 25000 kg/m\^3") as rec:
        exdex.Body.box(200.0, (SIDE, SIDE, SIDE))
    w = rec[0].message
    assert isinstance(w, exdex.PhysicsWarning) and w.kind == "plausibility" and w.field == "Body.mass"
    assert w.value == pytest.approx(200.0 / SIDE**3, rel=1e-12) and w.limit == DENSITY_RANGE[1]
    assert rec[0].filename == __file__
    vol = SIDE**3
    lo, hi = DENSITY_RANGE
    no_warnings(lambda: exdex.Body.box(0.999 * hi * vol, (SIDE, SIDE, SIDE)))
    no_warnings(lambda: exdex.Body.box(1.001 * lo * vol, (SIDE, SIDE, SIDE)))
    with pytest.warns(exdex.PlausibilityWarning, match=r"density of 9\.99 kg/m\^3"):
        exdex.Body.box(0.999 * lo * vol, (SIDE, SIDE, SIDE))
    # a cylinder's volume is pi r^2 h
    with pytest.warns(exdex.PlausibilityWarning, match="cylinder of radius 0.03 m") as rec:
        exdex.Body.cylinder(1.001 * hi * math.pi * 0.03**2 * 0.02, 0.03, 0.02)
    assert rec[0].message.value == pytest.approx(1.001 * hi, rel=1e-12)
    no_warnings(lambda: exdex.Body.cylinder(0.999 * hi * math.pi * 0.03**2 * 0.02, 0.03, 0.02))
    no_warnings(lambda: exdex.Body(mass=1e4))           # no size: no volume to check


def test_patch_larger_than_the_face_warns():
    with pytest.warns(exdex.PlausibilityWarning, match=r"Grasp\.patch \(a 0\.5 x 0\.5 m rectangle\) is larger than "
                                                       r"the object's contact face.*width 0\.5 m exceeds the face's "
                                                       r"width 0\.15 m") as rec:
        scene(exdex.Patch.rectangle(0.5, 0.5))
    assert rec[0].message.field == "Grasp.patch" and rec[0].filename == __file__
    with pytest.warns(exdex.PlausibilityWarning, match=r"Grasp\.patch \(a disc of radius 0\.08 m\)"):
        scene(exdex.Patch.disc(0.08))
    with pytest.warns(exdex.PlausibilityWarning, match=r"Grasp\.patch\.e_r = 0\.2 m exceeds 0\.1061 m"):
        scene(exdex.Patch(e_r=0.2))                     # e_r is a mean distance: at most the farthest, 0.075 sqrt 2
    with pytest.warns(exdex.PlausibilityWarning, match="diagonal"):
        scene(exdex.Patch.rectangle(0.05, 0.05), body=exdex.Body.cylinder(0.1, 0.0175, 0.02))   # 7.07 cm > 3.5 cm
    no_warnings(lambda: scene(exdex.Patch.rectangle(SIDE, SIDE)))   # the whole face
    no_warnings(lambda: scene(exdex.Patch.disc(SIDE / 2)))
    no_warnings(lambda: scene(exdex.Patch(e_r=0.1)))


@pytest.mark.warns_by_design("outline")
def test_a_patch_leaving_the_face_later_still_warns_when_it_does():
    """Refusing the start leaves the run's own check: a patch near the edge of
    a weakly held box slides off during the run (the "outline" warning)."""
    sc = exdex.Scene(body=exdex.Body.box(0.1, (0.03, 0.06, 0.02)),
                     grasp=exdex.Grasp(mu=0.5, grip_force=0.3, patch=exdex.Patch.rectangle(0.01, 0.01,
                                                                                          center=(0.0, 0.02))))
    with pytest.warns(exdex.PhysicsWarning, match="outside the body outline") as rec:
        exdex.simulate(sc, 0.3, 1e-3)
    assert any(w.message.kind == "outline" and w.message.time > 0 for w in rec)

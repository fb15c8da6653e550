"""exdex._params: the names a batch, a plan or a fit may vary, their
aliases, and the scene with new values (each checked against the scene
written out by hand with dataclasses.replace)."""
import dataclasses

import pytest

import exdex
from exdex._params import ALIASES, PARAMETERS, param_name, replace_params


def _scene():
    return exdex.Scene(body=exdex.Body(mass=0.1), grasp=exdex.Grasp(mu=0.5, grip_force=1.5),
                       motion=exdex.AsymmetricProfile(0.1, 0.5, 0.9))


def test_replace_params_equals_replace_by_hand():
    sc = _scene()
    got = replace_params(sc, {"mu": 0.4, "mass": 0.2, "beta": 0.8, "patch_x": 0.01})
    want = dataclasses.replace(
        sc, grasp=dataclasses.replace(sc.grasp, mu=0.4, patch=dataclasses.replace(sc.grasp.patch, center=(0.01, 0.0))),
        body=dataclasses.replace(sc.body, mass=0.2), motion=dataclasses.replace(sc.motion, beta=0.8))
    assert got == want


def test_grip_force_scales_a_schedule():
    sched = exdex.GripSchedule([0.0, 1.0], [1.0, 2.0])
    sc = dataclasses.replace(_scene(), grasp=dataclasses.replace(_scene().grasp, grip_force=sched))
    assert replace_params(sc, {"grip_force": 3.0}).grasp.grip_force == sched.scaled(3.0)


def test_aliases_and_unknown_names():
    sc = _scene()
    assert all(param_name(a, sc) == n for a, n in ALIASES.items() if not PARAMETERS[n].motions
               or isinstance(sc.motion, PARAMETERS[n].motions))
    with pytest.raises(ValueError, match="cannot vary 'colour'"):
        param_name("colour", sc)
    with pytest.raises(ValueError, match="has no such field"):
        param_name("v_max", sc)   # an Eq. 7 motion has no v_max

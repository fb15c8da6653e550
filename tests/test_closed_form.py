"""exdex._closed_form: the 1-DoF Coulomb closed form against hand-derived
motions (constant drives from rest: x = a t^2 / 2 while sliding, a stop at
t = -v / a), paper Eq. 9's accelerations, and the scenes it refuses."""
import math

import numpy as np
import pytest

import exdex
from exdex import _closed_form as cf
from exdex.studies import paper


def test_the_paper_lists_the_closed_form_as_its_own():
    for name in ("closed_form", "coulomb_1dof", "eq7_accelerations", "eq7_phases", "PiecewiseMotion"):
        assert getattr(paper, name) is getattr(cf, name) and name in paper.__all__


def test_slide_then_stop_by_hand():
    # drive 2 on [0, 1), 0 after, capacity 1, from rest: a = 1 to v = 1 at t = 1, x = 0.5;
    # then a = -1 to rest at t = 2, x = 0.5 + 1 - 0.5 = 1
    m = cf.coulomb_1dof([(0.0, 1.0, 2.0), (1.0, math.inf, 0.0)], 1.0)
    assert m.events == ((0.0, "slip"), (2.0, "stick"))
    assert m.final == 1.0 and m.rest_time == 2.0
    x, v = m(np.array([0.5, 1.0, 1.5, 3.0]))
    np.testing.assert_allclose(x, [0.125, 0.5, 0.875, 1.0], rtol=0, atol=1e-15)
    np.testing.assert_allclose(v, [0.5, 1.0, 0.5, 0.0], rtol=0, atol=1e-15)


def test_a_drive_within_the_capacity_sticks_exactly():
    m = cf.coulomb_1dof([(0.0, math.inf, -0.999)], 1.0)
    assert m.events == () and m.final == 0.0 and m.rest_time == 0.0
    with pytest.raises(ValueError, match="capacity must be >= 0"):
        cf.coulomb_1dof([(0.0, 1.0, 1.0)], -1.0)


def test_eq9_accelerations_and_phases_return_to_rest():
    a_h, a_l = cf.eq7_accelerations(0.1, 0.5, 0.9)
    assert a_h == pytest.approx(2 * 0.1 / (0.9 * 0.25), rel=1e-15)
    assert a_l == pytest.approx(2 * 0.1 / (-0.1 * 0.25), rel=1e-15)
    ph = cf.eq7_phases(0.1, 0.5, 0.9)
    v = sum(a * (t1 - t0) for t0, t1, a in ph[:-1])
    assert abs(v) <= 1e-12 and ph[-1] == (1.0, math.inf, 0.0)


def test_closed_form_refuses_what_it_does_not_solve():
    sc = paper.fig3_scene()
    assert cf.closed_form(sc).final == pytest.approx(-0.020, abs=1e-9)   # the paper's 20 mm (fig3_grip_force)
    with pytest.raises(ValueError, match="1-DoF"):
        cf.closed_form(exdex.replace(sc, dof="planar"))
    with pytest.raises(ValueError, match="AsymmetricProfile"):
        cf.closed_form(exdex.replace(sc, motion=exdex.Rest()))
    np.testing.assert_allclose(cf.world_dir(sc, (1.0, 0.0)), np.array(sc.gripper_rotation)[:, 0], rtol=0, atol=0)

"""Result.wrench at t = 0: the wrench that holds the object there.

Independent check: the static balance at t = 0 of gravity and the inertial
force of the accelerating gripper (closed form, no simulation): Fig. 3's
gripper starts accelerating down at a_H, so the plates carry m (g - a_H)
along the slide axis; an object held at rest by a patch beside its centre of
mass carries its weight and the weight's moment about the patch."""
import numpy as np
import pytest

import exdex
from exdex import paper

G = 9.81


@pytest.mark.parametrize("method", ["implicit", "event", "analytic", "explicit", "regularised"])
def test_row_0_is_the_holding_wrench_of_the_accelerating_gripper(method):
    sc = paper.fig3_scene()
    res = exdex.simulate(sc, 1.5, 1e-3, method=method)
    m, a = sc.body.mass, sc.motion.a_high
    assert res.stick[0]
    np.testing.assert_allclose(res.wrench[0], [0.0, m * (G - a), 0.0], rtol=1e-12, atol=1e-15)


def test_planar_row_0_balances_the_weight_and_its_moment():
    sc = paper.fig3_scene()
    cx = 0.01
    sc = exdex.replace(sc, dof="planar", motion=exdex.Rest(),
                       grasp=exdex.replace(sc.grasp, grip_force=3.0, patch=exdex.Patch(e_r=0.01, center=(cx, 0.0))))
    m = sc.body.mass
    # weight -m g along B's y at the centre of mass, cx beside the centre of
    # pressure: the friction carries +m g and the opposite moment -cx m g
    want = [0.0, m * G, -cx * m * G]
    for res in (exdex.simulate(sc, 0.5, 1e-3, method="event"), exdex.Model(sc).simulate(0.5, 1e-3),
                exdex.simulate_batch(sc, 0.5, 1e-3, grip_force=np.array([3.0, 4.0]))[1]):
        np.testing.assert_allclose(res.wrench[0], want, rtol=1e-12, atol=1e-15)


def test_the_stepper_starts_with_the_same_wrench():
    sc = paper.fig3_scene()
    st = exdex.Stepper(sc)
    np.testing.assert_array_equal(st.state.wrench, exdex.simulate(sc, 0.01, 1e-3).wrench[0])
    np.testing.assert_allclose(st.state.wrench, [0.0, sc.body.mass * (G - sc.motion.a_high), 0.0], rtol=1e-12)


def test_a_run_that_slips_at_once_has_no_holding_wrench():
    sc = paper.fig3_scene()
    sc = exdex.replace(sc, grasp=exdex.replace(sc.grasp, grip_force=0.3))   # capacity 0.3 N < m (g - a_H)
    res = exdex.simulate(sc, 0.1, 1e-3)
    assert not res.stick[1]
    np.testing.assert_array_equal(res.wrench[0], [0.0, 0.0, 0.0])

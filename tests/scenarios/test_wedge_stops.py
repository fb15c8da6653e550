"""Event method: an object between two nearly opposed stops (planar).

The scene is a fuzz input (csrc/fuzz/corpus/simulate/wedge-two-stops) given
to the core as its flat spec with the exact doubles. Two outline vertices
touch two stops whose in-plane rows are nearly opposed; vertex 1 lifts off
stop 1 at a gap rate of a few um/s, below the event method's Zeno hold
threshold. Holding both rows at rate 0 would need a pull on both stops, which
no stop can give.

Reference (independent of the hold): a stop pushes only, so the stop whose
row is separating carries no force, and the motion is the one with that stop
removed. Hence
    stop_force[:, 1] == 0 and stop_force[:, 0] == the one-stop scene's force,
    and the trajectory equals the one-stop scene's;
and the implicit method (fixed step, its own contact solve) must also put no
force on stop 1 and the same force on stop 0 up to its one-step error (the
step is the whole run, h = 4.45 ms; the relative difference of the mean force
is O(h |v| / L) ~ 1e-5 here, bounded by 1e-3).

twin: csrc/tests/scenarios/test_wedge_stops.c (the same subject on the C API)
"""
import numpy as np

from exdex import _core

T_END = 0.004452489262315929


def _spec(n_stops=2, method=_core.METHOD_EVENT):
    points = np.array([[-0.8001788821141842, 0.42082754812831502, 0.42591935813058623],
                       [0.73381198196706499, 1.2576907430518904, -0.86388019631132007]])
    normals = np.array([[-0.80066368331536042, 0.42108251324346729, 0.42617740820044103],
                        [0.43341571842420701, 0.74283733483623493, -0.51023867845962823]])
    return dict(
        mass=9.132626770902311,
        inertia=np.array([0.055122824092677013, -0.0087811566424874643, 0.0,
                          -0.0087811566424874643, 0.069133000374239806, 0.0,
                          0.0, 0.0, 0.044410478815152199]),
        vertices=np.array([[0.0072280840539597074, 0.040473816424790421],
                           [-0.020529784645506224, 0.0083102875743806121]]),
        mu=0.74916603304280549, grip_force=0.0026310180267177284, fingers=1, mu_static=0.0,
        e_r=0.0023690718916116191, patch_center=(0.019753055743108462, 0.025916396096897644),
        gravity=(0.0, 0.0, -9.81), dof=_core.DOF_PLANAR, slide_axis=(0.50519507687289711, -0.86300517629003104),
        q0=(-0.0061257966646439815, 0.024607908938051454, -0.34758493929062562), v0=(0.0, 0.0, 0.0),
        R0=np.array([-0.52499513320740521, -0.767850183872129, 0.36713240831623251,
                     -0.21733486374369038, -0.29611189486558587, -0.93009854462880648,
                     0.82288861160551419, -0.56808788127071497, -0.011423311398161662]),
        p0=(-1.0187268427095364, 1.9156756370298962, -1.448551316323214),
        motion_kind=_core.MOTION_REST, motion_rotation=0, motion_axis=(0.0, 0.0, 1.0),
        motion_center=(0.0, 0.0, 0.0), motion_amplitude=0.0, motion_duration=1.0, motion_beta=0.5,
        motion_v_max=1.0,
        stop_points=points[:n_stops], stop_normals=normals[:n_stops], stop_mus=np.zeros(n_stops),
        method=method, friction_solver=_core.SOLVER_BRENT,
        eps=0.0026218094842571744, rtol=8.3498963157401866e-08, atol=1.4648260118039653e-07)


def test_wedge_stop_forces_finite_nonnegative_and_equal_to_one_stop_scene():
    two = _core.simulate(_spec(2), T_END, T_END)
    one = _core.simulate(_spec(1), T_END, T_END)
    f2, f1 = two["stop_force"], one["stop_force"]
    assert np.all(np.isfinite(f2)) and np.all(f2 >= 0.0), f2
    assert f1[-1, 0] > 0.0  # the scene does press on stop 0
    np.testing.assert_array_equal(f2[:, 1], 0.0)
    np.testing.assert_allclose(f2.sum(axis=1), f1[:, 0], rtol=1e-12, atol=0.0)
    np.testing.assert_allclose(two["q"], one["q"], rtol=0.0, atol=1e-12)
    np.testing.assert_allclose(two["v"], one["v"], rtol=0.0, atol=1e-12)


def test_wedge_agrees_with_implicit_method():
    ev = _core.simulate(_spec(2), T_END, T_END)["stop_force"]
    im = _core.simulate(_spec(2, _core.METHOD_IMPLICIT), T_END, T_END)["stop_force"]
    assert np.all(np.isfinite(im)) and np.all(im >= 0.0), im
    np.testing.assert_array_equal(im[:, 1], 0.0)
    np.testing.assert_allclose(ev[-1, 0], im[-1, 0], rtol=1e-3)

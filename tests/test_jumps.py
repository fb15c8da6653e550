"""exdex._jumps: the gripper's velocity jumps of a scene and their warning.

References, by hand: a trapezoid without ramps (v_max = |X1| / T) starts and
stops at full speed, so the gripper's velocity (in A) jumps by v_max times
the axis at t = 0 and by minus that at t = T (an angular one: its angular
velocity, about an axis through B's origin, so B's origin does not move); a
log moving at a constant 0.1 m/s from its first to its last sample jumps by
+0.1 m/s at the first and -0.1 m/s at the last; a motion whose velocity is
continuous by construction (Rest, Eq. 7, a trapezoid with ramps) has none.
warn_jumps warns once per jump in (0, t_end], at the caller's line, with the
hint that fits the motion."""
import warnings

import numpy as np
import pytest

import exdex
from exdex._jumps import GripperJumpWarning, jumps, warn_jumps


def _scene(motion):
    return exdex.Scene(body=exdex.Body(mass=0.1, size=(0.04, 0.06, 0.03)), grasp=exdex.Grasp(mu=0.5, grip_force=1.5),
                       motion=motion)


def _jumps_of(motion):
    scene = _scene(motion)
    return jumps(scene, scene.to_spec())


def _log_at_speed(t0=0.1, t1=0.2, n=11, v=0.1):
    t = np.linspace(t0, t1, n)
    p = np.column_stack([v * (t - t0), np.zeros(n), np.zeros(n)])
    return exdex.SampledTrajectory(t, p, np.tile([1.0, 0.0, 0.0, 0.0], (n, 1)))


def test_a_trapezoid_without_ramps_jumps_by_its_speed_at_both_ends():
    (t0, dv0, dw0), (t1, dv1, dw1) = _jumps_of(exdex.TrapezoidalProfile(0.05, 0.5, 0.1, axis=(0, 0, -1)))
    assert (t0, t1) == (0.0, 0.5)
    assert np.array_equal(dv0, (0.0, 0.0, -0.1)) and np.array_equal(dv1, (0.0, 0.0, 0.1))
    assert np.array_equal(dw0, (0.0, 0.0, 0.0)) and np.array_equal(dw1, (0.0, 0.0, 0.0))
    (t0, dv0, dw0), (t1, dv1, dw1) = _jumps_of(exdex.TrapezoidalProfile(0.5, 0.5, 1.0, axis=(0, 1, 0), rotation=True))
    assert (t0, t1) == (0.0, 0.5)
    assert np.array_equal(dw0, (0.0, 1.0, 0.0)) and np.array_equal(dw1, (0.0, -1.0, 0.0))
    assert np.array_equal(dv0, (0.0, 0.0, 0.0)) and np.array_equal(dv1, (0.0, 0.0, 0.0))


def test_a_log_at_speed_jumps_at_its_first_and_last_sample():
    (t0, dv0, dw0), (t1, dv1, dw1) = _jumps_of(_log_at_speed())
    assert (t0, t1) == (0.1, 0.2)
    # the end velocity is the quadratic's through the three end samples: exact up to rounding
    assert np.allclose(dv0, (0.1, 0.0, 0.0), rtol=0, atol=1e-15) and np.allclose(dv1, (-0.1, 0.0, 0.0), rtol=0,
                                                                                   atol=1e-15)
    assert np.array_equal(dw0, (0.0, 0.0, 0.0)) and np.array_equal(dw1, (0.0, 0.0, 0.0))


@pytest.mark.parametrize("motion", [exdex.Rest(), exdex.AsymmetricProfile(0.1, 0.5, 0.9),
                                    exdex.TrapezoidalProfile(0.05, 0.5, 0.12)])
def test_continuous_motions_have_no_jumps(motion):
    assert _jumps_of(motion) == []


def _warned(scene, js, t_end):
    with warnings.catch_warnings(record=True) as seen:
        warnings.simplefilter("always")
        warn_jumps(scene, js, t_end)
    return [w for w in seen if issubclass(w.category, GripperJumpWarning)]


def test_warn_jumps_warns_once_per_jump_inside_the_run():
    scene = _scene(exdex.TrapezoidalProfile(0.05, 0.5, 0.1, axis=(0, 0, -1)))
    js = [(0.0, (0.0, 0.0, -0.1), (0.0, 0.0, 0.0)), (0.5, (0.0, 0.0, 0.1), (0.0, 0.0, 0.0)),
          (2.0, (0.0, 0.3, 0.4), (0.0, 0.0, 0.0))]
    assert [w.message.t for w in _warned(scene, js, 1.0)] == [0.5]      # t = 0 is the start, 2 s after the end
    assert [w.message.t for w in _warned(scene, js, 0.5)] == [0.5]      # (0, t_end]: the end counts
    assert [w.message.t for w in _warned(scene, js, 0.4999)] == []
    assert [w.message.t for w in _warned(scene, js, 3.0)] == [0.5, 2.0]
    (w,) = _warned(scene, js[1:2], 1.0)
    assert w.filename == __file__                                       # the caller's line, outside exdex
    m = w.message
    assert isinstance(m, exdex.PhysicsWarning) and m.kind == "gripper_jump"
    assert np.array_equal(m.dv, (0.0, 0.0, 0.1)) and np.array_equal(m.dw, (0.0, 0.0, 0.0))
    assert m.value == pytest.approx(0.1, rel=1e-15)
    text = str(m)
    assert "at t = 0.5 s by |dv| = 0.1 m/s, |dw| = 0 rad/s (dv = (0, 0, 0.1), dw = (0, 0, 0)" in text
    assert text.endswith("(a trapezoid without ramps, v_max = |amplitude| / duration).")
    (w,) = _warned(scene, js[2:], 3.0)
    assert "|dv| = 0.5 m/s" in str(w.message)                          # |(0, 0.3, 0.4)|


def test_a_log_at_speed_is_told_which_end_to_give_a_velocity():
    scene = _scene(_log_at_speed())
    start, end = _warned(scene, jumps(scene, scene.to_spec()), 1.0)
    assert "The log starts at speed" in str(start.message)
    assert "SampledTrajectory(start_velocity=(0, 0, 0), start_omega=(0, 0, 0))" in str(start.message)
    assert "The log ends at speed" in str(end.message)
    assert "SampledTrajectory(end_velocity=(0, 0, 0), end_omega=(0, 0, 0))" in str(end.message)

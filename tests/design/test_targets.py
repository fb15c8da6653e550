"""exdex.design._targets, what the inverse-design modules share: the peaks of
a gripper motion against their closed forms (Eq. 9, the trapezoid's ramps, a
sampled quadratic's exact differences), the target quantities checked
against the scene's free coordinates, and the unreachable target's error."""
import math

import numpy as np
import pytest

import exdex
from exdex.design._targets import QUANTITIES, QUANTITY_HELP, UnreachableTargetError, check_quantity, motion_peaks


def test_motion_peaks_closed_forms():
    """Eq. 9: a_H = 2 X1/(beta T^2), |a_L| = 2 X1/((1 - beta) T^2); the speed
    peaks at beta T with a_H beta T = 2 X1 / T; trapezoid: ramps of
    T - X1/v_max at v_max / t_a."""
    m = exdex.AsymmetricProfile(0.1, 0.5, 0.9)
    pk = motion_peaks(m)
    assert pk["acceleration"] == pytest.approx(2 * 0.1 / (0.1 * 0.25), rel=1e-12)
    assert pk["speed"] == pytest.approx(2 * 0.1 / 0.5, rel=1e-12)
    tp = exdex.TrapezoidalProfile(0.05, 0.5, 0.12)
    pk = motion_peaks(tp)
    ta = 0.5 - 0.05 / 0.12
    assert pk["acceleration"] == pytest.approx(0.12 / ta, rel=1e-12) and pk["speed"] == 0.12


def test_motion_peaks_of_a_sampled_log():
    """p(t) = a t^2 / 2 along x, sampled every 10 ms to 0.5 s: second
    differences of a quadratic are exact (a), the largest first difference
    is the speed at the last interval's midpoint a (0.5 - 0.005), the stroke
    a 0.5^2 / 2."""
    a = 2.0
    t = np.linspace(0.0, 0.5, 51)
    pos = np.column_stack([0.5 * a * t ** 2, np.zeros_like(t), np.zeros_like(t)])
    quat = np.tile([1.0, 0.0, 0.0, 0.0], (len(t), 1))
    pk = motion_peaks(exdex.SampledTrajectory(t, pos, quat))
    assert pk["acceleration"] == pytest.approx(a, rel=1e-9)
    assert pk["speed"] == pytest.approx(a * 0.495, rel=1e-9)
    assert pk["stroke"] == pytest.approx(0.25, rel=1e-12) and pk["duration"] == pytest.approx(0.5, rel=1e-12)


def test_motion_peaks_at_rest_and_without_ramps():
    assert motion_peaks(exdex.Rest()) == dict(acceleration=0.0, speed=0.0, stroke=0.0, duration=0.0)
    # a trapezoid at its lowest speed, v_max = |X1| / T, has no ramps: the acceleration is unbounded
    pk = motion_peaks(exdex.TrapezoidalProfile(-0.05, 0.5, 0.1))
    assert pk == dict(acceleration=math.inf, speed=0.1, stroke=0.05, duration=0.5)
    # an angular Eq. 7, pointing the other way: the same peaks in rad, rad/s and rad/s^2
    pk = motion_peaks(exdex.AsymmetricProfile(-1.0, 2.0, 0.5, rotation=True))
    assert pk["acceleration"] == pytest.approx(2 * 1.0 / (0.5 * 4.0), rel=1e-12)     # a_H = |a_L| at beta 1/2
    assert pk["speed"] == pytest.approx(2 * 1.0 / 2.0, rel=1e-12) and pk["stroke"] == 1.0 and pk["duration"] == 2.0
    with pytest.raises(TypeError, match="unknown motion type str"):
        motion_peaks("shake")


def test_check_quantity_names_the_allowed_outcomes():
    translation = exdex.Scene(body=exdex.Body(mass=0.1), grasp=exdex.Grasp(mu=0.5, grip_force=1.0))
    rotation = exdex.replace(translation, dof="rotation")
    for q in ("com_slide", "slip"):
        check_quantity(q, translation)
    check_quantity("rotation", rotation)
    with pytest.raises(ValueError, match=r"target quantity must be one of \['com_slide', 'contact_slip', "
                                         r"'rotation', 'slip', 'x', 'y'\], got 'angle'"):
        check_quantity("angle", translation)
    with pytest.raises(ValueError, match=r"a translation scene has no 'rotation' outcome; use one of "
                                         r"\['com_slide', 'slip'\]"):
        check_quantity("rotation", translation)
    with pytest.raises(ValueError, match=r"a rotation scene has no 'x' outcome; use one of \['rotation'\]"):
        check_quantity("x", rotation)
    assert set(QUANTITY_HELP) == set(QUANTITIES)
    assert all(f"[{unit}]" in QUANTITY_HELP[q] for q, unit in QUANTITIES.items())


def test_unreachable_target_error_carries_the_reachable_interval():
    e = UnreachableTargetError("target 0.2 m outside [0.01, 0.1] m", (0.01, 0.1), invalid=3, scanned=40)
    assert isinstance(e, ValueError) and str(e) == "target 0.2 m outside [0.01, 0.1] m"
    assert (e.low, e.high) == e.reachable == (0.01, 0.1) and (e.invalid, e.scanned) == (3, 40)
    assert type(e.reachable[0]) is float and type(e.invalid) is int
    assert exdex.UnreachableTargetError is UnreachableTargetError
    e = UnreachableTargetError("no run keeps the object in the grasp", (math.nan, math.nan))
    assert math.isnan(e.low) and math.isnan(e.high) and (e.invalid, e.scanned) == (0, 0)

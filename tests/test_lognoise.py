"""exdex._lognoise, the noise of a sampled gripper log, on small hand-built logs.

References, by hand: an alternating sequence y_i = s (-1)^i at spacing h has
k-th forward differences (-2)^k s (-1)^i, so every k-th divided difference is
2^k s / (k! h^k) in size and the module's scaled estimate is
2^k s / (sqrt(C(2k, k)) 0.6745); its smallest over k = 3 .. 6 is k = 3:
8 s / (sqrt(20) 0.6745). A polynomial of degree <= 3 has zero 4th
differences (rounding only): level 0. Second differences of the alternation
are 4 s (-1)^i at stride 1 and 0 at even strides, so the motion's peak
acceleration is 0 and the noise's is 3 sqrt(6) sigma / h^2. The end test
(the quadratic through three end samples): a uniformly accelerated start is
at rest, a constant speed is not. The smoothing spline's residual matches
the stated noise level (bisection on lambda to 5e-4 decades)."""
import math
import warnings

import numpy as np
import pytest

from exdex import _lognoise as L

H, S = 0.01, 1e-3


def _alternating(n=40):
    t = np.arange(n) * H
    return t, S * (-1.0) ** np.arange(n)


def test_levels_of_an_alternating_sequence_and_of_polynomials():
    t, alt = _alternating()
    y = np.column_stack([alt, np.zeros_like(t), 0.5 * t**2, 1 + 2 * t + 3 * t**2 - t**3])
    lv = L.levels(t, y)
    assert lv[0] == pytest.approx(8 * S / (math.sqrt(20) * 0.6745), rel=1e-12)
    assert np.array_equal(lv[1:], (0.0, 0.0, 0.0))
    # fewer than MIN_SAMPLES samples are not judged
    assert np.array_equal(L.levels(t[:L.MIN_SAMPLES - 1], y[:L.MIN_SAMPLES - 1]), (0.0, 0.0, 0.0, 0.0))
    assert L.levels(t[:L.MIN_SAMPLES], y[:L.MIN_SAMPLES])[0] > 0.0


def test_dominance_of_pure_noise_and_of_a_clean_log():
    t, alt = _alternating()
    sig, noise_peak, motion_peak = L.dominance(t, alt[:, None])
    sigma = 8 * S / (math.sqrt(20) * 0.6745)
    assert sig[0] == pytest.approx(sigma, rel=1e-12)
    assert noise_peak == pytest.approx(3 * math.sqrt(6) * sigma / H**2, rel=1e-12)
    assert motion_peak == 0.0
    # quaternion components: the accelerations doubled (factor 2, rad/s^2)
    assert L.dominance(t, alt[:, None], factor=2.0)[1] == pytest.approx(2 * noise_peak, rel=1e-12)
    sig, noise_peak, motion_peak = L.dominance(t, np.column_stack([0.5 * t**2]))
    assert np.array_equal(sig, (0.0,)) and noise_peak == 0.0 and motion_peak is None


def test_continuous_quaternions_pick_the_sign_that_agrees_with_the_neighbour():
    q = np.array([[1.0, 0.0, 0.0, 0.0], [-1.0, 0.1, 0.0, 0.0], [0.9, -0.1, 0.0, 0.0], [-2.0, 0.0, 0.0, 0.0]])
    out = L.continuous_quaternions(q)
    assert np.allclose(np.linalg.norm(out, axis=1), 1.0, rtol=0, atol=1e-15)
    assert np.allclose(out[1], np.array([1.0, -0.1, 0.0, 0.0]) / math.sqrt(1.01), rtol=0, atol=1e-15)
    assert np.allclose(out[2], np.array([0.9, -0.1, 0.0, 0.0]) / math.sqrt(0.82), rtol=0, atol=1e-15)
    assert np.allclose(out[3], (1.0, 0.0, 0.0, 0.0), rtol=0, atol=1e-15)
    assert np.all(np.sum(out[1:] * out[:-1], axis=1) > 0)


def test_end_at_rest():
    t = np.arange(5) * 0.1
    accelerated, uniform = np.column_stack([t**2]), np.column_stack([t])
    assert L.end_at_rest(t, accelerated, 0.0, 0)                       # v0 = 0 exactly
    assert not L.end_at_rest(t, uniform, 0.0, 0)                       # v0 . D1 = |D1|^2 / h1 > |D1|^2 / (2 h1)
    assert L.end_at_rest(t, np.column_stack([(t - 0.4) ** 2]), 0.0, 1)
    assert not L.end_at_rest(t, uniform, 0.0, 1)
    # with a noise level: |v0| = 1 m/s against 3 sqrt(2) sigma / h1, sigma twice and half the level that meets it
    meet = 0.1 / (3 * math.sqrt(2))
    assert L.end_at_rest(t, uniform, 2 * meet, 0) and not L.end_at_rest(t, uniform, 0.5 * meet, 0)
    assert L.end_at_rest(t, uniform, meet, 0, factor=0.25) and not L.end_at_rest(t, uniform, meet, 0, factor=4.0)


def test_smoothing_leaves_the_stated_residual():
    pytest.importorskip("scipy.interpolate")
    n, sigma = 101, 1e-3
    t = np.linspace(0.0, 1.0, n)
    clean = np.column_stack([0.1 * np.sin(2 * np.pi * t), 0.05 * t**2, 0.02 * np.cos(3 * t)])
    noisy = clean + sigma * np.random.default_rng(0).standard_normal((n, 3))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        fit = L.smooth_positions(t, noisy, sigma)
    rms = np.sqrt(np.mean((fit - noisy) ** 2, axis=0))
    # the bisection ends on the side at or below the target, 5e-4 decades of lambda from it (measured: 0.99998,
    # 0.999997 and 0.99997 sigma)
    assert np.all(rms <= sigma) and np.all(rms > 0.999 * sigma)
    # a level the straight line already meets: the least-squares line itself (zero second differences)
    line = np.column_stack([t, 2 * t, np.zeros(n)]) + S * (-1.0) ** np.arange(n)[:, None]
    flat = L.smooth_positions(t, line, 0.5)
    assert np.max(np.abs(np.diff(flat, 2, axis=0))) < 1e-12


def test_user_stacklevel_points_at_the_first_frame_outside_exdex():
    assert L.user_stacklevel() == 1          # called from here, outside exdex

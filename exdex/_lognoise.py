"""The noise of a sampled gripper log (exdex.SampledTrajectory): its level
estimated from the data, whether it dominates the log's accelerations, and
a smoothing spline whose residual matches a stated level.

Estimate. White noise of standard deviation sigma gives k-th divided
differences of standard deviation sigma sqrt(C(2k, k)) / (k! h^k) (spacing
h), whatever k, while a smooth motion's fall off as h^k times its k-th
derivative. Each channel's level is the smallest over k = 3 .. 6 of the
median of |k-th divided difference| scaled by that factor (over 0.6745,
the median of |N(0, 1)|): an upper bound of the noise that a few corners
of the motion (the start of a move) do not raise, and that a clean log
puts at the motion's own high-order differences, far below its
accelerations. Levels below 64 ulp of the channel's size are rounding and
count as zero.

Dominance. The spline through the samples passes the noise on to its
accelerations with a standard deviation of about sqrt(6) sigma / h^2 (the
second difference's); the motion's peak acceleration is read from second
differences over a stride of m samples, m doubled from 1 until the noise's
share at that stride, sqrt(6) sigma / (m h)^2, is below a tenth of the peak
there (minus three of those standard deviations). The accelerations are
dominated by the noise when three standard deviations of the noise's exceed
that peak. Positions [m] and orientations (the quaternion's components,
twice of which is the angle [rad]) are judged separately.
"""
from __future__ import annotations

import math
import sys
from typing import Dict, List, Optional, Tuple

import numpy as np

__all__ = ["MIN_SAMPLES", "ORDERS", "levels", "dominance", "smooth_positions", "smooth_quaternions",
           "continuous_quaternions", "end_at_rest", "user_stacklevel"]

#: Logs with fewer samples are not judged (too few differences to tell noise from motion).
MIN_SAMPLES = 12
#: Orders of the divided differences the noise level is read from.
ORDERS = (3, 4, 5, 6)
#: Three standard deviations: the noise's peak acceleration compared with the motion's.
PEAK_SIGMAS = 3.0


def _divided(t, y, k, stride=1):
    """k-th divided differences of y (n, c) over samples ``stride`` apart,
    (n - k stride, c), and each window's mean spacing (n - k stride,)."""
    d = y
    for j in range(1, k + 1):
        d = (d[stride:] - d[:-stride]) / (t[j * stride:] - t[:-j * stride])[:, None]
    span = (t[k * stride:] - t[:-k * stride]) / k
    return d, span


def levels(t, y):
    """The noise level (c,) of each channel of y (n, c) sampled at t (n,), in
    y's unit; zeros for fewer than MIN_SAMPLES samples or rounding only."""
    t = np.asarray(t, dtype=float)
    y = np.asarray(y, dtype=float)
    if len(t) < MIN_SAMPLES:
        return np.zeros(y.shape[1])
    best = np.full(y.shape[1], np.inf)
    for k in ORDERS:
        d, span = _divided(t, y, k)
        scale = math.factorial(k) * span**k / math.sqrt(math.comb(2 * k, k))
        best = np.minimum(best, np.median(np.abs(d) * scale[:, None], axis=0) / 0.6745)
    floor = 64 * np.finfo(float).eps * np.max(np.abs(y), axis=0)
    return np.where(best > floor, best, 0.0)


def dominance(t, y, factor=1.0):
    """(noise level (c,), the noise's peak acceleration, the motion's peak
    acceleration) of y (n, c) sampled at t, the accelerations in y's unit per
    s^2 times ``factor`` (2 for quaternion components: rad/s^2)."""
    t = np.asarray(t, dtype=float)
    y = np.asarray(y, dtype=float)
    sig = levels(t, y)
    h = float(np.median(np.diff(t)))
    rms = factor * math.sqrt(6.0) * float(np.linalg.norm(sig)) / h**2
    if rms == 0.0:
        return sig, 0.0, None
    m, n = 1, len(t)
    while True:
        d, _ = _divided(t, y, 2, m)
        peak = factor * 2.0 * float(np.max(np.linalg.norm(d, axis=1)))
        share = rms / m**2
        if share <= 0.1 * peak or 4 * m > (n - 1) // 4:
            break
        m *= 2
    return sig, PEAK_SIGMAS * rms, max(peak - PEAK_SIGMAS * share, 0.0)


def continuous_quaternions(q):
    """Unit quaternions (n, 4) with the sign of each chosen so that neighbours
    agree (q and -q are one orientation)."""
    q = np.asarray(q, dtype=float)
    q = q / np.linalg.norm(q, axis=1)[:, None]
    flip = np.ones(len(q))
    for i in range(1, len(q)):
        flip[i] = flip[i - 1] * (1.0 if q[i] @ q[i - 1] >= 0.0 else -1.0)
    return q * flip[:, None]


def _spline(feature):
    from exdex import _optional

    return _optional.require("scipy.interpolate", feature).make_smoothing_spline


def _fit(u, y, target, make):
    """Values at u of the smoothing spline of y (n, c) -- one lambda for all
    columns -- whose mean squared residual summed over the columns is
    ``target`` (bisection on log lambda; the straight line where even it
    fits closer, the data itself where target is 0)."""
    def values(lam):
        if y.shape[1] > 1:
            try:   # the columns at once (SciPy >= 1.14 takes y of shape (n, c))
                return np.asarray(make(u, y, lam=lam, axis=0)(u)).reshape(y.shape)
            except (TypeError, ValueError):
                pass
        return np.column_stack([make(u, y[:, c], lam=lam)(u) for c in range(y.shape[1])])

    def misfit(f):
        return float(np.mean(np.sum((f - y) ** 2, axis=1)))

    lo, hi = -24.0, 6.0          # log10 lambda, u in [0, 1]
    f_hi = values(10.0**hi)
    if misfit(f_hi) <= target:
        return f_hi
    for _ in range(16):         # to 5e-4 decades of lambda
        mid = 0.5 * (lo + hi)
        if misfit(values(10.0**mid)) > target:
            hi = mid
        else:
            lo = mid
    return values(10.0**lo)


def _extended(t, y, mirror):
    """Times scaled to [0, 1] and samples, each end in ``mirror`` (start, end)
    extended by the mirror image of half the samples about it (an end at
    rest: the motion even about it, so the fit's slope there is zero), and
    the slice of the original samples."""
    t = np.asarray(t, dtype=float)
    y = np.asarray(y, dtype=float)
    k = len(t) // 2
    ts, ys, first = [t], [y], 0
    if mirror[0]:
        ts.insert(0, 2.0 * t[0] - t[k:0:-1])
        ys.insert(0, y[k:0:-1])
        first = k
    if mirror[1]:
        ts.append(2.0 * t[-1] - t[-2:-k - 2:-1])
        ys.append(y[-2:-k - 2:-1])
    te, ye = np.concatenate(ts), np.concatenate(ys)
    return (te - te[0]) / (te[-1] - te[0]), ye, slice(first, first + len(t))


def smooth_positions(t, p, sigma, feature="SampledTrajectory(noise=...)", mirror=(False, False)):
    """Positions (n, 3) replaced by the smoothing spline of each axis whose
    residual's root mean square is ``sigma`` [m] (per axis); ends in
    ``mirror`` are fitted as ends at rest (zero slope)."""
    make = _spline(feature)
    u, p, keep = _extended(t, p, mirror)
    return np.column_stack([_fit(u, p[:, [c]], sigma**2, make)[keep] for c in range(3)])


def smooth_quaternions(t, q, sigma, feature="SampledTrajectory(noise=...)", mirror=(False, False)):
    """Quaternions (n, 4) (made sign-continuous and unit) replaced by the
    smoothing spline of their components (one lambda) whose residual matches
    an orientation noise of ``sigma`` [rad] per axis: a small rotation d
    moves a unit quaternion by |d| / 2, so the mean squared residual over the
    components is 3 sigma^2 / 4. Ends in ``mirror`` as in smooth_positions."""
    make = _spline(feature)
    u, q, keep = _extended(t, continuous_quaternions(q), mirror)
    return _fit(u, q, 0.75 * sigma**2, make)[keep]


def end_at_rest(t, y, sigma, end, factor=1.0):
    """Whether the start (end 0) or the end (1) of samples y (n, c) at t is at
    rest. With a noise level ``sigma`` > 0 (the samples smoothed for it): the
    end velocity v0 of the quadratic through the three end samples (the
    core's estimate) is within three standard deviations of one sample
    difference's noise, factor |v0| <= 3 sqrt(2) sigma / h1 (``factor`` 2 for
    quaternion components against an angle noise). Without: the core's own
    test, v0 . D1 <= |D1|^2 / (2 h1) (csrc/motion.c)."""
    t = np.asarray(t, dtype=float)
    y = np.asarray(y, dtype=float)
    if end:
        t, y = -t[::-1], y[::-1]
    h1, h2 = t[1] - t[0], t[2] - t[1]
    d1, d2 = (y[1] - y[0]) / h1, (y[2] - y[1]) / h2
    v0 = d1 * (2 * h1 + h2) / (h1 + h2) - d2 * h1 / (h1 + h2)
    if sigma > 0.0:
        return bool(factor * float(np.linalg.norm(v0)) <= 3.0 * math.sqrt(2.0) * sigma / h1)
    D1 = y[1] - y[0]
    return bool(float(v0 @ D1) <= float(D1 @ D1) / (2.0 * h1))


def user_stacklevel():
    """The stacklevel that points a warning issued by the caller of this
    function at the first frame outside exdex (and outside the generated
    dataclass __init__)."""
    import os

    pkg = os.path.dirname(os.path.abspath(__file__))
    f = sys._getframe(1)
    level = 1
    while f is not None:
        name = f.f_code.co_filename
        generated = name == "<string>" and f.f_code.co_name == "__init__"   # a dataclass's __init__
        if not (name.startswith(pkg + os.sep) or generated):
            return level
        f = f.f_back
        level += 1
    return level

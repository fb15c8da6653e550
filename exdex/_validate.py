"""Validation of user input shared by the modules of exdex: a finite real in a
range, a finite float array of a shape, an output time grid. Each raises a
ValueError or TypeError naming the parameter and the allowed range. Also the
stack level at which a warning names the user's line."""
import math
import numbers
import os
import sys

import numpy as np

__all__ = ["real", "array", "check_times", "user_stacklevel"]

#: the package's directory: frames in files under it are exdex's own
_PACKAGE_DIR = os.path.dirname(os.path.abspath(__file__)) + os.sep


def user_stacklevel() -> int:
    """The ``stacklevel`` for :func:`warnings.warn`, called by the function
    that calls this one, that names the first frame outside the exdex
    package: the user's line that called into exdex, however deep inside
    the package the warning arises."""
    f = sys._getframe(1)
    level = 1
    while f.f_back is not None and os.path.abspath(f.f_code.co_filename).startswith(_PACKAGE_DIR):
        f = f.f_back
        level += 1
    return level


def real(value, name, *, low=None, high=None, low_open=False, high_open=False):
    """A finite float within [low, high] (open ends where asked), else a clear error."""
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise TypeError(f"{name} must be a real number, got {type(value).__name__}")
    x = float(value)
    if not math.isfinite(x):
        raise ValueError(f"{name} must be finite, got {x}")
    bad_low = low is not None and (x <= low if low_open else x < low)
    bad_high = high is not None and (x >= high if high_open else x > high)
    if bad_low or bad_high:
        lo = "-inf" if low is None else f"{low:g}"
        hi = "inf" if high is None else f"{high:g}"
        lb = "(" if low_open or low is None else "["
        hb = ")" if high_open or high is None else "]"
        raise ValueError(f"{name} must be in {lb}{lo}, {hi}{hb}, got {x:g}")
    return x


def array(value, name, shape):
    """A finite float64 array of the given shape (None in shape = any length)."""
    if isinstance(value, (str, bytes)):
        raise TypeError(f"{name} must be an array of numbers, got {type(value).__name__}")
    try:
        a = np.asarray(value)
    except Exception as exc:  # pragma: no cover - numpy raises varied errors
        raise TypeError(f"{name} must be an array of numbers") from exc
    if a.dtype == object or not (np.issubdtype(a.dtype, np.number) or a.dtype == bool):
        raise TypeError(f"{name} must be an array of numbers, got dtype {a.dtype}")
    if np.iscomplexobj(a):
        raise TypeError(f"{name} must be real, got a complex array")
    a = np.array(a, dtype=np.float64)
    if a.ndim != len(shape) or any(s is not None and s != d for s, d in zip(shape, a.shape)):
        want = "(" + ", ".join("n" if s is None else str(s) for s in shape) + ("," if len(shape) == 1 else "") + ")"
        raise ValueError(f"{name} must have shape {want}, got {a.shape}")
    if not np.all(np.isfinite(a)):
        raise ValueError(f"{name} must be finite (no NaN or infinity)")
    return a


def check_times(t_end, dt):
    """(dt, t_end) as floats, or a ValueError / TypeError naming the bad one."""
    dt = real(dt, "dt", low=0.0, low_open=True)
    t_end = real(t_end, "t_end", low=0.0, low_open=True)
    if dt > t_end:
        raise ValueError(f"dt must be <= t_end: got dt = {dt:g} s and t_end = {t_end:g} s "
                         "(dt is the output step, t_end the end time)")
    if t_end / dt > 1e9:
        raise ValueError(f"t_end / dt must be at most 1e9 steps, got {t_end / dt:.3g}")
    return dt, t_end

"""exdex._validate: bad input is a TypeError or ValueError naming the
parameter and the allowed range; good input comes back as floats."""
import math

import numpy as np
import pytest

from exdex._validate import array, check_times, real


def test_real_accepts_and_converts():
    assert real(np.float32(0.5), "x") == 0.5 and type(real(1, "x")) is float
    assert real(0.0, "x", low=0.0) == 0.0 and real(1.0, "x", high=1.0) == 1.0


@pytest.mark.parametrize("value, kw, exc, text", [
    (True, {}, TypeError, "x must be a real number, got bool"),
    ("1", {}, TypeError, "x must be a real number, got str"),
    (math.nan, {}, ValueError, "x must be finite"),
    (0.0, dict(low=0.0, low_open=True), ValueError, r"x must be in \(0, inf\), got 0"),
    (2.0, dict(low=0.0, high=1.0), ValueError, r"x must be in \[0, 1\], got 2"),
    (1.0, dict(high=1.0, high_open=True), ValueError, r"x must be in \(-inf, 1\), got 1"),
])
def test_real_names_the_parameter_and_the_range(value, kw, exc, text):
    with pytest.raises(exc, match=text):
        real(value, "x", **kw)


def test_array_shape_and_finiteness():
    a = array([[1, 0, 0], [0, 1, 0], [0, 0, 1]], "R", (3, 3))
    assert a.dtype == np.float64 and a.shape == (3, 3)
    assert array([1, 2, 3, 4], "v", (None,)).shape == (4,)
    with pytest.raises(ValueError, match=r"v must have shape \(3,\), got \(2,\)"):
        array([1, 2], "v", (3,))
    with pytest.raises(ValueError, match="v must be finite"):
        array([1, np.inf, 0], "v", (3,))
    with pytest.raises(TypeError, match="v must be real"):
        array([1j, 0, 0], "v", (3,))
    with pytest.raises(TypeError, match="v must be an array of numbers"):
        array("abc", "v", (3,))


def test_check_times():
    assert check_times(1.5, 1e-3) == (1e-3, 1.5)
    with pytest.raises(ValueError, match="dt must be <= t_end"):
        check_times(1e-3, 1.0)
    with pytest.raises(ValueError, match=r"dt must be in \(0, inf\)"):
        check_times(1.0, 0.0)
    with pytest.raises(ValueError, match="at most 1e9 steps"):
        check_times(1e3, 1e-7)

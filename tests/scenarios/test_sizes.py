"""One size convention: patches, bodies and tools take full side lengths.

A user who writes "a 1 cm x 2 cm pad" passes ``Patch.rectangle(0.01, 0.02)``,
exactly as a 1 x 2 x 3 cm box is ``Body.box(m, (0.01, 0.02, 0.03))`` and a
1 x 2 object outline is ``exdex.tool.rectangle(1, 2)``.
"""
import math

import numpy as np
import pytest

import exdex
from exdex import engines
from exdex import tool as T


def er_rectangle_closed_form(a, b):
    """Mean distance from the centre of the uniform rectangle [-a, a] x [-b, b].

    Derivation: by symmetry the mean over the rectangle is the mean over the
    quadrant [0, a] x [0, b], (1 / (a b)) * integral of r dA. Split the quadrant
    along its diagonal (angle t1, tan t1 = b / a, d = sqrt(a^2 + b^2)). In polar
    coordinates the lower triangle is r <= a / cos t, 0 <= t <= t1, so
        integral r dA = int_0^t1 a^3 / (3 cos^3 t) dt
                      = (a^3 / 6) [sec t tan t + ln(sec t + tan t)]_0^t1
                      = a b d / 6 + (a^3 / 6) ln((b + d) / a),
    using sec t1 = d / a, tan t1 = b / a. The upper triangle is the same with
    a and b exchanged. Hence
        e_r = [a b d / 3 + (a^3/6) ln((b + d)/a) + (b^3/6) ln((a + d)/b)] / (a b).
    """
    d = math.hypot(a, b)
    return (a * b * d / 3 + a**3 / 6 * math.log((b + d) / a) + b**3 / 6 * math.log((a + d) / b)) / (a * b)


def test_one_by_two_cm_pad_has_the_closed_form_er():
    pad = exdex.Patch.rectangle(0.01, 0.02)      # 1 cm wide, 2 cm high
    expected = er_rectangle_closed_form(0.005, 0.01)
    assert expected == pytest.approx(0.0059323, abs=1e-7)  # the closed form evaluated by hand
    assert pad.e_r == pytest.approx(expected, rel=1e-14)
    # the half-side reading (e_r of a 2 x 4 cm pad) is exactly twice as large: the
    # convention mistake this test guards against
    assert pad.e_r == pytest.approx(er_rectangle_closed_form(0.01, 0.02) / 2, rel=1e-14)
    assert pad.dims == (0.01, 0.02)


def test_pad_er_matches_a_quadrature_of_the_mean_distance():
    """Independent check: midpoint rule for the mean distance over a w x h pad."""
    rng = np.random.default_rng(15)
    n = 600
    for _ in range(5):
        w, h = rng.uniform(1e-3, 0.05, size=2)
        x = ((np.arange(n) + 0.5) / n - 0.5) * w
        y = ((np.arange(n) + 0.5) / n - 0.5) * h
        X, Y = np.meshgrid(x, y)
        assert exdex.Patch.rectangle(w, h).e_r == pytest.approx(np.hypot(X, Y).mean(), rel=2e-5)


def test_square_pad_of_side_s():
    # square of side s (half-side s/2): e_r = (s/2) (sqrt2 + ln(1 + sqrt2)) / 3 = 0.3826 s
    s = 0.02
    assert exdex.Patch.rectangle(s, s).e_r == pytest.approx(
        s / 2 * (math.sqrt(2) + math.log(1 + math.sqrt(2))) / 3, rel=1e-14)


def test_patch_body_and_tool_outline_share_the_convention():
    w, h = 0.01, 0.02
    body = exdex.Body.box(0.1, (w, h, 0.03))
    span = body.vertices().max(axis=0) - body.vertices().min(axis=0)
    assert span == pytest.approx([w, h], rel=1e-15)
    outline = T.rectangle(w, h)
    assert np.ptp(outline, axis=0) == pytest.approx([w, h], rel=1e-15)
    # the physics engines' pad box for a rectangle patch has the same footprint
    a, b = engines.pad_geometry(exdex.Patch.rectangle(w, h))
    assert (2 * a, 2 * b) == pytest.approx((w, h), rel=1e-15)


def test_rod_tool_takes_full_sizes():
    # unit square (height 1, half-height 0.5), rod 0.25 to the side: asin(0.25 / 0.5) = 30 deg
    assert T.rod_max_rotation(1.0, 0.25) == pytest.approx(math.radians(30), abs=1e-15)
    # closed form at psi: d = b - (b - x_r sin psi) / cos psi with b = height / 2
    psi = 0.3
    assert T.rod_descent_closed_form(psi, 2.0, 0.25) == pytest.approx(
        1.0 - (1.0 - 0.25 * math.sin(psi)) / math.cos(psi), rel=1e-14)
    with pytest.raises(ValueError, match="rod_x"):
        T.rod_rotation(0.1, width=0.4, height=1.0, rod_x=0.25)   # rod beyond the half-width 0.2


@pytest.mark.parametrize("name,args", [("width", (0.0, 0.01)), ("height", (0.01, -1.0))])
def test_bad_rectangle_size_names_the_parameter(name, args):
    with pytest.raises(ValueError, match=name):
        exdex.Patch.rectangle(*args)

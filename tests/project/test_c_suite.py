"""The C suite run through pytest, and its numbers cross-checked through the
Python API: every value the C tests report (``VALUE key x`` lines) that has a
Python counterpart below is recomputed through exdex and must agree."""
import re

import numpy as np
import pytest

import exdex
from exdex import _core

G = 9.81


def c_values(stdout):
    return {m.group(1): float(m.group(2)) for m in re.finditer(r"^VALUE (\S+) (\S+)$", stdout, re.M)}


def test_c_suite_passes(c_suite):
    rc, out = c_suite
    m = re.search(r"^(\d+) passed, (\d+) failed$", out, re.M)
    assert m, "the C runner printed no 'N passed, N failed' line:\n" + out[-2000:]
    passed, failed = int(m.group(1)), int(m.group(2))
    assert failed == 0 and rc == 0, "C suite failures:\n" + "\n".join(
        l for l in out.splitlines() if l.startswith(("FAIL", "    ")))
    assert passed >= 40


def vertical(mass, capacity, motion=exdex.Rest(), **kw):
    return exdex.Scene(body=exdex.Body(mass=mass), grasp=exdex.Grasp(mu=0.5, grip_force=capacity),
                       motion=motion, **kw)


def _motion_s(motion, t):
    k = motion.evaluate([t], gripper_rotation=np.eye(3))
    return float(k["p"][0] @ np.array(motion.axis))


FIG3_MOTION = exdex.AsymmetricProfile(0.1, 0.5, 0.9)
FIG4_MOTION = exdex.TrapezoidalProfile(0.05, 0.5, 0.12)

# key -> recomputation through the Python API
PYTHON_SIDE = {
    "motion_fig3_a_H": lambda: FIG3_MOTION.a_high,
    "motion_fig3_a_L": lambda: FIG3_MOTION.a_low,
    "motion_fig3_s_0p25": lambda: _motion_s(FIG3_MOTION, 0.25),
    "motion_fig3_s_0p52": lambda: _motion_s(FIG3_MOTION, 0.52),
    "motion_fig4_s_half": lambda: _motion_s(FIG4_MOTION, 0.25),
    "sim_free_fall_0p7": lambda: exdex.simulate(
        exdex.replace(vertical(0.3, 1.0), grasp=exdex.Grasp(mu=0.0, grip_force=1.0)), 0.7, 1e-3).q[-1, 0],
    # capacity 0.6 m g with m = 0.2: 2 fingers x F x 0.5 = 0.6 * 0.2 * g
    "sim_slide_1s": lambda: exdex.simulate(vertical(0.2, 0.6 * 0.2 * G), 1.0, 1e-3).q[-1, 0],
    "sim_fig3_final_dt1e-4": lambda: exdex.simulate(
        vertical(0.1, 1.5, motion=exdex.AsymmetricProfile(0.1, 0.5, 0.9, axis=(0, 0, -1))), 1.5, 1e-4).q[-1, 0],
}


@pytest.mark.parametrize("key", sorted(PYTHON_SIDE))
def test_c_numbers_cross_checked_through_python(c_suite, key):
    values = c_values(c_suite[1])
    assert key in values, f"the C suite no longer reports {key}"
    got = PYTHON_SIDE[key]()
    assert got == pytest.approx(values[key], rel=1e-12, abs=1e-15)


def test_reference_values_through_python(ref):
    """The shared reference numbers (closed forms) reproduced via Python."""
    assert PYTHON_SIDE["sim_free_fall_0p7"]() == pytest.approx(ref["sim_free_fall_0p7"], abs=1e-12)
    assert PYTHON_SIDE["sim_slide_1s"]() == pytest.approx(ref["sim_slide_1s"], abs=1e-12)
    assert PYTHON_SIDE["sim_fig3_final_dt1e-4"]() == pytest.approx(ref["sim_fig3_grip1p5_final"], abs=1e-7)
    assert FIG3_MOTION.a_high == pytest.approx(ref["motion_fig3_a_H"], rel=1e-15)
    assert FIG3_MOTION.a_low == pytest.approx(ref["motion_fig3_a_L"], rel=1e-15)

"""What the inverse-design modules share: the target quantities, the error of
an unreachable target and the peaks of a gripper motion (exdex.design.plan
re-exports them; exdex.design.sequence uses them)."""
import math
from typing import Any, Dict

import numpy as np

from exdex.scene import AsymmetricProfile, Rest, SampledTrajectory, TrapezoidalProfile

__all__ = ["QUANTITIES", "UnreachableTargetError", "motion_peaks", "check_quantity"]

#: the quantities a target can name, with their units
QUANTITIES = {"slip": "m", "rotation": "rad", "x": "m", "y": "m", "contact_slip": "m"}


class UnreachableTargetError(ValueError):
    """The target lies outside what the varied parameter can reach.

    ``reachable`` is the (low, high) interval of the outcome over the
    parameter's bounds and limits (from the scan and its refinement)."""

    __module__ = "exdex.design.plan"   # where users import it from

    def __init__(self, message, reachable):
        super().__init__(message)
        self.reachable = reachable


def motion_peaks(motion: Any) -> Dict[str, float]:
    """Peak |acceleration|, peak |speed|, stroke (largest |s|) and duration T of
    a gripper motion's profile s(t) (m or rad; Eq. 7 from its closed form,
    Eq. 9; the trapezoid from its ramps; a sampled log from finite
    differences of its sample positions, angles ignored)."""
    if isinstance(motion, Rest):
        return dict(acceleration=0.0, speed=0.0, stroke=0.0, duration=0.0)
    if isinstance(motion, AsymmetricProfile):
        a_h, a_l = abs(motion.a_high), abs(motion.a_low)
        # speed peaks at the end of the first a_H phase (beta T): a_H beta T
        return dict(acceleration=max(a_h, a_l), speed=a_h * motion.beta * motion.duration,
                    stroke=abs(motion.amplitude), duration=motion.duration)
    if isinstance(motion, TrapezoidalProfile):
        ta = motion.duration - abs(motion.amplitude) / motion.v_max
        acc = motion.v_max / ta if ta > 0 else math.inf
        return dict(acceleration=acc, speed=motion.v_max, stroke=abs(motion.amplitude), duration=motion.duration)
    if isinstance(motion, SampledTrajectory):
        t = np.asarray(motion.times, dtype=float)
        p = np.asarray(motion.spline_positions, dtype=float)   # smoothed where the log states its noise
        v = np.diff(p, axis=0) / np.diff(t)[:, None]
        a = np.diff(v, axis=0) / (0.5 * (t[2:] - t[:-2]))[:, None]
        d = np.linalg.norm(p - p[0], axis=1)
        return dict(acceleration=float(np.max(np.linalg.norm(a, axis=1), initial=0.0)),
                    speed=float(np.max(np.linalg.norm(v, axis=1), initial=0.0)),
                    stroke=float(d.max()), duration=float(t[-1] - t[0]))
    raise TypeError(f"unknown motion type {type(motion).__name__}")


def check_quantity(quantity, scene):
    if quantity not in QUANTITIES:
        raise ValueError(f"target quantity must be one of {sorted(QUANTITIES)}, got {quantity!r}")
    dof = scene.dof
    ok = {"translation": ("slip",), "rotation": ("rotation",),
          "planar": ("slip", "rotation", "x", "y", "contact_slip")}[dof]
    if quantity not in ok:
        raise ValueError(f"a {dof} scene has no {quantity!r} outcome; use one of {list(ok)}")

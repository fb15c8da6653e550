"""What the inverse-design modules share: the target quantities, the error of
an unreachable target and the peaks of a gripper motion (exdex.design.plan
re-exports them; exdex.design.sequence uses them)."""
import math
from typing import Any, Dict, Tuple

import numpy as np

from exdex.scene import AsymmetricProfile, Rest, SampledTrajectory, TrapezoidalProfile

__all__ = ["QUANTITIES", "QUANTITY_HELP", "UnreachableTargetError", "motion_peaks", "check_quantity"]

#: the quantities a target can name, with their units: ``com_slide`` (the
#: centre of mass's slide; ``slip`` is its older name), ``contact_slip`` (how
#: far the object's face slid under the contact), ``rotation``, ``x``, ``y``
QUANTITIES = {"com_slide": "m", "slip": "m", "contact_slip": "m", "rotation": "rad", "x": "m", "y": "m"}

#: what each quantity is, in words (for help texts and docs)
QUANTITY_HELP = {
    "com_slide": "the slide of the object's centre of mass relative to the gripper [m]: along the slide axis "
                 "(signed) in translation scenes, the distance it moved in the plate plane in planar ones",
    "slip": "the older name of com_slide [m]",
    "contact_slip": "planar scenes: how far the object's face slid under the contact [m] (with pads on the "
                    "fingers the travel of the contact region's centroid over the object)",
    "rotation": "the turn of the object relative to the gripper [rad] (rotation and planar scenes)",
    "x": "the planar displacement's x component in the gripper frame [m]",
    "y": "the planar displacement's y component in the gripper frame [m]",
}


class UnreachableTargetError(ValueError):
    """The target lies outside what the varied parameters can reach.

    ``reachable`` is the (low, high) interval of the outcome [units of the
    quantity] over the parameter's bounds and limits, from the scan points
    whose runs keep the object in the grasp and pass the physics checks
    (NaN, NaN where none does or the planner has no interval); ``low`` and
    ``high`` are its ends. ``invalid`` counts the scan points left out because
    their runs leave the grasp or fail those checks, of ``scanned`` points
    within the limits (0 and 0 where the planner does not count them)."""

    __module__ = "exdex"   # where users import it from (also exdex.plan.UnreachableTargetError)

    def __init__(self, message: str, reachable: Tuple[float, float], invalid: int = 0, scanned: int = 0) -> None:
        super().__init__(message)
        self.reachable = (float(reachable[0]), float(reachable[1]))
        self.invalid, self.scanned = int(invalid), int(scanned)

    @property
    def low(self) -> float:
        """Lower end of the reachable interval."""
        return self.reachable[0]

    @property
    def high(self) -> float:
        """Upper end of the reachable interval."""
        return self.reachable[1]


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
    ok = {"translation": ("com_slide", "slip"), "rotation": ("rotation",),
          "planar": ("com_slide", "slip", "contact_slip", "rotation", "x", "y")}[dof]
    if quantity not in ok:
        raise ValueError(f"a {dof} scene has no {quantity!r} outcome; use one of {list(ok)}")

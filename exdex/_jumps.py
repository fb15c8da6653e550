"""The gripper's velocity jumps of a scene and their warning, shared by
exdex.simulate, exdex.batch and exdex.stepper."""
import warnings

import numpy as np

from exdex import _core
from exdex.diagnostics import PhysicsWarning
from exdex.scene import SampledTrajectory
from exdex._validate import user_stacklevel

__all__ = ["GripperJumpWarning", "jumps", "warn_jumps"]


class GripperJumpWarning(PhysicsWarning):
    """The gripper's velocity jumps inside the simulated interval (a sampled
    log that starts or ends at speed, a trapezoid without ramps).

    The plates cannot transmit an impulse (the grip force and hence the
    friction force are finite), so the object keeps its absolute velocity
    and its velocity relative to the gripper jumps by minus the gripper's
    jump at the object, projected onto the free coordinates in the mass
    metric; every method applies that jump. Attributes: ``t`` [s], ``dv``
    [m/s] and ``dw`` [rad/s], the jumps of the velocity of the gripper
    frame's origin and of its angular velocity in the world frame. A kind of
    :class:`exdex.PhysicsWarning` (``kind`` "gripper_jump").
    """

    def __init__(self, t, dv, dw, hint=""):
        self.t, self.dv, self.dw = float(t), np.asarray(dv, dtype=float), np.asarray(dw, dtype=float)
        super().__init__(
            f"the gripper's velocity jumps at t = {self.t:.9g} s by |dv| = {np.linalg.norm(self.dv):.3g} m/s, "
            f"|dw| = {np.linalg.norm(self.dw):.3g} rad/s (dv = {_fmt(self.dv)}, dw = {_fmt(self.dw)} in the "
            f"world frame): the plates cannot transmit an impulse, so the object keeps its absolute velocity "
            f"and its velocity relative to the gripper jumps{hint}",
            kind="gripper_jump", time=self.t, quantity="gripper velocity jump |dv| [m/s]",
            value=float(np.linalg.norm(self.dv)), limit=None)


def _fmt(x):
    return "(" + ", ".join(f"{v + 0.0:.3g}" for v in x) + ")"


def jumps(scene, spec):
    """The gripper's velocity jumps of a scene (its spec), [(t, dv, dw)]."""
    if not scene.motion._may_jump:
        return []
    return _core.motion_jumps(spec)


def warn_jumps(scene, jumps, t_end, stacklevel=None):
    """A GripperJumpWarning for each jump in (0, t_end], naming the user's
    line (or ``stacklevel``, counted from the caller of this function)."""
    level = user_stacklevel() if stacklevel is None else stacklevel + 1
    for t, dv, dw in jumps:
        if 0.0 < t <= t_end:
            if isinstance(scene.motion, SampledTrajectory):
                which = "start" if t == scene.motion.times[0] else "end"
                hint = (f". The log {which}s at speed; if the robot was at rest there, pass "
                        f"SampledTrajectory({which}_velocity=(0, 0, 0), {which}_omega=(0, 0, 0)), "
                        f"otherwise log the motion until the robot is at rest.")
            else:
                hint = " (a trapezoid without ramps, v_max = |amplitude| / duration)."
            warnings.warn(GripperJumpWarning(t, dv, dw, hint), stacklevel=level)

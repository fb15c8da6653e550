"""The closed-form 1-DoF reference: Coulomb friction with exact stick under
piecewise-constant drives (:func:`coulomb_1dof`), paper Eq. 7 as such
phases, and the closed form of a 1-DoF Eq. 7 scene (:func:`closed_form`).

Independent of the C core. The paper's cases (exdex.studies.paper, which
lists these names as its own) and the fit's exact event derivatives
(exdex.design.fit) both build on it.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, List, Sequence, Tuple

import numpy as np
from numpy.typing import ArrayLike, NDArray

from exdex.scene import AsymmetricProfile, Scene

__all__ = ["eq7_accelerations", "eq7_phases", "PiecewiseMotion", "coulomb_1dof", "world_dir", "profile_phases",
           "closed_form"]


def eq7_accelerations(amplitude: float, duration: float, beta: float) -> Tuple[float, float]:
    """(a_H, a_L) of paper Eq. 9: a_H = 2 X1 / (beta T^2), a_L = 2 X1 / ((beta - 1) T^2)."""
    return (2.0 * amplitude / (beta * duration**2),
            2.0 * amplitude / ((beta - 1.0) * duration**2))


def eq7_phases(amplitude: float, duration: float, beta: float) -> List[Tuple[float, float, float]]:
    """Paper Eq. 7 as piecewise-constant acceleration phases ``[(t0, t1, a)]``.

    a_H on [0, beta T), a_L on [beta T, (2 - beta) T), a_H on [(2 - beta) T,
    2 T), then rest (a = 0) for ever: a round trip that reaches X1 at t = T and
    is back at rest at its start at t = 2 T (the velocity a_H beta T + a_L
    (2 - 2 beta) T + a_H beta T is 0 by Eq. 9).
    """
    a_h, a_l = eq7_accelerations(amplitude, duration, beta)
    t1, t2, t3 = beta * duration, (2.0 - beta) * duration, 2.0 * duration
    return [(0.0, t1, a_h), (t1, t2, a_l), (t2, t3, a_h), (t3, math.inf, 0.0)]


@dataclass(frozen=True)
class PiecewiseMotion:
    """Exact solution of a 1-DoF Coulomb problem: piecewise-quadratic x(t).

    ``segments`` holds rows ``(t0, x0, v0, a)``: on [t0, next t0) the motion is
    x = x0 + v0 (t - t0) + a (t - t0)^2 / 2. ``events`` lists ``(t, kind)``
    with kind "slip" (stick -> slip) or "stick" (slip -> stick).
    """

    segments: Tuple[Tuple[float, float, float, float], ...]
    events: Tuple[Tuple[float, str], ...] = field(default=())

    def __call__(self, t: ArrayLike) -> Tuple[NDArray[np.float64], NDArray[np.float64]]:
        """(x, v) at times ``t`` (arrays) [m, m/s or rad, rad/s]."""
        seg = np.array(self.segments)
        t = np.asarray(t, dtype=float)
        i = np.clip(np.searchsorted(seg[:, 0], t, side="right") - 1, 0, len(seg) - 1)
        dt = t - seg[i, 0]
        x = seg[i, 1] + seg[i, 2] * dt + 0.5 * seg[i, 3] * dt**2
        v = seg[i, 2] + seg[i, 3] * dt
        return x, v

    @property
    def final(self) -> float:
        """Position after the last event, when the motion has settled at rest."""
        t0, x0, v0, a = self.segments[-1]
        if v0 != 0.0 or a != 0.0:
            raise ValueError("the closed-form motion does not come to rest")
        return x0

    @property
    def rest_time(self) -> float:
        """Start of the final rest segment [s]."""
        return self.segments[-1][0]


def coulomb_1dof(phases: Sequence[Tuple[float, float, float]], capacity: float, x0: float = 0.0,
                 v0: float = 0.0) -> PiecewiseMotion:
    """Closed-form solution of  x'' = d(t) + f/m,  |f/m| <= capacity,  exact stick.

    phases : ``[(t0, t1, d)]``, contiguous, the driving acceleration d
        (gravity + inertial terms along the free coordinate, per unit mass or
        inertia) constant on each; the last phase may end at ``math.inf``.
    capacity : friction capacity per unit mass [m/s^2] (or per unit inertia,
        [rad/s^2]), >= 0.

    Coulomb's law with maximum dissipation in one dimension: at rest the
    object sticks while |d| <= capacity, else slips with a = d - capacity
    sign(d); while sliding at v != 0, a = d - capacity sign(v) until v reaches
    0 (then the rest test again). Each piece is integrated exactly, with the
    event times solved in closed form (t = -v / a), so the result is exact up
    to rounding. Independent of the C core.
    """
    if not capacity >= 0:
        raise ValueError(f"capacity must be >= 0, got {capacity}")
    segs: List[Tuple[float, float, float, float]] = []
    events: List[Tuple[float, str]] = []
    x, v = float(x0), float(v0)
    moving = v != 0.0

    def advance(dur, a):
        nonlocal x, v
        x, v = x + v * dur + 0.5 * a * dur * dur, v + a * dur

    for ta, tb, d in phases:
        t = ta
        while t < tb:
            if v == 0.0:
                if abs(d) <= capacity:
                    if moving:
                        events.append((t, "stick"))
                        moving = False
                    segs.append((t, x, 0.0, 0.0))
                    break
                if not moving:
                    events.append((t, "slip"))
                    moving = True
                a = d - math.copysign(capacity, d)
            else:
                a = d - math.copysign(capacity, v)
                if a * v < 0:
                    ts = -v / a
                    if t + ts < tb:
                        segs.append((t, x, v, a))
                        advance(ts, a)
                        v = 0.0
                        t += ts
                        continue
            segs.append((t, x, v, a))
            if math.isfinite(tb):
                advance(tb - t, a)
            t = tb
    # merge consecutive rest segments (for a clean ``final``/``rest_time``)
    merged: List[Tuple[float, float, float, float]] = []
    for s in segs:
        if merged and s[2] == 0.0 and s[3] == 0.0 and merged[-1][2] == 0.0 and merged[-1][3] == 0.0 \
                and merged[-1][1] == s[1]:
            continue
        merged.append(s)
    return PiecewiseMotion(tuple(merged), tuple(events))


def world_dir(scene, v2):
    """A plate-plane vector of B (2,) as a vector of A at t = 0."""
    R0 = np.array(scene.gripper_rotation)
    return R0 @ np.array([v2[0], v2[1], 0.0])


def profile_phases(motion):
    if isinstance(motion, AsymmetricProfile):
        return eq7_phases(motion.amplitude, motion.duration, motion.beta)
    raise ValueError(f"closed form needs an AsymmetricProfile motion, got {type(motion).__name__}")


def closed_form(scene: Scene) -> PiecewiseMotion:
    """Closed-form solution (:class:`PiecewiseMotion`) of a 1-DoF Eq. 7 scene.

    Supported (else ValueError): ``"translation"`` scenes without stops whose
    gripper translates (Eq. 7) with a fixed orientation, and ``"rotation"``
    scenes whose pivot is the centre of mass (patch centre (0, 0)) and whose
    gripper turns (Eq. 7) about the plate normal. The object starts at rest.
    The coordinate is the displacement from the start: along the slide axis
    [m] or theta - theta0 [rad].

    Translation: drive d(t) = g . e - s''(t) (axis . e) with e the slide axis
    in A, capacity mu N / m. Rotation: d(t) = -s''(t) (axis . n) with n the
    plate normal in A (the Euler term -I_zz theta1'' is the only moment; the
    gyroscopic terms vanish for a rotation about n), capacity mu N e_r / I_zz.
    """
    if any(x != 0.0 for x in scene.v0):
        raise ValueError("closed form assumes the object starts at rest (v0 = 0)")
    motion: Any = scene.motion
    phases = profile_phases(motion)
    cap = scene.grasp.capacity
    if scene.dof == "translation":
        if scene.stops:
            raise ValueError("use stop_closed_form for scenes with stops")
        if motion.rotation:
            raise ValueError("closed form of a translation scene needs a translating gripper")
        e = world_dir(scene, scene.slide_axis)
        g_e = float(np.dot(scene.gravity, e))
        k = float(np.dot(motion.axis, e))
        drive = [(t0, t1, g_e - a * k) for t0, t1, a in phases]
        return coulomb_1dof(drive, cap / scene.body.mass)
    if scene.dof == "rotation":
        if scene.grasp.patch.center != (0.0, 0.0):
            raise ValueError("closed form of a rotation scene needs the pivot at the centre of mass")
        if not motion.rotation:
            raise ValueError("closed form of a rotation scene needs a rotating gripper")
        n = np.array(scene.gripper_rotation)[:, 2]
        k = float(np.dot(motion.axis, n))
        if abs(abs(k) - 1.0) > 1e-12:
            raise ValueError("closed form of a rotation scene needs the gripper to turn about the plate normal")
        izz = float(np.asarray(scene.body.inertia)[2, 2])
        drive = [(t0, t1, -a * k) for t0, t1, a in phases]
        return coulomb_1dof(drive, cap * scene.grasp.patch.e_r / izz)
    raise ValueError("closed form covers 1-DoF scenes only")

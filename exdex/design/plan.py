"""Inverse design: which motion or grip gives the in-hand displacement you want.

:func:`solve` varies one scene parameter (any parameter :func:`exdex.simulate_batch`
can vary: ``grip_force``, ``mu``, ``beta``, ``duration``, ``amplitude``,
``v_max``, ``mass``, ``e_r``) within bounds and the robot's limits until a
final quantity of the object's motion in the gripper meets a target:

    >>> import exdex
    >>> scene = exdex.paper.fig3_scene()
    >>> plan = exdex.plan.solve(scene, {"slip": -0.015}, vary={"grip_force": (1.0, 3.0)})
    >>> abs(plan.residual) <= 1e-6
    True

How: a batch scan of the parameter over its bounds (one C call, all cores),
the monotone branches of the outcome between the scan's local extrema, a
bracket on every branch whose outcome crosses the target, and a bracketing
refinement in batches (each round evaluates ``refine`` interior points and
keeps the sub-interval where the outcome crosses the target, shrinking the
bracket ``refine + 1`` times) until the outcome is within ``tol`` of the
target. A target outside every branch raises :class:`UnreachableTargetError`
with the reachable interval. Among several solutions (several branches) the
one of least cost is returned (by default the gentlest gripper motion: least
peak acceleration), the others are listed.

:func:`band` gives the outcome band of a scene under uncertain parameters
(intervals, e.g. ``{"mu": (0.4, 0.6)}``), with exact endpoints where the
outcome is monotone in the parameter; ``solve(..., uncertain=...)`` plans for
the worst case over such intervals.

Quantities (final value minus initial value of the free coordinates):
``"com_slide"`` [m] (older name ``"slip"``, still accepted) the slide of the
centre of mass relative to the gripper: the displacement along the slide axis
(translation scenes) or the distance moved in the plate plane (planar scenes;
a turn about a pad away from the centre of mass moves it too); ``"rotation"`` [rad]
the turn of the object relative to the gripper (rotation and planar scenes);
``"x"``, ``"y"`` [m] the planar displacement's components in the gripper frame;
``"contact_slip"`` [m] (planar scenes) how far the object's face slid under
the contact: with pads on the fingers (``Grasp.pad``) the distance the
contact region's centroid moved over the object (in C, from the region at
the start and at the end; NaN where the grasp was lost), with the patch the
distance its centre moved relative to the gripper. It uses the scene's own
pad (not one a batch varies).
A target may add ``"rest_by"`` [s], the time by which the object must be at
rest relative to the gripper. A planar pose (``x``, ``y``, ``rotation``)
without ``vary`` is planned as a sequence of motion primitives by
:func:`exdex.sequence.solve`.
Units are SI.
"""
from __future__ import annotations

import dataclasses
import functools
import math
import warnings
from dataclasses import dataclass, field
from typing import Any, Callable, Dict, List, Mapping, Optional, Sequence, Tuple, Union

import numpy as np

from exdex import _core, diagnostics
from exdex._optional import pyplot
from exdex._validate import real as _real, user_stacklevel
from exdex._params import PARAMETERS, param_name as _param_name, replace_params as _replace_params
from exdex.batch import simulate_batch
from exdex.design._targets import QUANTITIES, QUANTITY_HELP, UnreachableTargetError, check_quantity as _check_quantity, motion_peaks
from exdex.diagnostics import ReductionWarning
from exdex.scene import AsymmetricProfile, Rest, SampledTrajectory, Scene, TrapezoidalProfile
from exdex.simulate import SolverError, reduction_fails_at, resolve_method, simulate

__all__ = ["Limits", "Plan", "MultiPlan", "Band", "UnreachableTargetError", "solve", "band", "outcome", "motion_peaks",
           "QUANTITIES", "QUANTITY_HELP", "parameter_unit", "peak_units"]

#: samples of each run on which the planner checks that it stays in the grasp
#: (see ``solve``: runs that leave it are not reachable)
CHECK_SAMPLES = 100

#: units of the parameters ("" for dimensionless ones); see parameter_unit
_PARAM_UNITS = {"grip_force": "N", "mu": "", "mass": "kg", "e_r": "m", "amplitude": "m", "duration": "s",
                "beta": "", "v_max": "m/s", "mu_static": "", "patch_x": "m", "patch_y": "m",
                "pad_x": "m", "pad_y": "m", "pad_radius": "m", "pad_scale": ""}


def parameter_unit(scene: Scene, name: str) -> str:
    """The unit of plan parameter ``name`` on ``scene``, as printed and on
    axis labels: ``"N"``, ``"kg"``, ``"m"``, ``"s"``, ``"m/s"``; ``"rad"``
    and ``"rad/s"`` for a rotating motion's amplitude and peak speed;
    ``"x schedule"`` for ``grip_force`` on a scene with a
    :class:`exdex.GripSchedule` (the value scales the schedule); ``""`` for
    dimensionless ones (mu, mu_static, beta, pad_scale)."""
    name = _param_name(name, scene)
    if name == "grip_force" and scene.grasp.schedule is not None:
        return "x schedule"
    u = _PARAM_UNITS.get(name, "")
    if name in ("amplitude", "v_max") and getattr(scene.motion, "rotation", False):
        u = u.replace("m", "rad")
    return u


def _with_unit(value: str, unit: str) -> str:
    """``value`` followed by its unit (nothing for a dimensionless value)."""
    return f"{value} {unit}" if unit else value


def peak_units(motion: Any) -> Dict[str, str]:
    """Units of :func:`motion_peaks`' entries for ``motion``: m/s^2, m/s, m
    for translating motions, rad/s^2, rad/s, rad for rotating ones; s for
    the duration."""
    rot = bool(getattr(motion, "rotation", False))
    return dict(acceleration="rad/s^2" if rot else "m/s^2", speed="rad/s" if rot else "m/s",
                stroke="rad" if rot else "m", duration="s")


@dataclass(frozen=True)
class Limits:
    """What the robot can do: peak gripper acceleration [m/s^2 or rad/s^2],
    peak speed [m/s or rad/s], stroke (largest distance from the start, m, for
    translating motions), angle (largest turn, rad, for rotating motions) and
    the range of the motion's duration T [s]. None: no limit."""

    max_acceleration: Optional[float] = None
    max_speed: Optional[float] = None
    max_stroke: Optional[float] = None
    max_angle: Optional[float] = None
    duration: Optional[Tuple[float, float]] = None

    def __post_init__(self):
        for name in ("max_acceleration", "max_speed", "max_stroke", "max_angle"):
            v = getattr(self, name)
            if v is not None:
                object.__setattr__(self, name, _real(v, f"Limits.{name}", low=0.0, low_open=True))
        if self.duration is not None:
            lo, hi = _pair(self.duration, "Limits.duration")
            if not 0.0 <= lo <= hi:
                raise ValueError(f"Limits.duration must be (low, high) with 0 <= low <= high, got {self.duration}")
            object.__setattr__(self, "duration", (lo, hi))

    def violations(self, motion: Any) -> List[str]:
        """Names of the limits ``motion`` breaks (empty: within limits)."""
        pk = motion_peaks(motion)
        out = []
        if self.max_acceleration is not None and pk["acceleration"] > self.max_acceleration * (1 + 1e-12):
            out.append("max_acceleration")
        if self.max_speed is not None and pk["speed"] > self.max_speed * (1 + 1e-12):
            out.append("max_speed")
        rot = bool(getattr(motion, "rotation", False))
        if self.max_stroke is not None and not rot and pk["stroke"] > self.max_stroke * (1 + 1e-12):
            out.append("max_stroke")
        if self.max_angle is not None and rot and pk["stroke"] > self.max_angle * (1 + 1e-12):
            out.append("max_angle")
        if self.duration is not None and not isinstance(motion, Rest):
            T = pk["duration"]
            if not self.duration[0] <= T <= self.duration[1]:
                out.append("duration")
        return out


def _pair(value, name):
    try:
        lo, hi = value
    except (TypeError, ValueError):
        raise TypeError(f"{name} must be a (low, high) pair of numbers, got {value!r}") from None
    return _real(lo, f"{name}[0]"), _real(hi, f"{name}[1]")


# ---------------------------------------------------------------- outcomes

def outcome(final_displacement: Any, scene: Scene, quantity: str) -> np.ndarray:
    """The named quantity from final displacements (B, ndof) of ``scene``'s coordinates."""
    d = np.atleast_2d(np.asarray(final_displacement, dtype=float))
    if scene.dof in ("translation", "rotation"):
        return d[:, 0]
    if quantity in ("com_slide", "slip"):
        return np.hypot(d[:, 0], d[:, 1])
    if quantity == "contact_slip":
        return contact_slip(scene, d)
    return d[:, {"x": 0, "y": 1, "rotation": 2}[quantity]]


def contact_slip(scene: Scene, final_displacement: Any) -> np.ndarray:
    """How far the object's face slid under the contact [m] for final
    displacements (B, 3) of a planar ``scene`` (the ``"contact_slip"``
    outcome): with pads, the travel of the region's centroid over the object
    (in C); with the patch, the travel of its centre relative to the gripper."""
    d = np.atleast_2d(np.asarray(final_displacement, dtype=float))
    q0 = np.asarray(scene.q0, dtype=float)
    q = q0 + d

    def rot(th, v):
        c, s = np.cos(th), np.sin(th)
        return np.stack([c * v[..., 0] - s * v[..., 1], s * v[..., 0] + c * v[..., 1]], axis=-1)

    if scene.grasp.pad is None:
        pc = np.asarray(scene.grasp.patch.center, dtype=float)
        return np.linalg.norm(q[:, :2] + rot(q[:, 2], pc) - q0[:2] - rot(q0[2], pc), axis=1)
    spec = scene.to_spec()

    def centroid_C(p):
        reg = _core.pad_region(spec, p)
        if not reg["area"] > 0.0:
            return np.array([np.nan, np.nan])
        return rot(-p[2], np.asarray(reg["centroid"]) - p[:2])

    c0 = centroid_C(q0)
    return np.array([float(np.linalg.norm(centroid_C(p) - c0)) for p in q])


def _target(target, scene):
    if isinstance(target, Mapping):
        items = list(target.items())
    elif isinstance(target, (tuple, list)) and len(target) == 2 and isinstance(target[0], str):
        items = [tuple(target)]
    else:
        raise TypeError("target must be a dict {quantity: value}, e.g. {'slip': 0.015}, "
                        f"got {type(target).__name__}")
    if len(items) != 1:
        raise ValueError(f"target must name exactly one quantity when one parameter varies, got {len(items)}")
    q, v = items[0]
    _check_quantity(q, scene)
    return q, _real(v, f"target[{q!r}]")


def _bounds(name, value):
    lo, hi = _pair(value, f"bounds of {name!r}")
    if not lo < hi:
        raise ValueError(f"bounds of {name!r} must be (low, high) with low < high, got ({lo:g}, {hi:g})")
    p = PARAMETERS[name]
    for x, end in ((lo, "low"), (hi, "high")):
        bad = ((p.low is not None and (x <= p.low if p.low_open else x < p.low))
               or (p.high is not None and (x >= p.high if p.high_open else x > p.high)))
        if bad:
            raise ValueError(f"{end} bound of {name!r} must lie in {p.describe()}, got {x:g}")
    return lo, hi


def _default_t_end(scene):
    """The end of the motion and of the grip schedule (:attr:`exdex.Scene.end_time`)
    plus half of it (1 s when neither changes in time) [s]."""
    end = scene.end_time
    return 1.5 * end if end > 0 else 1.0


def _times_and_options(scene, t_end, dt, method, rtol, atol, eps, threads, friction_solver="scalar"):
    """(t_end, dt, batch options) of a planning call: t_end defaults to the
    end of the motion and grip schedule plus half of it, dt to t_end (the event and analytic
    methods' answers do not depend on the output grid) or, for scenes with
    stops, to at most 10 ms (the output interval bounds the event method's
    step, so that a short approach to a stop is not stepped over)."""
    t_end = _default_t_end(scene) if t_end is None else _real(t_end, "t_end", low=0.0, low_open=True)
    if dt is None:
        dt = t_end if not scene.stops else min(t_end, 0.01)
    else:
        dt = _real(dt, "dt", low=0.0, low_open=True, high=t_end)
    opts: Dict[str, Any] = dict(method=method, rtol=rtol, atol=atol, eps=eps)
    if friction_solver != "scalar":
        opts["friction_solver"] = friction_solver
    if threads is not None:
        opts["threads"] = threads
    return t_end, dt, opts


@dataclass(frozen=True)
class _Runner:
    scene: Scene
    quantity: str
    t_end: float
    dt: float
    options: Dict

    @functools.cached_property
    def _direct(self):
        """The scene's spec when the analytic method solves it (1-DoF, no
        stops, no sampled log: nothing for the batch wrapper's stop, log or
        contact checks to find), else None. Planning calls then go straight
        to the core's batch with values the planner has range-checked."""
        try:
            if self.options.get("method") not in ("auto", "analytic") or \
                    resolve_method(self.scene, "auto") != "analytic":
                return None
            return self.scene.to_spec(method="analytic")
        except (TypeError, ValueError):
            return None

    def at_rest_by(self, t_rest, **arrays):
        """True where the object is at rest relative to the gripper from
        ``t_rest`` on: zero relative speed at t_rest and the same
        coordinates at t_rest and t_end (within 1e-12 m or rad)."""
        late = self.final(self.t_end, **arrays)
        early = self.final(t_rest, **arrays)
        still = np.all(np.abs(early[1]) <= 1e-12, axis=-1) & np.all(np.abs(late[0] - early[0]) <= 1e-12, axis=-1)
        return still.reshape(early[2])

    def final(self, t_end, **arrays):
        """(final displacements (B, ndof), final rates (B, ndof), batch shape) at ``t_end``."""
        dt = t_end if not self.scene.stops else min(t_end, 0.01)
        direct = self._direct_batch(t_end, dt, arrays)
        if direct is not None:
            out, shape = direct
            return out["displacement"], out["v"], shape
        b = simulate_batch(self.scene, t_end, dt, record="final", warn=False, **self.options, **arrays)
        return b.final_displacement, b.v, b.shape

    def _direct_batch(self, t_end, dt, arrays):
        """(core batch output, batch shape) from the compiled spec, or None
        where the batch must go through the scene (no spec, a trapezoid's
        motion parameters or the pad centre varied)."""
        spec = self._direct
        trapezoid = isinstance(self.scene.motion, TrapezoidalProfile) and any(
            PARAMETERS[k].path[0] == "motion" for k in arrays)
        pad = any(k in ("patch_x", "patch_y") for k in arrays)
        if spec is None or trapezoid or pad:
            return None
        vals = np.broadcast_arrays(*(np.asarray(a, dtype=float) for a in arrays.values()))
        shape = vals[0].shape if vals else ()
        vary = {PARAMETERS[k].key: np.ascontiguousarray(v, dtype=float).ravel() for k, v in zip(arrays, vals)}
        n = int(np.prod(shape)) if shape else 1
        threads = self.options.get("threads") or (1 if n < 2048 else 0)
        out = _core.simulate_batch(spec, t_end, dt, threads=threads, record="final", vary=vary or None)
        return out, shape

    def __call__(self, **arrays):
        direct = self._direct_batch(self.t_end, self.dt, arrays)
        if direct is not None:
            out, shape = direct
            return outcome(out["displacement"], self.scene, self.quantity).reshape(shape)
        # candidates of a search, not results: no PhysicsWarning for each scan
        b = simulate_batch(self.scene, self.t_end, self.dt, record="final", warn=False, **self.options, **arrays)
        return outcome(b.final_displacement, self.scene, self.quantity).reshape(b.shape)

    def check(self, **arrays):
        """Which parameter sets give a run the model describes: ``(valid,
        why)``, valid (B,) bool in C order of the arrays' broadcast shape,
        why a list with, for each invalid set, the first reason (None where
        valid). A run is invalid where the pads on the fingers lost the
        object (``stats['grasp_lost_t']``), where the object slid beyond the
        patch's pad or the pad centre left the body outline (the
        :class:`exdex.PhysicsWarning` checks "pad" and "outline", on
        ``CHECK_SAMPLES`` samples of the run). Impacts on stops, the solver's
        soft problems and a 1-DoF reduction that fails (the plan's
        ``reduction_fails_at`` and its ReductionWarning say so) do not make a
        run invalid."""
        dt = self.t_end / CHECK_SAMPLES
        if self.scene.stops:
            dt = min(dt, 0.01)
        b = simulate_batch(self.scene, self.t_end, dt, record="all", warn=False, **self.options, **arrays)
        n = len(b)
        why: List[Optional[str]] = [None] * n
        lost = b.stats.get("grasp_lost_t")
        if lost is not None:
            for i in np.flatnonzero(np.isfinite(lost)):
                why[i] = f"the pads lost the object at t = {float(lost[i]):.4g} s"
        texts = {"pad": "the object slid beyond the pad", "outline": "the pad centre left the body outline"}
        geometry = any(k in ("patch_x", "patch_y") for k in arrays)
        groups = [(b.scene_at(i), [i]) for i in range(n)] if geometry else [(self.scene, list(range(n)))]
        for sc, idx in groups:
            q = b.q[idx]
            for chk in diagnostics.contact_checks(sc, q.reshape(-1, q.shape[-1])):
                mask = chk["mask"].reshape(q.shape[:2])
                for r in np.flatnonzero(mask.any(axis=1)):
                    i = idx[int(r)]
                    if why[i] is None:
                        j = int(np.flatnonzero(mask[r])[0])
                        why[i] = f"{texts.get(chk['kind'], chk['kind'])} at t = {float(b.t[j]):.4g} s"
        return np.array([w is None for w in why], dtype=bool), why


# -------------------------------------------------------------------- plan

@dataclass(frozen=True, eq=False)
class Plan:
    """A solution of :func:`solve`.

    scene : the scene that achieves the target (the base scene with the
        varied parameter replaced).
    parameter, value : the varied parameter and its value.
    quantity, target, achieved, residual : the target, the outcome of
        ``scene`` re-simulated by ``verify_method`` and achieved - target.
    cost : the plan's cost (see :func:`solve`'s ``cost``).
    reachable : (low, high) of the outcome over the bounds and limits.
    solutions : every parameter value found (one per monotone branch that
        reaches the target), least cost first.
    scan : (values, outcomes) of the batch scan (NaN where a limit is broken);
        robust plans: (values, worst-case |outcome - target|).
    worst_error : robust plans: the largest |outcome - target| over the
        uncertain parameters' samples (else NaN); band the outcome band there.
    rest_by : the time [s] by which the plan has the object at rest relative
        to the gripper (``target["rest_by"]``), or None.
    reduction_fails_at : for a translation or rotation scene, where the
        planned run's reduction fails (:attr:`exdex.Result.certificate`;
        the planner flags such a plan with an :class:`exdex.ReductionWarning`:
        past that time the planned outcome is not the grasp's), or None
        when it holds.
    t_end : the end time of the planner's runs [s].
    final_displacement : (1, ndof) the re-simulated run's q(t_end) - q(0)
        (None without ``verify``); :attr:`outcomes` reads every quantity from it.
    """

    scene: Scene
    parameter: str
    value: float
    quantity: str
    target: float
    achieved: float
    residual: float
    cost: float
    reachable: Tuple[float, float]
    solutions: Tuple[float, ...]
    scan: Tuple[np.ndarray, np.ndarray]
    tol: float
    worst_error: float = math.nan
    band: Optional["Band"] = None
    rest_by: Optional[float] = None
    reduction_fails_at: Optional[float] = None
    t_end: Optional[float] = None
    final_displacement: Optional[np.ndarray] = None

    @property
    def outcomes(self) -> Dict[str, float]:
        """Every quantity of the planned run that the scene has (see
        :data:`QUANTITY_HELP`; planar scenes: com_slide, contact_slip,
        rotation, x, y), from the re-simulated final displacement
        (``verify=True``; empty otherwise) [m or rad]."""
        if self.final_displacement is None:
            return {}
        names = {"translation": ("com_slide",), "rotation": ("rotation",),
                 "planar": ("com_slide", "contact_slip", "rotation", "x", "y")}[self.scene.dof]
        return {q: float(outcome(self.final_displacement, self.scene, q)[0]) for q in names}

    @property
    def meets_target(self) -> bool:
        """True if the plan meets the target within tol (robust plans: over the
        whole uncertainty, by its sampled worst case)."""
        if self.band is not None:
            return bool(self.worst_error <= self.tol)
        return bool(abs(self.residual) <= self.tol)

    @property
    def unit(self) -> str:
        """The unit of :attr:`value` (:func:`parameter_unit`: ``"x schedule"``
        for a grip force that scales a grip schedule)."""
        return parameter_unit(self.scene, self.parameter)

    def __repr__(self):
        u = QUANTITIES[self.quantity]
        s = (f"Plan({self.parameter} = {_with_unit(f'{self.value:.9g}', self.unit)}: {self.quantity} "
             f"{self.achieved:.6g} {u} (target {self.target:.6g} {u}, residual {self.residual:.2e} {u}), reachable "
             f"[{self.reachable[0]:.6g}, {self.reachable[1]:.6g}] {u}")
        if self.band is not None:
            s += f", worst error {self.worst_error:.3g} {u} over {self.band.describe()}"
        return s + ")"

    def gripper_poses(self, rate: float = 100.0, t_end: Optional[float] = None) -> Tuple[np.ndarray, np.ndarray]:
        """The planned gripper motion as poses at ``rate`` [Hz], what a robot
        controller consumes: ``(times, poses)``, poses (n, 7) rows
        x y z qw qx qy qz of frame B in the world (m, unit quaternion), from
        t = 0 to ``t_end`` (default: the motion's end)."""
        rate = _real(rate, "rate", low=0.0, low_open=True)
        motion = self.scene.motion
        end = motion.end_time if t_end is None else _real(t_end, "t_end", low=0.0)
        n = max(int(math.floor(end * rate + 1e-9)) + 1, 2)
        t = np.arange(n) / rate
        if t[-1] < end:
            t = np.append(t, end)
        k = motion.evaluate(t, self.scene.gripper_rotation, self.scene.gripper_position)
        from exdex._rotations import quat_from_matrix as _quat_from_matrix
        q = np.array([_quat_from_matrix(R) for R in k["R"]])
        return t, np.hstack([k["p"], q])

    def sampled_trajectory(self, rate: float = 100.0) -> SampledTrajectory:
        """The planned gripper motion as a :class:`exdex.SampledTrajectory`
        sampled at ``rate`` [Hz] (e.g. to replay it, or to add a tool offset)."""
        t, poses = self.gripper_poses(rate)
        return SampledTrajectory(t, poses[:, :3], poses[:, 3:])

    def plot(self, ax: Any = None) -> Any:
        """The scan (outcome against the parameter), the target and the plan."""
        if ax is None:
            plt = pyplot("Plan.plot")
            _, ax = plt.subplots(figsize=(6, 4), constrained_layout=True)
        x, y = self.scan
        u = QUANTITIES[self.quantity]
        ax.plot(x, y, ".-", label="scan")
        ax.axhline(self.target, color="k", lw=0.8, ls="--", label="target")
        ax.plot([self.value], [self.achieved], "o", color="C3", label="plan")
        ax.set_xlabel(f"{self.parameter} [{self.unit or '-'}]")
        ax.set_ylabel(f"{self.quantity} [{u}]")
        ax.legend()
        return ax


def _cost_of(cost, scene, name, value):
    if callable(cost):
        return float(cost(scene))
    if cost == "value":
        return float(value)
    pk = motion_peaks(scene.motion)
    if cost in ("acceleration", "speed", "duration"):
        return float(pk[cost])
    raise ValueError(f"cost must be 'acceleration', 'speed', 'duration', 'value' or a callable, got {cost!r}")


def _refine(f, a, b, ra, rb, tol, xtol, k, max_rounds):
    """Bracketing refinement of a root of r = f(x) - target between a and b
    (ra, rb of opposite signs): k equally spaced interior points and the
    secant root per batch; returns (x, r)
    of the first point with |r| <= tol, or the bracket end of least |r| when
    the bracket shrinks below xtol (a jump of the outcome: r never meets tol)."""
    for _ in range(max_rounds):
        if abs(ra) <= tol:
            return a, ra
        if abs(rb) <= tol:
            return b, rb
        if abs(b - a) <= xtol:
            break
        xs = np.linspace(a, b, k + 2)[1:-1]
        # plus the secant root of the bracket: where the outcome is smooth
        # it lands within tol after a round or two
        xsec = a - ra * (b - a) / (rb - ra) if rb != ra else 0.5 * (a + b)
        if a < xsec < b:
            xs = np.sort(np.append(xs, xsec))
        rs = f(xs)
        good = np.flatnonzero(np.abs(rs) <= tol)
        if good.size:
            i = good[np.argmin(np.abs(rs[good]))]
            return float(xs[i]), float(rs[i])
        X = np.concatenate(([a], xs, [b]))
        R = np.concatenate(([ra], rs, [rb]))
        s = np.flatnonzero(np.sign(R[:-1]) * np.sign(R[1:]) <= 0)
        j = int(s[0]) if s.size else int(np.argmin(np.abs(R[:-1])))
        a, b, ra, rb = float(X[j]), float(X[j + 1]), float(R[j]), float(R[j + 1])
    return (a, ra) if abs(ra) <= abs(rb) else (b, rb)


def _branches(y):
    """Index ranges [i, j] of the monotone runs of y (NaN splits runs)."""
    runs, i, n = [], 0, len(y)
    while i < n - 1:
        if not (np.isfinite(y[i]) and np.isfinite(y[i + 1])):
            i += 1
            continue
        j, s = i + 1, np.sign(y[i + 1] - y[i])
        while j < n - 1 and np.isfinite(y[j + 1]):
            s1 = np.sign(y[j + 1] - y[j])
            if s != 0 and s1 != 0 and s1 != s:
                break
            if s == 0:
                s = s1
            j += 1
        runs.append((i, j))
        i = j
    return runs


def solve(scene: Scene, target: Mapping[str, float], vary: Optional[Mapping[str, Tuple[float, float]]] = None, *,
          limits: Optional[Limits] = None, tol: float = 1e-6, t_end: Optional[float] = None,
          dt: Optional[float] = None, method: str = "auto", rtol: float = 1e-10, atol: float = 1e-12,
          eps: float = 1e-4, n_scan: int = 65, refine: int = 15,
          cost: Union[str, Callable[[Scene], float]] = "acceleration",
          uncertain: Optional[Mapping[str, Any]] = None, n_uncertain: int = 9, threads: Optional[int] = None,
          verify: bool = True, friction_solver: str = "scalar") -> Union[Plan, "MultiPlan", Any]:
    """Find the value of one scene parameter that makes a final quantity meet a target.

    Parameters
    ----------
    scene : exdex.Scene
        The base scene.
    target : dict
        One quantity and its wanted value, e.g. ``{"com_slide": 0.015}`` [m] or
        ``{"rotation": math.radians(30)}`` [rad] (see :data:`QUANTITIES`);
        several for a pose, e.g. ``{"x": 0.01, "y": -0.02, "rotation": 0.3}``
        (then several parameters vary, see below). With one varied parameter
        and one quantity the key ``"rest_by"`` [s] adds the time by which the
        object must be at rest relative to the gripper, e.g. ``{"slip":
        -0.015, "rest_by": 0.9}``: parameter values whose object still moves
        after it (relative speed above 1e-12 at rest_by, or coordinates that
        change between rest_by and t_end) are left out like a broken limit.
    vary : dict, optional
        ``{name: (low, high)}``: the parameter(s) to vary and their bounds
        (any :func:`exdex.simulate_batch` parameter). With one parameter and
        one target: the scan and bracket described above. With several:
        bounded nonlinear least squares on the targets' residuals (SciPy's
        trust-region reflective ``least_squares``, the Jacobian by central
        differences evaluated in one batch), started from the best points of
        a batch scan on a product grid; when the Jacobian at the solution
        has fewer independent rows than parameters the solutions form a
        family (a curve for one missing rank), returned as
        :attr:`MultiPlan.family` beside the least-cost representative.
        Omitted (None) with a planar pose target (any of ``x``, ``y``,
        ``rotation``) on a planar scene: the pose is reached by a sequence of
        motion primitives, :func:`exdex.sequence.solve` with its defaults
        (0.1 mm, 0.1 deg), which returns an :class:`exdex.sequence.SequencePlan`.
    limits : Limits, optional
        The robot's limits; parameter values whose motion breaks one are left out.
    tol : float
        Tolerance on the outcome (units of the quantity).
    t_end, dt : float, optional
        Simulated time [s] (default: the end of the motion and of the grip
        schedule, :attr:`exdex.Scene.end_time`, plus half of it) and
        output step (default t_end: the event method's answer does not
        depend on its output grid; at most 10 ms for scenes with stops,
        whose approach the output interval must not step over).
    method, rtol, atol, eps, friction_solver : as in :func:`exdex.simulate`
        (default "auto": the analytic path where it applies, else the event
        method, whose answer does not depend on the output grid).
    n_scan : int
        Scan points over the bounds (>= 3).
    refine : int
        Interior points per refinement round (>= 1).
    cost : {"acceleration", "speed", "duration", "value"} or callable
        Picks among several solutions: the gripper motion's peak acceleration,
        peak speed, duration, the parameter value, or ``cost(scene) -> float``.
    uncertain : dict, optional
        ``{name: (low, high)}`` of parameters known only within intervals.
        Then the plan minimises the worst-case |outcome - target| over
        ``n_uncertain`` samples per interval (a product grid, ends included),
        and ``Plan.band`` and ``Plan.worst_error`` describe it.
    verify : bool
        Re-simulate the plan with :func:`exdex.simulate` (``method``,
        ``rtol``) and report that outcome (default True).

    Returns
    -------
    Plan, MultiPlan (several parameters) or exdex.sequence.SequencePlan (no vary)

    Raises
    ------
    UnreachableTargetError
        When no parameter value within the bounds and limits reaches the
        target; ``.reachable`` gives the interval that can be reached.
    ValueError, TypeError
        For bad targets, bounds, limits or options, naming them.
    """
    if not isinstance(scene, Scene):
        raise TypeError(f"scene must be an exdex.Scene, got {type(scene).__name__}")
    if vary is None and scene.dof == "planar" and isinstance(target, Mapping) and target and \
            all(q in ("x", "y", "rotation") for q in target):
        from exdex.design import sequence
        return sequence.solve(scene, target)
    if not isinstance(vary, Mapping) or len(vary) < 1:
        raise ValueError("vary must be a dict of parameters and their bounds, e.g. {'grip_force': (0.5, 3.0)} "
                         "(only a planar pose target on a planar scene may omit it)")
    rest_by = None
    if isinstance(target, Mapping) and "rest_by" in target:
        target = dict(target)
        rest_by = _real(target.pop("rest_by"), "target['rest_by']", low=0.0, low_open=True)
        if not target:
            raise ValueError("target['rest_by'] constrains a plan: name a quantity too, e.g. "
                             "{'slip': -0.015, 'rest_by': 0.9}")
        if len(vary) > 1 or len(target) > 1 or uncertain is not None:
            raise ValueError("target['rest_by'] applies to plans with one varied parameter and one quantity "
                             "(not to several parameters or robust plans)")
    if len(vary) > 1 or (isinstance(target, Mapping) and len(target) > 1):
        if uncertain is not None:
            raise ValueError("robust planning (uncertain=...) varies one parameter; pass one entry in vary")
        return _solve_multi(scene, target, vary, limits=limits, tol=tol, t_end=t_end, dt=dt, method=method,
                            rtol=rtol, atol=atol, eps=eps, cost=cost, threads=threads, verify=verify,
                            n_scan=n_scan, friction_solver=friction_solver)
    quantity, goal = _target(target, scene)
    (raw, bnds), = vary.items()
    name = _param_name(raw, scene)
    lo, hi = _bounds(name, bnds)
    if limits is not None and not isinstance(limits, Limits):
        raise TypeError(f"limits must be an exdex.plan.Limits, got {type(limits).__name__}")
    tol = _real(tol, "tol", low=0.0, low_open=True)
    if isinstance(n_scan, bool) or not isinstance(n_scan, (int, np.integer)) or n_scan < 3:
        raise ValueError(f"n_scan must be an int >= 3, got {n_scan!r}")
    if isinstance(refine, bool) or not isinstance(refine, (int, np.integer)) or refine < 1:
        raise ValueError(f"refine must be an int >= 1, got {refine!r}")
    t_end, dt, opts = _times_and_options(scene, t_end, dt, method, rtol, atol, eps, threads, friction_solver)
    run = _Runner(scene, quantity, t_end, dt, opts)

    unc = _uncertain(uncertain, scene, exclude=name, n=n_uncertain)

    xs = np.linspace(lo, hi, int(n_scan))
    feasible = np.array([_feasible(scene, name, x, limits) for x in xs])
    if not feasible.any():
        raise UnreachableTargetError(
            f"no value of {name!r} in [{lo:g}, {hi:g}] keeps the motion within the limits "
            f"({', '.join(limits.violations(_replace_params(scene, {name: float(xs[0])}).motion)) if limits else ''}"
            f" at {lo:g})",
            (math.nan, math.nan))

    if unc:
        return _solve_robust(run, scene, name, xs, feasible, quantity, goal, tol, unc, refine, cost, verify,
                             limits)

    if rest_by is not None and rest_by > t_end:
        raise ValueError(f"target['rest_by'] must lie in (0, t_end] = (0, {t_end:g}] s, got {rest_by:g}; "
                         "pass a longer t_end")
    ys = np.full(xs.shape, np.nan)
    ys[feasible] = run(**{name: xs[feasible]})
    # runs that leave the grasp or the model are not reachable
    valid = np.zeros(xs.shape, bool)
    why: List[Optional[str]] = [None] * len(xs)
    if feasible.any():
        ok, reasons = run.check(**{name: xs[feasible]})
        valid[feasible] = ok
        for k, r in zip(np.flatnonzero(feasible).tolist(), reasons):
            why[k] = r
    # the edges of the valid runs, located between scan points by bisection
    # on the check: the reachable interval ends where the valid runs end
    extra = []
    for k in range(len(xs) - 1):
        if feasible[k] and feasible[k + 1] and valid[k] != valid[k + 1]:
            good, bad = (xs[k], xs[k + 1]) if valid[k] else (xs[k + 1], xs[k])
            for _ in range(60):
                if abs(bad - good) <= 1e-9 * max(abs(lo), abs(hi)):
                    break
                mid = 0.5 * (good + bad)
                if bool(run.check(**{name: np.array([mid])})[0][0]):
                    good = mid
                else:
                    bad = mid
            if good not in (xs[k], xs[k + 1]) and _feasible(scene, name, good, limits):
                extra.append(float(good))
    if extra:
        xe = np.array(extra)
        order = np.argsort(np.concatenate([xs, xe]), kind="stable")
        xs = np.concatenate([xs, xe])[order]
        ys = np.concatenate([ys, run(**{name: xe})])[order]
        valid = np.concatenate([valid, np.ones(len(xe), bool)])[order]
        feasible = np.concatenate([feasible, np.ones(len(xe), bool)])[order]
        why = [(why + [None] * len(xe))[int(i)] for i in order]
    ys_unchecked = ys.copy()
    ys[~valid] = np.nan
    invalid = feasible & ~valid
    if not valid.any():
        i = int(np.flatnonzero(invalid)[0])
        raise UnreachableTargetError(
            f"no value of {name!r} in [{lo:g}, {hi:g}]{' within the limits' if limits is not None else ''} "
            f"keeps the object in the grasp: every scan point's run leaves it or fails the physics checks "
            f"(at {name} = {xs[i]:.6g} {parameter_unit(scene, name)}: {why[i]})".replace("  ", " "),
            (math.nan, math.nan), invalid=int(invalid.sum()), scanned=int(feasible.sum()))
    ys_all = ys.copy()
    if rest_by is not None:
        # values whose object still moves after rest_by are left out, as a limit
        rest = np.zeros(xs.shape, bool)
        rest[feasible] = run.at_rest_by(rest_by, **{name: xs[feasible]})
        ys[~rest] = np.nan
        feasible = feasible & rest
        if not feasible.any():
            raise UnreachableTargetError(
                f"no value of {name!r} in [{lo:g}, {hi:g}] has the object at rest by target['rest_by'] = "
                f"{rest_by:g} s{' within the limits' if limits is not None else ''}", (math.nan, math.nan))
    f = lambda x: run(**{name: np.asarray(x)}) - goal  # noqa: E731
    xtol = 1e-13 * max(abs(lo), abs(hi))
    sols: list = []
    for i, j in _branches(ys):
        r = ys[i:j + 1] - goal
        for k in range(i, j):
            ra, rb = ys[k] - goal, ys[k + 1] - goal
            if ra == 0.0 or ra * rb < 0 or (k == j - 1 and rb == 0.0):
                x, rr = _refine(f, xs[k], xs[k + 1], ra, rb, tol, xtol, refine, 60)
                if abs(rr) <= tol and _feasible(scene, name, x, limits) and \
                        (rest_by is None or bool(run.at_rest_by(rest_by, **{name: np.array([x])})[0])) and \
                        not any(abs(x - s) <= xtol for s, _ in sols) and \
                        bool(run.check(**{name: np.array([x])})[0][0]):
                    sols.append((x, rr))
        del r
    fin = ys[np.isfinite(ys)]
    reach = (float(fin.min()), float(fin.max()))
    u = QUANTITIES[quantity]
    if not sols:
        where = "" if goal < reach[0] or goal > reach[1] else \
            " (it lies between the scan's values only across a jump of the outcome or a limit)"
        if invalid.any():
            i = int(np.flatnonzero(invalid)[0])
            bad = ys_unchecked[invalid]
            bad = bad[np.isfinite(bad)]
            span = f", which reach [{bad.min():.6g}, {bad.max():.6g}] {u}" if bad.size else ""
            where += (f"; {int(invalid.sum())} of {int(feasible.sum())} scan points are left out because their "
                      f"runs leave the grasp or fail the physics checks{span} (e.g. {name} = {xs[i]:.6g} "
                      f"{parameter_unit(scene, name)}: {why[i]})").replace("  ", " ")
        fin_all = ys_all[np.isfinite(ys_all)]
        if rest_by is not None and fin_all.size and fin_all.min() <= goal <= fin_all.max():
            where += (f"; without target['rest_by'] the scan reaches [{fin_all.min():.6g}, {fin_all.max():.6g}] "
                      f"{u}: the values that reach the target leave the object moving after {rest_by:g} s")
        raise UnreachableTargetError(
            f"target {quantity} {goal:.6g} {u} is not reachable by varying {name!r} in [{lo:g}, {hi:g}]"
            f"{' within the limits' if limits is not None else ''}"
            f"{f' with the object at rest by {rest_by:g} s' if rest_by is not None else ''}: reachable "
            f"[{reach[0]:.6g}, {reach[1]:.6g}] {u}{where}", reach, invalid=int(invalid.sum()),
            scanned=int(feasible.sum()))
    if len(sols) > 1:
        ranked = sorted(sols, key=lambda s: (_cost_of(cost, _replace_params(scene, {name: s[0]}), name, s[0]),
                                             s[0]))
    else:
        ranked = sols
    x, r = ranked[0]
    best = _replace_params(scene, {name: float(x)})
    achieved = goal + r
    d = None
    if verify:
        d, v_end, still = _final_state(best, t_end, dt, method, rtol, atol, eps,
                                       run._direct is not None and name not in ("patch_x", "patch_y"),
                                       friction_solver)
        achieved = float(outcome(d, best, quantity)[0])
        if not still:
            warnings.warn(f"the planned object is still moving at t_end = {t_end:g} s (relative speed "
                          f"{_speed_text(best, v_end)}): the 'final' {quantity} is not final; "
                          "pass a longer t_end", UserWarning, stacklevel=user_stacklevel())
    return Plan(scene=best, parameter=name, value=float(x), quantity=quantity, target=goal, achieved=achieved,
                residual=achieved - goal, cost=_cost_of(cost, best, name, x),
                reachable=(min(reach[0], achieved), max(reach[1], achieved)),
                solutions=tuple(float(s) for s, _ in ranked), scan=(xs, ys), tol=tol, rest_by=rest_by,
                reduction_fails_at=_flag_reduction(best, t_end, dt, opts), t_end=t_end,
                final_displacement=None if d is None else np.asarray(d, dtype=float).reshape(1, -1))


def _speed_text(scene, v):
    """The relative speed v (ndof,) of a run's end, with units."""
    v = np.asarray(v, dtype=float).ravel()
    if scene.dof == "planar":
        return f"{math.hypot(v[0], v[1]):.3g} m/s, turning at {abs(v[2]):.3g} rad/s"
    return f"{abs(v[0]):.3g} {'rad/s' if scene.dof == 'rotation' else 'm/s'}"


def _flag_reduction(scene, t_end, dt, opts):
    """The plan's reduction_fails_at (and its ReductionWarning, issued at the caller's caller)."""
    o = {k: v for k, v in opts.items() if k in ("method", "rtol", "atol", "eps", "friction_solver")}
    with warnings.catch_warnings(record=True) as rec:
        warnings.simplefilter("always")
        at = reduction_fails_at(scene, t_end, min(dt, t_end / 200), **o)
    for w in rec:
        if isinstance(w.message, ReductionWarning):
            warnings.warn(w.message, stacklevel=user_stacklevel())
    return at


def _final_state(scene, t_end, dt, method, rtol, atol, eps, analytic, friction_solver="scalar"):
    """(final displacement (1, ndof), final rates, at rest with exact stick)
    of ``scene`` simulated alone: by :func:`exdex.simulate`, or for a scene
    the analytic method solves, by the core's batch on that one trajectory
    (the same C solution without the Python result object)."""
    if analytic:
        out = _core.simulate_batch(scene.to_spec(method="analytic"), t_end, dt, threads=1, record="final")
        return out["displacement"], out["v"][0], bool(out["stick"][0])
    res = simulate(scene, t_end, dt, method=method, rtol=rtol, atol=atol, eps=eps,  # type: ignore[arg-type]
                   friction_solver=friction_solver)  # type: ignore[arg-type]
    return res.q[-1:] - res.q[:1], res.v[-1], bool(res.stick[-1])


def _feasible(scene, name, x, limits):
    if limits is None:
        return True
    try:
        s = _replace_params(scene, {name: float(x)})
    except (ValueError, TypeError):
        return False
    return not limits.violations(s.motion)


def _uncertain(uncertain, scene, exclude=None, n=9):
    if uncertain is None:
        return {}
    if not isinstance(uncertain, Mapping) or not uncertain:
        raise TypeError("uncertain must be a dict {name: (low, high)}, e.g. {'mu': (0.4, 0.6)}")
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 2:
        raise ValueError(f"n_uncertain must be an int >= 2, got {n!r}")
    out = {}
    for raw, iv in uncertain.items():
        name = _param_name(raw, scene)
        if name == exclude:
            raise ValueError(f"{name!r} cannot be both varied and uncertain")
        if isinstance(iv, (tuple, list)) and len(iv) == 2:
            lo, hi = _pair(iv, f"uncertain[{name!r}]")
            if not lo <= hi:
                raise ValueError(f"uncertain[{name!r}] must be (low, high) with low <= high, got {iv}")
            _bounds(name, (lo, hi if hi > lo else lo + abs(lo) * 1e-12 + 1e-300))
            out[name] = np.linspace(lo, hi, int(n))
        else:
            a = np.asarray(iv, dtype=float).ravel()
            if a.size < 1 or not np.all(np.isfinite(a)):
                raise ValueError(f"uncertain[{name!r}] must be an interval (low, high) or finite samples")
            out[name] = np.sort(a)
    return out


# -------------------------------------------------------------------- band

@dataclass(frozen=True, eq=False)
class Band:
    """Outcome band of a scene under uncertain parameters.

    low, high : the band [units of the quantity].
    exact : True when the outcome is monotone in every uncertain parameter on
        its samples, so the band's ends are the outcome at interval ends
        (exact to the simulation's accuracy); False: the extremes of the
        samples, which may miss a narrow excursion by up to ``bound``.
    bound : the largest change of the outcome between neighbouring samples
        (0 when exact).
    samples : {name: sample values}; outcomes : the outcome on their product grid.
    """

    quantity: str
    low: float
    high: float
    exact: bool
    bound: float
    samples: Dict[str, np.ndarray]
    outcomes: np.ndarray
    units: Dict[str, str] = field(default_factory=dict)

    def describe(self) -> str:
        """The uncertain parameters' intervals, with their units."""
        return ", ".join(_with_unit(f"{k} in [{v[0]:.4g}, {v[-1]:.4g}]", self.units.get(k, ""))
                         for k, v in self.samples.items())

    def __repr__(self):
        u = QUANTITIES[self.quantity]
        kind = "exact ends (monotone)" if self.exact else f"sampled, may miss up to {self.bound:.2g} {u}"
        return f"Band({self.quantity} in [{self.low:.6g}, {self.high:.6g}] {u} for {self.describe()}; {kind})"


def _monotone(y, axis):
    """Monotone along axis, up to rounding: steps within 64 ulps of the
    outcomes' magnitude count as flat (an outcome that does not depend on the
    parameter, e.g. a slide onto a stop, is then exactly monotone)."""
    d = np.diff(y, axis=axis)
    tol = 64 * np.finfo(float).eps * float(np.max(np.abs(y), initial=0.0))
    return bool(np.all(d >= -tol) or np.all(d <= tol))


def _make_band(quantity, samples, Y, scene=None):
    names = list(samples)
    mono = all(_monotone(Y, ax) for ax in range(len(names)))
    if mono:
        corners = Y[tuple(slice(None, None, max(1, s - 1)) for s in Y.shape)]
        lo, hi, bound = float(corners.min()), float(corners.max()), 0.0
    else:
        lo, hi = float(Y.min()), float(Y.max())
        bound = max(float(np.max(np.abs(np.diff(Y, axis=ax)), initial=0.0)) for ax in range(Y.ndim))
    units = {k: parameter_unit(scene, k) for k in samples} if scene is not None else {}
    return Band(quantity=quantity, low=lo, high=hi, exact=mono, bound=bound, samples=dict(samples), outcomes=Y,
                units=units)


def band(scene: Scene, quantity: str, uncertain: Mapping[str, Any], *, n: int = 17, t_end: Optional[float] = None,
         dt: Optional[float] = None, method: str = "auto", rtol: float = 1e-10, atol: float = 1e-12,
         eps: float = 1e-4, threads: Optional[int] = None, friction_solver: str = "scalar") -> Band:
    """The band of a final quantity when parameters are known only within intervals.

    ``uncertain`` maps parameter names to intervals ``(low, high)`` (or to
    arrays of samples). The outcome is computed on the product grid of ``n``
    samples per interval in one batch. Where it is monotone in every
    parameter on the samples (checked), the band's ends are the outcomes at
    the intervals' corners, exact; otherwise the band is the samples' range
    and ``Band.bound`` states what the sampling may miss. Returns a :class:`Band`.
    """
    if not isinstance(scene, Scene):
        raise TypeError(f"scene must be an exdex.Scene, got {type(scene).__name__}")
    _check_quantity(quantity, scene)
    unc = _uncertain(uncertain, scene, n=n)
    t_end, dt, opts = _times_and_options(scene, t_end, dt, method, rtol, atol, eps, threads, friction_solver)
    run = _Runner(scene, quantity, t_end, dt, opts)
    k = len(unc)
    grids = {name: v.reshape((1,) * i + (-1,) + (1,) * (k - i - 1)) for i, (name, v) in enumerate(unc.items())}
    Y = run(**grids)
    return _make_band(quantity, unc, Y, scene)


def _solve_robust(run, scene, name, xs, feasible, quantity, goal, tol, unc, refine, cost, verify, limits):
    """Minimise the worst-case |outcome - target| over the uncertain samples."""
    k = len(unc)
    grids = {u: v.reshape((1,) + (1,) * i + (-1,) + (1,) * (k - i - 1)) for i, (u, v) in enumerate(unc.items())}

    def worst(x):
        x = np.asarray(x, dtype=float)
        Y = run(**{name: x.reshape((-1,) + (1,) * k)}, **grids)
        return np.max(np.abs(Y - goal).reshape(len(x), -1), axis=1), Y

    W = np.full(xs.shape, np.inf)
    W[feasible], _ = worst(xs[feasible])
    # nominal runs that leave the grasp or fail the physics checks are no plan
    valid = np.zeros(xs.shape, bool)
    valid[feasible] = run.check(**{name: xs[feasible]})[0]
    if not valid.any():
        raise UnreachableTargetError(
            f"no value of {name!r} in [{xs[0]:g}, {xs[-1]:g}] keeps the nominal object in the grasp: every scan "
            "point's run leaves it or fails the physics checks", (math.nan, math.nan),
            invalid=int(feasible.sum()), scanned=int(feasible.sum()))
    W[~valid] = np.inf
    i = int(np.argmin(W))
    a, b = xs[max(i - 1, 0)], xs[min(i + 1, len(xs) - 1)]
    best_x, best_w = float(xs[i]), float(W[i])
    for _ in range(30):
        if b - a <= 1e-12 * max(abs(a), abs(b), 1e-300):
            break
        cand = np.linspace(a, b, refine + 2)
        cand = cand[[_feasible(scene, name, c, limits) for c in cand]]
        if cand.size == 0:
            break
        w, _ = worst(cand)
        j = int(np.argmin(w))
        if w[j] < best_w:
            best_x, best_w = float(cand[j]), float(w[j])
        a, b = cand[max(j - 1, 0)], cand[min(j + 1, len(cand) - 1)]
        if best_w <= 0.25 * tol:
            break
    if not run.check(**{name: np.array([best_x])})[0][0]:
        best_x, best_w = float(xs[i]), float(W[i])   # the refinement left the valid runs: the best scan point
    best = _replace_params(scene, {name: best_x})
    w, Y = worst(np.array([best_x]))
    bd = _make_band(quantity, unc, Y[0], scene)
    ys = run(**{name: xs[valid]})
    reach = (float(np.nanmin(ys)), float(np.nanmax(ys)))
    nominal = float(run(**{name: np.array([best_x])})[0])
    return Plan(scene=best, parameter=name, value=best_x, quantity=quantity, target=goal, achieved=nominal,
                residual=nominal - goal, cost=_cost_of(cost, best, name, best_x), reachable=reach,
                solutions=(best_x,), scan=(xs, np.where(feasible, W, np.nan)), tol=tol, worst_error=float(w[0]),
                band=bd, reduction_fails_at=_flag_reduction(best, run.t_end, run.dt, run.options), t_end=run.t_end)


# ------------------------------------------------------- several parameters

@dataclass(frozen=True, eq=False)
class MultiPlan:
    """A solution of :func:`solve` with several varied parameters.

    scene : the representative scene (least cost among the family found).
    values : {parameter: value}; targets, achieved, residuals : {quantity: ...}.
    cost : its cost; tol : the tolerance (max |residual| <= tol is met).
    rank : the rank of the targets' Jacobian in the scaled parameters
        (p / parameter range) at the solution; ``len(values) - rank`` is the
        dimension of the solution set there (1: a curve).
    family : for a solution curve, parameter dicts of other solutions along
        it (each meets the targets within tol), ordered by the first
        parameter; empty when the solution is isolated.
    """

    scene: Scene
    values: Dict[str, float]
    targets: Dict[str, float]
    achieved: Dict[str, float]
    residuals: Dict[str, float]
    cost: float
    tol: float
    rank: int
    family: Tuple[Dict[str, float], ...]
    reduction_fails_at: Optional[float] = None

    @property
    def meets_target(self) -> bool:
        return bool(max(abs(r) for r in self.residuals.values()) <= self.tol)

    @property
    def is_family(self) -> bool:
        """True when the solution set is not a point (a curve or more)."""
        return self.rank < len(self.values)

    def __repr__(self) -> str:
        v = ", ".join(f"{k} = {_with_unit(f'{x:.6g}', parameter_unit(self.scene, k))}" for k, x in self.values.items())
        r = ", ".join(f"{k} {self.achieved[k]:.6g} {QUANTITIES[k]} (target {self.targets[k]:.6g} {QUANTITIES[k]})"
                      for k in self.targets)
        fam = (f"; a {len(self.values) - self.rank}-dimensional family of solutions, {len(self.family)} listed"
               if self.is_family else "")
        res = max(self.residuals, key=lambda k: abs(self.residuals[k]))
        return (f"MultiPlan({v}: {r}, max residual {abs(self.residuals[res]):.2e} {QUANTITIES[res]} ({res})"
                f"{fam})")


def _targets(target, scene):
    if not isinstance(target, Mapping) or not target:
        raise TypeError("target must be a dict {quantity: value}, e.g. {'x': 0.01, 'rotation': 0.3}")
    out = {}
    for q, v in target.items():
        _check_quantity(q, scene)
        out[q] = _real(v, f"target[{q!r}]")
    return out


def _solve_multi(scene, target, vary, *, limits, tol, t_end, dt, method, rtol, atol, eps, cost, threads, verify,
                 n_scan, friction_solver="scalar"):
    from exdex._optional import require

    least_squares = require("scipy.optimize", "planning with several parameters").least_squares
    goals = _targets(target, scene)
    names = []
    for raw in vary:
        n = _param_name(raw, scene)
        if n in names:
            raise ValueError(f"vary names {n!r} twice")
        names.append(n)
    bounds = np.array([_bounds(n, vary[raw]) for n, raw in zip(names, vary)])
    if limits is not None and not isinstance(limits, Limits):
        raise TypeError(f"limits must be an exdex.plan.Limits, got {type(limits).__name__}")
    tol = _real(tol, "tol", low=0.0, low_open=True)
    t_end, dt, opts = _times_and_options(scene, t_end, dt, method, rtol, atol, eps, threads, friction_solver)
    opts["record"] = "final"
    quantities = list(goals)
    goal = np.array([goals[q] for q in quantities])
    k = len(names)
    lo, hi = bounds[:, 0], bounds[:, 1]
    span = hi - lo
    # stay strictly inside open parameter ranges
    lo_in, hi_in = lo + 1e-9 * span, hi - 1e-9 * span

    def outcomes(P):
        P = np.atleast_2d(P)
        vary_arrays: Dict[str, Any] = {n: P[:, i] for i, n in enumerate(names)}
        b = simulate_batch(scene, t_end, dt, **opts, **vary_arrays)
        return np.stack([outcome(b.final_displacement, scene, q) for q in quantities], axis=1)

    checker = _Runner(scene, quantities[0], t_end, dt, {k: v for k, v in opts.items() if k != "record"})

    def valid(x):
        """The run at parameters x keeps the object in the grasp and passes the physics checks."""
        return bool(checker.check(**{n: np.array([float(a)]) for n, a in zip(names, x)})[0][0])

    def feasible(x):
        return _feasible(scene, names[0], x[0], None) and (
            limits is None or not limits.violations(_replace_params(scene, dict(zip(names, map(float, x)))).motion))

    # batch scan on a product grid (n_scan^2 points: n_scan per axis for two
    # parameters), the best points start the least squares
    per = max(3, int(round(n_scan ** (2.0 / k))))
    axes = [np.linspace(lo_in[i], hi_in[i], per) for i in range(k)]
    grid = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, k)
    if limits is not None:
        grid = grid[[feasible(x) for x in grid]]
        if not len(grid):
            raise UnreachableTargetError("no parameter values within the bounds keep the motion within the limits",
                                         (math.nan, math.nan))
    try:
        Y = outcomes(grid)
    except SolverError:
        # the scan only picks starting points: where the requested method
        # fails somewhere on the grid, scan with the implicit method (it
        # returns on every valid scene) and refine with the requested one
        scan_opts = dict(opts, method="implicit")
        vary_arrays: Dict[str, Any] = {n: grid[:, i] for i, n in enumerate(names)}
        b = simulate_batch(scene, t_end, min(dt, t_end / 1000), **scan_opts, **vary_arrays)
        Y = np.stack([outcome(b.final_displacement, scene, q) for q in quantities], axis=1)
    err = np.max(np.abs(Y - goal), axis=1)
    starts = grid[np.argsort(err)[:4]]

    def resid(z):
        return outcomes(lo + z * span)[0] - goal

    def jac(z):
        h = 1e-6
        zp, zm = np.minimum(z + h, 1.0 - 1e-9), np.maximum(z - h, 1e-9)
        P = np.repeat(z[None, :], 2 * k, axis=0)
        for i in range(k):
            P[2 * i, i], P[2 * i + 1, i] = zp[i], zm[i]
        Yp = outcomes(lo + P * span)
        return np.stack([(Yp[2 * i] - Yp[2 * i + 1]) / (zp[i] - zm[i]) for i in range(k)], axis=1)

    sols = []
    for x0 in starts:
        r = least_squares(resid, (x0 - lo) / span, jac=jac, bounds=(np.full(k, 1e-9), np.full(k, 1 - 1e-9)),
                          method="trf", xtol=1e-14, ftol=1e-14, gtol=1e-14, max_nfev=200)
        x = lo + r.x * span
        if np.max(np.abs(r.fun)) <= tol and (limits is None or feasible(x)) and valid(x):
            sols.append((x, r))
    if not sols:
        best = grid[int(np.argmin(err))]
        raise UnreachableTargetError(
            f"targets {goals} not met within tol {tol:g} by varying {names} in their bounds"
            f"{' within the limits' if limits is not None else ''}: the closest scanned point "
            f"{dict(zip(names, map(float, best)))} misses by {float(err.min()):.3g}",
            (float(err.min()), math.nan))
    costs = [_cost_of(cost, _replace_params(scene, dict(zip(names, map(float, x)))), names[0], x[0])
             for x, _ in sols]
    x, r = sols[int(np.argmin(costs))]
    J = jac(r.x)
    S = np.linalg.svd(J, compute_uv=False)
    rank = int(np.sum(S > 1e-8 * S.max())) if S.size and S.max() > 0 else 0
    family = []
    if rank < k:
        # a curve (or more) of solutions: fix the first parameter at values
        # across its bounds and solve for the others
        for v in np.linspace(lo_in[0], hi_in[0], 9):
            if k == 1:
                break
            zv = (v - lo[0]) / span[0]

            def resid_fixed(z, zv=zv):
                return resid(np.concatenate([[zv], z]))

            def jac_fixed(z, zv=zv):
                return jac(np.concatenate([[zv], z]))[:, 1:]
            z0 = (x[1:] - lo[1:]) / span[1:]
            rf = least_squares(resid_fixed, np.clip(z0, 1e-9, 1 - 1e-9), jac=jac_fixed,
                               bounds=(np.full(k - 1, 1e-9), np.full(k - 1, 1 - 1e-9)), method="trf",
                               xtol=1e-14, ftol=1e-14, gtol=1e-14, max_nfev=100)
            xf = np.concatenate([[v], lo[1:] + rf.x * span[1:]])
            if np.max(np.abs(rf.fun)) <= tol and (limits is None or feasible(xf)) and valid(xf):
                family.append({n: float(a) for n, a in zip(names, xf)})
    values = {n: float(a) for n, a in zip(names, x)}
    best_scene = _replace_params(scene, values)
    achieved_arr = goal + r.fun
    if verify:
        res = simulate(best_scene, t_end, dt, method=method, rtol=rtol, atol=atol, eps=eps,  # type: ignore[arg-type]
                       friction_solver=friction_solver)  # type: ignore[arg-type]
        d = res.q[-1:] - res.q[:1]
        achieved_arr = np.array([outcome(d, best_scene, q)[0] for q in quantities])
    achieved = {q: float(a) for q, a in zip(quantities, achieved_arr)}
    return MultiPlan(scene=best_scene, values=values, targets=dict(goals), achieved=achieved,
                     residuals={q: achieved[q] - goals[q] for q in quantities}, cost=float(min(costs)), tol=tol,
                     rank=rank, family=tuple(family),
                     reduction_fails_at=_flag_reduction(best_scene, t_end, dt, opts))

"""Sensitivities of a simulation to its parameters, and identification of
uncertain parameters from an observed in-hand trajectory.

:func:`sensitivity` gives d q(t_end) / dp and d qd(t_end) / dp for scalar
scene parameters (any :func:`exdex.simulate_batch` parameter: ``mu``,
``mu_static`` (kept >= mu), ``grip_force``, ``mass``, ``e_r``, ``beta``,
``duration``, ``amplitude``, ``v_max``) by central differences on a ladder of steps, all evaluated in one
batch, with Richardson extrapolation and an error estimate from the ladder
(the difference of successive extrapolations). Where the solution is
piecewise polynomial in the parameter (the analytic 1-DoF path: positions
quadratic in time, event times roots of linear equations) the extrapolated
central difference is exact up to rounding unless an event appears or
vanishes inside the step, which the error estimate shows.

:func:`event_times` finds the first slip onset and the end of the last slip
of a run by bisection, and :func:`event_sensitivity` differentiates them
with respect to scalar parameters the same way (central differences,
Richardson, an error estimate).

:func:`identify` fits uncertain parameters to an observed trajectory of the
object relative to the gripper (e.g. a tracked pose from a robot
experiment) by nonlinear least squares (SciPy's trust-region reflective
``least_squares``, bounds respected) with the batch finite-difference
Jacobian, and reports each parameter's standard error and 95 % interval from
the Jacobian at the solution, and the parameter combinations the data
cannot identify (singular values of the scaled Jacobian below ``1e-8`` of
the largest): e.g. ``mu`` and ``grip_force`` enter a grasp only through the
capacity mu N, so a trajectory fixes their product, never both.

Units are SI.
"""
from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field
from typing import Any, Dict, List, Mapping, Optional, Sequence, Tuple, Union

import numpy as np
from numpy.typing import ArrayLike

from exdex._params import PARAMETERS, param_name as _param_name, replace_params as _replace_params
from exdex.batch import simulate_batch
from exdex.diagnostics import ReductionWarning
from exdex._validate import real as _real
from exdex.scene import GripSchedule, Scene
from exdex.simulate import reduction_fails_at, resolve_method

__all__ = ["Sensitivity", "sensitivity", "EventTimes", "event_times", "EventSensitivity", "event_sensitivity",
           "Identification", "identify"]


def _scene_params(scene, params):
    """The canonical names of params (one name or a sequence of them, at
    least one) for scene, an exdex.Scene: TypeError/ValueError otherwise."""
    if not isinstance(scene, Scene):
        raise TypeError(f"scene must be an exdex.Scene, got {type(scene).__name__}")
    if isinstance(params, str):
        params = (params,)
    names = tuple(_param_name(p, scene) for p in params)
    if not names:
        raise ValueError("params must name at least one parameter")
    return names


def _batch_method(scene, method, names):
    """The method of a batch varying ``names``: ``resolve_method``, except that
    "auto" stays off the analytic path when the pad centre varies (the
    analytic path needs a rotation scene's pivot at the centre of mass)."""
    if method == "auto" and any(n in ("patch_x", "patch_y") for n in names):
        return "event"
    return resolve_method(scene, method)


def _value_of(scene, name):
    if name == "mu_static":   # None: equal to mu
        return float(scene.grasp.static_mu)
    obj = scene
    for part in PARAMETERS[name].path:
        obj = obj[part] if isinstance(part, int) else getattr(obj, part)
    if isinstance(obj, GripSchedule):
        return 1.0  # grip_force on a schedule is a factor on it (batch.py), 1 for the schedule as given
    return float(obj)


def _inside(name, x, scene=None):
    p = PARAMETERS[name]
    if name == "mu_static" and scene is not None and x < scene.grasp.mu:
        return False          # the static coefficient stays >= mu
    if p.low is not None and (x <= p.low if p.low_open else x < p.low):
        return False
    if p.high is not None and (x >= p.high if p.high_open else x > p.high):
        return False
    return True


@dataclass(frozen=True, eq=False)
class Sensitivity:
    """Derivatives of the final state with respect to parameters.

    params : the parameter names, in order; values : their values.
    dq, dv : (n_params, ndof) d q(t_end) / dp and d qd(t_end) / dp.
    error : (n_params, ndof) estimated absolute error of dq (the spread of
        the Richardson ladder); a large value flags a kink (an event that
        appears or vanishes within the step) where no derivative exists.
    """

    params: Tuple[str, ...]
    values: Dict[str, float]
    dq: np.ndarray
    dv: np.ndarray
    error: np.ndarray
    t_end: float
    method: str

    def __getitem__(self, name: str) -> np.ndarray:
        """d q(t_end) / d name, (ndof,)."""
        return self.dq[self.params.index(name)]

    def __repr__(self) -> str:
        rows = ", ".join(f"d q/d {p} = {np.array2string(self.dq[i], precision=6)}" for i, p in
                         enumerate(self.params))
        return f"Sensitivity(t_end={self.t_end:g} s, {rows})"


def _fd_steps(scene, name, p0, rel_step, levels):
    """Central-difference steps h, h/2, ..., h/2^(levels-1) for parameter
    ``name`` at ``p0``: h = rel_step |p0| (rel_step when p0 = 0), halved
    until p0 +- h both lie inside the parameter's range."""
    h = rel_step * (abs(p0) if p0 != 0.0 else 1.0)
    while not (_inside(name, p0 - h, scene) and _inside(name, p0 + h, scene)) and h > 1e-300:
        h *= 0.5
    if not h > 1e-300:
        raise ValueError(f"cannot step {name!r} = {p0:g} inside its range {PARAMETERS[name].describe()}")
    return h / 2.0 ** np.arange(levels)


def sensitivity(scene: Scene, params: Sequence[str], t_end: float, *, dt: Optional[float] = None,
                method: str = "auto", rtol: float = 1e-10, atol: float = 1e-12, eps: float = 1e-4,
                rel_step: float = 1e-3, levels: int = 4) -> Sensitivity:
    """d q(t_end) / dp and d qd(t_end) / dp for each named parameter.

    Central differences at steps h, h/2, ..., h/2^(levels-1) (h = rel_step
    |p|, shrunk to keep p +- h in the parameter's range), Richardson
    extrapolation of successive pairs (second order -> fourth), and the
    extrapolation with the smallest difference to its neighbour is returned
    with that difference as its error estimate. All 2 levels trajectories
    of a parameter run in one batch. ``method`` as in :func:`exdex.simulate`
    (default "auto": the analytic path where it applies, else the event
    method at ``rtol``).
    """
    names = _scene_params(scene, params)
    t_end = _real(t_end, "t_end", low=0.0, low_open=True)
    dt = t_end if dt is None else _real(dt, "dt", low=0.0, low_open=True, high=t_end)
    rel_step = _real(rel_step, "rel_step", low=0.0, high=0.5, low_open=True)
    if isinstance(levels, bool) or not isinstance(levels, (int, np.integer)) or not 2 <= levels <= 20:
        raise ValueError(f"levels must be an int in [2, 20], got {levels!r}")
    method = _batch_method(scene, method, names)
    opts: Dict[str, Any] = dict(method=method, rtol=rtol, atol=atol, eps=eps, record="final")
    dq: List[np.ndarray] = []
    dv: List[np.ndarray] = []
    err: List[np.ndarray] = []
    vals: Dict[str, float] = {}
    for name in names:
        p0 = _value_of(scene, name)
        vals[name] = p0
        hs = _fd_steps(scene, name, p0, rel_step, levels)
        x = np.concatenate([p0 + hs, p0 - hs])
        vary: Dict[str, Any] = {name: x}
        b = simulate_batch(scene, t_end, dt, **opts, **vary)
        qp, qm = b.q[:levels], b.q[levels:]
        vp, vm = b.v[:levels], b.v[levels:]
        Dq = (qp - qm) / (2 * hs[:, None])
        Dv = (vp - vm) / (2 * hs[:, None])
        Rq = (4 * Dq[1:] - Dq[:-1]) / 3
        Rv = (4 * Dv[1:] - Dv[:-1]) / 3
        if len(Rq) >= 2:
            e = np.abs(np.diff(Rq, axis=0))          # (levels - 2, ndof)
            k = np.argmin(e.max(axis=1))
            dq.append(Rq[k + 1])
            dv.append(Rv[k + 1])
            err.append(e[k])
        else:
            dq.append(Rq[0])
            dv.append(Rv[0])
            err.append(np.abs(Rq[0] - Dq[1]))
    return Sensitivity(params=names, values=vals, dq=np.array(dq), dv=np.array(dv), error=np.array(err),
                       t_end=t_end, method=method)


# ------------------------------------------------------------- event times

@dataclass(frozen=True)
class EventTimes:
    """When the object first slips and when its last slip ends [s].

    onset : the first time the object moves relative to the gripper (NaN:
        it never does before t_end); stop : the end of the last slip before
        t_end (NaN: no slip; inf: still moving at t_end); xtol : the width
        of the brackets the times were bisected to [s].
    """

    onset: float
    stop: float
    xtol: float


def _moving(model, t, dt_max):
    dt = t if dt_max is None else min(t, dt_max)
    _, v, _ = model.final(t, dt)
    return any(x != 0.0 for x in v)


def _bisect(model, a, b, moving_at_b, xtol, dt_max):
    """The switch between [a, b] of the predicate 'moving' (False at a when
    moving_at_b, else True at a): bisection to xtol; returns the midpoint."""
    while b - a > xtol:
        m = 0.5 * (a + b)
        if m <= a or m >= b:
            break
        if _moving(model, m, dt_max) == moving_at_b:
            b = m
        else:
            a = m
    return 0.5 * (a + b)


def event_times(scene: Scene, t_end: float, *, method: str = "auto", rtol: float = 1e-10, atol: float = 1e-12,
                eps: float = 1e-4, n_grid: int = 1024, xtol: float = 1e-13) -> EventTimes:
    """The first slip onset and the end of the last slip of a scene, by bisection.

    A run on ``n_grid`` output intervals finds the first and the last
    interval where the relative speed is nonzero (both the analytic path and
    the event method hold a stuck object at exactly zero relative speed);
    each time is then bisected within its interval to ``xtol`` [s] on the
    predicate "moving at t" (the relative speed of a run ending at t, a
    compiled :class:`exdex.Model`, output step t for scenes without stops,
    at most t_end / n_grid with stops). A slip episode shorter than one grid
    interval between two rests can be missed: raise ``n_grid``.
    """
    from exdex.simulate import simulate
    from exdex.stepper import Model
    if not isinstance(scene, Scene):
        raise TypeError(f"scene must be an exdex.Scene, got {type(scene).__name__}")
    t_end = _real(t_end, "t_end", low=0.0, low_open=True)
    if isinstance(n_grid, bool) or not isinstance(n_grid, (int, np.integer)) or n_grid < 2:
        raise ValueError(f"n_grid must be an int >= 2, got {n_grid!r}")
    xtol = _real(xtol, "xtol", low=0.0, low_open=True)
    method = resolve_method(scene, method)
    dt = t_end / int(n_grid)
    r = simulate(scene, t_end, dt, method=method, rtol=rtol, atol=atol, eps=eps)  # type: ignore[arg-type]
    moving = np.any(r.v != 0.0, axis=1)
    idx = np.flatnonzero(moving)
    if idx.size == 0:
        return EventTimes(onset=math.nan, stop=math.nan, xtol=xtol)
    model = Model(scene, method=method, rtol=rtol, atol=atol, eps=eps)  # type: ignore[arg-type]
    dt_max = dt if scene.stops else None
    i = int(idx[0])
    onset = 0.0 if i == 0 else _bisect(model, float(r.t[i - 1]), float(r.t[i]), True, xtol, dt_max)
    j = int(idx[-1])
    stop = math.inf if j == len(r.t) - 1 else _bisect(model, float(r.t[j]), float(r.t[j + 1]), False, xtol,
                                                        dt_max)
    return EventTimes(onset=float(onset), stop=float(stop), xtol=xtol)


@dataclass(frozen=True, eq=False)
class EventSensitivity:
    """Derivatives of the event times with respect to parameters.

    params, values : the parameters and their values; times : the
    :class:`EventTimes` at those values. donset, dstop : (n_params,)
    d onset / dp and d stop / dp [s per unit of p]; onset_error, stop_error :
    their estimated errors (the spread of the Richardson ladder; 0 when
    exact); NaN where the event does not exist at the nominal values.
    exact : True when the derivatives were carried exactly through the
    piecewise-analytic solution rather than differenced.
    """

    params: Tuple[str, ...]
    values: Dict[str, float]
    times: EventTimes
    donset: np.ndarray
    dstop: np.ndarray
    onset_error: np.ndarray
    stop_error: np.ndarray
    exact: bool = False

    def __repr__(self) -> str:
        rows = ", ".join(f"d onset/d {p} = {self.donset[i]:.6g} (+- {self.onset_error[i]:.1g}), d stop/d {p} = "
                         f"{self.dstop[i]:.6g} (+- {self.stop_error[i]:.1g})" for i, p in enumerate(self.params))
        return f"EventSensitivity(onset {self.times.onset:.9g} s, stop {self.times.stop:.9g} s; {rows})"


class _Dual:
    """A value and its gradient (forward-mode differentiation): arithmetic
    carries exact first derivatives, comparisons look at the value."""

    __slots__ = ("v", "g")

    def __init__(self, v, g):
        self.v, self.g = float(v), np.asarray(g, dtype=float)

    @staticmethod
    def _lift(x, n):
        return x if isinstance(x, _Dual) else _Dual(x, np.zeros(n))

    def __add__(self, o):
        o = _Dual._lift(o, len(self.g))
        return _Dual(self.v + o.v, self.g + o.g)

    __radd__ = __add__

    def __sub__(self, o):
        o = _Dual._lift(o, len(self.g))
        return _Dual(self.v - o.v, self.g - o.g)

    def __rsub__(self, o):
        return _Dual._lift(o, len(self.g)) - self

    def __mul__(self, o):
        o = _Dual._lift(o, len(self.g))
        return _Dual(self.v * o.v, self.g * o.v + self.v * o.g)

    __rmul__ = __mul__

    def __truediv__(self, o):
        o = _Dual._lift(o, len(self.g))
        return _Dual(self.v / o.v, (self.g * o.v - self.v * o.g) / (o.v * o.v))

    def __rtruediv__(self, o):
        return _Dual._lift(o, len(self.g)) / self

    def __neg__(self):
        return _Dual(-self.v, -self.g)


def _dual_events(phases, capacity, n):
    """Slip onsets and stops [(time as _Dual, kind)] of the 1-DoF Coulomb
    problem x'' = d(t) + f, |f| <= capacity, exact stick, from rest: the
    algorithm of exdex.paper.coulomb_1dof (phases of constant drive, stops at
    t = -v / a) on dual numbers, so each event time carries its exact
    derivative with respect to the parameters the inputs depend on; and the
    smallest relative margin | |d| - capacity | / max of the two met by a
    rest test (near 0: the grasp is at a threshold where a slip can appear
    or vanish, and the derivative is one-sided)."""
    zero = _Dual(0.0, np.zeros(n))
    v, moving, events = zero, False, []
    margin = math.inf
    for ta, tb, d in phases:
        t = ta
        while t.v < tb.v:
            if v.v == 0.0:
                margin = min(margin, abs(abs(d.v) - capacity.v) / max(capacity.v, abs(d.v), 1e-300))
                if abs(d.v) <= capacity.v:
                    if moving:
                        events.append((t, "stick"))
                        moving = False
                    break
                if not moving:
                    events.append((t, "slip"))
                    moving = True
                a = d - capacity if d.v > 0 else d + capacity
            else:
                a = d - capacity if v.v > 0 else d + capacity
                if a.v * v.v < 0:
                    ts = -v / a
                    if (t + ts).v < tb.v:
                        v = zero
                        t = t + ts
                        continue
            if math.isfinite(tb.v):
                v = v + a * (tb - t)
            t = tb
    return events, margin


def _exact_event_derivatives(scene, names, t_end):
    """(d onset / dp, d stop / dp, threshold margin) exactly, for scenes of the closed form
    (exdex.paper.closed_form: 1-DoF, Eq. 7 motion, no stops, pivot at the
    centre of mass, constant grip) and parameters among mu, grip_force,
    mass, e_r, amplitude, duration, beta; None otherwise."""
    from exdex._closed_form import closed_form, world_dir
    from exdex.scene import AsymmetricProfile
    allowed = ("mu", "grip_force", "mass", "e_r", "amplitude", "duration", "beta")
    if not isinstance(scene.motion, AsymmetricProfile) or any(n not in allowed for n in names) or \
            not isinstance(scene.grasp.grip_force, (int, float)) or \
            getattr(scene.grasp, "mu_static", None) not in (None, scene.grasp.mu):
        return None
    try:
        closed_form(scene)
    except (ValueError, TypeError):
        return None
    k = len(names)

    def var(name, value):
        g = np.zeros(k)
        if name in names:
            g[names.index(name)] = 1.0
        return _Dual(value, g)

    mo = scene.motion
    X1, T, beta = var("amplitude", mo.amplitude), var("duration", mo.duration), var("beta", mo.beta)
    a_h = 2.0 * X1 / (beta * T * T)
    a_l = 2.0 * X1 / ((beta - 1.0) * T * T)
    t1, t2, t3 = beta * T, (2.0 - beta) * T, 2.0 * T
    cap = var("mu", scene.grasp.mu) * scene.grasp.fingers * var("grip_force", float(scene.grasp.grip_force))
    if scene.dof == "translation":
        e = world_dir(scene, scene.slide_axis)
        g_e, kk = float(np.dot(scene.gravity, e)), float(np.dot(mo.axis, e))
        drive = [g_e - a_h * kk, g_e - a_l * kk, g_e - a_h * kk, g_e + 0.0 * a_h]
        c = cap / var("mass", scene.body.mass)
    else:
        kk = float(np.dot(mo.axis, np.array(scene.gripper_rotation)[:, 2]))
        drive = [-a_h * kk, -a_l * kk, -a_h * kk, 0.0 * a_h]
        c = cap * var("e_r", scene.grasp.patch.e_r) / float(np.asarray(scene.body.inertia)[2, 2])
    zero = _Dual(0.0, np.zeros(k))
    inf = _Dual(math.inf, np.zeros(k))
    phases = [(zero, t1, drive[0]), (t1, t2, drive[1]), (t2, t3, drive[2]), (t3, inf, drive[3])]
    events, margin = _dual_events(phases, c, k)
    ev = [(t, kind) for t, kind in events if t.v <= t_end]
    nan = np.full(k, math.nan)
    slips = [t for t, kind in ev if kind == "slip"]
    donset = slips[0].g if slips else nan
    if not ev:
        dstop = nan
    elif ev[-1][1] == "stick":
        dstop = ev[-1][0].g
    else:
        dstop = np.full(k, math.nan)   # still moving at t_end
    return donset, dstop, margin


def _richardson(D):
    """Second-order central differences D at steps h, h/2, ...: the fourth-order
    extrapolation with the smallest difference to its neighbour, and that
    difference as its error estimate."""
    R = (4 * D[1:] - D[:-1]) / 3
    if len(R) >= 2:
        e = np.abs(np.diff(R))
        k = int(np.nanargmin(e)) if np.any(np.isfinite(e)) else 0
        return float(R[k + 1]), float(e[k])
    return float(R[0]), float(abs(R[0] - D[1]))


def event_sensitivity(scene: Scene, params: Sequence[str], t_end: float, *, method: str = "auto",
                      rtol: float = 1e-10, atol: float = 1e-12, eps: float = 1e-4, rel_step: float = 1e-4,
                      levels: int = 4, n_grid: int = 1024, exact_if_possible: bool = True) -> EventSensitivity:
    """d onset / dp and d stop / dp of :func:`event_times` for each named parameter.

    Central differences of the bisected event times at steps h, h/2, ...,
    h/2^(levels-1) (h = rel_step |p|, kept inside the parameter's range),
    Richardson extrapolation, the error from the ladder (as
    :func:`sensitivity`). The times are bisected to about 1e-13 s, so the
    differences carry an error of about 1e-13 / h; an event that appears or
    vanishes inside the step shows as a large error.

    Exact where the solution is piecewise analytic: for 1-DoF scenes of the
    closed form (an Eq. 7 motion, no stops, the pivot at the centre of mass,
    a constant grip; ``exdex.paper.closed_form``) and parameters among mu,
    grip_force, mass, e_r, amplitude, duration and beta, the event times are
    phase switches (beta T, (2 - beta) T, 2 T) or roots t = -v / a of the
    phase's linear speed, and their derivatives are carried through that
    algorithm by forward-mode differentiation (``exact`` True, errors 0;
    inf at a stick/slip threshold, relative margin below 1e-6, where a slip
    can appear or vanish and the derivative is one-sided);
    ``exact_if_possible=False`` forces the differences. The event times
    themselves are always the bisected ones of :func:`event_times`.
    """
    names = _scene_params(scene, params)
    rel_step = _real(rel_step, "rel_step", low=0.0, high=0.5, low_open=True)
    if isinstance(levels, bool) or not isinstance(levels, (int, np.integer)) or not 2 <= levels <= 20:
        raise ValueError(f"levels must be an int in [2, 20], got {levels!r}")
    kw: Dict[str, Any] = dict(method=method, rtol=rtol, atol=atol, eps=eps, n_grid=n_grid)
    nominal = event_times(scene, t_end, **kw)
    exact = _exact_event_derivatives(scene, list(names), float(t_end)) if exact_if_possible else None
    if exact is not None:
        # at a stick/slip threshold (relative margin below 1e-6) a slip can
        # appear or vanish with the parameter: the derivative is one-sided,
        # which the error states as inf
        errs = np.zeros(len(names)) if exact[2] > 1e-6 else np.full(len(names), math.inf)
        return EventSensitivity(params=names, values={n: _value_of(scene, n) for n in names}, times=nominal,
                                donset=np.asarray(exact[0], dtype=float), dstop=np.asarray(exact[1], dtype=float),
                                onset_error=errs, stop_error=errs.copy(), exact=True)
    don: List[float] = []
    dst: List[float] = []
    eon: List[float] = []
    est: List[float] = []
    vals: Dict[str, float] = {}
    for name in names:
        p0 = _value_of(scene, name)
        vals[name] = p0
        hs = _fd_steps(scene, name, p0, rel_step, levels)
        Don, Dst = np.empty(levels), np.empty(levels)
        for k, hk in enumerate(hs):
            ep = event_times(_replace_params(scene, {name: p0 + hk}), t_end, **kw)
            em = event_times(_replace_params(scene, {name: p0 - hk}), t_end, **kw)
            Don[k] = (ep.onset - em.onset) / (2 * hk)
            Dst[k] = (ep.stop - em.stop) / (2 * hk) if math.isfinite(ep.stop) and math.isfinite(em.stop) \
                else math.nan
        for D, out, err in ((Don, don, eon), (Dst, dst, est)):
            if np.all(np.isfinite(D)):
                d, e = _richardson(D)
            else:
                d, e = math.nan, math.nan
            out.append(d)
            err.append(e)
    return EventSensitivity(params=names, values=vals, times=nominal, donset=np.array(don), dstop=np.array(dst),
                            onset_error=np.array(eon), stop_error=np.array(est))


# ---------------------------------------------------------- identification

@dataclass(frozen=True, eq=False)
class Identification:
    """A fit of scene parameters to an observed trajectory.

    scene : the base scene with the fitted values.
    values, stderr : {name: value}, {name: standard error} (inf for a
        parameter the data cannot identify).
    interval : {name: (low, high)} 95 % intervals (value -+ 1.96 stderr).
    unidentifiable : tuple of (combination, singular value) pairs: unit
        vectors over ``params`` (in the scaled parameters p / |p0|) that the
        data do not constrain.
    residual_rms : RMS of the residuals at the fit [units of the data];
        sigma : the noise level used (given, or estimated from the residuals).
    cost, nfev, success, message : from the least-squares solver.
    reduction_fails_at : for a translation or rotation scene, where the
        fitted scene's reduction fails over the observed times
        (:attr:`exdex.Result.certificate`; flagged with an
        :class:`exdex.ReductionWarning`: the data past it cannot be a 1-DoF
        motion), or None when it holds.
    """

    scene: Scene
    params: Tuple[str, ...]
    values: Dict[str, float]
    stderr: Dict[str, float]
    interval: Dict[str, Tuple[float, float]]
    unidentifiable: Tuple[Tuple[Dict[str, float], float], ...]
    residual_rms: float
    sigma: float
    cost: float
    nfev: int
    success: bool
    message: str
    reduction_fails_at: Optional[float] = None

    @property
    def identifiable(self) -> bool:
        """True when the data fix every fitted parameter."""
        return not self.unidentifiable

    def report(self) -> str:
        """A plain-text table of the fit, its intervals and what it cannot identify."""
        lines = [f"fit of {', '.join(self.params)} ({'converged' if self.success else 'NOT converged'}: "
                 f"{self.message}); residual RMS {self.residual_rms:.3g}, sigma {self.sigma:.3g}"]
        for p in self.params:
            lo, hi = self.interval[p]
            lines.append(f"  {p:12s} {self.values[p]:.6g} +- {self.stderr[p]:.2g}  (95 %: [{lo:.6g}, {hi:.6g}])")
        for comb, s in self.unidentifiable:
            c = " + ".join(f"{w:+.3f} {p}" for p, w in comb.items() if abs(w) > 1e-3)
            lines.append(f"  not identifiable from these data: the combination {c} (singular value {s:.1e})")
        if self.reduction_fails_at is not None:
            lines.append(f"  the fitted {self.scene.dof} model's reduction fails at t = {self.reduction_fails_at:.6g} s: "
                         f"past it the object cannot move as the 1-DoF model says (fit dof='planar')")
        return "\n".join(lines)

    def __repr__(self):
        return self.report()


def _predict(scene, names, theta, times, dt, t_end, opts):
    vary: Dict[str, Any] = {n: np.atleast_1d(theta[:, i]) for i, n in enumerate(names)}
    with warnings.catch_warnings():
        # the fit's trial points: the fitted scene's reduction is flagged once (reduction_fails_at)
        warnings.simplefilter("ignore", ReductionWarning)
        b = simulate_batch(scene, t_end, dt, **opts, **vary)
    # b.q: (B, n, ndof) on the grid; interpolate to the observation times
    grid = b.t
    out = np.empty((b.q.shape[0], len(times), b.q.shape[2]))
    for k in range(b.q.shape[2]):
        for j in range(b.q.shape[0]):
            out[j, :, k] = np.interp(times, grid, b.q[j, :, k])
    return out


def identify(scene: Scene, times: ArrayLike, observed: ArrayLike, params: Mapping[str, Union[float, Tuple[float, float]]], *,
             sigma: Optional[float] = None, method: str = "auto", rtol: float = 1e-10, atol: float = 1e-12,
             eps: float = 1e-4, dt: Optional[float] = None, rel_step: float = 1e-4,
             max_nfev: int = 100) -> Identification:
    """Fit scene parameters to an observed relative trajectory.

    Parameters
    ----------
    scene : exdex.Scene
        The experiment's scene, with the initial guesses of the fitted parameters.
    times : (n,) array
        Observation times [s], increasing, within [0, t_end].
    observed : (n,) or (n, ndof) array
        The object's free coordinates relative to the gripper at those times
        (translation: s [m]; rotation: theta [rad]; planar: x, y, theta).
    params : dict
        ``{name: (low, high)}`` bounds of each fitted parameter (the scene's
        value is the start), or ``{name: None}`` for the parameter's own range.
    sigma : float, optional
        Standard deviation of the observation noise (else estimated from
        the residuals with n - p degrees of freedom).
    dt : float, optional
        Simulation output step; the model is interpolated linearly to the
        observation times (default: the smallest observation spacing / 8, or
        the observation step itself when the times are a grid i dt from 0).

    Needs SciPy (the ``design`` extra: ``pip install 'exdex[design]'``).
    """
    from exdex._optional import require

    least_squares = require("scipy.optimize", "exdex.identify").least_squares
    if not isinstance(scene, Scene):
        raise TypeError(f"scene must be an exdex.Scene, got {type(scene).__name__}")
    t = np.asarray(times, dtype=float)
    if t.ndim != 1 or t.size < 2 or not np.all(np.isfinite(t)) or np.any(np.diff(t) <= 0) or t[0] < 0:
        raise ValueError("times must be a 1-D array of at least 2 increasing, finite times >= 0")
    y = np.asarray(observed, dtype=float)
    if y.ndim == 1:
        y = y[:, None]
    if y.shape != (t.size, scene.ndof):
        raise ValueError(f"observed must have shape ({t.size},) or ({t.size}, {scene.ndof}) "
                         f"(times x free coordinates), got {np.shape(observed)}")
    if not np.all(np.isfinite(y)):
        raise ValueError("observed must be finite")
    if not isinstance(params, Mapping) or not params:
        raise TypeError("params must be a dict {name: (low, high) or None}")
    names = tuple(_param_name(p, scene) for p in params)
    if len(set(names)) != len(names):
        raise ValueError("params names a parameter twice")
    x0 = np.array([_value_of(scene, n) for n in names])
    lows: List[float] = []
    highs: List[float] = []
    for n, raw in zip(names, params):
        b: Any = params[raw]
        P = PARAMETERS[n]
        if b is None:
            if n == "mu_static" and "mu" not in names:   # the static coefficient stays >= mu
                lows.append(max(P.low or 0.0, scene.grasp.mu))
            else:
                lows.append(-np.inf if P.low is None else P.low)
            highs.append(np.inf if P.high is None else P.high)
        else:
            try:
                a, c = b
            except (TypeError, ValueError):
                raise TypeError(f"params[{raw!r}] must be (low, high) or None, got {b!r}") from None
            lows.append(_real(a, f"params[{raw!r}][0]"))
            highs.append(_real(c, f"params[{raw!r}][1]"))
    lo, hi = np.array(lows), np.array(highs)
    if np.any(~(lo < hi)) or np.any(x0 < lo) or np.any(x0 > hi):
        raise ValueError("each parameter's start (the scene's value) must lie in its bounds (low < high)")
    # open ends of the parameters' own ranges: keep the solver strictly inside
    lo_in, hi_in = lo.copy(), hi.copy()
    fl, fh = np.isfinite(lo), np.isfinite(hi)
    lo_in[fl] = lo[fl] + 1e-12 * np.maximum(np.abs(lo[fl]), 1.0)
    hi_in[fh] = hi[fh] - 1e-12 * np.maximum(np.abs(hi[fh]), 1.0)
    x0 = np.clip(x0, lo_in, hi_in)
    t_end = float(t[-1])
    if dt is None:
        steps = t / (t[1] - t[0])
        on_grid = t[0] == 0.0 and np.allclose(steps, np.round(steps), rtol=0, atol=1e-9)
        dt = float(t[1] - t[0]) if on_grid else float(np.min(np.diff(t))) / 8
    dt = _real(dt, "dt", low=0.0, low_open=True, high=t_end)
    method = _batch_method(scene, method, names)
    opts: Dict[str, Any] = dict(method=method, rtol=rtol, atol=atol, eps=eps, record="all")
    scale = np.where(x0 != 0.0, np.abs(x0), 1.0)

    def residual(z):
        th = (z * scale)[None, :]
        return (_predict(scene, names, th, t, dt, t_end, opts)[0] - y).ravel()

    def jac(z):
        th0 = z * scale
        h = rel_step * scale
        # central where both sides are inside the bounds, else one-sided
        plus = np.minimum(th0 + h, hi_in)
        minus = np.maximum(th0 - h, lo_in)
        P = np.repeat(th0[None, :], 2 * len(names), axis=0)
        for i in range(len(names)):
            P[2 * i, i] = plus[i]
            P[2 * i + 1, i] = minus[i]
        Y = _predict(scene, names, P, t, dt, t_end, opts)
        J = np.empty((y.size, len(names)))
        for i in range(len(names)):
            J[:, i] = (Y[2 * i] - Y[2 * i + 1]).ravel() / ((plus[i] - minus[i]) / scale[i])
        return J

    sol = least_squares(residual, x0 / scale, jac=jac, bounds=(lo_in / scale, hi_in / scale), x_scale=1.0,
                        max_nfev=max_nfev, method="trf")
    theta = sol.x * scale
    r = sol.fun
    m, p = r.size, len(names)
    J = jac(sol.x)
    U, S, Vt = np.linalg.svd(J, full_matrices=False)
    if sigma is None:
        sigma_used = float(np.sqrt(np.sum(r ** 2) / max(m - p, 1)))
    else:
        sigma_used = _real(sigma, "sigma", low=0.0, low_open=True)
    smax = S.max() if S.size else 0.0
    weak = S <= 1e-8 * smax if smax > 0 else np.ones_like(S, dtype=bool)
    unident = tuple(({n: float(w) for n, w in zip(names, Vt[k])}, float(S[k])) for k in np.flatnonzero(weak))
    cov = np.full((p, p), np.inf)
    if not weak.any():
        inv = (Vt.T / S ** 2) @ Vt
        cov = sigma_used ** 2 * inv
    se = np.sqrt(np.diag(cov)) * scale
    values = {n: float(v) for n, v in zip(names, theta)}
    stderr = {n: float(s) for n, s in zip(names, se)}
    if weak.any():
        # a parameter that takes part in an unconstrained combination is not fixed by the data
        for k in np.flatnonzero(weak):
            for i, n in enumerate(names):
                if abs(Vt[k, i]) > 1e-3:
                    stderr[n] = math.inf
        for i, n in enumerate(names):
            if math.isinf(stderr[n]):
                continue
            # the rest: from the constrained subspace
            keep = ~weak
            inv = (Vt[keep].T / S[keep] ** 2) @ Vt[keep]
            stderr[n] = float(sigma_used * math.sqrt(max(inv[i, i], 0.0)) * scale[i])
    interval = {n: (values[n] - 1.96 * stderr[n], values[n] + 1.96 * stderr[n]) for n in names}
    fitted = _replace_params(scene, values)
    fails = reduction_fails_at(fitted, t_end, dt, **{k: v for k, v in opts.items()
                                                    if k in ("method", "rtol", "atol", "eps")})
    return Identification(scene=fitted, params=names, values=values, stderr=stderr, interval=interval,
                          unidentifiable=unident, residual_rms=float(np.sqrt(np.mean(r ** 2))),
                          sigma=sigma_used, cost=float(sol.cost), nfev=int(sol.nfev), success=bool(sol.success),
                          message=str(sol.message), reduction_fails_at=fails)

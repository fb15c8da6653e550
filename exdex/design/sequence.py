"""Planar in-hand targets by short sequences of motion primitives.

A planar pose target ``{"x": ..., "y": ..., "rotation": ...}`` (the object's
displacement in the gripper frame [m] and its turn relative to the gripper
[rad], any subset) is rarely reachable by one gripper motion: each motion
moves the pose along its own curve. :func:`solve` chains primitives, each a
gripper motion that starts and ends at rest in the same pose (an Eq. 7 round
trip), so the object's pose at the end of one step is the start of the next
(``Scene.q0``) and nothing else carries over:

* ``slide_x``, ``slide_y``: inertial slides, the gripper translates along the
  plate's x or y axis (``AsymmetricProfile``, amplitude varied);
* ``pivot``: the gripper turns about the plate normal through its origin
  (``AsymmetricProfile(rotation=True)``, angle varied);
* ``push_k``: for each stop k of the scene, the gripper moves slowly
  (``push_duration``) towards the stop along its normal and back (amplitude
  varied): the object is pushed against the stop, and where it ends is set by
  the stop, not by friction, as long as the slow return does not make it slip.

The search (what it covers):

1. every primitive's one-step outcome is scanned in one batch over its
   parameter range from the start pose;
2. every sequence of length 1 to ``max_length`` (distinct primitives) is
   screened by the additive model (the sum of its steps' scanned outcomes,
   exact when a step's outcome does not depend on the pose it starts from:
   no stops and small turns), over the product of the scans linearly
   interpolated onto finer grids (about 10^5 combinations per sequence);
3. the screened best sequences (``n_polish``: first the shortest of those
   whose screened error is within what their scan grid can miss plus three
   tolerances, then the others by screened error) are solved exactly:
   bounded least squares (SciPy's trust-region reflective ``least_squares``)
   on the outcome of the sequence simulated step by step with the event
   method, residuals scaled by the tolerances, from the screen's best grid
   point (for two steps, if that fails, in the other order too), until every
   residual is within a quarter of its tolerance (a sequence within 0.9 of
   every tolerance counts as solved); once a
   sequence meets the target only plausible ones as short or shorter are
   still solved;
4. among those that meet every tolerance the shortest, then the least cost
   (the sum of the steps' peak gripper accelerations) is returned; otherwise :class:`exdex.plan.UnreachableTargetError`
   with the closest sequence found.

Not covered: repeated primitives in one sequence, sequences longer than
``max_length``, orders other than the screen's for three or more steps (the
additive screen cannot tell orders apart), durations and Eq. 7's beta as
unknowns (fixed per primitive), grip changes between steps, and targets that
need the object to leave the pad (a sequence whose re-simulated steps leave
the grasp -- the pads lose the object, or it slides beyond the patch's pad or
off the pad centre -- is not accepted). The search is local: a
reachable pose can be missed, and the error then names the closest sequence
solved. Units are SI.
"""
from __future__ import annotations

import dataclasses
import itertools
import math
import warnings
from dataclasses import dataclass
from typing import Any, Callable, Dict, List, Mapping, Optional, Sequence, Tuple

import numpy as np

from exdex import _core, diagnostics
from exdex.design._targets import UnreachableTargetError, check_quantity as _check_quantity, motion_peaks
from exdex._validate import real as _real, user_stacklevel
from exdex.scene import AsymmetricProfile, Scene
from exdex.simulate import SolverError, simulate

__all__ = ["Primitive", "SequencePlan", "primitives", "solve", "band", "POSE_QUANTITIES"]

#: the quantities of a planar pose target, with their units
POSE_QUANTITIES = {"x": "m", "y": "m", "rotation": "rad"}
_INDEX = {"x": 0, "y": 1, "rotation": 2}


@dataclass(frozen=True)
class Primitive:
    """One gripper motion with one free parameter.

    name : its name in a sequence; kind : "slide", "pivot" or "push".
    bounds : (low, high) of the parameter (m for slides and pushes, rad for
        the pivot); make : parameter -> the gripper motion (a round trip that
        ends at rest where it started).
    """

    name: str
    kind: str
    bounds: Tuple[float, float]
    make: Callable[[float], Any]

    def motion(self, value: float) -> Any:
        """The gripper motion for a parameter value (checked against bounds)."""
        lo, hi = self.bounds
        v = _real(value, f"{self.name} parameter")
        if not lo <= v <= hi:
            raise ValueError(f"{self.name} parameter must lie in [{lo:g}, {hi:g}], got {v:g}")
        return self.make(v)


def primitives(scene: Scene, *, duration: float = 0.15, beta: float = 0.3, max_stroke: float = 0.05,
               max_angle: float = 1.0, push_duration: float = 0.5) -> Dict[str, Primitive]:
    """The primitives a planar scene offers (see the module docstring).

    duration, beta : Eq. 7's T [s] and beta of the slides and the pivot.
    push_duration : Eq. 7's T [s] of the pushes (beta 0.5: slow and
        symmetric, so that the way back does not make the object slip).
    max_stroke : the slides' and pushes' largest amplitude [m]; max_angle :
        the pivot's largest angle [rad] (the robot's stroke and angle limits).
    """
    if not isinstance(scene, Scene):
        raise TypeError(f"scene must be an exdex.Scene, got {type(scene).__name__}")
    if scene.dof != "planar":
        raise ValueError(f"sequences of primitives plan planar poses: the scene's dof must be 'planar', "
                         f"got {scene.dof!r}")
    T = _real(duration, "duration", low=0.0, low_open=True)
    b = _real(beta, "beta", low=0.0, low_open=True, high=1.0)
    if b >= 1.0:
        raise ValueError(f"beta must lie in (0, 1), got {b:g}")
    s = _real(max_stroke, "max_stroke", low=0.0, low_open=True)
    a = _real(max_angle, "max_angle", low=0.0, low_open=True)
    Tp = _real(push_duration, "push_duration", low=0.0, low_open=True)
    R = np.asarray(scene.gripper_rotation, dtype=float)
    ex, ey, ez = (tuple(float(c) for c in R[:, k]) for k in range(3))
    out: Dict[str, Primitive] = {
        "slide_x": Primitive("slide_x", "slide", (-s, s), lambda v: AsymmetricProfile(v, T, b, axis=ex)),
        "slide_y": Primitive("slide_y", "slide", (-s, s), lambda v: AsymmetricProfile(v, T, b, axis=ey)),
        "pivot": Primitive("pivot", "pivot", (-a, a),
                           lambda v: AsymmetricProfile(v, T, b, axis=ez, rotation=True,
                                                       center=tuple(scene.gripper_position))),
    }
    for k, st in enumerate(scene.stops):
        n = np.asarray(st.normal, dtype=float)
        # the stop's normal points out of the stop, into the object's side:
        # the gripper pushes the object towards the stop along -n
        d = tuple(float(c) for c in -n / np.linalg.norm(n))
        out[f"push_{k}"] = Primitive(f"push_{k}", "push", (0.0, s), _push(d, Tp))
    return out


def _push(axis, T):
    def make(v: float) -> Any:
        return AsymmetricProfile(v, T, 0.5, axis=axis)
    return make


@dataclass(frozen=True, eq=False)
class SequencePlan:
    """A solution of :func:`solve`.

    steps : ((primitive name, parameter value), ...) in order.
    scenes : the scene of each step (its motion, and q0 the pose the previous
        step left); final : the pose (x, y, theta) after the last step.
    targets, achieved, residuals : {quantity: value} (achieved by the step by
        step re-simulation with the event method at rtol 1e-12).
    tol : {quantity: tolerance}; cost : the sum of the steps' peak gripper
        accelerations (m/s^2 for slides and pushes, rad/s^2 for pivots).
    tried : ((sequence, screened scaled error, solved scaled error or NaN), ...)
        for every sequence screened, best screened first; the scaled error is
        max |residual| / tol.
    settle : the rest after each step's motion [s].
    """

    steps: Tuple[Tuple[str, float], ...]
    scenes: Tuple[Scene, ...]
    final: Tuple[float, float, float]
    targets: Dict[str, float]
    achieved: Dict[str, float]
    residuals: Dict[str, float]
    tol: Dict[str, float]
    cost: float
    tried: Tuple[Tuple[Tuple[str, ...], float, float], ...]
    settle: float = 0.3

    def gripper_poses(self, rate: float = 100.0) -> Tuple[np.ndarray, np.ndarray]:
        """The whole sequence's gripper motion as poses at ``rate`` [Hz], what a
        robot controller consumes: ``(times, poses)``, poses (n, 7) rows x y
        z qw qx qy qz of frame B in the world (m, unit quaternion); each step
        runs its motion and then rests ``settle`` s, and starts where the
        previous one ended (every primitive is a round trip)."""
        from exdex._rotations import quat_from_matrix as _quat_from_matrix
        rate = _real(rate, "rate", low=0.0, low_open=True)
        ts, ps = [], []
        t0 = 0.0
        for k, sc in enumerate(self.scenes):
            span = sc.end_time + self.settle
            n = max(int(math.floor(span * rate + 1e-9)), 1)
            t = np.arange(n + 1) / rate
            t[-1] = min(t[-1], span)
            if t[-1] < span:
                t = np.append(t, span)
            if k:
                t = t[1:]   # the previous step's last sample is this one's first
            kin = sc.motion.evaluate(t, sc.gripper_rotation, sc.gripper_position)
            q = np.array([_quat_from_matrix(R) for R in kin["R"]])
            ts.append(t0 + t)
            ps.append(np.hstack([kin["p"], q]))
            t0 += span
        return np.concatenate(ts), np.vstack(ps)

    @property
    def meets_target(self) -> bool:
        return all(abs(self.residuals[q]) <= self.tol[q] for q in self.targets)

    def step_units(self) -> Tuple[str, ...]:
        """The unit of each step's parameter: rad for a pivot's angle, m for
        a slide's or a push's amplitude."""
        return tuple("rad" if getattr(sc.motion, "rotation", False) else "m" for sc in self.scenes)

    def __repr__(self) -> str:
        st = " -> ".join(f"{n}({v:.6g} {u})" for (n, v), u in zip(self.steps, self.step_units()))
        r = ", ".join(f"{q} {self.achieved[q]:.6g} {POSE_QUANTITIES[q]} (target {self.targets[q]:.6g} "
                      f"{POSE_QUANTITIES[q]})" for q in self.targets)
        return f"SequencePlan({st}: {r})"


def _dt(scene, t_end):
    """Output step of a primitive's run: the whole run for scenes without
    stops (the event method's answer does not depend on it), at most 10 ms
    with stops (the output interval bounds the event method's step, so that
    a short approach to a stop is not stepped over)."""
    return t_end if not scene.stops else min(t_end, 0.01)


def _end_time(scene, motion):
    """The end time of ``scene`` with ``motion`` in place of its own
    (:attr:`exdex.Scene.end_time`: the later of the motion's end and the grip
    schedule's last time) [s]."""
    sched = scene.grasp.schedule
    return max(float(motion.end_time), float(sched.times[-1]) if sched is not None else 0.0, 0.0)


def _step_scene(scene, prim, value, q):
    return dataclasses.replace(scene, motion=prim.make(value), q0=tuple(float(c) for c in q))


def _run_sequence(scene, prims, values, settle, rtol, atol, with_scenes=False):
    """The pose after the steps (x, y, theta) and, if asked, each step's scene
    and the warnings of their re-simulation by :func:`exdex.simulate`; None
    when a step fails, leaves the grasp or leaves the object moving. Without
    scenes each step is one call of the compiled core on the step's spec."""
    q = np.array(scene.q0, dtype=float)
    scenes = []
    caught: List[Any] = []
    specs: Dict[str, Dict[str, Any]] = {}
    for prim, v in zip(prims, values):
        if with_scenes:
            sc = _step_scene(scene, prim, float(v), q)
            t_end = sc.end_time + settle
            try:
                with warnings.catch_warnings(record=True) as rec:
                    warnings.simplefilter("always")
                    r = simulate(sc, t_end, _dt(sc, t_end), method="event", rtol=rtol, atol=atol)
            except SolverError:
                return None
            caught.extend(rec)
            if r.certificate is not None and not r.certificate["holds"]:
                return None   # a step whose 1-DoF reduction fails is no candidate
            if _leaves_grasp(r):
                return None   # nor one that leaves the grasp
            stick, q = bool(r.stick[-1]), np.array(r.q[-1], dtype=float)
            scenes.append(sc)
        else:
            if prim.name not in specs:
                specs[prim.name] = _step_scene(scene, prim, float(v), q).to_spec(method="event", rtol=rtol,
                                                                                 atol=atol)
            spec = dict(specs[prim.name])
            mo = prim.make(float(v))
            spec["motion_amplitude"] = float(mo.amplitude)
            spec["q0"] = np.array(q, dtype=float)
            t_end = _end_time(scene, mo) + settle
            try:
                out = _core.simulate(spec, t_end, _dt(scene, t_end))
            except (SolverError, ValueError):
                return None
            cert = out.get("certificate")
            if cert is not None and not cert["holds"]:
                return None   # a step whose 1-DoF reduction fails is no candidate
            stick, q = bool(out["stick"][-1]), np.array(out["q"][-1], dtype=float)
        if not stick:
            return None
    return (q, scenes, caught) if with_scenes else q


def _leaves_grasp(result):
    """True where a step's run leaves the grasp: the pads lost the object, or
    the object slid beyond the patch's pad or off the pad centre (the
    PhysicsWarning kinds "grasp", "pad" and "outline")."""
    kinds = {w.kind for w in diagnostics.contact_findings(result.scene, result.t, result.q)}
    kinds |= {w.kind for w in diagnostics.stats_findings(result.stats)}
    return bool(kinds & {"grasp", "pad", "outline"})


def _scan(scene, prim, n, settle, rtol, atol):
    """One-step outcomes (n, 3) of a primitive over its range from the start pose (NaN: failed)."""
    from exdex.batch import simulate_batch
    lo, hi = prim.bounds
    xs = np.linspace(lo, hi, n)
    out = np.full((n, 3), np.nan)
    q0 = np.array(scene.q0, dtype=float)
    # one batch over the amplitude when the motion's amplitude is the parameter
    base = _step_scene(scene, prim, xs[-1] if xs[-1] != 0 else hi, q0)
    t_end = base.end_time + settle
    try:
        b = simulate_batch(base, t_end, _dt(base, t_end), record="final", method="event", rtol=rtol, atol=atol,
                           warn=False, amplitude=xs)
        ok = np.asarray(b.stick, dtype=bool).reshape(-1)
        out[ok] = np.asarray(b.final_displacement).reshape(n, 3)[ok]
    except SolverError:
        for i, x in enumerate(xs):
            q = _run_sequence(scene, [prim], [x], settle, rtol, atol)
            if q is not None:
                out[i] = q - q0
    return xs, out


class _Done(Exception):
    """Raised inside the least-squares residual once the target is met with margin."""

    def __init__(self, z, r):
        super().__init__("done")
        self.z, self.r = z, r


def _targets(target):
    if not isinstance(target, Mapping) or not target:
        raise TypeError("target must be a dict of planar pose quantities, e.g. {'x': 0.005, 'y': -0.01, "
                        "'rotation': 0.2}")
    out = {}
    for q, v in target.items():
        if q not in POSE_QUANTITIES:
            raise ValueError(f"target quantity must be one of {list(POSE_QUANTITIES)}, got {q!r}")
        out[q] = _real(v, f"target[{q!r}]")
    return out


def solve(scene: Scene, target: Mapping[str, float], *, prims: Optional[Mapping[str, Primitive]] = None,
          max_length: int = 3, tol: Tuple[float, float] = (1e-4, math.radians(0.1)), n_scan: int = 41,
          n_polish: int = 3, settle: float = 0.3, rtol: float = 1e-9, atol: float = 1e-11,
          verify_rtol: float = 1e-12, max_nfev: int = 60) -> SequencePlan:
    """Reach a planar pose target by a sequence of primitives (see the module docstring).

    Parameters
    ----------
    scene : exdex.Scene
        A planar scene; its motion is ignored (the primitives replace it),
        its q0 is the start pose.
    target : dict
        Any of ``x``, ``y`` [m] (displacement of the object in the gripper
        frame) and ``rotation`` [rad], relative to the start pose.
    prims : dict, optional
        ``{name: Primitive}`` to search over (default :func:`primitives` of the scene).
    max_length : int
        Longest sequence tried (1 .. 4).
    tol : (float, float)
        Tolerances on x, y [m] and on the rotation [rad] (default 0.1 mm, 0.1 deg).
    n_scan : int
        Scan points per primitive for the screen (>= 5).
    n_polish : int
        Screened sequences solved exactly (>= 1).
    settle : float
        Time after each step's motion for the object to come to rest [s].
    rtol, atol : the event method's tolerances while solving; verify_rtol :
        the rtol of the final step-by-step re-simulation that reports the plan.
    max_nfev : int
        Residual evaluations per solved sequence (each simulates its steps).

    Returns
    -------
    SequencePlan

    Raises
    ------
    UnreachableTargetError
        No sequence met the tolerances; the message names the closest one.
    ValueError, TypeError
        For bad targets, primitives or options, naming them.
    """
    from exdex._optional import require

    least_squares = require("scipy.optimize", "exdex.sequence.solve (exdex plan --pose)").least_squares
    if not isinstance(scene, Scene):
        raise TypeError(f"scene must be an exdex.Scene, got {type(scene).__name__}")
    goals = _targets(target)
    for q in goals:
        _check_quantity(q, scene)
    if prims is None:
        prims = primitives(scene)
    if not isinstance(prims, Mapping) or not prims or not all(isinstance(p, Primitive) for p in prims.values()):
        raise TypeError("prims must be a non-empty dict {name: exdex.sequence.Primitive}")
    if isinstance(max_length, bool) or not isinstance(max_length, int) or not 1 <= max_length <= 4:
        raise ValueError(f"max_length must be an int in [1, 4], got {max_length!r}")
    try:
        tol_xy, tol_th = (float(tol[0]), float(tol[1]))
    except (TypeError, ValueError, IndexError):
        raise TypeError(f"tol must be a pair (metres, radians), got {tol!r}") from None
    tol_xy = _real(tol_xy, "tol[0]", low=0.0, low_open=True)
    tol_th = _real(tol_th, "tol[1]", low=0.0, low_open=True)
    if isinstance(n_scan, bool) or not isinstance(n_scan, int) or n_scan < 5:
        raise ValueError(f"n_scan must be an int >= 5, got {n_scan!r}")
    if isinstance(n_polish, bool) or not isinstance(n_polish, int) or n_polish < 1:
        raise ValueError(f"n_polish must be an int >= 1, got {n_polish!r}")
    settle = _real(settle, "settle", low=0.0, low_open=True)
    if isinstance(max_nfev, bool) or not isinstance(max_nfev, int) or max_nfev < 1:
        raise ValueError(f"max_nfev must be an int >= 1, got {max_nfev!r}")
    tols = {q: (tol_th if q == "rotation" else tol_xy) for q in goals}
    idx = np.array([_INDEX[q] for q in goals])
    goal = np.array([goals[q] for q in goals])
    scale = np.array([tols[q] for q in goals])

    names = list(prims)
    scans = {n: _scan(scene, prims[n], n_scan, settle, rtol, atol) for n in names}

    # screen: the additive model over the product of the scan grids, each
    # scan linearly interpolated onto a finer grid (finer for shorter
    # sequences: about 10^5 combinations each)
    screened = []
    for L in range(1, max_length + 1):
        fine = max(n_scan, int(round((2e5) ** (1.0 / L))))
        for seq in itertools.combinations(names, L):
            grids, Ys = [], []
            for n in seq:
                xs, Y = scans[n]
                xf = np.linspace(xs[0], xs[-1], fine)
                grids.append(xf)
                Ys.append(np.stack([np.interp(xf, xs, Y[:, c]) for c in idx], axis=1))
            total = Ys[0]
            for Y in Ys[1:]:
                total = (total[:, None, :] + Y[None, :, :]).reshape(-1, len(idx))
            err = np.max(np.abs(total - goal) / scale, axis=1)
            err = np.where(np.isfinite(err), err, np.inf)
            j = int(np.argmin(err))
            grid_idx = np.unravel_index(j, (fine,) * L)
            x0 = np.array([g[k] for g, k in zip(grids, grid_idx)])
            # what the fine grid can miss: the largest scaled change between
            # its neighbouring points, summed over the sequence's primitives
            res = sum(float(np.nanmax(np.abs(np.diff(Y, axis=0)) / scale, initial=0.0)) for Y in Ys)
            screened.append((float(err[j]), L, seq, x0, float(err[j]) <= res + 3.0))
    # plausible sequences (screened within what their grid can miss, plus
    # three tolerances) shortest first, then the rest by screened error
    screened.sort(key=lambda s: (not s[4], s[1] if s[4] else 0, s[0]))

    q_start = np.array(scene.q0, dtype=float)
    results: Dict[Tuple[str, ...], Tuple[float, Any]] = {}
    found: List[Tuple[int, float, Tuple[str, ...], np.ndarray]] = []
    for err0, L, seq, x0, plausible in screened[:n_polish]:
        if found and not (L <= min(f[0] for f in found) and plausible):
            continue   # a solution exists; only a plausible one as short or shorter could beat it
        # the screen's order first; for two steps also the other order
        orders = [seq] + ([seq[::-1]] if L == 2 else [])
        best_err, best_x = math.inf, None
        for order in orders:
            ps = [prims[n] for n in order]
            lo = np.array([p.bounds[0] for p in ps])
            hi = np.array([p.bounds[1] for p in ps])
            span = hi - lo

            def resid(z, ps=ps, lo=lo, span=span):
                q = _run_sequence(scene, ps, lo + z * span, settle, rtol, atol)
                if q is None:
                    return np.full(len(idx), 1e6)
                r = ((q - q_start)[idx] - goal) / scale
                if np.max(np.abs(r)) <= 0.25:
                    raise _Done(np.array(z, dtype=float), r)   # well within tol: no need to polish further
                return r

            start = np.array([x0[seq.index(n)] for n in order])
            z0 = np.clip((start - lo) / span, 0.0, 1.0)
            try:
                r = least_squares(resid, z0, bounds=(np.zeros(L), np.ones(L)), method="trf", diff_step=1e-6,
                                  xtol=1e-12, ftol=1e-12, gtol=1e-12, max_nfev=max_nfev)
                z, fun = r.x, r.fun
            except _Done as done:
                z, fun = done.z, done.r
            err = float(np.max(np.abs(fun)))
            if err < best_err:
                best_err, best_x = err, (order, lo + z * span)
            if best_err <= 0.9:
                break
        results[seq] = (best_err, best_x)
        if best_err <= 0.9 and best_x is not None:
            order, xs = best_x
            cost = sum(motion_peaks(prims[n].make(float(v)))["acceleration"] for n, v in zip(order, xs))
            found.append((L, cost, order, xs))
    tried = tuple((seq, e0, results[seq][0] if seq in results else math.nan) for e0, _, seq, _, _ in screened)
    if not found:
        best = min(results.items(), key=lambda kv: kv[1][0])
        raise UnreachableTargetError(
            f"no sequence of up to {max_length} of the primitives {names} meets the target {goals} within "
            f"tol ({tol_xy:g} m, {tol_th:g} rad); the closest solved, {' -> '.join(best[0])}, misses by "
            f"{best[1][0]:.3g} tolerances", (math.nan, math.nan))
    found.sort(key=lambda f: (f[0], f[1]))
    # the report is the re-simulation at verify_rtol: the first candidate
    # that still meets every tolerance there
    out = None
    for L, cost, order, xs in found:
        out = _run_sequence(scene, [prims[n] for n in order], xs, settle, verify_rtol, atol * 1e-2,
                            with_scenes=True)
        if out is not None and np.all(np.abs((out[0] - q_start)[idx] - goal) <= scale):
            break
        out = None
    if out is None:
        raise UnreachableTargetError(
            f"the sequences solved for the target {goals} ({', '.join(' -> '.join(f[2]) for f in found)}) miss "
            f"the tolerances when re-simulated at rtol {verify_rtol:g}, or leave the grasp on the way",
            (math.nan, math.nan))
    qf, scenes, caught = out
    for w in caught:   # the accepted re-simulation's warnings (impacts, solver notes), at the caller's line
        warnings.warn(w.message, stacklevel=user_stacklevel())
    # steps that leave the object where it was (a slide below the slip
    # threshold) are dropped: they change nothing
    keep = []
    q_prev = q_start
    for k, sc in enumerate(scenes):
        q_next = np.array(scenes[k + 1].q0 if k + 1 < len(scenes) else qf, dtype=float)
        if np.any(q_next != q_prev):
            keep.append(k)
        q_prev = q_next
    if keep and len(keep) < len(scenes):
        order, xs, scenes = tuple(order[k] for k in keep), [xs[k] for k in keep], [scenes[k] for k in keep]
    d = qf - q_start
    achieved = {q: float(d[_INDEX[q]]) for q in goals}
    return SequencePlan(steps=tuple((n, float(v)) for n, v in zip(order, xs)), scenes=tuple(scenes),
                        final=(float(qf[0]), float(qf[1]), float(qf[2])), targets=dict(goals), achieved=achieved,
                        residuals={q: achieved[q] - goals[q] for q in goals}, tol=tols, cost=float(cost),
                        tried=tried, settle=settle)


def band(plan: SequencePlan, uncertain: Mapping[str, Tuple[float, float]], *, n: int = 9,
         settle: float = 0.3, rtol: float = 1e-10, atol: float = 1e-12) -> Dict[str, Tuple[float, float]]:
    """The sampled band of a sequence plan's pose under uncertain grasp or body parameters.

    ``uncertain`` maps ``mu``, ``mu_static``, ``grip_force``, ``mass`` or ``e_r`` to an
    interval; the plan's steps are re-simulated step by step for ``n``
    equally spaced values per interval (the product grid, ends included).
    Returns ``{quantity: (low, high)}`` over the samples for the plan's
    target quantities; samples whose run fails or leaves the object moving
    are left out with a UserWarning that counts them (NaN if all fail). The
    band is sampled, not exact: a sequence's outcome need not be monotone.
    """
    from exdex._params import replace_params as _replace_params
    if not isinstance(plan, SequencePlan):
        raise TypeError(f"plan must be an exdex.sequence.SequencePlan, got {type(plan).__name__}")
    if not isinstance(uncertain, Mapping) or not uncertain:
        raise TypeError("uncertain must be a dict {name: (low, high)}, e.g. {'mu': (0.4, 0.6)}")
    if isinstance(n, bool) or not isinstance(n, int) or n < 2:
        raise ValueError(f"n must be an int >= 2, got {n!r}")
    axes = {}
    for name, iv in uncertain.items():
        if name not in ("mu", "mu_static", "grip_force", "mass", "e_r"):
            raise ValueError("uncertain parameters of a sequence band are mu, mu_static, grip_force, mass, e_r; "
                             f"got {name!r}")
        try:
            lo, hi = (float(iv[0]), float(iv[1]))
        except (TypeError, ValueError, IndexError):
            raise TypeError(f"uncertain[{name!r}] must be a (low, high) pair, got {iv!r}") from None
        if not (math.isfinite(lo) and math.isfinite(hi) and lo <= hi):
            raise ValueError(f"uncertain[{name!r}] must be (low, high) with low <= high, got {iv!r}")
        axes[name] = np.linspace(lo, hi, n)
    q_start = np.array(plan.scenes[0].q0, dtype=float)
    finals = []
    failed = 0
    for combo in itertools.product(*axes.values()):
        vals = dict(zip(axes, map(float, combo)))
        q: Optional[np.ndarray] = q_start.copy()
        for sc in plan.scenes:
            assert q is not None
            s = _replace_params(dataclasses.replace(sc, q0=tuple(q)), vals)
            t_end = s.end_time + settle
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                try:
                    r = simulate(s, t_end, _dt(s, t_end), method="event", rtol=rtol, atol=atol)
                except SolverError:
                    q = None
                    break
            if not r.stick[-1]:
                q = None
                break
            q = np.array(r.q[-1], dtype=float)
        if q is None:
            failed += 1
        else:
            finals.append(q - q_start)
    if failed:
        warnings.warn(f"{failed} of {failed + len(finals)} samples of the band failed (the event method gave up, "
                      "or the object was still moving after a step); the band covers the others",
                      UserWarning, stacklevel=user_stacklevel())
    F = np.array(finals).reshape(-1, 3)
    lows = {k: float(F[:, _INDEX[k]].min()) if len(F) else math.nan for k in plan.targets}
    highs = {k: float(F[:, _INDEX[k]].max()) if len(F) else math.nan for k in plan.targets}
    return {k: (lows[k], highs[k]) for k in plan.targets}

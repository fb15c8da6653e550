"""Batches and sweeps: many trajectories in one call, on threads or a cluster.

:func:`simulate_batch` runs one scene with parameters varied across a batch
(arrays of grip force, friction coefficient, Eq. 7's beta, T, X1, mass, ...)
in one C call: every model is built with the GIL held, then the trajectories
run on POSIX threads with the GIL released. Each trajectory is exactly the
computation of :func:`exdex.simulate` on the scene made by
``dataclasses.replace``: the results are bit-identical to the serial ones for
any thread count.

:func:`sweep` cuts a parameter grid into chunks and maps them over any
:class:`concurrent.futures.Executor`: a thread pool locally (the default) or a
Dask cluster through ``distributed.Client(...).get_executor()``. Each chunk is
one ``simulate_batch(..., threads=1)`` call, so a thread pool of k workers
keeps k cores busy and a cluster spreads the chunks over its workers. Results
come back in grid order whatever the completion order; a tqdm bar shows the
progress.

    >>> import numpy as np, exdex
    >>> scene = exdex.paper.fig3_scene()
    >>> b = exdex.simulate_batch(scene, t_end=1.5, dt=1e-3, record="final",
    ...                          grip_force=np.linspace(1.2, 1.8, 61))
    >>> b.final_displacement.shape        # (61, 1): slip [m] per grip force
    (61, 1)
    >>> s = exdex.sweep(scene, {"mu": [0.3, 0.5], "beta": np.linspace(0.6, 0.95, 8)},
    ...                 t_end=1.5, dt=1e-3, progress=False)
    >>> s.gridded("final_displacement").shape
    (2, 8, 1)

Units are SI, as everywhere in exdex.
"""
from __future__ import annotations

import concurrent.futures as cf
import dataclasses
import functools
import math
import os
import threading
import warnings
from dataclasses import dataclass, field
from typing import Any, Callable, Dict, Iterable, Iterator, Mapping, Optional, Sequence, Tuple, Union, cast

import numpy as np
from numpy.typing import ArrayLike, NDArray

from exdex import _core, _optional
from exdex._validate import check_times as _check_times, real as _real
from exdex.scene import (METHODS, SOLVERS, AsymmetricProfile, Body, Grasp, GripSchedule, Scene, TrapezoidalProfile,
                         patch_centres_outside)
from exdex import diagnostics
from exdex._params import ALIASES as _ALIASES, PARAMETERS, replace_params as _replace_params, unread as _unread
from exdex._obstacle_hint import reduced_obstacle_hint
from exdex.simulate import FrictionSolver, Method, Result, SolverError, resolve_method

__all__ = ["BatchResult", "simulate_batch", "sweep", "grid_points", "PARAMETERS", "INVALID_KINDS"]


# ------------------------------------------------------------------ result

@dataclass(frozen=True, eq=False)
class BatchResult:
    """Stacked trajectories of a batch (B trajectories, n samples each).

    The batch index runs over the parameter sets in C order of ``shape`` (the
    broadcast shape of the varied arrays); ``params[name][i]`` is the value of
    parameter ``name`` in trajectory i.

    With ``record="all"`` (every sample):

    t : (n,) times [s], shared by all trajectories.
    q, v : (B, n, ndof) free coordinates and their rates (as in
        :class:`exdex.Result`: s [m] / theta [rad], or x, y, theta).
    wrench : (B, n, 3) plate friction (f_x, f_y, m_z) in B at the centre of
        pressure, mean over the step ending at each sample [N, N, N m]
        (row 0: as in :attr:`exdex.Result.wrench`).
    stick : (B, n) True where the step ending there stuck exactly.
    stop_force : (B, n, n_stops) mean normal force of each stop [N].

    With ``record="final"`` the sample axis is dropped: the same arrays hold
    only the last sample (t = t_end): q, v (B, ndof), wrench (B, 3), stick
    (B,), stop_force (B, n_stops). 10^5 trajectories then take a few MB.

    Always:

    final_displacement : (B, ndof) q at t_end minus q at t = 0 [m or rad].
    stats : dict of (B,) arrays per trajectory: steps, stick_steps,
        solver_iterations, stop_iterations, warnings, impacts,
        max_impulse_stop (int64), min_gap [m], max_impulse [N s],
        max_impulse_t, first_warning_t, grasp_lost_t [s] (as in
        :class:`exdex.Result`; NaN and -1 where a single run's stats hold
        None; grasp_lost_t: pads on the fingers lost the object there, the
        samples after it are NaN).
    reduction_valid_until : (B,) the certificate of each translation or
        rotation trajectory (:attr:`exdex.Result.certificate`): until when
        its reduction held [s] (t_end where it held throughout; NaN for
        planar trajectories). :attr:`reduction_holds` says which held.
    reduction_first_bad : (B,) int64 index of the first sample whose check
        fails (n where it held, -1 for planar trajectories).
    params : dict name -> (B,) float64 values of the varied parameters.
    checks, valid : the physics checks per trajectory (kind -> (B,) bool,
        True where it failed) and (B,) True where none of those that decide
        whether a run describes the grasp failed (:attr:`valid`,
        :meth:`reasons`); :meth:`gridded` puts NaN at invalid points.
    shape : batch shape (B = prod(shape)); see :meth:`gridded`.
    scene : the base scene (or the tuple of scenes of a list batch).
    record, method, friction_solver, dt, t_end, threads : what produced it.
    """

    t: np.ndarray
    q: np.ndarray
    v: np.ndarray
    wrench: np.ndarray
    stick: np.ndarray
    stop_force: np.ndarray
    final_displacement: np.ndarray
    stats: Dict[str, np.ndarray]
    params: Dict[str, np.ndarray] = field(default_factory=dict)
    shape: Tuple[int, ...] = ()
    scene: Any = None
    record: str = "all"
    method: str = "implicit"
    friction_solver: str = "scalar"
    dt: float = float("nan")
    t_end: float = float("nan")
    threads: int = 1
    reduction_valid_until: Optional[np.ndarray] = None
    reduction_first_bad: Optional[np.ndarray] = None

    def __len__(self) -> int:
        return len(self.final_displacement)

    @property
    def reduction_holds(self) -> NDArray[np.bool_]:
        """(B,) True where a trajectory's reduction held over the whole run
        (and for planar trajectories, which neglect nothing)."""
        if self.reduction_first_bad is None:
            return np.ones(len(self), dtype=bool)
        bad = np.asarray(self.reduction_first_bad)
        return (bad < 0) | (bad >= len(self.t))

    @functools.cached_property
    def _check_results(self) -> Dict[str, Tuple[NDArray[np.bool_], Callable[[int], Any]]]:
        return _batch_checks(self)

    @property
    def checks(self) -> Dict[str, NDArray[np.bool_]]:
        """The physics checks of every trajectory: kind -> (B,) bool, True
        where that check failed (the kinds of :class:`exdex.PhysicsWarning`
        the batch warns about): ``"impact"`` (an impact on a stop),
        ``"solver"`` (soft solver problems, ``stats["warnings"]``),
        ``"grasp"`` (pads on the fingers lost the object), ``"pad"`` (a
        slide past the pad), ``"outline"`` (the pad centre left the body
        outline), ``"reduction"`` (a 1-DoF run's certificate failed). Only
        the checks that apply to the batch's scenes are present; with
        ``record="final"`` the pad and outline checks see the final pose."""
        return {k: m for k, (m, _) in self._check_results.items()}

    @property
    def valid(self) -> NDArray[np.bool_]:
        """(B,) True where the trajectory passed every check that decides
        whether it describes the grasp (``INVALID_KINDS``: grasp, pad,
        outline, reduction, solver); an impact alone leaves it valid."""
        ok = np.ones(len(self), dtype=bool)
        for k, m in self.checks.items():
            if k in INVALID_KINDS:
                ok &= ~m
        return ok

    def reasons(self, i: int) -> Tuple[str, ...]:
        """The kinds of the checks trajectory ``i`` failed (see :attr:`checks`), in that order."""
        i = _index(i, len(self))
        return tuple(k for k, m in self.checks.items() if m[i])

    def gridded(self, name: str, invalid: str = "nan") -> NDArray[Any]:
        """Attribute (or stats entry) ``name`` with the batch axis reshaped to
        ``shape``: e.g. ``gridded("final_displacement")`` is (*shape, ndof).

        invalid : what the grid holds for a trajectory that is not
            :attr:`valid`: ``"nan"`` (default; float arrays get NaN there,
            integer and bool arrays come back as a ``numpy.ma`` masked array),
            ``"mask"`` (a masked array, masked there), ``"include"`` (its
            values as they are). Parameters (``params``) are inputs and are
            never masked."""
        if invalid not in ("nan", "mask", "include"):
            raise ValueError(f"invalid must be 'nan', 'mask' or 'include', got {invalid!r}")
        is_param = name not in self.stats and name in self.params
        a = self.stats[name] if name in self.stats else (
            self.params[name] if name in self.params else getattr(self, name))
        a = np.asarray(a)
        if name == "t" or np.shape(a)[:1] != (len(self),):
            raise ValueError(f"gridded({name!r}): {name} has no batch axis (shape {np.shape(a)})")
        out = a.reshape(tuple(self.shape) + a.shape[1:])
        if invalid == "include" or is_param:
            return out
        bad = (~self.valid).reshape(tuple(self.shape) + (1,) * (a.ndim - 1))
        if invalid == "nan" and out.dtype.kind in "fc":
            return np.where(bad, np.nan, out) if bad.any() else out
        return np.ma.masked_array(out, mask=np.broadcast_to(bad, out.shape))

    def scene_at(self, i: int) -> Scene:
        """The :class:`exdex.Scene` of trajectory ``i``, made with
        ``dataclasses.replace`` from the base scene and ``params``."""
        i = _index(i, len(self))
        base = self.scene[i] if isinstance(self.scene, tuple) else self.scene
        return _replace_params(base, {k: float(v[i]) for k, v in self.params.items()})

    def at(self, i: int) -> Result:
        """Trajectory ``i`` as an :class:`exdex.Result` (record="all" only);
        ``batch[i]`` is the same."""
        if self.record != "all":
            raise ValueError("at(i) needs record='all'; this batch kept the final sample only")
        i = _index(i, len(self))
        stats = {k: (int(v[i]) if v.dtype.kind == "i" else float(v[i])) for k, v in self.stats.items()}
        cert = None
        if self.reduction_first_bad is not None and int(self.reduction_first_bad[i]) >= 0:
            # the batch keeps how long the reduction held; simulate the scene for the load
            until = np.asarray(self.reduction_valid_until)
            cert = dict(holds=bool(self.reduction_holds[i]), valid_until=float(until[i]))
            if not cert["holds"]:
                cert["first_bad"] = int(self.reduction_first_bad[i])
        return Result(t=self.t, q=self.q[i], v=self.v[i], wrench=self.wrench[i], stick=self.stick[i],
                      stop_force=self.stop_force[i], stats=stats, scene=self.scene_at(i), method=self.method,
                      friction_solver=self.friction_solver, dt=self.dt, certificate=cert)

    def __getitem__(self, i: int) -> Result:
        """``batch[i]``: trajectory ``i`` as an :class:`exdex.Result` (see :meth:`at`)."""
        if isinstance(i, (bool, np.bool_)) or not isinstance(i, (int, np.integer)):
            raise TypeError(f"batch indices must be integers, got {type(i).__name__}")
        return self.at(i)

    def __iter__(self) -> Iterator[Result]:
        return (self.at(i) for i in range(len(self)))

    def result(self, i: int) -> Result:
        """Deprecated name of :meth:`at` (``batch[i]`` reads better)."""
        warnings.warn("BatchResult.result(i) is deprecated: use BatchResult.at(i) or batch[i]",
                      DeprecationWarning, stacklevel=2)
        return self.at(i)

    @staticmethod
    def concatenate(parts: Iterable["BatchResult"], shape: Optional[Tuple[int, ...]] = None) -> "BatchResult":
        """One BatchResult from several of the same setting, in the given order."""
        parts = list(parts)
        if not parts:
            raise ValueError("nothing to concatenate")
        p0 = parts[0]
        for p in parts[1:]:
            if (p.record, p.method, p.dt, p.t_end) != (p0.record, p0.method, p0.dt, p0.t_end) \
                    or set(p.params) != set(p0.params) or p.q.shape[1:] != p0.q.shape[1:]:
                raise ValueError("can only concatenate batches of the same record, method, dt, t_end, "
                                 "parameters and shape")
        cat = lambda name: np.concatenate([getattr(p, name) for p in parts])  # noqa: E731
        n = sum(len(p) for p in parts)
        return BatchResult(
            t=p0.t, q=cat("q"), v=cat("v"), wrench=cat("wrench"), stick=cat("stick"),
            stop_force=cat("stop_force"), final_displacement=cat("final_displacement"),
            stats={k: np.concatenate([p.stats[k] for p in parts]) for k in p0.stats},
            params={k: np.concatenate([p.params[k] for p in parts]) for k in p0.params},
            shape=tuple(shape) if shape is not None else (n,), scene=p0.scene, record=p0.record,
            method=p0.method, friction_solver=p0.friction_solver, dt=p0.dt, t_end=p0.t_end,
            threads=max(p.threads for p in parts),
            reduction_valid_until=None if any(p.reduction_valid_until is None for p in parts)
            else cat("reduction_valid_until"),
            reduction_first_bad=None if any(p.reduction_first_bad is None for p in parts)
            else cat("reduction_first_bad"))


def _index(i, n):
    i = int(i)
    if not -n <= i < n:
        raise IndexError(f"batch index {i} out of range for a batch of {n}")
    return i % n


# ------------------------------------------------------------------ checks

def _cpu_count():
    """CPUs this process may run on (affinity-aware where the OS tells)."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except (AttributeError, OSError):  # pragma: no cover - not Linux
        return os.cpu_count() or 1


@functools.lru_cache(maxsize=None)
def _method_available(method):
    """A method runs in a batch exactly when exdex.simulate accepts it (one
    tiny probe per method and process, so the two can never disagree)."""
    from exdex.simulate import simulate

    probe = Scene(body=Body(mass=1.0), grasp=Grasp(mu=0.5, grip_force=1.0))
    try:
        simulate(probe, t_end=1e-3, dt=1e-3, method=method)
    except ValueError as exc:
        return str(exc)
    return None


def _check_options(method, friction_solver, eps, rtol, atol):
    if method not in METHODS:
        raise ValueError(f"method must be one of {sorted(METHODS)}, got {method!r}")
    why = _method_available(method)
    if why is not None:
        raise ValueError(why)
    if friction_solver not in SOLVERS:
        raise ValueError(f"friction_solver must be one of {sorted(SOLVERS)}, got {friction_solver!r}")
    return (_real(eps, "eps", low=0.0, low_open=True), _real(rtol, "rtol", low=0.0, low_open=True),
            _real(atol, "atol", low=0.0, low_open=True))


def _check_param(name, scene):
    if name not in PARAMETERS:
        hint = f"; did you mean {_ALIASES[name]!r}?" if name in _ALIASES else ""
        raise ValueError(f"unknown batch parameter {name!r}{hint} (allowed: {', '.join(PARAMETERS)})")
    p = PARAMETERS[name]
    scenes = scene if isinstance(scene, tuple) else (scene,)
    for sc in scenes:
        if name.startswith("pad_"):
            pad = sc.grasp.pad
            if pad is None:
                raise ValueError(f"batch parameter {name!r} sets Grasp.pad, which the scene does not have "
                                 "(pads on the fingers: Grasp(pad=exdex.Pad...))")
            if (name == "pad_radius") != (pad.radius is not None):
                raise ValueError(f"batch parameter {name!r} needs a {'disc' if name == 'pad_radius' else 'polygon'} "
                                 f"pad (Pad.{'radius' if name == 'pad_radius' else 'scale'})")
        if p.motions and not isinstance(sc.motion, p.motions):
            kinds = " or ".join(c.__name__ for c in p.motions)
            raise ValueError(f"batch parameter {name!r} sets motion.{p.path[-1]}, which needs a {kinds} "
                             f"motion; the scene's motion is {type(sc.motion).__name__}")
        why = _unread(name, sc)
        if why is not None:
            raise ValueError(f"batch parameter {name!r} does not change this scene: {why}")
    return p


def _check_values(name, p, a):
    """Vectorised form of the dataclass's range check, naming the first bad entry."""
    bad = ~np.isfinite(a)
    if p.low is not None:
        bad |= (a <= p.low) if p.low_open else (a < p.low)
    if p.high is not None:
        bad |= (a >= p.high) if p.high_open else (a > p.high)
    if np.any(bad):
        i = int(np.flatnonzero(bad.ravel())[0])
        idx = np.unravel_index(i, a.shape) if a.ndim else ()
        where = f"{name}[{', '.join(map(str, idx))}]" if a.ndim else name
        raise ValueError(f"{where} = {a.ravel()[i]:g} must be finite and in {p.describe()} "
                         f"({'.'.join(map(str, p.path))})")


def _check_trapezoids(scene, flat):
    """TrapezoidalProfile's coupled check, vectorised: amplitude != 0 and
    |X1|/T <= v_max <= 2|X1|/T (with the dataclass's 1e-12 slack)."""
    if not any(PARAMETERS[k].path[0] == "motion" for k in flat):
        return
    scenes = scene if isinstance(scene, tuple) else (scene,)
    if not any(isinstance(sc.motion, TrapezoidalProfile) for sc in scenes):
        return
    n = len(next(iter(flat.values())))
    base = lambda f: np.array([getattr(sc.motion, f) for sc in scenes]) if len(scenes) > 1 \
        else np.full(n, getattr(scenes[0].motion, f))  # noqa: E731
    a = flat.get("amplitude", base("amplitude"))
    T = flat.get("duration", base("duration"))
    v = flat.get("v_max", base("v_max"))
    bad = (a == 0.0) | (v < np.abs(a) / T * (1 - 1e-12)) | (v > 2 * np.abs(a) / T * (1 + 1e-12))
    if np.any(bad):
        i = int(np.flatnonzero(bad)[0])
        raise ValueError(f"batch index {i}: a TrapezoidalProfile needs amplitude != 0 and |amplitude|/duration "
                         f"<= v_max <= 2 |amplitude|/duration; got amplitude {a[i]:g}, duration {T[i]:g}, "
                         f"v_max {v[i]:g}")


def _check_static(scene, flat):
    """Grasp's coupled check, vectorised: mu_static >= mu where mu_static is
    given (a scene's None means equal to mu, whatever mu is varied to)."""
    if "mu" not in flat and "mu_static" not in flat:
        return
    scenes = scene if isinstance(scene, tuple) else (scene,)
    n = len(next(iter(flat.values())))
    base = lambda f: np.array([np.nan if getattr(sc.grasp, f) is None else getattr(sc.grasp, f)  # noqa: E731
                               for sc in scenes]) if len(scenes) > 1 else \
        np.full(n, np.nan if getattr(scenes[0].grasp, f) is None else getattr(scenes[0].grasp, f))
    mu = flat.get("mu", base("mu"))
    ms = flat.get("mu_static", base("mu_static"))
    bad = ms < mu   # NaN (not given) compares False
    if np.any(bad):
        i = int(np.flatnonzero(bad)[0])
        raise ValueError(f"batch index {i}: mu_static = {ms[i]:g} must be in [mu, inf) = [{mu[i]:g}, inf) "
                         "(grasp.mu_static)")


def _check_patch_centres(scene, flat):
    """Scene's check of the patch centre, vectorised: patch_x / patch_y must
    keep Grasp.patch.center on the object's face (naming the first entry off it)."""
    if "patch_x" not in flat and "patch_y" not in flat:
        return
    scenes = scene if isinstance(scene, tuple) else (scene,)
    n = len(next(iter(flat.values())))
    for j, sc in enumerate(scenes):
        idx = np.arange(n) if len(scenes) == 1 else np.array([j])
        c = np.column_stack([flat["patch_x"][idx] if "patch_x" in flat else np.full(len(idx), sc.grasp.patch.center[0]),
                             flat["patch_y"][idx] if "patch_y" in flat else np.full(len(idx), sc.grasp.patch.center[1])])
        d, tol = patch_centres_outside(sc, c)
        bad = np.flatnonzero(d > tol)
        if len(bad):
            k = int(bad[0])
            i = int(idx[k])
            raise ValueError(f"batch index {i}: patch_x = {c[k, 0]:g}, patch_y = {c[k, 1]:g} put Grasp.patch.center "
                             f"{d[k]:.4g} m outside the object's contact face: the plates would not touch the object "
                             "at t = 0 (grasp.patch.center)")


def _as_float_array(value, name):
    if isinstance(value, (str, bytes)):
        raise TypeError(f"batch parameter {name!r} must be numbers, got {type(value).__name__}")
    a = np.asarray(value)
    if a.dtype == object or not (np.issubdtype(a.dtype, np.number) or a.dtype == bool) or np.iscomplexobj(a):
        raise TypeError(f"batch parameter {name!r} must be an array of real numbers, got dtype {a.dtype}")
    return np.asarray(a, dtype=np.float64)


def _broadcast(arrays):
    """Broadcast the named arrays together; a clear error for mismatches."""
    try:
        shape = np.broadcast_shapes(*(a.shape for a in arrays.values()))
    except ValueError:
        shapes = ", ".join(f"{k} {a.shape}" for k, a in arrays.items())
        raise ValueError(f"batch parameter shapes do not broadcast together: {shapes} "
                         f"(give arrays of one length, or shapes like (k, 1) and (1, m) for a grid)") from None
    return shape, {k: np.ascontiguousarray(np.broadcast_to(a, shape)).ravel() for k, a in arrays.items()}


# ------------------------------------------------------------------ batch

def simulate_batch(scene: Union[Scene, Sequence[Scene]], t_end: float, dt: float = 1e-3,
                   threads: Optional[int] = None, record: str = "all", method: Method = "implicit",
                   friction_solver: FrictionSolver = "scalar", eps: float = 1e-4, rtol: float = 1e-8,
                   atol: float = 1e-10, *, warn: bool = True, **arrays: ArrayLike) -> BatchResult:
    """Simulate many variants of a scene in one call, on several threads.

    Parameters
    ----------
    scene : exdex.Scene or sequence of exdex.Scene
        The base scene, or one scene per trajectory (all with the same free
        coordinates and number of stops).
    t_end, dt : float
        End time and time step [s], shared by the batch (as in exdex.simulate).
    threads : int or None
        POSIX threads to use; None: one per CPU available to the process.
        The GIL is released while they run; called from the main thread,
        Ctrl-C (KeyboardInterrupt) stops the batch within about 0.1 s.
    record : {"all", "final"}
        "all" keeps every sample; "final" only the last one (and the final
        displacement), so 10^4 - 10^5 trajectories fit in memory.
    method, friction_solver, eps, rtol, atol
        As in :func:`exdex.simulate` (the batch accepts exactly its methods).
    warn : bool
        Issue :class:`exdex.PhysicsWarning` for results outside the model
        (one per kind of finding, naming the first trajectory and how many
        others); with ``record="final"`` the pad and outline checks see the
        final pose only.
    **arrays
        Parameters varied across the batch, each an array (or scalar); they
        broadcast together and the batch runs over their broadcast shape in
        C order. Names (the Scene field each replaces, its allowed range):

        ``mass`` (body.mass, kg > 0), ``mu`` (grasp.mu, >= 0), ``mu_static``
        (grasp.mu_static, >= mu; a scene without it keeps it equal to mu as
        mu varies), ``grip_force``
        (grasp.grip_force per finger, N >= 0; on a :class:`exdex.GripSchedule`
        a factor >= 0 on its forces, ``GripSchedule.scaled``), ``e_r``
        (grasp.patch.e_r, m > 0),
        ``amplitude`` (motion.amplitude, X1 [m] or theta1 [rad]),
        ``duration`` (motion.duration, T [s] > 0), ``beta`` (motion.beta of
        an AsymmetricProfile, in (0, 1)), ``v_max`` (motion.v_max of a
        TrapezoidalProfile), ``patch_x``, ``patch_y`` (grasp.patch.center,
        the pad centre in the object frame [m]; with ``method="auto"`` such
        a batch runs the event method, since the analytic path needs a
        rotation scene's pivot at the centre of mass).

        Trajectory i is the scene ``dataclasses.replace`` would make with the
        i-th values (:meth:`BatchResult.scene_at`), and its arrays are
        bit-identical to ``exdex.simulate`` of that scene.

    Returns
    -------
    BatchResult

    Raises
    ------
    TypeError, ValueError
        For unknown parameter names, shapes that do not broadcast, values out
        of range (naming the parameter and entry) or a scene the core rejects
        ("batch index i: ...").
    exdex.SolverError
        If a trajectory fails; ``.index`` is the smallest failing batch index
        and the message is simulate's for that trajectory ("batch index i: "
        in front: the time reached, the cause and the remedy; attributes
        ``time`` and ``cause`` as in :func:`exdex.simulate`).
    """
    if isinstance(scene, Scene):
        scenes = None
    elif isinstance(scene, (list, tuple)) and scene and all(isinstance(s, Scene) for s in scene):
        scenes = tuple(scene)
    else:
        raise TypeError("scene must be an exdex.Scene or a non-empty sequence of exdex.Scene, "
                        f"got {type(scene).__name__}")
    dt, t_end = _check_times(t_end, dt)
    if threads is None:
        threads = _cpu_count()
    elif isinstance(threads, bool) or not isinstance(threads, (int, np.integer)) or not 1 <= threads <= 1024:
        raise ValueError(f"threads must be an int in [1, 1024] or None (one per CPU), got {threads!r}")
    if record not in ("all", "final"):
        raise ValueError(f"record must be 'all' or 'final', got {record!r}")
    if method == "auto":
        ok = all(resolve_method(s, "auto") == "analytic" for s in (scenes if scenes is not None else (scene,))) \
            and not any(k in ("patch_x", "patch_y") for k in arrays)
        method = "analytic" if ok else "event"
    eps, rtol, atol = _check_options(method, friction_solver, eps, rtol, atol)

    base = scenes if scenes is not None else scene
    for i, sc in enumerate(scenes if scenes is not None else (scene,)):
        try:
            sc.check_stops()   # the varied parameters never move the object or the stops
        except ValueError as exc:
            raise ValueError(f"batch index {i}: {exc}" if scenes is not None else str(exc)) from None
    vals = {}
    for name, value in arrays.items():
        p = _check_param(name, base)
        a = _as_float_array(value, name)
        _check_values(name, p, a)
        vals[name] = a
    if scenes is not None:
        if any(a.ndim > 1 for a in vals.values()):
            raise ValueError("with a sequence of scenes the batch parameters must be scalars or 1-D arrays "
                             f"of its length {len(scenes)}")
        vals = {k: np.broadcast_to(a, (len(scenes),)) if a.ndim == 0 else a for k, a in vals.items()}
        for k, a in vals.items():
            if a.shape != (len(scenes),):
                raise ValueError(f"batch parameter {k!r} has {a.shape[0]} entries but {len(scenes)} scenes "
                                 "were given")
        shape = (len(scenes),)
        flat = {k: np.ascontiguousarray(a, dtype=np.float64) for k, a in vals.items()}
    elif vals:
        shape, flat = _broadcast(vals)
    else:
        shape, flat = (1,), {}
    if math.prod(shape) == 0:
        raise ValueError(f"the batch is empty (broadcast shape {shape})")
    _check_trapezoids(scenes if scenes is not None else scene, flat)
    _check_static(scenes if scenes is not None else scene, flat)
    _check_patch_centres(scenes if scenes is not None else scene, flat)

    opts: Dict[str, Any] = dict(method=method, friction_solver=friction_solver, eps=eps, rtol=rtol, atol=atol)
    specs: Any = [s.to_spec(**opts) for s in scenes] if scenes is not None else cast(Scene, scene).to_spec(**opts)
    vary: Optional[Dict[str, Any]] = {PARAMETERS[k].key: a for k, a in flat.items()}
    if not vary and scenes is None:
        vary = None
    try:
        out = _core.simulate_batch(specs, t_end, dt, threads=int(threads), record=record, vary=vary,
                                   check_signals=threading.current_thread() is threading.main_thread())
    except ValueError as exc:
        # name the user's parameter rather than the core's field
        msg = str(exc)
        for k, p in PARAMETERS.items():
            if p.path[0] == "motion":
                msg = msg.replace(f"'motion.{p.path[-1]}'", f"'{k}' (motion.{p.path[-1]})")
        raise ValueError(msg) from None
    except SolverError as exc:
        failed: Optional[int] = getattr(exc, "index", None)
        if failed is not None:
            one = cast(Scene, scenes[failed] if scenes is not None else scene)
            if one.dof == "rotation" and one.obstacles:
                # simulate's message for the failed trajectory (the rotation model against obstacles)
                one = _replace_params(one, {k: float(np.ravel(a)[failed]) for k, a in flat.items()})
                reduced_obstacle_hint(one, one.to_spec(**opts), exc)
        raise
    _warn_log_jumps(scenes if scenes is not None else [scene], specs if scenes is not None else [specs], t_end)
    res = BatchResult(t=out["t"], q=out["q"], v=out["v"], wrench=out["wrench"], stick=out["stick"],
                      stop_force=out["stop_force"], final_displacement=out["displacement"], stats=out["stats"],
                      params=flat, shape=tuple(int(s) for s in shape),
                      scene=scenes if scenes is not None else scene, record=record, method=method,
                      friction_solver=friction_solver, dt=dt, t_end=t_end, threads=int(out["threads"]),
                      reduction_valid_until=out["reduction_valid_until"],
                      reduction_first_bad=out["reduction_first_bad"])
    if warn:
        diagnostics.issue(_batch_findings(res))
    return res


#: The checks whose failure makes a trajectory invalid (:attr:`BatchResult.valid`): pads that
#: lost the object ("grasp"), a slide past the pad ("pad"), the pad centre outside the body
#: outline ("outline"), a failed reduction certificate ("reduction"), soft solver problems
#: ("solver"). An impact ("impact") leaves the trajectory valid: only ``stop_force`` holds the
#: impulse as a spike.
INVALID_KINDS = ("grasp", "pad", "outline", "reduction", "solver")


def _batch_checks(b):
    """kind -> ((B,) bool mask, True where that check fails; make(i): the
    PhysicsWarning of trajectory i), for every check the batch can run
    (record="final" checks the final pose against the pad and outline only)."""
    n = len(b)
    out = {}

    def add(kind, mask, make):
        if kind in out:
            old, make_old = out[kind]
            first_old = np.flatnonzero(old)
            first_new = np.flatnonzero(mask)
            keep_old = len(first_old) and (not len(first_new) or first_old[0] < first_new[0])
            out[kind] = (old | mask, make_old if keep_old else make)
        else:
            out[kind] = (np.asarray(mask, dtype=bool), make)

    # stats: only the flagged trajectories are looked at
    for key in ("impacts", "warnings"):
        if key in b.stats:
            flagged = np.asarray(b.stats[key]) > 0
            kind = {"impacts": "impact", "warnings": "solver"}[key]

            def make_stat(i, kind=kind):
                st = {k: np.asarray(v)[i].item() for k, v in b.stats.items()}
                st = {k: (None if isinstance(v, float) and math.isnan(v) else v) for k, v in st.items()}
                return [w for w in diagnostics.stats_findings(st) if w.kind == kind][0]
            add(kind, flagged, make_stat)
    # pads on the fingers: the core stops a run whose grasp is lost and
    # reports the time (stats["grasp_lost_t"]; the trajectory holds NaN after
    # that sample)
    if "grasp_lost_t" in b.stats:
        lost_t = np.asarray(b.stats["grasp_lost_t"], dtype=float)

        def make_lost(i):
            t = float(lost_t[i])
            return diagnostics.PhysicsWarning(
                f"at t = {t:.6g} s the contact region of the pads and the object's face vanished: the grasp is "
                "lost and the run stopped there (NaN after it)", kind="grasp", time=t,
                quantity="contact area [m^2]", value=0.0, limit=None)
        add("grasp", np.isfinite(lost_t), make_lost)
    # pad and outline: the varied parameters never change the geometry, so
    # one base scene checks every trajectory at once
    groups = [(b.scene[i], [i]) for i in range(n)] if isinstance(b.scene, tuple) else [(b.scene, list(range(n)))]
    for sc, idx in groups:
        idx = np.asarray(idx)
        if b.record == "all":
            q = b.q[idx]
            times = np.broadcast_to(b.t, q.shape[:2])
        else:
            q = b.q[idx][:, None, :]
            times = np.full(q.shape[:2], b.t_end)
        rows = q.reshape(-1, q.shape[-1])
        for chk in diagnostics.contact_checks(sc, rows):
            mask = chk["mask"].reshape(q.shape[:2])
            value = chk["value"].reshape(q.shape[:2])
            full = np.zeros(n, bool)
            full[idx] = mask.any(axis=1)

            def make_contact(i, chk=chk, mask=mask, value=value, times=times, idx=idx):
                r = int(np.flatnonzero(idx == i)[0])
                j = int(np.flatnonzero(mask[r])[0])
                v = float(value[r, j])
                return diagnostics.PhysicsWarning(
                    f"at t = {times[r, j]:.6g} s " + chk["text"](v, None), kind=chk["kind"],
                    time=float(times[r, j]), quantity=chk["quantity"], value=v, limit=chk["limit"])
            add(chk["kind"], full, make_contact)
    if b.reduction_first_bad is not None:
        def make_cert(i):
            t = float(b.reduction_valid_until[i])
            return diagnostics.PhysicsWarning(
                f"the reduction of its {b.scene_at(i).dof} model fails at t = {t:.6g} s "
                f"(reduction_valid_until): the neglected in-plane coordinates need a plate load the limit "
                f"surface does not hold; past this time that result does not describe the grasp (simulate "
                f"that scene for the load and margin, or with dof='planar')", kind="reduction", time=t,
                quantity="reduction_valid_until [s]", value=t, limit=None)
        add("reduction", ~b.reduction_holds, make_cert)
    return out


def _batch_findings(b):
    """One PhysicsWarning per kind of finding over the batch, naming the
    first trajectory and how many others (a :class:`exdex.ReductionWarning`
    for failed reductions)."""
    n = len(b)
    out = []
    for kind, (mask, make) in b._check_results.items():
        idx = np.flatnonzero(mask)
        if not len(idx):
            continue
        i, count = int(idx[0]), len(idx)
        w = make(i)
        msg = f"batch index {i}" + (f" (and {count - 1} more of {n} trajectories)" if count > 1 else "")
        marked = (f" ({'this trajectory is' if count == 1 else 'these trajectories are'} marked invalid: "
                  "BatchResult.valid, NaN in gridded())") if kind in INVALID_KINDS else ""
        text = f"{msg}: {w}{marked}"
        if kind == "reduction":
            out.append(diagnostics.ReductionWarning.aggregate(text, w.time))
        else:
            out.append(diagnostics.PhysicsWarning(text, kind=w.kind, time=w.time, quantity=w.quantity,
                                                  value=w.value, limit=w.limit))
    return out


def _warn_log_jumps(scenes, specs, t_end):
    """A GripperJumpWarning for each robot log of the batch that starts or
    ends at speed inside the run (as exdex.simulate warns)."""
    from exdex.scene import SampledTrajectory
    from exdex._jumps import jumps as _jumps, warn_jumps as _warn_jumps

    seen = set()
    for sc, spec in zip(scenes, specs):
        if isinstance(sc.motion, SampledTrajectory) and id(sc.motion) not in seen:
            seen.add(id(sc.motion))
            _warn_jumps(sc, _jumps(sc, spec), t_end)


# ------------------------------------------------------------------ sweep

def grid_points(grid: Mapping[str, ArrayLike], product: bool = True) -> Tuple[Dict[str, NDArray[np.float64]], Tuple[int, ...]]:
    """Flatten a parameter grid: returns (dict name -> (B,) arrays, shape).

    product=True: the Cartesian product of the value lists (each flattened to
    1-D), shape = their lengths, C order (the last name varies fastest).
    product=False: the arrays broadcast together (as in simulate_batch).
    """
    if not isinstance(grid, Mapping) or not grid:
        raise ValueError("grid must be a non-empty mapping name -> values")
    arrays = {}
    for k, v in grid.items():
        if not isinstance(k, str):
            raise TypeError(f"grid keys must be parameter names (str), got {k!r}")
        arrays[k] = _as_float_array(v, k)
    if product:
        axes = [a.ravel() for a in arrays.values()]
        shape = tuple(len(a) for a in axes)
        mesh = np.meshgrid(*axes, indexing="ij") if axes else []
        flat = {k: np.ascontiguousarray(m).ravel() for k, m in zip(arrays, mesh)}
    else:
        shape, flat = _broadcast(arrays)
    if math.prod(shape) == 0:
        raise ValueError(f"the grid is empty (shape {shape})")
    return flat, tuple(int(s) for s in shape)


def _run_scene_chunk(scene, t_end, options, params):
    """One sweep task: a single-threaded batch (module level, so it pickles)."""
    return simulate_batch(scene, t_end, threads=1, warn=False, **options, **params)


def _run_fn_chunk(fn, params):
    return fn(**params)


def _combine(parts, shape):
    p0 = parts[0]
    if isinstance(p0, BatchResult):
        return BatchResult.concatenate(parts, shape=shape)
    if isinstance(p0, Mapping):
        return {k: np.concatenate([np.atleast_1d(p[k]) for p in parts]) for k in p0}
    if isinstance(p0, (np.ndarray, list, tuple)):
        return np.concatenate([np.atleast_1d(np.asarray(p)) for p in parts])
    return list(parts)


def sweep(fn_or_scene: Union[Scene, Callable[..., Any]], grid: Mapping[str, ArrayLike],
          executor: Optional[cf.Executor] = None, chunk: Optional[int] = None,
          progress: Union[bool, None, Callable[[int, int], Any]] = None, *,
          product: bool = True, t_end: Optional[float] = None, dt: float = 1e-3, record: str = "final",
          **options: Any) -> Any:
    """Run a parameter grid in chunks over any concurrent.futures.Executor.

    Parameters
    ----------
    fn_or_scene : exdex.Scene or callable
        A scene: every chunk runs ``simulate_batch(scene, t_end, dt=dt,
        threads=1, record=record, **options, **chunk_params)``; the chunks'
        BatchResults are joined into one whose ``shape`` is the grid's.
        A callable: ``fn(**chunk_params)`` gets 1-D arrays of one chunk's
        parameter sets and returns a BatchResult, a dict of arrays, or an
        array, with one entry (leading axis) per parameter set; they are
        concatenated in grid order. With a process-based or remote executor
        the callable must be picklable (a module-level function).
    grid : mapping name -> values
        With ``product=True`` (default) the Cartesian product of the value
        lists, in C order (the last name varies fastest); with
        ``product=False`` arrays broadcast together (see :func:`grid_points`).
    executor : concurrent.futures.Executor or None
        Where the chunks run: e.g. ``ThreadPoolExecutor`` (the default, one
        worker per CPU, shut down afterwards) or a Dask cluster's
        ``client.get_executor()``. An executor you pass is not shut down.
    chunk : int or None
        Parameter sets per task (>= 1). Larger chunks cost less scheduling;
        keep several chunks per worker for balance. None (default): about
        eight chunks per worker, at most 256 parameter sets each (the grid
        size over 8 x the workers, rounded up), so the progress moves in
        steps of a few percent.
    progress : bool, None or callable
        Show a tqdm progress bar (parameter sets done), updated as each
        chunk finishes; None (default): when tqdm is installed (the ``plot``
        extra). A callable ``progress(done, total)`` is called instead after
        each chunk (in the calling thread) with the parameter sets done so
        far and the grid's size.
    t_end, dt, record, **options
        For a scene: as in :func:`simulate_batch` (options: method,
        friction_solver, eps, rtol, atol). Sweeps record the final sample only
        by default.

    Returns
    -------
    BatchResult (for a scene) or the concatenated results of ``fn``, entry i
    belonging to the i-th grid point (see :func:`grid_points`). A scene's
    BatchResult marks the grid points that failed a physics check
    (:attr:`BatchResult.valid`, :attr:`BatchResult.checks`); its
    ``gridded()`` holds NaN there unless ``invalid="include"``.

    A failing chunk cancels the chunks not yet started and re-raises its
    exception with a note naming the chunk's grid points.
    """
    flat, shape = grid_points(grid, product=product)
    total = math.prod(shape)
    warn = False
    if chunk is not None and (isinstance(chunk, bool) or not isinstance(chunk, (int, np.integer)) or chunk < 1):
        raise ValueError(f"chunk must be an int >= 1 or None, got {chunk!r}")
    report = progress if callable(progress) else None
    if not (report is not None or progress is None or isinstance(progress, (bool, np.bool_))):
        raise TypeError(f"progress must be True, False, None or a callable (done, total), got {progress!r}")
    if executor is not None and not isinstance(executor, cf.Executor):
        raise TypeError(f"executor must be a concurrent.futures.Executor, got {type(executor).__name__}")
    if isinstance(fn_or_scene, Scene):
        if t_end is None:
            raise ValueError("sweep over a scene needs t_end")
        # validate once, here, rather than in every task
        for name in flat:
            _check_values(name, _check_param(name, fn_or_scene), flat[name])
        warn = options.pop("warn", True)
        opts = dict(dt=dt, record=record, **options)
        _check_options(opts.get("method", "implicit"), opts.get("friction_solver", "scalar"),
                       opts.get("eps", 1e-4), opts.get("rtol", 1e-8), opts.get("atol", 1e-10))
        task = functools.partial(_run_scene_chunk, fn_or_scene, t_end, opts)
    elif callable(fn_or_scene):
        if t_end is not None or options:
            raise ValueError("t_end and simulation options apply to a scene; a callable gets only the grid")
        task = functools.partial(_run_fn_chunk, fn_or_scene)
    else:
        raise TypeError(f"fn_or_scene must be an exdex.Scene or a callable, got {type(fn_or_scene).__name__}")

    if chunk is None:
        workers = _cpu_count() if executor is None else int(getattr(executor, "_max_workers", 0) or _cpu_count())
        chunk = min(256, max(1, -(-total // (8 * workers))))
    bounds = [(a, min(a + int(chunk), total)) for a in range(0, total, int(chunk))]
    own = executor is None
    ex: cf.Executor = cf.ThreadPoolExecutor(max_workers=_cpu_count()) if executor is None else executor
    parts = [None] * len(bounds)
    if report is not None:
        progress = False
    elif progress is None:
        progress = _optional.available("tqdm")
    done = 0
    try:
        with _optional.progress_bar(total=total, desc="exdex sweep", unit="traj", disable=not progress,
                                    smoothing=0.1, auto=True, feature="sweep(progress=True)") as bar:
            futures = {ex.submit(task, {k: v[a:b] for k, v in flat.items()}): j for j, (a, b) in enumerate(bounds)}
            try:
                for fut in cf.as_completed(futures):
                    j = futures[fut]
                    try:
                        parts[j] = fut.result()
                    except BaseException as exc:
                        a, b = bounds[j]
                        if hasattr(exc, "add_note"):
                            exc.add_note(f"sweep: in chunk {j} (grid points {a}..{b - 1} of {total})")
                        raise
                    bar.update(bounds[j][1] - bounds[j][0])
                    done += bounds[j][1] - bounds[j][0]
                    if report is not None:
                        report(done, total)
            except BaseException:
                for f in futures:
                    f.cancel()
                raise
    finally:
        if own:
            ex.shutdown(wait=True, cancel_futures=True)
    out = _combine(parts, shape)
    if isinstance(out, BatchResult) and warn:
        diagnostics.issue(_batch_findings(out))
    return out

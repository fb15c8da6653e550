"""``exdex bench``: work-precision charts and stability maps (speed against accuracy).

Work-precision (error against run time, log-log)
------------------------------------------------
Four cases: the paper's Figs. 3, 4 and 6 (:mod:`exdex.paper`) and one planar
(x, y, theta) case with a stop defined here (:func:`planar_scene`: a wide box
held off-centre in a gripper that turns about the plate normal, sliding and
turning onto a tilted stop). Each integration method of :func:`exdex.simulate`
gives one line over a sweep of its accuracy knob:

* ``implicit``, ``explicit``: the time step dt = 2^-m s, m = 3 ... 16. Dyadic
  steps never put a grid point on the cases' switching times (0.45 s,
  0.595 s, 2.1 s, 1/12 s, ...), so these lines show the generic error.
* ``implicit, dt on switch times``: dt = (1/320 s) 2^-j, j = 0 ... 9, which
  divides Eq. 7's switching times in Figs. 3, 6 and the planar case (all
  multiples of 0.05 s) and the common grid: what the implicit method gives
  when its grid is laid on the motion's switches (a user can always do this).
* ``event``: the tolerance rtol = 1e-2 ... 1e-12 (atol = 1e-2 rtol), output
  every 2^-6 s.
* ``regularised``: rtol = 1e-2 ... 1e-10, one line per smoothing slip speed
  eps = 1e-2 ... 1e-5 (m/s; rad/s in Fig. 6).

pybullet, MuJoCo and Drake (:mod:`exdex.engines`, default solver settings;
contact "pads" in the translation cases, "point" with torsional friction mu e_r
in the rotation and planar cases, the engines' faithful mapping of the
friction ellipsoid; Drake, whose point contact has no torsional friction:
point contact on plate pads in translation, hydroelastic pads in rotation and
planar cases) give one line each over dt = 2^-m s, m = 7 ... 11. A method that
:func:`exdex.simulate` does not offer (it raises ValueError), in general or for
a scene, is left out and named on the chart. A run that takes more than a per-run budget ends its line.

Reference: the closed form where one exists (Figs. 3 and 6:
:func:`exdex.paper.closed_form`; Fig. 4: :func:`exdex.paper.stop_closed_form`),
else (planar) the event method at rtol 1e-12 when it supports the scene,
otherwise the implicit method at dt = 2^-18 s; its own uncertainty (the
difference to the same method one notch looser) is drawn as a band.

Errors, on the common time grid t = k 2^-6 s (every swept step size up to
2^-6 s divides it, so those runs have their own samples there; coarser or
adaptive runs are interpolated linearly): **final-displacement error**
|q(t_end) - q_ref(t_end)| (top row of the chart, the headline metric) and
**max abs trajectory error** over the grid (bottom row). 1-DoF cases: the free
coordinate (m or rad); planar case: the largest distance between the object's
outline vertices and their reference positions [m]. Observed orders are the
least-squares slopes of log error against log dt (or log rtol, or log eps
over the regularised lines), leaving out errors at the rounding floor.

Run time: median wall time (``time.perf_counter``) of whole
``exdex.simulate`` calls (argument checks, C core, output arrays) after one
warm-up call. Engines: the median wall time of their stepping loop
(``Result.stats["wall_time"]``: model building excluded, the per-step Python
that drives the kinematic gripper and records the state included); for MuJoCo
also a lower bound, the same number of bare ``mj_step`` calls on the same
model with the gripper held still (no Python per step). Its exdex
counterpart is the compiled model's C run, ``exdex.Model(...).final``: the
scene converted and the C model built once outside the timing (as MuJoCo's
model is), the whole trajectory integrated, only the last sample returned
(column ``run_time_compiled_s``, implicit and event runs). The run-time
ratios at equal error compare each engine point with the cheapest
exact-stick exdex run (implicit or event) at least as accurate: pybullet and
MuJoCo's driven loop against whole ``exdex.simulate`` calls, bare ``mj_step``
against ``Model.final``.

Stability maps
--------------
For each method, runs over (dt, friction capacity relative to load) on the
Fig. 3 family (grip force varied; load = m g, the weight the grasp holds once
the gripper stops) and the Fig. 6 family (torque capacity varied; load =
I_zz a_H, the gentle-phase drive of Eq. 7), and for ``regularised`` over
(dt, eps) at the paper's Fig. 3 grasp. Each run is classified against the
closed form (first match):

* ``collapse`` (step collapse): the simulation raised (solver failure, e.g.
  the event method's Zeno-like toggling past its event budget), or an
  adaptive method (event, regularised) took more than ``STEP_BUDGET`` steps
  per simulated second;
* ``blow-up``: non-finite state, or max trajectory error above
  ``BLOWUP_FRACTION`` (100 %) of the reference's largest displacement plus
  ``BLOWUP_FLOOR`` (10 mm or 0.1 rad): an error larger than the motion;
* ``chatter``: more than ``CHATTER_MIN`` sign changes of the velocity
  (counting only |v| > ``V_NOISE``) inside the intervals where the closed
  form sticks, each shrunk by max(2 dt, 10 ms) at both ends (a creep that
  follows the load's reversals changes sign at most twice per Eq. 7 cycle);
* ``drift`` (drift at stick): |v| > ``V_NOISE`` over the second half of a
  stick interval of the closed form (after the motion, or in a loaded hold
  during it); the creep rate is |dx| / dt over that half;
* ``ok``: none of these (implicit and event: exact zeros).

Cells not run are ``skipped`` (a run of the row exceeded the per-run wall
budget, or the 1/eps cost law predicts one would) or ``missing`` (method not
available). Fixed-step methods are mapped over dt = 2^-4 ... 2^-16 s, the
adaptive ones over every second of these (dt is only their output grid).

Output (``--out``, default ``exdex-output/bench``): ``work_precision.png``,
``work_precision.csv``, ``orders.csv``, ``headline.csv``, ``headline.txt``,
``stability_<family>.png``, ``stability.csv``, ``stability_summary.txt``.
"""
from __future__ import annotations

import csv
import math
import os
import platform
import statistics
import time
from dataclasses import dataclass, field
from typing import Optional

import numpy as np

from exdex.studies import paper
from exdex._optional import pyplot, require
from exdex._rotations import quat_from_matrix as _quat_from_matrix
from exdex.scene import AsymmetricProfile, Body, Grasp, Patch, Scene, Stop
from exdex.simulate import SolverError, simulate
from exdex.stepper import Model

__all__ = ["planar_scene", "CASES", "Case", "make_case", "method_available", "available_methods",
           "final_and_max_error", "vertex_error", "classify", "stick_intervals", "observed_order",
           "machine_name", "METHODS", "BLOWUP_FRACTION", "BLOWUP_FLOOR", "V_NOISE"]

METHODS = ("implicit", "explicit", "event", "regularised")
ENGINES = ("pybullet", "mujoco", "drake")
GRID_DT = 2.0 ** -6            # common time grid of the errors [s]
ATOL_PER_RTOL = 1e-2           # atol = ATOL_PER_RTOL * rtol for the adaptive methods
EPS_LINES = (1e-2, 1e-3, 1e-4, 1e-5)   # regularised: one work-precision line per eps
BLOWUP_FRACTION = 1.0          # blow-up: error > fraction * max |reference| + floor
BLOWUP_FLOOR = {"translation": 0.01, "rotation": 0.1}
V_NOISE = 1e-9                 # |v| at or below this counts as still [m/s or rad/s]
CHATTER_MIN = 4                # chatter: more sign changes of v than this in the stick intervals
EVENT_BUDGET = 1000            # event method: more switching events than this = step collapse
STEP_BUDGET = 1e6              # adaptive methods: more steps per simulated second = step collapse
CLASSES = ("ok", "drift", "chatter", "blow-up", "collapse", "skipped", "missing")
FLOOR = 1e-16                  # errors below FLOOR * scale are drawn at that floor

PLANAR = dict(size=(0.06, 0.03, 0.02), mass=0.1, capacity_per_weight=1.1, patch_size=(0.02, 0.02),
              patch_center=(0.01, 0.0), amplitude=0.6, duration=0.5, beta=0.8, tilt_deg=10.0, gap=0.008)


# ------------------------------------------------------------------ the planar case

def planar_scene():
    """Planar (x, y, theta) case with a stop, for the work-precision chart.

    A wide box (60 x 30 x 20 mm, 0.1 kg) is held by two fingers through a
    square patch (20 x 20 mm, uniform pressure) whose centre is 10 mm to the
    side of the centre of mass, with friction capacity 1.1 m g (mu 0.5, grip
    force 0.5396 N per finger): enough to hold the weight, not enough to hold
    the object against gravity plus the inertial terms while the gripper turns.
    The gripper (plates vertical) turns about the plate normal through its
    origin with Eq. 7 as an angle (theta1 0.6 rad, T 0.5 s, beta 0.8) and back.
    A fixed stop plane, tilted 10 deg (normal (sin 10 deg, 0, cos 10 deg) in
    A), lies 8 mm below the box's lowest point: the box slips, turns about the patch, lands on
    the stop, slides along it, and ends at rest with exact stick partly on the
    stop (about 0.28 N) and partly on friction. Every phase of the methods is
    exercised: stick, slip with rotation, unilateral contact, stick on a stop.
    """
    p = PLANAR
    tilt = math.radians(p["tilt_deg"])
    grip = p["capacity_per_weight"] * p["mass"] * paper.G / (paper.MU * paper.FINGERS)
    return Scene(
        body=Body.box(p["mass"], p["size"]),
        grasp=Grasp(mu=paper.MU, grip_force=grip, fingers=paper.FINGERS,
                    patch=Patch.rectangle(*p["patch_size"], center=p["patch_center"])),
        motion=AsymmetricProfile(p["amplitude"], p["duration"], p["beta"], axis=(0.0, -1.0, 0.0), rotation=True),
        dof="planar",
        stops=(Stop(point=(0.0, 0.0, -p["size"][1] / 2 - p["gap"]),
                    normal=(math.sin(tilt), 0.0, math.cos(tilt))),),
    )


# ------------------------------------------------------------------ cases and references

@dataclass
class Case:
    """One work-precision case: scene, horizon, reference on the common grid."""

    name: str
    title: str
    scene: Scene
    t_end: float
    unit: str                      # unit of the error ("m" or "rad")
    engine_contact: str            # contact model of the engine runs
    grid: Optional[np.ndarray] = None        # common time grid [s]
    ref: Optional[np.ndarray] = None         # (n, ndof) reference displacement on the grid
    ref_label: str = ""
    ref_uncertainty: float = 0.0   # final-displacement error of the reference (estimate), 0 for closed forms
    ref_uncertainty_max: float = 0.0
    scale: float = 1.0             # largest |reference| (for floors)
    aligned_dt: Optional[float] = None       # a step dividing the motion's switching times and the grid, if any
    unsupported: list = field(default_factory=list)   # methods simulate() refuses for this scene

    def errors(self, qg):
        """(final, max) error of a displacement ``qg`` (n, ndof) on the grid."""
        return final_and_max_error(self.scene, qg, self.ref)


def vertex_error(scene, q, qref):
    """(n,) largest distance [m] between the outline vertices of the object at
    planar poses ``q`` and at ``qref`` (both (n, 3): x, y, theta in B)."""
    out = np.zeros(len(q))
    for vx, vy in scene.body.vertices():
        def pts(p):
            c, s = np.cos(p[:, 2]), np.sin(p[:, 2])
            return np.stack([p[:, 0] + c * vx - s * vy, p[:, 1] + s * vx + c * vy], axis=1)
        out = np.maximum(out, np.linalg.norm(pts(q) - pts(qref), axis=1))
    return out


def final_and_max_error(scene, qg, qref):
    """(final, max) error of displacements ``qg`` against ``qref`` on the same
    grid: |difference| of the free coordinate (1-DoF) or the vertex distance
    (planar). Non-finite values give inf."""
    qg = np.asarray(qg, dtype=float)
    if not np.all(np.isfinite(qg)):
        return math.inf, math.inf
    if scene.dof == "planar":
        e = vertex_error(scene, qg, qref)
    else:
        e = np.abs(qg[:, 0] - qref[:, 0])
    return float(e[-1]), float(np.max(e))


def on_grid(result, grid):
    """A result's displacement (q - q[0]) at the grid times (linear interpolation
    between its samples; exact where it has a sample)."""
    d = result.q - result.q[0]
    t = result.t
    return np.column_stack([np.interp(grid, t, d[:, j]) for j in range(d.shape[1])])


def method_available(method):
    """(True, "") if ``exdex.simulate`` runs ``method``, else (False, reason)."""
    sc = paper.fig3_scene()
    try:
        simulate(sc, t_end=0.02, dt=0.01, method=method)
    except ValueError as exc:
        return False, str(exc)
    except Exception:   # noqa: BLE001 - it exists but failed on this tiny run: still available
        return True, ""
    return True, ""


def scene_supports(scene, method):
    """True if ``exdex.simulate`` accepts ``method`` for this scene; a two-step
    trial run decides."""
    try:
        simulate(scene, t_end=2 * 1e-3, dt=1e-3, method=method)
    except ValueError:
        return False
    except Exception:   # noqa: BLE001 - accepted, failed on the trial: still supported
        return True
    return True


def available_methods():
    """{method: reason or ""} and the list of available methods."""
    status = {m: method_available(m) for m in METHODS}
    return [m for m in METHODS if status[m][0]], {m: r for m, (ok, r) in status.items() if not ok}


def _tight_reference(scene, t_end, grid, methods, quick):
    """Tight-tolerance run and its uncertainty: (qg, label, unc_final, unc_max)."""
    if "event" in methods and scene_supports(scene, "event"):
        runs = []
        try:
            for rtol in (1e-11, 1e-12):
                r = simulate(scene, t_end, dt=GRID_DT, method="event", rtol=rtol, atol=ATOL_PER_RTOL * rtol)
                if r.stats["warnings"]:
                    raise SolverError(f"event run at rtol {rtol:g} counted {r.stats['warnings']} warnings")
                runs.append(on_grid(r, grid))
        except SolverError:
            runs = []   # the event method cannot reach this tolerance here: the implicit reference below
        if runs:
            unc = final_and_max_error(scene, runs[0], runs[1])
            return runs[1], "event method, rtol 1e-12", unc[0], unc[1]
    m = 15 if quick else 18
    runs = [on_grid(simulate(scene, t_end, dt=2.0 ** -k), grid) for k in (m - 1, m)]
    unc = final_and_max_error(scene, runs[0], runs[1])
    return runs[1], f"implicit method, dt = 2^-{m} s", unc[0], unc[1]


def make_case(name, methods=("implicit",), quick=False):
    """Build case ``name`` ("fig3", "fig4", "fig6", "planar") with its reference on the grid."""
    if name == "fig3":
        sc = paper.fig3_scene()
        c = Case(name, "Fig. 3: inertial slip (1-DoF translation)", sc, 1.5, "m", "pads")
    elif name == "fig4":
        sc = paper.fig4_scene()
        c = Case(name, "Fig. 4: slip against a stop (1-DoF translation)", sc, 1.0, "m", "pads")
    elif name == "fig6":
        sc = paper.fig6_scene()
        c = Case(name, "Fig. 6: rotation about the pivot (1-DoF)", sc, 8.0, "rad", "point")
    elif name == "planar":
        sc = planar_scene()
        c = Case(name, "planar (x, y, theta), tilted stop", sc, 1.5, "m", "point")
    else:
        raise ValueError(f"unknown case {name!r}; expected one of {CASES}")
    if name in ("fig3", "fig6", "planar"):
        # Eq. 7 switches at multiples of 0.05 s here (0.45, 0.55, 1.0 / 2.1, 3.9, 6.0 / 0.4, 0.6, 1.0 s):
        # 1/320 s = 0.05 s / 16 = 2^-6 s / 5 divides them and the common grid
        c.aligned_dt = 1.0 / 320.0
    n = int(round(c.t_end / GRID_DT))
    c.grid = np.arange(n + 1) * GRID_DT
    if name in ("fig3", "fig6"):
        x, _ = paper.closed_form(sc)(c.grid)
        c.ref = x[:, None]
        c.ref_label = "closed form"
    elif name == "fig4":
        x, _, _ = paper.stop_closed_form(sc, c.grid)
        c.ref = x[:, None]
        c.ref_label = "closed form"
    else:
        c.ref, c.ref_label, c.ref_uncertainty, c.ref_uncertainty_max = _tight_reference(
            sc, c.t_end, c.grid, methods, quick)
    c.scale = float(np.max(np.abs(c.ref))) or 1.0
    return c


CASES = ("fig3", "fig4", "fig6", "planar")


# ------------------------------------------------------------------ timing

def _timed(fn, target, min_rep, max_rep):
    """Median wall time of ``fn()`` after one warm-up call: (median [s], repeats, result)."""
    t0 = time.perf_counter()
    res = fn()
    first = time.perf_counter() - t0
    if first > 2.0 * target:
        min_rep = 1    # an expensive run (a stiff regularised one): one timed repeat after the warm-up
    reps = int(min(max_rep, max(min_rep, math.ceil(target / max(first, 1e-9)))))
    times = []
    for _ in range(reps):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times), reps, res


def machine_name():
    """CPU model and core count (no host name), Python and NumPy versions."""
    cpu = platform.processor() or platform.machine()
    try:
        with open("/proc/cpuinfo") as fh:
            for line in fh:
                if line.startswith("model name"):
                    cpu = line.split(":", 1)[1].strip()
                    break
    except OSError:
        pass
    return f"{cpu}, {os.cpu_count()} cores, {platform.system()} {platform.machine()}, " \
           f"Python {platform.python_version()}, NumPy {np.__version__}"


# ------------------------------------------------------------------ work-precision sweeps

ALIGNED_LINE = "implicit, dt on switch times"


def sweeps(methods, quick, aligned=None):
    """[(method, line label, eps or None, [(knob name, knob value, kwargs)])].

    ``aligned``: a step that divides the motion's switching times and the
    common grid (or None): adds the implicit line over aligned / 2^j."""
    if quick:
        ms = (6, 9, 12)
        js = (0, 3)
        tols = (1e-4, 1e-7, 1e-10)
        reg_tols = (1e-4, 1e-8)
        eps_lines = (1e-3,)
    else:
        ms = tuple(range(1, 17))   # dt = 1/2 .. 2^-16 s: from a few steps per motion to the rounding floor
        js = tuple(range(0, 10))
        tols = tuple(10.0 ** -k for k in range(2, 13))
        reg_tols = tuple(10.0 ** -k for k in range(2, 12, 2))
        eps_lines = EPS_LINES
    out = []
    for m in methods:
        if m in ("implicit", "explicit"):
            out.append((m, m, None, [("dt", 2.0 ** -k, dict(dt=2.0 ** -k)) for k in ms]))
        if m == "implicit" and aligned:
            out.append((m, ALIGNED_LINE, None, [("dt", aligned * 2.0 ** -j, dict(dt=aligned * 2.0 ** -j))
                                               for j in js]))
        elif m == "event":
            out.append((m, m, None, [("rtol", r, dict(dt=GRID_DT, rtol=r, atol=ATOL_PER_RTOL * r))
                                     for r in tols]))
        elif m == "regularised":
            for eps in eps_lines:
                out.append((m, f"regularised eps={eps:g}", eps,
                            [("rtol", r, dict(dt=GRID_DT, rtol=r, atol=ATOL_PER_RTOL * r, eps=eps))
                             for r in reg_tols]))
    return out


def _row(case, method, line, knob, value, eps, secs, reps, final, maxe, status, note="", dt=None,
         compiled=math.nan):
    return dict(case=case.name, method=method, line=line, knob=knob, value=value,
                eps="" if eps is None else eps, dt="" if dt is None else dt, run_time_s=secs,
                run_time_compiled_s=compiled, repeats=reps,
                final_error=final, max_error=maxe, error_unit=case.unit, status=status, note=note)


def sweep_exdex(case, methods, quick, bar=None, budget=None):
    """Run every exdex line of ``case``; returns CSV rows (dicts). Methods the
    case's scene does not support are left out (see :func:`scene_supports`)."""
    case.unsupported = [m for m in methods if not scene_supports(case.scene, m)]
    methods = [m for m in methods if m not in case.unsupported]
    budget = budget if budget is not None else (0.5 if quick else 3.0)
    target, min_rep, max_rep = (0.02, 3, 5) if quick else (0.15, 3, 15)
    rows = []
    for method, line, eps, points in sweeps(methods, quick, case.aligned_dt):
        skip = False
        for knob, value, kw in points:
            if bar is not None:
                bar.set_postfix_str(f"{case.name} {line} {knob}={value:.3g}")
            if skip:
                rows.append(_row(case, method, line, knob, value, eps, math.nan, 0, math.nan, math.nan,
                                 "skipped", "an earlier run of this line exceeded the per-run budget",
                                 dt=kw.get("dt")))
                if bar is not None:
                    bar.update()
                continue
            try:
                secs, reps, res = _timed(lambda: simulate(case.scene, case.t_end, method=method, **kw),
                                         target, min_rep, max_rep)
                final, maxe = case.errors(on_grid(res, case.grid))
                status, note = "ok", ""
                compiled = math.nan
                if method in RATIO_METHODS:
                    compiled = _compiled_time(case, method, kw, target, min_rep, max_rep)
                if secs > budget:
                    skip = True
            except Exception as exc:   # noqa: BLE001 - a failed run is a data point
                secs, reps, final, maxe, status, note = math.nan, 0, math.nan, math.nan, "failed", \
                    f"{type(exc).__name__}: {exc}"
                compiled = math.nan
            rows.append(_row(case, method, line, knob, value, eps, secs, reps, final, maxe, status, note,
                             dt=kw.get("dt"), compiled=compiled))
            if bar is not None:
                bar.update()
    return rows


def _compiled_time(case, method, kw, target, min_rep, max_rep):
    """Median wall time [s] of ``Model.final`` for one run of a sweep: the scene
    compiled once (outside the timing, like MuJoCo's model in its bare loop),
    the whole trajectory integrated in C, only the last sample returned. The
    exdex side of the comparison with bare ``mj_step`` calls."""
    kw = dict(kw)
    dt = kw.pop("dt")
    model = Model(case.scene, method=method, **kw)
    secs, _, _ = _timed(lambda: model.final(case.t_end, dt), target, min_rep, max_rep)
    return secs


def engine_runners():
    """{engine: function} of the engines that import; and {engine: reason} of the others."""
    from exdex import engines

    ok, missing = {}, {}
    for name, mod, fn in (("pybullet", "pybullet", engines.run_pybullet), ("mujoco", "mujoco", engines.run_mujoco),
                          ("drake", "pydrake", engines.run_drake)):
        try:
            __import__(mod)
            ok[name] = fn
        except ImportError as exc:
            missing[name] = str(exc)
    return ok, missing


def mujoco_bare_step_time(scene, t_end, dt, contact):
    """Wall time [s] of round(t_end / dt) bare ``mujoco.mj_step`` calls on the
    model ``exdex.engines.run_mujoco`` builds for ``scene`` (default settings),
    with the gripper held still and squeezing: a lower bound on MuJoCo's time
    per trajectory without the per-step Python that drives the gripper.
    Returns NaN if the model cannot be built this way."""
    try:
        import mujoco

        from exdex.engines._runner import Layout, gripper_kinematics
        from exdex.engines.mujoco import mujoco_xml

        lay = Layout(scene, contact)
        xml = mujoco_xml(lay, dt=dt, iterations=100, cone="elliptic", impratio=1.0, noslip_iterations=0,
                          solver="Newton", tolerance=1e-8, torsional=None, gripper_mass=1e4, plate_mass=0.1)
        m = mujoco.MjModel.from_xml_string(xml)
        d = mujoco.MjData(m)
        gid = m.body("gripper").id
        sq = m.joint("squeeze").dofadr[0]
        kin = gripper_kinematics(scene, [0.0])
        d.qpos[0:3] = kin["p"][0]
        d.qpos[3:7] = _quat_from_matrix(kin["R"][0])
        d.xfrc_applied[gid, 0:3] = -1e4 * np.array(scene.gravity)
        d.qfrc_applied[sq] = -scene.grasp.grip_force
        mujoco.mj_forward(m, d)
        n = int(round(t_end / dt))
        step = mujoco.mj_step
        t0 = time.perf_counter()
        for _ in range(n):
            step(m, d)
        return time.perf_counter() - t0
    except Exception:   # noqa: BLE001 - private helpers of exdex.engines may change
        return math.nan


def _engine_settings(name, case):
    """Keyword arguments of an engine's runs in ``case``: the case's contact, and for
    Drake, whose point contact has no torsional friction, hydroelastic pads in the
    rotation and planar cases (the pressure patch gives the torsion) and its
    default point contact with plate pads in translation."""
    if name != "drake":
        return dict(contact=case.engine_contact)
    if case.scene.dof == "translation":
        return dict(contact="pads", contact_model="point")
    return dict(contact="pads", contact_model="hydroelastic")


def sweep_engines(case, runners, quick, bar=None):
    """pybullet / MuJoCo / Drake at several step sizes; CSV rows."""
    ms = (8,) if quick else (7, 8, 9, 10, 11)
    rows = []
    for name, fn in runners.items():
        for k in ms:
            dt = 2.0 ** -k
            if bar is not None:
                bar.set_postfix_str(f"{case.name} {name} dt=2^-{k}")
            try:
                walls = []
                res = None
                reps = 1 if quick else 3
                for i in range(reps):
                    kw = _engine_settings(name, case)
                    res = fn(case.scene, case.t_end, dt=dt, **kw)
                    walls.append(res.stats["wall_time"])
                    if walls[-1] > 0.3:
                        break
                final, maxe = case.errors(on_grid(res, case.grid))
                what = ", ".join(f"{k}={v}" for k, v in kw.items())
                rows.append(_row(case, name, name, "dt", dt, None, statistics.median(walls), len(walls), final,
                                 maxe, "ok", f"stepping loop, {what}", dt=dt))
                if name == "mujoco":
                    bare = [mujoco_bare_step_time(case.scene, case.t_end, dt, case.engine_contact)
                            for _ in range(1 if quick else 3)]
                    rows.append(_row(case, "mujoco bare", "mujoco mj_step only (lower bound)", "dt", dt, None,
                                     statistics.median(bare), len(bare), final, maxe, "ok",
                                     "bare mj_step calls, gripper still (time only; error of the full run)",
                                     dt=dt))
            except Exception as exc:   # noqa: BLE001
                rows.append(_row(case, name, name, "dt", dt, None, math.nan, 0, math.nan, math.nan, "failed",
                                 f"{type(exc).__name__}: {exc}", dt=dt))
            if bar is not None:
                bar.update()
    return rows


# ------------------------------------------------------------------ orders and headline

def observed_order(knobs, errors, floor):
    """Least-squares slope of log(error) against log(knob) over the points with
    floor < error < inf (``floor`` a number or one per point); NaN with fewer
    than two such points."""
    k = np.asarray(knobs, dtype=float)
    e = np.asarray(errors, dtype=float)
    f = np.broadcast_to(np.asarray(floor, dtype=float), e.shape)
    sel = np.isfinite(e) & np.isfinite(k) & (e > f) & (k > 0)
    if np.count_nonzero(sel) < 2:
        return math.nan
    return float(np.polyfit(np.log(k[sel]), np.log(e[sel]), 1)[0])


def rounding_floor(case, row, uncertainty=0.0):
    """Error level a run cannot be told from exact at: 10 max(1000, sqrt(steps))
    machine epsilons of the largest |reference| (rounding accumulated over the
    steps as a random walk), or twice the reference's own uncertainty."""
    dt = row["dt"] if isinstance(row["dt"], float) else GRID_DT
    steps = case.t_end / dt
    return max(10.0 * max(1000.0, math.sqrt(steps)) * np.finfo(float).eps * case.scale, 2.0 * uncertainty)


def orders_table(rows, cases):
    """Observed orders per case and line: slope of error vs knob (dt or rtol)
    and vs run time (work-precision slope), for both error measures; points
    at the rounding floor (:func:`rounding_floor`) are left out. For the
    regularised lines also the order in eps: the slope of each line's
    smallest final error against eps."""
    out = []
    lines = []
    for r in rows:
        key = (r["case"], r["line"])
        if key not in lines:
            lines.append(key)
    for cname, line in lines:
        pts = [r for r in rows if r["case"] == cname and r["line"] == line and r["status"] == "ok"]
        if not pts:
            continue
        c = cases[cname]
        floor = [rounding_floor(c, r, c.ref_uncertainty) for r in pts]
        floor_max = [rounding_floor(c, r, c.ref_uncertainty_max) for r in pts]
        kn = [r["value"] for r in pts]
        tm = [r["run_time_s"] for r in pts]
        fe = [r["final_error"] for r in pts]
        me = [r["max_error"] for r in pts]
        out.append(dict(case=cname, line=line, method=pts[0]["method"], knob=pts[0]["knob"],
                        order_final=observed_order(kn, fe, floor), order_max=observed_order(kn, me, floor_max),
                        wp_slope_final=observed_order(tm, fe, floor), wp_slope_max=observed_order(tm, me, floor_max),
                        points=len(pts), points_above_floor=int(np.count_nonzero(np.array(fe) > np.array(floor))),
                        floor=min(floor)))
    for cname in cases:
        reg = [r for r in rows if r["case"] == cname and r["method"] == "regularised" and r["status"] == "ok"]
        eps = sorted({r["eps"] for r in reg})
        if len(eps) >= 2:
            best = [min(r["final_error"] for r in reg if r["eps"] == e) for e in eps]
            bmax = [min(r["max_error"] for r in reg if r["eps"] == e) for e in eps]
            floor = rounding_floor(cases[cname], dict(dt=GRID_DT))
            out.append(dict(case=cname, line="regularised, smallest error vs eps", method="regularised",
                            knob="eps", order_final=observed_order(eps, best, floor),
                            order_max=observed_order(eps, bmax, floor), wp_slope_final=math.nan,
                            wp_slope_max=math.nan, points=len(eps),
                            points_above_floor=int(np.count_nonzero(np.array(best) > floor)), floor=floor))
    return out


EXDEX_LINES = METHODS
#: the exdex side of the engine comparison: the exact-stick methods (not the two baselines)
RATIO_METHODS = ("implicit", "event")


def cheapest(rows, case, error, key="final_error", methods=EXDEX_LINES, time_key="run_time_s"):
    """The exdex run (row) of ``case`` with the least run time (``time_key``)
    whose error is <= ``error``, or None."""
    ok = [r for r in rows if r["case"] == case and r["method"] in methods and r["status"] == "ok"
          and r[key] <= error and np.isfinite(r.get(time_key, math.nan))]
    return min(ok, key=lambda r: r[time_key]) if ok else None


#: which exdex time each engine line is compared with: whole ``exdex.simulate``
#: calls against the engines' driven stepping loops, and the compiled model's
#: C run (``Model.final``) against MuJoCo's bare ``mj_step`` loop
ENGINE_EXDEX_TIME = {"pybullet": "run_time_s", "mujoco": "run_time_s", "drake": "run_time_s",
                     "mujoco bare": "run_time_compiled_s"}


def engine_ratios(rows, case, key="final_error"):
    """Run-time ratios at equal error, per engine line of ``case``: for each engine
    point, engine time / time of the cheapest exdex run at least as accurate
    (exdex time per :data:`ENGINE_EXDEX_TIME`)."""
    out = []
    for eng, tkey in ENGINE_EXDEX_TIME.items():
        pts = [r for r in rows if r["case"] == case and r["method"] == eng and r["status"] == "ok"]
        for r in pts:
            x = cheapest(rows, case, r[key], key, RATIO_METHODS, tkey)
            out.append(dict(case=case, engine=eng, dt=r["dt"], engine_time_s=r["run_time_s"], engine_error=r[key],
                            exdex_method=x["line"] if x else "", exdex_knob=f"{x['knob']}={x['value']:.3g}" if x else "",
                            exdex_time_s=x[tkey] if x else math.nan,
                            exdex_error=x[key] if x else math.nan,
                            ratio=r["run_time_s"] / x[tkey] if x else math.nan, metric=key))
    return out


def headline(rows, cases, machine, missing):
    """Headline numbers: Fig. 3 to 1e-6 m, ratios vs engines, orders. Returns (text, csv rows)."""
    lines = [f"machine: {machine}", ""]
    recs = []
    best = cheapest(rows, "fig3", 1e-6)
    lines.append("Fig. 3 to 1e-6 m final-displacement error (goal: under 1 ms):")
    fig3_lines = list(dict.fromkeys(r["line"] for r in rows if r["case"] == "fig3" and r["method"] in EXDEX_LINES))
    for line in fig3_lines + [m for m in EXDEX_LINES if m in missing]:
        sub = [r for r in rows if r["line"] == line]
        x = cheapest(sub, "fig3", 1e-6) if sub else None
        if x is None:
            why = "not available" if line in missing else "never reached 1e-6 m in the sweep"
            if sub and line not in missing:
                ok = [r for r in sub if r["case"] == "fig3" and r["status"] == "ok"]
                if ok:
                    b = min(ok, key=lambda r: r["final_error"])
                    why += f" (best {b['final_error']:.2e} m at {b['knob']} = {b['value']:.3g}, " \
                           f"{1e3 * b['run_time_s']:.2f} ms)"
            lines.append(f"  {line:30s} {why}")
            continue
        lines.append(f"  {x['line']:30s} {x['knob']} = {x['value']:.4g}: {1e3 * x['run_time_s']:.3f} ms, "
                     f"error {x['final_error']:.2e} m")
        recs.append(dict(item="fig3 to 1e-6 m", method=x["line"], knob=x["knob"], value=x["value"],
                         run_time_s=x["run_time_s"], error=x["final_error"], ratio=""))
    if best:
        lines.append(f"  best: {best['line']} ({best['knob']} = {best['value']:.4g}) in "
                     f"{1e3 * best['run_time_s']:.3f} ms -> goal {'met' if best['run_time_s'] < 1e-3 else 'NOT met'}")
    lines.append("")
    lines.append("Run time at equal final-displacement error, engine / exdex (cheapest implicit or event run at "
                 "least as accurate as the engine point; pybullet, mujoco and drake against whole exdex.simulate calls, "
                 "mujoco bare (mj_step only) against the compiled exdex.Model's C run, Model.final):")
    for cname in cases:
        rr = engine_ratios(rows, cname)
        for eng in ("pybullet", "mujoco", "drake", "mujoco bare"):
            pts = [r for r in rr if r["engine"] == eng and np.isfinite(r["ratio"])]
            if not pts:
                continue
            most = min(pts, key=lambda r: r["engine_error"])
            lo = min(pts, key=lambda r: r["ratio"])
            lines.append(f"  {cname:6s} {eng:11s} most accurate point (dt {most['dt']:.3g} s, error "
                         f"{most['engine_error']:.2e}, {1e3 * most['engine_time_s']:.1f} ms) vs {most['exdex_method']} "
                         f"{most['exdex_knob']} ({1e3 * most['exdex_time_s']:.3f} ms): {most['ratio']:.0f}x; "
                         f"smallest ratio over dt: {lo['ratio']:.0f}x")
            recs.append(dict(item=f"{cname} ratio vs {eng} (most accurate engine point)", method=most["exdex_method"],
                             knob=most["exdex_knob"], value=most["dt"], run_time_s=most["exdex_time_s"],
                             error=most["engine_error"], ratio=most["ratio"]))
            recs.append(dict(item=f"{cname} ratio vs {eng} (smallest over engine dt)", method=lo["exdex_method"],
                             knob=lo["exdex_knob"], value=lo["dt"], run_time_s=lo["exdex_time_s"],
                             error=lo["engine_error"], ratio=lo["ratio"]))
    lines.append("")
    lines.append("Observed orders (slope of log error vs log dt or log rtol; work-precision slope vs log run time):")
    for o in orders_table(rows, cases):
        if o["method"] not in EXDEX_LINES and o["method"] not in ENGINES:
            continue
        if o["points_above_floor"] == 0:
            lines.append(f"  {o['case']:6s} {o['line']:30s} exact to rounding: every final error at the "
                         f"rounding floor ({o['points']} points)")
            continue
        if o["knob"] == "eps":
            lines.append(f"  {o['case']:6s} {o['line']:30s} order in eps, final: {o['order_final']:5.2f}   "
                         f"max: {o['order_max']:5.2f}")
            continue
        lines.append(f"  {o['case']:6s} {o['line']:30s} final: {o['order_final']:5.2f} (wp {o['wp_slope_final']:5.2f})"
                     f"   max: {o['order_max']:5.2f} (wp {o['wp_slope_max']:5.2f})   "
                     f"[{o['points_above_floor']}/{o['points']} points above floor {o['floor']:.0e}]")
    if missing:
        lines.append("")
        lines.append("not available in this build (left out): " + ", ".join(sorted(missing)))
    return "\n".join(lines), recs


# ------------------------------------------------------------------ work-precision chart

_STYLE = {"implicit": dict(color="C0", marker="o"), ALIGNED_LINE: dict(color="C0", marker="o", mfc="none", ls="-."),
          "explicit": dict(color="C3", marker="v"),
          "event": dict(color="C2", marker="D"), "pybullet": dict(color="k", marker="s", ls="--"),
          "mujoco": dict(color="C4", marker="^", ls="--"), "drake": dict(color="C9", marker="P", ls="--"),
          "mujoco bare": dict(color="C4", marker="^", ls=":", mfc="none")}


#: errors at or below ROUNDING x max|reference| are rounding: "exact to rounding"
ROUNDING = 1e-12


def _log_axes(ax, floor, decades=4):
    """Log axes that cannot zoom into rounding noise: at least ``decades`` decades
    in y, labels on the decades only (no crowded minor labels)."""
    ticker = require("matplotlib.ticker", "exdex.studies.bench's figures")
    LogLocator, NullFormatter = ticker.LogLocator, ticker.NullFormatter

    lo, hi = ax.get_ylim()
    lo = max(lo, 0.5 * floor)
    if hi / lo < 10.0**decades:
        hi = lo * 10.0**decades
    ax.set_ylim(lo, hi)
    for axis in (ax.xaxis, ax.yaxis):
        axis.set_major_locator(LogLocator(base=10.0, numticks=8))
        axis.set_minor_locator(LogLocator(base=10.0, subs=np.arange(2, 10) * 0.1, numticks=12))
        axis.set_minor_formatter(NullFormatter())
    ax.grid(True, which="major", lw=0.3)
    ax.tick_params(labelsize=7)


def _rounding_panel(ax, rows, key, case, what):
    """A panel whose every error is rounding, said in words instead of plotted."""
    worst = max(r[key] for r in rows)
    lines = list(dict.fromkeys(r["line"] for r in rows))
    ax.set_xticks([])
    ax.set_yticks([])
    for side in ax.spines.values():
        side.set_color("0.8")
    ax.text(0.5, 0.5, f"{what}:\nexact to rounding\n\nevery run of every line\n"
            f"at or below {worst:.0e} {case.unit}\n({ROUNDING:g} x max|reference| = {ROUNDING * case.scale:.0e})"
            f"\n\n" + "\n".join(lines), transform=ax.transAxes, ha="center", va="center", fontsize=7,
            color="0.25")


def plot_work_precision(rows, cases, path, machine, missing):
    """The work-precision chart (see the module docstring) of sweep rows, saved to ``path``."""
    plt = pyplot("exdex.studies.bench.plot_work_precision", backend="Agg")

    names = list(cases)
    fig, axes = plt.subplots(2, len(names), figsize=(4.6 * len(names), 8.6), squeeze=False)
    reg_lines = sorted({r["line"] for r in rows if r["method"] == "regularised"})
    oranges = plt.get_cmap("Oranges")
    for j, cname in enumerate(names):
        c = cases[cname]
        for i, key in enumerate(("final_error", "max_error")):
            ax = axes[i, j]
            floor = FLOOR * c.scale
            what = "final-displacement error" if i == 0 else "max abs trajectory error"
            if i == 0:
                ax.set_title(f"{c.title}\nreference: {c.ref_label}", fontsize=8)
            ok = [r for r in rows if r["case"] == cname and r["status"] == "ok" and np.isfinite(r[key])]
            if ok and max(r[key] for r in ok) <= ROUNDING * c.scale:
                # every run is exact to rounding: a plot would show only rounding noise
                _rounding_panel(ax, ok, key, c, what)
                continue
            lines = []
            for r in rows:
                if r["case"] == cname and r["line"] not in lines:
                    lines.append(r["line"])
            for line in lines:
                pts = [r for r in rows if r["case"] == cname and r["line"] == line and r["status"] == "ok"]
                if not pts:
                    continue
                method = pts[0]["method"]
                if method == "regularised":
                    k = reg_lines.index(line)
                    st = dict(color=oranges(0.45 + 0.5 * k / max(1, len(reg_lines) - 1)), marker="x")
                else:
                    st = dict(_STYLE.get(line, _STYLE.get(method, {})))
                ls = st.pop("ls", "-")
                x = np.array([r["run_time_s"] for r in pts])
                y = np.maximum(np.array([r[key] for r in pts]), floor)
                ax.loglog(x, y, ls=ls, lw=1.2, ms=4, label=line, **st)
                if method in ENGINES:
                    for r, xx, yy in zip(pts, x, y):
                        ax.annotate(f"{1e3 * r['dt']:.2g}", (xx, yy), fontsize=6, xytext=(2, 2),
                                    textcoords="offset points", color=st.get("color", "k"))
            if c.ref_uncertainty > 0 or c.ref_uncertainty_max > 0:
                u = c.ref_uncertainty if i == 0 else c.ref_uncertainty_max
                ax.axhspan(floor, max(u, floor), color="0.85", zorder=0, label="reference uncertainty")
            if cname == "fig3" and i == 0:
                ax.axhline(1e-6, color="0.5", lw=0.8, ls=":")
                ax.axvline(1e-3, color="0.5", lw=0.8, ls=":")
                ax.text(1e-3, 1e-6, " goal: 1e-6 m in 1 ms", fontsize=7, color="0.35", va="bottom", ha="left")
            ax.set_ylabel(f"{what} [{c.unit}]", fontsize=8)
            ax.set_xlabel("run time (median wall) [s]", fontsize=8)
            if i == 0 and c.unsupported:
                ax.text(0.02, 0.02, "not supported for this scene (simulate raises ValueError):\n"
                        + ", ".join(c.unsupported), transform=ax.transAxes, fontsize=6, color="0.3")
            _log_axes(ax, floor)
            ev = [r for r in rows if r["case"] == cname and r["method"] == "event" and r["status"] == "ok"]
            if ev and max(r[key] for r in ev) <= ROUNDING * c.scale:
                # just above the event points (the y range spans >= 4 decades, so this stays
                # inside the axes, clear of the title)
                ax.annotate("event: every rtol, exact to rounding",
                            (min(r["run_time_s"] for r in ev), max(floor, max(r[key] for r in ev))),
                            xytext=(0, 7), textcoords="offset points", fontsize=6, color="C2", va="bottom")
    handles = {}
    for ax in axes.ravel():
        for h, lab in zip(*ax.get_legend_handles_labels()):
            handles.setdefault(lab, h)
    fig.legend(list(handles.values()), list(handles), loc="lower center", ncol=min(6, len(handles)), fontsize=7,
               frameon=False, bbox_to_anchor=(0.5, 0.03))
    note = (f"machine: {machine}.  Errors below {FLOOR:g} x max|reference| drawn at that floor. "
            "Engine labels: dt in ms. Engine time: stepping loop incl. per-step Python driving; "
            "'mujoco mj_step only': bare steps, a lower bound.")
    if missing:
        note += "\nnot available in exdex.simulate (left out): " + "; ".join(sorted(missing))
    fig.text(0.01, 0.005, note, fontsize=7, va="bottom")
    fig.suptitle("exdex work-precision: error against run time (top: final displacement, "
                 "bottom: max over the 2^-6 s grid)", fontsize=10)
    fig.tight_layout(rect=(0, 0.10, 1, 0.97))
    fig.savefig(path, dpi=110)
    plt.close(fig)


# ------------------------------------------------------------------ stability maps

def stick_intervals(cf, t_end):
    """[(t0, t1)] where the closed form :class:`exdex.paper.PiecewiseMotion` is at rest."""
    segs = list(cf.segments)
    out = []
    for k, (t0, x0, v0, a) in enumerate(segs):
        if v0 == 0.0 and a == 0.0:
            t1 = segs[k + 1][0] if k + 1 < len(segs) else t_end
            if out and abs(out[-1][1] - t0) < 1e-15:
                out[-1] = (out[-1][0], min(t1, t_end))
            else:
                out.append((t0, min(t1, t_end)))
    return [(a, b) for a, b in out if b > a]


def classify(result, cf, t_end, dt, dof, motion_end=None):
    """Classify a run against the closed form ``cf``: (class, details dict).

    ``result`` is an ``exdex.Result``, or an exception raised by the run
    (-> "collapse"). See the module docstring for the classes. ``motion_end``
    (when the gripper stops) only sets ``max_v_after``, a detail.
    """
    det = dict(chatter_sign_changes=0, max_v_stick=math.nan, max_v_after=math.nan, creep_rate=math.nan,
               max_error=math.nan, steps="", events="")
    if isinstance(result, BaseException):
        return "collapse", dict(det, note=f"{type(result).__name__}: {result}")
    t = result.t
    x = result.q[:, 0] - result.q[0, 0]
    v = result.v[:, 0]
    stats = result.stats or {}
    det["steps"] = stats.get("steps", "")
    for key in ("events", "switches", "event_count"):
        if key in stats:
            det["events"] = stats[key]
            if stats[key] > EVENT_BUDGET:
                return "collapse", dict(det, note=f"{key} = {stats[key]} > budget {EVENT_BUDGET}")
    if getattr(result, "method", None) in ADAPTIVE and isinstance(det["steps"], (int, float)) \
            and det["steps"] > STEP_BUDGET * t_end:
        return "collapse", dict(det, note=f"{det['steps']} adaptive steps > {STEP_BUDGET:g} per simulated second")
    if not (np.all(np.isfinite(result.q)) and np.all(np.isfinite(v))):
        return "blow-up", dict(det, note="non-finite state")
    xr, _ = cf(t)
    err = float(np.max(np.abs(x - xr)))
    det["max_error"] = err
    threshold = BLOWUP_FRACTION * float(np.max(np.abs(xr))) + BLOWUP_FLOOR[dof]
    if err > threshold:
        return "blow-up", dict(det, note=f"max error {err:.3g} > {threshold:.3g}")
    margin = max(2.0 * dt, 0.01)
    changes = 0
    vstick = 0.0
    creep = 0.0
    for a, b in stick_intervals(cf, t_end):
        lo, hi = a + margin, (b - margin if b < t_end - 1e-12 else t_end + 1.0)
        sel = (t > lo) & (t < hi)
        vs = v[sel]
        s = np.sign(vs[np.abs(vs) > V_NOISE])
        changes += int(np.count_nonzero(s[1:] != s[:-1]))
        # drift: still moving over the second half of the interval (past any late arrival at rest)
        ts = t[sel]
        if len(ts) >= 2:
            half = ts >= 0.5 * (ts[0] + ts[-1])
            if np.count_nonzero(half) >= 1:
                vstick = max(vstick, float(np.max(np.abs(vs[half]))))
            xh, th = x[sel][half], ts[half]
            if len(th) >= 2 and th[-1] > th[0]:
                creep = max(creep, abs(xh[-1] - xh[0]) / (th[-1] - th[0]))
    det["chatter_sign_changes"] = changes
    det["max_v_stick"] = vstick
    det["creep_rate"] = creep
    if motion_end is not None:
        after = t > motion_end + margin
        if np.any(after):
            det["max_v_after"] = float(np.max(np.abs(v[after])))
    if changes > CHATTER_MIN:
        return "chatter", dict(det, note=f"{changes} sign changes of v while the closed form sticks")
    if vstick > V_NOISE:
        return "drift", dict(det, note=f"|v| up to {vstick:.3g} late in a stick interval, creep {creep:.3g}")
    return "ok", dict(det, note="")


def _family(name):
    """(ratio -> Scene, t_end, label of the ratio, dof, ratio of the paper's grasp)."""
    if name == "fig3":
        f3 = paper.fig3_grip_force()
        w = paper.MASS * paper.G

        def make(ratio, f3=f3, w=w):
            return paper.fig3_scene(grip_force=ratio * w / (paper.MU * paper.FINGERS))
        return make, 1.5, "capacity / weight (mu N / m g)", "translation", paper.MU * paper.FINGERS * f3 / w
    if name == "fig6":
        f3 = paper.fig3_grip_force()
        izz = paper.FIG6["inertia"][2]
        a_h, _ = paper.eq7_accelerations(paper.FIG6["amplitude"], paper.FIG6["duration"], paper.FIG6["beta"])
        e_r = izz * a_h / (paper.MU * paper.FINGERS * f3)

        def make(ratio, f3=f3, e_r=e_r):
            return paper.fig6_scene(grip_force=ratio * f3, e_r=e_r)
        return make, 8.0, "torque capacity / (I_zz a_H)", "rotation", 1.0 + paper.FIG6_MARGIN
    raise ValueError(name)


ADAPTIVE = ("event", "regularised")


def map_grids(quick):
    """Axes of the maps. ``dts`` for the fixed-step methods; ``dts_adaptive``
    (every second one) for event and regularised, where dt only sets the
    output grid."""
    if quick:
        return dict(dts=[2.0 ** -k for k in (5, 8, 11, 14)], dts_adaptive=[2.0 ** -k for k in (5, 11)],
                    ratios=[0.9, 1.1, 2.0, 10.0], eps=[1e-2, 1e-4], families=("fig3",))
    return dict(dts=[2.0 ** -k for k in range(4, 17)], dts_adaptive=[2.0 ** -k for k in range(4, 17, 2)],
                ratios=[0.5, 0.9, 0.99, 1.01, 1.1, 1.5, 2.0, 3.0, 5.0, 10.0, 30.0, 100.0],
                eps=[10.0 ** -k for k in range(1, 8)], families=("fig3", "fig6"))


def map_dts(g, method):
    return g["dts_adaptive"] if method in ADAPTIVE else g["dts"]


def _map_run(scene, t_end, dt, method, eps=None):
    kw = dict(dt=dt, method=method)
    if eps is not None:
        kw["eps"] = eps
    t0 = time.perf_counter()
    try:
        res = simulate(scene, t_end, **kw)
    except Exception as exc:   # noqa: BLE001 - a failure is a class of the map
        res = exc
    return res, time.perf_counter() - t0


def stability_maps(methods, quick, bar=None):
    """Run the maps; returns CSV rows (one per cell)."""
    g = map_grids(quick)
    cap = 0.2 if quick else 1.5        # per-run wall budget: finer dt in the same row is skipped beyond it
    predict_cap = 0.5 if quick else 5.0  # a row predicted (cost ~ 1/eps) to exceed this per run is skipped
    total_cap = 6.0 if quick else 90.0  # per family and method
    rows = []
    for fam in g["families"]:
        make, t_end, rlabel, dof, paper_ratio = _family(fam)
        for method in METHODS:
            axes = [("ratio", r, None) for r in g["ratios"]]
            if method == "regularised":
                axes += [("eps", e, e) for e in g["eps"]]
            spent = 0.0
            last_eps_cost = None   # (eps, median wall of that row): the regularised cost grows like 1/eps
            for axis, yval, eps in axes:
                scene = make(yval if axis == "ratio" else paper_ratio)
                cf = paper.closed_form(scene)
                skip_reason = None if method in methods else "missing"
                if skip_reason is None and eps is not None and last_eps_cost is not None:
                    predicted = last_eps_cost[1] * last_eps_cost[0] / eps
                    if predicted > predict_cap:
                        skip_reason = f"skipped: predicted {predicted:.3g} s per run (cost ~ 1/eps)"
                walls = []
                for dt in sorted(map_dts(g, method), reverse=True):
                    if bar is not None:
                        bar.set_postfix_str(f"{fam} {method} {axis}={yval:.3g} dt={dt:.2g}")
                    row = dict(family=fam, method=method, axis=axis, y=yval, dt=dt,
                               eps=eps if eps is not None else "", ratio=yval if axis == "ratio" else paper_ratio,
                               y_label=rlabel if axis == "ratio" else "eps", wall_s=math.nan,
                               y_label_ratio=f"the paper's grasp, ratio {paper_ratio:.3g}")
                    if skip_reason is None and spent > total_cap:
                        skip_reason = "skipped"
                    if skip_reason is not None:
                        row.update(cls="missing" if skip_reason == "missing" else "skipped", note=skip_reason)
                    else:
                        res, secs = _map_run(scene, t_end, dt, method, eps)
                        spent += secs
                        walls.append(secs)
                        cls, det = classify(res, cf, t_end, dt, dof, scene.motion.end_time)
                        row.update(det)
                        row.update(cls=cls, wall_s=secs)
                        if secs > cap:
                            skip_reason = "skipped"
                    rows.append(row)
                    if bar is not None:
                        bar.update()
                if eps is not None and walls:
                    last_eps_cost = (eps, statistics.median(walls))
    return rows


_CLS_COLOR = {"ok": "#4daf4a", "drift": "#984ea3", "chatter": "#ff7f00", "blow-up": "#e41a1c",
              "collapse": "#333333", "skipped": "#dddddd", "missing": "#ffffff"}
_CLS_CODE = {"ok": "", "drift": "D", "chatter": "C", "blow-up": "B", "collapse": "X", "skipped": "-", "missing": ""}


def plot_maps(rows, family, path, machine, missing):
    """The stability maps of one family (see the module docstring), saved to ``path``."""
    plt = pyplot("exdex.studies.bench.plot_maps", backend="Agg")
    ListedColormap = require("matplotlib.colors", "exdex.studies.bench.plot_maps").ListedColormap
    LegendPatch = require("matplotlib.patches", "exdex.studies.bench.plot_maps").Patch

    panels = [(m, "ratio") for m in METHODS] + [("regularised", "eps")]
    panels = [p for p in panels if any(r["family"] == family and r["method"] == p[0] and r["axis"] == p[1]
                                       for r in rows)]
    fig, axes = plt.subplots(1, len(panels), figsize=(3.6 * len(panels), 4.4), squeeze=False)
    cmap = ListedColormap([_CLS_COLOR[c] for c in CLASSES])
    for ax, (method, axis) in zip(axes[0], panels):
        sub = [r for r in rows if r["family"] == family and r["method"] == method and r["axis"] == axis]
        dts = sorted({r["dt"] for r in sub})
        ys = sorted({r["y"] for r in sub})
        img = np.zeros((len(ys), len(dts)))
        for r in sub:
            i, j = ys.index(r["y"]), dts.index(r["dt"])
            img[i, j] = CLASSES.index(r["cls"])
            code = _CLS_CODE[r["cls"]]
            if r["cls"] == "drift" and isinstance(r.get("creep_rate"), float) and r["creep_rate"] > 0:
                code = f"{math.log10(r['creep_rate']):.0f}"
            if code:
                ax.text(j, i, code, ha="center", va="center", fontsize=5.5,
                        color="w" if r["cls"] in ("collapse", "drift", "blow-up") else "k")
        ax.imshow(img, cmap=cmap, vmin=-0.5, vmax=len(CLASSES) - 0.5, origin="lower", aspect="auto",
                  interpolation="nearest")
        ax.set_xticks(range(len(dts)))
        ax.set_xticklabels([f"{-math.log2(d):.0f}" for d in dts], fontsize=6)
        ax.set_yticks(range(len(ys)))
        ax.set_yticklabels([f"{y:g}" for y in ys], fontsize=6)
        ax.set_xlabel("dt = 2^-m s (m)", fontsize=7)
        ax.set_ylabel(sub[0]["y_label"] if sub else axis, fontsize=7)
        title = f"{method}" + (f" over (dt, eps)\nat {sub[0]['y_label_ratio']}" if axis == "eps" and sub else "")
        if method in missing:
            title += "\nnot available"
        ax.set_title(title, fontsize=8)
    handles = [LegendPatch(facecolor=_CLS_COLOR[c], edgecolor="k", lw=0.3, label=c) for c in CLASSES]
    fig.legend(handles=handles, loc="lower center", ncol=len(CLASSES), fontsize=7, frameon=False)
    fig.suptitle(f"stability map, {family} family (codes: C chatter, B blow-up, X step collapse, "
                 f"number = log10 creep rate of a drift; {machine.split(',')[0]})", fontsize=8)
    fig.tight_layout(rect=(0, 0.07, 1, 0.95))
    fig.savefig(path, dpi=110)
    plt.close(fig)


def map_summary(rows):
    """Per family, method and axis: counts of each class and the failure boundary
    in dt (largest dt that is ok / smallest dt that fails) per row."""
    lines = []
    keys = []
    for r in rows:
        k = (r["family"], r["method"], r["axis"])
        if k not in keys:
            keys.append(k)
    for fam, method, axis in keys:
        sub = [r for r in rows if (r["family"], r["method"], r["axis"]) == (fam, method, axis)]
        counts = {c: sum(1 for r in sub if r["cls"] == c) for c in CLASSES}
        cstr = ", ".join(f"{c} {n}" for c, n in counts.items() if n)
        lines.append(f"{fam} {method} over (dt, {axis}): {cstr}")
        if counts["missing"] == len(sub):
            continue
        for y in sorted({r["y"] for r in sub}):
            rr = sorted([r for r in sub if r["y"] == y], key=lambda r: r["dt"])
            classes = [r["cls"] for r in rr]
            if all(c == "ok" for c in classes):
                continue
            fails = [r for r in rr if r["cls"] not in ("ok", "skipped", "missing")]
            oks = [r for r in rr if r["cls"] == "ok"]
            desc = " ".join(f"{_CLS_CODE[c] or 'o'}" for c in classes)
            extra = ""
            if fails:
                worst = {}
                for r in fails:
                    worst[r["cls"]] = worst.get(r["cls"], 0) + 1
                extra = ", ".join(f"{c} x{n}" for c, n in worst.items())
                fmin = min(r["dt"] for r in fails)
                extra += f"; smallest failing dt {fmin:.3g} s"
            if oks:
                extra += f"; largest ok dt {max(r['dt'] for r in oks):.3g} s"
            creep = [r["creep_rate"] for r in rr if r["cls"] == "drift" and isinstance(r.get("creep_rate"), float)]
            if creep:
                extra += f"; creep rate {min(creep):.2g}..{max(creep):.2g}"
            lines.append(f"    {axis} = {y:g}: [{desc}] (finest dt first) {extra}")
    return "\n".join(lines)


# ------------------------------------------------------------------ CSV

def write_csv(path, rows, fields=None):
    fields = fields or list(dict.fromkeys(k for r in rows for k in r))
    with open(path, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=fields, extrasaction="ignore")
        w.writeheader()
        for r in rows:
            w.writerow({k: ("%.6g" % v if isinstance(v, float) else v) for k, v in r.items()})


# ------------------------------------------------------------------ command

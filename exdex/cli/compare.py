"""``exdex compare``: the paper cases and the planar case in exdex and the three engines.

Each case (Figs. 3, 4 and 6 of :mod:`exdex.paper`, the planar case of
:func:`exdex.studies.bench.planar_scene`, and ``incline``: a block sliding down an
inclined frictional stop, :func:`incline_scene`, shown as its slide along the
incline with its closed form) runs in exdex and in every engine setting
(:func:`exdex.engines.run_pybullet`, :func:`exdex.engines.run_mujoco`,
:func:`exdex.engines.run_drake`); rotation and planar cases also run the
friction-model ablation (:func:`exdex.engines.ablation`). Writes
``<case>_compare.csv``, ``<case>_compare.png``, ``<case>_ablation.png`` and
``compare_table.txt`` to ``--out`` and prints the table.
"""
from __future__ import annotations

import math
import os
import time

import numpy as np

from exdex._optional import pyplot, require
from exdex.cli.dispatch import require_engines
from exdex.engines import (DRAKE_APPROXIMATIONS, DRAKE_CONTACT_MODELS, ablation, drift_rate, run_drake, run_mujoco,
                           run_pybullet)
from exdex.scene import Body, Grasp, Patch, Scene, Stop
from exdex.simulate import simulate

__all__ = ["add_arguments", "run", "ablation_colors", "CASES", "incline_scene", "incline_closed_form"]


CASES = ("fig3", "fig4", "fig6", "planar", "incline")

INCLINE_ALPHA = 0.4      # incline of the stop from the horizontal [rad]
INCLINE_T = 0.6          # simulated time of the incline case [s]


def incline_scene(mu_s: float = 0.3, cap: float = 0.09, m: float = 0.1, a: float = 0.2,
                  patch: float = 0.08) -> Scene:
    """A square block (side ``a`` [m], mass ``m`` [kg]) resting with a face flush
    on a stop inclined by 0.4 rad, friction ``mu_s``, gripper at rest, plate
    capacity ``cap`` = 2 mu F [N] (mu 0.5), pads of side ``patch`` [m]."""
    n_b = np.array([-math.sin(INCLINE_ALPHA), math.cos(INCLINE_ALPHA)])
    p_b = -0.5 * a * n_b
    return Scene(body=Body.box(m, (a, a, 0.02)),
                 grasp=Grasp(mu=0.5, grip_force=cap, patch=Patch.rectangle(patch, patch)),
                 dof="planar", q0=(0.0, 0.0, INCLINE_ALPHA),
                 stops=(Stop((p_b[0], 0.0, p_b[1]), (n_b[0], 0.0, n_b[1]), mu=mu_s),))


def incline_closed_form(scene: Scene, t: np.ndarray) -> np.ndarray:
    """Slide [m] down the incline of :func:`incline_scene` at the times t (Coulomb,
    rigid): 0 if m g sin(alpha - atan mu_s) <= cap, else a t^2 / 2 with
    a = g sin(alpha) - mu_s g cos(alpha) - cap / m."""
    m, g = scene.body.mass, float(np.linalg.norm(scene.gravity))
    mu_s, cap = scene.stops[0].mu, scene.grasp.capacity
    t = np.asarray(t, dtype=float)
    if m * g * math.sin(INCLINE_ALPHA - math.atan(mu_s)) <= cap:
        return np.zeros_like(t)
    acc = g * math.sin(INCLINE_ALPHA) - mu_s * g * math.cos(INCLINE_ALPHA) - cap / m
    return 0.5 * acc * t * t


def _case_scenes(names):
    """The paper scenes (exdex.paper) and the planar case of ``exdex bench``: {name: scene}."""
    from exdex.studies import paper

    out = {}
    for name in names:
        if name == "planar":
            from exdex.studies.bench import planar_scene

            out[name] = planar_scene()
        elif name == "incline":
            out[name] = incline_scene()
        else:
            out[name] = getattr(paper, f"{name}_scene")()
    return out


def _is_incline(scene):
    return scene.dof == "planar" and len(scene.stops) == 1 and scene.stops[0].mu > 0


def _unit(scene):
    """Display scale and unit of the shown coordinate (see ``_disp``)."""
    if _is_incline(scene):
        return 1e3, "mm"
    return (180.0 / math.pi, "deg") if scene.dof in ("rotation", "planar") else (1e3, "mm")


def _disp(res):
    """The coordinate shown for a result: the free one of a 1-DoF scene, theta of
    a planar one, the slide down the stop of the incline case."""
    if _is_incline(res.scene):
        u = np.array([math.cos(INCLINE_ALPHA), math.sin(INCLINE_ALPHA)])
        return -(res.q[:, :2] - res.q[0, :2]) @ u
    return res.displacement[:, 2 if res.scene.dof == "planar" else 0]


def _drift(res, col):
    """Mean rate of the shown coordinate after the motion (drift_rate's window)."""
    if not _is_incline(res.scene):
        return drift_rate(res)[col]
    d = _disp(res)
    i = int(np.searchsorted(res.t, res.scene.motion.end_time + 0.1 - 1e-12))
    return (d[-1] - d[i]) / (res.t[-1] - res.t[i])


def _variants(args):
    """(label, function, settings) for every engine run of a case."""
    mj = dict(dt=args.mujoco_dt, cone=args.mujoco_cone, impratio=args.impratio,
              noslip_iterations=args.noslip, iterations=args.mujoco_iterations, contact=args.contact)
    pyb = dict(dt=args.pybullet_dt, iterations=args.pybullet_iterations, cone=not args.no_cone,
               contact=args.contact)
    dr = dict(dt=args.drake_dt, contact_model=args.drake_contact, approximation=args.drake_approximation,
              stiction_tolerance=args.stiction_tolerance, contact=args.contact)
    runs = [("pybullet", run_pybullet, pyb), ("mujoco", run_mujoco, mj), ("drake", run_drake, dr)]
    if args.variants:
        other = "hydroelastic" if args.drake_contact == "point" else "point"
        runs += [
            ("pybullet point+spin", run_pybullet, dict(pyb, contact="point")),
            ("pybullet no cone", run_pybullet, dict(pyb, cone=False)),
            ("mujoco pyramidal", run_mujoco, dict(mj, cone="pyramidal")),
            ("mujoco impratio 10", run_mujoco, dict(mj, impratio=10.0)),
            ("mujoco noslip 20", run_mujoco, dict(mj, noslip_iterations=20)),
            ("mujoco point+torsion", run_mujoco, dict(mj, contact="point")),
            (f"drake {other}", run_drake, dict(dr, contact_model=other)),
            ("drake sap", run_drake, dict(dr, approximation="sap")),
            ("drake stiction 1e-6", run_drake, dict(dr, stiction_tolerance=1e-6)),
        ]
    return runs


def add_arguments(parser):
    """Options of ``exdex compare``."""
    parser.add_argument("--out", default="exdex-output/compare", help="output folder (default: %(default)s)")
    parser.add_argument("--cases", nargs="+", choices=CASES, default=list(CASES), help="paper cases to run")
    parser.add_argument("--settle", type=float, default=1.0,
                        help="time simulated after the gripper stops, for the drift [s] (default: %(default)s)")
    parser.add_argument("--dt", type=float, default=1e-3, help="exdex time step [s] (default: %(default)s)")
    parser.add_argument("--contact", choices=("pads", "point"), default="pads",
                        help="engine contact model (default: %(default)s)")
    parser.add_argument("--pybullet-dt", type=float, default=1 / 240, help="pybullet step [s] (default 1/240)")
    parser.add_argument("--pybullet-iterations", type=int, default=50, help="pybullet solver iterations (50)")
    parser.add_argument("--no-cone", action="store_true", help="pybullet: disable cone friction (square pyramid)")
    parser.add_argument("--mujoco-dt", type=float, default=0.002, help="MuJoCo step [s] (default 0.002)")
    parser.add_argument("--mujoco-iterations", type=int, default=100, help="MuJoCo solver iterations (100)")
    parser.add_argument("--mujoco-cone", choices=("elliptic", "pyramidal"), default="elliptic",
                        help="MuJoCo friction cone (default: %(default)s; MuJoCo's own default is pyramidal)")
    parser.add_argument("--impratio", type=float, default=1.0, help="MuJoCo impratio (default 1)")
    parser.add_argument("--noslip", type=int, default=0, help="MuJoCo noslip iterations (default 0)")
    parser.add_argument("--drake-dt", type=float, default=1e-3, help="Drake step [s] (default 0.001)")
    parser.add_argument("--drake-contact", choices=DRAKE_CONTACT_MODELS, default="point",
                        help="Drake contact model (default: %(default)s)")
    parser.add_argument("--drake-approximation", choices=DRAKE_APPROXIMATIONS, default="lagged",
                        help="Drake discrete contact approximation (default: %(default)s, Drake's own)")
    parser.add_argument("--stiction-tolerance", type=float, default=1e-4,
                        help="Drake stiction tolerance [m/s] (default 1e-4, Drake's own)")
    parser.add_argument("--no-variants", dest="variants", action="store_false",
                        help="skip the refined/altered engine settings (point contact, cone, noslip, ...)")
    parser.add_argument("--no-plots", dest="plots", action="store_false", help="write no figures")
    parser.add_argument("--no-progress", action="store_true", help="print no line per run (the table only)")


def _figure(path, name, scene, ref, runs, scale, unit):
    plt = pyplot("exdex compare's figures", backend="Agg")

    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(7, 6.5), sharex=True)
    colors = ablation_colors((), [r[0] for r in runs])
    ax1.plot(ref.t, scale * _disp(ref), "k-", lw=2, label="exdex")
    for label, res, on_ref in runs:
        ax1.plot(res.t, scale * _disp(res), lw=1.2, color=colors[label], ls=_engine_ls(label), label=label)
        ax2.semilogy(ref.t, np.maximum(scale * np.abs(on_ref - _disp(ref)), 1e-9), lw=1.2, color=colors[label],
                     ls=_engine_ls(label), label=label)
    end = scene.motion.end_time
    for ax in (ax1, ax2):
        ax.axvline(end, color="0.6", ls=":", lw=1)
    ax1.set_ylabel(f"relative displacement [{unit}]")
    ax1.set_title(f"{name}: (a) object relative to the gripper")
    ax1.legend(fontsize=7, ncol=2)
    ax2.set_ylabel(f"|engine - exdex| [{unit}]")
    ax2.set_xlabel("t [s]")
    ax2.set_title("(b) absolute difference from exdex")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def ablation_colors(models, engine_labels):
    """{label: colour}: one colour per exdex model ("exdex <model>") and per engine
    run, none shared: models from matplotlib's tab10, engine runs from Dark2
    then Set1 (17 colours, none of them in tab10)."""
    matplotlib = require("matplotlib", "exdex compare's figures")

    a = matplotlib.colormaps["tab10"].colors
    b = list(matplotlib.colormaps["Dark2"].colors) + list(matplotlib.colormaps["Set1"].colors)
    cols = {f"exdex {m}": a[i % len(a)] for i, m in enumerate(models)}
    cols.update({lab: b[i % len(b)] for i, lab in enumerate(engine_labels)})
    return cols


def _engine_ls(label):
    """Line style of an engine run: pybullet dashed, MuJoCo dash-dot, Drake dotted."""
    return {"pybullet": "--", "mujoco": "-.", "drake": ":"}.get(label.split()[0], "-")


def _ablation_figure(path, name, scene, ref, ab, engine_runs, scale, unit):
    plt = pyplot("exdex compare's figures", backend="Agg")

    colors = ablation_colors(list(ab), [r[0] for r in engine_runs])
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11.5, 4.6), gridspec_kw=dict(width_ratios=[1.4, 1]))
    for model, (res, _) in ab.items():
        ax1.plot(res.t, scale * _disp(res), lw=2 if model == "ellipsoid" else 1.2,
                 ls="-" if model == "ellipsoid" else "--", color=colors[f"exdex {model}"], label=f"exdex {model}")
    for label, res, _ in engine_runs:
        ax1.plot(res.t, scale * _disp(res), lw=1.2, ls=_engine_ls(label), color=colors[label], label=label)
    ax1.set_xlabel("t [s]")
    ax1.set_ylabel(f"relative displacement [{unit}]")
    kind = "" if scene.dof == "rotation" else " (equivalent e_r: approximate in planar scenes)"
    ax1.set_title(f"{name}: friction-model ablation{kind}", fontsize=9)
    ax1.legend(fontsize=6, ncol=2)
    labels = [f"exdex {m}" for m in ab] + [r[0] for r in engine_runs]
    finals = [scale * _disp(r)[-1] for r, _ in ab.values()] + \
             [scale * _disp(r)[-1] for _, r, _ in engine_runs]
    ax2.barh(range(len(labels)), finals, color=[colors[lab] for lab in labels],
             hatch=None, edgecolor=["none"] * len(ab) + ["k"] * len(engine_runs))
    ax2.set_yticks(range(len(labels)))
    ax2.set_yticklabels(labels, fontsize=7)
    ax2.invert_yaxis()
    ax2.set_xlabel(f"final displacement [{unit}]")
    ax2.set_title("exdex models (no edge) and engines (black edge)", fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def run(args):
    """``exdex compare``: every case in exdex and the three engines, figures, CSV and a table."""
    status = require_engines("compare")
    if status:
        return status
    say = (lambda *a, **k: None) if getattr(args, "no_progress", False) else print  # noqa: E731

    os.makedirs(args.out, exist_ok=True)
    scenes = _case_scenes(args.cases)
    rows = []
    for name, scene in scenes.items():
        scale, unit = _unit(scene)
        col = 2 if scene.dof == "planar" else 0
        # the incline slides without bound: a fixed time keeps the block on the pads
        t_end = INCLINE_T if name == "incline" else scene.motion.end_time + args.settle
        t0 = time.perf_counter()
        ref = simulate(scene, t_end, dt=args.dt)
        rows.append((name, "exdex (ellipsoid)", scale * _disp(ref)[-1], scale * _drift(ref, col), 0.0,
                     time.perf_counter() - t0, unit))
        say(f"[{name}] exdex: {rows[-1][2]:.3f} {unit} ({rows[-1][5]:.2f} s)", flush=True)
        variants = _variants(args)
        if name == "incline":
            cf = incline_closed_form(scene, ref.t)
            i = int(np.searchsorted(ref.t, scene.motion.end_time + 0.1 - 1e-12))
            rows.append((name, "closed form (Coulomb)", scale * cf[-1], scale * (cf[-1] - cf[i]) / (ref.t[-1] - ref.t[i]),
                         scale * float(np.max(np.abs(cf - _disp(ref)))), float("nan"), unit))
            dr = next(v[2] for v in variants if v[0] == "drake")
            variants = variants + [("drake stop corners", run_drake, dict(dr, stop_contact="corners"))]
        runs = []
        for label, fn, settings in variants:
            res = fn(scene, t_end, **settings)
            on_ref = np.interp(ref.t, res.t, _disp(res))
            err = float(np.max(np.abs(on_ref - _disp(ref))))
            runs.append((label, res, on_ref))
            rows.append((name, label, scale * _disp(res)[-1], scale * _drift(res, col), scale * err,
                         res.stats["wall_time"], unit))
            say(f"[{name}] {label}: {rows[-1][2]:.3f} {unit}, drift {rows[-1][3]:.4g} {unit}/s "
                  f"({rows[-1][5]:.2f} s)", flush=True)
        # CSV of the main curves on exdex's time grid
        cols = [ref.t, scale * _disp(ref)] + [r[2] * scale for r in runs]
        header = "t_s,exdex_" + unit + "," + ",".join(f"{r[0].replace(' ', '_')}_{unit}" for r in runs)
        np.savetxt(os.path.join(args.out, f"{name}_compare.csv"), np.column_stack(cols), delimiter=",",
                   header=header, comments="")
        if args.plots:
            _figure(os.path.join(args.out, f"{name}_compare.png"), name, scene, ref, runs, scale, unit)
        if scene.dof in ("rotation", "planar") and name != "incline":   # the ablation concerns the plates' torque
            ab = ablation(scene, t_end, dt=args.dt)
            for model, (res, value) in ab.items():
                rows.append((name, f"ablation {model} ({'mu' if scene.dof == 'translation' else 'e_r'}="
                                   f"{value:.4g})", scale * _disp(res)[-1], scale * drift_rate(res)[col],
                             float("nan"), float("nan"), unit))
            if args.plots:
                _ablation_figure(os.path.join(args.out, f"{name}_ablation.png"), name, scene, ref, ab,
                                 runs[:3] + [r for r in runs if any(w in r[0] for w in ("point", "cone", "noslip", "hydro"))],
                                 scale, unit)
    cw = max([6] + [len(r[0]) for r in rows])  # the case column fits the longest case name
    lines = [f"{'case':{cw}s} {'model':40s} {'final':>10s} {'drift/s':>11s} {'max|diff|':>10s} {'wall [s]':>8s}  unit"]
    cell = lambda v, fmt, w: f"{v:{w}{fmt}}" if np.isfinite(v) else f"{'-':>{w}s}"  # noqa: E731
    for name, label, final, drift, err, wall, unit in rows:
        lines.append(f"{name:{cw}s} {label:40s} {cell(final, '.3f', 10)} {cell(drift, '.4g', 11)} "
                     f"{cell(err, '.3f', 10)} {cell(wall, '.2f', 8)}  {unit}")
    lines.append("final: displacement at the end [unit]; drift/s: mean rate after the motion [unit/s]; "
                 "max|diff|: largest gap to exdex [unit]; planar cases show the rotation, incline the slide "
                 "down the stop")
    table = "\n".join(lines)
    print(table)
    with open(os.path.join(args.out, "compare_table.txt"), "w") as fh:
        fh.write(table + "\n")
    return 0

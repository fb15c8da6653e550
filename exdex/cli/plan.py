"""``exdex plan``: plan the gripper motion or grip for a target in-hand outcome.

Scans a parameter of a paper case or a scene file in a batch and solves to
``--tol`` (:func:`exdex.plan.solve`), prints the plan and its outcome band,
and writes ``gripper_poses.csv`` (the poses a robot controller consumes,
:meth:`exdex.plan.Plan.gripper_poses`), ``planned_scene.toml`` and, with
matplotlib, ``plan.png`` to ``--out``. With ``--pose`` (a planar scene file)
it plans a planar pose by a sequence of motion primitives
(:func:`exdex.sequence.solve`) and writes the sequence's poses and one scene
file per step.
"""
from __future__ import annotations

import math
import os

import numpy as np

from exdex.studies import paper
from exdex._optional import pyplot
from exdex.io import load_scene, load_simulate_options, save_scene
from exdex.scene import METHODS
from exdex.design.plan import (QUANTITIES, QUANTITY_HELP, Limits, UnreachableTargetError, motion_peaks,
                               parameter_unit, peak_units, solve)

__all__ = ["add_arguments", "run"]


def _kv(text, what):
    try:
        k, v = text.split("=", 1)
        return k.strip(), v.strip()
    except ValueError:
        raise SystemExit(f"exdex plan: {what} must look like name=value, got {text!r}") from None


def _interval(text, what):
    k, v = _kv(text, what)
    try:
        lo, hi = (float(x) for x in v.split(":"))
    except ValueError:
        raise SystemExit(f"exdex plan: {what} must look like name=low:high, got {text!r}") from None
    return k, (lo, hi)


def add_arguments(parser):
    parser.description = ("Plan the gripper motion or grip for a target in-hand outcome: scan a parameter in a "
                          "batch, solve to tol, print the plan and its outcome band, write a figure and the "
                          "gripper poses (CSV) a robot controller consumes.")
    src = parser.add_mutually_exclusive_group()
    src.add_argument("--case", choices=("fig3", "fig4", "fig6"), default="fig3",
                     help="a paper case as the base scene (default fig3)")
    src.add_argument("--scene", help="a scene file (TOML or JSON, exdex.save_scene) as the base scene; its "
                     "[simulate] table gives t_end, dt, method, friction_solver, rtol, atol and eps (the options "
                     "below override them)")
    parser.add_argument("--scene-format", choices=("toml", "json"), default=None,
                        help="format of the --scene file when its extension does not say (.toml, .json)")
    parser.add_argument("--target", default="slip=-0.015",
                        help="quantity=value, quantity one of: "
                             + "; ".join(f"{k}: {v}" for k, v in QUANTITY_HELP.items())
                             + " (default slip=-0.015: slide 15 mm down)")
    parser.add_argument("--pose", default=None,
                        help="a planar pose target x=..,y=..,rotation=.. (m, m, rad; any of them) for a planar "
                             "--scene: planned by a sequence of motion primitives (exdex.sequence.solve) instead "
                             "of --target/--vary; --uncertain then gives its sampled band")
    parser.add_argument("--vary", default="grip_force=1.0:3.0",
                        help="parameter=low:high (default grip_force=1.0:3.0)")
    parser.add_argument("--uncertain", action="append", default=[],
                        help="parameter=low:high known only within the interval (repeatable): plan for the "
                             "worst case and report the band")
    parser.add_argument("--rest-by", type=float, default=None,
                        help="time [s] by which the object must be at rest relative to the gripper")
    parser.add_argument("--tol", type=float, default=1e-6, help="tolerance on the outcome (default 1e-6)")
    parser.add_argument("--t-end", type=float, default=None,
                        help="simulated time [s] (default: the scene file's simulate.t_end, else the end of the "
                             "motion and of the grip schedule x 1.5)")
    parser.add_argument("--dt", type=float, default=None,
                        help="output step [s] (default: the scene file's simulate.dt, else the planner's)")
    parser.add_argument("--method", default=None, choices=sorted(METHODS) + ["auto"],
                        help="integration method (default: the scene file's simulate.method, else auto)")
    parser.add_argument("--max-acceleration", type=float, default=None, help="robot limit [m/s^2 or rad/s^2]")
    parser.add_argument("--max-speed", type=float, default=None, help="robot limit [m/s or rad/s]")
    parser.add_argument("--rate", type=float, default=100.0, help="rate of the exported poses [Hz] (default 100)")
    parser.add_argument("--out", default="exdex-output/plan", help="output folder (default exdex-output/plan)")
    parser.add_argument("--no-progress", action="store_true", help="accepted for symmetry (a plan takes ms)")


def _write_poses(args, t, poses):
    csv_path = os.path.join(args.out, "gripper_poses.csv")
    np.savetxt(csv_path, np.column_stack([t, poses]), delimiter=",", header="t,x,y,z,qw,qx,qy,qz", comments="",
               fmt="%.17g")
    print(f"wrote {csv_path} ({len(t)} poses at {args.rate:g} Hz)")


def _run_pose(args, scene):
    import math
    import warnings
    from exdex.design import sequence
    if scene.dof != "planar":
        raise SystemExit(f"exdex plan: --pose needs a planar scene (--scene FILE with dof = 'planar'), got a "
                         f"{scene.dof} scene")
    target = {}
    for item in args.pose.split(","):
        k, v = _kv(item, "--pose")
        try:
            target[k] = float(v)
        except ValueError:
            raise SystemExit(f"exdex plan: --pose values must be numbers, got {item!r}") from None
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            p = sequence.solve(scene, target)
    except UnreachableTargetError as exc:
        print(f"exdex plan: {exc}")
        return 1
    except ValueError as exc:
        raise SystemExit(f"exdex plan: {exc}") from None
    os.makedirs(args.out, exist_ok=True)
    print("plan: " + " -> ".join(f"{n}({v:.6g} {u})" for (n, v), u in zip(p.steps, p.step_units())))
    for k in p.targets:
        u, f = ("deg", 180.0 / math.pi) if k == "rotation" else ("mm", 1e3)
        print(f"  {k}: {f * p.achieved[k]:.6g} {u} (target {f * p.targets[k]:g} {u}, residual "
              f"{f * p.residuals[k]:.2e} {u}, tol {f * p.tol[k]:g} {u})")
    if args.uncertain:
        unc = dict(_interval(u, "--uncertain") for u in args.uncertain)
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            b = sequence.band(p, unc, n=5)
        for k, (lo, hi) in b.items():
            u, f = ("deg", 180.0 / math.pi) if k == "rotation" else ("mm", 1e3)
            print(f"  band of {k} (sampled) for {', '.join(f'{n} in [{a:g}, {c:g}]' for n, (a, c) in unc.items())}: "
                  f"[{f * lo:.6g}, {f * hi:.6g}] {u}")
        for w in caught:
            print(f"  note: {w.message}")
    t, poses = p.gripper_poses(args.rate)
    _write_poses(args, t, poses)
    for k, sc in enumerate(p.scenes):
        path = os.path.join(args.out, f"step_{k + 1}.toml")
        save_scene(sc, path)
        print(f"wrote {path}")
    return 0


def _options(args):
    """The base scene and the planner's simulation options: the scene file's
    ``simulate`` table, overridden by --t-end, --dt and --method."""
    options = {}
    if args.scene:
        if not os.path.isfile(args.scene):
            raise SystemExit(f"exdex plan: no such scene file: {args.scene}")
        try:
            scene = load_scene(args.scene, format=args.scene_format)
            options = load_simulate_options(args.scene, format=args.scene_format)
        except (ValueError, TypeError, ImportError) as exc:
            raise SystemExit(f"exdex plan: {exc}") from None
    else:
        scene = {"fig3": paper.fig3_scene, "fig4": paper.fig4_scene, "fig6": paper.fig6_scene}[args.case]()
    for key in ("t_end", "dt", "method"):
        if getattr(args, key) is not None:
            options[key] = getattr(args, key)
    return scene, options


def _unit(value, unit):
    return f"{value} {unit}" if unit else value


def run(args):
    scene, options = _options(args)
    if args.pose is not None:
        return _run_pose(args, scene)
    q, v = _kv(args.target, "--target")
    try:
        target = {q: float(v)}
    except ValueError:
        raise SystemExit(f"exdex plan: --target value must be a number, got {v!r}") from None
    if args.rest_by is not None:
        target["rest_by"] = args.rest_by
    name, bounds = _interval(args.vary, "--vary")
    unc = dict(_interval(u, "--uncertain") for u in args.uncertain) or None
    limits = None
    if args.max_acceleration is not None or args.max_speed is not None:
        limits = Limits(max_acceleration=args.max_acceleration, max_speed=args.max_speed)
    try:
        p = solve(scene, target, {name: bounds}, limits=limits, tol=args.tol, uncertain=unc, **options)
    except UnreachableTargetError as exc:
        print(f"exdex plan: {exc}")
        return 1
    except (ValueError, TypeError) as exc:
        raise SystemExit(f"exdex plan: {exc}") from None
    os.makedirs(args.out, exist_ok=True)
    u = QUANTITIES[p.quantity]
    pu = parameter_unit(scene, p.parameter)
    print(f"plan: {p.parameter} = {_unit(f'{p.value:.9g}', pu)}")
    print(f"  {p.quantity}: {p.achieved:.9g} {u} (target {p.target:g} {u}, residual {p.residual:.2e} {u}, "
          f"tol {p.tol:g} {u})")
    if scene.dof == "planar" and p.outcomes:
        print("  planned run: " + ", ".join(
            f"{k} {v * 180 / math.pi:.4g} deg" if k == "rotation" else f"{k} {v * 1e3:.4g} mm"
            for k, v in p.outcomes.items()))
    if p.rest_by is not None:
        print(f"  at rest relative to the gripper by {p.rest_by:g} s")
    print(f"  reachable by {p.parameter} in [{_unit(f'{bounds[0]:g}, {bounds[1]:g}]', pu)}: "
          f"[{p.reachable[0]:.6g}, {p.reachable[1]:.6g}] {u}")
    pk, pku = motion_peaks(p.scene.motion), peak_units(p.scene.motion)
    print(f"  gripper: peak acceleration {pk['acceleration']:.4g} {pku['acceleration']}, peak speed "
          f"{pk['speed']:.4g} {pku['speed']}, stroke {pk['stroke']:.4g} {pku['stroke']}, duration "
          f"{pk['duration']:.4g} s")
    print(f"  simulated to t_end = {p.t_end:g} s" + (f" (from {args.scene}'s [simulate] table)"
                                                    if args.scene and "t_end" in options and args.t_end is None
                                                    else ""))
    if p.band is not None:
        print(f"  outcome band: [{p.band.low:.6g}, {p.band.high:.6g}] {u} for {p.band.describe()} "
              f"({'exact ends' if p.band.exact else f'sampled, bound {p.band.bound:.2g} {u}'}); worst error "
              f"{p.worst_error:.3g} {u}: {'meets' if p.meets_target else 'does NOT meet'} tol {p.tol:g} {u}")
    t, poses = p.gripper_poses(args.rate)
    _write_poses(args, t, poses)
    scene_path = os.path.join(args.out, "planned_scene.toml")
    save_scene(p.scene, scene_path)
    print(f"wrote {scene_path}")
    try:
        pyplot("exdex plan's figure", backend="Agg")
        ax = p.plot()
        fig_path = os.path.join(args.out, "plan.png")
        ax.figure.savefig(fig_path, dpi=120)
        print(f"wrote {fig_path}")
    except ImportError:
        print("(no figure: matplotlib is missing; pip install 'exdex[plot]')")
    return 0

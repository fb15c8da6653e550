"""``exdex tool``: the assistive-tool study of the paper's Section 3 into a folder.

theta* per phi range, model and box convention (:func:`exdex.tool.theta_study`);
the box-aspect sweep; friction; several shapes with a multi-parameter tool; the
rod of Fig. 11. Writes CSV and PNG files to ``--out`` and prints a summary.
"""
from __future__ import annotations

import csv
import math
import os
import time
from typing import Any

import numpy as np

from exdex.design.tool import (BOX_CONVENTIONS, UNIT_SQUARE, Box, Tool, ToolProblem, figure_box_aspect, figure_rod,
                               figure_theta_curves, optimise_theta, optimise_tool, phi_set, rectangle, regular_polygon,
                               rod_descent_closed_form, rod_max_rotation, rod_rotation, theta_study)

__all__ = ["add_arguments", "run"]


def add_arguments(parser: Any) -> None:
    """Options of ``exdex tool``."""
    parser.add_argument("--out", default=os.path.join("exdex-output", "tool"),
                        help="output folder for PNG and CSV files (default: %(default)s)")
    parser.add_argument("--quick", action="store_true",
                        help="coarser scans and phi sets (a smoke test)")
    parser.add_argument("--mu", type=float, default=0.0,
                        help="tool friction coefficient for the main study (default 0)")
    parser.add_argument("--no-progress", action="store_true", help="hide progress bars")


def _write_csv(path, rows, keys):
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(keys)
        for r in rows:
            w.writerow([r[k] for k in keys])


def run(args):
    """``exdex tool``: theta* per phi range, model and box convention; the
    box-aspect sweep; friction; several shapes with a multi-parameter tool; the
    rod of Fig. 11. Writes CSV and PNG files to ``args.out``, prints a summary."""
    from exdex._optional import progress_bar, pyplot
    from exdex._table import format_table

    plt = pyplot("exdex tool", backend="Agg")

    def tqdm(items, **kw):
        return progress_bar(items, auto=True, feature="exdex tool's progress bars", **kw)

    if args.mu < 0 or not math.isfinite(args.mu):
        raise SystemExit(f"--mu must be finite and >= 0, got {args.mu}")
    out = args.out
    os.makedirs(out, exist_ok=True)
    progress = not args.no_progress
    n_scan = 37 if args.quick else 179
    step = 2.0 if args.quick else 0.25
    t0 = time.perf_counter()

    # 1. theta* per phi range, model and box convention
    study = theta_study(mu=args.mu, n_scan=n_scan, step_deg=step, boxes=BOX_CONVENTIONS,
                        progress=progress)
    keys = ["box", "phi_range", "model", "mu", "dVx", "dVy", "dwz", "n_phi", "theta_star_deg",
            "objective", "mean_volume", "mean_volume_90deg", "bracketed"]
    _write_csv(os.path.join(out, "theta_star.csv"), study, keys)
    fig = figure_theta_curves(study)
    fig.savefig(os.path.join(out, "theta_curves.png"), dpi=120)
    plt.close(fig)

    # 2. continuous variation of the cuboid: dVx = dVy = a, dwz = 1/a^2
    aspects = np.geomspace(0.2, 2.0, 7 if args.quick else 19)
    sweep = []
    items = [(a, m) for a in aspects for m in ("paper", "contact")]
    for a, model in (tqdm(items, desc="box aspect", leave=False) if progress else items):
        prob = ToolProblem(phi=phi_set(0, 90, step), box=Box.with_aspect(a), model=model)
        res = optimise_theta(prob, n_scan=n_scan)
        sweep.append(dict(a=a, dwz=1 / a ** 2, model=model, theta_star_deg=math.degrees(res.theta),
                          mean_volume=res.objective / len(prob.phi), bracketed=res.bracketed))
    _write_csv(os.path.join(out, "box_aspect.csv"), sweep,
               ["a", "dwz", "model", "theta_star_deg", "mean_volume", "bracketed"])
    fig = figure_box_aspect(sweep)
    fig.savefig(os.path.join(out, "box_aspect.png"), dpi=120)
    plt.close(fig)

    # 3. friction: theta* against mu (derived rows, phi 0..90)
    fric = []
    mus = [0.0, 0.1, 0.3, 0.5, 1.0, 3.0]
    for mu in (tqdm(mus, desc="friction", leave=False) if progress else mus):
        prob = ToolProblem(phi=phi_set(0, 90, step), mu=mu)
        res = optimise_theta(prob, n_scan=n_scan)
        fric.append(dict(mu=mu, theta_star_deg=math.degrees(res.theta),
                         mean_volume=res.objective / len(prob.phi), bracketed=res.bracketed))
    _write_csv(os.path.join(out, "friction.csv"), fric,
               ["mu", "theta_star_deg", "mean_volume", "bracketed"])

    # 4. several shapes; two angles and a plunger together (nmsimplex2)
    shapes = (UNIT_SQUARE, rectangle(1.2, 0.6), regular_polygon(6, 0.55), regular_polygon(3, 0.6))
    prob = ToolProblem(phi=phi_set(0, 60, 5.0 if args.quick else 1.0), shapes=shapes)
    base = optimise_theta(prob, n_scan=n_scan)
    two = None
    starts = [Tool(theta=base.theta), Tool(theta=math.pi / 2, alpha1=-0.3), Tool(theta=2.0, alpha1=0.3)]
    for st in starts:
        r = optimise_tool(prob, st, free=("alpha1", "alpha2"))
        r = optimise_tool(prob, r.tool, free=("alpha1", "alpha2"))  # restart: non-smooth
        if two is None or r.objective < two.objective:
            two = r
    best = None
    starts = [Tool(theta=two.tool.theta, alpha1=two.tool.alpha1, s=-0.4),
              Tool(theta=math.pi / 2, alpha1=-0.3, s=-0.5), Tool(theta=2.0, alpha1=0.2, s=-0.2)]
    for st in (tqdm(starts, desc="multimin", leave=False) if progress else starts):
        r = optimise_tool(prob, st)
        r = optimise_tool(prob, r.tool)
        if best is None or r.objective < best.objective:
            best = r
    n_terms = len(shapes) * len(prob.phi)
    multi = [dict(case="V tool, alpha1 = 0 (Eq. 12, Brent)", alpha1_deg=0.0,
                  alpha2_deg=math.degrees(base.theta), s="", mean_volume=base.objective / n_terms),
             dict(case="V tool, alpha1 and alpha2 (nmsimplex2)",
                  alpha1_deg=math.degrees(two.tool.alpha1), alpha2_deg=math.degrees(two.tool.alpha2),
                  s="", mean_volume=two.objective / n_terms),
             dict(case="V tool + plunger, alpha1, alpha2, s (nmsimplex2)",
                  alpha1_deg=math.degrees(best.tool.alpha1), alpha2_deg=math.degrees(best.tool.alpha2),
                  s=best.tool.s, mean_volume=best.objective / n_terms)]
    multi[0]["converged"] = base.bracketed
    multi[1]["converged"] = two.converged
    multi[2]["converged"] = best.converged
    _write_csv(os.path.join(out, "multi_shape.csv"), multi,
               ["case", "alpha1_deg", "alpha2_deg", "s", "mean_volume", "converged"])

    # 5. the rod tool of Fig. 11
    height, xr = 1.0, 0.25  # the unit square, rod 0.25 m to the side
    pmax = rod_max_rotation(height, xr)
    psi, d, u = rod_rotation(0.999 * pmax, 1.0, height, xr, steps=2000)
    closed = rod_descent_closed_form(psi, height, xr)
    rod_err = float(np.max(np.abs(d - closed)))
    with open(os.path.join(out, "rod.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["psi_deg", "descent_m", "descent_closed_form_m", "contact_u_m"])
        for row in zip(np.degrees(psi[::40]), d[::40], closed[::40], u[::40]):
            w.writerow([f"{x:.12g}" for x in row])
    fig = figure_rod(d, psi, closed, height, xr)
    fig.savefig(os.path.join(out, "rod.png"), dpi=120)
    plt.close(fig)

    # summary
    print(f"exdex tool: results in {out}  ({time.perf_counter() - t0:.1f} s)")
    print(f"theta* (Eq. 12): unit square, phi midpoints of {step:g}-deg cells, theta scanned "
          f"1..179 deg ({n_scan} values) + Brent, mu = {args.mu:g}")
    print(format_table(
        [("box", None), ("phi [deg]", None), ("model", None), ("theta* [deg]", "{:.2f}"),
         ("mean V*", "{:.4f}"), ("mean V(90 deg)", "{:.4f}"), ("interior", None)],
        [(r["box"], r["phi_range"], r["model"], r["theta_star_deg"], r["mean_volume"], r["mean_volume_90deg"],
          "yes" if r["bracketed"] else "no") for r in study], indent="  "))
    print("box aspect, dVx = dVy = a, dwz = 1/a^2, phi 0..90 deg:")
    print(format_table(
        [("a", "{:.3f}"), ("theta* paper [deg]", "{:.2f}"), ("theta* contact [deg]", "{:.2f}")],
        [(a, *[next((x["theta_star_deg"] for x in sweep if x["a"] == a and x["model"] == m), None)
               for m in ("paper", "contact")]) for a in aspects], indent="  "))
    print("friction (contact rows, phi 0..90 deg):")
    print(format_table(
        [("mu", "{:g}"), ("theta* [deg]", "{:.2f}"), ("mean V*", "{:.4g}"), ("theta* unique", None)],
        [(r["mu"], r["theta_star_deg"], r["mean_volume"], "yes" if r["bracketed"] else "no (bound or plateau)")
         for r in fric], indent="  "))
    print(f"4 shapes, phi 0..60 deg (mean V over {n_terms} cones):")
    print(format_table(
        [("tool", None), ("alpha1 [deg]", "{:.2f}"), ("alpha2 [deg]", "{:.2f}"), ("s [m]", "{:.3f}"),
         ("mean V", "{:.4f}"), ("converged", None)],
        [(r["case"], r["alpha1_deg"], r["alpha2_deg"], None if r["s"] == "" else r["s"], r["mean_volume"],
          "yes" if r["converged"] else "no") for r in multi], indent="  "))
    print(f"rod (Fig. 11), rod {xr} m off the grasp, object height {height} m: at most {math.degrees(pmax):.2f} deg "
          f"of rotation from a straight push (descent {closed[-1]:.4f} m); RK4 vs closed form "
          f"max |d error| {rod_err:.1e} m")
    return 0

"""``exdex bench``: the work-precision chart, headline table and stability maps into a folder.

What is run and measured is described in :mod:`exdex.studies.bench`. Writes, in
``--out`` (default ``exdex-output/bench``): ``work_precision.png``,
``work_precision.csv``, ``orders.csv``, ``headline.csv``, ``headline.txt``
(also printed), ``stability_<family>.png``, ``stability.csv`` and
``stability_summary.txt``.
"""
from __future__ import annotations

import os
import sys
import time

from exdex._optional import progress_bar
from exdex.studies.bench import (CASES, METHODS, engine_runners, map_dts, sweeps, write_csv, available_methods, headline,
                                 machine_name, make_case, map_grids, map_summary, orders_table, plot_maps,
                                 plot_work_precision, scene_supports, stability_maps, sweep_engines, sweep_exdex)
from exdex.engines import missing_engines

__all__ = ["add_arguments", "run"]


def add_arguments(parser):
    """Options of ``exdex bench``."""
    parser.add_argument("--out", default=os.path.join("exdex-output", "bench"),
                        help="output folder (default: %(default)s)")
    parser.add_argument("--quick", action="store_true",
                        help="a few points per line, Fig. 3 map only, one engine step size (a smoke run, ~20 s)")
    parser.add_argument("--cases", nargs="+", choices=CASES, default=list(CASES), help="work-precision cases")
    parser.add_argument("--no-engines", dest="engines", action="store_false",
                        help="skip pybullet, MuJoCo and Drake (needed without the engines extra)")
    parser.add_argument("--no-maps", dest="maps", action="store_false", help="skip the stability maps")
    parser.add_argument("--no-progress", action="store_true", help="hide the progress bars")


def run(args):
    """``exdex bench``: work-precision chart, headline table, stability maps."""
    def tqdm(iterable=None, **kw):
        return progress_bar(iterable, feature="exdex bench's progress bars", **kw)

    if args.engines:
        gone = missing_engines()
        if gone:
            print(f"exdex bench runs the engines: pip install 'exdex[engines]' ({', '.join(gone)} not installed), "
                  f"or pass --no-engines", file=sys.stderr)
            return 2
    t_start = time.perf_counter()
    os.makedirs(args.out, exist_ok=True)
    machine = machine_name()
    methods, missing = available_methods()
    print(f"machine: {machine}")
    print(f"methods: {', '.join(methods)}" + (f"; not available: {', '.join(sorted(missing))}" if missing else ""))
    written = []

    # references
    cases = {}
    for name in tqdm(args.cases, desc="references", disable=args.no_progress):
        cases[name] = make_case(name, methods, args.quick)

    # exdex sweeps
    n_pts = sum(len(p[3]) for c in cases.values()
                for p in sweeps([m for m in methods if scene_supports(c.scene, m)], args.quick, c.aligned_dt))
    rows = []
    with tqdm(total=n_pts, desc="exdex sweeps", disable=args.no_progress) as bar:
        for c in cases.values():
            rows += sweep_exdex(c, methods, args.quick, bar)

    # engines
    engine_missing = {}
    if args.engines:
        runners, engine_missing = engine_runners()
        ecases = [c for c in cases.values() if not args.quick or c.name == "fig3"]
        n = len(ecases) * len(runners) * (1 if args.quick else 5)
        with tqdm(total=n, desc="engines", disable=args.no_progress) as bar:
            for c in ecases:
                rows += sweep_engines(c, runners, args.quick, bar)
    all_missing = dict(missing)
    all_missing.update({k: f"engine not installed ({v})" for k, v in engine_missing.items()})

    path = os.path.join(args.out, "work_precision.csv")
    write_csv(path, rows)
    written.append(path)
    path = os.path.join(args.out, "orders.csv")
    write_csv(path, orders_table(rows, cases))
    written.append(path)
    path = os.path.join(args.out, "work_precision.png")
    plot_work_precision(rows, cases, path, machine, all_missing)
    written.append(path)
    refs = "\n".join(f"  {c.name}: {c.ref_label}" + (f" (uncertainty: final {c.ref_uncertainty:.1e}, max "
                                                       f"{c.ref_uncertainty_max:.1e} {c.unit})"
                                                       if c.ref_uncertainty or c.ref_uncertainty_max else "")
                     for c in cases.values())
    text, recs = headline(rows, cases, machine, all_missing)
    text += "\n\nreferences:\n" + refs
    path = os.path.join(args.out, "headline.csv")
    write_csv(path, recs, ["item", "method", "knob", "value", "run_time_s", "error", "ratio"])
    written.append(path)

    # stability maps
    if args.maps:
        g = map_grids(args.quick)
        n = sum(len(map_dts(g, m)) * (len(g["ratios"]) + (len(g["eps"]) if m == "regularised" else 0))
                for m in METHODS) * len(g["families"])
        with tqdm(total=n, desc="stability maps", disable=args.no_progress) as bar:
            mrows = stability_maps(methods, args.quick, bar)
        path = os.path.join(args.out, "stability.csv")
        write_csv(path, mrows, ["family", "method", "axis", "y", "y_label", "dt", "eps", "ratio", "cls",
                                 "chatter_sign_changes", "max_v_stick", "max_v_after", "creep_rate", "max_error",
                                 "steps", "events",
                                 "wall_s", "note"])
        written.append(path)
        for fam in g["families"]:
            path = os.path.join(args.out, f"stability_{fam}.png")
            plot_maps(mrows, fam, path, machine, missing)
            written.append(path)
        summary = map_summary(mrows)
        path = os.path.join(args.out, "stability_summary.txt")
        with open(path, "w") as fh:
            fh.write(summary + "\n")
        written.append(path)
        text += "\n\nstability maps:\n" + summary
    path = os.path.join(args.out, "headline.txt")
    with open(path, "w") as fh:
        fh.write(text + "\n")
    written.append(path)
    print(text)
    print("wrote: " + ", ".join(written))
    print(f"elapsed: {time.perf_counter() - t_start:.1f} s")
    return 0

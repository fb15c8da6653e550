"""``exdex hold``: the hold benchmark (:mod:`exdex.studies.hold`) into a folder.

Runs every engine setting on every scenario (or ``--quick``: 1 s, margins
1.5x and 20x, one default setting per engine), prints the tables
(:func:`exdex.studies.hold.format_table`) and writes ``hold_table.csv``,
``hold_table.txt``, ``hold_curves.npz`` and ``hold_drift.png``
(:func:`exdex.studies.hold.plot`) to ``--out``. ``--combine`` merges the folders of
earlier runs instead of running.
"""
from __future__ import annotations

import csv
import math
import os
import sys

import numpy as np

from exdex.cli.dispatch import require_engines
from exdex.studies.hold import FIELDS, MARGINS, QUICK_SETTINGS, SETTINGS, benchmark, format_table, plot

__all__ = ["add_arguments", "run"]


def add_arguments(parser):
    """Options of ``exdex hold``."""
    parser.add_argument("--out", default="exdex-output/hold", help="output folder (default: %(default)s)")
    parser.add_argument("--duration", type=float, default=10.0, help="hold time T [s] (default: %(default)s)")
    parser.add_argument("--quick", action="store_true",
                        help="a smoke run: 1 s, margins 1.5x and 20x, one default setting per engine")
    parser.add_argument("--engines", nargs="+", choices=("exdex", "mujoco", "pybullet", "drake"),
                        default=None, help="run only these (default: all)")
    parser.add_argument("--settings", nargs="+", default=None, metavar="TEXT",
                        help="run only the settings whose name contains one of these (e.g. 'drake point')")
    parser.add_argument("--combine", nargs="+", default=None, metavar="DIR",
                        help="run nothing: merge the results of earlier runs (their --out folders) into --out")
    parser.add_argument("--no-plots", dest="plots", action="store_false", help="write no figure")
    parser.add_argument("--no-progress", action="store_true", help="print no line per run (the table only)")


def run(args):
    """``exdex hold``: the table, CSV and figure."""
    if args.combine:
        rows, curves, t_end = _load(args.combine)
    else:
        status = require_engines("hold")
        if status:
            return status
        if not (args.duration > 0 and math.isfinite(args.duration)):
            print(f"exdex hold: --duration must be a positive number of seconds, got {args.duration}",
                  file=sys.stderr)
            return 2
        t_end = 1.0 if args.quick else args.duration
        margins = (1.5, 20.0) if args.quick else MARGINS
        settings = QUICK_SETTINGS() if args.quick else SETTINGS()
        if args.engines:
            settings = [s for s in settings if s[1] in args.engines]
        if args.settings:
            settings = [s for s in settings if any(part in s[0] for part in args.settings)]
        if not settings:
            print("exdex hold: no setting matches --engines/--settings", file=sys.stderr)
            return 2

        def progress(r):
            if not args.no_progress:
                print(f"{r['setting']:38s} {r['dof']:11s} {r['margin']:4g}x {r['motion']:5s} drift "
                      f"{r['drift']:.3e} {r['unit']} ({r['wall_time_s']:.2f} s) "
                      f"{'' if r['status'] == 'ok' else r['status']}", flush=True)

        rows, curves = benchmark(t_end, margins=margins, settings=settings, progress=progress)
    os.makedirs(args.out, exist_ok=True)
    with open(os.path.join(args.out, "hold_table.csv"), "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=FIELDS)
        w.writeheader()
        for r in rows:
            w.writerow({k: (f"{r[k]:.6g}" if isinstance(r[k], float) else r[k]) for k in FIELDS})
    np.savez_compressed(os.path.join(args.out, "hold_curves.npz"), t_end=t_end,
                        **{"|".join(map(str, k)) + "|t": v[0] for k, v in curves.items()},
                        **{"|".join(map(str, k)) + "|d": v[1] for k, v in curves.items()})
    table = f"hold for {t_end:g} s\n" + format_table(rows)
    print(table)
    with open(os.path.join(args.out, "hold_table.txt"), "w") as fh:
        fh.write(table + "\n")
    if args.plots:
        margin = 3.0 if any(r["margin"] == 3.0 for r in rows) else min(r["margin"] for r in rows)
        plot(curves, os.path.join(args.out, "hold_drift.png"), t_end, margin=margin)
    return 0


def _load(folders):
    """Rows, curves and T of earlier runs (hold_table.csv and hold_curves.npz in each folder)."""
    rows, curves, t_end = [], {}, None
    for d in folders:
        with open(os.path.join(d, "hold_table.csv")) as fh:
            for r in csv.DictReader(fh):
                for k in ("margin", "drift", "creep_speed", "wall_time_s"):
                    r[k] = float(r[k]) if r[k] not in ("", "nan") else math.nan
                rows.append(r)
        z = np.load(os.path.join(d, "hold_curves.npz"))
        t = float(z["t_end"])
        if t_end is not None and t != t_end:
            raise ValueError(f"--combine: the runs differ in duration ({t_end:g} s and {t:g} s)")
        t_end = t
        for key in z.files:
            if key.endswith("|t"):
                name, dof, margin, motion, _ = key.split("|")
                curves[(name, dof, float(margin), motion)] = (z[key], z[key[:-2] + "|d"])
    return rows, curves, t_end

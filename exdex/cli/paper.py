"""``exdex paper``: the paper's case studies (Figs. 3, 4, 6) into a folder.

For each case, :func:`exdex.paper.run_case` simulates it against its
independent reference; the command writes ``<case>.png`` (or ``--format``),
``<case>.csv``, optionally an animation, ``summary.csv``, and prints the
table (:func:`exdex.paper.format_table`).
"""
from __future__ import annotations

import os
import time
from typing import Any

from exdex.studies.paper import CASES, format_table, plot_case, run_case, write_csv, write_summary

__all__ = ["add_arguments", "run"]


def add_arguments(parser: Any) -> None:
    """Options of ``exdex paper``."""
    parser.add_argument("--out", default=os.path.join("exdex-output", "paper"),
                        help="output folder (default: exdex-output/paper)")
    parser.add_argument("--dt", type=float, default=1e-4,
                        help="time step [s] (default 1e-4)")
    parser.add_argument("--cases", nargs="+", choices=CASES, default=list(CASES), help="cases to run (default: all)")
    parser.add_argument("--format", default="png", choices=("png", "pdf", "svg"), help="figure format")
    parser.add_argument("--animate", nargs="?", const="gif", default=None, choices=("gif", "mp4", "html"),
                        help="also write an animation per case (default format gif; mp4 needs ffmpeg)")
    parser.add_argument("--no-progress", action="store_true", help="hide the progress bar")


def run(args):
    """``exdex paper``: simulate the cases, write figures and CSV, print the table."""
    from exdex._optional import progress_bar

    t_start = time.perf_counter()
    if not args.dt > 0:
        raise SystemExit("exdex paper: --dt must be > 0")
    os.makedirs(args.out, exist_ok=True)
    rows = []
    notes = []
    written = []
    animate = getattr(args, "animate", None)
    tasks = 4 if animate else 3
    with progress_bar(total=tasks * len(args.cases), desc="exdex paper", unit="task", disable=args.no_progress,
                      feature="exdex paper's progress bar") as bar:
        for name in args.cases:
            bar.set_postfix_str(f"{name}: simulate")
            case = run_case(name, dt=args.dt)
            bar.update()
            bar.set_postfix_str(f"{name}: figure")
            fig_path = os.path.join(args.out, f"{name}.{args.format}")
            plot_case(case, fig_path)
            bar.update()
            bar.set_postfix_str(f"{name}: csv")
            csv_path = os.path.join(args.out, f"{name}.csv")
            write_csv(case, csv_path)
            bar.update()
            rows += case.rows
            notes += case.notes
            written += [fig_path, csv_path]
            if animate:
                bar.set_postfix_str(f"{name}: animation")
                anim_path = os.path.join(args.out, f"{name}.{animate}")
                try:
                    case.result.animate(title=case.title.split(":")[0]).save(anim_path)
                except RuntimeError as exc:  # no ffmpeg for mp4
                    raise SystemExit(f"exdex paper: {exc}")
                written.append(anim_path)
                bar.update()
    summary = os.path.join(args.out, "summary.csv")
    write_summary(rows, summary)
    written.append(summary)
    print(format_table(rows))
    for line in notes:
        print(line)
    print("wrote: " + ", ".join(written))
    print(f"elapsed: {time.perf_counter() - t_start:.2f} s")
    return 0

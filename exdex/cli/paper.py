"""``exdex paper``: the paper's case studies (Figs. 3, 4, 6) into a folder.

For each case, :func:`exdex.paper.run_case` simulates it against its
independent reference; the command writes the figure
(:func:`exdex.paper.plot_case`, at ``--width``: a 3.5 in column or the
7.16 in page) as ``<case>.png`` (300 dpi) and ``<case>.pdf`` (or the
``--format`` list; PDF and SVG are vector), ``<case>.csv``, optionally an
animation, ``summary.csv``, and prints the table
(:func:`exdex.paper.format_table`).
"""
from __future__ import annotations

import os
import time
from typing import Any

from exdex.studies.paper import CASES, WIDTHS, format_table, plot_case, run_case, save_figure, write_csv, write_summary

__all__ = ["add_arguments", "run"]


def add_arguments(parser: Any) -> None:
    """Options of ``exdex paper``."""
    parser.add_argument("--out", default=os.path.join("exdex-output", "paper"),
                        help="output folder (default: exdex-output/paper)")
    parser.add_argument("--dt", type=float, default=1e-4,
                        help="time step [s] (default 1e-4)")
    parser.add_argument("--cases", nargs="+", choices=CASES, default=list(CASES), help="cases to run (default: all)")
    parser.add_argument("--format", nargs="+", default=["png", "pdf"], choices=("png", "pdf", "svg"),
                        help="figure formats (default: png pdf; PNG at 300 dpi, PDF and SVG vector)")
    parser.add_argument("--width", default="column", choices=tuple(WIDTHS),
                        help="figure width: column (3.5 in, panels stacked) or page (7.16 in, side by side); "
                             "text is 8 pt at that size (default column)")
    parser.add_argument("--animate", nargs="?", const="gif", default=None, choices=("gif", "mp4", "html"),
                        help="also write an animation per case (default format gif; mp4 needs ffmpeg)")
    parser.add_argument("--no-progress", action="store_true", help="hide the progress bar")


def run(args):
    """``exdex paper``: simulate the cases, write figures and CSV, print the table."""
    from exdex._optional import progress_bar, pyplot

    t_start = time.perf_counter()
    if not args.dt > 0:
        raise SystemExit("exdex paper: --dt must be > 0")
    pyplot("exdex paper", backend="Agg")   # files only: no window system
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
            formats = [args.format] if isinstance(args.format, str) else list(dict.fromkeys(args.format))
            fig_paths = save_figure(plot_case(case, width=args.width), os.path.join(args.out, name), formats)
            bar.update()
            bar.set_postfix_str(f"{name}: csv")
            csv_path = os.path.join(args.out, f"{name}.csv")
            write_csv(case, csv_path)
            bar.update()
            rows += case.rows
            notes += case.notes
            written += fig_paths + [csv_path]
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

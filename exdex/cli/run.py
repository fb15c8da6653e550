"""``exdex run SCENE``: simulate a scene file and write what it gives.

The scene file is TOML or JSON (see :mod:`exdex.io`); its optional
``simulate`` table gives defaults for the options below, which the command
line overrides. Writes, in ``--out`` (default ``exdex-output/<scene name>``):

* ``<name>.csv`` -- one row per sample (:meth:`exdex.Result.save`),
* ``<name>.npz`` -- the arrays, the scene and the run's statistics
  (:meth:`exdex.Result.load` reads it back),
* ``<name>.png`` -- the displacement against time (:meth:`exdex.Result.plot`),
* ``<name>.gif`` (or ``.mp4``, ``.html``) with ``--animate``
  (:meth:`exdex.Result.animate`).
"""
from __future__ import annotations

import os
import time

__all__ = ["add_arguments", "run", "default_t_end"]


def default_t_end(scene):
    """End time used when neither the file nor the command line gives one [s]:
    the end of the gripper motion and of the grip schedule (:attr:`exdex.Scene.end_time`)
    plus 0.5 s to settle (1 s when neither changes in time)."""
    end = scene.end_time
    return end + 0.5 if end > 0 else 1.0


def add_arguments(parser):
    from exdex.scene import METHODS, SOLVERS

    parser.add_argument("scene", help="scene file, .toml or .json (exdex.save_scene writes one)")
    parser.add_argument("--scene-format", choices=("toml", "json"), default=None,
                        help="format of the scene file when its extension does not say (.toml, .json)")
    parser.add_argument("--method", choices=sorted(METHODS) + ["auto"], default=None,
                        help="integration method (default: the file's simulate.method, else implicit)")
    parser.add_argument("--friction-solver", choices=sorted(SOLVERS), default=None,
                        help="planar friction solve (default: the file's, else scalar)")
    parser.add_argument("--t-end", type=float, default=None,
                        help="end time [s] (default: the file's simulate.t_end, else the end of the motion and of the "
                             "grip schedule + 0.5 s)")
    parser.add_argument("--dt", type=float, default=None,
                        help="time step or output interval [s] (default: the file's simulate.dt, else 0.001)")
    parser.add_argument("--out", default=None, help="output folder (default: exdex-output/<scene name>)")
    parser.add_argument("--format", default="png", choices=("png", "pdf", "svg"), help="figure format")
    parser.add_argument("--animate", nargs="?", const="gif", default=None, choices=("gif", "mp4", "html"),
                        help="also write an animation (default format gif; mp4 needs ffmpeg)")
    parser.add_argument("--fps", type=float, default=25.0, help="animation frames per second (default 25)")
    parser.add_argument("--no-progress", action="store_true", help="hide the progress bar")


def run(args):
    import exdex
    from exdex import io
    from exdex._optional import available, progress_bar, pyplot, require

    plots = available("matplotlib")
    if args.animate:
        require("matplotlib", "exdex run --animate")  # the one-line missing-extra message, before simulating

    path = args.scene
    if not os.path.isfile(path):
        raise SystemExit(f"exdex run: no such scene file: {path}")
    try:
        scene = io.load_scene(path, format=args.scene_format)
        options = io.load_simulate_options(path, format=args.scene_format)
    except (ValueError, TypeError, ImportError) as exc:
        raise SystemExit(f"exdex run: {exc}")
    for key in ("method", "friction_solver", "t_end", "dt"):
        value = getattr(args, key)
        if value is not None:
            options[key] = value
    options.setdefault("t_end", default_t_end(scene))
    options.setdefault("dt", 1e-3)
    name = os.path.splitext(os.path.basename(path))[0]
    out = args.out or os.path.join("exdex-output", name)
    os.makedirs(out, exist_ok=True)
    files = []
    tasks = 2 + int(plots) + int(bool(args.animate))  # simulate, write, figure, animation
    t0 = time.perf_counter()
    with progress_bar(total=tasks, desc="exdex run", unit="task",
                      disable=args.no_progress or not available("tqdm")) as bar:
        bar.set_postfix_str("simulate")
        try:
            res = exdex.simulate(scene, **options)
        except (ValueError, TypeError) as exc:
            raise SystemExit(f"exdex run: {exc}")
        except exdex.SolverError as exc:
            raise SystemExit(f"exdex run: the solver failed: {exc}")
        bar.update()
        bar.set_postfix_str("write")
        for ext in (".csv", ".npz"):
            files.append(res.save(os.path.join(out, name + ext)))
        bar.update()
        if plots:
            bar.set_postfix_str("figure")
            plt = pyplot("exdex run (the figure)", backend="Agg")
            axes = res.plot()
            fig = (axes[0] if isinstance(axes, tuple) else axes).figure
            fig.suptitle(f"{name}: {scene.dof}, method {res.method}, dt {res.dt:g} s", fontsize="medium")
            fig.tight_layout()
            fig_path = os.path.join(out, f"{name}.{args.format}")
            fig.savefig(fig_path, dpi=120)
            plt.close(fig)
            files.append(fig_path)
            bar.update()
        if args.animate:
            bar.set_postfix_str("animation")
            anim_path = os.path.join(out, f"{name}.{args.animate}")
            try:
                res.animate(fps=args.fps, title=name).save(anim_path)
            except (RuntimeError, ValueError) as exc:
                raise SystemExit(f"exdex run: {exc}")
            files.append(anim_path)
            bar.update()
    print(repr(res))
    if not plots:
        print("exdex run: no figure: it needs matplotlib, not installed: pip install 'exdex[plot]'")
    print(f"exdex run: {len(files)} files in {out} ({time.perf_counter() - t0:.1f} s): "
          + ", ".join(os.path.basename(f) for f in files))
    return 0

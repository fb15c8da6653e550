"""Cost of a planar run against convex obstacles with every method (implicit,
explicit, event, regularised), against the same run with the equivalent plane
stop, and each method against the implicit one, measured in the same run.

The scene: a square block in the planar grasp with one face flush against a
wall fixed in the world, the gripper moving toward the wall at constant
speed so that the plates slide past the block and press it on the wall
(both corners push in every step). The wall is given as a Stop (the peer),
as a one-face obstacle (the same rows: the same cost expected), as the face
of a box (six faces per vertex row, plus the rows of the section's corners
against the block) and, with friction mu = 0.3, as the frictional stop and
the frictional box. A last pair pushes a pinned square onto a rod (one rod
row, rotation scene) against the same scene without contact.

The time is one compiled model's ``final`` call (the whole run, output of
the last sample only): the implicit and explicit methods take --steps steps
of dt = t_end / steps, the event and regularised methods integrate to their
default tolerances (rtol 1e-8, atol 1e-10; eps 1e-4) with one output sample
(at t_end). After one
warm-up call per model, each of --repeat rounds times every method once on
the scene (alternating, so that all share the machine's load), a sample
being as many back-to-back runs as fill about 0.2 s (the warm-up's time
decides how many), divided by their count; printed are
the median [ms] per run, its min and max, the ratio of the medians to the
implicit method's on the same scene ("vs implicit") and to the same
method's on the peer scene ("vs peer"). The table is written to
<out>/obstacles.txt, the numbers to obstacles.csv and a chart to
obstacles.png. Usage:

    python benchmarks/bench_obstacles.py [--repeat 7] [--steps 20000] [--out benchmarks/results]
"""
import argparse
import csv
import math
import os
import statistics
import textwrap
import time

import exdex
from _harness import machine_line

METHODS = ("implicit", "explicit", "event", "regularised")
MIN_TIME = 0.2  # s: a timed sample repeats the run until it lasts about this long (scheduler slices are ~ms)


def wall_scene(stops=(), obstacles=(), V=0.01, m=0.1, a=0.03):
    xw = 0.1
    return exdex.Scene(
        body=exdex.Body.box(m, (a, a, 0.02)),
        grasp=exdex.Grasp(mu=0.5, grip_force=1.5, patch=exdex.Patch.rectangle(0.02, 0.02)),
        motion=exdex.TrapezoidalProfile(amplitude=2.0 * V, duration=2.0, v_max=V, axis=(1, 0, 0)),
        dof="planar", q0=(xw - a / 2, 0.0, 0.0), stops=stops, obstacles=obstacles)


def rod_scene(stops=(), obstacles=()):
    a = 0.02
    body = exdex.Body(mass=0.1, inertia=0.1 * (2 * a) ** 2 / 6, outline=[(-a, -a), (a, -a), (a, a), (-a, a)])
    return exdex.Scene(body=body, grasp=exdex.Grasp(mu=0.5, grip_force=1.0), dof="rotation",
                       motion=exdex.TrapezoidalProfile(0.005, 1.0, 0.0075, axis=(0, 0, -1)),
                       stops=stops, obstacles=obstacles)


def cases():
    """(name, scene, is the peer of the lines below it)."""
    wall = ((0.1, 0.0, 0.0), (-1.0, 0.0, 0.0))
    return [
        ("wall: Stop (peer)", wall_scene(stops=(exdex.Stop(*wall),)), True),
        ("wall: one-face Obstacle", wall_scene(obstacles=(exdex.Obstacle.halfspaces([wall[1]], [-0.1]),)), False),
        ("wall: face of an Obstacle.box", wall_scene(obstacles=(exdex.Obstacle.box((0.6, 0, 0), (1, 1, 1)),)), False),
        ("wall mu 0.3: Stop (peer)", wall_scene(stops=(exdex.Stop(*wall, mu=0.3),)), True),
        ("wall mu 0.3: Obstacle.box", wall_scene(obstacles=(exdex.Obstacle.box((0.6, 0, 0), (1, 1, 1), mu=0.3),)),
         False),
        ("pinned square, no contact (peer)", rod_scene(), True),
        ("pinned square onto a rod: Obstacle.cylinder",
         rod_scene(obstacles=(exdex.Obstacle.cylinder((0.015, 0.0, -0.026), (0, 1, 0), 0.005),)), False),
    ]


def time_scene(scene, steps, repeat):
    """{method: list of ms per run}, the methods alternating in each round."""
    t_end = 0.2 if scene.dof == "planar" else 1.0
    dt = t_end / steps
    models = {m: exdex.Model(scene, method=m) for m in METHODS}
    step = {m: dt if m in ("implicit", "explicit") else t_end for m in METHODS}  # adaptive: one output sample
    calls = {}
    for m, mdl in models.items():
        t0 = time.perf_counter()
        mdl.final(t_end, step[m])  # warm-up
        calls[m] = max(1, math.ceil(MIN_TIME / max(time.perf_counter() - t0, 1e-6)))
    ms = {m: [] for m in METHODS}
    for k in range(repeat):
        order = METHODS if k % 2 == 0 else METHODS[::-1]
        for m in order:
            t0 = time.perf_counter()
            for _ in range(calls[m]):
                models[m].final(t_end, step[m])
            ms[m].append((time.perf_counter() - t0) * 1e3 / calls[m])
    return ms


def chart(rows, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np

    names = list(dict.fromkeys(r["contact"] for r in rows))
    fig, ax = plt.subplots(figsize=(10, 4.8))
    w = 0.8 / len(METHODS)
    x = np.arange(len(names))
    for i, m in enumerate(METHODS):
        y = [next(r["ms_median"] for r in rows if r["contact"] == n and r["method"] == m) for n in names]
        ax.bar(x + (i - 1.5) * w, y, w, label=m)
    ax.set_yscale("log")
    ax.set_xticks(x)
    ax.set_xticklabels([textwrap.fill(n, 20) for n in names], fontsize=7)
    ax.set_ylabel("ms per run (median)")
    ax.set_title("bench_obstacles: one run per method (implicit, explicit: fixed steps; event, regularised: rtol 1e-8)",
                 fontsize=9)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=7)
    ap.add_argument("--steps", type=int, default=20_000)
    ap.add_argument("--out", default=os.path.join(os.path.dirname(os.path.abspath(__file__)), "results"))
    args = ap.parse_args(argv)
    lines = [machine_line(args.repeat, args.steps) + " (implicit, explicit); event, regularised: default tolerances",
             f"{'contact':<44} {'method':<12} {'ms/run':>9} {'min':>9} {'max':>9} {'vs implicit':>11} {'vs peer':>8}"]
    print("\n".join(lines), flush=True)
    rows, peer = [], None
    for name, scene, is_peer in cases():
        ms = time_scene(scene, args.steps, args.repeat)
        med = {m: statistics.median(ms[m]) for m in METHODS}
        if is_peer:
            peer = med
        for m in METHODS:
            row = dict(contact=name, method=m, ms_median=med[m], ms_min=min(ms[m]), ms_max=max(ms[m]),
                       vs_implicit=med[m] / med["implicit"], vs_peer=med[m] / peer[m])
            rows.append(row)
            line = (f"{name if m == METHODS[0] else '':<44} {m:<12} {row['ms_median']:9.3f} {row['ms_min']:9.3f} "
                    f"{row['ms_max']:9.3f} {row['vs_implicit']:11.3g} {row['vs_peer']:8.3g}")
            lines.append(line)
            print(line, flush=True)
    os.makedirs(args.out, exist_ok=True)
    with open(os.path.join(args.out, "obstacles.txt"), "w") as f:
        f.write("\n".join(lines) + "\n")
    with open(os.path.join(args.out, "obstacles.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    chart(rows, os.path.join(args.out, "obstacles.png"))
    print(f"wrote {os.path.join(args.out, 'obstacles.txt')}, obstacles.csv, obstacles.png")


if __name__ == "__main__":
    main()

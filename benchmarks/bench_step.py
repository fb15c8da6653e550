"""Nanoseconds per simulation step of exdex.simulate (issue: core).

Two scenes, each with the three friction solvers:
  * 1-DoF: the paper's Fig. 3 scene (vertical translation, Eq. 7 motion);
  * planar (x, y, theta) with a stop: a box whose patch is off-centre, on a
    tilted stop, in a gripper that rotates (Eq. 7 as a rotation), so friction
    slides, sticks and the stop pushes.
The time is the whole exdex.simulate call (scene conversion, model set-up,
output arrays and their first touch included) divided by the number of steps;
median and spread over repeated runs, and the ratio of each solver's median
to the scalar solver's on the same scene (measured in the same run). The
table is also written to --results (default benchmarks/results/step.txt).
Usage:

    python benchmarks/bench_step.py [--repeat 7] [--out exdex-output/bench] [--results PATH]
    python benchmarks/bench_step.py --grip [--repeat 7]

--grip prints the cost of a 1-DoF step with a grip schedule (exdex.GripSchedule)
against the same scene's constant-grip step, measured alternately in the same
run: medians of ns/step and of the per-repeat ratio, for the time-stepping
methods (one step per sample).
"""
import argparse
import csv
import math
import os
import platform
import statistics
import time

import exdex


def scenes():
    fig3 = exdex.Scene(body=exdex.Body(mass=0.1), grasp=exdex.Grasp(mu=0.5, grip_force=1.5),
                       motion=exdex.AsymmetricProfile(0.1, 0.5, 0.9, axis=(0, 0, -1)))
    a = math.radians(10)
    planar = exdex.Scene(
        body=exdex.Body.box(0.1, (0.02, 0.04, 0.02)),
        grasp=exdex.Grasp(mu=0.5, grip_force=0.6, patch=exdex.Patch.rectangle(0.02, 0.04, center=(0.004, 0.0))),
        motion=exdex.AsymmetricProfile(0.6, 0.5, 0.7, axis=(0, -1, 0), rotation=True),
        dof="planar",
        stops=(exdex.Stop(point=(0, 0, -0.03), normal=(math.sin(a), 0, math.cos(a))),),
    )
    return {"1-DoF (Fig. 3)": (fig3, 1_000_000), "planar + stop": (planar, 200_000)}


def measure(scene, steps, solver, repeat):
    t_end = 2.0
    dt = t_end / steps
    exdex.simulate(scene, t_end, dt=dt, friction_solver=solver)  # warm-up
    ns = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        r = exdex.simulate(scene, t_end, dt=dt, friction_solver=solver)
        ns.append((time.perf_counter() - t0) / r.stats["steps"] * 1e9)
    return ns, r


def grip_scenes():
    """The 1-DoF Fig. 3 scene with its constant grip (1.5 N) and with a grip
    schedule of 11 points over the run, piecewise linear, within 1e-9
    relative of 1.5 N: every step evaluates the schedule (its mean over the
    step) while the motion stays the same (the same stick and slip phases,
    so the two runs do the same work besides the schedule)."""
    base, _ = scenes()["1-DoF (Fig. 3)"]
    times = [0.2 * k for k in range(11)]
    forces = [1.5 * (1.0 + 1e-9 * math.sin(1.7 * k)) for k in range(11)]
    sched = exdex.replace(base, grasp=exdex.Grasp(mu=0.5, grip_force=exdex.GripSchedule(times, forces)))
    return base, sched


def measure_grip(method, steps, repeat):
    """ns per step of the constant-grip and the scheduled scene, the two
    runs alternating within each repeat (same machine load); returns the
    two lists and the per-repeat ratios."""
    base, sched = grip_scenes()
    t_end = 2.0
    dt = t_end / steps
    const_ns, sched_ns, ratio = [], [], []
    for sc in (base, sched):
        exdex.simulate(sc, t_end, dt=dt, method=method)  # warm-up
    for k in range(repeat):
        pair = [0.0, 0.0]
        for j in ((0, 1) if k % 2 == 0 else (1, 0)):  # alternate which goes first
            t0 = time.perf_counter()
            r = exdex.simulate((base, sched)[j], t_end, dt=dt, method=method)
            pair[j] = (time.perf_counter() - t0) / r.stats["steps"] * 1e9
        const_ns.append(pair[0])
        sched_ns.append(pair[1])
        ratio.append(pair[1] / pair[0])
    return const_ns, sched_ns, ratio


def main_grip(repeat):
    print(f"1-DoF step with a grip schedule against the constant grip (Fig. 3 scene; median of {repeat} "
          f"alternating runs)")
    print(f"{'method':<10} {'const ns/step':>14} {'schedule ns/step':>17} {'ratio':>7} {'ratio min':>10} "
          f"{'ratio max':>10}")
    for method, steps in (("implicit", 200_000), ("explicit", 200_000)):
        c, s, q = measure_grip(method, steps, repeat)
        print(f"{method:<10} {statistics.median(c):14.1f} {statistics.median(s):17.1f} "
              f"{statistics.median(q):7.3f} {min(q):10.3f} {max(q):10.3f}")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=7)
    ap.add_argument("--out", default=os.path.join("exdex-output", "bench"))
    ap.add_argument("--results", default=os.path.join(os.path.dirname(os.path.abspath(__file__)), "results", "step.txt"),
                    help="the printed table, as benchmarks/README.md quotes it ('' : not written)")
    ap.add_argument("--grip", action="store_true",
                    help="only the cost of a 1-DoF step with a grip schedule against a constant grip")
    args = ap.parse_args(argv)
    if args.grip:
        main_grip(args.repeat)
        return
    os.makedirs(args.out, exist_ok=True)
    lines = [f"machine: {platform.processor() or platform.machine()}, {os.cpu_count()} cores, "
             f"Python {platform.python_version()}; median of {args.repeat} runs",
             f"{'scene':<16} {'solver':<10} {'ns/step':>9} {'min':>8} {'max':>8} {'vs scalar':>9} {'stick %':>8} "
             f"{'iter/step':>9}"]
    print("\n".join(lines), flush=True)
    rows = []
    for name, (scene, steps) in scenes().items():
        base = None
        for solver in ("scalar", "brent", "multiroot"):
            ns, r = measure(scene, steps, solver, args.repeat)
            st = r.stats
            row = dict(scene=name, solver=solver, ns_per_step=statistics.median(ns), ns_min=min(ns), ns_max=max(ns),
                       steps=st["steps"], stick_fraction=st["stick_steps"] / st["steps"],
                       iterations_per_step=st["solver_iterations"] / st["steps"])
            base = base if base is not None else row["ns_per_step"]
            row["vs_scalar"] = row["ns_per_step"] / base
            rows.append(row)
            lines.append(f"{name:<16} {solver:<10} {row['ns_per_step']:9.1f} {row['ns_min']:8.1f} "
                         f"{row['ns_max']:8.1f} {row['vs_scalar']:9.2f} {100 * row['stick_fraction']:8.1f} "
                         f"{row['iterations_per_step']:9.2f}")
            print(lines[-1], flush=True)
    if args.results:
        os.makedirs(os.path.dirname(os.path.abspath(args.results)), exist_ok=True)
        with open(args.results, "w") as f:
            f.write("\n".join(lines) + "\n")
        print(f"wrote {args.results}")
    path = os.path.join(args.out, "step_cost.csv")
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    print(f"wrote {path}")


if __name__ == "__main__":
    main()

"""The analytic 1-DoF path against the event method, and planning speed.

Run:  python benchmarks/bench_analytic.py [--repeats 7] [--n 200000] [--out benchmarks/results]

Prints, for the paper's Fig. 3 scene (medians over --repeats runs, both
methods measured in the same run):

* one trajectory (exdex.Model.final, output dt = t_end): time per call and
  the error of the final slip against the closed form
  (exdex.paper.fig3_grip_force's derivation);
* a batch of --n trajectories over grip forces (record="final"): trajectories
  per second on 1 and 2 threads;
* exdex.plan.solve for a 15 mm slip varying the grip force to 1e-6 m, with
  method "auto" (the analytic path) and "event": time per plan;
* robust plans over mu +-20 %: an inertial 15 mm slide (Fig. 3, analytic
  path) and a 40 mm slide onto a stop (Fig. 4, event method): time, worst
  error over the interval and whether it meets the tolerance;
* a planar pose target (x, y, theta) to 0.1 mm and 0.1 deg by a sequence of
  primitives (exdex.sequence.solve, the pose a 30 mm slide along x and a
  0.3 rad pivot leave): time per plan and its residuals.

Writes analytic.txt (what it prints), analytic.csv and analytic.png
(throughput bars) to --out.
"""
import argparse
import csv
import math
import os
import statistics
import time
import warnings

import numpy as np

import exdex
from exdex import paper, plan, sequence


def median_time(fn, repeats, inner=1):
    ts = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        for _ in range(inner):
            fn()
        ts.append((time.perf_counter() - t0) / inner)
    return statistics.median(ts)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--repeats", type=int, default=7)
    ap.add_argument("--n", type=int, default=200_000, help="trajectories per batch (analytic; event gets n/10)")
    ap.add_argument("--out", default=os.path.join(os.path.dirname(__file__), "results"))
    args = ap.parse_args(argv)
    os.makedirs(args.out, exist_ok=True)
    scene = paper.fig3_scene()
    exact = -paper.FIG3["slip"]
    rows = []
    lines = []

    def say(text):
        """Print and keep for analytic.txt."""
        lines.append(text)
        print(text)

    say("Fig. 3, one trajectory (Model.final, dt = t_end = 1.5 s):")
    for method, kw in (("analytic", {}), ("event", dict(rtol=1e-10, atol=1e-12))):
        m = exdex.Model(scene, method=method, **kw)
        q, _, _ = m.final(1.5, 1.5)
        t = median_time(lambda: m.final(1.5, 1.5), args.repeats, inner=2000 if method == "analytic" else 200)
        err = abs(q[0] - exact)
        say(f"  {method:9s} {1e6 * t:9.3f} us   |slip - closed form| = {err:.2e} m")
        rows.append(dict(item="one trajectory", method=method, value=t, unit="s", error=err))

    say(f"Fig. 3 batch over grip forces (record='final'):")
    tput = {}
    for method, n in (("analytic", args.n), ("event", max(args.n // 10, 1000))):
        F = np.linspace(1.2, 2.5, n)
        for threads in (1, 2):
            walls, cpus = [], []
            for _ in range(max(3, args.repeats // 2)):
                w0, c0 = time.perf_counter(), time.process_time()
                exdex.simulate_batch(scene, 1.5, 1.5, record="final", method=method, threads=threads,
                                     grip_force=F, warn=False)
                walls.append(time.perf_counter() - w0)
                cpus.append(time.process_time() - c0)
            t, c = statistics.median(walls), statistics.median(cpus)
            tput[(method, threads)] = n / t
            # per CPU-second of the process (all its threads): what each core
            # delivers, whatever else the machine runs meanwhile
            say(f"  {method:9s} {threads} thread(s): {n / t:12,.0f} trajectories/s "
                f"({n / c:12,.0f} per CPU-second, {c / t:.2f} cores busy)")
            rows.append(dict(item=f"batch {threads} threads", method=method, value=n / t, unit="1/s", error=""))
    say(f"  analytic / event on 2 threads: {tput[('analytic', 2)] / tput[('event', 2)]:.0f}x")

    say("plan: 15 mm slip varying grip force to 1e-6 m:")
    for method in ("auto", "event"):
        t = median_time(lambda: plan.solve(scene, {"slip": -0.015}, vary={"grip_force": (1.0, 3.0)}, tol=1e-6,
                                           t_end=1.5, method=method), args.repeats)
        p = plan.solve(scene, {"slip": -0.015}, vary={"grip_force": (1.0, 3.0)}, tol=1e-6, t_end=1.5,
                       method=method)
        say(f"  {method:9s} {1e3 * t:8.3f} ms   residual {p.residual:.1e} m")
        rows.append(dict(item="plan 1-DoF to 1e-6 m", method=method, value=t, unit="s", error=abs(p.residual)))
    t = median_time(lambda: plan.solve(scene, {"slip": -0.015}, vary={"grip_force": (1.0, 3.0)},
                                       uncertain={"mu": (0.4, 0.6)}, t_end=1.5, method="auto", tol=5e-3),
                    max(3, args.repeats // 2))
    rp = plan.solve(scene, {"slip": -0.015}, vary={"grip_force": (1.0, 3.0)}, uncertain={"mu": (0.4, 0.6)},
                    t_end=1.5, method="auto", tol=5e-3)
    say(f"robust plan over mu 0.4-0.6 (auto): {t:.3f} s; inertial 15 mm slide: worst error "
        f"{1e3 * rp.worst_error:.3f} mm, {'meets' if rp.meets_target else 'does not meet'} 5 mm")
    rows.append(dict(item="robust plan mu +-20%", method="auto", value=t, unit="s", error=rp.worst_error))
    s4 = paper.fig4_scene()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        t = median_time(lambda: plan.solve(s4, {"slip": 0.04}, vary={"amplitude": (0.031, 0.06)},
                                           uncertain={"mu": (0.4, 0.6)}, t_end=1.2, tol=1e-4),
                        max(3, args.repeats // 2))
        rp = plan.solve(s4, {"slip": 0.04}, vary={"amplitude": (0.031, 0.06)}, uncertain={"mu": (0.4, 0.6)},
                        t_end=1.2, tol=1e-4)
    say(f"robust plan over mu 0.4-0.6 (event, slide onto a stop, Fig. 4): {t:.3f} s; 40 mm: worst error "
        f"{1e3 * rp.worst_error:.2e} mm, {'meets' if rp.meets_target else 'does not meet'} 0.1 mm")
    rows.append(dict(item="robust plan onto a stop mu +-20%", method="event", value=t, unit="s",
                     error=rp.worst_error))

    # planar pose target by a sequence of primitives
    m, g = 0.1, 9.81
    box = exdex.Scene(body=exdex.Body.box(m, (0.06, 0.03, 0.02)),
                      grasp=exdex.Grasp(mu=0.5, grip_force=1.2 * m * g / (0.5 * 2),
                                        patch=exdex.Patch.rectangle(0.01, 0.01)), dof="planar")
    P = sequence.primitives(box)
    q = sequence._run_sequence(box, [P["slide_x"], P["pivot"]], [0.03, 0.3], 0.3, 1e-12, 1e-14)
    target = {"x": float(q[0]), "y": float(q[1]), "rotation": float(q[2])}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        sequence.solve(box, target)   # warm-up (SciPy's import)
        t = median_time(lambda: sequence.solve(box, target), max(3, args.repeats // 2))
        sp = sequence.solve(box, target)
    res = max(abs(sp.residuals["x"]), abs(sp.residuals["y"]))
    say(f"planar pose target to 0.1 mm / 0.1 deg (sequence of primitives): {t:.3f} s, "
          f"{' -> '.join(n for n, _ in sp.steps)}, residuals {1e3 * res:.1e} mm, "
          f"{math.degrees(abs(sp.residuals['rotation'])):.1e} deg")
    rows.append(dict(item="planar pose target", method="event", value=t, unit="s", error=res))

    with open(os.path.join(args.out, "analytic.txt"), "w") as fh:
        fh.write("\n".join(lines) + "\n")
    path = os.path.join(args.out, "analytic.csv")
    with open(path, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=["item", "method", "value", "unit", "error"])
        w.writeheader()
        w.writerows(rows)
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print(f"wrote {path} (matplotlib missing: no chart)")
        return 0
    fig, ax = plt.subplots(figsize=(6, 3.5), constrained_layout=True)
    labels = [f"{m}\n{k} thread{'s' if k > 1 else ''}" for (m, k) in tput]
    ax.bar(labels, list(tput.values()), color=["C0", "C0", "C1", "C1"])
    ax.set_yscale("log")
    ax.set_ylabel("Fig. 3 trajectories per second")
    ax.set_title("Batch throughput: analytic path vs event method")
    fig.savefig(os.path.join(args.out, "analytic.png"), dpi=120)
    print(f"wrote {path} and analytic.png")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

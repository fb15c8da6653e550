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
* a robust plan over mu +-20 %: time.

Writes analytic.csv and analytic.png (throughput bars) to --out.
"""
import argparse
import csv
import os
import statistics
import time

import numpy as np

import exdex
from exdex import paper, plan


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

    print("Fig. 3, one trajectory (Model.final, dt = t_end = 1.5 s):")
    for method, kw in (("analytic", {}), ("event", dict(rtol=1e-10, atol=1e-12))):
        m = exdex.Model(scene, method=method, **kw)
        q, _, _ = m.final(1.5, 1.5)
        t = median_time(lambda: m.final(1.5, 1.5), args.repeats, inner=2000 if method == "analytic" else 200)
        err = abs(q[0] - exact)
        print(f"  {method:9s} {1e6 * t:9.3f} us   |slip - closed form| = {err:.2e} m")
        rows.append(dict(item="one trajectory", method=method, value=t, unit="s", error=err))

    print(f"Fig. 3 batch over grip forces (record='final'):")
    tput = {}
    for method, n in (("analytic", args.n), ("event", max(args.n // 10, 1000))):
        F = np.linspace(1.2, 2.5, n)
        for threads in (1, 2):
            t = median_time(lambda: exdex.simulate_batch(scene, 1.5, 1.5, record="final", method=method,
                                                         threads=threads, grip_force=F, warn=False),
                            max(3, args.repeats // 2))
            tput[(method, threads)] = n / t
            print(f"  {method:9s} {threads} thread(s): {n / t:12,.0f} trajectories/s")
            rows.append(dict(item=f"batch {threads} threads", method=method, value=n / t, unit="1/s", error=""))
    print(f"  analytic / event on 2 threads: {tput[('analytic', 2)] / tput[('event', 2)]:.0f}x")

    print("plan: 15 mm slip varying grip force to 1e-6 m:")
    for method in ("auto", "event"):
        t = median_time(lambda: plan.solve(scene, {"slip": -0.015}, vary={"grip_force": (1.0, 3.0)}, tol=1e-6,
                                           t_end=1.5, method=method), args.repeats)
        p = plan.solve(scene, {"slip": -0.015}, vary={"grip_force": (1.0, 3.0)}, tol=1e-6, t_end=1.5,
                       method=method)
        print(f"  {method:9s} {1e3 * t:8.3f} ms   residual {p.residual:.1e} m")
        rows.append(dict(item="plan 1-DoF to 1e-6 m", method=method, value=t, unit="s", error=abs(p.residual)))
    t = median_time(lambda: plan.solve(scene, {"slip": -0.015}, vary={"grip_force": (1.0, 3.0)},
                                       uncertain={"mu": (0.4, 0.6)}, t_end=1.5, method="auto", tol=5e-3),
                    max(3, args.repeats // 2))
    print(f"robust plan over mu 0.4-0.6 (auto): {t:.3f} s")
    rows.append(dict(item="robust plan mu +-20%", method="auto", value=t, unit="s", error=""))

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

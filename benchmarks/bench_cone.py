"""Speed against accuracy of the three cone-volume methods (paper Section 3).

    python benchmarks/bench_cone.py [--out DIR] [--cones N] [--repeat R] [--quick]

Test set: N cones from the paper's Eqs. 10-11 at random (phi, theta)
(phi in [0, 90) deg, theta in (10, 170) deg; seed 0) in the centred Eq. 13 box.
Reference: the exact volume (divergence theorem); it agrees with scipy's
qhull to ~1e-16 (tests/design/test_tool.py). For each method and resolution the
script times one vectorised C call over all N cones, R times, and reports the
median time per cone and the median and the maximum absolute error over the
cones. "Equal error 1e-4": the time per cone at which a method's error curve
(log-log interpolation) crosses 1e-4, for the median error and for the
maximum error. Writes bench_cone.csv and bench_cone.png to DIR.
"""
import argparse
import csv
import math
import os
import sys
import time

import numpy as np

try:
    from exdex import tool as T
except ImportError:  # run from a source tree without installing
    sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    from exdex import tool as T


def timed(fn, repeat):
    ts = []
    out = None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        ts.append(time.perf_counter() - t0)
    return float(np.median(ts)), out


def crossing(times, errors, target):
    """Time at which the error curve first reaches target (log-log interpolation)."""
    t, e = np.log(np.asarray(times)), np.log(np.maximum(np.asarray(errors), 1e-300))
    for i in range(1, len(e)):
        if e[i] <= math.log(target) < e[i - 1]:
            w = (math.log(target) - e[i - 1]) / (e[i] - e[i - 1])
            return math.exp(t[i - 1] + w * (t[i] - t[i - 1]))
    return float("nan")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default=os.path.join("exdex-output", "bench_cone"))
    ap.add_argument("--cones", type=int, default=40)
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--quick", action="store_true", help="fewer resolutions (smoke test)")
    args = ap.parse_args(argv)
    os.makedirs(args.out, exist_ok=True)
    rng = np.random.default_rng(0)
    n = args.cones
    rows = T.paper_rows(np.radians(rng.uniform(0, 90, n)), np.radians(rng.uniform(10, 170, n)))
    box = T.Box.eq13()

    records = []
    t_exact, (exact, _) = timed(lambda: T.cone_volumes(rows, box), max(args.repeat, 20))
    # exact once more on a large batch for a stable per-cone time
    big = np.repeat(rows, 2500 // n + 1, axis=0)
    t_big, _ = timed(lambda: T.cone_volumes(big, box), args.repeat)
    per_exact = t_big / len(big)
    records.append(dict(method="exact", resolution=0, time_per_cone=per_exact,
                        median_error=0.0, max_error=0.0))
    print(f"exact: {per_exact * 1e6:.2f} us per cone (median of {args.repeat} runs, "
          f"{len(big)} cones per call)")

    grid_ns = [4, 8, 16, 32, 64, 128, 256] if args.quick else \
        [4, 8, 12, 16, 24, 32, 48, 64, 96, 128, 192, 256, 384, 512]
    for g in grid_ns:
        rep = args.repeat if g <= 128 else max(1, args.repeat // 2 + 1)
        t, (v, _) = timed(lambda: T.cone_volumes(rows, box, method="grid", grid_n=g), rep)
        err = np.abs(v - exact)
        records.append(dict(method="grid", resolution=g, time_per_cone=t / n,
                            median_error=float(np.median(err)), max_error=float(err.max())))
        print(f"grid n={g:4d}: {t / n * 1e3:10.4f} ms per cone, median err {np.median(err):.2e}, "
              f"max err {err.max():.2e}")

    qmc_pts = [2 ** k for k in (range(6, 19, 2) if args.quick else range(6, 23, 2))]
    for p in qmc_pts:
        t, (v, e) = timed(lambda: T.cone_volumes(rows, box, method="qmc", qmc_points=p // 16,
                                                 qmc_shifts=16, seed=3), args.repeat)
        err = np.abs(v - exact)
        records.append(dict(method="qmc", resolution=p, time_per_cone=t / n,
                            median_error=float(np.median(err)), max_error=float(err.max())))
        print(f"qmc N={p:8d}: {t / n * 1e3:10.4f} ms per cone, median err {np.median(err):.2e}, "
              f"max err {err.max():.2e}, median stderr {np.median(e):.2e}")

    with open(os.path.join(args.out, "bench_cone.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(records[0]))
        w.writeheader()
        w.writerows(records)

    # convergence rates: least-squares slopes of log(error) against log(n) / log(N)
    for m, lo in (("grid", 16), ("qmc", 1024)):
        r = [x for x in records if x["method"] == m and x["resolution"] >= lo]
        res = np.log([x["resolution"] for x in r])
        for kind in ("median_error", "max_error"):
            slope = np.polyfit(res, np.log([x[kind] for x in r]), 1)[0]
            per = "n (cells per axis)" if m == "grid" else "N (points)"
            print(f"{m} {kind.replace('_', ' ')} ~ {per}^{slope:.2f}")

    print("\ntime per cone at error 1e-4 (log-log interpolation):")
    summary = {}
    for m in ("grid", "qmc"):
        r = [x for x in records if x["method"] == m]
        for kind in ("median_error", "max_error"):
            tc = crossing([x["time_per_cone"] for x in r], [x[kind] for x in r], 1e-4)
            summary[(m, kind)] = tc
            print(f"  {m:4s} ({kind.replace('_', ' ')}): {tc * 1e3:.4f} ms  -> "
                  f"{tc / per_exact:,.0f} x the exact method")
    print(f"  exact: {per_exact * 1e3:.5f} ms, error ~1e-16")

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(6.5, 4.5))
    for m, mk, col in (("grid", "o-", "C0"), ("qmc", "s-", "C2")):
        r = [x for x in records if x["method"] == m]
        t = [x["time_per_cone"] for x in r]
        ax.loglog(t, [x["median_error"] for x in r], mk, color=col, label=f"{m} (median error)")
        ax.loglog(t, [x["max_error"] for x in r], mk, color=col, alpha=0.35,
                  label=f"{m} (max error)")
    ax.axvline(per_exact, color="k", ls="--", label=f"exact ({per_exact * 1e6:.1f} us, error ~1e-16)")
    ax.axhline(1e-4, color="0.6", lw=0.8)
    ax.set_xlabel("time per cone [s]")
    ax.set_ylabel("absolute volume error (Eq. 13 box, V_max = 1)")
    ax.set_title(f"cone volume: speed vs accuracy ({n} cones, Eqs. 10-11)")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(args.out, "bench_cone.png"), dpi=120)
    print(f"wrote {args.out}/bench_cone.csv and bench_cone.png")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

"""Batch throughput: Fig. 3 trajectories per second on 1 and 2 threads.

The scene is the paper's Fig. 3 (exdex.paper.fig3_scene(): Eq. 7 down first,
beta 0.9, X1 0.1 m, T 0.5 s, m 0.1 kg, mu 0.5, grip 1.50514 N per finger),
t_end 1.5 s, with the implicit method. The step dt is chosen by measurement:

1. dt scan. The final displacement of the closed form
   (exdex.paper.closed_form(scene).final, -20 mm) against exdex for
   dt = h0 / k, k = 1 .. K, where h0 is the grid of Eq. 7's switch times
   (0.45, 0.55, 1.0 s: h0 = 0.05 s), and for a geometric ladder of dt that
   does not divide h0. The chosen dt is the largest h0 / k such that *every*
   k' >= k up to K errs by <= 1e-6 m (so it does not rely on a lucky grid
   that also puts the slip->stick event, at 0.595 s, on a step boundary).
2. Throughput. Wall time of one exdex.simulate_batch call (parameter checks,
   model builds, the threads, output arrays: everything) for N copies of the
   scene (record="final"), medians of --repeat runs after a warm-up, on 1 and
   2 threads, for the implicit method at that dt and for the event-driven
   method (default rtol 1e-8; its dt is only the output grid, so
   record="final" uses dt = t_end); also record="all", a batch of varied grip
   forces (checked against each one's closed form), a serial exdex.simulate
   loop, exdex.sweep on a thread pool and on a Dask LocalCluster, and the
   implicit method at the off-grid dt that meets 1e-6 m. Every row reports
   the largest final-displacement error of its batch.

The machine may be shared: the load average before and after is printed and
written to the CSV. Usage:

    python benchmarks/bench_batch.py [--repeat 5] [--n 20000] [--out exdex-output/bench] [--no-dask]
                                     [--wait-idle 600]
"""
import argparse
import concurrent.futures as cf
import csv
import math
import os
import platform
import statistics
import time
from fractions import Fraction
from functools import reduce

import numpy as np

import exdex
from exdex import paper
from exdex.batch import simulate_batch, sweep

T_END = 1.5
TOL = 1e-6   # goal: final displacement error [m]


def switch_grid(scene):
    """Largest h0 dividing every switch time of the Eq. 7 motion [s]."""
    ts = [Fraction(t).limit_denominator(10**6) for t0, t1, _ in paper.eq7_phases(
        scene.motion.amplitude, scene.motion.duration, scene.motion.beta) for t in (t0, t1)
          if math.isfinite(t) and t > 0]
    num = reduce(math.gcd, [t.numerator * (reduce(math.lcm, [s.denominator for s in ts]) // t.denominator)
                            for t in ts])
    return float(Fraction(num, reduce(math.lcm, [s.denominator for s in ts])))


def final_error(scene, dt, exact):
    b = simulate_batch(scene, T_END, dt, threads=1, record="final")
    return abs(b.final_displacement[0, 0] - exact)


def dt_scan(scene, exact, k_max):
    h0 = switch_grid(scene)
    aligned = [(k, h0 / k, final_error(scene, h0 / k, exact)) for k in range(1, k_max + 1)]
    ok_from = None
    for k, dt, err in reversed(aligned):
        if err > TOL:
            break
        ok_from = (k, dt, err)
    # a ladder that avoids the switch grid: dt = 10^(-2 - j/16)
    generic = []
    for j in range(0, 58):
        dt = 10.0 ** (-2.0 - j / 16.0)
        r = h0 / dt
        if abs(r - round(r)) < 1e-6:
            continue
        generic.append((dt, final_error(scene, dt, exact)))
    gen_ok = None
    for dt, err in reversed(generic):
        if err > TOL:
            break
        gen_ok = (dt, err)
    return h0, aligned, ok_from, generic, gen_ok


def busy_seconds():
    """CPU seconds all processes have spent busy since boot (Linux /proc/stat), or NaN."""
    try:
        with open("/proc/stat") as f:
            v = [int(x) for x in f.readline().split()[1:]]
    except (OSError, ValueError):
        return math.nan
    idle = v[3] + (v[4] if len(v) > 4 else 0)
    return (sum(v[:8]) - idle) / os.sysconf("SC_CLK_TCK")


FOREIGN = []   # CPU seconds per wall second used by other processes during the timed runs


def timed(fn, repeat):
    """Wall times of `repeat` calls after a warm-up, the median CPU time of
    this process per wall second (all its threads: about the thread count
    when the cores are free, less when other processes take them), and the
    last result. Other processes' CPU use during the runs goes to FOREIGN."""
    fn()  # warm-up
    ts, util = [], []
    for _ in range(repeat):
        b0, c0, t0 = busy_seconds(), time.process_time(), time.perf_counter()
        out = fn()
        t1, c1, b1 = time.perf_counter(), time.process_time(), busy_seconds()
        ts.append(t1 - t0)
        util.append((c1 - c0) / (t1 - t0))
        FOREIGN.append(max(0.0, (b1 - b0) - (c1 - c0)) / (t1 - t0))
    return ts, statistics.median(util), out


def wait_idle(limit):
    """Wait up to `limit` seconds until other processes use < 0.1 CPU; returns their use [CPUs]."""
    t_stop = time.monotonic() + limit
    while True:
        b0, c0 = busy_seconds(), time.process_time()
        time.sleep(1.0)
        use = (busy_seconds() - b0) - (time.process_time() - c0)
        if not use >= 0.1 or time.monotonic() >= t_stop:
            return use


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=5, help="timed runs per figure (median reported)")
    ap.add_argument("--n", type=int, default=20000, help="trajectories per batch (record='final')")
    ap.add_argument("--k-max", type=int, default=200, help="dt scan: dt = h0 / k for k <= K")
    ap.add_argument("--out", default=os.path.join("exdex-output", "bench"))
    ap.add_argument("--no-dask", action="store_true", help="skip the Dask LocalCluster sweep")
    ap.add_argument("--wait-idle", type=float, default=0.0, metavar="S",
                    help="first wait up to S seconds for other processes to leave the CPUs")
    args = ap.parse_args(argv)
    os.makedirs(args.out, exist_ok=True)
    if args.wait_idle > 0:
        print(f"other processes' CPU use: {wait_idle(args.wait_idle):.2f} CPUs")
    load0 = os.getloadavg()
    print(f"machine: {platform.processor() or platform.machine()}, {os.cpu_count()} cores, "
          f"Python {platform.python_version()}, numpy {np.__version__}; load average {load0[0]:.2f}; "
          f"medians of {args.repeat} runs")

    scene = paper.fig3_scene()
    exact = paper.closed_form(scene).final
    grip = scene.grasp.grip_force

    # ---- 1. dt scan
    h0, aligned, ok_from, generic, gen_ok = dt_scan(scene, exact, args.k_max)
    print(f"\nFig. 3, closed-form final displacement {exact * 1e3:.6f} mm; Eq. 7 switch grid h0 = {h0:g} s")
    print(f"{'k':>4} {'dt [s]':>11} {'|error| [m]':>12}")
    for k, dt, err in aligned[:12] + [a for a in aligned if a[0] in (20, 23, 29, 30, 40, 50, 71, 100)]:
        print(f"{k:4d} {dt:11.4e} {err:12.3e}")
    if ok_from is None:
        raise SystemExit(f"no dt = h0/k with k <= {args.k_max} meets {TOL:g} m for all larger k; raise --k-max")
    k_star, dt_star, err_star = ok_from
    worst = max(err for k, _, err in aligned if k >= k_star)
    print(f"chosen dt = h0/{k_star} = {dt_star:.6g} s ({round(T_END / dt_star)} steps): error {err_star:.3e} m; "
          f"max error over k = {k_star}..{args.k_max}: {worst:.3e} m")
    if gen_ok:
        print(f"dt off the switch grid (first order): error <= {TOL:g} m from dt = {gen_ok[0]:.3e} s "
              f"({round(T_END / gen_ok[0])} steps) down (error there {gen_ok[1]:.2e} m)")
    with open(os.path.join(args.out, "batch_dt_scan.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["grid", "k", "dt [s]", "abs final displacement error [m]"])
        for k, dt, err in aligned:
            w.writerow(["switch grid h0/k", k, "%.17g" % dt, "%.6e" % err])
        for dt, err in generic:
            w.writerow(["off grid", "", "%.17g" % dt, "%.6e" % err])

    # ---- 2. throughput
    rows = []
    n = args.n

    def add(case, method, record, threads, dt, ntraj, ts, cpu, err):
        med = statistics.median(ts)
        other = statistics.median(FOREIGN[-len(ts):])
        row = dict(case=case, method=method, record=record, threads=threads, dt=dt, samples=round(T_END / dt) + 1,
                   trajectories=ntraj, median_s=med, min_s=min(ts), max_s=max(ts), traj_per_s=ntraj / med,
                   us_per_traj=1e6 * med / ntraj, cpu_per_wall=cpu, other_cpu_per_wall=other,
                   max_final_error_m=err)
        rows.append(row)
        print(f"{case:<34} {method:<8} {record:<6} {threads:>3} {dt:10.4e} {ntraj:>6} {row['traj_per_s']:9.0f} "
              f"{row['us_per_traj']:9.2f} {min(ts):7.3f} {max(ts):7.3f} {cpu:5.2f} {other:5.2f} {err:9.2e}")
        return row

    def batch(case, method, record, threads, dt, arrays, refs=None, repeat=args.repeat, **kw):
        """Time simulate_batch; error of every trajectory's final displacement
        against the closed form (refs: per-trajectory closed forms on a subset)."""
        ntraj = len(next(iter(arrays.values())))
        ts, cpu, b = timed(lambda: simulate_batch(scene, T_END, dt, threads=threads, record=record, method=method,
                                                  **kw, **arrays), repeat)
        if refs is None:
            err = float(np.max(np.abs(b.final_displacement[:, 0] - exact)))
        else:
            idx, want = refs
            err = float(np.max(np.abs(b.final_displacement[idx, 0] - want)))
        return add(case, method, record, threads, dt, ntraj, ts, cpu, err)

    print(f"\n{'case':<34} {'method':<8} {'record':<6} {'thr':>3} {'dt [s]':>10} {'traj':>6} {'traj/s':>9} "
          f"{'us/traj':>9} {'min [s]':>7} {'max [s]':>7} {'cpu/s':>5} {'other':>5} {'max err':>9}")
    print("(cpu/s: this process's CPU seconds per wall second, all threads; other: the other processes')")
    gf = {"grip_force": np.full(n, grip)}
    head = {}
    # implicit (default method) at the chosen dt
    for threads in (1, 2):
        head["implicit", threads] = batch("Fig. 3 x N", "implicit", "final", threads, dt_star, gf)
    for threads in (1, 2):
        batch("Fig. 3 x N", "implicit", "all", threads, dt_star, {"grip_force": np.full(max(1, n // 10), grip)})
    # event-driven: dt is only the output grid; record="final" needs one interval
    for threads in (1, 2):
        head["event", threads] = batch("Fig. 3 x N", "event", "final", threads, T_END, gf)
    for threads in (1, 2):
        batch("Fig. 3 x N (output every 10 ms)", "event", "all", threads, 0.01,
              {"grip_force": np.full(max(1, n // 10), grip)})
    # varied grip force 1.3 .. 1.7 N (slip 52 .. 4.5 mm): error against each closed form on a subset
    gv = np.random.default_rng(1).uniform(1.3, 1.7, n)
    sub = np.arange(0, n, max(1, n // 200))
    refs = (sub, np.array([paper.closed_form(exdex.replace(scene, grasp=exdex.replace(scene.grasp, grip_force=g))).final
                           for g in gv[sub]]))
    for method, dt in (("implicit", dt_star), ("event", T_END)):
        for threads in (1, 2):
            batch("grip force 1.3..1.7 N", method, "final", threads, dt, {"grip_force": gv}, refs)
    # serial Python loop of exdex.simulate, for comparison
    ns = max(1, n // 20)
    ts, cpu, res = timed(lambda: [exdex.simulate(scene, T_END, dt_star) for _ in range(ns)], max(1, args.repeat // 2))
    add("Fig. 3, exdex.simulate loop", "implicit", "all", 1, dt_star, ns, ts, cpu,
        abs(res[-1].displacement[-1, 0] - exact))
    # sweeps: chunks of 1000, each a single-threaded batch
    def sweep_row(case, ex, method, dt):
        ts, cpu, b = timed(lambda: sweep(scene, gf, executor=ex, chunk=1000, progress=False, t_end=T_END, dt=dt,
                                         method=method), args.repeat)
        add(case, method, "final", 2, dt, n, ts, cpu, float(np.max(np.abs(b.final_displacement[:, 0] - exact))))

    with cf.ThreadPoolExecutor(max_workers=2) as ex:
        sweep_row("Fig. 3 x N, sweep ThreadPool(2)", ex, "implicit", dt_star)
        sweep_row("Fig. 3 x N, sweep ThreadPool(2)", ex, "event", T_END)
    if not args.no_dask:
        try:
            import distributed
        except ImportError:
            print("(dask.distributed not installed: Dask sweep skipped)")
        else:
            for processes in (False, True):
                with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=processes,
                                              host="127.0.0.1", protocol="tcp", dashboard_address=None) as cl, \
                        distributed.Client(cl) as client:
                    # pure=False: Dask would otherwise hand back the warm-up's
                    # results for the identical tasks of the timed runs
                    ex = client.get_executor(pure=False)
                    kind = "processes" if processes else "threads"
                    sweep_row(f"Fig. 3 x N, sweep Dask 2 {kind}", ex, "implicit", dt_star)
                    sweep_row(f"Fig. 3 x N, sweep Dask 2 {kind}", ex, "event", T_END)
    if gen_ok:
        for threads in (1, 2):
            batch("Fig. 3 x N, dt off the switch grid", "implicit", "final", threads, gen_ok[0],
                  {"grip_force": np.full(max(2, n // 500), grip)}, repeat=max(1, args.repeat // 2))

    load1 = os.getloadavg()
    print()
    for method, dt in (("implicit", dt_star), ("event", T_END)):
        h1, h2 = head[method, 1], head[method, 2]
        print(f"headline, {method} (dt {dt:.6g} s): {h1['traj_per_s']:.0f} trajectories/s on 1 thread, "
              f"{h2['traj_per_s']:.0f} on 2 threads (speed-up {h2['traj_per_s'] / h1['traj_per_s']:.2f}; CPU per wall "
              f"second {h1['cpu_per_wall']:.2f} and {h2['cpu_per_wall']:.2f}), final error <= "
              f"{max(h1['max_final_error_m'], h2['max_final_error_m']):.1e} m; goal >= 1e4 /s at <= {TOL:g} m: "
              f"{'met' if h2['traj_per_s'] >= 1e4 and h2['max_final_error_m'] <= TOL else 'NOT met'}")
    print(f"load average before {load0[0]:.2f}, after {load1[0]:.2f}; other processes' CPU use during the timed "
          f"runs: median {statistics.median(FOREIGN):.2f}, max {max(FOREIGN):.2f} CPUs of {os.cpu_count()}")
    path = os.path.join(args.out, "batch_throughput.csv")
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]) + ["load_before", "load_after", "machine"])
        w.writeheader()
        for r in rows:
            w.writerow(dict(r, load_before=round(load0[0], 2), load_after=round(load1[0], 2),
                            machine=f"{platform.processor() or platform.machine()}, {os.cpu_count()} cores"))
    print(f"wrote {path} and {os.path.join(args.out, 'batch_dt_scan.csv')}")


if __name__ == "__main__":
    main()

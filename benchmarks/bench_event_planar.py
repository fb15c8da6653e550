"""The event method on the planar benchmark scene (exdex.studies.bench.planar_scene,
1.5 s, output every 2^-6 s): run time, ODE steps and error against the
reference at each rtol (atol = 1e-2 rtol), for this tree and, with --base, a
baseline tree measured in the same run.

The reference is the one of the work-precision chart (exdex.studies.bench):
the event method at rtol 1e-12 of the tree measured first; the error is the
largest distance between the object's outline vertices and the reference's
at t_end (final) and over the output grid (max). The time is the median over
--repeat runs of a whole exdex.simulate call after a warm-up, the trees
measured in alternation (one subprocess per tree, each run of a tree
interleaved with the other's), so the ratio compares them under the same
load. Usage:

    python benchmarks/bench_event_planar.py [--repeat 7] [--base PATH-TO-A-BUILT-TREE]
"""
import argparse
import json
import os
import statistics
import subprocess
import sys

RTOLS = (1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-10)

WORKER = r"""
import json, sys, time
import numpy as np
from exdex.studies import bench
from exdex import simulate
sc = bench.planar_scene()
rtols = json.loads(sys.argv[1])
def run(r):
    return simulate(sc, 1.5, dt=bench.GRID_DT, method="event", rtol=r, atol=bench.ATOL_PER_RTOL * r)
for r in rtols:
    run(r)
for line in sys.stdin:
    cmd = json.loads(line)
    if cmd == "ref":
        res = run(1e-12)
        print(json.dumps(res.q.tolist()), flush=True)
        continue
    out = {}
    for r in rtols:
        t0 = time.perf_counter()
        res = run(r)
        dt = time.perf_counter() - t0
        out[repr(r)] = dict(t=dt, steps=int(res.stats["steps"]), q=res.q.tolist())
    print(json.dumps(out), flush=True)
"""


def worker(tree):
    env = dict(os.environ, PYTHONPATH=tree)
    return subprocess.Popen([sys.executable, "-c", WORKER, json.dumps(RTOLS)], cwd=tree, env=env,
                            stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True)


def ask(p, cmd):
    p.stdin.write(json.dumps(cmd) + "\n")
    p.stdin.flush()
    return json.loads(p.stdout.readline())


def main(argv=None):
    import numpy as np
    from exdex.studies import bench

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=7)
    ap.add_argument("--base", default=None, help="a built exdex tree to compare with (measured alternately)")
    args = ap.parse_args(argv)
    here = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    trees = [("this", here)] + ([("base", os.path.abspath(args.base))] if args.base else [])
    procs = {name: worker(path) for name, path in trees}
    ref = np.array(ask(procs["this"], "ref"))
    sc = bench.planar_scene()
    runs = {name: [] for name, _ in trees}
    for _ in range(args.repeat):
        for name, _ in trees:
            runs[name].append(ask(procs[name], "run"))
    for p in procs.values():
        p.stdin.close()
        p.wait()
    print(f"planar scene, event method; median of {args.repeat} runs per tree, trees alternated; "
          f"reference: this tree's event run at rtol 1e-12")
    head = f"{'rtol':>7} {'tree':>5} {'time ms':>8} {'steps':>6} {'final err m':>12} {'max err m':>10}"
    if args.base:
        head += f" {'time/base':>10}"
    print(head)
    for r in RTOLS:
        med = {}
        for name, _ in trees:
            rs = [x[repr(r)] for x in runs[name]]
            med[name] = statistics.median(x["t"] for x in rs)
            q = np.array(rs[0]["q"])
            e = bench.vertex_error(sc, q - q[0], ref - ref[0])
            line = f"{r:7.0e} {name:>5} {1e3 * med[name]:8.3f} {rs[0]['steps']:6d} {e[-1]:12.2e} {e.max():10.2e}"
            if args.base and name == "this":
                ratios = [a[repr(r)]["t"] / b[repr(r)]["t"] for a, b in zip(runs["this"], runs["base"])]
                line += f" {statistics.median(ratios):10.3f}"
            print(line)


if __name__ == "__main__":
    main()

"""The scene zoo's long run: every method on many seeded zoo scenes.

    python benchmarks/zoo_long.py --n 10000 --seed 0 --jobs 2 --csv zoo_long.csv
    python benchmarks/zoo_long.py --inputs --n 5000 --csv zoo_inputs_long.csv

Draws scenes ``seed .. seed + n - 1`` from tests/zoo.py (the generator the
test suite uses; see its docstring for what a scene can be), runs each one
through ``zoo.check_scene`` (implicit at four time steps, explicit on its
time-step ladder from there, extended until consistent, event at two
tolerances and output grids, regularised at one smoothing
speed, and on its eps ladder on every 4th scene as in the test suite; every
tolerance in the scene's own units) on ``--jobs`` processes, shows a progress bar on
stderr and prints:

* how many scenes ran, and per method the failures grouped by cause (the
  exception's message, the free coordinates and the motion kind);
* per method how many scenes were compared with the reference and how many
  fell outside the method's error bound (``zoo.bound``, derived in
  tests/scenarios/test_zoo.py), and the agreement error (the final pose's distance to
  the event reference, relative to L; see ``zoo.pose_distance``) at the
  quantiles 50, 90, 99, 99.9 % and the maximum, and the same for the ratio
  of that error to the bound;
* the worst cases by that ratio, with their seeds (``zoo.zoo_scene(seed)``
  reproduces one);

and writes one CSV row per scene (seed, tags, per method: error message,
err, est, seconds).

``--inputs`` draws the zoo-inputs scenes instead
(tests/scenarios/test_zoo_inputs.py's ``input_scene``: each zoo scene with
random new inputs, grip schedules, obstacles, static friction) and checks
them as that test file does (``results``: the methods that support the
scene; the implicit ladder as the reference where the event method does
not run it). A method that does not support a scene is counted as skipped,
not as a failure.
"""
from __future__ import annotations

import argparse
import collections
import csv
import math
import multiprocessing
import os
import sys
import time
import warnings

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests"))
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "scenarios"))

import zoo  # noqa: E402

QUANTILES = (0.5, 0.9, 0.99, 0.999, 1.0)
REG_EVERY = 4


INPUTS = False   # --inputs: the zoo-inputs scenes (set in each worker)


def _init(inputs):
    global INPUTS
    INPUTS = inputs


def one(seed):
    """Check one scene; a plain dict (picklable) for the parent."""
    warnings.simplefilter("ignore")
    t0 = time.perf_counter()
    try:
        if INPUTS:
            import test_zoo_inputs

            s, out = test_zoo_inputs.results(seed)
            zs, tags = s.zs, s.tags
        else:
            zs = zoo.zoo_scene(seed)
            tags = zs.tags
    except Exception as e:  # noqa: BLE001 - a generator defect is a result too
        return dict(seed=seed, gen_error=f"{type(e).__name__}: {e}")
    row = dict(seed=seed, gen_error=None, tags=tags, L=zs.L, t_end=zs.t_end)
    if not INPUTS:
        agree = zoo.METHODS if seed % REG_EVERY == 0 else tuple(m for m in zoo.METHODS if m != "regularised")
        out = zoo.check_scene(zs, agree=agree)
    for m in zoo.METHODS:
        o = out.get(m)
        if o is None:   # the method does not support the scene
            row[m] = dict(error=None, err=None, est=None, ok=None, skipped=True)
            continue
        row[m] = dict(error=o["error"], err=o.get("err"), est=o.get("bound"), ok=o.get("ok"))
    ref = out.get("reference", {})
    row["ref_est"] = ref.get("err")
    row["jump"] = ref.get("jump")
    row["seconds"] = time.perf_counter() - t0
    return row


def cause(row, m):
    msg = row[m]["error"]
    return f"{msg[:70]} [{row['tags']['dof']}, {row['tags']['motion'].split('-')[0]}]"


def ratio(o):
    if o["err"] is None:
        return None
    if o["est"] == 0.0:
        return 0.0 if o["err"] == 0.0 else math.inf
    return o["err"] / o["est"]


def progress(done, total, t0):
    width = 40
    k = int(width * done / total)
    rate = done / max(time.time() - t0, 1e-9)
    eta = (total - done) / rate if rate > 0 else 0.0
    sys.stderr.write(f"\r[{'#' * k}{'.' * (width - k)}] {done}/{total} {rate:.1f}/s eta {eta / 60:.1f} min ")
    sys.stderr.flush()


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--n", type=int, default=10000, help="number of scenes (default 10000)")
    ap.add_argument("--seed", type=int, default=0, help="first seed (default 0)")
    ap.add_argument("--jobs", type=int, default=2, help="worker processes (default 2)")
    ap.add_argument("--csv", default="zoo_long.csv", help="output CSV path (default zoo_long.csv)")
    ap.add_argument("--worst", type=int, default=5, help="worst cases listed per method (default 5)")
    ap.add_argument("--inputs", action="store_true",
                    help="the zoo-inputs scenes (tests/scenarios/test_zoo_inputs.py) instead of the zoo's")
    ap.add_argument("--minutes", type=float, default=None,
                    help="stop after this wall time and report the scenes done so far (default: no limit)")
    args = ap.parse_args(argv)

    seeds = range(args.seed, args.seed + args.n)
    rows = []
    t0 = time.time()
    stopped = False
    with multiprocessing.Pool(args.jobs, initializer=_init, initargs=(args.inputs,)) as pool:
        for i, row in enumerate(pool.imap_unordered(one, seeds, chunksize=4), 1):
            rows.append(row)
            if i % 10 == 0 or i == args.n:
                progress(i, args.n, t0)
            if args.minutes is not None and time.time() - t0 > 60.0 * args.minutes:
                stopped = True
                pool.terminate()
                break
    sys.stderr.write("\n")
    rows.sort(key=lambda r: r["seed"])
    wall = time.time() - t0

    gen_fail = [r for r in rows if r["gen_error"]]
    ok = [r for r in rows if not r["gen_error"]]
    print(f"{'zoo-inputs' if args.inputs else 'zoo'} long run: {len(rows)} scenes from seed {args.seed}, {wall:.0f} s wall on {args.jobs} processes"
          + (f" (stopped by --minutes {args.minutes:g} before {args.n})" if stopped else ""))
    if gen_fail:
        print(f"generator errors: {len(gen_fail)} (first seed {gen_fail[0]['seed']}: {gen_fail[0]['gen_error']})")
    for m in zoo.METHODS:
        fails = collections.Counter(cause(r, m) for r in ok if r[m]["error"])
        first = {}
        for r in ok:
            if r[m]["error"]:
                first.setdefault(cause(r, m), r["seed"])
        nf = sum(fails.values())
        checked = [r for r in ok if r[m]["ok"] is not None]
        bad = [r for r in checked if not r[m]["ok"]]
        skipped = sum(1 for r in ok if r[m].get("skipped"))
        print(f"\n{m}: {len(ok) - skipped} scenes" + (f" ({skipped} skipped: not supported)" if skipped else "")
              + f", {nf} failures to return ({100.0 * nf / max(len(ok) - skipped, 1):.2f} %); "
              f"agreement checked on {len(checked)}, outside the bound on {len(bad)}"
              + (f" (seeds {', '.join(str(r['seed']) for r in bad[:12])}{' ...' if len(bad) > 12 else ''})" if bad else ""))
        for c, k in fails.most_common():
            print(f"    {k:6d}  {c}  (first seed {first[c]})")
        errs = np.array([r[m]["err"] for r in ok if r[m]["err"] is not None])
        rats = np.array([ratio(r[m]) for r in ok if r[m]["err"] is not None])
        if len(errs):
            qs = " ".join(f"q{100 * q:g}={np.quantile(errs, q):.2e}" for q in QUANTILES)
            print(f"    agreement error / L ({len(errs)} scenes with a reference): {qs}")
            fin = rats[np.isfinite(rats)]
            qs = " ".join(f"q{100 * q:g}={np.quantile(fin, q):.2e}" for q in QUANTILES) if len(fin) else "-"
            print(f"    error / bound: {qs}")
            worst = sorted((r for r in ok if r[m]["err"] is not None), key=lambda r: -ratio(r[m]))[:args.worst]
            for r in worst:
                print(f"    worst: seed {r['seed']:6d} err {r[m]['err']:.2e} bound {r[m]['est']:.2e} "
                      f"{r['tags']['dof']} {r['tags']['motion']} stops={r['tags']['stops']}")
    secs = np.array([r["seconds"] for r in ok])
    if len(secs):
        print(f"\nseconds per scene (all methods, all runs): median {np.median(secs):.3f}, max {secs.max():.1f} "
              f"(seed {ok[int(np.argmax(secs))]['seed']})")

    with open(args.csv, "w", newline="") as f:
        w = csv.writer(f)
        head = ["seed", "dof", "motion", "stops", "grip_ratio", "mu", "L", "t_end", "ref_err", "ref_jump", "seconds"]
        for m in zoo.METHODS:
            head += [f"{m}_error", f"{m}_err", f"{m}_bound", f"{m}_ok"]
        w.writerow(head)
        for r in rows:
            if r["gen_error"]:
                w.writerow([r["seed"], "generator error: " + r["gen_error"]])
                continue
            t = r["tags"]
            line = [r["seed"], t["dof"], t["motion"], t["stops"], t["grip_ratio"], t["mu"], r["L"], r["t_end"],
                    r["ref_est"], r["jump"], f"{r['seconds']:.3f}"]
            for m in zoo.METHODS:
                line += [r[m]["error"] or "", r[m]["err"], r[m]["est"], r[m]["ok"]]
            w.writerow(line)
    print(f"CSV: {args.csv}")


if __name__ == "__main__":
    main()

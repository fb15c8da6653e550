"""Digests of the event and regularised runs over the scene zoo, to show which
runs a change alters and by how much.

    python benchmarks/zoo_hash.py --n 300 --jobs 2 --out before.json
    python benchmarks/zoo_hash.py --n 300 --jobs 2 --out after.json --compare before.json

Runs, for seeds ``seed .. seed + n - 1``, the zoo scene (tests/zoo.py,
``zoo.zoo_scene``) and the zoo-inputs scene (tests/scenarios/test_zoo_inputs.py,
``input_scene``) of each seed with the event and the regularised method
(``zoo.run``: the scene's own tolerances and output grid). Each run's digest
is the SHA-256 of its outputs t, q, v, wrench and stick (their bytes, in that
order) or of its error message; it prints the number of runs, the digest of
all of them together and, with ``--compare``, every run whose digest differs
from the file's, with the largest difference of q over the run relative to
the scene's length L (and of v relative to L / tau) and the largest
distance of the pose over the run (zoo.pose_distance: max(|dx|, |dy|,
radius |dtheta|) / L, so an angle counts as the displacement of the
outline's farthest vertex; q / L divides an angle in rad by a length, which
overstates a turn by 1 / radius). ``--out`` writes one record per run
(source, seed, method, digest, error, L, tau, radius, q, v and pose) as JSON.
"""
from __future__ import annotations

import argparse
import hashlib
import json
import multiprocessing
import os
import sys
import warnings

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "tests"))
sys.path.insert(0, os.path.join(HERE, "..", "tests", "scenarios"))

import zoo  # noqa: E402
import test_zoo_inputs  # noqa: E402

METHODS = ("event", "regularised")
SOURCES = ("zoo", "zoo-inputs")


def scene_of(source, seed):
    """The zoo scene of ``seed`` from ``source`` (a zoo.ZooScene)."""
    return zoo.zoo_scene(seed) if source == "zoo" else test_zoo_inputs.input_scene(seed).zs


def one(job):
    """Run one (source, seed, method); a plain dict for the parent."""
    source, seed, method = job
    warnings.simplefilter("ignore")
    rec = dict(source=source, seed=seed, method=method, error=None, q=None, v=None, pose=None)
    h = hashlib.sha256()
    try:
        zs = scene_of(source, seed)
        rec.update(L=zs.L, tau=zs.tau, radius=zs.radius)
        res = zoo.run(zs, method)
        for a in (res.t, res.q, res.v, res.wrench, res.stick):
            h.update(np.ascontiguousarray(a).tobytes())
        rec.update(q=np.asarray(res.q).tolist(), v=np.asarray(res.v).tolist(), pose=np.asarray(res.pose).tolist())
    except Exception as e:  # noqa: BLE001 - an error is a result too
        rec["error"] = f"{type(e).__name__}: {e}"
        h.update(rec["error"].encode())
    rec["digest"] = h.hexdigest()
    return rec


def key(r):
    return (r["source"], r["seed"], r["method"])


def largest(a, b, scale):
    """Largest |a - b| / scale over the run (inf when the shapes differ)."""
    if a is None or b is None:
        return float("nan")
    a, b = np.asarray(a), np.asarray(b)
    if a.shape != b.shape:
        return float("inf")
    return float(np.max(np.abs(a - b))) / scale if a.size else 0.0


def largest_pose(a, b, L, radius):
    """Largest pose distance over the run, max(|dx|, |dy|, radius |dtheta|) / L
    (nan without poses, inf when the shapes differ)."""
    if a is None or b is None or radius is None:
        return float("nan")
    a, b = np.asarray(a), np.asarray(b)
    if a.shape != b.shape:
        return float("inf")
    if not a.size:
        return 0.0
    d = np.abs(a - b)
    return float(max(d[:, 0].max(), d[:, 1].max(), radius * d[:, 2].max())) / L


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--n", type=int, default=300, help="number of seeds")
    p.add_argument("--seed", type=int, default=0, help="first seed")
    p.add_argument("--jobs", type=int, default=1, help="processes")
    p.add_argument("--out", help="write the runs' records (JSON)")
    p.add_argument("--compare", help="a file written by --out: list the runs that differ")
    a = p.parse_args(argv)
    if a.n < 1:
        p.error("--n must be at least 1")
    jobs = [(s, seed, m) for s in SOURCES for seed in range(a.seed, a.seed + a.n) for m in METHODS]
    if a.jobs > 1:
        with multiprocessing.Pool(a.jobs) as pool:
            recs = pool.map(one, jobs, chunksize=4)
    else:
        recs = [one(j) for j in jobs]
    total = hashlib.sha256("".join(r["digest"] for r in recs).encode()).hexdigest()
    print(f"runs: {len(recs)} (errors: {sum(r['error'] is not None for r in recs)})")
    print(f"digest of all runs: {total}")
    if a.out:
        with open(a.out, "w") as f:
            json.dump(recs, f)
    if a.compare:
        with open(a.compare) as f:
            old = {key(r): r for r in json.load(f)}
        changed = [r for r in recs if key(r) in old and old[key(r)]["digest"] != r["digest"]]
        print(f"changed: {len(changed)} of {sum(key(r) in old for r in recs)} runs compared")
        for r in changed:
            o = old[key(r)]
            dq = largest(o["q"], r["q"], r.get("L", 1.0))
            dv = largest(o["v"], r["v"], r.get("L", 1.0) / r.get("tau", 1.0))
            dp = largest_pose(o.get("pose"), r.get("pose"), r.get("L", 1.0), r.get("radius"))
            err = "" if o["error"] == r["error"] else f"  error {o['error']!r} -> {r['error']!r}"
            print(f"  {r['source']:10s} {r['seed']:5d} {r['method']:11s} max|dq|/L {dq:.3g}  "
                  f"max|dv|/(L/tau) {dv:.3g}  max pose/L {dp:.3g}{err}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

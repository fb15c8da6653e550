"""Hashes of every method's runs over obstacle scenes, and their comparison:
the proof that a change of the obstacle rows changes no result, or which.

    python benchmarks/obstacle_hashes.py run OUT.npz [--n-inputs 320] [--n-zoo 400] [--n-disc 255]
    python benchmarks/obstacle_hashes.py compare BEFORE.npz AFTER.npz

Scenes (a pure function of the counts): the first --n-inputs zoo-inputs
scenes with an obstacle (tests/scenarios/test_zoo_inputs.py's input_scene),
the zoo scenes 0 .. --n-zoo - 1 (tests/zoo.py) with their stops replaced by
zoo.obstacle (a box, a rod or a wedge, frictionless or mu 0.5), and the first
--n-disc zoo scenes that are not translations with the body replaced by a
cylinder of the outline's radius (a disc outline) and zoo.obstacle added.
Each runs with every method (zoo.run, 200 output steps); ``run`` stores the
sha256 of (t, q, v, wrench, stick, stop_force) per run (an error's type and
message in its place) and the arrays; ``compare`` prints how many runs are
bit-identical and, for each changed one, the largest difference per field
(absolute, and relative to max(|value|, 1)).
"""
import argparse
import collections
import hashlib
import os
import sys
import time
import warnings

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path[:0] = [os.path.join(HERE, "..", "tests"), os.path.join(HERE, "..", "tests", "scenarios")]

import exdex  # noqa: E402
import zoo  # noqa: E402
import test_zoo_inputs  # noqa: E402

METHODS = ("implicit", "explicit", "event", "regularised")
FIELDS = ("t", "q", "v", "wrench", "stick", "stop_force")


def _added(seed, disc):
    zs = zoo.zoo_scene(seed)
    rng = np.random.default_rng([seed, 0x0b57, disc])
    sc = exdex.replace(zs.scene, stops=())
    if disc:
        rad = float(zs.radius)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # the zoo's mass in a cylinder: a plausibility warning by design
            sc = exdex.replace(sc, body=exdex.Body.cylinder(sc.body.mass, rad, 2.0 * rad))
    zs2 = zoo.ZooScene(seed=zs.seed, scene=sc, t_end=zs.t_end, L=zs.L, tau=zs.tau, radius=zs.radius, tags=zs.tags)
    ob, _ = zoo.obstacle(rng, zs2, float(rng.choice([0.0, 0.5])))
    sc = exdex.replace(sc, obstacles=(ob,))
    return zoo.ZooScene(seed=zs.seed, scene=sc, t_end=zs.t_end, L=zs.L, tau=zs.tau, radius=zs.radius, tags=zs.tags)


def scenes(n_inputs, n_zoo, n_disc):
    """(name, ZooScene) of every scene, in a fixed order."""
    k, seed = 0, 0
    while k < n_inputs:
        s = test_zoo_inputs.input_scene(seed).zs
        if s.scene.obstacles:
            yield f"in{seed}", s
            k += 1
        seed += 1
    for seed in range(n_zoo):
        yield f"zoo{seed}", _added(seed, 0)
    k, seed = 0, 0
    while k < n_disc:
        if zoo.zoo_scene(seed).scene.dof != "translation":
            yield f"disc{seed}", _added(seed, 1)
            k += 1
        seed += 1


def run(args):
    keys, hashes, data = [], [], {}
    t0 = time.time()
    for name, zs in scenes(args.n_inputs, args.n_zoo, args.n_disc):
        for m in METHODS:
            key = f"{name}:{m}"
            try:
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")
                    r = zoo.run(zs, m, n_out=200)
                arrs = [np.ascontiguousarray(np.asarray(getattr(r, f), dtype=float)) for f in FIELDS]
                h = hashlib.sha256(b"".join(x.tobytes() for x in arrs)).hexdigest()[:16]
                data[key] = arrs
            except Exception as e:  # an error is an outcome too: its type and message are hashed
                h = "ERR:" + type(e).__name__ + ":" + str(e)[:60]
            keys.append(key)
            hashes.append(h)
    np.savez_compressed(args.out, keys=np.array(keys), hashes=np.array(hashes),
                        **{f"{i}_{f}": x for i, k in enumerate(keys) if k in data for f, x in zip(FIELDS, data[k])})
    print(f"{len(keys)} runs, {sum(h.startswith('ERR') for h in hashes)} errors, {time.time() - t0:.0f} s")


def compare(args):
    a, b = np.load(args.before), np.load(args.after)
    ka = list(a["keys"])
    if ka != list(b["keys"]):
        sys.exit("the two files hold different runs")
    changed = []
    for i, k in enumerate(ka):
        if a["hashes"][i] == b["hashes"][i]:
            continue
        if f"{i}_t" not in a or f"{i}_t" not in b or any(a[f"{i}_{f}"].shape != b[f"{i}_{f}"].shape for f in FIELDS):
            changed.append((k, f"{a['hashes'][i][:40]} -> {b['hashes'][i][:40]}"))
            continue
        parts = []
        for f in FIELDS:
            x, y = a[f"{i}_{f}"], b[f"{i}_{f}"]
            d = np.abs(x - y)
            if d.size and np.nanmax(d) > 0:
                parts.append(f"{f} {np.nanmax(d):.2g} (rel {np.nanmax(d / np.maximum(np.abs(x), 1.0)):.2g})")
        changed.append((k, "; ".join(parts)))
    print(f"{len(ka)} runs, {len(ka) - len(changed)} bit-identical, {len(changed)} changed")
    print("changed per method:", dict(collections.Counter(k.split(":")[1] for k, _ in changed)))
    print("changed per scene set:", dict(collections.Counter(k.split(":")[0].rstrip("0123456789") for k, _ in changed)))
    for k, what in changed:
        print(f"  {k}: {what}")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sub = ap.add_subparsers(dest="cmd", required=True)
    r = sub.add_parser("run")
    r.add_argument("out")
    r.add_argument("--n-inputs", type=int, default=320)
    r.add_argument("--n-zoo", type=int, default=400)
    r.add_argument("--n-disc", type=int, default=255)
    c = sub.add_parser("compare")
    c.add_argument("before")
    c.add_argument("after")
    args = ap.parse_args(argv)
    run(args) if args.cmd == "run" else compare(args)


if __name__ == "__main__":
    main()

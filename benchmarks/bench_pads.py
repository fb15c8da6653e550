"""Pads on the fingers (exdex.Pad) against the patch fixed on the object.

Two parts:

  * the peer's scene (FrictionModelling, tests/planar_slip_stick.py: a 0.15 x
    0.08 m box of 0.2 kg on two 2 cm square pads, its centre of mass 2 mm
    beside the pad centre, gravity in the plate plane, grip 1.73 + 0.91 sin(4
    pi t) N per finger, mu 1, 2 s) with the patch fixed on the object and with
    pads on the fingers (every planar method), against the peer's own
    trajectory (tests/data/peer_planar_slip_stick.csv, its provenance in the
    file's header): final rotation, x at the end and its range, y at the end.
    Chart and table: --results (default benchmarks/results/) peer_pads.png,
    peer_pads.txt.
  * speed: ns per step of a planar slip-stick run with pads on the fingers
    against the same run with the patch (the implicit method at dt = 1e-4,
    the event method per run), measured alternately in one run; medians of
    the per-repeat ratio.

Usage:

    python benchmarks/bench_pads.py [--repeat 7] [--results DIR] [--no-plot] [--speed-only | --peer-only]
"""
import argparse
import math
import os
import statistics
import time
import warnings

import numpy as np

import exdex

HERE = os.path.dirname(os.path.abspath(__file__))
PEER = os.path.join(HERE, "..", "tests", "data", "peer_planar_slip_stick.csv")
METHODS = ("implicit", "event", "regularised", "explicit")


def peer_scene(pad=True, t_end=2.0, mu_static=None, limit_surface="ellipsoid"):
    """The peer's scene: B's x along the box's long side, gravity -9.81 along B's y."""
    t = np.linspace(0.0, t_end, 4001)
    sched = exdex.GripSchedule(times=t, forces=1.73 + 0.91 * np.sin(4 * np.pi * t), kind="cubic")
    body = exdex.Body.box(0.2, (0.15, 0.08, 0.02))
    # the patch of the patch-on-object model: the pad's square, centred where
    # the pad is at t = 0 (2 mm beside the centre of mass)
    grasp = exdex.Grasp(mu=1.0, grip_force=sched, patch=exdex.Patch.rectangle(0.02, 0.02, center=(-0.002, 0.0)),
                        pad=exdex.Pad.rectangle(0.02, 0.02) if pad else None, mu_static=mu_static,
                        limit_surface=limit_surface)
    return exdex.Scene(body=body, grasp=grasp, dof="planar", q0=(0.002, 0.0, 0.0), gravity=(0.0, -9.81, 0.0),
                       gripper_rotation=np.eye(3))


def load_peer(path=PEER):
    with open(path) as f:
        rows = [line.strip().split(",") for line in f if line.strip() and not line.startswith("#")]
    cols = np.array(rows[1:], dtype=float)
    return {k: cols[:, i] for i, k in enumerate(rows[0])}


def run(scene, method):
    dt = 1e-4 if method in ("implicit", "explicit") else 1e-3
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", exdex.PhysicsWarning)
        return exdex.simulate(scene, 2.0, dt, method=method)


def summary(t, x, y, th):
    return dict(theta_end=math.degrees(th[-1]), x_end=x[-1] * 1e3, x_min=float(np.min(x)) * 1e3,
                x_max=float(np.max(x)) * 1e3, y_end=y[-1] * 1e3)


def peer_part(results, plot):
    rows = []
    runs = {}
    for ls in ("ellipsoid", "exact"):
        for pad in (False, True):
            # the exact surface: every planar method but the regularised one
            for m in METHODS if ls == "ellipsoid" else ("implicit", "event", "explicit"):
                r = run(peer_scene(pad, limit_surface=ls), m)
                runs[("pads" if pad else "patch", m) + ((ls,) if ls == "exact" else ())] = r
                rows.append((f"exdex, {'pads on the fingers' if pad else 'patch on the object'}, {ls}", m,
                             summary(r.t, r.q[:, 0], r.q[:, 1], r.q[:, 2])))
    # the peer's LuGre breaks away at mu_s = 1.2 (its Stribeck curve falls to mu_c = 1 by v_s = 1 mm/s)
    r = run(peer_scene(True, mu_static=1.2), "event")
    runs[("pads-static", "event")] = r
    rows.append(("exdex, pads on the fingers, ellipsoid, mu_static 1.2", "event", summary(r.t, r.q[:, 0], r.q[:, 1], r.q[:, 2])))
    peer = load_peer()
    rows.append(("FrictionModelling, distributed LuGre (21 x 21)", "its own", summary(peer["t"], peer["x"], peer["y"], peer["theta"])))
    rows.append(("FrictionModelling, reduced LuGre", "its own",
                 summary(peer["t"], peer["x_reduced"], peer["y_reduced"], peer["theta_reduced"])))
    lines = ["model | method | final rotation [deg] | x at 2 s [mm] | x range [mm] | y at 2 s [mm]", "|".join(["---"] * 6)]
    for name, m, s in rows:
        lines.append(f"{name} | {m} | {s['theta_end']:.2f} | {s['x_end']:.2f} | {s['x_min']:.2f} .. {s['x_max']:.2f} "
                     f"| {s['y_end']:.2f}")
    text = "\n".join(lines)
    print(text)
    os.makedirs(results, exist_ok=True)
    with open(os.path.join(results, "peer_pads.txt"), "w") as f:
        f.write("python benchmarks/bench_pads.py (peer scene; patch and pads, the ellipsoid and the exact limit "
                "surface)\n\n" + text + "\n")
    if plot:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, axes = plt.subplots(3, 1, figsize=(7, 7), sharex=True)
        series = [("patch on the object, ellipsoid (event)", runs[("patch", "event")], "C0"),
                  ("pads on the fingers, ellipsoid (event)", runs[("pads", "event")], "C1"),
                  ("pads on the fingers, exact surface (event)", runs[("pads", "event", "exact")], "C3"),
                  ("pads on the fingers, ellipsoid, mu_static 1.2 (event)", runs[("pads-static", "event")], "C2")]
        for label, r, c in series:
            axes[0].plot(r.t, r.q[:, 0] * 1e3, c, label=label, lw=1.2)
            axes[1].plot(r.t, r.q[:, 1] * 1e3, c, lw=1.2)
            axes[2].plot(r.t, np.degrees(r.q[:, 2]), c, lw=1.2)
        for k, (col, lab) in enumerate((("x", "x [mm]"), ("y", "y [mm]"), ("theta", "theta [deg]"))):
            v = peer[col] * (1e3 if k < 2 else 1.0)
            axes[k].plot(peer["t"], np.degrees(v) if k == 2 else v, "k--", lw=1.0,
                         label="FrictionModelling (distributed LuGre)" if k == 0 else None)
            axes[k].set_ylabel(lab)
        axes[0].legend(fontsize=7)
        axes[2].set_xlabel("t [s]")
        fig.suptitle("The peer's slip-stick scene: a 0.15 x 0.08 m box on 2 cm square pads", fontsize=9)
        fig.tight_layout()
        fig.savefig(os.path.join(results, "peer_pads.png"), dpi=110)
        plt.close(fig)


def speed_part(repeat):
    out = []
    for method, dt in (("implicit", 1e-4), ("event", 1e-3)):
        scenes = {"patch": peer_scene(False), "pads": peer_scene(True)}
        models = {k: exdex.Model(s, method=method) for k, s in scenes.items()}
        ns = {k: [] for k in models}
        ratios = []
        for k, mo in models.items():
            mo.simulate(2.0, dt)   # warm-up
        for _ in range(repeat):
            per = {}
            for k, mo in models.items():
                t0 = time.perf_counter()
                r = mo.simulate(2.0, dt)
                per[k] = (time.perf_counter() - t0) / r.stats["steps"] * 1e9
                ns[k].append(per[k])
            ratios.append(per["pads"] / per["patch"])
        out.append((method, statistics.median(ns["patch"]), statistics.median(ns["pads"]), statistics.median(ratios)))
    print("\nmethod | patch [ns/step] | pads [ns/step] | ratio pads / patch (median of per-repeat ratios)")
    print("---|---|---|---")
    for m, a, b, q in out:
        print(f"{m} | {a:.0f} | {b:.0f} | {q:.2f}")
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--repeat", type=int, default=7)
    ap.add_argument("--results", default=os.path.join(HERE, "results"))
    ap.add_argument("--no-plot", action="store_true")
    ap.add_argument("--speed-only", action="store_true")
    ap.add_argument("--peer-only", action="store_true")
    a = ap.parse_args(argv)
    if not a.speed_only:
        peer_part(a.results, not a.no_plot)
    if not a.peer_only:
        speed_part(a.repeat)


if __name__ == "__main__":
    main()

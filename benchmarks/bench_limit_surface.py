"""The exact limit surface against the ellipsoid: cost per step, and the
ellipsoid's error in the force-motion map (Grasp.limit_surface).

    python benchmarks/bench_limit_surface.py [--repeat 7]
        nanoseconds per planar step with limit_surface="exact" and
        "ellipsoid" (the same scenes, implicit and event), measured
        alternately in one run: medians and the ratio of the medians;
        written to --results (default benchmarks/results/limit_surface.txt).
    python benchmarks/bench_limit_surface.py --errors [--out DIR]
        the ellipsoid's force-motion error against the exact surface over
        the centre of rotation, for a uniform disc and a square: for the
        slip twist of a rotation about the centre c (and the limit of pure
        translation), the angle between the two friction wrenches (force and
        moment scaled by the patch's size) and the ratios of their forces and
        of their moments; a table printed and the figure
        limit_surface_error.png in --out (default benchmarks/results); then
        the free sliding and spinning disc under each surface.
    python benchmarks/bench_limit_surface.py --baseline PYTHON [--repeat 7]
        the ellipsoid paths of this exdex against another install's (PYTHON:
        the interpreter of a virtual environment with another exdex, e.g. an
        older revision's .venv/bin/python): the same scenes in both, one run
        of each in turn, medians of ns/step and of the per-pair ratio.
    python benchmarks/bench_limit_surface.py --check PYTHON [--repeat 7]
        the speed targets side by side in one run, each variant a process of
        its own in turn (A B C D E, A B C D E, ...; CPU time of each, the
        best of 5 runs in the process): this exdex's ellipsoid
        against PYTHON's (an exdex from before pads and the limit surface),
        the exact surface, and pads on the fingers (the box with a pad where
        its patch is; the peer's scene of bench_pads.py) with each surface;
        medians of ns/step and of the per-round ratios exact/ellipsoid,
        pads/patch (ellipsoid, against this exdex's patch and the older
        one's) and this/baseline; written to
        benchmarks/results/limit_surface_check.txt.

The scenes: a box held by an off-centre rectangular patch under tilted
gravity in a gripper that moves (Eq. 7), which sticks, slides and sticks
again; and a free disc sliding and spinning to rest.
"""
import argparse
import math
import os
import statistics
import subprocess
import sys
import time
import warnings

import numpy as np

import exdex

HERE = os.path.dirname(os.path.abspath(__file__))


def scenes(limit_surface):
    # the default left out: an older exdex (--baseline) builds the same scenes
    ls = {} if limit_surface == "ellipsoid" else {"limit_surface": limit_surface}
    a = math.radians(20)
    box = exdex.Scene(
        body=exdex.Body.box(0.1, (0.06, 0.04, 0.02)),
        grasp=exdex.Grasp(mu=0.5, grip_force=1.1, patch=exdex.Patch.rectangle(0.02, 0.03, center=(0.004, 0.002)),
                          **ls),
        motion=exdex.AsymmetricProfile(0.05, 0.5, 0.8, axis=(1, 0, 0)),
        gravity=(9.81 * math.sin(a), 0.0, -9.81 * math.cos(a)),
        dof="planar",
    )
    R = 0.02
    disc = exdex.Scene(
        body=exdex.Body(mass=1.0, inertia=np.diag([R * R / 4, R * R / 4, R * R / 2])),
        grasp=exdex.Grasp(mu=0.5, grip_force=1.0, patch=exdex.Patch.disc(R), **ls),
        dof="planar", gravity=(0.0, 0.0, 0.0), v0=(0.8, 0.0, 40.0),
    )
    return {"box, moving gripper": (box, 1.0), "free disc": (disc, 1.2)}


# (method, dt): the implicit method's steps are the output samples; the event
# method's cost is per output sample of the same grid
RUNS = (("implicit", 1e-4), ("event", 1e-3))


def one_run(scene, t_end, method, dt, clock=time.perf_counter):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")   # the scenes' physics warnings are not the point here
        t0 = clock()
        exdex.simulate(scene, t_end, dt, method=method)
    return (clock() - t0) / round(t_end / dt) * 1e9


def cost(repeat, out_path):
    lines = [f"ns per output step, median of {repeat} runs (exact and ellipsoid alternately in one run)",
             f"{'scene':<22} {'method':<9} {'ellipsoid':>12} {'exact':>12} {'exact/ellipsoid':>16}"]
    ell, exa = scenes("ellipsoid"), scenes("exact")
    for name in ell:
        for method, dt in RUNS:
            (se, t_end), (sx, _) = ell[name], exa[name]
            one_run(se, t_end, method, dt), one_run(sx, t_end, method, dt)   # warm-up
            a, b = [], []
            for _ in range(repeat):
                a.append(one_run(se, t_end, method, dt))
                b.append(one_run(sx, t_end, method, dt))
            ma, mb = statistics.median(a), statistics.median(b)
            lines.append(f"{name:<22} {method:<9} {ma:>12.0f} {mb:>12.0f} {mb / ma:>16.2f}")
    text = "\n".join(lines)
    print(text)
    if out_path:
        os.makedirs(os.path.dirname(out_path), exist_ok=True)
        with open(out_path, "w") as f:
            f.write(text + "\n")


def _wrench_angle(a, b, L):
    s = np.array([1.0, 1.0, 1.0 / L])
    a, b = a * s, b * s
    c = float(np.dot(a, b) / (np.linalg.norm(a) * np.linalg.norm(b)))
    return math.degrees(math.acos(max(-1.0, min(1.0, c))))


def errors(out_dir):
    """The ellipsoid (e_r the patch's) against the exact surface for
    rotations about centres at distance rho along x (the disc: every
    direction alike) or along the diagonal (the square)."""
    patches = {"disc R": (exdex.Patch.disc(0.01), 0.01, (1.0, 0.0)),
               "square a (half-side)": (exdex.Patch.rectangle(0.02, 0.02), 0.01, (math.sqrt(0.5), math.sqrt(0.5)))}
    rhos = np.concatenate([[0.0], np.geomspace(1e-3, 1e3, 121)])
    rows, curves = [], {}
    for name, (patch, L, d) in patches.items():
        ang, fr, mr = [], [], []
        for rho in rhos:
            c = rho * L * np.array(d)
            u = (c[1], -c[0], 1.0)   # rotation about c at unit rate
            we, _ = patch.friction_wrench(u, "ellipsoid")
            wx, _ = patch.friction_wrench(u, "exact")
            ang.append(_wrench_angle(we, wx, L))
            fx, fe = np.hypot(*wx[:2]), np.hypot(*we[:2])
            fr.append(fe / fx if fx > 0 else float("nan"))
            mr.append(we[2] / wx[2] if wx[2] != 0 else float("nan"))
        ut = (d[1], -d[0], 1e-9)   # the limit of a pure translation
        we, _ = patch.friction_wrench(ut, "ellipsoid")
        wx, _ = patch.friction_wrench(ut, "exact")
        curves[name] = (np.array(ang), np.array(fr), np.array(mr))
        k1 = int(np.argmin(np.abs(rhos - 1.0)))
        rows.append((name, max(ang), float(rhos[int(np.argmax(ang))]), fr[1], mr[k1], we[2] / wx[2]))
    print("ellipsoid against exact, a rotation about a centre at distance rho (units of R or a):")
    print(f"{'patch':<22} {'largest angle [deg]':>20} {'at rho':>8} {'force ratio rho->0':>19} "
          f"{'moment ratio rho=1':>19} {'moment ratio rho->inf':>22}")
    for name, amax, at, f0, m1, minf in rows:
        print(f"{name:<22} {amax:>20.2f} {at:>8.3g} {f0:>19.4f} {m1:>19.4f} {minf:>22.4f}")
    free_disc()
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("matplotlib is not installed: no figure")
        return
    fig, ax = plt.subplots(1, 3, figsize=(13, 3.8))
    x = np.maximum(rhos, 1e-3)
    for name, (ang, fr, mr) in curves.items():
        ax[0].semilogx(x, ang, label=name)
        ax[1].semilogx(x, fr, label=name)
        ax[2].semilogx(x, mr, label=name)
    ax[0].set_ylabel("angle between the wrenches [deg]")
    ax[1].set_ylabel("|f| ellipsoid / |f| exact")
    ax[2].set_ylabel("m ellipsoid / m exact")
    for a in ax:
        a.set_xlabel("distance of the centre of rotation / R (or a)")
        a.grid(True, which="both", alpha=0.3)
    ax[0].legend()
    fig.suptitle("The ellipsoid's force-motion map against the exact surface (uniform pressure)")
    fig.tight_layout()
    os.makedirs(out_dir, exist_ok=True)
    path = os.path.join(out_dir, "limit_surface_error.png")
    fig.savefig(path, dpi=110)
    print(f"wrote {path}")


def free_disc():
    """The free sliding and spinning disc (v0 = R w0), event method: v / (R w)
    late in the slip and the instant both motions stop, for each surface."""
    sc0, t_end = scenes("ellipsoid")["free disc"]
    R, w0 = 0.02, sc0.v0[2]
    print("free uniform disc launched at v0 = R w0, event method:")
    print(f"{'surface':<10} {'v/(R w) at w = 1e-3 w0':>24} {'stops at [s]':>13}")
    for ls in ("ellipsoid", "exact"):
        sc, _ = scenes(ls)["free disc"]
        sc = exdex.replace(sc, v0=(R * w0, 0.0, w0))
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            r = exdex.simulate(sc, 2.0, 1e-4, method="event", rtol=1e-10, atol=1e-12)
        v, w = np.hypot(r.v[:, 0], r.v[:, 1]), np.abs(r.v[:, 2])
        i = np.nonzero(w > 1e-3 * w0)[0][-1]
        stop = r.t[np.nonzero((v == 0) & (w == 0))[0][0]]
        print(f"{ls:<10} {v[i] / (R * w[i]):>24.4f} {stop:>13.4f}")


_CHILD = r"""
import sys, time, json
sys.path.insert(0, sys.argv[1])
import bench_limit_surface as b
name, method, dt = sys.argv[2], sys.argv[3], float(sys.argv[4])
sc, t_end = b.scenes("ellipsoid")[name]
b.one_run(sc, t_end, method, dt)
print(json.dumps(min(b.one_run(sc, t_end, method, dt) for _ in range(3))))
"""


def check_scene(name, variant):
    """The --check scenes: "box" and "disc" of scenes(), and the peer's
    scene of bench_pads.py; variant "ellipsoid" (written as an older exdex
    reads it), "exact", "pad-ellipsoid" or "pad-exact" (pads: box and
    peer)."""
    ls = "exact" if variant.endswith("exact") else "ellipsoid"
    if name == "peer":
        t = np.linspace(0.0, 2.0, 4001)
        sched = exdex.GripSchedule(times=t, forces=1.73 + 0.91 * np.sin(4 * np.pi * t), kind="cubic")
        kw = {} if variant == "ellipsoid" else {"limit_surface": ls}
        if variant.startswith("pad"):
            kw["pad"] = exdex.Pad.rectangle(0.02, 0.02)
        g = exdex.Grasp(mu=1.0, grip_force=sched, patch=exdex.Patch.rectangle(0.02, 0.02, center=(-0.002, 0.0)),
                        **kw)
        return exdex.Scene(body=exdex.Body.box(0.2, (0.15, 0.08, 0.02)), grasp=g, dof="planar",
                           q0=(0.002, 0.0, 0.0), gravity=(0.0, -9.81, 0.0), gripper_rotation=np.eye(3)), 2.0
    sc, t_end = scenes(ls)["box, moving gripper" if name == "box" else "free disc"]
    if variant.startswith("pad"):
        # the pad where the patch is at t = 0 (q0 = 0: B and C coincide)
        p = sc.grasp.patch
        pad = exdex.Pad.rectangle(*p.dims, center=p.center)
        sc = exdex.replace(sc, grasp=exdex.replace(sc.grasp, pad=pad))
    return sc, t_end


_CHECK_CHILD = r"""
import sys, json, time
sys.path.insert(0, sys.argv[1])
import bench_limit_surface as b
name, variant, method, dt = sys.argv[2], sys.argv[3], sys.argv[4], float(sys.argv[5])
sc, t_end = b.check_scene(name, variant)
b.one_run(sc, t_end, method, dt)
print(json.dumps(min(b.one_run(sc, t_end, method, dt, time.process_time) for _ in range(5))))
"""


def check(python, repeat, out_path=None):
    """Issue 24's speed targets in one run (see the module's doc); the table
    also written to out_path."""
    import json
    lines = []

    def say(text):
        print(text, flush=True)
        lines.append(text)

    def child(py, name, variant, method, dt):
        cmd = [py, "-c", _CHECK_CHILD, HERE, name, variant, method, str(dt)]
        return json.loads(subprocess.run(cmd, check=True, capture_output=True, text=True).stdout)

    say(f"CPU ns per output step (process time: the shared machine's waits for a core left out); each figure "
        f"a process (the best of 5 runs in it), the variants in turn, {repeat} rounds; baseline {python}")
    say(f"{'scene':<6} {'method':<9} {'ell':>8} {'ell old':>8} {'exact':>8} {'pad ell':>8} {'pad ex':>8} "
          f"{'ell/old':>8} {'ex/ell':>7} {'pad/ell':>8} {'pad/old':>8} {'padx/pad':>9}")
    for name in ("box", "disc", "peer"):
        pads = name != "disc"
        for method, dt in RUNS:
            cols = {k: [] for k in ("ell", "old", "exact", "pad", "padx")}
            for _ in range(repeat):
                cols["ell"].append(child(sys.executable, name, "ellipsoid", method, dt))
                cols["old"].append(child(python, name, "ellipsoid", method, dt))
                cols["exact"].append(child(sys.executable, name, "exact", method, dt))
                if pads:
                    cols["pad"].append(child(sys.executable, name, "pad-ellipsoid", method, dt))
                    cols["padx"].append(child(sys.executable, name, "pad-exact", method, dt))

            def med(k):
                return statistics.median(cols[k]) if cols[k] else float("nan")

            def ratio(a, b):
                return statistics.median(x / y for x, y in zip(cols[a], cols[b])) if cols[a] else float("nan")

            say(f"{name:<6} {method:<9} {med('ell'):>8.0f} {med('old'):>8.0f} {med('exact'):>8.0f} "
                f"{med('pad'):>8.0f} {med('padx'):>8.0f} {ratio('ell', 'old'):>8.3f} {ratio('exact', 'ell'):>7.2f} "
                f"{ratio('pad', 'ell'):>8.2f} {ratio('pad', 'old'):>8.2f} {ratio('padx', 'pad'):>9.2f}")
    if out_path:
        os.makedirs(os.path.dirname(out_path), exist_ok=True)
        with open(out_path, "w") as f:
            f.write("\n".join(lines) + "\n")


def baseline(python, repeat):
    """This exdex's ellipsoid paths against another install's, in turn."""
    import json
    print(f"ellipsoid paths, ns per output step: this exdex ({sys.executable}) against {python}; "
          f"median of {repeat} pairs (each run the best of 3)")
    print(f"{'scene':<22} {'method':<9} {'this':>10} {'baseline':>10} {'this/baseline':>14}")
    for name in scenes("ellipsoid"):
        for method, dt in RUNS:
            a, b, r = [], [], []
            for _ in range(repeat):
                x = json.loads(subprocess.run([sys.executable, "-c", _CHILD, HERE, name, method, str(dt)],
                                              check=True, capture_output=True, text=True).stdout)
                y = json.loads(subprocess.run([python, "-c", _CHILD, HERE, name, method, str(dt)],
                                              check=True, capture_output=True, text=True).stdout)
                a.append(x), b.append(y), r.append(x / y)
            print(f"{name:<22} {method:<9} {statistics.median(a):>10.0f} {statistics.median(b):>10.0f} "
                  f"{statistics.median(r):>14.3f}")


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--repeat", type=int, default=7)
    p.add_argument("--errors", action="store_true")
    p.add_argument("--out", default=os.path.join(HERE, "results"))
    p.add_argument("--results", default=os.path.join(HERE, "results", "limit_surface.txt"))
    p.add_argument("--baseline", metavar="PYTHON")
    p.add_argument("--check", metavar="PYTHON")
    args = p.parse_args()
    if args.errors:
        errors(args.out)
    elif args.check:
        check(args.check, args.repeat, os.path.join(HERE, "results", "limit_surface_check.txt"))
    elif args.baseline:
        baseline(args.baseline, args.repeat)
    else:
        cost(args.repeat, args.results)


if __name__ == "__main__":
    main()

"""The certificate's cost: a reduced run with and without it, side by side.

Each case is compiled once (``exdex.Model``); ``Model.simulate(t_end, dt,
certify=...)`` is timed alternately with and without the check, after a
warm-up, and the table gives the medians and the extra time in percent of
the uncertified run (CPU time of the process, time.process_time: wall
times on a shared machine mostly measure the wait for a core), both for the whole call (``exdex.Model.simulate``: the
C run, the Result and the physics-warning checks) and for the C core alone
(the compiled model's run returning its arrays). The cases are reduced scenes whose reduction holds over
the whole run (a failing one stops checking at its failure, so it costs
less): the paper's Figs. 3 and 4, a box held still below its turning
threshold, a translation in a gripper that turns (Eq. 7 about the plate
normal, the load changes with time and state) and Fig. 6's rotation with
gravity along the plate normal (a slipping rotation), and scenes without a
phase proof: shakes (translating, and turning about the plate normal), a
sampled log and a chain of motions, and rotation runs in those (the box
held about a pivot off its centre of mass; Fig. 6's object spun, slipping,
in a shake along the plate normal; the box in a log and a chain that turn the
gripper). Where a piece between switching times is
proven for a mode (a constant load, or the bound of a gripper turning about
a fixed axis; csrc/certify.c), or a block of samples in a gripper that does
not turn (the box of its acceleration, for a rotation with the block's
angles and rates), its samples of that mode are not
evaluated; the others are, one by one. The last column is the core with
every sample evaluated (``every_sample=True``, the proofs' reference: the
certificate's cost on scenes without a phase proof before the block proofs).
The column "as it goes" is the core certifying as the run goes
(``stop_at_failure=True``, a window of samples at a time, the run stopping
where the reduction fails: what ``dof="auto"`` runs).
A table times ``dof="auto"`` against the scene's own 1-DoF model on
the paper's Figs. 3 and 4 (auto runs that model, its certificate holding),
and a last one times it on scenes that escalate (the reduction fails
mid-run and the planar model goes on from there) against the planar run
from t = 0, with the C core's share: the 1-DoF candidates (each ending
where its certificate fails) and the planar run from the switch.

    python benchmarks/bench_certify.py [--repeat N] [--out results/certify.txt] [--only TEXT]
"""
import argparse
import math
import os
import statistics
import sys
import time
import warnings

import numpy as np

import exdex
from exdex import paper

HERE = os.path.dirname(os.path.abspath(__file__))


def cases():
    box = exdex.Scene(body=exdex.Body.box(0.2, (0.15, 0.08, 0.03)),
                      grasp=exdex.Grasp(mu=1.0, grip_force=3.0, patch=exdex.Patch.rectangle(0.02, 0.02,
                                                                                          center=(0.02, 0.0))))
    turning = exdex.Scene(body=exdex.Body.box(0.1, (0.06, 0.03, 0.02)),
                          grasp=exdex.Grasp(mu=0.8, grip_force=2.0, patch=exdex.Patch.rectangle(0.02, 0.02)),
                          motion=exdex.AsymmetricProfile(math.radians(30), 0.5, 0.8, axis=(0, -1, 0),
                                                         rotation=True))
    fig6_flat = exdex.replace(paper.fig6_scene(), gravity=(0.0, -9.81, 0.0))
    held = dict(body=exdex.Body.box(0.1, (0.06, 0.03, 0.02)),
                grasp=exdex.Grasp(mu=0.8, grip_force=2.0, patch=exdex.Patch.rectangle(0.02, 0.02, center=(0.005, 0.0))))
    shake = exdex.Scene(motion=exdex.Shake(0.002, 4.0, cycles=4, axis=(1, 0, 0)), **held)
    shake_turn = exdex.Scene(motion=exdex.Shake(0.05, 2.0, cycles=2, axis=(0, 0, 1), rotation=True), **held)
    t = np.linspace(0.0, 1.0, 101)
    pos = np.stack([0.02 * (10 * t ** 3 - 15 * t ** 4 + 6 * t ** 5), 0 * t, 0 * t], 1)
    log = exdex.Scene(motion=exdex.SampledTrajectory(t, pos, np.tile([1.0, 0, 0, 0], (len(t), 1)), relative=True),
                      **held)
    chain = exdex.Scene(motion=exdex.Chain((exdex.Shake(0.002, 4.0, cycles=2, axis=(1, 0, 0)), exdex.Pause(0.2),
                                            exdex.AsymmetricProfile(0.01, 0.3, 0.5, axis=(1, 0, 0)))), **held)
    # rotation runs in a gripper that does not turn: the box held about its pivot 5 mm off the centre of
    # mass (stuck: the pin and the friction carry the weight and the shake), and Fig. 6's object spun at
    # 2 rad/s, gravity and the shake along the plate normal (a slip whose pin carries nothing)
    rot = {k: exdex.replace(v, dof="rotation") for k, v in (("shake", shake), ("log", log), ("chain", chain))}
    spun = exdex.replace(fig6_flat, v0=(0.0, 0.0, 2.0), motion=exdex.Shake(0.002, 4.0, cycles=4, axis=(0, 1, 0)))
    # rotation runs in a gripper that turns: a 100 Hz log turning 0.3 rad about a tilted axis (a smooth
    # step) while it moves 2 cm, and a chain whose last piece is Eq. 7 turning 0.3 rad about that axis
    tilt = np.array([0.3, 0.2, 1.0]) / np.linalg.norm([0.3, 0.2, 1.0])
    step = 10 * t ** 3 - 15 * t ** 4 + 6 * t ** 5
    quats = np.c_[np.cos(0.15 * step), np.sin(0.15 * step)[:, None] * tilt]
    rot["turning log"] = exdex.Scene(motion=exdex.SampledTrajectory(t, pos, quats, relative=True), dof="rotation",
                                     **held)
    rot["turning chain"] = exdex.Scene(motion=exdex.Chain((exdex.Shake(0.002, 4.0, cycles=2, axis=(1, 0, 0)),
                                                           exdex.Pause(0.2),
                                                           exdex.AsymmetricProfile(0.3, 0.3, 0.5, axis=tuple(tilt),
                                                                                   rotation=True))),
                                       dof="rotation", **held)
    out = []
    for method in ("analytic", "implicit", "event"):
        out.append((f"Fig. 3 ({method})", paper.fig3_scene(), method, 1.5, 1e-4))
    for method in ("implicit", "event"):
        out.append((f"Fig. 4 ({method})", paper.fig4_scene(), method, 1.0, 1e-4))
    for method in ("analytic", "implicit", "event", "explicit", "regularised"):
        out.append((f"held box ({method})", box, method, 1.0, 1e-4 if method != "regularised" else 1e-3))
    for method in ("implicit", "event"):
        out.append((f"turning gripper ({method})", turning, method, 1.5, 1e-4))
    for method in ("analytic", "implicit", "event"):
        out.append((f"Fig. 6, g along the normal ({method})", fig6_flat, method, 8.0, 1e-3))
    for method in ("implicit", "event"):
        out.append((f"shake ({method})", shake, method, 1.2, 1e-4))
        out.append((f"turning shake ({method})", shake_turn, method, 1.2, 1e-4))
        out.append((f"log, 100 Hz ({method})", log, method, 1.2, 1e-4))
        out.append((f"chain ({method})", chain, method, 1.2, 1e-4))
    for method in ("implicit", "event", "explicit"):
        out.append((f"rotation, shake ({method})", rot["shake"], method, 1.2, 1e-4))
        out.append((f"rotation, log, 100 Hz ({method})", rot["log"], method, 1.2, 1e-4))
        out.append((f"rotation, chain ({method})", rot["chain"], method, 1.2, 1e-4))
        out.append((f"rotation, spun, normal shake ({method})", spun, method, 1.2, 1e-4))
        out.append((f"rotation, turning log, 100 Hz ({method})", rot["turning log"], method, 1.2, 1e-4))
        out.append((f"rotation, turning chain ({method})", rot["turning chain"], method, 1.2, 1e-4))
    return out


def auto_rows(repeat):
    """dof="auto" against the scene's own 1-DoF model on the paper's cases
    (the same run, bit for bit, where the reduction holds): whole
    exdex.simulate calls, dt 1e-4, medians of ``repeat`` pairs, each pair's
    order alternated."""
    head = [f'dof="auto" against the explicit dof: whole exdex.simulate, dt 1e-4, medians of {repeat} pairs '
            f'(order alternated)',
            f"{'case':40s} {'explicit [ms]':>14s} {'auto [ms]':>10s} {'extra':>7s}"]
    print(head[0])
    print(head[1])
    out = head
    for case, t_end in (("fig3", 1.5), ("fig4", 1.0)):
        sc = getattr(paper, f"{case}_scene")()
        sa = exdex.replace(sc, dof="auto")
        for method in ("implicit", "event"):
            a, b = [], []
            for i in range(repeat):
                for which in ((0, 1) if i % 2 else (1, 0)):
                    t0 = time.process_time()
                    exdex.simulate(sa if which else sc, t_end, 1e-4, method=method)
                    (b if which else a).append(time.process_time() - t0)
            ma, mb = statistics.median(a), statistics.median(b)
            name = f"Fig. {case[3:]} ({method})"
            line = f"{name:40s} {1e3 * ma:14.3f} {1e3 * mb:10.3f} {100 * (mb / ma - 1):6.1f}%"
            print(line, flush=True)
            out.append(line)
    return out


def escalating_cases():
    """Scenes whose reduction fails mid-run: the box pushed across its slide
    axis by Eq. 7 (the second phase beyond the friction capacity, the
    switch at beta T = 0.21 s), and the box held 2 cm off its centre of
    mass while the grip ramps down through its turning threshold (the
    switch near 0.5 s)."""
    mass, mu, w = 0.2, 1.0, 0.2 * 9.81
    T, beta, X1 = 0.3, 0.7, 0.1
    aH, aL = paper.eq7_accelerations(X1, T, beta)
    C = 0.5 * (math.hypot(mass * aH, w) + math.hypot(mass * aL, w))
    body = exdex.Body.box(mass, (0.15, 0.08, 0.03))
    push = exdex.Scene(body=body, dof="auto",
                       grasp=exdex.Grasp(mu=mu, grip_force=C / (2 * mu), patch=exdex.Patch.rectangle(0.02, 0.02)),
                       motion=exdex.AsymmetricProfile(X1, T, beta, axis=(1.0, 0.0, 0.0)))
    e_r = exdex.Patch.rectangle(0.02, 0.02).e_r
    f = w * math.sqrt(1.0 + (0.02 / e_r) ** 2) / (2 * mu)   # the grip at which the box starts to turn
    ramp = exdex.Scene(body=body, dof="auto",
                       grasp=exdex.Grasp(mu=mu, grip_force=exdex.GripSchedule((0.0, 1.0), (1.3 * f, 0.7 * f), "linear"),
                                         patch=exdex.Patch.rectangle(0.02, 0.02, center=(0.02, 0.0))))
    return [("pushed across, switch at 0.21 s", push), ("grip ramp, switch at 0.5 s", ramp)]


def escalating_rows(repeat):
    """dof="auto" on the escalating scenes against the planar run from
    t = 0: whole exdex.simulate calls, t_end 1 s, dt 1e-3, medians of
    ``repeat`` pairs (order alternated); the C core's calls inside auto
    timed apart (the candidates, the planar run from the switch)."""
    sim = sys.modules["exdex.simulate"]
    core = sim._core
    calls = []

    class Timed:
        def __getattr__(self, name):
            return getattr(core, name)

        @staticmethod
        def simulate(*a, **k):
            t0 = time.process_time()
            out = core.simulate(*a, **k)
            calls.append(time.process_time() - t0)
            return out

    head = ["", f'dof="auto" on scenes that escalate, against the planar model from t = 0: whole exdex.simulate, '
            f't_end 1 s, dt 1e-3, medians of {repeat} pairs (order alternated); auto\'s C calls apart',
            f"{'case':44s} {'switch [s]':>10s} {'planar [ms]':>12s} {'auto [ms]':>10s} {'ratio':>6s}"
            f" {'1-DoF [ms]':>11s} {'tail [ms]':>10s} {'rest [ms]':>10s}"]
    for line in head:
        print(line)
    out = head
    for name, sa in escalating_cases():
        sp = exdex.replace(sa, dof="planar")
        for method in ("implicit", "event"):
            a, b, heads, tails = [], [], [], []
            t_sw = exdex.simulate(sa, 1.0, 1e-3, method=method).models[0][3]
            for i in range(repeat):
                for which in ((0, 1) if i % 2 else (1, 0)):
                    if which:
                        calls.clear()
                        sim._core = Timed()
                    t0 = time.process_time()
                    try:
                        exdex.simulate(sa if which else sp, 1.0, 1e-3, method=method)
                    finally:
                        sim._core = core
                    (b if which else a).append(time.process_time() - t0)
                    if which:
                        heads.append(sum(calls[:-1]))
                        tails.append(calls[-1])
            ma, mb = statistics.median(a), statistics.median(b)
            mh, mt = statistics.median(heads), statistics.median(tails)
            line = (f"{name + f' ({method})':44s} {t_sw:10.4f} {1e3 * ma:12.3f} {1e3 * mb:10.3f} {mb / ma:6.2f}"
                    f" {1e3 * mh:11.3f} {1e3 * mt:10.3f} {1e3 * (mb - mh - mt):10.3f}")
            print(line, flush=True)
            out.append(line)
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=21)
    ap.add_argument("--out", default=os.path.join(HERE, "results", "certify.txt"))
    ap.add_argument("--only", default="", help="run only the cases whose name holds this text")
    args = ap.parse_args(argv)
    warnings.simplefilter("ignore")
    lines = [f"certificate cost: CPU time (time.process_time), medians of {args.repeat} alternating runs "
             f"(Python {sys.version.split()[0]}); whole call Model.simulate, and the C core alone",
             f"{'case':40s} {'steps':>7s} {'without [ms]':>13s} {'with [ms]':>10s} {'extra':>7s}"
             f" {'core without':>13s} {'core with':>10s} {'extra':>7s} {'as it goes':>11s} {'extra':>7s}"
             f" {'every sample':>13s} {'extra':>7s}"]
    print(lines[0])
    print(lines[1])
    for name, sc, method, t_end, dt in cases():
        if args.only not in name:
            continue
        m = exdex.Model(sc, method=method)
        res = m.simulate(t_end, dt)
        assert res.certificate is not None and res.certificate["holds"], (name, res.certificate)
        m.simulate(t_end, dt, certify=False)
        assert m._model.simulate(t_end, dt, every_sample=True)["certificate"] == res.certificate, name
        assert m._model.simulate(t_end, dt, stop_at_failure=True)["certificate"] == res.certificate, name
        a, b, ca, cb, ce, cg = [], [], [], [], [], []
        core = m._model
        for _ in range(args.repeat):
            t0 = time.process_time()
            m.simulate(t_end, dt, certify=False)
            t1 = time.process_time()
            m.simulate(t_end, dt, certify=True)
            t2 = time.process_time()
            core.simulate(t_end, dt, certify=False)
            t3 = time.process_time()
            core.simulate(t_end, dt, certify=True)
            t4 = time.process_time()
            core.simulate(t_end, dt, certify=True, every_sample=True)
            t5 = time.process_time()
            core.simulate(t_end, dt, certify=True, stop_at_failure=True)
            t6 = time.process_time()
            ce.append(t5 - t4)
            cg.append(t6 - t5)
            a.append(t1 - t0)
            b.append(t2 - t1)
            ca.append(t3 - t2)
            cb.append(t4 - t3)
        ma, mb = statistics.median(a), statistics.median(b)
        mca, mcb, mce, mcg = (statistics.median(x) for x in (ca, cb, ce, cg))
        line = (f"{name:40s} {len(res.t) - 1:7d} {1e3 * ma:13.3f} {1e3 * mb:10.3f} {100 * (mb / ma - 1):6.1f}%"
                f" {1e3 * mca:13.3f} {1e3 * mcb:10.3f} {100 * (mcb / mca - 1):6.1f}%"
                f" {1e3 * mcg:11.3f} {100 * (mcg / mca - 1):6.1f}%"
                f" {1e3 * mce:13.3f} {100 * (mce / mca - 1):6.1f}%")
        print(line, flush=True)
        lines.append(line)
    if not args.only:
        lines += auto_rows(args.repeat)
        lines += escalating_rows(args.repeat)
    if args.out:
        with open(args.out, "w", encoding="utf-8") as f:
            f.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()

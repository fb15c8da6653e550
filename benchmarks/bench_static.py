"""Cost of a step with static and kinetic friction (mu_static > mu) against
the same step with one coefficient, measured in the same run.

The scenes: a 60 x 30 mm box of 0.1 kg held through a 20 x 20 mm patch
10 mm off its centre of mass, gravity in the plate plane; the gripper shakes
it down and up (Eq. 7, 0.1 m, T 0.5 s, beta 0.9), so it sticks, breaks away,
slides and turns, and sticks again. Planar (implicit: the ellipsoid solve
every step) and 1-DoF translation; each with mu = 0.3 and either no static
coefficient (the peer) or mu_static = 0.45.

The time is a compiled model's ``final`` call (every step, output of the
last sample only) divided by its steps; the median over --repeat runs and
the ratio of each median to its peer's. Usage:

    python benchmarks/bench_static.py [--repeat 7] [--steps 100000]
"""
import argparse
import statistics
import warnings

import exdex
from _harness import machine_line, measure


def shaken(dof, mu_static):
    return exdex.Scene(
        body=exdex.Body.box(0.1, (0.06, 0.03, 0.02)),
        grasp=exdex.Grasp(mu=0.3, grip_force=1.5, mu_static=mu_static,
                          patch=exdex.Patch.rectangle(0.02, 0.02, center=(0.01, 0.0))),
        motion=exdex.AsymmetricProfile(amplitude=0.1, duration=0.5, beta=0.9, axis=(0.0, 0.0, -1.0)),
        dof=dof)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=7)
    ap.add_argument("--steps", type=int, default=100_000)
    args = ap.parse_args(argv)
    t_end = 1.2
    dt = t_end / args.steps
    print(machine_line(args.repeat, args.steps))
    print(f"{'scene':<34} {'ns/step':>9} {'min':>8} {'max':>8} {'ratio':>7} {'stick %':>8}")
    for dof in ("planar", "translation"):
        base = None
        for ms in (None, 0.45):
            scene = shaken(dof, ms)
            model = exdex.Model(scene, method="implicit")
            ns = measure(model, t_end, dt, args.repeat)
            med = statistics.median(ns)
            base = med if base is None else base
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")   # the box turns off its pads: a cost scene
                r = exdex.simulate(scene, t_end, 1e-3)
            name = f"{dof}, mu_static = {'mu' if ms is None else ms}"
            print(f"{name:<34} {med:9.1f} {min(ns):8.1f} {max(ns):8.1f} {med / base:7.2f} "
                  f"{100 * r.stick.mean():8.1f}")


if __name__ == "__main__":
    main()

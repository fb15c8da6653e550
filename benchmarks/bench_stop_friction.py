"""Cost of a planar implicit step with two frictional stop contacts, against
the same step with frictionless stops, measured in the same run.

The scene: a square block in the planar grasp with one face flush against a
wall fixed in the world (two contact rows, its two corners), the gripper
moving toward the wall at constant speed so that the plates slide past the
block and press it on the wall. Three variants of the wall: frictionless
(mu = 0, the peer), sliding (mu = 0.3: the block slides down the wall, both
corners slide) and holding (mu = 0.8: both corners stick, the plates slide).
Every step has both rows active.

The time is a compiled model's ``final`` call (every step, output of the
last sample only: no trajectory arrays) divided by its steps; the median
over --repeat runs, each of --steps steps, and the ratio of each median to
the frictionless one. Usage:

    python benchmarks/bench_stop_friction.py [--repeat 7] [--steps 200000]
"""
import argparse
import statistics

import exdex
from _harness import machine_line, measure


def wall_scene(mu_stop, V=0.01, m=0.1, a=0.03):
    xw = 0.1
    return exdex.Scene(
        body=exdex.Body.box(m, (a, a, 0.02)),
        grasp=exdex.Grasp(mu=0.5, grip_force=1.5, patch=exdex.Patch.rectangle(0.02, 0.02)),
        motion=exdex.TrapezoidalProfile(amplitude=2.0 * V, duration=2.0, v_max=V, axis=(1, 0, 0)),
        dof="planar", q0=(xw - a / 2, 0.0, 0.0),
        stops=(exdex.Stop((xw, 0.0, 0.0), (-1.0, 0.0, 0.0), mu=mu_stop),))


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=7)
    ap.add_argument("--steps", type=int, default=200_000)
    args = ap.parse_args(argv)
    t_end = 0.2
    dt = t_end / args.steps
    print(machine_line(args.repeat, args.steps))
    print(f"{'wall':<28} {'ns/step':>9} {'min':>8} {'max':>8} {'ratio':>7} {'rows on':>8}")
    base = None
    for name, mu in (("frictionless (mu = 0)", 0.0), ("sliding corners (mu = 0.3)", 0.3),
                     ("sticking corners (mu = 0.8)", 0.8)):
        scene = wall_scene(mu)
        model = exdex.Model(scene, method="implicit")
        ns = measure(model, t_end, dt, args.repeat)
        med = statistics.median(ns)
        base = med if base is None else base
        # both corners push in every step: the stop force is carried by two rows
        r = exdex.simulate(scene, 0.01, 1e-3)
        on = "2" if r.stop_force[-1, 0] > 0 else "0"
        print(f"{name:<28} {med:9.1f} {min(ns):8.1f} {max(ns):8.1f} {med / base:7.2f} {on:>8}")


if __name__ == "__main__":
    main()

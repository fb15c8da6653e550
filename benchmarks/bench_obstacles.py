"""Cost of a planar implicit step against convex obstacles, against the same
step with the equivalent plane stop, measured in the same run.

The scene: a square block in the planar grasp with one face flush against a
wall fixed in the world, the gripper moving toward the wall at constant
speed so that the plates slide past the block and press it on the wall
(both corners push in every step). The wall is given as a Stop (the peer),
as a one-face obstacle (the same rows: the same cost expected), as the face
of a box (six faces per vertex row, plus the rows of the section's corners
against the block) and, with friction mu = 0.3, as the frictional stop and
the frictional box. A last line pushes a pinned square onto a rod (one rod
row, rotation scene) against the same scene without contact.

The time is a compiled model's ``final`` call (every step, output of the
last sample only) divided by its steps; the median over --repeat runs, each
of --steps steps, and the ratio of each median to its peer's. Usage:

    python benchmarks/bench_obstacles.py [--repeat 7] [--steps 100000]
"""
import argparse
import statistics

import exdex
from _harness import machine_line, measure


def wall_scene(stops=(), obstacles=(), V=0.01, m=0.1, a=0.03):
    xw = 0.1
    return exdex.Scene(
        body=exdex.Body.box(m, (a, a, 0.02)),
        grasp=exdex.Grasp(mu=0.5, grip_force=1.5, patch=exdex.Patch.rectangle(0.02, 0.02)),
        motion=exdex.TrapezoidalProfile(amplitude=2.0 * V, duration=2.0, v_max=V, axis=(1, 0, 0)),
        dof="planar", q0=(xw - a / 2, 0.0, 0.0), stops=stops, obstacles=obstacles)


def rod_scene(stops=(), obstacles=()):
    a = 0.02
    body = exdex.Body(mass=0.1, inertia=0.1 * (2 * a) ** 2 / 6, outline=[(-a, -a), (a, -a), (a, a), (-a, a)])
    return exdex.Scene(body=body, grasp=exdex.Grasp(mu=0.5, grip_force=1.0), dof="rotation",
                       motion=exdex.TrapezoidalProfile(0.005, 1.0, 0.0075, axis=(0, 0, -1)),
                       stops=stops, obstacles=obstacles)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=7)
    ap.add_argument("--steps", type=int, default=100_000)
    args = ap.parse_args(argv)
    print(machine_line(args.repeat, args.steps))
    print(f"{'contact':<44} {'ns/step':>9} {'min':>8} {'max':>8} {'ratio':>7}")
    wall = ((0.1, 0.0, 0.0), (-1.0, 0.0, 0.0))
    cases = [
        ("wall: Stop (peer)", wall_scene(stops=(exdex.Stop(*wall),)), True),
        ("wall: one-face Obstacle", wall_scene(obstacles=(exdex.Obstacle.halfspaces([wall[1]], [-0.1]),)), False),
        ("wall: face of an Obstacle.box", wall_scene(obstacles=(exdex.Obstacle.box((0.6, 0, 0), (1, 1, 1)),)), False),
        ("wall mu 0.3: Stop (peer)", wall_scene(stops=(exdex.Stop(*wall, mu=0.3),)), True),
        ("wall mu 0.3: Obstacle.box", wall_scene(obstacles=(exdex.Obstacle.box((0.6, 0, 0), (1, 1, 1), mu=0.3),)),
         False),
        ("pinned square, no contact (peer)", rod_scene(), True),
        ("pinned square onto a rod: Obstacle.cylinder",
         rod_scene(obstacles=(exdex.Obstacle.cylinder((0.015, 0.0, -0.026), (0, 1, 0), 0.005),)), False),
    ]
    base = None
    for name, scene, peer in cases:
        t_end = 0.2 if scene.dof == "planar" else 1.0
        dt = t_end / args.steps
        ns = measure(exdex.Model(scene, method="implicit"), t_end, dt, args.repeat)
        med = statistics.median(ns)
        if peer:
            base = med
        print(f"{name:<44} {med:9.1f} {min(ns):8.1f} {max(ns):8.1f} {med / base:7.2f}")


if __name__ == "__main__":
    main()

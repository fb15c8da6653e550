"""Cost of stepping a run from Python (exdex.Stepper, one call per step, the
state read back each step) against the whole run in one call
(exdex.Model.final, the same steps and results), measured in the same run.

The scene: a 60 x 30 mm box of 0.1 kg held through a 20 x 20 mm patch, the
gripper shaking it down and up (Eq. 7, 0.1 m, T 0.5 s, beta 0.9): it sticks,
slides and sticks again. 1-DoF translation and planar; implicit and event
methods; steps of 1 ms over 1.5 s. Printed: the median time per step over
--repeat runs of each, and the ratio of the stepper's median to the whole
run's (the Python call and state per step is the difference). Usage:

    python benchmarks/bench_stepper.py [--repeat 5]
"""
import argparse
import os
import platform
import statistics
import time

import exdex


def scene(dof):
    return exdex.Scene(
        body=exdex.Body.box(0.1, (0.06, 0.03, 0.02)),
        grasp=exdex.Grasp(mu=0.3, grip_force=1.5, patch=exdex.Patch.rectangle(0.02, 0.02)),
        motion=exdex.AsymmetricProfile(amplitude=0.1, duration=0.5, beta=0.9, axis=(0.0, 0.0, -1.0)),
        dof=dof)


def whole(model, n, dt):
    t0 = time.perf_counter()
    model.final(n * dt, dt)
    return (time.perf_counter() - t0) / n


def stepped(model, n, dt):
    st = exdex.Stepper(model)
    t0 = time.perf_counter()
    for _ in range(n):
        st.step(dt)
    return (time.perf_counter() - t0) / n


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=5)
    args = ap.parse_args(argv)
    n, dt = 1500, 1e-3
    print(f"{platform.processor() or platform.machine()}, {os.cpu_count()} CPUs, load {os.getloadavg()[0]:.2f}")
    print(f"{'scene':<12} {'method':<9} {'whole run [us/step]':>20} {'stepper [us/step]':>18} {'ratio':>7}")
    for dof in ("translation", "planar"):
        for method in ("implicit", "event"):
            model = exdex.Model(scene(dof), method=method)
            whole(model, n, dt), stepped(model, n, dt)   # warm-up
            a = statistics.median(whole(model, n, dt) for _ in range(args.repeat))
            b = statistics.median(stepped(model, n, dt) for _ in range(args.repeat))
            print(f"{dof:<12} {method:<9} {1e6 * a:20.2f} {1e6 * b:18.2f} {b / a:7.1f}")


if __name__ == "__main__":
    main()

"""A noisy robot log, raw and smoothed (SampledTrajectory(noise=...)).

The gripper moves 10 cm up in 0.5 s (minimum jerk, between rests; logged at
100 Hz in exdex's default plates-vertical pose) with Gaussian noise of
0.1 mm per axis on the positions. Printed per seed: the gripper's peak
acceleration of the raw log's spline, of the smoothed one and of the clean
log's, against the closed form 10 sqrt(3) / 3 X / T^2; the noise level
estimated from the data; then a 100 g box held by 1.5 N per finger (mu 0.5:
capacity 1.5 N against m (g + 2.31 m/s^2) = 1.21 N) under each log (event
method): its slip and the share of steps it sticks.

    python benchmarks/log_noise.py [--seeds N]
"""
import argparse
import math
import warnings

import numpy as np

import exdex

X, T, H, T_REST, T_LOG, SIGMA = 0.1, 0.5, 0.01, 0.2, 1.0, 1e-4
Q0 = np.array([math.sqrt(0.5), math.sqrt(0.5), 0.0, 0.0])
PEAK = 10.0 * math.sqrt(3.0) / 3.0 * X / T**2


def log(seed=None, **kw):
    t = np.arange(0.0, T_LOG + 1e-9, H)
    u = np.clip((t - T_REST) / T, 0.0, 1.0)
    pos = np.zeros((len(t), 3))
    pos[:, 2] = X * u**3 * (10.0 - 15.0 * u + 6.0 * u * u)
    if seed is not None:
        pos += np.random.default_rng(seed).normal(scale=SIGMA, size=pos.shape)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", exdex.NoisyLogWarning)
        return exdex.SampledTrajectory(t, pos, np.tile(Q0, (len(t), 1)), **kw)


def peak(motion):
    return float(np.max(np.linalg.norm(motion.evaluate(np.linspace(0.0, T_LOG, 20001))["a"], axis=1)))


def hold(motion):
    sc = exdex.Scene(body=exdex.Body.box(0.1, (0.03, 0.06, 0.02)),
                     grasp=exdex.Grasp(mu=0.5, grip_force=1.5, patch=exdex.Patch.rectangle(0.01, 0.02)),
                     motion=motion, slide_axis=(0.0, 1.0))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", exdex.PhysicsWarning)
        r = exdex.simulate(sc, T_LOG, 1e-3, method="event")
    return 1e3 * float(r.q[-1, 0] - r.q[0, 0]), float(np.mean(r.stick[1:]))


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, default=3)
    args = ap.parse_args(argv)
    print(f"peak acceleration: closed form {PEAK:.4f} m/s^2, clean log's spline {peak(log()):.4f} m/s^2")
    rest = dict(start_velocity=(0.0, 0.0, 0.0), end_velocity=(0.0, 0.0, 0.0))
    for seed in range(args.seeds):
        raw, smooth = log(seed), log(seed, noise=(SIGMA, 0.0))
        print(f"seed {seed}: raw {peak(raw):.3f} m/s^2, smoothed {peak(smooth):.4f} m/s^2 "
              f"({100 * (peak(smooth) / PEAK - 1):+.2f} % of the closed form); "
              f"estimated noise {1e3 * raw.noise_estimate()[0]:.4f} mm")
        for name, m in (("clean", log(**rest)), ("raw", log(seed, **rest)), ("smoothed", smooth)):
            slip, stick = hold(m)
            print(f"    {name:9s} log: slip {slip:+.3f} mm, stuck in {100 * stick:.1f} % of the steps")


if __name__ == "__main__":
    main()

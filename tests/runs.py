"""Run loops shared by the obstacle and disc tests (tests/scenarios/test_obstacles.py,
tests/scenarios/test_disc.py). Each takes the simulate function the test uses
(exdex.simulate or a wrapper with the same signature) and keeps the
references and tolerances of the tests that call it."""
import numpy as np

import exdex


def with_obstacles(scene, *obstacles):
    """The scene with its stops replaced by the obstacles."""
    return exdex.replace(scene, stops=(), obstacles=obstacles)


def face_is_the_stop(simulate, scene, face, t_end, dt, **kw):
    """Run the scene (its stops) and the same scene with its stops replaced
    by the one-face obstacle face through the same plane, both with
    simulate(scene, t_end, dt, **kw): the same trajectory and forces bit for
    bit (q, v, stop_force). Returns the stop's run."""
    a = simulate(scene, t_end, dt, **kw)
    b = simulate(with_obstacles(scene, face), t_end, dt, **kw)
    assert np.array_equal(a.q, b.q) and np.array_equal(a.v, b.v) and np.array_equal(a.stop_force, b.stop_force)
    return a


def implicit_converges_to_event(simulate, scene, t_end):
    """The event method (dt 1e-3, rtol 1e-10: no warnings, no gap below
    -1e-11) and the implicit method at h = 1e-3, h / 2, h / 4 converge to
    the same motion (q at every sample of the 1e-3 grid): the implicit error
    halves with dt (e(h / 2) <= 0.6 e(h)) and its Richardson extrapolation
    2 q(h / 4) - q(h / 2) lies at least 5x closer than q(h / 2); where the
    implicit error is not first order but tiny, e(h / 2) <= 1e-8 m and
    e(h / 2) <= e(h) pass instead."""
    ev = simulate(scene, t_end, 1e-3, method="event", rtol=1e-10, atol=1e-12)
    assert ev.stats["warnings"] == 0 and ev.stats["min_gap"] >= -1e-11
    q = {k: simulate(scene, t_end, 1e-3 / k, method="implicit").q[::k] for k in (1, 2, 4)}
    e1, e2 = np.abs(q[1] - ev.q).max(), np.abs(q[2] - ev.q).max()
    ext = np.abs(2 * q[4] - q[2] - ev.q).max()
    if not (e2 <= 1e-8 and e2 <= e1):
        assert e2 <= 0.6 * e1, (e1, e2)
        assert ext <= 0.2 * e2, (ext, e2)


def implicit_errors(simulate, scene, ref, t_end, dts=(1e-3, 1e-4)):
    """The implicit runs at the steps dts (each dividing 1e-3 s) and their
    largest distances in q from the run ref on its 1e-3 s grid: a list of
    (run, error)."""
    out = []
    for dt in dts:
        im = simulate(scene, t_end, dt, method="implicit")
        out.append((im, np.abs(im.q[::int(round(1e-3 / dt))] - ref.q).max()))
    return out

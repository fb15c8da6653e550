"""exdex.Model: a scene compiled once and run many times. Its runs must be
the runs of exdex.simulate (same C model, same integrator): the references
here are exdex.simulate itself (an independent path through the extension:
spec conversion and model set-up on every call) and closed forms."""
import threading

import numpy as np
import pytest

import exdex
from exdex import _core, paper


def planar_stop_scene():
    body = exdex.Body.box(0.1, (0.04, 0.02, 0.02))
    return exdex.Scene(body=body, dof="planar", q0=(0.0, 0.0, 0.3),
                       grasp=exdex.Grasp(mu=0.3, grip_force=0.5, patch=exdex.Patch.disc(0.01)),
                       stops=(exdex.Stop(point=(0, 0, -0.03), normal=(0, 0, 1)),))


CASES = [
    ("fig3 implicit", paper.fig3_scene, dict(), 1.2, 1e-3),
    ("fig3 event", paper.fig3_scene, dict(method="event", rtol=1e-9, atol=1e-12), 1.2, 1e-2),
    ("fig4 implicit", paper.fig4_scene, dict(), 1.0, 2e-3),
    ("planar stop multiroot", planar_stop_scene, dict(friction_solver="multiroot"), 0.3, 1e-3),
]


@pytest.mark.parametrize("name,make,kw,t_end,dt", CASES, ids=[c[0] for c in CASES])
def test_model_runs_are_bit_identical_to_simulate(name, make, kw, t_end, dt):
    scene = make()
    ref = exdex.simulate(scene, t_end, dt, **kw)
    model = exdex.Model(scene, **kw)
    for _ in range(2):   # and the model is not changed by a run
        res = model.simulate(t_end, dt)
        for f in ("t", "q", "v", "wrench", "stick", "stop_force"):
            assert np.array_equal(getattr(res, f), getattr(ref, f)), f
        assert res.stats == ref.stats
        q, v, stick = model.final(t_end, dt)
        assert q == tuple(ref.q[-1]) and v == tuple(ref.v[-1]) and stick == bool(ref.stick[-1])
    assert model.ndof == ref.q.shape[1]


def test_model_final_matches_the_closed_form():
    """Gripper accelerating up at a (first Eq. 7 phase) with no gravity and a
    capacity c < m a: s(t) = -(a - c/m) t^2 / 2 (uniform relative acceleration)."""
    m, cap = 0.1, 0.05
    mo = exdex.AsymmetricProfile(0.1, 0.5, 0.9, axis=(0, 0, 1))
    sc = exdex.Scene(body=exdex.Body(mass=m), grasp=exdex.Grasp(mu=0.5, grip_force=cap), motion=mo,
                     gravity=(0, 0, 0))
    model = exdex.Model(sc)
    for t_end in (0.1, 0.3, 0.45):
        (s,), (v,), stick = model.final(t_end, 1e-3)
        a_rel = -(mo.a_high - cap / m)
        assert s == pytest.approx(0.5 * a_rel * t_end**2, abs=1e-13)
        assert v == pytest.approx(a_rel * t_end, abs=1e-12)
        assert not stick


def test_model_bad_input_names_the_parameter():
    sc = paper.fig3_scene()
    with pytest.raises(TypeError, match="scene"):
        exdex.Model("not a scene")
    with pytest.raises(ValueError, match="method"):
        exdex.Model(sc, method="rk4")
    with pytest.raises(ValueError, match="eps"):
        exdex.Model(sc, method="regularised", eps=0.0)
    model = exdex.Model(sc)
    with pytest.raises(ValueError, match="dt"):
        model.final(1.0, dt=0.0)
    with pytest.raises(ValueError, match="t_end"):
        model.simulate(1e-4, dt=1e-3)
    with pytest.raises(ValueError, match="t_end / dt"):
        model.final(1e6, dt=1e-6)
    with pytest.raises(ValueError, match="mass"):
        _core.compile(dict(sc.to_spec(), mass=-1.0))
    with pytest.raises(TypeError, match="directly"):
        _core.Model()


def test_model_solver_error_carries_status():
    """A state that overflows (gravity -1e308 m/s^2: |v| grows by 5e306 m/s
    per step of 0.5 s) raises SolverError with EXDEX_ENONFINITE = 4 from both
    run methods, and the model stays usable for a valid run afterwards."""
    body = exdex.Body(mass=0.1)
    model = exdex.Model(exdex.Scene(body=body, grasp=exdex.Grasp(mu=0.5, grip_force=1.0), gravity=(0, 0, -1e308)))
    for run in (model.simulate, model.final):
        with pytest.raises(exdex.SolverError) as info:
            run(10.0, 0.5)
        assert info.value.status == 4
    (s,), (v,), _ = model.final(0.5, 0.5)     # one step: finite
    assert np.isfinite(s) and np.isfinite(v)


def test_model_runs_from_threads_identical_to_serial():
    model = exdex.Model(planar_stop_scene(), friction_solver="scalar")
    serial = [model.final(0.05 * (k + 1), 1e-3) for k in range(8)]
    out = [None] * 8

    def work(k):
        for _ in range(20):
            out[k] = model.final(0.05 * (k + 1), 1e-3)

    threads = [threading.Thread(target=work, args=(k,)) for k in range(8)]
    for th in threads:
        th.start()
    for th in threads:
        th.join()
    assert out == serial

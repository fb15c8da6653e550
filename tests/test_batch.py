"""Batches (exdex.simulate_batch, exdex._core.simulate_batch) and sweeps
(exdex.sweep) on thread pools and a Dask LocalCluster.

References: a batch must equal, bit for bit, serial exdex.simulate of the
scene dataclasses.replace makes for each parameter set (an independent code
path: one scene at a time, built in Python); its physics is checked against
the closed-form Coulomb solution of exdex.paper.closed_form; sweeps must equal
the batch of the same grid whatever executor runs them. No timings here
(benchmarks/bench_batch.py measures speed)."""
import concurrent.futures as cf
import dataclasses
import math
import re
import sys
import time

import numpy as np
import pytest

import exdex
from exdex import _core, paper
from exdex.batch import BatchResult, grid_points, simulate_batch, sweep
from exdex.scene import METHODS

ARRAYS = ("q", "v", "wrench", "stick", "stop_force")
STATS = ("steps", "stick_steps", "solver_iterations", "stop_iterations", "warnings", "min_gap")


@pytest.fixture(scope="module")
def fig3():
    return paper.fig3_scene()


def planar_scene():
    """A planar box (x, y, theta) dropped on a stop while the gripper moves
    down: slip, rotation, stop contact and stick in one short run."""
    return exdex.Scene(
        body=exdex.Body.box(0.1, (0.02, 0.04, 0.02)),
        grasp=exdex.Grasp(mu=0.5, grip_force=0.3, patch=exdex.Patch.rectangle(0.02, 0.04)),
        motion=exdex.TrapezoidalProfile(-0.05, 0.5, 0.12), dof="planar",
        stops=(exdex.Stop(point=(0, 0, -0.03), normal=(0, 0, 1)),), q0=(0.005, 0.0, 0.1))


def assert_same_as_serial(batch, t_end, dt):
    """Every trajectory of the batch equals serial exdex.simulate bit for bit."""
    for i in range(len(batch)):
        sc = batch.scene_at(i)
        r = exdex.simulate(sc, t_end, dt)
        np.testing.assert_array_equal(batch.t, r.t)
        if batch.record == "all":
            for name in ARRAYS:
                np.testing.assert_array_equal(getattr(batch, name)[i], getattr(r, name), err_msg=f"{name}[{i}]")
        else:
            for name in ARRAYS:
                np.testing.assert_array_equal(getattr(batch, name)[i], getattr(r, name)[-1], err_msg=f"{name}[{i}]")
        np.testing.assert_array_equal(batch.final_displacement[i], r.q[-1] - r.q[0])
        for k in STATS:
            assert batch.stats[k][i] == r.stats[k], (k, i)


# ------------------------------------------------------------ batch == serial

@pytest.mark.parametrize("threads", [1, 2])
def test_batch_bit_identical_to_serial_fig3_grid(fig3, threads):
    """Grip force x beta grid (broadcast (3, 1) x (1, 2)) of the Fig. 3 scene."""
    b = simulate_batch(fig3, 1.5, 1e-3, threads=threads, grip_force=[[1.3], [1.5051], [1.7]], beta=[[0.8, 0.9]])
    assert b.shape == (3, 2) and len(b) == 6 and b.q.shape == (6, 1501, 1)
    assert b.threads == threads
    np.testing.assert_array_equal(b.params["grip_force"], [1.3, 1.3, 1.5051, 1.5051, 1.7, 1.7])
    np.testing.assert_array_equal(b.params["beta"], [0.8, 0.9] * 3)
    assert b.scene_at(3) == dataclasses.replace(
        fig3, grasp=dataclasses.replace(fig3.grasp, grip_force=1.5051),
        motion=dataclasses.replace(fig3.motion, beta=0.9))
    assert_same_as_serial(b, 1.5, 1e-3)


@pytest.mark.warns_by_design("impact", "pad", "outline")
@pytest.mark.parametrize("threads", [1, 2])
def test_batch_bit_identical_to_serial_planar_with_stop(threads):
    """3-DoF scene with a stop: stop forces, planar friction solve, stats."""
    sc = planar_scene()
    b = simulate_batch(sc, 1.0, 1e-3, threads=threads, mu=[0.2, 0.5, 0.8], mass=[0.1, 0.12, 0.08])
    assert b.q.shape == (3, 1001, 3) and b.stop_force.shape == (3, 1001, 1)
    assert np.all(b.stop_force.max(axis=1) > 0)       # the stop acted in every run
    assert_same_as_serial(b, 1.0, 1e-3)


def test_batch_bit_identical_rotation_and_motion_parameters():
    """Rotation scene (Fig. 6) with amplitude and duration varied, record='final'."""
    sc = paper.fig6_scene()
    b = simulate_batch(sc, 7.0, 2e-3, threads=2, record="final", amplitude=np.radians([80.0, 100.0]),
                       duration=[2.5, 3.0])
    assert_same_as_serial(b, 7.0, 2e-3)


@pytest.mark.warns_by_design("outline")
@pytest.mark.parametrize("method", sorted(METHODS))
def test_every_method_bit_identical_to_serial(fig3, method):
    """Each integration method in a 2-thread batch equals serial
    exdex.simulate with that method (their workspaces are per call)."""
    b = simulate_batch(fig3, 1.5, 1e-2, threads=2, method=method, grip_force=[1.3, 1.5, 1.7], mu=0.5)
    for i in range(len(b)):
        r = exdex.simulate(b.scene_at(i), 1.5, 1e-2, method=method)
        for name in ARRAYS:
            np.testing.assert_array_equal(getattr(b, name)[i], getattr(r, name), err_msg=f"{method} {name}[{i}]")
        for k in STATS:
            assert b.stats[k][i] == r.stats[k], (method, k, i)


@pytest.mark.warns_by_design("outline")
def test_thread_counts_agree_on_a_larger_batch(fig3):
    """1, 2 and 7 threads (more than cores) give identical arrays."""
    g = np.linspace(1.2, 1.9, 150)
    runs = [simulate_batch(fig3, 1.5, 2e-3, threads=k, record="final", grip_force=g, mu=0.5) for k in (1, 2, 7)]
    for r in runs[1:]:
        for name in ARRAYS + ("final_displacement",):
            np.testing.assert_array_equal(getattr(r, name), getattr(runs[0], name))
        for k in STATS:
            np.testing.assert_array_equal(r.stats[k], runs[0].stats[k])


@pytest.mark.warns_by_design("impact", "pad", "outline", "solver", "jump")
@pytest.mark.parametrize("threads", [1, 2, 3])
def test_large_analytic_vary_batch_equals_serial(fig3, threads):
    """A batch long enough to be handed out in chunks, whose models the
    worker threads build from the base scene (one spec + vary): every
    trajectory equals serial exdex.simulate (checked on a spread of indices,
    including chunk edges), for any thread count."""
    g = np.linspace(1.1, 2.6, 20_000)
    b = simulate_batch(fig3, 1.5, 0.5, threads=threads, record="final", method="analytic", grip_force=g,
                       mu=0.5, warn=False)
    for i in (0, 1, 63, 64, 65, 127, 128, 4_999, 10_000, 19_998, 19_999):
        r = exdex.simulate(b.scene_at(i), 1.5, 0.5, method="analytic")
        for name in ARRAYS:
            np.testing.assert_array_equal(getattr(b, name)[i], getattr(r, name)[-1], err_msg=f"{name}[{i}]")


@pytest.mark.parametrize("threads", [1, 2, 3])
def test_rejected_scene_in_a_chunked_vary_batch_names_the_smallest_index(fig3, threads):
    """Scenes the core rejects at indices 3001 and 7000 of 10^4 (built by the
    workers): the error names 3001 whatever the thread count."""
    spec = fig3.to_spec(method="analytic")
    mass = np.full(10_000, fig3.body.mass)
    mass[[3001, 7000]] = -1.0
    with pytest.raises(ValueError, match=r"^batch index 3001: scene: invalid value of 'mass'"):
        _core.simulate_batch(spec, 1.5, 0.5, threads=threads, record="final", vary={"mass": mass})


def test_sequence_of_scenes(fig3):
    scenes = [fig3, exdex.replace(fig3, gravity=(0.0, 0.0, -9.0)), paper.fig3_scene(direction=1)]
    b = simulate_batch(scenes, 1.5, 1e-3, threads=2, grip_force=[1.4, 1.5, 1.6])
    assert b.scene_at(1).gravity == (0.0, 0.0, -9.0) and b.scene_at(1).grasp.grip_force == 1.5
    assert_same_as_serial(b, 1.5, 1e-3)


# ------------------------------------------------------------ record="final"

@pytest.mark.warns_by_design("impact", "pad", "outline")
@pytest.mark.parametrize("threads", [1, 2])
def test_record_final_is_last_row_of_all(threads):
    sc = planar_scene()
    kw = dict(mu=[0.2, 0.4, 0.6, 0.8], grip_force=0.3)
    a = simulate_batch(sc, 1.0, 1e-3, threads=threads, record="all", **kw)
    f = simulate_batch(sc, 1.0, 1e-3, threads=threads, record="final", **kw)
    assert f.q.shape == (4, 3) and f.wrench.shape == (4, 3) and f.stick.shape == (4,) and f.stop_force.shape == (4, 1)
    for name in ARRAYS:
        np.testing.assert_array_equal(getattr(f, name), getattr(a, name)[:, -1], err_msg=name)
    np.testing.assert_array_equal(f.final_displacement, a.q[:, -1] - a.q[:, 0])
    np.testing.assert_array_equal(f.t, a.t)
    for k in STATS:
        np.testing.assert_array_equal(f.stats[k], a.stats[k])
    with pytest.raises(ValueError, match="record='all'"):
        f.at(0)
    r = a.at(2)
    assert isinstance(r, exdex.Result) and r.scene.grasp.mu == 0.6


# ------------------------------------------------------------ physics

@pytest.mark.warns_by_design("outline")
def test_grip_force_batch_matches_closed_form(fig3):
    """Final slip of the Fig. 3 scene over grip forces 1.05..2.0 N per finger
    against the event-by-event closed form (exdex.paper.closed_form, no C
    core). The implicit method errs by about 1e-8 m at dt = 1e-4 here; a
    parameter mapped to the wrong trajectory or field would be off by
    millimetres (the slip changes by ~4 mm per 0.05 N)."""
    g = np.linspace(1.05, 2.0, 20)
    b = simulate_batch(fig3, 1.5, 1e-4, threads=2, record="final", grip_force=g)
    want = np.array([paper.closed_form(b.scene_at(i)).final for i in range(len(g))])
    np.testing.assert_allclose(b.final_displacement[:, 0], want, rtol=0, atol=1e-6)
    assert np.all(b.stick)                                    # at rest at t_end
    assert np.all(b.final_displacement[g >= 1.8, 0] == 0.0)   # capacity 18 >= g + |a_L|: exact stick


# ------------------------------------------------------------ bad input

def test_bad_parameter_names_and_shapes(fig3):
    with pytest.raises(ValueError, match="unknown batch parameter 'T'; did you mean 'duration'"):
        simulate_batch(fig3, 1.5, 1e-3, T=[0.4, 0.5])
    with pytest.raises(ValueError, match="unknown batch parameter 'gravity'.*allowed: mass, mu, grip_force"):
        simulate_batch(fig3, 1.5, 1e-3, gravity=[1.0])
    with pytest.raises(ValueError, match=r"do not broadcast together: mu \(3,\), beta \(2,\)"):
        simulate_batch(fig3, 1.5, 1e-3, mu=[0.1, 0.2, 0.3], beta=[0.5, 0.6])
    with pytest.raises(ValueError, match="needs a TrapezoidalProfile motion; the scene's motion is AsymmetricProfile"):
        simulate_batch(fig3, 1.5, 1e-3, v_max=[0.1])
    with pytest.raises(ValueError, match="needs a AsymmetricProfile motion; the scene's motion is Trapezoidal"):
        simulate_batch(planar_scene(), 1.0, 1e-3, beta=[0.5])
    with pytest.raises(ValueError, match="empty"):
        simulate_batch(fig3, 1.5, 1e-3, mu=[])
    with pytest.raises(TypeError, match="'mu' must be an array of real numbers"):
        simulate_batch(fig3, 1.5, 1e-3, mu=["a", "b"])
    with pytest.raises(ValueError, match=r"has 2 entries but 3 scenes"):
        simulate_batch([fig3] * 3, 1.5, 1e-3, mu=[0.1, 0.2])


def test_bad_parameter_values_name_the_entry(fig3):
    with pytest.raises(ValueError, match=r"grip_force\[2\] = -1 must be finite and in \[0, inf\) \(grasp.grip_force\)"):
        simulate_batch(fig3, 1.5, 1e-3, grip_force=[1.0, 1.5, -1.0])
    with pytest.raises(ValueError, match=r"beta\[1, 0\] = 1 must be finite and in \(0, 1\)"):
        simulate_batch(fig3, 1.5, 1e-3, beta=[[0.5], [1.0]])
    with pytest.raises(ValueError, match=r"mass\[0\] = nan"):
        simulate_batch(fig3, 1.5, 1e-3, mass=[np.nan])
    with pytest.raises(ValueError, match=r"duration = 0 must be"):
        simulate_batch(fig3, 1.5, 1e-3, duration=0.0, mu=[0.1, 0.2])


def test_bad_options(fig3):
    with pytest.raises(ValueError, match="record must be"):
        simulate_batch(fig3, 1.5, 1e-3, record="last")
    for bad in (0, -1, 2.5, True, 5000):
        with pytest.raises(ValueError, match="threads must be"):
            simulate_batch(fig3, 1.5, 1e-3, threads=bad)
    with pytest.raises(ValueError, match="dt must be"):
        simulate_batch(fig3, 1.5, 0.0)
    with pytest.raises(ValueError, match="dt must be <= t_end"):
        simulate_batch(fig3, 1e-4, 1e-3)
    with pytest.raises(TypeError, match="scene must be"):
        simulate_batch([], 1.5, 1e-3)
    with pytest.raises(ValueError, match="method must be one of"):
        simulate_batch(fig3, 1.5, 1e-3, method="rk4")


@pytest.mark.parametrize("method", sorted(METHODS))
def test_batch_accepts_exactly_the_methods_simulate_accepts(fig3, method):
    try:
        exdex.simulate(fig3, 0.01, 1e-3, method=method)
    except ValueError as exc:
        with pytest.raises(ValueError, match=re.escape(str(exc))):
            simulate_batch(fig3, 0.01, 1e-3, method=method, mu=[0.5])
    else:
        b = simulate_batch(fig3, 0.01, 1e-3, method=method, mu=[0.5, 0.4])
        assert b.method == method and len(b) == 2


def test_core_errors_name_the_batch_index(fig3):
    spec = fig3.to_spec()
    broken = dict(spec)
    del broken["mu"]
    with pytest.raises(KeyError, match="batch index 2: .*missing 'mu'"):
        _core.simulate_batch([spec, spec, broken], 1.5, 1e-3)
    with pytest.raises(ValueError, match=r"batch index 3: scene: invalid value of 'mass'"):
        _core.simulate_batch(spec, 1.5, 1e-3, vary={"mass": np.array([0.1, 0.1, 0.1, -1.0])})
    with pytest.raises(ValueError, match="unknown key 'gravity'"):
        _core.simulate_batch(spec, 1.5, 1e-3, vary={"gravity": np.ones(2)})
    with pytest.raises(ValueError, match="vary\\['mu'\\] has 3 entries, the other arrays 2"):
        _core.simulate_batch(spec, 1.5, 1e-3, vary={"grip_force": np.ones(2), "mu": np.ones(3)})
    with pytest.raises(ValueError, match="batch index 1: every scene of a batch needs the same free coordinates"):
        _core.simulate_batch([spec, planar_scene().to_spec()], 1.0, 1e-3)
    with pytest.raises(ValueError, match="record must be 'all' or 'final'"):
        _core.simulate_batch(spec, 1.5, 1e-3, record="some")
    with pytest.raises(ValueError, match="threads must be in"):
        _core.simulate_batch(spec, 1.5, 1e-3, threads=-1)
    with pytest.raises(ValueError, match=r"batch index 1: scene: invalid value of 'motion.v_max'"):
        _core.simulate_batch(planar_scene().to_spec(), 1.0, 1e-3, vary={"motion_v_max": np.array([0.12, -1.0])})
    # Eq. 9's a_H = 2 X1 / (beta T^2) overflows: the core rejects it, the
    # message uses the batch parameter's name
    with pytest.raises(ValueError, match=r"batch index 1: scene: invalid value of 'amplitude' \(motion.amplitude\)"):
        simulate_batch(fig3, 1.5, 1e-3, amplitude=[0.1, 1e308])


@pytest.mark.warns_by_design("impact", "pad", "outline", "jump")
def test_trapezoid_coupled_check_as_the_dataclass():
    """TrapezoidalProfile needs X1 != 0 and |X1|/T <= v_max <= 2|X1|/T."""
    sc = planar_scene()   # X1 -0.05 m, T 0.5 s, v_max 0.12 m/s (range 0.1 .. 0.2)
    for kw in (dict(amplitude=[-0.05, 0.0]), dict(amplitude=[-0.05, -0.01]), dict(v_max=[0.12, 0.21]),
               dict(duration=[0.5, 0.2])):
        with pytest.raises(ValueError, match="batch index 1: a TrapezoidalProfile needs"):
            simulate_batch(sc, 1.0, 1e-3, **kw)
        with pytest.raises(ValueError):   # the dataclass agrees
            (name, values), = kw.items()
            dataclasses.replace(sc.motion, **{name: values[1]})
    b = simulate_batch(sc, 1.0, 1e-3, record="final", amplitude=[-0.05, -0.04], v_max=[0.1, 0.16])
    assert_same_as_serial(b, 1.0, 1e-3)


@pytest.mark.parametrize("threads", [1, 2, 3])
def test_failing_trajectory_raises_with_its_index(fig3, threads):
    """Gravity 1e307 m/s^2 overflows the state (EXDEX_ENONFINITE) within 20 s;
    with two such scenes the smallest index is reported for any thread count."""
    bad = exdex.replace(fig3, gravity=(0.0, 0.0, -1e307))
    with pytest.raises(exdex.SolverError) as serial:
        exdex.simulate(bad, 20.0, 1e-2)
    scenes = [fig3] * 3 + [bad, fig3, bad] + [fig3] * 4
    with pytest.raises(exdex.SolverError, match="batch index 3: non-finite") as info:
        simulate_batch(scenes, 20.0, 1e-2, threads=threads, record="final")
    assert info.value.index == 3 and info.value.status == serial.value.status


def test_failing_trajectory_says_when_why_and_what_instead():
    """A batch's SolverError is simulate's (the time reached, the cause and
    the remedy, attributes time and cause) with the batch index in front: a
    regularised planar run whose eps makes the stepper's step collapse
    (stiffness C/(M eps) ~ 1e9/s) fails the step budget in both."""
    sc = exdex.Scene(body=exdex.Body.box(0.1, (0.06, 0.03, 0.02)),
                     grasp=exdex.Grasp(mu=0.5, grip_force=2.6,
                                       patch=exdex.Patch.rectangle(0.02, 0.02, center=(0.015, 0))),
                     dof="planar")
    kw = dict(method="regularised", eps=1e-12)
    with pytest.raises(exdex.SolverError) as serial:
        exdex.simulate(sc, 0.01, 0.01, **kw)
    with pytest.raises(exdex.SolverError) as info:
        simulate_batch([sc, sc], 0.01, 0.01, threads=1, record="final", **kw)
    e, s = info.value, serial.value
    assert s.cause == "step_budget" and "t = " in str(s) and "method='implicit'" in str(s)
    assert e.args == (f"batch index 0: {s.args[0]}", s.status)
    assert (e.index, e.status, e.time, e.cause) == (0, s.status, s.time, s.cause)


def test_keyboard_interrupt_stops_a_long_batch(fig3):
    """Ctrl-C (simulated with _thread.interrupt_main) reaches the main thread
    while the GIL is released: the batch stops long before its ~20 s of work."""
    import _thread
    import threading

    timer = threading.Timer(0.3, _thread.interrupt_main)
    t0 = time.perf_counter()
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            simulate_batch(fig3, 1.5, 1e-4, threads=2, record="final", grip_force=np.full(40000, 1.5))
    finally:
        timer.cancel()
    assert time.perf_counter() - t0 < 3.0


# ------------------------------------------------------------ sweeps

def test_grid_points_order():
    flat, shape = grid_points({"mu": [0.1, 0.2], "beta": [0.5, 0.6, 0.7]})
    assert shape == (2, 3)
    np.testing.assert_array_equal(flat["mu"], [0.1, 0.1, 0.1, 0.2, 0.2, 0.2])
    np.testing.assert_array_equal(flat["beta"], [0.5, 0.6, 0.7] * 2)
    flat, shape = grid_points({"mu": [0.1, 0.2], "beta": [0.5, 0.6]}, product=False)
    assert shape == (2,)
    with pytest.raises(ValueError, match="empty"):
        grid_points({"mu": []})


def test_sweep_equals_batch_thread_pool(fig3):
    grid = {"grip_force": np.linspace(1.3, 1.7, 5), "beta": [0.85, 0.9, 0.95]}
    want = simulate_batch(fig3, 1.5, 1e-3, threads=1, record="final",
                          grip_force=np.linspace(1.3, 1.7, 5)[:, None], beta=[[0.85, 0.9, 0.95]])
    with cf.ThreadPoolExecutor(max_workers=3) as ex:
        got = sweep(fig3, grid, executor=ex, chunk=4, progress=False, t_end=1.5, dt=1e-3)
    assert isinstance(got, BatchResult) and got.shape == (5, 3) and len(got) == 15
    for name in ARRAYS + ("final_displacement",):
        np.testing.assert_array_equal(getattr(got, name), getattr(want, name))
    for k in want.params:
        np.testing.assert_array_equal(got.params[k], want.params[k])
    assert got.gridded("final_displacement").shape == (5, 3, 1)
    # default executor and record="all"
    full = sweep(fig3, grid, chunk=7, progress=False, t_end=1.5, dt=1e-3, record="all")
    np.testing.assert_array_equal(full.q[:, -1], want.q)


def _slow_early(x):
    """Chunks that start first finish last (completion order reversed)."""
    time.sleep(0.02 * max(0.0, 3.0 - float(x[0])))
    return {"x2": np.asarray(x) ** 2, "first": np.full(len(x), x[0])}


def test_sweep_order_is_stable_for_any_completion_order():
    with cf.ThreadPoolExecutor(max_workers=4) as ex:
        out = sweep(_slow_early, {"x": np.arange(8.0)}, executor=ex, chunk=2, progress=False)
    np.testing.assert_array_equal(out["x2"], np.arange(8.0) ** 2)
    np.testing.assert_array_equal(out["first"], [0, 0, 2, 2, 4, 4, 6, 6])


def _fail_on_five(x):
    if np.any(np.asarray(x) == 5):
        raise RuntimeError("boom")
    return np.asarray(x)


def test_sweep_error_names_the_chunk(fig3):
    with pytest.raises(RuntimeError, match="boom") as info:
        sweep(_fail_on_five, {"x": np.arange(10.0)}, chunk=3, progress=False)
    if sys.version_info >= (3, 11):
        assert "sweep: in chunk 1 (grid points 3..5 of 10)" in info.value.__notes__
    with pytest.raises(ValueError, match="needs t_end"):
        sweep(fig3, {"mu": [0.1]})
    with pytest.raises(ValueError, match="chunk must be"):
        sweep(fig3, {"mu": [0.1]}, chunk=0, t_end=1.0)
    with pytest.raises(TypeError, match="concurrent.futures.Executor"):
        sweep(fig3, {"mu": [0.1]}, executor=object(), t_end=1.0)
    with pytest.raises(ValueError, match="unknown batch parameter 'T'"):
        sweep(fig3, {"T": [0.1]}, t_end=1.0)


def test_sweep_progress_bar(fig3, capsys):
    sweep(fig3, {"mu": [0.3, 0.4, 0.5]}, chunk=1, progress=True, t_end=0.1, dt=1e-3)
    err = capsys.readouterr().err
    assert "exdex sweep" in err and "3/3" in err


# ------------------------------------------------------------ Dask

@pytest.mark.warns_by_design("outline")
@pytest.mark.parametrize("processes", [False, True])
def test_sweep_on_dask_local_cluster(fig3, processes):
    """The same sweep through a Dask LocalCluster on loopback
    (client.get_executor()) equals the local thread-pool sweep."""
    distributed = pytest.importorskip("distributed")
    grid = {"grip_force": np.linspace(1.3, 1.7, 6), "mu": [0.45, 0.5]}
    local = sweep(fig3, grid, chunk=5, progress=False, t_end=1.5, dt=1e-3)
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=processes, host="127.0.0.1",
                                  protocol="tcp", dashboard_address=None) as cluster, \
            distributed.Client(cluster) as client:
        remote = sweep(fig3, grid, executor=client.get_executor(), chunk=5, progress=False, t_end=1.5, dt=1e-3)
    assert remote.shape == local.shape == (6, 2)
    for name in ARRAYS + ("final_displacement",):
        np.testing.assert_array_equal(getattr(remote, name), getattr(local, name))
    for k in STATS:
        np.testing.assert_array_equal(remote.stats[k], local.stats[k])


@pytest.mark.parametrize("threads", [1, 2])
def test_pad_centre_batch_equals_serial(threads):
    """patch_x / patch_y vary the pad centre (the pivot of a rotation scene);
    trajectory i equals exdex.simulate of scene_at(i) bit for bit, and
    method "auto" runs the event method (the analytic path needs the pivot
    at the centre of mass)."""
    s6 = paper.fig6_scene()
    b = simulate_batch(s6, 8.0, 0.5, threads=threads, record="all", method="auto", patch_y=[0.0, -0.005, 0.004],
                       patch_x=0.001, warn=False)
    assert b.method == "event"
    assert b.scene_at(1).grasp.patch.center == (0.001, -0.005)
    for i in range(len(b)):
        r = exdex.simulate(b.scene_at(i), 8.0, 0.5, method="event")
        for name in ARRAYS:
            np.testing.assert_array_equal(getattr(b, name)[i], getattr(r, name), err_msg=f"{name}[{i}]")
    with pytest.raises(ValueError, match=r"patch_y\[1\] = nan must be finite .*grasp\.patch\.center\.1"):
        simulate_batch(s6, 8.0, 0.5, patch_y=[0.0, np.nan])


# ------------------------------------------------------------ validity per trajectory

def _serial_kinds(scene, t_end, dt):
    """The kinds of PhysicsWarning exdex.simulate gives one scene (its own checks, serial)."""
    import warnings

    with warnings.catch_warnings(record=True) as rec:
        warnings.simplefilter("always")
        exdex.simulate(scene, t_end, dt)
    return {w.message.kind for w in rec if isinstance(w.message, exdex.PhysicsWarning)}


def _readme_box():
    return exdex.Scene(body=exdex.Body.box(0.1, (0.03, 0.06, 0.02)),
                       grasp=exdex.Grasp(mu=0.5, grip_force=1.5, patch=exdex.Patch.rectangle(0.01, 0.02)),
                       motion=exdex.AsymmetricProfile(amplitude=0.1, duration=0.5, beta=0.9, axis=(0, 0, -1)))


def test_batch_marks_the_trajectories_its_warning_counts():
    """The README's box: weak grips slide the pad centre off the 6 cm box.
    Each trajectory's mark equals what exdex.simulate of its scene warns
    (the serial checks, run one scene at a time), the warning's count is the
    number of invalid runs, and gridded() holds NaN exactly there."""
    grips = np.linspace(1.2, 1.8, 7)
    with pytest.warns(exdex.PhysicsWarning, match=r"batch index 0 \(and (\d+) more of 7 trajectories\).*outside "
                                                  r"the body outline.*marked invalid") as rec:
        b = simulate_batch(_readme_box(), 1.5, 1e-3, record="final", grip_force=grips)
    serial = [_serial_kinds(b.scene_at(i), 1.5, 1e-3) for i in range(len(b))]
    assert [bool(s & set(exdex.batch.INVALID_KINDS)) for s in serial] == list(~b.valid)
    assert [("outline" in s) for s in serial] == list(b.checks["outline"])
    assert 0 < (~b.valid).sum() < len(b)
    count = int(re.search(r"and (\d+) more", str(rec[0].message)).group(1)) + 1
    assert count == (~b.valid).sum()
    assert b.reasons(0) == ("outline",) and b.reasons(len(b) - 1) == ()
    g = b.gridded("final_displacement")
    assert np.array_equal(np.isnan(g[:, 0]), ~b.valid)
    np.testing.assert_array_equal(g[b.valid], b.final_displacement[b.valid])
    np.testing.assert_array_equal(b.gridded("final_displacement", invalid="include"), b.final_displacement)
    m = b.gridded("steps")                      # integers: masked, not NaN
    assert isinstance(m, np.ma.MaskedArray) and list(m.mask) == list(~b.valid)
    np.testing.assert_array_equal(b.gridded("grip_force"), grips)   # inputs are never masked
    with pytest.raises(ValueError, match="invalid must be"):
        b.gridded("q", invalid="drop")


@pytest.mark.warns_by_design("outline")
def test_sweep_grid_carries_the_mask():
    grid = {"grip_force": np.linspace(1.2, 1.8, 4), "beta": [0.8, 0.9]}
    s = sweep(_readme_box(), grid, chunk=3, progress=False, t_end=1.5, dt=1e-3)
    b = simulate_batch(_readme_box(), 1.5, 1e-3, record="final", warn=False,
                       grip_force=grid["grip_force"][:, None], beta=[grid["beta"]])
    np.testing.assert_array_equal(s.valid, b.valid)
    assert not s.valid.all()
    g = s.gridded("final_displacement")
    assert g.shape == (4, 2, 1) and np.array_equal(np.isnan(g[..., 0]), ~s.valid.reshape(4, 2))


def test_batch_reduction_warning_is_a_reduction_warning():
    """A batch's failed certificates come as one exdex.ReductionWarning (so a
    filter on that category catches it), like a single run's; the
    trajectories are invalid. Scene: tests/scenarios/test_certify.py's box held by a pad
    6 cm off its centre of mass, below and above the closed-form grip
    F* = W sqrt(1 + (d / e_r)^2) / (2 mu) at which the held load leaves the
    ellipsoid."""
    pad = exdex.Patch.rectangle(0.02, 0.02, center=(0.06, 0.0))
    sc = exdex.Scene(body=exdex.Body.box(0.2, (0.15, 0.08, 0.03)),
                     grasp=exdex.Grasp(mu=1.0, grip_force=3.0, patch=pad), dof="translation")
    F = 0.2 * 9.81 * math.sqrt(1.0 + (0.06 / pad.e_r) ** 2) / 2.0
    with pytest.warns(exdex.ReductionWarning, match=r"batch index 0 \(and 1 more of 4 trajectories\)") as rec:
        b = simulate_batch(sc, 0.2, 1e-3, grip_force=F * np.array([0.9, 0.99, 1.01, 1.1]))
    w = [r.message for r in rec if isinstance(r.message, exdex.ReductionWarning)]
    assert len(w) == 1 and w[0].kind == "reduction" and w[0].time == 0.0 and w[0].load is None
    assert list(b.valid) == [False, False, True, True] and list(b.checks["reduction"]) == [True, True, False, False]
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        warnings.simplefilter("ignore", exdex.ReductionWarning)
        simulate_batch(sc, 0.2, 1e-3, grip_force=F * np.array([0.9, 1.1]))   # filtered by category: no error


def test_batch_marks_a_lost_grasp():
    """Pads on the fingers: a weak grip slides the box off a 1 cm disc pad
    (the grasp is lost: NaN after that sample), a firm one holds it; the
    marks are the trajectories with stats["grasp_lost_t"], they match the
    NaN tails of the trajectories (the core's two reports of a loss agree)
    and the serial runs' grasp warnings."""
    body = exdex.Body.box(0.2, (0.15, 0.08, 0.02))
    sc = exdex.Scene(body=body, grasp=exdex.Grasp(mu=0.3, grip_force=0.3, patch=exdex.Patch.rectangle(0.02, 0.02),
                                                  pad=exdex.Pad.disc(0.01)),
                     dof="planar", q0=(0.002, 0.0, 0.0), gravity=(0.0, -9.81, 0.0), gripper_rotation=np.eye(3))
    grips = [0.3, 6.0]
    for record in ("all", "final"):
        with pytest.warns(exdex.PhysicsWarning, match="batch index 0: .*grasp is lost") as rec:
            b = simulate_batch(sc, 0.3, 1e-3, record=record, grip_force=grips)
        assert list(b.checks["grasp"]) == [True, False] and list(b.valid) == [False, True]
        # the check is the core's report: the trajectories it marks are those
        # with a loss time, and the warning gives that time
        lost_t = np.asarray(b.stats["grasp_lost_t"], dtype=float)
        assert list(np.isfinite(lost_t)) == list(b.checks["grasp"])
        w = [r.message for r in rec if isinstance(r.message, exdex.PhysicsWarning) and r.message.kind == "grasp"]
        assert len(w) == 1 and w[0].time == lost_t[0]
        if record == "all":
            # the trajectory itself agrees: NaN from the sample after that time on
            nan = np.isnan(b.q).any(axis=-1)
            assert not nan[1].any() and nan[0, -1]
            j = int(np.flatnonzero(nan[0])[0])
            assert nan[0, j:].all() and b.t[j - 1] == lost_t[0]
    assert [("grasp" in _serial_kinds(b.scene_at(i), 0.3, 1e-3)) for i in range(2)] == [True, False]


def test_sweep_progress_is_called_per_chunk(fig3):
    """progress=callable gets (done, total) once per finished chunk; the
    default chunk gives about eight chunks per worker, so a 183-point grid
    on 2 workers comes in chunks of ceil(183 / 16) = 12 points: 16 reports."""
    calls = []
    with cf.ThreadPoolExecutor(max_workers=2) as ex:
        sweep(fig3, {"grip_force": np.linspace(1.3, 1.7, 7)}, executor=ex, chunk=2, t_end=0.05, dt=1e-3,
              progress=lambda done, total: calls.append((done, total)))
    assert [c[1] for c in calls] == [7] * 4
    assert sorted(c[0] for c in calls) == [c[0] for c in calls] and calls[-1][0] == 7
    assert sorted(np.diff([0] + [c[0] for c in calls])) == [1, 2, 2, 2]
    calls.clear()
    with cf.ThreadPoolExecutor(max_workers=2) as ex:
        sweep(fig3, {"grip_force": np.linspace(1.3, 1.7, 61), "beta": [0.8, 0.85, 0.9]}, executor=ex,
              t_end=0.01, dt=1e-3, progress=lambda done, total: calls.append(done))
    assert len(calls) == 16 and calls[-1] == 183 and calls[0] == 12
    with pytest.raises(TypeError, match="progress must be"):
        sweep(fig3, {"mu": [0.1]}, t_end=0.01, progress="yes")


def test_parameters_the_scene_does_not_read_are_refused():
    """e_r where the contact region gives the surface (the exact surface, or
    pads on the fingers) and the patch centre with pads: a batch, a plan and
    a sensitivity of them would vary nothing, so each names why."""
    body = exdex.Body.box(0.1, (0.06, 0.03, 0.02))
    exact = exdex.Scene(body=body, grasp=exdex.Grasp(0.5, 2.0, exdex.Patch.rectangle(0.02, 0.02),
                                                     limit_surface="exact"), dof="planar")
    pads = exdex.Scene(body=body, grasp=exdex.Grasp(0.5, 2.0, pad=exdex.Pad.rectangle(0.02, 0.02)), dof="planar")
    for sc, name, why in ((exact, "e_r", "exact limit surface"), (pads, "e_r", "pads on the fingers"),
                          (pads, "patch_x", "centre of pressure")):
        with pytest.raises(ValueError, match=f"batch parameter '{name}' does not change this scene: .*{why}"):
            exdex.simulate_batch(sc, 0.1, 0.01, **{name: [0.001, 0.002]})
        with pytest.raises(ValueError, match=f"cannot vary '{name}': .*{why}"):
            exdex.sensitivity(sc, [name], t_end=0.1)
    # the exact surface's patch centre moves its region: read
    b = exdex.simulate_batch(exact, 0.1, 0.01, patch_x=[0.0, 0.002])
    assert b.q.shape[0] == 2


def test_patch_centre_batch_off_the_face_is_refused_naming_the_entry():
    """patch_x / patch_y get Scene's check: a centre off the 3 x 6 cm box's
    face (x = 0.1 m: 0.1 - 0.015 = 0.085 m outside) names its batch index."""
    with pytest.raises(ValueError, match=r"batch index 2: patch_x = 0\.1, patch_y = 0 put Grasp\.patch\.center "
                                         r"0\.085 m outside"):
        simulate_batch(_readme_box(), 0.01, 1e-3, patch_x=[0.0, 0.015, 0.1])
    with pytest.raises(ValueError, match=r"batch index 1: .*patch_y = -0\.0301"):
        simulate_batch(_readme_box(), 0.01, 1e-3, patch_y=[0.03, -0.0301])
    b = simulate_batch(_readme_box(), 0.01, 1e-3, patch_x=[-0.015, 0.015], patch_y=[0.03, -0.03])   # the corners
    assert len(b) == 2

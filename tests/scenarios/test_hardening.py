"""Hardening of the Python boundary and of the C core.

* The plain-C fuzz driver (csrc/fuzz/, `make -C csrc fuzz-quick`) runs >= 10^5
  decoded inputs over every C entry point: no crash, no hang, status codes for
  invalid input, finite output whenever the status is OK.
* Memory stays flat over 10^5 calls of each entry point of exdex._core and
  exdex._tool (tracemalloc for Python-level objects including NumPy data,
  resident set size for C allocations such as GSL workspaces), on success and
  on error paths, and the reference counts of the inputs do not change.
* Inputs are never modified; non-contiguous, Fortran-ordered, read-only,
  float32 and integer arrays give bit-identical results to C-ordered float64
  arrays of the same values (or a clear TypeError/ValueError naming the
  argument).
* Concurrent calls from several threads give results identical to serial
  calls; the same scene gives bit-identical trajectories across runs,
  processes and thread counts.

Expected values here are never numbers from the code under test: they are
the same call made serially / with canonical arrays / in another process
(determinism), or properties (flat memory, unchanged inputs).
"""
import gc
import hashlib
import os
import re
import shutil
import subprocess
import sys
import threading
import tracemalloc
from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pytest

import exdex
from exdex import _core, _tool

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
CSRC = os.path.join(ROOT, "csrc")

# 10^5 calls per entry point (the figure); EXDEX_HARDENING_CALLS
# overrides it (e.g. 10^6 for a longer local run).
N_CALLS = int(os.environ.get("EXDEX_HARDENING_CALLS", "100000"))
N_ERROR_CALLS = max(N_CALLS // 10, 1000)

UNIT_SQUARE = np.array([[-0.5, -0.5], [0.5, -0.5], [0.5, 0.5], [-0.5, 0.5]])
LO = np.array([-0.5 / np.sqrt(2), -0.5 / np.sqrt(2), -1.0])
HI = -LO


# ----------------------------------------------------------------- scenes

def fig3_scene(**kw):
    """The Fig. 3 scene (exdex.paper.fig3_scene): vertical slip under Eq. 7."""
    return exdex.Scene(body=exdex.Body(mass=0.1), grasp=exdex.Grasp(mu=0.5, grip_force=1.5),
                       motion=exdex.AsymmetricProfile(0.1, 0.5, 0.9, axis=(0, 0, -1)), **kw)


def planar_stop_scene():
    """A planar box under a rotating gripper, falling onto a tilted stop."""
    body = exdex.Body.box(0.2, (0.04, 0.06, 0.02))
    return exdex.Scene(body=body, grasp=exdex.Grasp(mu=0.3, grip_force=0.8, patch=exdex.Patch(0.01, (0.004, -0.003))),
                       motion=exdex.AsymmetricProfile(0.6, 0.3, 0.7, axis=(0, 1, 0), rotation=True,
                                                      center=(0.0, 0.0, 0.05)),
                       dof="planar", q0=(0.0, 0.0, 0.1),
                       stops=(exdex.Stop(point=(0, 0, -0.08), normal=(0.1, 0, 1)),))


def rotation_scene():
    """Fig. 6-like pivoting (paper Section 2.3)."""
    body = exdex.Body(mass=0.1, inertia=np.diag([0.5, 0.5, 0.04]))
    return exdex.Scene(body=body, grasp=exdex.Grasp(mu=0.5, grip_force=2.0, patch=exdex.Patch(0.01, (0.0, 0.05))),
                       motion=exdex.AsymmetricProfile(np.radians(100), 3.0, 0.7, axis=(0, 1, 0), rotation=True),
                       dof="rotation")


def sampled_scene():
    t = np.linspace(0.0, 0.4, 9)
    pos = np.stack([0.02 * np.sin(5 * t), np.zeros_like(t), -0.3 * t**2], axis=1)
    ang = 0.4 * t
    quat = np.stack([np.cos(ang / 2), np.zeros_like(t), np.sin(ang / 2), np.zeros_like(t)], axis=1)
    body = exdex.Body.box(0.1, (0.03, 0.05, 0.02))
    return exdex.Scene(body=body, grasp=exdex.Grasp(mu=0.4, grip_force=0.6), dof="planar",
                       motion=exdex.SampledTrajectory(t, pos, quat))


SCENES = {
    "fig3": (fig3_scene(), "scalar", 1.2),
    "planar_stop_scalar": (planar_stop_scene(), "scalar", 0.5),
    "planar_stop_brent": (planar_stop_scene(), "brent", 0.5),
    "planar_stop_multiroot": (planar_stop_scene(), "multiroot", 0.5),
    "rotation": (rotation_scene(), "scalar", 2.0),
    "sampled": (sampled_scene(), "scalar", 0.5),
}


def trajectory_bytes(res):
    """Every output array of a Result, concatenated as raw bytes."""
    parts = [np.ascontiguousarray(a).tobytes() for a in (res.t, res.q, res.v, res.wrench, res.stick, res.stop_force)]
    parts.append(repr(sorted(res.stats.items())).encode())
    return b"".join(parts)


def run_scene(name, dt=1e-3):
    scene, solver, t_end = SCENES[name]
    return exdex.simulate(scene, t_end, dt=dt, friction_solver=solver)


# ----------------------------------------------------------------- the C fuzz driver

def _have_c_toolchain():
    return all(shutil.which(x) for x in ("make", "gsl-config")) and (shutil.which("cc") or shutil.which("gcc"))


@pytest.mark.skipif(not _have_c_toolchain(), reason="needs make, a C compiler and gsl-config")
def test_c_fuzz_driver_quick(tmp_path):
    """>= 10^5 fuzzed inputs over every C entry point, plus the seed corpus:
    no crash, no hang beyond the budget, 0 failed checks (csrc/fuzz/fuzz.h)."""
    per_target = max(N_CALLS // 5, 2000)
    build = "build-pytest-fuzz"
    proc = subprocess.run(["make", "-s", "-C", CSRC, f"BUILD={build}", "fuzz-quick", f"FUZZ_QUICK_N={per_target}"],
                          capture_output=True, text=True, timeout=900)
    out = proc.stdout + proc.stderr
    assert proc.returncode == 0, out[-4000:]
    m = re.search(r"^fuzz: (\d+) inputs, (\d+) failed checks", proc.stdout, re.M)
    assert m, out[-4000:]
    assert int(m.group(2)) == 0, out[-4000:]
    assert int(m.group(1)) >= min(N_CALLS, 6 * per_target), out[-4000:]


# ----------------------------------------------------------------- memory and references

def _rss_bytes():
    try:
        with open("/proc/self/statm") as f:
            return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")
    except OSError:  # not Linux: fall back to maxrss (never decreases, still flat)
        import resource
        r = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
        return r if sys.platform == "darwin" else r * 1024


def assert_flat(fn, n, inputs=(), expect=None):
    """Call fn() n times: traced Python memory (tracemalloc, NumPy data
    included) grows by < 64 KiB, the resident set by < 4 MiB (a leak of 40
    bytes per call over 10^5 calls is 4 MB), and the reference counts of the
    inputs do not change. expect: an exception type every call must raise."""

    def call():
        if expect is None:
            return fn()
        try:
            fn()
        except expect:
            return None
        raise AssertionError(f"{fn} did not raise {expect}")

    for _ in range(200):  # warm-up: caches, interned strings, first allocations
        call()
    gc.collect()
    refs = [sys.getrefcount(x) for x in inputs]
    tracemalloc.start()
    try:
        mem0, _ = tracemalloc.get_traced_memory()
        rss0 = _rss_bytes()
        for _ in range(n):
            call()
        gc.collect()
        mem1, _ = tracemalloc.get_traced_memory()
        rss1 = _rss_bytes()
    finally:
        tracemalloc.stop()
    assert mem1 - mem0 < 64 * 1024, f"traced memory grew by {mem1 - mem0} bytes over {n} calls"
    assert rss1 - rss0 < 4 * 1024 * 1024, f"resident set grew by {rss1 - rss0} bytes over {n} calls"
    assert [sys.getrefcount(x) for x in inputs] == refs, "reference counts of the inputs changed"
    return mem1 - mem0, rss1 - rss0


def _entry_points():
    """(name, fn, inputs, n, expected exception) for every entry point: the
    success path with N_CALLS calls and error paths with N_ERROR_CALLS."""
    spec = fig3_scene().to_spec()
    spec_planar = planar_stop_scene().to_spec(friction_solver="multiroot")
    spec_sampled = sampled_scene().to_spec()
    bad_spec = dict(spec, mass=-1.0)
    t = np.array([0.0, 0.1, 0.7])
    W = np.array([[2.0, 0.1, 0.0], [0.1, 1.0, 0.2], [0.0, 0.2, 3.0]])
    b = np.array([1.0, -2.0, 0.5])
    e = np.array([1.0, 1.0, 0.01])
    W_bad = -W
    rows = np.random.default_rng(1).normal(size=(2, 4, 3))
    rows_nan = rows.copy()
    rows_nan[0, 0, 0] = np.nan
    shapes = [UNIT_SQUARE]
    phi = np.array([0.1, 0.7])
    tools = np.array([[0.0, np.pi / 2, 0.0], [0.1, 1.2, 0.0]])
    pts = np.array([[0.5, 0.0], [0.0, 0.5]])
    nrm = np.array([[-1.0, 0.0], [0.0, -1.0]])
    x0 = np.array([0.0, 1.5, 0.0])
    free = np.array([0, 1, 0])
    step = np.array([0.1, 0.1, 0.1])
    N, NE = N_CALLS, N_ERROR_CALLS
    model = _core.compile(spec)
    model_planar = _core.compile(spec_planar)
    return [
        ("compile", lambda: _core.compile(spec), (spec,), N, None),
        ("compile bad spec", lambda: _core.compile(bad_spec), (bad_spec,), NE, ValueError),
        ("Model.simulate", lambda: model.simulate(2e-3, 1e-3), (model,), N, None),
        ("Model.final planar stop", lambda: model_planar.final(2e-3, 1e-3), (model_planar,), N, None),
        ("Model.final bad dt", lambda: model.final(2e-3, -1.0), (model,), NE, ValueError),
        ("simulate", lambda: _core.simulate(spec, 2e-3, 1e-3), (spec,), N, None),
        ("simulate planar stop multiroot", lambda: _core.simulate(spec_planar, 2e-3, 1e-3), (spec_planar,), N, None),
        ("simulate sampled", lambda: _core.simulate(spec_sampled, 2e-3, 1e-3), (spec_sampled,), N, None),
        ("simulate bad spec", lambda: _core.simulate(bad_spec, 2e-3, 1e-3), (bad_spec,), NE, ValueError),
        ("simulate missing key", lambda: _core.simulate({"mass": 1.0}, 2e-3, 1e-3), (), NE, KeyError),
        ("exdex.simulate", lambda: exdex.simulate(SCENES["fig3"][0], 2e-3, 1e-3), (), N // 4, None),
        ("motion_eval", lambda: _core.motion_eval(spec, t), (spec, t), N, None),
        ("motion_eval sampled", lambda: _core.motion_eval(spec_sampled, t), (spec_sampled, t), N, None),
        ("motion_eval bad", lambda: _core.motion_eval(dict(spec, motion_duration=-1.0), t), (t,), NE, ValueError),
        ("friction_solve scalar", lambda: _core.friction_solve(W, b, e, 0.5), (W, b, e), N, None),
        ("friction_solve brent", lambda: _core.friction_solve(W, b, e, 0.5, 1), (W, b, e), N, None),
        ("friction_solve multiroot", lambda: _core.friction_solve(W, b, e, 0.5, 2), (W, b, e), N, None),
        ("friction_solve bad W", lambda: _core.friction_solve(W_bad, b, e, 0.5, 2), (W_bad, b, e), NE, ValueError),
        ("er_disc", lambda: _core.er_disc(0.01), (), N, None),
        ("er_rectangle", lambda: _core.er_rectangle(0.01, 0.02), (), N, None),
        ("n_samples", lambda: _core.n_samples(1.0, 1e-3), (), N, None),
        ("volumes exact", lambda: _tool.volumes(rows, LO, HI), (rows, LO, HI), N, None),
        ("volumes qmc", lambda: _tool.volumes(rows, LO, HI, method="qmc", qmc_points=64, qmc_shifts=4),
         (rows, LO, HI), N // 4, None),
        ("volumes grid", lambda: _tool.volumes(rows, LO, HI, method="grid", grid_n=4), (rows, LO, HI), N // 4, None),
        ("volumes NaN", lambda: _tool.volumes(rows_nan, LO, HI), (rows_nan,), NE, ValueError),
        ("paper_rows", lambda: _tool.paper_rows(phi, phi + 1.0), (phi,), N, None),
        ("contact_rows", lambda: _tool.contact_rows(pts, nrm, mu=0.3), (pts, nrm), N, None),
        ("tool_rows", lambda: _tool.tool_rows(shapes, 0.1, LO, HI, 0.0, 1.5, s=0.1), (shapes, LO, HI), N, None),
        ("tool_volumes", lambda: _tool.tool_volumes(shapes, phi, LO, HI, tools), (shapes, phi, tools), N, None),
        ("tool_volumes bad shape", lambda: _tool.tool_volumes([np.zeros((4, 2))], phi, LO, HI, tools), (phi,), NE,
         ValueError),
        ("optimise_theta", lambda: _tool.optimise_theta(shapes, phi, LO, HI, 0.5, 2.5, n_scan=5),
         (shapes, phi), N // 10, None),
        ("optimise_tool", lambda: _tool.optimise_tool(shapes, phi, LO, HI, x0, free, step, max_iter=5),
         (shapes, phi, x0, free, step), N // 10, None),
    ]


@pytest.mark.parametrize("case", _entry_points(), ids=lambda c: c[0])
def test_memory_flat_and_refcounts(case):
    name, fn, inputs, n, expect = case
    traced, rss = assert_flat(fn, n, inputs, expect)
    print(f"{name}: {n} calls, traced memory {traced:+d} B, resident set {rss:+d} B")


# ----------------------------------------------------------------- inputs never modified

def test_inputs_never_modified():
    spec = planar_stop_scene().to_spec(friction_solver="multiroot")
    spec_copy = {k: (v.copy() if isinstance(v, np.ndarray) else v) for k, v in spec.items()}
    W = np.array([[2.0, 0.1, 0.0], [0.1, 1.0, 0.2], [0.0, 0.2, 3.0]])
    b, e = np.array([1.0, -2.0, 0.5]), np.array([1.0, 1.0, 0.01])
    rows = np.random.default_rng(2).normal(size=(3, 5, 3))
    shapes = [UNIT_SQUARE.copy(), 0.5 * UNIT_SQUARE]
    phi, tools = np.array([0.2, 0.4]), np.array([[0.0, 1.5, 0.1]])
    t = np.linspace(0, 1, 5)
    arrays = [W, b, e, rows, shapes[0], shapes[1], phi, tools, t, LO, HI]
    before = [a.copy() for a in arrays]
    _core.simulate(spec, 0.05, 1e-3)
    _core.motion_eval(spec, t)
    for solver in (0, 1, 2):
        _core.friction_solve(W, b, e, 0.3, solver)
    _tool.volumes(rows, LO, HI)
    _tool.volumes(rows, LO, HI, method="qmc", qmc_points=128, qmc_shifts=2)
    _tool.tool_rows(shapes, 0.3, LO, HI, 0.0, 1.4, s=0.0)
    _tool.tool_volumes(shapes, phi, LO, HI, tools)
    _tool.optimise_theta(shapes, phi, LO, HI, 0.5, 2.5, n_scan=7)
    _tool.optimise_tool(shapes, phi, LO, HI, tools[0], np.array([1, 1, 0]), np.array([0.1, 0.1, 0.1]), max_iter=20)
    for a, a0 in zip(arrays, before):
        assert np.array_equal(a, a0)
    assert spec.keys() == spec_copy.keys()
    for k in spec:
        if isinstance(spec[k], np.ndarray):
            assert np.array_equal(spec[k], spec_copy[k]), k
        else:
            assert spec[k] == spec_copy[k], k


# ----------------------------------------------------------------- array layouts and dtypes

def _layouts(a):
    """Variants of a float64 array with the same values: (name, array, exact)."""
    out = [("fortran", np.asfortranarray(a), True)]
    big = np.zeros(a.shape + (2,))
    big[..., 0] = a
    out.append(("non-contiguous", big[..., 0], True))
    ro = a.copy()
    ro.setflags(write=False)
    out.append(("read-only", ro, True))
    rev = a[::-1].copy()[::-1] if a.ndim else a
    out.append(("negative strides", rev, True))
    if np.all(a == np.round(a)):
        out.append(("int64", a.astype(np.int64), True))
        out.append(("int32", a.astype(np.int32), True))
    f32 = a.astype(np.float32)
    out.append(("float32", f32, np.array_equal(f32.astype(np.float64), a)))
    return out


def _same(x, y):
    if isinstance(x, dict):
        return x.keys() == y.keys() and all(_same(x[k], y[k]) for k in x)
    if isinstance(x, (tuple, list)):
        return len(x) == len(y) and all(_same(a, b) for a, b in zip(x, y))
    if isinstance(x, np.ndarray):
        return x.dtype == y.dtype and x.shape == y.shape and x.tobytes() == y.tobytes()
    if isinstance(x, float) and np.isnan(x):
        return isinstance(y, float) and np.isnan(y)
    return x == y


def test_friction_solve_layouts():
    W = np.array([[2.0, 0.5, 0.0], [0.5, 1.0, 0.25], [0.0, 0.25, 3.0]])
    b, e = np.array([1.0, -2.0, 0.5]), np.array([1.0, 1.0, 0.0625])
    for solver in (0, 1, 2):
        ref = _core.friction_solve(W, b, e, 0.5, solver)
        for name, Wv, exact in _layouts(W):
            assert _same(_core.friction_solve(Wv, b, e, 0.5, solver), ref), name
        for name, bv, exact in _layouts(b):
            assert _same(_core.friction_solve(W, bv, e, 0.5, solver), ref), name
        # float32 of non-representable values: same as float64 of the rounded values
        b32 = np.array([0.1, -0.2, 0.3], dtype=np.float32)
        assert _same(_core.friction_solve(W, b32, e, 0.5, solver),
                     _core.friction_solve(W, b32.astype(np.float64), e, 0.5, solver))


def test_simulate_spec_layouts():
    spec = planar_stop_scene().to_spec()
    ref = _core.simulate(spec, 0.05, 1e-3)
    for key in ("inertia", "R0", "vertices", "stop_points", "stop_normals", "gravity", "q0"):
        base = np.asarray(spec[key], dtype=np.float64)
        if key in ("inertia", "R0"):
            base = base.reshape(3, 3)
        for name, arr, exact in _layouts(base):
            if not exact:
                continue
            out = _core.simulate(dict(spec, **{key: arr}), 0.05, 1e-3)
            assert _same(out, ref), (key, name)


def test_tool_layouts():
    rows = np.random.default_rng(3).integers(-3, 4, size=(4, 5, 3)).astype(np.float64)
    ref = _tool.volumes(rows, LO, HI)
    for name, arr, exact in _layouts(rows):
        assert _same(_tool.volumes(arr, LO, HI), ref), name
    for name, arr, exact in _layouts(HI):
        if exact:
            assert _same(_tool.volumes(rows, -arr, arr), ref), name
    phi, tools = np.array([0.25, 0.5]), np.array([[0.0, 1.5, 0.0], [0.125, 1.25, 0.0]])
    ref = _tool.tool_volumes([UNIT_SQUARE], phi, LO, HI, tools)
    for name, arr, exact in _layouts(UNIT_SQUARE):
        assert _same(_tool.tool_volumes([arr], phi, LO, HI, tools), ref), name
    for name, arr, exact in _layouts(tools):
        if exact:
            assert _same(_tool.tool_volumes([UNIT_SQUARE], phi, LO, HI, arr), ref), name
    for name, arr, exact in _layouts(phi):
        if exact:
            assert _same(_tool.tool_volumes([UNIT_SQUARE], arr, LO, HI, tools), ref), name


def test_motion_eval_layouts():
    spec = sampled_scene().to_spec()
    t = np.linspace(0.0, 0.5, 11)
    ref = _core.motion_eval(spec, t)
    for name, arr, exact in _layouts(t):
        if exact:
            assert _same(_core.motion_eval(spec, arr), ref), name
    for name, arr, exact in _layouts(np.asarray(spec["motion_poses"])):
        if exact:
            assert _same(_core.motion_eval(dict(spec, motion_poses=arr), t), ref), name


@pytest.mark.parametrize("bad, exc", [
    (np.array([1 + 2j, 0, 0]), (TypeError, ValueError)),
    (np.array(["a", "b", "c"]), (TypeError, ValueError)),
    (np.array([object(), 1, 2], dtype=object), (TypeError, ValueError)),
    ("abc", (TypeError, ValueError)),
    (None, (TypeError, ValueError)),
    (np.zeros(4), ValueError),
    (np.zeros((2, 2)), ValueError),
    (np.array([np.nan, 0.0, 0.0]), ValueError),
    (np.array([np.inf, 0.0, 0.0]), ValueError),
])
def test_bad_arrays_rejected_with_clear_error(bad, exc):
    """Wrong dtypes, shapes and non-finite values: a TypeError or ValueError
    naming the argument, never a crash or a silent result."""
    W, e = np.eye(3), np.array([1.0, 1.0, 0.01])
    with pytest.raises(exc) as info:
        _core.friction_solve(W, bad, e, 0.5)
    assert "b" in str(info.value)
    spec = fig3_scene().to_spec()
    with pytest.raises(exc) as info:
        _core.simulate(dict(spec, gravity=bad), 0.01, 1e-3)
    assert "gravity" in str(info.value)
    with pytest.raises(exc) as info:
        _tool.volumes(np.zeros((1, 2, 3)), bad, HI)
    assert "lo" in str(info.value)


def test_python_api_accepts_any_real_array_layout():
    """The scene dataclasses take float32, int, Fortran-ordered and read-only
    arrays and give the same trajectory as tuples of floats."""
    ref = exdex.simulate(planar_stop_scene(), 0.05)
    R = np.asfortranarray(np.array(exdex.scene.DEFAULT_GRIPPER_ROTATION))
    R.setflags(write=False)
    body = exdex.Body.box(0.2, (0.04, 0.06, 0.02))
    sc = exdex.replace(planar_stop_scene(), gripper_rotation=R, q0=np.array([0.0, 0.0, 0.1], dtype=np.float64),
                       v0=np.zeros(3, dtype=np.int32), gravity=np.array([0.0, 0.0, -9.81]),
                       body=exdex.Body(mass=body.mass, inertia=np.asfortranarray(np.array(body.inertia))[:, :],
                                       size=np.array(body.size)))
    out = exdex.simulate(sc, 0.05)
    assert trajectory_bytes(out) == trajectory_bytes(ref)


# ----------------------------------------------------------------- threads and determinism

def test_concurrent_calls_identical_to_serial():
    names = list(SCENES)
    serial = {n: trajectory_bytes(run_scene(n, dt=2e-3)) for n in names}
    W = np.array([[2.0, 0.5, 0.0], [0.5, 1.0, 0.25], [0.0, 0.25, 3.0]])
    rng = np.random.default_rng(4)
    bs = rng.normal(size=(64, 3))
    fr_serial = [[_core.friction_solve(W, b, np.array([1, 1, 0.05]), 0.7, s) for b in bs] for s in (0, 1, 2)]
    rows = rng.normal(size=(50, 6, 3))
    vol_serial = _tool.volumes(rows, LO, HI, method="qmc", qmc_points=256, qmc_shifts=4)
    theta_serial = _tool.optimise_theta([UNIT_SQUARE], np.linspace(0, 1.5, 7), LO, HI, 0.3, 2.8, n_scan=19)

    def work(i):
        n = names[i % len(names)]
        out = {"traj": (n, trajectory_bytes(run_scene(n, dt=2e-3)))}
        s = i % 3
        out["fr"] = (s, [_core.friction_solve(W, b, np.array([1, 1, 0.05]), 0.7, s) for b in bs])
        out["vol"] = _tool.volumes(rows, LO, HI, method="qmc", qmc_points=256, qmc_shifts=4)
        out["theta"] = _tool.optimise_theta([UNIT_SQUARE], np.linspace(0, 1.5, 7), LO, HI, 0.3, 2.8, n_scan=19)
        return out

    for workers in (2, 4, 8):
        with ThreadPoolExecutor(max_workers=workers) as ex:
            results = list(ex.map(work, range(3 * len(names))))
        for r in results:
            n, traj = r["traj"]
            assert traj == serial[n], (workers, n)
            s, fr = r["fr"]
            assert _same(fr, fr_serial[s]), (workers, s)
            assert _same(r["vol"], vol_serial)
            assert _same(r["theta"], theta_serial)


def test_gil_released_threads_make_progress():
    """A long simulate in one thread does not block another thread (the GIL
    is released around the C loop)."""
    scene, solver, _ = SCENES["planar_stop_multiroot"]
    done = threading.Event()
    ticks = []

    def ticker():
        while not done.is_set():
            ticks.append(1)
            done.wait(0.001)

    th = threading.Thread(target=ticker)
    th.start()
    try:
        exdex.simulate(scene, 2.0, dt=2e-5, friction_solver=solver)
    finally:
        done.set()
        th.join()
    assert len(ticks) > 5


def test_bit_identical_across_runs():
    for name in SCENES:
        first = trajectory_bytes(run_scene(name))
        for _ in range(3):
            assert trajectory_bytes(run_scene(name)) == first, name


_CHILD = r"""
import hashlib, sys
sys.path.insert(0, sys.argv[1])
sys.path.insert(0, sys.argv[2])
import test_hardening as th
from concurrent.futures import ThreadPoolExecutor
def h(name):
    return name + " " + hashlib.sha256(th.trajectory_bytes(th.run_scene(name))).hexdigest()
workers = int(sys.argv[3])
with ThreadPoolExecutor(max_workers=workers) as ex:
    for line in ex.map(h, sorted(th.SCENES)):
        print(line)
"""


def test_bit_identical_across_processes_and_thread_counts():
    """The same scenes hashed in fresh processes with 1 and 4 worker threads
    and different BLAS/OpenMP thread settings: identical digests."""
    here = os.path.dirname(os.path.abspath(__file__))
    digests = []
    for workers, env_threads in ((1, "1"), (4, "4"), (3, "2")):
        env = dict(os.environ, OMP_NUM_THREADS=env_threads, OPENBLAS_NUM_THREADS=env_threads,
                   MKL_NUM_THREADS=env_threads)
        proc = subprocess.run([sys.executable, "-c", _CHILD, ROOT, here, str(workers)], capture_output=True,
                              text=True, env=env, timeout=600)
        assert proc.returncode == 0, proc.stderr[-3000:]
        digests.append(proc.stdout)
    local = "".join(f"{n} {hashlib.sha256(trajectory_bytes(run_scene(n))).hexdigest()}\n" for n in sorted(SCENES))
    assert digests[0] == digests[1] == digests[2] == local

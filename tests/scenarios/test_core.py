"""exdex core through the Python API: closed forms, exact stick, friction
solvers, stops, motions, and bad input. Every expected value is a closed form
or an independent computation named beside it."""
import dataclasses
import math
import threading

import numpy as np
import pytest

import exdex
from exdex import _core

G = 9.81


def box_scene(**kw):
    body = exdex.Body.box(0.1, (0.02, 0.04, 0.02))
    base = dict(body=body, grasp=exdex.Grasp(mu=0.5, grip_force=1.5, patch=exdex.Patch.rectangle(0.02, 0.04)))
    base.update(kw)
    return exdex.Scene(**base)


# ---------------------------------------------------------------- closed forms

def test_block_slides_under_gripper_acceleration():
    """Gripper accelerating up at a (first Eq. 7 phase, axis +z) with no
    gravity and capacity c < m a: the object slides down relative to the plates
    at -(a - c/m), i.e. s = -(a - c/m) t^2 / 2 until beta T."""
    m, cap = 0.1, 0.05  # capacity 0.05 N -> 0.5 m/s^2
    mo = exdex.AsymmetricProfile(0.1, 0.5, 0.9, axis=(0, 0, 1))
    sc = exdex.Scene(body=exdex.Body(mass=m), grasp=exdex.Grasp(mu=0.5, grip_force=cap), motion=mo,
                     gravity=(0, 0, 0))
    r = exdex.simulate(sc, 0.45, dt=1e-3)
    a_rel = -(mo.a_high - cap / m)
    np.testing.assert_allclose(r.q[:, 0], 0.5 * a_rel * r.t**2, atol=1e-13)
    assert not r.stick[1:].any()


def test_object_inside_ellipsoid_stays_exactly_still_for_10s():
    """Load m g with capacity 1.02 m g: zero drift, bit for bit, stick set."""
    sc = box_scene(grasp=exdex.Grasp(mu=0.5, grip_force=1.02 * 0.1 * G), q0=(0.001, 0.002, 0.1))
    for dof in ("translation", "planar"):
        r = exdex.simulate(exdex.replace(sc, dof=dof), 10.0, dt=1e-3)
        assert np.all(r.v == 0.0)
        assert np.all(r.q == r.q[0])
        assert r.stick.all()
        assert r.drift_after(0.0) == 0.0


def test_fig3_style_slip_then_exact_rest():
    """Eq. 7 down first, capacity 1.5 N (m 0.1): the object slips during the
    deceleration phase and is exactly still from the end of the motion on."""
    sc = exdex.Scene(body=exdex.Body(mass=0.1), grasp=exdex.Grasp(mu=0.5, grip_force=1.5),
                     motion=exdex.AsymmetricProfile(0.1, 0.5, 0.9, axis=(0, 0, -1)))
    r = exdex.simulate(sc, 2.0, dt=1e-3)
    after = r.t >= 1.0
    assert np.all(r.v[after] == 0.0) and r.stick[after].all()
    assert np.all(r.q[after] == r.q[-1])
    # friction force while sliding is the capacity, against the relative velocity
    sliding = ~r.stick
    sliding[0] = False
    assert np.allclose(np.abs(r.wrench[sliding, 1]), 1.5, rtol=1e-12)


def test_rotation_scene_friction_torque_capacity():
    """Rotation about the pivot with the gripper at rest, no gravity, initial
    spin w0: the friction torque is mu N e_r, so the spin decays linearly,
    w(t) = w0 - mu N e_r t / I_zz, and stops at t* = I_zz w0 / (mu N e_r)."""
    patch = exdex.Patch.disc(0.01)
    sc = exdex.Scene(body=exdex.Body(mass=0.1, inertia=np.diag([1e-4, 1e-4, 2e-5])),
                     grasp=exdex.Grasp(mu=0.5, grip_force=1.0, patch=patch), dof="rotation",
                     v0=(0, 0, 3.0), gravity=(0, 0, 0))
    torque = 0.5 * 2 * 1.0 * (2 * 0.01 / 3)
    r = exdex.simulate(sc, 0.2, dt=1e-4)
    t_star = 2e-5 * 3.0 / torque
    moving = r.t < t_star - 1e-4
    np.testing.assert_allclose(r.v[moving, 0], 3.0 - torque / 2e-5 * r.t[moving], atol=1e-10)
    assert np.all(r.v[r.t > t_star + 1e-4] == 0.0)
    assert r.q[-1, 0] == pytest.approx(3.0 * t_star / 2, rel=1e-3)


@pytest.mark.parametrize("ratio", [0.5, 2.0])
def test_implicit_slip_stopping_or_reversing_inside_a_step_is_exact(ratio):
    """Vertical slide (B y = A z, gravity along -q), gripper at rest, the
    object thrown up at v0 = 1 m/s with capacity C = ratio m g: the slip
    decelerates at a1 = g + C / m and stops at t* = v0 / a1, having risen
    v0 t* / 2. With C < m g (ratio 0.5) it reverses at once and slides down
    at a2 = g - C / m: q(t) = v0 t* / 2 - a2 (t - t*)^2 / 2 after t*; with
    C >= m g (ratio 2) it stays at rest there. The forces are constant, so
    the implicit method, which places a stop inside a step where the slip
    ends under the step's constant force, is exact to rounding at every
    step of a nested ladder (t* = 0.0203.. s or 0.0340.. s is on none of the
    grids). Placing the stop at the step's end instead (rest at q + h v /
    2; a reversal stalled at rest until the step's end, or slid through with
    the new direction's friction over the whole step) errs by up to h^2 a1 /
    2 in q or 2 C t* / m in speed: 5e-6 m and more at these steps."""
    m, v0, t_end = 0.1, 1.0, 0.08
    C = ratio * m * G
    sc = exdex.Scene(body=exdex.Body(mass=m), grasp=exdex.Grasp(mu=0.5, grip_force=C), slide_axis=(0, 1),
                     v0=(0.0, v0, 0.0))
    a1 = G + C / m
    t_star = v0 / a1
    top = v0 * t_star / 2
    exact = top if ratio >= 1.0 else top - (G - C / m) * (t_end - t_star) ** 2 / 2
    for k in range(4):
        r = exdex.simulate(sc, t_end, dt=t_end / 50 / 2**k, method="implicit")
        assert r.q[-1, 0] == pytest.approx(exact, rel=1e-12, abs=1e-15), (k, r.q[-1, 0] - exact)


def test_sampled_trajectory_matches_analytic_motion():
    """mu = 0, no gravity: the object stays put in A, so its coordinate in B
    is minus the gripper displacement. Gripper y(t) = 0.02 sin(2 pi t) sampled
    every 5 ms: the cubic spline's position error bound h^4/384 max|y''''|
    = 0.02 (2 pi)^4 (5e-3)^4 / 384 ~ 5e-11 m; the midpoint scheme's error with
    dt 1e-4 over 1 s is ~ dt^2 max|y''''|... < 1e-7."""
    ts = np.arange(0.0, 1.0 + 1e-12, 5e-3)
    pos = np.zeros((len(ts), 3))
    pos[:, 2] = 0.02 * np.sin(2 * np.pi * ts)
    quat = np.tile([1.0, 0, 0, 0], (len(ts), 1))
    # gripper rotation: default plates-vertical orientation as a quaternion
    R0 = np.array(exdex.scene.DEFAULT_GRIPPER_ROTATION)
    quat[:] = exdex.scene._quat_from_matrix(R0)
    mo = exdex.SampledTrajectory(ts, pos, quat)
    sc = exdex.Scene(body=exdex.Body(mass=0.1), grasp=exdex.Grasp(mu=0.0, grip_force=0.0), motion=mo,
                     gravity=(0, 0, 0), v0=(0, -0.02 * 2 * np.pi, 0))
    r = exdex.simulate(sc, 0.9, dt=1e-4)
    # the end slopes come from the quadratic through three end samples (second order): compare inside
    inside = (r.t > 0.1) & (r.t < 0.8)
    np.testing.assert_allclose(r.q[inside, 0], -0.02 * np.sin(2 * np.pi * r.t[inside]), atol=2e-4)


def test_sampled_equals_from_matrices():
    ts = np.linspace(0, 1, 11)
    T = np.tile(np.eye(4), (11, 1, 1))
    T[:, 2, 3] = ts**2
    a = exdex.SampledTrajectory.from_matrices(ts, T)
    np.testing.assert_allclose(a.positions[:, 2], ts**2)
    np.testing.assert_allclose(np.abs(a.quaternions[:, 0]), 1.0)


# ---------------------------------------------------------------- friction solvers

def random_problem(rng):
    A = rng.normal(size=(3, 3))
    W = A @ A.T + 1e-3 * np.eye(3)
    e = np.array([1.0, 1.0, rng.uniform(1e-3, 1.0)])
    b = rng.normal(size=3)
    cap = rng.uniform(0.01, 2.0)
    return W, b, e, cap


def test_friction_solvers_agree_and_satisfy_optimality():
    """The three solvers agree to 1e-10 cap, and the sliding answer satisfies
    maximum dissipation independently: p on the ellipsoid and p parallel to
    -E^2 u (Eq. 6 optimality)."""
    rng = np.random.default_rng(1)
    for _ in range(500):
        W, b, e, cap = random_problem(rng)
        res = [_core.friction_solve(W, b, e, cap, s) for s in (0, 1, 2)]
        p0 = np.array(res[0][0])
        for p, u, sigma, stick, it in res[1:]:
            assert np.max(np.abs(np.array(p) - p0)) <= 1e-10 * cap
        p, u, sigma, stick, _ = res[0]
        p, u = np.array(p), np.array(u)
        if stick:
            assert np.all(u == 0.0)
            np.testing.assert_allclose(W @ p, -b, atol=1e-12 * (1 + np.abs(b).max()))
        else:
            assert np.linalg.norm(p / e) == pytest.approx(cap, rel=1e-12)
            d = -(e**2) * u
            cos = p @ d / (np.linalg.norm(p) * np.linalg.norm(d))
            assert cos == pytest.approx(1.0, abs=1e-10)


def test_planar_trajectory_same_for_all_solvers():
    mo = exdex.AsymmetricProfile(1.2, 0.4, 0.7, axis=(0, -1, 0), rotation=True, center=(0.05, 0, 0))
    sc = box_scene(dof="planar", motion=mo, grasp=exdex.Grasp(mu=0.5, grip_force=0.8,
                                                              patch=exdex.Patch.rectangle(0.02, 0.04, (0.005, 0))))
    runs = [exdex.simulate(sc, 1.0, dt=1e-3, friction_solver=s) for s in ("scalar", "brent", "multiroot")]
    assert not runs[0].stick.all()  # the case exercises sliding
    for r in runs[1:]:
        np.testing.assert_allclose(r.q, runs[0].q, atol=1e-10)


def test_patch_er_closed_forms():
    assert exdex.Patch.disc(0.03).e_r == pytest.approx(0.02, rel=1e-15)
    a = 0.01  # square of half-side a: e_r = a (sqrt2 + ln(1 + sqrt2)) / 3, the mean distance of a square
    assert exdex.Patch.rectangle(2 * a, 2 * a).e_r == pytest.approx(a * (math.sqrt(2) + math.log(1 + math.sqrt(2))) / 3,
                                                            rel=1e-13)
    # mean distance of a 2a x 2b rectangle by Monte Carlo-free midpoint quadrature
    hx, hy, n = 0.01, 0.03, 800
    x = (np.arange(n) + 0.5) / n * 2 * hx - hx
    y = (np.arange(n) + 0.5) / n * 2 * hy - hy
    X, Y = np.meshgrid(x, y)
    assert exdex.Patch.rectangle(2 * hx, 2 * hy).e_r == pytest.approx(np.hypot(X, Y).mean(), rel=1e-5)


# ---------------------------------------------------------------- stops

def world_vertices(result):
    """World coordinates of the body outline at every sample (independent of
    the C geometry): A = p_B + R_B (r + Rz(theta) v)."""
    sc = result.scene
    k = sc.motion.evaluate(result.t, sc.gripper_rotation, sc.gripper_position)
    pose = result.pose
    V = sc.body.vertices()
    out = []
    for i in range(len(result.t)):
        c, s = math.cos(pose[i, 2]), math.sin(pose[i, 2])
        xb = np.column_stack([pose[i, 0] + c * V[:, 0] - s * V[:, 1], pose[i, 1] + s * V[:, 0] + c * V[:, 1],
                              np.zeros(len(V))])
        out.append(k["p"][i] + xb @ k["R"][i].T)
    return np.array(out)


@pytest.mark.parametrize("dof", ["translation", "planar"])
def test_stop_never_penetrated(dof):
    """Box dropped (capacity 0.3 m g) onto a stop tilted by 20 deg while the
    gripper oscillates; geometric gap from Result.pose >= -1e-12 everywhere."""
    a = math.radians(20)
    sc = box_scene(dof=dof, grasp=exdex.Grasp(mu=0.5, grip_force=0.3 * 0.1 * G, patch=exdex.Patch.disc(0.01)),
                   stops=(exdex.Stop(point=(0, 0, -0.06), normal=(math.sin(a), 0, math.cos(a))),),
                   motion=exdex.AsymmetricProfile(0.02, 0.3, 0.6, axis=(1, 0, 0)))
    r = exdex.simulate(sc, 1.0, dt=1e-3)
    X = world_vertices(r)
    stop = sc.stops[0]
    gaps = (X - np.array(stop.point)) @ np.array(stop.normal)
    assert gaps.min() >= -1e-12
    assert gaps.min() < 1e-6  # it did land on the stop
    assert r.stop_force.max() > 0


def test_fig4_stop_force_is_weight_plus_capacity():
    """Object on a fixed stop while the plates slide down past it at constant
    speed: the stop carries m g plus the full friction capacity (1.5 N)."""
    sc = box_scene(motion=exdex.TrapezoidalProfile(0.05, 0.5, 0.12, axis=(0, 0, -1)),
                   stops=(exdex.Stop(point=(0, 0, -0.02), normal=(0, 0, 1)),))
    r = exdex.simulate(sc, 1.0, dt=1e-4)
    cruise = (r.t > 0.1) & (r.t < 0.4)
    np.testing.assert_allclose(r.stop_force[cruise, 0], 0.1 * G + 1.5, rtol=1e-10)
    assert r.displacement[-1, 0] == pytest.approx(0.05, abs=1e-6)
    assert np.all(r.v[r.t >= 0.5 + 1e-4] == 0.0)


# ---------------------------------------------------------------- API shape

def test_result_arrays_shapes_and_units():
    sc = box_scene(dof="planar", stops=(exdex.Stop(point=(0, 0, -0.05), normal=(0, 0, 1)),))
    r = exdex.simulate(sc, 0.1, dt=0.03)  # 0.03 0.06 0.09 then 0.1
    assert r.t.shape == (5,) and r.t[-1] == 0.1 and r.t[0] == 0.0
    assert r.q.shape == (5, 3) and r.v.shape == (5, 3) and r.wrench.shape == (5, 3)
    assert r.stick.dtype == bool and r.stop_force.shape == (5, 1)
    assert set(r.stats) >= {"steps", "stick_steps", "warnings", "min_gap"}


def test_scene_is_frozen_and_replace_makes_variants():
    sc = box_scene()
    with pytest.raises(dataclasses.FrozenInstanceError):
        sc.dof = "planar"
    sc2 = dataclasses.replace(sc, grasp=dataclasses.replace(sc.grasp, mu=0.2))
    assert sc2.grasp.mu == 0.2 and sc.grasp.mu == 0.5 and sc2.body is sc.body


def test_simulate_runs_in_threads_with_identical_results():
    sc = box_scene(dof="planar", motion=exdex.AsymmetricProfile(0.5, 0.3, 0.7, axis=(0, -1, 0), rotation=True))
    serial = exdex.simulate(sc, 0.6, dt=1e-4)
    out = [None] * 4

    def work(i):
        out[i] = exdex.simulate(sc, 0.6, dt=1e-4)

    th = [threading.Thread(target=work, args=(i,)) for i in range(4)]
    for t in th:
        t.start()
    for t in th:
        t.join()
    for r in out:
        assert np.array_equal(r.q, serial.q)


# ---------------------------------------------------------------- bad input

BODY = exdex.Body(mass=0.1)
GRASP = exdex.Grasp(mu=0.5, grip_force=1.0)

BAD = [
    (lambda: exdex.Body(mass=0.0), ValueError, "Body.mass must be in (0"),
    (lambda: exdex.Body(mass=-1), ValueError, "Body.mass"),
    (lambda: exdex.Body(mass=float("nan")), ValueError, "Body.mass must be finite"),
    (lambda: exdex.Body(mass="1"), TypeError, "Body.mass must be a real number"),
    (lambda: exdex.Body(mass=1, inertia=np.diag([1, 1, -1])), ValueError, "positive definite"),
    (lambda: exdex.Body(mass=1, inertia=[[1, 0.5, 0], [0, 1, 0], [0, 0, 1]]), ValueError, "symmetric"),
    (lambda: exdex.Body(mass=1, inertia=np.eye(2)), ValueError, "Body.inertia must have shape (3, 3)"),
    (lambda: exdex.Body(mass=1, inertia=[[1, 0, 0], [0, np.inf, 0], [0, 0, 1]]), ValueError, "finite"),
    (lambda: exdex.Grasp(mu=-0.1, grip_force=1), ValueError, "Grasp.mu must be in [0"),
    (lambda: exdex.Grasp(mu=0.5, grip_force=-1), ValueError, "Grasp.grip_force must be in [0"),
    (lambda: exdex.Grasp(mu=0.5, grip_force=1, fingers=3), ValueError, "Grasp.fingers must be 1 or 2"),
    (lambda: exdex.Patch.disc(0), ValueError, "radius must be in (0"),
    (lambda: exdex.Patch(e_r=float("inf")), ValueError, "Patch.e_r must be finite"),
    (lambda: exdex.AsymmetricProfile(0.1, 0.5, 1.0), ValueError, "AsymmetricProfile.beta must be in (0, 1)"),
    (lambda: exdex.AsymmetricProfile(0.1, -0.5, 0.5), ValueError, "AsymmetricProfile.duration"),
    (lambda: exdex.AsymmetricProfile(0.1, 0.5, 0.5, axis=(0, 0, 0)), ValueError, "axis must be a non-zero"),
    (lambda: exdex.TrapezoidalProfile(0.05, 0.5, 0.3), ValueError, "TrapezoidalProfile.v_max must be in [0.1, 0.2]"),
    (lambda: exdex.SampledTrajectory([0, 1, 1, 2], np.zeros((4, 3)), np.tile([1, 0, 0, 0], (4, 1))), ValueError,
     "strictly increasing"),
    (lambda: exdex.SampledTrajectory([0, 1, 2, 3], np.zeros((4, 2)), np.tile([1, 0, 0, 0], (4, 1))), ValueError,
     "positions must have shape (4, 3)"),
    (lambda: exdex.SampledTrajectory([0, 1, 2], np.zeros((3, 3)), np.tile([1, 0, 0, 0], (3, 1))), ValueError,
     "at least 4"),
    (lambda: exdex.SampledTrajectory(["a", "b", "c", "d"], np.zeros((4, 3)), np.tile([1, 0, 0, 0], (4, 1))),
     TypeError, "times must be an array of numbers"),
    (lambda: exdex.Scene(body=BODY, grasp=GRASP, dof="3d"), ValueError, "Scene.dof must be one of"),
    (lambda: exdex.Scene(body=BODY, grasp=GRASP, gripper_rotation=2 * np.eye(3)), ValueError, "rotation matrix"),
    (lambda: exdex.Scene(body=BODY, grasp=GRASP, gravity=(0, 0, np.nan)), ValueError, "Scene.gravity must be finite"),
    (lambda: exdex.Scene(body=BODY, grasp=GRASP, q0=(0, 0)), ValueError, "Scene.q0 must have shape (3,)"),
    (lambda: exdex.Scene(body="box", grasp=GRASP), TypeError, "Scene.body must be an exdex.Body"),
    (lambda: exdex.Scene(body=BODY, grasp=GRASP, motion="up"), TypeError, "Scene.motion must be"),
    (lambda: exdex.Scene(body=BODY, grasp=GRASP, stops=(1,)), TypeError, "Scene.stops"),
    (lambda: exdex.simulate(exdex.Scene(body=BODY, grasp=GRASP), 1.0, dt=0), ValueError, "dt must be in (0"),
    (lambda: exdex.simulate(exdex.Scene(body=BODY, grasp=GRASP), 1.0, dt=2.0), ValueError, "dt must be <= t_end"),
    (lambda: exdex.simulate(exdex.Scene(body=BODY, grasp=GRASP), float("inf")), ValueError, "t_end must be finite"),
    (lambda: exdex.simulate(exdex.Scene(body=BODY, grasp=GRASP), 1.0, method="rk4"), ValueError,
     "method must be one of"),
    (lambda: exdex.simulate(exdex.Scene(body=BODY, grasp=GRASP), 1.0, friction_solver="lcp"), ValueError,
     "friction_solver must be one of"),
    (lambda: exdex.simulate("scene", 1.0), TypeError, "scene must be an exdex.Scene"),
    (lambda: exdex.simulate(exdex.Scene(body=BODY, grasp=GRASP, stops=(exdex.Stop((0, 0, 1), (0, 0, 1)),)), 1.0),
     ValueError, "Scene.stops[0]"),
    (lambda: _core.friction_solve(np.eye(3), [1, 2], [1, 1, 1], 1.0), ValueError, "'b' must have 3 elements"),
    (lambda: _core.friction_solve(-np.eye(3), [1, 2, 3], [1, 1, 1], 1.0), ValueError, "SPD"),
    (lambda: _core.friction_solve(np.eye(3), [1, 2, 3], [1, 1, 1], -1.0), ValueError, "cap"),
    (lambda: _core.simulate({"mass": 1.0}, 1.0, 0.1), KeyError, "missing 'inertia'"),
]


@pytest.mark.parametrize("call,exc,fragment", BAD, ids=[f"bad{i}" for i in range(len(BAD))])
def test_bad_input_raises_clear_error(call, exc, fragment):
    with pytest.raises(exc) as info:
        call()
    assert fragment in str(info.value)


def test_solver_error_carries_status():
    """A non-finite state (an absurd gravity that overflows) raises the
    library exception with the C status code (EXDEX_ENONFINITE = 4)."""
    sc = exdex.Scene(body=BODY, grasp=GRASP, gravity=(0, 0, -1e308))
    with pytest.raises(exdex.SolverError) as info:
        exdex.simulate(sc, 10.0, dt=0.5)  # |v| grows by 5e306 m/s per step: overflows
    assert info.value.status == 4
    assert issubclass(exdex.SolverError, RuntimeError)


def test_result_plot_draws_each_coordinate_and_stick_shading():
    """Translations in mm and rotations in degrees never share an axis: a planar
    scene gets an mm axis (x, y) and a deg axis (theta), each labelled with its
    unit; a 1-DoF scene one labelled axis."""
    sc = exdex.Scene(body=exdex.Body(mass=0.1, inertia=1e-4), grasp=exdex.Grasp(mu=0.5, grip_force=1.5),
                     motion=exdex.AsymmetricProfile(0.1, 0.5, 0.9, axis=(0, 0, -1)), dof="planar")
    r = exdex.simulate(sc, 1.2, dt=1e-3)
    ax_mm, ax_deg = r.plot()
    assert [l.get_label() for l in ax_mm.get_lines()] == ["x [mm]", "y [mm]"]
    assert [l.get_label() for l in ax_deg.get_lines()] == ["theta [deg]"]
    assert ax_mm.get_ylabel().endswith("[mm]") and ax_deg.get_ylabel().endswith("[deg]")
    assert ax_deg.get_xlabel() == "time [s]"
    # the y line is the displacement in mm (closed-form final value -20.54 mm, see reference.dat)
    assert ax_mm.get_lines()[1].get_ydata()[-1] == pytest.approx(1e3 * r.displacement[-1, 1])
    assert len(ax_mm.collections) == 1  # the stick shading
    # on a given Axes: theta on a twin axis at the right, one legend for all
    import matplotlib.pyplot as plt

    _, ax = plt.subplots()
    a, b = r.plot(ax=ax)
    assert a is ax and b is not ax and b.get_ylabel().endswith("[deg]") and a.get_ylabel().endswith("[mm]")
    assert [t.get_text() for t in a.get_legend().get_texts()] == ["x [mm]", "y [mm]", "stick", "theta [deg]"]
    # 1-DoF scenes: one axis in its own unit
    for dof, unit in (("translation", "[mm]"), ("rotation", "[deg]")):
        ax1 = exdex.simulate(exdex.replace(sc, dof=dof), 0.3, dt=1e-3).plot()
        assert ax1.get_ylabel().endswith(unit) and all(l.get_label().endswith(unit) for l in ax1.get_lines())
    plt.close("all")

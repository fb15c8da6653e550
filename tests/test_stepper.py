"""exdex.Model and exdex.Stepper (exdex/stepper.py). A Model's runs are the
runs of exdex.simulate (same C model, same integrator), bit for bit, from
several threads too; stepping is bit-identical to exdex.simulate, save/restore
branches exactly, bad input is named, and two feedback controllers reach
their targets.

References: exdex.simulate on the same grid (the whole-run driver of the
same methods, an independent loop; for a Model an independent path through
the extension: spec conversion and model set-up on every call); closed
forms for a Model's final state and for the controllers:

* a Model's final slip with the gripper accelerating up at a and no
  gravity, capacity c < m a: s(t) = -(a - c/m) t^2 / 2;
* slip-speed control of a block sliding down between vertical plates:
  m dv/dt = -m g + 2 mu F while it slides down (v < 0). With
  F = F_ff + kp (v* - v) + ki int (v* - v) and any feed-forward F_ff, the
  error e = v - v* obeys m e'' + 2 mu kp e' + 2 mu ki e = 0: it decays to 0
  (natural frequency sqrt(2 mu ki / m), damping mu kp / sqrt(2 mu ki m));
  the integral term removes the feed-forward's error in steady state.
* gravitational pivoting: an object on a pin at the patch centre with its
  centre of mass `arm` beside it turns under the gravity torque
  m g arm cos(theta) against the friction torque C = 2 mu F e_r. With the
  grip re-closed at theta_c with rate w, it stops where the energy
  balance I w^2 / 2 = C (theta_s - theta_c) - m g arm (sin theta_s -
  sin theta_c) says; the controller closes when that stop falls on the
  target (one step of look-ahead), so it ends within about one step's
  rotation w dt of the target, and then sticks (C > m g arm).

twin: csrc/tests/test_stepper.c (the same subject on the C API)
"""
from __future__ import annotations

import math
import threading
import warnings

import numpy as np
import pytest

import exdex
from exdex import _core, paper
from zoo import zoo_scene

G = 9.81


def _compare(scene, method, n, dt, **options):
    """n steps of dt against simulate(n dt, dt): identical bits, or the same failure."""
    t_end = n * dt
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            res = exdex.simulate(scene, t_end, dt, method=method, **options)
    except exdex.SolverError as exc:
        res, err = None, exc
    st = exdex.Stepper(scene, method=method, **options)
    q, v, wr, stick, sf = [st.state.q], [st.state.v], [st.state.wrench], [st.state.stick], [st.state.stop_force]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for i in range(n):
            try:
                s = st.step(dt)
            except exdex.SolverError as exc:
                assert res is None, f"the stepper failed at step {i + 1} ({exc}), simulate did not"
                assert exc.cause == err.cause and exc.time == err.time
                return "failed"
            q.append(s.q), v.append(s.v), wr.append(s.wrench), stick.append(s.stick), sf.append(s.stop_force)
    assert res is not None, "simulate failed, the stepper did not"
    assert st.t == res.t[-1]
    for name, a, b in (("q", q, res.q), ("v", v, res.v), ("wrench", wr, res.wrench), ("stick", stick, res.stick),
                       ("stop_force", sf, res.stop_force)):
        a = np.array(a).reshape(b.shape)
        assert np.array_equal(a, b), (name, np.flatnonzero(np.any(a.reshape(len(a), -1) != b.reshape(len(b), -1), axis=1))[:5])
    assert st.stats == res.stats
    return "ok"


@pytest.mark.parametrize("seed", [3, 11, 27, 40, 58, 71])
def test_stepping_is_bit_identical_to_simulate_on_zoo_scenes(seed):
    zs = zoo_scene(seed)
    n = 120
    dt = zs.t_end / n
    for method in ("implicit", "event", "regularised", "explicit"):
        _compare(zs.scene, method, n, dt, **({"eps": 1e-3 * zs.L} if method == "regularised" else {}))
    if exdex.Model(zs.scene, method="auto").method == "analytic":
        _compare(zs.scene, "analytic", n, dt)


def test_stepping_is_bit_identical_with_a_chain_and_stops():
    body = exdex.Body.box(0.1, (0.04, 0.04, 0.02))
    scene = exdex.Scene(body=body, grasp=exdex.Grasp(0.4, 0.8), dof="planar",
                        motion=exdex.Chain([exdex.AsymmetricProfile(0.5, 0.2, 0.7, axis=(0, -1, 0), rotation=True),
                                            exdex.Pause(0.05), exdex.Shake(0.004, 8.0, cycles=2, axis=(0, 0, 1))]),
                        stops=(exdex.Stop((0, 0, -0.03), (0, 0, 1)),))
    for method in ("implicit", "event", "explicit"):
        assert _compare(scene, method, 330, 2e-3) == "ok"


@pytest.mark.parametrize("method", ["implicit", "explicit", "event"])
def test_stepper_counts_impacts_as_simulate(method):
    """A frictionless 20 mm cube falls H = 50 mm onto a floor (an impact of
    m sqrt(2 g H) at t = sqrt(2 H / g) = 0.101 s, closed form), and a cube
    on a floor that a vertically shaking gripper lifts and drops (several
    impacts). After every step n around and after the impacts, the
    stepper's impact stats (count, largest impulse, its time and stop) are
    those of simulate(n dt, dt): the time-stepping methods count an impact
    from the stop impulses of the steps around it (a scan that looks a few
    steps ahead, cut off at the end of the run), the stepper the same over
    the steps it took."""
    m, H = 0.1, 0.05
    body = exdex.Body.box(m, (0.02, 0.02, 0.02))
    fall = exdex.Scene(body=body, grasp=exdex.Grasp(mu=0.0, grip_force=1.0),
                       stops=exdex.Stop(point=(0, 0, -0.01 - H), normal=(0, 0, 1)), dof="planar")
    shake = exdex.Scene(body=body, grasp=exdex.Grasp(0.3, 2.0), dof="planar",
                        motion=exdex.Shake(0.01, 6.0, cycles=3, axis=(0, 0, 1)),
                        stops=exdex.Stop((0, 0, -0.012), (0, 0, 1)))
    keys = ("impacts", "max_impulse", "max_impulse_t", "max_impulse_stop")
    counted = []
    for scene, dt, ns in ((fall, 1e-3, range(95, 125)), (shake, 2e-3, range(1, 500, 7))):
        st = exdex.Stepper(scene, method=method)
        n_done = 0
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            for n in ns:
                while n_done < n:
                    st.step(dt)
                    n_done += 1
                ref = exdex.simulate(scene, n * dt, dt, method=method).stats
                got = st.stats
                assert [got[k] for k in keys] == [ref[k] for k in keys] or (
                    got["impacts"] == ref["impacts"] == 0), (n, got, ref)
        counted.append(st.stats["impacts"])
    assert counted[0] == 1 and counted[1] >= 2, counted
    # a snapshot carries the impulses of the last steps: stepping on from it
    # counts the same impacts
    st = exdex.Stepper(shake, method=method)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for _ in range(150):
            st.step(2e-3)
        snap = st.save()
        for _ in range(250):
            st.step(2e-3)
        first = st.stats
        st.restore(snap)
        for _ in range(250):
            st.step(2e-3)
    assert [st.stats[k] for k in keys] == [first[k] for k in keys]


def _branch_scene():
    return exdex.Scene(body=exdex.Body(0.1), grasp=exdex.Grasp(0.5, 1.5),
                       motion=exdex.AsymmetricProfile(0.1, 0.2, 0.8, axis=(0, 0, -1)))


@pytest.mark.parametrize("method", ["implicit", "event", "analytic"])
def test_save_restore_branches_exactly(method):
    model = exdex.Model(_branch_scene(), method=method)
    a, b = exdex.Stepper(model), model.stepper()
    for i in range(150):
        a.step(1e-3, None if i < 100 else 0.3)
    snap = a.save()
    assert snap.t == a.t
    first = [a.step(1e-3 if i < 30 else 2e-3, 1.0 - 0.01 * i) for i in range(60)]
    for stepper in (a, b):   # the same stepper, and another one of the same model
        stepper.restore(snap)
        again = [stepper.step(1e-3 if i < 30 else 2e-3, 1.0 - 0.01 * i) for i in range(60)]
        for x, y in zip(first, again):
            assert x.t == y.t and np.array_equal(x.q, y.q) and np.array_equal(x.v, y.v)
            assert np.array_equal(x.wrench, y.wrench) and x.stick == y.stick


def test_bad_input_names_the_parameter():
    st = exdex.Stepper(_branch_scene())
    for dt in (0.0, -1e-3, float("nan"), float("inf")):
        with pytest.raises(ValueError, match="dt must be finite and > 0"):
            st.step(dt)
    with pytest.raises(TypeError, match="dt must be a real number"):
        st.step("1e-3")
    with pytest.raises(ValueError, match="grip_force must be finite and >= 0"):
        st.step(1e-3, -1.0)
    with pytest.raises(TypeError, match="grip_force must be a real number"):
        st.step(1e-3, "strong")
    with pytest.raises(TypeError, match="state must be an exdex.StepperSnapshot"):
        st.restore(st.state)
    other = exdex.Stepper(_branch_scene())
    with pytest.raises(ValueError, match="another model"):
        st.restore(other.save())
    with pytest.raises(TypeError, match="the model's own method"):
        exdex.Stepper(exdex.Model(_branch_scene()), method="event")
    with pytest.raises(TypeError, match="scene must be an exdex.Scene or an exdex.Model"):
        exdex.Stepper("scene")
    with pytest.raises(ValueError, match="method must be one of"):
        exdex.Stepper(_branch_scene(), method="rk4")
    assert st.t == 0.0 and st.state.steps == 0   # nothing was taken
    st.step(1e-3)
    with pytest.raises(ValueError, match="cannot advance the time"):
        st.step(1e-300)
    assert st.t == 1e-3 and st.state.steps == 1


def test_release_and_regrip_closed_form():
    """Held, released (grip 0: free fall from rest, s = -g t^2 / 2, exact for
    the midpoint rule and to rtol for the event method), caught again."""
    scene = exdex.Scene(body=exdex.Body(0.2), grasp=exdex.Grasp(0.5, 3.0))
    for method in ("implicit", "event"):
        st = exdex.Stepper(scene, method=method)
        for _ in range(100):
            s = st.step(1e-3)
        assert s.q[0] == 0.0 and s.stick
        for _ in range(200):
            s = st.step(1e-3, 0.0)
        assert s.q[0] == pytest.approx(-0.5 * G * 0.2**2, rel=1e-9)
        assert s.v[0] == pytest.approx(-G * 0.2, rel=1e-9) and s.grip_force == 0.0
        # caught by 10 N per finger: capacity 10 N against the weight 1.962 N
        # decelerates it at 40.2 m/s^2, stopping 1.962 m/s within 49 ms
        for _ in range(100):
            s = st.step(1e-3, 10.0)
        assert s.v[0] == 0.0 and s.stick


def slip_speed_control(method, target=-0.05, t_end=1.0, dt=1e-3, kp=4.0, ki=80.0, ff_error=0.9):
    """PI control of the slip speed of a block between vertical plates (see
    the module docstring); the feed-forward is off by ff_error."""
    m, mu = 0.1, 0.5
    scene = exdex.Scene(body=exdex.Body.box(m, (0.04, 0.06, 0.02)), grasp=exdex.Grasp(mu, 2.0))
    st = exdex.Stepper(scene, method=method)
    ff, integral, s = ff_error * m * G / (2 * mu), 0.0, st.state
    t, v, force = [], [], []
    for _ in range(int(round(t_end / dt))):
        e = target - s.v[0]
        integral += e * dt
        f = max(0.0, ff + kp * e + ki * integral)
        s = st.step(dt, f)
        t.append(s.t), v.append(s.v[0]), force.append(f)
    return np.array(t), np.array(v), np.array(force)


@pytest.mark.parametrize("method", ["event", "implicit"])
def test_slip_speed_controller_tracks_the_target(method):
    t, v, f = slip_speed_control(method)
    # natural frequency sqrt(2 mu ki / m) = 28.3 /s, damping 0.71: the error
    # envelope is 0.05 / sqrt(1 - 0.71^2) exp(-20 t) = 0.071 exp(-20 t), below
    # 6e-6 m/s from 0.5 s on (starting the clock at 0 although the slip starts
    # only when the grip has opened: a few ms); asserted with a factor 3
    late = t >= 0.5
    assert np.max(np.abs(v[late] + 0.05)) < 2e-5
    assert np.all(v[t >= 0.05] < 0)       # it slides down once the grip opens
    # steady state: friction balances the weight, 2 mu F = m g
    assert f[-1] == pytest.approx(0.1 * G / (2 * 0.5), rel=1e-6)


def pivot_control(method, target=math.radians(60), dt=1e-3, t_end=1.5):
    """Open the grip, let gravity turn the object, re-close so that it stops
    at target (the energy balance of the module docstring)."""
    m, arm, mu = 0.1, 0.03, 0.5
    patch = exdex.Patch.disc(0.01, center=(arm, 0.0))
    body = exdex.Body.box(m, (0.10, 0.04, 0.03))
    f_close = 3 * m * G * arm / (2 * mu * patch.e_r)     # holds 3x the largest gravity torque
    f_open = 0.1 * f_close
    scene = exdex.Scene(body=body, grasp=exdex.Grasp(mu, f_close, patch=patch), dof="rotation", q0=(-arm, 0, 0))
    st = exdex.Stepper(scene, method=method)
    inertia = body.inertia[2][2] + m * arm**2
    torque = 2 * mu * f_close * patch.e_r
    s, closed, rows = st.state, False, []
    for k in range(int(round(t_end / dt))):
        th, w = s.q[0], s.v[0]
        ahead = th + w * dt   # where the next step starts braking
        if not closed and k >= 100 and 0.5 * inertia * w * w >= torque * (target - ahead) - m * G * arm * (
                math.sin(target) - math.sin(ahead)):
            closed = True
        f = f_close if closed or k < 100 else f_open
        s = st.step(dt, f)
        rows.append((s.t, s.q[0], s.v[0], f, s.stick))
    return np.array(rows)


@pytest.mark.parametrize("method", ["event", "implicit"])
def test_pivot_controller_ends_at_the_target(method):
    rows = pivot_control(method)
    t, th, w, f, stick = rows.T
    target = math.radians(60)
    # within the rotation of about one step at the closing speed (w_max dt = 0.6 deg here)
    w_max = np.max(np.abs(w))
    assert abs(th[-1] - target) <= 1.5 * w_max * 1e-3
    assert stick[-1] and w[-1] == 0.0
    assert np.all(th[: 100] == th[0])          # held while closed at the start
    assert np.all(np.diff(th) >= -1e-12)       # gravity turns it one way only


def test_stepping_is_bit_identical_with_static_friction_and_a_grip_schedule():
    body = exdex.Body.box(0.1, (0.04, 0.06, 0.02))
    motion = exdex.AsymmetricProfile(0.08, 0.25, 0.85, axis=(0, 0, -1))
    static = exdex.Scene(body=body, grasp=exdex.Grasp(0.4, 1.6, mu_static=0.6), motion=motion)
    for method in ("implicit", "event", "regularised", "explicit", "analytic"):
        assert _compare(static, method, 300, 2e-3) == "ok"
    sched = exdex.GripSchedule((0.0, 0.2, 0.35, 0.6), (2.5, 2.5, 0.6, 2.0), kind="cubic")
    scene = exdex.Scene(body=body, grasp=exdex.Grasp(0.5, sched, mu_static=0.7), motion=motion)
    for method in ("implicit", "event", "regularised", "explicit"):
        assert _compare(scene, method, 300, 2e-3) == "ok"
    # a step's own force replaces the schedule; None returns to it
    st = exdex.Stepper(scene, method="event")
    for i in range(300):
        s = st.step(2e-3, 0.0 if 100 <= i < 110 else None)
        assert s.grip_force == (0.0 if 100 <= i < 110 else None)


@pytest.mark.parametrize("method", ["implicit", "event", "explicit"])
def test_friction_never_adds_energy_under_random_grip_forces(method):
    """Property: with the gripper at rest and no gravity, only friction acts
    on a sliding block, whatever grip force each step takes: its speed never
    grows (the explicit method's sign friction may overshoot zero by at most
    one step's deceleration, h 2 mu F / m, so its speed is bounded by that)."""
    rng = np.random.default_rng(5)
    m, mu = 0.1, 0.5
    scene = exdex.Scene(body=exdex.Body(m), grasp=exdex.Grasp(mu, 0.0), v0=(0.0, 0.3, 0.0), gravity=(0, 0, 0))
    st = exdex.Stepper(scene, method=method)
    speed = 0.3
    for _ in range(400):
        s = st.step(1e-3, float(rng.uniform(0.0, 0.2)))
        bound = speed if method != "explicit" else max(speed, 1e-3 * 2 * mu * 0.2 / m)
        assert abs(s.v[0]) <= bound * (1 + 1e-12)
        speed = abs(s.v[0])


# ---------------------------------------------------------------- prescribed gripper poses

def _posed_scene():
    """A 40 mm square on a floor stop, slipping in a gripper that a Shake
    turns about an axis off the plate normal's line (gravity turns in B, the
    frame's rotation and its offset centre load the object)."""
    motion = exdex.Shake(0.5, 2.0, cycles=1, axis=(0, -1, 0), rotation=True, center=(0.01, 0, 0.02))
    scene = exdex.Scene(body=exdex.Body.box(0.1, (0.04, 0.04, 0.02)), grasp=exdex.Grasp(0.3, 0.5), dof="planar",
                        motion=motion, stops=(exdex.Stop((0, 0, -0.03), (0, 0, 1)),))
    return scene, motion


def _stepped_with_poses(scene, motion, method, n, t_end, twist=True, **options):
    """n steps of t_end / n, each given the motion's pose (and twist) at its end,
    on the same scene with the gripper at rest; the final q."""
    dt = t_end / n
    st = exdex.Stepper(exdex.replace(scene, motion=exdex.Rest()), method=method, **options)
    kin = motion.evaluate(np.arange(1, n + 1) * dt, scene.gripper_rotation, scene.gripper_position)
    for i in range(n):
        st.step(dt, gripper=exdex.GripperPose(kin["p"][i], kin["R"][i], kin["v"][i] if twist else None,
                                              kin["w"][i] if twist else None))
    return st.state.q


@pytest.mark.parametrize("method, ns", [("event", (25, 50, 100, 200)), ("implicit", (25, 50, 100)),
                                        ("explicit", (25, 50))])
def test_stepping_with_sampled_poses_reproduces_simulate(method, ns):
    """Stepping with the poses and twists of a known motion at the step ends
    reproduces simulate with that motion, to the interpolation's order.

    Over each step the interpolation matches the motion's pose and twist at
    both ends, with acceleration errors at most dt^2 / 12 max|f''''| (cubic
    Hermite) whose integral over the step vanishes (the velocities agree at
    the ends). The explicit method reads the frame only at the step ends and
    through its mean accelerations (v(t + dt) - v(t)) / dt: the same numbers
    up to the quaternion's rounding (1e-12 L). The implicit method also reads
    the pose at the step's midpoint, off by O(dt^4), and the twist, off by
    O(dt^3); the event method integrates the interpolated accelerations,
    off by O(dt^2) inside each step: each differs from simulate by at least
    second order in dt (halving dt divides the difference by >= 2^1.8), and
    by much less than the slip itself."""
    scene, motion = _posed_scene()
    T, L = 0.5, 0.02
    options = {"rtol": 1e-11, "atol": 1e-13} if method == "event" else {}
    errs = []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for n in ns:
            ref = exdex.simulate(scene, T, T / n, method=method, **options)
            errs.append(float(np.max(np.abs(_stepped_with_poses(scene, motion, method, n, T, **options) - ref.q[-1]))))
            slip = float(np.max(np.abs(ref.q[-1] - ref.q[0])))
    assert slip > 0.1 * L
    if method == "explicit":
        assert max(errs) <= 1e-12 * L, errs
    else:
        assert errs[-1] <= 1e-6 * L, errs
        for a, b in zip(errs, errs[1:]):
            assert a / b >= 2 ** 1.8, errs


def test_stepping_with_poses_without_twist_is_first_order():
    """Without the twist the velocity at each step end is the secant's,
    which lags the motion's by about dt / 2 (a first-order error): the
    difference from simulate halves (at least) with dt, and stays far above
    the run with the twist."""
    scene, motion = _posed_scene()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ref = {n: exdex.simulate(scene, 0.5, 0.5 / n, method="event").q[-1] for n in (50, 100)}
        secant = [float(np.max(np.abs(_stepped_with_poses(scene, motion, "event", n, 0.5, twist=False) - ref[n])))
                  for n in (50, 100)]
        full = float(np.max(np.abs(_stepped_with_poses(scene, motion, "event", 100, 0.5) - ref[100])))
    assert secant[0] / secant[1] >= 2 ** 0.8 and full < 0.1 * secant[1], (secant, full)


def test_gripper_pose_contract_and_errors():
    scene, motion = _posed_scene()
    model = exdex.Model(exdex.replace(scene, motion=exdex.Rest()), method="implicit")
    st = exdex.Stepper(model)
    R0, p0 = np.array(scene.gripper_rotation), np.array(scene.gripper_position)
    # no pose: bit-identical to simulate (the scene's motion); a pose that holds
    # the gripper where it is, at rest, is the same motion
    a = exdex.Stepper(model)
    for _ in range(20):
        st.step(1e-3)
        s = a.step(1e-3, gripper=exdex.GripperPose(p0, R0, np.zeros(3), np.zeros(3)))
    assert np.array_equal(s.q, st.state.q) and np.array_equal(s.v, st.state.v)
    with pytest.raises(ValueError, match="every step after"):
        a.step(1e-3)
    snap = a.save()
    b = exdex.Stepper(model)
    b.restore(snap)
    with pytest.raises(ValueError, match="every step after"):
        b.step(1e-3)
    x = b.step(1e-3, gripper=exdex.GripperPose(p0 + [0, 0, 1e-4], R0))
    y = a.step(1e-3, gripper=exdex.GripperPose(p0 + [0, 0, 1e-4], R0))
    assert np.array_equal(x.q, y.q)
    with pytest.raises(TypeError, match="GripperPose"):
        a.step(1e-3, gripper=(p0, R0))
    with pytest.raises(ValueError, match="GripperPose.rotation must be a rotation"):
        exdex.GripperPose(p0, 1.01 * R0)
    with pytest.raises(ValueError, match="GripperPose.position must have shape"):
        exdex.GripperPose((0.0, 1.0), R0)
    with pytest.raises(ValueError, match="GripperPose.velocity must be finite"):
        exdex.GripperPose(p0, R0, velocity=(np.nan, 0, 0))
    analytic = exdex.Stepper(_branch_scene(), method="analytic")
    with pytest.raises(ValueError, match="analytic method follows the scene's motion"):
        analytic.step(1e-3, gripper=exdex.GripperPose((0, 0, 0)))


def test_save_restore_in_a_stiff_planar_slip():
    """The event method integrates a planar slip lingering at a small speed
    with a linearly implicit stepper (tests/scenarios/test_event.py, the slip at the
    friction incline launched across it): a snapshot taken in that phase
    branches exactly too, on the same stepper and on another one of the same
    model, and a stepper that never saved takes the same steps."""
    m, mu, F, v0 = 0.1, 0.4, 0.5, 2e-6
    scene = exdex.Scene(body=exdex.Body.box(m, (0.04, 0.02, 0.01)),
                        grasp=exdex.Grasp(mu=mu, grip_force=F, patch=exdex.Patch.disc(0.008)),
                        dof="planar", gravity=(2 * mu * F / m, -9.81, 0.0), v0=(0.0, v0, 0.0))
    model = exdex.Model(scene, method="event", rtol=1e-10, atol=1e-13)
    a, b, c = exdex.Stepper(model), model.stepper(), model.stepper()
    for _ in range(10):
        a.step(0.05)
        c.step(0.05)
    snap = a.save()
    first = [a.step(0.05) for _ in range(10)]
    plain = [c.step(0.05) for _ in range(10)]
    assert a.stats["steps"] < 5000  # the implicit stepper took over (rk8pd alone: ~7.7e5 steps to 1 s)
    for stepper in (a, b):
        stepper.restore(snap)
        again = [stepper.step(0.05) for _ in range(10)]
        for x, y, z in zip(first, again, plain):
            assert x.t == y.t == z.t and np.array_equal(x.q, y.q) and np.array_equal(x.v, y.v)
            assert np.array_equal(x.q, z.q) and np.array_equal(x.v, z.v) and x.stick == y.stick


# ---------------------------------------------------------------- exdex.Model

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


@pytest.mark.warns_by_design("impact", "pad", "outline")
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

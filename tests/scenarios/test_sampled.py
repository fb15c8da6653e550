"""Robot logs (SampledTrajectory): end conditions from the data, the user's
end velocities, gripper velocity jumps (every method, warned), replay
relative to the initial gripper pose, and a tool offset.

References are closed forms derived in each docstring, hand compositions of
rigid transforms in NumPy, and error bounds of each method; none is the
output of the code under test.
"""
import math
import warnings

import numpy as np
import pytest

import exdex
from exdex.scene import DEFAULT_GRIPPER_ROTATION, _quat_from_matrix
from exdex.simulate import GripperJumpWarning

METHODS = ("implicit", "event", "regularised", "explicit")
R0 = np.array(DEFAULT_GRIPPER_ROTATION)
Q0 = _quat_from_matrix(R0)
EZ_A = R0[:, 2]  # B's plate normal in A


def qmul(a, b):
    w1, x1, y1, z1 = a
    w2, x2, y2, z2 = b
    return np.array([w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2, w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
                     w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2, w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2])


def qaxis(axis, angle):
    axis = np.asarray(axis, float) / np.linalg.norm(axis)
    return np.concatenate([[math.cos(angle / 2)], math.sin(angle / 2) * axis])


def turn_about_plate_normal(angles):
    """Quaternions of R_AB = R0 Rz(angle): the default gripper turned about its own z."""
    return np.array([qmul(Q0, qaxis((0, 0, 1), a)) for a in angles])


def run(scene, t_end, dt, method, **kw):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", GripperJumpWarning)
        return exdex.simulate(scene, t_end, dt, method=method, **kw)


# ---------------------------------------------------------------- end conditions

@pytest.mark.parametrize("dof, method", [(d, m) for d in ("rotation", "planar") for m in METHODS])
def test_sampled_turn_rest_to_rest_mu0_ends_at_minus_the_turn(dof, method):
    """A log that turns the gripper 0.6 rad about the plate normal, from rest
    to rest (quintic profile 0.6 (10 s^3 - 15 s^4 + 6 s^5), 8 samples over
    1 s), mu = 0, no gravity, the object's centre of mass on the axis: no
    torque acts, so the object keeps its absolute orientation and ends at
    theta = -0.6 rad relative to the gripper. Both ends are at rest by the
    data rule, so the spline starts at rest (the object, starting at relative
    rest, has no absolute spin) and passes through the last sample exactly:
    the final angle is -0.6 whatever the spline does in between. Natural
    spline ends gave the gripper a start velocity the log never had
    (-0.5859 rad).

    Error bounds: event/regularised integrate to rtol 1e-8 (|err| <= 1e-8);
    the implicit (midpoint) scheme integrates theta_dot = -w(t) by the
    trapezoid rule: |err| <= T h^2 / 12 max|w''| with w'' the third
    derivative of the spline's angle, bounded from the spline's own second
    derivative of w (piecewise linear); the explicit (symplectic Euler)
    scheme by the right rectangle rule: |err| <= T h / 2 max|w'|.
    """
    t = np.linspace(0.0, 1.0, 8)
    s = t
    phi = 0.6 * (10 * s**3 - 15 * s**4 + 6 * s**5)
    motion = exdex.SampledTrajectory(t, np.zeros((8, 3)), turn_about_plate_normal(phi))
    scene = exdex.Scene(body=exdex.Body(mass=0.1), grasp=exdex.Grasp(mu=0.0, grip_force=1.0), motion=motion,
                        dof=dof, gravity=(0, 0, 0))
    h = 1e-3
    r = run(scene, 1.2, h, method)
    tt = np.linspace(0, 1, 20001)
    k = motion.evaluate(tt, DEFAULT_GRIPPER_ROTATION)
    wz = k["dw"] @ EZ_A
    max_dw = np.max(np.abs(wz))
    max_ddw = np.max(np.abs(np.diff(wz) / np.diff(tt)))
    tol = {"event": 1e-8, "regularised": 1e-8, "implicit": 1.0 * h**2 / 12 * max_ddw * 1.01 + 1e-12,
           "explicit": 1.0 * h / 2 * max_dw}[method]
    assert abs(r.q[-1, -1] - (-0.6)) <= tol
    if dof == "planar":
        np.testing.assert_allclose(r.q[-1, :2], 0.0, atol=1e-12)


def test_sampled_end_rule_from_data():
    """The end rule, per end and separately for position and orientation:
    held poses and uniformly accelerated starts are at rest (zero end
    velocity exactly), a constant speed is not (its velocity exactly: the
    3-point quadratic is exact for lines and parabolas, and a clamped cubic
    spline with exact end slopes reproduces them)."""
    t = np.linspace(0.0, 0.5, 11)
    q = np.tile(Q0, (11, 1))
    held = np.zeros((11, 3))
    held[3:, 0] = 0.01 * (t[3:] - t[3])**2        # still for 3 samples, then accelerates
    acc = np.zeros((11, 3))
    acc[:, 2] = 0.5 * 2.0 * t**2                   # x = a t^2 / 2, a = 2
    cruise = np.zeros((11, 3))
    cruise[:, 1] = 0.3 * t                         # constant speed 0.3
    for pos, v_start, v_end in ((held, 0.0, 2 * 0.01 * (t[-1] - t[3])), (acc, 0.0, 2.0 * t[-1]),
                                (cruise, 0.3, 0.3)):
        m = exdex.SampledTrajectory(t, pos, q)
        k = m.evaluate([t[0]])
        assert np.linalg.norm(k["v"][0]) == pytest.approx(v_start, abs=1e-14)
        if v_start == 0.0:
            assert np.all(k["v"][0] == 0.0)
        jumps = m.velocity_jumps()
        assert jumps[-1][0] == t[-1]
        assert np.linalg.norm(jumps[-1][1]) == pytest.approx(v_end, rel=1e-12)
        assert np.all(jumps[-1][2] == 0.0)
    # the parabola comes back exactly inside
    m = exdex.SampledTrajectory(t, acc, q)
    ti = np.linspace(0.0, 0.49, 37)
    k = m.evaluate(ti)
    np.testing.assert_allclose(k["p"][:, 2], ti**2, atol=1e-15)
    np.testing.assert_allclose(k["v"][:, 2], 2 * ti, atol=1e-13)


def test_sampled_end_rule_threshold_and_scale_invariance():
    """x = v0 t + a t^2 / 2 sampled at steps h: the quadratic through the
    first three samples is x itself, with start velocity v0 and first
    displacement D1 = v0 h + a h^2 / 2, so the rule v0 D1 <= D1^2 / (2 h)
    reads v0 <= a h / 2: at rest below, v0 above. Random logs scaled by
    lengths L and times T give the same decisions and velocities scaled by
    L / T (the rule compares two velocities of the same data)."""
    h, a = 0.05, 3.0
    t = h * np.arange(8)
    for frac, rest in ((0.45, True), (0.55, False)):
        v0 = frac * a * h
        pos = np.zeros((8, 3))
        pos[:, 0] = v0 * t + 0.5 * a * t**2
        m = exdex.SampledTrajectory(t, pos, np.tile(Q0, (8, 1)))
        v = m.evaluate([0.0])["v"][0, 0]
        assert (v == 0.0) if rest else v == pytest.approx(v0, rel=1e-12)
    rng = np.random.default_rng(11)
    for _ in range(40):
        n = int(rng.integers(4, 12))
        tt = np.cumsum(rng.uniform(0.5, 1.5, n))
        pos = np.cumsum(rng.normal(size=(n, 3)) * rng.uniform(0, 1, (n, 1)), axis=0)
        if rng.uniform() < 0.5:
            pos[1] = pos[0]                                    # a held start
        ang = np.cumsum(rng.normal(size=n) * 0.2)
        quat = np.array([qaxis(rng.normal(size=3) * 0 + (0.3, 0.4, 0.5), x) for x in ang])
        base = exdex.SampledTrajectory(tt, pos, quat)
        L, T = 10.0 ** rng.uniform(-3, 2), 10.0 ** rng.uniform(-2, 2)
        scaled = exdex.SampledTrajectory(tt * T, pos * L, quat)
        for end in (0, -1):
            kb = base.evaluate([tt[end] if end == 0 else np.nextafter(tt[-1], -np.inf)])
            ks = scaled.evaluate([tt[end] * T if end == 0 else np.nextafter(tt[-1] * T, -np.inf)])
            assert (np.all(kb["v"] == 0.0)) == (np.all(ks["v"] == 0.0))
            assert (np.all(kb["w"] == 0.0)) == (np.all(ks["w"] == 0.0))
            np.testing.assert_allclose(ks["v"], kb["v"] * L / T, rtol=1e-9, atol=1e-12 * L / T)
            np.testing.assert_allclose(ks["w"], kb["w"] / T, rtol=1e-9, atol=1e-12 / T)


def test_sampled_given_end_velocities():
    """start_velocity / start_omega / end_velocity / end_omega are the
    spline's end slopes: the velocity at the first sample, and minus the
    jump at the last (right limit rest minus the left limit)."""
    t = np.linspace(0, 1, 6)
    pos = np.column_stack([np.sin(t), t**2, 0.1 * t])
    quat = np.array([qaxis((0, 0.6, 0.8), 0.5 * x) for x in t])
    vs, ws, ve, we = (0.1, 0.2, -0.3), (0.0, 1.0, 0.5), (0.0, 0.0, 0.4), (-2.0, 0.0, 0.0)
    m = exdex.SampledTrajectory(t, pos, quat, start_velocity=vs, start_omega=ws, end_velocity=ve, end_omega=we)
    k = m.evaluate([0.0])
    np.testing.assert_allclose(k["v"][0], vs, atol=1e-15)
    np.testing.assert_allclose(k["w"][0], ws, atol=1e-15)
    (t0, dv0, dw0), (t1, dv1, dw1) = m.velocity_jumps()
    assert (t0, t1) == (0.0, 1.0)
    np.testing.assert_allclose(dv1, -np.array(ve), atol=1e-15)
    np.testing.assert_allclose(dw1, -np.array(we), atol=1e-14)
    # only the linear part given: the angular one is zero
    m = exdex.SampledTrajectory(t, pos, quat, end_velocity=(0, 0, 0))
    assert m.velocity_jumps()[-1][0] == 0.0  # only the start jumps
    assert len(m.velocity_jumps()) == 1


# ---------------------------------------------------------------- velocity jumps

def cruise_log(v_a, t_first, t_last, n=21, omega=0.0, given=True):
    """B translating at v_a (world) and turning about its own z at omega,
    sampled from t_first to t_last, with the exact end velocities given
    (given=False: from the data, exact for the linear positions)."""
    t = np.linspace(t_first, t_last, n)
    pos = np.outer(t - t_first, v_a)
    quat = turn_about_plate_normal(omega * (t - t_first))
    if not given:
        return exdex.SampledTrajectory(t, pos, quat)
    w = tuple(omega * EZ_A)
    return exdex.SampledTrajectory(t, pos, quat, start_velocity=tuple(v_a), start_omega=w,
                                   end_velocity=tuple(v_a), end_omega=w)


@pytest.mark.parametrize("method", METHODS)
def test_log_ending_at_speed_mu0_translation_relative_velocity_jumps(method):
    """mu = 0, translation along B x (= A x), the log cruising at v from
    t_first = 0.1 s to t_last = 0.3 s (rest before and after: jumps +v and
    -v). The object keeps its absolute velocity through each jump: relative
    velocity -v from t_first, 0 again from t_last... no: it stays at absolute
    rest the whole time, so its relative position ends at -v (t_last -
    t_first) and its relative velocity is -v between the jumps and 0 after.
    The same log without the jump at the start (from t = 0, the object
    moving with the gripper) ends at speed: relative velocity +v from t_last.
    The midpoint and Euler schemes place each jump inside one step, but the
    two half-step errors cancel in the total displacement (exact here)."""
    v = 0.29
    base = dict(body=exdex.Body(mass=0.1), grasp=exdex.Grasp(mu=0.0, grip_force=1.0), slide_axis=(1, 0),
                gravity=(0, 0, 0))
    sc = exdex.Scene(motion=cruise_log((v, 0, 0), 0.1, 0.3), **base)
    r = run(sc, 0.4, 1e-3, method)
    mid = (r.t > 0.1 + 1e-9) & (r.t < 0.3 - 1e-9)
    np.testing.assert_allclose(r.v[mid, 0], -v, rtol=1e-12)
    assert r.v[-1, 0] == pytest.approx(0.0, abs=1e-12)
    assert r.q[-1, 0] == pytest.approx(-v * 0.2, rel=1e-10)
    sc = exdex.Scene(motion=cruise_log((v, 0, 0), 0.0, 0.3), **base)
    r = run(sc, 0.4, 1e-3, method)
    assert r.v[r.t < 0.3 - 1e-9, 0] == pytest.approx(0.0, abs=1e-12)
    np.testing.assert_allclose(r.v[r.t >= 0.3 - 1e-12, 0], v, rtol=1e-12)


def slip_after_jump(method, h, v=0.29, mu=0.5, grip=1.0, m=0.1):
    sc = exdex.Scene(body=exdex.Body(mass=m), grasp=exdex.Grasp(mu=mu, grip_force=grip), slide_axis=(1, 0),
                     motion=cruise_log((v, 0, 0), 0.0, 0.2, given=False))
    r = run(sc, 0.4, h, method)
    i0 = int(np.argmin(np.abs(r.t - (0.2 - h))))
    return r.q[-1, 0] - r.q[i0, 0], r


@pytest.mark.parametrize("method", METHODS)
def test_log_ending_at_speed_slip_distance_closed_form(method):
    """The log ends at speed v = 0.29 m/s; the slide axis is horizontal, so
    only friction acts along it, a_f = C / m = mu 2 F_g / m = 10 m/s^2. The
    jump gives the object relative velocity +v, friction stops it after
    v / a_f = 29 ms having slipped v^2 / (2 a_f) = 4.205 mm (before any fix
    the event method slipped 0 mm). Measured from one step before the jump.

    Error bounds. event: rtol 1e-8. regularised: the smoothed friction
    C u / sqrt(u^2 + eps^2) stops it over int_0^v sqrt(u^2 + eps^2) du / a_f
    <= v^2 / (2 a_f) + eps v / a_f. The time-stepping methods apply the jump
    at its time (a sub-step ends there), friction acts from then on.
    implicit (midpoint): at relative rest before the jump, the trapezoid
    rule is exact for the linear deceleration after it, and the step in
    which it stops places the stop where the slip ends under the step's
    constant force, t* = u / a_f from the step's slip speed u, with the
    displacement u t* / 2 = u^2 / (2 a_f): exact to rounding (1e-12
    relative; a stop at the step's end would move h u / 2, an error up to
    h^2 a_f / 2 = 5e-8 m). explicit (symplectic Euler): before the
    jump it chatters about relative rest with a velocity in (-h a_f, h a_f],
    so the slide starts from v to within h a_f, a distance error up to
    v h a_f / a_f = h v; the deceleration's right-rectangle sum undershoots
    by at most h v / 2 (+ h^2 a_f for the last step), and after it stops it
    chatters with a mean speed below h a_f / 2:
    |err| <= 3 h v / 2 + h^2 a_f + (h a_f / 2)(t_end - t_stop).
    """
    v, a_f, h = 0.29, 10.0, 1e-4
    d, r = slip_after_jump(method, h if method in ("implicit", "explicit") else 1e-3)
    exact = v**2 / (2 * a_f)
    t_stop = 0.2 + v / a_f
    tol = {"event": 1e-8 * exact + 1e-12, "regularised": 1e-4 * v / a_f,
           "implicit": 1e-12 * exact,
           "explicit": 1.5 * h * v + h**2 * a_f + h * a_f / 2 * (0.4 - t_stop)}[method]
    assert abs(d - exact) <= tol, (d, exact, tol)


def test_every_method_same_jump_answer_converges():
    """The time-stepping methods converge to the closed form on a ladder of
    steps, some landing on the jump time (0.2 s), others placing it inside a
    step (the step is split there), within the bounds derived in the test
    above: the implicit error to rounding at every step (1e-12 relative: the
    slide's stop is located inside its step), the explicit one within its
    first-order bound, and over the ladder (h / 5.7 from the first to the
    last) the explicit errors shrink: the finest two at most half the
    coarsest two (its error's constant varies with the chatter's phase)."""
    v, a_f = 0.29, 10.0
    exact = v**2 / (2 * a_f)
    t_stop = 0.2 + v / a_f
    hs = (4e-4, 3e-4, 2e-4, 1.5e-4, 1e-4, 7e-5)
    bound = {"implicit": lambda h: 1e-12 * exact,
             "explicit": lambda h: 1.5 * h * v + h**2 * a_f + h * a_f / 2 * (0.4 - t_stop)}
    for method in ("implicit", "explicit"):
        errs = [abs(slip_after_jump(method, h)[0] - exact) for h in hs]
        for h, e in zip(hs, errs):
            assert e <= bound[method](h), (method, h, e)
        if method == "explicit":
            assert max(errs[-2:]) <= max(errs[:2]) / 2, (method, errs)


def test_stop_from_speed_along_gravity_slide_closed_form():
    """The gripper carries the object down at V = 4 mm/s along the slide
    axis (B y = A z, gravity along it) and stops instantly at t_last =
    0.3001 s (a log ending at speed: the gripper's downward velocity jumps
    from V to 0, so the object's velocity relative to the plates jumps to V
    downwards). Before it the object is held (friction capacity C = 2 m g
    >= m g). The plates carry no
    impulse, so after the stop it slides down at V relative to the plates,
    decelerated by friction minus gravity, a = (C - m g) / m (= g here),
    and stops after V / a having slid
        d = V^2 / (2 a) = m V^2 / (2 (C - m g)) = 0.815 um (downwards).
    The step ladder h = 4, 2, 1, 0.5 ms is nested (t_end / 500 .. / 4000
    style) and puts the stop 0.1 ms after a grid point common to every
    level, inside a step; h a >= V, so the friction impulse of one step,
    h C, exceeds m V + h m g: a step that took the jump as a step-mean
    acceleration would hold the object (no slide at any h of the ladder,
    successive differences 0).

    implicit: exactly at rest before the stop; after it the trapezoid rule
    is exact for the constant deceleration, and the (sub-)step of length
    h_k <= h in which it sticks starts at a slip speed u <= min(V, h_k a)
    and places the stop where the slide ends under the step's constant
    force, t* = u / a, moving u t* / 2 = u^2 / (2 a): the distance is exact
    to rounding (1e-12 relative) at every level. (Stopping at the
    (sub-)step's end it would move h_k u / 2, an error up to h min(V, h a) /
    2, first order in h while h a >= V, and the same at every level whose
    grid puts the stop in the sub-step after the jump: successive
    differences 0.)

    explicit (symplectic Euler): before the stop it chatters about rest with
    |v| <= h (C / m + g) (csrc/explicit.c), so the slide starts from V to
    within that: a distance error up to V h (C / m + g) / a + (h (C / m +
    g))^2 / (2 a); the right-rectangle sum of the deceleration errs by at
    most h V / 2 + h^2 a; after the stop it chatters with |v| <= h (C / m +
    g) until t_end. First order; over the ladder the finest two errors are
    at most half the coarsest two."""
    m, mu, g, V, t_last, t_end = 0.1, 0.5, 9.81, 0.004, 0.3001, 0.31
    C = 2 * m * g
    a = (C - m * g) / m
    exact = -m * V**2 / (2 * (C - m * g))
    sc = exdex.Scene(body=exdex.Body(mass=m), grasp=exdex.Grasp(mu=mu, grip_force=C / (2 * mu)), slide_axis=(0, 1),
                     motion=cruise_log((0, 0, -V), 0.0, t_last))
    hs = (4e-3, 2e-3, 1e-3, 5e-4)
    assert min(hs) * a >= V
    t_stop = t_last + V / a
    ca = C / m + g
    bound = {"implicit": lambda h: 1e-12 * abs(exact),
             "explicit": lambda h: (V * h * ca / a + (h * ca)**2 / (2 * a) + h * V / 2 + h**2 * a
                                    + h * ca * (t_end - t_stop))}
    for method in ("implicit", "explicit"):
        d = []
        for h in hs:
            r = run(sc, t_end, h, method)
            i0 = np.searchsorted(r.t, t_last) - 1   # the grid point before the stop
            d.append(r.q[-1, 0] - r.q[i0, 0])
        errs = [abs(x - exact) for x in d]
        for h, e in zip(hs, errs):
            assert e <= bound[method](h), (method, h, e, d)
        if method == "explicit":
            assert np.all(np.abs(np.diff(d)) > 0.0), (method, d)
            assert max(errs[-2:]) <= max(errs[:2]) / 2, errs


@pytest.mark.parametrize("method", METHODS)
def test_rotation_dof_jump_closed_form(method):
    """Rotation DoF, mu = 0, no gravity. The gripper turns at omega = 2 rad/s
    about its plate normal through its origin; the object's centre of mass
    sits at (0.04, 0) in B and the pivot (centre of pressure) at (0.03, 0):
    axis, pivot and centre of mass on one line, so co-rotation is a
    solution with the pin force along that line (relative rest) until the
    log ends at speed at 0.2 s. There the pin stops with the gripper; the
    impulse acts at the pivot, so the angular momentum about it is kept:
        I w + m (rho x v_c) = I W + m |rho|^2 W,
    rho = (0.01, 0), v_c = w e_z x (0.04, 0) = (0, 0.04 w):
        W = w (I + 4e-4 m) / (I + 1e-4 m),
    and with the gripper at rest and no friction the object turns on at W
    relative to it."""
    w, m, I = 2.0, 0.1, 2e-5
    body = exdex.Body(mass=m, inertia=I)
    grasp = exdex.Grasp(mu=0.0, grip_force=1.0, patch=exdex.Patch(e_r=0.01, center=(-0.01, 0.0)))
    sc = exdex.Scene(body=body, grasp=grasp, motion=cruise_log((0, 0, 0), 0.0, 0.2, omega=w), dof="rotation",
                     q0=(0.04, 0.0, 0.0), gravity=(0, 0, 0))
    r = run(sc, 0.3, 1e-3, method)
    W = w * (I + 4e-4 * m) / (I + 1e-4 * m)
    np.testing.assert_allclose(r.v[r.t < 0.2 - 1e-9, 0], 0.0, atol=1e-9)
    assert r.v[-1, 0] == pytest.approx(W, rel=1e-9)


@pytest.mark.parametrize("method", METHODS)
def test_planar_jump_closed_form(method):
    """Planar, mu = 0, no gravity: the gripper translates at v_A and turns
    about its own plate normal through the object's centre of mass at
    omega; the free object co-moves (no force needed) until the log ends at
    speed. Through the jump it keeps its absolute velocity and spin: after
    it, relative to the resting gripper, (xd, yd) = (R_AB^T v_A)_xy at the
    end pose and thetad = omega, constant from then on. The event and
    regularised methods apply the jump at its time (to rounding); the
    step methods apply it through the step's mean frame acceleration,
    expressed in the gripper frame at a time within the step, so the jump's
    direction is off by at most the angle omega h the gripper turns in one
    step: |err| <= omega h |v_A|."""
    v_a, w = np.array([0.1, 0.0, 0.05]), 1.5
    sc = exdex.Scene(body=exdex.Body(mass=0.1, inertia=1e-4), grasp=exdex.Grasp(mu=0.0, grip_force=1.0),
                     motion=cruise_log(v_a, 0.0, 0.2, omega=w), dof="planar", gravity=(0, 0, 0))
    r = run(sc, 0.3, 1e-3, method)
    c, s = math.cos(w * 0.2), math.sin(w * 0.2)
    R_end = R0 @ np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])
    rel = R_end.T @ v_a
    np.testing.assert_allclose(r.v[r.t < 0.2 - 1e-9], 0.0, atol=1e-9)
    h = 1e-3
    atol = 1e-12 if method in ("event", "regularised") else w * h * np.linalg.norm(v_a)
    np.testing.assert_allclose(r.v[-1, :2], rel[:2], atol=atol)
    assert r.v[-1, 2] == pytest.approx(w, rel=1e-9)


# ---------------------------------------------------------------- warnings

def test_jump_warns_with_time_and_size():
    sc = exdex.Scene(body=exdex.Body(mass=0.1), grasp=exdex.Grasp(mu=0.5, grip_force=1.0), slide_axis=(1, 0),
                     motion=cruise_log((0.29, 0, 0), 0.0, 0.2))
    with pytest.warns(GripperJumpWarning, match=r"t = 0\.2 s by \|dv\| = 0\.29 m/s") as rec:
        exdex.simulate(sc, 0.4, 1e-3)
    w = rec[0].message
    assert isinstance(w, UserWarning)
    assert w.t == 0.2
    np.testing.assert_allclose(w.dv, (-0.29, 0, 0), atol=1e-15)
    with pytest.warns(GripperJumpWarning):
        exdex.Model(sc, method="event").simulate(0.4, 1e-3)
    # not reached in the run: no warning
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        exdex.simulate(sc, 0.1, 1e-3)


def test_log_at_rest_does_not_warn():
    t = np.linspace(0, 1, 8)
    phi = 0.6 * (10 * t**3 - 15 * t**4 + 6 * t**5)
    sc = exdex.Scene(body=exdex.Body(mass=0.1), grasp=exdex.Grasp(mu=0.5, grip_force=1.0),
                     motion=exdex.SampledTrajectory(t, np.zeros((8, 3)), turn_about_plate_normal(phi)))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        exdex.simulate(sc, 1.5, 1e-3)
        exdex.simulate(sc, 1.5, 1e-3, method="event")


# ---------------------------------------------------------------- relative and tool

def hom(R, p):
    T = np.eye(4)
    T[:3, :3] = R
    T[:3, 3] = p
    return T


def quat_R(q):
    w, x, y, z = np.asarray(q) / np.linalg.norm(q)
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def test_relative_and_tool_against_hand_composition():
    """B(t) = G0 (L(t0) X)^-1 L(t) X with relative=True and a tool X
    (flange -> B), composed here with 4x4 matrices at the sample times (the
    spline passes through the samples); B(t0) = G0. Velocities: w_B = R_P
    w_L and v_B = R_P (v_L + w_L x R_L p_X), from the same log evaluated
    without options; and against central differences of the pose."""
    rng = np.random.default_rng(5)
    n = 7
    t = np.linspace(0, 0.6, n)
    pos = np.cumsum(rng.normal(scale=0.05, size=(n, 3)), axis=0)
    quat = np.array([qaxis((0.2, -0.5, 0.8), 0.9 * x + 0.1) for x in t])
    X = hom(quat_R(qaxis((1, 1, 0), 0.7)), (0.0, 0.01, 0.12))
    G0 = hom(quat_R(qaxis((0, 0, 1), -0.4)) @ R0, (0.5, 0.2, 1.0))
    log = exdex.SampledTrajectory(t, pos, quat)
    m = exdex.SampledTrajectory(t, pos, quat, relative=True, tool=X)
    L = [hom(quat_R(q), p) for p, q in zip(pos, quat)]
    P = G0 @ np.linalg.inv(L[0] @ X)
    k = m.evaluate(t, gripper_rotation=G0[:3, :3], gripper_position=G0[:3, 3])
    for i in range(n - 1):   # the last sample time is already the held end pose (same pose)
        B = P @ L[i] @ X
        np.testing.assert_allclose(k["R"][i], B[:3, :3], atol=1e-14)
        np.testing.assert_allclose(k["p"][i], B[:3, 3], atol=1e-14)
    np.testing.assert_allclose(k["R"][0], G0[:3, :3], atol=1e-15)
    np.testing.assert_allclose(k["p"][0], G0[:3, 3], atol=1e-15)
    ti = np.array([0.05, 0.23, 0.41])
    kb = m.evaluate(ti, gripper_rotation=G0[:3, :3], gripper_position=G0[:3, 3])
    kl = log.evaluate(ti)
    RP = P[:3, :3]
    for i in range(len(ti)):
        r = kl["R"][i] @ X[:3, 3]
        np.testing.assert_allclose(kb["w"][i], RP @ kl["w"][i], atol=1e-13)
        np.testing.assert_allclose(kb["v"][i], RP @ (kl["v"][i] + np.cross(kl["w"][i], r)), atol=1e-13)
    hh = 1e-6
    kp = m.evaluate(ti + hh, gripper_rotation=G0[:3, :3], gripper_position=G0[:3, 3])
    km = m.evaluate(ti - hh, gripper_rotation=G0[:3, :3], gripper_position=G0[:3, 3])
    np.testing.assert_allclose(kb["v"], (kp["p"] - km["p"]) / (2 * hh), atol=1e-7)
    # absolute (default): the scene's gripper pose is ignored, B = L X
    k = exdex.SampledTrajectory(t, pos, quat, tool=X).evaluate(t[:1], gripper_position=(9, 9, 9))
    np.testing.assert_allclose(k["p"][0], (L[0] @ X)[:3, 3], atol=1e-15)


def test_relative_log_simulates_like_the_absolute_one_in_the_gripper_frame():
    """A log replayed from another initial pose with gravity rotated with
    it is the same physical scene seen from a rotated, shifted world: the
    relative trajectory must be the same (to rounding)."""
    t = np.linspace(0, 0.5, 11)
    pos = np.column_stack([0.1 * t**2, np.zeros(11), -0.3 * t**2])
    quat = turn_about_plate_normal(0.5 * t**2)
    G = quat_R(qaxis((0.3, 0.2, 0.9), 1.1))
    base = dict(body=exdex.Body(mass=0.1), grasp=exdex.Grasp(mu=0.3, grip_force=0.5), dof="planar")
    a = exdex.Scene(motion=exdex.SampledTrajectory(t, pos, quat), **base)
    b = exdex.Scene(motion=exdex.SampledTrajectory(t, pos, quat, relative=True),
                    gripper_rotation=G @ R0, gripper_position=(1.0, -2.0, 0.5), gravity=tuple(G @ (0, 0, -9.81)),
                    **base)
    ra, rb = run(a, 0.6, 1e-3, "implicit"), run(b, 0.6, 1e-3, "implicit")
    np.testing.assert_allclose(rb.q, ra.q, atol=1e-12)


# ---------------------------------------------------------------- validation

@pytest.mark.parametrize("kw, exc, name", [
    (dict(start_velocity=(0, 1)), ValueError, "SampledTrajectory.start_velocity"),
    (dict(end_omega=(0, float("nan"), 0)), ValueError, "SampledTrajectory.end_omega"),
    (dict(end_velocity="abc"), TypeError, "SampledTrajectory.end_velocity"),
    (dict(relative=1), TypeError, "SampledTrajectory.relative"),
    (dict(tool=np.eye(3)), ValueError, "SampledTrajectory.tool"),
    (dict(tool=np.diag([1.0, 1.0, -1.0, 1.0])), ValueError, "SampledTrajectory.tool"),
    (dict(tool=np.vstack([np.eye(4)[:3], [1.0, 0.0, 0.0, 1.0]])), ValueError, "SampledTrajectory.tool"),
])
def test_sampled_option_errors_name_the_parameter(kw, exc, name):
    t = np.linspace(0, 1, 5)
    with pytest.raises(exc, match=name.replace(".", r"\.").replace("[", r"\[")):
        exdex.SampledTrajectory(t, np.zeros((5, 3)), np.tile(Q0, (5, 1)), **kw)


def test_batch_warns_for_a_log_ending_at_speed():
    sc = exdex.Scene(body=exdex.Body(mass=0.1), grasp=exdex.Grasp(mu=0.5, grip_force=1.0), slide_axis=(1, 0),
                     motion=cruise_log((0.29, 0, 0), 0.0, 0.2))
    with pytest.warns(GripperJumpWarning, match=r"t = 0\.2 s"):
        exdex.simulate_batch(sc, 0.4, 1e-3, mu=[0.3, 0.5])


# ---------------------------------------------------------------- a planar slip stopping inside a step

def planar_slide_reference(sc, R, q0, v0):
    """The slide of a planar object from (q0, v0) to rest in a gripper at
    rest with orientation R, integrated by scipy (DOP853, rtol 1e-12):
        M vdot = F + Rz(th) J'^T w,   w = -C E^2 u / |E u|,   u = J' Rz(-th) v,
    v = (xd, yd, thd) in B, M = diag(m, m, I_zz), F = m (g_B,x, g_B,y, 0)
    (g_B = R^T g), J' = [[1, 0, -c_y], [0, 1, c_x], [0, 0, 1]] (c the patch
    centre: u is the slip at the centre of pressure in the object frame),
    E = diag(1, 1, e_r), C = mu fingers grip_force: the maximum-dissipation
    wrench on the friction ellipsoid opposing the slip (paper Eq. 6). The
    slip stops in finite time (|E u| falls at a rate >= (C - |b|) / ...
    with b the load inside the ellipsoid); integrated until |E u| <= 1e-9
    |E u0|, where the rest of the slide is ~1e-18 of it. Returns the final
    pose and the stop time."""
    solve_ivp = pytest.importorskip("scipy.integrate").solve_ivp
    m, izz = sc.body.mass, float(np.array(sc.body.inertia)[2, 2])
    cx, cy = sc.grasp.patch.center
    E = np.array([1.0, 1.0, sc.grasp.patch.e_r])
    C = sc.grasp.capacity
    gB = np.asarray(R).T @ np.asarray(sc.gravity)
    F = np.array([m * gB[0], m * gB[1], 0.0])
    Minv = np.array([1 / m, 1 / m, 1 / izz])
    Jp = np.array([[1.0, 0.0, -cy], [0.0, 1.0, cx], [0.0, 0.0, 1.0]])

    def rz(th):
        c, s = math.cos(th), math.sin(th)
        return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])

    def slip(y):
        return E * (Jp @ (rz(-y[2]) @ y[3:]))

    def rhs(t, y):
        z = slip(y)
        w = -C * E * z / np.linalg.norm(z)
        return np.concatenate([y[3:], Minv * (F + rz(y[2]) @ (Jp.T @ w))])

    z0 = np.linalg.norm(slip(np.concatenate([q0, v0])))

    def stopped(t, y):
        return np.linalg.norm(slip(y)) - 1e-9 * z0
    stopped.terminal = True
    sol = solve_ivp(rhs, (0.0, 1.0), np.concatenate([q0, v0]), method="DOP853", rtol=1e-12, atol=1e-30,
                    events=stopped)
    assert sol.status == 1
    return sol.y[:3, -1], sol.t[-1]


@pytest.mark.parametrize("case", ["initial-slip", "log-ends-at-speed"])
def test_planar_slip_stopping_inside_a_step_against_scipy(case):
    """A planar slip that stops inside one implicit step, with the patch
    centre off the centre of mass, a small e_r and a load in the plate
    plane (gravity tilted): the friction's direction turns as the slip
    decays (towards the slowest direction of E J' M^-1 J'^T E, here
    mostly a spin), so the object turns although the slip starts without
    spin. initial-slip: the gripper at rest, the object starting at v0;
    log-ends-at-speed: a log cruising at v_a ends at speed at t_last (a
    grid point), the object held until then (constant velocity: the load is
    gravity alone, inside the static ellipsoid); the plates carry no
    impulse, so after it the object's velocity relative to the resting
    gripper is (R0^T v_a)_xy, thetad = 0 (test_planar_jump_closed_form).
    Reference: the sliding law integrated by scipy
    (planar_slide_reference). The implicit step holds the applied force and
    the orientation at the step's midpoint, theta + h thetad / 2 = theta
    here, over the slide (the gripper at rest: F is constant in B): off the
    turning orientation by at most |dtheta| of the slide (< 1e-7 rad,
    checked), which turns the load and the initial slip against the
    object's axes by that angle: a relative change of the slide of order
    1e-7 times its sensitivity to the angle. Bound: 1e-5 of each component
    of the slide. (A slide integrated in 16 fixed pieces of its
    straight-line stop time, the last one straight, ended 83 % off in theta
    in the log case; in the other it was not applied, and the step's own
    end state, q + h v0 / 2, is 200 times the slide.)"""
    m, izz = 0.0136, 1.88e-6
    grasp = exdex.Grasp(mu=0.5, grip_force=0.76, patch=exdex.Patch(e_r=0.0015, center=(-0.0015, 0.005)))
    g = (1.2, -1.7, -9.5)
    body = exdex.Body(mass=m, inertia=izz)
    h = 1e-3
    if case == "initial-slip":
        q0, v0 = np.array([0.001, -0.002, 0.3]), np.array([-1.5e-4, -0.65e-4, 0.0])
        sc = exdex.Scene(body=body, grasp=grasp, motion=exdex.Rest(), dof="planar", q0=tuple(q0), v0=tuple(v0),
                         gravity=g)
        t0 = 0.0
    else:
        v_a, t0 = np.array([2e-4, 1e-4, -3e-4]), 0.2
        q0 = np.zeros(3)
        sc = exdex.Scene(body=body, grasp=grasp, motion=cruise_log(v_a, 0.0, t0), dof="planar", gravity=g)
        v0 = np.concatenate([(R0.T @ v_a)[:2], [0.0]])
    q_ref, t_stop = planar_slide_reference(sc, R0, q0, v0)
    assert t_stop < 0.1 * h   # the slip stops inside the step after t0
    d_ref = q_ref - q0
    assert 1e-10 < abs(d_ref[2]) < 1e-7
    r = run(sc, t0 + 3 * h, h, "implicit")
    assert np.all(r.stick[r.t > t0 + h / 2])
    np.testing.assert_allclose(r.pose[-1] - q0, d_ref, rtol=1e-5, atol=0)


def test_planar_slip_after_a_jump_between_grid_points_against_scipy():
    """The log of test_planar_slip_stopping_inside_a_step_against_scipy
    (log-ends-at-speed) 40 times as fast, ending at t_last = 0.2 s - 0.25 ms,
    on the nested ladder h = 4, 2, 1 ms: on every level the sub-step after
    the jump is (t_last, 0.2 s], 0.25 ms long, and the slip (stop time
    0.25 .. 1.25 ms, checked) slides through it and stops inside the next
    step. Reference: scipy (planar_slide_reference). The sub-step after the
    jump takes the slip's law over it (its length is the same on every
    level, so an error of the scheme there, the friction's turn over the
    sub-step, would be the same on every level and the ladder's differences
    would not show it); the next step takes the stop inside it
    (slip_stop_in_step_planar) at the orientation of its midpoint, theta +
    h thetad / 2 with the spin thetad the slip has at 0.2 s: first order in
    h. Bounds: the error at h = 4 ms within 1e-3 of the slide, and halving
    h twice at least halves it (first order: a quarter). (Taking the
    sub-step after the jump as a step of the scheme left theta 32 % off at
    every level.)"""
    m, izz = 0.0136, 1.88e-6
    grasp = exdex.Grasp(mu=0.5, grip_force=0.76, patch=exdex.Patch(e_r=0.0015, center=(-0.0015, 0.005)))
    body = exdex.Body(mass=m, inertia=izz)
    v_a, t0 = 40.0 * np.array([2e-4, 1e-4, -3e-4]), 0.2 - 2.5e-4
    sc = exdex.Scene(body=body, grasp=grasp, motion=cruise_log(v_a, 0.0, t0), dof="planar", gravity=(1.2, -1.7, -9.5))
    q0, v0 = np.zeros(3), np.concatenate([(R0.T @ v_a)[:2], [0.0]])
    q_ref, t_stop = planar_slide_reference(sc, R0, q0, v0)
    assert 2.5e-4 < t_stop < 1.25e-3
    d_ref = q_ref - q0
    errs = []
    for h in (4e-3, 2e-3, 1e-3):
        r = run(sc, 0.2 + 3 * h, h, "implicit")
        assert r.stick[-1]
        errs.append(np.max(np.abs(r.pose[-1] - q0 - d_ref) / np.abs(d_ref)))
    assert errs[0] <= 1e-3, errs
    assert errs[2] <= 0.5 * errs[0], errs

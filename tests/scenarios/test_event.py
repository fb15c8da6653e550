"""The event method on plain planar and 1-DoF scenes: it returns, locates
stick-to-slip at the exact crossing of the friction limit, and agrees with
closed forms and with the implicit method extrapolated in dt.

Reference values: closed forms (derived in each docstring) or the implicit
method at dt and dt/2, Richardson-extrapolated (first order in dt at the
stick/slip switches), whose difference is its error estimate.
"""
import math

import numpy as np
import pytest

import exdex
from exdex import (AsymmetricProfile, Body, Grasp, Patch, Rest, SampledTrajectory, Scene, Stop,
                   TrapezoidalProfile)

G = 9.81


def implicit_extrapolated(scene, t_end, dt):
    """Final q of the implicit method extrapolated to dt -> 0 from dt and dt/2
    (first order), and its error estimate |q(dt/2) - q(dt)|."""
    a = exdex.simulate(scene, t_end=t_end, dt=dt, method="implicit").q[-1]
    b = exdex.simulate(scene, t_end=t_end, dt=dt / 2, method="implicit").q[-1]
    return 2 * b - a, np.abs(b - a)


def grip_scene(grip):
    return Scene(body=Body.box(0.1, (0.06, 0.03, 0.02)),
                 grasp=Grasp(mu=0.5, grip_force=grip, patch=Patch.rectangle(0.02, 0.02, center=(0.015, 0))),
                 dof="planar")


def test_planar_grip_sweep_returns_and_agrees_with_implicit():
    """Gripper at rest, a 100 g box held by an off-centre patch: near the
    holding grip the load sits just outside the ellipsoid and the object
    starts to slip from rest (slowly, the slip direction set by the
    maximum-dissipation solve). Every grip of the sweep returns, and the final
    pose agrees with the implicit method extrapolated in dt within 3x its
    estimated error (+1e-12 for the grips that stick)."""
    for grip in np.linspace(1.0, 2.6, 17):
        sc = grip_scene(float(grip))
        exdex.simulate(sc, t_end=0.001, dt=1e-4, method="event")
        ev = exdex.simulate(sc, t_end=0.03, dt=1e-3, method="event").q[-1]
        ref, est = implicit_extrapolated(sc, 0.03, 2e-5)
        assert np.all(np.abs(ev - ref) <= 3 * est + 1e-12), (grip, ev, ref, est)


def turning_scene():
    """Translation along B x, gripper turning about the horizontal A y axis
    through the object's centre of mass (B z = -A y): ramp to w = 1.5 rad/s by
    t_a = 0.2 s, then constant w (trapezoid: 1.2 rad in 1 s)."""
    m, mu, F = 0.2, 0.5, 0.5
    sc = Scene(body=Body(m), grasp=Grasp(mu=mu, grip_force=F), dof="translation", slide_axis=(1.0, 0.0),
               motion=TrapezoidalProfile(amplitude=1.2, duration=1.0, v_max=1.5, axis=(0, 1, 0), rotation=True))
    return sc, m, 2 * mu * F, 1.5, 0.2


def turning_closed_form(t):
    """q(t), qd(t) of the turning scene.

    While it sticks the object stays on the axis (r = 0): no centrifugal,
    Euler or Coriolis force along the slide, only gravity, whose component
    along B x is g sin s(t) (B x tilts down by the turned angle s). In the
    cruise s(t) = w t_a / 2 + w (t - t_a). Slip starts where m g sin s = C:
    s* = arcsin(C / (m g)), t* = t_a + (s* - w t_a / 2) / w. Then, with
    tau = t - t*, q'' = g sin(s* + w tau) - C / m + w^2 q (centrifugal;
    Coriolis is normal to the slide), q(0) = q'(0) = 0:
        q = A sin(s* + w tau) + B + c1 cosh(w tau) + c2 sinh(w tau),
        A = -g / (2 w^2), B = C / (m w^2), c1 = -C / (2 m w^2),
        c2 = g cos(s*) / (2 w^2).
    """
    _, m, C, w, ta = turning_scene()
    s_star = math.asin(C / (m * G))
    t_star = ta + (s_star - 0.5 * w * ta) / w
    tau = t - t_star
    A, B, c1, c2 = -G / (2 * w * w), C / (m * w * w), -C / (2 * m * w * w), G * math.cos(s_star) / (2 * w * w)
    q = A * math.sin(s_star + w * tau) + B + c1 * math.cosh(w * tau) + c2 * math.sinh(w * tau)
    qd = w * (A * math.cos(s_star + w * tau) + c1 * math.sinh(w * tau) + c2 * math.cosh(w * tau))
    return q, qd, t_star


@pytest.mark.parametrize("t_end", [0.3, 0.5, 0.75])
def test_slip_onset_at_the_exact_crossing(t_end):
    """The slip starts at arcsin(C/(m g))/w into the cruise, inside an output
    interval: the final q matches the closed form for output dt = t_end,
    t_end/8 and 1 ms; the onset error inferred from it, (q - q_exact)/qd, is
    below 1e-9 s (an onset at the next output sample would be up to dt
    late)."""
    sc, *_ = turning_scene()
    q_ex, qd_ex, t_star = turning_closed_form(t_end)
    assert 0.27 < t_star < 0.3
    for dt in (t_end, t_end / 8, 1e-3):
        r = exdex.simulate(sc, t_end=t_end, dt=dt, method="event")
        assert abs(r.q[-1, 0] - q_ex) / qd_ex < 1e-9, (dt, r.q[-1, 0], q_ex)


@pytest.mark.parametrize("rtol", [1e-6, 1e-8, 1e-10])
def test_short_slip_inside_a_long_stick_step(rtol):
    """While the object sticks its state is constant, so the stepper's steps
    grow to the output interval or the motion's next switch; the stick guard
    C - |load| can still dip below 0 and recover within one such step. Here
    the gripper, tilted by -0.3 rad about its plate normal, turns by 0.7 rad
    (trapezoid, cruise at w = 0.9 rad/s from 0.222 s to 0.778 s) about that
    normal through the centre of mass, and the capacity is C = m g (1 -
    delta), delta = 1e-5: along the slide axis (B's y) the load m g cos(phi),
    phi = w tau the angle from upright (tau = t - 4/9 s in the cruise),
    exceeds C only for |tau| < arccos(1 - delta) / w ~ 5 ms. The slip then
    obeys s'' = -g cos(w tau) + C / m + w^2 s (gravity, friction up against
    the downward slip, the centrifugal term of the turn; Coriolis is normal
    to the slide axis) from s = s' = 0 at tau1 = -arccos(1 - delta) / w until
    s' returns to 0, after which the load is back inside the capacity
    (reference: scipy's DOP853 at rtol 1e-13). The final slip, -5.45e-9 m,
    is the same for output grids T/2, T/16 and 2^-8 s (steps that end at
    output samples no longer decide whether the slip is seen) and agrees
    with the reference to 1e-6 of itself at every rtol (the slip's start and
    end are located to 3e-12 T)."""
    from scipy.integrate import solve_ivp
    m, mu, delta, tilt, w, T = 0.1, 0.5, 1e-5, 0.3, 0.9, 1.0
    axis = np.array([0.0, -1.0, 0.0])
    K = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    R0 = (np.eye(3) - math.sin(tilt) * K + (1 - math.cos(tilt)) * K @ K) @ np.array(
        exdex.scene.DEFAULT_GRIPPER_ROTATION)
    C = m * G * (1 - delta)
    sc = Scene(body=Body.box(m, (0.03, 0.06, 0.02)),
               grasp=Grasp(mu=mu, grip_force=C / (2 * mu), patch=Patch.rectangle(0.01, 0.02)),
               motion=TrapezoidalProfile(amplitude=0.7, duration=T, v_max=w, axis=tuple(axis), rotation=True),
               gripper_rotation=tuple(map(tuple, R0)))
    tau1 = -math.acos(1 - delta) / w

    def ode(tau, y):
        return [y[1], -G * math.cos(w * tau) + C / m + w * w * y[0]]

    def stopped(tau, y):
        return y[1]
    stopped.terminal, stopped.direction = True, 1
    sol = solve_ivp(ode, (tau1, 1.0), [0.0, 0.0], method="DOP853", rtol=1e-13, atol=1e-22, events=stopped)
    s_ref = float(sol.y_events[0][0][0])
    assert -6e-9 < s_ref < -5e-9
    for dt in (T / 2, T / 16, 2.0 ** -8):
        r = exdex.simulate(sc, t_end=T, dt=dt, method="event", rtol=rtol, atol=1e-3 * rtol)
        assert abs(r.q[-1, 0] - s_ref) <= 1e-6 * abs(s_ref), (dt, r.q[-1, 0], s_ref)


def test_rotation_final_angle_independent_of_output_grid():
    """Rotation DoF about the patch centre 20 mm above the centre of mass (no
    gravity torque at rest); the gripper turns about its plate normal at
    constant rate after a ramp, so the gravity torque about the pivot,
    m g 0.02 sin(turned angle), crosses the friction torque C e_r inside an
    output interval (near t = 0.61 s) and the object swings. The final angle with output dt = t_end/8
    equals the fine-grid one (dt = 1 ms) to the event tolerance (rtol 1e-8)."""
    # a 3 x 6 cm box, so the pivot lies on it (a rotation's dynamics use I_zz alone: that of 6 x 3 cm)
    sc = Scene(body=Body.box(0.1, (0.03, 0.06, 0.02)),
               grasp=Grasp(mu=0.5, grip_force=1.5, patch=Patch.disc(0.01, center=(0.0, 0.02))),
               dof="rotation",
               motion=TrapezoidalProfile(amplitude=2.0, duration=2.0, v_max=1.2, axis=(0, -1, 0), rotation=True))
    t_end = 1.6
    fine = exdex.simulate(sc, t_end=t_end, dt=1e-3, method="event")
    assert np.all(fine.stick[:500]) and not np.all(fine.stick) and abs(fine.q[-1, 0]) > 0.05
    coarse = exdex.simulate(sc, t_end=t_end, dt=t_end / 8, method="event")
    assert abs(coarse.q[-1, 0] - fine.q[-1, 0]) <= 1e-8 * abs(fine.q[-1, 0]) + 1e-10


@pytest.mark.parametrize("v0, kind", [((0.3, 0.0, 0.0), "slide"), ((0.2, -0.15, 0.0), "slide"),
                                      ((0.0, 0.0, 4.0), "spin")])
@pytest.mark.warns_by_design("pad")
def test_launched_object_stops_on_resting_gripper(v0, kind):
    """Gripper at rest, gravity along the plate normal (no in-plane load),
    patch at the centre of mass. A slide v0 = (vx, vy, 0): the slip stays
    parallel to v0 (E^2 u / |E u| = u / |u| for u_r = 0), friction C = 2 mu F
    against it: decelerates at C/m, stops at |v0|^2 m / (2 C) along v0 at
    t = |v0| m / C and sticks. A spin w0: friction torque C e_r, stops at
    w0^2 I / (2 C e_r)."""
    m, mu, F = 0.1, 0.4, 0.5
    C = 2 * mu * F
    body = Body.box(m, (0.04, 0.02, 0.01))
    patch = Patch.disc(0.008)
    sc = Scene(body=body, grasp=Grasp(mu=mu, grip_force=F, patch=patch), dof="planar", v0=v0,
               gravity=(0.0, -G, 0.0))
    r = exdex.simulate(sc, t_end=0.2, dt=0.01, method="event")
    assert r.stick[-1] and np.all(r.v[-1] == 0.0)
    if kind == "slide":
        sp = math.hypot(v0[0], v0[1])
        d = sp * sp * m / (2 * C)
        want = np.array([v0[0] / sp * d, v0[1] / sp * d, 0.0])
        assert sp * m / C < 0.2
    else:
        izz = body.inertia[2][2]
        want = np.array([0.0, 0.0, v0[2] ** 2 * izz / (2 * C * patch.e_r)])
    np.testing.assert_allclose(r.q[-1], want, rtol=1e-7, atol=1e-12)


@pytest.mark.warns_by_design("impact")
def test_object_comes_to_rest_on_a_stop():
    """Grip below the weight: the box slides down (B y is up) at g - C/m,
    lands flat on a floor stop 5 mm below its lower face at
    t = sqrt(2 d / (g - C/m)) (plastic, frictionless impact) and rests there:
    final y = -d exactly (to the stop tolerance), x = theta = 0, v = 0, stick."""
    m, mu, F, d = 0.1, 0.5, 0.5, 0.005
    C = 2 * mu * F
    sc = Scene(body=Body.box(m, (0.04, 0.02, 0.01)), grasp=Grasp(mu=mu, grip_force=F, patch=Patch.disc(0.005)),
               dof="planar", stops=(Stop(point=(0.0, 0.0, -0.01 - d), normal=(0.0, 0.0, 1.0)),))
    t_hit = math.sqrt(2 * d / (G - C / m))
    r = exdex.simulate(sc, t_end=0.1, dt=0.01, method="event")
    assert t_hit < 0.1
    assert r.stick[-1] and np.all(r.v[-1] == 0.0)
    np.testing.assert_allclose(r.q[-1], [0.0, -d, 0.0], atol=1e-9)
    # before the landing it slides freely: y = -(g - C/m) t^2 / 2
    i = int(np.searchsorted(r.t, t_hit)) - 1
    np.testing.assert_allclose(r.q[i, 1], -0.5 * (G - C / m) * r.t[i] ** 2, rtol=1e-7)


def random_planar_scene(rng):
    """A planar scene a user would write: a box of 10-200 mm and 10 g-1 kg,
    an off-centre rectangular patch, grip 0.5-5x the weight, gripper at rest,
    Eq. 7 shifts along an arbitrary axis, turns about a tilted axis through an
    arbitrary centre, or a smooth sampled arc (run up to its last sample), an
    object launched on a resting gripper; a third with a floor stop, a third
    with tilted gravity."""
    m = float(10 ** rng.uniform(-2, 0))
    L = float(10 ** rng.uniform(-2, -0.7))
    lx, ly = L, L * rng.uniform(0.3, 1.0)
    ph = rng.uniform(0.05, 0.3) * L
    pc = (float(rng.uniform(-0.3, 0.3) * lx), float(rng.uniform(-0.3, 0.3) * ly))
    grasp = Grasp(mu=float(rng.uniform(0.2, 1.0)), grip_force=float(m * G * rng.uniform(0.5, 5.0)),
                  patch=Patch.rectangle(ph, ph * rng.uniform(0.5, 1), center=pc))
    axis = rng.normal(size=3)
    axis = tuple(axis / np.linalg.norm(axis))
    kind = int(rng.integers(0, 5))
    T = float(rng.uniform(0.05, 0.3))
    v0, t_end, motion = (0.0, 0.0, 0.0), T, Rest()
    if kind == 1:
        motion = AsymmetricProfile(amplitude=float(rng.uniform(-1, 1) * 0.05), duration=T,
                                   beta=float(rng.uniform(0.1, 0.5)), axis=axis)
        t_end = 2.2 * T
    elif kind == 2:
        motion = AsymmetricProfile(amplitude=float(rng.uniform(-0.8, 0.8)), duration=T,
                                   beta=float(rng.uniform(0.1, 0.5)), axis=axis, rotation=True,
                                   center=tuple(float(x) for x in rng.normal(size=3) * L))
        t_end = 2.2 * T
    elif kind == 3:
        ts = np.linspace(0, T, 12)
        th = rng.uniform(-0.6, 0.6) * (1 - np.cos(np.pi * ts / T)) / 2
        qs = np.stack([np.cos(th / 2)] + [np.sin(th / 2) * a for a in axis], 1)
        pos = np.outer(np.sin(np.pi * ts / T), rng.normal(size=3) * 0.02)
        motion = SampledTrajectory(times=ts, positions=pos, quaternions=qs)
        t_end = 0.95 * T
    elif kind == 4:
        v0 = tuple(float(x) for x in rng.normal(size=3) * np.array([0.2, 0.2, 3.0]))
    stops = ()
    if rng.uniform() < 1 / 3:
        stops = (Stop(point=(0, 0, -0.5 * max(lx, ly) - float(rng.uniform(0, 0.5)) * L), normal=(0, 0, 1)),)
    gravity = (0.0, 0.0, -G)
    if rng.uniform() < 1 / 3:
        gravity = tuple(float(x) * G for x in axis[::-1])
    sc = Scene(body=Body.box(m, (lx, ly, 0.3 * L)), grasp=grasp, motion=motion, dof="planar", v0=v0,
               gravity=gravity, stops=stops)
    return sc, t_end, L


# plausibility: the random masses and sizes are drawn apart (densities of any size)
@pytest.mark.warns_by_design("impact", "pad", "outline", "solver", "jump", "plausibility")
@pytest.mark.parametrize("seed", range(24))
def test_random_planar_scene_agrees_with_implicit(seed):
    """Every random planar scene returns with the event method at its default
    tolerances and a coarse output grid (t_end/4), and its final pose agrees
    with the implicit method extrapolated in dt (t_end/4000, t_end/8000) within
    4x the implicit estimate plus 1e-7 (lengths in units of the box size L,
    theta in rad)."""
    sc, t_end, L = random_planar_scene(np.random.default_rng(1000 + seed))
    ev = exdex.simulate(sc, t_end=t_end, dt=t_end / 4, method="event").q[-1]
    ref, est = implicit_extrapolated(sc, t_end, t_end / 4000)
    scale = np.array([L, L, 1.0])
    err, est = np.abs(ev - ref) / scale, est / scale
    assert np.all(err <= 4 * est + 1e-7), (err, est)


def test_solver_error_says_when_why_and_what_instead():
    """A regularised run whose eps makes the explicit stepper's step collapse
    (stiffness C/(M eps) ~ 1e9/s) fails with a SolverError that carries the
    time reached (inside the run), the cause, and names the remedy."""
    sc = grip_scene(2.6)  # holds: the regularised object creeps at ~eps
    with pytest.raises(exdex.SolverError) as info:
        exdex.simulate(sc, t_end=0.01, dt=0.01, method="regularised", eps=1e-12)
    e = info.value
    assert e.status == 3
    assert e.cause == "step_budget"
    assert 0.0 <= e.time < 0.01
    msg = str(e)
    assert "t = " in msg and "method='implicit'" in msg and "eps" in msg


def launched_scene(rng):
    """An object of 1 mm-1 m and 1 g-1 kg launched with a random slide and
    spin (v0 of the order of L/T, 1/T, T = 3 sqrt(L/g)) on a resting gripper
    that holds it (grip 1-5x the weight), an off-centre patch, gravity along
    a random direction: the slip decays to 0 in finite time while its
    direction turns."""
    m = float(10 ** rng.uniform(-3, 0))
    L = float(10 ** rng.uniform(-3, 0))
    lx, ly = L, L * rng.uniform(0.3, 1.0)
    grasp = Grasp(mu=float(rng.uniform(0.2, 1.0)), grip_force=float(m * G * rng.uniform(1.0, 5.0)),
                  patch=Patch.disc(0.15 * L, center=(float(rng.uniform(-0.2, 0.2) * lx),
                                                     float(rng.uniform(-0.2, 0.2) * ly))))
    g = rng.normal(size=3)
    T = 3.0 * math.sqrt(L / G)
    v0 = tuple(float(x) for x in rng.normal(size=3) * np.array([L / T, L / T, 1.0 / T]))
    sc = Scene(body=Body.box(m, (lx, ly, 0.3 * L)), grasp=grasp, dof="planar", v0=v0,
               gravity=tuple(float(x) for x in G * g / np.linalg.norm(g)))
    return sc, 2 * T, L


# plausibility: the random masses and sizes are drawn apart (densities of any size)
@pytest.mark.warns_by_design("impact", "pad", "outline", "solver", "jump", "plausibility")
@pytest.mark.parametrize("seed", range(12))
def test_launched_random_object_at_tight_tolerance(seed):
    """Launched objects at rtol 1e-12 (atol 1e-12 L): the event method
    returns, and its final pose agrees with the implicit method extrapolated
    in dt (t_end/4000, t_end/8000) within 4x its estimate plus 1e-7 (lengths in
    units of L)."""
    sc, t_end, L = launched_scene(np.random.default_rng(2000 + seed))
    ev = exdex.simulate(sc, t_end=t_end, dt=t_end / 8, method="event", rtol=1e-12, atol=1e-12 * L).q[-1]
    ref, est = implicit_extrapolated(sc, t_end, t_end / 4000)
    scale = np.array([L, L, 1.0])
    assert np.all(np.abs(ev - ref) / scale <= 4 * est / scale + 1e-7), (ev, ref, est)


def falling_onto_stop_scene(rng):
    """Grip 0.2-0.9x the weight: the box (1 mm-1 m, random initial angle)
    slides down from rest onto a floor stop tilted by up to 0.3 rad, lands on
    a corner and comes to rest on it or on a face, or slides along it."""
    m = float(10 ** rng.uniform(-3, 0))
    L = float(10 ** rng.uniform(-3, 0))
    lx, ly = L, L * rng.uniform(0.3, 1.0)
    grasp = Grasp(mu=float(rng.uniform(0.2, 1.0)), grip_force=float(m * G * rng.uniform(0.2, 0.9)),
                  patch=Patch.disc(0.15 * L, center=(float(rng.uniform(-0.2, 0.2) * lx),
                                                     float(rng.uniform(-0.2, 0.2) * ly))))
    tilt = rng.uniform(-0.3, 0.3)
    d = 0.5 * math.hypot(lx, ly) + rng.uniform(0.05, 0.5) * L
    stop = Stop(point=(0.0, 0.0, -float(d)), normal=(float(math.sin(tilt)), 0.0, float(math.cos(tilt))))
    sc = Scene(body=Body.box(m, (lx, ly, 0.3 * L)), grasp=grasp, dof="planar", stops=(stop,),
               q0=(0.0, 0.0, float(rng.uniform(-1, 1))))
    return sc, 9.0 * math.sqrt(L / G), L


def implicit_sequence(scene, t_end, k=(4000, 8000, 16000, 32000)):
    """The implicit method's final q at dt = t_end/k for a sequence of k: the
    finest one, and the largest distance of the others from it (its error
    estimate where impacts make the convergence in dt irregular, so that a
    two-level extrapolation is unreliable)."""
    qs = [exdex.simulate(scene, t_end=t_end, dt=t_end / kk, method="implicit").q[-1] for kk in k]
    return qs[-1], np.max(np.abs(np.array(qs[:-1]) - qs[-1]), axis=0)


# plausibility: the random masses and sizes are drawn apart (densities of any size)
@pytest.mark.warns_by_design("impact", "pad", "outline", "plausibility")
@pytest.mark.parametrize("seed", range(12))
def test_object_falling_onto_a_stop(seed):
    """The event method returns at rtol 1e-8 and 1e-10 (atol rtol L), keeps
    the outline out of the stop (min gap >= -1e-9 L), and its final pose
    agrees with the implicit method at dt = t_end/32000 within 2x the spread
    of the implicit results at t_end/4000 .. t_end/16000 plus 1e-7 (lengths
    in units of L, theta in rad)."""
    sc, t_end, L = falling_onto_stop_scene(np.random.default_rng(3000 + seed))
    ref, est = implicit_sequence(sc, t_end)
    scale = np.array([L, L, 1.0])
    for rtol in (1e-8, 1e-10):
        r = exdex.simulate(sc, t_end=t_end, dt=t_end / 8, method="event", rtol=rtol, atol=rtol * L)
        assert r.stats["min_gap"] >= -1e-9 * L
        assert np.all(np.abs(r.q[-1] - ref) / scale <= 2 * est / scale + 1e-7), (rtol, r.q[-1], ref, est)


@pytest.mark.warns_by_design("impact")
def test_planar_bench_scene_at_loose_rtol_converges_to_tight_rtol():
    """A loose rtol gives a less accurate answer, never a failure: the bench's
    planar scene (a stop turning in B pushes the resting box, so the rest and
    impact decisions meet stop speeds of mm/s) runs at rtol 1e-2, 1e-3, 1e-4
    (atol = 1e-2 rtol, as the bench), and its final state approaches the
    event method's own run at rtol 1e-12 (the reference: no closed form
    exists for this scene) with an error that shrinks as rtol does.

    Bounds: each tenfold tightening must reduce the final-state error by more
    than a factor 2 (an error controlled by rtol falls about tenfold), and the
    error at rtol 1e-2 must stay below rtol times the size of the final state
    (a tolerance-proportional error, not a different outcome)."""
    from exdex.studies import bench
    sc = bench.planar_scene()
    t_end, dt = 1.5, bench.GRID_DT
    ref = exdex.simulate(sc, t_end, dt=dt, method="event", rtol=1e-12, atol=1e-14).q[-1]
    errs = []
    for rtol in (1e-2, 1e-3, 1e-4):
        r = exdex.simulate(sc, t_end, dt=dt, method="event", rtol=rtol, atol=1e-2 * rtol)
        assert r.t[-1] == t_end
        errs.append(float(np.max(np.abs(r.q[-1] - ref))))
    assert errs[0] < 1e-2 * np.max(np.abs(ref)), errs
    assert errs[1] < errs[0] / 2 and errs[2] < errs[1] / 2, errs


# ------------------------------------------------- a corner grazing a stop
# A box spins freely (mu = 0, gravity along the plate normal, gripper at
# rest, frame B = A) past a stop y >= -d placed eps short of its corners'
# reach, d = R_c cos(eps) (R_c the half-diagonal): a corner dips below the
# stop plane only over a turn of 2 eps. Its gap is a smooth function whose
# end values over one step can both be positive, and a free spin is
# integrated exactly by the Runge-Kutta stepper, so its error control
# allows one step over the whole output interval: the impact shows only as
# an interior minimum of the gap.

def _grazing_scene(dof, v0, eps):
    a, b = 0.04, 0.02
    Rc = 0.5 * math.hypot(a, b)
    stop = Stop(point=(0.0, -Rc * math.cos(eps), 0.0), normal=(0.0, 1.0, 0.0))
    sc = Scene(body=Body.box(0.1, (a, b, 0.01)), grasp=Grasp(mu=0.0, grip_force=1.0, patch=Patch.disc(0.005)),
               dof=dof, stops=(stop,), v0=v0, gripper_rotation=np.eye(3))
    corners = [(sx * a / 2, sy * b / 2) for sx in (1, -1) for sy in (1, -1)]
    return sc, corners, Rc * math.cos(eps)


@pytest.mark.parametrize("method", ["event", "regularised"])
@pytest.mark.parametrize("rtol", [1e-6, 1e-9])
def test_grazing_corner_stops_a_spin_in_one_output_interval(method, rtol):
    """Rotation about the centre of mass at w0 (the patch there: no torque).
    Closed form: corner j at angle alpha_j reaches the stop when
    alpha_j + w0 t = -pi/2 - eps (mod 2 pi), first at t* = min_j
    ((-pi/2 - eps - alpha_j) mod 2 pi) / w0; the inelastic impact at a corner
    off the pivot's vertical kills the only velocity, and with no torque the
    box stays there: final angle w0 t*, rate 0, for output dt = t_end."""
    w0, eps = 2.0 * math.pi, 0.05
    sc, corners, _ = _grazing_scene("rotation", (0.0, 0.0, w0), eps)
    t_star = min(((-math.pi / 2 - eps - math.atan2(y, x)) % (2 * math.pi)) / w0 for x, y in corners)
    with pytest.warns(exdex.PhysicsWarning):
        r = exdex.simulate(sc, t_end=1.0, dt=1.0, method=method, rtol=rtol)
    assert r.stats["impacts"] == 1
    assert abs(r.q[-1, 0] - w0 * t_star) <= 1e-8
    assert r.v[-1, 0] == 0.0
    assert r.stats["min_gap"] >= -1e-12


@pytest.mark.parametrize("method", ["event", "regularised"])
def test_grazing_corner_planar_found_in_one_output_interval(method):
    """Planar free flight (mu = 0) at v = (vx, vy, w0): corner j is at
    (vx t, vy t) + Rz(w0 t) c_j; its first crossing of the stop t* is found
    here by scipy's brentq on a fine bracket of that closed-form gap
    (independent of exdex). Run to t_end = 2 s, past t* + 3 eps / w0 (when the
    free corner would be back above the stop), with the output grid one
    interval: the impact must be found (the same final state as with 4000
    output intervals, which cap the steps far below the dip's duration) and
    the outline must stay out of the stop."""
    from scipy.optimize import brentq
    w0, eps, vx, vy = 3.0, 0.03, 0.01, -0.0005
    sc, corners, d = _grazing_scene("planar", (vx, vy, w0), eps)

    def gap(t, c):
        ct, st = math.cos(w0 * t), math.sin(w0 * t)
        return vy * t + st * c[0] + ct * c[1] + d

    ts = np.linspace(0.0, 2 * math.pi / w0, 20001)
    t_star = math.inf
    for c in corners:
        g = np.array([gap(t, c) for t in ts])
        k = np.flatnonzero((g[:-1] > 0) & (g[1:] <= 0))
        if k.size:
            t_star = min(t_star, brentq(gap, ts[k[0]], ts[k[0] + 1], args=(c,), xtol=1e-15))
    t_end = 2.0
    assert t_star + 3.0 * eps / w0 < t_end
    with pytest.warns(exdex.PhysicsWarning):
        one = exdex.simulate(sc, t_end=t_end, dt=t_end, method=method, rtol=1e-9)
        fine = exdex.simulate(sc, t_end=t_end, dt=t_end / 4000, method=method, rtol=1e-9)
    assert one.stats["impacts"] >= 1
    assert one.stats["min_gap"] >= -1e-12
    np.testing.assert_allclose(one.q[-1], fine.q[-1], rtol=0, atol=1e-7)
    np.testing.assert_allclose(one.v[-1], fine.v[-1], rtol=0, atol=1e-6)


@pytest.mark.parametrize("rtol", [1e-6, 1e-8, 1e-10])
def test_brief_slip_inside_one_stick_step(rtol):
    """A held object (q and qd fixed, so the stepper takes the whole rest as
    one step) whose load leaves the friction cone for a moment: a vertical
    Shake(A < 0) peaks the gripper's upward acceleration |A| w^2 at
    t = pi / w, and the capacity C = m (g + (1 - delta) |A| w^2) holds the
    object except near that peak. Closed form, tau = t - pi / w, K = |A| w^2:
    the object slips down from tau1 = -arccos(1 - delta) / w with
    s'' = K ((1 - delta) - cos w tau), so
        s'(tau) = K ((1 - delta) (tau - tau1) - (sin w tau - sin w tau1) / w),
        s(tau)  = K ((1 - delta) (tau - tau1)^2 / 2
                     + (cos w tau - cos w tau1) / w^2 + sin(w tau1) (tau - tau1) / w),
    and sticks again at the root tau2 > -tau1 of s' (scipy's brentq; the
    load is then back inside the cone, and stays there). The output grid is
    one interval and the tolerance loose: the rest before and after the slip
    is one stick step across the peak unless the slip is found inside it.
    Event method, error within 10 rtol of the slip."""
    from scipy.optimize import brentq
    m, A, f, delta, g = 0.1, -0.01, 2.0, 0.02, 9.81
    w = 2 * math.pi * f
    K = abs(A) * w * w
    cap = m * (g + (1 - delta) * K)
    grasp = Grasp(mu=0.5, grip_force=cap / (2 * 0.5))
    scene = Scene(body=Body(m), grasp=grasp, motion=exdex.Shake(A, f, cycles=1, axis=(0, 0, 1)))
    tau1 = -math.acos(1 - delta) / w

    def v(tau):
        return K * ((1 - delta) * (tau - tau1) - (math.sin(w * tau) - math.sin(w * tau1)) / w)

    tau2 = brentq(v, -tau1, math.pi / w, xtol=1e-15)
    s2 = K * ((1 - delta) * (tau2 - tau1) ** 2 / 2 + (math.cos(w * tau2) - math.cos(w * tau1)) / w**2
              + math.sin(w * tau1) * (tau2 - tau1) / w)
    assert s2 < -1e-6
    for dt in (1.0, 1e-3):
        r = exdex.simulate(scene, t_end=1.0, dt=dt, method="event", rtol=rtol, atol=1e-3 * rtol)
        assert abs(r.q[-1, 0] - s2) <= 10 * rtol * abs(s2), (dt, r.q[-1, 0], s2)


@pytest.mark.parametrize("rtol", [1e-9, 1e-11])
def test_steady_slow_slip_on_the_friction_incline(rtol):
    """A planar slip that lingers at a small speed, where the sliding law's
    direction relaxes fast (rate C / (m |v|)) and an explicit stepper is held
    to steps ~ m |v| / C. Gripper at rest, patch at the centre of mass
    (E u = v for a translation, no friction moment, so theta stays 0), the
    in-plane gravity g' = C / m along x exactly at the friction limit (an
    incline at tan(alpha) = mu), launched at v0 along y. With phi the angle
    of v from x: along v, dv/dt = g' (cos phi - 1); across, v dphi/dt =
    -g' sin phi. So d ln v / dphi = tan(phi / 2), v (1 + cos phi) = v0
    (phi from pi / 2 to 0), the speed tends to v0 / 2 along x, and with dt
    = v dphi / (-g' sin phi):
        y_inf = (v0^2 / g') int_0^(pi/2) dphi / (1 + cos phi)^2
              = (v0^2 / g') [tan(phi/2) / 2 + tan^3(phi/2) / 6]_0^(pi/2) = 2/3 v0^2 / g',
        x(t) - v0 t / 2 -> (v0^2 / g') int_0^(pi/2) (cos phi - 1) / (2 (1 + cos phi)^2 sin phi) dphi
              = (v0^2 / g') [-1 / (16 cos^4(phi/2))]_0^(pi/2) = -3/16 v0^2 / g',
    reached within a few v0 / g' = 5e-7 s. v0 = 2e-6 m/s: a final speed of
    ~2e-6 of the scene's velocity scale, for 2 s (~40 time scales). The run
    returns on the output grid t_end / 8 (one interval of 0.25 s) and t_end
    / 64, and its final pose is the closed form's within 10 rtol of x."""
    m, mu, F, v0, t_end = 0.1, 0.4, 0.5, 2e-6, 2.0
    gp = 2 * mu * F / m
    sc = Scene(body=Body.box(m, (0.04, 0.02, 0.01)), grasp=Grasp(mu=mu, grip_force=F, patch=Patch.disc(0.008)),
               dof="planar", gravity=(gp, -G, 0.0), v0=(0.0, v0, 0.0))
    want = np.array([v0 / 2 * t_end - 3 / 16 * v0**2 / gp, 2 / 3 * v0**2 / gp, 0.0])
    for n in (8, 64):
        r = exdex.simulate(sc, t_end=t_end, dt=t_end / n, method="event", rtol=rtol, atol=1e-3 * rtol)
        assert not r.stick[-1]
        assert np.all(np.abs(r.q[-1] - want) <= 10 * rtol * want[0]), (n, r.q[-1], want)


@pytest.mark.warns_by_design("impact", "pad", "outline")
@pytest.mark.parametrize("seed", [4355, 4421, 7779, 5253])
def test_planar_stop_events_agree_across_output_grids_and_rtol(seed):
    """Planar zoo scenes with two and one stops (tests/zoo.py), whose stop
    events are delicate: a contact-set row separating where its force and gap
    acceleration both vanish (the complementarity solve at the decided state
    may return a force of rounding size for it), a corner lifted off by an
    impact coming back down within the next step (its gap starts at 0 to
    rounding, a zero that is no crossing), a box face arriving at a stop
    tangentially while sliding along it (normal rate ~0, pressed into it: at
    rtol 1e-9 on t_end / 8 it was 0.76 L off with 8 warnings). The event
    method's error is set by
    its tolerance (tests/scenarios/test_zoo.py: c rtol): its runs at rtol 1e-9 and
    1e-10 on the output grids t_end / 8 and t_end / 64 are within 100 rtol
    of the run at 1e-11 on t_end / 64 (the constant c measured on these
    scenes is below 0.01) and report no warnings."""
    import zoo
    zs = zoo.zoo_scene(seed)
    ref = zoo.run(zs, "event", rtol=1e-11, n_out=64)
    assert ref.stats["warnings"] == 0
    for rtol in (1e-9, 1e-10):
        for n_out in (8, 64):
            r = zoo.run(zs, "event", rtol=rtol, n_out=n_out)
            d = zoo.pose_distance(zs, zoo.final_pose(r), zoo.final_pose(ref))
            assert d <= 100 * rtol and r.stats["warnings"] == 0, (rtol, n_out, d, r.stats["warnings"])


# ------------------------------------------ a slip dying out near the friction limit

@pytest.mark.parametrize("rtol", [1e-4, 1e-6, 1e-8])
def test_slip_dying_out_on_a_rough_incline_closed_form_in_few_steps(rtol):
    """A box launched across a rough incline (a resting gripper, gravity a =
    4.95 m/s^2 in the plate plane, friction C / m = k = 5 m/s^2, a disc patch
    at the centre of mass: translation only, isotropic) at v0 = 0.02 m/s
    perpendicular to the load. Its velocity turns towards the load while it
    slows and stops, with psi the angle from the load's direction:
    v = v0 tan(psi / 2)^n / sin(psi), n = k / a (from dv/dt = a cos psi - k,
    v dpsi/dt = -a sin psi), which integrates in closed form to the stop
    time t* = v0 k / (k^2 - a^2) = 0.201 s and the rest position
    x* = 2 n v0^2 / (a (4 n^2 - 1)) across, y* = -v0^2 / (4 a (n^2 - 1))
    along the load. The direction relaxes at the rate a / v, stiff as the
    slip dies out, where rk8pd alone is held to steps ~ v / a (1146, 236,
    244 steps at rtol 1e-4, 1e-6, 1e-8); the Chebyshev stepper takes the
    slow end (hybrid.c): at most 200 steps, and the rest position within
    1e-3 rtol m of the closed form (errors 2e-10, 9e-12, 4e-14 m)."""
    m, mu, N, a, v0 = 0.1, 0.5, 0.5, 4.95, 0.02
    k = 2 * mu * N / m
    n = k / a
    sc = Scene(body=Body.box(m, (0.04, 0.02, 0.01)), grasp=Grasp(mu=mu, grip_force=N, patch=Patch.disc(0.005)),
               motion=Rest(), dof="planar", v0=(v0, 0.0, 0.0), gravity=(0.0, 0.0, -a))
    t_stop = v0 * k / (k * k - a * a)
    x_rest, y_rest = 2 * n * v0 ** 2 / (a * (4 * n * n - 1)), -v0 ** 2 / (4 * a * (n * n - 1))
    r = exdex.simulate(sc, t_end=0.25, dt=0.01, method="event", rtol=rtol, atol=1e-2 * rtol)
    assert r.stats["steps"] <= 200, r.stats["steps"]
    np.testing.assert_allclose(r.q[-1], [x_rest, y_rest, 0.0], rtol=0, atol=1e-3 * rtol)
    assert np.all(r.v[-1] == 0.0) and r.stick[-1]
    assert not np.any(r.stick[1:][r.t[1:] < t_stop]) and np.all(r.stick[r.t > t_stop])

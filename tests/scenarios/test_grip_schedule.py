"""Grip-force schedules (exdex.GripSchedule): the friction capacity
C(t) = mu * fingers * F(t) varies in time, in every method.

Reference values are closed forms, derived in each test's docstring, on the
1-DoF vertical slide: translation along B's y (up), gripper at rest, gravity
g down, mass m, two fingers, so that while the object slides down
    m s'' = -m g + C(t),
and it sticks (s' = 0 exactly) while m g <= C(t).

twin: csrc/tests/scenarios/test_grip_schedule.c (the same subject on the C API)
"""
import dataclasses
import math

import numpy as np
import pytest

import exdex
from exdex import AsymmetricProfile, Body, Grasp, GripSchedule, Patch, Scene

G = 9.81
MU = 0.5

# the planar runs slide far off the pads on purpose (energy and bit-equality
# checks, not grasp outcomes)
pytestmark = pytest.mark.filterwarnings("ignore::exdex.PhysicsWarning")


def vertical(grip, mass=0.1, **kw):
    return Scene(body=Body(mass=mass), grasp=Grasp(mu=MU, grip_force=grip), gravity=(0.0, 0.0, -G), **kw)


# ------------------------------------------------------------ the schedule itself

def test_schedule_values_by_kind():
    """linear through (0, 2), (1, 0), (2, 1): F(0.25) = 1.5, F(1.5) = 0.5,
    rate -2 then 1; held at the end values outside; step: right-continuous
    (F(1) = 0, F(0.999) = 2); cubic: through the points and, being monotone
    (Steffen), never outside the neighbouring forces."""
    lin = GripSchedule([0.0, 1.0, 2.0], [2.0, 0.0, 1.0])
    assert lin(0.25) == pytest.approx(1.5, abs=1e-15)
    assert lin(1.5) == pytest.approx(0.5, abs=1e-15)
    assert lin.rate(0.25) == pytest.approx(-2.0, abs=1e-15) and lin.rate(1.5) == pytest.approx(1.0, abs=1e-15)
    assert lin(-3.0) == 2.0 and lin(7.0) == 1.0
    step = GripSchedule([0.0, 1.0, 2.0], [2.0, 0.0, 1.0], kind="step")
    assert step(1.0) == 0.0 and step(0.999) == 2.0 and step(2.5) == 1.0
    cub = GripSchedule([0.0, 1.0, 2.0], [2.0, 0.0, 1.0], kind="cubic")
    t = np.linspace(0.0, 2.0, 401)
    f = cub(t)
    assert f.shape == t.shape
    assert np.all(f[t <= 1.0] <= 2.0) and np.all(f >= 0.0) and np.all(f[t >= 1.0] <= 1.0)
    assert cub(1.0) == pytest.approx(0.0, abs=1e-15)


@pytest.mark.parametrize("kwargs, exc, words", [
    (dict(times=[0.0, 0.0], forces=[1.0, 1.0]), ValueError, "strictly increasing"),
    (dict(times=[0.0, 1.0], forces=[1.0, -1.0]), ValueError, "forces[1]"),
    (dict(times=[], forces=[]), ValueError, "at least one"),
    (dict(times=[0.0, 1.0], forces=[1.0]), ValueError, "one force per time"),
    (dict(times=[0.0], forces=[1.0], kind="spline"), ValueError, "GripSchedule.kind"),
    (dict(times=[0.0, math.nan], forces=[1.0, 1.0]), ValueError, "GripSchedule.times"),
    (dict(times=[0.0, 1.0], forces=[1.0, math.inf]), ValueError, "GripSchedule.forces"),
    (dict(times="ab", forces=[1.0]), TypeError, "GripSchedule.times"),
])
def test_bad_schedules_named(kwargs, exc, words):
    with pytest.raises(exc, match=None) as info:
        GripSchedule(**kwargs)
    assert words in str(info.value)


def test_grasp_grip_force_type_named():
    with pytest.raises(TypeError, match="Grasp.grip_force"):
        Grasp(mu=0.5, grip_force="1 N")  # type: ignore[arg-type]


def test_capacity_semantics():
    """capacity is the largest capacity mu fingers max F; capacity_at(t) the
    capacity at t (a constant grip: the same value at every t)."""
    g = Grasp(mu=0.5, grip_force=GripSchedule([0.0, 1.0], [4.0, 0.0]))
    assert g.capacity == 0.5 * 2 * 4.0
    assert g.capacity_at(0.25) == pytest.approx(0.5 * 2 * 3.0, abs=1e-15)
    np.testing.assert_allclose(g.capacity_at([0.0, 1.0, 2.0]), [4.0, 0.0, 0.0], atol=1e-15)
    c = Grasp(mu=0.5, grip_force=1.5)
    assert c.capacity_at(3.0) == c.capacity and c.schedule is None
    np.testing.assert_array_equal(c.capacity_at([0.0, 1.0]), [1.5, 1.5])


# ------------------------------------------------------------ (a) linear ramp-down

def ramp_closed_form(m, F0, Tr, t):
    """Forces F0 -> 0 linearly over [0, Tr], C(t) = 2 mu F0 (1 - t/Tr). It
    sticks while C(t) >= m g, until the crossing
        t* = Tr (1 - m g / (2 mu F0));
    then s'' = -g + C(t)/m = -k (t - t*), k = 2 mu F0 / (m Tr), integrated
    twice from rest at t*:
        s' = -k (t - t*)^2 / 2,   s = -k (t - t*)^3 / 6     (t* <= t <= Tr),
    and free fall (C = 0) after Tr. Returns (t*, s(t), s'(t))."""
    t = np.asarray(t, dtype=float)
    ts = Tr * (1.0 - m * G / (2 * MU * F0))
    k = 2 * MU * F0 / (m * Tr)
    tau = np.clip(np.minimum(t, Tr) - ts, 0.0, None)
    s = -k * tau ** 3 / 6
    v = -k * tau ** 2 / 2
    u = np.clip(t - Tr, 0.0, None)
    return ts, s + v * u - 0.5 * G * u ** 2, v - G * u


M, F0, TR, T_END = 0.1, 2.0, 0.5, 0.6
RAMP = GripSchedule([0.0, TR], [F0, 0.0])


def test_ramp_event_exact_onset_and_slip():
    """Event method: every sample within 1e-9 m (and 1e-8 m/s) of the closed
    form, so the onset is located at t* (an onset error dt* shifts s(t_end)
    by k (t_end... ) ~ 1.2 m/s times dt*): stick exactly (v = 0, flag) at
    every sample before t*, slip after it."""
    sc = vertical(RAMP, mass=M)
    r = exdex.simulate(sc, t_end=T_END, dt=0.01, method="event")
    ts, s, v = ramp_closed_form(M, F0, TR, r.t)
    np.testing.assert_allclose(r.q[:, 0], s, rtol=0, atol=1e-9)
    np.testing.assert_allclose(r.v[:, 0], v, rtol=0, atol=1e-8)
    before = r.t < ts
    assert np.all(r.stick[before]) and np.all(r.v[before, 0] == 0.0) and np.all(r.q[before, 0] == 0.0)
    assert not np.any(r.stick[r.t > ts + 1e-6])


def test_ramp_event_independent_of_output_dt():
    """(e) the output grid is only where the event method reports: dt 0.01
    and 0.0037 (no common multiple with t* or Tr) agree at t_end to the
    integration tolerance (both are 1e-9 m from the closed form)."""
    sc = vertical(RAMP, mass=M)
    a = exdex.simulate(sc, t_end=T_END, dt=0.01, method="event")
    b = exdex.simulate(sc, t_end=T_END, dt=0.0037, method="event")
    assert abs(a.q[-1, 0] - b.q[-1, 0]) <= 2e-9
    assert abs(a.v[-1, 0] - b.v[-1, 0]) <= 2e-8


@pytest.mark.parametrize("method", ["implicit", "explicit"])
def test_ramp_time_stepping_first_order(method):
    """Implicit and explicit: first order in dt. Each step uses the exact
    mean capacity over the step, so the error comes from the onset inside a
    step and the velocity lag: at most a few steps' travel at the largest
    speed, 2 dt |v|max (|v|max = |s'(t_end)|) plus, for the explicit
    method, its chatter: at stick its velocity circulates in
    (-dt (C - m g)/m, dt (C + m g)/m] (header of explicit.c), an offset of at
    most dt (C0/m + g) carried to the end, dt (C0/m + g) t_end in position.
    Halving dt halves the error (a first-order method, the ratio within
    [1.6, 2.5])."""
    sc = vertical(RAMP, mass=M)
    ts, s_end, v_end = ramp_closed_form(M, F0, TR, T_END)
    errs = []
    for dt in (1e-3, 5e-4):
        r = exdex.simulate(sc, t_end=T_END, dt=dt, method=method)
        err = abs(r.q[-1, 0] - s_end)
        bound = 2 * dt * abs(v_end) + (dt * (2 * MU * F0 / M + G) * T_END if method == "explicit" else 0.0)
        assert err <= bound, (dt, err, bound)
        errs.append(err)
    assert 1.6 <= errs[0] / errs[1] <= 2.5


def test_ramp_regularised_converges_in_eps():
    """Regularised friction creeps at E u = eps Q / sqrt(C^2 - Q^2) under a
    load Q inside the capacity, so its error against the exact closed form
    vanishes with eps: eps 1e-5 is at least 5x closer than eps 1e-4, and
    within 1e-4 m."""
    sc = vertical(RAMP, mass=M)
    _, s_end, _ = ramp_closed_form(M, F0, TR, T_END)
    e1 = abs(exdex.simulate(sc, T_END, 0.01, method="regularised", eps=1e-4).q[-1, 0] - s_end)
    e2 = abs(exdex.simulate(sc, T_END, 0.01, method="regularised", eps=1e-5).q[-1, 0] - s_end)
    assert e2 <= 0.2 * e1 and e2 <= 1e-4


def test_ramp_analytic_exact():
    """The analytic method solves a piecewise-linear grip: the same
    polynomials (the cubic slip, the onset at the linear root t*), so every
    sample agrees with the closed form to rounding (1e-14 m)."""
    sc = vertical(RAMP, mass=M)
    r = exdex.simulate(sc, t_end=T_END, dt=0.01, method="analytic")
    ts, s, v = ramp_closed_form(M, F0, TR, r.t)
    np.testing.assert_allclose(r.q[:, 0], s, rtol=0, atol=1e-14)
    np.testing.assert_allclose(r.v[:, 0], v, rtol=0, atol=1e-13)
    assert np.all(r.stick[r.t < ts]) and not np.any(r.stick[r.t > ts])


def test_auto_picks_analytic_for_linear_and_event_for_cubic():
    """method='auto' takes the analytic method for linear and step schedules;
    a cubic schedule (no low-degree closed form) falls back to the event
    method, and asking the analytic method for it names the reason."""
    assert exdex.simulate(vertical(RAMP, mass=M), 0.3, 0.01, method="auto").method == "analytic"
    cub = vertical(GripSchedule([0.0, 0.2, 0.5], [2.0, 1.5, 0.0], kind="cubic"), mass=M)
    assert exdex.simulate(cub, 0.3, 0.01, method="auto").method == "event"
    with pytest.raises(ValueError, match="cubic"):
        exdex.simulate(cub, 0.3, 0.01, method="analytic")


# ------------------------------------------------------------ (b) step release and re-grip

# twin: csrc/tests/scenarios/test_grip_schedule.c::grip_step_release_regrip_closed_form
@pytest.mark.parametrize("method, tol", [("event", 1e-9), ("analytic", 1e-15), ("implicit", 2e-4)])
def test_step_release_and_regrip(method, tol):
    """Step schedule: F = 2 N (C = 2 N > m g = 0.981 N: held) until
    t1 = 0.1 s, released (F = 0) until t2 = 0.15 s, re-gripped at 3 N
    (C2 = 3 N). Free fall over tau = t2 - t1: v2 = -g tau, s2 = -g tau^2/2;
    then deceleration a = C2/m - g until v = 0 at t_s = t2 + g tau / a:
        s_final = -g tau^2 / 2 - (g tau)^2 / (2 a),
    after which it sticks (C2 > m g) exactly still. Analytic: the same
    formulas, to rounding. Implicit (dt 1e-4, the exact step-mean
    capacity): within 2 dt |v2| = 1e-4 m, here 2e-4."""
    m, t1, t2, C2 = 0.1, 0.1, 0.15, 3.0
    sc = vertical(GripSchedule([0.0, t1, t2], [2.0, 0.0, 3.0], kind="step"), mass=m)
    tau, a = t2 - t1, C2 / m - G
    t_s = t2 + G * tau / a
    s_final = -G * tau ** 2 / 2 - (G * tau) ** 2 / (2 * a)
    dt = 1e-4 if method == "implicit" else 0.01
    r = exdex.simulate(sc, t_end=0.4, dt=dt, method=method)
    assert abs(r.q[-1, 0] - s_final) <= tol
    held = (r.t < t1 - 1e-12) | (r.t > t_s + 2 * dt)
    assert np.all(r.v[held, 0] == 0.0) and np.all(r.stick[held])
    after = r.t > t_s + 2 * dt
    assert np.all(r.q[after, 0] == r.q[-1, 0])


# ------------------------------------------------------------ (c) rotation

@pytest.mark.parametrize("method, tol", [("event", 1e-9), ("analytic", 1e-14), ("implicit", 5e-4)])
def test_rotation_ramp_up_stops_spin(method, tol):
    """Rotation about the centre of mass (patch centre 0: gravity has no
    moment), spinning at w0, grip ramping up from 0: F(t) = F1 t / T1, the
    friction torque C(t) e_r = 2 mu F1 e_r t / T1 = c t decelerates it:
        I w' = -c t  ->  w = w0 - c t^2 / (2 I),
    stopping at t_s = sqrt(2 I w0 / c), turned by
        theta_s = w0 t_s - c t_s^3 / (6 I) = (2/3) w0 t_s,
    and then stuck (no load). Analytic: to rounding (its slip-stop root is
    that of the quadratic w(t)). Implicit (dt 1e-4): first order, 5e-4 rad."""
    I, e_r, w0, F1, T1 = 1e-4, 0.01, 2.0, 1.0, 1.0
    c = 2 * MU * F1 * e_r / T1
    t_s = math.sqrt(2 * I * w0 / c)
    sc = Scene(body=Body(mass=0.1, inertia=np.diag([I, I, I])),
               grasp=Grasp(mu=MU, grip_force=GripSchedule([0.0, T1], [0.0, F1]), patch=Patch(e_r=e_r)),
               dof="rotation", v0=(0.0, 0.0, w0))
    dt = 1e-4 if method == "implicit" else 0.01
    r = exdex.simulate(sc, t_end=0.3, dt=dt, method=method)
    assert t_s < 0.3
    assert abs(r.q[-1, 0] - 2.0 / 3.0 * w0 * t_s) <= tol
    assert r.v[-1, 0] == 0.0 and r.stick[-1]


# ------------------------------------------------------------ (d) planar: constant schedule

def planar(grip):
    return Scene(body=Body.box(0.1, (0.06, 0.03, 0.02)),
                 grasp=Grasp(mu=0.5, grip_force=grip, patch=Patch.rectangle(0.02, 0.02, center=(0.015, 0.0))),
                 motion=AsymmetricProfile(0.1, 0.25, 0.8, axis=(0.3, 0.0, -1.0)), dof="planar")


@pytest.mark.parametrize("method", ["implicit", "event", "regularised", "explicit"])
def test_planar_constant_schedule_is_the_constant(method):
    """A schedule that equals F on [0, t_end] (its points change only after
    t_end, and never above F, so the scene's scales are the same) gives the
    constant F's result bit for bit: every method evaluates F exactly there
    (the linear interpolant between equal values, the mean of a flat piece).
    A schedule of equal forces is the constant itself."""
    F, t_end = 1.2, 0.6
    ref = exdex.simulate(planar(F), t_end, 0.01, method=method)
    for sched in (GripSchedule([0.0, 1.0, 2.0], [F, F, 0.5 * F]), GripSchedule([0.0, 0.3], [F, F])):
        r = exdex.simulate(planar(sched), t_end, 0.01, method=method)
        for k in ("q", "v", "wrench", "stick"):
            np.testing.assert_array_equal(getattr(r, k), getattr(ref, k), err_msg=k)


# ------------------------------------------------------------ batches, files

def test_batch_scales_the_schedule():
    """The batch's grip_force multiplies the schedule's forces: trajectory i
    is bit-identical to the single run of scene_at(i), a GripSchedule with
    the forces scaled."""
    sc = vertical(RAMP, mass=M)
    b = exdex.simulate_batch(sc, T_END, 0.01, method="event", grip_force=np.array([0.75, 1.0, 1.25]))
    for i in range(3):
        si = b.scene_at(i)
        assert isinstance(si.grasp.grip_force, GripSchedule)
        assert si.grasp.grip_force.max_force == F0 * b.params["grip_force"][i]
        np.testing.assert_array_equal(b.q[i], exdex.simulate(si, T_END, 0.01, method="event").q)
    # at scale 1 the ramp's closed form
    assert abs(b.q[1, -1, 0] - ramp_closed_form(M, F0, TR, T_END)[1]) <= 1e-9


@pytest.mark.parametrize("fmt", ["toml", "json"])
def test_io_round_trip(fmt):
    sc = vertical(GripSchedule([0.0, 0.1, 0.35], [1.5, 0.1, 2.0], kind="cubic"), mass=M)
    back = exdex.io.loads(exdex.io.dumps(sc, fmt), fmt)
    assert back == sc


# ------------------------------------------------------------ properties

def random_schedule(rng):
    n = int(rng.integers(1, 7))
    times = np.sort(rng.uniform(0.0, 0.5, n))
    times = np.unique(times)
    forces = rng.uniform(0.0, 3.0, times.size) * (rng.uniform(size=times.size) > 0.2)
    return GripSchedule(times, forces, kind=str(rng.choice(["linear", "cubic", "step"])))


@pytest.mark.parametrize("seed", range(12))
@pytest.mark.parametrize("method, dof", [(m, d) for m in ("event", "implicit", "analytic")
                                         for d in ("translation", "rotation", "planar")
                                         if not (m == "analytic" and d == "planar")])  # analytic: 1-DoF only
def test_friction_never_adds_energy_random_schedules(seed, method, dof):
    """Across random valid schedules (1 to 6 points, releases included),
    gripper at rest and gravity along the plate normal (B's z = -A's y): only
    friction acts in the plane, so the kinetic energy never increases from
    sample to sample (beyond rounding). The analytic method takes the 1-DoF
    cases, a cubic schedule replaced by the linear one through its points."""
    rng = np.random.default_rng(seed)
    body = Body.box(0.1, (0.06, 0.03, 0.02))
    sched = random_schedule(rng)
    if method == "analytic" and sched.kind == "cubic":
        sched = dataclasses.replace(sched, kind="linear")
    sc = Scene(body=body, grasp=Grasp(mu=0.5, grip_force=sched,
                                      patch=Patch.rectangle(0.02, 0.02, center=(0.0, 0.0))),
               dof=dof, gravity=(0.0, G, 0.0), slide_axis=(0.6, 0.8),
               v0=(float(rng.uniform(-1, 1)), float(rng.uniform(-1, 1)), float(rng.uniform(-20, 20))))
    r = exdex.simulate(sc, t_end=0.6, dt=2e-3, method=method)
    izz = np.array(body.inertia)[2, 2]
    if dof == "translation":
        ke = 0.5 * 0.1 * r.v[:, 0] ** 2
    elif dof == "rotation":
        ke = 0.5 * izz * r.v[:, 0] ** 2
    else:
        ke = 0.5 * 0.1 * (r.v[:, 0] ** 2 + r.v[:, 1] ** 2) + 0.5 * izz * r.v[:, 2] ** 2
    assert np.all(np.diff(ke) <= 1e-12 * ke[:-1] + 1e-300), np.max(np.diff(ke))


@pytest.mark.parametrize("seed", range(12))
@pytest.mark.parametrize("method", ["event", "implicit", "analytic"])
def test_stick_exactly_still_random_schedules(seed, method):
    """Vertical slide under gravity, random schedule and initial speed: a
    sample flagged stick has v == 0 exactly, and consecutive stuck samples
    the same s (no drift while the plates hold, whatever the schedule). For
    the event and analytic methods (exact in time) also E = m v^2 / 2 + m g s
    (s up) never increases (friction dissipates, the capacity's changes do
    no work)."""
    rng = np.random.default_rng(seed)
    sched = random_schedule(rng)
    if method == "analytic" and sched.kind == "cubic":
        sched = dataclasses.replace(sched, kind="linear")
    sc = vertical(sched, mass=0.1, v0=(0.0, float(rng.uniform(-1, 1)), 0.0))
    r = exdex.simulate(sc, t_end=0.6, dt=2e-3, method=method)
    st = r.stick.astype(bool)
    assert np.all(r.v[st, 0] == 0.0)
    both = st[1:] & st[:-1]
    assert np.all(r.q[1:, 0][both] == r.q[:-1, 0][both])
    if method != "implicit":
        E = 0.5 * 0.1 * r.v[:, 0] ** 2 + 0.1 * G * r.q[:, 0]
        assert np.all(np.diff(E) <= 1e-12)


@pytest.mark.parametrize("seed", range(4))
def test_properties_planar_energy(seed):
    """Planar box, gripper at rest, random schedule: kinetic plus potential
    energy (m |v|^2 / 2 + I w^2 / 2 + m g y, B's y up) never increases
    under the event method (friction dissipates, stick holds)."""
    rng = np.random.default_rng(100 + seed)
    body = Body.box(0.1, (0.06, 0.03, 0.02))
    sc = Scene(body=body, grasp=Grasp(mu=0.5, grip_force=random_schedule(rng),
                                      patch=Patch.rectangle(0.02, 0.02, center=(0.01, 0.0))),
               dof="planar", v0=(float(rng.uniform(-0.3, 0.3)), 0.0, float(rng.uniform(-3, 3))))
    r = exdex.simulate(sc, t_end=0.4, dt=2e-3, method="event")
    izz = np.array(body.inertia)[2, 2]
    E = 0.5 * 0.1 * (r.v[:, 0] ** 2 + r.v[:, 1] ** 2) + 0.5 * izz * r.v[:, 2] ** 2 + 0.1 * G * r.q[:, 1]
    assert np.all(np.diff(E) <= 1e-10)


def test_sensitivity_to_the_schedules_scale():
    """exdex.sensitivity of the final slip to grip_force on a schedule is
    the derivative with respect to the factor on its forces (at 1). Closed
    form for the ramp: s(t_end) = s(Tr) + v(Tr) u - g u^2 / 2 (u = t_end -
    Tr) with tau = Tr - t*, t* = Tr (1 - m g / (2 mu k F0)), s(Tr) = -K
    tau^3 / 6, v(Tr) = -K tau^2 / 2, K = 2 mu k F0 / (m Tr); d/dk at k = 1
    by a central difference of the closed form (step 1e-6, error ~1e-12)."""
    sc = vertical(RAMP, mass=M)

    def s_end(k):
        return ramp_closed_form(M, k * F0, TR, T_END)[1]

    expect = (s_end(1 + 1e-6) - s_end(1 - 1e-6)) / 2e-6
    sens = exdex.sensitivity(sc, ["grip_force"], t_end=T_END, dt=0.01)
    assert sens.values["grip_force"] == 1.0
    assert float(sens.dq[0, 0]) == pytest.approx(expect, rel=1e-6)


def test_engine_runs_press_with_the_schedule():
    """The engine cross-checks press with the schedule's force at each step's
    midpoint: for the linear ramp F(t) = F0 (1 - t / TR) (0 after TR, the
    schedule holds its last force), not a constant; a constant grip stays
    that constant."""
    from exdex.engines import _runner
    sc = vertical(RAMP, mass=M)
    for t in (0.0, 0.25 * TR, 0.5 * TR, TR, 2.0 * TR):
        assert _runner.grip_force_at(sc, t) == pytest.approx(F0 * max(0.0, 1.0 - t / TR), abs=1e-15)
    assert _runner.grip_force_at(vertical(1.5, mass=M), 0.3) == 1.5


@pytest.mark.parametrize("method, tol", [("event", 1e-9), ("implicit", None)])
def test_planar_ramp_onset_located(method, tol):
    """Planar box held at its centre of mass (patch centre 0), gripper at
    rest, gravity along B's -y: the load on the patch is the pure force
    (0, -m g), its ellipsoid norm m g, so the object sticks while
    C(t) >= m g and then slides straight down (no torque, maximum
    dissipation keeps x = theta = 0) with y'' = -g + C(t)/m: the 1-DoF
    ramp's closed form in y (ramp_closed_form). Event: every sample to
    1e-9 m, stuck exactly before t*. Implicit: first order, 2 dt |v|max."""
    sc = Scene(body=Body.box(M, (0.06, 0.03, 0.02)),
               grasp=Grasp(mu=MU, grip_force=RAMP, patch=Patch.rectangle(0.02, 0.02)),
               dof="planar", gravity=(0.0, 0.0, -G))
    dt = 0.01 if method == "event" else 1e-3
    r = exdex.simulate(sc, t_end=T_END, dt=dt, method=method)
    ts, s, v = ramp_closed_form(M, F0, TR, r.t)
    if tol is None:
        tol = 2 * dt * abs(v[-1])
    np.testing.assert_allclose(r.q[:, 1], s, rtol=0, atol=tol)
    np.testing.assert_allclose(r.q[:, [0, 2]], 0.0, rtol=0, atol=1e-12)
    if method == "event":
        before = r.t < ts
        assert np.all(r.stick[before]) and np.all(r.v[before] == 0.0)


@pytest.mark.parametrize("seed", range(6))
@pytest.mark.parametrize("method", ["implicit", "event", "regularised", "explicit", "analytic"])
def test_mirror_symmetry_random_schedules(seed, method):
    """Mirror symmetry: the vertical slide with gravity and initial speed
    reversed is the mirror image, s -> -s, whatever the schedule (the
    capacity is a magnitude): q exactly negated, the stick flags equal.
    Planar: reflecting across B's y axis (gravity's and v0's x and the spin
    reversed, a symmetric box held at its centre) negates x and theta and
    keeps y, exactly."""
    rng = np.random.default_rng(200 + seed)
    sched = random_schedule(rng)
    if method == "analytic" and sched.kind == "cubic":
        sched = dataclasses.replace(sched, kind="linear")
    v = float(rng.uniform(-1, 1))
    a = exdex.simulate(vertical(sched, mass=0.1, v0=(0.0, v, 0.0)), 0.5, 0.01, method=method)
    b = exdex.simulate(dataclasses.replace(vertical(sched, mass=0.1, v0=(0.0, -v, 0.0)), gravity=(0.0, 0.0, G)),
                       0.5, 0.01, method=method)
    np.testing.assert_array_equal(a.q, -b.q)
    np.testing.assert_array_equal(a.stick, b.stick)
    if method == "analytic":
        return

    def planar_scene(sgn):
        return Scene(body=Body.box(0.1, (0.06, 0.03, 0.02)),
                     grasp=Grasp(mu=0.5, grip_force=sched, patch=Patch.rectangle(0.02, 0.02)), dof="planar",
                     gravity=(sgn * 3.0, 0.0, -G), v0=(sgn * 0.2, 0.1, sgn * 2.0))

    p = exdex.simulate(planar_scene(1.0), 0.5, 0.01, method=method)
    m = exdex.simulate(planar_scene(-1.0), 0.5, 0.01, method=method)
    np.testing.assert_array_equal(p.q[:, [0, 2]], -m.q[:, [0, 2]])
    np.testing.assert_array_equal(p.q[:, 1], m.q[:, 1])

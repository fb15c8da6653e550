"""The integration methods besides the implicit one (csrc/hybrid.c, explicit.c) through
the Python API: the paper cases against their closed forms (exdex.paper),
the regularised ODE against an independent stiff integrator (scipy Radau),
an event-driven closed form with a stick event, the explicit scheme's own
closed form and chatter, argument checks, and the numbers the C suite
reports (csrc/tests/scenarios/test_methods.c) recomputed through Python.

twin: csrc/tests/scenarios/test_methods.c (the same subject on the C API)
"""
import math
import re

import numpy as np
import pytest

import exdex
from exdex import paper

G = 9.81
METHODS = ["implicit", "event", "regularised", "explicit"]


def vertical(mass, capacity, motion=exdex.Rest(), **kw):
    """1-DoF vertical scene, two fingers, mu 0.5: capacity [N] = grip force."""
    return exdex.Scene(body=exdex.Body(mass=mass), grasp=exdex.Grasp(mu=0.5, grip_force=capacity),
                       motion=motion, **kw)


FIG3 = vertical(0.1, 1.5, motion=exdex.AsymmetricProfile(0.1, 0.5, 0.9, axis=(0, 0, -1)))


@pytest.mark.warns_by_design("outline")
@pytest.mark.parametrize("method", METHODS)
def test_every_method_runs_the_paper_cases(method):
    for scene, t_end in [(paper.fig3_scene(), 1.5), (paper.fig4_scene(), 1.0), (paper.fig6_scene(), 7.0)]:
        r = exdex.simulate(scene, t_end, 1e-2, method=method)
        assert r.method == method
        assert r.q.shape == (151 if t_end == 1.5 else int(round(t_end / 1e-2)) + 1, 1)
        assert np.all(np.isfinite(r.q)) and np.all(np.isfinite(r.wrench))


def test_event_fig3_fig6_closed_forms():
    """exdex.paper.closed_form: exact 1-DoF Coulomb propagation, written
    independently of the C core. The event method matches it to rounding
    at a coarse output grid, and is exactly still after the rest time."""
    for scene, t_end, tol in [(paper.fig3_scene(), 1.5, 1e-12), (paper.fig6_scene(), 7.0, 1e-9)]:
        cf = paper.closed_form(scene)
        r = exdex.simulate(scene, t_end, 1e-2, method="event")
        assert r.q[-1, 0] - r.q[0, 0] == pytest.approx(cf.final, abs=tol)
        for i in range(0, len(r.t), 7):
            x, v = cf(r.t[i])
            assert r.q[i, 0] - r.q[0, 0] == pytest.approx(x, abs=tol)
            assert r.v[i, 0] == pytest.approx(v, abs=1e3 * tol)
        assert r.drift_after(cf.rest_time + 1e-9) == 0.0
        assert r.stick[r.t > cf.rest_time + 1e-9].all()


def test_event_fig4_stop_force(ref):
    """Fig. 4: while the plates slide past the object held by the stop, the
    stop carries m g + mu N (paper_fig4_stop_force, closed form)."""
    r = exdex.simulate(paper.fig4_scene(), 1.0, 1e-3, method="event")
    cruise = (r.t > 0.1) & (r.t < 0.4)
    assert r.stop_force[cruise, 0] == pytest.approx(ref["paper_fig4_stop_force"], abs=1e-9)
    assert r.q[-1, 0] - r.q[0, 0] == pytest.approx(0.05, abs=1e-12)
    assert r.stats["min_gap"] >= -1e-15


def test_event_inward_throw_in_a_spinning_gripper_sticks_at_the_closed_form():
    """Gripper spinning at w about its plate normal, the object thrown inward
    along a radial line with friction capacity c m: s'' = w^2 s + c until it
    stops at tanh(w t*) = -v0 / (w (s0 + c/w^2)), then sticks (w^2 s* < c).
    s(t) = -c/w^2 + (s0 + c/w^2) cosh(w t) + (v0/w) sinh(w t)."""
    w, s0, c, v0 = 2.0, 0.05, 0.3, -0.1
    scene = exdex.Scene(
        body=exdex.Body(mass=0.1), grasp=exdex.Grasp(mu=0.5, grip_force=c * 0.1),
        motion=exdex.TrapezoidalProfile(w * 5.0, 5.0, w, axis=(0, -1, 0), rotation=True),
        slide_axis=(1.0, 0.0), q0=(s0, 0.0, 0.0), v0=(v0, 0.0, 0.0), gravity=(0.0, 0.0, 0.0))
    A = s0 + c / w**2
    t_star = math.atanh(-v0 / (w * A)) / w
    s_star = -c / w**2 + A * math.cosh(w * t_star) + v0 / w * math.sinh(w * t_star)
    assert w**2 * s_star < c
    r = exdex.simulate(scene, 1.0, 1e-2, method="event")
    before = r.t < t_star
    exact = -c / w**2 + A * np.cosh(w * r.t[before]) + v0 / w * np.sinh(w * r.t[before])
    assert r.q[before, 0] == pytest.approx(exact, abs=1e-12)
    assert r.q[-1, 0] == pytest.approx(s_star, abs=1e-12)
    assert r.drift_after(t_star + 1e-9) == 0.0


def test_regularised_matches_an_independent_stiff_integrator():
    """The regularised Fig. 3 ODE written here and integrated by scipy's
    Radau (implicit, stiff) must agree with the C method (rk8pd): relative
    up-positive coordinate s, m s'' = -m (g + a_gripper) - C s'/sqrt(s'^2 + eps^2)."""
    solve_ivp = pytest.importorskip("scipy.integrate").solve_ivp
    eps, m, C = 1e-3, 0.1, 1.5
    aH, aL = 2 * 0.1 / (0.9 * 0.25), 2 * 0.1 / (0.1 * 0.25)
    # gripper acceleration, up positive (Eq. 7 downward first)
    phases = [(0.0, 0.45, -aH), (0.45, 0.55, aL), (0.55, 1.0, -aH), (1.0, 1.5, 0.0)]
    y = np.array([0.0, 0.0])
    for t0, t1, a in phases:
        sol = solve_ivp(lambda t, y: [y[1], -(G + a) - C / m * y[1] / math.sqrt(y[1] ** 2 + eps**2)],
                        (t0, t1), y, method="Radau", rtol=1e-12, atol=1e-14)
        y = sol.y[:, -1]
    r = exdex.simulate(FIG3, 1.5, 1e-2, method="regularised", eps=eps, rtol=1e-10, atol=1e-12)
    assert r.q[-1, 0] == pytest.approx(y[0], abs=1e-9)
    assert r.v[-1, 0] == pytest.approx(y[1], abs=1e-9)


@pytest.mark.parametrize("ratio", [1.01, 1.5, 2.0])
def test_regularised_rotation_creeps_at_the_smoothed_slip_speed(ratio):
    """eps is a slip speed [m/s]; a 1-DoF rotation about the centre of
    pressure slips at e_r |theta'|, so its friction torque is -C w /
    sqrt(w^2 + (eps / e_r)^2) (C = mu N e_r, w = theta'). Paper Fig. 6 with
    the torque capacity C = ratio I_zz a_H: the object is pinned at its
    centre of mass, so over the first gentle phase (0 < t < beta T = 2.1 s)
    the load is Q = I_zz a_H and I_zz w' = Q - C w / sqrt(w^2 + (eps/e_r)^2)
    from rest. It creeps towards w_c = (eps / e_r) Q / sqrt(C^2 - Q^2) with
    the relaxation time I_zz (eps / e_r) / (C (1 - (Q/C)^2)^(3/2)): 0.0094 s
    at ratio 2, 0.020 s at 1.5, so the mean rate over 1.045 .. 2.09 s is w_c
    (closed form) to 1e-6; 4.4 s at ratio 1.01, where the same mean is the
    transient's, from scipy's Radau on that ODE. Smoothing theta' with eps
    as if it were rad/s gives 68x less (1 / e_r)."""
    solve_ivp = pytest.importorskip("scipy.integrate").solve_ivp
    eps = 1e-4
    izz = paper.FIG6["inertia"][2]
    a_h, _ = paper.eq7_accelerations(paper.FIG6["amplitude"], paper.FIG6["duration"], paper.FIG6["beta"])
    sc = paper.fig6_scene(grip_force=ratio * paper.fig3_grip_force(),
                          e_r=izz * a_h / (paper.MU * paper.FINGERS * paper.fig3_grip_force()))
    e_r = sc.grasp.patch.e_r
    Q, C = izz * a_h, paper.MU * paper.FINGERS * sc.grasp.grip_force * e_r
    assert C / Q == pytest.approx(ratio, rel=1e-12)
    ws = eps / e_r
    t0, t1 = 1.045, 2.09
    r = exdex.simulate(sc, t1, dt=t1 - t0, method="regularised", eps=eps, rtol=1e-10, atol=1e-13)
    assert r.t[1] == pytest.approx(t0, rel=1e-12)
    mean = (r.q[-1, 0] - r.q[1, 0]) / (t1 - t0)
    if ratio > 1.2:
        expected = ws * Q / math.sqrt(C * C - Q * Q)
    else:
        sol = solve_ivp(lambda t, y: [y[1], (Q - C * y[1] / math.hypot(y[1], ws)) / izz], (0.0, t1), [0.0, 0.0],
                        method="Radau", rtol=1e-11, atol=1e-15, t_eval=[t0, t1])
        expected = (sol.y[0, 1] - sol.y[0, 0]) / (t1 - t0)
    assert abs(mean) == pytest.approx(expected, rel=1e-6)


def test_explicit_scheme_closed_form_and_chatter():
    """Symplectic Euler free fall: q_n = -g t (t + h)/2. At rest with a load
    inside the capacity the explicit Coulomb velocity never returns to 0 and
    stays in (h (Q - C)/M, h (Q + C)/M] (Q = -m g)."""
    h = 1e-3
    ff = exdex.simulate(exdex.replace(vertical(0.3, 1.0), grasp=exdex.Grasp(mu=0.0, grip_force=1.0)),
                        0.7, h, method="explicit")
    assert ff.q[-1, 0] == pytest.approx(-G * 0.7 * (0.7 + h) / 2, abs=1e-12)
    ratio = 2 + math.sqrt(5)
    r = exdex.simulate(vertical(0.1, ratio * 0.1 * G), 2.0, h, method="explicit")
    v = r.v[2:, 0]
    assert np.all(v != 0.0) and not r.stick[2:].any()
    assert v.min() > h * (-G - ratio * G) * (1 + 1e-9) and v.max() <= h * (-G + ratio * G) * (1 + 1e-9)
    # the implicit and event methods hold it exactly
    for method in ("implicit", "event"):
        s = exdex.simulate(vertical(0.1, ratio * 0.1 * G), 2.0, h, method=method)
        assert s.drift_after(0.0) == 0.0 and s.stick.all()


# --- planar scenes with stops (every method) ---

TILT = 0.2
BOX_R = math.hypot(0.01, 0.02)  # largest vertex distance from the centre of mass [m]


def planar_floor(capacity_ratio=0.8, mu=0.5, theta0=0.0, height=0.01):
    """Planar box 20 x 40 mm, 0.1 kg, plates vertical (B y up), gripper at
    rest, centre of pressure 4 mm off the centre of mass, friction capacity
    capacity_ratio m g (< 1: it cannot hold the weight alone), `height` above
    a floor stop tilted by TILT about the plate normal (the lowest corner
    of the outline at theta0 = 0; a tilted box starts higher)."""
    m = 0.1
    cap = capacity_ratio * m * G
    grasp = exdex.Grasp(mu=mu, grip_force=cap / (2 * mu) if mu > 0 else 0.0,
                        patch=exdex.Patch(e_r=0.005, center=(0.004, 0.0)))
    body = exdex.Body(mass=m, inertia=((1e-4, 0, 0), (0, 1e-4, 0), (0, 0, m * (0.02**2 + 0.04**2) / 12)),
                      outline=((-0.01, -0.02), (0.01, -0.02), (0.01, 0.02), (-0.01, 0.02)))
    normal = (math.sin(TILT), 0.0, math.cos(TILT))
    point = (0.0, 0.0, -0.02 - height - 0.01 * math.sin(TILT))
    return exdex.Scene(body=body, grasp=grasp, dof="planar", q0=(0.0, 0.0, theta0),
                       stops=(exdex.Stop(point=point, normal=normal),))


def vertex_gaps(scene, res):
    """Gaps (n_samples, n_vertices) of every outline vertex to the stop,
    recomputed from the returned poses and the gripper kinematics (as in
    tests/scenarios/test_properties.py)."""
    kin = scene.motion.evaluate(res.t, scene.gripper_rotation, scene.gripper_position)
    pose = res.pose
    stop = scene.stops[0]
    n, p = np.array(stop.normal), np.array(stop.point)
    c, s = np.cos(pose[:, 2]), np.sin(pose[:, 2])
    gaps = []
    for vx, vy in scene.body.vertices():
        xb = np.stack([pose[:, 0] + c * vx - s * vy, pose[:, 1] + s * vx + c * vy, np.zeros_like(c)], axis=1)
        xa = kin["p"] + np.einsum("kij,kj->ki", kin["R"], xb)
        gaps.append((xa - p) @ n)
    return np.stack(gaps, axis=1)


def pose_err(a, b, t):
    """Largest pose difference at time t [m] (theta weighted by the box's
    half-length 0.02 m)."""
    ia, ib = int(np.argmin(abs(a.t - t))), int(np.argmin(abs(b.t - t)))
    assert abs(a.t[ia] - t) < 1e-9 and abs(b.t[ib] - t) < 1e-9
    d = abs(a.q[ia] - b.q[ib])
    return max(d[0], d[1], 0.02 * d[2])


@pytest.mark.warns_by_design("impact", "outline")
def test_planar_stop_methods_agree_with_implicit_at_small_dt():
    """The box slides and turns, lands on a corner, slides along the floor
    and comes to rest on it. Reference: the implicit method at dt = 1e-5.
    The implicit and explicit methods are first order here (impacts and
    stick/slip switches fall inside steps): e(h) ~ c h, so the difference
    between h = 1e-4 and 1e-5 is ~ 9 e(1e-5) (Richardson) and e(1e-5) <~
    |q(1e-4) - q(1e-5)| / 9; 3x that is the reference's tolerance. The
    event method is exact up to its rtol (1e-10, negligible); the
    regularised one is first order in eps (the smooth law differs from
    Coulomb only where the slip speed is ~eps), so the same Richardson
    estimate in eps (1e-4 -> 1e-5) bounds its error. Checked at t = 0.1 s
    (sliding on the floor) and 0.2 s (at rest)."""
    scene = planar_floor()
    T = 0.2
    im1 = exdex.simulate(scene, T, 1e-4, method="implicit")
    im2 = exdex.simulate(scene, T, 1e-5, method="implicit")
    ex1 = exdex.simulate(scene, T, 1e-4, method="explicit")
    ex2 = exdex.simulate(scene, T, 1e-5, method="explicit")
    ev = exdex.simulate(scene, T, 1e-3, method="event", rtol=1e-10, atol=1e-12)
    rg1 = exdex.simulate(scene, T, 1e-3, method="regularised", eps=1e-4, rtol=1e-10, atol=1e-12)
    rg2 = exdex.simulate(scene, T, 1e-3, method="regularised", eps=1e-5, rtol=1e-10, atol=1e-12)
    assert ev.stick[ev.t >= 0.2 - 1e-9].all()  # at rest by t = 0.2 s
    for t in (0.1, 0.2):
        tol_im = 3 * pose_err(im1, im2, t) / 9
        assert tol_im < 3 * 1e-5  # first order with a modest constant [m/s] x dt
        assert pose_err(ev, im2, t) <= tol_im + 1e-8, t
        assert pose_err(ex2, im2, t) <= tol_im + 3 * pose_err(ex1, ex2, t) / 9, t
        assert pose_err(rg2, im2, t) <= tol_im + 3 * pose_err(rg1, rg2, t) / 9, t


@pytest.mark.warns_by_design("impact", "outline")
@pytest.mark.parametrize("method", ["event", "regularised", "explicit", "implicit"])
@pytest.mark.parametrize("case", ["sliding", "falling"])
def test_planar_stop_never_penetrated_beyond_the_methods_bound(method, case):
    """Gaps recomputed from the returned poses. Event and regularised: an
    impact is located to 1e-13 s (approach speeds < 1 m/s here: < 1e-13 m)
    and the contact rows are projected back after every step: >= -1e-12 m.
    Explicit: its rows G v+ >= -gap/h are linear in v+ while a vertex moves
    on a circle of radius <= r_max about the centre of mass, so a step
    penetrates at most 1/2 h^2 thd^2 r_max (thd the step's v+, the returned
    velocity). Implicit (implicit.c): its positions are projected back, 1e-9 m
    as tests/scenarios/test_properties.py. No warnings from the other methods: nothing here is
    unavoidable.
    "falling": frictionless, tilted 0.3 rad, dropped from 20 mm: free fall,
    a corner impact at ~0.6 m/s, rocking and sliding along the floor."""
    if case == "sliding":
        scene, T = planar_floor(), 0.3
    else:
        scene, T = planar_floor(mu=0.0, capacity_ratio=0.0, theta0=0.3, height=0.02), 0.25
    h = 1e-3
    r = exdex.simulate(scene, T, h, method=method, eps=1e-5)
    gaps = vertex_gaps(scene, r)
    if method == "explicit":
        bound = 0.5 * h**2 * np.abs(r.v[:, 2]).max() ** 2 * BOX_R + 1e-15
    elif method == "implicit":
        bound = 1e-9
    else:
        bound = 1e-12
    assert gaps.min() >= -bound, (gaps.min(), bound)
    assert gaps.min() < 1e-6  # it did land
    assert r.stats["min_gap"] == pytest.approx(gaps.min(), abs=1e-12)
    if method != "implicit":  # (implicit.c counts warnings in its own stop solve here)
        assert r.stats["warnings"] == 0
    assert np.all(r.stop_force >= 0.0)


@pytest.mark.warns_by_design("impact", "outline")
def test_planar_box_resting_on_stop_stays_still_and_the_stop_balances_the_load():
    """Event method: after landing the box rests on the floor. Friction
    alone (0.8 m g) cannot hold the weight; the floor carries the rest.
    Exactly still (v = 0, the pose frozen bit for bit, stick) from 0.25 s;
    the plate wrench inside the ellipsoid (|E^-1 w| <= mu N = 0.8 m g); and
    Newton's law at rest with the gripper at rest: plate force + stop force
    lam n_B + m g_B = 0 in B (n_B, g_B the floor normal and gravity in B).
    The implicit method (its own rest solve) gives the same floor force."""
    scene = planar_floor()
    r = exdex.simulate(scene, 0.4, 1e-3, method="event")
    R = np.array(scene.gripper_rotation)
    nB = R.T @ np.array(scene.stops[0].normal)
    gB = R.T @ np.array(scene.gravity)
    m, cap, e_r = scene.body.mass, 0.8 * scene.body.mass * G, scene.grasp.patch.e_r
    rest = r.t >= 0.25
    i0 = int(np.argmax(rest))
    assert r.stick[rest].all()
    # it lies on a long side: both corners of that side on the floor, theta =
    # pi/2 - TILT (geometry), to the event location (1e-13 s) and rounding
    assert r.q[i0, 2] == pytest.approx(math.pi / 2 - TILT, abs=1e-9)
    assert np.sort(vertex_gaps(scene, r)[i0])[:2] == pytest.approx([0.0, 0.0], abs=1e-12)
    assert np.all(r.v[rest] == 0.0)
    assert np.all(r.q[rest] == r.q[i0])
    lam = r.stop_force[rest, 0]
    w = r.wrench[rest]
    assert np.all(lam > 0.0)
    assert np.all(np.sqrt(w[:, 0] ** 2 + w[:, 1] ** 2 + (w[:, 2] / e_r) ** 2) <= cap * (1 + 1e-9))
    resid = w[:, :2] + lam[:, None] * nB[None, :2] + m * gB[None, :2]
    assert np.abs(resid).max() < 1e-9
    assert lam.min() > 0.2 * m * G  # the floor does carry a real part of the weight
    im = exdex.simulate(scene, 0.4, 1e-4, method="implicit")
    assert im.stop_force[-1, 0] == pytest.approx(r.stop_force[-1, 0], abs=1e-3)


def turning_box_on_tilted_stop():
    """The benchmark's planar case (exdex.studies.bench.planar_scene, spelled out
    here): a 60 x 30 x 20 mm box, 0.1 kg, friction capacity 1.1 m g through
    a 20 x 20 mm patch 10 mm beside the centre of mass, the gripper turning
    0.6 rad about the plate normal and back (Eq. 7, T 0.5 s, beta 0.8), a
    stop tilted 10 deg, 8 mm below the box. The box slides onto the stop and
    along it; near t = T the gripper's rotation reverses, the constrained
    slip dies out while the stop (moving in B) still pushes it."""
    m, cap = 0.1, 1.1 * 0.1 * paper.G
    tilt = math.radians(10.0)
    return exdex.Scene(
        body=exdex.Body.box(m, (0.06, 0.03, 0.02)),
        grasp=exdex.Grasp(mu=paper.MU, grip_force=cap / (paper.MU * paper.FINGERS), fingers=paper.FINGERS,
                          patch=exdex.Patch.rectangle(0.02, 0.02, center=(0.01, 0.0))),
        motion=exdex.AsymmetricProfile(0.6, 0.5, 0.8, axis=(0.0, -1.0, 0.0), rotation=True),
        dof="planar",
        stops=(exdex.Stop(point=(0.0, 0.0, -0.015 - 0.008), normal=(math.sin(tilt), 0.0, math.cos(tilt))),))


@pytest.mark.warns_by_design("impact")
def test_event_slip_dying_against_a_moving_stop_converges_at_tight_rtol():
    """Regression: where the slip along the stop died out (|E u| < 1e-9 m/s)
    the stop, moving in B, pushed the object on at a slip below that
    threshold, which stopped it again at once: a Zeno-like cascade of
    restarts towards t = T, 61 warnings at rtol 1e-8 and EXDEX_ENOCONV (the
    step floor, the step collapsing on |E u| -> 0) at rtol 1e-10 and 1e-12.
    Now: no error, no warning, and the final pose agrees with an independent
    method, the implicit one (first order here): Richardson extrapolation
    of dt = 2^-18 and 2^-19, within that method's own error estimate at
    2^-19, |q(2^-19) - q(2^-18)| per coordinate."""
    scene, T = turning_box_on_tilted_stop(), 1.5
    ev = {}
    for rtol in (1e-8, 1e-10, 1e-12):
        r = exdex.simulate(scene, T, 2.0**-6, method="event", rtol=rtol, atol=1e-2 * rtol)
        assert r.stats["warnings"] == 0, rtol
        ev[rtol] = r.q[-1]
    q1 = exdex.simulate(scene, T, 2.0**-18, method="implicit").q[-1]
    q2 = exdex.simulate(scene, T, 2.0**-19, method="implicit").q[-1]
    ref, est = 2.0 * q2 - q1, np.abs(q2 - q1)
    assert est[2] < 1e-6  # the implicit method does converge here (first order)
    for rtol in ev:
        assert np.all(np.abs(ev[rtol] - ref) <= est), (rtol, ev[rtol] - ref, est)


# twin: csrc/tests/scenarios/test_methods.c::methods_event_zeno_like_toggling_fails_loudly
def test_event_zeno_like_toggling_raises_solver_error():
    """A 1 kHz vertical vibration with acceleration amplitude 2 g and
    capacity 1.5 m g crosses the friction limit 2000 times in 1 s: with one
    output interval the event method stops at 1000 events."""
    f = 1000.0
    wf = 2 * math.pi * f
    t = np.arange(int(40 * f) + 1) / (40 * f)
    pos = np.zeros((len(t), 3))
    pos[:, 2] = 2 * G / wf**2 * np.sin(wf * t)
    # R_AB of the default scene (B y up): a quarter turn about A x
    quat = np.tile([math.sqrt(0.5), math.sqrt(0.5), 0.0, 0.0], (len(t), 1))
    motion = exdex.SampledTrajectory(times=t, positions=pos, quaternions=quat)
    scene = vertical(0.1, 1.5 * 0.1 * G, motion=motion)
    with pytest.raises(exdex.SolverError):
        exdex.simulate(scene, 1.0, 1.0, method="event")


# --- numbers reported by csrc/tests/scenarios/test_methods.c, recomputed via Python ---

def _c_values(stdout):
    return {m.group(1): float(m.group(2)) for m in re.finditer(r"^VALUE (\S+) (\S+)$", stdout, re.M)}


PYTHON_SIDE = {
    "methods_event_fig3_final_dt1e-2": lambda: exdex.simulate(FIG3, 1.5, 1e-2, method="event").q[-1, 0],
    "methods_reg_slide_1s_eps1e-4": lambda: exdex.simulate(
        vertical(0.2, 0.6 * 0.2 * G), 1.0, 1e-3, method="regularised", eps=1e-4).q[-1, 0],
    "methods_reg_planar_creep_thd": lambda: exdex.simulate(
        exdex.Scene(body=exdex.Body(mass=0.1, inertia=((1.0, 0, 0), (0, 1.0, 0), (0, 0, 1e-3))),
                    grasp=exdex.Grasp(mu=0.5, grip_force=2.0 * 0.1 * G,
                                      patch=exdex.Patch(e_r=0.02, center=(0.004, 0.0))),
                    dof="planar"),
        0.01, 1e-3, method="regularised", eps=1e-4).v[-1, 2],
}


@pytest.mark.parametrize("key", sorted(PYTHON_SIDE))
def test_c_method_numbers_through_python(c_suite, key):
    values = _c_values(c_suite[1])
    assert key in values, f"the C suite no longer reports {key}"
    assert PYTHON_SIDE[key]() == pytest.approx(values[key], rel=1e-12, abs=1e-15)


def test_c_method_tests_pass(c_suite):
    out = c_suite[1]
    names = re.findall(r"^(ok|FAIL) +(methods_\S+)", out, re.M)
    assert len(names) >= 15
    assert all(s == "ok" for s, _ in names), [n for s, n in names if s != "ok"]

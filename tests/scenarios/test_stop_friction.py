"""Coulomb friction at the stops (``Stop(point, normal, mu)``): closed forms
with their derivations, properties, and the input checks.

Frames as everywhere in exdex: with the default gripper rotation B's x axis
is A's x, B's y axis is A's z (up), B's z axis is -A's y; gravity (0, 0,
-9.81) in A is -9.81 along B's y. A stop's normal (n_x, 0, n_y) in A is
(n_x, n_y) in the plate plane; its tangent there is t = e_z x n = (-n_y,
n_x). Stops are fixed in A, so a gripper moving past a stop slides the
touching vertex along it.

twin: csrc/tests/scenarios/test_stop_friction.c (the same subject on the C API)
"""
import math

import numpy as np
import pytest

import exdex

G = 9.81


def _wall_scene(mu_stop, V=0.01, m=0.1, a=0.03, mu=0.5, grip=1.5, **kw):
    """A square block (side a) in the planar grasp, its right face flush
    against a wall fixed in A at x = 0.1 (normal -x), the gripper moving
    toward the wall at constant speed V from t = 0 (a trapezoid without
    ramps: the velocity jumps to V at t = 0, the block keeps its absolute
    velocity 0, the plates slide past it)."""
    xw = 0.1
    return exdex.Scene(
        body=exdex.Body.box(m, (a, a, 0.02)),
        grasp=exdex.Grasp(mu=mu, grip_force=grip, patch=exdex.Patch.rectangle(0.02, 0.02)),
        motion=exdex.TrapezoidalProfile(amplitude=2.0 * V, duration=2.0, v_max=V, axis=(1, 0, 0)),
        dof="planar", q0=(xw - a / 2, 0.0, 0.0),
        stops=(exdex.Stop((xw, 0.0, 0.0), (-1.0, 0.0, 0.0), mu=mu_stop),), **kw)


def _wall_closed_form(mu_s, V=0.01, m=0.1, cap=1.5):
    """Block dragged against a frictional wall, gravity along the wall.

    The wall stops the block in x (its absolute x velocity is 0), so the
    plates slide past it at (-V, w) in B (w its downward speed, > 0). The
    plate friction opposes that slip (maximum dissipation over the ellipsoid
    with no spin: a pure translation slip gets a pure force): cap (V, w) / s,
    s = sqrt(V^2 + w^2), toward the wall and up. The wall's normal force
    balances the x part, lam = cap V / s; its friction, mu_s lam, acts up
    while the block slides down. Steady state (constant w):
        m g = cap w / s + mu_s cap V / s,   i.e.
        (m g)^2 (V^2 + w^2) = cap^2 (w + mu_s V)^2,
    a quadratic in w: (m^2 g^2 - cap^2) w^2 - 2 cap^2 mu_s V w + (m^2 g^2 -
    cap^2 mu_s^2) V^2 = 0. At w = 0 the wall alone can hold the weight iff
    mu_s cap >= m g: then the block does not slide down at all (w = 0,
    lam = cap). The two normal forces of the flush corners are both
    positive (the block does not tip) when mu_s < 1 for a square: the
    torque mu_s lam a / 2 of the friction about the centre is carried by
    lam_1 - lam_2 over the lever a / 2."""
    mg = m * G
    if mu_s * cap >= mg:
        return 0.0, cap
    A2 = mg ** 2 - cap ** 2
    B = -2.0 * cap ** 2 * mu_s * V
    C = (mg ** 2 - cap ** 2 * mu_s ** 2) * V ** 2
    disc = B * B - 4.0 * A2 * C
    roots = [(-B + sg * math.sqrt(disc)) / (2.0 * A2) for sg in (1.0, -1.0)]
    w = max(r for r in roots if r > 0)
    return w, cap * V / math.hypot(V, w)


@pytest.mark.parametrize("method", ["implicit", "explicit"])
@pytest.mark.parametrize("mu_s", [0.0, 0.3, 0.5])
def test_block_dragged_along_frictional_wall_slides_at_closed_form_speed(mu_s, method):
    """Sliding regime (mu_s cap < m g): after the transient (relaxation rate
    cap (V^2 - mu_s V w) / (m s^3) > 100 / s here, so 0.3 s is > 30 time
    constants) the speed and the wall force are the closed form's. The
    implicit step is backward Euler in the velocity: its fixed point at a
    constant velocity is the exact force balance, so the steady state is
    exact to rounding and the solver's tolerance. The explicit step
    evaluates the plate friction at the previous velocity, the same one at a
    steady state, and solves the stop rows at the new one: exact there too."""
    w, lam = _wall_closed_form(mu_s)
    assert w > 0
    r = exdex.simulate(_wall_scene(mu_s), t_end=0.3, dt=1e-3, method=method)
    assert r.stats["warnings"] == 0
    np.testing.assert_allclose(r.v[-1, 0], -0.01, rtol=1e-12)
    np.testing.assert_allclose(r.v[-1, 1], -w, rtol=1e-9)
    np.testing.assert_allclose(r.stop_force[-1, 0], lam, rtol=1e-9)


@pytest.mark.parametrize("method", ["implicit", "explicit"])
@pytest.mark.parametrize("mu_s", [0.8, 2.0])
def test_block_dragged_along_frictional_wall_holds_when_wall_friction_carries_weight(mu_s, method):
    """Holding regime (mu_s cap >= m g = 0.981 N, cap = 1.5 N): the block
    does not move down at all; the wall's normal force is the whole plate
    capacity (the slip is purely along x). The sticking contact is an
    equality of the step (slip T v + tb = 0): exact to rounding (the
    vertical velocity is a rounding error of the 0.01 m/s slide). The
    explicit method's first step has no plate friction (it is evaluated at
    the velocity before the step, 0) and so no wall force either: the block
    falls freely for that step, by g dt^2 at most; from then on it holds."""
    w, lam = _wall_closed_form(mu_s)
    assert w == 0.0
    r = exdex.simulate(_wall_scene(mu_s), t_end=0.3, dt=1e-3, method=method)
    assert r.stats["warnings"] == 0
    first = 1 if method == "implicit" else 2
    assert np.all(np.abs(r.v[first:, 1]) <= 1e-15)
    if method == "implicit":
        assert np.all(np.abs(r.q[:, 1]) <= 1e-15)
    else:
        assert np.all(np.abs(r.q[:, 1]) <= 2 * G * 1e-3 ** 2)
    np.testing.assert_allclose(r.stop_force[-1, 0], lam, rtol=1e-12)


def _incline_scene(mu_s, alpha, V, m=0.1, cap=0.5):
    """1-DoF translation along B's y (vertical) with the centre of mass as
    the outline: a point resting on an incline fixed in A, normal n =
    (sin alpha, cos alpha) in the plate plane, while the gripper translates
    along x at speed V (trapezoid with ramps of 0.05 s, then constant)."""
    n = (math.sin(alpha), 0.0, math.cos(alpha))
    return exdex.Scene(
        body=exdex.Body(mass=m), grasp=exdex.Grasp(mu=0.5, grip_force=cap),
        motion=exdex.TrapezoidalProfile(amplitude=math.copysign(V * 0.95, V), duration=1.0, v_max=abs(V),
                                        axis=(1, 0, 0)),
        stops=(exdex.Stop((0.0, 0.0, 0.0), n, mu=mu_s),))


@pytest.mark.parametrize("method", ["implicit", "explicit", "event", "regularised"])
@pytest.mark.parametrize("direction", [1.0, -1.0])
@pytest.mark.parametrize("mu_s", [0.0, 0.4])
def test_1dof_point_on_inclined_frictional_stop_closed_form(mu_s, direction, method):
    """The point follows the incline: its gap n . (V_g + v d) = 0 with d =
    (0, 1) gives v = -tan(alpha) V (kinematics: no friction in it). Its
    slip along t = (-cos a, sin a) is s = t . (V, v) = -V / cos(alpha): the
    gripper moving +x slides it with s < 0, so the stop's friction on it is
    +mu_s lam along t, and the generalised force on the free coordinate is
    lam (n . d) + beta (t . d) = lam (cos a + sigma' mu_s sin a) with sigma'
    = -sign(s). In the constant-speed phase v is constant: the plate
    friction -cap sign(v) (capacity cap = 2 mu F = 0.5 N < m g), gravity -m g
    and the stop balance:
        lam = (m g + cap sign(v)) / (cos a - sign(s) mu_s sin a).
    (Moving down, sign(v) = -1 and sign(s) = -1: (m g - cap) / (cos a + mu_s
    sin a); moving up, (m g + cap) / (cos a - mu_s sin a).) The time-stepping
    methods reach this balance exactly (a constant velocity is their fixed
    point), the event method holds the constraint and the forces exactly.
    The regularised method's plate friction is cap v / sqrt(v^2 + eps^2),
    short of cap by cap (1 - |v| / sqrt(v^2 + eps^2)) <= cap eps^2 / (2 v^2):
    lam is off by that over the stop's direction, which the test allows
    twice of."""
    alpha, V, m, cap, eps = 0.5, 0.05 * direction, 0.1, 0.5, 1e-4
    r = exdex.simulate(_incline_scene(mu_s, alpha, V), t_end=0.5, dt=1e-3, method=method, eps=eps)
    assert r.stats["warnings"] == 0
    v = -math.tan(alpha) * V
    s = -V / math.cos(alpha)
    D = math.cos(alpha) - math.copysign(1.0, s) * mu_s * math.sin(alpha)
    lam = (m * G + cap * math.copysign(1.0, v)) / D
    np.testing.assert_allclose(r.v[-1, 0], v, rtol=1e-12)
    tol = 2 * cap * eps ** 2 / (2 * v ** 2) / D / lam if method == "regularised" else 1e-10
    np.testing.assert_allclose(r.stop_force[-1, 0], lam, rtol=tol)


def test_1dof_incline_jams_beyond_the_friction_angle():
    """Dragged up the incline (s > 0) the stop's generalised force per unit
    normal force is cos a - mu_s sin a: for mu_s > cot(alpha) it is negative,
    so no normal force >= 0 can lift the point along the incline while the
    prescribed gripper motion demands it (a Painleve jam of the velocity
    level too: the motion has no finite-force solution). The step keeps the
    frictionless solution and counts a warning."""
    alpha = 0.5
    mu_s = 1.2 / math.tan(alpha)
    with pytest.warns(exdex.PhysicsWarning, match="soft problem"):
        r = exdex.simulate(_incline_scene(mu_s, alpha, -0.05), t_end=0.3, dt=1e-3)
    assert r.stats["warnings"] > 0


def test_mu_zero_is_the_frictionless_stop_bit_for_bit():
    for scene in (_wall_scene(0.0), _incline_scene(0.0, 0.5, 0.05)):
        plain = exdex.replace(scene, stops=tuple(exdex.Stop(s.point, s.normal) for s in scene.stops))
        a = exdex.simulate(scene, 0.2, 1e-3)
        b = exdex.simulate(plain, 0.2, 1e-3)
        assert np.array_equal(a.q, b.q) and np.array_equal(a.v, b.v)
        assert np.array_equal(a.stop_force, b.stop_force) and np.array_equal(a.wrench, b.wrench)


def test_stop_mu_input_checks():
    with pytest.raises(ValueError, match=r"Stop\.mu must be in \[0, inf\)"):
        exdex.Stop((0, 0, 0), (1, 0, 0), mu=-0.1)
    with pytest.raises(ValueError, match=r"Stop\.mu must be finite"):
        exdex.Stop((0, 0, 0), (1, 0, 0), mu=float("nan"))
    with pytest.raises(TypeError, match=r"Stop\.mu must be a real number"):
        exdex.Stop((0, 0, 0), (1, 0, 0), mu="0.3")  # type: ignore[arg-type]


def test_stop_mu_survives_a_scene_file(tmp_path):
    scene = _wall_scene(0.3)
    for ext in ("toml", "json"):
        path = tmp_path / f"wall.{ext}"
        exdex.save_scene(scene, path)
        assert exdex.load_scene(path) == scene


def _pivot_scene(mu_s, X=0.006, T=0.4, V=0.016):
    """1-DoF rotation about the patch centre (the centre of mass, so gravity
    has no torque about the pin): an outline whose one low corner rho_0 =
    (0.02, -0.02) m (from the pivot, at theta = 0) touches a floor fixed in
    A; the gripper descends along -z_A (B's -y) by X in T, peak speed V
    (trapezoid with ramps), so the floor pushes the corner up and the object
    pivots in the grip against the grip torque C = mu N e_r."""
    m, a = 0.1, 0.04
    izz = m * (a * a + a * a) / 12
    body = exdex.Body(mass=m, inertia=np.diag([izz, izz, izz]),
                      outline=[(0.02, -0.02), (-0.005, 0.01), (0.005, 0.01)])
    patch = exdex.Patch.disc(0.01)
    scene = exdex.Scene(body=body, grasp=exdex.Grasp(mu=0.5, grip_force=1.0, patch=patch),
                        motion=exdex.TrapezoidalProfile(X, T, V, axis=(0, 0, -1)), dof="rotation",
                        stops=(exdex.Stop((0, 0, -0.02), (0, 0, 1), mu=mu_s),))
    return scene, izz, 2 * 0.5 * 1.0 * patch.e_r


@pytest.mark.parametrize("mu_s", [0.0, 0.5, 0.9])
def test_pivoting_on_frictional_floor_corner_closed_form(mu_s):
    """The corner rho = Rz(theta) rho_0 = r (cos(theta + phi), sin(theta +
    phi)) (r = 0.02 sqrt 2, phi = -45 deg) stays on the floor: p_z(t) +
    rho_y = z_floor, so theta(t) = asin((z_floor - p_z(t)) / r) - phi
    (kinematics alone), and in the constant-speed phase omega = V / rho_x,
    omega' = rho_y omega^2 / rho_x (from d rho_x / dt = -rho_y omega).
    Torques about the pin (izz omega' = sum): the plates -C sign(omega)
    (sliding: omega > 0), the floor's normal force lam (up, n = e_y in B)
    with arm G = n . (e_z x rho) = rho_x, and its friction beta along t =
    e_z x n = -e_x with arm T = t . (e_z x rho) = rho_y. The corner slips
    along the floor at s = T omega = rho_y omega < 0, so beta = +mu lam and
        lam = (izz omega' + C) / (rho_x + mu rho_y).
    Friction raises the floor force needed to pivot the object (rho_y < 0).
    The implicit step is first order: the row and the friction direction
    are taken at the step's start, so lam is off by O(dt): by the relative
    change of the arm D = rho_x + mu rho_y over a step, |dD/dtheta| / D
    omega dt (dD/dtheta = -rho_y + mu rho_x), which the test allows twice
    of; and the error must double with dt (first order)."""
    X, T, V = 0.006, 0.4, 0.016
    scene, izz, C = _pivot_scene(mu_s, X, T, V)
    r0, phi = math.hypot(0.02, 0.02), -math.pi / 4
    tr = T - X / V  # ramp time
    A = V / tr

    def p_z(t):
        if t <= tr:
            return -0.5 * A * t * t
        if t <= T - tr:
            return -(0.5 * A * tr * tr + V * (t - tr))
        return -(X - 0.5 * A * (T - t) ** 2)

    errs = []
    for dt in (1e-5, 2e-5):
        r = exdex.simulate(scene, T, dt)
        assert r.stats["warnings"] == 0
        theta = np.array([math.asin((-0.02 - p_z(t)) / r0) - phi for t in r.t])
        np.testing.assert_allclose(r.q[:, 0], theta, atol=1e-12)
        err = 0.0
        for t_s in (0.1, 0.2, 0.3):
            i = int(round(t_s / dt))
            th = r.q[i, 0]
            rho = (r0 * math.cos(th + phi), r0 * math.sin(th + phi))
            om = V / rho[0]
            omd = rho[1] * om * om / rho[0]
            lam = (izz * omd + C) / (rho[0] + mu_s * rho[1])
            bound = 2.0 * abs(-rho[1] + mu_s * rho[0]) / (rho[0] + mu_s * rho[1]) * om * dt
            rel = abs(r.stop_force[i, 0] / lam - 1.0)
            assert rel <= bound, (t_s, rel, bound)
            err = max(err, rel)
        errs.append(err)
    assert 1.6 < errs[1] / errs[0] < 2.4


@pytest.mark.warns_by_design("impact")
def test_pivoting_jams_beyond_the_friction_threshold():
    """The floor can turn the object only while the arm of its reaction,
    rho_x + mu rho_y, is positive: mu < mu* = rho_x / |rho_y| = cot(45 deg -
    theta), 1 at the start. With mu = 1.5 the descending gripper drives the
    corner into the floor with no finite force that pivots it (a jam: the
    step keeps the frictionless solution and counts warnings) until theta
    passes 45 deg - acot(1.5) = 11.3 deg; from there the closed form holds
    again."""
    scene, izz, C = _pivot_scene(1.5)
    with pytest.warns(exdex.PhysicsWarning, match="soft problem"):
        r = exdex.simulate(scene, 0.4, 1e-5)
    assert r.stats["warnings"] > 0
    jam_end = math.pi / 4 - math.atan(1 / 1.5)
    late = r.q[:, 0] > jam_end + 0.02
    assert late.any()
    i = int(np.argmax(late)) + 100
    th = r.q[i, 0]
    r0, phi, V = math.hypot(0.02, 0.02), -math.pi / 4, 0.016
    rho = (r0 * math.cos(th + phi), r0 * math.sin(th + phi))
    om = V / rho[0]
    lam = (izz * rho[1] * om * om / rho[0] + C) / (rho[0] + 1.5 * rho[1])
    np.testing.assert_allclose(r.stop_force[i, 0], lam, rtol=1e-3)


@pytest.mark.warns_by_design("impact", "pad")
@pytest.mark.parametrize("seed", range(12))
def test_frictional_stops_never_add_energy_and_rest_is_exactly_still(seed):
    """A box thrown at a frictional stop (random normal in the plate plane,
    random mu, approach and spin; gripper at rest, no gravity, so no force
    does work but friction and the stops). Each implicit step satisfies
    M (v+ - v) = P + sum (lam_i G_i + beta_i T_i) with the plate impulse P
    dissipative (v+ . P <= 0, maximum dissipation), lam_i G_i v+ = lam_i rhs_i
    <= 0 (complementarity; rhs = -gap / h <= 0 with the gaps kept >= 0 and
    the stop at rest), and beta_i T_i v+ <= 0 (Coulomb opposes the slip,
    which is T_i v+ for a stop at rest). Hence v+ . M (v+ - v) <= 0 and
    |v+|_M <= |v|_M: the kinetic energy never grows. Once the plates hold
    it (v = 0 exactly) nothing moves it again: every later velocity is
    exactly 0."""
    rng = np.random.default_rng(seed)
    a = 0.03
    m = 0.1
    izz = m * (a * a + a * a) / 12
    ang = rng.uniform(0, 2 * np.pi)
    n_b = np.array([math.cos(ang), math.sin(ang)])   # stop normal in B
    d = 0.0215                                        # just beyond the box's reach (half-diagonal 21.2 mm)
    point_b = -d * n_b
    speed = rng.uniform(0.2, 0.4)
    tang = np.array([-n_b[1], n_b[0]])
    v_b = -speed * n_b + rng.uniform(-1, 1) * speed * tang   # toward the stop, with a slide
    scene = exdex.Scene(
        body=exdex.Body.box(m, (a, a, 0.02)),
        grasp=exdex.Grasp(mu=0.2, grip_force=rng.uniform(1.0, 2.0), patch=exdex.Patch.rectangle(0.01, 0.01)),
        dof="planar", gravity=(0.0, 0.0, 0.0),
        q0=(0.0, 0.0, rng.uniform(-0.5, 0.5)), v0=(v_b[0], v_b[1], rng.uniform(-5, 5)),
        # B (x, y) is A (x, z) with the default gripper rotation
        stops=(exdex.Stop((point_b[0], 0.0, point_b[1]), (n_b[0], 0.0, n_b[1]), mu=rng.uniform(0.0, 1.5)),))
    r = exdex.simulate(scene, 0.5, 1e-3)
    ke = 0.5 * (m * (r.v[:, 0] ** 2 + r.v[:, 1] ** 2) + izz * r.v[:, 2] ** 2)
    assert np.all(np.diff(ke) <= 1e-12 * ke[0])
    still = np.flatnonzero(np.all(r.v == 0.0, axis=1)[1:]) + 1
    assert still.size, "the plates should stop it within 0.5 s"
    assert np.all(r.v[still[0]:] == 0.0)
    assert r.stats["warnings"] == 0
    assert r.stop_force.max() > 0  # the stop acted


@pytest.mark.parametrize("mu_s", [0.3, 0.8])
def test_stepper_with_frictional_stops_is_bit_identical_and_branches_exactly(mu_s):
    """Stepping a frictional-stop scene reproduces simulate bit for bit, and
    a saved state restored into another stepper of the same model (whose
    own last contact modes differ: it has not run) continues exactly as the
    original: the friction solve's warm start is part of the state."""
    _stepping_is_simulate_and_a_restore_continues(_wall_scene(mu_s), 200, 1e-3)


def _stepping_is_simulate_and_a_restore_continues(scene, n, dt, **options):
    """n steps of dt reproduce simulate(scene, n dt, dt) bit for bit (q, v,
    stop forces), and a state saved after n / 2 steps and restored into
    another stepper of the same model (which has not run) continues as the
    original for 0.3 n steps, under the grip force 1.5 - 0.005 i N at step i."""
    res = exdex.simulate(scene, n * dt, dt, **options)
    st = exdex.Stepper(scene, **options)
    steps = [st.step(dt) for _ in range(n)]
    assert np.array_equal(np.array([s.q for s in steps]), res.q[1:])
    assert np.array_equal(np.array([s.v for s in steps]), res.v[1:])
    assert np.array_equal(np.array([s.stop_force for s in steps]).reshape(n, -1), res.stop_force[1:])
    model = exdex.Model(scene, **options)
    a, b = exdex.Stepper(model), exdex.Stepper(model)
    for _ in range(n // 2):
        a.step(dt)
    snap = a.save()
    first = [a.step(dt, 1.5 - 0.005 * i) for i in range(3 * n // 10)]
    b.restore(snap)
    again = [b.step(dt, 1.5 - 0.005 * i) for i in range(3 * n // 10)]
    for x, y in zip(first, again):
        assert np.array_equal(x.q, y.q) and np.array_equal(x.v, y.v) and np.array_equal(x.stop_force, y.stop_force)


def _incline_block(mu_s, cap, alpha=0.4, m=0.1, a=0.03):
    """A square block (side a) resting with a face flush on an inclined
    floor (a stop through the face, in-plane normal n = (-sin a, cos a),
    the block turned by alpha to match), gripper at rest, gravity -y in B;
    plate capacity cap = 2 mu F (mu = 0.5: F = cap)."""
    n_b = np.array([-math.sin(alpha), math.cos(alpha)])
    p_b = -0.5 * a * n_b
    return exdex.Scene(body=exdex.Body.box(m, (a, a, 0.02)),
                       grasp=exdex.Grasp(mu=0.5, grip_force=cap, patch=exdex.Patch.rectangle(0.01, 0.01)),
                       dof="planar", q0=(0.0, 0.0, alpha),
                       stops=(exdex.Stop((p_b[0], 0.0, p_b[1]), (n_b[0], 0.0, n_b[1]), mu=mu_s),))


def _incline_run_is_the_closed_form(r, mu_s, cap, rests, alpha=0.4, m=0.1):
    """A 0.2 s run r of _incline_block(mu_s, cap) with no warnings: at rest
    exactly still (v = 0 bit for bit, stick at every sample) with the
    creeping plates' split (test_rest_on_a_frictional_incline_is_the_creep_
    limit): the stop's normal force m g cos(alpha); sliding,
    the constant acceleration g sin(alpha) - mu_s g cos(alpha) - cap / m
    from rest, the stop's normal force m g cos(alpha), no turn."""
    assert r.stats["warnings"] == 0
    if rests:
        assert np.all(r.v == 0.0) and np.all(r.stick[1:])
        np.testing.assert_allclose(r.stop_force[-1, 0], m * G * math.cos(alpha), rtol=1e-12)
    else:
        acc = G * math.sin(alpha) - mu_s * G * math.cos(alpha) - cap / m
        np.testing.assert_allclose(np.hypot(r.v[-1, 0], r.v[-1, 1]), acc * 0.2, rtol=1e-9)
        np.testing.assert_allclose(r.stop_force[-1, 0], m * G * math.cos(alpha), rtol=1e-9)
        assert abs(r.v[-1, 2]) <= 1e-12


INCLINE_CASES = [(0.5, 0.01, True), (0.2, 0.21, True), (0.2, 0.18, False), (0.0, 0.40, True), (0.0, 0.37, False),
                 (0.2, 0.199, False), (0.2, 0.2005, False), (0.2, 0.203, True)]


@pytest.mark.parametrize("mu_s, cap, rests", INCLINE_CASES)
@pytest.mark.parametrize("method", ["implicit", "event"])
def test_rest_on_a_frictional_incline_is_the_creep_limit(method, mu_s, cap, rests):
    """A block flush on a frictional incline (alpha = 0.4 from the
    horizontal, phi = atan(mu_s)) held by the plates. Static splits of the
    weight over the plates and the stop's cone are not unique; the methods
    take the limit of a plate that creeps under its load (its slip along
    the normal of the limit surface, as the regularised method's band
    does). The stop blocks every creep into it, so the plates' reaction
    lies along the incline, the stop's normal force is m g cos(alpha) and
    its friction at most mu_s m g cos(alpha) (kinetic against the creep
    down the incline; the contact resultant passes through the centre of
    mass, the two corners sharing it, so the plates need no torque). The
    block rests iff
        m g (sin alpha - mu_s cos alpha) <= cap,
    above the least-friction split's need m g sin(alpha - phi) by 1 / cos
    phi (that split has the plates press the block into the stop, which a
    plate that can only creep along the incline cannot do). At rest it is
    exactly still (v = 0 bit for bit); below the need it slides with
    the normal force m g cos(alpha), friction mu_s m g cos(alpha) and the
    plates' cap against it:
        a = g sin(alpha) - mu_s g cos(alpha) - cap / m,
    which backward Euler and the event method reproduce exactly for a
    constant force (v = a t). The cases cap = 0.199, 0.2005 lie between the
    two needs, where the least-friction split would rest. The regularised
    method at eps = 1e-6 (an independent law: the smoothed plate, no rest
    test) must give the same verdict: at rest below 1e-4 m/s (it creeps
    at O(eps)), sliding within 1e-4 m/s of the closed form's speed a t (at
    least 1.6e-3 m/s here; the band's lag at the breakaway, about 2e-5 m/s,
    is below it)."""
    alpha, m = 0.4, 0.1
    need = max(m * G * (math.sin(alpha) - mu_s * math.cos(alpha)), 0.0)
    assert (need <= cap) == rests
    _incline_run_is_the_closed_form(exdex.simulate(_incline_block(mu_s, cap), 0.2, 1e-3, method=method), mu_s, cap,
                                    rests)
    g = exdex.simulate(_incline_block(mu_s, cap), 0.2, 1e-3, method="regularised", eps=1e-6)
    speed = np.hypot(g.v[-1, 0], g.v[-1, 1])
    if rests:
        assert speed <= 1e-4
    else:
        acc = G * math.sin(alpha) - mu_s * G * math.cos(alpha) - cap / m
        assert acc * 0.2 > 1e-3 and abs(speed - acc * 0.2) <= 1e-4


@pytest.mark.parametrize("mu_s", [0.0, 0.5, 0.9])
def test_event_pivoting_on_frictional_floor_matches_the_closed_form_to_rounding(mu_s):
    """The event method holds the corner on the floor exactly and integrates
    the stop force lam(t) (closed form above, as a function of time through
    theta(t)); its output is lam's mean over each output interval, which
    Simpson's rule on the closed form gives to dt^4 / 2880 times the fourth
    derivative of lam, far below the 1e-9 allowed. theta matches the
    kinematics to rounding."""
    X, T, V = 0.006, 0.4, 0.016
    scene, izz, C = _pivot_scene(mu_s, X, T, V)
    r0, phi = math.hypot(0.02, 0.02), -math.pi / 4
    tr = T - X / V
    A = V / tr

    def p_z(t):
        if t <= tr:
            return -0.5 * A * t * t
        if t <= T - tr:
            return -(0.5 * A * tr * tr + V * (t - tr))
        return -(X - 0.5 * A * (T - t) ** 2)

    def theta(t):
        return math.asin((-0.02 - p_z(t)) / r0) - phi

    def lam(t):
        th = theta(t)
        rho = (r0 * math.cos(th + phi), r0 * math.sin(th + phi))
        om = V / rho[0]
        return (izz * rho[1] * om * om / rho[0] + C) / (rho[0] + mu_s * rho[1])

    dt = 1e-3
    r = exdex.simulate(scene, T, dt, method="event")
    assert r.stats["warnings"] == 0
    np.testing.assert_allclose(r.q[:, 0], [theta(t) for t in r.t], atol=1e-12)
    for t_s in (0.1, 0.2, 0.3):
        i = int(round(t_s / dt))
        a, b = r.t[i - 1], r.t[i]
        mean = (lam(a) + 4 * lam(0.5 * (a + b)) + lam(b)) / 6
        np.testing.assert_allclose(r.stop_force[i, 0], mean, rtol=1e-9)


def test_event_pivoting_jam_is_reported():
    """Beyond the friction threshold (mu = 1.5 > mu* = 1) the acceleration-
    level contact has no solution: the event method takes it frictionless
    and counts a warning."""
    scene, _, _ = _pivot_scene(1.5)
    with pytest.warns(exdex.PhysicsWarning, match="soft problem"):
        r = exdex.simulate(scene, 0.4, 1e-3, method="event")
    assert r.stats["warnings"] > 0


def _random_incline_scene(seed):
    rng = np.random.default_rng(seed)
    alpha = rng.uniform(-0.7, 0.7)
    return exdex.Scene(
        body=exdex.Body(mass=0.1), grasp=exdex.Grasp(mu=0.5, grip_force=rng.uniform(0.2, 1.5)),
        motion=exdex.AsymmetricProfile(rng.uniform(0.02, 0.08), 0.4, rng.uniform(0.6, 0.9),
                                       axis=(rng.uniform(-1, 1), 0, rng.uniform(-1, 0.3))),
        stops=(exdex.Stop((0.0, 0.0, -rng.uniform(0, 0.01)), (math.sin(alpha), 0.0, math.cos(alpha)),
                          mu=rng.uniform(0.0, 1.0)),))


@pytest.mark.warns_by_design("impact", "pad", "outline", "solver", "jump")
@pytest.mark.parametrize("seed", range(8))
def test_methods_agree_on_random_1dof_frictional_stop_scenes(seed):
    """Seeded 1-DoF scenes: a point falling onto an incline (random angle
    and mu) while the gripper makes an Eq. 7 round trip in a random
    direction. The event method (rtol 1e-10) is the reference. The implicit
    and explicit methods are first-order time steppings (the implicit one
    second order in smooth phases): their largest deviation over the run
    must shrink by at least 0.6 when dt halves, unless it is already at
    rounding (1e-15 m: a point held on the incline follows the stop's
    kinematics exactly in every method)."""
    sc = _random_incline_scene(seed)
    ev = exdex.simulate(sc, 0.8, 1e-3, method="event", rtol=1e-10, atol=1e-12)
    assert ev.stats["warnings"] == 0
    for method in ("implicit", "explicit"):
        err = []
        for k, dt in ((1, 1e-3), (2, 5e-4)):
            r = exdex.simulate(sc, 0.8, dt, method=method)
            assert r.stats["warnings"] == 0
            err.append(np.abs(r.q[::k, 0] - ev.q[:, 0]).max())
        assert err[1] <= 1e-15 or err[1] <= 0.6 * err[0], (method, err)


# ------------------------------------------------ planar: event and regularised

@pytest.mark.warns_by_design("impact")  # the object starts in contact, approaching the wall at t = 0
@pytest.mark.parametrize("mu_s", [0.0, 0.3, 0.5])
def test_event_block_dragged_along_frictional_wall_sliding_closed_form(mu_s):
    """The sliding regime of the wall closed form (_wall_closed_form) with
    the event method: the wall's rows slide (both flush corners on one
    stop, one friction force shared in proportion to their normal forces),
    the plates slide by the sliding law; the steady state is an exact
    equilibrium of those equations, reached to the integration tolerance
    (rtol 1e-10) after > 30 relaxation times."""
    w, lam = _wall_closed_form(mu_s)
    r = exdex.simulate(_wall_scene(mu_s), t_end=0.3, dt=1e-3, method="event", rtol=1e-10, atol=1e-12)
    assert r.stats["warnings"] == 0
    np.testing.assert_allclose(r.v[-1, 0], -0.01, rtol=1e-12)
    np.testing.assert_allclose(r.v[-1, 1], -w, rtol=1e-9)
    np.testing.assert_allclose(r.stop_force[-1, 0], lam, rtol=1e-9)


@pytest.mark.warns_by_design("impact")  # the object starts in contact, approaching the wall at t = 0
@pytest.mark.parametrize("mu_s", [0.8, 2.0])
def test_event_block_dragged_along_frictional_wall_holds(mu_s):
    """The holding regime (mu_s cap >= m g) with the event method: the
    wall's friction sticks from the start (the slip along it is 0 and the
    cone holds the weight), so the block never moves down: its vertical
    velocity and position are rounding errors of the 0.01 m/s slide, the
    wall force is the whole capacity."""
    w, lam = _wall_closed_form(mu_s)
    assert w == 0.0
    r = exdex.simulate(_wall_scene(mu_s), t_end=0.3, dt=1e-3, method="event", rtol=1e-10, atol=1e-12)
    assert r.stats["warnings"] == 0
    assert np.all(np.abs(r.v[:, 1]) <= 1e-15)
    assert np.all(np.abs(r.q[:, 1]) <= 1e-15)
    np.testing.assert_allclose(r.stop_force[-1, 0], lam, rtol=1e-12)


@pytest.mark.warns_by_design("impact")  # the object starts in contact, approaching the wall at t = 0
@pytest.mark.parametrize("mu_s", [0.3, 0.5])
def test_regularised_block_dragged_along_frictional_wall_converges_in_eps(mu_s):
    """The regularised method smooths only the plate friction, cap (V, w) /
    sqrt(V^2 + w^2 + eps^2) (the stop's friction stays exact Coulomb): the
    steady speed moves off the closed form by O(eps^2 / s^2) and the error
    must fall by at least 50x per factor 10 in eps (second order: 100x),
    from below 1e-6 relative at eps = 1e-4."""
    w, lam = _wall_closed_form(mu_s)
    errs = []
    for eps in (1e-4, 1e-5):
        r = exdex.simulate(_wall_scene(mu_s), t_end=0.3, dt=1e-3, method="regularised", eps=eps,
                           rtol=1e-10, atol=1e-12)
        assert r.stats["warnings"] == 0
        np.testing.assert_allclose(r.v[-1, 0], -0.01, rtol=1e-12)
        errs.append(abs(-r.v[-1, 1] / w - 1.0) + abs(r.stop_force[-1, 0] / lam - 1.0))
    assert errs[0] < 1e-3 and errs[1] < errs[0] / 50, errs


@pytest.mark.warns_by_design("impact")  # the object starts in contact, approaching the wall at t = 0
@pytest.mark.parametrize("mu_s", [0.8, 2.0])
def test_regularised_block_dragged_along_frictional_wall_holds(mu_s):
    """Holding regime, regularised: the wall sticks exactly (w = 0), so the
    plates slip purely along x at V and carry cap V / sqrt(V^2 + eps^2),
    which the wall's normal force balances: lam = cap V / sqrt(V^2 +
    eps^2) (the exact closed form of the smoothed law)."""
    V, cap, eps = 0.01, 1.5, 1e-4
    r = exdex.simulate(_wall_scene(mu_s), t_end=0.3, dt=1e-3, method="regularised", eps=eps,
                       rtol=1e-10, atol=1e-12)
    assert r.stats["warnings"] == 0
    assert np.all(np.abs(r.v[:, 1]) <= 1e-15)
    np.testing.assert_allclose(r.stop_force[-1, 0], cap * V / math.hypot(V, eps), rtol=1e-9)


@pytest.mark.parametrize("mu_s, cap", [(0.2, 0.21), (0.2, 0.18), (0.0, 0.37)])
def test_regularised_on_a_frictional_incline_converges_in_eps(mu_s, cap):
    """Regularised on the incline: the smoothed plate friction cannot hold
    the block still, so it creeps (or slides) down the incline and the
    stop's friction is kinetic, mu_s lam, with lam = m g cos(alpha) (the
    plate friction opposes the slip, along the incline: no normal part).
    Creeping (cap above the need m g (sin alpha - mu_s cos alpha)), the
    speed is O(eps) and the normal force is m g cos(alpha) (the limit of
    the smoothed law, which the exact methods' rest takes too: static
    splits are not unique, the creep picks this one); sliding, the speed tends to the
    closed form's a t, and its error must fall at least 5x per factor 10
    in eps."""
    alpha, m = 0.4, 0.1
    acc = G * math.sin(alpha) - mu_s * G * math.cos(alpha) - cap / m
    errs = []
    for eps in (1e-4, 1e-5):
        r = exdex.simulate(_incline_block(mu_s, cap), 0.2, 1e-3, method="regularised", eps=eps)
        assert r.stats["warnings"] == 0
        np.testing.assert_allclose(r.stop_force[-1, 0], m * G * math.cos(alpha), rtol=1e-9)
        speed = np.hypot(r.v[-1, 0], r.v[-1, 1])
        if acc < 0:
            assert speed <= 20 * eps
        else:
            errs.append(abs(speed / (acc * 0.2) - 1.0))
    if errs:
        assert errs[1] < errs[0] / 5, errs


def _thrown_box(seed):
    """The box thrown at a frictional stop of
    test_frictional_stops_never_add_energy_and_rest_is_exactly_still."""
    rng = np.random.default_rng(seed)
    a, m = 0.03, 0.1
    ang = rng.uniform(0, 2 * np.pi)
    n_b = np.array([math.cos(ang), math.sin(ang)])
    point_b = -0.0215 * n_b
    speed = rng.uniform(0.2, 0.4)
    tang = np.array([-n_b[1], n_b[0]])
    v_b = -speed * n_b + rng.uniform(-1, 1) * speed * tang
    return exdex.Scene(
        body=exdex.Body.box(m, (a, a, 0.02)),
        grasp=exdex.Grasp(mu=0.2, grip_force=rng.uniform(1.0, 2.0), patch=exdex.Patch.rectangle(0.01, 0.01)),
        dof="planar", gravity=(0.0, 0.0, 0.0),
        q0=(0.0, 0.0, rng.uniform(-0.5, 0.5)), v0=(v_b[0], v_b[1], rng.uniform(-5, 5)),
        stops=(exdex.Stop((point_b[0], 0.0, point_b[1]), (n_b[0], 0.0, n_b[1]), mu=rng.uniform(0.0, 1.5)),))


@pytest.mark.warns_by_design("impact", "pad")
@pytest.mark.parametrize("seed", range(12))
def test_event_frictional_stop_never_adds_energy_and_rest_is_exactly_still(seed):
    """The thrown box with the event method: its impacts are plastic and
    frictionless (an M-metric projection onto the no-approach rows, which
    contain v = 0: the kinetic energy cannot grow), then the plates' and
    the stop's Coulomb forces oppose the slips (each does negative work),
    and a sticking stop's slip is projected to 0 (again onto a set holding
    v = 0). Hence the kinetic energy never grows, to rounding; once the
    plates hold the box (v = 0 exactly) it stays still."""
    a, m = 0.03, 0.1
    izz = m * (a * a + a * a) / 12
    r = exdex.simulate(_thrown_box(seed), 0.5, 1e-3, method="event")
    ke = 0.5 * (m * (r.v[:, 0] ** 2 + r.v[:, 1] ** 2) + izz * r.v[:, 2] ** 2)
    assert np.all(np.diff(ke) <= 1e-12 * ke[0])
    still = np.flatnonzero(np.all(r.v == 0.0, axis=1)[1:]) + 1
    assert still.size, "the plates should stop it within 0.5 s"
    assert np.all(r.v[still[0]:] == 0.0) and np.all(r.stick[still[0] + 1:])
    assert r.stats["warnings"] == 0
    assert r.stop_force.max() > 0


@pytest.mark.warns_by_design("impact")  # the object starts in contact, approaching the wall at t = 0
@pytest.mark.parametrize("method", ["event", "regularised"])
def test_planar_mu_zero_is_the_frictionless_stop_bit_for_bit(method):
    scene = _wall_scene(0.0)
    plain = exdex.replace(scene, stops=tuple(exdex.Stop(s.point, s.normal) for s in scene.stops))
    a = exdex.simulate(scene, 0.2, 1e-3, method=method)
    b = exdex.simulate(plain, 0.2, 1e-3, method=method)
    assert np.array_equal(a.q, b.q) and np.array_equal(a.v, b.v)
    assert np.array_equal(a.stop_force, b.stop_force) and np.array_equal(a.wrench, b.wrench)
    assert a.stats == b.stats


@pytest.mark.warns_by_design("impact")  # the object starts in contact, approaching the wall at t = 0
@pytest.mark.parametrize("method", ["event", "regularised"])
@pytest.mark.parametrize("mu_s", [0.3, 0.8])
def test_planar_hybrid_stepper_with_frictional_stops_is_bit_identical(mu_s, method):
    """The stops' friction modes are part of the hybrid state: stepping
    reproduces simulate bit for bit, and a restored state continues as the
    original."""
    _stepping_is_simulate_and_a_restore_continues(_wall_scene(mu_s), 100, 1e-3, method=method)


def _random_planar_incline_scene(seed):
    """A square block resting with a face flush on a frictional incline
    (random angle within +-0.5 rad, mu 0.1..1, plate capacity 0.1..1 N)
    while the gripper makes an Eq. 7 round trip in a random direction of
    the plate plane: the block sticks and slides along the incline, and a
    corner lifts off and lands again (2 to 8 impacts per run, at small
    tangential slips: the event method's impacts are frictionless, the
    implicit method's frictional, which these scenes do not tell apart)."""
    rng = np.random.default_rng([seed, 77])
    alpha = rng.uniform(-0.5, 0.5)
    a, m = 0.03, 0.1
    n_b = np.array([-math.sin(alpha), math.cos(alpha)])
    p_b = -0.5 * a * n_b
    ang = rng.uniform(0, 2 * np.pi)
    return exdex.Scene(body=exdex.Body.box(m, (a, a, 0.02)),
                       grasp=exdex.Grasp(mu=0.5, grip_force=rng.uniform(0.1, 1.0),
                                         patch=exdex.Patch.rectangle(0.01, 0.01)),
                       dof="planar", q0=(0.0, 0.0, alpha),
                       motion=exdex.AsymmetricProfile(rng.uniform(0.01, 0.04), 0.3, rng.uniform(0.6, 0.9),
                                                      axis=(math.cos(ang), 0, math.sin(ang))),
                       stops=(exdex.Stop((p_b[0], 0.0, p_b[1]), (n_b[0], 0.0, n_b[1]),
                                         mu=rng.uniform(0.1, 1.0)),))


@pytest.mark.warns_by_design("impact", "pad", "outline", "solver", "jump")
@pytest.mark.parametrize("seed", range(8))
def test_event_and_implicit_agree_on_random_planar_frictional_stop_scenes(seed):
    """Two independent formulations of the same Coulomb contact: the event
    method (acceleration-level modes, located switches, rtol 1e-10) and the
    implicit method (velocity-level complementarity per step, first order
    in dt). The implicit error against the event run must halve with dt
    (ratio <= 0.6), and its Richardson extrapolation 2 q(h/4) - q(h/2) must
    lie closer to the event run than q(h/2) by at least 5x: the two
    converge to the same motion (q over the whole run, every sample)."""
    sc = _random_planar_incline_scene(seed)
    ev = exdex.simulate(sc, 0.8, 1e-3, method="event", rtol=1e-10, atol=1e-12)
    assert ev.stats["warnings"] == 0
    q = {}
    for k in (1, 2, 4):
        r = exdex.simulate(sc, 0.8, 1e-3 / k, method="implicit")
        assert r.stats["warnings"] == 0
        q[k] = r.q[::k]
    e1, e2 = np.abs(q[1] - ev.q).max(), np.abs(q[2] - ev.q).max()
    ext = np.abs(2 * q[4] - q[2] - ev.q).max()
    assert e2 <= 0.6 * e1, (e1, e2)
    assert ext <= 0.2 * e2, (ext, e2)


# ------------------------------------------- planar: a block in a corner

def _corner_scene(mu_w, mu_f, V=0.01, **kw):
    """_wall_scene with a floor: a frictional stop fixed in A at z = -a/2
    (normal +z), flush under the block's bottom face from t = 0, so the
    block sits in the corner of the wall and the floor while the gripper
    drives it toward the wall at V."""
    sc = _wall_scene(mu_w, V=V, **kw)
    return exdex.replace(sc, stops=sc.stops + (exdex.Stop((0.0, 0.0, -0.015), (0.0, 0.0, 1.0), mu=mu_f),))


@pytest.mark.warns_by_design("impact")
@pytest.mark.parametrize("method", ["event", "regularised", "implicit"])
@pytest.mark.parametrize("V", [0.001, 0.01, 0.02])
@pytest.mark.parametrize("mu_w", [0.0, 0.3, 0.5, 2.0])
def test_block_held_in_frictional_corner_stays_at_rest(mu_w, V, method):
    """The gripper slides toward the wall past a block that sits in the
    corner of the wall and a floor (both frictional, the floor mu 0.4).
    The block stays at rest in A: its plate slip is the pure translation
    (V, 0) in B, so the plates push it toward the wall with the force cap
    (the regularised law: cap V / sqrt(V^2 + eps^2)) and no moment; the
    wall's normal force balances that force and the floor's the weight m g
    (0.981 N), both through the centre (each face's two corners share its
    force equally), with no friction needed at either stop: a split inside
    every cone, so the block is wedged (a lock: the three touching rows and
    the sticking stops fix its acceleration at 0). In B it moves at -V:
    q(t) = q0 - (V t, 0, 0), v = (-V, 0, 0) at every sample (to 1e-12 m
    and 1e-13 m/s: the event and regularised methods' integration
    tolerance, the implicit step's complementarity solve). With mu_w <
    m g / cap the block alone against the wall slides down (the wall scenes
    above); the floor holds it. A method that cannot describe the lock
    (its stops' slips exactly 0 at every instant) may decide the stops'
    friction from the slips' rounding and toggle without end."""
    r = exdex.simulate(_corner_scene(mu_w, 0.4, V=V), t_end=0.3, dt=1e-3, method=method, rtol=1e-10,
                       atol=1e-12)
    assert r.stats["warnings"] == 0
    q0 = np.array([0.1 - 0.015, 0.0, 0.0])
    np.testing.assert_allclose(r.q[:, 0], q0[0] - V * r.t, rtol=0, atol=1e-12)
    assert np.all(np.abs(r.q[:, 1:]) <= 1e-12)
    np.testing.assert_allclose(r.v[1:, 0], -V, rtol=0, atol=1e-13)
    assert np.all(np.abs(r.v[:, 1:]) <= 1e-12)


def _accel_corner_scene(mu_w, phi, Ag=2.0, T=0.2, m=0.1, a=0.03):
    """A square block (side a, mass m) flush in the corner of a wall (x =
    0.1, normal -x, mu_w) and a floor (z = -a/2, normal +z, mu 0.4) while
    the gripper accelerates from rest at Ag along (cos phi, sin phi) in the
    plate plane (a trapezoid whose ramps take half its duration: constant
    acceleration up to T / 2). Plate capacity 2 mu F = 1.5 N."""
    X = Ag * T * T / 4.0
    return exdex.Scene(body=exdex.Body.box(m, (a, a, 0.02)),
                       grasp=exdex.Grasp(mu=0.5, grip_force=1.5, patch=exdex.Patch.rectangle(0.02, 0.02)),
                       motion=exdex.TrapezoidalProfile(amplitude=X, duration=T, v_max=2.0 * X / T,
                                                       axis=(math.cos(phi), 0.0, math.sin(phi))),
                       dof="planar", q0=(0.1 - a / 2, 0.0, 0.0),
                       stops=(exdex.Stop((0.1, 0.0, 0.0), (-1.0, 0.0, 0.0), mu=mu_w),
                              exdex.Stop((0.0, 0.0, -a / 2), (0.0, 0.0, 1.0), mu=0.4)))


def _accel_corner_closed_form(mu_w, phi, Ag=2.0, m=0.1, cap=1.5):
    """The block's upward acceleration kappa along the wall (0: it stays).

    The gripper's velocity Ag t (c, s) (c = cos phi > 0: toward the wall)
    leaves the block behind: the plates slip past it and push it with cap
    along the slip, a pure force (a translation slip). At rest in A that
    force is cap (c, s): the wall takes cap c, and the rest of the load, m g
    - cap s downward, goes to the floor when it is >= 0 (no friction needed:
    the block stays, wedged). When cap s > m g the floor cannot pull: the
    wall's friction must hold cap s - m g <= mu_w cap c (Coulomb), or the
    block slides up the wall off the floor (for mu_w < 1 the friction's
    moment about the centre stays within what the wall's two corners carry,
    so it does not tip). Sliding at u(t) in A, the slip is t (Ag c, Ag s -
    u / t): with u = kappa t the direction is constant (self-similar, the
    solution from rest: w = u / t obeys t dw/dt = f(w) / m with f
    decreasing through its root), sigma = s - kappa / Ag, and
        m kappa = cap (sigma - mu_w c) / sqrt(c^2 + sigma^2) - m g,
    the wall's normal force cap c / sqrt(c^2 + sigma^2) times mu_w opposing
    the slide. f(0) > 0 in the sliding case and f(Ag s) < 0: one root."""
    from scipy.optimize import brentq
    c, s = math.cos(phi), math.sin(phi)
    if cap * s - m * G <= mu_w * cap * c:
        return 0.0

    def f(k):
        sig = s - k / Ag
        return cap * (sig - mu_w * c) / math.hypot(c, sig) - m * G - m * k
    return brentq(f, 0.0, Ag * s, xtol=1e-15, rtol=1e-15)


@pytest.mark.warns_by_design("impact")
@pytest.mark.parametrize("phi_deg", [-30.0, 30.0, 60.0, 75.0])
@pytest.mark.parametrize("mu_w", [0.0, 0.2, 0.5, 0.9])
def test_block_in_corner_under_constant_gripper_acceleration_closed_form(mu_w, phi_deg):
    """_accel_corner_closed_form: the block stays wedged (kappa = 0) or
    slides up the wall at kappa t, so in B (the gripper displaced by Ag t^2
    / 2 (c, s)) q = q0 + (-Ag c, kappa - Ag s) t^2 / 2, theta = 0. The event
    method holds it to the integration tolerance; the implicit step is exact
    for the wedged block and converges to the slide (its error must fall by
    at least 0.6 per halving of dt)."""
    phi, Ag = math.radians(phi_deg), 2.0
    kappa = _accel_corner_closed_form(mu_w, phi)
    sc = _accel_corner_scene(mu_w, phi)

    def err(r):
        qx = 0.085 - 0.5 * Ag * math.cos(phi) * r.t ** 2
        qy = 0.5 * (kappa - Ag * math.sin(phi)) * r.t ** 2
        return max(np.abs(r.q[:, 0] - qx).max(), np.abs(r.q[:, 1] - qy).max(), 0.03 * np.abs(r.q[:, 2]).max())
    ev = exdex.simulate(sc, 0.1, 1e-3, method="event", rtol=1e-10, atol=1e-12)
    assert ev.stats["warnings"] == 0
    assert err(ev) <= 1e-11
    e = [err(exdex.simulate(sc, 0.1, dt, method="implicit")) for dt in (1e-3, 5e-4)]
    if kappa == 0.0:
        assert max(e) <= 1e-15
    else:
        assert e[1] <= 0.6 * e[0] and e[0] <= 1e-6, e


def _random_corner_scene(seed):
    """A rectangular block (sides 15..40 mm, 50..300 g) flush on a floor
    tilted by up to 0.4 rad and touching a wall at 90 deg +- 0.4 rad to it
    (the corner's angle; 30 % of the corners square), both frictional (mu
    0..1.5), the corner fixed in A; the gripper (plate capacity 0.08..4 N)
    drives the block into the corner at a speed V from 1e-4 to 0.1 m/s: along
    the floor toward the wall, or into the corner within +-0.6 rad, the
    velocity jumping to V at t = 0 or ramping up, or by turning about a
    point 5..10 cm from the corner at V / r (30 %); it stops at t = 0.5 s."""
    rng = np.random.default_rng([seed, 31])
    a, b = rng.uniform(0.015, 0.04, 2)
    m = rng.uniform(0.05, 0.3)
    mu_w, mu_f = rng.uniform(0.0, 1.5, 2)
    V = 10.0 ** rng.uniform(-4.0, -1.0)
    alpha = rng.uniform(-0.4, 0.4)
    beta = alpha + rng.uniform(-0.4, 0.4) * (rng.uniform() < 0.7)
    n_f = np.array([math.sin(alpha), math.cos(alpha)])
    n_w = np.array([-math.cos(beta), math.sin(beta)])
    P = np.array([0.02, -0.02])
    c, s = math.cos(alpha), math.sin(alpha)
    verts = [np.array([c * x - s * y, s * x + c * y])
             for x, y in ((a / 2, b / 2), (-a / 2, b / 2), (-a / 2, -b / 2), (a / 2, -b / 2))]
    # the centre whose least gap to each stop is 0
    C = np.linalg.solve(np.array([n_w, n_f]), [n_w @ P - min(n_w @ v for v in verts),
                                               n_f @ P - min(n_f @ v for v in verts)])
    T = 0.5
    if rng.uniform() < 0.3:
        r = rng.uniform(0.05, 0.1)
        ang = rng.uniform(0, 2 * np.pi)
        ctr = P + r * np.array([math.cos(ang), math.sin(ang)])
        motion = exdex.TrapezoidalProfile(amplitude=rng.choice([-1.0, 1.0]) * 0.9 * V / r * T, duration=T,
                                          v_max=V / r, axis=(0.0, 1.0, 0.0), rotation=True,
                                          center=(ctr[0], 0.0, ctr[1]))
    else:
        if rng.uniform() < 0.5:
            d = np.array([n_f[1], -n_f[0]])
            d = d if d @ n_w < 0 else -d
        else:
            d = -(n_w + n_f) / np.linalg.norm(n_w + n_f)
            phi = rng.uniform(-0.6, 0.6)
            d = np.array([math.cos(phi) * d[0] - math.sin(phi) * d[1], math.sin(phi) * d[0] + math.cos(phi) * d[1]])
        motion = exdex.TrapezoidalProfile(amplitude=(1.0 if rng.uniform() < 0.5 else 0.9) * V * T, duration=T,
                                          v_max=V, axis=(d[0], 0.0, d[1]))
    return exdex.Scene(body=exdex.Body.box(m, (a, b, 0.02)),
                       grasp=exdex.Grasp(mu=rng.uniform(0.2, 1.0), grip_force=rng.uniform(0.2, 2.0),
                                         patch=exdex.Patch.rectangle(0.01, 0.01)),
                       dof="planar", q0=(C[0], C[1], alpha), motion=motion,
                       stops=(exdex.Stop((P[0], 0.0, P[1]), (n_w[0], 0.0, n_w[1]), mu=mu_w),
                              exdex.Stop((P[0], 0.0, P[1]), (n_f[0], 0.0, n_f[1]), mu=mu_f)))


# plausibility: the random masses and sizes are drawn apart (densities of any size)
@pytest.mark.warns_by_design("impact", "pad", "outline", "solver", "jump", "plausibility")
@pytest.mark.parametrize("seed", range(24))
def test_event_and_regularised_return_on_random_corner_scenes_and_agree_with_the_implicit_ladder(seed):
    """_random_corner_scene: the event and regularised methods return (no
    EXDEX_ENOCONV from mode switches at one instant), and the event
    method's final state lies on the implicit method's dt ladder (1, 1/2,
    1/4, 1/8 ms; first order): within 4 times the ladder's largest step
    between neighbouring rungs, plus 1e-8 m for the event method's own
    error (rtol 1e-10 on positions of centimetres, over its located events
    and impacts; theta weighted by 30 mm). A
    wrong branch (a block held wedged where it turns off a stop, or the
    reverse) is off by orders of magnitude more."""
    sc = _random_corner_scene(seed)
    ev = exdex.simulate(sc, 0.6, 1e-3, method="event", rtol=1e-10, atol=1e-12)
    exdex.simulate(sc, 0.6, 1e-3, method="regularised", rtol=1e-10, atol=1e-12)
    wgt = np.array([1.0, 1.0, 0.03])
    q = [exdex.simulate(sc, 0.6, 1e-3 / k, method="implicit").q[-1] for k in (1, 2, 4, 8)]
    spread = max(np.abs((q[i] - q[i + 1]) * wgt).max() for i in range(3))
    err = np.abs((ev.q[-1] - q[-1]) * wgt).max()
    assert err <= 4.0 * spread + 1e-8, (err, spread)


@pytest.mark.warns_by_design("impact")
def test_event_takes_the_mode_without_wedge_forces_where_a_lock_is_also_consistent():
    """A block touching a square corner (tilted by -0.387 rad) at one
    corner on the wall (mu 1.24) and one on the floor (mu 0.56) while the
    gripper pushes it into the corner at 5 mm/s. With both stops sticking
    the two contacts would pin it (a lock), and with mu > 1 on the wall the
    stops can hold it so with wedge forces; but it can also turn on the
    floor away from the wall, which needs no wall force at all. Both are
    consistent at the acceleration level (Coulomb friction's ambiguity);
    the implicit method's velocity-level step takes the turn (no wall force,
    theta rising by 0.02 rad), and so must the event method: its final
    state on the implicit ladder as in the random corner scenes."""
    sc = exdex.Scene(body=exdex.Body.box(0.13714788776095493, (0.03285224699425235, 0.028286567298935146, 0.02)),
                     grasp=exdex.Grasp(mu=0.3788270433585025, grip_force=1.4873026797533841,
                                       patch=exdex.Patch.rectangle(0.01, 0.01)),
                     dof="planar", q0=(-0.008184359777314102, -0.008167297844797956, -0.3870724019514009),
                     motion=exdex.TrapezoidalProfile(amplitude=0.0022785392670171918, duration=0.5,
                                                     v_max=0.005063420593371537,
                                                     axis=(0.7800079826440133, 0.0, -0.6257695638265066)),
                     stops=(exdex.Stop((0.02, 0.0, -0.02), (-0.9260181335131014, 0.0, -0.37747902776831443),
                                       mu=1.239938721245917),
                            exdex.Stop((0.02, 0.0, -0.02), (-0.37747902776831443, 0.0, 0.9260181335131014),
                                       mu=0.5633545316525804)))
    ev = exdex.simulate(sc, 0.6, 1e-3, method="event", rtol=1e-10, atol=1e-12)
    assert ev.stats["warnings"] == 0
    wgt = np.array([1.0, 1.0, 0.03])
    q = [exdex.simulate(sc, 0.6, 1e-3 / k, method="implicit").q[-1] for k in (1, 2, 4, 8)]
    spread = max(np.abs((q[i] - q[i + 1]) * wgt).max() for i in range(3))
    assert ev.q[-1, 2] - sc.q0[2] > 0.015
    assert np.abs((ev.q[-1] - q[-1]) * wgt).max() <= 4.0 * spread + 1e-8

"""Disc outlines (``Body.outline_radius``, ``Body.cylinder``): closed forms
with their derivations, agreement between methods, invariances and the
input checks.

Frames as everywhere in exdex: with the default gripper rotation B's x axis
is A's x, B's y axis is A's z (up), B's z axis is -A's y; gravity (0, 0,
-9.81) in A is -9.81 along B's y. A stop's normal (n_x, 0, n_z) in A is
(n_x, n_z) in the plate plane.

A disc of radius R about its centre c touches a stop at its support point
c - R n (n the stop's unit normal in the plate plane): the gap is n . c - R
(relative to the stop's line), whatever the disc's orientation.

twin: csrc/tests/scenarios/test_disc.c (the same subject on the C API)
"""
import math
import warnings

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import exdex
from exdex import Body, Grasp, Obstacle, Patch, Scene, Stop
from runs import face_is_the_stop, implicit_converges_to_event, implicit_errors, with_obstacles

G = 9.81
R = 0.02          # disc radius [m]
M = 0.1           # mass [kg]
FLOOR = -0.03     # floor height in B [m]
PAD = Patch.disc(0.005)
METHODS = ["implicit", "explicit", "event", "regularised"]


def disc(**kw):
    return Body.cylinder(M, R, 0.01, **kw)


def floor(mu=0.0):
    return Stop((0.0, 0.0, FLOOR), (0.0, 0.0, 1.0), mu=mu)


# ---------------------------------------------------------------- resting and spinning on a floor

# twin: csrc/tests/scenarios/test_disc.c::disc_rests_on_a_floor_at_its_radius_in_every_method
@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize("dof", ["translation", "planar"])
def test_disc_rests_on_a_floor_at_its_radius_carrying_its_weight(method, dof):
    """Dropped from 1 cm above a floor with frictionless plates (mu = 0): it
    comes to rest with its centre R above the floor (the support point on
    the floor), and the floor carries the whole weight m g (nothing else
    acts along B's y). The disc starts turned by 0.3 rad: a disc has no
    corners, so the angle changes nothing."""
    sc = Scene(body=disc(), grasp=Grasp(mu=0.0, grip_force=1.0, patch=PAD), dof=dof,
               q0=(0.0, FLOOR + R + 0.01, 0.3), stops=(floor(),))
    with pytest.warns(exdex.PhysicsWarning):
        res = exdex.simulate(sc, t_end=0.3, dt=1e-3, method=method)
    y = res.q[-1, 0] if dof == "translation" else res.q[-1, 1]
    np.testing.assert_allclose(y, FLOOR + R, rtol=0, atol=1e-15)
    np.testing.assert_allclose(res.stop_force[-1, 0], M * G, rtol=1e-12)
    if dof == "planar":
        assert res.q[-1, 2] == pytest.approx(0.3, abs=1e-15)


@pytest.mark.parametrize("method", METHODS)
def test_spinning_disc_keeps_its_centre_at_the_radius_on_a_frictionless_floor(method):
    """A uniform disc spinning at omega = 5 rad/s on a frictionless floor,
    plates frictionless: the floor's force passes through the centre (the
    support point lies below it), so nothing turns it and nothing lifts it:
    theta = omega t exactly, the centre stays R above the floor at every
    angle (gap 0 all the way round), the floor carries m g. A polygon
    spinning there would bounce on its corners."""
    sc = Scene(body=disc(), grasp=Grasp(mu=0.0, grip_force=1.0, patch=PAD), dof="planar",
               q0=(0.0, FLOOR + R, 0.0), v0=(0.0, 0.0, 5.0), stops=(floor(),))
    res = exdex.simulate(sc, t_end=0.5, dt=1e-3, method=method)
    assert res.q[-1, 2] > 2.4  # more than 137 deg turned
    np.testing.assert_allclose(res.q[:, 1], FLOOR + R, rtol=0, atol=1e-16)
    np.testing.assert_allclose(res.q[:, 2], 5.0 * res.t, rtol=0, atol=1e-13)
    np.testing.assert_allclose(res.stop_force[1:, 0], M * G, rtol=1e-14)
    assert res.stats["warnings"] == 0


@pytest.mark.warns_by_design("impact")
def test_eccentric_spinning_disc_event_and_implicit_agree_and_never_sink():
    """A disc whose centre is 5 mm from the centre of mass, spinning on a
    frictionless floor in frictional plates: no closed form, but the
    disc's centre c = (x, y) + Rz(theta) (5 mm, 0) never sinks below R above
    the floor (implicit, event: to rounding) and the implicit method
    converges to the event method's trajectory (first order in dt; the disc
    hops once and lands, an impact both methods resolve)."""
    body = disc(outline_center=(0.005, 0.0))
    sc = Scene(body=body, grasp=Grasp(mu=0.2, grip_force=0.5, patch=PAD), dof="planar",
               q0=(-0.005, FLOOR + R, 0.0), v0=(0.0, 0.0, 5.0), stops=(floor(),))
    ev = exdex.simulate(sc, t_end=0.5, dt=1e-3, method="event", rtol=1e-10, atol=1e-12)
    runs = implicit_errors(exdex.simulate, sc, ev, 0.5)
    errs = [err for _, err in runs]
    for im, _ in runs:
        cy = im.q[:, 1] + 0.005 * np.sin(im.q[:, 2])
        assert cy.min() >= FLOOR + R - 1e-15
    cy = ev.q[:, 1] + 0.005 * np.sin(ev.q[:, 2])
    assert cy.min() >= FLOOR + R - 1e-15
    # first order: ten times smaller steps, ten times closer (6.7e-3, 6.5e-4 rad at most, at the hop's landing)
    assert errs[1] < 1e-3 and errs[1] < 0.12 * errs[0]


# ---------------------------------------------------------------- rolling down a frictional incline

def incline_scene(alpha, mu_s, th0=0.0, body=None):
    """The disc touching a stop through A's origin with normal (-sin alpha,
    0, cos alpha) (an incline rising to the left), plates frictionless."""
    n = (-math.sin(alpha), 0.0, math.cos(alpha))
    return Scene(body=body or disc(), grasp=Grasp(mu=0.0, grip_force=1.0, patch=PAD), dof="planar",
                 q0=(-R * math.sin(alpha), R * math.cos(alpha), th0), stops=(Stop((0.0, 0.0, 0.0), n, mu=mu_s),))


def incline_closed_form(alpha, mu_s):
    """Uniform disc (I = m R^2 / 2) on an incline of angle alpha with
    Coulomb coefficient mu_s, released at rest. Down-slope d = (-cos alpha,
    -sin alpha) in B; with the support point at -R n, the contact point's
    velocity v + omega e_z x (-R n) vanishes for v = omega R d: rolling down
    turns the disc at omega = v / R > 0.
    Rolling: m a = m g sin alpha - f, I alpha_dot = f R, a = R alpha_dot give
    a = g sin alpha / (1 + I / (m R^2)) = 2/3 g sin alpha, f = m a / 3, which
    the stop carries while f <= mu_s m g cos alpha, i.e. tan alpha <= 3 mu_s.
    Else it slides: f = mu_s m g cos alpha, a = g (sin alpha - mu_s cos
    alpha), angular acceleration f R / I = 2 mu_s g cos alpha / R.
    Returns (a, angular acceleration); the normal force is m g cos alpha."""
    if math.tan(alpha) <= 3.0 * mu_s:
        a = 2.0 / 3.0 * G * math.sin(alpha)
        return a, a / R
    return G * (math.sin(alpha) - mu_s * math.cos(alpha)), 2.0 * mu_s * G * math.cos(alpha) / R


@pytest.mark.warns_by_design("pad", "outline")
@pytest.mark.parametrize("mu_s", [0.5, 0.05])
@pytest.mark.parametrize("method", ["implicit", "explicit"])
def test_disc_rolls_or_slides_down_a_frictional_incline_as_the_closed_form(method, mu_s):
    """Constant accelerations a (down the slope) and beta (spin) from rest:
    both time-stepping methods take v_k = a k h (the velocity update of a
    constant force is exact), q_k = h sum v_j = a h^2 k (k + 1) / 2, i.e.
    s(t) = a t (t + h) / 2: that discrete solution to rounding, the normal
    force m g cos alpha at every step and no motion across the slope.
    mu_s = 0.5: rolls (tan 0.3 <= 1.5), theta = s / R exactly; 0.05: slides
    and spins at the sliding rates."""
    alpha, h, t_end = 0.3, 1e-4, 0.2
    res = exdex.simulate(incline_scene(alpha, mu_s), t_end=t_end, dt=h, method=method)
    a, beta = incline_closed_form(alpha, mu_s)
    d = np.array([-math.cos(alpha), -math.sin(alpha)])
    nrm = np.array([-math.sin(alpha), math.cos(alpha)])
    rel = res.q[:, :2] - res.q[0, :2]
    t = res.t
    np.testing.assert_allclose(rel @ d, 0.5 * a * t * (t + h), rtol=1e-9, atol=1e-16)
    np.testing.assert_allclose(res.q[:, 2], 0.5 * beta * t * (t + h), rtol=1e-9, atol=1e-14)
    np.testing.assert_allclose(rel @ nrm, 0.0, rtol=0, atol=1e-15)
    np.testing.assert_allclose(res.stop_force[1:, 0], M * G * math.cos(alpha), rtol=1e-9)
    assert res.stats["warnings"] == 0


@pytest.mark.warns_by_design("pad", "outline")
@pytest.mark.parametrize("mu_s", [0.5, 0.05])
@pytest.mark.parametrize("method", ["event", "regularised"])
def test_disc_rolls_down_a_frictional_incline_exactly_in_the_adaptive_methods(method, mu_s):
    """The same closed form, continuous: s = a t^2 / 2, theta = beta t^2 / 2
    (the adaptive methods integrate a constant acceleration exactly), the
    rolling or sliding mode held at the disc's support point (its slip
    acceleration is the material point's there: the contact moving along the
    rim only adds terms normal to the stop's tangent)."""
    alpha = 0.3
    res = exdex.simulate(incline_scene(alpha, mu_s), t_end=0.2, dt=1e-3, method=method)
    assert_incline_exactly(res, alpha, mu_s)


def assert_incline_exactly(res, alpha, mu_s):
    """The continuous incline closed form (incline_closed_form) to 1e-12
    relative: s = a t^2 / 2 down the slope, theta = beta t^2 / 2, the normal
    force m g cos alpha after the first sample, no warnings."""
    a, beta = incline_closed_form(alpha, mu_s)
    d = np.array([-math.cos(alpha), -math.sin(alpha)])
    t = res.t
    np.testing.assert_allclose((res.q[:, :2] - res.q[0, :2]) @ d, 0.5 * a * t * t, rtol=1e-12, atol=1e-16)
    np.testing.assert_allclose(res.q[:, 2], 0.5 * beta * t * t, rtol=1e-12, atol=1e-14)
    np.testing.assert_allclose(res.stop_force[1:, 0], M * G * math.cos(alpha), rtol=1e-12)
    assert res.stats["warnings"] == 0


@pytest.mark.warns_by_design("pad", "outline")
def test_rolling_eccentric_disc_in_a_turning_gripper_event_and_implicit_agree():
    """A disc whose centre is 4 mm from the centre of mass rolls on a
    frictional floor (mu 0.8) while the gripper turns 0.6 rad about its
    plate normal: the floor's trace turns in B, so the support point moves
    along the rim with time as well as with the disc's angle. No closed
    form: the implicit method converges to the event method's run at first
    order (errors at 1e-3, 1e-4 s about ten times apart)."""
    mot = exdex.TrapezoidalProfile(amplitude=0.6, duration=0.6, v_max=1.5, axis=(0, -1, 0), rotation=True)
    sc = Scene(body=disc(outline_center=(0.004, 0.0)), grasp=Grasp(mu=0.3, grip_force=0.3, patch=PAD), dof="planar",
               q0=(-0.004, FLOOR + R, 0.0), stops=(floor(0.8),), motion=mot)
    ev = exdex.simulate(sc, t_end=0.6, dt=1e-3, method="event", rtol=1e-10, atol=1e-12)
    assert ev.stats["warnings"] == 0 and abs(ev.q[-1, 2]) > 0.3
    errs = [err for _, err in implicit_errors(exdex.simulate, sc, ev, 0.6)]
    assert errs[1] < 2e-3 and errs[1] < 0.12 * errs[0]


@pytest.mark.warns_by_design("pad", "outline")
def test_rolling_disc_is_invariant_under_turning_it_about_its_centre():
    """Turning the disc (its centre on the centre of mass, the patch at the
    centre) about its centre by any angle changes nothing but theta's
    offset: the positions and the stop force to rounding, theta - theta0
    likewise. A polygon's corners would make the runs differ."""
    ref = exdex.simulate(incline_scene(0.3, 0.5, th0=0.0), t_end=0.2, dt=1e-3)
    for th0 in (0.4, 1.0, -2.5):
        res = exdex.simulate(incline_scene(0.3, 0.5, th0=th0), t_end=0.2, dt=1e-3)
        np.testing.assert_allclose(res.q[:, :2], ref.q[:, :2], rtol=0, atol=1e-16)
        np.testing.assert_allclose(res.q[:, 2] - th0, ref.q[:, 2], rtol=0, atol=1e-13)
        np.testing.assert_allclose(res.stop_force, ref.stop_force, rtol=1e-13)


# ---------------------------------------------------------------- obstacles

# twin: csrc/tests/scenarios/test_disc.c::disc_rests_on_a_rod_at_the_sum_of_the_radii
@pytest.mark.parametrize("method", ["implicit", "explicit", "event", "regularised"])
@pytest.mark.parametrize("beta", [0.0, 0.5])
def test_disc_rests_on_top_of_a_rod_at_the_sum_of_the_radii(method, beta):
    """A rod of radius r along (sin beta, cos beta, 0) in A through (0, 0,
    FLOOR): its section by the plate plane is an ellipse with semi-axes r /
    cos beta (horizontal) and r (vertical) centred at (0, FLOOR). The disc
    held above the ellipse's top point, frictionless plates: the disc and the
    ellipse are convex and separated by the horizontal tangent at that top
    point (0, FLOOR + r), so they touch there only: the disc rests with its
    centre at FLOOR + r + R (a point (X, Z) of the plane lies at distance
    sqrt(X^2 cos^2 beta + Z^2) from the axis, r at the top point), the rod
    carrying m g."""
    r = 0.005
    rod = Obstacle.cylinder((0.0, 0.0, FLOOR), (math.sin(beta), math.cos(beta), 0.0), r)
    sc = Scene(body=disc(), grasp=Grasp(mu=0.0, grip_force=1.0, patch=PAD), dof="planar",
               q0=(0.0, FLOOR + r + R + 0.002, 0.3), obstacles=(rod,))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", exdex.PhysicsWarning)  # the impact
        res = exdex.simulate(sc, t_end=0.3, dt=1e-4, method=method)
    np.testing.assert_allclose(res.q[-1, 1], FLOOR + r + R, rtol=0, atol=1e-15)
    np.testing.assert_allclose(res.q[-1, 0], 0.0, rtol=0, atol=1e-14)
    np.testing.assert_allclose(res.stop_force[-1, 0], M * G, rtol=1e-12)


@pytest.mark.warns_by_design("pad", "outline")
def test_disc_rolls_off_a_box_corner_touching_it_at_the_radius():
    """A box occupying x <= 0, z <= FLOOR; the disc starts 1 mm right of its
    corner, touching the corner (centre at distance R from it), frictionless
    plates. It swings off the corner: while the box pushes, the corner is
    the nearest point of the section and the disc's centre stays at
    distance R from it (the gap of a section vertex against a disc), then
    the disc falls past it. It never enters the box (every sample's centre
    at least R from the box). The implicit step holds the row's gap
    linearised at the step's start: moving the centre by v h along the
    tangent of the circle of radius R about the corner lifts it off by
    (v h)^2 / (2 R); a touching row (gap within the core's contact band,
    1e-8 of the length scale, here R) only keeps its gap from closing (G v+
    >= 0), so those lifts add up within the band: the distance while
    pushing is at most R + 1e-8 R + (v h)^2 / (2 R)."""
    box = Obstacle.box((-0.5, 0.0, FLOOR - 0.5), (1.0, 1.0, 1.0))
    x0 = 0.001
    sc = Scene(body=disc(), grasp=Grasp(mu=0.0, grip_force=1.0, patch=PAD), dof="planar",
               q0=(x0, FLOOR + math.sqrt(R * R - x0 * x0), 0.0), obstacles=(box,))
    res = exdex.simulate(sc, t_end=0.2, dt=1e-5, method="implicit")
    c = res.q[:, :2]
    # distance of each centre from the box's quarter plane x <= 0, y <= FLOOR
    dx, dy = np.maximum(c[:, 0], 0.0), np.maximum(c[:, 1] - FLOOR, 0.0)
    dist = np.hypot(dx, dy)
    assert dist.min() >= R - 1e-12
    pushing = res.stop_force[:, 0] > 1e-9
    assert pushing.sum() > 100
    speed = np.hypot(res.v[:, 0], res.v[:, 1])
    lift = (speed * 1e-5) ** 2 / (2 * R)
    # (v h)^2 / (2 R) is the leading term (the velocity changes within the step): 0.1 % margin
    assert np.all(dist[pushing] - R <= 1e-8 * R + 1.001 * lift[pushing])
    assert lift[pushing].max() < 1e-9
    assert c[-1, 0] > R and c[-1, 1] < FLOOR  # it fell past the corner


@pytest.mark.warns_by_design("impact", "pad", "outline")
@pytest.mark.parametrize("method", ["implicit", "explicit", "event", "regularised"])
def test_one_face_obstacle_is_the_stop_for_a_disc_bit_for_bit(method):
    """A one-face obstacle and the stop through its plane: for a disc too,
    the same trajectory and forces, bit for bit (the same row: the face's
    plane gap at the disc's support point)."""
    n = np.array([0.3, 0.0, 1.0]) / math.hypot(0.3, 1.0)
    solid = Obstacle.halfspaces([n], [float(n @ (0.0, 0.0, FLOOR))])
    base = Scene(body=disc(outline_center=(0.004, 0.001)), grasp=Grasp(mu=0.5, grip_force=1.0, patch=PAD),
                 dof="planar", q0=(0.0, FLOOR + R + 0.01, 0.2),
                 motion=exdex.TrapezoidalProfile(0.05, 0.5, 0.12, axis=(0, 0, -1)))
    a = exdex.simulate(exdex.replace(base, stops=(Stop(solid.face_points[0], solid.face_normals[0]),)),
                       t_end=0.8, dt=1e-3, method=method)
    b = exdex.simulate(exdex.replace(base, obstacles=(solid,)), t_end=0.8, dt=1e-3, method=method)
    assert np.array_equal(a.q, b.q) and np.array_equal(a.v, b.v)
    assert np.array_equal(a.stop_force, b.stop_force)
    assert a.stop_force[:, 0].max() > 0.1  # the floor pushed


@pytest.mark.warns_by_design("pad", "outline")
@pytest.mark.parametrize("method", ["event", "regularised"])
def test_disc_swings_off_a_box_corner_at_the_radius_in_the_adaptive_methods(method):
    """The box corner of test_disc_rolls_off_a_box_corner_touching_it_at_the_radius
    in the event and regularised methods: their row of the disc against the
    section's corner (the centre's distance from it less the radius, held
    with its exact derivatives while the corner is the section's nearest
    point) keeps the centre at distance R from the corner at every sample
    where the box pushes, to rounding (the sample where it lets go
    excepted: the force is the interval's mean), never nearer, and the disc
    falls past the corner; the implicit method at dt = 1e-5 s lies within
    its first-order error (2e-6 m) of that run."""
    box = Obstacle.box((-0.5, 0.0, FLOOR - 0.5), (1.0, 1.0, 1.0))
    x0 = 0.001
    sc = Scene(body=disc(), grasp=Grasp(mu=0.0, grip_force=1.0, patch=PAD), dof="planar",
               q0=(x0, FLOOR + math.sqrt(R * R - x0 * x0), 0.0), obstacles=(box,))
    res = exdex.simulate(sc, t_end=0.2, dt=1e-3, method=method)
    c = res.q[:, :2]
    dist = np.hypot(np.maximum(c[:, 0], 0.0), np.maximum(c[:, 1] - FLOOR, 0.0))
    pushing = np.nonzero(res.stop_force[:, 0] > 1e-9)[0]
    assert len(pushing) > 100 and dist.min() >= R - 1e-15
    np.testing.assert_allclose(dist[pushing[:-1]], R, rtol=0, atol=1e-15)
    assert c[-1, 0] > R and c[-1, 1] < FLOOR
    im = exdex.simulate(sc, t_end=0.2, dt=1e-5, method="implicit")
    assert np.abs(im.q[::100] - res.q).max() < 2e-6


@pytest.mark.warns_by_design("pad", "outline")
@pytest.mark.parametrize("mu_s", [0.5, 0.05])
@pytest.mark.parametrize("method", ["event", "regularised"])
def test_disc_rolls_or_slides_down_a_frictional_box_top_as_the_incline(method, mu_s):
    """The frictional incline of incline_scene as obstacles, in the event
    and regularised methods: a one-face frictional obstacle through the
    incline is the frictional Stop bit for bit (the disc's support point
    against the face, its slip the stop's); a box whose top face is the
    incline (the other faces far away) meets the incline closed form
    (incline_closed_form) exactly: s = a t^2 / 2, theta = beta t^2 / 2 to
    1e-12 relative, rolling at mu_s = 0.5 and sliding at 0.05."""
    alpha = 0.3
    sc = incline_scene(alpha, mu_s)
    n = np.array(sc.stops[0].normal)
    face = Obstacle.halfspaces([n], [0.0], mu=mu_s)
    box = Obstacle.box(tuple(-0.5 * n), (1.0, 1.0, 1.0), rotation=Rotation.from_rotvec([0, -alpha, 0]).as_matrix(),
                       mu=mu_s)
    face_is_the_stop(exdex.simulate, sc, face, 0.2, 1e-3, method=method)
    res = exdex.simulate(with_obstacles(sc, box), t_end=0.2, dt=1e-3, method=method)
    assert_incline_exactly(res, alpha, mu_s)


def _disc_contact_scene(seed):
    """A disc (radius 15 .. 25 mm, its centre off the centre of mass on odd
    seeds) resting on the top face of a random tilted frictional box (slope
    within +-0.4 rad, the box wide enough that the disc stays on it), a
    frictional rod normal to the plates touching its rim up to 0.8 rad
    above the face's tangent; the gripper (plate capacity 0.5 .. 2 N) moves
    5 .. 15 mm toward the rod or away from it (within 0.5 rad) and stops:
    the disc rolls and slides on the face and against the rod. Both contacts
    touch from the start (gaps 1e-9 m)."""
    rng = np.random.default_rng([seed, 93])
    alpha = rng.uniform(-0.4, 0.4)
    rad = rng.uniform(0.015, 0.025)
    n_b = np.array([-math.sin(alpha), math.cos(alpha)])
    t_b = np.array([math.cos(alpha), math.sin(alpha)])
    bc = -(rad + 1e-9) * n_b - 0.15 * n_b + rng.uniform(-0.01, 0.01) * t_b
    box = Obstacle.box((bc[0], 0.0, bc[1]), (0.3, 0.3, 0.3), rotation=Rotation.from_rotvec([0, -alpha, 0]).as_matrix(),
                       mu=rng.uniform(0.05, 0.5))
    r = 0.006
    side = rng.choice([-1.0, 1.0])
    ang0 = rng.uniform(0.0, 0.8)
    c = (rad + r + 1e-9) * (side * math.cos(ang0) * t_b + math.sin(ang0) * n_b)
    rod = Obstacle.cylinder((c[0], 0.0, c[1]), (0, 1, 0), r, mu=rng.uniform(0.1, 1.0))
    dist = rng.uniform(0.005, 0.015)
    toward = rng.choice([-1.0, 1.0])
    ang = math.atan2(toward * side * t_b[1], toward * side * t_b[0]) + rng.uniform(-0.5, 0.5)
    oc = rng.uniform(-0.3, 0.3) * rad if seed % 2 else 0.0
    return Scene(body=Body.cylinder(0.1, rad, 0.02, outline_center=(oc, 0.0)),
                 grasp=Grasp(mu=0.5, grip_force=rng.uniform(0.5, 2.0), patch=PAD), dof="planar", q0=(-oc, 0.0, 0.0),
                 motion=exdex.TrapezoidalProfile(dist, 0.6, 1.5 * dist / 0.6, axis=(math.cos(ang), 0, math.sin(ang))),
                 obstacles=(box, rod))


@pytest.mark.warns_by_design("impact", "pad", "outline", "solver", "jump")
@pytest.mark.parametrize("seed", range(8))
def test_event_and_implicit_agree_on_random_disc_obstacle_scenes(seed):
    """The disc against frictional obstacles (_disc_contact_scene): the event
    method (rtol 1e-10) and the implicit method converge to the same motion,
    the check of tests/scenarios/test_obstacles.py's random frictional obstacle scenes
    (implicit error halving with dt, its Richardson extrapolation 5x closer;
    or below 1e-8 m at h / 2 and not growing)."""
    implicit_converges_to_event(exdex.simulate, _disc_contact_scene(seed), 0.8)


# ---------------------------------------------------------------- 1-DoF rotation

@pytest.mark.parametrize("method", METHODS)
def test_pinned_disc_off_its_centre_stops_on_a_floor_at_the_closed_form_angle(method):
    """Rotation scene, no gravity, frictionless plates: the disc's centre is
    d = 10 mm from the pivot (the centre of mass, at the patch), so at angle
    theta it is at (d cos theta, d sin theta). Turning down at 3 rad/s it
    reaches the floor where its centre is R above it, d sin theta_s =
    y_floor + R, and stays there (a plastic impact on a frictionless stop
    leaves no rate along the free coordinate)."""
    d, theta_s = 0.01, -0.5
    y_floor = d * math.sin(theta_s) - R
    sc = Scene(body=disc(outline_center=(d, 0.0)), grasp=Grasp(mu=0.0, grip_force=1.0, patch=PAD),
               dof="rotation", v0=(0.0, 0.0, -3.0), stops=(Stop((0.0, 0.0, y_floor), (0.0, 0.0, 1.0)),),
               gravity=(0.0, 0.0, 0.0))
    with pytest.warns(exdex.PhysicsWarning, match="impact"):
        res = exdex.simulate(sc, t_end=0.5, dt=1e-4, method=method)
    # the event and regularised methods locate the impact to their root resolution (~1e-12 T)
    np.testing.assert_allclose(res.q[-1, 0], theta_s, rtol=0, atol=1e-14 if method in ("implicit", "explicit") else 1e-11)
    assert res.v[-1, 0] == 0.0


# ---------------------------------------------------------------- input and files

def test_bad_disc_input_names_the_parameter():
    with pytest.raises(ValueError, match="Body.outline_radius"):
        Body(mass=0.1, outline_radius=0.0)
    with pytest.raises(ValueError, match="exclusive"):
        Body(mass=0.1, outline=[(0.0, 0.0)], outline_radius=0.01)
    with pytest.raises(ValueError, match="outline_center"):
        Body(mass=0.1, outline_center=(0.01, 0.0))
    with pytest.raises(ValueError, match="Body.outline_center"):
        Body(mass=0.1, outline_radius=0.01, outline_center=(0.0, np.nan))
    with pytest.raises(ValueError, match="radius"):
        Body.cylinder(0.1, -0.01, 0.01)
    with pytest.raises(TypeError, match="Body.outline_radius"):
        Body(mass=0.1, outline_radius="1")  # type: ignore[arg-type]
    # the core's own check: a disc with polygon vertices too
    spec = Scene(body=disc(), grasp=Grasp(mu=0.5, grip_force=1.0), stops=(floor(),)).to_spec()
    spec["vertices"] = np.zeros((3, 2))
    with pytest.raises(ValueError, match="disc_radius"):
        exdex._core.compile(spec)
    spec["vertices"] = None
    spec["disc_radius"] = -1.0
    with pytest.raises(ValueError, match="disc_radius"):
        exdex._core.compile(spec)


def test_disc_starting_beyond_a_stop_is_named():
    sc = Scene(body=disc(), grasp=Grasp(mu=0.5, grip_force=1.0), dof="planar",
               q0=(0.0, FLOOR + R - 1e-4, 0.0), stops=(floor(),))
    with pytest.raises(ValueError, match="the disc outline is"):
        sc.check_stops()


@pytest.mark.parametrize("fmt", ["json", "toml"])
def test_disc_scene_file_round_trip(fmt):
    sc = Scene(body=disc(outline_center=(0.001, -0.002)), grasp=Grasp(mu=0.5, grip_force=1.0), dof="planar",
               stops=(floor(0.4),))
    text = exdex.io.dumps(sc, fmt)
    assert "outline_radius" in text
    back = exdex.io.loads(text, fmt)
    assert back == sc and back.body.outline_radius == R and back.body.outline_center == (0.001, -0.002)


def test_cylinder_inertia_and_outline():
    """Uniform cylinder about its centre, axis along z: I_zz = m r^2 / 2,
    I_xx = I_yy = m (3 r^2 + h^2) / 12; the bounding box as size."""
    b = Body.cylinder(0.2, 0.03, 0.01)
    np.testing.assert_allclose(np.diag(b.inertia), [0.2 * (3 * 9e-4 + 1e-4) / 12] * 2 + [0.2 * 9e-4 / 2])
    assert b.size == (0.06, 0.06, 0.01) and b.outline_radius == 0.03 and b.is_disc
    v = b.vertices()
    np.testing.assert_allclose(np.hypot(v[:, 0], v[:, 1]), 0.03, rtol=1e-15)


@pytest.mark.parametrize("method", ["implicit", "event", "regularised"])
def test_pinned_disc_off_its_centre_stops_on_a_rod_at_the_closed_form_angle(method):
    """The pinned disc of the floor test above turning down onto a rod
    normal to the plates instead: its centre c(theta) = d (cos theta, sin
    theta) meets the rod (centre rc, radius r) where |c - rc| = R + r. With
    rc = c(theta_s) - (R + r) e_y, theta_s = -0.5, the distance falls on
    [theta_s, 0] (rc's angle, -1.28 rad, lies below), so the disc's rim
    first touches the rod at theta_s and stays there (a plastic impact on a
    frictionless rod leaves no rate along the free coordinate). The row is
    the disc's rim point nearest the rod's axis (a circle-circle distance
    here). (The explicit method, whose impact step linearises the row,
    ends 9e-13 rad off.)"""
    d, theta_s, r = 0.01, -0.5, 0.005
    rc = (d * math.cos(theta_s), d * math.sin(theta_s) - (R + r))
    rod = Obstacle.cylinder((rc[0], 0.0, rc[1]), (0.0, 1.0, 0.0), r)
    sc = Scene(body=disc(outline_center=(d, 0.0)), grasp=Grasp(mu=0.0, grip_force=1.0, patch=PAD),
               dof="rotation", v0=(0.0, 0.0, -3.0), obstacles=(rod,), gravity=(0.0, 0.0, 0.0))
    with pytest.warns(exdex.PhysicsWarning, match="impact"):
        res = exdex.simulate(sc, t_end=0.5, dt=1e-4, method=method)
    np.testing.assert_allclose(res.q[-1, 0], theta_s, rtol=0, atol=1e-14 if method in ("implicit", "explicit") else 1e-11)
    assert res.v[-1, 0] == 0.0

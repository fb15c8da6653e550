"""Impacts on frictional stops (``Stop(..., mu > 0)``): closed forms of the
impulse-level law, in every method that takes stops.

The law: an impact is plastic with Coulomb friction at the stop, the
velocity-level problem over the vanishing duration of the impact,

    M (v+ - v-) = G^T Pn + T^T Pt,   G v+ = b (no approach, plastic),
    |Pt| <= mu Pn,  Pt = -mu Pn sign(T v+) where the slip T v+ + tb != 0,

with G the stop's normal row, T its tangential row (the slip of the
touching vertex along the stop, in the plate plane) and no plate impulse:
the plates' friction is bounded by the grip force, so over an impact of
duration -> 0 its impulse is 0. The implicit step solves the same problem
with the plates' impulse c h of a step h (so it converges to this law as h
-> 0), the explicit step with no plate impulse; the event and regularised
methods apply it at the located impact time.

Frames: ``gripper_rotation`` is the identity here, so B's axes are A's and
the plate plane is A's xy plane.

twin: csrc/tests/scenarios/test_frictional_impacts.c (the same subject on the C API)
"""
import math
import warnings

import numpy as np
import pytest
from scipy.optimize import brentq

import exdex

IDENTITY = ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))
A_BOX, B_BOX, M_BOX = 0.04, 0.02, 0.1
I_BOX = M_BOX * (A_BOX ** 2 + B_BOX ** 2) / 12.0
ADAPTIVE = dict(rtol=1e-12, atol=1e-14)


def _run(scene, t_end, dt, method):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return exdex.simulate(scene, t_end, dt, method=method,
                              **(ADAPTIVE if method in ("event", "regularised") else {}))


def _corner_impact(r, v, mu):
    """Impulse-momentum closed form of a planar box (M = diag(m, m, I))
    whose corner r (from C, in B) strikes a floor with normal n = (0, 1)
    and tangent t = (1, 0), the floor at rest: rows G = (n, r x n), T =
    (t, r x t) (r x n = r_x n_y - r_y n_x), v+ = v + M^-1 (G Pn + T Pt).
    Sticking: G v+ = 0 and T v+ = 0, the 2 x 2 system
        [G M^-1 G, G M^-1 T; T M^-1 G, T M^-1 T] (Pn, Pt) = -(G v, T v),
    consistent if |Pt| <= mu Pn. Otherwise sliding in the direction
    sigma = sign(T v-) of the slip before the impact (the slip only shrinks
    under -mu sigma Pn): Pt = -mu sigma Pn and G v+ = 0 give Pn = -G v /
    (G M^-1 (G - mu sigma T)); the slip after keeps its sign (checked).
    Returns (v+, Pn, sliding)."""
    Mi = np.diag([1 / M_BOX, 1 / M_BOX, 1 / I_BOX])
    G = np.array([0.0, 1.0, r[0]])
    T = np.array([1.0, 0.0, -r[1]])
    A = np.array([[G @ Mi @ G, G @ Mi @ T], [T @ Mi @ G, T @ Mi @ T]])
    pn, pt = np.linalg.solve(A, -np.array([G @ v, T @ v]))
    sliding = abs(pt) > mu * pn
    if sliding:
        sg = math.copysign(1.0, T @ v)
        pn = -(G @ v) / (G @ Mi @ (G - mu * sg * T))
        pt = -mu * sg * pn
    vp = v + Mi @ (G * pn + T * pt)
    if sliding:
        assert (T @ vp) * (T @ v) > 0
    return vp, pn, sliding


def _box_scene(th0, v0, floor_y, mu):
    """The box (A_BOX x B_BOX, mass M_BOX) in a planar grasp whose plates
    have no friction (mu 0: before and after the impact the box flies
    freely, v and the spin constant), no gravity, gripper at rest, over a
    floor stop at y = floor_y (normal +y)."""
    return exdex.Scene(body=exdex.Body.box(M_BOX, (A_BOX, B_BOX, 0.02)),
                       grasp=exdex.Grasp(mu=0.0, grip_force=1.0, patch=exdex.Patch.rectangle(0.01, 0.01)),
                       dof="planar", gravity=(0.0, 0.0, 0.0), gripper_rotation=IDENTITY,
                       q0=(0.0, 0.0, th0), v0=tuple(v0),
                       stops=(exdex.Stop((0.0, floor_y, 0.0), (0.0, 1.0, 0.0), mu=mu),))


def _corners(th):
    c, s = math.cos(th), math.sin(th)
    return [np.array([c * x - s * y, s * x + c * y])
            for x, y in ((A_BOX / 2, B_BOX / 2), (-A_BOX / 2, B_BOX / 2), (-A_BOX / 2, -B_BOX / 2),
                         (A_BOX / 2, -B_BOX / 2))]


#: (floor mu, expected law): the same strike slides at mu 0.1 and 0.3 and
#: sticks at mu 2 (the closed form decides, the label is checked)
MUS = [(0.1, "slide"), (0.3, "slide"), (2.0, "stick")]


@pytest.mark.parametrize("method", ["event", "regularised", "implicit", "explicit"])
@pytest.mark.parametrize("mu, law", MUS)
def test_spinning_box_corner_touching_a_frictional_floor_closed_form(mu, law, method):
    """The box starts with its lowest corner on the floor (gap 0), turned
    by 0.3 rad, moving at (0.15, -0.2) m/s and spinning at 2 rad/s, so the
    corner approaches the floor: the impact is at t = 0 (the time-stepping
    methods' first step: its bound G v+ >= -gap / h = 0 is the plastic
    one, and with frictionless plates their step is the law above
    exactly). After it the box flies freely: every later sample has v+
    (the corner leaves the floor: its acceleration is centripetal, toward
    C, which is above it)."""
    th0, v0 = 0.3, np.array([0.15, -0.2, 2.0])
    r = min(_corners(th0), key=lambda p: p[1])
    vp, pn, sliding = _corner_impact(r, v0, mu)
    assert sliding == (law == "slide")
    res = _run(_box_scene(th0, v0, r[1], mu), 0.002, 1e-4, method)
    assert res.stats["impacts"] == 1 and res.stats["warnings"] == 0
    np.testing.assert_allclose(res.stats["max_impulse"], pn, rtol=1e-12)
    np.testing.assert_allclose(res.v[1:], np.tile(vp, (len(res.t) - 1, 1)), rtol=0, atol=1e-12)


def _strike():
    """The located strike: the box of the touching test 3 mm higher, flying
    freely (q(t) = q0 + v0 t) until a corner c reaches the floor, where y0
    + vy t + (R(th0 + w t) c)_y = floor_y: the first root over the four
    corners (brentq on a bracket from a scan). Returns (th0, v0, floor_y,
    t_hit, corner index)."""
    th0, v0 = 0.3, np.array([0.15, -0.2, 2.0])
    floor_y = min(p[1] for p in _corners(th0)) - 0.003

    def gap(t, k):
        return v0[1] * t + _corners(th0 + v0[2] * t)[k][1] - floor_y

    ts = np.linspace(0.0, 0.1, 2001)
    hits = []
    for k in range(4):
        g = np.array([gap(t, k) for t in ts])
        i = np.flatnonzero(g <= 0.0)
        if i.size:
            hits.append((brentq(gap, ts[i[0] - 1], ts[i[0]], args=(k,), xtol=1e-15), k))
    t_hit, k = min(hits)
    return th0, v0, floor_y, t_hit, k


@pytest.mark.parametrize("method", ["event", "regularised"])
@pytest.mark.parametrize("mu, law", MUS)
def test_spinning_box_corner_strikes_a_frictional_floor_closed_form(mu, law, method):
    """The box of the test above starts 3 mm above the floor and flies
    freely into it (frictionless plates, no gravity; _strike finds where a
    corner reaches the floor). The impact there is the closed form of _corner_impact
    with r = R(th(t*)) c; the method locates it (its own guard) and applies
    the law: the impulse, the impact time and the free flight after it."""
    th0, v0, floor_y, t_hit, k = _strike()
    r = _corners(th0 + v0[2] * t_hit)[k]
    vp, pn, sliding = _corner_impact(r, v0, mu)
    assert sliding == (law == "slide")
    res = _run(_box_scene(th0, v0, floor_y, mu), t_hit + 0.003, 1e-4, method)
    assert res.stats["impacts"] == 1 and res.stats["warnings"] == 0
    np.testing.assert_allclose(res.stats["max_impulse_t"], t_hit, rtol=1e-9)
    np.testing.assert_allclose(res.stats["max_impulse"], pn, rtol=1e-9)
    before, after = res.t < t_hit, res.t > t_hit
    np.testing.assert_allclose(res.v[before], np.tile(v0, (before.sum(), 1)), rtol=0, atol=1e-12)
    np.testing.assert_allclose(res.v[after], np.tile(vp, (after.sum(), 1)), rtol=0, atol=1e-9)


@pytest.mark.parametrize("mu, law", MUS)
def test_implicit_converges_to_the_law_on_the_located_strike(mu, law):
    """The located strike above with the implicit method: its impact falls
    inside a step (whose bound G v+ >= -gap / h can leave part of the
    approach to the next step: the impulse spread over two steps), and the law is
    the limit h -> 0 of its steps: the velocity after the strike tends to
    the closed form, the error falling at least fivefold per decade of h
    (1e-4, 1e-5, 1e-6 s: 2.6e-4, 7.3e-6, 8.1e-7 relative at mu 0.1)."""
    th0, v0, floor_y, t_hit, k = _strike()
    vp, _, sliding = _corner_impact(_corners(th0 + v0[2] * t_hit)[k], v0, mu)
    assert sliding == (law == "slide")
    err = [np.abs(_run(_box_scene(th0, v0, floor_y, mu), t_hit + 0.002, h, "implicit").v[-1] - vp).max()
           / np.abs(vp).max() for h in (1e-4, 1e-5, 1e-6)]
    assert err[1] < 0.2 * err[0] and err[2] < 0.2 * err[1] and err[2] < 1e-5, err


@pytest.mark.parametrize("mu_s, vt", [(0.3, 0.2), (0.8, 0.2), (0.5, -0.1), (1.5, 0.2)])
def test_thrown_block_strikes_a_frictional_wall_closed_form(mu_s, vt):
    """A square block with a face parallel to a wall (normal +x at x =
    -0.02 m, B = A), no gravity, gripper at rest, thrown at it with (-vn,
    vt) and no spin, plates with friction. They decelerate it along its
    path at c = cap / m (a pure translation slip of a patch centred on C
    gets a pure force) until it reaches the wall at ts, where its path has
    covered 5 mm of gap: (vn / s0) (s0 ts - c ts^2 / 2) = 5 mm (s0 = |v0|),
    speed s0 - c ts. The impact: normal impulse m vn* (both corners of the
    face strike together, their normal impulses carry the friction's
    torque: no spin), tangential velocity vt' = vt* - sign(vt*) min(|vt*|,
    mu vn*). Then it slides along the wall without pushing it (the plate
    friction is along the wall) and decelerates at c. At mu 1.5 the impact
    sticks (|vt*| <= mu vn*): the block stops dead at the wall, and the
    decision after the impact, from rest, holds it there (no load): v = 0
    exactly from then on."""
    a, m, cap, vn, gap = 0.03, 0.1, 1e-3, 0.2, 0.005
    sc = exdex.Scene(body=exdex.Body.box(m, (a, a, 0.02)),
                     grasp=exdex.Grasp(mu=0.5, grip_force=1e-3, patch=exdex.Patch.rectangle(0.01, 0.01)),
                     dof="planar", gravity=(0.0, 0.0, 0.0), gripper_rotation=IDENTITY, q0=(0.0, 0.0, 0.0),
                     v0=(-vn, vt, 0.0), stops=(exdex.Stop((-0.02, 0.0, 0.0), (1.0, 0.0, 0.0), mu=mu_s),))
    r = _run(sc, 0.05, 1e-3, "event")
    s0, dec = math.hypot(vn, vt), cap / m
    ts = (s0 - math.sqrt(s0 * s0 - 2 * dec * gap * s0 / vn)) / dec
    vns, vts = vn * (s0 - dec * ts) / s0, vt * (s0 - dec * ts) / s0
    vtp = vts - math.copysign(min(abs(vts), mu_s * vns), vts)
    assert r.stats["warnings"] == 0 and r.stats["impacts"] == 1
    np.testing.assert_allclose(r.stats["max_impulse"], m * vns, rtol=1e-12)
    late = r.t > ts + 1e-3
    vy = np.sign(vtp) * np.maximum(abs(vtp) - dec * (r.t[late] - ts), 0.0)
    assert np.all(r.v[late, 0] == 0.0) and np.all(r.v[late, 2] == 0.0)
    np.testing.assert_allclose(r.v[late, 1], vy, rtol=0, atol=1e-12)


def _sliding_scene(mu_s, V=(0.3, -0.2, 0.0), axis_angle=0.4, gap0=0.005):
    """1-DoF translation along d = (cos 0.4, sin 0.4) in B = A, the gripper
    moving at the constant velocity V (a log at constant speed: no inertial
    force), no gravity, the box held at rest by the plates; a floor stop
    (normal n = +y, fixed in A) gap0 below the box's lowest corner, which
    the gripper carries toward it at n.V = -0.2 m/s."""
    V = np.asarray(V, float)
    times = np.linspace(0.0, 0.2, 6)
    motion = exdex.SampledTrajectory(times, np.outer(times, V), np.tile([1.0, 0.0, 0.0, 0.0], (6, 1)),
                                     start_velocity=tuple(V), end_velocity=tuple(V))
    d = (math.cos(axis_angle), math.sin(axis_angle))
    return exdex.Scene(body=exdex.Body.box(M_BOX, (A_BOX, B_BOX, 0.02)),
                       grasp=exdex.Grasp(mu=0.5, grip_force=1.0, patch=exdex.Patch.rectangle(0.01, 0.01)),
                       dof="translation", slide_axis=d, gravity=(0.0, 0.0, 0.0), motion=motion,
                       gripper_rotation=IDENTITY,
                       stops=(exdex.Stop((0.0, -B_BOX / 2 - gap0, 0.0), (0.0, 1.0, 0.0), mu=mu_s),))


def _sliding_closed_form(mu_s, V=(0.3, -0.2, 0.0), axis_angle=0.4, gap0=0.005):
    """The 1-DoF strike of _sliding_scene: the stop reaches the resting box
    at ts = gap0 / (-n.V). The plastic impact gives the box the velocity
    vn along d with n.(vn d + V) = 0 (the corner's absolute normal
    velocity 0: vn = -n.V / n.d); the corner then slips along the floor at
    s = t.(vn d + V) (t = (-1, 0)), so the floor's friction impulse is
    -mu Pn sign(s) along t: m vn = Pn n.d - mu Pn sign(s) t.d, Pn = m vn /
    D with D = n.d - mu sign(s) t.d (frictionless: D = n.d). Returns (ts,
    Pn, D, the frictionless impulse m vn / n.d)."""
    V = np.asarray(V, float)
    d = np.array([math.cos(axis_angle), math.sin(axis_angle), 0.0])
    n, t = np.array([0.0, 1.0, 0.0]), np.array([-1.0, 0.0, 0.0])
    vn = -(n @ V) / (n @ d)
    s = t @ (vn * d + V)
    D = n @ d - mu_s * math.copysign(1.0, s) * (t @ d)
    return gap0 / -(n @ V), M_BOX * vn / D, D, M_BOX * vn / (n @ d)


@pytest.mark.parametrize("method", ["event", "regularised"])
def test_1dof_stop_strikes_resting_box_with_friction_closed_form(method):
    """The impulse of _sliding_closed_form at mu 0.2 (D > 0: 1.9 times the
    frictionless impulse), located at ts; the velocity after it is vn
    either way (one free coordinate)."""
    ts, pn, D, pn0 = _sliding_closed_form(0.2)
    assert D > 0 and pn > 1.5 * pn0
    res = _run(_sliding_scene(0.2), 0.1, 1e-3, method)
    assert res.stats["impacts"] == 1 and res.stats["warnings"] == 0
    np.testing.assert_allclose(res.stats["max_impulse_t"], ts, rtol=1e-12)
    np.testing.assert_allclose(res.stats["max_impulse"], pn, rtol=1e-12)


def test_1dof_implicit_impact_impulse_converges_to_the_law():
    """The implicit step of the strike solves the law with the plates'
    kinetic impulse c h over the step besides the stop's, so its impulse
    differs from the closed form by O(h): the error falls tenfold per
    decade of h (a step converging to the frictionless impulse, 0.53 of
    the law's here, would not)."""
    _, pn, _, _ = _sliding_closed_form(0.2)
    err = [abs(_run(_sliding_scene(0.2), 0.05, h, "implicit").stats["max_impulse"] - pn) / pn
           for h in (1e-3, 1e-4, 1e-5)]
    assert err[0] < 0.05 and err[1] < 0.15 * err[0] and err[2] < 0.15 * err[1], err


@pytest.mark.parametrize("method", ["event", "regularised", "implicit", "explicit"])
def test_1dof_frictional_impact_jam_is_frictionless_with_a_warning(method):
    """At mu 0.6 the strike has D = n.d - mu sign(s) t.d < 0: the floor's
    friction would turn the impulse's generalized direction around, no Pn
    >= 0 is consistent (an impact jam). Every method takes that impact
    frictionless (Pn = m vn / n.d) and counts a warning; the implicit step
    has the plates' kinetic impulse c h (c = 1 N) besides, which the
    frictionless stop impulse takes up along n.d: (m vn + c h) / n.d."""
    _, _, D, pn0 = _sliding_closed_form(0.6)
    assert D < 0
    h = 1e-3
    res = _run(_sliding_scene(0.6), 0.05, h, method)
    assert res.stats["warnings"] > 0
    extra = 1.0 * h / math.sin(0.4) if method == "implicit" else 0.0
    np.testing.assert_allclose(res.stats["max_impulse"], pn0 + extra, rtol=1e-12)


# ------------------------------------------------ slow impacts: every speed

def _corner_law(r, v, mu):
    """The law for the corner r (from C, in B) of the box striking the floor
    (normal (0, 1), tangent (1, 0), at rest) with velocity v, solved for
    every consistent mode (Stewart-Trinkle, plastic): rows G = (n, r x n),
    T = (t, r x t), W = M^-1, v+ = v + W (G Pn + T Pt), G v+ = 0.
      stick: T v+ = 0 too, the 2 x 2 system of _corner_impact, kept if
        |Pt| <= mu Pn;
      slide with sign sg of the slip after the impact: Pt = -mu sg Pn,
        Pn = -G v / (G W (G - mu sg T)), kept if Pn >= 0 and sg T v+ > 0
        (the slip before the impact need not have that sign: the normal
        impulse's coupling G W T can turn it).
    Returns the list of (v+, Pn, mode) of the consistent modes."""
    Mi = np.diag([1 / M_BOX, 1 / M_BOX, 1 / I_BOX])
    G = np.array([0.0, 1.0, r[0]])
    T = np.array([1.0, 0.0, -r[1]])
    A = np.array([[G @ Mi @ G, G @ Mi @ T], [T @ Mi @ G, T @ Mi @ T]])
    pn, pt = np.linalg.solve(A, -np.array([G @ v, T @ v]))
    if abs(pt) <= mu * pn:
        return [(v + Mi @ (G * pn + T * pt), pn, "stick")]
    out = []
    for sg in (1.0, -1.0):
        pn = -(G @ v) / (G @ Mi @ (G - mu * sg * T))
        vp = v + Mi @ (G - mu * sg * T) * pn
        if pn >= 0 and sg * (T @ vp) > 0:
            out.append((vp, pn, "slide"))
    return out


def _slow_strikes(n, seed):
    """n slow slanted strikes of the box's lowest corner on a frictional
    floor, drawn from a fixed stream: tilt th0 in (0.1, 0.6) rad, approach
    speed vn log-uniform in (1e-9, 1e-3) m/s, the corner's slip ct = vn
    tan(phi) (slant phi uniform in (-1.4, 1.4) rad), the box spinning at w
    (|w| 1 to 5 rad/s) about that corner, so v_C = (ct, -vn) - w (-r_y,
    r_x) is ~w |r| whatever vn; mu 0.05 to 2.5. Yields (th0, v0, r, mu,
    vn)."""
    rng = np.random.default_rng(seed)
    for _ in range(n):
        th0 = rng.uniform(0.1, 0.6)
        vn = 10.0 ** rng.uniform(-9.0, -3.0)
        phi = rng.uniform(-1.4, 1.4)
        w = rng.uniform(1.0, 5.0) * rng.choice([-1.0, 1.0])
        mu = rng.uniform(0.05, 2.5)
        r = min(_corners(th0), key=lambda p: p[1])
        v0 = np.array([vn * math.tan(phi) + w * r[1], -vn - w * r[0], w])
        yield th0, v0, r, mu, vn


@pytest.mark.parametrize("method", ["event", "regularised", "implicit", "explicit"])
def test_slow_slanted_strikes_on_a_frictional_floor_closed_form(method):
    """The touching strike of the spinning box (frictionless plates, no
    gravity, the impact at t = 0, free flight after it) at approach speeds
    from 1e-9 to 1e-3 m/s, at random slants, spins and mu (_slow_strikes):
    the law of _corner_law (one consistent mode in every scene) holds at
    every speed. The friction's share of the velocity change, v+ minus the
    frictionless v+, is ~mu vn: the error is held to 1e-6 of it (plus
    rounding of v), so a slow impact taken frictionless fails by 1e6. The
    implicit and explicit steps have no plate impulse here (mu 0): their
    first step is the law."""
    modes = set()
    for th0, v0, r, mu, vn in _slow_strikes(30, 7):
        law = _corner_law(r, v0, mu)
        assert len(law) == 1
        vp, pn, mode = law[0]
        modes.add(mode)
        (vf, _, _), = _corner_law(r, v0, 0.0)
        share = np.abs(vp - vf).max()
        assert share > 0.01 * mu * vn
        res = _run(_box_scene(th0, v0, r[1], mu), 0.002, 1e-4, method)
        assert res.stats["impacts"] == 1 and res.stats["warnings"] == 0
        np.testing.assert_allclose(res.stats["max_impulse"], pn, rtol=1e-9, atol=1e-14 * M_BOX)
        np.testing.assert_array_less(np.abs(res.v[-1] - vp), 1e-6 * share + 1e-14 * np.abs(vp) + 1e-15)
    assert modes == {"stick", "slide"}


@pytest.mark.parametrize("vn", [1e-9, 1e-7, 1e-5, 1e-3])
@pytest.mark.parametrize("method", ["event", "regularised", "implicit", "explicit"])
def test_block_sliding_slowly_into_a_frictional_wall_closed_form(method, vn):
    """The box flat on a floor stop (its lower face on it, gap 0), sliding
    along it at vt = 0.05 m/s and approaching it at vn (frictionless
    plates, gravity along the plate normal only: no in-plane force, the
    scene's velocity scale sqrt(g L) fixed while vn varies). Both corners
    of the face strike together: Pn = m vn, the friction impulse
    -sign(vt) min(m |vt|, mu m vn) at the face (its torque about C, at
    most mu Pn B / 2, is carried by the corners' split of Pn, possible
    while mu B <= A), so v+ = (vt - mu vn, 0, 0) at mu 0.3; the box then
    flies along the floor at that velocity. The friction's change mu vn is
    resolved to 1e-6 of itself."""
    mu, vt = 0.3, 0.05
    sc = exdex.Scene(body=exdex.Body.box(M_BOX, (A_BOX, B_BOX, 0.02)),
                     grasp=exdex.Grasp(mu=0.0, grip_force=1.0, patch=exdex.Patch.rectangle(0.01, 0.01)),
                     dof="planar", gravity=(0.0, 0.0, -9.81), gripper_rotation=IDENTITY, q0=(0.0, 0.0, 0.0),
                     v0=(vt, -vn, 0.0), stops=(exdex.Stop((0.0, -B_BOX / 2, 0.0), (0.0, 1.0, 0.0), mu=mu),))
    res = _run(sc, 0.002, 1e-4, method)
    assert res.stats["warnings"] == 0 and res.stats["impacts"] == 1
    np.testing.assert_allclose(res.stats["max_impulse"], M_BOX * vn, rtol=1e-9)
    assert abs(res.v[-1, 0] - (vt - mu * vn)) <= 1e-6 * mu * vn + 1e-16
    assert abs(res.v[-1, 1]) <= 1e-15 and abs(res.v[-1, 2]) <= 1e-13

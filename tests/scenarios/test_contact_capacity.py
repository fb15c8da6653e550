"""Frictional contact problems with more rows than a planar problem has
independent constraints: an outline with many vertices on one stop's line
(a face drawn with many points), several frictional stops touching at once.

In the plane at most 3 constraint rows are independent. Points on one line
of contact share the line's normal n and tangent t, so their gap rows are
G_i = (n, r_i x n) with the arm affine in the point's place along the line,
and their tangent rows coincide (t, r_i x t = r_0 x t). A force spread over
such points is a force at its centre of pressure on the segment between the
two extreme points, so a face drawn with 13 vertices must move exactly like
the same face drawn with its 2 corners. The scenes here have more rows than
the solvers enumerate one by one (8 rows of the acceleration-level problem
of the event and regularised methods, 4 candidate rows of the velocity-level
step of the implicit and explicit methods): friction must neither vanish
nor be reported as unsolved there, and the motion must be the closed form,
or the same scene drawn with the corners only.

Frames as everywhere in exdex: with the default gripper rotation B's x axis
is A's x, B's y axis is A's z (up); gravity is -9.81 along B's y. A stop's
normal (n_x, 0, n_y) in A is (n_x, n_y) in the plate plane.
"""
import math

import numpy as np
import pytest

import exdex
from test_stop_friction import _wall_closed_form

A = 0.03   # block side [m]
XW = 0.1   # wall position in A [m]


def _face_outline(n_face, side=A):
    """The square's outline (counter-clockwise) with its right face x = side/2
    drawn by n_face + 1 equally spaced vertices (n_face = 1: the square)."""
    h = side / 2
    right = [(h, -h + side * k / n_face) for k in range(n_face + 1)]
    return right + [(-h, h), (-h, -h)]


def _many_wall_scene(mu_s, n_face, V=0.01, m=0.1, mu=0.5, grip=1.5):
    """test_stop_friction's wall scene (a square block, its right face flush
    against a frictional wall fixed in A, the gripper moving toward the wall
    at V so that the plates slide past the block and press it on the wall),
    the right face drawn with n_face + 1 vertices, all on the wall."""
    body = exdex.Body.box(m, (A, A, 0.02), outline=_face_outline(n_face))
    return exdex.Scene(
        body=body,
        grasp=exdex.Grasp(mu=mu, grip_force=grip, patch=exdex.Patch.rectangle(0.02, 0.02)),
        motion=exdex.TrapezoidalProfile(amplitude=2.0 * V, duration=2.0, v_max=V, axis=(1, 0, 0)),
        dof="planar", q0=(XW - A / 2, 0.0, 0.0),
        stops=(exdex.Stop((XW, 0.0, 0.0), (-1.0, 0.0, 0.0), mu=mu_s),))


# ------------------------------------------- one face drawn with many vertices

@pytest.mark.parametrize("n_face", [8, 12])
@pytest.mark.parametrize("mu_s", [0.3, 0.5])
def test_event_many_vertex_face_on_frictional_wall_slides_at_closed_form(mu_s, n_face):
    """Sliding regime of the wall closed form (test_stop_friction's
    _wall_closed_form: m g = cap w / s + mu_s cap V / s, lam = cap V / s)
    with the face drawn by 9 or 13 vertices, every one on the wall: more
    rows than the event method's problem enumerates one by one. The face's
    total normal force carries the friction (Coulomb on the line), so the
    closed form is the same as for the two corners: speed and wall force
    to the integration tolerance, and no unsolved problem."""
    w, lam = _wall_closed_form(mu_s)
    r = exdex.simulate(_many_wall_scene(mu_s, n_face), t_end=0.3, dt=1e-3, method="event", rtol=1e-10,
                       atol=1e-12)
    assert r.stats["warnings"] == 0
    np.testing.assert_allclose(r.v[-1, 0], -0.01, rtol=1e-12)
    np.testing.assert_allclose(r.v[-1, 1], -w, rtol=1e-9)
    np.testing.assert_allclose(r.stop_force[-1, 0], lam, rtol=1e-9)


@pytest.mark.parametrize("method", ["event", "regularised"])
@pytest.mark.parametrize("mu_s", [0.8, 2.0])
def test_many_vertex_face_on_frictional_wall_holds(mu_s, method):
    """Holding regime (mu_s cap >= m g, cap = 1.5 N): the wall's friction
    sticks from the start and carries the weight, the block never moves
    down. The wall force is the plates' push along x: cap for the event
    method; cap V / sqrt(V^2 + eps^2) for the regularised one, whose plate
    friction is the smoothed law (eps its slip speed)."""
    V, cap, eps = 0.01, 1.5, 1e-4
    kw = dict(eps=eps) if method == "regularised" else {}
    r = exdex.simulate(_many_wall_scene(mu_s, 12), t_end=0.3, dt=1e-3, method=method, rtol=1e-10, atol=1e-12,
                       **kw)
    assert r.stats["warnings"] == 0
    assert np.all(np.abs(r.v[:, 1]) <= 1e-15)
    want = cap if method == "event" else cap * V / math.hypot(V, eps)
    np.testing.assert_allclose(r.stop_force[-1, 0], want, rtol=1e-9)


@pytest.mark.parametrize("method", ["event", "implicit", "explicit"])
def test_many_vertex_face_on_frictional_obstacle_wall_slides_at_closed_form(method):
    """The wall as the face of a frictional Obstacle.box (the rows of the
    13 face vertices on the obstacle's face, one line of contact): the same
    closed form as the stop (mu = 0.3, sliding regime). The implicit and
    explicit steps reach the steady state's exact balance (a fixed point of
    the step at constant velocity), the event method to its tolerance."""
    mu_s = 0.3
    w, lam = _wall_closed_form(mu_s)
    sc = exdex.replace(_many_wall_scene(mu_s, 12), stops=(),
                       obstacles=(exdex.Obstacle.box((XW + 0.5, 0.0, 0.0), (1.0, 1.0, 1.0), mu=mu_s),))
    kw = dict(rtol=1e-10, atol=1e-12) if method == "event" else {}
    r = exdex.simulate(sc, t_end=0.3, dt=1e-3, method=method, **kw)
    assert r.stats["warnings"] == 0
    np.testing.assert_allclose(r.v[-1, 0], -0.01, rtol=1e-9)
    np.testing.assert_allclose(r.v[-1, 1], -w, rtol=1e-7)
    np.testing.assert_allclose(r.stop_force[-1, 0], lam, rtol=1e-7)


# --------------------------------------- a face on a frictional floor, dragged

def _face_on_floor(n_face, mu_s, V=0.02, m=0.1, mu=0.5, grip=0.3):
    """The square lying on a frictional floor fixed in A (its bottom face,
    drawn with n_face + 1 vertices, flush on the floor), the gripper moving
    along x at V from t = 0 with the block at rest relative to the plates
    (so the block starts at V in A). Plate capacity cap = 2 mu grip = 0.3 N."""
    h = A / 2
    bottom = [(-h + A * k / n_face, -h) for k in range(n_face + 1)]
    body = exdex.Body.box(m, (A, A, 0.02), outline=bottom + [(h, h), (-h, h)])
    return exdex.Scene(
        body=body,
        grasp=exdex.Grasp(mu=mu, grip_force=grip, patch=exdex.Patch.rectangle(0.02, 0.02)),
        motion=exdex.TrapezoidalProfile(amplitude=2.0 * V, duration=2.0, v_max=V, axis=(1, 0, 0)),
        dof="planar", q0=(0.0, 0.0, 0.0), stops=(exdex.Stop((0.0, 0.0, -h), (0.0, 0.0, 1.0), mu=mu_s),))


def _floor_closed_form(t, mu_s, V=0.02, m=0.1, cap=0.3):
    """x of the block in B at t (> the stop time) when the floor can hold it
    against the plates (mu_s m g > cap). The block starts at V in A and
    slides on the floor, the plates slipping back past it (a slip purely
    along x: their friction is cap along +x, no vertical part, so the floor
    carries N = m g). Coulomb on the face's total normal force: the floor's
    friction is mu_s m g, the deceleration a = mu_s g - cap / m; the block
    stops in A after V / a, having moved V^2 / (2 a), and then the floor
    sticks (the plates' cap < mu_s m g). In B: x = V^2 / (2 a) - V t. No
    tipping: the friction's moment mu_s m g A / 2 about the centre is within
    the face's m g A / 2 for mu_s < 1."""
    a = mu_s * G_ACC - cap / m
    assert a > 0 and mu_s < 1
    return V * V / (2.0 * a) - V * t


G_ACC = 9.81


@pytest.mark.parametrize("n_face", [1, 12])
def test_event_face_dragged_on_frictional_floor_stops_at_closed_form(n_face):
    """Event method, the bottom face as 2 or 13 points (the latter beyond the
    rows enumerated one by one): the block's place in B at t = 0.3 s is the
    closed form (_floor_closed_form, mu_s = 0.8) to the integration
    tolerance, and nothing is left unsolved."""
    r = exdex.simulate(_face_on_floor(n_face, 0.8), t_end=0.3, dt=1e-3, method="event", rtol=1e-10, atol=1e-12)
    assert r.stats["warnings"] == 0
    np.testing.assert_allclose(r.q[-1, 0], _floor_closed_form(0.3, 0.8), rtol=1e-8)
    np.testing.assert_allclose(r.v[-1, 0], -0.02, rtol=1e-9)
    assert abs(r.q[-1, 2]) < 1e-9 and abs(r.q[-1, 1]) < 1e-9


@pytest.mark.parametrize("n_face", [1, 12])
def test_implicit_face_dragged_on_frictional_floor_converges_to_closed_form(n_face):
    """Implicit dt ladder on the same scene: the step is backward Euler in the
    velocity, so its error in the place at t = 0.3 s is O(dt): the place
    advances by the step's end velocity, so the jumps of the slip (the
    stop in A) are off by at most one step's travel V dt. The error must be
    below V dt (2e-5 m at dt = 1e-3 s; the stop distance is 4.1e-5 m),
    shrink by at least 1.6x per halving of dt (first order: 2x), and no step
    may fall back to frictionless stops."""
    want = _floor_closed_form(0.3, 0.8)
    errs, V = [], 0.02
    for dt in (1e-3, 5e-4, 2.5e-4):
        r = exdex.simulate(_face_on_floor(n_face, 0.8), t_end=0.3, dt=dt, method="implicit")
        assert r.stats["warnings"] == 0
        errs.append(abs(r.q[-1, 0] - want))
    assert errs[0] < V * 1e-3 and errs[1] < errs[0] / 1.6 and errs[2] < errs[1] / 1.6, errs

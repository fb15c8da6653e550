"""Shake, Pause and Chain motions: kinematics against closed forms, exact
stick under a shake below the slip threshold, continuity errors, and the
object's motion in a chained gripper motion against its closed form.

Closed forms used (derived here, not taken from the code):

* Shake: s(t) = A (1 - cos w t), w = 2 pi f, so v = A w sin w t and
  a = A w^2 cos w t for 0 <= t < D; held at s(D) afterwards.
* A chain plays each piece from the pose where the one before ended: a
  translation chain's position is the sum of the finished pieces'
  displacements plus the running piece's profile on its own clock.
* Frictionless plates (mu = 0) and no gravity: the object feels no force
  along the slide axis, so it keeps its absolute position and velocity; its
  coordinate relative to the gripper is s(t) = s0 - x(t) . d_A (d_A the
  slide axis in the world frame), its rate -v(t) . d_A, also across a
  velocity jump of the gripper (the plates cannot transmit an impulse).
* Held (stick) under a shake along the vertical slide axis: the load on
  the object in the gripper frame is m (g + a(t)) with |a| <= A w^2, so
  with a friction capacity above m (g + A w^2) the required friction never
  leaves the cone and the exact-stick methods keep q = q0 exactly.
"""
from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

import exdex

W = 2 * math.pi * 2.0   # shake of 2 Hz


def test_shake_kinematics_closed_form():
    A, D = 0.01, 1.5
    sh = exdex.Shake(A, 2.0, cycles=3, axis=(0, 0, 1))
    assert sh.duration == 1.5 and sh.end_time == 1.5
    assert sh.peak_acceleration == pytest.approx(A * W**2, rel=1e-15)
    t = np.linspace(-0.1, 2.0, 71)
    k = sh.evaluate(t)
    inside = (t >= 0) & (t < D)
    tt = np.clip(t, 0, D)
    np.testing.assert_allclose(k["p"][:, 2], A * (1 - np.cos(W * tt)), atol=1e-17)
    np.testing.assert_allclose(k["v"][:, 2], np.where(inside, A * W * np.sin(W * t), 0.0), atol=1e-15)
    np.testing.assert_allclose(k["a"][:, 2], np.where(inside, A * W**2 * np.cos(W * t), 0.0), atol=1e-13)
    assert exdex.Shake(A, 2.0, duration=1.5).cycles == 3.0
    # whole cycles: no velocity jump; a quarter cycle more: a jump of -A w at the end
    assert sh.velocity_jumps() == []
    jumps = exdex.Shake(A, 2.0, cycles=3.25, axis=(0, 0, 1)).velocity_jumps()
    assert len(jumps) == 1 and jumps[0][0] == pytest.approx(1.625, rel=1e-15)
    np.testing.assert_allclose(jumps[0][1], [0, 0, -A * W], atol=1e-14)


def test_shake_bad_input_names_the_parameter():
    with pytest.raises(ValueError, match="Shake.frequency"):
        exdex.Shake(0.01, 0.0, cycles=1)
    with pytest.raises(ValueError, match="exactly one of cycles"):
        exdex.Shake(0.01, 1.0)
    with pytest.raises(ValueError, match="exactly one of cycles"):
        exdex.Shake(0.01, 1.0, cycles=1, duration=2.0)
    with pytest.raises(ValueError, match="Shake.cycles"):
        exdex.Shake(0.01, 1.0, cycles=-1)
    with pytest.raises(ValueError, match="Pause.duration"):
        exdex.Pause(0.0)
    with pytest.raises(TypeError, match=r"Chain.pieces\[1\] is a Rest"):
        exdex.Chain([exdex.Pause(1.0), exdex.Rest()])
    with pytest.raises(TypeError, match=r"Chain.pieces\[0\] is a Chain"):
        exdex.Chain([exdex.Chain([exdex.Pause(1.0)])])
    with pytest.raises(ValueError, match="1 to 16"):
        exdex.Chain([])


def _chain():
    # trapezoid 0.1 m along z in 1 s (v_max 0.15: ramps of 1/3 s at 0.45 m/s^2),
    # a pause of 0.5 s, a 3-cycle shake of 1 cm along z
    return exdex.Chain([exdex.TrapezoidalProfile(0.1, 1.0, 0.15, axis=(0, 0, 1)), exdex.Pause(0.5),
                        exdex.Shake(0.01, 2.0, cycles=3, axis=(0, 0, 1))])


def _chain_z(t):
    """Closed form of _chain's height and vertical velocity."""
    ta, acc = 1.0 / 3.0, 0.45
    t = np.asarray(t, dtype=float)
    z = np.empty_like(t)
    v = np.empty_like(t)
    for i, x in enumerate(t):
        if x < 0:
            z[i], v[i] = 0.0, 0.0
        elif x < ta:
            z[i], v[i] = 0.5 * acc * x * x, acc * x
        elif x < 1 - ta:
            z[i], v[i] = 0.15 * (x - 0.5 * ta), 0.15
        elif x < 1:
            z[i], v[i] = 0.1 - 0.5 * acc * (1 - x) ** 2, acc * (1 - x)
        elif x < 1.5:
            z[i], v[i] = 0.1, 0.0
        elif x < 3.0:
            z[i], v[i] = 0.1 + 0.01 * (1 - math.cos(W * (x - 1.5))), 0.01 * W * math.sin(W * (x - 1.5))
        else:
            z[i], v[i] = 0.1, 0.0
    return z, v


def test_chain_kinematics_closed_form():
    ch = _chain()
    assert ch.end_time == 3.0 and ch.start_times == (0.0, 1.0, 1.5)
    t = np.linspace(-0.2, 3.5, 149)
    k = ch.evaluate(t)
    z, v = _chain_z(t)
    np.testing.assert_allclose(k["p"][:, 2], z, atol=1e-15)
    np.testing.assert_allclose(k["v"][:, 2], v, atol=1e-14)
    assert np.all(k["p"][:, :2] == 0.0)
    assert ch.velocity_jumps() == []


@pytest.mark.parametrize("method", ["event", "implicit", "regularised"])
def test_object_in_a_chained_motion_closed_form(method):
    """mu = 0, no gravity: s(t) = s0 - z(t) (the slide axis B y is A z)."""
    scene = exdex.Scene(body=exdex.Body(0.1), grasp=exdex.Grasp(mu=0.0, grip_force=1.0), motion=_chain(),
                        gravity=(0, 0, 0))
    res = exdex.simulate(scene, 3.5, 1e-3, method=method)
    z, v = _chain_z(res.t)
    # event and regularised integrate to rtol 1e-8 between the chain's
    # switches, which they step onto. The implicit scheme takes the frame's
    # mean acceleration over each step, (v(t + h) - v(t)) / h, so its
    # velocity is exact on the grid; its midpoint position update is second
    # order: a local error below h^3 max|da/dt| per step, at most
    # h^2 D max|da/dt| = h^2 D A w^3 over the shake's D = 1.5 s (the
    # trapezoid's piecewise-constant acceleration adds none on steps without
    # a switch, and O(h^2 a) at its two ramp ends inside steps).
    h = 1e-3
    tol = 1e-9 if method != "implicit" else h**2 * 1.5 * 0.01 * W**3
    np.testing.assert_allclose(res.q[:, 0], -z, atol=tol)
    np.testing.assert_allclose(res.v[:, 0], -v, atol=1e-9)


@pytest.mark.parametrize("method", ["event", "implicit"])
def test_shake_below_the_slip_threshold_holds_exactly(method):
    m, A, g = 0.1, 0.01, 9.81
    peak = A * W**2               # 1.58 m/s^2
    cap = 1.2 * m * (g + peak)    # capacity mu * 2 * F above the peak load
    grasp = exdex.Grasp(mu=0.5, grip_force=cap / (2 * 0.5))
    for motion in (exdex.Shake(A, 2.0, cycles=4, axis=(0, 0, 1)),
                   exdex.Chain([exdex.Pause(0.2), exdex.Shake(A, 2.0, cycles=2, axis=(0, 0, 1)), exdex.Pause(0.3),
                                exdex.Shake(-A, 2.0, cycles=1.5, axis=(0, 0, 1))])):
        scene = exdex.Scene(body=exdex.Body(m), grasp=grasp, motion=motion)
        res = exdex.simulate(scene, 2.5, 1e-3, method=method)
        assert np.all(res.q == res.q[0]) and np.all(res.v == 0.0) and np.all(res.stick)
    # above the threshold it slips: the check can fail
    weak = exdex.Grasp(mu=0.5, grip_force=0.8 * m * (g + peak))
    res = exdex.simulate(exdex.Scene(body=exdex.Body(m), grasp=weak,
                                     motion=exdex.Shake(A, 2.0, cycles=4, axis=(0, 0, 1))), 2.0, 1e-3, method=method)
    assert not np.all(res.q == res.q[0])


def test_chain_continuity_errors_name_the_piece():
    body, grasp = exdex.Body(0.1), exdex.Grasp(0.5, 1.0)
    # a constant speed (trapezoid without ramps) followed by a pause: the speed jumps to 0 at 1 s
    jump = exdex.Chain([exdex.Pause(0.5), exdex.TrapezoidalProfile(0.1, 1.0, 0.1, axis=(0, 0, 1)), exdex.Pause(0.5)])
    scene = exdex.Scene(body=body, grasp=grasp, motion=jump)
    with pytest.raises(ValueError, match=r"Chain.pieces\[1\] \(TrapezoidalProfile\) does not continue"):
        exdex.simulate(scene, 2.0, 1e-3)
    # a shake stopped mid-cycle
    mid = exdex.Chain([exdex.Shake(0.01, 2.0, cycles=0.25, axis=(0, 0, 1)), exdex.Pause(0.5)])
    with pytest.raises(ValueError, match=r"Chain.pieces\[1\] \(Pause\)"):
        exdex.simulate(exdex.replace(scene, motion=mid), 1.0, 1e-3)
    # an absolute log that starts 1 m away from where the chain is
    t = np.linspace(0.0, 0.3, 4)
    log = exdex.SampledTrajectory(t, np.tile([1.0, 0.0, 0.0], (4, 1)), np.tile([1.0, 0, 0, 0], (4, 1)))
    far = exdex.Chain([exdex.Pause(0.5), log])
    with pytest.raises(ValueError, match=r"Chain.pieces\[1\] \(SampledTrajectory\)"):
        exdex.simulate(exdex.replace(scene, motion=far), 1.0, 1e-3)
    # continuous: two constant-speed pieces at the same speed
    ok = exdex.Chain([exdex.TrapezoidalProfile(0.1, 1.0, 0.1, axis=(0, 0, 1)),
                      exdex.TrapezoidalProfile(0.2, 2.0, 0.1, axis=(0, 0, 1))])
    assert [j[0] for j in ok.velocity_jumps()] == [0.0, 3.0]


@pytest.mark.parametrize("method", ["event", "implicit", "explicit"])
def test_allowed_jump_is_applied_to_the_object(method):
    """allow_jump: the gripper moves at 0.1 m/s from 0.5 s to 1.5 s, its
    velocity jumping at both ends; with mu = 0 and no gravity the object
    keeps its absolute position, so s = s0 - z_gripper and the rate is
    -0.1 m/s in between, 0 after."""
    ch = exdex.Chain([exdex.Pause(0.5), exdex.TrapezoidalProfile(0.1, 1.0, 0.1, axis=(0, 0, 1)), exdex.Pause(0.5)],
                     allow_jump=True)
    scene = exdex.Scene(body=exdex.Body(0.1), grasp=exdex.Grasp(0.0, 1.0), motion=ch, gravity=(0, 0, 0))
    with warnings.catch_warnings(record=True) as rec:
        warnings.simplefilter("always")
        res = exdex.simulate(scene, 2.0, 1e-3, method=method)
    assert sorted(w.message.t for w in rec if isinstance(w.message, exdex.GripperJumpWarning)) == [0.5, 1.5]
    zg = np.clip(res.t - 0.5, 0.0, 1.0) * 0.1
    # the object never moves in the world: s = -z_gripper. The event method
    # applies each jump at its time (rounding only); the time-stepping
    # methods apply it within the step that holds it, a position error of at
    # most h |dv| = 1e-4 m (model.h)
    np.testing.assert_allclose(res.q[:, 0], -zg, atol=1e-12 if method == "event" else 1e-3 * 0.1 * (1 + 1e-9))
    i = np.searchsorted(res.t, 1.0)
    assert res.v[i, 0] == pytest.approx(-0.1, rel=1e-9)
    assert res.v[-1, 0] == pytest.approx(0.0, abs=1e-12)


def _random_chain(rng, axis, scale=1.0):
    """Pauses, whole-cycle shakes and Eq. 7 round trips along axis (every
    piece starts and ends at rest, so the chain is continuous)."""
    pieces = []
    for _ in range(int(rng.integers(2, 6))):
        kind = int(rng.integers(0, 3))
        if kind == 0:
            pieces.append(exdex.Pause(float(rng.uniform(0.02, 0.1))))
        elif kind == 1:
            pieces.append(exdex.Shake(scale * float(rng.uniform(-5e-3, 5e-3)), float(rng.uniform(1.0, 6.0)),
                                      cycles=float(rng.integers(1, 4)) / 2, axis=axis))
        else:
            pieces.append(exdex.AsymmetricProfile(scale * float(rng.uniform(-0.02, 0.02)), float(rng.uniform(0.1, 0.3)),
                                                  float(rng.uniform(0.55, 0.9)), axis=axis))
    return exdex.Chain(pieces)


@pytest.mark.parametrize("seed", range(6))
def test_random_chains_below_the_slip_threshold_hold_exactly(seed):
    """Property: a capacity above m (g + the chain's largest acceleration)
    keeps the object exactly still (q and v bit for bit) in the exact-stick
    methods, whatever the chain."""
    rng = np.random.default_rng(seed)
    motion = _random_chain(rng, (0, 0, 1))
    t = np.linspace(0, motion.end_time, 4001)
    a_max = float(np.max(np.abs(motion.evaluate(t)["a"][:, 2])))
    m = 0.1
    grasp = exdex.Grasp(mu=0.5, grip_force=1.1 * m * (9.81 + a_max) / (2 * 0.5))
    scene = exdex.Scene(body=exdex.Body(m), grasp=grasp, motion=motion)
    for method in ("implicit", "event"):
        res = exdex.simulate(scene, motion.end_time + 0.05, 1e-3, method=method)
        assert np.all(res.q == res.q[0]) and np.all(res.v == 0.0) and np.all(res.stick), method


@pytest.mark.parametrize("seed", range(4))
def test_mirrored_chain_gives_the_mirrored_slide(seed):
    """Property (mirror symmetry): without gravity, a chain along the slide
    axis and the same chain with every amplitude negated move the object by
    opposite amounts (Coulomb friction is odd in the slip velocity)."""
    rng = np.random.default_rng(100 + seed)
    state = rng.bit_generator.state
    plus = _random_chain(rng, (0, 0, 1))
    rng.bit_generator.state = state
    minus = _random_chain(rng, (0, 0, 1), scale=-1.0)
    grasp = exdex.Grasp(mu=0.4, grip_force=0.05)
    for method in ("implicit", "event"):
        a = exdex.simulate(exdex.Scene(body=exdex.Body(0.1), grasp=grasp, motion=plus, gravity=(0, 0, 0)),
                           plus.end_time, 1e-3, method=method)
        b = exdex.simulate(exdex.Scene(body=exdex.Body(0.1), grasp=grasp, motion=minus, gravity=(0, 0, 0)),
                           minus.end_time, 1e-3, method=method)
        assert np.max(np.abs(a.q)) > 1e-4   # it slides
        np.testing.assert_allclose(b.q, -a.q, rtol=0, atol=1e-12 * np.max(np.abs(a.q)) + 1e-15)

"""Static and kinetic friction (``Grasp(mu=..., mu_static=...)``): the plates
hold the object while the wrench that holds it lies in the static ellipsoid
(capacity Cs = mu_static * fingers * grip_force), a slip slides against the
kinetic one (Ck = mu * fingers * grip_force, the same shape), and a slip
sticks again where its velocity reaches 0 with the holding wrench inside the
static ellipsoid.

The closed forms are 1-DoF and planar scenes without gravity whose load comes
from the gripper's acceleration a0(t) along the slide axis: a sampled motion
whose positions are a C2 piecewise cubic (its acceleration piecewise linear),
which the motion's clamped C2 cubic spline reproduces exactly when every
breakpoint of the cubic is a sample and the end velocities are given. The
object (mass m) then feels the load Q(t) = -m a0(t) along the axis, and
    sticking:  s' = 0 while |Q| <= Cs,
    sliding:   m s'' = Q - sign(s') Ck,
with the switching times roots of linear or quadratic equations (Q is
linear in each piece).

twin: csrc/tests/scenarios/test_static_friction.c (the same subject on the C API)
"""
import math

import numpy as np
import pytest

import exdex
from exdex import AsymmetricProfile, Body, Grasp, Patch, SampledTrajectory, Scene

from zoo import random_rotation

# the planar runs turn the object off its pads on purpose (breakaway and
# symmetry checks, not grasp outcomes)
pytestmark = pytest.mark.filterwarnings("ignore::exdex.PhysicsWarning")

M = 1.0            # object mass [kg]
MU, MU_S = 0.5, 0.8
GRIP = 1.0         # two fingers: Ck = 1 N, Cs = 1.6 N
CK, CS = 2 * MU * GRIP, 2 * MU_S * GRIP


# ------------------------------------------------------------ helpers

def cubic_motion(knots, accels, t_last, n_per_piece=25):
    """A sampled motion of the gripper along B's y whose acceleration is
    linear between (knots[k], accels[k]) (a C2 piecewise cubic position,
    from rest at the origin), sampled n_per_piece times per piece up to
    t_last, with the exact end velocities. Returns the motion and the
    pieces (t0, t1, a0, slope)."""
    pieces, p, v, ts, ps = [], 0.0, 0.0, [], []
    for k in range(len(knots) - 1):
        t0, t1 = knots[k], knots[k + 1]
        a0, sl = accels[k], (accels[k + 1] - accels[k]) / (t1 - t0)
        pieces.append((t0, t1, a0, sl))
        for i in range(n_per_piece if k < len(knots) - 2 else n_per_piece + 1):
            h = (t1 - t0) * i / n_per_piece
            ts.append(t0 + h)
            ps.append(p + v * h + a0 * h * h / 2 + sl * h ** 3 / 6)
        h = t1 - t0
        p, v = p + v * h + a0 * h * h / 2 + sl * h ** 3 / 6, v + a0 * h + sl * h * h / 2
    assert knots[-1] == t_last
    pos = np.zeros((len(ts), 3))
    pos[:, 1] = ps
    quat = np.tile([1.0, 0.0, 0.0, 0.0], (len(ts), 1))
    motion = SampledTrajectory(np.array(ts), pos, quat, start_velocity=(0.0, 0.0, 0.0),
                               end_velocity=(0.0, v, 0.0), relative=True)
    return motion, pieces


def coulomb_segments(pieces, cs, ck, m=M):
    """Exact stick/slip of m s'' = Q(t) + f under the piecewise-linear load
    Q = -m a0(t), |f| <= cs at rest, f = -ck sign(s') sliding, from rest.
    Segments (t0, t1, s0, v0, acc0, jerk, stuck): s(t) = s0 + v0 h + acc0
    h^2 / 2 + jerk h^3 / 6 with h = t - t0."""
    segs, s, v, stuck, sig = [], 0.0, 0.0, True, 0.0
    for (t0, t1, a0, sl) in pieces:
        Q0, k = -m * a0, -m * sl                     # Q(t) = Q0 + k (t - t0)

        def Q(t, Q0=Q0, k=k, t0=t0):
            return Q0 + k * (t - t0)
        t = t0
        while t < t1:
            if stuck:
                # stays until |Q| reaches cs: a root of the linear Q(t) = +-cs
                roots = [t0 + (c - Q0) / k for c in (cs, -cs)] if k != 0 else []
                roots = [r for r in roots if t < r < t1]
                tb = min(roots, default=t1)
                segs.append((t, tb, s, 0.0, 0.0, 0.0, True))
                if tb < t1:
                    stuck, sig = False, math.copysign(1.0, Q(tb))
                t = tb
            else:
                acc, jerk = (Q(t) - sig * ck) / m, k / m
                # the slip stops at the first root of v + acc h + jerk h^2 / 2
                roots = np.roots([jerk / 2, acc, v]) if jerk else np.array([-v / acc] if acc else [])
                roots = [r.real for r in np.atleast_1d(roots) if abs(r.imag) < 1e-12 and 1e-13 < r.real <= t1 - t]
                te = t + min(roots) if roots else t1
                h = te - t
                segs.append((t, te, s, v, acc, jerk, False))
                s += v * h + acc * h * h / 2 + jerk * h ** 3 / 6
                v = 0.0 if roots else v + acc * h + jerk * h * h / 2
                t = te
                if roots:
                    if abs(Q(t)) <= cs:
                        stuck = True
                    else:
                        sig = math.copysign(1.0, Q(t))
    return segs


def evaluate(segs, t):
    out = np.empty(len(t))
    for i, ti in enumerate(t):
        for (t0, t1, s0, v0, a, j, _) in segs:
            if ti <= t1 + 1e-15:
                h = ti - t0
                out[i] = s0 + v0 * h + a * h * h / 2 + j * h ** 3 / 6
                break
    return out


def stuck_at(segs, t):
    return np.array([any(a < ti <= b and st for (a, b, *_, st) in segs) for ti in t])


def switch_times(segs):
    return np.array([sg[0] for sg in segs[1:]])


def scene(motion, mu_static=MU_S, dof="translation", patch=None):
    grasp = Grasp(mu=MU, grip_force=GRIP, mu_static=mu_static, **({"patch": patch} if patch else {}))
    return Scene(body=Body(mass=M), grasp=grasp, motion=motion, gravity=(0.0, 0.0, 0.0), dof=dof)


# ------------------------------------------------------------ the input

def test_mu_static_checked_and_named():
    with pytest.raises(ValueError, match=r"Grasp.mu_static must be in \[0.5, inf\)"):
        Grasp(mu=0.5, grip_force=1.0, mu_static=0.4)
    with pytest.raises(ValueError, match="Grasp.mu_static must be finite"):
        Grasp(mu=0.5, grip_force=1.0, mu_static=math.nan)
    with pytest.raises(TypeError, match="Grasp.mu_static must be a real number"):
        Grasp(mu=0.5, grip_force=1.0, mu_static="0.6")   # type: ignore[arg-type]
    g = Grasp(mu=0.5, grip_force=2.0, mu_static=0.7)
    assert g.static_mu == 0.7 and g.static_capacity == pytest.approx(2.8, abs=1e-15)
    assert Grasp(mu=0.5, grip_force=2.0).static_mu == 0.5
    assert Grasp(mu=0.0, grip_force=2.0, mu_static=0.3).static_capacity == pytest.approx(1.2, abs=1e-15)


def test_batch_parameter_and_its_range():
    """mu_static varies in a batch; it must stay >= mu (named, with the
    index); a scene without it keeps it equal to mu as mu varies (the run at
    mu = 0.7 is the one-coefficient run)."""
    sc = Scene(body=Body(mass=0.1), grasp=Grasp(mu=0.5, grip_force=1.0), v0=(0.0, 1.0, 0.0))
    b = exdex.simulate_batch(sc, 0.2, 1e-3, mu_static=[0.5, 0.6, 2.0], record="final")
    for i, ms in enumerate([0.5, 0.6, 2.0]):
        r = exdex.simulate(exdex.replace(sc, grasp=Grasp(mu=0.5, grip_force=1.0, mu_static=ms)), 0.2, 1e-3)
        assert np.array_equal(b.q[i], r.q[-1])
    with pytest.raises(ValueError, match=r"batch index 1: mu_static = 0.4 must be in \[mu, inf\)"):
        exdex.simulate_batch(sc, 0.2, 1e-3, mu_static=[0.5, 0.4])
    b = exdex.simulate_batch(sc, 0.2, 1e-3, mu=[0.7], record="final")
    r = exdex.simulate(exdex.replace(sc, grasp=Grasp(mu=0.7, grip_force=1.0)), 0.2, 1e-3)
    assert np.array_equal(b.q[0], r.q[-1])
    with pytest.raises(ValueError, match="batch index 0: mu_static"):
        exdex.simulate_batch(exdex.replace(sc, grasp=Grasp(mu=0.5, grip_force=1.0, mu_static=0.6)), 0.2, 1e-3,
                             mu=[0.7])


@pytest.mark.parametrize("fmt", ["json", "toml"])
def test_io_round_trip(tmp_path, fmt):
    sc = Scene(body=Body(mass=0.1), grasp=Grasp(mu=0.3, grip_force=1.0, mu_static=0.45))
    path = tmp_path / f"s.{fmt}"
    exdex.save_scene(sc, path)
    assert exdex.load_scene(path) == sc


# ------------------------------------------------------------ (a) breakaway under a ramp

def ramp(j=4.0, t_last=1.0):
    """a0 = j t up the slide axis: the load Q = -m j t grows down it."""
    return cubic_motion([0.0, t_last], [0.0, j * t_last], t_last, n_per_piece=100)


@pytest.mark.parametrize("method,dt,tol", [
    ("event", 1e-3, 1e-11),        # rtol 1e-8 on a smooth slip: far below
    ("implicit", 1e-3, 1e-6),      # the stick -> slip step is located within dt; O(dt^2) here
    ("implicit", 1e-4, 1e-8),
    ("explicit", 1e-3, 1e-3),      # symplectic Euler on a slip that never reverses: O(dt)
])
def test_breakaway_under_a_ramp_closed_form(method, dt, tol):
    """Q = -m j t: the object sticks until |Q| = Cs, t* = Cs / (m j) (0.4 s),
    exactly still before; then slides down against Ck, never stopping (the
    load keeps growing past Ck):
        s'(t) = -j (t^2 - t*^2) / 2 + Ck (t - t*) / m,
        s(t)  = -j ((t^3 - t*^3) / 3 - t*^2 (t - t*)) / 2 + Ck (t - t*)^2 / (2 m).
    With mu_static = mu the breakaway is at Ck / (m j) (0.25 s) instead."""
    j = 4.0
    motion, pieces = ramp(j)
    r = exdex.simulate(scene(motion), t_end=0.9, dt=dt, method=method)
    s = r.q[:, 0] - r.q[0, 0]
    ts = CS / (M * j)
    tt = np.maximum(r.t, ts)
    ref = -j / 2 * ((tt ** 3 - ts ** 3) / 3 - ts ** 2 * (tt - ts)) + CK / (2 * M) * (tt - ts) ** 2
    assert np.max(np.abs(s - ref)) <= tol
    # the independent piecewise solver agrees with the closed form
    assert np.max(np.abs(evaluate(coulomb_segments(pieces, CS, CK), r.t) - ref)) <= 1e-14
    before = r.t < ts - 1e-12
    assert np.all(r.v[before, 0] == 0.0) and np.all(s[before] == 0.0) and np.all(r.stick[1:][before[1:]])
    first_slip = r.t[1:][~r.stick[1:].astype(bool)][0]
    assert ts <= first_slip <= ts + dt + 1e-12
    if method == "explicit":
        return   # with one coefficient the sign() baseline moves from the first step (chatter)
    # one coefficient: breakaway at Ck
    r1 = exdex.simulate(scene(motion, mu_static=None), t_end=0.9, dt=dt, method=method)
    assert CK / (M * j) <= r1.t[1:][~r1.stick[1:].astype(bool)][0] <= CK / (M * j) + dt + 1e-12


def test_breakaway_regularised_first_order():
    """The regularised law (csrc/hybrid.c) holds a load inside the static
    capacity in a stick band of slip speeds |u| <= eps, viscous up to Cs,
    and slides against Ck beyond it. Against the closed form above, with
    eps0 = 1e-3 m/s (L = e_r = 0.01 m, A = Ck / m = 1 m/s^2: eps0 = 1e-2 V),
    the error is first order in eps: it falls by 3.5 .. 4.5 for each factor
    4 of eps (a smooth static-to-kinetic capacity over a speed sqrt(eps V)
    gives about 2, order 1/2). Its size: while stuck it creeps at u = eps
    Q / Cs (after the band's relaxation time m eps / Cs), which moves s by
    eps Q' t*^2 / (2 Cs) up to t* (Q' = m j); the slip then leaves the band
    at |u| = eps, a relaxation time after t*, where the exact slip has
    (Cs - Ck) / m times that time = eps (Cs - Ck) / Cs: it stays ahead by
    eps Ck / Cs in speed under the same kinetic law, so
        |error| <= eps (m j t*^2 / (2 Cs) + (Ck / Cs) (t_end - t*))."""
    j = 4.0
    motion, _ = ramp(j)
    ts = CS / (M * j)
    errs = []
    for eps in (1e-3, 2.5e-4, 6.25e-5):
        r = exdex.simulate(scene(motion), t_end=0.9, dt=1e-3, method="regularised", eps=eps)
        tt = np.maximum(r.t, ts)
        ref = -j / 2 * ((tt ** 3 - ts ** 3) / 3 - ts ** 2 * (tt - ts)) + CK / (2 * M) * (tt - ts) ** 2
        errs.append(np.max(np.abs(r.q[:, 0] - r.q[0, 0] - ref)))
        assert errs[-1] <= 1.01 * eps * (M * j * ts ** 2 / (2 * CS) + CK / CS * (0.9 - ts))
    assert 3.5 < errs[0] / errs[1] < 4.5 and 3.5 < errs[1] / errs[2] < 4.5


def test_sensitivity_to_mu_static_closed_form():
    """d s(t) / d mu_static of the ramp: s depends on mu_static only through
    t* = Cs / (m j), Cs = 2 mu_static F, and from the closed form above
    ds/dt* = (t - t*) (j t* - Ck / m) = (t - t*) (Cs - Ck) / m, so
        ds/dmu_static = (t - t*) (Cs - Ck) / m * 2 F / (m j)   (0.15 m at t = 0.9 s).
    The static coefficient is also identified from the trajectory (within
    its standard error)."""
    j = 4.0
    motion, _ = ramp(j)
    sc = scene(motion)
    ts = CS / (M * j)
    want = (0.9 - ts) * (CS - CK) / M * 2 * GRIP / (M * j)
    sens = exdex.sensitivity(sc, ["mu_static"], 0.9, method="event")
    assert sens.dq[0, 0] == pytest.approx(want, abs=1e-6)
    times = np.linspace(0.0, 0.9, 10)
    obs = exdex.simulate(sc, t_end=0.9, dt=0.1, method="event").q[:, 0]
    guess = exdex.replace(sc, grasp=exdex.replace(sc.grasp, mu_static=0.7))
    fit = exdex.identify(guess, times, obs, {"mu_static": None}, method="event")
    assert fit.values["mu_static"] == pytest.approx(MU_S, abs=1e-6)


@pytest.mark.parametrize("method", ["event", "implicit"])
def test_grip_ramp_down_breaks_away_at_the_static_capacity(method):
    """The static capacity follows a grip schedule: vertical slide (gravity g
    down, mass m), F(t) = F0 (1 - t / T1) per finger. It sticks until the
    static capacity 2 mu_s F(t) falls to m g, t* = T1 (1 - m g / (2 mu_s F0)),
    then slides against the kinetic one, s'' = -g + k (1 - t / T1),
    k = 2 mu F0 / m:
        s(t) = (k - g) tau^2 / 2 - k ((t^3 - t*^3) / 3 - t*^2 tau) / (2 T1),
    tau = t - t*. Event: its tolerances (1e-9). Implicit: the onset falls
    in the first step whose mean static capacity is below m g, at most dt
    late; the slip's acceleration jumps there from 0 to g - 2 mu F(t*) / m,
    so a late onset costs at most that times dt in speed and that times
    dt (t_end - t*) in s."""
    g, m, F0, T1 = 9.81, 0.1, 2.0, 1.0
    sched = exdex.GripSchedule(times=[0.0, T1], forces=[F0, 0.0])
    sc = Scene(body=Body(mass=m), grasp=Grasp(mu=MU, grip_force=sched, mu_static=MU_S))
    r = exdex.simulate(sc, t_end=0.8, dt=1e-4, method=method)
    ts = T1 * (1 - m * g / (2 * MU_S * F0))
    k = 2 * MU * F0 / m
    t = np.maximum(r.t, ts)
    tau = t - ts
    ref = (k - g) * tau ** 2 / 2 - k * ((t ** 3 - ts ** 3) / 3 - ts ** 2 * tau) / (2 * T1)
    tol = 1e-9 if method == "event" else (g - 2 * MU * F0 * (1 - ts / T1) / m) * 1e-4 * (0.8 - ts)
    assert np.max(np.abs(r.q[:, 0] - r.q[0, 0] - ref)) <= tol


# ------------------------------------------------------------ (b) hysteresis loop

def triangle(A=2.5, P=2.0, periods=2):
    """a0: a triangle wave, 0 -> A at P/4 -> -A at 3P/4 -> 0 at P (A = 2.5
    m/s^2 > Cs / m, so the load |Q| = m |a0| crosses the static limit)."""
    knots = [P / 4 * k for k in range(4 * periods + 1)]
    accels = [A * [0, 1, 0, -1][k % 4] for k in range(4 * periods + 1)]
    return cubic_motion(knots, accels, knots[-1])


def test_hysteresis_reference_loop():
    """The closed form of the loop itself (independent of the code): stick
    until |Q| = Cs at t = (Cs / A) P / 4 = 0.32 s; slide down; the slip stops
    at v = 0 while the load, now reversed, is |Q| = 1.035 N: above Ck but
    inside the static ellipsoid, so it sticks (with one coefficient it would
    slide straight back); it breaks away the other way at |Q| = Cs again,
    and the loop repeats with period P, shifted by nothing: the second
    breakaway is at 1.32 s and the object returns to s = 0."""
    _, pieces = triangle()
    segs = coulomb_segments(pieces, CS, CK)
    stick_starts = [sg[0] for sg in segs if sg[6] and sg[0] > 0]
    assert len(stick_starts) >= 3
    t_re = stick_starts[0]
    load = 2.5 * (t_re - 1.0) / 0.5     # Q = -m a0 on [1, 1.5]: a0 = -A (t - 1) / (P / 4)
    assert CK < load < CS
    breakaways = [sg[0] for sg in segs if not sg[6] and (segs[segs.index(sg) - 1][6])]
    assert breakaways[:3] == pytest.approx([0.32, 1.32, 2.32], abs=1e-12)
    assert evaluate(segs, [2.3])[0] == pytest.approx(0.0, abs=1e-14)


@pytest.mark.parametrize("method,dt,tol", [
    ("event", 1e-3, 1e-9),
    ("implicit", 1e-3, 1e-6),     # second order away from the switches, each located within dt
    ("implicit", 1e-4, 1e-8),
])
@pytest.mark.parametrize("dof", ["translation", "planar"])
def test_hysteresis_loop_closed_form(method, dt, tol, dof):
    """A slowly oscillating load (the triangle wave above, two periods):
    s(t) against the piecewise closed form; the stick flags agree except
    within one step of a switch; while stuck the object is exactly still.
    Planar: the same slide (patch centred: no torque, no turn); its slips
    stop under loads between Ck and Cs, where the kinetic step passes
    through zero and the static capacity holds."""
    motion, pieces = triangle()
    segs = coulomb_segments(pieces, CS, CK)
    kw = {"rtol": 1e-10, "atol": 1e-12} if method == "event" else {}
    r = exdex.simulate(scene(motion, dof=dof), t_end=3.5, dt=dt, method=method, **kw)
    s = r.q[:, 0] - r.q[0, 0] if dof == "translation" else r.q[:, 1] - r.q[0, 1]
    if dof == "planar":
        assert np.all(r.q[:, [0, 2]] == r.q[0, [0, 2]])
    assert np.max(np.abs(s - evaluate(segs, r.t))) <= tol
    near = np.min(np.abs(r.t[:, None] - switch_times(segs)[None, :]), axis=1) <= dt + 1e-12
    st = r.stick.astype(bool)
    assert np.all((st == stuck_at(segs, r.t))[1:] | near[1:])
    assert np.all(r.v[st, 0] == 0.0)
    both = st[1:] & st[:-1]
    assert np.all(s[1:][both] == s[:-1][both])


def near_stop(v_min):
    """A slip that slows to |s'| = v_min without stopping, then speeds up
    again. Acceleration knots (0, 0), (0.25, 2), (0.3, 0), (0.5, A), (1, A):
    the load Q = -m a0 passes -Cs at t = 0.2 (breakaway, sliding down),
    drops to 0 at 0.3 (the slip decelerates at (Q + Ck) / m), then falls
    through -Ck at t_m in (0.3, 0.5), where the slip is slowest and the load
    (|Q| = Ck < Cs) lies inside the static capacity. A is chosen (brentq on
    the piecewise closed form) so that s'(t_m) = -v_min. Returns the motion,
    its pieces and t_m."""
    from scipy.optimize import brentq
    knots = [0.0, 0.25, 0.3, 0.5, 1.0]

    def slowest(A):
        _, pieces = cubic_motion(knots, [0.0, 2.0, 0.0, A, A], 1.0, n_per_piece=10)
        segs = coulomb_segments(pieces, CS, CK)
        assert not any(st for (*_, st) in segs[1:]), "the slip stops"
        t0, _, _, v0, acc, jerk, _ = next(sg for sg in segs if sg[0] == 0.3)
        h = -acc / jerk                     # s'' = 0: the slowest point, Q = -Ck
        assert 0.0 < h < 0.2
        return v0 + acc * h + jerk * h * h / 2, t0 + h

    A = brentq(lambda a: slowest(a)[0] + v_min, 2.5001, 3.0, xtol=1e-14)
    motion, pieces = cubic_motion(knots, [0.0, 2.0, 0.0, A, A], 1.0, n_per_piece=100)
    return motion, pieces, slowest(A)[1]


@pytest.mark.parametrize("method", ["event", "implicit", "explicit"])
@pytest.mark.parametrize("v_min", [2e-5, 2e-4])
@pytest.mark.parametrize("dof", ["translation", "planar"])
def test_a_slip_that_only_slows_does_not_stick(method, v_min, dof):
    """Slip -> stick needs the slip to reach 0: a slip whose speed dips to
    v_min > 0 where the load is inside the static capacity (near_stop) slides
    on, however slow v_min is against the step (here below (Cs - Ck) h / m,
    the speed the static capacity could stop within one step of 1e-3 s);
    planar: the same slide (the patch centred, no torque, no turn).
    Reference: the piecewise closed form (coulomb_segments, no stick after
    the breakaway). Had the method stuck at t_m, it would stay until |Q| = Cs
    (0.1 s later), 2 mm behind. Event: to its tolerance; implicit: second
    order; explicit: first order."""
    motion, pieces, t_m = near_stop(v_min)
    segs = coulomb_segments(pieces, CS, CK)
    errs = []
    for dt in (1e-3, 5e-4):
        kw = {"rtol": 1e-10, "atol": 1e-12} if method == "event" else {}
        r = exdex.simulate(scene(motion, dof=dof), t_end=1.0, dt=dt, method=method, **kw)
        s = r.q[:, 0] - r.q[0, 0] if dof == "translation" else r.q[:, 1] - r.q[0, 1]
        if dof == "planar":
            assert np.all(r.q[:, [0, 2]] == r.q[0, [0, 2]])
        st = r.stick.astype(bool)
        assert not np.any(st[r.t > 0.25]), f"stuck at t = {r.t[st & (r.t > 0.25)][:3]} (slowest at {t_m:.4f} s)"
        errs.append(np.max(np.abs(s - evaluate(segs, r.t))))
    if method == "event":
        assert max(errs) <= 1e-9
    else:
        # implicit: the breakaway located in its step, the slip's polynomial
        # load integrated at second order; explicit: symplectic Euler, first
        # order (as in test_breakaway_under_a_ramp_closed_form)
        assert errs[0] <= (1e-6 if method == "implicit" else 1e-3), errs
        assert errs[1] <= (0.3 if method == "implicit" else 0.6) * errs[0], errs


@pytest.mark.parametrize("method", ["event", "implicit", "explicit"])
@pytest.mark.parametrize("dof", ["translation", "planar"])
def test_a_slip_stopped_by_a_load_between_the_capacities_sticks(method, dof):
    """A slip s'(0) = v0 > 0 against a constant load Q = -1.5 N (gravity
    along the slide), Ck = 1 < |Q| < Cs = 1.6: it decelerates at (|Q| + Ck)
    / m = 2.5 m/s^2, stops at t* = v0 / 2.5 at s* = v0^2 / 5 and stays there
    (the static capacity holds Q). With dt = 1e-3 s the kinetic step's
    velocity falls by 2.5e-3 m/s per step, more than the width 2 Ck h / m of
    the speeds it can end at rest, so for some v0 it passes through zero
    within a step: the slip stopped there, and must stick, not reverse.
    Several v0 (fractions of a step's fall) cover both cases. Reference: the
    closed form; s* to O(h v) (the stop's place in its step), then exactly
    still."""
    dt, g = 1e-3, 1.5
    for frac in np.linspace(0.05, 0.95, 7):
        v0 = 2.5e-3 * (20 + frac)
        sc = Scene(body=Body(mass=M), grasp=Grasp(mu=MU, grip_force=GRIP, mu_static=MU_S), motion=exdex.Rest(),
                   gravity=(0.0, 0.0, -g), dof=dof, v0=(0.0, v0, 0.0))
        kw = {"rtol": 1e-10, "atol": 1e-12} if method == "event" else {}
        r = exdex.simulate(sc, t_end=0.1, dt=dt, method=method, **kw)
        s = r.q[:, 0] - r.q[0, 0] if dof == "translation" else r.q[:, 1] - r.q[0, 1]
        ts, ss = v0 / (g + CK / M), v0 ** 2 / (2 * (g + CK / M))
        after = r.t > ts + dt
        assert np.all(r.stick[after]) and np.all(s[after] == s[-1]), (frac, s[-3:])
        assert abs(s[-1] - ss) <= (1e-9 if method == "event" else dt * v0), (frac, s[-1], ss)


def touching_stop_scene(dof, al, A):
    """An object held by static friction with a stop touching one outline
    corner, the load pointing away from the stop and between the kinetic
    and static capacities (|Q| = 1.25 C = 0.77 C_s; mu_static / mu = 1.625),
    the gripper accelerating (at most A) along the stop's plane (tilted by al
    from B's x), so the stop stays where it is in B while the gripper moves.
    rotation: pivot (the patch centre) 10 mm right of the centre of mass,
    gravity torque 0.01 m g counter-clockwise, the stop through the lower
    right corner, which that turn lifts off it; translation: slide along B's
    y, gravity down, the stop through the upper left corner (the slide
    leaves it). The gripper's inertial load (at most 0.01 m A sin(al) or m A
    sin(al)) stays within 0.15 of the gravity load, so |Q| stays in (C,
    C_s)."""
    m, g = 0.1, 9.81
    patch = Patch.disc(0.005, center=(0.01, 0.0) if dof == "rotation" else (0.0, 0.0))
    mu, mus = 0.4, 0.65
    if dof == "rotation":
        N = 0.01 * m * g / 1.25 / (mu * 2 * patch.e_r)
        n, corner, d = (-math.sin(al), math.cos(al)), (0.02, -0.01), (math.cos(al), math.sin(al))
    else:
        N = m * g / 1.25 / (mu * 2)
        n, corner, d = (math.sin(al), -math.cos(al)), (-0.02, 0.01), (math.cos(al), math.sin(al))
    vmax = 0.3
    motion = exdex.TrapezoidalProfile(amplitude=0.2, duration=vmax / A + 0.2 / vmax, v_max=vmax,
                                      axis=(d[0], 0.0, d[1]))
    # B's x, y are A's x, z at the default gripper pose
    stop = exdex.Stop((corner[0], 0.0, corner[1]), (n[0], 0.0, n[1]))
    return Scene(body=Body.box(m, (0.04, 0.02, 0.02)), grasp=Grasp(mu=mu, grip_force=N, mu_static=mus, patch=patch),
                 motion=motion, dof=dof, stops=(stop,))


@pytest.mark.parametrize("seed", range(4))
@pytest.mark.parametrize("dof", ["rotation", "translation"])
@pytest.mark.parametrize("method", ["event", "implicit", "explicit"])
def test_static_hold_beside_a_touching_stop_is_exact(method, dof, seed):
    """touching_stop_scene with al, A drawn at random (A sin(al) <= 0.15 g):
    statics (the load inside the static capacity throughout, pointing away
    from the stop) says the object never moves. Every method holds it
    exactly: q constant and v = 0 at every sample, at several dt. A stop
    whose gap is touched at the rounding level does not push it (a push of
    any speed would make the friction kinetic, which cannot hold this
    load)."""
    rng = np.random.default_rng([seed, 77])
    al = math.radians(rng.uniform(3.0, 20.0))
    A = rng.uniform(0.5, 0.15 * 9.81 / math.sin(al))
    sc = touching_stop_scene(dof, al, A)
    for dt in (1e-3, 1e-4):
        r = exdex.simulate(sc, t_end=1.0, dt=dt, method=method)
        assert np.all(r.q[:, 0] == r.q[0, 0]) and np.all(r.v == 0.0), (dt, np.abs(r.q[:, 0] - r.q[0, 0]).max())


def test_hysteresis_explicit_converges():
    """The explicit baseline over the whole loop (two breakaways, two
    re-sticks with the reversed load between Ck and Cs): it holds the load
    from rest with the static rule, breaks away at Cs, follows the kinetic
    slip (symplectic Euler) and sticks again in the step whose kinetic
    update reverses the slip (csrc/explicit.c). Each switch is then decided
    within a step, so the error is first order: it halves with dt (ratios
    1.7 .. 2.3) and stays below the largest slip speed of the closed form
    times dt. A scheme that slid on at the re-stick (load above Ck) would
    miss the second half of the loop by an amount independent of dt."""
    motion, pieces = triangle()
    segs = coulomb_segments(pieces, CS, CK)
    t = np.linspace(0.0, 3.5, 35001)
    vmax = np.max(np.abs(np.diff(evaluate(segs, t)))) / (t[1] - t[0])
    errs = []
    for dt in (1e-3, 5e-4, 2.5e-4):
        r = exdex.simulate(scene(motion), t_end=3.5, dt=dt, method="explicit")
        s = r.q[:, 0] - r.q[0, 0]
        errs.append(np.max(np.abs(s - evaluate(segs, r.t))))
        assert errs[-1] <= vmax * dt
        st = r.stick.astype(bool)
        assert np.all(r.v[st, 0] == 0.0)
        near = np.min(np.abs(r.t[:, None] - switch_times(segs)[None, :]), axis=1) <= 2 * dt + 1e-12
        assert np.all((st == stuck_at(segs, r.t))[1:] | near[1:])
    assert 1.7 < errs[0] / errs[1] < 2.3 and 1.7 < errs[1] / errs[2] < 2.3


def test_hysteresis_regularised_first_order():
    """The regularised loop (two breakaways, two re-sticks under a reversed
    load between Ck and Cs, caught in the stick band) against the closed
    form: first order in eps, the error falling by 3.5 .. 4.5 for each
    factor 4 of eps, and within eps t (the speed stays within eps of the
    exact one: the creep in the band is below eps, a breakaway starts the
    slip at |u| = eps instead of 0, a decelerating slip is caught at its
    creep speed once it enters the band)."""
    motion, pieces = triangle()
    segs = coulomb_segments(pieces, CS, CK)
    errs = []
    for eps in (1e-3, 2.5e-4, 6.25e-5):
        r = exdex.simulate(scene(motion), t_end=3.5, dt=1e-3, method="regularised", eps=eps)
        err = np.abs(r.q[:, 0] - r.q[0, 0] - evaluate(segs, r.t))
        assert np.all(err <= eps * r.t + 1e-15)
        errs.append(np.max(err))
    assert 3.5 < errs[0] / errs[1] < 4.5 and 3.5 < errs[1] / errs[2] < 4.5


@pytest.mark.parametrize("method", ["analytic", "event", "implicit", "explicit"])
def test_torsion_stick_slip_stick_closed_form(method):
    """Rotation about the centre of mass (patch centre 0), the gripper turning
    about the plate normal by Eq. 7 (theta1 0.5 rad, T 0.5 s, beta 0.8): the
    drive is the inertial torque -I dw, piecewise constant, a_H = 2 theta1 /
    (beta T^2) = 5 and a_L = 2 theta1 / ((1 - beta) T^2) = 20 rad/s^2. The
    capacities per unit inertia (I = 1e-4 kg m^2, e_r = 0.01 m, F = 0.04 N):
    c = 2 mu F e_r / I = 4, cs = 2 mu_s F e_r / I = 6.4 rad/s^2. Phase 1: a_H
    <= cs, it sticks (with one coefficient a_H > c: it would slip). Phase 2
    (0.2 s): slips at a_L - c = 16, reaching 3.2 rad/s after 0.32 rad. Phase
    3: decelerates at a_H + c = 9, stops after 3.2^2 / 18 rad (inside the
    phase) and, a_H <= cs, sticks for good: |theta| = 0.32 + 3.2^2 / 18.
    Implicit, explicit: first order, within the largest speed times dt
    (the explicit one sticks again in the step whose kinetic update reverses
    the slip, csrc/explicit.c)."""
    sc = Scene(body=Body(mass=0.1), grasp=Grasp(mu=MU, grip_force=0.04, mu_static=MU_S),
               motion=AsymmetricProfile(amplitude=0.5, duration=0.5, beta=0.8, axis=(0.0, -1.0, 0.0), rotation=True),
               dof="rotation")
    dt = 1e-3
    r = exdex.simulate(sc, t_end=1.2, dt=dt, method=method)
    want = 0.32 + 3.2 ** 2 / 18
    tol = {"analytic": 1e-14, "event": 1e-9}.get(method, 3.2 * dt)
    assert abs(r.q[-1, 0] - r.q[0, 0]) == pytest.approx(want, abs=tol)
    first = r.t < 0.4 - 1e-12
    assert np.all(r.v[first, 0] == 0.0)
    assert r.stick[-1] and r.v[-1, 0] == 0.0
    if method != "explicit":
        one = exdex.simulate(exdex.replace(sc, grasp=Grasp(mu=MU, grip_force=0.04)), t_end=0.3, dt=dt, method=method)
        assert one.v[-1, 0] != 0.0


# ------------------------------------------------------------ (c) planar breakaway

@pytest.mark.parametrize("method, mu_static", [("event", MU_S), ("event", None), ("implicit", MU_S),
                                               ("implicit", None), ("explicit", MU_S)])
def test_planar_torsion_and_force_breakaway(method, mu_static):
    """Planar object, patch centre at x = a from the centre of mass, load
    Q = -m j t along y at the centre of mass. The wrench that holds it at
    the patch is (0, m j t, -a m j t) (the load's moment about the patch
    centre, (-a, 0) x (0, -m j t) = a m j t), of ellipsoid norm
    m j t sqrt(1 + (a / e_r)^2): it breaks away at
        t* = C / (m j sqrt(1 + (a / e_r)^2)),
    C the static capacity (or Ck with one coefficient), exactly still before
    (the explicit baseline holds at rest only with mu_static > mu). The
    time-stepping methods see the step's mean load, which reaches the limit
    at most one step after t*: the first slipping step ends within 2 dt."""
    # explicit with one coefficient is left out: its sign() baseline has no rest
    j, a, er = 4.0, 0.01, 0.01
    motion, _ = ramp(j)
    sc = scene(motion, mu_static=mu_static, dof="planar", patch=Patch(e_r=er, center=(a, 0.0)))
    dt = 1e-3
    r = exdex.simulate(sc, t_end=0.6, dt=dt, method=method)
    C = CS if mu_static else CK
    ts = C / (M * j * math.sqrt(1 + (a / er) ** 2))
    st = r.stick.astype(bool)
    first_slip = r.t[1:][~st[1:]][0]
    assert ts <= first_slip <= ts + (dt if method == "event" else 2 * dt) + 1e-12
    before = r.t < ts - 1e-12
    assert np.all(r.v[before] == 0.0) and np.all(r.q[before] == r.q[0])


@pytest.mark.parametrize("method", ["implicit", "explicit"])
def test_planar_stick_slip_converges_to_event(method):
    """A shaken planar box with an offset patch (mu 0.3, mu_static 0.45),
    sticking most of the time and slipping and turning in between: the
    implicit and explicit methods' final poses approach the event method's
    (rtol 1e-11) at first order, the difference halving with dt (each switch
    is located within a step; the explicit re-stick: the step whose kinetic
    update reverses the slip or can stop it, csrc/explicit.c)."""
    sc = Scene(body=Body.box(0.1, (0.06, 0.03, 0.02)),
               grasp=Grasp(mu=0.3, grip_force=3.0, mu_static=0.45,
                           patch=Patch.rectangle(0.02, 0.02, center=(0.01, 0.0))),
               motion=AsymmetricProfile(amplitude=0.1, duration=0.5, beta=0.9, axis=(0.0, 0.0, -1.0)), dof="planar")
    e = exdex.simulate(sc, t_end=1.2, dt=1e-3, method="event", rtol=1e-11, atol=1e-13)
    assert 0.5 < e.stick.mean() < 0.95
    d = [np.abs(exdex.simulate(sc, t_end=1.2, dt=dt, method=method).q[-1] - e.q[-1]).max()
         for dt in (1e-3, 5e-4, 2.5e-4)]
    assert 1.7 < d[0] / d[1] < 2.3 and 1.7 < d[1] / d[2] < 2.3


# ------------------------------------------------------------ (d) mu_static == mu

def paper_scene(**grasp):
    return Scene(body=Body.box(0.1, (0.03, 0.16, 0.03)), grasp=Grasp(mu=0.5, grip_force=1.3, **grasp),
                 motion=AsymmetricProfile(amplitude=0.1, duration=0.5, beta=0.9, axis=(0.0, 0.0, -1.0)))


@pytest.mark.parametrize("method, dof", [(m, d) for m in ("implicit", "event", "regularised", "explicit", "analytic")
                                         for d in ("translation", "rotation", "planar")
                                         if m != "analytic" or d == "translation"])  # analytic: translation here
def test_equal_coefficients_bit_identical(method, dof):
    """mu_static = mu gives the same bits as leaving it out (the two
    capacities are one number), in every method; planar with a stop."""
    kw = {"dof": dof}
    if dof == "planar":
        kw["stops"] = (exdex.Stop(point=(0.0, 0.0, -0.12), normal=(0.0, 0.0, 1.0)),)
        kw["v0"] = (0.05, 0.0, 1.0)
    if dof == "rotation":
        kw["v0"] = (0.0, 0.0, 2.0)
    a = exdex.simulate(exdex.replace(paper_scene(), **kw), t_end=1.2, dt=1e-3, method=method)
    b = exdex.simulate(exdex.replace(paper_scene(mu_static=0.5), **kw), t_end=1.2, dt=1e-3, method=method)
    for name in ("t", "q", "v", "wrench", "stick", "stop_force"):
        assert np.array_equal(getattr(a, name), getattr(b, name)), name
    assert a.stats == b.stats


@pytest.mark.parametrize("method", ["implicit", "event", "regularised", "explicit"])
def test_equal_coefficients_bit_identical_with_a_grip_schedule(method):
    """The static capacity follows a grip schedule as the kinetic one does
    (the same ratio, 1 here): mu_static = mu is still the same bits."""
    sched = exdex.GripSchedule(times=[0.0, 0.3, 0.6], forces=[2.0, 0.5, 1.5], kind="cubic")
    a = exdex.simulate(Scene(body=Body(mass=0.1), grasp=Grasp(mu=0.5, grip_force=sched), v0=(0.0, 0.5, 0.0)),
                       t_end=0.8, dt=1e-3, method=method)
    b = exdex.simulate(Scene(body=Body(mass=0.1), grasp=Grasp(mu=0.5, grip_force=sched, mu_static=0.5),
                             v0=(0.0, 0.5, 0.0)), t_end=0.8, dt=1e-3, method=method)
    for name in ("q", "v", "wrench", "stick"):
        assert np.array_equal(getattr(a, name), getattr(b, name)), name


# ------------------------------------------------------------ properties

def random_scene(rng, dof):
    """Gripper at rest, gravity g along B's -y (A's -z) or in a random plane
    direction; random mu, mu_static >= mu, grip, initial velocity."""
    mu = float(rng.uniform(0.0, 1.0))
    ms = mu + float(rng.uniform(0.0, 1.0)) * float(rng.integers(0, 2))
    body = Body.box(0.1, (0.06, 0.03, 0.02))
    return Scene(body=body, grasp=Grasp(mu=mu, grip_force=float(rng.uniform(0.0, 3.0)), mu_static=ms,
                                        patch=Patch.rectangle(0.02, 0.02, center=(float(rng.uniform(-0.01, 0.01)), 0.0))),
                 dof=dof, v0=(float(rng.uniform(-0.5, 0.5)), float(rng.uniform(-0.5, 0.5)), float(rng.uniform(-5, 5))))


@pytest.mark.parametrize("seed", range(10))
@pytest.mark.parametrize("method", ["event", "implicit"])
@pytest.mark.parametrize("dof", ["translation", "planar"])
def test_friction_never_adds_energy_and_stick_is_still(seed, method, dof):
    """Gripper at rest: E = kinetic + m g y (B's y up) never increases (the
    plates dissipate; static friction does no work); a sample flagged stick
    has v == 0 exactly, and consecutive stuck samples the same q. For the
    implicit method gravity lies along the plate normal (only friction acts
    in the plane, E is the kinetic energy): its midpoint position update
    moves the object h v / 2 in the step that stops it, an O(h^2) change
    of the potential energy that is the scheme's, not the friction's."""
    rng = np.random.default_rng(seed)
    sc = random_scene(rng, dof)
    if method == "implicit":
        sc = exdex.replace(sc, gravity=(0.0, 9.81, 0.0))
    r = exdex.simulate(sc, t_end=0.5, dt=2e-3, method=method)
    izz = np.array(sc.body.inertia)[2, 2]
    g = 9.81 if method == "event" else 0.0
    if dof == "translation":
        E = 0.5 * 0.1 * r.v[:, 0] ** 2 + 0.1 * g * r.q[:, 0]
    else:
        E = 0.5 * 0.1 * (r.v[:, 0] ** 2 + r.v[:, 1] ** 2) + 0.5 * izz * r.v[:, 2] ** 2 + 0.1 * g * r.q[:, 1]
    scale = 0.1 * (0.5 ** 2 + 9.81 * 0.1) + izz * 25
    assert np.all(np.diff(E) <= 1e-9 * scale), np.max(np.diff(E))
    st = r.stick.astype(bool)
    assert np.all(r.v[st] == 0.0)
    both = st[1:] & st[:-1]
    assert np.all(r.q[1:][both] == r.q[:-1][both])


@pytest.mark.parametrize("seed", range(6))
@pytest.mark.parametrize("method", ["event", "implicit"])
def test_mirror_symmetry(seed, method):
    """Reflecting the scene in B's y-z plane (x -> -x: the patch centre, the
    initial x, theta and their rates change sign; the inertia, a box's, is
    unchanged) reflects the motion: x -> -x, y -> y, theta -> -theta."""
    rng = np.random.default_rng(50 + seed)
    sc = random_scene(rng, "planar")
    pc = sc.grasp.patch.center
    mir = exdex.replace(sc, grasp=exdex.replace(sc.grasp, patch=Patch(e_r=sc.grasp.patch.e_r, center=(-pc[0], pc[1]))),
                        v0=(-sc.v0[0], sc.v0[1], -sc.v0[2]))
    a = exdex.simulate(sc, t_end=0.4, dt=2e-3, method=method)
    b = exdex.simulate(mir, t_end=0.4, dt=2e-3, method=method)
    flip = np.array([-1.0, 1.0, -1.0])
    tol = 1e-9 if method == "event" else 1e-12
    assert np.allclose(b.q, a.q * flip, rtol=0, atol=tol * 10)
    assert np.allclose(b.v, a.v * flip, rtol=0, atol=tol * 100)
    assert np.array_equal(a.stick, b.stick)


# ------------------------------------------------------------ at rest against a stop


def stop_rest_scene(rng, mu_static, push=0.5, pull=1.3, t_end=1.0):
    """A box in a 1-DoF translation grasp with a random gripper rotation R0,
    slide axis e (random, in B) and a stop fixed in A whose trace in the
    plate plane has the in-plane normal nB (random, |nB . e| >= 0.3; the
    stop plane tilted out of the plates by a random nz), the box touching it
    at t = 0, at rest. No gravity; the gripper translates along the trace's
    tangent tB with an acceleration linear in time, so the trace is fixed in
    B (R0 tB lies in the stop plane) and the load along e is Q(t) = -m a(t)
    (tB . e). Its component toward the stop, P(t) = P0 - k t (P0 = push Ck,
    reaching -pull Cs at t_end), first presses the box on the stop and then
    pulls it away. Returns (scene, the unit of q toward the stop (+-1), P0,
    k)."""
    R0 = random_rotation(rng)
    al = rng.uniform(0.0, 2.0 * math.pi)
    e = np.array([math.cos(al), math.sin(al)])
    while True:
        be = rng.uniform(0.0, 2.0 * math.pi)
        nB = np.array([math.cos(be), math.sin(be)])
        if abs(nB @ e) >= 0.3:
            break
    tB = np.array([-nB[1], nB[0], 0.0])
    nW = R0 @ np.array([nB[0], nB[1], rng.uniform(-0.5, 0.5)])
    nW /= np.linalg.norm(nW)
    body = Body.box(M, (0.03, 0.02, 0.01))
    p0 = rng.uniform(-0.1, 0.1, size=3)
    xs = np.array([p0 + R0 @ np.array([vx, vy, 0.0]) for vx, vy in body.vertices()])
    point = xs[np.argmin(xs @ nW)]                    # the nearest vertex touches: gap 0
    into = -math.copysign(1.0, nB @ e)               # d gap / dq = nB . e: q toward the stop
    cs = CK * mu_static / MU
    P0, k = push * CK, (push * CK + pull * cs) / t_end
    # P = -m a (tB . e) into  =>  a(t) = -(P0 - k t) / (m (tB . e) into)
    c = -1.0 / (M * (tB[:2] @ e) * into)
    a0, a1 = c * P0, -c * k
    ts = np.linspace(0.0, t_end, 41)
    pos = np.outer(a0 * ts ** 2 / 2 + a1 * ts ** 3 / 6, tB)  # displacements along tB, in B
    motion = SampledTrajectory(ts, pos, np.tile([1.0, 0.0, 0.0, 0.0], (len(ts), 1)),
                               start_velocity=(0.0, 0.0, 0.0),
                               end_velocity=tuple((a0 * t_end + a1 * t_end ** 2 / 2) * tB), relative=True)
    sc = Scene(body=body, grasp=Grasp(mu=MU, grip_force=GRIP, mu_static=mu_static), motion=motion,
               gravity=(0.0, 0.0, 0.0), dof="translation", slide_axis=tuple(e),
               gripper_rotation=tuple(map(tuple, R0)), gripper_position=tuple(p0),
               stops=(exdex.Stop(tuple(point), tuple(nW)),))
    return sc, into, P0, k


@pytest.mark.parametrize("mu_static", [MU, MU_S])
@pytest.mark.parametrize("seed", range(10))
def test_rest_against_a_stop_fixed_in_B_breaks_away_at_the_static_capacity(seed, mu_static):
    """The box of stop_rest_scene rests on the stop while it presses on it
    (the stop carries P > 0) and, pulled away, while the plates can hold
    the pull (-P <= Cs, static friction: the box at rest on the plates); it
    leaves at t_b = (P0 + Cs) / k and slides away against Ck:
        m s'' = -P - Ck = k (t - t_b) + Cs - Ck   (s its distance from the stop),
        s(t) = ((Cs - Ck) h^2 / 2 + k h^3 / 6) / m,  h = t - t_b.
    The stop's trace is fixed in B by construction, so the stop's
    acceleration along q is rounding (a few ulps of the rotated kinematics):
    the rest must be decided as a rest (static friction), not as a contact
    sliding along with the stop, whose kinetic friction of a sign set by
    rounding ended it at Ck, (Cs - Ck) / k = 0.23 s early with Cs = 1.6 Ck,
    on some of these rotations). The event method to its rtol, the implicit
    one to O(dt) (it places the break-away at a step end)."""
    rng = np.random.default_rng([seed, 0x51])
    sc, into, P0, k = stop_rest_scene(rng, mu_static)
    cs = CK * mu_static / MU
    tb = (P0 + cs) / k
    for method, dt, tol in (("event", 1e-2, 1e-9), ("implicit", 1e-3, 2e-4)):
        r = exdex.simulate(sc, t_end=1.0, dt=dt, method=method)
        h = np.maximum(r.t - tb, 0.0)
        s = ((cs - CK) * h ** 2 / 2 + k * h ** 3 / 6) / M
        got = -(r.q[:, 0] - r.q[0, 0]) * into
        assert np.max(np.abs(got - s)) <= tol * (1.0 + np.max(s)), (method, np.max(np.abs(got - s)))
        still = r.t < tb - dt
        assert np.all(np.abs(got[still]) <= 1e-12), (method, np.max(np.abs(got[still])))


# ------------------------------------------------------------ a held load stepping inside the static ellipsoid


def held_step_scene(rng, f0=0.8, f1=0.97):
    """A planar box (mass M, random sides, centre of pressure pc off the
    centre of mass, torsional semi-axis e_r) held under gravity in a random
    in-plane direction, the grip set so that the gravity load is f0 Cs;
    after a pause a one-cycle Shake along an in-plane direction d, whose
    acceleration jumps from 0 to a0 = A (2 pi f)^2 at its start (and then
    runs through +-a0), with a0 the largest for which the load stays inside
    f1 Cs over the whole cycle. The load is linear in the gripper's
    acceleration (translation only): the generalized force F = M (g - a),
    held by the patch wrench w = -(F_x, F_y, pc_y F_x - pc_x F_y) (about the
    centre of pressure), |E^-1 w| = |(w_x, w_y, w_z / e_r)|.

    d (and its sign) is the one, of 36, whose step the regularised stick
    band turns into the largest excursion of the slip speed: in the band
    (w = -Cs E^2 u / eps) z = E u relaxes as z' = -(Cs / eps) S (z - z*) with
    S = E J M^-1 J^T E symmetric (J: qd -> u), z* = eps E^-1 w / Cs the
    creep of the new load; each of S's eigencomponents moves monotonically
    from the old creep to the new, so |z| can pass max(|z0|, |z*|) when the
    load turns (up to sqrt(|z0|^2 + |z*|^2)): past eps for a load still
    inside Cs. Scenes are drawn until that excursion (of this linear model)
    exceeds 1.02 eps. Returns (scene, t_end, e_r, pc)."""
    while True:
        a, b = rng.uniform(0.02, 0.05, size=2)
        pc = rng.uniform(-0.4, 0.4, size=2) * (a, b)
        er = rng.uniform(0.1, 0.4) * min(a, b)
        J = np.array([[1.0, 0.0, -pc[1]], [0.0, 1.0, pc[0]], [0.0, 0.0, 1.0]])
        E = np.diag([1.0, 1.0, er])
        S = E @ J @ np.diag([1 / M, 1 / M, 12 / (M * (a * a + b * b))]) @ J.T @ E
        lam, Qs = np.linalg.eigh(S)

        def z(F):
            return -np.array([F[0], F[1], (pc[1] * F[0] - pc[0] * F[1]) / er])
        th = rng.uniform(0.0, 2.0 * math.pi)
        g = 9.81 * np.array([math.cos(th), math.sin(th)])
        cs = np.linalg.norm(z(M * g)) / f0
        z0 = z(M * g) / cs
        ts = np.linspace(0.0, 10.0 / lam[0], 400)
        best = (0.0, None, 0.0)
        for ph in np.linspace(0.0, math.pi, 36, endpoint=False):
            d = np.array([math.cos(ph), math.sin(ph)])
            lo, hi = 0.0, 100.0
            for _ in range(50):
                s = (lo + hi) / 2
                ok = max(np.linalg.norm(z(M * (g - s * d))), np.linalg.norm(z(M * (g + s * d)))) <= f1 * cs
                lo, hi = (s, hi) if ok else (lo, s)
            for sg in (1.0, -1.0):
                zs = z(M * (g - sg * lo * d)) / cs
                path = zs[:, None] + Qs @ (np.exp(-np.outer(ts, lam)) * (Qs.T @ (z0 - zs))).T
                over = float(np.max(np.linalg.norm(path, axis=0)))
                if over > best[0]:
                    best = (over, d, sg * lo)
        if best[0] > 1.02:
            break
    _, d, a0 = best
    f = rng.uniform(5.0, 20.0)
    T0 = 0.05
    motion = exdex.Chain((exdex.Pause(T0), exdex.Shake(a0 / (2 * math.pi * f) ** 2, f, cycles=1.0,
                                                       axis=(d[0], 0.0, d[1]))))
    # default gripper rotation: B's (x, y) is A's (x, z)
    sc = Scene(body=Body.box(M, (a, b, 0.01)),
               grasp=Grasp(mu=MU, grip_force=cs / (2 * MU_S), mu_static=MU_S, patch=Patch(e_r=er, center=tuple(pc))),
               motion=motion, gravity=(g[0], 0.0, g[1]), dof="planar")
    return sc, T0 + 1.0 / f, er, pc


@pytest.mark.parametrize("seed", range(4))
def test_held_load_step_inside_the_static_capacity_planar(seed):
    """held_step_scene: the load stays inside f1 Cs < Cs throughout, so the
    exact motion is at rest (the event method: still, q exactly q0). The
    regularised method holds it by its stick band: the slip speed |E u| is
    at most eps there (and beyond it only while a step's transient relaxes,
    for a relaxation time M eps / Cs, with the friction at Cs, held), so the
    pose moves by at most ~ eps t_end per unit of (1 + |pc| / e_r) (the
    centre of mass moves at the patch's speed plus omega |pc|, omega <= eps
    / e_r); the check allows twice that. A band that dropped to Ck as soon
    as the transient left it (|E u| > eps) broke away at the step at every
    eps (35 to 180 times the allowance at eps = 1e-4 m/s)."""
    rng = np.random.default_rng([seed, 0x52])
    sc, t_end, er, pc = held_step_scene(rng)
    ev = exdex.simulate(sc, t_end, t_end / 16, method="event")
    assert np.all(ev.stick[1:]) and np.all(ev.q == ev.q[0])
    for eps in (1e-3, 1e-4):
        r = exdex.simulate(sc, t_end, t_end / 16, method="regularised", eps=eps)
        dq = np.abs(r.q - r.q[0])
        moved = max(np.max(dq[:, 0]), np.max(dq[:, 1]), np.max(dq[:, 2]) * er)
        assert moved <= 2.0 * eps * t_end * (1.0 + math.hypot(*pc) / er), (eps, moved)


@pytest.mark.parametrize("v0", [0.7, 0.53, 1.1])
@pytest.mark.parametrize("dt", [0.03, 0.007, 0.0013])
def test_explicit_reversal_beyond_the_static_capacity_closed_form(v0, dt):
    """1-DoF translation thrown up its slide axis at v0 against a constant
    load Q = -m g (g = 2.5 m/s^2, |Q| = 2.5 N > Cs = 1.6 N > Ck = 1 N): it
    slides up against Ck, s' = v0 - (|Q| + Ck) t / m, stops at t_r = m v0 /
    (|Q| + Ck), where the static capacity cannot hold the load, and slides
    back down against Ck: s' = -(|Q| - Ck) (t - t_r) / m. Under a constant
    load the explicit step's velocity is exact at every step end (the
    step's mean force is exact) once the step holding t_r is split there
    (kinetic friction of the other sign beyond the stop); keeping the
    step-start friction beyond it left the velocity 2 Ck (h - tau) / m off
    for the rest of the run (tau the stop's offset in its step), set by
    where the grid falls relative to t_r, so a nested dt ladder could show
    no difference while the error stayed. Positions: symplectic Euler,
    within h |s'| max of the exact one."""
    g = 2.5
    sc = Scene(body=Body(mass=M), grasp=Grasp(mu=MU, grip_force=GRIP, mu_static=MU_S), motion=exdex.Rest(),
               gravity=(0.0, 0.0, -g), dof="translation", v0=(0.0, v0, 0.0))
    t_end = 0.6
    r = exdex.simulate(sc, t_end=t_end, dt=dt, method="explicit")
    tr = M * v0 / (M * g + CK)
    ve = np.where(r.t <= tr, v0 - (M * g + CK) * r.t / M, -(M * g - CK) * (r.t - tr) / M)
    se = np.where(r.t <= tr, v0 * r.t - (M * g + CK) * r.t ** 2 / (2 * M),
                  v0 * tr / 2 - (M * g - CK) * (r.t - tr) ** 2 / (2 * M))
    assert np.max(np.abs(r.v[:, 0] - ve)) <= 1e-12, np.max(np.abs(r.v[:, 0] - ve))
    assert np.max(np.abs(r.q[:, 0] - r.q[0, 0] - se)) <= dt * max(v0, (M * g - CK) * (t_end - tr) / M)

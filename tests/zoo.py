"""The scene zoo: seeded random scenes of the kind users write.

``zoo_scene(seed)`` returns a :class:`ZooScene`: a valid ``exdex.Scene``, a
sensible ``t_end`` and the scene's own length scale, all a pure function of
the seed (NumPy's PCG64 seeded with it), so a failing seed is a complete
reproducer: ``zoo_scene(1234).scene``.

Coverage (each drawn independently per seed):

* free coordinates: ``"translation"`` (random slide axis in the plate plane),
  ``"rotation"`` (about the patch's centre of pressure) and ``"planar"``;
* gripper motions: at rest; paper Eq. 7 (``AsymmetricProfile``) and
  trapezoidal velocity profiles, translating along or turning about an
  arbitrary (tilted) axis through an arbitrary centre; sampled logs
  (``SampledTrajectory``): minimum-jerk moves chained with rest periods
  (holds at the start, between the moves and at the end), smooth or with
  measurement noise, some ending while still moving;
* the gripper's initial orientation: the default (plates vertical) or a
  random rotation;
* 0, 1 or 2 stops (``Stop``) placed just outside the initial outline (a gap
  from 0, touching, to a third of the object size), with normals the object
  can always give way to (below);
* grip force per finger from 0.5 to 5 times the object's weight, friction
  coefficient 0.2 to 1, one or two fingers, so that the object sticks,
  slips, or alternates;
* pressure patches (disc, rectangle or a given e_r) centred off the centre
  of mass, inside the outline;
* box bodies, some with tilted principal axes of inertia, some with a
  hexagonal outline;
* gravity of 9.81 m/s^2 tilted from the world's -z by up to 30 degrees, or
  in a random direction;
* objects from 1 mm to 1 m: every scene is drawn in units of its length
  scale ``L`` (log-uniform in [1e-3, 1] m) and its time scale
  ``tau = sqrt(L / g)`` (Froude scaling: lengths x L, times x tau, speeds
  x L/tau, accelerations x g), so a 1 mm scene and a 1 m scene are equally
  eventful; the mass follows a density of 200 to 8000 kg/m^3;
* initial relative velocities (in 40 % of the scenes) up to 0.5 L/tau and
  0.5 /tau.

Validity ("the API accepts it and it is physically meaningful"):

* the object never starts inside a stop: every outline vertex is on the
  allowed side at t = 0 (gap >= 0, recomputed here from the pose);
* a stop can always be given way to, so no scene demands an infinite force:
  its normal, seen in the gripper frame, keeps an in-plane component along a
  free direction of the object throughout the motion (the motion is sampled
  and checked). Planar: |n_B in plane| >= 0.3 and, with two stops, the two
  in-plane normals at most 135 degrees apart (they never pinch the object).
  Translation: |n_B . slide_axis| >= 0.3 with a constant sign, and both
  stops on the same side (n . axis of the same sign). Rotation (the object is
  pinned to the gripper): stops only when the stop does not move in the
  gripper frame (gripper at rest, or translating parallel to the stop
  plane), so staying still is always possible;
* sampled logs are absolute poses, so the scene's ``gripper_rotation`` and
  ``gripper_position`` are set to the log's first sample (what the gripper
  really is at t = 0).

``t_end`` is the end of the motion plus a settling time of 1 to 3 tau,
short enough for a test suite (the scenes stay eventful: slips start and
stop, stops are hit and rested on).
"""
from __future__ import annotations

import math
import os
import sys
import warnings
from dataclasses import dataclass

import numpy as np

import exdex

from expected_warnings import ALL, by_design

G = 9.81
DOFS = ("translation", "rotation", "planar")
MOTIONS = ("rest", "asym", "trap", "log")


@dataclass(frozen=True)
class ZooScene:
    """One zoo draw.

    scene : the exdex.Scene.
    t_end : a sensible end time [s].
    L : the scene's length scale [m] (the body's largest in-plane size).
    tau : its time scale sqrt(L / g) [s].
    radius : largest distance of an outline vertex from the centre of mass
        [m], the lever arm that turns an angle error into a length.
    tags : what was drawn (dof, motion kind, stops, ...), for reports.
    """

    seed: int
    scene: exdex.Scene
    t_end: float
    L: float
    tau: float
    radius: float
    tags: dict

    def __repr__(self):
        return f"ZooScene(seed={self.seed}, t_end={self.t_end:.4g}, L={self.L:.3g}, tags={self.tags})"


def _unit(v):
    v = np.asarray(v, dtype=float)
    return v / np.linalg.norm(v)


def _random_direction(rng):
    while True:
        v = rng.normal(size=3)
        n = np.linalg.norm(v)
        if n > 1e-3:
            return v / n


def _rotation(axis, angle):
    """Rodrigues: rotation by angle about the unit axis."""
    k = _unit(axis)
    K = np.array([[0.0, -k[2], k[1]], [k[2], 0.0, -k[0]], [-k[1], k[0], 0.0]])
    return np.eye(3) + math.sin(angle) * K + (1.0 - math.cos(angle)) * (K @ K)


def random_rotation(rng):
    """A uniformly random rotation matrix: the unit quaternion of four normal draws of rng."""
    q = rng.normal(size=4)
    w, x, y, z = q / np.linalg.norm(q)
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def _quat(R):
    """(w, x, y, z) of a rotation matrix (Shepperd), independent of exdex."""
    tr = np.trace(R)
    if tr > 0:
        s = 2.0 * math.sqrt(tr + 1.0)
        return np.array([0.25 * s, (R[2, 1] - R[1, 2]) / s, (R[0, 2] - R[2, 0]) / s, (R[1, 0] - R[0, 1]) / s])
    i = int(np.argmax(np.diag(R)))
    j, k = (i + 1) % 3, (i + 2) % 3
    s = 2.0 * math.sqrt(1.0 + R[i, i] - R[j, j] - R[k, k])
    q = np.empty(4)
    q[0] = (R[k, j] - R[j, k]) / s
    q[1 + i] = 0.25 * s
    q[1 + j] = (R[j, i] + R[i, j]) / s
    q[1 + k] = (R[k, i] + R[i, k]) / s
    return q


def _min_jerk(s):
    """Minimum-jerk blend 10 s^3 - 15 s^4 + 6 s^5 on [0, 1] (rest to rest)."""
    s = np.clip(s, 0.0, 1.0)
    return s**3 * (10.0 - 15.0 * s + 6.0 * s * s)


# ---------------------------------------------------------------- pieces

def _body(rng, L):
    """A box of in-plane size L x (0.3..1) L, thickness (0.2..1) L; density
    200..8000 kg/m^3; sometimes tilted principal axes or a hexagonal outline."""
    ly = L * rng.uniform(0.3, 1.0)
    lz = L * rng.uniform(0.2, 1.0)
    size = (L, ly, lz)
    if rng.random() < 0.5:
        size = (ly, L, lz)
    mass = float(rng.uniform(200.0, 8000.0) * L * ly * lz)
    body = exdex.Body.box(mass, size)
    kind = "box"
    if rng.random() < 0.25:
        R = random_rotation(rng)
        I = R @ np.array(body.inertia) @ R.T
        body = exdex.Body(mass=mass, inertia=0.5 * (I + I.T), size=size)
        kind = "box-tilted-inertia"
    if rng.random() < 0.2:
        hx, hy = size[0] / 2, size[1] / 2
        outline = tuple((hx * math.cos(a), hy * math.sin(a)) for a in np.arange(6) * math.pi / 3)
        body = exdex.Body(mass=mass, inertia=body.inertia, size=size, outline=outline)
        kind = "hexagon"
    return body, kind


def _grasp(rng, body, L):
    """mu 0.2..1, grip per finger 0.5..5 m g, a patch off the centre of mass."""
    hx, hy = body.size[0] / 2, body.size[1] / 2
    center = (float(rng.uniform(-0.6, 0.6) * hx), float(rng.uniform(-0.6, 0.6) * hy))
    kind = rng.choice(["disc", "rectangle", "given"])
    small = min(hx, hy)
    if kind == "disc":
        patch = exdex.Patch.disc(small * rng.uniform(0.1, 0.6), center=center)
    elif kind == "rectangle":
        patch = exdex.Patch.rectangle(2 * hx * rng.uniform(0.1, 0.6), 2 * hy * rng.uniform(0.1, 0.6), center=center)
    else:
        patch = exdex.Patch(e_r=float(small * rng.uniform(0.05, 0.5)), center=center)
    mu = float(rng.uniform(0.2, 1.0))
    ratio = float(math.exp(rng.uniform(math.log(0.5), math.log(5.0))))
    fingers = 2 if rng.random() < 0.85 else 1
    return exdex.Grasp(mu=mu, grip_force=ratio * body.mass * G, patch=patch, fingers=fingers), ratio


def _parametric_motion(rng, kind, L, tau, rotate, axis, center):
    """Eq. 7 or trapezoid; translations of (0.05..0.5) g T^2, turns of 0.2..1.5 rad."""
    T = float(tau * rng.uniform(3.0, 10.0))
    if rotate:
        amp = float(rng.uniform(0.2, 1.5) * rng.choice([-1.0, 1.0]))
    else:
        amp = float(rng.uniform(0.05, 0.5) * G * T * T * rng.choice([-1.0, 1.0]))
    if kind == "asym":
        return exdex.AsymmetricProfile(amp, T, float(rng.uniform(0.3, 0.9)), axis=tuple(axis), rotation=rotate,
                                       center=tuple(center))
    return exdex.TrapezoidalProfile(amp, T, abs(amp) / T * float(rng.uniform(1.05, 1.95)), axis=tuple(axis),
                                    rotation=rotate, center=tuple(center))


def _log_motion(rng, L, tau, R0, p0, rotate_axes, translate_axes, noisy, end_moving):
    """A robot log: 1-3 minimum-jerk moves (translation along a drawn axis
    and/or a turn about a drawn axis through a drawn centre) chained with rest
    periods, sampled at 20-60 samples per tau; Gaussian noise of 0.02 g h^2
    (h the sample spacing, so the spline's accelerations stay ~0.1 g) on the
    positions and the matching angle on the orientations; optionally cut
    while the last move is under way."""
    n_moves = int(rng.integers(1, 4))
    segments = []  # (kind, duration)
    segments.append(("hold", float(tau * rng.uniform(0.3, 1.0))))
    for i in range(n_moves):
        segments.append(("move", float(tau * rng.uniform(2.0, 5.0))))
        if i < n_moves - 1 or not end_moving:
            segments.append(("hold", float(tau * rng.uniform(0.3, 1.5))))
    total = sum(d for _, d in segments)
    rate = rng.uniform(20.0, 60.0) / tau
    n = max(8, int(total * rate) + 1)
    t = np.linspace(0.0, total, n)
    h = t[1] - t[0]
    disp = np.zeros((n, 3))
    R = np.repeat(R0[None], n, axis=0)
    t0 = 0.0
    for kind, d in segments:
        if kind == "move":
            cut = end_moving and (t0 + d >= total - 1e-12 * total)
            s = _min_jerk((t - t0) / (d / 0.6 if cut else d))  # the last move cut at 60 %
            if translate_axes is not None:
                ax = translate_axes(rng)
                step = float(rng.uniform(0.05, 0.3) * G * d * d * rng.choice([-1.0, 1.0]))
                disp += np.outer(s, step * ax)
            if rotate_axes is not None:
                ax, c = rotate_axes(rng)
                ang = float(rng.uniform(0.2, 1.0) * rng.choice([-1.0, 1.0]))
                for k in range(n):
                    if s[k] > 0.0:
                        Q = _rotation(ax, ang * s[k])
                        R[k] = Q @ R[k]
                        disp[k] = Q @ (disp[k] + p0 - c) + c - p0
        t0 += d
    if noisy:
        sigma = 0.02 * G * h * h
        disp += rng.normal(scale=sigma, size=disp.shape)
        for k in range(n):
            R[k] = _rotation(_random_direction(rng), rng.normal(scale=sigma / L)) @ R[k]
    quats = np.array([_quat(Rk) for Rk in R])
    with warnings.catch_warnings():
        if noisy:
            # noisy by design: where a move or turn is small, 0.02 g h^2 of noise dominates its
            # accelerations (exdex.NoisyLogWarning); the zoo runs the log as logged
            warnings.simplefilter("ignore", exdex.NoisyLogWarning)
        log = exdex.SampledTrajectory(times=t, positions=p0 + disp, quaternions=quats)
    return log, total


def _outline_world(body, q0, R0, p0):
    c, s = math.cos(q0[2]), math.sin(q0[2])
    return np.array([p0 + R0 @ np.array([q0[0] + c * vx - s * vy, q0[1] + s * vx + c * vy, 0.0])
                     for vx, vy in body.vertices()])


def _gripper_rotations(motion, R0, p0, t_end):
    """R_AB(t) on a grid covering the motion (to check the stops' normals)."""
    t = np.linspace(0.0, t_end, 200)
    return motion.evaluate(t, tuple(map(tuple, R0)), tuple(p0))["R"]


# ---------------------------------------------------------------- the generator

def zoo_scene(seed):
    """The zoo scene of a seed (a non-negative int): a :class:`ZooScene`."""
    rng = np.random.default_rng([int(seed), 0x200])
    L = float(math.exp(rng.uniform(math.log(1e-3), math.log(1.0))))
    tau = math.sqrt(L / G)
    dof = str(rng.choice(DOFS))
    body, body_kind = _body(rng, L)
    grasp, grip_ratio = _grasp(rng, body, L)

    # gravity: tilted from -z by up to 30 degrees, or any direction
    if rng.random() < 0.8:
        tilt = rng.uniform(0.0, math.radians(30.0))
        gdir = _rotation(_unit([math.cos(rng.uniform(0, 2 * math.pi)), math.sin(rng.uniform(0, 2 * math.pi)), 0.0]),
                         tilt) @ np.array([0.0, 0.0, -1.0])
    else:
        gdir = _random_direction(rng)
    gravity = G * gdir

    R0 = np.array(exdex.scene.DEFAULT_GRIPPER_ROTATION) if rng.random() < 0.5 else random_rotation(rng)
    p0 = rng.uniform(-1.0, 1.0, size=3) * 2.0 * L

    q0 = (float(rng.uniform(-0.3, 0.3) * L), float(rng.uniform(-0.3, 0.3) * L), float(rng.uniform(-math.pi, math.pi)))
    a = rng.uniform(0.0, 2.0 * math.pi)
    slide = np.array([math.cos(a), math.sin(a)])
    v0 = (0.0, 0.0, 0.0)
    if rng.random() < 0.4:
        v0 = (float(rng.uniform(-0.5, 0.5) * L / tau), float(rng.uniform(-0.5, 0.5) * L / tau),
              float(rng.uniform(-0.5, 0.5) / tau))

    n_stops = int(rng.choice([0, 1, 2], p=[0.45, 0.35, 0.2]))
    if dof == "rotation":
        n_stops = min(n_stops, 1)
    motion_kind = str(rng.choice(MOTIONS, p=[0.2, 0.3, 0.2, 0.3]))
    rotate = bool(rng.random() < 0.5)
    zB = R0[:, 2]

    # stop normals in B, drawn before the motion so the motion can respect them
    normals_B = []
    for _ in range(n_stops):
        for _attempt in range(100):
            n = _random_direction(rng)
            if dof == "planar":
                ok = np.linalg.norm(n[:2]) >= 0.5
                if ok and normals_B:
                    a, b = _unit(n[:2]), _unit(normals_B[0][:2])
                    ok = a @ b >= math.cos(math.radians(135.0))
            elif dof == "translation":
                ok = abs(n[:2] @ slide) >= 0.5 and (not normals_B or (n[:2] @ slide) * (normals_B[0][:2] @ slide) > 0)
            else:
                ok = np.linalg.norm(n[:2]) >= 0.5
            if ok:
                normals_B.append(n)
                break
    n_stops = len(normals_B)
    normals_A = [R0 @ n for n in normals_B]

    # the motion; with stops, turns only about the plate normal and (rotation
    # dof) translations only parallel to the stop plane
    if n_stops and dof == "rotation" and motion_kind != "rest":
        rotate = False
    def axis_for_turn(r):
        return zB.copy() if n_stops else _random_direction(r)

    def axis_for_shift(r):
        if n_stops and dof == "rotation":
            v = _random_direction(r)
            v = v - (v @ normals_A[0]) * normals_A[0]
            return _unit(v)
        return _random_direction(r)

    center = p0 + rng.uniform(-1.0, 1.0, size=3) * 2.0 * L
    if motion_kind == "rest":
        motion, t_motion = exdex.Rest(), 0.0
    elif motion_kind in ("asym", "trap"):
        axis = axis_for_turn(rng) if rotate else axis_for_shift(rng)
        motion = _parametric_motion(rng, motion_kind, L, tau, rotate, axis, center)
        t_motion = motion.end_time
    else:
        noisy = bool(rng.random() < 0.5)
        end_moving = bool(rng.random() < 0.15)
        turn = (lambda r: (axis_for_turn(r), p0 + r.uniform(-1.0, 1.0, size=3) * 2.0 * L)) if rotate else None
        shift = axis_for_shift if (not rotate or rng.random() < 0.5) else None
        if n_stops and dof == "rotation":
            turn = None
            shift = axis_for_shift
        motion, t_motion = _log_motion(rng, L, tau, R0, p0, turn, shift, noisy, end_moving)
        motion_kind = "log" + ("-noisy" if noisy else "-smooth") + ("-ends-moving" if end_moving else "")
        R0 = _quat_to_matrix(motion.quaternions[0])
        p0 = np.array(motion.positions[0])
        normals_A = [R0 @ n for n in normals_B]

    t_end = float(t_motion + tau * rng.uniform(1.0, 3.0))

    # check the stop normals over the motion; drop stops that the motion would
    # turn into an impossible constraint (rare: turns are about the plate normal)
    if n_stops and motion_kind != "rest":
        Rs = _gripper_rotations(motion, R0, p0, t_end)
        keep = []
        for nA in normals_A:
            nB = np.einsum("kji,j->ki", Rs, nA)  # R^T n at every sample
            if dof == "translation":
                d = nB[:, :2] @ slide
                good = np.all(np.abs(d) >= 0.3) and (np.all(d > 0) or np.all(d < 0))
            else:
                good = np.all(np.linalg.norm(nB[:, :2], axis=1) >= 0.3)
            if good:
                keep.append(nA)
        normals_A = keep
        n_stops = len(keep)

    stops = []
    if n_stops:
        xs = _outline_world(body, q0, R0, p0)
        for nA in normals_A:
            lowest = float(np.min(xs @ nA))
            gap = 0.0 if rng.random() < 0.2 else float(rng.uniform(0.0, 0.3) * L)
            stops.append(exdex.Stop(point=tuple((lowest - gap) * nA), normal=tuple(nA)))
        # rounding of the placement must not put a vertex inside: a vertex at
        # gap < 0 by rounding moves the stop back by that much, until none is
        fixed = []
        for s in stops:
            for _ in range(20):
                n, p = np.array(s.normal), np.array(s.point)
                g = float(np.min(_gaps(xs, s)))
                if g >= 0.0:
                    break
                s = exdex.Stop(point=tuple(p + (2.0 * g - 1e-16 * L) * n), normal=s.normal)
            fixed.append(s)
        stops = fixed

    if NUDGE_ULPS:
        gravity, grasp, motion = _nudge(seed, gravity, grasp, motion)
    scene = exdex.Scene(body=body, grasp=grasp, motion=motion, dof=dof, slide_axis=tuple(slide), q0=q0, v0=v0,
                        gripper_rotation=tuple(map(tuple, R0)), gripper_position=tuple(p0),
                        gravity=tuple(gravity), stops=tuple(stops))
    radius = float(np.max(np.linalg.norm(body.vertices(), axis=1)))
    tags = dict(dof=dof, motion=motion_kind, rotate=rotate and motion_kind != "rest", stops=len(stops),
                body=body_kind, grip_ratio=round(grip_ratio, 3), mu=round(grasp.mu, 3), L=L,
                v0=any(v != 0.0 for v in v0), default_gripper=bool(np.allclose(R0, exdex.scene.DEFAULT_GRIPPER_ROTATION)))
    return ZooScene(seed=int(seed), scene=scene, t_end=t_end, L=L, tau=tau, radius=radius, tags=tags)


#: A scan for assertions that pass only by how the last bits round:
#: ZOO_NUDGE_ULPS=k moves the drawn gravity, grip force, mu and a sampled
#: log's samples (all but the first, so the initial pose and every
#: placement from it stay exact) by up to k units in the last place (a
#: stream of its own per seed), the size of the differences between NumPy's
#: SIMD paths or libms. Unset (0) in the suite.
NUDGE_ULPS = int(os.environ.get("ZOO_NUDGE_ULPS", "0"))


def _nudge(seed, gravity, grasp, motion):
    rng = np.random.default_rng([int(seed), 0x7d9])

    def nudge(a):
        a = np.asarray(a, dtype=float)
        return a + rng.integers(-NUDGE_ULPS, NUDGE_ULPS + 1, size=a.shape) * np.spacing(a)

    gravity = nudge(gravity)
    grasp = exdex.replace(grasp, mu=float(nudge(grasp.mu)), grip_force=float(nudge(grasp.grip_force)))
    if isinstance(motion, exdex.SampledTrajectory):
        p, q = np.array(motion.positions), np.array(motion.quaternions)
        p[1:], q[1:] = nudge(p[1:]), nudge(q[1:])
        motion = exdex.replace(motion, positions=p, quaternions=q)
    return gravity, grasp, motion


def _quat_to_matrix(q):
    w, x, y, z = np.asarray(q) / np.linalg.norm(q)
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def stop_gaps(zs, t=None):
    """Gaps [m] (n_vertices, n_stops) of the outline at t = 0 (validity check)."""
    sc = zs.scene
    xs = _outline_world(sc.body, sc.q0, np.array(sc.gripper_rotation), np.array(sc.gripper_position))
    return np.stack([_gaps(xs, s) for s in sc.stops], axis=1)


def _gaps(xs, stop):
    return (xs - np.array(stop.point)) @ np.array(stop.normal)


# ---------------------------------------------------------------- running the methods

METHODS = ("implicit", "event", "regularised", "explicit")

#: Settings of the agreement check, in the scene's own units: output every
#: t_end / N_OUT (adaptive methods; the event reference's tight run at a
#: grid N_OUT_FINE, so an answer that depends on the output grid shows in
#: the reference's own estimate); the time-stepping methods at dt = t_end /
#: N_DT, / 2, / 4, / 8; the event reference at rtol REF_RTOL checked against
#: REF_RTOL_TIGHT; the regularised method at eps = EPS L / tau, / 2 and
#: / 4; DELTA the relative change of gravity that measures how well
#: conditioned the final pose is.
N_OUT, N_OUT_FINE = 8, 64
N_DT = 500
#: The implicit method's ladder is also run at dt = t_end / N_SHIFT (about
#: h / 8.8), a grid sharing no point with the ladder's but 0 and t_end
#: (4401 = 3^3 163 is prime to 4000 = 2^5 5^3), so that an error set by a
#: switching time's position in its step shows (see tests/scenarios/test_zoo.py).
N_SHIFT = 4401
REF_RTOL, REF_RTOL_TIGHT = 1e-9, 1e-11
EPS = 1e-2
DELTA = 1e-6


def final_pose(res):
    """(x, y, theta) of C in B at the last sample, whatever the dof."""
    return res.pose[-1]


def pose_distance(zs, a, b):
    """Distance between two final poses, relative to the scene's length:
    max(|dx|, |dy|, radius |dtheta|) / L (radius the outline's lever arm, so
    an angle error counts as the displacement of the farthest vertex)."""
    d = np.abs(np.asarray(a) - np.asarray(b))
    return float(max(d[0], d[1], zs.radius * d[2]) / zs.L)


def run(zs, method, scene=None, **kw):
    """simulate() on a zoo scene with scale-free tolerances: atol = rtol x the
    smallest of the scene's length, speed and impulse scales; eps relative
    to the speed scale L / tau."""
    sc = zs.scene if scene is None else scene
    opts = dict(kw)
    n_out = opts.pop("n_out", N_OUT)
    if method in ("event", "regularised"):
        rtol = opts.pop("rtol", REF_RTOL)
        scale = min(zs.L, zs.L / zs.tau, sc.body.mass * G * zs.tau)
        opts.update(rtol=rtol, atol=rtol * scale)
    if method == "regularised":
        opts["eps"] = opts.pop("eps_rel", EPS) * zs.L / zs.tau
    dt = opts.pop("dt", zs.t_end / n_out)
    with by_design(*ALL):  # random scenes give every kind of PhysicsWarning by design
        return exdex.simulate(sc, zs.t_end, dt, method=method, **opts)


def creep_speed(zs):
    """The explicit method's creep speed per unit time step while the exact
    solution sticks, as a pose distance / L per s per s: its velocity
    chatters in a band of width 2 h C / M about 0 (C the friction capacity,
    M the mass, or for turns C e_r and the moment of inertia about the
    pivot), so the pose drifts by at most h C / M per unit time."""
    sc = zs.scene
    C = sc.grasp.capacity
    m = sc.body.mass
    Izz = np.array(sc.body.inertia)[2, 2]
    if sc.dof == "rotation":
        c = np.array(sc.grasp.patch.center)
        Izz = Izz + m * (c @ c)
    lin = C / m
    ang = C * sc.grasp.patch.e_r / Izz * zs.radius
    return float(max(lin, ang) / zs.L)


#: Safety factor of the first-order error estimates, the event method's
#: tolerance proportionality (derivations in tests/scenarios/test_zoo.py) and the
#: floor of every bound.
S = 3.0
PROPORTIONAL = 0.3
FLOOR = REF_RTOL
#: The event method's planar rest against stops moving in B ends when a
#: touching row's gap leaves +-REST_GAP_REL x its length scale (the
#: outline's radius): the reference's rests are held to that (see
#: tests/scenarios/test_zoo.py).
REST_GAP_REL = 1e-7


def integration_tol(res, size):
    """Global error bound of an adaptive run at REF_RTOL, as a pose distance
    / L: the stepper keeps each step's error below rtol relative to the
    state (and atol, here rtol x the scene's scales), and the global error
    is at most the sum over the steps: steps x REF_RTOL x (1 + size), size
    the final pose's own pose distance from 0 (an angle of many turns is
    held to rtol relative to itself)."""
    return res.stats["steps"] * REF_RTOL * (1.0 + size)


def bound(method, o, ref):
    """The largest final-pose distance from the reference that a method's own
    error estimate allows (derivation in tests/scenarios/test_zoo.py)."""
    allow = ref["err"] + ref.get("jump", 0.0) + ref.get("rest", 0.0) + FLOOR
    if method == "event":
        return PROPORTIONAL * ref["err"] + ref.get("jump", 0.0) + FLOOR
    est = S * max(o["d"])
    if method == "implicit" and "d_shift" in o:
        est = S * max(max(o["d"]), o["d_shift"])  # the ladder and the offset grid (N_SHIFT)
    if method == "explicit":
        est += o["creep"]
    if method == "regularised":
        est += o["tol"] + o["creep"]  # its adaptive integration at REF_RTOL; its creep while stuck
    return est + allow


def regularised_creep(zs, ref_run, eps_rel):
    """The regularised method's creep over the reference's stuck time, as a
    pose distance / L. Under a plate load w inside the ellipsoid it does not
    stick but creeps at |E u| = eps |E^-1 w| / sqrt((mu N)^2 - |E^-1 w|^2)
    (exdex.simulate); u is the slip (v, e_r omega), so the pose moves by at
    most that speed times max(1, radius / e_r). Summed over the reference's
    stuck output intervals with the reference's wrench (the mean over each
    interval)."""
    sc = zs.scene
    C, er = sc.grasp.capacity, sc.grasp.patch.e_r
    if C <= 0.0:
        return 0.0
    w, st = ref_run.wrench[1:], ref_run.stick[1:]
    load = np.sqrt(w[:, 0] ** 2 + w[:, 1] ** 2 + (w[:, 2] / er) ** 2)
    gap = np.sqrt(np.maximum(C * C - load * load, 0.0))
    eps = eps_rel * zs.L / zs.tau
    with np.errstate(divide="ignore", invalid="ignore"):
        speed = np.where(st, eps * load / gap, 0.0)
    if not np.all(np.isfinite(speed)):
        return math.inf
    dt = ref_run.t[1:] - ref_run.t[:-1]
    return float(np.sum(speed * dt) * max(1.0, zs.radius / er) / zs.L)


#: Where the regularised ladder starts: its creep must leave the
#: configuration nearly unchanged, at most this fraction of L at eps0 (a
#: starting point that saves halvings; the ladder's ratios decide whether
#: it is in its first-order regime, see tests/scenarios/test_zoo.py).
CREEP_REGIME = 0.1
#: ... and the agreement ladder starts at eps0 = EPS x min(1, CREEP_REGIME /
#: creep(EPS)), but not below EPS / EPS_RANGE (each halving of eps doubles
#: the cost of a stiff run).
EPS_RANGE = 16.0


#: ... and lowered further, by halvings down to EPS / EPS_BRANCH_RANGE, until
#: the run at eps0 ends on the reference's branch (stop_contacts): its
#: first-order error moves the time of a stop contact, and a final pose held
#: by a stop the reference does not touch (or freed from one it rests on)
#: is a discrete outcome, identical at eps0, eps0/2, eps0/4 (see
#: tests/scenarios/test_zoo.py).
EPS_BRANCH_RANGE = 256.0


def stop_contacts(res):
    """The stops pressing on the object over the last output interval (mean
    normal force > 0), as a tuple of stop indices."""
    return tuple(int(k) for k in np.flatnonzero(np.ravel(res.stop_force[-1]) > 0.0))


def _branch_eps(zs, ref_run, eps0):
    """The largest eps_rel <= eps0 among eps0 / 2^j, down to EPS /
    EPS_BRANCH_RANGE, whose regularised run ends with the reference's stop
    contacts; eps0 itself when none does or a run fails (the ladder then
    ends off the branch and the check reports the scene outside the
    regime: zoo.check_scene).
    Returns (eps_rel, its run, or None where it is to be made again)."""
    want = stop_contacts(ref_run)
    eps = eps0
    while True:
        try:
            r = run(zs, "regularised", eps_rel=eps, n_out=N_OUT_FINE)
        except Exception:  # noqa: BLE001 - the ladder itself reports the failure
            return eps0, None
        if not all(np.all(np.isfinite(getattr(r, k))) for k in ("q", "v", "wrench", "stop_force")):
            return eps0, None
        if stop_contacts(r) == want:
            return eps, r
        if eps / 2 < EPS / EPS_BRANCH_RANGE * (1 - 1e-12):
            return eps0, None
        eps /= 2


#: The regularised ladder's successive differences D_k (between eps_k and
#: eps_k / 2) are an error estimate only once they shrink as a convergent
#: sequence's do: D_{k+1} / D_k in [RATIO_LO, RATIO_HI] (first order: 1/2,
#: second: 1/4; the tail of a sequence shrinking by at most r per halving is
#: at most r / (1 - r) times its last difference: 2 at RATIO_HI, S = 3 at
#: 3/4, the margin for ratios past the ladder). The ladder
#: is extended by halvings, down to EPS / EPS_LADDER_RANGE, until its last
#: N_RATIOS ratios are in that range (see tests/scenarios/test_zoo.py).
RATIO_LO, RATIO_HI = 0.125, 2.0 / 3.0
EPS_LADDER_RANGE = 1024.0


#: Consecutive ratios that must be in that range (a single one was seen in
#: range by coincidence on a ladder still far from its limit).
N_RATIOS = 2


def ladder_consistent(d, noise=0.0):
    """Whether the last N_RATIOS + 1 successive differences of a ladder
    shrink at a convergent rate (RATIO_LO <= D_{k+1} / D_k <= RATIO_HI
    for each consecutive pair), or are all within the runs' own
    integration error ``noise`` (the ladder cannot resolve them; the bound
    adds that error); identical runs (zero differences) are consistent, a
    zero difference next to a nonzero one is not."""
    if len(d) < N_RATIOS + 1:
        return False
    if max(d[-N_RATIOS - 1:]) <= noise:
        return True
    for a, b in zip(d[-N_RATIOS - 1:-1], d[-N_RATIOS:]):
        if a == 0.0:
            if b != 0.0:
                return False
        elif not RATIO_LO <= b / a <= RATIO_HI:
            return False
    return True


def _extend_ladder(zs, ref_run, rs, eps):
    """The regularised ladder rs (eps0, eps0/2, eps0/4, ..., the last at
    eps) extended by halvings of eps, down to EPS / EPS_LADDER_RANGE, until
    its last N_RATIOS + 1 differences are consistent (ladder_consistent,
    with the runs' integration_tol as the noise) and, where they are all
    within that noise (the pose may be held by a stop), its last N_RATIOS
    + 2 runs end with the reference's stop contacts; differences that
    shrink at a consistent rate show a pose that moves with eps, which the
    ladder measures on either branch (reported outside the regime when off
    it). A run that fails ends the extension (the scene is then judged on
    the ladder so far, outside the regime). Returns (runs, the last
    eps)."""
    want = stop_contacts(ref_run)
    size = pose_distance(zs, final_pose(ref_run), np.zeros(3))
    while True:
        poses = [final_pose(r) for r in rs]
        d = [pose_distance(zs, a, b) for a, b in zip(poses[:-1], poses[1:])]
        noise = max(integration_tol(r, size) for r in rs[-N_RATIOS - 2:])
        held = len(d) > N_RATIOS and max(d[-N_RATIOS - 1:]) <= noise
        if ladder_consistent(d, noise) and (not held or all(stop_contacts(r) == want for r in rs[-N_RATIOS - 2:])):
            return rs, eps
        if eps / 2 < EPS / EPS_LADDER_RANGE * (1 - 1e-12):
            return rs, eps
        try:
            r = run(zs, "regularised", eps_rel=eps / 2, n_out=N_OUT_FINE)
        except Exception:  # noqa: BLE001 - the ladder so far is judged
            return rs, eps
        if not all(np.all(np.isfinite(getattr(r, k))) for k in ("q", "v", "wrench", "stop_force")):
            return rs, eps
        rs = rs + [r]
        eps /= 2


#: The explicit method's dt ladder is judged the same way (its differences are
#: an error estimate only once they shrink at a convergent rate:
#: ladder_consistent, and its last runs share their impacts and end on the
#: reference's branch: same_events), and
#: extended by halvings of dt, down to t_end / (N_DT x DT_LADDER_RANGE),
#: until they do (see tests/scenarios/test_zoo.py).
DT_LADDER_RANGE = 512.0


def same_events(rs, ref_run):
    """Whether the runs of a time-stepping ladder share the discrete event
    structure its error model assumes: the same number of impacts on stops
    (Result.stats["impacts"]) in every run, and the reference's stop
    contacts at the end (stop_contacts)."""
    want = stop_contacts(ref_run)
    return (len({int(r.stats["impacts"]) for r in rs}) == 1
            and all(stop_contacts(r) == want for r in rs))


def _extend_dt_ladder(zs, method, ref_run, rs, dt):
    """A time-stepping ladder rs (dt = t_end / N_DT, dt/2, ..., the last at
    ``dt``) of ``method`` extended by halvings of dt, down to t_end / (N_DT
    x DT_LADDER_RANGE), until its last N_RATIOS + 1 differences are
    consistent (ladder_consistent; a fixed-step run has no integration
    tolerance) and its last N_RATIOS + 2 runs end with the reference's stop
    contacts and count the same impacts (same_events). A run that fails ends
    the extension (the scene is then judged on the ladder so far). Returns
    (runs, the last dt)."""
    while True:
        poses = [final_pose(r) for r in rs]
        d = [pose_distance(zs, a, b) for a, b in zip(poses[:-1], poses[1:])]
        if ladder_consistent(d) and same_events(rs[-N_RATIOS - 2:], ref_run):
            return rs, dt
        if dt / 2 < zs.t_end / (N_DT * DT_LADDER_RANGE) * (1 - 1e-12):
            return rs, dt
        try:
            r = run(zs, method, dt=dt / 2)
        except Exception:  # noqa: BLE001 - the ladder so far is judged
            return rs, dt
        if not all(np.all(np.isfinite(getattr(r, k))) for k in ("q", "v", "wrench", "stop_force")):
            return rs, dt
        rs = rs + [r]
        dt /= 2


def check_scene(zs, methods=METHODS, agree=METHODS):
    """Run every method on a zoo scene and measure the agreement.

    Returns a dict per method: ``error`` (None, or "ExceptionType: message"),
    ``pose`` (final pose of its finest run; event: the REF_RTOL run) and for the methods in
    ``agree``: ``err`` (pose_distance from the finest run to the
    reference), ``d`` (distances between successive runs at h, h/2, h/4,
    h/8; explicit: the last N_RATIOS + 1 of its ladder h, h/2, ... (extended
    by _extend_dt_ladder), all of them in ``ladder``, the steps in ``dt``;
    regularised: the last N_RATIOS + 1 of its ladder eps0, eps0/2,
    ..., all of them in ``ladder``, the eps in ``eps``), explicit and regularised also
    ``creep`` (explicit: the reference's stuck time x its finest dt x
    creep_speed, and ``regime``: the ladder consistent, its last runs
    same_events;
    regularised: regularised_creep at its finest eps, ``eps0``, ``branch``
    and ``regime``: the ladder consistent, ladder_consistent), ``bound``
    (zoo.bound) and ``ok``. Key "reference": the
    event method at REF_RTOL and N_OUT (its ``err``: the distance to the run
    at REF_RTOL_TIGHT and N_OUT_FINE, the reference) and, computed only when
    some method exceeds its bound without it, ``jump``: the largest
    distance from the reference of the reference runs with gravity scaled
    by (1 +- DELTA), the ill-conditioning of the final pose.
    """
    out = {}

    def attempt(method, **kw):
        try:
            r = run(zs, method, **kw)
        except exdex.SolverError as e:
            return None, f"SolverError: {e}"
        except Exception as e:  # noqa: BLE001 - a report, the test asserts on it
            return None, f"{type(e).__name__}: {e}"
        fin = all(np.all(np.isfinite(getattr(r, k))) for k in ("q", "v", "wrench", "stop_force"))
        return r, (None if fin else "non-finite output")

    agree = tuple(agree)
    if agree and "event" not in agree:
        agree = agree + ("event",)
    runs = {}
    shifted = None  # the implicit run on the offset grid (N_SHIFT)
    # the reference first: the regularised and explicit ladders follow its branch
    for method in sorted(methods, key=lambda m: m != "event"):
        full = method in agree
        first = None  # the regularised run at eps0, when the branch search made it
        if method in ("implicit", "explicit"):
            seq = [dict(dt=zs.t_end / (N_DT * k)) for k in ((1, 2, 4, 8) if full else (1,))]
        elif method == "event":
            seq = [dict(rtol=REF_RTOL)] + ([dict(rtol=REF_RTOL_TIGHT, n_out=N_OUT_FINE),
                                            dict(rtol=math.sqrt(REF_RTOL * REF_RTOL_TIGHT))] if full else [])
        else:
            eps0 = EPS
            if full and runs.get("event") and len(runs["event"]) == 3:
                creep = regularised_creep(zs, runs["event"][1], EPS)
                eps0 = EPS * max(min(1.0, CREEP_REGIME / creep), 1.0 / EPS_RANGE) if creep > 0 else EPS
            if full and runs.get("event") and len(runs["event"]) == 3:
                eps0, first = _branch_eps(zs, runs["event"][1], eps0)
            seq = [dict(eps_rel=eps0 / k, n_out=N_OUT_FINE) for k in ((1, 2, 4) if full else (1,))]
        rs, err = [], None
        for kw in seq:
            r, err = (first, None) if first is not None and kw is seq[0] else attempt(method, **kw)
            if err is not None:
                break
            rs.append(r)
        if method == "regularised" and full and err is None and runs.get("event") and len(runs["event"]) == 3:
            rs, _ = _extend_ladder(zs, runs["event"][1], rs, seq[-1]["eps_rel"])
        if method == "implicit" and full and err is None:
            r, err = attempt(method, dt=zs.t_end / N_SHIFT)
            shifted = r
        if method == "explicit" and full and err is None and runs.get("event") and len(runs["event"]) == 3:
            rs, _ = _extend_dt_ladder(zs, method, runs["event"][1], rs, seq[-1]["dt"])
        runs[method] = rs
        out[method] = dict(error=err, pose=None if err else final_pose(rs[-1]))
        if method == "explicit" and full:
            out[method]["dt"] = [seq[0]["dt"] / 2 ** k for k in range(len(rs))]
        if method == "regularised":
            out[method]["eps0"] = seq[0]["eps_rel"]
            out[method]["eps"] = [seq[0]["eps_rel"] / 2 ** k for k in range(len(rs))]
    if not agree or "event" not in runs or out["event"]["error"]:
        return out
    ev, tight, mid = runs["event"]
    ref = final_pose(tight)
    size = pose_distance(zs, ref, np.zeros(3))
    refd = dict(pose=ref, err=pose_distance(zs, final_pose(ev), ref), err_mid=pose_distance(zs, final_pose(mid), ref),
                min_gap=min(ev.stats["min_gap"], tight.stats["min_gap"]) / zs.L,
                warnings=ev.stats["warnings"] + tight.stats["warnings"], tol=integration_tol(ev, size),
                rest=REST_GAP_REL * zs.radius / zs.L if zs.scene.dof == "planar" and zs.scene.stops else 0.0)
    out["reference"] = refd
    stuck = float(np.sum(tight.stick[1:])) * zs.t_end / N_OUT_FINE
    for method in agree:
        o = out[method]
        if o["error"]:
            continue
        poses = [final_pose(r) for r in runs[method]]
        if method == "event":
            o.update(err=refd["err_mid"])
        else:
            d = [pose_distance(zs, a, b) for a, b in zip(poses[:-1], poses[1:])]
            o.update(err=pose_distance(zs, poses[-1], ref), d=d[-N_RATIOS - 1:] if method != "implicit" else d)
            if method != "implicit":
                o["ladder"] = d
            if method == "implicit" and shifted is not None:
                o["d_shift"] = pose_distance(zs, poses[-1], final_pose(shifted))
            if method == "explicit":
                o["creep"] = stuck * o["dt"][-1] * creep_speed(zs)
                o["regime"] = ladder_consistent(d) and same_events(runs[method][-N_RATIOS - 2:], tight)
            if method == "regularised":
                last = runs[method][-N_RATIOS - 2:]
                o["tol"] = max(integration_tol(r, size) for r in last)
                creep = regularised_creep(zs, tight, o["eps"][-1])
                # at the friction limit the creep law has no first-order term
                # (infinite speed): the ladder's differences carry that error
                o["creep"] = creep if math.isfinite(creep) else 0.0
                o["branch"] = all(stop_contacts(r) == stop_contacts(tight) for r in last)
                o["regime"] = o["branch"] and ladder_consistent(d, o["tol"])

    def judge():
        for method in agree:
            o = out[method]
            if not o["error"]:
                o["bound"] = bound(method, o, refd)
                o["ok"] = o["err"] <= o["bound"]
                if method == "event":
                    # the REF_RTOL run within its stated error (tests/scenarios/test_zoo.py)
                    o["ref_ok"] = refd["err"] <= refd["tol"] + refd.get("jump", 0.0) + FLOOR
                    o["ok"] = o["ok"] and o["ref_ok"]

    judge()
    if not all(out[m]["ok"] for m in agree if not out[m]["error"]):
        refd["jump"] = 0.0
        for f in (1 + DELTA, 1 - DELTA):
            sc = exdex.replace(zs.scene, gravity=tuple(np.array(zs.scene.gravity) * f))
            try:
                r = run(zs, "event", scene=sc, rtol=REF_RTOL_TIGHT, n_out=N_OUT_FINE)
                refd["jump"] = max(refd["jump"], pose_distance(zs, final_pose(r), ref))
            except Exception as e:  # noqa: BLE001
                refd["jump_error"] = f"{type(e).__name__}: {e}"
        judge()
    return out


def scene_source(scene):
    """Python source that rebuilds ``scene`` exactly (for reproducer scripts)."""
    with np.printoptions(threshold=sys.maxsize, precision=17, floatmode="unique"):
        text = repr(scene)
    return text


REPRO_HEADER = """import math
import numpy as np
from numpy import array
import exdex
from exdex import (AsymmetricProfile, Body, Grasp, Patch, Rest, SampledTrajectory, Scene, Stop,
                   TrapezoidalProfile)
"""


def zoo_pad_scene(seed):
    """The zoo scene of a seed with pads on the fingers in place of its patch
    (exdex.Pad, drawn from a stream of its own so zoo_scene's draws stay as
    they are): the pad sits where the patch is at t = 0 (in B), of the
    patch's shape and size (a given e_r: the disc of that e_r, R = 3 e_r / 2),
    the rectangle turned with the object; in a third of the scenes it is
    moved toward the face's edge (its centre kept inside the face), so the
    region starts clipped. Returns a ZooScene (tags["pad"] says which)."""
    zs = zoo_scene(seed)
    sc = zs.scene
    rng = np.random.default_rng([int(seed), 0x300])
    patch, th = sc.grasp.patch, sc.q0[2]
    c, s = math.cos(th), math.sin(th)
    R = np.array([[c, -s], [s, c]])
    center = np.array(sc.q0[:2]) + R @ np.array(patch.center)
    kind = "inside"
    if rng.random() < 1.0 / 3.0:
        # toward the face's boundary along a random direction, up to 0.5..0.95 of the way
        d = _unit([*rng.normal(size=2), 0.0])[:2]
        face = np.array(sc.q0[:2]) + sc.body.vertices() @ R.T
        # the outward normals of the ccw face's edges; the ray from the centre leaves through one
        edges = [(p, np.array([b[1] - p[1], p[0] - b[0]])) for p, b in zip(face, np.roll(face, -1, axis=0))]
        reach = min(float(((p - center) @ n) / (d @ n)) for p, n in edges if d @ n > 0)
        center = center + rng.uniform(0.5, 0.95) * reach * d
        kind = "edge"
    if patch.shape == "rectangle":
        w, h = patch.dims
        verts = np.array([(-w / 2, -h / 2), (w / 2, -h / 2), (w / 2, h / 2), (-w / 2, h / 2)]) @ R.T
        pad = exdex.Pad(vertices=tuple(map(tuple, verts)), center=tuple(center))
    else:
        radius = patch.dims[0] if patch.shape == "disc" else 1.5 * patch.e_r
        pad = exdex.Pad.disc(radius, center=tuple(center))
    grasp = exdex.replace(sc.grasp, pad=pad)
    tags = dict(zs.tags, pad=f"{patch.shape}-{kind}")
    return ZooScene(seed=zs.seed, scene=exdex.replace(sc, grasp=grasp), t_end=zs.t_end, L=zs.L, tau=zs.tau,
                    radius=zs.radius, tags=tags)


def obstacle(rng, zs, mu):
    """A box, a rod along the plate normal or a two-face wedge, its face(s)
    at a gap 0..L/3 from the initial outline, in a random in-plane direction."""
    sc = zs.scene
    R0, p0 = np.array(sc.gripper_rotation), np.array(sc.gripper_position)
    xs = _outline_world(sc.body, sc.q0, R0, p0)
    a = rng.uniform(0.0, 2.0 * math.pi)
    nB = np.array([math.cos(a), math.sin(a), 0.0])
    nA = R0 @ nB                       # the obstacle's face normal, pointing at the object
    zA = R0[:, 2]
    gap = 0.0 if rng.random() < 0.2 else float(rng.uniform(0.0, 1.0 / 3.0) * zs.L)
    low = float(np.min(xs @ nA)) - gap  # the face plane: n . x = low
    kind = str(rng.choice(["box", "rod", "wedge"]))
    com = p0 + R0 @ np.array([sc.q0[0], sc.q0[1], 0.0])
    if kind == "box":
        size = np.array([float(rng.uniform(0.3, 2.0) * zs.L), float(rng.uniform(0.5, 3.0) * zs.L), 1e3 * zs.L])
        t = np.cross(zA, nA)
        rot = np.stack([nA, t, zA], axis=1)
        off = float(rng.uniform(-0.5, 0.5) * zs.L)
        c = com + (low - com @ nA - 0.5 * size[0]) * nA + off * t
        ob = exdex.Obstacle.box(tuple(c), tuple(size), rotation=tuple(map(tuple, rot)), mu=mu)
    elif kind == "rod":
        r = float(rng.uniform(0.05, 0.5) * zs.L)
        reach = float(np.max(np.linalg.norm(xs - com, axis=1)))
        c = com - (reach + gap + r) * nA
        ob = exdex.Obstacle.cylinder(tuple(c), tuple(zA), r, mu=mu)
    else:
        half = float(rng.uniform(math.radians(20.0), math.radians(60.0)))
        t = np.cross(zA, nA)
        normals, offsets = [], []
        for sgn in (1.0, -1.0):
            m = math.cos(half) * nA + sgn * math.sin(half) * t
            normals.append(m)
            offsets.append(float(np.min(xs @ m)) - gap)
        # the solid {m_i . x <= d_i}: a convex edge pointing at the object,
        # every vertex on the allowed side m_i . x >= d_i of both faces
        ob = exdex.Obstacle.halfspaces(tuple(map(tuple, normals)), tuple(offsets), mu=mu)
    return ob, kind

"""What the engine runs share: where the plates, pads, object and stops sit
in the gripper frame (Layout), the gripper's kinematics along the scene's
motion, the obstacle shapes, and the engine run returned as an exdex.Result.
Each engine's module (exdex.engines.pybullet, .mujoco, .drake) builds its
scene from these."""
from __future__ import annotations

import math
import time

import numpy as np

from exdex._optional import require
from exdex._rotations import quat_from_matrix as _quat_from_matrix
from exdex._validate import real as _real
from exdex.scene import Scene
from exdex.simulate import Result

PAD_THICKNESS = 0.005      # half-thickness of the plate/pad boxes [m]
POINT_RADIUS = 0.005       # radius of the sphere pads of contact="point" [m]
STOP_HALF = (0.5, 0.5, 0.05)  # half-extents of a stop's box [m]


# ---------------------------------------------------------------- geometry shared by both engines

def _er_rectangle(a, b):
    """Howe & Cutkosky e_r of a uniform rectangle of half-sides a, b."""
    d = math.hypot(a, b)
    return (a * b * d / 3 + a**3 / 6 * math.log((b + d) / a) + b**3 / 6 * math.log((a + d) / b)) / (a * b)


def pad_geometry(patch):
    """Half-sides (a, b) [m] of the box pad standing for ``patch`` in contact="pads".

    A rectangle patch keeps its rectangle; any other patch (disc, given e_r)
    becomes the square with the same e_r (e_r of a square of half-side a is
    0.7652 a), so the pads differ from the patch only in where the engine
    puts its contact points.
    """
    if patch.shape == "rectangle" and len(patch.dims) == 2:
        return float(patch.dims[0]) / 2, float(patch.dims[1]) / 2
    a = patch.e_r / _er_rectangle(1.0, 1.0)
    return a, a


def _rot_z(theta):
    c, s = math.cos(theta), math.sin(theta)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def xyzw(R):
    w, x, y, z = _quat_from_matrix(R)
    return [x, y, z, w]


class Layout:
    """Where everything sits in the gripper frame B, from an exdex scene."""

    def __init__(self, scene, contact):
        if not isinstance(scene, Scene):
            raise TypeError(f"scene must be an exdex.Scene, got {type(scene).__name__}")
        if scene.body.size is None:
            raise ValueError("the engines need the object's box dimensions: set Body.size = (lx, ly, lz) [m]")
        if contact not in ("pads", "point"):
            raise ValueError(f"contact must be 'pads' or 'point', got {contact!r}")
        self.scene = scene
        self.contact = contact
        self.size = np.array(scene.body.size)
        lx, ly, lz = self.size
        # a disc outline: a cylinder (radius, centre in C) instead of the box
        self.disc = scene.body.outline_radius
        self.disc_center = np.array(tuple(scene.body.outline_center) + (0.0,))
        x0, y0, th0 = scene.q0
        self.th0 = th0
        self.R_BC0 = _rot_z(th0)
        self.com0 = np.array([x0, y0, 0.0])          # C origin in B
        c = np.array(scene.grasp.patch.center + (0.0,))
        self.patch_B = self.com0 + self.R_BC0 @ c     # patch centre (pivot) in B
        self.patch_C = c                              # in C
        # the joint frame of the object: at the pivot (rotation/planar) or at the COM
        self.joint_B = self.patch_B if scene.dof in ("rotation", "planar") else self.com0
        self.com_in_joint = (-c) if scene.dof in ("rotation", "planar") else np.zeros(3)  # in C axes
        # a point contact on the pivot cannot hold out-of-plane tilts: use a hinge there
        self.rot_joint = "hinge" if contact == "point" else "ball"
        self.pad_z = lz / 2 + (PAD_THICKNESS if contact == "pads" else POINT_RADIUS)
        if contact == "point":
            self.pad_center = self.patch_B.copy()
            self.pad_half = None
        elif scene.dof == "translation":
            # plates larger than the object and its travel: e_r plays no role
            span = float(np.hypot(lx, ly)) + 0.2
            self.pad_center = self.com0.copy()
            self.pad_half = (span, span)
        else:
            a, b = pad_geometry(scene.grasp.patch)
            self.pad_center = self.patch_B.copy()
            self.pad_half = (a, b)
            reach = math.hypot(a, b)
            # the object's face must cover the pad in every orientation about the pivot
            dist_edge = (min(lx / 2 - abs(c[0]), ly / 2 - abs(c[1])) if self.disc is None
                         else self.disc - float(np.hypot(*(c - self.disc_center)[:2])))
            self.pad_covered = dist_edge >= reach
        mu = scene.grasp.mu
        self.mu = (mu, mu if scene.grasp.fingers == 2 else 0.0)   # plate 1, plate 2
        I = np.array(scene.body.inertia)
        evals, evecs = np.linalg.eigh(I)
        if np.linalg.det(evecs) < 0:
            evecs[:, 0] = -evecs[:, 0]
        self.I_principal = evals
        self.R_C_principal = evecs   # columns: principal axes in C

    def spin(self, given):
        """Torsional friction [m] per pad contact: the user's, else mu e_r for point contact, 0 for pads."""
        if given is not None:
            return _real(given, "torsional friction", low=0.0)
        if self.contact == "point":
            return self.scene.grasp.mu * self.scene.grasp.patch.e_r
        return 0.0


#: why each engine cannot take a static friction coefficient above the kinetic one
_NO_STATIC_FRICTION = {
    "pybullet": "Bullet has one friction coefficient per contact (lateralFriction)",
    "mujoco": "MuJoCo has one sliding friction coefficient per contact",
    "drake": ("Drake's CoulombFriction takes a static coefficient, but its contact solvers use only the dynamic one: "
              "a block held at rest with its weight between 2 mu F and 2 mu_static F slides exactly as without "
              "mu_static (measured with the lagged and SAP discrete approximations and a continuous plant)"),
}


def check_static_friction(scene, engine):
    """ValueError naming Grasp.mu_static when it exceeds mu: no engine here
    has a faithful static coefficient (``_NO_STATIC_FRICTION``)."""
    g = scene.grasp
    if g.mu_static is not None and g.mu_static > g.mu:
        raise ValueError(f"Grasp.mu_static = {g.mu_static:g} > mu = {g.mu:g} cannot be run in {engine}: "
                         f"{_NO_STATIC_FRICTION[engine]}; run the engines with mu_static = None (equal to mu)")


def grip_force_at(scene, t):
    """The force [N] the engines' finger joint presses with during the step that
    starts at ``t``: the constant grip force, or a ``GripSchedule`` evaluated at
    the step's midpoint t + dt / 2 (``t`` is that midpoint here)."""
    f = scene.grasp.grip_force
    if isinstance(f, (int, float)):
        return float(f)
    return float(f(t))


def drake_friction(targets):
    """Drake combines two surfaces' friction as 2 mu1 mu2 / (mu1 + mu2). Given
    the coefficients each object pair must get (``targets``: the pads' and the
    stops'), return (M, partners): the object's coefficient M, the largest
    target, and each partner's x, for which 2 x M / (x + M) = mu, i.e.
    x = mu M / (2 M - mu) (finite, >= 0, since mu <= M < 2 M); a target equal
    to M keeps M itself (0 if all are 0)."""
    M = max(targets)
    if M == 0.0:
        return 0.0, [0.0] * len(targets)
    return M, [mu if mu == M else mu * M / (2.0 * M - mu) for mu in targets]


def gripper_kinematics(scene, t):
    """Gripper kinematics at times t in A: dict R, p, v, a, w, dw."""
    return scene.motion.evaluate(np.atleast_1d(np.asarray(t, dtype=float)), scene.gripper_rotation,
                                 scene.gripper_position)


def run_arrays(scene, n, dt):
    """Gravity, the sample times, the gripper kinematics there and the empty
    records (object position, velocity, orientation R_BC, spin, stop forces)
    of an engine run of n steps of dt."""
    times = np.arange(n + 1) * dt
    return (np.array(scene.gravity), times, gripper_kinematics(scene, times), np.empty((n + 1, 3)),
            np.empty((n + 1, 3)), np.empty((n + 1, 3, 3)), np.empty(n + 1),
            np.zeros((n + 1, len(scene.stops) + len(scene.obstacles))))


def stop_pose(stop):
    """Centre and rotation of the box standing for a stop half-space."""
    n = np.array(stop.normal)
    ref = np.array([1.0, 0.0, 0.0]) if abs(n[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    ex = np.cross(ref, n)
    ex /= np.linalg.norm(ex)
    ey = np.cross(n, ex)
    R = np.column_stack([ex, ey, n])
    return np.array(stop.point) - n * STOP_HALF[2], R


#: half-length [m] of the finite rod standing for a cylinder obstacle, and half-side of the cube that cuts an
#: unbounded intersection of half-spaces (a box of the same reach as a stop's, STOP_HALF)
OBSTACLE_REACH = 0.5


def _frame_of(axis):
    """A rotation whose third column is the unit ``axis``."""
    n = np.asarray(axis, float)
    ref = np.array([1.0, 0.0, 0.0]) if abs(n[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    ex = np.cross(ref, n)
    ex /= np.linalg.norm(ex)
    return np.column_stack([ex, np.cross(n, ex), n])


def obstacle_shape(obs, near):
    """The fixed collision geometry standing for an ``exdex.Obstacle`` in the
    engines, near the point ``near`` (A, the gripper's initial position):

    * a cylinder (an infinite rod) -> ("cylinder", centre, R, radius, half
      length): a rod of length 2 OBSTACLE_REACH along R's z, centred at the
      point of the axis nearest ``near``;
    * one half-space -> ("box", centre, R, half-sides): the box that stands
      for a ``Stop`` with the same point and normal (the obstacle acts as
      that stop);
    * six half-spaces in three opposite pairs of orthogonal normals (an
      ``Obstacle.box``) -> ("box", centre, R, half-sides);
    * any other intersection of half-spaces -> ("mesh", vertices (k, 3)):
      the vertices of the convex polytope (scipy's HalfspaceIntersection
      from its Chebyshev centre), cut by the cube of half-side
      OBSTACLE_REACH about ``near`` when unbounded. An empty one raises a
      ValueError.
    """
    near = np.asarray(near, float)
    if obs.kind == "cylinder":
        a, c = np.array(obs.axis), np.array(obs.center)
        centre = c + a * float(np.dot(near - c, a))
        return ("cylinder", centre, _frame_of(a), float(obs.radius), OBSTACLE_REACH)
    P, N = np.array(obs.face_points, float).reshape(-1, 3), np.array(obs.face_normals, float).reshape(-1, 3)
    if len(N) == 1:
        c, R = stop_pose(_StopLike(P[0], N[0]))
        return ("box", c, R, np.array(STOP_HALF))
    if len(N) == 6:
        pairs, used = [], set()
        for i in range(6):
            if i in used:
                continue
            j = next((j for j in range(6) if j != i and j not in used and np.allclose(N[j], -N[i], atol=1e-12)), None)
            if j is None:
                break
            used |= {i, j}
            pairs.append((N[i], float(N[i] @ P[i]), float(N[i] @ P[j])))
        if len(pairs) == 3:
            R = np.column_stack([p[0] for p in pairs])
            if np.allclose(R.T @ R, np.eye(3), atol=1e-12):
                if np.linalg.det(R) < 0:   # -n bounds -x: upper -lo, lower -hi
                    R[:, 2] = -R[:, 2]
                    pairs[2] = (-pairs[2][0], -pairs[2][2], -pairs[2][1])
                half = np.array([(hi - lo) / 2 for _, hi, lo in pairs])
                if np.all(half > 0):
                    centre = R @ np.array([(hi + lo) / 2 for _, hi, lo in pairs])
                    return ("box", centre, R, half)
    from scipy.optimize import linprog
    from scipy.spatial import ConvexHull, HalfspaceIntersection

    # the faces n . x <= n . p, and the cube about `near` (cuts an unbounded solid)
    A = np.vstack([N, np.eye(3), -np.eye(3)])
    b = np.concatenate([np.einsum("ij,ij->i", N, P), near + OBSTACLE_REACH, -(near - OBSTACLE_REACH)])
    # Chebyshev centre: max r with A x + r |a_i| <= b
    norms = np.linalg.norm(A, axis=1)
    lp = linprog(np.r_[0.0, 0.0, 0.0, -1.0], A_ub=np.column_stack([A, norms]), b_ub=b,
                 bounds=[(None, None)] * 3 + [(0, None)])
    if not lp.success or lp.x[3] <= 1e-9:
        raise ValueError("an Obstacle's half-spaces have no interior within "
                         f"{OBSTACLE_REACH} m of the gripper's initial position: the engines cannot build it")
    hs = HalfspaceIntersection(np.column_stack([A, -b]), lp.x[:3])
    verts = hs.intersections[ConvexHull(hs.intersections).vertices]
    return ("mesh", verts)


class _StopLike:
    """A plane (point, normal) as stop_pose reads a Stop."""

    def __init__(self, point, normal):
        self.point, self.normal = tuple(point), tuple(normal)


def obstacle_shapes(scene):
    return [obstacle_shape(o, scene.gripper_position) for o in scene.obstacles]


def obj_text(verts):
    """A Wavefront OBJ of the convex hull of ``verts`` (Drake's Convex reads it)."""
    from scipy.spatial import ConvexHull

    hull = ConvexHull(verts)
    lines = [f"v {float(x)!r} {float(y)!r} {float(z)!r}" for x, y, z in verts]
    c = verts.mean(axis=0)
    for simplex in hull.simplices:
        i, j, k = simplex
        # outward winding: the normal points away from the centroid
        if np.dot(np.cross(verts[j] - verts[i], verts[k] - verts[i]), verts[i] - c) < 0:
            j, k = k, j
        lines.append(f"f {i + 1} {j + 1} {k + 1}")
    return "\n".join(lines) + "\n"


def to_result(scene, method, t, pos_B, R_BC, vel_B, omega_B, stop_force, stats, dt):
    """Assemble an exdex.Result from the object's pose and twist relative to B."""
    theta = scene.q0[2] + np.unwrap(np.arctan2(R_BC[:, 1, 0], R_BC[:, 0, 0]) - scene.q0[2])
    if scene.dof == "translation":
        d = np.array(scene.slide_axis)
        q = (pos_B[:, :2] @ d)[:, None]
        v = (vel_B[:, :2] @ d)[:, None]
    elif scene.dof == "rotation":
        q = theta[:, None]
        v = omega_B[:, None]
    else:
        q = np.column_stack([pos_B[:, 0], pos_B[:, 1], theta])
        v = np.column_stack([vel_B[:, 0], vel_B[:, 1], omega_B])
    stick = np.all(v == 0.0, axis=1)
    wrench = np.full((len(t), 3), np.nan)
    return Result(t=t, q=q, v=v, wrench=wrench, stick=stick, stop_force=stop_force, stats=stats,
                  scene=scene, method=method, friction_solver="engine", dt=dt)


def drift_rate(result, t0=None):
    """Mean rate of the free coordinates over [t0, t_end]: (q(t_end) - q(t0)) / (t_end - t0).

    t0 defaults to 0.1 s after the end of the gripper motion (past the last
    step's transient). Units: m/s or rad/s. exdex gives exactly zero once the
    object sticks; soft-contact engines creep.
    """
    t = result.t
    if t0 is None:
        t0 = result.scene.motion.end_time + 0.1
    i = int(np.searchsorted(t, t0 - 1e-12))
    if i >= len(t) - 1:
        return np.zeros(result.q.shape[1])
    return (result.q[-1] - result.q[i]) / (t[-1] - t[i])


def step_count(t_end, dt):
    t_end = _real(t_end, "t_end", low=0.0, low_open=True)
    dt = _real(dt, "dt", low=0.0, low_open=True)
    n = int(round(t_end / dt))
    if n < 1:
        raise ValueError(f"t_end must be at least one time step dt = {dt:g} s, got {t_end:g}")
    return n, dt


#: the Python packages of the ``engines`` extra: (import name, distribution)
ENGINE_PACKAGES = (("pybullet", "pybullet"), ("mujoco", "mujoco"), ("pydrake", "drake"))


def missing_engines():
    """The distributions of the ``engines`` extra that do not import here (a list, empty when all do)."""
    import importlib.util

    return [dist for mod, dist in ENGINE_PACKAGES if importlib.util.find_spec(mod) is None]

"""Cross-checks against three general physics engines: pybullet, MuJoCo and Drake.

``run_pybullet(scene, t_end)``, ``run_mujoco(scene, t_end)`` and
``run_drake(scene, t_end)`` build the same
scene as exdex solves -- two plates driven kinematically along the gripper
trajectory, a box-shaped object squeezed between them with the grasp's normal
force per finger, the same mass, inertia, mu and gravity, the same stops -- and
return the object's motion relative to the gripper as an ``exdex.Result``
(same units, frames and free coordinates as ``exdex.simulate``).

How each scene is built (all engines)
-------------------------------------
* Gripper: a body with six free coordinates and a very large mass
  (``gripper_mass``, 1e4 kg by default, isotropic inertia). Before every step
  its pose and twist are reset to the prescribed trajectory and the applied
  wrench that gives it the prescribed linear and angular acceleration is set, so
  it is kinematic to within the mass ratio (1e-5 for a 0.1 kg object) and the
  contact solver sees the plates' true velocity and acceleration.
* Plates: plate 1 is rigid on the gripper; plate 2 sits on a prismatic joint
  along the plate normal (B z) and is pushed against the object by a constant
  joint force equal to ``grasp.grip_force``. In steady state each plate presses
  with exactly that force, whatever the engine's contact stiffness. A
  ``GripSchedule`` is applied as a zero-order hold: the joint force of the
  step [t, t + dt] is the schedule at the step's midpoint t + dt / 2.
* Object: a box of ``body.size`` (a disc outline, ``Body.outline_radius``:
  a cylinder of that radius about ``Body.outline_center``, its axis along the
  plate normal, as tall as ``body.size``'s lz) with the scene's mass and full
  inertia tensor, jointed to the gripper so that it has the scene's free coordinates
  plus the normal translation (so the squeeze passes through it):
  ``translation``: three prismatic joints (normal, B x, B y);
  ``rotation``: normal prismatic joint and a ball joint at the pivot (the
  patch centre); ``planar``: three prismatic joints and a ball joint. The ball
  joints' out-of-plane rotations are held by the plates' contacts (keeping
  them keeps MuJoCo's noslip post-solve well posed: with a hinge only, its
  per-contact friction blocks are singular and noslip silently does nothing).
  With ``contact="point"`` a single contact on the pivot cannot hold tilts,
  so the ball becomes a hinge about the plate normal.
* Contact (``contact=``): ``"pads"`` (default): the fingertip pads are boxes
  with the patch's footprint (``Patch.rectangle``: that rectangle; any other
  patch: the square with the same e_r) at the patch centre, and the engines'
  own box-box collision turns each face-to-face contact into points at the
  pad's corners (the paper's "multiple contact points at the vertices"). In
  translation scenes the pads are plates larger than the object (e_r plays no
  role there). With pads on the fingers (``Grasp.pad``) the engines' pads are
  exdex's: at ``Pad.center`` in B, a ``Pad.rectangle`` that rectangle, a
  ``Pad.disc`` the square of the same e_r (a general polygon: ValueError),
  the joints at the centroid of the region at the start (exdex's pivot).
  ``"point"``: one small sphere per finger at the patch centre,
  with torsional friction mu * e_r per contact: in MuJoCo (elliptic cone,
  condim 4) this is the same ellipsoid as exdex's, per contact; in pybullet the
  spin limit is independent of the lateral one (a cylinder).
* Friction: MuJoCo explicit contact pairs with friction (mu, mu, torsional);
  pybullet lateral friction mu on the pads and 1 on the object (Bullet
  multiplies them), spinning friction on the pads (Bullet combines it as
  spin_pad * lateral_object). Each stop-object pair gets exactly the stop's
  ``Stop.mu`` (Coulomb, static = kinetic; 0: frictionless), the way each
  engine combines two coefficients: MuJoCo takes an explicit ``<pair>``'s
  friction as given (it replaces the geoms' combination, the max), so the
  stop's pair has friction (mu, mu, 0) and condim 3 (condim 1, frictionless,
  for mu = 0); Bullet multiplies the two bodies' lateral friction, so the
  stop's box gets mu against the object's 1; Drake combines 2 mu1 mu2 /
  (mu1 + mu2), so the object gets the largest pair coefficient M and each pad
  and stop the partner x = mu M / (2 M - mu) that combines with M to its mu
  (the pads keep the grasp's mu when no stop's exceeds it). Drake's point
  contact touches a box on a stop at a single point, where friction jams a
  block flush on a stop: ``run_drake(stop_contact="corners")`` gives the
  object a sphere inside each in-plane corner instead, one contact per
  touching outline vertex as in exdex.
* Obstacles (``Scene(obstacles=...)``): fixed collision geometry of the
  world, touching only the object, with the obstacle's ``mu`` combined as a
  stop's (``_obstacle_shape``): an ``Obstacle.box`` (six faces in opposite
  pairs) is a box; a rod (``Obstacle.cylinder``, infinite) a capsule of
  length 2 ``OBSTACLE_REACH`` centred at the axis point nearest the
  gripper's initial position (its side is the rod's; the engines collide
  capsules with boxes more robustly than cylinders); a one-face obstacle
  the box of the equivalent ``Stop``; any other intersection of
  half-spaces its convex polytope, cut by the cube of half-side
  ``OBSTACLE_REACH`` about the gripper's initial position when unbounded,
  as a mesh whose convex hull the engine collides with (MuJoCo ``mesh``,
  Bullet ``GEOM_MESH``, Drake ``Convex``). Their normal forces follow the
  stops' in ``stop_force``, as in exdex.
* Static friction: ``Grasp(mu_static=...)`` above ``mu`` is a ValueError
  naming it in every engine. Bullet and MuJoCo have one coefficient per
  contact; Drake's ``CoulombFriction`` takes a static one, but its contact
  solvers use only the dynamic one (measured: a block held at rest between
  2 mu F and 2 mu_static F slides exactly as without it, lagged and SAP
  discrete solvers and a continuous plant alike).
* Drake (``run_drake``): a discrete ``MultibodyPlant`` built in code (no model
  files), the object on prismatic joints and a revolute joint about the plate
  normal (no out-of-plane tilt). ``contact_model="point"``: Drake's compliant
  point contact, which has no torsional friction and gives one point per
  box-box pair, so rotation and planar pads become spheres at the pad corners
  (the ``"corners"`` ablation model); ``"hydroelastic"``: compliant
  hydroelastic pads (``hydroelastic_modulus``) pressing a rigid (or
  compliant, ``object_modulus``) object, a pressure patch per finger from
  which torsional friction emerges. Friction: Drake combines two surfaces as
  2 mu1 mu2 / (mu1 + mu2), so pads and object both get mu. Discrete
  approximation ``"lagged"`` (Drake's default), ``"sap"``, ``"similar"`` or
  ``"tamsi"``; ``stiction_tolerance`` (1e-4 m/s, Drake's default) bounds the
  slip of an in-cone load in the regularised approximations.
* Engine settings default to the engine's own defaults (MuJoCo: 2 ms,
  Newton, 100 iterations, impratio 1, no noslip; pybullet: 1/240 s, 50
  iterations, cone friction on; Drake: 1 ms, lagged, point contact,
  stiction tolerance 1e-4 m/s), except MuJoCo's cone: ``"elliptic"`` by
  default, the faithful mapping of a friction cone (MuJoCo's own default is
  ``"pyramidal"``: pass ``cone="pyramidal"``).

Result fields: ``t, q, v`` as exdex; ``wrench`` is NaN (not measured);
``stick`` is True where the relative velocity is exactly zero;
``stop_force`` the summed normal contact force of each stop (Drake: of its
point contacts); ``stats`` holds the engine settings and wall time;
``method`` is ``"pybullet"``, ``"mujoco"`` or ``"drake"``.

The engines are imported inside the functions, so ``import exdex`` never
needs them (they come with ``pip install 'exdex[engines]'``); a run without
its engine raises ``exdex.MissingExtraError`` naming the extra.
``exdex compare`` (``exdex.cli_compare``) runs the paper cases and the planar
case in exdex and the three engines; ``exdex hold`` the hold benchmark
(``exdex.hold``).
"""
from __future__ import annotations

import math
import time

import numpy as np

from exdex import _core
from exdex._optional import require
from exdex.scene import Scene, _quat_from_matrix, _real
from exdex.simulate import Result

__all__ = ["run_pybullet", "run_mujoco", "run_drake", "missing_engines", "drift_rate", "pad_geometry", "torque_capacity",
           "ablation", "ABLATION_MODELS", "OBSTACLE_REACH"]

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


def _xyzw(R):
    w, x, y, z = _quat_from_matrix(R)
    return [x, y, z, w]


def _pad_half_sides(pad):
    """Half-sides (a, b) [m] of the engines' box pad for an exdex.Pad: a
    rectangle with sides along B's axes keeps its rectangle, a disc becomes
    the square of the same e_r (as pad_geometry does for a disc patch)."""
    if pad.radius is not None:
        a = _core.er_disc(pad.radius) / _er_rectangle(1.0, 1.0)
        return float(a), float(a)
    v = np.asarray(pad.vertices) * pad.scale
    xs, ys = np.unique(np.round(v[:, 0], 15)), np.unique(np.round(v[:, 1], 15))
    if len(v) != 4 or len(xs) != 2 or len(ys) != 2:
        raise ValueError("the engines build a rectangle pad (sides along B's x and y, Pad.rectangle) or a disc pad "
                         "(Pad.disc), not a general polygon")
    if abs(xs[0] + xs[1]) > 1e-12 * (abs(xs[0]) + abs(xs[1])) or abs(ys[0] + ys[1]) > 1e-12 * (abs(ys[0]) + abs(ys[1])):
        raise ValueError("the engines build a rectangle pad centred on Pad.center (vertices symmetric about it)")
    return float(xs[1] - xs[0]) / 2, float(ys[1] - ys[0]) / 2


class _Layout:
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
        pad = scene.grasp.pad
        if pad is not None:
            # pads on the fingers: the pivot (and the joint frame) at the centroid of the
            # region at the start, as exdex's rotation pivots there
            cB = np.array(_core.pad_region(scene.to_spec(), scene.q0)["centroid"])
            c = np.append(self.R_BC0[:2, :2].T @ (cB - self.com0[:2]), 0.0)
        else:
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
        elif pad is not None:
            # exdex's pads on the fingers: the engines' pads where they are, in B
            a, b = _pad_half_sides(pad)
            self.pad_center = np.array(tuple(pad.center) + (0.0,))
            self.pad_half = (a, b)
            self.pad_covered = True
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


def _check_static_friction(scene, engine):
    """ValueError naming Grasp.mu_static when it exceeds mu: no engine here
    has a faithful static coefficient (``_NO_STATIC_FRICTION``)."""
    g = scene.grasp
    if g.mu_static is not None and g.mu_static > g.mu:
        raise ValueError(f"Grasp.mu_static = {g.mu_static:g} > mu = {g.mu:g} cannot be run in {engine}: "
                         f"{_NO_STATIC_FRICTION[engine]}; run the engines with mu_static = None (equal to mu)")


def _grip_force(scene, t):
    """The force [N] the engines' finger joint presses with during the step that
    starts at ``t``: the constant grip force, or a ``GripSchedule`` evaluated at
    the step's midpoint t + dt / 2 (``t`` is that midpoint here)."""
    f = scene.grasp.grip_force
    if isinstance(f, (int, float)):
        return float(f)
    return float(f(t))


def _drake_friction(targets):
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


def _kinematics(scene, t):
    """Gripper kinematics at times t in A: dict R, p, v, a, w, dw."""
    return scene.motion.evaluate(np.atleast_1d(np.asarray(t, dtype=float)), scene.gripper_rotation,
                                 scene.gripper_position)


def _run_arrays(scene, n, dt):
    """Gravity, the sample times, the gripper kinematics there and the empty
    records (object position, velocity, orientation R_BC, spin, stop forces)
    of an engine run of n steps of dt."""
    times = np.arange(n + 1) * dt
    return (np.array(scene.gravity), times, _kinematics(scene, times), np.empty((n + 1, 3)),
            np.empty((n + 1, 3)), np.empty((n + 1, 3, 3)), np.empty(n + 1),
            np.zeros((n + 1, len(scene.stops) + len(scene.obstacles))))


def _stop_pose(stop):
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


def _obstacle_shape(obs, near):
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
        c, R = _stop_pose(_StopLike(P[0], N[0]))
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
    """A plane (point, normal) as _stop_pose reads a Stop."""

    def __init__(self, point, normal):
        self.point, self.normal = tuple(point), tuple(normal)


def _obstacle_shapes(scene):
    return [_obstacle_shape(o, scene.gripper_position) for o in scene.obstacles]


def _obj_text(verts):
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


def _to_result(scene, method, t, pos_B, R_BC, vel_B, omega_B, stop_force, stats, dt):
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


def _steps(t_end, dt):
    t_end = _real(t_end, "t_end", low=0.0, low_open=True)
    dt = _real(dt, "dt", low=0.0, low_open=True)
    n = int(round(t_end / dt))
    if n < 1:
        raise ValueError(f"t_end must be at least one time step dt = {dt:g} s, got {t_end:g}")
    return n, dt


# ---------------------------------------------------------------- MuJoCo

def _mujoco_xml(lay, *, dt, iterations, cone, impratio, noslip_iterations, solver, tolerance, torsional,
                gripper_mass, plate_mass, solimp=None, solreffriction=None):
    sc = lay.scene
    f = lambda v: " ".join(f"{float(x):.12g}" for x in np.ravel(v))  # noqa: E731
    lx, ly, lz = lay.size
    Mg = gripper_mass
    spin = lay.spin(torsional)
    condim = 4 if spin > 0 else 3
    # pads
    if lay.contact == "point":
        pad = f'type="sphere" size="{POINT_RADIUS}"'
    else:
        pad = f'type="box" size="{f(lay.pad_half)} {PAD_THICKNESS}"'
    pc = lay.pad_center
    # object joints (in the object's body frame = joint frame, axes of B rotated by theta0)
    Rj = lay.R_BC0
    ax = lambda v: f(Rj.T @ np.array(v, float))  # noqa: E731  B direction in body axes
    slides = (f'<joint name="on" type="slide" axis="{ax((0, 0, 1))}"/>'
              f'<joint name="ox" type="slide" axis="{ax((1, 0, 0))}"/>'
              f'<joint name="oy" type="slide" axis="{ax((0, 1, 0))}"/>')
    rot = ('<joint name="ob" type="ball"/>' if lay.rot_joint == "ball"
           else '<joint name="ob" type="hinge" axis="0 0 1"/>')
    if sc.dof == "translation":
        joints = slides
    elif sc.dof == "rotation":
        joints = f'<joint name="on" type="slide" axis="{ax((0, 0, 1))}"/>' + rot
    else:
        joints = slides + rot
    I = np.array(sc.body.inertia)
    full = f(([I[0, 0], I[1, 1], I[2, 2], I[0, 1], I[0, 2], I[1, 2]]))
    com = lay.com_in_joint
    # every contact pair's solver parameters (absent: MuJoCo's defaults)
    sol = ((f' solimp="{f(solimp)}"' if solimp is not None else "") +
           (f' solreffriction="{f(solreffriction)}"' if solreffriction is not None else ""))
    pairs = [f'<pair geom1="pad1" geom2="object" condim="{condim}"{sol} '
             f'friction="{f((lay.mu[0], lay.mu[0], spin, 0, 0))}"/>',
             f'<pair geom1="pad2" geom2="object" condim="{condim}"{sol} '
             f'friction="{f((max(lay.mu[1], 0.0), max(lay.mu[1], 0.0), spin if lay.mu[1] > 0 else 0.0, 0, 0))}"/>']
    stops = []
    for k, s in enumerate(sc.stops):
        c, R = _stop_pose(s)
        stops.append(f'<geom name="stop{k}" type="box" pos="{f(c)}" quat="{f(_quat_from_matrix(R))}" '
                     f'size="{f(STOP_HALF)}" contype="0" conaffinity="0"/>')
        # an explicit pair's friction replaces MuJoCo's combination of the geoms' (the max): exactly mu
        pairs.append(f'<pair geom1="stop{k}" geom2="object" condim="3"{sol} friction="{f((s.mu, s.mu, 0, 0, 0))}"/>'
                     if s.mu > 0 else f'<pair geom1="stop{k}" geom2="object" condim="1"{sol}/>')
    assets = []
    for k, (o, shape) in enumerate(zip(sc.obstacles, _obstacle_shapes(sc))):
        if shape[0] == "box":
            geom = (f'type="box" pos="{f(shape[1])}" quat="{f(_quat_from_matrix(shape[2]))}" '
                    f'size="{f(shape[3])}"')
        elif shape[0] == "cylinder":
            geom = (f'type="capsule" pos="{f(shape[1])}" quat="{f(_quat_from_matrix(shape[2]))}" '
                    f'size="{shape[3]!r} {shape[4]!r}"')
        else:   # MuJoCo collides with a mesh's convex hull
            assets.append(f'<mesh name="obstacle{k}" vertex="{f(shape[1])}"/>')
            geom = f'type="mesh" mesh="obstacle{k}"'
        stops.append(f'<geom name="obstacle{k}" {geom} contype="0" conaffinity="0"/>')
        pairs.append(f'<pair geom1="obstacle{k}" geom2="object" condim="3"{sol} friction="{f((o.mu, o.mu, 0, 0, 0))}"/>'
                     if o.mu > 0 else f'<pair geom1="obstacle{k}" geom2="object" condim="1"{sol}/>')
    obj_geom = (f'<geom name="object" type="box" pos="{f(com)}" size="{f(lay.size / 2)}" contype="0" conaffinity="0"/>'
                if lay.disc is None else
                f'<geom name="object" type="cylinder" pos="{f(com + lay.disc_center)}" size="{f((lay.disc, lz / 2))}" '
                f'contype="0" conaffinity="0"/>')
    return f"""<mujoco model="exdex-scene">
  <asset>{''.join(assets)}</asset>
  <option timestep="{dt!r}" gravity="{f(sc.gravity)}" cone="{cone}" impratio="{impratio!r}"
          noslip_iterations="{int(noslip_iterations)}" iterations="{int(iterations)}" solver="{solver}"
          tolerance="{tolerance!r}">
    <flag filterparent="disable"/>
  </option>
  <worldbody>
    {''.join(stops)}
    <body name="gripper">
      <freejoint name="gripper"/>
      <inertial pos="0 0 0" mass="{Mg!r}" diaginertia="{Mg!r} {Mg!r} {Mg!r}"/>
      <geom name="pad1" {pad} pos="{f(pc + [0, 0, -lay.pad_z])}" contype="0" conaffinity="0"/>
      <body name="plate2" pos="{f(pc + [0, 0, lay.pad_z])}">
        <joint name="squeeze" type="slide" axis="0 0 1"/>
        <inertial pos="0 0 0" mass="{plate_mass!r}" diaginertia="1e-4 1e-4 1e-4"/>
        <geom name="pad2" {pad} contype="0" conaffinity="0"/>
      </body>
      <body name="object" pos="{f(lay.joint_B)}" quat="{f(_quat_from_matrix(Rj))}">
        {joints}
        <inertial pos="{f(com)}" mass="{sc.body.mass!r}" fullinertia="{full}"/>
        {obj_geom}
      </body>
    </body>
  </worldbody>
  <contact>{''.join(pairs)}</contact>
</mujoco>"""


def _has_joint(m, name):
    try:
        m.joint(name)
        return True
    except KeyError:
        return False


def run_mujoco(scene, t_end, *, dt=0.002, iterations=100, cone="elliptic", impratio=1.0, noslip_iterations=0,
               solver="Newton", tolerance=1e-8, contact="pads", torsional=None, gripper_mass=1e4,
               plate_mass=0.1, solimp=None, solreffriction=None):
    """Simulate ``scene`` in MuJoCo from 0 to ``t_end`` [s]; return an ``exdex.Result``.

    Parameters (MuJoCo's own defaults unless said)
    ----------------------------------------------
    dt : time step [s] (MuJoCo default 0.002).
    iterations, solver, tolerance : main constraint solver (100, "Newton", 1e-8).
    cone : "elliptic" (default here: the faithful cone) or "pyramidal" (MuJoCo's default).
    impratio : ratio of frictional to normal constraint impedance (1).
    noslip_iterations : iterations of the noslip post-solve (0 = off).
    contact : "pads" (box pads, corner contacts) or "point" (one contact per
        finger with torsional friction mu * e_r: the ellipsoid, per contact).
    torsional : torsional friction length [m] per contact (default: mu e_r
        for "point", 0 for "pads").
    gripper_mass : mass of the kinematically driven gripper body [kg].
    plate_mass : mass of the pushed plate on its prismatic joint [kg].
    solimp : MuJoCo's contact impedance (d0, dwidth, width[, midpoint, power])
        of every contact pair (None: MuJoCo's default (0.9, 0.95, 0.001, 0.5, 2)).
    solreffriction : MuJoCo's reference (timeconst, dampratio), or in the
        direct format (-stiffness, -damping), of the frictional rows of every
        contact pair (None: the normal rows' solref, MuJoCo's default). In an
        elliptic cone a sliding contact pushes its normal with
        mu |a_t + B v_t| / (R_n (1 + mu^2 / impratio)) besides its penetration
        (a_t, v_t its slip acceleration and speed, B the frictional rows'
        damping, R_n = (1 - d) / d * A its normal regulariser, A the inverse
        mass there): a contact whose load falls below that separates and
        chatters while it slides; it slides on the cone (friction mu times
        its normal force) once mu |a_t + B v_t| exceeds (mu^2 / impratio) W R_n
        (W its load). A smaller d or B raises the slip speed it separates at,
        a larger impratio lowers the one it reaches the cone at.
    """
    mujoco = require("mujoco", "exdex.engines.run_mujoco")

    lay = _Layout(scene, contact)
    _check_static_friction(scene, "mujoco")
    n, dt = _steps(t_end, dt)
    if cone not in ("elliptic", "pyramidal"):
        raise ValueError(f"cone must be 'elliptic' or 'pyramidal', got {cone!r}")
    if solver not in ("Newton", "CG", "PGS"):
        raise ValueError(f"solver must be 'Newton', 'CG' or 'PGS', got {solver!r}")
    if solimp is not None:
        solimp = [_real(v, "solimp") for v in solimp]
        if len(solimp) not in (3, 5) or not (0 < solimp[0] < 1 and 0 < solimp[1] < 1 and solimp[2] >= 0):
            raise ValueError(f"solimp must be (d0, dwidth, width[, midpoint, power]) with 0 < d0, dwidth < 1 "
                             f"and width >= 0, got {solimp!r}")
    if solreffriction is not None:
        solreffriction = [_real(v, "solreffriction") for v in solreffriction]
        if len(solreffriction) != 2 or not (all(v > 0 for v in solreffriction) or all(v < 0 for v in solreffriction)):
            raise ValueError(f"solreffriction must be two reals of the same sign (timeconst, dampratio > 0 or "
                             f"-stiffness, -damping < 0), got {solreffriction!r}")
    xml = _mujoco_xml(lay, dt=dt, iterations=iterations, cone=cone, impratio=float(impratio),
                      noslip_iterations=noslip_iterations, solver=solver, tolerance=float(tolerance),
                      torsional=torsional, gripper_mass=float(gripper_mass), plate_mass=float(plate_mass),
                      solimp=solimp, solreffriction=solreffriction)
    m = mujoco.MjModel.from_xml_string(xml)
    d = mujoco.MjData(m)
    gid = m.body("gripper").id
    oid = m.body("object").id
    sq = m.joint("squeeze").dofadr[0]
    stop_gids = ([m.geom(f"stop{k}").id for k in range(len(scene.stops))] +
                 [m.geom(f"obstacle{k}").id for k in range(len(scene.obstacles))])
    Mg = float(gripper_mass)
    g, times, kin, pos, vel, RBC, om, fstop = _run_arrays(scene, n, dt)
    cf = np.zeros(6)

    def set_gripper(k):
        R = kin["R"][k]
        d.qpos[0:3] = kin["p"][k]
        d.qpos[3:7] = _quat_from_matrix(R)
        d.qvel[0:3] = kin["v"][k]
        d.qvel[3:6] = R.T @ kin["w"][k]
        d.xfrc_applied[gid, 0:3] = Mg * (kin["a"][k] - g)
        d.xfrc_applied[gid, 3:6] = Mg * kin["dw"][k]     # isotropic inertia: w x I w = 0
        d.qfrc_applied[sq] = -_grip_force(scene, (k + 0.5) * dt)

    dof = {name: m.joint(name).dofadr[0] for name in ("on", "ox", "oy", "ob") if _has_joint(m, name)}

    def record(k):
        R_AB = d.xmat[gid].reshape(3, 3)
        pos[k] = R_AB.T @ (d.xipos[oid] - d.xpos[gid])
        RBC[k] = R_AB.T @ d.xmat[oid].reshape(3, 3)   # the object's body axes are C's
        # relative velocities straight from the object's joints (children of the gripper)
        vel[k] = [d.qvel[dof["ox"]] if "ox" in dof else 0.0, d.qvel[dof["oy"]] if "oy" in dof else 0.0,
                  d.qvel[dof["on"]]]
        om[k] = d.qvel[dof["ob"] + (2 if lay.rot_joint == "ball" else 0)] if "ob" in dof else 0.0
        for j, sg in enumerate(stop_gids):
            tot = 0.0
            for i in range(d.ncon):
                c = d.contact[i]
                if sg in (c.geom1, c.geom2):
                    mujoco.mj_contactForce(m, d, i, cf)
                    tot += cf[0]
            fstop[k, j] = tot

    set_gripper(0)
    mujoco.mj_forward(m, d)
    record(0)
    t0 = time.perf_counter()
    for k in range(n):
        set_gripper(k)
        mujoco.mj_step(m, d)
        mujoco.mj_kinematics(m, d)   # poses of the new state for the record
        record(k + 1)
    wall = time.perf_counter() - t0
    stats = dict(engine="mujoco", version=mujoco.__version__, dt=dt, iterations=iterations, cone=cone,
                 impratio=impratio, noslip_iterations=noslip_iterations, solver=solver, contact=contact,
                 solimp=solimp, solreffriction=solreffriction,
                 torsional=lay.spin(torsional), wall_time=wall, steps=n)
    return _to_result(scene, "mujoco", times, pos, RBC, vel, om, fstop, stats, dt)


# ---------------------------------------------------------------- pybullet

def run_pybullet(scene, t_end, *, dt=1.0 / 240.0, iterations=50, cone=True, contact="pads", spinning=None,
                 erp=None, gripper_mass=1e4, plate_mass=0.1):
    """Simulate ``scene`` in pybullet (Bullet's Featherstone multibody) from 0
    to ``t_end`` [s]; return an ``exdex.Result``.

    Parameters (pybullet's own defaults unless said)
    ------------------------------------------------
    dt : fixed time step [s] (1/240).
    iterations : solver iterations (50).
    cone : enableConeFriction (True): the two lateral friction rows are
        projected onto the circle; False gives the square (4-facet) pyramid
        that circumscribes it.
    contact : "pads" or "point" (see the module docstring).
    spinning : spinning friction length [m] per contact (default: mu e_r for
        "point", 0 for "pads"); Bullet limits it independently of the lateral
        friction.
    erp : contact error reduction parameter (None: pybullet's default).
    gripper_mass, plate_mass : as for ``run_mujoco``.
    """
    pb = require("pybullet", "exdex.engines.run_pybullet")

    lay = _Layout(scene, contact)
    _check_static_friction(scene, "pybullet")
    n, dt = _steps(t_end, dt)
    cid = pb.connect(pb.DIRECT)
    kw = dict(physicsClientId=cid)
    try:
        pb.setGravity(*scene.gravity, **kw)
        params = dict(fixedTimeStep=dt, numSolverIterations=int(iterations), enableConeFriction=int(bool(cone)),
                      numSubSteps=0)
        if erp is not None:
            params["contactERP"] = float(erp)
        pb.setPhysicsEngineParameter(**params, **kw)
        spin = lay.spin(spinning)
        lx, ly, lz = lay.size
        pc = lay.pad_center
        if contact == "point":
            pad1 = pb.createCollisionShape(pb.GEOM_SPHERE, radius=POINT_RADIUS,
                                           collisionFramePosition=list(pc + [0, 0, -lay.pad_z]), **kw)
            pad2 = pb.createCollisionShape(pb.GEOM_SPHERE, radius=POINT_RADIUS, **kw)
        else:
            half = [lay.pad_half[0], lay.pad_half[1], PAD_THICKNESS]
            pad1 = pb.createCollisionShape(pb.GEOM_BOX, halfExtents=half,
                                           collisionFramePosition=list(pc + [0, 0, -lay.pad_z]), **kw)
            pad2 = pb.createCollisionShape(pb.GEOM_BOX, halfExtents=half, **kw)
        com = lay.R_C_principal  # principal axes in C
        if lay.disc is None:
            obj_shape = pb.createCollisionShape(pb.GEOM_BOX, halfExtents=list(lay.size / 2),
                                                collisionFramePosition=list(lay.com_in_joint), **kw)
        else:  # a disc outline: a cylinder along the plate normal (Bullet's cylinders run along z)
            obj_shape = pb.createCollisionShape(pb.GEOM_CYLINDER, radius=lay.disc, height=lz,
                                                collisionFramePosition=list(lay.com_in_joint + lay.disc_center), **kw)
        I4 = [0, 0, 0, 1]
        Rj = lay.R_BC0
        # links (parent indices are 1-based, 0 = the gripper base)
        links = [dict(mass=plate_mass, shape=pad2, pos=list(pc + [0, 0, lay.pad_z]), orn=I4, parent=0,
                      type=pb.JOINT_PRISMATIC, axis=[0, 0, 1])]
        eps_mass = 1e-6
        if scene.dof == "translation":
            chain = [("n", (0, 0, 1)), ("x", (1, 0, 0)), ("y", (0, 1, 0))]
        elif scene.dof == "rotation":
            chain = [("n", (0, 0, 1)), ("ball", None)]
        else:
            chain = [("n", (0, 0, 1)), ("x", (1, 0, 0)), ("y", (0, 1, 0)), ("ball", None)]
        for i, (name, axis) in enumerate(chain):
            last = i == len(chain) - 1
            first = i == 0
            links.append(dict(
                mass=scene.body.mass if last else eps_mass,
                shape=obj_shape if last else -1,
                pos=list(lay.joint_B) if first else [0, 0, 0],
                orn=_xyzw(Rj) if first else I4,
                parent=0 if first else len(links),
                type=(pb.JOINT_PRISMATIC if name != "ball" else
                      pb.JOINT_SPHERICAL if lay.rot_joint == "ball" else pb.JOINT_REVOLUTE),
                axis=list(Rj.T @ np.array(axis, float)) if axis is not None else [0, 0, 1]))
        obj_link = len(links) - 1
        jidx = {name: 1 + i for i, (name, _) in enumerate(chain)}
        Mg = float(gripper_mass)
        R0 = np.array(scene.gripper_rotation)
        body = pb.createMultiBody(
            baseMass=Mg, baseCollisionShapeIndex=pad1, basePosition=list(scene.gripper_position),
            baseOrientation=_xyzw(R0),
            linkMasses=[L["mass"] for L in links], linkCollisionShapeIndices=[L["shape"] for L in links],
            linkVisualShapeIndices=[-1] * len(links), linkPositions=[L["pos"] for L in links],
            linkOrientations=[L["orn"] for L in links],
            linkInertialFramePositions=[[0, 0, 0]] * (len(links) - 1) + [list(lay.com_in_joint)],
            linkInertialFrameOrientations=[I4] * (len(links) - 1) + [_xyzw(com)],
            linkParentIndices=[L["parent"] for L in links], linkJointTypes=[L["type"] for L in links],
            linkJointAxis=[L["axis"] for L in links], flags=pb.URDF_USE_SELF_COLLISION, **kw)
        pb.changeDynamics(body, -1, localInertiaDiagonal=[Mg, Mg, Mg], lateralFriction=lay.mu[0],
                          spinningFriction=spin, rollingFriction=0, linearDamping=0, angularDamping=0, **kw)
        pb.changeDynamics(body, 0, lateralFriction=lay.mu[1], spinningFriction=spin if lay.mu[1] > 0 else 0.0,
                          rollingFriction=0, linearDamping=0, angularDamping=0, jointDamping=0, **kw)
        for j in range(1, len(links)):
            pb.changeDynamics(body, j, lateralFriction=1.0, spinningFriction=0, rollingFriction=0,
                              linearDamping=0, angularDamping=0, jointDamping=0, **kw)
            if j < obj_link:
                pb.changeDynamics(body, j, localInertiaDiagonal=[eps_mass * 1e-4] * 3, **kw)
        pb.changeDynamics(body, obj_link, localInertiaDiagonal=list(lay.I_principal), **kw)
        for j in range(len(links)):
            if links[j]["type"] == pb.JOINT_SPHERICAL:
                pb.setJointMotorControlMultiDof(body, j, pb.POSITION_CONTROL, targetPosition=[0, 0, 0, 1],
                                                positionGain=0, velocityGain=0, force=[0, 0, 0], **kw)
            else:
                pb.setJointMotorControl2(body, j, pb.VELOCITY_CONTROL, force=0, **kw)
        # only the pads (and stops) touch the object
        for j in range(1, obj_link):
            for other in [-1, 0] + list(range(1, obj_link)):
                pb.setCollisionFilterPair(body, body, j, other, 0, **kw)
        pb.setCollisionFilterPair(body, body, -1, 0, 0, **kw)
        stop_ids = []
        for s in scene.stops:
            c, R = _stop_pose(s)
            sh = pb.createCollisionShape(pb.GEOM_BOX, halfExtents=list(STOP_HALF), **kw)
            sid = pb.createMultiBody(baseMass=0, baseCollisionShapeIndex=sh, basePosition=list(c),
                                     baseOrientation=_xyzw(R), **kw)
            # Bullet multiplies the two bodies' lateral friction: the object link has 1, so the pair gets mu
            pb.changeDynamics(sid, -1, lateralFriction=s.mu, spinningFriction=0.0, rollingFriction=0.0, **kw)
            for j in range(-1, obj_link):
                pb.setCollisionFilterPair(sid, body, -1, j, 0, **kw)
            stop_ids.append(sid)
        for o, shape in zip(scene.obstacles, _obstacle_shapes(scene)):
            if shape[0] == "box":
                sh = pb.createCollisionShape(pb.GEOM_BOX, halfExtents=list(shape[3]), **kw)
                c, orn = shape[1], _xyzw(shape[2])
            elif shape[0] == "cylinder":
                sh = pb.createCollisionShape(pb.GEOM_CAPSULE, radius=shape[3], height=2 * shape[4], **kw)
                c, orn = shape[1], _xyzw(shape[2])
            else:   # Bullet collides with a mesh's convex hull
                c = shape[1].mean(axis=0)
                sh = pb.createCollisionShape(pb.GEOM_MESH, vertices=(shape[1] - c).tolist(), **kw)
                orn = [0, 0, 0, 1]
            sid = pb.createMultiBody(baseMass=0, baseCollisionShapeIndex=sh, basePosition=list(c),
                                     baseOrientation=orn, **kw)
            pb.changeDynamics(sid, -1, lateralFriction=o.mu, spinningFriction=0.0, rollingFriction=0.0, **kw)
            for j in range(-1, obj_link):
                pb.setCollisionFilterPair(sid, body, -1, j, 0, **kw)
            stop_ids.append(sid)

        times = np.arange(n + 1) * dt
        kin = _kinematics(scene, times)
        g = np.array(scene.gravity)
        pos = np.empty((n + 1, 3))
        vel = np.empty((n + 1, 3))
        RBC = np.empty((n + 1, 3, 3))
        om = np.empty(n + 1)
        fstop = np.zeros((n + 1, len(stop_ids)))
        R_principal_T = lay.R_C_principal.T

        def set_gripper(k):
            pb.resetBasePositionAndOrientation(body, list(kin["p"][k]), _xyzw(kin["R"][k]), **kw)
            pb.resetBaseVelocity(body, list(kin["v"][k]), list(kin["w"][k]), **kw)

        def drive(k):
            pb.applyExternalForce(body, -1, list(Mg * (kin["a"][k] - g)), list(kin["p"][k]), pb.WORLD_FRAME, **kw)
            pb.applyExternalTorque(body, -1, list(Mg * kin["dw"][k]), pb.WORLD_FRAME, **kw)
            pb.setJointMotorControl2(body, 0, pb.TORQUE_CONTROL, force=-_grip_force(scene, (k + 0.5) * dt), **kw)

        def record(k):
            pB, qB = pb.getBasePositionAndOrientation(body, **kw)
            R_AB = np.array(pb.getMatrixFromQuaternion(qB, **kw)).reshape(3, 3)
            ls = pb.getLinkState(body, obj_link, computeForwardKinematics=1, **kw)
            pC = np.array(ls[0])
            R_A_inertial = np.array(pb.getMatrixFromQuaternion(ls[1], **kw)).reshape(3, 3)
            R_AC = R_A_inertial @ R_principal_T
            pos[k] = R_AB.T @ (pC - np.array(pB))
            RBC[k] = R_AB.T @ R_AC
            # relative velocities straight from the object's joints (children of the gripper)
            js = {name: pb.getJointState(body, j, **kw)[1] for name, j in jidx.items() if name != "ball"}
            vel[k] = [js.get("x", 0.0), js.get("y", 0.0), js["n"]]
            if "ball" not in jidx:
                om[k] = 0.0
            elif lay.rot_joint == "ball":
                om[k] = pb.getJointStateMultiDof(body, jidx["ball"], **kw)[1][2]
            else:
                om[k] = pb.getJointState(body, jidx["ball"], **kw)[1]
            for j, sid in enumerate(stop_ids):
                fstop[k, j] = sum(cp[9] for cp in pb.getContactPoints(sid, body, -1, obj_link, **kw))

        set_gripper(0)
        record(0)
        t0 = time.perf_counter()
        for k in range(n):
            set_gripper(k)
            drive(k)
            pb.stepSimulation(**kw)
            record(k + 1)
        wall = time.perf_counter() - t0
    finally:
        pb.disconnect(cid)
    stats = dict(engine="pybullet", dt=dt, iterations=iterations, cone=bool(cone), contact=contact,
                 spinning=spin, erp=erp, wall_time=wall, steps=n)
    return _to_result(scene, "pybullet", times, pos, RBC, vel, om, fstop, stats, dt)


# ---------------------------------------------------------------- Drake

DRAKE_CONTACT_MODELS = ("point", "hydroelastic")
DRAKE_APPROXIMATIONS = ("lagged", "sap", "similar", "tamsi")


def _drake_pad_shapes(lay, contact_model):
    """[(kind, offset in the pad frame)] of the collision shapes of one finger.

    kind is "box" (half-extents lay.pad_half, PAD_THICKNESS) or "sphere"
    (POINT_RADIUS). Drake's point contact between two boxes gives a single
    contact point, so with point contact the pads of a rotation or planar
    scene become the pad's corner points (spheres), as the other engines'
    box-box manifolds do; translation plates stay boxes (one point suffices
    when the object cannot turn)."""
    if lay.contact == "point":
        return [("sphere", np.zeros(3))]
    if contact_model == "hydroelastic" or lay.scene.dof == "translation":
        return [("box", np.zeros(3))]
    a, b = lay.pad_half
    return [("sphere", np.array([sx * a, sy * b, 0.0])) for sx, sy in ((1, 1), (-1, 1), (-1, -1), (1, -1))]


def run_drake(scene, t_end, *, dt=1e-3, contact_model="point", approximation="lagged", stiction_tolerance=1e-4,
              contact="pads", hydroelastic_modulus=1e6, object_modulus=None, resolution_hint=None,
              point_stiffness=None, dissipation=None, gripper_mass=1e4, plate_mass=0.1, stop_contact="box"):
    """Simulate ``scene`` in Drake (pydrake's discrete MultibodyPlant) from 0 to
    ``t_end`` [s]; return an ``exdex.Result``.

    The scene is built as for the other engines (a kinematically driven
    gripper body, plate 2 on a prismatic joint pushed by ``grip_force``, the
    object on joints relative to the gripper); the object turns on a revolute
    joint about the plate normal (no out-of-plane tilt).

    Parameters (Drake's own defaults unless said)
    ---------------------------------------------
    dt : time step of the discrete plant [s] (1e-3).
    contact_model : "point" (Drake's compliant point contact) or
        "hydroelastic" (compliant hydroelastic pads pressing a rigid object:
        a pressure patch per finger, from which torsional friction emerges;
        stops keep point contact, Drake's "hydroelastic_with_fallback").
    approximation : discrete contact approximation: "lagged" (Drake's
        default), "sap", "similar" or "tamsi".
    stiction_tolerance : regularisation of friction [m/s] (Drake's default
        1e-4): an in-cone load slips at a speed up to this value. Used by
        "lagged", "similar" and "tamsi"; "sap" regularises by its own
        near-rigid parameter instead.
    contact : "pads" or "point" (see the module docstring). With point contact
        and "pads", rotation and planar scenes get one small sphere at each
        pad corner (Drake's box-box point contact is a single point).
        Drake has no torsional friction at a point contact.
    hydroelastic_modulus : modulus of the compliant pads [Pa] (1e6).
    object_modulus : None (rigid object) or the object's hydroelastic modulus [Pa].
    resolution_hint : hydroelastic mesh resolution of tessellated shapes [m]
        (default: a quarter of a sphere pad's radius; Drake meshes boxes by
        its own rule).
    point_stiffness, dissipation : point-contact stiffness [N/m] and
        Hunt-Crossley dissipation [s/m] (None: Drake's defaults).
    gripper_mass, plate_mass : as for ``run_mujoco``.
    stop_contact : how the object meets the stops and obstacles: "box"
        (default: its box, which Drake's point contact touches at a single
        point per stop) or
        "corners" (a sphere of radius ``POINT_RADIUS`` inside each corner of
        the box's section by the plate plane, touching its two faces there:
        one point contact per touching outline vertex, as in exdex; the box
        then meets only the pads). A disc outline takes "box" only (its
        cylinder meets the stops; it has no corners).
    """
    pydrake = require("pydrake", "exdex.engines.run_drake")
    from pydrake.geometry import (AddCompliantHydroelasticProperties, AddContactMaterial,
                                  AddRigidHydroelasticProperties, Box, Capsule, CollisionFilterDeclaration, Convex,
                                  Cylinder, GeometrySet, ProximityProperties, Sphere)
    from pydrake.math import RigidTransform, RotationMatrix
    from pydrake.multibody.math import SpatialForce, SpatialVelocity
    from pydrake.multibody.plant import (AddMultibodyPlant, CoulombFriction, ExternallyAppliedSpatialForce,
                                        MultibodyPlantConfig)
    from pydrake.multibody.tree import (PrismaticJoint, RevoluteJoint, RotationalInertia, SpatialInertia,
                                        UnitInertia)
    from pydrake.systems.analysis import Simulator
    from pydrake.systems.framework import DiagramBuilder

    lay = _Layout(scene, contact)
    _check_static_friction(scene, "drake")
    n, dt = _steps(t_end, dt)
    if stop_contact not in ("box", "corners"):
        raise ValueError(f"stop_contact must be 'box' or 'corners', got {stop_contact!r}")
    if stop_contact == "corners" and lay.disc is not None:
        raise ValueError("stop_contact='corners' needs a polygon outline (spheres in the box's corners); "
                         "a disc outline (Body.outline_radius) has none: use stop_contact='box'")
    if contact_model not in DRAKE_CONTACT_MODELS:
        raise ValueError(f"contact_model must be one of {DRAKE_CONTACT_MODELS}, got {contact_model!r}")
    if approximation not in DRAKE_APPROXIMATIONS:
        raise ValueError(f"approximation must be one of {DRAKE_APPROXIMATIONS}, got {approximation!r}")
    vs = _real(stiction_tolerance, "stiction_tolerance", low=0.0, low_open=True)
    E = _real(hydroelastic_modulus, "hydroelastic_modulus", low=0.0, low_open=True)
    if object_modulus is not None:
        object_modulus = _real(object_modulus, "object_modulus", low=0.0, low_open=True)
    Mg = _real(gripper_mass, "gripper_mass", low=0.0, low_open=True)
    mp = _real(plate_mass, "plate_mass", low=0.0, low_open=True)
    lx, ly, lz = lay.size
    shapes = _drake_pad_shapes(lay, contact_model)
    if resolution_hint is not None:
        resolution_hint = _real(resolution_hint, "resolution_hint", low=0.0, low_open=True)

    def hint(size):
        """The user's resolution, else a quarter of a sphere's radius (boxes: their size)."""
        if resolution_hint is not None:
            return resolution_hint
        return max(size) if len(size) == 3 else size[0] / 4

    builder = DiagramBuilder()
    config = MultibodyPlantConfig(time_step=dt, stiction_tolerance=vs,
                                  contact_model="point" if contact_model == "point" else "hydroelastic_with_fallback",
                                  discrete_contact_approximation=approximation,
                                  adjacent_bodies_collision_filters=False)
    plant, sg = AddMultibodyPlant(config, builder)

    def inertia_zero():   # the massless links between the object's joints
        return SpatialInertia(0.0, np.zeros(3), UnitInertia(0.0, 0.0, 0.0))

    gripper = plant.AddRigidBody("gripper", SpatialInertia(Mg, np.zeros(3), UnitInertia(1.0, 1.0, 1.0)))
    plate2 = plant.AddRigidBody("plate2", SpatialInertia(mp, np.zeros(3), UnitInertia(1e-3, 1e-3, 1e-3)))
    I = np.array(scene.body.inertia)
    com = np.array(lay.com_in_joint)
    obj_inertia = SpatialInertia.MakeFromCentralInertia(
        scene.body.mass, com, RotationalInertia(I[0, 0], I[1, 1], I[2, 2], I[0, 1], I[0, 2], I[1, 2]))
    obj = plant.AddRigidBody("object", obj_inertia)
    pc = lay.pad_center
    X = lambda R, p: RigidTransform(RotationMatrix(np.asarray(R, float)), np.asarray(p, float))  # noqa: E731
    # plate 2: prismatic along B z, pushed towards the object by the grip force
    F2 = plant.AddFrame(_fixed_frame(plant, "plate2_seat", gripper.body_frame(), X(np.eye(3), pc + [0, 0, lay.pad_z])))
    squeeze = plant.AddJoint(PrismaticJoint("squeeze", F2, plate2.body_frame(), [0.0, 0.0, 1.0]))
    plant.AddJointActuator("squeeze", squeeze)
    # object joints, in the joint frame J (at joint_B, axes of B turned by theta0)
    Rj = lay.R_BC0
    J = plant.AddFrame(_fixed_frame(plant, "object_seat", gripper.body_frame(), X(Rj, lay.joint_B)))
    chain = [("on", "slide", (0, 0, 1))]
    if scene.dof in ("translation", "planar"):
        chain += [("ox", "slide", (1, 0, 0)), ("oy", "slide", (0, 1, 0))]
    if scene.dof in ("rotation", "planar"):
        chain.append(("ob", "hinge", (0, 0, 1)))
    joints = {}
    parent = J
    for i, (name, kind, axis) in enumerate(chain):
        last = i == len(chain) - 1
        child = obj if last else plant.AddRigidBody(f"link_{name}", inertia_zero())
        a = Rj.T @ np.array(axis, float) if kind == "slide" else np.array([0.0, 0.0, 1.0])
        if kind == "slide":
            jt = PrismaticJoint(name, parent, child.body_frame(), a)
        else:
            jt = RevoluteJoint(name, parent, child.body_frame(), a)
        joints[name] = plant.AddJoint(jt)
        parent = child.body_frame()
    # geometry
    def props(mu, compliant=None, rigid=False, size=(POINT_RADIUS,)):
        p = ProximityProperties()
        AddContactMaterial(dissipation, point_stiffness, CoulombFriction(mu, mu), p)
        if compliant is not None:
            AddCompliantHydroelasticProperties(hint(size), compliant, p)
        elif rigid:
            AddRigidHydroelasticProperties(hint(size), p)
        return p

    hydro = contact_model == "hydroelastic"
    pad_ids = []
    mu_obj, (mu_pad1, mu_pad2, *mu_stops) = _drake_friction([lay.mu[0], lay.mu[1]] + [s.mu for s in scene.stops]
                                                            + [o.mu for o in scene.obstacles])
    for body, sign, mu, X0 in ((gripper, -1.0, mu_pad1, pc + [0, 0, -lay.pad_z]), (plate2, 1.0, mu_pad2, np.zeros(3))):
        for k, (kind, off) in enumerate(shapes):
            size = (2 * lay.pad_half[0], 2 * lay.pad_half[1], 2 * PAD_THICKNESS) if kind == "box" else (POINT_RADIUS,)
            shape = Box(*size) if kind == "box" else Sphere(POINT_RADIUS)
            gid = plant.RegisterCollisionGeometry(body, X(np.eye(3), X0 + off), shape, f"{body.name()}_pad{k}",
                                                  props(mu, compliant=E if hydro else None, size=size))
            pad_ids.append(gid)
    # Drake combines two surfaces' mu as 2 mu1 mu2 / (mu1 + mu2): the object gets the largest
    # pair coefficient and each pad and stop its partner (_drake_friction), so every pair gets its own
    obj_props = props(mu_obj, compliant=object_modulus if hydro else None,
                      rigid=hydro and object_modulus is None, size=(lx, ly, lz))
    if lay.disc is None:
        obj_id = plant.RegisterCollisionGeometry(obj, X(np.eye(3), com), Box(lx, ly, lz), "object", obj_props)
    else:  # a disc outline: a cylinder along the plate normal (Drake's cylinders run along z)
        obj_id = plant.RegisterCollisionGeometry(obj, X(np.eye(3), com + lay.disc_center), Cylinder(lay.disc, lz),
                                                 "object", obj_props)
    corner_ids = []
    if stop_contact == "corners":
        r = POINT_RADIUS
        for sx, sy in ((1, 1), (-1, 1), (-1, -1), (1, -1)):
            off = com + [sx * (lx / 2 - r), sy * (ly / 2 - r), 0.0]
            corner_ids.append(plant.RegisterCollisionGeometry(obj, X(np.eye(3), off), Sphere(r), f"corner{len(corner_ids)}",
                                                              props(mu_obj)))
    stop_ids = []
    for k, s in enumerate(scene.stops):
        c, R = _stop_pose(s)
        stop_ids.append(plant.RegisterCollisionGeometry(plant.world_body(), X(R, c), Box(*(2 * np.array(STOP_HALF))),
                                                        f"stop{k}", props(mu_stops[k])))
    for k, shape in enumerate(_obstacle_shapes(scene)):
        mu_k = mu_stops[len(scene.stops) + k]
        if shape[0] == "box":
            geo, Xo = Box(*(2 * np.asarray(shape[3]))), X(shape[2], shape[1])
        elif shape[0] == "cylinder":
            geo, Xo = Capsule(shape[3], 2 * shape[4]), X(shape[2], shape[1])
        else:   # Drake collides with a Convex shape's hull
            from pydrake.common import MemoryFile
            from pydrake.geometry import InMemoryMesh

            geo = Convex(InMemoryMesh(mesh_file=MemoryFile(_obj_text(shape[1]), ".obj", f"obstacle{k}.obj")))
            Xo = X(np.eye(3), np.zeros(3))
        stop_ids.append(plant.RegisterCollisionGeometry(plant.world_body(), Xo, geo, f"obstacle{k}", props(mu_k)))
    plant.Finalize()
    # only the pads and the stops touch the object
    cfm = sg.collision_filter_manager()
    cfm.Apply(CollisionFilterDeclaration().ExcludeWithin(GeometrySet(pad_ids + stop_ids)))
    if corner_ids:   # the corner spheres meet the stops, the box the pads
        cfm.Apply(CollisionFilterDeclaration().ExcludeBetween(GeometrySet(corner_ids), GeometrySet(pad_ids)))
        cfm.Apply(CollisionFilterDeclaration().ExcludeBetween(GeometrySet([obj_id]), GeometrySet(stop_ids)))
    diagram = builder.Build()
    ctx = diagram.CreateDefaultContext()
    pctx = plant.GetMyMutableContextFromRoot(ctx)
    actuation = plant.get_actuation_input_port()
    force_port = plant.get_applied_spatial_force_input_port()
    g, times, kin, pos, vel, RBC, om, fstop = _run_arrays(scene, n, dt)
    # initial joint state: plate 2 touching, object at q0 (joints at zero)
    wrench = ExternallyAppliedSpatialForce()
    wrench.body_index = gripper.index()
    wrench.p_BoBq_B = np.zeros(3)
    nv_idx = {name: j.velocity_start() for name, j in joints.items()}
    gb = gripper

    def set_gripper(k):
        plant.SetFreeBodyPose(pctx, gb, X(kin["R"][k], kin["p"][k]))
        plant.SetFreeBodySpatialVelocity(pctx, gb, SpatialVelocity(kin["w"][k], kin["v"][k]))
        wrench.F_Bq_W = SpatialForce(Mg * kin["dw"][k], Mg * (kin["a"][k] - g))
        force_port.FixValue(pctx, [wrench])
        actuation.FixValue(pctx, [-_grip_force(scene, (k + 0.5) * dt)])

    query_port = plant.get_contact_results_output_port()

    def record(k):
        X_AB = plant.EvalBodyPoseInWorld(pctx, gb)
        X_AC = plant.EvalBodyPoseInWorld(pctx, obj)
        R_AB = X_AB.rotation().matrix()
        R_AC = X_AC.rotation().matrix()
        p_com = X_AC.translation() + R_AC @ com
        pos[k] = R_AB.T @ (p_com - X_AB.translation())
        RBC[k] = R_AB.T @ R_AC
        v = plant.GetVelocities(pctx)
        vel[k] = [v[nv_idx["ox"]] if "ox" in nv_idx else 0.0, v[nv_idx["oy"]] if "oy" in nv_idx else 0.0,
                  v[nv_idx["on"]]]
        om[k] = v[nv_idx["ob"]] if "ob" in nv_idx else 0.0
        if stop_ids:
            cr = query_port.Eval(pctx)
            for i in range(cr.num_point_pair_contacts()):
                info = cr.point_pair_contact_info(i)
                pair = info.point_pair()
                for j, sid in enumerate(stop_ids):
                    if sid in (pair.id_A, pair.id_B):
                        fstop[k, j] += abs(float(np.dot(info.contact_force(), pair.nhat_BA_W)))

    set_gripper(0)
    record(0)
    sim = Simulator(diagram, ctx)
    sim.Initialize()
    t0 = time.perf_counter()
    for k in range(n):
        set_gripper(k)
        sim.AdvanceTo((k + 1) * dt)
        record(k + 1)
    wall = time.perf_counter() - t0
    stats = dict(engine="drake", version=getattr(pydrake, "__version__", ""), dt=dt,
                 contact_model=contact_model, approximation=approximation, stiction_tolerance=vs, contact=contact,
                 stop_contact=stop_contact,
                 hydroelastic_modulus=E if hydro else None, wall_time=wall, steps=n)
    return _to_result(scene, "drake", times, pos, RBC, vel, om, fstop, stats, dt)


def _fixed_frame(plant, name, parent, X):
    from pydrake.multibody.tree import FixedOffsetFrame

    return FixedOffsetFrame(name, parent, X)


# ---------------------------------------------------------------- friction-model ablation (issue item 3)
#
# In a 1-DoF scene every maximum-dissipation friction model with a centrally
# symmetric convex friction set per contact reduces *exactly* to one number:
# the largest generalised friction force the contacts can exert against the
# free coordinate (stick: any force up to it; slip: exactly it, opposing the
# motion). For a pivoted rotation about the patch centre the slip twist there
# is a pure spin, so exdex's ellipsoid gives the torque mu N e_r; a model M
# gives mu N e_r(M), and exdex with e_r := e_r(M) *is* that model. For a
# translation the force mu N becomes mu(M) N. The engines' simplifications:
#   pyramid N   : a linearised cone with N facets fixed to the B axes,
#                 inscribed (vertices on the circle, MuJoCo's "pyramidal" with
#                 N = 4) or circumscribed (facets tangent, Bullet without cone
#                 friction, N = 4), applied at every point of the patch;
#   cylinder    : spin limit independent of the tangential one (Bullet's
#                 spinning friction): |f| <= mu N and |m| <= mu N e_r. A pure
#                 spin (pivoted rotation) or a pure slide meets the same limit
#                 as the ellipsoid, so it changes nothing in 1-DoF scenes;
#   corners     : the patch replaced by equal point contacts at its corners
#                 (the engines' box-box manifolds), each with a circular cone.

ABLATION_MODELS = ("ellipsoid", "cylinder", "pyramid4-in", "pyramid4-out", "pyramid8-in", "corners",
                   "corners+pyramid4-in", "corners+pyramid4-out")


def _support(phi, facets, inscribed):
    """Support function of the linearised unit friction disc in direction phi
    (the largest friction a contact can oppose to a slip along phi): 1 for the
    circle (facets=0), else the regular polygon with a vertex (inscribed) or a
    facet normal (circumscribed) on the B x axis."""
    phi = np.asarray(phi, dtype=float)
    if not facets:
        return np.ones_like(phi)
    if inscribed:      # vertices at angles 2 pi k / N on the unit circle
        k = 2 * np.pi * np.arange(facets) / facets
        return np.max(np.cos(phi[..., None] - k), axis=-1)
    # facet normals at 2 pi k / N, facets tangent to the circle: vertices at
    # 2 pi (k + 1/2) / N, a distance 1 / cos(pi / N) out
    k = 2 * np.pi * (np.arange(facets) + 0.5) / facets
    return np.max(np.cos(phi[..., None] - k), axis=-1) / np.cos(np.pi / facets)


def _parse_model(model):
    if model not in ABLATION_MODELS:
        raise ValueError(f"model must be one of {ABLATION_MODELS}, got {model!r}")
    corners = model.startswith("corners")
    facets, inscribed = 0, True
    if "pyramid" in model:
        part = model.split("pyramid")[1]
        facets = int(part.split("-")[0])
        inscribed = part.endswith("-in")
    return corners, facets, inscribed


def torque_capacity(patch, model="ellipsoid", grid=400):
    """Equivalent e_r [m] of ``patch`` under a friction ``model`` for a spin about the patch centre.

    The largest friction torque is mu N e_r(model). Uniform pressure over the
    patch's footprint (disc, rectangle; a patch given by e_r alone is the
    square with that e_r). ``"ellipsoid"`` and ``"cylinder"`` return
    ``patch.e_r``; distributed pyramids are integrated by the midpoint rule on
    a grid x grid mesh (relative error ~1e-5 at 400); corners are exact.
    """
    corners, facets, inscribed = _parse_model(model)
    if not corners and not facets:
        return float(patch.e_r)
    if corners:
        a, b = pad_geometry(patch)
        pts = np.array([(a, b), (-a, b), (-a, -b), (a, -b)])
        r = np.hypot(pts[:, 0], pts[:, 1])
        phi = np.arctan2(pts[:, 1], pts[:, 0]) + np.pi / 2     # slip direction of a positive spin
        return float(np.mean(r * _support(phi, facets, inscribed)))
    if patch.shape == "disc" and patch.dims:
        R = patch.dims[0]
        u = (np.arange(grid) + 0.5) / grid
        x, y = np.meshgrid((2 * u - 1) * R, (2 * u - 1) * R)
        inside = x**2 + y**2 <= R**2
    else:
        a, b = pad_geometry(patch)
        u = (np.arange(grid) + 0.5) / grid
        x, y = np.meshgrid((2 * u - 1) * a, (2 * u - 1) * b)
        inside = np.ones_like(x, dtype=bool)
    r = np.hypot(x, y)[inside]
    phi = np.arctan2(y, x)[inside] + np.pi / 2
    return float(np.mean(r * _support(phi, facets, inscribed)))


def ablation(scene, t_end, dt=1e-3, models=ABLATION_MODELS):
    """Run exdex with each friction ``model`` in place of the ellipsoid.

    1-DoF scenes (the reduction is exact there, see the comment above):
    rotation scenes get the model's equivalent e_r (``torque_capacity``),
    translation scenes the model's equivalent mu (support of the linearised
    cone along the slide axis; corners and the cylinder change nothing).
    Planar scenes get the model's equivalent e_r, as rotation scenes: exact
    for a pure spin about the patch centre, an approximation when the object
    slides and spins at once (the coupling stays the ellipsoid's), and the
    model's mu is kept (the slide direction is not known in advance).
    Returns {model: (exdex.Result, equivalent e_r [m] or mu)}.
    """
    import dataclasses

    from exdex.simulate import simulate

    out = {}
    for model in models:
        corners, facets, inscribed = _parse_model(model)
        if scene.dof in ("rotation", "planar"):
            er = torque_capacity(scene.grasp.patch, model)
            patch = dataclasses.replace(scene.grasp.patch, e_r=er)
            sc = dataclasses.replace(scene, grasp=dataclasses.replace(scene.grasp, patch=patch))
            value = er
        else:
            phi = math.atan2(scene.slide_axis[1], scene.slide_axis[0])
            mu = scene.grasp.mu * float(_support(np.array(phi), facets, inscribed))
            sc = dataclasses.replace(scene, grasp=dataclasses.replace(scene.grasp, mu=mu))
            value = mu
        out[model] = (simulate(sc, t_end, dt=dt), value)
    return out


#: the Python packages of the ``engines`` extra: (import name, distribution)
ENGINE_PACKAGES = (("pybullet", "pybullet"), ("mujoco", "mujoco"), ("pydrake", "drake"))


def missing_engines():
    """The distributions of the ``engines`` extra that do not import here (a list, empty when all do)."""
    import importlib.util

    return [dist for mod, dist in ENGINE_PACKAGES if importlib.util.find_spec(mod) is None]

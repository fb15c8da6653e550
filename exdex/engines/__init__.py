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
  the joints at the centroid of the region at the start (exdex's pivot);
  the limit surface is the engine's own (``Grasp.limit_surface`` is not
  read). Bullet's solver loads one corner of a pad with most of the grip,
  so a box turning on pads in pybullet turns about that corner.
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
``exdex compare`` (``exdex.cli.compare``) runs the paper cases and the planar
case in exdex and the three engines; ``exdex hold`` the hold benchmark
(``exdex.studies.hold``).
"""
from exdex.engines._runner import (ENGINE_PACKAGES, OBSTACLE_REACH, PAD_THICKNESS, POINT_RADIUS, STOP_HALF,
                                   drift_rate, missing_engines, pad_geometry)
from exdex.engines.ablation import ABLATION_MODELS, ablation, torque_capacity
from exdex.engines.drake import DRAKE_APPROXIMATIONS, DRAKE_CONTACT_MODELS, run_drake
from exdex.engines.mujoco import run_mujoco
from exdex.engines.pybullet import run_pybullet

__all__ = ["run_pybullet", "run_mujoco", "run_drake", "missing_engines", "drift_rate", "pad_geometry", "torque_capacity",
           "ablation", "ABLATION_MODELS", "OBSTACLE_REACH", "DRAKE_CONTACT_MODELS", "DRAKE_APPROXIMATIONS"]

"""exdex scenes run in Drake (``run_drake``): point or hydroelastic contact, four discrete approximations."""
from __future__ import annotations

import time

import numpy as np

from exdex._optional import require
from exdex._validate import real as _real
from exdex.engines._runner import (check_static_friction as _check_static_friction,
                                  drake_friction as _drake_friction, grip_force_at as _grip_force,
                                  Layout as _Layout, obj_text as _obj_text, obstacle_shapes as _obstacle_shapes,
                                  PAD_THICKNESS, POINT_RADIUS, run_arrays as _run_arrays, step_count as _steps,
                                  STOP_HALF, stop_pose as _stop_pose, to_result as _to_result)
from exdex.simulate import Result

__all__ = ['DRAKE_CONTACT_MODELS', 'DRAKE_APPROXIMATIONS', 'run_drake']


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

"""exdex scenes run in pybullet (``run_pybullet``)."""
from __future__ import annotations

import time

import numpy as np

from exdex._optional import require
from exdex.engines._runner import (check_static_friction as _check_static_friction, grip_force_at as _grip_force,
                                  gripper_kinematics as _kinematics, Layout as _Layout,
                                  obstacle_shapes as _obstacle_shapes, PAD_THICKNESS, POINT_RADIUS,
                                  step_count as _steps, STOP_HALF, stop_pose as _stop_pose,
                                  to_result as _to_result, xyzw as _xyzw)
from exdex.simulate import Result

__all__ = ['run_pybullet']


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

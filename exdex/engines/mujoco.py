"""exdex scenes run in MuJoCo (``run_mujoco``); the scene as MJCF (``mujoco_xml``)."""
from __future__ import annotations

import time

import numpy as np

from exdex._optional import require
from exdex._rotations import quat_from_matrix as _quat_from_matrix
from exdex._validate import real as _real
from exdex.engines._runner import (check_static_friction as _check_static_friction, grip_force_at as _grip_force,
                                  Layout as _Layout, obstacle_shapes as _obstacle_shapes, PAD_THICKNESS,
                                  POINT_RADIUS, run_arrays as _run_arrays, step_count as _steps, STOP_HALF,
                                  stop_pose as _stop_pose, to_result as _to_result)
from exdex.simulate import Result

__all__ = ['mujoco_xml', 'run_mujoco']


def mujoco_xml(lay, *, dt, iterations, cone, impratio, noslip_iterations, solver, tolerance, torsional,
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
    xml = mujoco_xml(lay, dt=dt, iterations=iterations, cone=cone, impratio=float(impratio),
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

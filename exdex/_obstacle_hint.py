"""The rotation model against obstacles: whether its pivot lies inside an
obstacle, and the SolverError message of a rotation run that cannot clear
one (shared by exdex.simulate and exdex.simulate_batch)."""
from __future__ import annotations

import math

import numpy as np

from exdex import _core, diagnostics


def pivot_in_obstacles(scene, spec, t):
    """The indices of the obstacles whose interior holds the rotation model's
    pivot (the grasp point it pins in the gripper) at time t [s], when the
    object's outline holds the pivot (then every angle of the object
    overlaps them); () when the outline states no area or misses the pivot."""
    centre = np.array(scene.grasp.patch.center, dtype=float)
    if not diagnostics.outline_holds(scene.body, centre):
        return ()
    th0 = scene.q0[2]
    cs, sn = math.cos(th0), math.sin(th0)
    pivot = np.array([scene.q0[0] + cs * centre[0] - sn * centre[1],
                      scene.q0[1] + sn * centre[0] + cs * centre[1], 0.0])
    kin = _core.motion_eval(spec, np.array([float(t)]))
    x = kin["p"][0] + kin["R"][0] @ pivot   # the pivot in the world frame A
    inside = []
    for i, ob in enumerate(scene.obstacles):
        if ob.kind == "cylinder":
            d = x - np.array(ob.center)
            a = np.array(ob.axis)
            if np.linalg.norm(d - (d @ a) * a) < ob.radius:
                inside.append(i)
        elif all((x - np.array(fp)) @ np.array(fn) < 0.0 for fp, fn in zip(ob.face_points, ob.face_normals)):
            inside.append(i)
    return tuple(inside)


def reduced_obstacle_hint(scene, spec, exc, motion_known=True):
    """Rewrite the message of a rotation run's SolverError whose state left
    the finite range against obstacles: the rotation model cannot clear the
    obstacle that holds its pivot at the failure time (when one does; else
    that it may be unable to clear them), and the remedy. Other errors are
    left as they are. motion_known False (a stepper given gripper poses,
    not the scene's motion): the pivot's place is not tested and the
    hedged form is used."""
    if (getattr(scene, "dof", None) != "rotation" or not scene.obstacles
            or getattr(exc, "cause", None) != "nonfinite" or not exc.args):
        return
    t = getattr(exc, "time", None)
    inside = pivot_in_obstacles(scene, spec, t) if (t is not None and motion_known) else ()
    remedy = "use dof='planar' (or dof='auto', which falls back to it)"
    msg, generic = str(exc.args[0]), "the state left the finite range (check the scene's scales and motion)"
    if inside:
        hint = (f"the state left the finite range: the rotation model cannot clear Scene.obstacles[{inside[0]}]: "
                f"its pivot (the grasp point, pinned in the gripper) is inside the obstacle then, so no angle of "
                f"the object clears it and no finite force keeps the object out; {remedy}")
        msg = msg.replace(generic, hint) if generic in msg else f"{msg}; {hint}"
    else:
        msg = (f"{msg}; against obstacles the rotation model (the object turning about the grasp point, pinned "
               f"in the gripper) may be unable to clear them: {remedy}")
    exc.args = (msg,) + tuple(exc.args[1:])

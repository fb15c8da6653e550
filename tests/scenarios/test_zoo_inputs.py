"""The scene zoo with the control inputs and contacts a robot adds: every
method returns, agrees with an independent reference within its own stated
error, or refuses by name; friction adds no energy, stick is exactly still,
nothing penetrates.

Scenes: ``input_scene(seed)`` takes the zoo scene of the seed
(tests/zoo.py: dof, body, grasp, gravity, scale, stops, motion) and adds, each
drawn independently from its own seeded stream (a failing seed is a complete
reproducer: ``input_scene(seed).scene``):

* a grip-force schedule (``GripSchedule``: linear, cubic or step; 2 to 5
  points over the run, forces 0 to 2 times the zoo's grip, a release to 0
  in some, then a re-grip or not);
* a static coefficient ``mu_static`` from mu to 1.6 mu;
* friction on the zoo's stops (``Stop.mu`` 0.1 to 1);
* a convex obstacle next to the object (planar scenes without stops and
  with a gripper that does not turn, so the section stays a fixed shape and
  the object can always give way, as the zoo's stops): a box, a rod along
  the plate normal, or a two-face wedge (the halfspaces of a V tool), at a
  gap 0 to L/3 from the outline, frictionless or with ``mu`` 0.1 to 1;
* the motion replaced by a ``Shake`` (whole or half cycles, peak
  acceleration 0.3 to 3 g, or its angular equivalent g / L) or a ``Chain``
  of a pause, a shake, a zoo profile and a pause; with stops only shifts
  (and with a rotation dof only parallel to the stop), as in the zoo.

Which method supports which input (simulate raises a ValueError naming the
parameter otherwise, checked here): obstacles (frictional ones too): every
method but analytic; everything else (stop friction included, in every
dof): every method.

Agreement, with tests/scenarios/test_zoo.py's machinery and bounds (zoo.check_scene;
derivations in tests/scenarios/test_zoo.py): where the event method supports the
scene it is the reference and every supporting method must lie within its
stated error of it (event: proportional to rtol; implicit: S times the
largest successive difference of the dt ladder t_end / 500 .. / 4000;
explicit: its dt ladder from there, extended until consistent, plus its
creep; regularised: its eps ladder, on every REG_EVERY-th
seed). Unsupported methods must refuse by name. Where the event method does not support a scene the
reference is the implicit method at h/8, whose own error is
bounded by its ladder's estimate S max(D) (the extrapolation of its
successive differences in dt, tests/scenarios/test_zoo.py), and the explicit method
must lie within the sum of both estimates (plus its creep and FLOOR).

Known defects are strict xfails in KNOWN with the cause stated; the list can
only shrink.
"""
from __future__ import annotations

import dataclasses
import math
import os

import numpy as np
import pytest

import exdex

import zoo

N_SCENES = 100
#: A longer sweep: ZOO_INPUTS_SEEDS="first:last" (e.g. 100:1000) runs those
#: seeds instead (KNOWN marks apply where they match).
_range = os.environ.get("ZOO_INPUTS_SEEDS")
#: Regression seeds beyond N_SCENES, each run in every method by default:
#: 384, a planar scene on two frictional stops where the event method spent
#: its event budget in a 4-event cycle (a small slip grown against a stop row
#: it could rest on; hybrid_decide.c's rule T2, and its C test
#: decide_event_small_slip_grown_against_set_rows_stops_where_held);
#: 3478, a planar scene on one frictional stop (mu 0.98) where a corner's
#: slide ran into a Painleve jam (its stop force without bound) and the event
#: and regularised steps collapsed at t = 0.1073 s (the jam's arrest impulse,
#: hybrid_impacts.c's hyb_planar_jam_impulse, and its C test
#: hybrid_impacts_jam_arrests_the_slip_as_the_rigid_limit);
#: 4114, a rotation scene whose grip is released to 0 while the object rests
#: on its one stop, where the plates' share of that rest, a rounding residual
#: of the stop's, failed the stick test at capacity 0 and the event run
#: slipped into the stop and through it (hyb_contact_forces, and its C test
#: decide_1dof_rest_on_a_pushing_stop_holds_with_the_grip_released);
#: 1126, a rotation scene resting on its one stop (pushed by 3.1e-4 N after
#: the trap's end at t = 0.963 s) through its cubic grip's release to 0 at
#: t = 1.021 s, a breakpoint that ends a step with a decision at capacity 0:
#: the same rounding residual taken as the plates' friction there slipped
#: the REF_RTOL run at grid t_end / 8 (1.2e-5 L off; the C test
#: event_run_rest_on_a_pushing_stop_holds_through_a_grip_released_at_a_breakpoint).
REGRESSION_SEEDS = (384, 1126, 3478, 4114)
SEEDS = (range(*map(int, _range.split(":"))) if _range
         else list(range(N_SCENES)) + [s for s in REGRESSION_SEEDS if s >= N_SCENES])
REG_EVERY = 1
G = zoo.G

#: (method, seed) -> the defect; strict xfails.
_PLATEAU = ('implicit with mu_static > mu, 1-DoF: the error is identical on the ladder t_end/500 .. t_end/4000 '
            '(differences 0 or ~1e-7 L) and drops only at finer steps, so the successive-difference estimate misses '
            'it (a brief load excursion past the static capacity that the step-mean load does not see until h is '
            'shorter than it); ')
KNOWN = {  # noqa: E501 - the defects, stated in full
    # seeds beyond N_SCENES: found by ZOO_INPUTS_SEEDS=100:400
    ('implicit', 151): _PLATEAU + 'translation, Shake, mu_static = 1.2 mu: 1.6e-5 L at t_end/500 and /4000, 1.3e-6 L at /32000, 2.4e-7 L at /128000',
    ('explicit', 206): 'explicit against the event reference (planar, Eq. 7 round trip of a gripper turn, one frictional stop): 1.07, 0.93, 0.84, 0.78, 0.72, 0.67, 0.65, 0.63, 0.61, 0.60 L apart at t_end/500 .. /256000 (the explicit ladder extended to its end without two ratios of its differences in range or equal impact counts, 25 .. 8 impacts; last differences 0.024, 0.016, 0.012 L: bound 0.075 L), not converging to the event answer. Final theta: event -1.532470 rad, implicit -1.5323, -1.5324, -1.5325 rad at t_end/500, /4000, /32000 (Richardson over /16000 and /32000: -1.5324697), explicit -3.17, -2.72, -2.53 rad. The explicit run creeps during the event run\'s rest (t_end/4000: x moves 1.7 mm between 0.35 and 0.8 s, the planar sign() chatter near stick) and so is struck by the returning stop (see the regularised entry) before t = 1.25 s, which drags it to the other branch',
    # found by ZOO_INPUTS_SEEDS=700:1000
    ('explicit', 790): 'explicit against the event reference (planar, Chain, a frictionless box, mu_static = mu, so the sign() baseline): 0.152, 0.163, 0.205, 0.214 L apart at t_end/4000, /16000, /64000, /256000 (the ladder\'s last differences 0.014, 0.0064, 0.0035 L: bound 0.047 L), while the implicit ladder agrees with the event run (2.8e-4 L, bound 1.0e-3 L). The event run rests from 0.358 s to 0.962 s with no contact, its load at 0.997 of the friction limit (the torque at 0.98 of C e_r, e_r = 1.6 mm against a 21 mm lever); the explicit run never sticks (stick flag 0 at every sample): it turns at ~0.5 rad/s (t_end/64000) while the event run rests from 0.008 s, the planar creep of the sign() law (explicit.c: the translation chatters, so the friction torque is only a fraction of C e_r), and between 0.372 and 0.846 s it slides 1.1 L (2.0 rad) at every dt from t_end/16000 to /256000, onto another branch; with mu x 1.01 and x 1.03 the same (0.15 .. 0.31 L)',
    ('regularised', 206): 'the reference itself is at a discontinuity that the conditioning allowance does not measure (planar, Eq. 7 round trip of a gripper turn, one frictional stop): the stop pushes the object until t = 0.2806 s, where its velocity in B reverses and the object comes to rest against it (gap 0, rate 0); the turn is symmetric in time about its midpoint, so at t = 1.3035 s the stop returns to the same place at rate 0 and grazes the rest (least gap 4.8e-11 L). Any creep toward it during the rest is struck there and turned: from the regularised run\'s state at t = 1.25 s (eps = EPS/256, crept by 1.2e-4 rad and 2.4e-5 m) the event and implicit methods end at theta = -2.441 and -2.443 rad (the regularised -2.444), from the event run\'s state at -1.5325 rad (both). The regularised method creeps by design (no exact stick), so it ends on the struck side at every eps: 0.86, 0.73, 0.67, 0.62, 0.60, 0.59 L at EPS / 1, 4, 16, 64, 256, 1024. The gravity perturbation (1 +- DELTA) does not move the rest pose, which the stop\'s path sets (jump 2.0e-7 L; the regularised check: 0.60 L off against its bound 0.067 L)',
    # found by the 1500-seed sweep (benchmarks/zoo_long.py --inputs --n 1500)
    ('event', 1146): 'the event method takes one of two slip modes at a stick release, decided by 1e-9-level differences of its state (planar, Chain, no stops, a frictional wedge obstacle, mu 0.503): the object sticks against the wedge (obstacle force 646.5 N in every run) until the stick ends in (0.14407, 0.14483] s at every rtol; mode A leaves it at v = (-5.7e-4 m/s, +2.7e-3 m/s, +0.0074 rad/s) at t = 0.14483 s (obstacle force 1.74e3 N), mode B at (+6.2e-4, -1.5e-5, +0.024) (1.2e3 N), and they end 0.948 L apart. At grid t_end/512, rtol 1e-6, 1e-7, 1e-10, 1e-12 take A, 1e-8 and 1e-9 B; at rtol 1e-9 the grid t_end/8 (the REF_RTOL run) takes A, /64 and /512 B; at rtol 1e-11 the grids /8 and /512 take A (4.3e-8 L from the rtol 1e-12 run), /64 (the tight reference run) B; grid /16 at rtol 1e-10 and 1e-11 ends 0.0030 and 0.0023 L from A. Gravity x (1 + 1e-6) gives B at rtol 1e-9 .. 1e-12, x (1 - 1e-6) B at 1e-9 and 1e-11 and A at 1e-12, x (1 +- 1e-4) and x (1 - 1e-3) A. The time-stepping methods take mode B at every step and gravity: the implicit run leaves the stick at 0.14427 s with mode B\'s velocity (0.0076 m/s, -6.1e-4 m/s, 0.301 rad/s at t = 0.1517 s, as the event run on B) and ends 0.017, 0.0023, 5.6e-4 L from the event run on B at t_end/4000, /32000, /128000, the explicit 0.045, 0.0057, 0.0014 L, and the implicit run at t_end/32000 stays within 0.0019 .. 0.0072 L of it at gravity x (1 +- 1e-6), (1 +- 1e-4), (1 - 1e-3); the regularised method ends 0.31 and 0.049 L from A at eps EPS/16 and /64, then 1.2e-4 and 8.7e-4 L from B at EPS/256 and /1024. The probe\'s two runs (rtol REF_RTOL_TIGHT, grid N_OUT_FINE) both take B like the reference (jump 4.9e-6 L), so the REF_RTOL run, on A, is 0.9477 L off against its stated 3.4e-6 L. Cause: a corner on a corner. The wedge is placed at gap 0 with the object\'s vertex 0 on both face planes, on the wedge\'s edge (the vertex within 6.5e-13 m of faces 0 and 1, the wedge\'s edge within 7e-13 m of the object\'s edges 0 and 3); each contact row holds one piece of its largest distance (vertex 0 against face 0 or 1, the wedge\'s edge against object edge 0 or 3), picked by contact.c\'s rate tie rule (the piece of the largest rate), and while the corner rides with the moving wedge (both friction groups\' slips ~1e-17 m/s) those rates are rounding (1e-17 .. 8e-17 m/s). At the decision of the group slips\' reaching 0 near t = 0.1442371 s the rule keeps face 0 and edge 0 (A: the vertex pinned on the wedge\'s edge by both rows, lam 1623 N and 413 N, their resultant at 110 deg inside the faces\' normal cone 73 .. 132 deg: a balance on the edge that holds only because face 0 is held as an inequality, which the non-convex constraint max(face gaps) >= 0 does not impose while face 1 is at 0) or takes face 1 and edge 3 (B: the vertex slides along face 1 away from face 0, the edge row without force)',
    ('implicit', 528): 'implicit converges to another trajectory (planar, Chain, no stops, a frictionless wedge obstacle, mu_static = 1.192 mu, L = 3.1 mm): 0.0185 .. 0.0187 L from the event run at every dt t_end/500 .. /128000 (successive differences 7e-5 .. 3e-5 L, so its estimate, bound 1.2e-3 L, misses it), while the explicit ladder (4.7e-4, 3.7e-5, 4.3e-6 L at t_end/4000, /16000, /64000) and the regularised one (0.013, 0.0032, 8.0e-4 L at eps EPS/16, /64, /256) converge to the event answer, itself well conditioned (rtol 1e-9 .. 1e-12 agree to 3e-16 L; gravity x (1 +- 1e-6) moves it 1e-9 L). Both methods stick against the wedge until t ~ 0.016 s (the event run with an obstacle force 1.7e-4 N, the implicit with 0) and leave the stick at different rates (t = 0.0167 s: theta rate -5.96 rad/s event, -3.12 rad/s implicit at t_end/32000 and /128000 alike); from t ~ 0.021 s the difference stays 0.0185 L',
    ('implicit', 723): 'implicit with mu_static > mu, 1-DoF (rotation, a noisy log motion that ends moving, one frictional stop, mu_static = 1.502 mu): an error plateau on the ladder, 6.3e-3, 7.0e-3, 6.5e-3, 6.7e-3 L at t_end/500 .. /4000 (differences 6.3e-4, 4.3e-4, 2.0e-4 L, so its estimate, bound 1.9e-3 L, misses it), then 1.1e-5 L at t_end/8000 and 1.9e-6 L at /64000 and /128000 (the event run: rtol 1e-9 .. 1e-12 agree to 3e-15 L); the drop at a finer step is the pattern of the mu_static > mu plateau above (seed 151), its load excursion not located here',
    ('explicit', 456): 'explicit out of its asymptotic regime far below the checked steps (planar, Chain, a hexagon, no stops, a frictionless rod obstacle, mu = 0.388): 1.03, 1.26, 1.31, 1.32, 1.30, 1.32, 1.69 L from the event run at t_end/500 .. /32000 (differences 0.23, 0.10, 0.028 L to t_end/4000 look consistent: bound 0.99 L), then 0.064, 0.024, 0.012, 0.0055, 0.0027 L at t_end/64000 .. /1024000, halving with dt: the explicit method converges to the event answer, which the implicit run confirms (3.2e-5 L at t_end/32000; the event pose well conditioned, jump 9.2e-9 L)',
    ('regularised', 1342): 'the regularised method converges to another limit (translation, trap, a hexagon on two stops, mu_static = 1.451 mu): 0.0125, 0.0181, 0.0195, 0.0198, 0.01993, 0.01995, 0.01996 L from the event run at eps EPS / 1, 4, 16, .., 4096, its differences 5.6e-3, 1.4e-3, 3.4e-4, 8.5e-5, 2.1e-5, 5.3e-6 L falling by 4 per factor 4 in eps (first order, so its ladder is consistent and its estimate small: bound 0.012 L), while the implicit run agrees with the event answer (9.9e-6 L at t_end/32000; jump 4.3e-7 L); where its limit leaves the event solution is not located here',
}


# ---------------------------------------------------------------- the generator

def _schedule(rng, F, t_end):
    kind = str(rng.choice(["linear", "cubic", "step"]))
    n = int(rng.integers(2, 6))
    times = np.sort(rng.uniform(0.0, t_end, size=n))
    if rng.random() < 0.5:
        times[0] = 0.0
    forces = F * rng.uniform(0.0, 2.0, size=n)
    release = bool(rng.random() < 0.3)
    if release:
        k = int(rng.integers(0, n))
        forces[k] = 0.0
        if kind == "step" and k + 1 < n and rng.random() < 0.7:
            forces[k + 1] = F * rng.uniform(0.5, 2.0)   # re-grip
    # strictly increasing times with a spacing the core's slope check accepts
    for i in range(1, n):
        times[i] = max(times[i], times[i - 1] + 1e-3 * t_end)
    return exdex.GripSchedule(times=tuple(times), forces=tuple(forces), kind=kind), kind, release


def _shake(rng, zs, axis, rotate, center):
    f = float(rng.uniform(0.5, 2.0) / zs.tau)
    peak = float(rng.uniform(0.3, 3.0)) * (G / zs.L if rotate else G)
    A = float(peak / (2.0 * math.pi * f) ** 2 * rng.choice([-1.0, 1.0]))
    cycles = 0.5 * int(rng.integers(1, 7))
    return exdex.Shake(A, f, cycles=cycles, axis=tuple(axis), rotation=rotate, center=tuple(center))


def _motion(rng, zs, turn=True):
    """A Shake or a Chain (pause, shake, profile, pause) that keeps the zoo's
    stops valid: with stops, shifts only (rotation dof: parallel to the
    stop); without, shifts or turns about any axis."""
    sc = zs.scene
    p0 = np.array(sc.gripper_position)
    rotate = bool(turn and not sc.stops and rng.random() < 0.4)
    axis = zoo._random_direction(rng)
    if not rotate and sc.stops and sc.dof == "rotation":
        nA = np.array(sc.stops[0].normal)
        axis = zoo._unit(axis - (axis @ nA) * nA)
    center = p0 + rng.uniform(-1.0, 1.0, size=3) * 2.0 * zs.L
    if rng.random() < 0.5:
        return _shake(rng, zs, axis, rotate, center), "shake", rotate
    pieces = [exdex.Pause(float(zs.tau * rng.uniform(0.3, 1.0))), _shake(rng, zs, axis, rotate, center),
              exdex.Pause(float(zs.tau * rng.uniform(0.2, 0.8)))]
    pieces.append(zoo._parametric_motion(rng, str(rng.choice(["asym", "trap"])), zs.L, zs.tau, rotate, axis, center))
    pieces.append(exdex.Pause(float(zs.tau * rng.uniform(0.3, 1.0))))
    return exdex.Chain(tuple(pieces)), "chain", rotate


_obstacle = zoo.obstacle


@dataclasses.dataclass(frozen=True)
class InputScene:
    zs: zoo.ZooScene
    tags: dict

    @property
    def scene(self):
        return self.zs.scene

    def __repr__(self):
        return f"InputScene(seed={self.zs.seed}, t_end={self.zs.t_end:.4g}, tags={self.tags})"


def input_scene(seed):
    """The zoo scene of ``seed`` with random new inputs (module docstring)."""
    zs = zoo.zoo_scene(seed)
    rng = np.random.default_rng([int(seed), 0x12])
    sc = zs.scene
    tags = dict(zs.tags)
    t_end = zs.t_end
    rotate = zs.tags["rotate"]
    # an obstacle: planar scenes with a gripper that does not turn (the
    # zoo's stops, if any, give way to it: one contact kind per scene)
    want_obstacle = sc.dof == "planar" and rng.random() < 0.6
    if rng.random() < 0.35 or (want_obstacle and rotate):
        if want_obstacle:
            sc = exdex.replace(sc, stops=())
        motion, kind, rotate = _motion(rng, dataclasses.replace(zs, scene=sc), turn=not want_obstacle)
        sc = exdex.replace(sc, motion=motion)
        t_end = float(motion.end_time + zs.tau * rng.uniform(1.0, 3.0))
        tags["motion"] = kind
        tags["rotate"] = rotate
    grasp = sc.grasp
    if rng.random() < 0.5:
        sched, kind, release = _schedule(rng, grasp.grip_force, t_end)
        grasp = exdex.replace(grasp, grip_force=sched)
        tags["grip"] = kind + ("-release" if release else "")
    if rng.random() < 0.4:
        grasp = exdex.replace(grasp, mu_static=float(grasp.mu * rng.uniform(1.0, 1.6)))
        tags["mu_static"] = round(grasp.mu_static / grasp.mu, 3)
    sc = exdex.replace(sc, grasp=grasp)
    if want_obstacle:
        sc = exdex.replace(sc, stops=())
        tags["stops"] = 0
    if sc.stops and rng.random() < 0.6:
        sc = exdex.replace(sc, stops=tuple(exdex.Stop(s.point, s.normal, mu=float(rng.uniform(0.1, 1.0)))
                                           for s in sc.stops))
        tags["stop_mu"] = True
    if want_obstacle:
        mu = 0.0 if rng.random() < 0.6 else float(rng.uniform(0.1, 1.0))
        ob, kind = _obstacle(rng, dataclasses.replace(zs, scene=sc), mu)
        sc = exdex.replace(sc, obstacles=(ob,))
        tags["obstacle"] = kind + ("-mu" if mu > 0 else "")
    return InputScene(dataclasses.replace(zs, scene=sc, t_end=t_end, tags=tags), tags)


def unsupported(scene, method):
    """The parameter simulate() names when ``method`` cannot run ``scene``,
    or None."""
    if scene.obstacles:
        if method == "analytic":
            return "Scene.obstacles"
    return None


# ---------------------------------------------------------------- running and agreement

def check_implicit_reference(zs, methods):
    """Agreement where the event method cannot run the scene: the implicit
    ladder h .. h/8 (h = t_end / N_DT) is the reference, its final pose at
    h/8 within its own estimate S max(D) of the exact one (tests/scenarios/test_zoo.py:
    the extrapolation of its successive differences in dt); the explicit
    ladder must lie within the sum of both estimates, its creep and FLOOR.
    Same keys as zoo.check_scene."""
    out = {}
    runs = {}
    for method in methods:
        rs, err = [], None
        for k in (1, 2, 4, 8):
            try:
                r = zoo.run(zs, method, dt=zs.t_end / (zoo.N_DT * k))
            except Exception as e:  # noqa: BLE001 - a report, the test asserts on it
                err = f"{type(e).__name__}: {e}"
                break
            if not all(np.all(np.isfinite(getattr(r, a))) for a in ("q", "v", "wrench", "stop_force")):
                err = "non-finite output"
                break
            rs.append(r)
        runs[method] = rs
        out[method] = dict(error=err, pose=None if err else zoo.final_pose(rs[-1]))
    imp = out.get("implicit")
    if imp is None or imp["error"]:
        return out
    poses = [zoo.final_pose(r) for r in runs["implicit"]]
    d_imp = [zoo.pose_distance(zs, a, b) for a, b in zip(poses[:-1], poses[1:])]
    ref_err = zoo.S * max(d_imp)
    out["reference"] = dict(pose=poses[-1], err=ref_err, method="implicit")
    imp.update(err=0.0, d=d_imp, bound=ref_err + zoo.FLOOR, ok=True)
    stuck = float(np.sum(runs["implicit"][-1].stick[1:])) * zs.t_end / (8 * zoo.N_DT)
    for method in methods:
        o = out[method]
        if method == "implicit" or o["error"]:
            continue
        ps = [zoo.final_pose(r) for r in runs[method]]
        d = [zoo.pose_distance(zs, a, b) for a, b in zip(ps[:-1], ps[1:])]
        o.update(err=zoo.pose_distance(zs, ps[-1], poses[-1]), d=d)
        o["creep"] = stuck * zs.t_end / (8 * zoo.N_DT) * zoo.creep_speed(zs)
        o["bound"] = zoo.S * max(d) + o["creep"] + ref_err + zoo.FLOOR
        o["ok"] = o["err"] <= o["bound"]
    return out


_CACHE: dict = {}


def results(seed):
    """(InputScene, agreement dict) of a seed, computed once per session."""
    if seed not in _CACHE:
        s = input_scene(seed)
        zs = s.zs
        ok = [m for m in zoo.METHODS if unsupported(zs.scene, m) is None]
        if "event" in ok:
            agree = ok if seed % REG_EVERY == 0 else [m for m in ok if m != "regularised"]
            out = zoo.check_scene(zs, methods=tuple(ok), agree=tuple(agree))
        else:
            out = check_implicit_reference(zs, ok)
        _CACHE[seed] = (s, out)
    return _CACHE[seed]


#: KNOWN entries whose outcome a rounding-level change of the state decides
#: (a near-tie of two modes): not strict, since the run may land on the
#: right mode by rounding alone, on one machine or build and not another.
#: ('event', 1146): the REF_RTOL run took mode A with the normal-equation and
#: QR solves of ldp_min_combination's supports, B (passing) with the closed
#: forms; the zoo-inputs long run reports it either way.
ROUNDING_TIES = {('event', 1146)}


def _cases():
    for method in zoo.METHODS:
        for seed in SEEDS:
            marks = []
            if (method, seed) in KNOWN:
                marks.append(pytest.mark.xfail(strict=(method, seed) not in ROUNDING_TIES, reason=KNOWN[method, seed]))
            yield pytest.param(method, seed, marks=marks, id=f"{method}-{seed}")


@pytest.mark.parametrize("method,seed", list(_cases()))
def test_inputs_scene(method, seed):
    """A supporting method returns finite values and agrees with the
    reference within its bound; a method that does not support an input
    raises a ValueError naming it."""
    s, out = results(seed)
    why = unsupported(s.scene, method)
    if why is not None:
        with pytest.raises(ValueError, match=why.replace(".", r"\.")):
            zoo.run(s.zs, method)
        return
    o = out[method]
    assert o["error"] is None, (s, o["error"])
    assert np.all(np.isfinite(o["pose"]))
    ref = out.get("reference")
    if ref is None or "ok" not in o:
        return
    assert "jump_error" not in ref, (s, ref["jump_error"])
    assert o["ok"], (s, {k: v for k, v in o.items() if k != "pose"}, {k: v for k, v in ref.items() if k != "pose"})


def test_event_short_slips_do_not_depend_on_the_output_grid():
    """Seed 143 (planar, a Chain of turns, a linear grip schedule released to
    0 and re-gripped): while the object sticks, the load leaves the friction
    ellipsoid for a few ms (near 0.228 s and 0.455 s) and slips ~1e-4 and
    ~1e-5 m. A stick step that spans such an excursion ends with the load
    back inside; were only the step ends checked, whether the slip happens
    would depend on where steps end (output grid, rtol): final poses 2.1e-5
    and 2.3e-4 L from the rtol 1e-12 run, swapping between grids t_end/8 and
    t_end/64 and between rtol 1e-9 and 1e-10. With the stick guard's minimum
    searched inside each step, each run's distance to the reference (rtol
    1e-12, output t_end/64) is proportional to rtol: D(1e-10) <=
    PROPORTIONAL D(1e-9) + FLOOR at both grids (tests/scenarios/test_zoo.py)."""
    zs = input_scene(143).zs
    ref = zoo.final_pose(zoo.run(zs, "event", rtol=1e-12, n_out=zoo.N_OUT_FINE))
    for n_out in (8, 64):
        d = [zoo.pose_distance(zs, zoo.final_pose(zoo.run(zs, "event", rtol=rtol, n_out=n_out)), ref)
             for rtol in (1e-9, 1e-10)]
        assert d[1] <= zoo.PROPORTIONAL * d[0] + zoo.FLOOR, (n_out, d)


@pytest.mark.warns_by_design("impact", "pad", "outline")
def test_event_corner_cutting_through_an_obstacle_is_an_impact():
    """Seed 248 (planar, a box obstacle, frictionless, a step grip released
    to 0 at 0.107 s): the object slides along the box's face with one corner
    on it and the other just lifted off by an impact (gap 0, rate +2.5e-4
    m/s), which the load turns back onto the face near the section's corner:
    the exact motion has an impact there 7.5e-5 s later. A free obstacle
    row's gap is a largest distance over the faces, continuous but with a
    rate that jumps at a feature switch: over one 3.3 ms step the corner
    went through the face (3.3e-5 m deep) and out again past the next face,
    so the step's end showed a positive gap (a "recovery" of a row that
    starts at 0) and the box's corner, which had entered the object's edge,
    was found only at its end: an impulse of 1676 N s, a final pose 0.03 rad
    off, a gap of -4.1e-8 L at output t_end / 8 (at t_end / 64 the shorter
    steps caught the impact). Every run must stay out of the box to the
    zoo's GAP_TOL and lie within its own integration tolerance
    (zoo.integration_tol: steps x rtol per unit of size) of the rtol 1e-11
    reference, at both output grids."""
    zs = input_scene(248).zs
    tight = zoo.run(zs, "event", rtol=zoo.REF_RTOL_TIGHT, n_out=zoo.N_OUT_FINE)
    ref = zoo.final_pose(tight)
    size = zoo.pose_distance(zs, ref, np.zeros(3))
    for n_out in (zoo.N_OUT, zoo.N_OUT_FINE):
        r = zoo.run(zs, "event", n_out=n_out)
        assert r.stats["min_gap"] >= -GAP_TOL * zs.L, (n_out, r.stats["min_gap"] / zs.L)
        d = zoo.pose_distance(zs, zoo.final_pose(r), ref)
        assert d <= zoo.integration_tol(r, size) + zoo.FLOOR, (n_out, d, zoo.integration_tol(r, size))
    assert tight.stats["min_gap"] >= -GAP_TOL * zs.L


def test_event_rest_touched_again_by_a_frictional_stop_stays_at_rest():
    """Seed 206 (planar, an Eq. 7 turn about a tilted axis and back, one
    stop with mu 0.92): the turning stop pushes the object until it stops
    at t = 0.28 s, where the stop's trace in B has its envelope, so the
    object rests on it. At t = 1.3035 s the turn back carries the stop
    through the same place: its path touches the resting pose at a
    tangency (rate 0 exactly), which the event method, whose rest holds the
    pose to tol.rest_gap of the stop's path, meets at an approach of
    8.8e-7 m/s while the stop slides past at 0.39 m/s. The exact motion
    stays at rest there (the plates hold the load, the stop recedes). Taken
    as an impact with Coulomb friction, the impulse of that approach moves
    the object at 10-100 times it (the stop's friction nearly cancels the
    normal impulse's effect on the gap, near a Painleve configuration) and
    the stop's friction then drags the slip to 5 rad/s, final theta -2.407
    rad; the implicit ladder converges to the rest's -1.53247 rad
    (Richardson over t_end/16000 and /32000: -1.5324697). The event method
    takes a stop whose path turns back within tol.rest_gap of a held pose
    as a contact of the rest, not an impact (impacts are frictional at
    every approach speed otherwise), and its run must lie within the
    implicit ladder's estimate of the implicit answer (zoo.check_scene)."""
    zs = input_scene(206).zs
    out = zoo.check_scene(zs, methods=("implicit", "event"), agree=("implicit", "event"))
    assert out["event"]["error"] is None and out["implicit"]["error"] is None
    assert out["implicit"]["ok"], {k: v for k, v in out["implicit"].items() if k != "pose"}


@pytest.mark.parametrize("mu", [0.65, 0.70, 0.749, 0.76])
def test_event_stop_on_a_frictional_obstacle_is_the_creeping_plates_rest(mu):
    """Seed 3540 (planar, a Chain, the default gripper, a wedge obstacle)
    with the wedge's mu set to 0.65 .. 0.76 (the seed's own is 0.749): the
    object pivots on the wedge's section vertex, its slip decays to 0 at t
    = 0.7474 s, and the plates alone cannot hold the load there (its gauge
    0.255 against C_s 0.187 at the seed's mu; the frictionless row does not
    help). A split over the row's friction cone holds it with a gauge of
    0.054, so a rest that takes the friction most favourable to the plates
    stays there to t_end, final theta 0.870 rad; but a plate that creeps
    under that load (its slip along the limit surface's normal) slips
    away from the wedge, where the row's friction cannot act: the object
    leaves the row, turns back and comes to rest at 0.907 rad. The event
    method's rest test is that creeping plate's split (stop_friction.h's
    problem on the creep), and its final pose must lie within 3e-3 L of
    two independent methods: the implicit method at t_end / 32000 and the
    regularised one at eps 1e-4 L / tau, which agree with each other to
    1e-3 L (1.6e-4 L seen). The favourable split missed them by 0.015 ..
    0.059 L over these mu; at mu 0.8 all three rest at the same pose."""
    zs = input_scene(3540).zs
    sc = dataclasses.replace(zs.scene, obstacles=(dataclasses.replace(zs.scene.obstacles[0], mu=mu),))
    ev = zoo.run(zs, "event", scene=sc)
    im = zoo.run(zs, "implicit", scene=sc, dt=zs.t_end / 32000)
    rg = zoo.run(zs, "regularised", scene=sc, eps_rel=1e-4)
    pe, pi, pr = (zoo.final_pose(r) for r in (ev, im, rg))
    assert zoo.pose_distance(zs, pi, pr) <= 1e-3
    assert zoo.pose_distance(zs, pe, pi) <= 3e-3 and zoo.pose_distance(zs, pe, pr) <= 3e-3, (pe, pi, pr)


@pytest.mark.warns_by_design("impact")
def test_event_rest_against_an_obstacle_is_reported_out_of_it():
    """Seed 790 (planar, a Chain, a frictionless box): the object comes to
    rest with an edge on the box's section vertex while the gripper moves
    on. The box is fixed in the world, so in B it moves with the gripper and
    closes in on the held pose, by up to tol.rest_gap (1e-7 of the
    outline's radius) before the rest ends; as with stops, the samples and
    the smallest gap must report the held pose pushed out of the obstacle
    (the projection the decision at the rest's end makes), so the gap stays
    above -GAP_TOL L (a pose inside the box, reported as held: -1.5e-9 L at
    rtol REF_RTOL)."""
    zs = input_scene(790).zs
    for kw in (dict(), dict(rtol=zoo.REF_RTOL_TIGHT, n_out=zoo.N_OUT_FINE)):
        r = zoo.run(zs, "event", **kw)
        assert r.stats["min_gap"] >= -GAP_TOL * zs.L, (kw, r.stats["min_gap"] / zs.L)


@pytest.mark.warns_by_design("impact", "outline")
def test_event_separation_from_a_frictional_obstacle_is_decided_once():
    """Seed 952 (planar, a Shake, a box with mu 0.19): the object slides
    with a corner on a face and an edge on the box's section vertex; at
    t = 0.0627 s the corner's force reaches 0 and the row separates. At that
    instant its force and gap acceleration both vanish, and the solve at
    the decided state can return a force of rounding size (2e-17 N) that
    keeps the row in the contact set: the same event is then found again at
    the same time (the tie set_tie_leaves breaks), and with frictional rows
    it was not broken: four repeats, a warning each, and the corner held
    on the face for 20 ms (7.4e-3 L off at rtol 1e-9, output t_end / 8;
    1e-12 L at t_end / 64). Every run lies within its own integration
    tolerance (zoo.integration_tol) of the rtol REF_RTOL_TIGHT reference,
    with no warning, at both output grids and two rtols."""
    zs = input_scene(952).zs
    tight = zoo.run(zs, "event", rtol=zoo.REF_RTOL_TIGHT, n_out=zoo.N_OUT_FINE)
    ref = zoo.final_pose(tight)
    size = zoo.pose_distance(zs, ref, np.zeros(3))
    for n_out in (zoo.N_OUT, zoo.N_OUT_FINE):
        for rtol in (zoo.REF_RTOL, 0.1 * zoo.REF_RTOL):
            r = zoo.run(zs, "event", rtol=rtol, n_out=n_out)
            d = zoo.pose_distance(zs, zoo.final_pose(r), ref)
            assert r.stats["warnings"] == 0, (n_out, rtol, r.stats["warnings"])
            assert d <= zoo.integration_tol(r, size) + zoo.FLOOR, (n_out, rtol, d)


def _nudged_log(zs, seed, ulps=4):
    """The zoo scene zs with its sampled log's positions moved by up to
    ``ulps`` units in the last place, drawn from ``seed`` (the first sample
    kept, so the scene's initial pose and placements stay exact): the
    last-bit differences NumPy's SIMD paths make in a drawn log
    (NPY_DISABLE_CPU_FEATURES)."""
    m = zs.scene.motion
    p = np.array(m.positions)
    k = np.random.default_rng(seed).integers(-ulps, ulps + 1, size=p.shape)
    k[0] = 0
    return dataclasses.replace(zs, scene=exdex.replace(zs.scene, motion=exdex.replace(m, positions=p + k * np.spacing(p))))


@pytest.mark.warns_by_design("impact", "pad", "outline")
def test_event_sliding_contact_with_an_obstacle_holds_through_decisions():
    """Seed 795 (planar, a log-smooth motion, a box with mu 0.73): the object
    slides along the box's face on one corner (t = 0.024 .. 0.119 s, two
    corners from 0.054 to 0.062 s). A contact-set row pushes until its
    separation is located, so its gap and rate are exactly 0 there; the
    integrated state carries them off by the integrator's error, and a
    decision on the way (the motion's switching times at 0.027, 0.073 and
    0.142 s, another row's event) found the pushing row separating and
    dropped it: a free flight, the box's friction lost, until an impact
    brought it back, 3 to 7 impacts, not shrinking with rtol. Held at gap 0
    and rate 0 there, every run has the exact motion's 3 impacts.
    The log has 337 samples, so its splines' jerk jumps at 335 knots; the
    event method's steps straddled them (rk8pd loses its order across one),
    and the error summed over them scattered with the last bits of the
    input: the log drawn through NumPy's AVX-512 path or without it
    (NPY_DISABLE_CPU_FEATURES="X86_V4 AVX512_ICL") moves positions by 1 ulp
    and gave D(1e-9), D(1e-10) = 5.3e-8, 1.9e-9 L or 1.4e-8, 8.0e-9 L
    (output t_end / 8), and over 20 logs a few ulps apart D(1e-9) spread
    over 6.9e-9 .. 1.2e-7 L, D(1e-10) over 4.8e-10 .. 2.6e-8 L (reference
    rtol 1e-13), so the check below failed on some. With steps ending at the knots (csrc/hybrid.c)
    D(1e-9) = 2.6e-11 .. 3.3e-11 L and D(1e-10) = 1.2e-12 .. 3.3e-12 L over
    the same logs, in 377 steps instead of 923. Checked on the drawn log and
    on 3 logs a few ulps apart: every run's distance to the reference (rtol
    1e-12) shrinks with rtol, D(1e-10) <= PROPORTIONAL D(1e-9) + FLOOR at
    both output grids (tests/scenarios/test_zoo.py), with the reference's 3 impacts.
    (tests/scenarios/test_sampled.py::test_free_flight_under_a_log_is_exact_at_every_rtol
    checks the knots against a closed form.)"""
    zs0 = input_scene(795).zs
    for zs in [zs0] + [_nudged_log(zs0, j) for j in range(1, 4)]:
        tight = zoo.run(zs, "event", rtol=1e-12, n_out=zoo.N_OUT_FINE)
        ref = zoo.final_pose(tight)
        for n_out in (zoo.N_OUT, zoo.N_OUT_FINE):
            rs = [zoo.run(zs, "event", rtol=rtol, n_out=n_out) for rtol in (1e-9, 1e-10)]
            d = [zoo.pose_distance(zs, zoo.final_pose(r), ref) for r in rs]
            assert [r.stats["impacts"] for r in rs] == [tight.stats["impacts"]] * 2, n_out
            assert d[1] <= zoo.PROPORTIONAL * d[0] + zoo.FLOOR, (n_out, d)


# ---------------------------------------------------------------- properties

#: (property, method, seed) -> the defect; strict xfails.
KNOWN_PROPS = {  # noqa: E501 - the defects, stated in full
}

#: Penetration allowed of the methods that keep contacts exactly (event and
#: regularised to their tolerance atol = REF_RTOL x the scene's scales, the
#: implicit method's position projection to rounding), relative to L.
GAP_TOL = zoo.REF_RTOL


def _params(prop, methods, applies):
    """(method, seed) pairs for which the property applies (applies(seed,
    method) true): the scenes are cheap to draw, so the pairs that do not
    apply are left out at collection rather than skipped."""
    out = []
    for method in methods:
        for seed in SEEDS:
            if not applies(seed, method):
                continue
            marks = []
            if (prop, method, seed) in KNOWN_PROPS:
                marks.append(pytest.mark.xfail(strict=True, reason=KNOWN_PROPS[prop, method, seed]))
            out.append(pytest.param(method, seed, marks=marks, id=f"{method}-{seed}"))
    return out


_RUNS: dict = {}


def test_inputs_generator_is_valid_and_covers_the_inputs():
    """Every drawn scene is a pure function of its seed, starts with no
    vertex beyond a stop, keeps mu_static >= mu, and the seeds in the test
    cover every new input: each schedule kind and a release, mu_static,
    stop friction (with each dof), each obstacle kind with and without
    friction, Shake and Chain motions."""
    seen = set()
    for seed in SEEDS:
        s = input_scene(seed)
        sc = s.scene
        sc.check_stops()
        if sc.grasp.mu_static is not None:
            assert sc.grasp.mu_static >= sc.grasp.mu
        for k in ("grip", "obstacle"):
            if k in s.tags:
                seen.add((k, s.tags[k]))
                seen.add((k, s.tags[k].split("-")[0]))
        if "mu_static" in s.tags:
            seen.add("mu_static")
        if "stop_mu" in s.tags:
            seen.add(("stop_mu", sc.dof))
        seen.add(("motion", s.tags["motion"]))
        for m in zoo.METHODS:
            if unsupported(sc, m):
                seen.add(("refuses", m, unsupported(sc, m)))
    assert input_scene(5).scene == input_scene(5).scene
    want = {("grip", k) for k in ("linear", "cubic", "step")} | {("obstacle", k) for k in ("box", "rod", "wedge")}
    want |= {("obstacle", k + "-mu") for k in ("box", "rod", "wedge")} | {"mu_static", ("motion", "shake"),
                                                                        ("motion", "chain")}
    want |= {("stop_mu", d) for d in zoo.DOFS}
    assert want <= seen, want - seen
    assert any(k[0] == "grip" and k[1].endswith("-release") for k in seen if isinstance(k, tuple))


def plain_run(seed, method):
    """One run of a supporting method at the zoo's coarsest settings (time
    stepping at t_end / N_DT, adaptive at REF_RTOL with output t_end / N_OUT)."""
    key = (seed, method)
    if key not in _RUNS:
        zs = input_scene(seed).zs
        kw = dict(dt=zs.t_end / zoo.N_DT) if method in ("implicit", "explicit") else {}
        _RUNS[key] = zoo.run(zs, method, **kw)
    return _RUNS[key]


def _has_contact(seed, method):
    sc = input_scene(seed).scene
    return not unsupported(sc, method) and bool(sc.stops or sc.obstacles)


@pytest.mark.warns_by_design("impact", "pad", "outline", "solver", "jump")
@pytest.mark.parametrize("method,seed", _params("penetration", zoo.METHODS, _has_contact))
def test_inputs_no_penetration(method, seed):
    """The smallest gap to a stop or obstacle over the run stays above
    -GAP_TOL L; explicit: above -(GAP_TOL L + the largest per-step bound
    P_i of its position projection (csrc/explicit.c).

    Derivation of P_i. The step enforces, for every row, the linearisation
    g(q) + h G v+ >= 0 of its gap at the step's start q (G = dg/dq exactly,
    obstacles and stops at t + h), then sets q+ = q + h v+; the gap measured
    after the step is g(q+) >= the row's own gap there (a vertex's gap is a
    maximum over faces or edges), so the penetration is at most the
    remainder g(q + h v+) - g(q) - h G v+, and none carries over (each step
    re-linearises at the true gap). With w = v+[2] (theta rate), phi = h w,
    v = v+[:2] (centre of mass), R(phi) the rotation:

    - an object vertex at offset l (|l| <= r_max) against a plane (stop or
      obstacle face, normal N): g = N.(r + R(theta) l) + c, linear in r, so
      the remainder is N.(R(phi) - I - phi J) R l, at most 1/2 phi^2 r_max
      (|d^2/dphi^2 R(phi) l| = |l|);
    - an obstacle's section vertex y (planar, fixed over the step) against an
      object edge (body normal n0, offset d from the centre of mass):
      g = R(theta) n0 . (y - r) - d, bilinear in (rotation, translation); with
      n = R n0, the remainder is (R(phi) n - n - phi J n).(y - r) -
      h (R(phi) n - n).v, at most 1/2 phi^2 |y - r| + h |phi| |v|; y ends
      inside the hull if it penetrates, so |y - r| <= r_max + h |v|;
    - a rod of radius rho along the plate normal (section: a disc, centre a)
      against the hull K: the row is the hull point V nearest a, a material
      point, while the nearest point slides along the hull as it turns, so
      V's own remainder does not bound the gap. K lies in the half-plane
      n.(x - V) >= 0 (n = (V - a) / |V - a|: V is a's projection onto K), the
      moved hull in R(phi) n.(x - V+) >= 0, so its distance from a is at
      least R(phi) n.(V+ - a) = cos(phi) n.(V+ - a) + sin(phi) Jn.(V+ - a);
      with V+ = V + h Vd + e (Vd = v + w J (V - r), |e| <= 1/2 phi^2 r_max),
      the row |V - a| + h n.Vd >= rho and Jn.(V - a) = 0, the gap after the
      step is at least -(1 - cos phi) rho - |e| (1 + |phi|) - |phi| h |Vd|:
      a penetration of at most 1/2 phi^2 (rho + r_max (1 + |phi|))
      + |phi| h (|v| + |w| r_max).

    Hence P_i = h^2 w^2 (r_max + h |v|) / 2 + h^2 |w| |v| for planar scenes
    with obstacles (the cross term h^2 |w| |v|: the edge normal turns while
    the object translates), and at least the rod's term with a rod,
    1/2 h^2 w^2 r_max with stops only, 0 for translation; rotation (about
    the pivot, no translation of the pivot) has only the first form. Each
    output sample is one step, so w and v are the recorded v+ of that step
    (explicit.c checks every step against the same bound and counts a
    warning beyond it)."""
    s = input_scene(seed)
    zs = s.zs
    r = plain_run(seed, method)
    allow = GAP_TOL * zs.L
    if method == "explicit" and zs.scene.dof != "translation":
        h = zs.t_end / zoo.N_DT
        w = np.abs(r.v[1:, -1])
        if zs.scene.dof == "planar" and zs.scene.obstacles:
            sp = np.hypot(r.v[1:, 0], r.v[1:, 1])
            P = 0.5 * h * h * w * w * (zs.radius + h * sp) + h * h * w * sp
        else:
            P = 0.5 * h * h * w * w * zs.radius
        rods = [o.radius for o in zs.scene.obstacles if o.kind == "cylinder"]
        if rods:
            phi = h * w
            sp = np.hypot(r.v[1:, 0], r.v[1:, 1]) if zs.scene.dof == "planar" else 0.0 * w
            P = np.maximum(P, 0.5 * phi * phi * (max(rods) + zs.radius * (1.0 + phi)) + phi * h * (sp + w * zs.radius))
        allow += float(np.max(P))
    assert r.stats["min_gap"] >= -allow, (s, r.stats["min_gap"] / zs.L, allow / zs.L)


@pytest.mark.parametrize("method,seed", _params("stick", zoo.METHODS,
                                                lambda seed, method: not unsupported(input_scene(seed).scene, method)))
@pytest.mark.warns_by_design("impact", "pad", "outline", "solver", "jump")
def test_inputs_stick_is_still(method, seed):
    """A sample flagged stick has a relative velocity of exactly 0; for the
    implicit method (a sample is flagged stick when every step of its
    interval stuck: one step, or the sub-steps of an interval split at a
    switching time) two consecutive stuck samples have the same pose, bit
    for bit."""
    s = input_scene(seed)
    r = plain_run(seed, method)
    st = r.stick.astype(bool)
    assert np.all(r.v[st] == 0.0), (s, np.max(np.abs(r.v[st])))
    if method == "implicit":
        both = st[1:] & st[:-1]
        assert np.all(r.q[1:][both] == r.q[:-1][both]), s


def rest_variant(seed):
    """The seed's scene with the gripper at rest (so the energy of the
    relative motion is defined) and an initial relative velocity (drawn if
    the scene has none), run to t_end."""
    s = input_scene(seed)
    zs = s.zs
    rng = np.random.default_rng([int(seed), 0x13])
    v0 = zs.scene.v0
    if not any(v0):
        v0 = (float(rng.uniform(-0.5, 0.5) * zs.L / zs.tau), float(rng.uniform(-0.5, 0.5) * zs.L / zs.tau),
              float(rng.uniform(-0.5, 0.5) / zs.tau))
    return s, exdex.replace(zs.scene, motion=exdex.Rest(), v0=v0)


def energy(sc, r, gravity_B):
    """Kinetic + gravitational energy of the relative motion [J]: the centre
    of mass C at pose[:, :2] in B, the gripper at rest; translation: m v^2 / 2
    along the slide axis; rotation: (Izz + m |c|^2) w^2 / 2 about the patch
    centre c; planar: m |v|^2 / 2 + Izz w^2 / 2."""
    m = sc.body.mass
    Izz = float(np.array(sc.body.inertia)[2, 2])
    if sc.dof == "translation":
        T_ = 0.5 * m * r.v[:, 0] ** 2
    elif sc.dof == "rotation":
        c = np.array(sc.grasp.patch.center)
        T_ = 0.5 * (Izz + m * (c @ c)) * r.v[:, 0] ** 2
    else:
        T_ = 0.5 * m * (r.v[:, 0] ** 2 + r.v[:, 1] ** 2) + 0.5 * Izz * r.v[:, 2] ** 2
    V = -m * (r.pose[:, :2] @ gravity_B[:2])
    return T_ + V


@pytest.mark.parametrize("method,seed", _params("energy", ("implicit", "event", "regularised"),
                                                lambda seed, method: not unsupported(rest_variant(seed)[1], method)))
@pytest.mark.warns_by_design("impact", "pad", "outline", "solver", "jump")
def test_inputs_friction_adds_no_energy(method, seed):
    """Gripper at rest: the plates' friction (any grip schedule, static or
    kinetic), the stops' and the obstacles' (normal forces and friction)
    never add energy: E = kinetic + gravitational energy never increases
    from one sample to the next. Event and regularised (adaptive at
    REF_RTOL): to their integration error, steps x REF_RTOL x the energy
    scale m g L + max E - min E. Implicit: gravity along the plate normal
    (only contact forces act in the plane, E is the kinetic energy: its
    midpoint position update changes the potential energy by O(h^2) in the
    step that stops the object, the scheme's, not the friction's); its
    velocity update is dissipative for every contact, to rounding. The
    explicit method chatters at stick and is not checked."""
    s, sc = rest_variant(seed)
    zs = s.zs
    R0 = np.array(sc.gripper_rotation)
    if method == "implicit":
        sc = exdex.replace(sc, gravity=tuple(R0 @ np.array([0.0, 0.0, -G])))
        r = exdex.simulate(sc, zs.t_end, zs.t_end / zoo.N_DT, method=method)
    else:
        r = zoo.run(dataclasses.replace(zs, scene=sc), method)
    gB = R0.T @ np.array(sc.gravity)
    E = energy(sc, r, gB)
    scale = sc.body.mass * G * zs.L + float(np.ptp(E))
    tol = (r.stats["steps"] * zoo.REF_RTOL if method != "implicit" else 1e-12) * scale
    rise = float(np.max(np.diff(E)))
    assert rise <= tol, (s, method, rise / scale)

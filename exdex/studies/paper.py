"""The paper's case studies (Section 2, Figs. 3, 4 and 6).

Three scene functions return the paper's scenes, :func:`fig3_scene`,
:func:`fig4_scene` and :func:`fig6_scene`. The paper gives the motion, the
mass, the friction coefficient and (Fig. 6) the inertia; everything else (grip
force, direction of motion, patch, pivot, centre of mass, stop geometry) is
chosen here, stated in the functions' docstrings and justified, by derivation
wherever one exists. In short:

* **Fig. 3** (inertial slip, Eq. 7): vertical motion starting *downward*; grip
  force 1.5051 N per finger (two fingers, mu 0.5: friction capacity 1.5051 N),
  derived in closed form so that the final slip is the paper's 20 mm
  (:func:`fig3_grip_force`).
* **Fig. 4** (stop, trapezoid): the gripper moves 50 mm down while the object
  stands on a fixed horizontal stop; the same grip force as Fig. 3. The slip is
  50 mm for any grip force; the stop force while sliding is m g + mu N.
* **Fig. 6** (rotation, Eq. 7 as an angle): the gripper turns about the plate
  normal through the pivot; the centre of mass is at the pivot (the centre of
  pressure), so gravity has no moment; the grip force of Fig. 3; the torque
  capacity mu N e_r = I_zz a_H, the weakest grasp that holds the object during
  the gentle phases of Eq. 7. That gives 2 theta1 (2 beta - 1) / beta
  = 114.29 deg, for beta = 0.7 the largest final rotation Eq. 7 can produce in
  this setting for any grip force and patch; the paper's ~140 deg lies beyond
  it (see :func:`fig6_scene`).

Independent references: the 1-DoF problems have piecewise-constant driving
accelerations and Coulomb friction with exact stick, solved here event by
event in closed form (:func:`coulomb_1dof`), without the C core. Fig. 4's
relative displacement is the gripper's own trapezoid (:func:`trapezoid`).

Units are SI inside; millimetres and degrees only in figures, tables and CSV
columns that say so.
"""
from __future__ import annotations

import csv
import math
import re
import warnings
from dataclasses import dataclass, field
from typing import Any, Dict, List, Optional, Sequence, Tuple, Union

import numpy as np
from numpy.typing import ArrayLike, NDArray

from exdex._closed_form import (PiecewiseMotion, closed_form, coulomb_1dof, eq7_accelerations, eq7_phases,
                                 world_dir)
from exdex.diagnostics import ReductionWarning
from exdex.scene import AsymmetricProfile, Body, Grasp, Pad, Patch, Scene, Stop, TrapezoidalProfile, replace
from exdex.simulate import Result, simulate

__all__ = [
    "G", "MASS", "MU", "FINGERS",
    "eq7_accelerations", "eq7_phases", "trapezoid", "coulomb_1dof", "PiecewiseMotion",
    "fig3_grip_force", "fig3_scene", "fig4_scene", "fig6_scene", "fig6_rotation_bound",
    "closed_form", "stop_closed_form", "stop_gaps", "gripper_coordinate", "run_case", "CaseRun", "CASES",
    "plot_case", "save_figure", "WIDTHS", "write_csv", "write_summary", "format_table", "fig6_reduction_notes", "FIG3", "FIG4", "FIG6", "FIG4_SIZE", "FIG6_MARGIN",
]

# ------------------------------------------------------------------ constants

#: gravitational acceleration [m/s^2] (the core's default, exdex.Scene.gravity)
G = 9.81
#: object mass of all three cases [kg] (paper Figs. 3, 4, 6)
MASS = 0.1
#: plate-object friction coefficient of all three cases (paper Figs. 3, 4, 6)
MU = 0.5
#: pressing patches: a two-finger parallel gripper (paper Section 1.1)
FINGERS = 2

#: the paper's values for the three cases
FIG3: Dict[str, Any] = dict(beta=0.9, amplitude=0.1, duration=0.5, slip=0.020)          # X1 [m], T [s], slip [m]
FIG4: Dict[str, Any] = dict(v_max=0.12, amplitude=0.05, duration=0.5, slip=0.050)       # [m/s], [m], [s], [m]
FIG6: Dict[str, Any] = dict(beta=0.7, amplitude=math.radians(100.0), duration=3.0,      # theta1 [rad], T [s]
            inertia=(0.5, 0.5, 0.04), rotation=math.radians(140.0))     # [kg m^2], ~[rad]

#: relative margin put on Fig. 6's torque capacity above I_zz a_H, so that
#: floating-point rounding cannot decide the stick test of the gentle phases
FIG6_MARGIN = 1e-9


# ------------------------------------------------------------- motion profiles

def trapezoid(t: ArrayLike, amplitude: float, duration: float,
              v_max: float) -> Tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """Trapezoidal velocity profile: (s, sd, sdd) at times ``t`` (arrays).

    Distance ``amplitude`` in ``duration`` T with peak speed v_max: ramps of
    t_a = T - |X1| / v_max with acceleration v_max / t_a, cruise between.
    Before 0: at rest at 0; after T: at rest at X1.
    """
    t = np.asarray(t, dtype=float)
    sign = math.copysign(1.0, amplitude)
    dist = abs(amplitude)
    ta = duration - dist / v_max
    acc = v_max / ta if ta > 0 else math.inf
    s = np.empty_like(t)
    sd = np.empty_like(t)
    sdd = np.empty_like(t)
    up = (t >= 0) & (t < ta)
    cruise = (t >= ta) & (t < duration - ta)
    down = (t >= duration - ta) & (t < duration)
    before, after = t < 0, t >= duration
    s[before], sd[before], sdd[before] = 0.0, 0.0, 0.0
    s[up], sd[up], sdd[up] = 0.5 * acc * t[up] ** 2, acc * t[up], acc
    tc = t[cruise]
    s[cruise], sd[cruise], sdd[cruise] = 0.5 * v_max * ta + v_max * (tc - ta), v_max, 0.0
    tau = duration - t[down]
    s[down], sd[down], sdd[down] = dist - 0.5 * acc * tau**2, acc * tau, -acc
    s[after], sd[after], sdd[after] = dist, 0.0, 0.0
    return sign * s, sign * sd, sign * sdd


# ------------------------------------------------ closed-form 1-DoF reference

def _bisect(f, lo, hi, tol=1e-15, maxiter=200):
    """Root of f in [lo, hi] (sign change required) by bisection."""
    flo, fhi = f(lo), f(hi)
    if flo == 0:
        return lo
    if fhi == 0:
        return hi
    if (flo > 0) == (fhi > 0):
        raise ValueError("no sign change in the bracket")
    for _ in range(maxiter):
        mid = 0.5 * (lo + hi)
        fm = f(mid)
        if fm == 0 or hi - lo <= tol * max(1.0, abs(mid)):
            return mid
        if (fm > 0) == (flo > 0):
            lo, flo = mid, fm
        else:
            hi = mid
    return 0.5 * (lo + hi)


# ------------------------------------------------------------------ Fig. 3

def fig3_grip_force(slip: float = FIG3["slip"], amplitude: float = FIG3["amplitude"],
                    duration: float = FIG3["duration"], beta: float = FIG3["beta"], mass: float = MASS,
                    mu: float = MU, fingers: int = FINGERS, g: float = G) -> float:
    """Grip force per finger [N] that gives a final downward slip ``slip`` [m]
    in the Fig. 3 scene (vertical Eq. 7 motion starting downward), in closed form.

    Relative to the gripper, along the vertical (up positive), the object feels
    d = -g - (gripper acceleration, up positive) per unit mass, and friction up
    to c = mu * fingers * grip_force / m. Starting downward, Eq. 7 gives the
    gripper an upward acceleration -a_H, then +|a_L|, then -a_H, so
    d = -(g - a_H), -(g + |a_L|), -(g - a_H), then -g at rest. With
    g - a_H <= c < g + |a_L| the object

    1. sticks on [0, beta T),
    2. slips for tau = (2 - 2 beta) T at the constant rate -u, u = g + |a_L| - c:
       v2 = -u tau, x2 = -u tau^2 / 2,
    3. decelerates at D - u, D = a_H + |a_L|, and sticks again after
       u tau / (D - u) (which must be <= beta T): x3 = -u^2 tau^2 / (2 (D - u)),

    and stays stuck at rest if c >= g. The total slip is
    s = u tau^2 D / (2 (D - u)), a monotone function of u, inverted exactly:
    u = 2 s D / (tau^2 D + 2 s), c = g + |a_L| - u.
    For the paper's values (beta 0.9, X1 0.1 m, T 0.5 s, m 0.1 kg, mu 0.5,
    two fingers, s = 20 mm): a_H = 8/9, |a_L| = 8 m/s^2, tau = 0.1 s,
    u = 80/29 m/s^2, c = 15.0514 m/s^2, grip force 1.50514 N per finger.
    Raises ValueError if the phase assumptions above do not hold.
    """
    a_h, a_l = eq7_accelerations(amplitude, duration, beta)
    a_l = abs(a_l)
    tau = (2.0 - 2.0 * beta) * duration
    D = a_h + a_l
    u = 2.0 * slip * D / (tau**2 * D + 2.0 * slip)
    c = g + a_l - u
    if not (c >= g - a_h and u > 0 and u * tau / (D - u) <= beta * duration and c >= g):
        raise ValueError("the requested slip is outside the stick/slip/stick regime of the closed form")
    return c * mass / (mu * fingers)


def fig3_scene(grip_force: Optional[float] = None, direction: int = -1, dof: str = "translation") -> Scene:
    """Paper Fig. 3: inertial slip with the Eq. 7 profile (Section 2.2.1).

    Given by the paper: Eq. 7 with beta 0.9, X1 0.1 m, T 0.5 s, m 0.1 kg,
    mu 0.5; 20 mm final relative displacement.

    Chosen here (the paper does not say):

    * **Gravity and motion vertical, plates vertical** (the default gripper
      orientation: B's y up) and the object free to slide along B's y: Fig. 1
      draws g along the gripper's motion and the object's slip.
    * **Direction: downward first** (``direction=-1``; motion axis
      (0, 0, -1)). Eq. 7 is a round trip (out to X1 at T, back at rest at
      2 T). Going down first, the long gentle phases (a_H = 0.889 m/s^2) only
      lighten the object (it needs 8.92 m/s^2 of friction) and the short
      sharp one (|a_L| = 8 m/s^2 upward, 0.1 s) drives it down: the slip is
      made by the inertial force, the point of Section 2.2.1. Going up first
      (``direction=+1``), the object slips only where the grasp fails against
      gravity plus a_H (10.70 m/s^2), i.e. in the two slow phases: 20 mm then
      needs a capacity of 10.606 m/s^2, only 8 % above g, the slip is gravity
      creeping through the slow phases and it goes on after the gripper has
      stopped (until 1.052 s) (see notebooks/fig3_inertial.ipynb).
    * **Grip force 1.50514 N per finger, two fingers** (capacity
      mu * 2 * F = 1.50514 N = 15.05 m/s^2 per unit mass), derived in closed
      form so that the final slip is exactly the paper's 20 mm
      (:func:`fig3_grip_force`).
    * **Patch** irrelevant for a pure translation (only the force capacity
      mu N acts); the default e_r is kept. Inertia irrelevant (no rotation).

    grip_force : per finger [N]; default :func:`fig3_grip_force` ().
    direction : -1 (down first, default) or +1 (up first).
    """
    if direction not in (-1, 1):
        raise ValueError(f"direction must be -1 (down first) or +1 (up first), got {direction!r}")
    if grip_force is None:
        grip_force = fig3_grip_force()
    return Scene(
        # the box of Fig. 4; its size matters only to the physics-engine cross-checks (exdex compare)
        body=Body(mass=MASS, size=FIG4_SIZE),
        grasp=Grasp(mu=MU, grip_force=grip_force, fingers=FINGERS),
        motion=AsymmetricProfile(FIG3["amplitude"], FIG3["duration"], FIG3["beta"],
                                 axis=(0.0, 0.0, float(direction))),
        dof=dof,
    )


# ------------------------------------------------------------------ Fig. 4

#: Fig. 4 object: a box, lx 30 mm, ly 160 mm (vertical), lz 30 mm (across the plates)
FIG4_SIZE = (0.03, 0.16, 0.03)
#: Fig. 6 object outline for the engine cross-checks: a 100 x 100 x 30 mm plate that holds the patch
FIG6_SIZE = (0.1, 0.1, 0.03)


def fig4_scene(grip_force: Optional[float] = None) -> Scene:
    """Paper Fig. 4: slip against a fixed stop with a trapezoidal velocity
    profile (Section 2.2.2).

    Given by the paper: trapezoid with Vmax 0.12 m/s, X1 0.05 m, T 0.5 s,
    m 0.1 kg, mu 0.5; contact with the stop from t = 0; 50 mm relative
    displacement against gravity.

    Chosen here:

    * **Gripper moves down** 50 mm (motion axis (0, 0, -1)), plates vertical
      (default orientation), object free along B's y (vertical): the object,
      held by the stop, rises 50 mm relative to the fingers, "opposite to
      gravity" as in the paper.
    * **Object**: a box 30 x 160 x 30 mm (``FIG4_SIZE``) whose centre of mass
      is at the gripper origin; 160 mm tall so that the fingers still hold it
      after sliding 50 mm along it. Only its lowest edge matters (the outline
      touching the stop).
    * **Stop**: the horizontal plane z = -80 mm with normal up, touching the
      object's bottom edge at t = 0 ("contact is made at t = 0").
    * **Grip force**: the one of Fig. 3 (the same object, mass and friction:
      1.50514 N per finger). The 50 mm does not depend on it: while the
      gripper moves down, friction drags the object down and the stop holds
      it, so the object stays fixed in the world. The stop force does: while
      the object slides up relative to the fingers, friction on it is mu N
      downward, so the stop carries m g + mu N = 0.981 + 1.505 = 2.486 N.
      Once the gripper is at rest the split between friction and stop is
      statically indeterminate for rigid bodies; the core lets the stop carry
      what it can, so the stop force drops to m g = 0.981 N and friction to 0
      (only their sum, m g, is checked in tests/studies/test_paper.py).

    grip_force : per finger [N]; default that of Fig. 3.
    """
    if grip_force is None:
        grip_force = fig3_grip_force()
    body = Body.box(MASS, FIG4_SIZE)
    bottom = -FIG4_SIZE[1] / 2.0
    return Scene(
        body=body,
        grasp=Grasp(mu=MU, grip_force=grip_force, fingers=FINGERS),
        motion=TrapezoidalProfile(FIG4["amplitude"], FIG4["duration"], FIG4["v_max"], axis=(0.0, 0.0, -1.0)),
        stops=(Stop(point=(0.0, 0.0, bottom), normal=(0.0, 0.0, 1.0)),),
    )


# ------------------------------------------------------------------ Fig. 6

def fig6_rotation_bound(amplitude: float = FIG6["amplitude"], beta: float = FIG6["beta"]) -> float:
    """Largest final relative rotation [rad] Eq. 7 gives about a pivot at the
    centre of mass when the grasp holds the object in the gentle phases:
    2 theta1 (2 beta - 1) / beta.

    With kappa = torque capacity / I_zz and the gripper's angular acceleration
    a_H, a_L (Eq. 9), the object's relative drive is -theta1''(t). For
    kappa >= a_H it sticks in the gentle phases and slips only in the sharp one
    (duration tau = 2 (1 - beta) T) at u = |a_L| - kappa, then decelerates at
    D - u, D = a_H + |a_L|: theta2 = u tau^2 D / (2 (D - u)), decreasing in
    kappa. At kappa = a_H this is tau^2 (|a_L|^2 - a_H^2) / (4 a_H)
    = 2 theta1 (2 beta - 1) / beta, independent of T.

    For kappa < a_H the object also slips backwards in the first phase. For
    the paper's beta = 0.7 the bound is then still the maximum over all
    kappa > 0 (a dense scan of the closed form, tests/studies/test_paper.py); this is
    not true for every beta (beta = 0.6: a weaker grasp gives ~77 deg against
    the bound's 66.7 deg; notebooks/parameters.ipynb).
    Requires 1/2 < beta < 1 (else a_H >= |a_L|: nothing slips forward).
    """
    return 2.0 * amplitude * (2.0 * beta - 1.0) / beta


def fig6_scene(grip_force: Optional[float] = None, e_r: Optional[float] = None) -> Scene:
    """Paper Fig. 6: rotation about the centre of pressure with Eq. 7 as an
    angular profile (Section 2.3, Fig. 5).

    Given by the paper: beta 0.7, theta1 100 deg, T 3 s, m 0.1 kg,
    I = diag(0.5, 0.5, 0.04) kg m^2, mu 0.5; a constant (uniform) pressure
    patch; rotation about its centre of pressure (the centroid of the contact
    surface), fixed during the motion; the object does not translate;
    relative rotation ~140 deg.

    Chosen here:

    * **Rotation axis: the plate normal** (B's z), the axis of theta1 and
      theta2 in Fig. 5; plates vertical (default orientation, B z = -A y), so
      the motion axis in A is (0, -1, 0). With the gripper's angular velocity
      along the plate normal, only I_zz = 0.04 kg m^2 enters (no gyroscopic
      coupling); I_xx, I_yy are inert.
    * **Pivot = centre of pressure = centre of mass** (patch centre (0, 0)):
      the paper's object "does not undergo any translation", and a rotation
      about a point other than the centre of mass would move it. Gravity (in
      the plate plane) then passes through the pivot and has no moment: the
      ideal pin of the core (paper 2.3) carries the weight, and the friction
      torque capacity is the full mu N e_r (the coupling of force and torque
      on the friction ellipsoid is not used for a pin, as in the paper).
    * **Gripper turns about the axis through the pivot** (the contact point is
      fixed in the world as well). With the centre of mass on the pivot the
      pin carries every force, so this choice does not change theta2.
    * **Grip force**: the one of Fig. 3 (same object mass, same mu, same
      gripper): 1.50514 N per finger, mu N = 1.50514 N.
    * **Patch: torque capacity mu N e_r = I_zz a_H** (a_H = 0.554 rad/s^2,
      Eq. 9a), i.e. e_r = 14.725 mm, a uniform-pressure disc of radius
      22.09 mm (e_r = 2R/3). The paper gives no patch size. As in Fig. 3, the
      grasp is the one for which Eq. 7 is designed: the object holds during
      the long gentle phases (|theta1''| = a_H) and slips only in the short
      sharp one (|a_L| = 1.293 rad/s^2); the weakest such grasp is chosen,
      plus 1e-9 relative (``FIG6_MARGIN``) so that rounding cannot decide the
      stick test. It gives the final rotation 2 theta1 (2 beta - 1) / beta
      = 800/7 = 114.29 deg (:func:`fig6_rotation_bound`, closed form), which
      for beta = 0.7 is the **largest this profile can produce for any grip
      force and patch** (a dense scan over the torque capacity): the paper's
      ~140 deg is out of reach under these assumptions (by 25.7 deg). A centre of mass
      off the pivot lets gravity act and can give anything from 0 to beyond
      200 deg (notebooks/fig6_rotation.ipynb), so the paper's number cannot
      be matched without inventing that offset.

    grip_force : per finger [N]; default that of Fig. 3.
    e_r : torsional semi-axis of the patch [m]; default I_zz a_H / (mu N)
        (1 + 1e-9).
    """
    if grip_force is None:
        grip_force = fig3_grip_force()
    izz = FIG6["inertia"][2]
    a_h, _ = eq7_accelerations(FIG6["amplitude"], FIG6["duration"], FIG6["beta"])
    mu_n = MU * FINGERS * grip_force
    if e_r is None:
        e_r = izz * a_h / mu_n * (1.0 + FIG6_MARGIN)
        patch = Patch(e_r=e_r, center=(0.0, 0.0), shape="disc", dims=(1.5 * e_r,))
    else:
        patch = Patch(e_r=e_r, center=(0.0, 0.0))
    return Scene(
        # box dimensions only for the engine cross-checks (the paper's inertia is used as given)
        body=Body(mass=MASS, inertia=FIG6["inertia"], size=FIG6_SIZE),
        grasp=Grasp(mu=MU, grip_force=grip_force, fingers=FINGERS, patch=patch),
        motion=AsymmetricProfile(FIG6["amplitude"], FIG6["duration"], FIG6["beta"],
                                 axis=(0.0, -1.0, 0.0), rotation=True, center=(0.0, 0.0, 0.0)),
        dof="rotation",
    )


# ------------------------------------------------- references from a scene

def stop_closed_form(scene: Scene, t: ArrayLike) -> Tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """Fig. 4 type reference: (x2, v2, stop_force) at times ``t``.

    The gripper translates with a trapezoid while the object stands on a fixed
    stop: as long as the gripper moves so that the object slides along +e
    relative to it (e the slide axis in A; here up), friction drags the object
    along -e into the stop, the stop holds it still in the world and
    x2(t) = -(axis . e) s(t) exactly, with stop force
    m (-g . e) + mu N while sliding (the object's world acceleration is 0).
    When the gripper is at rest the split is statically indeterminate: the
    value returned there is NaN.
    """
    motion = scene.motion
    if not isinstance(motion, TrapezoidalProfile) or motion.rotation or not scene.stops:
        raise ValueError("stop_closed_form needs a translating trapezoid and a stop")
    e = world_dir(scene, scene.slide_axis)
    k = float(np.dot(motion.axis, e))
    s, sd, _ = trapezoid(t, motion.amplitude, motion.duration, motion.v_max)
    x2, v2 = -k * s, -k * sd
    if np.any(v2 < 0):
        raise ValueError("the gripper would pull the object off the stop")
    force = np.where(v2 > 0, -scene.body.mass * float(np.dot(scene.gravity, e)) + scene.grasp.capacity, np.nan)
    return x2, v2, force


def gripper_coordinate(scene: Scene, t: ArrayLike) -> NDArray[np.float64]:
    """Gripper displacement along its motion axis [m] or rotation angle about
    it [rad] at times ``t``, from the core's motion evaluation."""
    motion: Any = scene.motion
    k = motion.evaluate(t, scene.gripper_rotation, scene.gripper_position)
    axis = np.array(motion.axis)
    if not motion.rotation:
        return (k["p"] - np.array(scene.gripper_position)) @ axis
    Rrel = k["R"] @ np.array(scene.gripper_rotation).T
    vee = 0.5 * np.stack([Rrel[:, 2, 1] - Rrel[:, 1, 2], Rrel[:, 0, 2] - Rrel[:, 2, 0],
                          Rrel[:, 1, 0] - Rrel[:, 0, 1]], axis=1)
    cos = 0.5 * (np.trace(Rrel, axis1=1, axis2=2) - 1.0)
    return np.arctan2(vee @ axis, cos)


def stop_gaps(result: Any) -> NDArray[np.float64]:
    """Geometric check, independent of the core's stop code: (n, n_stops)
    smallest distance of the object's outline to each stop plane over the
    recorded samples [m] (negative = penetration), from the recorded pose of
    the object in B and the gripper pose in A."""
    sc = result.scene
    k = sc.motion.evaluate(result.t, sc.gripper_rotation, sc.gripper_position)
    pose = result.pose
    verts = sc.body.vertices()
    c, s = np.cos(pose[:, 2]), np.sin(pose[:, 2])
    out = np.empty((len(result.t), len(sc.stops)))
    for j, stop in enumerate(sc.stops):
        gaps = []
        for vx, vy in verts:
            xb = np.stack([pose[:, 0] + c * vx - s * vy, pose[:, 1] + s * vx + c * vy, np.zeros_like(c)], axis=1)
            xa = np.einsum("nij,nj->ni", k["R"], xb) + k["p"]
            gaps.append((xa - np.array(stop.point)) @ np.array(stop.normal))
        out[:, j] = np.min(gaps, axis=0)
    return out


# ------------------------------------------------------------- running a case

@dataclass
class CaseRun:
    """One case study run: the simulation, its reference and the table rows."""

    name: str
    title: str
    result: Result
    scene: Scene
    motion_end: float
    unit: str                     # "mm" or "deg"
    scale: float                  # SI -> unit
    x: np.ndarray                 # exdex displacement [unit]
    reference: np.ndarray         # reference displacement at result.t [unit]
    reference_label: str
    error: np.ndarray             # |x - reference| [unit]
    extra_errors: dict = field(default_factory=dict)   # label -> |x - other| [unit]
    rows: list = field(default_factory=list)           # table rows (dicts)
    columns: dict = field(default_factory=dict)        # extra CSV columns
    notes: list = field(default_factory=list)          # lines printed below the table

    @property
    def still(self) -> Tuple[float, bool]:
        """Largest |v| and whether every step sticks, over samples strictly
        after the gripper stops (the sample at the end time reports the mean
        velocity of the last moving step)."""
        sel = self.result.t > self.motion_end
        return float(np.max(np.abs(self.result.v[sel]))), bool(np.all(self.result.stick[sel]))


def _row(case, quantity, paper, exdex, reference, still, note, difference=None):
    if difference is None and paper is not None:
        difference = exdex - paper
    return dict(case=case, quantity=quantity, paper=paper, exdex=exdex, difference=difference,
                reference=reference, max_v_after=still, note=note)


def run_case(name: str, dt: float = 1e-4, fine_factor: int = 10) -> "CaseRun":
    """Simulate case ``"fig3"``, ``"fig4"`` or ``"fig6"`` with step ``dt`` [s]
    and compute its reference; returns a :class:`CaseRun`.

    Fig. 3, 4: reference = closed form (:func:`closed_form`,
    :func:`stop_closed_form`). Fig. 6: reference = the same scene at
    dt / ``fine_factor``; the closed form is reported too.
    """
    if name == "fig3":
        sc = fig3_scene()
        end = sc.motion.end_time
        res = simulate(sc, t_end=1.5, dt=dt)
        cf = closed_form(sc)
        xr, _ = cf(res.t)
        x = res.displacement[:, 0]
        run = CaseRun(name, "Fig. 3: inertial slip (Eq. 7, beta 0.9, X1 0.1 m, T 0.5 s)", res, sc, end, "mm",
                      1e3, 1e3 * x, 1e3 * xr, "closed form", 1e3 * np.abs(x - xr))
        vmax, _ = run.still
        run.rows.append(_row("Fig. 3", "final relative displacement [mm]", 20.0, 1e3 * x[-1], 1e3 * cf.final,
                             vmax, "downward (sign -); difference of magnitudes",
                             difference=abs(1e3 * x[-1]) - 20.0))
        run.columns["gripper [mm]"] = 1e3 * gripper_coordinate(sc, res.t)
        run.columns["friction [N]"] = res.wrench[:, 1]
        return run
    if name == "fig4":
        sc = fig4_scene()
        end = sc.motion.end_time
        res = simulate(sc, t_end=1.0, dt=dt)
        xr, _, fr = stop_closed_form(sc, res.t)
        x = res.displacement[:, 0]
        run = CaseRun(name, "Fig. 4: slip against a stop (trapezoid, Vmax 0.12 m/s, X1 0.05 m, T 0.5 s)",
                      res, sc, end, "mm", 1e3, 1e3 * x, 1e3 * xr, "closed form", 1e3 * np.abs(x - xr))
        vmax, _ = run.still
        run.rows.append(_row("Fig. 4", "final relative displacement [mm]", 50.0, 1e3 * x[-1], 1e3 * xr[-1],
                             vmax, "upward, object on the stop"))
        force = res.stop_force[:, 0]
        sliding = (res.t > 0) & (res.t < end)
        expected = -sc.body.mass * sc.gravity[2] + sc.grasp.capacity
        run.rows.append(_row("Fig. 4", "stop force while sliding, median [N]", None, float(np.median(force[sliding])),
                             expected, vmax, "m g + mu N (derived; the paper gives none)"))
        run.rows.append(_row("Fig. 4", "min stop gap [m]", None, float(min(res.stats["min_gap"],
                                                                           stop_gaps(res).min())),
                             0.0, vmax, "min of core min_gap and geometric check; >= -1e-12 (rounding): no penetration"))
        run.columns["gripper [mm]"] = 1e3 * gripper_coordinate(sc, res.t)
        run.columns["stop force [N]"] = force
        run.columns["stop force expected [N]"] = fr
        run.columns["friction [N]"] = res.wrench[:, 1]
        return run
    if name == "fig6":
        sc = fig6_scene()
        end = sc.motion.end_time
        t_end = 8.0
        with warnings.catch_warnings():
            # the paper's 1-DoF model, kept; its reduction's failure is a note below
            warnings.simplefilter("ignore", ReductionWarning)
            res = simulate(sc, t_end=t_end, dt=dt)
            fine = simulate(sc, t_end=t_end, dt=dt / fine_factor)
        cf = closed_form(sc)
        x = res.displacement[:, 0]
        xf = np.interp(res.t, fine.t, fine.displacement[:, 0])
        xc, _ = cf(res.t)
        d = math.degrees(1.0)
        run = CaseRun(name, "Fig. 6: rotation (Eq. 7, beta 0.7, theta1 100 deg, T 3 s)", res, sc, end, "deg", d,
                      d * x, d * xf, f"fine run (dt/{fine_factor})", d * np.abs(x - xf),
                      extra_errors={"closed form": d * np.abs(x - xc)})
        vmax, _ = run.still
        run.rows.append(_row("Fig. 6", "final relative rotation [deg]", 140.0, d * x[-1], d * cf.final, vmax,
                             "paper ~140; 2 theta1 (2 beta - 1)/beta = 114.29 is the most any grip/patch gives "
                             "with the centre of mass at the pivot (beta 0.7)"))
        run.columns["gripper [deg]"] = d * gripper_coordinate(sc, res.t)
        run.columns["closed form [deg]"] = d * xc
        run.columns["friction torque [N m]"] = res.wrench[:, 2]
        run.notes += fig6_reduction_notes(res)
        return run
    raise ValueError(f"unknown case {name!r}; expected one of {CASES}")


CASES = ("fig3", "fig4", "fig6")


def fig6_reduction_notes(result: Result, dt: float = 1e-3) -> List[str]:
    """Where the paper's 1-DoF rotation model of Fig. 6 stops describing the
    grasp (its :attr:`exdex.Result.certificate`), and what the planar model
    (event method, output every ``dt``) makes of the same scene: lines of
    text with the figures."""
    c = result.certificate
    if c is None or c["holds"]:
        return [f"Fig. 6: the rotation model's reduction holds up to t = {result.t[-1]:g} s"]
    sc = result.scene
    assert sc is not None
    f = c["load"]
    lines = [f"Fig. 6: the paper's 1-DoF rotation model (kept above) fails its certificate at t = "
             f"{c['valid_until']:g} s: with the object {'stuck' if c['stick'] else 'slipping'}, the pin would carry "
             f"f = ({f[0]:.4g}, {f[1]:.4g}) N (the weight: gravity lies in the plate plane) and the pads "
             f"m_z = {f[2]:.4g} N m, gauge {c['gauge']:.4f} in the friction ellipsoid of capacity "
             f"{c['capacity']:.4g} N (margin {1 - c['gauge'] if c['stick'] else -c['gauge']:.4f}); while it "
             f"turns, a pure rotation slip's friction has no force, so nothing holds the weight"]
    # the planar comparison with the contact on the fingers: a pad of the
    # patch's disc (uniform pressure, e_r = 2R/3) at the pivot, so that the
    # friction stays where the fingers are while the object slides
    pc = sc.grasp.patch.center
    radius = 1.5 * sc.grasp.patch.e_r
    pads = replace(sc, dof="planar", grasp=replace(sc.grasp, pad=Pad(radius=radius, center=(pc[0], pc[1]))))
    planar = simulate(pads, result.t[-1], dt, method="event")
    dq = planar.q - planar.q[0]
    slide = np.hypot(dq[:, 0], dq[:, 1])
    first = np.flatnonzero(slide > 1e-4)
    lines.append(f"Fig. 6 as a planar scene with pads on the fingers (dof='planar', event method, a "
                 f"{1e3 * radius:.2f} mm disc pad at the pivot): turns {math.degrees(dq[-1, 2]):.1f} deg "
                 f"(1-DoF: {math.degrees(result.displacement[-1, 0]):.2f} deg) and slides {1e3 * dq[-1, 0]:.1f} mm "
                 f"along B's x, {1e3 * dq[-1, 1]:.1f} mm along B's y (up); " +
                 (f"first 0.1 mm of slide at t = {planar.t[first[0]]:.3f} s" if first.size else "it does not slide"))
    return lines


# ---------------------------------------------------------------- output

#: figure widths [inch] of a two-column paper: one column and the full page
WIDTHS: Dict[str, float] = {"column": 3.5, "page": 7.16}
#: smallest text size in the figures [pt], at print size (the figures are made at their print width)
FONT_PT = 8.0
#: errors below this fraction of the case's largest |value| are rounding: written as text, not drawn
#: (about 450 units in the last place)
ROUNDING = 1e-13
#: resolution of the PNG files [dpi]
PNG_DPI = 300

#: the figures' titles: the case and the paper's parameters with symbols and units
FIGURE_TITLES = {
    "fig3": ("Fig. 3: inertial slip",
             rf"Eq. 7: $\beta$ = {FIG3['beta']:g}, $X_1$ = {FIG3['amplitude']:g} m, $T$ = {FIG3['duration']:g} s"),
    "fig4": ("Fig. 4: slip against a stop",
             rf"trapezoid: $V_{{max}}$ = {FIG4['v_max']:g} m/s, $X_1$ = {FIG4['amplitude']:g} m, "
             rf"$T$ = {FIG4['duration']:g} s"),
    "fig6": ("Fig. 6: rotation about the pivot",
             rf"Eq. 7: $\beta$ = {FIG6['beta']:g}, $\theta_1$ = {math.degrees(FIG6['amplitude']):g}$\degree$, "
             rf"$T$ = {FIG6['duration']:g} s"),
}


def plot_case(run: "CaseRun", path: Optional[str] = None, width: str = "column") -> Any:
    """Print-ready figure of a case: (a) the gripper's motion, (b) the
    object's displacement in the fingers against its reference, (c) the
    absolute error; the interval after the gripper stops is shaded.

    width : ``"column"`` (3.5 in, panels stacked) or ``"page"`` (7.16 in,
        panels side by side); the figure is made at that size with text of
        at least 8 pt, so it prints at 100 %.

    Errors below 1e-13 of the case's largest |value| (down to a power of
    ten) are rounding: they are not drawn, and a series that is rounding at every sample is a line of
    text in panel (c). Returns the matplotlib Figure; with ``path`` it is
    saved there too (the extension picks the format, PNG at 300 dpi) and
    closed. :func:`save_figure` writes several formats.
    """
    from exdex._optional import pyplot

    if width not in WIDTHS:
        raise ValueError(f"width must be one of {', '.join(map(repr, WIDTHS))}, got {width!r}")
    plt = pyplot("exdex.paper.plot_case", backend="Agg" if path is not None else None)
    rc = {"font.size": FONT_PT, "axes.titlesize": FONT_PT, "axes.labelsize": FONT_PT, "xtick.labelsize": FONT_PT,
          "ytick.labelsize": FONT_PT, "legend.fontsize": FONT_PT, "figure.titlesize": FONT_PT,
          "lines.linewidth": 1.0, "axes.linewidth": 0.6, "xtick.major.width": 0.6, "ytick.major.width": 0.6,
          "legend.frameon": False, "svg.fonttype": "none", "pdf.fonttype": 42}
    with plt.rc_context(rc):
        fig = _draw_case(plt, run, width)
    if path is not None:
        fig.savefig(path, dpi=PNG_DPI)
        plt.close(fig)
    return fig


def _draw_case(plt, run, width):
    res = run.result
    t = res.t
    if width == "column":
        fig, axes = plt.subplots(3, 1, figsize=(WIDTHS[width], 5.4), sharex=True, layout="constrained")
    else:
        fig, axes = plt.subplots(1, 3, figsize=(WIDTHS[width], 2.7), layout="constrained")
    ax_g, ax_a, ax_b = axes
    head, params = FIGURE_TITLES.get(run.name, (run.title, ""))
    fig.suptitle(f"{head}\n{params}" if params else head)
    vmax, stuck = run.still
    for ax in axes:
        ax.axvspan(run.motion_end, t[-1], color="0.92", lw=0, zorder=0)
        ax.set_xlim(t[0], t[-1])
        if width == "page" or ax is ax_b:
            ax.set_xlabel("t [s]")
    unit = run.unit
    gripper = run.scale * gripper_coordinate(run.scene, t)
    motion: Any = run.scene.motion
    axis = np.array(motion.axis, dtype=float)
    if motion.rotation:
        what = "angle"
    elif abs(abs(axis[2]) - 1.0) < 1e-12:   # a vertical motion: drawn as the height
        gripper, what = axis[2] * gripper, "height"
    else:
        what = "along its axis"
    ax_g.plot(t, gripper, color="0.2")
    ax_g.set_ylabel(f"{what} [{unit}]")
    ax_g.set_title("(a) gripper motion", loc="left")

    sym = r"$\theta_2$" if unit == "deg" else r"$x_2$"
    ax_a.plot(t, run.x, color="C0", lw=1.6, label=f"exdex, dt = {res.dt:g} s")
    ax_a.plot(t, run.reference, color="C1", lw=1.0, ls="--", label=run.reference_label)
    ax_a.set_ylabel(f"{sym} [{unit}]")
    ax_a.set_title("(b) object in the fingers", loc="left")
    # the key of (b) and the shading below the panels, where it hides no curve
    ax_a.plot([], [], " ", label=f"shaded: gripper at rest; object: max |v| = {vmax:g} {_STILL_UNIT.get(unit, '')}, "
                                 f"{'stick' if stuck else 'not all stick'}")
    handles, labels = ax_a.get_legend_handles_labels()
    if width == "column":
        labels[-1] = labels[-1].replace("; ", ";\n")
    fig.legend(handles, labels, loc="outside lower center", ncols=2 if width == "column" else 3, handlelength=1.5,
               columnspacing=1.0)

    scale = float(np.max(np.abs(run.x))) if run.x.size else 1.0
    # the rounding floor, down to a power of ten: the panel's lower edge when anything is drawn
    floor = 10.0 ** math.floor(math.log10(ROUNDING * max(scale, 1e-300)))
    series = [(run.reference_label, run.error, "-")] + [(lb, e, ":") for lb, e in run.extra_errors.items()]
    series = [(label.split(" (")[0], err, ls) for label, err, ls in series]   # "fine run (dt/10)": in (b)
    rounding, peak = [], 0.0
    for i, (label, err, ls) in enumerate(series):
        err = np.asarray(err, dtype=float)
        big = err >= floor
        if not np.any(big):
            rounding.append(label)
            continue
        peak = max(peak, float(np.max(err)))
        ax_b.semilogy(t, np.where(big, err, np.nan), color="C0" if i == 0 else f"C{i + 1}", ls=ls,
                      label=f"|exdex - {label}|")
    ax_b.set_ylabel(f"abs. error [{unit}]")
    ax_b.set_title("(c) error", loc="left")
    if peak > 0:
        from matplotlib.ticker import LogLocator, NullFormatter

        ax_b.set_ylim(floor, 10.0 ** (math.ceil(math.log10(peak)) + 3))   # room for the key
        ax_b.yaxis.set_major_locator(LogLocator(base=10.0, numticks=6))
        ax_b.yaxis.set_minor_formatter(NullFormatter())
        for label in rounding:
            ax_b.plot([], [], " ", label=f"|exdex - {label}|:\nrounding")
        ax_b.plot([], [], " ", label=f"< {floor:.0e} {unit}: rounding,\nnot drawn")
        ax_b.legend(loc="upper left", handlelength=1.5)
    else:
        ax_b.set_yticks([])
        ax_b.text(0.5, 0.5, "\n".join(f"|exdex - {label}|\n< {floor:.0e} {unit} at every\nsample: rounding"
                                      for label in rounding), transform=ax_b.transAxes, ha="center", va="center")
    return fig


def save_figure(fig: Any, stem: str, formats: Sequence[str] = ("png", "pdf")) -> List[str]:
    """Write ``fig`` as ``stem.<format>`` for each of ``formats`` ("png" at
    300 dpi; "pdf", "svg" vector, text kept as text) and close it; returns the
    paths."""
    from exdex._optional import pyplot

    plt = pyplot("exdex.paper.save_figure", backend="Agg")
    bad = [f for f in formats if f not in ("png", "pdf", "svg")]
    if bad or not formats:
        raise ValueError(f"formats must be a non-empty subset of ('png', 'pdf', 'svg'), got {tuple(formats)!r}")
    paths = []
    for fmt in formats:
        path = f"{stem}.{fmt}"
        with plt.rc_context({"svg.fonttype": "none", "pdf.fonttype": 42}):
            fig.savefig(path, dpi=PNG_DPI if fmt == "png" else "figure")
        paths.append(path)
    plt.close(fig)
    return paths


def write_csv(run: "CaseRun", path: str) -> None:
    """The case's time series as CSV (header row with units)."""
    res = run.result
    cols = {"t [s]": res.t, f"exdex [{run.unit}]": run.x, f"reference [{run.unit}]": run.reference,
            f"abs error [{run.unit}]": run.error,
            f"v [{run.unit}/s]": run.scale * res.v[:, 0], "stick": res.stick.astype(int)}
    cols.update(run.columns)
    names = list(cols)
    data = np.column_stack([np.asarray(cols[k], dtype=float) for k in names])
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(names)
        for row in data:
            w.writerow(["%.17g" % v for v in row])


def _split_unit(quantity):
    """("final relative displacement", "mm") from "final relative displacement [mm]"."""
    m = re.match(r"^(.*?)\s*\[([^\]]+)\]\s*$", quantity)
    return (m.group(1), m.group(2)) if m else (quantity, "")


#: the unit of the object's largest |v| after the motion, by the unit of the row's quantity (a
#: translation case's lengths and forces: m/s; a rotation case's angles and torques: rad/s)
_STILL_UNIT = {"mm": "m/s", "m": "m/s", "N": "m/s", "deg": "rad/s", "rad": "rad/s", "N m": "rad/s"}
#: |values| below this [m] whose reference is 0 are printed as rounding
ROUNDING_M = 1e-15


def _rounded(value, reference, name, unit):
    """A value that is 0 up to rounding, as text saying so ("0 (rounding, |gap| < 1e-15 m)"); else the value."""
    if unit == "m" and reference == 0.0 and value is not None and abs(value) < ROUNDING_M:
        sym = "gap" if "gap" in name else "x"
        return f"0 (rounding, |{sym}| < {ROUNDING_M:.0e} m)"
    return value


def format_table(rows: Sequence[Dict[str, Any]]) -> str:
    """Plain-text table: case, quantity, unit, paper, exdex, difference,
    reference, largest |v| after the motion (m/s or rad/s); aligned columns,
    an en dash where there is no value."""
    from exdex._table import format_table as table

    body = []
    for r in rows:
        name, unit = _split_unit(r["quantity"])
        v_unit = _STILL_UNIT.get(unit, "")
        still = r["max_v_after"]
        body.append([r["case"], name, unit, r["paper"], _rounded(r["exdex"], r["reference"], name, unit),
                     r["difference"], r["reference"], None if still is None else f"{still:.3g} {v_unit}".rstrip()])
    cols = [("case", None), ("quantity", None), ("unit", None), ("paper", "{:g}"), ("exdex", "{:.6g}"),
            ("exdex - paper", "{:+.4g}"), ("reference", "{:.6g}"), ("max |v| after motion", None)]
    notes = [f"  {r['case']}, {r['quantity']}: {r['note']}" for r in rows if r["note"]]
    return "\n".join([table(cols, body)] + (["notes:"] + notes if notes else []))


def write_summary(rows: Sequence[Dict[str, Any]], path: str) -> None:
    """The cases' table rows (:attr:`CaseRun.rows`) as CSV, one row per quantity."""
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=["case", "quantity", "paper", "exdex", "difference", "reference",
                                          "max_v_after", "note"])
        w.writeheader()
        for r in rows:
            w.writerow({k: ("" if v is None else v) for k, v in r.items()})

"""exdex.studies.hold, the hold benchmark's scenes against their closed forms
(no engine needed; tests/cli/test_hold.py runs the benchmark in the engines).

* Translation: a box of mass m between two plates of friction mu, its weight
  along the plate plane, is held by friction when the plates' capacity
  2 mu F reaches m g: the grip needed is m g / (2 mu), and ``margin`` times
  that is the scene's grip. Below it the box slides at the constant
  a = g - 2 mu F / m (s = a t^2 / 2).
* Rotation: the box hangs from the centre of a disc patch of radius R, its
  centre of mass ARM beside the pivot, across gravity: the weight's torque
  m g ARM against the torsional limit of a pure spin on a disc under
  uniform pressure, mu F e_r per finger with e_r = 2 R / 3 (the mean
  radius of the disc); the grip is margin m g ARM / (2 mu e_r). Below it
  the box turns from rest with theta'' = (m g ARM cos theta - 2 mu F e_r) /
  I_pivot (I_pivot = I_zz + m ARM^2), so theta = alpha_0 t^2 / 2 to a
  relative theta^2 (1 - cos theta <= theta^2 / 2, and m g ARM = 2 I_pivot
  alpha_0 at half the torque needed).
* Shake: amp (1 - cos w t) sampled at 200 Hz; second differences of cos(w t)
  at spacing h are cos(w t) 2 (cos(w h) - 1) / h^2, so the log's peak
  discrete acceleration is exactly amp w^2 2 (1 - cos w h) / (w h)^2, with
  amp w^2 = SHAKE_LOAD g (translation) or SHAKE_LOAD m g ARM / I_pivot
  (rotation).
"""
import math
import warnings

import numpy as np
import pytest

import exdex
from exdex.studies import hold

M, G, MU = hold.MASS, hold.G, hold.MU


def _matrix(q):
    """The rotation matrix of a quaternion (w, x, y, z), normalised."""
    w, x, y, z = np.asarray(q, dtype=float) / np.linalg.norm(q)
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def test_the_grip_is_margin_times_what_friction_needs():
    for margin in hold.MARGINS:
        s = hold.hold_scene("translation", margin, "rest")
        assert s.grasp.grip_force == pytest.approx(margin * M * G / (2 * MU), rel=1e-14)
        assert s.grasp.capacity == pytest.approx(margin * M * G, rel=1e-14)        # 2 mu F
        r = hold.hold_scene("rotation", margin, "rest")
        e_r = 2 * hold.PATCH_RADIUS / 3
        assert r.grasp.patch.e_r == pytest.approx(e_r, rel=1e-14)
        assert r.grasp.grip_force == pytest.approx(margin * M * G * hold.ARM / (2 * MU * e_r), rel=1e-14)


def test_the_rotation_lever_is_across_gravity():
    """The patch centre (the pivot) sits ARM from the centre of mass, along B x,
    and gravity points along -B y (the default gripper pose), so the weight's
    torque about the pivot is the full m g ARM."""
    s = hold.hold_scene("rotation", 3.0, "rest")
    assert s.grasp.patch.center == (hold.ARM, 0.0)
    R = np.array(s.gripper_rotation)
    g_B = R.T @ np.array(s.gravity)
    assert np.allclose(g_B, (0.0, -G, 0.0), rtol=0, atol=1e-15)
    lever = -np.array([*s.grasp.patch.center, 0.0])      # the centre of mass from the pivot, in B
    assert np.cross(lever, M * g_B)[2] == pytest.approx(M * G * hold.ARM, rel=1e-14)


def test_below_the_grip_needed_the_box_slides_at_the_closed_form_acceleration():
    s = hold.hold_scene("translation", 1.5, "rest")
    F = 0.5 * M * G / (2 * MU)                             # half the grip needed
    weak = exdex.replace(s, grasp=exdex.replace(s.grasp, grip_force=F))
    t_end = 0.05
    a = G - 2 * MU * F / M
    res = exdex.simulate(weak, t_end, dt=1e-3)
    # a constant acceleration: the stepper is exact up to rounding; the box slides down (-B y)
    assert res.displacement[-1, 0] == pytest.approx(-0.5 * a * t_end**2, rel=1e-12)


def test_below_the_torque_needed_the_box_turns_at_the_closed_form_acceleration():
    s = hold.hold_scene("rotation", 1.5, "rest")
    e_r = 2 * hold.PATCH_RADIUS / 3
    F = 0.5 * M * G * hold.ARM / (2 * MU * e_r)            # half the torque needed
    weak = exdex.replace(s, grasp=exdex.replace(s.grasp, grip_force=F))
    i_pivot = s.body.inertia[2][2] + M * hold.ARM**2
    alpha0 = (M * G * hold.ARM - 2 * MU * F * e_r) / i_pivot
    t_end = 0.01
    res = exdex.simulate(weak, t_end, 1e-4, method="event", rtol=1e-12, atol=1e-14)
    theta = abs(res.displacement[-1, 0])
    assert theta == pytest.approx(0.5 * alpha0 * t_end**2, rel=(0.5 * alpha0 * t_end**2) ** 2)


@pytest.mark.parametrize("dof", hold.DOFS)
def test_the_shake_adds_a_quarter_of_the_static_load(dof):
    s = hold.hold_scene(dof, 3.0, "shake", t_end=1.0)
    motion = s.motion
    t = np.asarray(motion.times)
    h = 1 / 200
    assert np.allclose(np.diff(t), h, rtol=0, atol=1e-15) and t[-1] == pytest.approx(1.0 + 2 * h, rel=1e-15)
    w = 2 * math.pi * hold.SHAKE_HZ
    if dof == "translation":
        pos = np.asarray(motion.positions)
        axis = np.array(s.gripper_rotation) @ (0.0, 1.0, 0.0)          # the plate axis B y
        assert np.allclose(np.cross(pos, axis), 0.0, rtol=0, atol=1e-18)
        s_t, peak = pos @ axis, hold.SHAKE_LOAD * G
    else:
        R0 = np.array(s.gripper_rotation)
        turns = [R0.T @ _matrix(q) for q in motion.quaternions]      # R0 Rz(theta): the turn about B z
        assert all(np.allclose(Rz[2], (0.0, 0.0, 1.0), rtol=0, atol=1e-15) for Rz in turns)
        s_t = np.array([math.atan2(Rz[1, 0], Rz[0, 0]) for Rz in turns])
        i_pivot = s.body.inertia[2][2] + M * hold.ARM**2
        peak = hold.SHAKE_LOAD * M * G * hold.ARM / i_pivot
    assert s_t[0] == 0.0
    acc = np.diff(s_t, 2) / h**2
    discrete = 2 * (1 - math.cos(w * h)) / (w * h) ** 2
    # rounding only (measured: 3e-14 and 5e-14 relative)
    assert np.max(np.abs(acc)) == pytest.approx(peak * discrete, rel=1e-9)


@pytest.mark.parametrize("dof", hold.DOFS)
@pytest.mark.parametrize("motion", hold.MOTIONS)
def test_exdex_holds_every_scenario_exactly(dof, motion):
    """Within the capacity the stick is exact: no drift at all, and the shake's
    log ends after the run (no velocity jump of the gripper inside it)."""
    t_end = 1.0
    scene = hold.hold_scene(dof, hold.MARGINS[0], motion, t_end=t_end)
    with warnings.catch_warnings():
        warnings.simplefilter("error", exdex.PhysicsWarning)
        t, d, wall = hold.run_setting(("exdex", "exdex", None, dict(dt=1e-3)), scene, t_end)
    assert t[-1] == pytest.approx(t_end, rel=1e-15) and np.all(d == 0.0) and wall >= 0.0


def test_benchmark_rows_and_table():
    rows, curves = hold.benchmark(t_end=0.5, margins=(3.0,), motions=("rest",), dofs=hold.DOFS,
                                  settings=[("exdex", "exdex", None, dict(dt=1e-3))])
    assert [(r["dof"], r["unit"]) for r in rows] == [("translation", "m"), ("rotation", "rad")]
    assert all(r["drift"] == 0.0 and r["creep_speed"] == 0.0 and r["status"] == "ok" for r in rows)
    assert set(rows[0]) == set(hold.FIELDS)
    assert set(curves) == {("exdex", "translation", 3.0, "rest"), ("exdex", "rotation", 3.0, "rest")}
    failed = dict(rows[0], setting="pybullet default", engine="pybullet", drift=math.nan, creep_speed=math.nan,
                  status="failed: RuntimeError")
    slow = dict(rows[0], setting="mujoco elliptic impratio 1 noslip 0", engine="mujoco", drift=1.5e-3,
                creep_speed=2.5e-4)
    lines = hold.format_table([failed, slow] + rows).splitlines()
    drift = lines[:lines.index("")]
    # settings in the benchmark's own order (exdex first), a column per scenario
    assert [ln.split()[0] for ln in drift[3:]] == ["exdex", "mujoco", "pybullet"]
    assert drift[1].split() == ["trans", "3x", "rot", "3x"] and drift[2].split() == ["setting", "rest", "rest"]
    assert drift[3].split()[-2:] == ["0", "0"]                        # exactly zero, said as 0
    assert drift[4].split()[-2:] == ["1.50e-03", "-"]                 # no row for rotation: '-'
    assert drift[5].split()[-2:] == ["-", "-"]                        # failed: '-'


def test_bad_scenarios_are_named():
    with pytest.raises(ValueError, match=r"dof must be one of \('translation', 'rotation'\), got 'planar'"):
        hold.hold_scene("planar", 3.0, "rest")
    with pytest.raises(ValueError, match=r"motion must be one of \('rest', 'shake'\), got 'spin'"):
        hold.hold_scene("translation", 3.0, "spin")
    for margin in (1.0, 0.5, "3"):
        with pytest.raises(ValueError, match=r"margin must be a number > 1 \(capacity over static load\)"):
            hold.hold_scene("translation", margin, "rest")

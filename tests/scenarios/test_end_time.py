"""Default end times: the end of the gripper motion and of the grip schedule.

A grip ramp with the gripper at rest changes the scene until the schedule's
last time: runs and plans that take their end time from the scene must get
there. Checked against the schedule's own times and, for the run, against the
closed-form slide of the ramp (the object starts sliding where the falling
capacity meets its weight)."""
import math

import numpy as np
import pytest

import exdex
from exdex import cli
from exdex.cli.run import default_t_end

G = 9.81


def ramp_scene(t_ramp=2.0, f0=1.5, f1=0.9, mass=0.1, mu=0.5):
    """A 0.1 kg, 50 cm bar held by a grip force that falls linearly from f0
    to f1 over t_ramp seconds, the gripper at rest, the slide axis pointing
    up (capacity mu * 2 * F = F: below the weight 0.981 N from 1.73 s on)."""
    return exdex.Scene(body=exdex.Body.box(mass, (0.03, 0.5, 0.03)),
                       grasp=exdex.Grasp(mu=mu, grip_force=exdex.GripSchedule((0.0, t_ramp), (f0, f1))),
                       motion=exdex.Rest(), gripper_rotation=exdex.paper.fig3_scene().gripper_rotation)


def ramp_slide(k, t_end, t_ramp=2.0, f0=1.5, f1=0.9, m=0.1):
    """Closed form of the slide s(t_end) [m] of ramp_scene with the schedule
    scaled by k: capacity C(t) = k (f0 - r t), r = (f0 - f1) / t_ramp, meets
    m g at t* = (f0 - m g / k) / r; then a = -(k r / m) (t - t*) until
    t_ramp and a = -(m g - k f1) / m after it (still sliding: k f1 < m g)."""
    r = (f0 - f1) / t_ramp
    ts = (f0 - m * G / k) / r
    assert 0.0 < ts < t_ramp and k * f1 < m * G <= t_end * 1e9
    tau = t_ramp - ts
    v2, s2 = -k * r / (2 * m) * tau ** 2, -k * r / (6 * m) * tau ** 3
    a3 = -(m * G - k * f1) / m
    h = t_end - t_ramp
    return s2 + v2 * h + 0.5 * a3 * h ** 2, ts


def test_scene_end_time_is_the_later_of_motion_and_schedule():
    sc = ramp_scene()
    assert sc.motion.end_time == 0.0
    assert sc.end_time == 2.0                                  # the schedule's last time
    moving = exdex.replace(sc, motion=exdex.AsymmetricProfile(0.1, 1.6, 0.9, axis=(0, 0, -1)))
    assert moving.end_time == moving.motion.end_time > 2.0    # the motion ends later
    const = exdex.replace(sc, grasp=exdex.replace(sc.grasp, grip_force=1.0))
    assert const.end_time == 0.0
    # exdex run: 0.5 s after the end (1 s when nothing changes in time)
    assert default_t_end(sc) == 2.5 and default_t_end(const) == 1.0


def test_run_of_a_grip_ramp_reaches_past_the_ramp_and_matches_the_closed_form(tmp_path):
    sc = ramp_scene()
    path = tmp_path / "ramp.toml"
    exdex.save_scene(sc, path)
    out = tmp_path / "out"
    assert cli.main(["run", str(path), "--method", "analytic", "--no-progress", "--out", str(out)]) == 0
    res = exdex.Result.load(out / "ramp.npz")
    assert res.t[-1] == 2.5                                    # not 1 s: the ramp ends at 2 s
    s_end, ts = ramp_slide(1.0, 2.5)
    assert res.q[-1, 0] == pytest.approx(s_end, rel=1e-9, abs=1e-12)
    # held until t*: the first step that slides is the one holding t*
    moving = res.t[~res.stick]
    assert moving[0] - 1e-3 - 1e-12 <= ts < moving[0]


def test_plan_default_end_time_covers_the_schedule():
    """The planner's default end is 1.5 x the scene's end time: a plan of the
    ramp's grip scale slides the object, which a 1 s default would not see
    (the slide starts after t* > 1 s)."""
    sc = ramp_scene()
    with pytest.warns(UserWarning, match="still moving"):   # k f1 < m g: it slides on after the ramp
        p = exdex.plan.solve(sc, {"com_slide": -0.05}, {"grip_force": (1.0, 1.09)}, tol=1e-8)
    assert p.t_end == 3.0
    s_end, ts = ramp_slide(p.value, 3.0)
    assert 1.0 < ts
    assert s_end == pytest.approx(-0.05, abs=1e-7)
    assert p.achieved == pytest.approx(-0.05, abs=1e-8)

"""exdex.cli.plan: ``exdex plan``: a planned scene file and gripper poses for a
slip target, checked against the closed form of the 1-DoF Coulomb problem
(exdex.paper.closed_form) or re-simulated (event method, rtol 1e-12) for a
planar pose target; the scene file's simulate table and the units printed."""
import math

import numpy as np
import pytest

import exdex
from exdex import cli, paper
from scenes import planar_box

G = 9.81
TOL = (1e-4, math.radians(0.1))


def closed_slip(scene):
    """Final slip of a Fig. 3 type scene in closed form [m]."""
    return paper.closed_form(scene).final


def ramp_scene():
    """The gripper at rest, the grip force falling from 1.5 N to 0.9 N over
    2 s (capacity below the 0.1 kg bar's weight from 1.73 s on)."""
    return exdex.Scene(body=exdex.Body.box(0.1, (0.03, 0.5, 0.03)),
                       grasp=exdex.Grasp(mu=0.5, grip_force=exdex.GripSchedule((0.0, 2.0), (1.5, 0.9))),
                       motion=exdex.Rest(), gripper_rotation=paper.fig3_scene().gripper_rotation)


def test_cli_plan_writes_poses_and_reports_unreachable(tmp_path, capsys):
    from exdex import cli
    out = tmp_path / "plan"
    assert cli.main(["plan", "--out", str(out), "--target", "slip=-0.01"]) == 0
    text = capsys.readouterr().out
    assert "grip_force" in text and "residual" in text
    data = np.loadtxt(out / "gripper_poses.csv", delimiter=",", skiprows=1)
    assert data.shape[1] == 8
    loaded = exdex.load_scene(out / "planned_scene.toml")
    assert abs(closed_slip(loaded) - (-0.01)) <= 1e-6 + 1e-9
    assert cli.main(["plan", "--out", str(out), "--target", "slip=-0.9"]) == 1
    assert "reachable" in capsys.readouterr().out
    # rest_by: 0.7 s admits the 10 mm plan (closed-form rest time below it), 0.5 s does not
    assert cli.main(["plan", "--out", str(out), "--target", "slip=-0.01", "--rest-by", "0.7"]) == 0
    assert "at rest relative to the gripper by 0.7 s" in capsys.readouterr().out
    assert paper.closed_form(exdex.load_scene(out / "planned_scene.toml")).rest_time <= 0.7
    assert cli.main(["plan", "--out", str(out), "--target", "slip=-0.01", "--rest-by", "0.5"]) == 1
    assert "at rest by 0.5 s" in capsys.readouterr().out


def test_cli_plans_a_pose_and_writes_the_sequence_poses(tmp_path, capsys):
    """exdex plan --pose on a planar scene file: the steps, the residuals
    within tol, the sequence's gripper poses (every step a round trip: the
    gripper is back at its start pose at the end of each step) and one scene
    file per step, each re-simulated in turn to the target."""
    from exdex import cli
    path = tmp_path / "box.toml"
    exdex.save_scene(planar_box(), path)
    out = tmp_path / "plan"
    assert cli.main(["plan", "--scene", str(path), "--pose", "x=0.0,y=-0.004", "--out", str(out),
                     "--uncertain", "mu=0.48:0.52"]) == 0
    text = capsys.readouterr().out
    assert "plan: slide_y(" in text and "band of y (sampled)" in text
    data = np.loadtxt(out / "gripper_poses.csv", delimiter=",", skiprows=1)
    assert data.shape[1] == 8 and np.all(np.diff(data[:, 0]) > 0)
    np.testing.assert_allclose(data[-1, 1:], data[0, 1:], atol=1e-12)
    step = exdex.load_scene(out / "step_1.toml")
    t = step.motion.end_time + 0.3
    r = exdex.simulate(step, t, t, method="event", rtol=1e-12, atol=1e-14)
    assert abs(r.q[-1, 1] - r.q[0, 1] - (-0.004)) <= TOL[0]
    with pytest.raises(SystemExit, match="--pose needs a planar scene"):
        cli.main(["plan", "--case", "fig3", "--pose", "x=0.01", "--out", str(out)])


@pytest.mark.filterwarnings("ignore:the planned object is still moving")
def test_cli_plan_honours_the_simulate_table_and_prints_units(tmp_path, capsys):
    path = tmp_path / "ramp.toml"
    exdex.save_scene(ramp_scene(), path, simulate={"t_end": 2.5, "method": "analytic"})
    out = tmp_path / "plan"
    args = ["plan", "--scene", str(path), "--target", "slip=-0.05", "--vary", "grip_force=0.95:1.2",
            "--out", str(out)]
    assert cli.main(args) == 0
    text = capsys.readouterr().out
    assert "simulated to t_end = 2.5 s" in text
    # the grip force of a schedule is its scale
    line = [ln for ln in text.splitlines() if ln.startswith("plan:")][0]
    assert line.endswith(" x schedule") and " N" not in line
    k = float(line.split("=")[1].split()[0])
    assert "peak acceleration 0 m/s^2, peak speed 0 m/s, stroke 0 m, duration 0 s" in text
    assert "tol 1e-06 m" in text and "in [0.95, 1.2] x schedule" in text
    # independent: the planned scene simulated to the file's 2.5 s slides 50 mm;
    # the scale reproduces the closed form there (capacity k (1.5 - 0.3 t))
    planned = exdex.load_scene(out / "planned_scene.toml")
    res = exdex.simulate(planned, 2.5, 1e-3, method="analytic")
    assert res.q[-1, 0] == pytest.approx(-0.05, abs=1e-6)
    ts = (1.5 - 0.1 * G / k) / 0.3
    tau, a3 = 2.0 - ts, -(0.1 * G - 0.9 * k) / 0.1
    s_end = -k * 0.3 / 0.6 * tau ** 3 - k * 0.3 / 0.2 * tau ** 2 * 0.5 + 0.5 * a3 * 0.25
    assert s_end == pytest.approx(-0.05, abs=1e-6)
    # the command line overrides the file
    assert cli.main(args + ["--t-end", "3.0"]) == 0
    assert "simulated to t_end = 3 s" in capsys.readouterr().out


def test_scene_format_option_reads_a_file_of_another_extension(tmp_path, capsys):
    path = tmp_path / "ramp.scene"
    exdex.save_scene(ramp_scene(), path, format="toml", simulate={"t_end": 1.0})
    out = tmp_path / "o"
    with pytest.raises(SystemExit, match="--scene-format"):
        cli.main(["run", str(path), "--no-progress", "--out", str(out)])
    assert cli.main(["run", str(path), "--scene-format", "toml", "--no-progress", "--out", str(out)]) == 0
    assert exdex.Result.load(out / "ramp.npz").t[-1] == 1.0
    assert cli.main(["plan", "--scene", str(path), "--scene-format", "toml", "--target", "slip=-0.001",
                     "--vary", "grip_force=1.0:1.5", "--out", str(out)]) == 1   # held to the 1 s of the file
    assert "reachable [0, 0] m" in capsys.readouterr().out

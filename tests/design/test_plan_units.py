"""Plans say what they mean: units on every printed or plotted quantity, the
scene file's simulate table, plain quantity names, the slip at the contact.

References: the closed form of the grip ramp (a linear capacity against the
weight, tests/scenarios/test_end_time.py's derivation), direct simulations of the
planned scenes, and the pad geometry for the contact slip (the contact
region of a pad wholly inside the face is the pad itself, fixed on the
fingers, so its travel over the object follows from the object's pose
alone)."""
import math
import warnings

import numpy as np
import pytest

import exdex
from exdex import cli, paper



def ramp_scene():
    """The gripper at rest, the grip force falling from 1.5 N to 0.9 N over
    2 s (capacity below the 0.1 kg bar's weight from 1.73 s on)."""
    return exdex.Scene(body=exdex.Body.box(0.1, (0.03, 0.5, 0.03)),
                       grasp=exdex.Grasp(mu=0.5, grip_force=exdex.GripSchedule((0.0, 2.0), (1.5, 0.9))),
                       motion=exdex.Rest(), gripper_rotation=paper.fig3_scene().gripper_rotation)


def test_plan_labels_and_repr_carry_units():
    pytest.importorskip("matplotlib")
    import matplotlib
    matplotlib.use("Agg")
    with pytest.warns(UserWarning, match=r"still moving at t_end = 3 s \(relative speed [0-9.e-]+ m/s\)"):
        p = exdex.plan.solve(ramp_scene(), {"slip": -0.05}, {"grip_force": (1.0, 1.09)})
    ax = p.plot()
    assert ax.get_xlabel() == "grip_force [x schedule]" and ax.get_ylabel() == "slip [m]"
    assert p.unit == "x schedule" and " x schedule: slip " in repr(p) and "target -0.05 m" in repr(p)
    q = exdex.plan.solve(paper.fig3_scene(), {"slip": -0.01}, {"grip_force": (1.0, 3.0)}, t_end=1.5)
    assert q.plot().get_xlabel() == "grip_force [N]"
    assert exdex.plan.parameter_unit(paper.fig6_scene(), "amplitude") == "rad"
    assert exdex.plan.parameter_unit(paper.fig3_scene(), "mu") == ""
    assert exdex.plan.peak_units(paper.fig6_scene().motion)["speed"] == "rad/s"


def test_sequence_plan_repr_names_the_step_units():
    sc = exdex.replace(paper.fig3_scene(), dof="planar")
    prims = exdex.sequence.primitives(sc)
    steps = (("slide_x", 0.01), ("pivot", 0.2))
    p = exdex.sequence.SequencePlan(
        steps=steps, scenes=tuple(exdex.replace(sc, motion=prims[n].make(v)) for n, v in steps),
        final=(0.01, 0.0, 0.2), targets={"x": 0.01, "rotation": 0.2}, achieved={"x": 0.01, "rotation": 0.2},
        residuals={"x": 0.0, "rotation": 0.0}, tol={"x": 1e-4, "rotation": 1e-3}, cost=0.0, tried=())
    r = repr(p)
    assert "slide_x(0.01 m) -> pivot(0.2 rad)" in r and "x 0.01 m (target 0.01 m)" in r
    assert "rotation 0.2 rad (target 0.2 rad)" in r


def test_plain_quantity_names_and_the_old_one():
    sc = paper.fig3_scene()
    a = exdex.plan.solve(sc, {"com_slide": -0.01}, {"grip_force": (1.0, 3.0)}, t_end=1.5)
    b = exdex.plan.solve(sc, {"slip": -0.01}, {"grip_force": (1.0, 3.0)}, t_end=1.5)
    assert a.value == b.value and a.quantity == "com_slide" and b.quantity == "slip"
    helptext = cli.command_parser("plan", __import__("exdex.cli.plan", fromlist=["x"])).format_help()
    for name in ("com_slide", "contact_slip", "rotation", "slip"):
        assert name in helptext


def pad_scene(F=3.0):
    """A planar 8 cm box, a 2 cm square pad on the fingers 15 mm beside the
    centre of mass: the fig3 motion turns and slides the box."""
    f3 = paper.fig3_scene()
    return exdex.replace(f3, dof="planar", body=exdex.Body.box(0.1, (0.08, 0.08, 0.03)),
                         grasp=exdex.replace(f3.grasp, grip_force=F,
                                             pad=exdex.Pad.rectangle(0.02, 0.02, center=(0.015, 0.0))))


def test_contact_slip_plan_against_the_trajectory(capsys):
    sc = pad_scene()
    p = exdex.plan.solve(sc, {"contact_slip": 0.002}, {"grip_force": (2.5, 4.0)}, t_end=1.5, tol=1e-8)
    res = exdex.simulate(p.scene, 1.5, 1e-3, method="event", rtol=1e-10, atol=1e-12)
    x, y, th = res.q[-1]
    x0, y0, th0 = res.q[0]
    pc = np.array(sc.grasp.pad.center)
    # the pad stays wholly inside the face (its farthest corner from the centre
    # of mass within the face's inscribed circle), so the region is the pad:
    # its centre in the object frame is R(-theta) (pc - r)
    assert np.hypot(*(pc - [x, y])) + math.hypot(0.01, 0.01) < 0.04
    rot = lambda a, v: np.array([math.cos(a) * v[0] + math.sin(a) * v[1], -math.sin(a) * v[0] + math.cos(a) * v[1]])  # noqa: E731
    expected = np.linalg.norm(rot(th, pc - [x, y]) - rot(th0, pc - [x0, y0]))
    assert expected == pytest.approx(0.002, abs=1e-7)
    assert p.outcomes["contact_slip"] == pytest.approx(expected, abs=1e-7)
    # the other quantities of the same run: the centre of mass moved farther,
    # and it turned
    assert p.outcomes["com_slide"] == pytest.approx(math.hypot(x - x0, y - y0), abs=1e-7)
    assert p.outcomes["rotation"] == pytest.approx(th - th0, abs=1e-7)
    assert p.outcomes["com_slide"] > 2 * p.outcomes["contact_slip"]

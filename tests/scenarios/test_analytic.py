"""The analytic method: the exact phase-by-phase solution of 1-DoF scenes
with a piecewise-constant drive, checked against the closed form of the
paper's Fig. 3 (derived in exdex.paper.fig3_grip_force), against the
independent event method (GSL rk8pd at tight tolerances, located switches)
on random eligible scenes, and for its independence of the output grid.

twin: csrc/tests/test_analytic.c (the same subject on the C API)
"""
import dataclasses
import math

import numpy as np
import pytest

import exdex
from exdex import paper
from exdex.simulate import resolve_method


def fig3_slip_closed_form(grip_force):
    """Final slip of Fig. 3 (down first): s = u tau^2 D / (2 (D - u)),
    u = g + |a_L| - c, D = a_H + |a_L|, tau = (2 - 2 beta) T (stick, slip,
    decelerate, stick; exdex.paper.fig3_grip_force's docstring)."""
    a_h, a_l = paper.eq7_accelerations(0.1, 0.5, 0.9)
    a_l = abs(a_l)
    c = paper.MU * paper.FINGERS * grip_force / paper.MASS
    u = paper.G + a_l - c
    D = a_h + a_l
    tau = (2 - 2 * 0.9) * 0.5
    return -u * tau**2 * D / (2 * (D - u))


@pytest.mark.parametrize("grip", [1.3, 1.50514, 1.7])
def test_fig3_closed_form(grip):
    r = exdex.simulate(paper.fig3_scene(grip_force=grip), t_end=1.5, dt=1.5, method="analytic")
    assert r.q[-1, 0] - r.q[0, 0] == pytest.approx(fig3_slip_closed_form(grip), rel=1e-14, abs=1e-17)
    assert r.stick[-1] and r.v[-1, 0] == 0.0


def random_eligible_scene(rng):
    """A translation scene whose gripper translates (Eq. 7, trapezoid with
    ramps, or rest) along a random axis under random gravity, or a rotation
    scene about the centre of mass whose gripper turns about the plate
    normal; random grip (0.2x to 4x the drive), friction, initial velocity."""
    kind = rng.choice(["asym", "trap", "rest"])
    rotation = rng.random() < 0.4
    mass = float(10 ** rng.uniform(-2, 1))
    g = tuple(rng.normal(0, 6, 3))
    R = exdex.scene.DEFAULT_GRIPPER_ROTATION
    n = np.array(R)[:, 2]
    if rotation:
        axis = tuple(n * rng.choice([-1.0, 1.0]))
        amp = float(rng.uniform(0.2, 2.0)) * rng.choice([-1, 1])
    else:
        axis = tuple(rng.normal(size=3))
        amp = float(rng.uniform(0.01, 0.3)) * rng.choice([-1, 1])
    T = float(rng.uniform(0.2, 1.0))
    if kind == "asym":
        motion = exdex.AsymmetricProfile(amp, T, float(rng.uniform(0.1, 0.9)), axis=axis, rotation=rotation,
                                         center=tuple(rng.normal(0, 0.1, 3)))
    elif kind == "trap":
        motion = exdex.TrapezoidalProfile(amp, T, abs(amp) / T * float(rng.uniform(1.05, 1.95)), axis=axis,
                                          rotation=rotation, center=tuple(rng.normal(0, 0.1, 3)))
    else:
        motion = exdex.Rest()
    size = tuple(rng.uniform(0.02, 0.1, 3))
    izz = mass * (size[0] ** 2 + size[1] ** 2) / 12
    e_r = float(rng.uniform(0.003, 0.02))
    if rotation:
        drive = abs(amp) * 8 / T**2 * izz / e_r
        dof, patch = "rotation", exdex.Patch(e_r=e_r)
    else:
        drive = mass * (np.linalg.norm(g) + abs(amp) * 8 / T**2)
        dof, patch = "translation", exdex.Patch(e_r=e_r)
    mu = float(rng.uniform(0.2, 1.0))
    grip = float(rng.uniform(0.2, 4.0)) * drive / (2 * mu * (e_r if rotation else 1.0))
    v0 = (0.0, 0.0, 0.0)
    if rng.random() < 0.3:
        v0 = (0.0, 0.0, float(rng.normal(0, 2))) if rotation else (0.0, float(rng.normal(0, 0.3)), 0.0)
    scene = exdex.Scene(body=exdex.Body.box(mass, size), grasp=exdex.Grasp(mu=mu, grip_force=grip, patch=patch),
                        motion=motion, dof=dof, gravity=g, v0=v0)
    t_end = max(motion.end_time, 0.3) * float(rng.uniform(0.5, 1.5))
    return scene, t_end


@pytest.mark.warns_by_design("impact", "pad", "outline", "solver", "jump", "plausibility")  # random masses, sizes
def test_agrees_with_event_method_on_random_scenes():
    """200 random eligible scenes: the analytic final state agrees with the
    event method at rtol 1e-12 to 1e-12 of the scene's own scale (the event
    method integrates the same piecewise quadratics with rk8pd, exact for
    polynomials of that degree, and locates its switches to 1e-13 s; seen:
    at most 3e-16), and the stick flags agree."""
    rng = np.random.default_rng(20261124)
    worst = 0.0
    for _ in range(200):
        scene, t_end = random_eligible_scene(rng)
        assert resolve_method(scene, "auto") == "analytic"
        a = exdex.simulate(scene, t_end, t_end / 4, method="analytic")
        e = exdex.simulate(scene, t_end, t_end / 4, method="event", rtol=1e-12, atol=1e-15)
        scale = max(np.max(np.abs(e.q - e.q[0])), np.max(np.abs(e.v)) * t_end, 1e-12)
        err = float(np.max(np.abs(a.q - e.q)) / scale)
        worst = max(worst, err)
        assert err <= 1e-12, (scene, t_end, err)
        vs = max(np.max(np.abs(e.v)), 1e-12)
        assert np.max(np.abs(a.v - e.v)) <= 1e-9 * vs
        assert np.array_equal(a.stick, e.stick)


@pytest.mark.warns_by_design("outline", "plausibility")  # random masses and sizes
def test_output_grid_does_not_change_the_answer():
    """dt only sets the output grid: the final state with one output interval
    equals the one with 1000 exactly (samples are evaluated from the start of
    their segment; the segments are the same for any grid)."""
    rng = np.random.default_rng(7)
    for _ in range(50):
        scene, t_end = random_eligible_scene(rng)
        a = exdex.simulate(scene, t_end, t_end, method="analytic")
        b = exdex.simulate(scene, t_end, t_end / 1000, method="analytic")
        assert a.q[-1, 0] == b.q[-1, 0] and a.v[-1, 0] == b.v[-1, 0]
        assert a.stick[-1] == b.stick[-1]


def test_auto_and_errors():
    assert resolve_method(paper.fig3_scene(), "auto") == "analytic"
    assert resolve_method(paper.fig6_scene(), "auto") in ("analytic", "event")
    planar = paper.fig3_scene(dof="planar")
    assert resolve_method(planar, "auto") == "event"
    with pytest.raises(ValueError, match="analytic.*planar"):
        exdex.simulate(planar, 0.1, 0.1, method="analytic")
    fig4 = paper.fig4_scene()
    with pytest.raises(ValueError, match="stops"):
        exdex.simulate(fig4, 0.1, 0.1, method="analytic")
    off = dataclasses.replace(paper.fig6_scene(), grasp=dataclasses.replace(
        paper.fig6_scene().grasp, patch=exdex.Patch(e_r=0.01, center=(0.01, 0.0))))
    with pytest.raises(ValueError, match="pendulum"):
        exdex.simulate(off, 0.1, 0.1, method="analytic")
    r = exdex.simulate(paper.fig3_scene(), 1.5, 0.5, method="auto")
    assert r.method == "analytic"


@pytest.mark.warns_by_design("outline")
def test_batch_matches_serial_bit_for_bit():
    scene = paper.fig3_scene()
    F = np.linspace(1.2, 2.0, 33)
    b = exdex.simulate_batch(scene, 1.5, 0.1, method="analytic", grip_force=F, threads=2)
    for i in (0, 7, 32):
        r = exdex.simulate(dataclasses.replace(scene, grasp=dataclasses.replace(scene.grasp, grip_force=F[i])),
                           1.5, 0.1, method="analytic")
        assert np.array_equal(b.q[i], r.q) and np.array_equal(b.wrench[i], r.wrench)
    ba = exdex.simulate_batch(scene, 1.5, 1.5, method="auto", grip_force=F, record="final")
    assert ba.method == "analytic"

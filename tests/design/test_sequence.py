"""exdex.sequence: planar pose targets by sequences of motion primitives.

References independent of the search: the step-by-step re-simulation of the
returned scenes with exdex.simulate (event method, rtol 1e-12); for an
inertial slide along the plate's y axis with the pad at the centre of mass,
the closed form of the 1-DoF translation scene (exdex.paper.closed_form:
no rotation and no sideways force, so the planar motion is the 1-DoF one);
for a push against a stop, the geometry (the object's lowest point lands on
the stop: displacement = stroke - gap, whatever mu once the grasp holds the
weight).
"""
import math
import warnings

import numpy as np
import pytest

import exdex
from exdex import paper, plan, sequence
from scenes import planar_box

TOL = (1e-4, math.radians(0.1))


def resimulate(p):
    """Chain the plan's scenes with exdex.simulate at rtol 1e-12: returns the
    final pose, and checks each scene starts where the previous one ended."""
    q = np.array(p.scenes[0].q0)
    for sc in p.scenes:
        np.testing.assert_allclose(sc.q0, q, atol=1e-9)
        t = sc.motion.end_time + 0.3
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", exdex.PhysicsWarning)
            r = exdex.simulate(sc, t, t, method="event", rtol=1e-12, atol=1e-14)
        assert r.stick[-1]
        q = r.q[-1]
    return np.asarray(q) - np.asarray(p.scenes[0].q0)


def test_pose_target_by_a_sequence_meets_tolerances_when_resimulated():
    """Target: the pose a slide along x (30 mm) then a pivot (0.3 rad) leave
    (about -2.1 mm, -4.3 mm, -3.1 deg).
    The plan, re-simulated step by step by the event method at rtol 1e-12,
    is within 0.1 mm and 0.1 deg of it."""
    sc = planar_box()
    P = sequence.primitives(sc)
    q = sequence._run_sequence(sc, [P["slide_x"], P["pivot"]], [0.03, 0.3], 0.3, 1e-12, 1e-14)
    target = {"x": q[0], "y": q[1], "rotation": q[2]}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", exdex.PhysicsWarning)
        p = sequence.solve(sc, target, tol=TOL)
    assert p.meets_target
    d = resimulate(p)
    assert abs(d[0] - target["x"]) <= TOL[0] and abs(d[1] - target["y"]) <= TOL[0]
    assert abs(d[2] - target["rotation"]) <= TOL[1]
    assert any(n == "pivot" for n, _ in p.steps) and len(p.steps) <= 3


def test_one_slide_matches_the_1dof_closed_form():
    """x = 0, y = -4 mm: one inertial slide along the plate's y axis (a
    slide along x would move x too); the planar result equals the 1-DoF
    translation closed form of the same motion."""
    sc = planar_box()
    p = sequence.solve(sc, {"x": 0.0, "y": -0.004}, tol=TOL, max_length=2)
    assert [n for n, _ in p.steps] == ["slide_y"]
    amp = p.steps[0][1]
    tr = exdex.replace(sc, dof="translation", motion=sequence.primitives(sc)["slide_y"].make(amp))
    assert abs(paper.closed_form(tr).final - (-0.004)) <= TOL[0]
    assert abs(resimulate(p)[1] - (-0.004)) <= TOL[0]


@pytest.mark.warns_by_design("impact")
def test_push_against_a_stop_is_set_by_the_stop_not_by_mu():
    """A stop 10 mm below the box: y = +8 mm needs a push (slides only move
    the object down). A slow push of gap + 8 mm is the gentlest way. With a
    capacity of 1.5 m g at mu 0.5 (1.2 m g at mu 0.4: the grasp holds the
    weight and the slow return) the outcome is the same for mu 0.5 +- 20 %:
    the sampled band has zero width. The pad is 20 x 20 mm, so that the 8 mm
    slide stays on it (a sequence that slides the object off its pad is not
    accepted)."""
    sc = planar_box(stops=(exdex.Stop(point=(0.0, 0.0, -0.025), normal=(0.0, 0.0, 1.0)),), capacity=1.5, pad=0.02)
    p = sequence.solve(sc, {"y": 0.008}, tol=TOL, max_length=2)
    assert [n for n, _ in p.steps] == ["push_0"]
    mo = sequence.primitives(sc)[p.steps[0][0]].make(p.steps[0][1])
    stroke = -float(np.dot(mo.axis, (0.0, 0.0, 1.0))) * mo.amplitude   # towards the stop
    assert stroke == pytest.approx(0.018, abs=TOL[0])
    assert abs(resimulate(p)[1] - 0.008) <= TOL[0]
    b = sequence.band(p, {"mu": (0.4, 0.6)}, n=5)
    lo, hi = b["y"]
    assert hi - lo <= 1e-9 and abs(lo - p.achieved["y"]) <= 1e-9


def test_unreachable_pose_names_the_closest_sequence():
    """The pivot turns the object by at most about 0.3 rad here (scan of
    up to 1 rad): 2.5 rad is out of reach."""
    with pytest.raises(plan.UnreachableTargetError, match="no sequence of up to 2 .*closest solved"):
        sequence.solve(planar_box(), {"rotation": 2.5}, tol=TOL, max_length=2, n_polish=1, max_nfev=5)


@pytest.mark.parametrize("kw, match", [
    (dict(target={"slip": 0.01}), "target quantity must be one of"),
    (dict(target={"x": math.nan}), "target\\['x'\\]"),
    (dict(target={"x": 0.01}, max_length=7), "max_length"),
    (dict(target={"x": 0.01}, tol=(0.0, 0.1)), "tol\\[0\\]"),
    (dict(target={"x": 0.01}, n_scan=2), "n_scan"),
])
def test_bad_input_is_named(kw, match):
    with pytest.raises((ValueError, TypeError), match=match):
        sequence.solve(planar_box(), **kw)
    with pytest.raises(ValueError, match="dof must be 'planar'"):
        sequence.primitives(paper.fig3_scene())


def test_plan_solve_without_vary_plans_a_pose_by_a_sequence():
    sc = planar_box()
    p = plan.solve(sc, {"x": 0.0, "y": -0.004})
    assert isinstance(p, sequence.SequencePlan) and p.meets_target
    assert abs(resimulate(p)[1] - (-0.004)) <= TOL[0]
    with pytest.raises(ValueError, match="vary must be a dict"):
        plan.solve(paper.fig3_scene(), {"slip": -0.01})


def test_sequence_with_the_exact_surface_on_pads_meets_tolerances_when_resimulated():
    """The pose target of the first test with pads on the fingers (a 10 mm
    pad at the centre of mass, inside the face) and limit_surface="exact":
    the sequence found, re-simulated step by step by the event method at
    rtol 1e-12 (the exact surface of pad & face), is within 0.1 mm and 0.1
    deg of the target; the target is one the ellipsoid reaches differently
    (its pose from the same primitives differs by more than the tolerance)."""
    base = planar_box()
    sc = exdex.replace(base, grasp=exdex.replace(base.grasp, pad=exdex.Pad.rectangle(0.01, 0.01),
                                                 limit_surface="exact"))
    P = sequence.primitives(sc)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", exdex.PhysicsWarning)
        q = sequence._run_sequence(sc, [P["slide_x"], P["pivot"]], [0.03, 0.3], 0.3, 1e-12, 1e-14)
        qe = sequence._run_sequence(exdex.replace(sc, grasp=exdex.replace(sc.grasp, limit_surface="ellipsoid")),
                                    [P["slide_x"], P["pivot"]], [0.03, 0.3], 0.3, 1e-12, 1e-14)
        assert max(abs(q[0] - qe[0]), abs(q[1] - qe[1])) > TOL[0] or abs(q[2] - qe[2]) > TOL[1]
        target = {"x": q[0], "y": q[1], "rotation": q[2]}
        p = sequence.solve(sc, target, tol=TOL)
    assert p.meets_target
    d = resimulate(p)
    assert abs(d[0] - target["x"]) <= TOL[0] and abs(d[1] - target["y"]) <= TOL[0]
    assert abs(d[2] - target["rotation"]) <= TOL[1]

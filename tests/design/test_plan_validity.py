"""The planner accepts only runs that keep the object in the grasp.

An 8 cm box held by a 2 cm square pad slides along its 8 cm side: a slide of
more than 40 mm (half the side, closed form) takes the pad centre off the
box, and with pads on the fingers the contact region vanishes at 50 mm (half
the side plus half the pad). Before the check, the scan of the grip force
from 0 to 3 N over 3 s "reached" [-44.1, 0] m (a free fall) and planned a
200 mm slide; now those runs are not reachable and the reachable interval
ends where the valid runs end."""
import math
import warnings

import numpy as np
import pytest

import exdex
from exdex import paper

BOX = 0.08
PAD = 0.02


def box_scene(**kw):
    f3 = paper.fig3_scene()
    grasp = exdex.replace(f3.grasp, patch=exdex.Patch.rectangle(PAD, PAD))
    return exdex.replace(f3, body=exdex.Body.box(0.1, (BOX, BOX, BOX)), grasp=grasp, **kw)


def test_a_slide_off_the_box_is_not_reachable():
    sc = box_scene()
    with pytest.raises(exdex.UnreachableTargetError) as ei:
        exdex.plan.solve(sc, {"slip": -0.2}, {"grip_force": (0.0, 3.0)}, t_end=3.0)
    e = ei.value
    assert isinstance(e, ValueError) and isinstance(e, exdex.plan.UnreachableTargetError)
    # the valid runs end where the pad centre reaches the box's edge: -BOX / 2
    assert e.low == pytest.approx(-BOX / 2, abs=1e-7) and e.high == 0.0
    assert e.reachable == (e.low, e.high)
    assert 0 < e.invalid < e.scanned
    msg = str(e)
    assert "reachable [-0.04, 0] m" in msg and "leave the grasp" in msg and "outline" in msg
    # what the invalid runs would have "reached" is named, not offered
    assert "-44.1" in msg
    # inside the valid interval the plan is made, and its run stays on the box
    p = exdex.plan.solve(sc, {"slip": -0.039}, {"grip_force": (0.0, 3.0)}, t_end=3.0, tol=1e-8)
    assert p.reachable[0] == pytest.approx(-BOX / 2, abs=1e-7)
    assert abs(p.residual) <= 1e-8
    with warnings.catch_warnings():
        warnings.simplefilter("error", exdex.PhysicsWarning)
        res = exdex.simulate(p.scene, 3.0, 1e-3, method="analytic")
    assert res.q[-1, 0] == pytest.approx(-0.039, abs=1e-7)


def test_runs_whose_pads_lose_the_object_are_not_reachable():
    """Planar box with a pad on the fingers: the region vanishes once the box
    has slid BOX / 2 + PAD / 2 = 50 mm (closed form of the rectangles'
    overlap); the core stops such runs (stats['grasp_lost_t'])."""
    sc = box_scene(dof="planar")
    sc = exdex.replace(sc, grasp=exdex.replace(sc.grasp, pad=exdex.Pad.rectangle(PAD, PAD)))
    b = exdex.simulate_batch(sc, 1.0, 1.0, record="final", method="event", grip_force=np.array([0.2, 1.5]),
                             warn=False)
    assert np.isfinite(b.stats["grasp_lost_t"][0]) and np.isnan(b.stats["grasp_lost_t"][1])
    with pytest.raises(exdex.UnreachableTargetError) as ei:
        exdex.plan.solve(sc, {"com_slide": 0.2}, {"grip_force": (0.2, 3.0)}, t_end=1.0, n_scan=17)
    e = ei.value
    # the loss is seen at the check samples (every 10 ms): the edge to within
    # the slide over one of them
    assert e.high == pytest.approx((BOX + PAD) / 2, abs=1e-4) and e.high <= (BOX + PAD) / 2
    assert "the pads lost the object" in str(e)


def test_no_valid_run_at_all_says_why():
    sc = box_scene()
    with pytest.raises(exdex.UnreachableTargetError) as ei:
        exdex.plan.solve(sc, {"slip": -0.01}, {"grip_force": (0.0, 0.5)}, t_end=3.0)
    assert ei.value.invalid == ei.value.scanned > 0
    assert math.isnan(ei.value.low) and "keeps the object in the grasp" in str(ei.value)


def test_a_sequence_that_leaves_the_pad_is_not_accepted():
    """A planar 8 cm box on a 2 cm patch: 5 mm down the plate is one slide
    within the pad; 45 mm needs the object to slide across the pad (beyond
    its 10 mm half-side), which the model does not describe: such a sequence
    was returned with PhysicsWarnings, now it is refused."""
    f3 = paper.fig3_scene()
    sc = exdex.replace(f3, dof="planar", body=exdex.Body.box(0.1, (BOX, BOX, 0.03)),
                       grasp=exdex.replace(f3.grasp, grip_force=1.0, patch=exdex.Patch.rectangle(PAD, PAD)))
    with warnings.catch_warnings():
        warnings.simplefilter("error", exdex.PhysicsWarning)
        p = exdex.sequence.solve(sc, {"y": -0.005})
    assert abs(p.residuals["y"]) <= p.tol["y"]
    with pytest.raises(exdex.UnreachableTargetError, match="leave the grasp"):
        exdex.sequence.solve(sc, {"y": -0.045})

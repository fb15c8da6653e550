"""The event method after a change of state between two ODE steps.

GSL's evolve object starts a step from the previous step's end derivative
while its step count is > 0; the hybrid loop changes the state between steps
(contact projection, velocity jumps, events), and each change must restart
the stepper, else the next step starts from the derivative of a state the
run has left. On a planar log between two stops (zoo seed 9: a rotating
gripper, 2 stops, dozens of impacts and contact-set changes) a stale
derivative after the contact projection lets the log sink into a stop by
1e-6 L at rtol 1e-11, ten times the penetration tolerance (1e-7 L, the
threshold above which a step's penetration counts a warning), with hundreds
of warnings. The event method's contract: the stops are kept to rounding and
event location (|gap rate| x 3e-12 T, and decisions project the positions
back onto every stop row), far below 1e-7 L at every tolerance and output
grid.
"""
import pytest

import zoo

PEN_REL = 1e-7  # the penetration tolerance, x L


@pytest.mark.parametrize("rtol", [1e-9, 1e-10, 1e-11])
@pytest.mark.parametrize("n_out", [8, 64])
def test_planar_log_between_two_stops_stays_out(rtol, n_out):
    zs = zoo.zoo_scene(9)
    assert len(zs.scene.stops) == 2
    with pytest.warns(Warning):  # the scene's grasp warnings (pads, impacts)
        r = zoo.run(zs, "event", rtol=rtol, n_out=n_out)
    assert r.stats["warnings"] == 0, r.stats
    assert r.stats["min_gap"] / zs.L > -PEN_REL, r.stats["min_gap"] / zs.L

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
grid. Projections onto some rows only (the penetrating ones at an event, the
contact set after a step) rotate the log about one corner and push the
neighbouring corner into its stop by as much as they remove (~1e-8 L here, at
every rtol: the final pose then depends on where the steps end); onto every
row, the gap stays within event location: with gap rates up to a few L / T,
a few times 3e-12 L, bounded here by LOCATE_REL = 1e-11 L.
"""
import pytest

import zoo

PEN_REL = 1e-7  # the penetration tolerance, x L
LOCATE_REL = 1e-11  # event location, x L (module docstring)


@pytest.mark.parametrize("rtol", [1e-9, 1e-10, 1e-11])
@pytest.mark.parametrize("n_out", [8, 64])
def test_planar_log_between_two_stops_stays_out(rtol, n_out):
    zs = zoo.zoo_scene(9)
    assert len(zs.scene.stops) == 2
    with pytest.warns(Warning):  # the scene's grasp warnings (pads, impacts)
        r = zoo.run(zs, "event", rtol=rtol, n_out=n_out)
    assert r.stats["warnings"] == 0, r.stats
    assert r.stats["min_gap"] / zs.L > -PEN_REL, r.stats["min_gap"] / zs.L
    assert r.stats["min_gap"] / zs.L > -LOCATE_REL, r.stats["min_gap"] / zs.L


def test_regularised_frictional_stop_with_a_grip_schedule_stays_out():
    """The regularised method on a 1-DoF slide against one frictional stop
    (Stop.mu 0.97) under a linear grip schedule (tests/test_zoo_inputs.py
    input scene 123): in contact each step ends with the projection onto the
    stop (project_contact), so every following step must restart from the
    projected state's derivative. From a stale one the run sinks 7.4e-5 L
    into the stop at rtol 1e-9 with 26 soft problems from t = 0.586 s; the
    contract is the stop kept to rounding and event location, as above."""
    import test_zoo_inputs

    zs = test_zoo_inputs.input_scene(123).zs
    sc = zs.scene
    assert sc.dof == "translation" and len(sc.stops) == 1 and sc.stops[0].mu > 0
    with pytest.warns(Warning):  # the scene's grasp warnings (impacts)
        r = zoo.run(zs, "regularised", rtol=zoo.REF_RTOL)
    assert r.stats["warnings"] == 0, r.stats
    assert r.stats["min_gap"] / zs.L > -LOCATE_REL, r.stats["min_gap"] / zs.L

"""exdex.engines.drake (run_drake) against exdex: the paper's cases within
Drake's own error (its stiction tolerance), the frictional incline and box
face, obstacles, a grip schedule and a disc outline (the shared scenes and
derivations: tests/engines/engine_cases.py); point pads against the "corners"
ablation; bad input named."""
import math

import pytest

import exdex
from exdex import engines
import engine_cases as cases
from engine_cases import fig3_scene, fig4_scene, fig6_scene, step_bound, at
from optional_packages import need_drake


# Drake's own error, from its documented friction model: the discrete
# approximations "lagged", "similar" and "tamsi" regularise friction so that
# an in-cone load slips at a speed below the stiction tolerance v_s (at most
# v_s at the edge of the cone, less inside it). So over a motion of duration T
# the creep adds at most v_s * T (translation) or v_s / r * T (rotation, r the
# smallest distance of a contact point from the pivot) to the error of a
# first-order stepper (n_events * h * v_peak, ``step_bound``).

def _drake_tolerance(ref, res, T, radius=None):
    vs = res.stats["stiction_tolerance"]
    creep = vs * T if radius is None else vs / radius * T
    return step_bound(ref, res.stats["dt"]) + creep


@pytest.mark.warns_by_design("outline")
@pytest.mark.parametrize("contact_model", ["point", "hydroelastic"])
@pytest.mark.parametrize("case", ["fig3", "fig4"])
def test_drake_translation_agrees_within_its_own_error(case, contact_model):
    need_drake()
    scene = fig3_scene() if case == "fig3" else fig4_scene()
    end = scene.motion.end_time
    ref = exdex.simulate(scene, end, dt=1e-4)
    res = engines.run_drake(scene, end, contact_model=contact_model)
    tol = _drake_tolerance(ref, res, end)
    diff = abs(at(res, end) - at(ref, end))
    assert diff <= tol, f"drake {contact_model} {case}: |diff| = {diff * 1e3:.4f} mm > {tol * 1e3:.3f} mm"
    assert tol < 0.25 * abs(at(ref, end))


def test_drake_creep_is_bounded_by_its_stiction_tolerance():
    # a static hold (gripper at rest, load m g = 0.65 of the capacity): with
    # Drake's default v_s = 1e-4 m/s the regularised friction creeps, at less
    # than v_s; a smaller v_s creeps less, though not below the floor set by
    # the solver's near-rigid regularisation at a 1 ms step (the hold benchmark
    # measures it), so only the direction is asserted there
    need_drake()
    scene = exdex.replace(fig3_scene(), motion=exdex.Rest())
    rates = {}
    for vs in (1e-4, 1e-6):
        res = engines.run_drake(scene, 0.6, stiction_tolerance=vs)
        rates[vs] = abs(engines.drift_rate(res, 0.3)[0])
    assert 0 < rates[1e-4] <= 1e-4
    assert 0 < rates[1e-6] < rates[1e-4]


def test_drake_point_pads_match_corner_ablation():
    # Drake's point contact has no torsional friction: its pads are spheres at
    # the pad corners, each with a circular cone, i.e. the "corners" model.
    # Tolerance: the step bound of Drake's 1 ms step plus exdex's 1 ms step, and
    # the creep of the corner contacts at radius hypot(a, b) (see above).
    need_drake()
    scene = fig6_scene()
    t_end = scene.motion.end_time + 0.5
    corners = engines.ablation(scene, t_end, dt=1e-3, models=("corners",))["corners"][0]
    res = engines.run_drake(scene, t_end)
    a, b = engines.pad_geometry(scene.grasp.patch)
    tol = step_bound(corners, 1e-3 + 1e-3) + res.stats["stiction_tolerance"] / math.hypot(a, b) * t_end
    diff = abs(res.displacement[-1, 0] - corners.displacement[-1, 0])
    assert diff <= tol, f"|drake - corners| = {diff:.4f} rad > {tol:.4f} rad"


def test_drake_bad_input_is_named():
    need_drake()
    with pytest.raises(ValueError, match="contact_model"):
        engines.run_drake(fig3_scene(), 0.01, contact_model="mesh")
    with pytest.raises(ValueError, match="approximation"):
        engines.run_drake(fig3_scene(), 0.01, approximation="exact")
    with pytest.raises(ValueError, match="stiction_tolerance"):
        engines.run_drake(fig3_scene(), 0.01, stiction_tolerance=0.0)
    with pytest.raises(ValueError, match="stop_contact"):
        engines.run_drake(fig3_scene(), 0.01, stop_contact="mesh")


@pytest.mark.warns_by_design("outline")
@pytest.mark.parametrize("engine", ["drake"])
@pytest.mark.parametrize("case", ["fig3", "fig4"])
def test_translation_agrees_within_contact_model_tolerance(engine, case):
    cases.translation_agrees_within_contact_model_tolerance(engine, case)


@pytest.mark.parametrize("engine", ["drake"])
def test_rotation_gap_direction_matches_corner_ablation(engine):
    cases.rotation_gap_direction_matches_corner_ablation(engine)


_DRAKE_SLIDE = ("Drake's point contact between two boxes is a single point: with friction there the block jams on the "
                "incline (measured a = 0, where Coulomb slides at 0.2095 m/s^2 for any mu_s < tan(alpha) = 0.42; "
                "a 30 mm block jams at mu_s = 0.1 too); its frictionless twin is within 0.002 m/s^2; with "
                "stop_contact='corners' (a point contact per outline vertex) it agrees")


@pytest.mark.parametrize("engine, case", [
    pytest.param("drake", "slide", marks=pytest.mark.xfail(strict=True, reason=_DRAKE_SLIDE)),
    ("drake", "hold"), ("drake corners", "slide"), ("drake corners", "hold")])
def test_frictional_incline_agrees_within_the_engines_own_error(engine, case, obstacle=False):
    kw = dict(stop_contact="corners") if engine == "drake corners" else {}
    cases.frictional_incline_agrees_within_the_engines_own_error(engine, "drake", case, kw, obstacle=obstacle)


@pytest.mark.parametrize("engine, case", [("drake corners", "slide"), ("drake corners", "hold")])
def test_frictional_box_face_agrees_within_the_engines_own_error(engine, case):
    test_frictional_incline_agrees_within_the_engines_own_error(engine, case, obstacle=True)


@pytest.mark.parametrize("engine, shape", [("drake", "rod"), ("drake", "prism")])
@pytest.mark.warns_by_design("impact", "outline")
def test_square_rests_on_an_obstacle_within_the_engines_own_error(engine, shape):
    cases.square_rests_on_an_obstacle_within_the_engines_own_error(engine, shape)


@pytest.mark.warns_by_design("outline")
@pytest.mark.parametrize("engine", ["drake"])
def test_grip_schedule_ramp_down_agrees_within_contact_model_tolerance(engine):
    cases.grip_schedule_ramp_down_agrees_within_contact_model_tolerance(engine)


@pytest.mark.warns_by_design("impact")
@pytest.mark.parametrize("engine", ["drake"])
def test_disc_outline_is_a_cylinder_resting_on_the_floor_at_any_angle(engine):
    cases.disc_outline_is_a_cylinder_resting_on_the_floor_at_any_angle(engine)


def test_drake_corner_spheres_need_a_polygon_outline():
    need_drake()
    sc = exdex.Scene(body=exdex.Body.cylinder(0.1, 0.02, 0.02), grasp=exdex.Grasp(mu=0.5, grip_force=1.0),
                     dof="planar", stops=(exdex.Stop((0, 0, -0.05), (0, 0, 1)),))
    with pytest.raises(ValueError, match="stop_contact='corners' needs a polygon outline"):
        engines.run_drake(sc, 0.01, stop_contact="corners")


"""exdex.PhysicsWarning: results that leave the model's assumptions are
reported through :mod:`warnings`, each naming the time, the quantity and its
size; results inside the model are silent.

Reference times come from closed forms: with mu = 0 (or no grip) nothing
holds the object, so relative to a resting gripper it falls freely, s(t) =
g t^2 / 2 along B's y (the default gripper pose maps B's y to A's z), and it
passes a distance L at t* = sqrt(2 L / g).
"""
import math
import warnings

import numpy as np
import pytest

import exdex

G = 9.81


def _caught(fn):
    with warnings.catch_warnings(record=True) as rec:
        warnings.simplefilter("always")
        out = fn()
    return out, [w.message for w in rec if issubclass(w.category, exdex.PhysicsWarning)]


def _free_fall_scene(patch, body=None, dof="translation"):
    body = body or exdex.Body(mass=0.1)
    return exdex.Scene(body=body, grasp=exdex.Grasp(mu=0.0, grip_force=2.0, patch=patch), dof=dof)


def test_physics_warning_is_exported_user_warning():
    assert issubclass(exdex.PhysicsWarning, UserWarning)
    assert "PhysicsWarning" in exdex.__all__


def _pad(side):
    """A square pad of full side `side` [m] and its half-side (whatever size
    convention Patch.rectangle uses, the disc's radius is unambiguous)."""
    return exdex.Patch.disc(side / 2), side / 2


@pytest.mark.parametrize("method", ["implicit", "event", "regularised", "explicit"])
def test_object_sliding_off_the_pad_warns(method):
    """mu = 0, a 30 mm pad, no body outline: the object falls past the pad's
    15 mm radius at t* = sqrt(2 * 0.015 / g) = 55.3 ms and slides on to about
    11 m by 1.5 s (g t^2 / 2 = 11.04 m)."""
    patch, r = _pad(0.030)
    dt = 1e-3
    res, found = _caught(lambda: exdex.simulate(_free_fall_scene(patch), 1.5, dt, method=method))
    assert res.q[-1, 0] == pytest.approx(-0.5 * G * 1.5 ** 2, rel=2e-3)
    pads = [w for w in found if w.kind == "pad"]
    assert len(pads) == 1
    w = pads[0]
    t_star = math.sqrt(2 * r / G)
    assert abs(w.time - t_star) <= 2 * dt
    # the first sample past the pad's edge, and the slide it reports
    i = int(np.flatnonzero(res.t == w.time)[0])
    slide = np.abs(res.q[:, 0] - res.q[0, 0])
    assert slide[i] > r >= slide[i - 1]
    assert w.value == pytest.approx(slide[i], rel=1e-12)
    assert w.limit == pytest.approx(r)
    text = str(w)
    assert f"t = {w.time:.6g} s" in text and "slid" in text and "15 mm" in text and "11.0" in text


def test_pad_centre_leaving_the_body_outline_warns():
    """A box 20 mm wide and 80 mm tall, the pad at its centre, mu = 0: the
    pad's centre leaves the outline when the box has fallen 40 mm, at
    t* = sqrt(2 * 0.04 / g) = 90.3 ms. In a translation scene with an outline
    the pad size is not the warning."""
    body = exdex.Body.box(0.1, (0.02, 0.08, 0.02))
    patch, _ = _pad(0.010)
    dt = 5e-4
    _, found = _caught(lambda: exdex.simulate(_free_fall_scene(patch, body), 0.3, dt))
    assert [w.kind for w in found] == ["outline"]
    w = found[0]
    t_star = math.sqrt(2 * 0.04 / G)
    assert abs(w.time - t_star) <= 2 * dt
    assert 0 < w.value <= G * (t_star + 2 * dt) * 2 * dt
    assert "outside the body outline" in str(w) and f"t = {w.time:.6g} s" in str(w)


def test_planar_slide_beyond_the_pad_warns_with_an_outline():
    """Planar scene: the centre of pressure fixed on the object is the
    model's assumption, so sliding farther than the pad's size warns even
    while the pad is still on the (large) body."""
    body = exdex.Body.box(0.1, (0.2, 0.4, 0.02))
    patch, r = _pad(0.010)
    dt = 1e-3
    _, found = _caught(lambda: exdex.simulate(_free_fall_scene(patch, body, dof="planar"), 0.1, dt))
    assert [w.kind for w in found] == ["pad"]
    assert abs(found[0].time - math.sqrt(2 * r / G)) <= 2 * dt


def test_model_simulate_and_batch_warn_too():
    patch, r = _pad(0.030)
    sc = _free_fall_scene(patch)
    _, found = _caught(lambda: exdex.Model(sc).simulate(0.2, 1e-3))
    assert [w.kind for w in found] == ["pad"]
    # a batch over mu: mu = 0 and 0.05 slide off (capacity 0.2 N < weight 0.98 N), mu = 1 holds
    _, found = _caught(lambda: exdex.simulate_batch(sc, 0.2, 1e-3, mu=[1.0, 0.0, 0.05]))
    assert len(found) == 1 and found[0].kind == "pad"
    assert "batch index 1" in str(found[0]) and "1 more of 3" in str(found[0])
    # record="final" checks the final pose
    _, found = _caught(lambda: exdex.simulate_batch(sc, 0.2, 1e-3, record="final", mu=[1.0, 0.0]))
    assert len(found) == 1 and "batch index 1" in str(found[0]) and found[0].time == pytest.approx(0.2)
    # warn=False is silent
    _, found = _caught(lambda: exdex.simulate_batch(sc, 0.2, 1e-3, mu=[0.0], warn=False))
    assert found == []


def test_results_inside_the_model_are_silent():
    """Seeded random held scenes (capacity 1.5x to 5x the weight, gripper at
    rest or moving gently): the object sticks, so no PhysicsWarning."""
    rng = np.random.default_rng(5)
    for _ in range(20):
        m = rng.uniform(0.05, 0.5)
        mu = rng.uniform(0.3, 1.0)
        grip = rng.uniform(1.5, 5.0) * m * G / (2 * mu)
        body = exdex.Body.box(m, rng.uniform(0.02, 0.1, 3))
        patch = exdex.Patch.disc(rng.uniform(0.002, 0.01))
        dof = rng.choice(["translation", "planar"])
        sc = exdex.Scene(body=body, grasp=exdex.Grasp(mu=mu, grip_force=grip, patch=patch), dof=dof)
        with warnings.catch_warnings():
            warnings.simplefilter("error", exdex.PhysicsWarning)
            exdex.simulate(sc, 0.2, 1e-3)


def test_solver_warning_count_warns():
    """Two stops pinching a translation scene (one above, one below, both
    touching at t = 0) while gravity pulls: the implicit method keeps the
    lower bound and counts it in stats["warnings"]; that count is reported."""
    body = exdex.Body.box(0.1, (0.02, 0.04, 0.02))
    floor = exdex.Stop(point=(0, 0, -0.02), normal=(0, 0, 1))
    roof = exdex.Stop(point=(0, 0, 0.02), normal=(0, 0, -1))
    sc = exdex.Scene(body=body, grasp=exdex.Grasp(mu=0.0, grip_force=0.0), stops=(floor, roof),
                     motion=exdex.AsymmetricProfile(0.02, 0.3, 0.5, axis=(0, 0, 1)))
    res, found = _caught(lambda: exdex.simulate(sc, 0.6, 1e-3))
    solver = [w for w in found if w.kind == "solver"]
    assert res.stats["warnings"] > 0
    assert len(solver) == 1
    assert str(res.stats["warnings"]) in str(solver[0]) and "stats['warnings']" in str(solver[0])
    assert solver[0].value == res.stats["warnings"]
    # the time of the first counted warning: the end of a step of the run
    tw = res.stats["first_warning_t"]
    assert tw in set(res.t[1:]) and solver[0].time == tw and f"t = {tw:.6g} s" in str(solver[0])


def test_rectangular_pad_uses_its_half_sides():
    """Patch.rectangle(width, height) takes full sides: a 10 mm wide, 40 mm
    tall pad is left (along its height, the fall direction) after 20 mm, at
    t* = sqrt(2 * 0.02 / g) = 63.9 ms."""
    patch = exdex.Patch.rectangle(0.010, 0.040)
    dt = 5e-4
    _, found = _caught(lambda: exdex.simulate(_free_fall_scene(patch), 0.2, dt))
    assert [w.kind for w in found] == ["pad"]
    assert abs(found[0].time - math.sqrt(2 * 0.02 / G)) <= 2 * dt
    assert "5 mm x 20 mm" in str(found[0])


@pytest.mark.parametrize("dof", ["translation", "planar"])
@pytest.mark.parametrize("method", ["implicit", "event", "regularised", "explicit"])
def test_impact_on_a_stop_reports_the_impulse(method, dof):
    """mu = 0: a 20 mm cube falls H = 50 mm onto a floor stop. The plastic,
    frictionless impact takes the impulse m sqrt(2 g H) = 0.0990 N s at
    t = sqrt(2 H / g) = 0.101 s (closed form). The event-driven methods locate
    it exactly; the time-stepping ones within three steps, their impulse
    (the burst of stop impulses, at most four steps) off by at most the
    weight's impulse over those steps plus one, 5 m g dt. stop_force alone shows a spike of about impulse / dt instead."""
    m, H = 0.1, 0.05
    body = exdex.Body.box(m, (0.02, 0.02, 0.02))
    floor = exdex.Stop(point=(0, 0, -0.01 - H), normal=(0, 0, 1))
    sc = exdex.Scene(body=body, grasp=exdex.Grasp(mu=0.0, grip_force=1.0), stops=floor, dof=dof)
    J, t_hit = m * math.sqrt(2 * G * H), math.sqrt(2 * H / G)
    for dt in (1e-3, 1e-4):
        res, found = _caught(lambda: exdex.simulate(sc, 0.2, dt, method=method))
        st = res.stats
        assert st["impacts"] == 1 and st["max_impulse_stop"] == 0
        if method in ("event", "regularised"):
            assert st["max_impulse"] == pytest.approx(J, rel=1e-8)
            assert st["max_impulse_t"] == pytest.approx(t_hit, rel=1e-8)
        else:
            # the burst spans at most IMPACT_STEPS = 4 steps, each also carrying at
            # most the weight's impulse m g dt, plus one step of approach error
            assert abs(st["max_impulse"] - J) <= 5 * m * G * dt
            assert abs(st["max_impulse_t"] - t_hit) <= 3 * dt
        imp = [w for w in found if w.kind == "impact"]
        assert len(imp) == 1 and imp[0].value == st["max_impulse"]
        assert f"{st['max_impulse']:.4g} N s" in str(imp[0]) and "stop 0" in str(imp[0])
        assert f"t = {st['max_impulse_t']:.6g} s" in str(imp[0])


@pytest.mark.parametrize("method", ["implicit", "event", "explicit"])
def test_resting_on_a_stop_is_no_impact(method):
    """A cube resting on a floor from t = 0 and the paper's Fig. 4 (a stop
    that holds the object while the gripper slides past it): the stop carries
    a bounded force, never an impulse."""
    body = exdex.Body.box(0.1, (0.02, 0.02, 0.02))
    sc = exdex.Scene(body=body, grasp=exdex.Grasp(mu=0.0, grip_force=1.0),
                     stops=exdex.Stop(point=(0, 0, -0.01), normal=(0, 0, 1)))
    for scene in (sc, exdex.paper.fig4_scene()):
        res, found = _caught(lambda: exdex.simulate(scene, 1.0, 1e-3, method=method))
        assert res.stats["impacts"] == 0 and res.stats["max_impulse"] == 0.0
        assert not [w for w in found if w.kind == "impact"]


def test_batch_stats_carry_impacts():
    m, H = 0.1, 0.05
    body = exdex.Body.box(m, (0.02, 0.02, 0.02))
    floor = exdex.Stop(point=(0, 0, -0.01 - H), normal=(0, 0, 1))
    sc = exdex.Scene(body=body, grasp=exdex.Grasp(mu=0.0, grip_force=1.0), stops=floor)
    b, found = _caught(lambda: exdex.simulate_batch(sc, 0.2, 1e-3, mass=[0.1, 0.2], method="event"))
    np.testing.assert_allclose(b.stats["max_impulse"], np.array([0.1, 0.2]) * math.sqrt(2 * G * H), rtol=1e-8)
    assert list(b.stats["impacts"]) == [1, 1]
    assert [w.kind for w in found].count("impact") == 1 and "1 more of 2" in str(
        [w for w in found if w.kind == "impact"][0])

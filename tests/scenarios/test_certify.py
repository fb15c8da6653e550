"""The certificate of reduced runs (Result.certificate, ReductionWarning).

References are closed forms of the planar statics, derived here:

* a box held still (gripper at rest) by a patch a distance d from its centre
  of mass, gravity in the plate plane and perpendicular to the offset: the
  plates must carry the weight W and the moment W d, so the friction
  ellipsoid holds it iff (W / C)^2 + (W d / (C e_r))^2 <= 1 (C = mu * 2 *
  grip force): the pad offset at which the box starts to turn is
  d* = e_r sqrt((C / W)^2 - 1), and at a given offset the grip force
  F* = W sqrt(1 + (d / e_r)^2) / (2 mu);
* a slide whose axis makes an angle alpha with gravity (patch at the centre
  of mass): the load is the whole weight W, across the axis W sin(alpha);
  while stuck it must lie in the surface (W <= C), and while the slide slips
  (W cos(alpha) > C) the part across the axis is a load that a pure
  translation slip's friction (along the slip) cannot give;
* a rotation whose centre of mass sits on the pivot: turning the gripper
  about the plate normal through the pivot loads the pin only with gravity's
  in-plane part, which a pure rotation slip's friction (a moment only)
  cannot carry.

twin: csrc/tests/test_certify.c (the same subject on the C API)
"""
import math
import os
import re
import warnings

import numpy as np
import pytest

import exdex
from exdex import AsymmetricProfile, Body, Grasp, Patch, Rest, Scene, Stop

METHODS = ["implicit", "event", "regularised", "explicit", "analytic"]
MASS, G, MU = 0.2, 9.81, 1.0
W = MASS * G
PAD = Patch.rectangle(0.02, 0.02)
E_R = PAD.e_r


def box_scene(offset=0.06, grip=3.0, dof="translation", **kw):
    """The 200 g, 15 x 8 cm box held by 2 cm square pads ``offset`` from its
    centre of mass (along x; gravity along -y of B), gripper at rest."""
    return Scene(body=Body.box(MASS, (0.15, 0.08, 0.03)),
                 grasp=Grasp(mu=MU, grip_force=grip, patch=Patch.rectangle(0.02, 0.02, center=(offset, 0.0))),
                 dof=dof, **kw)


def offset_threshold(grip):
    C = MU * 2 * grip
    return E_R * math.sqrt((C / W) ** 2 - 1.0)


def grip_threshold(offset):
    return W * math.sqrt(1.0 + (offset / E_R) ** 2) / (2 * MU)


def run(scene, method, t_end=0.3, dt=1e-3):
    with warnings.catch_warnings(record=True) as rec:
        warnings.simplefilter("always")
        res = exdex.simulate(scene, t_end, dt, method=method)
    red = [w.message for w in rec if isinstance(w.message, exdex.ReductionWarning)]
    return res, red


def test_closed_form_thresholds_of_the_issue_example():
    # e_r of a uniform square of half-side a is 0.76520 a (known value), the
    # torsional capacity 6 N * e_r is about 0.046 N m, gravity's torque 0.118 N m
    assert E_R == pytest.approx(0.76520 * 0.01, rel=1e-4)
    assert 6.0 * E_R == pytest.approx(0.0459, abs=1e-4)
    assert W * 0.06 == pytest.approx(0.1177, abs=1e-4)
    assert offset_threshold(3.0) == pytest.approx(0.02211, abs=1e-5)
    assert grip_threshold(0.06) == pytest.approx(7.755, abs=1e-3)


@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize("side", [0.99, 1.01])
def test_pad_offset_threshold(method, side):
    d = offset_threshold(3.0) * side
    res, red = run(box_scene(offset=d), method)
    gauge = math.hypot(W / 6.0, W * d / (6.0 * E_R))     # closed form: gauge of (W, W d)
    if side < 1:
        assert res.certificate["holds"] and not red
        assert res.reduction_valid_until == res.t[-1]
        assert res.reduction_holds.all()
    else:
        c = res.certificate
        assert not c["holds"] and c["stick"]
        assert c["valid_until"] == 0.0              # the box swings out at once
        assert c["gauge"] == pytest.approx(gauge, rel=1e-12)
        assert c["load"][1] == pytest.approx(W, rel=1e-12)          # f_y carries the weight
        assert abs(c["load"][2]) == pytest.approx(W * d, rel=1e-12)  # m_z gravity's moment about the pad
        assert not res.reduction_holds.any()
        assert len(red) == 1
        w = red[0]
        assert w.kind == "reduction" and w.coordinate == "theta" and w.stick and w.time == 0.0
        assert w.margin == pytest.approx(1 - gauge, rel=1e-9) and w.margin < 0
        assert "t = 0 s" in str(w) and "theta" in str(w)


@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize("side", [0.99, 1.01])
def test_grip_threshold(method, side):
    F = grip_threshold(0.06) * side
    res, red = run(box_scene(offset=0.06, grip=F), method)
    assert res.certificate["holds"] == (side > 1)
    assert bool(red) == (side < 1)


def test_issue_example_fails_with_its_figures():
    res, red = run(box_scene(), "implicit")
    c = res.certificate
    assert res.stick[1:].all() and np.max(np.abs(res.wrench[:, 2])) == 0.0   # the reduced run itself
    assert not c["holds"] and c["valid_until"] == 0.0
    assert c["gauge"] == pytest.approx(math.hypot(W / 6, W * 0.06 / (6 * E_R)), rel=1e-12)
    assert red and red[0].coordinate == "theta"


def slide_scene(alpha, C, v0=0.0):
    """Patch at the centre of mass, slide axis at alpha from gravity (-y)."""
    return Scene(body=Body.box(MASS, (0.15, 0.08, 0.03)),
                 grasp=Grasp(mu=MU, grip_force=C / (2 * MU), patch=PAD),
                 slide_axis=(math.sin(alpha), -math.cos(alpha)), v0=(0.0, 0.0, 0.0))


@pytest.mark.parametrize("method", METHODS)
def test_slide_off_the_load(method):
    a = math.radians(30)
    # stuck (W cos a < C): holds iff the whole weight is inside, C >= W
    res, _ = run(slide_scene(a, 1.01 * W), method)
    assert res.certificate["holds"]
    res, red = run(slide_scene(a, 0.99 * W), method)
    c = res.certificate
    assert not c["holds"] and c["stick"] and c["valid_until"] == 0.0
    assert c["gauge"] == pytest.approx(1 / 0.99, rel=1e-9) and red[0].coordinate == "across"
    # slipping (C < W cos a): the load across the axis, W sin a, has no friction to hold it
    res, red = run(slide_scene(a, 0.5 * W), method)
    c = res.certificate
    assert not res.stick[1:].all()
    assert not c["holds"] and c["valid_until"] < 0.01
    assert red and red[0].coordinate == "across"
    # along the load (alpha = 0) a slip neglects nothing
    res, red = run(slide_scene(0.0, 0.5 * W), method)
    assert res.certificate["holds"] and not red


def turn_scene(gravity):
    """Fig. 6's rotation (centre of mass on the pivot, gripper turning about
    the plate normal through it) with a given gravity."""
    sc = exdex.paper.fig6_scene()
    return exdex.replace(sc, gravity=gravity)


@pytest.mark.parametrize("method", ["implicit", "event", "analytic", "regularised", "explicit"])
def test_rotation_pivot_force(method):
    sc = turn_scene((0.0, 0.0, -9.81))          # in the plate plane (default plates vertical)
    res, red = run(sc, method, t_end=6.0, dt=1e-2)
    c = res.certificate
    assert not c["holds"] and red and red[0].coordinate == "pivot"
    # gravity along the plate normal (B's z = -A y): the pin carries nothing
    res, red = run(turn_scene((0.0, -9.81, 0.0)), method, t_end=6.0, dt=1e-2)
    assert not res.stick[1:].all()                     # it slips (the paper's case)
    assert res.certificate["holds"] and not red


def test_paper_fig6_reduction_fails_at_start():
    # The torque capacity is I_zz a_H (1 + 1e-9) and the weight m g loads the
    # pads too: the gauge at t = 0+ is sqrt((m g / C)^2 + 1 / (1 + 1e-9)^2).
    sc = exdex.paper.fig6_scene()
    res, red = run(sc, "analytic", t_end=6.0, dt=1e-3)
    C = sc.grasp.capacity
    c = res.certificate
    assert not c["holds"] and c["stick"] and c["valid_until"] == 0.0
    assert c["gauge"] == pytest.approx(math.hypot(0.1 * 9.81 / C, 1.0), rel=1e-6)


def test_a_stop_carries_the_moment():
    # The box stands on a stop (its bottom edge) while the pads hold it 6 cm
    # off its centre of mass: the stop's two corners carry the moment.
    free = box_scene(offset=0.06, grip=3.0)
    stop = Stop(point=(0.0, 0.0, -0.04), normal=(0.0, 0.0, 1.0))
    for method in ["implicit", "event", "explicit", "regularised"]:
        res, red = run(exdex.replace(free, stops=(stop,)), method)
        assert res.certificate["holds"] and not red, method
        res, red = run(exdex.replace(free, stops=(Stop(point=(0.0, 0.0, -0.05), normal=(0.0, 0.0, 1.0)),)),
                       method)
        assert not res.certificate["holds"], method   # 1 cm below: nothing touches at first


@pytest.mark.parametrize("method", ["implicit", "event", "analytic"])
def test_failure_located_between_samples(method):
    # Gripper at rest in the plates' plane, then Eq. 7 along A's x (B's x):
    # the phase [0, beta T) pushes with m a_H across the slide axis, the next
    # one with m a_L; the offset is chosen so that the first holds and the
    # second does not. The output grid (dt = 7 ms) does not meet beta T.
    T, beta, X1 = 0.3, 0.7, 0.1
    aH, aL = exdex.paper.eq7_accelerations(X1, T, beta)
    # with the patch at the centre of mass the load is (m a, W): gauge hypot(m a, W) / C;
    # C between the two phases' loads
    C = 0.5 * (math.hypot(MASS * aH, W) + math.hypot(MASS * aL, W))
    sc = box_scene(offset=0.0, grip=C / (2 * MU), motion=AsymmetricProfile(X1, T, beta, axis=(1.0, 0.0, 0.0)))
    g1, g2 = math.hypot(MASS * aH, W) / C, math.hypot(MASS * aL, W) / C
    assert (g1 < 1) != (g2 < 1)
    res, red = run(sc, method, t_end=1.2, dt=7e-3)
    c = res.certificate
    assert not c["holds"]
    t_switch = beta * T if g1 < 1 else 0.0
    assert c["valid_until"] == pytest.approx(t_switch, abs=1e-9)
    assert c["gauge"] == pytest.approx(max(g1, g2), rel=1e-9)


def test_batch_carries_the_certificate_per_trajectory():
    F = grip_threshold(0.06)
    grips = F * np.array([0.9, 0.99, 1.01, 1.1])
    with warnings.catch_warnings(record=True) as rec:
        warnings.simplefilter("always")
        b = exdex.simulate_batch(box_scene(), 0.2, 1e-3, grip_force=grips)
    assert list(b.reduction_holds) == [False, False, True, True]
    assert np.all(b.reduction_valid_until[:2] == 0.0) and np.all(b.reduction_valid_until[2:] == 0.2)
    assert any(getattr(w.message, "kind", None) == "reduction" for w in rec)
    assert b[3].reduction_valid_until == 0.2 and not b[0].reduction_holds.any()


def test_planar_runs_have_no_certificate():
    res, red = run(box_scene(dof="planar"), "implicit", t_end=0.05)
    assert res.certificate is None and res.reduction_valid_until is None and res.reduction_holds.all()


def test_certify_false_gives_the_same_run():
    sc = box_scene()
    a = exdex.simulate(sc, 0.1, certify=False)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        b = exdex.simulate(sc, 0.1)
    assert a.certificate is None and b.certificate is not None
    for k in ("t", "q", "v", "wrench", "stick", "stop_force"):
        assert np.array_equal(getattr(a, k), getattr(b, k))


def test_result_save_load_keeps_certificate(tmp_path):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = exdex.simulate(box_scene(), 0.05)
    p = res.save(tmp_path / "r.npz")
    back = exdex.Result.load(p)
    assert back.certificate == res.certificate


# ---------------------------------------------------------------- dof="auto"

@pytest.mark.parametrize("case", ["fig3", "fig4"])
@pytest.mark.parametrize("method", ["implicit", "event", "auto"])
def test_auto_keeps_the_paper_cases(case, method):
    # the reduction holds: "auto" is the paper's 1-DoF run itself, bit for bit
    sc = getattr(exdex.paper, f"{case}_scene")()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        a = exdex.simulate(exdex.replace(sc, dof="auto"), 1.0, 1e-3, method=method)
        b = exdex.simulate(sc, 1.0, 1e-3, method=method)
    assert a.scene.dof == "translation" and len(a.models) == 1 and a.models[0][0] == "translation"
    for k in ("t", "q", "v", "wrench", "stick", "stop_force"):
        assert np.array_equal(getattr(a, k), getattr(b, k)), k


def test_auto_fig6_is_planar_from_the_start():
    sc = exdex.paper.fig6_scene()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        a = exdex.simulate(exdex.replace(sc, dof="auto"), 8.0, 1e-3, method="event")
        p = exdex.simulate(exdex.replace(sc, dof="planar"), 8.0, 1e-3, method="event")
    assert [m[0] for m in a.models] == ["planar"] and a.models[0][2] == 0.0
    assert "fails its certificate at t = 0 s" in a.models[0][4]
    assert np.array_equal(a.q, p.q)


@pytest.mark.parametrize("method", ["implicit", "event"])
def test_auto_switches_where_the_certificate_fails(method):
    # the located-failure scene above: translation to beta T, then planar; the
    # planar run from t = 0 holds the box still up to there (exact stick), so
    # both end in the same state
    T, beta, X1 = 0.3, 0.7, 0.1
    aH, aL = exdex.paper.eq7_accelerations(X1, T, beta)
    C = 0.5 * (math.hypot(MASS * aH, W) + math.hypot(MASS * aL, W))
    sc = box_scene(offset=0.0, grip=C / (2 * MU), motion=AsymmetricProfile(X1, T, beta, axis=(1.0, 0.0, 0.0)),
                   dof="auto")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        a = exdex.simulate(sc, 1.0, 1e-3, method=method)
        p = exdex.simulate(exdex.replace(sc, dof="planar"), 1.0, 1e-3, method=method)
    assert [m[0] for m in a.models] == ["translation", "planar"]
    assert a.models[0][3] == pytest.approx(beta * T, abs=1e-9) and a.models[1][2] == a.models[0][3]
    assert a.scene.dof == "planar" and a.q.shape[1] == 3 and a.t[-1] == pytest.approx(1.0, abs=1e-12)
    # before the switch both grids are i dt, the object at rest in both
    pre = a.t < beta * T
    assert np.array_equal(a.t[pre], p.t[: pre.sum()]) and np.all(a.q[pre] == p.q[0])
    assert np.max(np.abs(a.q[-1] - p.q[-1])) < 1e-9 * 0.15   # event/implicit rounding against the box size
    assert abs(a.q[-1, 0] - p.q[0, 0]) > 1e-3                 # it did slide


def _event_run(sc, dof, zs):
    """A zoo scene run as dof (event method, rtol 1e-10, 200 output steps)."""
    return exdex.simulate(exdex.replace(sc, dof=dof), zs.t_end, zs.t_end / 200, method="event", rtol=1e-10,
                          atol=1e-12)


def _assert_auto_matches_planar(a, p, zs, seed):
    """dof="auto" run a against the planar run p from t = 0: same end time,
    final poses within 1e-6 L and 1e-6 rad, and where "auto" chose the
    planar model from the start, the same run bit for bit."""
    qa = a.q if a.q.shape[1] == 3 else exdex.diagnostics.poses(a.scene, a.q)
    assert a.t[-1] == pytest.approx(p.t[-1], rel=1e-12)
    assert np.all(np.abs(qa[-1, :2] - p.q[-1, :2]) <= 1e-6 * zs.L), (seed, a.models)
    assert abs(qa[-1, 2] - p.q[-1, 2]) <= 1e-6, (seed, a.models)
    if a.models[0][0] == "planar":
        assert np.array_equal(a.q, p.q), seed


def test_auto_against_planar_on_zoo_scenes():
    # Random 1-DoF zoo scenes run as dof="auto" and as planar from t = 0 (event
    # method, rtol 1e-10): the final poses agree. Tolerance: a slip's unbalanced
    # load counts as zero up to 1e-9 of the scene's force scale m A, which can
    # move the planar object by at most 1e-9 A t^2 / 2, under 1e-6 L over a
    # zoo run (t_end below ~40 tau, A ~ g = L / tau^2), plus the event method's
    # rtol.
    import zoo

    checked = switched = 0
    for seed in range(60):
        zs = zoo.zoo_scene(seed)
        sc = zs.scene
        if sc.dof == "planar" or sc.obstacles:
            continue
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            try:
                a = _event_run(sc, "auto", zs)
                p = _event_run(sc, "planar", zs)
            except exdex.SolverError:
                continue
        _assert_auto_matches_planar(a, p, zs, seed)
        checked += 1
        switched += len(a.models) == 2
    assert checked >= 20 and switched >= 2


def test_auto_against_planar_on_zoo_scenes_with_obstacles():
    # The 1-DoF zoo scenes with an obstacle added (zoo.obstacle: a box, a rod
    # or a wedge 0..L/3 from the outline, frictionless or mu 0.5), run as
    # dof="auto" and as planar from t = 0 (event method, rtol 1e-10): the
    # final poses agree to the tolerance of the test above. The certificate
    # counts the obstacles' normal and friction forces as carrying load; a
    # 1-DoF candidate that raises SolverError against an obstacle is not
    # used (Result.models says so).
    import zoo

    checked = reduced = switched = 0
    for seed in range(60):
        zs = zoo.zoo_scene(seed)
        sc = zs.scene
        if sc.dof == "planar":
            continue
        rng = np.random.default_rng(1000 + seed)
        ob, _ = zoo.obstacle(rng, zs, float(rng.choice([0.0, 0.5])))
        sc = exdex.replace(sc, obstacles=(ob,))
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            try:
                p = _event_run(sc, "planar", zs)
            except exdex.SolverError:
                continue
            a = _event_run(sc, "auto", zs)
        _assert_auto_matches_planar(a, p, zs, seed)
        checked += 1
        reduced += a.models[0][0] != "planar"
        switched += len(a.models) == 2
    assert checked >= 25 and reduced >= 8 and switched >= 3


_RUN_KEYS = ("t", "q", "v", "wrench", "stick", "stop_force")


def test_run_certified_as_it_goes_against_the_whole_run():
    # The reference: the whole run and its certificate (exdex_certify over
    # all its samples). Certified as it goes, a window at a time
    # (stop_at_failure), the run must find the same certificate; where the
    # reduction holds it is the same run bit for bit, where it fails the
    # samples before the failing one are, and the run ends at valid_until.
    import zoo
    from exdex import _core

    held = failed = 0
    for seed in range(80):
        zs = zoo.zoo_scene(seed)
        sc = zs.scene
        if sc.dof == "planar":
            continue
        for method in ["implicit", "event", "regularised", "explicit", "analytic"]:
            if method == "analytic" and (sc.obstacles or _core.analytic_unsupported(sc.to_spec()) is not None):
                continue
            spec = sc.to_spec(method=method)
            dt = zs.t_end / 200
            try:
                whole = _core.simulate(spec, zs.t_end, dt)
            except exdex.SolverError:
                continue
            run = _core.simulate(spec, zs.t_end, dt, stop_at_failure=True)
            c, cr = whole["certificate"], run["certificate"]
            if c["holds"]:
                held += 1
                assert cr == c and run["stats"] == whole["stats"], (seed, method)
                assert all(np.array_equal(run[k], whole[k]) for k in _RUN_KEYS), (seed, method)
                continue
            failed += 1
            assert {k: v for k, v in cr.items() if k != "valid_until"} == \
                {k: v for k, v in c.items() if k != "valid_until"}, (seed, method)
            keep = max(c["first_bad"], 1)
            assert all(np.array_equal(run[k][:keep], whole[k][:keep]) for k in _RUN_KEYS), (seed, method)
            assert len(run["t"]) in (keep, keep + 1) and run["t"][-1] == cr["valid_until"], (seed, method)
            # valid_until is the whole run's, or (no step to it returned) the sample before
            assert cr["valid_until"] == c["valid_until"] or len(run["t"]) == keep, (seed, method)
    assert held >= 5 and failed >= 50


@pytest.mark.parametrize("seed", [375, 386])
def test_a_slip_inside_an_output_interval_is_certified(seed):
    # Zoo scenes run as translation (event method): at 200 output steps a
    # slip starts and ends inside one interval (both samples stuck, the
    # coordinate moved); its friction, along the slide axis, cannot carry
    # the load across it. The reference: the same run at 10 and 100 times
    # the samples, which show the slip, and whose certificates fail while
    # it slips at one time (to the finer grid's step). The coarse run's
    # certificate must fail no later than the interval holding that time,
    # and dof="auto" then agrees with the planar run from t = 0.
    import zoo

    zs = zoo.zoo_scene(seed)
    sc = exdex.replace(zs.scene, dof="translation")
    runs = {}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for k in (200, 2000, 20000):
            runs[k] = exdex.simulate(sc, zs.t_end, zs.t_end / k, method="event", rtol=1e-10, atol=1e-12)
    fine = runs[20000].certificate
    assert not fine["holds"] and not fine["stick"]
    assert runs[2000].certificate["valid_until"] == pytest.approx(fine["valid_until"], abs=zs.t_end / 2000)
    c = runs[200].certificate
    assert not c["holds"] and c["valid_until"] <= fine["valid_until"] + zs.t_end / 200
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        a = _event_run(zs.scene, "auto", zs)
        p = _event_run(zs.scene, "planar", zs)
    assert [m[0] for m in a.models] == ["translation", "planar"]
    _assert_auto_matches_planar(a, p, zs, seed)


def _shake_between_samples():
    """The box held at its centre of mass (no moment) on a slide axis at
    alpha = -30 deg from gravity, shaken across that axis in the plate plane,
    s(t) = A (1 - cos w t) (5 Hz): the slide axis carries W cos(alpha), the
    plates across it W |sin(alpha)| - m A w^2 cos(w t). The reduction holds
    while that load lies in the surface, |across| <= K = sqrt(C^2 -
    (W cos alpha)^2); at the peaks (t = k / f) it does, at the troughs
    between them it does not: it first fails at t* = acos((W |sin alpha| - K)
    / (m A w^2)) / w."""
    alpha, grip, P, f = math.radians(-30.0), 1.25, 1.5, 5.0
    C, w = 2 * MU * grip, 2 * math.pi * f
    K = math.sqrt(C ** 2 - (W * math.cos(alpha)) ** 2)
    s = abs(math.sin(alpha))
    assert abs(W * s - P) < K < W * s + P   # holds at the peaks, fails at the troughs
    across = (math.cos(alpha), math.sin(alpha))
    # B's plate plane (x, y) is the world's (x, z) under the default gripper rotation
    motion = exdex.Shake(P / MASS / w ** 2, f, cycles=3, axis=(across[0], 0.0, across[1]))
    sc = box_scene(offset=0.0, grip=grip, motion=motion, slide_axis=(math.sin(alpha), -math.cos(alpha)))
    assert sc.gripper_rotation == ((1.0, 0.0, 0.0), (0.0, 0.0, -1.0), (0.0, 1.0, 0.0))
    return sc, math.acos((W * s - K) / P) / w, 1.0 / f


@pytest.mark.parametrize("method", ["implicit", "event"])
@pytest.mark.parametrize("per_period", [1, 3])
def test_a_stuck_load_leaving_the_surface_between_samples_is_certified(method, per_period):
    # Closed form (_shake_between_samples): output samples at the shake's
    # peaks, or at every third of its period (w t = 2 pi k / 3, the load
    # across W |sin alpha| + m A w^2 / 2 at most), all of them inside the
    # surface while the troughs between them are not; the stuck run's certificate
    # still fails at t*, and dof="auto" switches to the planar model there.
    sc, t_star, period = _shake_between_samples()
    dt = period / per_period
    res, red = run(sc, method, t_end=3 * period, dt=dt)
    assert res.stick.all() and np.ptp(res.q[:, 0]) == 0.0
    c = res.certificate
    assert not c["holds"] and c["stick"]
    assert c["valid_until"] == pytest.approx(t_star, abs=1e-9)
    assert len(red) == 1
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        a = exdex.simulate(exdex.replace(sc, dof="auto"), 3 * period, dt, method=method)
    assert [m[0] for m in a.models] == ["translation", "planar"]
    assert a.models[0][3] == pytest.approx(t_star, abs=1e-9)


def test_auto_head_is_the_one_dof_run():
    # Up to the switch, "auto" returns the 1-DoF run itself: the explicit
    # dof's samples bit for bit (mapped to planar poses), the switch at that
    # run's valid_until
    T, beta, X1 = 0.3, 0.7, 0.1
    aH, aL = exdex.paper.eq7_accelerations(X1, T, beta)
    C = 0.5 * (math.hypot(MASS * aH, W) + math.hypot(MASS * aL, W))
    sc = box_scene(offset=0.0, grip=C / (2 * MU), motion=AsymmetricProfile(X1, T, beta, axis=(1.0, 0.0, 0.0)),
                   dof="auto")
    for method in ["implicit", "event", "analytic", "regularised", "explicit"]:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            a = exdex.simulate(sc, 1.0, 7e-3, method=method)
            r = exdex.simulate(exdex.replace(sc, dof="translation"), 1.0, 7e-3, method=method)
        t_sw = a.models[0][3]
        assert a.models[0][0] == "translation" and t_sw == r.certificate["valid_until"], method
        k = r.certificate["first_bad"]
        pose = exdex.diagnostics.poses(r.scene, r.q[:k])
        assert np.array_equal(a.t[:k], r.t[:k]) and np.array_equal(a.q[:k], pose), method
        # the head's last sample at the switch: one step on from sample k - 1, or sample k - 1 itself
        assert np.array_equal(a.stick[:k], r.stick[:k]) and t_sw in (a.t[k - 1], a.t[k]), method
        assert a.t[k - 1] < a.t[k], method


def test_auto_is_refused_where_a_dof_is_needed():
    sc = box_scene(dof="auto")
    with pytest.raises(ValueError, match="dof='auto'"):
        exdex.Model(sc)
    with pytest.raises(ValueError, match="dof='auto'"):
        exdex.simulate_batch(sc, 0.1, 1e-3, grip_force=[1.0, 2.0])


# ------------------------------------------------------ the exact surface

def disc_boundary_wrench(x0, R, n_r=400, n_t=800):
    """Friction wrench per unit capacity (f_y, m_z) of a uniform disc of radius
    R slipping about the instantaneous centre (x0, 0): the Coulomb integral
    -(1/A) Int s/|s| dA, s = z x (r - x0 e_x), by Gauss-Legendre quadrature in
    the radius and the midpoint rule in the angle (an independent evaluation
    of the definition; smooth for x0 > R, converged to 1e-15 here)."""
    xr, wr = np.polynomial.legendre.leggauss(n_r)
    r, wr = 0.5 * R * (xr + 1), 0.5 * R * wr
    th = (np.arange(n_t) + 0.5) * 2 * np.pi / n_t
    rr, tt = np.meshgrid(r, th, indexing="ij")
    wt = wr[:, None] * rr * (2 * np.pi / n_t) / (np.pi * R * R)
    x, y = rr * np.cos(tt), rr * np.sin(tt)
    sx, sy = -y, x - x0
    s = np.hypot(sx, sy)
    return -(wt * sy / s).sum(), -(wt * (x * sy - y * sx) / s).sum()


@pytest.mark.parametrize("method", ["implicit", "event", "analytic"])
@pytest.mark.parametrize("lam", [0.99, 1.01])
def test_exact_surface_certifies_against_itself(method, lam):
    # A disc pad of radius R under the held box: the load (f, m) = (W, W d) at
    # the pad. With d = R |m1| / f1, (f1, m1) the exact surface's boundary
    # wrench for the instantaneous centre 1.5 R away, the load is lam times
    # the boundary point at capacity C = W / (lam f1): exact gauge lam. The
    # ellipsoid (e_r = 2R/3) is larger there: its gauge is
    # lam hypot(f1, m1 / (2/3)) = 0.976 lam, so with lam = 1.01 the exact
    # surface fails and the ellipsoid holds.
    R = 0.02
    f1, m1 = disc_boundary_wrench(1.5, 1.0)
    g_ell = math.hypot(f1, m1 / (2.0 / 3.0))
    assert g_ell == pytest.approx(0.97627, abs=1e-5)
    d = R * abs(m1) / f1
    C = W / (lam * f1)
    pad = Patch.disc(R, center=(d, 0.0))
    assert pad.e_r == pytest.approx(2 * R / 3, rel=1e-12)
    for surface, gauge in (("exact", lam), ("ellipsoid", lam * g_ell)):
        sc = Scene(body=Body.box(MASS, (0.15, 0.08, 0.03)),
                   grasp=Grasp(mu=MU, grip_force=C / (2 * MU), patch=pad, limit_surface=surface))
        res, red = run(sc, method)
        c = res.certificate
        assert res.stick[1:].all()                       # the reduced run holds: W < C
        assert c["holds"] == (gauge <= 1.0), surface
        assert bool(red) == (gauge > 1.0), surface
        if not c["holds"]:
            assert c["stick"] and c["valid_until"] == 0.0 and c["gauge"] == pytest.approx(gauge, rel=1e-6)


# ------------------------------------------------------ stop friction

@pytest.mark.parametrize("method", ["implicit", "event", "explicit", "regularised"])
@pytest.mark.parametrize("wall", ["stop", "obstacle"])
def test_frictional_wall_carries_the_weight(method, wall):
    # A cylinder (radius R = 1 cm) on a slide across gravity (B x), pressed by
    # nothing against a wall at its side (normal -x, touching at (R, 0)): the
    # weight W lies across the slide. The wall pushes with lambda >= 0 and its
    # friction beta (|beta| <= mu_s lambda) at (R, 0) takes part of the weight
    # at the price of a moment R beta on the pads, so the pads must give
    # (lambda, W - beta, -R beta); the least gauge is at lambda = beta / mu_s,
    # beta = W / (1 / mu_s^2 + 1 + k^2), k = R / e_r:
    #     g = W sqrt((1 + mu_s^2 k^2) / (1 + mu_s^2 (1 + k^2))) / C.
    # With C = 0.9 W: mu_s = 1 gives 0.8546 / 0.9 (holds), mu_s = 0.5
    # 0.9224 / 0.9 and a frictionless wall 1 / 0.9 (both fail) for the 2 cm
    # square's e_r; the pads here are a disc as wide as the cylinder's face
    # (e_r = 2 R / 3: 0.8742, 0.9285 and 1 over 0.9, the same verdicts). The
    # wall is a stop, or the face x = R of a box obstacle.
    R, C = 0.01, 0.9 * W
    pad = Patch.disc(R)
    k = R / pad.e_r
    for mu_s in (0.0, 0.5, 1.0):
        g = math.sqrt((1 + mu_s ** 2 * k ** 2) / (1 + mu_s ** 2 * (1 + k ** 2))) * W / C
        if wall == "stop":
            walls = dict(stops=(Stop(point=(R, 0.0, 0.0), normal=(-1.0, 0.0, 0.0), mu=mu_s),))
        else:
            walls = dict(obstacles=(exdex.Obstacle.box((R + 0.05, 0.0, 0.0), (0.1, 0.1, 0.1), mu=mu_s),))
        sc = Scene(body=Body.cylinder(MASS, R, 0.03), grasp=Grasp(mu=MU, grip_force=C / (2 * MU), patch=pad),
                   slide_axis=(1.0, 0.0), **walls)
        res, red = run(sc, method, t_end=0.1)
        c = res.certificate
        assert c["holds"] == (g <= 1.0), mu_s
        assert bool(red) == (g > 1.0), mu_s
        if g > 1.0:
            assert c["stick"] and c["valid_until"] == 0.0 and c["gauge"] == pytest.approx(g, rel=1e-9)


# ---------------------------------------- plans, fits and sequences

def tilted_fig3(alpha_deg=30.0):
    """Fig. 3 (Eq. 7 down first, beta 0.9, T 0.5 s) with the slide axis alpha
    off the vertical: stuck through the slow phase, it slips at beta T, where
    the load m (g + a_L) has the part m (g + a_L) sin(alpha) across the axis,
    which a slip along it cannot hold: the reduction fails at beta T = 0.45 s
    (the grip forces below keep it stuck before: m (g - a_H) = 0.892 N < C)."""
    a = math.radians(alpha_deg)
    return exdex.replace(exdex.paper.fig3_scene(), slide_axis=(math.sin(a), -math.cos(a)))


def test_plan_flags_a_failing_reduction():
    with warnings.catch_warnings(record=True) as rec:
        warnings.simplefilter("always")
        p = exdex.plan.solve(tilted_fig3(), {"slip": 0.01}, vary={"grip_force": (1.0, 3.0)}, tol=1e-7, t_end=1.5)
    assert p.reduction_fails_at == pytest.approx(0.45, abs=1e-6)
    assert [w.message.kind for w in rec if isinstance(w.message, exdex.ReductionWarning)] == ["reduction"]
    # along the axis (the paper's Fig. 3) the same plan holds
    with warnings.catch_warnings(record=True) as rec:
        warnings.simplefilter("always")
        p = exdex.plan.solve(tilted_fig3(0.0), {"slip": 0.01}, vary={"grip_force": (1.0, 3.0)}, tol=1e-7,
                             t_end=1.5)
    assert p.reduction_fails_at is None
    assert not [w for w in rec if isinstance(w.message, exdex.ReductionWarning)]


def test_identify_flags_a_failing_reduction_once():
    sc = tilted_fig3()
    r = exdex.simulate(exdex.replace(sc, grasp=exdex.replace(sc.grasp, mu=0.46)), 1.5, 0.01, method="analytic",
                       certify=False)
    t = np.linspace(0.0, 1.5, 151)
    with warnings.catch_warnings(record=True) as rec:
        warnings.simplefilter("always")
        fit = exdex.identify(sc, t, np.interp(t, r.t, r.q[:, 0]), {"mu": (0.3, 0.7)})
    assert fit.values["mu"] == pytest.approx(0.46, abs=1e-6)
    assert fit.reduction_fails_at == pytest.approx(0.45, abs=1e-6)
    # the fitted scene's warning only, not one per trial point
    assert len([w for w in rec if isinstance(w.message, exdex.ReductionWarning)]) == 1
    assert "reduction fails at t = 0.45" in fit.report()


def test_sequences_plan_planar_poses_only():
    # a sequence's steps are planar runs (nothing neglected, no certificate):
    # a 1-DoF scene is refused rather than planned on a reduction
    with pytest.raises(ValueError, match="dof must be 'planar'"):
        exdex.sequence.primitives(tilted_fig3())


@pytest.mark.parametrize("method", ["analytic", "implicit", "event", "explicit", "regularised"])
def test_a_slip_onset_on_the_slide_axis_is_no_failure(method):
    """A bar held upright (gravity along the slide axis, the centre of
    pressure at the centre of mass) while its grip ramps down: the load the
    neglected coordinates need is zero at every instant, so the reduction
    holds throughout (closed form), also at the slip's onset, where the
    along-axis load meets the capacity and the planar gauge is 1 to
    rounding. Random ramps and masses move where that tie falls in its last
    bits; the verdict must not depend on them."""
    rng = np.random.default_rng(7)
    rot = exdex.paper.fig3_scene().gripper_rotation
    cases = [(0.1, 1.5, 0.9)]       # 0.1 kg, 1.5 N -> 0.9 N: the onset at 1.73 s is a tie to 2e-16
    for _ in range(4):
        mass = rng.uniform(0.05, 0.3)
        cases.append((mass, rng.uniform(1.2, 2.0) * mass * 9.81, rng.uniform(0.5, 0.9) * mass * 9.81))
    for mass, f0, f1 in cases:
        sc = Scene(body=Body.box(mass, (0.03, 0.5, 0.03)),
                   grasp=Grasp(mu=0.5, grip_force=exdex.GripSchedule((0.0, 2.0), (f0, f1))),
                   motion=Rest(), gripper_rotation=rot)
        res, red = run(sc, method, t_end=2.5)
        assert not red, (mass, f0, f1, [str(w) for w in red])
        assert res.certificate["holds"], (mass, f0, f1)
        assert res.stick[0] and not res.stick[-1]      # it did start to slip in the run


# A shake of the held box along gravity (B's -y): s(t) = A (1 - cos w t),
# A < 0, so B accelerates by A w^2 cos(w t) along y and the load is the
# weight m (g - |A| w^2 cos w t), largest, m (g + |A| w^2), half a cycle in.
# With gravity's moment about the pad the box starts to turn where
# (F / C)^2 (1 + (d / e_r)^2) = 1: the offset threshold is
# d* = e_r sqrt((C / (m (g + |A| w^2)))^2 - 1) (below the 22.1 mm at rest),
# and past it the first failure is at cos(w t*) = (g - F* / m) / (|A| w^2),
# F* = C / sqrt(1 + (d / e_r)^2).
SHAKE_A, SHAKE_F = -0.004, 4.0


@pytest.mark.parametrize("method", ["implicit", "event", "explicit", "regularised"])
@pytest.mark.parametrize("side", [0.99, 1.01])
def test_shake_offset_threshold(method, side):
    w = 2 * math.pi * SHAKE_F
    C = MU * 2 * 3.0
    d_star = E_R * math.sqrt((C / (MASS * (G + abs(SHAKE_A) * w * w))) ** 2 - 1.0)
    assert d_star < 0.8 * offset_threshold(3.0)
    d = d_star * side
    scene = box_scene(offset=d, motion=exdex.Shake(SHAKE_A, SHAKE_F, cycles=2, axis=(0, 0, 1)))
    res, red = run(scene, method, t_end=0.6)
    c = res.certificate
    if side < 1:
        assert c["holds"] and not red
    else:
        t_star = math.acos((G - C / math.sqrt(1 + (d / E_R) ** 2) / MASS) / (abs(SHAKE_A) * w * w)) / w
        assert not c["holds"] and c["stick"] and len(red) == 1
        assert c["valid_until"] == pytest.approx(t_star, abs=1e-9)


def _random_motion(rng, kind):
    """The random motions of the block proofs' tests: a shake along a random
    axis (half or whole cycles), a shake turning about the plate normal, a
    log of a constant orientation (positions 1 - cos along a random
    direction, uneven sample times) or a chain (pauses, a shake, Eq. 7)."""
    axis = tuple(rng.uniform(-1, 1, 3))
    A, f = rng.uniform(-0.006, 0.006), rng.uniform(2.0, 6.0)
    if kind == "shake":
        return exdex.Shake(A, f, cycles=rng.integers(1, 5) / 2, axis=axis)
    if kind == "turning shake":
        return exdex.Shake(30 * A, f, cycles=rng.integers(1, 5) / 2, axis=(0, 1, 0), rotation=True,
                           center=(rng.uniform(-0.05, 0.05), 0.0, 0.0))
    if kind == "log":
        t = np.cumsum(np.r_[0.0, rng.uniform(0.02, 0.04, 29)])
        pos = rng.uniform(-1, 1, 3) * A * (1 - np.cos(2 * math.pi * f * t))[:, None]
        return exdex.SampledTrajectory(t, pos, np.tile([1.0, 0, 0, 0], (30, 1)), relative=True)
    assert kind == "chain", kind
    return exdex.Chain((exdex.Pause(0.1), exdex.Shake(A, f, cycles=2, axis=axis), exdex.Pause(0.1),
                        AsymmetricProfile(10 * A, 0.2, 0.6, axis=axis)))


def _random_scene(rng, kind):
    """A held box in a shake, a turning shake, a log of a constant
    orientation or a chain, its pad offset below the turning threshold at
    rest, the grip constant or falling."""
    grip = rng.uniform(1.5, 4.0)
    d = rng.uniform(0.6, 0.98) * offset_threshold(grip)
    motion = _random_motion(rng, ("shake", "turning shake", "log", "chain")[kind])
    if rng.uniform() < 0.4:
        # the grip falls by 20 % over the run: failures come later in it
        return box_scene(offset=d, grip=exdex.GripSchedule((0.0, 0.8), (grip, 0.8 * grip)), motion=motion)
    return box_scene(offset=d, grip=grip, motion=motion)


def test_block_proofs_give_the_every_sample_certificate():
    # the proofs skip evaluations only: the certificate is the one of
    # evaluating every sample (Model.simulate(every_sample=True)), field
    # for field, on scenes on both sides of their thresholds
    rng = np.random.default_rng(7)
    verdicts = []
    for i in range(32):
        scene = _random_scene(rng, i % 4)
        method = ["implicit", "event", "explicit"][i % 3]
        m = exdex.Model(scene, method=method)._model
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            a = m.simulate(0.8, 1e-3)["certificate"]
            b = m.simulate(0.8, 1e-3, every_sample=True)["certificate"]
        assert a == b, (i, a, b)
        verdicts.append("held" if a["holds"] else ("later" if a["valid_until"] > 0.0 else "at once"))
    # failures inside the run (past the samples the proofs skip), not only at t = 0
    assert verdicts.count("held") >= 6 and verdicts.count("later") >= 6


def _random_rotation_scene(rng, kind):
    """A rotation run in a gripper that does not turn: the box held about its
    pivot (the pads' centre) d off its centre of mass, d below the held
    threshold at rest (the same closed form as the translation's: the pin
    and the plates carry W and W d, so a failure is the motion's or the
    falling grip's), in a shake, a log of a constant orientation or a chain,
    the grip constant or falling; or (kind 3) Fig. 6's object spun, gravity and
    the shake along the plate normal, its centre of mass 1e-10 .. 1e-6 m off
    the pivot (the pin carries m omega^2 |c| only, against the slip's
    tolerance of ~1e-9 of the force scale: both sides)."""
    grip = rng.uniform(1.5, 4.0)
    d = rng.uniform(0.6, 0.98) * offset_threshold(grip)
    if kind < 3:
        motion = _random_motion(rng, ("shake", "log", "chain")[kind])
    else:
        rng.uniform(size=5)  # as many draws as a motion's axis, A and f: every kind at the same stream position
        c = math.exp(rng.uniform(math.log(1e-10), math.log(1e-6)))
        sc = exdex.paper.fig6_scene()
        grasp = exdex.replace(sc.grasp, patch=exdex.replace(sc.grasp.patch, center=(c, 0.0)))
        return exdex.replace(sc, gravity=(0.0, -9.81, 0.0), grasp=grasp, v0=(0.0, 0.0, rng.uniform(1.0, 3.0)),
                             motion=exdex.Shake(0.002, 4.0, cycles=2, axis=(0, 1, 0)))
    if rng.uniform() < 0.4:
        # the grip falls by 20 % over the run: failures come later in it
        grip = exdex.GripSchedule((0.0, 0.8), (grip, 0.8 * grip))
    return box_scene(offset=d, grip=grip, motion=motion, dof="rotation")


def _cert_slip_tol():
    """CERT_SLIP_TOL, read from csrc/tolerances.h (its one definition)."""
    path = os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, os.pardir, "csrc", "tolerances.h")
    with open(path, encoding="utf-8") as f:
        return float(re.search(r"#define CERT_SLIP_TOL ([0-9.eE+-]+)", f.read()).group(1))


def _spun_scene(rng):
    """Fig. 6's object spun at omega0, gravity along the plate normal, a pause
    and then a shake tilted off the normal. A slip's tolerance is
    CERT_SLIP_TOL (F + C) (csrc/certify.c; F = max(m g, C) the force scale,
    C the capacity, the load's own share ~1e-9 of it): the pin must carry
    the centripetal force m omega^2 |c| (x of the tolerance at the start, c
    the centre of mass from the pivot) and the shake's plate-plane force
    (at most y of it); they add or cancel as the object turns, so the slip
    holds, or fails inside the run."""
    sc = exdex.paper.fig6_scene()
    m, C = sc.body.mass, sc.grasp.capacity
    tol = _cert_slip_tol() * (max(m * G, C) + C)
    w0, x, y, f = rng.uniform(1.5, 3.0), rng.uniform(0.5, 0.8), rng.uniform(0.4, 0.7), rng.uniform(2.0, 6.0)
    a, b = rng.uniform(0.0, 2.0 * math.pi, 2)
    c = x * tol / (m * w0 * w0)
    eps = y * tol / (m * 0.004 * (2 * math.pi * f) ** 2)
    grasp = exdex.replace(sc.grasp, patch=exdex.replace(sc.grasp.patch, center=(c * math.cos(a), c * math.sin(a))))
    shake = exdex.Shake(0.004, f, cycles=int(rng.integers(1, 5)) / 2,
                        axis=(eps * math.cos(b), 1.0, eps * math.sin(b)))
    return exdex.replace(sc, gravity=(0.0, -G, 0.0), grasp=grasp, v0=(0.0, 0.0, w0 * rng.choice([-1.0, 1.0])),
                         motion=exdex.Chain((exdex.Pause(rng.uniform(0.05, 0.3)), shake)))


def test_rotation_block_proofs_give_the_every_sample_certificate():
    # the rotation's block proofs (the pin's load enclosed over the block's
    # angles and rates) skip evaluations only: the certificate is that of
    # evaluating every sample, field for field, on both sides of the
    # thresholds (the held box's at rest and the spun slip's tolerance), in
    # every method that runs these motions
    rng = np.random.default_rng(11)
    verdicts = []
    for i in range(48):
        scene = _random_rotation_scene(rng, i % 4) if i < 32 else _spun_scene(rng)
        method = ["implicit", "event", "explicit", "regularised"][(i // 4) % 4]
        verdicts.append(_blocks_give_every_sample(scene, method, i))
    spun = verdicts[32:]
    assert verdicts.count("held") >= 6 and verdicts.count("later") >= 6 and verdicts.count("at once") >= 3
    # the spun slips: both sides, failures inside the run (where a block's rates and angles decide)
    assert spun.count("held") >= 3 and spun.count("later") >= 3


def _blocks_give_every_sample(scene, method, i):
    """Run scene for 0.8 s (dt 1e-3, regularised 4e-3) with the block proofs
    and with every sample evaluated; assert the two certificates are equal
    field for field and return the verdict: "held", "later" (failed after
    t = 0) or "at once"."""
    m = exdex.Model(scene, method=method)._model
    dt = 4e-3 if method == "regularised" else 1e-3
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        a = m.simulate(0.8, dt)["certificate"]
        b = m.simulate(0.8, dt, every_sample=True)["certificate"]
    assert a == b, (i, a, b)
    return "held" if a["holds"] else ("later" if a["valid_until"] > 0.0 else "at once")


def _turning_motion(rng, kind):
    """A gripper that turns: a log of a turn A (1 - cos 2 pi f t) about an
    axis that drifts (uneven sample times), a
    chain with Eq. 7 turning about a random axis through a point off B and
    a shake turning about the plate normal, or Eq. 7 alone turning about a
    random axis."""
    if kind == 0:
        t = np.cumsum(np.r_[0.0, rng.uniform(0.02, 0.04, 29)])
        A, f, a0, a1 = rng.uniform(-0.4, 0.4), rng.uniform(1.0, 3.0), rng.uniform(-1, 1, 3), rng.uniform(-2, 2, 3)
        ax = a0 + a1 * t[:, None]
        ax /= np.linalg.norm(ax, axis=1)[:, None]
        half = 0.5 * A * (1 - np.cos(2 * math.pi * f * t))
        quats = np.c_[np.cos(half), np.sin(half)[:, None] * ax]
        pos = rng.uniform(-1, 1, 3) * 0.003 * (1 - np.cos(2 * math.pi * f * t))[:, None]
        return exdex.SampledTrajectory(t, pos, quats, relative=True)
    axis, center = tuple(rng.uniform(-1, 1, 3)), tuple(rng.uniform(-0.05, 0.05, 3))
    turn = AsymmetricProfile(rng.uniform(-0.5, 0.5), rng.uniform(0.2, 0.4), rng.uniform(0.2, 0.8), axis=axis,
                             rotation=True, center=center)
    if kind == 1:
        return exdex.Chain((exdex.Pause(0.1), turn, exdex.Shake(rng.uniform(-0.2, 0.2), rng.uniform(2.0, 5.0),
                                                                 cycles=1, axis=(0, 1, 0), rotation=True)))
    return turn


def test_turning_rotation_block_proofs_give_the_every_sample_certificate():
    # a rotation run in a gripper that turns (a log, a chain with turning
    # pieces, Eq. 7 off the plate normal): the blocks' proofs (the load
    # enclosed over the frame's enclosure and the block's angles and rates)
    # skip evaluations only: the certificate is that of evaluating every
    # sample, field for field, on both sides of the held box's threshold
    # (its offset 0.3 to 1.3 of the one at rest; the turn moves it)
    rng = np.random.default_rng(23)
    verdicts = []
    for i in range(48):
        grip = rng.uniform(1.5, 4.0)
        d = rng.uniform(0.3, 1.3) * offset_threshold(grip)
        scene = box_scene(offset=d, grip=grip, motion=_turning_motion(rng, i % 3), dof="rotation")
        method = ["implicit", "event", "explicit", "regularised"][(i // 3) % 4]
        verdicts.append(_blocks_give_every_sample(scene, method, i))
    assert verdicts.count("held") >= 10 and verdicts.count("later") >= 6 and verdicts.count("at once") >= 3, verdicts


def _stepped(scene, method, n, dt, grip=None):
    st = exdex.Stepper(scene, method=method)
    with warnings.catch_warnings(record=True) as rec:
        warnings.simplefilter("always")
        for _ in range(n):
            st.step(dt, grip)
    return st, [w.message for w in rec if isinstance(w.message, exdex.ReductionWarning)]


@pytest.mark.parametrize("method", METHODS)
def test_stepper_carries_the_certificate_of_simulate(method):
    # n steps of dt with the scene's grip are simulate(scene, n dt, dt)'s
    # samples; the stepper's certificate, checked step by step, is the one
    # simulate gives them (verdict, failure time, step, load, gauge): on
    # both sides of the held box's offset threshold (closed form above),
    # past the shake's threshold (failing half a cycle in), under a falling
    # grip, and Fig. 6's rotation (its pin force fails at once)
    w = 2 * math.pi * SHAKE_F
    d_shake = E_R * math.sqrt((MU * 6.0 / (MASS * (G + abs(SHAKE_A) * w * w))) ** 2 - 1.0) * 1.01
    scenes = [box_scene(offset=offset_threshold(3.0) * 0.99), box_scene(offset=offset_threshold(3.0) * 1.01),
              box_scene(offset=0.01, grip=exdex.GripSchedule((0.0, 0.4), (3.0, 0.5)))]
    if method != "analytic":
        scenes.append(box_scene(offset=d_shake, motion=exdex.Shake(SHAKE_A, SHAKE_F, cycles=2, axis=(0, 0, 1))))
    from exdex import paper
    scenes.append(paper.fig6_scene())
    verdicts = []
    for sc in scenes:
        n, dt = 400, 1e-3
        res, red = run(sc, method, t_end=n * dt, dt=dt)
        st, red_st = _stepped(sc, method, n, dt)
        assert st.certificate == res.certificate
        assert st.reduction_valid_until == res.reduction_valid_until
        assert len(red_st) == len(red) <= 1
        if red:
            assert (red_st[0].time, red_st[0].margin, red_st[0].coordinate) == (red[0].time, red[0].margin,
                                                                                 red[0].coordinate)
        verdicts.append(res.certificate["holds"])
    assert verdicts[0] and not verdicts[1] and not verdicts[-1] and not all(verdicts)


@pytest.mark.parametrize("method", ["implicit", "event"])
@pytest.mark.parametrize("side", [0.99, 1.01])
def test_stepper_certifies_its_own_grip(method, side):
    # steps with grip_force=F are checked with F: the held box of the
    # 60 mm offset is held from F* = W sqrt(1 + (d / e_r)^2) / (2 mu) on
    # (closed form above), whatever the scene's own grip
    F = grip_threshold(0.06) * side
    st, red = _stepped(box_scene(offset=0.06, grip=1.0), method, 100, 1e-3, grip=F)
    ref, _ = run(box_scene(offset=0.06, grip=F), method, t_end=0.1, dt=1e-3)
    assert st.certificate == ref.certificate
    assert st.certificate["holds"] == (side > 1) and bool(red) == (side < 1)


def test_stepper_snapshot_keeps_the_certificate():
    sc = box_scene(offset=0.01, grip=exdex.GripSchedule((0.0, 0.4), (3.0, 0.5)))
    st = exdex.Stepper(sc, method="implicit")
    for _ in range(100):
        st.step(1e-3)
    snap = st.save()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for _ in range(300):
            st.step(1e-3)
        failed = st.certificate
        assert not failed["holds"]
        st.restore(snap)
        assert st.certificate["holds"] and st.certificate["valid_until"] == pytest.approx(0.1, abs=1e-15)
        for _ in range(300):
            st.step(1e-3)
    assert st.certificate == failed


@pytest.mark.parametrize("method", ["implicit", "event", "analytic"])
@pytest.mark.parametrize("side", [0.99, 1.01])
def test_model_final_certifies_on_request(method, side):
    # Model.final(certify=True): the last sample of simulate, bit for bit,
    # and simulate's verdict (its warning) on both sides of the offset threshold
    m = exdex.Model(box_scene(offset=offset_threshold(3.0) * side), method=method)
    with warnings.catch_warnings(record=True) as rec:
        warnings.simplefilter("always")
        q, v, stick = m.final(0.3, 1e-3, certify=True)
        res = m.simulate(0.3, 1e-3)
    red = [w.message for w in rec if isinstance(w.message, exdex.ReductionWarning)]
    assert q == tuple(res.q[-1]) and v == tuple(res.v[-1]) and stick == bool(res.stick[-1])
    assert len(red) == (0 if side < 1 else 2)
    if red:
        assert (red[0].time, red[0].margin) == (red[1].time, red[1].margin)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert m.final(0.3, 1e-3) == (q, v, stick)     # unchecked by default


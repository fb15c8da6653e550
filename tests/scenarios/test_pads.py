"""Pads on the fingers (exdex.Pad): the contact region and its use by every method.

References, test by test: a brute-force grid of the region (each cell centre
tested against the pad's and the turned face's half-planes, in NumPy,
independent of the core's clipping and closed forms); the patch fixed on
the object, where the region is fixed on the object (the face inside the
pad); the translation's friction mu N whatever the region (the patch's run);
the face's edge crossing the pad at a known pose (the loss time from the
slide's closed form); and the methods against each other.
"""
import dataclasses
import math
import warnings

import numpy as np
import pytest

import exdex
from exdex import _core, paper

BOX = (0.15, 0.08, 0.02)


def _box_scene(pad=None, q0=(0.002, 0.0, 0.0), mu=1.0, grip=1.73, gravity=(0.0, -9.81, 0.0), dof="planar", **kw):
    body = exdex.Body.box(0.2, BOX)
    grasp = exdex.Grasp(mu=mu, grip_force=grip, patch=exdex.Patch.rectangle(0.02, 0.02, center=(-q0[0], -q0[1])),
                        pad=pad)
    return exdex.Scene(body=body, grasp=grasp, dof=dof, q0=q0, gravity=gravity, gripper_rotation=np.eye(3), **kw)


GRID = 450


def _grid_region(pad_outline, face_B, n=GRID):
    """Area, centroid and mean distance from the centroid of pad & face by a
    midpoint grid over the pad's bounding box (convex ccw polygons)."""
    lo, hi = pad_outline.min(axis=0), pad_outline.max(axis=0)
    xs = lo[0] + (np.arange(n) + 0.5) * (hi[0] - lo[0]) / n
    ys = lo[1] + (np.arange(n) + 0.5) * (hi[1] - lo[1]) / n
    X, Y = np.meshgrid(xs, ys)
    inside = np.ones_like(X, dtype=bool)
    for poly in (pad_outline, face_B):
        for p, q in zip(poly, np.roll(poly, -1, axis=0)):
            inside &= (q[0] - p[0]) * (Y - p[1]) - (q[1] - p[1]) * (X - p[0]) >= 0
    dA = (hi[0] - lo[0]) * (hi[1] - lo[1]) / n**2
    A = inside.sum() * dA
    if A == 0:
        return 0.0, None, None
    cx, cy = X[inside].mean(), Y[inside].mean()
    er = np.hypot(X[inside] - cx, Y[inside] - cy).mean()
    return A, np.array([cx, cy]), er


def _face_B(scene, q):
    c, s = math.cos(q[2]), math.sin(q[2])
    return np.array(q[:2]) + scene.body.vertices() @ np.array([[c, s], [-s, c]])


@pytest.mark.parametrize("seed", range(6))
def test_region_and_centroid_against_grid_as_an_edge_crosses(seed):
    """The face's corner region sweeps across a random rectangle pad: area,
    centroid and e_r of the core's region against the brute-force grid."""
    rng = np.random.default_rng(seed)
    pad = exdex.Pad.rectangle(rng.uniform(0.01, 0.03), rng.uniform(0.01, 0.03), center=tuple(rng.uniform(-0.01, 0.01, 2)))
    sc = _box_scene(pad)
    spec = sc.to_spec()
    th = rng.uniform(-0.6, 0.6)
    # put a face corner near the pad centre, then sweep it across the pad
    corner = sc.body.vertices()[int(rng.integers(4))]
    c, s = math.cos(th), math.sin(th)
    base = np.array(pad.center) - np.array([c * corner[0] - s * corner[1], s * corner[0] + c * corner[1]])
    d = rng.normal(size=2)
    d /= np.linalg.norm(d)
    size = float(np.max(np.ptp(pad.outline(), axis=0)))
    for k in range(7):
        q = (*(base + (k - 3) / 3 * 0.5 * size * d), th)
        got = _core.pad_region(spec, q)
        A, cen, er = _grid_region(pad.outline(), _face_B(sc, q))
        h = size / GRID
        assert got["area"] == pytest.approx(A, abs=4 * h * size)
        if A > 20 * h * size:
            assert np.allclose(got["centroid"], cen, atol=4 * h)
            assert got["e_r"] == pytest.approx(er, abs=4 * h)


def test_region_shrinks_and_its_centroid_moves_continuously():
    """As the face's end crosses a square pad the area falls linearly, the
    centroid moves at half the slide's speed and e_r falls monotonically
    (the rectangle's closed form: exdex_er_rectangle), with no jump."""
    sc = _box_scene(exdex.Pad.rectangle(0.02, 0.02))
    spec = sc.to_spec()
    xs = np.linspace(-0.085, -0.065, 201)   # the face's right end x + 0.075 from -0.01 to 0.01
    reg = [_core.pad_region(spec, (x, 0.0, 0.0)) for x in xs]
    A = np.array([r["area"] for r in reg])
    cx = np.array([r["centroid"][0] for r in reg])
    er = np.array([r["e_r"] for r in reg])
    e = xs + 0.075
    np.testing.assert_allclose(A, 0.02 * (e + 0.01), rtol=1e-12, atol=1e-18)
    ok = A > 0
    np.testing.assert_allclose(cx[ok], 0.5 * (e[ok] - 0.01), rtol=0, atol=1e-15)
    np.testing.assert_allclose(er[ok], [_core.er_rectangle(0.5 * (v + 0.01), 0.01) for v in e[ok]], rtol=1e-12)
    assert np.all(np.diff(er[ok]) > 0)


@pytest.mark.warns_by_design("outline")  # the object slides off the patch's point
def test_object_inside_the_pads_is_the_patch_on_the_object():
    """A pad larger than the face: the region is the face, fixed on the
    object, so each method's run is the run of the patch at the face's
    centroid with the face's e_r (to rounding of the region's integrals)."""
    body = exdex.Body.box(0.2, (0.04, 0.03, 0.02))
    pad = exdex.Pad.rectangle(0.3, 0.3)
    er = _core.er_rectangle(0.02, 0.015)
    mo = exdex.Shake(axis=(1.0, 0.3, 0.0), amplitude=0.01, frequency=3.0, cycles=2) \
        if hasattr(exdex, "Shake") else exdex.Rest()
    for method in ("implicit", "event", "regularised", "explicit"):
        res = []
        for p in (None, pad):
            sc = exdex.Scene(body=body, grasp=exdex.Grasp(mu=0.3, grip_force=3.0, patch=exdex.Patch(e_r=er), pad=p),
                             dof="planar", q0=(0.001, 0.002, 0.3), gravity=(0.0, -9.81, 0.0),
                             gripper_rotation=np.eye(3), motion=mo)
            res.append(exdex.simulate(sc, 0.3, 1e-3, method=method))
        np.testing.assert_allclose(res[1].q, res[0].q, rtol=0, atol=1e-9, err_msg=method)


@pytest.mark.warns_by_design("outline")  # it slides until the grasp is lost
@pytest.mark.parametrize("method", ["implicit", "event", "regularised", "explicit"])
def test_translation_is_unaffected_and_the_grasp_is_lost_off_the_pad(method):
    """1-DoF translation: mu N whatever the region, so the run is the patch's
    sample for sample; the face (0.08 m along the slide) leaves the 2 cm pad
    after a slide of 0.05 m, where the run stops with a grasp warning."""
    pad = exdex.Pad.rectangle(0.02, 0.02)
    kw = dict(dof="translation", slide_axis=(0.0, 1.0), q0=(0.0, 0.0, 0.0), mu=0.3, grip=0.2)
    a = exdex.simulate(_box_scene(None, **kw), 0.4, 1e-3, method=method)
    with pytest.warns(exdex.PhysicsWarning, match="grasp is lost") as rec:
        b = exdex.simulate(_box_scene(pad, **kw), 0.4, 1e-3, method=method)
    assert any(w.message.kind == "grasp" for w in rec)
    n = len(b.t)
    assert n < len(a.t)
    np.testing.assert_array_equal(b.q, a.q[:n])
    # the slide from rest at a = g - mu N / m: the face's end (0.04 m) passes the pad's edge (0.01 m)
    acc = 9.81 - 0.3 * 2 * 0.2 / 0.2
    t_loss = math.sqrt(2 * 0.05 / acc)
    assert b.stats["grasp_lost_t"] == b.t[-1]
    if method != "explicit":   # explicit: first order in dt, its slide not the closed form's
        assert t_loss <= b.t[-1] < t_loss + 1e-3 + 1e-9
    assert abs(b.q[-1, 0]) >= 0.05 and abs(b.q[-2, 0]) < 0.05


@pytest.mark.parametrize("method", ["implicit", "event", "regularised", "explicit"])
def test_planar_slide_off_the_pad_stops_the_run(method):
    """A weak grip: the box slides down off a small pad; the result ends at
    the first sample with no region, which the core's region confirms."""
    sc = _box_scene(exdex.Pad.disc(0.01), mu=0.3, grip=0.3)
    with pytest.warns(exdex.PhysicsWarning, match="grasp is lost"):
        r = exdex.simulate(sc, 0.5, 1e-3, method=method)
    spec = sc.to_spec()
    assert r.stats["grasp_lost_t"] == r.t[-1] < 0.5
    assert _core.pad_region(spec, r.q[-1])["area"] == 0.0
    assert _core.pad_region(spec, r.q[-2])["area"] > 0.0


def test_methods_agree_on_the_peer_scene():
    """The peer's box on 2 cm pads, its grip force 1.73 + 0.91 sin(4 pi t):
    the event method (exact Coulomb, adaptive) and the implicit one at
    dt = 1e-4 agree to 0.02 deg in the final rotation; the regularised and
    explicit methods (first order in eps and dt) to 0.6 deg."""
    t = np.linspace(0.0, 2.0, 2001)
    sched = exdex.GripSchedule(times=t, forces=1.73 + 0.91 * np.sin(4 * np.pi * t), kind="cubic")
    sc = _box_scene(exdex.Pad.rectangle(0.02, 0.02), grip=sched)
    th = {m: math.degrees(exdex.simulate(sc, 2.0, 1e-4 if m in ("implicit", "explicit") else 1e-3, method=m).q[-1, 2])
          for m in ("implicit", "event", "regularised", "explicit")}
    assert abs(th["implicit"] - th["event"]) < 0.02, th
    assert abs(th["regularised"] - th["event"]) < 0.6, th
    assert abs(th["explicit"] - th["event"]) < 0.6, th
    # and it turns less than the patch fixed on the object, whose lever arm stays 2 mm
    with pytest.warns(exdex.PhysicsWarning, match="relative to the plate pads"):   # the patch slides past its size
        th_patch = math.degrees(exdex.simulate(_box_scene(None, grip=sched), 2.0, 1e-4).q[-1, 2])
    assert th["event"] > th_patch + 3.0, (th, th_patch)


def test_stepper_repeats_simulate_with_pads():
    sc = _box_scene(exdex.Pad.rectangle(0.02, 0.02), grip=1.0)
    for method in ("implicit", "event"):
        r = exdex.simulate(sc, 0.2, 1e-3, method=method)
        st = exdex.Stepper(sc, method=method)
        qs = [st.step(1e-3).q for _ in range(200)]
        np.testing.assert_array_equal(np.array(qs), r.q[1:])


def test_batch_pad_parameters_match_single_runs():
    sc = _box_scene(exdex.Pad.rectangle(0.02, 0.02), grip=1.0)
    xs = np.array([-0.004, 0.0, 0.006])
    b = exdex.simulate_batch(sc, 0.2, 1e-3, pad_x=xs, pad_scale=np.array([1.0, 0.7, 1.3]))
    for i, (x, s) in enumerate(zip(xs, [1.0, 0.7, 1.3])):
        one = exdex.simulate(exdex.replace(sc, grasp=exdex.replace(sc.grasp, pad=exdex.replace(sc.grasp.pad, center=(x, 0.0), scale=s))), 0.2, 1e-3)
        np.testing.assert_array_equal(b.q[i], one.q)
    with pytest.raises(ValueError, match="pad_radius.*disc"):
        exdex.simulate_batch(sc, 0.2, 1e-3, pad_radius=np.array([0.01]))
    with pytest.raises(ValueError, match="Grasp.pad"):
        exdex.simulate_batch(_box_scene(None), 0.2, 1e-3, pad_x=xs)


def test_scene_file_with_pads_round_trips_and_schema_1_rejects_it(tmp_path):
    sc = _box_scene(exdex.Pad.disc(0.012, center=(0.001, -0.002)))
    for ext in (".json", ".toml"):
        p = tmp_path / f"s{ext}"
        exdex.save_scene(sc, p)
        assert exdex.load_scene(p) == sc
    d = exdex.io.scene_to_dict(sc)
    assert d["schema"] == exdex.io.SCHEMA_VERSION >= 2  # pads need schema 2 or later
    d["grasp"].pop("limit_surface", None)  # schema 3's key: schema 1 lacks both
    d["schema"] = 1
    with pytest.raises(ValueError, match="pad.*schema 2"):
        exdex.io.scene_from_dict(d)
    d.pop("grasp").pop("pad")
    d["grasp"] = exdex.io.scene_to_dict(_box_scene())["grasp"]
    d["grasp"].pop("limit_surface", None)
    assert exdex.io.scene_from_dict(d).grasp.pad is None


def test_bad_pads_are_named():
    with pytest.raises(ValueError, match="exactly one of vertices"):
        exdex.Pad()
    with pytest.raises(ValueError, match="exactly one of vertices"):
        exdex.Pad(vertices=((0, 0), (1, 0), (0, 1)), radius=1.0)
    with pytest.raises(ValueError, match="Pad.radius"):
        exdex.Pad(radius=-1.0)
    dent = ((0, 0), (0.02, 0), (0.02, 0.02), (0.01, 0.005), (0, 0.02))
    with pytest.raises(ValueError, match="pad"):
        exdex.simulate(_box_scene(exdex.Pad(vertices=dent)), 0.01, 1e-3)
    with pytest.raises(ValueError, match="pad"):
        exdex.simulate(_box_scene(exdex.Pad.disc(0.01, center=(0.5, 0.0))), 0.01, 1e-3)
    with pytest.raises(ValueError, match="contact face"):
        sc = exdex.Scene(body=exdex.Body(mass=0.1), grasp=exdex.Grasp(mu=0.5, grip_force=1.0, pad=exdex.Pad.disc(0.01)),
                         dof="planar")
        exdex.simulate(sc, 0.01, 1e-3)
    with pytest.raises(ValueError, match="analytic"):
        exdex.simulate(_box_scene(exdex.Pad.disc(0.01), dof="translation"), 0.01, 1e-3, method="analytic")


def test_engines_build_the_pads_where_exdex_has_them():
    """The engine runners' pad boxes: at Pad.center in B with the rectangle's
    half-sides, a disc pad as the square of its e_r (2R/3 = 0.76520 a), the
    joint at the region's centroid at the start."""
    from exdex.engines import _runner

    sc = _box_scene(exdex.Pad.rectangle(0.02, 0.012, center=(0.003, -0.001)))
    lay = _runner.Layout(sc, "pads")
    np.testing.assert_allclose(lay.pad_center, (0.003, -0.001, 0.0), atol=1e-15)
    np.testing.assert_allclose(lay.pad_half, (0.01, 0.006), rtol=1e-12)
    np.testing.assert_allclose(lay.joint_B, (0.003, -0.001, 0.0), atol=1e-12)
    lay = _runner.Layout(_box_scene(exdex.Pad.disc(0.009)), "pads")
    a = (2 * 0.009 / 3) / ((math.sqrt(2) + math.asinh(1)) / 3)
    np.testing.assert_allclose(lay.pad_half, (a, a), rtol=1e-12)
    with pytest.raises(ValueError, match="rectangle pad"):
        _runner.Layout(_box_scene(exdex.Pad(vertices=((-0.01, -0.01), (0.01, -0.01), (0.0, 0.01)))), "pads")


@pytest.mark.parametrize("method,dt", [("event", 1e-4), ("implicit", 2e-5)])
def test_rotation_about_the_pad_is_a_pendulum_with_coulomb_torque(method, dt):
    """A 0.2 m rod held 0.08 m from its centre of mass by a disc pad (R = 5 mm)
    on the pin of a rotation scene, gravity in the plane: it pivots at the pad
    centre and swings as a physical pendulum whose friction torque is the
    disc's C e_r = C 2R/3. Linearised (closed form): every half period
    pi sqrt(I_pad / (m g d)) the turning angle goes from theta_k to
    -theta_k + 2 delta sgn(theta_k), delta = C e_r / (m g d), until
    |theta_k| <= delta holds it; the amplitude 0.05 rad keeps sin theta =
    theta to 4e-4 relative."""
    m, d, R, mu, grip, th0, g = 0.1, 0.08, 0.005, 0.5, 0.05, 0.05, 9.81
    body = exdex.Body.box(m, (0.02, 0.2, 0.01))
    sc = exdex.Scene(body=body, grasp=exdex.Grasp(mu=mu, grip_force=grip, pad=exdex.Pad.disc(R)), dof="rotation",
                     q0=(d * math.sin(th0), -d * math.cos(th0), th0), gravity=(0.0, -g, 0.0),
                     gripper_rotation=np.eye(3))
    I = body.inertia[2][2] + m * d * d
    delta = mu * 2 * grip * (2 * R / 3) / (m * g * d)
    half = math.pi * math.sqrt(I / (m * g * d))
    want = [th0]
    while abs(want[-1]) > delta:
        want.append(-want[-1] + 2 * delta * math.copysign(1.0, want[-1]))
    r = exdex.simulate(sc, half * (len(want) - 0.5), dt, method=method)
    th, v = r.q[:, 0], r.v[:, 0]
    turns = [i for i in range(1, len(v)) if v[i - 1] != 0 and (np.sign(v[i]) != np.sign(v[i - 1]) or v[i] == 0)]
    assert len(turns) == len(want) - 1, ([th[i] for i in turns], want)
    for k, i in enumerate(turns, start=1):
        assert th[i] == pytest.approx(want[k], abs=3e-5), (k, th[i], want[k])
        assert r.t[i] == pytest.approx(k * half, abs=4e-4 + dt)
    assert th[-1] == pytest.approx(want[-1], abs=3e-5) and v[-1] == 0.0


def test_contact_slip_outcome():
    """plan's "contact_slip": the object's face sliding under the contact.
    Pads (the pad inside the face, its centroid fixed in B): a shift (dx, dy)
    at theta = 0 moves the centroid by (-dx, -dy) over the object, a turn by
    phi about the centre of mass moves it by 2 |c - r| sin(phi / 2); the patch
    fixed on the object: its centre's travel in B."""
    from exdex import plan

    sc = _box_scene(exdex.Pad.rectangle(0.02, 0.02, center=(0.001, 0.0)), q0=(0.004, 0.0, 0.0))
    d = np.array([[0.003, -0.004, 0.0], [0.0, 0.0, 0.2]])
    got = plan.outcome(d, sc, "contact_slip")
    np.testing.assert_allclose(got, [0.005, 2 * 0.003 * math.sin(0.1)], rtol=1e-12)
    patch = _box_scene(None, q0=(0.004, 0.0, 0.0))   # patch centre at (-0.004, 0) in C: the CoM's offset
    np.testing.assert_allclose(plan.outcome(d, patch, "contact_slip"), [0.005, 2 * 0.004 * math.sin(0.1)], rtol=1e-12)
    # a slide that leaves the pad: no region, NaN
    assert np.isnan(plan.outcome(np.array([[0.2, 0.0, 0.0]]), sc, "contact_slip")[0])
    with pytest.raises(ValueError, match="contact_slip"):
        plan._check_quantity("contact_slip", _box_scene(None, dof="translation"))


def test_stepper_stops_where_the_grasp_is_lost():
    sc = _box_scene(exdex.Pad.disc(0.01), mu=0.3, grip=0.3)
    with pytest.warns(exdex.PhysicsWarning):
        r = exdex.simulate(sc, 0.5, 1e-3)
    st = exdex.Stepper(sc)
    with pytest.warns(exdex.PhysicsWarning, match="grasp is lost"):
        for _ in range(len(r.t) - 1):
            st.step(1e-3)
    np.testing.assert_array_equal(st.state.q, r.q[-1])
    assert st.stats["grasp_lost_t"] == r.t[-1]
    with pytest.raises(ValueError, match="grasp was lost") as exc:
        st.step(1e-3)
    # the message carries the time itself (it printed "%.17g" before)
    assert float(str(exc.value).split("lost at t = ")[1].split(" s ")[0]) == r.t[-1]


# ---------------------------------------------------------------- the exact surface with pads

@pytest.mark.warns_by_design("pad", "outline")  # the patch-on-object runs: the patch slides off the face's centre
def test_exact_object_inside_a_centred_pad_is_the_patch():
    """limit_surface="exact": a pad larger than the face, centred on it:
    the region is the face, fixed on the object, so each method's run is
    the run of the exact surface of the patch of the face's size at its
    centre (to rounding of the region's integrals). The face is offset from
    the centre of mass, so gravity turns the box and the surface's moment
    enters."""
    off = np.array([0.006, -0.004])
    body = dataclasses.replace(exdex.Body.box(0.2, (0.04, 0.03, 0.02)),
                               outline=tuple(map(tuple, exdex.Body.box(0.2, (0.04, 0.03, 0.02)).vertices() + off)))
    mo = exdex.Shake(axis=(1.0, 0.3, 0.0), amplitude=0.01, frequency=3.0, cycles=2)
    for method in ("implicit", "event"):
        res = []
        for p in (None, exdex.Pad.rectangle(0.3, 0.3)):
            g = exdex.Grasp(mu=0.3, grip_force=3.0, patch=exdex.Patch.rectangle(0.04, 0.03, center=tuple(off)), pad=p,
                            limit_surface="exact")
            sc = exdex.Scene(body=body, grasp=g, dof="planar", q0=(0.001, 0.002, 0.3), gravity=(0.0, -9.81, 0.0),
                             gripper_rotation=np.eye(3), motion=mo)
            res.append(exdex.simulate(sc, 0.3, 1e-3, method=method))
        assert np.ptp(res[0].q[:, 2]) > 1e-3   # it turns: the surface's moment matters
        np.testing.assert_allclose(res[1].q, res[0].q, rtol=0, atol=1e-9, err_msg=method)


def _edge_pad_scene(grip, limit_surface="exact"):
    """A 3 x 2 cm box on a 2 cm pad whose centre sits 4 mm inside the face's
    right edge: the region is clipped (1.4 x 2 cm), its centroid 8 mm from
    the centre of mass, about 1.2 of its e_r (where the ellipsoid's and the
    exact surface's gauges of a force and moment differ most)."""
    body = exdex.Body.box(0.2, (0.03, 0.02, 0.02))
    pad = exdex.Pad.rectangle(0.02, 0.02, center=(0.011, 0.0))
    g = exdex.Grasp(mu=0.5, grip_force=grip, patch=exdex.Patch.rectangle(0.02, 0.02), pad=pad,
                    limit_surface=limit_surface)
    return exdex.Scene(body=body, grasp=g, dof="planar", q0=(0.0, 0.0, 0.0), gravity=(0.0, -9.81, 0.0),
                       gripper_rotation=np.eye(3))


def _held_gauges(sc):
    """The gauges per unit capacity of the wrench that holds the box at rest
    against gravity (about the region's centroid): the exact surface's of
    the clipped region (from the core's region outline and the surface's
    public evaluation) and the ellipsoid's of the region's e_r."""
    reg = _core.pad_region(sc.to_spec(), sc.q0)
    c = np.array(reg["centroid"])
    f = -sc.body.mass * np.array(sc.gravity[:2])
    arm = np.array(sc.q0[:2]) - c
    w = (f[0], f[1], arm[0] * f[1] - arm[1] * f[0])
    _, g = _core.limit_surface(1, 0.01, np.array(reg["vertices"]) - c, 0.0, 1, w)
    return g, math.sqrt(w[0] ** 2 + w[1] ** 2 + (w[2] / reg["e_r"]) ** 2), reg


@pytest.mark.parametrize("method", ["implicit", "event"])
def test_exact_held_load_inside_the_clipped_region_leaves_the_box_still(method):
    """Gravity on the box held by a clipped region beside its centre of
    mass: with the capacity 1.5 % above the holding wrench's exact gauge
    the box stays at q0 bit for bit (v exactly 0 at every sample); 1.5 %
    below it it slips, where the ellipsoid of the region's e_r (whose gauge
    of this load is 3.5 % lower) holds it still."""
    g, ge, reg = _held_gauges(_edge_pad_scene(1.0))
    assert 0.6 * 0.02 * 0.02 < reg["area"] < 0.8 * 0.02 * 0.02
    assert ge < 0.97 * g, (ge, g)
    for f, held in ((1.015, True), (0.985, False)):
        grip = f * g / (0.5 * 2)
        for ls in ("exact", "ellipsoid"):
            sc = _edge_pad_scene(grip, ls)
            r = exdex.simulate(sc, 0.05, 1e-3, method=method)
            if held or ls == "ellipsoid":
                assert np.all(r.q == np.array(sc.q0)), (method, ls, f)
                assert np.all(r.v == 0.0), (method, ls, f)
            else:
                assert np.max(np.abs(r.q[-1] - r.q[0])) > 1e-6, (method, ls, f)


@pytest.mark.warns_by_design("pad", "outline")  # the patch-on-object run slides past its patch
@pytest.mark.parametrize("method", ["implicit", "event"])
@pytest.mark.parametrize("pad", [None, exdex.Pad.rectangle(0.3, 0.3)])
def test_exact_slide_down_a_frictionless_wall_is_the_closed_form(pad, method):
    """A box pressed against a frictionless wall (a stop at its left face) by
    a lateral gravity component, sliding down it: the slip is a pure
    translation, whose exact friction is the capacity against the slip with
    no moment about the region's centroid (the centre of mass here: the face
    inside a large pad, or the patch of the face), so vy(t) = -(g_y - C / m)
    t, which the implicit step's velocity reproduces exactly (constant
    acceleration; the event method to its tolerance), and y(t) = -(g_y - C /
    m) t^2 / 2, from which the implicit position (q + h v+) lies at most
    (g_y - C / m) h t / 2; x and theta held. The wall as a one-face obstacle
    gives the same run bit for bit."""
    from runs import face_is_the_stop
    body = exdex.Body.box(0.2, (0.04, 0.03, 0.02))
    g = exdex.Grasp(mu=0.3, grip_force=0.5, patch=exdex.Patch.rectangle(0.04, 0.03), pad=pad, limit_surface="exact")
    wall = exdex.Stop(point=(-0.02, 0.0, 0.0), normal=(1.0, 0.0, 0.0))
    sc = exdex.Scene(body=body, grasp=g, dof="planar", q0=(0.0, 0.0, 0.0), gravity=(-3.0, -9.81, 0.0),
                     gripper_rotation=np.eye(3), stops=(wall,))
    kw = dict(method=method) if method == "implicit" else dict(method=method, rtol=1e-11, atol=1e-13)
    r = face_is_the_stop(exdex.simulate, sc, exdex.Obstacle.halfspaces([(1.0, 0.0, 0.0)], [-0.02]), 0.15, 1e-3, **kw)
    acc = 9.81 - 0.3 * 2 * 0.5 / 0.2
    np.testing.assert_allclose(r.v[:, 1], -acc * r.t, rtol=1e-12 if method == "implicit" else 1e-9, atol=1e-15)
    if method == "implicit":
        assert np.all(np.abs(r.q[:, 1] + 0.5 * acc * r.t ** 2) <= 0.5 * acc * 1e-3 * r.t * (1 + 1e-9) + 1e-15)
    else:
        np.testing.assert_allclose(r.q[:, 1], -0.5 * acc * r.t ** 2, rtol=1e-9, atol=1e-15)
    np.testing.assert_allclose(r.q[:, 0], 0.0, atol=1e-12)
    np.testing.assert_allclose(r.q[:, 2], 0.0, atol=1e-10)
    assert r.q[-1, 1] < -0.09   # it slid 9.3 cm, the face still inside the pad


def test_exact_slide_down_a_frictional_wall_is_the_closed_form():
    """The wall of the test above with Coulomb friction mu_w = 0.2: the
    slide's acceleration is g_y - C / m - mu_w g_x; the event velocity is it
    to its tolerance, the implicit one (the wall's friction row beside the
    plates' exact surface in one impulse problem) to rounding at every
    sample, the explicit one reaches it at first order in dt (the wall's
    friction enters a step late: an offset of order mu_w g_x dt)."""
    body = exdex.Body.box(0.2, (0.04, 0.03, 0.02))
    g = exdex.Grasp(mu=0.3, grip_force=0.5, pad=exdex.Pad.rectangle(0.3, 0.3), limit_surface="exact")
    wall = exdex.Stop(point=(-0.02, 0.0, 0.0), normal=(1.0, 0.0, 0.0), mu=0.2)
    sc = exdex.Scene(body=body, grasp=g, dof="planar", q0=(0.0, 0.0, 0.0), gravity=(-3.0, -9.81, 0.0),
                     gripper_rotation=np.eye(3), stops=(wall,))
    acc = 9.81 - 0.3 * 2 * 0.5 / 0.2 - 0.2 * 3.0
    err = []
    for dt in (1e-3, 5e-4, 2.5e-4):
        r = exdex.simulate(sc, 0.15, dt, method="explicit")
        err.append(abs(r.v[-1, 1] + acc * 0.15))
        assert np.all(r.v[:, 0] == 0.0) and np.max(np.abs(r.v[:, 2])) < 1e-9
    assert err[0] <= 3 * 0.2 * 3.0 * 1e-3
    assert err[1] < 0.6 * err[0] and err[2] < 0.6 * err[1], err
    r = exdex.simulate(sc, 0.15, 1e-3, method="event", rtol=1e-11, atol=1e-13)
    np.testing.assert_allclose(r.v[:, 1], -acc * r.t, rtol=1e-9, atol=1e-15)
    assert np.max(np.abs(r.v[:, 0])) < 1e-12 and np.max(np.abs(r.v[:, 2])) < 1e-9
    r = exdex.simulate(sc, 0.15, 1e-3, method="implicit")
    np.testing.assert_allclose(r.v[:, 1], -acc * r.t, rtol=1e-12, atol=1e-15)
    assert np.all(r.v[:, 0] == 0.0) and np.max(np.abs(r.v[:, 2])) < 1e-12


def test_batch_says_where_the_grasp_is_lost():
    """A batch of the slide off a small pad (test_planar_slide_off_the_pad):
    each trajectory's stats hold the single run's grasp_lost_t, its samples
    after the loss are NaN, and the batch warns (kind "grasp") as
    simulate does; one that holds keeps NaN there."""
    sc = _box_scene(exdex.Pad.disc(0.01), mu=0.3, grip=0.3)
    with pytest.warns(exdex.PhysicsWarning, match="batch index 0 .*grasp is lost") as rec:
        b = exdex.simulate_batch(sc, 0.5, 1e-3, grip_force=[0.3, 0.32, 5.0])
    assert any(w.message.kind == "grasp" for w in rec)
    lost = b.stats["grasp_lost_t"]
    for i, f in enumerate((0.3, 0.32)):
        with pytest.warns(exdex.PhysicsWarning, match="grasp is lost"):
            r = exdex.simulate(exdex.replace(sc, grasp=exdex.replace(sc.grasp, grip_force=f)), 0.5, 1e-3)
        assert lost[i] == r.stats["grasp_lost_t"]
        n = len(r.t)
        np.testing.assert_array_equal(b.q[i, :n], r.q)
        assert np.all(np.isnan(b.q[i, n:]))
    assert np.isnan(lost[2]) and np.all(np.isfinite(b.q[2]))


@pytest.mark.parametrize("limit_surface", ["ellipsoid", "exact"])
def test_no_patch_slide_warning_with_pads_on_the_fingers(limit_surface):
    """The patch-on-object checks (the slide past the patch, the patch
    leaving the outline) do not apply with pads on the fingers, where the
    contact stays on the finger: the peer's scene with pads, which slides
    and swings 35 mm down the pads, gives no "pad" or "outline" warning
    through simulate (every method), Model, dof="auto", a batch or the
    Stepper, while the same scene with the patch fixed on the object gives
    the slide warning (at 0.88 s)."""
    t = np.linspace(0.0, 2.0, 2001)
    sched = exdex.GripSchedule(times=t, forces=1.73 + 0.91 * np.sin(4 * np.pi * t), kind="cubic")
    sc = _box_scene(exdex.Pad.rectangle(0.02, 0.02), grip=sched)
    sc = exdex.replace(sc, grasp=exdex.replace(sc.grasp, limit_surface=limit_surface))
    methods = ("implicit", "event", "explicit") + (("regularised",) if limit_surface == "ellipsoid" else ())

    def stepper():
        st = exdex.Stepper(sc, method="implicit")
        for _ in range(2000):
            st.step(1e-3)
        return st.state

    runs = [lambda m=m: exdex.simulate(sc, 2.0, 1e-3, method=m) for m in methods]
    runs += [lambda: exdex.Model(sc).simulate(2.0, 1e-3),
             lambda: exdex.simulate(exdex.replace(sc, dof="auto"), 2.0, 1e-3),
             lambda: exdex.simulate_batch(sc, 2.0, 1e-3, mu=[0.9, 1.0]), stepper]
    for run in runs:
        with warnings.catch_warnings(record=True) as rec:
            warnings.simplefilter("always")
            run()
        kinds = [getattr(w.message, "kind", None) for w in rec]
        assert "pad" not in kinds and "outline" not in kinds, [str(w.message) for w in rec]
    assert abs(exdex.simulate(sc, 2.0, 1e-3).q[-1, 1]) > 0.03   # it slid down the pads
    with pytest.warns(exdex.PhysicsWarning, match="slid .* relative to the plate pads") as rec:
        exdex.simulate(exdex.replace(sc, grasp=exdex.replace(sc.grasp, pad=None)), 2.0, 1e-3)
    assert [w.message.kind for w in rec if isinstance(w.message, exdex.PhysicsWarning)] == ["pad"]


def _stop_pad_scene(seed, flush=True):
    """A 60 x 30 mm box on pads on the fingers (rectangle or disc, its centre
    up to 15 x 3.6 mm off the box's: some regions clipped) with the exact
    surface, resting flush on a frictional floor (seed even: a stop; odd: a
    one-face obstacle; mu 0.1..0.6), gravity in the plate plane tilted up to
    0.3 rad from the floor's normal, the gripper shaking along the floor or
    turning about the plate normal; the plates' capacity 0.5..1.2 of the
    weight. flush=False: the floor tilted up to 0.2 rad and up to 3 mm
    below the box (it falls onto it). Returns the scene and the box length."""
    rng = np.random.default_rng([int(seed), 0x2424])
    L = 0.06
    body = exdex.Body.box(rng.uniform(0.1, 0.3), (L, L / 2, 0.02))
    c = (rng.uniform(-0.25, 0.25) * L, rng.uniform(-0.12, 0.12) * L)
    if rng.random() < 0.5:
        pad = exdex.Pad.rectangle(rng.uniform(0.3, 0.6) * L, rng.uniform(0.3, 0.6) * L, center=c)
    else:
        pad = exdex.Pad.disc(rng.uniform(0.12, 0.25) * L, center=c)
    mu = rng.uniform(0.3, 0.8)
    grip = rng.uniform(0.5, 1.2) * body.mass * 9.81 / (2 * mu)
    grasp = exdex.Grasp(mu=mu, grip_force=grip, patch=exdex.Patch.rectangle(0.01, 0.01), pad=pad,
                        limit_surface="exact")
    a = rng.uniform(-0.3, 0.3)
    gravity = (9.81 * math.sin(a), -9.81 * math.cos(a), 0.0)
    tilt, gap = rng.uniform(-0.2, 0.2), rng.uniform(0.0, 0.003)
    smu = rng.uniform(0.1, 0.6)
    if flush:
        tilt, gap = 0.0, 0.0
    n = np.array([math.sin(tilt), math.cos(tilt), 0.0])
    p = np.array([0.0, -L / 4 - gap - L / 2 * abs(math.sin(tilt)), 0.0])
    stops, obst = (), ()
    if seed % 2 == 0:
        stops = (exdex.Stop(point=tuple(p), normal=tuple(n), mu=smu),)
    else:
        obst = (exdex.Obstacle.halfspaces([n], [float(n @ p)], mu=smu),)
    if rng.random() < 0.5:
        motion = exdex.AsymmetricProfile(rng.uniform(0.02, 0.06), rng.uniform(0.3, 0.5), beta=0.8,
                                         axis=(1.0, 0.0, 0.0))
    else:
        motion = exdex.AsymmetricProfile(rng.uniform(0.2, 0.5), rng.uniform(0.3, 0.5), beta=0.8,
                                         axis=(0.0, 0.0, 1.0), rotation=True)
    sc = exdex.Scene(body=body, grasp=grasp, dof="planar", q0=(0.0, 0.0, 0.0), gravity=gravity,
                     gripper_rotation=np.eye(3), stops=stops, obstacles=obst, motion=motion)
    return sc, L


# seeds 8 and 14 miss the ladder's rate with the ellipsoid in place of the exact
# surface too (seed 8: the implicit run stays 1.55e-5 L from the event run at
# every dt below 2^-12, on a pure slide along the floor; seed 14: one halving
# 1.3x farther): not of the exact surface, left open
_LADDER_MISSES = {8: "implicit 1.55e-5 L off at every dt < 2^-12 (the ellipsoid the same)",
                  14: "one halving 1.3x farther (the ellipsoid non-monotone too)"}


@pytest.mark.warns_by_design("impact", "solver")
@pytest.mark.parametrize("seed", [pytest.param(s, marks=pytest.mark.xfail(strict=True, reason=_LADDER_MISSES[s]))
                                  if s in _LADDER_MISSES else s for s in range(16)])
def test_implicit_with_frictional_stops_and_the_exact_surface_converges_to_event(seed):
    """The implicit method's stop friction (Stewart-Trinkle rows with the
    plate's exact surface: its maximum-dissipation wrench and Hessian while
    sliding, its least gauge over the stop forces at rest) against the event
    method (acceleration-level stop friction, the exact reference, rtol
    1e-10) on random scenes of pads, the exact surface and a frictional floor
    (_stop_pad_scene). Where the event run holds the box still all along (the
    floor carrying load: stop_force > 0), the implicit run holds it bit for
    bit too (q = q0 and v = 0 at every sample). Otherwise the final poses
    converge at the implicit method's first order in dt: each halving of
    2^-11 .. 2^-14 s at least 0.7x closer, within 1e-4 L at the end."""
    sc, L = _stop_pad_scene(seed)
    t_end = 1.0
    ref = exdex.simulate(sc, t_end, 1e-3, method="event", rtol=1e-10, atol=1e-12)
    assert ref.stats["grasp_lost_t"] is None
    assert np.max(np.abs(ref.stop_force)) > 0.1 * sc.body.mass * 9.81
    if np.all(ref.q == 0.0):
        assert np.all(ref.v == 0.0)
        r = exdex.simulate(sc, t_end, 2 ** -11, method="implicit")
        assert np.all(r.q == 0.0) and np.all(r.v == 0.0) and np.all(r.stick)
        return
    errs = []
    for dt in (2 ** -11, 2 ** -12, 2 ** -13, 2 ** -14):
        r = exdex.simulate(sc, t_end, dt, method="implicit")
        errs.append(np.max(np.abs(r.q[-1] - ref.q[-1]) / (L, L, 1.0)))
    for a, b in zip(errs, errs[1:]):
        assert b < 0.7 * a, errs
    assert errs[-1] < 1e-4, errs


@pytest.mark.warns_by_design("impact", "solver")
@pytest.mark.parametrize("method", ["implicit", "event", "explicit", "regularised"])
def test_stepper_repeats_simulate_with_pads_and_the_exact_surface(method):
    """exdex.Stepper with pads on the fingers and the exact surface of their
    region (alone, and with a frictional floor or obstacle: _stop_pad_scene
    seeds 0 and 9, each of which slides and turns) steps as simulate() does,
    sample for sample bit for bit, in every method."""
    box = _box_scene(exdex.Pad.rectangle(0.02, 0.02), grip=1.0)
    scenes = [exdex.replace(box, grasp=exdex.replace(box.grasp, limit_surface="exact")),
              _stop_pad_scene(0)[0], _stop_pad_scene(9)[0]]
    for sc in scenes:
        r = exdex.simulate(sc, 0.3, 1e-3, method=method)
        assert np.max(np.abs(r.q[-1] - r.q[0])) > 1e-3
        st = exdex.Stepper(sc, method=method)
        qs = [st.step(1e-3).q for _ in range(300)]
        np.testing.assert_array_equal(np.array(qs), r.q[1:])


def _sliver_scene(grip):
    """A 60 x 30 mm box of 0.1 kg on a 20 mm square pad 8 mm beside its
    centre of mass, the exact surface, the Fig. 3 motion: from about 0.45 s
    the box slips and turns about the pad until an edge of the face has
    crossed it and the region is a sliver; with grip 1.30..1.44 N it
    vanishes at 0.57..0.62 s (the grasp is lost), with 1.46 N it stays a
    sliver of 1e-6..1e-4 of the pad to the end, the box spinning at 6-8
    rad/s on it."""
    pad = exdex.Pad.rectangle(0.02, 0.02, center=(0.008, 0.0))
    return exdex.Scene(body=exdex.Body.box(0.1, (0.06, 0.03, 0.02)),
                       grasp=exdex.Grasp(mu=0.5, grip_force=grip, pad=pad, limit_surface="exact"),
                       motion=paper.fig3_scene().motion, dof="planar")


@pytest.mark.parametrize("grip", [1.30, 1.36, 1.44])
def test_event_run_ends_where_a_sliver_region_vanishes(grip):
    """The event method on _sliver_scene with one output interval (dt =
    t_end, as a plan's grip scan runs it) used to go on past the region's
    end on the last sliver's surface (its derivatives growing as its width
    -> 0) and run out of its step budget (SolverError at 1.06-1.5 s); it
    now ends the integration at the end of the step where the region
    vanishes: the run returns, reports the loss at its sample (t_end) and
    that sample's pose has no region. On the 1 ms grid its loss time and
    pose agree with the implicit method at dt = 2.5e-5 s (within a sample,
    1e-4 m and 1e-3 rad)."""
    sc = _sliver_scene(grip)
    spec = sc.to_spec()
    area0 = _core.pad_region(spec, sc.q0)["area"]
    with pytest.warns(exdex.PhysicsWarning, match="grasp is lost"):
        r = exdex.simulate(sc, 1.5, 1.5, method="event")
    assert r.stats["grasp_lost_t"] == r.t[-1] == 1.5
    assert _core.pad_region(spec, r.q[-1])["area"] <= 1e-6 * area0
    with pytest.warns(exdex.PhysicsWarning, match="grasp is lost"):
        fine = exdex.simulate(sc, 1.5, 1e-3, method="event")
    with pytest.warns(exdex.PhysicsWarning, match="grasp is lost"):
        imp = exdex.simulate(sc, 1.5, 2.5e-5, method="implicit")
    assert 0.55 < imp.stats["grasp_lost_t"] < 0.65
    assert abs(fine.stats["grasp_lost_t"] - imp.stats["grasp_lost_t"]) <= 1e-3 + 1e-9
    assert np.all(np.abs(fine.q[-1] - imp.q[-1]) <= (1e-4, 1e-4, 1e-3)), fine.q[-1] - imp.q[-1]
    assert _core.pad_region(spec, fine.q[-1])["area"] <= 1e-6 * area0


def test_event_run_on_a_lasting_sliver_agrees_with_implicit():
    """_sliver_scene at 1.46 N: the region stays a sliver (down to about
    3e-6 of the pad) for the last second and the grasp is not lost. The
    event method returns (its steps there set by the sliver's stiffness,
    about 50,000, the same at rtol 1e-6 and 1e-8) and the implicit method
    converges to its final pose at first order (dt 1e-4, 5e-5, 2.5e-5 s:
    each halving at least 0.7x closer)."""
    sc = _sliver_scene(1.46)
    spec = sc.to_spec()
    ref = exdex.simulate(sc, 1.5, 1e-3, method="event")
    assert ref.stats["grasp_lost_t"] is None
    areas = np.array([_core.pad_region(spec, q)["area"] for q in ref.q[::5]]) / _core.pad_region(spec, sc.q0)["area"]
    assert areas.min() < 1e-4
    errs = []
    for dt in (1e-4, 5e-5, 2.5e-5):
        r = exdex.simulate(sc, 1.5, dt, method="implicit")
        assert r.stats["grasp_lost_t"] is None
        errs.append(np.max(np.abs(r.q[-1] - ref.q[-1]) / (0.06, 0.06, 1.0)))
    assert errs[1] < 0.7 * errs[0] and errs[2] < 0.7 * errs[1], errs
    assert errs[2] < 5e-4, errs


@pytest.mark.warns_by_design("impact")
def test_implicit_rest_on_a_frictional_stop_with_the_exact_surface_counts_no_soft_problems():
    """_stop_pad_scene(4, flush=False): the box falls onto a tilted
    frictional floor, slides and comes to rest on it at 0.82 s. The implicit
    step there is the frictional solve (the plates' exact surface and the
    floor's friction: exact rest); the frictionless solve before it, whose
    Newton runs to its cap at that rest (the exact surface's D is not
    differentiable at the optimum), is replaced and its soft problem is not
    counted (it was, once per step: 722 at dt 2.5e-4). The rest is exact
    (v = 0 at every sample from 0.82 s) and agrees with the event method's
    within 2e-3 L (first order in dt)."""
    sc, L = _stop_pad_scene(4, flush=False)
    r = exdex.simulate(sc, 1.0, 2.5e-4, method="implicit")
    assert r.stats["warnings"] == 0
    assert np.all(r.v[r.t >= 0.82] == 0.0) and np.all(r.stick[r.t >= 0.82])
    ref = exdex.simulate(sc, 1.0, 1e-3, method="event", rtol=1e-10, atol=1e-12)
    assert ref.stick[-1]
    assert np.max(np.abs(r.q[-1] - ref.q[-1]) / (L, L, 1.0)) < 2e-3

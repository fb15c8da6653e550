"""Result.animate (exdex.animation): the geometry of each frame against closed
forms and invariances, frame timing, and the files it writes.

The geometry (``frame_geometry``) is what the frames draw, so it is checked
rather than pixels: the plate follows the gripper's closed-form profile, a
stuck object turns with the gripper, friction balances gravity at rest,
the outline never crosses a stop and touches it when the C core reports
contact, and the picture does not change when the whole world is rotated
and shifted (the view is the gripper's initial frame).
"""
import math

import numpy as np
import pytest

import exdex
from expected_warnings import by_design
from exdex import animation

BOX = exdex.Body.box(0.1, (0.04, 0.06, 0.02))
GRASP = exdex.Grasp(mu=0.5, grip_force=1.5)
DROP = exdex.AsymmetricProfile(0.1, 0.5, 0.9, axis=(0, 0, -1))


def test_plate_follows_the_gripper_profile():
    """Eq. 7: the gripper is at X1 = 0.1 m along -z (down, the view's -y with
    the default pose) at t = T = 0.5 s and back at 2 T."""
    r = exdex.simulate(exdex.Scene(body=BOX, grasp=GRASP, motion=DROP), 1.2, 1e-3)
    idx = [0, 500, 1000]
    g = animation.frame_geometry(r, idx)
    assert r.t[500] == 0.5 and r.t[1000] == 1.0
    c = g["plate"].mean(axis=1)
    assert np.allclose(c[1] - c[0], [0.0, -0.1], atol=1e-12, rtol=0)
    assert np.allclose(c[2], c[0], atol=1e-12, rtol=0)
    # the object's centre of mass: the gripper's displacement plus the slide in the fingers
    assert np.allclose(g["com"][1] - g["com"][0], [0.0, -0.1 + r.q[500, 0] - r.q[0, 0]], atol=1e-12, rtol=0)


def test_stuck_object_turns_with_the_gripper():
    """A rotation of 0.5 rad about the plate normal (B z = -A y by default) with a
    grip that holds: the outline turns by +0.5 rad in the view (x, y of B)."""
    motion = exdex.TrapezoidalProfile(0.5, 0.4, 1.5, axis=(0, -1, 0), rotation=True)
    sc = exdex.Scene(body=BOX, grasp=exdex.Grasp(mu=1.0, grip_force=50.0), motion=motion, dof="planar")
    r = exdex.simulate(sc, 0.6, 1e-3)
    assert r.stick[1:].all()
    g = animation.frame_geometry(r, [0, len(r.t) - 1])
    e0 = g["outline"][0, 1] - g["outline"][0, 0]
    e1 = g["outline"][1, 1] - g["outline"][1, 0]
    turn = math.atan2(e0[0] * e1[1] - e0[1] * e1[0], e0 @ e1)
    assert turn == pytest.approx(0.5, abs=1e-9)


@pytest.mark.parametrize("seed", range(4))
def test_friction_arrow_balances_gravity_at_rest(seed):
    """Statics: an object stuck in a gripper at rest feels plate friction
    -m g projected onto the plate plane (the view plane)."""
    rng = np.random.default_rng(seed)
    q = rng.normal(size=4)
    R0 = exdex.SampledTrajectory([0, 1, 2, 3], np.zeros((4, 3)), np.tile(q, (4, 1)))
    sc = exdex.Scene(body=BOX, grasp=exdex.Grasp(mu=1.0, grip_force=30.0), motion=R0, dof="planar")
    r = exdex.simulate(sc, 0.5, 1e-2)
    assert r.stick[1:].all()
    g = animation.frame_geometry(r, [len(r.t) - 1])
    assert np.allclose(g["force"][0], -BOX.mass * g["gravity"], atol=1e-9, rtol=0)
    # the view plane is the plate plane at t = 0: B's origin is the view's origin
    assert np.allclose(g["plate"][0].mean(axis=0), g["cop"][0], atol=1e-12)


@pytest.mark.warns_by_design("impact", "outline")
@pytest.mark.parametrize("normal", [(0, 0, 1), (0.15, 0.0, 1.0)])
def test_outline_rests_on_the_stop_without_crossing(normal):
    """The gripper goes down 0.1 m onto a table 0.09 m below the grasp: the box
    (bottom 0.03 m below it) is stopped and slides up in the fingers. In the
    view its outline never crosses the table line and touches it."""
    sc = exdex.Scene(body=BOX, grasp=GRASP, motion=DROP, dof="planar",
                     stops=(exdex.Stop((0, 0, -0.09), normal),))
    r = exdex.simulate(sc, 1.2, 1e-3)
    assert r.stop_force.max() > 0
    g = animation.frame_geometry(r)
    (n2, off), = g["stops"]
    gap = g["outline"] @ n2 - off  # (frames, vertices)
    assert gap.min() > -1e-9
    assert gap.min(axis=1).min() < 1e-6
    if normal == (0, 0, 1):  # box bottom 0.03 m below the grasp, table 0.09 m below
        assert gap.min(axis=1)[0] == pytest.approx(0.06, abs=1e-12)


def test_view_is_invariant_under_a_rigid_motion_of_the_world():
    """Rotating and shifting everything (gripper pose, motion axis and centre,
    gravity, stops) by one rigid motion leaves the picture unchanged."""
    rng = np.random.default_rng(3)
    q = rng.normal(size=4)
    G = exdex.SampledTrajectory([0, 1, 2, 3], np.zeros((4, 3)), np.tile(q, (4, 1))).evaluate(0.0)["R"][0]
    shift = rng.normal(size=3)
    motion = exdex.AsymmetricProfile(0.4, 0.5, 0.8, axis=(0.3, 0.2, 1.0), rotation=True, center=(0.02, 0.0, 0.05))
    stop = exdex.Stop((0, 0, -0.08), (0.1, 0, 1))
    a = exdex.Scene(body=BOX, grasp=GRASP, motion=motion, dof="planar", stops=(stop,))
    b = exdex.Scene(body=BOX, grasp=GRASP, dof="planar",
                    motion=exdex.AsymmetricProfile(0.4, 0.5, 0.8, axis=tuple(G @ motion.axis), rotation=True,
                                                   center=tuple(G @ motion.center + shift)),
                    gripper_rotation=G @ np.array(a.gripper_rotation), gripper_position=tuple(shift),
                    gravity=tuple(G @ a.gravity),
                    stops=(exdex.Stop(tuple(G @ stop.point + shift), tuple(G @ stop.normal)),))
    ra, rb = exdex.simulate(a, 1.2, 1e-3), exdex.simulate(b, 1.2, 1e-3)
    assert np.allclose(ra.q, rb.q, atol=1e-7)
    ga, gb = animation.frame_geometry(ra), animation.frame_geometry(rb)
    for key in ("outline", "plate", "cop", "com"):
        assert np.allclose(ga[key], gb[key], atol=1e-6), key
    assert np.allclose(ga["gravity"], gb["gravity"], atol=1e-12)
    assert np.allclose(ga["stops"][0][0], gb["stops"][0][0], atol=1e-12)
    assert ga["stops"][0][1] == pytest.approx(gb["stops"][0][1], abs=1e-12)


@pytest.fixture(scope="module")
def drop():
    with by_design("impact", "outline"):  # a box dropped onto a stop, sliding off the pads' centre
        return exdex.simulate(exdex.Scene(body=BOX, grasp=GRASP, motion=DROP, dof="planar",
                                          stops=(exdex.Stop((0, 0, -0.09), (0, 0, 1)),)), 1.2, 1e-3)


@pytest.mark.warns_by_design("impact", "outline")
def test_frame_timing(drop):
    a = drop.animate()
    assert a.n_frames == 31 and a.interval_ms == pytest.approx(40.0)  # 1.2 s at 25 fps, real time
    a = drop.animate(speed=0.5, fps=10)
    assert a.n_frames == 25 and a.interval_ms == pytest.approx(100.0)
    a = drop.animate(max_frames=7)
    assert a.n_frames == 7 and a.interval_ms == pytest.approx(200.0)  # same duration, fewer frames
    assert "7 frames" in repr(a)


def test_writes_gif_html_and_reports_missing_ffmpeg(drop, tmp_path, monkeypatch):
    PIL = pytest.importorskip("PIL.Image")
    a = drop.animate(max_frames=6, fps=5, figsize=(3, 3))
    a.save(tmp_path / "a.gif", dpi=50)
    with PIL.open(tmp_path / "a.gif") as im:
        assert im.n_frames == 6
    a.save(tmp_path / "a.html", dpi=50)
    html = (tmp_path / "a.html").read_text()
    assert "<script" in html and html.count("data:image/png;base64") == 6
    monkeypatch.setattr(animation, "_ffmpeg", lambda: None)
    with pytest.raises(RuntimeError, match="ffmpeg"):
        a.save(tmp_path / "a.mp4")
    assert "<script" in a._repr_html_()  # the JavaScript player without ffmpeg
    with pytest.raises(ValueError, match=r"\.gif, \.mp4 or \.html.*'\.avi'"):
        a.save(tmp_path / "a.avi")


def test_mp4_with_ffmpeg(drop, tmp_path):
    if animation._ffmpeg() is None:
        pytest.skip("no ffmpeg (PATH or imageio-ffmpeg)")
    path = drop.animate(max_frames=4, fps=5, figsize=(3, 3)).save(tmp_path / "a.mp4", dpi=50)
    assert (tmp_path / "a.mp4").stat().st_size > 1000 and path == tmp_path / "a.mp4"


@pytest.mark.parametrize("kw, message", [
    (dict(fps=0), "fps must be in"), (dict(speed=-1), "speed must be in"),
    (dict(max_frames=1), "max_frames must be an integer >= 2"), (dict(plate_size=(0.1,)), "plate_size"),
])
def test_bad_options(drop, kw, message):
    with pytest.raises(ValueError, match=message):
        drop.animate(**kw)


# ------------------------------------------------------- drawn to scale, with a plain key

def _artist(anim, gid):
    found = [p for p in anim.figure.axes[0].patches if p.get_gid() == gid]
    return found[0] if found else None


def _extent(poly):
    xy = np.asarray(poly.get_xy())
    return np.ptp(xy, axis=0), 0.5 * (xy.min(axis=0) + xy.max(axis=0))


BIG_BOX = exdex.Body.box(0.2, (0.15, 0.08, 0.03))   # 15 x 8 cm face


def test_pad_plate_and_object_are_drawn_to_scale():
    """A 2 cm square pad 1 cm right of B's origin on a 15 x 8 cm box: drawn as a 20 x 20 mm square at
    (10, 0) mm (the view is B at t = 0), the object as 150 x 80 mm, the finger plate as the box around
    both (the scene gives no finger size); the key names them plainly and gives the arrow's scale."""
    pad = exdex.Pad.rectangle(0.02, 0.02, center=(0.01, 0.0))
    sc = exdex.Scene(body=BIG_BOX, grasp=exdex.Grasp(mu=0.5, grip_force=3.0, pad=pad))
    anim = exdex.simulate(sc, 0.05, 1e-3).animate(max_frames=2)
    size, centre = _extent(_artist(anim, "contact"))
    assert np.allclose(size, [20.0, 20.0], atol=1e-9) and np.allclose(centre, [10.0, 0.0], atol=1e-9)
    size, centre = _extent(_artist(anim, "object"))
    assert np.allclose(size, [150.0, 80.0], atol=1e-9) and np.allclose(centre, [0.0, 0.0], atol=1e-9)
    size, _ = _extent(_artist(anim, "plate"))
    assert np.allclose(size, [150.0, 80.0], atol=1e-9)
    keys = [t.get_text() for t in anim.figure.legends[0].get_texts()]
    assert "pad on the finger" in keys and "object" in keys and "finger plate" in keys
    # capacity mu x 2 fingers x 3 N = 3 N is drawn as the object's longest side, 150 mm
    assert "friction force: 150 mm = 3 N" in keys
    assert not any("mu fingers" in k for k in keys)
    g = animation.frame_geometry(exdex.simulate(sc, 0.05, 1e-3), [0])
    assert g["contact_kind"] == "pad" and g["plate_size"] == pytest.approx((0.15, 0.08), abs=1e-15)


def test_patch_region_is_drawn_on_the_object():
    """Patch.disc(5 mm): the drawn contact is the disc's rim, radius 5 mm about the centre of pressure,
    also after the object has slid (it moves with the object, not the fingers)."""
    sc = exdex.Scene(body=BIG_BOX, grasp=exdex.Grasp(mu=0.5, grip_force=0.5, patch=exdex.Patch.disc(0.005)))
    r = exdex.simulate(sc, 0.08, 1e-3)
    assert r.displacement[-1, 0] < -0.01   # it slides (capacity 0.5 N < weight 1.96 N), the patch stays on the face
    g = animation.frame_geometry(r, [0, len(r.t) - 1])
    for k in (0, 1):
        d = np.linalg.norm(g["contact"][k] - g["cop"][k], axis=1)
        assert np.allclose(d, 0.005, atol=1e-12)
    anim = r.animate(max_frames=2)
    xy = np.asarray(_artist(anim, "contact").get_xy())
    assert np.allclose(np.ptp(xy, axis=0), [10.0, 10.0], atol=1e-2)   # 64 rim points of a 10 mm disc


def test_a_patch_given_by_e_r_alone_has_no_drawn_shape():
    sc = exdex.Scene(body=BIG_BOX, grasp=exdex.Grasp(mu=0.5, grip_force=3.0, patch=exdex.Patch(e_r=0.004)))
    anim = exdex.simulate(sc, 0.05, 1e-3).animate(max_frames=2)
    assert _artist(anim, "contact") is None
    keys = [t.get_text() for t in anim.figure.legends[0].get_texts()]
    assert "centre of pressure (patch given by e_r)" in keys


@pytest.mark.parametrize("figsize", [(3.5, 3.5), (5.0, 5.0)])
def test_key_title_and_time_fit_in_the_figure(figsize):
    """The key below the picture and the title with the time stay inside the figure, also at 3.5 in."""
    pad = exdex.Pad.rectangle(0.02, 0.02)
    sc = exdex.Scene(body=BIG_BOX, grasp=exdex.Grasp(mu=0.5, grip_force=3.0, pad=pad))
    anim = exdex.simulate(sc, 0.05, 1e-3).animate(max_frames=2, figsize=figsize)
    anim._update(1)
    fig = anim.figure
    fig.canvas.draw()
    r = fig.canvas.get_renderer()
    texts = list(fig.legends[0].get_texts()) + [fig.axes[0].title]
    assert fig.axes[0].title.get_text().endswith("t = 0.050 s, stick")
    for t in texts:
        e = t.get_window_extent(r)
        assert fig.bbox.x0 - 0.5 <= e.x0 and e.x1 <= fig.bbox.x1 + 0.5 and e.y0 >= -0.5 and e.y1 <= fig.bbox.y1 + 0.5, \
            t.get_text()

"""Scenes as files (exdex.io); results out (Result.to_dict / to_dataframe /
save / load / repr) are tested in tests/test_simulate.py, the ``exdex run``
command in tests/cli/test_run.py.

Round trips are checked on seeded random scenes covering every scene object
and option: bodies (scalar, diagonal and full inertia; size; outline; a disc outline),
patches (given, disc, rectangle), one or two fingers, every motion (Rest,
AsymmetricProfile and TrapezoidalProfile translating and rotating,
SampledTrajectory with random arrays), 0 to 8 stops, every dof, random
gripper poses, gravity, q0, v0 and slide axes. Floats include values whose
decimal forms are long or unusual (0.1 + 0.2, subnormals, -0.0, 1e300): a
loaded scene must be equal *and* write the same text again (which sees the
sign of zero), and simulate to bit-identical arrays.
"""
import json
import math

import numpy as np
import pytest

import exdex
from exdex import io
from zoo import random_rotation

AWKWARD = [0.1 + 0.2, 1 / 3, -0.0, 5e-324, 2.2250738585072014e-308, 1e300, -1e-300, 123456789.123456789,
           2.0 ** -1074 * 3, 0.1, 1e16, 1e-5]


def _awkward(rng, n=None, positive=False):
    """Random floats mixing uniform draws and awkward decimal forms."""
    def one():
        x = float(rng.choice(AWKWARD)) if rng.random() < 0.3 else float(rng.normal() * 10.0 ** int(rng.integers(-6, 4)))
        return abs(x) if positive else x
    return one() if n is None else [one() for _ in range(n)]


def _body(rng):
    mass = abs(_awkward(rng)) or 0.3
    kind = rng.integers(0, 5)
    if kind == 0:
        return exdex.Body(mass=mass, inertia=float(rng.uniform(1e-6, 1e-2)))
    if kind == 4:
        return exdex.Body.cylinder(float(rng.uniform(0.01, 1.0)), float(rng.uniform(0.005, 0.1)),
                                   float(rng.uniform(0.005, 0.1)), outline_center=tuple(rng.normal(size=2) * 0.01))
    if kind == 1:
        return exdex.Body(mass=mass, inertia=rng.uniform(1e-6, 1e-2, size=3))
    if kind == 2:
        A = rng.normal(size=(3, 3)) * 1e-2
        return exdex.Body(mass=mass, inertia=A @ A.T + 1e-5 * np.eye(3), size=tuple(rng.uniform(0.01, 0.2, 3)))
    k = int(rng.integers(1, 33))
    return exdex.Body.box(float(rng.uniform(0.01, 1.0)), tuple(rng.uniform(0.01, 0.2, 3)), outline=rng.normal(size=(k, 2)) * 0.05)


def _patch(rng):
    kind = rng.integers(0, 3)
    center = tuple(rng.normal(size=2) * 0.01)
    if kind == 0:
        return exdex.Patch(e_r=float(rng.uniform(1e-4, 0.05)), center=center)
    if kind == 1:
        return exdex.Patch.disc(float(rng.uniform(1e-3, 0.05)), center=center)
    return exdex.Patch.rectangle(float(rng.uniform(1e-3, 0.05)), float(rng.uniform(1e-3, 0.05)), center=center)


def _motion(rng):
    kind = rng.integers(0, 4)
    axis = tuple(rng.normal(size=3))
    center = tuple(_awkward(rng, 3))
    rotation = bool(rng.integers(0, 2))
    if kind == 0:
        return exdex.Rest()
    if kind == 1:
        return exdex.AsymmetricProfile(_awkward(rng), float(rng.uniform(0.05, 2)), float(rng.uniform(0.01, 0.99)),
                                       axis=axis, rotation=rotation, center=center)
    if kind == 2:
        a, T = float(rng.uniform(0.01, 1) * rng.choice([-1, 1])), float(rng.uniform(0.1, 2))
        return exdex.TrapezoidalProfile(a, T, abs(a) / T * float(rng.uniform(1, 2)), axis=axis,
                                        rotation=rotation, center=center)
    n = int(rng.integers(4, 40))
    times = np.cumsum(rng.uniform(1e-3, 0.1, n)) + float(rng.choice([0.0, 0.1 + 0.2]))
    options = {}
    for name in ("start_velocity", "start_omega", "end_velocity", "end_omega"):
        if rng.random() < 0.3:
            options[name] = tuple(_awkward(rng, 3))
    if rng.random() < 0.5:
        options["relative"] = bool(rng.integers(0, 2))
    if rng.random() < 0.3:
        X = np.eye(4)
        X[:3, :3], X[:3, 3] = random_rotation(rng), rng.normal(size=3) * 0.05
        options["tool"] = X
    return exdex.SampledTrajectory(times, rng.normal(size=(n, 3)) * 0.1, rng.normal(size=(n, 4)), **options)


def _grasp(rng):
    mu = abs(_awkward(rng))
    grasp = exdex.Grasp(mu=mu, grip_force=abs(_awkward(rng)), patch=_patch(rng), fingers=int(rng.integers(1, 3)))
    if rng.integers(0, 2):   # a static coefficient (>= mu), or None
        grasp = exdex.replace(grasp, mu_static=mu + abs(_awkward(rng)))
    k = int(rng.integers(0, 3))   # pads on the fingers: none, a disc or a polygon
    if k == 1:
        grasp = exdex.replace(grasp, pad=exdex.Pad.disc(abs(_awkward(rng)) + 1e-3, center=tuple(rng.normal(size=2) * 0.01)))
    elif k == 2:
        a = np.sort(rng.uniform(0, 2 * np.pi, 5))
        grasp = exdex.replace(grasp, pad=exdex.Pad(vertices=tuple(zip(np.cos(a) * 0.01, np.sin(a) * 0.01)),
                                                   center=tuple(rng.normal(size=2) * 0.01), scale=abs(_awkward(rng)) + 1e-3))
    if grasp.patch.region() is not None and rng.integers(0, 2):   # the exact limit surface (a patch with a region)
        grasp = exdex.replace(grasp, limit_surface="exact")
    return grasp


def _touching(body, grasp, q0):
    """The grasp with its patch centre (or pad) moved onto the body's contact
    face where the drawn one misses it: a scene whose plates do not touch the
    object at t = 0 cannot be built (the draws stay as they were)."""
    try:
        face = body.contact_face()
    except ValueError:
        return grasp          # no face stated: nothing to touch
    try:
        exdex.Scene(body=body, grasp=grasp, q0=q0)
        return grasp
    except ValueError:
        pass
    centre = np.array(face["face_center"]) if "face_center" in face else np.mean(face["face"], axis=0)
    if grasp.pad is None:
        return exdex.replace(grasp, patch=exdex.replace(grasp.patch, center=tuple(centre)))
    c, s = math.cos(q0[2]), math.sin(q0[2])
    centre = np.array(q0[:2]) + np.array([[c, -s], [s, c]]) @ centre
    pad = grasp.pad
    if pad.vertices is not None:
        centre = centre - pad.scale * np.mean(np.array(pad.vertices), axis=0)
    moved = exdex.replace(grasp, pad=exdex.replace(pad, center=tuple(centre)))
    try:
        exdex.Scene(body=body, grasp=moved, q0=q0)
        return moved
    except ValueError:        # a pose like 1e16 m: no pad of this size overlaps the face in floats
        return exdex.replace(grasp, pad=None)


def random_scene(rng):
    dof = str(rng.choice(["translation", "rotation", "planar"]))
    stops = tuple(exdex.Stop(tuple(_awkward(rng, 3)), tuple(rng.normal(size=3)), mu=_awkward(rng, positive=True))
                  for _ in range(rng.integers(0, 9)))
    body, grasp, motion = _body(rng), _grasp(rng), _motion(rng)
    slide_axis, q0 = tuple(rng.normal(size=2)), tuple(_awkward(rng, 3))
    return exdex.Scene(
        body=body, grasp=_touching(body, grasp, q0), motion=motion, dof=dof, slide_axis=slide_axis, q0=q0,
        v0=tuple(_awkward(rng, 3)), gripper_rotation=random_rotation(rng), gripper_position=tuple(_awkward(rng, 3)),
        gravity=tuple(_awkward(rng, 3)), stops=stops)


def _same(a, b):
    """Equal scenes, and equal to the bit (the written text sees -0.0 and every digit)."""
    return a == b and io.dumps(a, "json") == io.dumps(b, "json") and repr(io.scene_to_dict(a)) == repr(
        io.scene_to_dict(b))


@pytest.mark.warns_by_design("noisy_log", "plausibility")  # random logs are normal draws, random bodies awkward
@pytest.mark.parametrize("fmt", ["toml", "json"])
def test_round_trip_random_scenes_is_exact(fmt, tmp_path):
    rng = np.random.default_rng(20261124)
    seen = set()
    scenes = []
    for i in range(300):
        sc = random_scene(rng)
        scenes.append(sc)
        seen.add((type(sc.motion).__name__, sc.dof, len(sc.stops) > 0, sc.grasp.patch.shape))
        path = tmp_path / f"s{i}.{fmt}"
        exdex.save_scene(sc, path)
        back = exdex.load_scene(path)
        assert _same(back, sc), path.read_text()
        # writing the loaded scene gives the same file, byte for byte
        assert io.dumps(back, fmt) == path.read_text()
    logs = [sc.motion for sc in scenes if isinstance(sc.motion, exdex.SampledTrajectory)]
    assert any(m.tool is not None for m in logs) and any(m.relative for m in logs)
    assert any(m.end_velocity is not None for m in logs) and any(m.start_omega is not None for m in logs)
    motions = {m for m, *_ in seen}
    assert motions == {"Rest", "AsymmetricProfile", "TrapezoidalProfile", "SampledTrajectory"}
    assert {d for _, d, *_ in seen} == {"translation", "rotation", "planar"}
    assert {p for *_, p in seen} == {"given", "disc", "rectangle"}


@pytest.mark.warns_by_design("noisy_log", "plausibility")  # random logs are normal draws, random bodies awkward
@pytest.mark.parametrize("fmt", ["toml", "json"])
def test_round_trip_obstacles_is_exact(fmt, tmp_path):
    """Scenes with boxes, half-space intersections and rods (awkward floats)
    load back equal and write the same text again."""
    rng = np.random.default_rng(20261126)
    for i in range(40):
        obs = []
        for _ in range(rng.integers(1, 5)):
            k = rng.integers(0, 3)
            if k == 0:
                obs.append(exdex.Obstacle.box(tuple(_awkward(rng, 3)), tuple(rng.uniform(0.01, 1.0, 3)),
                                              rotation=random_rotation(rng), mu=abs(_awkward(rng))))
            elif k == 1:
                n = int(rng.integers(1, 7))
                obs.append(exdex.Obstacle.halfspaces(rng.normal(size=(n, 3)), _awkward(rng, n)))
            else:
                obs.append(exdex.Obstacle.cylinder(tuple(_awkward(rng, 3)), tuple(rng.normal(size=3)),
                                                   float(rng.uniform(0.001, 0.1))))
        sc = exdex.replace(random_scene(rng), obstacles=tuple(obs))
        path = tmp_path / f"o{i}.{fmt}"
        exdex.save_scene(sc, path)
        back = exdex.load_scene(path)
        assert _same(back, sc), path.read_text()
        assert io.dumps(back, fmt) == path.read_text()


def test_sampled_trajectory_arrays_round_trip_to_the_bit(tmp_path):
    rng = np.random.default_rng(7)
    n = 500
    t = np.cumsum(rng.uniform(1e-4, 1e-2, n))
    p = rng.normal(size=(n, 3)) * 10.0 ** rng.integers(-12, 3, size=(n, 3)).astype(float)
    q = rng.normal(size=(n, 4))
    p[0, 0], p[1, 1], q[2, 2] = -0.0, 5e-324, 0.1 + 0.2
    sc = exdex.Scene(body=exdex.Body(0.2), grasp=exdex.Grasp(0.5, 2.0), motion=exdex.SampledTrajectory(t, p, q))
    for fmt in ("toml", "json"):
        path = tmp_path / f"log.{fmt}"
        exdex.save_scene(sc, path)
        m = exdex.load_scene(path).motion
        for name, a in (("times", t), ("positions", p), ("quaternions", q)):
            b = getattr(m, name)
            assert b.dtype == np.float64 and b.shape == a.shape
            assert b.tobytes() == a.tobytes(), name  # bitwise, sign of zero included


@pytest.mark.warns_by_design("impact", "pad", "outline")
def test_loaded_scene_simulates_bit_identically(tmp_path):
    """A scene and its reload give bit-identical trajectories with every method."""
    sc = exdex.Scene(body=exdex.Body.box(0.1, (0.04, 0.06, 0.02)),
                     grasp=exdex.Grasp(mu=0.4, grip_force=1.2, patch=exdex.Patch.disc(0.01, center=(0.003, 0.0))),
                     motion=exdex.AsymmetricProfile(0.1, 0.4, 0.8, axis=(1, 0, -1)), dof="planar",
                     stops=(exdex.Stop((0, 0, -0.09), (0.1, 0, 1)),), q0=(0.0, 0.0, 0.1))
    exdex.save_scene(sc, tmp_path / "s.toml")
    back = exdex.load_scene(tmp_path / "s.toml")
    for method in ("implicit", "explicit"):
        a = exdex.simulate(sc, 1.0, 2e-3, method=method)
        b = exdex.simulate(back, 1.0, 2e-3, method=method)
        assert a.q.tobytes() == b.q.tobytes() and a.wrench.tobytes() == b.wrench.tobytes()


def test_hand_written_toml_takes_the_defaults(tmp_path):
    text = """
schema = 1
dof = "planar"

[body]
mass = 0.1

[grasp]
mu = 0.5
grip_force = 1.5

[motion]
type = "AsymmetricProfile"
amplitude = 0.1
duration = 0.5
beta = 0.9
axis = [0, 0, -1]

[[stops]]
point = [0, 0, -0.2]
normal = [0, 0, 1]
"""
    (tmp_path / "a.toml").write_text(text)
    want = exdex.Scene(body=exdex.Body(mass=0.1), grasp=exdex.Grasp(mu=0.5, grip_force=1.5),
                       motion=exdex.AsymmetricProfile(0.1, 0.5, 0.9, axis=(0, 0, -1)), dof="planar",
                       stops=(exdex.Stop((0, 0, -0.2), (0, 0, 1)),))
    assert exdex.load_scene(tmp_path / "a.toml") == want


def test_simulate_options_round_trip_and_checks(tmp_path):
    sc = exdex.Scene(body=exdex.Body(0.1), grasp=exdex.Grasp(0.5, 1.5))
    opts = dict(t_end=1.25, dt=1e-3, method="event", rtol=1e-9)
    for fmt in ("toml", "json"):
        exdex.save_scene(sc, tmp_path / f"s.{fmt}", simulate=opts)
        assert io.load_simulate_options(tmp_path / f"s.{fmt}") == opts
        assert exdex.load_scene(tmp_path / f"s.{fmt}") == sc
    with pytest.raises(ValueError, match="'tend'.*allowed"):
        io.dumps(sc, simulate=dict(tend=1.0))
    with pytest.raises(ValueError, match="method must be a string"):
        io.dumps(sc, simulate=dict(method=3))


@pytest.mark.parametrize("edit, message", [
    (lambda d: d.update(schema=5), r"unsupported scene-file schema 5.*reads schema 1, 2, 3, 4"),
    (lambda d: d.update(schema="1"), r"unsupported scene-file schema '1'"),
    (lambda d: d.pop("schema"), r"missing key in scene: 'schema'"),
    (lambda d: d["grasp"].update(frction=0.3), r"unknown key in scene\.grasp: 'frction'; allowed: .*mu"),
    (lambda d: d.update(gravty=[0, 0, -9.8], stopz=[]), r"unknown keys in scene: 'gravty', 'stopz'"),
    (lambda d: d["grasp"]["patch"].update(radius=0.01), r"unknown key in scene\.grasp\.patch: 'radius'"),
    (lambda d: d["body"].pop("mass"), r"missing key in scene\.body: 'mass'"),
    (lambda d: d["motion"].update(type="Spline"), r"unknown scene\.motion\.type 'Spline'; allowed: Rest"),
    (lambda d: d["motion"].pop("type"), r"missing key in scene\.motion: 'type'"),
    (lambda d: d["motion"].update(beta2=0.3), r"unknown key in scene\.motion \(AsymmetricProfile\): 'beta2'"),
    (lambda d: d["stops"][0].update(depth=1), r"unknown key in scene\.stops\[0\]: 'depth'"),
    (lambda d: d.update(stops={"point": [0, 0, 0]}), r"scene\.stops must be a list"),
    (lambda d: d["body"].update(mass=-1.0), r"Body\.mass must be in \(0, inf\)"),
])
@pytest.mark.parametrize("fmt", ["toml", "json"])
def test_bad_files_name_the_problem(edit, message, fmt, tmp_path):
    sc = exdex.Scene(body=exdex.Body(0.1), grasp=exdex.Grasp(0.5, 1.5),
                     motion=exdex.AsymmetricProfile(0.1, 0.5, 0.9), stops=(exdex.Stop((0, 0, -1), (0, 0, 1)),))
    d = io.scene_to_dict(sc)
    edit(d)
    path = tmp_path / f"bad.{fmt}"
    path.write_text(io._toml_dumps(d) if fmt == "toml" else json.dumps(d))
    with pytest.raises(ValueError, match=message) as info:
        exdex.load_scene(path)
    assert str(path) in str(info.value)  # the file is named too


def test_format_errors(tmp_path):
    sc = exdex.Scene(body=exdex.Body(0.1), grasp=exdex.Grasp(0.5, 1.5))
    with pytest.raises(ValueError, match=r"extension '\.yaml'.*\.toml or \.json"):
        exdex.save_scene(sc, tmp_path / "s.yaml")
    exdex.save_scene(sc, tmp_path / "s.txt", format="json")
    assert exdex.load_scene(tmp_path / "s.txt", format="json") == sc
    (tmp_path / "broken.toml").write_text("schema = 1\n[body\n")
    with pytest.raises(ValueError, match="not valid TOML"):
        exdex.load_scene(tmp_path / "broken.toml")
    (tmp_path / "broken.json").write_text("{\"schema\": 1,")
    with pytest.raises(ValueError, match="not valid JSON"):
        exdex.load_scene(tmp_path / "broken.json")
    with pytest.raises(TypeError, match="scene must be an exdex.Scene"):
        exdex.save_scene({"body": 1}, tmp_path / "x.toml")


def test_toml_writer_strings_and_keys_round_trip():
    """The TOML writer against Python's TOML reader on strings needing escapes."""
    tomllib = pytest.importorskip("tomllib")
    d = {"a": 'quote " backslash \\ tab \t nl \n é ∑', "odd key": [1, -0.0, True, "x"], "t": {"u": [[1.5], []]}}
    assert repr(tomllib.loads(io._toml_dumps(d))) == repr(d)


# ---------------------------------------------------------------- exdex run


def test_the_schema_covers_every_scene_field_and_motion():
    """The round-trip tests above generate these fields and motions: a field or
    motion added to the scene objects must be added to them (and to the file
    format, if it holds more than numbers, strings and lists)."""
    import dataclasses

    fields = {cls.__name__: [f.name for f in dataclasses.fields(cls)]
              for cls in (exdex.Scene, exdex.Body, exdex.Grasp, exdex.Patch, exdex.Pad, exdex.Stop, exdex.Obstacle)}
    assert fields == {
        "Scene": ["body", "grasp", "motion", "dof", "slide_axis", "q0", "v0", "gripper_rotation",
                  "gripper_position", "gravity", "stops", "obstacles"],
        "Body": ["mass", "inertia", "size", "outline", "outline_radius", "outline_center"],
        "Grasp": ["mu", "grip_force", "patch", "fingers", "mu_static", "pad", "limit_surface"],
        "Patch": ["e_r", "center", "shape", "dims"],
        "Pad": ["vertices", "radius", "center", "scale"],
        "Stop": ["point", "normal", "mu"],
        "Obstacle": ["kind", "face_points", "face_normals", "center", "axis", "radius", "mu"],
    }
    motion_fields = {name: [f.name for f in dataclasses.fields(cls)] for name, cls in io.MOTIONS.items()}
    assert motion_fields == {
        "Rest": [],
        "AsymmetricProfile": ["amplitude", "duration", "beta", "axis", "rotation", "center"],
        "TrapezoidalProfile": ["amplitude", "duration", "v_max", "axis", "rotation", "center"],
        "SampledTrajectory": ["times", "positions", "quaternions", "start_velocity", "start_omega",
                              "end_velocity", "end_omega", "relative", "tool", "noise"],
        "Shake": ["amplitude", "frequency", "cycles", "duration", "axis", "rotation", "center"],
        "Pause": ["duration"],
        "Chain": ["pieces", "allow_jump"],
    }
    assert sorted(io.MOTIONS) == ["AsymmetricProfile", "Chain", "Pause", "Rest", "SampledTrajectory", "Shake",
                                  "TrapezoidalProfile"]


@pytest.mark.parametrize("fmt", ["toml", "json"])
def test_round_trip_shake_pause_chain_is_exact(fmt, tmp_path):
    """Chains hold other motions (a log included): written as a list of
    motion tables and loaded back to the bit."""
    rng = np.random.default_rng(7)
    log = exdex.SampledTrajectory(np.cumsum(rng.uniform(0.01, 0.1, 6)), rng.normal(size=(6, 3)) * 0.1,
                                  rng.normal(size=(6, 4)), relative=True)
    for motion in (exdex.Shake(0.01 / 3, 2.7, cycles=3.3, axis=(0, 1, 1), rotation=True, center=(0.1, 0, 0)),
                   exdex.Pause(0.3),
                   exdex.Chain([exdex.Pause(0.2), exdex.Shake(-0.02, 1.5, duration=0.7), log,
                                exdex.AsymmetricProfile(0.1, 0.5, 0.9)], allow_jump=True)):
        sc = exdex.Scene(body=exdex.Body(0.1), grasp=exdex.Grasp(0.5, 1.0), motion=motion)
        path = tmp_path / f"s.{fmt}"
        exdex.save_scene(sc, path)
        back = exdex.load_scene(path)
        assert _same(back, sc), path.read_text()
        assert io.dumps(back, fmt) == path.read_text()


def test_schema_3_limit_surface_and_older_files(tmp_path):
    """grasp.limit_surface is schema 3: written and read back; a schema 1 or 2
    file without it loads as the ellipsoid, one with it is refused naming the
    key and the schema it needs."""
    sc = exdex.Scene(body=exdex.Body(0.1), grasp=exdex.Grasp(0.5, 1.5, exdex.Patch.disc(0.01), limit_surface="exact"))
    exdex.save_scene(sc, tmp_path / "s.toml")
    text = (tmp_path / "s.toml").read_text()
    assert f"schema = {io.SCHEMA_VERSION}" in text and 'limit_surface = "exact"' in text
    assert exdex.load_scene(tmp_path / "s.toml") == sc
    for version in (1, 2):
        old = text.replace(f"schema = {io.SCHEMA_VERSION}", f"schema = {version}")
        (tmp_path / "old.toml").write_text(old.replace('limit_surface = "exact"\n', ""))
        back = exdex.load_scene(tmp_path / "old.toml")
        assert back.grasp.limit_surface == "ellipsoid" and back == exdex.replace(sc, grasp=exdex.replace(sc.grasp, limit_surface="ellipsoid"))
        (tmp_path / "old.toml").write_text(old)
        with pytest.raises(ValueError, match=r"unknown key in scene.grasp: 'limit_surface'.*schema 3"):
            exdex.load_scene(tmp_path / "old.toml")


@pytest.mark.parametrize("fmt", ["toml", "json"])
def test_log_noise_round_trips_and_needs_schema_4(fmt, tmp_path):
    """SampledTrajectory.noise is written (as the pair) and read back; the
    loaded log smooths to the same knots, bit for bit (a plain function of
    the file's numbers); a schema 1 to 3 file with it is refused naming the
    key and the schema (also inside a Chain)."""
    pytest.importorskip("scipy")
    t = np.linspace(0.0, 1.0, 41)
    rng = np.random.default_rng(3)
    pos = np.outer(t**3 * (10 - 15 * t + 6 * t * t), [0.1, 0.0, 0.0]) + rng.normal(scale=1e-4, size=(41, 3))
    log = exdex.SampledTrajectory(t, pos, np.tile([1.0, 0.0, 0.0, 0.0], (41, 1)), noise=(1e-4, 2e-4))
    sc = exdex.Scene(body=exdex.Body(0.1), grasp=exdex.Grasp(0.5, 1.5), motion=log)
    path = tmp_path / f"log.{fmt}"
    exdex.save_scene(sc, path)
    back = exdex.load_scene(path)
    assert _same(back, sc) and back.motion.noise == (1e-4, 2e-4)
    np.testing.assert_array_equal(back.motion._spec()["motion_poses"], log._spec()["motion_poses"])
    assert not np.array_equal(log._spec()["motion_poses"][:, :3], pos)   # smoothed, not the raw samples
    d = io.scene_to_dict(sc)
    assert d["motion"]["noise"] == [1e-4, 2e-4]
    d["schema"] = 3
    with pytest.raises(ValueError, match=r"unknown key in scene.motion: 'noise'.*schema 4"):
        io.scene_from_dict(d)
    d["motion"] = {"type": "Chain", "pieces": [dict(d["motion"])]}
    with pytest.raises(ValueError, match=r"scene.motion.pieces\[0\]: 'noise'.*schema 4"):
        io.scene_from_dict(d)
    del d["motion"]["pieces"][0]["noise"]
    with pytest.warns(exdex.NoisyLogWarning, match="noise="):   # the raw log: its noise dominates
        assert io.scene_from_dict(d).motion.pieces[0].noise is None

"""Scenes as files: save and load an :class:`exdex.Scene` in JSON or TOML.

    >>> exdex.save_scene(scene, "drop.toml")        # or "drop.json"
    >>> scene = exdex.load_scene("drop.toml")
    >>> scene == exdex.load_scene("drop.toml")
    True

The format is chosen by the file extension (``.json`` or ``.toml``). A file
holds one scene as nested tables whose keys are the constructor arguments of
the scene objects, plus a ``schema`` version number::

    schema = 4
    dof = "translation"
    q0 = [0.0, 0.0, 0.0]
    ...

    [body]
    mass = 0.1
    inertia = [[1e-05, 0.0, 0.0], [0.0, 1e-05, 0.0], [0.0, 0.0, 1e-05]]

    [grasp]
    mu = 0.5
    grip_force = 1.5
    fingers = 2
    limit_surface = "ellipsoid"    # or "exact" (a patch with a region)

    [grasp.patch]
    e_r = 0.01
    center = [0.0, 0.0]

    [grasp.pad]                    # optional: pads on the fingers (exdex.Pad)
    vertices = [[-0.01, -0.01], [0.01, -0.01], [0.01, 0.01], [-0.01, 0.01]]
    center = [0.0, 0.0]

    [motion]
    type = "AsymmetricProfile"     # Rest, AsymmetricProfile, TrapezoidalProfile, SampledTrajectory
    amplitude = 0.1
    duration = 0.5
    beta = 0.9

    [[stops]]
    point = [0.0, 0.0, -0.05]
    normal = [0.0, 0.0, 1.0]

    [[obstacles]]                  # Obstacle: "halfspaces" or "cylinder"
    kind = "cylinder"
    center = [0.05, 0.0, -0.1]
    axis = [0.0, 1.0, 0.0]
    radius = 0.01

    [simulate]                     # optional: defaults for `exdex run`
    t_end = 1.5
    dt = 0.001
    method = "implicit"

Keys left out take the constructors' defaults, so a hand-written file only
needs what differs from them (``body.mass``, ``grasp.mu``,
``grasp.grip_force``; ``motion.type`` and that motion's arguments). Files
written by :func:`save_scene` list every field, and loading them gives back
an equal scene: floats are written in their shortest exact decimal form, so
every number, including the arrays of a :class:`exdex.SampledTrajectory`,
comes back bit for bit.

A grip force that varies in time (an :class:`exdex.GripSchedule`) is a
table in place of the number::

    [grasp.grip_force]
    times = [0.0, 0.2, 0.4]
    forces = [1.5, 1.5, 0.5]
    kind = "linear"

Schema 2 added ``grasp.pad``, schema 3 ``grasp.limit_surface``, schema 4
a log's ``noise`` (``SampledTrajectory.noise``); files of an older schema
(without them) load as before.
An unknown ``schema`` version, an unknown key or a missing required key is
a ``ValueError`` naming it; the scene objects then check their own values
(ranges, shapes) as when built in Python.
"""
from __future__ import annotations

import dataclasses
import importlib
import json
import math
import os
import re

from typing import Any, Dict, Mapping, Optional, Union

import numpy as np

from exdex import scene as _scene

PathLike = Union[str, "os.PathLike[str]"]

__all__ = ["SCHEMA_VERSION", "save_scene", "load_scene", "load_simulate_options", "scene_to_dict",
           "scene_from_dict", "dumps", "loads"]

#: Version of the scene-file schema written by :func:`save_scene`.
SCHEMA_VERSION = 4
SUPPORTED_SCHEMAS = (1, 2, 3, 4)

def _motion_classes() -> Dict[str, type]:
    """Every gripper motion class (the subclasses of the scenes' motion base), by name."""
    out: Dict[str, type] = {}
    todo = list(_scene._Motion.__subclasses__())
    while todo:
        cls = todo.pop(0)
        if not cls.__name__.startswith("_"):
            out[cls.__name__] = cls
        todo.extend(cls.__subclasses__())
    return out


#: Gripper motions by the name used in the ``motion.type`` key.
MOTIONS = _motion_classes()

#: Keys of the optional ``simulate`` table: arguments of :func:`exdex.simulate`.
SIMULATE_KEYS = {"t_end": float, "dt": float, "method": str, "friction_solver": str, "eps": float,
                 "rtol": float, "atol": float}

FORMATS = {".json": "json", ".toml": "toml"}


# ---------------------------------------------------------------- to plain data

def _plain(value):
    """Python data of a field value: floats, ints, bools, strings and lists."""
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, (tuple, list)):
        return [_plain(v) for v in value]
    if isinstance(value, (bool, str)) or value is None:
        return value
    if isinstance(value, (int, np.integer)):
        return int(value)
    if isinstance(value, (float, np.floating)):
        return float(value)
    if dataclasses.is_dataclass(value):
        return _object_to_dict(value)
    raise TypeError(f"cannot write a value of type {type(value).__name__} to a scene file")


def _object_to_dict(obj):
    out = {}
    if isinstance(obj, _scene._Motion):
        out["type"] = type(obj).__name__
    for f in dataclasses.fields(obj):
        value = getattr(obj, f.name)
        if value is None:  # TOML has no null: a missing key means the default, None
            continue
        out[f.name] = _plain(value)
    return out


def scene_to_dict(scene: _scene.Scene) -> Dict[str, Any]:
    """The scene as plain Python data (dicts, lists, floats, strings): what
    :func:`save_scene` writes, with ``schema`` first."""
    if not isinstance(scene, _scene.Scene):
        raise TypeError(f"scene must be an exdex.Scene, got {type(scene).__name__}")
    d = {"schema": SCHEMA_VERSION}
    d.update(_object_to_dict(scene))
    return d


# ---------------------------------------------------------------- from plain data

def _fields(cls):
    return {f.name: f for f in dataclasses.fields(cls)}


def _check_keys(data, allowed, required, where):
    if not isinstance(data, dict):
        raise ValueError(f"{where} must be a table (a dict of keys), got {type(data).__name__}")
    unknown = [k for k in data if k not in allowed]
    if unknown:
        raise ValueError(f"unknown key{'s' if len(unknown) > 1 else ''} in {where}: "
                         f"{', '.join(map(repr, unknown))}; allowed: {', '.join(sorted(allowed))}")
    missing = [k for k in required if k not in data]
    if missing:
        raise ValueError(f"missing key{'s' if len(missing) > 1 else ''} in {where}: "
                         f"{', '.join(map(repr, missing))}")


def _required(cls):
    return [f.name for f in dataclasses.fields(cls)
            if f.default is dataclasses.MISSING and f.default_factory is dataclasses.MISSING]


def _build(cls, data, where, nested=None):
    """cls(**data) after checking the keys; ``nested`` maps a key to a builder."""
    allowed = set(_fields(cls))
    _check_keys(data, allowed, _required(cls), where)
    kwargs = {}
    for k, v in data.items():
        if nested and k in nested:
            v = nested[k](v, f"{where}.{k}")
        elif isinstance(v, list):
            v = _tuples(v)
        kwargs[k] = v
    return cls(**kwargs)


def _tuples(v):
    return tuple(_tuples(x) if isinstance(x, list) else x for x in v)


def _motion(data, where):
    if not isinstance(data, dict):
        raise ValueError(f"{where} must be a table with a 'type' key, got {type(data).__name__}")
    if "type" not in data:
        raise ValueError(f"missing key in {where}: 'type' (one of {', '.join(MOTIONS)})")
    kind = data["type"]
    if kind not in MOTIONS:
        raise ValueError(f"unknown {where}.type {kind!r}; allowed: {', '.join(MOTIONS)}")
    cls = MOTIONS[kind]
    rest = {k: v for k, v in data.items() if k != "type"}
    if cls is _scene.Chain:
        _check_keys(rest, set(_fields(cls)), _required(cls), f"{where} ({kind})")
        pieces = rest.get("pieces")
        if not isinstance(pieces, list):
            raise ValueError(f"{where}.pieces must be a list of motion tables, got {type(pieces).__name__}")
        rest["pieces"] = tuple(_motion(p, f"{where}.pieces[{i}]") for i, p in enumerate(pieces))
        return cls(**rest)
    if cls is _scene.SampledTrajectory:
        _check_keys(rest, set(_fields(cls)), _required(cls), f"{where} ({kind})")
        return cls(**{k: np.array(v, dtype=np.float64) if isinstance(v, list) else v for k, v in rest.items()})
    return _build(cls, rest, f"{where} ({kind})")


def _patch(data, where):
    return _build(_scene.Patch, data, where)


def _grip(data, where):
    """A grip force: a number, or a table (times, forces, kind) of a GripSchedule."""
    if isinstance(data, dict):
        return _build(_scene.GripSchedule, data, where)
    return data


def _pad(data, where):
    return _build(_scene.Pad, data, where)


def _grasp(data, where):
    return _build(_scene.Grasp, data, where, nested={"patch": _patch, "grip_force": _grip, "pad": _pad})


def _body(data, where):
    return _build(_scene.Body, data, where)


def _stops(data, where):
    if not isinstance(data, list):
        raise ValueError(f"{where} must be a list of tables (point, normal, mu), got {type(data).__name__}")
    return tuple(_build(_scene.Stop, s, f"{where}[{i}]") for i, s in enumerate(data))


def _obstacles(data, where):
    if not isinstance(data, list):
        raise ValueError(f"{where} must be a list of tables (kind, face_points, face_normals, center, axis, "
                         f"radius), got {type(data).__name__}")
    return tuple(_build(_scene.Obstacle, o, f"{where}[{i}]") for i, o in enumerate(data))


def _check_schema(data, where="scene"):
    if not isinstance(data, dict):
        raise ValueError(f"{where} must be a table (a dict of keys), got {type(data).__name__}")
    if "schema" not in data:
        raise ValueError(f"missing key in {where}: 'schema' (the scene-file schema version; "
                         f"this exdex reads {', '.join(map(str, SUPPORTED_SCHEMAS))})")
    version = data["schema"]
    if isinstance(version, bool) or version not in SUPPORTED_SCHEMAS:
        raise ValueError(f"unsupported scene-file schema {version!r}: this exdex reads schema "
                         f"{', '.join(map(str, SUPPORTED_SCHEMAS))}")


def scene_from_dict(data: Mapping[str, Any], where: str = "scene") -> _scene.Scene:
    """An :class:`exdex.Scene` from the plain data of :func:`scene_to_dict`
    (a ``simulate`` table, if present, is checked and ignored)."""
    _check_schema(data, where)
    if data["schema"] == 1 and isinstance(data.get("grasp"), dict) and "pad" in data["grasp"]:
        raise ValueError(f"unknown key in {where}.grasp: 'pad' (pads on the fingers need schema 2)")
    if data["schema"] < 3 and isinstance(data.get("grasp"), dict) and "limit_surface" in data["grasp"]:
        raise ValueError(f"unknown key in {where}.grasp: 'limit_surface' (the limit surface needs schema 3)")
    if data["schema"] < 4:
        _refuse_log_noise(data.get("motion"), f"{where}.motion")
    body = {k: v for k, v in data.items() if k not in ("schema", "simulate")}
    if "simulate" in data:
        _simulate_options(data["simulate"], f"{where}.simulate")
    return _build(_scene.Scene, body, where,
                  nested={"body": _body, "grasp": _grasp, "motion": _motion, "stops": _stops,
                          "obstacles": _obstacles})


def _refuse_log_noise(motion, where):
    """A log's noise in a file of schema 1 to 3 (chains searched too): the error naming the schema."""
    if not isinstance(motion, dict):
        return
    if motion.get("type") == "SampledTrajectory" and "noise" in motion:
        raise ValueError(f"unknown key in {where}: 'noise' (a log's noise needs schema 4)")
    if motion.get("type") == "Chain" and isinstance(motion.get("pieces"), list):
        for i, p in enumerate(motion["pieces"]):
            _refuse_log_noise(p, f"{where}.pieces[{i}]")


def _simulate_options(data, where):
    _check_keys(data, set(SIMULATE_KEYS), (), where)
    out = {}
    for k, v in data.items():
        kind = SIMULATE_KEYS[k]
        ok = isinstance(v, str) if kind is str else (isinstance(v, (int, float)) and not isinstance(v, bool))
        if not ok:
            raise ValueError(f"{where}.{k} must be a {'string' if kind is str else 'number'}, got {v!r}")
        out[k] = kind(v)
    return out


# ---------------------------------------------------------------- text formats

def _json_value(v, indent, level):
    pad = " " * (indent * (level + 1))
    end = " " * (indent * level)
    if isinstance(v, dict):
        if not v:
            return "{}"
        items = [f"{pad}{json.dumps(k)}: {_json_value(x, indent, level + 1)}" for k, x in v.items()]
        return "{\n" + ",\n".join(items) + "\n" + end + "}"
    if isinstance(v, list):
        if not v:
            return "[]"
        if all(not isinstance(x, (dict, list)) for x in v):
            return "[" + ", ".join(_json_value(x, indent, level) for x in v) + "]"
        return "[\n" + ",\n".join(pad + _json_value(x, indent, level + 1) for x in v) + "\n" + end + "]"
    if isinstance(v, float):
        if not math.isfinite(v):
            raise ValueError(f"cannot write the non-finite number {v} to JSON")
        return repr(v)  # shortest decimal that reads back to the same double
    return json.dumps(v)


_BARE_KEY = re.compile(r"^[A-Za-z0-9_-]+$")


def _toml_key(k):
    return k if _BARE_KEY.match(k) else json.dumps(k)


def _toml_scalar(v):
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        if math.isnan(v):
            return "nan"
        if math.isinf(v):
            return "inf" if v > 0 else "-inf"
        return repr(v)  # e.g. 0.1, 1e-05, -0.0, 1e+16: all valid TOML floats, exact on reading
    if isinstance(v, str):
        return json.dumps(v)  # a TOML basic string: JSON's escapes are TOML's (ASCII output)
    raise TypeError(f"cannot write a value of type {type(v).__name__} to TOML")


def _toml_array(v, level=0):
    if not v:
        return "[]"
    if all(not isinstance(x, list) for x in v):
        return "[" + ", ".join(_toml_scalar(x) for x in v) + "]"
    pad = "  " * (level + 1)
    return "[\n" + "".join(f"{pad}{_toml_array(x, level + 1)},\n" for x in v) + "  " * level + "]"


def _is_table_list(v):
    return isinstance(v, list) and v and all(isinstance(x, dict) for x in v)


def _toml_table(d, prefix, lines):
    for k, v in d.items():
        if isinstance(v, dict) or _is_table_list(v):
            continue
        if isinstance(v, list):
            if any(isinstance(x, dict) for x in v):
                raise TypeError(f"cannot write a list mixing tables and values to TOML ({k})")
            lines.append(f"{_toml_key(k)} = {_toml_array(v)}")
        else:
            lines.append(f"{_toml_key(k)} = {_toml_scalar(v)}")
    for k, v in d.items():
        name = f"{prefix}.{_toml_key(k)}" if prefix else _toml_key(k)
        if isinstance(v, dict):
            lines.append("")
            lines.append(f"[{name}]")
            _toml_table(v, name, lines)
        elif _is_table_list(v):
            for item in v:
                lines.append("")
                lines.append(f"[[{name}]]")
                _toml_table(item, name, lines)


def _toml_dumps(d):
    lines = []
    _toml_table(d, "", lines)
    return "\n".join(lines) + "\n"


def _toml_loads(text):
    try:
        tomllib = importlib.import_module("tomllib")
    except ImportError:  # Python < 3.11
        try:
            tomllib = importlib.import_module("tomli")
        except ImportError:
            raise ImportError("reading TOML scene files needs Python 3.11+ (tomllib) or the tomli "
                              "package (pip install tomli); JSON files need nothing") from None
    return tomllib.loads(text)


def dumps(scene: _scene.Scene, format: str = "toml", simulate: Optional[Mapping[str, Any]] = None) -> str:
    """The text of a scene file (``format`` "toml" or "json"); ``simulate``
    an optional dict of :func:`exdex.simulate` arguments stored with it."""
    d = scene_to_dict(scene)
    if simulate is not None:
        d["simulate"] = _simulate_options(dict(simulate), "simulate")
    if format == "json":
        return _json_value(d, 2, 0) + "\n"
    if format == "toml":
        return _toml_dumps(d)
    raise ValueError(f"format must be 'toml' or 'json', got {format!r}")


def _parse(text, format, where):
    if format == "json":
        try:
            return json.loads(text)
        except json.JSONDecodeError as exc:
            raise ValueError(f"{where} is not valid JSON: {exc}") from None
    if format == "toml":
        data = None
        try:
            data = _toml_loads(text)
        except ValueError as exc:  # tomllib.TOMLDecodeError is a ValueError
            raise ValueError(f"{where} is not valid TOML: {exc}") from None
        return data
    raise ValueError(f"format must be 'toml' or 'json', got {format!r}")


def loads(text: str, format: str = "toml") -> _scene.Scene:
    """An :class:`exdex.Scene` from the text of a scene file."""
    return scene_from_dict(_parse(text, format, "scene text"))


def _format(path, format):
    if format is not None:
        if format not in ("json", "toml"):
            raise ValueError(f"format must be 'toml' or 'json', got {format!r}")
        return format
    ext = os.path.splitext(os.fspath(path))[1].lower()
    if ext not in FORMATS:
        raise ValueError(f"cannot tell the scene-file format from the extension {ext!r} of {os.fspath(path)!r}: "
                         "use .toml or .json, or name the format: format='toml' or 'json' in Python, "
                         "--scene-format toml or json on the exdex command line")
    return FORMATS[ext]


def save_scene(scene: _scene.Scene, path: PathLike, *, simulate: Optional[Mapping[str, Any]] = None,
               format: Optional[str] = None) -> PathLike:
    """Write ``scene`` to ``path`` as TOML or JSON (by the extension, ``.toml``
    or ``.json``, unless ``format`` says). ``simulate``: an optional dict of
    :func:`exdex.simulate` arguments (t_end, dt, method, friction_solver,
    eps, rtol, atol) stored in the file's ``simulate`` table, which
    ``exdex run`` uses as its defaults. Returns the path."""
    fmt = _format(path, format)
    text = dumps(scene, fmt, simulate=simulate)
    with open(path, "w", encoding="utf-8") as f:
        f.write(text)
    return path


def _read(path, format):
    fmt = _format(path, format)
    with open(path, encoding="utf-8") as f:
        text = f.read()
    return _parse(text, fmt, os.fspath(path))


def load_scene(path: PathLike, *, format: Optional[str] = None) -> _scene.Scene:
    """The :class:`exdex.Scene` stored in a TOML or JSON file (by the extension
    unless ``format`` says). Raises ``ValueError`` naming an unsupported
    schema version, an unknown or a missing key, and the scene objects'
    own errors for values out of range."""
    data = _read(path, format)
    try:
        return scene_from_dict(data)
    except (ValueError, TypeError) as exc:
        raise type(exc)(f"{os.fspath(path)}: {exc}") from None


def load_simulate_options(path: PathLike, *, format: Optional[str] = None) -> Dict[str, Any]:
    """The ``simulate`` table of a scene file as a dict of :func:`exdex.simulate`
    arguments (empty when the file has none)."""
    data = _read(path, format)
    try:
        _check_schema(data)
        return _simulate_options(data.get("simulate", {}), "scene.simulate")
    except (ValueError, TypeError) as exc:
        raise type(exc)(f"{os.fspath(path)}: {exc}") from None

"""The scene parameters a batch, a plan or a fit can vary: their names, the
Scene field each replaces and its allowed range; the scene with new values."""
import dataclasses
from dataclasses import dataclass
from typing import Dict, Optional, Tuple, Union

from exdex.scene import AsymmetricProfile, GripSchedule, TrapezoidalProfile

__all__ = ["PARAMETERS", "ALIASES", "param_name", "replace_params", "unread"]


@dataclass(frozen=True)
class _Param:
    path: Tuple[Union[str, int], ...]   # attribute names, or an index into a tuple field     # dataclass fields from the Scene down, for dataclasses.replace
    key: str                  # the scalar of Scene.to_spec() (and exdex_scene_def) it sets
    low: Optional[float]      # bounds, as in the dataclass's own validation
    high: Optional[float]
    low_open: bool
    high_open: bool
    motions: Tuple[type, ...] = ()   # motion classes that have the field (empty: any scene)

    def describe(self):
        lo = "-inf" if self.low is None else f"{self.low:g}"
        hi = "inf" if self.high is None else f"{self.high:g}"
        lb = "(" if self.low_open or self.low is None else "["
        hb = ")" if self.high_open or self.high is None else "]"
        return f"{lb}{lo}, {hi}{hb}"


_MOTIONS = (AsymmetricProfile, TrapezoidalProfile)

#: Parameters a batch can vary: name -> the Scene field it replaces
#: (``dataclasses.replace`` along ``path``), the spec key and the allowed range.
PARAMETERS: Dict[str, _Param] = {
    "mass": _Param(("body", "mass"), "mass", 0.0, None, True, False),
    "mu": _Param(("grasp", "mu"), "mu", 0.0, None, False, False),
    "grip_force": _Param(("grasp", "grip_force"), "grip_force", 0.0, None, False, False),
    "e_r": _Param(("grasp", "patch", "e_r"), "e_r", 0.0, None, True, False),
    "amplitude": _Param(("motion", "amplitude"), "motion_amplitude", None, None, False, False, _MOTIONS),
    "duration": _Param(("motion", "duration"), "motion_duration", 0.0, None, True, False, _MOTIONS),
    "beta": _Param(("motion", "beta"), "motion_beta", 0.0, 1.0, True, True, (AsymmetricProfile,)),
    "v_max": _Param(("motion", "v_max"), "motion_v_max", 0.0, None, True, False, (TrapezoidalProfile,)),
    "mu_static": _Param(("grasp", "mu_static"), "mu_static", 0.0, None, False, False),
    # the pad centre in the object frame (the centre of mass is at its
    # negative from the pivot of a rotation scene) [m]
    "patch_x": _Param(("grasp", "patch", "center", 0), "patch_center_x", None, None, False, False),
    "patch_y": _Param(("grasp", "patch", "center", 1), "patch_center_y", None, None, False, False),
    # pads on the fingers (Grasp.pad): the pad's position on the plate in B [m],
    # a disc pad's radius [m] and a polygon pad's size factor
    "pad_x": _Param(("grasp", "pad", "center", 0), "pad_center_x", None, None, False, False),
    "pad_y": _Param(("grasp", "pad", "center", 1), "pad_center_y", None, None, False, False),
    "pad_radius": _Param(("grasp", "pad", "radius"), "pad_radius", 0.0, None, True, False),
    "pad_scale": _Param(("grasp", "pad", "scale"), "pad_scale", 0.0, None, True, False),
}

# names people reach for, pointing at ours
ALIASES = {"T": "duration", "X1": "amplitude", "theta1": "amplitude", "m": "mass", "grip": "grip_force",
            "F": "grip_force", "friction": "mu", "vmax": "v_max"}


def replace_params(scene, values):
    """dataclasses.replace along each parameter's path (validated by the dataclasses)."""
    for name, value in values.items():
        scene = _replace_path(scene, PARAMETERS[name].path, value)
    return scene


def _replace_path(obj, path, value):
    if isinstance(path[0], int):   # a component of a tuple field (Patch.center)
        items = list(obj)
        items[path[0]] = value
        return tuple(items)
    if len(path) == 1:
        if path[0] == "grip_force" and isinstance(getattr(obj, "grip_force"), GripSchedule):
            # on a grip schedule the batch's grip_force is a scale of it (the core's grip_force)
            value = obj.grip_force.scaled(value)
        return dataclasses.replace(obj, **{path[0]: value})
    return dataclasses.replace(obj, **{path[0]: _replace_path(getattr(obj, path[0]), path[1:], value)})


def unread(name, scene):
    """Why the scene's model does not read the parameter ``name`` (a
    sentence), or None where it does: the patch's e_r where the contact
    region gives the surface (limit_surface "exact", or pads on the fingers,
    whose region pad & face gives e_r too), and the patch centre with pads
    (the region's centroid is the centre of pressure)."""
    g = scene.grasp
    if name == "e_r" and g.pad is not None:
        return "with pads on the fingers the region pad & face gives e_r, not Patch.e_r"
    if name == "e_r" and g.limit_surface == "exact":
        return "the exact limit surface is that of the patch's region, not of Patch.e_r"
    if name in ("patch_x", "patch_y") and g.pad is not None:
        return "with pads on the fingers the region's centroid is the centre of pressure, not Patch.center"
    return None


def param_name(name, scene):
    name = ALIASES.get(name, name)
    if name not in PARAMETERS:
        raise ValueError(f"cannot vary {name!r}: the parameters are {sorted(PARAMETERS)}")
    p = PARAMETERS[name]
    if p.motions and not isinstance(scene.motion, p.motions):
        raise ValueError(f"cannot vary {name!r}: the scene's motion {type(scene.motion).__name__} has no such field")
    why = unread(name, scene)
    if why is not None:
        raise ValueError(f"cannot vary {name!r}: {why}")
    return name

"""Scenes: the object, the grasp, the gripper motion, stops and free coordinates.

Everything is a frozen dataclass, so ``dataclasses.replace(scene, grasp=...)``
makes a variant and scenes can be hashed, compared and shared between threads.

Units are SI (m, kg, s, rad, N). Frames (paper Section 2.1):

* **A** -- the world, fixed. Gravity is given in A (default ``(0, 0, -9.81)``,
  z up).
* **B** -- the gripper: origin on the plates' mid-plane, ``x`` and ``y`` span
  the plate plane, ``z`` is the plate normal (the fingers' closing direction).
  Its initial pose in A is ``Scene.gripper_rotation`` (R_AB) and
  ``Scene.gripper_position``; the default orientation has B's ``y`` pointing
  up (B x = A x, B y = A z, B z = -A y): plates vertical.
* **C** -- the object: origin at its centre of mass, ``z`` parallel to B's
  ``z``. Its pose in B is ``(x, y, theta)``.
"""
from __future__ import annotations

import dataclasses
import math
import numbers
import warnings
from dataclasses import dataclass, field
from typing import Any, Dict, Optional, Sequence, Tuple, TypeVar, Union

import numpy as np
from numpy.typing import ArrayLike, NDArray

from exdex import _core, _lognoise, diagnostics as _diagnostics
from exdex._rotations import quat_from_matrix as _quat_from_matrix
from exdex._validate import array as _array, real as _real

__all__ = [
    "Body", "Patch", "GripSchedule", "Grasp", "Rest", "AsymmetricProfile", "TrapezoidalProfile",
    "SampledTrajectory", "Shake", "Pause", "Chain", "Stop", "Obstacle", "Scene", "DEFAULT_GRIPPER_ROTATION",
    "quaternion_from_matrix",
]

#: B x = A x, B y = A z (up), B z = -A y: plates vertical, normal horizontal.
DEFAULT_GRIPPER_ROTATION = ((1.0, 0.0, 0.0), (0.0, 0.0, -1.0), (0.0, 1.0, 0.0))

_T = TypeVar("_T")

#: What a vector or matrix field accepts: a sequence (tuple, list) or a NumPy
#: array. Fields are stored as tuples of floats (arrays for SampledTrajectory).
Vector = Union[Sequence[float], NDArray[Any]]
Matrix = Union[Sequence[Sequence[float]], NDArray[Any]]

# Names of the C core's enums; the values are the constants exdex._core exports.
DOFS = {"translation": _core.DOF_TRANSLATION, "rotation": _core.DOF_ROTATION, "planar": _core.DOF_PLANAR}
METHODS = {"implicit": _core.METHOD_IMPLICIT, "event": _core.METHOD_EVENT,
           "regularised": _core.METHOD_REGULARISED, "explicit": _core.METHOD_EXPLICIT,
           "analytic": _core.METHOD_ANALYTIC}
SOLVERS = {"scalar": _core.SOLVER_SCALAR, "brent": _core.SOLVER_BRENT, "multiroot": _core.SOLVER_MULTIROOT}
GRIP_KINDS = {"linear": _core.GRIP_LINEAR, "cubic": _core.GRIP_CUBIC, "step": _core.GRIP_STEP}
#: Limit surfaces of the plate friction (Grasp.limit_surface), as the core's enum.
LIMIT_SURFACES = {"ellipsoid": 0, "exact": 1}


def quaternion_from_matrix(rotation: Matrix) -> NDArray[np.float64]:
    """The unit quaternion ``(w, x, y, z)`` with ``w >= 0`` of a 3x3 rotation
    matrix (the orientation format of :class:`SampledTrajectory`), e.g.
    ``quaternion_from_matrix(scene.gripper_rotation)``. ValueError unless
    ``rotation`` is orthonormal with determinant +1 (to 1e-9)."""
    R = _rotation(rotation, "rotation")
    q = _quat_from_matrix(np.array(R))
    q = q / np.linalg.norm(q)
    return -q if q[0] < 0 else q


# ---------------------------------------------------------------- validation

def _tuple(a):
    return tuple(_tuple(x) for x in a) if isinstance(a, np.ndarray) and a.ndim > 1 else tuple(float(x) for x in a)


def _unit(value, name, n):
    a = _array(value, name, (n,))
    norm = float(np.linalg.norm(a))
    if norm == 0.0:
        raise ValueError(f"{name} must be a non-zero vector")
    if abs(norm - 1.0) <= 8 * np.finfo(float).eps:
        # already unit up to rounding: kept as given, so normalising is idempotent (a saved
        # scene loads back bit for bit)
        return tuple(float(x) for x in a)
    return tuple(float(x) for x in a / norm)


def _rotation(value, name):
    R = _array(value, name, (3, 3))
    if not np.allclose(R @ R.T, np.eye(3), atol=1e-9) or np.linalg.det(R) < 0:
        raise ValueError(f"{name} must be a rotation matrix (orthonormal, det +1)")
    return _tuple(R)


# ---------------------------------------------------------------- plausibility

#: Densities [kg/m^3] outside which a body's mass and size give a PlausibilityWarning: below 10
#: (lighter than an empty paper box: a 15 cm cube of 34 g), above 25000 (denser than osmium,
#: 22590, the densest solid).
DENSITY_RANGE = (10.0, 25000.0)


def _plausibility(message, field, value, limit):
    warnings.warn(_diagnostics.PlausibilityWarning(message, field, value, limit),
                  stacklevel=_lognoise.user_stacklevel())


def _check_density(body):
    """A PlausibilityWarning for a mass whose density in the body's volume
    (its size: the box, the disc or the outline's area times the thickness)
    is outside DENSITY_RANGE."""
    if body.size is None:
        return
    lx, ly, lz = body.size
    if body.outline_radius is not None:
        vol, what = math.pi * body.outline_radius**2 * lz, f"cylinder of radius {body.outline_radius:g} m"
    else:   # a polygon outline may list only the corners that touch stops: the box bounds the volume
        vol, what = lx * ly * lz, f"{lx:g} x {ly:g} x {lz:g} m box"
    if vol <= 0.0:
        return
    rho = body.mass / vol
    lo, hi = DENSITY_RANGE
    if not lo <= rho <= hi:
        _plausibility(f"Body.mass = {body.mass:g} kg in a {what} (Body.size, {vol:.4g} m^3) is a density of "
                      f"{rho:.4g} kg/m^3, outside the {lo:g} .. {hi:g} kg/m^3 of objects a gripper holds (an empty "
                      f"paper box .. osmium): check Body.mass [kg] and Body.size [m]",
                      "Body.mass", rho, lo if rho < lo else hi)


def _hull(points):
    """Convex hull of (k, 2) points, counter-clockwise (Andrew's monotone chain)."""
    pts = sorted(set(map(tuple, np.asarray(points, dtype=float))))
    if len(pts) < 3:
        return np.array(pts)

    def half(seq):
        out = []
        for p in seq:
            while len(out) >= 2 and ((out[-1][0] - out[-2][0]) * (p[1] - out[-2][1])
                                     - (out[-1][1] - out[-2][1]) * (p[0] - out[-2][0])) <= 0:
                out.pop()
            out.append(p)
        return out
    lower, upper = half(pts), half(reversed(pts))
    return np.array(lower[:-1] + upper[:-1])


def _outside(hull, p):
    """Distance [m] of point p outside the convex polygon ``hull`` (ccw), 0 inside."""
    p = np.asarray(p, dtype=float)
    a, b = hull, np.roll(hull, -1, axis=0)
    e = b - a
    cross = e[:, 0] * (p[1] - a[:, 1]) - e[:, 1] * (p[0] - a[:, 0])
    if np.all(cross >= 0.0):
        return 0.0
    s = np.clip(np.einsum("ij,ij->i", p - a, e) / np.maximum(np.einsum("ij,ij->i", e, e), 1e-300), 0.0, 1.0)
    d = a + s[:, None] * e - p
    return float(np.min(np.hypot(d[:, 0], d[:, 1])))


def _separated(P, Q):
    """True when the convex polygons P and Q (ccw) share no area: some edge
    normal of either separates them (touching counts as separated)."""
    for poly in (P, Q):
        e = np.roll(poly, -1, axis=0) - poly
        for n in np.column_stack([e[:, 1], -e[:, 0]]):
            if n @ n == 0.0:
                continue
            pa, pb = P @ n, Q @ n
            if pa.max() <= pb.min() or pb.max() <= pa.min():
                return True
    return False


# ---------------------------------------------------------------- object and grasp

@dataclass(frozen=True)
class Body:
    """The grasped object.

    mass : kg, > 0.
    inertia : 3x3 inertia about the centre of mass in the object frame C
        (z = plate normal) [kg m^2], symmetric positive definite. A scalar is
        taken as I_zz of a body whose other principal moments equal it; a
        3-vector as the diagonal.
    size : (lx, ly, lz) box dimensions [m] (x, y in the plate plane, z across
        the plates), or None. Gives the outline used against stops (and the
        shape the physics-engine cross-checks build).
    outline : polygon vertices (k, 2) in C [m] touching stops; default: the
        box corners from ``size``, or the centre of mass alone.
    outline_radius : radius [m] > 0 of a disc outline, or None (a polygon
        outline). A disc touches each stop at its support point, the rim
        point nearest the stop, which moves along the rim as the object turns
        (on a frictional stop it rolls or slides), and each obstacle at its
        point nearest the obstacle. Exclusive with ``outline``.
        ``Body.cylinder`` makes a uniform cylinder with this outline.
    outline_center : centre of the disc outline in C, relative to the centre
        of mass [m]; default the centre of mass.

    A mass whose density in the body's volume (``size``: the box, or the
    cylinder of a disc outline) is outside ``DENSITY_RANGE``, 10 .. 25000
    kg/m^3, gives an :class:`exdex.PlausibilityWarning` naming ``Body.mass``.
    """

    mass: float
    inertia: Union[float, Vector, Matrix] = ((1e-4, 0.0, 0.0), (0.0, 1e-4, 0.0), (0.0, 0.0, 1e-4))
    size: Optional[Vector] = None
    outline: Optional[Matrix] = None
    outline_radius: Optional[float] = None
    outline_center: Vector = (0.0, 0.0)

    def __post_init__(self):
        object.__setattr__(self, "mass", _real(self.mass, "Body.mass", low=0.0, low_open=True))
        inertia = self.inertia
        if isinstance(inertia, numbers.Real) and not isinstance(inertia, bool):
            inertia = np.eye(3) * _real(inertia, "Body.inertia", low=0.0, low_open=True)
        else:
            a = np.asarray(inertia)
            if a.ndim == 1:
                inertia = np.diag(_array(a, "Body.inertia", (3,)))
        I = _array(inertia, "Body.inertia", (3, 3))
        if not np.allclose(I, I.T, rtol=1e-9, atol=0.0):
            raise ValueError("Body.inertia must be symmetric")
        if np.any(np.linalg.eigvalsh(I) <= 0):
            raise ValueError("Body.inertia must be positive definite (all principal moments > 0)")
        object.__setattr__(self, "inertia", _tuple(I))
        if self.size is not None:
            s = _array(self.size, "Body.size", (3,))
            if np.any(s <= 0):
                raise ValueError("Body.size must be positive (lx, ly, lz > 0) [m]")
            object.__setattr__(self, "size", _tuple(s))
        if self.outline is not None:
            o = _array(self.outline, "Body.outline", (None, 2))
            if not 1 <= len(o) <= _core.MAX_VERTICES:
                raise ValueError(f"Body.outline must have 1 to {_core.MAX_VERTICES} vertices, got {len(o)}")
            object.__setattr__(self, "outline", _tuple(o))
        object.__setattr__(self, "outline_center", _tuple(_array(self.outline_center, "Body.outline_center", (2,))))
        if self.outline_radius is not None:
            object.__setattr__(self, "outline_radius",
                               _real(self.outline_radius, "Body.outline_radius", low=0.0, low_open=True))
            if self.outline is not None:
                raise ValueError("Body.outline and Body.outline_radius are exclusive: give a polygon outline or a "
                                 "disc outline, not both")
        elif self.outline_center != (0.0, 0.0):
            raise ValueError("Body.outline_center is the centre of a disc outline: it needs Body.outline_radius")
        _check_density(self)

    @classmethod
    def cylinder(cls, mass: float, radius: float, height: float, **kw: Any) -> "Body":
        """A uniform cylinder of ``radius`` and ``height`` [m] with its axis along
        the plate normal (C's z), so its outline in the plate plane is a disc:
        inertia m/12 diag(3 r^2 + h^2, 3 r^2 + h^2, 6 r^2), ``size`` its
        bounding box (2 r, 2 r, h), ``outline_radius`` r (``outline_center``
        may be passed to put the disc's centre off the centre of mass)."""
        r = _real(radius, "Body.cylinder: radius", low=0.0, low_open=True)
        h = _real(height, "Body.cylinder: height", low=0.0, low_open=True)
        m = _real(mass, "Body.mass", low=0.0, low_open=True)
        I = m / 12.0 * np.diag([3 * r**2 + h**2, 3 * r**2 + h**2, 6 * r**2])
        return cls(mass=m, inertia=I, size=(2 * r, 2 * r, h), outline_radius=r, **kw)

    @property
    def is_disc(self) -> bool:
        """True when the outline is a disc (``outline_radius`` given)."""
        return self.outline_radius is not None

    @classmethod
    def box(cls, mass: float, size: Vector, **kw: Any) -> "Body":
        """A uniform box of dimensions ``size = (lx, ly, lz)`` [m]: its inertia is
        m/12 diag(ly^2 + lz^2, lx^2 + lz^2, lx^2 + ly^2)."""
        lx, ly, lz = _array(size, "Body.box: size", (3,))
        I = mass / 12.0 * np.diag([ly**2 + lz**2, lx**2 + lz**2, lx**2 + ly**2])
        return cls(mass=mass, inertia=I, size=(lx, ly, lz), **kw)

    def contact_face(self) -> Dict[str, Any]:
        """The face the pads touch, in C relative to the centre of mass
        (:class:`Pad`): the disc outline (a cylinder's disc), else the given
        ``outline`` (it must then be convex), else the box's x-y rectangle
        from ``size``. A dict ``{"face": (k, 2) array}`` or ``{"face_radius":
        r, "face_center": (x, y)}``; ValueError for a body with none of them."""
        if self.outline_radius is not None:
            return dict(face_radius=self.outline_radius, face_center=self.outline_center)
        if self.outline is not None:
            if len(self.outline) < 3:
                raise ValueError("pads on the fingers need a contact face: Body.outline has fewer than 3 vertices")
            return dict(face=np.array(self.outline))
        if self.size is not None:
            return dict(face=self.vertices())
        raise ValueError("pads on the fingers need the object's contact face: give Body.size (a box), "
                         "Body.outline (a convex polygon) or Body.outline_radius (a disc)")

    def vertices(self) -> NDArray[np.float64]:
        """Outline vertices (k, 2) in C used against stops. A disc outline gives
        64 points of its rim, equally spaced from angle 0 (for drawing and
        distances; the core uses the disc itself)."""
        if self.outline_radius is not None:
            a = np.linspace(0.0, 2.0 * np.pi, 64, endpoint=False)
            return np.asarray(self.outline_center) + self.outline_radius * np.column_stack([np.cos(a), np.sin(a)])
        if self.outline is not None:
            return np.array(self.outline)
        if self.size is not None:
            sx, sy = np.asarray(self.size, dtype=float)[:2]
            hx, hy = sx / 2, sy / 2
            return np.array([(-hx, -hy), (hx, -hy), (hx, hy), (-hx, hy)])
        return np.zeros((1, 2))


@dataclass(frozen=True)
class Patch:
    """Pressure patch between one plate and the object.

    e_r : torsional semi-axis of the friction ellipsoid [m], the ratio of the
        largest friction torque to the largest friction force, mu N. Use
        ``Patch.disc`` or ``Patch.rectangle`` to compute it from a uniform
        pressure distribution (Howe & Cutkosky), or give it directly.
    center : centre of pressure in the object frame C, relative to the centre
        of mass [m]. In ``"rotation"`` scenes it is the pivot (paper 2.3).
    shape : description only ("disc", "rectangle", "polygon" or "given").
    dims : the sizes the patch was made from [m]: ``(radius,)`` for a disc,
        ``(width, height)`` for a rectangle, the vertices relative to
        ``center`` flattened ``(x0, y0, x1, y1, ...)`` (counter-clockwise)
        for a polygon.
    """

    e_r: float
    center: Vector = (0.0, 0.0)
    shape: str = "given"
    dims: Tuple[float, ...] = ()

    def __post_init__(self):
        object.__setattr__(self, "e_r", _real(self.e_r, "Patch.e_r", low=0.0, low_open=True))
        object.__setattr__(self, "center", _tuple(_array(self.center, "Patch.center", (2,))))

    def region(self) -> Optional[Dict[str, Any]]:
        """The contact region the exact limit surface integrates over, in the
        object frame relative to ``center`` (the reference point of the
        friction wrench): ``{"radius": R}`` for a disc, ``{"vertices": (k, 2)
        array}`` (counter-clockwise) for a rectangle, None for a patch given
        by e_r alone."""
        if self.shape == "disc" and len(self.dims) == 1:
            return {"radius": float(self.dims[0])}
        if self.shape == "rectangle" and len(self.dims) == 2:
            a, b = 0.5 * float(self.dims[0]), 0.5 * float(self.dims[1])
            return {"vertices": np.array([[-a, -b], [a, -b], [a, b], [-a, b]])}
        if self.shape == "polygon" and len(self.dims) >= 6 and len(self.dims) % 2 == 0:
            return {"vertices": np.array(self.dims, dtype=float).reshape(-1, 2)}
        return None

    def _surface_args(self, limit_surface: str) -> Tuple[int, float, Any, float]:
        if not isinstance(limit_surface, str) or limit_surface not in LIMIT_SURFACES:
            raise ValueError(f"limit_surface must be one of {', '.join(map(repr, LIMIT_SURFACES))}, "
                             f"got {limit_surface!r}")
        reg = self.region() if limit_surface == "exact" else None
        if limit_surface == "exact" and reg is None:
            raise ValueError("limit_surface='exact' needs a patch with a contact region (Patch.disc, .rectangle or "
                             f".polygon); this patch is given by e_r alone (shape {self.shape!r})")
        verts = None if reg is None else reg.get("vertices")
        radius = 0.0 if reg is None else float(reg.get("radius", 0.0))
        return LIMIT_SURFACES[limit_surface], float(self.e_r), verts, radius

    def friction_wrench(self, slip: Sequence[float], limit_surface: str = "ellipsoid") -> Tuple[NDArray[np.float64], float]:
        """The friction of one unit of capacity (mu N = 1 N) for a slip twist
        ``slip = (v_x, v_y, omega)`` [m/s, m/s, rad/s] of the object over the
        plate at the patch's centre, in the object frame: the wrench
        ``(f_x, f_y, m_z)`` [N, N, N m] (maximum dissipation: it opposes the
        slip) and the power it dissipates, ``D = -wrench . slip`` [W]. Multiply
        both by the capacity. ``"ellipsoid"`` is the paper's Eq. 6,
        ``"exact"`` uniform Coulomb friction over the region."""
        u = _tuple(_array(slip, "slip", (3,)))
        if u == (0.0, 0.0, 0.0):
            raise ValueError("slip must be a non-zero twist (v_x, v_y, omega): a patch at rest has no slip direction")
        w, d = _core.limit_surface(*self._surface_args(limit_surface), 0, u)
        return np.array(w), d

    def load_gauge(self, wrench: Sequence[float], limit_surface: str = "ellipsoid") -> Tuple[float, NDArray[np.float64]]:
        """The stick test of a load: the friction wrench ``(f_x, f_y, m_z)``
        [N, N, N m] the plates must supply to hold the object (at the patch's
        centre, object frame) is carried at capacity C iff the returned gauge
        [N] is <= C. Also returns the unit slip twist the load drives once it
        reaches the limit (the direction in which the object starts to
        slide)."""
        w = _tuple(_array(wrench, "wrench", (3,)))
        u, g = _core.limit_surface(*self._surface_args(limit_surface), 1, w)
        return g, np.array(u)

    @classmethod
    def disc(cls, radius: float, center: Vector = (0.0, 0.0)) -> "Patch":
        """Uniform pressure over a disc of ``radius`` [m]: e_r = 2 R / 3."""
        r = _real(radius, "Patch.disc: radius", low=0.0, low_open=True)
        return cls(e_r=_core.er_disc(r), center=center, shape="disc", dims=(r,))

    @classmethod
    def polygon(cls, vertices: Matrix, center: Optional[Vector] = None) -> "Patch":
        """Uniform pressure over a convex polygon: ``vertices`` (k, 2) [m] in
        the object frame C relative to the centre of mass (either
        orientation, 3 to 32 vertices). The centre
        of pressure is the polygon's centroid (or ``center``, in C), e_r the
        polygon's mean distance from it, and :meth:`region` the polygon
        about it (the region of ``limit_surface="exact"``)."""
        v = _array(vertices, "vertices", (None, 2))
        if not 3 <= len(v) <= 32:
            raise ValueError(f"Patch.polygon: vertices must have 3 to 32 vertices, got {len(v)}")
        x, y = v[:, 0], v[:, 1]
        cr = x * np.roll(y, -1) - np.roll(x, -1) * y
        area2 = float(np.sum(cr))
        if area2 < 0.0:
            v = v[::-1].copy()
            x, y = v[:, 0], v[:, 1]
            cr = x * np.roll(y, -1) - np.roll(x, -1) * y
            area2 = -area2
        size2 = float(np.max(np.sum((v - v.mean(axis=0)) ** 2, axis=1)))
        e = np.roll(v, -1, axis=0) - v
        turn = e[:, 0] * np.roll(e[:, 1], -1) - e[:, 1] * np.roll(e[:, 0], -1)
        if not (area2 > 0.0 and np.all(turn >= -1e-12 * size2)):
            raise ValueError("Patch.polygon: vertices must be a convex polygon of positive area (every turn "
                             "the same way)")
        g = np.array([np.sum((x + np.roll(x, -1)) * cr), np.sum((y + np.roll(y, -1)) * cr)]) / (3.0 * area2)
        c = g if center is None else np.asarray(_array(center, "center", (2,)), dtype=float)
        rel = v - c
        _, er = _core.limit_surface(LIMIT_SURFACES["exact"], 1.0, rel, 0.0, 0, (0.0, 0.0, 1.0))
        return cls(e_r=float(er), center=tuple(float(a) for a in c), shape="polygon",
                   dims=tuple(float(a) for a in rel.ravel()))

    @classmethod
    def rectangle(cls, width: float, height: float, center: Vector = (0.0, 0.0)) -> "Patch":
        """Uniform pressure over a ``width`` x ``height`` rectangle [m] (full
        side lengths along the object's x and y, as in ``Body.box``): e_r is
        the mean distance of the rectangle from its centre."""
        w = _real(width, "Patch.rectangle: width", low=0.0, low_open=True)
        h = _real(height, "Patch.rectangle: height", low=0.0, low_open=True)
        return cls(e_r=_core.er_rectangle(w / 2, h / 2), center=center, shape="rectangle", dims=(w, h))


@dataclass(frozen=True)
class Pad:
    """A pad fixed on the finger: where the plate touches the object, in the
    gripper frame B (both fingers identical and aligned).

    With ``Grasp(pad=...)`` the contact stays on the finger: at each instant
    the contact region is the pad intersected with the object's contact face
    (:meth:`Body.contact_face`) at the object's pose, under uniform pressure
    (grip force / area). The friction acts at the region's centroid with the
    ellipsoid's e_r its mean distance from the centroid (in place of
    ``Patch.center`` and ``Patch.e_r``; with ``Grasp(limit_surface="exact")``
    the exact surface of the region), both following the object's pose; the
    capacity stays ``mu * fingers * grip_force`` while the region is not
    empty. When the region vanishes at an output sample the grasp is lost:
    the run stops there (the Result ends at that sample, ``stats
    ["grasp_lost_t"]`` holds its time) with a :class:`PhysicsWarning` of kind
    ``"grasp"``; the event and regularised methods stop integrating at the
    end of the step in which it vanished, and that sample holds the pose
    there. A 1-DoF translation is unaffected but for that; a 1-DoF
    rotation pivots at the centroid of the region at the start (the pad
    centre when the face covers the pad) with that region's e_r.

    vertices : convex polygon (k, 2) [m] relative to ``center`` (either
        orientation, up to ``MAX_PAD_VERTICES`` vertices), or None for a disc.
    radius : disc radius [m] > 0 (exclusive with ``vertices``).
    center : position of the pad on the plate, in B [m].
    scale : the polygon's size factor (> 0) about ``center``.

    A disc whose rim crosses the other shape enters as the regular 32-gon of
    its area (its rim within 3.3e-3 R); a disc inside the other shape is
    exact.
    """

    vertices: Optional[Matrix] = None
    radius: Optional[float] = None
    center: Vector = (0.0, 0.0)
    scale: float = 1.0

    def __post_init__(self):
        object.__setattr__(self, "center", _tuple(_array(self.center, "Pad.center", (2,))))
        object.__setattr__(self, "scale", _real(self.scale, "Pad.scale", low=0.0, low_open=True))
        if (self.vertices is None) == (self.radius is None):
            raise ValueError("Pad needs exactly one of vertices (a convex polygon) and radius (a disc)")
        if self.vertices is not None:
            v = _array(self.vertices, "Pad.vertices", (None, 2))
            if not 3 <= len(v) <= _core.MAX_PAD_VERTICES:
                raise ValueError(f"Pad.vertices must have 3 to {_core.MAX_PAD_VERTICES} vertices, got {len(v)}")
            object.__setattr__(self, "vertices", _tuple(v))
        else:
            object.__setattr__(self, "radius", _real(self.radius, "Pad.radius", low=0.0, low_open=True))

    @classmethod
    def rectangle(cls, width: float, height: float, center: Vector = (0.0, 0.0)) -> "Pad":
        """A ``width`` x ``height`` rectangle [m] (sides along B's x and y) about ``center``."""
        w = _real(width, "Pad.rectangle: width", low=0.0, low_open=True) / 2
        h = _real(height, "Pad.rectangle: height", low=0.0, low_open=True) / 2
        return cls(vertices=((-w, -h), (w, -h), (w, h), (-w, h)), center=center)

    @classmethod
    def disc(cls, radius: float, center: Vector = (0.0, 0.0)) -> "Pad":
        """A disc of ``radius`` [m] about ``center``."""
        return cls(radius=radius, center=center)

    def outline(self) -> NDArray[np.float64]:
        """The pad's boundary (k, 2) in B [m] (a disc: 64 rim points)."""
        if self.radius is not None:
            a = np.linspace(0.0, 2.0 * np.pi, 64, endpoint=False)
            return np.asarray(self.center) + self.radius * np.column_stack([np.cos(a), np.sin(a)])
        return np.asarray(self.center) + self.scale * np.asarray(self.vertices)

    def _spec(self) -> Dict[str, Any]:
        if self.radius is not None:
            return dict(pad_radius=self.radius, pad_center=self.center)
        return dict(pad=np.array(self.vertices), pad_center=self.center, pad_scale=self.scale)


@dataclass(frozen=True)
class GripSchedule:
    """A grip force that varies in time: the normal force of each finger F(t)
    [N] through the points ``(times[i], forces[i])``.

    times : [s], finite and strictly increasing, at least one point.
    forces : [N], finite and >= 0, one per time.
    kind : between the points, ``"linear"`` (piecewise linear), ``"cubic"``
        (Steffen's monotone cubic: continuous slope, no overshoot, so F stays
        between the neighbouring forces and >= 0; through two points it is
        the line) or ``"step"`` (piecewise constant, right-continuous:
        ``forces[i]`` from ``times[i]`` on, e.g. a release and a re-grip).

    Before ``times[0]`` and after ``times[-1]`` the force is held at the first
    and last value. A force of 0 (a release) makes the plates frictionless
    meanwhile. Every method evaluates the capacity ``mu * fingers * F(t)`` at
    its own times (the time-stepping methods use its exact mean over each
    step; the event and regularised methods step onto the times, and the
    event method locates where a falling capacity meets the load; the
    analytic method solves linear and step schedules in closed form, a
    cubic one is left to the event method by ``method="auto"``). A
    schedule whose forces are all equal is that constant grip force.
    """

    times: Vector
    forces: Vector
    kind: str = "linear"

    def __post_init__(self):
        t = _array(self.times, "GripSchedule.times", (None,))
        f = _array(self.forces, "GripSchedule.forces", (None,))
        if t.size < 1:
            raise ValueError("GripSchedule.times must hold at least one time")
        if t.size > _core.MAX_GRIP_POINTS:
            raise ValueError(f"GripSchedule holds at most {_core.MAX_GRIP_POINTS} points, got {t.size}")
        if f.size != t.size:
            raise ValueError(f"GripSchedule.forces must have one force per time: {t.size} times, {f.size} forces")
        bad = np.flatnonzero(np.diff(t) <= 0.0)
        if bad.size:
            i = int(bad[0]) + 1
            raise ValueError(f"GripSchedule.times must be strictly increasing: times[{i}] = {t[i]:g} "
                             f"<= times[{i - 1}] = {t[i - 1]:g}")
        bad = np.flatnonzero(f < 0.0)
        if bad.size:
            i = int(bad[0])
            raise ValueError(f"GripSchedule.forces[{i}] = {f[i]:g} must be >= 0 [N]")
        if not isinstance(self.kind, str) or self.kind not in GRIP_KINDS:
            raise ValueError(f"GripSchedule.kind must be one of {sorted(GRIP_KINDS)}, got {self.kind!r}")
        object.__setattr__(self, "times", _tuple(t))
        object.__setattr__(self, "forces", _tuple(f))

    def _eval(self, t: ArrayLike) -> Tuple[NDArray[np.float64], NDArray[np.float64], Tuple[int, ...]]:
        ta = np.asarray(t, dtype=np.float64)
        if not np.all(np.isfinite(ta)):
            raise ValueError("t must be finite")
        probe = Scene(body=Body(mass=1.0), grasp=Grasp(mu=0.0, grip_force=self))
        force, rate = _core.grip_eval(probe.to_spec(), ta.ravel())
        return force, rate, ta.shape

    def __call__(self, t: ArrayLike) -> Union[float, NDArray[np.float64]]:
        """F(t) [N] (as the core evaluates it); a float for a scalar t."""
        force, _, shape = self._eval(t)
        return float(force[0]) if shape == () else force.reshape(shape)

    def rate(self, t: ArrayLike) -> Union[float, NDArray[np.float64]]:
        """dF/dt [N/s] (the right derivative at a point; 0 for ``"step"``)."""
        _, rate, shape = self._eval(t)
        return float(rate[0]) if shape == () else rate.reshape(shape)

    @property
    def max_force(self) -> float:
        """Largest force of the schedule [N] (the interpolation never exceeds it)."""
        return max(self.forces)

    def scaled(self, factor: float) -> "GripSchedule":
        """The schedule with every force multiplied by ``factor`` (>= 0)."""
        k = _real(factor, "factor", low=0.0)
        return GripSchedule(self.times, tuple(k * f for f in self.forces), self.kind)


@dataclass(frozen=True)
class Grasp:
    """How the plates hold the object.

    mu : plate-object friction coefficient, >= 0: the kinetic coefficient,
        the one a slip slides against.
    grip_force : normal force of each finger [N], >= 0, or a
        :class:`GripSchedule` of it in time.
    patch : the pressure patch (both fingers identical and aligned), fixed
        on the object.
    pad : a :class:`Pad` fixed on the fingers, or None (the default: the
        patch). With a pad the contact region follows the object's pose and
        ``patch`` is not used.
    fingers : number of pressing patches, 1 or 2. The ellipsoids of the
        fingers add: the friction capacity is ``mu * fingers * grip_force`` [N]
        and the largest torque ``capacity * patch.e_r`` [N m].
    mu_static : static coefficient, >= mu; None (the default) is ``mu``. The
        plates hold the object while the wrench that holds it lies in the
        static ellipsoid (capacity ``mu_static * fingers * grip_force``, the
        same shape); a slip slides against the kinetic one and sticks again
        where its slip twist reaches 0 with the holding wrench inside the
        static ellipsoid. ``mu_static == mu`` gives the same results, bit for
        bit, as leaving it out.
    limit_surface : the shape of the set of friction wrenches the plates can
        exert, ``"ellipsoid"`` (the default: the paper's Eq. 6 with
        ``patch.e_r``) or ``"exact"`` (Coulomb friction of uniform pressure
        over the patch's region, with maximum dissipation: the integral of
        ``-mu p s / |s|`` over the region for the slip ``s`` at each point,
        in closed form). ``"exact"`` needs a region: pads on the fingers
        (the surface of pad & face, which follows the pose) or a patch with
        one (``Patch.disc``, ``.rectangle``, ``.polygon``); every method
        takes it (the regularised method's law is its gain of the
        slip speed D(u) along the exact surface's wrench; a 1-DoF rotation's
        torque capacity is the region's mean distance from its centre times
        the capacity, as with the ellipsoid of that e_r). Static and kinetic
        friction are two surfaces of one shape (``mu_static``). See the
        README's "Ellipsoid or exact" for the differences in numbers.
    """

    mu: float
    grip_force: Union[float, GripSchedule]
    patch: Patch = field(default_factory=lambda: Patch(e_r=0.01))
    fingers: int = 2
    mu_static: Optional[float] = None
    pad: Optional[Pad] = None
    limit_surface: str = "ellipsoid"

    def __post_init__(self):
        object.__setattr__(self, "mu", _real(self.mu, "Grasp.mu", low=0.0))
        if self.pad is not None and not isinstance(self.pad, Pad):
            raise TypeError(f"Grasp.pad must be an exdex.Pad or None, got {type(self.pad).__name__}")
        if not isinstance(self.grip_force, GripSchedule):
            if not isinstance(self.grip_force, numbers.Real) or isinstance(self.grip_force, bool):
                raise TypeError(f"Grasp.grip_force must be a real number [N] or an exdex.GripSchedule, "
                                f"got {type(self.grip_force).__name__}")
            object.__setattr__(self, "grip_force", _real(self.grip_force, "Grasp.grip_force", low=0.0))
        if not isinstance(self.patch, Patch):
            raise TypeError(f"Grasp.patch must be an exdex.Patch, got {type(self.patch).__name__}")
        if isinstance(self.fingers, bool) or not isinstance(self.fingers, numbers.Integral) or self.fingers not in (1, 2):
            raise ValueError(f"Grasp.fingers must be 1 or 2, got {self.fingers!r}")
        if self.mu_static is not None:
            object.__setattr__(self, "mu_static", _real(self.mu_static, "Grasp.mu_static", low=self.mu))
        if not isinstance(self.limit_surface, str) or self.limit_surface not in LIMIT_SURFACES:
            raise ValueError(f"Grasp.limit_surface must be one of {', '.join(map(repr, LIMIT_SURFACES))}, "
                             f"got {self.limit_surface!r}")
        if self.limit_surface == "exact" and self.pad is None and self.patch.region() is None:
            raise ValueError("Grasp.limit_surface='exact' needs a contact region: pads on the fingers "
                             "(Grasp.pad) or a patch with one (Patch.disc, .rectangle or .polygon); this patch "
                             f"is given by e_r alone (shape {self.patch.shape!r})")

    @property
    def capacity(self) -> float:
        """Largest friction force the plates can exert, mu * fingers * grip_force
        [N]; with a :class:`GripSchedule` the largest over time (with its
        largest force; :meth:`capacity_at` gives it at given times)."""
        if isinstance(self.grip_force, GripSchedule):
            return self.mu * self.fingers * self.grip_force.max_force
        return self.mu * self.fingers * self.grip_force

    @property
    def static_mu(self) -> float:
        """The static coefficient: ``mu_static``, or ``mu`` when it is None."""
        return self.mu if self.mu_static is None else self.mu_static

    @property
    def static_capacity(self) -> float:
        """Largest friction force the plates can hold at rest, static_mu *
        fingers * grip_force [N] (with a schedule: its largest force)."""
        return self.capacity if self.mu == self.static_mu else \
            self.static_mu * self.fingers * (self.grip_force.max_force if isinstance(self.grip_force, GripSchedule)
                                             else self.grip_force)

    def capacity_at(self, t: ArrayLike) -> Union[float, NDArray[np.float64]]:
        """Friction capacity mu * fingers * F(t) at the times t [N] (F the
        grip schedule, or the constant grip force); a float for a scalar t."""
        if isinstance(self.grip_force, GripSchedule):
            return self.mu * self.fingers * self.grip_force(t)
        ta = np.asarray(t, dtype=np.float64)
        c = self.mu * self.fingers * self.grip_force
        return c if ta.shape == () else np.full(ta.shape, c)

    @property
    def schedule(self) -> Optional[GripSchedule]:
        """The grip schedule, or None for a constant grip force."""
        return self.grip_force if isinstance(self.grip_force, GripSchedule) else None


# ---------------------------------------------------------------- motions

class _Motion:
    """Common part of the gripper motions: conversion to the C spec and evaluation."""

    _may_jump = True  # False where the velocity is continuous by construction

    def _spec(self):  # pragma: no cover - overridden
        raise NotImplementedError

    @property
    def end_time(self) -> float:
        """Time after which the gripper is at rest [s]."""
        raise NotImplementedError

    def evaluate(self, t: ArrayLike, gripper_rotation: Matrix = DEFAULT_GRIPPER_ROTATION,
                 gripper_position: Vector = (0.0, 0.0, 0.0)) -> Dict[str, NDArray[np.float64]]:
        """Kinematics of the gripper frame B at times ``t`` [s], in the world frame A.

        Returns a dict of arrays: ``R`` (n, 3, 3) = R_AB, ``p`` position of B's
        origin [m], ``v`` [m/s], ``a`` [m/s^2], ``w`` angular velocity [rad/s],
        ``dw`` angular acceleration [rad/s^2], each (n, 3).
        """
        scene = Scene(body=Body(mass=1.0), grasp=Grasp(mu=0.0, grip_force=0.0), motion=self,
                      gripper_rotation=gripper_rotation, gripper_position=gripper_position)
        t = _array(np.atleast_1d(t), "t", (None,))
        return _core.motion_eval(scene.to_spec(), t)

    def velocity_jumps(self, gripper_rotation=DEFAULT_GRIPPER_ROTATION, gripper_position=(0.0, 0.0, 0.0)):
        """Times where the gripper's velocity jumps (a log starting or ending at
        speed, a trapezoid without ramps): a list of ``(t, dv, dw)``, ``t``
        [s], the jumps (after minus before) of the velocity of B's origin
        ``dv`` [m/s] and of its angular velocity ``dw`` [rad/s], (3,) arrays
        in the world frame A."""
        from exdex import _core

        scene = Scene(body=Body(mass=1.0), grasp=Grasp(mu=0.0, grip_force=0.0), motion=self,
                      gripper_rotation=gripper_rotation, gripper_position=gripper_position)
        return [(t, np.array(dv), np.array(dw)) for t, dv, dw in _core.motion_jumps(scene.to_spec())]


def _axis_fields(self, name):
    object.__setattr__(self, "axis", _unit(self.axis, f"{name}.axis", 3))
    object.__setattr__(self, "center", _tuple(_array(self.center, f"{name}.center", (3,))))
    if not isinstance(self.rotation, bool):
        raise TypeError(f"{name}.rotation must be True or False")


@dataclass(frozen=True)
class Rest(_Motion):
    """The gripper holds its initial pose."""

    _may_jump = False

    def _spec(self):
        return dict(motion_kind=_core.MOTION_REST)

    @property
    def end_time(self) -> float:
        return 0.0


@dataclass(frozen=True)
class AsymmetricProfile(_Motion):
    """Paper Eq. 7: acceleration a_H for beta T, a_L until (2 - beta) T, a_H
    until 2 T, with a_H = 2 X1 / (beta T^2), a_L = 2 X1 / ((beta - 1) T^2)
    (Eq. 9). A round trip: out to ``amplitude`` at t = T, back at rest at 2 T.

    amplitude : X1 [m] (translation) or theta1 [rad] (rotation); its sign
        gives the direction along ``axis``.
    duration : T [s] > 0.
    beta : ratio in (0, 1).
    axis : direction (translation) or rotation axis, in A (normalised).
    rotation : False to translate along axis, True to rotate about it.
    center : a point on the rotation axis, in A [m].
    """

    _may_jump = False

    amplitude: float
    duration: float
    beta: float
    axis: Vector = (0.0, 0.0, 1.0)
    rotation: bool = False
    center: Vector = (0.0, 0.0, 0.0)

    def __post_init__(self):
        object.__setattr__(self, "amplitude", _real(self.amplitude, "AsymmetricProfile.amplitude"))
        object.__setattr__(self, "duration", _real(self.duration, "AsymmetricProfile.duration", low=0.0, low_open=True))
        object.__setattr__(self, "beta", _real(self.beta, "AsymmetricProfile.beta", low=0.0, high=1.0,
                                               low_open=True, high_open=True))
        _axis_fields(self, "AsymmetricProfile")

    @property
    def a_high(self) -> float:
        """a_H = 2 X1 / (beta T^2) (Eq. 9a)."""
        return 2 * self.amplitude / (self.beta * self.duration**2)

    @property
    def a_low(self) -> float:
        """a_L = 2 X1 / ((beta - 1) T^2) (Eq. 9b)."""
        return 2 * self.amplitude / ((self.beta - 1) * self.duration**2)

    def _spec(self):
        return dict(motion_kind=_core.MOTION_ASYMMETRIC, motion_rotation=int(self.rotation), motion_axis=self.axis,
                    motion_center=self.center, motion_amplitude=self.amplitude,
                    motion_duration=self.duration, motion_beta=self.beta)

    @property
    def end_time(self) -> float:
        return 2.0 * self.duration


@dataclass(frozen=True)
class TrapezoidalProfile(_Motion):
    """Trapezoidal velocity: ``amplitude`` (distance [m] or angle [rad]) in
    ``duration`` T [s] with peak speed ``v_max``; requires
    |X1|/T <= v_max <= 2|X1|/T. Ramps of T - |X1|/v_max at each end."""

    amplitude: float
    duration: float
    v_max: float
    axis: Vector = (0.0, 0.0, 1.0)
    rotation: bool = False
    center: Vector = (0.0, 0.0, 0.0)

    def __post_init__(self):
        a = _real(self.amplitude, "TrapezoidalProfile.amplitude")
        T = _real(self.duration, "TrapezoidalProfile.duration", low=0.0, low_open=True)
        if a == 0.0:
            raise ValueError("TrapezoidalProfile.amplitude must be non-zero")
        v = _real(self.v_max, "TrapezoidalProfile.v_max", low=abs(a) / T * (1 - 1e-12),
                  high=2 * abs(a) / T * (1 + 1e-12))
        object.__setattr__(self, "amplitude", a)
        object.__setattr__(self, "duration", T)
        object.__setattr__(self, "v_max", v)
        _axis_fields(self, "TrapezoidalProfile")

    def _spec(self):
        return dict(motion_kind=_core.MOTION_TRAPEZOID, motion_rotation=int(self.rotation), motion_axis=self.axis,
                    motion_center=self.center, motion_amplitude=self.amplitude,
                    motion_duration=self.duration, motion_v_max=self.v_max)

    @property
    def end_time(self) -> float:
        return self.duration


@dataclass(frozen=True, eq=False)
class SampledTrajectory(_Motion):
    """Gripper poses sampled at increasing times (e.g. a robot log).

    times : (n,) strictly increasing [s], n >= 4.
    positions : (n, 3) positions of the logged frame's origin [m].
    quaternions : (n, 4) its orientation as (w, x, y, z), normalised
        internally; sign flips between samples are handled.
    start_velocity, start_omega : velocity [m/s] and angular velocity
        [rad/s] of the logged frame at the first sample, (3,) in the
        coordinates of the poses; giving either one sets the start's end
        condition (the other is then zero). Default: from the data (below).
    end_velocity, end_omega : the same at the last sample.
    relative : False (default): the poses are absolute, in the world frame A,
        and ``Scene.gripper_rotation``/``gripper_position`` are ignored. True:
        the log's motion is replayed from the scene's initial gripper pose:
        B(t) = G0 (L(t_0) X)^-1 L(t) X with G0 the initial gripper pose, L the
        logged pose and X the tool (so a log whose first pose is the identity
        gives displacements of the initial gripper pose).
    tool : (4, 4) homogeneous transform of the gripper frame B in the logged
        frame (flange -> B), or None (the log is B itself). B(t) = L(t) X.
    noise : the log's measurement noise, the standard deviation per axis of
        the positions [m] and of the orientation (a small rotation) [rad]: a
        pair ``(position, orientation)``, or one number for both; 0 leaves
        that part as logged. None (the default): no smoothing. Given, the
        poses are replaced by a smoothing spline (SciPy's
        ``make_smoothing_spline``, the ``design`` extra) whose residual
        matches the noise: each position axis has the root-mean-square
        residual ``noise[0]``, the quaternion's components together the
        residual a rotation noise of ``noise[1]`` per axis gives (3
        ``noise[1]``^2 / 4 mean square); the interpolation below then runs
        through the smoothed samples. An end whose velocities are not given
        is at rest where the smoothed samples' end velocity is within 3
        sqrt(2) noise / h of zero (three standard deviations of one sample
        difference's noise, h the end interval; a 0-noise part by the test
        below). Stored as the pair.

    Interpolated with C2 cubic splines of the position and quaternion
    components, clamped at the ends: where the log starts or ends at rest
    the end velocity is zero, otherwise it is the velocity of the quadratic
    through the three end samples. An end counts as at rest (separately for
    position and orientation) when that estimated velocity, along the first
    displacement D1 away from the end over the interval h1, is at most half
    the mean velocity over that interval, v0 . D1 <= |D1|^2 / (2 h1): a held
    pose or a uniformly accelerated start is at rest, a constant speed is
    not (the test compares two velocities of the same data, so it holds in
    any units). Before the first and after the last time the gripper holds
    the end pose at rest: a log that starts or ends at speed makes the
    gripper's velocity jump there. Every method then applies the same jump
    to the object (the plates cannot transmit an impulse, so the object
    keeps its absolute velocity and its velocity relative to the gripper
    jumps), and :func:`exdex.simulate` warns (``velocity_jumps`` lists
    them). A log starting at speed at t = 0 has no jump in the run: the
    simulation starts there, and ``Scene.v0`` is the object's velocity
    relative to the already moving gripper.

    A log made without ``noise`` whose accelerations are dominated by its
    noise (three standard deviations of the acceleration the noise gives
    exceed the motion's peak, each estimated from the data:
    :meth:`noise_estimate`) gives an :class:`exdex.NoisyLogWarning` naming
    the option; logs of fewer than 12 samples are not judged.
    """

    times: Vector
    positions: Matrix
    quaternions: Matrix
    start_velocity: Optional[Tuple[float, float, float]] = None
    start_omega: Optional[Tuple[float, float, float]] = None
    end_velocity: Optional[Tuple[float, float, float]] = None
    end_omega: Optional[Tuple[float, float, float]] = None
    relative: bool = False
    tool: Optional[Tuple[Tuple[float, ...], ...]] = None
    noise: Optional[Union[float, Tuple[float, float]]] = None

    def __post_init__(self):
        t = _array(self.times, "SampledTrajectory.times", (None,))
        if len(t) < 4:
            raise ValueError(f"SampledTrajectory.times needs at least 4 samples, got {len(t)}")
        bad = np.flatnonzero(np.diff(t) <= 0)
        if bad.size:
            i = int(bad[0]) + 1
            raise ValueError(f"SampledTrajectory.times must be strictly increasing: times[{i}] = {t[i]:.17g} "
                             f"<= times[{i - 1}] = {t[i - 1]:.17g}")
        p = _array(self.positions, "SampledTrajectory.positions", (len(t), 3))
        q = _array(self.quaternions, "SampledTrajectory.quaternions", (len(t), 4))
        if np.any(np.linalg.norm(q, axis=1) == 0):
            raise ValueError("SampledTrajectory.quaternions must be non-zero")
        for name, a in (("times", t), ("positions", p), ("quaternions", q)):
            a.setflags(write=False)
            object.__setattr__(self, name, a)
        for name in ("start_velocity", "start_omega", "end_velocity", "end_omega"):
            value = getattr(self, name)
            if value is not None:
                object.__setattr__(self, name, _tuple(_array(value, f"SampledTrajectory.{name}", (3,))))
        if not isinstance(self.relative, (bool, np.bool_)):
            raise TypeError(f"SampledTrajectory.relative must be True or False, got {type(self.relative).__name__}")
        object.__setattr__(self, "relative", bool(self.relative))
        if self.tool is not None:
            X = _array(self.tool, "SampledTrajectory.tool", (4, 4))
            if not np.array_equal(X[3], [0.0, 0.0, 0.0, 1.0]):
                raise ValueError("SampledTrajectory.tool must be a homogeneous transform: last row (0, 0, 0, 1)")
            _rotation(X[:3, :3], "SampledTrajectory.tool[:3, :3]")
            object.__setattr__(self, "tool", _tuple(X))
        self._smooth()

    def _smooth(self):
        """Validate ``noise``; keep the smoothed poses (or None), or warn on a noisy log."""
        smoothed = None
        if self.noise is not None:
            a = np.asarray(self.noise)
            if a.ndim == 0:
                pair = (_real(self.noise, "SampledTrajectory.noise", low=0.0),) * 2
            else:
                v = _array(a, "SampledTrajectory.noise", (2,))
                pair = tuple(_real(float(x), f"SampledTrajectory.noise[{i}]", low=0.0) for i, x in enumerate(v))
            object.__setattr__(self, "noise", pair)
            if pair != (0.0, 0.0):
                if len(self.times) < 5:
                    raise ValueError(f"SampledTrajectory.noise: smoothing needs at least 5 samples, got "
                                     f"{len(self.times)}")
                feature = "SampledTrajectory(noise=...)"
                p = _lognoise.smooth_positions(self.times, self.positions, pair[0], feature) if pair[0] > 0 \
                    else np.array(self.positions)
                q = _lognoise.smooth_quaternions(self.times, self.quaternions, pair[1], feature) if pair[1] > 0 \
                    else np.array(self.quaternions)
                # an end the user did not state is at rest where the smoothed samples stop within the
                # noise; it is then smoothed again as an end at rest (mirrored: zero slope, as clamped)
                user = ((self.start_velocity, self.start_omega), (self.end_velocity, self.end_omega))
                rest = tuple(all(v is None for v in user[e])
                             and _lognoise.end_at_rest(self.times, p, pair[0], e)
                             and _lognoise.end_at_rest(self.times, _lognoise.continuous_quaternions(q), pair[1], e, 2.0)
                             for e in (0, 1))
                if any(rest):
                    if pair[0] > 0:
                        p = _lognoise.smooth_positions(self.times, self.positions, pair[0], feature, rest)
                    if pair[1] > 0:
                        q = _lognoise.smooth_quaternions(self.times, self.quaternions, pair[1], feature, rest)
                smoothed = np.hstack([p, q])
                smoothed.setflags(write=False)
        object.__setattr__(self, "_smoothed", smoothed)
        object.__setattr__(self, "_rest_ends", rest if smoothed is not None else (False, False))
        if self.noise is None:
            for w in self._noise_findings():
                warnings.warn(w, stacklevel=_lognoise.user_stacklevel())

    def _knots(self) -> NDArray[np.float64]:
        """(n, 7) the poses (position, quaternion) the splines run through."""
        smoothed = getattr(self, "_smoothed")   # set in __post_init__ (not a field: files keep the log)
        return np.hstack([self.positions, self.quaternions]) if smoothed is None else smoothed

    @property
    def spline_positions(self) -> NDArray[np.float64]:
        """(n, 3) the positions the splines run through [m]: the logged ones,
        or with ``noise`` the smoothed ones."""
        return self._knots()[:, :3]

    @property
    def spline_quaternions(self) -> NDArray[np.float64]:
        """(n, 4) the quaternions the splines run through: the logged ones, or
        with ``noise`` the smoothed ones (sign-continuous, not normalised)."""
        return self._knots()[:, 3:]

    def noise_estimate(self) -> Tuple[float, float]:
        """The noise of the logged poses estimated from the data: (position
        [m] per axis, the largest over the axes; orientation [rad] per axis
        of a small rotation). Each coordinate's level is the smallest, over
        the 3rd to 6th divided differences, of their median size scaled to
        white noise (sigma sqrt(C(2k, k)) / (k! h^k) for the k-th), which
        the motion's own smooth differences do not reach; rounding-level
        values count as 0, and logs of fewer than 12 samples give zeros. A
        value for ``noise`` where the sensor's own figures are not known."""
        sp = _lognoise.levels(self.times, self.positions)
        sq = _lognoise.levels(self.times, _lognoise.continuous_quaternions(self.quaternions))
        return float(np.max(sp)), float(2.0 * np.linalg.norm(sq) / math.sqrt(3.0))

    def _noise_findings(self):
        out = []
        est = None
        parts = (("positions", self.positions, 1.0, "m/s^2"),
                 ("orientations", _lognoise.continuous_quaternions(self.quaternions), 2.0, "rad/s^2"))
        for part, y, factor, unit in parts:
            sig, noise_acc, motion_acc = _lognoise.dominance(self.times, y, factor)
            if motion_acc is None or noise_acc <= motion_acc:
                continue
            if est is None:
                est = self.noise_estimate()
            level = est[0] if part == "positions" else est[1]
            out.append(_diagnostics.NoisyLogWarning(
                f"SampledTrajectory: the log's {part} are noisy enough to dominate their accelerations: their "
                f"noise, about {level:.3g} {'m' if part == 'positions' else 'rad'} per axis (estimated from "
                f"the data's 3rd to 6th differences), gives the gripper accelerations of about {noise_acc:.3g} "
                f"{unit} (3 standard deviations) against the motion's peak of about {motion_acc:.3g} {unit}. "
                f"Pass SampledTrajectory(..., noise=({est[0]:.2g}, {est[1]:.2g})) (position [m], orientation "
                f"[rad]; your sensor's figures if you know them) to smooth the log",
                part, level, noise_acc, motion_acc))
        return out

    @classmethod
    def from_matrices(cls, times: Vector, transforms: ArrayLike, **options: Any) -> "SampledTrajectory":
        """From homogeneous transforms (n, 4, 4) of the logged frame; ``options``
        are the other arguments (end velocities, ``relative``, ``tool``)."""
        T = _array(transforms, "transforms", (None, 4, 4))
        quats = np.array([_quat_from_matrix(M[:3, :3]) for M in T])
        return cls(times, T[:, :3, 3], quats, **options)

    def _spec(self):
        poses = self._knots()
        zero = (0.0, 0.0, 0.0)
        rest = getattr(self, "_rest_ends")    # smoothed ends at rest within the noise (noise=...)
        given = (self.start_velocity is not None or self.start_omega is not None or rest[0],
                 self.end_velocity is not None or self.end_omega is not None or rest[1])
        spec = dict(motion_kind=_core.MOTION_SAMPLED, motion_times=self.times, motion_poses=poses,
                    motion_end_given=tuple(float(g) for g in given),
                    motion_end_velocity=(self.start_velocity or zero) + (self.end_velocity or zero),
                    motion_end_omega=(self.start_omega or zero) + (self.end_omega or zero),
                    motion_relative=int(self.relative), motion_tool=int(self.tool is not None))
        if self.tool is not None:
            X = np.array(self.tool)
            spec["motion_tool_pose"] = np.concatenate([X[:3, 3], _quat_from_matrix(X[:3, :3])])
        return spec

    @property
    def end_time(self) -> float:
        return float(np.asarray(self.times)[-1])

    def _key(self):
        return (self.times.tobytes(), self.positions.tobytes(), self.quaternions.tobytes(), self.start_velocity,
                self.start_omega, self.end_velocity, self.end_omega, self.relative, self.tool, self.noise)

    def __eq__(self, other):
        return isinstance(other, SampledTrajectory) and self._key() == other._key()

    def __hash__(self):
        return hash(self._key())


@dataclass(frozen=True)
class Shake(_Motion):
    """An oscillation of the gripper: s(t) = A (1 - cos 2 pi f t) for
    ``duration`` D, then held at s(D).

    It starts at rest (velocity 0, acceleration A (2 pi f)^2) and, after
    whole or half cycles, ends at rest; otherwise its velocity jumps to rest
    at D (a :class:`exdex.GripperJumpWarning` in a run, an error between the
    pieces of a :class:`Chain` unless allowed). The peak acceleration is
    A (2 pi f)^2 [m/s^2 or rad/s^2].

    amplitude : A [m] (translation) or [rad] (rotation); any sign.
    frequency : f [Hz] > 0.
    cycles, duration : give exactly one: the number of cycles f D (> 0) or
        D [s] (> 0).
    axis, rotation, center : as :class:`AsymmetricProfile`.
    """

    amplitude: float
    frequency: float
    cycles: Optional[float] = None
    duration: Optional[float] = None
    axis: Vector = (0.0, 0.0, 1.0)
    rotation: bool = False
    center: Vector = (0.0, 0.0, 0.0)

    def __post_init__(self):
        object.__setattr__(self, "amplitude", _real(self.amplitude, "Shake.amplitude"))
        f = _real(self.frequency, "Shake.frequency", low=0.0, low_open=True)
        object.__setattr__(self, "frequency", f)
        if self.cycles is not None and self.duration is not None:
            # both (a saved scene): consistent, and kept as given
            n = _real(self.cycles, "Shake.cycles", low=0.0, low_open=True, high=1e9)
            D = _real(self.duration, "Shake.duration", low=0.0, low_open=True)
            if not math.isclose(n / f, D, rel_tol=1e-12):
                raise ValueError("Shake needs exactly one of cycles (the number of cycles, > 0) and duration [s] "
                                 f"(or both with duration = cycles / frequency), got cycles={n!r}, duration={D!r}")
            object.__setattr__(self, "cycles", n)
            object.__setattr__(self, "duration", D)
        elif self.cycles is None and self.duration is None:
            raise ValueError("Shake needs exactly one of cycles (the number of cycles, > 0) and duration [s], "
                             "got neither")
        elif self.cycles is not None:
            n = _real(self.cycles, "Shake.cycles", low=0.0, low_open=True, high=1e9)
            object.__setattr__(self, "cycles", n)
            object.__setattr__(self, "duration", n / f)
        else:
            D = _real(self.duration, "Shake.duration", low=0.0, low_open=True)
            object.__setattr__(self, "duration", D)
            object.__setattr__(self, "cycles", D * f)
            if D * f > 1e9:
                raise ValueError(f"Shake.duration * Shake.frequency (cycles) must be at most 1e9, got {D * f:g}")
        _axis_fields(self, "Shake")

    @property
    def peak_acceleration(self) -> float:
        """|A| (2 pi f)^2 [m/s^2 or rad/s^2]."""
        return abs(self.amplitude) * (2.0 * math.pi * self.frequency) ** 2

    def _spec(self):
        return dict(motion_kind=_core.MOTION_SHAKE, motion_rotation=int(self.rotation), motion_axis=self.axis,
                    motion_center=self.center, motion_amplitude=self.amplitude,
                    motion_duration=self.duration, motion_frequency=self.frequency)

    @property
    def end_time(self) -> float:
        return float(self.duration)  # type: ignore[arg-type]


@dataclass(frozen=True)
class Pause(_Motion):
    """The gripper holds its pose for ``duration`` [s] (> 0): a rest between
    the pieces of a :class:`Chain` (on its own, the same as :class:`Rest`)."""

    _may_jump = False

    duration: float

    def __post_init__(self):
        object.__setattr__(self, "duration", _real(self.duration, "Pause.duration", low=0.0, low_open=True))

    def _spec(self):
        return dict(motion_kind=_core.MOTION_REST, motion_duration=self.duration)

    @property
    def end_time(self) -> float:
        return self.duration


#: The motion keys every chain piece passes to the core (defaults of unused fields).
_PIECE_DEFAULTS = dict(motion_kind=_core.MOTION_REST, motion_rotation=0, motion_axis=(0.0, 0.0, 1.0),
                       motion_center=(0.0, 0.0, 0.0), motion_amplitude=0.0, motion_duration=1.0,
                       motion_beta=0.5, motion_v_max=1.0, motion_frequency=1.0)


@dataclass(frozen=True)
class Chain(_Motion):
    """Motions played one after the other.

    Each piece starts from the pose where the one before ended (the first
    from the scene's initial gripper pose) and runs on its own clock: a
    profile or shake from its time 0, a :class:`SampledTrajectory` from its
    first sample (relative logs replay from that pose; an absolute log must
    start there), a :class:`Pause` for its duration. The chain's switching
    times (every piece boundary and the pieces' own phase switches) are
    stepped onto by the event and regularised methods; the implicit and
    explicit methods split a step that holds one there.

    pieces : 1 to 16 motions (:class:`AsymmetricProfile`,
        :class:`TrapezoidalProfile`, :class:`Shake`, :class:`Pause`,
        :class:`SampledTrajectory`); not :class:`Rest` (no duration: use a
        :class:`Pause`) nor a chain (list its pieces instead).
    allow_jump : the gripper's velocity must be continuous where one piece
        ends and the next starts (e.g. a shake stopped mid-cycle followed by
        a pause is not), and an absolute log must start at the pose where
        the piece before ended; a violation raises a ValueError naming the
        piece when the scene is simulated. With ``allow_jump=True`` a
        velocity jump between pieces is accepted and applied like a sampled
        log's (:class:`exdex.GripperJumpWarning`): the object keeps its
        absolute velocity. A position jump is always an error. Jumps and
        mismatches within 1e-9 of the speeds or positions compared are
        rounding and ignored.
    """

    pieces: Tuple[_Motion, ...]
    allow_jump: bool = False

    def __post_init__(self):
        pieces = self.pieces
        if isinstance(pieces, _Motion) or isinstance(pieces, (str, bytes)) or not hasattr(pieces, "__iter__"):
            raise TypeError(f"Chain.pieces must be a sequence of motions, got {type(pieces).__name__}")
        pieces = tuple(pieces)
        if not 1 <= len(pieces) <= _core.MOTION_MAX_PIECES:
            raise ValueError(f"Chain.pieces must hold 1 to {_core.MOTION_MAX_PIECES} motions, got {len(pieces)}")
        for i, p in enumerate(pieces):
            if isinstance(p, Chain):
                raise TypeError(f"Chain.pieces[{i}] is a Chain: list its pieces in this chain instead")
            if isinstance(p, Rest):
                raise TypeError(f"Chain.pieces[{i}] is a Rest, which has no duration: use exdex.Pause(duration)")
            if not isinstance(p, _Motion):
                raise TypeError(f"Chain.pieces[{i}] must be an exdex motion, got {type(p).__name__}")
        object.__setattr__(self, "pieces", pieces)
        if not isinstance(self.allow_jump, (bool, np.bool_)):
            raise TypeError(f"Chain.allow_jump must be True or False, got {type(self.allow_jump).__name__}")
        object.__setattr__(self, "allow_jump", bool(self.allow_jump))

    @property
    def start_times(self) -> Tuple[float, ...]:
        """Start time of each piece in the chain [s] (a log's own clock starts
        at its first sample)."""
        out, t = [], 0.0
        for p in self.pieces:
            out.append(t)
            t += self._length(p)
        return tuple(out)

    @staticmethod
    def _length(p):
        if isinstance(p, SampledTrajectory):
            return float(p.times[-1] - p.times[0])
        return p.end_time

    def _spec(self):
        pieces = []
        for p in self.pieces:
            d = dict(_PIECE_DEFAULTS)
            d.update(p._spec())
            pieces.append(d)
        return dict(motion_kind=_core.MOTION_CHAIN, motion_pieces=pieces, motion_allow_jump=int(self.allow_jump),
                    motion_duration=self.end_time)

    @property
    def end_time(self) -> float:
        t = 0.0
        for p in self.pieces:
            t += self._length(p)
        return t


# ---------------------------------------------------------------- stops and scene

@dataclass(frozen=True)
class Stop:
    """A fixed plane of the world the object may not cross: the allowed side
    is ``(x - point) . normal >= 0`` for every outline vertex x (a disc
    outline: every point of the disc), in A [m].

    mu : Coulomb friction coefficient between the stop and each outline
        vertex touching it (a disc: its support point, so it rolls or
        slides), in [0, inf) (0: frictionless). The friction acts
        in the plate plane, along the stop's trace there, bounded by mu times
        the vertex's normal force; exact in every method that supports
        stops (``implicit`` and ``explicit``: velocity-level
        complementarity; ``event`` and ``regularised``: friction modes with
        located switches, the regularised method smoothing only the plate
        friction), stick exactly still. Impacts are plastic with Coulomb
        friction at the impulse level (no plate impulse: the grip force is
        finite), in every method.
    """

    point: Vector
    normal: Vector
    mu: float = 0.0

    def __post_init__(self):
        object.__setattr__(self, "point", _tuple(_array(self.point, "Stop.point", (3,))))
        object.__setattr__(self, "normal", _unit(self.normal, "Stop.normal", 3))
        object.__setattr__(self, "mu", _real(self.mu, "Stop.mu", low=0.0))


@dataclass(frozen=True)
class Obstacle:
    """A convex solid fixed in the world frame A that the object's outline may
    not enter. Build one with :meth:`halfspaces`, :meth:`box` or
    :meth:`cylinder`.

    kind : ``"halfspaces"`` (the intersection of the half-spaces
        ``(x - face_points[i]) . face_normals[i] <= 0``, normals unit and
        pointing out of the solid; it may be unbounded) or ``"cylinder"`` (the
        points within ``radius`` of the line through ``center`` along
        ``axis``: an infinite rod).
    mu : Coulomb friction coefficient against the object (>= 0; every method
        that takes obstacles), as a stop's: along the tangent of the plate
        plane at each contact, bounded by mu times the contact's normal force.

    The plate plane cuts the solid in a convex polygon of the gripper frame B
    (a rod: a disc when its axis is normal to the plates, else an ellipse),
    recomputed from the gripper's pose as it moves (:meth:`section`). The
    object touches it with its outline vertices (against the faces) and with
    the edges of the outline's convex hull (against the section's vertices,
    or the rod); a disc outline (``Body.outline_radius``) with its point
    nearest the section. A one-face obstacle keeps the object where
    ``Stop(point, normal)`` with the same point and normal does; its force
    is the stop force column after the stops' (``Result.stop_force``).
    """

    kind: str
    face_points: Matrix = ()
    face_normals: Matrix = ()
    center: Vector = (0.0, 0.0, 0.0)
    axis: Vector = (0.0, 0.0, 1.0)
    radius: float = 0.0
    mu: float = 0.0

    def __post_init__(self):
        object.__setattr__(self, "mu", _real(self.mu, "Obstacle.mu", low=0.0))
        if self.kind not in ("halfspaces", "cylinder"):
            raise ValueError(f"Obstacle.kind must be 'halfspaces' or 'cylinder', got {self.kind!r}")
        if self.kind == "halfspaces":
            pts = _array(self.face_points, "Obstacle.face_points", (None, 3))
            if not 1 <= len(pts) <= _core.MAX_FACES:
                raise ValueError(f"Obstacle.face_points must have 1 to {_core.MAX_FACES} faces, got {len(pts)}")
            nrm = _array(self.face_normals, "Obstacle.face_normals", (len(pts), 3))
            units = tuple(_unit(n, f"Obstacle.face_normals[{i}]", 3) for i, n in enumerate(nrm))
            object.__setattr__(self, "face_points", _tuple(pts) if len(pts) > 1 else (tuple(float(x) for x in pts[0]),))
            object.__setattr__(self, "face_normals", units)
        else:
            object.__setattr__(self, "face_points", ())
            object.__setattr__(self, "face_normals", ())
        object.__setattr__(self, "center", _tuple(_array(self.center, "Obstacle.center", (3,))))
        object.__setattr__(self, "axis", _unit(self.axis, "Obstacle.axis", 3))
        if self.kind == "cylinder":
            object.__setattr__(self, "radius", _real(self.radius, "Obstacle.radius", low=0.0, low_open=True))
        else:
            object.__setattr__(self, "radius", _real(self.radius, "Obstacle.radius"))

    @classmethod
    def halfspaces(cls, normals: Matrix, offsets: Vector, mu: float = 0.0) -> "Obstacle":
        """The solid ``normals[i] . x <= offsets[i]`` for every i (A, [m]); the
        normals need not be unit (each row is scaled with its offset)."""
        n = _array(normals, "Obstacle.halfspaces: normals", (None, 3))
        d = _array(offsets, "Obstacle.halfspaces: offsets", (len(n),))
        norms = np.linalg.norm(n, axis=1)
        if np.any(norms == 0.0):
            raise ValueError("Obstacle.halfspaces: normals must be non-zero vectors")
        nu, du = n / norms[:, None], d / norms
        return cls(kind="halfspaces", face_points=du[:, None] * nu, face_normals=nu, mu=mu)

    @classmethod
    def box(cls, center: Vector, size: Vector, rotation: Matrix = ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0),
                                                                      (0.0, 0.0, 1.0)),
            mu: float = 0.0) -> "Obstacle":
        """A box of full side lengths ``size`` (> 0) [m] centred at ``center``
        (A), its edges along the columns of ``rotation`` (a rotation matrix)."""
        c = _array(center, "Obstacle.box: center", (3,))
        sz = _array(size, "Obstacle.box: size", (3,))
        if np.any(sz <= 0):
            raise ValueError("Obstacle.box: size must be positive (three side lengths > 0) [m]")
        R = np.array(_rotation(rotation, "Obstacle.box: rotation"))
        pts, nrm = [], []
        for i in range(3):
            for sgn in (1.0, -1.0):
                nrm.append(sgn * R[:, i])
                pts.append(c + sgn * 0.5 * sz[i] * R[:, i])
        return cls(kind="halfspaces", face_points=np.array(pts), face_normals=np.array(nrm), mu=mu)

    @classmethod
    def cylinder(cls, center: Vector, axis: Vector, radius: float, mu: float = 0.0) -> "Obstacle":
        """An infinite rod of ``radius`` (> 0) [m] about the line through
        ``center`` along ``axis`` (A)."""
        return cls(kind="cylinder", center=center, axis=axis, radius=radius, mu=mu)

    def _spec(self) -> Dict[str, Any]:
        if self.kind == "cylinder":
            return dict(kind=_core.OBSTACLE_CYLINDER, center=self.center, axis=self.axis, radius=self.radius,
                        mu=self.mu)
        return dict(kind=_core.OBSTACLE_POLYTOPE, face_points=np.array(self.face_points).reshape(-1, 3),
                    face_normals=np.array(self.face_normals).reshape(-1, 3), mu=self.mu)

    def section(self, gripper_rotation: Matrix, gripper_position: Vector) -> Any:
        """The section by the plate plane of the gripper pose (R_AB, position
        of B in A), in B [m]: a polytope gives its polygon's finite vertices
        (k, 2), counter-clockwise (none: the plane misses it, or the section
        is a strip or half-plane without corners); a cylinder gives
        ``(centre, (a, b, angle))``, its ellipse's centre (2,), semi-axes
        a >= b = radius and the angle of the major axis [rad], or None when
        the axis lies in the plate plane."""
        R = _array(gripper_rotation, "gripper_rotation", (3, 3))
        p = _array(gripper_position, "gripper_position", (3,))
        out = _core.obstacle_section(self._spec(), R.ravel(), p)
        if self.kind == "cylinder" and out is not None:
            return np.array(out[0]), tuple(out[1])
        return out


def _check_contact(scene):
    """The plates touch the object at t = 0: a ValueError for a patch centre
    outside the object's contact face, or a pad on the fingers that misses the
    face at Scene.q0; a PlausibilityWarning for a patch reaching beyond the
    face (or an e_r larger than the face allows). Bodies that state no face
    (no size, outline or disc) are not checked."""
    body, grasp = scene.body, scene.grasp
    if grasp.pad is not None:
        try:
            face = body.contact_face()      # the face the core clips the pads with
        except ValueError:
            return
    else:
        face = _patch_face(body, scene.dof)
        if face is None:
            return
    with np.errstate(all="ignore"):     # awkward poses (1e300 m) compare as they can
        _check_contact_face(scene, body, grasp, face)


def _patch_face(body, dof):
    """The face a patch centre must lie on: the disc outline, the box of
    Body.size, else (not for a rotation's pin) the outline; None when the
    body states none."""
    if body.outline_radius is not None:
        return dict(face_radius=body.outline_radius, face_center=body.outline_center)
    if body.size is not None:
        return dict(face=body.vertices() if body.outline is None else
                    np.array([(-0.5, -0.5), (0.5, -0.5), (0.5, 0.5), (-0.5, 0.5)]) * np.array(body.size[:2]))
    if body.outline is not None and len(body.outline) >= 3 and dof != "rotation":
        # only an outline (it may list just the corners that touch stops): a rotation's pin may lie
        # outside it, a slide's patch centre not (as the run's own "outline" check)
        return dict(face=np.array(body.outline), partial=True)
    return None


def patch_centres_outside(scene: "Scene", centres: ArrayLike) -> Tuple[NDArray[np.float64], float]:
    """(distances, tol): (k,) the distance [m] by which each patch centre of
    ``centres`` (k, 2) (object frame) lies outside the face ``scene``'s patch
    must touch (0 on it; zeros for a scene with pads or a body without a
    face), and the distance [m] above which a centre counts as off the face
    (1e-9 of the face's size), as :class:`Scene` checks its own patch."""
    c = np.asarray(centres, dtype=float).reshape(-1, 2)
    face = None if scene.grasp.pad is not None else _patch_face(scene.body, scene.dof)
    if face is None:
        return np.zeros(len(c)), 0.0
    with np.errstate(all="ignore"):
        if "face_radius" in face:
            R, fc = float(face["face_radius"]), np.asarray(face["face_center"], dtype=float)
            return np.maximum(np.hypot(c[:, 0] - fc[0], c[:, 1] - fc[1]) - R, 0.0), 1e-9 * R
        hull = _hull(face["face"])
        if len(hull) < 3:
            return np.zeros(len(c)), 0.0
        a, e = hull, np.roll(hull, -1, axis=0) - hull
        rel = c[:, None, :] - a[None, :, :]                                  # (k, m, 2)
        cross = e[None, :, 0] * rel[..., 1] - e[None, :, 1] * rel[..., 0]
        s = np.clip(np.einsum("kmi,mi->km", rel, e) / np.maximum(np.einsum("mi,mi->m", e, e), 1e-300), 0.0, 1.0)
        d = rel - s[..., None] * e[None, :, :]
        dist = np.min(np.hypot(d[..., 0], d[..., 1]), axis=1)
        return np.where(np.all(cross >= 0.0, axis=1), 0.0, dist), 1e-9 * float(np.max(np.abs(hull)))


def _check_contact_face(scene, body, grasp, face):
    if "face_radius" in face:
        R, fc = float(face["face_radius"]), np.asarray(face["face_center"], dtype=float)
        what = f"the disc of radius {R:g} m (Body.outline_radius)"
        scale = R
        outside = lambda p: max(math.hypot(*(np.asarray(p) - fc)) - R, 0.0)  # noqa: E731
        far = lambda p: math.hypot(*(np.asarray(p) - fc)) + R  # noqa: E731
        hull = None
    else:
        hull = _hull(face["face"])
        if len(hull) < 3:
            return
        what = ("the outline's convex hull (Body.outline)" if face.get("partial") or (
            grasp.pad is not None and body.outline is not None) else "the box's x-y face (Body.size)")
        scale = float(np.max(np.abs(hull)))
        outside = lambda p: _outside(hull, p)  # noqa: E731
        far = lambda p: float(np.max(np.hypot(*(hull - np.asarray(p)).T)))  # noqa: E731
    tol = 1e-9 * scale
    if grasp.pad is None:
        patch = grasp.patch
        c = np.asarray(patch.center)
        d = outside(c)
        if d > tol:
            raise ValueError(
                f"Grasp.patch.center = ({c[0]:g}, {c[1]:g}) m lies {d:.4g} m outside the object's contact face, "
                f"{what}: the plates would not touch the object at t = 0. The centre of pressure is in the object "
                f"frame, relative to the centre of mass: put it inside the face")
        # a patch larger than the face: it fits inside the face in no position
        if hull is None:
            span = np.array([2.0 * R, 2.0 * R])
        else:
            span = hull.max(axis=0) - hull.min(axis=0)
        reg = patch.region()
        big = None
        if face.get("partial"):
            return                          # an outline of contact corners states no face to compare with
        if reg is not None and patch.shape == "rectangle":
            w, h = patch.dims
            size = f"a {w:g} x {h:g} m rectangle"
            if hull is None and math.hypot(w, h) > 2.0 * R * (1 + 1e-9):
                big = (math.hypot(w, h), 2.0 * R, "diagonal", "diameter")
            elif hull is not None and (w > span[0] * (1 + 1e-9) or h > span[1] * (1 + 1e-9)):
                big = (w, span[0], "width", "width") if w > span[0] * (1 + 1e-9) else (h, span[1], "height", "height")
        elif reg is not None and "vertices" in reg:
            v = np.asarray(reg["vertices"], dtype=float)
            ext = v.max(axis=0) - v.min(axis=0)
            size = f"a polygon of {ext[0]:g} x {ext[1]:g} m"
            limit = np.array([2.0 * R, 2.0 * R]) if hull is None else span
            if ext[0] > limit[0] * (1 + 1e-9) or ext[1] > limit[1] * (1 + 1e-9):
                k = 0 if ext[0] > limit[0] * (1 + 1e-9) else 1
                big = (float(ext[k]), float(limit[k]), ("width", "height")[k],
                       "diameter" if hull is None else ("width", "height")[k])
        elif reg is not None:
            r = reg["radius"]
            size = f"a disc of radius {r:g} m"
            if 2.0 * r > float(np.min(span)) * (1 + 1e-9):
                big = (2.0 * r, float(np.min(span)), "diameter", "diameter" if hull is None else "smaller side")
        if big is not None:
            _plausibility(
                f"Grasp.patch ({size}) is larger than the object's contact face, {what}: its {big[2]} {big[0]:g} m "
                f"exceeds the face's {big[3]} {big[1]:.4g} m. The pressure patch lies on the face; check the patch's "
                f"size [m] (full side lengths, Patch.rectangle(width, height) along the object's x and y) against "
                f"the body's", "Grasp.patch", big[0], big[1])
        if reg is None and patch.e_r > far(c) * (1 + 1e-9):
            _plausibility(
                f"Grasp.patch.e_r = {patch.e_r:g} m exceeds {far(c):.4g} m, the farthest point of the object's "
                f"contact face ({what}) from the patch centre: e_r is the patch's mean distance from its centre, "
                f"so no patch on that face has it", "Grasp.patch.e_r", patch.e_r, far(c))
        return
    pad = grasp.pad
    th = scene.q0[2]
    cs, sn = math.cos(th), math.sin(th)
    rot = np.array([[cs, -sn], [sn, cs]])
    q = np.asarray(scene.q0[:2])
    if hull is None:
        fcB = q + rot @ fc
        if pad.radius is not None:
            miss = math.hypot(*(np.asarray(pad.center) - fcB)) >= R + pad.radius
        else:
            miss = _outside(_hull(pad.outline()), fcB) >= R
    else:
        faceB = q + hull @ rot.T
        if pad.radius is not None:
            miss = _outside(faceB, pad.center) >= pad.radius
        else:
            miss = _separated(faceB, _hull(pad.outline()))
    if miss:
        kind = f"disc of radius {pad.radius:g} m" if pad.radius is not None else "polygon"
        raise ValueError(
            f"Grasp.pad (a {kind} about ({pad.center[0]:g}, {pad.center[1]:g}) m in the gripper frame B) misses the "
            f"object's contact face, {what}, at its initial pose Scene.q0 = {scene.q0}: the plates would not touch "
            f"the object at t = 0. Move Grasp.pad.center or Scene.q0 so that the pad overlaps the face")


@dataclass(frozen=True)
class Scene:
    """A complete forward problem: object, grasp, gripper motion, free coordinates.

    dof : which coordinates of the object relative to the gripper are free:
        ``"translation"`` (along ``slide_axis``, q = s [m]),
        ``"rotation"`` (about the patch's centre of pressure, fixed in B, an
        ideal pin: paper Section 2.3; q = theta [rad]) or
        ``"planar"`` (q = x, y, theta). A 1-DoF scene is solved in 1-DoF and
        its reduction certified along the run (:attr:`exdex.Result.certificate`).
        ``"auto"``: :func:`exdex.simulate` runs the smallest model whose
        certificate holds and switches to the planar model where it fails
        (:attr:`exdex.Result.models`): each 1-DoF candidate is certified as
        it runs and ends at its failure, and the planar run goes on from
        the chosen one's last state there, so an escalating scene costs the
        1-DoF runs up to the switch plus the planar run from it (see
        ``benchmarks/bench_certify.py``); the other entry points (Model,
        Stepper, batches, plans) take an explicit dof. Not the default: the
        default ``"translation"`` keeps every existing result bit for bit (and
        warns where its reduction fails), while ``"auto"`` may answer in other
        coordinates (x, y, theta) than the scene's user wrote code for.
    slide_axis : unit vector of B's plate plane (translation scenes).
    q0 : initial (x, y, theta) of the object frame C in B [m, m, rad].
    v0 : initial relative velocity (vx, vy, omega) [m/s, m/s, rad/s]; a
        translation scene keeps its component along slide_axis.
    gripper_rotation, gripper_position : initial pose of B in A.
    gravity : in A [m/s^2].
    stops : fixed world planes (``Stop``) the object outline may not cross.
    obstacles : convex solids fixed in the world (``Obstacle``) the object
        outline may not enter (every method but the analytic one solves such
        scenes, with frictional obstacles and disc outlines too).

    The plates must touch the object at t = 0: a ``Grasp.patch.center``
    outside the object's face (the box of ``Body.size``, the disc outline,
    else -- not for a rotation's pin -- the hull of ``Body.outline``) or a
    ``Grasp.pad`` that misses the face (:meth:`Body.contact_face`) at ``q0``
    is a ValueError naming the field. A patch larger than the face (it fits
    in no position; an ``e_r`` beyond the face's farthest point) gives an
    :class:`exdex.PlausibilityWarning` naming ``Grasp.patch``.
    """

    body: Body
    grasp: Grasp
    motion: _Motion = field(default_factory=Rest)
    dof: str = "translation"
    slide_axis: Vector = (0.0, 1.0)
    q0: Vector = (0.0, 0.0, 0.0)
    v0: Vector = (0.0, 0.0, 0.0)
    gripper_rotation: Matrix = DEFAULT_GRIPPER_ROTATION
    gripper_position: Vector = (0.0, 0.0, 0.0)
    gravity: Vector = (0.0, 0.0, -9.81)
    stops: Tuple[Stop, ...] = ()
    obstacles: Tuple[Obstacle, ...] = ()

    def __post_init__(self):
        if not isinstance(self.body, Body):
            raise TypeError(f"Scene.body must be an exdex.Body, got {type(self.body).__name__}")
        if not isinstance(self.grasp, Grasp):
            raise TypeError(f"Scene.grasp must be an exdex.Grasp, got {type(self.grasp).__name__}")
        if not isinstance(self.motion, _Motion):
            raise TypeError(f"Scene.motion must be an exdex motion (Rest, AsymmetricProfile, "
                            f"TrapezoidalProfile, SampledTrajectory, Shake, Pause, Chain), "
                            f"got {type(self.motion).__name__}")
        if self.dof not in DOFS and self.dof != "auto":
            raise ValueError(f"Scene.dof must be one of {sorted(DOFS) + ['auto']}, got {self.dof!r}")
        object.__setattr__(self, "slide_axis", _unit(self.slide_axis, "Scene.slide_axis", 2))
        object.__setattr__(self, "q0", _tuple(_array(self.q0, "Scene.q0", (3,))))
        object.__setattr__(self, "v0", _tuple(_array(self.v0, "Scene.v0", (3,))))
        object.__setattr__(self, "gripper_rotation", _rotation(self.gripper_rotation, "Scene.gripper_rotation"))
        object.__setattr__(self, "gripper_position", _tuple(_array(self.gripper_position, "Scene.gripper_position", (3,))))
        object.__setattr__(self, "gravity", _tuple(_array(self.gravity, "Scene.gravity", (3,))))
        stops = self.stops
        if isinstance(stops, Stop):
            stops = (stops,)  # a single stop
        elif isinstance(stops, (str, bytes)) or not hasattr(stops, "__iter__"):
            raise TypeError(f"Scene.stops must be an exdex.Stop or a sequence of them, got {type(stops).__name__}")
        stops = tuple(stops)
        for i, s in enumerate(stops):
            if not isinstance(s, Stop):
                raise TypeError(f"Scene.stops[{i}] must be an exdex.Stop, got {type(s).__name__}")
        if len(stops) > _core.MAX_STOPS:
            raise ValueError(f"Scene.stops holds at most {_core.MAX_STOPS} stops, got {len(stops)}")
        object.__setattr__(self, "stops", stops)
        obstacles = self.obstacles
        if isinstance(obstacles, Obstacle):
            obstacles = (obstacles,)
        elif isinstance(obstacles, (str, bytes)) or not hasattr(obstacles, "__iter__"):
            raise TypeError(f"Scene.obstacles must be an exdex.Obstacle or a sequence of them, "
                            f"got {type(obstacles).__name__}")
        obstacles = tuple(obstacles)
        for i, o in enumerate(obstacles):
            if not isinstance(o, Obstacle):
                raise TypeError(f"Scene.obstacles[{i}] must be an exdex.Obstacle, got {type(o).__name__}")
        if len(obstacles) > _core.MAX_OBSTACLES:
            raise ValueError(f"Scene.obstacles holds at most {_core.MAX_OBSTACLES} obstacles, got {len(obstacles)}")
        object.__setattr__(self, "obstacles", obstacles)
        _check_contact(self)

    def _repr_html_(self) -> str:
        from exdex._html import quantity, summary_table

        b, g = self.body, self.grasp
        body = quantity(b.mass, "kg")
        if b.size is not None:
            body += ", box " + " x ".join(f"{1e3 * x:g}" for x in b.size) + " mm"
        elif b.outline_radius is not None:
            body += f", disc radius {1e3 * b.outline_radius:g} mm"
        gs = g.schedule
        grip = (f"schedule {min(gs.forces):g} to {max(gs.forces):g} N ({gs.kind}, t = {gs.times[0]:g} to "
                f"{gs.times[-1]:g} s)" if gs is not None else quantity(g.grip_force, "N"))
        if g.pad is not None:
            outline = g.pad.outline()
            contact = "pad on the fingers, " + (f"disc radius {1e3 * g.pad.radius:g} mm" if g.pad.radius is not None
                                                else f"polygon of {len(outline)} vertices")
        else:
            p = g.patch
            dims = {"disc": lambda d: f"disc radius {1e3 * d[0]:g} mm",
                    "rectangle": lambda d: f"rectangle {1e3 * d[0]:g} x {1e3 * d[1]:g} mm"}
            shape = dims[p.shape](p.dims) if p.shape in dims and p.dims else "given"
            contact = f"patch on the object, {shape}, e_r {1e3 * p.e_r:.4g} mm"
        capacity = f"{g.capacity:.6g} N" + (" (at t = 0)" if gs is not None else "")
        rows = [("object", body), ("grip force per finger", grip), ("fingers", g.fingers),
                ("mu" if g.mu_static is None else "mu (static)",
                 f"{g.mu:g}" if g.mu_static is None else f"{g.mu:g} ({g.mu_static:g})"),
                ("friction capacity", capacity), ("contact", f"{contact}; limit surface {g.limit_surface}"),
                ("motion", f"{type(self.motion).__name__}, ends at t = {self.motion.end_time:g} s"),
                ("free coordinates", self.dof)]
        if self.stops or self.obstacles:
            rows.append(("stops, obstacles", f"{len(self.stops)}, {len(self.obstacles)}"))
        return summary_table("exdex.Scene", rows)

    def check_stops(self) -> None:
        """Raise a ValueError naming the stop, the outline vertex and the
        penetration depth if the object starts beyond a stop (the core's test,
        in the same metres). A scene may be built and saved that way; it is
        checked when simulated."""
        if not self.stops:
            return
        if isinstance(self.motion, (Rest, AsymmetricProfile, TrapezoidalProfile)):
            # these motions start at the initial pose
            R, p = np.array(self.gripper_rotation), np.array(self.gripper_position)
        else:
            kin = self.motion.evaluate(0.0, self.gripper_rotation, self.gripper_position)
            R, p = kin["R"][0], kin["p"][0]
        th = self.q0[2]
        c, s = math.cos(th), math.sin(th)
        radius = self.body.outline_radius
        disc = radius is not None
        verts = np.array([self.body.outline_center]) if disc else self.body.vertices()
        xb = np.array(self.q0[:2]) + verts @ np.array([[c, s], [-s, c]])   # rows: q0 + Rz(th) v
        xa = np.hstack([xb, np.zeros((len(xb), 1))]) @ R.T + p
        for k, st in enumerate(self.stops):
            gaps = (xa - np.array(st.point)) @ np.array(st.normal)
            if radius is not None:
                # the support point: the centre less the radius times |n_B,xy|
                gaps = gaps - radius * float(np.hypot(*(R.T @ np.array(st.normal))[:2]))
            j = int(np.argmin(gaps))
            if gaps[j] < -1e-9:
                where = "the disc outline" if disc else (
                    "the centre of mass" if self.body.size is None and self.body.outline is None
                    else f"outline vertex {j} ({verts[j][0]:g}, {verts[j][1]:g}) m")
                raise ValueError(
                    f"Scene.stops[{k}] (point {st.point}, normal {st.normal}) starts inside the object: "
                    f"{where} is {-gaps[j]:.6g} m beyond it at t = 0. Move the stop or the object "
                    f"(Scene.q0 = {self.q0}) so that it starts on the stop's allowed side")

    def check_motion(self) -> None:
        """Raise a ValueError naming the piece if a :class:`Chain` motion
        jumps between two pieces (position, or velocity without
        ``allow_jump``), as the core checks it at this initial gripper pose."""
        if not isinstance(self.motion, Chain):
            return
        try:
            _core.motion_jumps(self.to_spec())
        except ValueError as exc:
            import re

            m = re.search(r"motion\.pieces\[(\d+)\]", str(exc))
            if not m:
                raise
            i = int(m.group(1))
            piece = self.motion.pieces[i]
            if i == 0:
                raise ValueError(f"Chain.pieces[0] ({type(piece).__name__}) is not a valid chain piece: {exc}") from None
            t = self.motion.start_times[i]
            raise ValueError(
                f"Chain.pieces[{i}] ({type(piece).__name__}) does not continue Chain.pieces[{i - 1}] "
                f"({type(self.motion.pieces[i - 1]).__name__}) at t = {t:.9g} s: the gripper's velocity jumps there "
                f"(or an absolute log starts away from the pose where the piece before ends). Make the pieces meet "
                f"(e.g. a Shake of whole or half cycles, ramps on a trapezoid) or pass Chain(..., allow_jump=True) "
                f"to apply the velocity jump to the object") from None

    @property
    def ndof(self) -> int:
        """Number of free coordinates (1 or 3; "auto": 3, its results' planar coordinates)."""
        return 3 if self.dof in ("planar", "auto") else 1

    @property
    def coordinate_names(self) -> Tuple[str, ...]:
        return {"translation": ("s",), "rotation": ("theta",), "planar": ("x", "y", "theta"),
                "auto": ("x", "y", "theta")}[self.dof]

    @property
    def end_time(self) -> float:
        """When the scene's inputs stop changing [s]: the later of the gripper
        motion's end (``motion.end_time``) and the grip schedule's last time
        (0 for a gripper at rest with a constant grip). Default end times of
        runs and plans start from it."""
        end = float(self.motion.end_time)
        sched = self.grasp.schedule
        if sched is not None:
            end = max(end, float(sched.times[-1]))
        return max(end, 0.0)

    def to_spec(self, method: str = "implicit", friction_solver: str = "scalar", eps: float = 1e-4,
                rtol: float = 1e-8, atol: float = 1e-10) -> Dict[str, Any]:
        """The flat dict the C core reads (keys mirror ``exdex_scene_def``)."""
        if self.dof == "auto":
            raise ValueError("Scene.dof='auto' is resolved by exdex.simulate (it runs the smallest model whose "
                             "certificate holds); Model, Stepper, batches and plans need an explicit dof "
                             "('translation', 'rotation' or 'planar')")
        spec = dict(
            mass=self.body.mass, inertia=np.array(self.body.inertia).ravel(),
            vertices=self.body.vertices() if (self.stops or self.obstacles) and self.body.outline_radius is None
            else None,
            mu=self.grasp.mu, grip_force=self.grasp.grip_force, fingers=int(self.grasp.fingers),
            mu_static=0.0 if self.grasp.mu_static is None else self.grasp.mu_static,  # 0: equal to mu
            e_r=self.grasp.patch.e_r, patch_center=self.grasp.patch.center,
            gravity=self.gravity, dof=DOFS[self.dof], slide_axis=self.slide_axis,
            q0=self.q0, v0=self.v0, R0=np.array(self.gripper_rotation).ravel(), p0=self.gripper_position,
            motion_kind=_core.MOTION_REST, motion_rotation=0, motion_axis=(0.0, 0.0, 1.0), motion_center=(0.0, 0.0, 0.0),
            motion_amplitude=0.0, motion_duration=1.0, motion_beta=0.5, motion_v_max=1.0,
            stop_points=np.array([s.point for s in self.stops]).reshape(-1, 3),
            stop_normals=np.array([s.normal for s in self.stops]).reshape(-1, 3),
            stop_mus=np.array([s.mu for s in self.stops], dtype=float),
            method=METHODS[method], friction_solver=SOLVERS[friction_solver],
            eps=eps, rtol=rtol, atol=atol,
        )
        if self.body.outline_radius is not None:
            spec.update(disc_radius=self.body.outline_radius, disc_center=self.body.outline_center)
        if self.grasp.pad is not None:
            if method == "analytic":
                raise ValueError("Grasp.pad: the analytic method solves the patch fixed on the object; use "
                                 "method='implicit', 'event', 'regularised' or 'explicit' with pads on the fingers")
            spec.update(self.grasp.pad._spec())
            spec.update(self.body.contact_face())
        if self.obstacles:
            if method not in ("implicit", "explicit", "event", "regularised"):
                raise ValueError(f"Scene.obstacles: the implicit, explicit, event and regularised methods solve "
                                 f"scenes with obstacles, got method={method!r}")
            spec["obstacles"] = [o._spec() for o in self.obstacles]
        spec.update(self.motion._spec())
        sched = self.grasp.schedule
        if sched is not None:
            # the core's grip_force scales the schedule (a batch's grip_force varies that scale)
            spec.update(grip_force=1.0, grip_schedule=np.array([sched.times, sched.forces]),
                        grip_kind=GRIP_KINDS[sched.kind])
        if self.grasp.limit_surface == "exact":
            spec["limit_surface"] = LIMIT_SURFACES["exact"]
            # the region: pad and face (the core intersects them), else the patch's
            reg = None if self.grasp.pad is not None else self.grasp.patch.region()
            if reg is not None and "radius" in reg:
                spec["region_radius"] = reg["radius"]
            elif reg is not None:
                spec["region_vertices"] = reg["vertices"]
        return spec


def replace(scene: _T, **changes: Any) -> _T:
    """``dataclasses.replace`` re-exported for convenience."""
    return dataclasses.replace(scene, **changes)  # type: ignore[type-var]

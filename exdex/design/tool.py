"""Assistive-tool design (paper Section 3): twist cones, their volumes, tool optimisation.

A planar object pushed against fixed tool surfaces can only move with twists
x = (Vx, Vy, wz) that do not push any contact point into its surface:
n . (v + w x r) >= 0 per contact point r with normal n (pointing from the tool
into the object's free side). The feasible set is a polyhedral cone
{x : A x >= 0} (Fig. 8). The paper measures how well a tool constrains an
object by the cone's volume inside a cuboid of twists (Eq. 13) and picks the
tool angle minimising that volume summed over the attack angles (Eq. 12).

Conventions (stated once, used everywhere):

* Twists are expressed in the object's own frame at its reference point (the
  origin of its vertex coordinates; the centre for :data:`UNIT_SQUARE`), as
  in Eqs. 10-11. Units: m/s, m/s, rad/s (the paper's unit square is 1 m).
* The cuboid is **centred** on the zero twist: ``[-dVx/2, dVx/2] x
  [-dVy/2, dVy/2] x [-dwz/2, dwz/2]`` (:class:`Box`; ``centre`` moves it).
  The paper's Eq. 13 box is ``Box.eq13()`` (dVx = dVy = 1/sqrt2, dwz = 2,
  V_max = 1).
* Tool: two flat surfaces through the apex with inward normals
  ``(-sin alpha1, cos alpha1)`` ("left", a floor for alpha1 = 0) and
  ``(-sin alpha2, cos alpha2)`` ("right"); the paper's tool angle is
  ``theta = alpha2 - alpha1`` (90 deg: a square corner, 0: one flat surface).
  An object at attack angle ``phi`` is its polygon rotated by ``phi``.
* Model ``"contact"`` derives the rows from the contacts (support vertices of
  the polygon, one row per end vertex of an edge contact); model ``"paper"``
  uses Eqs. 10-11 literally (unit square only). See :func:`compare_rows`.

Volumes: ``"exact"`` (divergence theorem: only the box faces contribute), ``"grid"`` (the
paper's discretisation) and ``"qmc"`` (randomised Sobol, with a standard error).
All the loops run in C (``exdex._tool``) with the GIL released.
"""
from __future__ import annotations

import math
import numbers
from dataclasses import dataclass, field
from typing import Any, Dict, Iterable, List, Mapping, Optional, Sequence, Tuple, Union

import numpy as np
from numpy.typing import ArrayLike, NDArray

from exdex import _tool

__all__ = [
    "UNIT_SQUARE", "Box", "Tool", "ToolProblem", "ThetaResult", "ToolResult", "ConvergenceError",
    "rectangle", "regular_polygon", "contact_rows", "paper_rows", "tool_rows", "compare_rows",
    "cone_volume", "cone_volumes", "tool_volumes", "objective", "theta_curve", "optimise_theta",
    "optimise_tool", "permitted_rows", "rod_rotation", "rod_descent_closed_form",
    "rod_max_rotation", "phi_set",
    "figure_theta_curves", "figure_box_aspect", "figure_rod",
]

#: A GSL minimiser did not converge: the same class as :class:`exdex.SolverError`.
ConvergenceError = _tool.SolverError

#: The paper's unit square, centred on its reference point (counter-clockwise).
UNIT_SQUARE = np.array([[-0.5, -0.5], [0.5, -0.5], [0.5, 0.5], [-0.5, 0.5]])

SQRT2 = math.sqrt(2.0)


# ---------------------------------------------------------------- validation

def _real(value, name, *, low=None, high=None, low_open=False):
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise TypeError(f"{name} must be a real number, got {type(value).__name__}")
    x = float(value)
    if not math.isfinite(x):
        raise ValueError(f"{name} must be finite, got {x}")
    if low is not None and (x <= low if low_open else x < low):
        raise ValueError(f"{name} must be {'>' if low_open else '>='} {low:g}, got {x:g}")
    if high is not None and x > high:
        raise ValueError(f"{name} must be <= {high:g}, got {x:g}")
    return x


def _angles(values, name):
    try:
        a = np.atleast_1d(np.asarray(values, dtype=float))
    except (TypeError, ValueError):
        raise TypeError(f"{name} must be a real number or 1-D array of angles [rad]") from None
    if a.ndim != 1 or a.size == 0 or not np.all(np.isfinite(a)):
        raise ValueError(f"{name} must be a non-empty 1-D array of finite angles [rad]")
    return a


def _polygon(v, name="shape"):
    try:
        a = np.ascontiguousarray(v, dtype=float)
    except (TypeError, ValueError):
        raise TypeError(f"{name} must be a real (nv, 2) array of vertices [m]") from None
    if a.ndim != 2 or a.shape[1] != 2 or not 3 <= a.shape[0] <= _tool.MAX_VERTICES:
        raise ValueError(f"{name} must have shape (nv, 2) with 3 <= nv <= {_tool.MAX_VERTICES}")
    if not np.all(np.isfinite(a)):
        raise ValueError(f"{name} must have finite vertices")
    x, y = a[:, 0], a[:, 1]
    area = 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y))
    if not abs(area) > 0:
        raise ValueError(f"{name} must have a non-zero area")
    return a


def rectangle(width: float, height: float) -> NDArray[np.float64]:
    """A centred width x height rectangle [m], counter-clockwise."""
    w = _real(width, "width", low=0, low_open=True) / 2
    h = _real(height, "height", low=0, low_open=True) / 2
    return np.array([[-w, -h], [w, -h], [w, h], [-w, h]])


def regular_polygon(n: int, radius: float = 0.5, rotation: float = 0.0) -> NDArray[np.float64]:
    """A regular n-gon (3 <= n <= 32) of circumradius ``radius`` [m] about its centre."""
    if isinstance(n, bool) or not isinstance(n, numbers.Integral):
        raise TypeError(f"n must be an int, got {type(n).__name__}")
    if not 3 <= n <= _tool.MAX_VERTICES:
        raise ValueError(f"n must be in [3, {_tool.MAX_VERTICES}], got {n}")
    r = _real(radius, "radius", low=0, low_open=True)
    t = _real(rotation, "rotation") + 2 * np.pi * np.arange(n) / n
    return np.column_stack([r * np.cos(t), r * np.sin(t)])


# ---------------------------------------------------------------- the box

@dataclass(frozen=True)
class Box:
    """The cuboid of twists, centred on ``centre`` (default the zero twist).

    ``dVx, dVy`` [m/s], ``dwz`` [rad/s] are its full side lengths (Eq. 13).
    """
    dVx: float = 1 / SQRT2
    dVy: float = 1 / SQRT2
    dwz: float = 2.0
    centre: Union[Sequence[float], NDArray[Any]] = (0.0, 0.0, 0.0)

    def __post_init__(self):
        for name in ("dVx", "dVy", "dwz"):
            object.__setattr__(self, name, _real(getattr(self, name), name, low=0, low_open=True))
        c = tuple(_real(x, "centre[i]") for x in self.centre)
        if len(c) != 3:
            raise ValueError("centre must have 3 entries (Vx, Vy, wz)")
        object.__setattr__(self, "centre", c)

    @classmethod
    def eq13(cls) -> "Box":
        """The paper's choice (Eq. 13): dVx = dVy = 1/sqrt2, dwz = 2, V_max = 1."""
        return cls(1 / SQRT2, 1 / SQRT2, 2.0)

    @classmethod
    def with_aspect(cls, a: float) -> "Box":
        """Unit volume, dVx = dVy = a, dwz = 1/a^2 (the continuous variation of
        the cuboid's dimensions the paper mentions; a = 2^-1/2 is Eq. 13)."""
        a = _real(a, "a", low=0, low_open=True)
        return cls(a, a, 1.0 / (a * a))

    @property
    def lo(self) -> NDArray[np.float64]:
        return np.array(self.centre) - 0.5 * np.array([self.dVx, self.dVy, self.dwz])

    @property
    def hi(self) -> NDArray[np.float64]:
        return np.array(self.centre) + 0.5 * np.array([self.dVx, self.dVy, self.dwz])

    @property
    def volume(self) -> float:
        return self.dVx * self.dVy * self.dwz


def _box(box):
    if box is None:
        return Box.eq13()
    if not isinstance(box, Box):
        raise TypeError(f"box must be an exdex.tool.Box, got {type(box).__name__}")
    return box


# ---------------------------------------------------------------- rows

def contact_rows(points: ArrayLike, normals: ArrayLike, mu: float = 0.0) -> NDArray[np.float64]:
    """Rows of contacts at ``points`` (k, 2) with unit ``normals`` (k, 2).

    mu = 0: one row (n, r x n) per contact, shape (k, 3). mu > 0: each contact's
    two friction-cone edges (paper Fig. 10), shape (2k, 3); see
    :func:`permitted_rows` for what the resulting cone means.
    """
    return _tool.contact_rows(points, normals, _real(mu, "mu", low=0))


def paper_rows(phi: ArrayLike, theta: ArrayLike) -> NDArray[np.float64]:
    """The paper's Eqs. 10-11 literally, rows (n, 2, 3) (phi, theta broadcast) [rad]."""
    p, t = np.broadcast_arrays(np.asarray(phi, dtype=float), np.asarray(theta, dtype=float))
    return _tool.paper_rows(p.ravel(), t.ravel())


@dataclass(frozen=True)
class Tool:
    """A V tool: opening ``theta`` = alpha2 - alpha1 [rad] and rotation
    ``alpha1`` [rad]; ``s`` [m], if given, places a spring plunger pressing
    along -y at x = s (tool frame, apex at the origin) on the wedged object:
    it touches the object's topmost point on the line x = s (no contact if the
    line misses the object; collisions of the plunger with the tool's own
    surfaces are not checked)."""
    theta: float = math.pi / 2
    alpha1: float = 0.0
    s: Optional[float] = None

    def __post_init__(self):
        object.__setattr__(self, "theta", _real(self.theta, "theta"))
        object.__setattr__(self, "alpha1", _real(self.alpha1, "alpha1"))
        if self.s is not None:
            object.__setattr__(self, "s", _real(self.s, "s"))

    @property
    def alpha2(self) -> float:
        return self.alpha1 + self.theta

    def params(self) -> Tuple[float, float, float]:
        return (self.alpha1, self.alpha2, 0.0 if self.s is None else self.s)


@dataclass(frozen=True)
class ToolProblem:
    """What Eq. 12 sums over: object ``shapes`` (polygons (nv, 2) in their own
    frame [m]), attack angles ``phi`` [rad], the twist ``box``, tool friction
    ``mu`` and an optional ``push`` wrench (F_x, F_y, M_z) in the tool frame
    (then only twists with push . x >= 0 count, see :func:`permitted_rows`).
    ``model``: "contact" (derived rows) or "paper" (Eqs. 10-11, unit square)."""
    phi: Union[Sequence[float], NDArray[Any]]
    shapes: Sequence[ArrayLike] = (UNIT_SQUARE,)
    box: Box = field(default_factory=Box.eq13)
    mu: float = 0.0
    push: Optional[Union[Sequence[float], NDArray[Any]]] = None
    model: str = "contact"

    def __post_init__(self):
        object.__setattr__(self, "phi", tuple(_angles(self.phi, "phi")))
        if isinstance(self.shapes, np.ndarray) and self.shapes.ndim == 2:
            shapes = (self.shapes,)
        else:
            shapes = tuple(self.shapes)
        if not shapes:
            raise ValueError("shapes must hold at least one polygon")
        object.__setattr__(self, "shapes",
                           tuple(_polygon(s, f"shapes[{i}]") for i, s in enumerate(shapes)))
        object.__setattr__(self, "box", _box(self.box))
        object.__setattr__(self, "mu", _real(self.mu, "mu", low=0))
        if self.push is not None:
            p = tuple(_real(x, "push[i]") for x in self.push)
            if len(p) != 3:
                raise ValueError("push must have 3 entries (F_x, F_y, M_z)")
            object.__setattr__(self, "push", p)
        if self.model not in ("contact", "paper"):
            raise ValueError(f"model must be 'contact' or 'paper', got {self.model!r}")

    def _kw(self):
        return dict(shapes=list(self.shapes), phi=np.array(self.phi), lo=self.box.lo,
                    hi=self.box.hi, mu=self.mu, push=self.push, model=self.model)


def tool_rows(problem: "ToolProblem", tool: Tool, phi: float, shape: int = 0) -> NDArray[np.float64]:
    """Rows (m, 3) of ``problem.shapes[shape]`` at attack angle ``phi`` in ``tool``."""
    if not isinstance(tool, Tool):
        raise TypeError("tool must be an exdex.tool.Tool")
    kw = problem._kw()
    kw.pop("phi")
    return _tool.tool_rows(phi=_real(phi, "phi"), alpha1=tool.alpha1, alpha2=tool.alpha2,
                           s=tool.s, shape=shape, **kw)


def compare_rows(phi: float, theta: float) -> Tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Eqs. 10-11 against the rows derived from the contacts, unit square.

    Returns (paper (2, 3), derived (k, 3)). For 0 < phi < 90 deg and
    0 < theta - phi < 90 deg the derived contacts are the vertices (-1/2, -1/2)
    (left surface) and (1/2, -1/2) (right surface), and the derived rows are
        ( sin phi,  cos phi, -(cos phi - sin phi) / 2)
        (-sin psi,  cos psi,  (cos psi - sin psi) / 2),   psi = theta - phi.
    The translational parts equal Eqs. 10-11; the wz coefficients differ: Eq. 10
    has (1 - sin phi) where the lever arm gives (cos phi - sin phi) (equal only
    at phi = 0), and Eq. 11 has the sign of Eq. 10, where the mirror symmetry of
    the set-up (x -> -x, wz -> -wz) flips it.
    """
    prob = ToolProblem(phi=[phi], model="contact")
    return paper_rows(phi, theta)[0], tool_rows(prob, Tool(theta=theta), phi)


def permitted_rows(points: ArrayLike, normals: ArrayLike, mu: float = 0.0,
                   push: Optional[ArrayLike] = None) -> NDArray[np.float64]:
    """Rows of the twists a frictional tool still permits (paper Section 3.2).

    Model (documented force analysis): a contact with friction coefficient mu
    can transmit any force in its friction cone, spanned by the two edges
    e+- = n cos(a) +- t sin(a), tan(a) = mu (Fig. 10). A twist is permitted if
    no such contact force opposes it, i.e. every contact wrench does
    non-negative power on it: (e+-, r x e+-) . x >= 0 for both edges of every
    contact, so the contact point's velocity lies in the dual of its friction
    cone (a cone of half-angle 90 deg - a about n). mu = 0 gives the
    frictionless cone; mu -> infinity pins the contact point (it may only lift
    off along n). With a ``push`` wrench P (F_x, F_y, M_z) applied by the
    gripper, quasi-static motion must be driven by the push (contacts only
    dissipate), adding P . x >= 0; if -P is a non-negative combination of the
    contact wrenches the tool holds the object and the permitted set has
    volume 0.
    """
    rows = contact_rows(points, normals, mu)
    if push is not None:
        p = np.asarray(push, dtype=float)
        if p.shape != (3,) or not np.all(np.isfinite(p)):
            raise ValueError("push must be a finite wrench (F_x, F_y, M_z) of shape (3,)")
        rows = np.vstack([rows, p])
    return rows


# ---------------------------------------------------------------- volumes

def cone_volumes(rows: ArrayLike, box: Optional[Box] = None, method: str = "exact", grid_n: int = 64,
                 qmc_points: int = 1 << 16, qmc_shifts: int = 16, seed: int = 1) -> Tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Volumes of {x in box : rows x >= 0} for rows (n, m, 3) (or (m, 3)).

    Returns (volume (n,), err (n,)); err is the QMC standard error over the
    ``qmc_shifts`` random shifts (NaN for "exact" and "grid").
    """
    box = _box(box)
    try:
        r = np.asarray(rows, dtype=float)
    except (TypeError, ValueError):
        raise TypeError("rows must be a real array of shape (m, 3) or (n, m, 3)") from None
    if r.ndim == 2:
        r = r[None]
    return _tool.volumes(r, box.lo, box.hi, method, grid_n=grid_n, qmc_points=qmc_points,
                         qmc_shifts=qmc_shifts, seed=seed)


def cone_volume(rows: ArrayLike, box: Optional[Box] = None, method: str = "exact", **opts: Any) -> float:
    """Volume of one cone {x in box : rows x >= 0}, rows (m, 3); a float."""
    r = np.asarray(rows, dtype=float)
    if r.ndim != 2:
        raise ValueError("rows must have shape (m, 3) for one cone (use cone_volumes for many)")
    return float(cone_volumes(r, box, method, **opts)[0][0])


def tool_volumes(problem: "ToolProblem", tools: Iterable[Tool], progress: bool = False,
                 chunk: int = 64) -> NDArray[np.float64]:
    """Exact volumes (T, S, P) for T tools, S shapes, P attack angles (one C
    call per chunk of tools, GIL released; tqdm progress if ``progress``)."""
    tools = list(tools)
    if not all(isinstance(t, Tool) for t in tools):
        raise TypeError("tools must be exdex.tool.Tool instances")
    if not tools:
        raise ValueError("tools must not be empty")
    plunger = tools[0].s is not None
    if any((t.s is not None) != plunger for t in tools):
        raise ValueError("tools must all have a plunger (s) or none")
    params = np.array([t.params() for t in tools])
    starts = range(0, len(tools), chunk)
    if progress:
        from exdex._optional import progress_bar

        starts = progress_bar(starts, desc="volumes", unit="chunk", leave=False, auto=True,
                              feature="tool_volumes(progress=True)")
    parts = [_tool.tool_volumes(tools=params[i:i + chunk], plunger=plunger, **problem._kw())
             for i in starts]
    return np.concatenate(parts, axis=0)


def objective(problem: "ToolProblem", tool: Tool) -> float:
    """Eq. 12's objective: the sum over shapes and attack angles of the exact volume."""
    return float(tool_volumes(problem, [tool]).sum())


def theta_curve(problem: "ToolProblem", thetas: ArrayLike, alpha1: float = 0.0, s: Optional[float] = None,
                progress: bool = False) -> NDArray[np.float64]:
    """Objective of Eq. 12 on a grid of tool angles ``thetas`` [rad]: (T,)."""
    th = _angles(thetas, "thetas")
    v = tool_volumes(problem, [Tool(theta=t, alpha1=alpha1, s=s) for t in th], progress=progress)
    return v.sum(axis=(1, 2))


@dataclass(frozen=True)
class ThetaResult:
    theta: float            # theta* [rad]
    objective: float        # sum of volumes at theta*
    bracketed: bool         # False: minimum at a bound of the range or on a plateau
    iterations: int
    evaluations: int
    scan_theta: np.ndarray  # the coarse scan [rad]
    scan_objective: np.ndarray


def optimise_theta(problem: "ToolProblem", theta_range: Tuple[float, float] = (math.radians(1), math.radians(179)),
                   n_scan: int = 73, xtol: float = 1e-9, alpha1: float = 0.0,
                   s: Optional[float] = None) -> "ThetaResult":
    """Eq. 12: theta* = argmin_theta sum_phi V(phi, theta), a coarse scan of
    ``n_scan`` values in ``theta_range`` [rad] then GSL Brent (in C)."""
    lo = _real(theta_range[0], "theta_range[0]")
    hi = _real(theta_range[1], "theta_range[1]")
    if not hi > lo:
        raise ValueError(f"theta_range must be increasing, got ({lo:g}, {hi:g})")
    th, f, it, ev, br, scan = _tool.optimise_theta(
        theta_lo=lo, theta_hi=hi, n_scan=n_scan, xtol=xtol, alpha1=_real(alpha1, "alpha1"),
        s=s, **problem._kw())
    return ThetaResult(th, f, bool(br), it, ev, np.linspace(lo, hi, n_scan), scan)


@dataclass(frozen=True)
class ToolResult:
    tool: Tool
    objective: float
    iterations: int
    evaluations: int
    converged: bool  # False: max_iter reached before the simplex shrank to size_tol


def optimise_tool(problem: "ToolProblem", start: Tool, free: Sequence[str] = ("alpha1", "alpha2", "s"),
                  step: Sequence[float] = (0.2, 0.2, 0.1), max_iter: int = 2000,
                  size_tol: float = 1e-7) -> "ToolResult":
    """Several tool parameters together with GSL's nmsimplex2 (in C).

    ``free`` names the parameters to optimise among "alpha1", "alpha2" and "s"
    (the plunger position; only with ``start.s`` given). The objective is only
    piecewise smooth (contacts switch, the plunger may miss the object), so
    the simplex can wander on a plateau: then ``converged`` is False and the
    best point found is returned. Restart from the result or from several
    starts.
    """
    if not isinstance(start, Tool):
        raise TypeError("start must be an exdex.tool.Tool")
    names = ("alpha1", "alpha2", "s")
    bad = [f for f in free if f not in names]
    if bad or not free:
        raise ValueError(f"free must name some of {names}, got {tuple(free)!r}")
    if "s" in free and start.s is None:
        raise ValueError("free includes 's' but start has no plunger (start.s is None)")
    flags = [1.0 if n in free else 0.0 for n in names]
    x, f, it, ev, conv = _tool.optimise_tool(x0=np.array(start.params()), free=flags,
                                       step=np.asarray(step, dtype=float),
                                       plunger=start.s is not None, max_iter=max_iter,
                                       size_tol=size_tol, **problem._kw())
    tool = Tool(theta=x[1] - x[0], alpha1=x[0], s=None if start.s is None else x[2])
    return ToolResult(tool, f, it, ev, conv)


# ---------------------------------------------------------------- rod (Fig. 11)

def rod_descent_closed_form(psi: ArrayLike, height: float, rod_x: float) -> NDArray[np.float64]:
    """Closed form of the rod worked case (Fig. 11): gripper descent d [m]
    at which the object of ``height`` [m] has turned by ``psi`` [rad] (see
    :func:`rod_rotation`).

    With b = height / 2, the rod, fixed at (rod_x, 0), stays on the bottom
    edge of the object whose centre is at (0, b - d) and rotation psi: in the
    object's frame the rod is at height -b, i.e.
    rod_x sin(psi) + (b - d) cos(psi) = b, so
        d = b - (b - rod_x sin psi) / cos psi.
    """
    p = np.asarray(psi, dtype=float)
    b, xr = float(height) / 2, float(rod_x)
    return b - (b - xr * np.sin(p)) / np.cos(p)


def rod_max_rotation(height: float, rod_x: float) -> float:
    """The largest rotation [rad] a straight downward push can give with the
    rod to an object of ``height`` [m]: asin(rod_x / b), b = height / 2 (then
    the rod is right below the grasp point and the push no longer turns the
    object); pi/2 if rod_x >= b."""
    b = _real(height, "height", low=0, low_open=True) / 2
    xr = _real(rod_x, "rod_x", low=0, low_open=True)
    return math.asin(xr / b) if xr < b else math.pi / 2


def rod_rotation(psi_end: float, width: float = 1.0, height: float = 1.0, rod_x: float = 0.25,
                 steps: int = 1000) -> Tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """The rod tool of the paper's Fig. 11, worked from the twist cone.

    An object (a ``width`` x ``height`` rectangle [m], half-sides
    a = width / 2, b = height / 2) is held by the gripper at its centre
    G, which the plates' torsional friction lets turn (paper 2.3). The gripper
    moves straight down (the twist of G is imposed: Vx = 0, Vy = -1 per unit
    descent) onto a fixed rod at (rod_x, 0), 0 < rod_x <= a; the object starts
    level with its bottom edge on the rod. The rod alone is one contact: its
    cone is a half-space (half of any centred box, so it constrains nothing
    fully, as the paper notes). Under the push the permitted twists are the
    slice Vx = 0, Vy = -1 of that cone: with the row (n, r x n) of the contact
    (n the edge's inward normal, r the contact from G, world frame),
    -n_y + (r x n) wz >= 0. The plates resist rotation, so the object turns at
    the least permitted rate, dpsi/dd = n_y / (r x n): the rod turns the
    descent into a rotation, up to :func:`rod_max_rotation`.

    Integrated in psi (dd/dpsi = (r x n) / n_y, regular up to the maximum) by
    RK4 over ``steps`` steps, the rows coming from the C core. Returns
    (psi (steps+1,) [rad], descent [m], contact position u along the edge from
    the edge's middle [m]). Compare with :func:`rod_descent_closed_form`.
    """
    a = _real(width, "width", low=0, low_open=True) / 2
    h = _real(height, "height", low=0, low_open=True)
    b = h / 2
    xr = _real(rod_x, "rod_x", low=0, low_open=True)
    if xr > a:
        raise ValueError(f"rod_x must be in (0, width / 2 = {a:g}], got {xr:g}")
    pmax = rod_max_rotation(h, xr)
    p_end = _real(psi_end, "psi_end", low=0)
    if not p_end < pmax:
        raise ValueError(f"psi_end must be in [0, {pmax:.6g}) rad (asin(2 rod_x / height)), "
                         f"got {p_end:g}")
    if isinstance(steps, bool) or not isinstance(steps, numbers.Integral) or steps < 1:
        raise ValueError("steps must be an int >= 1")

    def u_of(d, psi):
        # the rod in the object's frame: R(-psi) (rod - G), G = (0, b - d)
        return math.cos(psi) * xr - math.sin(psi) * (b - d)

    def slope(psi, d):
        u = u_of(d, psi)
        c, s = math.cos(psi), math.sin(psi)
        n = np.array([[-s, c]])                       # R(psi) (0, 1)
        r = np.array([[c * u + s * b, s * u - c * b]])  # R(psi) (u, -b)
        row = _tool.contact_rows(r, n)[0]
        return row[2] / row[1]                        # dd/dpsi

    ps = np.linspace(0.0, p_end, steps + 1)
    d = np.zeros_like(ps)
    h = p_end / steps
    for i in range(steps):
        p, x = ps[i], d[i]
        k1 = slope(p, x)
        k2 = slope(p + h / 2, x + h / 2 * k1)
        k3 = slope(p + h / 2, x + h / 2 * k2)
        k4 = slope(p + h, x + h * k3)
        d[i + 1] = x + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
    u = np.array([u_of(x, p) for p, x in zip(ps, d)])
    return ps, d, u


# ---------------------------------------------------------------- studies

#: Attack-angle ranges reported by ``exdex tool`` [deg]; see :func:`phi_set`.
PHI_RANGES = {
    "0..45": (0.0, 45.0),
    "0..90": (0.0, 90.0),
    "-45..45": (-45.0, 45.0),
    "0..30": (0.0, 30.0),
    "15..75": (15.0, 75.0),
}

#: Box conventions reported by ``exdex tool`` (Eq. 13 side lengths).
BOX_CONVENTIONS = {
    "centred": Box.eq13(),
    "orthant": Box(1 / SQRT2, 1 / SQRT2, 2.0, centre=(0.5 / SQRT2, 0.5 / SQRT2, 1.0)),
}


def phi_set(lo_deg: float, hi_deg: float, step_deg: float = 0.25, midpoints: bool = True) -> NDArray[np.float64]:
    """Attack angles [rad] covering [lo, hi] deg.

    ``midpoints`` (default): the centres of cells of ``step_deg``, i.e. the
    midpoint rule for the mean of V over the range; this avoids the exact
    edge contacts (phi = 0, theta - phi = 90 deg, ...) where a frictionless
    point-contact model gives isolated low values. Otherwise lo..hi inclusive.
    """
    lo = _real(lo_deg, "lo_deg")
    hi = _real(hi_deg, "hi_deg")
    st = _real(step_deg, "step_deg", low=0, low_open=True)
    if not hi > lo:
        raise ValueError(f"hi_deg must exceed lo_deg, got {lo:g}..{hi:g}")
    n = max(1, int(round((hi - lo) / st)))
    if midpoints:
        return np.radians(lo + (hi - lo) * (np.arange(n) + 0.5) / n)
    return np.radians(np.linspace(lo, hi, n + 1))


def theta_study(ranges: Optional[Mapping[str, Tuple[float, float]]] = None,
                models: Sequence[str] = ("paper", "contact"), boxes: Optional[Mapping[str, Box]] = None,
                mu: float = 0.0, n_scan: int = 179, step_deg: float = 0.25,
                progress: bool = True) -> List[Dict[str, Any]]:
    """theta* (Eq. 12) for each phi range, model and box: a list of dict rows."""
    ranges = PHI_RANGES if ranges is None else ranges
    boxes = {"centred": Box.eq13()} if boxes is None else boxes
    out = []
    items = [(r, m, b) for b in boxes for r in ranges for m in models]
    if progress:
        from exdex._optional import progress_bar

        items = progress_bar(items, desc="theta*", unit="case", leave=False, auto=True,
                             feature="theta_study(progress=True)")
    for name, model, bname in items:
        box = boxes[bname]
        prob = ToolProblem(phi=phi_set(*ranges[name], step_deg=step_deg), box=box, mu=mu,
                           model=model)
        res = optimise_theta(prob, n_scan=n_scan)
        n = len(prob.phi)
        out.append(dict(box=bname, phi_range=name, model=model, mu=mu, dVx=box.dVx, dVy=box.dVy,
                        dwz=box.dwz, theta_star_deg=math.degrees(res.theta),
                        objective=res.objective, mean_volume=res.objective / n,
                        bracketed=res.bracketed,
                        mean_volume_90deg=float(theta_curve(prob, [math.pi / 2])[0]) / n,
                        result=res, n_phi=n))
    return out


# ---------------------------------------------------------------- figures of ``exdex tool``

VOLUME_UNIT = "(m/s)$^2$ rad/s"  # twist-cone volumes: Vx, Vy [m/s] x wz [rad/s]


def figure_theta_curves(study: Sequence[Mapping[str, Any]]) -> Any:
    """Mean cone volume against the tool angle per phi range (rows of
    :func:`theta_study`, centred box), one panel per model: a Figure."""
    from exdex._optional import pyplot

    plt = pyplot("exdex.tool figures")

    fig, axes = plt.subplots(1, 2, figsize=(11, 4), sharey=True)
    for ax, model in zip(axes, ("paper", "contact")):
        for r in study:
            if r["model"] != model or r["box"] != "centred":
                continue
            res = r["result"]
            ax.plot(np.degrees(res.scan_theta), res.scan_objective / r["n_phi"],
                    label=f"phi {r['phi_range']} deg: theta* {r['theta_star_deg']:.1f} deg")
            ax.plot(r["theta_star_deg"], r["mean_volume"], "k.")
        ax.axvline(90, color="0.6", lw=0.8, ls="--")
        ax.set_title("Eqs. 10-11 literally" if model == "paper" else "rows derived from contacts")
        ax.set_xlabel("tool angle theta [deg]")
        ax.legend(fontsize=7)
    axes[0].set_ylabel(f"mean cone volume over phi [{VOLUME_UNIT}]\n(centred Eq. 13 box)")
    fig.tight_layout()
    return fig


def figure_box_aspect(sweep: Sequence[Mapping[str, Any]]) -> Any:
    """theta* against the box side a (dVx = dVy = a, dwz = 1/a^2): a Figure."""
    from exdex._optional import pyplot

    plt = pyplot("exdex.tool figures")

    fig, ax = plt.subplots(figsize=(6, 4))
    for model in ("paper", "contact"):
        r = [x for x in sweep if x["model"] == model]
        ax.semilogx([x["a"] for x in r], [x["theta_star_deg"] for x in r], "o-", label=model)
    ax.axvline(1 / SQRT2, color="0.6", lw=0.8, ls="--", label="Eq. 13")
    ax.axhline(90, color="0.8", lw=0.8)
    ax.set_xlabel("box side a = dVx = dVy [m/s]  (dwz = 1/a$^2$ [rad/s], volume 1 " + VOLUME_UNIT + ")")
    ax.set_ylabel("theta* [deg] (phi 0..90 deg)")
    ax.legend()
    fig.tight_layout()
    return fig


def figure_rod(descent: Any, psi: Any, closed: Any, height: float, rod_x: float) -> Any:
    """Object rotation against gripper descent for the rod tool (Fig. 11): a Figure."""
    from exdex._optional import pyplot

    plt = pyplot("exdex.tool figures")

    fig, ax = plt.subplots(figsize=(5, 3.5))
    ax.plot(descent, np.degrees(psi), label="RK4 on the contact row")
    ax.plot(closed[::100], np.degrees(psi[::100]), "k.", label="closed form")
    ax.set_xlabel("gripper descent [m]")
    ax.set_ylabel("object rotation [deg]")
    ax.set_title(f"rod tool (Fig. 11): rod {rod_x} m off the grasp, object height {height} m")
    ax.legend()
    fig.tight_layout()
    return fig

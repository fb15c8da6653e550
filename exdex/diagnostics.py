"""Physics warnings: results that leave the model's assumptions.

exdex models the plates' friction as a patch whose centre of pressure is
fixed on the object (``Patch.center``) and whose pressure covers the pad the
patch describes. A result is outside that model when

* the object slides farther relative to the plates than the pad's own size
  (``Patch.disc`` / ``Patch.rectangle`` state it): the contact has moved
  across the pad, so the pressure distribution and e_r no longer hold, and
  past the pad's edge the object has left the fingers;
* the plates' pad centre leaves the body's outline (``Body.size`` or
  ``Body.outline``): the plates no longer press on the object;
* the object hits a stop: an impact is an impulse, which the sampled
  ``stop_force`` (a mean force over one step) can show only as a spike whose
  height depends on the step;
* the solver counted soft problems in ``stats["warnings"]`` (an iteration
  limit reached with the last iterate kept, a stop that cannot act along the
  free direction or pinches the object, a penetration left after a step).

:func:`exdex.simulate`, :meth:`exdex.Model.simulate` and
:func:`exdex.simulate_batch` issue one :class:`PhysicsWarning` per finding
through :mod:`warnings`; each names the time, the quantity and its size.
Silence them with ``warnings.simplefilter("ignore", exdex.PhysicsWarning)``
or turn them into errors with ``"error"``.

Two kinds are issued where a scene is made, before any run: a
:class:`NoisyLogWarning` for a robot log whose noise dominates its
accelerations (``exdex.SampledTrajectory``) and a :class:`PlausibilityWarning`
for a field no real object or grasp has (a density far outside solids, a
patch larger than the face). A batch's failed reductions come as one
:class:`ReductionWarning` (:meth:`ReductionWarning.aggregate`).
"""
from __future__ import annotations

import math
import warnings

import numpy as np

from exdex._validate import user_stacklevel

__all__ = ["PhysicsWarning", "ReductionWarning", "NoisyLogWarning", "PlausibilityWarning", "findings", "pad_half_size"]


class PhysicsWarning(UserWarning):
    """A simulated result left the assumptions of the model.

    Attributes: ``kind`` ("pad", "outline", "impact", "solver",
    "grasp": pads on the fingers lost the object; the subclasses'
    "reduction", "noisy_log", "plausibility", "gripper_jump"), ``time``
    (the first time it happened [s], or None when the core does not know it),
    ``quantity`` (what was measured), ``value`` and ``limit`` (its size and
    the bound it passed, SI units; ``limit`` may be None).
    """

    def __init__(self, message, kind=None, time=None, quantity=None, value=None, limit=None):
        super().__init__(message)
        self.kind, self.time, self.quantity, self.value, self.limit = kind, time, quantity, value, limit


class ReductionWarning(PhysicsWarning):
    """A 1-DoF run's reduction failed: the neglected in-plane coordinates
    needed a friction load the plates cannot give (``kind`` "reduction").

    Attributes besides :class:`PhysicsWarning`'s: ``coordinate`` (the
    neglected coordinate that needs most of the load: ``"theta"`` or
    ``"across"`` -- across the slide axis -- in translation runs,
    ``"pivot"`` -- the pivot's translation -- in rotation runs), ``load``
    (the plate friction wrench (f_x, f_y, m_z) in B at the centre of
    pressure that keeps them still [N, N, N m]), ``stick`` (True: the
    reduced coordinate was stuck, the load is checked against the static
    limit surface; False: it slipped, and the part of the load the slip's
    friction cannot give must be zero), ``gauge`` (``value``: stuck, the
    load's gauge in the surface, fails above 1; slipping, that part's size
    over the capacity, fails above 0) and ``margin`` (1 - gauge while
    stuck, -gauge while slipping: negative where it fails).
    """

    def __init__(self, message, time, coordinate, load, stick, gauge, capacity):
        self.coordinate, self.load, self.stick = coordinate, tuple(float(x) for x in load), bool(stick)
        self.gauge, self.capacity = float(gauge), float(capacity)
        self.margin = 1.0 - self.gauge if self.stick else -self.gauge
        super().__init__(message, kind="reduction", time=time,
                         quantity="gauge of the needed plate load in the limit surface" if self.stick
                         else "plate load the slip's friction cannot give, over the capacity",
                         value=self.gauge, limit=1.0 if self.stick else 0.0)

    @classmethod
    def aggregate(cls, message: str, time: float) -> "ReductionWarning":
        """The warning of a batch whose trajectories' reductions failed (one
        for the batch): ``time`` the first trajectory's ``reduction_valid_until``
        [s] (also ``value``). A batch keeps only when each reduction failed, so
        ``coordinate``, ``load``, ``stick``, ``gauge``, ``capacity`` and
        ``margin`` are None; simulate that trajectory's scene
        (``BatchResult.scene_at``) for them."""
        w = cls.__new__(cls)
        w.coordinate = w.load = w.stick = w.gauge = w.capacity = w.margin = None
        PhysicsWarning.__init__(w, message, kind="reduction", time=time, quantity="reduction_valid_until [s]",
                                value=time, limit=None)
        return w


class NoisyLogWarning(PhysicsWarning):
    """A robot log's accelerations are dominated by its measurement noise
    (``kind`` "noisy_log"): the spline through the samples passes the noise
    on to the gripper's accelerations, and so to the object. Issued when an
    :class:`exdex.SampledTrajectory` is made without ``noise``; the message
    names the option and the level estimated from the data.

    Attributes besides :class:`PhysicsWarning`'s: ``part`` ("positions" or
    "orientations"), ``noise`` (the estimated level: m per axis, or rad per
    axis of a small rotation), ``noise_acceleration`` (three standard
    deviations of the acceleration the noise gives, ``value``: m/s^2 or
    rad/s^2) and ``motion_acceleration`` (the motion's peak acceleration
    read at a coarser stride, ``limit``)."""

    def __init__(self, message, part, noise, noise_acceleration, motion_acceleration):
        self.part, self.noise = part, float(noise)
        self.noise_acceleration, self.motion_acceleration = float(noise_acceleration), float(motion_acceleration)
        unit = "m/s^2" if part == "positions" else "rad/s^2"
        super().__init__(message, kind="noisy_log", time=None,
                         quantity=f"the noise's acceleration (3 standard deviations) [{unit}]",
                         value=self.noise_acceleration, limit=self.motion_acceleration)


class PlausibilityWarning(PhysicsWarning):
    """A scene's field holds a value no real gripper or object has (``kind``
    "plausibility"): a density far outside solids, a pad larger than the
    face it presses on. The scene runs as given; the warning names the
    field (``quantity``), its value and the bound it passed (``value``,
    ``limit``, SI units)."""

    def __init__(self, message, field, value, limit):
        self.field = field
        super().__init__(message, kind="plausibility", time=None, quantity=field, value=float(value),
                         limit=float(limit))


_COORD = {0: "pivot", 1: "across", 2: "theta"}
_COORD_TEXT = {"pivot": "the pivot's translation (x, y)", "across": "the translation across the slide axis",
               "theta": "the rotation theta"}


def reduction_findings(scene, cert):
    """The :class:`ReductionWarning` of a run's certificate dict (or none)."""
    if not cert or cert.get("holds", True):
        return []
    coord = _COORD.get(int(cert["coordinate"]), "theta")
    f = cert["load"]
    t = float(cert["valid_until"])
    stick = bool(cert["stick"])
    gauge = float(cert["gauge"])
    cap = float(cert["capacity"])
    if stick:
        how = (f"while the object is stuck to the plates this load lies outside the static limit surface: "
               f"its gauge is {gauge:.4g} > 1 (margin {1 - gauge:.4g}) at a capacity of {cap:.4g} N")
    else:
        how = (f"while the {scene.dof} slips, maximum dissipation gives the plates' friction no part of it, "
               f"and no stop carries {gauge * cap:.4g} N (scaled by the limit surface; {gauge:.4g} of the "
               f"capacity {cap:.4g} N, margin {-gauge:.4g})")
    msg = (f"the {scene.dof} model's reduction fails at t = {t:.6g} s: to keep {_COORD_TEXT[coord]} (and every "
           f"other neglected coordinate) still, the plates would have to carry f = ({f[0]:.4g}, {f[1]:.4g}) N, "
           f"m_z = {f[2]:.4g} N m at the centre of pressure; {how}. Past this time the {scene.dof} result does "
           f"not describe the grasp (Result.reduction_valid_until); simulate it with dof='planar'")
    return [ReductionWarning(msg, t, coord, f, stick, gauge, cap)]


def _length(x):
    """A length [m] in the unit that reads best."""
    a = abs(x)
    if a >= 1.0 or a == 0.0:
        return f"{x:.4g} m"
    if a >= 1e-3:
        return f"{x * 1e3:.4g} mm"
    return f"{x * 1e6:.4g} um"


def pad_half_size(patch):
    """Half-extents of the pad a patch was built from [m]: ``(r,)`` for a
    disc of radius r, ``(width / 2, height / 2)`` for a rectangle (along the
    object's x and y at t = 0), for a polygon the half-extents of its
    bounding box about the centre (largest |x|, largest |y|), or None when
    the patch states no size."""
    if patch.shape == "disc" and len(patch.dims) == 1:
        return (float(patch.dims[0]),)
    if patch.shape == "rectangle" and len(patch.dims) == 2:
        return (float(patch.dims[0]) / 2, float(patch.dims[1]) / 2)
    reg = patch.region() if patch.shape == "polygon" else None
    if reg is not None:
        v = np.abs(reg["vertices"])
        return (float(np.max(v[:, 0])), float(np.max(v[:, 1])))
    return None


def _polygon_inradius(verts):
    """The distance from the origin to the nearest edge line of the convex
    ccw polygon verts (0 if the origin is not inside)."""
    d = []
    for a, b in zip(verts, np.roll(verts, -1, axis=0)):
        e = b - a
        n = math.hypot(*e)
        if n > 0.0:
            d.append((e[0] * (-a[1]) - e[1] * (-a[0])) / n)
    return max(0.0, min(d)) if d else 0.0


def _outside_polygon(verts, p):
    """Per point of p (n, 2): True where it lies outside the convex ccw
    polygon verts (k, 2), beyond a relative 1e-9 of its size."""
    scale = float(np.max(np.abs(verts)))
    out = np.zeros(len(p), dtype=bool)
    for a, b in zip(verts, np.roll(verts, -1, axis=0)):
        e = b - a
        n = math.hypot(*e)
        if n == 0.0:
            continue
        out |= (e[0] * (p[:, 1] - a[1]) - e[1] * (p[:, 0] - a[0])) / n < -1e-9 * scale
    return out


def poses(scene, q):
    """(n, 3) planar poses (x, y, theta) of the object frame C in B for the
    free coordinates q (n, ndof) of ``scene``."""
    q = np.asarray(q, dtype=float).reshape(len(q), -1)
    n = len(q)
    out = np.empty((n, 3))
    if scene.dof == "planar":
        out[:] = q
    elif scene.dof == "translation":
        d = np.array(scene.slide_axis)
        s = q[:, 0] - (d[0] * scene.q0[0] + d[1] * scene.q0[1])   # q = s, the COM's coordinate along d
        out[:, 0] = scene.q0[0] + s * d[0]
        out[:, 1] = scene.q0[1] + s * d[1]
        out[:, 2] = scene.q0[2]
    else:
        th = q[:, 0]
        c = -np.array(scene.grasp.patch.center)
        th0 = scene.q0[2]
        pivot = np.array(scene.q0[:2]) - _rot(th0, c)
        out[:, 0] = pivot[0] + np.cos(th) * c[0] - np.sin(th) * c[1]
        out[:, 1] = pivot[1] + np.sin(th) * c[0] + np.cos(th) * c[1]
        out[:, 2] = th
    return out


def _rot(th, v):
    c, s = np.cos(th), np.sin(th)
    return np.array([c * v[0] - s * v[1], s * v[0] + c * v[1]])


def _hull(points):
    """Convex hull (counter-clockwise, Andrew's monotone chain) of (k, 2) points."""
    pts = sorted(set(map(tuple, np.asarray(points, dtype=float))))
    if len(pts) < 3:
        return np.array(pts)

    def cross(o, a, b):
        return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])

    lower, upper = [], []
    for p in pts:
        while len(lower) >= 2 and cross(lower[-2], lower[-1], p) <= 0:
            lower.pop()
        lower.append(p)
    for p in reversed(pts):
        while len(upper) >= 2 and cross(upper[-2], upper[-1], p) <= 0:
            upper.pop()
        upper.append(p)
    return np.array(lower[:-1] + upper[:-1])


def _outside_distance(hull, p):
    """For points p (n, 2): the largest outward distance from the hull's edge
    lines (> 0 outside the convex polygon, its Euclidean distance to the
    polygon along an edge normal)."""
    a = hull
    b = np.roll(hull, -1, axis=0)
    e = b - a
    nrm = np.stack([e[:, 1], -e[:, 0]], axis=1)  # outward normal of a CCW polygon
    nrm /= np.linalg.norm(nrm, axis=1)[:, None]
    return np.einsum("nkj,kj->nk", p[:, None, :] - a[None, :, :], nrm).max(axis=1)


def _outline(body):
    """The body's outline in C as a convex polygon (counter-clockwise): the
    box of ``Body.size`` when given (``Body.outline`` may list only the
    vertices that touch stops), else the hull of ``Body.outline``; None when
    neither states an area. A disc outline (``Body.outline_radius``): the
    64 rim points of ``Body.vertices``, a polygon inscribed in the disc."""
    if body.outline_radius is not None:
        return body.vertices()
    if body.size is not None:
        hx, hy = body.size[0] / 2, body.size[1] / 2
        return np.array([(-hx, -hy), (hx, -hy), (hx, hy), (-hx, hy)])
    if body.outline is not None and len(body.outline) >= 3:
        hull = _hull(body.outline)
        if len(hull) >= 3:
            return hull
    return None


def outline_holds(body, point):
    """Whether ``point`` (2,) of the object frame C [m] lies strictly inside
    the body's outline polygon (:func:`_outline`); False for a body whose
    outline states no area."""
    outline = _outline(body)
    if outline is None:
        return False
    return bool(_outside_distance(_hull(outline), np.asarray(point, dtype=float).reshape(1, 2))[0] < 0.0)


def _first(mask):
    idx = np.flatnonzero(mask)
    return int(idx[0]) if len(idx) else None


def contact_checks(scene, q):
    """The pad and outline checks of poses q (n, ndof) of ``scene``, row by
    row: a list of dicts with ``kind``, ``mask`` (n,) (True where the check
    fails), ``value`` (n,) the measured size [m], ``limit`` [m], ``text`` a
    function (value, largest) -> the message after "at t = ... s"."""
    out = []
    if scene.dof == "rotation" or len(q) == 0:
        return out  # the centre of pressure is the pin: fixed on the plates
    if scene.grasp.pad is not None:
        return out  # pads on the fingers: the core follows the contact region (and its loss)
    q = np.asarray(q, dtype=float).reshape(len(q), -1)
    c = np.array(scene.grasp.patch.center)
    th0 = scene.q0[2]
    pad = np.array(scene.q0[:2]) + _rot(th0, c)                     # pad centre in B, fixed
    body = scene.body
    outline = _outline(body)
    half = pad_half_size(scene.grasp.patch)
    # The pad-size check: in planar scenes the centre of pressure fixed on
    # the object is an assumption the slide breaks; in translation scenes it
    # does not enter the dynamics, so there the pad is the only size to
    # check only when the body states no outline.
    check_pad = half is not None and (scene.dof == "planar" or outline is None)
    # a polygon patch: the slide is checked against the polygon itself, its
    # inradius about the centre the cheap bound
    poly = scene.grasp.patch.region()["vertices"] if half is not None and scene.grasp.patch.shape == "polygon" \
        else None
    inner = _polygon_inradius(poly) if poly is not None else min(half) if half is not None else 0.0
    # Cheap bounds first (long runs that stay well inside skip the per-row
    # work): the centre of mass moves by at most dr and turns by at most dth,
    # so the centre of pressure moves by at most dr + |c| dth relative to the
    # pad, and the pad centre by at most dr + |pad - r0| dth in the object.
    if scene.dof == "planar":
        r0 = np.array(scene.q0)
        dx, dy, dth = (float(np.max(np.abs(q[:, j] - r0[j]))) for j in range(3))
        dr = math.hypot(dx, dy)
    else:
        d = scene.slide_axis
        dr = float(np.max(np.abs(q[:, 0] - (d[0] * scene.q0[0] + d[1] * scene.q0[1]))))
        dth = 0.0
    if check_pad and dr + float(np.hypot(*c)) * dth < inner * (1 - 1e-9):
        check_pad = False
    if outline is not None:
        rel0 = _rot(-th0, pad - np.array(scene.q0[:2]))
        inside = -float(_outside_distance(outline, rel0[None, :])[0])
        if dr + float(np.hypot(*(pad - np.array(scene.q0[:2])))) * dth < inside * (1 - 1e-9):
            outline = None
    if not check_pad and outline is None:
        return out
    pose = poses(scene, q)
    cs, sn = np.cos(pose[:, 2]), np.sin(pose[:, 2])
    cop = pose[:, :2] + np.stack([cs * c[0] - sn * c[1], sn * c[0] + cs * c[1]], axis=1)
    slide = cop - pad                                                # CoP relative to the pad, in B
    if check_pad:
        ca, sa = math.cos(th0), math.sin(th0)
        local = np.stack([ca * slide[:, 0] + sa * slide[:, 1], -sa * slide[:, 0] + ca * slide[:, 1]], axis=1)
        dist = np.hypot(local[:, 0], local[:, 1])
        if poly is not None:
            # the centre of pressure (the pad's centre + the slide) outside the pad's polygon
            mask = _outside_polygon(poly, local)
            size_txt, limit = "the pad's polygon", float(np.max(np.hypot(poly[:, 0], poly[:, 1])))
        elif len(half) == 1:
            mask = dist > half[0] * (1 + 1e-9)
            size_txt, limit = f"the pad radius {_length(half[0])}", half[0]
        else:
            mask = (np.abs(local[:, 0]) > half[0] * (1 + 1e-9)) | (np.abs(local[:, 1]) > half[1] * (1 + 1e-9))
            size_txt = f"the pad's half-sides {_length(half[0])} x {_length(half[1])}"
            limit = float(math.hypot(*half))
        out.append(dict(
            kind="pad", mask=mask, value=dist, limit=limit, quantity="slide relative to the pad [m]",
            text=lambda v, end, size_txt=size_txt: (
                f"the object has slid {_length(v)} relative to the plate pads, beyond {size_txt}"
                + (f" ({_length(end)} at the end of the run)" if end is not None else "")
                + ": the model keeps the centre of pressure fixed on the object, so past this time the "
                "result does not describe the grasp")))
    if outline is not None:
        hull = outline
        rel = pad[None, :] - pose[:, :2]                          # pad centre rel. to the COM, in B
        in_c = np.stack([cs * rel[:, 0] + sn * rel[:, 1], -sn * rel[:, 0] + cs * rel[:, 1]], axis=1)
        scale = float(np.max(np.abs(hull)))
        dout = _outside_distance(hull, in_c)
        out.append(dict(
            kind="outline", mask=dout > 1e-9 * scale, value=dout, limit=0.0,
            quantity="distance outside the body outline [m]",
            text=lambda v, end: (
                f"the centre of pressure (the plate pads' centre) is {_length(v)} outside the body "
                f"outline" + (f" ({_length(end)} at the end of the run)" if end is not None and end > 0 else "")
                + ": the plates no longer press on the object, so past this time the result does not "
                "describe the grasp")))
    return out


def contact_findings(scene, t, q, chunk=2048):
    """Pad and outline findings for the samples (t, q) of one trajectory of
    ``scene``. Rows are checked in chunks, and a check stops at its first
    failing sample, so long runs cost little beyond their own output."""
    q = np.asarray(q, dtype=float).reshape(len(q), -1)
    first = {}
    possible = None
    for a in range(0, len(q), chunk):
        checks = contact_checks(scene, q[a:a + chunk])
        for chk in checks:
            if chk["kind"] in first:
                continue
            i = _first(chk["mask"])
            if i is not None:
                first[chk["kind"]] = (a + i, chk, float(chk["value"][i]))
        if possible is None:
            possible = _possible_kinds(scene)
        if possible <= set(first):
            break
    out = []
    if not first:
        return out
    end = {chk["kind"]: float(chk["value"][-1]) for chk in contact_checks(scene, q[-1:])}
    for kind in ("pad", "outline"):
        if kind not in first:
            continue
        i, chk, v = first[kind]
        out.append(PhysicsWarning(
            f"at t = {t[i]:.6g} s " + chk["text"](v, end.get(kind)), kind=kind, time=float(t[i]),
            quantity=chk["quantity"], value=v, limit=chk["limit"]))
    return out


def _possible_kinds(scene):
    """The kinds of contact finding a scene can give at all."""
    if scene.dof == "rotation" or scene.grasp.pad is not None:
        return set()
    outline = _outline(scene.body)
    kinds = set()
    if pad_half_size(scene.grasp.patch) is not None and (scene.dof == "planar" or outline is None):
        kinds.add("pad")
    if outline is not None:
        kinds.add("outline")
    return kinds


def stats_findings(stats):
    """Impact and solver-warning findings from a stats dict of one trajectory."""
    out = []
    tl = stats.get("grasp_lost_t", None)
    if tl is not None and math.isfinite(tl):
        out.append(PhysicsWarning(
            f"at t = {tl:.6g} s the contact region of the pads and the object's face vanished: the grasp is "
            "lost and the run stopped there (the result ends at that sample)",
            kind="grasp", time=float(tl), quantity="contact area [m^2]", value=0.0, limit=None))
    n_imp = int(stats.get("impacts", 0) or 0)
    if n_imp > 0:
        J = float(stats.get("max_impulse", float("nan")))
        tj = stats.get("max_impulse_t", None)
        k = stats.get("max_impulse_stop", None)
        where = f" on stop {int(k)}" if k is not None and k >= 0 else ""
        when = f" at t = {tj:.6g} s" if tj is not None and math.isfinite(tj) else ""
        out.append(PhysicsWarning(
            f"{n_imp} impact{'s' if n_imp != 1 else ''} on stops; the largest impulse is {J:.4g} N s{where}{when}. "
            "stop_force holds an impact as its impulse divided by the step (a spike that grows as dt "
            "shrinks): read the impulse, not the force, there",
            kind="impact", time=float(tj) if tj is not None and math.isfinite(tj) else None,
            quantity="impulse [N s]", value=J, limit=None))
    n_warn = int(stats.get("warnings", 0) or 0)
    if n_warn > 0:
        tw = stats.get("first_warning_t", None)
        when = f", the first by t = {tw:.6g} s" if tw is not None and math.isfinite(tw) else ""
        out.append(PhysicsWarning(
            f"the solver counted {n_warn} soft problem{'s' if n_warn != 1 else ''}{when} (stats['warnings']): "
            "an iteration limit reached with the last iterate kept, a stop that cannot act along the free "
            "direction or pinches the object, a penetration left after a step, or a frictional stop that "
            "jams (its friction turns its normal force around: no finite contact force). The result may be "
            "inaccurate there: try a smaller dt, or another method",
            kind="solver", time=float(tw) if tw is not None and math.isfinite(tw) else None,
            quantity="stats['warnings']", value=float(n_warn), limit=0.0))
    return out


def findings(result):
    """Every :class:`PhysicsWarning` a :class:`exdex.Result` deserves (not issued)."""
    return (contact_findings(result.scene, result.t, result.q) + stats_findings(result.stats)
            + reduction_findings(result.scene, getattr(result, "certificate", None)))


def issue(found, stacklevel=None):
    """Issue each finding through :func:`warnings.warn`, naming the user's
    line (the first frame outside the package) unless ``stacklevel`` says
    otherwise (counted from the caller of ``issue``)."""
    level = user_stacklevel() if stacklevel is None else stacklevel + 1
    for w in found:
        warnings.warn(w, stacklevel=level)

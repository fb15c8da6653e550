"""Animations of a simulated result: the object moving between the plates.

    >>> anim = res.animate()          # an exdex.animation.Animation
    >>> anim                          # in Jupyter: plays inline (HTML5 video or JavaScript player)
    >>> anim.save("drop.gif")         # GIF (Pillow); "drop.mp4" needs ffmpeg; "drop.html" a web page

The picture is the world seen along the plate normal at the start: the plane
of the plates in their initial pose (axes: the gripper frame B's initial x
and y, in mm; with the default gripper pose, y is up). It shows

* the finger plate (a grey rectangle moving with the gripper; the scene does
  not give the fingers' size: by default the rectangle around the object's
  face and the pad at t = 0, ``plate_size`` sets it),
* the object outline (``Body.outline``, the box of ``Body.size`` or the disc
  of ``Body.outline_radius``; a dot at the centre of mass without any), to
  scale,
* the contact, to scale: a pad on the fingers (``Grasp.pad``, moving with
  the gripper) or the pressure patch on the object (``Patch.disc``,
  ``Patch.rectangle``, moving with the object); a patch given by e_r alone
  has no shape and is drawn as its centre,
* the stops (fixed lines, the forbidden side hatched),
* the plate friction force on the object as an arrow at the centre of
  pressure (the key says how many newtons its length is: the object's size
  stands for the grip's friction limit), and the friction torque as an arc
  (a full turn = the largest torque),
* gravity's direction, the time, and stick or slip.

Motions that turn the plates out of their initial plane are drawn projected
onto it. Matplotlib is imported when an animation is made.
"""
from __future__ import annotations

import importlib
import math
import os
import shutil
from typing import Any, Optional, Sequence

import numpy as np

__all__ = ["Animation", "animate", "frame_geometry"]


def _frame_indices(t, fps, speed, max_frames):
    span = float(t[-1] - t[0])
    n = int(round(span / speed * fps)) + 1 if span > 0 else 1
    n = max(2, min(max_frames, n, len(t)))
    times = np.linspace(t[0], t[-1], n)
    idx = np.clip(np.searchsorted(t, times), 0, len(t) - 1)
    prev = np.clip(idx - 1, 0, len(t) - 1)
    closer = np.abs(t[prev] - times) < np.abs(t[idx] - times)
    idx = np.where(closer, prev, idx)
    interval_ms = 1000.0 * span / speed / (n - 1) if span > 0 else 1000.0 / fps
    return idx, interval_ms


def _rot2(th):
    c, s = np.cos(th), np.sin(th)
    return np.stack([np.stack([c, -s], -1), np.stack([s, c], -1)], -2)  # (..., 2, 2)


def frame_geometry(result: Any, indices: Optional[Sequence[int]] = None,
                   plate_size: Optional[Sequence[float]] = None) -> dict:
    """Everything an animation frame draws, in view coordinates [m].

    The view plane is the plate plane at t = 0: a world point X is drawn at
    ``(R0^T (X - p0))[:2]`` with (R0, p0) the gripper pose at t = 0.
    Returns a dict of arrays over the frames ``indices`` (default: every
    sample): ``t``; ``outline`` (f, k, 2) object outline; ``com`` (f, 2);
    ``plate`` (f, 4, 2) plate rectangle; ``cop`` (f, 2) centre of pressure;
    ``force`` (f, 2) plate friction force [N] as a view vector; ``m_z``
    (f,) [N m]; ``stick`` (f,); and ``stops``: a list of (normal, offset)
    pairs, the line ``normal . u = offset`` with the allowed side
    ``normal . u >= offset`` (stops parallel to the view are left out);
    ``gravity`` the view vector of gravity [m/s^2]; ``plate_size``;
    ``contact`` (f, k, 2) the contact's boundary, to scale (``Grasp.pad``:
    the pad on the finger; else the patch's disc or rectangle on the
    object; None for a patch given by e_r alone) and ``contact_kind``
    (``"pad"``, ``"patch"`` or None).
    """
    sc = result.scene
    if sc is None:
        raise ValueError("Result.animate needs the result's scene (Result.scene is None)")
    t = np.asarray(result.t)
    idx = np.arange(len(t)) if indices is None else np.asarray(indices)
    kin = sc.motion.evaluate(np.concatenate([[0.0], t[idx]]), sc.gripper_rotation, sc.gripper_position)
    R0, p0 = kin["R"][0], kin["p"][0]
    R, p = kin["R"][1:], kin["p"][1:]
    pose = result.pose[idx]  # (f, 3): x, y, theta of C in B
    rot = _rot2(pose[:, 2])  # (f, 2, 2)

    def to_view(pts_b):  # (f, k, 2) points of B's plane -> (f, k, 2) view
        pts3 = np.concatenate([pts_b, np.zeros(pts_b.shape[:-1] + (1,))], axis=-1)
        world = p[:, None, :] + np.einsum("fij,fkj->fki", R, pts3)
        return np.einsum("ji,fkj->fki", R0, world - p0)[..., :2]

    verts = sc.body.vertices()  # (k, 2) in C
    outline_b = pose[:, None, :2] + np.einsum("fij,kj->fki", rot, verts)
    com_b = pose[:, None, :2]
    c = np.array(sc.grasp.patch.center)
    cop_b = pose[:, None, :2] + np.einsum("fij,j->fi", rot, c)[:, None, :]

    # the contact to scale: a pad fixed in B, or the patch's region fixed on the object
    grasp = sc.grasp
    contact_b, kind = None, None
    if grasp.pad is not None:
        kind = "pad"
        contact_b = np.broadcast_to(grasp.pad.outline(), (len(idx),) + grasp.pad.outline().shape)
    else:
        region = grasp.patch.region()
        if region is not None:
            kind = "patch"
            if "radius" in region:
                a = np.linspace(0.0, 2.0 * np.pi, 64, endpoint=False)
                local = region["radius"] * np.column_stack([np.cos(a), np.sin(a)])
            else:
                local = np.asarray(region["vertices"], dtype=float)
            contact_b = pose[:, None, :2] + np.einsum("fij,kj->fki", rot, c + local)

    # the finger plate: not part of the scene, by default the box around the object's face and the pad
    # in the initial pose (B), or plate_size about that box's centre
    pose0 = np.asarray(result.pose[0], dtype=float)
    face0 = pose0[:2] + verts @ _rot2(pose0[2]).T
    pts0 = np.concatenate([face0] + ([grasp.pad.outline()] if grasp.pad is not None else []))
    lo0, hi0 = pts0.min(axis=0), pts0.max(axis=0)
    size = (hi0 - lo0 if np.all(hi0 > lo0) else np.full(2, 4.0 * grasp.patch.e_r)) if plate_size is None else plate_size
    w, h = (float(x) for x in size)
    centre = 0.5 * (lo0 + hi0)
    rect = centre + np.array([[-w / 2, -h / 2], [w / 2, -h / 2], [w / 2, h / 2], [-w / 2, h / 2]])
    plate_b = np.broadcast_to(rect, (len(idx), 4, 2))

    wrench = np.asarray(result.wrench)[idx]
    f3 = np.concatenate([wrench[:, :2], np.zeros((len(idx), 1))], axis=1)
    force = np.einsum("ji,fj->fi", R0, np.einsum("fij,fj->fi", R, f3))[:, :2]

    stops = []
    for s in sc.stops:
        n_v = R0.T @ np.array(s.normal)
        n2 = n_v[:2]
        norm = float(np.linalg.norm(n2))
        if norm < 1e-9:
            continue
        offset = float(np.dot(np.array(s.point) - p0, s.normal))
        stops.append((n2 / norm, offset / norm))
    return dict(t=t[idx], outline=to_view(outline_b), com=to_view(com_b)[:, 0], plate=to_view(plate_b),
                cop=to_view(cop_b)[:, 0], force=force, m_z=wrench[:, 2], stick=np.asarray(result.stick)[idx],
                stops=stops, gravity=(R0.T @ np.array(sc.gravity))[:2], plate_size=(w, h),
                contact=None if contact_b is None else to_view(np.ascontiguousarray(contact_b)), contact_kind=kind)


def _ffmpeg():
    """Path of an ffmpeg executable, or None: the PATH, else the imageio-ffmpeg package's."""
    exe = shutil.which("ffmpeg")
    if exe:
        return exe
    try:
        imageio_ffmpeg = importlib.import_module("imageio_ffmpeg")
    except ImportError:
        return None
    try:
        return imageio_ffmpeg.get_ffmpeg_exe()
    except Exception:  # pragma: no cover - a broken install
        return None


class Animation:
    """A matplotlib animation of a :class:`exdex.Result` (see :func:`animate`).

    In Jupyter it plays inline (HTML5 video when ffmpeg is available, else a
    JavaScript player). ``save(path)`` writes a GIF, an MP4 or an HTML page;
    ``to_jshtml()`` and ``to_html5_video()`` give the HTML text;
    ``figure`` is the matplotlib Figure and ``make()`` a fresh
    ``matplotlib.animation.FuncAnimation`` of it.
    """

    def __init__(self, figure, update, n_frames, interval_ms):
        self.figure = figure
        self._update = update
        self.n_frames = int(n_frames)
        self.interval_ms = float(interval_ms)

    @property
    def fps(self) -> float:
        """Frames per second of playback in real time (times ``speed``)."""
        return 1000.0 / self.interval_ms

    def make(self) -> Any:
        """A ``matplotlib.animation.FuncAnimation`` drawing the frames."""
        from matplotlib import animation

        return animation.FuncAnimation(self.figure, self._update, frames=self.n_frames,
                                       interval=self.interval_ms, blit=False, repeat=True)

    def _write(self, writer, path, dpi):
        """Draw each frame once into ``writer`` (a matplotlib MovieWriter)."""
        with writer.saving(self.figure, os.fspath(path), dpi):
            for k in range(self.n_frames):
                self._update(k)
                writer.grab_frame()
        self._update(0)

    def save(self, path: Any, dpi: float = 100) -> Any:
        """Write the animation to ``path``: ``.gif`` (Pillow), ``.mp4`` (ffmpeg,
        from the PATH or the imageio-ffmpeg package) or ``.html`` (a
        self-contained JavaScript player). Returns the path."""
        from matplotlib import animation

        ext = os.path.splitext(os.fspath(path))[1].lower()
        fps = max(1, int(round(self.fps)))
        if ext == ".gif":
            self._write(animation.PillowWriter(fps=fps), path, dpi)
        elif ext == ".mp4":
            exe = _ffmpeg()
            if exe is None:
                raise RuntimeError("writing .mp4 needs ffmpeg: install it (e.g. apt-get install ffmpeg) or the "
                                   "imageio-ffmpeg package (pip install imageio-ffmpeg), or save a .gif")
            import matplotlib

            with matplotlib.rc_context({"animation.ffmpeg_path": exe}):
                self._write(animation.FFMpegWriter(fps=fps), path, dpi)
        elif ext in (".html", ".htm"):
            with open(path, "w", encoding="utf-8") as f:
                f.write(self.to_jshtml(dpi=dpi))
        else:
            raise ValueError(f"Animation.save: the extension of path must be .gif, .mp4 or .html, got {ext!r}")
        return path

    def to_jshtml(self, dpi: float = 80) -> str:
        """HTML (with embedded frames) of a JavaScript player."""
        import tempfile

        from matplotlib import animation

        with tempfile.TemporaryDirectory() as tmp:
            path = os.path.join(tmp, "animation.html")
            writer = animation.HTMLWriter(fps=max(1, int(round(self.fps))), embed_frames=True, default_mode="loop")
            self._write(writer, path, dpi)
            with open(path, encoding="utf-8") as f:
                return f.read()

    def to_html5_video(self, dpi: float = 80) -> str:
        """HTML5 ``<video>`` tag with the MP4 embedded (needs ffmpeg)."""
        import base64
        import tempfile

        with tempfile.TemporaryDirectory() as tmp:
            path = self.save(os.path.join(tmp, "animation.mp4"), dpi=dpi)
            with open(path, "rb") as f:
                data = base64.b64encode(f.read()).decode("ascii")
        w, h = (int(round(x * dpi)) for x in self.figure.get_size_inches())
        return (f'<video width="{w}" height="{h}" controls autoplay loop>'
                f'<source type="video/mp4" src="data:video/mp4;base64,{data}"></video>')

    def _repr_html_(self):
        return self.to_html5_video() if _ffmpeg() is not None else self.to_jshtml()

    def __repr__(self):
        return f"<exdex.animation.Animation {self.n_frames} frames at {self.fps:.3g} fps>"


def animate(result: Any, fps: float = 25, speed: float = 1.0, max_frames: int = 200,
            plate_size: Optional[Sequence[float]] = None, figsize: Sequence[float] = (5.0, 5.0),
            title: Optional[str] = None) -> "Animation":
    """An :class:`Animation` of ``result`` (an :class:`exdex.Result`).

    fps : frames per second of playback, > 0.
    speed : playback speed relative to real time (0.25 = four times slower), > 0.
    max_frames : at most this many frames (>= 2); longer runs are sampled
        more sparsely and play at the same speed.
    plate_size : (width, height) of the drawn finger plate [m] (the scene
        does not give it); default the rectangle around the object's face
        and the pad at t = 0, centred on it.
    figsize : of the matplotlib Figure [inch].
    title : text above the picture (default: the scene's dof and method).
    """
    from exdex._validate import real as _real

    fps = _real(fps, "fps", low=0.0, low_open=True)
    speed = _real(speed, "speed", low=0.0, low_open=True)
    if isinstance(max_frames, bool) or not isinstance(max_frames, int) or max_frames < 2:
        raise ValueError(f"max_frames must be an integer >= 2, got {max_frames!r}")
    if plate_size is not None:
        plate_size = tuple(_real(x, "plate_size", low=0.0, low_open=True) for x in plate_size)
        if len(plate_size) != 2:
            raise ValueError("plate_size must be (width, height) [m]")
    if len(result.t) == 0:
        raise ValueError("Result.animate needs at least one sample")

    from exdex._optional import require

    FigureCanvasAgg = require("matplotlib.backends.backend_agg", "Result.animate()").FigureCanvasAgg
    from matplotlib.figure import Figure
    from matplotlib.patches import Polygon

    idx, interval = _frame_indices(np.asarray(result.t), fps, speed, max_frames)
    g = frame_geometry(result, idx, plate_size)
    sc = result.scene
    mm = 1e3

    fig = Figure(figsize=(float(figsize[0]), float(figsize[1])), layout="constrained")
    FigureCanvasAgg(fig)
    ax = fig.add_subplot()
    ax.set_aspect("equal")
    ax.set_xlabel("x [mm] (plate plane at t = 0)")
    ax.set_ylabel("y [mm]")
    head = title if title is not None else f"{sc.dof} scene, method {result.method}"
    heading = ax.set_title(f"{head}\n", fontsize="medium")   # the second line: the time and stick or slip

    pts = np.concatenate([g["outline"].reshape(-1, 2), g["plate"].reshape(-1, 2)]) * mm
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    size = float(max(np.max(hi - lo), 1e-6))
    lo, hi = lo - 0.15 * size, hi + 0.15 * size
    # a square view (the picture is to scale, aspect 1): a tall or wide motion keeps readable axes
    mid0 = 0.5 * (lo + hi)
    half = 0.5 * float(np.max(hi - lo))
    lo, hi = mid0 - half, mid0 + half
    span = hi - lo
    ax.set_xlim(lo[0], hi[0])
    ax.set_ylim(lo[1], hi[1])

    # stops: the line through the view, the forbidden side hatched
    far = 4.0 * float(np.max(span))
    mid = (lo + hi) / 2
    for n2, off in g["stops"]:
        foot = mid + (off * mm - float(np.dot(n2, mid))) * n2
        tang = np.array([-n2[1], n2[0]])
        a, b = foot - far * tang, foot + far * tang
        # drawn over the plate: the fingers' part beyond a stop is hidden by it
        ax.add_patch(Polygon([a, b, b - far * n2, a - far * n2], closed=True, facecolor="white",
                             edgecolor="0.3", hatch="///", lw=0, zorder=4))
        ax.plot([a[0], b[0]], [a[1], b[1]], color="0.2", lw=1.5, zorder=4)

    plate = Polygon(g["plate"][0] * mm, closed=True, facecolor="0.85", edgecolor="0.5", lw=1, zorder=1,
                    label="finger plate", gid="plate")
    ax.add_patch(plate)
    if g["outline"].shape[1] > 1:
        body = Polygon(g["outline"][0] * mm, closed=True, facecolor="#9ecae1", edgecolor="#08519c", lw=1.5,
                       alpha=0.9, zorder=2, label="object", gid="object")
        ax.add_patch(body)
    else:
        body = None
    (com,) = ax.plot([], [], "o", color="#08519c", ms=4, zorder=3, label="centre of mass")
    contact = None
    if g["contact"] is not None:
        key = "pad on the finger" if g["contact_kind"] == "pad" else "contact patch on the object"
        contact = Polygon(g["contact"][0] * mm, closed=True, facecolor="#fdae6b", edgecolor="#e6550d", alpha=0.6,
                          lw=1, zorder=3, label=key, gid="contact")
        ax.add_patch(contact)
    (cop_dot,) = ax.plot([], [], "+", color="#e6550d", ms=7, mew=1.5, zorder=4,
                         label="centre of pressure" + ("" if contact is not None else " (patch given by e_r)"))
    r_patch = sc.grasp.patch.e_r * mm   # the arc's radius: the patch's torsion length

    capacity = sc.grasp.capacity
    fmax = float(np.nanmax(np.linalg.norm(g["force"], axis=1))) if len(g["force"]) else 0.0
    ref = capacity if capacity > 0 else (fmax if np.isfinite(fmax) and fmax > 0 else 1.0)
    ext = np.ptp(sc.body.vertices(), axis=0) if len(sc.body.vertices()) > 1 else np.array([4 * r_patch / mm] * 2)
    if not np.max(ext) > 0:
        ext = np.array([4 * r_patch / mm] * 2)
    arrow_len = float(max(np.max(ext), 1e-9)) * mm  # full capacity = the object's size
    arrow = ax.annotate("", xy=(0, 0), xytext=(0, 0), zorder=5,
                        arrowprops=dict(arrowstyle="-|>", color="#d62728", lw=2, mutation_scale=12))
    (arc,) = ax.plot([], [], color="#d62728", lw=1.5, zorder=5)
    gv = g["gravity"]
    if np.linalg.norm(gv) > 0:
        d = gv / np.linalg.norm(gv) * 0.07 * float(np.max(span))
        c = np.array([lo[0] + 0.08 * span[0], hi[1] - 0.08 * span[1]])
        ax.annotate("", xy=tuple(c + d / 2), xytext=tuple(c - d / 2),
                    arrowprops=dict(arrowstyle="-|>", color="0.3"))
        ax.text(c[0] + 0.05 * span[0], c[1], "g", color="0.3", fontsize="small", va="center")
    from matplotlib.lines import Line2D

    force_key = Line2D([], [], color="#d62728", lw=2, marker=">", markevery=[1], ms=5,
                       label=f"friction force: {arrow_len:.3g} mm = {ref:.3g} N")
    torque_key = Line2D([], [], color="#d62728", lw=1.5,
                        label=f"friction torque: full turn = {ref * sc.grasp.patch.e_r:.3g} N m")
    handles = [h for h in (plate, body, contact, cop_dot) if h is not None] + [force_key, torque_key]
    fig.legend(handles=handles, loc="outside lower center", ncols=2 if fig.get_figwidth() >= 4.5 else 1,
               fontsize="x-small", frameon=False)
    fig.canvas.draw()                 # lay out once (the key below the picture), then keep it for every frame
    fig.set_layout_engine("none")

    finite = np.isfinite(g["force"]).all(axis=1)
    torque_ref = ref * sc.grasp.patch.e_r

    def update(k):
        plate.set_xy(g["plate"][k] * mm)
        if body is not None:
            body.set_xy(g["outline"][k] * mm)
        com.set_data([g["com"][k, 0] * mm], [g["com"][k, 1] * mm])
        cop = g["cop"][k] * mm
        if contact is not None:
            contact.set_xy(g["contact"][k] * mm)
        cop_dot.set_data([cop[0]], [cop[1]])
        if finite[k]:
            tip = cop + g["force"][k] / ref * arrow_len
            arrow.set_position((cop[0], cop[1]))  # the tail (the annotation's text position)
            arrow.xy = (tip[0], tip[1])
            arrow.set_visible(True)
            sweep = 2 * math.pi * float(np.clip(g["m_z"][k] / torque_ref, -1, 1)) if torque_ref > 0 else 0.0
            ang = np.linspace(0.0, sweep, 40)
            arc.set_data(cop[0] + 0.7 * r_patch * np.cos(ang), cop[1] + 0.7 * r_patch * np.sin(ang))
        else:
            arrow.set_visible(False)
            arc.set_data([], [])
        state = "stick" if g["stick"][k] else "slip"
        heading.set_text(f"{head}\nt = {g['t'][k]:.3f} s, {state}")
        return ()

    update(0)
    return Animation(fig, update, len(idx), interval)

"""Hold benchmark: does a grasped object that should stay put stay put?

``exdex hold`` (``exdex.cli.hold``) holds an object between the plates for ``--duration`` seconds
(10 s by default) and measures how far it moves relative to the gripper, in
exdex and in every engine setting users pick. Exact stick (exdex) gives
exactly zero; regularised or soft friction lets an in-cone load creep.

Scenarios (every combination):

* ``dof``: ``translation`` (the object may slide along the vertical plate
  axis; the load is its weight) or ``rotation`` (the object hangs from a
  pivot at the centre of a 20 mm disc patch whose centre is ``ARM`` = 30 mm to
  the side of its centre of mass; the load is the torque of its weight).
* ``margin``: the friction capacity over the static load, 1.5, 3 and 20
  (the grip force is set from it: mu * 2 * F = margin * m g for translation,
  mu * 2 * F * e_r = margin * m g * ARM for rotation).
* ``motion``: ``rest`` (gripper still) or ``shake`` (the gripper oscillates
  at ``SHAKE_HZ``, amp (1 - cos 2 pi f t), starting and ending at rest, along the plate axis, or about the plate normal through the
  pivot, with an acceleration amplitude adding a quarter of the static load:
  the peak load is 1.25 m g (or 1.25 m g ARM), below the slip threshold of
  every margin).

Measured: ``drift`` = |q(T) - q(0)| after T seconds [m or rad], and the mean
creep speed |q(T) - q(T0)| / (T - T0) after the first ``T0`` = T/10 seconds
(the squeeze's settling transient excluded) [m/s or rad/s].

Engine settings (``SETTINGS``): MuJoCo elliptic and pyramidal cones with
impratio 1, 10, 100 and noslip 0 and 10 iterations (2 ms step, plus the
default at 1 ms and 5 ms); pybullet's default and cone friction off (1/240 s,
plus the default at 1 ms); Drake point and hydroelastic contact, stiction
tolerance 1e-4 (Drake's default) and 1e-6 m/s with the default "lagged"
approximation, "sap" at 1 ms, and the 10 ms step. The engines are built by
``exdex.engines`` (box pads as in ``exdex compare``).

``exdex hold`` writes ``hold_table.csv`` (one row per setting and scenario),
``hold_table.txt`` (the table, also printed) and ``hold_drift.png`` (drift
against time on a log scale, margin 3).
"""
from __future__ import annotations

import dataclasses
import math
import time

import numpy as np

from exdex._optional import pyplot, require
from exdex._rotations import quat_from_matrix as _quat_from_matrix
from exdex.scene import DEFAULT_GRIPPER_ROTATION, Body, Grasp, Patch, SampledTrajectory, Scene
from exdex.simulate import simulate

__all__ = ["MARGINS", "MOTIONS", "DOFS", "SETTINGS", "QUICK_SETTINGS", "hold_scene", "run_setting", "benchmark",
           "FIELDS", "format_table", "plot"]

MARGINS = (1.5, 3.0, 20.0)
MOTIONS = ("rest", "shake")
DOFS = ("translation", "rotation")
MASS = 0.1                      # kg
SIZE = (0.10, 0.04, 0.03)       # box [m]; x, y in the plate plane
MU = 0.5
ARM = 0.03                      # patch centre to centre of mass, rotation scenes [m]
PATCH_RADIUS = 0.01             # disc patch [m]
SHAKE_HZ = 5.0
SHAKE_LOAD = 0.25               # shake's peak inertial load / static load
G = 9.81


def _settings():
    from exdex import engines as E

    out = [("exdex", "exdex", None, dict(dt=1e-3))]
    for cone in ("elliptic", "pyramidal"):
        for imp in (1.0, 10.0, 100.0):
            for ns in (0, 10):
                out.append((f"mujoco {cone} impratio {imp:g} noslip {ns}", "mujoco", E.run_mujoco,
                            dict(dt=0.002, cone=cone, impratio=imp, noslip_iterations=ns)))
    for dt in (0.001, 0.005):
        out.append((f"mujoco elliptic dt {1e3 * dt:g} ms", "mujoco", E.run_mujoco, dict(dt=dt)))
    out.append(("pybullet default", "pybullet", E.run_pybullet, dict()))
    out.append(("pybullet cone off", "pybullet", E.run_pybullet, dict(cone=False)))
    out.append(("pybullet dt 1 ms", "pybullet", E.run_pybullet, dict(dt=0.001)))
    for model in ("point", "hydroelastic"):
        for vs in (1e-4, 1e-6):
            out.append((f"drake {model} stiction {vs:g}", "drake", E.run_drake,
                        dict(contact_model=model, stiction_tolerance=vs)))
        out.append((f"drake {model} sap", "drake", E.run_drake, dict(contact_model=model, approximation="sap")))
        out.append((f"drake {model} dt 10 ms", "drake", E.run_drake, dict(contact_model=model, dt=0.01)))
    return out


def _quick_settings():
    from exdex import engines as E

    return [("exdex", "exdex", None, dict(dt=1e-3)),
            ("mujoco elliptic impratio 1 noslip 0", "mujoco", E.run_mujoco, dict()),
            ("mujoco elliptic impratio 1 noslip 10", "mujoco", E.run_mujoco, dict(noslip_iterations=10)),
            ("pybullet default", "pybullet", E.run_pybullet, dict()),
            ("drake point stiction 0.0001", "drake", E.run_drake, dict())]


SETTINGS = _settings
QUICK_SETTINGS = _quick_settings


def _shake(dof, t_end, scene):
    """The gripper's shake as sampled poses (200 per second): amp (1 - cos w t),
    which starts and (after whole periods) ends at rest, so the gripper's
    velocity never jumps, with an acceleration amplitude amp w^2 adding
    SHAKE_LOAD times the static load."""
    w = 2 * math.pi * SHAKE_HZ
    # sampled two intervals past t_end: the log ends at speed, and its end (a
    # velocity jump of the gripper) must fall outside the run
    t = np.arange(int(round(t_end * 200)) + 3) / 200.0
    R0 = np.array(DEFAULT_GRIPPER_ROTATION)
    if dof == "translation":
        amp = SHAKE_LOAD * G / w**2                      # a = amp w^2
        axis = R0 @ np.array([0.0, 1.0, 0.0])            # plate axis B y (vertical)
        pos = np.outer(amp * (1.0 - np.cos(w * t)), axis)
        quats = np.tile(_quat_from_matrix(R0), (len(t), 1))
    else:
        c = scene.grasp.patch.center
        I = np.array(scene.body.inertia)
        i_pivot = I[2, 2] + scene.body.mass * (c[0] ** 2 + c[1] ** 2)
        amp = SHAKE_LOAD * MASS * G * ARM / i_pivot / w**2  # angular acceleration amplitude / w^2
        pos = np.zeros((len(t), 3))
        quats = []
        for th in amp * (1.0 - np.cos(w * t)):
            cs, sn = math.cos(th), math.sin(th)
            Rz = np.array([[cs, -sn, 0.0], [sn, cs, 0.0], [0.0, 0.0, 1.0]])
            quats.append(_quat_from_matrix(R0 @ Rz))     # about the plate normal through B's origin (the pivot)
        quats = np.array(quats)
    return SampledTrajectory(t, pos, quats)


def hold_scene(dof, margin, motion, t_end=10.0):
    """The benchmark's scene for one scenario (see the module docstring)."""
    if dof not in DOFS:
        raise ValueError(f"dof must be one of {DOFS}, got {dof!r}")
    if motion not in MOTIONS:
        raise ValueError(f"motion must be one of {MOTIONS}, got {motion!r}")
    if not (isinstance(margin, (int, float)) and margin > 1.0):
        raise ValueError(f"margin must be a number > 1 (capacity over static load), got {margin!r}")
    body = Body.box(MASS, SIZE)
    if dof == "translation":
        grip = margin * MASS * G / (2 * MU)
        scene = Scene(body=body, grasp=Grasp(mu=MU, grip_force=grip), dof="translation", gravity=(0.0, 0.0, -G))
    else:
        patch = Patch.disc(PATCH_RADIUS, center=(ARM, 0.0))
        grip = margin * MASS * G * ARM / (2 * MU * patch.e_r)
        # pivot (patch centre) at B's origin; the centre of mass ARM beside it, perpendicular to gravity
        scene = Scene(body=body, grasp=Grasp(mu=MU, grip_force=grip, patch=patch), dof="rotation",
                      q0=(-ARM, 0.0, 0.0), gravity=(0.0, 0.0, -G))
    if motion == "shake":
        scene = dataclasses.replace(scene, motion=_shake(dof, t_end, scene))
    return scene


def run_setting(setting, scene, t_end):
    """Run one setting on one scene; returns (t, q - q0, wall time [s])."""
    label, engine, fn, kw = setting
    t0 = time.perf_counter()
    if engine == "exdex":
        res = simulate(scene, t_end, **kw)
    else:
        res = fn(scene, t_end, **kw)
    wall = time.perf_counter() - t0
    return res.t, res.displacement[:, 0], wall


def benchmark(t_end=10.0, margins=MARGINS, motions=MOTIONS, dofs=DOFS, settings=None, progress=None):
    """Rows (dicts) and sampled drift curves of every setting and scenario."""
    settings = _settings() if settings is None else settings
    rows, curves = [], {}
    for dof in dofs:
        for margin in margins:
            for motion in motions:
                scene = hold_scene(dof, margin, motion, t_end)
                for st in settings:
                    try:
                        t, d, wall = run_setting(st, scene, t_end)
                        t_creep = t_end / 10
                        i = int(np.searchsorted(t, t_creep - 1e-12))
                        drift = abs(float(d[-1]))
                        creep = abs(float(d[-1] - d[i])) / (t[-1] - t[i])
                        status = "ok" if np.all(np.isfinite(d)) else "non-finite"
                        step = max(1, len(t) // 1000)
                        curves[(st[0], dof, margin, motion)] = (t[::step], np.abs(d[::step]))
                    except Exception as exc:   # noqa: BLE001 - a failing engine setting is a row, not a crash
                        drift = creep = wall = math.nan
                        status = f"failed: {type(exc).__name__}: {exc}".replace(",", ";")[:120]
                    rows.append(dict(setting=st[0], engine=st[1], dof=dof, margin=margin, motion=motion,
                                     unit="m" if dof == "translation" else "rad", drift=drift, creep_speed=creep,
                                     wall_time_s=wall, status=status))
                    if progress is not None:
                        progress(rows[-1])
    return rows, curves


def format_table(rows):
    """The table: one line per setting, drift after T per scenario."""
    keys = [(dof, m, mo) for dof in DOFS for m in MARGINS for mo in MOTIONS
            if any(r["dof"] == dof and r["margin"] == m and r["motion"] == mo for r in rows)]
    canonical = [s[0] for s in _settings()]
    settings = sorted(dict.fromkeys(r["setting"] for r in rows),
                      key=lambda s: canonical.index(s) if s in canonical else len(canonical))
    by = {(r["setting"], r["dof"], r["margin"], r["motion"]): r for r in rows}
    head1 = f"{'':38s}" + "".join(f"{('trans' if d == 'translation' else 'rot') + f' {m:g}x':>11s}" for d, m, _ in keys)
    head2 = f"{'setting':38s}" + "".join(f"{mo:>11s}" for _, _, mo in keys)
    lines = []
    for title, field in (("drift |q(T) - q(0)| (translation in m, rotation in rad; '0' = exactly zero; "
                          "'-' = failed)", "drift"),
                         ("mean creep speed after T/10 (m/s, rad/s):", "creep_speed")):
        if lines:
            lines.append("")
        lines += [title, head1, head2]
        for s in settings:
            cells = []
            for k in keys:
                r = by.get((s,) + k)
                v = math.nan if r is None else r[field]
                cells.append(f"{'-':>11s}" if not np.isfinite(v) else f"{'0':>11s}" if v == 0 else f"{v:11.2e}")
            lines.append(f"{s:38s}" + "".join(cells))
    return "\n".join(lines)


def plot(curves, path, t_end, margin=3.0):
    """Drift against time (log scale) of every engine setting at ``margin``, one
    panel per dof and motion; exdex's exact zero said in words. Saved to ``path``."""
    matplotlib = require("matplotlib", "exdex.studies.hold.plot")
    plt = pyplot("exdex.studies.hold.plot", backend="Agg")

    fig, axes = plt.subplots(2, 2, figsize=(12, 8.5), sharex=True)
    labels = list(dict.fromkeys(k[0] for k in curves if k[0] != "exdex"))
    # 40 distinct colours, so no two settings share one: tab20, then tab20b one hue after another
    b = matplotlib.colormaps["tab20b"].colors
    palette = list(matplotlib.colormaps["tab20"].colors) + [b[i + k] for k in (0, 2, 1, 3) for i in range(0, 20, 4)]
    colors = {lab: palette[i % len(palette)] for i, lab in enumerate(labels)}
    styles = {"mujoco": "-", "pybullet": "--", "drake": ":"}
    for i, dof in enumerate(DOFS):
        for j, motion in enumerate(MOTIONS):
            ax = axes[i, j]
            for lab in labels:
                c = curves.get((lab, dof, margin, motion))
                if c is None:
                    continue
                t, d = c
                ok = d > 0
                if np.any(ok):
                    ax.semilogy(t[ok], d[ok], lw=1.1, color=colors[lab], ls=styles.get(lab.split()[0], "-"), label=lab)
            ex = curves.get(("exdex", dof, margin, motion))
            if ex is not None:
                msg = "exdex: exactly 0 throughout" if np.all(ex[1] == 0) else f"exdex: max {ex[1].max():.1e}"
                ax.text(0.02, 0.03, msg, transform=ax.transAxes, fontsize=8, color="k")
            unit = "m" if dof == "translation" else "rad"
            ax.set_title(f"{dof}, gripper {'at rest' if motion == 'rest' else 'shaking'}, margin {margin:g}x",
                         fontsize=9)
            ax.set_ylabel(f"|q(t) - q(0)| [{unit}]", fontsize=8)
            ax.grid(True, which="major", lw=0.3)
            ax.tick_params(labelsize=7)
            if i == 1:
                ax.set_xlabel("t [s]", fontsize=8)
    handles = {}
    for ax in axes.ravel():
        for h, lab in zip(*ax.get_legend_handles_labels()):
            handles.setdefault(lab, h)
    fig.legend(list(handles.values()), list(handles), loc="lower center", ncol=4, fontsize=7, frameon=False)
    fig.suptitle(f"Hold benchmark: drift of a held object against time ({t_end:g} s, log scale)", fontsize=10)
    fig.tight_layout(rect=(0, 0.16, 1, 0.97))
    fig.savefig(path, dpi=110)
    plt.close(fig)


#: columns of ``hold_table.csv`` (one row per setting and scenario)
FIELDS = ["setting", "engine", "dof", "margin", "motion", "unit", "drift", "creep_speed", "wall_time_s", "status"]

"""exdex.simulate: one whole trajectory computed in C, returned as NumPy arrays."""
from __future__ import annotations

import copy
import dataclasses
import math
import numbers
import os
import warnings
from dataclasses import dataclass, field
from typing import Any, Dict, Literal, Optional, Tuple, Union

import numpy as np
from numpy.typing import NDArray

from exdex import _core, diagnostics
from exdex._jumps import GripperJumpWarning, jumps as _jumps, warn_jumps as _warn_jumps
from exdex._obstacle_hint import reduced_obstacle_hint
from exdex.diagnostics import PhysicsWarning
from exdex._validate import check_times as _check_times, real as _real
from exdex.scene import METHODS, SOLVERS, Scene

__all__ = ["Result", "simulate", "SolverError", "PhysicsWarning", "GripperJumpWarning"]

SolverError = _core.SolverError

#: The integration methods and friction solvers (see :func:`simulate`).
Method = Literal["implicit", "event", "regularised", "explicit", "analytic", "auto"]
FrictionSolver = Literal["scalar", "brent", "multiroot"]


@dataclass(frozen=True, eq=False)
class Result:
    """A simulated trajectory of the object relative to the gripper.

    Attributes (n samples; row 0 is the initial state):

    t : (n,) times [s].
    q : (n, ndof) free coordinates: ``s`` [m] (translation scenes, the
        position of the centre of mass along the slide axis), ``theta`` [rad]
        (rotation scenes) or ``x, y, theta`` (planar), of the object frame C in
        the gripper frame B.
    v : (n, ndof) their rates [m/s or rad/s].
    wrench : (n, 3) plate friction on the object (f_x, f_y, m_z) in B at the
        centre of pressure [N, N, N m], mean over the step ending at the
        sample; row 0 (t = 0): the wrench that holds the object where it
        starts at rest with its load inside the static limit surface, in a
        scene without stops or obstacles (the static balance of gravity and
        the inertial forces at t = 0), else zero (the object starts moving
        or slipping, or stops and obstacles share the load). The stepper's
        initial state has the same wrench.
    stick : (n,) True where the step ending there left the object exactly at
        rest relative to the gripper (row 0: the initial velocity is zero).
    stop_force : (n, n_stops) mean normal force of each stop on the object [N].
    stats : dict of solver statistics: steps, stick_steps,
        solver_iterations, stop_iterations, warnings (soft problems: an
        iteration limit reached with the last iterate kept, a stop that
        cannot act or pinches the object, a penetration left after a step),
        first_warning_t [s] (end of the first step or output interval that
        counted one; None: none), min_gap [m], impacts (stops that started
        pushing an approaching object: velocity jumps), max_impulse [N s]
        (largest impact impulse, generalized N m s on a rotation pin; 0:
        none), max_impulse_t [s] and max_impulse_stop (its time and stop;
        None: none), grasp_lost_t [s] (pads on the fingers: the time of the
        sample where the contact region vanished; the run stopped there and
        the arrays end at it; None: held to the end). ``stop_force`` shows an
        impact as its impulse divided by the step.
    scene, method, friction_solver, dt : what produced it.
    certificate : the check of a translation or rotation run's reduction
        (None for planar runs, which neglect nothing, and for runs with
        ``certify=False``): a dict with ``holds`` (bool) and
        ``valid_until`` [s]; where it fails also ``first_bad`` (the first
        sample that fails), ``stick``, ``load`` (f_x, f_y, m_z) [N, N, N m],
        ``capacity`` [N], ``gauge`` and ``coordinate`` (see
        :class:`exdex.ReductionWarning`, issued then). Along the run, the
        plate friction wrench that the neglected in-plane coordinates need
        to stay still (the planar equations with the reduced coordinate's
        motion, gravity and the frame's inertial terms, stops that touch the
        object pushing as needed) is checked against the friction limit
        surface: inside the static surface while the reduced coordinate
        sticks; while it slips, maximum dissipation gives a pure translation
        slip no friction moment and a pure rotation about the centre of
        pressure no friction force, so that part of the load must be zero
        (to 1e-9 of the scene's force scale) or carried by a stop. Checked
        at every sample and every switching time of the motion and grip
        schedule, and between two stuck samples over the interval (proven
        with interval bounds, or halved up to four times where they cannot
        show it); the failure is located between samples by Brent's method.
        :attr:`reduction_valid_until` and :attr:`reduction_holds` read it.
    models : for a scene with ``dof="auto"``: which model ran over which
        interval and why, as ``(dof, method, t_start, t_end, why)`` tuples
        (empty for an explicit dof). Where a 1-DoF model holds throughout,
        the Result is that model's (``scene.dof`` says which, q its one
        coordinate); after a switch it is planar, q = (x, y, theta) over the
        whole run (the 1-DoF part as the full pose), and the samples after the
        switch lie on the grid t_switch + k dt.
    """

    t: np.ndarray
    q: np.ndarray
    v: np.ndarray
    wrench: np.ndarray
    stick: np.ndarray
    stop_force: np.ndarray
    stats: Dict[str, Any]
    scene: Optional[Scene] = None
    method: str = "implicit"
    friction_solver: str = "scalar"
    dt: float = float("nan")
    certificate: Optional[Dict[str, Any]] = None
    models: Tuple[Tuple[str, str, float, float, str], ...] = ()

    @property
    def reduction_valid_until(self) -> Optional[float]:
        """Until when a translation or rotation run's reduction held [s]: the
        last time at which the planar model admits the reduced motion (the
        last sample's time when it held throughout; the failure is just
        after it otherwise). None for planar runs and uncertified ones."""
        if self.certificate is None:
            return None
        return float(self.certificate["valid_until"])

    @property
    def reduction_holds(self) -> NDArray[np.bool_]:
        """(n,) True at the samples up to :attr:`reduction_valid_until`
        (every sample of a run whose reduction held, of a planar run and of
        an uncertified one): where the reduced result describes the grasp."""
        c = self.certificate
        if c is None or c["holds"]:
            return np.ones(len(self.t), dtype=bool)
        out = np.zeros(len(self.t), dtype=bool)
        out[:int(c["first_bad"])] = True
        return out

    @property
    def displacement(self) -> NDArray[np.float64]:
        """(n, ndof) coordinates relative to the initial ones, q - q[0]."""
        return self.q - self.q[0]

    @property
    def pose(self) -> NDArray[np.float64]:
        """(n, 3) full planar pose (x, y, theta) of C in B, whatever the scene's dof."""
        if self.scene is None:
            raise ValueError("Result.pose needs the Result's scene (Result.scene is None)")
        return diagnostics.poses(self.scene, self.q)

    def plot(self, ax: Any = None, label: Optional[str] = None, stick_shading: bool = True) -> Any:
        """Plot the displacement of each free coordinate against time.

        Translations in mm and rotations in degrees, each on its own labelled
        axis: a translation or rotation scene draws one Axes; a planar scene
        draws x and y [mm] on one and theta [deg] on a second, stacked below
        it in a new figure, or a twin y axis (right-hand side) of a given
        ``ax``. Steps where the object stuck to the plates are shaded.

        Returns the Axes (1-DoF scenes) or a tuple ``(ax_mm, ax_deg)``
        (planar scenes).
        """
        from exdex._optional import pyplot

        plt = pyplot("Result.plot()")
        names = self.scene.coordinate_names if self.scene is not None else tuple(f"q{i}" for i in range(self.q.shape[1]))
        lin = [i for i, n in enumerate(names) if n != "theta"]
        ang = [i for i, n in enumerate(names) if n == "theta"]
        groups = [g for g in (lin, ang) if g]
        if ax is None:
            if len(groups) == 2:
                _, axes = plt.subplots(2, 1, figsize=(6, 5), sharex=True)
                axes = list(axes)
            else:
                _, a = plt.subplots(figsize=(6, 3.5))
                axes = [a]
        elif len(groups) == 2:
            axes = [ax, ax.twinx()]
        else:
            axes = [ax]
        colours = plt.rcParams["axes.prop_cycle"].by_key().get("color", ["C0", "C1", "C2"])
        for a, idx in zip(axes, groups):
            angular = names[idx[0]] == "theta"
            scale, unit = (180 / math.pi, "deg") if angular else (1e3, "mm")
            for i in idx:
                lab = f"{label} {names[i]}" if label else names[i]
                a.plot(self.t, scale * self.displacement[:, i], label=f"{lab} [{unit}]",
                       color=colours[i % len(colours)])
            what = "rotation" if angular else ("displacement" if names != ("s",) else "slide along the axis")
            a.set_ylabel(f"{what} {', '.join(names[i] for i in idx)} [{unit}]")
            twin = ax is not None and a is not axes[0]
            if stick_shading and self.stick.any() and not twin:
                a.fill_between(self.t, 0, 1, where=self.stick, transform=a.get_xaxis_transform(), color="0.9",
                               step="post", label="stick", zorder=0)
        axes[-1].set_xlabel("time [s]")
        if ax is None or len(axes) == 1:
            for a in axes:
                a.legend(loc="best", fontsize="small")
        else:  # twin axes: one legend for both
            h0, l0 = axes[0].get_legend_handles_labels()
            h1, l1 = axes[1].get_legend_handles_labels()
            axes[0].legend(h0 + h1, l0 + l1, loc="best", fontsize="small")
        if len(axes) == 1:
            return axes[0]
        return tuple(axes)

    # ------------------------------------------------------------ export

    def _names(self) -> Tuple[str, ...]:
        if self.scene is not None:
            return self.scene.coordinate_names
        return tuple(f"q{i}" for i in range(self.q.shape[1]))

    @property
    def units(self) -> Dict[str, str]:
        """Units of the columns of :meth:`to_dict` (SI), by column name."""
        units = {"t": "s"}
        for n in self._names():
            units[n] = "rad" if n == "theta" else "m"
        for n in self._names():
            units[f"v_{n}"] = "rad/s" if n == "theta" else "m/s"
        units.update(f_x="N", f_y="N", m_z="N m", stick="")
        for i in range(self.stop_force.shape[1] if self.stop_force.ndim == 2 else 0):
            units[f"stop_force_{i}"] = "N"
        return units

    def to_dict(self) -> Dict[str, NDArray[Any]]:
        """The trajectory as named columns, each an (n,) NumPy array:

        ``t`` [s]; the free coordinates by name (``s`` [m] in translation
        scenes, ``theta`` [rad] in rotation scenes, ``x``, ``y`` [m] and
        ``theta`` [rad] in planar ones); their rates ``v_<name>`` [m/s or
        rad/s]; the plate friction wrench ``f_x``, ``f_y`` [N] and ``m_z``
        [N m] (in B, at the centre of pressure); ``stick`` (bool); and
        ``stop_force_<i>`` [N] for each stop. :attr:`units` names the units.
        """
        names = self._names()
        out = {"t": self.t}
        for i, n in enumerate(names):
            out[n] = self.q[:, i]
        for i, n in enumerate(names):
            out[f"v_{n}"] = self.v[:, i]
        out["f_x"], out["f_y"], out["m_z"] = self.wrench[:, 0], self.wrench[:, 1], self.wrench[:, 2]
        out["stick"] = self.stick
        for i in range(self.stop_force.shape[1] if self.stop_force.ndim == 2 else 0):
            out[f"stop_force_{i}"] = self.stop_force[:, i]
        return out

    def to_dataframe(self) -> Any:
        """The columns of :meth:`to_dict` as a ``pandas.DataFrame`` (one row per
        sample); ``df.attrs`` holds the units, method and time step.
        Needs pandas (an optional dependency)."""
        try:
            import pandas as pd
        except ImportError:
            raise ImportError("Result.to_dataframe needs pandas (pip install pandas); "
                              "Result.to_dict() gives the same columns as NumPy arrays") from None
        df = pd.DataFrame(self.to_dict())
        df.attrs.update(units=self.units, method=self.method, friction_solver=self.friction_solver, dt=self.dt)
        return df

    def save(self, path: Union[str, "os.PathLike[str]"]) -> Union[str, "os.PathLike[str]"]:
        """Write the result to ``path``, in the format of its extension:

        ``.npz`` -- NumPy archive of the arrays (``t``, ``q``, ``v``,
        ``wrench``, ``stick``, ``stop_force``), the scene (as the JSON of
        :func:`exdex.save_scene`) and the run's settings and statistics;
        :meth:`Result.load` reads it back exactly.
        ``.csv`` -- one row per sample, the columns of :meth:`to_dict` with a
        header row of their names; numbers in their shortest exact decimal
        form, ``stick`` as 0 or 1.

        Returns the path.
        """
        ext = os.path.splitext(os.fspath(path))[1].lower()
        if ext == ".npz":
            import json

            meta = dict(method=self.method, friction_solver=self.friction_solver, dt=self.dt,
                        stats=self.stats, names=list(self._names()), certificate=self.certificate,
                        models=[list(m) for m in self.models])
            arrays: Dict[str, Any] = dict(t=self.t, q=self.q, v=self.v, wrench=self.wrench, stick=self.stick,
                          stop_force=self.stop_force, meta=np.array(json.dumps(meta)))
            if self.scene is not None:
                from exdex import io

                arrays["scene"] = np.array(io.dumps(self.scene, "json"))
            with open(path, "wb") as f:
                np.savez(f, **arrays)
        elif ext == ".csv":
            cols = self.to_dict()
            keys = list(cols)
            rows = np.column_stack([np.asarray(c, dtype=np.float64) for c in cols.values()])
            stick_col = keys.index("stick")
            with open(path, "w", encoding="utf-8", newline="") as f:
                f.write(",".join(keys) + "\n")
                for row in rows.tolist():
                    row[stick_col] = int(row[stick_col])
                    f.write(",".join(map(repr, row)) + "\n")
        else:
            raise ValueError(f"Result.save: the extension of path must be .npz or .csv, got {ext!r}")
        return path

    @classmethod
    def load(cls, path: Union[str, "os.PathLike[str]"]) -> "Result":
        """A :class:`Result` from an ``.npz`` file written by :meth:`save`."""
        import json

        with np.load(path, allow_pickle=False) as z:
            meta = json.loads(str(z["meta"]))
            scene = None
            if "scene" in z.files:
                from exdex import io

                scene = io.loads(str(z["scene"]), "json")
            return cls(t=z["t"], q=z["q"], v=z["v"], wrench=z["wrench"], stick=z["stick"],
                       stop_force=z["stop_force"], stats=meta["stats"], scene=scene, method=meta["method"],
                       friction_solver=meta["friction_solver"], dt=meta["dt"],
                       certificate=_cert_load(meta.get("certificate")),
                       models=tuple(tuple(m) for m in meta.get("models", ())))

    def __repr__(self) -> str:
        names = self._names()
        n = len(self.t)
        if n == 0:
            return f"<exdex.Result method={self.method!r}, 0 samples>"
        final = ", ".join(f"{nm} = {x:.6g} {'rad' if nm == 'theta' else 'm'}" for nm, x in zip(names, self.q[-1]))
        steps = self.stick[1:]
        stick = f"{np.mean(steps):.0%}" if len(steps) else "n/a"
        dof = self.scene.dof if self.scene is not None else f"{len(names)}-DoF"
        return (f"<exdex.Result {dof}, method={self.method!r}, {n} samples, t = {self.t[0]:g}..{self.t[-1]:g} s, "
                f"final {final}, stick in {stick} of steps>")

    def _repr_html_(self) -> str:
        from exdex._html import summary_table

        names = self._names()
        n = len(self.t)
        dof = self.scene.dof if self.scene is not None else f"{len(names)}-DoF"
        rows = [("model", f"{dof}, method {self.method}, dt {self.dt:g} s"), ("samples", n)]
        if n:
            unit = {"theta": ("deg", 180.0 / math.pi)}
            rows.append(("time", f"{self.t[0]:g} to {self.t[-1]:g} s"))
            for nm, x0, x1 in zip(names, self.q[0], self.q[-1]):
                u, k = unit.get(nm, ("mm", 1e3))
                rows.append((f"{nm}: start, end", f"{k * x0:.6g} {u}, {k * x1:.6g} {u}"))
            steps = self.stick[1:]
            rows.append(("stick", f"{np.mean(steps):.0%} of steps, at the end: {'yes' if self.stick[-1] else 'no'}"
                         if len(steps) else "n/a"))
        if self.certificate is not None:
            c = self.certificate
            rows.append(("1-DoF reduction", "holds" if c["holds"] else f"fails at t = {c['valid_until']:g} s"))
        if self.stats.get("warnings"):
            rows.append(("solver warnings", self.stats["warnings"]))
        return summary_table("exdex.Result", rows)

    def animate(self, **options: Any) -> Any:
        """An animation of the object between the plates: plates, object
        outline, stops and the plate friction wrench (see
        :func:`exdex.animation.animate` for the options: fps, speed,
        max_frames, plate_size, figsize, title). Plays inline in Jupyter;
        ``.save("run.gif")`` (or ``.mp4`` with ffmpeg, ``.html``) writes it."""
        from exdex.animation import animate

        return animate(self, **options)

    def drift_after(self, t0: float) -> float:
        """Largest |v| over samples at t >= t0 (0.0 means exactly still)."""
        sel = self.t >= t0
        return float(np.max(np.abs(self.v[sel]))) if np.any(sel) else 0.0


def simulate(scene: Scene, t_end: float, dt: float = 1e-3, method: Method = "implicit",
             friction_solver: FrictionSolver = "scalar", eps: float = 1e-4, rtol: float = 1e-8,
             atol: float = 1e-10, certify: bool = True) -> Result:
    """Simulate the object in the moving gripper from t = 0 to ``t_end``.

    Parameters
    ----------
    scene : exdex.Scene
        With ``dof="auto"``, the smallest model that holds: the 1-DoF models
        (translation along ``slide_axis``, rotation about the centre of
        pressure; the analytic method where ``method="auto"`` and it applies)
        are run with their certificate, the one that holds longest is kept
        up to where it fails, and the planar model continues from that
        instant with the state carried over exactly (the motion and grip
        schedule played on from there); :attr:`Result.models` says which ran
        when and why. A reduction that fails at once runs planar from t = 0
        (the same run as ``dof="planar"``); one that holds gives the 1-DoF
        run itself, bit for bit. Stops and obstacles carry load in the
        certificate (their normal forces and friction); a 1-DoF model that
        cannot run against the scene's obstacles (a SolverError) is passed
        over.
    t_end : float
        End time [s], >= dt.
    dt : float
        Time step [s], > 0. Steps of dt; the last one is shortened to end
        exactly at t_end.
    method : {"implicit", "event", "regularised", "explicit", "analytic", "auto"}
        "implicit" (default): Moreau's midpoint time stepping with the
        maximum-dissipation friction solve (paper Eq. 6) at every step of dt;
        exact stick; first order in dt where stick/slip switches fall inside
        a step. A step holding one of the scene's known switching times (the
        motion's phase switches and velocity jumps, the grip schedule's
        breakpoints) is taken as two sub-steps split there (the output stays
        on the grid), and a velocity jump of the gripper is applied at its
        time as a jump of the relative velocity, friction acting after it.
        A slip that stops inside a step is stopped where it ends under the
        step's force (1-DoF: also a slip that reverses through zero, which
        slides on from there; exact for a constant force), and a
        translation step in which a stop pushes the object ends with the
        stop's own velocity.
        "event": event-driven exact Coulomb friction. Smooth slip phases are
        integrated by GSL's adaptive rk8pd stepper to ``rtol``/``atol``;
        slip -> stick (the slip speed reaches 0) and stick -> slip (the
        wrench needed to stick leaves the friction ellipsoid) are located by
        Brent's method on the stepper's one-step map; the motion's switching
        times are stepped onto. Exact stick, accuracy set by the tolerances
        (``dt`` only sets the output grid). Costs two events per crossing of
        the friction limit (Zeno-like toggling makes it expensive and, past
        1000 events in one output interval, raises SolverError).
        "regularised": smooth friction w = -mu N E^2 u / sqrt(|E u|^2 + eps^2)
        (``eps`` a slip speed [m/s]) with the same adaptive stepper; no true
        stick: under a load w inside the ellipsoid the object creeps at
        E u = eps E^-1 w / sqrt((mu N)^2 - |E^-1 w|^2), and the stiffness
        mu N / (M eps) makes the explicit stepper's steps collapse for small
        eps: past 1e5 steps (accepted, rejected and event-location
        iterations) in one output interval, or a step below 16 ulps of t,
        "event" and "regularised" raise SolverError instead of grinding.
        "analytic": the exact solution, phase by phase, of 1-DoF scenes
        without stops whose drive is piecewise constant (a translating
        gripper with Eq. 7, a trapezoid with ramps or rest; a rotation about
        the centre of mass with the gripper turning about the plate normal):
        positions are quadratics in time and events roots of linear
        equations, nothing is integrated (``dt`` only sets the output grid).
        Other scenes raise ValueError saying why.
        "auto": "analytic" where it applies, else "event".
        "explicit": explicit Coulomb friction -mu N E^2 u / |E u| (0 at u = 0)
        with symplectic Euler steps of dt (split at the known switching
        times as "implicit"), the naive baseline. Never sticks:
        under a load |Q| < mu N the velocity chatters in a band of width
        2 dt mu N / M about 0 and the object creeps at dt Q / M on average
        (1-DoF). In a planar scene the chatter of the translation (~dt
        mu N / M) leaves only part of the friction torque acting, so the
        object can turn at up to ~(dt mu N / M) / e_r: first order in dt,
        but with a constant 1 / e_r, so coarse steps can be far off when
        the patch is small against the outline.
        With ``Grasp.mu_static`` > mu (static capacity Cs, kinetic C):
        "implicit" tries each step's stick with Cs first and else slides
        against C (a slip may stick one step early: O(dt)); "event" tests
        every stick with Cs and slides with C; "analytic" likewise;
        "regularised" holds the load in a stick band |E u| <= eps with the
        viscous friction -Cs E^2 u / eps (up to Cs at the band's edge) and
        slides with -C E^2 u / |E u| beyond it: first order in eps (it
        creeps below eps while stuck and starts a slip at eps instead of 0);
        "explicit" holds the load with Cs at u = 0 and returns a slip to
        u = 0 in the step whose kinetic update reverses it (or whose
        friction impulse can stop it) if Cs holds the load there: first
        order in dt.
        Every method handles stops in every scene (planar: plastic impacts,
        Coulomb at the impulse level on frictional stops, unilateral contact
        with the stop force from the constraint acceleration; "event" also
        rests exactly against stops).
    friction_solver : {"scalar", "brent", "multiroot"}
        How the ellipsoid step is solved in planar scenes: the monotone scalar
        (secular) equation by safeguarded Newton (default) or GSL Brent, or the
        paper's four quadratic equations with GSL's hybridsj. 1-DoF scenes have
        a closed form and ignore it.
    eps : float
        "regularised" only: the smoothing slip speed [m/s], > 0.
    rtol, atol : float
        "event" and "regularised" only: relative and absolute tolerances of
        the adaptive stepper's error control (GSL odeiv2 standard control on
        q, their rates and the wrench integrals), > 0.

    Returns
    -------
    exdex.Result

    Raises
    ------
    TypeError, ValueError
        For bad arguments, naming the parameter and its allowed range.
    exdex.SolverError
        If a solver fails to converge (``.status`` carries the C status).
        The message says when (``.time``, the time the run had reached
        [s], or None), why (``.cause``: ``"events"`` for a Zeno-like
        accumulation of switches, ``"step_budget"``, ``"step_floor"``,
        ``"stepper"``, ``"solver"`` or ``"nonfinite"``) and what to use
        instead (e.g. ``method="implicit"``, a larger rtol/atol or eps).
        A rotation run against obstacles whose state leaves the finite range
        says that the rotation model cannot clear ``Scene.obstacles[i]``
        when the pivot (the grasp point) is inside it at ``.time`` (then no
        angle of the object clears it), else that it may be unable to clear
        them, and suggests ``dof="planar"`` (or ``"auto"``).

    Warns
    -----
    exdex.ReductionWarning
        A kind of PhysicsWarning: where a translation or rotation run's
        reduction fails (time, neglected coordinate, load, margin).
    exdex.PhysicsWarning
        When the result leaves the model's assumptions (the object slides
        beyond the pad, the pads leave the body outline, impacts on stops,
        solver warnings in ``stats``): see :mod:`exdex.diagnostics`.
    exdex.GripperJumpWarning
        For each time in (0, t_end] where the gripper's velocity jumps (a
        sampled log that starts or ends at speed, a trapezoid without ramps),
        with the time and the size of the jump. Every method applies the
        same jump to the object: it keeps its absolute velocity (the plates
        cannot transmit an impulse).
    """
    dt, t_end = _check_times(t_end, dt)
    if isinstance(scene, Scene) and scene.dof == "auto":
        return _simulate_auto(scene, t_end, dt, method, friction_solver, eps, rtol, atol)
    res, spec = _run(scene, t_end, dt, method, friction_solver, eps, rtol, atol, certify)
    _warn_jumps(scene, _jumps(scene, spec), t_end)
    diagnostics.issue(diagnostics.findings(res))
    return res


def _run(scene, t_end, dt, method, friction_solver, eps, rtol, atol, certify=True, stop_at_failure=False):
    """The run of :func:`simulate` (times checked, dof not "auto") and its
    core spec, without the warnings simulate issues about it;
    stop_at_failure: a 1-DoF run certified as it goes ends where its
    certificate fails, its last sample there."""
    method = resolve_method(scene, method)
    spec = scene_spec(scene, method, friction_solver, eps, rtol, atol)
    try:
        out = _core.simulate(spec, t_end, dt, certify=bool(certify), stop_at_failure=stop_at_failure)
    except SolverError as exc:
        reduced_obstacle_hint(scene, spec, exc)
        raise
    return result_from_core(out, scene, method, friction_solver, dt), spec


_PLANAR_METHODS = ("implicit", "event", "regularised", "explicit")


def _full_state(scene, q, v):
    """Planar poses and velocities (n, 3) of a 1-DoF scene's coordinates q, rates v (n, 1)."""
    pose = diagnostics.poses(scene, q)
    v = np.asarray(v, dtype=float).reshape(len(pose), -1)[:, 0]
    vel = np.zeros_like(pose)
    if scene.dof == "translation":
        d = scene.slide_axis
        vel[:, 0], vel[:, 1] = v * d[0], v * d[1]
    else:
        c = -np.array(scene.grasp.patch.center)
        th0 = scene.q0[2]
        cs, sn = math.cos(th0), math.sin(th0)
        pivot = np.array(scene.q0[:2]) - np.array([cs * c[0] - sn * c[1], sn * c[0] + cs * c[1]])
        rho = pose[:, :2] - pivot
        vel[:, 0], vel[:, 1], vel[:, 2] = -v * rho[:, 1], v * rho[:, 0], v
    return pose, vel


def _with_dof(scene, dof):
    """The scene of dof="auto" with ``dof`` set, not validated again: the
    checks of the auto scene hold for every dof (a translation's and the
    planar model's are its own, a rotation's pin skips the patch face's)."""
    out = copy.copy(scene)
    object.__setattr__(out, "dof", dof)
    return out


def _simulate_auto(scene, t_end, dt, method, friction_solver, eps, rtol, atol):
    """dof="auto" (see :class:`exdex.Scene`): the 1-DoF models in the order
    the motion suggests (a turning gripper: rotation first), each certified
    as it runs and ending where its certificate fails, the one that holds
    longest, then the planar model from where it fails."""
    opts = dict(friction_solver=friction_solver, eps=eps, rtol=rtol, atol=atol)
    order = ("rotation", "translation") if getattr(scene.motion, "rotation", False) else ("translation", "rotation")
    best = None     # (valid_until, dof, method, result, its core spec)
    why_not = []
    for dof in order:
        sc = _with_dof(scene, dof)
        m = resolve_method(sc, method)
        if m == "analytic" and _core.analytic_unsupported(sc.to_spec()) is not None:
            m = "event"
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            try:
                res, spec = _run(sc, t_end, dt, m, stop_at_failure=True, **opts)
            except ValueError as exc:   # e.g. stops the 1-DoF model cannot give way to
                why_not.append(f"the {dof} model does not apply ({exc})")
                continue
            except SolverError as exc:
                # a 1-DoF run that fails against the obstacles (e.g. the
                # rotation model's state leaving the finite range where an
                # obstacle presses on the pinned object): the planar model
                # decides
                if not scene.obstacles:
                    raise
                why_not.append(f"the {dof} model does not apply against the obstacles ({exc.args[0]})")
                continue
        c = res.certificate
        if c["holds"]:
            best = (t_end, dof, m, res, spec)
            break
        why_not.append(f"the {dof} model fails its certificate at t = {c['valid_until']:.6g} s "
                       f"(gauge {c['gauge']:.4g}, {'stuck' if c['stick'] else 'slipping'})")
        if best is None or c["valid_until"] > best[0]:
            best = (float(c["valid_until"]), dof, m, res, spec)
    pm = method if method in _PLANAR_METHODS else "event"
    if best is not None and best[3].certificate["holds"]:
        _, dof, m, res, spec = best
        res = dataclasses.replace(res, models=((dof, m, 0.0, float(res.t[-1]),
                                                f"the {dof} model's certificate holds to t_end"),))
        _warn_jumps(scene, _jumps(res.scene, spec), t_end)
        diagnostics.issue(diagnostics.findings(res))
        return res
    planar = _with_dof(scene, "planar")
    if best is None or best[0] <= 0.0:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", GripperJumpWarning)
            res = simulate(planar, t_end, dt, method=pm, **opts)
        _warn_jumps(scene, _jumps(planar, planar.to_spec(method=pm)), t_end)
        return dataclasses.replace(res, models=(("planar", pm, 0.0, float(res.t[-1]),
                                                 "; ".join(why_not) or "no 1-DoF model applies"),))
    # the 1-DoF run up to the switch: it ended there
    t_sw, dof, m, head, _ = best
    t_sw = float(head.t[-1])
    sc = _with_dof(scene, dof)
    pose, vel = _full_state(sc, head.q, head.v)
    # the planar scene from the switch: the head's last state, the motion and
    # the grip schedule shifted by t_sw (the state comes from a run of the
    # checked scene: the spec is edited, not a new Scene checked again)
    spec = planar.to_spec(method=pm, **opts)
    spec.update(q0=tuple(float(x) for x in pose[-1]), v0=tuple(float(x) for x in vel[-1]), motion_time_shift=t_sw)
    sched = scene.grasp.schedule
    if sched is not None:
        spec["grip_schedule"] = np.array([[t - t_sw for t in sched.times], sched.forces])
    rest = t_end - t_sw
    out = _core.simulate(spec, rest, min(dt, rest))
    st = dict(out["stats"])
    for k in ("steps", "stick_steps", "solver_iterations", "stop_iterations", "warnings", "impacts"):
        st[k] = st.get(k, 0) + head.stats.get(k, 0)
    st["min_gap"] = min(st.get("min_gap", math.inf), head.stats.get("min_gap", math.inf))
    for k in ("first_warning_t", "max_impulse_t"):
        if st.get(k) is not None:
            st[k] = st[k] + t_sw
    res = Result(t=np.concatenate([head.t, t_sw + out["t"][1:]]), q=np.concatenate([pose, out["q"][1:]]),
                 v=np.concatenate([vel, out["v"][1:]]), wrench=np.concatenate([head.wrench, out["wrench"][1:]]),
                 stick=np.concatenate([head.stick, out["stick"][1:]]),
                 stop_force=np.concatenate([head.stop_force, out["stop_force"][1:]]), stats=st, scene=planar,
                 method=pm, friction_solver=friction_solver, dt=dt,
                 models=((dof, m, 0.0, float(t_sw), f"the {dof} model's certificate holds to t = {t_sw:.6g} s"),
                         ("planar", pm, float(t_sw), float(t_end), "; ".join(why_not))))
    _warn_jumps(scene, _jumps(planar, planar.to_spec(method=pm)), t_end)
    diagnostics.issue(diagnostics.findings(res))
    return res


def reduction_fails_at(scene: Scene, t_end: float, dt: float, method: Method = "auto",
                       **options: Any) -> Optional[float]:
    """Where the reduction of a translation or rotation scene fails over
    [0, t_end]: :attr:`Result.reduction_valid_until` of its run (which
    issues the :class:`exdex.ReductionWarning`), or None when it holds and
    for planar scenes. Plans, sequences and fits record it for what they
    return."""
    if scene.dof == "planar":
        return None
    res = simulate(scene, t_end, dt, method=method, **options)
    c = res.certificate
    return None if c is None or c["holds"] else float(c["valid_until"])


def resolve_method(scene, method):
    """The method a name stands for on ``scene``: ``"auto"`` is ``"analytic"``
    where the analytic method solves the scene (1-DoF, no stops, a
    piecewise-constant drive), else ``"event"``; other names stand for
    themselves."""
    if method != "auto":
        return method
    if not isinstance(scene, Scene):
        raise TypeError(f"scene must be an exdex.Scene, got {type(scene).__name__}")
    return "analytic" if _core.analytic_unsupported(scene.to_spec()) is None else "event"


def scene_spec(scene, method, friction_solver, eps, rtol, atol):
    if not isinstance(scene, Scene):
        raise TypeError(f"scene must be an exdex.Scene, got {type(scene).__name__}")
    if method not in METHODS:
        raise ValueError(f"method must be one of {sorted(METHODS) + ['auto']}, got {method!r}")
    if method == "analytic":
        why = _core.analytic_unsupported(scene.to_spec())
        if why is not None:
            raise ValueError(f"method='analytic' cannot solve this scene: {why}; use method='event' "
                             "(or 'auto', which picks the analytic method where it applies)")
    if friction_solver not in SOLVERS:
        raise ValueError(f"friction_solver must be one of {sorted(SOLVERS)}, got {friction_solver!r}")
    eps = _real(eps, "eps", low=0.0, low_open=True)
    rtol = _real(rtol, "rtol", low=0.0, low_open=True)
    atol = _real(atol, "atol", low=0.0, low_open=True)
    scene.check_stops()
    scene.check_motion()
    return scene.to_spec(method=method, friction_solver=friction_solver, eps=eps, rtol=rtol, atol=atol)


def _cert_load(c):
    if c is not None and "load" in c:
        c = dict(c, load=tuple(c["load"]))
    return c


def result_from_core(out, scene, method, friction_solver, dt):
    return Result(t=out["t"], q=out["q"], v=out["v"], wrench=out["wrench"], stick=out["stick"],
                  stop_force=out["stop_force"], stats=out["stats"], scene=scene, method=method,
                  friction_solver=friction_solver, dt=dt, certificate=out.get("certificate"))

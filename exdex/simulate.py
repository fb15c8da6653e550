"""exdex.simulate: one whole trajectory computed in C, returned as NumPy arrays."""
from __future__ import annotations

import math
import numbers
from dataclasses import dataclass, field

import numpy as np

from exdex import _core, diagnostics
from exdex.diagnostics import PhysicsWarning
from exdex.scene import METHODS, SOLVERS, Scene, _real

__all__ = ["Result", "simulate", "SolverError", "PhysicsWarning"]

SolverError = _core.SolverError


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
        sample (row 0 is zero).
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
        None: none). ``stop_force`` shows an impact as its impulse divided by the
        step.
    scene, method, friction_solver, dt : what produced it.
    """

    t: np.ndarray
    q: np.ndarray
    v: np.ndarray
    wrench: np.ndarray
    stick: np.ndarray
    stop_force: np.ndarray
    stats: dict
    scene: Scene = None
    method: str = "implicit"
    friction_solver: str = "scalar"
    dt: float = float("nan")

    @property
    def displacement(self):
        """(n, ndof) coordinates relative to the initial ones, q - q[0]."""
        return self.q - self.q[0]

    @property
    def pose(self):
        """(n, 3) full planar pose (x, y, theta) of C in B, whatever the scene's dof."""
        return diagnostics.poses(self.scene, self.q)

    def plot(self, ax=None, label=None, stick_shading=True):
        """Plot the displacement of each free coordinate against time.

        Translations in mm, rotations in degrees; steps where the object stuck
        to the plates are shaded. Returns the matplotlib Axes (a new figure
        when ``ax`` is None).
        """
        from exdex._optional import pyplot

        plt = pyplot("Result.plot()")
        if ax is None:
            _, ax = plt.subplots(figsize=(6, 3.5))
        names = self.scene.coordinate_names if self.scene is not None else tuple(f"q{i}" for i in range(self.q.shape[1]))
        for i, name in enumerate(names):
            scale, unit = (180 / math.pi, "deg") if name == "theta" else (1e3, "mm")
            lab = f"{label} {name}" if label else name
            ax.plot(self.t, scale * self.displacement[:, i], label=f"{lab} [{unit}]")
        if stick_shading and self.stick.any():
            ax.fill_between(self.t, 0, 1, where=self.stick, transform=ax.get_xaxis_transform(), color="0.9",
                            step="post", label="stick", zorder=0)
        ax.set_xlabel("time [s]")
        ax.set_ylabel("displacement relative to the gripper")
        ax.legend(loc="best", fontsize="small")
        return ax

    def drift_after(self, t0):
        """Largest |v| over samples at t >= t0 (0.0 means exactly still)."""
        sel = self.t >= t0
        return float(np.max(np.abs(self.v[sel]))) if np.any(sel) else 0.0


def simulate(scene, t_end, dt=1e-3, method="implicit", friction_solver="scalar", eps=1e-4,
             rtol=1e-8, atol=1e-10):
    """Simulate the object in the moving gripper from t = 0 to ``t_end``.

    Parameters
    ----------
    scene : exdex.Scene
    t_end : float
        End time [s], >= dt.
    dt : float
        Time step [s], > 0. Steps of dt; the last one is shortened to end
        exactly at t_end.
    method : {"implicit", "event", "regularised", "explicit"}
        "implicit" (default): Moreau's midpoint time stepping with the
        maximum-dissipation friction solve (paper Eq. 6) at every step of dt;
        exact stick; first order in dt where stick/slip switches fall inside
        a step.
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
        "explicit": explicit Coulomb friction -mu N E^2 u / |E u| (0 at u = 0)
        with symplectic Euler steps of dt, the naive baseline. Never sticks:
        under a load |Q| < mu N the velocity chatters in a band of width
        2 dt mu N / M about 0 and the object creeps at dt Q / M on average.
        Every method handles stops in every scene (planar: plastic
        frictionless impacts, unilateral contact with the stop force from the
        constraint acceleration; "event" also rests exactly against stops).
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

    Warns
    -----
    exdex.PhysicsWarning
        When the result leaves the model's assumptions (the object slides
        beyond the pad, the pads leave the body outline, impacts on stops,
        solver warnings in ``stats``): see :mod:`exdex.diagnostics`.
    """
    dt, t_end = _check_times(t_end, dt)
    spec = _spec(scene, method, friction_solver, eps, rtol, atol)
    out = _core.simulate(spec, t_end, dt)
    res = _result(out, scene, method, friction_solver, dt)
    diagnostics.issue(diagnostics.findings(res))
    return res


def _check_times(t_end, dt):
    """(dt, t_end) as floats, or a ValueError / TypeError naming the bad one."""
    dt = _real(dt, "dt", low=0.0, low_open=True)
    t_end = _real(t_end, "t_end", low=0.0, low_open=True)
    if dt > t_end:
        raise ValueError(f"dt must be <= t_end: got dt = {dt:g} s and t_end = {t_end:g} s "
                         "(dt is the output step, t_end the end time)")
    if t_end / dt > 1e9:
        raise ValueError(f"t_end / dt must be at most 1e9 steps, got {t_end / dt:.3g}")
    return dt, t_end


def _spec(scene, method, friction_solver, eps, rtol, atol):
    if not isinstance(scene, Scene):
        raise TypeError(f"scene must be an exdex.Scene, got {type(scene).__name__}")
    if method not in METHODS:
        raise ValueError(f"method must be one of {sorted(METHODS)}, got {method!r}")
    if friction_solver not in SOLVERS:
        raise ValueError(f"friction_solver must be one of {sorted(SOLVERS)}, got {friction_solver!r}")
    eps = _real(eps, "eps", low=0.0, low_open=True)
    rtol = _real(rtol, "rtol", low=0.0, low_open=True)
    atol = _real(atol, "atol", low=0.0, low_open=True)
    return scene.to_spec(method=method, friction_solver=friction_solver, eps=eps, rtol=rtol, atol=atol)


def _result(out, scene, method, friction_solver, dt):
    return Result(t=out["t"], q=out["q"], v=out["v"], wrench=out["wrench"], stick=out["stick"],
                  stop_force=out["stop_force"], stats=out["stats"], scene=scene, method=method,
                  friction_solver=friction_solver, dt=dt)


class Model:
    """A scene compiled once in C and run many times.

    ``exdex.simulate(scene, t_end, dt, ...)`` converts the scene and builds
    the C model on every call; a ``Model`` does that once, so loops that
    re-run one scene (optimisation, learning, parameter studies over t_end
    or dt, benchmarks) pay only for the integration. The arguments are those
    of :func:`exdex.simulate`; the model is immutable and may be run from
    several threads at once.

        >>> model = exdex.Model(scene, method="event")
        >>> res = model.simulate(t_end=1.5, dt=1e-3)      # an exdex.Result
        >>> q, v, stick = model.final(t_end=1.5, dt=1e-3)  # last sample only

    ``simulate`` returns the same :class:`Result` as :func:`exdex.simulate`
    (bit-identical). ``final`` keeps only the last sample (tuples of floats
    and the stick flag), without building the trajectory arrays.
    """

    __slots__ = ("scene", "method", "friction_solver", "_model")

    def __init__(self, scene, method="implicit", friction_solver="scalar", eps=1e-4, rtol=1e-8, atol=1e-10):
        spec = _spec(scene, method, friction_solver, eps, rtol, atol)
        self.scene, self.method, self.friction_solver = scene, method, friction_solver
        self._model = _core.compile(spec)

    @property
    def ndof(self):
        """Number of free coordinates: 1 (translation or rotation) or 3 (planar)."""
        return self._model.ndof

    def simulate(self, t_end, dt=1e-3):
        """Run from t = 0 to ``t_end`` in steps of ``dt``: an :class:`exdex.Result`."""
        dt, t_end = _check_times(t_end, dt)
        res = _result(self._model.simulate(t_end, dt), self.scene, self.method, self.friction_solver, dt)
        diagnostics.issue(diagnostics.findings(res))
        return res

    def final(self, t_end, dt=1e-3):
        """Run like :meth:`simulate` and return only the last sample:
        ``(q, v, stick)`` with q, v tuples of ``ndof`` floats."""
        dt, t_end = _check_times(t_end, dt)
        return self._model.final(t_end, dt)

    def __repr__(self):
        return f"exdex.Model(ndof={self.ndof}, method={self.method!r}, friction_solver={self.friction_solver!r})"

"""exdex.Model and exdex.Stepper: a scene compiled once in C, run whole
(:class:`Model`) or advanced one step at a time, for feedback control
(:class:`Stepper`, made from a Model or a scene).

A controller reads the state after each step and chooses the next step's
grip force::

    >>> stepper = exdex.Stepper(scene, method="event")
    >>> for _ in range(1000):
    ...     state = stepper.step(1e-3, grip_force=controller(stepper.state))

Stepping n times with the same ``dt`` and the scene's own grip force
reproduces ``exdex.simulate(scene, n * dt, dt, method=...)`` bit for bit (the
same samples and solver statistics, the impacts included: the implicit and
explicit methods find those from the stop impulses of a few steps around
each, and ``stats`` after n steps counts them as a run ending there).
``save()`` and ``restore()`` branch a run: stepping on from a
restored snapshot repeats what the saved stepper did, bit for bit.

A step may also prescribe the gripper's pose at its end
(``step(dt, gripper=exdex.GripperPose(position, rotation, velocity,
omega))``): the gripper then moves over the step along the cubic
interpolation that :class:`GripperPose` states, in place of the scene's
motion, on that step and every later one.
"""
from __future__ import annotations

import math
import numbers
from dataclasses import dataclass
from typing import Any, Dict, Optional, Tuple, Union

import numpy as np
from numpy.typing import NDArray

from exdex import _core, diagnostics
from exdex._validate import array as _array, check_times as _check_times
from exdex.scene import Scene
from exdex._jumps import jumps as _jumps, warn_jumps as _warn_jumps
from exdex._obstacle_hint import reduced_obstacle_hint
from exdex.simulate import (FrictionSolver, Method, Result, SolverError, resolve_method, result_from_core,
                            scene_spec)

__all__ = ["Model", "Stepper", "StepperState", "StepperSnapshot", "GripperPose"]


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
    ``stepper()`` starts a run to advance step by step (:class:`exdex.Stepper`).
    """

    __slots__ = ("scene", "method", "friction_solver", "_model", "_jumps", "_spec")

    def __init__(self, scene: Scene, method: Method = "implicit", friction_solver: FrictionSolver = "scalar",
                 eps: float = 1e-4, rtol: float = 1e-8, atol: float = 1e-10) -> None:
        method = resolve_method(scene, method)
        spec = scene_spec(scene, method, friction_solver, eps, rtol, atol)
        self.scene, self.method, self.friction_solver = scene, method, friction_solver
        self._model = _core.compile(spec)
        self._jumps = _jumps(scene, spec)
        self._spec = spec   # for the message of a rotation run that cannot clear an obstacle

    @property
    def ndof(self) -> int:
        """Number of free coordinates: 1 (translation or rotation) or 3 (planar)."""
        return self._model.ndof

    def simulate(self, t_end: float, dt: float = 1e-3, certify: bool = True) -> Result:
        """Run from t = 0 to ``t_end`` in steps of ``dt``: an :class:`exdex.Result`
        (``certify`` as in :func:`exdex.simulate`)."""
        dt, t_end = _check_times(t_end, dt)
        try:
            out = self._model.simulate(t_end, dt, certify=bool(certify))
        except SolverError as exc:
            reduced_obstacle_hint(self.scene, self._spec, exc)
            raise
        _warn_jumps(self.scene, self._jumps, t_end)
        res = result_from_core(out, self.scene, self.method, self.friction_solver, dt)
        diagnostics.issue(diagnostics.findings(res))
        return res

    def final(self, t_end: float, dt: float = 1e-3,
              certify: bool = False) -> Tuple[Tuple[float, ...], Tuple[float, ...], bool]:
        """Run like :meth:`simulate` and return only the last sample:
        ``(q, v, stick)`` with q, v tuples of ``ndof`` floats.

        certify : False (the default: the speed path that benchmarks, fits
            and plans time and call many times) returns the last sample
            unchecked. True checks a translation or rotation run's reduction
            along its samples first, as :meth:`simulate` does (its
            certificate), and warns where it fails
            (:class:`exdex.ReductionWarning`); the sample returned is the
            same."""
        dt, t_end = _check_times(t_end, dt)
        try:
            if not certify:
                out = self._model.final(t_end, dt)
                _warn_jumps(self.scene, self._jumps, t_end)
                return out
            q, v, stick, cert = self._model.final(t_end, dt, certify=True)
        except SolverError as exc:
            reduced_obstacle_hint(self.scene, self._spec, exc)
            raise
        _warn_jumps(self.scene, self._jumps, t_end)
        diagnostics.issue(diagnostics.reduction_findings(self.scene, cert))
        return q, v, stick

    def stepper(self) -> "Stepper":
        """A new :class:`exdex.Stepper` of this model at its initial state
        (runs of one model branch into each other with save / restore)."""
        return Stepper(self)

    def __repr__(self) -> str:
        return f"exdex.Model(ndof={self.ndof}, method={self.method!r}, friction_solver={self.friction_solver!r})"


@dataclass(frozen=True, eq=False)
class GripperPose:
    """The gripper's pose at the end of a step, for ``Stepper.step(dt,
    gripper=...)``: the pose of the gripper frame B in the world frame A
    and, optionally, its twist there.

    position : (3,) position of B's origin in A [m].
    rotation : (3, 3) R_AB, the columns B's axes in A (a rotation matrix:
        orthonormal with det +1, to 1e-9). Default: the identity.
    velocity : (3,) velocity of B's origin in A [m/s], or None: the step's
        mean velocity (position - p0) / dt, p0 the position at the step's
        start.
    omega : (3,) angular velocity of B in A [rad/s], or None: the constant
        angular velocity that turns the rotation at the step's start into
        ``rotation`` over dt (the shorter way).

    Over the step the gripper moves from its pose and twist at the step's
    start (the previous step's end, or the scene's motion at that time for
    the first step given a pose) to this pose and twist: its position and
    the quaternion of its rotation are each the cubic with those end values
    and rates (cubic Hermite interpolation, the quaternion normalised). The
    position, velocity, orientation and angular velocity are continuous
    from step to step; the accelerations are the cubic's, linear in time
    within a step for the position. Poses and twists sampled from a smooth
    motion at the step ends reproduce it with errors O(dt^4) in the pose,
    O(dt^3) in the twist and O(dt^2) in the accelerations (exactly, for a
    position cubic in time and a fixed rotation). Without the twist (the
    secants) the velocity lags the motion's by about dt / 2: first order.
    """

    position: Any
    rotation: Any = ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))
    velocity: Any = None
    omega: Any = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "position", _array(self.position, "GripperPose.position", (3,)))
        R = _array(self.rotation, "GripperPose.rotation", (3, 3))
        if not (np.max(np.abs(R @ R.T - np.eye(3))) <= 1e-9 and abs(np.linalg.det(R) - 1.0) <= 1e-9):
            raise ValueError("GripperPose.rotation must be a rotation matrix (orthonormal with det +1, to 1e-9)")
        object.__setattr__(self, "rotation", R)
        for name in ("velocity", "omega"):
            value = getattr(self, name)
            if value is not None:
                object.__setattr__(self, name, _array(value, f"GripperPose.{name}", (3,)))

    def _core(self) -> Any:
        return (tuple(self.rotation.ravel()), tuple(self.position),
                None if self.velocity is None else tuple(self.velocity),
                None if self.omega is None else tuple(self.omega))


@dataclass(frozen=True, eq=False)
class StepperState:
    """The state of a :class:`Stepper` after its last step.

    t : time [s].
    q, v : (ndof,) coordinates and their rates (as :class:`exdex.Result`).
    stick : True if the last step ended exactly at rest relative to the
        gripper (before the first step: the initial velocity is zero).
    wrench : (3,) plate friction (f_x, f_y, m_z) on the object in B at the
        centre of pressure, mean over the last step [N, N, N m] (before the
        first step: the wrench holding the object at t = 0, as row 0 of
        :attr:`exdex.Result.wrench`).
    stop_force : (n_stops,) mean normal force of each stop over the last
        step [N].
    grip_force : the last step's grip force [N per finger], or None (the
        scene's own force or schedule).
    steps : steps taken.
    """

    t: float
    q: NDArray[np.float64]
    v: NDArray[np.float64]
    stick: bool
    wrench: NDArray[np.float64]
    stop_force: NDArray[np.float64]
    grip_force: Optional[float]
    steps: int


class StepperSnapshot:
    """An opaque copy of a :class:`Stepper`'s whole state (``Stepper.save``),
    valid for the steppers of the same compiled model."""

    __slots__ = ("_data", "_model", "t", "_posed")

    def __init__(self, data: bytes, model: Any, t: float, posed: bool = False) -> None:
        self._data, self._model, self.t, self._posed = data, model, t, posed

    def __repr__(self) -> str:
        return f"exdex.StepperSnapshot(t={self.t!r})"


class Stepper:
    """A run of a scene advanced step by step with a grip force per step.

    Parameters
    ----------
    scene : exdex.Scene or exdex.Model
        The scene (compiled here with ``method`` and the options, which are
        those of :func:`exdex.simulate`), or a compiled :class:`exdex.Model`
        (its method and options; then pass no others).
    method, friction_solver, eps, rtol, atol
        As :func:`exdex.simulate` (``"auto"`` included).

    Grip force: ``step(dt, grip_force=F)`` holds F [N per finger] constant
    over the step: the friction capacity mu * fingers * F replaces the
    scene's grip force (or schedule) for that step; ``grip_force=None``
    takes the scene's own. A change between steps is a jump of the capacity
    at the step boundary (the event method decides stick or slip again
    there). The model's scales and tolerances stay those of the scene's
    grip. The GIL is released while a step runs; one stepper must not be
    stepped from two threads at once (a RuntimeError says so), distinct
    steppers may run in parallel.

    Certified: a translation or rotation stepper checks its reduction
    after every step, as :func:`exdex.simulate` does along its samples, with
    each step's own grip force and gripper motion (:attr:`certificate`:
    the dict of :attr:`exdex.Result.certificate`, the same as
    :func:`exdex.simulate`'s over the same steps; :attr:`reduction_valid_until`).
    At the first step whose check fails it warns once
    (:class:`exdex.ReductionWarning`, naming the time, the coordinate, the
    load and the margin) and stops checking. A stepper given gripper poses
    is checked against the step's interpolated motion.
    """

    __slots__ = ("model", "_s", "_t", "_posed", "_pads", "_warned")

    def __init__(self, scene: Union[Scene, Model], method: Optional[Method] = None,
                 friction_solver: Optional[FrictionSolver] = None, eps: Optional[float] = None,
                 rtol: Optional[float] = None, atol: Optional[float] = None) -> None:
        options: Dict[str, Any] = dict(method=method, friction_solver=friction_solver, eps=eps, rtol=rtol, atol=atol)
        given = {k: v for k, v in options.items() if v is not None}
        if isinstance(scene, Model):
            if given:
                raise TypeError(f"Stepper(model) takes the model's own method and options; got {sorted(given)}")
            self.model = scene
        elif isinstance(scene, Scene):
            self.model = Model(scene, **given)
        else:
            raise TypeError(f"scene must be an exdex.Scene or an exdex.Model, got {type(scene).__name__}")
        self._s = self.model._model.stepper()
        self._t = 0.0   # time reached (the last step's end)
        self._posed = False   # a step gave the gripper pose (every later one must)
        self._pads = self.model.scene.grasp.pad is not None   # pads: warn when the grasp is lost
        self._warned = False   # the certificate's failure was warned

    @property
    def scene(self) -> Scene:
        return self.model.scene

    @property
    def method(self) -> str:
        return self.model.method

    @property
    def ndof(self) -> int:
        return self.model.ndof

    def step(self, dt: float, grip_force: Optional[float] = None,
             gripper: Optional[GripperPose] = None) -> StepperState:
        """Advance by ``dt`` [s] (> 0) with this step's ``grip_force`` [N per
        finger] (>= 0; None: the scene's own) and, optionally, the gripper's
        pose at the step's end, and return the new state.

        Parameters
        ----------
        dt : step [s], > 0.
        grip_force : this step's grip force [N per finger], >= 0, or None.
        gripper : an :class:`exdex.GripperPose`, the gripper's pose (and
            twist) at t + dt, or None: the scene's motion. The gripper moves
            over the step by the interpolation :class:`GripperPose` states,
            in place of the scene's motion (whose switching times and
            velocity jumps then no longer apply). Once a step gives a pose,
            every later step must. Not with the analytic method (its phases
            are the scene's motion).

        Steps of one ``dt`` end on the grid t_base + k dt (t_base where dt
        last changed), as :func:`exdex.simulate`'s samples. Raises
        ValueError / TypeError naming the argument, and
        :class:`exdex.SolverError` as :func:`exdex.simulate` does (after
        which only :meth:`restore` revives the stepper). Warns
        :class:`exdex.GripperJumpWarning` for a gripper velocity jump of the
        scene's motion inside the step.
        """
        if isinstance(dt, bool) or not isinstance(dt, numbers.Real):
            raise TypeError(f"dt must be a real number [s], got {type(dt).__name__}")
        dt = float(dt)
        if not (math.isfinite(dt) and dt > 0.0):
            raise ValueError(f"dt must be finite and > 0 [s], got {dt!r}")
        if grip_force is not None:
            if isinstance(grip_force, bool) or not isinstance(grip_force, numbers.Real):
                raise TypeError(f"grip_force must be a real number [N] or None, got {type(grip_force).__name__}")
            grip_force = float(grip_force)
            if not (math.isfinite(grip_force) and grip_force >= 0.0):
                raise ValueError(f"grip_force must be finite and >= 0 [N per finger] (or None), got {grip_force!r}")
        if gripper is not None:
            if not isinstance(gripper, GripperPose):
                raise TypeError(f"gripper must be an exdex.GripperPose or None, got {type(gripper).__name__}")
            if self.method == "analytic":
                raise ValueError("gripper poses need method 'implicit', 'event', 'regularised' or 'explicit': "
                                 "the analytic method follows the scene's motion")
        elif self._posed:
            raise ValueError("gripper must be given on every step after the first step that gives it "
                             "(an exdex.GripperPose: the scene's motion no longer describes the gripper)")
        try:
            self._s.step(dt, grip_force, None if gripper is None else gripper._core())
        except SolverError as exc:
            # the pivot's place is known from the scene's motion only
            posed = self._posed or gripper is not None
            reduced_obstacle_hint(self.model.scene, self.model._spec, exc, motion_known=not posed)
            raise
        state = self.state
        if self._pads:
            tl = self._s.stats().get("grasp_lost_t")
            if tl is not None:
                diagnostics.issue(diagnostics.stats_findings({"grasp_lost_t": tl}))
        if not self._warned and not self._s.holds():
            self._warned = True
            diagnostics.issue(diagnostics.reduction_findings(self.model.scene, self._s.certificate()))
        if gripper is not None:
            self._posed = True
        elif self.model._jumps:
            _warn_jumps(self.model.scene, [j for j in self.model._jumps if self._t < j[0]], state.t)
        self._t = state.t
        return state

    @property
    def state(self) -> StepperState:
        """The state after the last step (a :class:`StepperState`)."""
        t, q, v, stick, wrench, sf, grip, steps = self._s.state()
        return StepperState(t=t, q=np.array(q), v=np.array(v), stick=stick, wrench=np.array(wrench),
                            stop_force=np.array(sf), grip_force=grip, steps=steps)

    @property
    def t(self) -> float:
        """Time reached [s]."""
        return float(self._s.state()[0])

    @property
    def certificate(self) -> Optional[Dict[str, Any]]:
        """The certificate of a translation or rotation stepper's steps so
        far (the keys of :attr:`exdex.Result.certificate`: ``holds``,
        ``valid_until`` and, where it failed, ``first_bad`` (the step), ``stick``,
        ``load``, ``capacity``, ``gauge``, ``coordinate``); None for a planar one."""
        return self._s.certificate()

    @property
    def reduction_valid_until(self) -> float:
        """How long the reduction held [s]: the time reached while it holds,
        else the last time known to hold (planar steppers: the time reached)."""
        cert = self._s.certificate()
        return self.t if cert is None else float(cert["valid_until"])

    @property
    def stats(self) -> Dict[str, Any]:
        """Solver statistics over the steps taken (the keys of
        :attr:`exdex.Result.stats`)."""
        return self._s.stats()

    def save(self) -> StepperSnapshot:
        """A snapshot of the whole state, to :meth:`restore` later."""
        return StepperSnapshot(self._s.save(), self.model._model, self.t, self._posed)

    def restore(self, state: StepperSnapshot) -> None:
        """Return to a snapshot saved by a stepper of the same model (this
        one or another made from the same :class:`exdex.Model`)."""
        if not isinstance(state, StepperSnapshot):
            raise TypeError(f"state must be an exdex.StepperSnapshot (from Stepper.save()), got {type(state).__name__}")
        if state._model is not self.model._model:
            raise ValueError("state was saved by a stepper of another model: pass Stepper(model) the same "
                             "exdex.Model to branch runs")
        self._s.restore(state._data)
        self._t = self.t
        self._posed = state._posed
        cert = self._s.certificate()
        self._warned = cert is not None and not cert["holds"]

    def run(self, dt: float, grip_forces: Any) -> Dict[str, NDArray[Any]]:
        """Take ``len(grip_forces)`` steps of ``dt``, step i with grip force
        ``grip_forces[i]`` (NaN: the scene's own), and return the arrays
        ``t``, ``q``, ``v``, ``stick``, ``wrench``, ``stop_force`` of the
        states after each step (an open-loop schedule, e.g. to replay a
        controller's forces)."""
        forces = np.asarray(grip_forces, dtype=float).ravel()
        rows = [self.step(dt, None if math.isnan(F) else float(F)) for F in forces]
        return dict(t=np.array([r.t for r in rows]), q=np.array([r.q for r in rows]),
                    v=np.array([r.v for r in rows]), stick=np.array([r.stick for r in rows]),
                    wrench=np.array([r.wrench for r in rows]),
                    stop_force=np.array([r.stop_force for r in rows]).reshape(len(rows), -1))

    def __repr__(self) -> str:
        return f"exdex.Stepper(method={self.method!r}, t={self.t!r})"

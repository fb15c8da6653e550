"""exdex.Stepper: a run advanced one step at a time, for feedback control.

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
"""
from __future__ import annotations

import math
import numbers
from dataclasses import dataclass
from typing import Any, Dict, Optional, Union

import numpy as np
from numpy.typing import NDArray

from exdex import _core
from exdex.scene import Scene
from exdex.simulate import FrictionSolver, Method, Model, _warn_jumps

__all__ = ["Stepper", "StepperState", "StepperSnapshot"]


@dataclass(frozen=True, eq=False)
class StepperState:
    """The state of a :class:`Stepper` after its last step.

    t : time [s].
    q, v : (ndof,) coordinates and their rates (as :class:`exdex.Result`).
    stick : True if the last step ended exactly at rest relative to the
        gripper (before the first step: the initial velocity is zero).
    wrench : (3,) plate friction (f_x, f_y, m_z) on the object in B at the
        centre of pressure, mean over the last step [N, N, N m] (zero before
        the first step).
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

    __slots__ = ("_data", "_model", "t")

    def __init__(self, data: bytes, model: Any, t: float) -> None:
        self._data, self._model, self.t = data, model, t

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
    """

    __slots__ = ("model", "_s", "_t")

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

    @property
    def scene(self) -> Scene:
        return self.model.scene

    @property
    def method(self) -> str:
        return self.model.method

    @property
    def ndof(self) -> int:
        return self.model.ndof

    def step(self, dt: float, grip_force: Optional[float] = None) -> StepperState:
        """Advance by ``dt`` [s] (> 0) with this step's ``grip_force`` [N per
        finger] (>= 0; None: the scene's own) and return the new state.

        Steps of one ``dt`` end on the grid t_base + k dt (t_base where dt
        last changed), as :func:`exdex.simulate`'s samples. Raises
        ValueError / TypeError naming the argument, and
        :class:`exdex.SolverError` as :func:`exdex.simulate` does (after
        which only :meth:`restore` revives the stepper). Warns
        :class:`exdex.GripperJumpWarning` for a gripper velocity jump inside
        the step.
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
        self._s.step(dt, grip_force)
        state = self.state
        if self.model._jumps:
            _warn_jumps(self.model.scene, [j for j in self.model._jumps if self._t < j[0]], state.t, stacklevel=3)
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
    def stats(self) -> Dict[str, Any]:
        """Solver statistics over the steps taken (the keys of
        :attr:`exdex.Result.stats`)."""
        return self._s.stats()

    def save(self) -> StepperSnapshot:
        """A snapshot of the whole state, to :meth:`restore` later."""
        return StepperSnapshot(self._s.save(), self.model._model, self.t)

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

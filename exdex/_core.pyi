# Type stub of the C extension exdex._core (exdex/_coremodule.c).
from typing import Any, Literal, Mapping, Sequence, overload

import numpy as np
from numpy.typing import ArrayLike, NDArray

MAX_VERTICES: int
MAX_PAD_VERTICES: int
MAX_STOPS: int
MAX_OBSTACLES: int
MAX_FACES: int
OBSTACLE_POLYTOPE: int
OBSTACLE_CYLINDER: int
STATUS_OK: int
STATUS_EINVAL: int
STATUS_ENOMEM: int
STATUS_ENOCONV: int
STATUS_ENONFINITE: int
DOF_TRANSLATION: int
DOF_ROTATION: int
DOF_PLANAR: int
METHOD_IMPLICIT: int
METHOD_EVENT: int
METHOD_REGULARISED: int
METHOD_EXPLICIT: int
METHOD_ANALYTIC: int
SOLVER_SCALAR: int
SOLVER_BRENT: int
SOLVER_MULTIROOT: int
MOTION_REST: int
MOTION_ASYMMETRIC: int
MOTION_TRAPEZOID: int
MOTION_SAMPLED: int
MOTION_SHAKE: int
MOTION_CHAIN: int
MOTION_MAX_PIECES: int
GRIP_LINEAR: int
GRIP_CUBIC: int
GRIP_STEP: int
MAX_GRIP_POINTS: int

class SolverError(RuntimeError):
    status: int
    index: int
    time: float | None
    cause: str

class CompiledModel:
    @property
    def ndof(self) -> int: ...
    @property
    def n_stops(self) -> int: ...
    def simulate(self, t_end: float, dt: float, certify: bool = ..., every_sample: bool = ...,
                 stop_at_failure: bool = ...) -> dict[str, Any]: ...
    @overload
    def final(self, t_end: float, dt: float,
              certify: Literal[False] = ...) -> tuple[tuple[float, ...], tuple[float, ...], bool]: ...
    @overload
    def final(self, t_end: float, dt: float, certify: Literal[True]
              ) -> tuple[tuple[float, ...], tuple[float, ...], bool, dict[str, Any] | None]: ...
    def stepper(self) -> CompiledStepper: ...

class CompiledStepper:
    def step(self, dt: float, grip_force: float | None = ...,
             gripper: tuple[Sequence[float], Sequence[float], Sequence[float] | None, Sequence[float] | None]
             | None = ...) -> None: ...
    def state(self) -> tuple[float, tuple[float, ...], tuple[float, ...], bool, tuple[float, float, float],
                             tuple[float, ...], float | None, int]: ...
    def stats(self) -> dict[str, Any]: ...
    def certificate(self) -> dict[str, Any] | None: ...
    def holds(self) -> bool: ...
    def save(self) -> bytes: ...
    def restore(self, snapshot: bytes, /) -> None: ...

def simulate(spec: Mapping[str, Any], t_end: float, dt: float, certify: bool = ...,
             stop_at_failure: bool = ...) -> dict[str, Any]: ...
def compile(spec: Mapping[str, Any], /) -> CompiledModel: ...
def analytic_unsupported(spec: Mapping[str, Any], /) -> str | None: ...
def simulate_batch(specs: Mapping[str, Any] | Sequence[Mapping[str, Any]], t_end: float, dt: float, threads: int = ...,
                   record: str = ..., vary: Mapping[str, ArrayLike] | None = ...,
                   check_signals: bool = ...) -> dict[str, Any]: ...
def motion_eval(spec: Mapping[str, Any], t: ArrayLike) -> dict[str, NDArray[np.float64]]: ...
def grip_eval(spec: Mapping[str, Any], t: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64]]: ...
def friction_solve(W: ArrayLike, b: ArrayLike, e: ArrayLike, cap: float, solver: int = ...) -> Any: ...
def obstacle_section(obstacle: Mapping[str, Any], R: ArrayLike, p: ArrayLike, /) -> Any: ...
def er_disc(radius: float, /) -> float: ...
def er_rectangle(half_a: float, half_b: float, /) -> float: ...
def limit_surface(surface: int, e_r: float, vertices: Any, radius: float, what: int,
                  vec: tuple[float, float, float], /) -> tuple[tuple[float, float, float], float]: ...
def pad_region(spec: Mapping[str, Any], q: ArrayLike, /) -> dict[str, Any]: ...
def n_samples(t_end: float, dt: float, /) -> int: ...
def __getattr__(name: str) -> Any: ...

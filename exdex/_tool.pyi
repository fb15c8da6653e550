# Type stub of the C extension exdex._tool (exdex/_toolmodule.c).
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from exdex._core import SolverError as SolverError

MAX_VERTICES: int
MAX_ROWS: int
VOLUME_EXACT: int
VOLUME_GRID: int
VOLUME_QMC: int
TOOL_MODEL_CONTACT: int
TOOL_MODEL_PAPER: int

#: the same class as exdex._core.SolverError
ConvergenceError = SolverError

def volumes(rows: ArrayLike, lo: ArrayLike, hi: ArrayLike, method: str = ..., grid_n: int = ...,
            qmc_points: int = ..., qmc_shifts: int = ..., seed: int = ...) -> Any: ...
def paper_rows(phi: ArrayLike, theta: ArrayLike) -> NDArray[np.float64]: ...
def contact_rows(points: ArrayLike, normals: ArrayLike, mu: float = ...) -> NDArray[np.float64]: ...
def tool_rows(shapes: Any, phi: ArrayLike, lo: ArrayLike, hi: ArrayLike, alpha1: Any, alpha2: Any,
              s: Any = ..., mu: float = ..., push: Any = ..., model: str = ..., shape: Any = ...) -> Any: ...
def tool_volumes(shapes: Any, phi: ArrayLike, lo: ArrayLike, hi: ArrayLike, tools: Any, **kwargs: Any) -> Any: ...
def optimise_theta(shapes: Any, phi: ArrayLike, lo: ArrayLike, hi: ArrayLike, theta_lo: float, theta_hi: float,
                   **kwargs: Any) -> Any: ...
def optimise_tool(shapes: Any, phi: ArrayLike, lo: ArrayLike, hi: ArrayLike, x0: ArrayLike, **kwargs: Any) -> Any: ...
def __getattr__(name: str) -> Any: ...

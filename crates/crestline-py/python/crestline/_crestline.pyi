# The extension module; the package's functions check every argument before
# calling these.
from typing import Any, Optional

import numpy as np
import numpy.typing as npt

F64 = npt.NDArray[np.float64]
I64 = npt.NDArray[np.int64]

def read_mesh(path: str) -> tuple[F64, I64, str]: ...
def curvature(vertices: F64, faces: I64, estimator: str) -> dict[str, Any]: ...
def ridges(
    vertices: F64,
    faces: I64,
    estimator: str,
    smooth_steps: int,
    smooth_time: float,
    threshold: float,
    field: Optional[tuple[F64, F64, F64, F64, F64, npt.NDArray[np.bool_]]] = None,
    progress: Optional[Any] = None,
) -> list[dict[str, Any]]: ...
def morse(
    vertices: F64, faces: I64, estimator: str, keep_saddles: int, indicator: str, values: Optional[F64] = None
) -> list[dict[str, Any]]: ...
def draw(
    vertices: F64,
    faces: I64,
    lines: list[tuple[str, bool, F64]],
    azimuth: float,
    elevation: float,
    width: int,
    height: int,
    silhouettes: bool,
    png: bool,
) -> tuple[str, Optional[bytes]]: ...

from os import PathLike
from typing import Any, Literal, Optional, TypedDict, Union

import numpy as np
import numpy.typing as npt

class Error(Exception): ...

Estimator = Literal["shape-operator", "jet-fit"]

class Curvature(TypedDict):
    k_max: npt.NDArray[np.float64]
    k_min: npt.NDArray[np.float64]
    d_max: npt.NDArray[np.float64]
    d_min: npt.NDArray[np.float64]
    normal: npt.NDArray[np.float64]
    unreliable: npt.NDArray[np.bool_]

class Line(TypedDict):
    kind: str
    closed: bool
    strength: float
    points: npt.NDArray[np.float64]
    values: dict[str, npt.NDArray[np.float64]]

def read_mesh(
    path: Union[str, PathLike[str]],
) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.int64], dict[str, int]]: ...
def curvature(
    vertices: Any, faces: Optional[npt.ArrayLike] = ..., estimator: Estimator = ...
) -> Curvature: ...
def ridges(
    vertices: Any,
    faces: Optional[npt.ArrayLike] = ...,
    estimator: Estimator = ...,
    smooth_steps: int = ...,
    smooth_time: float = ...,
    threshold: float = ...,
) -> list[Line]: ...
def morse(
    vertices: Any,
    faces: Optional[npt.ArrayLike] = ...,
    values: Optional[npt.ArrayLike] = ...,
    estimator: Estimator = ...,
    keep_saddles: int = ...,
) -> list[Line]: ...

# The extension module; the package's functions check every argument before
# calling these.
from typing import Any, Optional

import numpy as np
import numpy.typing as npt

F64 = npt.NDArray[np.float64]
I64 = npt.NDArray[np.int64]
LineParts = tuple[str, bool, float, F64, list[tuple[str, list[float]]]]

def read_mesh(path: str) -> tuple[F64, I64, str]: ...

class Mesh:
    def __init__(self, vertices: F64, faces: I64) -> None: ...
    def mean_edge_length(self) -> float: ...

def curvature(mesh: Mesh, options: str) -> dict[str, Any]: ...
def ridges(
    mesh: Mesh,
    options: str,
    weights: Optional[F64] = None,
    field: Optional[dict[str, Any]] = None,
    progress: Optional[Any] = None,
) -> list[dict[str, Any]]: ...
def mesh_landmarks(
    mesh: Mesh,
    ridges: str,
    options: str,
    weights: Optional[F64] = None,
    progress: Optional[Any] = None,
) -> str: ...
def morse(
    mesh: Mesh,
    options: str,
    values: Optional[F64] = None,
    field: Optional[dict[str, Any]] = None,
    progress: Optional[Any] = None,
) -> list[dict[str, Any]]: ...
def draw(
    mesh: Mesh,
    lines: Optional[list[LineParts]],
    options: str,
    png: bool,
    progress: Optional[Any] = None,
) -> tuple[str, Optional[bytes]]: ...
def view(
    mesh: Mesh,
    lines: Optional[list[LineParts]],
    options: str,
    title: str,
    progress: Optional[Any] = None,
) -> str: ...
def read_volume(path: str, series: Optional[str] = None) -> tuple[npt.NDArray[np.float32], F64, Optional[str]]: ...
def read_dicom(files: list[str], series: Optional[str] = None) -> tuple[npt.NDArray[np.float32], F64, Optional[str]]: ...
def isosurface(
    samples: npt.NDArray[np.float32], affine: F64, level: float, options: str, progress: Optional[Any] = None
) -> tuple[F64, I64]: ...
def crest_lines(
    samples: npt.NDArray[np.float32], affine: F64, level: float, options: str, progress: Optional[Any] = None
) -> list[dict[str, Any]]: ...
def crease_surface(
    samples: npt.NDArray[np.float32], affine: F64, options: str, progress: Optional[Any] = None
) -> dict[str, Any]: ...
def image_landmarks(
    samples: npt.NDArray[np.float32],
    affine: F64,
    level: float,
    crest: str,
    options: str,
    progress: Optional[Any] = None,
) -> str: ...
def write_landmarks(path: str, landmarks: str, declared: Optional[str], given: Optional[str]) -> None: ...
def write_lines(path: str, lines: list[LineParts], space: Optional[str] = None) -> None: ...
def write_line_labels(
    path: str, mesh: Mesh, lines: list[tuple[str, I64, F64]], structure: str
) -> None: ...
def write_mesh(path: str, vertices: F64, faces: I64, values: list[tuple[str, list[float]]], space: Optional[str]) -> None: ...
def read_vertex_values(path: str) -> list[float]: ...
def write_vertex_values(path: str, values: list[float], name: Optional[str], structure: str) -> None: ...
def voxel_size(affine: F64) -> float: ...
def write_transform(path: str, matrix: F64, space: str) -> None: ...
def lines_landmarks(lines: list[LineParts], unit: float, options: str) -> str: ...
def register_lines(
    fixed: F64, moving: F64, fixed_keys: F64, moving_keys: F64, options: str, progress: Optional[Any] = None
) -> dict[str, Any]: ...
def compare_files(
    a: str, b: str, transform_file: Optional[str] = None, transform_matrix: Optional[F64] = None,
    tolerance: Optional[str] = None,
) -> str: ...
def defaults() -> str: ...
def names() -> dict[str, list[str]]: ...

__version__: str

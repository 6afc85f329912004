"""Argument checks: every bad argument raises ``TypeError`` or ``ValueError``
naming it, before the library sees it."""

import math
import os
from typing import Any, Callable, Optional, Tuple, TypeVar

import numpy as np
import numpy.typing as npt

from ._jobs import NAMES

Vertices = npt.NDArray[np.float64]
Faces = npt.NDArray[np.int64]

T = TypeVar("T")


def file_path(path: Any, name: str = "path") -> str:
    """A path given as ``str``, ``bytes`` or :class:`os.PathLike`, as ``str`` (bytes
    that are not UTF-8 kept as the file system encodes them)."""
    try:
        return os.fsdecode(path)
    except TypeError:
        raise TypeError(f"{name}: expected a path (str, bytes or os.PathLike), got {type(path).__name__}") from None


def numeric(array: Any, name: str) -> Any:
    """``array`` as a numpy array of real numbers (booleans, integers or floats):
    complex numbers, strings and other objects raise ``TypeError`` naming it
    (numpy would drop an imaginary part or parse a string silently)."""
    a = np.asarray(array)
    if a.dtype.kind == "O":
        try:
            a = a.astype(np.float64)
        except (TypeError, ValueError) as e:
            raise TypeError(f"{name}: not an array of numbers ({e})") from None
    if a.dtype.kind not in "biuf":
        raise TypeError(f"{name}: expected real numbers, got an array of dtype {a.dtype}")
    return a


def mesh_object(mesh: Any) -> Optional[Tuple[Any, Any]]:
    """The vertex and face arrays of a mesh object of trimesh (``.vertices``,
    ``.faces``), pymeshlab (``vertex_matrix()``, ``face_matrix()``; a MeshSet
    gives its current mesh) or pyvista (a triangulated PolyData), else None."""
    if hasattr(mesh, "current_mesh") and callable(mesh.current_mesh):
        mesh = mesh.current_mesh()
    if callable(getattr(mesh, "vertex_matrix", None)) and callable(getattr(mesh, "face_matrix", None)):
        return mesh.vertex_matrix(), mesh.face_matrix()
    if hasattr(mesh, "points") and hasattr(mesh, "faces") and hasattr(mesh, "n_cells"):
        flat = np.asarray(mesh.faces)
        if flat.size and not (flat.size % 4 == 0 and (flat.reshape(-1, 4)[:, 0] == 3).all()):
            raise ValueError("vertices: the PolyData has faces that are not triangles (call .triangulate() first)")
        return mesh.points, flat.reshape(-1, 4)[:, 1:]
    if hasattr(mesh, "vertices") and hasattr(mesh, "faces"):
        return mesh.vertices, mesh.faces
    return None


def mesh_arrays(vertices: Any, faces: Any) -> Tuple[Vertices, Faces]:
    """The mesh arguments as contiguous float64 and int64 arrays, checked."""
    if faces is None:
        arrays = mesh_object(vertices)
        if arrays is None:
            raise TypeError(
                "faces: missing (pass vertices and faces, or a mesh object of trimesh, pymeshlab or pyvista)"
            )
        vertices, faces = arrays
    v = points(vertices, "vertices")
    f = np.asarray(faces)
    if f.dtype.kind not in "iu":
        raise TypeError(f"faces: expected integer vertex indices, got dtype {f.dtype}")
    if f.ndim != 2 or f.shape[1] != 3:
        raise ValueError(f"faces: expected shape (m, 3), got {f.shape}")
    # Checked in the given type, before the cast: uint64 2**64 - 1 would become -1.
    if f.size and (f.min() < 0 or f.max() >= len(v)):
        row = int(np.argmax(((f < 0) | (f >= len(v))).any(axis=1)))
        raise ValueError(f"faces: row {row} ({f[row].tolist()}) refers to a vertex outside 0..{len(v) - 1}")
    return v, np.ascontiguousarray(f, dtype=np.int64)


def points(array: Any, name: str) -> Vertices:
    """An (n, 3) array of finite numbers as contiguous float64."""
    try:
        p = np.ascontiguousarray(numeric(array, name), dtype=np.float64)
    except ValueError as e:
        raise TypeError(f"{name}: not an array of numbers ({e})") from None
    if p.ndim != 2 or p.shape[1] != 3:
        raise ValueError(f"{name}: expected shape (n, 3), got {p.shape}")
    if not np.isfinite(p).all():  # the row is only looked for when there is one
        row = int(np.argmax(~np.isfinite(p).all(axis=1)))
        raise ValueError(f"{name}: row {row} is not finite ({p[row].tolist()})")
    return p


def per_vertex(array: Any, name: str, count: int, columns: Optional[int] = None) -> npt.NDArray[np.float64]:
    """One finite float64 (or one row of ``columns``) per vertex."""
    try:
        a = np.ascontiguousarray(numeric(array, name), dtype=np.float64)
    except ValueError as e:
        raise TypeError(f"{name}: not an array of numbers ({e})") from None
    shape = (count,) if columns is None else (count, columns)
    if a.shape != shape:
        raise ValueError(f"{name}: expected shape {shape}, one per vertex, got {a.shape}")
    if not np.isfinite(a).all():
        raise ValueError(f"{name}: entry {int(np.argmax(~np.isfinite(a).reshape(count, -1).all(axis=1)))} is not finite")
    return a


def estimator_name(estimator: Any) -> str:
    if estimator not in NAMES["estimator"]:
        raise ValueError(f"estimator: expected one of {NAMES['estimator']} or a callable, got {estimator!r}")
    return str(estimator)


# The largest count the library takes (an unsigned 64-bit integer).
MAX_COUNT = 2**64 - 1


def count(value: Any, name: str, low: int, high: int = MAX_COUNT) -> int:
    """An integer in [low, high] (at most :data:`MAX_COUNT`)."""
    ok = isinstance(value, (int, np.integer)) and not isinstance(value, bool)
    if not ok or value < low or value > min(high, MAX_COUNT):
        raise ValueError(f"{name}: expected an integer from {low} to {min(high, MAX_COUNT)}, got {value!r}")
    return int(value)


def number(value: Any, name: str, low: float = 0.0, strict: bool = False) -> float:
    """A finite number ≥ low (> low if strict)."""
    ok = isinstance(value, (int, float, np.integer, np.floating)) and not isinstance(value, bool)
    if not ok or not math.isfinite(value) or value < low or (strict and value == low):
        relation = ">" if strict else "≥"
        raise ValueError(f"{name}: expected a finite number {relation} {low}, got {value!r}")
    return float(value)


def callback(value: Any, name: str) -> Any:
    if value is not None and not callable(value):
        raise TypeError(f"{name}: expected a callable or None, got {type(value).__name__}")
    return value


def pair(value: Any, name: str, check: Callable[[Any, str], T]) -> Tuple[T, T]:
    """Two values, each passing ``check``."""
    try:
        first, second = value
    except (TypeError, ValueError):
        raise ValueError(f"{name}: expected a pair of numbers, got {value!r}") from None
    return check(first, name), check(second, name)

"""A mesh checked and built once, for several calls on it."""

from __future__ import annotations

from typing import Any, Optional, Tuple

import numpy.typing as npt

from . import _crestline
from ._checks import Faces, Vertices, mesh_arrays


class Mesh:
    """A triangle mesh, its arrays checked and its half-edge structure built once.

    Every function that takes ``vertices`` and ``faces`` (or a mesh object of
    trimesh, pymeshlab or pyvista) checks the arrays and builds crestline's mesh
    from them at each call; ``Mesh(vertices, faces)`` does it once, and is then
    passed in their place (``crestline.curvature(mesh)``, ``crestline.ridges(mesh)``,
    ...). The mesh must need no repairs that renumber its vertices, as for those
    functions (:func:`repair_mesh` and :func:`read_mesh` return repaired arrays).

    ``vertices`` (n, 3) float64 and ``faces`` (m, 3) int64 are read-only copies of
    the arrays given: the mesh cannot change under the built structure.
    """

    __slots__ = ("_vertices", "_faces", "_built")

    def __init__(self, vertices: Any, faces: Optional[npt.ArrayLike] = None) -> None:
        v, f = mesh_arrays(vertices, faces)
        v, f = v.copy(), f.copy()
        v.flags.writeable = False
        f.flags.writeable = False
        self._built = _crestline.Mesh(v, f)
        self._vertices, self._faces = v, f

    @property
    def vertices(self) -> Vertices:
        """The vertex positions, (n, 3) float64, read-only."""
        return self._vertices

    @property
    def faces(self) -> Faces:
        """The triangles' vertex indices, (m, 3) int64, read-only."""
        return self._faces

    def mean_edge_length(self) -> float:
        """The mean length of the mesh's edges, each counted once: the length unit
        of the options documented "in mean edge lengths"."""
        return float(self._built.mean_edge_length())

    def __reduce__(self) -> Tuple[Any, Tuple[Vertices, Faces]]:
        # Pickled as its arrays (for multiprocessing and Dask), built again when
        # unpickled.
        return (Mesh, (self._vertices, self._faces))

    def __repr__(self) -> str:
        return f"crestline.Mesh({len(self._vertices)} vertices, {len(self._faces)} faces)"


def built_mesh(vertices: Any, faces: Optional[npt.ArrayLike]) -> Mesh:
    """``vertices`` itself when it is a :class:`Mesh` (and ``faces`` is None), else
    the mesh of the arguments, built."""
    if faces is None and isinstance(vertices, Mesh):
        return vertices
    return Mesh(vertices, faces)

"""crestline: feature lines on surfaces, from numpy arrays.

Meshes are two arrays: ``vertices`` (n × 3, float) and ``faces`` (m × 3, integer
vertex indices, counter-clockwise seen from outside). Mesh objects of trimesh
(``.vertices``, ``.faces``), pymeshlab (``vertex_matrix()``, ``face_matrix()``)
and pyvista (a triangulated ``PolyData``) are accepted where the two arrays are.

    >>> import crestline
    >>> vertices, faces, repairs = crestline.read_mesh("meshes/bunny.obj")
    >>> field = crestline.curvature(vertices, faces)
    >>> lines = crestline.ridges(vertices, faces)
    >>> lines.kinds()
    >>> svg = crestline.draw(vertices, faces, lines, view=(20, 15))
    >>> brain = crestline.read_volume("volumes/mni152_t1_1mm.nii.gz")
    >>> crests = crestline.crest_lines(brain, level=60)
    >>> moved = crestline.transfer(brain, "template.mrk.json", "subject.nii.gz", level=60)

Images are indexed ``[i, j, k]`` with a 4 × 4 voxel-to-world affine, as nibabel
has them; nibabel images are accepted where a :class:`Volume` is.

Every option left at ``None`` takes the library's default, the same as the
command-line tool's; :func:`defaults` lists them.

Bad arguments raise ``ValueError`` or ``TypeError`` naming the argument; errors of
the library raise a subclass of :class:`crestline.Error`; warnings about the input
(repaired samples, no line found) are shown as ``UserWarning``. The computations release
the GIL; Ctrl-C stops them (``KeyboardInterrupt``), and so does an exception
raised by a ``progress`` callback, which propagates.
"""

import copy
from typing import Any, Dict

from ._crestline import __version__

from ._built import Mesh
from ._compare import compare
from ._errors import ArgumentError, Error, FileError, MeshError, StageError
from ._lines import Line, Lines, colors, families
from ._view import View, view
from ._mesh import (
    Curvature,
    Estimator,
    Progress,
    curvature,
    draw,
    morse,
    read_mesh,
    read_vertex_values,
    repair_mesh,
    ridges,
    write_mesh,
    write_vertex_values,
)
from ._jobs import DEFAULTS as _DEFAULTS
from ._transfer import Transferred, read_labelled, transfer
from ._volume import (
    Image,
    Landmarks,
    Space,
    Volume,
    crease_surface,
    crest_lines,
    isosurface,
    landmarks,
    read_volume,
    register,
    write_landmarks,
    write_transform,
)


def defaults() -> Dict[str, Dict[str, Any]]:
    """The defaults of every option, by job (``"iso"``, ``"crest_lines"``,
    ``"crease"``, ``"ridges"``, ``"landmarks"``) and option, as the library and
    the command-line tool apply them. A length relative to the input is
    ``{"units": x}``: x voxels of an image (its largest spacing), or x mean edge
    lengths of a mesh."""
    return copy.deepcopy(_DEFAULTS)


__all__ = [
    "__version__",
    "ArgumentError",
    "Curvature",
    "Error",
    "Estimator",
    "FileError",
    "Image",
    "Landmarks",
    "Line",
    "Lines",
    "Mesh",
    "MeshError",
    "Progress",
    "Space",
    "StageError",
    "Transferred",
    "View",
    "Volume",
    "colors",
    "compare",
    "crease_surface",
    "crest_lines",
    "curvature",
    "defaults",
    "draw",
    "families",
    "isosurface",
    "landmarks",
    "morse",
    "read_labelled",
    "read_mesh",
    "read_vertex_values",
    "read_volume",
    "register",
    "repair_mesh",
    "ridges",
    "transfer",
    "view",
    "write_landmarks",
    "write_mesh",
    "write_vertex_values",
    "write_transform",
]

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

Images are indexed ``[i, j, k]`` with a 4 × 4 voxel-to-world affine, as nibabel
has them; nibabel images are accepted where a :class:`Volume` is.

Bad arguments raise ``ValueError`` or ``TypeError`` naming the argument; errors of
the library raise a subclass of :class:`crestline.Error`. The computations release
the GIL.
"""

from ._errors import ArgumentError, Error, FileError, MeshError, StageError
from ._lines import Line, Lines
from ._mesh import Curvature, Estimator, Progress, curvature, draw, morse, read_mesh, ridges, write_mesh
from ._volume import Image, Volume, crease_surface, crest_lines, isosurface, landmarks, read_volume, register

__all__ = [
    "ArgumentError",
    "Curvature",
    "Error",
    "Estimator",
    "FileError",
    "Image",
    "Line",
    "Lines",
    "MeshError",
    "Progress",
    "StageError",
    "Volume",
    "crease_surface",
    "crest_lines",
    "curvature",
    "draw",
    "isosurface",
    "landmarks",
    "morse",
    "read_mesh",
    "read_volume",
    "register",
    "ridges",
    "write_mesh",
]

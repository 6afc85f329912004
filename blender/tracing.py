"""Feature lines of a mesh given as arrays: ridges and valleys, Morse lines or
both, as the library traces them."""

import os
import tempfile
from dataclasses import dataclass
from typing import Optional

import crestline


class Problem(Exception):
    """An input the lines cannot be traced on; the message says why, for a report."""


class Cancelled(Exception):
    """Raised by the progress callback when the user asked to stop."""


FAILURES = (Problem, crestline.Error, ValueError, TypeError)
"""What tracing or drawing may raise that is reported to the user rather than shown
as a traceback: bad input, and the library's errors and refused arguments."""


@dataclass(frozen=True)
class Tracing:
    """Which lines to trace and the options of the library's jobs."""

    families: str  # 'RIDGES', 'MORSE' or 'BOTH'
    estimator: Optional[str]
    scale: Optional[float]
    threshold: float
    keep_saddles: int


def trace(vertices, faces, options, progress=None):
    """The lines of the mesh (``crestline.Lines``) chosen by ``options``.
    ``progress`` is the library's callback (see ``crestline.Progress``)."""
    mesh = built(vertices, faces)
    found = []
    if options.families in ("RIDGES", "BOTH"):
        found += crestline.ridges(
            mesh, estimator=options.estimator, threshold=options.threshold, scale=options.scale, progress=progress
        )
    if options.families in ("MORSE", "BOTH"):
        found += crestline.morse(mesh, estimator=options.estimator, keep_saddles=options.keep_saddles, progress=progress)
    return crestline.Lines(found)


def built(vertices, faces):
    """The library's mesh of the arrays; a mesh that needs repairs renumbering its
    vertices (duplicate or loose vertices, as Blender meshes often have) is repaired
    as the command-line tool repairs a file. Raises :class:`Problem`."""
    if len(faces) == 0:
        raise Problem("the mesh has no faces")
    try:
        return crestline.Mesh(vertices, faces)
    except crestline.Error as error:
        raise Problem(str(error)) from error
    except ValueError as error:
        if "repairs" not in str(error):
            raise Problem(str(error)) from error
    return crestline.Mesh(*repaired(vertices, faces))


def repaired(vertices, faces):
    """The arrays repaired by ``crestline.read_mesh`` (through a temporary file)."""
    with tempfile.TemporaryDirectory() as folder:
        path = os.path.join(folder, "mesh.ply")
        crestline.write_mesh(path, vertices, faces)
        try:
            fixed, fixed_faces, _ = crestline.read_mesh(path)
        except crestline.Error as error:
            raise Problem(str(error)) from error
    if len(fixed_faces) == 0:
        raise Problem("the mesh has no faces left after its repairs")
    return fixed, fixed_faces

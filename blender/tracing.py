"""Feature lines of a mesh given as arrays: ridges and valleys, Morse lines or
both, as the library traces them."""

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
    """The library's mesh of the arrays, repaired as ``crestline.read_mesh``
    repairs a file: a Blender mesh often has duplicate or loose vertices, whose
    repairs renumber its vertices, which ``crestline.Mesh`` refuses. Raises
    :class:`Problem`."""
    if len(faces) == 0:
        raise Problem("the mesh has no faces")
    try:
        repaired, repaired_faces, _ = crestline.repair_mesh(vertices, faces)
        return crestline.Mesh(repaired, repaired_faces)
    except (crestline.Error, ValueError) as error:
        raise Problem(str(error)) from error

"""How well two files of feature lines or landmarks agree: the library's
``compare``, as the command-line tool's ``compare`` prints it."""

from __future__ import annotations

import json
from os import PathLike
from typing import Any, Dict, Optional, Union

import numpy as np
import numpy.typing as npt

from . import _crestline
from ._checks import file_path, number

Path = Union[str, "PathLike[str]"]


def compare(
    a: Path,
    b: Path,
    transform: Union[None, Path, Dict[str, Any], npt.ArrayLike] = None,
    tolerance: Union[None, float, str] = None,
) -> Dict[str, Any]:
    """The agreement of two lines or landmarks files (``.json`` as the tool and
    :meth:`Lines.save` write them, lines as ``.obj`` or legacy ``.vtk`` from any
    program, 3D Slicer markups ``.mrk.json``, or landmarks ``.csv``), kind by kind and both
    ways: for each kind of line, the share of A's length within ``tolerance`` of
    B's lines of that kind (the distance to B's segments, not its vertices), for
    each kind of landmark the share of A's with one of B's that near, and the
    reverse — what a test–retest study reports.

    ``transform`` moves B's points into A's frame first: a transform file as the
    tool's ``register`` writes it (``.json``, or ITK's ``.tfm``), the dictionary
    :func:`register` returns, or a 4 × 4 matrix (B → A, RAS). ``tolerance`` is a
    length in world units, or a share of the diagonal of A's features as a string
    such as ``"0.5%"`` (the default).

    Returns ``{"tolerance": length, "lines": [...], "landmarks": [...]}``, a row
    per kind: ``{"kind", "a", "b" (length or count), "a_count", "b_count",
    "a_in_b", "b_in_a" (shares from 0 to 1)}``.
    """
    file = matrix = None
    if isinstance(transform, dict):
        matrix = transform["matrix"]
    elif isinstance(transform, (str, PathLike)):
        file = file_path(transform, "transform")
    elif transform is not None:
        matrix = transform
    if matrix is not None:
        matrix = np.ascontiguousarray(matrix, dtype=np.float64)
    if tolerance is not None and not isinstance(tolerance, str):
        tolerance = repr(number(tolerance, "tolerance", strict=True))
    found: Dict[str, Any] = json.loads(
        _crestline.compare_files(file_path(a, "a"), file_path(b, "b"), file, matrix, tolerance)
    )
    return found

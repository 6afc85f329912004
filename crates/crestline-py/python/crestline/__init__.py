"""crestline: feature lines on surfaces, from numpy arrays.

Meshes are two arrays: ``vertices`` (n × 3, float) and ``faces`` (m × 3, integer
vertex indices, counter-clockwise seen from outside). Objects with ``.vertices``
and ``.faces`` (trimesh) are accepted where the two arrays are.

    >>> import crestline
    >>> vertices, faces, repairs = crestline.read_mesh("meshes/bunny.obj")
    >>> field = crestline.curvature(vertices, faces)
    >>> lines = crestline.ridges(vertices, faces)
    >>> [(line["kind"], len(line["points"])) for line in lines][:2]
"""

import json

import numpy as np

from . import _crestline
from ._crestline import Error

__all__ = ["Error", "read_mesh", "curvature", "ridges", "morse"]

ESTIMATORS = ("shape-operator", "jet-fit")


def _mesh_arrays(vertices, faces):
    """The mesh arguments as contiguous float64 and int64 arrays, checked."""
    if faces is None and hasattr(vertices, "vertices") and hasattr(vertices, "faces"):
        vertices, faces = vertices.vertices, vertices.faces
    if faces is None:
        raise TypeError("faces: missing (pass vertices and faces, or a mesh object with .vertices and .faces)")
    try:
        v = np.ascontiguousarray(vertices, dtype=np.float64)
    except (TypeError, ValueError) as e:
        raise TypeError(f"vertices: not an array of numbers ({e})") from None
    if v.ndim != 2 or v.shape[1] != 3:
        raise ValueError(f"vertices: expected shape (n, 3), got {v.shape}")
    bad = ~np.isfinite(v).all(axis=1)
    if bad.any():
        raise ValueError(f"vertices: row {int(np.argmax(bad))} is not finite ({v[np.argmax(bad)].tolist()})")
    f = np.asarray(faces)
    if f.dtype.kind not in "iu":
        raise TypeError(f"faces: expected integer vertex indices, got dtype {f.dtype}")
    f = np.ascontiguousarray(f, dtype=np.int64)
    if f.ndim != 2 or f.shape[1] != 3:
        raise ValueError(f"faces: expected shape (m, 3), got {f.shape}")
    if f.size and (f.min() < 0 or f.max() >= len(v)):
        row = int(np.argmax(((f < 0) | (f >= len(v))).any(axis=1)))
        raise ValueError(f"faces: row {row} ({f[row].tolist()}) refers to a vertex outside 0..{len(v) - 1}")
    return v, f


def _estimator(estimator):
    if estimator not in ESTIMATORS:
        raise ValueError(f"estimator: expected one of {ESTIMATORS}, got {estimator!r}")
    return estimator


def read_mesh(path):
    """Read a mesh file (OBJ, PLY, OFF, STL) and repair it as the command-line tool
    does (welding duplicate vertices, orienting faces consistently, ...).

    Returns ``(vertices, faces, repairs)``: an (n, 3) float64 array, an (m, 3) int64
    array and a dict counting each repair made. Raises :class:`crestline.Error`
    naming the file if it cannot be read.
    """
    vertices, faces, repairs = _crestline.read_mesh(str(path))
    return vertices, faces, json.loads(repairs)


def curvature(vertices, faces=None, estimator="shape-operator"):
    """Principal curvatures and directions at every vertex.

    Returns a dict of arrays: ``k_max``, ``k_min`` (n,), ``d_max``, ``d_min``,
    ``normal`` (n, 3) and ``unreliable`` (n,) bool. ``estimator`` is
    ``"shape-operator"`` (fast) or ``"jet-fit"`` (accurate on irregular meshes).
    Positive curvature is convex (a sphere with outward faces has ``k > 0``).
    Raises ``ValueError`` naming the argument for bad arrays, and for a mesh that
    needs repairs which renumber its vertices (use :func:`read_mesh`).
    """
    v, f = _mesh_arrays(vertices, faces)
    return _crestline.curvature(v, f, _estimator(estimator))


def ridges(vertices, faces=None, estimator="shape-operator", smooth_steps=3, smooth_time=2.0, threshold=2.0):
    """Ridge and valley lines by extremality tracing (Hildebrandt, Polthier,
    Wardetzky 2005), with the command-line tool's defaults.

    Returns a list of dicts, one per line: ``kind`` (``"ridge"`` or ``"valley"``),
    ``closed``, ``strength`` (∫|k| ds, dimensionless), ``points`` ((k, 3) float64)
    and ``values`` (per-point arrays: ``k_max``, ``k_min``, ``e_max``, ``e_min``).
    """
    v, f = _mesh_arrays(vertices, faces)
    if not (isinstance(smooth_steps, int) and 0 <= smooth_steps <= 1000):
        raise ValueError(f"smooth_steps: expected an integer from 0 to 1000, got {smooth_steps!r}")
    for name, value in (("smooth_time", smooth_time), ("threshold", threshold)):
        if not (isinstance(value, (int, float)) and np.isfinite(value) and value >= 0):
            raise ValueError(f"{name}: expected a finite number ≥ 0, got {value!r}")
    return _crestline.ridges(v, f, _estimator(estimator), smooth_steps, float(smooth_time), float(threshold))


def morse(vertices, faces=None, values=None, estimator="shape-operator", keep_saddles=100):
    """Feature lines as the ascending 1-cells (saddle to maximum) of a simplified
    Morse-Smale complex (Sahner et al. 2008) of the curvedness, or of ``values``
    (one float per vertex) when given, keeping the ``keep_saddles`` most
    significant saddles; faired on the surface.

    Returns a list of dicts like :func:`ridges`, of kind ``"ascending"``, with the
    indicator at each point in ``values["indicator"]``.
    """
    v, f = _mesh_arrays(vertices, faces)
    if not (isinstance(keep_saddles, int) and keep_saddles >= 0):
        raise ValueError(f"keep_saddles: expected an integer ≥ 0, got {keep_saddles!r}")
    if values is not None:
        values = np.ascontiguousarray(values, dtype=np.float64)
        if values.shape != (len(v),):
            raise ValueError(f"values: expected shape ({len(v)},), one per vertex, got {values.shape}")
        if not np.isfinite(values).all():
            raise ValueError(f"values: entry {int(np.argmax(~np.isfinite(values)))} is not finite")
    return _crestline.morse(v, f, _estimator(estimator), keep_saddles, values)

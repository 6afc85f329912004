"""The mesh half: reading meshes, curvature, ridges, Morse-Smale lines and
drawings."""

import json
from os import PathLike
from typing import Any, Callable, Dict, Literal, Optional, Tuple, Union, overload

import numpy as np
import numpy.typing as npt

from . import _crestline
from ._checks import (
    Faces,
    Vertices,
    callback,
    count,
    estimator_name,
    mesh_arrays,
    number,
    pair,
    per_vertex,
)
from ._jobs import choice, documented, options
from ._lines import Lines

Curvature = Dict[str, npt.NDArray[Any]]
"""``k_max``, ``k_min`` (n,) float64; ``d_max``, ``d_min``, ``normal`` (n, 3)
float64; ``unreliable`` (n,) bool."""

EstimatorName = Literal["shape-operator", "jet-fit"]
Estimator = Union[EstimatorName, Callable[[Vertices, Faces], Dict[str, Any]]]
"""The name of one of crestline's estimators, or a function ``(vertices, faces)
-> dict`` returning ``k_max``, ``k_min`` (n,), ``d_max``, ``d_min``, ``normal``
(n, 3), one row per vertex, with positive curvature where the surface is convex;
optionally ``unreliable`` (n,) bool, and the extremalities ``e_max``, ``e_min``
(n,: the derivatives of k_max along d_max and of k_min along d_min, with the
directions' signs) with ``fit_residual`` (n,) as the jet fit gives them."""

Progress = Optional[Callable[[str, Optional[float]], Any]]
"""Called with ``(stage, None)`` when a stage of the computation starts and
``(stage, seconds)`` when it ends."""


def read_mesh(path: Union[str, "PathLike[str]"]) -> Tuple[Vertices, Faces, Dict[str, Any]]:
    """Read a mesh file (OBJ, PLY, OFF, STL) and repair it as the command-line tool
    does (welding duplicate vertices, orienting faces consistently, ...).

    Returns ``(vertices, faces, repairs)``: an (n, 3) float64 array, an (m, 3) int64
    array and a dict counting each repair made. Raises :class:`crestline.FileError`
    naming the file if it cannot be read.
    """
    vertices, faces, repairs = _crestline.read_mesh(str(path))
    return vertices, faces, json.loads(repairs)


def write_mesh(
    path: Union[str, "PathLike[str]"],
    vertices: Any,
    faces: Optional[npt.ArrayLike] = None,
    values: Optional[Dict[str, npt.ArrayLike]] = None,
) -> None:
    """Write a triangle mesh in the format of the file's extension: ``.ply`` (with
    ``values``, one float per vertex each, as vertex properties), ``.obj`` or
    ``.vtk``. The file is written under a temporary name and renamed."""
    v, f = mesh_arrays(vertices, faces)
    named = [(str(name), per_vertex(array, f"values[{name!r}]", len(v)).tolist()) for name, array in (values or {}).items()]
    _crestline.write_mesh(str(path), v, f, named)


def _custom_field(estimator: Callable[..., Any], v: Vertices, f: Faces) -> Curvature:
    """The curvature a user's estimator returns, checked."""
    field = estimator(v, f)
    if not isinstance(field, dict):
        raise TypeError(f"estimator: the callable returned {type(field).__name__}, expected a dict of arrays")
    n = len(v)
    checked: Curvature = {}
    for name in ("k_max", "k_min", "d_max", "d_min", "normal"):
        if name not in field:
            raise ValueError(f"estimator: the callable's result has no {name!r}")
        columns = None if name.startswith("k_") else 3
        checked[name] = per_vertex(field[name], f"estimator result {name!r}", n, columns)
    unreliable = np.ascontiguousarray(field.get("unreliable", np.zeros(n, bool)), dtype=bool)
    if unreliable.shape != (n,):
        raise ValueError(f"estimator result 'unreliable': expected shape ({n},), got {unreliable.shape}")
    checked["unreliable"] = unreliable
    if ("e_max" in field) != ("e_min" in field):
        raise ValueError("estimator: the callable's result has one of 'e_max' and 'e_min' without the other")
    for name in ("e_max", "e_min", "fit_residual"):
        if name in field:
            checked[name] = per_vertex(field[name], f"estimator result {name!r}", n)
    return checked


@documented("curvature", unit="mean edge length")
def curvature(vertices: Any, faces: Optional[npt.ArrayLike] = None, estimator: Optional[Estimator] = None) -> Curvature:
    """Principal curvatures and directions at every vertex, as the command-line
    tool's ``curvature`` estimates them.

    Returns a dict of arrays: ``k_max``, ``k_min`` (n,), ``d_max``, ``d_min``,
    ``normal`` (n, 3) and ``unreliable`` (n,) bool; the jet fit adds the
    extremalities ``e_max``, ``e_min`` from its cubic terms and ``fit_residual``.
    ``estimator`` (default {estimator}) is ``"shape-operator"`` (fast),
    ``"jet-fit"`` (accurate on irregular meshes) or a callable (see
    ``Estimator``), whose result is checked and returned.
    Positive curvature is convex (a sphere with outward faces has ``k > 0``).
    Raises ``ValueError`` naming the argument for bad arrays, and for a mesh that
    needs repairs which renumber its vertices (use :func:`read_mesh`).
    """
    v, f = mesh_arrays(vertices, faces)
    if callable(estimator):
        return _custom_field(estimator, v, f)
    given = options(estimator=None if estimator is None else estimator_name(estimator))
    result: Curvature = _crestline.curvature(v, f, given)
    return result


@documented("ridges", unit="mean edge length")
def ridges(
    vertices: Any,
    faces: Optional[npt.ArrayLike] = None,
    estimator: Optional[Estimator] = None,
    smooth_steps: Optional[int] = None,
    smooth_time: Optional[float] = None,
    threshold: Optional[float] = None,
    progress: Progress = None,
    *,
    kind: Optional[Literal["ridges", "valleys", "both"]] = None,
    presmooth: Optional[int] = None,
    solver: Optional[str] = None,
    fair: Optional[bool] = None,
    all_extrema: Optional[bool] = None,
    smoothing_weights: Optional[npt.ArrayLike] = None,
) -> Lines:
    """Ridge and valley lines by extremality tracing (Hildebrandt, Polthier,
    Wardetzky 2005), as the command-line tool's ``ridges`` traces them.

    ``estimator`` (default {estimator}) is a name or a callable (see
    ``Estimator``). The extremalities are smoothed in ``smooth_steps`` steps of
    time ``smooth_time`` (in mean edge lengths squared; by default those the
    library sets for the estimator's extremalities, discrete or fitted, the fitted
    ones smoothed only where the fit's residual shows noise), with optional
    per-vertex ``smoothing_weights``. Lines weaker than ``threshold`` (default
    {threshold}) are dropped. ``kind`` (default {kind}), ``presmooth`` (surface
    smoothing steps; default {presmooth}), ``solver`` (default {solver}), ``fair``
    (default {fair}) and ``all_extrema`` (default {all_extrema}) are the tool's
    options of the same names.

    Returns :class:`Lines` of kind ``"ridge"`` (convex crests) and ``"valley"``
    (concave creases), with per-point ``k_max``, ``k_min``, ``e_max``, ``e_min``
    and the surface location of every point. ``progress`` (see ``Progress``) is
    told of each stage.
    """
    v, f = mesh_arrays(vertices, faces)
    given = options(
        estimator=None if estimator is None or callable(estimator) else estimator_name(estimator),
        smooth_steps=None if smooth_steps is None else count(smooth_steps, "smooth_steps", 0, 1000),
        smooth_time=None if smooth_time is None else number(smooth_time, "smooth_time"),
        threshold=None if threshold is None else number(threshold, "threshold"),
        kind=choice(kind, "kind", "kind"),
        presmooth=None if presmooth is None else count(presmooth, "presmooth", 0, 1000),
        solver=choice(solver, "solver", "solver"),
        fair=None if fair is None else bool(fair),
        all_extrema=None if all_extrema is None else bool(all_extrema),
    )
    weights = None if smoothing_weights is None else per_vertex(smoothing_weights, "smoothing_weights", len(v))
    field = _custom_field(estimator, v, f) if callable(estimator) else None
    dicts = _crestline.ridges(v, f, given, weights, field, callback(progress, "progress"))
    return Lines._from_dicts(dicts)


INDICATORS = {"curvedness": "curvedness", "k_max": "kmax", "k_min": "kmin"}


def morse(
    vertices: Any,
    faces: Optional[npt.ArrayLike] = None,
    indicator: Union[str, npt.ArrayLike] = "curvedness",
    estimator: Estimator = "shape-operator",
    keep_saddles: int = 100,
) -> Lines:
    """Feature lines as the ascending 1-cells (saddle to maximum) of a simplified
    Morse-Smale complex (Sahner et al. 2008) of ``indicator``: ``"curvedness"``,
    ``"k_max"``, ``"k_min"`` (of ``estimator``'s curvature) or an array with one
    float per vertex, keeping the ``keep_saddles`` most significant saddles;
    faired on the surface.

    Returns :class:`Lines` of kind ``"ascending"``, with the indicator at each point
    in ``values["indicator"]``.
    """
    v, f = mesh_arrays(vertices, faces)
    keep_saddles = count(keep_saddles, "keep_saddles", 0)
    if isinstance(indicator, str):
        if indicator not in INDICATORS:
            raise ValueError(f"indicator: expected one of {tuple(INDICATORS)} or one value per vertex, got {indicator!r}")
        if callable(estimator):
            c = _custom_field(estimator, v, f)
            by_name = {"curvedness": np.sqrt(0.5 * (c["k_max"] ** 2 + c["k_min"] ** 2))}
            values = by_name.get(indicator, c.get(indicator))
            dicts = _crestline.morse(v, f, "shape-operator", keep_saddles, "curvedness", values)
        else:
            dicts = _crestline.morse(v, f, estimator_name(estimator), keep_saddles, INDICATORS[indicator], None)
    else:
        values = per_vertex(indicator, "indicator", len(v))
        dicts = _crestline.morse(v, f, "shape-operator", keep_saddles, "curvedness", values)
    return Lines._from_dicts(dicts)


@overload
def draw(
    vertices: Any,
    faces: Optional[npt.ArrayLike] = ...,
    lines: Optional[Lines] = ...,
    view: Tuple[float, float] = ...,
    size: Tuple[int, int] = ...,
    silhouettes: bool = ...,
    png: Literal[False] = ...,
) -> str: ...
@overload
def draw(
    vertices: Any,
    faces: Optional[npt.ArrayLike] = ...,
    lines: Optional[Lines] = ...,
    view: Tuple[float, float] = ...,
    size: Tuple[int, int] = ...,
    silhouettes: bool = ...,
    *,
    png: Literal[True],
) -> Tuple[str, bytes]: ...
def draw(
    vertices: Any,
    faces: Optional[npt.ArrayLike] = None,
    lines: Optional[Lines] = None,
    view: Tuple[float, float] = (0.0, 0.0),
    size: Tuple[int, int] = (800, 800),
    silhouettes: bool = True,
    png: bool = False,
) -> Union[str, Tuple[str, bytes]]:
    """A line drawing of the mesh: ``lines`` (the :func:`ridges` with defaults when
    None) and the silhouettes, with hidden lines removed, seen from ``view`` =
    (azimuth, elevation) in degrees, on a canvas of ``size`` = (width, height)
    pixels, in the command-line tool's default style.

    Returns the SVG document, or ``(svg, png_bytes)`` with ``png=True``.
    """
    v, f = mesh_arrays(vertices, faces)
    if lines is None:
        lines = ridges(v, f)
    if not isinstance(lines, Lines):
        raise TypeError(f"lines: expected crestline.Lines, got {type(lines).__name__}")
    azimuth, elevation = pair(view, "view", lambda a, name: number(a, name, low=-360.0))
    width, height = pair(size, "size", lambda s, name: count(s, name, 1, 20000))
    svg, image = _crestline.draw(v, f, lines._parts(), azimuth, elevation, width, height, bool(silhouettes), bool(png))
    return (svg, image) if png else svg


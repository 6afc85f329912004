"""The mesh half: reading meshes, curvature, ridges, Morse-Smale lines and
drawings."""

from __future__ import annotations

import json
from os import PathLike
from typing import Any, Callable, Dict, Literal, Optional, Tuple, Union, overload

import numpy as np
import numpy.typing as npt

from . import _crestline
from ._built import built_mesh
from ._checks import (
    Faces,
    Vertices,
    callback,
    count,
    estimator_name,
    file_path,
    mesh_arrays,
    number,
    pair,
    per_vertex,
)
from ._jobs import DEFAULTS, NAMES, choice, documented, options
from ._lines import Lines

Curvature = Dict[str, npt.NDArray[Any]]
"""``k_max``, ``k_min`` (n,) float64; ``d_max``, ``d_min``, ``normal`` (n, 3)
float64; ``unreliable`` (n,) bool."""

EstimatorName = Literal["shape-operator", "jet-fit", "auto"]
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
    """Read a mesh file (OBJ, PLY, OFF, STL, GIfTI ``.gii``, or a FreeSurfer
    surface such as ``lh.pial``, told by its content whatever its name) and repair
    it as the command-line tool does (welding duplicate vertices, orienting faces
    consistently, ...). GIfTI and FreeSurfer surfaces are in RAS; a FreeSurfer
    surface with a volume geometry footer is placed in scanner RAS (its tkr-RAS
    coordinates plus the image's centre, in general through the image's matrices).

    Returns ``(vertices, faces, repairs)``: an (n, 3) float64 array, an (m, 3) int64
    array and a dict counting each repair made. Raises :class:`crestline.FileError`
    naming the file if it cannot be read.
    """
    vertices, faces, repairs = _crestline.read_mesh(file_path(path))
    return vertices, faces, json.loads(repairs)


def repair_mesh(vertices: Any, faces: Optional[npt.ArrayLike] = None) -> Tuple[Vertices, Faces, Dict[str, Any]]:
    """Repair a mesh given as arrays (or a mesh object of trimesh, pymeshlab or
    pyvista) as :func:`read_mesh` repairs a file's: duplicate vertices welded,
    degenerate, repeated and back-to-back faces dropped, non-manifold edges and
    vertices split, faces oriented consistently, unreferenced vertices dropped.
    The functions that take arrays refuse a mesh whose repairs renumber its
    vertices (their per-vertex results would not match its rows); pass them the
    repaired arrays.

    Returns ``(vertices, faces, repairs)`` as :func:`read_mesh` does: an (n, 3)
    float64 array, an (m, 3) int64 array and a dict counting each repair made.
    Raises ``ValueError`` or ``TypeError`` naming the argument for bad arrays
    (wrong shape or type, a non-finite coordinate, an index out of range), and
    :class:`crestline.MeshError` if no face is left.
    """
    v, f = mesh_arrays(vertices, faces)
    repaired, repaired_faces, repairs = _crestline.repair_mesh(v, f)
    return repaired, repaired_faces, json.loads(repairs)


def write_mesh(
    path: Union[str, "PathLike[str]"],
    vertices: Any,
    faces: Optional[npt.ArrayLike] = None,
    values: Optional[Dict[str, npt.ArrayLike]] = None,
    space: Optional[str] = None,
) -> None:
    """Write a triangle mesh in the format of the file's extension: ``.ply`` (with
    ``values``, one float per vertex each, as vertex properties), ``.obj``,
    ``.vtk`` or ``.surf.gii`` (GIfTI). ``space`` (``"RAS"`` or ``"LPS"``: for a
    surface of an image, the image's :attr:`Volume.space`) is written as 3D
    Slicer's ``SPACE=`` mark, so that Slicer places the surface on its image; a
    GIfTI surface is in RAS (LPS points are converted) in the scanner's space, or
    without ``space`` as given, in an unknown space. The file is written under a
    temporary name and renamed."""
    v, f = mesh_arrays(vertices, faces)
    named = [(str(name), per_vertex(array, f"values[{name!r}]", len(v)).tolist()) for name, array in (values or {}).items()]
    _crestline.write_mesh(file_path(path), v, f, named, space)


def read_vertex_values(path: Union[str, "PathLike[str]"]) -> npt.NDArray[np.float64]:
    """Read one value per vertex, in the order of the mesh file's vertices, from a
    FreeSurfer curv file (``lh.curv``, ``lh.sulc``: told by its content), a GIfTI
    file (``.shape.gii``, ``.func.gii``: its first array) or a text file of one
    number per line. Raises :class:`crestline.FileError` naming the file."""
    return np.asarray(_crestline.read_vertex_values(file_path(path)), dtype=np.float64)


def write_vertex_values(
    path: Union[str, "PathLike[str]"], values: npt.ArrayLike, name: Optional[str] = None, structure: str = "Other"
) -> None:
    """Write one value per vertex as a GIfTI ``.shape.gii`` or ``.func.gii`` (the
    array's ``Name`` metadata is ``name``, the file's ``AnatomicalStructurePrimary``
    ``structure``, one of Connectome Workbench's names such as ``"CortexLeft"``) or
    a FreeSurfer ``.curv`` (32-bit
    floats, no NaN), by the file's extension. The values are written as given,
    signs included (FreeSurfer's ``?h.curv`` is positive in sulci, crestline's
    curvature positive where convex: negate crestline's mean curvature for a
    ``.curv`` that matches FreeSurfer's). The file is written under a temporary
    name and renamed."""
    array = np.asarray(values, dtype=np.float64)
    if array.ndim != 1:
        raise ValueError(f"values: expected one value per vertex (a 1-D array), got shape {array.shape}")
    _crestline.write_vertex_values(file_path(path), array.tolist(), name, structure)


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
    ``"jet-fit"`` (accurate on irregular meshes), ``"auto"`` (the jet fit on a
    clean mesh, the shape operator on a noisy one, by the fit's residual) or a
    callable (see ``Estimator``), whose result is checked and returned.
    Positive curvature is convex (a sphere with outward faces has ``k > 0``).
    Raises ``ValueError`` naming the argument for bad arrays, and for a mesh that
    needs repairs which renumber its vertices (repair it with :func:`repair_mesh`).
    """
    mesh = built_mesh(vertices, faces)
    if callable(estimator):
        return _custom_field(estimator, mesh.vertices, mesh.faces)
    given = options(estimator=None if estimator is None else estimator_name(estimator))
    result: Curvature = _crestline.curvature(mesh._built, given)
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
    scale: Optional[float] = None,
) -> Lines:
    """Ridge and valley lines by extremality tracing (Hildebrandt, Polthier,
    Wardetzky 2005), as the command-line tool's ``ridges`` traces them.

    ``estimator`` (default {estimator}) is a name or a callable (see
    ``Estimator``). The extremalities are smoothed in ``smooth_steps`` steps of
    time ``smooth_time`` (in mean edge lengths squared; by default those the
    library sets for the estimator's extremalities, discrete or fitted, the fitted
    ones smoothed only where the fit's residual shows noise, and one light step
    for an image's isosurface, whose extremalities come from the image), with optional
    per-vertex ``smoothing_weights``. Lines weaker than ``threshold`` (default
    {threshold}) are dropped. ``kind`` (default {kind}), ``presmooth`` (surface
    smoothing steps; default {presmooth}), ``solver`` (default {solver}), ``fair``
    (default {fair}) and ``all_extrema`` (default {all_extrema}) are the tool's
    options of the same names. With a feature ``scale`` (world units; default
    none) the surface is smoothed for a time of (0.7 scale)², its curvature
    tensor field for scale² and the extremalities for (scale/2)², in world units
    rather than mean edge lengths, so that another sampling of the same surface
    gives the same lines.

    Returns :class:`Lines` of kind ``"ridge"`` (convex crests) and ``"valley"``
    (concave creases), with per-point ``k_max``, ``k_min``, ``e_max``, ``e_min``
    and the surface location of every point. ``progress`` (see ``Progress``) is
    told of each stage.
    """
    mesh = built_mesh(vertices, faces)
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
        scale=None if scale is None else number(scale, "scale", strict=True),
    )
    weights = None if smoothing_weights is None else per_vertex(smoothing_weights, "smoothing_weights", len(mesh.vertices))
    field = _custom_field(estimator, mesh.vertices, mesh.faces) if callable(estimator) else None
    dicts = _crestline.ridges(mesh._built, given, weights, field, callback(progress, "progress"))
    return Lines._from_dicts(dicts)


@documented("morse", unit="mean edge length")
def morse(
    vertices: Any,
    faces: Optional[npt.ArrayLike] = None,
    indicator: Union[str, npt.ArrayLike, None] = None,
    estimator: Optional[Estimator] = None,
    keep_saddles: Optional[int] = None,
    progress: Progress = None,
    *,
    criterion: Optional[Literal["feature", "persistence"]] = None,
    cancel: Optional[int] = None,
    cells: Optional[Literal["ascending", "descending", "both"]] = None,
    keep_forced: Optional[bool] = None,
    smooth: Optional[int] = None,
) -> Lines:
    """Feature lines as 1-cells of a simplified Morse-Smale complex (Sahner et al.
    2008), as the command-line tool's ``morse`` extracts them, of ``indicator``
    (default {indicator}): ``"curvedness"``, ``"kmax"``, ``"kmin"`` (of
    ``estimator``'s curvature; default {estimator}) or an array with one float per
    vertex. The complex is simplified by ``criterion`` (default {criterion}) down
    to ``keep_saddles`` saddles (default {keep_saddles}) that could still be
    cancelled, or by ``cancel`` cancellations; the ``cells`` (default {cells}) are
    output, lines forced by topology only with ``keep_forced`` (default
    {keep_forced}), and faired on the surface in ``smooth`` iterations (default
    {smooth}).

    Returns :class:`Lines` of kind ``"ascending"`` (and ``"descending"``), with
    the indicator at each point in ``values["indicator"]``. ``progress`` (see
    ``Progress``) is told of each stage.
    """
    mesh = built_mesh(vertices, faces)
    values = None
    if indicator is not None and not isinstance(indicator, str):
        values, indicator = per_vertex(indicator, "indicator", len(mesh.vertices)), None
    given = options(
        indicator=choice(indicator, "indicator", "indicator"),
        estimator=None if estimator is None or callable(estimator) else estimator_name(estimator),
        keep_saddles=None if keep_saddles is None else count(keep_saddles, "keep_saddles", 0),
        criterion=choice(criterion, "criterion", "criterion"),
        cancel=None if cancel is None else count(cancel, "cancel", 0),
        cells=choice(cells, "cells", "cells"),
        keep_forced=None if keep_forced is None else bool(keep_forced),
        smooth=None if smooth is None else count(smooth, "smooth", 0),
    )
    field = _custom_field(estimator, mesh.vertices, mesh.faces) if callable(estimator) else None
    dicts = _crestline.morse(mesh._built, given, values, field, callback(progress, "progress"))
    return Lines._from_dicts(dicts)


@overload
def draw(
    vertices: Any,
    faces: Optional[npt.ArrayLike] = ...,
    lines: Union[Lines, str, None] = ...,
    view: Optional[Tuple[float, float]] = ...,
    size: Optional[Tuple[int, int]] = ...,
    silhouettes: Optional[bool] = ...,
    png: Literal[False] = ...,
    **more: Any,
) -> str: ...
@overload
def draw(
    vertices: Any,
    faces: Optional[npt.ArrayLike] = ...,
    lines: Union[Lines, str, None] = ...,
    view: Optional[Tuple[float, float]] = ...,
    size: Optional[Tuple[int, int]] = ...,
    silhouettes: Optional[bool] = ...,
    *,
    png: Literal[True],
    **more: Any,
) -> Tuple[str, bytes]: ...
@documented("draw", unit="mean edge length")
def draw(
    vertices: Any,
    faces: Optional[npt.ArrayLike] = None,
    lines: Union[Lines, str, None] = None,
    view: Optional[Tuple[float, float]] = None,
    size: Optional[Tuple[int, int]] = None,
    silhouettes: Optional[bool] = None,
    png: bool = False,
    **more: Any,
) -> Union[str, Tuple[str, bytes]]:
    """A line drawing of the mesh with hidden lines removed, as the command-line
    tool's ``draw`` makes it: ``lines`` (:class:`Lines` to draw, or which to trace:
    ``"ridges"``, ``"morse"`` or ``"none"``; default {lines}), and the silhouettes
    with ``silhouettes=True`` (default {silhouettes}), seen from ``view`` =
    (azimuth, elevation) in degrees (default {view}), on a canvas of ``size`` =
    (width, height) pixels (default {size}), in the tool's default style.

    The tool's other options are keyword arguments of the same names: ``camera``
    (eye, target and up, nine numbers), ``perspective`` (field of view),
    ``borders``, ``creases`` (an angle in degrees), ``suggestive``, ``taper``,
    ``width_by_depth``, ``fade_by_view``, ``silhouette_clearance``, and ``ridges``
    and ``morse`` (dicts of the options of :func:`ridges` and :func:`morse`).
    ``page`` lays the drawing out for a pen plotter or print: a paper (``"a4"``,
    ``"letter"``, ``"200x200mm"``) or a dict ``{{"paper": "a4", "landscape": True,
    "margin": "10mm", "pen": "0.3mm"}}``; the SVG then has the paper's size in
    millimetres, every line the pen's width, and ``taper`` and
    ``silhouette_clearance`` are in millimetres.

    Returns the SVG document, or ``(svg, png_bytes)`` with ``png=True``.
    """
    mesh = built_mesh(vertices, faces)
    given_lines = None
    if isinstance(lines, Lines):
        given_lines, lines = lines._parts(), None
    elif isinstance(lines, str):
        choice(lines, "lines", "lines")
    elif lines is not None:
        raise TypeError(f"lines: expected crestline.Lines or one of {NAMES['lines']}, got {type(lines).__name__}")
    unknown = set(more) - set(DEFAULTS["draw"]) - {"progress"}
    if unknown:
        raise TypeError(f"draw: unexpected keyword arguments {sorted(unknown)}; expected some of {sorted(DEFAULTS['draw'])}")
    progress = callback(more.pop("progress", None), "progress")
    chosen = dict(
        lines=lines,
        view=None if view is None else list(pair(view, "view", lambda a, name: number(a, name, low=-360.0))),
        size=None if size is None else list(pair(size, "size", lambda s, name: count(s, name, 1, 20000))),
        silhouettes=None if silhouettes is None else bool(silhouettes),
        **more,
    )
    svg, image = _crestline.draw(mesh._built, given_lines, options(**chosen), bool(png), progress)
    return (svg, image) if png else svg

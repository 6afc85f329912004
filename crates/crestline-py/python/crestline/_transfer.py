"""Landmarks that correspond across scans: a template's labelled landmarks carried
onto a subject through their lines, as the command-line tool's ``transfer``."""

from __future__ import annotations

from os import PathLike
from typing import Any, Dict, List, Mapping, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

from . import _crestline
from ._built import built_mesh
from ._checks import callback, count, file_path, number, points
from ._jobs import documented, options
from ._lines import Lines, _frame
from ._mesh import Progress
from ._volume import _image, _space, read_volume

Transferred = Dict[str, Any]
"""What :func:`transfer` returns: ``labels`` (a list, in the order given),
``positions`` ((n, 3) float64, RAS), ``confidence`` ((n,) float64, mm; lower is
better, infinite where no line is near), ``coverage`` ((n,) float64: the
subject's lines around each landmark over the template's, near 1 where the
subject shows that part), ``flagged`` (a list of bools: coverage below
``min_coverage`` or no confidence, a part cut off or missing in the subject),
``rms`` (float), ``rigid`` (the rigid stage's 4 × 4 matrix, template →
subject, RAS) and ``template_lines`` (the template's :class:`Lines` as
registered: the ``template_lines=`` of the transfers onto other subjects)."""

Labelled = Tuple[List[str], npt.NDArray[np.float64]]


def read_labelled(path: Union[str, "PathLike[str]"]) -> Labelled:
    """The labels and positions ((n, 3), RAS) of a landmarks file as ``transfer``
    reads it: 3D Slicer markups (``.mrk.json``, the point lists' control points),
    the tool's landmarks ``.json`` (labelled ``extremal-12``, ...), or ``.csv``
    with columns label, x, y, z and space (RAS or LPS)."""
    labels, positions = _crestline.read_labelled_points(file_path(path))
    return list(labels), positions


def _landmarks(value: Any) -> Labelled:
    """Labelled landmarks from a file, a mapping label → (x, y, z) in RAS, or a
    pair (labels, (n, 3) positions in RAS)."""
    if isinstance(value, (str, PathLike)):
        return read_labelled(value)
    if isinstance(value, Mapping):
        labels, rows = [str(label) for label in value], list(value.values())
    else:
        try:
            labels, rows = value
        except (TypeError, ValueError):
            raise TypeError("landmarks: expected a file, a mapping label → (x, y, z) or a pair "
                            f"(labels, positions), got {type(value).__name__}") from None
        labels = [str(label) for label in labels]
    found = points(np.asarray(rows, dtype=np.float64).reshape(-1, 3), "landmarks")
    if len(labels) != len(found) or not labels:
        raise ValueError(f"landmarks: {len(labels)} labels for {len(found)} positions; expected as many, at least one")
    return labels, found


def scan_lines(scan: Any, name: str, level: Optional[float], given: str, progress: Progress = None) -> Lines:
    """The lines ``transfer`` registers of ``scan``: lines as given; of an image
    (with ``level``), the crest lines of its isosurface and of the inner ones
    (``image_scale``, ``inner_levels``); of a mesh, its ridges and
    valleys of every strength down to the transfer's ``mesh_threshold``
    (``given``: the transfer's options as JSON)."""
    if isinstance(scan, Lines):
        return scan
    if level is not None:
        image = read_volume(scan) if isinstance(scan, (str, PathLike)) else scan
        samples, affine = _image(image, None, None)
        dicts = _crestline.transfer_image_lines(samples, affine, level, given, progress)
        return Lines._from_dicts(dicts, space=_space(image))
    if isinstance(scan, (str, PathLike)):
        dicts, space = _crestline.transfer_mesh_file_lines(file_path(scan, name), given, progress)
        return Lines._from_dicts(dicts, space=space)
    dicts = _crestline.transfer_mesh_lines(built_mesh(scan, None)._built, given, progress)
    return Lines._from_dicts(dicts)


@documented("transfer")
def transfer(
    template: Any,
    landmarks: Union[str, "PathLike[str]", Mapping[str, Sequence[float]], Labelled],
    subject: Any,
    level: Optional[float] = None,
    *,
    template_lines: Union[Lines, str, "PathLike[str]", None] = None,
    space: Optional[str] = None,
    scales: Optional[Sequence[float]] = None,
    iterations: Optional[int] = None,
    max_distance: Optional[float] = None,
    max_angle: Optional[float] = None,
    max_points: Optional[int] = None,
    confidence_radius: Optional[float] = None,
    mesh_threshold: Optional[float] = None,
    min_coverage: Optional[float] = None,
    image_scale: Optional[float] = None,
    inner_levels: Optional[Sequence[float]] = None,
    output: Union[str, "PathLike[str]", None] = None,
    output_space: Optional[str] = None,
    progress: Progress = None,
) -> Transferred:
    """A template's labelled landmarks carried onto a subject scan of the same
    anatomy through their lines, as the command-line tool's ``transfer``: the
    template's lines are registered rigidly onto the subject's, then a smooth
    displacement is grown over the Gaussian ``scales`` (mm, coarse to fine;
    default {scales}), ``iterations`` at each (default {iterations}), from pairs
    of line points of the same kind whose tangents make at most ``max_angle``
    degrees (default {max_angle}) and which lie at most ``max_distance`` scales
    apart (default {max_distance}), of at most ``max_points`` points per scan
    (default {max_points}); each landmark moves by it. Its ``confidence`` is the
    RMS distance of the template's lines around it (Gaussian weights of
    ``confidence_radius``, default {confidence_radius}) to the subject's; a
    landmark whose coverage (the subject's lines around it over the template's)
    is below ``min_coverage`` (default {min_coverage}) is flagged, and still
    placed.

    ``template`` and ``subject`` are two images (a :class:`Volume`, a nibabel
    image or a file) with ``level``: the crest lines of their isosurfaces at the
    level and at the ``inner_levels`` (quantiles of the samples inside it;
    default {inner_levels}), traced at ``image_scale`` (mm; default
    {image_scale}); or,
    without ``level``, two meshes (a :class:`Mesh`, a mesh object or a file):
    their ridges and valleys at least ``mesh_threshold`` strong (default
    {mesh_threshold}); or :class:`Lines` already traced. ``template_lines``, the
    template's lines computed once (:class:`Lines`, or a lines ``.json`` file as
    :meth:`Lines.save` and the tool's ``transfer --save-template-lines`` write it), are
    used in place of the template's. Lines
    that do not state their frame (those of meshes given as arrays or of files
    without 3D Slicer's ``SPACE=`` mark) are taken in ``space`` (default LPS, as
    3D Slicer reads models).

    ``landmarks``: a file (3D Slicer ``.mrk.json``, the tool's landmarks ``.json``
    or a ``.csv`` with label, x, y, z and space columns; see
    :func:`read_labelled`), a mapping label → (x, y, z) or a pair (labels,
    positions), positions in RAS. With ``output`` (``.mrk.json``, ``.json``,
    ``.csv``) they are written as the tool writes them, ``.json`` and ``.csv`` in
    ``output_space`` (default RAS).

    Returns ``Transferred``: ``labels``, ``positions`` ((n, 3), RAS),
    ``confidence``, ``coverage``, ``flagged``, ``rms``, ``rigid`` (4 × 4, RAS)
    and ``template_lines`` (to give to the next subject's transfer).
    """
    progress = callback(progress, "progress")
    labels, positions = _landmarks(landmarks)
    given = options(
        scales=None if scales is None else [number(s, "scales", strict=True) for s in scales],
        iterations=None if iterations is None else count(iterations, "iterations", 1, 1000),
        max_distance=None if max_distance is None else number(max_distance, "max_distance", strict=True),
        max_angle=None if max_angle is None else number(max_angle, "max_angle"),
        max_points=None if max_points is None else count(max_points, "max_points", 100),
        confidence_radius=None if confidence_radius is None else number(confidence_radius, "confidence_radius",
                                                                        strict=True),
        mesh_threshold=None if mesh_threshold is None else number(mesh_threshold, "mesh_threshold"),
        min_coverage=None if min_coverage is None else number(min_coverage, "min_coverage"),
        image_scale=None if image_scale is None else number(image_scale, "image_scale", strict=True),
        inner_levels=None if inner_levels is None else [number(q, "inner_levels") for q in inner_levels],
    )
    frame = "LPS" if space is None else _frame(space)
    level = None if level is None else number(level, "level", low=-np.inf)
    if isinstance(template_lines, (str, PathLike)):
        dicts, declared = _crestline.read_lines_file(file_path(template_lines, "template_lines"))
        template_lines = Lines._from_dicts(dicts, space=declared)
    scans = [template_lines if template_lines is not None else template, subject]
    found = [scan_lines(scan, name, level, given, progress) for scan, name in zip(scans, ("template", "subject"))]
    result: Transferred = _crestline.transfer_landmarks(
        found[0]._parts(), found[0].space or frame, found[1]._parts(), found[1].space or frame,
        labels, positions, given, progress,
    )
    result["labels"] = labels
    result["template_lines"] = found[0]
    if output is not None:
        frame_out = "RAS" if output_space is None else _frame(output_space)
        _crestline.write_labelled_points(file_path(output, "output"), labels, result["positions"],
                                         result["confidence"], result["flagged"], frame_out)
    return result

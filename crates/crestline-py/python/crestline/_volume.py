"""The image half: 3D images, isosurfaces, crest lines by Marching Lines, crease
surfaces, landmarks and rigid registration of crest lines.

Images are indexed ``[i, j, k]`` (x, y, z voxel indices) with a 4 × 4
voxel-to-world ``affine``, as nibabel has them: a nibabel image is accepted
wherever a :class:`Volume` is, and so is a plain 3-D array with ``spacing`` and
``origin``.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from os import PathLike
from typing import Any, Dict, Literal, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

from . import _crestline
from ._built import built_mesh
from ._checks import Faces, Vertices, callback, count, estimator_name, file_path, number, numeric, points
from ._jobs import NAMES, documented, options
from ._lines import Lines, _frame
from ._mesh import Progress


Space = Literal["RAS", "LPS"]
"""An anatomical world frame: ``"RAS"`` (x to the right, y to the front, z up:
NIfTI) or ``"LPS"`` (x to the left, y to the back: DICOM, NRRD, MetaImage, 3D
Slicer's files); either letter case is accepted."""


@dataclass(frozen=True)
class Volume:
    """A 3-D image: ``data`` (nx, ny, nz) float32 indexed ``[i, j, k]``, the
    voxel-to-world ``affine`` (4 × 4) and ``space``, the anatomical frame of the
    world coordinates as the file declares it (NIfTI: ``"RAS"``; NRRD: its
    ``space``; MetaImage: ``"LPS"``; ``None``: not anatomical). Lines and landmarks
    found in the image carry its ``space``."""

    data: npt.NDArray[np.float32]
    affine: npt.NDArray[np.float64]
    space: Optional[Space] = None

    def __post_init__(self) -> None:
        """Refuse, when made, what would fail at first use: a data array that is
        not 3-D numbers, an affine that is not a finite 4 × 4 matrix with last row
        [0, 0, 0, 1] and an invertible 3 × 3 part, an unknown frame."""
        data = np.asarray(self.data)
        if data.ndim != 3 or data.dtype.kind not in "biuf":
            raise ValueError(f"data: expected a 3-D array of numbers, got {data.dtype} of shape {data.shape}")
        affine = np.asarray(self.affine)
        if affine.shape != (4, 4) or affine.dtype.kind not in "biuf" or not np.isfinite(affine).all():
            raise ValueError(f"affine: expected a finite 4 × 4 matrix, got shape {affine.shape}")
        if abs(np.linalg.det(affine[:3, :3])) < 1e-12:
            raise ValueError("affine: its 3 × 3 part is singular")
        if not np.array_equal(affine[3], [0.0, 0.0, 0.0, 1.0]):
            raise ValueError(f"affine: its last row must be [0, 0, 0, 1], got {affine[3].tolist()}")
        if self.space is not None:
            object.__setattr__(self, "space", _frame(self.space))

    @property
    def spacing(self) -> npt.NDArray[np.float64]:
        """The voxel size along i, j and k."""
        return np.linalg.norm(self.affine[:3, :3], axis=0)

    @property
    def voxel(self) -> float:
        """One voxel: the largest spacing, the unit of the relative lengths of the
        image functions' defaults."""
        return float(_crestline.voxel_size(np.ascontiguousarray(self.affine, dtype=np.float64)))

    @property
    def origin(self) -> npt.NDArray[np.float64]:
        """The world position of voxel (0, 0, 0)."""
        return self.affine[:3, 3].copy()


Image = Union[Volume, npt.ArrayLike, Any]
"""A :class:`Volume`, a nibabel image (``.affine`` and ``get_fdata()``) or a 3-D
array indexed ``[i, j, k]`` (with ``spacing`` and ``origin``)."""


def read_volume(
    path: Union[str, "PathLike[str]", Sequence[Union[str, "PathLike[str]"]]], series: Optional[str] = None
) -> Volume:
    """Read a 3-D image: NIfTI (.nii, .nii.gz), NRRD (.nrrd, .nhdr), MetaImage
    (.mha, .mhd), or a DICOM series from a folder, a DICOMDIR, a ``.dcm`` file (or
    any file with the DICOM mark) or a list of files.

    A DICOM series is read in LPS millimetres, its samples the modality values
    (Rescale Slope and Intercept applied), its slices ordered by position along the
    normal of their planes. ``series`` is the Series Instance UID to read where the
    input holds several (without it, the error lists them). Missing slices, uneven
    spacing, gantry tilt, mixed orientations and transfer syntaxes that cannot be
    decoded (JPEG-LS, JPEG 2000) are refused. Raises :class:`crestline.FileError`
    naming the file or folder if it cannot be read."""
    if series is not None and not isinstance(series, str):
        raise TypeError(f"series: expected a Series Instance UID (str), got {type(series).__name__}")
    if isinstance(path, (list, tuple)):
        files = [file_path(p, "path") for p in path]
        samples, affine, space = _crestline.read_dicom(files, series)
    else:
        samples, affine, space = _crestline.read_volume(file_path(path), series)
    frame: Optional[Space] = "RAS" if space == "RAS" else "LPS" if space == "LPS" else None
    return Volume(samples.transpose(2, 1, 0), affine, frame)


def _space(volume: Image) -> Optional[Space]:
    """The frame of an image's world coordinates: a :class:`Volume`'s own, RAS for
    a nibabel image (NIfTI's world), none for an array."""
    if isinstance(volume, Volume):
        return volume.space
    if hasattr(volume, "affine") and callable(getattr(volume, "get_fdata", None)):
        return "RAS"
    return None


def _image(volume: Image, spacing: Optional[Sequence[float]], origin: Optional[Sequence[float]]) -> Tuple[Any, Any]:
    """The samples as a C-contiguous (nz, ny, nx) float32 array and the affine."""
    placed = isinstance(volume, Volume) or hasattr(volume, "affine")
    if placed and (spacing is not None or origin is not None):
        raise ValueError("spacing, origin: only for plain arrays; this image has its own affine")
    if isinstance(volume, Volume):
        data, affine = volume.data, volume.affine
    elif hasattr(volume, "affine") and callable(getattr(volume, "get_fdata", None)):
        data, affine = volume.get_fdata(dtype=np.float32), volume.affine
    else:
        data = volume
        steps = pair3(spacing if spacing is not None else (1.0, 1.0, 1.0), "spacing", positive=True)
        start = pair3(origin if origin is not None else (0.0, 0.0, 0.0), "origin", positive=False)
        affine = np.eye(4)
        affine[:3, :3] = np.diag(steps)
        affine[:3, 3] = start
    try:
        samples = np.asarray(numeric(data, "volume"), dtype=np.float32)
    except ValueError as e:
        raise TypeError(f"volume: not an array of numbers ({e})") from None
    if samples.ndim != 3 or min(samples.shape) < 2:
        raise ValueError(f"volume: expected a 3-D image at least 2 voxels wide, got shape {samples.shape}")
    affine = np.ascontiguousarray(affine, dtype=np.float64)
    if affine.shape != (4, 4) or not np.isfinite(affine).all():
        raise ValueError(f"affine: expected a finite 4 × 4 matrix, got shape {affine.shape}")
    if abs(np.linalg.det(affine[:3, :3])) < 1e-12:
        raise ValueError("affine: its 3 × 3 part is singular")
    return np.ascontiguousarray(samples.transpose(2, 1, 0)), affine


def pair3(value: Any, name: str, positive: bool) -> npt.NDArray[np.float64]:
    """Three finite numbers (positive ones if ``positive``)."""
    try:
        v = np.asarray(value, dtype=np.float64).reshape(3)
    except (TypeError, ValueError):
        raise ValueError(f"{name}: expected three numbers, got {value!r}") from None
    if not np.isfinite(v).all() or (positive and (v <= 0).any()):
        raise ValueError(f"{name}: expected three finite{' positive' if positive else ''} numbers, got {value!r}")
    return v


@documented("iso")
def isosurface(
    volume: Image,
    level: float,
    sigma: Optional[float] = None,
    progress: Progress = None,
    *,
    scale: Optional[float] = None,
    close: Optional[bool] = None,
    spacing: Optional[Sequence[float]] = None,
    origin: Optional[Sequence[float]] = None,
) -> Tuple[Vertices, Faces]:
    """The isosurface ``f = level`` of the image smoothed by a Gaussian of
    ``sigma`` (world units; default {sigma}; 0: none, the cubic B-spline of the
    samples), by marching cubes with the asymptotic decider, inside being
    ``f ≥ level``, as the command-line tool's ``iso`` extracts it: vertices (world
    coordinates) and faces, counter-clockwise seen from outside, ready for
    :func:`crestline.ridges`. With ``close`` (default {close}) the surface is
    closed where it reaches the border of the image, watertight. Non-finite
    samples are set to the smallest value with a ``UserWarning``.
    ``scale`` (world units) is the feature scale σ and the
    other lengths' defaults are multiples of; default: from the size of the object
    (2% of the cube root of the volume the isosurface encloses, at least a voxel),
    not from the grid, so that a rescan gives the same result.
    """
    samples, affine = _image(volume, spacing, origin)
    given = options(scale=_scale(scale),
                    sigma=None if sigma is None else number(sigma, "sigma"),
                    close=None if close is None else bool(close))
    vertices, faces = _crestline.isosurface(
        samples, affine, number(level, "level", low=-np.inf), given, callback(progress, "progress")
    )
    return vertices, faces


def _scale(scale: Optional[float]) -> Optional[float]:
    """The feature scale given, checked: a positive length, or None."""
    return None if scale is None else number(scale, "scale", strict=True)


def _family(kind: Optional[str], gauss: Optional[float]) -> Optional[str]:
    """The library's name of the line family ``kind`` (``"gauss"`` with the value
    ``gauss``)."""
    if kind is None:
        return None
    kinds = tuple(name.split("=")[0] for name in NAMES["family"])
    if kind not in kinds:
        raise ValueError(f"kind: expected one of {kinds}, got {kind!r}")
    if kind != "gauss":
        return kind
    if gauss is None or number(gauss, "gauss", low=-np.inf) == 0.0:
        raise ValueError("gauss: the iso-Gaussian curves need a nonzero value (kind='parabolic' is K = 0)")
    return f"gauss={float(gauss)!r}"


@documented("crest_lines")
def crest_lines(
    volume: Image,
    level: float,
    sigma: Optional[float] = None,
    kind: Optional[Literal["crest", "parabolic", "gauss"]] = None,
    gauss: Optional[float] = None,
    min_length: Optional[float] = None,
    min_strength: Optional[float] = None,
    seeds: Optional[int] = None,
    rng_seed: Optional[int] = None,
    progress: Progress = None,
    *,
    scale: Optional[float] = None,
    spacing: Optional[Sequence[float]] = None,
    origin: Optional[Sequence[float]] = None,
) -> Lines:
    """Lines of the isosurface ``f = level`` of the image smoothed by a Gaussian of
    ``sigma`` (world units; default {sigma}), traced in the image by Marching
    Lines (Thirion & Gourdon 1993), as the command-line tool's ``crest-lines``
    does.

    ``kind="crest"`` (the default, {kind}) gives crest lines, of kind
    ``"ridge"`` (convex) and ``"valley"`` (concave); ``"parabolic"`` the lines
    where the Gaussian curvature is 0; ``"gauss"`` those where it is ``gauss``.
    With ``seeds``, only the lines through that many random cells, longest first,
    drawn with ``rng_seed`` (default {rng_seed}). Lines shorter than
    ``min_length`` (world units; default {min_length}) or weaker than
    ``min_strength`` (default {min_strength}) are dropped. Each point carries
    ``k_max``, ``k_min``, ``e_max``, ``e_min``. ``progress`` (see ``Progress``) is
    told of each stage. ``scale`` (world units) is the feature scale σ and the
    other lengths' defaults are multiples of; default: from the size of the object
    (2% of the cube root of the volume the isosurface encloses, at least a voxel),
    not from the grid, so that a rescan gives the same result.
    """
    samples, affine = _image(volume, spacing, origin)
    given = options(
        scale=_scale(scale),
        sigma=None if sigma is None else number(sigma, "sigma", strict=True),
        kind=_family(kind, gauss),
        min_length=None if min_length is None else number(min_length, "min_length"),
        min_strength=None if min_strength is None else number(min_strength, "min_strength"),
        seeds=None if seeds is None else count(seeds, "seeds", 1),
        rng_seed=None if rng_seed is None else count(rng_seed, "rng_seed", 0),
    )
    level = number(level, "level", low=-np.inf)
    dicts = _crestline.crest_lines(samples, affine, level, given, callback(progress, "progress"))
    return Lines._from_dicts(dicts, space=_space(volume))


@documented("crease")
def crease_surface(
    volume: Image,
    valley: Optional[bool] = None,
    sigma: Optional[float] = None,
    strength: Optional[float] = None,
    min_component: Optional[int] = None,
    progress: Progress = None,
    *,
    spacing: Optional[Sequence[float]] = None,
    origin: Optional[Sequence[float]] = None,
) -> Dict[str, npt.NDArray[Any]]:
    """The ridge surface of the image (its valley surface with ``valley=True``;
    default {valley}) by Schultz, Theisel & Seidel (2010), as the command-line
    tool's ``crease`` does: ``sigma`` (default {sigma}) 0 differentiates the cubic
    B-spline of the samples, else a Gaussian of that width; only where −λ3 is at
    least ``strength`` (default {strength}) times the strongest in the image;
    pieces of fewer than ``min_component`` (default {min_component}) triangles
    dropped.

    Returns a dict: ``vertices`` (n, 3), ``faces`` (m, 3) (the surface need not be
    orientable), and per vertex ``strength`` (−λ3) and ``degenerate`` (1 on the
    degenerate lines where the surface ends, else 0). ``progress`` (see
    ``Progress``) is told of each stage.
    """
    samples, affine = _image(volume, spacing, origin)
    given = options(
        valley=None if valley is None else bool(valley),
        sigma=None if sigma is None else number(sigma, "sigma"),
        strength=None if strength is None else number(strength, "strength"),
        min_component=None if min_component is None else count(min_component, "min_component", 0),
    )
    result: Dict[str, npt.NDArray[Any]] = _crestline.crease_surface(
        samples, affine, given, callback(progress, "progress")
    )
    return result


Landmarks = Dict[str, Any]
"""``{"source": str, "space": "RAS", "LPS" or None, "points": {"id": (n,) int,
"kind": (n,) str, "position": (n, 3), "curvature": (n,), "line": (n,) int},
"lines": [dict per crest line: id, kind, closed, length, mean_curvature,
strength, convex, points]}``; ids number points and lines from 1, ``line`` is the
id of a point's line, and ``space`` the frame of the positions (the image's, or
the lines')."""


def write_landmarks(
    path: Union[str, "PathLike[str]"], found: Landmarks, space: Optional[Space] = None
) -> None:
    """Write landmarks (as :func:`landmarks` returns them) as the command-line
    tool's ``landmarks`` does, in the format of the file's extension: ``.mrk.json``
    (3D Slicer markups, in LPS), ``.json`` (every landmark and line) or ``.csv``
    (the point landmarks: id, kind, x, y, z, curvature, line, space). The frame of
    the positions is the landmarks' own ``space``; ``space`` gives it when they
    have none (landmarks of a mesh; default ``"LPS"``, as 3D Slicer reads models)
    and must not contradict it. The file is written under a temporary name and
    renamed."""
    points = found["points"]
    document = {
        "source": str(found.get("source", "")),
        "points": [
            {"id": int(i), "kind": str(kind), "position": [float(c) for c in position],
             "curvature": float(k), "line": int(line)}
            for i, kind, position, k, line in zip(points["id"], points["kind"], points["position"],
                                                 points["curvature"], points["line"])
        ],
        "lines": [{**line, "points": np.asarray(line["points"], dtype=np.float64).tolist()}
                  for line in found["lines"]],
    }
    _crestline.write_landmarks(
        file_path(path), json.dumps(document), found.get("space"), None if space is None else str(space)
    )


@documented("landmarks", unit="unit")
def landmarks(
    source: Any,
    faces: Optional[npt.ArrayLike] = None,
    *,
    level: Optional[float] = None,
    scale: Optional[float] = None,
    radius: Optional[float] = None,
    persistence: Optional[float] = None,
    sigma: Optional[float] = None,
    min_length: Optional[float] = None,
    estimator: Optional[str] = None,
    threshold: Optional[float] = None,
    unit: Optional[float] = None,
    progress: Progress = None,
    spacing: Optional[Sequence[float]] = None,
    origin: Optional[Sequence[float]] = None,
) -> Landmarks:
    """Anatomical landmarks of crest lines, as the command-line tool's
    ``landmarks`` finds them: extremal points, where both principal curvatures
    are extremal (the other extremality keeps each sign for ``persistence`` of arc
    length on each side; default {persistence}); curvature maxima, the largest
    within ``radius`` on both sides (default {radius}); and the ends of open
    lines. The feature scale is a length taken from the size of the object (an
    image's isosurface, a mesh's area), not from its sampling.

    ``source`` is what the tool takes:

    - an image (a :class:`Volume`, a nibabel image or an array) with ``level``:
      the crest lines of its isosurface by Marching Lines, smoothed by ``sigma``
      and at least ``min_length`` long, as :func:`crest_lines` has them, at the
      feature ``scale`` (world units; default from the image, see there);
    - a mesh (``vertices`` and ``faces``, or a mesh object): its ridges and
      valleys, by ``estimator`` and ``threshold`` as :func:`ridges` has them;
    - or :class:`Lines` already traced, with ``unit``, the length of one feature
      scale of the defaults (the tool's ``--report`` gives it as ``scale``), or
      with both ``radius`` and ``persistence``.

    Returns ``Landmarks`` (see there).
    """
    marks = options(
        radius=None if radius is None else number(radius, "radius", strict=True),
        persistence=None if persistence is None else number(persistence, "persistence", strict=True),
    )
    progress = callback(progress, "progress")
    if isinstance(source, Lines):
        if unit is None and (radius is None or persistence is None):
            raise ValueError("unit: lines carry no scale; give their feature scale as unit, "
                             "or both radius and persistence, or pass the mesh or the image")
        scale = 1.0 if unit is None else number(unit, "unit", strict=True)
        found = _crestline.lines_landmarks(source._parts(), scale, marks)
        space = source.space
    elif level is not None:
        samples, affine = _image(source, spacing, origin)
        crest = options(
            scale=_scale(scale),
            sigma=None if sigma is None else number(sigma, "sigma", strict=True),
            min_length=None if min_length is None else number(min_length, "min_length"),
        )
        found = _crestline.image_landmarks(samples, affine, number(level, "level", low=-np.inf), crest, marks, progress)
        space = _space(source)
    else:
        if sigma is not None or min_length is not None or scale is not None:
            raise ValueError("scale, sigma, min_length: for an image (with level), not for a mesh")
        mesh = built_mesh(source, faces)
        tracing = options(
            estimator=None if estimator is None else estimator_name(estimator),
            threshold=None if threshold is None else number(threshold, "threshold"),
        )
        found = _crestline.mesh_landmarks(mesh._built, tracing, marks, None, progress)
        space = None
    return {**_landmark_arrays(json.loads(found)), "space": space}


def _landmark_arrays(found: Dict[str, Any]) -> Landmarks:
    """The library's landmarks JSON with numpy arrays."""
    marks = found["points"]
    return {
        "source": found["source"],
        "points": {
            "id": np.array([p["id"] for p in marks], dtype=np.int64),
            "kind": np.array([p["kind"] for p in marks], dtype=str),
            "position": np.array([p["position"] for p in marks], dtype=np.float64).reshape(-1, 3),
            "curvature": np.array([p["curvature"] for p in marks], dtype=np.float64),
            "line": np.array([p["line"] for p in marks], dtype=np.int64),
        },
        "lines": [{**line, "points": np.array(line["points"], dtype=np.float64)} for line in found["lines"]],
    }


def _line_points(value: Any, name: str) -> Vertices:
    """The points of ridge and valley lines (in RAS when the lines have a frame),
    or an (n, 3) array of points."""
    if isinstance(value, Lines):
        crests = [line.points for line in value if line.kind in ("ridge", "valley")]
        found = points(np.vstack(crests) if crests else np.zeros((0, 3)), name)
        return found * np.array([-1.0, -1.0, 1.0]) if value.space == "LPS" else found
    return points(value, name)


@documented("register")
def register(
    fixed: Union[Lines, npt.ArrayLike],
    moving: Union[Lines, npt.ArrayLike],
    fixed_keys: Optional[npt.ArrayLike] = None,
    moving_keys: Optional[npt.ArrayLike] = None,
    min_overlap: Optional[float] = None,
    max_iterations: Optional[int] = None,
    progress: Progress = None,
) -> Dict[str, Any]:
    """The rigid motion taking ``moving`` onto ``fixed`` (crest lines, or (n, 3)
    point arrays), by trimmed ICP from the best of the principal-axes guesses, as
    the command-line tool's ``register``; key points (e.g. extremal landmarks) of
    both, when given, guide the coarse stage. ``min_overlap`` (default
    {min_overlap}) is the least share of moving points expected to match;
    ``max_iterations`` (default {max_iterations}) bounds the final ICP.
    :class:`Lines` with a frame (:attr:`Lines.space`, e.g. of an NRRD and of a
    NIfTI image) are first brought to RAS, as the tool does, and the matrix is
    then in RAS; arrays and lines without a frame are taken as they are.

    Returns ``{{"matrix": 4 × 4 (moving → fixed), "rms", "matched",
    "matched_share", "iterations"}}``.
    """
    keys = [points(np.zeros((0, 3)) if k is None else k, name) for k, name in
            ((fixed_keys, "fixed_keys"), (moving_keys, "moving_keys"))]
    given = options(
        min_overlap=None if min_overlap is None else number(min_overlap, "min_overlap"),
        max_iterations=None if max_iterations is None else count(max_iterations, "max_iterations", 1),
    )
    result: Dict[str, Any] = _crestline.register_lines(
        _line_points(fixed, "fixed"), _line_points(moving, "moving"), keys[0], keys[1], given,
        callback(progress, "progress"),
    )
    return result


def write_transform(
    path: Union[str, "PathLike[str]"], transform: Union[Dict[str, Any], npt.ArrayLike], space: Space = "RAS"
) -> None:
    """Write a rigid motion as the command-line tool's ``register`` does, in the
    format of the file's extension: ``.json`` (moving → fixed, RAS) or ``.tfm``
    (ITK and 3D Slicer: fixed → moving, LPS, what ``SimpleITK.ReadTransform`` and
    Slicer's transform reader take). ``transform`` is what :func:`register`
    returns, or a 4 × 4 moving → fixed matrix whose frame is ``space``
    (:func:`register`'s matrices are RAS). The file is written under a
    temporary name and renamed."""
    matrix = transform["matrix"] if isinstance(transform, dict) else transform
    array = np.ascontiguousarray(np.asarray(matrix, dtype=np.float64))
    _crestline.write_transform(file_path(path), array, str(space))

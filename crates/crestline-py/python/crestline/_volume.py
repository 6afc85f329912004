"""The image half: 3D images, isosurfaces, crest lines by Marching Lines, crease
surfaces, landmarks and rigid registration of crest lines.

Images are indexed ``[i, j, k]`` (x, y, z voxel indices) with a 4 × 4
voxel-to-world ``affine``, as nibabel has them: a nibabel image is accepted
wherever a :class:`Volume` is, and so is a plain 3-D array with ``spacing`` and
``origin``.
"""

import json
from dataclasses import dataclass
from os import PathLike
from typing import Any, Dict, Literal, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

from . import _crestline
from ._checks import Faces, Vertices, callback, count, number, points
from ._lines import Lines
from ._mesh import Progress


@dataclass(frozen=True)
class Volume:
    """A 3-D image: ``data`` (nx, ny, nz) float32 indexed ``[i, j, k]`` and the
    voxel-to-world ``affine`` (4 × 4), world coordinates in the image's frame
    (NIfTI: RAS, millimetres)."""

    data: npt.NDArray[np.float32]
    affine: npt.NDArray[np.float64]

    @property
    def spacing(self) -> npt.NDArray[np.float64]:
        """The voxel size along i, j and k."""
        return np.linalg.norm(self.affine[:3, :3], axis=0)

    @property
    def origin(self) -> npt.NDArray[np.float64]:
        """The world position of voxel (0, 0, 0)."""
        return self.affine[:3, 3].copy()


Image = Union[Volume, npt.ArrayLike, Any]
"""A :class:`Volume`, a nibabel image (``.affine`` and ``get_fdata()``) or a 3-D
array indexed ``[i, j, k]`` (with ``spacing`` and ``origin``)."""


def read_volume(path: Union[str, "PathLike[str]"]) -> Volume:
    """Read a 3-D image: NIfTI (.nii, .nii.gz), NRRD (.nrrd, .nhdr) or MetaImage
    (.mha, .mhd). Raises :class:`crestline.FileError` naming the file if it cannot
    be read."""
    samples, affine = _crestline.read_volume(str(path))
    return Volume(samples.transpose(2, 1, 0), affine)


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
        samples = np.asarray(data, dtype=np.float32)
    except (TypeError, ValueError) as e:
        raise TypeError(f"volume: not an array of numbers ({e})") from None
    if samples.ndim != 3 or min(samples.shape) < 2:
        raise ValueError(f"volume: expected a 3-D image at least 2 voxels wide, got shape {samples.shape}")
    if not np.isfinite(samples).all():
        raise ValueError(f"volume: {int((~np.isfinite(samples)).sum())} samples are not finite")
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


def isosurface(
    volume: Image,
    level: float,
    *,
    spacing: Optional[Sequence[float]] = None,
    origin: Optional[Sequence[float]] = None,
) -> Tuple[Vertices, Faces]:
    """The isosurface ``f = level`` by marching cubes with the asymptotic decider,
    inside being ``f ≥ level``: vertices (world coordinates) and faces,
    counter-clockwise seen from outside, ready for :func:`crestline.ridges`."""
    samples, affine = _image(volume, spacing, origin)
    vertices, faces = _crestline.isosurface(samples, affine, number(level, "level", low=-np.inf))
    return vertices, faces


def crest_lines(
    volume: Image,
    level: float,
    sigma: Optional[float] = None,
    kind: Literal["crest", "parabolic", "gauss"] = "crest",
    gauss: float = 0.0,
    min_length: Optional[float] = None,
    min_strength: float = 0.0,
    seeds: Optional[int] = None,
    rng_seed: int = 0,
    *,
    spacing: Optional[Sequence[float]] = None,
    origin: Optional[Sequence[float]] = None,
) -> Lines:
    """Lines of the isosurface ``f = level`` of the image smoothed by a Gaussian of
    ``sigma`` (world units; the largest voxel size by default), traced in the image
    by Marching Lines (Thirion & Gourdon 1993), as the command-line tool's
    ``crest-lines`` does.

    ``kind="crest"`` gives crest lines, of kind ``"ridge"`` (convex) and
    ``"valley"`` (concave); ``"parabolic"`` the lines where the Gaussian curvature
    is 0; ``"gauss"`` those where it is ``gauss``. With ``seeds``, only the lines
    through that many random cells (``rng_seed``), longest first. Lines shorter
    than ``min_length`` (three voxels by default, as the tool's) or weaker than
    ``min_strength`` are dropped. Each point carries ``k_max``, ``k_min``,
    ``e_max``, ``e_min``.
    """
    samples, affine = _image(volume, spacing, origin)
    voxel = float(np.linalg.norm(affine[:3, :3], axis=0).max())
    sigma = voxel if sigma is None else number(sigma, "sigma", strict=True)
    min_length = 3.0 * voxel if min_length is None else number(min_length, "min_length")
    kinds = {"crest": None, "parabolic": 0.0, "gauss": number(gauss, "gauss", low=-np.inf)}
    if kind not in kinds:
        raise ValueError(f"kind: expected one of {tuple(kinds)}, got {kind!r}")
    if kind == "gauss" and gauss == 0.0:
        raise ValueError("gauss: the iso-Gaussian curves need a nonzero value (kind='parabolic' is K = 0)")
    seeds = None if seeds is None else count(seeds, "seeds", 1)
    dicts = _crestline.crest_lines(
        samples,
        affine,
        number(level, "level", low=-np.inf),
        sigma,
        min_length,
        number(min_strength, "min_strength"),
        kinds[kind],
        seeds,
        count(rng_seed, "rng_seed", 0, 2**64 - 1),
    )
    return Lines._from_dicts(dicts)


def crease_surface(
    volume: Image,
    valley: bool = False,
    sigma: float = 0.0,
    strength: float = 0.1,
    min_component: int = 20,
    progress: Progress = None,
    *,
    spacing: Optional[Sequence[float]] = None,
    origin: Optional[Sequence[float]] = None,
) -> Dict[str, npt.NDArray[Any]]:
    """The ridge surface of the image (its valley surface with ``valley=True``) by
    Schultz, Theisel & Seidel (2010), as the command-line tool's ``crease`` does:
    ``sigma`` 0 differentiates the cubic B-spline of the samples, else a Gaussian
    of that width; only where −λ3 is at least ``strength`` times the strongest in
    the image; pieces of fewer than ``min_component`` triangles dropped.

    Returns a dict: ``vertices`` (n, 3), ``faces`` (m, 3) (the surface need not be
    orientable), and per vertex ``strength`` (−λ3) and ``degenerate`` (1 on the
    degenerate lines where the surface ends, else 0). ``progress`` (see
    ``Progress``) is told when each stage ends (and when the first two start).
    """
    samples, affine = _image(volume, spacing, origin)
    if not (isinstance(strength, (int, float)) and 0.0 <= strength <= 1.0):
        raise ValueError(f"strength: expected a fraction from 0 to 1, got {strength!r}")
    result: Dict[str, npt.NDArray[Any]] = _crestline.crease_surface(
        samples,
        affine,
        bool(valley),
        number(sigma, "sigma"),
        float(strength),
        count(min_component, "min_component", 0),
        callback(progress, "progress"),
    )
    return result


def landmarks(lines: Lines, radius: float, persistence: float) -> Dict[str, Any]:
    """Anatomical landmarks of ridge and valley lines (as the command-line tool's
    ``landmarks``): extremal points, where both principal curvatures are extremal
    (the other extremality keeps each sign for ``persistence`` of arc length on
    each side); curvature maxima, the largest within ``radius`` on both sides; and
    the ends of open lines.

    Returns ``{"points": {"kind": (n,) str, "position": (n, 3), "curvature": (n,),
    "line": (n,) int}, "lines": [dict per crest line: id, kind, closed, length,
    mean_curvature, strength, convex, points]}``; ``line`` numbers lines from 1.
    """
    if not isinstance(lines, Lines):
        raise TypeError(f"lines: expected crestline.Lines, got {type(lines).__name__}")
    found = json.loads(
        _crestline.landmarks(lines._parts(), number(radius, "radius", strict=True),
                             number(persistence, "persistence", strict=True))
    )
    marks = found["points"]
    return {
        "points": {
            "kind": np.array([p["kind"] for p in marks], dtype=str),
            "position": np.array([p["position"] for p in marks], dtype=np.float64).reshape(-1, 3),
            "curvature": np.array([p["curvature"] for p in marks], dtype=np.float64),
            "line": np.array([p["line"] for p in marks], dtype=np.int64),
        },
        "lines": [{**line, "points": np.array(line["points"], dtype=np.float64)} for line in found["lines"]],
    }


def _line_points(value: Any, name: str) -> Vertices:
    """The points of ridge and valley lines, or an (n, 3) array of points."""
    if isinstance(value, Lines):
        crests = [line.points for line in value if line.kind in ("ridge", "valley")]
        return points(np.vstack(crests) if crests else np.zeros((0, 3)), name)
    return points(value, name)


def register(
    fixed: Union[Lines, npt.ArrayLike],
    moving: Union[Lines, npt.ArrayLike],
    fixed_keys: Optional[npt.ArrayLike] = None,
    moving_keys: Optional[npt.ArrayLike] = None,
    min_overlap: float = 0.4,
) -> Dict[str, Any]:
    """The rigid motion taking ``moving`` onto ``fixed`` (crest lines, or (n, 3)
    point arrays), by trimmed ICP from the best of the principal-axes guesses, as
    the command-line tool's ``register``; key points (e.g. extremal landmarks) of
    both, when given, guide the coarse stage. ``min_overlap`` is the least share
    of moving points expected to match.

    Returns ``{"matrix": 4 × 4 (moving → fixed), "rms", "matched",
    "matched_share", "iterations"}``.
    """
    keys = [points(np.zeros((0, 3)) if k is None else k, name) for k, name in
            ((fixed_keys, "fixed_keys"), (moving_keys, "moving_keys"))]
    overlap = number(min_overlap, "min_overlap")
    result: Dict[str, Any] = _crestline.register_lines(
        _line_points(fixed, "fixed"), _line_points(moving, "moving"), keys[0], keys[1], overlap
    )
    return result

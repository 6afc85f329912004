"""Feature lines: :class:`Line` and the sequence of them, :class:`Lines`."""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass, field
from os import PathLike
from typing import TYPE_CHECKING, Any, Dict, Iterable, Iterator, List, Optional, Sequence, Tuple, Union, overload

import numpy as np
import numpy.typing as npt

from ._checks import file_path

if TYPE_CHECKING:
    from ._view import View


def families() -> Dict[str, str]:
    """The family of every kind of line, ``{kind: family}`` in the order of the
    kinds' codes: ``{"ridge": "ridges", "valley": "valleys", "ascending":
    "ascending", ...}``. The family's name is what drawings name their layers,
    views their toggles, and style files their entries."""
    from . import _crestline

    return {kind: family for kind, family, _ in _crestline.line_kinds()}


def colors() -> Dict[str, str]:
    """The colour of every family of lines (:func:`families`), ``{family:
    "#rrggbb"}``: ridges red, valleys blue, ascending Morse-Smale lines orange,
    descending ones teal, ... as drawings, views, label and border files draw
    them."""
    from . import _crestline

    return {family: color for _, family, color in _crestline.line_kinds()}


@dataclass(frozen=True)
class Line:
    """One feature line.

    ``kind`` is ``"ridge"``, ``"valley"``, ``"ascending"``, ``"crest"``,
    ``"parabolic"``, ``"gauss"``, ... (every kind: :func:`families`); ``points``
    is (k, 3) float64, without a repeated first point when ``closed``;
    ``strength`` is how pronounced it is (for ridges and valleys ∫|k| ds,
    dimensionless); ``values`` holds per-point arrays
    (e.g. ``k_max``, ``e_max``). Lines traced on a mesh also tell where each point
    lies on it: ``location_vertices`` (k, 3) int64 and ``location_weights`` (k, 3)
    float64, so that ``(weights[:, :, None] * vertices[location_vertices]).sum(1)``
    is the point on the mesh (before fairing moved it along the surface).
    """

    kind: str
    closed: bool
    strength: float
    points: npt.NDArray[np.float64]
    values: Dict[str, npt.NDArray[np.float64]] = field(default_factory=dict)
    location_vertices: Optional[npt.NDArray[np.int64]] = None
    location_weights: Optional[npt.NDArray[np.float64]] = None

    def __len__(self) -> int:
        return len(self.points)

    def length(self) -> float:
        """The length of the polyline (with the closing segment if closed)."""
        p = np.vstack([self.points, self.points[:1]]) if self.closed else self.points
        return float(np.linalg.norm(np.diff(p, axis=0), axis=1).sum())

    def to_dict(self) -> Dict[str, Any]:
        """The line as a dict of its fields (arrays as they are)."""
        d: Dict[str, Any] = {
            "kind": self.kind,
            "closed": self.closed,
            "strength": self.strength,
            "points": self.points,
            "values": dict(self.values),
        }
        if self.location_vertices is not None:
            d["location_vertices"] = self.location_vertices
            d["location_weights"] = self.location_weights
        return d


class Lines(Sequence[Line]):
    """The feature lines found on one surface: a sequence of :class:`Line`, in the
    order the library produced them. ``space`` is the anatomical frame of the
    points (``"RAS"`` or ``"LPS"``: that of the image they were found in), or
    ``None``; :meth:`save` writes it into the file."""

    def __init__(self, lines: Iterable[Line], space: Optional[str] = None) -> None:
        self._lines = list(lines)
        self.space = None if space is None else _frame(space)

    @classmethod
    def _from_dicts(cls, dicts: Iterable[Dict[str, Any]], space: Optional[str] = None) -> "Lines":
        return cls((Line(**d) for d in dicts), space)

    @overload
    def __getitem__(self, index: int) -> Line: ...
    @overload
    def __getitem__(self, index: slice) -> "Lines": ...
    def __getitem__(self, index: Union[int, slice]) -> Union[Line, "Lines"]:
        if isinstance(index, slice):
            return Lines(self._lines[index], self.space)
        return self._lines[index]

    def __len__(self) -> int:
        return len(self._lines)

    def __iter__(self) -> Iterator[Line]:
        return iter(self._lines)

    def __repr__(self) -> str:
        counts = Counter(line.kind for line in self._lines)
        return f"Lines({', '.join(f'{n} {kind}' for kind, n in sorted(counts.items())) or 'none'})"

    def of_kind(self, kind: str) -> "Lines":
        """The lines of one kind."""
        return Lines((line for line in self._lines if line.kind == kind), self.space)

    def kinds(self) -> Dict[str, int]:
        """How many lines of each kind."""
        return dict(Counter(line.kind for line in self._lines))

    def to_list(self) -> List[Dict[str, Any]]:
        """Every line as a dict (:meth:`Line.to_dict`)."""
        return [line.to_dict() for line in self._lines]

    def save(self, path: Union[str, "PathLike[str]"]) -> None:
        """Write the lines in the format of the file's extension, as the
        command-line tool does: ``.json`` (points, per-point values), ``.ply``,
        ``.obj``, ``.vtk`` or ``.mrk.json`` (3D Slicer markups, a curve per line),
        each saying :attr:`space` where the format can. The file is written under
        a temporary name and renamed, so it is never left half written."""
        from . import _crestline

        _crestline.write_lines(file_path(path), self._parts(), self.space)

    def save_labels(
        self, path: Union[str, "PathLike[str]"], vertices: Any, faces: Any = None, structure: str = "Other"
    ) -> None:
        """Write the vertices of the mesh these ridges and valleys were traced on
        that they pass near, as the command-line tool does: each point labels the
        corner of the edge or face it lies on with the largest weight. ``.label.gii``
        (GIfTI: one int32 per vertex, 0 none, 1 ridges, 2 valleys, with the label
        table, the file's ``AnatomicalStructurePrimary`` ``structure``, one of
        Connectome Workbench's names such as ``"CortexLeft"``) or ``.label``
        (FreeSurfer: the labelled vertices, value 1 on ridges and -1 on valleys). Every line needs its ``location_vertices`` (lines
        traced on ``vertices`` without fairing). The file is written under a
        temporary name and renamed."""
        from . import _crestline

        from ._built import built_mesh

        mesh = built_mesh(vertices, faces)
        located = []
        for i, line in enumerate(self._lines):
            if line.location_vertices is None or line.location_weights is None:
                raise ValueError(f"lines[{i}]: no location_vertices: the line does not say where it lies on the mesh")
            located.append(
                (
                    line.kind,
                    np.ascontiguousarray(line.location_vertices, dtype=np.int64).reshape(-1, 3),
                    np.ascontiguousarray(line.location_weights, dtype=np.float64).reshape(-1, 3),
                )
            )
        _crestline.write_line_labels(file_path(path), mesh._built, located, structure)

    def show(
        self,
        vertices: Any,
        faces: Any = None,
        title: str = "",
        path: Union[str, "PathLike[str]", None] = None,
    ) -> "View":
        """The interactive 3D view of these lines on the mesh (:func:`crestline.view`):
        shown in Jupyter when it is a cell's result, and written to ``path``
        (``.html``) when given (or later by ``.save(path)``)."""
        from ._view import view

        page = view(vertices, faces, lines=self, title=title)
        if path is not None:
            page.save(path)
        return page

    def _parts(self) -> List[Tuple[str, bool, float, npt.NDArray[np.float64], List[Tuple[str, List[float]]]]]:
        """The lines as the extension module takes them."""
        return [
            (
                line.kind,
                bool(line.closed),
                float(line.strength),
                np.ascontiguousarray(line.points, dtype=np.float64).reshape(-1, 3),
                [(name, np.asarray(v, dtype=np.float64).tolist()) for name, v in line.values.items()],
            )
            for line in self._lines
        ]


def _frame(space: str) -> str:
    """``space`` as the library names frames (``"RAS"``, ``"LPS"``)."""
    from ._jobs import NAMES

    name = str(space).upper()
    if name not in NAMES["space"]:
        raise ValueError(f"space: expected one of {NAMES['space']}, got {space!r}")
    return name

"""Interactive 3D views: a mesh and its lines as one self-contained HTML page, shown
in Jupyter or written to a file."""

from __future__ import annotations

import html
from os import PathLike
from typing import Any, Optional, Union

import numpy.typing as npt

from . import _crestline
from ._built import built_mesh
from ._checks import callback, file_path
from ._jobs import options
from ._lines import Lines


class View:
    """A page showing a surface with its lines (``crestline view``): drag to rotate,
    wheel to zoom, toggle each family, colour the surface by a curvature quantity,
    click a line for its kind, length and strength. It needs no network. In Jupyter
    it shows in the cell's output; :meth:`save` writes it to a file."""

    def __init__(self, page: str) -> None:
        self.html = page

    def save(self, path: Union[str, "PathLike[str]"]) -> None:
        """Write the page to ``path`` (``.html``)."""
        with open(file_path(path), "w", encoding="utf-8") as out:
            out.write(self.html)

    def _repr_html_(self) -> str:
        # In an iframe of its own, so that the page's script and style stay its own.
        return (
            f'<iframe srcdoc="{html.escape(self.html, quote=True)}" '
            'style="width:100%;height:480px;border:0"></iframe>'
        )


def view(
    vertices: Any,
    faces: Optional[npt.ArrayLike] = None,
    lines: Union[Lines, str, None] = None,
    title: str = "",
    **more: Any,
) -> View:
    """The interactive view of the mesh with ``lines`` (:class:`Lines`, or which to
    trace: ``"ridges"``, ``"morse"`` or ``"none"``; default ridges), as the
    command-line tool's ``view`` makes it. Keyword arguments ``ridges`` and
    ``morse`` (dicts of the options of :func:`ridges` and :func:`morse`) and
    ``progress``."""
    mesh = built_mesh(vertices, faces)
    given = None
    if isinstance(lines, Lines):
        given, lines = lines._parts(), None
    progress = callback(more.pop("progress", None), "progress")
    page = _crestline.view(mesh._built, given, options(lines=lines, **more), str(title), progress)
    return View(page)

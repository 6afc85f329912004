"""The colours of the line families as crestline's drawings and views show them
(ridges red, valleys blue, ...), read from the library rather than restated."""

import functools
import json

import numpy as np

import crestline

KINDS = ("ridge", "valley", "ascending", "descending")


@functools.lru_cache(maxsize=None)
def family_colours():
    """``{family: (r, g, b)}`` in [0, 1] (sRGB), by the family's name as drawings
    name their layers (``"ridges"``, ``"valleys"``, ``"ascending"``, ...). The
    library tells a family's colour in the data of its interactive view; this asks
    it for the view of one triangle with a short line of every kind."""
    vertices = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])
    faces = np.array([[0, 1, 2]])
    segment = np.array([[0.1, 0.1, 0.0], [0.2, 0.2, 0.0]])
    lines = crestline.Lines(crestline.Line(kind, False, 1.0, segment) for kind in KINDS)
    page = crestline.view(vertices, faces, lines=lines).html
    start = page.index('"families":') + len('"families":')
    families, _ = json.JSONDecoder().raw_decode(page, start)
    return {family["name"]: rgb(family["color"]) for family in families}


def rgb(css):
    """``"#rrggbb"`` as three floats in [0, 1]."""
    return tuple(int(css[i : i + 2], 16) / 255.0 for i in (1, 3, 5))


def linear(colour):
    """An sRGB colour in Blender's linear scene colour space (for materials)."""
    return tuple(c / 12.92 if c <= 0.04045 else ((c + 0.055) / 1.055) ** 2.4 for c in colour)

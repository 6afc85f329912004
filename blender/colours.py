"""The colours of the line families as crestline's drawings and views show them
(ridges red, valleys blue, ...), read from the library rather than restated."""

import functools

import crestline


@functools.lru_cache(maxsize=None)
def family_colours():
    """``{family: (r, g, b)}`` in [0, 1] (sRGB), by the family's name as drawings
    name their layers (``"ridges"``, ``"valleys"``, ``"ascending"``, ...)."""
    return {family: rgb(css) for family, css in crestline.colors().items()}


def rgb(css):
    """``"#rrggbb"`` as three floats in [0, 1]."""
    return tuple(int(css[i : i + 2], 16) / 255.0 for i in (1, 3, 5))


def linear(colour):
    """An sRGB colour in Blender's linear scene colour space (for materials)."""
    return tuple(c / 12.92 if c <= 0.04045 else ((c + 0.055) / 1.055) ** 2.4 for c in colour)

"""The options the operators share, each with the library's default as
``crestline.defaults()`` gives it (never restated here)."""

import typing

import bpy
import crestline

from .tracing import Tracing

RIDGES = crestline.defaults()["ridges"]
MORSE = crestline.defaults()["morse"]

LINE_FAMILIES = [
    ("RIDGES", "Ridges and Valleys", "Ridges (convex crests) and valleys (concave creases)"),
    ("MORSE", "Morse Lines", "Lines of the simplified Morse-Smale complex of the curvedness"),
    ("BOTH", "Both", "Ridges, valleys and Morse lines"),
]


def estimator_items():
    """The library's curvature estimators, as enum items (names in capitals), after
    ``'DEFAULT'``: each job's own default."""
    names = typing.get_args(typing.get_args(crestline.Estimator)[0])
    default = f"The library's: {RIDGES['estimator']} for ridges and valleys, {MORSE['estimator']} for Morse lines"
    return [("DEFAULT", "Default", default)] + [
        (name.upper().replace("-", "_"), name.replace("-", " ").title(), f"crestline's {name} estimator") for name in names
    ]


def estimator_name(item):
    """The library's name of an estimator enum item (``'JET_FIT'`` is
    ``"jet-fit"``), None for the jobs' defaults."""
    return None if item == "DEFAULT" else item.lower().replace("_", "-")


class LineOptions:
    """Which lines to trace, and how: mixed into the operators."""

    lines: bpy.props.EnumProperty(name="Lines", items=LINE_FAMILIES, default="RIDGES")
    estimator: bpy.props.EnumProperty(
        name="Estimator",
        description="How the curvature is estimated",
        items=estimator_items(),
        default="DEFAULT",
    )
    scale: bpy.props.FloatProperty(
        name="Feature Scale",
        description=(
            "The size of the smallest features kept, in scene units: the surface is smoothed at this "
            "scale, so that another sampling of the same shape gives the same lines. 0: smoothing by "
            "mean edge lengths instead"
        ),
        default=RIDGES["scale"] or 0.0,
        min=0.0,
        subtype="DISTANCE",
    )
    threshold: bpy.props.FloatProperty(
        name="Threshold",
        description="Ridges and valleys weaker than this (the integral of |curvature| along the line) are dropped",
        default=RIDGES["threshold"],
        min=0.0,
    )
    keep_saddles: bpy.props.IntProperty(
        name="Morse Saddles",
        description="The Morse-Smale complex is simplified down to this many saddles",
        default=MORSE["keep_saddles"],
        min=0,
    )

    def draw_line_options(self, layout):
        """The options in ``layout`` (the redo panel or the file browser's side)."""
        layout.prop(self, "lines")
        layout.prop(self, "estimator")
        layout.prop(self, "scale")
        if self.lines != "MORSE":
            layout.prop(self, "threshold")
        if self.lines != "RIDGES":
            layout.prop(self, "keep_saddles")

    def tracing(self, unit=1.0):
        """These options as :func:`tracing.trace` takes them; ``unit`` is the length
        of one scene unit in the coordinates the lines are traced in."""
        return Tracing(
            families=self.lines,
            estimator=estimator_name(self.estimator),
            scale=self.scale * unit if self.scale > 0 else None,
            threshold=self.threshold,
            keep_saddles=self.keep_saddles,
        )

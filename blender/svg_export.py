"""File ‣ Export ‣ Line drawing (crestline): the scene camera's view of the mesh
objects as crestline draws it, hidden lines removed, on the render's pixels."""

import re

import bpy
import crestline
from bpy_extras.io_utils import ExportHelper

from .camera_view import camera_view
from .evaluated import mesh_arrays, merged
from .options import LineOptions
from .tracing import FAILURES, Problem, built, trace

DRAW = crestline.defaults()["draw"]

POINT = re.compile(r"([ML])(-?\d+(?:\.\d+)?) (-?\d+(?:\.\d+)?)")
"""A point of a path's data as crestline writes it (``M12.34 56.78``, ``L...``)."""


class CRESTLINE_OT_export_svg(LineOptions, bpy.types.Operator, ExportHelper):
    """Export the scene camera's view of the visible mesh objects as an SVG line
    drawing: silhouettes and feature lines with hidden lines removed, in layers"""

    bl_idname = "crestline.export_svg"
    bl_label = "Export Line Drawing"
    bl_options = {"REGISTER"}

    filename_ext = ".svg"
    filter_glob: bpy.props.StringProperty(default="*.svg", options={"HIDDEN"})

    use_selection: bpy.props.BoolProperty(name="Selected Only", description="Draw the selected mesh objects only", default=False)
    silhouettes: bpy.props.BoolProperty(name="Silhouettes", default=True)
    page: bpy.props.StringProperty(
        name="Page",
        description="A paper for a pen plotter or print (a4, letter, 200x200mm): the drawing is laid out on it. Empty: the render's pixels",
        default="",
    )
    landscape: bpy.props.BoolProperty(name="Landscape", default=False)
    margin: bpy.props.StringProperty(
        name="Margin", description="The blank border of the page (mm, cm or in). Empty: crestline's default", default=""
    )
    pen: bpy.props.StringProperty(
        name="Pen", description="The pen's width on the page (mm, cm or in). Empty: crestline's default", default=""
    )
    plot: bpy.props.BoolProperty(
        name="For a Plotter",
        description="Every stroke drawn once, strokes joined where their ends meet and ordered for short pen travel",
        default=DRAW["plot"],
    )

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        layout.prop(self, "use_selection")
        layout.prop(self, "silhouettes")
        self.draw_line_options(layout)
        layout.prop(self, "page")
        if self.page:
            layout.prop(self, "landscape")
            layout.prop(self, "margin")
            layout.prop(self, "pen")
        layout.prop(self, "plot")

    def execute(self, context):
        try:
            svg = self.drawing(context)
        except FAILURES as error:
            self.report({"ERROR"}, f"Line drawing: {error}")
            return {"CANCELLED"}
        try:
            with open(self.filepath, "w", encoding="utf-8") as out:
                out.write(svg)
        except OSError as error:
            self.report({"ERROR"}, f"Line drawing: cannot write {self.filepath}: {error.strerror}")
            return {"CANCELLED"}
        self.report({"INFO"}, f"Line drawing written to {self.filepath}")
        return {"FINISHED"}

    def objects(self, context):
        """The mesh objects to draw."""
        chosen = context.selected_objects if self.use_selection else context.view_layer.objects
        meshes = [obj for obj in chosen if obj.type == "MESH" and obj.visible_get()]
        if not meshes:
            raise Problem("no visible mesh object to draw" + (" is selected" if self.use_selection else ""))
        return meshes

    def drawing(self, context):
        """The SVG text. Raises :class:`Problem` or the library's errors."""
        view = camera_view(context.scene)
        depsgraph = context.evaluated_depsgraph_get()
        vertices, faces = merged([mesh_arrays(obj, depsgraph, world=True) for obj in self.objects(context)])
        mesh = built(vertices, faces)
        lines = trace(mesh.vertices, mesh.faces, self.tracing())
        options = view.draw_options()
        if self.page:
            del options["size"]  # the canvas is the page's printable area
        svg = crestline.draw(
            mesh, lines=lines, silhouettes=self.silhouettes, plot=self.plot, page=self.page_options(), **options
        )
        if self.page:
            return svg
        return on_render_pixels(svg, *view.canvas_map(mesh.vertices))

    def page_options(self):
        """The ``page`` of ``crestline.draw``, or None."""
        if not self.page:
            return None
        given = {"paper": self.page, "landscape": self.landscape, "margin": self.margin, "pen": self.pen}
        return {name: value for name, value in given.items() if value != ""}


def on_render_pixels(svg, k, a, b):
    """``svg`` with every path point (x, y) moved to (k x + a, k y + b)."""

    def moved(match):
        x, y = float(match.group(2)), float(match.group(3))
        return f"{match.group(1)}{k * x + a:.2f} {k * y + b:.2f}"

    return re.sub(r'(?<= d=")[^"]*', lambda m: POINT.sub(moved, m.group(0)), svg)

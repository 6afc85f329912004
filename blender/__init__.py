"""crestline for Blender: the ridges, valleys and Morse lines of a mesh object as
Grease Pencil or curves (Object ‣ Feature Lines), and the camera's view as a
plotter-ready SVG line drawing (File ‣ Export ‣ Line drawing (crestline))."""

import bpy

from .feature_lines import OBJECT_OT_crestline_feature_lines
from .svg_export import CRESTLINE_OT_export_svg

CLASSES = (OBJECT_OT_crestline_feature_lines, CRESTLINE_OT_export_svg)


def object_menu(self, context):
    self.layout.operator(OBJECT_OT_crestline_feature_lines.bl_idname)


def export_menu(self, context):
    self.layout.operator(CRESTLINE_OT_export_svg.bl_idname, text="Line drawing (crestline)")


MENUS = ((bpy.types.VIEW3D_MT_object, object_menu), (bpy.types.TOPBAR_MT_file_export, export_menu))


def register():
    for cls in CLASSES:
        bpy.utils.register_class(cls)
    for menu, entry in MENUS:
        menu.append(entry)


def unregister():
    for menu, entry in MENUS:
        menu.remove(entry)
    for cls in reversed(CLASSES):
        bpy.utils.unregister_class(cls)

"""The lines as Blender data: a Grease Pencil object with a layer per family, or a
curve object of poly splines with a bevel; either a child of the mesh object, in
its local coordinates, replacing the lines made before."""

import bpy
import numpy as np

import crestline

from .colours import family_colours, linear

MARK = "crestline_lines"
"""The custom property that marks an object made here (its value: the output)."""

FAMILY_OF_KIND = crestline.families()
"""A line's family (the drawings' layer name) by its kind, as the library names them."""


def family(line):
    """The family of ``line``: ``"ridges"``, ``"valleys"``, ``"ascending"``, ..."""
    return FAMILY_OF_KIND[line.kind]


def families(frames):
    """The families of the lines of every frame, in order of first appearance."""
    return list(dict.fromkeys(family(line) for lines in frames.values() for line in lines))


def replace_lines(context, parent, frames, output, radius):
    """A new object holding ``frames`` (``{frame number: crestline.Lines}``) as
    ``output`` (``'GREASE_PENCIL'`` or ``'CURVE'``; a curve holds one frame),
    lines ``radius`` thick, parented to ``parent`` after the lines made on it
    before are removed. Returns the object."""
    remove_lines(parent)
    name = f"{parent.name} Lines"
    if output == "GREASE_PENCIL":
        data = grease_pencil(name, frames, radius)
    else:
        (lines,) = frames.values()
        data = curve(name, lines, radius)
    obj = bpy.data.objects.new(name, data)
    obj[MARK] = output
    context.collection.objects.link(obj)
    obj.parent = parent
    obj.matrix_parent_inverse.identity()
    obj.matrix_basis.identity()
    return obj


def remove_lines(parent):
    """Delete the children of ``parent`` made here, with their data."""
    for child in list(parent.children):
        if MARK in child:
            data = child.data
            bpy.data.objects.remove(child)
            if data is not None and data.users == 0:
                collection_of(data).remove(data)


def collection_of(data):
    """The ``bpy.data`` collection holding ``data`` (a curve or a Grease Pencil)."""
    return bpy.data.curves if isinstance(data, bpy.types.Curve) else grease_pencils()


def grease_pencils():
    """Grease Pencil (v3) data: ``bpy.data.grease_pencils_v3`` in Blender 4.3 and
    4.4, ``bpy.data.grease_pencils`` from 4.5 on."""
    return getattr(bpy.data, "grease_pencils_v3", None) or bpy.data.grease_pencils


def material(name, colour, grease_pencil_material):
    """The material ``crestline <name>`` of the family's colour: a Grease Pencil
    stroke, or an emission shader (the line's colour whatever the lighting) for
    curves rendered by Cycles and EEVEE. Made once, then reused."""
    full = f"crestline {name}" + (" stroke" if grease_pencil_material else "")
    found = bpy.data.materials.get(full)
    if found is not None:
        return found
    made = bpy.data.materials.new(full)
    made.diffuse_color = (*linear(colour), 1.0)
    if grease_pencil_material:
        bpy.data.materials.create_gpencil_data(made)
        made.grease_pencil.color = (*linear(colour), 1.0)
    else:
        emission_shader(made, linear(colour))
    return made


def emission_shader(made, colour):
    """Make ``made``'s node tree an emission of ``colour`` (linear RGB)."""
    if made.node_tree is None:  # Blender before 5.0: materials start without nodes
        made.use_nodes = True
    nodes = made.node_tree.nodes
    nodes.clear()
    emission = nodes.new("ShaderNodeEmission")
    emission.inputs["Color"].default_value = (*colour, 1.0)
    emission.inputs["Strength"].default_value = 1.0
    out = nodes.new("ShaderNodeOutputMaterial")
    made.node_tree.links.new(emission.outputs["Emission"], out.inputs["Surface"])


def grease_pencil(name, frames, radius):
    """Grease Pencil data: a layer per family, a keyframe per frame, a stroke per
    line, each family's material."""
    data = grease_pencils().new(name)
    colours = family_colours()
    names = families(frames)
    for index, family_name in enumerate(names):
        data.materials.append(material(family_name, colours[family_name], True))
        layer = data.layers.new(family_name)
        for number, lines in frames.items():
            drawing = layer.frames.new(number).drawing
            chosen = [line for line in lines if family(line) == family_name]
            fill_drawing(drawing, chosen, index, radius)
    return data


def fill_drawing(drawing, lines, material_index, radius):
    """Strokes of ``lines`` in an empty Grease Pencil drawing."""
    if not lines:
        return
    drawing.add_strokes([len(line.points) for line in lines])
    points = np.concatenate([line.points for line in lines]).astype(np.float32)
    set_attribute(drawing, "position", "FLOAT_VECTOR", "POINT", "vector", points.ravel())
    set_attribute(drawing, "radius", "FLOAT", "POINT", "value", np.full(len(points), radius, np.float32))
    set_attribute(drawing, "cyclic", "BOOLEAN", "CURVE", "value", np.array([line.closed for line in lines]))
    set_attribute(drawing, "material_index", "INT", "CURVE", "value", np.full(len(lines), material_index, np.int32))


def set_attribute(drawing, name, kind, domain, key, values):
    """Write ``values`` into the drawing's attribute ``name``, made if missing."""
    attribute = drawing.attributes.get(name) or drawing.attributes.new(name, kind, domain)
    attribute.data.foreach_set(key, values)
    drawing.tag_positions_changed()


def curve(name, lines, radius):
    """Curve data: a poly spline per line, beveled to ``radius``, each family's
    emission material."""
    data = bpy.data.curves.new(name, "CURVE")
    data.dimensions = "3D"
    data.bevel_depth = radius
    data.bevel_resolution = 2
    data.use_fill_caps = True
    colours = family_colours()
    names = families({0: lines})
    for family_name in names:
        data.materials.append(material(family_name, colours[family_name], False))
    for line in lines:
        spline = data.splines.new("POLY")
        spline.points.add(len(line.points) - 1)
        homogeneous = np.hstack([line.points, np.ones((len(line.points), 1))])
        spline.points.foreach_set("co", homogeneous.ravel())
        spline.use_cyclic_u = line.closed
        spline.material_index = names.index(family(line))
    return data

"""The arrays of a Blender object's mesh as evaluated (modifiers, shape keys and
armatures applied), triangulated, in local or world coordinates."""

import numpy as np

from .tracing import Problem


def mesh_arrays(obj, depsgraph, world=False):
    """``(vertices, faces)`` of ``obj`` evaluated in ``depsgraph``: (n, 3) float64
    and (m, 3) int64, in the object's local coordinates (the world's with
    ``world``). Raises :class:`Problem` for an object that is not a mesh or whose
    mesh has no triangles."""
    if obj is None:
        raise Problem("no active object")
    if obj.type != "MESH":
        raise Problem(f"'{obj.name}' is not a mesh (its type is {obj.type})")
    evaluated = obj.evaluated_get(depsgraph)
    mesh = evaluated.to_mesh()
    try:
        vertices = np.empty(3 * len(mesh.vertices), dtype=np.float64)
        mesh.vertices.foreach_get("co", vertices)
        mesh.calc_loop_triangles()
        faces = np.empty(3 * len(mesh.loop_triangles), dtype=np.int64)
        mesh.loop_triangles.foreach_get("vertices", faces)
    finally:
        evaluated.to_mesh_clear()
    if len(vertices) == 0:
        raise Problem(f"the mesh of '{obj.name}' is empty")
    if len(faces) == 0:
        raise Problem(f"the mesh of '{obj.name}' has no faces (only vertices or edges)")
    vertices = vertices.reshape(-1, 3)
    if world:
        vertices = transformed(vertices, obj.matrix_world)
    return vertices, faces.reshape(-1, 3)


def transformed(points, matrix):
    """``points`` (n, 3) moved by the 4 × 4 ``matrix``."""
    m = np.array(matrix, dtype=np.float64)
    return points @ m[:3, :3].T + m[:3, 3]


def unit_in_local(obj):
    """The length of one world unit in the object's local coordinates (the inverse
    of its mean scale)."""
    volume = abs(np.linalg.det(np.array(obj.matrix_world, dtype=np.float64)[:3, :3]))
    return 1.0 / volume ** (1.0 / 3.0) if volume > 0 else 1.0


def merged(parts):
    """One ``(vertices, faces)`` of several, the faces renumbered."""
    offsets = np.cumsum([0] + [len(v) for v, _ in parts[:-1]])
    return (
        np.concatenate([v for v, _ in parts]),
        np.concatenate([f + offset for (_, f), offset in zip(parts, offsets)]),
    )

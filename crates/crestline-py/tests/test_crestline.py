"""Tests of the Python package: arrays in and out with the right shapes and
dtypes, curvature of a sphere, ridges of the bunny, mesh objects, and a clear
exception for every bad argument."""

from pathlib import Path

import numpy as np
import pytest

import crestline

ROOT = Path(__file__).resolve().parents[3]
BUNNY = ROOT / "meshes" / "bunny.obj"


def icosphere(radius, subdivisions):
    """A sphere of `radius`: an icosahedron subdivided `subdivisions` times, its
    vertices pushed onto the sphere; faces counter-clockwise seen from outside."""
    t = (1 + 5**0.5) / 2
    vertices = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t),
                (0, -1, -t), (0, 1, -t), (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    faces = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4),
             (11, 10, 2), (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8),
             (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    vertices = [np.array(v, float) / np.linalg.norm(v) for v in vertices]
    for _ in range(subdivisions):
        middle = {}

        def mid(a, b):
            key = (min(a, b), max(a, b))
            if key not in middle:
                m = vertices[a] + vertices[b]
                vertices.append(m / np.linalg.norm(m))
                middle[key] = len(vertices) - 1
            return middle[key]

        faces = [tri for a, b, c in faces
                 for tri in ((a, mid(a, b), mid(c, a)), (b, mid(b, c), mid(a, b)),
                             (c, mid(c, a), mid(b, c)), (mid(a, b), mid(b, c), mid(c, a)))]
    return radius * np.array(vertices), np.array(faces, dtype=np.int64)


def test_read_mesh_gives_float64_vertices_int64_faces_and_the_repairs():
    vertices, faces, repairs = crestline.read_mesh(BUNNY)
    assert vertices.dtype == np.float64 and vertices.shape[1] == 3
    assert faces.dtype == np.int64 and faces.shape[1] == 3
    assert faces.min() == 0 and faces.max() == len(vertices) - 1
    assert repairs["welded_vertices"] == 0 and set(repairs) >= {"flipped_faces", "cut_edges"}


def test_curvature_of_a_sphere_is_one_over_its_radius_at_every_scale():
    scaled = []
    for radius in (0.01, 2.0, 1000.0):
        vertices, faces = icosphere(radius, 4)
        n = len(vertices)
        field = crestline.curvature(vertices, faces)
        assert {k: v.shape for k, v in field.items()} == {
            "k_max": (n,), "k_min": (n,), "d_max": (n, 3), "d_min": (n, 3), "normal": (n, 3), "unreliable": (n,)}
        assert field["unreliable"].dtype == np.bool_
        # The discrete shape operator is off by up to 15% at the icosahedron's
        # twelve five-neighbour vertices and their rings, close elsewhere.
        for k in (field["k_max"], field["k_min"]):
            assert np.median(np.abs(k * radius - 1)) < 0.005
            assert np.abs(k * radius - 1).max() < 0.2
        # The jet fit is exact to second order.
        jet = crestline.curvature(vertices, faces, estimator="jet-fit")
        assert np.abs(jet["k_max"] * radius - 1).max() < 1e-3
        # Outward normals: along the position on a sphere about the origin.
        assert np.einsum("ij,ij->i", field["normal"], vertices / radius).min() > 0.999
        scaled.append(field["k_max"] * radius)
    # The same numbers at every scale.
    assert np.abs(scaled[0] - scaled[2]).max() < 1e-9


def test_ridges_of_the_bunny_are_lines_with_per_point_values():
    vertices, faces, _ = crestline.read_mesh(BUNNY)
    lines = crestline.ridges(vertices, faces)
    assert len(lines) > 20
    assert set(lines.kinds()) == {"ridge", "valley"}
    for line in lines:
        n = len(line)
        assert line.points.shape == (n, 3) and line.points.dtype == np.float64
        assert n >= (3 if line.closed else 2)
        assert line.strength >= 2.0  # the default threshold
        assert sorted(line.values) == ["e_max", "e_min", "k_max", "k_min"]
        assert all(len(v) == n for v in line.values.values())
    # A stricter threshold keeps fewer lines, and never a weaker one.
    strong = crestline.ridges(vertices, faces, threshold=10.0)
    assert 0 < len(strong) < len(lines)
    assert min(line.strength for line in strong) >= 10.0


def test_morse_lines_follow_the_given_values():
    vertices, faces, _ = crestline.read_mesh(BUNNY)
    lines = crestline.morse(vertices, faces, keep_saddles=20)
    assert 0 < len(lines) <= 2 * 20
    assert lines.kinds().keys() == {"ascending"}
    # With the height as the indicator, the lines climb to its maxima: the
    # indicator they carry is the height of their points.
    height = vertices[:, 1]
    climbing = crestline.morse(vertices, faces, indicator=height, keep_saddles=5)
    assert climbing
    for line in climbing:
        assert np.abs(line.values["indicator"] - line.points[:, 1]).max() < 1e-9
    with pytest.raises(ValueError, match=r"indicator: expected shape"):
        crestline.morse(vertices, faces, indicator=height[:-1])
    with pytest.raises(ValueError, match=r"indicator: expected one of"):
        crestline.morse(vertices, faces, indicator="height")
    # kmax by name (the library's and the tool's name) is k_max of the estimator.
    by_name = crestline.morse(vertices, faces, indicator="kmax", keep_saddles=5)
    k_max = crestline.curvature(vertices, faces)["k_max"]
    by_values = crestline.morse(vertices, faces, indicator=k_max, keep_saddles=5)
    assert len(by_name) == len(by_values) > 0
    for a, b in zip(by_name, by_values):
        assert np.array_equal(a.points, b.points)


def test_repair_mesh_repairs_arrays_as_read_mesh_repairs_their_file(tmp_path):
    vertices, faces = icosphere(1.0, 2)
    n = len(vertices)
    # A copy of vertex 0 that the first face around it uses, a loose vertex, and a
    # degenerate face (a repeated corner).
    copied = np.vstack([vertices, vertices[:1], [[3.0, 3.0, 3.0]]])
    first = int(np.argmax((faces == 0).any(axis=1)))
    broken = faces.copy()
    broken[first] = np.where(broken[first] == 0, n, broken[first])
    broken = np.vstack([broken, [[1, 1, 2]]])
    with pytest.raises(ValueError, match="renumber its vertices"):
        crestline.Mesh(copied, broken)

    repaired, repaired_faces, repairs = crestline.repair_mesh(copied, broken)
    crestline.write_mesh(tmp_path / "broken.ply", copied, broken)
    read, read_faces, read_repairs = crestline.read_mesh(tmp_path / "broken.ply")
    assert np.array_equal(repaired, read) and np.array_equal(repaired_faces, read_faces)
    assert repairs == read_repairs
    assert repaired.dtype == np.float64 and repaired_faces.dtype == np.int64
    nonzero = {name: count for name, count in repairs.items() if count}
    assert nonzero == {"welded_vertices": 1, "unreferenced_vertices": 1, "degenerate_faces": 1}
    # The copy welded into vertex 0, the loose vertex and the degenerate face
    # dropped: the sphere as it was, which the functions on arrays take.
    assert np.array_equal(repaired, vertices) and np.array_equal(repaired_faces, faces)
    assert crestline.Mesh(repaired, repaired_faces).faces.shape == faces.shape


def test_repair_mesh_refuses_bad_arrays_and_a_mesh_without_faces():
    vertices, faces = icosphere(1.0, 1)
    unknown = vertices.copy()
    unknown[3, 1] = np.nan
    with pytest.raises(ValueError, match="vertices: row 3 is not finite"):
        crestline.repair_mesh(unknown, faces)
    with pytest.raises(ValueError, match=r"faces: expected shape \(m, 3\)"):
        crestline.repair_mesh(vertices, faces[:, :2])
    with pytest.raises(ValueError, match="faces: row 0 .* refers to a vertex outside"):
        crestline.repair_mesh(vertices, faces + len(vertices))
    with pytest.raises(crestline.MeshError, match="no faces"):
        crestline.repair_mesh(vertices, np.array([[0, 0, 1], [2, 2, 2]]))


def test_objects_with_vertices_and_faces_are_accepted():
    class Mesh:  # the shape of a trimesh.Trimesh
        def __init__(self, vertices, faces):
            self.vertices, self.faces = vertices, faces

    vertices, faces = icosphere(1.0, 4)
    from_object = crestline.curvature(Mesh(vertices, faces))
    from_arrays = crestline.curvature(vertices, faces)
    assert np.array_equal(from_object["k_max"], from_arrays["k_max"])
    # float32 vertices and int32 faces are converted.
    converted = crestline.curvature(vertices.astype(np.float32), faces.astype(np.int32))
    assert np.abs(converted["k_max"] - from_arrays["k_max"]).max() < 1e-4


@pytest.mark.parametrize(
    "change, error, words",
    [
        (lambda v, f: (v[:, :2], f), ValueError, "vertices: expected shape (n, 3)"),
        (lambda v, f: (np.where(np.arange(len(v))[:, None] == 7, np.nan, v), f), ValueError, "vertices: row 7 is not finite"),
        (lambda v, f: (v, f[:, :2]), ValueError, "faces: expected shape (m, 3)"),
        (lambda v, f: (v, f.astype(float)), TypeError, "faces: expected integer"),
        (lambda v, f: (v, np.where(f == 0, len(v), f)), ValueError, "refers to a vertex outside"),
        (lambda v, f: (v, -f), ValueError, "refers to a vertex outside"),
        (lambda v, f: ("not numbers", f), TypeError, "vertices: expected real numbers"),
        (lambda v, f: (np.vstack([v, v[:1]]), np.where(f == 0, len(v), f)), ValueError, "renumber its vertices"),
    ],
)
def test_bad_arrays_raise_an_exception_naming_the_argument(change, error, words):
    vertices, faces = icosphere(1.0, 1)
    bad_vertices, bad_faces = change(vertices, faces)
    with pytest.raises(error, match=words.replace("(", r"\(").replace(")", r"\)")):
        crestline.curvature(bad_vertices, bad_faces)


def test_bad_options_and_files_raise_clear_errors():
    vertices, faces = icosphere(1.0, 1)
    with pytest.raises(ValueError, match="estimator: expected one of"):
        crestline.curvature(vertices, faces, estimator="magic")
    with pytest.raises(ValueError, match="smooth_steps"):
        crestline.ridges(vertices, faces, smooth_steps=-1)
    with pytest.raises(ValueError, match="threshold"):
        crestline.ridges(vertices, faces, threshold=float("nan"))
    with pytest.raises(crestline.FileError, match="no-such-mesh.obj") as raised:
        crestline.read_mesh("no-such-mesh.obj")
    assert raised.value.path == "no-such-mesh.obj"
    assert isinstance(raised.value, crestline.Error)
    with pytest.raises(TypeError, match="faces: missing"):
        crestline.curvature(vertices)

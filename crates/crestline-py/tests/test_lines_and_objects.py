"""Tests of the Lines object, drawings, callable estimators, progress, the
exception hierarchy and the mesh objects of trimesh, pymeshlab and pyvista."""

from pathlib import Path
from xml.etree import ElementTree

import numpy as np
import pytest

import crestline

ROOT = Path(__file__).resolve().parents[3]
BUNNY = ROOT / "meshes" / "bunny.obj"


@pytest.fixture(scope="module")
def bunny():
    vertices, faces, _ = crestline.read_mesh(BUNNY)
    return vertices, faces


def test_lines_are_a_sequence_of_lines_located_on_the_mesh(bunny):
    vertices, faces = bunny
    lines = crestline.ridges(vertices, faces)
    assert isinstance(lines, crestline.Lines) and isinstance(lines[0], crestline.Line)
    counts = lines.kinds()
    assert repr(lines) == f"Lines({counts['ridge']} ridge, {counts['valley']} valley)"
    assert len(lines.of_kind("ridge")) == counts["ridge"] and len(lines[:3]) == 3
    assert [line.kind for line in lines] == [d["kind"] for d in lines.to_list()]
    for line in lines:
        # Every point is where its location on the mesh says it is.
        assert line.location_vertices.shape == (len(line), 3)
        assert line.location_vertices.dtype == np.int64
        weights = line.location_weights
        assert np.allclose(weights.sum(axis=1), 1) and weights.min() >= 0
        on_mesh = (weights[:, :, None] * vertices[line.location_vertices]).sum(axis=1)
        assert np.abs(on_mesh - line.points).max() < 1e-9
        assert line.length() > 0


def test_a_drawing_is_svg_with_the_lines_and_a_png_on_request(bunny):
    vertices, faces = bunny
    lines = crestline.ridges(vertices, faces)
    svg = crestline.draw(vertices, faces, lines, view=(20, 15), size=(400, 300), silhouettes=True)
    assert svg.startswith("<?xml") and 'width="400"' in svg and 'height="300"' in svg
    assert 'id="ridges"' in svg and 'id="valleys"' in svg and 'id="silhouettes"' in svg
    svg_again, png = crestline.draw(vertices, faces, lines, view=(20, 15), size=(400, 300), silhouettes=True,
                                    png=True)
    assert svg_again == svg and png.startswith(b"\x89PNG\r\n\x1a\n")
    plain = crestline.draw(vertices, faces, crestline.Lines([]), silhouettes=False)
    assert 'id="ridges"' not in plain and 'id="silhouettes"' not in plain
    with pytest.raises(ValueError, match="size"):
        crestline.draw(vertices, faces, lines, size=(0, 100))
    with pytest.raises(ValueError, match="view"):
        crestline.draw(vertices, faces, lines, view=(float("nan"), 0))
    with pytest.raises(TypeError, match="lines: expected crestline.Lines"):
        crestline.draw(vertices, faces, [{"kind": "ridge"}])


def test_every_kind_is_drawn_in_the_layer_of_its_family_in_its_colour(bunny):
    # Each kind alone, drawn as the ridges' copies: the drawing's only layer is the
    # kind's family, its stroke the family's colour.
    vertices, faces = bunny
    ridges = crestline.ridges(vertices, faces).of_kind("ridge")
    families, colors = crestline.families(), crestline.colors()
    assert {"ridge": "ridges", "valley": "valleys", "ascending": "ascending"}.items() <= families.items()
    assert list(colors) == list(dict.fromkeys(families.values()))
    drawn = {}
    for kind in families:
        lines = crestline.Lines(crestline.Line(kind, line.closed, line.strength, line.points) for line in ridges)
        svg = ElementTree.fromstring(crestline.draw(vertices, faces, lines, view=(20, 15), silhouettes=False))
        (layer,) = svg.iter("{http://www.w3.org/2000/svg}g")
        drawn[kind] = (layer.get("id"), layer.get("stroke"))
    assert drawn == {kind: (family, colors[family]) for kind, family in families.items()}
    assert colors["ridges"] != colors["valleys"]


def test_a_callable_estimator_is_used_as_given(bunny):
    vertices, faces = bunny
    calls = []

    def jet(v, f):
        calls.append(len(v))
        return crestline.curvature(v, f, estimator="jet-fit")

    field = crestline.curvature(vertices, faces, estimator=jet)
    assert np.array_equal(field["k_max"], crestline.curvature(vertices, faces, estimator="jet-fit")["k_max"])
    # The lines of the callable's curvature are those of the named estimator.
    given = crestline.ridges(vertices, faces, estimator=jet)
    named = crestline.ridges(vertices, faces, estimator="jet-fit")
    assert len(given) == len(named) > 0
    for a, b in zip(given, named):
        assert a.kind == b.kind and np.array_equal(a.points, b.points)
    # Morse lines of the callable's curvedness are those of the named estimator's.
    assert len(crestline.morse(vertices, faces, estimator=jet, keep_saddles=10)) == len(
        crestline.morse(vertices, faces, estimator="jet-fit", keep_saddles=10))
    assert calls == [len(vertices)] * 3
    # The jet fit's extremalities travel with its curvature; the shape operator
    # has none.
    assert {"e_max", "e_min", "fit_residual"} <= set(field)
    assert not {"e_max", "e_min", "fit_residual"} & set(crestline.curvature(vertices, faces))
    with pytest.raises(ValueError, match="'e_max' and 'e_min' without the other"):
        crestline.ridges(vertices, faces, estimator=lambda v, f: {k: x for k, x in jet(v, f).items() if k != "e_min"})
    # Its results are checked.
    with pytest.raises(ValueError, match="estimator result 'k_min': expected shape"):
        crestline.ridges(vertices, faces, estimator=lambda v, f: {**jet(v, f), "k_min": np.zeros(3)})
    with pytest.raises(ValueError, match="has no 'd_max'"):
        crestline.curvature(vertices, faces, estimator=lambda v, f: {k: jet(v, f)[k] for k in ("k_max", "k_min")})
    with pytest.raises(TypeError, match="returned list"):
        crestline.curvature(vertices, faces, estimator=lambda v, f: [])


def test_progress_is_told_of_every_stage_start_and_end(bunny):
    vertices, faces = bunny
    events = []
    crestline.ridges(vertices, faces, progress=lambda stage, seconds: events.append((stage, seconds)))
    started = [stage for stage, seconds in events if seconds is None]
    finished = [stage for stage, seconds in events if seconds is not None]
    assert started == finished and {"extremality", "smoothing", "ridges: tracing"} <= set(started)
    assert all(seconds >= 0 for _, seconds in events if seconds is not None)
    with pytest.raises(TypeError, match="progress: expected a callable"):
        crestline.ridges(vertices, faces, progress="yes")


def test_library_errors_are_subclasses_of_crestline_error(tmp_path):
    broken = tmp_path / "broken.obj"
    broken.write_text("v 0 0 0\nv 1 0 0\nf 1 2 9\n")
    with pytest.raises(crestline.FileError, match="broken.obj") as raised:
        crestline.read_mesh(broken)
    assert raised.value.path == str(broken)
    no_faces = np.zeros((0, 3), dtype=np.int64)
    with pytest.raises(crestline.MeshError) as raised:
        crestline.curvature(np.eye(3), no_faces)
    assert isinstance(raised.value, crestline.Error) and isinstance(raised.value, ValueError)
    assert issubclass(crestline.ArgumentError, crestline.Error)
    assert issubclass(crestline.StageError, crestline.Error)


def test_trimesh_objects_are_accepted(bunny):
    trimesh = pytest.importorskip("trimesh")
    vertices, faces = bunny
    mesh = trimesh.Trimesh(vertices, faces, process=False)
    assert np.array_equal(crestline.curvature(mesh)["k_max"], crestline.curvature(vertices, faces)["k_max"])


def test_pymeshlab_meshes_and_mesh_sets_are_accepted(bunny):
    pymeshlab = pytest.importorskip("pymeshlab")
    vertices, faces = bunny
    mesh = pymeshlab.Mesh(vertex_matrix=vertices, face_matrix=faces.astype(np.int32))
    expected = crestline.curvature(vertices, faces)["k_max"]
    assert np.array_equal(crestline.curvature(mesh)["k_max"], expected)
    meshes = pymeshlab.MeshSet()
    meshes.add_mesh(mesh)
    assert np.array_equal(crestline.curvature(meshes)["k_max"], expected)


def test_a_mesh_built_once_serves_every_call_as_its_arrays_would(bunny):
    vertices, faces = bunny
    mesh = crestline.Mesh(vertices, faces)
    assert repr(mesh) == f"crestline.Mesh({len(vertices)} vertices, {len(faces)} faces)"
    for name in ("k_max", "k_min", "d_max", "e_max"):
        built, given = crestline.curvature(mesh, estimator="jet-fit"), crestline.curvature(vertices, faces, estimator="jet-fit")
        assert np.array_equal(built[name], given[name])
    for trace in (crestline.ridges, crestline.morse):
        built, given = trace(mesh), trace(vertices, faces)
        assert len(built) == len(given) > 0
        for a, b in zip(built, given):
            assert a.kind == b.kind and np.array_equal(a.points, b.points)
    assert crestline.draw(mesh) == crestline.draw(vertices, faces)
    edges = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]])
    unique = np.unique(np.sort(edges, axis=1), axis=0)
    lengths = np.linalg.norm(vertices[unique[:, 0]] - vertices[unique[:, 1]], axis=1)
    assert mesh.mean_edge_length() == pytest.approx(lengths.mean(), rel=1e-12)


def test_a_built_mesh_holds_read_only_copies_of_its_arrays(bunny):
    vertices, faces = bunny
    moved = vertices.copy()
    mesh = crestline.Mesh(moved, faces)
    moved *= 2.0  # the caller's array changes; the mesh does not
    assert np.array_equal(mesh.vertices, vertices)
    with pytest.raises(ValueError, match="read-only"):
        mesh.vertices[0, 0] = 1.0
    with pytest.raises(ValueError, match="read-only"):
        mesh.faces[0, 0] = 1
    # Other functions take it as a mesh object with vertices and faces.
    other = crestline.curvature(crestline.Mesh(mesh))["k_max"]
    assert np.array_equal(other, crestline.curvature(vertices, faces)["k_max"])


def test_a_built_mesh_pickles_as_its_arrays(bunny):
    import pickle

    mesh = crestline.Mesh(*bunny)
    again = pickle.loads(pickle.dumps(mesh))
    assert np.array_equal(again.vertices, mesh.vertices) and np.array_equal(again.faces, mesh.faces)
    assert again.mean_edge_length() == mesh.mean_edge_length()
    assert np.array_equal(crestline.curvature(again)["k_max"], crestline.curvature(mesh)["k_max"])


def test_a_mesh_that_needs_renumbering_is_refused_when_built(bunny):
    vertices, faces = bunny
    doubled = np.vstack([vertices, vertices[:1]])  # an unreferenced vertex is dropped
    with pytest.raises(ValueError, match="renumber its vertices.*crestline.repair_mesh"):
        crestline.Mesh(doubled, faces)
    with pytest.raises(ValueError, match=r"faces: expected shape \(m, 3\)"):
        crestline.Mesh(vertices, faces[:, :2])


class PolyDataLike:
    """The layout of a pyvista PolyData: ``points`` and a flat ``faces`` array of
    ``[3, a, b, c, 3, ...]``, with ``n_cells``."""

    def __init__(self, points, flat_faces):
        self.points, self.faces = points, flat_faces
        self.n_cells = len(flat_faces) // 4


def test_polydata_of_triangles_is_accepted_and_polygons_are_refused(bunny):
    vertices, faces = bunny
    flat = np.hstack([np.full((len(faces), 1), 3), faces]).ravel()
    field = crestline.curvature(PolyDataLike(vertices, flat))
    assert np.array_equal(field["k_max"], crestline.curvature(vertices, faces)["k_max"])
    quads = np.array([4, 0, 1, 2, 3])
    with pytest.raises(ValueError, match="not triangles"):
        crestline.curvature(PolyDataLike(vertices, quads))


def test_lines_and_meshes_are_saved_as_the_tool_saves_them(bunny, tmp_path):
    import json

    vertices, faces = bunny
    lines = crestline.ridges(vertices, faces)
    lines.save(tmp_path / "lines.json")
    saved = json.loads((tmp_path / "lines.json").read_text())
    assert saved["format"].startswith("crestline-lines") and len(saved["lines"]) == len(lines)
    for line, written in zip(lines, saved["lines"]):
        assert written["kind"] == line.kind and written["strength"] == line.strength
        assert np.array_equal(np.array(written["points"]), line.points)
        assert np.array_equal(np.array(written["values"]["e_max"]), line.values["e_max"])
    for suffix in ("ply", "obj", "vtk"):
        lines.save(tmp_path / f"lines.{suffix}")
    assert_read_by_other_programs(lines, tmp_path)
    with pytest.raises(crestline.FileError, match="lines.txt"):
        lines.save(tmp_path / "lines.txt")
    assert not (tmp_path / "lines.txt").exists()

    k_max = crestline.curvature(vertices, faces)["k_max"]
    crestline.write_mesh(tmp_path / "bunny.ply", vertices, faces, {"k_max": k_max})
    again, again_faces, _ = crestline.read_mesh(tmp_path / "bunny.ply")
    assert np.array_equal(again, vertices) and np.array_equal(again_faces, faces)
    with pytest.raises(ValueError, match=r"values\['k_max'\]: expected shape"):
        crestline.write_mesh(tmp_path / "short.ply", vertices, faces, {"k_max": k_max[:5]})


def test_compare_reads_lines_that_meshio_and_vtk_write(tmp_path):
    """The bunny's lines written as VTK by meshio (5.1: an unstructured grid of
    segments, offsets, connectivity and a field array `kind`) and by VTK's own
    legacy writer (4.2: poly data, counted cells and a scalar `kind`) compare with
    the lines' JSON as the same lines, kind by kind."""
    meshio = pytest.importorskip("meshio")
    vtk = pytest.importorskip("vtk")
    lines = crestline.ridges(*crestline.read_mesh(ROOT / "meshes" / "bunny_small.obj")[:2])
    lines.save(tmp_path / "lines.json")
    codes = {"ridge": 0, "valley": 1}
    paths = [np.vstack([line.points, line.points[:1]]) if line.closed else line.points
             for line in lines]
    points = np.vstack(paths)
    starts = np.cumsum([0] + [len(p) for p in paths])
    cells = [np.arange(s, e) for s, e in zip(starts[:-1], starts[1:])]
    kinds = np.array([codes[line.kind] for line in lines], dtype=np.int32)
    # meshio writes an unstructured grid of two-point lines: each segment a cell.
    segments = np.vstack([np.column_stack([c[:-1], c[1:]]) for c in cells])
    segment_kinds = np.concatenate([np.full(len(c) - 1, k, dtype=np.int32) for c, k in zip(cells, kinds)])
    meshio.write(str(tmp_path / "meshio.vtk"),
                 meshio.Mesh(points, [("line", segments)], cell_data={"kind": [segment_kinds]}),
                 binary=False)

    polydata = vtk.vtkPolyData()
    vtk_points = vtk.vtkPoints()
    for p in points:
        vtk_points.InsertNextPoint(*p)
    polydata.SetPoints(vtk_points)
    vtk_lines = vtk.vtkCellArray()
    for c in cells:
        vtk_lines.InsertNextCell(len(c), [int(i) for i in c])
    polydata.SetLines(vtk_lines)
    kind = vtk.vtkIntArray()
    kind.SetName("kind")
    for k in kinds:
        kind.InsertNextValue(int(k))
    polydata.GetCellData().SetScalars(kind)
    writer = vtk.vtkPolyDataWriter()
    writer.SetFileName(str(tmp_path / "vtk.vtk"))
    writer.SetFileVersion(42)
    writer.SetInputData(polydata)
    writer.Write()

    for name in ("meshio.vtk", "vtk.vtk"):
        # VTK writes the points as floats of six significant digits.
        found = crestline.compare(tmp_path / "lines.json", tmp_path / name, tolerance="0.01%")
        rows = {row["kind"]: row for row in found["lines"]}
        assert set(rows) == {"ridge", "valley"}, name
        for row in rows.values():
            assert row["a_in_b"] == pytest.approx(1.0) and row["b_in_a"] == pytest.approx(1.0), name
        assert rows["ridge"]["b_count"] == (rows["ridge"]["a_count"] if name == "vtk.vtk"
                                            else sum(len(c) - 1 for c, k in zip(cells, kinds) if k == 0))


def polylines(lines):
    """Every line's points, a closed line's first point repeated at its end."""
    return [np.vstack([line.points, line.points[:1]]) if line.closed else line.points
            for line in lines]


def assert_read_by_other_programs(lines, folder):
    """``lines`` saved in ``folder`` as OBJ, VTK and PLY read back as the same
    polylines by programs other than ours: the OBJ's ``v`` and ``l`` records as
    written, VTK's own legacy reader, and pymeshlab's PLY reader (points and
    edges)."""
    expected = polylines(lines)
    records = [row.split() for row in (folder / "lines.obj").read_text().splitlines()]
    vertices = np.array([[float(t) for t in r[1:4]] for r in records if r and r[0] == "v"])
    obj = [vertices[[int(i) - 1 for i in r[1:]]] for r in records if r and r[0] == "l"]
    assert len(obj) == len(expected)
    for read, line in zip(obj, expected):
        assert np.array_equal(read, line)

    vtk = pytest.importorskip("vtk")
    from vtk.util.numpy_support import vtk_to_numpy

    reader = vtk.vtkPolyDataReader()
    reader.SetFileName(str(folder / "lines.vtk"))
    reader.ReadAllScalarsOn()
    reader.Update()
    data = reader.GetOutput()
    points = vtk_to_numpy(data.GetPoints().GetData())
    cells = data.GetLines()
    assert cells.GetNumberOfCells() == len(expected)
    ids = vtk.vtkIdList()
    cells.InitTraversal()
    for line in expected:
        cells.GetNextCell(ids)
        indices = [ids.GetId(k) for k in range(ids.GetNumberOfIds())]
        assert np.array_equal(points[indices], line)
    kinds = vtk_to_numpy(data.GetCellData().GetArray("kind"))
    assert list(kinds) == [{"ridge": 0, "valley": 1}[line.kind] for line in lines]

    pymeshlab = pytest.importorskip("pymeshlab")
    meshes = pymeshlab.MeshSet()
    meshes.load_new_mesh(str(folder / "lines.ply"))
    ply = meshes.current_mesh()
    assert ply.edge_number() == sum(len(line) - 1 for line in expected)
    assert np.allclose(ply.vertex_matrix(), np.vstack([line.points for line in lines]), rtol=0, atol=1e-6)

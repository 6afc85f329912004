"""FreeSurfer and GIfTI files through nibabel: what nibabel writes crestline reads,
and what crestline writes nibabel reads, vertex for vertex; fsaverage5's ridges
as labels. The label tests run the command-line tool (skipped when it is not
built) on data/fsaverage/ when tools/fetch_fsaverage.sh has fetched it, else on
the bundled meshes/fsaverage5_pial_left.obj."""

import json
import subprocess
from pathlib import Path

import numpy as np
import pytest

import crestline

from test_crestline import icosphere

nib = pytest.importorskip("nibabel")

ROOT = Path(__file__).resolve().parents[3]
TOOL = ROOT / "target" / "release" / "crestline"
NIFTI_INTENT_POINTSET = "NIFTI_INTENT_POINTSET"
NIFTI_INTENT_TRIANGLE = "NIFTI_INTENT_TRIANGLE"


def surface():
    """A closed, outward, float32-exact sphere of radius 60 mm."""
    vertices, faces = icosphere(60.0, 3)
    return vertices.astype(np.float32), faces.astype(np.int32)


def volume_info(cras, voxelsize=(1.0, 1.0, 1.0), xras=(-1, 0, 0), yras=(0, 0, -1), zras=(0, 1, 0)):
    return {
        "head": np.array([2, 0, 20], dtype=np.int32),
        "valid": "1  # volume info valid",
        "filename": "../mri/filled-pretess255.mgz",
        "volume": np.array([256, 240, 176]),
        "voxelsize": np.array(voxelsize, dtype=float),
        "xras": np.array(xras, dtype=float),
        "yras": np.array(yras, dtype=float),
        "zras": np.array(zras, dtype=float),
        "cras": np.array(cras, dtype=float),
    }


def tkr_to_scanner(points, info):
    """Scanner RAS of tkr-RAS points: vox2ras · tkr_vox2ras⁻¹, both built as
    FreeSurfer builds them (nibabel's MGHHeader does the same)."""
    sizes = info["voxelsize"]
    half = info["volume"] / 2.0
    directions = np.column_stack([info["xras"], info["yras"], info["zras"]]) * sizes
    vox2ras = np.eye(4)
    vox2ras[:3, :3] = directions
    vox2ras[:3, 3] = info["cras"] - directions @ half
    tkr = np.array([[-sizes[0], 0, 0], [0, 0, sizes[2]], [0, -sizes[1], 0]])
    tkr_vox2ras = np.eye(4)
    tkr_vox2ras[:3, :3] = tkr
    tkr_vox2ras[:3, 3] = -tkr @ half
    moved = vox2ras @ np.linalg.inv(tkr_vox2ras) @ np.column_stack([points, np.ones(len(points))]).T
    return moved[:3].T


def test_a_freesurfer_surface_without_footer_keeps_its_coordinates(tmp_path):
    vertices, faces = surface()
    path = tmp_path / "lh.pial"
    nib.freesurfer.write_geometry(str(path), vertices, faces)
    read, read_faces, repairs = crestline.read_mesh(path)
    assert not any(repairs.values()), repairs
    np.testing.assert_array_equal(read, vertices.astype(np.float64))
    np.testing.assert_array_equal(read_faces, faces)


@pytest.mark.parametrize(
    "info",
    [
        volume_info(cras=(5.25, -18.5, 12.0)),
        # FreeSurfer's conformed axes (LIA) turned about z, anisotropic voxels.
        volume_info(cras=(-3.0, 7.5, 1.25), voxelsize=(0.9, 1.1, 1.3), xras=(-0.8, -0.6, 0), yras=(0, 0, -1), zras=(-0.6, 0.8, 0)),
    ],
    ids=["conformed", "oblique"],
)
def test_a_freesurfer_surface_with_footer_is_placed_in_scanner_ras_and_written_as_gifti(tmp_path, info):
    vertices, faces = surface()
    path = tmp_path / "lh.white"
    nib.freesurfer.write_geometry(str(path), vertices, faces, volume_info=info)
    read, read_faces, _ = crestline.read_mesh(path)
    expected = tkr_to_scanner(vertices.astype(np.float64), info)
    assert np.abs(read - expected).max() < 1e-4
    np.testing.assert_array_equal(read_faces, faces)

    gifti = tmp_path / "lh.white.surf.gii"
    crestline.write_mesh(gifti, read, read_faces, space="RAS")
    image = nib.load(str(gifti))
    coords = image.agg_data(NIFTI_INTENT_POINTSET)
    triangles = image.agg_data(NIFTI_INTENT_TRIANGLE)
    np.testing.assert_array_equal(coords, read.astype(np.float32))
    assert np.abs(coords - expected).max() < 1e-4
    np.testing.assert_array_equal(triangles, faces)
    pointset = image.get_arrays_from_intent(NIFTI_INTENT_POINTSET)[0]
    assert pointset.coordsys.dataspace == 1  # NIFTI_XFORM_SCANNER_ANAT
    assert pointset.meta["AnatomicalStructurePrimary"] == "Other"
    # Without a frame the coordinates are written as they are, in an unknown space.
    crestline.write_mesh(gifti, read, read_faces)
    pointset = nib.load(str(gifti)).get_arrays_from_intent(NIFTI_INTENT_POINTSET)[0]
    assert pointset.coordsys.dataspace == 0  # NIFTI_XFORM_UNKNOWN
    np.testing.assert_array_equal(pointset.data, read.astype(np.float32))


# nibabel writes ASCII data row by row whatever ArrayIndexingOrder says: ASCII is
# written in row-major order only.
@pytest.mark.parametrize("encoding, ordering", [
    ("ASCII", "RowMajorOrder"),
    ("B64BIN", "RowMajorOrder"), ("B64BIN", "ColumnMajorOrder"),
    ("B64GZ", "RowMajorOrder"), ("B64GZ", "ColumnMajorOrder"),
])
def test_gifti_surfaces_in_every_encoding_read(tmp_path, encoding, ordering):
    vertices, faces = surface()
    # ASCII keeps float32 only with enough digits; nibabel writes 10.
    vertices = np.round(vertices, 3).astype(np.float32) if encoding == "ASCII" else vertices
    arrays = [
        nib.gifti.GiftiDataArray(vertices, intent=NIFTI_INTENT_POINTSET, datatype="NIFTI_TYPE_FLOAT32", encoding=encoding, ordering=ordering),
        nib.gifti.GiftiDataArray(faces, intent=NIFTI_INTENT_TRIANGLE, datatype="NIFTI_TYPE_INT32", encoding=encoding, ordering=ordering),
    ]
    path = tmp_path / "lh.sphere.surf.gii"
    nib.save(nib.gifti.GiftiImage(darrays=arrays), str(path))
    read, read_faces, _ = crestline.read_mesh(path)
    np.testing.assert_array_equal(read.astype(np.float32), vertices)
    np.testing.assert_array_equal(read_faces, faces)


def test_per_vertex_values_round_trip_bitwise(tmp_path):
    rng = np.random.default_rng(7)
    values = (rng.standard_normal(2562) * 0.3).astype(np.float32)
    curv = tmp_path / "lh.curv"
    nib.freesurfer.write_morph_data(str(curv), values)
    read = crestline.read_vertex_values(curv)
    np.testing.assert_array_equal(read.astype(np.float32).view(np.uint32), values.view(np.uint32))
    shape = tmp_path / "lh.thickness.shape.gii"
    array = nib.gifti.GiftiDataArray(values, intent="NIFTI_INTENT_SHAPE", datatype="NIFTI_TYPE_FLOAT32")
    nib.save(nib.gifti.GiftiImage(darrays=[array]), str(shape))
    np.testing.assert_array_equal(crestline.read_vertex_values(shape).astype(np.float32), values)

    out_curv = tmp_path / "out.curv"
    out_shape = tmp_path / "out.shape.gii"
    crestline.write_vertex_values(out_curv, read)
    crestline.write_vertex_values(out_shape, read, name="thickness", structure="CORTEX_RIGHT")
    with pytest.raises(ValueError, match="CortexLeft"):
        crestline.write_vertex_values(out_shape, read, structure="LeftCortex")
    back = nib.freesurfer.read_morph_data(str(out_curv))
    np.testing.assert_array_equal(back.astype(np.float32).view(np.uint32), values.view(np.uint32))
    image = nib.load(str(out_shape))
    np.testing.assert_array_equal(image.darrays[0].data.view(np.uint32), values.view(np.uint32))
    assert image.darrays[0].meta["Name"] == "thickness"
    assert image.meta["AnatomicalStructurePrimary"] == "CortexRight"
    assert image.darrays[0].intent == nib.nifti1.intent_codes["NIFTI_INTENT_SHAPE"]


@pytest.fixture(scope="module")
def tool():
    if not TOOL.exists():
        pytest.skip(f"{TOOL} is not built (run cargo build --release)")
    return TOOL


def fsaverage_pial():
    fetched = ROOT / "data" / "fsaverage" / "pial_left.gii"
    return fetched if fetched.exists() else ROOT / "meshes" / "fsaverage5_pial_left.obj"


def run(tool, *args):
    done = subprocess.run([str(tool), *map(str, args)], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    return done


def test_curvature_files_match_the_mesh_and_freesurfer_sign(tool, tmp_path):
    pial = fsaverage_pial()
    run(tool, "curvature", pial, "-o", tmp_path / "c.ply")
    run(tool, "curvature", pial, "-o", tmp_path / "lh.mean.curv")
    run(tool, "curvature", pial, "-o", tmp_path / "lh.mean.shape.gii", "--structure", "cortex_left")
    curv = nib.freesurfer.read_morph_data(str(tmp_path / "lh.mean.curv"))
    image = nib.load(str(tmp_path / "lh.mean.shape.gii"))
    # Workbench places a shape file by its file-level structure, in its spelling.
    assert image.meta["AnatomicalStructurePrimary"] == "CortexLeft"
    shape = image.darrays[0]
    assert curv.shape == shape.data.shape == (10242,)
    np.testing.assert_array_equal(curv, -shape.data)
    assert shape.meta["Name"] == "mean"
    assert "convex" in shape.meta["CurvatureSign"]


def test_fsaverage_ridges_as_labels(tool, tmp_path):
    pial = fsaverage_pial()
    gifti, label, lines = tmp_path / "lh.ridges.label.gii", tmp_path / "lh.ridges.label", tmp_path / "lines.json"
    for output in (gifti, label, lines):
        run(tool, "ridges", pial, "-o", output, "--structure", "CortexLeft")
    image = nib.load(str(gifti))
    assert image.meta["AnatomicalStructurePrimary"] == "CortexLeft"
    labels = image.darrays[0].data
    assert labels.shape == (10242,)
    assert set(np.unique(labels)) == {0, 1, 2}
    assert image.labeltable.get_labels_as_dict() == {0: "???", 1: "ridges", 2: "valleys"}
    vertices, values = nib.freesurfer.read_label(str(label), read_scalars=True)
    np.testing.assert_array_equal(vertices, np.flatnonzero(labels))
    np.testing.assert_array_equal(values, np.where(labels[vertices] == 1, 1.0, -1.0))

    # Each labelled vertex lies within one of its edges' length of a point of a
    # line of its family.
    positions, faces, repairs = crestline.read_mesh(pial)
    assert not any(repairs.values()), repairs
    edges = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]])
    lengths = np.linalg.norm(positions[edges[:, 0]] - positions[edges[:, 1]], axis=1)
    reach = np.zeros(len(positions))
    np.maximum.at(reach, edges[:, 0], lengths)
    np.maximum.at(reach, edges[:, 1], lengths)
    document = json.loads(lines.read_text())
    for family, kind in ((1, "ridge"), (2, "valley")):
        points = np.concatenate([np.array(line["points"]) for line in document["lines"] if line["kind"] == kind])
        labelled = np.flatnonzero(labels == family)
        nearest = np.array([np.linalg.norm(points - positions[v], axis=1).min() for v in labelled])
        assert (nearest <= reach[labelled]).all(), nearest.max()


def test_lines_save_labels_as_the_tool_does(tool, tmp_path):
    pial = fsaverage_pial()
    vertices, faces, _ = crestline.read_mesh(pial)
    lines = crestline.ridges(vertices, faces)
    mine, tools = tmp_path / "mine.label.gii", tmp_path / "tool.label.gii"
    lines.save_labels(mine, vertices, faces, structure="CortexLeft")
    lines.save_labels(tmp_path / "mine.label", vertices, faces)
    run(tool, "ridges", pial, "-o", tools, "--structure", "CortexLeft")
    assert nib.load(str(mine)).meta["AnatomicalStructurePrimary"] == "CortexLeft"
    labels = nib.load(str(mine)).darrays[0].data
    np.testing.assert_array_equal(labels, nib.load(str(tools)).darrays[0].data)
    np.testing.assert_array_equal(nib.freesurfer.read_label(str(tmp_path / "mine.label")), np.flatnonzero(labels))
    with pytest.raises(ValueError, match="location_vertices"):
        crestline.Lines([crestline.Line(kind="ridge", closed=False, strength=1.0, points=np.zeros((2, 3)))]).save_labels(mine, vertices, faces)

"""World frames, checked with the tools users open crestline's outputs with.

NIfTI, NRRD and MetaImage copies of one image (and a copy whose first index axis
runs the other way) are written by SimpleITK; crestline's surfaces, crest lines
and landmarks of each copy must land on the same physical points once read the
way their users' tools read them:

- models (``.vtk``, ``.ply``, ``.obj``) by 3D Slicer's rule, read in its source
  (``vtkMRMLModelStorageNode::ReadDataInternal`` and
  ``GetCoordinateSystemFromFileHeader``): the text ``SPACE=RAS`` or ``SPACE=LPS``
  in the legacy VTK header line, a PLY comment or the OBJ comment declares the
  frame, and a file without it is read as LPS. Slicer cannot run here, so the rule
  is applied to what VTK's own readers (vtkPolyDataReader, vtkPLYReader,
  vtkOBJReader) return;
- lines JSON by its ``space`` key; landmarks by their ``space``; transforms by
  SimpleITK.

The positions are then compared in LPS (SimpleITK's physical space) with the
image itself: a surface of level 80 sampled in the image must sit at the level,
which a mirrored reading does not. Skipped without the tool
(``cargo build --release``) or the Python packages of the ``test`` extra.
"""

import json
import subprocess
import tempfile
from pathlib import Path

import numpy as np
import pytest

sitk = pytest.importorskip("SimpleITK")
vtk = pytest.importorskip("vtk")

ROOT = Path(__file__).resolve().parents[3]
TOOL = ROOT / "target" / "release" / "crestline"
MNI = ROOT / "volumes" / "mni152_t1_1mm.nii.gz"
LEVEL = 80.0


def tool(*args, check=True):
    """Run the tool (skipping the test when it is not built)."""
    if not TOOL.exists():
        pytest.skip(f"{TOOL} is not built (run cargo build --release)")
    return subprocess.run([TOOL, *map(str, args)], check=check, capture_output=True, text=True)


def flipped_copy(image):
    """The image with its first index axis reversed and its geometry changed to
    match: every voxel keeps its physical place."""
    nx = image.GetSize()[0]
    array = sitk.GetArrayFromImage(image)[:, :, ::-1]
    flipped = sitk.GetImageFromArray(np.ascontiguousarray(array))
    flipped.SetSpacing(image.GetSpacing())
    direction = np.array(image.GetDirection()).reshape(3, 3)
    direction[:, 0] *= -1
    flipped.SetDirection(direction.ravel().tolist())
    flipped.SetOrigin(image.TransformIndexToPhysicalPoint((nx - 1, 0, 0)))
    return flipped


@pytest.fixture(scope="module")
def image():
    """The MNI template made slightly asymmetric (times 1 + 0.001 i / nx): the
    template is symmetric about x = 0, where exact ties would otherwise decide
    crest-line points differently in mirrored frames."""
    template = sitk.ReadImage(str(MNI), sitk.sitkFloat32)
    array = sitk.GetArrayFromImage(template)
    ramp = 1.0 + 1e-3 * np.arange(array.shape[2], dtype=np.float32) / array.shape[2]
    asymmetric = sitk.GetImageFromArray(array * ramp)
    asymmetric.CopyInformation(template)
    return asymmetric


@pytest.fixture(scope="module")
def copies(image, tmp_path_factory):
    """The image as NIfTI (RAS), NRRD and MetaImage (LPS), and a copy with its
    first index axis reversed as NIfTI and NRRD: name → path."""
    folder = tmp_path_factory.mktemp("copies")
    flipped = flipped_copy(image)
    paths = {}
    for name, copy, suffix in [("nifti", image, ".nii.gz"), ("nrrd", image, ".nrrd"), ("metaimage", image, ".mha"),
                               ("flipped-nifti", flipped, ".nii.gz"), ("flipped-nrrd", flipped, ".nrrd")]:
        paths[name] = folder / f"{name}{suffix}"
        sitk.WriteImage(copy, str(paths[name]))
    return paths


def sample(image, lps):
    """Trilinear samples of the image at physical (LPS) points; NaN outside."""
    spacing = np.array(image.GetSpacing())
    direction = np.array(image.GetDirection()).reshape(3, 3)
    origin = np.array(image.GetOrigin())
    index = (np.linalg.inv(direction * spacing) @ (lps - origin).T).T
    array = sitk.GetArrayFromImage(image).transpose(2, 1, 0)
    low = np.floor(index).astype(int)
    inside = np.all((low >= 0) & (low + 1 < np.array(array.shape)), axis=1)
    values = np.full(len(lps), np.nan)
    low, t = low[inside], index[inside] - low[inside]
    total = np.zeros(len(low))
    for corner in np.ndindex(2, 2, 2):
        weight = np.prod(np.where(corner, t, 1 - t), axis=1)
        i = low + corner
        total += weight * array[i[:, 0], i[:, 1], i[:, 2]]
    values[inside] = total
    return values


# Surfaces and lines come from the image smoothed by its feature scale (σ of
# 2.5 mm here): within 25% of the level in the image smoothed as much, as read
# right, mirrored far fewer.
AT_LEVEL = 0.6
MIRRORED = 0.15
SMOOTHED = {}


def smoothed(image):
    """The image smoothed by a Gaussian of the feature scale the tool reports for
    it at the level, as the tool smooths it."""
    if id(image) not in SMOOTHED:
        with tempfile.TemporaryDirectory() as folder:
            path, report = Path(folder) / "image.nii.gz", Path(folder) / "report.json"
            sitk.WriteImage(image, str(path))
            tool("iso", path, "--level", LEVEL, "-o", Path(folder) / "surface.ply", "--report", report)
            scale = json.loads(report.read_text())["counts"]["scale"]
        SMOOTHED[id(image)] = (image, sitk.SmoothingRecursiveGaussian(image, scale))
    return SMOOTHED[id(image)][1]


def at_level(image, lps):
    """The share of points where the image, smoothed as the tool smooths it, is
    within 25% of the level."""
    values = sample(smoothed(image), lps)
    return np.mean(np.abs(values - LEVEL) < 0.25 * LEVEL)


def slicer_frame(texts):
    """3D Slicer's reading of a model's header or comments: the frame its
    ``SPACE=`` mark names, LPS without one."""
    for text in texts:
        if "SPACE=RAS" in text:
            return "RAS"
        if "SPACE=LPS" in text:
            return "LPS"
    return "LPS"


def to_lps(points, frame):
    return points * np.array([-1.0, -1.0, 1.0]) if frame == "RAS" else points


def read_model(path):
    """The points of a model file in LPS, read by VTK's reader of its format and
    placed by Slicer's rule."""
    suffix = Path(path).suffix
    if suffix == ".vtk":
        reader = vtk.vtkPolyDataReader()
        reader.SetFileName(str(path))
        reader.Update()
        texts = [reader.GetHeader() or ""]
    elif suffix == ".ply":
        reader = vtk.vtkPLYReader()
        reader.SetFileName(str(path))
        reader.Update()
        comments = reader.GetComments()
        texts = [comments.GetValue(i) for i in range(comments.GetNumberOfValues())]
    else:
        reader = vtk.vtkOBJReader()
        reader.SetFileName(str(path))
        reader.Update()
        texts = [reader.GetComment() or ""]
    output = reader.GetOutput()
    points = np.array([output.GetPoint(i) for i in range(output.GetNumberOfPoints())])
    return to_lps(points, slicer_frame(texts)), output


@pytest.fixture(scope="module")
def surfaces(copies, tmp_path_factory):
    """``iso`` of every copy as VTK, PLY and OBJ: (copy, suffix) → LPS points."""
    folder = tmp_path_factory.mktemp("surfaces")
    found = {}
    for name, path in copies.items():
        for suffix in (".vtk", ".ply", ".obj"):
            out = folder / f"{name}{suffix}"
            tool("iso", path, "--level", LEVEL, "-o", out)
            found[name, suffix] = read_model(out)[0]
    return found


def test_surfaces_sit_at_the_level_of_their_image_as_slicer_reads_them(surfaces, image):
    for (name, suffix), lps in surfaces.items():
        assert len(lps) > 100_000, (name, suffix)
        share = at_level(image, lps)
        mirrored = at_level(image, lps * np.array([-1.0, -1.0, 1.0]))
        assert share > AT_LEVEL and mirrored < MIRRORED, (name, suffix, share, mirrored)


def test_surfaces_of_every_copy_coincide(surfaces):
    reference = surfaces["nifti", ".vtk"]
    for key, lps in surfaces.items():
        assert len(lps) == len(reference), key
        # The same points, in another order where the grid runs the other way.
        ours, theirs = np.sort(lps, axis=0), np.sort(reference, axis=0)
        assert np.abs(ours - theirs).max() < 1e-3, key


def test_crest_lines_and_landmarks_land_on_the_same_points(copies, image, tmp_path):
    found_points = {}
    for name, path in copies.items():
        lines_path = tmp_path / f"{name}.json"
        tool("crest-lines", path, "--level", LEVEL, "-o", lines_path)
        document = json.loads(lines_path.read_text())
        assert document["format"] == "crestline-lines/1.1"
        expected = "RAS" if "nifti" in name else "LPS"
        assert (document["space"], document["units"]) == (expected, "mm"), name
        points = np.concatenate([line["points"] for line in document["lines"]])
        lps = to_lps(points, document["space"])
        assert at_level(image, lps) > AT_LEVEL, name
        found_points[name] = lps
        marks = tmp_path / f"{name}.landmarks.json"
        tool("landmarks", path, "--level", LEVEL, "-o", marks)
        found = json.loads(marks.read_text())
        assert (found["space"], found["units"]) == (expected, "mm"), name
        positions = to_lps(np.array([p["position"] for p in found["points"]]), found["space"])
        found_points[name, "landmarks"] = positions
    for name in copies:
        for key, reference in [(name, found_points["nifti"]),
                               ((name, "landmarks"), found_points["nifti", "landmarks"])]:
            ours = found_points[key]
            assert len(ours) == len(reference), key
            assert np.abs(np.sort(ours, axis=0) - np.sort(reference, axis=0)).max() < 1e-3, key


def test_lines_read_by_vtk_and_meshio_carry_the_frame(copies, image, tmp_path):
    meshio = pytest.importorskip("meshio")
    for name in ("nifti", "flipped-nrrd"):
        tool("crest-lines", copies[name], "--level", LEVEL, "--seeds", 300, "-o", tmp_path / "lines.json")
        document = json.loads((tmp_path / "lines.json").read_text())
        lps = to_lps(np.concatenate([line["points"] for line in document["lines"]]), document["space"])
        for suffix in (".vtk", ".vtp", ".vtu"):
            out = tmp_path / f"lines{suffix}"
            tool("crest-lines", copies[name], "--level", LEVEL, "--seeds", 300, "-o", out)
            if suffix == ".vtk":
                from_vtk, output = read_model(out)
                assert output.GetNumberOfLines() == len(document["lines"]), name
            else:
                # Slicer's rule for XML files: the field-data string array SPACE.
                reader = vtk.vtkXMLPolyDataReader() if suffix == ".vtp" else vtk.vtkXMLUnstructuredGridReader()
                reader.SetFileName(str(out))
                reader.Update()
                output = reader.GetOutput()
                declared = output.GetFieldData().GetAbstractArray("SPACE")
                frame = "LPS" if declared is None else declared.GetValue(0)
                # .vtp declares the lines' frame; .vtu (for meshio, which refuses
                # string arrays) holds LPS points, which Slicer assumes.
                assert frame == (document["space"] if suffix == ".vtp" else "LPS"), (name, suffix)
                assert (declared is None) == (suffix == ".vtu"), (name, suffix)
                points = np.array([output.GetPoint(i) for i in range(output.GetNumberOfPoints())])
                from_vtk = to_lps(points, frame)
                cells = output.GetNumberOfLines() if suffix == ".vtp" else output.GetNumberOfCells()
                segments = sum(len(line["points"]) - 1 + line["closed"] for line in document["lines"])
                assert cells == (len(document["lines"]) if suffix == ".vtp" else segments), (name, suffix)
            assert np.abs(from_vtk - lps).max() < 1e-9, (name, suffix)
        mesh = meshio.read(tmp_path / "lines.vtu")
        assert np.abs(mesh.points - lps).max() < 1e-9
        assert len(mesh.cells_dict["line"]) == segments
        assert set(mesh.cell_data) >= {"strength", "kind", "line"}


def moved(image, transform):
    """The image moved by the inverse of `transform` (SimpleITK's resampling
    convention): anatomy at p in `image` lies at transform⁻¹(p)."""
    return sitk.Resample(image, image, transform, sitk.sitkLinear, 0.0)


def correlation(a, b):
    x, y = sitk.GetArrayFromImage(a).ravel(), sitk.GetArrayFromImage(b).ravel()
    return np.corrcoef(x, y)[0, 1]


def test_register_across_formats_recovers_the_motion(tmp_path):
    image = sitk.ReadImage(str(MNI), sitk.sitkFloat32)
    motion = sitk.Euler3DTransform()
    motion.SetCenter(image.TransformContinuousIndexToPhysicalPoint([s / 2 for s in image.GetSize()]))
    motion.SetRotation(0.06, -0.04, 0.08)
    motion.SetTranslation((4.0, -3.0, 2.0))
    moving_image = moved(image, motion)
    sitk.WriteImage(moving_image, str(tmp_path / "moving.nrrd"))
    fixed_lines, moving_lines = tmp_path / "fixed.json", tmp_path / "moving.json"
    tool("crest-lines", MNI, "--level", LEVEL, "-o", fixed_lines)
    tool("crest-lines", tmp_path / "moving.nrrd", "--level", LEVEL, "-o", moving_lines)
    transform_path = tmp_path / "transform.tfm"
    tool("register", fixed_lines, moving_lines, "-o", transform_path)
    transform = sitk.ReadTransform(str(transform_path))
    realigned = sitk.Resample(moving_image, image, transform, sitk.sitkLinear, 0.0)
    before, after = correlation(moving_image, image), correlation(realigned, image)
    assert after >= 0.99 and after > before, (before, after)

    # A lines file that does not say its frame is refused, unless --space says it;
    # --space contradicting a declared frame is refused.
    old = json.loads(moving_lines.read_text())
    old["format"] = "crestline-lines/1"
    del old["space"]
    undeclared = tmp_path / "old.json"
    undeclared.write_text(json.dumps(old))
    refused = tool("register", fixed_lines, undeclared, "-o", tmp_path / "t.tfm", check=False)
    assert refused.returncode == 1 and "--space" in refused.stderr, refused.stderr
    assert str(undeclared) in refused.stderr
    tool("register", undeclared, moving_lines, "--space", "LPS", "-o", tmp_path / "t.json")
    same = np.array(json.loads((tmp_path / "t.json").read_text())["matrix"])
    assert np.abs(same - np.eye(4)).max() < 1e-6
    contradicted = tool("register", fixed_lines, moving_lines, "--space", "RAS", "-o", tmp_path / "t.tfm",
                        check=False)
    assert contradicted.returncode == 1 and "contradicts" in contradicted.stderr, contradicted.stderr


def test_the_package_carries_the_frame_from_image_to_files(copies, image, tmp_path):
    import typing

    import crestline
    from crestline._jobs import NAMES

    assert typing.get_args(crestline.Space) == NAMES["space"]
    for name, path in copies.items():
        volume = crestline.read_volume(path)
        expected = "RAS" if "nifti" in name else "LPS"
        assert volume.space == expected, name
        lines = crestline.crest_lines(volume, LEVEL, seeds=100)
        assert lines.space == expected and lines[:3].space == expected
        lines.save(tmp_path / "lines.json")
        assert json.loads((tmp_path / "lines.json").read_text())["space"] == expected
        lines.save(tmp_path / "lines.vtk")
        lps, _ = read_model(tmp_path / "lines.vtk")
        assert at_level(image, lps) > AT_LEVEL, name
        found = crestline.landmarks(lines, unit=volume.voxel)
        assert found["space"] == expected
        crestline.write_landmarks(tmp_path / "marks.json", found)
        assert json.loads((tmp_path / "marks.json").read_text())["space"] == expected
        other = "LPS" if expected == "RAS" else "RAS"
        with pytest.raises(crestline.ArgumentError, match="contradicts"):
            crestline.write_landmarks(tmp_path / "marks.json", found, other)
        vertices, faces = crestline.isosurface(volume, LEVEL)
        crestline.write_mesh(tmp_path / "surface.ply", vertices, faces, space=volume.space)
        lps, _ = read_model(tmp_path / "surface.ply")
        assert at_level(image, lps) > AT_LEVEL, name
    # nibabel's images are NIfTI's world, RAS.
    nibabel = pytest.importorskip("nibabel")
    assert crestline.crest_lines(nibabel.load(MNI), LEVEL, seeds=20).space == "RAS"


# The parts of 3D Slicer's markups schema v1.0.3
# (Modules/Loadable/Markups/Resources/Schema/markups-schema-v1.0.3.json in Slicer's
# source, draft-07) that constrain what crestline writes, restated because the
# schema cannot be fetched here: the required keys, the types and every enum.
SLICER_MARKUPS_SCHEMA = {
    "$schema": "http://json-schema.org/draft-07/schema",
    "type": "object",
    "required": ["@schema", "markups"],
    "properties": {
        "@schema": {"type": "string"},
        "markups": {
            "type": "array",
            "items": {
                "type": "object",
                "required": ["type"],
                "properties": {
                    "type": {"type": "string",
                             "enum": ["Fiducial", "Line", "Angle", "Curve", "ClosedCurve", "Plane", "ROI"]},
                    "name": {"type": "string"},
                    "coordinateSystem": {"type": "string", "enum": ["LPS", "RAS"]},
                    "coordinateUnits": {"type": "string", "enum": ["mm", "um"]},
                    "locked": {"type": "boolean"},
                    "controlPoints": {
                        "type": "array",
                        "items": {
                            "type": "object",
                            "properties": {
                                "id": {"type": "string"},
                                "label": {"type": "string"},
                                "description": {"type": "string"},
                                "position": {"type": "array", "items": {"type": "number"},
                                             "minItems": 3, "maxItems": 3},
                                "positionStatus": {"type": "string", "enum": ["undefined", "preview", "defined"]},
                            },
                        },
                    },
                },
            },
        },
    },
}


def markups_points(path):
    """Validate a markups file against Slicer's schema; its control points in LPS."""
    jsonschema = pytest.importorskip("jsonschema")
    document = json.loads(Path(path).read_text())
    jsonschema.validate(document, SLICER_MARKUPS_SCHEMA)
    assert document["@schema"].endswith("markups-schema-v1.0.3.json#")
    points = [(m["coordinateSystem"], p["position"]) for m in document["markups"] for p in m["controlPoints"]]
    return np.array([to_lps(np.array(p), frame) for frame, p in points]), document


def test_markups_of_lines_and_landmarks_follow_slicers_schema_and_sit_on_the_image(copies, image, tmp_path):
    import crestline

    for name in ("nifti", "nrrd"):
        out = tmp_path / f"{name}.lines.mrk.json"
        tool("crest-lines", copies[name], "--level", LEVEL, "--seeds", 300, "-o", out)
        lps, document = markups_points(out)
        assert {m["type"] for m in document["markups"]} <= {"Curve", "ClosedCurve"}
        assert at_level(image, lps) > AT_LEVEL, name
        marks = tmp_path / f"{name}.landmarks.mrk.json"
        tool("landmarks", copies[name], "--level", LEVEL, "-o", marks)
        lps, document = markups_points(marks)
        assert document["markups"][0]["type"] == "Fiducial"
        assert at_level(image, lps) > AT_LEVEL, name
        lines = crestline.crest_lines(crestline.read_volume(copies[name]), LEVEL, seeds=100)
        lines.save(tmp_path / "package.mrk.json")
        lps, _ = markups_points(tmp_path / "package.mrk.json")
        assert at_level(image, lps) > AT_LEVEL, name
    # Lines of a mesh (no frame) as markups: LPS as given, the frame Slicer gives
    # the mesh itself.
    tool("ridges", ROOT / "meshes" / "bunny.obj", "-o", tmp_path / "bunny.mrk.json")
    tool("ridges", ROOT / "meshes" / "bunny.obj", "-o", tmp_path / "bunny.json")
    lps, _ = markups_points(tmp_path / "bunny.mrk.json")
    plain = np.concatenate([line["points"] for line in json.loads((tmp_path / "bunny.json").read_text())["lines"]])
    assert np.abs(lps - plain).max() < 1e-9


def test_output_space_writes_the_other_frame_and_says_so(copies, tmp_path):
    nifti = copies["nifti"]
    for suffix in (".vtk", ".ply"):
        tool("iso", nifti, "--level", LEVEL, "-o", tmp_path / f"ras{suffix}")
        tool("iso", nifti, "--level", LEVEL, "--output-space", "lps", "-o", tmp_path / f"lps{suffix}")
        ras, ras_mesh = read_model(tmp_path / f"ras{suffix}")
        lps, lps_mesh = read_model(tmp_path / f"lps{suffix}")
        assert np.abs(ras - lps).max() < 1e-9, suffix
        raw = np.array([lps_mesh.GetPoint(i) for i in range(lps_mesh.GetNumberOfPoints())])
        assert np.abs(raw - lps).max() == 0.0, "written in LPS, and marked so"
    # The curvature directions turn with the surface; the curvatures stay.
    meshio = pytest.importorskip("meshio")
    ras, lps = meshio.read(tmp_path / "ras.ply"), meshio.read(tmp_path / "lps.ply")
    assert np.array_equal(ras.point_data["k_max"], lps.point_data["k_max"])
    for axis, sign in (("x", -1.0), ("y", -1.0), ("z", 1.0)):
        assert np.array_equal(lps.point_data[f"dmax_{axis}"], sign * ras.point_data[f"dmax_{axis}"]), axis
    tool("crest-lines", nifti, "--level", LEVEL, "--seeds", 100, "-o", tmp_path / "ras.json")
    tool("crest-lines", nifti, "--level", LEVEL, "--seeds", 100, "--output-space", "LPS", "-o", tmp_path / "lps.json")
    ras, lps = (json.loads((tmp_path / f"{f}.json").read_text()) for f in ("ras", "lps"))
    assert (ras["space"], lps["space"]) == ("RAS", "LPS")
    points = [np.concatenate([line["points"] for line in d["lines"]]) for d in (ras, lps)]
    assert np.abs(to_lps(points[0], "RAS") - points[1]).max() == 0.0
    # A mesh that does not say its frame cannot be converted.
    refused = tool("ridges", ROOT / "meshes" / "bunny.obj", "--output-space", "LPS", "-o", tmp_path / "b.json",
                   check=False)
    assert refused.returncode == 1 and "--output-space" in refused.stderr, refused.stderr
    assert not (tmp_path / "b.json").exists()


def test_the_package_registers_across_frames_and_writes_transforms_itk_reads(tmp_path):
    import crestline

    image = sitk.ReadImage(str(MNI), sitk.sitkFloat32)
    motion = sitk.Euler3DTransform()
    motion.SetCenter(image.TransformContinuousIndexToPhysicalPoint([s / 2 for s in image.GetSize()]))
    motion.SetRotation(-0.05, 0.03, 0.07)
    motion.SetTranslation((-3.0, 2.0, 4.0))
    moving_image = moved(image, motion)
    sitk.WriteImage(moving_image, str(tmp_path / "moving.mha"))
    fixed = crestline.crest_lines(crestline.read_volume(MNI), LEVEL)
    moving = crestline.crest_lines(crestline.read_volume(tmp_path / "moving.mha"), LEVEL)
    assert (fixed.space, moving.space) == ("RAS", "LPS")
    found = crestline.register(fixed, moving)
    crestline.write_transform(tmp_path / "t.tfm", found)
    transform = sitk.ReadTransform(str(tmp_path / "t.tfm"))
    realigned = sitk.Resample(moving_image, image, transform, sitk.sitkLinear, 0.0)
    assert correlation(realigned, image) >= 0.99 > correlation(moving_image, image)
    # The same motion given in LPS writes the same file.
    flip = np.diag([-1.0, -1.0, 1.0, 1.0])
    crestline.write_transform(tmp_path / "lps.tfm", flip @ found["matrix"] @ flip, space="LPS")
    assert np.allclose(sitk.ReadTransform(str(tmp_path / "lps.tfm")).GetParameters(),
                       transform.GetParameters(), atol=1e-12)
    crestline.write_transform(tmp_path / "t.json", found)
    written = json.loads((tmp_path / "t.json").read_text())
    assert written["coordinate_system"] == "RAS" and np.allclose(written["matrix"], found["matrix"])
    with pytest.raises(crestline.ArgumentError, match="rotation"):
        crestline.write_transform(tmp_path / "bad.tfm", np.diag([2.0, 1.0, 1.0, 1.0]))

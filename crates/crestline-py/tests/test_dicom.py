"""DICOM series input: series written from the MNI template by
``tools/write_dicom_series.py`` (axis-aligned and rotated 10° off the axes, in
every transfer syntax it writes) read to the NIfTI's samples and LPS positions,
with the geometry SimpleITK's series reader finds; the same landmarks from the
series as from the NIfTI; and malformed series refused with one clear error.

Needs pydicom and nibabel (the writer's), SimpleITK for the comparisons with ITK;
the tests that need them skip when they are absent."""

import io
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import crestline

ROOT = Path(__file__).resolve().parents[3]
MNI = ROOT / "volumes" / "mni152_t1_1mm.nii.gz"
TOOL = ROOT / "target" / "release" / "crestline"
PYDICOM_DATA = ROOT / "data" / "dicom" / "pydicom"
RAS_TO_LPS = np.diag([-1.0, -1.0, 1.0, 1.0])
# Positions and directions are written as decimal strings of 16 characters (12 or
# more significant digits): below 1 m positions are exact to 1e-9 mm, and the
# rounded directions carried across 230 voxels move them by less than 1e-7 mm.
POSITION_TOLERANCE = 1e-6
# Slab of the template's planes for the tests that do not need the whole head.
SLAB = (80, 96)

pytest.importorskip("pydicom")
nib = pytest.importorskip("nibabel")
sys.path.insert(0, str(ROOT / "tools"))
import write_dicom_series  # noqa: E402


@pytest.fixture(scope="module")
def template():
    image = nib.load(str(MNI))
    return np.asanyarray(image.dataobj).astype(np.float32), image.affine


def write(tmp_path_factory, name, **options):
    """A series written into a fresh folder: (folder, what the writer returned)."""
    folder = tmp_path_factory.mktemp(name)
    return folder, write_dicom_series.write_series(MNI, folder, **options)


@pytest.fixture(scope="module")
def axial(tmp_path_factory):
    return write(tmp_path_factory, "axial", shuffle=True)


@pytest.fixture(scope="module")
def oblique(tmp_path_factory):
    return write(tmp_path_factory, "oblique", rotate=10.0, shuffle=True, seed=1)


@pytest.fixture(scope="module", params=sorted(write_dicom_series.SYNTAXES))
def syntax_slab(request, tmp_path_factory):
    return request.param, write(tmp_path_factory, request.param, syntax=request.param, slices=SLAB, shuffle=True)


def corners(shape):
    """The homogeneous indices of the 8 corner voxels of a grid of ``shape``."""
    return np.array([[i, j, k, 1.0] for i in (0, shape[0] - 1) for j in (0, shape[1] - 1) for k in (0, shape[2] - 1)]).T


def assert_reads_as_template(volume, template, expected_affine, slices=None):
    """The series' samples are the template's, and every corner voxel lies where
    the expected LPS affine puts it."""
    data, _ = template
    if slices is not None:
        data = data[:, :, slices[0] : slices[1]]
    assert volume.space == "LPS"
    assert volume.data.shape == data.shape
    assert np.array_equal(volume.data, data), f"max sample difference {np.abs(volume.data - data).max()}"
    grid = corners(data.shape)
    error = np.abs(volume.affine @ grid - expected_affine @ grid).max()
    assert error < POSITION_TOLERANCE, f"corner positions differ by {error} mm"


def test_an_axial_series_reads_as_the_nifti_in_lps(axial, template):
    folder, _ = axial
    # The NIfTI's own affine, RAS to LPS: x and y change sign.
    expected = RAS_TO_LPS @ template[1]
    assert_reads_as_template(crestline.read_volume(folder), template, expected)


def test_an_oblique_series_keeps_its_rotation(oblique, template):
    folder, written = oblique
    turn = written["affine"] @ np.linalg.inv(RAS_TO_LPS @ template[1])
    # The writer turned the grid by 10° about an oblique axis, rigidly.
    rotation = turn[:3, :3]
    assert np.allclose(rotation @ rotation.T, np.eye(3), atol=1e-12)
    angle = np.degrees(np.arccos((np.trace(rotation) - 1) / 2))
    assert abs(angle - 10.0) < 1e-9
    volume = crestline.read_volume(folder)
    assert_reads_as_template(volume, template, written["affine"])
    # No index axis is along a patient axis.
    directions = volume.affine[:3, :3] / np.linalg.norm(volume.affine[:3, :3], axis=0)
    assert np.abs(directions).max() < 0.999


def test_a_list_of_files_reads_as_its_folder(tmp_path_factory, template):
    folder, written = write(tmp_path_factory, "listed", slices=SLAB, shuffle=True)
    (folder / "README.txt").write_text("notes beside the series")
    (folder / ".hidden.dcm").write_bytes(b"\0" * 200)
    from_folder = crestline.read_volume(folder)
    files = sorted(f for f in folder.glob("*.dcm") if not f.name.startswith("."))
    from_list = crestline.read_volume(files)
    assert np.array_equal(from_list.data, from_folder.data)
    assert np.array_equal(from_list.affine, from_folder.affine)
    assert_reads_as_template(from_folder, template, written["affine"], SLAB)


def test_every_transfer_syntax_reads_the_same_samples(syntax_slab, template):
    syntax, (folder, written) = syntax_slab
    assert_reads_as_template(crestline.read_volume(folder), template, written["affine"], SLAB)


@pytest.mark.parametrize("rotate", [0.0, 10.0])
def test_an_enhanced_multi_frame_file_reads_as_the_nifti(rotate, tmp_path_factory, template):
    folder, written = write(tmp_path_factory, "enhanced", slices=SLAB, rotate=rotate, enhanced=True)
    volume = crestline.read_volume(folder / "enhanced.dcm")
    assert_reads_as_template(volume, template, written["affine"], SLAB)


def test_a_dicomdir_reads_the_files_it_references(tmp_path_factory, template):
    from pydicom.fileset import FileSet

    source, written = write(tmp_path_factory, "media-source", slices=SLAB)
    media = tmp_path_factory.mktemp("media")
    files = FileSet()
    for path in sorted(source.glob("*.dcm")):
        files.add(str(path))
    files.write(str(media))
    volume = crestline.read_volume(media / "DICOMDIR")
    assert_reads_as_template(volume, template, written["affine"], SLAB)


def test_jpeg_baseline_decodes_as_libjpeg_does(tmp_path, template):
    image = pytest.importorskip("PIL.Image")
    from pydicom.encaps import encapsulate
    from pydicom.uid import JPEGBaseline8Bit

    plane = template[0][:, :, 90].astype(np.uint8)  # [column, row]
    compressed = io.BytesIO()
    image.fromarray(plane.T).save(compressed, format="JPEG", quality=90)
    # Pillow's libjpeg decodes the same bytes: the reference.
    reference = np.asarray(image.open(io.BytesIO(compressed.getvalue()))).T.astype(np.float32)
    uids = {"study": "1.2.3", "series": "1.2.3.4", "frame": "1.2.3.5"}
    ds = write_dicom_series.slice_dataset(plane, np.zeros(3), np.array([1.0, 0, 0, 0, 1, 0]), [1.0, 1.0, 1.0], uids, 1, "explicit")
    ds.BitsAllocated, ds.BitsStored, ds.HighBit, ds.PixelRepresentation = 8, 8, 7, 0
    ds.RescaleSlope, ds.RescaleIntercept = "1", "0"
    ds.file_meta.TransferSyntaxUID = JPEGBaseline8Bit
    ds.PixelData = encapsulate([compressed.getvalue()])
    ds["PixelData"].VR = "OB"
    ds["PixelData"].is_undefined_length = True
    ds.save_as(tmp_path / "slice.dcm", enforce_file_format=True)
    volume = crestline.read_volume(tmp_path / "slice.dcm")
    assert volume.data.shape == (*plane.shape, 1)
    # Two decoders may round their inverse DCTs differently, by one grey level.
    difference = np.abs(volume.data[:, :, 0] - reference)
    print(f"JPEG baseline: largest difference from libjpeg {difference.max()}, mean {difference.mean():.4f}")
    assert difference.max() <= 1
    # And it is the image, lossy: within a few levels of the samples on average.
    assert np.abs(volume.data[:, :, 0] - plane).mean() < 3


def simpleitk_geometry(folder):
    """Origin, spacing and direction (row-major) of the series SimpleITK reads."""
    sitk = pytest.importorskip("SimpleITK")
    reader = sitk.ImageSeriesReader()
    reader.SetFileNames(reader.GetGDCMSeriesFileNames(str(folder)))
    image = reader.Execute()
    return (
        np.array(image.GetOrigin()),
        np.array(image.GetSpacing()),
        np.array(image.GetDirection()).reshape(3, 3),
        sitk.GetArrayFromImage(image),
    )


def assert_simpleitk_agrees(folder):
    volume = crestline.read_volume(folder)
    origin, spacing, direction, samples = simpleitk_geometry(folder)
    axes = volume.affine[:3, :3]
    ours = np.linalg.norm(axes, axis=0)
    assert np.abs(volume.affine[:3, 3] - origin).max() < POSITION_TOLERANCE
    assert np.abs(ours - spacing).max() < POSITION_TOLERANCE
    assert np.abs(axes / ours - direction).max() < 1e-6
    # ITK indexes [k, j, i]; both apply the rescale.
    assert np.array_equal(samples.astype(np.float32), volume.data.transpose(2, 1, 0))


def test_simpleitk_agrees_on_the_axial_and_oblique_series(axial, oblique):
    assert_simpleitk_agrees(axial[0])
    assert_simpleitk_agrees(oblique[0])


def test_simpleitk_agrees_in_every_transfer_syntax(syntax_slab):
    _, (folder, _) = syntax_slab
    assert_simpleitk_agrees(folder)


def landmarks_csv(path, out, *extra):
    """The point landmarks (n × 3, LPS) the tool finds on ``path``, and their kinds."""
    if not TOOL.exists():
        pytest.skip(f"{TOOL} is not built (cargo build --release)")
    subprocess.run([str(TOOL), "landmarks", str(path), "--level", "60", "--output-space", "LPS", "-o", str(out), *extra], check=True)
    rows = np.genfromtxt(out, delimiter=",", names=True, dtype=None, encoding="utf-8")
    return np.column_stack([rows["x"], rows["y"], rows["z"]]), rows["kind"]


@pytest.fixture(scope="module")
def nifti_landmarks(tmp_path_factory):
    return landmarks_csv(MNI, tmp_path_factory.mktemp("nifti-landmarks") / "nifti.csv")


# The series holds the NIfTI's samples and spacing exactly (the spacing is Slice
# Thickness, which the positions agree with) and its geometry to the 12 or more
# significant digits of its decimal strings; the lines are computed from the
# samples and the spacing alone, whatever the world frame (LPS for the series,
# RAS for the NIfTI, turned for the oblique series). So every landmark has one of
# its kind at the same place, up to the rounding of the world positions
# (measured: 0 mm axial, 9e-12 mm oblique).
LANDMARK_TOLERANCE = 1e-6


def nearest(points, others):
    """For each of ``points``, the index of and distance to the nearest of ``others``."""
    index = np.empty(len(points), dtype=np.int64)
    for start in range(0, len(points), 512):
        block = points[start : start + 512]
        squared = ((block[:, None, :] - others[None, :, :]) ** 2).sum(axis=-1)
        index[start : start + 512] = squared.argmin(axis=1)
    return index, np.linalg.norm(points - others[index], axis=1)


def distance_to_same_kind(points, kinds, others, other_kinds):
    """The distance from each of ``points`` to the nearest of ``others`` of its kind
    (an extremal point and a curvature maximum may coincide)."""
    distance = np.full(len(points), np.inf)
    for kind in np.unique(kinds):
        mine, theirs = kinds == kind, other_kinds == kind
        if theirs.any():
            distance[mine] = nearest(points[mine], others[theirs])[1]
    return distance


@pytest.mark.parametrize("which", ["axial", "oblique"])
def test_the_landmarks_of_a_series_are_the_niftis(which, request, nifti_landmarks, template, tmp_path):
    folder, written = request.getfixturevalue(which)
    points, kinds = landmarks_csv(folder, tmp_path / "series.csv")
    expected, expected_kinds = nifti_landmarks
    # The oblique series is the NIfTI turned rigidly: its landmarks are too.
    turn = written["affine"] @ np.linalg.inv(RAS_TO_LPS @ template[1])
    expected = expected @ turn[:3, :3].T + turn[:3, 3]
    assert len(expected) > 1000
    missing = distance_to_same_kind(expected, expected_kinds, points, kinds)
    extra = distance_to_same_kind(points, kinds, expected, expected_kinds)
    print(f"{which}: {len(points)} landmarks for the NIfTI's {len(expected)}; the farthest {max(missing.max(), extra.max()):.1e} mm from one of its kind")
    assert len(points) == len(expected)
    assert missing.max() <= LANDMARK_TOLERANCE and extra.max() <= LANDMARK_TOLERANCE


def refused(folder, *words):
    """The error of reading ``folder``, from Python and from the tool (exit status
    1, one line naming the folder), contains every one of ``words``."""
    with pytest.raises(crestline.FileError) as raised:
        crestline.read_volume(folder)
    message = str(raised.value)
    for word in words:
        assert word in message, message
    if TOOL.exists():
        run = subprocess.run([str(TOOL), "info", str(folder)], capture_output=True, text=True)
        assert run.returncode == 1, run.stderr
        lines = run.stderr.strip().splitlines()
        assert len(lines) == 1 and str(folder) in lines[0], run.stderr
        for word in words:
            assert word in lines[0], run.stderr
    return message


def test_a_missing_slice_is_refused_naming_the_gap(tmp_path):
    write_dicom_series.write_series(MNI, tmp_path, slices=SLAB, drop_slice=5, shuffle=True)
    message = refused(tmp_path, str(tmp_path), "unevenly spaced", "2.0000 mm between", "the spacing is 1.0000 mm")
    assert "missing slice" in message


def test_mixed_orientations_are_refused(tmp_path):
    write_dicom_series.write_series(MNI, tmp_path, slices=SLAB, mixed_orientation=True)
    refused(tmp_path, str(tmp_path), "mixes orientations", "Image Orientation (Patient)")


def test_a_gantry_tilt_is_refused_with_its_angle(tmp_path):
    write_dicom_series.write_series(MNI, tmp_path, slices=SLAB, tilt=12.0)
    refused(tmp_path, str(tmp_path), "12.00° from the normal", "gantry tilt", "rather than resampling")


def test_two_series_are_listed_unless_one_is_chosen(tmp_path, template):
    written = write_dicom_series.write_series(MNI, tmp_path, slices=SLAB, second_series=True)
    message = refused(tmp_path, str(tmp_path), "holds 2 series", written["series"])
    assert message.count("1.2.826.0.1.3680043") == 2, message
    chosen = crestline.read_volume(tmp_path, series=written["series"])
    assert_reads_as_template(chosen, template, written["affine"], SLAB)
    if TOOL.exists():
        run = subprocess.run([str(TOOL), "info", str(tmp_path), "--series", written["series"]], capture_output=True, text=True)
        assert run.returncode == 0, run.stderr
        assert "197 × 233 × 16" in run.stdout


def test_a_truncated_file_is_refused_naming_it(tmp_path):
    write_dicom_series.write_series(MNI, tmp_path, slices=SLAB)
    victim = sorted(tmp_path.glob("*.dcm"))[3]
    victim.write_bytes(victim.read_bytes()[: victim.stat().st_size // 2])
    refused(tmp_path, victim.name)


def test_a_modality_lut_table_is_refused_naming_the_file(tmp_path):
    import pydicom
    from pydicom.dataset import Dataset

    write_dicom_series.write_series(MNI, tmp_path, slices=SLAB)
    victim = sorted(tmp_path.glob("*.dcm"))[2]
    ds = pydicom.dcmread(victim)
    table = Dataset()
    table.LUTDescriptor = [4, 0, 16]
    table.ModalityLUTType = "HU"
    table.add_new(0x00283006, "US", [0, 1, 2, 3])  # LUT Data
    ds.ModalityLUTSequence = [table]
    ds.save_as(victim, enforce_file_format=True)
    refused(tmp_path, victim.name, "Modality LUT Sequence (0028,3000)")


def test_an_undecodable_transfer_syntax_is_refused_by_name(tmp_path):
    source = PYDICOM_DATA / "MR_small_jp2klossless.dcm"
    if not source.exists():
        pytest.skip(f"{source} is absent (run tools/fetch_pydicom_data.sh)")
    shutil.copy(source, tmp_path / source.name)
    refused(tmp_path, source.name, "JPEG 2000", "cannot decode")


def test_a_folder_without_images_is_refused(tmp_path):
    (tmp_path / "notes.txt").write_text("no images")
    refused(tmp_path, str(tmp_path), "holds no DICOM file")


def test_a_decoder_panic_is_an_error_without_its_text(tmp_path, capfd):
    """pydicom's RLE image with an empty second segment made dicom-rs's decoder
    index past what it decoded and panic on a worker thread: the package raises
    the library's error about the file, and Rust's panic text stays off stderr."""
    source = PYDICOM_DATA / "MR_small_RLE.dcm"
    if not source.exists():
        pytest.skip(f"{source} is absent (run tools/fetch_pydicom_data.sh)")
    data = bytearray(source.read_bytes())
    # The RLE header of the 16-bit frame: 2 segments, the first at byte 64. The
    # second is made to start where the data end (offsets count from the header).
    at = data.find(bytes([2, 0, 0, 0, 64, 0, 0, 0]))
    end = data.find(bytes([0xFE, 0xFF, 0xDD, 0xE0]), at)
    data[at + 8:at + 12] = ((end if end > 0 else len(data)) - at).to_bytes(4, "little")
    victim = tmp_path / "empty.dcm"
    victim.write_bytes(bytes(data))
    with pytest.raises(crestline.FileError, match="cannot be decoded"):
        crestline.read_volume(victim)
    assert "panicked" not in capfd.readouterr().err

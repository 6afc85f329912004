"""Tests of the image half: images read as nibabel reads them, isosurfaces, crest
lines and landmarks equal to the command-line tool's, crease surfaces of an
analytic shell, registration of moved crest lines, and bad images refused."""

import json
import subprocess
from pathlib import Path

import numpy as np
import pytest

import crestline

ROOT = Path(__file__).resolve().parents[3]
MNI = ROOT / "volumes" / "mni152_t1_1mm.nii.gz"
TOOL = ROOT / "target" / "release" / "crestline"


def radial(n, field):
    """An n³ unit-spaced image of ``field(r)``, r the distance to the centre, as
    (data indexed [i, j, k], centre)."""
    axis = np.arange(n, dtype=np.float64)
    i, j, k = np.meshgrid(axis, axis, axis, indexing="ij")
    centre = (n - 1) / 2 + 0.1
    r = np.sqrt((i - centre) ** 2 + (j - centre) ** 2 + (k - centre) ** 2)
    return field(r).astype(np.float32), centre


@pytest.fixture(scope="module")
def brain():
    return crestline.read_volume(MNI)


@pytest.fixture(scope="module")
def brain_crests(brain):
    return crestline.crest_lines(brain, level=60)


def test_read_volume_agrees_with_nibabel(brain):
    nib = pytest.importorskip("nibabel")
    image = nib.load(MNI)
    assert brain.data.shape == image.shape and brain.data.dtype == np.float32
    assert np.array_equal(brain.affine, image.affine)
    assert np.array_equal(brain.data, image.get_fdata(dtype=np.float32))
    assert np.allclose(brain.spacing, 1.0) and np.array_equal(brain.origin, image.affine[:3, 3])
    # A nibabel image is accepted where a Volume is, with the same result.
    assert np.array_equal(crestline.isosurface(image, 60)[0], crestline.isosurface(brain, 60)[0])


def test_an_isosurface_of_a_ball_lies_on_its_sphere_in_world_coordinates():
    data, centre = radial(24, lambda r: 10.0 - r)
    spacing, origin = (0.5, 0.5, 0.5), (-3.0, 2.0, 7.0)
    # sigma 0: the samples as they are (the default smooths by a voxel, which
    # moves the level set of a cone inwards by about sigma² / r).
    vertices, faces = crestline.isosurface(data, 2.0, sigma=0, spacing=spacing, origin=origin)
    assert vertices.dtype == np.float64 and faces.dtype == np.int64 and len(faces) > 1000
    world_centre = np.array(origin) + 0.5 * centre
    radius = np.linalg.norm(vertices - world_centre, axis=1)
    # Within 0.06 voxel (linear interpolation of r along cell edges).
    assert np.abs(radius - 0.5 * 8.0).max() < 0.03
    # Closed and counter-clockwise seen from outside: the signed volume is the
    # ball's.
    a, b, c = (vertices[faces[:, n]] - world_centre for n in range(3))
    volume = np.einsum("ij,ij->i", a, np.cross(b, c)).sum() / 6
    assert abs(volume / (4 / 3 * np.pi * 4.0**3) - 1) < 0.02
    # The mesh half takes it as it is (no repair renumbers its vertices), and
    # finds it convex: outward faces. (Its curvature is not the sphere's: the
    # linear interpolation ripples at the scale of the voxels, which is why the
    # command-line tool takes an isosurface's curvature from the image.)
    field = crestline.curvature(vertices, faces, estimator="jet-fit")
    assert np.median(field["k_min"]) > 0


def run_tool(*args):
    if not TOOL.exists():
        pytest.skip(f"{TOOL} is not built (run cargo build --release)")
    subprocess.run([TOOL, *map(str, args)], check=True, capture_output=True)


def test_crest_lines_of_the_brain_equal_the_tools(brain_crests, tmp_path):
    run_tool("crest-lines", MNI, "--level", 60, "-o", tmp_path / "lines.json")
    cli = json.loads((tmp_path / "lines.json").read_text())["lines"]
    assert len(brain_crests) == len(cli) > 300
    assert brain_crests.kinds() == {"ridge": sum(line["kind"] == "ridge" for line in cli),
                                    "valley": sum(line["kind"] == "valley" for line in cli)}
    for ours, theirs in zip(brain_crests, cli):
        assert ours.kind == theirs["kind"]
        assert np.abs(ours.points - np.array(theirs["points"])).max() < 1e-9
    assert brain_crests[0].location_vertices is None
    assert sorted(brain_crests[0].values) == ["e_max", "e_min", "k_max", "k_min"]


def test_landmarks_of_the_brain_equal_the_tools(brain_crests, tmp_path):
    run_tool("landmarks", MNI, "--level", 60, "-o", tmp_path / "landmarks.json", "--report", tmp_path / "r.json")
    cli = json.loads((tmp_path / "landmarks.json").read_text())
    # The lengths' unit is the feature scale the tool used.
    scale = json.loads((tmp_path / "r.json").read_text())["counts"]["scale"]
    found = crestline.landmarks(brain_crests, unit=scale)
    points = found["points"]
    assert len(points["kind"]) == len(cli["points"]) > 1000
    assert list(points["kind"]) == [p["kind"] for p in cli["points"]]
    assert np.abs(points["position"] - np.array([p["position"] for p in cli["points"]])).max() < 1e-9
    assert len(found["lines"]) == len(cli["lines"])
    with pytest.raises(ValueError, match="radius"):
        crestline.landmarks(brain_crests, radius=0.0, persistence=2.0)


def test_moved_crest_lines_register_back(brain_crests):
    angle = np.radians(10.0)
    axis = np.array([1.0, 2.0, 0.5]) / np.linalg.norm([1.0, 2.0, 0.5])
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    rotation = np.eye(3) + np.sin(angle) * k + (1 - np.cos(angle)) * k @ k
    shift = np.array([8.0, -3.0, 2.0])
    long_lines = crestline.Lines(line for line in brain_crests if line.length() > 10)
    fixed = np.vstack([line.points for line in long_lines])
    moving = fixed @ rotation.T + shift
    found = crestline.register(long_lines, moving)
    expected = np.eye(4)
    expected[:3, :3], expected[:3, 3] = rotation.T, -rotation.T @ shift
    assert np.abs(found["matrix"] - expected).max() < 1e-6
    assert found["matched_share"] > 0.9 and found["rms"] < 1e-6


def test_the_ridge_surface_of_a_shell_is_its_sphere():
    radius, width = 9.0, 2.5
    data, centre = radial(26, lambda r: np.exp(-((r - radius) / width) ** 2))
    stages = []
    surface = crestline.crease_surface(data, progress=lambda stage, seconds: stages.append((stage, seconds)))
    finished = [stage for stage, seconds in stages if seconds is not None]
    assert finished[:2] == ["reconstruction", "eigenframes"] and "degenerate points" in finished
    vertices, faces = surface["vertices"], surface["faces"]
    assert len(faces) > 1000 and faces.max() < len(vertices)
    distance = np.abs(np.linalg.norm(vertices - centre, axis=1) - radius)
    assert distance.mean() < 0.05 and np.quantile(distance, 0.995) < 1.0
    assert surface["strength"].shape == (len(vertices),) and surface["strength"].min() > 0
    assert surface["degenerate"].shape == (len(vertices),)
    # No valley surface is as strong in a single shell.
    assert len(crestline.crease_surface(data, valley=True, strength=0.5)["faces"]) < len(faces) / 10


def test_non_finite_samples_are_set_to_the_background_with_a_warning():
    data, _ = radial(16, lambda r: 5.0 - r)
    holes = data.copy()
    holes[0, 0, :4] = np.nan
    holes[1, 0, 0] = np.inf
    with pytest.warns(UserWarning, match="5 samples are not finite"):
        with_holes = crestline.isosurface(holes, 1.0)
    filled = np.where(np.isfinite(holes), holes, data.min())
    expected = crestline.isosurface(filled, 1.0)
    assert np.array_equal(with_holes[0], expected[0]) and np.array_equal(with_holes[1], expected[1])
    with pytest.raises(crestline.ArgumentError, match="no finite sample"):
        crestline.isosurface(np.full((4, 4, 4), np.nan, np.float32), 1.0)


def test_parabolic_and_seeded_lines():
    data, _ = radial(28, lambda r: 10.0 - r)
    # A sphere has no parabolic line.
    assert len(crestline.crest_lines(data, 2.0, kind="parabolic")) == 0
    # An ellipsoid has crest lines; the same seed draws the same ones.
    x, y, z = np.mgrid[-14:15, -14:15, -14:15].astype(float)
    ellipsoid = 10.0 - np.sqrt(x**2 + (y / 0.7) ** 2 + (z / 0.5) ** 2)
    a = crestline.crest_lines(ellipsoid, 2.0, seeds=20, rng_seed=4)
    b = crestline.crest_lines(ellipsoid, 2.0, seeds=20, rng_seed=4)
    assert len(a) > 0
    assert [line.points.tolist() for line in a] == [line.points.tolist() for line in b]


@pytest.mark.parametrize(
    "call, error, words",
    [
        (lambda d: crestline.isosurface(d[0], 1.0), ValueError, "expected a 3-D image"),
        (lambda d: crestline.isosurface(d, 1.0, spacing=(1, 0, 1)), ValueError, "spacing"),
        (lambda d: crestline.isosurface(crestline.Volume(d, np.zeros((4, 4))), 1.0), ValueError, "singular"),
        (lambda d: crestline.isosurface(crestline.Volume(d, np.eye(4)), 1.0, origin=(0, 0, 0)), ValueError,
         "only for plain arrays"),
        (lambda d: crestline.crest_lines(d, 1.0, kind="ridges"), ValueError, "kind: expected one of"),
        (lambda d: crestline.crest_lines(d, 1.0, kind="gauss"), ValueError, "nonzero"),
        (lambda d: crestline.crest_lines(d, 1.0, seeds=0), ValueError, "seeds"),
        (lambda d: crestline.crest_lines(d, 1.0, sigma=-1), ValueError, "sigma"),
        (lambda d: crestline.crease_surface(d, strength=2), ValueError, "strength"),
        (lambda d: crestline.register(np.zeros((2, 3)), np.zeros((5, 3))), crestline.ArgumentError, "at least 3"),
        (lambda d: crestline.read_volume("missing.nii.gz"), crestline.FileError, "missing.nii.gz"),
    ],
)
def test_bad_images_and_options_raise_clear_errors(call, error, words):
    data, _ = radial(8, lambda r: 3.0 - r)
    with pytest.raises(error, match=words):
        call(data)


def test_counts_beyond_64_bits_name_their_argument():
    import crestline

    image = np.zeros((6, 6, 6), dtype=np.float32)
    image[2:4, 2:4, 2:4] = 1.0
    with pytest.raises(ValueError, match="seeds"):
        crestline.crest_lines(image, 0.5, seeds=2**70)
    with pytest.raises(ValueError, match="rng_seed"):
        crestline.crest_lines(image, 0.5, seeds=3, rng_seed=2**64)


def test_a_volume_is_checked_when_made():
    import crestline

    data = np.zeros((3, 3, 3), dtype=np.float32)
    for affine, words in [(np.eye(3), "4 × 4"), (np.full((4, 4), np.nan), "finite"),
                          (np.diag([1.0, 1.0, 1.0, 2.0]), "last row"), (np.diag([1.0, 0.0, 1.0, 1.0]), "singular")]:
        with pytest.raises(ValueError, match=words):
            crestline.Volume(data, affine)
    with pytest.raises(ValueError, match="3-D"):
        crestline.Volume(np.zeros((3, 3)), np.eye(4))
    with pytest.raises(ValueError, match="3-D array of numbers"):
        crestline.Volume(np.zeros((2, 2, 2), dtype=complex), np.eye(4))
    with pytest.raises(ValueError, match="space"):
        crestline.Volume(data, np.eye(4), "XYZ")
    assert crestline.Volume(data, np.eye(4), "ras").space == "RAS"

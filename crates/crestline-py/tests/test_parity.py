"""Every function of the package gives what the command-line tool writes for the
same input, with the defaults and with two options changed: the bundled bunny
and the MNI template, the tool run as a process. (The tool's own tests hold it to
the library's jobs, so the three doors agree.) Skipped when the tool is not built
(``cargo build --release``)."""

import json
import subprocess
from pathlib import Path

import numpy as np
import pytest

import crestline

ROOT = Path(__file__).resolve().parents[3]
TOOL = ROOT / "target" / "release" / "crestline"
BUNNY = ROOT / "meshes" / "bunny.obj"
MNI = ROOT / "volumes" / "mni152_t1_1mm.nii.gz"
LEVEL = 80.0


def tool(*args):
    """Run the tool from the repository's root (skipping the test when it is not
    built)."""
    if not TOOL.exists():
        pytest.skip(f"{TOOL} is not built (run cargo build --release)")
    paths = [str(a.relative_to(ROOT)) if isinstance(a, Path) and a.is_relative_to(ROOT) else str(a) for a in args]
    subprocess.run([TOOL, *paths], check=True, capture_output=True, cwd=ROOT)


@pytest.fixture(scope="module")
def bunny():
    vertices, faces, _ = crestline.read_mesh(BUNNY)
    return vertices, faces


@pytest.fixture(scope="module")
def brain():
    return crestline.read_volume(MNI)


def read_obj(path):
    """Vertices and faces of an OBJ file the tool wrote."""
    vertices, faces = [], []
    for line in Path(path).read_text().splitlines():
        if line.startswith("v "):
            vertices.append([float(x) for x in line.split()[1:4]])
        elif line.startswith("f "):
            faces.append([int(i.split("/")[0]) - 1 for i in line.split()[1:4]])
    return np.array(vertices), np.array(faces)


def assert_same_surface(written, vertices, faces):
    ours_v, ours_f = written
    assert len(faces) > 1000
    assert np.array_equal(ours_f, faces)
    assert np.abs(ours_v - vertices).max() <= 1e-12 * (1 + np.abs(vertices).max())


def assert_same_lines(path, lines):
    """The lines of the tool's JSON file are ``lines``: kinds, strengths, points."""
    theirs = json.loads(Path(path).read_text())["lines"]
    assert len(lines) == len(theirs) > 0
    for ours, line in zip(lines, theirs):
        assert (ours.kind, ours.closed) == (line["kind"], line["closed"])
        assert ours.strength == pytest.approx(line["strength"], rel=1e-12, abs=1e-12)
        assert np.abs(ours.points - np.array(line["points"])).max() <= 1e-12 * (1 + np.abs(ours.points).max())


def assert_same_landmarks(path, found):
    theirs = json.loads(Path(path).read_text())
    points = found["points"]
    assert len(points["kind"]) == len(theirs["points"]) > 0
    assert list(points["id"]) == [p["id"] for p in theirs["points"]]
    assert list(points["kind"]) == [p["kind"] for p in theirs["points"]]
    assert list(points["line"]) == [p["line"] for p in theirs["points"]]
    assert np.abs(points["position"] - np.array([p["position"] for p in theirs["points"]])).max() < 1e-9
    assert [line["id"] for line in found["lines"]] == [line["id"] for line in theirs["lines"]]


@pytest.mark.parametrize("args, kwargs", [([], {}), (["--sigma", 2], {"sigma": 2.0})])
def test_isosurface(brain, tmp_path, args, kwargs):
    tool("iso", MNI, "--level", LEVEL, *args, "-o", tmp_path / "iso.obj")
    assert_same_surface(read_obj(tmp_path / "iso.obj"), *crestline.isosurface(brain, LEVEL, **kwargs))


@pytest.mark.parametrize(
    "args, kwargs",
    [
        ([], {}),
        (["--seeds", 300], {"seeds": 300}),
        (["--sigma", 1.5, "--min-length", 10], {"sigma": 1.5, "min_length": 10.0}),
        (["--kind", "parabolic", "--min-strength", 0.5], {"kind": "parabolic", "min_strength": 0.5}),
    ],
)
def test_crest_lines(brain, tmp_path, args, kwargs):
    tool("crest-lines", MNI, "--level", LEVEL, *args, "-o", tmp_path / "lines.json")
    assert_same_lines(tmp_path / "lines.json", crestline.crest_lines(brain, LEVEL, **kwargs))


@pytest.fixture(scope="module")
def half_brain(brain, tmp_path_factory):
    """Every second sample of the template (a short test), as a Volume and as an
    NRRD file the tool reads."""
    data = np.ascontiguousarray(brain.data[::2, ::2, ::2])
    affine = brain.affine.copy()
    affine[:3, :3] *= 2
    path = tmp_path_factory.mktemp("half") / "half.nrrd"
    spacing, origin = [float(s) for s in np.diag(affine)[:3]], [float(o) for o in affine[:3, 3]]
    header = (
        "NRRD0004\ntype: float\ndimension: 3\nspace: right-anterior-superior\n"
        f"sizes: {data.shape[0]} {data.shape[1]} {data.shape[2]}\n"
        f"space directions: ({spacing[0]!r},0,0) (0,{spacing[1]!r},0) (0,0,{spacing[2]!r})\n"
        f"space origin: ({origin[0]!r},{origin[1]!r},{origin[2]!r})\nencoding: raw\nendian: little\n\n"
    )
    path.write_bytes(header.encode() + data.astype("<f4").transpose(2, 1, 0).tobytes())
    return crestline.read_volume(path), path


@pytest.mark.parametrize("args, kwargs", [([], {}), (["--valley", "--strength", 0.2], {"valley": True, "strength": 0.2})])
def test_crease_surface(half_brain, tmp_path, args, kwargs):
    volume, path = half_brain
    tool("crease", path, *args, "-o", tmp_path / "crease.obj")
    surface = crestline.crease_surface(volume, **kwargs)
    assert_same_surface(read_obj(tmp_path / "crease.obj"), surface["vertices"], surface["faces"])


@pytest.mark.parametrize(
    "args, kwargs",
    [([], {}), (["--estimator", "jet-fit", "--threshold", 4], {"estimator": "jet-fit", "threshold": 4.0})],
)
def test_ridges(bunny, tmp_path, args, kwargs):
    tool("ridges", BUNNY, *args, "-o", tmp_path / "ridges.json")
    assert_same_lines(tmp_path / "ridges.json", crestline.ridges(*bunny, **kwargs))


@pytest.mark.parametrize(
    "args, kwargs",
    [([], {}), (["--estimator", "jet-fit", "--radius", 0.01], {"estimator": "jet-fit", "radius": 0.01})],
)
def test_landmarks_of_a_mesh(bunny, tmp_path, args, kwargs):
    tool("landmarks", BUNNY, *args, "-o", tmp_path / "marks.json")
    assert_same_landmarks(tmp_path / "marks.json", crestline.landmarks(*bunny, **kwargs))


@pytest.mark.parametrize(
    "args, kwargs",
    [([], {}), (["--sigma", 1.5, "--persistence", 3], {"sigma": 1.5, "persistence": 3.0})],
)
def test_landmarks_of_an_image(brain, tmp_path, args, kwargs):
    tool("landmarks", MNI, "--level", LEVEL, *args, "-o", tmp_path / "marks.json")
    assert_same_landmarks(tmp_path / "marks.json", crestline.landmarks(brain, level=LEVEL, **kwargs))


def test_landmarks_written_by_the_package_are_the_tools(brain, tmp_path):
    tool("landmarks", MNI, "--level", LEVEL, "-o", tmp_path / "tool.csv")
    crestline.write_landmarks(tmp_path / "package.csv", crestline.landmarks(brain, level=LEVEL), "ras")
    assert (tmp_path / "package.csv").read_text() == (tmp_path / "tool.csv").read_text()


@pytest.mark.parametrize(
    "args, kwargs",
    [([], {}), (["--keep-saddles", 20, "--cells", "both"], {"keep_saddles": 20, "cells": "both"})],
)
def test_morse(bunny, tmp_path, args, kwargs):
    tool("morse", BUNNY, *args, "-o", tmp_path / "morse.json")
    assert_same_lines(tmp_path / "morse.json", crestline.morse(*bunny, **kwargs))


@pytest.mark.parametrize(
    "args, kwargs",
    [
        (["--view", "20,15", "--silhouettes"], {"view": (20, 15), "silhouettes": True}),
        (["--lines", "morse", "--suggestive", "--size", "400x300"], {"lines": "morse", "suggestive": True, "size": (400, 300)}),
        (["--silhouettes", "--page", "a5", "--landscape", "--pen", "0.5mm", "--taper", "2"],
         {"silhouettes": True, "page": {"paper": "a5", "landscape": True, "pen": "0.5mm"}, "taper": 2.0}),
    ],
)
def test_draw(bunny, tmp_path, args, kwargs):
    tool("draw", BUNNY, *args, "-o", tmp_path / "drawing.svg")
    ours = crestline.draw(*bunny, **kwargs)
    assert ours.count("<path") > 10
    # The tool titles the drawing with the mesh's file name; arrays have none.
    title = f"<title>{BUNNY.relative_to(ROOT)}</title>"
    assert ours.replace("<title></title>", title) == (tmp_path / "drawing.svg").read_text()


@pytest.mark.parametrize("args, kwargs", [([], {}), (["--min-overlap", 0.6, "--max-iterations", 50],
                                                      {"min_overlap": 0.6, "max_iterations": 50})])
def test_register(brain, tmp_path, args, kwargs):
    fixed = crestline.crest_lines(brain, LEVEL, min_length=20.0)
    turn = np.radians(6.0)
    rotation = np.array([[np.cos(turn), -np.sin(turn), 0], [np.sin(turn), np.cos(turn), 0], [0, 0, 1]])
    moving = crestline.Lines(
        (crestline.Line(line.kind, line.closed, line.strength, line.points @ rotation.T + [4.0, -2.0, 1.0], {})
         for line in fixed),
        space=fixed.space,
    )
    fixed.save(tmp_path / "fixed.json")
    moving.save(tmp_path / "moving.json")
    tool("register", tmp_path / "fixed.json", tmp_path / "moving.json", *args, "-o", tmp_path / "t.json")
    theirs = json.loads((tmp_path / "t.json").read_text())
    ours = crestline.register(fixed, moving, **kwargs)
    assert np.abs(ours["matrix"] - np.array(theirs["matrix"])).max() < 1e-9
    assert ours["rms"] < 1e-6

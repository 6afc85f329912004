"""The package computes what the command-line tool computes: the curvature of an
analytic ellipsoid to 1e-12 and the same ridge lines on a rotated one. Skipped
when the tool is not built (``cargo build --release``)."""

import json
import struct
import subprocess
from pathlib import Path

import numpy as np
import pytest

import crestline

from test_crestline import icosphere

ROOT = Path(__file__).resolve().parents[3]
TOOL = ROOT / "target" / "release" / "crestline"


@pytest.fixture(scope="module")
def tool():
    if not TOOL.exists():
        pytest.skip(f"{TOOL} is not built (run cargo build --release)")
    return TOOL


AXES = (1.0, 0.7, 0.45)


def rotation(angles=(0.3, -0.5, 0.9)):
    """Turns about x, y and z by the angles, in that order."""
    result = np.eye(3)
    for axis, angle in enumerate(angles):
        c, s = np.cos(angle), np.sin(angle)
        turn = np.eye(3)
        i, j = [a for a in range(3) if a != axis]
        turn[i, i], turn[i, j], turn[j, i], turn[j, j] = c, -s, s, c
        result = turn @ result
    return result


def ellipsoid(subdivisions=4):
    """An ellipsoid with the semi-axes AXES, turned by rotation()."""
    vertices, faces = icosphere(1.0, subdivisions)
    return (vertices * np.array(AXES)) @ rotation().T, faces


def write_obj(path, vertices, faces):
    """An OBJ file whose coordinates read back exactly (17 significant digits)."""
    with open(path, "w") as out:
        out.writelines(f"v {x:.17g} {y:.17g} {z:.17g}\n" for x, y, z in vertices)
        out.writelines(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in faces)


def read_ply_vertex_properties(path):
    """The vertex properties of a binary little-endian PLY file whose vertex
    properties are all doubles, as a dict of arrays."""
    data = Path(path).read_bytes()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    header = data[:end].decode().splitlines()
    count = next(int(line.split()[2]) for line in header if line.startswith("element vertex"))
    names = []
    for line in header[header.index(next(h for h in header if h.startswith("element vertex"))) + 1:]:
        if not line.startswith("property"):
            break
        kind, name = line.split()[1:]
        assert kind == "double", f"{name} is {kind}"
        names.append(name)
    values = np.frombuffer(data, dtype="<f8", count=count * len(names), offset=end).reshape(count, len(names))
    assert struct.calcsize("<d") == 8
    return {name: values[:, i] for i, name in enumerate(names)}


@pytest.mark.parametrize("estimator", ["shape-operator", "jet-fit"])
def test_curvature_equals_the_tools_to_1e_12(tool, tmp_path, estimator):
    vertices, faces = ellipsoid()
    write_obj(tmp_path / "ellipsoid.obj", vertices, faces)
    subprocess.run([tool, "curvature", tmp_path / "ellipsoid.obj", "-o", tmp_path / "curvature.ply",
                    "--estimator", estimator], check=True, capture_output=True)
    cli = read_ply_vertex_properties(tmp_path / "curvature.ply")
    assert np.array_equal(np.column_stack([cli["x"], cli["y"], cli["z"]]), vertices)
    field = crestline.curvature(vertices, faces, estimator=estimator)
    for name in ("k_max", "k_min"):
        assert np.abs(field[name] - cli[name]).max() < 1e-12
    for name, prefix in (("d_max", "dmax"), ("d_min", "dmin"), ("normal", "n")):
        theirs = np.column_stack([cli[f"{prefix}_{c}"] for c in "xyz"])
        assert np.abs(field[name] - theirs).max() < 1e-12
    # And the curvature is the ellipsoid's: k between 0.45/1² and 1/0.45².
    assert 0.4 < field["k_min"].min() and field["k_max"].max() < 5.3


def test_ridges_equal_the_tools(tool, tmp_path):
    vertices, faces = ellipsoid()
    write_obj(tmp_path / "ellipsoid.obj", vertices, faces)
    subprocess.run([tool, "ridges", tmp_path / "ellipsoid.obj", "-o", tmp_path / "lines.json"],
                   check=True, capture_output=True)
    cli = json.loads((tmp_path / "lines.json").read_text())["lines"]
    lines = crestline.ridges(vertices, faces)
    assert len(lines) == len(cli) > 0
    for ours, theirs in zip(lines, cli):
        assert ours.kind == theirs["kind"] and ours.closed == theirs["closed"]
        assert abs(ours.strength - theirs["strength"]) < 1e-12
        assert np.abs(ours.points - np.array(theirs["points"])).max() < 1e-12
    # The one ridge is the ellipsoid's largest principal ellipse, round the
    # longest and middle axes: in their plane, and as long (Ramanujan's perimeter).
    ridges = lines.of_kind("ridge")
    assert len(ridges) == 1 and ridges[0].closed
    normal = rotation()[:, 2]
    assert np.abs(ridges[0].points @ normal).mean() < 1e-3
    a, b = AXES[:2]
    h = ((a - b) / (a + b)) ** 2
    perimeter = np.pi * (a + b) * (1 + 3 * h / (10 + np.sqrt(4 - 3 * h)))
    assert abs(ridges[0].length() / perimeter - 1) < 0.01


def test_compare_equals_the_tools(tool, tmp_path):
    """A mesh's lines against a shifted copy's markups, moved back by a transform
    file and by the same matrix: the tool's report and the package's dict agree."""
    vertices, faces, _ = crestline.read_mesh(ROOT / "meshes" / "bunny_small.obj")
    crestline.ridges(vertices, faces).save(tmp_path / "a.json")
    shift = np.array([0.5, -0.25, 1.0])
    crestline.ridges(vertices + shift, faces).save(tmp_path / "b.json")
    back = np.eye(4)
    back[:3, 3] = -shift
    crestline.write_transform(tmp_path / "back.json", back)
    report = tmp_path / "report.json"
    subprocess.run([tool, "compare", tmp_path / "a.json", tmp_path / "b.json", "--transform",
                    tmp_path / "back.json", "--tolerance", "0.5%", "--report", report],
                   check=True, capture_output=True)
    cli = json.loads(report.read_text())["comparison"]
    for transform in (tmp_path / "back.json", back):
        ours = crestline.compare(tmp_path / "a.json", tmp_path / "b.json", transform=transform, tolerance="0.5%")
        assert ours == cli
    assert {row["kind"] for row in cli["lines"]} == {"ridge", "valley"}
    assert all(row["a_in_b"] > 0.999 for row in cli["lines"])

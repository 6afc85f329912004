"""pymeshlab reads the ``quality`` vertex property of the command-line tool's
curvature PLY file as the quantity chosen with ``--quality``: the same values the
file's own columns give, read here with numpy. Skipped when pymeshlab is not
installed or the tool is not built (``cargo build --release``)."""

import re
import subprocess
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[3]
TOOL = ROOT / "target" / "release" / "crestline"
MESH = ROOT / "meshes" / "bunny_small.obj"


@pytest.fixture(scope="module")
def tool():
    if not TOOL.exists():
        pytest.skip(f"{TOOL} is not built (run cargo build --release)")
    return TOOL


def quality_choices(tool):
    """The names ``--quality`` takes and its default, as the tool's help lists them."""
    help_text = subprocess.run([tool, "curvature", "--help"], check=True, capture_output=True, text=True).stdout
    option = re.search(r"^\s+--quality <.*?(?=^\s+-|\Z)", help_text, re.MULTILINE | re.DOTALL).group(0)
    names = re.search(r"\[possible values: ([^\]]+)\]", option).group(1).split(", ")
    default = re.search(r"\[default: ([^\]]+)\]", option).group(1)
    return names, default


def read_ply_vertex_properties(path):
    """The vertex properties of a binary little-endian PLY file whose vertex
    properties are all doubles, as a dict of arrays."""
    data = Path(path).read_bytes()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    header = data[:end].decode().splitlines()
    assert "format binary_little_endian 1.0" in header
    start = next(i for i, line in enumerate(header) if line.startswith("element vertex"))
    count = int(header[start].split()[2])
    names = []
    for line in header[start + 1:]:
        if not line.startswith("property"):
            break
        kind, name = line.split()[1:]
        assert kind == "double", f"{name} is {kind}"
        names.append(name)
    values = np.frombuffer(data, dtype="<f8", count=count * len(names), offset=end).reshape(count, len(names))
    return {name: values[:, i] for i, name in enumerate(names)}


def expected_quality(columns, name):
    """The quantity ``name`` from the file's own columns."""
    if name == "curvedness":
        return np.sqrt((columns["k_max"] ** 2 + columns["k_min"] ** 2) / 2)
    return columns[name]


def meshlab_quality(pymeshlab, path):
    """The per-vertex quality of the PLY file at ``path`` as pymeshlab loads it."""
    meshes = pymeshlab.MeshSet()
    meshes.load_new_mesh(str(path))
    return np.asarray(meshes.current_mesh().vertex_scalar_array(), dtype=np.float64)


def test_the_tool_offers_every_quantity_with_the_mean_as_default(tool):
    names, default = quality_choices(tool)
    assert set(names) == {"k_max", "k_min", "mean", "gauss", "curvedness"}
    assert default == "mean"


@pytest.mark.parametrize("choice", [None, "k_max", "k_min", "mean", "gauss", "curvedness"])
def test_pymeshlab_reads_the_chosen_quantity_as_quality(tool, pymeshlab, tmp_path, choice):
    path = tmp_path / "curvature.ply"
    option = [] if choice is None else ["--quality", choice]
    subprocess.run([tool, "curvature", MESH, "-o", path, *option], check=True, capture_output=True, cwd=ROOT)
    name = quality_choices(tool)[1] if choice is None else choice
    columns = read_ply_vertex_properties(path)
    expected = expected_quality(columns, name)
    assert np.array_equal(columns["quality"], expected)
    theirs = meshlab_quality(pymeshlab, path)
    assert theirs.shape == expected.shape
    # MeshLab may keep the quality in single precision.
    scale = np.abs(expected).max()
    assert scale > 0
    np.testing.assert_allclose(theirs, expected, rtol=1e-6, atol=1e-7 * scale)

"""Connectome Workbench border files (``.border``) of the ridges of a cortical
surface: the file passes every check of Workbench's own reader of version 3
(``BorderFile::parseBorderFile3``, ``Border::readXML3``), and its points, unprojected
on the surface file's vertices, are the lines' points. Skipped when the tool is not
built (``cargo build --release``)."""

import json
import subprocess
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[3]
TOOL = ROOT / "target" / "release" / "crestline"
PIAL = ROOT / "meshes" / "fsaverage5_pial_left.obj"

# Workbench's StructureEnum names, as border files spell them.
STRUCTURES = {"CORTEX_LEFT", "CORTEX_RIGHT", "OTHER", "CEREBELLUM", "ALL", "INVALID"}


@pytest.fixture(scope="module")
def tool():
    if not TOOL.exists():
        pytest.skip(f"{TOOL} is not built (run cargo build --release)")
    return TOOL


def read_workbench_border(path):
    """The border file at ``path`` read by Workbench's rules for version 3: a
    ``BorderFile`` root with ``Version="3"``, a known ``Structure`` and a positive
    ``SurfaceNumberOfVertices``; optional ``MetaData``; classes with a name and
    ``Red``/``Green``/``Blue``, each holding at least one border, names unique in
    their class; borders with colours and at least one part; parts with
    ``Closed="True"|"False"``, one ``Vertices`` and one ``Weights`` element whose
    items come in threes, as many of each, vertices non-negative integers below
    the surface's count, weights numbers. Returns the vertex count and
    ``{class: [(closed, vertices (n, 3), weights (n, 3)), ...]}``; any breach fails
    the test, as Workbench would refuse the file."""
    root = ET.parse(path).getroot()
    assert root.tag == "BorderFile"
    assert root.get("Version") == "3"
    assert root.get("Structure") in STRUCTURES, root.get("Structure")
    count = int(root.get("SurfaceNumberOfVertices"))
    assert count >= 1
    classes = {}
    for element in root:
        if element.tag == "MetaData":
            assert all(md.tag == "MD" and [c.tag for c in md] == ["Name", "Value"] for md in element)
            continue
        assert element.tag == "Class", element.tag
        name = element.get("Name")
        assert name is not None and name not in classes
        colour(element)
        borders = set()
        parts = []
        for border in element:
            assert border.tag == "Border"
            assert border.get("Name") not in borders
            borders.add(border.get("Name"))
            colour(border)
            assert len(border) >= 1
            for part in border:
                assert part.tag == "BorderPart"
                assert part.get("Closed") in ("True", "False")
                assert [c.tag for c in part] == ["Vertices", "Weights"]
                vertices = part.find("Vertices").text.split()
                weights = part.find("Weights").text.split()
                assert len(vertices) % 3 == 0 and len(vertices) == len(weights)
                vertices = np.array([int(v) for v in vertices]).reshape(-1, 3)
                weights = np.array([float(w) for w in weights]).reshape(-1, 3)
                assert (vertices >= 0).all() and (vertices < count).all()
                assert (weights >= 0).all()
                parts.append((part.get("Closed") == "True", vertices, weights))
        assert borders, f"class {name} has no border"
        classes[name] = parts
    return count, classes


def colour(element):
    """The element's Red, Green and Blue, which must be numbers."""
    return [float(element.get(c)) for c in ("Red", "Green", "Blue")]


def read_obj_vertices(path):
    """The ``v`` records of an OBJ file, in file order."""
    rows = [line.split()[1:4] for line in Path(path).read_text().splitlines() if line.startswith("v ")]
    return np.array(rows, dtype=float)


# The border class of each kind of line: its family's name.
FAMILIES = {"ridge": "ridges", "valley": "valleys", "ascending": "ascending", "descending": "descending"}


def check_border_against_lines(tool, surface, vertices, tmp_path, command="ridges"):
    """Trace the lines of ``command`` on ``surface`` into a border file and a
    lines JSON; the border passes Workbench's checks, has a class per family and a
    part per line, and its points, unprojected on ``vertices`` (the surface
    file's, in its order), are the lines' points."""
    border, lines_json = tmp_path / "lh.lines.border", tmp_path / "lh.lines.json"
    for output in (border, lines_json):
        subprocess.run(
            [tool, command, surface, "-o", output, "--structure", "CortexLeft"],
            check=True,
            capture_output=True,
        )
    count, classes = read_workbench_border(border)
    assert count == len(vertices)
    assert ET.parse(border).getroot().get("Structure") == "CORTEX_LEFT"
    lines = json.loads(lines_json.read_text())["lines"]
    by_kind = {
        family: [line for line in lines if line["kind"] == kind] for kind, family in FAMILIES.items()
    }
    assert set(classes) == {family for family, found in by_kind.items() if found}
    assert sum(map(len, by_kind.values())) > 20
    worst = 0.0
    for name, parts in classes.items():
        assert len(parts) == len(by_kind[name])
        for (closed, triangle, weights), line in zip(parts, by_kind[name]):
            assert closed == line["closed"]
            points = np.einsum("nk,nkj->nj", weights, vertices[triangle]) / weights.sum(axis=1)[:, None]
            worst = max(worst, np.abs(points - np.array(line["points"])).max())
    # Both files hold the same locations, to 17 digits; the surface's coordinates
    # are float32 in the GIfTI file, read the same by nibabel and crestline.
    assert worst < 1e-6, worst


def test_border_of_a_repaired_mesh_uses_the_files_vertex_numbers(tool, tmp_path):
    # An unreferenced vertex first: the mesh drops it, so the mesh's vertex numbers
    # are one less than the file's, and the border must use the file's.
    surface = tmp_path / "lh.pial.obj"
    shifted = (
        "f " + " ".join(str(int(i) + 1) for i in line.split()[1:]) if line.startswith("f ") else line
        for line in PIAL.read_text().splitlines()
    )
    surface.write_text("v 0 0 0\n" + "\n".join(shifted) + "\n")
    check_border_against_lines(tool, surface, read_obj_vertices(surface), tmp_path)


def test_border_of_fsaverage5_fits_the_gifti_surface_as_nibabel_reads_it(tool, tmp_path):
    gifti = ROOT / "data" / "fsaverage" / "pial_left.gii"
    if not gifti.exists():
        pytest.skip(f"{gifti} is absent (run tools/fetch_fsaverage.sh)")
    nibabel = pytest.importorskip("nibabel")
    vertices = nibabel.load(gifti).agg_data("NIFTI_INTENT_POINTSET").astype(float)
    check_border_against_lines(tool, gifti, vertices, tmp_path)


def test_morse_lines_as_a_border_file_lie_where_the_lines_are(tool, tmp_path):
    # Morse-Smale lines are faired on the surface: every point keeps its place on
    # the mesh, so the border holds them as they are.
    check_border_against_lines(tool, PIAL, read_obj_vertices(PIAL), tmp_path, command="morse")

"""Drawings as pen-plotter users open them: read by vpype (the plotting pipeline most
such users run), with its own rules for layers and pages."""

import subprocess
from pathlib import Path

import numpy as np
import pytest
import vpype
from scipy.spatial import cKDTree
from vpype_cli import execute

import crestline

ROOT = Path(__file__).resolve().parents[3]
TOOL = ROOT / "target" / "release" / "crestline"

# vpype measures in CSS pixels: 96 per inch.
PX_PER_MM = 96 / 25.4


@pytest.fixture(scope="module")
def bunny():
    vertices, faces, _ = crestline.read_mesh(ROOT / "meshes" / "bunny.obj")
    return vertices, faces


def read(tmp_path, svg):
    path = tmp_path / "drawing.svg"
    path.write_text(svg)
    return vpype.read_multilayer_svg(str(path), quantization=0.1)


def plotted(name, tmp_path):
    """The file of the --plot drawing of a bundled mesh (silhouettes and ridges) or
    of the MNI template's crest lines."""
    path = tmp_path / f"{name}.svg"
    if name == "mni":
        if not TOOL.exists():
            pytest.skip(f"{TOOL} is not built (run cargo build --release)")
        volume = ROOT / "volumes" / "mni152_t1_1mm.nii.gz"
        subprocess.run([TOOL, "draw", volume, "--level", "60", "--lines", "crest", "--plot", "-o", path],
                       check=True, capture_output=True)
    else:
        vertices, faces, _ = crestline.read_mesh(ROOT / "meshes" / f"{name}.obj")
        path.write_text(crestline.draw(vertices, faces, silhouettes=True, plot=True))
    return path


def pen_up(document):
    return sum(layer.pen_up_length()[0] for layer in document.layers.values())


def share_beside_another_stroke(document, distance=0.5, step=0.1):
    """The share of the drawn length within `distance` of another stroke, from
    samples every `step` along every stroke."""
    strokes = [line for layer in document.layers.values() for line in layer]
    samples, owners = [], []
    for k, line in enumerate(strokes):
        points = np.column_stack([line.real, line.imag])
        for a, b in zip(points[:-1], points[1:]):
            count = max(1, int(np.ceil(np.hypot(*(b - a)) / step)))
            samples.append(a + (b - a) * (np.arange(count) / count)[:, None])
            owners.append(np.full(count, k))
    points, owners = np.vstack(samples), np.concatenate(owners)
    near = cKDTree(points).query_ball_point(points, distance)
    beside = [any(owners[j] != owners[i] for j in neighbours) for i, neighbours in enumerate(near)]
    return float(np.mean(beside))


@pytest.mark.parametrize("name", ["bunny", "cow", "mni"])
def test_vpype_cannot_shorten_the_pens_travel_and_no_stroke_is_drawn_twice(name, tmp_path):
    path = plotted(name, tmp_path)
    ours = vpype.read_multilayer_svg(str(path), quantization=0.1)
    theirs = execute(f"read '{path}' linemerge linesort")
    assert len(theirs.layers) == len(ours.layers)
    assert pen_up(ours) <= pen_up(theirs) + 1e-6
    assert share_beside_another_stroke(ours) < 0.01


def test_plotting_shortens_the_travel_and_drops_nothing_but_duplicates(bunny, tmp_path):
    plain = read(tmp_path, crestline.draw(*bunny, silhouettes=True))
    plot = read(tmp_path, crestline.draw(*bunny, silhouettes=True, plot=True))
    assert pen_up(plot) < 0.4 * pen_up(plain)
    drawn = [sum(layer.length() for layer in d.layers.values()) for d in (plain, plot)]
    assert 0.95 * drawn[0] < drawn[1] <= drawn[0]
    with pytest.raises(crestline.ArgumentError, match="pen draws every stroke alike"):
        crestline.draw(*bunny, plot=True, taper=5.0)


def test_every_family_is_a_named_layer_in_plotting_order(bunny, tmp_path):
    document = read(tmp_path, crestline.draw(*bunny, silhouettes=True, view=(20, 15)))
    layers = [document.layers[i] for i in sorted(document.layers)]
    assert sorted(document.layers) == [1, 2, 3]
    assert [layer.property("vp_name") for layer in layers] == ["1 silhouettes", "2 ridges", "3 valleys"]
    assert all(len(layer) > 0 for layer in layers)
    # The white background is no path: a plotter would draw it as a frame around the
    # page, which spans the whole canvas.
    for layer in layers:
        for line in layer:
            xs, ys = line.real, line.imag
            assert xs.max() - xs.min() < 790 or ys.max() - ys.min() < 790


@pytest.mark.parametrize("paper, landscape, size_mm", [("a4", False, (210, 297)), ("letter", True, (279.4, 215.9))])
def test_the_page_is_the_paper_asked_for_and_the_lines_keep_its_margin(bunny, tmp_path, paper, landscape, size_mm):
    page = {"paper": paper, "landscape": landscape, "margin": "15mm", "pen": "0.3mm"}
    document = read(tmp_path, crestline.draw(*bunny, silhouettes=True, page=page))
    width, height = document.page_size
    assert width == pytest.approx(size_mm[0] * PX_PER_MM, rel=1e-6)
    assert height == pytest.approx(size_mm[1] * PX_PER_MM, rel=1e-6)
    x0, y0, x1, y1 = document.bounds()
    margin = 15 * PX_PER_MM
    assert x0 >= margin - 1e-6 and y0 >= margin - 1e-6
    assert x1 <= width - margin + 1e-6 and y1 <= height - margin + 1e-6
    # The drawing fills the printable area but for the framing's 5% on each side.
    assert max((x1 - x0) / (width - 2 * margin), (y1 - y0) / (height - 2 * margin)) > 0.85
    for i in document.layers:
        assert document.layers[i].property("vp_pen_width") == pytest.approx(0.3 * PX_PER_MM, rel=1e-3)


def test_a_page_refuses_a_size_and_a_margin_that_leaves_nothing(bunny):
    with pytest.raises(crestline.ArgumentError, match="size"):
        crestline.draw(*bunny, page="a4", size=(100, 100))
    with pytest.raises(crestline.ArgumentError, match="leaves nothing"):
        crestline.draw(*bunny, page={"paper": "a5", "margin": "80mm"})

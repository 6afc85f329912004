"""Interactive views from Python: the same page as the tool's, shown in Jupyter."""

import html
from pathlib import Path

import pytest

import crestline

ROOT = Path(__file__).resolve().parents[3]


@pytest.fixture(scope="module")
def bunny_small():
    vertices, faces, _ = crestline.read_mesh(ROOT / "meshes" / "bunny_small.obj")
    return vertices, faces


def test_lines_show_on_their_mesh_as_a_self_contained_page(bunny_small, tmp_path):
    lines = crestline.ridges(*bunny_small)
    view = lines.show(*bunny_small, title="bunny & co")
    page = view.html
    assert page.startswith("<!DOCTYPE html>") and "<title>bunny &amp; co</title>" in page
    # three.js and its licence are in the page; nothing is fetched.
    assert "three.js authors" in page and "Permission is hereby granted" in page
    assert '<script src=' not in page and "<link" not in page
    # Jupyter shows it in an iframe of its own.
    frame = view._repr_html_()
    assert frame.startswith("<iframe srcdoc=") and html.unescape(frame.split('"')[1]) == page
    view.save(tmp_path / "bunny.html")
    assert (tmp_path / "bunny.html").read_text(encoding="utf-8") == page
    lines.show(*bunny_small, title="bunny & co", path=tmp_path / "shown.html")
    assert (tmp_path / "shown.html").read_text(encoding="utf-8") == page
    # The families shown are those of the lines.
    assert '"name":"ridges"' in page and '"name":"valleys"' in page


def test_view_traces_the_lines_it_is_asked_for(bunny_small):
    none = crestline.view(*bunny_small, lines="none").html
    assert '"families":[]' in none
    morse = crestline.view(*bunny_small, lines="morse").html
    assert '"name":"ascending"' in morse
    with pytest.raises(crestline.ArgumentError, match="unknown option of view"):
        crestline.view(*bunny_small, colour="red")

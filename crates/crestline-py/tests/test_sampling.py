"""The same surface sampled otherwise gives the same lines at a feature scale:
the bunny remeshed and decimated by pymeshlab and turned by a rotation, its lines
mapped back by :func:`crestline.compare`'s ``transform``. Skipped when pymeshlab
is not installed."""

from pathlib import Path

import numpy as np
import pytest

import crestline

ROOT = Path(__file__).resolve().parents[3]
BUNNY = ROOT / "meshes" / "bunny.obj"
# One hundredth of the square root of the bunny's area (0.92): 1.5 mean edge
# lengths of the scan, 0.8 of its copy decimated to a quarter.
SCALE = 0.0096


def rotation(seed):
    """A random rotation matrix."""
    q, _ = np.linalg.qr(np.random.default_rng(seed).normal(size=(3, 3)))
    return q * np.sign(np.linalg.det(q))


def resampled(pymeshlab, how):
    """The bunny remeshed at its mean edge length, or decimated to half its faces."""
    ms = pymeshlab.MeshSet()
    ms.load_new_mesh(str(BUNNY))
    if how == "remeshed":
        length = ms.get_geometric_measures()["avg_edge_length"]
        ms.meshing_isotropic_explicit_remeshing(targetlen=pymeshlab.PureValue(length), iterations=5)
    else:
        faces = ms.current_mesh().face_number() // 2
        ms.meshing_decimation_quadric_edge_collapse(targetfacenum=faces, preservenormal=True,
                                                    preservetopology=True)
    mesh = ms.current_mesh()
    return mesh.vertex_matrix(), mesh.face_matrix()


@pytest.mark.parametrize("how, seed", [("remeshed", 1), ("decimated", 2)])
def test_a_remeshed_or_decimated_turned_bunny_has_the_same_ridges_at_a_scale(pymeshlab, tmp_path, how, seed):
    vertices, faces, _ = crestline.read_mesh(BUNNY)
    copy, copy_faces = resampled(pymeshlab, how)
    turn = rotation(seed)
    crestline.ridges(vertices, faces, scale=SCALE).save(tmp_path / "a.json")
    crestline.ridges(copy @ turn.T, copy_faces, scale=SCALE).save(tmp_path / "b.json")
    back = np.eye(4)
    back[:3, :3] = turn.T
    found = crestline.compare(tmp_path / "a.json", tmp_path / "b.json", transform=back, tolerance="0.5%")
    rows = {row["kind"]: row for row in found["lines"]}
    assert set(rows) == {"ridge", "valley"}
    for kind, row in rows.items():
        assert row["a_in_b"] >= 0.85 and row["b_in_a"] >= 0.85, (kind, row)
    counts = [sum(row[side] for row in rows.values()) for side in ("a_count", "b_count")]
    assert abs(counts[1] / counts[0] - 1) <= 0.2, rows


def test_compare_reads_the_transform_register_returns_and_refuses_a_scaling(tmp_path):
    vertices, faces, _ = crestline.read_mesh(ROOT / "meshes" / "bunny_small.obj")
    lines = crestline.ridges(vertices, faces)
    lines.save(tmp_path / "a.json")
    shift = np.eye(4)
    shift[:3, 3] = [0.5, -0.25, 1.0]
    crestline.ridges(vertices + shift[:3, 3], faces).save(tmp_path / "b.json")
    back = np.linalg.inv(shift)
    found = crestline.compare(tmp_path / "a.json", tmp_path / "b.json", transform={"matrix": back}, tolerance=1e-6)
    assert all(row["a_in_b"] > 0.999 and row["b_in_a"] > 0.999 for row in found["lines"])
    assert found["tolerance"] == pytest.approx(1e-6)
    with pytest.raises(crestline.Error, match="rotation"):
        crestline.compare(tmp_path / "a.json", tmp_path / "b.json", transform=np.diag([2.0, 1.0, 1.0, 1.0]))

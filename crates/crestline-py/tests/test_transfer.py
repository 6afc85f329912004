"""``crestline.transfer`` computes what the command-line tool's ``transfer``
writes, on images (the MNI template and a copy moved rigidly by its affine) and on
meshes (the small bunny and a moved copy), from files and from objects; the
landmarks land where the motion takes them, and the markups written follow 3D
Slicer's schema. Skipped when the tool is not built
(``cargo build --release``)."""

import csv
import subprocess

import numpy as np
import pytest

import crestline

from test_frames import markups_points
from test_same_as_cli import ROOT, rotation, tool, write_obj  # noqa: F401 (tool: a fixture)

MNI = ROOT / "volumes" / "mni152_t1_1mm.nii.gz"
BUNNY = ROOT / "meshes" / "bunny_small.obj"


def motion(angles, shift):
    """A 4 × 4 rigid motion."""
    matrix = np.eye(4)
    matrix[:3, :3] = rotation(angles)
    matrix[:3, 3] = shift
    return matrix


def moved(matrix, points):
    return points @ matrix[:3, :3].T + matrix[:3, 3]


def landmarks_csv(path, lines, space="RAS", every=None):
    """About 30 points spread over the ridge and valley lines (in ``space``)
    written as a landmarks CSV; their labels and positions."""
    crests = np.vstack([line.points for line in lines if line.kind in ("ridge", "valley")])
    chosen = crests[:: max(1, len(crests) // 30)]
    labels = [f"P{n:02d}" for n in range(len(chosen))]
    with open(path, "w") as f:
        f.write("label,x,y,z,space\n")
        f.writelines(f"{label},{x:.17g},{y:.17g},{z:.17g},{space}\n" for label, (x, y, z) in zip(labels, chosen))
    return labels, chosen


def read_csv(path):
    """Labels, positions (RAS) and confidence of the tool's CSV output; no
    landmark flagged."""
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    assert all(row["space"] == "RAS" and row["flagged"] == "false" for row in rows)
    positions = np.array([[float(row[c]) for c in "xyz"] for row in rows])
    return [row["label"] for row in rows], positions, np.array([float(row["confidence"]) for row in rows])


def run_tool(tool, *args):
    done = subprocess.run([str(tool), "transfer", *map(str, args)], capture_output=True, text=True, cwd=ROOT)
    assert done.returncode == 0, done.stderr


def test_images_give_the_tools_landmarks(tool, tmp_path):
    nib = pytest.importorskip("nibabel")
    template = crestline.read_volume(MNI)
    # The subject: the same samples placed by a moved affine, a rigid motion of 3°
    # and a few millimetres in RAS.
    truth = motion((0.03, -0.04, 0.05), (2.0, -3.0, 1.5))
    subject = tmp_path / "subject.nii.gz"
    nib.save(nib.Nifti1Image(template.data, truth @ template.affine), subject)
    csv_path = tmp_path / "landmarks.csv"
    labels, chosen = landmarks_csv(csv_path, crestline.crest_lines(template, level=60))
    out = tmp_path / "tool.csv"
    run_tool(tool, MNI, csv_path, subject, "-o", out, "--level", "60")
    tool_labels, tool_positions, tool_confidence = read_csv(out)

    from_files = crestline.transfer(MNI, csv_path, subject, level=60)
    assert from_files["labels"] == tool_labels == labels
    assert np.abs(from_files["positions"] - tool_positions).max() < 1e-9
    assert np.abs(from_files["confidence"] - tool_confidence).max() < 1e-9
    # The same from objects, the template's lines given once, as the first
    # transfer registered them.
    from_objects = crestline.transfer(template, dict(zip(labels, chosen)), crestline.read_volume(subject),
                                      level=60, template_lines=from_files["template_lines"])
    assert np.abs(from_objects["positions"] - tool_positions).max() < 1e-9
    errors = np.linalg.norm(from_files["positions"] - moved(truth, chosen), axis=1)
    assert np.median(errors) < 0.3, errors


def test_meshes_give_the_tools_landmarks(tool, tmp_path):
    vertices, faces, _ = crestline.read_mesh(BUNNY)
    truth = motion((0.05, 0.02, -0.04), (0.4, -0.2, 0.3))
    subject = tmp_path / "subject.obj"
    write_obj(subject, moved(truth, vertices), faces)
    lines = crestline.ridges(vertices, faces, threshold=crestline.defaults()["transfer"]["mesh_threshold"])
    # The OBJ files state no frame: LPS, as the tool takes them; the landmarks
    # are written in LPS too.
    csv_path = tmp_path / "landmarks.csv"
    labels, chosen = landmarks_csv(csv_path, lines, space="LPS")
    out = tmp_path / "tool.csv"
    run_tool(tool, BUNNY, csv_path, subject, "-o", out, "--scales", "3,2,1")
    tool_labels, tool_positions, tool_confidence = read_csv(out)
    lps = np.array([-1.0, -1.0, 1.0])

    found = crestline.transfer(BUNNY, csv_path, subject, scales=[3, 2, 1])
    assert found["labels"] == tool_labels == labels
    assert np.abs(found["positions"] - tool_positions).max() < 1e-9
    assert np.abs(found["confidence"] - tool_confidence).max() < 1e-9
    from_arrays = crestline.transfer(crestline.Mesh(vertices, faces), (labels, chosen * lps),
                                     crestline.Mesh(moved(truth, vertices), faces), scales=[3, 2, 1])
    assert np.abs(from_arrays["positions"] - tool_positions).max() < 1e-9
    errors = np.linalg.norm(found["positions"] * lps - moved(truth, chosen), axis=1)
    assert np.median(errors) < 1e-3, errors


def test_the_output_is_written_as_the_tool_writes_it(tmp_path):
    vertices, faces, _ = crestline.read_mesh(BUNNY)
    marks = {"tip": vertices[0], "other": vertices[100]}
    out = tmp_path / "moved.mrk.json"
    found = crestline.transfer(crestline.Mesh(vertices, faces), marks, crestline.Mesh(vertices, faces),
                               scales=[2], output=out)
    labels, positions = crestline.read_labelled(out)
    assert labels == found["labels"] == ["tip", "other"]
    assert np.abs(positions - found["positions"]).max() < 1e-9
    assert found["flagged"] == [False, False] and np.all(found["coverage"] > 0.5)
    # 3D Slicer's markups schema, the positions in LPS.
    lps, document = markups_points(out)
    assert [m["type"] for m in document["markups"]] == ["Fiducial"]
    assert np.abs(lps - found["positions"] * np.array([-1.0, -1.0, 1.0])).max() < 1e-9


def test_bad_arguments_are_named():
    with pytest.raises(ValueError, match="scales"):
        crestline.transfer(BUNNY, {"a": (0, 0, 0)}, BUNNY, scales=[0])
    with pytest.raises(ValueError, match="landmarks"):
        crestline.transfer(BUNNY, (["a", "b"], [(0, 0, 0)]), BUNNY)
    # Scales in millimetres on a model in metres: refused, not a grid of 10¹² nodes.
    with pytest.raises(crestline.ArgumentError, match="too small"):
        crestline.transfer(BUNNY, {"a": (0, 0, 0)}, BUNNY, scales=[0.0001])
    with pytest.raises(crestline.FileError, match="no-such"):
        crestline.transfer(BUNNY, "no-such.mrk.json", BUNNY)

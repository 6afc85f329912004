"""Cohort runs on a 2-worker Dask LocalCluster: good and broken scans, results equal
to the calls made one by one, and an interrupted run resumed without recomputing
finished subjects."""

import csv
import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

import crestline

distributed = pytest.importorskip("dask.distributed")
nib = pytest.importorskip("nibabel")
cohort = pytest.importorskip("crestline.cohort")


def ellipsoid_image(path, n, axes):
    """An n³ image of 1 − (ellipsoidal radius), its level 0 an ellipsoid."""
    ax = np.arange(n, dtype=np.float64)
    i, j, k = np.meshgrid(ax, ax, ax, indexing="ij")
    c = (n - 1) / 2 + 0.1
    data = 1 - np.sqrt(((i - c) / axes[0]) ** 2 + ((j - c) / axes[1]) ** 2 + ((k - c) / axes[2]) ** 2)
    nib.save(nib.Nifti1Image(data.astype(np.float32), np.diag([1.0, 1.0, 1.0, 1.0])), path)


def cohort_files(folder, n, count):
    paths = []
    for s in range(count):
        path = folder / f"sub-{s:02d}.nii.gz"
        ellipsoid_image(path, n, (0.35 * n + s % 4, 0.27 * n - s % 3, 0.2 * n))
        paths.append(path)
    return paths


@pytest.fixture(scope="module")
def client():
    cluster = distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None)
    with distributed.Client(cluster) as c:
        yield c
    cluster.close()


def test_good_and_broken_scans_give_ok_and_error_rows_equal_to_single_calls(client, tmp_path):
    paths = cohort_files(tmp_path, 40, 12)
    (tmp_path / "garbage.nii.gz").write_bytes(b"not an image at all")
    truncated = tmp_path / "truncated.nii"
    nib.save(nib.Nifti1Image(np.zeros((20, 20, 20), np.float32), np.eye(4)), truncated)
    truncated.write_bytes(truncated.read_bytes()[:2000])
    inputs = [*paths, tmp_path / "garbage.nii.gz", truncated]
    rows = cohort.run(inputs, tmp_path / "out", task="landmarks", options={"level": 0.0}, client=client,
                      progress=False)
    assert [row["subject"] for row in rows] == [cohort.subject_of(p) for p in inputs]
    assert [row["status"] for row in rows] == ["ok"] * 12 + ["error"] * 2
    assert "garbage.nii.gz" in rows[12]["error"] and "truncated.nii" in rows[13]["error"]
    assert not (tmp_path / "out" / "garbage").exists()
    for path, row in zip(paths, rows):
        lines = crestline.crest_lines(crestline.read_volume(path), level=0.0)
        marks = crestline.landmarks(lines, radius=5.0, persistence=2.0)["points"]
        saved = json.loads((tmp_path / "out" / row["subject"] / "lines.json").read_text())["lines"]
        assert len(saved) == len(lines) == row["lines"] > 0
        for ours, theirs in zip(lines, saved):
            assert np.array_equal(ours.points, np.array(theirs["points"]))
        with open(tmp_path / "out" / row["subject"] / "landmarks.csv") as f:
            table = list(csv.DictReader(f))
        assert len(table) == len(marks["kind"]) == row["points"]
        assert np.array_equal(np.array([[float(r[c]) for c in "xyz"] for r in table]), marks["position"])
    with open(tmp_path / "out" / "summary.csv") as f:
        summary = list(csv.DictReader(f))
    assert [r["status"] for r in summary] == [row["status"] for row in rows]
    with open(tmp_path / "out" / "landmarks.csv") as f:
        everything = list(csv.DictReader(f))
    assert len(everything) == sum(row["points"] for row in rows)
    assert {r["subject"] for r in everything} == {row["subject"] for row in rows[:12]}


def test_an_interrupted_run_resumes_without_recomputing_finished_subjects(client, tmp_path):
    paths = cohort_files(tmp_path, 100, 12)
    out = tmp_path / "out"
    command = [sys.executable, "-m", "crestline.cohort", *map(str, paths), "-o", str(out), "--level", "0",
               "--no-progress"]
    run = subprocess.Popen(command, start_new_session=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    deadline = time.time() + 120
    while len(list(out.glob("*/manifest.json"))) < 3 and time.time() < deadline and run.poll() is None:
        time.sleep(0.02)
    os.killpg(run.pid, signal.SIGKILL)
    run.wait()
    finished = {m.parent.name: json.loads(m.read_text())["finished"] for m in out.glob("*/manifest.json")}
    assert 3 <= len(finished) < 12, f"{len(finished)} subjects finished before the kill"
    rows = cohort.run(paths, out, task="landmarks", options={"level": 0.0}, client=client, progress=False)
    assert [row["status"] for row in rows] == ["ok"] * 12
    for row in rows:
        manifest = json.loads((out / row["subject"] / "manifest.json").read_text())
        if row["subject"] in finished:
            assert row["reused"] and manifest["finished"] == finished[row["subject"]]
        else:
            assert not row["reused"]
    # A changed option recomputes everything.
    again = cohort.run(paths[:2], out, task="landmarks", options={"level": 0.1}, client=client, progress=False)
    assert [row["reused"] for row in again] == [False, False]


def test_inputs_from_a_csv_with_per_subject_options(client, tmp_path):
    paths = cohort_files(tmp_path, 32, 2)
    table = tmp_path / "cohort.csv"
    table.write_text(f"subject,path,level\nfirst,{paths[0].name},0.0\nsecond,{paths[1]},0.2\n")
    rows = cohort.run(table, tmp_path / "out", task="isosurface", client=client, progress=False)
    assert [(row["subject"], row["status"]) for row in rows] == [("first", "ok"), ("second", "ok")]
    manifests = [json.loads((tmp_path / "out" / s / "manifest.json").read_text()) for s in ("first", "second")]
    assert [m["options"]["level"] for m in manifests] == [0.0, 0.2]
    vertices, _, _ = crestline.read_mesh(tmp_path / "out" / "first" / "surface.ply")
    assert len(vertices) == rows[0]["points"] > 100
    with pytest.raises(ValueError, match="task: expected one of"):
        cohort.run(table, tmp_path / "out", task="everything", client=client)
    missing_level = cohort.run(paths[:1], tmp_path / "out2", task="crest_lines", client=client, progress=False)
    assert missing_level[0]["status"] == "error" and "level" in missing_level[0]["error"]


def test_transfer_writes_the_long_table_of_every_subject(client, tmp_path):
    # Three small subjects: the small bunny moved by three rigid motions; the
    # template's landmarks are points of its lines.
    from test_same_as_cli import rotation, write_obj

    bunny = Path(__file__).resolve().parents[3] / "meshes" / "bunny_small.obj"
    vertices, faces, _ = crestline.read_mesh(bunny)
    lines = crestline.ridges(vertices, faces, threshold=crestline.defaults()["transfer"]["mesh_threshold"])
    crests = np.vstack([line.points for line in lines])
    chosen = crests[:: len(crests) // 12]
    labels = [f"L{n:02d}" for n in range(len(chosen))]
    marks = tmp_path / "template.csv"
    marks.write_text("label,x,y,z,space\n" + "".join(f"{l},{x:.17g},{y:.17g},{z:.17g},LPS\n" for l, (x, y, z) in
                                                    zip(labels, chosen)))
    paths, motions = [], []
    for s in range(3):
        turn, shift = rotation((0.02 * s, -0.03, 0.01 * s)), np.array([0.2 * s, -0.1, 0.3])
        path = tmp_path / f"sub-{s}.obj"
        write_obj(path, vertices @ turn.T + shift, faces)
        paths.append(path)
        motions.append((turn, shift))
    options = {"template": str(bunny), "landmarks": str(marks), "scales": "3,2,1"}
    rows = cohort.run(paths, tmp_path / "out", task="transfer", options=options, client=client, progress=False)
    assert [row["status"] for row in rows] == ["ok"] * 3, rows
    assert (tmp_path / "out" / "template.lines.json").exists()
    with open(tmp_path / "out" / "transferred.csv", newline="") as f:
        table = list(csv.DictReader(f))
    assert list(table[0]) == ["subject", "label", "x", "y", "z", "confidence", "flagged"]
    assert {r["flagged"] for r in table} == {"false"}
    assert [r["subject"] for r in table] == [f"sub-{s}" for s in range(3) for _ in labels]
    assert [r["label"] for r in table] == labels * 3
    lps = np.array([-1.0, -1.0, 1.0])
    for s, (turn, shift) in enumerate(motions):
        found = np.array([[float(r[c]) for c in "xyz"] for r in table if r["subject"] == f"sub-{s}"])
        # The same as one call, and where the motion takes the landmarks.
        one = crestline.transfer(bunny, marks, paths[s], scales=[3, 2, 1])
        assert np.abs(found - one["positions"]).max() < 1e-9
        assert np.median(np.linalg.norm(found * lps - (chosen @ turn.T + shift), axis=1)) < 1e-3
        assert (tmp_path / "out" / f"sub-{s}" / "landmarks.mrk.json").exists()
    # A rerun reuses every subject.
    again = cohort.run(paths, tmp_path / "out", task="transfer", options=options, client=client, progress=False)
    assert all(row["reused"] for row in again)

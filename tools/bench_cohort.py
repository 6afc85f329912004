#!/usr/bin/env python3
"""Time a cohort run: the landmarks of N generated 128³ images, as a plain loop of
the same tasks in this process and through crestline.cohort on a LocalCluster of 1
and of 2 worker processes (the cores shared out among them).

    python3 tools/bench_cohort.py [--count 24] [--size 128] [--rounds 1]

Needs the package with its cohort extra (pip install "./crates/crestline-py[cohort]")
and nibabel. Prints seconds per configuration, the speed-up of 2 workers over 1, and
the per-task overhead of the cohort layer (1 worker against the plain loop, divided
by the number of scans). Each cohort run writes into a fresh folder, so nothing is
reused; the cluster's start-up is included, as a user pays it.
"""

import argparse
import statistics
import tempfile
import time
from pathlib import Path

import nibabel as nib
import numpy as np

import crestline.cohort as cohort


def write_images(folder: Path, count: int, n: int) -> list:
    """``count`` n³ images of a wavy ellipsoid, each a little different."""
    ax = np.linspace(-1.0, 1.0, n)
    i, j, k = np.meshgrid(ax, ax, ax, indexing="ij")
    paths = []
    for s in range(count):
        a, b, c = 0.8 + 0.01 * s, 0.6 - 0.005 * s, 0.45
        wave = 0.03 * np.sin(7 * i + s) * np.cos(5 * j)
        data = (1 - np.sqrt((i / a) ** 2 + (j / b) ** 2 + (k / c) ** 2) + wave).astype(np.float32)
        path = folder / f"sub-{s:03d}.nii.gz"
        nib.save(nib.Nifti1Image(data, np.diag([2 / n, 2 / n, 2 / n, 1.0])), path)
        paths.append(path)
    return paths


def plain_loop(paths: list, level: float, out: Path) -> float:
    """The same work as a cohort task, each in turn in this process: reading,
    checksum, crest lines, landmarks, writing the outputs and the manifest."""
    started = time.perf_counter()
    for path in paths:
        row = cohort.run_subject(cohort.subject_of(path), str(path), "landmarks", {"level": level}, str(out))
        assert row["status"] == "ok", row["error"]
    return time.perf_counter() - started


def cohort_run(paths: list, level: float, workers: int, out: Path) -> float:
    from dask.distributed import Client, LocalCluster

    started = time.perf_counter()
    with LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=None,
                      env=cohort.worker_environment(workers)) as cluster:
        with Client(cluster) as client:
            rows = cohort.run(paths, out, task="landmarks", options={"level": level}, client=client,
                              progress=False)
    assert all(row["status"] == "ok" for row in rows), [row["error"] for row in rows if row["error"]]
    return time.perf_counter() - started


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--count", type=int, default=24)
    parser.add_argument("--size", type=int, default=128)
    parser.add_argument("--rounds", type=int, default=1)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        paths = write_images(folder, args.count, args.size)
        times = {"plain loop": [], "cohort, 1 worker": [], "cohort, 2 workers": []}
        for r in range(args.rounds):
            times["plain loop"].append(plain_loop(paths, 0.0, folder / f"loop-{r}"))
            times["cohort, 1 worker"].append(cohort_run(paths, 0.0, 1, folder / f"out1-{r}"))
            times["cohort, 2 workers"].append(cohort_run(paths, 0.0, 2, folder / f"out2-{r}"))
    median = {name: statistics.median(t) for name, t in times.items()}
    print(f"{args.count} images of {args.size}³, landmarks (crest lines at level 0), median of {args.rounds}:")
    for name, seconds in median.items():
        print(f"  {name:<18} {seconds:7.2f} s  ({seconds / args.count:.3f} s per image)")
    print(f"  speed-up of 2 workers over 1: {median['cohort, 1 worker'] / median['cohort, 2 workers']:.2f}×")
    overhead = (median["cohort, 1 worker"] - median["plain loop"]) / args.count
    print(f"  cohort overhead per task (1 worker against the loop, start-up included): {overhead:.3f} s")


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""What calling crestline's curvature from Python costs over calling it from Rust.

    python3 tools/bench_python_overhead.py [--mesh FILE] [--rounds N]

Requirements: numpy and the crestline package
(``python3 -m pip install ./crates/crestline-py``), and cargo.

Reads ``--mesh`` (default ``data/dragon/dragon_vrip.ply``, 437,645 vertices, fetched
by ``tools/fetch_dragon.sh``) with ``crestline.read_mesh``, which repairs it, and
writes the repaired arrays to ``tools/out/bench_curvature_mesh.ply`` (binary, double
coordinates, so that Rust reads exactly the same numbers). It starts the Rust example
``bench_curvature`` (``cargo run --release -p crestline --example bench_curvature --
tools/out/bench_curvature_mesh.ply``), which reads that file once into a triangle soup
and answers each estimator name sent to its standard input with the time of one
``Mesh::from_soup`` + ``estimate_curvature`` on a fresh copy of the soup: the library
calls that ``crestline.curvature`` makes.

In this process it times ``crestline.curvature(vertices, faces, estimator)`` with
``time.perf_counter()``: the package's argument checks, the conversion of the numpy
arrays to a soup, the same two library calls, the check that the mesh kept every
vertex in place, and the copies of the result into numpy arrays. The difference is
what the Python binding costs.

After one untimed warm-up call on each side and for each estimator, the two are
timed in interleaved rounds (Python, Rust, Python, Rust, ... for ``shape-operator``
then ``jet-fit`` in each round), so that other work on the machine slows both alike.
Both use all cores (rayon), unless ``RAYON_NUM_THREADS`` in the environment says
otherwise; the Rust process inherits it. The table gives the median and the minimum
of the rounds, the Rust median split into construction and estimate, and the ratio of
the medians, Python / Rust (the acceptance target is at most 1.10 on a mesh of 250k
vertices or more), and the ratio of the minima, which other load on the machine
disturbs less.
"""

import argparse
import json
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

import crestline

REPO = Path(__file__).resolve().parent.parent
DEFAULT_MESH = REPO / "data" / "dragon" / "dragon_vrip.ply"
SOUP_FILE = REPO / "tools" / "out" / "bench_curvature_mesh.ply"
ESTIMATORS = ("shape-operator", "jet-fit")
TARGET = 1.10


def write_ply(path, vertices, faces):
    """Binary little-endian PLY with double coordinates and int32 triangles."""
    path.parent.mkdir(parents=True, exist_ok=True)
    header = (
        "ply\nformat binary_little_endian 1.0\n"
        f"element vertex {len(vertices)}\n"
        "property double x\nproperty double y\nproperty double z\n"
        f"element face {len(faces)}\n"
        "property list uchar int vertex_indices\nend_header\n"
    )
    records = np.empty(len(faces), dtype=[("count", "u1"), ("indices", "<i4", (3,))])
    records["count"] = 3
    records["indices"] = faces
    with open(path, "wb") as f:
        f.write(header.encode("ascii"))
        f.write(np.ascontiguousarray(vertices, dtype="<f8").tobytes())
        f.write(records.tobytes())


class RustBench:
    """The ``bench_curvature`` example, timing one run per estimator name sent."""

    def __init__(self, mesh):
        command = ["cargo", "run", "--quiet", "--release", "-p", "crestline",
                   "--example", "bench_curvature", "--", str(mesh)]
        self.process = subprocess.Popen(command, cwd=REPO, stdin=subprocess.PIPE,
                                        stdout=subprocess.PIPE, text=True)

    def time(self, estimator):
        self.process.stdin.write(estimator + "\n")
        self.process.stdin.flush()
        line = self.process.stdout.readline()
        if not line:
            sys.exit(f"bench_curvature stopped (exit status {self.process.wait()})")
        return json.loads(line)

    def close(self):
        self.process.stdin.close()
        if self.process.wait() != 0:
            sys.exit(f"bench_curvature failed with exit status {self.process.returncode}")


def time_python(vertices, faces, estimator):
    """Seconds of one ``crestline.curvature`` call (its result is freed untimed)."""
    start = time.perf_counter()
    field = crestline.curvature(vertices, faces, estimator=estimator)
    seconds = time.perf_counter() - start
    del field
    return seconds


def print_table(headers, rows):
    widths = [max(len(str(row[i])) for row in [headers] + rows) for i in range(len(headers))]
    for cells in [headers, ["-" * w for w in widths]] + rows:
        print("  ".join(str(c).ljust(w) if i == 0 else str(c).rjust(w)
                        for i, (c, w) in enumerate(zip(cells, widths))))


def parse_arguments():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--mesh", type=Path, default=DEFAULT_MESH,
                        help="mesh file (default data/dragon/dragon_vrip.ply)")
    parser.add_argument("--rounds", type=int, default=7,
                        help="timed rounds per estimator and side (default 7, at least 5)")
    arguments = parser.parse_args()
    if arguments.rounds < 5:
        parser.error("--rounds: at least 5")
    if not arguments.mesh.exists():
        parser.error(f"--mesh: {arguments.mesh} is missing (tools/fetch_dragon.sh fetches "
                     "the dragon)")
    return arguments


def main():
    arguments = parse_arguments()
    vertices, faces, repairs = crestline.read_mesh(arguments.mesh)
    write_ply(SOUP_FILE, vertices, faces)
    made = {name: count for name, count in repairs.items() if count}
    print(f"mesh: {arguments.mesh.name}, {len(vertices)} vertices, {len(faces)} faces "
          f"after crestline.read_mesh (repairs: {made or 'none'})")
    threads = os.environ.get("RAYON_NUM_THREADS", f"all {os.cpu_count()} cores")
    print(f"threads: {threads}; rounds: {arguments.rounds}; soup file: "
          f"{SOUP_FILE.relative_to(REPO)}\n")

    rust = RustBench(SOUP_FILE)
    python_seconds = {e: [] for e in ESTIMATORS}
    rust_runs = {e: [] for e in ESTIMATORS}
    for estimator in ESTIMATORS:
        time_python(vertices, faces, estimator)
        warm_up = rust.time(estimator)
        if (warm_up["vertices"], warm_up["faces"]) != (len(vertices), len(faces)):
            sys.exit(f"bench_curvature read {warm_up['vertices']} vertices and "
                     f"{warm_up['faces']} faces, not {len(vertices)} and {len(faces)}")
    for _ in range(arguments.rounds):
        for estimator in ESTIMATORS:
            python_seconds[estimator].append(time_python(vertices, faces, estimator))
            rust_runs[estimator].append(rust.time(estimator))
    rust.close()

    rows = []
    for estimator in ESTIMATORS:
        py = python_seconds[estimator]
        rs = [run["seconds"] for run in rust_runs[estimator]]
        build = statistics.median(run["build"] for run in rust_runs[estimator])
        estimate = statistics.median(run["estimate"] for run in rust_runs[estimator])
        ratio = statistics.median(py) / statistics.median(rs)
        rows.append([estimator, f"{statistics.median(py):.4f}", f"{min(py):.4f}",
                     f"{statistics.median(rs):.4f}", f"{min(rs):.4f}",
                     f"{build:.4f} + {estimate:.4f}",
                     f"{statistics.median(py) - statistics.median(rs):+.4f}",
                     f"{ratio:.3f}", "yes" if ratio <= TARGET else "NO",
                     f"{min(py) / min(rs):.3f}"])
    print_table(["estimator", "Python median s", "min", "Rust median s", "min",
                 "Rust build + estimate", "difference", "Python / Rust",
                 f"<= {TARGET:.2f}", "ratio of minima"], rows)


if __name__ == "__main__":
    main()

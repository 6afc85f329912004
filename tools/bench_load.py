#!/usr/bin/env python3
"""Compare crestline's read + build with pymeshlab's load of the same files.

Builds the ``bench_load`` example in release mode and runs it once: it generates
``torus.ply`` (binary) and ``torus.obj`` in the data directory if they are missing
and prints crestline's read, build and read + build times, repeated in one process.
Then, for each file, it measures:

* pymeshlab ``MeshSet().load_new_mesh(path)`` repeated inside this process (warm:
  after earlier loads in the same process);
* whole processes: ``bench_load --once FILE`` (with all threads and with one), a
  Python process that imports pymeshlab and loads the file, and a Python process
  that only imports pymeshlab (the baseline to subtract from the previous one).
  The first two also print the time of the load itself, measured inside the fresh
  process (cold: all memory is new to the process).

Every measurement is repeated round by round (one of each kind per round), so that
noise from other work on the machine hits all of them alike.

Wall time of a process is measured here around the child; its peak resident memory
is the maximum RSS that GNU time (``/usr/bin/time -f %M``) reports for that one
command. ``ru_maxrss`` of this script's own children is not used: Linux carries the
RSS of the process that spawned a child into the child's maximum, so a child spawned
from this (large) Python process would report at least this process's size.

Usage: python3 tools/bench_load.py [--out DIR] [--triangles N] [--repetitions R]
"""

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import pymeshlab

REPO = Path(__file__).resolve().parent.parent
EXAMPLE = REPO / "target" / "release" / "examples" / "bench_load"
GNU_TIME = Path("/usr/bin/time")
FILES = ("torus.ply", "torus.obj")

IMPORT_ONLY = "import pymeshlab"
# Prints the seconds of the load and the number of faces loaded.
IMPORT_AND_LOAD = """
import sys, time, pymeshlab
mesh_set = pymeshlab.MeshSet()
start = time.perf_counter()
mesh_set.load_new_mesh(sys.argv[1])
print(time.perf_counter() - start, mesh_set.current_mesh().face_number())
"""


def parse_args():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", type=Path, default=REPO / "bench-data",
                        help="directory of the benchmark meshes (default: bench-data/)")
    parser.add_argument("--triangles", type=int, default=1_200_000,
                        help="triangles of a generated mesh (default: 1200000)")
    parser.add_argument("--repetitions", type=int, default=5,
                        help="repetitions of every measurement (default: 5)")
    return parser.parse_args()


def run_process(command, env=None):
    """Run ``command`` under GNU time; return (wall seconds, peak MiB, stdout)."""
    with tempfile.NamedTemporaryFile("r", suffix=".time") as report:
        start = time.perf_counter()
        result = subprocess.run(
            [str(GNU_TIME), "-f", "%M", "-o", report.name, *command],
            env=env, capture_output=True, text=True)
        wall = time.perf_counter() - start
        if result.returncode != 0:
            sys.exit(f"error: {' '.join(command)} failed:\n{result.stderr}")
        peak_kib = int(report.read().split()[-1])
    return wall, peak_kib / 1024, result.stdout


def crestline_load(stdout):
    """Read + build seconds and triangles from the line ``bench_load --once`` prints."""
    figures = dict(item.split("=", 1) for item in stdout.split())
    return float(figures["read_build_s"]), int(figures["triangles"])


def pymeshlab_load(stdout):
    """Load seconds and faces from the line ``IMPORT_AND_LOAD`` prints."""
    seconds, faces = stdout.split()
    return float(seconds), int(faces)


def warm_pymeshlab_load(path):
    """Seconds of one ``load_new_mesh`` call in this process and the faces loaded."""
    mesh_set = pymeshlab.MeshSet()
    start = time.perf_counter()
    mesh_set.load_new_mesh(str(path))
    seconds = time.perf_counter() - start
    return seconds, mesh_set.current_mesh().face_number()


def measure(path, repetitions):
    """All measurements of one file, run round-robin.

    Returns {kind: {"wall": [...], "peak": [...], "load": [...], "triangles": n}}:
    "wall" and "peak" are the wall seconds and peak MiB of each process run, "load"
    the load (or read + build) time measured by the tool itself and "triangles" the
    count it loaded.
    """
    one_thread = dict(os.environ, RAYON_NUM_THREADS="1")
    processes = {
        "crestline": ([str(EXAMPLE), "--once", str(path)], None, crestline_load),
        "crestline 1 thread": ([str(EXAMPLE), "--once", str(path)], one_thread,
                               crestline_load),
        "pymeshlab": ([sys.executable, "-c", IMPORT_AND_LOAD, str(path)], None,
                      pymeshlab_load),
        "import only": ([sys.executable, "-c", IMPORT_ONLY], None, None),
    }
    results = {kind: {"wall": [], "peak": [], "load": [], "triangles": None}
               for kind in ["pymeshlab warm", *processes]}
    for _ in range(repetitions):
        seconds, faces = warm_pymeshlab_load(path)
        results["pymeshlab warm"]["load"].append(seconds)
        results["pymeshlab warm"]["triangles"] = faces
        for kind, (command, env, parse_output) in processes.items():
            wall, peak, stdout = run_process(command, env)
            entry = results[kind]
            entry["wall"].append(wall)
            entry["peak"].append(peak)
            if parse_output:
                seconds, entry["triangles"] = parse_output(stdout)
                entry["load"].append(seconds)
    return results


class Table:
    """Rows of the final table, printed with aligned columns."""

    HEADER = ("file", "measurement", "triangles", "min s", "median s", "s/Mt",
              "peak MiB", "MiB/Mt", "time ratio", "peak ratio")

    def __init__(self):
        self.rows = []

    def add(self, file, measurement, triangles, seconds, peak=None, reference=None):
        """Add a row; ``triangles`` is None for a row that loads no mesh,
        ``seconds`` a list of samples, ``peak`` the peak MiB, and ``reference`` the
        (median seconds, peak MiB) of the pymeshlab row that the ratios compare
        against. Returns the row's (median seconds, peak MiB)."""
        median = statistics.median(seconds)

        def per_million(value, digits):
            return "-" if triangles is None else f"{value * 1e6 / triangles:.{digits}f}"

        cells = [file, measurement, str(triangles or "-"), f"{min(seconds):.3f}",
                 f"{median:.3f}", per_million(median, 3)]
        cells += [f"{peak:.0f}", per_million(peak, 0)] if peak is not None else ["-", "-"]
        if reference is None:
            cells += ["-", "-"]
        else:
            ref_seconds, ref_peak = reference
            cells.append(f"{median / ref_seconds:.2f}")
            cells.append(f"{peak / ref_peak:.2f}" if peak is not None and ref_peak else "-")
        self.rows.append(cells)
        return median, peak

    def print(self):
        rows = [self.HEADER, *self.rows]
        widths = [max(len(row[i]) for row in rows) for i in range(len(self.HEADER))]
        for row in rows:
            print("  ".join(cell.ljust(w) if i < 2 else cell.rjust(w)
                            for i, (cell, w) in enumerate(zip(row, widths))))


def add_rows(table, name, results):
    """The table rows of one file."""
    warm = results["pymeshlab warm"]
    crestline, crestline_1t = results["crestline"], results["crestline 1 thread"]
    pymesh, baseline = results["pymeshlab"], results["import only"]
    faces = pymesh["triangles"]

    table.add(name, "pymeshlab load, in-process, warm", warm["triangles"], warm["load"])
    cold = table.add(name, "pymeshlab load, in-process, cold", faces, pymesh["load"])
    table.add(name, "crestline read+build, in-process, cold", crestline["triangles"],
              crestline["load"], reference=cold)
    table.add(name, "crestline read+build, 1 thread, cold", crestline_1t["triangles"],
              crestline_1t["load"], reference=cold)
    table.add(name, "python + import pymeshlab, process", None, baseline["wall"],
              max(baseline["peak"]))
    process = table.add(name, "python + import + load, process", faces, pymesh["wall"],
                        max(pymesh["peak"]))
    load_only = [w - b for w, b in zip(pymesh["wall"], baseline["wall"])]
    table.add(name, "pymeshlab load (process - import)", faces, load_only,
              max(pymesh["peak"]) - max(baseline["peak"]))
    table.add(name, "crestline --once, process", crestline["triangles"], crestline["wall"],
              max(crestline["peak"]), reference=process)


def main():
    args = parse_args()
    if not GNU_TIME.exists():
        sys.exit("error: GNU time (/usr/bin/time) is needed to measure peak memory "
                 "(Debian/Ubuntu: apt-get install time)")
    subprocess.run(["cargo", "build", "--release", "--example", "bench_load"],
                   cwd=REPO, check=True)
    print("\n== crestline stages, repeated in one process (warm) ==", flush=True)
    subprocess.run([str(EXAMPLE), "--out", str(args.out), "--triangles", str(args.triangles),
                    "--repetitions", str(args.repetitions)], check=True)

    load_before = os.getloadavg()[0]
    table = Table()
    for name in FILES:
        path = args.out / name
        print(f"measuring {path} ...", flush=True)
        add_rows(table, name, measure(path, args.repetitions))

    print(f"\n== {args.repetitions} rounds; {os.cpu_count()} CPUs; 1-minute load average "
          f"{load_before:.1f} before, {os.getloadavg()[0]:.1f} after ==")
    table.print()
    print("s/Mt and MiB/Mt are per million triangles; peak MiB is the largest maximum RSS "
          "over the runs.\n"
          "warm: repeated in one process; cold: the first load of a fresh process. "
          "Compare the warm row with\nthe read+build rows of the stage table above.\n"
          "Ratios are crestline / pymeshlab: in-process rows against pymeshlab's cold "
          "in-process load,\nthe process row against the whole pymeshlab process "
          "(python + import + load).")


if __name__ == "__main__":
    main()

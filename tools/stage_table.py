#!/usr/bin/env python3
"""Stage table: what crestline's commands cost against `crestline info`, in time and memory.

Runs each command on each mesh (or 3D image) in interleaved rounds (round by round,
mesh by mesh, command by command, so that other work on the machine slows all of
them alike) and prints two Markdown tables:

1. per mesh and command: the median wall time (and the minimum, with more than one
   round), its ratio to `info` on the same file in the same run (the cost of reading
   and repairing the mesh), the peak resident memory of the command's process
   (`ru_maxrss` from `os.wait4`, the largest of the rounds, in GB = 10^9 bytes) and
   its ratio to `info`'s peak;
2. the median seconds of every stage in the `--report` JSON files, one column per
   mesh (stages of the same name in one report are added up).

    python3 tools/stage_table.py MESH... [--rounds N] [--commands info,ridges,morse]
                                 [--args "--estimator shape-operator"] [--threads N]

`--args` go to every command but `info` (which takes none of the extraction
options), e.g. `--args "--level 90"` for images. Build first: `cargo build
--release`. The dragon scans come from tools/fetch_dragon.sh, their refinements
from tools/refine_mesh.py. Standard library only; Python 3.9 or later.
"""

import argparse
import json
import os
import shlex
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

BINARY = Path(__file__).resolve().parent.parent / "target" / "release" / "crestline"

# Output file extension of the commands whose output is not a JSON file.
OUTPUT_SUFFIX = {"curvature": ".ply", "iso": ".ply", "crease": ".ply", "draw": ".svg"}


def peak_gb(rusage):
    """ru_maxrss in GB: kibibytes on Linux, bytes on macOS."""
    scale = 1 if sys.platform == "darwin" else 1024
    return rusage.ru_maxrss * scale / 1e9


def run(args, log):
    """Run one command; its wall time in seconds and peak resident memory in GB."""
    with open(log, "wb") as stderr:
        start = time.perf_counter()
        process = subprocess.Popen(args, stdout=subprocess.DEVNULL, stderr=stderr)
        _, status, rusage = os.wait4(process.pid, 0)
        seconds = time.perf_counter() - start
    process.returncode = os.waitstatus_to_exitcode(status)
    if process.returncode != 0:
        message = Path(log).read_text(errors="replace").strip().splitlines()[-20:]
        sys.exit(f"failed (exit {process.returncode}): {shlex.join(args)}\n" + "\n".join(message))
    return seconds, peak_gb(rusage)


def stage_seconds(report):
    """Seconds per stage name of one --report file, in order, same names added up."""
    stages = {}
    for stage in json.loads(Path(report).read_text())["stages"]:
        stages[stage["name"]] = stages.get(stage["name"], 0.0) + stage["seconds"]
    return stages


def size_of(report):
    """The size of the input from `info`'s report: faces of a mesh, voxels of an image."""
    counts = json.loads(Path(report).read_text()).get("counts", {})
    for key, unit in (("faces", "faces"), ("voxels", "voxels")):
        if key in counts:
            return f"{counts[key]:,} {unit}"
    return ""


def seconds_text(seconds):
    return f"{seconds:.3f}" if seconds < 0.1 else f"{seconds:.2f}"


def gb_text(gb):
    return f"{gb:.3f}" if gb < 1 else f"{gb:.2f}"


def markdown(header, rows, right):
    """A Markdown table; the columns whose index is in `right` are right-aligned."""
    widths = [max(len(str(row[i])) for row in [header] + rows) for i in range(len(header))]
    align = ["-" * (w - 1) + ":" if i in right else "-" * w for i, w in enumerate(widths)]

    def line(cells):
        return "| " + " | ".join(
            str(c).rjust(w) if i in right else str(c).ljust(w)
            for i, (c, w) in enumerate(zip(cells, widths))) + " |"

    return "\n".join([line(header), line(align)] + [line(row) for row in rows])


def parse_arguments():
    parser = argparse.ArgumentParser(
        description="Wall time, peak memory and stage times of crestline commands "
                    "against `crestline info`, as Markdown tables.")
    parser.add_argument("inputs", nargs="+", metavar="MESH",
                        help="meshes or 3D images (a last bare number is read as --rounds, "
                             "the old usage)")
    parser.add_argument("--rounds", type=int, default=None,
                        help="interleaved rounds; the table shows medians (default 3)")
    parser.add_argument("--commands", default="info,ridges,morse",
                        help="comma-separated crestline commands (default info,ridges,morse); "
                             "info is added first when missing")
    parser.add_argument("--args", default="", dest="extra",
                        help="extra arguments for every command but info, one string")
    parser.add_argument("--threads", type=int, default=None,
                        help="pass --threads N to every command (default: crestline's, all cores)")
    parser.add_argument("--binary", default=str(BINARY),
                        help="the crestline executable (default target/release/crestline)")
    # `--args "--kind ridges"` would read as an option: glue the value on (--args=...).
    argv, rest = [], sys.argv[1:]
    while rest:
        word = rest.pop(0)
        argv.append(f"--args={rest.pop(0)}" if word == "--args" and rest else word)
    args = parser.parse_args(argv)
    # The old usage: stage_table.py MESH [ROUNDS].
    if (len(args.inputs) > 1 and args.inputs[-1].isdigit()
            and not Path(args.inputs[-1]).exists() and args.rounds is None):
        args.rounds = int(args.inputs.pop())
    if args.rounds is None:
        args.rounds = 3
    if args.rounds < 1:
        parser.error("--rounds must be at least 1")
    args.commands = [c.strip() for c in args.commands.split(",") if c.strip()]
    if "register" in args.commands:
        parser.error("register takes two inputs; it is not supported here")
    if "info" not in args.commands:
        args.commands.insert(0, "info")
    if len(set(args.commands)) != len(args.commands):
        parser.error("a command is listed twice")
    for path in args.inputs:
        if not Path(path).is_file():
            parser.error(f"no such file: {path}")
    if not Path(args.binary).is_file():
        parser.error(f"{args.binary} is missing: build it first with `cargo build --release`")
    return args


def main():
    args = parse_arguments()
    extra = shlex.split(args.extra)
    prefix = [args.binary] + (["--threads", str(args.threads)] if args.threads is not None else [])
    times, peaks, stages, sizes = {}, {}, {}, {}
    with tempfile.TemporaryDirectory(prefix="stage_table-") as out:
        out = Path(out)
        for round_number in range(args.rounds):
            for index, path in enumerate(args.inputs):
                for command in args.commands:
                    report = out / f"{index}-{command}-report.json"
                    call = prefix + [command, path, "--report", str(report)]
                    if command != "info":
                        output = out / f"{index}-{command}{OUTPUT_SUFFIX.get(command, '.json')}"
                        call += ["-o", str(output)] + extra
                    print(f"round {round_number + 1}/{args.rounds}: {command} {path}",
                          file=sys.stderr, flush=True)
                    seconds, peak = run(call, out / "stderr.txt")
                    key = (path, command)
                    times.setdefault(key, []).append(seconds)
                    peaks.setdefault(key, []).append(peak)
                    for name, value in stage_seconds(report).items():
                        stages.setdefault(command, {}).setdefault(name, {}) \
                            .setdefault(path, []).append(value)
                    if command == "info" and path not in sizes:
                        sizes[path] = size_of(report)

    rounds = args.rounds
    header = ["mesh", "size", "command", "median s"] + (["min s"] if rounds > 1 else []) \
        + ["× info", "peak GB", "× info"]
    rows = []
    for path in args.inputs:
        info_time = statistics.median(times[(path, "info")])
        info_peak = max(peaks[(path, "info")])
        for number, command in enumerate(args.commands):
            median = statistics.median(times[(path, command)])
            peak = max(peaks[(path, command)])
            row = [path if number == 0 else "", sizes[path] if number == 0 else "", command,
                   seconds_text(median)]
            if rounds > 1:
                row.append(seconds_text(min(times[(path, command)])))
            row += [f"{median / info_time:.1f}", gb_text(peak), f"{peak / info_peak:.1f}"]
            rows.append(row)
    numeric = set(range(3, len(header)))

    print(f"crestline {', '.join(args.commands)}: median wall time of {rounds} interleaved "
          f"round{'s' if rounds > 1 else ''}; peak resident memory (largest of the rounds)"
          + (f"; arguments `{args.extra}`" if extra else "")
          + (f"; --threads {args.threads}" if args.threads is not None else "")
          + f"; {os.cpu_count()} cores")
    print()
    print(markdown(header, rows, numeric))
    print()

    names = {path: Path(path).name for path in args.inputs}
    if len(set(names.values())) != len(names):
        names = {path: path for path in args.inputs}
    header = ["stage (median s)"] + [names[path] for path in args.inputs]
    rows = []
    for command in args.commands:
        for name, per_path in stages.get(command, {}).items():
            rows.append([f"{command}: {name}"] + [
                seconds_text(statistics.median(per_path[path])) if path in per_path else "–"
                for path in args.inputs])
    print(markdown(header, rows, set(range(1, len(header)))))


if __name__ == "__main__":
    main()

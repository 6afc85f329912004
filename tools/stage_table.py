#!/usr/bin/env python3
"""Stage table of `crestline ridges` and `crestline morse` against `crestline info`.

Runs the three commands on one mesh, interleaved, ROUNDS times (default 3), and
prints the median wall time of each command (and its minimum), its ratio to
`info` (the cost of loading the mesh), and the median of every stage from the
`--report` files.

    python3 tools/stage_table.py data/dragon/dragon_vrip.ply [ROUNDS]

Build first: `cargo build --release`. The scans come from tools/fetch_dragon.sh.
"""

import json
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

BINARY = Path(__file__).resolve().parent.parent / "target" / "release" / "crestline"


def timed(args):
    start = time.perf_counter()
    subprocess.run(args, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=True)
    return time.perf_counter() - start


def main():
    mesh = sys.argv[1]
    rounds = int(sys.argv[2]) if len(sys.argv) > 2 else 3
    times, stages = {}, {}
    with tempfile.TemporaryDirectory() as out:
        for _ in range(rounds):
            for command in ["info", "ridges", "morse"]:
                args = [str(BINARY), command, mesh]
                report = Path(out) / f"{command}-report.json"
                if command != "info":
                    args += ["-o", str(Path(out) / f"{command}.json"), "--report", str(report)]
                times.setdefault(command, []).append(timed(args))
                if command == "info":
                    continue
                for stage in json.loads(report.read_text())["stages"]:
                    key = (command, stage["name"])
                    stages.setdefault(key, []).append(stage["seconds"])
    median = {command: statistics.median(t) for command, t in times.items()}
    info = median["info"]
    print(f"{mesh}: median (minimum) of {rounds} interleaved rounds")
    print(f"info {info:.2f} s ({min(times['info']):.2f} s)")
    for command in ["ridges", "morse"]:
        ratio = median[command] / info
        print(f"{command} {median[command]:.2f} s ({min(times[command]):.2f} s), {ratio:.1f}x info")
        for (owner, name), seconds in stages.items():
            if owner == command:
                print(f"  {name:<24} {statistics.median(seconds):.3f} s")


if __name__ == "__main__":
    main()

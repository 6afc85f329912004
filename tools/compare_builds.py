#!/usr/bin/env python3
"""Do two builds of the tool write the same files? Run every command with its
defaults on the bundled meshes and the MNI template with both, and compare the
outputs byte for byte: the check for a change that should not change results
(a refactoring, a dependency update).

    python3 tools/compare_builds.py OLD_CRESTLINE NEW_CRESTLINE [--quick]

OLD_CRESTLINE is e.g. a build of the main branch
(`git worktree add /tmp/base main && cargo build --release --manifest-path
/tmp/base/Cargo.toml`), NEW_CRESTLINE `target/release/crestline`. Prints one
line per run (`same`, or the outputs that differ) and exits 1 if any differs.
Stage timings are left out of the comparison (`--report` is not asked for).
`--quick` leaves out the larger runs (the template's crest lines, landmarks,
crease surface and drawings of the image).
"""

import argparse
import filecmp
import os
import subprocess
import sys
import tempfile

MESHES = [
    "meshes/bunny.obj",
    "meshes/bunny_small.obj",
    "meshes/cow.obj",
    "meshes/airplane.obj",
    "meshes/bone.ply",
    "meshes/fsaverage5_pial_left.obj",
]
IMAGE = "volumes/mni152_t1_1mm.nii.gz"
LEVEL = "60"

# Per command: the arguments before the output, and the output's name.
MESH_RUNS = [
    ("info", [], None),
    ("curvature", [], "curvature.ply"),
    ("ridges", [], "ridges.json"),
    ("ridges", [], "ridges.vtk"),
    ("ridges", [], "ridges.obj"),
    ("morse", [], "morse.json"),
    ("landmarks", [], "landmarks.mrk.json"),
    ("draw", [], "drawing.svg"),
    ("view", [], "view.html"),
]
IMAGE_RUNS = [
    ("info", [], None, False),
    ("iso", ["--level", LEVEL], "iso.ply", False),
    ("ridges", ["--level", LEVEL], "ridges.json", False),
    ("morse", ["--level", LEVEL], "morse.json", False),
    ("crest-lines", ["--level", LEVEL], "crest.json", True),
    ("landmarks", ["--level", LEVEL], "landmarks.json", True),
    ("crease", [], "crease.ply", True),
    ("draw", ["--level", LEVEL, "--lines", "crest"], "drawing.svg", True),
]


def run(tool, command, source, extra, output, folder):
    """Run one command; its standard output and the file it wrote."""
    args = [tool, command, source, *extra]
    path = None
    if output:
        path = os.path.join(folder, output)
        args += ["-o", path]
    done = subprocess.run(args, capture_output=True, text=True)
    if done.returncode != 0:
        sys.exit(f"{' '.join(args)} failed:\n{done.stderr}")
    return done.stdout.replace(folder, "OUT"), path


def compare(old, new, command, source, extra, output):
    """`None` if both builds write the same, else what differs."""
    with tempfile.TemporaryDirectory() as a, tempfile.TemporaryDirectory() as b:
        out_a, file_a = run(old, command, source, extra, output, a)
        out_b, file_b = run(new, command, source, extra, output, b)
        differs = []
        if out_a.replace(a, "OUT") != out_b.replace(b, "OUT"):
            differs.append("standard output")
        if file_a and not filecmp.cmp(file_a, file_b, shallow=False):
            differs.append(output)
        return ", ".join(differs) or None


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("old")
    parser.add_argument("new")
    parser.add_argument("--quick", action="store_true")
    args = parser.parse_args()
    runs = [(c, m, e, o) for m in MESHES for c, e, o in MESH_RUNS]
    runs += [(c, IMAGE, e, o) for c, e, o, large in IMAGE_RUNS if not (large and args.quick)]
    failed = 0
    for command, source, extra, output in runs:
        differs = compare(args.old, args.new, command, source, extra, output)
        label = " ".join([command, source, *extra, *(["-o", output] if output else [])])
        print(f"{label:<60} {'same' if differs is None else 'DIFFERS: ' + differs}", flush=True)
        failed += differs is not None
    print(f"{len(runs) - failed} of {len(runs)} runs the same")
    sys.exit(1 if failed else 0)


if __name__ == "__main__":
    main()

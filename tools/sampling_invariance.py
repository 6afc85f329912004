#!/usr/bin/env python3
"""Do a mesh's ridges and valleys depend on its sampling? Make copies of the same
surface with another triangulation — isotropic remeshing at 0.5×, 1× and 2× the mean
edge length, quadric decimation to 1/2 and 1/4 of the faces (pymeshlab) — each turned
by a random rotation, run `crestline ridges` on the original and on every copy, and
compare them with `crestline compare` (the copy's lines moved back by the rotation's
inverse, given as --transform).

    python3 tools/sampling_invariance.py meshes/bunny.obj [--copies remesh1,decimate2]
        [--args "--scale 0.02"] [--tolerance 0.005]

Prints per copy: the share of the original's ridge (valley) length within the
tolerance (a share of the original mesh's bounding-box diagonal) of the copy's
ridges (valleys), the reverse, and the line counts. Needs pymeshlab and numpy
(tools/requirements.txt) and a release build of the tool.
"""

import argparse
import json
import os
import shlex
import subprocess
import sys
import tempfile

import numpy as np
import pymeshlab

COPIES = {
    "remesh0.5": ("remesh", 0.5),
    "remesh1": ("remesh", 1.0),
    "remesh2": ("remesh", 2.0),
    "decimate2": ("decimate", 2),
    "decimate4": ("decimate", 4),
}


def mean_edge_length(ms):
    geometry = ms.get_geometric_measures()
    return geometry["avg_edge_length"]


def make_copy(source, how, amount, path):
    ms = pymeshlab.MeshSet()
    ms.load_new_mesh(source)
    if how == "remesh":
        length = amount * mean_edge_length(ms)
        ms.meshing_isotropic_explicit_remeshing(
            targetlen=pymeshlab.PureValue(length), iterations=5
        )
    else:
        faces = ms.current_mesh().face_number() // amount
        ms.meshing_decimation_quadric_edge_collapse(
            targetfacenum=faces, preservenormal=True, preservetopology=True
        )
    ms.save_current_mesh(path)


def random_rotation(seed):
    q = np.random.default_rng(seed).normal(size=4)
    w, x, y, z = q / np.linalg.norm(q)
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
        ]
    )


def rotate_obj(path, rotation):
    """Rotate the vertices of an OBJ file in place (about the origin)."""
    with open(path) as f:
        lines = f.readlines()
    out = []
    for line in lines:
        if line.startswith("v "):
            p = rotation @ np.array([float(t) for t in line.split()[1:4]])
            out.append(f"v {p[0]:.9g} {p[1]:.9g} {p[2]:.9g}\n")
        else:
            out.append(line)
    with open(path, "w") as f:
        f.writelines(out)


def write_transform(path, rotation):
    """The copy's lines back into the original's frame: the inverse rotation."""
    matrix = np.eye(4)
    matrix[:3, :3] = rotation.T
    with open(path, "w") as f:
        json.dump({"format": "crestline-transform/1", "matrix": matrix.tolist()}, f)


def run(tool, *args):
    done = subprocess.run([tool, *args], capture_output=True, text=True)
    if done.returncode != 0:
        sys.exit(f"{shlex.join([tool, *args])} failed:\n{done.stderr}")
    return done


def diagonal(path):
    ms = pymeshlab.MeshSet()
    ms.load_new_mesh(path)
    box = ms.current_mesh().bounding_box()
    return box.diagonal()


def compare(tool, a, b, transform, tolerance, folder, name):
    report = os.path.join(folder, f"{name}.report.json")
    run(tool, "compare", a, b, "--transform", transform, "--tolerance", str(tolerance),
        "--report", report)
    with open(report) as f:
        return {row["kind"]: row for row in json.load(f)["comparison"]["lines"]}


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("mesh")
    parser.add_argument("--copies", default=",".join(COPIES))
    parser.add_argument("--args", default="", help="more arguments of `crestline ridges`")
    parser.add_argument("--tolerance", type=float, default=0.005,
                        help="a share of the bounding-box diagonal")
    parser.add_argument("--crestline", default="target/release/crestline")
    parser.add_argument("--seed", type=int, default=1)
    args = parser.parse_args()
    extra = shlex.split(args.args)
    tolerance = args.tolerance * diagonal(args.mesh)
    with tempfile.TemporaryDirectory() as folder:
        original = os.path.join(folder, "original.json")
        run(args.crestline, "ridges", args.mesh, "-o", original, *extra)
        print(f"{args.mesh}: tolerance {tolerance:.4g} ({100 * args.tolerance}% of the diagonal)")
        print(f"{'copy':<12} {'ridges':>8} {'back':>8} {'valleys':>8} {'back':>8}  lines")
        for seed, name in enumerate(args.copies.split(","), start=args.seed):
            how, amount = COPIES[name]
            mesh = os.path.join(folder, f"{name}.obj")
            make_copy(args.mesh, how, amount, mesh)
            rotation = random_rotation(seed)
            rotate_obj(mesh, rotation)
            transform = os.path.join(folder, f"{name}.transform.json")
            write_transform(transform, rotation)
            lines = os.path.join(folder, f"{name}.json")
            run(args.crestline, "ridges", mesh, "-o", lines, *extra)
            rows = compare(args.crestline, original, lines, transform, tolerance, folder, name)
            shares = []
            for kind in ("ridge", "valley"):
                row = rows.get(kind, {"a_in_b": 0, "b_in_a": 0})
                shares += [f"{100 * row['a_in_b']:7.1f}%", f"{100 * row['b_in_a']:7.1f}%"]
            count = lambda side: sum(r[f"{side}_count"] for r in rows.values())
            print(f"{name:<12} {' '.join(shares)}  {count('a')} -> {count('b')}", flush=True)


if __name__ == "__main__":
    main()

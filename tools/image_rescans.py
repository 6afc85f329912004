#!/usr/bin/env python3
"""Do an image's landmarks and crest lines depend on its voxel grid? Make second
scans of the same head — moved rigidly on the same grid, shifted by a fraction of a
voxel, moved with Gaussian noise, rescanned at 0.8 mm and at 1.5 mm — by SimpleITK's
B-spline resampling, run `crestline landmarks` on the original and on every copy,
and compare them with `crestline compare` (the copy's points mapped back by the true
motion, given as --transform, so no registration error enters).

    python3 tools/image_rescans.py volumes/mni152_t1_1mm.nii.gz --level 60
        [--args "--sigma 2"] [--copies moved1,shift,noise,grid0.8,grid1.5]

Prints per copy: the share of the original's extremal points with an extremal point
of the copy within the tolerance (1 mm; 1.5 mm for the 1.5 mm grid), the reverse, the
same for the crest lines' length, and the landmark and line counts. Needs SimpleITK
and numpy, and a release build of the tool.
"""

import argparse
import json
import os
import shlex
import subprocess
import sys
import tempfile

import numpy as np
import SimpleITK as sitk

# name: (rotation in degrees about x, y, z; shift in mm; noise as a share of the
# level; spacing of the new grid in mm, or None for the original's)
COPIES = {
    "moved1": ((4.0, -3.0, 6.0), (2.5, -1.5, 3.0), 0.0, None),
    "moved2": ((-10.0, 5.0, -2.0), (-5.0, 4.0, 1.0), 0.0, None),
    "shift": ((0.0, 0.0, 0.0), (0.5, 0.3, 0.2), 0.0, None),
    "noise": ((4.0, -3.0, 6.0), (2.5, -1.5, 3.0), 0.05, None),
    "grid0.8": ((4.0, -3.0, 6.0), (2.5, -1.5, 3.0), 0.0, 0.8),
    "grid1.5": ((4.0, -3.0, 6.0), (2.5, -1.5, 3.0), 0.0, 1.5),
}

FLIP = np.diag([-1.0, -1.0, 1.0])


def resample_transform(image, degrees, shift):
    """The resampling transform (copy point -> original point, LPS) about the centre."""
    transform = sitk.Euler3DTransform()
    size = np.array(image.GetSize())
    centre = image.TransformContinuousIndexToPhysicalPoint(((size - 1) / 2).tolist())
    transform.SetCenter(centre)
    transform.SetRotation(*np.radians(degrees))
    transform.SetTranslation(shift)
    return transform


def copy_of(image, degrees, shift, noise, spacing, level, seed):
    transform = resample_transform(image, degrees, shift)
    old_spacing = np.array(image.GetSpacing())
    new_spacing = old_spacing if spacing is None else np.full(3, spacing)
    size = np.round(np.array(image.GetSize()) * old_spacing / new_spacing).astype(int)
    copy = sitk.Resample(
        sitk.Cast(image, sitk.sitkFloat32), size.tolist(), transform, sitk.sitkBSpline,
        image.GetOrigin(), new_spacing.tolist(), image.GetDirection(), 0.0, sitk.sitkFloat32,
    )
    if noise > 0:
        values = sitk.GetArrayFromImage(copy)
        values += np.random.default_rng(seed).normal(0.0, noise * level, values.shape)
        noisy = sitk.GetImageFromArray(values.astype(np.float32))
        noisy.CopyInformation(copy)
        copy = noisy
    return copy, transform


def ras_matrix(transform):
    """The copy -> original map in RAS, as a 4x4 matrix."""
    matrix = np.array(transform.GetMatrix()).reshape(3, 3)
    centre = np.array(transform.GetCenter())
    offset = np.array(transform.GetTranslation()) + centre - matrix @ centre
    out = np.eye(4)
    out[:3, :3] = FLIP @ matrix @ FLIP
    out[:3, 3] = FLIP @ offset
    return out


def run(tool, *args):
    done = subprocess.run([tool, *args], capture_output=True, text=True)
    if done.returncode != 0:
        sys.exit(f"{shlex.join([tool, *args])} failed:\n{done.stderr}")


def compare(tool, a, b, transform, tolerance, report):
    run(tool, "compare", a, b, "--transform", transform, "--tolerance", str(tolerance),
        "--report", report)
    with open(report) as f:
        return json.load(f)["comparison"]


def length_shares(rows):
    """The shares of every kind of line together, weighted by length, and the line
    counts."""
    total = lambda side: sum(r[side] for r in rows)
    return {
        "a_in_b": sum(r["a_in_b"] * r["a"] for r in rows) / total("a"),
        "b_in_a": sum(r["b_in_a"] * r["b"] for r in rows) / total("b"),
        "a_count": sum(r["a_count"] for r in rows),
        "b_count": sum(r["b_count"] for r in rows),
    }


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("image")
    parser.add_argument("--level", type=float, required=True)
    parser.add_argument("--copies", default=",".join(COPIES))
    parser.add_argument("--args", default="", help="more arguments of `crestline landmarks`")
    parser.add_argument("--crestline", default="target/release/crestline")
    args = parser.parse_args()
    extra = shlex.split(args.args)
    image = sitk.ReadImage(args.image)
    with tempfile.TemporaryDirectory() as folder:
        original = os.path.join(folder, "original.json")
        run(args.crestline, "landmarks", args.image, "--level", str(args.level), "-o",
            original, *extra)
        print(f"{'copy':<9} {'tol':>4} {'extremal':>9} {'back':>7} {'lines':>7} {'back':>7}"
              "  landmarks      lines")
        for seed, name in enumerate(args.copies.split(","), start=1):
            degrees, shift, noise, spacing = COPIES[name]
            copy, transform = copy_of(image, degrees, shift, noise, spacing, args.level, seed)
            path = os.path.join(folder, f"{name}.nii.gz")
            sitk.WriteImage(copy, path)
            motion = os.path.join(folder, f"{name}.transform.json")
            with open(motion, "w") as f:
                json.dump({"format": "crestline-transform/1",
                           "matrix": ras_matrix(transform).tolist()}, f)
            lines = os.path.join(folder, f"{name}.json")
            run(args.crestline, "landmarks", path, "--level", str(args.level), "-o", lines,
                *extra)
            tolerance = 1.5 if spacing == 1.5 else 1.0
            found = compare(args.crestline, original, lines, motion, tolerance,
                            os.path.join(folder, f"{name}.report.json"))
            point = {r["kind"]: r for r in found["landmarks"]}["extremal"]
            line = length_shares(found["lines"])
            points_total = sum(r["a_count"] for r in found["landmarks"]), sum(
                r["b_count"] for r in found["landmarks"])
            print(f"{name:<9} {tolerance:>4} {100 * point['a_in_b']:8.1f}% "
                  f"{100 * point['b_in_a']:6.1f}% {100 * line['a_in_b']:6.1f}% "
                  f"{100 * line['b_in_a']:6.1f}%  {points_total[0]:>5} -> {points_total[1]:<5}"
                  f" {line['a_count']:>4} -> {line['b_count']}", flush=True)


if __name__ == "__main__":
    main()

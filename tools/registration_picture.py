#!/usr/bin/env python3
"""Crest-line registration of the MNI152 template against a rigidly moved copy.

    python3 tools/registration_picture.py OUT.png [--degrees 10] [--shift 8]

Moves and resamples the template (volumes/mni152_t1_1mm.nii.gz) by a rotation
about a skew axis through the image centre and a translation (scipy, trilinear),
writes the copy as NIfTI in a temporary folder, traces the crest lines of both
with `crestline crest-lines`, registers them with `crestline register`, and
draws the two line sets seen from above, before and after registration. Prints
the true and the recovered motion. Build first: `cargo build --release`.
"""

import argparse
import json
import subprocess
import tempfile
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import nibabel as nib  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.collections import LineCollection  # noqa: E402
from scipy.ndimage import affine_transform  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
BINARY = ROOT / "target" / "release" / "crestline"
TEMPLATE = ROOT / "volumes" / "mni152_t1_1mm.nii.gz"


def rotation(axis, degrees):
    """The rotation matrix about `axis` by `degrees` (Rodrigues)."""
    k = np.asarray(axis, float) / np.linalg.norm(axis)
    a = np.radians(degrees)
    cross = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + np.sin(a) * cross + (1 - np.cos(a)) * cross @ cross


def moved_copy(image, r, t):
    """The image moved by x -> r (x - c) + c + t in world coordinates (c the
    centre of the box), resampled trilinearly on the same grid."""
    affine = image.affine
    data = np.asarray(image.dataobj, dtype=np.float32)
    centre = affine[:3, :3] @ ((np.array(data.shape) - 1) / 2) + affine[:3, 3]
    world = np.eye(4)
    world[:3, :3], world[:3, 3] = r, centre + t - r @ centre
    # For each output voxel, the input voxel it comes from.
    pull = np.linalg.inv(affine) @ np.linalg.inv(world) @ affine
    moved = affine_transform(data, pull[:3, :3], pull[:3, 3], order=1, mode="constant")
    return nib.Nifti1Image(moved, affine, image.header), world


def crest_lines(volume, out):
    subprocess.run([str(BINARY), "crest-lines", str(volume), "--level", "60", "--min-length", "10", "-o", str(out)], check=True)
    return [np.array(line["points"]) for line in json.load(open(out))["lines"]]


def draw(ax, fixed, moving, title):
    ax.add_collection(LineCollection([p[:, :2] for p in fixed], colors="#7f7f7f", linewidths=0.6, label="fixed"))
    ax.add_collection(LineCollection([p[:, :2] for p in moving], colors="#c0392b", linewidths=0.6, label="moving"))
    ax.autoscale()
    ax.set_aspect("equal")
    ax.axis("off")
    ax.set_title(title)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out")
    parser.add_argument("--degrees", type=float, default=10.0)
    parser.add_argument("--shift", type=float, default=8.0, help="translation length in mm")
    args = parser.parse_args()
    image = nib.load(TEMPLATE)
    r = rotation([0.3, -0.5, 1.0], args.degrees)
    t = args.shift * np.array([1.0, 0.5, -0.3]) / np.linalg.norm([1.0, 0.5, -0.3])
    moved, world = moved_copy(image, r, t)
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        nib.save(moved, tmp / "moved.nii.gz")
        fixed = crest_lines(TEMPLATE, tmp / "fixed.json")
        moving = crest_lines(tmp / "moved.nii.gz", tmp / "moving.json")
        run = subprocess.run(
            [str(BINARY), "register", str(tmp / "fixed.json"), str(tmp / "moving.json"), "-o", str(tmp / "t.json")],
            check=True, capture_output=True, text=True,
        )
        found = np.array(json.load(open(tmp / "t.json"))["matrix"])
    # The moving lines are the fixed ones moved by `world`; registration should
    # find its inverse.
    error = found @ world
    angle = np.degrees(np.arccos(np.clip((np.trace(error[:3, :3]) - 1) / 2, -1, 1)))
    print(f"true motion: {args.degrees}° and {args.shift} mm; {run.stdout.strip()}")
    print(f"left over after registration: {angle:.4f}°, {np.linalg.norm(error[:3, 3]):.4f} mm")
    registered = [p @ found[:3, :3].T + found[:3, 3] for p in moving]
    fig, axes = plt.subplots(1, 2, figsize=(12, 6.5))
    draw(axes[0], fixed, moving, f"before: moved by {args.degrees:g}° and {args.shift:g} mm")
    draw(axes[1], fixed, registered, f"after: {angle:.3f}° and {np.linalg.norm(error[:3, 3]):.3f} mm left")
    axes[0].legend(loc="lower left")
    fig.savefig(args.out, dpi=100, bbox_inches="tight")


if __name__ == "__main__":
    main()

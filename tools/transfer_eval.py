#!/usr/bin/env python3
"""How well are a template's labelled landmarks carried onto other scans? Make
subjects from a template image by a smooth random warp after a rigid motion, know
where each landmark truly lands, run a transfer command on every subject and
measure the distances.

    python3 tools/transfer_eval.py volumes/mni152_t1_1mm.nii.gz --level 60
        [--subjects 3] [--seed 1] [--method rigid|transfer|sitk] [--command "..."]
        [--meshes] [--keep DIR]

The landmarks: the template's extremal points (`crestline landmarks`), the 400 of
largest |curvature|, a farthest-point sample of 40 of them, labelled L01…L40 and
written as 3D Slicer markups (LPS).

A subject: Gaussian noise on a 4 mm grid, smoothed with σ = 12 mm, scaled to a
standard deviation of 4 mm per axis, is a displacement field D; a rigid motion E
(rotations uniform within ±6° about each axis, about the image's centre; shifts
uniform within ±4 mm) comes first; the subject is the template resampled through
x ↦ D(E(x)) by SimpleITK's B-spline interpolation (the map from a subject point to
the template point it shows). A landmark p of the template is at x = E⁻¹(D⁻¹(p)) in
the subject, D inverted by fixed-point iteration (checked: the map takes x back to p).

With --meshes the template and every subject are replaced by their isosurface
meshes at the level (`crestline iso`, outside the timing), whose lines are their
ridges and valleys of every strength (`crestline ridges --threshold 0`); the truth
is the same.

Methods: `rigid` (today's `crestline register` of the template's crest lines onto
the subject's, the landmarks moved by that motion), `transfer` (`crestline
transfer`), `sitk` (SimpleITK's registration of the template image onto the
subject's by mean squares on a random 5% of the voxels: an affine map, then a
B-spline free-form deformation on a 10×10×10 mesh; the landmarks moved by the
inverse of the map, found by Newton's method from the affine map's inverse; images
only), or any --command with the fields {crestline} {template} {landmarks}
{subject} {template_lines} {level} {level_option} (`--level` and the level, empty
with --meshes) {out}, whose output {out} is a markups file
(.mrk.json) with the same labels. The template's lines are computed once,
outside the timing (for `transfer`, by `crestline transfer --save-template-lines`);
a subject's own are timed.

Prints per subject the median and 90th percentile error (mm), the time, and the
error of the best affine map fitted to the true positions (a floor for affine
methods); then the same over all subjects. Needs SimpleITK, numpy, scipy and a
release build of the tool.
"""

import argparse
import json
import os
import shlex
import subprocess
import sys
import tempfile
import time

import numpy as np
import SimpleITK as sitk
from scipy.ndimage import gaussian_filter

FLIP = np.array([-1.0, -1.0, 1.0])
COUNT, POOL = 40, 400
GRID, SMOOTH, SPREAD = 4.0, 12.0, 4.0
DEGREES, SHIFT = 6.0, 4.0
SAMPLING_SEED = 1

TRANSFER = ("{crestline} transfer {template} {landmarks} {subject} -o {out} {level_option} "
            "--template-lines {template_lines}")


def run(*command):
    done = subprocess.run(command, capture_output=True, text=True)
    if done.returncode != 0:
        sys.exit(f"{shlex.join(command)} failed:\n{done.stderr}")
    return done.stdout


def template_landmarks(tool, template, level, folder):
    """The 40 labelled landmarks (LPS, in order) and the markups file holding them."""
    found = os.path.join(folder, "template.landmarks.json")
    run(tool, "landmarks", template, "--level", str(level), "-o", found)
    with open(found) as f:
        document = json.load(f)
    flip = FLIP if document["space"] == "RAS" else np.ones(3)
    extremal = [p for p in document["points"] if p["kind"] == "extremal"]
    extremal.sort(key=lambda p: -abs(p["curvature"]))
    pool = np.array([p["position"] for p in extremal[:POOL]]) * flip
    chosen = [0]
    distance = np.linalg.norm(pool - pool[0], axis=1)
    while len(chosen) < COUNT:
        chosen.append(int(np.argmax(distance)))
        distance = np.minimum(distance, np.linalg.norm(pool - pool[chosen[-1]], axis=1))
    points = pool[chosen]
    labels = [f"L{n + 1:02d}" for n in range(COUNT)]
    path = os.path.join(folder, "template.mrk.json")
    write_markups(path, labels, points)
    return labels, points, path


def write_markups(path, labels, lps):
    control = [{"id": str(n + 1), "label": label, "position": list(map(float, p)),
                "positionStatus": "defined"} for n, (label, p) in enumerate(zip(labels, lps))]
    document = {
        "@schema": "https://raw.githubusercontent.com/slicer/slicer/master/Modules/Loadable/"
                   "Markups/Resources/Schema/markups-schema-v1.0.3.json#",
        "markups": [{"type": "Fiducial", "name": "landmarks", "coordinateSystem": "LPS",
                     "coordinateUnits": "mm", "controlPoints": control}]}
    with open(path, "w") as f:
        json.dump(document, f, indent=1)


def read_markups(path):
    """Label → position (LPS) of the point lists of a markups file."""
    with open(path) as f:
        document = json.load(f)
    found = {}
    for markup in document["markups"]:
        if markup.get("type") != "Fiducial":
            continue
        flip = FLIP if markup.get("coordinateSystem") == "RAS" else np.ones(3)
        for point in markup["controlPoints"]:
            found[point["label"]] = np.array(point["position"]) * flip
    return found


def displacement_field(image, rng):
    """Smooth random displacements on a 4 mm grid over the image (a transform)."""
    size = np.array(image.GetSize()) * np.array(image.GetSpacing())
    shape = tuple(int(np.ceil(s / GRID)) + 1 for s in size)
    components = []
    for _ in range(3):
        noise = gaussian_filter(rng.normal(size=shape[::-1]), SMOOTH / GRID)
        components.append(noise * SPREAD / noise.std())
    field = sitk.GetImageFromArray(np.stack(components, axis=-1), isVector=True)
    field.SetSpacing((GRID,) * 3)
    field.SetOrigin(image.GetOrigin())
    field.SetDirection(image.GetDirection())
    return sitk.DisplacementFieldTransform(sitk.Cast(field, sitk.sitkVectorFloat64))


def rigid_motion(image, rng):
    transform = sitk.Euler3DTransform()
    size = np.array(image.GetSize())
    transform.SetCenter(image.TransformContinuousIndexToPhysicalPoint(((size - 1) / 2).tolist()))
    transform.SetRotation(*np.radians(rng.uniform(-DEGREES, DEGREES, 3)))
    transform.SetTranslation(rng.uniform(-SHIFT, SHIFT, 3).tolist())
    return transform


def invert(transform_point, p, start):
    """The x with transform_point(x) = p, by Newton's method from `start`, the
    Jacobian by central differences."""
    x = np.array(start, dtype=float)
    for _ in range(50):
        residual = transform_point(x) - p
        if np.linalg.norm(residual) < 1e-9:
            break
        jacobian = np.column_stack([(transform_point(x + h) - transform_point(x - h)) / 0.02
                                    for h in np.eye(3) * 0.01])
        x -= np.linalg.solve(jacobian, residual)
    assert np.linalg.norm(transform_point(x) - p) < 1e-5, "the map was not inverted"
    return x


def point_map(transform):
    """A transform as a function of numpy points."""
    return lambda x: np.array(transform.TransformPoint(tuple(map(float, x))))


def make_subject(image, seed):
    """The subject image, the map subject → template (LPS), and the inverse map of
    template points."""
    rng = np.random.default_rng(seed)
    field, motion = displacement_field(image, rng), rigid_motion(image, rng)
    warp = lambda x: np.array(field.TransformPoint(motion.TransformPoint(tuple(map(float, x)))))
    inverse_motion = motion.GetInverse()

    def to_subject(p):
        x = point_map(inverse_motion)(invert(point_map(field), p, p))
        assert np.linalg.norm(warp(x) - p) < 1e-5, "the warp was not inverted"
        return x

    composite = sitk.CompositeTransform(3)
    composite.AddTransform(field)
    composite.AddTransform(motion)  # the last added applies first: x ↦ D(E(x))
    probe = np.array(image.TransformContinuousIndexToPhysicalPoint((70.5, 90.25, 80.0)))
    assert np.linalg.norm(np.array(composite.TransformPoint(tuple(probe))) - warp(probe)) < 1e-9
    subject = sitk.Resample(sitk.Cast(image, sitk.sitkFloat32), image, composite,
                            sitk.sitkBSpline, 0.0, sitk.sitkFloat32)
    return subject, to_subject


def best_affine_error(source, target):
    """Errors of the least-squares affine map of source onto target."""
    homogeneous = np.hstack([source, np.ones((len(source), 1))])
    matrix, *_ = np.linalg.lstsq(homogeneous, target, rcond=None)
    return np.linalg.norm(homogeneous @ matrix - target, axis=1)


def lines_command(tool, scan, level, out):
    """The command writing the lines of `scan` to `out`: crest lines of an image's
    isosurface at `level`, or ridges and valleys of a mesh (`level` None) of every
    strength, as `crestline transfer` traces them on meshes."""
    if level is None:
        return [tool, "ridges", scan, "--threshold", "0", "-o", out]
    return [tool, "crest-lines", scan, "--level", str(level), "-o", out]


def save_transfer_lines(tool, template, landmarks, level, out):
    """The template's lines as `crestline transfer` traces them, written to `out`
    (by a transfer of the template onto itself)."""
    scratch = out + ".self.mrk.json"
    level_option = [] if level is None else ["--level", str(level)]
    run(tool, "transfer", template, landmarks, template, "-o", scratch, *level_option,
        "--save-template-lines", out)
    os.remove(scratch)


def rigid_transfer(tool, fields, level):
    """Today's answer: the template's crest lines registered rigidly onto the
    subject's, the landmarks moved by that motion."""
    lines = fields["out"] + ".lines.json"
    motion = fields["out"] + ".transform.json"
    run(*lines_command(tool, fields["subject"], level, lines))
    run(tool, "register", lines, fields["template_lines"], "-o", motion)
    with open(motion) as f:
        matrix = np.array(json.load(f)["matrix"])
    points = read_markups(fields["landmarks"])
    moved = {label: FLIP * (matrix[:3, :3] @ (FLIP * p) + matrix[:3, 3])
             for label, p in points.items()}
    write_markups(fields["out"], list(moved), list(moved.values()))


def registration(shrink, smooth):
    """A SimpleITK registration by mean squares on a random 5% of the voxels,
    linearly interpolated, over levels shrunk and smoothed (σ in voxels)."""
    method = sitk.ImageRegistrationMethod()
    method.SetMetricAsMeanSquares()
    method.SetMetricSamplingStrategy(method.RANDOM)
    method.SetMetricSamplingPercentage(0.05, SAMPLING_SEED)
    method.SetInterpolator(sitk.sitkLinear)
    method.SetShrinkFactorsPerLevel(shrink)
    method.SetSmoothingSigmasPerLevel(smooth)
    method.SmoothingSigmasAreSpecifiedInPhysicalUnitsOff()
    return method


def sitk_transfer(fields):
    """SimpleITK's intensity registration: the map of subject points to template
    points, affine then a B-spline FFD, inverted at the landmarks."""
    fixed = sitk.ReadImage(fields["subject"], sitk.sitkFloat32)
    moving = sitk.ReadImage(fields["template"], sitk.sitkFloat32)
    affine = sitk.CenteredTransformInitializer(fixed, moving, sitk.AffineTransform(3),
                                               sitk.CenteredTransformInitializerFilter.GEOMETRY)
    method = registration([4, 2, 1], [2, 1, 0])
    method.SetOptimizerAsRegularStepGradientDescent(learningRate=1.0, minStep=1e-4,
                                                    numberOfIterations=200)
    method.SetOptimizerScalesFromPhysicalShift()
    method.SetInitialTransform(affine, inPlace=True)
    method.Execute(fixed, moving)
    bspline = sitk.BSplineTransformInitializer(fixed, [10, 10, 10])
    method = registration([4, 2], [2, 1])
    method.SetOptimizerAsLBFGSB(gradientConvergenceTolerance=1e-5, numberOfIterations=50,
                                maximumNumberOfCorrections=5,
                                maximumNumberOfFunctionEvaluations=1000,
                                costFunctionConvergenceFactor=1e7)
    method.SetMovingInitialTransform(affine)
    method.SetInitialTransform(bspline, inPlace=True)
    method.Execute(fixed, moving)
    composite = sitk.CompositeTransform(3)
    composite.AddTransform(affine)
    composite.AddTransform(bspline)  # the last added applies first: x ↦ A(B(x))
    to_template = point_map(composite)
    probe = np.array(fixed.TransformContinuousIndexToPhysicalPoint((70.5, 90.25, 80.0)))
    assert np.linalg.norm(to_template(probe)
                          - point_map(affine)(point_map(bspline)(probe))) < 1e-9
    start = point_map(affine.GetInverse())
    points = read_markups(fields["landmarks"])
    moved = {label: invert(to_template, p, start(p)) for label, p in points.items()}
    write_markups(fields["out"], list(moved), list(moved.values()))


def summary(errors):
    return f"median {np.median(errors):5.2f} mm, p90 {np.percentile(errors, 90):5.2f} mm"


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("template")
    parser.add_argument("--level", type=float, required=True)
    parser.add_argument("--subjects", type=int, default=3)
    parser.add_argument("--seed", type=int, default=1, help="of the first subject")
    parser.add_argument("--method", choices=["rigid", "transfer", "sitk"], default="rigid")
    parser.add_argument("--command", help="a transfer command (see above) instead of --method")
    parser.add_argument("--crestline", default="target/release/crestline")
    parser.add_argument("--meshes", action="store_true",
                        help="transfer between the isosurface meshes of the images")
    parser.add_argument("--keep", help="a folder to keep the subjects and outputs in")
    args = parser.parse_args()
    if args.meshes and args.method == "sitk" and not args.command:
        parser.error("--method sitk registers images, not meshes")
    image = sitk.ReadImage(args.template)
    with tempfile.TemporaryDirectory() as scratch:
        folder = args.keep or scratch
        os.makedirs(folder, exist_ok=True)
        labels, points, landmarks = template_landmarks(args.crestline, args.template,
                                                       args.level, folder)
        template = args.template
        if args.meshes:
            template = os.path.join(folder, "template.ply")
            run(args.crestline, "iso", args.template, "--level", str(args.level), "-o", template)
        level = None if args.meshes else args.level
        template_lines = os.path.join(folder, "template.lines.json")
        if args.method == "rigid" and not args.command:
            run(*lines_command(args.crestline, template, level, template_lines))
        else:
            save_transfer_lines(args.crestline, template, landmarks, level, template_lines)
        every, times = [], []
        for seed in range(args.seed, args.seed + args.subjects):
            subject, to_subject = make_subject(image, seed)
            path = os.path.join(folder, f"subject{seed}.nii.gz")
            sitk.WriteImage(subject, path)
            if args.meshes:
                volume, path = path, os.path.join(folder, f"subject{seed}.ply")
                run(args.crestline, "iso", volume, "--level", str(args.level), "-o", path)
            truth = np.array([to_subject(p) for p in points])
            fields = {"crestline": args.crestline, "template": template,
                      "landmarks": landmarks, "subject": path, "template_lines": template_lines,
                      "level": args.level,
                      "level_option": "" if level is None else f"--level {level}",
                      "out": os.path.join(folder, f"subject{seed}.mrk.json")}
            start = time.perf_counter()
            if args.command or args.method == "transfer":
                run(*shlex.split((args.command or TRANSFER).format(**fields)))
            elif args.method == "sitk":
                sitk_transfer(fields)
            else:
                rigid_transfer(args.crestline, fields, level)
            times.append(time.perf_counter() - start)
            found = read_markups(fields["out"])
            missing = [label for label in labels if label not in found]
            if missing:
                sys.exit(f"subject {seed}: no {', '.join(missing)} in {fields['out']}")
            errors = np.linalg.norm(np.array([found[l] for l in labels]) - truth, axis=1)
            every.append(errors)
            print(f"subject {seed}: {summary(errors)}, {times[-1]:5.1f} s; best affine "
                  f"{summary(best_affine_error(points, truth))}", flush=True)
        print(f"all {args.subjects}: {summary(np.concatenate(every))}, "
              f"{np.mean(times):5.1f} s per subject")


if __name__ == "__main__":
    main()

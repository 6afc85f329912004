#!/usr/bin/env python3
"""Time crestline's isosurface against scikit-image and VTK on the same sampled field.

    python3 tools/compare_isosurface.py [--size N] [--period P] [--level L]
                                        [--repetitions R] [--threads T]

Builds and runs the ``bench_isosurface`` example (``cargo run --release --example
bench_isosurface``), which samples the gyroid

    f = sin x cos y + sin y cos z + sin z cos x,   (x, y, z) = 2π (i, j, k) / P

on an N³ grid (computed in f64, stored as f32) and writes the samples to a raw
little-endian f32 file, x fastest. This script builds the same field with numpy
from the same formula, checks that it matches the file, and runs on the file's
samples:

- ``skimage.measure.marching_cubes`` (one thread), area by
  ``skimage.measure.mesh_surface_area``;
- VTK's ``vtkFlyingEdges3D`` (multithreaded through vtkSMPTools, backend STDThread
  with T threads: the pip wheels default to the sequential backend),
  normals, gradients and scalars off, area by ``vtkMassProperties``.

Each is timed R times around the extraction call alone (loading is not timed) and
the minimum and median are printed with the vertex and triangle counts and the
area, then the area of each against VTK's and the time of each against crestline's
extraction. crestline's figures come from the example's own output: the extraction
(to shared vertices and triangles, like the other two) and, apart, the building of
its half-edge mesh, which the others do not make. crestline uses T threads too
(``RAYON_NUM_THREADS``).

Needs numpy, scikit-image and vtk (``tools/requirements.txt``).
"""

import argparse
import os
import re
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import vtk
from skimage import measure
from vtk.util import numpy_support

ROOT = Path(__file__).resolve().parent.parent


def gyroid(size: int, period: float) -> np.ndarray:
    """The field as a (z, y, x) float32 array, x fastest in memory."""
    w = 2.0 * np.pi / period
    s, c = np.sin(w * np.arange(size)), np.cos(w * np.arange(size))
    k, j, i = np.meshgrid(np.arange(size), np.arange(size), np.arange(size), indexing="ij")
    f = s[i] * c[j] + s[j] * c[k] + s[k] * c[i]
    return f.astype(np.float32)


def run_crestline(args, raw: Path) -> dict:
    env = dict(os.environ, RAYON_NUM_THREADS=str(args.threads))
    env.setdefault("CARGO_BUILD_JOBS", "1")
    command = [
        "cargo", "run", "--quiet", "--release", "-p", "crestline",
        "--example", "bench_isosurface", "--",
        "--size", str(args.size), "--period", str(args.period), "--level", str(args.level),
        "--repetitions", str(args.repetitions), "--raw", str(raw),
    ]
    out = subprocess.run(command, cwd=ROOT, env=env, check=True, capture_output=True, text=True)
    print(out.stdout.strip())
    figures = dict(re.findall(r"([a-z_]+)=([0-9.e+-]+)", out.stdout))
    return {key: float(value) for key, value in figures.items()}


def timed(call, repetitions: int):
    seconds, result = [], None
    for _ in range(repetitions):
        start = time.perf_counter()
        result = call()
        seconds.append(time.perf_counter() - start)
    return min(seconds), statistics.median(seconds), result


def run_skimage(volume: np.ndarray, level: float, repetitions: int) -> dict:
    best, median, (verts, faces, _, _) = timed(
        lambda: measure.marching_cubes(volume, level), repetitions
    )
    return {
        "min": best, "median": median, "vertices": len(verts), "triangles": len(faces),
        "area": measure.mesh_surface_area(verts, faces),
    }


def run_vtk(volume: np.ndarray, level: float, repetitions: int, threads: int) -> dict:
    # The pip wheels default to the sequential backend; STDThread runs in parallel.
    vtk.vtkSMPTools.SetBackend("STDThread")
    vtk.vtkSMPTools.Initialize(threads)
    image = vtk.vtkImageData()
    nz, ny, nx = volume.shape
    image.SetDimensions(nx, ny, nz)
    flat = np.ascontiguousarray(volume).ravel()
    image.GetPointData().SetScalars(numpy_support.numpy_to_vtk(flat, deep=False))

    def extract():
        fe = vtk.vtkFlyingEdges3D()
        fe.SetInputData(image)
        fe.SetValue(0, level)
        fe.ComputeNormalsOff()
        fe.ComputeGradientsOff()
        fe.ComputeScalarsOff()
        fe.Update()
        return fe.GetOutput()

    best, median, surface = timed(extract, repetitions)
    mass = vtk.vtkMassProperties()
    mass.SetInputData(surface)
    mass.Update()
    return {
        "min": best, "median": median, "vertices": surface.GetNumberOfPoints(),
        "triangles": surface.GetNumberOfPolys(), "area": mass.GetSurfaceArea(),
        "backend": vtk.vtkSMPTools.GetBackend(),
    }


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--size", type=int, default=256)
    parser.add_argument("--period", type=float, default=40.0)
    parser.add_argument("--level", type=float, default=0.2)
    parser.add_argument("--repetitions", type=int, default=5)
    parser.add_argument("--threads", type=int, default=os.cpu_count())
    args = parser.parse_args()

    with tempfile.TemporaryDirectory() as tmp:
        raw = Path(tmp) / "gyroid.raw"
        ours = run_crestline(args, raw)
        n = args.size
        volume = np.fromfile(raw, dtype="<f4").reshape(n, n, n)
    difference = np.abs(volume - gyroid(n, args.period)).max()
    print(f"field: {n}^3 gyroid, period {args.period}, level {args.level}; "
          f"largest difference between the file and numpy's field: {difference:.3g}")
    if difference > 1e-6:
        sys.exit("the field written by the example differs from numpy's")

    skimage = run_skimage(volume, args.level, args.repetitions)
    vtk_fe = run_vtk(volume, args.level, args.repetitions, args.threads)
    rows = [
        ("crestline extraction", ours["extract_min"], ours["extract_median"],
         ours["vertices"], ours["triangles"], ours["area"]),
        ("crestline half-edge mesh", ours["mesh_min"], ours["mesh_median"], None, None, None),
        ("skimage marching_cubes", skimage["min"], skimage["median"],
         skimage["vertices"], skimage["triangles"], skimage["area"]),
        (f"vtkFlyingEdges3D ({vtk_fe['backend']})", vtk_fe["min"], vtk_fe["median"],
         vtk_fe["vertices"], vtk_fe["triangles"], vtk_fe["area"]),
    ]
    print(f"{args.threads} threads for crestline and VTK, {args.repetitions} repetitions")
    print(f"{'':28} {'min s':>8} {'median s':>9} {'vertices':>10} {'triangles':>10} "
          f"{'area':>12} {'area/VTK':>9} {'time/crestline':>15}")
    for name, best, median, vertices, triangles, area in rows:
        counts = (f"{int(vertices):>10} {int(triangles):>10} {area:>12.1f} "
                  f"{area / vtk_fe['area']:>9.4f}" if area is not None else " " * 43)
        print(f"{name:28} {best:>8.3f} {median:>9.3f} {counts} "
              f"{best / ours['extract_min']:>15.2f}")


if __name__ == "__main__":
    main()

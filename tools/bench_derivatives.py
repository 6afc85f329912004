#!/usr/bin/env python3
"""Time scipy's Gaussian derivative filters on the work of ``bench_derivatives``.

For a SIZE³ float32 volume (256 by default), times
``scipy.ndimage.gaussian_filter(volume, sigma, order=(a, b, c), truncate=T)`` for
all 20 partial derivatives of order <= 3 and for the 10 of order <= 2, and prints
the seconds for each set and per output volume (minimum over the repetitions).
scipy filters one output at a time, each with three 1-D passes, on one thread.

The truncation defaults to 5 standard deviations, the radius of crestline's
kernels, so that both filter with kernels of the same length (scipy's own default
is 4).

With ``--rust``, also builds and runs the Rust example
``cargo run --release --example bench_derivatives`` with the same size and sigma
and prints the ratio of the seconds per output volume (scipy / crestline).

Usage: python3 tools/bench_derivatives.py [--size N] [--sigma S]
       [--truncate T] [--repetitions R] [--rust]
"""

import argparse
import re
import subprocess
import sys
import time
from pathlib import Path

try:
    import numpy as np
    import scipy
    from scipy import ndimage
except ImportError:
    sys.exit(
        "this script needs numpy and scipy: "
        "python3 -m pip install -r tools/requirements.txt"
    )

REPO = Path(__file__).resolve().parent.parent


def partials(max_order):
    """The (a, b, c) orders with a + b + c <= max_order."""
    return [
        (a, b, c)
        for a in range(4)
        for b in range(4)
        for c in range(4)
        if a + b + c <= max_order
    ]


def synthetic(size):
    """A smooth field with some texture, float32, indexed [z, y, x]."""
    axis = np.arange(size, dtype=np.float32) / size - 0.5
    z, y, x = np.meshgrid(axis, axis, axis, indexing="ij")
    blob = 1.0 - 4.0 * (x * x + 2.0 * y * y + 3.0 * z * z)
    index = np.arange(size)
    texture = 0.05 * ((index[None, None, :] * 7
                       + index[None, :, None] * 13
                       + index[:, None, None] * 29) % 17)
    return (blob + texture).astype(np.float32)


def time_scipy(volume, sigma, truncate, max_order, repetitions):
    """Minimum seconds over the repetitions for all partials up to max_order."""
    best = float("inf")
    orders = partials(max_order)
    for _ in range(repetitions):
        start = time.perf_counter()
        for order in orders:
            ndimage.gaussian_filter(volume, sigma, order=order, truncate=truncate)
        best = min(best, time.perf_counter() - start)
    return best, len(orders)


def time_rust(size, sigma):
    """Seconds per output volume printed by the Rust example, by max order."""
    command = [
        "cargo", "run", "--release", "-q", "-p", "crestline",
        "--example", "bench_derivatives", "--", str(size), str(sigma),
    ]
    output = subprocess.run(
        command, cwd=REPO, check=True, capture_output=True, text=True
    ).stdout
    print(output, end="")
    per_volume = {}
    for line in output.splitlines():
        found = re.match(r"order <= (\d).* ([0-9.]+) s per volume", line)
        if found:
            per_volume[int(found.group(1))] = float(found.group(2))
    return per_volume


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--size", type=int, default=256)
    parser.add_argument("--sigma", type=float, default=1.5)
    parser.add_argument("--truncate", type=float, default=5.0)
    parser.add_argument("--repetitions", type=int, default=1)
    parser.add_argument("--rust", action="store_true")
    args = parser.parse_args()
    volume = synthetic(args.size)
    print(f"scipy {scipy.__version__}, {args.size}^3 float32, "
          f"sigma {args.sigma} voxels, truncate {args.truncate}")
    scipy_per_volume = {}
    for max_order in (3, 2):
        seconds, count = time_scipy(
            volume, args.sigma, args.truncate, max_order, args.repetitions
        )
        scipy_per_volume[max_order] = seconds / count
        print(f"order <= {max_order}: {count} volumes in {seconds:.3f} s, "
              f"{seconds / count:.4f} s per volume")
    if args.rust:
        rust = time_rust(args.size, args.sigma)
        for max_order, seconds in sorted(rust.items(), reverse=True):
            ratio = scipy_per_volume[max_order] / seconds
            print(f"order <= {max_order}: scipy / crestline = {ratio:.1f} "
                  "per output volume")


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""Compare two lines files (`crestline ridges -o A.json`, the same mesh): how many
lines and points each has, and how far their points lie from the other file's.

    python3 tools/compare_lines.py A.json B.json

Prints the line counts and their relative difference, the point counts, and the
distance of every point to the nearest point of the other file (both ways), over the
bounding-box diagonal of all points: the largest, the 99.9th percentile and the share
above 10⁻⁴. This is how two solvers, or two versions, are checked to give the same
lines (count within 2 %, points within 10⁻⁴ of the diagonal). Needs numpy and scipy
(tools/requirements.txt).
"""

import argparse
import json

import numpy as np
from scipy.spatial import cKDTree


def points(path):
    with open(path) as f:
        lines = json.load(f)["lines"]
    return len(lines), np.array([p for line in lines for p in line["points"]], dtype=float)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("a")
    parser.add_argument("b")
    args = parser.parse_args()
    (na, pa), (nb, pb) = points(args.a), points(args.b)
    both = np.vstack([pa, pb])
    diagonal = np.linalg.norm(both.max(0) - both.min(0))
    da, _ = cKDTree(pb).query(pa)
    db, _ = cKDTree(pa).query(pb)
    d = np.concatenate([da, db]) / diagonal
    print(
        f"lines {na} vs {nb} ({100 * (nb - na) / max(na, 1):+.2f}%), points {len(pa)} vs {len(pb)}; "
        f"distance / diagonal: max {d.max():.2e}, 99.9th percentile {np.quantile(d, 0.999):.2e}, "
        f"share above 1e-4 {np.mean(d > 1e-4):.2e}"
    )


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""Share of feature-line length that runs within a distance of a silhouette.

Reads a drawing made by `crestline draw ... --silhouettes` and, for every group of
feature lines (ridges, valleys, ascending, descending, crest), prints the share of
its drawn length that lies within DISTANCE pixels (default 3) of a silhouette
path: the length a reader sees twice, once as the outline and once beside it.

    python3 tools/silhouette_overlap.py drawing.svg [DISTANCE]

Output: one line per group, `group share length`, e.g. `ridges 0.043 1234.5`.
Only the standard library is used.
"""

import math
import re
import sys
import xml.etree.ElementTree as ET

FEATURE_GROUPS = ["ridges", "valleys", "ascending", "descending", "crest"]
# Samples along the feature lines, in pixels.
STEP = 0.25


def paths_of(svg, group_id):
    """The polylines of a group: lists of (x, y), closed paths repeat their start."""
    ns = {"svg": "http://www.w3.org/2000/svg"}
    lines = []
    for group in svg.iterfind(".//svg:g", ns):
        if group.get("id") != group_id:
            continue
        for path in group.iterfind("svg:path", ns):
            lines.append(parse_path(path.get("d", "")))
    return lines


def parse_path(d):
    """Points of an SVG path made of M, L and Z commands (absolute)."""
    points = []
    for command, x, y in re.findall(r"([MLZ])\s*(?:(-?[\d.]+)[ ,](-?[\d.]+))?", d):
        if command == "Z":
            if points:
                points.append(points[0])
        else:
            points.append((float(x), float(y)))
    return points


class SegmentGrid:
    """Silhouette segments bucketed in square cells for distance queries."""

    def __init__(self, polylines, cell):
        self.cell = cell
        self.cells = {}
        for line in polylines:
            for a, b in zip(line, line[1:]):
                self.insert(a, b)

    def insert(self, a, b):
        lo_x, hi_x = sorted((a[0], b[0]))
        lo_y, hi_y = sorted((a[1], b[1]))
        for i in range(int(lo_x // self.cell), int(hi_x // self.cell) + 1):
            for j in range(int(lo_y // self.cell), int(hi_y // self.cell) + 1):
                self.cells.setdefault((i, j), []).append((a, b))

    def near(self, p, distance):
        """Whether a segment lies within `distance` of `p` (distance ≤ cell)."""
        ci, cj = int(p[0] // self.cell), int(p[1] // self.cell)
        for i in (ci - 1, ci, ci + 1):
            for j in (cj - 1, cj, cj + 1):
                for a, b in self.cells.get((i, j), ()):
                    if point_segment_distance(p, a, b) <= distance:
                        return True
        return False


def point_segment_distance(p, a, b):
    dx, dy = b[0] - a[0], b[1] - a[1]
    length2 = dx * dx + dy * dy
    t = 0.0
    if length2 > 0.0:
        t = max(0.0, min(1.0, ((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / length2))
    return math.hypot(p[0] - a[0] - t * dx, p[1] - a[1] - t * dy)


def overlap(lines, grid, distance):
    """(length within `distance` of the grid's segments, total length)."""
    near, total = 0.0, 0.0
    for line in lines:
        for a, b in zip(line, line[1:]):
            length = math.hypot(b[0] - a[0], b[1] - a[1])
            steps = max(1, math.ceil(length / STEP))
            piece = length / steps
            for k in range(steps):
                t = (k + 0.5) / steps
                p = (a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]))
                if grid.near(p, distance):
                    near += piece
            total += length
    return near, total


def main():
    path = sys.argv[1]
    distance = float(sys.argv[2]) if len(sys.argv) > 2 else 3.0
    svg = ET.parse(path).getroot()
    grid = SegmentGrid(paths_of(svg, "silhouettes"), max(distance, 1.0))
    for group in FEATURE_GROUPS:
        lines = paths_of(svg, group)
        if not lines:
            continue
        near, total = overlap(lines, grid, distance)
        share = near / total if total > 0 else 0.0
        print(f"{group} {share:.4f} {total:.1f}")


if __name__ == "__main__":
    main()

"""Render feature lines on their mesh as a PNG (orthographic view, matplotlib).

    python3 tools/plot_lines.py MESH.obj LINES.json OUT.png [--view AZIMUTH ELEVATION]

LINES.json is a lines file (`crestline ridges`, `crestline crest-lines`) or a
landmarks file (`crestline landmarks -o L.json`), whose point landmarks are drawn
as markers: extremal points as black dots, curvature maxima as orange triangles,
line ends as small grey squares.

The mesh (OBJ with `v`/`f` records, or any format crestline reads if converted to
OBJ first) is drawn as flat-shaded grey triangles, sorted back to front; ridges are
drawn in red, valleys in blue, other kinds in black. Line points hidden behind the
surface are not removed, so choose a view that shows the side of interest.
"""

import argparse
import json

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.collections import LineCollection, PolyCollection  # noqa: E402

COLOURS = {"ridge": "#c0392b", "valley": "#2e5fb8"}
MARKERS = {
    "extremal": dict(marker="o", color="black", s=18),
    "curvature_maximum": dict(marker="^", color="#e67e22", s=22),
    "end": dict(marker="s", color="#7f7f7f", s=6),
}


def read_obj(path):
    """Vertex positions and triangles (fanned) of an OBJ file."""
    vertices, faces = [], []
    with open(path) as f:
        for line in f:
            parts = line.split()
            if not parts:
                continue
            if parts[0] == "v":
                vertices.append([float(x) for x in parts[1:4]])
            elif parts[0] == "f":
                idx = [int(p.split("/")[0]) for p in parts[1:]]
                idx = [i - 1 if i > 0 else len(vertices) + i for i in idx]
                faces.extend([idx[0], idx[k], idx[k + 1]] for k in range(1, len(idx) - 1))
    return np.array(vertices), np.array(faces)


def view_matrix(azimuth, elevation):
    """Rotation taking world coordinates to (right, up, towards the viewer)."""
    a, e = np.radians(azimuth), np.radians(elevation)
    towards = np.array([np.cos(e) * np.sin(a), np.sin(e), np.cos(e) * np.cos(a)])
    right = np.cross([0.0, 1.0, 0.0], towards)
    right /= np.linalg.norm(right)
    up = np.cross(towards, right)
    return np.stack([right, up, towards])


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("mesh")
    parser.add_argument("lines")
    parser.add_argument("out")
    parser.add_argument("--view", nargs=2, type=float, default=(0.0, 0.0), metavar=("AZIMUTH", "ELEVATION"))
    parser.add_argument("--size", type=float, default=8.0, help="figure size in inches")
    args = parser.parse_args()

    vertices, faces = read_obj(args.mesh)
    rotation = view_matrix(*args.view)
    projected = vertices @ rotation.T
    triangles = projected[faces]
    normals = np.cross(triangles[:, 1] - triangles[:, 0], triangles[:, 2] - triangles[:, 0])
    normals /= np.linalg.norm(normals, axis=1, keepdims=True) + 1e-300
    visible = normals[:, 2] > 0
    order = np.argsort(triangles[visible][:, :, 2].mean(axis=1))
    shade = 0.55 + 0.4 * normals[visible][order, 2]

    fig, ax = plt.subplots(figsize=(args.size, args.size))
    ax.add_collection(PolyCollection(triangles[visible][order][:, :, :2], facecolors=np.repeat(shade[:, None], 3, axis=1), edgecolors="none"))
    document = json.load(open(args.lines))
    lines = document["lines"]
    for kind in sorted({line["kind"] for line in lines}):
        paths = []
        for line in (l for l in lines if l["kind"] == kind):
            points = np.array(line["points"]) @ rotation.T
            if line["closed"]:
                points = np.vstack([points, points[:1]])
            paths.append(points[:, :2])
        ax.add_collection(LineCollection(paths, colors=COLOURS.get(kind, "black"), linewidths=1.2, label=kind))
    for kind, style in MARKERS.items():
        points = [p["position"] for p in document.get("points", []) if p["kind"] == kind]
        if points:
            xy = np.array(points) @ rotation.T
            ax.scatter(xy[:, 0], xy[:, 1], zorder=3, label=kind.replace("_", " "), **style)
    ax.autoscale()
    ax.set_aspect("equal")
    ax.axis("off")
    ax.legend(loc="lower right")
    fig.savefig(args.out, dpi=120, bbox_inches="tight")


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""Compare crestline's curvature estimators with pymeshlab's principal-curvature filter.

    python3 tools/compare_pymeshlab.py [--vertices N] [--large-vertices N] [--out PNG]
                                       [--skip-large]

Builds crestline (``cargo build --release``) and runs, on the same meshes, both of its
estimators (``crestline curvature --estimator shape-operator|jet-fit``) and every method
of pymeshlab's ``compute_curvature_principal_directions_per_vertex``. It prints:

1. a calibration of each pymeshlab method on the regular analytic ellipsoid (and the
   sphere, for the scale factor): the normalization the data asks for (which output
   label holds the larger curvature, sign, whether values are integrated over an area,
   best scale factor) next to the fixed normalization this script applies
   (``NORMALIZATIONS`` below, where each choice is explained);
2. accuracy on the analytic meshes (``cargo run --example analytic_meshes``, exact
   curvature per vertex): relative RMS error and seconds per method;
3. agreement on the bundled real meshes (``meshes/``): Pearson correlation of k_max and
   of k_min between crestline's default estimator and every other estimator;
4. unless ``--skip-large``: timing on a jittered ellipsoid of ``--large-vertices``
   vertices (at least 200k by default), in seconds per 100k vertices, with the ratios
   the benchmark targets are stated in.

It also writes a grouped bar chart of the relative errors (log scale) to ``--out``
(default ``tools/out/curvature_errors.png``). Intermediate files go to a temporary
directory. The default run takes a few minutes on two cores.

Relative RMS error, over vertices (crestline's ``unreliable`` ones excluded)::

    sqrt(mean((k_max - k1)^2 + (k_min - k2)^2) / 2) / sqrt(mean(k1^2 + k2^2) / 2)

Timing: crestline's time is the ``estimate`` stage of its ``--report`` (median of three
runs; reading and building the mesh are shown apart), pymeshlab's is
``time.perf_counter()`` around the filter call alone (median of its calls; loading is
not timed). pymeshlab's filter runs on one thread; crestline uses all cores unless
``RAYON_NUM_THREADS`` says otherwise, so the timing table shows it on one thread too.

pymeshlab's filter returns one curvature per call, as the per-vertex quality chosen by
``curvcolormethod``, so every mesh is loaded and filtered twice, once for 'Max
Curvature' and once for 'Min Curvature', each time into a new ``MeshSet`` (a second
'Taubin approximation' call on the same mesh has crashed with a double free in
pymeshlab 2025.7.post1). ``autoclean=True`` drops unreferenced vertices ('Scale
Dependent Quadric Fitting' does not finish on meshes that have some); crestline also
drops them and welds duplicates, so vertices are matched by position everywhere.
"""

import argparse
import contextlib
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pymeshlab  # noqa: E402

REPO = Path(__file__).resolve().parent.parent
CRESTLINE = REPO / "target" / "release" / "crestline"
ANALYTIC_MESHES = REPO / "target" / "release" / "examples" / "analytic_meshes"
REAL_MESHES = sorted((REPO / "meshes").glob("*.obj")) + sorted((REPO / "meshes").glob("*.ply"))
DEFAULT_OUT = REPO / "tools" / "out" / "curvature_errors.png"

SURFACES = ("sphere", "ellipsoid", "torus")
SAMPLINGS = ("regular", "jittered")
CRESTLINE_ESTIMATORS = ("shape-operator", "jet-fit")
CRESTLINE_REPEATS = 3
PYMESHLAB_FILTER = "compute_curvature_principal_directions_per_vertex"
MAX_LABEL, MIN_LABEL = "Max Curvature", "Min Curvature"

# pymeshlab's default scale for its two scale-dependent methods is 10% of the bounding
# box diagonal, a ball that holds more vertices the finer the mesh: on a 210k-vertex
# ellipsoid 'Principal Component Analysis' took 287 s at that scale, and on the 20k
# ellipsoid 'Scale Dependent Quadric Fitting' was 3.9% off against 0.3-0.5% with a
# ball of 2-4 mean edge lengths. Both get an absolute scale of this many mean edge
# lengths instead (2 was the most accurate of 2, 3 and 4 for the quadric fit).
SCALE_IN_MEAN_EDGES = 2.0
SCALE_DEPENDENT = ("Principal Component Analysis", "Scale Dependent Quadric Fitting")


@dataclass(frozen=True)
class Normalization:
    """How the two values pymeshlab returns for a method become k_max >= k_min.

    Whatever the labels, the larger normalized value is taken as k_max and the smaller
    as k_min at every vertex; ``labels`` records what calibration is expected to find
    about the 'Max Curvature' output ('as labelled', 'swapped' or 'unordered').
    """

    per_area: bool  # values are integrated: divide by the barycentric vertex area
    factor: float  # then multiply by this (its sign is the sign convention)
    labels: str
    is_curvature: bool  # False: the values are not curvatures in any fixed unit
    reason: str


# VCG, under pymeshlab, stores the principal curvatures as K1 and K2 and its
# quality mapping writes K1 for 'Min Curvature' and K2 for 'Max Curvature'. The
# estimators below store the larger value in K1, so their labels come out swapped.
NORMALIZATIONS = {
    "Taubin approximation": Normalization(
        per_area=False,
        factor=1.0,
        labels="unordered",
        is_curvature=True,
        reason=(
            "Taubin's tensor formula yields curvatures in curvature units. K1 and K2 "
            "come out in the order of the Givens rotation that diagonalizes the "
            "tensor, not by size, so each label holds the larger value at about half "
            "of the vertices: the values are ordered per vertex. The best-fit factor "
            "is about 1 on the sphere and moves away from 1 on the ellipsoid and the "
            "torus: that is the estimator's bias on anisotropic curvature, not a "
            "unit, so no factor is applied."
        ),
    ),
    "Principal Component Analysis": Normalization(
        per_area=False,
        factor=1.0,
        labels="n/a",
        is_curvature=False,
        reason=(
            "Not usable as a curvature. The values are far from curvature units "
            "(thousands to tens of millions in magnitude on these meshes, growing "
            "with the vertex count), mostly an offset, and not even the sign of "
            "their relation to curvature holds: their correlation with the exact "
            "curvature is negative on the ellipsoid and positive on the torus. No "
            "fixed sign or factor fits, so the values are kept as returned (ordered "
            "per vertex); their error and correlation are shown only to document this."
        ),
    ),
    "Normal Cycles": Normalization(
        per_area=True,
        factor=0.5,
        labels="swapped",
        is_curvature=True,
        reason=(
            "The normal-cycle tensor is an integral: VCG sums beta*|e|*e e^T over "
            "every edge at the vertex, each at its full length, while an edge is "
            "shared by its two end vertices. The values are therefore divided by the "
            "barycentric vertex area (a third of the adjacent triangles) and halved. "
            "K1 is the tangent eigenvalue of largest magnitude, written to 'Min "
            "Curvature', hence the swap. No normalization repairs saddles: where "
            "k2 < 0 (the inner half of the torus) the smaller value comes out about 0 "
            "instead of k2, while the same tensor evaluated with numpy on the same "
            "mesh has the eigenvalues k2, about 0 (along the normal) and k1. So VCG "
            "takes the eigenvector of the negative eigenvalue for the normal, and the "
            "torus errors show it."
        ),
    ),
    "Quadric Fitting": Normalization(
        per_area=False,
        factor=1.0,
        labels="swapped",
        is_curvature=True,
        reason=(
            "Pointwise curvature of a quadric fitted around the vertex, K1 >= K2, "
            "with outward normals (convex positive); only the labels are swapped."
        ),
    ),
    "Scale Dependent Quadric Fitting": Normalization(
        per_area=False,
        factor=1.0,
        labels="swapped",
        is_curvature=True,
        reason=(
            "As 'Quadric Fitting', with the quadric fitted over a ball of "
            f"{SCALE_IN_MEAN_EDGES:g} mean edge lengths (see SCALE_IN_MEAN_EDGES)."
        ),
    ),
}
PYMESHLAB_METHODS = tuple(NORMALIZATIONS)
SHORT_NAMES = {
    "shape-operator": "cl:shape-op",
    "jet-fit": "cl:jet-fit",
    "Taubin approximation": "pm:Taubin",
    "Principal Component Analysis": "pm:PCA",
    "Normal Cycles": "pm:NormCyc",
    "Quadric Fitting": "pm:Quadric",
    "Scale Dependent Quadric Fitting": "pm:SDQuadric",
}
ALL_METHODS = CRESTLINE_ESTIMATORS + PYMESHLAB_METHODS


@dataclass
class Estimate:
    """Principal curvatures per vertex (k_max >= k_min), with the vertex positions."""

    positions: np.ndarray
    k_max: np.ndarray
    k_min: np.ndarray
    seconds: float


@dataclass
class RawOutput:
    """The two values pymeshlab returns for one method, as labelled by pymeshlab."""

    positions: np.ndarray
    faces: np.ndarray
    max_label: np.ndarray
    min_label: np.ndarray
    seconds: float


@dataclass
class Exact:
    """An analytic mesh: vertex positions and exact principal curvatures k1 >= k2."""

    name: str
    path: Path
    positions: np.ndarray
    k1: np.ndarray
    k2: np.ndarray


# --- files and processes -------------------------------------------------------------

PLY_TYPES = {
    "char": "i1", "int8": "i1", "uchar": "u1", "uint8": "u1",
    "short": "<i2", "int16": "<i2", "ushort": "<u2", "uint16": "<u2",
    "int": "<i4", "int32": "<i4", "uint": "<u4", "uint32": "<u4",
    "float": "<f4", "float32": "<f4", "double": "<f8", "float64": "<f8",
}


def read_ply_vertices(path):
    """The vertex element of a binary little-endian PLY file whose first element it is."""
    with open(path, "rb") as f:
        header = []
        while not header or header[-1] != "end_header":
            header.append(f.readline().decode("ascii").strip())
        if "format binary_little_endian 1.0" not in header:
            raise ValueError(f"{path}: not a binary little-endian PLY file")
        elements = [line.split() for line in header if line.startswith("element")]
        if elements[0][1] != "vertex":
            raise ValueError(f"{path}: the vertex element is not the first one")
        fields = []
        for line in header[header.index(" ".join(elements[0])) + 1:]:
            if not line.startswith("property"):
                break
            _, kind, name = line.split()
            fields.append((name, PLY_TYPES[kind]))
        count = int(elements[0][2])
        dtype = np.dtype(fields)
        return np.frombuffer(f.read(count * dtype.itemsize), dtype=dtype, count=count)


def positions_of(vertices):
    """An (n, 3) float64 array of the x, y, z fields of a PLY vertex array."""
    return np.stack([vertices[axis].astype(np.float64) for axis in "xyz"], axis=1)


def run(command, env=None):
    """Run a command; on failure print its output and stop."""
    result = subprocess.run([str(c) for c in command], cwd=REPO, env=env,
                            capture_output=True, text=True)
    if result.returncode != 0:
        sys.exit(f"failed: {' '.join(map(str, command))}\n{result.stdout}{result.stderr}")
    return result.stdout


def build():
    run(["cargo", "build", "--release", "--bin", "crestline", "--example", "analytic_meshes"])


def write_analytic_meshes(directory, vertices):
    """Write the six analytic meshes; return them in table order."""
    run([ANALYTIC_MESHES, directory, vertices])
    meshes = []
    for surface in SURFACES:
        for sampling in SAMPLINGS:
            name = f"{surface}_{sampling}"
            path = Path(directory) / f"{name}_{vertices}.ply"
            v = read_ply_vertices(path)
            meshes.append(Exact(name, path, positions_of(v),
                                v["k1"].astype(np.float64), v["k2"].astype(np.float64)))
    return meshes


# --- running the estimators ----------------------------------------------------------

def run_crestline(mesh, estimator, workdir, repeats, threads=None):
    """crestline's curvature on its reliable vertices, and the median read + build time.

    The returned estimate's seconds are the median of the runs' ``estimate`` stages.
    """
    output = Path(workdir) / f"{mesh.stem}.{estimator}.ply"
    report = Path(workdir) / f"{mesh.stem}.{estimator}.json"
    env = dict(os.environ, RAYON_NUM_THREADS=str(threads)) if threads else None
    estimate_seconds, setup_seconds = [], []
    for _ in range(repeats):
        run([CRESTLINE, "curvature", mesh, "-o", output, "--estimator", estimator,
             "--report", report], env=env)
        stages = {s["name"]: s["seconds"] for s in json.loads(report.read_text())["stages"]}
        estimate_seconds.append(stages["estimate"])
        setup_seconds.append(stages["read"] + stages["build"])
    v = read_ply_vertices(output)
    reliable = v["unreliable"] == 0
    estimate = Estimate(positions_of(v)[reliable], v["k_max"][reliable].astype(np.float64),
                        v["k_min"][reliable].astype(np.float64),
                        statistics.median(estimate_seconds))
    return estimate, statistics.median(setup_seconds)


def mean_edge_length(mesh):
    positions, faces = mesh.vertex_matrix(), mesh.face_matrix()
    edges = positions[faces] - positions[np.roll(faces, 1, axis=1)]
    return float(np.linalg.norm(edges, axis=2).mean())


@contextlib.contextmanager
def native_stdout_silenced():
    """Send file descriptor 1 to /dev/null: the quadric fits print a line per call."""
    sys.stdout.flush()
    saved = os.dup(1)
    with open(os.devnull, "w") as devnull:
        os.dup2(devnull.fileno(), 1)
    try:
        yield
    finally:
        os.dup2(saved, 1)
        os.close(saved)


def run_pymeshlab(path, method, calls=2):
    """pymeshlab's two curvature outputs for one method; seconds: median filter time.

    Calls alternate between the 'Max Curvature' and 'Min Curvature' quality, each on a
    freshly loaded mesh.
    """
    values, seconds = {}, []
    for call in range(calls):
        label = (MAX_LABEL, MIN_LABEL)[call % 2]
        meshes = pymeshlab.MeshSet()
        meshes.load_new_mesh(str(path))
        arguments = dict(method=method, curvcolormethod=label, autoclean=True)
        if method in SCALE_DEPENDENT:
            scale = SCALE_IN_MEAN_EDGES * mean_edge_length(meshes.current_mesh())
            arguments["scale"] = pymeshlab.PureValue(scale)
        with native_stdout_silenced():
            start = time.perf_counter()
            getattr(meshes, PYMESHLAB_FILTER)(**arguments)
            seconds.append(time.perf_counter() - start)
        mesh = meshes.current_mesh()
        values[label] = mesh.vertex_scalar_array().copy()
        positions, faces = mesh.vertex_matrix().copy(), mesh.face_matrix().copy()
    return RawOutput(positions, faces, values[MAX_LABEL], values[MIN_LABEL],
                     statistics.median(seconds))


# --- normalization and calibration ---------------------------------------------------

def barycentric_areas(positions, faces):
    """A third of the area of the triangles around each vertex."""
    corners = positions[faces]
    areas = 0.5 * np.linalg.norm(
        np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]), axis=1)
    result = np.zeros(len(positions))
    for corner in range(3):
        np.add.at(result, faces[:, corner], areas / 3.0)
    return result


def labelled_values(raw, per_area):
    """pymeshlab's 'Max' and 'Min' outputs, divided by the vertex area if asked."""
    if not per_area:
        return raw.max_label, raw.min_label
    areas = barycentric_areas(raw.positions, raw.faces)
    with np.errstate(divide="ignore", invalid="ignore"):
        return raw.max_label / areas, raw.min_label / areas


def ordered(a, b, factor):
    """(k_max, k_min) from two per-vertex values after scaling."""
    a, b = factor * a, factor * b
    return np.maximum(a, b), np.minimum(a, b)


def normalize(raw, normalization):
    """Apply a method's fixed normalization to pymeshlab's raw output."""
    a, b = labelled_values(raw, normalization.per_area)
    k_max, k_min = ordered(a, b, normalization.factor)
    return Estimate(raw.positions, k_max, k_min, raw.seconds)


@dataclass
class Detection:
    """The normalization that best maps a method's output onto the exact curvature."""

    per_area: bool
    factor: float
    max_holds_larger: float  # share of vertices where 'Max' is the larger curvature
    fit_error: float

    @property
    def labels(self):
        if self.max_holds_larger > 0.95:
            return "as labelled"
        if self.max_holds_larger < 0.05:
            return "swapped"
        return "unordered"


def fitted_factor(a, b, exact_k1, exact_k2, sign):
    """Least-squares factor (of the given sign) mapping ordered (a, b) onto (k1, k2)."""
    k_max, k_min = ordered(a, b, sign)
    x, y = np.concatenate([k_max, k_min]), np.concatenate([exact_k1, exact_k2])
    finite = np.isfinite(x)
    return sign * float(x[finite] @ y[finite] / (x[finite] @ x[finite]))


def detect_normalization(raw, exact):
    """Try pointwise and per-area values, both signs; keep the best-fitting factor."""
    k1, k2, found = exact_at(exact, raw.positions)
    best = None
    for per_area in (False, True):
        a, b = (values[found] for values in labelled_values(raw, per_area))
        for sign in (1.0, -1.0):
            factor = fitted_factor(a, b, k1, k2, sign)
            error = relative_rms_error(*ordered(a, b, factor), k1, k2)
            if best is None or error < best.fit_error:
                share = float(np.mean(sign * a > sign * b))
                best = Detection(per_area, factor, share, error)
    return best


def factor_on(raw, exact, detection):
    """The best factor on another mesh, with the detected area handling and sign."""
    k1, k2, found = exact_at(exact, raw.positions)
    a, b = (values[found] for values in labelled_values(raw, detection.per_area))
    return fitted_factor(a, b, k1, k2, np.sign(detection.factor))


# --- comparing -----------------------------------------------------------------------

def match(reference, query):
    """Index of the reference vertex at each query position (-1 where there is none).

    Positions are compared on a grid of 1e-7 of the bounding-box diagonal.
    """
    extent = reference.max(axis=0) - reference.min(axis=0)
    step = 1e-7 * float(np.linalg.norm(extent))
    keys = {tuple(k): i for i, k in enumerate(np.round(reference / step).astype(np.int64))}
    return np.array([keys.get(tuple(k), -1)
                     for k in np.round(query / step).astype(np.int64)], dtype=np.int64)


def exact_at(exact, positions):
    """Exact k1, k2 at the given positions, and the mask of positions found."""
    index = match(exact.positions, positions)
    found = index >= 0
    return exact.k1[index[found]], exact.k2[index[found]], found


def relative_rms_error(k_max, k_min, k1, k2):
    finite = np.isfinite(k_max) & np.isfinite(k_min)
    k_max, k_min, k1, k2 = k_max[finite], k_min[finite], k1[finite], k2[finite]
    error = np.mean((k_max - k1) ** 2 + (k_min - k2) ** 2) / 2
    return float(np.sqrt(error) / np.sqrt(np.mean(k1 ** 2 + k2 ** 2) / 2))


def error_against(estimate, exact):
    k1, k2, found = exact_at(exact, estimate.positions)
    return relative_rms_error(estimate.k_max[found], estimate.k_min[found], k1, k2)


def pearson(x, y):
    finite = np.isfinite(x) & np.isfinite(y)
    return float(np.corrcoef(x[finite], y[finite])[0, 1])


def correlations(reference, other):
    """Pearson correlation of k_max and of k_min at the vertices both have."""
    index = match(reference.positions, other.positions)
    found = index >= 0
    return (pearson(reference.k_max[index[found]], other.k_max[found]),
            pearson(reference.k_min[index[found]], other.k_min[found]))


def same_order(positions, exact):
    return positions.shape == exact.positions.shape and np.array_equal(positions, exact.positions)


# --- printing ------------------------------------------------------------------------

def print_table(headers, rows):
    """A plain-text table: first column left-aligned, the others right-aligned."""
    widths = [max(len(str(row[i])) for row in [headers] + rows) for i in range(len(headers))]

    def line(cells):
        return "  ".join(str(c).ljust(w) if i == 0 else str(c).rjust(w)
                         for i, (c, w) in enumerate(zip(cells, widths)))

    print(line(headers))
    print("  ".join("-" * w for w in widths))
    for row in rows:
        print(line(row))


def percent(value):
    return f"{100 * value:.3g}%"


def print_heading(title):
    print(f"\n=== {title} ===\n")


def wrap(text, indent="    ", width=88):
    lines, current = [], ""
    for word in text.split():
        if current and len(indent) + len(current) + 1 + len(word) > width:
            lines.append(indent + current)
            current = word
        else:
            current = f"{current} {word}".strip()
    return "\n".join(lines + [indent + current])


# --- the four sections ---------------------------------------------------------------

def run_analytic(meshes, workdir):
    """Normalized estimates and raw pymeshlab outputs on every analytic mesh."""
    estimates, raw_outputs = {}, {}
    for exact in meshes:
        for estimator in CRESTLINE_ESTIMATORS:
            estimates[exact.name, estimator], _ = run_crestline(
                exact.path, estimator, workdir, CRESTLINE_REPEATS)
        for method in PYMESHLAB_METHODS:
            raw = run_pymeshlab(exact.path, method)
            raw_outputs[exact.name, method] = raw
            estimates[exact.name, method] = normalize(raw, NORMALIZATIONS[method])
    return estimates, raw_outputs


def print_calibration(meshes, raw_outputs):
    by_name = {exact.name: exact for exact in meshes}
    ellipsoid, sphere = by_name["ellipsoid_regular"], by_name["sphere_regular"]
    print_heading(f"1. Calibration of pymeshlab's methods on {ellipsoid.path.name}")
    print("Detected: the share of vertices where 'Max Curvature' holds the larger value,")
    print("whether dividing by the barycentric vertex area fits better, the least-squares")
    print("factor (sign included) on the ellipsoid and, with the same choices, on")
    print(f"{sphere.path.name}, and the error left after that fit. Applied: the fixed")
    print("normalization used everywhere below (values are then ordered per vertex).\n")
    rows = []
    for method in PYMESHLAB_METHODS:
        detected = detect_normalization(raw_outputs[ellipsoid.name, method], ellipsoid)
        sphere_factor = factor_on(raw_outputs[sphere.name, method], sphere, detected)
        applied = NORMALIZATIONS[method]
        rows.append([
            method,
            f"{detected.labels} ({detected.max_holds_larger:.0%})",
            "yes" if detected.per_area else "no",
            f"{detected.factor:.4g}", f"{sphere_factor:.4g}", percent(detected.fit_error),
            applied.labels, "yes" if applied.per_area else "no", f"{applied.factor:g}",
            agreement(detected, sphere_factor, applied),
        ])
    print_table(["method", "det: 'Max' label", "per area", "factor ell.", "factor sph.",
                 "fit err", "applied: labels", "per area", "factor", "agree"], rows)
    print()
    for method in PYMESHLAB_METHODS:
        print(f"  {method}:")
        print(wrap(NORMALIZATIONS[method].reason))


def agreement(detected, sphere_factor, applied):
    """Whether calibration supports the applied normalization (factor: within 5% on the
    sphere, whose curvature is the same in every direction)."""
    if not applied.is_curvature:
        return f"none fits ({percent(detected.fit_error)} left)"
    same = (detected.labels == applied.labels and detected.per_area == applied.per_area
            and abs(sphere_factor / applied.factor - 1) < 0.05)
    return "yes" if same else "NO"


def print_accuracy(meshes, estimates):
    print_heading("2. Accuracy on the analytic meshes: relative RMS error, seconds")
    print("crestline (cl:): its estimate stage, median of 3 runs; pymeshlab (pm:): the")
    print("filter call, median of 2. Vertices are matched to the exact ones by position.\n")
    rows = []
    for exact in meshes:
        cells = [f"{percent(error_against(estimates[exact.name, m], exact))} "
                 f"{estimates[exact.name, m].seconds:.3f}s" for m in ALL_METHODS]
        rows.append([f"{exact.name} ({len(exact.positions)})"] + cells)
    print_table(["mesh (vertices)"] + [SHORT_NAMES[m] for m in ALL_METHODS], rows)
    reordered = [f"{exact.name}: {SHORT_NAMES[m]}" for exact in meshes for m in ALL_METHODS
                 if not same_order(estimates[exact.name, m].positions, exact)]
    print("\nVertex order and count the same as in the file for every method and mesh"
          if not reordered else f"\nVertices reordered or dropped: {', '.join(reordered)}")


def print_real_mesh_agreement(workdir):
    print_heading("3. Agreement on the real meshes: Pearson r of k_max / r of k_min")
    reference = CRESTLINE_ESTIMATORS[0]
    others = CRESTLINE_ESTIMATORS[1:] + PYMESHLAB_METHODS
    print(f"Each column against crestline's default estimator ({reference}), over its")
    print("reliable vertices (boundary vertices excluded), matched by position.\n")
    rows = []
    for path in REAL_MESHES:
        base, _ = run_crestline(path, reference, workdir, repeats=1)
        estimates = [run_crestline(path, other, workdir, repeats=1)[0]
                     for other in CRESTLINE_ESTIMATORS[1:]]
        estimates += [normalize(run_pymeshlab(path, method), NORMALIZATIONS[method])
                      for method in PYMESHLAB_METHODS]
        cells = ["{:.3f} / {:.3f}".format(*correlations(base, e)) for e in estimates]
        rows.append([f"{path.name} ({len(base.positions)})"] + cells)
    print_table(["mesh (reliable vertices)"] + [SHORT_NAMES[m] for m in others], rows)


def time_large_mesh(exact, workdir):
    """Rows of the timing table, and the seconds and error per method."""
    per_100k = 1e5 / len(exact.positions)
    rows, seconds, errors, setups = [], {}, {}, []
    for estimator in CRESTLINE_ESTIMATORS:
        for threads in (None, 1):
            estimate, setup = run_crestline(exact.path, estimator, workdir,
                                            CRESTLINE_REPEATS, threads)
            key = estimator if threads is None else f"{estimator} (1 thread)"
            seconds[key], errors[key] = estimate.seconds, error_against(estimate, exact)
            setups.append(setup)
            rows.append([f"crestline {key}", f"{estimate.seconds:.3f}",
                         f"{estimate.seconds * per_100k:.4f}", percent(errors[key])])
    setup = statistics.median(setups)
    rows.append(["crestline read + build (not in the rows above)", f"{setup:.3f}",
                 f"{setup * per_100k:.4f}", ""])
    for method in PYMESHLAB_METHODS:
        estimate = normalize(run_pymeshlab(exact.path, method, calls=3),
                             NORMALIZATIONS[method])
        seconds[method], errors[method] = estimate.seconds, error_against(estimate, exact)
        rows.append([f"pymeshlab {method}", f"{estimate.seconds:.3f}",
                     f"{estimate.seconds * per_100k:.4f}", percent(errors[method])])
    return rows, seconds, errors


def print_timing(exact, workdir, analytic_errors):
    print_heading(f"4. Timing on {exact.path.name} ({len(exact.positions)} vertices)")
    print("crestline: estimate stage, median of 3 runs, all cores and one thread;")
    print("pymeshlab: filter call (one thread), median of 3 calls.\n")
    rows, seconds, errors = time_large_mesh(exact, workdir)
    print_table(["method", "seconds", "s / 100k vertices", "rel. RMS error"], rows)
    fastest = min(PYMESHLAB_METHODS, key=seconds.get)
    print(f"\nfastest pymeshlab method: {fastest}")
    for threads in ("", " (1 thread)"):
        ratio = seconds[fastest] / seconds["shape-operator" + threads]
        print(f"pymeshlab {fastest} / crestline shape-operator{threads}: {ratio:.2f}x "
              f"(target >= 5x: {'met' if ratio >= 5 else 'MISSED'})")
    for threads in ("", " (1 thread)"):
        ratio = seconds["Quadric Fitting"] / seconds["jet-fit" + threads]
        print(f"pymeshlab Quadric Fitting / crestline jet-fit{threads}: {ratio:.2f}x "
              f"(target > 1x: {'met' if ratio > 1 else 'MISSED'})")
    print(f"error on this mesh: jet-fit {percent(errors['jet-fit'])}, "
          f"Quadric Fitting {percent(errors['Quadric Fitting'])}")
    at_least_as_accurate = [name for name, errs in analytic_errors.items()
                            if errs["jet-fit"] <= errs["Quadric Fitting"]]
    print(f"analytic meshes where jet-fit is at least as accurate as Quadric Fitting: "
          f"{len(at_least_as_accurate)} of {len(analytic_errors)}")


def plot_errors(meshes, analytic_errors, out):
    """Grouped bars: one group per analytic mesh, one bar per method, log scale."""
    out.parent.mkdir(parents=True, exist_ok=True)
    figure, axes = plt.subplots(figsize=(13, 5))
    width = 0.8 / len(ALL_METHODS)
    groups = np.arange(len(meshes))
    for i, method in enumerate(ALL_METHODS):
        values = [100 * analytic_errors[exact.name][method] for exact in meshes]
        uncalibrated = method in NORMALIZATIONS and not NORMALIZATIONS[method].is_curvature
        label = SHORT_NAMES[method] + (" (not a curvature)" if uncalibrated else "")
        axes.bar(groups + (i - (len(ALL_METHODS) - 1) / 2) * width, values, width,
                 label=label, hatch="//" if uncalibrated else None)
    axes.set_yscale("log")
    axes.set_xticks(groups, [exact.name.replace("_", "\n") for exact in meshes])
    axes.set_ylabel("relative RMS error of (k_max, k_min), %")
    axes.set_title(f"Principal curvature error on analytic meshes "
                   f"({len(meshes[0].positions)} vertices); cl: crestline, pm: pymeshlab")
    axes.grid(axis="y", which="both", alpha=0.3)
    axes.legend(loc="upper left", bbox_to_anchor=(1.0, 1.0), fontsize="small")
    figure.tight_layout()
    figure.savefig(out, dpi=120)
    plt.close(figure)


def parse_arguments():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--vertices", type=int, default=20000,
                        help="vertices of the analytic meshes (default 20000)")
    parser.add_argument("--large-vertices", type=int, default=250000,
                        help="vertices of the timing ellipsoid (default 250000)")
    parser.add_argument("--out", type=Path, default=DEFAULT_OUT,
                        help=f"error chart PNG (default {DEFAULT_OUT.relative_to(REPO)})")
    parser.add_argument("--skip-large", action="store_true", help="skip the timing run")
    return parser.parse_args()


def main():
    arguments = parse_arguments()
    build()
    with tempfile.TemporaryDirectory() as workdir:
        meshes = write_analytic_meshes(workdir, arguments.vertices)
        estimates, raw_outputs = run_analytic(meshes, workdir)
        print_calibration(meshes, raw_outputs)
        print_accuracy(meshes, estimates)
        analytic_errors = {exact.name: {m: error_against(estimates[exact.name, m], exact)
                                        for m in ALL_METHODS} for exact in meshes}
        plot_errors(meshes, analytic_errors, arguments.out)
        print(f"\nerror chart: {arguments.out}")
        print_real_mesh_agreement(workdir)
        if not arguments.skip_large:
            large_dir = Path(workdir) / "large"
            large_dir.mkdir()
            large = write_analytic_meshes(large_dir, arguments.large_vertices)
            ellipsoid = next(m for m in large if m.name == "ellipsoid_jittered")
            print_timing(ellipsoid, workdir, analytic_errors)


if __name__ == "__main__":
    main()

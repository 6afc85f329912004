#!/usr/bin/env python3
"""Conditioning of crestline's smoothing system M + tK, with the input mesh's cotan
Laplacian and with the intrinsic Delaunay one.

    python3 tools/laplacian_conditioning.py data/dragon/dragon_vrip.ply [--tau 2 0.25]

crestline smooths the extremalities implicitly, (M + tK) e' = M e with t = τ h̄² (h̄ the
mean edge length), on large meshes by preconditioned conjugate gradients: K is the cotan
Laplacian with weights w = ½ (cot α + cot β) clamped to [0, 10⁴] (NaN gives 0), M the
lumped masses (star area / 3, at least 10⁻⁶ t). On a scan, slivers couple nearly
coincident vertices far more strongly than their masses, and pairs of obtuse triangles
have negative weights, which the clamp sets to 0. Does the Laplacian of the intrinsic
Delaunay triangulation (Bobenko and Springborn 2007; Sharp, Soliman and Crane 2019),
whose weights are all non-negative, make the system well conditioned on a scan?

The intrinsic triangulation keeps the vertices and the edge lengths; its edges are
flipped while cot α + cot β < -10⁻¹², the new edge's length measured with its two
triangles unfolded into the plane. The script prints the flip count and, for each τ and
both Laplacians, two Markdown tables:

1. the stiff couplings: the edges with t w / min(M_pp, M_qq) above 10, 100, 10³ and
   10⁴, the largest ratio, and the lengths over h̄ of the edges above 100 (median,
   share below 0.1) and of the five strongest;
2. the iterations of the conjugate gradient method from x = 0 to a relative residual of
   10⁻⁷ (at most 3000), for a random right-hand side M r (r uniform in [-1, 1]) and a
   smooth one M x (the x coordinates), preconditioned by Jacobi and by block Jacobi:
   exact inverses on groups of at most 8 unknowns joined by couplings
   |A_pq| >= θ √(A_pp A_qq), merged strongest first, for θ = 0.5 (the threshold of
   crestline's stiff blocks) and 0.1.

Input: a PLY file of triangles, ASCII or binary, repaired like crestline does (vertices
at identical positions welded, faces with a repeated vertex or zero area dropped); the
Stanford dragon comes from tools/fetch_dragon.sh. BLAS is held to one thread; on the
dragon (871,414 triangles) the run takes about two minutes of one core, nearly all in
the solves. Progress goes to standard error. Needs numpy and scipy.
"""

import os

for variable in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[variable] = "1"  # read when numpy loads its BLAS

import argparse
import math
import sys
import time
from collections import deque
from functools import partial

import numpy as np
import scipy.sparse as sp

from refine_mesh import Unsupported, read_ply  # the tools' PLY reader

MAX_WEIGHT = 1e4  # crestline's clamp of the cotan weights
MIN_MASS_FRACTION = 1e-6  # the masses are at least this times t
FLIP_TOLERANCE = 1e-12  # an edge is flipped while cot α + cot β < -FLIP_TOLERANCE
TOLERANCE = 1e-7  # relative residual of the conjugate gradient solves
MAX_ITERATIONS = 3000
MAX_BLOCK = 8
LEVELS = (10, 100, 1e3, 1e4)  # coupling levels t w / min(M_pp, M_qq) counted
START = time.process_time()


def progress(message):
    print(f"[{time.process_time() - START:6.1f} s] {message}", file=sys.stderr, flush=True)


def read_triangles(path):
    """Vertices (n, 3) float64 and triangles (m, 3) int64 of a PLY file, ASCII or binary,
    read as tools/refine_mesh.py reads it (keeping the file's coordinates in double
    precision); on a file it does not read the script stops with a message naming it."""
    try:
        vertices, faces = read_ply(path, coordinates=np.float64)
    except (OSError, ValueError, KeyError, Unsupported) as error:
        sys.exit(f"{path}: not a triangle mesh this script reads ({error})")
    if vertices is None or faces is None:
        sys.exit(f"{path}: no vertex or no face element")
    return vertices, faces


def repair(vertices, faces):
    """Weld vertices at identical positions, drop faces with a repeated vertex or zero
    area and the vertices left unused; also returns how many were welded and dropped."""
    unique, index = np.unique(vertices, axis=0, return_inverse=True)
    faces = index.ravel()[faces]
    a, b, c = (unique[faces[:, k]] for k in range(3))
    repeated = (faces[:, 0] == faces[:, 1]) | (faces[:, 1] == faces[:, 2]) | (faces[:, 2] == faces[:, 0])
    bad = repeated | (np.linalg.norm(np.cross(b - a, c - a), axis=1) == 0)
    used, faces = np.unique(faces[~bad], return_inverse=True)
    return unique[used], faces.reshape(-1, 3), len(vertices) - len(unique), int(bad.sum())


def next_half_edge(h):
    """Half-edge 3f + k runs from corner k of face f to corner k + 1 (ints or arrays)."""
    return h - h % 3 + (h + 1) % 3


def previous_half_edge(h):
    """The half-edge before h in its face."""
    return h - h % 3 + (h + 2) % 3


def half_edges(vertices, faces):
    """Origins, twins (-1 unless the edge has exactly two opposite half-edges), lengths,
    and the counts of edges, boundary edges, non-manifold and inconsistently oriented ones."""
    origin = faces.reshape(-1)
    target = origin[next_half_edge(np.arange(len(origin)))]
    length = np.linalg.norm(vertices[target] - vertices[origin], axis=1)
    key = np.minimum(origin, target) * len(vertices) + np.maximum(origin, target)
    order = np.argsort(key, kind="stable")
    key = key[order]
    first = np.nonzero(np.r_[True, key[1:] != key[:-1]])[0]
    size = np.diff(np.r_[first, len(key)])
    h1, h2 = order[first[size == 2]], order[first[size == 2] + 1]
    opposite = origin[h1] == target[h2]
    twin = np.full(len(origin), -1)
    twin[h1[opposite]], twin[h2[opposite]] = h2[opposite], h1[opposite]
    counts = dict(edges=len(first), boundary=int((size == 1).sum()),
                  non_manifold=int((size > 2).sum()), misoriented=int((~opposite).sum()))
    return origin, twin, length, counts


def heron_product(a, b, c):
    """16 area² of a triangle with sides a >= b >= c, in Kahan's stable arrangement."""
    return (a + (b + c)) * (c - (a - b)) * (c + (a - b)) * (a + (b - c))


def cotangents(length):
    """The cotangent of the angle opposite every half-edge and the area of every face."""
    sides = length.reshape(-1, 3)
    area = 0.25 * np.sqrt(np.maximum(heron_product(*np.sort(sides, axis=1)[:, ::-1].T), 0.0))
    a, b, c = sides, sides[:, [1, 2, 0]], sides[:, [2, 0, 1]]
    with np.errstate(divide="ignore", invalid="ignore"):
        return ((b * b + c * c - a * a) / (4.0 * area[:, None])).reshape(-1), area


def non_delaunay(twin, length):
    """One half-edge (the lower) of every interior edge with cot α + cot β < -FLIP_TOLERANCE."""
    cot, _ = cotangents(length)
    h = np.nonzero(twin > np.arange(len(twin)))[0]
    return h[cot[h] + cot[twin[h]] < -FLIP_TOLERANCE]


def flip_to_delaunay(origin, twin, length):
    """Flip edges of the intrinsic triangulation until it is Delaunay.

    Edge ab of triangles abc and bad becomes cd, its length measured with both triangles
    unfolded into the plane. The non-Delaunay edges are queued in order; a flip queues
    the four outer edges of its quadrilateral again. Flips that would make a degenerate
    triangle are skipped. Returns the new (origin, twin, length), the flips and the
    skipped flips."""
    queue = deque(non_delaunay(twin, length).tolist())
    origin, twin, length = origin.tolist(), twin.tolist(), length.tolist()
    queued = bytearray(len(origin))
    for h in queue:
        queued[h] = 1

    def area(a, b, c):
        product = heron_product(*sorted((a, b, c), reverse=True))
        return 0.25 * math.sqrt(product) if product > 0 else 0.0

    def cot(h):
        a, b, c = length[h], length[next_half_edge(h)], length[previous_half_edge(h)]
        face_area = area(a, b, c)
        return (b * b + c * c - a * a) / (4.0 * face_area) if face_area > 0 else math.nan

    flips = skipped = 0
    while queue:
        h = queue.popleft()
        queued[h] = 0
        t = twin[h]
        if t < 0 or t // 3 == h // 3 or not cot(h) + cot(t) < -FLIP_TOLERANCE:
            continue
        h1, h2, t1, t2 = next_half_edge(h), previous_half_edge(h), next_half_edge(t), previous_half_edge(t)
        a, b, c, d = origin[h], origin[h1], origin[h2], origin[t2]
        ab, bc, ca, ad, db = length[h], length[h1], length[h2], length[t1], length[t2]
        # a at the origin, b on the positive x axis, c above it and d below.
        cx = (ab * ab + ca * ca - bc * bc) / (2 * ab)
        cy = math.sqrt(max(ca * ca - cx * cx, 0.0))
        dx = (ab * ab + ad * ad - db * db) / (2 * ab)
        dy = -math.sqrt(max(ad * ad - dx * dx, 0.0))
        cd = math.hypot(cx - dx, cy - dy)
        if not (area(cd, ca, ad) > 0.0 and area(cd, db, bc) > 0.0):
            skipped += 1
            continue
        # Face of h becomes (d, c, a), face of t (c, d, b); the outer edges ca, ad, db, bc move.
        f, g = h - h % 3, t - t % 3
        old, new = (h2, t1, t2, h1), (f + 1, f + 2, g + 1, g + 2)
        moved = dict(zip(old, new))
        outer = [(twin[x], length[x]) for x in old]
        origin[f:f + 3], origin[g:g + 3] = (d, c, a), (c, d, b)
        length[f] = length[g] = cd
        twin[f], twin[g] = g, f
        for y, (other, outer_length) in zip(new, outer):
            length[y] = outer_length
            twin[y] = moved.get(other, other)
            if other >= 0 and other not in moved:
                twin[other] = y
        flips += 1
        if flips > 50 * len(origin):
            raise RuntimeError("no Delaunay triangulation after 50 flips per half-edge")
        for y in new:
            if not queued[y] and twin[y] >= 0:
                queued[y] = 1
                queue.append(y)
    return (np.array(origin), np.array(twin), np.array(length)), flips, skipped


def laplacian_edges(origin, twin, length):
    """Edges (p, q) with their clamped cotan weights and lengths, and the faces' areas.

    Twin half-edges make one edge; the others (boundary, non-manifold, misoriented) are
    summed by vertex pair. Self-loops of the intrinsic triangulation add nothing to K."""
    cot, area = cotangents(length)
    half = np.where(np.isnan(cot), 0.0, 0.5 * cot)
    h = np.arange(len(origin))
    target = origin[next_half_edge(h)]
    paired, single = np.nonzero(twin > h)[0], np.nonzero(twin < 0)[0]
    n = int(origin.max()) + 1
    keys, first, group = np.unique(np.minimum(origin[single], target[single]) * n
                                   + np.maximum(origin[single], target[single]),
                                   return_index=True, return_inverse=True)
    p, q = np.r_[origin[paired], keys // n], np.r_[target[paired], keys % n]
    w = np.r_[half[paired] + half[twin[paired]],
              np.bincount(group.ravel(), weights=half[single], minlength=len(keys))]
    w = np.clip(w, 0.0, MAX_WEIGHT)
    w[np.isnan(w)] = 0.0
    edge_length = np.r_[length[paired], length[single[first]]]
    keep = p != q
    return p[keep], q[keep], w[keep], edge_length[keep], area


def masses(origin, area, count, t):
    """Lumped masses, a third of the area of every face at each corner, at least 10⁻⁶ t."""
    corners = origin.reshape(-1, 3)
    mass = sum(np.bincount(corners[:, k], weights=area / 3, minlength=count) for k in range(3))
    return np.maximum(mass, MIN_MASS_FRACTION * t)


def system_matrix(p, q, w, mass, t):
    """A = M + tK as a CSR matrix."""
    n = len(mass)
    K = sp.coo_matrix((np.r_[-w, -w], (np.r_[p, q], np.r_[q, p])), shape=(n, n)).tocsr()
    degree = np.bincount(p, weights=w, minlength=n) + np.bincount(q, weights=w, minlength=n)
    A = (sp.diags(mass + t * degree) + t * K).tocsr()
    A.sum_duplicates()
    A.eliminate_zeros()
    A.sort_indices()
    return A


def coupling_cells(p, q, w, edge_length, mass, t, hbar):
    """Table cells: the edges with t w / min(M_pp, M_qq) above each of LEVELS, the
    largest ratio, and lengths over h̄: median and share below 0.1 of the edges above
    100, those of the five strongest."""
    ratio = t * w / np.minimum(mass[p], mass[q])
    relative = edge_length / hbar
    stiff = relative[ratio > 100] if np.any(ratio > 100) else np.array([math.nan])
    return ([f"{np.count_nonzero(ratio > level):,}" for level in LEVELS]
            + [f"{ratio.max():.3g}", f"{np.median(stiff):.3g}", f"{np.mean(stiff < 0.1):.0%}",
               ", ".join(f"{x:.2g}" for x in relative[np.argsort(-ratio)[:5]])])


def jacobi(A):
    """r ↦ D⁻¹ r, D the diagonal of A."""
    inverse = 1.0 / A.diagonal()
    return lambda r: inverse * r


def strong_groups(A, threshold):
    """The group of every unknown: unknowns joined by couplings |A_pq| >= threshold
    √(A_pp A_qq) are merged, strongest coupling first, while groups keep at most
    MAX_BLOCK members (union–find by size)."""
    diagonal = A.diagonal()
    upper = sp.triu(A, 1).tocoo()
    strength = np.abs(upper.data) / np.sqrt(diagonal[upper.row] * diagonal[upper.col])
    strong = strength >= threshold
    rows, cols = upper.row[strong].tolist(), upper.col[strong].tolist()
    parent, size = list(range(A.shape[0])), [1] * A.shape[0]

    def root(x):
        while parent[x] != x:
            parent[x] = parent[parent[x]]
            x = parent[x]
        return x

    for k in np.argsort(-strength[strong]).tolist():
        a, b = root(rows[k]), root(cols[k])
        if a == b or size[a] + size[b] > MAX_BLOCK:
            continue
        if size[a] < size[b]:
            a, b = b, a
        parent[b] = a
        size[a] += size[b]
    return np.unique([root(x) for x in range(A.shape[0])], return_inverse=True)[1].ravel()


def block_jacobi(A, threshold):
    """r ↦ B⁻¹ r, B the diagonal blocks of A on the strong groups, inverted exactly."""
    group = strong_groups(A, threshold)
    sizes = np.bincount(group)
    order = np.argsort(group, kind="stable")  # the groups' members, one group after another
    rows, cols, values = [], [], []
    for size in np.unique(sizes).tolist():
        members = order[sizes[group[order]] == size].reshape(-1, size)
        rows.append(np.repeat(members, size, axis=1).ravel())
        cols.append(np.tile(members, (1, size)).ravel())
        blocks = np.asarray(A[rows[-1], cols[-1]]).reshape(-1, size, size)
        values.append(np.linalg.inv(blocks).ravel())
    inverse = sp.coo_matrix((np.concatenate(values), (np.concatenate(rows), np.concatenate(cols))),
                            shape=A.shape).tocsr()
    return lambda r: inverse @ r


def cg_iterations(A, b, precondition):
    """Preconditioned conjugate gradient iterations from x = 0 until |r| <= TOLERANCE |b|,
    None when MAX_ITERATIONS do not reach it (x itself is not needed for the count)."""
    goal = TOLERANCE * np.linalg.norm(b)
    r = b.copy()
    z = precondition(r)
    p, rz = z.copy(), r @ z
    for iteration in range(1, MAX_ITERATIONS + 1):
        Ap = A @ p
        alpha = rz / (p @ Ap)
        r -= alpha * Ap
        if np.linalg.norm(r) <= goal:
            return iteration
        z = precondition(r)
        rz, previous = r @ z, rz
        p = z + (rz / previous) * p
    return None


PRECONDITIONERS = (("Jacobi", jacobi), ("block θ=0.5", partial(block_jacobi, threshold=0.5)),
                   ("block θ=0.1", partial(block_jacobi, threshold=0.1)))


def print_table(header, rows):
    """A Markdown table, the first two columns aligned left and the others right."""
    print("| " + " | ".join(header) + " |")
    print("|---|---|" + "--:|" * (len(header) - 2))
    for row in rows:
        print("| " + " | ".join(row) + " |")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("mesh", help="triangle mesh, PLY (ASCII or binary)")
    parser.add_argument("--tau", type=float, nargs="+", default=[2.0, 0.25],
                        help="time steps t = τ h̄² (default: 2 0.25)")
    args = parser.parse_args()
    if not os.path.isfile(args.mesh):
        parser.error(f"no such file: {args.mesh}")

    vertices, faces = read_triangles(args.mesh)
    vertices, faces, welded, dropped = repair(vertices, faces)
    origin, twin, length, counts = half_edges(vertices, faces)
    before = len(non_delaunay(twin, length))
    progress(f"{len(vertices):,} vertices, {len(faces):,} faces, {counts['edges']:,} edges "
             f"({counts['boundary']:,} boundary, {counts['non_manifold']:,} non-manifold, "
             f"{counts['misoriented']:,} misoriented), {before:,} not Delaunay")
    intrinsic, flips, skipped = flip_to_delaunay(origin, twin, length)
    after = len(non_delaunay(*intrinsic[1:]))
    progress(f"{flips:,} flips ({skipped} skipped as degenerate), {after} edges not Delaunay")
    triangulations = {"input": (origin, twin, length), "intrinsic Delaunay": intrinsic}
    edges = {name: laplacian_edges(*triangulation) for name, triangulation in triangulations.items()}
    hbar = edges["input"][3].mean()
    draw = np.random.default_rng(1).uniform(-1, 1, len(vertices))

    coupling_rows, iteration_rows = [], []
    for tau in args.tau:
        t = tau * hbar ** 2
        for name, (p, q, w, edge_length, area) in edges.items():
            mass = masses(triangulations[name][0], area, len(vertices), t)
            A = system_matrix(p, q, w, mass, t)
            coupling_rows.append([f"{tau:g}", name,
                                  *coupling_cells(p, q, w, edge_length, mass, t, hbar)])
            iteration_rows.append([f"{tau:g}", name])
            for label, preconditioner in PRECONDITIONERS:
                precondition = preconditioner(A)
                both = [cg_iterations(A, b, precondition) for b in (mass * draw, mass * vertices[:, 0])]
                progress(f"τ = {tau:g}, {name}, {label}: {both} iterations")
                iteration_rows[-1].append(" / ".join("—" if n is None else str(n) for n in both))

    print(f"{os.path.basename(args.mesh)}: {len(vertices):,} vertices ({welded:,} welded), "
          f"{len(faces):,} triangles ({dropped:,} dropped), h̄ = {hbar:.4g}; {before:,} edges "
          f"not Delaunay, {after} after {flips:,} intrinsic flips.\n")
    print_table(["τ", "Laplacian", "t w / min M > 10", "> 100", "> 10³", "> 10⁴", "largest",
                 "> 100: median ℓ/h̄", "ℓ < 0.1 h̄", "ℓ/h̄ of the 5 strongest"], coupling_rows)
    print(f"\nConjugate gradient iterations to a relative residual of {TOLERANCE:g} "
          f"(— : not within {MAX_ITERATIONS}), right-hand sides random / smooth:\n")
    print_table(["τ", "Laplacian", *(label for label, _ in PRECONDITIONERS)], iteration_rows)


if __name__ == "__main__":
    main()

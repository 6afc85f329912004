//! Implicit smoothing: of the extremalities with the sign-aware cotan Laplacian
//! (Hildebrandt, Polthier, Wardetzky 2005, §5.1) and of the surface itself (step 1
//! of their Table 1, implicit fairing after Desbrun et al. 1999).

use std::sync::Arc;

use crate::linalg::{
    CgSettings, CholeskyAnalysis, Lanes, Pair, Solver, SpdSolver, SymmetricMatrix,
};
use rayon::prelude::*;

use crate::mesh::{EdgeId, Mesh, VertexId};
use crate::progress::{Observer, Silent};
use crate::{Error, Result};

#[cfg(test)]
use crate::lines::DirectionField;
use crate::lines::EdgeSigns;
use crate::mesh::morton::{morton_order, ranks};

/// The smallest lumped mass, as a fraction of the time step t (an area, like the
/// masses).
///
/// The weights are at most [`MAX_COTAN_WEIGHT`](crate::mesh::geometry::MAX_COTAN_WEIGHT),
/// so the diagonal of t K is at most about 10⁴ t · valence; with every mass at
/// least 10⁻⁶ t the condition number of M + t K stays below about 10¹⁰ · valence,
/// where a Cholesky factorization in f64 still succeeds, even where triangles
/// have collapsed to zero area (a surface smoothed many steps shrinks). On a
/// sound mesh masses are near h̄² and the floor never applies.
const MIN_MASS_FRACTION: f64 = 1e-6;

/// The lumped masses area(star(v)) / 3, at least [`MIN_MASS_FRACTION`] · `time`
/// (NaN masses included), so that M + t K stays positive definite.
fn bounded_masses(mesh: &Mesh, time: f64) -> Vec<f64> {
    let floor = (MIN_MASS_FRACTION * time).max(f64::MIN_POSITIVE);
    let mut mass = mesh.vertex_areas();
    for m in &mut mass {
        if m.is_nan() || *m < floor {
            *m = floor;
        }
    }
    mass
}

/// The iteration's stopping rule for the extremality systems: a relative
/// residual of 10⁻⁷, looser than the default (10⁻¹⁰, which the surface smoothing
/// keeps: its errors move vertices, and the curvature amplifies them). Measured
/// against the factorization's lines (`ridges --solver direct` against the
/// default, which iterates from 2M vertices on): the dragon ×4 774 and 774
/// lines, every point within 6.6 · 10⁻⁶ of the bounding box diagonal; the dragon
/// ×16 1030 and 1030, within 3.3 · 10⁻⁵, for about a tenth less time than
/// 10⁻⁸ (smoothing 90 → 81 s). 10⁻⁶ is too loose: the dragon ×16 loses 4 lines
/// and some points move 1.2 · 10⁻⁴ of the diagonal.
const EXTREMALITY_SETTINGS: CgSettings = CgSettings {
    tolerance: 1e-7,
    max_iterations: CgSettings::DEFAULT_MAX_ITERATIONS,
};

/// The time step τ (in units of h̄²) up to which [`Solver::Auto`] solves the
/// extremality systems by iteration at any mesh size. A short step makes M + t K
/// strongly diagonally dominant: the conjugate gradient converges in a few
/// iterations, while the Cholesky factor's fill decays towards subnormal numbers
/// and costs as much as ever. Measured with the one step of τ = 0.25 of an image's
/// extremalities (`ridges <image> --level 60 --report`): the MNI template's
/// isosurface (225k vertices) 0.78 s direct, 0.65 s iterative (563 and 235 MB
/// peak); upsampled ×2 (900k vertices) 15.2 s direct, 3.3 s iterative (2.6 and
/// 0.98 GB), the same lines.
const SHORT_TIME: f64 = 0.5;

/// Where the entries of M + t K sit in a compressed column matrix over a mesh:
/// the column of vertex v holds its own row and the rows of v's edge neighbours,
/// increasing. The pattern depends on the connectivity alone, so it is made once
/// and every system on the mesh (both extremality fields, every surface smoothing
/// step) only writes its values.
///
/// The unknowns are the vertices in the mesh's order, or (for systems solved by
/// iteration) in the Morton order of their positions ([`morton_order`]): each
/// step of the iteration then reads its vectors mostly from nearby memory, which
/// on a refined scan whose neighbours lie far apart in the vertex list makes the
/// smoothing about a quarter faster (dragon ×4, `examples/bench_smoothing.rs`,
/// with one sweep per side of the V-cycle: 41 s in the mesh's order, 29 s in
/// Morton order). The interface speaks of vertices either way;
/// [`to_unknowns`](Self::to_unknowns) and [`to_vertices`](Self::to_vertices)
/// reorder vectors.
#[derive(Clone, Debug)]
struct SystemPattern {
    col_ptr: Arc<[usize]>,
    row_idx: Arc<[u32]>,
    /// The slot of entry (v, v).
    diagonal: Vec<usize>,
    /// The vertices (p, q) of every edge (32 bits wide, as the mesh's ids).
    ends: Vec<[u32; 2]>,
    /// The slots of entries (p, q) and (q, p) of every edge (32 bits wide: a mesh
    /// with 2³² stored entries would have over 600 million vertices).
    edges: Vec<[u32; 2]>,
    /// The vertex of each unknown, when they are not in the mesh's order.
    order: Option<Vec<u32>>,
}

impl SystemPattern {
    /// The pattern of the mesh's systems as `solver` solves them: the unknowns in
    /// Morton order if it iterates on a mesh of this size. Built in parallel, a
    /// column per unknown from its vertex's one-ring, then every edge's two slots
    /// looked up in the sorted columns: on the dragon ×16 (7M vertices), while
    /// the curvature is estimated beside it, 2.9 s instead of 4.6 s sequentially
    /// by scattering the edges into columns.
    fn new(mesh: &Mesh, solver: Solver) -> SystemPattern {
        let n = mesh.vertex_count();
        let iterates = solver.resolve(n) == Solver::Iterative;
        let order = iterates.then(|| morton_order(mesh.positions()));
        // The unknown of each vertex, where they are reordered.
        let ranks: Option<Vec<u32>> = order.as_deref().map(ranks);
        let rank = |v: usize| ranks.as_ref().map_or(v as u32, |ranks| ranks[v]);
        let vertex = |c: usize| order.as_ref().map_or(c, |order| order[c] as usize);
        // Column c: the unknowns of vertex(c) and of its neighbours, increasing and
        // each once (edges between the same two vertices, left by repairs of
        // non-manifold scans, share their entry, where their weights add up).
        let (col_ptr, row_idx) = columns(n, |c, rows| {
            let v = VertexId(vertex(c) as u32);
            rows.push(c as u32);
            rows.extend(mesh.neighbors(v).map(|w| rank(w.idx())));
            rows.sort_unstable();
            rows.dedup();
        });
        let slot = |row: u32, column: u32| {
            let range = col_ptr[column as usize]..col_ptr[column as usize + 1];
            let k = row_idx[range.clone()]
                .binary_search(&row)
                .expect("every edge's entries are in its columns");
            range.start + k
        };
        let diagonal: Vec<usize> = (0..n)
            .into_par_iter()
            .map(|v| {
                let c = rank(v);
                slot(c, c)
            })
            .collect();
        let ends: Vec<[u32; 2]> = (0..mesh.edge_count() as u32)
            .into_par_iter()
            .map(|e| mesh.edge_vertices(EdgeId(e)).map(|v| v.0))
            .collect();
        // Slot 0 in p's column, slot 1 in q's.
        let edges: Vec<[u32; 2]> = ends
            .par_iter()
            .map(|&[p, q]| {
                let (p, q) = (rank(p as usize), rank(q as usize));
                [slot(q, p) as u32, slot(p, q) as u32]
            })
            .collect();
        SystemPattern {
            col_ptr: col_ptr.into(),
            row_idx: row_idx.into(),
            diagonal,
            ends,
            edges,
            order,
        }
    }

    /// The vertex of unknown `i`.
    fn vertex(&self, i: usize) -> usize {
        self.order.as_ref().map_or(i, |order| order[i] as usize)
    }

    /// `fields` (one value per vertex each) in the order of the unknowns,
    /// interleaved ([`Lanes`]: as many fields as lanes).
    fn to_unknowns<V: Lanes>(&self, fields: &[&[f64]]) -> Vec<V> {
        (0..self.diagonal.len())
            .map(|i| {
                let v = self.vertex(i);
                let mut x = V::default();
                for (k, field) in fields.iter().enumerate() {
                    x.set_lane(k, field[v]);
                }
                x
            })
            .collect()
    }

    /// `unknowns` (in their order, interleaved) written to `fields`, one value
    /// per vertex each.
    fn to_vertices<V: Lanes>(&self, unknowns: &[V], fields: &mut [&mut [f64]]) {
        for (i, x) in unknowns.iter().enumerate() {
            let v = self.vertex(i);
            for (k, field) in fields.iter_mut().enumerate() {
                field[v] = x.lane(k);
            }
        }
    }

    /// The matrix with `mass` (per vertex) on the diagonal plus, for every edge
    /// e = (p, q) with weight w = `weights[e]` and sign σ = `sign(e)`, K_pp += w,
    /// K_qq += w and K_pq += −σ w, K_qp += −σ w (summed in edge order), over the
    /// unknowns.
    fn matrix(
        &self,
        mass: &[f64],
        weights: &[f64],
        sign: impl Fn(EdgeId) -> f64,
    ) -> Result<SymmetricMatrix> {
        let mut values = vec![0.0; self.row_idx.len()];
        for (&slot, &m) in self.diagonal.iter().zip(mass) {
            values[slot] = m;
        }
        for (e, ((&w, slots), &[p, q])) in
            weights.iter().zip(&self.edges).zip(&self.ends).enumerate()
        {
            let (p, q) = (p as usize, q as usize);
            values[self.diagonal[p]] += w;
            values[self.diagonal[q]] += w;
            let off = -w * sign(EdgeId(e as u32));
            values[slots[0] as usize] += off;
            values[slots[1] as usize] += off;
        }
        SymmetricMatrix::from_csc(
            self.diagonal.len(),
            self.col_ptr.clone(),
            self.row_idx.clone(),
            values,
        )
    }
}

/// Compressed columns (offsets and row indices) of `n` columns, each written by
/// `fill(c, rows)` into an empty buffer, in parallel over blocks of columns.
fn columns(n: usize, fill: impl Fn(usize, &mut Vec<u32>) + Sync) -> (Vec<usize>, Vec<u32>) {
    const BLOCK: usize = 16_384;
    let blocks: Vec<(Vec<usize>, Vec<u32>)> = (0..n.div_ceil(BLOCK))
        .into_par_iter()
        .map_init(Vec::new, |rows, b| {
            let (mut lengths, mut block_rows) = (Vec::new(), Vec::new());
            for c in b * BLOCK..((b + 1) * BLOCK).min(n) {
                rows.clear();
                fill(c, rows);
                lengths.push(rows.len());
                block_rows.extend_from_slice(rows);
            }
            (lengths, block_rows)
        })
        .collect();
    let mut col_ptr = Vec::with_capacity(n + 1);
    col_ptr.push(0);
    let mut row_idx = Vec::with_capacity(blocks.iter().map(|b| b.1.len()).sum());
    for (lengths, block_rows) in blocks {
        for length in lengths {
            col_ptr.push(col_ptr[col_ptr.len() - 1] + length);
        }
        row_idx.extend(block_rows);
    }
    (col_ptr, row_idx)
}

/// The time-scaled edge weights t c w of M + t K for the cotan Laplacian with
/// clamped weights ([`Mesh::clamped_cotan_weight`]), with `scale(p, q)` = c ≥ 0,
/// and the masses bounded below ([`bounded_masses`]). With every c ≥ 0 and any
/// signs σ, xᵀKx = Σ c w (x_p − σ x_q)² ≥ 0, so with M > 0 the matrix is
/// symmetric positive definite on every mesh, boundary and obtuse triangles
/// included.
fn implicit_terms(
    mesh: &Mesh,
    time: f64,
    scale: impl Fn(usize, usize) -> f64 + Sync,
) -> (Vec<f64>, Vec<f64>) {
    let weights = mesh
        .clamped_cotan_weights()
        .into_par_iter()
        .enumerate()
        .map(|(e, w)| {
            let [p, q] = mesh.edge_vertices(EdgeId(e as u32)).map(|v| v.idx());
            // Zero weights are stored too, so the pattern is the mesh's edges.
            time * scale(p, q) * w
        })
        .collect();
    (weights, bounded_masses(mesh, time))
}

/// `steps` implicit steps (M + tK) e' = M e of the extremality `e`, with the
/// sign-aware Laplacian (Δe)(p) = Σ_q w_pq (σ_pq e(q) − e(p)) (§5.1), σ_pq the
/// sign between the directions `d` at p and q, the one transported into the
/// other's tangent plane ([`DirectionField::sign`]): the result does not depend
/// on the arbitrary signs of the directions. `t = tau · h̄²` (h̄ the mean edge length), so `tau` is
/// dimensionless. Optional per-vertex `weights` (≥ 0) make the smoothing
/// inhomogeneous (§6): edge (p, q) is scaled by (w_p + w_q) / 2. The matrix is
/// the same for every step: one sparse Cholesky factorization serves them all,
/// or on large meshes each step is a conjugate gradient solve warm-started from
/// the previous step ([`Solver::Auto`]).
#[cfg(test)]
pub fn smooth_extremality(
    mesh: &Mesh,
    d: DirectionField,
    e: &mut [f64],
    steps: usize,
    tau: f64,
    weights: Option<&[f64]>,
) -> Result<()> {
    let signs = EdgeSigns::new(mesh, d);
    ExtremalitySmoother::new(mesh, tau, weights, Solver::Auto)?.smooth(
        &signs,
        &mut [e],
        steps,
        &mut Silent,
    )
}

/// `smooth_extremality` for several fields of one mesh: the matrices differ only
/// in the signs σ_pq, so they share their pattern, weights and masses (computed
/// once, when the smoother is made) and a direct solver's ordering and symbolic
/// analysis (computed once, [`analyzed`](Self::analyzed)). Fields whose signs
/// are the same (up to a per-vertex sign, as the two principal directions',
/// [`crate::lines::direction_field::gauge_between`]) share one matrix too:
/// [`smooth`](Self::smooth) them together.
#[derive(Clone)]
pub struct ExtremalitySmoother {
    pattern: SystemPattern,
    /// The time step τ, in units of h̄².
    tau: f64,
    /// The per-vertex weights the smoother was made with.
    vertex_weights: Option<Vec<f64>>,
    /// t c w per edge.
    weights: Vec<f64>,
    mass: Vec<f64>,
    solver: SpdSolver,
}

impl ExtremalitySmoother {
    /// A smoother with time step `tau` (in units of h̄²) and optional per-vertex
    /// weights, whose systems are solved as `solver` says.
    pub fn new(mesh: &Mesh, tau: f64, weights: Option<&[f64]>, solver: Solver) -> Result<Self> {
        check_weights(mesh, weights)?;
        let vertex_weights = weights;
        let h = mesh.mean_edge_length();
        let (weights, mass) = implicit_terms(mesh, tau * h * h, |p, q| {
            weights.map_or(1.0, |w| 0.5 * (w[p] + w[q]))
        });
        let solver = for_time_step(solver, tau);
        Ok(ExtremalitySmoother {
            pattern: SystemPattern::new(mesh, solver),
            tau,
            vertex_weights: vertex_weights.map(<[f64]>::to_vec),
            weights,
            mass,
            solver: SpdSolver::new(solver, EXTREMALITY_SETTINGS),
        })
    }

    /// The smoother with its systems' ordering and symbolic analysis made now
    /// ([`SpdSolver::analyze`]) rather than by every field's smoothing, or taken
    /// from `known`, an analysis of the same mesh's systems (the surface
    /// smoothing's, [`presmooth_analyzed`]).
    pub fn analyzed(mut self, known: Option<CholeskyAnalysis>) -> Result<Self> {
        if self.iterates() {
            return Ok(self);
        }
        if let Some(analysis) = known {
            self.solver.reuse_analysis(analysis);
            return Ok(self);
        }
        // The signs change neither the pattern nor what Auto chooses (it looks at
        // magnitudes): analyse the system with every σ = +1.
        let unsigned = self.system(|_| 1.0)?;
        self.solver.analyze(&unsigned)?;
        Ok(self)
    }

    /// The smoother of the same mesh (`mesh`, the one it was made for) with its
    /// per-vertex weights multiplied by `factors` (≥ 0), keeping its solver and
    /// any analysis made: the pattern is the same.
    pub fn reweighted(&self, mesh: &Mesh, factors: &[f64]) -> Result<Self> {
        check_weights(mesh, Some(factors))?;
        let combined: Vec<f64> = match &self.vertex_weights {
            Some(w) => w.iter().zip(factors).map(|(w, f)| w * f).collect(),
            None => factors.to_vec(),
        };
        let h = mesh.mean_edge_length();
        let (weights, mass) = implicit_terms(mesh, self.tau * h * h, |p, q| {
            0.5 * (combined[p] + combined[q])
        });
        Ok(ExtremalitySmoother {
            weights,
            mass,
            vertex_weights: Some(combined),
            ..self.clone()
        })
    }

    /// M + t K with the signs `sigma(e)` of the edges.
    fn system(&self, sigma: impl Fn(EdgeId) -> f64) -> Result<SymmetricMatrix> {
        self.pattern.matrix(&self.mass, &self.weights, sigma)
    }

    /// Whether its systems are solved by iteration ([`Solver::Iterative`], which
    /// runs in parallel within each system), not by factorization.
    pub fn iterates(&self) -> bool {
        self.solver.solver().resolve(self.mass.len()) == Solver::Iterative
    }

    /// Smooth each of `fields` (values per vertex whose signs follow directions
    /// whose edges' signs are `signs`) by `steps` implicit steps, with one system
    /// for all: one factorization, or one multigrid hierarchy. Asks `observer`
    /// before every step and every iteration whether to go on
    /// ([`Error::Cancelled`] if not).
    pub fn smooth(
        &self,
        signs: &EdgeSigns,
        fields: &mut [&mut [f64]],
        steps: usize,
        observer: &mut dyn Observer,
    ) -> Result<()> {
        if steps == 0 || fields.is_empty() {
            return Ok(());
        }
        let mut solver = self.solver.clone();
        solver.set_matrix(self.system(|e| signs.sign(e))?)?;
        let mass = self.pattern.to_unknowns::<f64>(&[&self.mass]);
        match fields {
            // Two fields in lockstep: every pass over the matrix serves both.
            [a, b] => self.run_steps::<Pair>(&mut solver, &mass, &mut [a, b], steps, observer),
            // More fields: two at a time, the last alone if their number is odd.
            _ => fields
                .chunks_mut(2)
                .try_for_each(|chunk| match chunk.len() {
                    2 => self.run_steps::<Pair>(&mut solver, &mass, chunk, steps, observer),
                    _ => self.run_steps::<f64>(&mut solver, &mass, chunk, steps, observer),
                }),
        }
    }

    /// `steps` implicit steps of the `fields` (as many as `V` has lanes) with the
    /// system `solver` holds, whose masses are `mass` (in the unknowns' order),
    /// asking `observer` whether to go on.
    fn run_steps<V: Lanes>(
        &self,
        solver: &mut SpdSolver,
        mass: &[f64],
        fields: &mut [&mut [f64]],
        steps: usize,
        observer: &mut dyn Observer,
    ) -> Result<()> {
        let values: Vec<&[f64]> = fields.iter().map(|e| &e[..]).collect();
        let mut x = self.pattern.to_unknowns::<V>(&values);
        let mut rhs = vec![V::default(); x.len()];
        for step in 0..steps {
            observer.progress(step, steps);
            mass_times(mass, &x, &mut rhs);
            // x holds the previous step's solution: the iteration's warm start.
            solver.solve(&rhs, &mut x, observer)?;
        }
        observer.progress(steps, steps);
        self.pattern.to_vertices(&x, fields);
        Ok(())
    }
}

/// `solver`, with [`Solver::Auto`] made [`Solver::Iterative`] for a time step
/// `tau` of at most [`SHORT_TIME`].
fn for_time_step(solver: Solver, tau: f64) -> Solver {
    match solver {
        Solver::Auto if tau <= SHORT_TIME => Solver::Iterative,
        chosen => chosen,
    }
}

/// `out = M x` for the lumped (diagonal) mass matrix M.
fn mass_times<V: Lanes>(mass: &[f64], x: &[V], out: &mut [V]) {
    for ((o, &x), &m) in out.iter_mut().zip(x).zip(mass) {
        *o = x * m;
    }
}

fn check_weights(mesh: &Mesh, weights: Option<&[f64]>) -> Result<()> {
    let Some(w) = weights else { return Ok(()) };
    if w.len() != mesh.vertex_count() {
        return Err(Error::Argument(format!(
            "{} smoothing weights for a mesh with {} vertices",
            w.len(),
            mesh.vertex_count()
        )));
    }
    match w.iter().position(|x| !x.is_finite() || *x < 0.0) {
        Some(i) => Err(Error::Argument(format!(
            "smoothing weight of vertex {i} is {}; weights must be finite and ≥ 0",
            w[i]
        ))),
        None => Ok(()),
    }
}

/// `steps` implicit cotan smoothing steps of the vertex positions,
/// (M + tL) x' = M x with t = h̄² (h̄ the mean edge length of the input, so t has
/// the units of M / L: length²); weights and masses are recomputed from the
/// current positions at every step, weights clamped and masses bounded below
/// ([`Mesh::clamped_cotan_weight`]; masses at least 10⁻⁶ t), so every step's
/// system is positive definite, with boundary or obtuse triangles. Works in the
/// unit frame ([`Mesh::in_unit_frame`]) at any coordinate scale. Returns the
/// smoothed mesh; connectivity is unchanged. The systems are solved as
/// [`Solver::Auto`] chooses.
pub fn presmooth_surface(mesh: &Mesh, steps: usize) -> Result<Mesh> {
    presmooth_surface_with(mesh, steps, 1.0, Solver::Auto, &mut Silent)
}

/// [`presmooth_surface`] with steps of time `tau` h̄² (rather than h̄²), the
/// systems solved by `solver`, asking `observer` before every solve and
/// iteration whether to go on ([`Error::Cancelled`] if not).
pub fn presmooth_surface_with(
    mesh: &Mesh,
    steps: usize,
    tau: f64,
    solver: Solver,
    observer: &mut dyn Observer,
) -> Result<Mesh> {
    Ok(presmooth_analyzed(mesh, steps, tau, solver, observer)?.0)
}

/// [`presmooth_surface_with`], and the ordering and symbolic analysis of its
/// system when it was factored: the extremalities' systems on the smoothed
/// surface have the same pattern ([`ExtremalitySmoother::analyzed`]).
pub(crate) fn presmooth_analyzed(
    mesh: &Mesh,
    steps: usize,
    tau: f64,
    solver: Solver,
    observer: &mut dyn Observer,
) -> Result<(Mesh, Option<CholeskyAnalysis>)> {
    let (unit, factor) = mesh.in_unit_frame();
    let (mut smoothed, analysis) = presmooth_unit(unit.into_owned(), steps, tau, solver, observer)?;
    smoothed.scale(1.0 / factor);
    Ok((smoothed, analysis))
}

/// [`presmooth_analyzed`] of a mesh in the unit frame, in place.
fn presmooth_unit(
    mut current: Mesh,
    steps: usize,
    tau: f64,
    solver: Solver,
    observer: &mut dyn Observer,
) -> Result<(Mesh, Option<CholeskyAnalysis>)> {
    let h = current.mean_edge_length() * tau.sqrt();
    // The pattern never changes: a direct solver reuses its symbolic analysis.
    let pattern = SystemPattern::new(&current, solver);
    let mut solver = SpdSolver::new(solver, CgSettings::default());
    for step in 0..steps {
        observer.progress(step, steps);
        let (weights, mass) = implicit_terms(&current, h * h, |_, _| 1.0);
        solver.set_matrix(pattern.matrix(&mass, &weights, |_| 1.0)?)?;
        let mass = pattern.to_unknowns::<f64>(&[&mass]);
        let next = smoothed_positions(&current, &pattern, &mut solver, &mass, observer)?;
        current.set_positions(next)?;
    }
    observer.progress(steps, steps);
    Ok((current, solver.analysis().cloned()))
}

/// The positions of `current` after one step with the system `solver` holds
/// (masses `mass` in the unknowns' order): x and y solved side by side, then z,
/// each from the current coordinates (the iteration's warm start).
fn smoothed_positions(
    current: &Mesh,
    pattern: &SystemPattern,
    solver: &mut SpdSolver,
    mass: &[f64],
    observer: &mut dyn Observer,
) -> Result<Vec<crate::Point>> {
    let column =
        |axis: usize| -> Vec<f64> { current.positions().iter().map(|p| p[axis]).collect() };
    let n = current.vertex_count();
    let (mut x, mut y, mut z) = (column(0), column(1), column(2));
    let mut xy = pattern.to_unknowns::<Pair>(&[&x, &y]);
    let mut rhs = vec![Pair::default(); xy.len()];
    mass_times(mass, &xy, &mut rhs);
    solver.solve(&rhs, &mut xy, observer)?;
    let mut zs = pattern.to_unknowns::<f64>(&[&z]);
    let mut rhs = vec![0.0; zs.len()];
    mass_times(mass, &zs, &mut rhs);
    solver.solve(&rhs, &mut zs, observer)?;
    pattern.to_vertices(&xy, &mut [&mut x, &mut y]);
    pattern.to_vertices(&zs, &mut [&mut z]);
    Ok((0..n)
        .map(|k| crate::Point::new(x[k], y[k], z[k]))
        .collect())
}

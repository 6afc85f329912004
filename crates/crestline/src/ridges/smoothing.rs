//! Implicit smoothing: of the extremalities with the sign-aware cotan Laplacian
//! (Hildebrandt, Polthier, Wardetzky 2005, §5.1) and of the surface itself (step 1
//! of their Table 1, implicit fairing after Desbrun et al. 1999).

use crate::linalg::{CgSettings, Solver, SpdSolver, SymmetricBuilder, SymmetricMatrix};
use crate::mesh::{EdgeId, Mesh};
use crate::{Error, Result, Vector};

use crate::lines::zero_set::direction_sign;

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

/// M + t K for the cotan Laplacian with clamped weights
/// ([`Mesh::clamped_cotan_weight`]) and masses bounded below ([`bounded_masses`]),
/// where the edge (p, q) enters K as K_pp += c w, K_qq += c w, K_pq = −c w σ_pq
/// with `(σ_pq, c) = edge_terms(p, q)`. With every c ≥ 0,
/// xᵀKx = Σ c w (x_p − σ x_q)² ≥ 0, so with M > 0 the matrix is symmetric positive
/// definite on every mesh, boundary and obtuse triangles included. Also returns M.
fn implicit_system(
    mesh: &Mesh,
    time: f64,
    edge_terms: impl Fn(usize, usize) -> (f64, f64),
) -> (SymmetricMatrix, Vec<f64>) {
    let n = mesh.vertex_count();
    let mass = bounded_masses(mesh, time);
    let mut system = SymmetricBuilder::with_capacity(n, n + 4 * mesh.edge_count());
    for (v, &m) in mass.iter().enumerate() {
        system.add_diagonal(v, m);
    }
    for (e, w) in mesh.clamped_cotan_weights().into_iter().enumerate() {
        let [p, q] = mesh.edge_vertices(EdgeId(e as u32)).map(|v| v.idx());
        let (sigma, scale) = edge_terms(p, q);
        let weight = time * scale * w;
        // Zero weights are stored too, so the sparsity pattern is the mesh's edges.
        system.add_diagonal(p, weight);
        system.add_diagonal(q, weight);
        system.add(p, q, -weight * sigma);
    }
    (system.build(), mass)
}

/// `steps` implicit steps (M + tK) e' = M e of the extremality `e`, with the
/// sign-aware Laplacian (Δe)(p) = Σ_q w_pq (σ_pq e(q) − e(p)), σ_pq =
/// sign⟨d(p), d(q)⟩ (§5.1): the result does not depend on the arbitrary signs of
/// the directions `d`. `t = tau · h̄²` (h̄ the mean edge length), so `tau` is
/// dimensionless. Optional per-vertex `weights` (≥ 0) make the smoothing
/// inhomogeneous (§6): edge (p, q) is scaled by (w_p + w_q) / 2. The matrix is
/// the same for every step: one sparse Cholesky factorization serves them all,
/// or on large meshes each step is a conjugate gradient solve warm-started from
/// the previous step ([`Solver::Auto`]).
pub fn smooth_extremality(
    mesh: &Mesh,
    d: &[Vector],
    e: &mut [f64],
    steps: usize,
    tau: f64,
    weights: Option<&[f64]>,
) -> Result<()> {
    ExtremalitySmoother::new(mesh, tau, weights)?.smooth(d, e, steps)
}

/// [`smooth_extremality`] for several fields of one mesh: the matrices differ only
/// in the signs σ_pq, so they share their sparsity pattern and a direct solver's
/// symbolic factorization is computed once.
pub struct ExtremalitySmoother<'a> {
    mesh: &'a Mesh,
    time: f64,
    weights: Option<&'a [f64]>,
    solver: SpdSolver,
}

impl<'a> ExtremalitySmoother<'a> {
    /// A smoother with time step `tau` (in units of h̄²) and optional per-vertex weights.
    pub fn new(mesh: &'a Mesh, tau: f64, weights: Option<&'a [f64]>) -> Result<Self> {
        check_weights(mesh, weights)?;
        let h = mesh.mean_edge_length();
        Ok(ExtremalitySmoother {
            mesh,
            time: tau * h * h,
            weights,
            solver: SpdSolver::new(Solver::Auto, CgSettings::default()),
        })
    }

    /// The same smoother solving its systems with `solver`.
    pub fn with_solver(mut self, solver: Solver) -> Self {
        self.solver = SpdSolver::new(solver, CgSettings::default());
        self
    }

    /// Smooth `e`, whose signs follow the directions `d`, by `steps` implicit steps.
    pub fn smooth(&mut self, d: &[Vector], e: &mut [f64], steps: usize) -> Result<()> {
        if steps == 0 {
            return Ok(());
        }
        let weights = self.weights;
        let (system, mass) = implicit_system(self.mesh, self.time, |p, q| {
            let scale = weights.map_or(1.0, |w| 0.5 * (w[p] + w[q]));
            (direction_sign(d, p, q), scale)
        });
        self.solver.set_matrix(system)?;
        let mut rhs = vec![0.0; e.len()];
        for _ in 0..steps {
            mass_times(&mass, e, &mut rhs);
            // e holds the previous step's solution: the iteration's warm start.
            self.solver.solve(&rhs, e)?;
        }
        Ok(())
    }
}

/// `out = M x` for the lumped (diagonal) mass matrix M.
fn mass_times(mass: &[f64], x: &[f64], out: &mut [f64]) {
    for ((o, x), m) in out.iter_mut().zip(x).zip(mass) {
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
    presmooth_surface_with(mesh, steps, Solver::Auto)
}

/// [`presmooth_surface`] with the systems solved by `solver`.
pub fn presmooth_surface_with(mesh: &Mesh, steps: usize, solver: Solver) -> Result<Mesh> {
    let (unit, factor) = mesh.in_unit_frame();
    let mut smoothed = presmooth_unit(unit.into_owned(), steps, solver)?;
    smoothed.scale(1.0 / factor);
    Ok(smoothed)
}

/// [`presmooth_surface`] of a mesh in the unit frame, in place.
fn presmooth_unit(mut current: Mesh, steps: usize, solver: Solver) -> Result<Mesh> {
    let h = current.mean_edge_length();
    // The pattern never changes: a direct solver reuses its symbolic analysis.
    let mut solver = SpdSolver::new(solver, CgSettings::default());
    for _ in 0..steps {
        let (system, mass) = implicit_system(&current, h * h, |_, _| (1.0, 1.0));
        solver.set_matrix(system)?;
        let mut next = current.positions().to_vec();
        for axis in 0..3 {
            let coordinate: Vec<f64> = current.positions().iter().map(|p| p[axis]).collect();
            let mut rhs = vec![0.0; coordinate.len()];
            mass_times(&mass, &coordinate, &mut rhs);
            // The current coordinate is the iteration's warm start.
            let mut x = coordinate;
            solver.solve(&rhs, &mut x)?;
            for (p, x) in next.iter_mut().zip(x) {
                p[axis] = x;
            }
        }
        current.set_positions(next)?;
    }
    Ok(current)
}

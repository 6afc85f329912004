//! The conjugate gradient method preconditioned by a multigrid V-cycle.

use rayon::prelude::*;

use super::{Multigrid, SymmetricMatrix, CHUNK};
#[cfg(test)]
use crate::Result;

/// When the conjugate gradient iteration stops.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CgSettings {
    /// Converged when ‖b − A x‖ ≤ `tolerance` · ‖b‖ (Euclidean norms).
    pub tolerance: f64,
    /// Give up (not converged) after this many iterations.
    pub max_iterations: usize,
}

impl CgSettings {
    /// Default relative residual: the presmoothed bunny's lines then stay
    /// within 10⁻⁶ of its diagonal of the factorization's; 10⁻⁸ moves them by
    /// that much (surface smoothing solves for positions, whose errors the
    /// curvature amplifies).
    pub const DEFAULT_TOLERANCE: f64 = 1e-10;
    /// Default iteration cap; the smoothing systems converge in under a hundred
    /// iterations (23–59 on the Stanford dragon and its refinements).
    pub const DEFAULT_MAX_ITERATIONS: usize = 1000;
}

impl Default for CgSettings {
    fn default() -> Self {
        CgSettings {
            tolerance: Self::DEFAULT_TOLERANCE,
            max_iterations: Self::DEFAULT_MAX_ITERATIONS,
        }
    }
}

/// The outcome of [`conjugate_gradient`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CgReport {
    /// Iterations run.
    pub iterations: usize,
    /// The true relative residual ‖b − A x‖ / ‖b‖ of the returned `x` (recomputed,
    /// not the recurrence's estimate).
    pub relative_residual: f64,
    /// Whether it is below [`CgSettings::tolerance`].
    pub converged: bool,
}

/// Solves `A x = b` for a symmetric positive definite `matrix` by the conjugate
/// gradient method preconditioned by a multigrid V-cycle ([`Multigrid`]; Saad,
/// *Iterative Methods for Sparse Linear Systems*, Algorithm 9.1), starting from
/// the given `x` (a warm start: the previous smoothing step's solution) and
/// overwriting it. Matrix-vector products and vector updates run in parallel;
/// sums are reduced in a fixed order, so the result does not depend on the
/// number of threads.
///
/// When the recurrence's residual meets the tolerance, the true residual is
/// recomputed; if rounding has let them drift apart the iteration restarts from
/// the true residual.
///
/// An [`Error::Argument`](crate::Error::Argument) if a diagonal entry is not
/// positive and finite.
///
/// # Panics
/// If `b` or `x` does not have the matrix's size.
#[cfg(test)]
pub fn conjugate_gradient(
    matrix: &SymmetricMatrix,
    b: &[f64],
    x: &mut [f64],
    settings: CgSettings,
) -> Result<CgReport> {
    let multigrid = Multigrid::new(matrix)?;
    Ok(Cg::new(matrix, &multigrid, b).run(x, settings))
}

/// The state of one preconditioned conjugate gradient solve.
pub(super) struct Cg<'a> {
    matrix: &'a SymmetricMatrix,
    preconditioner: &'a Multigrid,
    b: &'a [f64],
    /// Residual b − A x.
    r: Vec<f64>,
    /// Search direction.
    p: Vec<f64>,
    /// A p, then scratch.
    q: Vec<f64>,
}

impl<'a> Cg<'a> {
    pub(super) fn new(
        matrix: &'a SymmetricMatrix,
        preconditioner: &'a Multigrid,
        b: &'a [f64],
    ) -> Self {
        let n = matrix.size();
        assert_eq!(
            b.len(),
            n,
            "right-hand side of length {} for a {n}×{n} system",
            b.len()
        );
        Cg {
            matrix,
            preconditioner,
            b,
            r: vec![0.0; n],
            p: vec![0.0; n],
            q: vec![0.0; n],
        }
    }

    /// Iterates from `x` until the tolerance or the cap.
    pub(super) fn run(&mut self, x: &mut [f64], settings: CgSettings) -> CgReport {
        assert_eq!(x.len(), self.b.len(), "initial guess of the wrong length");
        let b_norm = dot(self.b, self.b).sqrt();
        if b_norm == 0.0 {
            x.fill(0.0);
            return CgReport {
                iterations: 0,
                relative_residual: 0.0,
                converged: true,
            };
        }
        let target = settings.tolerance * b_norm;
        let mut iterations = 0;
        loop {
            let residual = self.restart(x);
            if residual <= target || iterations >= settings.max_iterations {
                return CgReport {
                    iterations,
                    relative_residual: residual / b_norm,
                    converged: residual <= target,
                };
            }
            iterations += self.iterate(x, target, settings.max_iterations - iterations);
        }
    }

    /// Sets r = b − A x and p = P⁻¹ r (P the preconditioner); returns ‖r‖.
    fn restart(&mut self, x: &[f64]) -> f64 {
        self.matrix.residual(x, self.b, &mut self.r);
        self.preconditioner.apply(&self.r, &mut self.p);
        dot(&self.r, &self.r).sqrt()
    }

    /// At most `budget` iterations from the state [`restart`](Self::restart) left,
    /// until the recurrence's residual is at most `target`; returns how many ran.
    fn iterate(&mut self, x: &mut [f64], target: f64, budget: usize) -> usize {
        let mut rz = dot(&self.r, &self.p);
        for iteration in 1..=budget {
            self.matrix.mul_vec(&self.p, &mut self.q);
            let alpha = rz / dot(&self.p, &self.q);
            let (next_rz, rr) = self.step(x, alpha);
            if rr.sqrt() <= target {
                return iteration;
            }
            let beta = next_rz / rz;
            rz = next_rz;
            self.update_direction(beta);
        }
        budget
    }

    /// x += α p, r −= α q, and z = P⁻¹ r kept in q; returns (rᵀz, rᵀr).
    fn step(&mut self, x: &mut [f64], alpha: f64) -> (f64, f64) {
        let sums: Vec<f64> = x
            .par_chunks_mut(CHUNK)
            .zip(self.r.par_chunks_mut(CHUNK))
            .zip(self.p.par_chunks(CHUNK).zip(self.q.par_chunks(CHUNK)))
            .map(|((x, r), (p, q))| {
                let mut rr = 0.0;
                for k in 0..x.len() {
                    x[k] += alpha * p[k];
                    r[k] -= alpha * q[k];
                    rr += r[k] * r[k];
                }
                rr
            })
            .collect();
        self.preconditioner.apply(&self.r, &mut self.q);
        (dot(&self.r, &self.q), sums.iter().sum())
    }

    /// p = z + β p, with z = P⁻¹ r held in q.
    fn update_direction(&mut self, beta: f64) {
        self.p
            .par_chunks_mut(CHUNK)
            .zip(self.q.par_chunks(CHUNK))
            .for_each(|(p, z)| {
                for (p, z) in p.iter_mut().zip(z) {
                    *p = z + beta * *p;
                }
            });
    }
}

/// The dot product `aᵀb`, summed per chunk in parallel and the chunks in order.
fn dot(a: &[f64], b: &[f64]) -> f64 {
    let sums: Vec<f64> = a
        .par_chunks(CHUNK)
        .zip(b.par_chunks(CHUNK))
        .map(|(a, b)| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>())
        .collect();
    sums.iter().sum()
}

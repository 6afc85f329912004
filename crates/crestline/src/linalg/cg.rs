//! The conjugate gradient method preconditioned by a multigrid V-cycle.

use rayon::prelude::*;

use super::{CycleBuffers, Lanes, Multigrid, SymmetricMatrix, CHUNK};
use crate::progress::{checkpoint, Observer};
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

/// The outcome of [`conjugate_gradient`]: of the worst vector, when several are
/// solved at once.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CgReport {
    /// Iterations run.
    pub iterations: usize,
    /// The true relative residual ‖b − A x‖ / ‖b‖ of the returned `x` (recomputed,
    /// not the recurrence's estimate), the largest over the vectors.
    pub relative_residual: f64,
    /// Whether it is below [`CgSettings::tolerance`] for every vector.
    pub converged: bool,
}

/// Solves `A x = b` for a symmetric positive definite `matrix` by the conjugate
/// gradient method preconditioned by a multigrid V-cycle ([`Multigrid`]; Saad,
/// *Iterative Methods for Sparse Linear Systems*, Algorithm 9.1), starting from
/// the multiple of the given `x` (a warm start: the previous smoothing step's
/// solution) closest to the solution in the energy norm, and overwriting it.
/// Matrix-vector products and vector updates run in parallel; sums are reduced
/// in a fixed order, so the result does not depend on the number of threads.
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
pub fn conjugate_gradient<V: Lanes>(
    matrix: &SymmetricMatrix,
    b: &[V],
    x: &mut [V],
    settings: CgSettings,
) -> Result<CgReport> {
    let multigrid = Multigrid::new(matrix)?;
    Cg::new(matrix, &multigrid, b).run(x, settings, &mut crate::progress::Silent)
}

/// The state of one preconditioned conjugate gradient solve, of one vector or of
/// several interleaved ([`Lanes`]), run in lockstep: each vector has its own
/// step lengths, and a vector that has converged stops moving (its steps are 0)
/// while the others go on.
pub(super) struct Cg<'a, V: Lanes> {
    matrix: &'a SymmetricMatrix,
    preconditioner: &'a Multigrid,
    b: &'a [V],
    /// Residual b − A x.
    r: Vec<V>,
    /// Search direction.
    p: Vec<V>,
    /// A p, then scratch.
    q: Vec<V>,
    /// The preconditioner's vectors.
    buffers: CycleBuffers<V>,
}

impl<'a, V: Lanes> Cg<'a, V> {
    pub(super) fn new(
        matrix: &'a SymmetricMatrix,
        preconditioner: &'a Multigrid,
        b: &'a [V],
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
            r: vec![V::default(); n],
            p: vec![V::default(); n],
            q: vec![V::default(); n],
            buffers: preconditioner.buffers(),
        }
    }

    /// Iterates from `x` until the tolerance (for every vector) or the cap, asking
    /// `observer` before every iteration whether to go on
    /// ([`Error::Cancelled`](crate::Error::Cancelled) if not): an iteration of the
    /// dragon ×16's smoothing takes about a second, its solves a quarter of a minute.
    pub(super) fn run(
        &mut self,
        x: &mut [V],
        settings: CgSettings,
        observer: &mut dyn Observer,
    ) -> Result<CgReport> {
        assert_eq!(x.len(), self.b.len(), "initial guess of the wrong length");
        let b_norm = norms(dot(self.b, self.b));
        // A zero right-hand side has the solution 0.
        let zero: Vec<usize> = (0..V::COUNT).filter(|&k| b_norm.lane(k) == 0.0).collect();
        for v in x.iter_mut() {
            zero.iter().for_each(|&k| v.set_lane(k, 0.0));
        }
        let target = b_norm * settings.tolerance;
        self.scale_start(x, target);
        let mut iterations = 0;
        loop {
            let residual = norms(self.restart(x));
            let done: Vec<bool> = (0..V::COUNT)
                .map(|k| residual.lane(k) <= target.lane(k))
                .collect();
            if done.iter().all(|&d| d) || iterations >= settings.max_iterations {
                let relative = (0..V::COUNT)
                    .filter(|k| !zero.contains(k))
                    .map(|k| residual.lane(k) / b_norm.lane(k))
                    .fold(0.0, f64::max);
                return Ok(CgReport {
                    iterations,
                    relative_residual: relative,
                    converged: done.iter().all(|&d| d),
                });
            }
            let budget = settings.max_iterations - iterations;
            iterations += self.iterate(x, target, done, budget, observer)?;
        }
    }

    /// Replaces the start `x` by its multiple α x closest to the solution x* in
    /// the energy norm: ‖x* − α x‖²_A = x*ᵀb − 2α xᵀb + α² xᵀAx is least at
    /// α = xᵀb / xᵀAx (per vector). Never worse than `x` itself (α = 1 is a
    /// candidate), and much better when `x` is the previous smoothing step of a
    /// rough field: the Stanford dragon ×4's unsmoothed extremalities have
    /// α ≈ 10⁻⁷ (the Laplacian of the field, large on the scan's slivers, dwarfs
    /// it: zero is the better start), the first step's result α ≈ 0.01, the
    /// second's 0.36; the three solves take 9, 11 and 9 iterations instead of 16,
    /// 13 and 10. A vector whose start already meets its `target` residual, or
    /// with xᵀAx = 0, is left as it is.
    fn scale_start(&mut self, x: &mut [V], target: V) {
        self.matrix.residual(x, self.b, &mut self.r);
        let residual = norms(dot(&self.r, &self.r));
        let energy = self.matrix.mul_vec(x, &mut self.q);
        let mut alpha = dot(x, self.b).over(energy);
        for k in 0..V::COUNT {
            if residual.lane(k) <= target.lane(k) || !alpha.lane(k).is_finite() {
                alpha.set_lane(k, 1.0);
            }
        }
        x.par_chunks_mut(CHUNK)
            .for_each(|x| x.iter_mut().for_each(|v| *v = alpha.times(*v)));
    }

    /// Sets r = b − A x and p = P⁻¹ r (P the preconditioner); returns rᵀr.
    fn restart(&mut self, x: &[V]) -> V {
        self.matrix.residual(x, self.b, &mut self.r);
        self.preconditioner
            .apply(&self.r, &mut self.p, &mut self.buffers);
        dot(&self.r, &self.r)
    }

    /// At most `budget` iterations from the state [`restart`](Self::restart) left,
    /// until the recurrence's residual of every vector is at most its `target`
    /// (the vectors `done` already do not move); returns how many ran. Asks
    /// `observer` before each whether to go on.
    fn iterate(
        &mut self,
        x: &mut [V],
        target: V,
        mut done: Vec<bool>,
        budget: usize,
        observer: &mut dyn Observer,
    ) -> Result<usize> {
        let mut rz = dot(&self.r, &self.p);
        for iteration in 1..=budget {
            checkpoint(observer)?;
            let pq = self.matrix.mul_vec(&self.p, &mut self.q);
            let alpha = unless_done(rz.over(pq), &done);
            let (next_rz, rr) = self.step(x, alpha);
            let rr = norms(rr);
            for (k, done) in done.iter_mut().enumerate() {
                *done |= rr.lane(k) <= target.lane(k);
            }
            if done.iter().all(|&d| d) {
                return Ok(iteration);
            }
            let beta = unless_done(next_rz.over(rz), &done);
            rz = next_rz;
            self.update_direction(beta);
        }
        Ok(budget)
    }

    /// x += α p, r −= α q, and z = P⁻¹ r kept in q; returns (rᵀz, rᵀr).
    fn step(&mut self, x: &mut [V], alpha: V) -> (V, V) {
        let sums: Vec<V> = x
            .par_chunks_mut(CHUNK)
            .zip(self.r.par_chunks_mut(CHUNK))
            .zip(self.p.par_chunks(CHUNK).zip(self.q.par_chunks(CHUNK)))
            .map(|((x, r), (p, q))| {
                let mut rr = V::default();
                for k in 0..x.len() {
                    x[k] += alpha.times(p[k]);
                    r[k] -= alpha.times(q[k]);
                    rr += r[k].times(r[k]);
                }
                rr
            })
            .collect();
        self.preconditioner
            .apply(&self.r, &mut self.q, &mut self.buffers);
        (dot(&self.r, &self.q), sum(&sums))
    }

    /// p = z + β p, with z = P⁻¹ r held in q.
    fn update_direction(&mut self, beta: V) {
        self.p
            .par_chunks_mut(CHUNK)
            .zip(self.q.par_chunks(CHUNK))
            .for_each(|(p, z)| {
                for (p, &z) in p.iter_mut().zip(z) {
                    *p = z + beta.times(*p);
                }
            });
    }
}

/// The step `v` with the lanes of the vectors `done` set to 0 (they may be NaN:
/// a converged vector's search direction can vanish).
fn unless_done<V: Lanes>(mut v: V, done: &[bool]) -> V {
    for (k, &done) in done.iter().enumerate() {
        if done {
            v.set_lane(k, 0.0);
        }
    }
    v
}

/// The square root of every lane.
fn norms<V: Lanes>(mut squares: V) -> V {
    for k in 0..V::COUNT {
        squares.set_lane(k, squares.lane(k).sqrt());
    }
    squares
}

/// The dot products `aᵀb` of every lane, summed per chunk in parallel and the
/// chunks in order.
fn dot<V: Lanes>(a: &[V], b: &[V]) -> V {
    let sums: Vec<V> = a
        .par_chunks(CHUNK)
        .zip(b.par_chunks(CHUNK))
        .map(|(a, b)| {
            a.iter()
                .zip(b)
                .fold(V::default(), |sum, (&x, &y)| sum + x.times(y))
        })
        .collect();
    sum(&sums)
}

/// The sum of `parts`, in order.
fn sum<V: Lanes>(parts: &[V]) -> V {
    parts.iter().fold(V::default(), |total, &part| total + part)
}

//! Times the implicit extremality smoothing (Hildebrandt et al. 2005, §5.1) of a
//! mesh's ridge and valley fields with each [`Solver`]: the sparse Cholesky
//! factorization and the Jacobi-preconditioned conjugate gradient method.
//!
//! ```text
//! cargo run --release --example bench_smoothing -- MESH [REPETITIONS]
//! cargo run --release --example bench_smoothing -- torus:VERTICES [REPETITIONS]
//! ```
//!
//! `torus:VERTICES` smooths a generated jittered torus instead of a mesh file.
//!
//! Prints, per solver, the minimum over the repetitions of the seconds for both
//! fields, smoothed in parallel (3 steps of τ = 2, the pipeline's defaults; the
//! same work as the `smoothing` stage of `crestline ridges` plus the analysis it
//! overlaps with the curvature estimation),
//! and the largest difference between the solvers' smoothed values relative to
//! the largest value.

use std::time::Instant;

use crestline::curvature::{estimate_curvature, ShapeOperator};
use crestline::linalg::Solver;
use crestline::mesh::generate::{self, Sampling};
use crestline::mesh::Mesh;
use crestline::ridges::extremality::{extremality, Principal};
use crestline::ridges::smoothing::ExtremalitySmoother;
use crestline::ridges::ExtremalityTracer;
use rayon::prelude::*;

fn main() -> crestline::Result<()> {
    let mut args = std::env::args().skip(1);
    let path = args
        .next()
        .expect("usage: bench_smoothing MESH [REPETITIONS]");
    let repetitions: usize = args.next().map_or(3, |r| r.parse().expect("a count"));
    let mesh = match path.strip_prefix("torus:") {
        Some(n) => {
            generate::torus(
                1.0,
                0.35,
                n.parse().expect("a vertex count"),
                Sampling::jittered(1),
            )?
            .mesh
        }
        None => Mesh::from_soup(crestline::io::read_mesh(path.as_ref())?)?.0,
    };
    let work = mesh.in_unit_frame().0;
    let field = estimate_curvature(&work, &ShapeOperator)?;
    let fields: Vec<(Principal, Vec<f64>)> = [Principal::Max, Principal::Min]
        .into_iter()
        .map(|which| (which, extremality(&work, &field, which)))
        .collect();
    println!("{path}: {} vertices", mesh.vertex_count());
    let mut results = Vec::new();
    for solver in [Solver::Direct, Solver::Iterative, Solver::Auto] {
        let mut best = f64::INFINITY;
        let mut smoothed = Vec::new();
        for _ in 0..repetitions {
            let start = Instant::now();
            let smoother = ExtremalitySmoother::new(
                &work,
                ExtremalityTracer::DEFAULT_SMOOTH_TIME,
                None,
                solver,
            )?
            .analyzed()?;
            smoothed = fields
                .par_iter()
                .map(|(which, e)| {
                    let mut e = e.clone();
                    smoother
                        .smooth(
                            which.directions(&field),
                            &mut e,
                            ExtremalityTracer::DEFAULT_SMOOTH_STEPS,
                        )
                        .map(|()| e)
                })
                .collect::<crestline::Result<Vec<_>>>()?;
            best = best.min(start.elapsed().as_secs_f64());
        }
        println!("{solver:>9}: {best:.3} s");
        results.push(smoothed);
    }
    let scale = results[0]
        .iter()
        .flatten()
        .fold(0.0f64, |m, x| m.max(x.abs()));
    let difference = results[0]
        .iter()
        .flatten()
        .zip(results[1].iter().flatten())
        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
    println!(
        "largest difference direct − iterative: {:.2e} of the largest value",
        difference / scale
    );
    Ok(())
}

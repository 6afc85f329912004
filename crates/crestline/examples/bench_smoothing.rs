//! Times the implicit extremality smoothing (Hildebrandt et al. 2005, §5.1) of a
//! mesh's ridge and valley fields with each [`Solver`]: the sparse Cholesky
//! factorization and the multigrid-preconditioned conjugate gradient method.
//!
//! ```text
//! cargo run --release --example bench_smoothing -- MESH [REPETITIONS]
//! cargo run --release --example bench_smoothing -- torus:VERTICES [REPETITIONS]
//! ```
//!
//! `torus:VERTICES` smooths a generated jittered torus instead of a mesh file.
//!
//! Runs the ridge tracer with the pipeline's defaults (3 steps of τ = 2) and
//! prints, per solver, the minimum over the repetitions of its `smoothing` stage
//! (both fields, smoothed in parallel) and of the `smoothing analysis` stage
//! (the ordering's time beyond the curvature, extremality and edge signs it
//! overlaps with), and the largest distance between the lines of the
//! direct and the iterative solver, relative to the bounding box diagonal.

use crestline::lines::{FeatureLines, LineExtractor};
use crestline::mesh::generate::{self, Sampling};
use crestline::mesh::Mesh;
use crestline::progress::Timings;
use crestline::ridges::{ExtremalityTracer, Solver};

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
    println!("{path}: {} vertices", mesh.vertex_count());
    let mut results: Vec<FeatureLines> = Vec::new();
    for solver in [Solver::Direct, Solver::Iterative, Solver::Auto] {
        let tracer = ExtremalityTracer {
            solver,
            ..ExtremalityTracer::default()
        };
        let (mut smoothing, mut analysis) = (f64::INFINITY, f64::INFINITY);
        let mut lines = FeatureLines::default();
        for _ in 0..repetitions {
            let mut timings = Timings::default();
            lines = tracer.extract(&mesh, &mut timings)?;
            smoothing = smoothing.min(timings.seconds("smoothing"));
            analysis = analysis.min(timings.seconds("smoothing analysis"));
        }
        println!(
            "{solver:>9}: smoothing {smoothing:.3} s, analysis beyond the curvature {analysis:.3} s, \
             {} lines",
            lines.len()
        );
        results.push(lines);
    }
    println!(
        "largest distance direct − iterative: {:.2e} of the diagonal",
        largest_distance(&results[0], &results[1]) / mesh.bounding_box().diagonal()
    );
    Ok(())
}

/// The largest distance between matching points of two sets of lines, or
/// infinity when they differ in the number of lines or points.
fn largest_distance(a: &FeatureLines, b: &FeatureLines) -> f64 {
    if a.len() != b.len() {
        return f64::INFINITY;
    }
    a.iter().zip(b.iter()).fold(0.0, |worst, (p, q)| {
        if p.points.len() != q.points.len() {
            return f64::INFINITY;
        }
        p.points
            .iter()
            .zip(&q.points)
            .fold(worst, |w, (x, y)| w.max((x - y).norm()))
    })
}

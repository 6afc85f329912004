//! Relative RMS error of each built-in curvature estimator against the exact
//! curvature of analytic surfaces, on regular and jittered triangulations.
//!
//! `cargo run --release --example curvature_accuracy [-- VERTICES]`

use std::time::Instant;

use crestline::curvature::{CurvatureEstimator, JetFit, ShapeOperator};
use crestline::mesh::generate::{self, AnalyticMesh, Sampling};

/// The relative RMS error of `estimator` on `surface`, and its time in seconds.
fn measure(surface: &AnalyticMesh, estimator: &dyn CurvatureEstimator) -> (f64, f64) {
    let start = Instant::now();
    let field = estimator.estimate(&surface.mesh).expect("estimate");
    let seconds = start.elapsed().as_secs_f64();
    (
        field
            .relative_rms_error(&surface.exact)
            .expect("reliable vertices"),
        seconds,
    )
}

fn main() {
    let vertices: usize = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(20_000);
    let samplings = [
        ("regular", Sampling::Regular),
        ("jittered", Sampling::jittered(1)),
    ];
    println!(
        "{:<10} {:<9} {:>8} {:>16} {:>10} {:>9}",
        "surface", "mesh", "vertices", "estimator", "rel. RMS", "seconds"
    );
    for (name, sampling) in samplings {
        let surfaces = [
            ("sphere", generate::sphere(1.0, vertices, sampling)),
            (
                "ellipsoid",
                generate::ellipsoid([1.0, 0.7, 0.45], vertices, sampling),
            ),
            ("torus", generate::torus(1.0, 0.35, vertices, sampling)),
        ];
        for (surface_name, surface) in surfaces {
            let surface = surface.expect("generate");
            let estimators: [(&str, &dyn CurvatureEstimator); 2] = [
                ("shape-operator", &ShapeOperator),
                ("jet-fit", &JetFit::default()),
            ];
            for (estimator_name, estimator) in estimators {
                let (error, seconds) = measure(&surface, estimator);
                println!(
                    "{:<10} {:<9} {:>8} {:>16} {:>9.3}% {:>9.4}",
                    surface_name,
                    name,
                    surface.mesh.vertex_count(),
                    estimator_name,
                    100.0 * error,
                    seconds
                );
            }
        }
    }
}

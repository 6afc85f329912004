//! Morse-Smale benchmark (Sahner et al. 2008, Table 1: 3.8 s to build the complex
//! and 30 s to cancel it fully on the 280k-triangle bunny): stage times of the
//! indicator, the discrete gradient, the 1-cell measures and the full cancellation
//! hierarchy on a large generated surface, read from the extractor's progress
//! reports.
//!
//! ```sh
//! cargo run --release --example bench_morse -- [VERTICES] [NOISE]
//! ```
//!
//! The surface is a jittered torus with about `VERTICES` vertices (default 150 000,
//! about 300 000 triangles) whose vertices are moved along the normals by Gaussian
//! noise of `NOISE` mean edge lengths (default 0.2), so that the curvedness has
//! many critical points. Every valid cancellation is made. Prints the counts and
//! the time of each stage in seconds.

use std::sync::Arc;

use crestline::curvature::ShapeOperator;
use crestline::mesh::generate::{self, Sampling};
use crestline::morse::{Criterion, Indicator, MorseSmale, Simplification};
use crestline::progress::Timings;
use crestline::Result;

fn main() -> Result<()> {
    let mut args = std::env::args().skip(1);
    let vertices: usize = args.next().and_then(|a| a.parse().ok()).unwrap_or(150_000);
    let noise: f64 = args.next().and_then(|a| a.parse().ok()).unwrap_or(0.2);
    let torus = generate::torus(1.0, 0.35, vertices, Sampling::jittered(1))?.mesh;
    let mesh = generate::with_normal_noise(&torus, noise, 2)?;
    println!(
        "torus: {} vertices, {} triangles, noise {noise} mean edge lengths",
        mesh.vertex_count(),
        mesh.face_count()
    );
    for criterion in [Criterion::Feature, Criterion::Persistence] {
        let extractor = MorseSmale {
            estimator: Arc::new(ShapeOperator),
            indicator: Indicator::Curvedness,
            criterion,
            simplification: Simplification::Cancel(usize::MAX),
            ..MorseSmale::default()
        };
        let mut timings = Timings::default();
        let (_, summary) = extractor.run(&mesh, &mut timings)?;
        let initial = summary.initial;
        println!(
            "{criterion:?}: {} minima, {} saddles, {} maxima; {} cancellations",
            initial.minima,
            initial.saddles,
            initial.maxima,
            summary.hierarchy.len()
        );
        let seconds = |stage| timings.seconds(stage);
        println!(
            "  indicator {:.3} s, gradient {:.3} s, cells {:.3} s, cancellation {:.3} s; \
             construction + cancellation {:.3} s",
            seconds("indicator"),
            seconds("gradient"),
            seconds("cells"),
            seconds("cancellation"),
            seconds("gradient") + seconds("cells") + seconds("cancellation")
        );
    }
    Ok(())
}

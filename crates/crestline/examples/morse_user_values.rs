//! Morse-Smale lines of a scalar field the caller computes.
//!
//! The Morse-Smale extractor needs no curvature: any value per vertex will do. Here
//! the value is the height of the Stanford bunny (its y axis), so the ascending
//! 1-cells run from saddles up to the peaks (ears, head, back) and persistence
//! cancellation keeps the most prominent of them. The values go in through the public entry point
//! [`LineExtractor<SurfaceWithValues>`]; each output point carries the value where
//! it lies (`"indicator"`).
//!
//! `cargo run --release --example morse_user_values [-- --mesh MESH]`
//! (an option rather than a bare path: `cargo test FILTER` runs this example
//! with the filter as its argument)

use std::path::PathBuf;

use crestline::io::read_mesh;
use crestline::lines::{LineExtractor, SurfaceWithValues};
use crestline::mesh::Mesh;
use crestline::morse::{Criterion, MorseSmale, Simplification};
use crestline::progress::Silent;

fn main() -> crestline::Result<()> {
    let path = std::env::args()
        .skip_while(|a| a != "--mesh")
        .nth(1)
        .map_or_else(
            || PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../meshes/bunny_small.obj"),
            PathBuf::from,
        );
    let (mesh, _repairs) = Mesh::from_soup(read_mesh(&path)?).map_err(|e| e.in_file(&path))?;
    let height: Vec<f64> = mesh.positions().iter().map(|p| p.y).collect();
    let extractor = MorseSmale {
        criterion: Criterion::Persistence,
        simplification: Simplification::KeepSaddles(8),
        ..Default::default()
    };
    let lines = extractor.extract(
        &SurfaceWithValues {
            mesh: &mesh,
            values: &height,
        },
        &mut Silent,
    )?;
    println!(
        "{}: {} vertices, {} ascending lines of the height",
        path.file_name().unwrap_or_default().to_string_lossy(),
        mesh.vertex_count(),
        lines.len()
    );
    for line in &lines {
        let values = &line.values["indicator"];
        let (low, high) = values
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &v| {
                (lo.min(v), hi.max(v))
            });
        println!(
            "  persistence {:.4}: {} points, height {low:.4} to {high:.4}",
            line.strength,
            line.points.len()
        );
    }
    assert!(!lines.is_empty(), "the bunny's height has saddles to keep");
    Ok(())
}

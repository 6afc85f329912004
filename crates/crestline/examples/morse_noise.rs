//! Noise insensitivity of the Morse-Smale feature lines (Sahner et al. 2008, §4.1):
//! the ascending lines of curvedness on a bundled mesh, and on copies whose vertices
//! are moved along the normals by Gaussian noise of 0.2, 0.5 and 1 mean edge
//! lengths, all simplified to the same number of saddles.
//!
//! ```sh
//! cargo run --release --example morse_noise -- [MESH] [KEEP_SADDLES]
//! ```
//!
//! For each curvature estimator and noise level, prints the mean distance from the
//! noisy lines' points to the nearest point of the noise-free lines, relative to the
//! mean edge length and to the bounding-box diagonal of the noise-free mesh. The
//! noise itself moves the surface by σ mean edge lengths (root mean square), which
//! bounds what a line on the noisy surface can achieve. Defaults: `meshes/bunny.obj`,
//! 100 saddles.

use std::path::PathBuf;
use std::sync::Arc;

use crestline::curvature::{CurvatureEstimator, JetFit, ShapeOperator};
use crestline::lines::{FeatureLines, LineExtractor, LineKind};
use crestline::mesh::generate;
use crestline::mesh::Mesh;
use crestline::morse::{MorseSmale, Simplification};
use crestline::progress::Silent;
use crestline::{Point, Result};

fn points(lines: &FeatureLines) -> Vec<Point> {
    lines
        .of_kind(LineKind::Ascending)
        .flat_map(|l| l.points.iter().copied())
        .collect()
}

/// Mean over `from` of the distance to the nearest point of `to` (a uniform grid
/// of buckets of side `cell` keeps the search local).
fn mean_distance(from: &[Point], to: &[Point], cell: f64) -> f64 {
    use std::collections::HashMap;
    let key = |p: &Point| [p.x, p.y, p.z].map(|c| (c / cell).floor() as i64);
    let mut grid: HashMap<[i64; 3], Vec<Point>> = HashMap::new();
    for p in to {
        grid.entry(key(p)).or_default().push(*p);
    }
    let nearest = |p: &Point| {
        let k = key(p);
        // Grow the searched cube until it holds a point at most its inner radius away.
        (1i64..)
            .find_map(|r| {
                let mut best = f64::INFINITY;
                for dx in -r..=r {
                    for dy in -r..=r {
                        for dz in -r..=r {
                            if let Some(bucket) = grid.get(&[k[0] + dx, k[1] + dy, k[2] + dz]) {
                                for q in bucket {
                                    best = best.min((p - q).norm());
                                }
                            }
                        }
                    }
                }
                (best <= r as f64 * cell || r > 64).then_some(best)
            })
            .unwrap_or(f64::INFINITY)
    };
    from.iter().map(nearest).sum::<f64>() / from.len().max(1) as f64
}

fn main() -> Result<()> {
    let mut args = std::env::args().skip(1);
    let path = args.next().map_or_else(
        || PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../meshes/bunny.obj"),
        PathBuf::from,
    );
    let keep: usize = args.next().and_then(|a| a.parse().ok()).unwrap_or(100);
    let mesh = Mesh::from_soup(crestline::io::read_mesh(&path)?)?.0;
    let h = mesh.mean_edge_length();
    let diagonal = mesh.bounding_box().diagonal();
    println!(
        "{}: {} vertices, {} triangles; {keep} saddles kept; curvedness, feature criterion",
        path.display(),
        mesh.vertex_count(),
        mesh.face_count()
    );
    println!("estimator       sigma  points  mean distance / edge  / diagonal");
    let estimators: [(&str, Arc<dyn CurvatureEstimator + Send + Sync>); 2] = [
        ("shape-operator", Arc::new(ShapeOperator)),
        ("jet-fit", Arc::new(JetFit::default())),
    ];
    for (name, estimator) in estimators {
        let extractor = MorseSmale {
            estimator,
            simplification: Simplification::KeepSaddles(keep),
            ..Default::default()
        };
        let clean = points(&extractor.extract(&mesh, &mut Silent)?);
        println!("{name:<15} {:>5}  {:>6}", 0.0, clean.len());
        for sigma in [0.2, 0.5, 1.0] {
            let lines =
                extractor.extract(&generate::with_normal_noise(&mesh, sigma, 7)?, &mut Silent)?;
            let noisy_points = points(&lines);
            let d = mean_distance(&noisy_points, &clean, 2.0 * h);
            println!(
                "{name:<15} {sigma:>5}  {:>6}  {:>20.2}  {:>9.4}",
                noisy_points.len(),
                d / h,
                d / diagonal
            );
        }
    }
    Ok(())
}

//! Write the analytic test surfaces as binary PLY files carrying their exact
//! curvature (vertex properties `k1`, `k2` with k1 ≥ k2, convex-positive), for
//! comparisons with other tools.
//!
//! `cargo run --release --example analytic_meshes -- OUT_DIR [VERTICES]`
//! writes `sphere`, `ellipsoid` and `torus`, each `_regular` and `_jittered`.

use std::path::PathBuf;

use crestline::io::{write_ply, VertexAttribute};
use crestline::mesh::generate::{self, Sampling};

fn main() -> crestline::Result<()> {
    let mut args = std::env::args().skip(1);
    let dir = PathBuf::from(args.next().unwrap_or_else(|| "bench-data".into()));
    let vertices: usize = args.next().and_then(|a| a.parse().ok()).unwrap_or(20_000);
    std::fs::create_dir_all(&dir).map_err(|e| crestline::Error::io(&dir, e))?;
    for (sampling_name, sampling) in [
        ("regular", Sampling::Regular),
        ("jittered", Sampling::jittered(1)),
    ] {
        let surfaces = [
            ("sphere", generate::sphere(1.0, vertices, sampling)?),
            (
                "ellipsoid",
                generate::ellipsoid([1.0, 0.7, 0.45], vertices, sampling)?,
            ),
            ("torus", generate::torus(1.0, 0.35, vertices, sampling)?),
        ];
        for (name, surface) in surfaces {
            let k1: Vec<f64> = surface.exact.iter().map(|k| k.k_max).collect();
            let k2: Vec<f64> = surface.exact.iter().map(|k| k.k_min).collect();
            let path = dir.join(format!("{name}_{sampling_name}_{vertices}.ply"));
            let attributes = [
                VertexAttribute::Scalar {
                    name: "k1",
                    values: &k1,
                },
                VertexAttribute::Scalar {
                    name: "k2",
                    values: &k2,
                },
            ];
            write_ply(&path, &surface.mesh, &attributes)?;
            println!(
                "{} ({} vertices)",
                path.display(),
                surface.mesh.vertex_count()
            );
        }
    }
    Ok(())
}

//! Quantiles of the jet fit's residual (`CurvatureField::fit_residual`) on a
//! clean and a noisy irregular ellipsoid and on the meshes given as arguments:
//! the measurements behind `ridges::FULL_SMOOTHING_RESIDUAL`.
//!
//! `cargo run --release -p crestline --example fit_residuals -- meshes/bunny.obj …`
use crestline::curvature::{CurvatureEstimator, JetFit};
use crestline::mesh::generate::{self, Sampling};
use crestline::ridges::presmooth_surface;

fn q(mut r: Vec<f64>) -> String {
    r.sort_by(f64::total_cmp);
    let at = |f: f64| r[((r.len() - 1) as f64 * f) as usize];
    format!(
        "p10 {:.2e} p50 {:.2e} p90 {:.2e} p99 {:.2e}",
        at(0.1),
        at(0.5),
        at(0.9),
        at(0.99)
    )
}

fn main() {
    let clean = generate::ellipsoid([1.0, 0.7, 0.45], 30_000, Sampling::jittered(1))
        .unwrap()
        .mesh;
    let noisy = generate::with_normal_noise(&clean, 0.2, 5).unwrap();
    let mut meshes = vec![
        ("clean".to_string(), clean),
        (
            "noisy presmooth 3".to_string(),
            presmooth_surface(&noisy, 3).unwrap(),
        ),
        ("noisy".to_string(), noisy),
    ];
    for path in std::env::args().skip(1) {
        let soup = crestline::io::read_mesh(std::path::Path::new(&path)).unwrap();
        let mesh = crestline::mesh::Mesh::from_soup(soup).unwrap().0;
        meshes.push((path, mesh));
    }
    for (name, mesh) in meshes {
        let field = JetFit::default().estimate(&mesh).unwrap();
        println!("{name}: {}", q(field.fit_residual.unwrap()));
    }
}

//! Ridge precision of the extremality tracer with extremalities from the fitted
//! jet (`JetFit`, third-order terms) against the discrete ones (eq. 4 of
//! Hildebrandt, Polthier and Wardetzky 2005), on a rotated, scaled (×1000),
//! jittered 30k-vertex ellipsoid with axes 1, 0.7, 0.45, clean and with normal
//! noise of 0.2 mean edge lengths. The true ridge is the principal ellipse through
//! the two longer axes.
//!
//! Prints, per setting: the mean distance of the line points from the nearest
//! principal plane as a share of the bounding-box diagonal, the share of the ellipse
//! within two mean edge lengths of a line point, the number of lines and the time
//! of the whole extraction.
//!
//! `cargo run --release -p crestline --example jet_extremality [-- --sweep]`
//! (`--sweep`: also the smoothing steps and times of the jet path).
//!
//! `-- --noise-table`: instead, the default estimator (`auto`) against the shape
//! operator and the jet fit with isotropic Gaussian noise of 0 to 0.5 mean edge
//! lengths, three seeds each.
//!
//! With mesh files as arguments (`-- meshes/bunny.obj …`), prints instead the
//! defaults against the jet path on each: time of the extraction (the mesh
//! loaded), number of lines and their total length.

use std::sync::Arc;
use std::time::Instant;

use crestline::curvature::{
    AutoEstimator, CurvatureEstimator, Estimator, JetFit, ShapeOperator, WithoutExtremality,
};
use crestline::jobs::{RidgesOptions, Surface};
use crestline::lines::{FeatureLines, LineExtractor, LineKind};
use crestline::mesh::generate::{self, Sampling};
use crestline::mesh::{Mesh, TriangleSoup};
use crestline::progress::Silent;
use crestline::ridges::{ExtremalityTracer, Kinds};
use crestline::{Point, Vector};
use nalgebra::{Isometry3, Translation3, UnitQuaternion};

const AXES: [f64; 3] = [1.0, 0.7, 0.45];
const SCALE: f64 = 1000.0;

fn motion() -> Isometry3<f64> {
    Isometry3::from_parts(
        Translation3::new(5.0 * SCALE, -2.0 * SCALE, 9.0 * SCALE),
        UnitQuaternion::from_euler_angles(0.7, 0.4, -1.2),
    )
}

/// Share of the ellipse in z = 0 within `radius` of a point, away from the
/// umbilics (which lie in y = 0), as in the crate's tests.
fn coverage(points: &[Point], radius: f64) -> f64 {
    let [a, b, c] = AXES;
    let umbilic = Point::new(
        a * ((a * a - b * b) / (a * a - c * c)).sqrt(),
        0.0,
        c * ((b * b - c * c) / (a * a - c * c)).sqrt(),
    ) * SCALE;
    let samples: Vec<Point> = (0..720)
        .map(|i| {
            let angle = std::f64::consts::TAU * i as f64 / 720.0;
            Point::new(a * angle.cos(), b * angle.sin(), 0.0) * SCALE
        })
        .filter(|p| {
            let mirrored = Point::new(p.x.abs(), p.y.abs(), p.z.abs());
            (mirrored - umbilic).norm() > 0.15 * SCALE
        })
        .collect();
    let covered = samples
        .iter()
        .filter(|s| points.iter().any(|p| (p - *s).norm() < radius))
        .count();
    covered as f64 / samples.len() as f64
}

/// The mean distance of the lines' points from the nearest principal plane as a
/// share of the diagonal, the coverage of the ridge ellipse and the lines.
fn fidelity(mesh: &Mesh, tracer: &ExtremalityTracer) -> (f64, f64, FeatureLines) {
    let lines = tracer.extract(mesh, &mut Silent).unwrap();
    let motion = motion();
    let points: Vec<Point> = lines
        .iter()
        .flat_map(|l| l.points.iter())
        .map(|p| motion.inverse_transform_point(p))
        .collect();
    let diagonal = 2.0 * Vector::from(AXES).norm() * SCALE;
    let distance = points
        .iter()
        .map(|p| p.x.abs().min(p.y.abs()).min(p.z.abs()))
        .sum::<f64>()
        / points.len().max(1) as f64;
    let h = mesh.mean_edge_length();
    (distance / diagonal, coverage(&points, 2.0 * h), lines)
}

fn measure(name: &str, mesh: &Mesh, tracer: &ExtremalityTracer) {
    let start = Instant::now();
    let (distance, coverage, lines) = fidelity(mesh, tracer);
    let seconds = start.elapsed().as_secs_f64();
    println!(
        "| {name:<44} | {:>9.4}% | {:>7.1}% | {:>5} | {:>5} | {:>6.2} s |",
        100.0 * distance,
        100.0 * coverage,
        lines.len(),
        lines.of_kind(LineKind::Ridge).count(),
        seconds
    );
}

/// `mesh` with every vertex moved by isotropic Gaussian noise of standard
/// deviation `sigma` mean edge lengths along each axis, reproducibly from `seed`.
fn with_isotropic_noise(mesh: &Mesh, sigma: f64, seed: u64) -> Mesh {
    use rand::{Rng, SeedableRng};
    let h = mesh.mean_edge_length();
    let mut rng = rand::rngs::StdRng::seed_from_u64(seed);
    let mut normal = || {
        let (u, v): (f64, f64) = (rng.random_range(f64::EPSILON..1.0), rng.random());
        (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
    };
    let positions = mesh
        .positions()
        .iter()
        .map(|p| p + Vector::new(normal(), normal(), normal()) * (sigma * h))
        .collect();
    let soup = TriangleSoup {
        positions,
        triangles: mesh.triangles(),
        ..TriangleSoup::default()
    };
    Mesh::from_soup(soup).unwrap().0
}

/// The default estimator against the shape operator and the jet fit over noise
/// levels and seeds, each with the other defaults of `ridges`: clean as they are,
/// noisy with `--presmooth 3 --smooth-steps 5 --kind ridges`. Prints, per level, the mean over the seeds of
/// the distance (share of the diagonal) and of the coverage, and the least
/// coverage.
fn noise_table(clean: &Mesh) {
    println!("| noise (h̄) | estimator | distance / diagonal | coverage (mean, least) | clean by the residual |");
    println!("|---|---|---|---|---|");
    for noise in [0.0, 0.05, 0.1, 0.2, 0.3, 0.5] {
        let seeds: &[u64] = if noise == 0.0 { &[1] } else { &[1, 2, 3] };
        let meshes: Vec<Mesh> = seeds
            .iter()
            .map(|&seed| with_isotropic_noise(clean, noise, seed))
            .collect();
        for estimator in [Estimator::ShapeOperator, Estimator::JetFit, Estimator::Auto] {
            // The tracer `ridges` makes of these options.
            let noisy = noise > 0.0;
            let options = RidgesOptions {
                estimator,
                presmooth: if noisy { 3 } else { 0 },
                smooth_steps: noisy.then_some(5),
                kind: if noisy { Kinds::Ridges } else { Kinds::Both },
                ..RidgesOptions::default()
            };
            let tracer = options.tracer(&Surface::of_mesh(clean.clone()));
            let runs: Vec<(f64, f64)> = meshes
                .iter()
                .map(|mesh| {
                    let (distance, coverage, _) = fidelity(mesh, &tracer);
                    (distance, coverage)
                })
                .collect();
            let count = runs.len() as f64;
            let distance = runs.iter().map(|r| r.0).sum::<f64>() / count;
            let mean_coverage = runs.iter().map(|r| r.1).sum::<f64>() / count;
            let least = runs.iter().map(|r| r.1).fold(1.0, f64::min);
            let clean_count = if estimator == Estimator::Auto {
                let judged = meshes.iter().map(|m| presmoothed(m, &tracer));
                format!(
                    "{} of {}",
                    judged.filter(AutoEstimator::is_clean).count(),
                    meshes.len()
                )
            } else {
                String::new()
            };
            println!(
                "| {noise} | {estimator} | {:.4}% | {:.1}%, {:.1}% | {clean_count} |",
                100.0 * distance,
                100.0 * mean_coverage,
                100.0 * least
            );
        }
    }
}

/// The mesh the tracer estimates curvature on: `mesh` after its presmoothing.
fn presmoothed(mesh: &Mesh, tracer: &ExtremalityTracer) -> Mesh {
    crestline::ridges::presmooth_surface(mesh, tracer.presmooth_steps).unwrap()
}

fn tracer(
    estimator: Arc<dyn CurvatureEstimator + Send + Sync>,
    presmooth_steps: usize,
    smooth_steps: usize,
    smooth_time: f64,
) -> ExtremalityTracer {
    ExtremalityTracer {
        estimator,
        presmooth_steps,
        smooth_steps,
        smooth_time,
        ..ExtremalityTracer::default()
    }
}

/// Defaults against the jet path on the meshes at `paths`.
fn compare_on_meshes(paths: &[String]) {
    println!("| mesh | vertices | path | time | lines (ridges / valleys) | total length |");
    println!("|---|---|---|---|---|---|");
    for path in paths {
        let soup = crestline::io::read_mesh(std::path::Path::new(path)).unwrap();
        let mesh = Mesh::from_soup(soup).unwrap().0;
        let tracers = [
            ("defaults", ExtremalityTracer::default()),
            (
                "jet path",
                ExtremalityTracer::with_estimator(Estimator::JetFit),
            ),
        ];
        for (name, tracer) in tracers {
            let start = Instant::now();
            let lines = tracer.extract(&mesh, &mut Silent).unwrap();
            let seconds = start.elapsed().as_secs_f64();
            println!(
                "| {path} | {} | {name} | {seconds:.2} s | {} ({} / {}) | {:.4} |",
                mesh.vertex_count(),
                lines.len(),
                lines.of_kind(LineKind::Ridge).count(),
                lines.of_kind(LineKind::Valley).count(),
                lines.total_length()
            );
        }
    }
}

fn main() {
    let paths: Vec<String> = std::env::args()
        .skip(1)
        .filter(|a| !a.starts_with("--"))
        .collect();
    if !paths.is_empty() {
        compare_on_meshes(&paths);
        return;
    }
    let sweep = std::env::args().any(|a| a == "--sweep");
    let motion = motion();
    let surface = generate::ellipsoid(AXES, 30_000, Sampling::jittered(1)).unwrap();
    let soup = TriangleSoup {
        positions: surface
            .mesh
            .positions()
            .iter()
            .map(|p| motion * (p * SCALE))
            .collect(),
        triangles: surface.mesh.triangles(),
        ..TriangleSoup::default()
    };
    let clean = Mesh::from_soup(soup).unwrap().0;
    if std::env::args().any(|a| a == "--noise-table") {
        noise_table(&clean);
        return;
    }
    let noisy = generate::with_normal_noise(&clean, 0.2, 5).unwrap();
    let shape: Arc<dyn CurvatureEstimator + Send + Sync> = Arc::new(ShapeOperator);
    let jet: Arc<dyn CurvatureEstimator + Send + Sync> = Arc::new(JetFit::default());
    let jet_discrete: Arc<dyn CurvatureEstimator + Send + Sync> =
        Arc::new(WithoutExtremality(jet.clone()));
    let steps = ExtremalityTracer::DEFAULT_SMOOTH_STEPS;
    let time = ExtremalityTracer::DEFAULT_SMOOTH_TIME;
    let (jet_steps, jet_time) = (
        ExtremalityTracer::DEFAULT_FITTED_SMOOTH_STEPS,
        ExtremalityTracer::DEFAULT_FITTED_SMOOTH_TIME,
    );
    println!("| setting | distance / diagonal | coverage | lines | ridges | time |");
    println!("|---|---|---|---|---|---|");
    for (label, mesh) in [("clean", &clean), ("noise 0.2 h", &noisy)] {
        let presmooth = if label == "clean" { 0 } else { 3 };
        let (s, ss) = if label == "clean" { (steps, 0) } else { (5, 5) };
        let p = format!("{label}, presmooth {presmooth}");
        let chosen = if label == "clean" { jet_steps } else { 5 };
        let rows = [
            ("shape operator", &shape, s, time),
            ("jet, discrete e", &jet_discrete, s, time),
            ("jet, discrete e", &jet_discrete, 0, time),
            ("jet, fitted e", &jet, chosen, jet_time),
            ("jet, fitted e", &jet, ss, time),
            ("jet, fitted e", &jet, 0, time),
        ];
        for (name, estimator, n, tau) in rows {
            let setting = if n == 0 {
                "0 steps".to_string()
            } else {
                format!("{n}×τ{tau}")
            };
            measure(
                &format!("{p}: {name}, {setting}"),
                mesh,
                &tracer(estimator.clone(), presmooth, n, tau),
            );
        }
        if sweep {
            let taus: &[f64] = if label == "clean" {
                &[0.25, 0.5, 1.0, 2.0]
            } else {
                &[2.0, 3.0, 4.0, 6.0, 8.0]
            };
            for n in [1, 2, 3, 5] {
                for &tau in taus {
                    measure(
                        &format!("{p}: jet, fitted e, {n}×τ{tau}"),
                        mesh,
                        &tracer(jet.clone(), presmooth, n, tau),
                    );
                }
            }
        }
    }
}

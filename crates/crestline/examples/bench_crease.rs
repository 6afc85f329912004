//! Crease surface benchmark: ridge surfaces of a sampled gyroid at each `--size`
//! (default 128³ and 256³) and of the MNI152 white-matter probability map
//! (`volumes/mni152_wm_1mm.nii.gz`, 197×233×189; skipped with a message if absent),
//! in full and at every second sample (99×117×95, the size of the paper's
//! full-brain field).
//!
//! ```sh
//! cargo run --release --example bench_crease -- [--size N]... [--period P]
//!     [--volume FILE]
//! ```
//!
//! The gyroid is `f = sin x cos y + sin y cos z + sin z cos x` with `(x, y, z) =
//! 2π (i, j, k) / P` at sample `(i, j, k)` (default P = 40). Each field is run with
//! the default options (cubic B-spline derivatives, default ε, θ and strength) and
//! no component filter; one line per field gives the seconds of each stage —
//! reconstruction (derivatives), eigenframes, and the four stages of the surface
//! ([`crestline::jobs::crease`]) — the total, and the triangle count.

use std::path::PathBuf;

use clap::Parser;
use crestline::io::read_volume;
use crestline::jobs::{crease, CreaseOptions};
use crestline::progress::Timings;
use crestline::volume::Volume;
use crestline::Result;
use nalgebra::Matrix3;

/// The stages of the crease surface, as the job reports them to its observer.
const SURFACE_STAGES: [&str; 4] = [
    "crossings",
    "degenerate points",
    "normals",
    "pairing and triangulation",
];

/// Crease surface timing.
#[derive(Parser, Debug)]
struct Args {
    /// Samples along each axis of a gyroid (repeatable).
    #[arg(long = "size", default_values_t = [128, 256])]
    sizes: Vec<usize>,
    /// Period of the gyroid in samples.
    #[arg(long, default_value_t = 40.0)]
    period: f64,
    /// The real volume.
    #[arg(long, default_value = concat!(env!("CARGO_MANIFEST_DIR"), "/../../volumes/mni152_wm_1mm.nii.gz"))]
    volume: PathBuf,
}

fn main() -> Result<()> {
    let args = Args::parse();
    println!(
        "{:<22} {:>8} {:>8} {:>9} {:>10} {:>9} {:>11} {:>8} {:>10}",
        "field",
        "recon s",
        "eigen s",
        "crossing s",
        "degenerate s",
        "normals s",
        "triangulate s",
        "total s",
        "triangles"
    );
    for &n in &args.sizes {
        let volume = gyroid(n, args.period)?;
        run(&format!("gyroid {n}^3"), &volume)?;
    }
    if args.volume.exists() {
        let volume = read_volume(&args.volume)?;
        let [x, y, z] = volume.dims();
        run(&format!("MNI152 WM {x}x{y}x{z}"), &volume)?;
        let half = every_second_sample(&volume)?;
        let [x, y, z] = half.dims();
        run(&format!("MNI152 WM /2 {x}x{y}x{z}"), &half)?;
    } else {
        println!("{} not found: skipped", args.volume.display());
    }
    Ok(())
}

/// Times the ridge surface of `volume` and prints a row.
fn run(name: &str, volume: &Volume) -> Result<()> {
    let mut timings = Timings::default();
    let options = CreaseOptions {
        min_component: 0,
        ..CreaseOptions::default()
    };
    let soup = crease(volume, &options, &mut timings)?;
    let columns: Vec<String> = ["reconstruction", "eigenframes"]
        .into_iter()
        .chain(SURFACE_STAGES)
        .zip([8, 8, 9, 10, 9, 11])
        .map(|(stage, width)| format!("{:>width$.3}", timings.seconds(stage)))
        .collect();
    let total: f64 = timings.stages.iter().map(|(_, seconds)| seconds).sum();
    println!(
        "{name:<22} {} {total:>8.3} {:>10}",
        columns.join(" "),
        soup.triangles.len()
    );
    Ok(())
}

/// Every second sample of `volume` along each axis (no smoothing): about the size
/// of the paper's full-brain field (93×116×93).
fn every_second_sample(volume: &Volume) -> Result<Volume> {
    let [nx, ny, nz] = volume.dims();
    let samples = volume.samples();
    let mut kept = Vec::new();
    for k in (0..nz).step_by(2) {
        for j in (0..ny).step_by(2) {
            for i in (0..nx).step_by(2) {
                kept.push(samples[i + nx * (j + ny * k)]);
            }
        }
    }
    Volume::new(
        [nx.div_ceil(2), ny.div_ceil(2), nz.div_ceil(2)],
        volume.spacing().map(|s| 2.0 * s),
        volume.origin(),
        *volume.direction(),
        kept,
    )
}

/// The gyroid sampled on an n³ grid of unit voxels with `period` samples.
fn gyroid(n: usize, period: f64) -> Result<Volume> {
    let w = 2.0 * std::f64::consts::PI / period;
    let (sin, cos): (Vec<f64>, Vec<f64>) = (0..n).map(|i| (w * i as f64).sin_cos()).unzip();
    let mut samples = Vec::with_capacity(n * n * n);
    for k in 0..n {
        for j in 0..n {
            for i in 0..n {
                samples.push((sin[i] * cos[j] + sin[j] * cos[k] + sin[k] * cos[i]) as f32);
            }
        }
    }
    Volume::new([n; 3], [1.0; 3], [0.0; 3], Matrix3::identity(), samples)
}

//! Isosurface benchmark: the surface `f = level` of a gyroid sampled on an `n³` grid.
//!
//! ```sh
//! cargo run --release --example bench_isosurface -- [--size N] [--period P]
//!     [--level L] [--repetitions R] [--raw FILE]
//! ```
//!
//! The field is `f = sin x cos y + sin y cos z + sin z cos x` with `(x, y, z) =
//! 2π (i, j, k) / P` at sample `(i, j, k)`, computed in `f64` and stored as `f32`
//! (defaults: N = 256, P = 40, level 0.2). `--raw FILE` also writes the samples as
//! little-endian `f32`, x fastest, for other tools to read the same field
//! (`tools/compare_isosurface.py` does). Times, `R` times each, [`isosurface`] (the
//! extraction: shared vertices and triangles) and [`Isosurface::to_mesh`](crestline::volume::Isosurface::to_mesh) (the
//! half-edge mesh), and prints one line of `key=value` figures: the minimum and
//! median seconds of each, the vertex and triangle counts and the area.

use std::path::PathBuf;
use std::time::Instant;

use clap::Parser;
use crestline::isosurface::isosurface;
use crestline::volume::Volume;
use crestline::Result;
use nalgebra::Matrix3;

/// Isosurface timing on a sampled gyroid.
#[derive(Parser, Debug)]
struct Args {
    /// Samples along each axis.
    #[arg(long, default_value_t = 256)]
    size: usize,
    /// Period of the gyroid in samples.
    #[arg(long, default_value_t = 40.0)]
    period: f64,
    /// Level of the isosurface.
    #[arg(long, default_value_t = 0.2)]
    level: f64,
    /// Timed repetitions.
    #[arg(long, default_value_t = 5, value_parser = clap::value_parser!(u32).range(1..))]
    repetitions: u32,
    /// Write the samples to this file (little-endian f32, x fastest).
    #[arg(long)]
    raw: Option<PathBuf>,
}

/// The gyroid samples of `args`, x fastest.
fn gyroid(args: &Args) -> Vec<f32> {
    let n = args.size;
    let w = 2.0 * std::f64::consts::PI / args.period;
    let (sin, cos): (Vec<f64>, Vec<f64>) = (0..n).map(|i| (w * i as f64).sin_cos()).unzip();
    let mut samples = Vec::with_capacity(n * n * n);
    for k in 0..n {
        for j in 0..n {
            for i in 0..n {
                let f = sin[i] * cos[j] + sin[j] * cos[k] + sin[k] * cos[i];
                samples.push(f as f32);
            }
        }
    }
    samples
}

fn main() -> Result<()> {
    let args = Args::parse();
    let samples = gyroid(&args);
    if let Some(path) = &args.raw {
        let bytes: Vec<u8> = samples.iter().flat_map(|v| v.to_le_bytes()).collect();
        std::fs::write(path, bytes).map_err(|e| crestline::Error::File {
            path: path.clone(),
            message: e.to_string(),
        })?;
    }
    let n = args.size;
    let volume = Volume::new([n; 3], [1.0; 3], [0.0; 3], Matrix3::identity(), samples)?;
    let (extract, surface) = timed(args.repetitions, || isosurface(&volume, args.level))?;
    let (mesh_seconds, mesh) = timed(args.repetitions, || surface.to_mesh())?;
    let area: f64 = mesh.face_areas().iter().sum();
    println!(
        "crestline {n}^3 gyroid period={} level={} threads={} extract_min={:.4} \
         extract_median={:.4} mesh_min={:.4} mesh_median={:.4} vertices={} triangles={} \
         area={area:.1}",
        args.period,
        args.level,
        rayon::current_num_threads(),
        extract[0],
        extract[extract.len() / 2],
        mesh_seconds[0],
        mesh_seconds[mesh_seconds.len() / 2],
        mesh.vertex_count(),
        mesh.face_count(),
    );
    Ok(())
}

/// Run `step` `repetitions` times: the sorted seconds and the last result.
fn timed<T>(repetitions: u32, mut step: impl FnMut() -> Result<T>) -> Result<(Vec<f64>, T)> {
    let mut seconds = Vec::new();
    for _ in 1..repetitions {
        // Each result is freed before the next step starts.
        seconds.push(time(&mut step)?.0);
    }
    let (last, result) = time(&mut step)?;
    seconds.push(last);
    seconds.sort_by(f64::total_cmp);
    Ok((seconds, result))
}

/// The seconds `step` takes, and its result.
fn time<T>(step: &mut impl FnMut() -> Result<T>) -> Result<(f64, T)> {
    let start = Instant::now();
    let result = step()?;
    Ok((start.elapsed().as_secs_f64(), result))
}

//! Load benchmark: how long reading a large mesh file and building the half-edge
//! mesh take.
//!
//! ```sh
//! cargo run --release --example bench_load -- [--out DIR] [--triangles N] [--repetitions R]
//! cargo run --release --example bench_load -- --once FILE
//! ```
//!
//! The first form makes sure `DIR/torus.ply` (binary little endian) and
//! `DIR/torus.obj` exist, generating a jittered torus with about `N` triangles if
//! either is missing (existing files are reused whatever their size: delete them to
//! change it). It then times, `R` times per file, [`read_mesh`] alone, the build
//! as the command line makes it ([`Mesh::from_file_soup`]: the repairs of
//! [`Mesh::from_soup`], after renumbering a file whose vertex order is
//! scattered) alone and both together, and prints the minimum and the median of
//! each in seconds and in seconds per million triangles.
//!
//! `--once FILE` reads and builds `FILE` once and prints one line of
//! `key=value` figures, so that whole-process wall time and peak memory can be
//! measured from outside (e.g. `/usr/bin/time -v`, or `tools/bench_load.py`).

use std::path::{Path, PathBuf};
use std::time::Instant;

use clap::Parser;
use crestline::io::{read_mesh, write_obj, write_ply};
use crestline::mesh::generate::{self, Sampling};
use crestline::mesh::Mesh;
use crestline::Result;

/// Read + build timings on large mesh files.
#[derive(Parser, Debug)]
struct Args {
    /// Directory holding the benchmark meshes (created if missing).
    #[arg(long, default_value = "bench-data")]
    out: PathBuf,
    /// Approximate number of triangles of a generated mesh.
    #[arg(long, default_value_t = 1_200_000)]
    triangles: usize,
    /// Timed repetitions per file.
    #[arg(long, default_value_t = 5, value_parser = clap::value_parser!(u32).range(1..))]
    repetitions: u32,
    /// Read and build this one file once, print its figures and exit.
    #[arg(long, value_name = "FILE", conflicts_with_all = ["out", "triangles", "repetitions"])]
    once: Option<PathBuf>,
}

/// Major and minor radius of the generated torus.
const TORUS_RADII: (f64, f64) = (3.0, 1.0);
/// Seed of the jitter, so that every run generates the same files.
const SEED: u64 = 7;

fn main() {
    let args = Args::parse();
    let outcome = match &args.once {
        Some(file) => once(file),
        None => benchmark(&args),
    };
    if let Err(e) = outcome {
        eprintln!("error: {e}");
        std::process::exit(1);
    }
}

/// The times of one read + build of a file.
struct Sample {
    read: f64,
    build: f64,
    /// Triangles in the file (before any repair).
    triangles: usize,
    /// Vertices of the built mesh.
    vertices: usize,
}

impl Sample {
    fn total(&self) -> f64 {
        self.read + self.build
    }

    /// The seconds of each reported stage, with its name.
    fn stages(&self) -> [(&'static str, f64); 3] {
        [
            ("read", self.read),
            ("build", self.build),
            ("read+build", self.total()),
        ]
    }
}

/// Read `file` and build its mesh, timing both stages. The mesh is dropped after
/// the clock stops.
fn measure(file: &Path) -> Result<Sample> {
    let start = Instant::now();
    let soup = read_mesh(file)?;
    let read = start.elapsed().as_secs_f64();
    let triangles = soup.triangles.len();
    let start = Instant::now();
    let (mesh, _) = Mesh::from_file_soup(soup, false)?;
    let build = start.elapsed().as_secs_f64();
    Ok(Sample {
        read,
        build,
        triangles,
        vertices: mesh.vertex_count(),
    })
}

/// `--once`: one read + build, printed as `key=value` pairs on one line.
fn once(file: &Path) -> Result<()> {
    let sample = measure(file)?;
    println!(
        "file={} triangles={} vertices={} read_s={:.6} build_s={:.6} read_build_s={:.6}",
        file.display(),
        sample.triangles,
        sample.vertices,
        sample.read,
        sample.build,
        sample.total()
    );
    Ok(())
}

/// The full benchmark: make the files if needed, then time each stage per file.
fn benchmark(args: &Args) -> Result<()> {
    let files = ensure_files(&args.out, args.triangles)?;
    println!(
        "{} repetitions per file, {} threads",
        args.repetitions,
        rayon::current_num_threads()
    );
    println!(
        "{:<10} {:<10} {:>10} {:>9} {:>10} {:>10} {:>12}",
        "file", "stage", "triangles", "min s", "median s", "min s/Mt", "median s/Mt"
    );
    for file in &files {
        let samples = (0..args.repetitions)
            .map(|_| measure(file))
            .collect::<Result<Vec<_>>>()?;
        let name = file.file_name().unwrap_or_default().to_string_lossy();
        let triangles = samples[0].triangles;
        for (k, (stage, _)) in samples[0].stages().into_iter().enumerate() {
            let (min, median) = min_median(samples.iter().map(|s| s.stages()[k].1).collect());
            let per_million = |s: f64| s * 1e6 / triangles as f64;
            println!(
                "{name:<10} {stage:<10} {triangles:>10} {min:>9.3} {median:>10.3} {:>10.3} {:>12.3}",
                per_million(min),
                per_million(median)
            );
        }
    }
    Ok(())
}

/// The smallest and the median of `values` (not empty).
fn min_median(mut values: Vec<f64>) -> (f64, f64) {
    values.sort_by(f64::total_cmp);
    let n = values.len();
    let median = if n % 2 == 1 {
        values[n / 2]
    } else {
        (values[n / 2 - 1] + values[n / 2]) / 2.0
    };
    (values[0], median)
}

/// `dir/torus.ply` and `dir/torus.obj`, written from a jittered torus with about
/// `triangles` triangles unless both exist already.
fn ensure_files(dir: &Path, triangles: usize) -> Result<[PathBuf; 2]> {
    let ply = dir.join("torus.ply");
    let obj = dir.join("torus.obj");
    if ply.is_file() && obj.is_file() {
        println!("using the existing {} and {}", ply.display(), obj.display());
        return Ok([ply, obj]);
    }
    std::fs::create_dir_all(dir).map_err(|e| crestline::Error::io(dir, e))?;
    let (major, minor) = TORUS_RADII;
    // A torus grid has two triangles per vertex.
    let torus = generate::torus(major, minor, triangles / 2, Sampling::jittered(SEED))?;
    write_ply(&ply, &torus.mesh, &[])?;
    write_obj(&obj, &torus.mesh)?;
    println!(
        "wrote {} and {} ({} triangles, {} vertices)",
        ply.display(),
        obj.display(),
        torus.mesh.face_count(),
        torus.mesh.vertex_count()
    );
    Ok([ply, obj])
}

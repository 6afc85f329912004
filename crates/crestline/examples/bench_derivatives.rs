//! Times the Gaussian derivatives of a synthetic volume ([`Derivatives`]): all 20
//! partials of order ≤ 3, and the 10 of order ≤ 2.
//!
//! ```text
//! cargo run --release --example bench_derivatives -- [SIZE] [SIGMA] [REPETITIONS]
//! ```
//!
//! The volume has `SIZE³` voxels (256 by default) of unit spacing; σ is `SIGMA`
//! voxels (1.5 by default). Prints, for each set of partials, the minimum over the
//! repetitions (3 by default) of the seconds for the whole set and the seconds per
//! output volume, with the number of threads used (set `RAYON_NUM_THREADS` to change
//! it). `tools/bench_derivatives.py` times scipy on the same work.

use std::time::Instant;

use crestline::volume::{Derivatives, Partial, Volume};
use nalgebra::Matrix3;

fn main() -> crestline::Result<()> {
    let mut args = std::env::args().skip(1);
    let size: usize = args.next().map_or(256, |s| s.parse().expect("a size"));
    let sigma: f64 = args.next().map_or(1.5, |s| s.parse().expect("a σ"));
    let repetitions: usize = args.next().map_or(3, |r| r.parse().expect("a count"));
    let volume = synthetic(size)?;
    println!(
        "{size}^3 voxels, sigma {sigma} voxels, {} threads",
        rayon::current_num_threads()
    );
    for max_order in [3, 2] {
        let mut best = f64::INFINITY;
        let mut outputs = 0;
        for _ in 0..repetitions {
            let start = Instant::now();
            let derivatives = Derivatives::new(&volume, sigma, max_order)?;
            best = best.min(start.elapsed().as_secs_f64());
            outputs = (0..20)
                .filter(|&n| derivatives.grid(Partial::ALL[n]).is_some())
                .count();
        }
        println!(
            "order <= {max_order}: {outputs} volumes in {best:.3} s, {:.4} s per volume",
            best / outputs as f64
        );
    }
    Ok(())
}

/// A smooth field with some high-frequency texture, `size³` unit voxels.
fn synthetic(size: usize) -> crestline::Result<Volume> {
    let n = size as f32;
    let mut samples = Vec::with_capacity(size * size * size);
    for k in 0..size {
        for j in 0..size {
            for i in 0..size {
                let [x, y, z] = [i, j, k].map(|v| v as f32 / n - 0.5);
                let blob = 1.0 - 4.0 * (x * x + 2.0 * y * y + 3.0 * z * z);
                let texture = 0.05 * ((i * 7 + j * 13 + k * 29) % 17) as f32;
                samples.push(blob + texture);
            }
        }
    }
    Volume::new([size; 3], [1.0; 3], [0.0; 3], Matrix3::identity(), samples)
}

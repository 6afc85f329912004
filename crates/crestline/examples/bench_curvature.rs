//! Curvature benchmark for comparison with the Python package: the time of
//! building the half-edge mesh from a triangle soup ([`Mesh::from_soup`]) and
//! estimating its curvature ([`estimate_curvature`]), the library calls that
//! `crestline.curvature(vertices, faces, estimator)` makes.
//!
//! ```sh
//! cargo run --release -p crestline --example bench_curvature -- MESH ESTIMATOR RUNS
//! cargo run --release -p crestline --example bench_curvature -- MESH
//! ```
//!
//! Both read MESH (any format crestline reads) into a soup once and check that
//! building it keeps every vertex in place, as the Python package requires. The
//! first form makes one untimed warm-up run of ESTIMATOR (`shape-operator` or
//! `jet-fit`), then times RUNS runs and prints one JSON line with the seconds of
//! every run and their median. The second reads one estimator name per line of
//! standard input and answers each with one JSON line for one timed run, so that a
//! driving process (`tools/bench_python_overhead.py`) can interleave these runs
//! with its own. Each run starts from a copy of the soup made outside the timer;
//! the time covers construction and estimation, and each line also gives the two
//! apart. The mesh and the field are dropped after the timer stops.

use std::io::BufRead;
use std::path::Path;
use std::time::Instant;

use crestline::curvature::{estimate_curvature, Estimator};
use crestline::io::read_mesh;
use crestline::mesh::{Mesh, TriangleSoup};
use crestline::{Error, Result};
use serde_json::json;

/// Seconds of construction and of estimation of one run.
fn run(soup: &TriangleSoup, estimator: Estimator) -> Result<(f64, f64)> {
    let soup = soup.clone();
    let start = Instant::now();
    let (mesh, _) = Mesh::from_soup(soup)?;
    let built = start.elapsed().as_secs_f64();
    let field = estimate_curvature(&mesh, estimator.build().as_ref())?;
    let total = start.elapsed().as_secs_f64();
    drop((mesh, field));
    Ok((built, total - built))
}

fn median(values: &[f64]) -> f64 {
    let mut sorted = values.to_vec();
    sorted.sort_by(f64::total_cmp);
    let n = sorted.len();
    if n % 2 == 1 {
        sorted[n / 2]
    } else {
        (sorted[n / 2 - 1] + sorted[n / 2]) / 2.0
    }
}

/// The soup of `path`, checked to be one that the Python package accepts.
fn read_soup(path: &Path) -> Result<TriangleSoup> {
    let soup = read_mesh(path)?;
    let (mesh, report) = Mesh::from_soup(soup.clone())?;
    if mesh.positions() != soup.positions.as_slice() {
        return Err(Error::Mesh(format!(
            "{}: building the mesh renumbers its vertices ({})",
            path.display(),
            report.messages().join("; ")
        )));
    }
    Ok(soup)
}

fn main() -> Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let Some(path) = args.first() else {
        eprintln!("usage: bench_curvature MESH [ESTIMATOR RUNS]");
        std::process::exit(2);
    };
    let soup = read_soup(Path::new(path))?;
    let (vertices, faces) = (soup.positions.len(), soup.triangles.len());
    match &args[1..] {
        [estimator, runs] => {
            let name = estimator.as_str();
            let estimator = name.parse()?;
            let runs: usize = runs
                .parse()
                .map_err(|e| Error::Argument(format!("runs {runs:?}: {e}")))?;
            run(&soup, estimator)?;
            let timed = (0..runs)
                .map(|_| run(&soup, estimator).map(|(b, e)| b + e))
                .collect::<Result<Vec<f64>>>()?;
            let line = json!({
                "estimator": name, "vertices": vertices, "faces": faces,
                "runs": runs, "median": median(&timed), "seconds": timed,
            });
            println!("{line}");
        }
        [] => {
            for name in std::io::stdin().lock().lines() {
                let name = name.map_err(|e| Error::io(Path::new("<stdin>"), e))?;
                let (build, estimate) = run(&soup, name.trim().parse()?)?;
                let line = json!({
                    "estimator": name.trim(), "vertices": vertices, "faces": faces,
                    "seconds": build + estimate, "build": build, "estimate": estimate,
                });
                println!("{line}");
            }
        }
        _ => {
            eprintln!("usage: bench_curvature MESH [ESTIMATOR RUNS]");
            std::process::exit(2);
        }
    }
    Ok(())
}

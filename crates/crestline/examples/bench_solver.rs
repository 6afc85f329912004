//! Times the sparse symmetric positive definite solve of the implicit curvature
//! smoothing step `(M + t K) e' = M e` (Hildebrandt et al. 2005, §5.1) on a jittered
//! torus, for two backends:
//!
//! - sprs-ldl: `LDLᵀ` with a reverse Cuthill–McKee ordering, single-threaded;
//! - faer through [`CholeskyFactor`]: supernodal `LLᵀ` with an approximate minimum
//!   degree ordering, on all cores and on one.
//!
//! `M` is the lumped mass, `K` the cotan Laplacian with weights clamped at 0, and
//! `t = 2 h̄²` with `h̄` the mean edge length. Both solutions are checked: relative
//! residual below 1e-10 and agreement within 1e-8.
//!
//! ```text
//! cargo run --release --example bench_solver -- [VERTICES] [--ldl-max-fill N] [--skip-ldl]
//! ```
//!
//! sprs-ldl's band-like fill grows quickly with the mesh; its numeric factorization
//! is skipped (after reporting the fill of its symbolic analysis) when the factor
//! would hold more than `--ldl-max-fill` nonzeros (default 150 million).

use std::time::Instant;

use crestline::linalg::{CholeskyFactor, SymmetricBuilder, SymmetricMatrix};
use crestline::mesh::generate::{self, Sampling};
use crestline::mesh::Mesh;
use sprs::{CsMat, FillInReduction, SymmetryCheck};
use sprs_ldl::Ldl;

/// Reads the seconds of one stage from a backend's timings.
type Stage = fn(&Timings) -> Option<f64>;

/// Runs of the faer factorization, of which the fastest counts.
const REPEATS: usize = 2;

/// Command line options.
struct Options {
    vertices: usize,
    ldl_max_fill: usize,
    skip_ldl: bool,
}

/// Seconds taken by each stage of one backend; `None` where it did not run.
#[derive(Default)]
struct Timings {
    symbolic: Option<f64>,
    numeric: Option<f64>,
    factor: Option<f64>,
    solve: Option<f64>,
    solve5: Option<f64>,
    solve_xyz: Option<f64>,
}

fn main() -> crestline::Result<()> {
    let options = parse_options()?;
    let (mesh, seconds) =
        timed(|| generate::torus(1.0, 0.35, options.vertices, Sampling::jittered(1)));
    let mesh = mesh?.mesh;
    println!(
        "jittered torus: {} vertices, {} faces ({seconds:.2} s)",
        mesh.vertex_count(),
        mesh.face_count()
    );
    let h = mesh.mean_edge_length();
    let ((matrix, b), seconds) = timed(|| smoothing_system(&mesh, 2.0 * h * h));
    println!(
        "assembled M + t K: n = {}, nnz = {} ({seconds:.2} s)",
        matrix.size(),
        matrix.csc().1.len()
    );

    // A first, untimed run warms up the thread pool and the allocator.
    bench_faer(&matrix, &b, faer::Par::rayon(0))?;
    let (faer_seq, _) = bench_faer(&matrix, &b, faer::Par::Seq)?;
    let (faer, x_faer) = bench_faer(&matrix, &b, faer::Par::rayon(0))?;
    let (ldl, x_ldl) = if options.skip_ldl {
        (Timings::default(), None)
    } else {
        bench_ldl(&matrix, &b, options.ldl_max_fill)
    };

    check("faer", &matrix, &x_faer, &b);
    if let Some(x_ldl) = &x_ldl {
        check("sprs-ldl", &matrix, x_ldl, &b);
        let difference = relative_difference(x_ldl, &x_faer);
        println!("‖x_ldl − x_faer‖ / ‖x_faer‖ = {difference:.2e}");
        assert!(difference < 1e-8, "the two solutions differ");
    }
    print_table(&ldl, &faer, &faer_seq);
    Ok(())
}

/// Reads `[VERTICES] [--ldl-max-fill N] [--skip-ldl]`.
fn parse_options() -> crestline::Result<Options> {
    let mut options = Options {
        vertices: 1_000_000,
        ldl_max_fill: 150_000_000,
        skip_ldl: false,
    };
    let mut args = std::env::args().skip(1);
    while let Some(arg) = args.next() {
        match arg.as_str() {
            "--skip-ldl" => options.skip_ldl = true,
            "--ldl-max-fill" => options.ldl_max_fill = parse_count(args.next())?,
            _ => options.vertices = parse_count(Some(arg))?,
        }
    }
    Ok(options)
}

/// A positive count, accepting `_` separators (`1_000_000`).
fn parse_count(arg: Option<String>) -> crestline::Result<usize> {
    let arg = arg.unwrap_or_default();
    arg.replace('_', "")
        .parse()
        .map_err(|_| crestline::Error::Argument(format!("expected a count, got '{arg}'")))
}

/// The matrix `M + t K` and the right-hand side `M e` for a smooth test function `e`.
fn smoothing_system(mesh: &Mesh, t: f64) -> (SymmetricMatrix, Vec<f64>) {
    let masses = mesh.vertex_areas();
    let mut builder =
        SymmetricBuilder::with_capacity(mesh.vertex_count(), 4 * mesh.edge_count() + masses.len());
    for (v, &mass) in masses.iter().enumerate() {
        builder.add_diagonal(v, mass);
    }
    for (e, w) in mesh.edges().zip(mesh.cotan_weights()) {
        let [p, q] = mesh.edge_vertices(e);
        builder.add_edge(p.idx(), q.idx(), t * w.max(0.0));
    }
    let b = mesh
        .positions()
        .iter()
        .zip(&masses)
        .map(|(p, m)| m * (3.0 * p.x * p.y + p.z).sin())
        .collect();
    (builder.build(), b)
}

/// Times faer through [`CholeskyFactor`] with the given parallelism. The symbolic
/// analysis is the time of [`CholeskyFactor::new`] minus that of a numeric-only
/// [`CholeskyFactor::refactor`] with the same matrix, each the best of a few runs.
fn bench_faer(
    matrix: &SymmetricMatrix,
    b: &[f64],
    par: faer::Par,
) -> crestline::Result<(Timings, Vec<f64>)> {
    faer::set_global_parallelism(par);
    let (factor, mut factor_seconds) = timed(|| CholeskyFactor::new(matrix));
    let mut factor = factor?;
    let mut numeric_seconds = f64::INFINITY;
    for _ in 0..REPEATS {
        let (refactored, seconds) = timed(|| factor.refactor(matrix));
        refactored?;
        numeric_seconds = numeric_seconds.min(seconds);
        factor_seconds = factor_seconds.min(timed(|| CholeskyFactor::new(matrix)).1);
    }
    let (x, solve) = timed(|| factor.solve(b));
    let ((), solve5) = timed(|| (0..5).for_each(|_| drop(factor.solve(b))));
    let mut columns = vec![b.to_vec(); 3];
    let ((), solve_xyz) = timed(|| factor.solve_columns(&mut columns));
    let timings = Timings {
        symbolic: Some(factor_seconds - numeric_seconds),
        numeric: Some(numeric_seconds),
        factor: Some(factor_seconds),
        solve: Some(solve),
        solve5: Some(solve5),
        solve_xyz: Some(solve_xyz),
    };
    Ok((timings, x))
}

/// Times sprs-ldl; the numeric stages only run if the factor has at most
/// `max_fill` nonzeros.
fn bench_ldl(matrix: &SymmetricMatrix, b: &[f64], max_fill: usize) -> (Timings, Option<Vec<f64>>) {
    let (col_ptr, rows, values) = matrix.csc();
    let n = matrix.size();
    let matrix = CsMat::new_csc((n, n), col_ptr.to_vec(), rows.to_vec(), values.to_vec());
    let ldl = Ldl::new()
        .fill_in_reduction(FillInReduction::ReverseCuthillMcKee)
        .check_symmetry(SymmetryCheck::DontCheckSymmetry);
    let (symbolic, symbolic_seconds) = timed(|| ldl.symbolic(matrix.view()));
    let fill = symbolic.nnz();
    println!(
        "sprs-ldl: L has {fill} nonzeros ({:.1} GiB), symbolic {symbolic_seconds:.2} s",
        (fill * 16) as f64 / (1u64 << 30) as f64
    );
    let mut timings = Timings {
        symbolic: Some(symbolic_seconds),
        ..Timings::default()
    };
    if fill > max_fill {
        println!("sprs-ldl: numeric factorization skipped (fill above {max_fill})");
        return (timings, None);
    }
    let (numeric, numeric_seconds) = timed(|| symbolic.factor(matrix.view()));
    let Ok(numeric) = numeric else {
        println!("sprs-ldl: numeric factorization failed");
        return (timings, None);
    };
    let (x, solve) = timed(|| numeric.solve(b));
    let ((), solve5) = timed(|| (0..5).for_each(|_| drop(numeric.solve(b))));
    timings.numeric = Some(numeric_seconds);
    timings.factor = Some(symbolic_seconds + numeric_seconds);
    timings.solve = Some(solve);
    timings.solve5 = Some(solve5);
    (timings, Some(x))
}

/// Prints ‖A x − b‖ / ‖b‖ and fails if it is not below 1e-10.
fn check(name: &str, matrix: &SymmetricMatrix, x: &[f64], b: &[f64]) {
    let mut ax = vec![0.0; b.len()];
    for (i, j, value) in matrix.entries() {
        ax[i] += value * x[j];
    }
    let residual = relative_difference(&ax, b);
    println!("{name}: ‖Ax − b‖ / ‖b‖ = {residual:.2e}");
    assert!(residual < 1e-10, "{name}: residual too large");
}

/// ‖a − b‖ / ‖b‖.
fn relative_difference(a: &[f64], b: &[f64]) -> f64 {
    let difference: f64 = a.iter().zip(b).map(|(p, q)| (p - q).powi(2)).sum();
    let norm: f64 = b.iter().map(|q| q * q).sum();
    (difference / norm).sqrt()
}

fn print_table(ldl: &Timings, faer: &Timings, faer_seq: &Timings) {
    let threads = rayon::current_num_threads();
    println!();
    println!(
        "{:<30} {:>12} {:>12} {:>12} {:>16}",
        "seconds",
        "sprs-ldl",
        "faer 1 thr",
        format!("faer {threads} thr"),
        "sprs-ldl / faer"
    );
    let rows: [(&str, Stage); 6] = [
        ("symbolic analysis", |t| t.symbolic),
        ("numeric factorization", |t| t.numeric),
        ("analysis + factorization", |t| t.factor),
        ("1 solve", |t| t.solve),
        ("5 solves", |t| t.solve5),
        ("3-column solve (x, y, z)", |t| t.solve_xyz),
    ];
    for (label, get) in rows {
        let ratio = get(ldl).zip(get(faer)).map(|(l, f)| l / f);
        println!(
            "{label:<30} {:>12} {:>12} {:>12} {:>16}",
            cell(get(ldl)),
            cell(get(faer_seq)),
            cell(get(faer)),
            ratio.map_or("—".to_string(), |r| format!("{r:.1}×"))
        );
    }
}

fn cell(seconds: Option<f64>) -> String {
    seconds.map_or("—".to_string(), |s| format!("{s:.3}"))
}

/// The result of `f` and the seconds it took.
fn timed<T>(f: impl FnOnce() -> T) -> (T, f64) {
    let start = Instant::now();
    let result = f();
    (result, start.elapsed().as_secs_f64())
}

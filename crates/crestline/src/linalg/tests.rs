//! Sparse Cholesky solves against dense solves and residuals, and the conjugate
//! gradient method against the factorization, on the systems of the implicit
//! smoothing steps (M + t K) x' = M x (Hildebrandt et al. 2005, §5.1).

use nalgebra::{DMatrix, DVector};

use super::{
    conjugate_gradient, CgSettings, CholeskyFactor, Multigrid, Pair, Solver, SpdSolver,
    SymmetricBuilder, SymmetricMatrix, ITERATIVE_MIN_SIZE,
};
use crate::mesh::generate::{self, Sampling};
use crate::mesh::{EdgeId, Mesh};
use crate::Error;

/// The 1D Poisson matrix tridiag(−1, 2, −1) plus `shift` times the identity.
fn poisson_1d(n: usize, shift: f64) -> SymmetricMatrix {
    let mut builder = SymmetricBuilder::new(n);
    for i in 0..n {
        builder.add_diagonal(i, 2.0 + shift);
        if i + 1 < n {
            builder.add(i, i + 1, -1.0);
        }
    }
    builder.build()
}

/// `M + t K` of §5.1: lumped masses plus `t` times the cotan Laplacian with
/// weights clamped at 0.
fn mass_plus_stiffness(mesh: &Mesh, t: f64) -> SymmetricMatrix {
    let mut builder = SymmetricBuilder::new(mesh.vertex_count());
    for (v, mass) in mesh.vertex_areas().into_iter().enumerate() {
        builder.add_diagonal(v, mass);
    }
    for (e, w) in mesh.edges().zip(mesh.cotan_weights()) {
        let [p, q] = mesh.edge_vertices(e);
        builder.add_edge(p.idx(), q.idx(), t * w.max(0.0));
    }
    builder.build()
}

pub(super) fn dense(matrix: &SymmetricMatrix) -> DMatrix<f64> {
    let mut a = DMatrix::zeros(matrix.size(), matrix.size());
    for (i, j, value) in matrix.entries() {
        a[(i, j)] += value;
    }
    a
}

fn relative_residual(matrix: &SymmetricMatrix, x: &[f64], b: &[f64]) -> f64 {
    let mut ax = vec![0.0; matrix.size()];
    for (i, j, value) in matrix.entries() {
        ax[i] += value * x[j];
    }
    let r: f64 = ax.iter().zip(b).map(|(p, q)| (p - q).powi(2)).sum();
    let bn: f64 = b.iter().map(|q| q * q).sum();
    (r / bn).sqrt()
}

fn max_abs_difference(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(p, q)| (p - q).abs())
        .fold(0.0, f64::max)
}

fn rhs(n: usize, phase: f64) -> Vec<f64> {
    (0..n).map(|i| (i as f64 * 0.37 + phase).sin()).collect()
}

#[test]
fn poisson_matches_dense_solve() {
    let n = 40;
    let matrix = poisson_1d(n, 1.0);
    let b = rhs(n, 0.0);
    let x = CholeskyFactor::new(&matrix).unwrap().solve(&b);
    let expected = dense(&matrix)
        .cholesky()
        .unwrap()
        .solve(&DVector::from_vec(b));
    assert!(max_abs_difference(&x, expected.as_slice()) < 1e-12);
}

#[test]
fn sphere_smoothing_system_has_small_residual() {
    let mesh = generate::sphere(1.0, 2000, Sampling::jittered(3))
        .unwrap()
        .mesh;
    let h = mesh.mean_edge_length();
    let matrix = mass_plus_stiffness(&mesh, 2.0 * h * h);
    let factor = CholeskyFactor::new(&matrix).unwrap();
    let b: Vec<f64> = mesh.positions().iter().map(|p| p.x * p.y + p.z).collect();
    let x = factor.solve(&b);
    assert!(relative_residual(&matrix, &x, &b) < 1e-10);
}

#[test]
fn negative_identity_is_an_error() {
    let mut builder = SymmetricBuilder::new(5);
    for i in 0..5 {
        builder.add_diagonal(i, -1.0);
    }
    let err = CholeskyFactor::new(&builder.build()).unwrap_err();
    assert!(matches!(err, Error::Argument(_)), "{err}");
    assert!(err.to_string().contains("not positive definite"), "{err}");
}

#[test]
fn indefinite_matrix_is_an_error() {
    let mut builder = SymmetricBuilder::new(2);
    builder.add_diagonal(0, 1.0);
    builder.add_diagonal(1, 1.0);
    builder.add(0, 1, 2.0);
    assert!(CholeskyFactor::new(&builder.build()).is_err());
}

#[test]
fn non_square_and_nan_matrices_are_errors() {
    // Two columns of three rows cannot be a square matrix.
    let rectangular = SymmetricMatrix::from_csc(3, vec![0, 1, 2], vec![0, 1], vec![1.0, 1.0]);
    assert!(rectangular.is_err());
    let mut builder = SymmetricBuilder::new(2);
    builder.add_diagonal(0, 1.0);
    builder.add_diagonal(1, f64::NAN);
    let err = CholeskyFactor::new(&builder.build()).unwrap_err();
    assert!(err.to_string().contains("not finite"), "{err}");
}

#[test]
fn the_builder_sums_repeated_entries_into_sorted_columns() {
    let mut builder = SymmetricBuilder::new(3);
    builder.add(2, 0, 1.5);
    builder.add_diagonal(1, 4.0);
    builder.add_edge(0, 1, 2.0);
    builder.add(0, 2, 0.5);
    let matrix = builder.build();
    let entries: Vec<(usize, usize, f64)> = matrix.entries().collect();
    assert_eq!(
        entries,
        [
            (0, 0, 2.0),
            (1, 0, -2.0),
            (2, 0, 2.0),
            (0, 1, -2.0),
            (1, 1, 6.0),
            (0, 2, 2.0),
        ]
    );
    let (col_ptr, rows, values) = matrix.csc();
    let copy = SymmetricMatrix::from_csc(3, col_ptr.to_vec(), rows.to_vec(), values.to_vec());
    assert_eq!(copy.unwrap(), matrix);
    let unsorted = SymmetricMatrix::from_csc(2, vec![0, 2, 2], vec![1, 0], vec![1.0, 1.0]);
    assert!(unsorted.unwrap_err().to_string().contains("unsorted"));
}

/// M + t K of a jittered sphere of about `vertices` vertices (jitter `seed`)
/// with the sign-aware cotan Laplacian of §5.1, t = 2 h̄² (the default τ), each edge (p, q) scaled by
/// `stiffness_and_sign(p, q).0` and signed by its `.1`, and the right-hand side
/// M e for the smooth e = `field(position)`.
pub(super) fn smoothing_system(
    vertices: usize,
    seed: u64,
    stiffness_and_sign: impl Fn(usize, usize) -> (f64, f64),
    field: impl Fn(&crate::Point) -> f64,
) -> (SymmetricMatrix, Vec<f64>) {
    let mesh = generate::sphere(1.0, vertices, Sampling::jittered(seed))
        .unwrap()
        .mesh;
    let h = mesh.mean_edge_length();
    let mass = mesh.vertex_areas();
    let mut system = SymmetricBuilder::new(mesh.vertex_count());
    for (v, &m) in mass.iter().enumerate() {
        system.add_diagonal(v, m);
    }
    for (e, w) in mesh.clamped_cotan_weights().into_iter().enumerate() {
        let [p, q] = mesh.edge_vertices(EdgeId(e as u32)).map(|v| v.idx());
        let (stiffness, sign) = stiffness_and_sign(p, q);
        let w = 2.0 * h * h * w * stiffness;
        system.add_diagonal(p, w);
        system.add_diagonal(q, w);
        system.add(p, q, -w * sign);
    }
    let rhs = mesh
        .positions()
        .iter()
        .zip(&mass)
        .map(|(p, m)| m * field(p))
        .collect();
    (system.build(), rhs)
}

/// M + t K of a sphere with the cotan Laplacian, and M e for a smooth e.
fn sphere_system() -> (SymmetricMatrix, Vec<f64>) {
    smoothing_system(
        30_000,
        3,
        |_, _| (1.0, 1.0),
        |p| (3.0 * p.x + p.y * p.z).sin(),
    )
}

#[test]
fn conjugate_gradient_meets_its_tolerance_on_a_sphere() {
    let (matrix, rhs) = sphere_system();
    let settings = CgSettings::default();
    let mut x = rhs.clone();
    let report = conjugate_gradient(&matrix, &rhs, &mut x, settings).unwrap();
    eprintln!("{report:?}");
    assert!(report.converged);
    assert!(report.iterations > 1 && report.iterations < settings.max_iterations);
    assert!(report.relative_residual <= settings.tolerance);
    assert!(relative_residual(&matrix, &x, &rhs) <= settings.tolerance);
    let exact = CholeskyFactor::new(&matrix).unwrap().solve(&rhs);
    let scale = exact.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    for (a, b) in x.iter().zip(&exact) {
        assert!((a - b).abs() <= 1e-8 * scale);
    }
}

#[test]
fn conjugate_gradient_capped_at_one_iteration_falls_back_to_the_factorization() {
    let (matrix, rhs) = sphere_system();
    let capped = CgSettings {
        max_iterations: 1,
        ..CgSettings::default()
    };
    let mut x = rhs.clone();
    let report = conjugate_gradient(&matrix, &rhs, &mut x, capped).unwrap();
    assert!(!report.converged && report.iterations == 1);

    let exact = CholeskyFactor::new(&matrix).unwrap().solve(&rhs);
    let mut solver = SpdSolver::new(Solver::Iterative, capped);
    solver.set_matrix(matrix.clone()).unwrap();
    for _ in 0..2 {
        let mut x = rhs.clone();
        solver
            .solve(&rhs, &mut x, &mut crate::progress::Silent)
            .unwrap();
        assert!(relative_residual(&matrix, &x, &rhs) < 1e-12);
        let scale = exact.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        for (a, b) in x.iter().zip(&exact) {
            assert!((a - b).abs() <= 1e-12 * scale);
        }
    }
}

#[test]
fn auto_takes_the_iteration_only_for_large_systems() {
    let (matrix, _) = sphere_system();
    assert_eq!(
        Solver::Auto.resolve(matrix.size()),
        Solver::Direct,
        "30k unknowns"
    );
    assert_eq!(Solver::Iterative.resolve(matrix.size()), Solver::Iterative);
    assert_eq!(Solver::Direct.resolve(matrix.size()), Solver::Direct);
    assert_eq!(Solver::Auto.resolve(ITERATIVE_MIN_SIZE - 1), Solver::Direct);
    assert_eq!(Solver::Auto.resolve(ITERATIVE_MIN_SIZE), Solver::Iterative);
}

/// A deterministic hash of an edge, for its sign and its stiffness.
fn edge_hash(p: usize, q: usize) -> u64 {
    let key = (p.min(q) as u64) << 32 | p.max(q) as u64;
    key.wrapping_mul(0x9E37_79B9_7F4A_7C15) >> 40
}

/// The stiffness and sign of every edge (p, q) for [`smoothing_system`]: one edge
/// in `every` (by [`edge_hash`]) `factor` times stiffer, σ from `signs`.
pub(super) fn stiff_edges(
    every: u64,
    factor: f64,
    signs: impl Fn(usize, usize) -> f64,
) -> impl Fn(usize, usize) -> (f64, f64) {
    move |p, q| {
        let stiffer = edge_hash(p, q).is_multiple_of(every);
        (if stiffer { factor } else { 1.0 }, signs(p, q))
    }
}

/// M + t K of a jittered sphere with the sign-aware Laplacian of §5.1 (each edge's
/// σ = ±1 from `signs`) and one edge in 40 made 10⁴ times stiffer, like a scan's
/// slivers, with a right-hand side M e for a smooth e.
fn sliver_system(signs: impl Fn(usize, usize) -> f64) -> (SymmetricMatrix, Vec<f64>) {
    smoothing_system(30_000, 5, stiff_edges(40, 1e4, signs), |p| {
        (2.0 * p.x - p.y * p.z).cos()
    })
}

pub(super) fn random_sign(p: usize, q: usize) -> f64 {
    if edge_hash(p, q).is_multiple_of(3) {
        -1.0
    } else {
        1.0
    }
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

#[test]
fn the_v_cycle_is_symmetric_and_positive_definite() {
    let (matrix, _) = sliver_system(random_sign);
    let multigrid = Multigrid::new(&matrix).unwrap();
    assert!(multigrid.depth() >= 3, "{} levels", multigrid.depth());
    let vectors: Vec<Vec<f64>> = (0..3).map(|k| rhs(matrix.size(), k as f64)).collect();
    // One set of buffers for every cycle: what one cycle leaves in them must not
    // change the next.
    let mut buffers = multigrid.buffers();
    let images: Vec<Vec<f64>> = vectors
        .iter()
        .map(|v| {
            let mut z = vec![0.0; v.len()];
            multigrid.apply(v, &mut z, &mut buffers);
            z
        })
        .collect();
    for (a, za) in vectors.iter().zip(&images) {
        assert!(dot(a, za) > 0.0);
        for (b, zb) in vectors.iter().zip(&images) {
            let (ab, ba) = (dot(za, b), dot(a, zb));
            assert!(
                (ab - ba).abs() <= 1e-10 * ab.abs().max(ba.abs()),
                "{ab} ≠ {ba}"
            );
        }
    }
}

/// Iterations of the multigrid-preconditioned conjugate gradient method on the
/// sliver system with the signs `signs`, checked against the factorization.
fn iterations_on_slivers(signs: impl Fn(usize, usize) -> f64) -> usize {
    let (matrix, rhs) = sliver_system(signs);
    let mut x = vec![0.0; rhs.len()];
    let report = conjugate_gradient(&matrix, &rhs, &mut x, CgSettings::default()).unwrap();
    assert!(report.converged, "{report:?}");
    let exact = CholeskyFactor::new(&matrix).unwrap().solve(&rhs);
    let scale = exact.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    assert!(max_abs_difference(&x, &exact) <= 1e-6 * scale);
    report.iterations
}

#[test]
fn multigrid_resolves_stiff_edges_whatever_their_signs() {
    let unsigned = iterations_on_slivers(|_, _| 1.0);
    let signed = iterations_on_slivers(random_sign);
    eprintln!("iterations: {unsigned} with σ = +1, {signed} with random σ");
    // A tentative basis blind to the signs needs about 200.
    assert!(unsigned <= 40, "{unsigned} iterations");
    assert!(signed <= unsigned + 10, "{signed} against {unsigned}");
}

#[test]
fn solver_names_round_trip() {
    for &name in Solver::NAMES {
        assert_eq!(name.parse::<Solver>().unwrap().name(), name);
    }
    assert!("cholesky".parse::<Solver>().is_err());
    assert_eq!(Solver::default(), Solver::Auto);
}

#[test]
fn stiff_blocks_hold_the_stiff_edges_and_invert_their_blocks() {
    use super::stiff_blocks::{Relax, StiffBlocks, MAX_BLOCK};
    let (matrix, _) = sliver_system(random_sign);
    let n = matrix.size();
    let piece = n.div_ceil(8);
    let blocks = StiffBlocks::new(&matrix, piece).expect("the slivers' edges are stiff");
    let mut block_of = vec![usize::MAX; n];
    let mut count = 0;
    for i in 0..n {
        let Relax::Block { members, inverse } = blocks.at(i) else {
            continue;
        };
        let k = members.len();
        assert!((2..=MAX_BLOCK).contains(&k), "{k} members");
        assert_eq!(
            members[0] as usize, i,
            "a block is relaxed at its first member"
        );
        assert!(members.windows(2).all(|w| w[0] < w[1]));
        assert!(members.iter().all(|&m| m as usize / piece == i / piece));
        // The inverse times the block (with the ℓ1 terms of other pieces) is I.
        for (r, &p) in members.iter().enumerate() {
            block_of[p as usize] = count;
            let mut row = vec![0.0; k];
            for (j, v) in matrix.column(p as usize) {
                match members.iter().position(|&m| m as usize == j) {
                    Some(c) => row[c] += v,
                    None if j / piece != p as usize / piece => row[r] += v.abs(),
                    None => {}
                }
            }
            for c in 0..k {
                let product: f64 = (0..k).map(|s| inverse[c * k + s] * row[s]).sum();
                let expected = if c == r { 1.0 } else { 0.0 };
                assert!((product - expected).abs() < 1e-9, "{product} ≠ {expected}");
            }
        }
        count += 1;
    }
    // Every coupling of nearly its diagonals' size inside a piece (a sliver's
    // edge: weights clamped to 0 stay 0 when made stiffer) joins one block: the
    // slivers are far apart, so no block reaches its size cap.
    let diagonal = matrix.diagonal();
    let mut stiffest = 0;
    for j in 0..n {
        for (i, v) in matrix.column(j) {
            if i < j && i / piece == j / piece && v * v >= 0.81 * diagonal[i] * diagonal[j] {
                assert!(block_of[i] != usize::MAX && block_of[i] == block_of[j]);
                stiffest += 1;
            }
        }
    }
    assert!(stiffest > 500, "{stiffest} sliver edges");
    // An edge of the usual weight is not stiff: the blocks are the slivers'.
    let members = (0..n).filter(|&i| block_of[i] != usize::MAX).count();
    assert!(members < n / 5, "{members} of {n} unknowns in blocks");
}

#[test]
fn block_relaxation_speeds_up_moderately_stiff_systems() {
    // One edge in five 50 times stiffer, like the many short edges of a scan
    // (rather than the few extreme slivers of `sliver_system`): relaxed one
    // unknown at a time, 17 iterations; with the stiff pairs relaxed together, 14.
    let (matrix, rhs) = smoothing_system(30_000, 5, stiff_edges(5, 50.0, random_sign), |p| {
        (2.0 * p.x - p.y * p.z).cos()
    });
    let mut x = vec![0.0; rhs.len()];
    let report = conjugate_gradient(&matrix, &rhs, &mut x, CgSettings::default()).unwrap();
    assert!(report.converged, "{report:?}");
    assert!(report.iterations <= 15, "{} iterations", report.iterations);
}

#[test]
fn two_right_hand_sides_in_lockstep_are_solved_as_each_alone() {
    let (matrix, first) = sphere_system();
    let second: Vec<f64> = (0..first.len()).map(|i| (0.37 * i as f64).cos()).collect();
    // The second starts near its solution: it converges first.
    let near: Vec<f64> = CholeskyFactor::new(&matrix)
        .unwrap()
        .solve(&second)
        .iter()
        .enumerate()
        .map(|(i, x)| x * (1.0 + 1e-6 * (i as f64).sin()))
        .collect();
    let settings = CgSettings::default();
    let alone = |b: &[f64], start: &[f64]| {
        let mut x = start.to_vec();
        let report = conjugate_gradient(&matrix, b, &mut x, settings).unwrap();
        (x, report.iterations)
    };
    let (x0, n0) = alone(&first, &vec![0.0; first.len()]);
    let (x1, n1) = alone(&second, &near);
    assert!(n1 < n0, "{n1} iterations against {n0}");
    let b: Vec<Pair> = first
        .iter()
        .zip(&second)
        .map(|(&a, &b)| Pair([a, b]))
        .collect();
    let mut x: Vec<Pair> = near.iter().map(|&x| Pair([0.0, x])).collect();
    let report = conjugate_gradient(&matrix, &b, &mut x, settings).unwrap();
    assert!(report.converged && report.relative_residual <= settings.tolerance);
    assert_eq!(report.iterations, n0);
    // The vector that converged first stopped where it converged alone.
    for (k, alone) in [x0, x1].iter().enumerate() {
        let lane: Vec<f64> = x.iter().map(|x| x.0[k]).collect();
        let scale = alone.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        assert!(
            max_abs_difference(&lane, alone) <= 1e-12 * scale,
            "lane {k}"
        );
    }
}

#[test]
fn a_vector_solved_already_or_zero_does_not_move_in_lockstep() {
    let (matrix, rhs) = sphere_system();
    let exact = CholeskyFactor::new(&matrix).unwrap().solve(&rhs);
    for other in [0.0, 1.0] {
        // Lane 0: the exact solution as the start; lane 1: a zero right-hand
        // side (other = 0) or the system again from zero.
        let b: Vec<Pair> = rhs.iter().map(|&v| Pair([v, other * v])).collect();
        let mut x: Vec<Pair> = exact.iter().map(|&v| Pair([v, 0.0])).collect();
        let report = conjugate_gradient(&matrix, &b, &mut x, CgSettings::default()).unwrap();
        assert!(report.converged, "{report:?}");
        assert!(
            x.iter().zip(&exact).all(|(x, &e)| x.0[0] == e),
            "lane 0 moved"
        );
        let lane: Vec<f64> = x.iter().map(|x| x.0[1]).collect();
        assert!(lane.iter().all(|v| v.is_finite()));
        if other == 0.0 {
            assert!(lane.iter().all(|&v| v == 0.0));
        } else {
            assert!(relative_residual(&matrix, &lane, &rhs) <= 1e-10);
        }
    }
}

#[test]
fn a_start_along_the_solution_is_scaled_onto_it() {
    // The energy-best multiple of a start parallel to the solution is the
    // solution: no iteration is left to do, whatever the start's length (the
    // previous smoothing step of a rough field is far too long).
    let (matrix, rhs) = sphere_system();
    let exact = CholeskyFactor::new(&matrix).unwrap().solve(&rhs);
    for scale in [1e3, -2.0, 1e-6] {
        let mut x: Vec<f64> = exact.iter().map(|v| v * scale).collect();
        let report = conjugate_gradient(&matrix, &rhs, &mut x, CgSettings::default()).unwrap();
        assert!(report.converged, "{report:?}");
        assert_eq!(report.iterations, 0, "start scaled by {scale}");
        let size = exact.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        assert!(max_abs_difference(&x, &exact) <= 1e-9 * size);
    }
}

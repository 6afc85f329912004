//! Gaussian derivatives and cubic B-splines of volumes, against closed forms:
//! cubic polynomials (differentiated exactly by the moment-corrected kernels and
//! reproduced by the spline) and a Gaussian blob (whose smoothed derivatives are
//! Gaussians again).

use crate::volume::{BSpline, Derivatives, Jet, Partial, ThirdOrder, Volume};
use crate::{Error, Point, Vector};
use nalgebra::Matrix3;

/// A small deterministic generator of numbers in `[-1, 1)`.
struct Lcg(u64);

impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((self.0 >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    }
}

/// `Σ coef · ((x − center) / scale)^α` over the 20 monomials of degree ≤ 3 (the
/// exponents of [`Partial::ALL`]).
struct Cubic {
    coefficients: [f64; 20],
    center: Point,
    scale: f64,
}

impl Cubic {
    fn random(seed: u64, center: Point, scale: f64) -> Cubic {
        let mut rng = Lcg(seed);
        Cubic {
            coefficients: std::array::from_fn(|_| rng.next()),
            center,
            scale,
        }
    }

    /// The natural size of the derivatives of each order: `Σ|coef| / scaleᵐ`.
    fn magnitudes(&self) -> [f64; 4] {
        let sum: f64 = self.coefficients.iter().map(|c| c.abs()).sum();
        [0, 1, 2, 3].map(|m| sum / self.scale.powi(m))
    }

    /// `∂^d p` at `x`.
    fn derivative(&self, x: &Point, d: [usize; 3]) -> f64 {
        let u = (x - self.center) / self.scale;
        let mut sum = 0.0;
        for (c, p) in self.coefficients.iter().zip(Partial::ALL) {
            let e = p.orders();
            let mut term = *c;
            for axis in 0..3 {
                if d[axis] > e[axis] {
                    term = 0.0;
                    break;
                }
                let falling: usize = (e[axis] - d[axis] + 1..=e[axis]).product();
                term *= falling as f64 * u[axis].powi((e[axis] - d[axis]) as i32)
                    / self.scale.powi(d[axis] as i32);
            }
            sum += term;
        }
        sum
    }

    /// `∂^d (G_σ * p) = ∂^d p + σ²/2 Σᵢ ∂^(d + 2eᵢ) p` (exact for cubics).
    fn smoothed_derivative(&self, x: &Point, d: [usize; 3], sigma: f64) -> f64 {
        let laplacian: f64 = (0..3)
            .map(|axis| {
                let mut dd = d;
                dd[axis] += 2;
                self.derivative(x, dd)
            })
            .sum();
        self.derivative(x, d) + sigma * sigma / 2.0 * laplacian
    }

    /// The jet of `G_σ * p` at `x` (σ = 0: of `p`).
    fn smoothed_jet(&self, x: &Point, sigma: f64) -> Jet {
        let values = Partial::ALL.map(|p| self.smoothed_derivative(x, p.orders(), sigma));
        Jet::from_partials(&values)
    }

    fn volume(&self, dims: [usize; 3], spacing: [f64; 3], direction: Matrix3<f64>) -> Volume {
        sampled(dims, spacing, direction, |x| self.derivative(x, [0, 0, 0]))
    }
}

/// A volume centred on the world origin sampling `field`.
fn sampled(
    dims: [usize; 3],
    spacing: [f64; 3],
    direction: Matrix3<f64>,
    field: impl Fn(&Point) -> f64,
) -> Volume {
    let half = Vector::new(
        (dims[0] - 1) as f64 * spacing[0],
        (dims[1] - 1) as f64 * spacing[1],
        (dims[2] - 1) as f64 * spacing[2],
    ) / 2.0;
    let origin = Point::origin() - direction * half;
    let geometry = Volume::new(
        dims,
        spacing,
        origin.into(),
        direction,
        vec![0.0; dims.iter().product()],
    )
    .unwrap();
    let mut samples = Vec::with_capacity(geometry.len());
    for k in 0..dims[2] {
        for j in 0..dims[1] {
            for i in 0..dims[0] {
                let x = geometry.index_to_world([i as f64, j as f64, k as f64]);
                samples.push(field(&x) as f32);
            }
        }
    }
    Volume::new(dims, spacing, origin.into(), direction, samples).unwrap()
}

/// Axis flips and a permutation: index x → world y, y → −z, z → −x.
fn flipped_permutation() -> Matrix3<f64> {
    Matrix3::new(0.0, 0.0, -1.0, 1.0, 0.0, 0.0, 0.0, -1.0, 0.0)
}

/// A rotation about a skew axis.
fn oblique_rotation() -> Matrix3<f64> {
    let axis = nalgebra::Unit::new_normalize(Vector::new(1.0, 2.0, -0.5));
    *nalgebra::Rotation3::from_axis_angle(&axis, 0.7).matrix()
}

/// The largest component magnitude of each order of a jet.
fn scales(jet: &Jet) -> [f64; 4] {
    let third = (0..27)
        .map(|n| jet.third.get(n / 9, n / 3 % 3, n % 3).abs())
        .fold(0.0, f64::max);
    [
        jet.value.abs(),
        jet.gradient.amax(),
        jet.hessian.amax(),
        third,
    ]
}

/// The largest absolute difference between `got` and `want` in each order.
fn errors(got: &Jet, want: &Jet) -> [f64; 4] {
    let third = (0..27)
        .map(|n| {
            let [i, j, k] = [n / 9, n / 3 % 3, n % 3];
            (got.third.get(i, j, k) - want.third.get(i, j, k)).abs()
        })
        .fold(0.0, f64::max);
    [
        (got.value - want.value).abs(),
        (got.gradient - want.gradient).amax(),
        (got.hessian - want.hessian).amax(),
        third,
    ]
}

/// Asserts that `got` matches `want` order by order, to `relative[m]` times
/// `magnitude[m]`, the size of the derivatives of order `m`.
fn assert_jets_close(got: &Jet, want: &Jet, relative: [f64; 4], magnitude: [f64; 4], what: &str) {
    let errors = errors(got, want);
    for order in 0..4 {
        assert!(
            errors[order] <= relative[order] * magnitude[order],
            "{what}: order {order} error {:.3e} for a magnitude {:.3e}\n got {got:?}\nwant {want:?}",
            errors[order],
            magnitude[order]
        );
    }
}

/// Voxels at least `margin` from every border, every `step`.
fn interior(dims: [usize; 3], margin: [usize; 3], step: usize) -> Vec<[usize; 3]> {
    let range = |a: usize| (margin[a]..dims[a] - margin[a]).step_by(step);
    let mut points = Vec::new();
    for k in range(2) {
        for j in range(1) {
            for i in range(0) {
                points.push([i, j, k]);
            }
        }
    }
    assert!(!points.is_empty());
    points
}

/// Kernel radius in voxels for σ (world) along an axis of `spacing`.
fn radius(sigma: f64, spacing: f64) -> usize {
    ((5.0 * sigma / spacing).ceil() as usize).max(2)
}

/// All 20 partials of a Gaussian-smoothed random cubic, through the world-space
/// accessors, at interior voxels.
fn check_cubic(sigma: f64, spacing: [f64; 3], direction: Matrix3<f64>, seed: u64) {
    let margin = [0, 1, 2].map(|a| radius(sigma, spacing[a]));
    let dims = margin.map(|m| 2 * m + 5);
    let extent = (0..3)
        .map(|a| dims[a] as f64 * spacing[a])
        .fold(0.0, f64::max);
    let cubic = Cubic::random(seed, Point::new(0.3, -0.2, 0.1), extent / 2.0);
    let volume = cubic.volume(dims, spacing, direction);
    let derivatives = Derivatives::new(&volume, sigma, 3).unwrap();
    for index in interior(dims, margin, 2) {
        let x = volume.index_to_world(index.map(|v| v as f64));
        let want = cubic.smoothed_jet(&x, sigma);
        let got = derivatives.jet(index).unwrap();
        let what = format!("σ {sigma} spacing {spacing:?} at {index:?}");
        assert_jets_close(&got, &want, [1e-4; 4], cubic.magnitudes(), &what);
        assert_eq!(derivatives.value(index), Some(got.value));
        assert_eq!(derivatives.gradient(index), Some(got.gradient));
        assert_eq!(derivatives.hessian(index), Some(got.hessian));
        assert_eq!(derivatives.third(index), Some(got.third));
    }
}

#[test]
fn cubic_polynomials_are_differentiated_exactly_at_small_sigma() {
    check_cubic(0.7, [1.0; 3], Matrix3::identity(), 1);
    check_cubic(0.5, [1.0; 3], Matrix3::identity(), 2);
}

#[test]
fn cubic_polynomials_are_differentiated_exactly_at_larger_sigma() {
    check_cubic(1.0, [1.0; 3], Matrix3::identity(), 3);
    check_cubic(2.2, [1.0; 3], Matrix3::identity(), 4);
}

#[test]
fn cubic_polynomials_with_anisotropic_voxels_and_rotated_axes() {
    // σ = 1.4 is 1.4, 2.8 and 0.7 voxels along x, y and z.
    check_cubic(1.4, [1.0, 0.5, 2.0], Matrix3::identity(), 5);
    check_cubic(1.4, [1.0, 0.5, 2.0], flipped_permutation(), 6);
    check_cubic(1.0, [0.8, 1.3, 1.0], oblique_rotation(), 7);
}

#[test]
fn grids_are_derivatives_along_the_index_axes_in_world_units() {
    let spacing = [1.0, 0.5, 2.0];
    let sigma = 1.2;
    let margin = [0, 1, 2].map(|a| radius(sigma, spacing[a]));
    let dims = margin.map(|m| 2 * m + 3);
    let cubic = Cubic::random(11, Point::origin(), 6.0);
    let volume = cubic.volume(dims, spacing, Matrix3::identity());
    let derivatives = Derivatives::new(&volume, sigma, 3).unwrap();
    let index = margin.map(|m| m + 1);
    let at = volume.linear_index(index[0], index[1], index[2]).unwrap();
    let x = volume.index_to_world(index.map(|v| v as f64));
    for partial in Partial::ALL {
        let want = cubic.smoothed_derivative(&x, partial.orders(), sigma);
        let got = f64::from(derivatives.grid(partial).unwrap()[at]);
        assert!(
            (got - want).abs() < 1e-4 * (1.0 + want.abs()),
            "{partial:?}: {got} vs {want}"
        );
    }
}

#[test]
fn selected_partials_equal_those_of_the_full_set() {
    let cubic = Cubic::random(12, Point::origin(), 5.0);
    let volume = cubic.volume([14, 12, 10], [1.0, 0.5, 2.0], flipped_permutation());
    let full = Derivatives::new(&volume, 1.1, 3).unwrap();
    let fxz = Partial::new([1, 0, 1]).unwrap();
    let fyyy = Partial::new([0, 3, 0]).unwrap();
    let some = Derivatives::with_partials(&volume, 1.1, &[fyyy, fxz, fyyy]).unwrap();
    assert_eq!(some.grid(fxz), full.grid(fxz));
    assert_eq!(some.grid(fyyy), full.grid(fyyy));
    assert!(some.grid(Partial::ALL[0]).is_none());
    assert!(some.gradient([5, 5, 5]).is_none());
    assert!(full.jet([14, 0, 0]).is_none());
    let second = Derivatives::new(&volume, 1.1, 2).unwrap();
    assert!(second.hessian([5, 5, 5]).is_some());
    assert!(second.third([5, 5, 5]).is_none());
    assert_eq!(second.grid(fxz), full.grid(fxz));
}

#[test]
fn a_block_of_slices_holds_exactly_those_slices_of_the_whole() {
    let cubic = Cubic::random(13, Point::origin(), 5.0);
    let volume = cubic.volume([14, 12, 10], [1.0, 0.5, 2.0], flipped_permutation());
    let plane = 14 * 12;
    let full = Derivatives::new(&volume, 1.1, 3).unwrap();
    // A block at the border (clamped samples reach it) and one inside.
    for slices in [0..3, 4..9, 9..10] {
        let block = Derivatives::on_slices(&volume, 1.1, &Partial::ALL, slices.clone()).unwrap();
        assert_eq!(block.slices(), slices);
        for partial in Partial::ALL {
            let whole = &full.grid(partial).unwrap()[slices.start * plane..slices.end * plane];
            assert_eq!(
                block.grid(partial).unwrap(),
                whole,
                "{partial:?} on {slices:?}"
            );
        }
        let inside = [3, 7, slices.start];
        assert_eq!(block.jet(inside), full.jet(inside));
        assert!(block.jet([3, 7, slices.end]).is_none());
        if slices.start > 0 {
            assert!(block.jet([3, 7, slices.start - 1]).is_none());
        }
    }
    for empty_or_past_the_end in [3..3, 8..11] {
        let block = Derivatives::on_slices(&volume, 1.1, &Partial::ALL, empty_or_past_the_end);
        assert!(matches!(block, Err(Error::Argument(_))));
    }
}

/// `B exp(−|x − c|² / 2S²)` and its derivatives up to order 3.
fn gaussian_jet(x: &Point, center: &Point, amplitude: f64, width: f64) -> Jet {
    let d = x - center;
    let s2 = width * width;
    let g = amplitude * (-d.norm_squared() / (2.0 * s2)).exp();
    let delta = |i: usize, j: usize| if i == j { 1.0 } else { 0.0 };
    let mut t = [[[0.0; 3]; 3]; 3];
    for (i, plane) in t.iter_mut().enumerate() {
        for (j, row) in plane.iter_mut().enumerate() {
            for (k, v) in row.iter_mut().enumerate() {
                *v = g
                    * (-d[i] * d[j] * d[k] / (s2 * s2 * s2)
                        + (delta(i, j) * d[k] + delta(i, k) * d[j] + delta(j, k) * d[i])
                            / (s2 * s2));
            }
        }
    }
    Jet {
        value: g,
        gradient: -g * d / s2,
        hessian: g * (d * d.transpose() / (s2 * s2) - Matrix3::identity() / s2),
        third: ThirdOrder(t),
    }
}

#[test]
fn smoothed_gaussian_blob_matches_its_closed_form() {
    // A blob of width s smoothed by σ is a blob of width √(s² + σ²) and amplitude
    // (s² / (s² + σ²))^(3/2).
    let (s, sigma) = (4.0, 3.0);
    let spacing = [1.0, 0.5, 2.0];
    let center = Point::new(0.4, -0.3, 0.6);
    let dims = [40, 80, 24];
    let volume = sampled(dims, spacing, oblique_rotation(), |x| {
        gaussian_jet(x, &center, 1.0, s).value
    });
    let derivatives = Derivatives::new(&volume, sigma, 3).unwrap();
    let width = (s * s + sigma * sigma).sqrt();
    let amplitude = (s * s / (width * width)).powf(1.5);
    let peak = gaussian_jet(&center, &center, amplitude, width);
    // Scales of the field's derivatives (at the peak or one width away).
    let floor = scales(&peak)[0].max(1.0);
    let margin = [0, 1, 2].map(|a| radius(sigma, spacing[a]) + 1);
    let mut worst = [0.0f64; 4];
    for index in interior(dims, margin, 3) {
        let x = volume.index_to_world(index.map(|v| v as f64));
        let want = gaussian_jet(&x, &center, amplitude, width);
        let got = derivatives.jet(index).unwrap();
        let d = [1.0, 1.0 / width, 1.0 / (width * width), 1.0 / width.powi(3)];
        let errors = errors(&got, &want);
        for order in 0..4 {
            worst[order] = worst[order].max(errors[order] / (floor * d[order]));
        }
    }
    // Truncating the kernels at 5σ costs a few 1e-4 of the third derivatives (about
    // 5e-4 measured here) and far less in the lower orders.
    let tolerance = [1e-5, 5e-5, 2e-4, 1e-3];
    assert!((0..4).all(|m| worst[m] < tolerance[m]), "{worst:?}");
}

#[test]
fn a_single_slice_has_no_z_derivatives() {
    let volume = sampled([12, 10, 1], [1.0; 3], Matrix3::identity(), |x| {
        x.x * x.x - 2.0 * x.y
    });
    let derivatives = Derivatives::new(&volume, 1.0, 3).unwrap();
    let fz = derivatives.grid(Partial::new([0, 0, 1]).unwrap()).unwrap();
    assert!(fz.iter().all(|&v| v == 0.0));
    let h = derivatives.hessian([6, 5, 0]).unwrap();
    assert!((h[(0, 0)] - 2.0).abs() < 1e-4, "{h}");
}

#[test]
fn bad_sigma_and_geometry_are_errors() {
    let volume = sampled([10, 10, 10], [1.0, 1.0, 0.5], Matrix3::identity(), |x| x.x);
    for sigma in [0.0, -1.0, f64::NAN, f64::INFINITY, 1e-4, 1e9, 11.0] {
        match Derivatives::new(&volume, sigma, 2) {
            Err(Error::Argument(message)) => assert!(message.contains('σ'), "{message}"),
            other => panic!("σ = {sigma}: {other:?}"),
        }
    }
    assert!(Derivatives::new(&volume, 4.0, 1).is_ok());
    assert!(matches!(
        Derivatives::new(&volume, 1.0, 4),
        Err(Error::Argument(_))
    ));
    assert!(matches!(
        Derivatives::with_partials(&volume, 1.0, &[]),
        Err(Error::Argument(_))
    ));
    assert!(Partial::new([2, 1, 1]).is_err());
    let sheared = Matrix3::new(1.0, 0.5, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0);
    let skew = sampled([6, 6, 6], [1.0; 3], sheared, |x| x.x);
    match Derivatives::new(&skew, 1.0, 1) {
        Err(Error::Argument(message)) => assert!(message.contains("orthonormal"), "{message}"),
        other => panic!("{other:?}"),
    }
}

/// A volume of random samples.
fn noise(dims: [usize; 3], spacing: [f64; 3], direction: Matrix3<f64>, seed: u64) -> Volume {
    let mut rng = Lcg(seed);
    let samples = (0..dims.iter().product())
        .map(|_| rng.next() as f32)
        .collect();
    Volume::new(dims, spacing, [1.0, -2.0, 0.5], direction, samples).unwrap()
}

#[test]
fn bspline_interpolates_the_samples() {
    for dims in [[9, 7, 5], [1, 4, 2], [2, 2, 2], [40, 3, 30]] {
        let volume = noise(dims, [0.7, 1.0, 1.3], flipped_permutation(), 21);
        let spline = BSpline::new(&volume);
        for k in 0..dims[2] {
            for j in 0..dims[1] {
                for i in 0..dims[0] {
                    let want = f64::from(volume.value(i, j, k).unwrap());
                    let index = [i as f64, j as f64, k as f64];
                    let got = spline.value_at_index(index).unwrap();
                    assert!(
                        (got - want).abs() < 1e-5,
                        "{dims:?} {index:?}: {got} vs {want}"
                    );
                    let world = spline
                        .value_at_world(&volume.index_to_world(index))
                        .unwrap();
                    assert!(
                        (world - want).abs() < 1e-5,
                        "{dims:?} {index:?}: {world} vs {want}"
                    );
                }
            }
        }
    }
}

#[test]
fn bspline_reproduces_cubic_polynomials_and_their_derivatives() {
    let sheared = Matrix3::new(1.0, 0.3, 0.0, 0.0, 1.0, -0.2, 0.1, 0.0, 1.0);
    for (n, direction) in [
        Matrix3::identity(),
        flipped_permutation(),
        oblique_rotation(),
        sheared,
    ]
    .into_iter()
    .enumerate()
    {
        let dims = [30, 28, 32];
        let spacing = [1.0, 0.5, 2.0];
        let cubic = Cubic::random(30 + n as u64, Point::new(0.5, 0.2, -0.4), 4.0);
        let volume = cubic.volume(dims, spacing, direction);
        let spline = BSpline::new(&volume);
        let mut rng = Lcg(40 + n as u64);
        for _ in 0..50 {
            let index = [0, 1, 2].map(|a| dims[a] as f64 / 2.0 + 2.0 * rng.next());
            let x = volume.index_to_world(index);
            let want = cubic.smoothed_jet(&x, 0.0);
            let got = spline.jet_at_world(&x).unwrap();
            // The coefficients are f32 like the samples: their rounding, amplified by
            // the third-difference stencil, bounds the third derivatives' accuracy.
            let what = format!("direction {n} at {index:?}");
            assert_jets_close(
                &got,
                &want,
                [1e-5, 1e-4, 1e-4, 1e-3],
                cubic.magnitudes(),
                &what,
            );
        }
    }
}

#[test]
fn bspline_is_c2_across_cell_faces() {
    let volume = noise([8, 9, 7], [1.0, 0.5, 2.0], oblique_rotation(), 50);
    let spline = BSpline::new(&volume);
    let mut rng = Lcg(51);
    for axis in 0..3 {
        for _ in 0..20 {
            let mut index = [0, 1, 2].map(|_| 3.0 + 1.5 * rng.next());
            index[axis] = index[axis].round();
            let above = spline.jet_at_index(index).unwrap();
            let mut below_index = index;
            below_index[axis] -= 1e-9;
            let below = spline.jet_at_index(below_index).unwrap();
            let scale = scales(&above);
            let tolerance = |order: usize| 1e-6 * scale[order].max(1.0);
            assert!((above.value - below.value).abs() < tolerance(0));
            assert!((above.gradient - below.gradient).amax() < tolerance(1));
            assert!(
                (above.hessian - below.hessian).amax() < tolerance(2),
                "{index:?}"
            );
        }
    }
    assert!(spline.jet_at_index([-0.5, 1.0, 1.0]).is_none());
    assert!(spline.value_at_index([1.0, 8.01, 1.0]).is_none());
    assert!(spline.value_at_index([7.0, 8.0, 6.0]).is_some());
}

#[test]
fn approximating_spline_derivatives_of_cubics_are_exact() {
    // The approximating cubic B-spline with the samples as coefficients smooths
    // axis a by a variance of h_a²/3: ∂^d s = ∂^d p + Σ_a (h_a² / 6) ∂^(d + 2e_a) p
    // for a cubic p (index axes along the world axes here).
    let spacing = [1.0, 0.6, 1.5];
    let dims = [12, 14, 10];
    let cubic = Cubic::random(11, Point::new(0.3, -0.2, 0.1), 4.0);
    let volume = cubic.volume(dims, spacing, Matrix3::identity());
    let derivatives = Derivatives::cubic_spline(&volume, 2).unwrap();
    let smoothed = |x: &Point, d: [usize; 3]| {
        let blur: f64 = (0..3)
            .map(|axis| {
                let mut dd = d;
                dd[axis] += 2;
                spacing[axis] * spacing[axis] / 6.0 * cubic.derivative(x, dd)
            })
            .sum();
        cubic.derivative(x, d) + blur
    };
    let magnitude = cubic.magnitudes();
    for index in interior(dims, [1; 3], 2) {
        let x = volume.index_to_world(index.map(|v| v as f64));
        let value = derivatives.value(index).unwrap();
        assert!((value - smoothed(&x, [0, 0, 0])).abs() < 1e-5 * magnitude[0]);
        let gradient = derivatives.gradient(index).unwrap();
        let hessian = derivatives.hessian(index).unwrap();
        for i in 0..3 {
            let mut d = [0; 3];
            d[i] = 1;
            assert!(
                (gradient[i] - smoothed(&x, d)).abs() < 1e-5 * magnitude[1],
                "{index:?}"
            );
            for j in 0..3 {
                let mut d = [0; 3];
                d[i] += 1;
                d[j] += 1;
                assert!(
                    (hessian[(i, j)] - smoothed(&x, d)).abs() < 1e-5 * magnitude[2],
                    "{index:?} H[{i}][{j}] {} vs {}",
                    hessian[(i, j)],
                    smoothed(&x, d)
                );
            }
        }
    }
    assert!(Derivatives::cubic_spline(&volume, 3).is_err());
}

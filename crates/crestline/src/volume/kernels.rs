//! Sampled, moment-corrected 1-D Gaussian derivative kernels (orders 0 to 3).
//!
//! Thirion & Gourdon (1993) take the image as the continuous function
//! `f = G_σ * i`, the samples `i` convolved with a Gaussian, and read the
//! differential characteristics of its isosurfaces off the derivatives of `f`. A
//! derivative of `f` along one axis is a correlation of the samples with a
//! Gaussian derivative kernel:
//!
//! `∂ᵐf(n) = Σ_k c_m[k] · i[n + k]`,  `c_m[k] = (−1)ᵐ G_σ⁽ᵐ⁾(k)`
//!
//! (the `(−1)ᵐ` turns the convolution with `G⁽ᵐ⁾` into a correlation). Sampling and
//! truncating `c_m` breaks its moments, and docs/design/images.md ("Isosurfaces and implicit
//! curvature") records what that costs: at σ = 0.7 voxel the plain kernels carry
//! spurious third derivatives that double the crest lines. The kernels here are
//! therefore corrected so that their moments of degree 0 to 3 are exactly those of
//! the continuous kernel,
//!
//! `Σ_k kʲ c_m[k] = dᵐ/dxᵐ E[(x + Y)ʲ] at x = 0`,  `Y ~ N(0, σ²)`,
//!
//! that is `[1, 0, σ², 0]` for the value, `[0, 1, 0, 3σ²]` for the first
//! derivative, `[0, 0, 2, 0]` for the second and `[0, 0, 0, 6]` for the third
//! (degrees 0, 1, 2, 3). On any polynomial of degree ≤ 3 a corrected kernel of order
//! `m` therefore returns exactly the `m`-th derivative of the Gaussian-smoothed
//! polynomial (for orders 2 and 3 this is the polynomial's own derivative; the value
//! and the first derivative also carry the smoothing terms `σ²/2 · p''` and
//! `σ²/2 · p'''`).
//!
//! The correction adds `w(k) · (λ₀ k^p + λ₁ k^(p+2))` with `p = m mod 2`, a
//! polynomial of the kernel's parity under a Gaussian window `w` (of width
//! `max(σ, 1)` voxels), so that the corrected kernel stays symmetric (even orders)
//! or antisymmetric (odd orders) and moments of the other parity stay zero.

use crate::{Error, Result};

/// Highest derivative order with a kernel.
pub const MAX_ORDER: usize = 3;

/// Kernels reach this many standard deviations on each side. At 4σ the truncated
/// third-derivative kernel misses about 6 % of its third moment; the correction
/// restores it, but then costs about 1 % of the third derivative on signals whose
/// scale is close to σ. At 5σ both effects are below 1e-3.
pub const RADIUS_IN_SIGMAS: f64 = 5.0;

/// Kernels have at least this radius (in samples), so that the four moment
/// conditions can be met however small σ is.
pub const MIN_RADIUS: usize = 2;

/// The smallest σ accepted, in voxels: below it the Gaussian is no longer sampled
/// and the kernels degenerate into finite differences of the correction alone.
pub const MIN_SIGMA_VOXELS: f64 = 0.1;

/// σ, in voxels, is at most the number of samples along its axis (a wider Gaussian
/// only measures the border extension), or this many voxels along an axis with
/// fewer samples (e.g. a single slice).
pub const MIN_SIGMA_CAP: f64 = 4.0;

/// A 1-D correlation kernel for the derivative of order `order` of a sampled
/// Gaussian: `weights()[R + k]` multiplies the sample at offset `k`, for
/// `k = −R..=R` with `R` the radius.
#[derive(Clone, Debug, PartialEq)]
pub struct Kernel {
    order: usize,
    /// `c[k]` for `k = 0..=R`; `c[−k] = (−1)^order c[k]`.
    half: Vec<f64>,
}

impl Kernel {
    /// The corrected Gaussian derivative kernel of `order` (0 to 3) for a Gaussian
    /// of standard deviation `sigma`, in samples, with radius
    /// `max(⌈5σ⌉, 2)` (see the module documentation).
    ///
    /// Errors ([`Error::Argument`]) if `order > 3` or `sigma` is not finite or is
    /// below [`MIN_SIGMA_VOXELS`]; no upper bound is checked here (see
    /// [`check_sigma`]).
    pub fn gaussian(sigma: f64, order: usize) -> Result<Kernel> {
        if order > MAX_ORDER {
            return Err(Error::Argument(format!(
                "Gaussian derivative kernels go up to order {MAX_ORDER}, not {order}"
            )));
        }
        if !sigma.is_finite() || sigma < MIN_SIGMA_VOXELS {
            return Err(Error::Argument(format!(
                "σ = {sigma} samples is not a finite value of at least {MIN_SIGMA_VOXELS}"
            )));
        }
        let radius = kernel_radius(sigma);
        let mut half: Vec<f64> = (0..=radius)
            .map(|k| gaussian_derivative(k as f64, sigma, order))
            .collect();
        correct_moments(&mut half, sigma, order);
        Ok(Kernel { order, half })
    }

    #[cfg(test)]
    /// The radius `R`: the kernel has `2R + 1` taps.
    pub fn radius(&self) -> usize {
        self.half.len() - 1
    }

    #[cfg(test)]
    /// The weight at offset `k` (zero outside `−R..=R`).
    pub fn weight(&self, k: isize) -> f64 {
        let Some(&w) = self.half.get(k.unsigned_abs()) else {
            return 0.0;
        };
        if k < 0 && self.is_odd() {
            -w
        } else {
            w
        }
    }

    #[cfg(test)]
    /// All `2R + 1` weights, offset `−R` first.
    pub fn weights(&self) -> Vec<f64> {
        let r = self.radius() as isize;
        (-r..=r).map(|k| self.weight(k)).collect()
    }

    /// The weights at offsets `0..=R`, each multiplied by `scale`, as `f32`.
    pub(crate) fn half_scaled(&self, scale: f64) -> Vec<f32> {
        self.half.iter().map(|w| (w * scale) as f32).collect()
    }

    /// Whether the kernel is antisymmetric (odd order).
    pub fn is_odd(&self) -> bool {
        self.order % 2 == 1
    }

    #[cfg(test)]
    /// The moment `Σ_k kʲ c[k]` of degree `j`.
    pub fn moment(&self, j: u32) -> f64 {
        let r = self.radius() as isize;
        (-r..=r)
            .map(|k| (k as f64).powi(j as i32) * self.weight(k))
            .sum()
    }
}

/// The moments of degree 0 to 3 of the continuous kernel of `order`:
/// `dᵐ/dxᵐ E[(x + Y)ʲ]` at `x = 0` for `Y ~ N(0, σ²)`.
pub fn target_moments(sigma: f64, order: usize) -> [f64; 4] {
    let variance = sigma * sigma;
    match order {
        0 => [1.0, 0.0, variance, 0.0],
        1 => [0.0, 1.0, 0.0, 3.0 * variance],
        2 => [0.0, 0.0, 2.0, 0.0],
        _ => [0.0, 0.0, 0.0, 6.0],
    }
}

/// Checks σ (world units) against an axis with `samples` samples of `spacing`
/// world units, and returns σ in voxels along that axis.
///
/// Errors ([`Error::Argument`]) if σ is not finite and positive, is below
/// [`MIN_SIGMA_VOXELS`] voxel, or exceeds `max(samples, 4)` voxels (the kernel
/// would be wider than the image).
pub fn check_sigma(sigma: f64, spacing: f64, samples: usize, axis: usize) -> Result<f64> {
    let name = ["x", "y", "z"].get(axis).copied().unwrap_or("?");
    if !sigma.is_finite() || sigma <= 0.0 {
        return Err(Error::Argument(format!(
            "the Gaussian σ = {sigma} is not finite and positive"
        )));
    }
    let voxels = sigma / spacing;
    if voxels < MIN_SIGMA_VOXELS {
        return Err(Error::Argument(format!(
            "the Gaussian σ = {sigma} is {voxels} voxel along {name} (spacing {spacing}), \
             below the {MIN_SIGMA_VOXELS} voxel that can be sampled"
        )));
    }
    let cap = (samples as f64).max(MIN_SIGMA_CAP);
    if voxels > cap {
        return Err(Error::Argument(format!(
            "the Gaussian σ = {sigma} is {voxels} voxels along {name} (spacing {spacing}), \
             more than the {cap} allowed for {samples} samples"
        )));
    }
    Ok(voxels)
}

/// `max(⌈5σ⌉, 2)` samples.
fn kernel_radius(sigma: f64) -> usize {
    ((RADIUS_IN_SIGMAS * sigma).ceil() as usize).max(MIN_RADIUS)
}

/// `(−1)ᵐ G⁽ᵐ⁾(x)` for the normalised Gaussian `G` of standard deviation `s`.
fn gaussian_derivative(x: f64, s: f64, order: usize) -> f64 {
    let s2 = s * s;
    let g = (-x * x / (2.0 * s2)).exp() / ((2.0 * std::f64::consts::PI).sqrt() * s);
    let factor = match order {
        0 => 1.0,
        1 => x / s2,
        2 => (x * x - s2) / (s2 * s2),
        _ => (x * x * x - 3.0 * x * s2) / (s2 * s2 * s2),
    };
    factor * g
}

/// Adds `w(k) (λ₀ k^p + λ₁ k^(p+2))` to the half kernel (offsets `0..=R`) so that
/// the moments of degree `p` and `p + 2` (`p` the parity of `order`) take their
/// continuous values; the other two moments vanish by symmetry.
fn correct_moments(half: &mut [f64], sigma: f64, order: usize) {
    let parity = (order % 2) as i32;
    let degrees = [parity, parity + 2];
    let width = sigma.max(1.0);
    let basis: [Vec<f64>; 2] = degrees.map(|d| {
        (0..half.len())
            .map(|k| {
                let k = k as f64;
                (-k * k / (2.0 * width * width)).exp() * k.powi(d)
            })
            .collect()
    });
    let target = target_moments(sigma, order);
    let rhs = degrees.map(|j| target[j as usize] - full_moment(half, j));
    let a = degrees.map(|j| [&basis[0], &basis[1]].map(|b| full_moment(b, j)));
    let det = a[0][0] * a[1][1] - a[0][1] * a[1][0];
    let l0 = (rhs[0] * a[1][1] - a[0][1] * rhs[1]) / det;
    let l1 = (a[0][0] * rhs[1] - a[1][0] * rhs[0]) / det;
    for ((w, b0), b1) in half.iter_mut().zip(&basis[0]).zip(&basis[1]) {
        *w += l0 * b0 + l1 * b1;
    }
}

/// The moment `Σ_k kʲ v[k]` over `k = −R..=R` of the full kernel whose offsets
/// `0..=R` are `half`, for `j` of the kernel's parity (the terms at `±k` are equal).
fn full_moment(half: &[f64], j: i32) -> f64 {
    half.iter()
        .enumerate()
        .map(|(k, v)| {
            let term = (k as f64).powi(j) * v;
            if k == 0 {
                term
            } else {
                2.0 * term
            }
        })
        .sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn moments_are_exact_at_small_and_large_sigma() {
        for sigma in [0.1, 0.5, 0.7, 1.0, 1.5, 3.3, 10.0] {
            for order in 0..=MAX_ORDER {
                let kernel = Kernel::gaussian(sigma, order).unwrap();
                let target = target_moments(sigma, order);
                for j in 0..4 {
                    let m = kernel.moment(j);
                    let scale = 1.0 + target[j as usize].abs();
                    assert!(
                        (m - target[j as usize]).abs() < 1e-10 * scale,
                        "σ {sigma} order {order} moment {j}: {m} vs {}",
                        target[j as usize]
                    );
                }
            }
        }
    }

    #[test]
    fn orders_above_three_and_non_finite_sigma_are_refused() {
        assert!(Kernel::gaussian(1.0, 4).is_err());
        assert!(Kernel::gaussian(f64::NAN, 0).is_err());
        assert!(Kernel::gaussian(0.05, 0).is_err());
    }

    #[test]
    fn corrections_are_small_for_wide_kernels() {
        let sigma = 3.0;
        for order in 0..=MAX_ORDER {
            let kernel = Kernel::gaussian(sigma, order).unwrap();
            let r = kernel.radius() as isize;
            for k in -r..=r {
                let plain = gaussian_derivative(k as f64, sigma, order);
                assert!(
                    (kernel.weight(k) - plain).abs() < 1e-4,
                    "order {order} k {k}"
                );
            }
        }
    }

    #[test]
    fn radius_and_symmetry() {
        let kernel = Kernel::gaussian(1.5, 1).unwrap();
        assert_eq!(kernel.radius(), 8);
        assert_eq!(kernel.weights().len(), 17);
        assert_eq!(kernel.weight(-2), -kernel.weight(2));
        assert_eq!(kernel.weight(9), 0.0);
        assert!(kernel.weight(1) > 0.0);
        assert_eq!(Kernel::gaussian(0.3, 0).unwrap().radius(), 2);
    }
}

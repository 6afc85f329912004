//! Gaussian derivatives of a volume: the partial derivatives of orders 0 to 3 of the
//! image smoothed by a Gaussian of standard deviation σ (world units), on the grid.
//!
//! This is the differentiation step of Thirion & Gourdon (1993): the image is taken
//! as `f = G_σ * i`, and the derivatives of `f` are separable filters of the
//! samples with the moment-corrected kernels of [`super::kernels`] (see docs/design/images.md,
//! "Isosurfaces and implicit curvature"). σ is isotropic in the world: along index
//! axis `a` it is `σ / spacing[a]` voxels, and derivatives are taken with respect to
//! world length along the axes, then turned into world coordinates by the
//! direction matrix (which must therefore be orthonormal).
//!
//! Borders are clamped to the edge: samples outside the grid repeat the nearest
//! sample. Derivatives within `max(⌈5σ⌉, 2)` voxels of the border feel that
//! extension; further in, cubic polynomials are differentiated exactly.

use super::grid::Grid;
use super::jet::{hessian_from_components, Jet, ThirdOrder};
use super::kernels::{check_sigma, Kernel, MAX_ORDER};
use super::separable::{self, AxisKernels, HalfKernel};
use super::voxel_set::VoxelSet;
use super::Volume;
use crate::{Error, Result, Vector};
use nalgebra::Matrix3;
use rayon::prelude::*;
use std::ops::Range;

/// The z slices whose derivatives [`Derivatives::at_voxels`] holds at once.
const BLOCK_SLICES: usize = 8;

/// One partial derivative along the index axes, `∂^(a+b+c) f / ∂xᵃ ∂yᵇ ∂zᶜ` with
/// total order `a + b + c ≤ 3`, lengths along the axes in world units.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Partial {
    orders: [usize; 3],
}

/// [`Partial`] of orders `(a, b, c)`, for the constant table.
const fn partial(a: usize, b: usize, c: usize) -> Partial {
    Partial { orders: [a, b, c] }
}

impl Partial {
    /// The 20 partials of order ≤ 3: `f; fx fy fz; fxx fxy fxz fyy fyz fzz; fxxx fxxy
    /// fxxz fxyy fxyz fxzz fyyy fyyz fyzz fzzz`.
    pub const ALL: [Partial; 20] = [
        partial(0, 0, 0),
        partial(1, 0, 0),
        partial(0, 1, 0),
        partial(0, 0, 1),
        partial(2, 0, 0),
        partial(1, 1, 0),
        partial(1, 0, 1),
        partial(0, 2, 0),
        partial(0, 1, 1),
        partial(0, 0, 2),
        partial(3, 0, 0),
        partial(2, 1, 0),
        partial(2, 0, 1),
        partial(1, 2, 0),
        partial(1, 1, 1),
        partial(1, 0, 2),
        partial(0, 3, 0),
        partial(0, 2, 1),
        partial(0, 1, 2),
        partial(0, 0, 3),
    ];

    /// The partial derivative of orders `[a, b, c]` along x, y and z.
    ///
    /// Errors ([`Error::Argument`]) if the total order exceeds 3.
    pub fn new(orders: [usize; 3]) -> Result<Partial> {
        if orders.iter().sum::<usize>() > MAX_ORDER {
            return Err(Error::Argument(format!(
                "the partial derivative of orders {orders:?} has a total order above {MAX_ORDER}"
            )));
        }
        Ok(Partial { orders })
    }

    /// The partials of total order at most `max_order`, in the order of
    /// [`Partial::ALL`].
    pub fn up_to(max_order: usize) -> impl Iterator<Item = Partial> {
        Partial::ALL
            .into_iter()
            .filter(move |p| p.order() <= max_order)
    }

    /// The orders along x, y and z.
    pub fn orders(self) -> [usize; 3] {
        self.orders
    }

    /// The total order.
    pub fn order(self) -> usize {
        self.orders.iter().sum()
    }

    /// The position of this partial in [`Derivatives`]' table.
    fn slot(self) -> usize {
        let [a, b, c] = self.orders;
        a + 4 * (b + 4 * c)
    }
}

/// Partial derivatives of a Gaussian-smoothed volume, each an `f32` grid of the
/// volume's size (x fastest), or of a block of its z slices
/// ([`Derivatives::on_slices`]), with accessors for world-space gradients, Hessians
/// and third-derivative tensors at grid points.
#[derive(Clone, Debug)]
pub struct Derivatives {
    dims: [usize; 3],
    /// The z slices computed.
    slices: Range<usize>,
    smoothing: Smoothing,
    direction: Matrix3<f64>,
    /// The grid of each computed partial, at [`Partial::slot`].
    grids: Vec<Option<Vec<f32>>>,
}

/// How [`Derivatives`] make the samples differentiable.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Smoothing {
    /// A Gaussian of this standard deviation, in world units.
    Gaussian(f64),
    /// The approximating (not interpolating) cubic B-spline whose coefficients are
    /// the samples: a C² reconstruction that smooths about as much as a Gaussian of
    /// σ = 1/√3 voxel, with derivatives at the grid points from the 3-tap kernels
    /// β³(k) = (1, 4, 1)/6, β³′(k) = (1, 0, −1)/2 and β³″(k) = (1, −2, 1) (Schultz,
    /// Theisel and Seidel 2010, §4.6).
    CubicSpline,
}

impl Derivatives {
    /// Partial derivatives of total order at most `max_order` (0 to 2: 1, 4 or 10
    /// grids) of the approximating cubic B-spline of `volume`
    /// (`Smoothing::CubicSpline`).
    ///
    /// Errors ([`Error::Argument`]) if `max_order > 2` (the spline's third
    /// derivatives jump at the grid points) or the direction matrix is not
    /// orthonormal.
    pub fn cubic_spline(volume: &Volume, max_order: usize) -> Result<Derivatives> {
        check_spline_order(max_order)?;
        let partials: Vec<Partial> = Partial::up_to(max_order).collect();
        let kernels = spline_kernels(volume.spacing());
        let slices = 0..volume.dims()[2];
        Derivatives::filtered(volume, Smoothing::CubicSpline, &kernels, &partials, slices)
    }

    /// All partial derivatives of total order at most `max_order` (0 to 3: 1, 4, 10
    /// or 20 grids) of `volume` smoothed by a Gaussian of standard deviation `sigma`
    /// in world units.
    ///
    /// Errors as [`Derivatives::with_partials`], and if `max_order > 3`.
    pub fn new(volume: &Volume, sigma: f64, max_order: usize) -> Result<Derivatives> {
        if max_order > MAX_ORDER {
            return Err(Error::Argument(format!(
                "derivatives go up to order {MAX_ORDER}, not {max_order}"
            )));
        }
        let partials: Vec<Partial> = Partial::up_to(max_order).collect();
        Derivatives::with_partials(volume, sigma, &partials)
    }

    /// The partial derivatives `partials` (repetitions are computed once) of
    /// `volume` smoothed by a Gaussian of standard deviation `sigma` in world units.
    /// The 1-D passes are shared between partials and run in parallel over z slices.
    ///
    /// Errors ([`Error::Argument`]) if `partials` is empty, the volume's direction
    /// matrix is not orthonormal (a Gaussian isotropic in the world needs it), or σ
    /// is not finite and positive, is under a tenth of a voxel along an axis, or is
    /// more voxels than the samples along an axis (at least 4 voxels are allowed).
    pub fn with_partials(volume: &Volume, sigma: f64, partials: &[Partial]) -> Result<Derivatives> {
        Derivatives::on_slices(volume, sigma, partials, 0..volume.dims()[2])
    }

    /// `volume` smoothed by a Gaussian of standard deviation `sigma` in world units:
    /// the partial of order 0 alone, as a volume on the same grid.
    ///
    /// Errors as [`Derivatives::with_partials`].
    pub fn smoothed(volume: &Volume, sigma: f64) -> Result<Volume> {
        let value = Partial::ALL[0];
        let samples = Derivatives::with_partials(volume, sigma, &[value])?
            .into_grid(value)
            .expect("the partial asked for is computed");
        volume.with_samples(samples)
    }

    /// [`Derivatives::with_partials`] on the z slices `slices` only: the same values
    /// at their grid points (every slice is filtered from the samples alone), in
    /// memory for those slices. The accessors answer `None` at other slices.
    ///
    /// Errors as [`Derivatives::with_partials`], and ([`Error::Argument`]) if
    /// `slices` is empty or reaches past the last slice.
    pub fn on_slices(
        volume: &Volume,
        sigma: f64,
        partials: &[Partial],
        slices: Range<usize>,
    ) -> Result<Derivatives> {
        if partials.is_empty() {
            return Err(Error::Argument(
                "no partial derivative was requested".to_string(),
            ));
        }
        let nz = volume.dims()[2];
        if slices.is_empty() || slices.end > nz {
            return Err(Error::Argument(format!(
                "the slices {slices:?} are not a nonempty range of the volume's {nz} z slices"
            )));
        }
        let kernels = world_kernels(volume, sigma)?;
        Derivatives::filtered(
            volume,
            Smoothing::Gaussian(sigma),
            &kernels,
            partials,
            slices,
        )
    }

    /// `partials` of `volume` filtered by `kernels` (per axis, per order) on the z
    /// slices `slices`.
    fn filtered(
        volume: &Volume,
        smoothing: Smoothing,
        kernels: &[AxisKernels; 3],
        partials: &[Partial],
        slices: Range<usize>,
    ) -> Result<Derivatives> {
        let direction = orthonormal_direction(volume)?;
        let mut wanted = partials.to_vec();
        wanted.sort_unstable();
        wanted.dedup();
        let orders: Vec<[usize; 3]> = wanted.iter().map(|p| p.orders).collect();
        let grid = volume.grid();
        let filtered = separable::filter(volume.samples(), grid, kernels, &orders, slices.clone());
        let mut grids = vec![None; 64];
        for (p, grid) in wanted.iter().zip(filtered) {
            grids[p.slot()] = Some(grid);
        }
        Ok(Derivatives {
            dims: volume.dims(),
            slices,
            smoothing,
            direction,
            grids,
        })
    }

    /// `value(derivatives, index)` at each member of `voxels` (sample `index`), in
    /// order, with `derivatives` holding `partials` of `volume` smoothed by a
    /// Gaussian of standard deviation `sigma` on a block of z slices that holds
    /// `index` ([`Derivatives::for_blocks`]); the members of a block are evaluated
    /// in parallel.
    ///
    /// Errors as [`Derivatives::on_slices`].
    pub(crate) fn at_voxels<T: Send>(
        volume: &Volume,
        sigma: f64,
        partials: &[Partial],
        voxels: &VoxelSet,
        value: impl Fn(&Derivatives, [usize; 3]) -> T + Sync,
    ) -> Result<Vec<T>> {
        let grid = volume.grid();
        let mut values = Vec::with_capacity(voxels.len());
        let smoothing = Smoothing::Gaussian(sigma);
        Derivatives::for_blocks(
            volume,
            smoothing,
            partials,
            voxels,
            |derivatives, members| {
                let at = |&at: &usize| value(derivatives, grid.position_of(at));
                values.par_extend(members.par_iter().map(at));
                Ok(())
            },
        )?;
        Ok(values)
    }

    /// `visit(derivatives, members)` for every block of [`BLOCK_SLICES`] z slices
    /// that holds members of `voxels`, in order: `derivatives` hold `partials` of
    /// `volume` made differentiable as `smoothing` says on the block's slices, and
    /// `members` are the block's members (linear indices, increasing). The
    /// derivatives at scattered samples in the memory of a few slices.
    ///
    /// Errors as [`Derivatives::on_slices`] (and, for the spline, as
    /// [`Derivatives::cubic_spline`]), or as `visit`.
    pub(crate) fn for_blocks(
        volume: &Volume,
        smoothing: Smoothing,
        partials: &[Partial],
        voxels: &VoxelSet,
        mut visit: impl FnMut(&Derivatives, &[usize]) -> Result<()>,
    ) -> Result<()> {
        orthonormal_direction(volume)?;
        let kernels = match smoothing {
            Smoothing::Gaussian(sigma) => world_kernels(volume, sigma)?,
            Smoothing::CubicSpline => {
                partials
                    .iter()
                    .try_for_each(|p| check_spline_order(p.order()))?;
                spline_kernels(volume.spacing())
            }
        };
        let grid = volume.grid();
        let (nz, plane) = (grid.dims[2], grid.plane_len());
        for first in (0..nz).step_by(BLOCK_SLICES) {
            let slices = first..(first + BLOCK_SLICES).min(nz);
            let members: Vec<usize> = voxels
                .members(slices.start * plane..slices.end * plane)
                .collect();
            if members.is_empty() {
                continue;
            }
            let derivatives = Derivatives::filtered(volume, smoothing, &kernels, partials, slices)?;
            visit(&derivatives, &members)?;
        }
        Ok(())
    }

    /// The number of samples along x, y and z (those of the volume).
    pub fn dims(&self) -> [usize; 3] {
        self.dims
    }

    /// How the samples were made differentiable.
    pub fn smoothing(&self) -> Smoothing {
        self.smoothing
    }

    /// The grid of `partial` (x fastest, derivatives with respect to world length
    /// along the index axes; the computed slices only), or `None` if it was not
    /// computed.
    pub fn grid(&self, partial: Partial) -> Option<&[f32]> {
        self.grids[partial.slot()].as_deref()
    }

    /// The grid of `partial` as [`Derivatives::grid`] gives it, taken out of the
    /// derivatives without a copy.
    pub fn into_grid(mut self, partial: Partial) -> Option<Vec<f32>> {
        self.grids[partial.slot()].take()
    }

    /// The z slices computed: all of them unless made by
    /// [`Derivatives::on_slices`].
    pub fn slices(&self) -> Range<usize> {
        self.slices.clone()
    }

    /// The smoothed value at voxel `index`, or `None` outside the grid or if it was
    /// not computed.
    pub fn value(&self, index: [usize; 3]) -> Option<f64> {
        self.components::<1>(0, index).map(|[f]| f)
    }

    /// The world-space gradient at voxel `index` (`R g` for the direction `R` and the
    /// gradient `g` along the axes), or `None` outside the grid or if a first
    /// derivative was not computed.
    pub fn gradient(&self, index: [usize; 3]) -> Option<Vector> {
        let local = Vector::from(self.components::<3>(1, index)?);
        Some(self.direction * local)
    }

    /// The world-space Hessian at voxel `index` (`R H Rᵀ`), or `None` outside the
    /// grid or if a second derivative was not computed.
    pub fn hessian(&self, index: [usize; 3]) -> Option<Matrix3<f64>> {
        let local = hessian_from_components(self.components::<6>(4, index)?);
        Some(self.direction * local * self.direction.transpose())
    }

    /// The world-space third derivatives at voxel `index`, or `None` outside the grid
    /// or if a third derivative was not computed.
    pub fn third(&self, index: [usize; 3]) -> Option<ThirdOrder> {
        let local = ThirdOrder::from_components(self.components::<10>(10, index)?);
        Some(local.pulled_back(&self.direction.transpose()))
    }

    /// Value and world-space derivatives up to order 3 at voxel `index`, or `None`
    /// outside the grid or unless all 20 partials were computed.
    pub fn jet(&self, index: [usize; 3]) -> Option<Jet> {
        Some(
            self.axis_jet(index)?
                .pulled_back(&self.direction.transpose()),
        )
    }

    /// [`Derivatives::jet`] in the frame of the grid's index axes (lengths in world
    /// units): the world frame turned by the direction matrix, which is orthonormal.
    /// Quantities that do not change under rotation (curvatures, extremalities)
    /// computed in it depend on the samples and the spacing only, not on how the
    /// image is placed in the world.
    pub fn axis_jet(&self, index: [usize; 3]) -> Option<Jet> {
        Some(Jet::from_partials(&self.components::<20>(0, index)?))
    }

    /// The values at voxel `index` of the `N` partials of [`Partial::ALL`] from
    /// position `first` on, along the index axes.
    pub(crate) fn components<const N: usize>(
        &self,
        first: usize,
        index: [usize; 3],
    ) -> Option<[f64; N]> {
        let [i, j, k] = index;
        let k = k.checked_sub(self.slices.start)?;
        let [nx, ny, _] = self.dims;
        let at = Grid {
            dims: [nx, ny, self.slices.len()],
        }
        .checked_index([i, j, k])?;
        let mut values = [0.0; N];
        for (value, partial) in values.iter_mut().zip(&Partial::ALL[first..]) {
            *value = f64::from(self.grid(*partial)?[at]);
        }
        Some(values)
    }
}

/// An error unless the approximating cubic B-spline has derivatives of `order` at
/// the grid points (up to 2: its third derivatives jump there).
fn check_spline_order(order: usize) -> Result<()> {
    if order > 2 {
        return Err(Error::Argument(format!(
            "the approximating cubic B-spline has derivatives up to order 2 at the grid points, not {order}"
        )));
    }
    Ok(())
}

/// The volume's direction matrix, or an error unless it is orthonormal.
fn orthonormal_direction(volume: &Volume) -> Result<Matrix3<f64>> {
    let direction = *volume.direction();
    let defect = (direction.transpose() * direction - Matrix3::identity())
        .abs()
        .max();
    if defect > 1e-6 {
        return Err(Error::Argument(format!(
            "Gaussian derivatives need an orthonormal direction matrix (a Gaussian \
             isotropic in the world), but RᵀR differs from the identity by {defect:.3e}"
        )));
    }
    Ok(direction)
}

/// For each axis, the kernels of orders 0 to 3 for σ (world units), scaled to
/// derivatives with respect to world length (`1 / spacingᵐ`).
/// The approximating cubic B-spline's kernels of orders 0 to 2 along each axis
/// (world units: order m scaled by spacing⁻ᵐ), in the correlation form of
/// [`HalfKernel`]: c[t] = (−1)ᵐ β³⁽ᵐ⁾(t).
fn spline_kernels(spacing: [f64; 3]) -> [AxisKernels; 3] {
    const TAPS: [([f64; 2], bool); 3] = [
        ([4.0 / 6.0, 1.0 / 6.0], false),
        // β³′(1) = −1/2, so c[1] = +1/2 (c[−1] = −1/2).
        ([0.0, 0.5], true),
        ([-2.0, 1.0], false),
    ];
    spacing.map(|h| {
        TAPS.iter()
            .enumerate()
            .map(|(order, (taps, odd))| HalfKernel {
                taps: taps
                    .iter()
                    .map(|t| (t * h.powi(-(order as i32))) as f32)
                    .collect(),
                odd: *odd,
            })
            .collect()
    })
}

fn world_kernels(volume: &Volume, sigma: f64) -> Result<[AxisKernels; 3]> {
    let dims = volume.dims();
    let spacing = volume.spacing();
    let axis = |a: usize| -> Result<AxisKernels> {
        let voxels = check_sigma(sigma, spacing[a], dims[a], a)?;
        (0..=MAX_ORDER)
            .map(|order| {
                let kernel = Kernel::gaussian(voxels, order)?;
                Ok(HalfKernel {
                    taps: kernel.half_scaled(spacing[a].powi(-(order as i32))),
                    odd: kernel.is_odd(),
                })
            })
            .collect()
    };
    Ok([axis(0)?, axis(1)?, axis(2)?])
}

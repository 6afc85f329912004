//! 3D images: a regular grid of scalar samples placed in world space.
//!
//! A [`Volume`] holds `nx × ny × nz` samples as `f32`, x fastest in memory, with the
//! geometry that places voxel `(i, j, k)` in the world:
//!
//! `world = origin + direction · (spacing ⊙ (i, j, k))`
//!
//! where `spacing` is the size of a voxel along each index axis (world units,
//! usually mm) and the columns of `direction` are the world directions of the
//! three index axes. The readers in [`crate::io`] fill volumes from image files;
//! which world convention a volume uses (e.g. RAS+ for NIfTI) is stated by each
//! reader.
//!
//! [`Derivatives`] computes Gaussian derivatives of orders 0 to 3 on the grid
//! (separable, moment-corrected kernels, σ in world units) and `BSpline` the C²
//! cubic B-spline that interpolates the samples, both with world-space gradients,
//! Hessians and third derivatives. The image extractors build on it: isosurfaces
//! ([`crate::isosurface`]), crest lines by Marching Lines ([`crate::crest_lines`])
//! and crease surfaces.

pub(crate) mod bspline;
pub(crate) mod derivatives;
pub(crate) mod grid;
pub(crate) mod jet;
pub(crate) mod kernels;
mod separable;
mod statistics;
pub(crate) mod trilinear;
pub(crate) mod voxel_set;

pub(crate) use bspline::BSpline;
pub(crate) use derivatives::Smoothing;
pub use derivatives::{Derivatives, Partial};
pub(crate) use jet::Jet;
#[cfg(test)]
pub(crate) use jet::ThirdOrder;
pub use statistics::ValueSummary;

use crate::{Error, Point, Result, Space, Vector};
use grid::Grid;
use nalgebra::{Matrix3, Matrix4};

/// A scalar 3D image: samples on a regular grid with its placement in world space.
///
/// Built by [`Volume::new`], which checks that the geometry is usable; the fields
/// are read through accessors so that the checks hold for the volume's lifetime.
#[derive(Clone, Debug, PartialEq)]
pub struct Volume {
    dims: [usize; 3],
    spacing: [f64; 3],
    origin: [f64; 3],
    direction: Matrix3<f64>,
    /// `(direction · diag(spacing))⁻¹`, cached for [`Volume::world_to_index`].
    world_to_grid: Matrix3<f64>,
    samples: Vec<f32>,
    /// The anatomical frame of the world coordinates, if the file declared one.
    space: Option<Space>,
}

impl Volume {
    /// A volume of `dims` samples (x fastest: sample `(i, j, k)` is at
    /// `i + nx·(j + ny·k)`), voxel `spacing`, world position `origin` of voxel
    /// `(0, 0, 0)` and `direction` matrix whose columns are the world directions of
    /// the index axes (the identity for an axis-aligned image).
    ///
    /// Errors ([`Error::Argument`]) if a dimension is zero, the number of voxels
    /// overflows, `samples` does not hold exactly that many values, a spacing is not
    /// finite and positive, or the origin or direction is not finite or the
    /// direction is singular.
    pub fn new(
        dims: [usize; 3],
        spacing: [f64; 3],
        origin: [f64; 3],
        direction: Matrix3<f64>,
        samples: Vec<f32>,
    ) -> Result<Volume> {
        let count = voxel_count(dims)?;
        if samples.len() != count {
            return Err(invalid(format!(
                "{} samples for {}×{}×{} = {count} voxels",
                samples.len(),
                dims[0],
                dims[1],
                dims[2]
            )));
        }
        if !spacing.iter().all(|s| s.is_finite() && *s > 0.0) {
            return Err(invalid(format!(
                "the voxel spacing {spacing:?} is not finite and positive"
            )));
        }
        if !origin.iter().all(|o| o.is_finite()) {
            return Err(invalid(format!("the origin {origin:?} is not finite")));
        }
        let world_to_grid = grid_inverse(&direction, spacing)?;
        check_world_box(dims, spacing, origin, &direction)?;
        Ok(Volume {
            dims,
            spacing,
            origin,
            direction,
            world_to_grid,
            samples,
            space: None,
        })
    }

    /// The volume with its world coordinates declared to be in `space` (`None`:
    /// no anatomical frame, e.g. a volume made from arrays).
    pub fn with_space(self, space: Option<Space>) -> Volume {
        Volume { space, ..self }
    }

    /// The smallest and largest sample (`(∞, −∞)` when every sample is NaN).
    pub fn value_range(&self) -> (f32, f32) {
        self.samples
            .iter()
            .fold((f32::INFINITY, f32::NEG_INFINITY), |(lo, hi), &v| {
                (lo.min(v), hi.max(v))
            })
    }

    /// The anatomical frame of the world coordinates, if known: from the reader
    /// (NIfTI: RAS; NRRD: its `space`; MetaImage: LPS) or [`Volume::with_space`].
    /// Every surface, line and landmark derived from the volume carries it.
    pub fn space(&self) -> Option<Space> {
        self.space
    }

    /// The number of samples along x, y and z.
    pub fn dims(&self) -> [usize; 3] {
        self.dims
    }

    /// The size of a voxel along each index axis, in world units.
    pub fn spacing(&self) -> [f64; 3] {
        self.spacing
    }

    /// The world position of voxel `(0, 0, 0)`.
    pub fn origin(&self) -> [f64; 3] {
        self.origin
    }

    /// The direction matrix: column `a` is the world direction of index axis `a`.
    pub fn direction(&self) -> &Matrix3<f64> {
        &self.direction
    }

    /// All samples, x fastest, then y, then z.
    pub fn samples(&self) -> &[f32] {
        &self.samples
    }

    /// The number of samples (`nx · ny · nz`).
    pub fn len(&self) -> usize {
        self.samples.len()
    }

    /// Whether the volume has no samples: never true, since [`Volume::new`] refuses
    /// zero dimensions.
    pub fn is_empty(&self) -> bool {
        self.samples.is_empty()
    }

    /// The position of sample `(i, j, k)` in [`Volume::samples`], or `None` outside
    /// the grid.
    #[inline]
    pub fn linear_index(&self, i: usize, j: usize, k: usize) -> Option<usize> {
        self.grid().checked_index([i, j, k])
    }

    /// The index arithmetic of the volume's grid.
    #[inline]
    pub(crate) fn grid(&self) -> Grid {
        Grid { dims: self.dims }
    }

    /// The sample at voxel `(i, j, k)`, or `None` outside the grid.
    #[inline]
    pub fn value(&self, i: usize, j: usize, k: usize) -> Option<f32> {
        self.linear_index(i, j, k).map(|at| self.samples[at])
    }

    /// The world position of the (possibly fractional) voxel index `index`.
    pub fn index_to_world(&self, index: [f64; 3]) -> Point {
        let scaled = Vector::new(
            index[0] * self.spacing[0],
            index[1] * self.spacing[1],
            index[2] * self.spacing[2],
        );
        Point::from(self.origin) + self.direction * scaled
    }

    /// The fractional voxel index of world position `point`: the inverse of
    /// [`Volume::index_to_world`].
    pub fn world_to_index(&self, point: &Point) -> [f64; 3] {
        let grid = self.world_to_grid * (point - Point::from(self.origin));
        [grid.x, grid.y, grid.z]
    }

    /// The trilinear interpolation of the samples at world position `point`, or
    /// `None` outside the grid (by more than a rounding error).
    pub fn interpolate(&self, point: &Point) -> Option<f64> {
        let (corners, weights) =
            trilinear::corners_and_weights(self.dims, self.world_to_index(point))?;
        Some(
            corners
                .iter()
                .zip(weights)
                .map(|(&c, w)| w * f64::from(self.samples[c]))
                .sum(),
        )
    }

    /// `∂index/∂world = (direction · diag(spacing))⁻¹`: the matrix that
    /// [`Volume::world_to_index`] applies to `point − origin`, and the Jacobian that
    /// turns derivatives along the index axes into world derivatives (∇ₓf =
    /// Jᵀ ∇ᵢf).
    pub fn world_to_grid(&self) -> &Matrix3<f64> {
        &self.world_to_grid
    }

    /// Sets every sample that is not finite (NaN, ±∞: e.g. outside the mask of a
    /// resampled scan) to `value`, and returns how many there were.
    pub fn replace_non_finite(&mut self, value: f32) -> usize {
        let mut count = 0;
        for sample in self.samples.iter_mut().filter(|s| !s.is_finite()) {
            *sample = value;
            count += 1;
        }
        count
    }

    /// The 4 × 4 voxel-to-world affine, `[direction · diag(spacing) | origin]`, as
    /// NIfTI's sform and nibabel write it.
    pub fn affine(&self) -> Matrix4<f64> {
        let mut affine = Matrix4::identity();
        for c in 0..3 {
            let column = self.direction.column(c) * self.spacing[c];
            affine.fixed_view_mut::<3, 1>(0, c).copy_from(&column);
            affine[(c, 3)] = self.origin[c];
        }
        affine
    }

    /// A volume placed by a voxel-to-world `affine` ([`Volume::affine`]): the
    /// spacing is the length of each of its first three columns, the direction
    /// those columns normalised, the origin its last column. Errors as
    /// [`Volume::new`] (a zero column is a spacing that is not positive).
    pub fn from_affine(
        dims: [usize; 3],
        affine: &Matrix4<f64>,
        samples: Vec<f32>,
    ) -> Result<Volume> {
        let (spacing, origin, direction) = split_affine(affine);
        Volume::new(dims, spacing, origin, direction, samples)
    }

    /// The volume with one more sample of `value` on every side of the grid (and
    /// its origin moved back by a voxel), in the same place and frame: an
    /// isosurface of it that reaches the border of the grid is closed there when
    /// `value` is outside the surface.
    pub fn padded(&self, value: f32) -> Result<Volume> {
        self.clone().into_padded(value)
    }

    /// [`Volume::padded`], reusing this volume's memory: the samples are grown in
    /// place (a large allocation is remapped, not copied) and moved to their padded
    /// places from the last down, so that no second copy of the image is held.
    pub fn into_padded(self, value: f32) -> Result<Volume> {
        let [nx, ny, nz] = self.dims;
        let dims = [nx + 2, ny + 2, nz + 2];
        let origin = self.index_to_world([-1.0; 3]);
        let padded = Grid { dims };
        let mut samples = self.samples;
        samples.resize(voxel_count(dims)?, value);
        // Every sample moves to a higher index, so going down never overwrites one
        // still to move.
        for k in (0..nz).rev() {
            for j in (0..ny).rev() {
                let from = nx * (j + ny * k);
                samples.copy_within(from..from + nx, padded.index([1, j + 1, k + 1]));
            }
        }
        for k in 0..dims[2] {
            for j in 0..dims[1] {
                let row = &mut samples[padded.index([0, j, k])..][..dims[0]];
                if (1..=ny).contains(&j) && (1..=nz).contains(&k) {
                    row[0] = value;
                    row[nx + 1] = value;
                } else {
                    row.fill(value);
                }
            }
        }
        Ok(
            Volume::new(dims, self.spacing, origin.into(), self.direction, samples)?
                .with_space(self.space),
        )
    }

    /// A volume with this one's grid, placement and frame and other `samples`
    /// (e.g. a filtered copy). Errors if their number differs.
    pub fn with_samples(&self, samples: Vec<f32>) -> Result<Volume> {
        Ok(Volume::new(
            self.dims,
            self.spacing,
            self.origin,
            self.direction,
            samples,
        )?
        .with_space(self.space))
    }
}

/// The largest world coordinate a grid may reach. Beyond it the positions of
/// neighbouring voxels are no longer resolved in f64 at any usual spacing, and
/// surfaces and lines derived from them would have non-finite or collapsed
/// coordinates (1e12 mm is a million kilometres).
pub(crate) const MAX_WORLD_COORDINATE: f64 = 1e12;

/// Refuse a placement whose grid reaches beyond [`MAX_WORLD_COORDINATE`] (a far
/// origin, a spacing of 1e308): said now, naming the spacing and origin, rather
/// than as a failure of the extraction later.
fn check_world_box(
    dims: [usize; 3],
    spacing: [f64; 3],
    origin: [f64; 3],
    direction: &Matrix3<f64>,
) -> Result<()> {
    let step = direction * Matrix3::from_diagonal(&Vector::from(spacing));
    let far = (0..8)
        .map(|corner| {
            let index = Vector::from_fn(|axis, _| {
                if corner >> axis & 1 == 1 {
                    (dims[axis] - 1) as f64
                } else {
                    0.0
                }
            });
            Point::from(origin) + step * index
        })
        .flat_map(|p| [p.x, p.y, p.z])
        .fold(0.0f64, |far, c| {
            if c.is_finite() {
                far.max(c.abs())
            } else {
                f64::INFINITY
            }
        });
    if far <= MAX_WORLD_COORDINATE {
        return Ok(());
    }
    Err(invalid(format!(
        "the voxel spacing {spacing:?} and origin {origin:?} place the grid at world \
         coordinates of {far:e}, beyond ±{MAX_WORLD_COORDINATE:e}"
    )))
}

/// The spacing, origin and direction of a voxel-to-world `affine`
/// ([`Volume::from_affine`]).
pub fn split_affine(affine: &Matrix4<f64>) -> ([f64; 3], [f64; 3], Matrix3<f64>) {
    let linear: Matrix3<f64> = affine.fixed_view::<3, 3>(0, 0).into_owned();
    let spacing: [f64; 3] = std::array::from_fn(|c| linear.column(c).norm());
    let direction = Matrix3::from_fn(|row, column| linear[(row, column)] / spacing[column]);
    let origin = std::array::from_fn(|row| affine[(row, 3)]);
    (spacing, origin, direction)
}

/// Most voxels a volume may have (2^34, 64 GiB of `f32`): far more than any image
/// that fits in memory, few enough that a corrupt header is caught before anything
/// is allocated for it.
pub(crate) const MAX_VOXELS: u64 = 1 << 34;

/// `nx · ny · nz`, checked: every dimension positive and the product at most
/// [`MAX_VOXELS`].
pub(crate) fn voxel_count(dims: [usize; 3]) -> Result<usize> {
    if dims.contains(&0) {
        return Err(invalid(format!("a dimension is zero in {dims:?}")));
    }
    dims.iter()
        .try_fold(1u64, |product, &n| {
            product
                .checked_mul(u64::try_from(n).ok()?)
                .filter(|&p| p <= MAX_VOXELS)
        })
        .and_then(|count| usize::try_from(count).ok())
        .ok_or_else(|| {
            invalid(format!(
                "{}×{}×{} voxels are more than the {MAX_VOXELS} supported (a corrupt header?)",
                dims[0], dims[1], dims[2]
            ))
        })
}

/// `(direction · diag(spacing))⁻¹`, or an error if `direction` is not finite or
/// is singular.
fn grid_inverse(direction: &Matrix3<f64>, spacing: [f64; 3]) -> Result<Matrix3<f64>> {
    if !direction.iter().all(|d| d.is_finite()) {
        return Err(invalid("the direction matrix is not finite".to_string()));
    }
    if direction.determinant().abs() < 1e-9 {
        return Err(invalid(format!(
            "the direction matrix is singular: {:?}",
            direction.as_slice()
        )));
    }
    let scaled = direction * Matrix3::from_diagonal(&Vector::from(spacing));
    match scaled.try_inverse() {
        Some(inverse) if inverse.iter().all(|x| x.is_finite()) => Ok(inverse),
        _ => Err(invalid(format!(
            "the voxel spacing {spacing:?} is too small to invert (world to grid coordinates overflow)"
        ))),
    }
}

/// An [`Error::Argument`] about an invalid volume.
fn invalid(message: String) -> Error {
    Error::Argument(format!("invalid volume: {message}"))
}

#[cfg(test)]
mod tests {
    mod volume_derivatives;

    use super::*;

    #[test]
    fn a_grid_placed_beyond_the_representable_world_is_refused() {
        let new = |spacing: [f64; 3], origin: [f64; 3]| {
            Volume::new(
                [3, 3, 3],
                spacing,
                origin,
                Matrix3::identity(),
                vec![0.0; 27],
            )
        };
        assert!(new([1.0; 3], [-98.0, -134.0, -72.0]).is_ok());
        for (spacing, origin) in [([1e308, 1.0, 1.0], [0.0; 3]), ([1.0; 3], [0.0, 2e12, 0.0])] {
            let error = new(spacing, origin).unwrap_err().to_string();
            assert!(
                error.contains("spacing") && error.contains("origin"),
                "{error}"
            );
        }
        // A spacing so small that grid coordinates overflow is blamed, not the
        // (identity) direction matrix.
        let error = new([1e-310, 1.0, 1.0], [0.0; 3]).unwrap_err().to_string();
        assert!(
            error.contains("spacing") && !error.contains("singular"),
            "{error}"
        );
    }

    #[test]
    fn the_affine_places_voxels_as_index_to_world_and_gives_the_volume_back() {
        let turn = nalgebra::Rotation3::from_euler_angles(0.3, -0.2, 0.7).into_inner();
        let samples: Vec<f32> = (0..24).map(|v| v as f32).collect();
        let volume = Volume::new(
            [4, 3, 2],
            [0.5, 1.0, 2.0],
            [1.0, -2.0, 3.0],
            turn,
            samples.clone(),
        )
        .unwrap();
        let affine = volume.affine();
        let index = [1.5, 2.0, 0.25];
        let placed = affine * nalgebra::Vector4::new(index[0], index[1], index[2], 1.0);
        assert!((placed.xyz() - volume.index_to_world(index).coords).norm() < 1e-12);
        let again = Volume::from_affine([4, 3, 2], &affine, samples).unwrap();
        assert!((again.affine() - affine).norm() < 1e-12);
        assert!(again
            .spacing()
            .iter()
            .zip(volume.spacing())
            .all(|(a, b)| (a - b).abs() < 1e-12));
        let mut flat = affine;
        flat.set_column(1, &nalgebra::Vector4::zeros());
        assert!(Volume::from_affine([4, 3, 2], &flat, vec![0.0; 24]).is_err());
    }

    fn ramp() -> Volume {
        let samples = (0..24).map(|v| v as f32).collect();
        Volume::new(
            [4, 3, 2],
            [0.5, 1.0, 2.0],
            [10.0, 20.0, 30.0],
            Matrix3::identity(),
            samples,
        )
        .unwrap()
    }

    #[test]
    fn samples_are_x_fastest() {
        let volume = ramp();
        assert_eq!(volume.len(), 24);
        assert_eq!(volume.value(1, 0, 0), Some(1.0));
        assert_eq!(volume.value(0, 1, 0), Some(4.0));
        assert_eq!(volume.value(0, 0, 1), Some(12.0));
        assert_eq!(volume.value(3, 2, 1), Some(23.0));
        assert_eq!(volume.value(4, 0, 0), None);
    }

    #[test]
    fn index_and_world_are_inverse() {
        let rotation = Matrix3::new(0.0, -1.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0);
        let volume = Volume::new(
            [2, 2, 2],
            [0.5, 2.0, 3.0],
            [1.0, 2.0, 3.0],
            rotation,
            vec![0.0; 8],
        )
        .unwrap();
        let world = volume.index_to_world([1.0, 1.0, 1.0]);
        assert_eq!(world, Point::new(1.0 - 2.0, 2.0 + 0.5, 3.0 + 3.0));
        let back = volume.world_to_index(&world);
        for (b, e) in back.iter().zip([1.0, 1.0, 1.0]) {
            assert!((b - e).abs() < 1e-12, "{back:?}");
        }
    }

    #[test]
    fn bad_geometry_is_refused() {
        let identity = Matrix3::identity();
        let new = |dims, spacing, origin, direction, n| {
            Volume::new(dims, spacing, origin, direction, vec![0.0; n])
        };
        assert!(new([0, 1, 1], [1.0; 3], [0.0; 3], identity, 0).is_err());
        assert!(new([2, 1, 1], [1.0; 3], [0.0; 3], identity, 1).is_err());
        assert!(new([1, 1, 1], [1.0, 0.0, 1.0], [0.0; 3], identity, 1).is_err());
        assert!(new([1, 1, 1], [1.0, f64::NAN, 1.0], [0.0; 3], identity, 1).is_err());
        assert!(new([1, 1, 1], [1.0; 3], [f64::INFINITY, 0.0, 0.0], identity, 1).is_err());
        assert!(new([1, 1, 1], [1.0; 3], [0.0; 3], Matrix3::zeros(), 1).is_err());
        let huge = voxel_count([usize::MAX, 2, 1]).unwrap_err().to_string();
        assert!(huge.contains("more than"), "{huge}");
    }
}

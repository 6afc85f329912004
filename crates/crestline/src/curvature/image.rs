//! Curvature of an isosurface taken from the image it was extracted from, not from
//! its triangles (Thirion & Gourdon 1993, part 1: differential characteristics of
//! iso-intensity surfaces; conventions of docs/design/images.md, "Isosurfaces and implicit
//! curvature").
//!
//! At a point p of the surface f = I, with g = ∇f and H the Hessian of the
//! (smoothed) image at p: n = −g/|g|, P = I − n nᵀ and the shape operator
//! W = −P H P / |g|, so a bright convex object has positive curvature
//! ([`implicit_curvature`] of −f). The image is made differentiable either by a
//! Gaussian (derivatives at the grid points, [`Derivatives`], interpolated
//! trilinearly; at every grid point, or only at the corners of the cells that hold
//! given points, [`ImageCurvature::at_points`]) or by the cubic B-spline through
//! the samples ([`BSpline`]).
//!
//! The third derivatives give the extremalities too (`e = ∇k · t`, Thirion &
//! Gourdon's extremality; [`isosurface_curvature`]), which the estimate hands to the
//! ridge tracer ([`CurvatureField::extremality`]) in place of differences of the
//! curvature across the triangles.

use std::borrow::Cow;

use nalgebra::Matrix3;
use rayon::prelude::*;

use super::PrincipalCurvatures;
use super::{isosurface_curvature, CurvatureEstimator, CurvatureField, IsoCurvature};
#[cfg(test)]
use crate::isosurface::{isosurface, Isosurface};
use crate::mesh::Mesh;
use crate::volume::trilinear::corners_and_weights;
use crate::volume::voxel_set::{VoxelSet, VoxelSetBuilder};
use crate::volume::{BSpline, Derivatives, Jet, Partial, Volume};
use crate::{Error, Point, Result, Vector};

/// The partials of order 1 to 3 along the index axes (fx fy fz; fxx fxy fxz fyy
/// fyz fzz; fxxx … fzzz), in the order of [`Partial::ALL`] from position 1.
const FIRST_TO_THIRD: std::ops::Range<usize> = 1..20;

/// How many partials [`FIRST_TO_THIRD`] holds.
const PARTIALS: usize = FIRST_TO_THIRD.end - FIRST_TO_THIRD.start;

/// How many of them are of order 1 and 2 (they come first).
const FIRST_AND_SECOND: usize = 9;

/// The highest order of the image's derivatives an [`ImageCurvature`] made for
/// some points keeps ([`ImageCurvature::at_points`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DerivativeOrder {
    /// First and second derivatives: the curvature (9 partials per grid point).
    Second,
    /// Up to the third: the curvature and its extremalities (19 partials).
    Third,
}

/// Image-based curvature: a [`CurvatureEstimator`] that gives every vertex of a
/// surface in the image's world the curvature of the isosurface of the image
/// through that vertex. For an isosurface mesh this is the curvature of the
/// surface the mesh approximates, free of the noise of its triangles.
#[derive(Clone, Debug)]
pub struct ImageCurvature {
    reconstruction: Reconstruction,
}

/// How the image is differentiated between samples.
#[derive(Clone, Debug)]
enum Reconstruction {
    /// Gaussian derivatives at the grid points, trilinear in between.
    Gaussian {
        partials: GridPartials,
        origin: Point,
        world_to_grid: Matrix3<f64>,
        direction: Matrix3<f64>,
    },
    /// The C² cubic B-spline through the samples.
    Spline(BSpline),
}

/// The partials of order 1 to 3 of the smoothed image (along the index axes, in
/// the order of [`FIRST_TO_THIRD`]) at grid points.
#[derive(Clone, Debug)]
enum GridPartials {
    /// At every grid point, with the smoothed values.
    Whole(Derivatives),
    /// At the members of `voxels` only, numbered by it.
    Some {
        dims: [usize; 3],
        voxels: VoxelSet,
        values: HeldPartials,
    },
}

/// The partials held at some grid points: all of [`FIRST_TO_THIRD`], or those of
/// order 1 and 2 only.
#[derive(Clone, Debug)]
enum HeldPartials {
    Second(Vec<[f32; FIRST_AND_SECOND]>),
    Third(Vec<[f32; PARTIALS]>),
}

impl HeldPartials {
    /// The partials of point number `k`, those of third order zero if not held.
    fn get(&self, k: usize) -> [f32; PARTIALS] {
        match self {
            HeldPartials::Second(values) => {
                let mut all = [0.0; PARTIALS];
                all[..FIRST_AND_SECOND].copy_from_slice(&values[k]);
                all
            }
            HeldPartials::Third(values) => values[k],
        }
    }
}

impl GridPartials {
    /// The number of samples along each axis of the grid.
    fn dims(&self) -> [usize; 3] {
        match self {
            GridPartials::Whole(derivatives) => derivatives.dims(),
            GridPartials::Some { dims, .. } => *dims,
        }
    }

    /// The partials at the sample of linear index `at`, `None` where not held.
    fn at(&self, at: usize) -> Option<[f32; PARTIALS]> {
        match self {
            GridPartials::Whole(derivatives) => {
                let mut values = [0.0; PARTIALS];
                for (value, partial) in values.iter_mut().zip(&Partial::ALL[FIRST_TO_THIRD]) {
                    *value = derivatives.grid(*partial)?[at];
                }
                Some(values)
            }
            GridPartials::Some { voxels, values, .. } => Some(values.get(voxels.number(at)?)),
        }
    }
}

impl ImageCurvature {
    /// [`ImageCurvature::gaussian`] for `sigma > 0`, [`ImageCurvature::spline`] for
    /// `sigma = 0`.
    ///
    /// Errors ([`Error::Argument`]) for a negative or non-finite σ, and as
    /// [`ImageCurvature::gaussian`].
    pub fn new(volume: &Volume, sigma: f64) -> Result<ImageCurvature> {
        ImageCurvature::check_sigma(sigma)?;
        if sigma == 0.0 {
            Ok(ImageCurvature::spline(volume))
        } else {
            ImageCurvature::gaussian(volume, sigma)
        }
    }

    /// Errors ([`Error::Argument`]) unless `sigma` is finite and ≥ 0 (0: the
    /// spline, no smoothing).
    pub(crate) fn check_sigma(sigma: f64) -> Result<()> {
        if sigma >= 0.0 && sigma.is_finite() {
            Ok(())
        } else {
            Err(Error::Argument(format!(
                "the smoothing σ must be finite and ≥ 0 (0: no smoothing), not {sigma}"
            )))
        }
    }

    /// [`ImageCurvature::new`] to be evaluated at `points` (world coordinates)
    /// only: with σ > 0 the derivatives are kept at the corners of the cells that
    /// hold the points (elsewhere the curvature is `None`, as outside the grid),
    /// computed a few z slices at a time, so that
    /// memory grows with the points rather than with the image. At the points, the
    /// same values as [`ImageCurvature::new`]'s. With `order`
    /// [`DerivativeOrder::Second`] only the first and second derivatives are
    /// computed and kept: the curvature, without extremalities
    /// ([`gives_extremalities`](Self::gives_extremalities) is false).
    ///
    /// Errors as [`ImageCurvature::new`].
    pub fn at_points(
        volume: &Volume,
        sigma: f64,
        points: &[Point],
        order: DerivativeOrder,
    ) -> Result<ImageCurvature> {
        ImageCurvature::check_sigma(sigma)?;
        if sigma == 0.0 {
            return Ok(ImageCurvature::spline(volume));
        }
        let origin = Point::from(volume.origin());
        let world_to_grid = *volume.world_to_grid();
        let mut voxels = VoxelSetBuilder::new(volume.len());
        for point in points {
            let index = world_to_grid * (point - origin);
            if let Some((corners, _)) = corners_and_weights(volume.dims(), index.into()) {
                corners.into_iter().for_each(|at| voxels.insert(at));
            }
        }
        let voxels = voxels.build();
        let values = match order {
            DerivativeOrder::Second => HeldPartials::Second(partials_at(volume, sigma, &voxels)?),
            DerivativeOrder::Third => HeldPartials::Third(partials_at(volume, sigma, &voxels)?),
        };
        Ok(ImageCurvature {
            reconstruction: Reconstruction::Gaussian {
                partials: GridPartials::Some {
                    dims: volume.dims(),
                    voxels,
                    values,
                },
                origin,
                world_to_grid,
                direction: *volume.direction(),
            },
        })
    }

    /// The image whose isosurfaces this curvature belongs to: `volume` smoothed
    /// (for the Gaussian), or `volume` itself (for the spline). `volume` must be the
    /// one this curvature was made from.
    ///
    /// Errors ([`Error::Argument`]) for a curvature made for some points
    /// ([`ImageCurvature::at_points`]), which keeps no smoothed image.
    pub fn surface_volume<'v>(&self, volume: &'v Volume) -> Result<Cow<'v, Volume>> {
        match (&self.reconstruction, self.smoothed()) {
            (_, Some(smoothed)) => Ok(Cow::Owned(volume.with_samples(smoothed.to_vec())?)),
            (Reconstruction::Spline(_), None) => Ok(Cow::Borrowed(volume)),
            (Reconstruction::Gaussian { .. }, None) => Err(Error::Argument(
                "this image curvature was made for some points only and keeps no smoothed image"
                    .to_string(),
            )),
        }
    }

    /// Curvature of the image smoothed by a Gaussian of standard deviation `sigma`
    /// (world units): its derivatives of order 1 to 3 are computed on the grid
    /// (with the smoothed values, [`ImageCurvature::smoothed`]): twenty volumes of
    /// the image's size; [`ImageCurvature::at_points`] keeps them only where asked.
    ///
    /// Errors as [`Derivatives::new`] (σ not finite and positive, or absurd for
    /// the grid; a direction matrix that is not orthonormal).
    pub fn gaussian(volume: &Volume, sigma: f64) -> Result<ImageCurvature> {
        Ok(ImageCurvature {
            reconstruction: Reconstruction::Gaussian {
                partials: GridPartials::Whole(Derivatives::new(volume, sigma, 3)?),
                origin: Point::from(volume.origin()),
                world_to_grid: *volume.world_to_grid(),
                direction: *volume.direction(),
            },
        })
    }

    /// Curvature of the cubic B-spline that interpolates the samples (no
    /// smoothing: exact on smooth images, noisy on noisy ones).
    pub fn spline(volume: &Volume) -> ImageCurvature {
        ImageCurvature {
            reconstruction: Reconstruction::Spline(BSpline::new(volume)),
        }
    }

    /// The Gaussian-smoothed samples, the image whose isosurfaces this curvature
    /// belongs to; `None` for the spline, which interpolates the samples as they
    /// are, and for a curvature made for some points only
    /// ([`ImageCurvature::at_points`]).
    pub fn smoothed(&self) -> Option<&[f32]> {
        match &self.reconstruction {
            Reconstruction::Gaussian {
                partials: GridPartials::Whole(derivatives),
                ..
            } => derivatives.grid(Partial::ALL[0]),
            _ => None,
        }
    }

    /// The gradient and Hessian of the image at world position `point`, or `None`
    /// outside the grid.
    pub fn derivatives_at(&self, point: &Point) -> Option<(Vector, Matrix3<f64>)> {
        let jet = self.jet_at(point)?;
        Some((jet.gradient, jet.hessian))
    }

    /// The derivatives of order 1 to 3 of the image at world position `point`, in
    /// world coordinates (the value is not kept: 0), or `None` outside the grid.
    pub fn jet_at(&self, point: &Point) -> Option<Jet> {
        match &self.reconstruction {
            Reconstruction::Gaussian {
                partials,
                origin,
                world_to_grid,
                direction,
            } => {
                let index = world_to_grid * (point - origin);
                let p = trilinear(partials, [index.x, index.y, index.z])?;
                let mut all = [0.0; 20];
                all[FIRST_TO_THIRD].copy_from_slice(&p);
                // The partials are along the index axes in world lengths; the
                // direction R is orthonormal (Derivatives checks it): g = R g_axes,
                // H = R H_axes Rᵀ, and so on.
                Some(Jet::from_partials(&all).pulled_back(&direction.transpose()))
            }
            Reconstruction::Spline(spline) => spline.jet_at_world(point),
        }
    }

    /// Whether the estimate gives the extremalities: with a Gaussian, whose
    /// derivatives are smooth. The cubic B-spline is C² only: its third derivatives
    /// jump across every grid plane, and their zero sets with them (on the MNI
    /// template, `--sigma 0`: 9,168 lines against 1,802 from differences of its
    /// curvature), so the ridge tracer differentiates the curvature instead.
    pub fn gives_extremalities(&self) -> bool {
        match &self.reconstruction {
            Reconstruction::Gaussian { partials, .. } => !matches!(
                partials,
                GridPartials::Some {
                    values: HeldPartials::Second(_),
                    ..
                }
            ),
            Reconstruction::Spline(_) => false,
        }
    }

    /// Principal curvatures, the outward normal n = −∇f/|∇f| and the
    /// extremalities of the isosurface through `point`, or `None` outside the grid
    /// or where the gradient vanishes.
    pub fn at(&self, point: &Point) -> Option<IsoCurvature> {
        let jet = self.jet_at(point)?;
        isosurface_curvature(&jet.gradient, &jet.hessian, &jet.third)
    }
}

impl CurvatureEstimator for ImageCurvature {
    /// The image's curvature at every vertex position, and with a Gaussian its
    /// extremalities ([`CurvatureField::extremality`]; [`Self::gives_extremalities`]).
    /// Vertices outside the grid or where the image gradient vanishes are marked
    /// unreliable and get zero curvature and extremality about the mesh's vertex
    /// normal.
    fn estimate(&self, mesh: &Mesh) -> Result<CurvatureField> {
        let normals = mesh.vertex_normals();
        let at: Vec<Option<IsoCurvature>> = mesh
            .par_vertices()
            .map(|v| self.at(&mesh.position(v)))
            .collect();
        let mut field = CurvatureField::from_fn(mesh.vertex_count(), |v| match &at[v.idx()] {
            Some(c) => (c.principal, c.normal, false),
            None => {
                let n = normals[v.idx()];
                let flat = PrincipalCurvatures::from_tangent_operator(&Matrix3::zeros(), &n);
                (flat, n, true)
            }
        });
        let extremality = |e: fn(&IsoCurvature) -> f64| -> Vec<f64> {
            at.iter().map(|c| c.as_ref().map_or(0.0, e)).collect()
        };
        if self.gives_extremalities() {
            field.extremality = Some([extremality(|c| c.e_max), extremality(|c| c.e_min)]);
        }
        Ok(field)
    }
}

/// The isosurface `f = level` of `volume` smoothed by a Gaussian of standard
/// deviation `sigma` (world units), with the image-based curvature of that
/// smoothed image; with `sigma = 0` the isosurface of the samples as they are and
/// the curvature of their cubic B-spline ([`ImageCurvature::new`]).
///
/// Errors as [`ImageCurvature::new`] and [`isosurface()`] (no surface at that
/// level, non-finite samples).
#[cfg(test)]
pub fn image_isosurface(
    volume: &Volume,
    level: f64,
    sigma: f64,
) -> Result<(Isosurface, ImageCurvature)> {
    let curvature = ImageCurvature::new(volume, sigma)?;
    let surface = isosurface(&*curvature.surface_volume(volume)?, level)?;
    Ok((surface, curvature))
}

/// The first `N` partials of [`FIRST_TO_THIRD`] of `volume` smoothed by `sigma`
/// at the members of `voxels`, in their numbering, as `f32` (NaN where not
/// defined).
fn partials_at<const N: usize>(
    volume: &Volume,
    sigma: f64,
    voxels: &VoxelSet,
) -> Result<Vec<[f32; N]>> {
    let partials = &Partial::ALL[FIRST_TO_THIRD.start..FIRST_TO_THIRD.start + N];
    Derivatives::at_voxels(volume, sigma, partials, voxels, |d, index| {
        let values = d.components::<N>(FIRST_TO_THIRD.start, index);
        values.map_or([f32::NAN; N], |v| v.map(|x| x as f32))
    })
}

/// The partials of order 1 to 3 at the fractional index `index`, interpolated
/// trilinearly; `None` outside the grid (beyond a small tolerance) or next to a
/// grid point whose partials are not held.
fn trilinear(partials: &GridPartials, index: [f64; 3]) -> Option<[f64; PARTIALS]> {
    let (corners, weights) = corners_and_weights(partials.dims(), index)?;
    let mut values = [[0.0; PARTIALS]; 8];
    for (value, &at) in values.iter_mut().zip(&corners) {
        *value = partials.at(at)?;
    }
    Some(std::array::from_fn(|p| {
        values
            .iter()
            .zip(weights)
            .map(|(value, w)| w * f64::from(value[p]))
            .sum()
    }))
}

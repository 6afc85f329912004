//! Gradients and Hessians of an image at its grid points, in world coordinates,
//! linearly interpolated in between, with the Hessian's eigenframe at every point
//! (Schultz, Theisel and Seidel 2010, §4.6: store derivatives, never interpolate T).
//!
//! A field may keep them only where a crease of a least strength can pass
//! ([`Survey`]): at the samples within two of a sample whose −λ3 may reach it, which
//! hold every cell with a strong corner and the cells around those (where the
//! normals' probes land). Elsewhere the field reads as flat (zero gradient and
//! Hessian), which no crease crosses.

use nalgebra::{Matrix3, SymmetricEigen};
use rayon::prelude::*;

use super::edges::CrossingOptions;
use super::tensor::Eigenframe;
use super::{DEFAULT_EPSILON_FRACTION, DEFAULT_STRENGTH_FRACTION, DEFAULT_THETA};
use crate::volume::grid::Grid;
use crate::volume::trilinear::corners_and_weights;
use crate::volume::voxel_set::{VoxelSet, VoxelSetBuilder};
use crate::volume::{Derivatives, Partial, Smoothing, Volume};
#[cfg(test)]
use crate::Error;
use crate::{Point, Result, Space, Vector};

/// Gradient and Hessian at one point, and the Hessian's eigenframe.
#[derive(Clone, Copy, Debug)]
pub struct Sample {
    /// ∇f in world coordinates.
    pub gradient: Vector,
    /// The Hessian in world coordinates.
    pub hessian: Matrix3<f64>,
    /// Its eigenvalues and e3.
    pub frame: Eigenframe,
}

impl Sample {
    fn new(gradient: Vector, hessian: Matrix3<f64>) -> Sample {
        Sample {
            gradient,
            hessian,
            frame: Eigenframe::of(&hessian),
        }
    }

    /// The sample a fraction `t` of the way from `a` to `b`: gradient and Hessian
    /// interpolated linearly, the eigenframe computed anew.
    pub fn between(a: &Sample, b: &Sample, t: f64) -> Sample {
        Sample::new(
            a.gradient.lerp(&b.gradient, t),
            a.hessian * (1.0 - t) + b.hessian * t,
        )
    }

    /// h = T g − g with the tensor of `epsilon` ([`Eigenframe::h`]).
    pub fn h(&self, epsilon: f64) -> Vector {
        self.frame.h(&self.gradient, epsilon)
    }
}

/// The image's gradients and Hessians at every grid point, for ridges of f (or of
/// −f, for valleys), and the grid's placement.
#[derive(Clone, Debug)]
pub struct CreaseField {
    dims: [usize; 3],
    /// The grid points with values, numbering `values` and `frames`; `None`: all.
    kept: Option<VoxelSet>,
    /// The least strength −λ3 of the creases this field holds all of (0 when it
    /// keeps every grid point).
    least_strength: f64,
    /// Gradient (3) and Hessian (xx xy xz yy yz zz) per grid point, world coordinates.
    values: Vec<[f32; 9]>,
    /// The Hessian's eigenframe per grid point, computed once: every grid point
    /// ends six edges.
    frames: Vec<Eigenframe>,
    origin: Point,
    /// direction · diag(spacing): world offset per index step.
    grid_to_world: Matrix3<f64>,
    /// Its inverse.
    world_to_grid: Matrix3<f64>,
    /// The smallest and largest Hessian eigenvalue over the grid, which the
    /// tests' default options are a fraction of.
    #[cfg_attr(not(test), allow(dead_code))]
    eigenvalue_range: (f64, f64),
    /// The anatomical frame of the world coordinates ([`Volume::space`]).
    space: Option<Space>,
}

impl CreaseField {
    /// The field of `derivatives` (orders 1 and 2 computed) of `volume`, negated for
    /// valleys (`ridges = false`: valleys of f are ridges of −f).
    ///
    /// Errors ([`Error::Argument`]) if a first or second partial is missing.
    #[cfg(test)]
    pub fn new(volume: &Volume, derivatives: &Derivatives, ridges: bool) -> Result<CreaseField> {
        let sign = if ridges { 1.0 } else { -1.0 };
        let grids: Vec<&[f32]> = Partial::ALL[1..10]
            .iter()
            .map(|p| derivatives.grid(*p))
            .collect::<Option<_>>()
            .ok_or_else(|| {
                Error::Argument("crease surfaces need first and second derivatives".into())
            })?;
        let r = *volume.direction();
        let values: Vec<[f32; 9]> = (0..volume.len())
            .into_par_iter()
            .map(|n| packed(std::array::from_fn(|c| grids[c][n]), sign, &r))
            .collect();
        let mut field = CreaseField::of_records(volume, None, 0.0, values, EMPTY_RANGE);
        field.eigenvalue_range = field
            .frames
            .par_iter()
            .map(|f| (f.eigenvalues[2], f.eigenvalues[0]))
            .reduce(|| EMPTY_RANGE, widest);
        Ok(field)
    }

    /// The field of `volume` with the packed `values` of the grid points `kept`
    /// (all with `None`), their eigenframes computed, holding every crease of at
    /// least `least_strength`, with the eigenvalue range `eigenvalue_range`.
    fn of_records(
        volume: &Volume,
        kept: Option<VoxelSet>,
        least_strength: f64,
        values: Vec<[f32; 9]>,
        eigenvalue_range: (f64, f64),
    ) -> CreaseField {
        let frames = values.par_iter().map(|v| unpack(v).frame).collect();
        let r = *volume.direction();
        CreaseField {
            dims: volume.dims(),
            kept,
            least_strength,
            values,
            frames,
            origin: Point::from(volume.origin()),
            grid_to_world: r * Matrix3::from_diagonal(&Vector::from(volume.spacing())),
            world_to_grid: *volume.world_to_grid(),
            eigenvalue_range,
            space: volume.space(),
        }
    }

    /// The anatomical frame of the world coordinates, the image's.
    pub fn space(&self) -> Option<Space> {
        self.space
    }

    /// The default options: ε a fraction [`DEFAULT_EPSILON_FRACTION`] of the range
    /// of the Hessian's eigenvalues over the grid (docs/design/crease.md), θ =
    /// [`DEFAULT_THETA`], and the strength a fraction [`DEFAULT_STRENGTH_FRACTION`]
    /// of the strongest −λ3 over the grid.
    #[cfg(test)]
    pub fn default_options(&self) -> CrossingOptions {
        default_options(self.eigenvalue_range)
    }

    /// The linear index of grid point `index`.
    #[inline]
    pub fn linear_index(&self, index: [usize; 3]) -> usize {
        self.grid().index(index)
    }

    /// The index arithmetic of the grid.
    #[inline]
    pub(crate) fn grid(&self) -> Grid {
        Grid { dims: self.dims }
    }

    /// The world position of grid point `index`.
    pub fn position(&self, index: [usize; 3]) -> Point {
        self.origin + self.grid_to_world * Vector::from(index.map(|v| v as f64))
    }

    /// The world position of the fractional grid coordinates `u`.
    pub(crate) fn position_at_grid(&self, u: &Vector) -> Point {
        self.origin + self.grid_to_world * u
    }

    /// The fractional grid coordinates of world `point`.
    pub(crate) fn to_grid(&self, point: &Point) -> Vector {
        self.world_to_grid * (point - self.origin)
    }

    /// Gradient and Hessian at world `point`, interpolated trilinearly between the
    /// grid points (the eigenframe computed there); `None` outside the grid.
    pub fn sample_at(&self, point: &Point) -> Option<Sample> {
        let u = self.world_to_grid * (point - self.origin);
        let (corners, weights) = corners_and_weights(self.dims, [u.x, u.y, u.z])?;
        let mut sum = [0.0f64; 9];
        for (&at, weight) in corners.iter().zip(weights) {
            for (s, x) in sum.iter_mut().zip(&self.values_at(at)) {
                *s += weight * f64::from(*x);
            }
        }
        Some(unpack_f64(sum))
    }

    /// The unit normal of the crease surface at `point`: the dominant right
    /// singular vector of J = ∂h/∂x (on the surface J = a nᵀ has rank one; an
    /// eigenvector of J would be e3), with J by central differences. The zero
    /// vector outside the grid.
    pub fn normal_at(&self, point: &Point, epsilon: f64) -> Vector {
        let step = 0.05 / self.world_to_grid.norm().max(f64::MIN_POSITIVE) * 3f64.sqrt();
        let h = |p: Point| self.sample_at(&p).map(|s| s.h(epsilon));
        let mut jacobian = Matrix3::zeros();
        for j in 0..3 {
            let offset = Vector::ith(j, step);
            match (h(point + offset), h(point - offset)) {
                (Some(a), Some(b)) => jacobian.set_column(j, &((a - b) / (2.0 * step))),
                _ => return Vector::zeros(),
            }
        }
        let gram = SymmetricEigen::new(jacobian.transpose() * jacobian);
        let largest = gram.eigenvalues.imax();
        gram.eigenvectors.column(largest).into_owned()
    }

    /// Gradient, Hessian and eigenframe at grid point `index` (flat where the field
    /// keeps none).
    pub fn sample(&self, index: [usize; 3]) -> Sample {
        let Some(n) = self.slot(self.linear_index(index)) else {
            return Sample {
                gradient: Vector::zeros(),
                hessian: Matrix3::zeros(),
                frame: FLAT,
            };
        };
        let v = self.values[n].map(f64::from);
        Sample {
            gradient: Vector::new(v[0], v[1], v[2]),
            hessian: hessian(&v),
            frame: self.frames[n],
        }
    }

    /// The place of grid point `n` (linear index) in `values`, `None` where the
    /// field keeps none.
    #[inline]
    fn slot(&self, n: usize) -> Option<usize> {
        match &self.kept {
            None => Some(n),
            Some(kept) => kept.number(n),
        }
    }

    /// The values at grid point `n` (zero where the field keeps none).
    fn values_at(&self, n: usize) -> [f32; 9] {
        self.slot(n).map_or([0.0; 9], |k| self.values[k])
    }

    /// The least crease strength −λ3 this field holds every crease of (0 for a
    /// field of every grid point): a surface asked for weaker creases would miss
    /// some.
    pub fn least_strength(&self) -> f64 {
        self.least_strength
    }

    /// The number of grid points the field keeps values at.
    pub fn kept_len(&self) -> usize {
        self.values.len()
    }
}

/// [`CreaseField::default_options`] for a field whose Hessian eigenvalues span
/// `(lowest, highest)` ([`Survey::eigenvalue_range`]).
pub fn default_options((lowest, highest): (f64, f64)) -> CrossingOptions {
    CrossingOptions {
        epsilon: DEFAULT_EPSILON_FRACTION * (highest - lowest),
        theta: DEFAULT_THETA,
        strength: DEFAULT_STRENGTH_FRACTION * (-lowest).max(0.0),
    }
}

/// The eigenframe of a zero Hessian, where a field keeps nothing.
const FLAT: Eigenframe = Eigenframe {
    eigenvalues: [0.0; 3],
    e3: Vector::new(0.0, 0.0, 1.0),
};

/// No eigenvalue yet: the neutral element of [`widest`].
const EMPTY_RANGE: (f64, f64) = (f64::INFINITY, f64::NEG_INFINITY);

/// The range holding both ranges.
fn widest(a: (f64, f64), b: (f64, f64)) -> (f64, f64) {
    (a.0.min(b.0), a.1.max(b.1))
}

/// The gradient and Hessian along the index axes, `partials` (fx fy fz fxx fxy fxz
/// fyy fyz fzz), times `sign` and turned into world coordinates by the direction
/// `r`: the record a field keeps per grid point.
fn packed(partials: [f32; 9], sign: f64, r: &Matrix3<f64>) -> [f32; 9] {
    let v = partials.map(|x| sign * f64::from(x));
    let g = r * Vector::new(v[0], v[1], v[2]);
    let h = r * Matrix3::new(v[3], v[4], v[5], v[4], v[6], v[7], v[5], v[7], v[8]) * r.transpose();
    [
        g.x,
        g.y,
        g.z,
        h[(0, 0)],
        h[(0, 1)],
        h[(0, 2)],
        h[(1, 1)],
        h[(1, 2)],
        h[(2, 2)],
    ]
    .map(|x| x as f32)
}

/// The first pass of a field kept only where creases are strong: the range of the
/// Hessian's eigenvalues over the grid and, per grid point, λ3 rounded down to
/// `f32` (so that `−λ3 ≥ s` holds at least where it holds exactly). The derivatives
/// are computed a few z slices at a time and not kept.
pub struct Survey {
    /// The smallest and largest Hessian eigenvalue over the grid, which the
    /// tests' default options are a fraction of.
    #[cfg_attr(not(test), allow(dead_code))]
    eigenvalue_range: (f64, f64),
    /// λ3 per grid point, rounded towards −∞.
    lowest: Vec<f32>,
    smoothing: Smoothing,
    ridges: bool,
}

impl Survey {
    /// Surveys `volume` made differentiable as `smoothing` says (the cubic spline or
    /// a Gaussian; first and second derivatives), for ridges of f (`ridges`) or of
    /// −f.
    ///
    /// Errors as [`Derivatives::new`] and [`Derivatives::cubic_spline`].
    pub fn new(volume: &Volume, smoothing: Smoothing, ridges: bool) -> Result<Survey> {
        let sign = if ridges { 1.0 } else { -1.0 };
        let r = *volume.direction();
        let every = VoxelSetBuilder::full(volume.len()).build();
        let mut lowest = vec![0.0f32; volume.len()];
        let mut range = EMPTY_RANGE;
        let partials = &Partial::ALL[FIRST_AND_SECOND];
        Derivatives::for_blocks(volume, smoothing, partials, &every, |d, members| {
            let eigenvalues: Vec<[f64; 3]> = members
                .par_iter()
                .map(|&at| {
                    let record = packed(partials_at(d, volume, at), sign, &r);
                    unpack(&record).frame.eigenvalues
                })
                .collect();
            for (&at, e) in members.iter().zip(&eigenvalues) {
                lowest[at] = rounded_down(e[2]);
                range = widest(range, (e[2], e[0]));
            }
            Ok(())
        })?;
        Ok(Survey {
            eigenvalue_range: range,
            lowest,
            smoothing,
            ridges,
        })
    }

    /// The smallest and largest Hessian eigenvalue over the grid, as
    /// [`CreaseField::default_options`] reads them.
    pub fn eigenvalue_range(&self) -> (f64, f64) {
        self.eigenvalue_range
    }

    /// The field of `volume` (the surveyed one) kept at the grid points within two
    /// (along each axis) of a point where −λ3 may reach `strength`: every crease of
    /// at least that strength, its cells and their neighbours.
    ///
    /// Errors as [`Survey::new`].
    pub fn field(self, volume: &Volume, strength: f64) -> Result<CreaseField> {
        let grid = volume.grid();
        let mut kept = VoxelSetBuilder::new(volume.len());
        for (n, &l) in self.lowest.iter().enumerate() {
            if -f64::from(l) >= strength {
                around(grid, grid.position_of(n), 2, |at| kept.insert(at));
            }
        }
        drop(self.lowest);
        let kept = kept.build();
        let sign = if self.ridges { 1.0 } else { -1.0 };
        let r = *volume.direction();
        let mut values = Vec::with_capacity(kept.len());
        let partials = &Partial::ALL[FIRST_AND_SECOND];
        Derivatives::for_blocks(volume, self.smoothing, partials, &kept, |d, members| {
            let record = |&at: &usize| packed(partials_at(d, volume, at), sign, &r);
            values.par_extend(members.par_iter().map(record));
            Ok(())
        })?;
        Ok(CreaseField::of_records(
            volume,
            Some(kept),
            strength,
            values,
            self.eigenvalue_range,
        ))
    }
}

/// The first and second partials' places in [`Partial::ALL`].
const FIRST_AND_SECOND: std::ops::Range<usize> = 1..10;

/// The nine first and second partials of `d` at the sample of linear index `at`.
fn partials_at(d: &Derivatives, volume: &Volume, at: usize) -> [f32; 9] {
    let index = volume.grid().position_of(at);
    d.components::<9>(FIRST_AND_SECOND.start, index)
        .map_or([f32::NAN; 9], |v| v.map(|x| x as f32))
}

/// `x` as the largest `f32` not above it.
fn rounded_down(x: f64) -> f32 {
    let y = x as f32;
    if f64::from(y) > x {
        y.next_down()
    } else {
        y
    }
}

/// `visit` of the linear index of every sample within `reach` of `index` along
/// each axis, inside the grid.
fn around(grid: Grid, index: [usize; 3], reach: usize, mut visit: impl FnMut(usize)) {
    let range = |a: usize| index[a].saturating_sub(reach)..(index[a] + reach + 1).min(grid.dims[a]);
    for k in range(2) {
        for j in range(1) {
            for i in range(0) {
                visit(grid.index([i, j, k]));
            }
        }
    }
}

fn unpack(v: &[f32; 9]) -> Sample {
    unpack_f64(v.map(f64::from))
}

fn unpack_f64(v: [f64; 9]) -> Sample {
    Sample::new(Vector::new(v[0], v[1], v[2]), hessian(&v))
}

/// The symmetric Hessian of a packed gradient-and-Hessian record.
fn hessian(v: &[f64; 9]) -> Matrix3<f64> {
    Matrix3::new(v[3], v[4], v[5], v[4], v[6], v[7], v[5], v[7], v[8])
}

//! Gradients and Hessians of an image at its grid points, in world coordinates,
//! linearly interpolated in between, with the Hessian's eigenframe at every point
//! (Schultz, Theisel and Seidel 2010, §4.6: store derivatives, never interpolate T).

use nalgebra::{Matrix3, SymmetricEigen};
use rayon::prelude::*;

use super::edges::CrossingOptions;
use super::tensor::Eigenframe;
use super::{DEFAULT_EPSILON_FRACTION, DEFAULT_STRENGTH_FRACTION, DEFAULT_THETA};
use crate::volume::grid::Grid;
use crate::volume::trilinear::corners_and_weights;
use crate::volume::{Derivatives, Partial, Volume};
use crate::{Error, Point, Result, Space, Vector};

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
pub struct CreaseField {
    dims: [usize; 3],
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
    /// The smallest and largest Hessian eigenvalue over the grid.
    eigenvalue_range: (f64, f64),
    /// The anatomical frame of the world coordinates ([`Volume::space`]).
    space: Option<Space>,
}

impl CreaseField {
    /// The field of `derivatives` (orders 1 and 2 computed) of `volume`, negated for
    /// valleys (`ridges = false`: valleys of f are ridges of −f).
    ///
    /// Errors ([`Error::Argument`]) if a first or second partial is missing.
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
            .map(|n| {
                let v: [f64; 9] = std::array::from_fn(|c| sign * f64::from(grids[c][n]));
                let g = r * Vector::new(v[0], v[1], v[2]);
                let h = r
                    * Matrix3::new(v[3], v[4], v[5], v[4], v[6], v[7], v[5], v[7], v[8])
                    * r.transpose();
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
            })
            .collect();
        let frames: Vec<Eigenframe> = values.par_iter().map(|v| unpack(v).frame).collect();
        let eigenvalue_range = frames
            .par_iter()
            .map(|f| (f.eigenvalues[2], f.eigenvalues[0]))
            .reduce(
                || (f64::INFINITY, f64::NEG_INFINITY),
                |a, b| (a.0.min(b.0), a.1.max(b.1)),
            );
        Ok(CreaseField {
            dims: volume.dims(),
            values,
            frames,
            origin: Point::from(volume.origin()),
            grid_to_world: r * Matrix3::from_diagonal(&Vector::from(volume.spacing())),
            world_to_grid: *volume.world_to_grid(),
            eigenvalue_range,
            space: volume.space(),
        })
    }

    /// The anatomical frame of the world coordinates, the image's.
    pub fn space(&self) -> Option<Space> {
        self.space
    }

    /// The number of grid points along x, y and z.
    pub fn dims(&self) -> [usize; 3] {
        self.dims
    }

    /// The default options: ε a fraction [`DEFAULT_EPSILON_FRACTION`] of the range
    /// of the Hessian's eigenvalues over the grid (docs/design.md), θ =
    /// [`DEFAULT_THETA`], and the strength a fraction [`DEFAULT_STRENGTH_FRACTION`]
    /// of the strongest −λ3 over the grid.
    pub fn default_options(&self) -> CrossingOptions {
        let (lowest, highest) = self.eigenvalue_range;
        CrossingOptions {
            epsilon: DEFAULT_EPSILON_FRACTION * (highest - lowest),
            theta: DEFAULT_THETA,
            strength: DEFAULT_STRENGTH_FRACTION * (-lowest).max(0.0),
        }
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
            for (s, x) in sum.iter_mut().zip(&self.values[at]) {
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

    /// Gradient, Hessian and eigenframe at grid point `index`.
    pub fn sample(&self, index: [usize; 3]) -> Sample {
        let n = self.linear_index(index);
        let v = self.values[n].map(f64::from);
        Sample {
            gradient: Vector::new(v[0], v[1], v[2]),
            hessian: hessian(&v),
            frame: self.frames[n],
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

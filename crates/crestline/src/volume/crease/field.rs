//! Gradients and Hessians of an image at its grid points, in world coordinates,
//! linearly interpolated in between, with the Hessian's eigenframe at every point
//! (Schultz, Theisel and Seidel 2010, §4.6: store derivatives, never interpolate T).

use nalgebra::Matrix3;
use rayon::prelude::*;

use super::edges::CrossingOptions;
use super::tensor::Eigenframe;
use super::{DEFAULT_EPSILON_FRACTION, DEFAULT_STRENGTH_FRACTION, DEFAULT_THETA};
use crate::volume::{Derivatives, Partial, Volume};
use crate::{Error, Point, Result, Vector};

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
    origin: Point,
    /// direction · diag(spacing): world offset per index step.
    grid_to_world: Matrix3<f64>,
    /// The smallest and largest Hessian eigenvalue over the grid.
    eigenvalue_range: (f64, f64),
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
        let eigenvalue_range = values
            .par_iter()
            .map(|v| {
                let s = unpack(v);
                (s.frame.eigenvalues[2], s.frame.eigenvalues[0])
            })
            .reduce(
                || (f64::INFINITY, f64::NEG_INFINITY),
                |a, b| (a.0.min(b.0), a.1.max(b.1)),
            );
        Ok(CreaseField {
            dims: volume.dims(),
            values,
            origin: Point::from(volume.origin()),
            grid_to_world: r * Matrix3::from_diagonal(&Vector::from(volume.spacing())),
            eigenvalue_range,
        })
    }

    /// The number of grid points along x, y and z.
    pub fn dims(&self) -> [usize; 3] {
        self.dims
    }

    /// The default options: ε a fraction [`DEFAULT_EPSILON_FRACTION`] of the range
    /// of the Hessian's eigenvalues over the grid (DESIGN.md), θ =
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
    pub fn linear_index(&self, [i, j, k]: [usize; 3]) -> usize {
        i + self.dims[0] * (j + self.dims[1] * k)
    }

    /// The world position of grid point `index`.
    pub fn position(&self, index: [usize; 3]) -> Point {
        self.origin + self.grid_to_world * Vector::from(index.map(|v| v as f64))
    }

    /// Gradient, Hessian and eigenframe at grid point `index`.
    pub fn sample(&self, index: [usize; 3]) -> Sample {
        unpack(&self.values[self.linear_index(index)])
    }
}

fn unpack(v: &[f32; 9]) -> Sample {
    let v = v.map(f64::from);
    Sample::new(
        Vector::new(v[0], v[1], v[2]),
        Matrix3::new(v[3], v[4], v[5], v[4], v[6], v[7], v[5], v[7], v[8]),
    )
}

//! Crest lines of the isosurfaces of a 3D image, by the Marching Lines algorithm
//! (Thirion & Gourdon 1993, "The 3D marching lines algorithm", §5): the lines where
//! the isosurface `f = I` of the smoothed image meets the zero set of an
//! extremality, with the conventions of DESIGN.md ("Isosurfaces and implicit
//! curvature").
//!
//! - The image is smoothed by a Gaussian of standard deviation σ (world units) and
//!   differentiated up to order 3 ([`Derivatives`]); at every grid point the
//!   isosurface through it has principal curvatures `k_max ≥ k_min` (positive on a
//!   bright convex object), directions `t_max`, `t_min` and extremalities
//!   `e_max = ∇k_max · t_max`, `e_min = ∇k_min · t_min`
//!   ([`crate::differential::isosurface_curvature`]).
//! - Ridges are maxima of `k_max` along `t_max` where `k_max > |k_min|`, so that
//!   Thirion's crest lines of the curvature larger in magnitude map to our ridges;
//!   valleys are minima of `k_min` along `t_min` where `|k_min| > |k_max|`.
//! - The sign of a principal direction, and so of its extremality, is only locally
//!   meaningful: in each cell the eight corner directions are oriented to corner 0,
//!   and the cell is used only if all 28 pairwise dot products are then positive
//!   (the two cells of a face decide the same); other cells, and cells with a
//!   corner where the curvature is undefined (vanishing gradient), have no segment.
//!   A segment is kept where the trilinear gradient of the oriented extremality
//!   points against the trilinear (oriented) direction at its midpoint
//!   (`∇e_max · t_max < 0` for a maximum, `> 0` for a minimum) and the curvature
//!   condition holds there.
//! - The lines are chained by point key without regard to direction
//!   ([`crate::volume::marching_lines()`]) and are unoriented. Their strength is the
//!   integral of the curvature magnitude along them (dimensionless).
//! - Parabolic lines ([`parabolic_lines`]) are the bi-iso-lines of the Gaussian
//!   curvature `K = k_max k_min` at 0, a field with a global sign.

use rayon::prelude::*;

use crate::differential::IsoCurvature;
use crate::lines::{LineKind, Polyline};
use crate::volume::marching_lines::{
    bi_iso_lines, cell_corners, marching_lines, BiIsoLine, SecondField,
};
use crate::volume::trilinear::{weight_derivatives, weights};
use crate::volume::{Derivatives, Partial, Volume};
use crate::{Point, Result, Vector};

/// Curvature of the isosurface through one grid point, stored compactly.
#[derive(Clone, Copy, Debug)]
struct Frame {
    /// `k_max`, `k_min`.
    k: [f32; 2],
    /// `e_max`, `e_min`.
    e: [f32; 2],
    /// `t_max`, `t_min`.
    t: [[f32; 3]; 2],
}

impl Frame {
    fn new(c: &IsoCurvature) -> Frame {
        let p = &c.principal;
        let direction = |d: &Vector| [d.x as f32, d.y as f32, d.z as f32];
        Frame {
            k: [p.k_max as f32, p.k_min as f32],
            e: [c.e_max as f32, c.e_min as f32],
            t: [direction(&p.d_max), direction(&p.d_min)],
        }
    }

    /// The curvature magnitude that measures a line of kind `kind`: `|k_max|` for a
    /// ridge, `|k_min|` for a valley, the larger of the two otherwise.
    fn magnitude(&self, kind: LineKind) -> f64 {
        let [k_max, k_min] = self.k.map(|k| f64::from(k).abs());
        match kind {
            LineKind::Ridge => k_max,
            LineKind::Valley => k_min,
            _ => k_max.max(k_min),
        }
    }

    /// Direction `which` (0: `t_max`, 1: `t_min`).
    fn direction(&self, which: usize) -> Vector {
        Vector::from(self.t[which].map(f64::from))
    }
}

/// The curvature at every grid point of a volume, `None` where undefined.
struct Curvatures {
    dims: [usize; 3],
    frames: Vec<Option<Frame>>,
    /// `∂index/∂world`, turning gradients along index axes into world gradients.
    world_to_grid: nalgebra::Matrix3<f64>,
}

impl Curvatures {
    fn new(derivatives: &Derivatives, volume: &Volume) -> Curvatures {
        let [nx, ny, nz] = volume.dims();
        let frames = (0..nx * ny * nz)
            .into_par_iter()
            .map(|at| {
                let index = [at % nx, (at / nx) % ny, at / (nx * ny)];
                let curvature = derivatives.jet(index)?.isosurface_curvature()?;
                let frame = Frame::new(&curvature);
                let finite = frame.k.iter().chain(&frame.e).all(|v| v.is_finite());
                finite.then_some(frame)
            })
            .collect();
        Curvatures {
            dims: volume.dims(),
            frames,
            world_to_grid: *volume.world_to_grid(),
        }
    }

    /// The frames at the 8 corners of `cell`, or `None` if one is undefined.
    fn corners(&self, cell: [usize; 3]) -> Option<[Frame; 8]> {
        let frames = cell_corners(self.dims, cell).map(|at| self.frames[at]);
        frames
            .iter()
            .all(Option::is_some)
            .then(|| frames.map(Option::unwrap))
    }
}

/// The extremality of one kind of crest line as the second field of the Marching
/// Lines, oriented per cell: `e_max` for ridges (maxima of `k_max` along `t_max`),
/// `e_min` for valleys (minima of `k_min` along `t_min`).
struct Extremality<'a> {
    curvatures: &'a Curvatures,
    /// [`LineKind::Ridge`] or [`LineKind::Valley`].
    kind: LineKind,
}

impl Extremality<'_> {
    /// 0 for `k_max`, `t_max`, `e_max`; 1 for `k_min`, `t_min`, `e_min`.
    fn which(&self) -> usize {
        usize::from(self.kind == LineKind::Valley)
    }

    /// The corner frames of `cell` and the signs that orient their directions to
    /// corner 0, if all 28 pairs of oriented directions then agree.
    fn oriented(&self, cell: [usize; 3]) -> Option<([Frame; 8], [f64; 8])> {
        let frames = self.curvatures.corners(cell)?;
        let directions = frames.map(|f| f.direction(self.which()));
        let signs = directions.map(|d| d.dot(&directions[0]).signum());
        let oriented: [Vector; 8] = std::array::from_fn(|c| directions[c] * signs[c]);
        let agree = (0..8).all(|a| (a + 1..8).all(|b| oriented[a].dot(&oriented[b]) > 0.0));
        agree.then_some((frames, signs))
    }
}

/// A fixed direction with no zero component, to break ties (see [`untied`]).
const TIE_BREAK: Vector = Vector::new(0.36, 0.48, 0.8);

/// The extremality `e` along principal direction `direction`, moved off an exact
/// zero (which symmetric images produce on whole grid planes) by the smallest
/// amount, with the sign of `direction · TIE_BREAK`: like a nonzero `e`, the result
/// changes sign with the direction, so once oriented per cell the labels of the two
/// cells of a face stay opposite (an exact zero would be `+` in both).
fn untied(e: f64, direction: &Vector) -> f64 {
    if e == 0.0 {
        f64::MIN_POSITIVE.copysign(direction.dot(&TIE_BREAK))
    } else {
        e
    }
}

impl SecondField for Extremality<'_> {
    fn corners(&self, cell: [usize; 3]) -> Option<[f64; 8]> {
        let (frames, signs) = self.oriented(cell)?;
        Some(std::array::from_fn(|c| {
            let direction = frames[c].direction(self.which());
            untied(f64::from(frames[c].e[self.which()]), &direction) * signs[c]
        }))
    }

    fn keep(&self, cell: [usize; 3], corners: &[f64; 8], local: [f64; 3]) -> bool {
        let Some((frames, signs)) = self.oriented(cell) else {
            return false;
        };
        let (weights, slopes) = (weights(local), weight_derivatives(local));
        let along_index = Vector::from(slopes.map(|s| (0..8).map(|c| s[c] * corners[c]).sum()));
        let gradient = self.curvatures.world_to_grid.transpose() * along_index;
        let direction: Vector = (0..8)
            .map(|c| frames[c].direction(self.which()) * (signs[c] * weights[c]))
            .sum();
        let k = |n: usize| {
            (0..8)
                .map(|c| f64::from(frames[c].k[n]) * weights[c])
                .sum::<f64>()
        };
        let (k_max, k_min) = (k(0), k(1));
        let slope = gradient.dot(&direction);
        if self.kind == LineKind::Ridge {
            slope < 0.0 && k_max > k_min.abs()
        } else {
            slope > 0.0 && -k_min > k_max.abs()
        }
    }
}

/// The image smoothed by a Gaussian of standard deviation `sigma` (world units),
/// and the curvature of its isosurfaces at every grid point.
fn smoothed_curvatures(volume: &Volume, sigma: f64) -> Result<(Volume, Curvatures)> {
    let derivatives = Derivatives::new(volume, sigma, 3)?;
    let smoothed = derivatives
        .grid(Partial::new([0, 0, 0])?)
        .expect("order 0 is computed");
    let smoothed = volume.with_samples(smoothed.to_vec())?;
    Ok((smoothed, Curvatures::new(&derivatives, volume)))
}

/// The crest lines (ridges, then valleys) of the isosurface `f = level` of
/// `volume` smoothed by a Gaussian of standard deviation `sigma` in world units
/// (Thirion & Gourdon 1993 §5; see the [module documentation](self)), as
/// unoriented polylines of kind [`LineKind::Ridge`] and [`LineKind::Valley`] in
/// world coordinates, with the integral of `|k_max|` (ridges) or `|k_min|`
/// (valleys) along them as strength.
///
/// Errors as [`Derivatives::new`] (σ, direction matrix) and
/// [`marching_lines`](crate::volume::marching_lines()) (level, samples, dimensions).
pub fn crest_lines(volume: &Volume, level: f64, sigma: f64) -> Result<Vec<Polyline>> {
    let (smoothed, curvatures) = smoothed_curvatures(volume, sigma)?;
    let mut polylines = Vec::new();
    for kind in [LineKind::Ridge, LineKind::Valley] {
        let field = Extremality {
            curvatures: &curvatures,
            kind,
        };
        let lines = marching_lines(&smoothed, level, &field, 0.0)?;
        let polyline = |line| polyline(line, kind, &curvatures, volume);
        polylines.extend(lines.iter().map(polyline));
    }
    Ok(polylines)
}

/// The parabolic lines of the isosurface `f = level` of `volume` smoothed by a
/// Gaussian of standard deviation `sigma` in world units: the bi-iso-lines of the
/// Gaussian curvature `K = k_max k_min` at `K = 0` (Thirion & Gourdon 1993 §5),
/// oriented by the bi-iso-line convention (`K ≥ 0` on the left seen from
/// `f < level`), of kind [`LineKind::Parabolic`], with the integral of the larger
/// curvature magnitude along them as strength. `K` is undefined (and the lines
/// end) where the gradient vanishes.
///
/// Errors as [`crest_lines`].
pub fn parabolic_lines(volume: &Volume, level: f64, sigma: f64) -> Result<Vec<Polyline>> {
    iso_gaussian_lines(volume, level, sigma, 0.0)
}

/// The iso-Gaussian curves `K = gauss` of the isosurface `f = level` (Thirion &
/// Gourdon 1993 §5), as [`parabolic_lines`] (which are the case `gauss = 0`) but of
/// kind [`LineKind::Contour`] for `gauss ≠ 0`. `gauss` has the units of a
/// curvature squared (world units⁻²).
///
/// Errors as [`crest_lines`], and for a non-finite `gauss`.
pub fn iso_gaussian_lines(
    volume: &Volume,
    level: f64,
    sigma: f64,
    gauss: f64,
) -> Result<Vec<Polyline>> {
    let (smoothed, curvatures) = smoothed_curvatures(volume, sigma)?;
    let values: Vec<f32> = curvatures
        .frames
        .iter()
        .map(|frame| frame.map_or(f32::NAN, |f| f.k[0] * f.k[1]))
        .collect();
    let lines = bi_iso_lines(&smoothed, level, &values, gauss)?;
    let kind = if gauss == 0.0 {
        LineKind::Parabolic
    } else {
        LineKind::Contour
    };
    let polyline = |line| polyline(line, kind, &curvatures, volume);
    Ok(lines.iter().map(polyline).collect())
}

/// A line as a [`Polyline`] of kind `kind`, its strength the integral along it of
/// the curvature magnitude [`Frame::magnitude`] (trapezoid rule, interpolated
/// trilinearly).
fn polyline(
    line: &BiIsoLine,
    kind: LineKind,
    curvatures: &Curvatures,
    volume: &Volume,
) -> Polyline {
    let k: Vec<f64> = line
        .points
        .iter()
        .map(|p| interpolated(curvatures, volume, p, |f| f.magnitude(kind)))
        .collect();
    let n = line.points.len();
    let pieces = if line.closed { n } else { n.saturating_sub(1) };
    let strength = (0..pieces)
        .map(|i| {
            let j = (i + 1) % n;
            0.5 * (k[i] + k[j]) * (line.points[j] - line.points[i]).norm()
        })
        .sum();
    Polyline::new(kind, line.closed, strength, line.points.clone())
}

/// `value` of the frames at world point `p`, interpolated trilinearly in its cell
/// (0 if a corner is undefined).
fn interpolated(
    curvatures: &Curvatures,
    volume: &Volume,
    p: &Point,
    value: impl Fn(&Frame) -> f64,
) -> f64 {
    let index = volume.world_to_index(p);
    let dims = curvatures.dims;
    let cell: [usize; 3] =
        std::array::from_fn(|a| (index[a].floor().max(0.0) as usize).min(dims[a] - 2));
    let local = std::array::from_fn(|a| index[a] - cell[a] as f64);
    let weights = weights(local);
    curvatures.corners(cell).map_or(0.0, |frames| {
        (0..8).map(|c| value(&frames[c]) * weights[c]).sum()
    })
}

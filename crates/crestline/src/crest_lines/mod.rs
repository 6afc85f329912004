//! Crest lines of the isosurfaces of a 3D image, by the Marching Lines algorithm
//! (Thirion & Gourdon 1993, "The 3D marching lines algorithm", §5): the lines where
//! the isosurface `f = I` of the smoothed image meets the zero set of an
//! extremality, with the conventions of docs/design/images.md ("Isosurfaces and implicit
//! curvature").
//!
//! - The image is smoothed by a Gaussian of standard deviation σ (world units) and
//!   differentiated up to order 3 ([`Derivatives`]); at every grid point the
//!   isosurface through it has principal curvatures `k_max ≥ k_min` (positive on a
//!   bright convex object), directions `t_max`, `t_min` and extremalities
//!   `e_max = ∇k_max · t_max`, `e_min = ∇k_min · t_min`
//!   (`crate::differential::isosurface_curvature`).
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
//!   (`marching_lines::marching_lines`) and are unoriented: each runs in the
//!   direction of its grid keys (`BiIsoLine::in_key_order`). The curvature is
//!   computed in the frame of the grid's axes and ties of an extremality at exactly
//!   0 are broken there, so that the lines do not depend on the world frame the
//!   image declares (module `frames`). Their strength is the
//!   integral of the curvature magnitude along them (dimensionless).
//! - Parabolic lines (`parabolic_lines`) are the bi-iso-lines of the Gaussian
//!   curvature `K = k_max k_min` at 0, a field with a global sign; iso-Gaussian
//!   curves (`iso_gaussian_lines`) those at another value.
//! - The smoothed image is kept whole (one value per sample), but the derivatives
//!   of order 1 to 3 and the curvature only at the corners of the cells the
//!   isosurface meets (the others cannot carry a line), computed over blocks of z
//!   slices (module `frames`): memory grows with the isosurface, not with the image.

mod frames;
mod marching_lines;

pub use marching_lines::Sweep;

use crate::lines::oriented::{along_line, DirectedSample};
use crate::lines::{FeatureLines, LineExtractor, LineKind, Polyline};
#[cfg(test)]
use crate::progress::Silent;
use crate::progress::{try_stage, Observer};
use crate::volume::trilinear::{weight_derivatives, weights};
use crate::volume::{Derivatives, Volume};
use crate::{Error, Point, Result, Vector};
use frames::{Curvatures, Frame};
use marching_lines::{BiIsoLine, SecondField};

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

/// A fixed direction in the frame of the grid's axes with no zero component, to
/// break ties (see [`untied`]).
const TIE_BREAK: Vector = Vector::new(0.36, 0.48, 0.8);

/// The extremality `e` along principal direction `direction`, moved off an exact
/// zero (which symmetric images produce on whole grid planes) by the smallest
/// amount, with the sign of `grid_direction · TIE_BREAK`: like a nonzero `e`, the
/// result changes sign with the direction, so once oriented per cell the labels of
/// the two cells of a face stay opposite (an exact zero would be `+` in both).
///
/// `direction` is in the frame of the grid's axes (as every frame here), so that
/// the tie falls the same way whatever world frame the image declares.
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
        let gradient = self.curvatures.axis_to_grid.transpose() * along_index;
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

/// The Gaussian curvature `K = k_max k_min` of the isosurfaces, as the second field
/// of the Marching Lines.
struct GaussianCurvature<'a> {
    curvatures: &'a Curvatures,
}

impl SecondField for GaussianCurvature<'_> {
    fn corners(&self, cell: [usize; 3]) -> Option<[f64; 8]> {
        let frames = self.curvatures.corners(cell)?;
        Some(frames.map(|f| f64::from(f.k[0]) * f64::from(f.k[1])))
    }
}

/// Which lines of an isosurface to trace.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum LineFamily {
    /// Crest lines: ridges (maxima of `k_max` along `t_max` where `k_max > |k_min|`:
    /// convex crests, gyri) and valleys (the mirror case: concave crests, sulci).
    #[default]
    Crest,
    /// Parabolic lines, where the Gaussian curvature is zero.
    Parabolic,
    /// Iso-Gaussian curves, where the Gaussian curvature is this value (world
    /// units⁻²).
    Gauss(f64),
}

impl LineFamily {
    /// The names of the families, as [`std::str::FromStr`] reads them (`gauss=J`
    /// with `J` a number).
    pub const NAMES: &'static [&'static str] = &["crest", "parabolic", "gauss=J"];
}

impl std::fmt::Display for LineFamily {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            LineFamily::Crest => f.write_str("crest"),
            LineFamily::Parabolic => f.write_str("parabolic"),
            LineFamily::Gauss(j) => write!(f, "gauss={j}"),
        }
    }
}

impl std::str::FromStr for LineFamily {
    type Err = Error;

    /// `crest`, `parabolic` or `gauss=J` (`J` a finite number, in world units⁻²).
    fn from_str(text: &str) -> Result<LineFamily> {
        match text {
            "crest" => Ok(LineFamily::Crest),
            "parabolic" => Ok(LineFamily::Parabolic),
            _ => text
                .strip_prefix("gauss=")
                .and_then(|j| j.parse::<f64>().ok())
                .filter(|j| j.is_finite())
                .map(LineFamily::Gauss)
                .ok_or_else(|| {
                    Error::Argument(format!(
                        "'{text}' is not a line family: crest, parabolic or gauss=J (J a number)"
                    ))
                }),
        }
    }
}

impl serde::Serialize for LineFamily {
    fn serialize<S: serde::Serializer>(
        &self,
        serializer: S,
    ) -> std::result::Result<S::Ok, S::Error> {
        serializer.collect_str(self)
    }
}

impl<'de> serde::Deserialize<'de> for LineFamily {
    fn deserialize<D: serde::Deserializer<'de>>(
        deserializer: D,
    ) -> std::result::Result<Self, D::Error> {
        let text = <std::borrow::Cow<'de, str>>::deserialize(deserializer)?;
        text.parse().map_err(serde::de::Error::custom)
    }
}

/// What `trace` traces, and how.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LineTracing {
    /// The isosurface level `I`; inside is `f ≥ I`.
    pub level: f64,
    /// The standard deviation of the Gaussian smoothing, in world units.
    pub sigma: f64,
    /// Which lines.
    pub family: LineFamily,
    /// Every cell, or the randomized variant from seed cells.
    pub sweep: Sweep,
}

impl LineTracing {
    /// The crest lines of the isosurface `level` of the image smoothed by `sigma`,
    /// visiting every cell.
    pub fn new(level: f64, sigma: f64) -> LineTracing {
        LineTracing {
            level,
            sigma,
            family: LineFamily::Crest,
            sweep: Sweep::Every,
        }
    }
}

/// The lines of `tracing.family` on the isosurface `f = level` of `volume`
/// smoothed by a Gaussian of standard deviation `sigma` (Thirion & Gourdon 1993 §5;
/// see the [module documentation](self)), as polylines in world coordinates with
/// the curvatures `k_max` and `k_min` at each point (named values).
///
/// - [`LineFamily::Crest`]: unoriented lines of kind [`LineKind::Ridge`] and
///   [`LineKind::Valley`], with the integral of `|k_max|` (ridges) or `|k_min|`
///   (valleys) along them as strength.
/// - [`LineFamily::Parabolic`] and [`LineFamily::Gauss`]: the bi-iso-lines of the
///   Gaussian curvature `K = k_max k_min` at 0 or `J`, of kind
///   [`LineKind::Parabolic`] (`J = 0`) or [`LineKind::Gauss`], oriented by the
///   bi-iso-line convention (`K ≥ J` on the left seen from `f < level`), with the
///   integral of the larger curvature magnitude as strength. `K` is undefined (and
///   the lines end) where the gradient vanishes.
///
/// With [`Sweep::Seeds`] only the lines through the seed cells are traced, longest
/// first (ridges and valleys each from the same number of seeds).
///
/// Errors as [`Derivatives::new`] (σ, direction matrix) and
/// [`marching_lines`](marching_lines::marching_lines()) (level, samples, dimensions),
/// and for a non-finite `J`.
#[cfg(test)]
pub(crate) fn trace(volume: &Volume, tracing: &LineTracing) -> Result<Vec<Polyline>> {
    trace_observed(volume, tracing, &mut Silent)
}

/// [`trace`], telling `observer` of the stages `derivatives` (the smoothed image's
/// derivatives to order 3) and `ridges` and `valleys` (crest lines) or `lines`
/// (the other families), and asking it between them whether to go on
/// ([`Error::Cancelled`] if not).
pub(crate) fn trace_observed(
    volume: &Volume,
    tracing: &LineTracing,
    observer: &mut dyn Observer,
) -> Result<Vec<Polyline>> {
    if let LineFamily::Gauss(j) = tracing.family {
        if !j.is_finite() {
            return Err(Error::Argument(format!(
                "the Gaussian curvature {j} of the iso-Gaussian curves is not finite"
            )));
        }
    }
    let (curvatures, smoothed) = try_stage(observer, "derivatives", || {
        let smoothed = Derivatives::smoothed(volume, tracing.sigma)?;
        let curvatures =
            Curvatures::at_isosurface(volume, &smoothed, tracing.sigma, tracing.level)?;
        Ok((curvatures, smoothed))
    })?;
    let (level, sweep) = (tracing.level, tracing.sweep);
    let polylines = |lines: Vec<BiIsoLine>, kind| -> Vec<Polyline> {
        let polyline = |line| polyline(line, kind, &curvatures, volume);
        lines.iter().map(polyline).collect()
    };
    let gauss = match tracing.family {
        LineFamily::Crest => {
            let mut crests = Vec::new();
            for (kind, stage) in [(LineKind::Ridge, "ridges"), (LineKind::Valley, "valleys")] {
                let field = Extremality {
                    curvatures: &curvatures,
                    kind,
                };
                let lines = try_stage(observer, stage, || {
                    sweep.lines(&smoothed, level, &field, 0.0)
                })?;
                let lines = lines.into_iter().map(BiIsoLine::in_key_order).collect();
                crests.extend(polylines(lines, kind));
            }
            return Ok(crests);
        }
        LineFamily::Parabolic => 0.0,
        LineFamily::Gauss(j) => j,
    };
    let kind = if gauss == 0.0 {
        LineKind::Parabolic
    } else {
        LineKind::Gauss
    };
    let field = GaussianCurvature {
        curvatures: &curvatures,
    };
    let lines = try_stage(observer, "lines", || {
        sweep.lines(&smoothed, level, &field, gauss)
    })?;
    Ok(polylines(lines, kind))
}

/// Marching Lines as a line extractor of volumes: `trace_observed`, the lines
/// collected in a [`FeatureLines`].
impl LineExtractor<Volume> for LineTracing {
    fn extract(&self, volume: &Volume, observer: &mut dyn Observer) -> Result<FeatureLines> {
        let mut lines = FeatureLines::new(String::new());
        lines.space = volume.space();
        lines.lines = trace_observed(volume, self, observer)?;
        Ok(lines)
    }
}

/// The crest lines (ridges, then valleys) of the isosurface `f = level` of
/// `volume` smoothed by a Gaussian of standard deviation `sigma` in world units,
/// every cell visited: [`trace`] with [`LineTracing::new`].
#[cfg(test)]
pub(crate) fn crest_lines(volume: &Volume, level: f64, sigma: f64) -> Result<Vec<Polyline>> {
    trace(volume, &LineTracing::new(level, sigma))
}

/// The parabolic lines (`K = 0`) of the isosurface `f = level` of `volume`
/// smoothed by `sigma`: [`trace`] with [`LineFamily::Parabolic`].
#[cfg(test)]
pub(crate) fn parabolic_lines(volume: &Volume, level: f64, sigma: f64) -> Result<Vec<Polyline>> {
    iso_gaussian_lines(volume, level, sigma, 0.0)
}

/// The iso-Gaussian curves `K = gauss` of the isosurface `f = level` of `volume`
/// smoothed by `sigma`: [`trace`] with [`LineFamily::Gauss`] (of kind
/// [`LineKind::Parabolic`] for `gauss = 0`). `gauss` has the units of a curvature
/// squared (world units⁻²).
#[cfg(test)]
pub(crate) fn iso_gaussian_lines(
    volume: &Volume,
    level: f64,
    sigma: f64,
    gauss: f64,
) -> Result<Vec<Polyline>> {
    let tracing = LineTracing {
        family: LineFamily::Gauss(gauss),
        ..LineTracing::new(level, sigma)
    };
    trace(volume, &tracing)
}

/// A line as a [`Polyline`] of kind `kind`, with at each point `k_max` and `k_min`
/// (interpolated trilinearly; 0 next to a corner where they are undefined) and
/// `e_max`, `e_min` read along the line with the principal directions' signs
/// carried from point to point ([`along_line`]: only their signs along the line
/// mean something; the zero crossings of the other extremality on a crest line
/// are Thirion's extremal points). Its strength is the integral along it
/// (trapezoid rule) of the curvature magnitude that measures the kind: `|k_max|`
/// for a ridge, `|k_min|` for a valley, the larger of the two otherwise.
fn polyline(
    line: &BiIsoLine,
    kind: LineKind,
    curvatures: &Curvatures,
    volume: &Volume,
) -> Polyline {
    let corners: Vec<Option<([Frame; 8], [f64; 8])>> = line
        .points
        .iter()
        .map(|p| corner_frames(curvatures, volume, p))
        .collect();
    let k: Vec<[f64; 2]> = corners
        .iter()
        .map(|corners| {
            corners.map_or([0.0; 2], |(frames, weights)| {
                [0, 1].map(|n| (0..8).map(|c| f64::from(frames[c].k[n]) * weights[c]).sum())
            })
        })
        .collect();
    let extremality = |n: usize| {
        along_line(corners.iter().map(|corners| {
            corners.map_or(Vec::new(), |(frames, weights)| {
                (0..8)
                    .map(|c| DirectedSample {
                        weight: weights[c],
                        value: f64::from(frames[c].e[n]),
                        direction: frames[c].direction(n),
                    })
                    .collect()
            })
        }))
    };
    let magnitude = |[k_max, k_min]: [f64; 2]| match kind {
        LineKind::Ridge => k_max.abs(),
        LineKind::Valley => k_min.abs(),
        _ => k_max.abs().max(k_min.abs()),
    };
    let n = line.points.len();
    let pieces = if line.closed { n } else { n.saturating_sub(1) };
    let strength = (0..pieces)
        .map(|i| {
            let j = (i + 1) % n;
            0.5 * (magnitude(k[i]) + magnitude(k[j])) * (line.points[j] - line.points[i]).norm()
        })
        .sum();
    Polyline::new(kind, line.closed, strength, line.points.clone())
        .with_values("k_max", k.iter().map(|k| k[0]).collect())
        .with_values("k_min", k.iter().map(|k| k[1]).collect())
        .with_values("e_max", extremality(0))
        .with_values("e_min", extremality(1))
}

/// The frames at the corners of the cell holding world point `p` and their
/// trilinear weights at `p`, `None` if a corner is undefined.
fn corner_frames(
    curvatures: &Curvatures,
    volume: &Volume,
    p: &Point,
) -> Option<([Frame; 8], [f64; 8])> {
    let index = volume.world_to_index(p);
    let cell = curvatures.grid.cell_holding(index);
    let local = std::array::from_fn(|a| index[a] - cell[a] as f64);
    Some((curvatures.corners(cell)?, weights(local)))
}

#[cfg(test)]
mod tests;

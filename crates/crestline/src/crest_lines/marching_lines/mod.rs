//! Bi-iso-lines: the curves where the isosurface `f = I` of a volume meets the
//! level set `g = J` of a second field on the same grid, by the Marching Lines
//! algorithm of Thirion & Gourdon 1993 ("The 3D marching lines algorithm", §4),
//! with the conventions of docs/design/images.md ("Isosurfaces and implicit curvature").
//!
//! In every cell the isosurface is cut into its oriented polygons, exactly as
//! [`isosurface()`](crate::isosurface::isosurface()) does (BUILDCYCLES, asymptotic
//! decider, inside `f ≥ I`, counter-clockwise seen from `f < I`). Then:
//!
//! - `g` is interpolated linearly along the grid edge of each polygon vertex, and
//!   each polygon edge whose ends lie on different sides of `J` (a vertex with
//!   `g ≥ J` is `+`, the object/background convention) carries one point, at the
//!   linear interpolation of `g` between its ends, labelled like the edge's end
//!   (CYCLESTOPOINTS, §4.2). A polygon edge lies on one face of the cell, so the
//!   point is named by the polygon edge, the pair of grid-edge keys `3·point +
//!   axis` of its ends ([`PointKey`]), and computed from the ends in key order: the
//!   two cells of the face produce the same point, bit for bit.
//! - The labelled points alternate `−`, `+` around the polygon. Rotated so that
//!   `Q0` is a `−` point, they are paired `Q0→Q1, Q2→Q3, …` or, shifted,
//!   `Q2→Q1, Q4→Q3, …, Q0→Q(n−1)`: the only two non-crossing matchings that run
//!   from `−` to `+` (CYCLETOSEGS). The first joins the `+` sides of the polygon,
//!   the second its `−` sides; the mean of `g` over the polygon's vertices (the
//!   values the points are interpolated from) decides: at least `J` joins the `+`
//!   sides (the average value convention, convention 4 of the paper). Each segment
//!   keeps `g ≥ J` on its left seen from `f < I` (the bi-iso-line orientation
//!   convention, convention 3).
//! - The segments of all cells are chained by point key into polylines. Every point
//!   inside the volume ends one segment in each of the two cells of its face, so the
//!   lines are closed except at the volume border and next to cells where `g` is
//!   undefined ([`SecondField::corners`] gives `None`, e.g. a NaN sample).
//!
//! A [`SecondField`] may also orient its values per cell and drop segments
//! ([`SecondField::keep`]), as crest lines need (`g` = extremality, whose sign
//! follows a principal direction chosen per cell; docs/design/crest-lines.md): the chaining is
//! therefore undirected, and a line is given the direction of the majority of its
//! segments, which for a field with a global sign is the convention's.
//!
//! Points are in world coordinates. Cells are processed in parallel over slabs of
//! z layers of fixed size, so the result does not depend on the number of threads.
//!
//! The randomized variant of the paper ([`seeded_marching_lines`]) visits only the
//! cells of the lines through a few random seed cells, longest lines first.

mod cell;
mod chain;
mod seeded;

use rayon::prelude::*;

use crate::isosurface::check_input;
#[cfg(test)]
use crate::volume::grid::Grid;
use crate::volume::Volume;
use crate::{Error, Point, Result};

pub use seeded::seeded_marching_lines;

/// Names a point of a bi-iso-line: the polygon edge of the isosurface it lies on,
/// as the keys `3·point + axis` of the two grid edges that carry the edge's ends,
/// smaller first. Both cells sharing the face of the polygon edge give it the same
/// key.
pub type PointKey = [u64; 2];

/// The second field `g` of a bi-iso-line, read cell by cell.
pub trait SecondField: Sync {
    /// The values of `g` at the 8 corners of the cell whose lowest corner is
    /// sample `cell` (corner `c` at offset `(c & 1, (c >> 1) & 1, (c >> 2) & 1)`),
    /// or `None` where `g` is undefined: the cell then has no segments, and the
    /// lines that reach it end there. Two cells sharing a face must give the same
    /// values on it, or the same values negated.
    fn corners(&self, cell: [usize; 3]) -> Option<[f64; 8]>;

    /// Whether to keep a segment of `cell` whose midpoint is at `local` (cell
    /// coordinates in `[0, 1]³`), with the corner values `corners` given by
    /// [`SecondField::corners`]. Keeps every segment unless overridden.
    fn keep(&self, cell: [usize; 3], corners: &[f64; 8], local: [f64; 3]) -> bool {
        let _ = (cell, corners, local);
        true
    }
}

/// A field sampled on the grid of a volume: `g` at each sample, undefined where a
/// value is not finite.
#[derive(Clone, Copy, Debug)]
#[cfg(test)]
pub struct SampledField<'a> {
    values: &'a [f32],
    grid: Grid,
}

#[cfg(test)]
impl<'a> SampledField<'a> {
    /// The field with one value per sample of `volume`, in the same order (x
    /// fastest). Errors ([`Error::Argument`]) if the number of values differs.
    pub fn new(volume: &Volume, values: &'a [f32]) -> Result<SampledField<'a>> {
        if values.len() != volume.len() {
            return Err(Error::Argument(format!(
                "the second field has {} values for a volume of {} samples",
                values.len(),
                volume.len()
            )));
        }
        Ok(SampledField {
            values,
            grid: volume.grid(),
        })
    }
}

#[cfg(test)]
impl SecondField for SampledField<'_> {
    fn corners(&self, cell: [usize; 3]) -> Option<[f64; 8]> {
        let corners = self.grid.corners(cell).map(|at| f64::from(self.values[at]));
        corners.iter().all(|v| v.is_finite()).then_some(corners)
    }
}

/// One bi-iso-line: world points in order and whether the line is a loop.
#[derive(Clone, Debug, PartialEq)]
pub struct BiIsoLine {
    /// The points, without a repeated first point for a loop.
    pub points: Vec<Point>,
    /// The key of each point (see `PointKey`).
    pub keys: Vec<PointKey>,
    /// Whether the last point joins the first.
    pub closed: bool,
}

impl BiIsoLine {
    /// The line in the direction its point keys give, which depends on the grid
    /// alone: an open line from its end of smaller key, a loop from its point of
    /// smallest key towards the smaller of that point's neighbours. For lines whose
    /// second field has no global sign (crest lines: the sign of an extremality
    /// follows a principal direction's sign, which an eigensolver picks in world
    /// coordinates), the segments' majority direction would depend on the world
    /// frame the image declares; this direction does not.
    pub fn in_key_order(mut self) -> BiIsoLine {
        let n = self.keys.len();
        if n < 2 {
            return self;
        }
        if self.closed {
            let lowest = (0..n).min_by_key(|&i| self.keys[i]).unwrap_or(0);
            self.keys.rotate_left(lowest);
            self.points.rotate_left(lowest);
            if self.keys[n - 1] < self.keys[1] {
                self.keys[1..].reverse();
                self.points[1..].reverse();
            }
        } else if self.keys[n - 1] < self.keys[0] {
            self.keys.reverse();
            self.points.reverse();
        }
        self
    }
}

/// A segment of a bi-iso-line inside one cell, from its first end to its second.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Segment {
    keys: [PointKey; 2],
    points: [Point; 2],
}

/// Cell layers per slab: a fixed number, so the output does not depend on the
/// number of threads.
const SLAB_LAYERS: usize = 8;

/// The bi-iso-lines of `volume`'s samples `f` at `level` and the samples `g` at
/// `g_level` (Marching Lines; see `crest_lines/marching_lines/mod.rs`), with `g` one
/// value per sample (NaN where undefined).
///
/// Errors ([`Error::Argument`]) as [`marching_lines`], or if `g` does not have one
/// value per sample.
#[cfg(test)]
pub fn bi_iso_lines(
    volume: &Volume,
    level: f64,
    g: &[f32],
    g_level: f64,
) -> Result<Vec<BiIsoLine>> {
    marching_lines(volume, level, &SampledField::new(volume, g)?, g_level)
}

/// The lines where the isosurface `f = level` of `volume` meets `g = g_level` for
/// the second field `field` (Marching Lines, Thirion & Gourdon 1993 §4; see the
/// source file `crest_lines/marching_lines/mod.rs`): closed except at the border
/// of the volume and where `g` is undefined, in a deterministic order.
///
/// Errors ([`Error::Argument`]): a level is not finite, a dimension of the volume
/// is below 2, or a sample of `f` is not finite. No crossing is not an error: the
/// result is empty.
pub fn marching_lines(
    volume: &Volume,
    level: f64,
    field: &impl SecondField,
    g_level: f64,
) -> Result<Vec<BiIsoLine>> {
    check_levels(volume, level, g_level)?;
    let layers = volume.grid().cell_layers();
    let slabs: Vec<Vec<Segment>> = (0..layers)
        .into_par_iter()
        .step_by(SLAB_LAYERS)
        .map(|first| {
            let layers = first..(first + SLAB_LAYERS).min(layers);
            cell::slab_segments(volume, (level, g_level), field, layers)
        })
        .collect();
    Ok(chain::chain(&slabs.concat()))
}

/// Which cells the Marching Lines visit.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Sweep {
    /// Every cell: every line, in a deterministic order.
    #[default]
    Every,
    /// `count` cells drawn at random among those the isosurface crosses, with a
    /// generator seeded by `rng_seed`, and the lines through them followed from
    /// cell to cell (the randomized variant, Thirion & Gourdon 1993 §5): the longer
    /// lines, longest first.
    Seeds {
        /// How many cells to draw.
        count: usize,
        /// The seed of the random generator (the same seed gives the same lines).
        rng_seed: u64,
    },
}

impl Sweep {
    /// The lines of `f = level` and `g = g_level` ([`marching_lines`] arguments)
    /// found by this sweep.
    pub(crate) fn lines(
        self,
        volume: &Volume,
        level: f64,
        field: &impl SecondField,
        g_level: f64,
    ) -> Result<Vec<BiIsoLine>> {
        match self {
            Sweep::Every => marching_lines(volume, level, field, g_level),
            Sweep::Seeds { count, rng_seed } => {
                seeded_marching_lines(volume, level, field, g_level, count, rng_seed)
            }
        }
    }
}

/// The checks of [`marching_lines`]: the volume and `level` as for an isosurface,
/// and a finite `g_level`.
fn check_levels(volume: &Volume, level: f64, g_level: f64) -> Result<()> {
    check_input(volume, level)?;
    if !g_level.is_finite() {
        return Err(Error::Argument(format!(
            "the level {g_level} of the second field is not finite"
        )));
    }
    Ok(())
}

//! The vertex numbering shared by the OBJ, PLY and VTK writers: the points of all
//! lines are written in order, so line `k`'s points get consecutive indices starting
//! after those of lines `0..k`.

use super::{FeatureLines, Polyline};
use crate::Point;

/// A line together with its position in [`FeatureLines::lines`] and the index of its
/// first point among all written points.
pub(super) struct IndexedLine<'a> {
    /// The position of the line in [`FeatureLines::lines`].
    pub(super) number: usize,
    /// The line itself.
    pub(super) line: &'a Polyline,
    /// The 0-based index of the line's first point.
    first: usize,
}

impl IndexedLine<'_> {
    /// The 0-based point indices the line visits, in order; a closed line ends with
    /// its first index again.
    pub(super) fn path(&self) -> impl Iterator<Item = usize> {
        let end = self.first + self.line.points.len();
        let closing = self.line.closed.then_some(self.first);
        (self.first..end).chain(closing)
    }

    /// The number of indices [`path`](Self::path) yields.
    pub(super) fn path_len(&self) -> usize {
        self.line.points.len() + usize::from(self.line.closed)
    }

    /// The segments of the line as pairs of consecutive [`path`](Self::path) indices.
    pub(super) fn edges(&self) -> impl Iterator<Item = (usize, usize)> {
        self.path().zip(self.path().skip(1))
    }
}

/// Every line with its numbering, in order.
pub(super) fn indexed(lines: &FeatureLines) -> impl Iterator<Item = IndexedLine<'_>> {
    lines.iter().enumerate().scan(0, |next, (number, line)| {
        let first = *next;
        *next += line.points.len();
        Some(IndexedLine {
            number,
            line,
            first,
        })
    })
}

/// The points of all lines in the order of their indices.
pub(super) fn points(lines: &FeatureLines) -> impl Iterator<Item = &Point> {
    lines.iter().flat_map(|line| line.points.iter())
}

/// The names of the per-point values every line has (none when there are no lines),
/// in order: what the PLY and VTK writers can store per point.
pub(super) fn shared_value_names(lines: &FeatureLines) -> Vec<&str> {
    let Some(first) = lines.lines.first() else {
        return Vec::new();
    };
    first
        .values
        .keys()
        .filter(|name| lines.iter().all(|line| line.values.contains_key(*name)))
        .map(String::as_str)
        .collect()
}

/// The value `name` at every point, in the order of [`points`].
pub(super) fn point_values<'a>(
    lines: &'a FeatureLines,
    name: &'a str,
) -> impl Iterator<Item = f64> + 'a {
    lines
        .iter()
        .flat_map(move |line| line.values[name].iter().copied())
}

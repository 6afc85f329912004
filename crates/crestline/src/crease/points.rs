//! The points a crease surface is built from: edge crossings first, then the
//! degenerate points of the faces, with what the pairing and the output need.

use rayon::prelude::*;

use super::degenerate::DegeneratePoint;
use super::edges::EdgeCrossing;
use super::field::CreaseField;
use crate::volume::grid::in_face_axes;
use crate::{Point, Vector};

/// Positions, grid coordinates, normals, strengths and kinds of the surface's
/// points: ids below the number of crossings are crossings, the rest degenerate
/// points.
pub(crate) struct Points {
    /// World positions.
    pub position: Vec<Point>,
    /// Fractional grid coordinates (for the 2D tests on a face).
    pub grid: Vec<Vector>,
    /// Unit normals (the zero vector where none could be computed).
    pub normal: Vec<Vector>,
    /// Ridge strength −λ3.
    pub strength: Vec<f64>,
    /// Whether the point was located where λ2 = λ3 (a degenerate point found by
    /// the search, not a fallback).
    pub degenerate: Vec<bool>,
}

impl Points {
    /// The crossings followed by the degenerate points, with their normals
    /// ([`CreaseField::normal_at`]).
    pub fn new(
        field: &CreaseField,
        epsilon: f64,
        crossings: &[EdgeCrossing],
        degenerate: &[DegeneratePoint],
    ) -> Points {
        let position: Vec<Point> = crossings
            .iter()
            .map(|c| c.position)
            .chain(degenerate.iter().map(|d| d.position))
            .collect();
        let strength = crossings
            .iter()
            .map(|c| -c.lambda3)
            .chain(degenerate.iter().map(|d| -d.lambda3))
            .collect();
        let kind = std::iter::repeat_n(false, crossings.len())
            .chain(degenerate.iter().map(|d| d.found))
            .collect();
        Points {
            grid: position.iter().map(|p| field.to_grid(p)).collect(),
            normal: position
                .par_iter()
                .map(|p| field.normal_at(p, epsilon))
                .collect(),
            position,
            strength,
            degenerate: kind,
        }
    }

    /// The 2D coordinates of point `id` in a face normal to `axis`.
    pub fn in_face(&self, id: usize, axis: usize) -> [f64; 2] {
        let (u, v) = in_face_axes(axis);
        [self.grid[id][u], self.grid[id][v]]
    }
}

//! Where crease surfaces cross the edges of the grid (Schultz, Theisel and Seidel
//! 2010, §4.3 and eq. 6, with the rules of docs/design/crease.md, "Crease surfaces").

use rayon::prelude::*;

use super::field::{CreaseField, Sample};
use super::strong::StrongCells;
use super::tensor::similarity;
use crate::{Point, Vector};

/// Sub-edges are not bisected below this fraction of an edge.
const SHORTEST_SUB_EDGE: f64 = 0.25;

/// How opposite h must be at the ends of a (sub-)edge to count as a crossing: the
/// cosine of their angle at most −this. Across a genuine crossing e3 turns little
/// and h = (λ'3 − 1)(g·e3) e3 flips; where one end enters a degenerate region, e3
/// there is any direction of a plane and h nearly orthogonal or vanishing, with a
/// random sign, which a bare h₀·h₁ < 0 would take for a crossing.
const OPPOSITION: f64 = 0.5;

/// Crossings kept per grid edge at most.
pub const MAX_CROSSINGS_PER_EDGE: usize = 3;

/// A point where h = T g − g changes sign along a grid edge.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EdgeCrossing {
    /// The grid edge: `3 · point + axis`, `point` the linear index of its first
    /// sample, `axis` the index axis it runs along.
    pub edge: u64,
    /// The position along the edge, as a fraction of its length from `point`.
    pub t: f64,
    /// The world position.
    pub position: Point,
    /// λ3 of the Hessian there (negative on ridges).
    pub lambda3: f64,
}

/// The parameters of the edge crossings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CrossingOptions {
    /// ε of the tensor T: ends with λ2 − λ3 < ε are degenerate.
    pub epsilon: f64,
    /// Sub-edges are bisected while their ends' tensors are less similar than this.
    pub theta: f64,
    /// The least ridge strength −λ3 kept (the side constraint λ3 < 0 with a
    /// margin): [`edge_crossings`] keeps crossings this strong, and
    /// [`crease_surface`](super::crease_surface) trims its surface along −λ3 = s.
    pub strength: f64,
}

/// The crossings of every grid edge, in edge order (and by `t` on an edge): an
/// edge is crossed where h is opposite at its ends (h₀·h₁ < −½|h₀||h₁|), at t =
/// |h₀| / (|h₀| + |h₁|), where −λ3 is at least the strength; it is bisected first
/// while the tensors at its ends are less similar than θ ([`similarity`], eq. 6),
/// down to a quarter of its length, and it is never crossed between two degenerate
/// ends (λ2 − λ3 < ε): around a rotationally symmetric ridge h is tiny there with a
/// random sign.
#[cfg(test)]
pub fn edge_crossings(field: &CreaseField, options: &CrossingOptions) -> Vec<EdgeCrossing> {
    let strong = StrongCells::new(field, options.strength);
    let mut crossings = crossings_in_strong_cells(field, options, &strong);
    crossings.retain(|c| -c.lambda3 >= options.strength);
    crossings
}

/// The crossings of every edge of the strong cells ([`StrongCells`]) where λ3 < 0,
/// as [`edge_crossings`] finds them but of any strength.
pub(crate) fn crossings_in_strong_cells(
    field: &CreaseField,
    options: &CrossingOptions,
    strong: &StrongCells,
) -> Vec<EdgeCrossing> {
    let grid = field.grid();
    let [nx, ny, nz] = grid.dims;
    (0..nz)
        .into_par_iter()
        .flat_map_iter(|k| {
            let mut found = Vec::new();
            for j in 0..ny {
                for i in 0..nx {
                    for axis in 0..3 {
                        let key = grid.key([i, j, k], axis);
                        if strong.edge(key) {
                            found.extend(crossings_on_edge(field, key, options));
                        }
                    }
                }
            }
            found
        })
        .collect()
}

/// The crossings of the grid edge `key` (`3 · point + axis`, as in
/// [`EdgeCrossing::edge`]) with `options`, by increasing t: none for an edge that
/// leaves the grid.
pub(crate) fn crossings_on_edge(
    field: &CreaseField,
    key: u64,
    options: &CrossingOptions,
) -> Vec<EdgeCrossing> {
    let grid = field.grid();
    let (start, axis) = grid.unkey(key);
    let mut end = start;
    end[axis] += 1;
    let mut found = Vec::new();
    if grid.contains(end) {
        edge(key, [start, end], field, options, &mut found);
    }
    found
}

/// The crossings of the grid edge `key` from sample `start` to `end`.
fn edge(
    key: u64,
    [start, end]: [[usize; 3]; 2],
    field: &CreaseField,
    options: &CrossingOptions,
    found: &mut Vec<EdgeCrossing>,
) {
    let (a, b) = (field.sample(start), field.sample(end));
    if a.frame.gap() < options.epsilon && b.frame.gap() < options.epsilon {
        return;
    }
    // λ3 is concave in the Hessian, so along the edge −λ3 stays below the larger of
    // its end values: an edge with λ3 ≥ 0 at both ends meets the side constraint
    // nowhere.
    if a.frame.eigenvalues[2].min(b.frame.eigenvalues[2]) >= 0.0 {
        return;
    }
    let mut ts = Vec::new();
    let search = Search {
        a: &a,
        b: &b,
        epsilon: options.epsilon,
        theta: options.theta,
    };
    search.split(0.0, &a, 1.0, &b, &mut ts);
    let ridge = ts.into_iter().filter(|&(_, lambda3)| lambda3 < 0.0);
    for (t, lambda3) in ridge.take(MAX_CROSSINGS_PER_EDGE) {
        let position = field.position(start) + (field.position(end) - field.position(start)) * t;
        found.push(EdgeCrossing {
            edge: key,
            t,
            position,
            lambda3,
        });
    }
}

/// The bisection of one grid edge between its end samples `a` and `b`.
struct Search<'s> {
    a: &'s Sample,
    b: &'s Sample,
    epsilon: f64,
    theta: f64,
}

impl Search<'_> {
    /// Appends `(t, λ3)` of the crossings in the sub-edge `[t0, t1]`.
    fn split(&self, t0: f64, s0: &Sample, t1: f64, s1: &Sample, out: &mut Vec<(f64, f64)>) {
        let similar = similarity(
            &s0.frame.tensor(self.epsilon),
            &s1.frame.tensor(self.epsilon),
        );
        if similar < self.theta && t1 - t0 > SHORTEST_SUB_EDGE {
            let middle = 0.5 * (t0 + t1);
            let sm = Sample::between(self.a, self.b, middle);
            self.split(t0, s0, middle, &sm, out);
            self.split(middle, &sm, t1, s1, out);
            return;
        }
        if s0.frame.gap() < self.epsilon && s1.frame.gap() < self.epsilon {
            return;
        }
        let (h0, h1): (Vector, Vector) = (s0.h(self.epsilon), s1.h(self.epsilon));
        if h0.dot(&h1) < -OPPOSITION * h0.norm() * h1.norm() {
            let fraction = h0.norm() / (h0.norm() + h1.norm());
            let t = t0 + (t1 - t0) * fraction;
            let lambda3 = Sample::between(self.a, self.b, t).frame.eigenvalues[2];
            out.push((t, lambda3));
        }
    }
}

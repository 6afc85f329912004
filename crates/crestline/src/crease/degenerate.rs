//! Degenerate points: where a degenerate line (λ2 = λ3 for ridges), along which a
//! crease surface ends, passes through a grid face (Schultz, Theisel and Seidel
//! 2010, §3.2 and §4.3).
//!
//! Only faces of strong cells crossed an odd number of times (by crossings of any
//! strength) are searched, and only those with a corner as strong as the strength:
//! elsewhere on the face −λ3 stays below it, and whatever point the face gets is
//! trimmed away. A ridge that enters a face either leaves it or ends there. The
//! search minimises (λ2 − λ3)² / ‖H‖²_F
//! over the face by gradient descent with Armijo steps from several seeds. Where no
//! point is found, an edge crossing was probably missed: the face's edges are
//! searched again with a higher similarity threshold θ (eq. 6) and, if the face is
//! still crossed an odd number of times, a fallback point at its centre keeps the
//! polygons closed.

use std::collections::{HashMap, HashSet};

use nalgebra::Matrix3;
use rayon::prelude::*;

use super::edge_index::EdgeIndex;
use super::edges::{crossings_on_edge, CrossingOptions, EdgeCrossing};
use super::field::CreaseField;
use super::strong::StrongCells;
use crate::volume::grid::{in_face_axes, Grid};
use crate::{Point, Vector};

/// The raised thresholds θ of the passes over faces with no degenerate point.
const RAISED_THETAS: [f64; 2] = [0.8, 0.9];

/// A point is degenerate where (λ2 − λ3)² / ‖H‖²_F is below this.
const TOLERANCE: f64 = 1e-9;

/// Descent steps per seed at most.
const MAX_STEPS: usize = 100;

/// Halvings of a step at most (Armijo backtracking).
const MAX_HALVINGS: usize = 30;

/// The sufficient decrease of an Armijo step, as a fraction of the decrease the
/// gradient predicts.
const ARMIJO: f64 = 1e-4;

/// A descent stalls, and fails, when a step lowers the objective by less than this
/// fraction: it is caught in a local minimum above the tolerance.
const STALL: f64 = 1e-3;

/// The longest step, in face widths.
const LONGEST_STEP: f64 = 0.25;

/// Finite-difference step of the gradient, in face widths.
const DIFFERENCE_STEP: f64 = 1e-5;

/// The seeds of the descent, in face coordinates.
const SEEDS: [[f64; 2]; 5] = [
    [0.5, 0.5],
    [0.25, 0.25],
    [0.75, 0.25],
    [0.75, 0.75],
    [0.25, 0.75],
];

/// The point where a crease ends on a face crossed an odd number of times.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct DegeneratePoint {
    /// The face: `3 · lowest corner + normal axis` (linear index of the corner).
    pub face: u64,
    /// The world position.
    pub position: Point,
    /// λ3 of the Hessian there.
    pub lambda3: f64,
    /// Whether λ2 = λ3 there (`false`: the fallback point at the face centre).
    pub found: bool,
}

/// The degenerate points of the faces of `strong` cells crossed an odd number of
/// times, and the crossings updated on the edges searched again with a raised θ
/// (still sorted by edge, then t). Every such face that stays crossed an odd number
/// of times gets one point, found or fallback, sorted by face key.
pub(crate) fn degenerate_points(
    field: &CreaseField,
    options: &CrossingOptions,
    crossings: Vec<EdgeCrossing>,
    strong: &StrongCells,
) -> (Vec<EdgeCrossing>, Vec<DegeneratePoint>) {
    let grid = field.grid();
    let index = EdgeIndex::new(&crossings);
    let mut redone: HashMap<u64, Vec<EdgeCrossing>> = HashMap::new();
    let count = |redone: &HashMap<u64, Vec<EdgeCrossing>>, face: u64| {
        let (low, axis) = grid.unkey(face);
        grid.face_edges(low, axis)
            .iter()
            .map(|(e, _)| redone.get(e).map_or(index.on(*e).len(), Vec::len))
            .sum::<usize>()
    };
    let mut candidates: Vec<u64> = index
        .edges()
        .par_iter()
        .flat_map_iter(|&e| grid.edge_faces(e))
        .collect();
    candidates.par_sort_unstable();
    candidates.dedup();
    let mut odd: Vec<u64> = candidates
        .into_par_iter()
        .filter(|&f| strong.face(f) && count(&redone, f) % 2 == 1)
        .collect();
    let searched = |faces: &[u64]| -> Vec<u64> {
        let strong_corner = faces.iter().copied().filter(|&f| strong.face_corner(f));
        strong_corner.collect()
    };
    let mut located: HashMap<u64, Option<(Point, f64)>> = search(field, &grid, &searched(&odd));
    for theta in RAISED_THETAS {
        let failed: Vec<u64> = odd
            .iter()
            .copied()
            .filter(|f| located.get(f).is_some_and(Option::is_none))
            .collect();
        if failed.is_empty() {
            break;
        }
        let raised = CrossingOptions { theta, ..*options };
        let mut edges: Vec<u64> = failed
            .iter()
            .flat_map(|&f| {
                let (low, axis) = grid.unkey(f);
                grid.face_edges(low, axis).map(|(e, _)| e)
            })
            .collect();
        edges.sort_unstable();
        edges.dedup();
        let again: Vec<(u64, Vec<EdgeCrossing>)> = edges
            .par_iter()
            .map(|&e| (e, crossings_on_edge(field, e, &raised)))
            .collect();
        redone.extend(again);
        let mut affected: Vec<u64> = edges.iter().flat_map(|&e| grid.edge_faces(e)).collect();
        affected.sort_unstable();
        affected.dedup();
        let affected_set: HashSet<u64> = affected.iter().copied().collect();
        odd.retain(|f| !affected_set.contains(f));
        odd.extend(
            affected
                .into_iter()
                .filter(|&f| strong.face(f) && count(&redone, f) % 2 == 1),
        );
        odd.sort_unstable();
        let unsearched: Vec<u64> = odd
            .iter()
            .copied()
            .filter(|f| !located.contains_key(f))
            .collect();
        located.extend(search(field, &grid, &searched(&unsearched)));
    }
    let points = odd
        .iter()
        .map(|&face| match located.get(&face).copied().flatten() {
            Some((position, lambda3)) => DegeneratePoint {
                face,
                position,
                lambda3,
                found: true,
            },
            None => fallback(field, &grid, face),
        })
        .collect();
    (merge(crossings, redone), points)
}

/// The crossings with those of the `redone` edges replaced, sorted by edge and t.
fn merge(
    crossings: Vec<EdgeCrossing>,
    redone: HashMap<u64, Vec<EdgeCrossing>>,
) -> Vec<EdgeCrossing> {
    if redone.is_empty() {
        return crossings;
    }
    let mut all: Vec<EdgeCrossing> = crossings
        .into_iter()
        .filter(|c| !redone.contains_key(&c.edge))
        .collect();
    all.extend(redone.into_values().flatten());
    all.par_sort_by(|a, b| a.edge.cmp(&b.edge).then(a.t.total_cmp(&b.t)));
    all
}

/// The degenerate point (position, λ3) of each face, `None` where none was found.
fn search(field: &CreaseField, grid: &Grid, faces: &[u64]) -> HashMap<u64, Option<(Point, f64)>> {
    faces
        .par_iter()
        .map(|&face| {
            let (low, axis) = grid.unkey(face);
            let patch = FacePatch::new(field, grid, low, axis);
            (face, patch.locate())
        })
        .collect()
}

/// The point at the centre of a face with no degenerate point, so that the
/// polygons of its cells still close.
fn fallback(field: &CreaseField, grid: &Grid, face: u64) -> DegeneratePoint {
    let (low, axis) = grid.unkey(face);
    let patch = FacePatch::new(field, grid, low, axis);
    DegeneratePoint {
        face,
        position: patch.position([0.5, 0.5]),
        lambda3: gap_and_lambda3(&patch.hessian([0.5, 0.5])).1,
        found: false,
    }
}

/// The Hessians of a face's four corners, bilinearly interpolated over it (the
/// trilinear interpolation restricted to the face).
struct FacePatch<'f> {
    field: &'f CreaseField,
    /// Grid coordinates of the lowest corner.
    low: Vector,
    /// The in-face axes.
    axes: (usize, usize),
    /// Hessians at the corners (0, 0), (1, 0), (1, 1), (0, 1).
    corners: [Matrix3<f64>; 4],
}

impl<'f> FacePatch<'f> {
    fn new(field: &'f CreaseField, grid: &Grid, low: [usize; 3], axis: usize) -> FacePatch<'f> {
        let corners = grid
            .face_corners(low, axis)
            .map(|c| field.sample(c).hessian);
        FacePatch {
            field,
            low: Vector::from(low.map(|x| x as f64)),
            axes: in_face_axes(axis),
            corners,
        }
    }

    /// The Hessian at face coordinates `[s, t]`.
    fn hessian(&self, [s, t]: [f64; 2]) -> Matrix3<f64> {
        let [c00, c10, c11, c01] = &self.corners;
        (c00 * (1.0 - s) + c10 * s) * (1.0 - t) + (c01 * (1.0 - s) + c11 * s) * t
    }

    /// The world position of face coordinates `[s, t]`.
    fn position(&self, [s, t]: [f64; 2]) -> Point {
        let mut u = self.low;
        u[self.axes.0] += s;
        u[self.axes.1] += t;
        self.field.position_at_grid(&u)
    }

    /// The objective (λ2 − λ3)² / ‖H‖²_F at `x`: zero exactly where λ2 = λ3,
    /// invariant to the scale of f, at most 2.
    fn objective(&self, x: [f64; 2]) -> f64 {
        let h = self.hessian(x);
        let value = gap_and_lambda3(&h).0.powi(2) / h.norm_squared();
        if value.is_finite() {
            value
        } else {
            2.0
        }
    }

    /// The gradient of the objective at `x`, by central differences.
    fn gradient(&self, [s, t]: [f64; 2]) -> [f64; 2] {
        let d = DIFFERENCE_STEP;
        [
            (self.objective([s + d, t]) - self.objective([s - d, t])) / (2.0 * d),
            (self.objective([s, t + d]) - self.objective([s, t - d])) / (2.0 * d),
        ]
    }

    /// The degenerate point (position, λ3) of the face with λ3 < 0, from the first
    /// seed whose descent stays on the face and ends below the tolerance.
    fn locate(&self) -> Option<(Point, f64)> {
        SEEDS.iter().find_map(|&seed| {
            let x = self.descend(seed)?;
            let lambda3 = gap_and_lambda3(&self.hessian(x)).1;
            (lambda3 < 0.0).then(|| (self.position(x), lambda3))
        })
    }

    /// Gradient descent with Armijo backtracking from `x`: the point where the
    /// objective drops below the tolerance, `None` if the descent leaves the face
    /// or stalls above it (a step that gains less than [`STALL`]).
    fn descend(&self, mut x: [f64; 2]) -> Option<[f64; 2]> {
        let mut value = self.objective(x);
        // The first trial length of a step, in face widths: twice the last one.
        let mut length = LONGEST_STEP;
        for _ in 0..MAX_STEPS {
            if value < TOLERANCE {
                return Some(x);
            }
            let g = self.gradient(x);
            let slope = g[0] * g[0] + g[1] * g[1];
            if !(slope > 0.0 && slope.is_finite()) {
                return None;
            }
            let mut step = length / slope.sqrt();
            let mut accepted = None;
            for _ in 0..MAX_HALVINGS {
                let trial = [x[0] - step * g[0], x[1] - step * g[1]];
                let trial_value = self.objective(trial);
                if trial_value <= value - ARMIJO * step * slope {
                    accepted = Some((trial, trial_value));
                    length = (2.0 * step * slope.sqrt()).min(LONGEST_STEP);
                    break;
                }
                step *= 0.5;
            }
            let (next, next_value) = accepted?;
            if !on_face(next) || next_value > (1.0 - STALL) * value {
                return None;
            }
            (x, value) = (next, next_value);
        }
        (value < TOLERANCE).then_some(x)
    }
}

/// Whether face coordinates `x` lie on the face.
fn on_face(x: [f64; 2]) -> bool {
    x.iter().all(|&c| (-1e-9..=1.0 + 1e-9).contains(&c))
}

/// λ2 − λ3 and λ3 of the symmetric `h`, in closed form: with q = tr h / 3, p the
/// root mean square of the eigenvalues of h − qI over √2, and cos 3φ = det((h −
/// qI)/p) / 2 (φ ∈ [0, π/3]), λ3 = q + 2p cos(φ + 2π/3) and λ2 − λ3 = 2√3 p sin φ,
/// which is smooth where λ2 = λ3.
fn gap_and_lambda3(h: &Matrix3<f64>) -> (f64, f64) {
    let q = h.trace() / 3.0;
    let shifted = h - Matrix3::identity() * q;
    let p = (shifted.norm_squared() / 6.0).sqrt();
    // p = 0 (or NaN): a multiple of the identity, all eigenvalues q.
    if p.is_nan() || p <= 0.0 {
        return (0.0, q);
    }
    let r = ((shifted / p).determinant() / 2.0).clamp(-1.0, 1.0);
    let phi = r.acos() / 3.0;
    let third = 2.0 * std::f64::consts::FRAC_PI_3;
    (
        2.0 * 3f64.sqrt() * p * phi.sin(),
        q + 2.0 * p * (phi + third).cos(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::crease::Eigenframe;

    #[test]
    fn closed_form_gap_and_lambda3_match_the_eigen_decomposition() {
        let matrices = [
            Matrix3::new(-3.0, 1.0, 0.5, 1.0, -1.0, 0.2, 0.5, 0.2, -2.0),
            Matrix3::from_diagonal(&Vector::new(0.0, -2.0, -2.0)),
            Matrix3::from_diagonal(&Vector::new(-2.0, -2.0, 1.0)),
            Matrix3::new(0.1, -0.4, 0.3, -0.4, 2.0, 0.0, 0.3, 0.0, -0.7),
        ];
        for h in matrices {
            let frame = Eigenframe::of(&h);
            let (gap, lambda3) = gap_and_lambda3(&h);
            assert!((gap - frame.gap()).abs() < 1e-7, "{h} {gap}");
            assert!(
                (lambda3 - frame.eigenvalues[2]).abs() < 1e-7,
                "{h} {lambda3}"
            );
        }
    }

    #[test]
    fn the_descent_finds_the_degenerate_point_of_a_linear_hessian_field() {
        // H = −4I + [[s − 0.3, t − 0.6, 0], [t − 0.6, 0.3 − s, 0], [0, 0, 3]] is
        // degenerate (λ2 = λ3 = −4) only at (s, t) = (0.3, 0.6).
        let base = Matrix3::from_diagonal(&Vector::new(-4.0, -4.0, -1.0));
        let hessian = |s: f64, t: f64| {
            base + Matrix3::new(s - 0.3, t - 0.6, 0.0, t - 0.6, 0.3 - s, 0.0, 0.0, 0.0, 0.0)
        };
        let volume = crate::volume::Volume::new(
            [2, 2, 2],
            [1.0; 3],
            [0.0; 3],
            Matrix3::identity(),
            vec![0.0; 8],
        )
        .unwrap();
        let derivatives = crate::volume::Derivatives::cubic_spline(&volume, 2).unwrap();
        let field = CreaseField::new(&volume, &derivatives, true).unwrap();
        let patch = FacePatch {
            field: &field,
            low: Vector::zeros(),
            axes: (0, 1),
            corners: [
                hessian(0.0, 0.0),
                hessian(1.0, 0.0),
                hessian(1.0, 1.0),
                hessian(0.0, 1.0),
            ],
        };
        let (point, lambda3) = patch.locate().expect("a degenerate point");
        assert!((point - Point::new(0.3, 0.6, 0.0)).norm() < 1e-3, "{point}");
        assert!((lambda3 + 4.0).abs() < 1e-3);
        // Without a degenerate point on the face, none is found.
        let far = FacePatch {
            corners: patch
                .corners
                .map(|c| c + Matrix3::new(2.0, 0.0, 0.0, 0.0, -2.0, 0.0, 0.0, 0.0, 0.0)),
            ..patch
        };
        assert!(far.locate().is_none());
    }
}

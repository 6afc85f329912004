//! Trimmed iterative closest points: ICP (Besl & McKay 1992) that fits each step
//! to the best share of the closest-point pairs only, that share chosen at every
//! iteration by the fractional trimmed ICP of Chetverikov et al. (2002, 2005).

use kiddo::{ImmutableKdTree, SquaredEuclidean};
use rayon::prelude::*;

use super::fit::best_rigid_fit;
use super::transform::{rotation_angle, RigidTransform};
use crate::{Point, Result, Vector};

/// The exponent λ of the overlap objective `e(ξ) / ξ^(1+λ)`: 2, the value
/// Chetverikov et al. recommend.
const OVERLAP_EXPONENT: i32 = 2;

/// Distances below this share of the moving points' RMS radius are round-off.
const ROUND_OFF: f64 = 1e-9;

/// The fixed points and a k-d tree over them for closest-point queries.
pub struct Target {
    points: Vec<Point>,
    tree: ImmutableKdTree<f64, 3>,
}

impl Target {
    /// A tree over `points`, which must not be empty.
    pub fn new(points: &[Point]) -> Target {
        let coordinates: Vec<[f64; 3]> = points.iter().map(|p| [p.x, p.y, p.z]).collect();
        Target {
            points: points.to_vec(),
            tree: ImmutableKdTree::new_from_slice(&coordinates),
        }
    }

    /// The index of the fixed point closest to `query`, and its squared distance.
    fn closest(&self, query: &Point) -> (usize, f64) {
        let nearest = self
            .tree
            .nearest_one::<SquaredEuclidean>(&[query.x, query.y, query.z]);
        (nearest.item as usize, nearest.distance)
    }
}

/// The iteration limits of one ICP run.
#[derive(Clone, Copy, Debug)]
pub struct Schedule {
    /// At most this many fit steps.
    pub max_iterations: usize,
    /// The smallest share of pairs kept, in `(0, 1]`.
    pub min_overlap: f64,
    /// Stop once a step moves the points by less than this share of their RMS
    /// radius.
    pub tolerance: f64,
}

/// Where an ICP run ended.
#[derive(Clone, Copy, Debug)]
pub struct Alignment {
    /// The transform taking the moving points onto the fixed ones.
    pub transform: RigidTransform,
    /// The RMS distance of the kept pairs.
    pub rms: f64,
    /// The number of kept pairs.
    pub matched: usize,
    /// The share of the moving points kept.
    pub share: f64,
    /// The trimmed objective `e(ξ) / ξ^(1+λ)` that chose the share; lower is better.
    pub objective: f64,
    /// The fit steps taken.
    pub iterations: usize,
}

/// The closest-point pairs of one iteration that the trimming kept.
struct Trimmed {
    /// `(moving index, fixed index)`, closest pairs first.
    pairs: Vec<(usize, usize)>,
    /// Mean squared distance of the kept pairs.
    mse: f64,
    /// Share of the moving points kept.
    share: f64,
    /// `mse / share^(1+λ)`.
    objective: f64,
}

/// Trimmed ICP from `start`: pair every moving point with its closest fixed point,
/// keep the closest share ξ of the pairs, ξ ≥ `min_overlap` minimizing
/// `e(ξ) / ξ^(1+λ)`, fit the rigid motion to the kept pairs, repeat until a step
/// is below the tolerance or the iterations are spent. `moving` has at least three
/// points.
pub fn trimmed_icp(
    target: &Target,
    moving: &[Point],
    start: RigidTransform,
    schedule: &Schedule,
) -> Result<Alignment> {
    let (centre, radius) = centre_and_radius(moving);
    let negligible = (ROUND_OFF * radius).powi(2);
    let mut transform = start;
    let mut iterations = 0;
    while iterations < schedule.max_iterations {
        let trimmed = trim(
            &closest_pairs(target, moving, &transform, negligible),
            schedule,
        );
        let (source, destination): (Vec<Point>, Vec<Point>) = trimmed
            .pairs
            .iter()
            .map(|&(m, f)| (moving[m], target.points[f]))
            .unzip();
        let next = best_rigid_fit(&source, &destination, None)?;
        iterations += 1;
        let step = displacement(&transform, &next, &centre, radius);
        transform = next;
        if step <= schedule.tolerance * radius {
            break;
        }
    }
    let trimmed = trim(
        &closest_pairs(target, moving, &transform, negligible),
        schedule,
    );
    Ok(Alignment {
        transform,
        rms: trimmed.mse.sqrt(),
        matched: trimmed.pairs.len(),
        share: trimmed.share,
        objective: trimmed.objective,
        iterations,
    })
}

/// For each moving point (in order), the index of the fixed point closest to its
/// image under `transform` and their squared distance, taken as 0 when below
/// `negligible` (round-off), so that exact matches tie.
fn closest_pairs(
    target: &Target,
    moving: &[Point],
    transform: &RigidTransform,
    negligible: f64,
) -> Vec<(usize, f64)> {
    moving
        .par_iter()
        .map(|p| {
            let (index, squared) = target.closest(&transform.apply(p));
            (index, if squared <= negligible { 0.0 } else { squared })
        })
        .collect()
}

/// Keep the closest share of `pairs` (closest fixed index and squared distance per
/// moving point) that minimizes the trimmed objective; among equal objectives the
/// larger share, so that an exact match keeps every pair.
fn trim(pairs: &[(usize, f64)], schedule: &Schedule) -> Trimmed {
    let mut order: Vec<usize> = (0..pairs.len()).collect();
    order.sort_by(|&a, &b| pairs[a].1.total_cmp(&pairs[b].1));
    let mut prefix = Vec::with_capacity(order.len() + 1);
    prefix.push(0.0);
    for &i in &order {
        prefix.push(prefix[prefix.len() - 1] + pairs[i].1);
    }
    let n = pairs.len();
    let smallest = ((schedule.min_overlap * n as f64).ceil() as usize).clamp(3.min(n), n);
    let objective = |k: usize| {
        let share = k as f64 / n as f64;
        (prefix[k] / k as f64) / share.powi(1 + OVERLAP_EXPONENT)
    };
    let mut kept = n;
    for k in (smallest..n).rev() {
        if objective(k) < objective(kept) {
            kept = k;
        }
    }
    Trimmed {
        pairs: order[..kept].iter().map(|&m| (m, pairs[m].0)).collect(),
        mse: prefix[kept] / kept as f64,
        share: kept as f64 / n as f64,
        objective: objective(kept),
    }
}

/// The centroid of `points` and their RMS distance to it (1 if that is zero).
pub fn centre_and_radius(points: &[Point]) -> (Point, f64) {
    let centre = Point::from(points.iter().map(|p| p.coords).sum::<Vector>() / points.len() as f64);
    let mean_square = points
        .iter()
        .map(|p| (p - centre).norm_squared())
        .sum::<f64>()
        / points.len() as f64;
    let radius = mean_square.sqrt();
    (centre, if radius > 0.0 { radius } else { 1.0 })
}

/// A bound on how far the change from `before` to `after` moves points within
/// `radius` of `centre`: the motion of the centre plus the rotation change's arc.
fn displacement(
    before: &RigidTransform,
    after: &RigidTransform,
    centre: &Point,
    radius: f64,
) -> f64 {
    let turn = rotation_angle(&(after.rotation * before.rotation.inverse()));
    (after.apply(centre) - before.apply(centre)).norm() + turn * radius
}

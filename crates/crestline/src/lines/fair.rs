//! Fairing of traced lines as space curves (Hildebrandt et al. 2005, §5.2).

use crate::Point;

/// Smooth a polyline with `iterations` Taubin λ|μ steps (λ = 0.5, μ = −0.53: a
/// low-pass filter that does not shrink the curve the way plain Laplacian smoothing
/// does), keeping every point within `max_distance` of its original position (so
/// the Hausdorff distance to the input stays below it). Open lines keep their end
/// points, where they meet other lines or end.
pub fn fair_polyline(points: &mut [Point], closed: bool, iterations: usize, max_distance: f64) {
    const LAMBDA: f64 = 0.5;
    const MU: f64 = -0.53;
    let n = points.len();
    if n < 3 {
        return;
    }
    let original = points.to_vec();
    let movable = |i: usize| closed || (i > 0 && i + 1 < n);
    for _ in 0..iterations {
        for factor in [LAMBDA, MU] {
            let before = points.to_vec();
            for i in (0..n).filter(|&i| movable(i)) {
                let prev = before[(i + n - 1) % n];
                let next = before[(i + 1) % n];
                let target = before[i] + (nalgebra::center(&prev, &next) - before[i]) * factor;
                let offset = target - original[i];
                let length = offset.norm();
                points[i] = if length > max_distance {
                    original[i] + offset * (max_distance / length)
                } else {
                    target
                };
            }
        }
    }
}

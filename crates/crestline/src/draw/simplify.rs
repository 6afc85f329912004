//! Douglas–Peucker simplification of canvas polylines.

/// The points of `points` that Douglas–Peucker keeps at `tolerance` (pixels): the
/// ends, and every point farther than `tolerance` from the chord of the span it
/// splits. A closed line is simplified as an open one from its first point back to
/// itself, so the result is again a closed line without a repeated end.
#[cfg(test)]
pub fn douglas_peucker(points: &[[f64; 2]], closed: bool, tolerance: f64) -> Vec<[f64; 2]> {
    points
        .iter()
        .zip(douglas_peucker_kept(points, closed, tolerance))
        .filter_map(|(&p, kept)| kept.then_some(p))
        .collect()
}

/// Which points [`douglas_peucker`] keeps, one flag per point.
pub fn douglas_peucker_kept(points: &[[f64; 2]], closed: bool, tolerance: f64) -> Vec<bool> {
    let mut ring: Vec<[f64; 2]> = points.to_vec();
    if closed {
        if let Some(&first) = points.first() {
            ring.push(first);
        }
    }
    if ring.len() < 3 {
        return vec![true; points.len()];
    }
    let mut keep = vec![false; ring.len()];
    keep[0] = true;
    keep[ring.len() - 1] = true;
    let mut spans = vec![(0, ring.len() - 1)];
    while let Some((start, end)) = spans.pop() {
        let farthest = (start + 1..end)
            .map(|i| (i, distance_to_chord(&ring[i], &ring[start], &ring[end])))
            .max_by(|a, b| a.1.total_cmp(&b.1));
        if let Some((i, distance)) = farthest {
            if distance > tolerance {
                keep[i] = true;
                spans.push((start, i));
                spans.push((i, end));
            }
        }
    }
    keep.truncate(points.len());
    keep
}

/// Distance from `p` to the segment from `a` to `b` (to `a` if they coincide).
pub(super) fn distance_to_chord(p: &[f64; 2], a: &[f64; 2], b: &[f64; 2]) -> f64 {
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    let (px, py) = (p[0] - a[0], p[1] - a[1]);
    let length_squared = dx * dx + dy * dy;
    let t = if length_squared > 0.0 {
        ((px * dx + py * dy) / length_squared).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (px - t * dx).hypot(py - t * dy)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn straight_runs_collapse_to_their_ends() {
        let line: Vec<[f64; 2]> = (0..=10)
            .map(|i| [i as f64, 0.01 * (i % 2) as f64])
            .collect();
        assert_eq!(
            douglas_peucker(&line, false, 0.25),
            vec![[0.0, 0.0], [10.0, 0.0]]
        );
    }

    #[test]
    fn corners_are_kept() {
        let line = [[0.0, 0.0], [5.0, 0.0], [5.0, 5.0], [5.0, 10.0]];
        assert_eq!(
            douglas_peucker(&line, false, 0.25),
            vec![[0.0, 0.0], [5.0, 0.0], [5.0, 10.0]]
        );
    }

    #[test]
    fn closed_squares_keep_their_four_corners() {
        let square = [
            [0.0, 0.0],
            [1.0, 0.0],
            [2.0, 0.0],
            [2.0, 2.0],
            [0.0, 2.0],
            [0.0, 1.0],
        ];
        let simplified = douglas_peucker(&square, true, 0.25);
        assert_eq!(
            simplified,
            vec![[0.0, 0.0], [2.0, 0.0], [2.0, 2.0], [0.0, 2.0]]
        );
    }
}

//! Quantities whose sign follows an unoriented direction (the extremality
//! `e = ∇k · t` of a principal direction `t`, which flips with `t`), read along a
//! line with the direction's sign carried continuously from point to point.
//!
//! A principal direction has no global orientation (Thirion & Gourdon 1993, §5.1
//! of the first part: there is no continuous choice over a closed surface), but
//! along a line it can be carried from each point to the next. The sign of the
//! result then depends only on the sign chosen at the first point, so its zero
//! crossings along the line (Thirion's extremal points, where the other
//! extremality vanishes on a crest line) do not depend on any choice.

use crate::Vector;

/// A sample of a direction-signed quantity near a line point: its interpolation
/// weight, its value and the direction its sign refers to.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DirectedSample {
    /// The interpolation weight (e.g. barycentric or trilinear).
    pub weight: f64,
    /// The value for `direction`; the value for `−direction` is `−value`.
    pub value: f64,
    /// The direction the sign of `value` refers to.
    pub direction: Vector,
}

/// The values along a line whose points are interpolated from `samples` (one list
/// per point, in line order): at each point every sample's direction is turned
/// towards the previous point's interpolated direction (at the first point,
/// towards its heaviest sample's) and the signed values interpolated. Points
/// without samples get 0.
pub fn along_line<I>(samples: I) -> Vec<f64>
where
    I: IntoIterator,
    I::Item: AsRef<[DirectedSample]>,
{
    let mut reference: Option<Vector> = None;
    let mut values = Vec::new();
    for point in samples {
        let point = point.as_ref();
        let heaviest = point
            .iter()
            .max_by(|a, b| a.weight.total_cmp(&b.weight))
            .map(|s| s.direction);
        let towards = reference.or(heaviest).unwrap_or_else(Vector::zeros);
        let sign = |s: &DirectedSample| {
            if s.direction.dot(&towards) < 0.0 {
                -1.0
            } else {
                1.0
            }
        };
        values.push(point.iter().map(|s| s.weight * s.value * sign(s)).sum());
        let direction: Vector = point
            .iter()
            .map(|s| s.direction * (s.weight * sign(s)))
            .sum();
        if direction.norm() > 0.0 {
            reference = Some(direction);
        }
    }
    values
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample(value: f64, direction: [f64; 3]) -> DirectedSample {
        DirectedSample {
            weight: 1.0,
            value,
            direction: Vector::from(direction),
        }
    }

    #[test]
    fn a_flipped_direction_does_not_flip_the_value() {
        // The same field, e = 1 along +x, sampled with arbitrary signs of the
        // direction: read along the line, the value keeps one sign.
        let points = [
            [sample(1.0, [1.0, 0.0, 0.0])],
            [sample(-1.0, [-1.0, 0.1, 0.0])],
            [sample(1.0, [1.0, 0.2, 0.0])],
            [sample(-1.0, [-1.0, 0.0, 0.1])],
        ];
        assert_eq!(along_line(points), [1.0, 1.0, 1.0, 1.0]);
    }

    #[test]
    fn a_true_sign_change_is_kept_and_the_first_choice_only_flips_all() {
        let line = |first: f64| {
            vec![
                vec![sample(2.0 * first, [first, 0.0, 0.0])],
                vec![sample(1.0, [1.0, 0.0, 0.0])],
                vec![sample(1.0, [-1.0, 0.0, 0.0])],
            ]
        };
        assert_eq!(along_line(line(1.0)), [2.0, 1.0, -1.0]);
        assert_eq!(along_line(line(-1.0)), [-2.0, -1.0, 1.0]);
    }

    #[test]
    fn corners_are_oriented_before_they_are_interpolated() {
        // Two corners holding the same oriented value, stored with opposite
        // directions: averaged without orienting them, they would cancel.
        let corner = |value: f64, direction: [f64; 3]| DirectedSample {
            weight: 0.5,
            ..sample(value, direction)
        };
        let points = [[
            corner(3.0, [0.1, 1.0, 0.0]),
            corner(-3.0, [-0.1, -1.0, 0.0]),
        ]];
        // Which sign the first point takes is arbitrary; the magnitude is not.
        assert_eq!(along_line(points)[0].abs(), 3.0);
    }
}

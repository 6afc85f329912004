//! Chaining the segments of all cells into polylines by point key, with the
//! chaining that lines on meshes use ([`chain_oriented`]).
//!
//! Each point is shared by the segments of the (at most two) cells around its face,
//! so most points have degree two; points of other degree (the border of the
//! volume, cells where the second field is undefined or a segment was dropped) end
//! lines. The graph is walked without regard to the segments' directions, because a
//! [`SecondField`](super::SecondField) may flip its sign from cell to cell; each
//! line then takes the direction most of its segments have.

use super::{BiIsoLine, PointKey, Segment};
use crate::chain::chain_oriented;
use crate::Point;

/// Chain `segments` into maximal polylines: open lines between points whose degree
/// is not two, then loops, in the order of their lowest point or segment. The two
/// cells of a point's face compute it bit for bit alike, so either position serves.
pub(super) fn chain(segments: &[Segment]) -> Vec<BiIsoLine> {
    let ends: Vec<[(PointKey, Point); 2]> = segments
        .iter()
        .map(|s| [0, 1].map(|e| (s.keys[e], s.points[e])))
        .collect();
    chain_oriented(&ends, |&(key, _)| key)
        .into_iter()
        .map(|line| {
            let (keys, points) = line.points.into_iter().unzip();
            BiIsoLine {
                points,
                keys,
                closed: line.closed,
            }
        })
        .collect()
}

//! The extremality, its smoothing and the tracing of its zero set, below the
//! public tracer: independence of the principal directions' signs, and chains that
//! use every traced segment once.

use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};

use super::extremality::{extremality, regular_faces, Principal};
use super::smoothing::smooth_extremality;
use super::trace::{trace, Extremality};
use crate::curvature::{CurvatureEstimator, ShapeOperator};
use crate::lines::chain::chain;
use crate::mesh::generate::{self, Sampling};
use crate::Point;

#[test]
fn smoothed_extremality_does_not_depend_on_direction_signs() {
    let mesh = generate::torus(1.0, 0.35, 20_000, Sampling::jittered(6))
        .unwrap()
        .mesh;
    let reference = ShapeOperator.estimate(&mesh).unwrap();
    let mut flipped = reference.clone();
    let mut rng = StdRng::seed_from_u64(99);
    for d in flipped.d_max.iter_mut() {
        if rng.random_bool(0.5) {
            *d = -*d;
        }
    }
    let smoothed = |field: &crate::curvature::CurvatureField| {
        let mut e = extremality(&mesh, field, Principal::Max);
        smooth_extremality(&mesh, &field.d_max, &mut e, 3, 2.0, None).unwrap();
        e
    };
    let (a, b) = (smoothed(&reference), smoothed(&flipped));
    let scale = a.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    assert!(scale > 0.0);
    let sign_changes = (0..a.len()).filter(|&v| a[v] * b[v] < 0.0).count();
    assert!(
        sign_changes > a.len() / 4,
        "the flips change the signs of e"
    );
    for v in 0..a.len() {
        assert!(
            (a[v].abs() - b[v].abs()).abs() <= 1e-12 * scale,
            "|e| differs at {v}"
        );
    }
}

#[test]
fn chained_lines_have_no_gaps() {
    let mesh = generate::torus(1.0, 0.35, 20_000, Sampling::jittered(2))
        .unwrap()
        .mesh;
    let field = ShapeOperator.estimate(&mesh).unwrap();
    for which in [Principal::Max, Principal::Min] {
        let directions = which.directions(&field);
        let mut e = extremality(&mesh, &field, which);
        smooth_extremality(&mesh, directions, &mut e, 3, 2.0, None).unwrap();
        let regular = regular_faces(&mesh, directions);
        let ext = Extremality::new(which, e, &field, &regular, false);
        let segments = trace(&mesh, &field, &ext);
        assert!(segments.len() > 100);
        let chains = chain(&segments, |_| (Point::origin(), 0.0), 0.0);
        // Every segment appears exactly once as a pair of consecutive points.
        let mut from_chains: Vec<[_; 2]> = Vec::new();
        for c in &chains {
            let n = c.points.len();
            let pairs = if c.closed { n } else { n - 1 };
            for i in 0..pairs {
                let mut pair = [c.points[i], c.points[(i + 1) % n]];
                pair.sort();
                from_chains.push(pair);
            }
        }
        let mut expected: Vec<[_; 2]> = segments
            .iter()
            .map(|s| {
                let mut s = *s;
                s.sort();
                s
            })
            .collect();
        from_chains.sort();
        expected.sort();
        assert_eq!(from_chains, expected);
        // Interior points of a polyline are shared by exactly two segments.
        let degree = |p| expected.iter().filter(|s| s.contains(p)).count();
        for c in &chains {
            let interior = if c.closed {
                &c.points[..]
            } else {
                &c.points[1..c.points.len() - 1]
            };
            assert!(interior.iter().all(|p| degree(p) == 2));
            if !c.closed {
                assert!(degree(&c.points[0]) != 2 && degree(c.points.last().unwrap()) != 2);
            }
        }
    }
}

//! The extremality, its smoothing and the tracing of its zero set, below the
//! public tracer: independence of the principal directions' signs, one system
//! for both principal fields, and chains that use every traced segment once.

use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};

use super::extremality::{extremality, regular_faces, Principal};
use super::smoothing::{smooth_extremality, ExtremalitySmoother};
use super::trace::{trace, Extremality};
use super::{ExtremalityTracer, Solver};
use crate::curvature::{CurvatureEstimator, CurvatureField, ShapeOperator};
use crate::lines::chain::chain;
use crate::lines::direction_field::gauge_between;
use crate::lines::{DirectionField, EdgeSigns};
use crate::mesh::generate::{self, Sampling};
use crate::mesh::Mesh;
use crate::progress::Silent;
use crate::Point;

/// A jittered torus of about `vertices` vertices and its shape-operator curvature.
fn torus_and_curvature(vertices: usize, seed: u64) -> (Mesh, CurvatureField) {
    let mesh = generate::torus(1.0, 0.35, vertices, Sampling::jittered(seed))
        .unwrap()
        .mesh;
    let field = ShapeOperator.estimate(&mesh).unwrap();
    (mesh, field)
}

#[test]
fn smoothed_extremality_does_not_depend_on_direction_signs() {
    let (mesh, reference) = torus_and_curvature(20_000, 6);
    let mut flipped = reference.clone();
    let mut rng = StdRng::seed_from_u64(99);
    for d in flipped.d_max.iter_mut() {
        if rng.random_bool(0.5) {
            *d = -*d;
        }
    }
    let smoothed = |field: &CurvatureField| {
        let mut e = extremality(&mesh, field, Principal::Max);
        smooth_extremality(
            &mesh,
            Principal::Max.direction_field(field),
            &mut e,
            3,
            2.0,
            None,
        )
        .unwrap();
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
    let (mesh, field) = torus_and_curvature(20_000, 2);
    for which in [Principal::Max, Principal::Min] {
        let directions = which.direction_field(&field);
        let mut e = extremality(&mesh, &field, which);
        smooth_extremality(&mesh, directions, &mut e, 3, 2.0, None).unwrap();
        let signs = EdgeSigns::new(&mesh, directions);
        let regular = regular_faces(&mesh, &signs);
        let ext = Extremality::new(which, e, &field, &signs, &regular, false);
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

#[test]
fn both_fields_smoothed_with_one_system_are_smoothed_with_their_own() {
    let (mesh, mut field) = torus_and_curvature(20_000, 3);
    // Arbitrary signs of the valleys' directions: the gauge has to undo them.
    let mut rng = StdRng::seed_from_u64(7);
    for d in field.d_min.iter_mut() {
        if rng.random_bool(0.5) {
            *d = -*d;
        }
    }
    let [ridges, valleys] = [Principal::Max, Principal::Min].map(|w| w.direction_field(&field));
    let signs = [ridges, valleys].map(|d| EdgeSigns::new(&mesh, d));
    let gauge = gauge_between(&mesh, (ridges, &signs[0]), (valleys, &signs[1]))
        .expect("principal fields share signs");
    let turned = gauge.iter().filter(|&&g| g < 0.0).count();
    assert!(turned > mesh.vertex_count() / 3, "{turned} turned");
    let initial = [Principal::Max, Principal::Min].map(|w| extremality(&mesh, &field, w));
    let scale = initial[1].iter().fold(0.0f64, |m, e| m.max(e.abs()));
    // The iteration stops at a relative residual of 10⁻⁷, with another
    // preconditioner when each field has its own system.
    for (solver, tolerance) in [(Solver::Direct, 1e-10), (Solver::Iterative, 1e-5)] {
        let tracer = ExtremalityTracer {
            solver,
            ..ExtremalityTracer::default()
        };
        let smoother = ExtremalitySmoother::new(&mesh, tracer.smooth_time, None, solver)
            .unwrap()
            .analyzed(None)
            .unwrap();
        let mut shared = initial.to_vec();
        tracer
            .smooth_extremalities(&mesh, &smoother, &field, &signs, &mut shared, &mut Silent)
            .unwrap();
        for (signs, (shared, initial)) in signs.iter().zip(shared.iter().zip(&initial)) {
            let mut own = initial.clone();
            smoother
                .smooth(signs, &mut [&mut own], tracer.smooth_steps, &mut Silent)
                .unwrap();
            let worst = own
                .iter()
                .zip(shared)
                .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
            assert!(
                worst <= tolerance * scale,
                "{solver}: {worst:e} of {scale:e}"
            );
            let moved = own
                .iter()
                .zip(initial)
                .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
            assert!(moved > 0.01 * scale, "{solver}: smoothing changed nothing");
        }
    }
}

#[test]
fn fields_whose_signs_disagree_are_not_gauged_together() {
    let (mesh, field) = torus_and_curvature(5_000, 4);
    // Tangent directions at random angles to the principal ones.
    let mut rng = StdRng::seed_from_u64(5);
    let random: Vec<_> = (0..mesh.vertex_count())
        .map(|v| {
            let angle = rng.random_range(0.0..std::f64::consts::PI);
            field.d_max[v] * angle.cos() + field.d_min[v] * angle.sin()
        })
        .collect();
    let ridges = Principal::Max.direction_field(&field);
    let other = DirectionField::new(&random, &field.normal);
    let signs = |d| EdgeSigns::new(&mesh, d);
    let (ridge_signs, other_signs) = (signs(ridges), signs(other));
    assert!(gauge_between(&mesh, (ridges, &ridge_signs), (other, &other_signs)).is_none());
    // Turned by a fixed angle, a field keeps its signs: one system serves both.
    let turned: Vec<_> = (0..mesh.vertex_count())
        .map(|v| field.d_max[v] * 0.6 + field.d_min[v] * 0.8)
        .collect();
    let turned = DirectionField::new(&turned, &field.normal);
    let turned_signs = signs(turned);
    let gauge =
        gauge_between(&mesh, (ridges, &ridge_signs), (turned, &turned_signs)).expect("signs agree");
    assert!(gauge.iter().all(|&g| g == 1.0));
}

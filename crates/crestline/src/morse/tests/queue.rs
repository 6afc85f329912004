//! The lazy cancellation queue against a slow reference: every cancellation must
//! be the least valid score over all live saddles, each scored from scratch.

use crate::curvature::ShapeOperator;
use crate::mesh::generate::{self, Sampling};
use crate::mesh::Mesh;
use crate::morse::cancel::{Criterion, Hierarchy};
use crate::morse::cells::{maximum_regions, measure_saddles, minimum_regions};
use crate::morse::gradient::{Gradient, Keys};
use crate::morse::Indicator;

/// A noisy torus: many critical points, and saddles forced by its genus.
fn noisy_torus() -> Mesh {
    let torus = generate::torus(1.0, 0.35, 4000, Sampling::jittered(3))
        .unwrap()
        .mesh;
    generate::with_normal_noise(&torus, 0.2, 4).unwrap()
}

/// The least score of a valid cancellation over the live saddles, recomputed for
/// every saddle from the current state.
fn reference_minimum(hierarchy: &Hierarchy<'_>) -> Option<f64> {
    (0..hierarchy.saddles.len())
        .filter(|&s| hierarchy.alive[s])
        .filter_map(|s| hierarchy.best(s).map(|(t, _)| t))
        .min_by(f64::total_cmp)
}

/// Whether `a` and `b` agree up to the queue's relative tolerance.
fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-9 * a.abs().max(b.abs()).max(1e-300)
}

#[test]
fn every_cancellation_has_the_least_score_recomputed_from_scratch() {
    let mesh = noisy_torus();
    let values = Indicator::Curvedness.values(&mesh, &ShapeOperator).unwrap();
    let keys = Keys::new(&mesh, values);
    for criterion in [Criterion::Feature, Criterion::Persistence] {
        let gradient = Gradient::new(&mesh, &keys);
        let saddles = measure_saddles(&mesh, &keys, &gradient);
        let regions = (
            minimum_regions(&mesh, &keys, &gradient),
            maximum_regions(&mesh, &keys, &gradient),
        );
        let mut hierarchy = Hierarchy::new(&mesh, &keys, gradient, saddles, regions, criterion);
        let mut count = 0;
        loop {
            let expected = reference_minimum(&hierarchy);
            let Some(cancellation) = hierarchy.cancel_next() else {
                assert_eq!(expected, None, "{criterion:?}: valid cancellations left");
                break;
            };
            let expected = expected.expect("a cancellation with no valid candidate");
            assert!(
                close(cancellation.t, expected),
                "{criterion:?} cancellation {count}: t = {} but the least score is {expected}",
                cancellation.t
            );
            count += 1;
        }
        assert!(count > 100, "{criterion:?}: only {count} cancellations");
    }
}

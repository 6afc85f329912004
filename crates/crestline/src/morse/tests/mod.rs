//! The Morse-Smale complex: topological invariants, the shape of its 1-cells, and the
//! feature-preserving cancellation criterion against persistence.

mod queue;

use std::cmp::Ordering;

use crate::curvature::JetFit;
use crate::mesh::generate::{self, Sampling};
use crate::mesh::{Mesh, TriangleSoup};
use crate::morse::cancel::{Criterion, Hierarchy};
use crate::morse::cells::{maximum_regions, measure_saddles, minimum_regions};
use crate::morse::gradient::{
    compare, local_maximum_faces, local_minimum_vertices, Gradient, Keys,
};
use crate::morse::Indicator;
use crate::progress::Silent;
use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};

fn bundled(name: &str) -> Mesh {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../meshes")
        .join(name);
    Mesh::from_soup(crate::io::read_mesh(&path).unwrap())
        .unwrap()
        .0
}

fn test_meshes() -> Vec<(&'static str, Mesh)> {
    let cap = generate::Paraboloid { a: -1.0, b: 0.4 };
    vec![
        (
            "sphere",
            generate::sphere(1.0, 3000, Sampling::jittered(1))
                .unwrap()
                .mesh,
        ),
        (
            "torus",
            generate::torus(1.0, 0.35, 4000, Sampling::jittered(2))
                .unwrap()
                .mesh,
        ),
        (
            "height field",
            generate::height_field(&cap, 1.0, 3000, Sampling::jittered(3))
                .unwrap()
                .mesh,
        ),
        ("bunny", bundled("bunny.obj")),
        ("cow", bundled("cow.obj")),
        ("airplane", bundled("airplane.obj")),
        (
            "noisy bunny_small",
            generate::with_normal_noise(&bundled("bunny_small.obj"), 0.5, 7).unwrap(),
        ),
    ]
}

fn curvedness_keys(mesh: &Mesh) -> Keys {
    Keys::new(
        mesh,
        Indicator::Curvedness
            .values(mesh, &JetFit::default())
            .unwrap(),
    )
}

#[test]
fn critical_points_satisfy_euler_before_and_after_cancellations() {
    for (name, mesh) in test_meshes() {
        let chi = mesh.euler_characteristic();
        let keys = curvedness_keys(&mesh);
        let gradient = Gradient::new(&mesh, &keys);
        let (m, s, big_m) = (
            gradient.minima.len(),
            gradient.saddles.len(),
            gradient.maxima.len(),
        );
        assert_eq!(m as i64 - s as i64 + big_m as i64, chi, "{name} initial");
        // The roots are the data's extrema, not one per component.
        let local_max = local_maximum_faces(&mesh, &keys)
            .iter()
            .filter(|&&x| x)
            .count();
        let local_min = local_minimum_vertices(&mesh, &keys)
            .iter()
            .filter(|&&x| x)
            .count();
        assert_eq!((big_m, m), (local_max, local_min), "{name}");

        for criterion in [Criterion::Feature, Criterion::Persistence] {
            let saddles = measure_saddles(&mesh, &keys, &gradient);
            let regions = (
                minimum_regions(&mesh, &keys, &gradient),
                maximum_regions(&mesh, &keys, &gradient),
            );
            let mut hierarchy =
                Hierarchy::new(&mesh, &keys, gradient.clone(), saddles, regions, criterion);
            let mut done = 0;
            for target in [1, 10, 100, usize::MAX] {
                while done < target && hierarchy.cancel_next().is_some() {
                    done += 1;
                }
                let (minima, maxima) = hierarchy.extremum_counts();
                let saddles = hierarchy.saddle_count();
                assert_eq!(
                    minima as i64 - saddles as i64 + maxima as i64,
                    chi,
                    "{name} {criterion:?} after {done}"
                );
                assert_eq!(saddles, s - done);
            }
            // Fully simplified: no live saddle has a valid cancellation left.
            let live = (0..s).filter(|&i| hierarchy.alive[i]);
            assert!(
                live.clone().all(|i| hierarchy.best(i).is_none()),
                "{name}: not simplified"
            );
            eprintln!("{name} {criterion:?}: {} saddles left of {s}", live.count());
        }
    }
}

/// The saddles forced by topology (no valid cancellation) are counted as they
/// appear, without rescoring every saddle: the count matches a full scan after
/// every cancellation, on closed meshes of genus 0 and 1 and on a mesh with a
/// boundary, and at the end only forced saddles remain.
#[test]
fn forced_saddles_are_counted_as_cancellations_create_them() {
    let meshes = [
        generate::torus(1.0, 0.35, 1500, Sampling::jittered(4)),
        generate::sphere(1.0, 1000, Sampling::jittered(5)),
        generate::height_field(
            &generate::Paraboloid { a: -1.0, b: 0.4 },
            1.0,
            1000,
            Sampling::jittered(6),
        ),
    ];
    for mesh in meshes.map(|m| m.unwrap().mesh) {
        let keys = curvedness_keys(&mesh);
        let gradient = Gradient::new(&mesh, &keys);
        for criterion in [Criterion::Feature, Criterion::Persistence] {
            let saddles = measure_saddles(&mesh, &keys, &gradient);
            let regions = (
                minimum_regions(&mesh, &keys, &gradient),
                maximum_regions(&mesh, &keys, &gradient),
            );
            let n = saddles.len();
            let mut hierarchy =
                Hierarchy::new(&mesh, &keys, gradient.clone(), saddles, regions, criterion);
            let scanned = |h: &Hierarchy<'_>| {
                (0..n)
                    .filter(|&s| h.alive[s] && h.best(s).is_some())
                    .count()
            };
            assert_eq!(hierarchy.cancellable_count(), scanned(&hierarchy));
            while hierarchy.cancel_next().is_some() {
                assert_eq!(hierarchy.cancellable_count(), scanned(&hierarchy));
            }
            assert_eq!(hierarchy.cancellable_count(), 0, "{criterion:?}");
        }
    }
}

/// Follow parent pointers from a face, returning the faces visited.
fn face_path(
    mesh: &Mesh,
    gradient: &Gradient,
    start: crate::mesh::FaceId,
) -> Vec<crate::mesh::FaceId> {
    let mut path = vec![start];
    while let Some((_, next)) = gradient.face_step(mesh, *path.last().unwrap()) {
        path.push(next);
        assert!(path.len() <= mesh.face_count(), "cycle in the dual forest");
    }
    path
}

fn vertex_path(
    mesh: &Mesh,
    gradient: &Gradient,
    start: crate::mesh::VertexId,
) -> Vec<crate::mesh::VertexId> {
    let mut path = vec![start];
    while let Some((_, next)) = gradient.vertex_step(mesh, *path.last().unwrap()) {
        path.push(next);
        assert!(
            path.len() <= mesh.vertex_count(),
            "cycle in the primal forest"
        );
    }
    path
}

#[test]
fn one_cells_are_connected_monotone_paths_to_extrema_of_the_right_kind() {
    for (name, mesh) in test_meshes() {
        let keys = curvedness_keys(&mesh);
        let gradient = Gradient::new(&mesh, &keys);
        let is_max = local_maximum_faces(&mesh, &keys);
        let is_min = local_minimum_vertices(&mesh, &keys);
        let (mut steps, mut downhill_steps) = (0usize, 0usize);
        for &s in &gradient.saddles {
            let h = mesh.edge_halfedge(s, 0);
            for f in [mesh.face(h), mesh.face(mesh.twin(h))]
                .into_iter()
                .filter(|f| f.is_valid())
            {
                let path = face_path(&mesh, &gradient, f);
                assert!(
                    is_max[path.last().unwrap().idx()],
                    "{name}: ascending line ends off a maximum"
                );
                for w in path.windows(2) {
                    // Consecutive faces share an edge: the strip is connected.
                    let shared = mesh
                        .face_vertices(w[0])
                        .iter()
                        .filter(|v| mesh.face_vertices(w[1]).contains(v))
                        .count();
                    assert_eq!(shared, 2, "{name}");
                    steps += 1;
                    if compare(keys.face_key(w[1]), keys.face_key(w[0])) == Ordering::Less {
                        downhill_steps += 1;
                    }
                }
            }
            for v in mesh.edge_vertices(s) {
                let path = vertex_path(&mesh, &gradient, v);
                assert!(
                    is_min[path.last().unwrap().idx()],
                    "{name}: descending line ends off a minimum"
                );
                for w in path.windows(2) {
                    assert!(
                        mesh.neighbors(w[0]).any(|x| x == w[1]),
                        "{name}: path not connected"
                    );
                    steps += 1;
                    if compare(keys.vertex_key(w[1]), keys.vertex_key(w[0])) == Ordering::Greater {
                        downhill_steps += 1;
                    }
                }
            }
        }
        eprintln!("{name}: {downhill_steps} of {steps} 1-cell steps go against the indicator");
        assert_eq!(
            downhill_steps, 0,
            "{name}: 1-cells must climb (ascending) and fall (descending)"
        );
    }
}

/// A circular ridge in the plane with a Gaussian profile, its crest dipping at one
/// place.
struct Ridge {
    centre: [f64; 2],
    radius: f64,
    height: f64,
    /// The angle where the crest dips, and the depth as a fraction of the height.
    notch: (f64, f64),
}

impl Ridge {
    fn value(&self, x: f64, y: f64, width: f64) -> f64 {
        let (dx, dy) = (x - self.centre[0], y - self.centre[1]);
        let d = dx.hypot(dy) - self.radius;
        let angle = dy.atan2(dx) - self.notch.0;
        let along = self.radius * angle.sin().atan2(angle.cos());
        self.height
            * (-(d / width).powi(2)).exp()
            * (1.0 - self.notch.1 * (-(along / width).powi(2)).exp())
    }

    fn crest(&self, samples: usize) -> impl Iterator<Item = (f64, f64)> + '_ {
        (0..samples).map(move |i| {
            let a = std::f64::consts::TAU * i as f64 / samples as f64;
            (
                self.centre[0] + self.radius * a.cos(),
                self.centre[1] + self.radius * a.sin(),
            )
        })
    }
}

fn ridge_landscape(
    ridges: &[Ridge],
    bumps: &[([f64; 2], f64)],
    width: f64,
    noise: f64,
    vertices: usize,
    seed: u64,
) -> Mesh {
    let flat = generate::Paraboloid { a: 0.0, b: 0.0 };
    let plane = generate::height_field(&flat, 1.0, vertices, Sampling::jittered(seed))
        .unwrap()
        .mesh;
    let mut rng = StdRng::seed_from_u64(seed);
    let height = plane
        .positions()
        .iter()
        .map(|p| {
            let ridge = ridges
                .iter()
                .map(|r| r.value(p.x, p.y, width))
                .fold(0.0, f64::max);
            let bump = bumps
                .iter()
                .map(|(c, h)| h * (-((p.x - c[0]).hypot(p.y - c[1]) / width).powi(2)).exp())
                .fold(0.0, f64::max);
            ridge.max(bump) + rng.random_range(-noise..noise)
        })
        .collect();
    let soup = TriangleSoup {
        positions: plane.positions().to_vec(),
        triangles: plane.triangles(),
        vertex_scalars: vec![crate::mesh::ScalarProperty {
            name: "height".into(),
            values: height,
        }],
        space: None,
        volume_geometry: None,
    };
    Mesh::from_soup(soup).unwrap().0
}

/// Share of each ridge's crest within `radius` of an ascending line point.
fn ridge_coverage(ridges: &[Ridge], lines: &crate::lines::FeatureLines, radius: f64) -> Vec<f64> {
    let points: Vec<_> = lines
        .of_kind(crate::lines::LineKind::Ascending)
        .flat_map(|l| l.points.iter().copied())
        .collect();
    ridges
        .iter()
        .map(|r| {
            let samples = 200;
            let covered = r
                .crest(samples)
                .filter(|&(x, y)| points.iter().any(|p| (p.x - x).hypot(p.y - y) < radius))
                .count();
            covered as f64 / samples as f64
        })
        .collect()
}

/// The paper's Fig. 3 effect (§3.3–3.4): persistence looks only at the deepest point
/// of a line, so a long ridge whose crest dips once loses its line there, while the
/// feature criterion weighs the whole line against the valleys beside it. Three
/// ring-shaped ridges of height 1, each dipping to 15% at one point, beside short
/// bumps of height 0.5 on a noisy plane: persistence keeps the bumps (persistence
/// 0.5) and cuts the rings at their dips (0.15), the feature criterion cancels the
/// bumps (short lines no more salient than their hills, eq. 7) and keeps the rings.
#[test]
fn feature_criterion_keeps_long_ridges_that_persistence_cuts() {
    use crate::lines::LineExtractor;
    use crate::morse::{MorseSmale, Simplification};
    let ridges = [
        Ridge {
            centre: [-0.5, -0.45],
            radius: 0.3,
            height: 1.0,
            notch: (0.5, 0.85),
        },
        Ridge {
            centre: [0.5, -0.45],
            radius: 0.3,
            height: 1.0,
            notch: (2.5, 0.85),
        },
        Ridge {
            centre: [0.0, 0.5],
            radius: 0.3,
            height: 1.0,
            notch: (4.0, 0.85),
        },
    ];
    let bumps = [
        ([-0.6, 0.3], 0.5),
        ([0.6, 0.3], 0.5),
        ([0.0, -0.3], 0.5),
        ([-0.2, -0.85], 0.5),
        ([0.8, 0.8], 0.5),
    ];
    for seed in [2, 5] {
        let mesh = ridge_landscape(&ridges, &bumps, 0.05, 0.02, 12_000, seed);
        let h = mesh.mean_edge_length();
        let coverage = |criterion| {
            let extractor = MorseSmale {
                indicator: Indicator::Property("height".into()),
                criterion,
                simplification: Simplification::KeepSaddles(6),
                ..Default::default()
            };
            ridge_coverage(
                &ridges,
                &extractor.extract(&mesh, &mut Silent).unwrap(),
                3.0 * h,
            )
        };
        let (feature, persistence) = (
            coverage(Criterion::Feature),
            coverage(Criterion::Persistence),
        );
        eprintln!("seed {seed}, 6 saddles kept: ring coverage, feature {feature:.2?}, persistence {persistence:.2?}");
        assert!(feature.iter().all(|&c| c > 0.9), "feature: {feature:?}");
        assert!(
            persistence.iter().any(|&c| c < 0.8),
            "persistence: {persistence:?}"
        );
    }
}

/// Values computed by the caller go through the same complex as the built-in
/// indicator: curvedness from the jet fit, given as numbers, gives the very lines
/// the extractor finds when it estimates curvedness itself; each point carries the
/// indicator where it lies, and bad values are refused with a reason.
#[test]
fn user_values_drive_the_extractor_like_its_own_indicator() {
    use crate::curvature::{estimate_curvature, CurvatureEstimator};
    use crate::lines::{LineExtractor, SurfaceWithValues};
    use crate::morse::{Cells, MorseSmale};
    use std::sync::Arc;
    let mesh = bundled("bunny_small.obj");
    let extractor = MorseSmale {
        estimator: Arc::new(JetFit::default()),
        cells: Cells::Both,
        ..Default::default()
    };
    let own = extractor.extract(&mesh, &mut Silent).unwrap();
    let field = estimate_curvature(&mesh, &JetFit::default() as &dyn CurvatureEstimator).unwrap();
    let values = field.curvedness();
    let given = extractor
        .extract(
            &SurfaceWithValues {
                mesh: &mesh,
                values: &values,
            },
            &mut Silent,
        )
        .unwrap();
    assert!(own.len() > 10, "{}", own.len());
    assert_eq!(own, given);
    for line in &given {
        assert_eq!(line.locations.len(), line.points.len());
        for ((at, p), value) in line
            .locations
            .iter()
            .zip(&line.points)
            .zip(&line.values["indicator"])
        {
            assert!((at.position(&mesh) - p).norm() < 1e-12);
            assert!((at.interpolate(&mesh, &values) - value).abs() < 1e-12);
        }
    }
    let mut short = values.clone();
    short.pop();
    let err = extractor
        .run_with_values(&mesh, short, &mut Silent)
        .unwrap_err();
    assert!(err.to_string().contains("vertices"), "{err}");
    let mut nan = values;
    nan[7] = f64::NAN;
    let err = extractor
        .run_with_values(&mesh, nan, &mut Silent)
        .unwrap_err();
    assert!(err.to_string().contains("vertex 7"), "{err}");
}

//! Isosurfaces of sampled fields: topology (closed, manifold, consistently
//! oriented, Euler characteristic), geometry (area, distance to the true surface,
//! normals toward decreasing f) and the hard cases (ambiguous faces and cells,
//! samples equal to the level, mirrored and anisotropic grids, bad samples).

use std::collections::HashMap;
use std::f64::consts::PI;

use crestline::isosurface::{isosurface, Isosurface, VertexSource};
use crestline::mesh::Mesh;
use crestline::volume::Volume;
use crestline::{Point, Vector};
use nalgebra::Matrix3;
use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};

/// A volume of `dims` samples of `field` (a function of world position) placed by
/// `spacing`, `origin` and `direction`.
fn sampled(
    dims: [usize; 3],
    spacing: [f64; 3],
    origin: [f64; 3],
    direction: Matrix3<f64>,
    field: impl Fn(Point) -> f64,
) -> Volume {
    let count = dims[0] * dims[1] * dims[2];
    let grid = Volume::new(dims, spacing, origin, direction, vec![0.0; count]).unwrap();
    let samples = (0..count)
        .map(|at| {
            let index = [
                at % dims[0],
                (at / dims[0]) % dims[1],
                at / (dims[0] * dims[1]),
            ];
            field(grid.index_to_world(index.map(|x| x as f64))) as f32
        })
        .collect();
    Volume::new(dims, spacing, origin, direction, samples).unwrap()
}

/// A unit-spaced, axis-aligned volume of `n³` samples of `field`.
fn cube(n: usize, field: impl Fn(Point) -> f64) -> Volume {
    sampled([n; 3], [1.0; 3], [0.0; 3], Matrix3::identity(), field)
}

/// A volume of `dims` samples with the given values, unit spacing.
fn from_samples(dims: [usize; 3], samples: Vec<f32>) -> Volume {
    Volume::new(dims, [1.0; 3], [0.0; 3], Matrix3::identity(), samples).unwrap()
}

/// Signed distance to a sphere, positive inside.
fn ball(centre: Point, radius: f64) -> impl Fn(Point) -> f64 {
    move |p| radius - (p - centre).norm()
}

/// Six times the signed volume enclosed by the mesh.
fn signed_volume(mesh: &Mesh) -> f64 {
    mesh.faces()
        .map(|f| {
            let [a, b, c] = mesh.face_points(f).map(|p| p.coords);
            a.dot(&b.cross(&c))
        })
        .sum::<f64>()
        / 6.0
}

fn area(mesh: &Mesh) -> f64 {
    mesh.face_areas().iter().sum()
}

/// The isosurface of `volume` at `level` and its half-edge mesh (built without
/// any repair, or `to_mesh` fails).
fn surface(volume: &Volume, level: f64) -> (Isosurface, Mesh) {
    let iso = isosurface(volume, level).unwrap();
    let mesh = iso.to_mesh().unwrap();
    mesh.check_connectivity().unwrap();
    assert_eq!(mesh.triangles(), iso.soup().triangles);
    assert_eq!(mesh.positions(), iso.soup().positions);
    (iso, mesh)
}

/// Checks on the raw triangle list, independent of the halfedge structure: no
/// directed edge is used twice, and an edge used one way only (a boundary edge)
/// lies in a border plane of the grid. So every interior edge has exactly two
/// faces running along it in opposite directions.
fn assert_closed_away_from_border(iso: &Isosurface, volume: &Volume) {
    let mut directed = HashMap::new();
    for (f, t) in iso.soup().triangles.iter().enumerate() {
        for k in 0..3 {
            let edge = (t[k], t[(k + 1) % 3]);
            assert!(
                directed.insert(edge, f).is_none(),
                "edge {edge:?} used twice one way"
            );
        }
    }
    for &(a, b) in directed.keys() {
        if !directed.contains_key(&(b, a)) {
            assert!(on_border(iso, volume, a) && on_border(iso, volume, b));
        }
    }
}

/// Whether vertex `v` is a crossing on an edge that lies in a border plane.
fn on_border(iso: &Isosurface, volume: &Volume, v: u32) -> bool {
    let dims = volume.dims();
    match iso.source(v as usize) {
        VertexSource::Edge { point, axis, .. } => {
            let at = point as usize;
            let index = [
                at % dims[0],
                (at / dims[0]) % dims[1],
                at / (dims[0] * dims[1]),
            ];
            (0..3).any(|a| a != axis as usize && (index[a] == 0 || index[a] == dims[a] - 1))
        }
        VertexSource::Cell { .. } => false,
    }
}

/// Every component satisfies χ = 2 − 2g − b with a whole genus g ≥ 0.
fn assert_euler_consistent(mesh: &Mesh) {
    for c in mesh.components() {
        let twice_genus = 2 - c.euler_characteristic - c.boundary_loops as i64;
        assert!(twice_genus >= 0 && twice_genus % 2 == 0, "{c:?}");
    }
}

/// Fraction of the area whose face normal points toward decreasing f (`gradient`).
fn area_facing_down(mesh: &Mesh, gradient: impl Fn(Point) -> Vector) -> f64 {
    let facing: f64 = mesh
        .faces()
        .filter(|&f| {
            let [a, b, c] = mesh.face_points(f);
            let centroid = Point::from((a.coords + b.coords + c.coords) / 3.0);
            mesh.face_normal(f).dot(&gradient(centroid)) < 0.0
        })
        .map(|f| mesh.face_area(f))
        .sum();
    facing / area(mesh)
}

/// The position of vertex source `source` recomputed from the grid.
fn source_position(volume: &Volume, source: VertexSource) -> Option<Point> {
    let dims = volume.dims();
    let VertexSource::Edge { point, axis, t } = source else {
        return None;
    };
    let at = point as usize;
    let mut index = [
        at % dims[0],
        (at / dims[0]) % dims[1],
        at / (dims[0] * dims[1]),
    ]
    .map(|x| x as f64);
    index[axis as usize] += t;
    Some(volume.index_to_world(index))
}

#[test]
fn sphere_is_closed_genus_zero_with_accurate_area_and_outward_normals() {
    let (centre, radius) = (Point::new(24.3, 23.7, 24.1), 20.0);
    let volume = cube(49, ball(centre, radius));
    let (iso, mesh) = surface(&volume, 0.0);
    let mesh = &mesh;
    assert_closed_away_from_border(&iso, &volume);
    assert!(mesh.boundary_loops().is_empty());
    assert_eq!(mesh.components().len(), 1);
    assert_eq!(mesh.euler_characteristic(), 2);

    let (exact_area, exact_volume) = (4.0 * PI * radius.powi(2), 4.0 / 3.0 * PI * radius.powi(3));
    let area_error = (area(mesh) - exact_area).abs() / exact_area;
    assert!(area_error < 0.01, "area off by {area_error}");
    let volume_error = (signed_volume(mesh) - exact_volume).abs() / exact_volume;
    assert!(volume_error < 0.01, "volume off by {volume_error}");
    // Crossings lie on the sphere up to the interpolation error (h²/8r), polygon
    // centres a little inside it.
    for (p, source) in mesh.positions().iter().zip(iso.sources()) {
        let off = ((p - centre).norm() - radius).abs();
        let tolerance = match source {
            VertexSource::Edge { .. } => 0.01,
            VertexSource::Cell { .. } => 0.1,
        };
        assert!(off < tolerance, "{source:?} is {off} off the sphere");
    }
    // Every face normal points out, toward decreasing f.
    assert_eq!(area_facing_down(mesh, |p| centre - p), 1.0);
}

#[test]
fn vertex_sources_give_back_the_positions() {
    let volume = cube(20, ball(Point::new(9.6, 10.2, 9.9), 6.5));
    let (iso, mesh) = surface(&volume, 0.0);
    assert_eq!(iso.sources().len(), mesh.vertex_count());
    let mut centres = 0;
    for (v, source) in iso.sources().enumerate() {
        match source_position(&volume, source) {
            Some(p) => assert!((p - mesh.positions()[v]).norm() < 1e-12),
            None => centres += 1,
        }
        if let VertexSource::Edge { t, .. } = source {
            assert!(t > 0.0 && t < 1.0);
        }
    }
    assert!(
        centres > 0,
        "a sphere has polygons of more than three corners"
    );
    // A centre is the mean of its neighbours: the corners of its polygon, which
    // lie on the edges of its cell.
    let n = volume.dims()[0] as u64;
    for v in mesh.vertices() {
        let VertexSource::Cell { cell } = iso.source(v.idx()) else {
            continue;
        };
        let corners: Vec<_> = mesh.neighbors(v).collect();
        let mean = corners
            .iter()
            .map(|&u| mesh.position(u).coords)
            .sum::<Vector>()
            / corners.len() as f64;
        assert!((mean - mesh.position(v).coords).norm() < 1e-9);
        for u in corners {
            let VertexSource::Edge { point, .. } = iso.source(u.idx()) else {
                panic!("a centre next to a centre");
            };
            let d = point.wrapping_sub(cell);
            assert!([0, 1, n, n + 1, n * n, n * n + 1, n * n + n].contains(&d));
        }
    }
}

#[test]
fn torus_has_euler_characteristic_zero() {
    let (major, minor) = (14.0, 5.5);
    let centre = Point::new(20.2, 19.9, 15.1);
    let volume = cube(41, |p| {
        let q = p - centre;
        let ring = (q.x.hypot(q.y) - major).hypot(q.z);
        minor - ring
    });
    let (iso, mesh) = surface(&volume, 0.0);
    let mesh = &mesh;
    assert_closed_away_from_border(&iso, &volume);
    assert!(mesh.boundary_loops().is_empty());
    assert_eq!(mesh.components().len(), 1);
    assert_eq!(mesh.euler_characteristic(), 0);
    let exact_area = 4.0 * PI * PI * major * minor;
    assert!((area(mesh) - exact_area).abs() / exact_area < 0.01);
    assert!(signed_volume(mesh) > 0.0);
}

/// The gyroid sin x cos y + sin y cos z + sin z cos x with period `period`.
fn gyroid(period: f64) -> impl Fn(Point) -> f64 {
    let w = 2.0 * PI / period;
    move |p| {
        let (x, y, z) = (w * p.x, w * p.y, w * p.z);
        x.sin() * y.cos() + y.sin() * z.cos() + z.sin() * x.cos()
    }
}

#[test]
fn the_clipped_gyroid_padded_outside_the_surface_is_watertight() {
    let volume = cube(37, gyroid(16.0));
    let padded = volume.padded(-10.0).unwrap();
    assert_eq!(padded.dims(), [39, 39, 39]);
    // The padding is around the grid, which stays where it was.
    assert!((padded.index_to_world([1.0; 3]) - volume.index_to_world([0.0; 3])).norm() < 1e-12);
    assert_eq!(padded.value(1, 1, 1), volume.value(0, 0, 0));
    assert_eq!(padded.value(0, 5, 5), Some(-10.0));
    let (_, open) = surface(&volume, 0.3);
    let (_, closed) = surface(&padded, 0.3);
    assert!(!open.boundary_loops().is_empty());
    assert!(closed.boundary_loops().is_empty(), "closed by the caps");
    assert!(closed.face_count() > open.face_count());
    assert_euler_consistent(&closed);
}

#[test]
fn padding_in_place_puts_every_sample_one_step_in_and_the_value_around() {
    let dims = [5, 3, 4];
    let samples: Vec<f32> = (0..60).map(|n| n as f32).collect();
    let volume = from_samples(dims, samples);
    let copied = volume.padded(-1.0).unwrap();
    let padded = volume.clone().into_padded(-1.0).unwrap();
    assert_eq!(padded.dims(), [7, 5, 6]);
    assert_eq!(padded.samples(), copied.samples());
    assert_eq!(padded.origin(), copied.origin());
    for k in 0..6 {
        for j in 0..5 {
            for i in 0..7 {
                let inner = (1..=dims[0]).contains(&i)
                    && (1..=dims[1]).contains(&j)
                    && (1..=dims[2]).contains(&k);
                let want = if inner {
                    volume.value(i - 1, j - 1, k - 1)
                } else {
                    Some(-1.0)
                };
                assert_eq!(padded.value(i, j, k), want, "sample ({i}, {j}, {k})");
            }
        }
    }
}

#[test]
fn clipped_gyroid_is_open_only_at_the_volume_border() {
    let volume = cube(37, gyroid(16.0));
    let (iso, mesh) = surface(&volume, 0.3);
    let mesh = &mesh;
    assert_closed_away_from_border(&iso, &volume);
    assert!(!mesh.boundary_loops().is_empty());
    for boundary in mesh.boundary_loops() {
        for h in boundary {
            assert!(on_border(&iso, &volume, mesh.target(h).0));
        }
    }
    assert_euler_consistent(mesh);
    let w = 2.0 * PI / 16.0;
    let gradient = |p: Point| {
        let (x, y, z) = (w * p.x, w * p.y, w * p.z);
        Vector::new(
            x.cos() * y.cos() - z.sin() * x.sin(),
            -x.sin() * y.sin() + y.cos() * z.cos(),
            -y.sin() * z.sin() + z.cos() * x.cos(),
        )
    };
    assert!(area_facing_down(mesh, gradient) > 0.999);
}

/// The number of faces of the grid whose inside corners (f ≥ level) are on one
/// diagonal.
fn ambiguous_faces(volume: &Volume, level: f64) -> usize {
    let [nx, ny, nz] = volume.dims();
    let inside = |i: usize, j: usize, k: usize| f64::from(volume.value(i, j, k).unwrap()) >= level;
    let mut count = 0;
    for k in 0..nz {
        for j in 0..ny {
            for i in 0..nx {
                let steps = [[1, 0, 0], [0, 1, 0], [0, 0, 1]];
                for (a, b) in [(0, 1), (1, 2), (0, 2)] {
                    let [u, v] = [steps[a], steps[b]];
                    let corner = |du: usize, dv: usize| {
                        let p = [0, 1, 2].map(|x| [i, j, k][x] + du * u[x] + dv * v[x]);
                        (p[0] < nx && p[1] < ny && p[2] < nz).then(|| inside(p[0], p[1], p[2]))
                    };
                    if let (Some(s00), Some(s10), Some(s11), Some(s01)) =
                        (corner(0, 0), corner(1, 0), corner(1, 1), corner(0, 1))
                    {
                        count += usize::from(s00 == s11 && s10 == s01 && s00 != s10);
                    }
                }
            }
        }
    }
    count
}

#[test]
fn two_touching_spheres_stay_a_manifold_at_the_contact() {
    // The spheres touch where their fields are equal; around the contact the
    // inside corners of many faces sit on a diagonal.
    let (a, b) = (Point::new(11.3, 11.6, 12.2), Point::new(22.7, 22.4, 12.2));
    let radius = (b - a).norm() / 2.0;
    let (first, second) = (ball(a, radius), ball(b, radius));
    let volume = cube(35, |p| first(p).max(second(p)));
    for level in [-0.3, 0.0, 0.3] {
        let (iso, mesh) = surface(&volume, level);
        assert_closed_away_from_border(&iso, &volume);
        assert!(mesh.boundary_loops().is_empty());
        assert_euler_consistent(&mesh);
        assert!(signed_volume(&mesh) > 0.0);
    }
    // Joined below the contact level, apart above it.
    let (_, joined) = surface(&volume, -0.5);
    assert_eq!(joined.components().len(), 1);
    let (_, apart) = surface(&volume, 0.5);
    assert_eq!(apart.components().len(), 2);
    assert_eq!(apart.euler_characteristic(), 4);
}

#[test]
fn an_ambiguous_face_between_two_cells_is_decided_alike_by_both() {
    // Two cells stacked along z share the face z = 1, whose inside corners (value
    // 1) sit on a diagonal. Either decision must give a manifold that is closed
    // across the shared face.
    // With inside corners at 1 and outside ones at -o, v̂ = (1 - o²) / (2 + 2o).
    for saddle_inside in [false, true] {
        let low = if saddle_inside { -0.5 } else { -3.0 };
        let mut samples = vec![-1.0f32; 12];
        samples[4] = 1.0; // (0, 0, 1)
        samples[7] = 1.0; // (1, 1, 1)
        samples[5] = low; // (1, 0, 1)
        samples[6] = low; // (0, 1, 1)
        let volume = from_samples([2, 2, 3], samples);
        assert_eq!(ambiguous_faces(&volume, 0.0), 1);
        let (iso, mesh) = surface(&volume, 0.0);
        assert_closed_away_from_border(&iso, &volume);
        // Joined inside corners make one component, separate ones two.
        let expected = if saddle_inside { 1 } else { 2 };
        assert_eq!(mesh.components().len(), expected, "v̂ ≥ I: {saddle_inside}");
    }
}

/// A volume of `n³` uniform random samples in `[-1, 1]`, or in `{-1, 0, 1}`.
fn noise(n: usize, seed: u64, integers: bool) -> Volume {
    let mut rng = StdRng::seed_from_u64(seed);
    let samples = (0..n * n * n)
        .map(|_| {
            if integers {
                rng.random_range(-1..=1) as f32
            } else {
                rng.random_range(-1.0..=1.0)
            }
        })
        .collect();
    from_samples([n; 3], samples)
}

#[test]
fn random_noise_gives_a_manifold_closed_away_from_the_border() {
    for seed in 0..6 {
        let volume = noise(18, seed, false);
        assert!(ambiguous_faces(&volume, 0.0) > 1000);
        for level in [0.0, 0.37] {
            let (iso, mesh) = surface(&volume, level);
            assert_closed_away_from_border(&iso, &volume);
            assert_euler_consistent(&mesh);
        }
    }
}

#[test]
fn samples_equal_to_the_level_give_distinct_vertices_and_a_clean_manifold() {
    // Integer samples at an integer level: many crossings sit exactly on a sample,
    // and whole faces and cells are equal to the level.
    for seed in 0..4 {
        let volume = noise(16, seed, true);
        for level in [0.0, 1.0] {
            let (iso, mesh) = surface(&volume, level);
            assert_closed_away_from_border(&iso, &volume);
            assert_euler_consistent(&mesh);
        }
    }
    // A cube of samples equal to the level in a field below it: a closed box.
    let volume = cube(8, |p| {
        let inside =
            (2.0..=5.0).contains(&p.x) && (2.0..=5.0).contains(&p.y) && (2.0..=5.0).contains(&p.z);
        if inside {
            1.0
        } else {
            0.0
        }
    });
    let (iso, mesh) = surface(&volume, 1.0);
    assert_closed_away_from_border(&iso, &volume);
    assert!(mesh.boundary_loops().is_empty());
    assert_eq!(mesh.euler_characteristic(), 2);
    let enclosed = signed_volume(&mesh);
    assert!((enclosed - 27.0).abs() < 0.01, "{enclosed}");
}

#[test]
fn a_cavity_keeps_its_normals_toward_decreasing_f() {
    // A hollow ball: the inner surface bounds a cavity and faces into it.
    let centre = Point::new(12.1, 11.8, 12.3);
    let volume = cube(25, |p| {
        let r = (p - centre).norm();
        (10.0 - r).min(r - 5.0)
    });
    let (iso, mesh) = surface(&volume, 0.0);
    assert_closed_away_from_border(&iso, &volume);
    assert_eq!(mesh.components().len(), 2);
    let exact = 4.0 / 3.0 * PI * (1000.0 - 125.0);
    assert!((signed_volume(&mesh) - exact).abs() / exact < 0.02);
    let gradient = |p: Point| {
        let q = p - centre;
        if q.norm() > 7.5 {
            -q
        } else {
            q
        }
    };
    assert_eq!(area_facing_down(&mesh, gradient), 1.0);
}

#[test]
fn anisotropic_and_mirrored_grids_keep_normals_pointing_out() {
    let (centre, radius) = (Point::new(1.3, -0.7, 2.1), 9.0);
    let spacing = [0.5, 0.8, 1.3];
    let dims = [45, 29, 19];
    // Index axes mapped to (-y, x, z) and to a reflection (x, -y, z), and a
    // reflection with a rotation.
    let rotation = Matrix3::new(0.0, 1.0, 0.0, -1.0, 0.0, 0.0, 0.0, 0.0, 1.0);
    let mirror = Matrix3::from_diagonal(&Vector::new(1.0, -1.0, 1.0));
    let c = (0.3f64).cos();
    let s = (0.3f64).sin();
    let tilted = Matrix3::new(c, s, 0.0, -s, c, 0.0, 0.0, 0.0, -1.0);
    for direction in [Matrix3::identity(), rotation, mirror, tilted] {
        // Place the grid so that it is centred on the sphere.
        let half = Vector::from(std::array::from_fn(|a| {
            spacing[a] * (dims[a] - 1) as f64 / 2.0
        }));
        let origin = centre - direction * half;
        let volume = sampled(
            dims,
            spacing,
            origin.coords.into(),
            direction,
            ball(centre, radius),
        );
        let (iso, mesh) = surface(&volume, 0.0);
        let mesh = &mesh;
        assert_closed_away_from_border(&iso, &volume);
        assert!(mesh.boundary_loops().is_empty());
        assert_eq!(mesh.euler_characteristic(), 2);
        assert_eq!(area_facing_down(mesh, |p| centre - p), 1.0, "{direction}");
        let exact = 4.0 / 3.0 * PI * radius.powi(3);
        let error = (signed_volume(mesh) - exact).abs() / exact;
        assert!(error < 0.01, "volume off by {error} for {direction}");
    }
}

#[test]
fn output_does_not_depend_on_the_number_of_threads() {
    let volume = cube(40, gyroid(13.0));
    let run = |threads| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| isosurface(&volume, 0.1).unwrap())
    };
    let (one, three) = (run(1), run(3));
    assert_eq!(one.soup(), three.soup());
    assert!(one.sources().eq(three.sources()));
}

#[test]
fn non_finite_samples_are_an_error_naming_the_voxel() {
    let mut samples: Vec<f32> = (0..6 * 5 * 4).map(|v| v as f32).collect();
    samples[3 + 6 * (2 + 5)] = f32::NAN;
    let message = isosurface(&from_samples([6, 5, 4], samples.clone()), 10.0)
        .unwrap_err()
        .to_string();
    assert!(
        message.contains("voxel (3, 2, 1)") && message.contains("NaN"),
        "{message}"
    );
    samples[3 + 6 * (2 + 5)] = f32::INFINITY;
    let message = isosurface(&from_samples([6, 5, 4], samples), 10.0)
        .unwrap_err()
        .to_string();
    assert!(message.contains("voxel (3, 2, 1)"), "{message}");
}

#[test]
fn no_crossing_bad_level_or_flat_volume_is_a_clear_error() {
    let volume = cube(6, ball(Point::new(2.5, 2.5, 2.5), 2.0));
    let message = isosurface(&volume, 5.0).unwrap_err().to_string();
    assert!(message.contains("no isosurface at level 5"), "{message}");
    assert!(isosurface(&volume, f64::NAN).is_err());
    let flat = from_samples([4, 4, 1], (0..16).map(|v| v as f32).collect());
    let message = isosurface(&flat, 7.5).unwrap_err().to_string();
    assert!(message.contains("at least 2 samples"), "{message}");
}

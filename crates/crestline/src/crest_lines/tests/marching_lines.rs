//! Marching Lines (Thirion & Gourdon 1993, §4): bi-iso-lines of two sampled
//! fields are closed except at the volume border and where the second field is
//! undefined, lie where both fields cross their levels, follow the bi-iso-line
//! orientation convention and do not depend on the number of threads; crest
//! lines (§5) of an ellipsoid are its largest principal ellipse.

use std::f64::consts::PI;

use crate::crest_lines::marching_lines::{
    bi_iso_lines, seeded_marching_lines, BiIsoLine, SampledField,
};
use crate::crest_lines::Sweep;
use crate::crest_lines::{
    crest_lines, iso_gaussian_lines, parabolic_lines, trace, LineFamily, LineTracing,
};
use crate::lines::LineKind;
use crate::volume::Volume;
use crate::Point;
use nalgebra::Matrix3;

use crate::common;

/// A unit-spaced volume of `n³` samples centred on the origin, with the samples of
/// `f` and of `g` (world functions).
fn fields(n: usize, f: impl Fn(Point) -> f64, g: impl Fn(Point) -> f64) -> (Volume, Vec<f32>) {
    let half = (n as f64 - 1.0) / 2.0;
    let origin = [-half; 3];
    let count = n * n * n;
    let grid = Volume::new(
        [n; 3],
        [1.0; 3],
        origin,
        Matrix3::identity(),
        vec![0.0; count],
    );
    let grid = grid.unwrap();
    let positions: Vec<Point> = (0..count)
        .map(|at| grid.index_to_world([at % n, (at / n) % n, at / (n * n)].map(|x| x as f64)))
        .collect();
    let f = positions.iter().map(|&p| f(p) as f32).collect();
    let g = positions.iter().map(|&p| g(p) as f32).collect();
    (grid.with_samples(f).unwrap(), g)
}

/// Signed distance to a sphere of radius `r` about the origin, positive inside.
fn ball(r: f64) -> impl Fn(Point) -> f64 {
    move |p| r - p.coords.norm()
}

/// The length of a line, closing it if it is a loop.
fn length(line: &BiIsoLine) -> f64 {
    let n = line.points.len();
    let pairs = if line.closed { n } else { n - 1 };
    (0..pairs)
        .map(|i| (line.points[(i + 1) % n] - line.points[i]).norm())
        .sum()
}

/// Twice the area a loop encloses, projected on the xy plane (positive when it runs
/// counter-clockwise seen from +z).
fn xy_area(line: &BiIsoLine) -> f64 {
    let n = line.points.len();
    (0..n)
        .map(|i| {
            let (a, b) = (line.points[i], line.points[(i + 1) % n]);
            a.x * b.y - a.y * b.x
        })
        .sum()
}

#[test]
fn a_sphere_cut_by_a_plane_is_one_closed_circle() {
    let r = 15.0;
    let (volume, g) = fields(40, ball(r), |p| p.z);
    let lines = bi_iso_lines(&volume, 0.0, &g, 0.0).unwrap();
    assert_eq!(lines.len(), 1);
    let circle = &lines[0];
    assert!(circle.closed);
    let worst = circle
        .points
        .iter()
        .map(|p| (p.coords.norm() - r).abs() / r)
        .fold(0.0, f64::max);
    let height = circle.points.iter().map(|p| p.z.abs()).fold(0.0, f64::max);
    let error = (length(circle) - 2.0 * PI * r).abs() / (2.0 * PI * r);
    println!(
        "circle: {} points, radius error {worst:.2e}, |z| ≤ {height:.1e}, length error {error:.2e}",
        circle.points.len()
    );
    assert!(worst < 0.005, "radius error {worst}");
    assert!(height < 1e-6, "off the plane by {height}");
    assert!(error < 0.01, "length error {error}");
}

#[test]
fn lines_keep_the_positive_side_of_g_on_their_left_seen_from_outside() {
    // Outside the ball (f < I), g = z ≥ 0 on the left: the equator runs
    // counter-clockwise seen from +z. Negating g reverses it.
    let (volume, g) = fields(24, ball(8.0), |p| p.z);
    let up = bi_iso_lines(&volume, 0.0, &g, 0.0).unwrap();
    let negated: Vec<f32> = g.iter().map(|v| -v).collect();
    let down = bi_iso_lines(&volume, 0.0, &negated, 0.0).unwrap();
    assert!(xy_area(&up[0]) > 0.0);
    assert!(xy_area(&down[0]) < 0.0);
}

#[test]
fn a_mirrored_grid_keeps_the_orientation_in_the_world() {
    // The same ball and plane on a grid whose x axis runs backwards.
    let n = 24;
    let mirror = Matrix3::from_diagonal(&nalgebra::Vector3::new(-1.0, 1.0, 1.0));
    let half = (n as f64 - 1.0) / 2.0;
    let grid = Volume::new(
        [n; 3],
        [1.0; 3],
        [half, -half, -half],
        mirror,
        vec![0.0; n * n * n],
    );
    let grid = grid.unwrap();
    let positions: Vec<Point> = (0..n * n * n)
        .map(|at| grid.index_to_world([at % n, (at / n) % n, at / (n * n)].map(|x| x as f64)))
        .collect();
    let f = positions.iter().map(|&p| ball(8.0)(p) as f32).collect();
    let g: Vec<f32> = positions.iter().map(|p| p.z as f32).collect();
    let lines = bi_iso_lines(&grid.with_samples(f).unwrap(), 0.0, &g, 0.0).unwrap();
    assert_eq!(lines.len(), 1);
    assert!(xy_area(&lines[0]) > 0.0);
}

#[test]
fn two_planes_meet_in_a_straight_open_line_ending_at_the_border() {
    let (volume, g) = fields(16, |p| 0.3 - p.x, |p| p.y - 0.2);
    let lines = bi_iso_lines(&volume, 0.0, &g, 0.0).unwrap();
    assert_eq!(lines.len(), 1);
    let line = &lines[0];
    assert!(!line.closed);
    let off = line
        .points
        .iter()
        .map(|p| (p.x - 0.3).abs().max((p.y - 0.2).abs()))
        .fold(0.0, f64::max);
    assert!(off < 1e-5, "off the line by {off}");
    let ends = [line.points[0].z, line.points[line.points.len() - 1].z];
    let span = ends[0].min(ends[1])..=ends[0].max(ends[1]);
    println!(
        "line: {} points, off by {off:.1e}, ends {ends:?}",
        line.points.len()
    );
    assert!(*span.start() <= -7.0 && *span.end() >= 7.0, "ends {ends:?}");
}

#[test]
fn a_torus_cut_through_its_middle_gives_two_circles() {
    let (big, small) = (10.0, 3.5);
    let torus = move |p: Point| small - ((p.x.hypot(p.y) - big).powi(2) + p.z * p.z).sqrt();
    let (volume, g) = fields(36, torus, |p| p.z);
    let lines = bi_iso_lines(&volume, 0.0, &g, 0.0).unwrap();
    assert_eq!(lines.len(), 2);
    let mut radii: Vec<f64> = lines
        .iter()
        .map(|line| {
            assert!(line.closed);
            let n = line.points.len() as f64;
            line.points.iter().map(|p| p.coords.norm()).sum::<f64>() / n
        })
        .collect();
    radii.sort_by(f64::total_cmp);
    println!("torus circles: mean radii {radii:?}");
    assert!((radii[0] - (big - small)).abs() < 0.05);
    assert!((radii[1] - (big + small)).abs() < 0.05);
    // Both run with z ≥ 0 on their left seen from outside the tube: the outer
    // circle counter-clockwise seen from +z, the inner one clockwise.
    let areas: Vec<f64> = lines.iter().map(xy_area).collect();
    assert!(areas.iter().any(|&a| a > 0.0) && areas.iter().any(|&a| a < 0.0));
}

#[test]
fn lines_end_where_g_is_undefined() {
    let (volume, g) = fields(30, ball(11.0), |p| if p.x > 0.0 { f64::NAN } else { p.z });
    let lines = bi_iso_lines(&volume, 0.0, &g, 0.0).unwrap();
    assert_eq!(lines.len(), 1);
    let line = &lines[0];
    assert!(!line.closed);
    let rightmost = line.points.iter().map(|p| p.x).fold(f64::MIN, f64::max);
    let ends = [line.points[0], line.points[line.points.len() - 1]];
    println!("half circle: {} points, x ≤ {rightmost}", line.points.len());
    assert!(rightmost <= 0.0);
    assert!(
        ends.iter().all(|p| p.x > -1.5 && p.y.abs() > 9.0),
        "ends {ends:?}"
    );
}

#[test]
fn the_lines_do_not_depend_on_the_number_of_threads() {
    let (volume, g) = fields(
        44,
        |p| 12.0 - p.coords.norm() + 0.8 * (p.x * 0.7).sin(),
        |p| p.z + 2.0 * (p.x * 0.5).cos() * (p.y * 0.4).sin(),
    );
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| bi_iso_lines(&volume, 0.0, &g, 0.0).unwrap())
    };
    let one = run(1);
    assert!(!one.is_empty());
    assert_eq!(one, run(3));
    assert_eq!(one, run(4));
}

#[test]
fn bad_input_is_an_error() {
    let (volume, g) = fields(8, ball(2.0), |p| p.z);
    assert!(bi_iso_lines(&volume, 0.0, &g[1..], 0.0).is_err());
    assert!(bi_iso_lines(&volume, f64::NAN, &g, 0.0).is_err());
    assert!(bi_iso_lines(&volume, 0.0, &g, f64::INFINITY).is_err());
    assert!(bi_iso_lines(&volume, 100.0, &g, 0.0).unwrap().is_empty());
}

/// A volume of `dims` unit-spaced samples of `f`, centred on the origin.
fn centred(dims: [usize; 3], f: impl Fn(Point) -> f64) -> Volume {
    let origin = dims.map(|n| -(n as f64 - 1.0) / 2.0);
    let count = dims.iter().product();
    let grid = Volume::new(
        dims,
        [1.0; 3],
        origin,
        Matrix3::identity(),
        vec![0.0; count],
    );
    let grid = grid.unwrap();
    let samples = samples_of(&grid, f);
    grid.with_samples(samples).unwrap()
}

/// The samples of `f` at the grid points of `grid`.
fn samples_of(grid: &Volume, f: impl Fn(Point) -> f64) -> Vec<f32> {
    let [nx, ny, _] = grid.dims();
    (0..grid.len())
        .map(|at| {
            let index = [at % nx, (at / nx) % ny, at / (nx * ny)];
            f(grid.index_to_world(index.map(|x| x as f64))) as f32
        })
        .collect()
}

/// The fraction of the angles around the z axis (in bins of half a degree) that
/// segments of `lines` span.
fn angular_coverage(lines: &[&crate::lines::Polyline]) -> f64 {
    const BINS: usize = 720;
    let bin = |p: &Point| {
        let turn = p.y.atan2(p.x) / (2.0 * PI) + 1.0;
        ((turn * BINS as f64) as usize) % BINS
    };
    let mut covered = [false; BINS];
    for line in lines {
        let n = line.points.len();
        let pairs = if line.closed { n } else { n - 1 };
        for i in 0..pairs {
            let (a, b) = (bin(&line.points[i]), bin(&line.points[(i + 1) % n]));
            let (low, high) = (a.min(b), a.max(b));
            // The short way round between the two bins.
            if high - low <= BINS / 2 {
                covered[low..=high].iter_mut().for_each(|c| *c = true);
            } else {
                covered[high..].iter_mut().for_each(|c| *c = true);
                covered[..=low].iter_mut().for_each(|c| *c = true);
            }
        }
    }
    covered.iter().filter(|&&c| c).count() as f64 / BINS as f64
}

/// The crest lines of kind `kind` of the ellipsoid image `sign · (x²/a² + y²/b² +
/// z²/c²)` at level `sign` on a grid of `dims`, σ = 1.5 voxels: they are one
/// closed line in the plane of the two longest axes, around all of it; the lines
/// of the other kind are none.
fn check_ellipsoid_crests(dims: [usize; 3], sign: f64, kind: LineKind) {
    let (a, b, c) = (16.0, 11.0, 7.0);
    let ellipsoid =
        move |p: Point| sign * ((p.x / a).powi(2) + (p.y / b).powi(2) + (p.z / c).powi(2));
    let volume = centred(dims, ellipsoid);
    let lines = crest_lines(&volume, sign, 1.5).unwrap();
    let crests: Vec<_> = lines.iter().filter(|l| l.kind == kind).collect();
    let points: Vec<Point> = crests.iter().flat_map(|l| l.points.clone()).collect();
    assert!(!points.is_empty());
    let mean = points.iter().map(|p| p.z.abs()).sum::<f64>() / points.len() as f64;
    let worst = points.iter().map(|p| p.z.abs()).fold(0.0, f64::max);
    let coverage = angular_coverage(&crests);
    let others = lines.len() - crests.len();
    assert!(crests.len() == 1 && crests[0].closed, "not one closed line");
    println!(
        "ellipsoid {dims:?}, {kind:?}: {} lines ({} closed), {} points, mean |z| {mean:.2e} \
         ({:.2e} of a), max |z| {worst:.2e}, coverage {coverage:.3}, {others} other lines",
        crests.len(),
        crests.iter().filter(|l| l.closed).count(),
        points.len(),
        mean / a
    );
    assert!(mean < 0.005 * a, "mean distance to the plane {mean}");
    // Minima of k_max (on the other principal ellipses) are not ridges.
    assert!(worst < 1.0, "a point {worst} off the plane");
    assert!(coverage >= 0.95, "coverage {coverage}");
    assert_eq!(others, 0, "lines of the other kind");
}

#[test]
fn the_ridges_of_an_ellipsoid_are_its_largest_principal_ellipse() {
    // The plane z = 0 through grid points (extremality exactly zero there) or
    // between them.
    check_ellipsoid_crests([49, 39, 31], -1.0, LineKind::Ridge);
    check_ellipsoid_crests([48, 38, 30], -1.0, LineKind::Ridge);
}

#[test]
fn crest_lines_scale_with_the_image() {
    // The same ellipsoid sampled with voxels twice as large in world units, σ
    // doubled: the same lines, twice as large.
    let (a, b, c) = (16.0, 11.0, 7.0);
    let ellipsoid = move |p: Point| -((p.x / a).powi(2) + (p.y / b).powi(2) + (p.z / c).powi(2));
    let small = centred([48, 38, 30], ellipsoid);
    let doubled = move |p: Point| ellipsoid(p / 2.0);
    let large = Volume::new(
        small.dims(),
        [2.0; 3],
        small.origin().map(|x| 2.0 * x),
        Matrix3::identity(),
        small.samples().to_vec(),
    )
    .unwrap();
    let large = large.with_samples(samples_of(&large, doubled)).unwrap();
    let unit = crest_lines(&small, -1.0, 1.5).unwrap();
    let twice = crest_lines(&large, -1.0, 3.0).unwrap();
    assert_eq!(unit.len(), twice.len());
    for (u, t) in unit.iter().zip(&twice) {
        assert_eq!(u.points.len(), t.points.len());
        let worst = u
            .points
            .iter()
            .zip(&t.points)
            .map(|(p, q)| (p.coords * 2.0 - q.coords).norm())
            .fold(0.0, f64::max);
        assert!(worst < 1e-3, "points differ by {worst}");
        assert!((u.strength - t.strength).abs() < 1e-3 * u.strength);
    }
}

#[test]
fn the_crests_of_a_dark_ellipsoid_are_valleys() {
    check_ellipsoid_crests([49, 39, 31], 1.0, LineKind::Valley);
}

#[test]
fn the_parabolic_lines_of_a_torus_are_its_top_and_bottom_circles() {
    let (big, small) = (10.0, 4.0);
    let torus = move |p: Point| small - ((p.x.hypot(p.y) - big).powi(2) + p.z * p.z).sqrt();
    let volume = centred([40, 40, 20], torus);
    let lines = parabolic_lines(&volume, 0.0, 1.0).unwrap();
    assert_eq!(lines.len(), 2);
    for line in &lines {
        assert!(line.closed);
        assert_eq!(line.kind, LineKind::Parabolic);
        let n = line.points.len() as f64;
        let radius = line.points.iter().map(|p| p.x.hypot(p.y)).sum::<f64>() / n;
        let height = line.points.iter().map(|p| p.z.abs()).sum::<f64>() / n;
        let spread = line
            .points
            .iter()
            .map(|p| {
                (p.x.hypot(p.y) - radius)
                    .abs()
                    .max((p.z.abs() - height).abs())
            })
            .fold(0.0, f64::max);
        println!("parabolic circle: radius {radius:.3}, |z| {height:.3}, spread {spread:.3}");
        assert!((radius - big).abs() < 0.3, "radius {radius}");
        assert!((height - small).abs() < 0.3, "height {height}");
        assert!(spread < 0.2, "spread {spread}");
    }
}

#[test]
fn the_iso_gaussian_curves_of_a_torus_are_circles_of_one_latitude() {
    // On the torus of radii R, r the Gaussian curvature at tube angle φ is
    // K = cos φ / (r (R + r cos φ)): K = J on the two circles of cos φ = J r R /
    // (1 − J r²), at distance R + r cos φ from the axis and height ±r sin φ.
    let (big, small) = (10.0, 4.0);
    let torus = move |p: Point| small - ((p.x.hypot(p.y) - big).powi(2) + p.z * p.z).sqrt();
    let volume = centred([40, 40, 20], torus);
    let gauss = 0.01;
    let lines = iso_gaussian_lines(&volume, 0.0, 1.0, gauss).unwrap();
    let cos = gauss * small * big / (1.0 - gauss * small * small);
    let (radius, height) = (big + small * cos, small * (1.0 - cos * cos).sqrt());
    assert_eq!(lines.len(), 2);
    for line in &lines {
        assert!(line.closed);
        assert_eq!(line.kind, LineKind::Gauss);
        // The curvatures each point carries give K = J there.
        let (k_max, k_min) = (&line.values["k_max"], &line.values["k_min"]);
        assert_eq!(k_max.len(), line.points.len());
        let worst = k_max
            .iter()
            .zip(k_min)
            .map(|(a, b)| (a * b - gauss).abs())
            .fold(0.0, f64::max);
        assert!(worst < 0.1 * gauss, "K differs from J by {worst}");
        let n = line.points.len() as f64;
        let r = line.points.iter().map(|p| p.x.hypot(p.y)).sum::<f64>() / n;
        let z = line.points.iter().map(|p| p.z.abs()).sum::<f64>() / n;
        println!("iso-Gaussian circle: radius {r:.3} (exact {radius:.3}), |z| {z:.3} (exact {height:.3})");
        assert!((r - radius).abs() < 0.3, "radius {r}, exact {radius}");
        assert!((z - height).abs() < 0.3, "height {z}, exact {height}");
    }
}

/// A smooth random field: a sum of Gaussian bumps of both signs, from a seed.
fn random_smooth(seed: u64) -> impl Fn(Point) -> f64 {
    let mut state = seed;
    let mut next = move || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((state >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    };
    let bumps: Vec<(Point, f64, f64)> = (0..40)
        .map(|_| {
            let centre = Point::new(9.0 * next(), 9.0 * next(), 9.0 * next());
            (centre, next(), 2.0 + 2.0 * next().abs())
        })
        .collect();
    move |p: Point| {
        bumps
            .iter()
            .map(|(c, a, w)| a * (-(p - c).norm_squared() / (w * w)).exp())
            .sum()
    }
}

/// Two independent random smooth fields on a grid of `dims`: f and g.
fn random_pair(dims: [usize; 3], seed: u64) -> (Volume, Volume) {
    (
        centred(dims, random_smooth(seed)),
        centred(dims, random_smooth(seed + 100)),
    )
}

#[test]
fn bi_iso_lines_of_random_fields_end_only_at_the_border_and_cross_each_face_once() {
    let dims = [22, 20, 18];
    let mut lines_seen = 0;
    for seed in 1..=6 {
        let (f, g_volume) = random_pair(dims, seed);
        let lines = bi_iso_lines(&f, 0.0, g_volume.samples(), 0.0).unwrap();
        let mut keys = std::collections::HashSet::new();
        for line in &lines {
            for key in &line.keys {
                assert!(
                    keys.insert(*key),
                    "seed {seed}: a polygon edge is visited twice"
                );
            }
            if !line.closed {
                // g is defined everywhere: an open line ends in a border cell.
                for end in [line.points[0], *line.points.last().unwrap()] {
                    let index = f.world_to_index(&end);
                    let on_border = (0..3)
                        .any(|a| index[a] <= 1.0 + 1e-9 || index[a] >= (dims[a] - 2) as f64 - 1e-9);
                    assert!(
                        on_border,
                        "seed {seed}: a line ends inside the grid at {index:?}"
                    );
                }
            }
        }
        lines_seen += lines.len();
    }
    assert!(
        lines_seen > 20,
        "{lines_seen} lines: the fields are too tame to test anything"
    );
}

/// The points of a line as a set of keys, for comparing lines whatever their start
/// and direction.
fn key_set(line: &BiIsoLine) -> std::collections::BTreeSet<[u64; 2]> {
    line.keys.iter().copied().collect()
}

#[test]
fn seeded_lines_are_whole_lines_of_the_full_sweep_longest_first() {
    let dims = [22, 20, 18];
    let mut longest_found = 0;
    for seed in 1..=6 {
        let (f, g_volume) = random_pair(dims, seed);
        let g = SampledField::new(&f, g_volume.samples()).unwrap();
        let every = bi_iso_lines(&f, 0.0, g_volume.samples(), 0.0).unwrap();
        let seeded = seeded_marching_lines(&f, 0.0, &g, 0.0, 150, seed).unwrap();
        assert!(!seeded.is_empty(), "seed {seed}: 150 seeds found nothing");
        for line in &seeded {
            let twin = every.iter().find(|l| key_set(l) == key_set(line));
            let twin = twin.unwrap_or_else(|| panic!("seed {seed}: a line not in the full sweep"));
            assert_eq!(twin.closed, line.closed);
            assert_eq!(twin.points.len(), line.points.len());
            assert!((length(twin) - length(line)).abs() < 1e-9);
        }
        let lengths: Vec<f64> = seeded.iter().map(length).collect();
        assert!(
            lengths.windows(2).all(|w| w[0] >= w[1]),
            "not longest first"
        );
        let distinct: std::collections::BTreeSet<_> = seeded.iter().map(key_set).collect();
        assert_eq!(
            distinct.len(),
            seeded.len(),
            "seed {seed}: a line found twice"
        );
        let longest = every.iter().map(length).fold(0.0, f64::max);
        longest_found += usize::from(lengths[0] == longest);
        // The same seed draws the same cells.
        assert_eq!(
            seeded,
            seeded_marching_lines(&f, 0.0, &g, 0.0, 150, seed).unwrap()
        );
    }
    // A line is found with a probability that grows with its length: the longest
    // line of the full sweep is among the first found in most fields.
    assert!(
        longest_found >= 5,
        "the longest line found in {longest_found} of 6 fields"
    );
}

#[test]
fn more_seeds_than_crossed_cells_seed_every_cell_once_and_find_every_line() {
    let (f, g_volume) = random_pair([14, 12, 10], 3);
    let g = SampledField::new(&f, g_volume.samples()).unwrap();
    let every = bi_iso_lines(&f, 0.0, g_volume.samples(), 0.0).unwrap();
    // 2⁶⁴ − 1 seeds would run for ever; the work is bounded by the cells.
    let seeded = seeded_marching_lines(&f, 0.0, &g, 0.0, usize::MAX, 1).unwrap();
    let ours: std::collections::BTreeSet<_> = seeded.iter().map(key_set).collect();
    let theirs: std::collections::BTreeSet<_> = every.iter().map(key_set).collect();
    assert!(theirs.len() > 3);
    assert_eq!(ours, theirs);
}

#[test]
fn a_few_seeds_find_the_crest_of_an_ellipsoid() {
    let (a, b, c) = (16.0, 11.0, 7.0);
    let ellipsoid = move |p: Point| -((p.x / a).powi(2) + (p.y / b).powi(2) + (p.z / c).powi(2));
    let volume = centred([48, 38, 30], ellipsoid);
    let tracing = LineTracing {
        sweep: Sweep::Seeds {
            count: 100,
            rng_seed: 7,
        },
        ..LineTracing::new(-1.0, 1.5)
    };
    let seeded = trace(&volume, &tracing).unwrap();
    let every = crest_lines(&volume, -1.0, 1.5).unwrap();
    // The single ridge loop, point for point (from another start).
    assert_eq!((seeded.len(), every.len()), (1, 1));
    let (line, full) = (&seeded[0], &every[0]);
    assert_eq!((line.kind, line.closed), (full.kind, full.closed));
    assert_eq!(line.points.len(), full.points.len());
    assert!(line.points.iter().all(|p| full.points.contains(p)));
    assert!((line.strength - full.strength).abs() < 1e-9 * full.strength);
    // Each point carries the curvatures of the isosurface; on the ridge k_max is the
    // larger in magnitude, as the kind says.
    assert!(line.values["k_max"]
        .iter()
        .zip(&line.values["k_min"])
        .all(|(k_max, k_min)| *k_max > k_min.abs()));
}

#[test]
fn a_non_finite_gaussian_curvature_is_an_error() {
    let volume = centred([8, 8, 8], ball(2.5));
    let tracing = LineTracing {
        family: LineFamily::Gauss(f64::NAN),
        ..LineTracing::new(0.0, 1.0)
    };
    let error = trace(&volume, &tracing).unwrap_err().to_string();
    assert!(error.contains("not finite"), "{error}");
}

/// Crest lines of a real head's skin, on the full-head T1 template that
/// `tools/fetch_head_template.sh` fetches (skipped when it is absent): the tip of
/// the nose, the most anterior crest point (RAS: largest y), lies on a ridge, the
/// convex kind, and ridges outnumber valleys around it. Swapping the sides of
/// the isosurface or the sign of the curvature would make it a valley.
#[test]
fn the_tip_of_the_nose_is_on_a_ridge_of_the_skin() {
    let path = std::path::Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../data/head/mean_head_t1.nii.gz"
    ));
    if !path.exists() {
        common::skip(&format!(
            "{} is missing (run tools/fetch_head_template.sh to fetch it)",
            path.display()
        ));
        return;
    }
    let volume = crate::io::read_volume(path).unwrap();
    let lines = crest_lines(&volume, 120.0, 1.0).unwrap();
    let points: Vec<(Point, LineKind)> = lines
        .iter()
        .flat_map(|line| line.points.iter().map(|p| (*p, line.kind)))
        .collect();
    let (tip, kind) = points
        .iter()
        .copied()
        .max_by(|a, b| a.0.y.total_cmp(&b.0.y))
        .unwrap();
    assert_eq!(
        kind,
        LineKind::Ridge,
        "the nose tip {tip:?} is on a {kind:?}"
    );
    let around = |k: LineKind| {
        points
            .iter()
            .filter(|(p, kind)| *kind == k && (p - tip).norm() < 10.0)
            .count()
    };
    let (ridges, valleys) = (around(LineKind::Ridge), around(LineKind::Valley));
    assert!(
        ridges > 2 * valleys,
        "{ridges} ridge and {valleys} valley points within 10 mm of the nose tip"
    );
}

#[test]
fn crest_lines_do_not_depend_on_the_world_frame() {
    // One image (an ellipsoid, symmetric about the grid plane z = 0 where its
    // extremalities are exactly zero, made bumpy so that it has many lines, open
    // and closed), placed in the world three ways: as sampled, in LPS (x and y
    // negated, as a DICOM series states what its NIfTI conversion states in RAS),
    // and turned 10° about an oblique axis. The lines are the same in index
    // coordinates, point for point, in the same order and direction.
    let (a, b, c) = (16.0, 11.0, 7.0);
    let image = move |p: Point| {
        let bumps = 0.08 * (0.7 * p.x).sin() * (0.5 * p.y).sin() * (0.6 * p.z).cos();
        -((p.x / a).powi(2) + (p.y / b).powi(2) + (p.z / c).powi(2)) + bumps
    };
    let sampled = centred([49, 39, 31], image);
    let placed = |direction: Matrix3<f64>| {
        let origin = direction * nalgebra::Vector3::from(sampled.origin());
        let volume = Volume::new(
            sampled.dims(),
            sampled.spacing(),
            origin.into(),
            direction,
            sampled.samples().to_vec(),
        );
        volume.unwrap()
    };
    let axis = nalgebra::Unit::new_normalize(nalgebra::Vector3::new(1.0, 2.0, 3.0));
    let turned = nalgebra::Rotation3::from_axis_angle(&axis, 10f64.to_radians());
    let lps = placed(Matrix3::from_diagonal(&nalgebra::Vector3::new(
        -1.0, -1.0, 1.0,
    )));
    let oblique = placed(*turned.matrix());
    let in_index = |volume: &Volume| -> Vec<(LineKind, bool, Vec<[f64; 3]>)> {
        let lines = crest_lines(volume, -1.0, 1.5).unwrap();
        let index = |p: &Point| volume.world_to_index(p);
        let line =
            |l: &crate::lines::Polyline| (l.kind, l.closed, l.points.iter().map(index).collect());
        lines.iter().map(line).collect()
    };
    let expected = in_index(&sampled);
    assert!(expected.len() >= 10, "{} lines", expected.len());
    assert!(expected.iter().any(|l| !l.1) && expected.iter().any(|l| l.1));
    for (name, volume) in [("LPS", &lps), ("oblique", &oblique)] {
        let found = in_index(volume);
        assert_eq!(found.len(), expected.len(), "{name}: line count");
        for (n, (f, e)) in found.iter().zip(&expected).enumerate() {
            assert_eq!(
                (f.0, f.1, f.2.len()),
                (e.0, e.1, e.2.len()),
                "{name}: line {n}"
            );
            let worst =
                f.2.iter()
                    .zip(&e.2)
                    .flat_map(|(p, q)| (0..3).map(move |i| (p[i] - q[i]).abs()));
            let worst = worst.fold(0.0, f64::max);
            assert!(worst < 1e-9, "{name}: line {n} is {worst} voxels off");
        }
    }
}

//! The line families of drawings: borders, creases and suggestive contours, each
//! against a surface where the lines are known in closed form.

use std::f64::consts::{PI, TAU};

use crate::common::mesh_of;
use crate::curvature::{estimate_curvature, ShapeOperator};
use crate::draw::{
    borders, creases, draw, suggestive_contours, Camera, DrawOptions, Projection,
    SuggestiveOptions, View,
};
use crate::lines::{FeatureLines, LineKind};
use crate::mesh::generate::{
    height_field, sphere, torus, HeightFunction, ImplicitSurface, Sampling, Torus,
};
use crate::mesh::Mesh;
use crate::{Point, Vector};
use nalgebra::Matrix3;

/// The unit disk in the plane z = 0: its centre and `rings` rings of `sectors`
/// points each, the outer one on the unit circle.
fn disk(rings: usize, sectors: usize) -> Mesh {
    let mut positions = vec![Point::origin()];
    for ring in 1..=rings {
        let radius = ring as f64 / rings as f64;
        positions.extend((0..sectors).map(|s| {
            let a = TAU * s as f64 / sectors as f64;
            Point::new(radius * a.cos(), radius * a.sin(), 0.0)
        }));
    }
    let at = |ring: usize, s: usize| (1 + (ring - 1) * sectors + s % sectors) as u32;
    let mut triangles = Vec::new();
    for s in 0..sectors {
        triangles.push([0, at(1, s), at(1, s + 1)]);
        for ring in 1..rings {
            let (a, b, c, d) = (
                at(ring, s),
                at(ring + 1, s),
                at(ring + 1, s + 1),
                at(ring, s + 1),
            );
            triangles.push([a, b, c]);
            triangles.push([a, c, d]);
        }
    }
    mesh_of(positions, triangles)
}

/// The cube [−1, 1]³, every face a grid of `n` × `n` squares split in two
/// (points on shared edges are merged when the mesh is built).
fn cube(n: usize) -> Mesh {
    let mut positions = Vec::new();
    let mut triangles = Vec::new();
    for axis in 0..3 {
        for side in [-1.0, 1.0] {
            let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
            let base = positions.len() as u32;
            for i in 0..=n {
                for j in 0..=n {
                    let mut p = Point::origin();
                    p[axis] = side;
                    p[u] = -1.0 + 2.0 * i as f64 / n as f64;
                    p[v] = -1.0 + 2.0 * j as f64 / n as f64;
                    positions.push(p);
                }
            }
            let at = |i: usize, j: usize| base + (i * (n + 1) + j) as u32;
            for i in 0..n {
                for j in 0..n {
                    let (a, b, c, d) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
                    // (u, v, axis) is right-handed: counter-clockwise from outside
                    // on the positive side, clockwise on the negative one.
                    if side > 0.0 {
                        triangles.extend([[a, b, c], [a, c, d]]);
                    } else {
                        triangles.extend([[a, c, b], [a, d, c]]);
                    }
                }
            }
        }
    }
    mesh_of(positions, triangles)
}

fn unit_sphere() -> Mesh {
    sphere(1.0, 4000, Sampling::jittered(3)).unwrap().mesh
}

fn camera(mesh: &Mesh, azimuth: f64, elevation: f64) -> Camera {
    let view = View::Orbit { azimuth, elevation };
    Camera::framing(mesh.positions(), view, Projection::Orthographic, 400, 400).unwrap()
}

#[test]
fn a_disk_has_one_closed_border_along_its_rim() {
    let sectors = 64;
    let lines = borders(&disk(10, sectors));
    assert_eq!(lines.len(), 1);
    let border = &lines.lines[0];
    assert_eq!(border.kind, LineKind::Border);
    assert!(border.closed);
    assert_eq!(border.points.len(), sectors);
    for p in &border.points {
        assert!((p.coords.norm() - 1.0).abs() < 1e-12, "{p:?}");
    }
    // The rim is the regular polygon inscribed in the unit circle: it is shorter
    // than 2π by at most 2π − 2N sin(π/N).
    let polygon = 2.0 * sectors as f64 * (PI / sectors as f64).sin();
    assert!((border.length() - polygon).abs() < 1e-12);
    assert!((border.length() - TAU).abs() <= TAU - polygon + 1e-12);
}

#[test]
fn a_closed_mesh_has_no_border() {
    assert!(borders(&unit_sphere()).is_empty());
    assert!(borders(&cube(3)).is_empty());
}

#[test]
fn a_cube_has_twelve_creases_as_long_as_its_edges() {
    for n in [1, 4] {
        let lines = creases(&cube(n), 30.0).unwrap();
        assert_eq!(lines.len(), 12, "{n} squares per side");
        for line in &lines {
            assert_eq!(line.kind, LineKind::Crease);
            assert!(!line.closed);
            assert_eq!(line.points.len(), n + 1);
            assert!((line.length() - 2.0).abs() < 1e-12, "{}", line.length());
            for end in [line.points[0], line.points[n]] {
                assert!(end.iter().all(|x| x.abs() == 1.0), "{end:?} is no corner");
            }
        }
    }
}

#[test]
fn a_smooth_sphere_has_no_crease() {
    assert!(creases(&unit_sphere(), 30.0).unwrap().is_empty());
}

#[test]
fn a_loop_of_crease_edges_is_one_closed_line() {
    // A cylinder of height 2 closed by flat caps: the two rims are the creases.
    let sectors = 48;
    let mut positions = vec![Point::new(0.0, 0.0, -1.0), Point::new(0.0, 0.0, 1.0)];
    for z in [-1.0, 1.0] {
        positions.extend((0..sectors).map(|s| {
            let a = TAU * s as f64 / sectors as f64;
            Point::new(a.cos(), a.sin(), z)
        }));
    }
    let (low, high) = (
        |s: usize| (2 + s % sectors) as u32,
        |s: usize| (2 + sectors + s % sectors) as u32,
    );
    let mut triangles = Vec::new();
    for s in 0..sectors {
        triangles.push([0, low(s + 1), low(s)]);
        triangles.push([1, high(s), high(s + 1)]);
        triangles.push([low(s), low(s + 1), high(s + 1)]);
        triangles.push([low(s), high(s + 1), high(s)]);
    }
    let lines = creases(&mesh_of(positions, triangles), 30.0).unwrap();
    assert_eq!(lines.len(), 2);
    for line in &lines {
        assert!(line.closed);
        assert_eq!(line.points.len(), sectors);
    }
}

#[test]
fn crease_angles_outside_the_open_half_turn_are_refused() {
    let cube = cube(1);
    for angle in [0.0, -10.0, 180.0, 200.0, f64::NAN, f64::INFINITY] {
        let message = creases(&cube, angle).unwrap_err().to_string();
        assert!(message.contains("crease angle"), "{message}");
        let options = DrawOptions {
            crease_angle: Some(angle),
            ..DrawOptions::default()
        };
        assert!(options.check().is_err(), "{angle}");
    }
}

/// The Gaussian bump z = height · exp(−ρ² / 2σ²) around the z axis.
struct Bump {
    height: f64,
    sigma: f64,
}

impl Bump {
    fn point(&self, x: f64, y: f64) -> Point {
        Point::new(x, y, self.value(x, y))
    }
}

impl HeightFunction for Bump {
    fn value(&self, x: f64, y: f64) -> f64 {
        self.height * (-(x * x + y * y) / (2.0 * self.sigma * self.sigma)).exp()
    }

    fn gradient(&self, x: f64, y: f64) -> [f64; 2] {
        let s = -self.value(x, y) / (self.sigma * self.sigma);
        [s * x, s * y]
    }

    fn hessian(&self, x: f64, y: f64) -> [f64; 3] {
        let (f, s2) = (self.value(x, y), self.sigma * self.sigma);
        [
            f * (x * x / s2 - 1.0) / s2,
            f * x * y / (s2 * s2),
            f * (y * y / s2 - 1.0) / s2,
        ]
    }
}

/// The bump as the implicit surface F = z − f(x, y) (normal upwards).
impl ImplicitSurface for Bump {
    fn gradient(&self, p: &Point) -> Vector {
        let [fx, fy] = HeightFunction::gradient(self, p.x, p.y);
        Vector::new(-fx, -fy, 1.0)
    }

    fn hessian(&self, p: &Point) -> Matrix3<f64> {
        let [fxx, fxy, fyy] = HeightFunction::hessian(self, p.x, p.y);
        -Matrix3::new(fxx, fxy, 0.0, fxy, fyy, 0.0, 0.0, 0.0, 0.0)
    }
}

/// The exact radial curvature of `surface` at its point `q` seen along the unit
/// vector `v` towards the viewer, and the unit direction of w.
fn exact_radial(surface: &dyn ImplicitSurface, q: &Point, v: &Vector) -> (f64, Vector) {
    let n = surface.gradient(q).normalize();
    let k = surface.curvature(q);
    let w = (v - n * n.dot(v)).normalize();
    let (c, s) = (w.dot(&k.d_max), w.dot(&k.d_min));
    ((k.k_max * c * c + k.k_min * s * s) / (c * c + s * s), w)
}

/// Check that every point of `lines` lies within `tolerance` of a suggestive
/// contour of `surface`: the exact κ_r is negative `tolerance` behind the point and
/// positive `tolerance` ahead of it along w (so κ_r = 0 in between, with
/// D_w κ_r > 0). `project` maps a point near the surface onto it.
fn assert_on_suggestive_contours(
    lines: &FeatureLines,
    surface: &dyn ImplicitSurface,
    project: impl Fn(&Point) -> Point,
    v: &Vector,
    tolerance: f64,
) {
    for p in lines.iter().flat_map(|line| &line.points) {
        let q = project(p);
        let (_, w) = exact_radial(surface, &q, v);
        let behind = exact_radial(surface, &project(&(q - w * tolerance)), v).0;
        let ahead = exact_radial(surface, &project(&(q + w * tolerance)), v).0;
        assert!(
            behind < 0.0 && ahead > 0.0,
            "{p:?}: κ_r {behind} behind, {ahead} ahead"
        );
    }
}

fn traced_suggestive(mesh: &Mesh, camera: &Camera) -> FeatureLines {
    let field = estimate_curvature(mesh, &ShapeOperator).unwrap();
    let options = SuggestiveOptions::default();
    suggestive_contours(mesh, &field, camera, &options).unwrap()
}

#[test]
fn a_bump_seen_from_above_has_its_circle_of_inflections_as_suggestive_contour() {
    // Seen along its axis, w is radial and κ_r the curvature of the profile, zero
    // on the circle ρ = σ of inflections and increasing inwards, towards w.
    let bump = Bump {
        height: 1.0,
        sigma: 1.0,
    };
    let mesh = height_field(&bump, 3.0, 20_000, Sampling::Regular)
        .unwrap()
        .mesh;
    let h = mesh.mean_edge_length();
    let lines = traced_suggestive(&mesh, &camera(&mesh, 0.0, 0.0));
    assert_eq!(lines.len(), 1, "{:?}", lines.count_by_kind());
    let circle = &lines.lines[0];
    assert_eq!(circle.kind, LineKind::Suggestive);
    assert!(circle.closed);
    let tolerance = 0.25 * h;
    for p in &circle.points {
        let rho = p.x.hypot(p.y);
        assert!((rho - bump.sigma).abs() < tolerance, "ρ = {rho}, h = {h}");
    }
    assert!((circle.length() - TAU * bump.sigma).abs() < 0.01 * TAU);
    let v = Vector::z();
    assert_on_suggestive_contours(&lines, &bump, |p| bump.point(p.x, p.y), &v, tolerance);
}

/// The distance from `p` to the nearest segment of `lines`.
fn distance_to_lines(p: &Point, lines: &FeatureLines) -> f64 {
    lines
        .iter()
        .flat_map(|line| line.segments())
        .map(|(a, b)| {
            let ab = b - a;
            let t = ((p - a).dot(&ab) / ab.norm_squared()).clamp(0.0, 1.0);
            (p - (a + ab * t)).norm()
        })
        .fold(f64::INFINITY, f64::min)
}

/// The points of the exact suggestive contour generator of the torus seen along
/// `v` that pass DeCarlo et al.'s filters with a margin: n · v above 0.05, the
/// angle between n and v at least 5° above θ_c, and D_w κ_r / ‖w‖ at least twice
/// its threshold `min_derivative`. Found as sign changes of κ_r along the meridians
/// of a fine parameter grid, refined by bisection.
fn exact_torus_contours(torus: &Torus, v: &Vector, min_derivative: f64) -> Vec<Point> {
    let at = |u: f64, t: f64| {
        let rho = torus.major + torus.minor * t.cos();
        Point::new(rho * u.cos(), rho * u.sin(), torus.minor * t.sin())
    };
    let radial = |u: f64, t: f64| exact_radial(torus, &at(u, t), v).0;
    let max_cos = (SuggestiveOptions::default().min_view_angle + 5.0)
        .to_radians()
        .cos();
    let steps = 720;
    let angle = |i: usize| TAU * i as f64 / steps as f64;
    let mut points = Vec::new();
    // Sign changes along the meridians and along the parallels of the grid.
    for (i, j, along_meridian) in
        (0..steps).flat_map(|i| (0..steps).flat_map(move |j| [(i, j, true), (i, j, false)]))
    {
        let param = |s: f64| {
            if along_meridian {
                (angle(i), s)
            } else {
                (s, angle(i))
            }
        };
        let sign = |s: f64| {
            let (u, t) = param(s);
            radial(u, t) > 0.0
        };
        let (mut low, mut high) = (angle(j), angle(j + 1));
        if sign(low) == sign(high) {
            continue;
        }
        for _ in 0..40 {
            let middle = 0.5 * (low + high);
            if sign(middle) == sign(low) {
                low = middle;
            } else {
                high = middle;
            }
        }
        let (u, t) = param(low);
        let q = at(u, t);
        let cos_theta = torus.gradient(&q).normalize().dot(v);
        let (_, w) = exact_radial(torus, &q, v);
        let step = 1e-5;
        let derivative = (exact_radial(torus, &project_on_torus(torus, &(q + w * step)), v).0
            - exact_radial(torus, &project_on_torus(torus, &(q - w * step)), v).0)
            / (2.0 * step);
        if cos_theta > 0.05 && cos_theta < max_cos && derivative > 2.0 * min_derivative {
            points.push(q);
        }
    }
    points
}

/// The point of the torus nearest to `p`.
fn project_on_torus(torus: &Torus, p: &Point) -> Point {
    let radial = Vector::new(p.x, p.y, 0.0).normalize();
    let centre = Point::from(radial * torus.major);
    centre + (p - centre).normalize() * torus.minor
}

#[test]
fn a_torus_seen_obliquely_has_suggestive_contours_where_the_exact_ones_are() {
    let exact = Torus {
        major: 2.0,
        minor: 1.0,
    };
    let analytic = torus(exact.major, exact.minor, 40_000, Sampling::Regular).unwrap();
    let mesh = analytic.mesh;
    let h = mesh.mean_edge_length();
    let camera = camera(&mesh, 0.0, 50.0);
    let v = -camera.forward();
    let lines = traced_suggestive(&mesh, &camera);
    assert_on_suggestive_contours(&lines, &exact, |p| project_on_torus(&exact, p), &v, 0.5 * h);

    // Every exact point that passes the filters with a margin is traced: the
    // feature curvature K is taken from the exact curvatures of the vertices.
    let mut curvedness: Vec<f64> = analytic
        .exact
        .iter()
        .map(|k| (0.5 * (k.k_max * k.k_max + k.k_min * k.k_min)).sqrt())
        .collect();
    curvedness.sort_by(f64::total_cmp);
    let feature = curvedness[(0.9 * (curvedness.len() - 1) as f64).round() as usize];
    let min_derivative = SuggestiveOptions::default().min_derivative * feature * feature;
    let expected = exact_torus_contours(&exact, &v, min_derivative);
    assert!(expected.len() > 100, "{}", expected.len());
    for q in &expected {
        let distance = distance_to_lines(q, &lines);
        assert!(
            distance < 0.5 * h,
            "{q:?} is {distance} from the traced lines, h = {h}"
        );
    }
}

#[test]
fn a_sphere_has_no_suggestive_contour() {
    let mesh = unit_sphere();
    for (azimuth, elevation) in [(0.0, 0.0), (40.0, 25.0)] {
        let lines = traced_suggestive(&mesh, &camera(&mesh, azimuth, elevation));
        assert!(lines.is_empty(), "{:?}", lines.count_by_kind());
    }
}

#[test]
fn drawings_have_the_families_only_when_asked_for() {
    let mesh = disk(8, 48);
    let camera = camera(&mesh, 10.0, 20.0);
    let lines = FeatureLines::new("disk");
    let plain = draw(&mesh, &lines, &camera, &with_silhouettes()).unwrap();
    assert!(plain.groups.is_empty());
    let options = DrawOptions {
        borders: true,
        crease_angle: Some(30.0),
        suggestive: Some(SuggestiveOptions::default()),
        ..DrawOptions::default()
    };
    let drawing = draw(&mesh, &lines, &camera, &options).unwrap();
    let border = drawing.group(LineKind::Border).expect("a border group");
    assert_eq!(border.paths.len(), 1);
    assert!(border.paths[0].closed);
    assert!(drawing.group(LineKind::Crease).is_none());
    assert!(drawing.group(LineKind::Suggestive).is_none());
}

#[test]
fn bad_suggestive_settings_are_refused() {
    let bad = [
        SuggestiveOptions {
            min_view_angle: 90.0,
            ..SuggestiveOptions::default()
        },
        SuggestiveOptions {
            min_derivative: -1.0,
            ..SuggestiveOptions::default()
        },
        SuggestiveOptions {
            min_length: f64::NAN,
            ..SuggestiveOptions::default()
        },
    ];
    for options in bad {
        assert!(options.check().is_err(), "{options:?}");
    }
}

/// The default drawing settings with the silhouettes drawn.
fn with_silhouettes() -> DrawOptions {
    DrawOptions {
        silhouettes: true,
        ..DrawOptions::default()
    }
}

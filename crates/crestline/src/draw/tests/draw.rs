//! Line drawings: SVG structure, hidden-line removal on a sphere, silhouettes,
//! styles and the PNG preview.

use std::f64::consts::TAU;

use crate::draw::{
    clear_of_silhouettes, draw, with_facing, write_png, Camera, DrawOptions, Drawing, Group,
    Projection, ScreenPath, SilhouetteIndex, Style, View, FACING,
};
use crate::lines::{FeatureLines, LineKind, Polyline, SurfaceLocation};
use crate::mesh::generate::{sphere, Sampling};
use crate::mesh::Mesh;
use crate::Point;

fn unit_sphere() -> Mesh {
    sphere(1.0, 4000, Sampling::jittered(7)).unwrap().mesh
}

fn camera(mesh: &Mesh, azimuth: f64, elevation: f64, width: u32, height: u32) -> Camera {
    let view = View::Orbit { azimuth, elevation };
    Camera::framing(
        mesh.positions(),
        view,
        Projection::Orthographic,
        width,
        height,
    )
    .unwrap()
}

/// The circle of latitude z = `height` on the exact sphere of radius 1 (it lies
/// just outside the mesh, whose faces are chords).
fn latitude(kind: LineKind, height: f64) -> Polyline {
    let radius = (1.0 - height * height).sqrt();
    let points = (0..240)
        .map(|i| {
            let a = TAU * i as f64 / 240.0;
            Point::new(radius * a.cos(), radius * a.sin(), height)
        })
        .collect();
    Polyline::new(kind, true, 5.0, points)
}

/// The section of the mesh by the plane z = `height`: crossing points of the edges,
/// in angular order, so consecutive points share a face and every segment lies
/// exactly on the mesh.
fn section(mesh: &Mesh, height: f64) -> Polyline {
    let mut points: Vec<Point> = mesh
        .edges()
        .filter_map(|e| {
            let [a, b] = mesh.edge_vertices(e).map(|v| mesh.position(v));
            let (da, db) = (a.z - height, b.z - height);
            ((da < 0.0) != (db < 0.0)).then(|| a + (b - a) * (da / (da - db)))
        })
        .collect();
    points.sort_by(|p, q| p.y.atan2(p.x).total_cmp(&q.y.atan2(q.x)));
    Polyline::new(LineKind::Ridge, true, 5.0, points)
}

fn lines(list: Vec<Polyline>) -> FeatureLines {
    FeatureLines {
        source: "sphere".into(),
        lines: list,
        space: None,
    }
}

fn no_silhouettes() -> DrawOptions {
    DrawOptions {
        silhouettes: false,
        ..DrawOptions::default()
    }
}

/// Summed length in pixels of the drawn paths of `kind`.
fn drawn_length(drawing: &Drawing, kind: LineKind) -> f64 {
    drawing.group(kind).map_or(0.0, |g| {
        g.paths
            .iter()
            .map(|p| {
                let mut length: f64 = p.points.windows(2).map(|w| distance(w[0], w[1])).sum();
                if p.closed {
                    length += distance(p.points[p.points.len() - 1], p.points[0]);
                }
                length
            })
            .sum()
    })
}

fn distance(a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}

/// Length of `line` projected on the canvas.
fn projected_length(line: &Polyline, camera: &Camera) -> f64 {
    line.segments()
        .map(|(a, b)| {
            let (pa, pb) = (camera.project(a).unwrap(), camera.project(b).unwrap());
            (pa.x - pb.x).hypot(pa.y - pb.y)
        })
        .sum()
}

/// The coordinates of an SVG path `d` attribute written by crestline (`M`, `L`, `Z`).
fn path_points(d: &str) -> Vec<[f64; 2]> {
    d.split(['M', 'L', 'Z'])
        .filter(|s| !s.trim().is_empty())
        .map(|pair| {
            let mut xy = pair.split_whitespace().map(|v| v.parse::<f64>().unwrap());
            [xy.next().unwrap(), xy.next().unwrap()]
        })
        .collect()
}

#[test]
fn svg_has_the_groups_and_every_path_inside_the_viewbox() {
    let mesh = unit_sphere();
    let camera = camera(&mesh, 30.0, 20.0, 400, 300);
    let input = lines(vec![
        latitude(LineKind::Ridge, 0.5),
        latitude(LineKind::Valley, -0.3),
    ]);
    let drawing = draw(&mesh, &input, &camera, &with_silhouettes()).unwrap();
    let svg = drawing.svg(&Style::default());
    let doc = roxmltree::Document::parse(&svg).expect("the SVG is well-formed XML");
    let root = doc.root_element();
    assert_eq!(root.tag_name().name(), "svg");
    assert_eq!(root.attribute("viewBox"), Some("0 0 400 300"));
    assert_eq!(root.attribute("width"), Some("400"));
    assert_eq!(root.attribute("height"), Some("300"));
    let groups: Vec<&str> = root
        .children()
        .filter(|n| n.has_tag_name("g"))
        .filter_map(|g| g.attribute("id"))
        .collect();
    assert_eq!(groups, ["silhouettes", "ridges", "valleys"]);
    let paths: Vec<_> = root
        .descendants()
        .filter(|n| n.has_tag_name("path"))
        .collect();
    assert!(paths.len() >= 3, "{svg}");
    for path in paths {
        assert!(path.parent().unwrap().has_tag_name("g"));
        for [x, y] in path_points(path.attribute("d").unwrap()) {
            assert!(
                (0.0..=400.0).contains(&x) && (0.0..=300.0).contains(&y),
                "({x}, {y})"
            );
        }
    }
    for g in root.children().filter(|n| n.has_tag_name("g")) {
        assert_eq!(g.attribute("fill"), Some("none"));
        assert_eq!(g.attribute("stroke-linecap"), Some("round"));
    }
}

#[test]
fn far_side_of_a_sphere_is_hidden_and_near_side_drawn() {
    let mesh = unit_sphere();
    // Azimuth 0, elevation 0: the eye is on the +z side.
    let camera = camera(&mesh, 0.0, 0.0, 400, 400);
    let near = latitude(LineKind::Ridge, 0.5);
    let far = latitude(LineKind::Valley, -0.5);
    let expected = projected_length(&near, &camera);
    let drawing = draw(&mesh, &lines(vec![near, far]), &camera, &no_silhouettes()).unwrap();
    let ridges = drawing.group(LineKind::Ridge).unwrap();
    assert_eq!(ridges.paths.len(), 1);
    assert!(ridges.paths[0].closed);
    assert!((drawn_length(&drawing, LineKind::Ridge) - expected).abs() < 0.01 * expected);
    let valleys = drawing
        .group(LineKind::Valley)
        .expect("a group even when hidden");
    assert!(valleys.paths.is_empty(), "{:?}", valleys.paths);
}

#[test]
fn a_line_lying_on_the_surface_is_not_hidden_by_it_even_at_grazing_angles() {
    let mesh = unit_sphere();
    // Seen from 30° above the equator, the section z = 0.5 faces the viewer
    // everywhere and touches the silhouette at one point.
    let camera = camera(&mesh, 0.0, 30.0, 400, 400);
    let on_surface = section(&mesh, 0.5);
    let expected = projected_length(&on_surface, &camera);
    let drawing = draw(&mesh, &lines(vec![on_surface]), &camera, &no_silhouettes()).unwrap();
    let drawn = drawn_length(&drawing, LineKind::Ridge);
    assert!(drawn > 0.99 * expected, "drawn {drawn} of {expected} px");
    assert!(drawing.group(LineKind::Ridge).unwrap().paths.len() <= 2);
}

#[test]
fn the_silhouette_of_a_sphere_is_one_circle_of_its_projected_radius() {
    let mesh = sphere(2.0, 4000, Sampling::jittered(3)).unwrap().mesh;
    let camera = camera(&mesh, 40.0, -25.0, 500, 500);
    let drawing = draw(&mesh, &lines(vec![]), &camera, &with_silhouettes()).unwrap();
    let contour = drawing.group(LineKind::Silhouette).unwrap();
    assert_eq!(contour.paths.len(), 1);
    assert!(contour.paths[0].closed);
    let center = camera.project(&Point::origin()).unwrap();
    // The canvas radius of the sphere: the farthest projected vertex.
    let radius = mesh
        .positions()
        .iter()
        .map(|p| {
            let s = camera.project(p).unwrap();
            (s.x - center.x).hypot(s.y - center.y)
        })
        .fold(0.0, f64::max);
    for &[x, y] in &contour.paths[0].points {
        let r = (x - center.x).hypot(y - center.y);
        assert!((r - radius).abs() < 0.01 * radius, "{r} against {radius}");
    }
}

#[test]
fn perspective_drawings_keep_the_near_side_and_hide_the_far_side() {
    let mesh = unit_sphere();
    let view = View::Orbit {
        azimuth: 0.0,
        elevation: 0.0,
    };
    let projection = Projection::Perspective { fov: 40.0 };
    let camera = Camera::framing(mesh.positions(), view, projection, 300, 300).unwrap();
    let near = latitude(LineKind::Ridge, 0.5);
    let far = latitude(LineKind::Valley, -0.5);
    let drawing = draw(&mesh, &lines(vec![near, far]), &camera, &no_silhouettes()).unwrap();
    assert_eq!(drawing.group(LineKind::Ridge).unwrap().paths.len(), 1);
    assert!(drawing.group(LineKind::Valley).unwrap().paths.is_empty());
}

#[test]
fn absurd_camera_settings_are_errors() {
    let mesh = unit_sphere();
    let points = mesh.positions();
    let orbit = View::default();
    let ortho = Projection::Orthographic;
    for (width, height) in [(0, 100), (100, 20_001)] {
        let err = Camera::framing(points, orbit, ortho, width, height).unwrap_err();
        assert!(err.to_string().contains("between 1 and 20000"), "{err}");
    }
    for fov in [0.0, 180.0, -5.0, f64::NAN] {
        let projection = Projection::Perspective { fov };
        let err = Camera::framing(points, orbit, projection, 100, 100).unwrap_err();
        assert!(err.to_string().contains("field of view"), "{err}");
    }
    let nan = View::Orbit {
        azimuth: f64::NAN,
        elevation: 0.0,
    };
    assert!(Camera::framing(points, nan, ortho, 100, 100).is_err());
    let along_up = View::LookAt {
        eye: Point::new(0.0, 5.0, 0.0),
        target: Point::origin(),
        up: crate::Vector::y(),
    };
    assert!(Camera::framing(points, along_up, ortho, 100, 100).is_err());
}

#[test]
fn a_style_file_overrides_colours_and_keeps_the_other_defaults() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("style.json");
    std::fs::write(
        &path,
        r##"{"background": null, "kinds": {"ridges": {"color": "#00ff00", "width": 3}}}"##,
    )
    .unwrap();
    let style = Style::read(&path).unwrap();
    assert_eq!(style.background, None);
    assert_eq!(style.kind(LineKind::Ridge).color, "#00ff00");
    assert_eq!(style.kind(LineKind::Ridge).width, 3.0);
    assert_eq!(
        style.kind(LineKind::Valley),
        Style::default().kind(LineKind::Valley)
    );

    let mesh = unit_sphere();
    let camera = camera(&mesh, 0.0, 0.0, 200, 200);
    let input = lines(vec![latitude(LineKind::Ridge, 0.5)]);
    let drawing = draw(&mesh, &input, &camera, &no_silhouettes()).unwrap();
    let svg = drawing.svg(&style);
    let doc = roxmltree::Document::parse(&svg).unwrap();
    let ridges = doc
        .descendants()
        .find(|n| n.attribute("id") == Some("ridges"))
        .unwrap();
    assert_eq!(ridges.attribute("stroke"), Some("#00ff00"));
    assert!(!svg.contains("id=\"background\""));
}

#[test]
fn a_bad_style_file_is_an_error_naming_the_file_and_the_key() {
    let dir = tempfile::tempdir().unwrap();
    let cases = [
        (r#"{"kinds": {"ridges": {"colour": "red"}}}"#, "colour"),
        (r#"{"kinds": {"ridge": {"color": "red"}}}"#, "\"ridge\""),
        (r#"{"foreground": "red"}"#, "foreground"),
        (
            r#"{"kinds": {"valleys": {"color": "red\" onload=\"x"}}}"#,
            "kinds.valleys.color",
        ),
        (
            r#"{"kinds": {"valleys": {"width": -1}}}"#,
            "kinds.valleys.width",
        ),
    ];
    for (i, (text, key)) in cases.into_iter().enumerate() {
        let path = dir.path().join(format!("bad{i}.json"));
        std::fs::write(&path, text).unwrap();
        let err = Style::read(&path).unwrap_err().to_string();
        assert!(err.starts_with(&path.display().to_string()), "{err}");
        assert!(err.contains(key), "{err}");
    }
}

#[test]
fn the_png_preview_shows_the_lines() {
    let mesh = unit_sphere();
    let camera = camera(&mesh, 0.0, 0.0, 200, 200);
    let input = lines(vec![latitude(LineKind::Ridge, 0.5)]);
    let drawing = draw(&mesh, &input, &camera, &with_silhouettes()).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("sphere.png");
    let style = Style::default();
    let background = style.background.as_deref();
    write_png(&path, &drawing.svg(&style), background).unwrap();
    let pixmap = resvg::tiny_skia::Pixmap::load_png(&path).unwrap();
    assert_eq!((pixmap.width(), pixmap.height()), (200, 200));
    let pixels = pixmap.pixels();
    let white = pixels
        .iter()
        .filter(|p| (p.red(), p.green(), p.blue()) == (255, 255, 255));
    let reddish = pixels.iter().filter(|p| p.red() > 120 && p.green() < 110);
    assert!(white.count() > pixels.len() / 2);
    assert!(reddish.count() > 100);
}

/// A path of screen points every half pixel from `from` to `to`.
fn screen_path(from: [f64; 2], to: [f64; 2]) -> ScreenPath {
    let steps = ((to[0] - from[0]).hypot(to[1] - from[1]) / 0.5).ceil() as usize;
    let points: Vec<[f64; 2]> = (0..=steps)
        .map(|i| {
            let t = i as f64 / steps as f64;
            [
                from[0] + t * (to[0] - from[0]),
                from[1] + t * (to[1] - from[1]),
            ]
        })
        .collect();
    ScreenPath {
        depths: vec![0.0; points.len()],
        facings: vec![1.0; points.len()],
        points,
        closed: false,
        strength: 1.0,
    }
}

/// Beside a silhouette and parallel to it, a feature line is dropped; crossing it,
/// or parallel but farther than the clearance, it is kept whole; a line that
/// leaves the outline keeps the part beyond the clearance.
#[test]
fn feature_lines_are_cleared_only_where_they_double_a_silhouette() {
    let outline = screen_path([0.0, 100.0], [400.0, 100.0]);
    let index = SilhouetteIndex::new([&outline], 4.0);
    let clear = |path: &ScreenPath| clear_of_silhouettes(path, &index, 4.0);
    assert!(clear(&screen_path([100.0, 102.0], [300.0, 102.0])).is_empty());
    let crossing = screen_path([200.0, 50.0], [200.0, 150.0]);
    assert_eq!(clear(&crossing), vec![crossing.clone()]);
    let apart = screen_path([100.0, 110.0], [300.0, 110.0]);
    assert_eq!(clear(&apart), vec![apart.clone()]);
    let mut leaving = screen_path([100.0, 102.0], [200.0, 102.0]);
    leaving
        .points
        .extend(screen_path([200.0, 102.0], [260.0, 140.0]).points);
    let kept = clear(&leaving);
    assert_eq!(kept.len(), 1, "{kept:?}");
    let first = kept[0].points[0];
    assert!(first[0] > 200.0 && first[1] > 103.0, "{first:?}");
    assert_eq!(kept[0].points.last(), leaving.points.last());
}

/// Attribute `name` of every `<path>` of group `id` in an SVG document, in order,
/// as a number; where a path lacks it, the group's value, else `default`.
fn path_attribute(svg: &str, id: &str, name: &str, default: f64) -> Vec<f64> {
    let doc = roxmltree::Document::parse(svg).unwrap();
    let group = doc
        .descendants()
        .find(|n| n.has_tag_name("g") && n.attribute("id") == Some(id))
        .unwrap();
    let inherited = group
        .attribute(name)
        .map_or(default, |v| v.parse().unwrap());
    group
        .children()
        .filter(|n| n.has_tag_name("path"))
        .map(|n| n.attribute(name).map_or(inherited, |v| v.parse().unwrap()))
        .collect()
}

/// The stroke widths of the `<path>`s of group `id`, in order.
fn path_widths(svg: &str, id: &str) -> Vec<f64> {
    path_attribute(svg, id, "stroke-width", f64::NAN)
}

/// The stroke opacities of the `<path>`s of group `id`, in order.
fn path_opacities(svg: &str, id: &str) -> Vec<f64> {
    path_attribute(svg, id, "stroke-opacity", 1.0)
}

/// Tapered lines narrow towards both ends and keep their width in the middle;
/// lines weighted by depth are thinner where they are farther, down to half;
/// lines faded by view are opaque where the surface faces the viewer and vanish
/// where it is seen edge-on.
#[test]
fn line_weights_follow_the_taper_the_depth_and_the_view() {
    let mut path = screen_path([100.0, 100.0], [300.0, 100.0]);
    // Depth grows from 0 at the left end to 1 at the right, n · v falls from 1 to 0.
    path.depths = path.points.iter().map(|p| (p[0] - 100.0) / 200.0).collect();
    path.facings = path.depths.iter().map(|d| 1.0 - d).collect();
    let drawing = Drawing {
        source: "test".into(),
        width: 400,
        height: 200,
        groups: vec![Group {
            kind: LineKind::Ridge,
            paths: vec![path],
        }],
        page: None,
    };
    let mut style = Style::default();
    let full = style.kind(LineKind::Ridge).width;
    assert_eq!(path_widths(&drawing.svg(&style), "ridges"), vec![full]);

    style.kind_mut(LineKind::Ridge).taper = 20.0;
    let tapered = path_widths(&drawing.svg(&style), "ridges");
    let middle = tapered.len() / 2;
    assert!(tapered.len() >= 5, "{tapered:?}");
    assert!((tapered[middle] - full).abs() < 1e-9, "{tapered:?}");
    assert!(
        tapered[0] < 0.3 * full && tapered[tapered.len() - 1] < 0.3 * full,
        "{tapered:?}"
    );
    assert!(
        tapered[..=middle].windows(2).all(|w| w[0] <= w[1]),
        "{tapered:?}"
    );
    assert!(
        tapered[middle..].windows(2).all(|w| w[0] >= w[1]),
        "{tapered:?}"
    );

    style.kind_mut(LineKind::Ridge).taper = 0.0;
    style.kind_mut(LineKind::Ridge).width_by_depth = true;
    let by_depth = path_widths(&drawing.svg(&style), "ridges");
    assert!((by_depth[0] - full).abs() < 1e-9, "{by_depth:?}");
    assert!(
        (by_depth[by_depth.len() - 1] - 0.5 * full).abs() < 0.06 * full,
        "{by_depth:?}"
    );
    assert!(by_depth.windows(2).all(|w| w[0] >= w[1]), "{by_depth:?}");

    style.kind_mut(LineKind::Ridge).width_by_depth = false;
    style.kind_mut(LineKind::Ridge).fade_by_view = true;
    let svg = drawing.svg(&style);
    let faded = path_opacities(&svg, "ridges");
    // Opaque while n · v ≥ ½ (the left half), then fading; the last stretch,
    // seen edge-on, is not drawn at all.
    assert_eq!(faded[0], 1.0, "{faded:?}");
    assert!(faded.windows(2).all(|w| w[0] >= w[1]), "{faded:?}");
    assert!(*faded.last().unwrap() <= 0.1, "{faded:?}");
    let drawn: f64 = roxmltree::Document::parse(&svg)
        .unwrap()
        .descendants()
        .filter_map(|n| n.attribute("d"))
        .filter_map(|d| d.rsplit('L').next()?.split(' ').next()?.parse::<f64>().ok())
        .fold(0.0, f64::max);
    assert!(drawn < 300.0 && drawn > 280.0, "drawn up to x = {drawn}");
}

/// n · v along a line on a sphere seen along −z is the cosine z / r of its points.
#[test]
fn facing_is_the_cosine_between_normal_and_view() {
    let mesh = sphere(2.0, 4000, Sampling::jittered(5)).unwrap().mesh;
    let locations: Vec<SurfaceLocation> = (0..mesh.vertex_count() as u32)
        .step_by(97)
        .map(|vertex| SurfaceLocation::Vertex { vertex })
        .collect();
    let points: Vec<Point> = locations.iter().map(|at| at.position(&mesh)).collect();
    let mut lines = FeatureLines::new(String::new());
    lines
        .push(Polyline::new(LineKind::Ridge, false, 1.0, points.clone()).with_locations(locations));
    let camera = Camera::framing(
        mesh.positions(),
        View::default(),
        Projection::Orthographic,
        400,
        400,
    )
    .unwrap();
    with_facing(&mesh, &camera, &mut lines);
    let facing = &lines.lines[0].values[FACING];
    for (p, f) in points.iter().zip(facing) {
        assert!((f - p.z / p.coords.norm()).abs() < 0.05, "{p}: {f}");
    }
}

/// The default drawing settings with the silhouettes drawn.
fn with_silhouettes() -> DrawOptions {
    DrawOptions {
        silhouettes: true,
        ..DrawOptions::default()
    }
}

//! Morse-Smale lines as drawn: smooth, and still on the crests of the indicator.

use crate::draw::{draw, Camera, DrawOptions, Projection, View};
use crate::lines::{FeatureLines, LineExtractor, LineKind};
use crate::mesh::Mesh;
use crate::morse::{Indicator, MorseSmale};
use crate::progress::Silent;

fn bunny() -> Mesh {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../meshes/bunny.obj");
    let soup = crate::io::read_mesh(std::path::Path::new(path)).unwrap();
    Mesh::from_soup(soup).unwrap().0
}

/// Radians of turning per 100 px of the drawn paths of `kind`.
fn turning_per_100_px(mesh: &Mesh, lines: &FeatureLines, kind: LineKind) -> f64 {
    let view = View::Orbit {
        azimuth: 20.0,
        elevation: 15.0,
    };
    let camera =
        Camera::framing(mesh.positions(), view, Projection::Orthographic, 800, 800).unwrap();
    let options = DrawOptions {
        silhouettes: false,
        ..DrawOptions::default()
    };
    let drawing = draw(mesh, lines, &camera, &options).unwrap();
    let (mut turning, mut length) = (0.0, 0.0);
    for path in &drawing.group(kind).unwrap().paths {
        let p = &path.points;
        for w in p.windows(2) {
            length += (w[1][0] - w[0][0]).hypot(w[1][1] - w[0][1]);
        }
        for w in p.windows(3) {
            let a = (w[1][1] - w[0][1]).atan2(w[1][0] - w[0][0]);
            let b = (w[2][1] - w[1][1]).atan2(w[2][0] - w[1][0]);
            let turn = (b - a + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU)
                - std::f64::consts::PI;
            turning += turn.abs();
        }
    }
    100.0 * turning / length
}

/// The share of the lines' length (on the surface) along which the indicator
/// stays in its upper quartile over the mesh.
fn share_on_crest(mesh: &Mesh, lines: &FeatureLines, indicator: &[f64]) -> f64 {
    let mut sorted = indicator.to_vec();
    sorted.sort_by(f64::total_cmp);
    let quartile = sorted[3 * (sorted.len() - 1) / 4];
    let (mut on, mut total) = (0.0, 0.0);
    for line in &lines.lines {
        let values: Vec<f64> = line
            .locations
            .iter()
            .map(|at| at.interpolate(mesh, indicator))
            .collect();
        for (k, w) in line.points.windows(2).enumerate() {
            let length = (w[1] - w[0]).norm();
            total += length;
            if 0.5 * (values[k] + values[k + 1]) >= quartile {
                on += length;
            }
        }
    }
    on / total
}

/// With the defaults, Morse lines are drawn smooth (at most 8 radians of turning
/// per 100 px on the bunny, from 36 unfaired) and stay on the crests: along at
/// least 75% of their length the curvedness is in its upper quartile.
#[test]
fn default_morse_lines_are_smooth_and_stay_on_the_crests() {
    let mesh = bunny();
    let morse = MorseSmale::default();
    let unfaired = MorseSmale {
        smooth: 0,
        ..MorseSmale::default()
    };
    let (lines, raw) = (
        morse.extract(&mesh, &mut Silent).unwrap(),
        unfaired.extract(&mesh, &mut Silent).unwrap(),
    );
    let indicator = Indicator::Curvedness
        .values(&mesh, morse.estimator.as_ref())
        .unwrap();
    let (smooth, staircase) = (
        turning_per_100_px(&mesh, &lines, LineKind::Ascending),
        turning_per_100_px(&mesh, &raw, LineKind::Ascending),
    );
    let (on, before) = (
        share_on_crest(&mesh, &lines, &indicator),
        share_on_crest(&mesh, &raw, &indicator),
    );
    eprintln!("turning per 100 px: {staircase:.1} unfaired, {smooth:.1} faired");
    eprintln!("share on the crest: {before:.3} unfaired, {on:.3} faired");
    assert!(staircase > 20.0, "{staircase}");
    assert!(smooth <= 8.0, "{smooth}");
    assert!(on >= 0.75, "{on}");
    assert!(lines
        .lines
        .iter()
        .all(|l| l.locations.len() == l.points.len()));
}

//! Landmark transfer with known truth: analytic crest lines of an ellipsoid (with
//! a knot inside, so that no symmetry hides the motion) moved by a known rigid
//! motion and a smooth warp; landmarks on the template's lines must land where the
//! warp takes them. Also the labelled landmark files.

use std::f64::consts::TAU;

use crestline::lines::{FeatureLines, LineKind, Polyline};
use crestline::progress::Silent;
use crestline::transfer::{
    read_labelled, transfer, write_labelled, LabelledPoint, TransferOptions,
};
use crestline::{Point, Space, Vector};
use nalgebra::Rotation3;

/// Points of the closed curve `f` on `[0, 1)`, about `step` apart along a curve of
/// length about `length`.
fn sampled(f: impl Fn(f64) -> Point, length: f64, step: f64) -> Vec<Point> {
    let n = (length / step).ceil() as usize;
    (0..n).map(|i| f(i as f64 / n as f64)).collect()
}

/// Latitude circles (ridges) and meridians (valleys) of an ellipsoid of semi-axes
/// 60, 45 and 35 mm, and a trefoil knot (a ridge) inside, off centre.
fn template() -> FeatureLines {
    let axes = Vector::new(60.0, 45.0, 35.0);
    let on_ellipsoid = |theta: f64, phi: f64| {
        Point::new(
            axes.x * theta.sin() * phi.cos(),
            axes.y * theta.sin() * phi.sin(),
            axes.z * theta.cos(),
        )
    };
    let mut lines = FeatureLines::new("ellipsoid");
    lines.space = Some(Space::Ras);
    for band in 1..8 {
        let theta = band as f64 * TAU / 16.0;
        let points = sampled(|t| on_ellipsoid(theta, t * TAU), 400.0, 0.5);
        lines
            .lines
            .push(Polyline::new(LineKind::Ridge, true, 1.0, points));
    }
    for meridian in 0..10 {
        let phi = meridian as f64 * TAU / 10.0;
        let points = sampled(|t| on_ellipsoid(t * TAU / 2.0, phi), 200.0, 0.5);
        lines
            .lines
            .push(Polyline::new(LineKind::Valley, false, 1.0, points));
    }
    let knot = |t: f64| {
        let s = t * TAU;
        Point::new(
            15.0 + 8.0 * ((s).sin() + 2.0 * (2.0 * s).sin()),
            10.0 + 8.0 * ((s).cos() - 2.0 * (2.0 * s).cos()),
            -8.0 * (3.0 * s).sin(),
        )
    };
    lines.lines.push(Polyline::new(
        LineKind::Ridge,
        true,
        1.0,
        sampled(knot, 300.0, 0.5),
    ));
    lines
}

/// The subject's frame: a smooth warp of 4 mm amplitude and 94 mm wavelength, then
/// a rotation of about 6° and a shift.
fn warp(p: &Point) -> Point {
    let bent = p + 4.0 * Vector::new((p.y / 15.0).sin(), (p.z / 15.0).sin(), (p.x / 15.0).sin());
    Rotation3::from_euler_angles(0.06, -0.05, 0.08) * bent + Vector::new(3.0, -2.0, 4.0)
}

fn median(mut values: Vec<f64>) -> f64 {
    values.sort_by(f64::total_cmp);
    values[values.len() / 2]
}

#[test]
fn landmarks_on_warped_lines_land_where_the_warp_takes_them() {
    let template = template();
    let mut subject = template.clone();
    for line in &mut subject.lines {
        line.points.iter_mut().for_each(|p| *p = warp(p));
    }
    // Every 97th line point: on lines of both kinds, on the knot too.
    let landmarks: Vec<Point> = template
        .iter()
        .flat_map(|l| l.points.iter().copied())
        .step_by(97)
        .collect();
    let truth: Vec<Point> = landmarks.iter().map(warp).collect();
    let errors = |options: &TransferOptions| {
        let carried = transfer(&template, &subject, &landmarks, options, &mut Silent).unwrap();
        let errors: Vec<f64> = carried
            .positions
            .iter()
            .zip(&truth)
            .map(|(p, q)| (p - q).norm())
            .collect();
        (median(errors), carried)
    };
    let (rigid, _) = errors(&TransferOptions {
        scales: vec![1000.0],
        iterations: 1,
        ..TransferOptions::default()
    });
    let (deformed, carried) = errors(&TransferOptions::default());
    println!("median error: rigid {rigid:.2} mm, deformed {deformed:.2} mm");
    // Measured: 4.19 mm rigid, 0.03 mm deformed.
    assert!(rigid > 3.0, "the warp is not rigid: {rigid} mm");
    assert!(
        deformed < 0.1,
        "median error {deformed} mm (rigid {rigid} mm)"
    );
    // Each landmark sits on a line of the subject: its residual is small.
    assert!(
        median(carried.confidence.clone()) < 0.5,
        "{:?}",
        carried.confidence
    );
}

#[test]
fn a_landmark_far_from_every_line_has_no_confidence() {
    let template = template();
    let far = [Point::new(0.0, 0.0, 400.0), Point::new(15.0, 10.0, 0.0)];
    let carried = transfer(
        &template,
        &template,
        &far,
        &TransferOptions::default(),
        &mut Silent,
    )
    .unwrap();
    assert_eq!(carried.confidence[0], f64::INFINITY);
    // The far one is flagged (no line near), the one on the knot is not.
    assert_eq!(carried.flagged, [true, false], "{:?}", carried.coverage);
    assert!(carried.confidence[1] < 0.1, "{:?}", carried.confidence);
    assert!(
        (carried.positions[1] - far[1]).norm() < 0.1,
        "{:?}",
        carried.positions
    );
}

#[test]
fn labelled_landmarks_round_trip_through_every_format() {
    let dir = tempfile::tempdir().unwrap();
    let points = vec![
        LabelledPoint {
            label: "nasion".into(),
            position: Point::new(1.5, -2.0, 3.25),
        },
        LabelledPoint {
            label: "L02".into(),
            position: Point::new(-10.0, 20.0, 0.0),
        },
    ];
    for name in ["a.mrk.json", "a.json", "a.csv"] {
        for space in [Space::Ras, Space::Lps] {
            let path = dir.path().join(name);
            write_labelled(&path, &points, &[0.5, f64::INFINITY], &[false, true], space).unwrap();
            if name == "a.json" {
                // JSON has no infinity.
                let text = std::fs::read_to_string(&path).unwrap();
                assert!(text.contains("\"confidence\":null"), "{text}");
            }
            assert_eq!(read_labelled(&path).unwrap(), points, "{name} in {space}");
        }
    }
    let bad = dir.path().join("bad.csv");
    std::fs::write(&bad, "label,x,y,z\nnasion,1,2,3\n").unwrap();
    let message = read_labelled(&bad).unwrap_err().to_string();
    assert!(
        message.contains("bad.csv") && message.contains("`space`"),
        "{message}"
    );
}

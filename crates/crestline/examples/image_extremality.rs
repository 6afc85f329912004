//! Ridge precision on image isosurfaces with the extremalities taken from the
//! image's third derivatives (`ImageCurvature`, Thirion & Gourdon's e = ∇k · t)
//! against discrete differences of the image's curvature across the triangles
//! (eq. 4 of Hildebrandt, Polthier and Wardetzky 2005).
//!
//! The image is the ellipsoid field −(x²/a² + y²/b² + z²/c²) with axes 30, 21 and
//! 13.5 voxels, turned off the grid axes and centred off the grid points; its
//! isosurface at −1 is the ellipsoid, whose ridge is the principal ellipse in the
//! plane of the two longer axes. The isosurface is that of the image smoothed by σ
//! (`ridges <volume> --level -1`, as the tool runs it).
//!
//! Prints, per setting: the mean and largest distance of the ridge points from the
//! true plane in voxels, the share of the ellipse within two voxels of a ridge
//! point (away from the umbilics), and the number of ridge lines.
//!
//! `cargo run --release -p crestline --example image_extremality [-- --sweep]`
//! (`--sweep`: also lighter smoothings of the image's extremalities).

use std::sync::Arc;

use crestline::curvature::{DerivativeOrder, WithoutExtremality};
use crestline::jobs::{isosurface, IsoOptions, RidgesOptions, Surface};
use crestline::lines::LineKind;
use crestline::progress::Silent;
use crestline::ridges::Kinds;
use crestline::volume::Volume;
use crestline::{Point, Vector};
use nalgebra::{Matrix3, Rotation3, Unit};

const AXES: [f64; 3] = [30.0, 21.0, 13.5];

/// The ellipsoid's frame: turned about an oblique axis, centred off the grid.
fn frame() -> (Rotation3<f64>, Point) {
    let axis = Unit::new_normalize(Vector::new(0.3, -0.5, 0.8));
    (
        Rotation3::from_axis_angle(&axis, 0.6),
        Point::new(40.3, 38.7, 36.45),
    )
}

fn ellipsoid_image() -> Volume {
    let dims = [80, 78, 74];
    let (turn, centre) = frame();
    let [a, b, c] = AXES;
    let mut samples = Vec::with_capacity(dims.iter().product());
    for k in 0..dims[2] {
        for j in 0..dims[1] {
            for i in 0..dims[0] {
                let p = turn.inverse() * (Point::new(i as f64, j as f64, k as f64) - centre);
                let value = -((p.x / a).powi(2) + (p.y / b).powi(2) + (p.z / c).powi(2));
                samples.push(value as f32);
            }
        }
    }
    Volume::new(dims, [1.0; 3], [0.0; 3], Matrix3::identity(), samples).unwrap()
}

/// Mean and largest distance of the points from the plane of the two longer axes,
/// and the share of the ridge ellipse (away from the umbilics) within 2 voxels of
/// a point.
fn measure(points: &[Point]) -> (f64, f64, f64) {
    let (turn, centre) = frame();
    let local: Vec<Point> = points
        .iter()
        .map(|p| turn.inverse() * (p - centre))
        .map(Point::from)
        .collect();
    let distances: Vec<f64> = local.iter().map(|p| p.z.abs()).collect();
    let mean = distances.iter().sum::<f64>() / distances.len().max(1) as f64;
    let largest = distances.iter().copied().fold(0.0, f64::max);
    let [a, b, c] = AXES;
    let umbilic_x = a * ((a * a - b * b) / (a * a - c * c)).sqrt();
    let samples: Vec<Point> = (0..720)
        .map(|i| {
            let angle = std::f64::consts::TAU * f64::from(i) / 720.0;
            Point::new(a * angle.cos(), b * angle.sin(), 0.0)
        })
        .filter(|p| (p.x.abs() - umbilic_x).abs() > 0.15 * a)
        .collect();
    let covered = samples
        .iter()
        .filter(|s| local.iter().any(|p| (p - *s).norm() < 2.0))
        .count();
    (mean, largest, covered as f64 / samples.len() as f64)
}

fn report(name: &str, surface: &Surface, options: &RidgesOptions) {
    let tracer = options.tracer(surface);
    let lines = tracer.trace(&surface.mesh, &mut Silent).unwrap();
    let ridges: Vec<_> = lines.iter().filter(|l| l.kind == LineKind::Ridge).collect();
    let points: Vec<Point> = ridges
        .iter()
        .flat_map(|l| l.points.iter().copied())
        .collect();
    let (mean, largest, coverage) = measure(&points);
    println!(
        "{name:<44} mean {mean:.4} voxel, largest {largest:.3}, coverage {:.1}%, {} ridge lines",
        100.0 * coverage,
        ridges.len()
    );
}

/// The lines traced with `steps` smoothing steps of time `time` on `surface`
/// (`None`: the defaults of `ridges`).
fn report_smoothing(name: &str, surface: &Surface, smoothing: Option<(usize, f64)>) {
    let options = RidgesOptions {
        kind: Kinds::Ridges,
        smooth_steps: smoothing.map(|s| s.0),
        smooth_time: smoothing.map(|s| s.1),
        ..RidgesOptions::default()
    };
    let setting = match smoothing {
        Some((steps, time)) => format!("{steps} smoothing steps of τ = {time}"),
        None => "default smoothing".to_string(),
    };
    report(&format!("  {name}, {setting}"), surface, &options);
}

fn main() {
    let sweep = std::env::args().any(|a| a == "--sweep");
    let volume = ellipsoid_image();
    for sigma in [1.0, 2.0] {
        let iso = IsoOptions {
            sigma: sigma.into(),
            ..IsoOptions::default()
        };
        let third = Some(DerivativeOrder::Third);
        let surface = isosurface(&volume, -1.0, &iso, third, &mut Silent).unwrap();
        let image = surface.curvature.clone().expect("the image's curvature");
        // Not marked as an image's isosurface: the defaults are the discrete
        // extremalities' (the shape operator's).
        let discrete = Surface {
            mesh: surface.mesh.clone(),
            curvature: Some(Arc::new(WithoutExtremality(image))),
            image: None,
        };
        println!(
            "σ = {sigma} voxel, {} vertices",
            surface.mesh.vertex_count()
        );
        for smoothing in [None, Some((0, 2.0))] {
            report_smoothing("image extremalities", &surface, smoothing);
            report_smoothing("discrete extremalities", &discrete, smoothing);
        }
        if sweep {
            for smoothing in [(1, 0.5), (3, 0.25), (3, 0.5), (1, 2.0), (3, 2.0)] {
                report_smoothing("image extremalities", &surface, Some(smoothing));
            }
        }
    }
}

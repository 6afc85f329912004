//! `crestline transfer` on the MNI152 template and a copy of it warped by a
//! known smooth map (resampled by the library's trilinear interpolation, written as
//! MetaImage): the landmarks, points of the template's crest lines, must land near
//! where the map takes them, closer than a rigid registration puts them; labels
//! and order are kept.

use std::io::Write;
use std::path::Path;

use crestline::volume::Volume;
use crestline::{Point, Vector};
use nalgebra::Rotation3;
use serde_json::Value;

use crate::common::{crestline, stderr};

const MNI: &str = "volumes/mni152_t1_1mm.nii.gz";

/// The map from a subject point to the template point it shows (RAS): a smooth
/// triangular warp of 3 mm amplitude, then a rotation of about 4° and a shift.
fn to_template(x: &Point) -> Point {
    let p = motion() * x + Vector::new(2.0, -1.5, 2.5);
    Point::new(
        p.x + 3.0 * (p.y / 14.0).sin(),
        p.y + 3.0 * (p.z / 14.0).sin(),
        p.z + 3.0 * (p.x / 14.0).cos(),
    )
}

fn motion() -> Rotation3<f64> {
    Rotation3::from_euler_angles(0.05, -0.04, 0.06)
}

/// Where template point `p` lies in the subject: [`to_template`] inverted (the
/// warp is triangular, so exactly).
fn to_subject(p: &Point) -> Point {
    let z = p.z - 3.0 * (p.x / 14.0).cos();
    let y = p.y - 3.0 * (z / 14.0).sin();
    let x = p.x - 3.0 * (y / 14.0).sin();
    Point::from(motion().inverse() * (Point::new(x, y, z) - Vector::new(2.0, -1.5, 2.5)))
}

/// `volume` as a MetaImage (LPS) at `path`; its direction must be diagonal.
fn write_mha(path: &Path, volume: &Volume) {
    let [nx, ny, nz] = volume.dims();
    let lps = |p: Point| [-p.x, -p.y, p.z];
    let origin = lps(volume.index_to_world([0.0; 3]));
    let axes: Vec<[f64; 3]> = (0..3)
        .map(|a| {
            let mut unit = [0.0; 3];
            unit[a] = 1.0;
            let step = volume.index_to_world(unit) - volume.index_to_world([0.0; 3]);
            lps(Point::from(step.normalize()))
        })
        .collect();
    let matrix: Vec<String> = axes.iter().flatten().map(|v| v.to_string()).collect();
    let mut file = std::fs::File::create(path).unwrap();
    write!(
        file,
        "ObjectType = Image\nNDims = 3\nBinaryData = True\nBinaryDataByteOrderMSB = False\n\
         DimSize = {nx} {ny} {nz}\nElementSpacing = 1 1 1\nOffset = {} {} {}\n\
         TransformMatrix = {}\nElementType = MET_FLOAT\nElementDataFile = LOCAL\n",
        origin[0],
        origin[1],
        origin[2],
        matrix.join(" ")
    )
    .unwrap();
    let mut bytes = Vec::with_capacity(4 * nx * ny * nz);
    for k in 0..nz {
        for j in 0..ny {
            for i in 0..nx {
                bytes.extend_from_slice(&volume.value(i, j, k).unwrap().to_le_bytes());
            }
        }
    }
    file.write_all(&bytes).unwrap();
}

/// The labelled control points of a markups file, in LPS.
fn control_points(path: &Path) -> Vec<(String, Point)> {
    let document: Value = serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    document["markups"][0]["controlPoints"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| {
            let xyz: Vec<f64> = c["position"]
                .as_array()
                .unwrap()
                .iter()
                .map(|v| v.as_f64().unwrap())
                .collect();
            (
                c["label"].as_str().unwrap().to_string(),
                Point::new(xyz[0], xyz[1], xyz[2]),
            )
        })
        .collect()
}

fn median(mut values: Vec<f64>) -> f64 {
    values.sort_by(f64::total_cmp);
    values[values.len() / 2]
}

#[test]
fn landmarks_of_the_mni_template_land_on_a_warped_copy() {
    let dir = tempfile::tempdir().unwrap();
    let template = crestline::io::read_volume(Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../volumes/mni152_t1_1mm.nii.gz"
    )))
    .unwrap();
    let [nx, ny, nz] = template.dims();
    let samples: Vec<f32> = (0..nx * ny * nz)
        .map(|at| {
            let index = [at % nx, (at / nx) % ny, at / (nx * ny)].map(|i| i as f64);
            let source = to_template(&template.index_to_world(index));
            template.interpolate(&source).unwrap_or(0.0) as f32
        })
        .collect();
    let subject = dir.path().join("subject.mha");
    write_mha(&subject, &template.with_samples(samples).unwrap());

    // The landmarks: points of the template's crest lines, spread over them.
    let lines = dir.path().join("template.json");
    let out = crestline(&[
        "crest-lines",
        MNI,
        "--level",
        "60",
        "-o",
        lines.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let document: Value = serde_json::from_str(&std::fs::read_to_string(&lines).unwrap()).unwrap();
    let all: Vec<Point> = document["lines"]
        .as_array()
        .unwrap()
        .iter()
        .flat_map(|l| l["points"].as_array().unwrap().clone())
        .map(|p| {
            Point::new(
                p[0].as_f64().unwrap(),
                p[1].as_f64().unwrap(),
                p[2].as_f64().unwrap(),
            )
        })
        .collect();
    assert_eq!(document["space"], "RAS");
    let chosen: Vec<Point> = all.iter().step_by(all.len() / 60).copied().collect();
    let csv = dir.path().join("landmarks.csv");
    let mut text = String::from("label,x,y,z,space\n");
    for (n, p) in chosen.iter().enumerate() {
        text += &format!("P{n:02},{},{},{},RAS\n", p.x, p.y, p.z);
    }
    std::fs::write(&csv, text).unwrap();

    let run = |name: &str, scales: &str| {
        let output = dir.path().join(name);
        let out = crestline(&[
            "transfer",
            MNI,
            csv.to_str().unwrap(),
            subject.to_str().unwrap(),
            "-o",
            output.to_str().unwrap(),
            "--level",
            "60",
            "--template-lines",
            lines.to_str().unwrap(),
            "--scales",
            scales,
        ]);
        assert!(out.status.success(), "{}", stderr(&out));
        let found = control_points(&output);
        let labels: Vec<String> = (0..chosen.len()).map(|n| format!("P{n:02}")).collect();
        assert_eq!(
            found.iter().map(|(l, _)| l.clone()).collect::<Vec<_>>(),
            labels
        );
        let errors: Vec<f64> = found
            .iter()
            .zip(&chosen)
            .map(|((_, lps), p)| {
                let truth = to_subject(p);
                (Point::new(-lps.x, -lps.y, lps.z) - truth).norm()
            })
            .collect();
        median(errors)
    };
    let deformed = run("deformed.mrk.json", "24,16,10,6,4");
    // One huge scale: a rigid motion and a near-uniform shift.
    let rigid = run("rigid.mrk.json", "1000");
    eprintln!("median error: rigid {rigid:.2} mm, deformed {deformed:.2} mm");
    // Measured: 3.80 mm rigid, 0.58 mm deformed.
    assert!(rigid > 2.5, "the warp should not be rigid: {rigid} mm");
    assert!(deformed < 0.9, "{deformed} mm; rigid {rigid} mm");
}

//! The isosurface's area against VTK's flying edges (`vtkFlyingEdges3D`) on the same
//! samples: a gyroid, whose many saddles make ambiguous faces, and a sphere. Skipped
//! with a message when python3 with vtk and numpy is not installed
//! (`pip install -r tools/requirements.txt`).

use crate::common;

use crestline::isosurface::isosurface;
use crestline::volume::Volume;
use nalgebra::Matrix3;

/// Reads `n³` little-endian f32 samples (x fastest) from a raw file and prints the
/// area of VTK's flying-edges isosurface at `level`.
const VTK_AREA: &str = r#"
import sys
import numpy as np
import vtk
from vtk.util import numpy_support
path, n, level = sys.argv[1], int(sys.argv[2]), float(sys.argv[3])
samples = np.fromfile(path, dtype="<f4")
image = vtk.vtkImageData()
image.SetDimensions(n, n, n)
image.GetPointData().SetScalars(numpy_support.numpy_to_vtk(samples, deep=True))
surface = vtk.vtkFlyingEdges3D()
surface.SetInputData(image)
surface.SetValue(0, level)
properties = vtk.vtkMassProperties()
properties.SetInputConnection(surface.GetOutputPort())
properties.Update()
print(properties.GetSurfaceArea())
"#;

fn vtk_available() -> bool {
    let probe = common::python().args(["-c", "import vtk, numpy"]).output();
    let ok = probe.is_ok_and(|out| out.status.success());
    if !ok {
        common::skip(
            "python3 with vtk and numpy is not installed (pip install -r tools/requirements.txt)",
        );
    }
    ok
}

fn sampled(n: usize, f: impl Fn(f64, f64, f64) -> f64) -> Volume {
    let samples = (0..n * n * n)
        .map(|i| f((i % n) as f64, ((i / n) % n) as f64, (i / (n * n)) as f64) as f32)
        .collect();
    Volume::new([n; 3], [1.0; 3], [0.0; 3], Matrix3::identity(), samples).unwrap()
}

fn our_area(volume: &Volume, level: f64) -> f64 {
    let soup = isosurface(volume, level).unwrap().into_soup();
    soup.triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|v| soup.positions[v as usize]);
            0.5 * (b - a).cross(&(c - a)).norm()
        })
        .sum()
}

fn vtk_area(volume: &Volume, level: f64) -> f64 {
    let dir = tempfile::tempdir().unwrap();
    let raw = dir.path().join("samples.raw");
    let bytes: Vec<u8> = volume
        .samples()
        .iter()
        .flat_map(|s| s.to_le_bytes())
        .collect();
    std::fs::write(&raw, bytes).unwrap();
    let out = common::python()
        .args(["-c", VTK_AREA])
        .arg(&raw)
        .arg(volume.dims()[0].to_string())
        .arg(level.to_string())
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout)
        .unwrap()
        .trim()
        .parse()
        .unwrap()
}

#[test]
fn area_agrees_with_vtk_flying_edges_within_two_percent() {
    if !vtk_available() {
        return;
    }
    let w = 2.0 * std::f64::consts::PI / 16.0;
    let gyroid = sampled(48, |x, y, z| {
        (w * x).sin() * (w * y).cos()
            + (w * y).sin() * (w * z).cos()
            + (w * z).sin() * (w * x).cos()
    });
    let sphere = sampled(40, |x, y, z| {
        15.0 - ((x - 19.5).powi(2) + (y - 19.5).powi(2) + (z - 19.5).powi(2)).sqrt()
    });
    for (name, volume, level) in [("gyroid", &gyroid, 0.2), ("sphere", &sphere, 0.0)] {
        let (ours, theirs) = (our_area(volume, level), vtk_area(volume, level));
        let ratio = ours / theirs;
        eprintln!("{name}: area {ours:.1} here, {theirs:.1} by VTK, ratio {ratio:.4}");
        assert!((ratio - 1.0).abs() < 0.02, "{name}: area ratio {ratio}");
    }
}

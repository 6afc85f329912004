//! The NIfTI files that ship in nibabel's test data (big- and little-endian, NIfTI-1
//! and NIfTI-2, 3-D and 4-D, sform, qform), read by crestline and by nibabel and
//! compared: dimensions, voxel sizes, the voxel-to-world affine and the scaled
//! samples of the first 3-D volume.
//!
//! The files are fetched by `tools/fetch_nibabel_data.sh` into `data/nibabel/`; the
//! test is skipped, with a message, when they or nibabel are absent.

use crate::common;
use std::path::{Path, PathBuf};

use crestline::io::read_volume;
use crestline::volume::Volume;

/// Every how many voxels (x fastest) a sample is compared.
const STRIDE: usize = 97;

/// Prints, as JSON, what nibabel reads from the file given as argument.
const NIBABEL_DUMP: &str = r#"
import json, sys
import nibabel as nib
import numpy as np
img = nib.load(sys.argv[1])
hdr = img.header
data = np.asanyarray(img.dataobj, dtype=np.float64)
while data.ndim > 3:
    data = data[..., 0]
while data.ndim < 3:
    data = data[..., np.newaxis]
print(json.dumps({
    "shape": list(data.shape),
    "zooms": [float(z) for z in hdr.get_zooms()[:3]],
    "has_form": bool(int(hdr["sform_code"]) > 0 or int(hdr["qform_code"]) > 0),
    "affine": img.affine.tolist(),
    "samples": [None if np.isnan(v) else v
                for v in data.ravel(order="F")[::int(sys.argv[2])].tolist()],
}))
"#;

/// What nibabel read.
#[derive(serde::Deserialize)]
struct Reference {
    shape: Vec<usize>,
    zooms: Vec<f64>,
    has_form: bool,
    affine: Vec<Vec<f64>>,
    /// `None` for NaN (JSON has no NaN).
    samples: Vec<Option<f64>>,
}

fn data_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../data/nibabel")
}

/// The fetched files, or `None` (after saying why) when the test cannot run.
fn inputs() -> Option<Vec<PathBuf>> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(data_dir())
        .map(|dir| dir.filter_map(|e| Some(e.ok()?.path())).collect())
        .unwrap_or_default();
    files.retain(|p| p.to_string_lossy().contains(".nii"));
    files.sort();
    if files.is_empty() {
        common::skip("no data/nibabel/*.nii*; run tools/fetch_nibabel_data.sh");
        return None;
    }
    let nibabel = common::python().args(["-c", "import nibabel"]).output();
    if !nibabel.is_ok_and(|out| out.status.success()) {
        common::skip(
            "python3 with nibabel is not installed (pip install -r tools/requirements.txt)",
        );
        return None;
    }
    Some(files)
}

fn nibabel_reads(path: &Path) -> Reference {
    let out = common::python()
        .args(["-c", NIBABEL_DUMP])
        .arg(path)
        .arg(STRIDE.to_string())
        .output()
        .expect("python3 runs");
    assert!(
        out.status.success(),
        "nibabel failed on {}: {}",
        path.display(),
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("the dump is JSON")
}

/// Voxel `(i, j, k)`'s world position by the volume, and by the nibabel affine.
fn compare_geometry(name: &str, volume: &Volume, reference: &Reference) {
    let spacing = volume.spacing();
    for axis in 0..3 {
        let zoom = reference.zooms[axis];
        assert!(
            (spacing[axis] - zoom).abs() < 1e-5 * zoom,
            "{name}: spacing {spacing:?}, nibabel's zooms {:?}",
            reference.zooms
        );
    }
    if !reference.has_form {
        // Without sform or qform, NIfTI places voxel (0,0,0) at the origin while
        // nibabel centres the image: only the voxel sizes are comparable.
        return;
    }
    let a = &reference.affine;
    for index in [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [3.0, 2.0, 1.0],
    ] {
        let ours = volume.index_to_world(index);
        for row in 0..3 {
            let theirs = (0..3).map(|c| a[row][c] * index[c]).sum::<f64>() + a[row][3];
            assert!(
                (ours[row] - theirs).abs() < 1e-4,
                "{name}: voxel {index:?} at {ours:?} here, row {row} is {theirs} by nibabel"
            );
        }
    }
}

fn compare_samples(name: &str, volume: &Volume, reference: &Reference) {
    let expected_len = volume.len().div_ceil(STRIDE);
    assert_eq!(
        reference.samples.len(),
        expected_len,
        "{name}: sample count"
    );
    for (n, &theirs) in reference.samples.iter().enumerate() {
        let ours = f64::from(volume.samples()[n * STRIDE]);
        let Some(theirs) = theirs else {
            assert!(
                ours.is_nan(),
                "{name}: sample {} is {ours}, NaN by nibabel",
                n * STRIDE
            );
            continue;
        };
        assert!(
            (ours - theirs).abs() <= 1e-6 * theirs.abs().max(1.0),
            "{name}: sample {} is {ours} here, {theirs} by nibabel",
            n * STRIDE
        );
    }
}

#[test]
fn nibabel_test_files_read_as_nibabel_reads_them() {
    let Some(files) = inputs() else { return };
    for path in &files {
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        let volume = read_volume(path).unwrap_or_else(|e| panic!("{name}: {e}"));
        let reference = nibabel_reads(path);
        assert_eq!(
            volume.dims().to_vec(),
            reference.shape,
            "{name}: dimensions"
        );
        compare_geometry(&name, &volume, &reference);
        compare_samples(&name, &volume, &reference);
        eprintln!("{name}: {:?} voxels agree with nibabel", volume.dims());
    }
}

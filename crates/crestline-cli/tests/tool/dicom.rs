//! DICOM folders on the command line, with pydicom's test files (fetched by
//! `tools/fetch_pydicom_data.sh`; each test is skipped, saying so, without them):
//! several series refused with their UIDs unless `--series` chooses one, and the
//! files of a series protected from being written over.

use std::path::{Path, PathBuf};

use crate::common;

use common::{assert_one_line_error, crestline};

const MR: &str = "1.3.6.1.4.1.5962.1.3.4.1.20040826185059.5457";
const CT: &str = "1.3.6.1.4.1.5962.1.3.1.1.20040119072730.12322";

/// A folder holding pydicom's MR and CT slices (two series), or `None` when they
/// are not fetched.
fn two_series() -> Option<tempfile::TempDir> {
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../data/dicom/pydicom");
    let dir = tempfile::tempdir().unwrap();
    for name in ["MR_small.dcm", "CT_small.dcm"] {
        let source: PathBuf = data.join(name);
        if !source.is_file() {
            common::skip(&format!(
                "{} is absent (run tools/fetch_pydicom_data.sh)",
                source.display()
            ));
            return None;
        }
        std::fs::copy(&source, dir.path().join(name)).unwrap();
    }
    Some(dir)
}

#[test]
fn two_series_exit_with_their_uids_unless_one_is_chosen() {
    let Some(dir) = two_series() else {
        return;
    };
    let folder = dir.path().to_str().unwrap();
    let out = crestline(&["info", folder]);
    assert_one_line_error(&out, folder, "holds 2 series");
    let err = common::stderr(&out);
    assert!(err.contains(MR) && err.contains(CT), "{err}");
    assert!(err.contains("(the option --series)"), "{err}");
    let out = crestline(&["info", folder, "--series", CT]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{}", common::stderr(&out));
    assert!(
        text.contains("128 × 128 × 1") && text.contains("LPS"),
        "{text}"
    );
    let out = crestline(&["info", folder, "--series", "1.2.3"]);
    assert_one_line_error(&out, folder, "holds no series 1.2.3");
}

#[test]
fn the_files_of_a_series_are_not_written_over() {
    let Some(dir) = two_series() else {
        return;
    };
    let folder = dir.path().to_str().unwrap();
    // A slice is told by its DICM mark, whatever its name: one named like a mesh.
    let target = dir.path().join("slice.ply");
    std::fs::rename(dir.path().join("CT_small.dcm"), &target).unwrap();
    let out = crestline(&[
        "iso",
        folder,
        "--level",
        "0",
        "-o",
        target.to_str().unwrap(),
    ]);
    assert_one_line_error(
        &out,
        target.to_str().unwrap(),
        "would replace the data file",
    );
}

#[test]
fn series_apply_to_images_only() {
    let out = crestline(&[
        "ridges",
        "meshes/bunny.obj",
        "--series",
        MR,
        "-o",
        "unused.json",
    ]);
    assert_one_line_error(&out, "meshes/bunny.obj", "--series apply to 3D images");
}

//! DICOM input on the files that ship in pydicom's test data: one MR slice in
//! every transfer syntax, JPEG extended images, a CT slice with a rescale, RT dose
//! grids as multi-frame files, a deflated image, a truncated file and a DICOMDIR.
//!
//! The files are fetched by `tools/fetch_pydicom_data.sh` into
//! `data/dicom/pydicom/`; each test is skipped, with a message, when they are
//! absent.

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use crestline::io::{read_volume, volume_files, VolumeReadOptions};
use crestline::volume::Volume;
use crestline::Space;

use crate::common::{self, mutation};

fn data_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../data/dicom/pydicom")
}

/// The fetched file `name`, or `None` (after saying why) when it is absent.
fn fetched(name: &str) -> Option<PathBuf> {
    let path = data_dir().join(name);
    if path.is_file() {
        Some(path)
    } else {
        common::skip(&format!(
            "{} is absent (run tools/fetch_pydicom_data.sh)",
            path.display()
        ));
        None
    }
}

fn read(name: &str) -> Option<Volume> {
    let path = fetched(name)?;
    Some(read_volume(&path).unwrap_or_else(|e| panic!("{e}")))
}

fn error(name: &str) -> Option<String> {
    let path = fetched(name)?;
    Some(read_volume(&path).unwrap_err().to_string())
}

#[test]
fn every_decodable_transfer_syntax_gives_the_same_samples() {
    let Some(reference) = read("MR_small.dcm") else {
        return;
    };
    assert_eq!(reference.dims(), [64, 64, 1]);
    assert_eq!(reference.space(), Some(Space::Lps));
    assert_eq!(reference.origin(), [-83.9063, -91.2, 6.6406]);
    assert_eq!(&reference.spacing()[..2], &[0.3125, 0.3125]);
    let (low, high) = reference.value_range();
    assert!(low < high, "a constant image: {low}..{high}");
    for name in [
        "MR_small_implicit.dcm",
        "MR_small_bigendian.dcm",
        "MR_small_expb.dcm",
        "MR_small_RLE.dcm",
    ] {
        let Some(volume) = read(name) else {
            return;
        };
        assert_eq!(volume, reference, "{name} differs from MR_small.dcm");
    }
}

#[test]
fn jpeg_ls_and_jpeg_2000_are_refused_by_name() {
    for (name, syntax) in [
        ("MR_small_jpeg_ls_lossless.dcm", "JPEG-LS"),
        ("MR_small_jp2klossless.dcm", "JPEG 2000"),
    ] {
        let Some(err) = error(name) else {
            return;
        };
        assert!(err.contains(name), "{err}");
        assert!(err.contains(syntax), "{err}");
        assert!(err.contains("cannot decode"), "{err}");
    }
}

#[test]
fn twelve_bit_jpeg_extended_is_an_error_naming_the_file_and_the_precision() {
    // jpeg-decoder decodes 8-bit lossy JPEG only (and lossless of any precision);
    // these NM images store 12 bits.
    for name in ["JPGExtended.dcm", "JPEG-lossy.dcm"] {
        let Some(err) = error(name) else {
            return;
        };
        assert!(err.contains(name), "{err}");
        assert!(
            err.contains("cannot be decoded") && err.contains("12"),
            "{err}"
        );
    }
}

#[test]
fn the_ct_rescale_gives_hounsfield_units() {
    let Some(volume) = read("CT_small.dcm") else {
        return;
    };
    assert_eq!(volume.dims(), [128, 128, 1]);
    // Rescale Intercept −1024, slope 1, signed 16-bit values. pydicom reads the
    // same file as stored values from −896 + 1024 = 128 to 2191, and its first
    // samples as −849, −844, −858, −881 HU after the rescale.
    assert_eq!(volume.value_range(), (-896.0, 1167.0));
    assert_eq!(&volume.samples()[..4], &[-849.0, -844.0, -858.0, -881.0]);
}

#[test]
fn an_rt_dose_grid_is_a_multi_frame_volume_in_gray() {
    let Some(volume) = read("rtdose.dcm") else {
        return;
    };
    // 15 frames of 10×10 voxels of 10 mm, 5 mm apart (Grid Frame Offset Vector),
    // 32-bit values scaled by the Dose Grid Scaling of 1e-6.
    assert_eq!(volume.dims(), [10, 10, 15]);
    assert_eq!(volume.spacing(), [10.0, 10.0, 5.0]);
    assert_eq!(volume.origin(), [189.43125, 199.43125, -761.87]);
    // pydicom: from 0.795 to 1.254 Gy, summing to 1519.91 Gy.
    let (low, high) = volume.value_range();
    assert!(
        (low - 0.795).abs() < 1e-6 && (high - 1.254).abs() < 1e-6,
        "{low}..{high}"
    );
    let sum: f64 = volume.samples().iter().map(|&v| f64::from(v)).sum();
    assert!((sum - 1519.91).abs() < 1e-3, "{sum}");
    // dicom-rs decodes RLE of 8 and 16 bits only: the 32-bit dose grid in RLE is
    // an error naming the file and why.
    let Some(err) = error("rtdose_rle.dcm") else {
        return;
    };
    assert!(
        err.contains("rtdose_rle.dcm: its pixel data cannot be decoded"),
        "{err}"
    );
    assert!(err.contains("BitsAllocated"), "{err}");
}

#[test]
fn a_deflated_file_reads() {
    let Some(volume) = read("image_dfl.dcm") else {
        return;
    };
    assert_eq!(volume.dims(), [512, 512, 1]);
    let (low, high) = volume.value_range();
    assert!(low < high);
}

#[test]
fn a_truncated_file_is_an_error_naming_it() {
    let Some(err) = error("MR_truncated.dcm") else {
        return;
    };
    assert!(err.contains("MR_truncated.dcm"), "{err}");
    assert!(!err.contains('\n'), "{err}");
}

#[test]
fn a_dicomdir_lists_the_files_it_references() {
    let Some(dicomdir) = fetched("dicomdirtests/TINY_ALPHA/DICOMDIR") else {
        return;
    };
    let files = volume_files(&dicomdir);
    assert_eq!(files[0], dicomdir);
    assert!(files.len() > 10, "{files:?}");
    let image = dicomdir
        .parent()
        .unwrap()
        .join("PT000000/ST000000/SE000000/IM000000");
    assert!(files.contains(&image), "{files:?}");
    // The referenced files are not fetched: reading names the first one missing.
    let err = read_volume(&dicomdir).unwrap_err().to_string();
    assert!(err.contains("IM000000"), "{err}");
}

/// A folder holding copies of `names`.
fn folder_of(names: &[&str]) -> Option<tempfile::TempDir> {
    let dir = tempfile::tempdir().unwrap();
    for name in names {
        std::fs::copy(fetched(name)?, dir.path().join(name)).unwrap();
    }
    Some(dir)
}

#[test]
fn two_series_in_a_folder_are_listed_unless_one_is_chosen() {
    let Some(dir) = folder_of(&["MR_small.dcm", "CT_small.dcm"]) else {
        return;
    };
    std::fs::write(dir.path().join("README.txt"), "not DICOM").unwrap();
    let err = read_volume(dir.path()).unwrap_err().to_string();
    let mr = "1.3.6.1.4.1.5962.1.3.4.1.20040826185059.5457";
    let ct = "1.3.6.1.4.1.5962.1.3.1.1.20040119072730.12322";
    assert!(err.starts_with(&dir.path().display().to_string()), "{err}");
    assert!(
        err.contains("holds 2 series") && err.contains(mr) && err.contains(ct),
        "{err}"
    );
    let options = VolumeReadOptions {
        series: Some(ct.to_string()),
    };
    let chosen = options.read(dir.path()).unwrap();
    assert_eq!(chosen, read("CT_small.dcm").unwrap());
    let files = [dir.path().join("CT_small.dcm")];
    assert_eq!(options.read_dicom(&files).unwrap(), chosen);
}

#[test]
fn a_folder_without_dicom_files_is_an_error_saying_so() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("notes.txt"), "no images here").unwrap();
    let err = read_volume(dir.path()).unwrap_err().to_string();
    assert!(err.contains("holds no DICOM file"), "{err}");
    let nifti = dir.path().join("x.nii");
    let options = VolumeReadOptions {
        series: Some("1.2".to_string()),
    };
    let err = options.read(&nifti).unwrap_err().to_string();
    assert!(err.contains("not DICOM"), "{err}");
}

/// Mutants of each seed file read by [`mutants_never_panic_or_hang`] in a plain
/// `cargo test` (`CRESTLINE_FUZZ_MUTANTS=N` for more).
const MUTANTS: usize = 200;
/// A mutant taking longer than this to read is a hang (a corrupt length that
/// made dicom-rs fill a 4 GiB buffer took 6 s before lengths were checked).
const HANG: Duration = Duration::from_secs(2);

#[test]
fn mutants_never_panic_or_hang() {
    // Bit flips, interesting bytes, truncations, duplicated and deleted chunks of
    // a native, an RLE, a JPEG (extended, 12 bits; baseline) and a native and an
    // RLE multi-frame file: each read ends in a volume or in an error naming the
    // file, on one line, without hanging.
    let dir = tempfile::tempdir().unwrap();
    let kept_dir = Path::new(env!("CARGO_TARGET_TMPDIR"));
    let mut rng = mutation::Rng(0x0d1c_0a11);
    for name in [
        "MR_small.dcm",
        "MR_small_RLE.dcm",
        "JPGExtended.dcm",
        "JPEG-lossy.dcm",
        "rtdose.dcm",
        "rtdose_rle.dcm",
    ] {
        let Some(seed) = fetched(name) else {
            return;
        };
        let seed = std::fs::read(seed).unwrap();
        let count = mutation::env_number("CRESTLINE_FUZZ_MUTANTS").map_or(MUTANTS, |n| n as usize);
        for index in 0..count {
            let (bytes, applied) = mutation::mutate(&seed, &mut rng);
            let path = dir.path().join(format!("{index}-{name}"));
            std::fs::write(&path, &bytes).unwrap();
            let start = Instant::now();
            let outcome = catch_unwind(AssertUnwindSafe(|| read_volume(&path)));
            let elapsed = start.elapsed();
            let kept = kept_dir.join(format!("dicom-mutant-{index}-{name}"));
            let Ok(result) = outcome else {
                std::fs::copy(&path, &kept).unwrap();
                panic!(
                    "{name} mutant {index} ({applied:?}) panicked; kept as {}",
                    kept.display()
                );
            };
            if elapsed > HANG {
                std::fs::copy(&path, &kept).unwrap();
                panic!(
                    "{name} mutant {index} ({applied:?}) took {elapsed:?}; kept as {}",
                    kept.display()
                );
            }
            if let Err(err) = result {
                let message = err.to_string();
                if let Some(problem) = mutation::message_problem(&message, &path) {
                    panic!("{name} mutant {index} ({applied:?}): the error {problem}: {message}");
                }
            }
        }
    }
}

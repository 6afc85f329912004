//! Hostile GIfTI, FreeSurfer and DICOM input built on purpose, one file per way
//! it once went wrong: a pipe or a device in place of a file (it blocked in
//! `open` forever), a GIfTI gzip bomb and a declared size beyond memory (aborts),
//! an element with 200,000 attributes (quadratic parsing), DICOM pixel data that
//! makes dicom-rs's decoders panic (their text on stderr), words a library quoted
//! between backticks (shown as options), and non-finite per-vertex values
//! (reported against the mesh). Each must end with exit code 1 and one `error:`
//! line naming the file at fault.
#![cfg(unix)]

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

use crate::common::{assert_one_line_error, stderr};

/// Long enough for any of these runs on a busy machine; a bound for hangs, not a
/// timing assertion.
const HANG: Duration = Duration::from_secs(60);

/// Run the tool with `args` under a 4 GiB address-space limit, killing it after
/// [`HANG`] (a failure: the run hung).
fn run_bounded(args: &[&str]) -> Output {
    let mut child = Command::new("sh")
        .arg("-c")
        .arg("ulimit -v 4194304 && exec \"$0\" \"$@\"")
        .arg(env!("CARGO_BIN_EXE_crestline"))
        .args(args)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let start = Instant::now();
    while child.try_wait().unwrap().is_none() {
        if start.elapsed() > HANG {
            child.kill().unwrap();
            panic!("crestline {args:?} hung (killed after {HANG:?})");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    child.wait_with_output().unwrap()
}

/// [`assert_one_line_error`], and no panic or abort text.
fn refused(out: &Output, file: &Path, words: &str) {
    let err = stderr(out);
    assert!(!err.contains("panicked"), "{err}");
    assert!(!err.contains("memory allocation"), "{err}");
    assert_one_line_error(out, file.to_str().unwrap(), words);
}

/// A FIFO at `path`.
fn fifo(path: &Path) {
    let made = Command::new("mkfifo").arg(path).status().unwrap();
    assert!(made.success(), "mkfifo {}", path.display());
}

/// A small closed mesh (an octahedron, 6 vertices) as OBJ.
fn octahedron(dir: &Path) -> PathBuf {
    let path = dir.join("octahedron.obj");
    std::fs::write(
        &path,
        "v 1 0 0\nv -1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nv 0 0 -1\n\
         f 1 3 5\nf 3 2 5\nf 2 4 5\nf 4 1 5\nf 3 1 6\nf 2 3 6\nf 4 2 6\nf 1 4 6\n",
    )
    .unwrap();
    path
}

/// A GIfTI file holding `arrays` (`DataArray` elements).
fn gifti(arrays: &str) -> String {
    format!("<?xml version=\"1.0\"?>\n<GIFTI Version=\"1.0\">\n{arrays}</GIFTI>\n")
}

/// A `DataArray` of `dims` with `attributes` more and the encoded `data`.
fn data_array(intent: &str, kind: &str, dims: &[usize], encoding: &str, data: &str) -> String {
    let dim_attributes: String = dims
        .iter()
        .enumerate()
        .map(|(i, d)| format!(" Dim{i}=\"{d}\""))
        .collect();
    format!(
        "<DataArray Intent=\"{intent}\" DataType=\"{kind}\" ArrayIndexingOrder=\"RowMajorOrder\" \
         Dimensionality=\"{}\"{dim_attributes} Encoding=\"{encoding}\" Endian=\"LittleEndian\">\
         <Data>{data}</Data></DataArray>\n",
        dims.len()
    )
}

/// `bytes` zlib-compressed and base64-encoded, as `GZipBase64Binary`.
fn gzip_base64(bytes: impl Iterator<Item = Vec<u8>>) -> String {
    use base64::Engine;
    let mut encoder = flate2::write::ZlibEncoder::new(Vec::new(), flate2::Compression::best());
    for chunk in bytes {
        encoder.write_all(&chunk).unwrap();
    }
    base64::engine::general_purpose::STANDARD.encode(encoder.finish().unwrap())
}

#[test]
fn a_pipe_or_device_named_as_an_input_is_refused_at_once() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = octahedron(dir.path());
    let mesh = mesh.to_str().unwrap();
    let out = dir.path().join("out.ply");
    let out = out.to_str().unwrap();
    for name in [
        "p.surf.gii",
        "lh.pipe",
        "v.nii.gz",
        "v.nrrd",
        "s.dcm",
        "DICOMDIR",
    ] {
        let pipe = dir.path().join(name);
        fifo(&pipe);
        let path = pipe.to_str().unwrap();
        refused(&run_bounded(&["info", path]), &pipe, "not a regular file");
        let level = ["--level", "1"];
        let iso = [&["iso", path, "-o", out][..], &level].concat();
        if name.ends_with(".gz") || name.ends_with(".nrrd") {
            refused(&run_bounded(&iso), &pipe, "not a regular file");
        }
        if name.contains("surf") || name.contains("pipe") {
            refused(
                &run_bounded(&["ridges", path, "-o", out]),
                &pipe,
                "not a regular file",
            );
        }
    }
    let curv = dir.path().join("lh.curv");
    fifo(&curv);
    // A pipe is not an existing file: `--indicator` takes it as a property name.
    let indicator = [
        "morse",
        mesh,
        "--indicator",
        curv.to_str().unwrap(),
        "-o",
        out,
    ];
    refused(
        &run_bounded(&indicator),
        Path::new(mesh),
        "no vertex property",
    );
    let device = Path::new("/dev/zero");
    refused(
        &run_bounded(&["info", "/dev/zero"]),
        device,
        "not a regular file",
    );
    assert!(!Path::new(out).exists());
}

#[test]
fn a_gifti_gzip_bomb_or_a_size_beyond_memory_is_refused_naming_the_file() {
    let dir = tempfile::tempdir().unwrap();
    // 1 GiB of zeros: 89,478,485 points (1.4 MB compressed), and one triangle.
    let points = (1usize << 30) / 12;
    let zeros = (0..1024).map(|_| vec![0u8; 1 << 20]);
    let corners: Vec<u8> = [0i32, 1, 2].iter().flat_map(|c| c.to_le_bytes()).collect();
    let bomb = gifti(
        &(data_array(
            "NIFTI_INTENT_POINTSET",
            "NIFTI_TYPE_FLOAT32",
            &[points, 3],
            "GZipBase64Binary",
            &gzip_base64(
                zeros
                    .take((points * 12) >> 20)
                    .chain([vec![0u8; points * 12 % (1 << 20)]]),
            ),
        ) + &data_array(
            "NIFTI_INTENT_TRIANGLE",
            "NIFTI_TYPE_INT32",
            &[1, 3],
            "GZipBase64Binary",
            &gzip_base64([corners].into_iter()),
        )),
    );
    let bomb_path = dir.path().join("bomb.surf.gii");
    std::fs::write(&bomb_path, bomb).unwrap();
    assert!(std::fs::metadata(&bomb_path).unwrap().len() < 2 << 20);
    let err = run_bounded(&["info", bomb_path.to_str().unwrap()]);
    refused(&err, &bomb_path, "more than can be allocated");
    // 4.4 GB declared over 4.3 MB of incompressible data (within deflate's ratio):
    // nothing is reserved before the data is inflated.
    let mut noise = Vec::with_capacity(4_300_000);
    let mut state = 0x2545_f491_4f6c_dd1du64;
    while noise.len() < 4_300_000 {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        noise.extend(state.to_le_bytes());
    }
    let declared = 1_100_000_000;
    let shape = gifti(&data_array(
        "NIFTI_INTENT_SHAPE",
        "NIFTI_TYPE_FLOAT32",
        &[declared],
        "GZipBase64Binary",
        &gzip_base64([noise].into_iter()),
    ));
    let shape_path = dir.path().join("w.shape.gii");
    std::fs::write(&shape_path, shape).unwrap();
    let mesh = octahedron(dir.path());
    let out = dir.path().join("out.ply");
    let args = [
        "ridges",
        mesh.to_str().unwrap(),
        "--smoothing-weights",
        shape_path.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ];
    refused(
        &run_bounded(&args),
        &shape_path,
        "where the dimensions declare",
    );
    assert!(!out.exists());
}

#[test]
fn a_gifti_element_with_200000_attributes_is_refused_in_linear_time() {
    let dir = tempfile::tempdir().unwrap();
    let attributes: String = (0..200_000).map(|i| format!(" a{i}=\"{i}\"")).collect();
    let text = gifti("").replace("<GIFTI Version=\"1.0\">", &format!("<GIFTI{attributes}>"));
    assert!(text.len() > 3_000_000);
    let path = dir.path().join("many.surf.gii");
    std::fs::write(&path, text).unwrap();
    let out = run_bounded(&["info", path.to_str().unwrap()]);
    refused(&out, &path, "line 2: an element with 200000 attributes");
}

#[test]
fn non_finite_or_negative_values_are_reported_against_the_values_file() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = octahedron(dir.path());
    let mesh = mesh.to_str().unwrap();
    let out = dir.path().join("out.ply");
    let out = out.to_str().unwrap();
    // A FreeSurfer curv file: magic, vertex and face counts, one value each.
    let mut curv = vec![0xFF, 0xFF, 0xFF];
    for word in [6i32, 8, 1] {
        curv.extend(word.to_be_bytes());
    }
    for value in [0.5f32, 1.0, 2.0, f32::INFINITY, 0.0, 1.0] {
        curv.extend(value.to_be_bytes());
    }
    let curv_path = dir.path().join("lh.curv");
    std::fs::write(&curv_path, curv).unwrap();
    let args = [
        "morse",
        mesh,
        "--indicator",
        curv_path.to_str().unwrap(),
        "-o",
        out,
    ];
    refused(
        &run_bounded(&args),
        &curv_path,
        "the value of vertex 3 is inf",
    );
    let shape = gifti(&data_array(
        "NIFTI_INTENT_SHAPE",
        "NIFTI_TYPE_FLOAT32",
        &[6],
        "ASCII",
        "1 1 -2 1 1 1",
    ));
    let shape_path = dir.path().join("w.shape.gii");
    std::fs::write(&shape_path, shape).unwrap();
    let args = [
        "ridges",
        mesh,
        "--smoothing-weights",
        shape_path.to_str().unwrap(),
        "-o",
        out,
    ];
    refused(
        &run_bounded(&args),
        &shape_path,
        "the value of vertex 2 is -2",
    );
    assert!(!Path::new(out).exists());
}

/// pydicom's test file `name`, or `None` (saying why) when it is absent.
fn pydicom_file(name: &str) -> Option<PathBuf> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../data/dicom/pydicom")
        .join(name);
    if path.is_file() {
        Some(path)
    } else {
        crate::common::skip(&format!(
            "{} is absent (run tools/fetch_pydicom_data.sh)",
            path.display()
        ));
        None
    }
}

/// The position of the RLE header of the first frame of `bytes` (two segments,
/// the first at byte 64).
fn rle_header(bytes: &[u8]) -> usize {
    let header = [2u8, 0, 0, 0, 64, 0, 0, 0];
    bytes
        .windows(header.len())
        .position(|w| w == header)
        .expect("an RLE header")
}

#[test]
fn corrupt_rle_data_is_one_error_line_without_panic_text() {
    let Some(source) = pydicom_file("MR_small_RLE.dcm") else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let bytes = std::fs::read(source).unwrap();
    let at = rle_header(&bytes);
    let write = |name: &str, change: &dyn Fn(&mut Vec<u8>)| {
        let mut mutant = bytes.clone();
        change(&mut mutant);
        let path = dir.path().join(name);
        std::fs::write(&path, mutant).unwrap();
        path
    };
    // 0xFFFFFFFF segments (16 GiB of offsets once); a second segment that starts
    // past the data; an empty second segment, which made the decoder index past
    // what it decoded and panic on a worker thread.
    let huge = write("huge.dcm", &|m| m[at..at + 4].copy_from_slice(&[0xFF; 4]));
    refused(
        &run_bounded(&["info", huge.to_str().unwrap()]),
        &huge,
        "4294967295 segments",
    );
    let past = write("past.dcm", &|m| {
        m[at + 8..at + 12].copy_from_slice(&0x7FFF_FFFFu32.to_le_bytes())
    });
    refused(
        &run_bounded(&["info", past.to_str().unwrap()]),
        &past,
        "segment 2 at byte",
    );
    let end = bytes[at..]
        .windows(4)
        .position(|w| w == [0xFE, 0xFF, 0xDD, 0xE0])
        .map_or(bytes.len() - at, |p| p);
    let empty = write("empty.dcm", &|m| {
        m[at + 8..at + 12].copy_from_slice(&(end as u32).to_le_bytes())
    });
    refused(
        &run_bounded(&["info", empty.to_str().unwrap()]),
        &empty,
        "cannot be decoded",
    );
}

#[test]
fn a_jpeg_frame_header_larger_than_the_image_is_refused() {
    let Some(source) = pydicom_file("JPEG-lossy.dcm") else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let mut bytes = std::fs::read(source).unwrap();
    // The frame header (FF C0 or C1, length, precision, height, width) after the
    // image's start (FF D8).
    let start = bytes
        .windows(3)
        .position(|w| w == [0xFF, 0xD8, 0xFF])
        .expect("a JPEG image");
    let sof = start
        + bytes[start..]
            .windows(2)
            .position(|w| w[0] == 0xFF && (w[1] == 0xC0 || w[1] == 0xC1))
            .expect("a JPEG frame header");
    bytes[sof + 5..sof + 9].copy_from_slice(&[0xFF; 4]);
    let path = dir.path().join("big.dcm");
    std::fs::write(&path, bytes).unwrap();
    let out = run_bounded(&["info", path.to_str().unwrap()]);
    refused(&out, &path, "a 65535 × 65535 image");
}

//! The image readers: small files of every format written byte by byte here, read
//! back and compared sample by sample, malformed and truncated files refused with a
//! message naming the file, and the bundled MNI152 template.

use std::io::Write;
use std::path::{Path, PathBuf};

use crate::io::{read_raw_volume, read_volume, SampleType};
use crate::volume::Volume;
use nalgebra::Matrix3;

/// The test grid: 4 × 3 × 2 voxels.
const DIMS: [usize; 3] = [4, 3, 2];
const VOXELS: usize = 24;

/// Sample `n` of the ramp: distinct, and negative for half of them so that signed
/// types are exercised (shifted to be non-negative for unsigned types).
fn ramp(n: usize, signed: bool) -> f64 {
    let value = n as f64 * 5.0 - 60.0;
    if signed {
        value
    } else {
        value + 60.0
    }
}

/// The ramp's samples encoded as `sample_type` in the given byte order.
fn encode(sample_type: SampleType, little: bool) -> (Vec<u8>, Vec<f32>) {
    let signed = matches!(
        sample_type,
        SampleType::I8 | SampleType::I16 | SampleType::I32 | SampleType::F32 | SampleType::F64
    );
    let mut bytes = Vec::new();
    let mut values = Vec::new();
    for n in 0..VOXELS {
        let v = ramp(n, signed);
        values.push(v as f32);
        let mut encoded = match sample_type {
            SampleType::U8 => vec![v as u8],
            SampleType::I8 => vec![(v as i8) as u8],
            SampleType::I16 => (v as i16).to_le_bytes().to_vec(),
            SampleType::U16 => (v as u16 * 300).to_le_bytes().to_vec(),
            SampleType::I32 => (v as i32 * 100_000).to_le_bytes().to_vec(),
            SampleType::U32 => (v as u32 * 100_000).to_le_bytes().to_vec(),
            SampleType::F32 => ((v as f32) * 0.25).to_le_bytes().to_vec(),
            SampleType::F64 => (v * 0.25).to_le_bytes().to_vec(),
        };
        *values.last_mut().unwrap() = match sample_type {
            SampleType::U16 => (v * 300.0) as f32,
            SampleType::I32 | SampleType::U32 => (v * 100_000.0) as f32,
            SampleType::F32 | SampleType::F64 => (v * 0.25) as f32,
            _ => v as f32,
        };
        if !little {
            encoded.reverse();
        }
        bytes.extend(encoded);
    }
    (bytes, values)
}

const ALL_TYPES: [SampleType; 8] = [
    SampleType::U8,
    SampleType::I8,
    SampleType::I16,
    SampleType::U16,
    SampleType::I32,
    SampleType::U32,
    SampleType::F32,
    SampleType::F64,
];

fn gzip(bytes: &[u8]) -> Vec<u8> {
    let mut encoder = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::fast());
    encoder.write_all(bytes).unwrap();
    encoder.finish().unwrap()
}

fn write(dir: &Path, name: &str, bytes: &[u8]) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, bytes).unwrap();
    path
}

fn assert_close(actual: [f64; 3], expected: [f64; 3]) {
    for (a, e) in actual.iter().zip(expected) {
        assert!((a - e).abs() < 1e-5, "{actual:?} != {expected:?}");
    }
}

fn assert_direction(volume: &Volume, expected: Matrix3<f64>) {
    assert!(
        (volume.direction() - expected).abs().max() < 1e-6,
        "direction {} != {expected}",
        volume.direction()
    );
}

/// The error of reading `path`, checked to name the file and contain `word`.
fn read_error(path: &Path, word: &str) -> String {
    let message = read_volume(path).unwrap_err().to_string();
    let name = path.file_name().unwrap().to_str().unwrap();
    assert!(message.contains(name), "no file name in: {message}");
    assert!(message.contains(word), "no '{word}' in: {message}");
    message
}

// ---------------------------------------------------------------- NIfTI

/// A NIfTI header, written field by field at the offsets of nifti1.h / nifti2.h.
#[derive(Clone)]
struct Nifti {
    version: u8,
    little: bool,
    dim: [i64; 8],
    datatype: i16,
    pixdim: [f64; 8],
    vox_offset: i64,
    scl: [f64; 2],
    qform_code: i32,
    sform_code: i32,
    quatern: [f64; 6],
    srow: [[f64; 4]; 3],
}

impl Nifti {
    fn new(version: u8, little: bool, datatype: i16) -> Nifti {
        Nifti {
            version,
            little,
            dim: [3, 4, 3, 2, 1, 1, 1, 1],
            datatype,
            pixdim: [1.0, 0.5, 1.5, 2.0, 1.0, 1.0, 1.0, 1.0],
            vox_offset: if version == 1 { 352 } else { 544 },
            scl: [0.0, 0.0],
            qform_code: 0,
            sform_code: 0,
            quatern: [0.0; 6],
            srow: [[0.0; 4]; 3],
        }
    }

    fn put(&self, out: &mut [u8], at: usize, bytes: &[u8]) {
        let mut bytes = bytes.to_vec();
        if !self.little {
            bytes.reverse();
        }
        out[at..at + bytes.len()].copy_from_slice(&bytes);
    }

    /// Write an integer field `width` bytes wide.
    fn int(&self, out: &mut [u8], at: usize, width: usize, value: i64) {
        match width {
            2 => self.put(out, at, &(value as i16).to_le_bytes()),
            4 => self.put(out, at, &(value as i32).to_le_bytes()),
            _ => self.put(out, at, &value.to_le_bytes()),
        }
    }

    /// Write a float field (f32 in NIfTI-1, f64 in NIfTI-2).
    fn float(&self, out: &mut [u8], at: usize, value: f64) {
        if self.version == 1 {
            self.put(out, at, &(value as f32).to_le_bytes());
        } else {
            self.put(out, at, &value.to_le_bytes());
        }
    }

    fn bytes(&self, data: &[u8]) -> Vec<u8> {
        let v1 = self.version == 1;
        let mut out = vec![0u8; self.vox_offset as usize];
        let (f, i_dim, dim_at) = if v1 { (4, 2, 40) } else { (8, 8, 16) };
        self.int(&mut out, 0, 4, if v1 { 348 } else { 540 });
        if v1 {
            out[344..348].copy_from_slice(b"n+1\0");
        } else {
            out[4..12].copy_from_slice(b"n+2\0\r\n\x1a\n");
        }
        for (n, &d) in self.dim.iter().enumerate() {
            self.int(&mut out, dim_at + n * i_dim, i_dim, d);
        }
        self.int(&mut out, if v1 { 70 } else { 12 }, 2, self.datatype.into());
        let pixdim_at = if v1 { 76 } else { 104 };
        for (n, &p) in self.pixdim.iter().enumerate() {
            self.float(&mut out, pixdim_at + n * f, p);
        }
        if v1 {
            self.float(&mut out, 108, self.vox_offset as f64);
        } else {
            self.int(&mut out, 168, 8, self.vox_offset);
        }
        let scl_at = if v1 { 112 } else { 176 };
        self.float(&mut out, scl_at, self.scl[0]);
        self.float(&mut out, scl_at + f, self.scl[1]);
        let (codes_at, code_width) = if v1 { (252, 2) } else { (344, 4) };
        self.int(&mut out, codes_at, code_width, self.qform_code.into());
        self.int(
            &mut out,
            codes_at + code_width,
            code_width,
            self.sform_code.into(),
        );
        let quatern_at = if v1 { 256 } else { 352 };
        for (n, &q) in self.quatern.iter().enumerate() {
            self.float(&mut out, quatern_at + n * f, q);
        }
        let srow_at = if v1 { 280 } else { 400 };
        for (row, values) in self.srow.iter().enumerate() {
            for (n, &s) in values.iter().enumerate() {
                self.float(&mut out, srow_at + (row * 4 + n) * f, s);
            }
        }
        out.extend_from_slice(data);
        out
    }
}

/// A rotation by 90° about z: x → y, y → -x.
fn quarter_turn() -> Matrix3<f64> {
    Matrix3::new(0.0, -1.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0)
}

#[test]
fn nifti_every_type_version_and_byte_order() {
    let dir = tempfile::tempdir().unwrap();
    let codes = [2, 256, 4, 512, 8, 768, 16, 64];
    for version in [1, 2] {
        for little in [true, false] {
            for (sample_type, code) in ALL_TYPES.into_iter().zip(codes) {
                let (data, values) = encode(sample_type, little);
                let header = Nifti::new(version, little, code);
                let name = format!("v{version}_{little}_{code}.nii");
                let path = write(dir.path(), &name, &header.bytes(&data));
                let volume = read_volume(&path).unwrap_or_else(|e| panic!("{e}"));
                assert_eq!(volume.dims(), DIMS, "{name}");
                assert_close(volume.spacing(), [0.5, 1.5, 2.0]);
                assert_close(volume.origin(), [0.0; 3]);
                assert_direction(&volume, Matrix3::identity());
                assert_eq!(volume.samples(), values.as_slice(), "{name}");
            }
        }
    }
}

#[test]
fn nifti_sform_gives_the_affine() {
    let dir = tempfile::tempdir().unwrap();
    let (data, values) = encode(SampleType::U8, true);
    let mut header = Nifti::new(1, true, 2);
    header.sform_code = 1;
    header.qform_code = 1; // ignored: the sform wins
    header.quatern = [0.0, 0.0, 1.0, 7.0, 7.0, 7.0];
    // Index axes: i along world y (0.5 mm), j along -x (1.5 mm), k along z (2 mm).
    header.srow = [
        [0.0, -1.5, 0.0, 10.0],
        [0.5, 0.0, 0.0, -20.0],
        [0.0, 0.0, 2.0, 30.0],
    ];
    let path = write(dir.path(), "sform.nii.gz", &gzip(&header.bytes(&data)));
    let volume = read_volume(&path).unwrap();
    assert_eq!(volume.samples(), values.as_slice());
    assert_close(volume.spacing(), [0.5, 1.5, 2.0]);
    assert_close(volume.origin(), [10.0, -20.0, 30.0]);
    assert_direction(&volume, quarter_turn());
    let corner = volume.index_to_world([3.0, 2.0, 1.0]);
    assert_close(corner.into(), [10.0 - 3.0, -20.0 + 1.5, 32.0]);
    assert_close(volume.world_to_index(&corner), [3.0, 2.0, 1.0]);
}

#[test]
fn nifti_qform_quaternion_and_qfac() {
    let dir = tempfile::tempdir().unwrap();
    let (data, values) = encode(SampleType::I16, false);
    let mut header = Nifti::new(2, false, 4);
    header.qform_code = 1;
    let half = std::f64::consts::FRAC_1_SQRT_2;
    header.quatern = [0.0, 0.0, half, 1.0, 2.0, 3.0];
    header.pixdim[0] = -1.0;
    let path = write(dir.path(), "qform.nii.gz", &gzip(&header.bytes(&data)));
    let volume = read_volume(&path).unwrap();
    assert_eq!(volume.samples(), values.as_slice());
    assert_close(volume.spacing(), [0.5, 1.5, 2.0]);
    assert_close(volume.origin(), [1.0, 2.0, 3.0]);
    let mut expected = quarter_turn();
    expected[(2, 2)] = -1.0;
    assert_direction(&volume, expected);
}

#[test]
fn nifti_scaling_and_the_first_volume_of_a_4d_image() {
    let dir = tempfile::tempdir().unwrap();
    let (mut data, values) = encode(SampleType::U8, true);
    data.extend(vec![255u8; VOXELS]);
    let mut header = Nifti::new(1, true, 2);
    header.dim = [4, 4, 3, 2, 2, 1, 1, 1];
    header.scl = [2.0, -1.0];
    let path = write(dir.path(), "scaled4d.nii", &header.bytes(&data));
    let volume = read_volume(&path).unwrap();
    assert_eq!(volume.dims(), DIMS);
    let scaled: Vec<f32> = values.iter().map(|v| v * 2.0 - 1.0).collect();
    assert_eq!(volume.samples(), scaled.as_slice());
}

#[test]
fn nifti_scaling_beyond_float_range_is_refused_naming_the_fields() {
    let dir = tempfile::tempdir().unwrap();
    let (data, _) = encode(SampleType::U8, true);
    let mut header = Nifti::new(1, true, 2);
    header.scl = [1e38, 0.0];
    let path = write(dir.path(), "overflow.nii", &header.bytes(&data));
    let message = read_error(&path, "scl_slope 1e38 and scl_inter 0 scale the sample");
    assert!(
        message.contains("beyond the range of 32-bit floats"),
        "{message}"
    );
    // A large slope that keeps every sample finite is fine.
    header.scl = [1e30, 0.0];
    let path = write(dir.path(), "large.nii", &header.bytes(&data));
    let volume = read_volume(&path).unwrap();
    assert!(volume.samples().iter().all(|v| v.is_finite()));
}

#[test]
fn a_gzip_stream_shorter_than_its_header_claims_fails_after_what_it_holds() {
    // 64 MiB of zeros compress to about 64 KiB; the header claims 1024³ samples.
    let dir = tempfile::tempdir().unwrap();
    let mut header = Nifti::new(1, true, 2);
    header.dim = [3, 1024, 1024, 1024, 1, 1, 1, 1];
    let bytes = header.bytes(&vec![0u8; 64 << 20]);
    let path = write(dir.path(), "bomb.nii.gz", &gzip(&bytes));
    assert!(std::fs::metadata(&path).unwrap().len() < 1 << 20);
    read_error(&path, "data ends after 67108864 of 1073741824 bytes");
}

#[test]
fn nifti_malformed_files_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let (data, _) = encode(SampleType::I16, true);
    let good = Nifti::new(1, true, 4).bytes(&data);

    let path = write(dir.path(), "short_header.nii", &good[..100]);
    let message = read_error(&path, "ends after 100 of 348 bytes");
    assert!(message.contains("header"), "{message}");
    let path = write(dir.path(), "short_data.nii", &good[..good.len() - 5]);
    read_error(&path, "data ends after 43 of 48 bytes");
    let path = write(dir.path(), "short.nii.gz", &gzip(&good[..good.len() - 5]));
    read_error(&path, "ends after 43 of 48 bytes");
    let compressed = gzip(&good);
    let path = write(
        dir.path(),
        "cut.nii.gz",
        &compressed[..compressed.len() / 2],
    );
    read_error(&path, "ends after");

    let path = write(dir.path(), "not_nifti.nii", &[7u8; 400]);
    read_error(&path, "sizeof_hdr");
    let mut bad_magic = good.clone();
    bad_magic[344..348].copy_from_slice(b"ni1\0");
    let path = write(dir.path(), "pair.nii", &bad_magic);
    read_error(&path, ".hdr/.img");

    let mut complex = Nifti::new(1, true, 32);
    let path = write(dir.path(), "complex.nii", &complex.bytes(&data));
    read_error(&path, "unsupported datatype 32");
    complex.datatype = 4;
    complex.dim = [3, 30000, 30000, 30000, 1, 1, 1, 1];
    let path = write(dir.path(), "huge.nii", &complex.bytes(&data));
    read_error(&path, "more than");
    complex.dim = [3, 4, -3, 2, 1, 1, 1, 1];
    let path = write(dir.path(), "negative.nii", &complex.bytes(&data));
    read_error(&path, "dim[2] is -3");
    complex.dim = [3, 4, 3, 2, 1, 1, 1, 1];
    complex.vox_offset = 352;
    let mut early = complex.clone();
    early.pixdim[2] = 0.0;
    let path = write(dir.path(), "flat.nii", &early.bytes(&data));
    read_error(&path, "spacing");

    let path = dir.path().join("missing.nii");
    read_error(&path, "no such file");
    let path = write(dir.path(), "image.png", b"png");
    read_error(&path, "unsupported file extension");
}

#[test]
fn the_mni152_template_reads_with_its_sform() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../volumes/mni152_t1_1mm.nii.gz");
    let volume = read_volume(&path).unwrap();
    let bytes = std::fs::read(&path).unwrap();
    let mut header = Vec::new();
    std::io::Read::read_to_end(
        &mut std::io::Read::take(flate2::read::GzDecoder::new(bytes.as_slice()), 348),
        &mut header,
    )
    .unwrap();
    let float = |at: usize| f64::from(f32::from_le_bytes(header[at..at + 4].try_into().unwrap()));
    let sform_code = i16::from_le_bytes([header[254], header[255]]);
    let srow: Vec<[f64; 4]> = (0..3)
        .map(|row| std::array::from_fn(|n| float(280 + (row * 4 + n) * 4)))
        .collect();
    println!("sform_code {sform_code}, srow {srow:?}");
    assert!(sform_code > 0);
    assert_eq!(volume.dims(), [197, 233, 189]);
    assert_close(volume.spacing(), [1.0, 1.0, 1.0]);
    assert_close(volume.origin(), [srow[0][3], srow[1][3], srow[2][3]]);
    assert_close(volume.origin(), [-98.0, -134.0, -72.0]);
    assert_direction(&volume, Matrix3::identity());
    let (min, max) = volume
        .samples()
        .iter()
        .fold((f32::MAX, f32::MIN), |(lo, hi), &v| (lo.min(v), hi.max(v)));
    println!("samples in {min}..={max}");
    assert!(min >= 0.0 && max <= 255.0 && max > 100.0, "{min}..{max}");
    assert!(volume.samples().iter().all(|v| v.fract() == 0.0));
}

// ---------------------------------------------------------------- raw

#[test]
fn raw_samples_in_both_byte_orders() {
    let dir = tempfile::tempdir().unwrap();
    for little in [true, false] {
        let (data, values) = encode(SampleType::F32, little);
        let path = write(dir.path(), "ramp.raw", &data);
        let volume =
            read_raw_volume(&path, DIMS, [1.0, 2.0, 3.0], SampleType::F32, little).unwrap();
        assert_eq!(volume.samples(), values.as_slice());
        assert_close(volume.spacing(), [1.0, 2.0, 3.0]);
        let path = write(dir.path(), "short.raw", &data[..90]);
        let message = read_raw_volume(&path, DIMS, [1.0; 3], SampleType::F32, little)
            .unwrap_err()
            .to_string();
        assert!(
            message.contains("short.raw") && message.contains("ends after 90 of 96 bytes"),
            "{message}"
        );
        let path = write(dir.path(), "long.raw", &[data.as_slice(), &[0]].concat());
        let message = read_raw_volume(&path, DIMS, [1.0; 3], SampleType::F32, little)
            .unwrap_err()
            .to_string();
        assert!(
            message.contains("long.raw") && message.contains("more than"),
            "{message}"
        );
    }
}

// ---------------------------------------------------------------- NRRD

/// A NRRD header for the test grid with `extra` lines, then `data` attached after
/// a blank line (no blank line and no data for a detached header).
fn nrrd(type_name: &str, extra: &str, data: Option<&[u8]>) -> Vec<u8> {
    let mut bytes = format!(
        "NRRD0004\n# a comment\ntype: {type_name}\ndimension: 3\nsizes: 4 3 2\n\
         space: right-anterior-superior\nspace directions: (0,0.5,0) (-1.5,0,0) (0,0,2)\n\
         space origin: (10,-20,30)\nunits:=mm\n{extra}"
    )
    .into_bytes();
    if let Some(data) = data {
        bytes.push(b'\n');
        bytes.extend_from_slice(data);
    }
    bytes
}

const NRRD_TYPES: [&str; 8] = [
    "uchar",
    "int8",
    "short",
    "unsigned short",
    "int",
    "uint32",
    "float",
    "double",
];

fn check_ramp_geometry(volume: &Volume) {
    assert_eq!(volume.dims(), DIMS);
    assert_close(volume.spacing(), [0.5, 1.5, 2.0]);
    assert_close(volume.origin(), [10.0, -20.0, 30.0]);
    assert_direction(volume, quarter_turn());
}

#[test]
fn nrrd_types_encodings_byte_orders_and_detached_data() {
    let dir = tempfile::tempdir().unwrap();
    for (sample_type, type_name) in ALL_TYPES.into_iter().zip(NRRD_TYPES) {
        for little in [true, false] {
            let (data, values) = encode(sample_type, little);
            let endian = format!("endian: {}\n", if little { "little" } else { "big" });
            let raw = nrrd(type_name, &format!("encoding: raw\n{endian}"), Some(&data));
            let path = write(dir.path(), "raw.nrrd", &raw);
            let volume = read_volume(&path).unwrap_or_else(|e| panic!("{e}"));
            check_ramp_geometry(&volume);
            assert_eq!(volume.samples(), values.as_slice(), "{type_name}");

            let gz = nrrd(
                type_name,
                &format!("encoding: gzip\n{endian}"),
                Some(&gzip(&data)),
            );
            let path = write(dir.path(), "gz.nrrd", &gz);
            assert_eq!(read_volume(&path).unwrap().samples(), values.as_slice());

            let skipped = [&[9u8; 5][..], &data].concat();
            write(dir.path(), "ramp.raw", &skipped);
            let extra = format!("encoding: raw\n{endian}byte skip: 5\ndata file: ramp.raw\n");
            let path = write(dir.path(), "detached.nhdr", &nrrd(type_name, &extra, None));
            assert_eq!(read_volume(&path).unwrap().samples(), values.as_slice());
            let extra = format!("encoding: raw\n{endian}byte skip: -1\ndata file: ramp.raw\n");
            let path = write(dir.path(), "at_end.nhdr", &nrrd(type_name, &extra, None));
            assert_eq!(read_volume(&path).unwrap().samples(), values.as_slice());
        }
    }
}

#[test]
fn nrrd_spacings_without_directions() {
    let dir = tempfile::tempdir().unwrap();
    let (data, values) = encode(SampleType::U8, true);
    let header =
        "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 4 3 2\nspacings: 0.5 1.5 2\nencoding: raw\n\n";
    let path = write(
        dir.path(),
        "spacings.nrrd",
        &[header.as_bytes(), &data].concat(),
    );
    let volume = read_volume(&path).unwrap();
    assert_eq!(volume.samples(), values.as_slice());
    assert_close(volume.spacing(), [0.5, 1.5, 2.0]);
    assert_close(volume.origin(), [0.0; 3]);
    assert_direction(&volume, Matrix3::identity());
}

#[test]
fn nrrd_malformed_files_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let (data, _) = encode(SampleType::I16, true);
    let ok = "encoding: raw\nendian: little\n";
    let cases: [(&str, Vec<u8>, &str); 8] = [
        (
            "short.nrrd",
            nrrd("short", ok, Some(&data[..40])),
            "data ends after 40 of 48 bytes",
        ),
        (
            "ascii.nrrd",
            nrrd("short", "encoding: ascii\nendian: little\n", Some(&data)),
            "unsupported encoding 'ascii'",
        ),
        (
            "complex.nrrd",
            nrrd("block", ok, Some(&data)),
            "unsupported type 'block'",
        ),
        (
            "noendian.nrrd",
            nrrd("short", "encoding: raw\n", Some(&data)),
            "missing field 'endian'",
        ),
        (
            "fourd.nrrd",
            b"NRRD0004\ntype: short\ndimension: 4\nsizes: 4 3 2 1\nencoding: raw\n\n".to_vec(),
            "only 3-D",
        ),
        ("notnrrd.nrrd", b"P6\n".to_vec(), "not a NRRD file"),
        (
            "line.nrrd",
            b"NRRD0004\ntype short\n\n".to_vec(),
            "line 2: expected 'field: value'",
        ),
        (
            "sizes.nrrd",
            b"NRRD0004\ntype: short\ndimension: 3\nsizes: 4 x 2\nencoding: raw\nendian: big\n\n"
                .to_vec(),
            "line 4: field 'sizes': cannot read 'x'",
        ),
    ];
    for (name, bytes, word) in cases {
        let path = write(dir.path(), name, &bytes);
        read_error(&path, word);
    }
    let path = write(
        dir.path(),
        "missing.nhdr",
        &nrrd("short", &format!("{ok}data file: nowhere.raw\n"), None),
    );
    read_error(&path, "nowhere.raw");
    write(dir.path(), "short.raw", &data[..10]);
    let path = write(
        dir.path(),
        "shortdata.nhdr",
        &nrrd("short", &format!("{ok}data file: short.raw\n"), None),
    );
    let message = read_error(&path, "ends after 10 of 48 bytes");
    assert!(message.contains("short.raw"), "{message}");
    let huge = b"NRRD0004\ntype: short\ndimension: 3\nsizes: 100000 100000 100000\nencoding: raw\nendian: big\n\n";
    let path = write(dir.path(), "huge.nrrd", huge);
    read_error(&path, "more than");
}

// ---------------------------------------------------------------- MetaImage

/// A MetaImage header for the test grid ending with `ElementDataFile = data_file`.
fn metaimage(element_type: &str, extra: &str, data_file: &str) -> String {
    format!(
        "ObjectType = Image\nNDims = 3\nDimSize = 4 3 2\nElementSpacing = 0.5 1.5 2\n\
         Offset = 10 -20 30\nTransformMatrix = 0 1 0 -1 0 0 0 0 1\n\
         ElementType = {element_type}\n{extra}ElementDataFile = {data_file}\n"
    )
}

const MET_TYPES: [&str; 8] = [
    "MET_UCHAR",
    "MET_CHAR",
    "MET_SHORT",
    "MET_USHORT",
    "MET_INT",
    "MET_UINT",
    "MET_FLOAT",
    "MET_DOUBLE",
];

fn zlib(bytes: &[u8]) -> Vec<u8> {
    let mut encoder = flate2::write::ZlibEncoder::new(Vec::new(), flate2::Compression::fast());
    encoder.write_all(bytes).unwrap();
    encoder.finish().unwrap()
}

#[test]
fn metaimage_types_byte_orders_compression_and_detached_data() {
    let dir = tempfile::tempdir().unwrap();
    for (sample_type, type_name) in ALL_TYPES.into_iter().zip(MET_TYPES) {
        for little in [true, false] {
            let (data, values) = encode(sample_type, little);
            let msb = format!(
                "BinaryDataByteOrderMSB = {}\n",
                if little { "False" } else { "True" }
            );
            let header = metaimage(type_name, &msb, "LOCAL");
            let path = write(
                dir.path(),
                "local.mha",
                &[header.as_bytes(), &data].concat(),
            );
            let volume = read_volume(&path).unwrap_or_else(|e| panic!("{e}"));
            check_ramp_geometry(&volume);
            assert_eq!(volume.samples(), values.as_slice(), "{type_name}");

            let extra = format!("{msb}CompressedData = True\n");
            let header = metaimage(type_name, &extra, "LOCAL");
            let path = write(
                dir.path(),
                "zlib.mha",
                &[header.as_bytes(), &zlib(&data)].concat(),
            );
            assert_eq!(read_volume(&path).unwrap().samples(), values.as_slice());

            write(dir.path(), "ramp.raw", &[&[0u8; 3][..], &data].concat());
            let header = metaimage(type_name, &format!("{msb}HeaderSize = 3\n"), "ramp.raw");
            let path = write(dir.path(), "detached.mhd", header.as_bytes());
            let volume = read_volume(&path).unwrap();
            check_ramp_geometry(&volume);
            assert_eq!(volume.samples(), values.as_slice());
        }
    }
}

#[test]
fn metaimage_malformed_files_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let (data, _) = encode(SampleType::I16, true);
    let with_data = |header: String, data: &[u8]| [header.as_bytes(), data].concat();
    let cases: [(&str, Vec<u8>, &str); 7] = [
        (
            "short.mha",
            with_data(metaimage("MET_SHORT", "", "LOCAL"), &data[..30]),
            "data ends after 30 of 48 bytes",
        ),
        (
            "type.mha",
            with_data(metaimage("MET_LONG_LONG", "", "LOCAL"), &data),
            "unsupported ElementType 'MET_LONG_LONG'",
        ),
        (
            "twod.mha",
            b"NDims = 2\nDimSize = 4 3\nElementType = MET_SHORT\nElementDataFile = LOCAL\n"
                .to_vec(),
            "only 3-D",
        ),
        (
            "noend.mha",
            b"NDims = 3\nDimSize = 4 3 2\n".to_vec(),
            "missing field 'ElementDataFile'",
        ),
        (
            "line.mha",
            b"NDims = 3\nDimSize 4 3 2\nElementDataFile = LOCAL\n".to_vec(),
            "line 2: expected 'Key = Value'",
        ),
        (
            "dims.mha",
            with_data(
                metaimage("MET_SHORT", "", "LOCAL").replace("4 3 2", "4 3"),
                &data,
            ),
            "field 'DimSize': expected 3 values",
        ),
        (
            "zlib.mha",
            with_data(
                metaimage("MET_SHORT", "CompressedData = True\n", "LOCAL"),
                &data,
            ),
            "cannot be read",
        ),
    ];
    for (name, bytes, word) in cases {
        let path = write(dir.path(), name, &bytes);
        read_error(&path, word);
    }
    let path = write(
        dir.path(),
        "missing.mhd",
        metaimage("MET_SHORT", "", "gone.raw").as_bytes(),
    );
    read_error(&path, "gone.raw");
}

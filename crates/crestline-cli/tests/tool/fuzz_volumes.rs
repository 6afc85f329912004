//! Mutation fuzzing of the image readers, run through the command-line tool.
//!
//! Small valid images (6 × 5 × 4 samples of a ramp) are written here in every
//! format the tool reads: NIfTI-1 in both byte orders, NIfTI-2, gzipped `.nii.gz`,
//! NRRD with raw and gzip data, a `.nhdr` header with a detached `.raw` file,
//! MetaImage `.mha` with raw and zlib-compressed data and a `.mhd` header with a
//! detached `.raw` file, across uint8, int16, float32 and float64 samples, with
//! sform and qform placements. Each mutant changes one to three things, drawn
//! from a seeded generator: a binary header field set to an interesting value (a
//! 16/32/64-bit integer or a float such as NaN, inf, 1e38, 1e308, -1 or 0 at the
//! offsets of `dim[]`, `datatype`, `bitpix`, `pixdim`, `vox_offset`,
//! `scl_slope/inter`, the qform and sform codes, the quaternion and the srows), a
//! text header field given a strange value (`sizes`, `DimSize`, `type`,
//! `ElementType`, `encoding`, `data file`, `ElementDataFile`, ...), a number of
//! a text header replaced by a huge, negative, NaN or garbage one, header lines
//! deleted, duplicated or swapped, non-finite or extreme samples, the samples cut
//! short or made longer, a gzip or zlib stream with a flipped byte, cut short or
//! followed by garbage, the detached data file truncated, longer, empty, missing,
//! replaced by a folder, or a link to `/dev/zero`, `/dev/urandom`, nothing or the
//! header (and the header's `data file` naming such files), and the generic byte
//! mutations of the mesh reader fuzz test (`crates/crestline/tests/library/
//! common/mutation.rs`, shared with it).
//!
//! Every mutant is read by the real `crestline` binary: `crestline info IMAGE`,
//! and for every fourth mutant also `crestline iso IMAGE --level L -o
//! OUT/out.ply` (half of those with `--sigma 0`), each in a shell limited to 4 GiB
//! of address space (`ulimit -v`) and killed after [`TIMEOUT`] (then run once more
//! with a longer timeout, to tell a hang from a busy machine). A run must exit
//! with 0 or 1 (no panic, abort or signal); a failure must print one line `error:
//! ...` (besides `warning:` lines) naming the image, without Rust debug text; a
//! failed run must leave nothing in its output folder (no `out.ply`, no hidden
//! `.crestline-*` temporary file), and no run may change the input files (header
//! and data file). A failing mutant is kept in `crestline-fuzz-volumes/seed-S/`
//! under the system's temporary folder, with what the tool printed; the failure
//! names it and the command to run again, and every failure is listed in
//! `failures.txt` there.
//!
//! `cargo test --release` runs [`DEFAULT_MUTANTS`] mutants per seed image (2,200
//! in all: about 8 s on two idle cores, 15 s on busy ones). For a longer run set
//! `CRESTLINE_FUZZ_MUTANTS=N` (mutants per seed image) and optionally
//! `CRESTLINE_FUZZ_SEED=S` (and `CRESTLINE_FUZZ_SHOW=1` to print every error
//! message), e.g. `CRESTLINE_FUZZ_MUTANTS=2000 CRESTLINE_FUZZ_SEED=7 cargo test
//! --release -p crestline-cli --test tool fuzz_volumes -- --nocapture` (about 100 s);
//! the table of outcomes is printed either way.
//!
//! A second test mutates DICOM input (pydicom's native, RLE and JPEG files and a
//! series of three slices made from them, when `tools/fetch_pydicom_data.sh` has
//! fetched them) and per-vertex files given to `morse --indicator` and `ridges
//! --smoothing-weights` (GIfTI `.shape.gii`, FreeSurfer curv), judged by the same
//! checks: [`DEFAULT_OTHER_MUTANTS`] per seed (about 400 runs, a few seconds), or
//! `CRESTLINE_FUZZ_MUTANTS`. `python3 tools/fuzz_readers.py --mutants 3000` runs
//! thousands per format, with mutations aimed at each reader (gzip bombs, huge
//! dimensions, 200,000 attributes, RLE and JPEG headers) and a pipe in place of
//! each file.
#![cfg(unix)]

use std::collections::BTreeMap;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;
use std::time::{Duration, Instant};

#[path = "../../../crestline/tests/library/common/mutation.rs"]
mod mutation;

use mutation::{digit_runs, env_number, mutate, pick_run, text_problem, Rng};

/// Mutants per seed image in a plain `cargo test --release`.
const DEFAULT_MUTANTS: usize = 200;
/// Every this many mutants is also run through `crestline iso`.
const ISO_EVERY: usize = 4;
/// A run taking longer is killed and run again with [`RERUN_TIMEOUT`]; killed
/// again, it is a hang. (A bound for hangs, not a timing assertion.)
const TIMEOUT: Duration = Duration::from_secs(5);
const RERUN_TIMEOUT: Duration = Duration::from_secs(30);
/// The shell that runs the tool: at most 4 GiB of address space (`ulimit -v`
/// counts KiB), so that a header asking for more must be refused, not allocated.
const LIMITED_SHELL: &str = r#"ulimit -v 4194304; exec "$0" "$@""#;
/// Text on stderr that only a panic or an abort prints.
const PANIC_TEXT: &[&str] = &["panicked", "RUST_BACKTRACE", "memory allocation of"];
/// The file name of the detached data of the `.nhdr` and `.mhd` seeds.
const DATA_FILE: &str = "image.raw";

// ---------------------------------------------------------------------------
// Seed images

/// The grid of every seed image.
const DIMS: [usize; 3] = [6, 5, 4];
/// The middle of the ramp's values (0 to 102), where the isosurface is taken.
const MIDDLE: f64 = 51.0;

/// The ramp with a wrinkle at voxel `(i, j, k)`: 0 to 102.
fn ramp(i: usize, j: usize, k: usize) -> f64 {
    (10 * i + 7 * j + 5 * k + 3 * ((i * j) % 4)) as f64
}

/// The sample types of the seeds.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Type {
    U8,
    I16,
    F32,
    F64,
}

impl Type {
    fn size(self) -> usize {
        match self {
            Type::U8 => 1,
            Type::I16 => 2,
            Type::F32 => 4,
            Type::F64 => 8,
        }
    }

    /// The stored sample of the ramp value `v` is `a·v + b`.
    fn scale(self) -> (f64, f64) {
        match self {
            Type::U8 => (1.0, 0.0),
            Type::I16 => (37.0, -1500.0),
            Type::F32 => (0.25, -3.1),
            Type::F64 => (0.5, -20.0),
        }
    }

    /// `value` as a sample of this type, little endian.
    fn le_bytes(self, value: f64) -> Vec<u8> {
        match self {
            Type::U8 => vec![value as u8],
            Type::I16 => (value as i16).to_le_bytes().to_vec(),
            Type::F32 => (value as f32).to_le_bytes().to_vec(),
            Type::F64 => value.to_le_bytes().to_vec(),
        }
    }

    /// Samples at the edges of the type: the extremes, and for floats values
    /// that are not finite, tiny or beyond `f32`.
    fn extremes(self) -> &'static [f64] {
        match self {
            Type::U8 => &[0.0, 255.0],
            Type::I16 => &[-32768.0, 32767.0, 0.0],
            Type::F32 | Type::F64 => &[
                f64::NAN,
                f64::INFINITY,
                f64::NEG_INFINITY,
                3.4e38,
                -3.4e38,
                1e308,
                1e-45,
                -0.0,
            ],
        }
    }

    fn nifti_code(self) -> f64 {
        match self {
            Type::U8 => 2.0,
            Type::I16 => 4.0,
            Type::F32 => 16.0,
            Type::F64 => 64.0,
        }
    }

    fn nrrd_name(self) -> &'static str {
        match self {
            Type::U8 => "uchar",
            Type::I16 => "short",
            Type::F32 => "float",
            Type::F64 => "double",
        }
    }

    fn met_name(self) -> &'static str {
        match self {
            Type::U8 => "MET_UCHAR",
            Type::I16 => "MET_SHORT",
            Type::F32 => "MET_FLOAT",
            Type::F64 => "MET_DOUBLE",
        }
    }
}

/// `le` (little-endian bytes) in the given byte order.
fn ordered(mut le: Vec<u8>, little: bool) -> Vec<u8> {
    if !little {
        le.reverse();
    }
    le
}

/// The ramp's samples as `ty` in the given byte order, x fastest.
fn samples(ty: Type, little: bool) -> Vec<u8> {
    let (a, b) = ty.scale();
    let mut bytes = Vec::new();
    for k in 0..DIMS[2] {
        for j in 0..DIMS[1] {
            for i in 0..DIMS[0] {
                bytes.extend(ordered(ty.le_bytes(a * ramp(i, j, k) + b), little));
            }
        }
    }
    bytes
}

fn gzip(bytes: &[u8]) -> Vec<u8> {
    let mut encoder = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::default());
    encoder.write_all(bytes).unwrap();
    encoder.finish().unwrap()
}

fn zlib(bytes: &[u8]) -> Vec<u8> {
    let mut encoder = flate2::write::ZlibEncoder::new(Vec::new(), flate2::Compression::default());
    encoder.write_all(bytes).unwrap();
    encoder.finish().unwrap()
}

/// The width of a binary header field.
#[derive(Clone, Copy, Debug)]
enum Width {
    I16,
    I32,
    I64,
    F32,
    F64,
}

impl Width {
    fn size(self) -> usize {
        match self {
            Width::I16 => 2,
            Width::I32 | Width::F32 => 4,
            Width::I64 | Width::F64 => 8,
        }
    }

    /// `value` written in this width, little endian (integers saturate).
    fn le_bytes(self, value: f64) -> Vec<u8> {
        match self {
            Width::I16 => (value as i16).to_le_bytes().to_vec(),
            Width::I32 => (value as i32).to_le_bytes().to_vec(),
            Width::I64 => (value as i64).to_le_bytes().to_vec(),
            Width::F32 => (value as f32).to_le_bytes().to_vec(),
            Width::F64 => value.to_le_bytes().to_vec(),
        }
    }
}

/// A field of a NIfTI header: name, byte offset, width and number of values.
type NiftiField = (&'static str, usize, Width, usize);

/// The fields of a NIfTI-1 or NIfTI-2 header that the fuzzer sets (offsets of
/// `nifti1.h` and `nifti2.h`; `extension` is the 4 bytes after the header).
fn nifti_fields(version: u8) -> Vec<NiftiField> {
    use Width::*;
    if version == 1 {
        vec![
            ("sizeof_hdr", 0, I32, 1),
            ("dim", 40, I16, 8),
            ("intent_code", 68, I16, 1),
            ("datatype", 70, I16, 1),
            ("bitpix", 72, I16, 1),
            ("pixdim", 76, F32, 8),
            ("vox_offset", 108, F32, 1),
            ("scl_slope", 112, F32, 1),
            ("scl_inter", 116, F32, 1),
            ("qform_code", 252, I16, 1),
            ("sform_code", 254, I16, 1),
            ("quatern", 256, F32, 6),
            ("srow_x", 280, F32, 4),
            ("srow_y", 296, F32, 4),
            ("srow_z", 312, F32, 4),
            ("magic", 344, I32, 1),
            ("extension", 348, I32, 1),
        ]
    } else {
        vec![
            ("sizeof_hdr", 0, I32, 1),
            ("magic", 4, I64, 1),
            ("datatype", 12, I16, 1),
            ("bitpix", 14, I16, 1),
            ("dim", 16, I64, 8),
            ("pixdim", 104, F64, 8),
            ("vox_offset", 168, I64, 1),
            ("scl_slope", 176, F64, 1),
            ("scl_inter", 184, F64, 1),
            ("qform_code", 344, I32, 1),
            ("sform_code", 348, I32, 1),
            ("quatern", 352, F64, 6),
            ("srow_x", 400, F64, 4),
            ("srow_y", 432, F64, 4),
            ("srow_z", 464, F64, 4),
            ("intent_code", 504, I32, 1),
            ("extension", 540, I32, 1),
        ]
    }
}

/// The header size of a NIfTI version.
fn nifti_header_size(version: u8) -> usize {
    if version == 1 {
        348
    } else {
        540
    }
}

/// Write `value` into element `n` of the header field `name` (if the header
/// reaches that far).
fn set_nifti(bytes: &mut [u8], version: u8, little: bool, (name, n): (&str, usize), value: f64) {
    let &(_, at, width, _) = nifti_fields(version)
        .iter()
        .find(|field| field.0 == name)
        .expect("a known field");
    let at = at + n * width.size();
    let raw = ordered(width.le_bytes(value), little);
    // A header cut short by an earlier mutation keeps its length.
    if let Some(field) = bytes.get_mut(at..at + raw.len()) {
        field.copy_from_slice(&raw);
    }
}

/// A NIfTI seed's header choices.
struct NiftiSpec {
    version: u8,
    little: bool,
    ty: Type,
    /// `scl_slope`, `scl_inter`.
    scl: [f64; 2],
    qform: bool,
    sform: bool,
}

/// A `.nii` file: header, 4 empty extension bytes, samples.
fn nifti(spec: &NiftiSpec) -> Vec<u8> {
    let (version, little) = (spec.version, spec.little);
    let header_size = nifti_header_size(version);
    let mut bytes = vec![0u8; header_size + 4];
    let mut set = |field: (&str, usize), value: f64| {
        set_nifti(&mut bytes, version, little, field, value);
    };
    set(("sizeof_hdr", 0), header_size as f64);
    for (n, d) in [3.0, 6.0, 5.0, 4.0, 1.0, 1.0, 1.0, 1.0]
        .into_iter()
        .enumerate()
    {
        set(("dim", n), d);
    }
    set(("datatype", 0), spec.ty.nifti_code());
    set(("bitpix", 0), (8 * spec.ty.size()) as f64);
    let qfac = if spec.qform { -1.0 } else { 1.0 };
    for (n, p) in [qfac, 0.9, 1.1, 1.6, 1.0, 1.0, 1.0, 1.0]
        .into_iter()
        .enumerate()
    {
        set(("pixdim", n), p);
    }
    set(("vox_offset", 0), (header_size + 4) as f64);
    set(("scl_slope", 0), spec.scl[0]);
    set(("scl_inter", 0), spec.scl[1]);
    if spec.qform {
        set(("qform_code", 0), 1.0);
        for (n, q) in [0.1, 0.2, 0.3, -12.5, 30.0, 7.25].into_iter().enumerate() {
            set(("quatern", n), q);
        }
    }
    if spec.sform {
        set(("sform_code", 0), 2.0);
        // A rotation about z (cos 0.8, sin 0.6) times the voxel sizes: smoothing
        // needs an orthonormal direction.
        let rows = [
            ("srow_x", [0.8 * 0.9, -0.6 * 1.1, 0.0, -10.0]),
            ("srow_y", [0.6 * 0.9, 0.8 * 1.1, 0.0, 5.0]),
            ("srow_z", [0.0, 0.0, 1.6, 2.5]),
        ];
        for (name, row) in rows {
            for (n, value) in row.into_iter().enumerate() {
                set((name, n), value);
            }
        }
    }
    if version == 1 {
        bytes[344..348].copy_from_slice(b"n+1\0");
    } else {
        bytes[4..12].copy_from_slice(b"n+2\0\r\n\x1a\n");
    }
    bytes.extend(samples(spec.ty, little));
    bytes
}

/// Where the samples of an image are.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Data {
    /// After the header, stored as the codec says.
    Attached(Codec),
    /// In the file [`DATA_FILE`] next to the header, uncompressed.
    Detached,
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Codec {
    Raw,
    Gzip,
    Zlib,
}

impl Codec {
    fn encode(self, bytes: &[u8]) -> Vec<u8> {
        match self {
            Codec::Raw => bytes.to_vec(),
            Codec::Gzip => gzip(bytes),
            Codec::Zlib => zlib(bytes),
        }
    }
}

#[derive(Clone, Copy, Debug)]
enum Format {
    Nifti { version: u8, gz: bool },
    Nrrd(Data),
    MetaImage(Data),
}

/// A valid image to mutate.
struct Seed {
    name: &'static str,
    /// The image's file name.
    file: &'static str,
    format: Format,
    ty: Type,
    /// NIfTI: the whole uncompressed `.nii`; NRRD and MetaImage: the header text.
    header: Vec<u8>,
    /// NRRD and MetaImage: the sample bytes as stored before compression.
    raw: Vec<u8>,
    /// Where the samples start in `header` (NIfTI) or in `raw`.
    data_at: usize,
    little: bool,
    /// An isosurface level inside the image's values.
    level: f64,
}

impl Seed {
    /// The files of the seed itself.
    fn files(&self) -> Vec<(String, Entry)> {
        encode(self, &self.header, &self.raw).files(self)
    }
}

/// A NIfTI seed.
fn nifti_seed(name: &'static str, file: &'static str, spec: NiftiSpec) -> Seed {
    let (a, b) = spec.ty.scale();
    let stored_level = a * MIDDLE + b;
    let level = if spec.scl[0] != 0.0 {
        stored_level * spec.scl[0] + spec.scl[1]
    } else {
        stored_level
    };
    Seed {
        name,
        file,
        format: Format::Nifti {
            version: spec.version,
            gz: file.ends_with(".gz"),
        },
        ty: spec.ty,
        header: nifti(&spec),
        raw: Vec::new(),
        data_at: nifti_header_size(spec.version) + 4,
        little: spec.little,
        level,
    }
}

/// A NRRD or MetaImage seed: `header` with `{type}`, `{endian}` and `{size}`
/// (the compressed size) filled in, and `skip` bytes before the samples.
fn text_seed(
    (name, file): (&'static str, &'static str),
    format: Format,
    (ty, little): (Type, bool),
    header: &str,
    skip: usize,
) -> Seed {
    let mut raw: Vec<u8> = (0..skip).map(|n| (n * 37) as u8).collect();
    raw.extend(samples(ty, little));
    let data = match format {
        Format::Nrrd(data) | Format::MetaImage(data) => data,
        Format::Nifti { .. } => unreachable!("a text header"),
    };
    let size = match data {
        Data::Attached(codec) => codec.encode(&raw).len(),
        Data::Detached => raw.len(),
    };
    let header = header
        .replace("{type}", ty.nrrd_name())
        .replace("{met}", ty.met_name())
        .replace("{endian}", if little { "little" } else { "big" })
        .replace("{msb}", if little { "False" } else { "True" })
        .replace("{size}", &size.to_string());
    let (a, b) = ty.scale();
    Seed {
        name,
        file,
        format,
        ty,
        header: header.into_bytes(),
        raw,
        data_at: skip,
        little,
        level: a * MIDDLE + b,
    }
}

fn seeds() -> Vec<Seed> {
    let spec = |version, little, ty, qform, sform| NiftiSpec {
        version,
        little,
        ty,
        scl: [0.0, 0.0],
        qform,
        sform,
    };
    vec![
        nifti_seed(
            "NIfTI-1 LE int16 sform",
            "image.nii",
            spec(1, true, Type::I16, true, true),
        ),
        nifti_seed(
            "NIfTI-1 BE float32 qform",
            "image.nii",
            spec(1, false, Type::F32, true, false),
        ),
        nifti_seed(
            "NIfTI-2 LE float64 sform",
            "image.nii",
            spec(2, true, Type::F64, false, true),
        ),
        nifti_seed(
            "NIfTI-1 gz uint8 scaled",
            "image.nii.gz",
            NiftiSpec {
                scl: [2.0, -10.0],
                ..spec(1, true, Type::U8, true, false)
            },
        ),
        nifti_seed(
            "NIfTI-2 gz BE float32",
            "image.nii.gz",
            spec(2, false, Type::F32, true, true),
        ),
        text_seed(
            ("NRRD raw int16", "image.nrrd"),
            Format::Nrrd(Data::Attached(Codec::Raw)),
            (Type::I16, true),
            "NRRD0004\n# Complete NRRD file format specification at:\n\
             # http://teem.sourceforge.net/nrrd/format.html\ntype: {type}\ndimension: 3\n\
             space: left-posterior-superior\nsizes: 6 5 4\n\
             space directions: (0.9,0.1,0) (-0.1,0.9,0) (0,0,1.5)\nkinds: domain domain domain\n\
             endian: {endian}\nencoding: raw\nspace origin: (-10.5,20.25,3)\n\n",
            0,
        ),
        text_seed(
            ("NRRD gzip BE float32", "image.nrrd"),
            Format::Nrrd(Data::Attached(Codec::Gzip)),
            (Type::F32, false),
            "NRRD0005\ntype: {type}\ndimension: 3\nsizes: 6 5 4\nspacings: 0.8 0.8 1.25\n\
             endian: {endian}\nencoding: gzip\ncontent: ramp\nkey:=value\n\n",
            0,
        ),
        text_seed(
            ("NHDR + raw float64", "image.nhdr"),
            Format::Nrrd(Data::Detached),
            (Type::F64, true),
            "NRRD0004\ntype: {type}\ndimension: 3\nspace: RAS\nsizes: 6 5 4\n\
             space directions: (1,0,0) (0,1,0) (0,0,2)\nspace origin: (0,0,0)\n\
             endian: {endian}\nencoding: raw\nbyte skip: 8\ndata file: image.raw\n",
            8,
        ),
        text_seed(
            ("MHA raw float32", "image.mha"),
            Format::MetaImage(Data::Attached(Codec::Raw)),
            (Type::F32, true),
            "ObjectType = Image\nNDims = 3\nBinaryData = True\nBinaryDataByteOrderMSB = {msb}\n\
             CompressedData = False\nTransformMatrix = 1 0 0 0 0.8 0.6 0 -0.6 0.8\n\
             Offset = -5 2.5 10\nCenterOfRotation = 0 0 0\nAnatomicalOrientation = RAI\n\
             ElementSpacing = 1.2 1.2 2\nDimSize = 6 5 4\nElementType = {met}\n\
             ElementDataFile = LOCAL\n",
            0,
        ),
        text_seed(
            ("MHA zlib BE int16", "image.mha"),
            Format::MetaImage(Data::Attached(Codec::Zlib)),
            (Type::I16, false),
            "ObjectType = Image\nNDims = 3\nBinaryData = True\nBinaryDataByteOrderMSB = {msb}\n\
             CompressedData = True\nCompressedDataSize = {size}\nOffset = 0 0 0\n\
             ElementSpacing = 0.5 0.5 0.5\nDimSize = 6 5 4\nElementType = {met}\n\
             ElementDataFile = LOCAL\n",
            0,
        ),
        text_seed(
            ("MHD + raw uint8", "image.mhd"),
            Format::MetaImage(Data::Detached),
            (Type::U8, true),
            "ObjectType = Image\nNDims = 3\nDimSize = 6 5 4\nElementSpacing = 1 1 3\n\
             HeaderSize = -1\nElementType = {met}\nElementDataFile = image.raw\n",
            5,
        ),
    ]
}

// ---------------------------------------------------------------------------
// Mutations

/// One file of a mutant, as written.
#[derive(Clone, Debug, PartialEq)]
enum Entry {
    File(Vec<u8>),
    /// An empty folder.
    Dir,
    /// A symbolic link to this target.
    Link(PathBuf),
}

/// A mutant: its files (the image first) and what was changed.
struct Mutant {
    files: Vec<(String, Entry)>,
    notes: Vec<String>,
}

/// The files of a (mutated) seed before its last changes.
struct Encoded {
    /// The image file.
    main: Vec<u8>,
    /// Where a compressed stream starts in `main`.
    stream_at: Option<usize>,
    /// The detached data file; `None` when missing.
    data: Option<Entry>,
}

impl Encoded {
    fn files(self, seed: &Seed) -> Vec<(String, Entry)> {
        let mut files = vec![(seed.file.to_string(), Entry::File(self.main))];
        files.extend(self.data.map(|entry| (DATA_FILE.to_string(), entry)));
        files
    }
}

/// The files of `seed` with the given header (or whole `.nii`) and samples.
fn encode(seed: &Seed, header: &[u8], raw: &[u8]) -> Encoded {
    match seed.format {
        Format::Nifti { gz, .. } => Encoded {
            main: if gz { gzip(header) } else { header.to_vec() },
            stream_at: gz.then_some(0),
            data: None,
        },
        Format::Nrrd(data) | Format::MetaImage(data) => match data {
            Data::Attached(codec) => {
                let mut main = header.to_vec();
                main.extend(codec.encode(raw));
                Encoded {
                    main,
                    stream_at: (codec != Codec::Raw).then_some(header.len()),
                    data: None,
                }
            }
            Data::Detached => Encoded {
                main: header.to_vec(),
                stream_at: None,
                data: Some(Entry::File(raw.to_vec())),
            },
        },
    }
}

/// The kinds of change, each drawn with a weight that depends on the seed.
#[derive(Clone, Copy, Debug)]
enum Change {
    /// A NIfTI header field set to an interesting value.
    NiftiField,
    /// Samples set to extreme or non-finite values.
    Samples,
    /// Generic byte mutations of the header (the uncompressed `.nii`).
    HeaderBytes,
    /// A text header field given a strange value (added if missing).
    SetField,
    /// A number of a text header replaced.
    Number,
    /// Text header lines deleted, duplicated or swapped.
    Lines,
    /// The sample bytes cut short or made longer (before compression).
    DataLength,
    /// The compressed stream corrupted or cut.
    Stream,
    /// The detached data file changed, replaced or removed.
    DataFile,
    /// Generic byte mutations of the image file as stored.
    WholeFile,
}

impl Change {
    /// Whether the change applies to the stored files rather than to the
    /// header and samples before they are encoded.
    fn is_late(self) -> bool {
        matches!(self, Change::Stream | Change::DataFile | Change::WholeFile)
    }
}

/// The changes that apply to `seed`, with their weights.
fn changes(seed: &Seed) -> Vec<(usize, Change)> {
    use Change::*;
    match seed.format {
        Format::Nifti { gz: false, .. } => {
            vec![(5, NiftiField), (1, Samples), (3, WholeFile)]
        }
        Format::Nifti { gz: true, .. } => vec![
            (4, NiftiField),
            (1, Samples),
            (2, HeaderBytes),
            (3, Stream),
            (1, WholeFile),
        ],
        Format::Nrrd(data) | Format::MetaImage(data) => {
            let mut list = vec![
                (5, SetField),
                (2, Number),
                (2, Lines),
                (1, HeaderBytes),
                (1, Samples),
                (1, DataLength),
                (1, WholeFile),
            ];
            match data {
                Data::Attached(Codec::Raw) => {}
                Data::Attached(_) => list.push((3, Stream)),
                Data::Detached => list.push((4, DataFile)),
            }
            list
        }
    }
}

fn weighted<T: Copy>(rng: &mut Rng, items: &[(usize, T)]) -> T {
    let total: usize = items.iter().map(|(w, _)| w).sum();
    let mut r = rng.below(total);
    for &(weight, item) in items {
        if r < weight {
            return item;
        }
        r -= weight;
    }
    unreachable!("r < total")
}

/// A mutant of `seed`: one to three changes.
fn mutant(seed: &Seed, rng: &mut Rng) -> Mutant {
    let count = match rng.below(10) {
        0..=5 => 1,
        6..=8 => 2,
        _ => 3,
    };
    let choices = changes(seed);
    let picked: Vec<Change> = (0..count).map(|_| weighted(rng, &choices)).collect();
    let (mut header, mut raw) = (seed.header.clone(), seed.raw.clone());
    let mut notes = Vec::new();
    for change in picked.iter().filter(|c| !c.is_late()) {
        notes.push(match change {
            Change::NiftiField => nifti_field(seed, &mut header, rng),
            Change::Samples => {
                let samples = match seed.format {
                    Format::Nifti { .. } => &mut header,
                    _ => &mut raw,
                };
                extreme_samples(seed, samples, rng)
            }
            Change::HeaderBytes => {
                let (bytes, mutations) = mutate(&header, rng);
                header = bytes;
                format!("header bytes {mutations:?}")
            }
            Change::SetField => set_field(seed, &mut header, rng),
            Change::Number => replace_number(&mut header, rng),
            Change::Lines => change_lines(&mut header, rng),
            Change::DataLength => data_length(&mut raw, rng),
            _ => unreachable!("an early change"),
        });
    }
    let mut encoded = encode(seed, &header, &raw);
    for change in picked.iter().filter(|c| c.is_late()) {
        notes.push(match change {
            Change::Stream => corrupt_stream(&mut encoded, rng),
            Change::DataFile => change_data_file(&mut encoded.data, rng),
            Change::WholeFile => {
                let (bytes, mutations) = mutate(&encoded.main, rng);
                encoded.main = bytes;
                format!("file bytes {mutations:?}")
            }
            _ => unreachable!("a late change"),
        });
    }
    Mutant {
        files: encoded.files(seed),
        notes,
    }
}

/// Integers for any integer field: the limits of the integer types and beyond.
const INTEGERS: &[f64] = &[
    0.0,
    1.0,
    -1.0,
    2.0,
    255.0,
    256.0,
    32767.0,
    -32768.0,
    65535.0,
    2147483647.0,
    -2147483648.0,
    4294967295.0,
    1099511627776.0,
    9.3e18,
    -9.3e18,
];
/// Values for any float field.
const FLOATS: &[f64] = &[
    f64::NAN,
    f64::INFINITY,
    f64::NEG_INFINITY,
    1e38,
    -1e38,
    3.4028235e38,
    1e308,
    -1e308,
    1e-38,
    1e-45,
    5e-324,
    0.0,
    -0.0,
    -1.0,
    1.0,
    0.5,
    1e10,
    1e-10,
];

/// The values worth trying in a NIfTI field (element `n` of `name`).
fn nifti_values(name: &str, n: usize) -> &'static [f64] {
    match (name, n) {
        ("dim", 0) => &[0.0, 1.0, 2.0, 4.0, 5.0, 7.0, 8.0, -1.0, 32767.0],
        ("dim", _) => &[
            0.0,
            -1.0,
            -6.0,
            1.0,
            7.0,
            100.0,
            32767.0,
            -32768.0,
            65535.0,
            1048576.0,
            2147483648.0,
            8589934592.0,
            1099511627776.0,
            9.3e18,
        ],
        ("datatype", _) => &[
            0.0, 1.0, 2.0, 4.0, 8.0, 16.0, 32.0, 64.0, 128.0, 256.0, 512.0, 768.0, 1024.0, 1280.0,
            1536.0, 1792.0, 2048.0, 2304.0, -1.0, 32767.0,
        ],
        ("bitpix", _) => &[0.0, 1.0, 8.0, 16.0, 32.0, 64.0, 128.0, -8.0, 255.0],
        ("vox_offset", _) => &[
            0.0,
            -352.0,
            347.0,
            348.0,
            351.0,
            352.0,
            352.5,
            353.0,
            356.0,
            540.0,
            544.0,
            545.0,
            548.0,
            4096.0,
            1e10,
            f64::NAN,
            f64::INFINITY,
            1e38,
            9.3e18,
        ],
        ("pixdim", 1..=3) => &[1e11, 1e-9, 1e5, 1e-5, 1e-30, 0.0, -0.9, 100.0],
        ("qform_code" | "sform_code", _) => &[0.0, 1.0, 2.0, 3.0, 4.0, 5.0, -1.0, 255.0, 32767.0],
        ("sizeof_hdr", _) => &[0.0, -1.0, 347.0, 348.0, 349.0, 539.0, 540.0, 1543569408.0],
        _ => &[],
    }
}

/// Set a NIfTI header field to an interesting value, usually in the file's byte
/// order.
fn nifti_field(seed: &Seed, bytes: &mut [u8], rng: &mut Rng) -> String {
    let Format::Nifti { version, .. } = seed.format else {
        unreachable!("a NIfTI seed")
    };
    let fields = nifti_fields(version);
    let &(name, _, width, count) = rng.pick(&fields);
    let n = rng.below(count);
    let special = nifti_values(name, n);
    let generic = match width {
        Width::F32 | Width::F64 => FLOATS,
        _ => INTEGERS,
    };
    let value = if special.is_empty() || rng.below(4) == 0 {
        *rng.pick(generic)
    } else {
        *rng.pick(special)
    };
    let swapped = rng.below(8) == 0;
    set_nifti(bytes, version, seed.little != swapped, (name, n), value);
    let order = if swapped { " (other byte order)" } else { "" };
    format!("{name}[{n}] = {}{order}", shown(value))
}

/// `value` for a note: whole numbers as they are, others in scientific notation.
fn shown(value: f64) -> String {
    if value.fract() == 0.0 && value.abs() < 1e15 {
        format!("{value}")
    } else {
        format!("{value:e}")
    }
}

/// Set one to three samples to extreme values of their type.
fn extreme_samples(seed: &Seed, samples: &mut [u8], rng: &mut Rng) -> String {
    let size = seed.ty.size();
    let count = (samples.len().saturating_sub(seed.data_at)) / size;
    let mut changed = Vec::new();
    for _ in 0..1 + rng.below(3) {
        if count == 0 {
            break;
        }
        let n = rng.below(count);
        let value = *rng.pick(seed.ty.extremes());
        let at = seed.data_at + n * size;
        let raw = ordered(seed.ty.le_bytes(value), seed.little);
        if let Some(sample) = samples.get_mut(at..at + size) {
            sample.copy_from_slice(&raw);
        }
        changed.push(format!("{n} = {}", shown(value)));
    }
    format!("samples {}", changed.join(", "))
}

/// Values for a field of a text header, by name.
fn text_values(format: Format) -> Vec<(&'static str, Vec<&'static str>)> {
    const SIZES: &[&str] = &[
        "6 5",
        "6 5 4 2",
        "0 5 4",
        "-6 5 4",
        "6 5 40",
        "6 5 3",
        "6 5 4000000000",
        "65536 65536 65536",
        "18446744073709551615 1 1",
        "4294967296 4294967296 1",
        "6 5 4.5",
        "6 5 nan",
        "",
    ];
    const SPACINGS: &[&str] = &[
        "0 0 0",
        "nan 1 1",
        "1e308 1e308 1e308",
        "-1 1 1",
        "1e-308 1 1",
        "inf 1 1",
        "1e38 1e-38 1",
        "1e11 1 1",
        "1 1e-9 1",
        "1e5 1e-5 1",
        "1 1",
    ];
    const ORIGINS: &[&str] = &[
        "nan 0 0",
        "1e308 1e308 1e308",
        "inf -inf 0",
        "1 2",
        "1 2 3 4",
    ];
    let list = |values: &[&'static str]| values.to_vec();
    match format {
        Format::Nrrd(_) => vec![
            (
                "dimension",
                list(&["2", "4", "0", "-3", "3 3", "three", ""]),
            ),
            (
                "type",
                list(&[
                    "uchar",
                    "signed char",
                    "short",
                    "ushort",
                    "int",
                    "uint",
                    "float",
                    "double",
                    "int64",
                    "unsigned long long int",
                    "block",
                    "FLOAT",
                    "",
                ]),
            ),
            ("sizes", list(SIZES)),
            (
                "encoding",
                list(&[
                    "raw", "gzip", "gz", "ascii", "text", "hex", "bzip2", "zstd", "GZIP", "",
                ]),
            ),
            ("endian", list(&["little", "big", "middle", ""])),
            (
                "byte skip",
                list(&[
                    "-1",
                    "0",
                    "1",
                    "7",
                    "4096",
                    "-2",
                    "9223372036854775807",
                    "18446744073709551615",
                ]),
            ),
            ("line skip", list(&["0", "1", "-1", "1000"])),
            (
                "space directions",
                list(&[
                    "(0,0,0) (0,1,0) (0,0,1)",
                    "(nan,0,0) (0,1,0) (0,0,1)",
                    "(1e308,0,0) (0,1e308,0) (0,0,1e308)",
                    "(1,0,0) (1,0,0) (0,0,1)",
                    "none (1,0,0) (0,1,0)",
                    "(1,0,0) (0,1,0)",
                    "(1e-300,0,0) (0,1e-300,0) (0,0,1e-300)",
                    "(inf,0,0) (0,1,0) (0,0,1)",
                    "(1e11,0,0) (0,1,0) (0,0,1)",
                    "(0,1e-9,0) (1,0,0) (0,0,1)",
                    "(1,0,0 (0,1,0) (0,0,1)",
                ]),
            ),
            (
                "space origin",
                list(&[
                    "(nan,0,0)",
                    "(1e308,1e308,1e308)",
                    "(inf,-inf,0)",
                    "(1,2)",
                    "1 2 3",
                ]),
            ),
            ("spacings", list(SPACINGS)),
            ("space", list(&["RAS", "LPS", "LAS", "scanner-xyz", ""])),
            (
                "data file",
                list(&[
                    "image.raw",
                    "missing.raw",
                    "/dev/zero",
                    "/dev/urandom",
                    ".",
                    "",
                    "/",
                    "image.nhdr",
                    "image.nrrd",
                    "LIST",
                    "image%d.raw 1 2 1",
                    "../image.raw",
                ]),
            ),
        ],
        Format::MetaImage(_) => vec![
            ("NDims", list(&["2", "4", "0", "-1", "3.0", ""])),
            ("DimSize", list(SIZES)),
            (
                "ElementType",
                list(&[
                    "MET_UCHAR",
                    "MET_CHAR",
                    "MET_SHORT",
                    "MET_USHORT",
                    "MET_INT",
                    "MET_UINT",
                    "MET_FLOAT",
                    "MET_DOUBLE",
                    "MET_LONG",
                    "MET_ULONG_LONG",
                    "MET_FLOAT_ARRAY",
                    "float",
                    "",
                ]),
            ),
            (
                "ElementDataFile",
                list(&[
                    "LOCAL",
                    "image.raw",
                    "missing.raw",
                    "/dev/zero",
                    "/dev/urandom",
                    ".",
                    "",
                    "/",
                    "image.mha",
                    "image.mhd",
                    "LIST",
                    "image%03d.raw 1 2 1",
                ]),
            ),
            ("CompressedData", list(&["True", "False", "yes", ""])),
            (
                "CompressedDataSize",
                list(&["0", "1", "-1", "18446744073709551615", "nan"]),
            ),
            ("BinaryDataByteOrderMSB", list(&["True", "False", "maybe"])),
            ("BinaryData", list(&["True", "False"])),
            (
                "HeaderSize",
                list(&["-1", "0", "1", "4096", "-2", "18446744073709551615"]),
            ),
            ("ElementSpacing", list(SPACINGS)),
            ("Offset", list(ORIGINS)),
            (
                "TransformMatrix",
                list(&[
                    "0 0 0 0 0 0 0 0 0",
                    "nan 0 0 0 1 0 0 0 1",
                    "1 0 0 1 0 0 0 0 1",
                    "1e308 0 0 0 1e308 0 0 0 1e308",
                    "1 0 0 0 1 0",
                    "1e-300 0 0 0 1e-300 0 0 0 1e-300",
                ]),
            ),
            ("ElementNumberOfChannels", list(&["1", "3", "0", "-1"])),
        ],
        Format::Nifti { .. } => unreachable!("a text header"),
    }
}

/// The lines of a text header (split at `\n`, joined back by [`join_lines`]).
fn split_lines(header: &[u8]) -> Vec<Vec<u8>> {
    header.split(|&b| b == b'\n').map(<[u8]>::to_vec).collect()
}

fn join_lines(lines: &[Vec<u8>]) -> Vec<u8> {
    lines.join(&b'\n')
}

/// Give a field of a text header a strange value, or add it.
fn set_field(seed: &Seed, header: &mut Vec<u8>, rng: &mut Rng) -> String {
    let fields = text_values(seed.format);
    let (key, values) = rng.pick(&fields);
    let value = *rng.pick(values);
    let separator = match seed.format {
        Format::Nrrd(_) => ": ",
        _ => " = ",
    };
    let line = format!("{key}{separator}{value}").into_bytes();
    let mut lines = split_lines(header);
    let found = lines.iter().position(|l| {
        l.splitn(2, |&b| b == b':' || b == b'=')
            .next()
            .is_some_and(|k| k.trim_ascii().eq_ignore_ascii_case(key.as_bytes()))
    });
    match found {
        Some(n) => lines[n] = line,
        None => {
            // Before the end of the header: its blank line (NRRD) or its last
            // field, `ElementDataFile` (MetaImage).
            let end = match seed.format {
                Format::Nrrd(_) => lines.iter().position(|l| l.is_empty()),
                _ => lines.iter().position(|l| l.starts_with(b"ElementDataFile")),
            }
            .unwrap_or(lines.len());
            let at = 1 + rng.below(end.max(1));
            lines.insert(at.min(lines.len()), line);
        }
    }
    *header = join_lines(&lines);
    let verb = if found.is_some() { "set" } else { "added" };
    format!("{verb} '{key}{separator}{value}'")
}

/// Numbers to write over a number of a text header: zero, negative, beyond the
/// integer types, not finite, or not a number at all.
const TEXT_NUMBERS: &[&str] = &[
    "0",
    "-1",
    "-0",
    "2147483648",
    "4294967296",
    "18446744073709551615",
    "99999999999999999999999",
    "9223372036854775807",
    "1e308",
    "1e400",
    "1e-320",
    "nan",
    "NaN",
    "inf",
    "-inf",
    "0x10",
    "1.5",
    "+3",
    "",
    "abc",
];

/// Replace a number of a text header by a strange one.
fn replace_number(header: &mut Vec<u8>, rng: &mut Rng) -> String {
    let runs = digit_runs(header);
    if runs.is_empty() {
        return "no number to replace".to_string();
    }
    let (start, end) = pick_run(&runs, rng);
    let old = String::from_utf8_lossy(&header[start..end]).into_owned();
    let new = *rng.pick(TEXT_NUMBERS);
    header.splice(start..end, new.bytes());
    format!("number '{old}' at byte {start} -> '{new}'")
}

/// Delete, duplicate or swap lines of a text header.
fn change_lines(header: &mut Vec<u8>, rng: &mut Rng) -> String {
    let mut lines = split_lines(header);
    let (a, b) = (rng.below(lines.len()), rng.below(lines.len()));
    let note = match rng.below(3) {
        0 => {
            lines.remove(a);
            format!("line {} deleted", a + 1)
        }
        1 => {
            let copy = lines[a].clone();
            lines.insert(b, copy);
            format!("line {} copied before line {}", a + 1, b + 1)
        }
        _ => {
            lines.swap(a, b);
            format!("lines {} and {} swapped", a + 1, b + 1)
        }
    };
    *header = join_lines(&lines);
    note
}

/// Cut the samples short or add bytes after them (before compression).
fn data_length(raw: &mut Vec<u8>, rng: &mut Rng) -> String {
    let before = raw.len();
    if rng.below(2) == 0 {
        raw.truncate(rng.below(before.max(1)));
    } else {
        let extra = *rng.pick(&[1, 7, 8, 240, 4096]);
        raw.extend((0..extra).map(|_| rng.next() as u8));
    }
    format!("sample bytes {before} -> {}", raw.len())
}

/// Corrupt the compressed stream of the image: a flipped byte (in its header,
/// body or trailer), cut short, or followed by garbage.
fn corrupt_stream(encoded: &mut Encoded, rng: &mut Rng) -> String {
    let Some(at) = encoded.stream_at else {
        return "no stream".to_string();
    };
    let main = &mut encoded.main;
    let length = main.len().saturating_sub(at);
    if length == 0 {
        return "empty stream".to_string();
    }
    match rng.below(6) {
        0 => {
            let n = rng.below(length);
            main[at + n] ^= 1 << rng.below(8);
            format!("stream bit flipped at byte {n} of {length}")
        }
        1 => {
            let n = length - 1 - rng.below(length.min(8));
            main[at + n] ^= 0xff;
            format!("stream trailer byte {n} of {length} inverted")
        }
        2 => {
            let n = rng.below(length.min(12));
            main[at + n] = *rng.pick(&[0, 0xff, 0x08, 0x1f, 0x8b, 0x04, 0x10, 0xe0]);
            format!("stream header byte {n} of {length} replaced")
        }
        3 => {
            let n = rng.below(length);
            main.truncate(at + n);
            format!("stream cut after {n} of {length} bytes")
        }
        4 => {
            let n = 1 + rng.below(length.min(8));
            main.truncate(main.len() - n);
            format!("stream's last {n} bytes cut")
        }
        _ => {
            let extra = 1 + rng.below(64);
            main.extend((0..extra).map(|_| rng.next() as u8));
            format!("{extra} bytes of garbage after the stream")
        }
    }
}

/// Change the detached data file: cut, longer, empty, missing, a folder, a link
/// to a device, to nothing or to the header, or its bytes mutated.
fn change_data_file(data: &mut Option<Entry>, rng: &mut Rng) -> String {
    let note = match rng.below(10) {
        0 | 1 => match data {
            Some(Entry::File(bytes)) => {
                let before = bytes.len();
                if rng.below(2) == 0 {
                    bytes.truncate(rng.below(before.max(1)));
                } else {
                    let extra = *rng.pick(&[1, 3, 8, 1000]);
                    bytes.extend((0..extra).map(|_| rng.next() as u8));
                }
                format!("{before} -> {} bytes", bytes.len())
            }
            _ => "not a file to resize".to_string(),
        },
        2 => {
            *data = Some(Entry::File(Vec::new()));
            "empty".to_string()
        }
        3 => {
            *data = None;
            "missing".to_string()
        }
        4 => {
            *data = Some(Entry::Dir);
            "a folder".to_string()
        }
        5..=8 => {
            let target = *rng.pick(&[
                "/dev/zero",
                "/dev/urandom",
                "nowhere.raw",
                "image.nhdr",
                "image.mhd",
                "/",
            ]);
            *data = Some(Entry::Link(PathBuf::from(target)));
            format!("a link to {target}")
        }
        _ => match data {
            Some(Entry::File(bytes)) => {
                let (mutated, mutations) = mutate(bytes, rng);
                *bytes = mutated;
                format!("bytes {mutations:?}")
            }
            _ => "not a file to mutate".to_string(),
        },
    };
    format!("data file: {note}")
}

// ---------------------------------------------------------------------------
// Running the tool

/// How a run of the tool ended.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Status {
    Code(i32),
    Signal(i32),
    /// Killed after the timeout.
    TimedOut,
}

/// A finished run of the tool.
struct Run {
    status: Status,
    stdout: String,
    stderr: String,
    elapsed: Duration,
}

/// Run `crestline args` in `cwd` under the address-space limit, killed after
/// `timeout`; its output is kept in files in `logs`.
fn run_tool(args: &[String], cwd: &Path, logs: &Path, timeout: Duration) -> Run {
    use std::os::unix::process::ExitStatusExt;
    let (out_path, err_path) = (logs.join("stdout"), logs.join("stderr"));
    let start = Instant::now();
    let mut child = Command::new("sh")
        .arg("-c")
        .arg(LIMITED_SHELL)
        .arg(env!("CARGO_BIN_EXE_crestline"))
        .args(args)
        .current_dir(cwd)
        .env_remove("RUST_BACKTRACE")
        .env_remove("RUST_LIB_BACKTRACE")
        .stdin(Stdio::null())
        .stdout(std::fs::File::create(&out_path).unwrap())
        .stderr(std::fs::File::create(&err_path).unwrap())
        .spawn()
        .expect("sh runs");
    let status = loop {
        if let Some(status) = child.try_wait().expect("the child can be waited for") {
            break match (status.code(), status.signal()) {
                (Some(code), _) => Status::Code(code),
                (None, Some(signal)) => Status::Signal(signal),
                (None, None) => Status::Signal(-1),
            };
        }
        if start.elapsed() > timeout {
            let _ = child.kill();
            let _ = child.wait();
            break Status::TimedOut;
        }
        std::thread::sleep(Duration::from_millis(2));
    };
    let elapsed = start.elapsed();
    let read = |path: &Path| String::from_utf8_lossy(&std::fs::read(path).unwrap()).into_owned();
    Run {
        status,
        stdout: read(&out_path),
        stderr: read(&err_path),
        elapsed,
    }
}

/// The entries of a folder, by name.
fn snapshot(dir: &Path) -> BTreeMap<String, Entry> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|entry| {
            let entry = entry.unwrap();
            let path = entry.path();
            let kind = entry.file_type().unwrap();
            let value = if kind.is_symlink() {
                Entry::Link(std::fs::read_link(&path).unwrap())
            } else if kind.is_dir() {
                match std::fs::read_dir(&path).unwrap().count() {
                    0 => Entry::Dir,
                    n => Entry::File(format!("a folder of {n} entries").into_bytes()),
                }
            } else {
                Entry::File(std::fs::read(&path).unwrap())
            };
            (entry.file_name().to_string_lossy().into_owned(), value)
        })
        .collect()
}

fn write_files(dir: &Path, files: &[(String, Entry)]) {
    for (name, entry) in files {
        let path = dir.join(name);
        match entry {
            Entry::File(bytes) => std::fs::write(&path, bytes).unwrap(),
            Entry::Dir => std::fs::create_dir(&path).unwrap(),
            Entry::Link(target) => std::os::unix::fs::symlink(target, &path).unwrap(),
        }
    }
}

/// What a run of a mutant gave.
#[derive(Clone, Debug, PartialEq)]
enum Outcome {
    /// Exit status 0.
    Read,
    /// Exit status 1 with this error message.
    Refused(String),
    /// Anything else (a failure).
    Broken,
}

/// The problems of a finished run: its status, its stderr (one clean error
/// line naming `input` on failure), the output folder `out` (nothing left after
/// a failure, only the command's `outputs` after a success) and the inputs (as
/// `before`, in `inputs`).
fn check(
    run: &Run,
    input: &Path,
    outputs: Vec<String>,
    (out, inputs): (&Path, &Path),
    before: &BTreeMap<String, Entry>,
) -> (Outcome, Vec<String>) {
    let mut problems = Vec::new();
    let mut outcome = Outcome::Broken;
    match run.status {
        Status::Code(0) => outcome = Outcome::Read,
        Status::Code(1) => {}
        Status::Code(101) => problems.push("exit status 101 (a panic)".to_string()),
        Status::Code(code) => problems.push(format!("exit status {code}")),
        Status::Signal(signal) => problems.push(format!("killed by signal {signal}")),
        Status::TimedOut => problems.push(format!(
            "still running after {RERUN_TIMEOUT:?} (a hang), killed"
        )),
    }
    if let Some(text) = PANIC_TEXT.iter().find(|t| run.stderr.contains(*t)) {
        problems.push(format!("stderr says '{text}' (a panic or an abort)"));
    }
    let lines: Vec<&str> = run
        .stderr
        .lines()
        .filter(|l| !l.trim().is_empty())
        .collect();
    let errors: Vec<&str> = lines
        .iter()
        .filter_map(|l| l.strip_prefix("error: "))
        .collect();
    let others: Vec<&&str> = lines
        .iter()
        .filter(|l| !l.starts_with("error: ") && !l.starts_with("warning: "))
        .collect();
    for warning in lines.iter().filter_map(|l| l.strip_prefix("warning: ")) {
        if let Some(problem) = text_problem(warning) {
            problems.push(format!("a warning {problem}: {warning}"));
        }
    }
    if !others.is_empty() {
        problems.push(format!(
            "stderr has lines that are neither errors nor warnings: {others:?}"
        ));
    }
    if run.status == Status::Code(1) {
        match errors.as_slice() {
            [message] => {
                outcome = Outcome::Refused(message.to_string());
                if let Some(problem) = error_problem(message, input) {
                    problems.push(format!("the error {problem}: {message}"));
                }
            }
            _ => problems.push(format!("{} error lines, not one", errors.len())),
        }
    } else if !errors.is_empty() {
        problems.push(format!(
            "error lines {errors:?} with status {:?}",
            run.status
        ));
    }
    // A killed run may leave its temporary files: only finished runs are judged.
    if run.status != Status::TimedOut {
        let left: Vec<String> = snapshot(out).into_keys().collect();
        let expected = if outcome == Outcome::Read {
            outputs
        } else {
            Vec::new()
        };
        if left != expected {
            problems.push(format!(
                "the output folder holds {left:?}, expected {expected:?}"
            ));
        }
    }
    let after = snapshot(inputs);
    if &after != before {
        let changed: Vec<&String> = before
            .keys()
            .chain(after.keys())
            .filter(|name| before.get(*name) != after.get(*name))
            .collect();
        problems.push(format!("the input files changed: {changed:?}"));
    }
    if !problems.is_empty() {
        outcome = Outcome::Broken;
    }
    (outcome, problems)
}

/// A command the tool runs on a mutant.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Cmd {
    /// `crestline info IMAGE`.
    Info,
    /// `crestline iso IMAGE --level L -o OUT/out.ply`, with `--sigma 0` (no
    /// smoothing) if `unsmoothed`.
    Iso { unsmoothed: bool },
}

impl Cmd {
    /// The arguments of the command on `input` (`level` for an isosurface,
    /// written in the folder `out`).
    fn args(self, input: &Path, out: &Path, level: f64) -> Vec<String> {
        let input = input.display().to_string();
        match self {
            Cmd::Info => vec!["info".to_string(), input],
            Cmd::Iso { unsmoothed } => {
                let mut args = vec![
                    "iso".to_string(),
                    input,
                    "--level".to_string(),
                    level.to_string(),
                    "-o".to_string(),
                    out.join("out.ply").display().to_string(),
                ];
                if unsmoothed {
                    args.extend(["--sigma".to_string(), "0".to_string()]);
                }
                args
            }
        }
    }

    /// The output files a successful run leaves.
    fn outputs(self) -> Vec<String> {
        match self {
            Cmd::Info => Vec::new(),
            Cmd::Iso { .. } => vec!["out.ply".to_string()],
        }
    }
}

/// What is wrong with the error message of a failed run on `input`, if
/// anything: it must name the image (by its path or file name) and be clean text.
fn error_problem(message: &str, input: &Path) -> Option<String> {
    let name = input.file_name().unwrap_or_default().to_string_lossy();
    if !message.contains(&input.display().to_string()) && !message.contains(&*name) {
        return Some("does not name the file".to_string());
    }
    text_problem(message)
}

/// A mutant to run.
struct Job {
    /// The seed of the run.
    run_seed: u64,
    /// The seed image.
    seed: usize,
    index: usize,
    mutant: Mutant,
    /// `info`, then for some mutants `iso`.
    commands: Vec<Cmd>,
}

/// The runs of a mutant, judged.
struct Judged {
    /// The outcome of each command of the job.
    outcomes: Vec<Outcome>,
    problems: Vec<String>,
    /// The time of all the runs.
    elapsed: Duration,
    /// The runs killed once after [`TIMEOUT`] and run again.
    reruns: usize,
}

/// Write the job's files in a folder of their own under `root`, run each of its
/// commands (again with a longer timeout if one timed out) and judge the runs.
fn run_job(job: &Job, seed: &Seed, root: &Path) -> Judged {
    let dir = root.join(format!("{}-{}", job.seed, job.index));
    let (inputs, out, logs) = (dir.join("in"), dir.join("out"), dir.join("logs"));
    for d in [&inputs, &out, &logs] {
        std::fs::create_dir_all(d).unwrap();
    }
    write_files(&inputs, &job.mutant.files);
    let before = snapshot(&inputs);
    let input = inputs.join(seed.file);
    let mut judged = Judged {
        outcomes: Vec::new(),
        problems: Vec::new(),
        elapsed: Duration::ZERO,
        reruns: 0,
    };
    for &cmd in &job.commands {
        let args = cmd.args(&input, &out, seed.level);
        let mut run = run_tool(&args, &out, &logs, TIMEOUT);
        if run.status == Status::TimedOut {
            judged.reruns += 1;
            std::fs::remove_dir_all(&out).unwrap();
            std::fs::create_dir(&out).unwrap();
            run = run_tool(&args, &out, &logs, RERUN_TIMEOUT);
        }
        judged.elapsed += run.elapsed;
        let (outcome, problems) = check(&run, &input, cmd.outputs(), (&out, &inputs), &before);
        if std::env::var_os("CRESTLINE_FUZZ_SHOW").is_some() {
            if let Outcome::Refused(message) = &outcome {
                println!("{message}");
            }
        }
        if !problems.is_empty() {
            let kept = kept_mutant(job, seed);
            let shown = cmd.args(&kept.join(seed.file), &std::env::temp_dir(), seed.level);
            keep_failure(job, &kept, judged.problems.is_empty(), &run, &shown);
            judged
                .problems
                .extend(problems.iter().map(|p| format!("{}: {p}", args[0])));
            judged.problems.push(format!(
                "kept in {}; run again with: crestline {}",
                kept.display(),
                shown.join(" ")
            ));
            judged
                .problems
                .push(format!("stderr: {}", run.stderr.trim_end()));
        }
        judged.outcomes.push(outcome);
        // The next command starts with an empty output folder.
        std::fs::remove_dir_all(&out).unwrap();
        std::fs::create_dir(&out).unwrap();
    }
    std::fs::remove_dir_all(&dir).unwrap();
    judged
}

/// The folder under the system's temporary folder where the failing mutants of
/// the run with seed `run_seed` are kept.
fn failure_folder(run_seed: u64) -> PathBuf {
    std::env::temp_dir()
        .join("crestline-fuzz-volumes")
        .join(format!("seed-{run_seed}"))
}

/// The folder where a failing mutant is kept.
fn kept_mutant(job: &Job, seed: &Seed) -> PathBuf {
    let name = format!("{}-{}", seed.name, job.index).replace([' ', '+', '(', ')'], "_");
    failure_folder(job.run_seed).join(name)
}

/// Keep a failing mutant in the folder `dir` (written when `first` of its
/// failing runs is kept), and add what the tool printed for `shown` (the command
/// on the kept copy) to the file `fuzz-run.txt` there.
fn keep_failure(job: &Job, dir: &Path, first: bool, run: &Run, shown: &[String]) {
    let log = dir.join("fuzz-run.txt");
    if first {
        let _ = std::fs::remove_dir_all(dir);
        std::fs::create_dir_all(dir).unwrap();
        write_files(dir, &job.mutant.files);
        std::fs::write(&log, job.mutant.notes.join("\n") + "\n").unwrap();
    }
    let entry = format!(
        "\n$ crestline {}\nstatus: {:?}\n--- stdout\n{}--- stderr\n{}",
        shown.join(" "),
        run.status,
        run.stdout,
        run.stderr
    );
    let mut file = std::fs::OpenOptions::new().append(true).open(&log).unwrap();
    file.write_all(entry.as_bytes()).unwrap();
}

/// Run the jobs on a few threads (each starts processes); their judgements in
/// order.
fn run_all(jobs: &[Job], seeds: &[Seed], root: &Path) -> Vec<Judged> {
    let workers = std::thread::available_parallelism()
        .map_or(2, usize::from)
        .clamp(1, 4);
    let next = AtomicUsize::new(0);
    let results: Mutex<Vec<Option<Judged>>> = Mutex::new((0..jobs.len()).map(|_| None).collect());
    std::thread::scope(|scope| {
        for _ in 0..workers {
            scope.spawn(|| loop {
                let n = next.fetch_add(1, Ordering::Relaxed);
                let Some(job) = jobs.get(n) else { break };
                let judged = run_job(job, &seeds[job.seed], root);
                results.lock().unwrap()[n] = Some(judged);
            });
        }
    });
    results
        .into_inner()
        .unwrap()
        .into_iter()
        .map(|r| r.expect("every job ran"))
        .collect()
}

/// Tallies of one seed image.
#[derive(Default)]
struct Tally {
    mutants: usize,
    /// `info` exited with 0.
    read: usize,
    /// `info` exited with 1 and a clean error.
    refused: usize,
    iso_read: usize,
    iso_refused: usize,
    /// Mutants with a problem.
    failed: usize,
    /// Runs killed after [`TIMEOUT`] and run again.
    reruns: usize,
    /// The time of all runs.
    total: Duration,
    /// The slowest mutant (all its runs).
    slowest: Duration,
}

fn print_table(seeds: &[Seed], tallies: &[Tally], seed: u64, wall: Duration) {
    println!(
        "\nimage fuzzing through `crestline info` (every {ISO_EVERY}th mutant also `iso`, \
         half of those with --sigma 0), seed {seed}"
    );
    println!(
        "{:<26} {:>7} {:>7} {:>6} {:>7} {:>9} {:>7} {:>7} {:>8} {:>10}",
        "image",
        "mutants",
        "info ok",
        "error",
        "iso ok",
        "iso error",
        "failed",
        "re-runs",
        "mean ms",
        "slowest ms"
    );
    for (seed, t) in seeds.iter().zip(tallies) {
        println!(
            "{:<26} {:>7} {:>7} {:>6} {:>7} {:>9} {:>7} {:>7} {:>8.1} {:>10.1}",
            seed.name,
            t.mutants,
            t.read,
            t.refused,
            t.iso_read,
            t.iso_refused,
            t.failed,
            t.reruns,
            t.total.as_secs_f64() * 1e3 / t.mutants.max(1) as f64,
            t.slowest.as_secs_f64() * 1e3
        );
    }
    let total: usize = tallies.iter().map(|t| t.mutants).sum();
    println!("{total} mutants in {:.1} s", wall.as_secs_f64());
}

#[test]
fn seed_images_are_read_by_the_tool() {
    let root = tempfile::tempdir().unwrap();
    for (k, seed) in seeds().iter().enumerate() {
        let dir = root.path().join(k.to_string());
        let (inputs, out) = (dir.join("in"), dir.join("out"));
        std::fs::create_dir_all(&inputs).unwrap();
        std::fs::create_dir_all(&out).unwrap();
        write_files(&inputs, &seed.files());
        let input = inputs.join(seed.file);
        let commands = [
            Cmd::Info,
            Cmd::Iso { unsmoothed: false },
            Cmd::Iso { unsmoothed: true },
        ];
        for cmd in commands {
            let args = cmd.args(&input, &out, seed.level);
            let run = run_tool(&args, &out, &dir, RERUN_TIMEOUT);
            assert_eq!(
                (run.status, run.stderr.as_str()),
                (Status::Code(0), ""),
                "{} ({cmd:?})",
                seed.name
            );
            if cmd != Cmd::Info {
                let ply = std::fs::read(out.join("out.ply")).unwrap();
                assert!(ply.starts_with(b"ply\n"), "{}", seed.name);
                std::fs::remove_file(out.join("out.ply")).unwrap();
            } else {
                assert!(
                    run.stdout.contains("6 × 5 × 4 (120 voxels)"),
                    "{}: {}",
                    seed.name,
                    run.stdout
                );
            }
        }
    }
}

/// The checks are not vacuous: each kind of failure the fuzzer looks for is
/// caught in a run made up here.
#[test]
fn the_checks_catch_each_kind_of_failure() {
    let root = tempfile::tempdir().unwrap();
    let (inputs, out) = (root.path().join("in"), root.path().join("out"));
    std::fs::create_dir_all(&inputs).unwrap();
    std::fs::create_dir_all(&out).unwrap();
    write_files(
        &inputs,
        &[("image.nii".to_string(), Entry::File(vec![1, 2, 3]))],
    );
    let before = snapshot(&inputs);
    let input = inputs.join("image.nii");
    let problems = |status: Status, stderr: &str| {
        let run = Run {
            status,
            stdout: String::new(),
            stderr: stderr.to_string(),
            elapsed: Duration::ZERO,
        };
        check(&run, &input, Vec::new(), (&out, &inputs), &before).1
    };
    let clean = format!(
        "warning: {0}: odd\nerror: {0}: bad header\n",
        input.display()
    );
    assert_eq!(problems(Status::Code(1), &clean), Vec::<String>::new());
    assert_eq!(
        problems(Status::Code(1), "error: image.nii: bad\n"),
        Vec::<String>::new()
    );
    assert_eq!(
        problems(Status::Code(0), "warning: odd\n"),
        Vec::<String>::new()
    );
    let failures = [
        (
            Status::Code(101),
            "thread 'main' panicked at src/x.rs:1:1:\n",
        ),
        (Status::Signal(6), "memory allocation of 8 bytes failed\n"),
        (Status::TimedOut, ""),
        (Status::Code(2), "error: unexpected argument\n"),
        (Status::Code(1), "error: bad header\n"),
        (Status::Code(1), "error: image.nii: bad\nheader\n"),
        (
            Status::Code(1),
            "error: image.nii: bad\nerror: image.nii: worse\n",
        ),
        (Status::Code(1), "error: image.nii: Some(3)\n"),
        (
            Status::Code(1),
            "error: image.nii: Custom { kind: Other }\n",
        ),
        (Status::Code(1), ""),
        (Status::Code(0), "error: image.nii: bad\n"),
        (Status::Code(0), "warning: Some(3)\n"),
    ];
    for (status, stderr) in failures {
        assert_ne!(
            problems(status, stderr),
            Vec::<String>::new(),
            "{status:?} {stderr}"
        );
    }
    std::fs::write(out.join(".crestline-x1.ply"), "").unwrap();
    assert_ne!(problems(Status::Code(1), &clean), Vec::<String>::new());
    std::fs::remove_file(out.join(".crestline-x1.ply")).unwrap();
    std::fs::write(&input, [1, 2, 4]).unwrap();
    assert_ne!(problems(Status::Code(1), &clean), Vec::<String>::new());
}

#[test]
fn mutants_never_crash_hang_garble_their_errors_or_leave_files() {
    let count = env_number("CRESTLINE_FUZZ_MUTANTS").map_or(DEFAULT_MUTANTS, |n| n as usize);
    let seed = env_number("CRESTLINE_FUZZ_SEED").unwrap_or(0x5ee_d1ce);
    let seeds = seeds();
    let mut jobs = Vec::new();
    for (k, image) in seeds.iter().enumerate() {
        let mut rng = Rng(seed ^ (k as u64 + 1).wrapping_mul(0x2545_f491_4f6c_dd1d));
        for index in 0..count {
            jobs.push(Job {
                run_seed: seed,
                seed: k,
                index,
                mutant: mutant(image, &mut rng),
                commands: match index % (2 * ISO_EVERY) {
                    n if n == ISO_EVERY - 1 => vec![Cmd::Info, Cmd::Iso { unsmoothed: false }],
                    n if n == 2 * ISO_EVERY - 1 => vec![Cmd::Info, Cmd::Iso { unsmoothed: true }],
                    _ => vec![Cmd::Info],
                },
            });
        }
    }
    let root = tempfile::tempdir().unwrap();
    let start = Instant::now();
    let judged = run_all(&jobs, &seeds, root.path());
    let wall = start.elapsed();
    let mut tallies: Vec<Tally> = seeds.iter().map(|_| Tally::default()).collect();
    let mut failures = Vec::new();
    for (job, result) in jobs.iter().zip(&judged) {
        let t = &mut tallies[job.seed];
        t.mutants += 1;
        t.total += result.elapsed;
        t.slowest = t.slowest.max(result.elapsed);
        t.reruns += result.reruns;
        for (cmd, outcome) in job.commands.iter().zip(&result.outcomes) {
            match (cmd, outcome) {
                (Cmd::Info, Outcome::Read) => t.read += 1,
                (Cmd::Info, Outcome::Refused(_)) => t.refused += 1,
                (Cmd::Iso { .. }, Outcome::Read) => t.iso_read += 1,
                (Cmd::Iso { .. }, Outcome::Refused(_)) => t.iso_refused += 1,
                (_, Outcome::Broken) => {}
            }
        }
        if let Some(first) = result.problems.first() {
            t.failed += 1;
            let text = format!(
                "{} mutant {}: {}\n  {}",
                seeds[job.seed].name,
                job.index,
                job.mutant.notes.join("; "),
                result.problems.join("\n  ")
            );
            failures.push((problem_kind(first), text));
        }
    }
    print_table(&seeds, &tallies, seed, wall);
    if failures.is_empty() {
        return;
    }
    let list = failure_folder(seed).join("failures.txt");
    let all: Vec<&str> = failures.iter().map(|(_, text)| text.as_str()).collect();
    std::fs::write(&list, all.join("\n")).unwrap();
    // One example of each kind of problem, the most frequent first.
    let mut kinds: BTreeMap<&str, (usize, &str)> = BTreeMap::new();
    for (kind, text) in &failures {
        kinds.entry(kind).or_insert((0, text)).0 += 1;
    }
    let mut kinds: Vec<_> = kinds.into_iter().collect();
    kinds.sort_by_key(|(_, (count, _))| std::cmp::Reverse(*count));
    let examples: Vec<String> = kinds
        .iter()
        .map(|(kind, (count, text))| format!("{count} × {kind}, e.g.\n{text}"))
        .collect();
    panic!(
        "{} of {} mutants fail (all listed in {}), {} kind(s) of problem:\n\n{}",
        failures.len(),
        jobs.len(),
        list.display(),
        kinds.len(),
        examples.join("\n\n")
    );
}

/// The kind of a problem, to group failures: its command and what is wrong,
/// without the message it quotes or the files it lists.
fn problem_kind(problem: &str) -> String {
    let kind: Vec<&str> = problem.splitn(3, ": ").take(2).collect();
    let kind = kind.join(": ");
    let end = kind.find(['[', '"']).unwrap_or(kind.len());
    kind[..end].trim_end().to_string()
}

// ---------------------------------------------------------------------------
// DICOM input and per-vertex value files

/// Mutants per seed of [`dicom_and_values_mutants_never_crash_or_garble_their_errors`]
/// in a plain `cargo test --release` (`CRESTLINE_FUZZ_MUTANTS` sets it too).
const DEFAULT_OTHER_MUTANTS: usize = 60;

/// A file or folder the tool reads, with the command run on its mutants.
struct OtherSeed {
    name: &'static str,
    /// The files, by name; a seed of several files is a folder (a DICOM series),
    /// one of whose files each mutant changes.
    files: Vec<(String, Vec<u8>)>,
    /// The command on the input (its path), writing into the output folder.
    args: fn(&Path, &Path, &Path) -> Vec<String>,
}

/// pydicom's test file `name`, or `None` when it is not fetched.
fn pydicom_bytes(name: &str) -> Option<Vec<u8>> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../data/dicom/pydicom")
        .join(name);
    std::fs::read(path).ok()
}

/// `bytes` with the first `from` replaced by `to` (of the same length, so that
/// every element length stays right).
fn patched(bytes: &[u8], from: &[u8], to: &[u8]) -> Vec<u8> {
    assert_eq!(from.len(), to.len());
    let at = bytes
        .windows(from.len())
        .position(|w| w == from)
        .expect("the text to patch");
    let mut out = bytes.to_vec();
    out[at..at + to.len()].copy_from_slice(to);
    out
}

/// The octahedron (6 vertices) as OBJ, the mesh of the per-vertex files.
const OCTAHEDRON: &str = "v 1 0 0\nv -1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nv 0 0 -1\n\
    f 1 3 5\nf 3 2 5\nf 2 4 5\nf 4 1 5\nf 3 1 6\nf 2 3 6\nf 4 2 6\nf 1 4 6\n";

/// A per-vertex file written by the library's writer (`.shape.gii` or `.curv`).
fn values_file(name: &str) -> Vec<u8> {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join(name);
    let values = [0.5, 1.25, 3.0, 0.0, 0.125, 7.5];
    let metadata = (&[][..], crestline::io::Structure::default());
    crestline::io::write_vertex_values(&path, &values, metadata, 8).unwrap();
    std::fs::read(path).unwrap()
}

/// The seeds: pydicom's native, RLE and JPEG files, a series of three slices
/// (native and RLE) made from its MR slice by moving it along z, and per-vertex
/// GIfTI and curv files given to `--indicator` and `--smoothing-weights`. DICOM
/// seeds are left out, saying so, when pydicom's files are not fetched.
fn other_seeds() -> Vec<OtherSeed> {
    fn info(input: &Path, _: &Path, _: &Path) -> Vec<String> {
        vec!["info".to_string(), input.display().to_string()]
    }
    fn indicator(input: &Path, mesh: &Path, out: &Path) -> Vec<String> {
        let (input, mesh) = (input.display().to_string(), mesh.display().to_string());
        let out = out.join("out.ply").display().to_string();
        ["morse", &mesh, "--indicator", &input, "-o", &out]
            .map(String::from)
            .to_vec()
    }
    fn weights(input: &Path, mesh: &Path, out: &Path) -> Vec<String> {
        let (input, mesh) = (input.display().to_string(), mesh.display().to_string());
        let out = out.join("out.ply").display().to_string();
        ["ridges", &mesh, "--smoothing-weights", &input, "-o", &out]
            .map(String::from)
            .to_vec()
    }
    let one = |name: &'static str, file: &str, bytes: Vec<u8>, args| OtherSeed {
        name,
        files: vec![(file.to_string(), bytes)],
        args,
    };
    let mut seeds = vec![
        one(
            "GIfTI values --indicator",
            "v.shape.gii",
            values_file("v.shape.gii"),
            indicator,
        ),
        one(
            "curv --smoothing-weights",
            "lh.curv",
            values_file("lh.curv"),
            weights,
        ),
    ];
    let dicom: Vec<(&str, Option<Vec<u8>>)> =
        ["MR_small.dcm", "MR_small_RLE.dcm", "JPGExtended.dcm"]
            .iter()
            .map(|name| (*name, pydicom_bytes(name)))
            .collect();
    if dicom.iter().any(|(_, bytes)| bytes.is_none()) {
        crate::common::skip("the DICOM seeds are absent (run tools/fetch_pydicom_data.sh)");
        return seeds;
    }
    let names = ["DICOM native", "DICOM RLE", "DICOM JPEG extended"];
    for (name, (file, bytes)) in names.into_iter().zip(&dicom) {
        seeds.push(one(name, file, bytes.clone().unwrap_or_default(), info));
    }
    // The MR slice lies at z = 6.6406: two more slices 1 mm and 2 mm further.
    let (native, rle) = (dicom[0].1.clone().unwrap(), dicom[1].1.clone().unwrap());
    let series = vec![
        ("a.dcm".to_string(), native.clone()),
        ("b.dcm".to_string(), patched(&rle, b"\\6.6406", b"\\7.6406")),
        (
            "c.dcm".to_string(),
            patched(&native, b"\\6.6406", b"\\8.6406"),
        ),
    ];
    seeds.push(OtherSeed {
        name: "DICOM series",
        files: series,
        args: info,
    });
    seeds
}

/// Run the tool on one mutant of `seed` in `dir` (on the seed itself without
/// `rng`); its problems.
fn run_other(seed: &OtherSeed, dir: &Path, mut rng: Option<&mut Rng>) -> Vec<String> {
    let (inputs, out) = (dir.join("in"), dir.join("out"));
    for folder in [&inputs, &out] {
        std::fs::create_dir_all(folder).unwrap();
    }
    let mesh = dir.join("octahedron.obj");
    std::fs::write(&mesh, OCTAHEDRON).unwrap();
    let changed = rng.as_deref_mut().map(|rng| rng.below(seed.files.len()));
    let mut notes = Vec::new();
    for (k, (name, bytes)) in seed.files.iter().enumerate() {
        let bytes = match rng.as_deref_mut() {
            Some(rng) if changed == Some(k) => {
                let (bytes, applied) = mutate(bytes, rng);
                notes.push(format!("{name}: {applied:?}"));
                bytes
            }
            _ => bytes.clone(),
        };
        std::fs::write(inputs.join(name), bytes).unwrap();
    }
    let input = match seed.files.as_slice() {
        [(name, _)] => inputs.join(name),
        _ => inputs.clone(),
    };
    let before = snapshot(&inputs);
    let args = (seed.args)(&input, &mesh, &out);
    // `info` writes nothing; the others write `out.ply` when they succeed.
    let outputs = if args[0] == "info" {
        Vec::new()
    } else {
        vec!["out.ply".to_string()]
    };
    let run = run_tool(&args, dir, dir, RERUN_TIMEOUT);
    let (outcome, mut problems) = check(&run, &input, outputs, (&out, &inputs), &before);
    let refused = matches!(outcome, Outcome::Refused(_));
    // Of the seeds only the 12-bit JPEG is refused (jpeg-decoder decodes 8 bits).
    if notes.is_empty() && refused != (seed.name == "DICOM JPEG extended") {
        problems.push(format!("the seed gives {:?}: {}", run.status, run.stderr));
    }
    problems
        .into_iter()
        .map(|p| format!("{} {notes:?}: {p}", seed.name))
        .collect()
}

/// DICOM files and series (native, RLE, JPEG) and per-vertex files given to
/// `--indicator` and `--smoothing-weights`, mutated as the images above and run
/// through the tool under the same limits: exit 0 or 1, no panic or abort text,
/// one error line naming the input, no output left, inputs unchanged.
/// `CRESTLINE_FUZZ_MUTANTS=N` runs N mutants per seed (default
/// [`DEFAULT_OTHER_MUTANTS`]); `tools/fuzz_readers.py` runs thousands per format
/// with the same checks and mutations aimed at each reader's weak spots.
#[test]
fn dicom_and_values_mutants_never_crash_or_garble_their_errors() {
    let count = env_number("CRESTLINE_FUZZ_MUTANTS").map_or(DEFAULT_OTHER_MUTANTS, |n| n as usize);
    let seed = env_number("CRESTLINE_FUZZ_SEED").unwrap_or(0x0d1c_057e);
    let root = tempfile::tempdir().unwrap();
    let mut failures = Vec::new();
    for (k, other) in other_seeds().iter().enumerate() {
        let seed_dir = root.path().join(format!("{k}-seed"));
        failures.extend(run_other(other, &seed_dir, None));
        let mut rng = Rng(seed ^ (k as u64 + 1).wrapping_mul(0x9e37_79b9_7f4a_7c15));
        for index in 0..count {
            let dir = root.path().join(format!("{k}-{index}"));
            failures.extend(run_other(other, &dir, Some(&mut rng)));
            std::fs::remove_dir_all(&dir).unwrap();
        }
    }
    assert!(
        failures.is_empty(),
        "{} failures:\n{}",
        failures.len(),
        failures
            .iter()
            .take(20)
            .cloned()
            .collect::<Vec<_>>()
            .join("\n")
    );
}

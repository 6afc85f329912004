//! Reading and writing triangle meshes.
//!
//! [`read_mesh`] reads OBJ, PLY (ASCII and binary), OFF, STL (ASCII and binary) and
//! GIfTI (`.gii`, see `gifti`) files into a [`TriangleSoup`], choosing the format
//! by the file extension, and FreeSurfer surfaces (see `freesurfer`) by their
//! magic bytes whatever their name (`lh.pial` has no extension); the per-format
//! readers (`read_obj`, `read_ply`, `read_off`, `read_stl`) parse
//! bytes already in memory. Readers check the structure of a file (counts, indices,
//! numbers) and fan polygons into triangles, but keep coordinates as written: a NaN
//! or infinite coordinate is left to [`crate::mesh::Mesh::from_soup`] to reject.
//! Their errors name the line (text formats) or the element and byte offset (binary
//! formats) where the file goes wrong, on one line and in plain words (input text
//! they quote is shortened, and its control characters escaped when the error is
//! displayed). Counts announced by a header are checked against the size of the
//! file before anything is allocated for them, and a polygon declaring more than
//! `MAX_FACE_CORNERS` corners is rejected before its indices are read.
//!
//! [`write_ply`] and [`write_obj`] save a [`crate::mesh::Mesh`]; [`write_soup`] saves
//! any triangles, orientable or not, as PLY, OBJ, VTK or GIfTI. Like every writer of the
//! crate they go through [`crate::atomic::write_atomically`].
//!
//! Per-vertex values come from files of their own through [`read_vertex_values`]
//! (FreeSurfer curv, GIfTI, text), and go to GIfTI and FreeSurfer curv files
//! through [`write_vertex_values`].
//!
//! [`read_volume`] reads 3D images (NIfTI, NRRD, MetaImage, DICOM series) into a
//! [`crate::volume::Volume`], [`VolumeReadOptions::read`] a chosen DICOM series,
//! [`VolumeReadOptions::read_dicom`] a series from a list of files, and `read_raw_volume`
//! headerless samples.
//!
//! Every reader and writer of the crate that picks its format by the file name
//! asks [`choose_format`] for it, among the [`FileFormat`]s it handles. Every PLY
//! header the crate writes comes from one header writer, and every VTK file from
//! one legacy VTK writer, both in this module.

pub(crate) mod file;
mod format;
pub(crate) mod freesurfer;
pub(crate) mod gifti;
pub(crate) mod obj;
mod off;
mod ply;
mod ply_binary;
mod ply_edges;
pub(crate) mod ply_header;
mod ply_records;
mod soup;
mod stl;
mod structure;
mod vertex_data;
mod volume;
pub(crate) mod vtk;

pub use crate::atomic::write_atomically;
pub use format::{choose_format, FileFormat, FormatChoice};
#[cfg(test)]
pub(crate) use obj::read_obj;
pub use obj::write_obj;
#[cfg(test)]
pub(crate) use off::read_off;
#[cfg(test)]
pub(crate) use ply::read_ply;
pub use ply::{write_ply, VertexAttribute};
pub(crate) use ply_edges::read_ply_edges;
pub use soup::{soup_format, write_soup, write_soup_of_structure};
#[cfg(test)]
pub(crate) use stl::read_stl;
pub use structure::Structure;
pub use vertex_data::{read_vertex_values, write_vertex_values};
pub use volume::{is_volume_path, read_volume, volume_files, VolumeReadOptions};
#[cfg(test)]
pub(crate) use volume::{read_raw_volume, SampleType};

use std::path::Path;

use crate::mesh::TriangleSoup;
use crate::{Error, Point, Result, Space};

/// Whether `value` can be stored as a finite 32-bit float (values below f32's
/// smallest positive number round towards zero).
pub(crate) fn fits_f32(value: f64) -> bool {
    value.is_finite() && value.abs() <= f64::from(f32::MAX)
}

/// The formats [`read_mesh`] reads, each with its parser, in the order listed in
/// error messages.
const READERS: [(FileFormat, Parser); 5] = [
    (FileFormat::Obj, obj::parse),
    (FileFormat::Ply, ply::parse),
    (FileFormat::Off, off::parse),
    (FileFormat::Stl, stl::parse),
    (FileFormat::Gifti, gifti::parse_surface),
];

/// The file extensions [`read_mesh`] understands (compared case-insensitively).
#[cfg(test)]
pub(crate) const SUPPORTED_MESH_EXTENSIONS: &[&str] = &format::extensions(&READERS);

/// A callback told how many bytes of a file have been parsed so far and the file's
/// total size, e.g. to drive a progress bar.
pub(crate) type Progress<'a> = &'a dyn Fn(u64, u64);

/// Read a triangle mesh file, choosing the reader by the extension, in any letter
/// case: `.obj`, `.ply` (ASCII, binary little and big endian), `.off` (also `COFF`,
/// `NOFF`, `CNOFF`, `NCOFF`), `.stl` (ASCII and binary) or `.gii` (a GIfTI surface,
/// `.surf.gii`); a FreeSurfer triangle surface (`lh.pial`, `lh.white`) is told by
/// its magic bytes, whatever its name.
///
/// GIfTI and FreeSurfer surfaces are declared [`Space::Ras`]; a FreeSurfer
/// surface with a valid volume geometry is placed in scanner RAS and keeps the
/// geometry ([`TriangleSoup::volume_geometry`], see `freesurfer`).
///
/// Errors are [`Error::File`] naming `path`: an unsupported extension, a missing
/// file, a directory, or malformed content (with the line, element or array).
///
/// # Examples
///
/// ```
/// let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../meshes/bunny_small.obj");
/// let soup = crestline::io::read_mesh(path.as_ref())?;
/// let (mesh, _repairs) = crestline::mesh::Mesh::from_soup(soup)?;
/// assert!(mesh.vertex_count() > 0);
/// # Ok::<(), crestline::Error>(())
/// ```
pub fn read_mesh(path: &Path) -> Result<TriangleSoup> {
    read_mesh_impl(path, None)
}

/// [`read_mesh`], calling `progress(bytes_parsed, total_bytes)` as parsing advances
/// (about every megabyte, and once at the end).
pub fn read_mesh_with_progress(path: &Path, progress: &dyn Fn(u64, u64)) -> Result<TriangleSoup> {
    read_mesh_impl(path, Some(progress))
}

fn read_mesh_impl(path: &Path, progress: Option<Progress<'_>>) -> Result<TriangleSoup> {
    let parse = parser_for(path)?;
    let bytes = file::read(path)?;
    parse_bytes(&bytes, progress, parse).map_err(|e| e.in_file(path))
}

/// A format's parser, working on an [`Input`].
type Parser = fn(&mut Input<'_>) -> Result<TriangleSoup>;

/// The parser of the file at `path`: a FreeSurfer surface by its magic bytes,
/// whatever its name, else the parser of its extension. The path must name a
/// regular file (a pipe is refused before it is opened).
fn parser_for(path: &Path) -> Result<Parser> {
    let magic = file::head(path, 3)?;
    if magic == freesurfer::SURFACE_MAGIC {
        return Ok(freesurfer::surface::parse);
    }
    if magic == freesurfer::CURV_MAGIC {
        return Err(Error::File {
            path: path.to_path_buf(),
            message: "a FreeSurfer curv file (per-vertex values) or quad surface, \
                      not a triangle surface"
                .into(),
        });
    }
    choose_format(path, "a mesh", &READERS)
        .map(|(_, parse)| parse)
        .map_err(|e| match e {
            Error::File { path, message } => Error::File {
                path,
                message: format!(
                    "{message}, or a FreeSurfer surface (told by its first bytes, FF FF FE)"
                ),
            },
            other => other,
        })
}

/// Run `parse` over `bytes`; the common entry of every reader.
fn parse_bytes(
    bytes: &[u8],
    progress: Option<Progress<'_>>,
    parse: Parser,
) -> Result<TriangleSoup> {
    if bytes.is_empty() {
        return Err(Error::Parse("the file is empty".to_string()));
    }
    let mut soup = parse(&mut Input::new(bytes, progress))?;
    soup.space = soup.space.or_else(|| declared_space(bytes));
    if let Some(progress) = progress {
        progress(bytes.len() as u64, bytes.len() as u64);
    }
    Ok(soup)
}

/// How far into a mesh file its frame may be declared, in bytes: the header of a
/// PLY file, the leading comments of an OBJ or OFF file, the header of an STL file.
const FRAME_MARK_REACH: usize = 1024;

/// The frame the head of a mesh file declares by 3D Slicer's mark (`SPACE=RAS`
/// or `SPACE=LPS` in a PLY comment, an OBJ comment or the STL header; see
/// [`Space::from_header`]), if any.
fn declared_space(bytes: &[u8]) -> Option<Space> {
    let head = &bytes[..bytes.len().min(FRAME_MARK_REACH)];
    Space::from_header(&String::from_utf8_lossy(head))
}

/// Report progress after at least this many bytes.
const PROGRESS_STEP: usize = 1 << 20;

/// The bytes of a mesh file being parsed: a cursor that hands out lines or byte
/// blocks, counts lines for error messages and reports progress.
struct Input<'a> {
    bytes: &'a [u8],
    pos: usize,
    /// Number of lines handed out by [`Input::next_line`] (the current line number).
    line: usize,
    progress: Option<Progress<'a>>,
    next_report: usize,
}

impl<'a> Input<'a> {
    fn new(bytes: &'a [u8], progress: Option<Progress<'a>>) -> Self {
        Input {
            bytes,
            pos: 0,
            line: 0,
            progress,
            next_report: PROGRESS_STEP,
        }
    }

    /// Bytes not parsed yet.
    fn remaining(&self) -> usize {
        self.bytes.len() - self.pos
    }

    /// The bytes not parsed yet, without consuming them.
    fn rest(&self) -> &'a [u8] {
        &self.bytes[self.pos..]
    }

    /// Offset of the next byte to parse.
    fn position(&self) -> usize {
        self.pos
    }

    /// The 1-based number of the line last returned by [`Input::next_line`].
    fn line(&self) -> usize {
        self.line
    }

    fn advance(&mut self, n: usize) {
        self.pos += n;
        if self.pos >= self.next_report {
            self.next_report = self.pos + PROGRESS_STEP;
            if let Some(progress) = self.progress {
                progress(self.pos as u64, self.bytes.len() as u64);
            }
        }
    }

    /// The next `n` bytes, or `None` (consuming nothing) if fewer are left.
    fn take(&mut self, n: usize) -> Option<&'a [u8]> {
        let block = self.bytes.get(self.pos..self.pos.checked_add(n)?)?;
        self.advance(n);
        Some(block)
    }

    /// The next line without its line break, or `None` at the end of the input.
    fn next_line(&mut self) -> Result<Option<&'a str>> {
        let rest = &self.bytes[self.pos..];
        if rest.is_empty() {
            return Ok(None);
        }
        let (line, consumed) = match rest.iter().position(|&b| b == b'\n') {
            Some(end) => (&rest[..end], end + 1),
            None => (rest, rest.len()),
        };
        self.line += 1;
        self.advance(consumed);
        let line = line.strip_suffix(b"\r").unwrap_or(line);
        std::str::from_utf8(line).map(Some).map_err(|_| {
            line_error(
                self.line,
                "not text (binary data or an unsupported character encoding)",
            )
        })
    }

    /// The next line that is not blank once a `#` comment is cut off, trimmed.
    fn next_record(&mut self) -> Result<Option<&'a str>> {
        while let Some(line) = self.next_line()? {
            let content = line
                .split_once('#')
                .map_or(line, |(before, _)| before)
                .trim();
            if !content.is_empty() {
                return Ok(Some(content));
            }
        }
        Ok(None)
    }
}

/// A parse error located at a line of a text file.
fn line_error(line: usize, message: impl std::fmt::Display) -> Error {
    Error::Parse(format!("line {line}: {message}"))
}

/// The error for a file that stops before all the elements its header announced.
fn truncated(read: usize, claimed: usize, what: &str) -> Error {
    Error::Parse(format!(
        "the file ends after {read} of {claimed} {what} (truncated file or wrong count in the header)"
    ))
}

/// How many items to reserve for a count claimed by a header: never more than the
/// rest of the file could hold at `min_bytes` bytes per item, so an absurd header
/// cannot trigger a huge allocation.
fn capped_capacity(claimed: usize, remaining_bytes: usize, min_bytes: usize) -> usize {
    claimed.min(remaining_bytes / min_bytes.max(1))
}

/// Parse a number written in a text file, naming the token if it is not one.
/// `nan` and `inf` are numbers here.
fn parse_number<T: std::str::FromStr>(token: &str) -> std::result::Result<T, String> {
    token
        .parse()
        .map_err(|_| format!("cannot read {} as a number", quoted(token)))
}

/// Longest piece of input text quoted in a message, in characters.
const MAX_QUOTED_CHARS: usize = 40;

/// `text` in single quotes for a message, shortened to its first
/// [`MAX_QUOTED_CHARS`] characters if longer (control characters are escaped when
/// the error is displayed).
fn quoted(text: &str) -> String {
    match text.char_indices().nth(MAX_QUOTED_CHARS) {
        Some((end, _)) => format!("'{}...'", &text[..end]),
        None => format!("'{text}'"),
    }
}

/// Most corners a polygon may have: far more than any real mesh uses, few enough
/// that a corrupt count cannot make a reader loop or allocate for long.
pub(crate) const MAX_FACE_CORNERS: usize = 1024;

/// Check the corner count a file declares for a polygon before reading it.
fn check_corner_count(count: u64) -> std::result::Result<usize, String> {
    if count < 3 {
        return Err(format!("a face needs at least 3 corners, found {count}"));
    }
    if count > MAX_FACE_CORNERS as u64 {
        return Err(format!(
            "a face of {count} corners (at most {MAX_FACE_CORNERS} are supported; a corrupt count?)"
        ));
    }
    Ok(count as usize)
}

/// The next three tokens as a point.
fn parse_point<'t>(
    tokens: &mut impl Iterator<Item = &'t str>,
) -> std::result::Result<Point, String> {
    let mut xyz = [0.0; 3];
    for (i, value) in xyz.iter_mut().enumerate() {
        let token = tokens
            .next()
            .ok_or_else(|| format!("a vertex needs 3 coordinates, found {i}"))?;
        *value = parse_number(token)?;
    }
    Ok(Point::from(xyz))
}

/// Check a polygon's 0-based corner indices against `vertex_count` and fan it into
/// triangles `(c0, ci, ci+1)`. `scratch` is a reusable buffer. The error message
/// does not say where the polygon is: the caller prefixes that.
fn push_polygon(
    corners: impl IntoIterator<Item = i64>,
    vertex_count: usize,
    scratch: &mut Vec<u32>,
    triangles: &mut Vec<[u32; 3]>,
) -> std::result::Result<(), String> {
    scratch.clear();
    for index in corners {
        match u32::try_from(index) {
            Ok(i) if (i as usize) < vertex_count => scratch.push(i),
            _ => {
                return Err(format!(
                    "vertex index {index} is out of range (the file has {vertex_count} vertices)"
                ))
            }
        }
    }
    if scratch.len() < 3 {
        return Err(format!(
            "a face needs at least 3 corners, found {}",
            scratch.len()
        ));
    }
    let first = scratch[0];
    triangles.extend(scratch.windows(2).skip(1).map(|w| [first, w[0], w[1]]));
    Ok(())
}

#[cfg(test)]
mod tests;

//! DICOM series input: a folder of slices, a DICOMDIR, a list of files or one
//! (multi-frame) file, read into a [`Volume`] in LPS, the DICOM patient
//! coordinate system (PS3.3 C.7.6.2.1.1).
//!
//! Reading goes in stages, each in its own module:
//!
//! 1. [`files`]: the files of the input (a folder's files with the `DICM` mark,
//!    or those a DICOMDIR references);
//! 2. [`header`]: each file parsed up to its pixel data, once [`lengths`] has
//!    checked its element lengths against its size (files that hold no image are
//!    skipped), with the frames [`multiframe`] finds in it;
//! 3. [`series`]: the files of one Series Instance UID;
//! 4. [`geometry`]: the regular grid of the frames, ordered by position along
//!    the normal of their planes;
//! 5. [`pixels`]: the frames decoded (in parallel, one file per task) into their
//!    slices of the volume, with the modality LUT applied.
//!
//! Errors are [`Error::File`] naming the file at fault, or the input (the folder,
//! DICOMDIR or file given) for what is wrong with the series as a whole.
//! Without the cargo feature `dicom` the same inputs are recognised and refused
//! with an error saying so.

#[cfg(feature = "dicom")]
mod encapsulated;
mod files;
#[cfg(feature = "dicom")]
mod geometry;
#[cfg(feature = "dicom")]
mod header;
#[cfg(feature = "dicom")]
mod lengths;
#[cfg(feature = "dicom")]
mod multiframe;
#[cfg(feature = "dicom")]
mod pixels;
#[cfg(feature = "dicom")]
mod series;

use std::path::{Path, PathBuf};

use crate::volume::Volume;
use crate::{Error, Result};

pub(super) use files::is_dicom_input;

/// Where a series is read from.
#[derive(Clone, Copy, Debug)]
pub(super) enum Input<'a> {
    /// A folder, a DICOMDIR or one file.
    Path(&'a Path),
    /// The files of a series (with other files among them, possibly).
    Files(&'a [PathBuf]),
}

impl Input<'_> {
    /// The path that errors about the series as a whole name: the path given, or
    /// the folder of the first file of a list.
    fn name(self) -> PathBuf {
        match self {
            Input::Path(path) => path.to_path_buf(),
            Input::Files(files) => files
                .first()
                .and_then(|file| file.parent())
                .filter(|dir| !dir.as_os_str().is_empty())
                .unwrap_or(Path::new("."))
                .to_path_buf(),
        }
    }
}

/// The files reading the DICOM input at `path` reads: `path` itself first, then
/// the DICOM files of a folder or the files a DICOMDIR references (as far as
/// they can be listed).
pub(super) fn input_files(path: &Path) -> Vec<PathBuf> {
    let listed = if path.is_dir() {
        files::folder_files(path).unwrap_or_default()
    } else {
        dicomdir_files(path).unwrap_or_default()
    };
    std::iter::once(path.to_path_buf()).chain(listed).collect()
}

/// The files a DICOMDIR references (none for any other file).
#[cfg(feature = "dicom")]
fn dicomdir_files(path: &Path) -> Result<Vec<PathBuf>> {
    if files::is_dicomdir(path) {
        files::dicomdir_files(path)
    } else {
        Ok(Vec::new())
    }
}

/// Without DICOM support a DICOMDIR is not read.
#[cfg(not(feature = "dicom"))]
fn dicomdir_files(_path: &Path) -> Result<Vec<PathBuf>> {
    Ok(Vec::new())
}

/// Without DICOM support every DICOM input is an error saying so.
#[cfg(not(feature = "dicom"))]
pub(super) fn read(input: Input<'_>, _series: Option<&str>) -> Result<Volume> {
    Err(Error::File {
        path: input.name(),
        message: "is DICOM input, but crestline was built without DICOM support (the cargo feature `dicom`)"
            .to_string(),
    })
}

/// The volume of the series in `input`: its only series, or the one whose
/// Series Instance UID is `series`.
#[cfg(feature = "dicom")]
pub(super) fn read(input: Input<'_>, series: Option<&str>) -> Result<Volume> {
    use rayon::prelude::*;

    let name = input.name();
    let in_input = |e: Error| super::in_file(e, &name);
    let files = input_series_files(input)?;
    // Read in parallel, but report the first failing file in the listed order, so
    // that the error does not depend on which thread failed first.
    let read: Vec<Result<Option<header::Header>>> =
        files.par_iter().map(|file| header::read(file)).collect();
    let headers: Vec<header::Header> = read
        .into_iter()
        .collect::<Result<Vec<_>>>()?
        .into_iter()
        .flatten()
        .collect();
    if headers.is_empty() {
        return Err(in_input(Error::Parse(format!(
            "holds no DICOM image (of {} DICOM file{})",
            files.len(),
            if files.len() == 1 { "" } else { "s" }
        ))));
    }
    let chosen = series::choose(headers, series).map_err(in_input)?;
    let frames: Vec<(&header::Header, &header::Frame)> = chosen
        .iter()
        .flat_map(|h| h.frames.iter().map(move |frame| (h, frame)))
        .collect();
    let planes: Vec<&header::Plane> = frames.iter().map(|(_, frame)| &frame.plane).collect();
    let label = |i: usize| {
        let (header, frame) = frames[i];
        if header.frames.len() > 1 {
            format!("frame {} of {}", frame.number + 1, header.path.display())
        } else {
            header.path.display().to_string()
        }
    };
    let stack = geometry::stack(&planes, &label).map_err(in_input)?;
    let samples = decode(&frames, &stack).map_err(in_input)?;
    let volume = Volume::new(
        stack.dims,
        stack.spacing,
        stack.origin,
        stack.direction,
        samples,
    )
    .map_err(in_input)?;
    Ok(volume.with_space(Some(crate::Space::Lps)))
}

/// The files of `input` to look at, or an error for a folder without DICOM
/// files or an empty list.
#[cfg(feature = "dicom")]
fn input_series_files(input: Input<'_>) -> Result<Vec<PathBuf>> {
    let files = match input {
        Input::Path(path) if path.is_dir() => files::folder_files(path)?,
        Input::Path(path) if files::is_dicomdir(path) => files::dicomdir_files(path)?,
        Input::Path(path) => vec![path.to_path_buf()],
        Input::Files(files) => files.to_vec(),
    };
    if files.is_empty() {
        return Err(Error::File {
            path: input.name(),
            message:
                "holds no DICOM file (a file with the DICM mark at byte 128); subfolders are not \
                      searched: give the folder of the series or its DICOMDIR"
                    .to_string(),
        });
    }
    Ok(files)
}

/// The samples of the `frames` in the order of `stack`, one file decoded per
/// task; the voxel count is checked and the buffer reserved fallibly first.
#[cfg(feature = "dicom")]
fn decode(
    frames: &[(&header::Header, &header::Frame)],
    stack: &geometry::Stack,
) -> Result<Vec<f32>> {
    use rayon::prelude::*;
    use std::collections::BTreeMap;

    let count = crate::volume::voxel_count(stack.dims)?;
    let mut samples = super::reserve_samples(count)?;
    samples.resize(count, 0.0);
    let slice = stack.dims[0] * stack.dims[1];
    let mut by_file: BTreeMap<&Path, Vec<pixels::Target>> = BTreeMap::new();
    for (out, &i) in samples.chunks_mut(slice).zip(&stack.order) {
        let (header, frame) = frames[i];
        by_file
            .entry(&header.path)
            .or_default()
            .push((frame.number, frame.rescale, out));
    }
    let decoded: Vec<Result<()>> = by_file
        .into_par_iter()
        .map(|(path, targets)| pixels::decode(path, targets))
        .collect();
    decoded.into_iter().collect::<Result<()>>()?;
    Ok(samples)
}

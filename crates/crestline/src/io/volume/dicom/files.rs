//! Which files a DICOM input is: the images of a folder, the files a DICOMDIR
//! references, or one file.
//!
//! A DICOM file (PS3.10 §7.1) starts with a 128-byte preamble followed by the
//! four characters `DICM`; that mark tells DICOM files from the other files a
//! folder may hold (a readme, a DICOMDIR's own index, hidden files), which are
//! skipped. A DICOMDIR (PS3.3 F.2, Basic Directory IOD) lists the files of its
//! media in its Directory Record Sequence (0004,1220), each by its Referenced
//! File ID (0004,1500): path components relative to the DICOMDIR's folder.

use std::path::{Path, PathBuf};

use crate::io::file;
use crate::io::format::{choose_format, FileFormat};
use crate::{Error, Result};

/// The name of the index file of DICOM media (PS3.10 §8.6), in any letter case.
const DICOMDIR: &str = "DICOMDIR";

/// Whether `path` names DICOM input: a folder, a DICOMDIR, a `.dcm` file, or a
/// file with the `DICM` mark after its preamble (such as `.dicom` files and the
/// extensionless files of DICOM media).
pub(in crate::io::volume) fn is_dicom_input(path: &Path) -> bool {
    path.is_dir() || is_dicomdir(path) || has_dicom_extension(path) || has_dicm_mark(path)
}

/// Whether the file name of `path` is `DICOMDIR` (in any letter case).
pub(super) fn is_dicomdir(path: &Path) -> bool {
    path.file_name()
        .is_some_and(|name| name.to_string_lossy().eq_ignore_ascii_case(DICOMDIR))
}

/// Whether `path` ends in `.dcm` (in any letter case).
fn has_dicom_extension(path: &Path) -> bool {
    choose_format(path, "a DICOM file", &[FileFormat::Dicom]).is_ok()
}

/// Whether `path` is a regular file holding `DICM` at byte 128 (PS3.10 §7.1).
/// Anything else (a pipe, a device) is not opened.
pub(super) fn has_dicm_mark(path: &Path) -> bool {
    file::head(path, 132).is_ok_and(|head| head.get(128..) == Some(b"DICM"))
}

/// The DICOM files in the folder `dir`, in the order of their names: regular
/// files with the `DICM` mark, not hidden and not a DICOMDIR. Subfolders are not
/// searched (a DICOMDIR names the files of nested media folders).
pub(super) fn folder_files(dir: &Path) -> Result<Vec<PathBuf>> {
    let entries = std::fs::read_dir(dir).map_err(|e| Error::io(dir, e))?;
    let mut files = Vec::new();
    for entry in entries {
        let path = entry.map_err(|e| Error::io(dir, e))?.path();
        let hidden = path
            .file_name()
            .is_some_and(|name| name.to_string_lossy().starts_with('.'));
        if !hidden && !is_dicomdir(&path) && has_dicm_mark(&path) {
            files.push(path);
        }
    }
    files.sort();
    Ok(files)
}

/// The path of the file a DICOMDIR at `dicomdir` references by the components of
/// its Referenced File ID, or an error for one that leaves the DICOMDIR's folder
/// (an empty, `.`, `..` or absolute component).
#[cfg(feature = "dicom")]
fn referenced_file(dicomdir: &Path, components: &[String]) -> Result<PathBuf> {
    let mut path = dicomdir.parent().unwrap_or(Path::new("")).to_path_buf();
    for component in components {
        let component = component.trim();
        let plain = !component.is_empty()
            && component != "."
            && component != ".."
            && !component.contains(['/', '\\']);
        if !plain {
            return Err(Error::File {
                path: dicomdir.to_path_buf(),
                message: format!(
                    "a Referenced File ID (0004,1500) '{}' is not a path inside the DICOMDIR's folder",
                    components.join("\\")
                ),
            });
        }
        path.push(component);
    }
    Ok(path)
}

/// The files the DICOMDIR at `path` references, in the order of its records.
#[cfg(feature = "dicom")]
pub(super) fn dicomdir_files(path: &Path) -> Result<Vec<PathBuf>> {
    use dicom_dictionary_std::tags;

    file::regular_file(path)?;
    let object = dicom_object::open_file(path).map_err(|e| Error::File {
        path: path.to_path_buf(),
        message: format!(
            "cannot be read as a DICOMDIR: {}",
            super::header::causes(&e)
        ),
    })?;
    let records = object
        .get(tags::DIRECTORY_RECORD_SEQUENCE)
        .and_then(|element| element.items())
        .unwrap_or_default();
    records
        .iter()
        .filter_map(|record| record.get(tags::REFERENCED_FILE_ID))
        .map(|id| {
            let components = id.to_multi_str().map_err(|_| Error::File {
                path: path.to_path_buf(),
                message: "has a Referenced File ID (0004,1500) that is not text".to_string(),
            })?;
            referenced_file(path, &components)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_folder_keeps_only_marked_files_in_name_order() {
        let dir = tempfile::tempdir().unwrap();
        let marked = |name: &str| {
            let mut bytes = vec![0u8; 128];
            bytes.extend_from_slice(b"DICM");
            std::fs::write(dir.path().join(name), bytes).unwrap();
        };
        marked("b");
        marked("a.dcm");
        marked(".hidden");
        marked("DICOMDIR");
        std::fs::write(dir.path().join("README"), "notes").unwrap();
        std::fs::create_dir(dir.path().join("sub")).unwrap();
        let names: Vec<String> = folder_files(dir.path())
            .unwrap()
            .iter()
            .map(|p| p.file_name().unwrap().to_string_lossy().into_owned())
            .collect();
        assert_eq!(names, ["a.dcm", "b"]);
    }

    #[test]
    #[cfg(feature = "dicom")]
    fn referenced_files_stay_in_the_dicomdir_folder() {
        let dicomdir = Path::new("media/DICOMDIR");
        let parts = |p: &[&str]| p.iter().map(|s| s.to_string()).collect::<Vec<_>>();
        let inside = referenced_file(dicomdir, &parts(&["PT0", "IM1 "])).unwrap();
        assert_eq!(inside, Path::new("media/PT0/IM1"));
        for bad in [&["..", "x"][..], &["/etc"], &[""]] {
            let err = referenced_file(dicomdir, &parts(bad)).unwrap_err();
            assert!(err.to_string().contains("not a path inside"), "{err}");
        }
    }

    #[test]
    fn dicom_inputs_are_told_by_name_folder_or_mark() {
        let dir = tempfile::tempdir().unwrap();
        assert!(is_dicom_input(dir.path()));
        assert!(is_dicom_input(Path::new("x/Dicomdir")));
        assert!(is_dicom_input(Path::new("slice.DCM")));
        let unmarked = dir.path().join("scan.nii");
        std::fs::write(&unmarked, [0u8; 400]).unwrap();
        assert!(!is_dicom_input(&unmarked));
    }
}

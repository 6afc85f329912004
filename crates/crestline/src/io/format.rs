//! File formats and the one place that tells them by a file's name.
//!
//! [`FileFormat`] lists every kind of file crestline reads or writes.
//! [`choose_format`] maps a path to the one of a caller's choices (the formats it
//! reads or writes, or its own format enum, or formats paired with their readers)
//! that the name ends in: in any letter case, a double extension such as `.nii.gz`
//! or `.mrk.json` before the single one it ends with. Every reader and writer that
//! picks its format by the file name goes through it, so all of them accept the same
//! names and fail with the same message, naming the file and the extensions
//! accepted.

use std::path::Path;

use crate::{Error, Result};

/// A kind of file crestline reads or writes, named by its extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum FileFormat {
    /// `.obj`: Wavefront OBJ (meshes, surfaces, feature lines).
    Obj,
    /// `.ply`: Stanford PLY (meshes with vertex properties, feature lines).
    Ply,
    /// `.off`: Object File Format meshes.
    Off,
    /// `.stl`: STL meshes, ASCII or binary.
    Stl,
    /// `.vtk`: legacy VTK poly data (surfaces, feature lines).
    Vtk,
    /// `.vtp`: VTK XML poly data (feature lines).
    Vtp,
    /// `.vtu`: VTK XML unstructured grids (feature lines as segments).
    Vtu,
    /// `.json`: crestline's own JSON documents (feature lines, landmarks,
    /// transforms, reports).
    Json,
    /// `.mrk.json`: 3D Slicer markups.
    SlicerMarkups,
    /// `.csv`: comma-separated tables.
    Csv,
    /// `.tfm`: ITK text transform files.
    ItkTransform,
    /// `.svg`: line drawings.
    Svg,
    /// `.png`: rendered drawings.
    Png,
    /// `.html`: interactive 3D views.
    Html,
    /// `.nii`: NIfTI-1 or NIfTI-2 images.
    Nifti,
    /// `.nii.gz`: gzip-compressed NIfTI images.
    NiftiGz,
    /// `.nrrd`: NRRD images.
    Nrrd,
    /// `.nhdr`: NRRD headers with a detached data file.
    NrrdHeader,
    /// `.mha`: MetaImage images.
    MetaImage,
    /// `.mhd`: MetaImage headers with a detached data file.
    MetaImageHeader,
    /// `.dcm`: DICOM files (a series is also read from a folder or a DICOMDIR).
    Dicom,
    /// `.gii`: GIfTI files (surfaces, per-vertex values, labels).
    Gifti,
    /// `.surf.gii`: GIfTI surfaces.
    GiftiSurface,
    /// `.shape.gii`: GIfTI per-vertex shape measures (curvature, thickness).
    GiftiShape,
    /// `.func.gii`: GIfTI per-vertex functional data.
    GiftiFunc,
    /// `.label.gii`: GIfTI per-vertex labels.
    GiftiLabel,
    /// `.curv`: FreeSurfer per-vertex values (new curv format).
    FreeSurferCurv,
    /// `.label`: FreeSurfer ASCII labels.
    FreeSurferLabel,
    /// `.border`: Connectome Workbench border files (lines on a surface).
    Border,
}

impl FileFormat {
    /// Every format.
    pub const ALL: [FileFormat; 29] = [
        FileFormat::Obj,
        FileFormat::Ply,
        FileFormat::Off,
        FileFormat::Stl,
        FileFormat::Vtk,
        FileFormat::Vtp,
        FileFormat::Vtu,
        FileFormat::Json,
        FileFormat::SlicerMarkups,
        FileFormat::Csv,
        FileFormat::ItkTransform,
        FileFormat::Svg,
        FileFormat::Png,
        FileFormat::Html,
        FileFormat::Nifti,
        FileFormat::NiftiGz,
        FileFormat::Nrrd,
        FileFormat::NrrdHeader,
        FileFormat::MetaImage,
        FileFormat::MetaImageHeader,
        FileFormat::Dicom,
        FileFormat::Gifti,
        FileFormat::GiftiSurface,
        FileFormat::GiftiShape,
        FileFormat::GiftiFunc,
        FileFormat::GiftiLabel,
        FileFormat::FreeSurferCurv,
        FileFormat::FreeSurferLabel,
        FileFormat::Border,
    ];

    /// The extension, lowercase and without the leading dot (`"nii.gz"` for
    /// [`FileFormat::NiftiGz`]).
    pub const fn extension(self) -> &'static str {
        match self {
            FileFormat::Obj => "obj",
            FileFormat::Ply => "ply",
            FileFormat::Off => "off",
            FileFormat::Stl => "stl",
            FileFormat::Vtk => "vtk",
            FileFormat::Vtp => "vtp",
            FileFormat::Vtu => "vtu",
            FileFormat::Json => "json",
            FileFormat::SlicerMarkups => "mrk.json",
            FileFormat::Csv => "csv",
            FileFormat::ItkTransform => "tfm",
            FileFormat::Svg => "svg",
            FileFormat::Png => "png",
            FileFormat::Html => "html",
            FileFormat::Nifti => "nii",
            FileFormat::NiftiGz => "nii.gz",
            FileFormat::Nrrd => "nrrd",
            FileFormat::NrrdHeader => "nhdr",
            FileFormat::MetaImage => "mha",
            FileFormat::MetaImageHeader => "mhd",
            FileFormat::Dicom => "dcm",
            FileFormat::Gifti => "gii",
            FileFormat::GiftiSurface => "surf.gii",
            FileFormat::GiftiShape => "shape.gii",
            FileFormat::GiftiFunc => "func.gii",
            FileFormat::GiftiLabel => "label.gii",
            FileFormat::FreeSurferCurv => "curv",
            FileFormat::FreeSurferLabel => "label",
            FileFormat::Border => "border",
        }
    }

    /// Whether the lowercase file name `name` ends in this format's extension
    /// after a non-empty stem (a hidden file such as `.ply` has no extension).
    fn names(self, name: &str) -> bool {
        name.strip_suffix(self.extension())
            .and_then(|stem| stem.strip_suffix('.'))
            .is_some_and(|stem| !stem.is_empty())
    }
}

/// One of the ways a kind of file can be read or written, told by its
/// [`FileFormat`]: a format itself, a writer's own format enum (such as
/// [`crate::lines::LineFormat`]), or a format paired with its reader or writer.
pub trait FormatChoice: Copy {
    /// The file format of this choice.
    fn file_format(self) -> FileFormat;
}

impl FormatChoice for FileFormat {
    fn file_format(self) -> FileFormat {
        self
    }
}

impl<T: Copy> FormatChoice for (FileFormat, T) {
    fn file_format(self) -> FileFormat {
        self.0
    }
}

/// The one of `choices` whose format the name of `path` ends in, compared in any
/// letter case; of two that match (`.json` and `.mrk.json`) the longer extension.
///
/// `what` says what the file holds, for the error (e.g. `"feature lines"`, `"a
/// mesh"`): an [`Error::File`] naming `path`, its extension (or that it has none)
/// and the extensions of `choices`, in their order.
pub fn choose_format<T: FormatChoice>(path: &Path, what: &str, choices: &[T]) -> Result<T> {
    longest_match(&lowercase_name(path), choices.iter().copied())
        .ok_or_else(|| unsupported(path, what, choices))
}

/// The extensions of the formats of `choices`, in order: the lists of supported
/// extensions that readers publish, such as [`super::SUPPORTED_MESH_EXTENSIONS`].
#[cfg(test)]
pub(crate) const fn extensions<T, const N: usize>(
    choices: &[(FileFormat, T); N],
) -> [&'static str; N] {
    let mut extensions = [""; N];
    let mut i = 0;
    while i < N {
        extensions[i] = choices[i].0.extension();
        i += 1;
    }
    extensions
}

/// The file name of `path` in ASCII lowercase, empty without one.
fn lowercase_name(path: &Path) -> String {
    path.file_name()
        .map(|name| name.to_string_lossy().to_ascii_lowercase())
        .unwrap_or_default()
}

/// The error for a `path` whose name ends in none of the formats of `choices`.
fn unsupported<T: FormatChoice>(path: &Path, what: &str, choices: &[T]) -> Error {
    let known = longest_match(&lowercase_name(path), FileFormat::ALL);
    let extension = known
        .map(|format| format.extension().to_string())
        .or_else(|| path.extension().map(|e| e.to_string_lossy().into_owned()));
    let problem = match extension {
        Some(extension) => format!("unsupported file extension '.{extension}' for {what}"),
        None => format!("no file extension to tell the format of {what}"),
    };
    let supported: Vec<String> = choices
        .iter()
        .map(|choice| format!(".{}", choice.file_format().extension()))
        .collect();
    Error::File {
        path: path.to_path_buf(),
        message: format!("{problem}; supported extensions: {}", supported.join(", ")),
    }
}

/// The one of `choices` whose extension the lowercase file name `name` ends in,
/// the longest extension of those that do.
fn longest_match<T: FormatChoice>(name: &str, choices: impl IntoIterator<Item = T>) -> Option<T> {
    choices
        .into_iter()
        .filter(|choice| choice.file_format().names(name))
        .max_by_key(|choice| choice.file_format().extension().len())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn double_extensions_win_and_case_does_not_matter() {
        let all = &FileFormat::ALL;
        let format = |name: &str| choose_format(Path::new(name), "a test", all).ok();
        assert_eq!(format("a/b.MRK.Json"), Some(FileFormat::SlicerMarkups));
        assert_eq!(format("b.json"), Some(FileFormat::Json));
        assert_eq!(format("brain.NII.GZ"), Some(FileFormat::NiftiGz));
        assert_eq!(format("brain.nii"), Some(FileFormat::Nifti));
        assert_eq!(format(".ply"), None);
        assert_eq!(format("x.gz"), None);
        let json_only = [FileFormat::Json];
        let chosen = choose_format(Path::new("x.mrk.json"), "a test", &json_only);
        assert_eq!(chosen.ok(), Some(FileFormat::Json));
    }

    #[test]
    fn the_error_names_the_file_its_extension_and_the_choices() {
        let choices = [FileFormat::Ply, FileFormat::Obj];
        let message = |name: &str| {
            choose_format(Path::new(name), "a surface", &choices)
                .unwrap_err()
                .to_string()
        };
        assert_eq!(
            message("d/brain.nii.gz"),
            "d/brain.nii.gz: unsupported file extension '.nii.gz' for a surface; \
             supported extensions: .ply, .obj"
        );
        assert_eq!(
            message("s.Txt"),
            "s.Txt: unsupported file extension '.Txt' for a surface; \
             supported extensions: .ply, .obj"
        );
        assert_eq!(
            message("surface"),
            "surface: no file extension to tell the format of a surface; \
             supported extensions: .ply, .obj"
        );
    }
}

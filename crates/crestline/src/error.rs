//! The one error type of the crate. Every fallible call returns [`Result`].

use std::path::{Path, PathBuf};

/// Everything that can go wrong in crestline, each variant naming what is wrong
/// (and, once known, which file).
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// A problem tied to a file: it could not be read or written, or its content is
    /// malformed. The message names the line or element where that is known.
    #[error("{}: {message}", path.display())]
    File {
        /// The file.
        path: PathBuf,
        /// What is wrong with it.
        message: String,
    },
    /// Malformed content read from a stream with no file name (yet). Readers return
    /// this and [`crate::io::read_mesh`] turns it into [`Error::File`].
    #[error("{0}")]
    Parse(String),
    /// The mesh cannot be used: no faces, a NaN coordinate, a non-orientable component.
    #[error("{0}")]
    Mesh(String),
    /// A parameter outside its meaningful range.
    #[error("invalid argument: {0}")]
    Argument(String),
}

impl Error {
    /// Attach a file name to an error that does not name one yet.
    pub fn in_file(self, path: &Path) -> Error {
        match self {
            Error::Parse(message) | Error::Mesh(message) => Error::File {
                path: path.to_path_buf(),
                message,
            },
            other => other,
        }
    }

    /// `name` is not one of the `known` names of a `what` (an estimator, a line
    /// kind, ...).
    pub fn unknown_name(what: &str, name: &str, known: &[&str]) -> Error {
        Error::Argument(format!(
            "unknown {what} '{name}'; expected one of: {}",
            known.join(", ")
        ))
    }

    /// An I/O failure on `path`.
    pub fn io(path: &Path, err: std::io::Error) -> Error {
        Error::File {
            path: path.to_path_buf(),
            message: err.to_string(),
        }
    }
}

/// Shorthand for results of this crate.
pub type Result<T> = std::result::Result<T, Error>;

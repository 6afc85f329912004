//! The one error type of the crate. Every fallible call returns [`Result`].
//!
//! Messages are shown on one line: control characters in them (which can come from
//! a malformed input file quoted in a message) are written as escapes such as `\x07`
//! when an [`Error`] is displayed. An option a message names is written between
//! backticks as its options struct spells it (`` `taper` ``), for each caller to
//! show in its own spelling, as warnings do ([`crate::progress::Observer::warning`]).

use std::borrow::Cow;
use std::path::{Path, PathBuf};

/// Everything that can go wrong in crestline, each variant naming what is wrong
/// (and, once known, which file).
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// A problem tied to a file: it could not be read or written, or its content is
    /// malformed. The message names the line or element where that is known.
    #[error("{}: {}", escape_control(&path.display().to_string()), escape_control(message))]
    File {
        /// The file.
        path: PathBuf,
        /// What is wrong with it.
        message: String,
    },
    /// Malformed content read from a stream with no file name (yet). Readers return
    /// this and [`crate::io::read_mesh`] turns it into [`Error::File`].
    #[error("{}", escape_control(.0))]
    Parse(String),
    /// The mesh cannot be used: no faces, a NaN coordinate, a non-orientable component.
    #[error("{}", escape_control(.0))]
    Mesh(String),
    /// A parameter outside its meaningful range.
    #[error("invalid argument: {}", escape_control(.0))]
    Argument(String),
    /// A stage of a computation failed on this input (e.g. a linear system that is
    /// not positive definite during smoothing); see [`Error::in_stage`].
    #[error("{} failed: {}", escape_control(stage), escape_control(message))]
    Stage {
        /// The stage, named as in the progress reports (e.g. `"smoothing"`).
        stage: String,
        /// What went wrong.
        message: String,
    },
    /// The computation was stopped because its [`crate::progress::Observer`] asked
    /// for it (Ctrl-C, a progress callback that raised).
    #[error("cancelled")]
    Cancelled,
}

impl Error {
    /// Attach a file name to an error that does not name one yet (a failed stage
    /// keeps its name in the message).
    pub fn in_file(self, path: &Path) -> Error {
        match self {
            Error::Parse(message) | Error::Mesh(message) => Error::File {
                path: path.to_path_buf(),
                message,
            },
            Error::Stage { stage, message } => Error::File {
                path: path.to_path_buf(),
                message: format!("{stage} failed: {message}"),
            },
            other => other,
        }
    }

    /// Say that this error arose in stage `stage` of a computation. Errors that name
    /// a file or a stage already are returned unchanged.
    pub fn in_stage(self, stage: &str) -> Error {
        match self {
            Error::Parse(message) | Error::Mesh(message) | Error::Argument(message) => {
                Error::Stage {
                    stage: stage.to_string(),
                    message,
                }
            }
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

    /// An I/O failure on `path` (`io_message`).
    pub fn io(path: &Path, err: std::io::Error) -> Error {
        Error::File {
            path: path.to_path_buf(),
            message: io_message(&err),
        }
    }
}

/// The message of an I/O error, without the name of the temporary file it arose
/// on ("... at path \"/out/.crestline-XXXX\"", as `tempfile` says): the user asked
/// for the final file, which the caller names.
pub(crate) fn io_message(err: &std::io::Error) -> String {
    let message = err.to_string();
    match message.find(" at path \"") {
        Some(at) => message[..at].to_string(),
        None => message,
    }
}

/// `text` with every control character (line breaks, tabs, NUL, bell, escape, ...)
/// written as `\xNN`, so that a message quoting bytes of a malformed file stays on
/// one line and cannot drive a terminal.
pub(crate) fn escape_control(text: &str) -> Cow<'_, str> {
    if !text.chars().any(char::is_control) {
        return Cow::Borrowed(text);
    }
    let mut escaped = String::with_capacity(text.len() + 8);
    for c in text.chars() {
        if c.is_control() {
            escaped.push_str(&format!("\\x{:02x}", u32::from(c)));
        } else {
            escaped.push(c);
        }
    }
    Cow::Owned(escaped)
}

/// Shorthand for results of this crate.
pub type Result<T> = std::result::Result<T, Error>;

/// `x` to 7 significant digits for a message, in scientific notation when it is
/// very large or small (`1e38`, not 39 digits; `8.379870e-16`, not 0.000…).
pub(crate) fn readable(x: f64) -> String {
    let rounded: f64 = format!("{x:.6e}").parse().unwrap_or(x);
    if rounded == 0.0 || (1e-3..1e7).contains(&rounded.abs()) {
        rounded.to_string()
    } else {
        format!("{rounded:e}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn control_characters_are_escaped_when_displayed() {
        let err = Error::Parse("cannot read 'a\u{7}b\nc' as a number".to_string());
        assert_eq!(err.to_string(), r"cannot read 'a\x07b\x0ac' as a number");
        let err = Error::Parse("plain words".to_string()).in_file(Path::new("m\u{1b}.ply"));
        assert_eq!(err.to_string(), r"m\x1b.ply: plain words");
    }

    #[test]
    fn a_failed_stage_is_named_and_then_the_file() {
        let err = Error::Argument("not positive definite".to_string()).in_stage("smoothing");
        assert_eq!(err.to_string(), "smoothing failed: not positive definite");
        let err = err.in_stage("another").in_file(Path::new("m.obj"));
        assert_eq!(
            err.to_string(),
            "m.obj: smoothing failed: not positive definite"
        );
    }
}

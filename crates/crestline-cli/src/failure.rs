//! Errors of the library's computation stages in the user's terms: which stage
//! failed on which file, and which option to try instead.

use std::path::Path;

use crestline::Error;

/// `err` naming the input file `path`. A failed stage ([`Error::Stage`]) is given
/// a plain name and, where one helps, the options to try.
pub fn explain(err: Error, path: &Path) -> Error {
    match err {
        Error::Stage { stage, message } => {
            let (what, hint) = describe(&stage);
            let hint = hint.map(|h| format!("; try {h}")).unwrap_or_default();
            Error::File {
                path: path.to_path_buf(),
                message: format!("{what} failed: {message}{hint}"),
            }
        }
        other => other.in_file(path),
    }
}

/// `err`, an error of a computation on a mesh, also naming the per-vertex values
/// file an option gave (`values`: the option and the file), when there is one: the
/// values may be what the computation failed on (a weight of 10³⁸ makes the
/// smoothing's matrix singular).
pub fn with_values(err: Error, values: Option<(&str, &Path)>) -> Error {
    match (err, values) {
        (Error::File { path, message }, Some((option, file))) if path != file => Error::File {
            path,
            message: format!("{message} (with the {option} values of {})", file.display()),
        },
        (err, _) => err,
    }
}

/// A plain name for a library stage (`"smoothing"`, `"ridges: tracing"`, ...)
/// and what to try when it fails.
fn describe(stage: &str) -> (&str, Option<&'static str>) {
    // Per-field stages are named "ridges: <step>" and "valleys: <step>".
    let step = stage.rsplit(": ").next().unwrap_or(stage);
    match step {
        "presmooth" => (
            "surface pre-smoothing",
            Some("a smaller --presmooth, or --presmooth 0"),
        ),
        "curvature" => (
            "curvature estimation",
            Some("the other --estimator (of an image's surface: --curvature mesh)"),
        ),
        "smoothing" | "smoothing analysis" => (
            "extremality smoothing",
            Some("--presmooth 0 or a smaller --smooth-time (--smooth-steps 0 skips it)"),
        ),
        "indicator" => (
            "indicator computation",
            Some("another --indicator or --estimator"),
        ),
        _ => (stage, None),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_failed_stage_names_the_file_the_stage_and_what_to_try() {
        let err = Error::Argument("the 12×12 matrix is not positive definite".into())
            .in_stage("smoothing");
        assert_eq!(
            explain(err, Path::new("mesh.obj")).to_string(),
            "mesh.obj: extremality smoothing failed: the 12×12 matrix is not positive \
             definite; try --presmooth 0 or a smaller --smooth-time (--smooth-steps 0 skips it)"
        );
        let err = Error::Mesh("no faces".into()).in_stage("gradient");
        assert_eq!(
            explain(err, Path::new("m.ply")).to_string(),
            "m.ply: gradient failed: no faces"
        );
    }

    #[test]
    fn a_values_file_is_named_with_the_mesh() {
        let err = Error::Mesh("the values range over too much".into());
        let err = with_values(
            explain(err, Path::new("m.ply")),
            Some(("--indicator", Path::new("v.curv"))),
        );
        assert_eq!(
            err.to_string(),
            "m.ply: the values range over too much (with the --indicator values of v.curv)"
        );
    }

    #[test]
    fn other_errors_only_gain_the_file() {
        let err = Error::Mesh("no faces".into());
        assert_eq!(
            explain(err, Path::new("m.ply")).to_string(),
            "m.ply: no faces"
        );
        let err = Error::Argument("at most 1000 smoothing steps".into());
        assert_eq!(
            explain(err, Path::new("m.ply")).to_string(),
            "invalid argument: at most 1000 smoothing steps"
        );
    }
}

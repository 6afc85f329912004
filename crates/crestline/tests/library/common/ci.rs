//! What continuous integration changes in the tests, shared by the library's and
//! the tool's test crates (the tool's includes this file by path).

/// Skips the calling test for `reason` (data or a tool it needs is absent), or,
/// in continuous integration (`CI=true`, where `.ci/run` provides every such
/// input), fails it: a green run then means every cross-check ran.
#[allow(dead_code)]
pub fn skip(reason: &str) {
    if std::env::var("CI").is_ok_and(|ci| ci == "true") {
        panic!("{reason}; in CI every test's data and tools must be present");
    }
    eprintln!("skipped: {reason}");
}

/// The Python interpreter of the cross-checks: `CRESTLINE_PYTHON` (`.ci/run`
/// points it at its virtual environment, which holds tools/requirements.txt), or
/// `python3`.
#[allow(dead_code)]
pub fn python() -> std::process::Command {
    std::process::Command::new(
        std::env::var("CRESTLINE_PYTHON").unwrap_or_else(|_| "python3".into()),
    )
}

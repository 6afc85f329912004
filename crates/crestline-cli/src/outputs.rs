//! The files a run writes. Their paths are checked before any work (none may
//! replace an input or another output, and each directory must exist and be
//! writable); each file is then written under a temporary name next to its place,
//! and all of them are renamed into place together once every one is written.

use std::path::{Path, PathBuf};

use crestline::io::{choose_format, volume_files, FileFormat};
use crestline::{Error, Result};
use tempfile::TempPath;

/// A file of a run and what it is to the user, e.g. `("-o", "lines.json")` or
/// `("the input mesh", "bunny.obj")`.
pub type Role<'a> = (&'a str, &'a Path);

/// Refuse `outputs` that would replace one of `inputs` or each other, that name a
/// directory, or whose directory is missing or not writable. Paths are compared
/// after resolving `.`, `..` and symbolic links (an output that does not exist yet
/// by its directory), so `./x.obj`, `x.obj` and a link to it are the same file.
/// Inputs that do not exist are not compared (reading them fails anyway).
/// An image's detached data file (of a NRRD or MetaImage header) counts as an
/// input too.
pub fn check_paths(inputs: &[Role<'_>], outputs: &[Role<'_>]) -> Result<()> {
    let files: Vec<(String, PathBuf)> = inputs
        .iter()
        .flat_map(|&(role, path)| {
            let data_files = volume_files(path).into_iter().skip(1);
            std::iter::once((role.to_string(), path.to_path_buf()))
                .chain(data_files.map(move |data| (format!("the data file of {role}"), data)))
        })
        .collect();
    let inputs: Vec<(&str, &Path, PathBuf)> = files
        .iter()
        .filter_map(|(role, path)| {
            Some((
                role.as_str(),
                path.as_path(),
                std::fs::canonicalize(path).ok()?,
            ))
        })
        .collect();
    let mut checked: Vec<(&str, PathBuf)> = Vec::new();
    for &(role, path) in outputs {
        let resolved = resolve_output(role, path)?;
        if let Some((input, input_path, _)) = inputs.iter().find(|i| i.2 == resolved) {
            return Err(Error::File {
                path: path.to_path_buf(),
                message: format!(
                    "{role} would replace {input} {}; choose another file",
                    input_path.display()
                ),
            });
        }
        if let Some((other, _)) = checked.iter().find(|c| c.1 == resolved) {
            return Err(Error::File {
                path: path.to_path_buf(),
                message: format!("given for both {other} and {role}; choose different files"),
            });
        }
        check_writable(role, path)?;
        checked.push((role, resolved));
    }
    Ok(())
}

/// The directory `path` is written in (`.` for a bare file name).
fn directory_of(path: &Path) -> &Path {
    match path.parent() {
        Some(dir) if !dir.as_os_str().is_empty() => dir,
        _ => Path::new("."),
    }
}

/// The absolute path an output will have, symbolic links resolved: the file itself
/// if it exists, else its resolved directory joined with its name.
fn resolve_output(role: &str, path: &Path) -> Result<PathBuf> {
    let fail = |message: String| Error::File {
        path: path.to_path_buf(),
        message,
    };
    if path.is_dir() {
        return Err(fail(format!("{role} names a directory, not a file")));
    }
    if let Ok(resolved) = std::fs::canonicalize(path) {
        return Ok(resolved);
    }
    let dir = directory_of(path);
    let name = path
        .file_name()
        .ok_or_else(|| fail(format!("{role} does not name a file")))?;
    if !dir.is_dir() {
        let what = if dir.exists() {
            "is not a directory"
        } else {
            "does not exist"
        };
        return Err(fail(format!(
            "cannot write {role} here: directory '{}' {what}",
            dir.display()
        )));
    }
    let dir = std::fs::canonicalize(dir).map_err(|e| Error::io(path, e))?;
    Ok(dir.join(name))
}

/// A file can be created in the directory of `path` (a probe created and removed).
fn check_writable(role: &str, path: &Path) -> Result<()> {
    let dir = directory_of(path);
    temporary_in(dir, "").map(drop).map_err(|e| Error::File {
        path: path.to_path_buf(),
        message: format!(
            "cannot write {role} in directory '{}': {}",
            dir.display(),
            io_message(&e)
        ),
    })
}

/// The message of an I/O error without the name of the probe it arose on ("... at
/// path \"/out/.crestline-XXXX\"", as `tempfile` says): the user named the
/// directory, which the caller names.
fn io_message(err: &std::io::Error) -> String {
    let message = err.to_string();
    match message.find(" at path \"") {
        Some(at) => message[..at].to_string(),
        None => message,
    }
}

/// The extension of the format `path` names, with its dot (`.mrk.json`,
/// `.nii.gz`, `.ply`), so that a temporary file stands for `path` to the writers
/// that choose the format by the file name; empty for a name of no known format.
fn suffix(path: &Path) -> String {
    choose_format(path, "an output", &FileFormat::ALL)
        .map_or(String::new(), |format| format!(".{}", format.extension()))
}

/// A new empty file with a hidden name in `dir` ending in `suffix`.
fn temporary_in(dir: &Path, suffix: &str) -> std::io::Result<TempPath> {
    tempfile::Builder::new()
        .prefix(".crestline-")
        .suffix(suffix)
        .tempfile_in(dir)
        .map(tempfile::NamedTempFile::into_temp_path)
}

/// Files written under temporary names, each next to its final place, renamed
/// into place by [`OutputSet::commit`]. Dropped without a commit (a later step
/// failed), it removes them, so a failed run leaves none of its outputs.
#[derive(Default)]
pub struct OutputSet {
    staged: Vec<(PathBuf, TempPath)>,
}

impl OutputSet {
    /// Write the output `path` by calling `write` with a temporary path in the
    /// same directory and with the same suffix (writers that choose the format by
    /// the file name still do, `.mrk.json` included). Errors name `path`, not the
    /// temporary file.
    pub fn write(&mut self, path: &Path, write: impl FnOnce(&Path) -> Result<()>) -> Result<()> {
        let temporary =
            temporary_in(directory_of(path), &suffix(path)).map_err(|e| Error::io(path, e))?;
        write(&temporary).map_err(|e| name_output(e, &temporary, path))?;
        self.staged.push((path.to_path_buf(), temporary));
        Ok(())
    }

    /// Rename every written file into place. The renames stay within each file's
    /// directory, so they only fail if the directory changed during the run; the
    /// files not yet renamed are then removed.
    pub fn commit(self) -> Result<()> {
        if crate::signals::received().is_some() {
            // Dropped, the temporary files are removed: nothing lands.
            return Err(Error::Cancelled);
        }
        for (path, temporary) in self.staged {
            temporary
                .persist(&path)
                .map_err(|e| Error::io(&path, e.error))?;
        }
        Ok(())
    }
}

/// `err` with the temporary file's name replaced by the output's.
fn name_output(err: Error, temporary: &Path, path: &Path) -> Error {
    match err {
        Error::File { path: p, message } if p == temporary => Error::File {
            path: path.to_path_buf(),
            message,
        },
        other => other,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nothing_is_left_unless_committed() {
        let dir = tempfile::tempdir().unwrap();
        let (a, b) = (dir.path().join("a.json"), dir.path().join("b.txt"));
        let mut set = OutputSet::default();
        set.write(&a, |p| {
            assert_eq!(p.extension().unwrap(), "json");
            std::fs::write(p, "a").map_err(|e| Error::io(p, e))
        })
        .unwrap();
        let failed = set.write(&b, |p| {
            Err(Error::io(p, std::io::Error::other("disk full")))
        });
        assert_eq!(
            failed.unwrap_err().to_string(),
            format!("{}: disk full", b.display())
        );
        drop(set);
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);

        let mut set = OutputSet::default();
        set.write(&a, |p| std::fs::write(p, "a").map_err(|e| Error::io(p, e)))
            .unwrap();
        set.commit().unwrap();
        assert_eq!(std::fs::read_to_string(&a).unwrap(), "a");
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
    }

    #[test]
    fn the_same_file_by_another_name_is_refused() {
        let dir = tempfile::tempdir().unwrap();
        let input = dir.path().join("in.obj");
        std::fs::write(&input, "v 0 0 0\n").unwrap();
        let dotted = dir.path().join(".").join("in.obj");
        let roles = |out: &Path| check_paths(&[("the input mesh", &input)], &[("-o", out)]);
        assert!(roles(&dotted).is_err());
        #[cfg(unix)]
        {
            let link = dir.path().join("link.obj");
            std::os::unix::fs::symlink(&input, &link).unwrap();
            assert!(roles(&link).is_err());
        }
        assert!(roles(&dir.path().join("out.obj")).is_ok());
    }
}

//! Opening input files and reserving memory for what they declare, shared by every
//! reader and format sniffer of the crate.
//!
//! A path is checked to name a regular file before it is opened: opening a FIFO
//! blocks until someone writes to it, and a device (`/dev/zero`) never ends.
//! [`std::fs::metadata`] does not open the path, so the check cannot block. Buffers
//! whose size a file declares are reserved fallibly ([`reserve`]): a header asking
//! for more than can be allocated (under a memory or address-space limit too) is
//! an error saying how much, never an abort.

use std::fs::{File, Metadata};
use std::io::Read;
use std::path::Path;

use crate::{Error, Result};

/// The metadata of `path` once it is known to name a regular file; an error naming
/// the file for a missing path, a folder, a device, a pipe or a socket.
pub(crate) fn regular_file(path: &Path) -> Result<Metadata> {
    let file_error = |message: &str| Error::File {
        path: path.to_path_buf(),
        message: message.to_string(),
    };
    match std::fs::metadata(path) {
        Ok(meta) if meta.is_file() => Ok(meta),
        Ok(meta) if meta.is_dir() => Err(file_error("is a directory, not a file")),
        // A device (/dev/zero), a pipe or a socket never ends, or ends when someone
        // else decides, and opening a pipe waits for a writer.
        Ok(_) => Err(file_error(
            "is not a regular file (a device, pipe or socket); only files are read",
        )),
        Err(e) => Err(open_error(path, e)),
    }
}

/// The regular file at `path`, opened for reading ([`regular_file`]).
pub(crate) fn open(path: &Path) -> Result<File> {
    regular_file(path)?;
    File::open(path).map_err(|e| open_error(path, e))
}

/// The first `count` bytes of the regular file at `path` (fewer in a shorter file).
pub(crate) fn head(path: &Path, count: u64) -> Result<Vec<u8>> {
    let mut head = Vec::new();
    open(path)?
        .take(count)
        .read_to_end(&mut head)
        .map_err(|e| Error::io(path, e))?;
    Ok(head)
}

/// The bytes of the regular file at `path`, their buffer reserved fallibly.
pub(crate) fn read(path: &Path) -> Result<Vec<u8>> {
    let size = regular_file(path)?.len();
    let mut bytes = reserve::<u8>(usize::try_from(size).unwrap_or(usize::MAX), "bytes")
        .map_err(|e| e.in_file(path))?;
    File::open(path)
        .and_then(|mut file| file.read_to_end(&mut bytes))
        .map_err(|e| open_error(path, e))?;
    Ok(bytes)
}

/// The text of the regular file at `path` (UTF-8).
pub(crate) fn read_text(path: &Path) -> Result<String> {
    String::from_utf8(read(path)?).map_err(|_| Error::File {
        path: path.to_path_buf(),
        message: "is not text (UTF-8)".to_string(),
    })
}

/// The error for a file that cannot be opened or read: "no such file" when it is
/// missing.
pub(crate) fn open_error(path: &Path, err: std::io::Error) -> Error {
    match err.kind() {
        std::io::ErrorKind::NotFound => Error::File {
            path: path.to_path_buf(),
            message: "no such file".to_string(),
        },
        _ => Error::io(path, err),
    }
}

/// An empty vector with room for `count` values of `T`, reserved fallibly: a file
/// declaring more than can be allocated is an error ([`Error::Parse`], for the
/// caller to name the file) saying how much memory the `count` `what` need.
pub(crate) fn reserve<T>(count: usize, what: &str) -> Result<Vec<T>> {
    let mut values = Vec::new();
    values
        .try_reserve_exact(count)
        .map_err(|_| out_of_memory(count, std::mem::size_of::<T>(), what))?;
    Ok(values)
}

/// Room for `additional` more values in `values` (growing as a vector does),
/// reserved fallibly as [`reserve`] does: for data whose size is known only once
/// it has been read, such as a decompressed stream.
pub(crate) fn grow<T>(values: &mut Vec<T>, additional: usize, what: &str) -> Result<()> {
    values.try_reserve(additional).map_err(|_| {
        let count = values.len().saturating_add(additional);
        out_of_memory(count, std::mem::size_of::<T>(), what)
    })
}

/// The error for `count` values of `size` bytes that do not fit in the memory this
/// process may allocate.
fn out_of_memory(count: usize, size: usize, what: &str) -> Error {
    let bytes = count as f64 * size as f64;
    Error::Parse(format!(
        "its {count} {what} need {:.1} GiB of memory, more than can be allocated",
        bytes / (1u64 << 30) as f64
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_regular_files_are_opened() {
        let dir = tempfile::tempdir().unwrap();
        let err = open(dir.path()).unwrap_err().to_string();
        assert!(err.contains("is a directory"), "{err}");
        let err = read(&dir.path().join("none")).unwrap_err().to_string();
        assert!(err.ends_with("none: no such file"), "{err}");
        let err = head(Path::new("/dev/zero"), 3).unwrap_err().to_string();
        assert!(err.contains("not a regular file"), "{err}");
        let file = dir.path().join("f");
        std::fs::write(&file, "abcd").unwrap();
        assert_eq!(head(&file, 3).unwrap(), b"abc");
        assert_eq!(read_text(&file).unwrap(), "abcd");
    }

    #[test]
    fn a_reservation_beyond_memory_is_an_error() {
        let err = reserve::<f64>(usize::MAX / 16, "numbers")
            .unwrap_err()
            .to_string();
        assert!(err.contains("numbers need"), "{err}");
        assert!(err.contains("more than can be allocated"), "{err}");
        let mut bytes = vec![0u8; 4];
        grow(&mut bytes, 12, "bytes").unwrap();
        assert!(bytes.capacity() >= 16);
        assert!(grow(&mut bytes, usize::MAX / 2, "bytes").is_err());
    }
}

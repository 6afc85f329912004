//! Grouping image files by series (PS3.3 C.7.3.1 General Series Module): the
//! frames of one volume share a Series Instance UID (0020,000E).

use std::collections::BTreeMap;

use super::header::Header;
use crate::{Error, Result};

/// The images of the one series in `headers`, or of the series whose UID is
/// `chosen`. Errors (to be put in the name of the input) list the series, with
/// their number of files, when there are several and none is chosen, or when
/// the chosen one is not there.
pub(super) fn choose(headers: Vec<Header>, chosen: Option<&str>) -> Result<Vec<Header>> {
    let mut series: BTreeMap<String, Vec<Header>> = BTreeMap::new();
    for header in headers {
        series
            .entry(header.series.clone())
            .or_default()
            .push(header);
    }
    let listing = |series: &BTreeMap<String, Vec<Header>>| {
        series
            .iter()
            .map(|(uid, files)| {
                let plural = if files.len() == 1 { "" } else { "s" };
                format!("{} ({} file{plural})", shown(uid), files.len())
            })
            .collect::<Vec<_>>()
            .join(", ")
    };
    match chosen {
        Some(uid) => match series.remove(uid.trim()) {
            Some(files) => Ok(files),
            None => Err(Error::Parse(format!(
                "holds no series {uid}; its series: {}",
                listing(&series)
            ))),
        },
        None if series.len() == 1 => Ok(series.into_values().next().unwrap_or_default()),
        None => Err(Error::Parse(format!(
            "holds {} series; choose one by its Series Instance UID (the option `series`): {}",
            series.len(),
            listing(&series)
        ))),
    }
}

/// A series UID as listed: `(none)` for files without one.
fn shown(uid: &str) -> &str {
    if uid.is_empty() {
        "(none)"
    } else {
        uid
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn header(file: &str, series: &str) -> Header {
        Header {
            path: file.into(),
            series: series.to_string(),
            frames: Vec::new(),
        }
    }

    #[test]
    fn several_series_are_listed_unless_one_is_chosen() {
        let headers = vec![header("a", "1.2"), header("b", "1.3"), header("c", "1.2")];
        let err = choose(headers.clone(), None).unwrap_err().to_string();
        assert!(err.contains("holds 2 series"), "{err}");
        assert!(err.contains("1.2 (2 files), 1.3 (1 file)"), "{err}");
        let chosen = choose(headers.clone(), Some("1.2")).unwrap();
        assert_eq!(chosen.len(), 2);
        let err = choose(headers, Some("9.9")).unwrap_err().to_string();
        assert!(err.contains("no series 9.9"), "{err}");
    }
}

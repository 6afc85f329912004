//! The last two stages of the pipeline as one-method traits: filters that keep or
//! drop lines, and exporters that save them. With [`super::LineExtractor`] and
//! [`crate::curvature::CurvatureEstimator`] every stage can be replaced.

use std::path::Path;

use crate::Result;

use super::{FeatureLines, LineFormat, Polyline};

/// Decides which lines to keep.
pub trait LineFilter {
    /// Whether to keep `line`.
    fn keep(&self, line: &Polyline) -> bool;
}

impl FeatureLines {
    /// Keep only the lines `filter` accepts, in order.
    pub fn filter(&mut self, filter: &dyn LineFilter) {
        self.lines.retain(|line| filter.keep(line));
    }
}

/// Keeps lines at least this long (in the units of the mesh).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MinLength(pub f64);

impl LineFilter for MinLength {
    fn keep(&self, line: &Polyline) -> bool {
        line.length() >= self.0
    }
}

/// Keeps lines of at least this strength.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MinStrength(pub f64);

impl LineFilter for MinStrength {
    fn keep(&self, line: &Polyline) -> bool {
        line.strength >= self.0
    }
}

/// Saves lines to a file.
pub trait LineExporter {
    /// Write `lines` to `path`; a failed write leaves no file behind.
    fn export(&self, path: &Path, lines: &FeatureLines) -> Result<()>;
}

impl LineExporter for LineFormat {
    fn export(&self, path: &Path, lines: &FeatureLines) -> Result<()> {
        self.write(path, lines)
    }
}

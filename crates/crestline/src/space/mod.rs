//! World frames of medical images and of everything derived from them.
//!
//! An image's world coordinates are anatomical: NIfTI's are RAS (x to the right,
//! y to the front, z up), DICOM's, ITK's and 3D Slicer's files are LPS (x to the
//! left, y to the back, z up); the two differ by the sign of x and y. A point
//! means nothing without its frame, and a tool that guesses guesses LPS (3D
//! Slicer reads a model without a mark as LPS): so every result crestline derives
//! from an image carries the image's [`Space`] and every writer records it where
//! its format can (see `docs/design/formats.md`, "World frames").
//!
//! Slicer's mark, read in its model storage node
//! (`vtkMRMLModelStorageNode::GetCoordinateSystemFromFileHeader`), is the text
//! `SPACE=RAS` or `SPACE=LPS` anywhere in the legacy VTK header line, in a PLY
//! comment, in the OBJ comment or in the STL header; [`Space::slicer_mark`] writes
//! it and [`Space::from_header`] reads it.
//!
//! FreeSurfer surfaces hold tkr-RAS coordinates, placed in the scanner's RAS by
//! the `VolumeGeometry` of their image.

mod volume_geometry;

pub(crate) use volume_geometry::to_tkr;
pub(crate) use volume_geometry::VolumeGeometry;

use std::fmt;
use std::str::FromStr;

use serde::{Deserialize, Serialize};

use crate::{Error, Point, Result, Vector};

/// The anatomical world frame of positions.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum Space {
    /// x to the right, y to the front (anterior), z up: the NIfTI world.
    #[serde(rename = "RAS")]
    Ras,
    /// x to the left, y to the back (posterior), z up: DICOM, ITK, MetaImage and
    /// 3D Slicer's files.
    #[serde(rename = "LPS")]
    Lps,
}

/// The length unit of coordinates in an anatomical frame: millimetres, as DICOM,
/// ITK and NIfTI's usual `xyzt_units` have them (other NIfTI units are not
/// converted).
pub(crate) const UNITS: &str = "mm";

impl Space {
    /// The unit of the coordinates of points in `space`: `UNITS` in an
    /// anatomical frame, none without one.
    pub fn units_of(space: Option<Space>) -> Option<&'static str> {
        space.map(|_| UNITS)
    }

    /// Every name, in the order of the variants.
    pub const NAMES: &'static [&'static str] = &["RAS", "LPS"];

    /// The frame's name, `RAS` or `LPS`.
    pub fn name(self) -> &'static str {
        match self {
            Space::Ras => "RAS",
            Space::Lps => "LPS",
        }
    }

    /// The position `p` of this frame in `to`: x and y change sign between RAS
    /// and LPS.
    pub fn convert(self, p: &Point, to: Space) -> Point {
        Point::from(self.convert_vector(&p.coords, to))
    }

    /// The vector `v` (a direction or a normal) of this frame in `to`: the frames
    /// differ by a half turn about z, which keeps orientations.
    pub fn convert_vector(self, v: &Vector, to: Space) -> Vector {
        if self == to {
            *v
        } else {
            Vector::new(-v.x, -v.y, v.z)
        }
    }

    /// The position `p` of this frame in LPS.
    pub fn to_lps(self, p: &Point) -> Point {
        self.convert(p, Space::Lps)
    }

    /// The position `p` of this frame in RAS.
    pub fn to_ras(self, p: &Point) -> Point {
        self.convert(p, Space::Ras)
    }

    /// 3D Slicer's mark of the frame in a model file's header or comment:
    /// `SPACE=RAS` or `SPACE=LPS`.
    pub fn slicer_mark(self) -> String {
        format!("SPACE={}", self.name())
    }

    /// The frame a header or comment line marks, by 3D Slicer's rule: the text
    /// `SPACE=RAS` or `SPACE=LPS` anywhere in it.
    pub fn from_header(text: &str) -> Option<Space> {
        if text.contains("SPACE=RAS") {
            Some(Space::Ras)
        } else if text.contains("SPACE=LPS") {
            Some(Space::Lps)
        } else {
            None
        }
    }
}

/// Convert `points`, in frame `from`, into `to`; points without a frame are
/// taken to be in `to` already.
pub(crate) fn convert_all<'a>(
    from: Option<Space>,
    to: Space,
    points: impl IntoIterator<Item = &'a mut Point>,
) {
    if let Some(from) = from {
        for p in points {
            *p = from.convert(p, to);
        }
    }
}

/// [`Space::resolve`].
pub(crate) fn resolve(declared: Option<Space>, given: Option<Space>) -> Result<Option<Space>> {
    match (declared, given) {
        (Some(declared), Some(given)) if declared != given => Err(Error::Argument(format!(
            "the input declares its points in {declared}; `space` {given} contradicts it"
        ))),
        (Some(space), _) | (None, Some(space)) => Ok(Some(space)),
        (None, None) => Ok(None),
    }
}

impl fmt::Display for Space {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Space {
    type Err = Error;

    /// `RAS` or `LPS`, in any letter case.
    fn from_str(name: &str) -> Result<Space> {
        match name.to_ascii_uppercase().as_str() {
            "RAS" => Ok(Space::Ras),
            "LPS" => Ok(Space::Lps),
            _ => Err(Error::unknown_name("world frame", name, Space::NAMES)),
        }
    }
}

impl Space {
    /// The frame of an input's points: the one it declares, else the one the user
    /// gives (`given`, the option `space`). A given frame that contradicts the
    /// declared one is an [`Error::Argument`]; `None` when neither says.
    pub fn resolve(declared: Option<Space>, given: Option<Space>) -> Result<Option<Space>> {
        resolve(declared, given)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn converting_flips_x_and_y_and_round_trips() {
        let p = Point::new(1.0, -2.0, 3.0);
        assert_eq!(Space::Ras.to_lps(&p), Point::new(-1.0, 2.0, 3.0));
        assert_eq!(Space::Lps.to_lps(&p), p);
        for from in [Space::Ras, Space::Lps] {
            for to in [Space::Ras, Space::Lps] {
                assert_eq!(to.convert(&from.convert(&p, to), from), p);
            }
        }
    }

    #[test]
    fn a_declared_frame_wins_and_a_contradiction_is_an_error() {
        assert_eq!(resolve(Some(Space::Lps), None).unwrap(), Some(Space::Lps));
        assert_eq!(
            resolve(Some(Space::Lps), Some(Space::Lps)).unwrap(),
            Some(Space::Lps)
        );
        assert_eq!(resolve(None, Some(Space::Ras)).unwrap(), Some(Space::Ras));
        assert_eq!(resolve(None, None).unwrap(), None);
        let error = resolve(Some(Space::Ras), Some(Space::Lps))
            .unwrap_err()
            .to_string();
        assert!(
            error.contains("RAS") && error.contains("`space` LPS"),
            "{error}"
        );
    }

    #[test]
    fn names_parse_in_any_case_and_marks_read_back() {
        for &name in Space::NAMES {
            let space: Space = name.parse().unwrap();
            assert_eq!(space.name(), name);
            assert_eq!(name.to_lowercase().parse::<Space>().unwrap(), space);
            assert_eq!(
                Space::from_header(&format!("3D Slicer output. {}", space.slicer_mark())),
                Some(space)
            );
        }
        assert!("scanner".parse::<Space>().is_err());
        assert_eq!(Space::from_header("vtk output"), None);
    }
}

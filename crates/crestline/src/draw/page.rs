//! A physical page for pen plotters and print: the paper, its margin and the pen.
//!
//! With a page the drawing is made on the printable area (the paper less the margin
//! on every side) at [`PIXELS_PER_MM`], and the SVG declares the paper's physical
//! size (`width="210mm" height="297mm"`) with a `viewBox` that maps those pixels to
//! millimetres, the printable area offset by the margin. Every line is stroked with
//! the pen's width.

use std::str::FromStr;

use serde::{Deserialize, Serialize};

use crate::{Error, Result};

/// Drawing pixels per millimetre of paper: the resolution of the visibility test
/// and of the paths' simplification on a page (a tenth of a millimetre, finer
/// than any pen).
pub const PIXELS_PER_MM: f64 = 10.0;

/// Millimetres per inch.
const MM_PER_INCH: f64 = 25.4;

/// The named paper sizes, portrait (width, height) in millimetres.
pub const PAPERS: &[(&str, [f64; 2])] = &[
    ("a5", [148.0, 210.0]),
    ("a4", [210.0, 297.0]),
    ("a3", [297.0, 420.0]),
    ("a2", [420.0, 594.0]),
    ("letter", [215.9, 279.4]),
    ("legal", [215.9, 355.6]),
    ("tabloid", [279.4, 431.8]),
];

/// The largest paper side accepted, in millimetres (a 2 m roll).
const MAX_SIDE_MM: f64 = 2000.0;

/// A length on paper: a number with the unit `mm`, `cm` or `in` (a bare number is
/// in millimetres), read as millimetres.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "String", into = "String")]
pub struct PaperLength(pub f64);

impl FromStr for PaperLength {
    type Err = Error;

    fn from_str(text: &str) -> Result<PaperLength> {
        let text = text.trim();
        let (number, scale) = [("mm", 1.0), ("cm", 10.0), ("in", MM_PER_INCH)]
            .iter()
            .find_map(|(unit, scale)| text.strip_suffix(unit).map(|n| (n, *scale)))
            .unwrap_or((text, 1.0));
        number
            .trim()
            .parse::<f64>()
            .ok()
            .map(|n| n * scale)
            .filter(|mm| mm.is_finite() && *mm >= 0.0)
            .map(PaperLength)
            .ok_or_else(|| {
                Error::Argument(format!(
                    "'{text}' is not a length on paper: a number of mm, cm or in, e.g. 0.3mm"
                ))
            })
    }
}

impl TryFrom<String> for PaperLength {
    type Error = Error;
    fn try_from(text: String) -> Result<PaperLength> {
        text.parse()
    }
}

impl std::fmt::Display for PaperLength {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}mm", self.0)
    }
}

impl From<PaperLength> for String {
    fn from(length: PaperLength) -> String {
        length.to_string()
    }
}

/// A paper size: a name of `PAPERS` or `WxH` with a unit (`210x297mm`,
/// `8.5x11in`), portrait or landscape as given.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "String", into = "String")]
pub struct Paper {
    /// Width and height in millimetres.
    pub size_mm: [f64; 2],
}

impl Paper {
    /// The names of the papers, then the `WxH` form, for help and errors.
    pub fn names() -> Vec<&'static str> {
        let mut names: Vec<&str> = PAPERS.iter().map(|(name, _)| *name).collect();
        names.push("WxH{mm,cm,in}");
        names
    }

    /// The same paper turned a quarter (width and height exchanged).
    pub fn turned(self) -> Paper {
        let [w, h] = self.size_mm;
        Paper { size_mm: [h, w] }
    }
}

impl FromStr for Paper {
    type Err = Error;

    fn from_str(text: &str) -> Result<Paper> {
        let lower = text.trim().to_ascii_lowercase();
        if let Some((_, size_mm)) = PAPERS.iter().find(|(name, _)| *name == lower) {
            return Ok(Paper { size_mm: *size_mm });
        }
        let unknown = || {
            Error::Argument(format!(
                "'{text}' is not a paper: {} (e.g. 200x200mm)",
                Paper::names().join(", ")
            ))
        };
        let (width, height) = lower.split_once('x').ok_or_else(unknown)?;
        let unit = ["mm", "cm", "in"]
            .into_iter()
            .find(|u| height.ends_with(u))
            .ok_or_else(unknown)?;
        let side = |n: &str| -> Result<f64> {
            let mm = format!("{}{unit}", n.trim_end_matches(unit)).parse::<PaperLength>()?;
            (mm.0 > 0.0 && mm.0 <= MAX_SIDE_MM)
                .then_some(mm.0)
                .ok_or_else(unknown)
        };
        let width = side(width).map_err(|_| unknown())?;
        let height = side(height).map_err(|_| unknown())?;
        Ok(Paper {
            size_mm: [width, height],
        })
    }
}

impl TryFrom<String> for Paper {
    type Error = Error;
    fn try_from(text: String) -> Result<Paper> {
        text.parse()
    }
}

impl std::fmt::Display for Paper {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let [w, h] = self.size_mm;
        write!(f, "{w}x{h}mm")
    }
}

impl From<Paper> for String {
    fn from(paper: Paper) -> String {
        paper.to_string()
    }
}

/// The page a drawing is laid out on. Read from a paper alone (`"a4"`: the
/// default margin and pen) or from the fields, margin and pen optional.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(from = "PageInput")]
pub struct Page {
    /// The paper, as it lies (already turned for landscape).
    pub paper: Paper,
    /// The blank border on every side.
    pub margin: PaperLength,
    /// The pen's width: the stroke width of every line.
    pub pen: PaperLength,
}

/// What a page is read from: a paper, or the fields of [`Page`].
#[derive(Deserialize)]
#[serde(untagged)]
enum PageInput {
    Paper(Paper),
    Fields(PageFields),
}

/// The fields of [`Page`], margin and pen optional.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct PageFields {
    paper: Paper,
    #[serde(default)]
    landscape: bool,
    margin: Option<PaperLength>,
    pen: Option<PaperLength>,
}

impl From<PageInput> for Page {
    fn from(input: PageInput) -> Page {
        match input {
            PageInput::Paper(paper) => Page::new(paper),
            PageInput::Fields(fields) => {
                let paper = if fields.landscape {
                    fields.paper.turned()
                } else {
                    fields.paper
                };
                let defaults = Page::new(paper);
                Page {
                    margin: fields.margin.unwrap_or(defaults.margin),
                    pen: fields.pen.unwrap_or(defaults.pen),
                    ..defaults
                }
            }
        }
    }
}

impl Page {
    /// The default margin, in millimetres.
    pub const DEFAULT_MARGIN_MM: f64 = 10.0;
    /// The default pen width, in millimetres (a fine felt tip).
    pub const DEFAULT_PEN_MM: f64 = 0.3;

    /// `paper` with the default margin and pen.
    pub fn new(paper: Paper) -> Page {
        Page {
            paper,
            margin: PaperLength(Page::DEFAULT_MARGIN_MM),
            pen: PaperLength(Page::DEFAULT_PEN_MM),
        }
    }

    /// Errors ([`Error::Argument`]) unless the margin leaves a printable area and
    /// the pen has a width that fits in it.
    pub fn check(&self) -> Result<()> {
        let [w, h] = self.printable_mm();
        if !(w > 0.0 && h > 0.0) {
            return Err(Error::Argument(format!(
                "a margin of {} mm leaves nothing of a {} x {} mm paper to draw on",
                self.margin.0, self.paper.size_mm[0], self.paper.size_mm[1]
            )));
        }
        if !(self.pen.0 > 0.0 && self.pen.0 <= w.min(h)) {
            return Err(Error::Argument(format!(
                "the pen must be wider than 0 and fit on the page, not {} mm",
                self.pen.0
            )));
        }
        Ok(())
    }

    /// The width and height of the printable area, in millimetres.
    pub fn printable_mm(&self) -> [f64; 2] {
        self.paper.size_mm.map(|side| side - 2.0 * self.margin.0)
    }

    /// The canvas of the printable area, in drawing pixels (`PIXELS_PER_MM`).
    pub fn canvas(&self) -> [u32; 2] {
        self.printable_mm()
            .map(|mm| (mm * PIXELS_PER_MM).round().max(1.0) as u32)
    }

    /// A length on paper in drawing pixels.
    pub fn pixels(length_mm: f64) -> f64 {
        length_mm * PIXELS_PER_MM
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn papers_and_lengths_read_in_millimetres() {
        let a4: Paper = "A4".parse().unwrap();
        assert_eq!(a4.size_mm, [210.0, 297.0]);
        assert_eq!(a4.turned().size_mm, [297.0, 210.0]);
        let inches: Paper = "8.5x11in".parse().unwrap();
        assert!(
            (inches.size_mm[0] - 215.9).abs() < 1e-9 && (inches.size_mm[1] - 279.4).abs() < 1e-9
        );
        assert_eq!(
            "200x150mm".parse::<Paper>().unwrap().size_mm,
            [200.0, 150.0]
        );
        assert_eq!("20x15cm".parse::<Paper>().unwrap().size_mm, [200.0, 150.0]);
        for bad in [
            "b7",
            "200x",
            "x200mm",
            "200x150",
            "0x10mm",
            "-5x10mm",
            "1e9x1e9mm",
        ] {
            assert!(bad.parse::<Paper>().is_err(), "{bad}");
        }
        assert_eq!("0.3mm".parse::<PaperLength>().unwrap().0, 0.3);
        assert_eq!("0.5".parse::<PaperLength>().unwrap().0, 0.5);
        assert!(("0.01in".parse::<PaperLength>().unwrap().0 - 0.254).abs() < 1e-12);
        for bad in ["", "mm", "-1mm", "NaNmm", "3px"] {
            assert!(bad.parse::<PaperLength>().is_err(), "{bad}");
        }
    }

    #[test]
    fn a_page_reads_from_a_paper_or_its_fields() {
        let a4: Page = serde_json::from_str("\"a4\"").unwrap();
        assert_eq!(a4, Page::new("a4".parse().unwrap()));
        let turned: Page = serde_json::from_str(
            r#"{"paper": "letter", "landscape": true, "pen": "0.5mm", "margin": "1in"}"#,
        )
        .unwrap();
        assert_eq!(turned.paper.size_mm, [279.4, 215.9]);
        assert_eq!((turned.pen.0, turned.margin.0), (0.5, 25.4));
        let written = serde_json::to_string(&turned).unwrap();
        assert_eq!(serde_json::from_str::<Page>(&written).unwrap(), turned);
        for bad in [
            r#""b9""#,
            r#"{"paper": "a4", "colour": 1}"#,
            r#"{"pen": "1mm"}"#,
        ] {
            assert!(serde_json::from_str::<Page>(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn the_canvas_is_the_printable_area_in_pixels() {
        let page = Page::new("a4".parse().unwrap());
        assert_eq!(page.printable_mm(), [190.0, 277.0]);
        assert_eq!(page.canvas(), [1900, 2770]);
        page.check().unwrap();
        let no_room = Page {
            margin: PaperLength(105.0),
            ..page
        };
        assert!(no_room.check().is_err());
        let no_pen = Page {
            pen: PaperLength(0.0),
            ..page
        };
        assert!(no_pen.check().is_err());
    }
}

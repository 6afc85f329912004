//! Stroke colours and widths per kind of line, with overrides from a small JSON file:
//!
//! ```json
//! {
//!   "background": "#ffffff",
//!   "kinds": {
//!     "ridges": {"color": "#c0392b", "width": 1.2, "width_by_strength": false},
//!     "silhouettes": {"width": 2}
//!   }
//! }
//! ```
//!
//! Every key is optional: what a file leaves out keeps its default. `background` is
//! a colour or `null` (transparent). The kinds are named as the SVG groups
//! ([`LineKind::family`]). Colours are `#rgb`, `#rrggbb` or a CSS colour name; widths are
//! in pixels. With `width_by_strength`, a line's width is scaled by its strength
//! relative to the median strength of its group, between half and twice the width.
//! With `width_by_depth`, lines thin with depth, from the full width at the nearest
//! point of the drawing to half of it at the farthest. `taper` (pixels, 0 for
//! none) narrows the ends of open lines over that length, as a pen lifting off.
//! With `fade_by_view`, lines fade where the surface turns away from the viewer
//! (fully drawn where n · v ≥ ½, gone where the surface is seen edge-on).

use std::collections::BTreeMap;
use std::path::Path;

use serde::{Deserialize, Deserializer};

use crate::lines::LineKind;
use crate::{Error, Result};

/// How the lines of one kind are stroked.
#[derive(Clone, Debug, PartialEq)]
pub struct KindStyle {
    /// Stroke colour (`#rgb`, `#rrggbb` or a CSS colour name).
    pub color: String,
    /// Stroke width in pixels.
    pub width: f64,
    /// Scale each line's width by its strength (see the module docs).
    pub width_by_strength: bool,
    /// Thin lines with depth (see the module docs).
    pub width_by_depth: bool,
    /// Length in pixels over which the ends of open lines narrow; 0 for none.
    pub taper: f64,
    /// Fade lines where the surface turns away from the viewer (see the module
    /// docs); lines that keep their surface locations only.
    pub fade_by_view: bool,
}

/// The look of a drawing: a background and a stroke per kind of line.
#[derive(Clone, Debug, PartialEq)]
pub struct Style {
    /// Background colour, or `None` for a transparent background.
    pub background: Option<String>,
    /// The stroke of every kind, indexed by [`LineKind::code`].
    kinds: [KindStyle; LineKind::ALL.len()],
}

impl Default for Style {
    /// White background; every family in its colour ([`LineKind::color`]),
    /// silhouettes slightly wider, borders a little thinner than silhouettes,
    /// suggestive contours thin.
    fn default() -> Self {
        let stroke = |kind: LineKind, width: f64| KindStyle {
            color: kind.color_hex(),
            width,
            width_by_strength: false,
            width_by_depth: false,
            taper: 0.0,
            fade_by_view: false,
        };
        let kinds = LineKind::ALL.map(|kind| {
            let width = match kind {
                LineKind::Silhouette => 1.5,
                LineKind::Border => 1.3,
                LineKind::Contour => 1.0,
                LineKind::Suggestive => 0.9,
                _ => 1.2,
            };
            stroke(kind, width)
        });
        Style {
            background: Some("#ffffff".to_string()),
            kinds,
        }
    }
}

/// A style file: every entry optional.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct StyleFile {
    #[serde(default, deserialize_with = "present")]
    background: Option<Option<String>>,
    #[serde(default)]
    kinds: BTreeMap<String, KindOverride>,
}

/// The entries of one kind in a style file.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct KindOverride {
    color: Option<String>,
    width: Option<f64>,
    width_by_strength: Option<bool>,
    width_by_depth: Option<bool>,
    taper: Option<f64>,
    fade_by_view: Option<bool>,
}

/// Tell a key given as `null` (`Some(None)`) from a missing key (`None`).
fn present<'de, D: Deserializer<'de>>(
    d: D,
) -> std::result::Result<Option<Option<String>>, D::Error> {
    Option::<String>::deserialize(d).map(Some)
}

/// The widest stroke a style may ask for, in pixels.
const MAX_WIDTH: f64 = 100.0;

impl Style {
    /// The stroke of `kind`.
    pub fn kind(&self, kind: LineKind) -> &KindStyle {
        &self.kinds[usize::from(kind.code())]
    }

    /// The stroke of `kind`, to change it.
    pub fn kind_mut(&mut self, kind: LineKind) -> &mut KindStyle {
        &mut self.kinds[usize::from(kind.code())]
    }

    /// The default style with the overrides of the JSON file `path`. Errors
    /// ([`Error::File`]) name the file and the key: unreadable or malformed JSON,
    /// an unknown key or kind, a bad colour or width.
    pub fn read(path: &Path) -> Result<Style> {
        let text = crate::io::file::read_text(path)?;
        Style::default()
            .with_overrides(&text)
            .map_err(|message| Error::File {
                path: path.to_path_buf(),
                message,
            })
    }

    /// This style with the overrides of a style file's text, or what is wrong.
    fn with_overrides(mut self, text: &str) -> std::result::Result<Style, String> {
        let file: StyleFile =
            serde_json::from_str(text).map_err(|e| format!("bad style file: {e}"))?;
        if let Some(background) = file.background {
            if let Some(color) = &background {
                check_color("background", color)?;
            }
            self.background = background;
        }
        for (name, entry) in file.kinds {
            let kind = LineKind::ALL
                .into_iter()
                .find(|&k| k.family() == name)
                .ok_or_else(|| {
                    let known: Vec<&str> =
                        LineKind::ALL.into_iter().map(LineKind::family).collect();
                    format!(
                        "unknown kind \"{name}\" in \"kinds\"; known: {}",
                        known.join(", ")
                    )
                })?;
            let style = self.kind_mut(kind);
            if let Some(color) = entry.color {
                check_color(&format!("kinds.{name}.color"), &color)?;
                style.color = color;
            }
            if let Some(width) = entry.width {
                if !(width > 0.0 && width <= MAX_WIDTH) {
                    return Err(format!(
                        "kinds.{name}.width must be above 0 and at most {MAX_WIDTH}, got {width}"
                    ));
                }
                style.width = width;
            }
            if let Some(by_strength) = entry.width_by_strength {
                style.width_by_strength = by_strength;
            }
            if let Some(by_depth) = entry.width_by_depth {
                style.width_by_depth = by_depth;
            }
            if let Some(fade) = entry.fade_by_view {
                style.fade_by_view = fade;
            }
            if let Some(taper) = entry.taper {
                check_taper(&format!("kinds.{name}.taper"), taper)?;
                style.taper = taper;
            }
        }
        Ok(self)
    }
}

/// The longest taper a style may ask for, in pixels.
pub const MAX_TAPER: f64 = 1000.0;

/// Accept a taper length from 0 to [`MAX_TAPER`] pixels.
pub fn check_taper(key: &str, taper: f64) -> std::result::Result<(), String> {
    if (0.0..=MAX_TAPER).contains(&taper) {
        Ok(())
    } else {
        Err(format!(
            "{key} must be from 0 to {MAX_TAPER} pixels, got {taper}"
        ))
    }
}

/// Accept `#rgb`, `#rrggbb` or a name made of ASCII letters.
fn check_color(key: &str, color: &str) -> std::result::Result<(), String> {
    let hex = color.strip_prefix('#').is_some_and(|digits| {
        matches!(digits.len(), 3 | 6) && digits.chars().all(|c| c.is_ascii_hexdigit())
    });
    let name = !color.is_empty() && color.chars().all(|c| c.is_ascii_alphabetic());
    if hex || name {
        Ok(())
    } else {
        Err(format!(
            "{key}: \"{color}\" is not a colour (#rgb, #rrggbb or a CSS colour name)"
        ))
    }
}

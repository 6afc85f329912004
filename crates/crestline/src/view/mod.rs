//! An interactive 3D view of a surface and its lines as one self-contained HTML
//! file (feature `view`): three.js and the data are embedded, so the file opens
//! in a browser with no network.
//!
//! - The surface is drawn light grey, or coloured by a curvature quantity (`mean`,
//!   `gauss`, `k_max`, `k_min`: blue negative, red positive, saturated at the 95th
//!   percentile of the magnitude); above [`DISPLAY_FACES`] triangles it is shown
//!   decimated by vertex clustering ([`display_mesh`]), the lines keep every point.
//! - Each family of lines is drawn in the drawings' colour ([`Style`]: ridges red,
//!   valleys blue) and can be toggled; a click on a line shows its kind, length and
//!   strength.
//! - Drag to rotate, wheel to zoom. The URL fragment sets the initial state:
//!   `#hide=ridges,valleys&color=mean`.
//!
//! three.js (MIT licence, in the file) is vendored from the npm registry by
//! `tools/vendor_three.sh`.

mod decimate;

use std::fmt::Write as _;

use base64::Engine as _;
use serde_json::json;

use crate::curvature::CurvatureField;
use crate::draw::Style;
use crate::lines::{FeatureLines, LineKind};
use crate::mesh::Mesh;
use crate::xml::escape;

pub use decimate::{display_mesh, DisplayMesh};

/// Above this many triangles the surface is shown decimated (the lines are not):
/// 400,000 triangles embed as about 9 MB of HTML and turn smoothly in a browser.
pub const DISPLAY_FACES: usize = 400_000;

/// The light grey of the surface.
const SURFACE_COLOR: &str = "#d0d0d0";

/// The three.js module, embedded as text.
const THREE: &str = include_str!("three.module.min.js");

/// three.js's licence, embedded beside it.
const THREE_LICENSE: &str = include_str!("three-LICENSE");

/// The viewer's script.
const VIEWER: &str = include_str!("viewer.js");

/// The HTML page showing `mesh` with `lines` in `style`'s colours, titled `title`,
/// with the curvature quantities of `curvature` (one per vertex) to colour the
/// surface by.
pub fn view_html(
    mesh: &Mesh,
    lines: &FeatureLines,
    curvature: Option<&CurvatureField>,
    style: &Style,
    title: &str,
) -> String {
    let display = display_mesh(mesh, DISPLAY_FACES);
    let scene = scene_json(mesh, &display, lines, curvature, style);
    let mut html = String::with_capacity(THREE.len() + scene.len() + 4096);
    let _ = writeln!(
        html,
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>{}</title>\n\
         <style>{CSS}</style>\n</head>\n<body>\n\
         <canvas id=\"view\"></canvas>\n\
         <div id=\"panel\"><div id=\"families\"></div>\
         <label>surface <select id=\"color\"><option value=\"\">grey</option></select></label>\
         <div id=\"info\"></div></div>",
        escape(title)
    );
    let _ = writeln!(
        html,
        "<script id=\"scene\" type=\"application/json\">{}</script>",
        scene.replace("</", "<\\/")
    );
    let _ = writeln!(
        html,
        "<!-- three.js {}-->\n<script id=\"three\" type=\"text/plain\">{THREE}</script>",
        // A comment holds any text but `--`.
        THREE_LICENSE.replace("--", "- -")
    );
    let _ = writeln!(
        html,
        "<script>{ON_ERROR}</script>\n<script type=\"module\">\n{VIEWER}</script>\n</body>\n</html>"
    );
    html
}

/// Shows an error of the viewer's script in the panel (and on `<body
/// data-error>`), rather than a blank page.
const ON_ERROR: &str = "addEventListener('error',e=>{document.body.dataset.error=e.message;\
document.getElementById('info').textContent='The view failed: '+e.message});";

/// The page's style: the canvas fills the window, the panel floats on it.
const CSS: &str = "html,body{margin:0;height:100%;overflow:hidden;font:13px sans-serif}\
#view{width:100%;height:100%;display:block}\
#panel{position:absolute;top:8px;left:8px;background:rgba(255,255,255,.85);padding:6px 8px;border-radius:4px}\
#panel label{display:block;margin:2px 0}\
.swatch{display:inline-block;width:10px;height:10px;margin:0 4px}\
#info{max-width:22em;margin-top:4px}";

/// The scene as the viewer reads it: the display mesh, the quantities per display
/// vertex, and per family its segments, the line of each segment and the lines'
/// kind, length and strength.
fn scene_json(
    mesh: &Mesh,
    display: &DisplayMesh,
    lines: &FeatureLines,
    curvature: Option<&CurvatureField>,
    style: &Style,
) -> String {
    let bounds = mesh.bounding_box();
    let center = bounds.center();
    let radius = (bounds.diagonal() / 2.0).max(f64::MIN_POSITIVE);
    let mut quantities = serde_json::Map::new();
    if let Some(field) = curvature {
        let k = |v: usize| (field.k_max[v], field.k_min[v]);
        let named: [(&str, &dyn Fn(usize) -> f64); 4] = [
            ("mean", &|v| 0.5 * (k(v).0 + k(v).1)),
            ("gauss", &|v| k(v).0 * k(v).1),
            ("k_max", &|v| k(v).0),
            ("k_min", &|v| k(v).1),
        ];
        for (name, value) in named {
            let values = display.per_vertex(|v| {
                if field.unreliable[v] {
                    f64::NAN
                } else {
                    value(v)
                }
            });
            quantities.insert(name.into(), floats(&values).into());
        }
    }
    let mut kinds: Vec<LineKind> = lines.count_by_kind().into_keys().collect();
    kinds.sort();
    let families: Vec<serde_json::Value> = kinds
        .into_iter()
        .map(|kind| family_json(lines, kind, style))
        .collect();
    let positions: Vec<f32> = display.positions.iter().flatten().copied().collect();
    let triangles: Vec<u32> = display.triangles.iter().flatten().copied().collect();
    json!({
        "background": style.background.clone().unwrap_or_else(|| "#ffffff".into()),
        "surface_color": SURFACE_COLOR,
        "center": [center.x, center.y, center.z],
        "radius": radius,
        "positions": floats(&positions),
        "triangles": bytes_of_u32(&triangles),
        "quantities": quantities,
        "families": families,
    })
    .to_string()
}

/// The lines of `kind`: their segments, the line of each and their descriptions.
fn family_json(lines: &FeatureLines, kind: LineKind, style: &Style) -> serde_json::Value {
    let mut segments: Vec<f32> = Vec::new();
    let mut line_of_segment: Vec<u32> = Vec::new();
    let mut described = Vec::new();
    for line in lines.lines.iter().filter(|l| l.kind == kind) {
        let n = line.points.len();
        let pieces = if line.closed { n } else { n.saturating_sub(1) };
        for i in 0..pieces {
            for p in [line.points[i], line.points[(i + 1) % n]] {
                segments.extend([p.x as f32, p.y as f32, p.z as f32]);
            }
            line_of_segment.push(described.len() as u32);
        }
        described.push(json!({
            "kind": kind.name(),
            "closed": line.closed,
            "length": line.length(),
            "strength": line.strength,
        }));
    }
    json!({
        "name": kind.family(),
        "color": style.kind(kind).color,
        "segments": floats(&segments),
        "line_of_segment": bytes_of_u32(&line_of_segment),
        "lines": described,
    })
}

/// `values` as little-endian `f32` bytes in base64.
fn floats<T: Copy + Into<f64>>(values: &[T]) -> String {
    let bytes: Vec<u8> = values
        .iter()
        .flat_map(|&v| (v.into() as f32).to_le_bytes())
        .collect();
    base64::engine::general_purpose::STANDARD.encode(bytes)
}

/// `values` as little-endian `u32` bytes in base64.
fn bytes_of_u32(values: &[u32]) -> String {
    let bytes: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
    base64::engine::general_purpose::STANDARD.encode(bytes)
}

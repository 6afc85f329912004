//! Connectome Workbench border files (`.border`, version 3): feature lines drawn
//! on the surface they were traced on, as Workbench shows borders.
//!
//! A border file names no coordinates: every point is a triangle of the surface
//! (three vertex numbers) with barycentric weights, so the same file shows on every
//! surface of the same mesh (pial, white, inflated, sphere). That is what a
//! [`SurfaceLocation`] is. The layout follows Workbench's own reader
//! (`BorderFile::parseBorderFile3`, `Border::readXML3`):
//!
//! ```xml
//! <BorderFile Version="3" Structure="CORTEX_LEFT" SurfaceNumberOfVertices="10242">
//!   <Class Name="ridges" Red="0.75" Green="0.22" Blue="0.17">
//!     <Border Name="ridges" Red="0.75" Green="0.22" Blue="0.17">
//!       <BorderPart Closed="False">
//!         <Vertices>12 13 40 ...</Vertices>
//!         <Weights>0.25 0.75 0 ...</Weights>
//!       </BorderPart>
//!     </Border>
//!   </Class>
//! </BorderFile>
//! ```
//!
//! Each family of lines is a class holding one border of the same name, each line
//! one part of it (Workbench's multi-part borders), in the family's colour
//! ([`LineKind::color`]).

use std::io::Write;
use std::path::Path;

use super::{write_checked, FeatureLines, LineKind, Polyline, SurfaceLocation};
use crate::io::Structure;
use crate::mesh::{EdgeId, FaceId, Mesh, VertexId};
use crate::xml::escape;
use crate::{Error, Result};

/// The surface a border file refers to.
#[derive(Clone, Copy, Debug)]
pub struct BorderSurface<'a> {
    /// The mesh the lines were traced on.
    pub mesh: &'a Mesh,
    /// The vertex number in the file of each mesh vertex, when the file's numbering
    /// differs from the mesh's (a mesh file repaired on reading); `None` writes the
    /// mesh's own numbers.
    pub file_vertex: Option<&'a [u32]>,
    /// How many vertices the surface file holds (the border's
    /// `SurfaceNumberOfVertices`).
    pub file_vertex_count: usize,
    /// The structure the surface belongs to.
    pub structure: Structure,
}

impl<'a> BorderSurface<'a> {
    /// The surface of `mesh` itself, numbered as the mesh is.
    pub fn of_mesh(mesh: &'a Mesh, structure: Structure) -> BorderSurface<'a> {
        BorderSurface {
            mesh,
            file_vertex: None,
            file_vertex_count: mesh.vertex_count(),
            structure,
        }
    }

    /// The file's number of mesh vertex `v`.
    fn number(&self, v: VertexId) -> u32 {
        self.file_vertex.map_or(v.0, |numbers| numbers[v.idx()])
    }

    /// Why the border cannot refer to this surface, if it cannot: a numbering of
    /// the wrong length or beyond the file's vertex count.
    fn problem(&self) -> Option<String> {
        let numbers = self.file_vertex?;
        if numbers.len() != self.mesh.vertex_count() {
            return Some(format!(
                "{} file vertex numbers for a mesh of {} vertices",
                numbers.len(),
                self.mesh.vertex_count()
            ));
        }
        let beyond = numbers
            .iter()
            .find(|&&n| n as usize >= self.file_vertex_count)?;
        Some(format!(
            "file vertex number {beyond} is beyond the file's {} vertices",
            self.file_vertex_count
        ))
    }
}

/// Write `lines`, traced on `surface.mesh`, as a Workbench border file: one class
/// and border per family, one border part per line, every point a triangle of the
/// surface with barycentric weights. Every point needs its [`SurfaceLocation`] on
/// that mesh: lines read from a file or found in an image have none, and are an
/// [`Error::Argument`].
pub fn write_border(path: &Path, lines: &FeatureLines, surface: &BorderSurface<'_>) -> Result<()> {
    if let Some(problem) = surface.problem() {
        return Err(Error::Argument(problem));
    }
    let parts = lines
        .iter()
        .enumerate()
        .map(|(n, line)| border_part(line, surface).map_err(|e| in_line(e, n)))
        .collect::<Result<Vec<_>>>()?;
    write_checked(path, lines, |out| {
        writeln!(out, r#"<?xml version="1.0" encoding="UTF-8"?>"#)?;
        writeln!(
            out,
            r#"<BorderFile Version="3" Structure="{}" SurfaceNumberOfVertices="{}">"#,
            surface.structure.border_name(),
            surface.file_vertex_count
        )?;
        write_metadata(out, lines)?;
        for kind in LineKind::ALL {
            let family: Vec<&String> = lines
                .iter()
                .zip(&parts)
                .filter(|(line, _)| line.kind == kind)
                .map(|(_, part)| part)
                .collect();
            if family.is_empty() {
                continue;
            }
            let name = kind.family();
            let [red, green, blue] = kind.color_unit();
            let color = format!(r#"Red="{red:.3}" Green="{green:.3}" Blue="{blue:.3}""#);
            writeln!(out, r#"  <Class Name="{name}" {color}>"#)?;
            writeln!(out, r#"    <Border Name="{name}" {color}>"#)?;
            for part in family {
                out.write_all(part.as_bytes())?;
            }
            writeln!(out, "    </Border>\n  </Class>")?;
        }
        writeln!(out, "</BorderFile>")
    })
}

/// The `MetaData` element: where the lines come from and what made the file.
fn write_metadata(out: &mut impl Write, lines: &FeatureLines) -> std::io::Result<()> {
    writeln!(out, "  <MetaData>")?;
    let entries = [
        ("Source", lines.source.as_str()),
        (
            "Generator",
            concat!("crestline ", env!("CARGO_PKG_VERSION")),
        ),
    ];
    for (name, value) in entries {
        writeln!(
            out,
            "    <MD><Name>{name}</Name><Value>{}</Value></MD>",
            escape(value)
        )?;
    }
    writeln!(out, "  </MetaData>")
}

/// The `BorderPart` element of `line`: its points as triangles and weights.
fn border_part(line: &Polyline, surface: &BorderSurface<'_>) -> Result<String> {
    if line.locations.len() != line.points.len() {
        return Err(Error::Argument(
            "a border file needs the surface location of every point: lines traced on the mesh \
             itself, not read from a file or found in an image"
                .to_string(),
        ));
    }
    let mut vertices = String::new();
    let mut weights = String::new();
    for location in &line.locations {
        let (triangle, w) = triangle_weights(surface.mesh, location)?;
        let [a, b, c] = triangle.map(|v| surface.number(v));
        vertices.push_str(&format!("{a} {b} {c}\n"));
        weights.push_str(&format!("{} {} {}\n", w[0], w[1], w[2]));
    }
    let closed = if line.closed { "True" } else { "False" };
    Ok(format!(
        "      <BorderPart Closed=\"{closed}\">\n        <Vertices>{vertices}</Vertices>\n        \
         <Weights>{weights}</Weights>\n      </BorderPart>\n"
    ))
}

/// A triangle of `mesh` holding `location` and the location's barycentric weights
/// in it. A point on a vertex or an edge is given in a face around it, its weight
/// on the face's other corners zero, as Workbench has every point in a triangle.
fn triangle_weights(mesh: &Mesh, location: &SurfaceLocation) -> Result<([VertexId; 3], [f64; 3])> {
    if let Some(missing) = location.missing_on(mesh) {
        return Err(Error::Argument(format!(
            "a line point lies on {missing} (lines traced on another mesh?)"
        )));
    }
    let face = match *location {
        SurfaceLocation::Face { face, barycentric } => {
            return Ok((mesh.face_vertices(FaceId(face)), barycentric));
        }
        SurfaceLocation::Vertex { vertex } => mesh.vertex_faces(VertexId(vertex)).next(),
        SurfaceLocation::Edge { edge, .. } => {
            let sides = [0, 1].map(|side| mesh.edge_halfedge(EdgeId(edge), side));
            sides
                .into_iter()
                .find(|&h| !mesh.is_boundary_halfedge(h))
                .map(|h| mesh.face(h))
        }
    }
    .ok_or_else(|| Error::Argument("a line point lies on no face of the mesh".to_string()))?;
    let corners = mesh.face_vertices(face);
    let mut weights = [0.0; 3];
    for (v, w) in location.weights(mesh) {
        if let Some(i) = corners.iter().position(|&c| c == v) {
            weights[i] += w;
        }
    }
    Ok((corners, weights))
}

/// `err` said of line `n` (counted from 1).
fn in_line(err: Error, n: usize) -> Error {
    match err {
        Error::Argument(message) => Error::Argument(format!("line {}: {message}", n + 1)),
        other => other,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::Mesh;
    use crate::{Point, Space};

    /// A unit square of two triangles and a ridge across it, through a vertex, an
    /// edge and a face.
    fn square_with_line() -> (Mesh, FeatureLines) {
        let mesh = crate::lines::test_meshes::unit_square();
        let diagonal = (0..mesh.edge_count() as u32)
            .find(|&e| {
                let [a, b] = mesh.edge_vertices(EdgeId(e));
                a.0 + b.0 == 2 && a.0 != 1
            })
            .unwrap();
        let locations = vec![
            SurfaceLocation::Vertex { vertex: 1 },
            SurfaceLocation::Edge {
                edge: diagonal,
                t: 0.25,
            },
            SurfaceLocation::Face {
                face: 1,
                barycentric: [0.2, 0.3, 0.5],
            },
        ];
        let points = locations.iter().map(|l| l.position(&mesh)).collect();
        let line = Polyline::new(LineKind::Ridge, false, 1.0, points).with_locations(locations);
        let mut lines = FeatureLines::new("square");
        lines.push(line);
        lines.space = Some(Space::Ras);
        (mesh, lines)
    }

    /// The points of the only border part of `text`, unprojected on `mesh` with the
    /// file numbering `numbering` undone.
    fn unprojected(text: &str, mesh: &Mesh, numbering: &[u32]) -> Vec<Point> {
        let document = roxmltree::Document::parse(text).unwrap();
        let part = document
            .descendants()
            .find(|n| n.has_tag_name("BorderPart"))
            .unwrap();
        let numbers = |tag: &str| -> Vec<f64> {
            part.children()
                .find(|n| n.has_tag_name(tag))
                .and_then(|n| n.text())
                .unwrap()
                .split_whitespace()
                .map(|t| t.parse().unwrap())
                .collect()
        };
        let (vertices, weights) = (numbers("Vertices"), numbers("Weights"));
        assert_eq!(vertices.len(), weights.len());
        vertices
            .chunks(3)
            .zip(weights.chunks(3))
            .map(|(triangle, w)| {
                let sum: crate::Vector = triangle
                    .iter()
                    .zip(w)
                    .map(|(&n, &w)| {
                        let v = numbering.iter().position(|&m| f64::from(m) == n).unwrap();
                        mesh.positions()[v].coords * w
                    })
                    .sum();
                Point::from(sum / w.iter().sum::<f64>())
            })
            .collect()
    }

    #[test]
    fn points_unproject_to_the_line_in_the_files_numbering() {
        let (mesh, lines) = square_with_line();
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("lines.border");
        let numbering = [3, 0, 2, 1];
        let surface = BorderSurface {
            file_vertex: Some(&numbering),
            ..BorderSurface::of_mesh(&mesh, "CortexLeft".parse().unwrap())
        };
        write_border(&path, &lines, &surface).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        assert!(text.contains(
            r#"<BorderFile Version="3" Structure="CORTEX_LEFT" SurfaceNumberOfVertices="4">"#
        ));
        assert!(text.contains(r#"<Class Name="ridges" Red="0.753" Green="0.224" Blue="0.169">"#));
        assert!(text.contains(r#"<BorderPart Closed="False">"#));
        let points = unprojected(&text, &mesh, &numbering);
        assert_eq!(points.len(), 3);
        for (found, expected) in points.iter().zip(&lines.lines[0].points) {
            assert!((found - expected).norm() < 1e-12, "{found} vs {expected}");
        }
    }

    #[test]
    fn lines_without_locations_and_bad_numberings_are_refused_before_writing() {
        let (mesh, mut lines) = square_with_line();
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("lines.border");
        let short = [0, 1];
        let surface = BorderSurface {
            file_vertex: Some(&short),
            ..BorderSurface::of_mesh(&mesh, Structure::OTHER)
        };
        let error = write_border(&path, &lines, &surface)
            .unwrap_err()
            .to_string();
        assert!(
            error.contains("2 file vertex numbers for a mesh of 4"),
            "{error}"
        );
        lines.lines[0].locations.clear();
        let error = write_border(
            &path,
            &lines,
            &BorderSurface::of_mesh(&mesh, Structure::OTHER),
        )
        .unwrap_err()
        .to_string();
        assert!(
            error.contains("line 1") && error.contains("surface location"),
            "{error}"
        );
        assert!(!path.exists());
    }
}

//! Writing triangle soups: surfaces that need not be orientable or manifold (crease
//! surfaces of images may be Möbius-like), saved as they are, without the repairs
//! of [`crate::mesh::Mesh::from_soup`].

use std::io::Write;
use std::path::Path;

use crate::mesh::TriangleSoup;
use crate::{Error, Result};

use super::obj::write_triangles_obj;
use super::ply::write_triangles_ply;
use super::VertexAttribute;

/// Write `soup` in the format given by the extension of `path`: `.ply` (binary,
/// with every vertex scalar as a float property), `.obj`, or `.vtk` (legacy ASCII
/// `POLYDATA` with the vertex scalars as `POINT_DATA`). Written atomically.
///
/// Errors ([`Error::File`] naming `path`, before any file is created): an unknown
/// extension, a non-finite coordinate or scalar, an index out of range, or a scalar
/// without one value per vertex.
pub fn write_soup(path: &Path, soup: &TriangleSoup) -> Result<()> {
    let in_file = |message: String| Error::File {
        path: path.to_path_buf(),
        message,
    };
    check_soup(soup).map_err(in_file)?;
    let extension = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    match extension.as_deref() {
        Some("ply") => {
            let attributes: Vec<VertexAttribute<'_>> = soup
                .vertex_scalars
                .iter()
                .map(|s| VertexAttribute::Scalar {
                    name: &s.name,
                    values: &s.values,
                })
                .collect();
            write_triangles_ply(path, &soup.positions, &soup.triangles, &attributes)
        }
        Some("obj") => write_triangles_obj(path, &soup.positions, &soup.triangles),
        Some("vtk") => write_soup_vtk(path, soup),
        _ => Err(in_file(
            "unknown surface format; supported extensions: .ply, .obj, .vtk".into(),
        )),
    }
}

/// Why `soup` cannot be written, if it cannot.
fn check_soup(soup: &TriangleSoup) -> std::result::Result<(), String> {
    let n = soup.positions.len();
    if let Some(v) = soup
        .positions
        .iter()
        .position(|p| !p.iter().all(|c| c.is_finite()))
    {
        return Err(format!("vertex {v} has a coordinate that is not finite"));
    }
    if let Some(f) = soup
        .triangles
        .iter()
        .position(|t| t.iter().any(|&v| v as usize >= n))
    {
        return Err(format!(
            "triangle {f} refers to a vertex beyond the {n} given"
        ));
    }
    for scalar in &soup.vertex_scalars {
        if scalar.values.len() != n {
            return Err(format!(
                "vertex scalar '{}' has {} values for {n} vertices",
                scalar.name,
                scalar.values.len()
            ));
        }
        if scalar.name.is_empty() || scalar.name.chars().any(|c| c.is_whitespace()) {
            return Err(format!("'{}' is not a valid property name", scalar.name));
        }
        if let Some(v) = scalar.values.iter().position(|x| !x.is_finite()) {
            return Err(format!(
                "vertex scalar '{}' is not finite at vertex {v}",
                scalar.name
            ));
        }
    }
    Ok(())
}

/// Legacy ASCII VTK: `POINTS`, `POLYGONS` of three corners, and `POINT_DATA` with
/// one `SCALARS` array per vertex scalar.
fn write_soup_vtk(path: &Path, soup: &TriangleSoup) -> Result<()> {
    crate::atomic::write_atomically(path, |w| {
        writeln!(w, "# vtk DataFile Version 3.0")?;
        writeln!(w, "triangle surface written by crestline")?;
        writeln!(w, "ASCII")?;
        writeln!(w, "DATASET POLYDATA")?;
        writeln!(w, "POINTS {} double", soup.positions.len())?;
        for p in &soup.positions {
            writeln!(w, "{} {} {}", p.x, p.y, p.z)?;
        }
        let faces = soup.triangles.len();
        writeln!(w, "POLYGONS {faces} {}", 4 * faces)?;
        for [a, b, c] in &soup.triangles {
            writeln!(w, "3 {a} {b} {c}")?;
        }
        if !soup.vertex_scalars.is_empty() {
            writeln!(w, "POINT_DATA {}", soup.positions.len())?;
        }
        for scalar in &soup.vertex_scalars {
            writeln!(w, "SCALARS {} double 1", scalar.name)?;
            writeln!(w, "LOOKUP_TABLE default")?;
            for value in &scalar.values {
                writeln!(w, "{value}")?;
            }
        }
        Ok(())
    })
}

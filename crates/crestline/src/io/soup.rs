//! Writing triangle soups: surfaces that need not be orientable or manifold (crease
//! surfaces of images may be Möbius-like), saved as they are, without the repairs
//! of [`crate::mesh::Mesh::from_soup`].
//!
//! A GIfTI surface says which anatomical structure it is for Connectome
//! Workbench ([`write_soup_of_structure`]).

use std::path::Path;

use crate::atomic::write_atomically;
use crate::mesh::TriangleSoup;
use crate::{Error, Result};

use super::format::{choose_format, FileFormat};
use super::gifti::write_gifti_surface;
use super::obj::write_triangles_obj;
use super::ply::write_triangles_ply;
use super::vtk::{self, Attachment, CellType};
use super::Structure;
use super::VertexAttribute;

/// A writer of one format, given a soup already checked and the anatomical
/// structure it is a surface of.
type SoupWriter = fn(&Path, &TriangleSoup, Structure) -> Result<()>;

/// The formats of [`write_soup`], each with its writer, in the order listed in
/// error messages.
const WRITERS: [(FileFormat, SoupWriter); 4] = [
    (FileFormat::Ply, write_soup_ply),
    (FileFormat::Obj, write_soup_obj),
    (FileFormat::Vtk, write_soup_vtk),
    (FileFormat::GiftiSurface, write_soup_gifti),
];

/// Write `soup` in the format given by the extension of `path`: `.ply` (binary,
/// with every vertex scalar as a double property), `.obj`, `.vtk` (legacy ASCII
/// `POLYDATA` with the vertex scalars as `POINT_DATA`) or `.surf.gii` (a GIfTI
/// surface in RAS, without the scalars, of the default [`Structure`], `Other`;
/// see [`write_soup_of_structure`]). Written atomically.
///
/// Errors ([`Error::File`] naming `path`, before any file is created): an unknown
/// extension ([`soup_format`]), a non-finite coordinate or scalar, an index out of
/// range, or a scalar without one value per vertex.
pub fn write_soup(path: &Path, soup: &TriangleSoup) -> Result<()> {
    write_soup_of_structure(path, soup, Structure::default())
}

/// [`write_soup`] of a surface of the anatomical `structure`, which a GIfTI
/// surface records as Connectome Workbench reads it (`AnatomicalStructurePrimary`,
/// with the `GeometricType` `Anatomical`); the other formats have no place for it.
pub fn write_soup_of_structure(
    path: &Path,
    soup: &TriangleSoup,
    structure: Structure,
) -> Result<()> {
    check_soup(soup).map_err(|message| Error::File {
        path: path.to_path_buf(),
        message,
    })?;
    let (_, write) = writer_for(path)?;
    write(path, soup, structure)
}

/// The format [`write_soup`] writes `path` in: [`FileFormat::Ply`],
/// [`FileFormat::Obj`], [`FileFormat::Vtk`] or [`FileFormat::GiftiSurface`] by
/// its extension, in any letter case; another extension is an [`Error::File`]
/// listing these, so that a caller can check an output's name before the work.
pub fn soup_format(path: &Path) -> Result<FileFormat> {
    writer_for(path).map(|(format, _)| format)
}

/// The format and writer of the extension of `path`.
fn writer_for(path: &Path) -> Result<(FileFormat, SoupWriter)> {
    choose_format(path, "a surface", &WRITERS)
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

/// Binary PLY with every vertex scalar as a double property.
fn write_soup_ply(path: &Path, soup: &TriangleSoup, _: Structure) -> Result<()> {
    let attributes: Vec<VertexAttribute<'_>> = soup
        .vertex_scalars
        .iter()
        .map(|s| VertexAttribute::Scalar {
            name: &s.name,
            values: &s.values,
        })
        .collect();
    write_triangles_ply(
        path,
        (&soup.positions, &soup.triangles, soup.space),
        &attributes,
    )
}

/// OBJ of the positions and triangles.
fn write_soup_obj(path: &Path, soup: &TriangleSoup, _: Structure) -> Result<()> {
    write_triangles_obj(path, &soup.positions, &soup.triangles, soup.space)
}

/// Legacy ASCII VTK: `POINTS`, `POLYGONS` of three corners, and `POINT_DATA` with
/// one `SCALARS` array per vertex scalar.
fn write_soup_vtk(path: &Path, soup: &TriangleSoup, _: Structure) -> Result<()> {
    let n = soup.positions.len();
    write_atomically(path, |w| {
        vtk::write_header(
            w,
            &vtk::title("triangle surface written by crestline", soup.space),
        )?;
        vtk::write_points(w, n, &soup.positions)?;
        vtk::write_cells(w, CellType::Polygons, || {
            soup.triangles.iter().map(|t| t.map(|v| v as usize))
        })?;
        if !soup.vertex_scalars.is_empty() {
            vtk::write_data(w, Attachment::Points, n)?;
        }
        for scalar in &soup.vertex_scalars {
            vtk::write_scalars(w, &scalar.name, scalar.values.iter().copied())?;
        }
        Ok(())
    })
}

/// A GIfTI surface: the positions in RAS (GIfTI's frame; converted from LPS, in
/// an unknown space when the soup has no frame), the triangles, and the
/// structure.
fn write_soup_gifti(path: &Path, soup: &TriangleSoup, structure: Structure) -> Result<()> {
    let [named] = structure.gifti_metadata();
    let metadata = [named, ("GeometricType", "Anatomical")];
    write_gifti_surface(
        path,
        (&soup.positions, soup.space),
        &soup.triangles,
        &metadata,
    )
}

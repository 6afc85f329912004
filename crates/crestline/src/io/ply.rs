//! Stanford PLY: reading (ASCII and binary) and writing (binary little endian).
//!
//! The header is checked line by line ([`super::ply_header`]) and its element counts
//! against the size of the file before anything is allocated; binary files of the
//! common layout are decoded by [`super::ply_binary`], every other layout record by
//! record ([`super::ply_records`]).

use std::io::Write;
use std::path::Path;

use super::ply_binary::{self, Endian};
use super::ply_header::{self, Element, Encoding, Header, Property, PropertyType, ScalarType};
use super::ply_records::read_element;
use super::{push_polygon, Input};
use crate::mesh::{Mesh, ScalarProperty, TriangleSoup};
use crate::{Error, Point, Result, Space, Vector};

/// Names under which PLY files store a face's vertex list.
const FACE_INDEX_NAMES: &[&str] = &["vertex_indices", "vertex_index"];
/// Vertex properties not kept as [`ScalarProperty`]: the position and the normal.
const DROPPED_VERTEX_PROPERTIES: &[&str] = &["x", "y", "z", "nx", "ny", "nz"];

/// Read a PLY file from memory: ASCII, binary little endian or binary big endian.
///
/// Needs a `vertex` element with scalar `x`, `y`, `z` and a `face` element with an
/// integer list `vertex_indices` (or `vertex_index`) of 3 to
/// [`super::MAX_FACE_CORNERS`] corners; polygons are fanned into triangles and
/// other elements are skipped. Every other scalar vertex property (`quality`,
/// `red`, user fields, ...) except the normal `nx`, `ny`, `nz` is kept as a
/// [`ScalarProperty`] of the same name, converted to `f64`.
///
/// Element names must be unique, and the counts of the header must fit in the
/// file: a header announcing more records than the file can hold is an error
/// before anything is read.
#[cfg(test)]
pub fn read_ply(bytes: &[u8]) -> Result<TriangleSoup> {
    super::parse_bytes(bytes, None, parse)
}

pub(super) fn parse(input: &mut Input<'_>) -> Result<TriangleSoup> {
    let header = ply_header::read_header(input)?;
    let layout = Layout::new(&header)?;
    ply_header::check_counts_fit(&header, input.rest())?;
    let mut soup = TriangleSoup::default();
    for element in &header.elements {
        match element.name.as_str() {
            "vertex" => read_vertices(input, header.encoding, element, &layout, &mut soup)?,
            "face" => read_faces(input, header.encoding, element, &layout, &mut soup)?,
            _ => read_element(input, header.encoding, element, None, |_| Ok(()))?,
        }
    }
    Ok(soup)
}

/// What the header says about the elements the reader uses.
struct Layout {
    vertex: VertexLayout,
    vertex_count: usize,
    /// The position of the index list among the face element's properties.
    face_list: usize,
}

/// Where the values of a vertex record go: the columns are positions among the
/// vertex element's scalar properties, in header order.
struct VertexLayout {
    xyz: [usize; 3],
    scalar_count: usize,
    /// Kept properties: name and column.
    extras: Vec<(String, usize)>,
}

impl Layout {
    fn new(header: &Header) -> Result<Layout> {
        let element = |name: &str| header.elements.iter().find(|e| e.name == name);
        let vertex = element("vertex")
            .ok_or_else(|| Error::Parse("the PLY file has no 'vertex' element".to_string()))?;
        let face = element("face").ok_or_else(|| {
            Error::Parse("the PLY file has no 'face' element (point clouds are not meshes)".into())
        })?;
        let face_list = face_index_list(face)?;
        Ok(Layout {
            vertex: VertexLayout::new(vertex)?,
            vertex_count: vertex.count,
            face_list,
        })
    }
}

impl VertexLayout {
    fn new(def: &Element) -> Result<VertexLayout> {
        let scalars: Vec<&str> = def
            .properties
            .iter()
            .filter(|p| matches!(p.kind, PropertyType::Scalar(_)))
            .map(|p| p.name.as_str())
            .collect();
        let xyz = [
            def.scalar_column("x")?,
            def.scalar_column("y")?,
            def.scalar_column("z")?,
        ];
        let extras = scalars
            .iter()
            .enumerate()
            .filter(|(_, name)| !DROPPED_VERTEX_PROPERTIES.contains(name))
            .map(|(i, name)| (name.to_string(), i))
            .collect();
        Ok(VertexLayout {
            xyz,
            scalar_count: scalars.len(),
            extras,
        })
    }
}

/// The position of the face element's vertex index list, which must be the only
/// one and of an integer type.
fn face_index_list(def: &Element) -> Result<usize> {
    let lists: Vec<(usize, PropertyType)> = FACE_INDEX_NAMES
        .iter()
        .filter_map(|name| def.property(name))
        .map(|(k, p)| (k, p.kind))
        .collect();
    let problem = match lists.as_slice() {
        [(_, PropertyType::List { item, .. })] if item.is_float() => {
            "its vertex index list has a floating-point type"
        }
        [(k, PropertyType::List { .. })] => return Ok(*k),
        [_] => "its vertex indices are not a list",
        [] => "it has no 'vertex_indices' list",
        _ => "it has both 'vertex_indices' and 'vertex_index'",
    };
    Err(Error::Parse(format!(
        "unsupported PLY face element: {problem}"
    )))
}

/// Read the vertex element: binary records of scalars column by column, any other
/// layout record by record.
fn read_vertices(
    input: &mut Input<'_>,
    encoding: Encoding,
    def: &Element,
    layout: &Layout,
    soup: &mut TriangleSoup,
) -> Result<()> {
    let layout = &layout.vertex;
    if let Some((endian, fixed)) = binary(encoding).zip(ply_binary::fixed_layout(def)) {
        let extras: Vec<usize> = layout.extras.iter().map(|(_, c)| *c).collect();
        let (positions, values) = ply_binary::read_vertices(
            input,
            def,
            (&fixed.0, fixed.1),
            layout.xyz,
            &extras,
            endian,
        )?;
        soup.positions = positions;
        soup.vertex_scalars = named_columns(layout, values);
        return Ok(());
    }
    let mut extras: Vec<Vec<f64>> = layout.extras.iter().map(|_| Vec::new()).collect();
    let [x, y, z] = layout.xyz;
    read_element(input, encoding, def, None, |record| {
        let values = &record.scalars;
        if values.len() != layout.scalar_count {
            return Err(format!(
                "{} values, expected {}",
                values.len(),
                layout.scalar_count
            ));
        }
        soup.positions
            .push(Point::new(values[x], values[y], values[z]));
        for ((_, column), property) in layout.extras.iter().zip(&mut extras) {
            property.push(values[*column]);
        }
        Ok(())
    })?;
    soup.vertex_scalars = named_columns(layout, extras);
    Ok(())
}

/// The byte order of a binary encoding.
fn binary(encoding: Encoding) -> Option<Endian> {
    match encoding {
        Encoding::Ascii => None,
        Encoding::Binary(endian) => Some(endian),
    }
}

/// The kept vertex properties, named.
fn named_columns(layout: &VertexLayout, columns: Vec<Vec<f64>>) -> Vec<ScalarProperty> {
    layout
        .extras
        .iter()
        .zip(columns)
        .map(|((name, _), values)| ScalarProperty {
            name: name.clone(),
            values,
        })
        .collect()
}

/// Read the face element, fanning polygons into `soup.triangles`: binary records
/// made of the index list alone straight from the bytes, any other layout record
/// by record.
fn read_faces(
    input: &mut Input<'_>,
    encoding: Encoding,
    def: &Element,
    layout: &Layout,
    soup: &mut TriangleSoup,
) -> Result<()> {
    let vertex_count = layout.vertex_count;
    let triangles = &mut soup.triangles;
    if let Some((endian, list)) = binary(encoding).zip(ply_binary::single_list(def)) {
        return ply_binary::read_faces(input, def, list, vertex_count, endian, triangles);
    }
    let mut scratch = Vec::new();
    read_element(input, encoding, def, Some(layout.face_list), |record| {
        let corners = record.corners.iter().copied();
        push_polygon(corners, vertex_count, &mut scratch, triangles)
    })
}

/// A per-vertex quantity to store in a PLY file next to the positions.
#[derive(Clone, Copy, Debug)]
pub enum VertexAttribute<'a> {
    /// One value per vertex, written as the double property `name`.
    Scalar {
        /// The property name.
        name: &'a str,
        /// One value per vertex.
        values: &'a [f64],
    },
    /// One vector per vertex, written as the double properties `name_x`, `name_y`,
    /// `name_z`.
    Vector {
        /// The name before the `_x`, `_y`, `_z` suffixes.
        name: &'a str,
        /// One vector per vertex.
        values: &'a [Vector],
    },
}

impl VertexAttribute<'_> {
    fn name(&self) -> &str {
        match self {
            VertexAttribute::Scalar { name, .. } | VertexAttribute::Vector { name, .. } => name,
        }
    }

    fn len(&self) -> usize {
        match self {
            VertexAttribute::Scalar { values, .. } => values.len(),
            VertexAttribute::Vector { values, .. } => values.len(),
        }
    }

    /// The PLY property names this attribute is written as.
    fn property_names(&self) -> Vec<String> {
        match self {
            VertexAttribute::Scalar { name, .. } => vec![name.to_string()],
            VertexAttribute::Vector { name, .. } => {
                ["x", "y", "z"].map(|c| format!("{name}_{c}")).to_vec()
            }
        }
    }

    /// The first value that is not finite, described with its property and
    /// vertex, or `None`.
    fn first_non_finite(&self) -> Option<String> {
        let fits = |x: f64| x.is_finite();
        let (property, v, value) = match self {
            VertexAttribute::Scalar { name, values } => {
                let v = values.iter().position(|&x| !fits(x))?;
                (name.to_string(), v, values[v])
            }
            VertexAttribute::Vector { name, values } => {
                let (v, c) = values.iter().enumerate().find_map(|(v, p)| {
                    let c = p.iter().position(|&x| !fits(x))?;
                    Some((v, c))
                })?;
                (format!("{name}_{}", ["x", "y", "z"][c]), v, values[v][c])
            }
        };
        Some(format!(
            "vertex property '{property}' of vertex {v} is {value}, not a finite number"
        ))
    }

    /// Append vertex `v`'s value(s) as little-endian `f64`.
    fn write_vertex(&self, v: usize, w: &mut impl Write) -> std::io::Result<()> {
        match self {
            VertexAttribute::Scalar { values, .. } => w.write_all(&values[v].to_le_bytes()),
            VertexAttribute::Vector { values, .. } => values[v]
                .iter()
                .try_for_each(|&c| w.write_all(&c.to_le_bytes())),
        }
    }
}

/// Write `mesh` as a binary little-endian PLY file: a `vertex` element with double
/// `x`, `y`, `z` followed by the `attributes` in order (a scalar as one double
/// property, a vector as three), and a `face` element with a
/// `list uchar int vertex_indices`. The file is written atomically.
///
/// Fails with [`Error::Argument`] if an attribute does not have one value per
/// vertex, or its name is empty, contains white space or repeats another property,
/// and with [`Error::File`] naming the property if a value is not finite; no file
/// is created then. Everything is written in double precision, so that the
/// values read back exactly.
pub fn write_ply(path: &Path, mesh: &Mesh, attributes: &[VertexAttribute<'_>]) -> Result<()> {
    let triangles = mesh.triangles();
    write_triangles_ply(
        path,
        (mesh.positions(), &triangles, mesh.space()),
        attributes,
    )
}

/// [`write_ply`] for any indexed triangles (checked by the caller to be in range),
/// orientable or not, with their frame, marked in a comment as 3D Slicer does.
pub(super) fn write_triangles_ply(
    path: &Path,
    (positions, triangles, space): (&[Point], &[[u32; 3]], Option<Space>),
    attributes: &[VertexAttribute<'_>],
) -> Result<()> {
    let elements = header_elements(positions.len(), triangles.len(), attributes)?;
    if let Some(message) = attributes
        .iter()
        .find_map(VertexAttribute::first_non_finite)
    {
        return Err(Error::File {
            path: path.to_path_buf(),
            message,
        });
    }
    crate::atomic::write_atomically(path, |w| {
        let comments: Vec<String> = std::iter::once("written by crestline".to_string())
            .chain(space.map(Space::slicer_mark))
            .collect();
        ply_header::write_header(w, &comments, &elements)?;
        for (v, p) in positions.iter().enumerate() {
            p.coords
                .iter()
                .try_for_each(|&c| w.write_all(&c.to_le_bytes()))?;
            for attribute in attributes {
                attribute.write_vertex(v, w)?;
            }
        }
        for triangle in triangles {
            w.write_all(&[3])?;
            for &v in triangle {
                // Below i32::MAX: checked by `header_elements`.
                w.write_all(&(v as i32).to_le_bytes())?;
            }
        }
        Ok(())
    })
}

/// The elements of [`write_ply`]'s header, after checking the attributes.
fn header_elements(
    vertex_count: usize,
    face_count: usize,
    attributes: &[VertexAttribute<'_>],
) -> Result<[Element; 2]> {
    if i32::try_from(vertex_count).is_err() {
        return Err(Error::Argument(format!(
            "{vertex_count} vertices are too many for PLY int indices"
        )));
    }
    let mut names: Vec<String> = ["x", "y", "z"].map(String::from).to_vec();
    for attribute in attributes {
        let name = attribute.name();
        if attribute.len() != vertex_count {
            return Err(Error::Argument(format!(
                "vertex attribute '{name}' has {} values for {vertex_count} vertices",
                attribute.len()
            )));
        }
        if name.is_empty() || name.chars().any(char::is_whitespace) {
            return Err(Error::Argument(format!(
                "'{name}' is not a valid PLY property name"
            )));
        }
        for property in attribute.property_names() {
            if names.contains(&property) {
                return Err(Error::Argument(format!(
                    "vertex property '{property}' is given twice"
                )));
            }
            names.push(property);
        }
    }
    // Double precision, so that a written mesh and its values read back exactly.
    let vertex = Element {
        name: "vertex".to_string(),
        count: vertex_count,
        properties: names
            .into_iter()
            .map(|name| Property::scalar(ScalarType::Double, name))
            .collect(),
    };
    let face = Element {
        name: "face".to_string(),
        count: face_count,
        properties: vec![Property {
            name: "vertex_indices".to_string(),
            kind: PropertyType::List {
                count: ScalarType::UChar,
                item: ScalarType::Int,
            },
        }],
    };
    Ok([vertex, face])
}

//! Stanford PLY: reading (ASCII and binary, through `ply-rs-bw`) and writing
//! (binary little endian).

use std::io::Write;
use std::path::Path;

use ply_rs_bw::parser::{ParseError, Parser, Reader};
use ply_rs_bw::ply::{
    BeginList, ElementDef, Encoding, Header, PropertyAccess, PropertyAccessResult, PropertyType,
    ScalarType,
};

use super::ply_binary::{self, scalar_size, Endian};
use super::{capped_capacity, line_error, push_polygon, truncated, Input};
use crate::mesh::{Mesh, ScalarProperty, TriangleSoup};
use crate::{Error, Point, Result, Vector};

/// Names under which PLY files store a face's vertex list.
const FACE_INDEX_NAMES: &[&str] = &["vertex_indices", "vertex_index"];
/// Vertex properties not kept as [`ScalarProperty`]: the position and the normal.
const DROPPED_VERTEX_PROPERTIES: &[&str] = &["x", "y", "z", "nx", "ny", "nz"];

/// Read a PLY file from memory: ASCII, binary little endian or binary big endian.
///
/// Needs a `vertex` element with scalar `x`, `y`, `z` and a `face` element with an
/// integer list `vertex_indices` (or `vertex_index`); polygons are fanned into
/// triangles and other elements are skipped. Every other scalar vertex property
/// (`quality`, `red`, user fields, ...) except the normal `nx`, `ny`, `nz` is kept
/// as a [`ScalarProperty`] of the same name, converted to `f64`.
pub fn read_ply(bytes: &[u8]) -> Result<TriangleSoup> {
    super::parse_bytes(bytes, None, parse)
}

pub(super) fn parse(input: &mut Input<'_>) -> Result<TriangleSoup> {
    if !input.rest().starts_with(b"ply") {
        return Err(Error::Parse(
            "not a PLY file: it does not start with 'ply'".to_string(),
        ));
    }
    let mut reader = Reader::new(input);
    let header = Parser::<Skipped>::new()
        .read_header(&mut reader)
        .map_err(|e| header_error(&e, reader.line()))?;
    let layout = Layout::new(&header)?;
    let next_line = reader.line();
    reader.get_mut().set_line(next_line.saturating_sub(1));
    let mut payload = Payload {
        reader,
        encoding: header.encoding,
    };
    let mut soup = TriangleSoup::default();
    let endian = match header.encoding {
        Encoding::Ascii => None,
        Encoding::BinaryLittleEndian => Some(Endian::Little),
        Encoding::BinaryBigEndian => Some(Endian::Big),
    };
    for def in header.elements.values() {
        let fixed = endian.zip(ply_binary::fixed_layout(def));
        let index_list = endian.zip(single_list(def));
        match (def.name.as_str(), fixed, index_list) {
            ("vertex", Some((endian, (columns, stride))), _) => {
                let extras: Vec<usize> = layout.vertex.extras.iter().map(|(_, c)| *c).collect();
                let input = payload.reader.get_mut();
                let (positions, values) = ply_binary::read_vertices(
                    input,
                    def,
                    (&columns, stride),
                    layout.vertex.xyz,
                    &extras,
                    endian,
                )?;
                soup.positions = positions;
                soup.vertex_scalars = named_columns(&layout.vertex, values);
            }
            ("vertex", None, _) => read_vertices(&mut payload, def, &layout.vertex, &mut soup)?,
            ("face", _, Some((endian, (count, index)))) => {
                let input = payload.reader.get_mut();
                let vertex_count = layout.vertex_count;
                ply_binary::read_faces(
                    input,
                    def,
                    (&count, &index),
                    vertex_count,
                    endian,
                    &mut soup.triangles,
                )?;
            }
            ("face", _, None) => {
                read_faces(&mut payload, def, layout.vertex_count, &mut soup.triangles)?
            }
            _ => payload.records(def, |_, _: Skipped| Ok(()))?,
        }
    }
    Ok(soup)
}

/// The error for a malformed header.
fn header_error(e: &ParseError, line: usize) -> Error {
    line_error(e.line().unwrap_or(line), library_message(e))
}

/// A `ply-rs-bw` error message on one line, without its own line prefix and
/// without the grammar's internal diagnostics: "Couldn't parse line: 'property
/// floot x'".
fn library_message(e: &ParseError) -> String {
    let text = e.to_string();
    let text = match e.line() {
        Some(line) => text
            .strip_prefix(&format!("Line {line}: "))
            .unwrap_or(&text)
            .to_string(),
        None => text,
    };
    let text = text.split_whitespace().collect::<Vec<_>>().join(" ");
    match text.split_once(" String: ") {
        Some((reason, rest)) => {
            let quoted = rest.split(" Error: ").next().unwrap_or(rest).trim();
            let quoted = quoted.replace(" '", "'");
            format!("{}: {quoted}", reason.trim_end_matches('.'))
        }
        None => text,
    }
}

/// What the header says about the elements the reader uses.
struct Layout {
    vertex: VertexLayout,
    vertex_count: usize,
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
        let vertex = header
            .elements
            .get("vertex")
            .ok_or_else(|| Error::Parse("the PLY file has no 'vertex' element".to_string()))?;
        let face = header.elements.get("face").ok_or_else(|| {
            Error::Parse("the PLY file has no 'face' element (point clouds are not meshes)".into())
        })?;
        check_face_indices(face)?;
        Ok(Layout {
            vertex: VertexLayout::new(vertex)?,
            vertex_count: vertex.count,
        })
    }
}

impl VertexLayout {
    fn new(def: &ElementDef) -> Result<VertexLayout> {
        let scalars: Vec<&str> = def
            .properties
            .values()
            .filter(|p| matches!(p.data_type, PropertyType::Scalar(_)))
            .map(|p| p.name.as_str())
            .collect();
        let column = |name: &str| {
            scalars.iter().position(|&s| s == name).ok_or_else(|| {
                Error::Parse(format!(
                    "the PLY vertex element has no scalar property '{name}'"
                ))
            })
        };
        let xyz = [column("x")?, column("y")?, column("z")?];
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

/// The face element must have exactly one vertex index list, of an integer type.
fn check_face_indices(def: &ElementDef) -> Result<()> {
    let lists: Vec<&PropertyType> = FACE_INDEX_NAMES
        .iter()
        .filter_map(|name| def.properties.get(*name))
        .map(|p| &p.data_type)
        .collect();
    let problem = match lists.as_slice() {
        [PropertyType::List(_, ScalarType::Float | ScalarType::Double)] => {
            "its vertex index list has a floating-point type"
        }
        [PropertyType::List(_, _)] => return Ok(()),
        [_] => "its vertex indices are not a list",
        [] => "it has no 'vertex_indices' list",
        _ => "it has both 'vertex_indices' and 'vertex_index'",
    };
    Err(Error::Parse(format!(
        "unsupported PLY face element: {problem}"
    )))
}

/// The outcome of reading one record.
enum Next<E> {
    Record(E),
    Malformed(String),
    /// The file ended before the record.
    End,
}

/// The payload of a PLY file, read one record at a time.
struct Payload<'i, 'a> {
    reader: Reader<&'i mut Input<'a>>,
    encoding: Encoding,
}

impl Payload<'_, '_> {
    /// Read every record of `def`, passing each to `sink`. Errors name the record and
    /// where it is: the line (ASCII) or the byte offset (binary).
    fn records<E: PropertyAccess>(
        &mut self,
        def: &ElementDef,
        mut sink: impl FnMut(usize, E) -> std::result::Result<(), String>,
    ) -> Result<()> {
        if def.properties.is_empty() {
            // Records without properties take no bytes: nothing to read, however
            // large the count.
            return Ok(());
        }
        let parser = Parser::<E>::new();
        for i in 0..def.count {
            let offset = self.reader.get_ref().position();
            let record = match self.read_record(&parser, def)? {
                Next::Record(record) => Ok(record),
                Next::Malformed(message) => Err(message),
                Next::End => {
                    return Err(truncated(i, def.count, &format!("'{}' elements", def.name)))
                }
            };
            record
                .and_then(|r| sink(i, r))
                .map_err(|message| self.locate(def, i, offset, message))?;
        }
        Ok(())
    }

    /// The next record of `def`.
    fn read_record<E: PropertyAccess>(
        &mut self,
        parser: &Parser<E>,
        def: &ElementDef,
    ) -> Result<Next<E>> {
        let input = self.reader.get_mut();
        let result = match self.encoding {
            Encoding::Ascii => match input.next_line()? {
                Some(line) => parser.read_ascii_element(line, def),
                None => return Ok(Next::End),
            },
            Encoding::BinaryLittleEndian => parser.read_little_endian_element(input, def),
            Encoding::BinaryBigEndian => parser.read_big_endian_element(input, def),
        };
        Ok(match result {
            Ok(record) => Next::Record(record),
            Err(e) if e.kind() == std::io::ErrorKind::UnexpectedEof => Next::End,
            Err(e) => Next::Malformed(library_message(&e)),
        })
    }

    /// An error about record `i` of `def`, which starts at byte `offset`.
    fn locate(&self, def: &ElementDef, i: usize, offset: usize, message: String) -> Error {
        match self.encoding {
            Encoding::Ascii => line_error(
                self.reader.get_ref().line(),
                format!("{} {i}: {message}", def.name),
            ),
            _ => Error::Parse(format!("{} {i} (byte {offset}): {message}", def.name)),
        }
    }

    /// Fewest bytes a record of `def` can take, to cap allocations.
    fn min_record_bytes(&self, def: &ElementDef) -> usize {
        match self.encoding {
            // A digit and a separator per property.
            Encoding::Ascii => 2 * def.properties.len(),
            _ => def
                .properties
                .values()
                .map(|p| match &p.data_type {
                    PropertyType::Scalar(t) | PropertyType::List(t, _) => scalar_size(t),
                })
                .sum(),
        }
    }

    /// A capacity for the records of `def` that the rest of the file could hold.
    fn capacity(&self, def: &ElementDef) -> usize {
        capped_capacity(
            def.count,
            self.reader.get_ref().remaining(),
            self.min_record_bytes(def),
        )
    }
}

/// The count and index types of an element made of a single list property.
fn single_list(def: &ElementDef) -> Option<(ScalarType, ScalarType)> {
    match def.properties.values().collect::<Vec<_>>().as_slice() {
        [p] => match &p.data_type {
            PropertyType::List(count, index) => Some((count.clone(), index.clone())),
            PropertyType::Scalar(_) => None,
        },
        _ => None,
    }
}

fn read_vertices(
    payload: &mut Payload<'_, '_>,
    def: &ElementDef,
    layout: &VertexLayout,
    soup: &mut TriangleSoup,
) -> Result<()> {
    let capacity = payload.capacity(def);
    soup.positions.reserve(capacity);
    let mut extras: Vec<Vec<f64>> = layout
        .extras
        .iter()
        .map(|_| Vec::with_capacity(capacity))
        .collect();
    let [x, y, z] = layout.xyz;
    payload.records(def, |_, record: VertexRecord| {
        let values = record.0;
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

fn read_faces(
    payload: &mut Payload<'_, '_>,
    def: &ElementDef,
    vertex_count: usize,
    triangles: &mut Vec<[u32; 3]>,
) -> Result<()> {
    triangles.reserve(payload.capacity(def));
    let mut scratch = Vec::new();
    payload.records(def, |_, face: FaceRecord| {
        push_polygon(face.corners(), vertex_count, &mut scratch, triangles)
    })
}

/// A record of an element the reader does not use.
struct Skipped;

impl PropertyAccess for Skipped {
    fn new() -> Self {
        Skipped
    }
}

/// The scalar values of a vertex record, in header order, as `f64`. List properties
/// are ignored.
struct VertexRecord(Vec<f64>);

impl PropertyAccess for VertexRecord {
    fn new() -> Self {
        VertexRecord(Vec::with_capacity(8))
    }
    fn set_char(&mut self, _: &str, value: i8) -> PropertyAccessResult {
        self.push(value)
    }
    fn set_uchar(&mut self, _: &str, value: u8) -> PropertyAccessResult {
        self.push(value)
    }
    fn set_short(&mut self, _: &str, value: i16) -> PropertyAccessResult {
        self.push(value)
    }
    fn set_ushort(&mut self, _: &str, value: u16) -> PropertyAccessResult {
        self.push(value)
    }
    fn set_int(&mut self, _: &str, value: i32) -> PropertyAccessResult {
        self.push(value)
    }
    fn set_uint(&mut self, _: &str, value: u32) -> PropertyAccessResult {
        self.push(value)
    }
    fn set_float(&mut self, _: &str, value: f32) -> PropertyAccessResult {
        self.push(value)
    }
    fn set_double(&mut self, _: &str, value: f64) -> PropertyAccessResult {
        self.push(value)
    }
}

impl VertexRecord {
    fn push(&mut self, value: impl Into<f64>) -> PropertyAccessResult {
        self.0.push(value.into());
        PropertyAccessResult::Set
    }
}

/// The vertex index list of a face record. `int` and `uint` lists (the usual
/// types) are filled in place; narrower types are widened into `signed`.
#[derive(Default)]
struct FaceRecord {
    signed: Vec<i32>,
    unsigned: Vec<u32>,
}

impl FaceRecord {
    fn corners(&self) -> impl Iterator<Item = i64> + '_ {
        let signed = self.signed.iter().map(|&i| i64::from(i));
        signed.chain(self.unsigned.iter().map(|&i| i64::from(i)))
    }

    fn widen<T: Copy + Into<i32>>(&mut self, name: &str, values: &[T]) -> PropertyAccessResult {
        if !FACE_INDEX_NAMES.contains(&name) {
            return PropertyAccessResult::Ignored;
        }
        self.signed.extend(values.iter().map(|&v| v.into()));
        PropertyAccessResult::Set
    }
}

impl PropertyAccess for FaceRecord {
    fn new() -> Self {
        FaceRecord::default()
    }
    fn begin_list_int(&mut self, name: &str, _: usize) -> BeginList<'_, i32> {
        if FACE_INDEX_NAMES.contains(&name) {
            BeginList::Fill(&mut self.signed)
        } else {
            BeginList::UseSetter
        }
    }
    fn begin_list_uint(&mut self, name: &str, _: usize) -> BeginList<'_, u32> {
        if FACE_INDEX_NAMES.contains(&name) {
            BeginList::Fill(&mut self.unsigned)
        } else {
            BeginList::UseSetter
        }
    }
    fn set_list_char(&mut self, name: &str, values: Vec<i8>) -> PropertyAccessResult {
        self.widen(name, &values)
    }
    fn set_list_uchar(&mut self, name: &str, values: Vec<u8>) -> PropertyAccessResult {
        self.widen(name, &values)
    }
    fn set_list_short(&mut self, name: &str, values: Vec<i16>) -> PropertyAccessResult {
        self.widen(name, &values)
    }
    fn set_list_ushort(&mut self, name: &str, values: Vec<u16>) -> PropertyAccessResult {
        self.widen(name, &values)
    }
}

/// A per-vertex quantity to store in a PLY file next to the positions.
#[derive(Clone, Copy, Debug)]
pub enum VertexAttribute<'a> {
    /// One value per vertex, written as the float property `name`.
    Scalar {
        /// The property name.
        name: &'a str,
        /// One value per vertex.
        values: &'a [f64],
    },
    /// One vector per vertex, written as the float properties `name_x`, `name_y`,
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

    /// Append vertex `v`'s value(s) as little-endian `f32`.
    fn write_vertex(&self, v: usize, w: &mut impl Write) -> std::io::Result<()> {
        match self {
            VertexAttribute::Scalar { values, .. } => write_f32(w, values[v]),
            VertexAttribute::Vector { values, .. } => {
                values[v].iter().try_for_each(|&c| write_f32(w, c))
            }
        }
    }
}

fn write_f32(w: &mut impl Write, value: f64) -> std::io::Result<()> {
    w.write_all(&(value as f32).to_le_bytes())
}

/// Write `mesh` as a binary little-endian PLY file: a `vertex` element with double
/// `x`, `y`, `z` followed by the `attributes` in order (a scalar as one float
/// property, a vector as three), and a `face` element with a
/// `list uchar int vertex_indices`. The file is written atomically.
///
/// Fails with [`Error::Argument`] if an attribute does not have one value per
/// vertex, or its name is empty, contains white space or repeats another property.
pub fn write_ply(path: &Path, mesh: &Mesh, attributes: &[VertexAttribute<'_>]) -> Result<()> {
    write_triangles_ply(path, mesh.positions(), &mesh.triangles(), attributes)
}

/// [`write_ply`] for any indexed triangles (checked by the caller to be in range),
/// orientable or not.
pub(super) fn write_triangles_ply(
    path: &Path,
    positions: &[Point],
    triangles: &[[u32; 3]],
    attributes: &[VertexAttribute<'_>],
) -> Result<()> {
    let header = ply_header(positions.len(), triangles.len(), attributes)?;
    crate::atomic::write_atomically(path, |w| {
        w.write_all(header.as_bytes())?;
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
                // Below i32::MAX: checked by `ply_header`.
                w.write_all(&(v as i32).to_le_bytes())?;
            }
        }
        Ok(())
    })
}

/// The header of [`write_ply`]'s output, after checking the attributes.
fn ply_header(
    vertex_count: usize,
    face_count: usize,
    attributes: &[VertexAttribute<'_>],
) -> Result<String> {
    if i32::try_from(vertex_count).is_err() {
        return Err(Error::Argument(format!(
            "{vertex_count} vertices are too many for PLY int indices"
        )));
    }
    let mut names: Vec<String> = ["x", "y", "z"].map(String::from).to_vec();
    let mut attribute_names = Vec::new();
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
            names.push(property.clone());
            attribute_names.push(property);
        }
    }
    let mut header = format!(
        "ply\nformat binary_little_endian 1.0\ncomment written by crestline\nelement vertex {vertex_count}\n"
    );
    // Positions in double precision, so that a written mesh reads back exactly.
    for name in ["x", "y", "z"] {
        header += &format!("property double {name}\n");
    }
    for name in &attribute_names {
        header += &format!("property float {name}\n");
    }
    header +=
        &format!("element face {face_count}\nproperty list uchar int vertex_indices\nend_header\n");
    Ok(header)
}

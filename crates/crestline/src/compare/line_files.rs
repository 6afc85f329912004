//! Polylines of Wavefront OBJ and legacy VTK files, and the edges of PLY files,
//! as [`super::compare`] takes them: the files the `ridges` and `crest-lines`
//! jobs write, and those of other programs (Blender's, meshio's, VTK's own
//! writers). A line's kind comes from the file where it says one — the OBJ object
//! named `line<i>_<kind>`, the VTK cell scalar or the PLY edge property `kind` (a
//! [`LineKind::code`]) — and is `line` otherwise. The frame is 3D Slicer's
//! `SPACE=` mark in the OBJ's leading comments, the VTK title or the PLY header,
//! if any.

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;
use std::str::SplitAsciiWhitespace;

use super::Features;
use crate::io::read_ply_edges;
use crate::lines::LineKind;
use crate::space::{convert_all, Space};
use crate::{Error, Point, Result};

/// What a file of faces and no lines is told.
const MESH_NOT_LINES: &str = "a mesh (faces and no lines): compare takes the lines \
     or landmarks found on it, e.g. by `crestline ridges`";

/// The segments of a PLY file's `edge` element (as the lines' PLY writer writes
/// them, or any program that writes edges), kinds from its `kind` property, lines
/// counted by its `line` property (each edge a line without it). Errors name the
/// file.
pub fn read_ply_lines(path: &Path) -> Result<Features> {
    let bytes = crate::io::file::read(path)?;
    let ply = read_ply_edges(&bytes).map_err(|e| e.in_file(path))?;
    if ply.faces && ply.edges.is_empty() {
        return Err(file_error(path, MESH_NOT_LINES.into()));
    }
    let mut features = Features {
        declared: ply.space,
        ..Features::default()
    };
    let mut lines: BTreeMap<&str, BTreeSet<u64>> = BTreeMap::new();
    for (index, edge) in ply.edges.iter().enumerate() {
        let kind = edge.kind.map_or(UNNAMED_KIND, kind_of_code);
        let mut ends = edge.ends.map(|v| ply.positions[v]).to_vec();
        convert_all(features.declared, Space::Ras, &mut ends);
        features
            .segments
            .entry(kind.to_string())
            .or_default()
            .push([ends[0], ends[1]]);
        let line = edge.line.map_or(index as u64, |line| line.to_bits());
        lines.entry(kind).or_default().insert(line);
    }
    for (kind, ids) in lines {
        features.line_counts.insert(kind.to_string(), ids.len());
    }
    Ok(features)
}

/// The kind of the code `code` ([`LineKind::code`]), or [`UNNAMED_KIND`].
fn kind_of_code(code: f64) -> &'static str {
    LineKind::ALL
        .iter()
        .find(|kind| f64::from(kind.code()) == code)
        .map_or(UNNAMED_KIND, |kind| kind.name())
}

/// A parsed value, or what is wrong.
type Parsed<T> = std::result::Result<T, String>;

/// The kind of a line whose file does not say one.
pub const UNNAMED_KIND: &str = "line";

/// The polylines of an OBJ file's `l` records (1-based or negative indices,
/// corners such as `7/3` read as their vertex); a record whose last index
/// repeats its first is a closed line. Errors name the file and the line.
pub fn read_obj_lines(path: &Path) -> Result<Features> {
    let text = crate::io::file::read_text(path)?;
    let error = |line: usize, message: String| file_error(path, format!("line {line}: {message}"));
    let mut positions: Vec<Point> = Vec::new();
    let mut kind = UNNAMED_KIND;
    let mut lines: Vec<(&str, Vec<usize>, usize)> = Vec::new();
    let mut faces = false;
    for (number, record) in text.lines().enumerate().map(|(i, r)| (i + 1, r)) {
        let mut tokens = record.split_ascii_whitespace();
        match tokens.next() {
            Some("v") => positions.push(point(&mut tokens).map_err(|m| error(number, m))?),
            Some("o" | "g") => kind = kind_of_object(tokens.next().unwrap_or("")),
            Some("f") => faces = true,
            Some("l") => {
                let indices = tokens
                    .map(|token| obj_index(token, positions.len()))
                    .collect::<Parsed<Vec<_>>>()
                    .map_err(|m| error(number, m))?;
                lines.push((kind, indices, number));
            }
            _ => {}
        }
    }
    if faces && lines.is_empty() {
        return Err(file_error(path, MESH_NOT_LINES.into()));
    }
    let mut features = Features {
        declared: Space::from_header(&leading_comments(&text)),
        ..Features::default()
    };
    for (kind, indices, number) in lines {
        let points = points_of(&indices, &positions).map_err(|m| error(number, m))?;
        add_polyline(&mut features, kind, &indices, points);
    }
    Ok(features)
}

/// The polylines of a legacy ASCII VTK file of poly data or an unstructured grid
/// (versions 2 to 5.1: cells as counted index lists or as `OFFSETS` and
/// `CONNECTIVITY`), with the kinds of a `CELL_DATA` scalar or field array `kind`
/// if there is one. Errors name the file.
pub fn read_vtk_lines(path: &Path) -> Result<Features> {
    let text = crate::io::file::read_text(path)?;
    let bad = |message: String| file_error(path, message);
    let mut rows = text.lines();
    let version = rows.next().unwrap_or("");
    if !version.starts_with("# vtk DataFile") {
        return Err(bad(
            "not a legacy VTK file (no `# vtk DataFile` line)".into()
        ));
    }
    let title = rows.next().unwrap_or("");
    if rows.next().map(str::trim) != Some("ASCII") {
        return Err(bad("only ASCII legacy VTK files are read".into()));
    }
    let body: String = rows.collect::<Vec<_>>().join("\n");
    let parsed = VtkLines::parse(&mut body.split_ascii_whitespace()).map_err(bad)?;
    if parsed.polygons && parsed.lines.is_empty() {
        return Err(bad(MESH_NOT_LINES.into()));
    }
    let mut features = Features {
        declared: Space::from_header(title),
        ..Features::default()
    };
    for (cell, indices) in &parsed.lines {
        let kind = parsed
            .kinds
            .as_ref()
            .and_then(|kinds| kinds.get(*cell))
            .map_or(UNNAMED_KIND, |&code| kind_of_code(code));
        let points = points_of(indices, &parsed.points).map_err(bad)?;
        add_polyline(&mut features, kind, indices, points);
    }
    Ok(features)
}

/// What a legacy VTK file holds of its lines.
#[derive(Default)]
struct VtkLines {
    points: Vec<Point>,
    /// The lines, each with its index among all cells (which the cell data
    /// follow: in poly data vertex cells come first).
    lines: Vec<(usize, Vec<usize>)>,
    /// The cells of an unstructured grid, until `CELL_TYPES` tells which are lines.
    grid_cells: Vec<Vec<usize>>,
    /// The number of vertex cells of poly data.
    vertex_cells: usize,
    /// The cell scalar `kind`, if any.
    kinds: Option<Vec<f64>>,
    /// Whether it has polygons, triangle strips or other cells of a surface or a
    /// volume (a mesh).
    polygons: bool,
}

/// The VTK cell types of lines: `VTK_LINE` and `VTK_POLY_LINE`.
const VTK_LINE_TYPES: [usize; 2] = [3, 4];

/// The VTK cell types of points: `VTK_VERTEX` and `VTK_POLY_VERTEX`.
const VTK_VERTEX_TYPES: [usize; 2] = [1, 2];

impl VtkLines {
    /// Reads the sections after the header, keyword by keyword.
    fn parse(tokens: &mut SplitAsciiWhitespace<'_>) -> Parsed<Self> {
        let mut file = VtkLines::default();
        // The section the next data arrays belong to, and how many values they have.
        let mut attached: Option<(bool, usize)> = None;
        while let Some(keyword) = tokens.next() {
            match keyword {
                "DATASET" => {
                    let kind = tokens.next().unwrap_or("");
                    if !matches!(kind, "POLYDATA" | "UNSTRUCTURED_GRID") {
                        return Err(format!(
                            "a {kind} data set, not POLYDATA or UNSTRUCTURED_GRID"
                        ));
                    }
                }
                "POINTS" => {
                    let n = count(tokens, "POINTS")?;
                    tokens.next(); // The value type.
                    file.points = (0..n).map(|_| point(tokens)).collect::<Parsed<_>>()?;
                }
                "VERTICES" | "LINES" | "POLYGONS" | "TRIANGLE_STRIPS" => {
                    let cells = cells(tokens, keyword)?;
                    match keyword {
                        "VERTICES" => file.vertex_cells = cells.len(),
                        "LINES" => {
                            let first = file.vertex_cells;
                            file.lines = cells
                                .into_iter()
                                .enumerate()
                                .map(|(i, c)| (first + i, c))
                                .collect();
                        }
                        _ => file.polygons |= !cells.is_empty(),
                    }
                }
                "CELLS" => file.grid_cells = cells(tokens, keyword)?,
                "CELL_TYPES" => {
                    let n = count(tokens, keyword)?;
                    let types = numbers(tokens, n)?;
                    file.take_grid_lines(&types)?;
                }
                "CELL_DATA" => attached = Some((true, count(tokens, keyword)?)),
                "POINT_DATA" => attached = Some((false, count(tokens, keyword)?)),
                "SCALARS" => {
                    let (cells, n) = attached.ok_or("SCALARS before CELL_DATA or POINT_DATA")?;
                    let name = tokens.next().unwrap_or("");
                    let values = scalars(tokens, n)?;
                    if cells && name == "kind" {
                        file.kinds = Some(values);
                    }
                }
                "VECTORS" | "NORMALS" => {
                    let (_, n) = attached.ok_or("VECTORS before CELL_DATA or POINT_DATA")?;
                    tokens.next(); // The name.
                    tokens.next(); // The value type.
                    let total = n.checked_mul(3).ok_or("too many values")?;
                    for _ in 0..total {
                        number::<f64>(tokens)?;
                    }
                }
                "FIELD" => {
                    tokens.next(); // The field's name.
                    for _ in 0..count(tokens, keyword)? {
                        let (name, values) = field_array(tokens)?;
                        if matches!(attached, Some((true, _))) && name == "kind" {
                            file.kinds = Some(values);
                        }
                    }
                }
                "METADATA" | "INFORMATION" | "NAME" | "DATA" => {
                    return Err(format!(
                        "the section {keyword} is not read; write the file without metadata"
                    ));
                }
                other => return Err(format!("unexpected `{other}`")),
            }
        }
        Ok(file)
    }
}

impl VtkLines {
    /// The lines among the unstructured grid's cells, by their `types`.
    fn take_grid_lines(&mut self, types: &[usize]) -> Parsed<()> {
        if types.len() != self.grid_cells.len() {
            return Err(format!(
                "{} cell types for {} cells",
                types.len(),
                self.grid_cells.len()
            ));
        }
        let cells = std::mem::take(&mut self.grid_cells);
        for (index, (cell, cell_type)) in cells.into_iter().zip(types).enumerate() {
            if VTK_LINE_TYPES.contains(cell_type) {
                self.lines.push((index, cell));
            } else if !VTK_VERTEX_TYPES.contains(cell_type) {
                self.polygons = true;
            }
        }
        Ok(())
    }
}

/// The cells after `VERTICES|LINES|... n size`: `size` counted index lists, or
/// (version 5.1) `OFFSETS` and `CONNECTIVITY` arrays.
fn cells(tokens: &mut SplitAsciiWhitespace<'_>, keyword: &str) -> Parsed<Vec<Vec<usize>>> {
    let first = count(tokens, keyword)?;
    let size = count(tokens, keyword)?;
    let mut peek = tokens.clone();
    if peek.next() == Some("OFFSETS") {
        tokens.next();
        tokens.next(); // The offsets' type.
        let offsets = numbers(tokens, first)?;
        if tokens.next() != Some("CONNECTIVITY") {
            return Err(format!("{keyword}: OFFSETS without CONNECTIVITY"));
        }
        tokens.next();
        let connectivity = numbers(tokens, size)?;
        let cell = |w: &[usize]| connectivity.get(w[0]..w[1]).map(<[usize]>::to_vec);
        return offsets
            .windows(2)
            .map(|w| cell(w).ok_or_else(|| format!("{keyword}: an offset beyond the connectivity")))
            .collect();
    }
    let mut all = Vec::new();
    for _ in 0..first {
        let length = count(tokens, keyword)?;
        all.push(numbers(tokens, length)?);
    }
    Ok(all)
}

/// `n` values of a `SCALARS name type [components]` array (one component is
/// read), after its optional `LOOKUP_TABLE` line.
fn scalars(tokens: &mut SplitAsciiWhitespace<'_>, n: usize) -> Parsed<Vec<f64>> {
    tokens.next(); // The value type.
    let mut peek = tokens.clone();
    let components = match peek.next() {
        Some("LOOKUP_TABLE") => 1,
        Some(c) => {
            tokens.next();
            c.parse::<usize>()
                .map_err(|_| format!("`{c}` is not a component count"))?
        }
        None => 1,
    };
    if tokens.clone().next() == Some("LOOKUP_TABLE") {
        tokens.next();
        tokens.next();
    }
    let total = n.checked_mul(components).ok_or("too many values")?;
    let values = (0..total)
        .map(|_| number::<f64>(tokens))
        .collect::<Parsed<Vec<_>>>()?;
    Ok(values.into_iter().step_by(components.max(1)).collect())
}

/// One array of a `FIELD` section, `name components tuples type` and its values:
/// its name and the first component of every tuple.
fn field_array(tokens: &mut SplitAsciiWhitespace<'_>) -> Parsed<(String, Vec<f64>)> {
    let name = tokens.next().ok_or("the file ends early")?.to_string();
    let components = count(tokens, "FIELD")?.max(1);
    let tuples = count(tokens, "FIELD")?;
    tokens.next(); // The value type.
    let total = tuples.checked_mul(components).ok_or("too many values")?;
    let values = (0..total)
        .map(|_| number::<f64>(tokens))
        .collect::<Parsed<Vec<_>>>()?;
    Ok((name, values.into_iter().step_by(components).collect()))
}

/// Adds the line through `points` (of `indices`) to `features`, in RAS if the
/// file states its frame, closed when its last index repeats its first.
fn add_polyline(features: &mut Features, kind: &str, indices: &[usize], mut points: Vec<Point>) {
    let closed = indices.len() > 2 && indices.first() == indices.last();
    if closed {
        points.pop();
    }
    convert_all(features.declared, Space::Ras, &mut points);
    if points.len() >= 2 {
        features.add_line(kind, &points, closed);
    }
}

/// The points of `indices` among `positions`.
fn points_of(indices: &[usize], positions: &[Point]) -> Parsed<Vec<Point>> {
    indices
        .iter()
        .map(|&i| {
            positions.get(i).copied().ok_or_else(|| {
                format!(
                    "a line refers to point {}, but there are {}",
                    i + 1,
                    positions.len()
                )
            })
        })
        .collect()
}

/// The kind named by an OBJ object `line<i>_<kind>` (the `ridges` job's), or
/// [`UNNAMED_KIND`].
fn kind_of_object(name: &str) -> &'static str {
    let suffix = name.rsplit('_').next().unwrap_or("");
    LineKind::ALL
        .iter()
        .find(|kind| kind.name() == suffix)
        .map_or(UNNAMED_KIND, |kind| kind.name())
}

/// The 0-based vertex of an OBJ `l` corner (`7`, `7/3`, `-1`), with `defined`
/// vertices read so far.
fn obj_index(token: &str, defined: usize) -> Parsed<usize> {
    let vertex = token.split('/').next().unwrap_or("");
    let bad = || format!("`{token}` is not a vertex index");
    let index: i64 = vertex.parse().map_err(|_| bad())?;
    match index {
        0 => Err(bad()),
        i if i > 0 => Ok(i as usize - 1),
        i => usize::try_from((defined as i64).saturating_add(i)).map_err(|_| {
            format!("`{token}` refers before the first vertex ({defined} defined so far)")
        }),
    }
}

/// The comments at the head of a file, where a frame mark is looked for.
fn leading_comments(text: &str) -> String {
    let comments: Vec<&str> = text.lines().take_while(|l| l.starts_with('#')).collect();
    comments.join("\n")
}

/// Three finite coordinates.
fn point(tokens: &mut SplitAsciiWhitespace<'_>) -> Parsed<Point> {
    let mut coordinate = || {
        let value: f64 = number(tokens)?;
        match value.is_finite() {
            true => Ok(value),
            false => Err(format!("the coordinate {value} is not finite")),
        }
    };
    Ok(Point::new(coordinate()?, coordinate()?, coordinate()?))
}

/// `n` indices.
fn numbers(tokens: &mut SplitAsciiWhitespace<'_>, n: usize) -> Parsed<Vec<usize>> {
    (0..n).map(|_| number::<usize>(tokens)).collect()
}

/// A count after `keyword`.
fn count(tokens: &mut SplitAsciiWhitespace<'_>, keyword: &str) -> Parsed<usize> {
    number::<usize>(tokens).map_err(|m| format!("{keyword}: {m}"))
}

/// The next token as a number of type `T`.
fn number<T: std::str::FromStr>(tokens: &mut SplitAsciiWhitespace<'_>) -> Parsed<T> {
    let token = tokens.next().ok_or("the file ends early")?;
    token
        .parse::<T>()
        .map_err(|_| format!("`{token}` is not a number here"))
}

fn file_error(path: &Path, message: String) -> Error {
    Error::File {
        path: path.to_path_buf(),
        message,
    }
}

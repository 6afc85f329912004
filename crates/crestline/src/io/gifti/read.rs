//! Reading GIfTI files: surfaces (`.surf.gii`: a `NIFTI_INTENT_POINTSET` and a
//! `NIFTI_INTENT_TRIANGLE` array) and per-vertex values (`.shape.gii`,
//! `.func.gii`: the first array), as the GIfTI 1.0 spec lays them out.
//!
//! Every error says which `DataArray` (0-based, in file order) is wrong.

use roxmltree::{Document, Node, ParsingOptions};

use super::encoding::{decode, DataType, Encoding, Layout};
use super::{POINTSET, TRIANGLE};
use crate::io::Input;
use crate::mesh::TriangleSoup;
use crate::{Error, Point, Result, Space};

/// One `DataArray` element, its attributes checked.
struct DataArray<'a, 'input> {
    index: usize,
    intent: &'a str,
    dims: Vec<usize>,
    layout: Layout,
    column_major: bool,
    node: Node<'a, 'input>,
}

impl DataArray<'_, '_> {
    /// An error about this array.
    fn error(&self, message: impl std::fmt::Display) -> Error {
        array_error(self.index, message)
    }

    /// The numbers, row-major (a column-major 2-D array is transposed).
    fn values(&self) -> Result<Vec<f64>> {
        let text = self
            .node
            .children()
            .find(|n| n.has_tag_name("Data"))
            .map(|n| n.text().unwrap_or(""))
            .ok_or_else(|| self.error("no Data element"))?;
        let values = decode(text, &self.layout).map_err(|m| self.error(m))?;
        match (self.column_major, self.dims.as_slice()) {
            (true, &[rows, columns]) if columns > 1 => {
                let mut transposed = self.reserve(values.len())?;
                transposed.extend(
                    (0..rows * columns).map(|k| values[(k % columns) * rows + k / columns]),
                );
                Ok(transposed)
            }
            _ => Ok(values),
        }
    }

    /// Room for `count` values of `T` made from this array's numbers, reserved
    /// fallibly ([`crate::io::file::reserve`]).
    fn reserve<T>(&self, count: usize) -> Result<Vec<T>> {
        crate::io::file::reserve(count, "values").map_err(|e| self.error(e))
    }

    /// The rows of an `n` × 3 array.
    fn triples(&self, what: &str) -> Result<Vec<[f64; 3]>> {
        if self.dims.len() != 2 || self.dims[1] != 3 {
            return Err(self.error(format!(
                "{what} must be an N x 3 array, not {}",
                shape(&self.dims)
            )));
        }
        let values = self.values()?;
        let mut rows = self.reserve(values.len() / 3)?;
        rows.extend(values.chunks_exact(3).map(|r| [r[0], r[1], r[2]]));
        Ok(rows)
    }
}

/// An error about `DataArray` `index`.
fn array_error(index: usize, message: impl std::fmt::Display) -> Error {
    Error::Parse(format!("DataArray {index}: {message}"))
}

/// Dimensions as `N x M`.
fn shape(dims: &[usize]) -> String {
    let dims: Vec<String> = dims.iter().map(usize::to_string).collect();
    dims.join(" x ")
}

/// Parse the XML of a GIfTI file (a `DOCTYPE` allowed, as nibabel writes one),
/// after refusing elements with absurdly many attributes, which the parser checks
/// for duplicates in quadratic time ([`crate::xml::check_attribute_counts`]).
fn document(text: &str) -> Result<Document<'_>> {
    crate::xml::check_attribute_counts(text).map_err(Error::Parse)?;
    let options = ParsingOptions {
        allow_dtd: true,
        ..ParsingOptions::default()
    };
    let document = Document::parse_with_options(text, options)
        .map_err(|e| Error::Parse(format!("not well-formed XML ({e})")))?;
    if !document.root_element().has_tag_name("GIFTI") {
        return Err(Error::Parse(
            "not a GIfTI file (no GIFTI root element)".into(),
        ));
    }
    Ok(document)
}

/// The `DataArray` elements of `document`, their attributes checked.
fn data_arrays<'a, 'input>(document: &'a Document<'input>) -> Result<Vec<DataArray<'a, 'input>>> {
    document
        .root_element()
        .children()
        .filter(|n| n.has_tag_name("DataArray"))
        .enumerate()
        .map(|(index, node)| data_array(index, node))
        .collect()
}

/// Check the attributes of `DataArray` `index`.
fn data_array<'a, 'input>(index: usize, node: Node<'a, 'input>) -> Result<DataArray<'a, 'input>> {
    let error = |message: String| array_error(index, message);
    let attribute = |name: &str| {
        node.attribute(name)
            .ok_or_else(|| error(format!("no {name} attribute")))
    };
    let dimensionality: usize = attribute("Dimensionality")?
        .trim()
        .parse()
        .ok()
        .filter(|d| (1..=6).contains(d))
        .ok_or_else(|| error("Dimensionality is not a number from 1 to 6".into()))?;
    let dims = (0..dimensionality)
        .map(|i| {
            attribute(&format!("Dim{i}"))?
                .trim()
                .parse::<usize>()
                .map_err(|_| error(format!("Dim{i} is not a count")))
        })
        .collect::<Result<Vec<usize>>>()?;
    let count = dims
        .iter()
        .try_fold(1usize, |n, &d| n.checked_mul(d))
        .ok_or_else(|| error(format!("absurd dimensions {}", shape(&dims))))?;
    let layout = Layout {
        data_type: DataType::from_name(attribute("DataType")?).map_err(error)?,
        encoding: Encoding::from_name(attribute("Encoding")?).map_err(error)?,
        // Without an `Endian`, the byte order of the machines that write GIfTI.
        little_endian: node.attribute("Endian") != Some("BigEndian"),
        count,
    };
    let column_major = match node.attribute("ArrayIndexingOrder") {
        Some("ColumnMajorOrder") => true,
        Some("RowMajorOrder") | None => false,
        Some(other) => return Err(error(format!("unknown ArrayIndexingOrder '{other}'"))),
    };
    Ok(DataArray {
        index,
        intent: attribute("Intent")?,
        dims,
        layout,
        column_major,
        node,
    })
}

/// The text of a GIfTI file.
fn text<'a>(input: &Input<'a>) -> Result<&'a str> {
    std::str::from_utf8(input.rest())
        .map_err(|_| Error::Parse("not text (a GIfTI file is XML)".into()))
}

/// Parse a GIfTI surface; the [`crate::io::read_mesh`] reader of `.gii` files.
/// Its points are declared RAS: the GIfTI spec's coordinates are RAS
/// millimetres whichever `DataSpace` names them.
pub(in crate::io) fn parse_surface(input: &mut Input<'_>) -> Result<TriangleSoup> {
    let document = document(text(input)?)?;
    let arrays = data_arrays(&document)?;
    let find = |intent: &str| {
        arrays.iter().find(|a| a.intent == intent).ok_or_else(|| {
            let found: Vec<&str> = arrays.iter().map(|a| a.intent).collect();
            Error::Parse(format!(
                "no {intent} DataArray, so not a surface (the arrays are: {})",
                if found.is_empty() {
                    "none".to_string()
                } else {
                    found.join(", ")
                }
            ))
        })
    };
    let points = find(POINTSET)?;
    let triangles = find(TRIANGLE)?;
    if points.layout.data_type != DataType::Float32 {
        return Err(points.error("the coordinates must be NIFTI_TYPE_FLOAT32"));
    }
    let positions: Vec<Point> = points
        .triples("a point set")?
        .into_iter()
        .map(Point::from)
        .collect();
    let n = positions.len();
    let corners = triangles.triples("a triangle array")?;
    let mut triangles_out = triangles.reserve(corners.len())?;
    for (f, t) in corners.iter().enumerate() {
        let index = |v: f64| {
            (v >= 0.0 && v < n as f64 && v.fract() == 0.0)
                .then_some(v as u32)
                .ok_or_else(|| {
                    triangles.error(format!(
                        "triangle {f} refers to vertex {v}, out of range (the point set has {n})"
                    ))
                })
        };
        triangles_out.push([index(t[0])?, index(t[1])?, index(t[2])?]);
    }
    Ok(TriangleSoup {
        positions,
        triangles: triangles_out,
        space: Some(Space::Ras),
        ..TriangleSoup::default()
    })
}

/// The per-vertex values of a GIfTI file: its first `DataArray`, which must be a
/// vector (`N` or `N x 1`) and not a point set or triangles.
pub(crate) fn parse_values(bytes: &[u8]) -> Result<Vec<f64>> {
    let input = Input::new(bytes, None);
    let document = document(text(&input)?)?;
    let arrays = data_arrays(&document)?;
    let first = arrays
        .first()
        .ok_or_else(|| Error::Parse("no DataArray".into()))?;
    if first.intent == POINTSET || first.intent == TRIANGLE {
        return Err(first.error(format!(
            "a surface's {} array, not per-vertex values",
            first.intent
        )));
    }
    match first.dims.as_slice() {
        [_] | [_, 1] => first.values(),
        dims => Err(first.error(format!(
            "per-vertex values must be a vector, not {}",
            shape(dims)
        ))),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn gifti(arrays: &str) -> String {
        format!(
            "<?xml version=\"1.0\"?>\n<!DOCTYPE GIFTI SYSTEM \"http://www.nitrc.org/frs/download.php/115/gifti.dtd\">\n\
             <GIFTI Version=\"1.0\" NumberOfDataArrays=\"2\">{arrays}</GIFTI>"
        )
    }

    fn array(intent: &str, data_type: &str, dims: &[usize], order: &str, data: &str) -> String {
        let dim_attributes: String = dims
            .iter()
            .enumerate()
            .map(|(i, d)| format!(" Dim{i}=\"{d}\""))
            .collect();
        format!(
            "<DataArray Intent=\"{intent}\" DataType=\"{data_type}\" ArrayIndexingOrder=\"{order}\" \
             Dimensionality=\"{}\"{dim_attributes} Encoding=\"ASCII\" Endian=\"LittleEndian\" \
             ExternalFileName=\"\" ExternalFileOffset=\"\"><Data>{data}</Data></DataArray>",
            dims.len()
        )
    }

    fn surface(points_order: &str, points: &str) -> String {
        gifti(
            &(array(
                POINTSET,
                "NIFTI_TYPE_FLOAT32",
                &[3, 3],
                points_order,
                points,
            ) + &array(
                TRIANGLE,
                "NIFTI_TYPE_INT32",
                &[1, 3],
                "RowMajorOrder",
                "0 1 2",
            )),
        )
    }

    fn read(text: &str) -> Result<TriangleSoup> {
        parse_surface(&mut Input::new(text.as_bytes(), None))
    }

    #[test]
    fn row_and_column_major_surfaces_read_alike() {
        let rows = read(&surface("RowMajorOrder", "0 0 0 1 0 0 0 1 0")).unwrap();
        let columns = read(&surface("ColumnMajorOrder", "0 1 0 0 0 1 0 0 0")).unwrap();
        assert_eq!(rows.positions, columns.positions);
        assert_eq!(rows.positions[2], Point::new(0.0, 1.0, 0.0));
        assert_eq!(rows.triangles, vec![[0, 1, 2]]);
        assert_eq!(rows.space, Some(Space::Ras));
    }

    #[test]
    fn malformed_surfaces_name_the_array() {
        let message = |text: &str| read(text).unwrap_err().to_string();
        assert!(message(&surface("RowMajorOrder", "0 0 0 1 0 0 0 1")).starts_with("DataArray 0:"));
        let bad_index = gifti(
            &(array(
                POINTSET,
                "NIFTI_TYPE_FLOAT32",
                &[3, 3],
                "RowMajorOrder",
                "0 0 0 1 0 0 0 1 0",
            ) + &array(
                TRIANGLE,
                "NIFTI_TYPE_INT32",
                &[1, 3],
                "RowMajorOrder",
                "0 1 3",
            )),
        );
        assert!(message(&bad_index).contains("DataArray 1: triangle 0 refers to vertex 3"));
        let values_only = gifti(&array(
            "NIFTI_INTENT_SHAPE",
            "NIFTI_TYPE_FLOAT32",
            &[2],
            "RowMajorOrder",
            "1 2",
        ));
        assert!(message(&values_only).contains("no NIFTI_INTENT_POINTSET DataArray"));
        assert!(message("<GIFTI><DataArray").contains("XML"));
        assert!(message("<html/>").contains("not a GIfTI file"));
        let odd = surface("Diagonal", "0 0 0 1 0 0 0 1 0");
        assert!(message(&odd).contains("ArrayIndexingOrder"));
    }

    #[test]
    fn values_are_the_first_array() {
        let shape = gifti(&array(
            "NIFTI_INTENT_SHAPE",
            "NIFTI_TYPE_FLOAT32",
            &[3, 1],
            "RowMajorOrder",
            "1 -2 0.5",
        ));
        assert_eq!(parse_values(shape.as_bytes()).unwrap(), [1.0, -2.0, 0.5]);
        let matrix = gifti(&array(
            "NIFTI_INTENT_NONE",
            "NIFTI_TYPE_FLOAT32",
            &[2, 2],
            "RowMajorOrder",
            "1 2 3 4",
        ));
        assert!(parse_values(matrix.as_bytes())
            .unwrap_err()
            .to_string()
            .contains("vector"));
        let surface = surface("RowMajorOrder", "0 0 0 1 0 0 0 1 0");
        assert!(parse_values(surface.as_bytes())
            .unwrap_err()
            .to_string()
            .contains("not per-vertex"));
    }
}

//! Writing GIfTI files (GIfTI 1.0 spec): surfaces, per-vertex values and labels,
//! each array `GZipBase64Binary`, little-endian, row-major, as nibabel and
//! Connectome Workbench write them.

use std::io::Write;
use std::path::Path;

use super::encoding::{encode, DataType};
use super::{POINTSET, TRIANGLE};
use crate::atomic::write_atomically;
use crate::io::fits_f32;
use crate::xml::escape;
use crate::{Error, Point, Result, Space};

/// Metadata entries (`MD` elements): name and value.
pub type Metadata<'a> = [(&'a str, &'a str)];

/// One entry of a label file's `LabelTable`.
#[derive(Clone, Debug, PartialEq)]
pub struct GiftiLabel {
    /// The value vertices of this label hold.
    pub key: i32,
    /// The label's name.
    pub name: String,
    /// Red, green, blue and opacity, from 0 to 1.
    pub rgba: [f32; 4],
}

/// A `DataArray` to write.
struct ArrayOut<'a> {
    intent: &'a str,
    data_type: DataType,
    dims: Vec<usize>,
    metadata: &'a Metadata<'a>,
    /// The space of a point set's coordinates (`NIFTI_XFORM_SCANNER_ANAT`,
    /// `NIFTI_XFORM_UNKNOWN`), stated as its coordinate system.
    space: Option<&'a str>,
    /// The numbers, little-endian.
    bytes: Vec<u8>,
}

/// Write a surface: `positions` as a `NIFTI_INTENT_POINTSET` array with
/// `metadata` (Connectome Workbench reads `AnatomicalStructurePrimary` and
/// `GeometricType` there), and `triangles` as a `NIFTI_INTENT_TRIANGLE` array.
/// Positions in a known `frame` are written in RAS (GIfTI's frame; LPS is
/// converted) in the scanner's space (`NIFTI_XFORM_SCANNER_ANAT`); without one
/// they are written as they are, in an unknown space (`NIFTI_XFORM_UNKNOWN`).
/// Written atomically.
///
/// Errors ([`Error::File`] naming `path`): a coordinate that is not a finite
/// 32-bit float.
pub fn write_gifti_surface(
    path: &Path,
    (positions, frame): (&[Point], Option<Space>),
    triangles: &[[u32; 3]],
    metadata: &Metadata<'_>,
) -> Result<()> {
    if let Some(v) = positions
        .iter()
        .position(|p| !p.iter().all(|&c| fits_f32(c)))
    {
        return Err(Error::File {
            path: path.to_path_buf(),
            message: format!("vertex {v} has a coordinate that is not a finite 32-bit float"),
        });
    }
    let ras = positions
        .iter()
        .map(|p| frame.map_or(*p, |frame| frame.to_ras(p)));
    let points = ArrayOut {
        intent: POINTSET,
        data_type: DataType::Float32,
        dims: vec![positions.len(), 3],
        metadata,
        space: Some(if frame.is_some() {
            "NIFTI_XFORM_SCANNER_ANAT"
        } else {
            "NIFTI_XFORM_UNKNOWN"
        }),
        bytes: f32_bytes(ras.flat_map(|p| [p.x, p.y, p.z])),
    };
    let faces = ArrayOut {
        intent: TRIANGLE,
        data_type: DataType::Int32,
        dims: vec![triangles.len(), 3],
        metadata: &[],
        space: None,
        bytes: triangles
            .iter()
            .flatten()
            .flat_map(|&v| (v as i32).to_le_bytes())
            .collect(),
    };
    write_gifti(path, &[], None, &[points, faces])
}

/// Write per-vertex values as one float32 `intent` array (`NIFTI_INTENT_SHAPE`
/// for a `.shape.gii`, `NIFTI_INTENT_NONE` for a `.func.gii`) with
/// `array_metadata` (its `Name`, ...), and `file_metadata`. NaN stays NaN.
/// Written atomically.
///
/// Errors ([`Error::File`] naming `path`): a finite value too large for a 32-bit
/// float.
pub fn write_gifti_values(
    path: &Path,
    values: &[f64],
    intent: &str,
    array_metadata: &Metadata<'_>,
    file_metadata: &Metadata<'_>,
) -> Result<()> {
    if let Some(v) = values.iter().position(|&x| x.is_finite() && !fits_f32(x)) {
        return Err(Error::File {
            path: path.to_path_buf(),
            message: format!(
                "the value of vertex {v} ({}) is too large for a 32-bit float",
                values[v]
            ),
        });
    }
    let array = ArrayOut {
        intent,
        data_type: DataType::Float32,
        dims: vec![values.len()],
        metadata: array_metadata,
        space: None,
        bytes: f32_bytes(values.iter().copied()),
    };
    write_gifti(path, file_metadata, None, &[array])
}

/// Write per-vertex labels (`.label.gii`): one int32 `NIFTI_INTENT_LABEL` array
/// of the keys of `table`, with `file_metadata`. Written atomically.
pub fn write_gifti_labels(
    path: &Path,
    labels: &[i32],
    table: &[GiftiLabel],
    array_metadata: &Metadata<'_>,
    file_metadata: &Metadata<'_>,
) -> Result<()> {
    let array = ArrayOut {
        intent: "NIFTI_INTENT_LABEL",
        data_type: DataType::Int32,
        dims: vec![labels.len()],
        metadata: array_metadata,
        space: None,
        bytes: labels.iter().flat_map(|k| k.to_le_bytes()).collect(),
    };
    write_gifti(path, file_metadata, Some(table), &[array])
}

/// Numbers as little-endian f32 bytes.
fn f32_bytes(values: impl Iterator<Item = f64>) -> Vec<u8> {
    values.flat_map(|x| (x as f32).to_le_bytes()).collect()
}

/// Write the document: the file's metadata, its label table and the arrays.
fn write_gifti(
    path: &Path,
    metadata: &Metadata<'_>,
    table: Option<&[GiftiLabel]>,
    arrays: &[ArrayOut<'_>],
) -> Result<()> {
    write_atomically(path, |w| {
        writeln!(w, "<?xml version=\"1.0\" encoding=\"UTF-8\"?>")?;
        writeln!(
            w,
            "<!DOCTYPE GIFTI SYSTEM \"http://www.nitrc.org/frs/download.php/115/gifti.dtd\">"
        )?;
        writeln!(
            w,
            "<GIFTI Version=\"1.0\" NumberOfDataArrays=\"{}\">",
            arrays.len()
        )?;
        write_metadata(w, metadata, "  ")?;
        write_label_table(w, table.unwrap_or_default())?;
        for array in arrays {
            write_array(w, array)?;
        }
        writeln!(w, "</GIFTI>")
    })
}

/// A `MetaData` element.
fn write_metadata(
    w: &mut impl Write,
    metadata: &Metadata<'_>,
    indent: &str,
) -> std::io::Result<()> {
    writeln!(w, "{indent}<MetaData>")?;
    for (name, value) in metadata {
        writeln!(
            w,
            "{indent}  <MD><Name>{}</Name><Value>{}</Value></MD>",
            escape(name),
            escape(value)
        )?;
    }
    writeln!(w, "{indent}</MetaData>")
}

/// A `LabelTable` element.
fn write_label_table(w: &mut impl Write, table: &[GiftiLabel]) -> std::io::Result<()> {
    writeln!(w, "  <LabelTable>")?;
    for label in table {
        let [r, g, b, a] = label.rgba;
        writeln!(
            w,
            "    <Label Key=\"{}\" Red=\"{r}\" Green=\"{g}\" Blue=\"{b}\" Alpha=\"{a}\">{}</Label>",
            label.key,
            escape(&label.name)
        )?;
    }
    writeln!(w, "  </LabelTable>")
}

/// A `DataArray` element.
fn write_array(w: &mut impl Write, array: &ArrayOut<'_>) -> std::io::Result<()> {
    let dims: String = array
        .dims
        .iter()
        .enumerate()
        .map(|(i, d)| format!(" Dim{i}=\"{d}\""))
        .collect();
    writeln!(
        w,
        "  <DataArray Intent=\"{}\" DataType=\"{}\" ArrayIndexingOrder=\"RowMajorOrder\" \
         Dimensionality=\"{}\"{dims} Encoding=\"GZipBase64Binary\" Endian=\"LittleEndian\" \
         ExternalFileName=\"\" ExternalFileOffset=\"\">",
        array.intent,
        array.data_type.name(),
        array.dims.len()
    )?;
    write_metadata(w, array.metadata, "    ")?;
    if let Some(space) = array.space {
        writeln!(w, "    <CoordinateSystemTransformMatrix>")?;
        writeln!(w, "      <DataSpace>{space}</DataSpace>")?;
        writeln!(w, "      <TransformedSpace>{space}</TransformedSpace>")?;
        writeln!(
            w,
            "      <MatrixData>1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1</MatrixData>"
        )?;
        writeln!(w, "    </CoordinateSystemTransformMatrix>")?;
    }
    writeln!(w, "    <Data>{}</Data>", encode(&array.bytes))?;
    writeln!(w, "  </DataArray>")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::io::gifti::read::{parse_surface, parse_values};
    use crate::io::Input;

    #[test]
    fn written_files_read_back() {
        let dir = tempfile::tempdir().unwrap();
        let surface = dir.path().join("s.surf.gii");
        let positions = [
            Point::new(0.0, 0.0, 0.0),
            Point::new(1.5, 0.0, 0.0),
            Point::new(0.0, -2.25, 1.0),
        ];
        let metadata = [("AnatomicalStructurePrimary", "CortexLeft")];
        write_gifti_surface(&surface, (&positions, None), &[[0, 1, 2]], &metadata).unwrap();
        let bytes = std::fs::read(&surface).unwrap();
        let soup = parse_surface(&mut Input::new(&bytes, None)).unwrap();
        assert_eq!(soup.positions, positions);
        assert_eq!(soup.triangles, vec![[0, 1, 2]]);
        let text = String::from_utf8_lossy(&bytes).into_owned();
        assert!(text.contains("<Value>CortexLeft</Value>"));
        assert!(text.contains("<DataSpace>NIFTI_XFORM_UNKNOWN</DataSpace>"));
        // LPS positions are written in RAS, in the scanner's space.
        write_gifti_surface(&surface, (&positions, Some(Space::Lps)), &[[0, 1, 2]], &[]).unwrap();
        let bytes = std::fs::read(&surface).unwrap();
        let soup = parse_surface(&mut Input::new(&bytes, None)).unwrap();
        assert_eq!(soup.positions[2], Point::new(0.0, 2.25, 1.0));
        assert!(String::from_utf8_lossy(&bytes).contains("NIFTI_XFORM_SCANNER_ANAT"));

        let shape = dir.path().join("s.shape.gii");
        write_gifti_values(
            &shape,
            &[0.5, f64::NAN, -3.0],
            "NIFTI_INTENT_SHAPE",
            &[("Name", "a <b>")],
            &[],
        )
        .unwrap();
        let values = parse_values(&std::fs::read(&shape).unwrap()).unwrap();
        assert_eq!(values[0], 0.5);
        assert!(values[1].is_nan());
        assert!(write_gifti_values(&shape, &[1e300], "NIFTI_INTENT_SHAPE", &[], &[]).is_err());
    }
}

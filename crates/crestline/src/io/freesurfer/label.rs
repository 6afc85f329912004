//! FreeSurfer ASCII label files (`lh.cortex.label`): the vertices of a surface
//! that belong to a region, each with its tkr-RAS position and a value, as
//! FreeSurfer's `LabelWrite` writes them and `LabelRead` and nibabel's
//! `read_label` read them:
//!
//! ```text
//! #!ascii label , from crestline vox2ras=TkReg
//! 2
//! 1021  -31.250  12.500  40.125 1.0000000000
//! 1022  -31.000  13.000  40.250 -1.0000000000
//! ```

use std::io::Write;
use std::path::Path;

use crate::atomic::write_atomically;
use crate::{Error, Point, Result};

/// One line of a label file.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LabelledVertex {
    /// The vertex number on the surface (0-based, in the surface file's order).
    pub vertex: u32,
    /// The vertex's position in tkr-RAS (millimetres).
    pub position: Point,
    /// The value FreeSurfer calls the "stat" of the vertex.
    pub value: f64,
}

/// Write an ASCII label of `vertices` (positions in tkr-RAS, as the first line
/// says). Written atomically.
///
/// Errors ([`Error::File`] naming `path`): a position or value that is not finite.
pub fn write_label(path: &Path, vertices: &[LabelledVertex]) -> Result<()> {
    let finite =
        |v: &LabelledVertex| v.value.is_finite() && v.position.iter().all(|c| c.is_finite());
    if let Some(bad) = vertices.iter().find(|v| !finite(v)) {
        return Err(Error::File {
            path: path.to_path_buf(),
            message: format!(
                "vertex {} has a value or coordinate that is not finite",
                bad.vertex
            ),
        });
    }
    write_atomically(path, |w| {
        writeln!(w, "#!ascii label , from crestline vox2ras=TkReg")?;
        writeln!(w, "{}", vertices.len())?;
        for v in vertices {
            let [x, y, z] = [v.position.x, v.position.y, v.position.z];
            writeln!(w, "{} {x:.3} {y:.3} {z:.3} {:.10}", v.vertex, v.value)?;
        }
        Ok(())
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn labels_are_written_as_freesurfer_reads_them() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("lh.test.label");
        let vertices = [
            LabelledVertex {
                vertex: 7,
                position: Point::new(1.0, -2.5, 3.25),
                value: 1.0,
            },
            LabelledVertex {
                vertex: 12,
                position: Point::new(0.0, 0.0, 0.125),
                value: -1.0,
            },
        ];
        write_label(&path, &vertices).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        assert!(lines[0].starts_with("#!ascii label"));
        assert_eq!(lines[1], "2");
        assert_eq!(lines[2], "7 1.000 -2.500 3.250 1.0000000000");
        assert_eq!(lines[3], "12 0.000 0.000 0.125 -1.0000000000");
        let nan = LabelledVertex {
            value: f64::NAN,
            ..vertices[0]
        };
        assert!(write_label(&path, &[nan]).is_err());
    }
}

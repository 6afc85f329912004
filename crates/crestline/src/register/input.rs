//! Reading a rigid motion back: the JSON files [`super::write_transform`] writes,
//! and ITK transform files (`.tfm`) as ITK, SimpleITK and 3D Slicer write them.
//!
//! Both are returned as the moving → fixed motion in RAS that the JSON file
//! states; an ITK file holds the fixed → moving motion in LPS (see
//! `register/output.rs`), so it is inverted and flipped.

use std::path::Path;

use nalgebra::{Matrix3, Matrix4};
use serde::Deserialize;

use super::output::FORMAT;
use super::transform::RigidTransform;
use super::TransformFormat;
use crate::{Error, Result, Vector};

/// The keys of a transform JSON file that [`read_transform`] reads.
#[derive(Deserialize)]
struct Document {
    format: String,
    matrix: [[f64; 4]; 4],
}

/// [`RigidTransform::read`].
pub(crate) fn read_transform(path: &Path) -> Result<RigidTransform> {
    let format = TransformFormat::from_path(path)?;
    let text = crate::io::file::read_text(path)?;
    let parsed = match format {
        TransformFormat::Json => from_json(&text),
        TransformFormat::Itk => from_itk(&text),
    };
    parsed.map_err(|message| Error::File {
        path: path.to_path_buf(),
        message,
    })
}

/// The motion of a `crestline-transform/1` JSON document.
fn from_json(text: &str) -> std::result::Result<RigidTransform, String> {
    let document: Document =
        serde_json::from_str(text).map_err(|e| format!("not a {FORMAT} JSON file: {e}"))?;
    if document.format != FORMAT {
        return Err(format!("the format is '{}', not {FORMAT}", document.format));
    }
    let matrix = Matrix4::from_fn(|row, column| document.matrix[row][column]);
    RigidTransform::from_matrix4(&matrix).map_err(|e| e.to_string())
}

/// The RAS moving → fixed motion of an ITK transform file's text.
fn from_itk(text: &str) -> std::result::Result<RigidTransform, String> {
    let parameters = numbers_after(text, "Parameters:")?;
    let centre = match numbers_after(text, "FixedParameters:") {
        Ok(centre) => centre,
        Err(_) => vec![0.0; 3],
    };
    let [m0, m1, m2, m3, m4, m5, m6, m7, m8, t0, t1, t2] = parameters[..] else {
        return Err(format!(
            "{} parameters; a 3D affine transform has 12 (the matrix row by row, then the \
             translation)",
            parameters.len()
        ));
    };
    let [c0, c1, c2] = centre[..] else {
        return Err(format!(
            "{} fixed parameters; a 3D affine transform has 3 (its centre)",
            centre.len()
        ));
    };
    let rotation = Matrix3::new(m0, m1, m2, m3, m4, m5, m6, m7, m8);
    let centre = Vector::new(c0, c1, c2);
    let translation = Vector::new(t0, t1, t2) + centre - rotation * centre;
    let mut matrix = Matrix4::identity();
    matrix.fixed_view_mut::<3, 3>(0, 0).copy_from(&rotation);
    matrix.fixed_view_mut::<3, 1>(0, 3).copy_from(&translation);
    let itk = RigidTransform::from_matrix4(&matrix).map_err(|e| e.to_string())?;
    Ok(itk.inverse().flip_xy())
}

/// The numbers on the first line that starts with `key` (`Parameters:`, and not
/// `FixedParameters:` when asking for the former).
fn numbers_after(text: &str, key: &str) -> std::result::Result<Vec<f64>, String> {
    let line = text
        .lines()
        .map(str::trim)
        .find_map(|line| line.strip_prefix(key))
        .ok_or_else(|| format!("no '{key}' line: not an ITK transform file"))?;
    line.split_whitespace()
        .map(|word| {
            word.parse::<f64>()
                .map_err(|_| format!("'{word}' on the '{key}' line is not a number"))
        })
        .collect()
}

impl RigidTransform {
    /// The moving → fixed motion in RAS of the transform file `path`: a `.json` as
    /// [`Registration::write`](super::Registration::write) writes it, or an ITK
    /// `.tfm` holding one transform of 12 parameters (`AffineTransform_double_3_3`,
    /// `MatrixOffsetTransformBase`) whose 3 × 3 part is a rotation (ITK's
    /// `x ↦ M·(x − c) + c + t`, with `c` its fixed parameters).
    ///
    /// Errors are [`Error::File`] naming `path`: an unreadable or malformed file, or a
    /// transform that is not a rigid motion.
    pub fn read(path: &Path) -> Result<RigidTransform> {
        read_transform(path)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::register::output::itk_text;
    use nalgebra::Rotation3;

    fn motion() -> RigidTransform {
        RigidTransform::new(
            Rotation3::from_euler_angles(0.1, -0.2, 0.3),
            Vector::new(4.0, -5.0, 6.0),
        )
    }

    #[test]
    fn itk_text_reads_back_as_the_motion_written() {
        let read = from_itk(&itk_text(&motion())).unwrap();
        assert!((read.to_matrix4() - motion().to_matrix4()).amax() < 1e-12);
    }

    #[test]
    fn an_itk_centre_of_rotation_is_taken_into_account() {
        // The same LPS fixed → moving motion, written about the centre c: t' = t + R·c − c.
        let itk = motion().flip_xy().inverse();
        let centre = Vector::new(10.0, 20.0, -30.0);
        let shifted = itk.translation + itk.rotation * centre - centre;
        let m = itk.rotation.matrix();
        let text = format!(
            "Transform: AffineTransform_double_3_3\nParameters: {} {} {} {} {} {} {} {} {} {} {} {}\n\
             FixedParameters: {} {} {}\n",
            m[(0, 0)], m[(0, 1)], m[(0, 2)], m[(1, 0)], m[(1, 1)], m[(1, 2)], m[(2, 0)],
            m[(2, 1)], m[(2, 2)], shifted.x, shifted.y, shifted.z, centre.x, centre.y, centre.z
        );
        let read = from_itk(&text).unwrap();
        assert!((read.to_matrix4() - motion().to_matrix4()).amax() < 1e-9);
    }

    #[test]
    fn a_scaling_matrix_is_refused() {
        let text = "Parameters: 2 0 0 0 1 0 0 0 1 0 0 0\nFixedParameters: 0 0 0\n";
        assert!(from_itk(text).unwrap_err().contains("rotation"));
    }
}

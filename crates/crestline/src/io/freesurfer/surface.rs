//! FreeSurfer binary triangle surfaces (see the parent module for the layout).
//!
//! The vertices of a surface file are in tkr-RAS, the frame of the image the
//! surface was made from with its centre at the origin. With a valid volume
//! geometry footer the reader places them in the scanner's RAS, where the image
//! and everything else derived from it (NIfTI files, GIfTI surfaces written by
//! `mris_convert`) are; without one it keeps them as written, still a RAS frame.
//! Either way the soup declares [`Space::Ras`] and keeps the footer, and
//! [`write_surface`] writes the tkr-RAS coordinates and the footer back.

#[cfg(test)]
use std::io::Write;
#[cfg(test)]
use std::path::Path;

#[cfg(test)]
use crate::atomic::write_atomically;
#[cfg(test)]
use crate::io::fits_f32;
use crate::io::Input;
use crate::mesh::TriangleSoup;
use crate::{Error, Point, Result, Space};

#[cfg(test)]
use super::footer::footer_bytes;
use super::footer::read_footer;
use super::{count, VolumeGeometry, SURFACE_MAGIC};

/// The "created by" line of the surfaces crestline writes.
#[cfg(test)]
const CREATED_BY: &str = "created by crestline";

/// Bytes of a vertex (three f32) and of a face (three i32).
const RECORD_BYTES: usize = 12;

/// Parse a triangle surface file; the [`crate::io::read_mesh`] reader of files
/// that start with [`SURFACE_MAGIC`].
pub(in crate::io) fn parse(input: &mut Input<'_>) -> Result<TriangleSoup> {
    if input.take(3) != Some(&SURFACE_MAGIC[..]) {
        return Err(Error::Parse(
            "not a FreeSurfer triangle surface (no magic bytes FF FF FE)".into(),
        ));
    }
    skip_line(input, "the 'created by' line")?;
    skip_line(input, "the empty line after the 'created by' line")?;
    let counts = input
        .take(8)
        .ok_or_else(|| Error::Parse("the file ends before the vertex and face counts".into()))?;
    let mut pos = 0;
    let vertex_count = count(super::be_i32(counts, &mut pos).unwrap_or(0), "vertex")?;
    let face_count = count(super::be_i32(counts, &mut pos).unwrap_or(0), "face")?;
    check_size(vertex_count, face_count, input.remaining())?;
    let vertices = input.take(vertex_count * RECORD_BYTES).unwrap_or_default();
    let mut positions: Vec<Point> = vertices
        .chunks_exact(RECORD_BYTES)
        .map(|xyz| Point::from(be_f32s(xyz).map(f64::from)))
        .collect();
    let faces = input.take(face_count * RECORD_BYTES).unwrap_or_default();
    let triangles = faces
        .chunks_exact(RECORD_BYTES)
        .enumerate()
        .map(|(f, corners)| triangle(f, corners, vertex_count))
        .collect::<Result<Vec<_>>>()?;
    let geometry = read_footer(input.rest())?;
    if let Some(map) = geometry.as_ref().and_then(VolumeGeometry::tkr_to_scanner) {
        for p in &mut positions {
            *p = map.transform_point(p);
        }
    }
    Ok(TriangleSoup {
        positions,
        triangles,
        space: Some(Space::Ras),
        volume_geometry: geometry,
        ..TriangleSoup::default()
    })
}

/// Consume the bytes up to and including the next line break.
fn skip_line(input: &mut Input<'_>, what: &str) -> Result<()> {
    let end = input
        .rest()
        .iter()
        .position(|&b| b == b'\n')
        .ok_or_else(|| Error::Parse(format!("the file ends in {what}")))?;
    input.take(end + 1);
    Ok(())
}

/// Check that the vertices and faces the header announces fit in the bytes left.
fn check_size(vertex_count: usize, face_count: usize, remaining: usize) -> Result<()> {
    let needed = vertex_count
        .checked_add(face_count)
        .and_then(|n| n.checked_mul(RECORD_BYTES));
    match needed {
        Some(needed) if needed <= remaining => Ok(()),
        _ => Err(Error::Parse(format!(
            "the header announces {vertex_count} vertices and {face_count} faces, \
             more than the {remaining} bytes that follow hold (truncated file or wrong counts)"
        ))),
    }
}

/// Three big-endian f32.
fn be_f32s(bytes: &[u8]) -> [f32; 3] {
    std::array::from_fn(|i| {
        f32::from_be_bytes([
            bytes[4 * i],
            bytes[4 * i + 1],
            bytes[4 * i + 2],
            bytes[4 * i + 3],
        ])
    })
}

/// Face `f` from its three big-endian i32 corners, checked against the vertex count.
fn triangle(f: usize, corners: &[u8], vertex_count: usize) -> Result<[u32; 3]> {
    let mut pos = 0;
    let mut triangle = [0u32; 3];
    for corner in &mut triangle {
        let index = super::be_i32(corners, &mut pos).unwrap_or(-1);
        *corner = u32::try_from(index)
            .ok()
            .filter(|&v| (v as usize) < vertex_count)
            .ok_or_else(|| {
                Error::Parse(format!(
                    "face {f}: vertex index {index} is out of range (the file has {vertex_count} vertices)"
                ))
            })?;
    }
    Ok(triangle)
}

/// Write a FreeSurfer triangle surface: `positions` in RAS, taken back to tkr-RAS
/// through `geometry` when it is valid, and `geometry` as the footer. Written
/// atomically.
///
/// Errors ([`Error::File`] naming `path`): a coordinate that is not a finite
/// 32-bit float once in tkr-RAS.
#[cfg(test)]
pub fn write_surface(
    path: &Path,
    positions: &[Point],
    triangles: &[[u32; 3]],
    geometry: Option<&VolumeGeometry>,
) -> Result<()> {
    let fail = |message: String| Error::File {
        path: path.to_path_buf(),
        message,
    };
    let tkr = crate::space::to_tkr(positions, geometry);
    if let Some(v) = tkr.iter().position(|p| !p.iter().all(|&c| fits_f32(c))) {
        return Err(fail(format!(
            "vertex {v} has a coordinate that is not a finite 32-bit float"
        )));
    }
    let counts = [positions.len(), triangles.len()].map(i32::try_from);
    let [Ok(vertex_count), Ok(face_count)] = counts else {
        return Err(fail("too many vertices or faces for the format".into()));
    };
    write_atomically(path, |w| {
        w.write_all(&SURFACE_MAGIC)?;
        write!(w, "{CREATED_BY}\n\n")?;
        w.write_all(&vertex_count.to_be_bytes())?;
        w.write_all(&face_count.to_be_bytes())?;
        for p in &tkr {
            for c in p.iter() {
                w.write_all(&(*c as f32).to_be_bytes())?;
            }
        }
        for t in triangles {
            for &v in t {
                w.write_all(&(v as i32).to_be_bytes())?;
            }
        }
        if let Some(geometry) = geometry {
            w.write_all(&footer_bytes(geometry))?;
        }
        Ok(())
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A tetrahedron surface file as FreeSurfer writes it, with `footer` appended.
    fn tetrahedron(footer: &[u8]) -> Vec<u8> {
        let mut bytes = SURFACE_MAGIC.to_vec();
        bytes.extend_from_slice(b"created by someone on a day\n\n");
        for n in [4i32, 4] {
            bytes.extend_from_slice(&n.to_be_bytes());
        }
        let vertices = [
            [0.0f32, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
        ];
        for c in vertices.iter().flatten() {
            bytes.extend_from_slice(&c.to_be_bytes());
        }
        for v in [0i32, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3] {
            bytes.extend_from_slice(&v.to_be_bytes());
        }
        bytes.extend_from_slice(footer);
        bytes
    }

    fn read(bytes: &[u8]) -> Result<TriangleSoup> {
        parse(&mut Input::new(bytes, None))
    }

    #[test]
    fn a_surface_without_footer_keeps_its_coordinates() {
        let soup = read(&tetrahedron(&[])).unwrap();
        assert_eq!(soup.positions[1], Point::new(1.0, 0.0, 0.0));
        assert_eq!(soup.triangles[3], [1, 2, 3]);
        assert_eq!(soup.space, Some(Space::Ras));
        assert_eq!(soup.volume_geometry, None);
    }

    #[test]
    fn a_valid_footer_moves_vertices_to_scanner_ras() {
        let geometry = VolumeGeometry {
            valid: "1  # volume info valid".into(),
            filename: "orig.mgz".into(),
            volume: [256, 256, 256],
            voxel_size: [1.0; 3],
            x_ras: [-1.0, 0.0, 0.0],
            y_ras: [0.0, 0.0, -1.0],
            z_ras: [0.0, 1.0, 0.0],
            c_ras: [10.0, -20.0, 30.0],
        };
        let soup = read(&tetrahedron(&footer_bytes(&geometry))).unwrap();
        assert_eq!(soup.positions[3], Point::new(10.0, -20.0, 31.0));
        assert_eq!(soup.volume_geometry, Some(geometry));
    }

    #[test]
    fn truncated_files_and_bad_indices_are_errors() {
        let whole = tetrahedron(&[]);
        let cut = read(&whole[..whole.len() - 1]).unwrap_err().to_string();
        assert!(cut.contains("announces 4 vertices and 4 faces"), "{cut}");
        let mut absurd = whole.clone();
        let counts = absurd.iter().position(|&b| b == b'\n').unwrap() + 2;
        absurd[counts..counts + 4].copy_from_slice(&i32::MAX.to_be_bytes());
        assert!(read(&absurd).unwrap_err().to_string().contains("announces"));
        absurd[counts..counts + 4].copy_from_slice(&(-3i32).to_be_bytes());
        assert!(read(&absurd)
            .unwrap_err()
            .to_string()
            .contains("negative vertex count"));
        let mut bad_index = whole.clone();
        let last = bad_index.len() - 4;
        bad_index[last..].copy_from_slice(&9i32.to_be_bytes());
        let error = read(&bad_index).unwrap_err().to_string();
        assert!(
            error.contains("face 3: vertex index 9 is out of range"),
            "{error}"
        );
        assert!(read(&SURFACE_MAGIC).is_err());
    }
}

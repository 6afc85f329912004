//! The frames of a file and where each lies.
//!
//! - A single-frame image: the Image Plane Module (PS3.3 C.7.6.2) and the
//!   Modality LUT Module (C.11.1) at the root of the data set.
//! - An enhanced multi-frame image (PS3.3 C.7.6.16, Multi-frame Functional
//!   Groups): item `f` of the Per-frame Functional Groups Sequence (5200,9230)
//!   places frame `f`; a functional group missing there is taken from the Shared
//!   Functional Groups Sequence (5200,9229), then from the root. The groups read
//!   are Plane Position (Patient) (0020,9113, C.7.6.16.2.3), Plane Orientation
//!   (Patient) (0020,9116, C.7.6.16.2.4), Pixel Measures (0028,9110,
//!   C.7.6.16.2.1) and Pixel Value Transformation (0028,9145, C.7.6.16.2.9).
//! - A classic multi-frame image whose Frame Increment Pointer (0028,0009) is the
//!   Grid Frame Offset Vector (3004,000C), as RT Dose has (PS3.3 C.8.8.3.2):
//!   frame `f` lies at the Image Position (Patient) moved along the normal of the
//!   planes by `offset[f] − offset[0]` (both kinds of vector, relative ones
//!   starting at 0 and absolute ones starting at the position's z, come out
//!   alike). Its Dose Grid Scaling (3004,000E) is the slope of its values.
//!
//! The frames of any other multi-frame file have no position of their own, and
//! reading them as a volume fails in [`super::geometry`].

use dicom_dictionary_std::tags;
use dicom_object::Tag;

use super::header::{decimals, first_item, numbers, tag_value, Frame, Object, Plane};
use super::pixels::Rescale;
use crate::{Error, Point, Result, Vector};

/// The `count` frames of `object`, each of `size` (rows, columns).
pub(super) fn frames(object: &Object, size: [u32; 2], count: u32) -> Result<Vec<Frame>> {
    if let Some(per_frame) = object.get(tags::PER_FRAME_FUNCTIONAL_GROUPS_SEQUENCE) {
        let items = per_frame.items().unwrap_or_default();
        if items.len() != count as usize {
            return Err(Error::Parse(format!(
                "has {} items in its Per-frame Functional Groups Sequence (5200,9230) for {count} frames",
                items.len()
            )));
        }
        let shared = first_item(object, tags::SHARED_FUNCTIONAL_GROUPS_SEQUENCE);
        return (0..count)
            .zip(items)
            .map(|(number, item)| functional_frame(object, [Some(item), shared], size, number))
            .collect();
    }
    let plane = plane(object, object, object, size)?;
    let rescale = rescale(object)?;
    let offsets = grid_frame_offsets(object, count)?;
    Ok((0..count)
        .map(|number| {
            let position = match &offsets {
                Some(offsets) => plane
                    .position
                    .zip(normal(&plane))
                    .map(|(p, n)| p + n * (offsets[number as usize] - offsets[0])),
                None if number == 0 => plane.position,
                None => None,
            };
            Frame {
                number,
                plane: Plane {
                    position,
                    ..plane.clone()
                },
                rescale,
            }
        })
        .collect())
}

/// Frame `number` of an enhanced multi-frame image, its functional groups looked
/// up in `groups` (the frame's own item, then the shared one), then at the root.
fn functional_frame(
    root: &Object,
    groups: [Option<&Object>; 2],
    size: [u32; 2],
    number: u32,
) -> Result<Frame> {
    let group = |sequence: Tag| {
        groups
            .iter()
            .flatten()
            .find_map(|item| first_item(item, sequence))
            .unwrap_or(root)
    };
    let plane = plane(
        group(tags::PLANE_POSITION_SEQUENCE),
        group(tags::PLANE_ORIENTATION_SEQUENCE),
        group(tags::PIXEL_MEASURES_SEQUENCE),
        size,
    )?;
    let rescale = rescale(group(tags::PIXEL_VALUE_TRANSFORMATION_SEQUENCE))?;
    Ok(Frame {
        number,
        plane,
        rescale,
    })
}

/// The plane of a frame whose position, orientation and pixel measures are in
/// the given data sets.
fn plane(
    position: &Object,
    orientation: &Object,
    measures: &Object,
    size: [u32; 2],
) -> Result<Plane> {
    let position = numbers::<3>(
        position,
        tags::IMAGE_POSITION_PATIENT,
        "Image Position (Patient)",
    )?;
    let orientation = numbers::<6>(
        orientation,
        tags::IMAGE_ORIENTATION_PATIENT,
        "Image Orientation (Patient)",
    )?;
    Ok(Plane {
        size,
        position: position.map(Point::from),
        orientation: orientation
            .map(|o| [Vector::new(o[0], o[1], o[2]), Vector::new(o[3], o[4], o[5])]),
        pixel_spacing: numbers::<2>(measures, tags::PIXEL_SPACING, "Pixel Spacing")?,
        thickness: numbers::<1>(measures, tags::SLICE_THICKNESS, "Slice Thickness")?.map(|[t]| t),
    })
}

/// The unit normal of a plane with an orientation (`None` without one or for
/// parallel directions).
fn normal(plane: &Plane) -> Option<Vector> {
    let [row, column] = plane.orientation?;
    row.cross(&column).try_normalize(1e-12)
}

/// The modality LUT of the data set (PS3.3 C.11.1.1.2): Rescale Slope (0028,1053)
/// and Rescale Intercept (0028,1052), or RT Dose's Dose Grid Scaling (3004,000E)
/// as the slope; the identity without them. A Modality LUT Sequence (0028,3000),
/// a table instead of a line, is refused rather than ignored.
fn rescale(object: &Object) -> Result<Rescale> {
    if object.get(tags::MODALITY_LUT_SEQUENCE).is_some() {
        return Err(Error::Parse(
            "has a Modality LUT Sequence (0028,3000), a lookup table crestline does not apply"
                .to_string(),
        ));
    }
    let slope = numbers::<1>(object, tags::RESCALE_SLOPE, "Rescale Slope")?;
    let dose = numbers::<1>(object, tags::DOSE_GRID_SCALING, "Dose Grid Scaling")?;
    let intercept = numbers::<1>(object, tags::RESCALE_INTERCEPT, "Rescale Intercept")?;
    Ok(Rescale {
        slope: slope.or(dose).map_or(1.0, |[s]| s),
        intercept: intercept.map_or(0.0, |[i]| i),
    })
}

/// The Grid Frame Offset Vector (3004,000C) if the Frame Increment Pointer
/// (0028,0009) points to it: one offset per frame.
fn grid_frame_offsets(object: &Object, count: u32) -> Result<Option<Vec<f64>>> {
    if tag_value(object, tags::FRAME_INCREMENT_POINTER) != Some(tags::GRID_FRAME_OFFSET_VECTOR) {
        return Ok(None);
    }
    let name = "Grid Frame Offset Vector";
    match decimals(object, tags::GRID_FRAME_OFFSET_VECTOR, name, count as usize)? {
        Some(offsets) => Ok(Some(offsets)),
        None => Err(Error::Parse(format!(
            "has no {name} (3004,000C), which its Frame Increment Pointer (0028,0009) points to"
        ))),
    }
}

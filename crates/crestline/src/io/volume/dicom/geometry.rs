//! The regular grid that the frames of a series make, or why they make none.
//!
//! Frames are ordered by their Image Position (Patient) (PS3.3 C.7.6.2.1.1)
//! projected on the normal of their Image Orientation (Patient), never by Instance
//! Number (which scanners number in acquisition order, in either direction). The
//! grid's index axes are the row direction (increasing column index), the column
//! direction and that normal, so an oblique series keeps its orientation as the
//! direction matrix; its slice spacing is the step between positions, not Slice
//! Thickness (slices may overlap or leave gaps between them), unless the two agree
//! to [`NOMINAL_AGREEMENT`]: then the step is the thickness, the exact number of
//! which the positions' decimal strings are a rounding. A series of 1 mm slices so
//! has a spacing of exactly 1 mm, as its NIfTI conversion has, not 1 mm and a
//! rounding error that the Gaussian smoothing and every later decision carry.
//!
//! Refused, since the frames would not be samples of one regular grid:
//! frames of different sizes, pixel spacings or orientations; positions offset
//! along a direction other than the normal (a gantry tilt, which would need
//! resampling to a sheared grid: refused, not resampled); two frames at one
//! position (several acquisitions or time points in one series); and steps that
//! differ from the usual one (a missing slice).
//!
//! Tolerances are relative, [`TOLERANCE`] of the spacing they concern: a position
//! off by less than a thousandth of a voxel moves nothing a feature line can
//! show, while the rounding of decimal strings (16 characters, so positions keep
//! at least 10 significant digits below 1 m) stays far below it and a missing
//! slice, a whole step, far above.

use nalgebra::Matrix3;

use super::header::Plane;
use crate::{Error, Point, Result, Vector};

/// The relative tolerance on positions, steps, spacings and direction cosines.
pub(super) const TOLERANCE: f64 = 1e-3;

/// How closely, relatively, the step between positions must match Slice Thickness
/// for the thickness to be taken as the step: positions written with 8
/// significant digits or more over two slices or more agree this well with the
/// thickness they were made with, while slices that overlap or leave gaps differ
/// by far more.
const NOMINAL_AGREEMENT: f64 = 1e-6;

/// The grid a series makes.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct Stack {
    /// The frames in the order of the slices (indices into the frames given).
    pub order: Vec<usize>,
    /// Columns, rows and slices.
    pub dims: [usize; 3],
    /// Between columns, between rows and between slices, mm.
    pub spacing: [f64; 3],
    /// The centre of the first pixel of the first slice.
    pub origin: [f64; 3],
    /// Columns: the row direction, the column direction and the slice normal.
    pub direction: Matrix3<f64>,
}

/// The grid of the frames with the `planes`; `name(i)` names frame `i` in errors
/// (its file, and its number in a multi-frame file). Errors are
/// [`Error::Parse`] messages to be put in the name of the series' folder.
pub(super) fn stack(planes: &[&Plane], name: &dyn Fn(usize) -> String) -> Result<Stack> {
    let first = planes
        .first()
        .ok_or_else(|| Error::Parse("has no image".to_string()))?;
    check_alike(planes, name)?;
    let [rows, columns] = first.size;
    let [row_spacing, column_spacing] = first.pixel_spacing.unwrap_or([1.0, 1.0]);
    let [row, column] = unit_orientation(first, &name(0))?;
    let normal = row.cross(&column);
    let (order, slice_spacing) = if planes.len() == 1 {
        (vec![0], first.thickness.filter(|t| *t > 0.0).unwrap_or(1.0))
    } else {
        let positions = positions(planes, name)?;
        let order = sorted_along(&positions, &normal);
        check_tilt(&positions, &order, &normal, column_spacing.min(row_spacing))?;
        let step = check_steps(&positions, &order, &normal, name)?;
        (order, nominal(step, first.thickness))
    };
    let origin = planes[order[0]].position.unwrap_or(Point::origin());
    Ok(Stack {
        dims: [columns as usize, rows as usize, order.len()],
        order,
        spacing: [column_spacing, row_spacing, slice_spacing],
        origin: origin.coords.into(),
        direction: Matrix3::from_columns(&[row, column, normal]),
    })
}

/// An error unless every plane has the size, pixel spacing and orientation of
/// the first.
fn check_alike(planes: &[&Plane], name: &dyn Fn(usize) -> String) -> Result<()> {
    let first = planes[0];
    let mixed = |what: &str, i: usize, a: String, b: String| {
        Error::Parse(format!(
            "mixes {what}: {} has {a} and {} has {b}; a volume needs one",
            name(0),
            name(i)
        ))
    };
    for (i, plane) in planes.iter().enumerate().skip(1) {
        if plane.size != first.size {
            let size = |p: &Plane| format!("{}×{} pixels", p.size[1], p.size[0]);
            return Err(mixed("image sizes", i, size(first), size(plane)));
        }
        if !close_all(first.pixel_spacing, plane.pixel_spacing) {
            let spacing = |p: &Plane| attribute("Pixel Spacing", p.pixel_spacing.as_ref());
            return Err(mixed("pixel spacings", i, spacing(first), spacing(plane)));
        }
        let orientation = |p: &Plane| p.orientation.map(|[r, c]| [r.x, r.y, r.z, c.x, c.y, c.z]);
        if !close_all(orientation(first), orientation(plane)) {
            let text =
                |p: &Plane| attribute("Image Orientation (Patient)", orientation(p).as_ref());
            return Err(mixed("orientations", i, text(first), text(plane)));
        }
    }
    Ok(())
}

/// An attribute as a message shows it: its name and values as DICOM writes them
/// (`Pixel Spacing 0.5\0.5`), or `no Pixel Spacing` when absent.
fn attribute<const N: usize>(name: &str, numbers: Option<&[f64; N]>) -> String {
    match numbers {
        Some(numbers) => format!("{name} {}", values(numbers)),
        None => format!("no {name}"),
    }
}

/// Numbers separated by backslashes, as in a DICOM multi-valued attribute, each
/// to 7 significant digits.
fn values(numbers: &[f64]) -> String {
    let shown: Vec<String> = numbers.iter().map(|&x| crate::error::readable(x)).collect();
    shown.join("\\")
}

/// Whether `a` and `b` are both absent or agree within [`TOLERANCE`] relative to
/// their largest value.
fn close_all<const N: usize>(a: Option<[f64; N]>, b: Option<[f64; N]>) -> bool {
    match (a, b) {
        (None, None) => true,
        (Some(a), Some(b)) => {
            let scale = a.iter().chain(&b).fold(0.0f64, |m, v| m.max(v.abs()));
            a.iter()
                .zip(&b)
                .all(|(x, y)| (x - y).abs() <= TOLERANCE * scale)
        }
        _ => false,
    }
}

/// The row and column directions of `plane` as unit vectors (the axes without an
/// orientation), or an error if they are not perpendicular.
fn unit_orientation(plane: &Plane, name: &str) -> Result<[Vector; 2]> {
    let Some([row, column]) = plane.orientation else {
        return Ok([Vector::x(), Vector::y()]);
    };
    let unit = [row.try_normalize(1e-9), column.try_normalize(1e-9)];
    match unit {
        [Some(row), Some(column)] if row.dot(&column).abs() <= TOLERANCE => Ok([row, column]),
        _ => Err(Error::Parse(format!(
            "{name} has an Image Orientation (Patient) (0020,0037) that is not two perpendicular directions: {}",
            values([row.as_slice(), column.as_slice()].concat().as_slice())
        ))),
    }
}

/// The position of every plane, or an error naming one without.
fn positions(planes: &[&Plane], name: &dyn Fn(usize) -> String) -> Result<Vec<Point>> {
    planes
        .iter()
        .enumerate()
        .map(|(i, plane)| {
            plane.position.ok_or_else(|| {
                Error::Parse(format!(
                    "{} has no Image Position (Patient) (0020,0032): its slices cannot be ordered",
                    name(i)
                ))
            })
        })
        .collect()
}

/// The indices of `positions` sorted along `normal` (a stable sort: equal
/// positions keep their order, and [`check_steps`] refuses them).
fn sorted_along(positions: &[Point], normal: &Vector) -> Vec<usize> {
    let mut order: Vec<usize> = (0..positions.len()).collect();
    order.sort_by(|&a, &b| {
        positions[a]
            .coords
            .dot(normal)
            .total_cmp(&positions[b].coords.dot(normal))
    });
    order
}

/// An error if the slices are offset across the normal by more than
/// [`TOLERANCE`] of the pixel spacing (a gantry tilt), giving the angle.
fn check_tilt(positions: &[Point], order: &[usize], normal: &Vector, pixel: f64) -> Result<()> {
    let first = positions[order[0]];
    let across = |p: &Point| {
        let offset = p - first;
        (offset - normal * offset.dot(normal)).norm()
    };
    let worst = order
        .iter()
        .map(|&i| across(&positions[i]))
        .fold(0.0, f64::max);
    if worst <= TOLERANCE * pixel {
        return Ok(());
    }
    let last = positions[order[order.len() - 1]];
    let along = (last - first).dot(normal);
    let angle = across(&last).atan2(along).to_degrees();
    Err(Error::Parse(format!(
        "has slices offset along a direction {angle:.2}° from the normal of their planes (a gantry tilt; \
         the slices are {worst:.4} mm apart across the normal): such a series is not a regular grid, \
         and crestline refuses it rather than resampling it"
    )))
}

/// The slice spacing of a series whose positions are `step` apart: its Slice
/// Thickness if the two agree to [`NOMINAL_AGREEMENT`], else `step`.
fn nominal(step: f64, thickness: Option<f64>) -> f64 {
    match thickness {
        Some(t) if (t - step).abs() <= NOMINAL_AGREEMENT * step => t,
        _ => step,
    }
}

/// The slice spacing: the usual (median) step between consecutive positions
/// along `normal`, after checking that every position is where that step puts it
/// within [`TOLERANCE`] of it. Errors name the two slices around the first
/// position that is not.
fn check_steps(
    positions: &[Point],
    order: &[usize],
    normal: &Vector,
    name: &dyn Fn(usize) -> String,
) -> Result<f64> {
    let along: Vec<f64> = order
        .iter()
        .map(|&i| positions[i].coords.dot(normal))
        .collect();
    let mut steps: Vec<f64> = along.windows(2).map(|w| w[1] - w[0]).collect();
    steps.sort_by(f64::total_cmp);
    let step = steps[steps.len() / 2];
    let at = |k: usize| {
        let p = positions[order[k]];
        format!("{} at [{:.4}, {:.4}, {:.4}]", name(order[k]), p.x, p.y, p.z)
    };
    if let Some(k) = (1..along.len()).find(|&k| along[k] - along[k - 1] <= TOLERANCE * step) {
        return Err(Error::Parse(format!(
            "has two slices at one position: {} and {} (several acquisitions or time points in one series?)",
            at(k - 1),
            at(k)
        )));
    }
    let off = |k: usize| (along[k] - along[0] - k as f64 * step).abs() > TOLERANCE * step;
    if let Some(k) = (1..along.len()).find(|&k| off(k)) {
        return Err(Error::Parse(format!(
            "has unevenly spaced slices: {} mm between {} and {} along the normal where the spacing is {step:.4} mm \
             (a missing slice?)",
            format_args!("{:.4}", along[k] - along[k - 1]),
            at(k - 1),
            at(k)
        )));
    }
    Ok((along[along.len() - 1] - along[0]) / (along.len() - 1) as f64)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An axial 4×3 slice at `position`.
    fn slice(position: [f64; 3]) -> Plane {
        Plane {
            size: [3, 4],
            position: Some(Point::from(position)),
            orientation: Some([Vector::x(), Vector::y()]),
            pixel_spacing: Some([0.5, 0.25]),
            thickness: Some(9.0),
        }
    }

    fn stack_of(planes: &[Plane]) -> Result<Stack> {
        let refs: Vec<&Plane> = planes.iter().collect();
        stack(&refs, &|i| format!("file {i}"))
    }

    #[test]
    fn shuffled_slices_are_ordered_by_position_and_spaced_by_it() {
        let z = [6.0, 0.0, 4.0, 2.0];
        let planes: Vec<Plane> = z.iter().map(|&z| slice([1.0, 2.0, z])).collect();
        let stack = stack_of(&planes).unwrap();
        assert_eq!(stack.order, [1, 3, 2, 0]);
        assert_eq!(stack.dims, [4, 3, 4]);
        // Pixel Spacing is rows then columns; the slice spacing comes from the
        // positions, not from the Slice Thickness of 9.
        assert_eq!(stack.spacing, [0.25, 0.5, 2.0]);
        assert_eq!(stack.origin, [1.0, 2.0, 0.0]);
        assert_eq!(stack.direction, Matrix3::identity());
    }

    #[test]
    fn the_thickness_is_the_spacing_only_where_the_positions_round_it() {
        // Positions of 1.5 mm slices, each off by the rounding of a decimal
        // string: the spacing is the thickness, exactly.
        let rounded = [0.0, 1.500_000_000_1, 2.999_999_999_8];
        let with_thickness = |z: &[f64], t: f64| -> Vec<Plane> {
            z.iter()
                .map(|&z| Plane {
                    thickness: Some(t),
                    ..slice([0.0, 0.0, z])
                })
                .collect()
        };
        let stack = stack_of(&with_thickness(&rounded, 1.5)).unwrap();
        assert_eq!(stack.spacing[2], 1.5);
        // Slices 1.5 mm apart but 1.5001 mm thick (overlapping): the positions.
        let stack = stack_of(&with_thickness(&rounded, 1.5001)).unwrap();
        assert!((stack.spacing[2] - 1.5).abs() < 1e-9 && stack.spacing[2] != 1.5);
    }

    #[test]
    fn an_oblique_series_keeps_its_orientation() {
        let (c, s) = (0.8, 0.6);
        let row = Vector::new(c, s, 0.0);
        let column = Vector::new(0.0, 0.0, -1.0);
        let normal = row.cross(&column);
        let planes: Vec<Plane> = [2.0, 0.0, 1.0]
            .iter()
            .map(|&k| Plane {
                orientation: Some([row, column]),
                position: Some(Point::new(5.0, 0.0, 0.0) + normal * (1.5 * k)),
                ..slice([0.0; 3])
            })
            .collect();
        let stack = stack_of(&planes).unwrap();
        assert_eq!(stack.order, [1, 2, 0]);
        assert!((stack.spacing[2] - 1.5).abs() < 1e-12);
        assert_eq!(stack.direction.column(2), normal);
        assert_eq!(stack.origin, [5.0, 0.0, 0.0]);
    }

    #[test]
    fn a_missing_slice_is_refused_naming_the_gap() {
        let planes: Vec<Plane> = [0.0, 1.0, 2.0, 4.0, 5.0]
            .iter()
            .map(|&z| slice([0.0, 0.0, z]))
            .collect();
        let err = stack_of(&planes).unwrap_err().to_string();
        assert!(err.contains("unevenly spaced"), "{err}");
        assert!(
            err.contains("2.0000 mm between file 2 at [0.0000, 0.0000, 2.0000]"),
            "{err}"
        );
        assert!(err.contains("file 3 at [0.0000, 0.0000, 4.0000]"), "{err}");
        assert!(err.contains("the spacing is 1.0000 mm"), "{err}");
    }

    #[test]
    fn steps_within_the_tolerance_pass_and_beyond_it_fail() {
        let with_error = |e: f64| {
            let planes: Vec<Plane> = [0.0, 1.0 + e, 2.0, 3.0]
                .iter()
                .map(|&z| slice([0.0, 0.0, z]))
                .collect();
            stack_of(&planes)
        };
        assert!(with_error(0.5 * TOLERANCE).is_ok());
        assert!(with_error(2.0 * TOLERANCE).is_err());
    }

    #[test]
    fn a_gantry_tilt_is_refused_with_its_angle() {
        let tilt = 10f64.to_radians();
        let planes: Vec<Plane> = (0..5)
            .map(|k| slice([0.0, k as f64 * tilt.tan(), k as f64]))
            .collect();
        let err = stack_of(&planes).unwrap_err().to_string();
        assert!(err.contains("10.00° from the normal"), "{err}");
        assert!(err.contains("gantry tilt"), "{err}");
    }

    #[test]
    fn mixed_orientations_sizes_and_duplicates_are_refused() {
        let mut planes: Vec<Plane> = (0..3).map(|k| slice([0.0, 0.0, k as f64])).collect();
        planes[2].orientation = Some([Vector::x(), Vector::z()]);
        let err = stack_of(&planes).unwrap_err().to_string();
        assert!(err.contains("mixes orientations: file 0"), "{err}");
        assert!(err.contains("(Patient) 1\\0\\0\\0\\0\\1"), "{err}");
        planes[2].orientation = planes[0].orientation;
        planes[1].pixel_spacing = None;
        let err = stack_of(&planes).unwrap_err().to_string();
        assert!(
            err.contains(" has Pixel Spacing 0.5\\0.25 and file 1 has no Pixel Spacing;"),
            "{err}"
        );
        planes[1].pixel_spacing = planes[0].pixel_spacing;
        planes[2] = Plane {
            size: [3, 5],
            ..slice([0.0, 0.0, 2.0])
        };
        let err = stack_of(&planes).unwrap_err().to_string();
        assert!(
            err.contains("4×3 pixels and file 2 has 5×3 pixels"),
            "{err}"
        );
        planes[2] = slice([0.0, 0.0, 1.0]);
        let err = stack_of(&planes).unwrap_err().to_string();
        assert!(err.contains("two slices at one position"), "{err}");
    }

    #[test]
    fn a_lone_slice_without_a_plane_is_axis_aligned() {
        let plane = Plane {
            size: [2, 2],
            position: None,
            orientation: None,
            pixel_spacing: None,
            thickness: None,
        };
        let stack = stack_of(std::slice::from_ref(&plane)).unwrap();
        assert_eq!(stack.spacing, [1.0; 3]);
        assert_eq!(stack.origin, [0.0; 3]);
        let err = stack_of(&[plane.clone(), plane]).unwrap_err().to_string();
        assert!(err.contains("file 0 has no Image Position"), "{err}");
    }
}

//! The rigid motion taking one scan's crest lines onto another's (`crestline
//! register`; trimmed ICP, Chetverikov et al. 2002).

use std::path::Path;

use crate::landmarks::{holds_landmarks, read_landmarks, LandmarkKind};
use crate::lines::read_json;
use crate::progress::{checkpoint, stage, Observer};
use crate::register::{register as align, PointSet, Registration, RegistrationOptions};
use crate::space::{self, Space};
use crate::{Error, Point, Result};

/// The rigid motion taking `moving` onto `fixed` as `options` say
/// (trimmed ICP, [`crate::register`]): the stage `registration`, and the counts
/// `fixed_points`, `moving_points` and `matched`.
///
/// # Examples
///
/// ```
/// # use crestline::jobs::{self, Surface};
/// # use crestline::progress::Silent;
/// # let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../meshes/bunny_small.obj");
/// # let (mesh, _repairs) = jobs::build_mesh(crestline::io::read_mesh(path.as_ref())?, false, &mut Silent)?;
/// # let surface = Surface::of_mesh(mesh);
/// use crestline::register::{PointSet, RegistrationOptions};
///
/// // The bunny's vertices, and a copy moved by 2 mm along x.
/// let fixed = PointSet { line_points: surface.mesh.positions().to_vec(), key_points: vec![] };
/// let shift = crestline::Vector::new(2.0, 0.0, 0.0);
/// let moved = fixed.line_points.iter().map(|p| p + shift).collect();
/// let moving = PointSet { line_points: moved, key_points: vec![] };
/// let found = jobs::register(&fixed, &moving, &RegistrationOptions::default(), &mut Silent)?;
/// println!("rms {} after {} iterations", found.rms, found.iterations);
/// # Ok::<(), crestline::Error>(())
/// ```
pub fn register(
    fixed: &PointSet,
    moving: &PointSet,
    options: &RegistrationOptions,
    observer: &mut dyn Observer,
) -> Result<Registration> {
    options.validate()?;
    // Too few points is the caller's argument, not a failure of the stage.
    checkpoint(observer)?;
    let found = stage(observer, "registration", || align(fixed, moving, options))?;
    observer.count("fixed_points", fixed.line_points.len());
    observer.count("moving_points", moving.line_points.len());
    observer.count("matched", found.matched);
    Ok(found)
}

/// [`PointSet::read`].
pub(crate) fn read_point_set(path: &Path, space: Option<Space>) -> Result<PointSet> {
    let in_file = |message: String| Error::File {
        path: path.to_path_buf(),
        message,
    };
    let text = crate::io::file::read_text(path)?;
    let (line_points, key_points, declared) = if holds_landmarks(&text) {
        let (landmarks, declared) = read_landmarks(path)?;
        let line_points = landmarks.lines.iter().flat_map(|line| line.points.clone());
        let extremal = landmarks
            .points
            .iter()
            .filter(|p| p.kind == LandmarkKind::Extremal)
            .map(|p| p.position);
        (line_points.collect(), extremal.collect(), Some(declared))
    } else {
        let lines = read_json(path)?;
        let line_points = lines.iter().flat_map(|line| line.points.clone());
        (line_points.collect::<Vec<_>>(), Vec::new(), lines.space)
    };
    let frame = space::resolve(declared, space)
        .map_err(|e| match e {
            Error::Argument(message) => in_file(message),
            other => other,
        })?
        .ok_or_else(|| {
            in_file(
                "the file does not say the frame of its points (RAS or LPS); give it with `space`"
                    .to_string(),
            )
        })?;
    let to_ras = |points: Vec<Point>| points.iter().map(|p| frame.to_ras(p)).collect();
    Ok(PointSet {
        line_points: to_ras(line_points),
        key_points: to_ras(key_points),
    })
}

impl PointSet {
    /// The points to register of a file, in RAS: a lines file (`crestline-lines`
    /// JSON; every line point) or a landmarks file (`crestline-landmarks` JSON; every
    /// line point, and the extremal points as key points), each in the frame it
    /// declares. `space` is the frame of a file that declares none (a lines file of a
    /// mesh, or of an older version); such a file without `space` is refused, as is a
    /// `space` that contradicts the file, so that frames are never mixed silently.
    ///
    /// Errors are [`Error::File`] naming `path`.
    pub fn read(path: &Path, space: Option<Space>) -> Result<PointSet> {
        read_point_set(path, space)
    }
}

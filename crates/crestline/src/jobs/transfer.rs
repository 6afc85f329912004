//! A template's labelled landmarks carried onto another scan through their crest
//! lines (`crestline transfer`; [`crate::transfer`]).

use super::ridges::RidgesOptions;
use crate::lines::FeatureLines;
use crate::progress::Observer;
use crate::space::Space;
use crate::transfer::{transfer as carry, LabelledPoint, Transfer, TransferOptions};
use crate::{Error, Result};

/// The `landmarks` of the template (positions in RAS), whose crest lines are
/// `template`, carried onto the subject whose crest lines are `subject`
/// ([`crate::transfer::transfer`]): the stages `rigid` and `deform`, the counts
/// `pairs` and `landmarks` and the measure `rms`. The lines are taken to RAS
/// from the frame they declare; lines that declare none are an
/// [`Error::Argument`] naming which.
///
/// # Examples
///
/// Three points of the bunny's lines (diagonal 1), carried onto a copy of its lines
/// moved by 5% of the diagonal, land within 0.1% of it from where they should:
///
/// ```
/// # use crestline::jobs::{self, Surface};
/// # use crestline::progress::Silent;
/// use crestline::transfer::{LabelledPoint, TransferOptions};
/// use crestline::{Space, Vector};
///
/// # let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../meshes/bunny.obj");
/// # let (mesh, _repairs) = jobs::build_mesh(crestline::io::read_mesh(path.as_ref())?, false, &mut Silent)?;
/// let options = TransferOptions::default();
/// let mut template = jobs::ridges(&Surface::of_mesh(mesh), &options.mesh_tracing(), &mut Silent)?;
/// template.space = Some(Space::Ras);
/// let shift = Vector::new(0.04, 0.03, 0.0);
/// let mut subject = template.clone();
/// subject.lines.iter_mut().flat_map(|l| l.points.iter_mut()).for_each(|p| *p += shift);
/// let landmarks: Vec<LabelledPoint> = (0..3)
///     .map(|k| LabelledPoint { label: format!("L{k}"), position: template.lines[k].points[0] })
///     .collect();
/// let carried = jobs::transfer(&template, &subject, &landmarks, &options, &mut Silent)?;
/// for (landmark, landed) in landmarks.iter().zip(&carried.positions) {
///     assert!((landed - (landmark.position + shift)).norm() < 1e-3);
/// }
/// # Ok::<(), crestline::Error>(())
/// ```
pub fn transfer(
    template: &FeatureLines,
    subject: &FeatureLines,
    landmarks: &[LabelledPoint],
    options: &TransferOptions,
    observer: &mut dyn Observer,
) -> Result<Transfer> {
    let in_ras = |lines: &FeatureLines, what: &str| match lines.space {
        Some(_) => Ok(lines.in_space(Space::Ras)),
        None => Err(Error::Argument(format!(
            "the {what}'s lines do not say the frame of their points (RAS or LPS)"
        ))),
    };
    let (template, subject) = (in_ras(template, "template")?, in_ras(subject, "subject")?);
    let points: Vec<_> = landmarks.iter().map(|l| l.position).collect();
    let carried = carry(&template, &subject, &points, options, observer)?;
    observer.count("landmarks", landmarks.len());
    Ok(carried)
}

impl TransferOptions {
    /// How the lines of a mesh that [`transfer`] registers are traced: its ridges
    /// and valleys ([`ridges`](super::ridges()), the default tracing) at least
    /// [`TransferOptions::mesh_threshold`] strong.
    pub fn mesh_tracing(&self) -> RidgesOptions {
        RidgesOptions {
            threshold: self.mesh_threshold,
            ..RidgesOptions::default()
        }
    }
}

//! A template's labelled landmarks carried onto another scan through their crest
//! lines (`crestline transfer`; [`crate::transfer`]).

use super::image::{image_units, voxel_size};
use super::ridges::RidgesOptions;
use super::{crest_lines, CrestLinesOptions, Length, Units};
use crate::lines::FeatureLines;
use crate::progress::Observer;
use crate::space::Space;
use crate::transfer::{transfer as carry, LabelledPoint, Transfer, TransferOptions};
use crate::volume::Volume;
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

    /// The lines [`transfer`] registers of the image `volume` whose landmarks lie on
    /// its isosurface `level` (inside is `f ≥ level`): the crest lines of that
    /// isosurface and of the inner ones at [`inner_levels`](Self::inner_levels) (the
    /// quantiles of the samples at or above the level), all traced at
    /// [`image_scale`](Self::image_scale); each isosurface's stages are told to
    /// `observer` as [`crest_lines`] tells them.
    ///
    /// Errors as [`crest_lines`] (no isosurface at the level), or if an option is
    /// out of range.
    pub fn image_lines(
        &self,
        volume: &Volume,
        level: f64,
        observer: &mut dyn Observer,
    ) -> Result<FeatureLines> {
        self.validate()?;
        let units = match self.image_scale {
            Length::Scaled { .. } => image_units(volume, level, None, observer)?,
            // No feature scale is needed, and none is told.
            _ => Units {
                sample: voxel_size(volume),
                scale: f64::NAN,
            },
        };
        let scale = self.image_scale.resolve(units);
        let tracing = CrestLinesOptions {
            scale: Some(scale),
            ..CrestLinesOptions::default()
        };
        let mut lines = crest_lines(volume, level, &tracing, observer)?;
        for inner in inner_levels(volume, level, &self.inner_levels) {
            let more = crest_lines(volume, inner, &tracing, observer)?;
            lines.lines.extend(more.lines);
        }
        Ok(lines)
    }
}

/// The `quantiles` of the finite samples of `volume` at or above `level`, those
/// above the level only (a quantile equal to it would trace its lines twice).
fn inner_levels(volume: &Volume, level: f64, quantiles: &[f64]) -> Vec<f64> {
    let mut inside: Vec<f32> = volume
        .samples()
        .iter()
        .copied()
        .filter(|s| s.is_finite() && f64::from(*s) >= level)
        .collect();
    if inside.is_empty() {
        return Vec::new();
    }
    // A selection per quantile, not a sort of the whole image.
    let last = inside.len() - 1;
    quantiles
        .iter()
        .map(|q| {
            let rank = (q * last as f64).round() as usize;
            f64::from(*inside.select_nth_unstable_by(rank, f32::total_cmp).1)
        })
        .filter(|inner| *inner > level)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 10 × 10 × 10 image of the samples 0, 1, …, 999 (unit spacing).
    fn counting() -> Volume {
        let samples = (0..1000).map(|s| s as f32).collect();
        Volume::new(
            [10; 3],
            [1.0; 3],
            [0.0; 3],
            nalgebra::Matrix3::identity(),
            samples,
        )
        .unwrap()
    }

    #[test]
    fn inner_levels_are_quantiles_of_the_samples_inside_the_level() {
        // Inside 600: the samples 600…999, whose median is 799.5 → 800 (rounded
        // index), first 600 and last 999.
        let levels = inner_levels(&counting(), 600.0, &[0.5, 0.0, 1.0]);
        assert_eq!(levels, vec![800.0, 999.0]);
        assert!(inner_levels(&counting(), 1000.0, &[0.5]).is_empty());
    }

    #[test]
    fn out_of_range_image_options_are_refused() {
        for (options, name) in [
            (
                TransferOptions {
                    inner_levels: vec![1.0],
                    ..TransferOptions::default()
                },
                "inner_levels",
            ),
            (
                TransferOptions {
                    image_scale: Length::units(0.0),
                    ..TransferOptions::default()
                },
                "image_scale",
            ),
        ] {
            let error = options.image_lines(&counting(), 500.0, &mut crate::progress::Silent);
            assert!(
                matches!(&error, Err(Error::Argument(m)) if m.contains(name)),
                "{error:?}"
            );
        }
    }
}

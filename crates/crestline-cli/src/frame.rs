//! `--output-space`: write an output in the other anatomical frame than its
//! input's.

use std::borrow::Cow;

use crestline::curvature::CurvatureField;
use crestline::landmarks::Landmarks;
use crestline::lines::FeatureLines;
use crestline::mesh::{Mesh, TriangleSoup};
use crestline::{Error, Result, Space};

/// The frame to write in.
#[derive(clap::Args, Debug, Clone, Copy)]
pub struct OutputSpaceArg {
    /// Write the points in this frame, RAS or LPS, converted from the input's
    /// (default: the input's own frame, which the output declares).
    #[arg(long, ignore_case = true, value_parser = super::named::<Space>(Space::NAMES))]
    pub output_space: Option<Space>,
}

impl OutputSpaceArg {
    /// `lines` in the frame asked for.
    pub fn lines(&self, lines: FeatureLines) -> Result<FeatureLines> {
        Ok(match self.wanted(lines.space)? {
            Some(space) => lines.in_space(space),
            None => lines,
        })
    }

    /// `soup` in the frame asked for.
    pub fn soup(&self, soup: TriangleSoup) -> Result<TriangleSoup> {
        Ok(match self.wanted(soup.space)? {
            Some(space) => soup.in_space(space),
            None => soup,
        })
    }

    /// A surface and its curvature in the frame asked for.
    pub fn surface<'m>(
        &self,
        mesh: &'m Mesh,
        field: Option<CurvatureField>,
    ) -> Result<(Cow<'m, Mesh>, Option<CurvatureField>)> {
        Ok(match (self.wanted(mesh.space())?, mesh.space()) {
            (Some(wanted), Some(declared)) => (
                Cow::Owned(mesh.in_space(wanted)),
                field.map(|field| field.in_space(declared, wanted)),
            ),
            _ => (Cow::Borrowed(mesh), field),
        })
    }

    /// `landmarks`, in `space`, in the frame asked for, and that frame.
    pub fn landmarks(&self, landmarks: Landmarks, space: Space) -> Result<(Landmarks, Space)> {
        Ok(match self.wanted(Some(space))? {
            Some(wanted) => (
                Landmarks {
                    space: Some(space),
                    ..landmarks
                }
                .in_space(wanted),
                wanted,
            ),
            None => (landmarks, space),
        })
    }

    /// The frame to convert to, if one was asked for; an error if the input has
    /// no frame to convert from.
    fn wanted(&self, declared: Option<Space>) -> Result<Option<Space>> {
        match (self.output_space, declared) {
            (Some(_), None) => Err(Error::Argument(
                "`output-space`: the input does not say its frame, so it cannot be converted"
                    .to_string(),
            )),
            (wanted, _) => Ok(wanted),
        }
    }
}

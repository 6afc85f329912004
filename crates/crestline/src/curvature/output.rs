//! Saving a curvature field with its mesh.

use std::path::Path;

use crate::io::{write_ply, VertexAttribute};
use crate::mesh::Mesh;
use crate::Result;

use super::{CurvatureEstimator, CurvatureField, Quality};

/// Run `estimator` on `mesh` and check its output fits the mesh and is finite: the
/// one entry point through which every stage gets curvature, so a custom estimator
/// is held to the same contract as the built-in ones.
pub fn estimate_curvature(
    mesh: &Mesh,
    estimator: &dyn CurvatureEstimator,
) -> Result<CurvatureField> {
    let field = estimator.estimate(mesh)?;
    field.check(mesh)?;
    Ok(field)
}

/// [`CurvatureField::write_ply`].
pub(crate) fn write_curvature_ply(path: &Path, mesh: &Mesh, field: &CurvatureField) -> Result<()> {
    write_curvature_ply_with_quality(path, mesh, field, Quality::default())
}

/// [`CurvatureField::write_ply_with_quality`].
pub(crate) fn write_curvature_ply_with_quality(
    path: &Path,
    mesh: &Mesh,
    field: &CurvatureField,
    quality: Quality,
) -> Result<()> {
    let (mean, gauss) = (field.mean(), field.gauss());
    let chosen = quality.values(field);
    let unreliable: Vec<f64> = field
        .unreliable
        .iter()
        .map(|&u| f64::from(u8::from(u)))
        .collect();
    let attributes = [
        VertexAttribute::Scalar {
            name: "k_max",
            values: &field.k_max,
        },
        VertexAttribute::Scalar {
            name: "k_min",
            values: &field.k_min,
        },
        VertexAttribute::Scalar {
            name: "mean",
            values: &mean,
        },
        VertexAttribute::Scalar {
            name: "gauss",
            values: &gauss,
        },
        VertexAttribute::Vector {
            name: "dmax",
            values: &field.d_max,
        },
        VertexAttribute::Vector {
            name: "dmin",
            values: &field.d_min,
        },
        VertexAttribute::Vector {
            name: "n",
            values: &field.normal,
        },
        VertexAttribute::Scalar {
            name: "unreliable",
            values: &unreliable,
        },
        VertexAttribute::Scalar {
            name: "quality",
            values: &chosen,
        },
    ];
    write_ply(path, mesh, &attributes)
}

impl CurvatureField {
    /// Write `mesh` as binary PLY with the double vertex properties `k_max`, `k_min`,
    /// `mean`, `gauss`, `dmax_x/y/z`, `dmin_x/y/z`, `n_x/y/z`, `unreliable` (1 or 0)
    /// and `quality`: the quantity [`Quality::default`] chooses, under the name that
    /// MeshLab and pymeshlab colour and filter by.
    pub fn write_ply(&self, path: &Path, mesh: &Mesh) -> Result<()> {
        write_curvature_ply(path, mesh, self)
    }

    /// [`CurvatureField::write_ply`] with the `quality` property holding the quantity that
    /// `quality` chooses.
    pub fn write_ply_with_quality(&self, path: &Path, mesh: &Mesh, quality: Quality) -> Result<()> {
        write_curvature_ply_with_quality(path, mesh, self, quality)
    }
}

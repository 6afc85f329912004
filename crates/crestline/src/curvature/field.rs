//! The per-vertex curvature field every estimator produces.

use rayon::prelude::*;

use crate::mesh::{Mesh, VertexId};
use crate::{Result, Space, Vector};

use super::PrincipalCurvatures;

/// Principal curvatures, directions and normals at every vertex of a mesh, stored
/// as one array per quantity (indexed by [`VertexId`]).
#[derive(Clone, Debug, Default)]
pub struct CurvatureField {
    /// The larger principal curvature (algebraically) per vertex.
    pub k_max: Vec<f64>,
    /// The smaller principal curvature (algebraically) per vertex.
    pub k_min: Vec<f64>,
    /// Unit direction of `k_max`, defined up to sign.
    pub d_max: Vec<Vector>,
    /// Unit direction of `k_min`, defined up to sign; `(d_max, d_min, normal)` is
    /// right-handed.
    pub d_min: Vec<Vector>,
    /// The unit normal the estimator used (outward).
    pub normal: Vec<Vector>,
    /// Vertices whose values are not to be trusted: on the boundary, where the
    /// estimator had too little data, or where its estimate was not finite or an
    /// outlier and was replaced (`super::repair_outliers`).
    pub unreliable: Vec<bool>,
    /// Extremalities `[e_max, e_min]` per vertex, where the estimator gives them
    /// directly (e.g. [`super::JetFit`], from the third-order terms of its fitted
    /// height function): e_max = ∇k_max · d_max and e_min = ∇k_min · d_min
    /// (Hildebrandt, Polthier, Wardetzky 2005, eq. 4, in the smooth setting), with
    /// the signs of the directions stored in [`Self::d_max`] and [`Self::d_min`]:
    /// flipping a direction flips its extremality. `None` where the estimator only
    /// gives curvature; consumers then differentiate the curvature across the mesh
    /// (`crate::ridges::extremality::extremality`).
    pub extremality: Option<[Vec<f64>; 2]>,
    /// Where the estimator fits a surface to the vertices around each one (e.g.
    /// [`super::JetFit`]): the root mean square distance of those vertices from the
    /// fitted surface, relative to the radius of the neighbourhood fitted
    /// (dimensionless). Near 0 on a clean smooth mesh, it grows with noise: the
    /// extremality tracer smooths fitted extremalities in proportion
    /// ([`crate::ridges::ExtremalityTracer`]).
    pub fit_residual: Option<Vec<f64>>,
}

impl CurvatureField {
    /// The field of the same surface with its positions converted from frame
    /// `from` to `to` (a half turn about z when they differ): the curvatures stay,
    /// the directions and normals turn with the surface.
    pub fn in_space(&self, from: Space, to: Space) -> CurvatureField {
        let turn = |vectors: &[Vector]| -> Vec<Vector> {
            vectors.iter().map(|v| from.convert_vector(v, to)).collect()
        };
        CurvatureField {
            d_max: turn(&self.d_max),
            d_min: turn(&self.d_min),
            normal: turn(&self.normal),
            ..self.clone()
        }
    }

    /// The field of `n` vertices whose values at vertex `v` are
    /// `estimate(v) = (curvatures, normal, unreliable)`, evaluated in parallel and
    /// written straight into the field's arrays.
    pub fn from_fn<F>(n: usize, estimate: F) -> CurvatureField
    where
        F: Fn(VertexId) -> (PrincipalCurvatures, Vector, bool) + Sync,
    {
        let mut field = CurvatureField {
            k_max: vec![0.0; n],
            k_min: vec![0.0; n],
            d_max: vec![Vector::zeros(); n],
            d_min: vec![Vector::zeros(); n],
            normal: vec![Vector::zeros(); n],
            unreliable: vec![false; n],
            extremality: None,
            fit_residual: None,
        };
        (
            &mut field.k_max,
            &mut field.k_min,
            &mut field.d_max,
            &mut field.d_min,
            &mut field.normal,
            &mut field.unreliable,
        )
            .into_par_iter()
            .enumerate()
            .for_each(|(v, (k_max, k_min, d_max, d_min, normal, unreliable))| {
                let (k, n, flag) = estimate(VertexId(v as u32));
                (*k_max, *k_min, *d_max, *d_min, *normal, *unreliable) =
                    (k.k_max, k.k_min, k.d_max, k.d_min, n, flag);
            });
        field
    }

    /// Multiply both principal curvatures by `factor` (e.g. 2^k for a field
    /// estimated on the mesh scaled by 2^k) and the extremalities, derivatives of
    /// curvature along the surface, by `factor²`; directions and normals are
    /// unchanged.
    pub fn scale_curvature(&mut self, factor: f64) {
        for k in self.k_max.iter_mut().chain(&mut self.k_min) {
            *k *= factor;
        }
        for e in self.extremality.iter_mut().flatten().flatten() {
            *e *= factor * factor;
        }
        // Extremalities scale with the square of the factor and can leave f64's
        // range where the curvature does not (a mesh of size 1e-160): then they
        // are dropped, and consumers differentiate the curvature instead.
        let overflowed = self
            .extremality
            .iter()
            .flatten()
            .flatten()
            .any(|e| !e.is_finite());
        if overflowed {
            self.extremality = None;
        }
    }

    /// Reverse the direction `d_max` (`max`) or `d_min` (`!max`) at vertex `v`,
    /// and with it the sign of its extremality, if the field has extremalities:
    /// an equally valid field.
    pub fn flip_direction(&mut self, v: VertexId, max: bool) {
        let (d, slot) = if max {
            (&mut self.d_max, 0)
        } else {
            (&mut self.d_min, 1)
        };
        d[v.idx()] = -d[v.idx()];
        if let Some(e) = &mut self.extremality {
            e[slot][v.idx()] = -e[slot][v.idx()];
        }
    }

    /// Number of vertices.
    pub fn len(&self) -> usize {
        self.k_max.len()
    }

    /// Whether the field has no vertices.
    pub fn is_empty(&self) -> bool {
        self.k_max.is_empty()
    }

    /// The principal curvatures and directions at `v`.
    pub fn at(&self, v: VertexId) -> PrincipalCurvatures {
        let i = v.idx();
        PrincipalCurvatures {
            k_max: self.k_max[i],
            k_min: self.k_min[i],
            d_max: self.d_max[i],
            d_min: self.d_min[i],
        }
    }

    /// Mean curvature (k_max + k_min) / 2 per vertex.
    pub fn mean(&self) -> Vec<f64> {
        self.k_max
            .iter()
            .zip(&self.k_min)
            .map(|(a, b)| 0.5 * (a + b))
            .collect()
    }

    /// Gaussian curvature k_max k_min per vertex.
    pub fn gauss(&self) -> Vec<f64> {
        self.k_max
            .iter()
            .zip(&self.k_min)
            .map(|(a, b)| a * b)
            .collect()
    }

    /// Curvedness √((k_max² + k_min²) / 2) per vertex (Koenderink).
    pub fn curvedness(&self) -> Vec<f64> {
        self.k_max
            .iter()
            .zip(&self.k_min)
            .map(|(a, b)| (0.5 * (a * a + b * b)).sqrt())
            .collect()
    }

    /// Check that the field fits `mesh` and holds only finite values: the contract
    /// every estimator must meet before later stages use its output.
    pub fn check(&self, mesh: &Mesh) -> Result<()> {
        let n = mesh.vertex_count();
        let lengths = [
            self.k_min.len(),
            self.d_max.len(),
            self.d_min.len(),
            self.normal.len(),
            self.unreliable.len(),
        ];
        if self.k_max.len() != n
            || lengths.iter().any(|&l| l != n)
            || self.extremality.iter().flatten().any(|e| e.len() != n)
            || self.fit_residual.as_ref().is_some_and(|r| r.len() != n)
        {
            return Err(crate::Error::Argument(format!(
                "curvature field has {} values for a mesh with {n} vertices",
                self.k_max.len()
            )));
        }
        let finite = |v: &Vector| v.iter().all(|x| x.is_finite());
        let bad = (0..n).find(|&i| {
            !self.k_max[i].is_finite()
                || !self.k_min[i].is_finite()
                || !finite(&self.d_max[i])
                || !finite(&self.d_min[i])
                || !finite(&self.normal[i])
                || self.extremality.iter().flatten().any(|e| !e[i].is_finite())
                || self
                    .fit_residual
                    .as_ref()
                    .is_some_and(|r| !r[i].is_finite())
        });
        match bad {
            Some(i) => Err(crate::Error::Mesh(format!(
                "curvature estimate at vertex {i} is not finite"
            ))),
            None => Ok(()),
        }
    }
}

/// A way of estimating curvature on a mesh. Implement it to plug a custom
/// estimator into every stage that needs curvature.
pub trait CurvatureEstimator {
    /// Estimate principal curvatures, directions and normals at every vertex.
    fn estimate(&self, mesh: &Mesh) -> Result<CurvatureField>;
}

/// Curvature computed elsewhere (by a caller's own estimator, or an earlier run),
/// served as an estimator: [`CurvatureEstimator::estimate`] returns a copy of the
/// field, checked against the mesh it is asked about.
#[derive(Clone, Debug)]
pub struct GivenCurvature(pub CurvatureField);

impl CurvatureEstimator for GivenCurvature {
    fn estimate(&self, mesh: &Mesh) -> Result<CurvatureField> {
        self.0.check(mesh)?;
        Ok(self.0.clone())
    }
}

/// The curvature another estimator gives, without the extremalities it may give
/// too ([`CurvatureField::extremality`]): the ridge tracer then differentiates the
/// curvature across the mesh (Hildebrandt, Polthier, Wardetzky 2005, eq. 4). For
/// comparing the two ways to the extremalities.
#[derive(Clone)]
pub struct WithoutExtremality(pub std::sync::Arc<dyn CurvatureEstimator + Send + Sync>);

impl CurvatureEstimator for WithoutExtremality {
    fn estimate(&self, mesh: &Mesh) -> Result<CurvatureField> {
        let mut field = self.0.estimate(mesh)?;
        field.extremality = None;
        Ok(field)
    }
}

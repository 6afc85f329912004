//! Ridge and valley lines by extremality tracing (Hildebrandt, Polthier, Wardetzky:
//! "Smooth feature lines on surface meshes", SGP 2005).
//!
//! The steps of the paper's Table 1, each in its own module:
//! 1. optional implicit smoothing of the surface ([`smoothing::presmooth_surface`]);
//! 2. principal curvatures and directions (any [`CurvatureEstimator`]), extremalities
//!    e_max, e_min (eq. 4) and regular triangles (Definition 1) ([`extremality`]);
//! 3. sign-aware implicit smoothing of the extremalities (§5.1)
//!    ([`smoothing::smooth_extremality`]);
//! 4. tracing the zero sets in regular triangles under the feature conditions (eqs. 5,
//!    6), then bridging singular triangles (§4.2) ([`trace`]);
//! 5. chaining into polylines and the strength filter ∫ k ds ≥ T ([`chain`]);
//! 6. optional fairing of the lines as space curves (§5.2) ([`fair`]).
//!
//! Ridges are maxima of k_max along its direction (convex crests); valleys are
//! minima of k_min (concave creases), with outward normals.

pub mod chain;
pub mod extremality;
pub mod fair;
pub mod smoothing;
pub mod trace;

use std::sync::Arc;

use crate::curvature::{estimate_curvature, CurvatureEstimator, CurvatureField, ShapeOperator};
use crate::lines::{FeatureLines, LineExtractor, LineKind, Polyline};
use crate::mesh::Mesh;
use crate::progress::{stage, Observer, Silent};
use crate::{Error, Point, Result};

use extremality::{extremality, regular_faces, Principal};
use trace::{Extremality, LinePoint};

/// Which lines to extract.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Kinds {
    Ridges,
    Valleys,
    #[default]
    Both,
}

impl Kinds {
    fn fields(self) -> &'static [Principal] {
        match self {
            Kinds::Ridges => &[Principal::Max],
            Kinds::Valleys => &[Principal::Min],
            Kinds::Both => &[Principal::Max, Principal::Min],
        }
    }
}

/// Fairing of the traced lines as space curves.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Fairing {
    /// Number of λ|μ smoothing iterations.
    pub iterations: usize,
    /// How far a point may move, in mean edge lengths.
    pub max_distance: f64,
}

impl Default for Fairing {
    fn default() -> Self {
        Fairing {
            iterations: 10,
            max_distance: 0.5,
        }
    }
}

/// Ridge and valley lines by extremality tracing, with every option of the paper.
/// The defaults give clean lines on a clean irregular mesh: 3 smoothing steps of
/// τ = 2 and threshold 2 (see the crate's design notes for the measurements).
#[derive(Clone)]
pub struct ExtremalityTracer {
    /// Curvature estimator ([`ShapeOperator`] by default).
    pub estimator: Arc<dyn CurvatureEstimator + Send + Sync>,
    pub kinds: Kinds,
    /// Implicit smoothing steps of the extremalities.
    pub smooth_steps: usize,
    /// Time step τ of extremality smoothing, in units of the mean edge length squared.
    pub smooth_time: f64,
    /// Keep connected lines with ∫ k ds ≥ this (dimensionless).
    pub threshold: f64,
    /// Implicit smoothing steps of the surface before curvature estimation; lines
    /// are traced on the smoothed surface and placed back on the input mesh.
    pub presmooth_steps: usize,
    /// Optional fairing of the lines as space curves.
    pub fairing: Option<Fairing>,
    /// Optional per-vertex factors for inhomogeneous extremality smoothing (§6).
    pub smoothing_weights: Option<Vec<f64>>,
    /// Apply the feature conditions (eqs. 5, 6: maxima of k_max where it dominates
    /// in magnitude, minima of k_min likewise). Off, every extremal line of either
    /// curvature is traced, maxima and minima alike (the generic ridges of
    /// Porteous; e.g. all three principal ellipses of an ellipsoid, where the
    /// conditions keep only the sharpest one).
    pub feature_conditions: bool,
}

impl Default for ExtremalityTracer {
    fn default() -> Self {
        ExtremalityTracer {
            estimator: Arc::new(ShapeOperator),
            kinds: Kinds::Both,
            smooth_steps: 3,
            smooth_time: 2.0,
            threshold: 2.0,
            presmooth_steps: 0,
            fairing: None,
            smoothing_weights: None,
            feature_conditions: true,
        }
    }
}

impl LineExtractor for ExtremalityTracer {
    fn extract(&self, mesh: &Mesh) -> Result<FeatureLines> {
        self.trace(mesh, &mut Silent)
    }
}

impl ExtremalityTracer {
    /// Extract the lines of `mesh`, recording stage timings, the share of singular
    /// triangles per field and line counts in `report`.
    pub fn trace(&self, mesh: &Mesh, observer: &mut dyn Observer) -> Result<FeatureLines> {
        self.check()?;
        let smoothed = stage(observer, "presmooth", || self.presmoothed(mesh))?;
        let work = smoothed.as_ref().unwrap_or(mesh);
        let field = stage(observer, "curvature", || {
            estimate_curvature(work, self.estimator.as_ref())
        })?;
        let h = mesh.mean_edge_length();
        let mut lines = FeatureLines::new(String::new());
        let mut smoother = smoothing::ExtremalitySmoother::new(
            work,
            self.smooth_time,
            self.smoothing_weights.as_deref(),
        )?;
        for &which in self.kinds.fields() {
            for line in self.trace_field(work, &field, which, mesh, &mut smoother, observer)? {
                lines.push(line);
            }
        }
        if let Some(fairing) = self.fairing {
            stage(observer, "fairing", || {
                for line in &mut lines.lines {
                    fair::fair_polyline(
                        &mut line.points,
                        line.closed,
                        fairing.iterations,
                        fairing.max_distance * h,
                    );
                }
            });
        }
        observer.count("lines", lines.len());
        observer.count("ridges", lines.of_kind(LineKind::Ridge).count());
        observer.count("valleys", lines.of_kind(LineKind::Valley).count());
        observer.measure("total_length", lines.total_length());
        Ok(lines)
    }

    fn check(&self) -> Result<()> {
        let bad = |what: &str, value: f64| {
            Error::Argument(format!("{what} must be finite and positive, got {value}"))
        };
        if !(self.smooth_time.is_finite() && self.smooth_time > 0.0) {
            return Err(bad("smoothing time", self.smooth_time));
        }
        if !(self.threshold.is_finite() && self.threshold >= 0.0) {
            return Err(bad("threshold", self.threshold));
        }
        if let Some(f) = self.fairing {
            if !(f.max_distance.is_finite() && f.max_distance >= 0.0) {
                return Err(bad("fairing distance", f.max_distance));
            }
        }
        const MAX_STEPS: usize = 1000;
        if self.smooth_steps > MAX_STEPS || self.presmooth_steps > MAX_STEPS {
            return Err(Error::Argument(format!(
                "at most {MAX_STEPS} smoothing steps"
            )));
        }
        Ok(())
    }

    /// The smoothed surface, if pre-smoothing is asked for.
    fn presmoothed(&self, mesh: &Mesh) -> Result<Option<Mesh>> {
        if self.presmooth_steps == 0 {
            return Ok(None);
        }
        Ok(Some(smoothing::presmooth_surface(
            mesh,
            self.presmooth_steps,
        )?))
    }

    /// Extremality, smoothing, tracing and chaining of one field on `work`; line
    /// points are placed on `input` (the same edge and parameter).
    fn trace_field(
        &self,
        work: &Mesh,
        field: &CurvatureField,
        which: Principal,
        input: &Mesh,
        smoother: &mut smoothing::ExtremalitySmoother<'_>,
        observer: &mut dyn Observer,
    ) -> Result<Vec<Polyline>> {
        let (name, kind) = match which {
            Principal::Max => ("ridges", LineKind::Ridge),
            Principal::Min => ("valleys", LineKind::Valley),
        };
        let directions = which.directions(field);
        let mut values = stage(observer, &format!("{name}: extremality"), || {
            extremality(work, field, which)
        });
        stage(observer, &format!("{name}: smoothing"), || {
            smoother.smooth(directions, &mut values, self.smooth_steps)
        })?;
        let regular = regular_faces(work, directions);
        let singular = regular.iter().filter(|&&r| !r).count();
        observer.measure(
            &format!("{name}_singular_share"),
            singular as f64 / regular.len() as f64,
        );
        let ext = Extremality::new(which, values, field, &regular, self.feature_conditions);
        let segments = stage(observer, &format!("{name}: tracing"), || {
            trace::trace(work, field, &ext)
        });
        let place = |p: LinePoint| place(input, work, field, &ext, p);
        let chains = stage(observer, &format!("{name}: chaining"), || {
            chain::chain(&segments, place, self.threshold)
        });
        Ok(chains
            .into_iter()
            .map(|c| {
                let points = c.points.iter().map(|&p| place(p).0).collect();
                Polyline::new(kind, c.closed, c.strength, points)
            })
            .collect())
    }
}

/// Position of a line point on the input mesh and the strength integrand there
/// (k_max for ridges, |k_min| for valleys), interpolated from `work`'s curvature.
fn place(
    input: &Mesh,
    work: &Mesh,
    field: &CurvatureField,
    ext: &Extremality<'_>,
    p: LinePoint,
) -> (Point, f64) {
    let integrand = |v: usize| match ext.which {
        Principal::Max => field.k_max[v],
        Principal::Min => field.k_min[v].abs(),
    };
    match p {
        LinePoint::Edge(e) => {
            let [a, b] = input.edge_vertices(e);
            let t = ext.crossing(work, e).unwrap_or(0.5);
            let point = input.position(a) + (input.position(b) - input.position(a)) * t;
            (
                point,
                (1.0 - t) * integrand(a.idx()) + t * integrand(b.idx()),
            )
        }
        LinePoint::Face(f) => {
            let corners = input.face_vertices(f);
            let [a, b, c] = corners.map(|v| input.position(v).coords);
            let k = corners.iter().map(|v| integrand(v.idx())).sum::<f64>() / 3.0;
            (Point::from((a + b + c) / 3.0), k)
        }
    }
}

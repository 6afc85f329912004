//! Plugging a curvature estimator written outside the crate into crestline.
//!
//! The estimator below fits the second fundamental form to the normal curvatures of
//! the edges around each vertex (κ along an edge from the osculating circle through
//! both ends: κ = 2⟨n, p − q⟩ / |p − q|²), by least squares in the tangent plane.
//! It goes through the same entry point as the built-in estimators
//! ([`estimate_curvature`], which checks the output) and the same writer.
//!
//! `cargo run --release --example custom_estimator [-- --output OUT.ply]`
//! (an option rather than a bare path: `cargo test FILTER` runs this example
//! with the filter as its argument)

use crestline::curvature::{
    estimate_curvature, CurvatureEstimator, CurvatureField, JetFit, PrincipalCurvatures,
    ShapeOperator,
};
use crestline::mesh::generate::{self, Sampling};
use crestline::mesh::Mesh;
use crestline::Vector;
use nalgebra::{Matrix3, SMatrix, SVector};

/// Least-squares fit of the shape operator to edge normal curvatures.
struct EdgeCurvatureFit;

impl CurvatureEstimator for EdgeCurvatureFit {
    fn estimate(&self, mesh: &Mesh) -> crestline::Result<CurvatureField> {
        Ok(CurvatureField::from_fn(mesh.vertex_count(), |v| {
            let normal = mesh.area_weighted_normal(v);
            let (t1, t2) = tangent_basis(&normal);
            // Fit κ(t) = a u² + 2 b u w + c w² for tangent t = (u, w).
            let mut lhs = SMatrix::<f64, 3, 3>::zeros();
            let mut rhs = SVector::<f64, 3>::zeros();
            for w in mesh.neighbors(v) {
                let d = mesh.position(v) - mesh.position(w);
                let kappa = 2.0 * normal.dot(&d) / d.norm_squared();
                let tangent = Vector::new(d.dot(&t1), d.dot(&t2), 0.0).normalize();
                let row = SVector::<f64, 3>::new(
                    tangent.x * tangent.x,
                    2.0 * tangent.x * tangent.y,
                    tangent.y * tangent.y,
                );
                lhs += row * row.transpose();
                rhs += row * kappa;
            }
            let [a, b, c] = match lhs.cholesky() {
                Some(cholesky) => cholesky.solve(&rhs).into(),
                None => [0.0; 3],
            };
            // Back to a 3×3 operator in world coordinates.
            let frame = Matrix3::from_columns(&[t1, t2, normal]);
            let local = Matrix3::new(a, b, 0.0, b, c, 0.0, 0.0, 0.0, 0.0);
            let operator = frame * local * frame.transpose();
            let k = PrincipalCurvatures::from_tangent_operator(&operator, &normal);
            (k, normal, mesh.is_boundary_vertex(v))
        }))
    }
}

fn main() -> crestline::Result<()> {
    let surface = generate::ellipsoid([1.0, 0.7, 0.45], 20_000, Sampling::jittered(3))?;
    let estimators: [(&str, &dyn CurvatureEstimator); 3] = [
        ("edge fit (this example)", &EdgeCurvatureFit),
        ("shape operator", &ShapeOperator),
        ("jet fit", &JetFit::default()),
    ];
    println!(
        "jittered ellipsoid, {} vertices",
        surface.mesh.vertex_count()
    );
    for (name, estimator) in estimators {
        let field = estimate_curvature(&surface.mesh, estimator)?;
        let error = field.relative_rms_error(&surface.exact).unwrap_or(f64::NAN);
        println!("  {name:<24} relative RMS error {:6.2}%", 100.0 * error);
    }
    if let Some(out) = std::env::args().skip_while(|a| a != "--output").nth(1) {
        let field = estimate_curvature(&surface.mesh, &EdgeCurvatureFit)?;
        field.write_ply(out.as_ref(), &surface.mesh)?;
        println!("wrote {out}");
    }
    Ok(())
}

/// Two unit tangents that, with the unit normal `n`, make a right-handed
/// orthonormal frame: `n × z`, or `n × x` where `n` is nearly along z.
fn tangent_basis(n: &Vector) -> (Vector, Vector) {
    let t1 = n
        .cross(&Vector::z())
        .try_normalize(0.1)
        .unwrap_or_else(|| n.cross(&Vector::x()).normalize());
    (t1, n.cross(&t1))
}

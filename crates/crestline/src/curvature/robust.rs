//! Curvature estimates that degrade instead of failing: non-finite values and
//! outliers are flagged unreliable and replaced by the median of their
//! neighbourhood, so one collapsed star (a sliver fan in a scan, a vertex pushed
//! far out) never stops a run.
//!
//! A value k(v) of either principal curvature is an outlier when
//! |k(v) − m| > C · max(1.4826 · MAD, 1 / ℓ), where m and MAD are the median and
//! the median absolute deviation from it of the finite values at the 1-ring of v
//! (v excluded), 1.4826 · MAD the usual robust estimate of a standard deviation,
//! ℓ the median length of the edges at v and C = [`OUTLIER_SCALES`]. The floor 1/ℓ
//! keeps features: a discrete curvature resolved by edges of length ℓ is at most a
//! few times 1/ℓ (a sharp crease with a dihedral angle of π/2 gives about 1.5/ℓ), so
//! on a regular ring, where MAD ≈ 0, only values more than C/ℓ from the median are
//! flagged: the numerical blow-ups of degenerate stars, which reach 10⁴–10⁵/ℓ.

use rayon::prelude::*;

use crate::mesh::geometry::robust_norm;
use crate::mesh::{Mesh, VertexId};
use crate::Vector;

use super::{symmetric_2x2_eigen, tangent_basis, CurvatureField};

/// C: how many robust scales a curvature may lie from the median of its 1-ring.
/// Chosen well above the spread of estimates on noisy scans (a few scales) and
/// well below the blow-ups of degenerate stars (thousands).
pub const OUTLIER_SCALES: f64 = 10.0;

/// 1.4826 · MAD estimates the standard deviation of normally distributed values.
const MAD_TO_SIGMA: f64 = 1.4826;

/// How the built-in estimators run: `estimate_unit` on `mesh` in a frame free of
/// overflow and underflow ([`Mesh::in_unit_frame`]), curvatures scaled back, then
/// non-finite and outlying values flagged and repaired ([`repair_outliers`]).
pub(super) fn estimate_robustly(
    mesh: &Mesh,
    estimate_unit: impl FnOnce(&Mesh) -> CurvatureField,
) -> CurvatureField {
    let (unit, factor) = mesh.in_unit_frame();
    let mut field = estimate_unit(&unit);
    field.scale_curvature(factor);
    repair_outliers(mesh, &mut field);
    field
}

/// Flag as unreliable every vertex of `field` (estimated on `mesh`) with a
/// non-finite value or an outlying curvature (see the module documentation), and
/// replace its values: curvatures by the medians over its reliable neighbours, the
/// normal (if not finite) by their mean normal, the directions by the mean axis of
/// theirs in the tangent plane (the dominant axis of their d dᵀ, whatever the
/// order of the neighbours), and extremalities, if the field has them, by the
/// medians of its reliable neighbours' (each read with the sign of the vertex's
/// own direction). Returns the number of vertices repaired.
pub fn repair_outliers(mesh: &Mesh, field: &mut CurvatureField) -> usize {
    let bad: Vec<bool> = mesh
        .par_vertices()
        .map(|v| !is_finite_at(field, v.idx()) || is_outlier(mesh, field, v))
        .collect();
    let repairs: Vec<(usize, Repair)> = mesh
        .par_vertices()
        .filter(|v| bad[v.idx()])
        .map(|v| (v.idx(), repair(mesh, field, &bad, v)))
        .collect();
    for &(i, ref r) in &repairs {
        field.k_max[i] = r.k_max;
        field.k_min[i] = r.k_min;
        field.normal[i] = r.normal;
        field.d_max[i] = r.d_max;
        field.d_min[i] = r.d_min;
        field.unreliable[i] = true;
    }
    // The extremalities belong to the replaced directions: take them from the
    // neighbours too.
    if field.extremality.is_some() {
        let known: Vec<bool> = bad.iter().map(|b| !b).collect();
        fill_extremality(mesh, field, &known);
    }
    repairs.len()
}

/// Whether every value of the field at vertex `i` is finite.
fn is_finite_at(field: &CurvatureField, i: usize) -> bool {
    let finite = |v: &Vector| v.iter().all(|x| x.is_finite());
    field.k_max[i].is_finite()
        && field.k_min[i].is_finite()
        && finite(&field.d_max[i])
        && finite(&field.d_min[i])
        && finite(&field.normal[i])
        && field.extremality.iter().flatten().all(|e| e[i].is_finite())
}

thread_local! {
    /// Scratch lists of one vertex's ring values, reused from vertex to vertex.
    static SCRATCH: std::cell::RefCell<[Vec<f64>; 2]> = const {
        std::cell::RefCell::new([Vec::new(), Vec::new()])
    };
}

/// Whether k_max or k_min at `v` lies more than [`OUTLIER_SCALES`] robust scales
/// from the median of its 1-ring (module documentation). The scale is at least
/// one over the median length of the edges at `v`.
fn is_outlier(mesh: &Mesh, field: &CurvatureField, v: VertexId) -> bool {
    !surely_inlying(mesh, field, v) && outlying_by_medians(mesh, field, v)
}

/// The test of [`is_outlier`] itself, with the medians of the module
/// documentation.
fn outlying_by_medians(mesh: &Mesh, field: &CurvatureField, v: VertexId) -> bool {
    SCRATCH.with_borrow_mut(|[values, deviations]| {
        values.clear();
        values.extend(
            mesh.outgoing(v)
                .map(|h| robust_norm(&mesh.halfedge_vector(h))),
        );
        let floor = median(values).map_or(0.0, |l| 1.0 / l);
        [&field.k_max, &field.k_min]
            .into_iter()
            .any(|k| is_outlying(mesh, k, v, floor, values, deviations))
    })
}

/// A test, without medians, that neither curvature at `v` is an outlier, passed
/// by nearly every vertex of a smooth mesh: the median of the ring lies between its
/// least and greatest finite values, and the floor of the scale is at least one
/// over the longest edge at `v`, so a value within [`OUTLIER_SCALES`] / (longest
/// edge) of every ring value is within the outlier bound of [`is_outlying`]. A
/// ring without finite values is left to the full test.
fn surely_inlying(mesh: &Mesh, field: &CurvatureField, v: VertexId) -> bool {
    let longest = mesh
        .outgoing(v)
        .map(|h| robust_norm(&mesh.halfedge_vector(h)))
        .fold(0.0, f64::max);
    let bound = OUTLIER_SCALES / longest;
    [&field.k_max, &field.k_min].into_iter().all(|k| {
        let (low, high) = mesh
            .neighbors(v)
            .map(|w| k[w.idx()])
            .filter(|x| x.is_finite())
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), x| {
                (lo.min(x), hi.max(x))
            });
        let value = k[v.idx()];
        low <= high && value - low <= bound && high - value <= bound
    })
}

/// Whether `k` at `v` lies more than [`OUTLIER_SCALES`] times the larger of its
/// ring's robust scale and `floor` from the ring's median (the values and
/// deviations lists are scratch space). A vertex without finite neighbours is not
/// an outlier.
fn is_outlying(
    mesh: &Mesh,
    k: &[f64],
    v: VertexId,
    floor: f64,
    values: &mut Vec<f64>,
    deviations: &mut Vec<f64>,
) -> bool {
    values.clear();
    values.extend(
        mesh.neighbors(v)
            .map(|w| k[w.idx()])
            .filter(|x| x.is_finite()),
    );
    let Some(centre) = median(values) else {
        return false;
    };
    deviations.clear();
    deviations.extend(values.iter().map(|x| (x - centre).abs()));
    let spread = MAD_TO_SIGMA * median(deviations).unwrap_or(0.0);
    (k[v.idx()] - centre).abs() > OUTLIER_SCALES * spread.max(floor)
}

/// The median of `values` (reordered), the mean of the middle two for an even
/// count; `None` if empty.
pub(super) fn median(values: &mut [f64]) -> Option<f64> {
    let n = values.len();
    if n == 0 {
        return None;
    }
    let (_, &mut upper, _) = values.select_nth_unstable_by(n / 2, f64::total_cmp);
    if n % 2 == 1 {
        return Some(upper);
    }
    let lower = values[..n / 2]
        .iter()
        .copied()
        .fold(f64::NEG_INFINITY, f64::max);
    Some(0.5 * (lower + upper))
}

/// Give every vertex not marked `known` the medians of the extremalities
/// ([`CurvatureField::extremality`]) of its known neighbours, each read with the
/// sign of the vertex's own direction (σ_pq e(q), σ_pq = sign⟨d(p), d(q)⟩), and of
/// their fit residuals ([`CurvatureField::fit_residual`]); 0 if it has none. Does
/// nothing to a field without extremalities.
pub(super) fn fill_extremality(mesh: &Mesh, field: &mut CurvatureField, known: &[bool]) {
    let Some(mut extremality) = field.extremality.take() else {
        return;
    };
    let ring_median = |v: VertexId, value: &dyn Fn(usize) -> f64| {
        let mut ring: Vec<f64> = mesh
            .neighbors(v)
            .map(|w| w.idx())
            .filter(|&q| known[q])
            .map(value)
            .collect();
        median(&mut ring).unwrap_or(0.0)
    };
    let directions = [&field.d_max, &field.d_min];
    for (e, d) in extremality.iter_mut().zip(directions) {
        let filled: Vec<(usize, f64)> = mesh
            .par_vertices()
            .filter(|v| !known[v.idx()])
            .map(|v| {
                let p = v.idx();
                (p, ring_median(v, &|q| d[p].dot(&d[q]).signum() * e[q]))
            })
            .collect();
        for (p, value) in filled {
            e[p] = value;
        }
    }
    if let Some(residual) = &mut field.fit_residual {
        let filled: Vec<(usize, f64)> = mesh
            .par_vertices()
            .filter(|v| !known[v.idx()])
            .map(|v| (v.idx(), ring_median(v, &|q| residual[q])))
            .collect();
        for (p, value) in filled {
            residual[p] = value;
        }
    }
    field.extremality = Some(extremality);
}

/// Replacement values of a flagged vertex.
struct Repair {
    k_max: f64,
    k_min: f64,
    normal: Vector,
    d_max: Vector,
    d_min: Vector,
}

/// The replacement values of flagged vertex `v` from its neighbours that are not
/// flagged (`bad`). Medians of k_max and k_min keep k_max ≥ k_min. Without such
/// neighbours the curvatures are 0 and the frame is built from the normal alone.
fn repair(mesh: &Mesh, field: &CurvatureField, bad: &[bool], v: VertexId) -> Repair {
    let good: Vec<usize> = mesh
        .neighbors(v)
        .map(|w| w.idx())
        .filter(|&w| !bad[w])
        .collect();
    let median_of = |k: &[f64]| {
        let mut values: Vec<f64> = good.iter().map(|&w| k[w]).collect();
        median(&mut values).unwrap_or(0.0)
    };
    let normal = repaired_normal(field, &good, v.idx());
    let d_max = mean_tangent_direction(good.iter().map(|&w| &field.d_max[w]), &normal)
        .unwrap_or_else(|| tangent_direction(&field.d_max[v.idx()], &normal));
    Repair {
        k_max: median_of(&field.k_max),
        k_min: median_of(&field.k_min),
        normal,
        d_max,
        d_min: normal.cross(&d_max),
    }
}

/// The normal at `i` if finite, else the normalised sum of the normals at the
/// `good` neighbours, else +z.
fn repaired_normal(field: &CurvatureField, good: &[usize], i: usize) -> Vector {
    let own = field.normal[i];
    if own.iter().all(|x| x.is_finite()) && own.norm() > 0.5 {
        return own;
    }
    let sum: Vector = good.iter().map(|&w| field.normal[w]).sum();
    sum.try_normalize(f64::MIN_POSITIVE)
        .unwrap_or_else(Vector::z)
}

/// The mean axis of the line field `directions` (each direction as good as its
/// opposite) in the plane normal to `normal`: the dominant eigenvector of the sum
/// of their projections' outer products d dᵀ, which does not depend on the order
/// of the directions (nor on the numbering of the mesh they come from). `None`
/// if that sum has no dominant axis (no directions, or directions that cancel).
fn mean_tangent_direction<'a>(
    directions: impl Iterator<Item = &'a Vector>,
    normal: &Vector,
) -> Option<Vector> {
    let (t1, t2) = tangent_basis(normal);
    let [mut a, mut b, mut c] = [0.0; 3];
    for d in directions.filter(|d| d.iter().all(|x| x.is_finite())) {
        let (p, q) = (d.dot(&t1), d.dot(&t2));
        a += p * p;
        b += p * q;
        c += q * q;
    }
    let (major, minor, [x, y]) = symmetric_2x2_eigen(a, b, c);
    (major > minor + 1e-12 * major.abs()).then(|| t1 * x + t2 * y)
}

/// `reference` projected into the plane normal to `normal` and normalised, or a
/// tangent of `normal` if that vanishes.
fn tangent_direction(reference: &Vector, normal: &Vector) -> Vector {
    let projected = reference - normal * normal.dot(reference);
    projected
        .try_normalize(1e-12)
        .filter(|d| d.iter().all(|x| x.is_finite()))
        .unwrap_or_else(|| tangent_basis(normal).0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::curvature::{CurvatureEstimator, ShapeOperator};

    /// The bundled small bunny, a real scan with irregular triangles.
    fn bunny() -> Mesh {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../meshes/bunny_small.obj");
        let soup = crate::io::read_mesh(std::path::Path::new(path)).unwrap();
        Mesh::from_soup(soup).unwrap().0
    }

    #[test]
    fn the_quick_test_never_clears_an_outlier_and_clears_most_vertices() {
        let mesh = bunny();
        let mut field = ShapeOperator.estimate(&mesh).unwrap();
        // Spikes of every size, from within the spread to blow-ups.
        for (n, v) in (0..mesh.vertex_count()).step_by(37).enumerate() {
            field.k_max[v] += 10f64.powi(n as i32 % 7 - 1);
            field.k_min[v] -= 10f64.powi(n as i32 % 5);
        }
        let (mut cleared, mut outliers) = (0, 0);
        for v in mesh.vertices() {
            let by_medians = outlying_by_medians(&mesh, &field, v);
            let quick = surely_inlying(&mesh, &field, v);
            assert!(
                !(quick && by_medians),
                "vertex {} cleared but outlying",
                v.idx()
            );
            cleared += usize::from(quick);
            outliers += usize::from(by_medians);
        }
        assert!(outliers > 20, "{outliers}");
        assert!(
            cleared * 10 > mesh.vertex_count() * 8,
            "{cleared} of {}",
            mesh.vertex_count()
        );
    }

    #[test]
    fn the_mean_axis_of_directions_ignores_their_order_and_signs() {
        let normal = Vector::new(0.2, -0.3, 1.0).normalize();
        let (t1, t2) = tangent_basis(&normal);
        // Directions about 30° from t1 in the tangent plane, some tilted out of
        // it, some reversed.
        let axis = t1 * 30f64.to_radians().cos() + t2 * 30f64.to_radians().sin();
        let spread = [-0.2, 0.1, 0.15, -0.05, 0.0];
        let directions: Vec<Vector> = spread
            .iter()
            .enumerate()
            .map(|(k, &a)| {
                let d = (axis + (t2 * 0.866 - t1 * 0.5) * a + normal * 0.1).normalize();
                if k % 2 == 0 {
                    -d
                } else {
                    d
                }
            })
            .collect();
        let mean = mean_tangent_direction(directions.iter(), &normal).unwrap();
        let mut reordered = directions.clone();
        reordered.reverse();
        reordered.swap(0, 2);
        let flipped: Vec<Vector> = reordered.iter().map(|d| -d).collect();
        for other in [&reordered, &flipped] {
            let again = mean_tangent_direction(other.iter(), &normal).unwrap();
            assert!((mean.dot(&again).abs() - 1.0).abs() < 1e-14);
        }
        assert!(mean.dot(&normal).abs() < 1e-14);
        assert!(mean.dot(&axis).abs() > 0.999, "{mean} against {axis}");
        // No directions, or two perpendicular ones, have no mean axis.
        assert!(mean_tangent_direction([].iter(), &normal).is_none());
        assert!(mean_tangent_direction([t1, t2].iter(), &normal).is_none());
    }
}

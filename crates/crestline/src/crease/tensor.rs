//! The crease condition of Schultz, Theisel and Seidel (2010), §4.1–4.2, at one
//! point: the eigenframe of the Hessian and the transformed tensor T whose fixed
//! points g = T g are the ridge points and the degenerate points.

use nalgebra::{Matrix3, SymmetricEigen};

use crate::Vector;

/// The Hessian's eigenvalues λ1 ≥ λ2 ≥ λ3 and the unit eigenvector e3 of λ3.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Eigenframe {
    /// λ1 ≥ λ2 ≥ λ3.
    pub eigenvalues: [f64; 3],
    /// The eigenvector of λ3 (defined up to sign).
    pub e3: Vector,
}

impl Eigenframe {
    /// The eigen-decomposition of the symmetric `hessian`.
    pub fn of(hessian: &Matrix3<f64>) -> Eigenframe {
        let eigen = SymmetricEigen::new(*hessian);
        let mut order = [0, 1, 2];
        order.sort_by(|&a, &b| eigen.eigenvalues[b].total_cmp(&eigen.eigenvalues[a]));
        Eigenframe {
            eigenvalues: order.map(|i| eigen.eigenvalues[i]),
            e3: eigen.eigenvectors.column(order[2]).into_owned(),
        }
    }

    /// λ2 − λ3: zero on the degenerate lines where a ridge may end.
    pub fn gap(&self) -> f64 {
        self.eigenvalues[1] - self.eigenvalues[2]
    }

    /// The weight λ'3 of e3 in T: 0 where the gap is at least `epsilon`, rising as
    /// (1 − gap/ε)² to 1 where λ2 = λ3.
    pub fn weight(&self, epsilon: f64) -> f64 {
        let gap = self.gap();
        if gap >= epsilon {
            0.0
        } else {
            (1.0 - gap / epsilon).powi(2)
        }
    }

    /// The transformed tensor T = e1e1ᵀ + e2e2ᵀ + λ'3 e3e3ᵀ = I − (1 − λ'3) e3e3ᵀ.
    pub fn tensor(&self, epsilon: f64) -> Matrix3<f64> {
        Matrix3::identity() - (1.0 - self.weight(epsilon)) * self.e3 * self.e3.transpose()
    }

    /// h = T g − g = (λ'3 − 1)(g·e3) e3: zero on the ridge (g·e3 = 0) and where the
    /// Hessian is degenerate, whatever the sign of λ3 (the side constraint λ3 < 0
    /// is checked apart).
    pub fn h(&self, gradient: &Vector, epsilon: f64) -> Vector {
        (self.weight(epsilon) - 1.0) * gradient.dot(&self.e3) * self.e3
    }
}

/// The similarity tr(T1ᵀT2) / (‖T1‖_F ‖T2‖_F) of two tensors, 1 for equal ones: an
/// edge is bisected while it is below the threshold θ (eq. 6).
pub fn similarity(t1: &Matrix3<f64>, t2: &Matrix3<f64>) -> f64 {
    t1.dot(t2) / (t1.norm() * t2.norm())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn eigenvalues_are_sorted_and_e3_belongs_to_the_smallest() {
        let h = Matrix3::from_diagonal(&Vector::new(-1.0, 2.0, -5.0));
        let frame = Eigenframe::of(&h);
        assert_eq!(frame.eigenvalues, [2.0, -1.0, -5.0]);
        assert!((frame.e3.z.abs() - 1.0).abs() < 1e-12);
        assert_eq!(frame.gap(), 4.0);
    }

    #[test]
    fn h_vanishes_on_the_ridge_and_at_degenerate_points() {
        let frame = Eigenframe::of(&Matrix3::from_diagonal(&Vector::new(0.0, -1.0, -4.0)));
        // g along e3 is off the ridge: h = −g there (λ'3 = 0).
        let off = frame.h(&Vector::new(0.0, 0.0, 2.0), 0.1);
        assert!((off - Vector::new(0.0, 0.0, -2.0)).norm() < 1e-12);
        // g orthogonal to e3 is on the ridge.
        assert!(frame.h(&Vector::new(1.0, 1.0, 0.0), 0.1).norm() < 1e-12);
        // λ2 = λ3: T = I and h = 0 for any g.
        let degenerate = Eigenframe::of(&Matrix3::from_diagonal(&Vector::new(0.0, -2.0, -2.0)));
        assert!(degenerate.h(&Vector::new(0.3, 0.4, 0.5), 0.1).norm() < 1e-12);
        assert!((similarity(&degenerate.tensor(0.1), &Matrix3::identity()) - 1.0).abs() < 1e-12);
    }

    #[test]
    fn the_sign_of_e3_does_not_matter() {
        let h = Matrix3::new(-3.0, 1.0, 0.5, 1.0, -1.0, 0.2, 0.5, 0.2, -2.0);
        let frame = Eigenframe::of(&h);
        let flipped = Eigenframe {
            e3: -frame.e3,
            ..frame
        };
        let g = Vector::new(0.7, -0.1, 0.4);
        assert!((frame.h(&g, 0.01) - flipped.h(&g, 0.01)).norm() < 1e-12);
        assert!((frame.tensor(0.01) - flipped.tensor(0.01)).norm() < 1e-12);
    }
}

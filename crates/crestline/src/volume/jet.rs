//! Derivatives of a scalar field at one point up to order 3, and their change of
//! coordinates from a grid's axes to the world.
//!
//! If local coordinates are `u = J (x − x₀)` (for the index axes of a volume,
//! `J = (direction · diag(spacing))⁻¹`), the chain rule gives the world derivatives
//! `∇ₓf = Jᵀ ∇ᵤf`, `Hₓ = Jᵀ Hᵤ J` and `Tₓ[i][j][k] = Σ J[a][i] J[b][j] J[c][k] Tᵤ[a][b][c]`.
//! For world lengths along orthonormal axes `J = directionᵀ`, so that
//! `g = R g_axes`, `H = R H_axes Rᵀ`.

pub use crate::differential::ThirdOrder;
use crate::differential::{isosurface_curvature, IsoCurvature};
use crate::Vector;
use nalgebra::Matrix3;

/// A scalar field's value and derivatives up to order 3 at one point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Jet {
    /// The value `f`.
    pub value: f64,
    /// The gradient `∇f`.
    pub gradient: Vector,
    /// The Hessian `∇∇f`.
    pub hessian: Matrix3<f64>,
    /// The third derivatives.
    pub third: ThirdOrder,
}

impl Jet {
    /// Principal curvatures, directions, normal and extremalities of the
    /// iso-surface through this point ([`isosurface_curvature`]); `None` where the
    /// gradient vanishes.
    pub fn isosurface_curvature(&self) -> Option<IsoCurvature> {
        isosurface_curvature(&self.gradient, &self.hessian, &self.third)
    }

    /// The jet from its 20 partial derivatives, in the order of
    /// [`crate::volume::Partial::ALL`]: `f; fx fy fz; fxx fxy fxz fyy fyz fzz;
    /// fxxx fxxy fxxz fxyy fxyz fxzz fyyy fyyz fyzz fzzz`.
    pub fn from_partials(p: &[f64; 20]) -> Jet {
        Jet {
            value: p[0],
            gradient: Vector::new(p[1], p[2], p[3]),
            hessian: hessian_from_components([p[4], p[5], p[6], p[7], p[8], p[9]]),
            third: ThirdOrder::from_components(std::array::from_fn(|n| p[10 + n])),
        }
    }

    /// The jet in coordinates `x` where the present ones are `u = J x` (see the
    /// module documentation).
    pub fn pulled_back(&self, jacobian: &Matrix3<f64>) -> Jet {
        Jet {
            value: self.value,
            gradient: jacobian.transpose() * self.gradient,
            hessian: jacobian.transpose() * self.hessian * jacobian,
            third: self.third.pulled_back(jacobian),
        }
    }
}

/// The symmetric Hessian from `xx, xy, xz, yy, yz, zz`.
pub fn hessian_from_components(c: [f64; 6]) -> Matrix3<f64> {
    let [xx, xy, xz, yy, yz, zz] = c;
    Matrix3::new(xx, xy, xz, xy, yy, yz, xz, yz, zz)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn components_are_placed_symmetrically() {
        let t = ThirdOrder::from_components(std::array::from_fn(|n| n as f64));
        assert_eq!(t.get(0, 0, 0), 0.0);
        assert_eq!(t.get(1, 0, 0), 1.0);
        assert_eq!(t.get(0, 2, 0), 2.0);
        assert_eq!(t.get(1, 1, 0), 3.0);
        assert_eq!(t.get(2, 0, 1), 4.0);
        assert_eq!(t.get(2, 2, 0), 5.0);
        assert_eq!(t.get(1, 1, 1), 6.0);
        assert_eq!(t.get(1, 2, 1), 7.0);
        assert_eq!(t.get(2, 1, 2), 8.0);
        assert_eq!(t.get(2, 2, 2), 9.0);
    }

    #[test]
    fn pull_back_by_a_rotation_matches_directional_derivatives() {
        let t = ThirdOrder::from_components([1.0, -2.0, 0.5, 3.0, 0.25, -1.0, 2.0, 0.0, 1.5, -0.5]);
        let rotation = Matrix3::new(0.0, 0.6, 0.8, 1.0, 0.0, 0.0, 0.0, 0.8, -0.6);
        // World tensor: T_w = pulled back by J = Rᵀ; directional derivative along
        // world v equals the local one along Rᵀ v.
        let world = t.pulled_back(&rotation.transpose());
        let v = Vector::new(0.3, -0.5, 0.8);
        let local = rotation.transpose() * v;
        assert!((world.directional(&v) - t.directional(&local)).abs() < 1e-12);
    }
}

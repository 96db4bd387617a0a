//! Finite rotations: the rotation vector, its exponential and logarithm, composition of a
//! spatial spin onto a rotation, and the tangent operator between the two.
//!
//! **The scheme.** At a node whose elements or links ask for finite rotations
//! ([`crate::ElementProperties::finite_rotations`]), the three rotational entries of the
//! node's displacement hold the *total rotation vector* `ψ` of the node's triad, with
//! `R = exp([ψ]×)` (Rodrigues). A correction `δ` that the solver finds for those entries is a
//! *spatial spin*: the rotation is updated by composition, `R ← exp([δ]×)·R`, and the stored
//! vector becomes `ψ ← log(exp([δ]×)·exp([ψ]×))` ([`compose`]); it is never added to `ψ`.
//! Elements that declare finite rotations return their resisting force and tangent stiffness
//! conjugate to that spin (a variation `δR = [δθ]×·R`). [`spin_from_rotation_vector`] turns a
//! variation of `ψ` into that spin for elements that differentiate with respect to `ψ`.
//!
//! **Limits.** `log` returns `|ψ| ≤ π`; a node that turns through more than half a turn has
//! its vector wrapped to the equivalent rotation (the triad is unchanged, so objective
//! elements see the same state). Nodal angular velocities and accelerations are spatial
//! vectors; the time integrator treats the incremental rotation vector of a step,
//! [`increment`] `Θ = log(R_{n+1}·R_nᵀ)`, as the step's rotational displacement increment
//! (see the solvers' driver), and the energy ledger takes it as the rotation the nodal
//! moments work on. That update is exact for rotation about a fixed axis and for isotropic
//! rotary inertia; otherwise it is first order in the step rotation.
//!
//! **Where the scheme applies.** Which nodes are finite-rotation nodes, the equation triples
//! that are composed, and the rule for partly fixed rotations (all three free, all fixed, or
//! exactly one free — composition mixes components, so two free and one fixed is refused)
//! live in [`crate::dofmap`]; anything other than an element (a nonlinear link) asks for a
//! node with [`crate::Model::mark_finite_rotation`]. Linear elements attached to such a
//! node read ψ as a small rotation (exact to first order).
//!
//! Everything here is a pure function of 3-vectors and 3×3 matrices (radians).

use crate::dual;
use nalgebra::{Matrix3, Vector3};

/// The skew-symmetric matrix `[v]×` with `[v]×·w = v × w`.
pub fn skew(v: &Vector3<f64>) -> Matrix3<f64> {
    Matrix3::new(0.0, -v.z, v.y, v.z, 0.0, -v.x, -v.y, v.x, 0.0)
}

/// The axial vector of the skew part of `m`: `axial([v]×) = v`.
pub fn axial(m: &Matrix3<f64>) -> Vector3<f64> {
    Vector3::new(
        0.5 * (m[(2, 1)] - m[(1, 2)]),
        0.5 * (m[(0, 2)] - m[(2, 0)]),
        0.5 * (m[(1, 0)] - m[(0, 1)]),
    )
}

/// Rodrigues' formula: `exp([ψ]×) = I + sin φ/φ·[ψ]× + (1 − cos φ)/φ²·[ψ]×²`, φ = |ψ|.
/// Series for small φ keep full precision near zero.
pub fn exp(psi: &Vector3<f64>) -> Matrix3<f64> {
    let phi2 = psi.norm_squared();
    let (a, b) = if phi2 < 1e-8 {
        // sin φ/φ and (1 − cos φ)/φ² to O(φ⁴).
        (1.0 - phi2 / 6.0 + phi2 * phi2 / 120.0, 0.5 - phi2 / 24.0)
    } else {
        let phi = phi2.sqrt();
        (phi.sin() / phi, (1.0 - phi.cos()) / phi2)
    };
    let s = skew(psi);
    Matrix3::identity() + s * a + s * s * b
}

/// The rotation vector of a rotation matrix, `|ψ| ≤ π`; inverse of [`exp`].
///
/// Goes through the unit quaternion (Shepperd's choice of the largest component), which is
/// accurate at every angle including near π where the skew part vanishes; the `f64`
/// instance of [`crate::dual::log`].
pub fn log(r: &Matrix3<f64>) -> Vector3<f64> {
    Vector3::from(dual::log(&array(r)))
}

/// Unit quaternion `[w, x, y, z]` of a rotation matrix (Shepperd's method), the `f64`
/// instance of [`crate::dual::quaternion`].
pub fn quaternion(r: &Matrix3<f64>) -> [f64; 4] {
    dual::quaternion(&array(r))
}

fn array(r: &Matrix3<f64>) -> dual::M3<f64> {
    std::array::from_fn(|i| std::array::from_fn(|j| r[(i, j)]))
}

/// The rotation vector after the spatial spin `delta` is applied to `psi`:
/// `log(exp([δ]×)·exp([ψ]×))`.
pub fn compose(psi: &Vector3<f64>, delta: &Vector3<f64>) -> Vector3<f64> {
    log(&(exp(delta) * exp(psi)))
}

/// The incremental rotation vector from `psi_old` to `psi_new`: `Θ = log(R_new·R_oldᵀ)`, the
/// spatial spin that carries the old triad onto the new one (`exp([Θ]×)·R_old = R_new`).
/// The driver uses it as a step's rotational increment and the energy ledger as the
/// rotation the work of a nodal moment is done on.
pub fn increment(psi_old: &Vector3<f64>, psi_new: &Vector3<f64>) -> Vector3<f64> {
    log(&(exp(psi_new) * exp(psi_old).transpose()))
}

/// The spatial spin `δθ` produced by a variation `dψ` of the rotation vector:
/// `[δθ]× = δR·Rᵀ` with `R = exp([ψ]×)` gives `δθ = T(ψ)·dψ`,
///
/// `T(ψ) = I + (1 − cos φ)/φ²·[ψ]× + (φ − sin φ)/φ³·[ψ]×²`
///
/// (the left Jacobian of SO(3)). Its inverse maps a spin back to `dψ`
/// ([`rotation_vector_from_spin`]).
pub fn spin_from_rotation_vector(psi: &Vector3<f64>) -> Matrix3<f64> {
    let phi2 = psi.norm_squared();
    let (a, b) = if phi2 < 1e-8 {
        (0.5 - phi2 / 24.0, 1.0 / 6.0 - phi2 / 120.0)
    } else {
        let phi = phi2.sqrt();
        ((1.0 - phi.cos()) / phi2, (phi - phi.sin()) / (phi2 * phi))
    };
    let s = skew(psi);
    Matrix3::identity() + s * a + s * s * b
}

/// The inverse of [`spin_from_rotation_vector`]: `dψ = T(ψ)⁻¹·δθ`,
///
/// `T⁻¹(ψ) = I − ½[ψ]× + (1/φ² − (1 + cos φ)/(2φ·sin φ))·[ψ]×²`
///
/// (column by column from [`crate::dual::inv_jacobian_times`]).
pub fn rotation_vector_from_spin(psi: &Vector3<f64>) -> Matrix3<f64> {
    let p: dual::V3<f64> = (*psi).into();
    let mut m = Matrix3::zeros();
    for j in 0..3 {
        let mut e = [0.0; 3];
        e[j] = 1.0;
        let c = dual::inv_jacobian_times(&p, &e, false);
        for i in 0..3 {
            m[(i, j)] = c[i];
        }
    }
    m
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: &Matrix3<f64>, b: &Matrix3<f64>, tol: f64) -> bool {
        (a - b).amax() <= tol
    }

    /// exp lands on SO(3): orthogonal with determinant one, and a rotation about z by φ is
    /// the textbook matrix.
    #[test]
    fn exp_is_a_rotation() {
        let r = exp(&Vector3::new(0.3, -1.1, 2.0));
        assert!(close(&(r.transpose() * r), &Matrix3::identity(), 1e-14));
        assert!((r.determinant() - 1.0).abs() < 1e-14);
        let phi: f64 = 0.7;
        let rz = exp(&Vector3::new(0.0, 0.0, phi));
        let want = Matrix3::new(
            phi.cos(),
            -phi.sin(),
            0.0,
            phi.sin(),
            phi.cos(),
            0.0,
            0.0,
            0.0,
            1.0,
        );
        assert!(close(&rz, &want, 1e-15));
    }

    /// log inverts exp at small, moderate and near-π angles (where the skew part vanishes).
    #[test]
    fn log_inverts_exp() {
        let axis = Vector3::new(1.0, -2.0, 0.5).normalize();
        for phi in [
            0.0,
            1e-9,
            1e-4,
            0.3,
            1.0,
            2.5,
            3.1,
            std::f64::consts::PI - 1e-7,
        ] {
            let psi = axis * phi;
            let back = log(&exp(&psi));
            assert!(
                (back - psi).norm() <= 1e-12 * (1.0 + phi),
                "φ = {phi}: {back:?}"
            );
        }
    }

    /// Composition agrees with matrix products; composing a spin and its inverse is identity.
    #[test]
    fn compose_is_matrix_product() {
        let psi = Vector3::new(0.4, 0.2, -0.9);
        let d = Vector3::new(-0.3, 0.8, 0.1);
        let c = compose(&psi, &d);
        assert!(close(&exp(&c), &(exp(&d) * exp(&psi)), 1e-14));
        let back = compose(&c, &(-d));
        assert!((back - psi).norm() < 1e-14);
    }

    /// The increment inverts composition: composing `increment(ψ, ψ')` onto ψ gives ψ'.
    #[test]
    fn increment_inverts_compose() {
        let psi = Vector3::new(1.2, -0.4, 0.9);
        let d = Vector3::new(0.05, 0.3, -0.2);
        let next = compose(&psi, &d);
        assert!((increment(&psi, &next) - d).norm() < 1e-14);
    }

    /// T(ψ) by central differences of exp: δR·Rᵀ = [T·dψ]× for each direction dψ = e_i.
    #[test]
    fn tangent_operator_matches_finite_differences() {
        let psi = Vector3::new(0.7, -1.2, 0.4);
        let t = spin_from_rotation_vector(&psi);
        let r = exp(&psi);
        let h = 1e-6;
        for i in 0..3 {
            let mut e = Vector3::zeros();
            e[i] = h;
            let dr = (exp(&(psi + e)) - exp(&(psi - e))) / (2.0 * h);
            let spin = axial(&(dr * r.transpose()));
            assert!((spin - t.column(i)).norm() < 1e-9, "column {i}");
        }
        let ti = rotation_vector_from_spin(&psi);
        assert!(close(&(t * ti), &Matrix3::identity(), 1e-13));
        let small = Vector3::new(1e-6, 2e-6, -1e-6);
        assert!(close(
            &(spin_from_rotation_vector(&small) * rotation_vector_from_spin(&small)),
            &Matrix3::identity(),
            1e-15
        ));
    }
}

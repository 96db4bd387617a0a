//! The rail point C under a wheel: its displacement and rotation interpolated from the two
//! rail-beam nodes I and J (the paper's missing Eq. 14, `T_{12×18}`'s rail part).
//!
//! In the beam's local axes (x along I→J, y and z across), with `ξ = |IC|/|IJ|`
//! (so `S_m = 1 − ξ`, `S_n = ξ` in the paper's notation):
//!
//! - axial displacement and torsion rotation are linear: `u_x = (1−ξ)·u_xI + ξ·u_xJ`,
//!   `θ_x = (1−ξ)·θ_xI + ξ·θ_xJ`;
//! - transverse displacements use the cubic Hermite functions of the Euler–Bernoulli
//!   beam, with `N1 = 1 − 3ξ² + 2ξ³`, `N2 = L·(ξ − 2ξ² + ξ³)`, `N3 = 3ξ² − 2ξ³`,
//!   `N4 = L·(ξ³ − ξ²)`: `u_y = N1·v_I + N2·θ_zI + N3·v_J + N4·θ_zJ` and
//!   `u_z = N1·w_I − N2·θ_yI + N3·w_J − N4·θ_yJ`;
//! - bending rotations are the slopes: `θ_z = du_y/dx`, `θ_y = −du_z/dx`.
//!
//! These reproduce every rigid-body motion of the segment exactly (tested), which is what
//! makes the contact forces objective.

use crate::beam3d::{hermite, hermite_d as hermite_slope};
use nalgebra::{Matrix3, SMatrix};

/// The 6×12 matrix mapping `(u_I, θ_I, u_J, θ_J)` to `(u_C, θ_C)`, all in global axes,
/// for the point at `ξ` of a beam of length `l` whose local axes (columns: x along the
/// beam, y, z) are `axes`.
pub fn rail_point_matrix(xi: f64, l: f64, axes: &Matrix3<f64>) -> SMatrix<f64, 6, 12> {
    let n = hermite(xi, l);
    let d = hermite_slope(xi, l);
    let (a, b) = (1.0 - xi, xi);
    // Local interpolation: rows (ux, uy, uz, θx, θy, θz), columns local DOFs of I then J.
    let mut t = SMatrix::<f64, 6, 12>::zeros();
    // Axial and torsion.
    t[(0, 0)] = a;
    t[(0, 6)] = b;
    t[(3, 3)] = a;
    t[(3, 9)] = b;
    // u_y with θ_z.
    t[(1, 1)] = n[0];
    t[(1, 5)] = n[1];
    t[(1, 7)] = n[2];
    t[(1, 11)] = n[3];
    // u_z with θ_y (opposite sign).
    t[(2, 2)] = n[0];
    t[(2, 4)] = -n[1];
    t[(2, 8)] = n[2];
    t[(2, 10)] = -n[3];
    // θ_y = −du_z/dx.
    t[(4, 2)] = -d[0];
    t[(4, 4)] = d[1];
    t[(4, 8)] = -d[2];
    t[(4, 10)] = d[3];
    // θ_z = du_y/dx.
    t[(5, 1)] = d[0];
    t[(5, 5)] = d[1];
    t[(5, 7)] = d[2];
    t[(5, 11)] = d[3];
    // Global ↔ local: local = Rᵀ·global for every 3-vector block.
    let rt = axes.transpose();
    let mut out = SMatrix::<f64, 6, 12>::zeros();
    for bi in 0..2 {
        for bj in 0..4 {
            let blk = t.fixed_view::<3, 3>(3 * bi, 3 * bj).into_owned();
            let g = axes * blk * rt;
            out.fixed_view_mut::<3, 3>(3 * bi, 3 * bj).copy_from(&g);
        }
    }
    out
}

/// Orthonormal beam axes for a beam from `xi` to `xj`: x along the beam, z = x × up-ish
/// helper, y = z × x, using global Z as the reference unless the beam is vertical.
pub fn beam_axes(xi: &nalgebra::Vector3<f64>, xj: &nalgebra::Vector3<f64>) -> Matrix3<f64> {
    let ex = (xj - xi).normalize();
    let refv = if ex.z.abs() < 0.9 {
        nalgebra::Vector3::z()
    } else {
        nalgebra::Vector3::x()
    };
    let ey = refv.cross(&ex).normalize();
    let ez = ex.cross(&ey);
    Matrix3::from_columns(&[ex, ey, ez])
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{SVector, Vector3};

    fn rigid(
        xi_pos: Vector3<f64>,
        xj_pos: Vector3<f64>,
        c: Vector3<f64>,
        t: Vector3<f64>,
        th: Vector3<f64>,
    ) -> SVector<f64, 12> {
        let ui = t + th.cross(&(xi_pos - c));
        let uj = t + th.cross(&(xj_pos - c));
        let mut q = SVector::<f64, 12>::zeros();
        q.fixed_rows_mut::<3>(0).copy_from(&ui);
        q.fixed_rows_mut::<3>(3).copy_from(&th);
        q.fixed_rows_mut::<3>(6).copy_from(&uj);
        q.fixed_rows_mut::<3>(9).copy_from(&th);
        q
    }

    /// Rigid-body motions (translation plus infinitesimal rotation about an arbitrary
    /// centre) of an arbitrarily oriented segment are reproduced exactly at every ξ.
    #[test]
    fn exact_for_rigid_body_modes() {
        let xi_pos = Vector3::new(1.0, 2.0, 0.5);
        let xj_pos = Vector3::new(1.5, 2.4, 0.45);
        let axes = beam_axes(&xi_pos, &xj_pos);
        let l = (xj_pos - xi_pos).norm();
        let c = Vector3::new(-3.0, 0.7, 2.0);
        let tr = Vector3::new(1e-3, -2e-3, 5e-4);
        let th = Vector3::new(2e-4, -1e-4, 3e-4);
        let q = rigid(xi_pos, xj_pos, c, tr, th);
        for k in 0..=10 {
            let xi = k as f64 / 10.0;
            let out = rail_point_matrix(xi, l, &axes) * q;
            let p = xi_pos + (xj_pos - xi_pos) * xi;
            let expect_u = tr + th.cross(&(p - c));
            assert!(
                (out.fixed_rows::<3>(0) - expect_u).norm() < 1e-15,
                "ξ = {xi}"
            );
            assert!((out.fixed_rows::<3>(3) - th).norm() < 1e-15, "ξ = {xi}");
        }
    }

    /// A cubic deflection `w(x) = x²(3L − x)` (a cantilever's tip-load shape) is interpolated
    /// exactly: Hermite functions span the cubics.
    #[test]
    fn exact_for_cubic_bending() {
        let l = 0.6;
        let axes = Matrix3::identity();
        let w = |x: f64| 1e-3 * x * x * (3.0 * l - x);
        let dw = |x: f64| 1e-3 * (6.0 * l * x - 3.0 * x * x);
        let mut q = SVector::<f64, 12>::zeros();
        q[2] = w(0.0);
        q[4] = -dw(0.0);
        q[8] = w(l);
        q[10] = -dw(l);
        for k in 0..=6 {
            let xi = k as f64 / 6.0;
            let out = rail_point_matrix(xi, l, &axes) * q;
            assert!((out[2] - w(xi * l)).abs() < 1e-16);
            assert!((out[4] + dw(xi * l)).abs() < 1e-15);
        }
    }
}

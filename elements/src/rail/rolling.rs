//! Rolling-contact creep at one contact point of the `moving_axle` element (issue 14): the
//! creepages from the wheelset's kinematics over the step, the creep force of a tangential
//! law ([`super::creep::law`]) on the wheel, and its exact derivative with respect to the
//! element's 21 DOFs. The element owns the contact search; this module owns the
//! kinematics and the chain rule.
//!
//! # Creepages (option (a) of issue 14: displacement increments over the step)
//!
//! Wheel frame 1-2-3 (lateral, up, rolling direction), `ds` = distance the wheelset's
//! station advanced since the last converged step, `r0` = rolling radius of the tape
//! circle, `Δ = T·q (+ prescribed rail offsets)` the rail-minus-wheel displacement of the
//! contact node (moving-axle docs). The slip of the wheel relative to the rail over the
//! step, at the contact point, is
//!
//! ```text
//! S = −T·(q − q_n) + ds·[ (1 − r/r0)·e3 − ψ·e1 ],   r = r0 − z_w
//! ```
//!
//! - `−T·(q − q_n)`: the wheel's material displacement (B's translation, the wheelset's
//!   rotations) minus the rail's material displacement at the contact (rail nodes I, J
//!   through the rail-point map), both from their committed values `q_n`. `T` is that of
//!   the current placement, so the rail term is the material motion of the rail point now
//!   under the wheel, not the convected change of the rail's deflected shape.
//! - `ds·(1 − r/r0)·e3`: the wheelset spins at the nominal `V/r0` (plus the DOF θ1, which
//!   is in the first term through the A–B springs); a contact at rolling radius `r`
//!   therefore advances by `ds·(1 − r/r0)` relative to the rail. `z_w` is the height of the
//!   contact node in the wheel's profile plane above the tape circle (`p.y`), so
//!   `r0 − z_w` is its distance from the axle; it is linear in `q` (row 2 of `T`).
//! - `−ds·ψ·e1`: rolling in a direction yawed by ψ = θ2 of K carries the contact sideways.
//!
//! Then `ξx = S·e3/ds`, `ξy = S·u/ds` with `u = e3 × w` the in-plane tangent at the current
//! contact point (`w` the outward wheel normal), and the spin
//! `φ = n·(e1/r0 + Θ·(q − q_n)/ds)`, `n = −w` the normal pointing into the wheel, `Θ` the
//! map to the wheelset's rotation minus the rail's. For a coned tread of contact angle δ
//! this gives `φ = ∓sin δ/r0` (left/right wheel, Garg & Dukkipati's sign) plus `ψ̇·cos δ/V`.
//! Lateral alignment irregularities stay reference geometry: the rail does not move, so
//! the lateral creepage is the wheel's own lateral velocity minus `V·ψ` in the track frame;
//! the offset moves the contact point on the profiles (rolling radius, contact angle).
//!
//! The load is the penalty normal force `N = −k·g`. The force on the wheel is
//! `Fx·e3 + Fy·u` and its derivative follows by the chain rule through `ξx, ξy, φ, N` (the
//! law's exact gradient) and through `u(w(q))` (`∂w/∂Δ = ∇²g`).

use super::creep::law::{creep_forces, EllipseShape, Material, TangentialLaw};
use nalgebra::{Matrix3, SMatrix, SVector, Vector3};

/// Index of θ2 (yaw of the axle node K) among the element DOFs.
pub const YAW_DOF: usize = 7;

/// What the step contributes: distance rolled, speed, nominal rolling radius.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rolling {
    /// Distance the wheelset rolled since the committed state (m), > 0.
    pub ds: f64,
    /// Speed `ds/dt` (m/s), for velocity-dependent friction.
    pub speed: f64,
    /// Rolling radius of the tape circle (m).
    pub r0: f64,
}

/// One contact point's inputs.
pub struct PointInput<'a> {
    /// `Δ = T·q + offset` map (3×21).
    pub t: &'a SMatrix<f64, 3, 21>,
    /// Rotation map: wheelset rotation minus rail rotation (3×21).
    pub theta: &'a SMatrix<f64, 3, 21>,
    /// `q − q_n` (element DOFs).
    pub dq: &'a SVector<f64, 21>,
    /// Yaw θ2 of K at the trial (rad).
    pub psi: f64,
    /// Height of the contact node above the tape circle in the wheel's profile plane (m).
    pub z_w: f64,
    /// Gap (m, < 0) and outward wheel normal (wheel frame, unit).
    pub gap: f64,
    pub w: Vector3<f64>,
    /// `∇²g` in 3-D (1/m).
    pub hess: &'a Matrix3<f64>,
    /// Normal penalty (N/m).
    pub k: f64,
}

/// One contact point's result.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PointCreep {
    /// `ξx`, `ξy` (−) and `φ` (1/m).
    pub creepage: [f64; 3],
    /// Creep forces on the wheel along `e3` and `u` (N).
    pub fx: f64,
    pub fy: f64,
    /// Normal force (N).
    pub f_n: f64,
    /// Whole contact force on the wheel (normal + creep), wheel frame, and its derivative
    /// with respect to the element DOFs.
    pub force: Vector3<f64>,
    pub d_force: SMatrix<f64, 3, 21>,
}

fn skew(r: &Vector3<f64>) -> Matrix3<f64> {
    Matrix3::new(0.0, -r.z, r.y, r.z, 0.0, -r.x, -r.y, r.x, 0.0)
}

/// Creepages, forces and derivative of one contact point.
pub fn point_creep(
    law: &TangentialLaw,
    shape: &EllipseShape,
    mat: &Material,
    roll: &Rolling,
    p: &PointInput,
) -> PointCreep {
    let t = p.t;
    let ds = roll.ds;
    let e1 = Vector3::x();
    let e3 = Vector3::z();
    // Slip S and dS/dq.
    let s = -(t * p.dq) + (e3 * (p.z_w / roll.r0) - e1 * p.psi) * ds;
    let mut ds_dq = -t;
    let row_z = t.fixed_view::<1, 21>(1, 0).into_owned();
    ds_dq += e3 * row_z * (ds / roll.r0);
    ds_dq[(0, YAW_DOF)] -= ds;
    // The in-plane tangent u = e3 × w and its derivative [e3]ₓ·∇²g·T.
    let u = e3.cross(&p.w);
    let hess_t = p.hess * t;
    let du_dq = skew(&e3) * hess_t;
    let xi_x = s.z / ds;
    let xi_y = s.dot(&u) / ds;
    let dxi_x = ds_dq.fixed_view::<1, 21>(2, 0).into_owned() / ds;
    let dxi_y = (u.transpose() * ds_dq + s.transpose() * du_dq) / ds;
    // Spin: n·Ω, n = −w, Ω = e1/r0 + Θ·dq/ds; ∂n/∂q = −∇²g·T.
    let omega = e1 / roll.r0 + p.theta * p.dq / ds;
    let spin = -p.w.dot(&omega);
    let dspin = -(p.w.transpose() * p.theta) / ds - omega.transpose() * hess_t;
    // Normal load.
    let f_n = -p.k * p.gap;
    let dn = -(p.w.transpose() * t) * p.k;
    let (fx, fy) = creep_forces(law, shape, mat, roll.speed, [xi_x, xi_y, spin, f_n]);
    let grad = |f: &super::creep::dual::D4| -> SMatrix<f64, 1, 21> {
        dxi_x * f.d[0] + dxi_y * f.d[1] + dspin * f.d[2] + dn * f.d[3]
    };
    // Normal part as in the Coulomb law: φ = k·g·w, ∂φ/∂Δ = k·(w·wᵀ + g·∇²g).
    let force = p.w * (p.k * p.gap) + e3 * fx.v + u * fy.v;
    let d_normal = (p.w * p.w.transpose() + p.hess * p.gap) * p.k;
    let d_force = d_normal * t + e3 * grad(&fx) + u * grad(&fy) + du_dq * fy.v;
    PointCreep {
        creepage: [xi_x, xi_y, spin],
        fx: fx.v,
        fy: fy.v,
        f_n,
        force,
        d_force,
    }
}

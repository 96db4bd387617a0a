//! Rolling-contact creep at one contact point of the `moving_axle` element (issue 14): the
//! creepages from the wheelset's kinematics over the step, the creep force of a tangential
//! law ([`crate::rail::contact::creep::law`]) on the wheel, and its exact derivative with respect to the
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

use crate::rail::contact::creep::law::{creep_forces, EllipseShape, Material, TangentialLaw};
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
    /// Rotation of the wheel frame over the step, wheel-frame components (rad): the
    /// carrier turns with the track (curvature, cant rate), and the wheel with it
    /// ([`frame_rotation`]). Zero on straight track of constant cant.
    pub frame_rotation: Vector3<f64>,
}

/// The rotation vector (wheel-frame components, rad) that takes the committed wheel frame
/// `w0` to the current one `w` (columns e1 e2 e3 in global axes). The relative rotation in
/// the current frame's components is `w0ᵀ·w` (since `wᵀ·(w·w0ᵀ)·w = w0ᵀ·w`); for the small
/// rotation of one step (`ds/R`) its axial vector is read from the skew part,
/// `θ = vee((R − Rᵀ)/2)`, exact to `O(θ³)` — below 1e-12 rad for any step that rolls less
/// than a hundredth of the curve radius.
pub fn frame_rotation(w0: &Matrix3<f64>, w: &Matrix3<f64>) -> Vector3<f64> {
    let r = w0.transpose() * w;
    Vector3::new(
        r[(2, 1)] - r[(1, 2)],
        r[(0, 2)] - r[(2, 0)],
        r[(1, 0)] - r[(0, 1)],
    ) * 0.5
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
    /// Gap (m, < 0).
    pub gap: f64,
    /// Outward wheel normal (wheel frame, unit).
    pub w: Vector3<f64>,
    /// `∇²g` in 3-D (1/m).
    pub hess: &'a Matrix3<f64>,
    /// Normal penalty (N/m).
    pub k: f64,
    /// Position of the contact's rail profile node relative to the track centre line at
    /// the station, wheel frame (m): the lever arm of the frame's rotation.
    pub rho: Vector3<f64>,
    /// The contact patch this point belongs to, when it shares it with other points: the
    /// patch's total normal load `N_p` (N) and its derivative with respect to the element
    /// DOFs. `None`: the point is a patch of its own (`N_p = N`).
    pub patch: Option<(f64, SMatrix<f64, 1, 21>)>,
}

/// One contact point's result.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PointCreep {
    /// `ξx`, `ξy` (−) and `φ` (1/m).
    pub creepage: [f64; 3],
    /// Creep force on the wheel along `e3` (N).
    pub fx: f64,
    /// Creep force on the wheel along `u` (N).
    pub fy: f64,
    /// Normal force (N).
    pub f_n: f64,
    /// Whole contact force on the wheel (normal + creep), wheel frame, and its derivative
    /// with respect to the element DOFs.
    pub force: Vector3<f64>,
    /// The derivative of `force` with respect to the element's 21 DOFs.
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
    // The frame's rotation carries the wheel: `Δθ_f × ρ` at the contact (on a curve of
    // radius R the wheel at lateral ρ1 advances by `−ds·ρ1/R` relative to its rail: the
    // outer rail is longer). It is a prescribed motion within the step (no tangent).
    let s = -(t * p.dq)
        + (e3 * (p.z_w / roll.r0) - e1 * p.psi) * ds
        + roll.frame_rotation.cross(&p.rho);
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
    let omega = e1 / roll.r0 + (p.theta * p.dq + roll.frame_rotation) / ds;
    let spin = -p.w.dot(&omega);
    let dspin = -(p.w.transpose() * p.theta) / ds - omega.transpose() * hess_t;
    // Normal load.
    let f_n = -p.k * p.gap;
    let dn = -(p.w.transpose() * t) * p.k;
    // The patch rule (module docs of `moving_axle`): the law is evaluated with this point's
    // creepages and the patch's load `N_p` (its ellipse), and the point carries the share
    // `w = N/N_p` of that force: F = w·F_law(ξ, φ, N_p). Then
    // dF = w·(∂F_law/∂ξ·dξ + ∂F_law/∂φ·dφ + ∂F_law/∂N·dN_p) + F_law·dw,
    // dw = (dN − w·dN_p)/N_p, where dN_p sums the loads of every point of the patch.
    let (n_p, dn_p) = p.patch.unwrap_or((f_n, dn));
    let share = if n_p > 0.0 { f_n / n_p } else { 1.0 };
    let dshare = if n_p > 0.0 {
        (dn - dn_p * share) / n_p
    } else {
        SMatrix::zeros()
    };
    let (fx, fy) = creep_forces(law, shape, mat, roll.speed, [xi_x, xi_y, spin, n_p]);
    let grad = |f: &crate::rail::contact::creep::dual::D4| -> SMatrix<f64, 1, 21> {
        (dxi_x * f.d[0] + dxi_y * f.d[1] + dspin * f.d[2] + dn_p * f.d[3]) * share + dshare * f.v
    };
    let (fx_v, fy_v) = (fx.v * share, fy.v * share);
    // Normal part as in the Coulomb law: φ = k·g·w, ∂φ/∂Δ = k·(w·wᵀ + g·∇²g).
    let force = p.w * (p.k * p.gap) + e3 * fx_v + u * fy_v;
    let d_normal = (p.w * p.w.transpose() + p.hess * p.gap) * p.k;
    let d_force = d_normal * t + e3 * grad(&fx) + u * grad(&fy) + du_dq * fy_v;
    PointCreep {
        creepage: [xi_x, xi_y, spin],
        fx: fx_v,
        fy: fy_v,
        f_n,
        force,
        d_force,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rail::contact::creep::hertz::{hertz_ellipse, Curvatures};
    use crate::rail::contact::creep::kalker::kalker_coefficients;

    const R0: f64 = 0.43;
    const DS: f64 = 0.2;
    const K: f64 = 1e9;

    /// A contact whose rail point is node I's translation and whose wheel point is B's:
    /// `Δ = u_I − u_B` (the element's `T` without lever arms).
    fn t_simple() -> SMatrix<f64, 3, 21> {
        let mut t = SMatrix::<f64, 3, 21>::zeros();
        t.fixed_view_mut::<3, 3>(0, 0)
            .copy_from(&(-Matrix3::identity()));
        t.fixed_view_mut::<3, 3>(0, 9)
            .copy_from(&Matrix3::identity());
        t
    }

    fn theta_map() -> SMatrix<f64, 3, 21> {
        let mut m = SMatrix::<f64, 3, 21>::zeros();
        m.fixed_view_mut::<3, 3>(0, 6)
            .copy_from(&Matrix3::identity());
        m
    }

    fn shape() -> EllipseShape {
        // Wheel r = 0.43 m on a 0.3 m rail crown, the ellipse at the reference load.
        let e = hertz_ellipse(
            &Curvatures {
                wheel_rolling_radius: R0,
                wheel_transverse: 0.0,
                rail_transverse: 1.0 / 0.3,
            },
            1e4,
            2.0 * 8e10 * 1.28,
            0.28,
        )
        .unwrap();
        EllipseShape {
            n_ref: 1e4,
            a_ref: e.a,
            b_ref: e.b,
            c: kalker_coefficients(e.a / e.b, 0.28).unwrap(),
        }
    }

    const MAT: Material = Material {
        shear_modulus: 8e10,
        mu: 0.3,
    };

    struct Case {
        dq: SVector<f64, 21>,
        psi: f64,
        z_w: f64,
        w: Vector3<f64>,
        gap: f64,
        frame_rotation: Vector3<f64>,
        rho: Vector3<f64>,
    }

    impl Default for Case {
        fn default() -> Self {
            Case {
                dq: SVector::zeros(),
                psi: 0.0,
                z_w: 0.0,
                w: -Vector3::y(),
                gap: -6e-5,
                frame_rotation: Vector3::zeros(),
                rho: Vector3::zeros(),
            }
        }
    }

    fn run(c: &Case) -> PointCreep {
        let (t, th) = (t_simple(), theta_map());
        point_creep(
            &TangentialLaw::KalkerLinear,
            &shape(),
            &MAT,
            &Rolling {
                ds: DS,
                speed: 20.0,
                r0: R0,
                frame_rotation: c.frame_rotation,
            },
            &PointInput {
                t: &t,
                theta: &th,
                dq: &c.dq,
                psi: c.psi,
                z_w: c.z_w,
                gap: c.gap,
                w: c.w,
                hess: &Matrix3::zeros(),
                k: K,
                rho: c.rho,
                patch: None,
            },
        )
    }

    /// On a curve of radius R turning towards +e1 (rotation +ds/R about the up axis e2),
    /// a wheel at lateral ρ1 = b is on the inner rail: its centre travels ds·(1 − b/R)
    /// while the tread, spinning at the nominal V/r0, turns through ds, so the tread
    /// slips backwards against the rail by ds·b/R: ξx = −b/R. The outer wheel (ρ1 = −b)
    /// gets +b/R. This is the steering demand of linear curving theory.
    #[test]
    fn curve_frame_rotation_gives_the_inner_wheel_negative_longitudinal_creepage() {
        let (r, b) = (1500.0, 0.75);
        for side in [1.0, -1.0] {
            let c = Case {
                frame_rotation: Vector3::new(0.0, DS / r, 0.0),
                rho: Vector3::new(side * b, 0.0, 0.0),
                ..Default::default()
            };
            let p = run(&c);
            let want = -side * b / r;
            assert!(
                (p.creepage[0] - want).abs() < 1e-12 * (b / r),
                "{side}: {} vs {want}",
                p.creepage[0]
            );
            assert!(p.creepage[1].abs() < 1e-15);
        }
    }

    /// The frame rotation read from two frames: a turn by angle a about e2 gives (0, a, 0)
    /// to O(a³).
    #[test]
    fn frame_rotation_of_a_turn_about_the_up_axis() {
        let a = 1e-4_f64;
        let w = Matrix3::new(a.cos(), 0.0, a.sin(), 0.0, 1.0, 0.0, -a.sin(), 0.0, a.cos());
        let th = frame_rotation(&Matrix3::identity(), &w);
        assert!((th - Vector3::new(0.0, a, 0.0)).norm() < 1e-12, "{th}");
    }

    /// A wheelset yawed by ψ rolling straight on: ξy = −ψ (Kalker's `ẏ/V − ψ` with ẏ = 0),
    /// no longitudinal creepage, no spin on a flat contact.
    #[test]
    fn pure_yaw_gives_lateral_creepage_minus_psi() {
        let p = run(&Case {
            psi: 3e-3,
            ..Default::default()
        });
        assert!((p.creepage[1] + 3e-3).abs() < 1e-15, "{:?}", p.creepage);
        assert_eq!(p.creepage[0], 0.0);
        assert_eq!(p.creepage[2], 0.0);
        // The lateral force opposes the lateral creepage.
        assert!(p.fy > 0.0);
    }

    /// A conical wheel (conicity λ) displaced by y towards its flange touches at the
    /// rolling radius r0 + λ·y: the contact is λ·y below the tape circle (z_w = −λ·y) and
    /// ξx = (1 − r/r0) = −λ·y/r0 (the other wheel, +λ·y/r0).
    #[test]
    fn conical_offset_gives_longitudinal_creepage() {
        let (lambda, y) = (0.05, 2e-3);
        for sign in [1.0, -1.0] {
            let p = run(&Case {
                z_w: -sign * lambda * y,
                ..Default::default()
            });
            let expect = -sign * lambda * y / R0;
            assert!((p.creepage[0] - expect).abs() < 1e-15 * R0);
            assert!(p.fx * expect < 0.0);
        }
    }

    /// Spin of a coned contact: the left wheel's normal into the wheel, n = −w, tilted by δ
    /// towards its flange (−e1), gives φ = −sin δ/r0; the mirror image (right wheel) +sin δ/r0.
    /// A yaw rate adds ψ̇·cos δ/V = Δψ·cos δ/ds.
    #[test]
    fn spin_of_a_coned_contact() {
        let d: f64 = 0.4;
        for side in [1.0, -1.0] {
            let w = Vector3::new(side * d.sin(), -d.cos(), 0.0);
            let p = run(&Case {
                w,
                ..Default::default()
            });
            assert!((p.creepage[2] + side * d.sin() / R0).abs() < 1e-14);
            let mut dq = SVector::zeros();
            dq[YAW_DOF] = 1e-4;
            let p = run(&Case {
                w,
                dq,
                // The yaw angle itself (ξy) is not what is checked here.
                psi: 0.0,
                ..Default::default()
            });
            let expect = -side * d.sin() / R0 + 1e-4 * d.cos() / DS;
            assert!((p.creepage[2] - expect).abs() < 1e-14);
        }
    }

    /// Wheel and rail moving together (the same material displacement over the step) is
    /// no slip: zero creepage and zero tangential force, only the normal force.
    #[test]
    fn wheel_and_rail_moving_together_do_not_creep() {
        let mut dq = SVector::zeros();
        for i in 0..3 {
            dq[i] = [1e-4, -2e-5, 3e-4][i];
            dq[9 + i] = dq[i];
        }
        let p = run(&Case {
            dq,
            ..Default::default()
        });
        assert_eq!(p.creepage[..2], [0.0, 0.0]);
        assert_eq!((p.fx, p.fy), (0.0, 0.0));
        assert!((p.force - Vector3::new(0.0, 6e4, 0.0)).norm() < 1e-6);
    }

    /// A braked wheel: its contact point runs ahead of the rail by d over the step (the
    /// wheel turns slower than rolling), ξx = d/ds > 0. Below saturation the force is
    /// Kalker's `−G·a·b·C11·ξx` (times the Shen–Hedrick–Elkins factor, 1 − u/3 + u²/27,
    /// which is 1 to 1e-3 at u = 3e-3); well above, it is −μN.
    #[test]
    fn braked_wheel_follows_kalker_then_saturates_at_mu_n() {
        let sh = shape();
        let n = K * 6e-5;
        let scale = (n / sh.n_ref).cbrt();
        let (a, b) = (sh.a_ref * scale, sh.b_ref * scale);
        let slope = MAT.shear_modulus * a * b * sh.c.c11;
        // Wheel point ahead of the rail by d: Δ_z = −d, so −T·dq has +d along e3.
        let xi = 3e-3 * MAT.mu * n / slope;
        let mut dq = SVector::zeros();
        dq[2] = xi * DS;
        let p = run(&Case {
            dq,
            ..Default::default()
        });
        assert!((p.creepage[0] - xi).abs() < 1e-12 * xi);
        let u = slope * xi / (MAT.mu * n);
        let she = 1.0 - u / 3.0 + u * u / 27.0;
        assert!(
            (p.fx + slope * xi * she).abs() < 1e-9 * slope * xi,
            "{} vs {}",
            p.fx,
            -slope * xi
        );
        assert!((p.fx + slope * xi).abs() < 2e-3 * slope * xi);
        dq[2] = 0.05 * DS;
        let p = run(&Case {
            dq,
            ..Default::default()
        });
        assert!((p.fx + MAT.mu * n).abs() < 1e-9 * n);
    }
}

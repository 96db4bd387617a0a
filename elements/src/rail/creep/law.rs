//! The tangential laws of a rolling contact point: given the creepages `ξx, ξy` (−), the
//! spin `φ` (1/m) and the normal load `N` (N), the creep forces `Fx` (rolling direction) and
//! `Fy` (lateral, in the contact plane) on the wheel, with their exact gradient with respect
//! to `(ξx, ξy, φ, N)` (forward-mode [`D4`] numbers, so the element's tangent is consistent).
//!
//! - [`TangentialLaw::KalkerLinear`]: Kalker's linear theory (`Fx = −G·a·b·C11·ξx`,
//!   `Fy = −G·a·b·C22·ξy − G·(ab)^{3/2}·C23·φ`, [`super::kalker`]) saturated at `μN` by
//!   Shen, Hedrick & Elkins (1983), [`super::kalker::she_factor`].
//! - [`TangentialLaw::Polach`]: O. Polach, "Creep forces in simulations of traction vehicles
//!   running on adhesion limit", Wear 258 (2005) 992–1000, built on his closed form of 1999
//!   (Vehicle System Dynamics 33 suppl., 728–739): with the total creepage
//!   `s = √(ξx² + ξy²)`, the combined coefficient `c = √((C11·ξx/s)² + (C22·ξy/s)²)`, the
//!   gradient of the tangential stress `ε = G·π·a·b·c·s / (4·N·μ)` and the falling friction
//!   `μ = μ0·[(1 − A)·e^{−B·w} + A]` of the slip velocity `w = V·s`,
//!   `F = (2Nμ/π)·[kA·ε/(1 + (kA·ε)²) + atan(kS·ε)]`, `Fx = −F·ξx/s`, `Fy = −F·ξy/s`.
//!   For small `ε` this is `(kA + kS)/2` times Kalker's linear force (the reduction of the
//!   initial slope Polach introduced for real, contaminated surfaces); `kA = kS = 1`,
//!   `A = 1` give his 1999 method. **Spin is not included** in this law: Polach's spin
//!   correction (1999, his Eqs. for `F_yS`) was not available to check in this session,
//!   so `φ` does not enter `Polach` (it does enter `KalkerLinear` through `C23`).
//!
//! The ellipse semi-axes scale with the load, `a = a_ref·(N/N_ref)^{1/3}` (Hertz), from an
//! ellipse computed once per contact point and step at `N_ref` ([`EllipseShape`]).

use super::dual::D4;
use super::kalker::CreepCoefficients;
use std::f64::consts::PI;

/// A tangential law and its constants.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum TangentialLaw {
    /// Kalker's linear creep saturated by Shen–Hedrick–Elkins.
    KalkerLinear,
    /// Polach (2005) with reduction factors `ka`, `ks` and falling friction `a`, `b` (s/m).
    Polach { ka: f64, ks: f64, a: f64, b: f64 },
}

/// The load-independent part of the contact: the ellipse at a reference load and Kalker's
/// coefficients for its shape.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EllipseShape {
    /// Reference normal load (N).
    pub n_ref: f64,
    /// Semi-axis along the rolling direction at `n_ref` (m).
    pub a_ref: f64,
    /// Lateral semi-axis at `n_ref` (m).
    pub b_ref: f64,
    /// Kalker's coefficients.
    pub c: CreepCoefficients,
}

/// Material and friction of the contact.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Material {
    /// Shear modulus `G` (Pa).
    pub shear_modulus: f64,
    /// Friction coefficient μ (Kalker) or its maximum at zero slip μ0 (Polach).
    pub mu: f64,
}

/// `(Fx, Fy)` on the wheel (N), each with `∂/∂(ξx, ξy, φ, N)`.
pub fn creep_forces(
    law: &TangentialLaw,
    shape: &EllipseShape,
    mat: &Material,
    speed: f64,
    input: [f64; 4],
) -> (D4, D4) {
    if input[3] <= 0.0 || mat.mu <= 0.0 {
        return (D4::c(0.0), D4::c(0.0));
    }
    let x = D4::var(input[0], 0);
    let y = D4::var(input[1], 1);
    let sp = D4::var(input[2], 2);
    let n = D4::var(input[3], 3);
    let scale = (n * (1.0 / shape.n_ref)).cbrt();
    let ab = scale * scale * (shape.a_ref * shape.b_ref);
    let g = mat.shear_modulus;
    let c = &shape.c;
    match *law {
        TangentialLaw::KalkerLinear => {
            let fx = -(ab * x) * (g * c.c11);
            // (ab)^{3/2} as ab·√(ab): a square root instead of a power.
            let fy = -(ab * y) * (g * c.c22) - ((ab * ab.sqrt()) * sp) * (g * c.c23);
            let f = (fx * fx + fy * fy).sqrt();
            if f.v == 0.0 {
                return (fx, fy);
            }
            let limit = n * mat.mu;
            let u = f / limit;
            // Shen–Hedrick–Elkins: ε = 1 − u/3 + u²/27 below u = 3, μN/F beyond.
            let eps = if u.v < 3.0 {
                (u * u) * (1.0 / 27.0) - u * (1.0 / 3.0) + 1.0
            } else {
                limit / f
            };
            (eps * fx, eps * fy)
        }
        TangentialLaw::Polach { ka, ks, a, b } => {
            let s = (x * x + y * y).sqrt();
            let half = 0.5 * (ka + ks);
            if s.v < 1e-14 {
                // The limit ε → 0: (kA + kS)/2 times Kalker's linear force, no spin.
                return (
                    -(ab * x) * (g * c.c11 * half),
                    -(ab * y) * (g * c.c22 * half),
                );
            }
            let cx = x * (c.c11) / s;
            let cy = y * (c.c22) / s;
            let cc = (cx * cx + cy * cy).sqrt();
            let mu = ((s * (-b * speed)).exp() * (1.0 - a) + a) * mat.mu;
            let eps = ab * cc * s * (g * PI / 4.0) / (n * mu);
            let kae = eps * ka;
            let bracket = kae / (kae * kae + 1.0) + (eps * ks).atan();
            let f = n * mu * bracket * (2.0 / PI);
            (-(f * x / s), -(f * y / s))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rail::creep::kalker::kalker_coefficients;

    fn shape() -> EllipseShape {
        EllipseShape {
            n_ref: 1e4,
            a_ref: 3e-3,
            b_ref: 4e-3,
            c: kalker_coefficients(0.75, 0.28).unwrap(),
        }
    }

    const MAT: Material = Material {
        shear_modulus: 8e10,
        mu: 0.3,
    };

    /// Below saturation the Kalker law is G·a·b·C11·ξx (with the ellipse scaled to the
    /// load by N^{1/3}); far above it is μN along the linear force.
    #[test]
    fn kalker_linear_limits() {
        let s = shape();
        let n = 8e4;
        let (a, b) = (s.a_ref * 2.0, s.b_ref * 2.0); // (8e4/1e4)^{1/3} = 2
        let xi = 1e-6;
        let (fx, fy) = creep_forces(
            &TangentialLaw::KalkerLinear,
            &s,
            &MAT,
            30.0,
            [xi, 0.0, 0.0, n],
        );
        let lin = 8e10 * a * b * s.c.c11 * xi;
        assert!((fx.v + lin).abs() < 1e-3 * lin, "{} vs {lin}", fx.v);
        assert!(fy.v.abs() < 1e-12);
        let (fx, fy) = creep_forces(
            &TangentialLaw::KalkerLinear,
            &s,
            &MAT,
            30.0,
            [0.03, -0.04, 0.0, n],
        );
        let f = fx.v.hypot(fy.v);
        assert!((f - 0.3 * n).abs() < 1e-9 * n);
        // SHE scales both linear components alike: the direction is (C11·ξx, C22·ξy).
        let ratio = (s.c.c11 * 0.03) / (s.c.c22 * -0.04);
        assert!((fx.v / fy.v - ratio).abs() < 1e-12);
    }

    /// Polach: small creepage gives (kA + kS)/2 of Kalker's slope; large creepage tends to
    /// μ(w)·N with the falling friction of the slip velocity.
    #[test]
    fn polach_limits() {
        let s = shape();
        let n = 1e4;
        let law = TangentialLaw::Polach {
            ka: 1.0,
            ks: 0.4,
            a: 0.4,
            b: 0.6,
        };
        let xi = 1e-7;
        let (fx, _) = creep_forces(&law, &s, &MAT, 30.0, [xi, 0.0, 0.0, n]);
        let lin = 0.7 * 8e10 * s.a_ref * s.b_ref * s.c.c11 * xi;
        assert!((fx.v + lin).abs() < 1e-4 * lin, "{} vs {lin}", fx.v);
        // Huge creepage: ε → ∞, bracket → π/2, F → μ(w)·N.
        let xi = 5.0;
        let v = 30.0;
        let (fx, _) = creep_forces(&law, &s, &MAT, v, [xi, 0.0, 0.0, n]);
        let mu = 0.3 * ((1.0 - 0.4) * (-0.6 * v * xi).exp() + 0.4);
        let eps = 8e10 * PI * s.a_ref * s.b_ref * s.c.c11 * xi / (4.0 * n * mu);
        let expect = 2.0 * n * mu / PI * (eps / (1.0 + eps * eps) + (0.4 * eps).atan());
        assert!((fx.v + expect).abs() < 1e-9 * expect);
        assert!((-fx.v - mu * n).abs() < 1e-3 * mu * n);
    }

    /// The gradients of both laws against central differences, unsaturated and saturated.
    #[test]
    fn gradients_are_exact() {
        let s = shape();
        let laws = [
            TangentialLaw::KalkerLinear,
            TangentialLaw::Polach {
                ka: 1.0,
                ks: 0.4,
                a: 0.4,
                b: 0.6,
            },
        ];
        for law in &laws {
            for x0 in [
                [2e-4, -1e-4, 0.05, 3e4],
                [4e-3, 6e-3, -0.3, 2e4],
                [0.05, 0.01, 0.5, 2e4],
            ] {
                let (fx, fy) = creep_forces(law, &s, &MAT, 30.0, x0);
                for i in 0..4 {
                    let h = 1e-6 * x0[i].abs();
                    let mut p = x0;
                    p[i] += h;
                    let mut m = x0;
                    m[i] -= h;
                    let (px, py) = creep_forces(law, &s, &MAT, 30.0, p);
                    let (mx, my) = creep_forces(law, &s, &MAT, 30.0, m);
                    for (d, a, b) in [(fx.d[i], px.v, mx.v), (fy.d[i], py.v, my.v)] {
                        let fd = (a - b) / (2.0 * h);
                        let scale = fx.v.abs().max(fy.v.abs()) / x0[i].abs();
                        assert!(
                            (fd - d).abs() < 1e-6 * scale,
                            "{law:?} {x0:?} input {i}: {fd} vs {d}"
                        );
                    }
                }
            }
        }
    }
}

//! The frictional penalty law of one wheel–rail contact point (the paper's Eqs. 6–10).
//!
//! A contact point is a rail profile node that has entered the wheel. Its state is
//! described by the relative displacement `Δ` (rail material point minus wheel material
//! point, wheel frame 1-2-3) and by the signed gap `g` along the wheel's outward normal
//! `w` (negative = penetration). With penalty constants `k` (normal and in-plane tangential)
//! and `k_v` (longitudinal), and the stick anchor `Δ_a` (the relative displacement at
//! which the point last stuck, committed only when a step converges):
//!
//! - **separation** (`g ≥ 0`): no force, no stiffness (Eq. 7, `[K_local] = 0`);
//! - **sticking**: `f_n = −k·g`, `f_u = k·s_u`, `f_v = k_v·s_v` with `s = Δ − Δ_a` resolved on
//!   the contact frame `u = v × w` (the in-plane tangent at the *current* contact point, so
//!   it turns with the normal as the point moves along the profile), `v` (longitudinal,
//!   the anchor's, normal to the cross-section plane); the local
//!   stiffness is `diag(k, k, k_v)` (Eq. 7);
//! - **sliding** (`|k·s_u| > μ·f_n`): `f_u = μ·f_n·sign(s_u)`, exactly Coulomb at every
//!   evaluation, hence at convergence. The tangent is either the symmetric matrix of
//!   Ju & Rowlands (1999) (Eq. 8: `[[μ²k, μk, 0], [μk, k, 0], [0, 0, k_v]]` in `(u, w, v)`,
//!   the sign of μ set by the slip direction — rank one in the `u–w` block, so the global
//!   matrix stays symmetric), or the consistent (unsymmetric) derivative
//!   `∂f_u/∂Δ = μ·sign·∂f_n/∂Δ`, which converges quadratically and passes a
//!   finite-difference check.
//!
//! Everything is written as a generalized force `φ = ∂Φ/∂Δ` conjugate to `Δ` and its
//! derivative `D = ∂φ/∂Δ` (3×3); the element maps both to its 21 DOFs with `Tᵀφ` and
//! `TᵀDT` (Eqs. 9–13). The normal part carries the exact curvature term of the signed
//! distance, `k·(w·wᵀ + g·∇²g)`, so the stick tangent is exact.

use nalgebra::{Matrix3, Vector3};

fn skew(r: &Vector3<f64>) -> Matrix3<f64> {
    // [r]ₓ such that [r]ₓ·x = r × x.
    Matrix3::new(0.0, -r.z, r.y, r.z, 0.0, -r.x, -r.y, r.x, 0.0)
}
use serde::{Deserialize, Serialize};

/// Which tangent to use for sliding points.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum SlidingTangent {
    /// The symmetric tangent of Ju & Rowlands (1999) (the paper's Eq. 8).
    #[default]
    Symmetric,
    /// The exact derivative of the sliding force (unsymmetric).
    Consistent,
}

/// Penalty constants and friction of the contact law.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct PenaltyLaw {
    /// Normal and in-plane tangential penalty `k` (N/m).
    pub k: f64,
    /// Longitudinal penalty `k_v` (N/m).
    pub k_v: f64,
    /// Coefficient of friction μ.
    pub mu: f64,
    /// Sliding tangent.
    pub tangent: SlidingTangent,
}

/// Contact mode of a point.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Mode {
    /// Gap open: no force.
    Open,
    /// Sticking.
    Stick,
    /// Sliding at `|f_u| = μ·f_n`.
    Slide,
}

impl Mode {
    /// 0 open, 1 stick, 2 slide (for recorders).
    pub fn code(self) -> f64 {
        match self {
            Mode::Open => 0.0,
            Mode::Stick => 1.0,
            Mode::Slide => 2.0,
        }
    }
}

/// The status of a point in the contact's active set: open, sticking, or sliding along
/// `+u` or `−u`. Two points with the same status obey the same branch of the law, which
/// is smooth in `Δ` within a branch; Newton iterates that change statuses cross its kinks.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Status {
    /// Gap open.
    Open,
    /// Sticking: `|k·s_u| ≤ μ·f_n`.
    Stick,
    /// Sliding with `f_u = +μ·f_n`.
    SlidePlus,
    /// Sliding with `f_u = −μ·f_n`.
    SlideMinus,
}

impl Status {
    /// The status of a closed point with trial friction force `k·s_u` and limit `μ·f_n`.
    fn of_slip(trial: f64, limit: f64) -> Status {
        if trial.abs() <= limit {
            Status::Stick
        } else if trial.signum() < 0.0 {
            Status::SlideMinus
        } else {
            Status::SlidePlus
        }
    }
}

/// The committed stick anchor of a point and the tangential frame it was taken in.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Anchor {
    /// Relative displacement at the anchor (m), wheel frame.
    pub delta: Vector3<f64>,
    /// In-plane tangent `u` (unit), wheel frame, at the last commit (for reference: the
    /// law evaluates with the current tangent `v × w`).
    pub u: Vector3<f64>,
    /// Longitudinal direction `v` (unit), wheel frame.
    pub v: Vector3<f64>,
}

/// The evaluated state of a point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PointState {
    /// Mode.
    pub mode: Mode,
    /// Generalized force `φ = ∂Φ/∂Δ` (N): the contact force on the wheel, wheel frame.
    pub phi: Vector3<f64>,
    /// Its derivative `∂φ/∂Δ` (N/m).
    pub d: Matrix3<f64>,
    /// Normal force (N, compressive positive).
    pub f_n: f64,
    /// In-plane tangential force along `u` (N).
    pub f_u: f64,
    /// Longitudinal force along `v` (N).
    pub f_v: f64,
    /// In-plane slip from the anchor along `u` (m).
    pub s_u: f64,
    /// The in-plane tangent `u = v × w` the point was evaluated with (unit, wheel frame).
    pub u: Vector3<f64>,
}

impl PenaltyLaw {
    /// Evaluates a point with gap `g` (m), unit outward wheel normal `w` (wheel frame),
    /// curvature term `hess = ∇²g` mapped to 3-D (1/m), relative displacement `delta` and
    /// its anchor. Returns the state and the status the point is in (from `g` and `s_u`).
    ///
    /// `held`: `None` evaluates the point in the status it is in. `Some` evaluates it in the
    /// status given (an active set held fixed, solvers/src/held_active_set.rs): that branch's
    /// formulas apply beyond their range — a held contact with `g ≥ 0` pulls
    /// (`f_n = −k·g < 0`), a held stick exceeds `μ·f_n`, a held slide keeps its direction
    /// when `s_u` turns — so the law is smooth in `Δ` while the set is held. Where the held
    /// status is the one found, the state is the one `None` gives, bit for bit.
    pub fn evaluate(
        &self,
        g: f64,
        w: &Vector3<f64>,
        hess: &Matrix3<f64>,
        delta: &Vector3<f64>,
        anchor: &Anchor,
        held: Option<Status>,
    ) -> (PointState, Status) {
        let v = anchor.v;
        let u = v.cross(w);
        if held == Some(Status::Open) || (held.is_none() && g >= 0.0) {
            let open = PointState {
                mode: Mode::Open,
                phi: Vector3::zeros(),
                d: Matrix3::zeros(),
                f_n: 0.0,
                f_u: 0.0,
                f_v: 0.0,
                s_u: 0.0,
                u,
            };
            let found = if g >= 0.0 {
                Status::Open
            } else {
                Status::of_slip(
                    self.k * u.dot(&(delta - anchor.delta)),
                    -self.mu * self.k * g,
                )
            };
            return (open, found);
        }
        let k = self.k;
        let f_n = -k * g;
        // Normal: Φ_n = ½·k·g², ∂Φ_n/∂Δ = k·g·w, ∂²Φ_n/∂Δ² = k·(w·wᵀ + g·∇²g).
        let mut phi = w * (k * g);
        let mut d = (w * w.transpose() + hess * g) * k;
        let s = delta - anchor.delta;
        // The in-plane tangent follows the current normal, u = v × w, so that the friction
        // force is tangent to the wheel at the current contact point and Coulomb holds
        // exactly against the current normal (`f_u = μ·f_n`, both resolved on the current
        // frame). Its derivative is ∂u/∂Δ = [v]ₓ·∂w/∂Δ = [v]ₓ·∇²g.
        let du = skew(&v) * hess;
        let s_u = u.dot(&s);
        let s_v = v.dot(&s);
        let f_v = self.k_v * s_v;
        phi += v * f_v;
        d += v * v.transpose() * self.k_v;
        let trial = k * s_u;
        let limit = self.mu * f_n;
        let found = if g >= 0.0 {
            Status::Open
        } else {
            Status::of_slip(trial, limit)
        };
        let branch = match held {
            Some(h) => h,
            None => found,
        };
        if branch == Status::Stick {
            phi += u * trial;
            // ∂(f_u·u)/∂Δ = k·u·(uᵀ + sᵀ·∂u/∂Δ) + f_u·∂u/∂Δ; the curvature terms are
            // symmetrized for the symmetric variant (an O(f·κ) approximation).
            let extra = u * (s.transpose() * du) * k + du * trial;
            d += u * u.transpose() * k;
            d += match self.tangent {
                SlidingTangent::Consistent => extra,
                SlidingTangent::Symmetric => (extra + extra.transpose()) * 0.5,
            };
            let st = PointState {
                mode: Mode::Stick,
                phi,
                d,
                f_n,
                f_u: trial,
                f_v,
                s_u,
                u,
            };
            (st, found)
        } else {
            let sgn = if branch == Status::SlideMinus {
                -1.0
            } else {
                1.0
            };
            let f_u = limit * sgn;
            phi += u * f_u;
            let extra = du * f_u;
            // ∂f_n/∂Δ = −k·w, so ∂f_u/∂Δ = −μ·k·sign·w.
            match self.tangent {
                SlidingTangent::Consistent => {
                    d += u * w.transpose() * (-self.mu * k * sgn) + extra;
                }
                SlidingTangent::Symmetric => {
                    d += (u * w.transpose() + w * u.transpose()) * (-self.mu * k * sgn)
                        + u * u.transpose() * (self.mu * self.mu * k)
                        + (extra + extra.transpose()) * 0.5;
                }
            }
            let st = PointState {
                mode: Mode::Slide,
                phi,
                d,
                f_n,
                f_u,
                f_v,
                s_u,
                u,
            };
            (st, found)
        }
    }

    /// The anchor after a converged step: unchanged when sticking; moved along `u` so that
    /// `k·s_u = μ·f_n·sign` when sliding (returning the frictional work of the slip, J);
    /// reset to the current `Δ` (with the current frame) when open.
    pub fn commit_anchor(
        &self,
        st: &PointState,
        delta: &Vector3<f64>,
        anchor: &Anchor,
        frame: (Vector3<f64>, Vector3<f64>),
    ) -> (Anchor, f64) {
        match st.mode {
            Mode::Open => (
                Anchor {
                    delta: *delta,
                    u: frame.0,
                    v: frame.1,
                },
                0.0,
            ),
            Mode::Stick => (*anchor, 0.0),
            Mode::Slide => {
                // Slip measured from the anchor passed in, so that committing twice moves
                // the anchor once: k·u·(Δ − Δ_a') = f_u afterwards.
                let s_u = st.u.dot(&(delta - anchor.delta));
                let slip = s_u - st.f_u / self.k;
                (
                    Anchor {
                        delta: anchor.delta + st.u * slip,
                        u: st.u,
                        ..*anchor
                    },
                    (st.f_u * slip).abs(),
                )
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn law(t: SlidingTangent) -> PenaltyLaw {
        PenaltyLaw {
            k: 1e9,
            k_v: 5e8,
            mu: 0.3,
            tangent: t,
        }
    }

    fn anchor() -> Anchor {
        Anchor {
            delta: Vector3::zeros(),
            u: Vector3::x(),
            v: Vector3::z(),
        }
    }

    /// Open points carry nothing; sticking points are linear springs `diag(k, k, k_v)`.
    #[test]
    fn open_and_stick() {
        let l = law(SlidingTangent::Symmetric);
        let w = -Vector3::y();
        let st = l
            .evaluate(
                1e-6,
                &w,
                &Matrix3::zeros(),
                &Vector3::new(1e-5, 0.0, 0.0),
                &anchor(),
                None,
            )
            .0;
        assert_eq!(st.mode, Mode::Open);
        assert_eq!(st.phi, Vector3::zeros());
        let g = -1e-5;
        let st = l
            .evaluate(
                g,
                &w,
                &Matrix3::zeros(),
                &Vector3::new(1e-6, 0.0, 2e-6),
                &anchor(),
                None,
            )
            .0;
        assert_eq!(st.mode, Mode::Stick);
        assert!((st.f_n - 1e4).abs() < 1e-9);
        assert!((st.f_u - 1e3).abs() < 1e-9);
        assert!((st.f_v - 1e3).abs() < 1e-9);
        let expect = Matrix3::from_diagonal(&Vector3::new(1e9, 1e9, 5e8));
        assert!((st.d - expect).norm() < 1e-3);
    }

    /// Sliding: the friction force is exactly μ·f_n; the consistent tangent is the exact
    /// derivative; the symmetric one differs from it by `μ²k·uuᵀ + μk·w uᵀ` (Eq. 8) and is
    /// symmetric positive semi-definite in the u–w block.
    #[test]
    fn slide_tangents() {
        let w = -Vector3::y();
        let delta = Vector3::new(1e-4, 0.0, 0.0);
        let g = -1e-5;
        let lc = law(SlidingTangent::Consistent);
        let st = lc
            .evaluate(g, &w, &Matrix3::zeros(), &delta, &anchor(), None)
            .0;
        assert_eq!(st.mode, Mode::Slide);
        assert!((st.f_u - 0.3 * 1e4).abs() < 1e-9);
        // Finite differences of φ with g following Δ along w (g = g0 + w·(Δ − Δ0)).
        let h = 1e-9;
        let mut fd = Matrix3::zeros();
        for j in 0..3 {
            let mut e = Vector3::zeros();
            e[j] = h;
            let gp = g + w.dot(&e);
            let gm = g - w.dot(&e);
            let p = lc
                .evaluate(gp, &w, &Matrix3::zeros(), &(delta + e), &anchor(), None)
                .0
                .phi;
            let m = lc
                .evaluate(gm, &w, &Matrix3::zeros(), &(delta - e), &anchor(), None)
                .0
                .phi;
            fd.set_column(j, &((p - m) / (2.0 * h)));
        }
        assert!((fd - st.d).norm() / st.d.norm() < 1e-6, "{fd} vs {}", st.d);
        let ls = law(SlidingTangent::Symmetric);
        let ss = ls
            .evaluate(g, &w, &Matrix3::zeros(), &delta, &anchor(), None)
            .0;
        assert!((ss.d - ss.d.transpose()).norm() < 1e-6);
        let diff = ss.d - st.d;
        let u = Vector3::x();
        let expect = u * u.transpose() * (0.09 * 1e9) + w * u.transpose() * (-0.3 * 1e9);
        assert!((diff - expect).norm() < 1e-3, "{diff}");
        let eig = ss.d.symmetric_eigen().eigenvalues;
        assert!(eig.iter().all(|e| *e > -1e-3));
        // Commit moves the anchor so that the committed slip satisfies Coulomb exactly.
        let (a, work) = ls.commit_anchor(&ss, &delta, &anchor(), (u, Vector3::z()));
        let again = ls.evaluate(g, &w, &Matrix3::zeros(), &delta, &a, None).0;
        assert!((again.f_u - 0.3 * 1e4).abs() < 1e-6);
        assert!(work > 0.0);
    }

    /// A held status: where it is the status found, the state is `None`'s to the bit; held
    /// past its range it keeps its branch (a slide held along +u after the slip turned
    /// pushes +μ·f_n, a contact held open after the gap opened pulls `−k·g`) and reports the
    /// status found.
    #[test]
    fn held_status_keeps_its_branch() {
        let l = law(SlidingTangent::Symmetric);
        let w = -Vector3::y();
        let h = Matrix3::zeros();
        let g = -1e-5;
        for (delta, status) in [
            (Vector3::new(1e-4, 0.0, 0.0), Status::SlidePlus),
            (Vector3::new(-1e-4, 0.0, 0.0), Status::SlideMinus),
            (Vector3::new(1e-6, 0.0, 0.0), Status::Stick),
        ] {
            let (free, found) = l.evaluate(g, &w, &h, &delta, &anchor(), None);
            assert_eq!(found, status);
            let (held, again) = l.evaluate(g, &w, &h, &delta, &anchor(), Some(status));
            assert_eq!((held, again), (free, found));
        }
        // Slip turned to −u, slide held along +u: f_u = +μ·f_n = +3e3 N.
        let back = Vector3::new(-1e-4, 0.0, 0.0);
        let (st, found) = l.evaluate(g, &w, &h, &back, &anchor(), Some(Status::SlidePlus));
        assert_eq!(found, Status::SlideMinus);
        assert!((st.f_u - 0.3 * 1e4).abs() < 1e-9);
        // Gap opened to +1e-6 m, held in stick: f_n = −k·g = −1e3 N (a pull).
        let (st, found) = l.evaluate(1e-6, &w, &h, &back, &anchor(), Some(Status::Stick));
        assert_eq!(found, Status::Open);
        assert!((st.f_n + 1e3).abs() < 1e-9);
        // Held open while pressed: no force, found sliding.
        let (st, found) = l.evaluate(g, &w, &h, &back, &anchor(), Some(Status::Open));
        assert_eq!((st.mode, found), (Mode::Open, Status::SlideMinus));
        assert_eq!(st.phi, Vector3::zeros());
    }
}

//! The linearised lateral dynamics of a railway wheelset and of a two-axle bogie on straight
//! and on curved track: Kalker's linear creep forces without spin (coefficients `f11`,
//! `f22` per contact, from the Hertz ellipse and Kalker's table), the conicity `λ`, the
//! gravitational stiffness, and primary lateral and yaw stiffness; the state matrix, its
//! eigenvalues, the linear critical speed by bisection on the largest real part, the Klingel
//! wavelength, a Routh–Hurwitz closed form of the critical speed, and steady curving.
//! The derivation is written out in docs/rolling-contact.md; in short:
//!
//! # Wheelset equations
//!
//! Wheelset lateral shift `y` (to the left), yaw `ψ` (nose to the left, about the vertical),
//! speed `V`, rolling radius `r0`, half distance of the contact points `b`, conicity `λ`
//! (`r_L,R = r0 ± λy`). Creepages (wheel velocity relative to the rail at the contact over
//! `V`), left / right:
//!
//! ```text
//! ξx = ∓(λy/r0 + bψ̇/V + b/R),   ξy = ẏ/V − ψ
//! ```
//!
//! (`1/R` the track curvature, positive for a curve to the left; `y`, `ψ` are then measured
//! from the track's centre line and its radial direction). The creep forces on each wheel are
//! `Fx = −f11·ξx`, `Fy = −f22·ξy` with `f11 = G·a·b_c·C11`, `f22 = G·a·b_c·C22` (Kalker; `a`,
//! `b_c` the ellipse's semi-axes). Their resultants:
//!
//! ```text
//! lateral force  −2 f22 (ẏ/V − ψ)
//! yaw moment     −2 f11 b (λy/r0 + bψ̇/V + b/R)
//! ```
//!
//! The normal forces lean with the contact angles `δ_L`, `δ_R` (rad, see
//! [`super::conicity`]): their lateral resultant on the wheelset is `−(W/2)(δ_L − δ_R)` for an
//! axle load `W` (first order), i.e. a **gravitational stiffness** `k_g = (W/2)·d(δ_L − δ_R)/dy`.
//! For a cone of slope `λ` on knife-edge rails the wheelset rolls by `φ = λy/b` and
//! `δ_L − δ_R = 2φ`, so `k_g = Wλ/b`: *not* zero. It would vanish only if the contact angles
//! in the track frame stayed equal, which a rolled rigid wheelset does not do. The FE model
//! (rigid wheel profile spline in the wheelset's frame, which rolls with the wheelset's
//! rotation DOF) contains exactly this effect; [`gravitational_stiffness`] takes it from the
//! contact geometry of [`super::conicity`].
//!
//! **Spin.** The classical Wickens/Klingel analysis leaves spin out (`f23 = 0`, the default
//! of the tests against closed forms). The `moving_axle` element's creep laws include the
//! spin's lateral force `−f23·φ` but no spin moment (Kalker's `C33` is not available,
//! docs/creep.md), with the spin `φ = ∓sin δ/r0 + ψ̇ cos δ/V` (left/right wheel). Summed over
//! both wheels that is a lateral force `f23(sin δ_L − sin δ_R)/r0 − 2f23 ψ̇/V`: a negative
//! lateral stiffness `−f23·ε'/r0` (`ε' = d(δ_L − δ_R)/dy`) that partly cancels `k_g`, and a
//! yaw-rate coupling. Both are in [`Wheelset`] when `f23` is given, so the model has the
//! same terms as the FE element.
//!
//! Primary suspension (per wheelset, to a frame moving at `V`): lateral stiffness `k_y` (N/m,
//! both sides together) and yaw stiffness `k_ψ = 2·k_x·b1²` (N·m/rad) from longitudinal
//! springs `k_x` at `±b1`. With mass `m`, yaw inertia `I`:
//!
//! ```text
//! m ÿ + 2f22/V ẏ + (k_y + k_g) y − 2f22 ψ = F
//! I ψ̈ + 2f11 b²/V ψ̇ + k_ψ ψ + 2f11 bλ/r0 y = −2 f11 b²/R
//! ```
//!
//! `F = −m(V²/R − gθ)` is the lateral load of a cant deficiency on the wheelset (towards the
//! outside of a left-hand curve; 0 at balance speed).
//!
//! # Eigenvalues and the critical speed
//!
//! With `x = (q, q̇)`, `A = [[0, I], [−M⁻¹K, −M⁻¹C]]`; its eigenvalues come from the real
//! Schur form (nalgebra, after a diagonal balancing by powers of two). The critical speed is
//! the lowest `V` at which the largest real part crosses zero, bracketed on a speed grid and
//! bisected. Independent check: the Routh–Hurwitz condition of the wheelset's quartic
//! characteristic polynomial, solved in closed form for `V` ([`routh_hurwitz_critical_speed`]).
//!
//! # Klingel
//!
//! Pure rolling (`ξ = 0`) leaves `ẏ = Vψ`, `ψ̇ = −Vλy/(b r0)`, so `ÿ = −V²λ/(b r0)·y`: a
//! sinusoid of wavelength `L = 2π√(r0·b/λ)`, the limit `Im(s)/V → 2π/L` of the kinematic
//! eigenvalue at low speed.

use super::hertz::{hertz_ellipse, Curvatures, HertzError};
use super::kalker::{kalker_coefficients, KalkerError};
use nalgebra::{Complex, DMatrix, DVector, Schur};
use thiserror::Error;

/// What can go wrong in the linear analysis.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum LinearError {
    /// A parameter is out of range.
    #[error("{what} = {value} is invalid; fix: {fix}")]
    Invalid {
        /// Which parameter.
        what: &'static str,
        /// Its value.
        value: f64,
        /// How to fix it.
        fix: &'static str,
    },
    /// The Schur decomposition did not converge.
    #[error("the eigenvalues of the state matrix did not converge at V = {0} m/s")]
    Eigen(f64),
    /// No sign change of the largest real part on the speed range.
    #[error("no critical speed between {from} and {to} m/s (largest real part {re_from} 1/s at the start, {re_to} 1/s at the end)")]
    NoCrossing {
        /// Start of the range (m/s).
        from: f64,
        /// End of the range (m/s).
        to: f64,
        /// Largest real part at the start (1/s).
        re_from: f64,
        /// Largest real part at the end (1/s).
        re_to: f64,
    },
    /// Hertz contact failed.
    #[error(transparent)]
    Hertz(#[from] HertzError),
    /// Kalker's table failed.
    #[error(transparent)]
    Kalker(#[from] KalkerError),
}

/// One wheelset and its contact, for the linear equations.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Wheelset {
    /// Mass m (kg).
    pub mass: f64,
    /// Yaw moment of inertia I about the vertical (kg·m²).
    pub yaw_inertia: f64,
    /// Nominal rolling radius r0 (m).
    pub rolling_radius: f64,
    /// Half the lateral distance between the contact points b (m).
    pub half_gauge: f64,
    /// Conicity λ (−).
    pub conicity: f64,
    /// Longitudinal creep coefficient f11 of one contact (N).
    pub f11: f64,
    /// Lateral creep coefficient f22 of one contact (N).
    pub f22: f64,
    /// Gravitational stiffness k_g (N/m).
    pub gravitational_stiffness: f64,
    /// Spin creep coefficient f23 = G·(a·b_c)^{3/2}·C23 of one contact (N·m); 0 leaves
    /// spin out (the classical analysis).
    pub f23: f64,
    /// Slope ε' = d(δ_L − δ_R)/dy of the contact-angle difference (1/m); with `f23` it gives
    /// the lateral spin force `f23·ε'·y/r0` (see the module doc).
    pub contact_angle_slope: f64,
}

/// Primary suspension of one wheelset: lateral and yaw stiffness to its frame.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Primary {
    /// Lateral stiffness k_y of the wheelset (N/m, both sides).
    pub lateral: f64,
    /// Yaw stiffness k_ψ (N·m/rad), `2·k_x·b1²` for longitudinal springs k_x at ±b1.
    pub yaw: f64,
}

/// A linear second-order system `M q̈ + C q̇ + K q = f`.
#[derive(Debug, Clone, PartialEq)]
pub struct LinearSystem {
    /// Mass matrix.
    pub m: DMatrix<f64>,
    /// Damping (creep) matrix.
    pub c: DMatrix<f64>,
    /// Stiffness matrix.
    pub k: DMatrix<f64>,
    /// Load vector of the steady curve (curvature and cant deficiency).
    pub f: DVector<f64>,
}

/// Kalker's `f11`, `f22` (N) and `f23` (N·m) of one contact: Hertz ellipse from the
/// rolling radius `rolling_radius`, the wheel's and rail's transverse curvatures (1/m,
/// convex > 0) and the normal load (N), then `G·a·b·C11`, `G·a·b·C22`, `G·(ab)^{3/2}·C23`
/// with `G = E/(2(1 + ν))`.
pub fn creep_coefficients(
    rolling_radius: f64,
    wheel_transverse: f64,
    rail_transverse: f64,
    normal_load: f64,
    young: f64,
    poisson: f64,
) -> Result<(f64, f64, f64), LinearError> {
    let e = hertz_ellipse(
        &Curvatures {
            wheel_rolling_radius: rolling_radius,
            wheel_transverse,
            rail_transverse,
        },
        normal_load,
        young,
        poisson,
    )?;
    let c = kalker_coefficients(e.ratio(), poisson)?;
    let g = young / (2.0 * (1.0 + poisson));
    let ab = e.a * e.b;
    Ok((g * ab * c.c11, g * ab * c.c22, g * ab.powf(1.5) * c.c23))
}

/// Gravitational stiffness `k_g = (W/2)·(δ_L − δ_R)/y` (N/m) from a contact-angle
/// difference `delta_contact_angle` (rad) at a small lateral shift `shift` (m), axle load `W`.
pub fn gravitational_stiffness(axle_load: f64, delta_contact_angle: f64, shift: f64) -> f64 {
    0.5 * axle_load * delta_contact_angle / shift
}

fn check(ok: bool, what: &'static str, value: f64, fix: &'static str) -> Result<(), LinearError> {
    if ok {
        Ok(())
    } else {
        Err(LinearError::Invalid { what, value, fix })
    }
}

impl Wheelset {
    fn validate(&self) -> Result<(), LinearError> {
        let pos = "give a positive value in SI units";
        check(self.mass > 0.0, "mass", self.mass, pos)?;
        check(self.yaw_inertia > 0.0, "yaw inertia", self.yaw_inertia, pos)?;
        check(
            self.rolling_radius > 0.0,
            "rolling radius",
            self.rolling_radius,
            pos,
        )?;
        check(self.half_gauge > 0.0, "half gauge b", self.half_gauge, pos)?;
        check(self.conicity > 0.0, "conicity", self.conicity, pos)?;
        check(self.f11 > 0.0, "f11", self.f11, pos)?;
        check(self.f22 > 0.0, "f22", self.f22, pos)?;
        check(
            self.gravitational_stiffness.is_finite(),
            "gravitational stiffness",
            self.gravitational_stiffness,
            "give a finite value in N/m",
        )
    }

    /// Klingel's wavelength `2π√(r0·b/λ)` (m).
    pub fn klingel_wavelength(&self) -> f64 {
        2.0 * std::f64::consts::PI * (self.rolling_radius * self.half_gauge / self.conicity).sqrt()
    }

    /// Adds this wheelset's creep and contact terms at DOFs `(iy, ipsi)`.
    fn add_to(&self, s: &mut LinearSystem, iy: usize, ipsi: usize, v: f64, curvature: f64) {
        let (b, r0) = (self.half_gauge, self.rolling_radius);
        s.m[(iy, iy)] += self.mass;
        s.m[(ipsi, ipsi)] += self.yaw_inertia;
        s.c[(iy, iy)] += 2.0 * self.f22 / v;
        s.c[(ipsi, ipsi)] += 2.0 * self.f11 * b * b / v;
        s.k[(iy, iy)] += self.gravitational_stiffness - self.f23 * self.contact_angle_slope / r0;
        s.c[(iy, ipsi)] += 2.0 * self.f23 / v;
        s.k[(iy, ipsi)] -= 2.0 * self.f22;
        s.k[(ipsi, iy)] += 2.0 * self.f11 * b * self.conicity / r0;
        s.f[ipsi] -= 2.0 * self.f11 * b * b * curvature;
    }
}

/// Adds a spring `k` on the relative displacement `Σ c_i q_i` (pairs `(dof, c_i)`).
fn add_spring(k_mat: &mut DMatrix<f64>, k: f64, terms: &[(usize, f64)]) {
    for &(i, ci) in terms {
        for &(j, cj) in terms {
            k_mat[(i, j)] += k * ci * cj;
        }
    }
}

/// A single wheelset on its primary suspension, the frame running along the track at `v`
/// (m/s). DOFs `(y, ψ)`. `curvature` = 1/R (1/m, positive to the left), `lateral_load` the
/// lateral force on the wheelset (N, positive to the left; a cant deficiency gives
/// `−m(V²/R − gθ)`).
pub fn wheelset_system(
    ws: &Wheelset,
    primary: &Primary,
    v: f64,
    curvature: f64,
    lateral_load: f64,
) -> Result<LinearSystem, LinearError> {
    ws.validate()?;
    check(v > 0.0, "speed", v, "give a positive speed in m/s")?;
    let mut s = LinearSystem {
        m: DMatrix::zeros(2, 2),
        c: DMatrix::zeros(2, 2),
        k: DMatrix::zeros(2, 2),
        f: DVector::zeros(2),
    };
    ws.add_to(&mut s, 0, 1, v, curvature);
    s.k[(0, 0)] += primary.lateral;
    s.k[(1, 1)] += primary.yaw;
    s.f[0] += lateral_load;
    Ok(s)
}

/// A bogie frame: mass, yaw inertia, semi-wheelbase and its own (secondary) stiffness to a
/// body running straight at `V`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Frame {
    /// Frame mass (kg).
    pub mass: f64,
    /// Frame yaw inertia (kg·m²).
    pub yaw_inertia: f64,
    /// Semi-wheelbase a (m): wheelsets at ±a.
    pub semi_wheelbase: f64,
    /// Secondary lateral stiffness to the body (N/m).
    pub secondary_lateral: f64,
    /// Secondary yaw stiffness to the body (N·m/rad).
    pub secondary_yaw: f64,
}

/// A two-axle bogie on straight track: DOFs `(y1, ψ1, y2, ψ2, y_f, ψ_f)`, wheelset 1
/// leading at `+a`. Primary springs act on `y_i − y_f − a_i ψ_f` and `ψ_i − ψ_f`.
pub fn bogie_system(
    ws: &Wheelset,
    primary: &Primary,
    frame: &Frame,
    v: f64,
) -> Result<LinearSystem, LinearError> {
    ws.validate()?;
    check(v > 0.0, "speed", v, "give a positive speed in m/s")?;
    check(frame.mass > 0.0, "frame mass", frame.mass, "give kg")?;
    check(
        frame.yaw_inertia > 0.0,
        "frame yaw inertia",
        frame.yaw_inertia,
        "give kg·m²",
    )?;
    let n = 6;
    let mut s = LinearSystem {
        m: DMatrix::zeros(n, n),
        c: DMatrix::zeros(n, n),
        k: DMatrix::zeros(n, n),
        f: DVector::zeros(n),
    };
    for (i, a) in [(0usize, frame.semi_wheelbase), (1, -frame.semi_wheelbase)] {
        let (iy, ip) = (2 * i, 2 * i + 1);
        ws.add_to(&mut s, iy, ip, v, 0.0);
        add_spring(&mut s.k, primary.lateral, &[(iy, 1.0), (4, -1.0), (5, -a)]);
        add_spring(&mut s.k, primary.yaw, &[(ip, 1.0), (5, -1.0)]);
    }
    s.m[(4, 4)] = frame.mass;
    s.m[(5, 5)] = frame.yaw_inertia;
    s.k[(4, 4)] += frame.secondary_lateral;
    s.k[(5, 5)] += frame.secondary_yaw;
    Ok(s)
}

impl LinearSystem {
    /// The first-order state matrix `[[0, I], [−M⁻¹K, −M⁻¹C]]`.
    pub fn state_matrix(&self) -> DMatrix<f64> {
        let n = self.m.nrows();
        let minv = DMatrix::from_diagonal(&self.m.diagonal().map(|d| 1.0 / d));
        let mut a = DMatrix::zeros(2 * n, 2 * n);
        for i in 0..n {
            a[(i, n + i)] = 1.0;
        }
        a.view_mut((n, 0), (n, n)).copy_from(&(-(&minv * &self.k)));
        a.view_mut((n, n), (n, n)).copy_from(&(-(&minv * &self.c)));
        a
    }

    /// Eigenvalues of the state matrix (1/s).
    pub fn eigenvalues(&self, v: f64) -> Result<Vec<Complex<f64>>, LinearError> {
        // nalgebra's shifted QR can stall on this matrix at some speeds (two modes of
        // nearly equal frequency); a looser convergence threshold, then the unbalanced
        // matrix, are tried before giving up.
        let raw = self.state_matrix();
        let balanced = balance(raw.clone());
        for (a, eps) in [
            (&balanced, f64::EPSILON),
            (&balanced, 1e3 * f64::EPSILON),
            (&raw, f64::EPSILON),
            (&raw, 1e3 * f64::EPSILON),
        ] {
            if let Some(schur) = Schur::try_new(a.clone(), eps, 100_000) {
                return Ok(schur.complex_eigenvalues().iter().copied().collect());
            }
        }
        Err(LinearError::Eigen(v))
    }

    /// The static solution `K q = f` (steady curving), `None` if `K` is singular.
    pub fn static_solution(&self) -> Option<DVector<f64>> {
        self.k.clone().lu().solve(&self.f)
    }
}

/// Diagonal similarity `D⁻¹AD` by powers of two that equalises row and column norms
/// (Parlett & Reinsch): the eigenvalues are unchanged, the rounding of the Schur iteration
/// on a badly scaled matrix (creep terms of 1e4 1/s beside unit entries) much reduced.
fn balance(mut a: DMatrix<f64>) -> DMatrix<f64> {
    let n = a.nrows();
    for _ in 0..100 {
        let mut done = true;
        for i in 0..n {
            let (mut c, mut r) = (0.0, 0.0);
            for j in 0..n {
                if j != i {
                    c += a[(j, i)].abs();
                    r += a[(i, j)].abs();
                }
            }
            if c == 0.0 || r == 0.0 {
                continue;
            }
            let mut f = 1.0;
            let s = c + r;
            let (mut cc, mut rr) = (c, r);
            while cc < rr / 2.0 {
                cc *= 2.0;
                rr /= 2.0;
                f *= 2.0;
            }
            while cc >= rr * 2.0 {
                cc /= 2.0;
                rr *= 2.0;
                f /= 2.0;
            }
            if (cc + rr) < 0.95 * s {
                done = false;
                for j in 0..n {
                    a[(i, j)] /= f;
                    a[(j, i)] *= f;
                }
            }
        }
        if done {
            break;
        }
    }
    a
}

/// The largest real part of the eigenvalues (1/s) of `system(v)`.
pub fn max_real_part<F>(system: &F, v: f64) -> Result<f64, LinearError>
where
    F: Fn(f64) -> Result<LinearSystem, LinearError>,
{
    let eig = system(v)?.eigenvalues(v)?;
    Ok(eig.iter().map(|z| z.re).fold(f64::NEG_INFINITY, f64::max))
}

/// The lowest speed in `[from, to]` (m/s) at which the largest real part turns positive:
/// a scan on `steps` equal intervals, then bisection to a relative width `1e-10`.
pub fn critical_speed<F>(system: F, from: f64, to: f64, steps: usize) -> Result<f64, LinearError>
where
    F: Fn(f64) -> Result<LinearSystem, LinearError>,
{
    check(
        from > 0.0 && to > from,
        "speed range",
        to - from,
        "give 0 < from < to (m/s)",
    )?;
    let steps = steps.max(1);
    let re_from = max_real_part(&system, from)?;
    let (mut lo, mut re_lo) = (from, re_from);
    for k in 1..=steps {
        let v = from + (to - from) * k as f64 / steps as f64;
        let re = max_real_part(&system, v)?;
        if re_lo < 0.0 && re >= 0.0 {
            let mut hi = v;
            while hi - lo > 1e-10 * hi {
                let mid = 0.5 * (lo + hi);
                if max_real_part(&system, mid)? < 0.0 {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            return Ok(0.5 * (lo + hi));
        }
        lo = v;
        re_lo = re;
    }
    Err(LinearError::NoCrossing {
        from,
        to,
        re_from,
        re_to: re_lo,
    })
}

/// The critical speed of a single suspended wheelset from the Routh–Hurwitz condition of its
/// characteristic quartic (no eigenvalues involved), spin left out (`f23` is ignored). With `c = 1/V` the coefficients are
/// `a4 = mI`, `a3 = c·A3`, `a2 = P + Q c²`, `a1 = c·A1`, `a0 = R`, where
/// `A3 = 2(m f11 b² + I f22)`, `P = m k_ψ + I K`, `Q = 4 f11 f22 b²`,
/// `A1 = 2(f22 k_ψ + f11 b² K)`, `R = K k_ψ + 4 f11 f22 bλ/r0`, `K = k_y + k_g`. The
/// stability boundary `a1(a2 a3 − a1 a4) − a0 a3² = 0` is linear in `c²`:
/// `c² = (R A3² + A1² mI − A1 P A3) / (A1 Q A3)`. `None` when that is not positive
/// (unstable at every speed, or stable at every speed) or `A1 = 0`.
pub fn routh_hurwitz_critical_speed(ws: &Wheelset, primary: &Primary) -> Option<f64> {
    let (m, i, b) = (ws.mass, ws.yaw_inertia, ws.half_gauge);
    let (f11, f22) = (ws.f11, ws.f22);
    let kk = primary.lateral + ws.gravitational_stiffness;
    let a3 = 2.0 * (m * f11 * b * b + i * f22);
    let p = m * primary.yaw + i * kk;
    let q = 4.0 * f11 * f22 * b * b;
    let a1 = 2.0 * (f22 * primary.yaw + f11 * b * b * kk);
    let r = kk * primary.yaw + 4.0 * f11 * f22 * b * ws.conicity / ws.rolling_radius;
    if a1 <= 0.0 {
        return None;
    }
    let c2 = (r * a3 * a3 + a1 * a1 * m * i - a1 * p * a3) / (a1 * q * a3);
    (c2 > 0.0).then(|| 1.0 / c2.sqrt())
}

/// Steady curving of a single suspended wheelset (frame radial, on the centre line), in
/// closed form: from the yaw equation `ψ = −2f11 b(λy/r0 + b/R)/k_ψ`, into the lateral one:
///
/// ```text
/// y = (F − 4 f11 f22 b²/(R k_ψ)) / (K + 4 f11 f22 bλ/(r0 k_ψ)),   K = k_y + k_g
/// ```
///
/// Returns `(y, ψ)`: lateral offset (m, positive towards the centre of a left-hand curve)
/// and angle of attack (rad). As `k_ψ → 0`, `y → −r0 b/(λR)` (pure rolling) and `ψ → K y/(2f22)`.
pub fn steady_curving(
    ws: &Wheelset,
    primary: &Primary,
    curvature: f64,
    lateral_load: f64,
) -> Result<(f64, f64), LinearError> {
    ws.validate()?;
    check(
        primary.yaw > 0.0,
        "primary yaw stiffness",
        primary.yaw,
        "a wheelset without yaw stiffness has no steady curving solution of this form; give k_ψ > 0",
    )?;
    let (b, r0, lam) = (ws.half_gauge, ws.rolling_radius, ws.conicity);
    let ff = 4.0 * ws.f11 * ws.f22;
    let kk = primary.lateral + ws.gravitational_stiffness;
    let y = (lateral_load - ff * b * b * curvature / primary.yaw)
        / (kk + ff * b * lam / (r0 * primary.yaw));
    let psi = -2.0 * ws.f11 * b * (lam * y / r0 + b * curvature) / primary.yaw;
    Ok((y, psi))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The wavelength `2πV/ω` of the kinematic mode: the oscillatory eigenvalue of
    /// smallest modulus.
    fn kinematic_wavelength(eig: &[Complex<f64>], v: f64) -> f64 {
        let kin = eig
            .iter()
            .filter(|z| z.im > 0.0)
            .min_by(|a, b| a.norm().total_cmp(&b.norm()))
            .unwrap();
        2.0 * std::f64::consts::PI * v / kin.im
    }

    /// A wheelset of the sks700 stand-in's size on a cone (λ = 0.05).
    fn wheelset() -> Wheelset {
        let (f11, f22, _) = creep_coefficients(0.46, 0.0, 1.0 / 0.3, 50e3, 2.1e11, 0.28).unwrap();
        Wheelset {
            mass: 1813.0,
            yaw_inertia: 1120.0,
            rolling_radius: 0.46,
            half_gauge: 0.75,
            conicity: 0.05,
            f11,
            f22,
            gravitational_stiffness: 100e3 * 0.05 / 0.75,
            f23: 0.0,
            contact_angle_slope: 0.0,
        }
    }

    #[test]
    fn creep_coefficients_match_a_hand_evaluation() {
        // r0 0.46 m on a 0.3 m crown, 50 kN, steel: a/b from Hertz, C11, C22 from the table.
        let (f11, f22, f23) = creep_coefficients(0.46, 0.0, 1.0 / 0.3, 50e3, 2.1e11, 0.28).unwrap();
        let e = hertz_ellipse(
            &Curvatures {
                wheel_rolling_radius: 0.46,
                wheel_transverse: 0.0,
                rail_transverse: 1.0 / 0.3,
            },
            50e3,
            2.1e11,
            0.28,
        )
        .unwrap();
        let c = kalker_coefficients(e.a / e.b, 0.28).unwrap();
        let g = 2.1e11 / 2.56;
        assert!((f11 / (g * e.a * e.b * c.c11) - 1.0).abs() < 1e-14);
        assert!((f22 / (g * e.a * e.b * c.c22) - 1.0).abs() < 1e-14);
        assert!((f23 / (g * (e.a * e.b).powf(1.5) * c.c23) - 1.0).abs() < 1e-12);
        // Order of magnitude of the literature (about 10 MN for a 50 kN wheel).
        assert!((5e6..2e7).contains(&f11), "f11 {f11}");
    }

    #[test]
    fn free_wheelset_eigenvalue_tends_to_the_klingel_wavelength() {
        // Free wheelset (no suspension): at low speed the kinematic eigenvalue's imaginary
        // part over V is 2π/L. The corrections are O(m V²/(f22 L)) ≈ 1e-6 at 1 m/s.
        let ws = wheelset();
        let free = Primary::default();
        for v in [0.5, 1.0, 2.0] {
            let eig = wheelset_system(&ws, &free, v, 0.0, 0.0)
                .unwrap()
                .eigenvalues(v)
                .unwrap();
            let wavelength = kinematic_wavelength(&eig, v);
            let l = ws.klingel_wavelength();
            assert!(
                (wavelength / l - 1.0).abs() < 1e-4,
                "V {v}: {wavelength} vs {l}"
            );
        }
    }

    #[test]
    fn critical_speed_by_eigenvalues_matches_routh_hurwitz() {
        let ws = wheelset();
        // Yaw stiffness only, lateral only (with the gravitational stiffness), and both.
        for primary in [
            Primary {
                lateral: 0.0,
                yaw: 2.0 * 1e6 * 1.0 * 1.0,
            },
            Primary {
                lateral: 1e6,
                yaw: 0.0,
            },
            Primary {
                lateral: 1e6,
                yaw: 2.0 * 2e6 * 1.0 * 1.0,
            },
        ] {
            let rh = routh_hurwitz_critical_speed(&ws, &primary);
            let eig = critical_speed(
                |v| wheelset_system(&ws, &primary, v, 0.0, 0.0),
                0.5,
                400.0,
                400,
            );
            match (rh, eig) {
                (Some(a), Ok(b)) => assert!((a / b - 1.0).abs() < 1e-6, "{primary:?}: {a} vs {b}"),
                (a, b) => panic!("{primary:?}: Routh–Hurwitz {a:?}, eigenvalues {b:?}"),
            }
        }
    }

    #[test]
    fn steady_curving_closed_form_is_the_static_solution() {
        let ws = wheelset();
        let primary = Primary {
            lateral: 1e6,
            yaw: 2.0 * 1e6 * 1.0,
        };
        for (curv, load) in [(1.0 / 3000.0, 0.0), (-1.0 / 1500.0, 2e3)] {
            let s = wheelset_system(&ws, &primary, 30.0, curv, load).unwrap();
            let q = s.static_solution().unwrap();
            let (y, psi) = steady_curving(&ws, &primary, curv, load).unwrap();
            assert!((q[0] - y).abs() < 1e-12 * y.abs().max(1e-6), "{q} vs {y}");
            assert!(
                (q[1] - psi).abs() < 1e-12 * psi.abs().max(1e-9),
                "{q} vs {psi}"
            );
        }
        // Soft yaw: the offset tends to pure rolling, y = −r0·b/(λR).
        let soft = Primary {
            lateral: 0.0,
            yaw: 1.0,
        };
        let (y, _) = steady_curving(&ws, &soft, 1.0 / 3000.0, 0.0).unwrap();
        let pure = -0.46 * 0.75 / (0.05 * 3000.0);
        assert!((y / pure - 1.0).abs() < 1e-3, "{y} vs {pure}");
    }

    #[test]
    fn bogie_with_rigid_frame_limits_behaves() {
        // A bogie whose primary springs are very stiff moves as one rigid body. Without
        // inertia (low speed) the lateral creep forces sum to zero, so ẏ = Vψ, and the yaw
        // balance −4f11 b(λy/r0 + bψ̇/V) − 4f22 a² ψ̇/V = 0 gives a sinusoid of wavelength
        // L = 2π√(r0 b/λ · (1 + (f22/f11)(a/b)²)) (Wickens' rigid-truck result; with
        // f11 = f22 the familiar √(1 + (a/b)²) factor).
        let ws = Wheelset {
            gravitational_stiffness: 0.0,
            ..wheelset()
        };
        let stiff = Primary {
            lateral: 1e12,
            yaw: 1e12,
        };
        let frame = Frame {
            mass: 2600.0,
            yaw_inertia: 1500.0,
            semi_wheelbase: 1.28,
            secondary_lateral: 0.0,
            secondary_yaw: 0.0,
        };
        let v = 1.0;
        let eig = bogie_system(&ws, &stiff, &frame, v)
            .unwrap()
            .eigenvalues(v)
            .unwrap();
        let wavelength = kinematic_wavelength(&eig, v);
        let (a, b) = (1.28f64, 0.75f64);
        let l = ws.klingel_wavelength() * (1.0 + ws.f22 / ws.f11 * (a / b).powi(2)).sqrt();
        assert!((wavelength / l - 1.0).abs() < 1e-3, "{wavelength} vs {l}");
    }
}

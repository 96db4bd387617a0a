//! The cut-off frequency of a reduced block's fixed-interface modes, derived from the time
//! step and the output band.
//!
//! # Derivation
//!
//! Two bounds decide which modes a reduced block must keep.
//!
//! 1. **What the integrator resolves.** The trapezoidal rule (Newmark `β = ¼`, `γ = ½`)
//!    integrates an undamped mode `ẍ + ω²·x = 0` exactly in amplitude; its amplification
//!    matrix turns the state by `2·atan(ω·Δt/2)` per step instead of `ω·Δt` (Hughes, *The
//!    Finite Element Method*, 2000, §9.3; Bathe & Wilson, *Earthquake Eng. Struct. Dyn.*
//!    1, 1973). The integrated period is therefore longer by
//!
//!    `ε(ω·Δt) = ω·Δt / (2·atan(ω·Δt/2)) − 1 = (ω·Δt)²/12 + O((ω·Δt)⁴)`.
//!
//!    A mode whose period the integrator gets within `ε` has `ω·Δt ≤ x_ε`, the root of
//!    `ε(x) = ε` ([`resolved_omega_dt`]; `x_ε ≈ √(12·ε)`, 0.346 for 1 %). The
//!    generalized-α family is second-order accurate too, with the same leading period
//!    error for `ρ∞ = 1` and a slightly larger one below (Chung & Hulbert, *J. Appl.
//!    Mech.* 60, 1993); above `x_ε` the full model itself integrates a mode with a
//!    period error larger than `ε`, and (for `ρ∞ < 1`) damps it. Keeping every mode up
//!    to `x_ε/Δt` keeps everything the full model resolves.
//! 2. **The output band.** A mode well above the highest frequency `f_out` of the load
//!    and of the quantities read responds quasi-statically, and the reduced block's own
//!    frequencies converge to the full block's as the first left-out mode moves away
//!    from them. Keeping the modes up to `k·f_out` with `k = 4` puts the band's
//!    frequencies within 0.1 % of the full block's: on a simply supported beam span
//!    cut at 100 Hz (`reduced::tests`), the error is 2e-6 for its mode at `ω_c/26`, 4e-5
//!    at `ω_c/6.4` and 1.7e-3 at `ω_c/2.8`.
//!
//! The cut-off is the larger of the two, `ω_c = max(x_ε/Δt, 2π·k·f_out)`: every mode the
//! integrator resolves, and never fewer than the band needs. With the defaults (`ε` = 1 %,
//! `f_out` = 25 Hz, the band of strong ground motion, `k` = 4) and `Δt` = 0.5 ms,
//! `ω_c` = 695.6 rad/s (110.7 Hz; `x_ε` = 0.3478).

use std::f64::consts::PI;

/// How the cut-off is derived (module documentation).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct CutOffRule {
    /// Largest relative period error `ε` of a mode the integrator is taken to resolve
    /// (dimensionless; default 0.01).
    pub period_error: f64,
    /// Highest frequency of the load and of the output `f_out` (Hz; default 25 Hz).
    pub output_band: f64,
    /// Margin `k` of the cut-off over the output band (dimensionless; default 4).
    pub band_factor: f64,
}

impl Default for CutOffRule {
    fn default() -> Self {
        CutOffRule {
            period_error: 0.01,
            output_band: 25.0,
            band_factor: 4.0,
        }
    }
}

impl CutOffRule {
    /// The cut-off `ω_c = max(x_ε/Δt, 2π·k·f_out)` (rad/s) for the step `dt` (s).
    pub fn omega(&self, dt: f64) -> f64 {
        (resolved_omega_dt(self.period_error) / dt)
            .max(2.0 * PI * self.band_factor * self.output_band)
    }
}

/// The trapezoidal rule's relative period error `ω·Δt / (2·atan(ω·Δt/2)) − 1` at
/// `x = ω·Δt` (dimensionless).
pub fn period_error(x: f64) -> f64 {
    if x == 0.0 {
        return 0.0;
    }
    x / (2.0 * (0.5 * x).atan()) - 1.0
}

/// The `x = ω·Δt` at which [`period_error`] reaches `eps` (bisection on the increasing
/// function; `eps > 0`; infinite for an infinite `eps`).
pub fn resolved_omega_dt(eps: f64) -> f64 {
    if eps == f64::INFINITY {
        return f64::INFINITY;
    }
    let (mut lo, mut hi) = (0.0_f64, 1.0_f64);
    while period_error(hi) < eps {
        hi *= 2.0;
    }
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if period_error(mid) < eps {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

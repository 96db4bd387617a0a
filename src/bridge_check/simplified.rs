//! The simplified dynamic methods of ERRI D214 (RP9) for a simply supported span, used by
//! EN 1991-2 Annex E.2 for the HSLM: the DER method (decomposition of the excitation at
//! resonance) and the LIR method (residual influence line). Both write the peak deck
//! acceleration of the first mode at midspan as a product
//! `a = C · A(K) · G(λ)`: a constant of the span, the span's influence factor `A` of the
//! ratio `K = λ/(2L)`, and the train's "aggressivity" spectrum `G(λ)`, with the wavelength
//! `λ = v/n₀`. Only the first bending mode is represented; the module derives both forms
//! below (the derivation is ours; its structure follows ERRI D214 RP9 and Domínguez,
//! *Dinámica de puentes de ferrocarril para alta velocidad*, 2001, ch. 5).
//!
//! # One load crossing the span (both methods)
//!
//! Mode 1 of a span of length `L`, mass per metre `μ`: `φ = sin(πx/L)`, modal mass `μL/2`,
//! `ω = 2πn₀`. A load `P` entering at `t = 0` with speed `v` gives the modal force
//! `f(t) = (2P/(μL))·sin Ωt` for `0 ≤ t ≤ T = L/v`, `Ω = πv/L`. Its Fourier integral at `ω`,
//! with `ΩT = π`, is
//! `∫₀ᵀ sin Ωτ·e^{iωτ} dτ = −Ω·(1 + e^{iωT})/(ω² − Ω²)`,
//! so the free vibration the load leaves behind (undamped) has the acceleration amplitude
//! `(2P/(μL))·ω·|1 + e^{iωT}|·Ω/|ω² − Ω²|`. With `Ω/ω = K = λ/(2L)` and `ωT = π/K`:
//! `(2P/M)·K/|1 − K²|·|1 + e^{iπ/K}|`, `M = μL` the span's mass. The two terms are the
//! load's entry and exit. With damping the Duhamel integral has `e^{sτ}`, `s = ω(ζ − i)`
//! (taking `ω_d ≈ ω`, an error of order `ζ²`), in place of `e^{iωτ}`: the same integral
//! gives `Ω·(1 + e^{sT})/(s² + Ω²)`, and seen from the exit the entry's share has decayed
//! by `e^{−ζπ/K}`. This is the influence factor of the residual influence line:
//!
//! `A(K) = K·√(1 + e^{−2ζπ/K} + 2·e^{−ζπ/K}·cos(π/K)) / √((K² − 1 + ζ²)² + 4ζ²)`,
//!
//! which is `K/|1 − K²|·√(…)` up to terms in `ζ²` away from `K = 1` and stays finite there
//! (`λ = 2L`, the load's own half sine in tune with the mode): undamped the limit is `π/2`,
//! which [`influence`] uses at `K = 1` for `ζ = 0`.
//!
//! # LIR: the residual vibration of the train
//!
//! Load `k` (distance `x_k` behind the first) leaves at `t_k = (x_k + L)/v`. When load `i`
//! leaves, the residues of loads `k ≤ i` add with the phase `ω(t_i − t_k) = 2πδ_k/λ` and the
//! decay `e^{−2πζδ_k/λ}`, `δ_k = x_i − x_k`:
//!
//! `a_LIR = (2/M) · A(K) · G_LIR(λ)`,
//! `G_LIR(λ) = max_i |Σ_{k≤i} P_k · e^{−2πζδ_k/λ} · e^{i2πδ_k/λ}|`.
//!
//! # DER: the resonant harmonic of the train
//!
//! Treat the first `i` loads (length `x_i`, duration `T_i = x_i/v`) as one period of a
//! periodic excitation. Its harmonic at `ω` has the Fourier coefficient
//! `(2/T_i)·(2/(μL))·|∫ sin Ωτ e^{iωτ}dτ|·|S_i|`, `S_i = Σ_{k≤i} P_k e^{i2πx_k/λ}`; a damped
//! mode driven at resonance by a harmonic of amplitude `F` reaches the acceleration
//! `F/(2ζ)·(1 − e^{−ζωT_i})` after `T_i`. With `v/ω = λ/(2π)` this is
//!
//! `a_DER = (2/M) · A_DER(K) · G_DER(λ)`, `A_DER(K) = 2K·|cos(π/(2K))|/|1 − K²|`
//! (the undamped `A`, since `|1 + e^{iπ/K}| = 2|cos(π/(2K))|`),
//! `G_DER(λ) = max_i (λ/(2πζx_i)) · |S_i| · (1 − e^{−2πζx_i/λ})`.
//!
//! The deflection amplitude of the first mode follows from either as `a/ω²` (mode 1 is
//! harmonic at `ω`); it is the dynamic part only, to be added to the static deflection.

use super::trains::Train;
use std::f64::consts::PI;

/// The simplified method.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Method {
    /// Decomposition of the excitation at resonance (ERRI D214).
    Der,
    /// Residual influence line (ERRI D214).
    Lir,
}

/// `√(1 + e^{−2ζπ/K} + 2e^{−ζπ/K}cos(π/K))`: the entry and exit of one load combined
/// (module documentation), `ζ = 0` gives `2|cos(π/(2K))|`.
fn entry_exit(k: f64, zeta: f64) -> f64 {
    let e = (-zeta * PI / k).exp();
    (1.0 + e * e + 2.0 * e * (PI / k).cos()).max(0.0).sqrt()
}

/// The span's influence factor `A(K)` of the method, `K = λ/(2L)` (module documentation):
/// damped for LIR, undamped for DER. Undamped, `K = 1` is a 0/0 form whose limit, the
/// integral `∫₀ᵀ sin²(ωτ) dτ·ω = π/2`, is used within 1e-6 of it.
pub fn influence(method: Method, k: f64, zeta: f64) -> f64 {
    let z = match method {
        Method::Der => 0.0,
        Method::Lir => zeta,
    };
    if z == 0.0 && (k - 1.0).abs() < 1e-6 {
        return PI / 2.0;
    }
    let den = (k * k - 1.0 + z * z).hypot(2.0 * z);
    k * entry_exit(k, z) / den
}

/// The train's aggressivity spectrum `G(λ)` (N) of the method at wavelength `λ` (m) and
/// damping ratio `ζ` (module documentation).
pub fn aggressivity(method: Method, train: &Train, lambda: f64, zeta: f64) -> f64 {
    let ax = &train.axles;
    let w = 2.0 * PI / lambda;
    let mut best = 0.0f64;
    match method {
        Method::Lir => {
            for (i, ai) in ax.iter().enumerate() {
                let (mut re, mut im) = (0.0, 0.0);
                for a in &ax[..=i] {
                    let d = ai.position - a.position;
                    let m = a.load * (-zeta * w * d).exp();
                    re += m * (w * d).cos();
                    im += m * (w * d).sin();
                }
                best = best.max(re.hypot(im));
            }
        }
        Method::Der => {
            let (mut re, mut im) = (0.0, 0.0);
            for a in ax {
                re += a.load * (w * a.position).cos();
                im += a.load * (w * a.position).sin();
                let x = a.position;
                if x > 0.0 {
                    let g = if zeta > 0.0 {
                        (1.0 - (-zeta * w * x).exp()) / (zeta * w * x)
                    } else {
                        1.0
                    };
                    best = best.max(re.hypot(im) * g);
                }
            }
        }
    }
    best
}

/// A simply supported span for the simplified methods.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Span {
    /// Length `L` (m).
    pub length: f64,
    /// First natural frequency `n₀` (Hz).
    pub n0: f64,
    /// Mass per metre `μ` (kg/m).
    pub mass: f64,
    /// Damping ratio `ζ` (fraction of critical).
    pub zeta: f64,
}

/// The estimate of one method at one speed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Estimate {
    /// Peak midspan acceleration of the first mode (m/s²).
    pub acceleration: f64,
    /// Its deflection amplitude `a/ω²` (m), dynamic part only.
    pub deflection: f64,
}

/// The peak midspan acceleration and deflection amplitude of `train` at speed `v` (m/s)
/// on `span` by `method`: `a = (2/M)·A(K)·G(λ)`, `λ = v/n₀`, `K = λ/(2L)`, `M = μL`.
pub fn estimate(method: Method, span: &Span, train: &Train, v: f64) -> Estimate {
    let lambda = v / span.n0;
    let k = lambda / (2.0 * span.length);
    let a = 2.0 / (span.mass * span.length)
        * influence(method, k, span.zeta)
        * aggressivity(method, train, lambda, span.zeta);
    let w = 2.0 * PI * span.n0;
    Estimate {
        acceleration: a,
        deflection: a / (w * w),
    }
}

//! The reference solution of the check: moving forces on one simply supported
//! Euler–Bernoulli span by modal superposition with exact sine modes, each mode integrated
//! exactly between samples.
//!
//! `w(x,t) = Σ_{n≤N} q_n(t)·sin(nπx/L)`, `ω_n = (nπ/L)²·√(EI/μ)`, modal mass `μL/2`. An
//! axle of load `P_k` (down) at `x_k(t) = v·t − s_k` (`s_k` its distance behind the first
//! axle) loads mode `n` with `−(2P_k/(μL))·sin(Ω_n·(t − t_k))` while it is on the span,
//! `Ω_n = nπv/L`, `t_k = s_k/v`. Between two instants at which no axle enters or leaves,
//! the sum over the axles on the span is one harmonic of frequency `Ω_n`:
//! `f_n(t) = a·sin Ω_n t + b·cos Ω_n t` with
//! `a = −(2/(μL))·Σ P_k cos Ω_n t_k`, `b = (2/(μL))·Σ P_k sin Ω_n t_k`.
//! Each mode `q̈ + 2ζ_nω_n q̇ + ω_n² q = f_n(t)` is then advanced exactly: the particular
//! solution `C sin Ω t + D cos Ω t` with
//! `(ω² − Ω²)·C − 2ζωΩ·D = a`, `(ω² − Ω²)·D + 2ζωΩ·C = b`, plus the free damped response
//! of the remainder (`e = q − q_p`):
//! `e(τ) = e^{−ζωτ}·(e₀ cos ω_d τ + (ė₀ + ζω e₀)/ω_d · sin ω_d τ)`,
//! `ė(τ) = e^{−ζωτ}·(ė₀ cos ω_d τ − (ζω ė₀ + ω² e₀)/ω_d · sin ω_d τ)`, `ω_d = ω√(1 − ζ²)`.
//! The samples are exact for the modal model; the only approximation is the truncation at
//! `N` modes, whose convergence the tests and `docs/bridge-check.md` show.

use super::trains::Train;
use std::f64::consts::PI;

/// A simply supported span for the modal reference.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Span {
    /// Length `L` (m).
    pub length: f64,
    /// Bending stiffness `EI` (N·m²).
    pub ei: f64,
    /// Mass per metre `μ` (kg/m).
    pub mass: f64,
}

impl Span {
    /// Circular frequency of mode `n` (rad/s).
    pub fn omega(&self, n: usize) -> f64 {
        let k = n as f64 * PI / self.length;
        k * k * (self.ei / self.mass).sqrt()
    }
}

/// Histories at the stations: `deflection[j][i]` and `acceleration[j][i]` at station `j`,
/// sample `i` (time `i·dt`), vertical, up positive (m, m/s²).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ModalHistories {
    /// Deflection (m).
    pub deflection: Vec<Vec<f64>>,
    /// Acceleration (m/s²).
    pub acceleration: Vec<Vec<f64>>,
}

/// The response of `span` to `train` at speed `v` (m/s), first axle on the left support at
/// t = 0, sampled every `dt` for `samples` samples, at `stations` (m from the left
/// support), with `modes` modes whose damping ratio is `zeta(ω_n)`.
// The arguments are the case's physical inputs, each named in the doc line above.
#[allow(clippy::too_many_arguments)]
pub fn response(
    span: &Span,
    train: &Train,
    v: f64,
    dt: f64,
    samples: usize,
    stations: &[f64],
    modes: usize,
    zeta: &dyn Fn(f64) -> f64,
) -> ModalHistories {
    let l = span.length;
    let scale = 2.0 / (span.mass * l);
    // Entry and exit times of every axle: the forcing changes form only there.
    let mut events: Vec<f64> = train
        .axles
        .iter()
        .flat_map(|a| [a.position / v, (a.position + l) / v])
        .collect();
    events.sort_by(f64::total_cmp);
    let mut out = ModalHistories {
        deflection: vec![vec![0.0; samples]; stations.len()],
        acceleration: vec![vec![0.0; samples]; stations.len()],
    };
    for n in 1..=modes {
        let w = span.omega(n);
        let z = zeta(w);
        let big = n as f64 * PI * v / l;
        let wd = w * (1.0 - z * z).sqrt();
        // The harmonic's coefficients for the axles on the span at time t.
        let at = |t: f64| {
            let (mut a, mut b) = (0.0, 0.0);
            for ax in &train.axles {
                let tk = ax.position / v;
                if t >= tk && t < tk + l / v {
                    let (s, c) = (big * tk).sin_cos();
                    a -= ax.load * c;
                    b += ax.load * s;
                }
            }
            (scale * a, scale * b)
        };
        // They change only at the events: one pair per interval between them (taken at its
        // middle, away from the rounding of the events' times), the interval of `t` being
        // the one after the events up to `t`.
        let n_ev = events.len();
        let table: Vec<(f64, f64)> = (0..=n_ev)
            .map(|k| match k {
                0 => at(-1.0),
                _ if k == n_ev => at(events[k - 1] + 1.0),
                _ => at(0.5 * (events[k - 1] + events[k])),
            })
            .collect();
        let coeffs = |t: f64| table[events.partition_point(|&e| e <= t)];
        let particular = |a: f64, b: f64| {
            let (p, q) = (w * w - big * big, 2.0 * z * w * big);
            let det = p * p + q * q;
            ((p * a + q * b) / det, (p * b - q * a) / det)
        };
        // Exact advance over [t0, t1] with the harmonic (a, b) holding throughout.
        let advance = |t0: f64, t1: f64, q: f64, qd: f64, a: f64, b: f64| {
            let (c, d) = particular(a, b);
            let qp = |t: f64| c * (big * t).sin() + d * (big * t).cos();
            let qpd = |t: f64| big * (c * (big * t).cos() - d * (big * t).sin());
            let (e0, ed0) = (q - qp(t0), qd - qpd(t0));
            let tau = t1 - t0;
            let (sn, cs) = (wd * tau).sin_cos();
            let ex = (-z * w * tau).exp();
            let e = ex * (e0 * cs + (ed0 + z * w * e0) / wd * sn);
            let ed = ex * (ed0 * cs - (z * w * ed0 + w * w * e0) / wd * sn);
            (e + qp(t1), ed + qpd(t1))
        };
        let shapes: Vec<f64> = stations
            .iter()
            .map(|x| (n as f64 * PI * x / l).sin())
            .collect();
        let (mut q, mut qd) = (0.0, 0.0);
        let mut ev = 0;
        for i in 0..samples {
            let t = i as f64 * dt;
            if i > 0 {
                let mut t0 = (i - 1) as f64 * dt;
                while ev < events.len() && events[ev] <= t0 {
                    ev += 1;
                }
                // Split the interval at every event inside it.
                while ev < events.len() && events[ev] < t {
                    let te = events[ev];
                    let (a, b) = coeffs(0.5 * (t0 + te));
                    (q, qd) = advance(t0, te, q, qd, a, b);
                    t0 = te;
                    ev += 1;
                }
                let (a, b) = coeffs(0.5 * (t0 + t));
                (q, qd) = advance(t0, t, q, qd, a, b);
            }
            let (a, b) = coeffs(t);
            let f = a * (big * t).sin() + b * (big * t).cos();
            let qdd = f - 2.0 * z * w * qd - w * w * q;
            for (j, s) in shapes.iter().enumerate() {
                out.deflection[j][i] += q * s;
                out.acceleration[j][i] += qdd * s;
            }
        }
    }
    out
}

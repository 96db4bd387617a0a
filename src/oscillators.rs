//! Validation of the moving oscillators (`moving_sprung_mass`, `moving_mass`) against an
//! independent modal solution of a simply supported Euler–Bernoulli span.
//!
//! What lives here: the modal model ([`modal`], derived in `docs/moving-oscillators.md`)
//! integrated by classical RK4, the finite element run of the same case ([`fe_run`]) and
//! their comparison ([`compare`]). The span and the sprung mass are the `railfem pareto`
//! case (Yang & Wu's 25 m bridge: EI = 2.943e10 N·m², m = 2303 kg/m; M = 5750 kg,
//! k = 1.595 MN/m). The tests (tests/moving_oscillators.rs) run short versions; the
//! convergence study with the figure is `cargo run --release --example moving_oscillators`.
//!
//! # Modal model
//!
//! `w(x,t) = Σ_{n≤N} q_n(t)·φ_n(x)`, `φ_n = sin(nπx/L)` on `0 ≤ x ≤ L` (zero off the span),
//! `ω_n = (nπ/L)²·√(EI/μ)`. The contact point is at `x_c = s(t)` (the speed history),
//! moving at `v = ṡ`, accelerating at `a = v̇`. Projection of `EI·w'''' + μ·ẅ = f·δ(x − x_c)`
//! on `φ_n` (with `∫μφ_n² = μL/2`): `q̈_n + ω_n²·q_n = (2/(μL))·φ_n(x_c)·f`.
//!
//! Gravity acts on the span too: its static sag `w_s(x)` ([`sag`]) superposes (the problem
//! is linear), and the rider travels over it, so the contact sees `w_s + Σ q_n φ_n`.
//!
//! - **Sprung mass** (`z` up from the unstretched spring): `f = k·(z − w_c) + c·(ż − ẇ_c)`
//!   with `w_c = w_s(x_c) + Σ q_n φ_n(x_c)`, `ẇ_c = v·w_s'(x_c) + Σ (q̇_n φ_n + v·q_n φ_n')`, and
//!   `m·z̈ = −m·g − f`. From `q = q̇ = 0`, `ż = 0` and `z` in static equilibrium over the
//!   support, `k·z − c·v0·w_s'(0) = −m·g` (the FE's initial static solve balances the
//!   dashpot's convective force at t = 0 too).
//! - **Moving mass**: `f = −m·(g + ÿ_c)`,
//!   `ÿ_c = v²·w_s'' + a·w_s' + Σ_k [q̈_k φ_k + 2v·q̇_k φ_k' + (v²·φ_k'' + a·φ_k')·q_k]`
//!   (the convective terms). Moving `m·φφᵀq̈` to the left gives the mass matrix
//!   `(μL/2)·I + m·φφᵀ`, inverted in O(N) by Sherman–Morrison.

use crate::framework::element::Element;
use crate::framework::model::{AnalysisSpec, IntegratorKind};
use crate::framework::speed::SpeedHistory;
use crate::framework::{Dof, FemError};
use crate::pareto::{EI, MASS_PER_LENGTH, SPAN, SPRUNG_K, SPRUNG_MASS};
use crate::solvers::Driver;
use serde_json::json;
use std::f64::consts::PI;

/// Gravity (m/s²).
pub const G: f64 = 9.81;

/// What rides over the span.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Rider {
    /// A mass `m` (kg) on a spring `k` (N/m) and dashpot `c` (N·s/m).
    Sprung {
        /// Mass (kg).
        m: f64,
        /// Stiffness (N/m).
        k: f64,
        /// Damping (N·s/m).
        c: f64,
    },
    /// A mass `m` (kg) rolling on the span.
    Rolling {
        /// Mass (kg).
        m: f64,
    },
}

/// A validation case: the rider, its speed history from station 0 (the left support) and
/// the duration (s).
#[derive(Debug, Clone)]
pub struct Case {
    /// Short name.
    pub name: &'static str,
    /// The rider.
    pub rider: Rider,
    /// Speed history (`start` = 0).
    pub history: SpeedHistory,
    /// The model-file keys of the same history (`speed`/`accel` or `speed_table`).
    pub speed_keys: serde_json::Value,
    /// Duration (s): up to the crossing's end.
    pub t_end: f64,
}

impl Case {
    /// The `railfem pareto` sprung mass at constant speed 27.78 m/s (undamped).
    pub fn sprung_constant() -> Case {
        let v = crate::pareto::SPEED;
        Case {
            name: "sprung mass, constant speed",
            rider: Rider::Sprung {
                m: SPRUNG_MASS,
                k: SPRUNG_K,
                c: 0.0,
            },
            history: SpeedHistory::uniform(0.0, v, 0.0).expect("valid"),
            speed_keys: json!({"speed": v}),
            t_end: SPAN / v,
        }
    }

    /// The sprung mass, damped (c = 2·0.05·√(k·m)), braking at 6 m/s² from 27.78 m/s.
    pub fn sprung_braking() -> Case {
        let (v0, a) = (crate::pareto::SPEED, -6.0);
        // Time to cover the span: L = v0·t + ½·a·t².
        let t_end = (v0 - (v0 * v0 + 2.0 * a * SPAN).sqrt()) / -a;
        Case {
            name: "sprung mass, braking",
            rider: Rider::Sprung {
                m: SPRUNG_MASS,
                k: SPRUNG_K,
                c: 0.1 * (SPRUNG_K * SPRUNG_MASS).sqrt(),
            },
            history: SpeedHistory::uniform(0.0, v0, a).expect("valid"),
            speed_keys: json!({"speed": v0, "accel": a}),
            t_end,
        }
    }

    /// A 20 t mass rolling over the span, braking from 40 to 30 m/s in 0.7 s (speed table),
    /// then at 30 m/s.
    pub fn rolling_table() -> Case {
        let rows = [[0.0, 40.0], [0.7, 30.0]];
        // 24.5 m in the first 0.7 s, the last 0.5 m at 30 m/s.
        let t_end = 0.7 + (SPAN - 24.5) / 30.0;
        Case {
            name: "moving mass, speed table",
            rider: Rider::Rolling { m: 20_000.0 },
            history: SpeedHistory::from_table(0.0, &rows, "speed_table").expect("valid"),
            speed_keys: json!({"speed_table": rows}),
            t_end,
        }
    }
}

/// Histories sampled at the times `t`: midspan deflection (m, up) and the rider's vertical
/// acceleration (m/s²: the sprung mass's `z̈`, or the rolling mass's `ÿ_c`).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Histories {
    /// Times (s).
    pub t: Vec<f64>,
    /// Midspan deflection (m, up positive).
    pub midspan: Vec<f64>,
    /// The rider's vertical acceleration (m/s²).
    pub rider_acc: Vec<f64>,
}

fn omega(n: usize) -> f64 {
    (n as f64 * PI / SPAN).powi(2) * (EI / MASS_PER_LENGTH).sqrt()
}

/// Mode shapes and their first two derivatives at `x` into `p`, `d`, `dd` (zero off the
/// span); `sin(nθ)`, `cos(nθ)` by the angle-addition recurrence.
fn shapes(x: f64, p: &mut [f64], d: &mut [f64], dd: &mut [f64]) {
    if !(0.0..=SPAN).contains(&x) {
        p.fill(0.0);
        d.fill(0.0);
        dd.fill(0.0);
        return;
    }
    let k1 = PI / SPAN;
    let (s1, c1) = (k1 * x).sin_cos();
    let (mut s, mut c) = (s1, c1);
    for i in 0..p.len() {
        let kx = (i + 1) as f64 * k1;
        p[i] = s;
        d[i] = kx * c;
        dd[i] = -kx * kx * s;
        (s, c) = (s * c1 + c * s1, c * c1 - s * s1);
    }
}

/// The modal solution of `case` with `modes` modes, sampled at `samples + 1` equally
/// spaced times; classical RK4 with the step `h ≤ courant/ω_N` (a whole number of steps
/// per sample; RK4 is stable for `h·ω < 2.8`). See the module documentation.
pub fn modal(case: &Case, modes: usize, samples: usize, courant: f64) -> Histories {
    let n = modes;
    let every = ((case.t_end * omega(n) / courant / samples as f64).ceil() as usize).max(1);
    let steps = samples * every;
    let h = case.t_end / steps as f64;
    let w2: Vec<f64> = (1..=n).map(|i| omega(i).powi(2)).collect();
    let d = MASS_PER_LENGTH * SPAN / 2.0;
    let rider = case.rider;
    let hist = &case.history;
    // State y = [q, q̇, (z, ż)]; returns dy and the rider's acceleration.
    let rhs = |t: f64, y: &[f64], dy: &mut [f64]| -> f64 {
        let (x, v, a) = (hist.station(t), hist.speed(t), hist.accel(t));
        let (mut p, mut p1, mut p2) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
        shapes(x, &mut p, &mut p1, &mut p2);
        let [ws, ws1, ws2] = sag(x);
        dy[..n].copy_from_slice(&y[n..2 * n]);
        match rider {
            Rider::Sprung { m, k, c } => {
                let (mut wc, mut wcd) = (ws, v * ws1);
                for i in 0..n {
                    wc += y[i] * p[i];
                    wcd += y[n + i] * p[i] + v * y[i] * p1[i];
                }
                let f = k * (y[2 * n] - wc) + c * (y[2 * n + 1] - wcd);
                for i in 0..n {
                    dy[n + i] = -w2[i] * y[i] + f * p[i] / d;
                }
                dy[2 * n] = y[2 * n + 1];
                dy[2 * n + 1] = -G - f / m;
                dy[2 * n + 1]
            }
            Rider::Rolling { m } => {
                // e = Σ 2v·q̇φ' + (v²φ'' + aφ')·q: the convective part of ÿ_c.
                let mut e = v * v * ws2 + a * ws1;
                for i in 0..n {
                    e += 2.0 * v * y[n + i] * p1[i] + (v * v * p2[i] + a * p1[i]) * y[i];
                }
                // (D·I + m·φφᵀ)·q̈ = r, r = −D·ω²q − m·(g + e)·φ.
                let r: Vec<f64> = (0..n)
                    .map(|i| -d * w2[i] * y[i] - m * (G + e) * p[i])
                    .collect();
                let pr: f64 = (0..n).map(|i| p[i] * r[i]).sum();
                let pp: f64 = p.iter().map(|x| x * x).sum();
                let coef = m * pr / (d * d) / (1.0 + m * pp / d);
                let mut acc = e;
                for i in 0..n {
                    let qdd = r[i] / d - p[i] * coef;
                    dy[n + i] = qdd;
                    acc += p[i] * qdd;
                }
                acc
            }
        }
    };
    let len = match rider {
        Rider::Sprung { .. } => 2 * n + 2,
        Rider::Rolling { .. } => 2 * n,
    };
    let mut y = vec![0.0; len];
    if let Rider::Sprung { m, k, c } = rider {
        // Static equilibrium at t = 0 over the support, as the FE's initial static solve:
        // k·z − c·v0·w_s'(0) = −m·g (the dashpot feels the sag's slope at the speed v0).
        y[2 * n] = (-m * G + c * hist.speed(0.0) * sag(hist.station(0.0))[1]) / k;
    }
    let mid = |y: &[f64]| {
        (0..n)
            .map(|i| y[i] * ((i + 1) as f64 * PI * 0.5).sin())
            .sum::<f64>()
    };
    let mut out = Histories::default();
    let (mut k1, mut k2, mut k3, mut k4, mut tmp) = (
        vec![0.0; len],
        vec![0.0; len],
        vec![0.0; len],
        vec![0.0; len],
        vec![0.0; len],
    );
    let record = |t: f64, y: &[f64], out: &mut Histories, k: &mut [f64]| {
        let acc = rhs(t, y, k);
        out.t.push(t);
        out.midspan.push(mid(y));
        out.rider_acc.push(acc);
    };
    record(0.0, &y, &mut out, &mut k1);
    for s in 0..steps {
        let t = s as f64 * h;
        rhs(t, &y, &mut k1);
        for i in 0..len {
            tmp[i] = y[i] + 0.5 * h * k1[i];
        }
        rhs(t + 0.5 * h, &tmp, &mut k2);
        for i in 0..len {
            tmp[i] = y[i] + 0.5 * h * k2[i];
        }
        rhs(t + 0.5 * h, &tmp, &mut k3);
        for i in 0..len {
            tmp[i] = y[i] + h * k3[i];
        }
        rhs(t + h, &tmp, &mut k4);
        for i in 0..len {
            y[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
        }
        if (s + 1) % every == 0 {
            record(t + h, &y, &mut out, &mut k1);
        }
    }
    out
}

/// The sag of the span under its own weight at `x` and its first two derivatives:
/// `w_s = −(μg/(24EI))·x·(L³ − 2Lx² + x³)` (the static solution of `EI·w'''' = −μg`,
/// simply supported; zero off the span). The rider travels over it.
pub fn sag(x: f64) -> [f64; 3] {
    if !(0.0..=SPAN).contains(&x) {
        return [0.0; 3];
    }
    let c = -MASS_PER_LENGTH * G / (24.0 * EI);
    let l = SPAN;
    [
        c * x * (l.powi(3) - 2.0 * l * x * x + x.powi(3)),
        c * (l.powi(3) - 6.0 * l * x * x + 4.0 * x.powi(3)),
        c * (-12.0 * l * x + 12.0 * x * x),
    ]
}

/// Static midspan deflection of the span under its own weight (m, up):
/// `−5·μ·g·L⁴/(384·EI)`; the finite element runs carry it (gravity acts on the beam too),
/// the modal model does not (the problem is linear, so it superposes).
pub fn self_weight_midspan() -> f64 {
    -5.0 * MASS_PER_LENGTH * G * SPAN.powi(4) / (384.0 * EI)
}

/// The finite element run of `case`: `ne` `beam3d` elements (consistent mass), average-
/// acceleration Newmark with step `dt`, gravity on everything, static equilibrium at t = 0.
/// The midspan history has the self-weight deflection removed.
pub fn fe_run(case: &Case, ne: usize, dt: f64) -> Result<Histories, FemError> {
    let mut b = crate::pareto::span(ne);
    let path: Vec<u64> = (1..=ne as u64).collect();
    let mass_node = ne as u64 + 2;
    let mut keys = case.speed_keys.clone();
    let kind = match case.rider {
        Rider::Sprung { m, k, c } => {
            b.node_fixed(mass_node, [0.0, 0.0, 1.0], crate::framework::DofSet::NONE);
            keys["m"] = json!(m);
            keys["k"] = json!(k);
            keys["c"] = json!(c);
            "moving_sprung_mass"
        }
        Rider::Rolling { m } => {
            keys["m"] = json!(m);
            "moving_mass"
        }
    };
    keys["path"] = json!(path);
    let nodes: Vec<u64> = if kind == "moving_sprung_mass" {
        vec![mass_node]
    } else {
        Vec::new()
    };
    b.element(kind, ne as u64 + 1, &nodes, &keys);
    let steps = (case.t_end / dt - 1e-9).floor() as usize;
    b.analysis(AnalysisSpec {
        dt,
        duration: steps as f64 * dt,
        integrator: IntegratorKind::Newmark,
        beta: 0.25,
        gamma: 0.5,
        gravity: Some([0.0, 0.0, -G]),
        initial_static: true,
        ..Default::default()
    });
    let model = b.build()?;
    let mut d = Driver::new(model)?;
    d.initialize()?;
    let mid = (ne / 2 + 1) as u64;
    let w0 = self_weight_midspan();
    let osc = d.model.elements.len() - 1;
    let mass_index = d.model.node(mass_node);
    let mut out = Histories::default();
    let record = |d: &Driver, out: &mut Histories| {
        out.t.push(d.state.t);
        out.midspan
            .push(d.displacement(mid, Dof::Uz).unwrap_or(f64::NAN) - w0);
        let acc = match mass_index {
            Some(i) => d.asm.dofmap.value(&d.state.a, i, Dof::Uz),
            None => {
                let mut o = Vec::new();
                d.model.elements[osc].element.outputs(&mut o);
                o[4]
            }
        };
        out.rider_acc.push(acc);
    };
    record(&d, &mut out);
    for _ in 0..steps {
        crate::framework::interrupt::check(d.state.t)?;
        d.step(dt)?;
        record(&d, &mut out);
    }
    Ok(out)
}

/// Linear interpolation of a history `(t, y)` at `t`.
fn interp(t: &[f64], y: &[f64], x: f64) -> f64 {
    let i = t.partition_point(|v| *v <= x).clamp(1, t.len() - 1);
    let (t0, t1) = (t[i - 1], t[i]);
    let f = ((x - t0) / (t1 - t0)).clamp(0.0, 1.0);
    y[i - 1] * (1.0 - f) + y[i] * f
}

/// Errors of `fe` against `reference` (sampled much finer): the largest difference over
/// the run relative to the reference's largest magnitude, for the midspan deflection and
/// the rider's acceleration.
pub fn compare(fe: &Histories, reference: &Histories) -> (f64, f64) {
    let rel = |a: &[f64], r: &[f64]| {
        let peak = r.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let worst =
            fe.t.iter()
                .zip(a)
                .map(|(&t, &x)| (x - interp(&reference.t, r, t)).abs())
                .fold(0.0f64, f64::max);
        worst / peak
    };
    (
        rel(&fe.midspan, &reference.midspan),
        rel(&fe.rider_acc, &reference.rider_acc),
    )
}

/// `(largest |difference|, largest |reference|)` of two modal solutions on the same grid.
pub fn modal_difference(a: &[f64], b: &[f64]) -> f64 {
    let peak = b.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0f64, f64::max)
        / peak
}

/// The element of a finished run, for callers that want its outputs.
pub fn oscillator(d: &Driver) -> &dyn Element {
    &*d.model.elements[d.model.elements.len() - 1].element
}

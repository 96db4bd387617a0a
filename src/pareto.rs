//! `railfem pareto`: run time against error over time step, mesh size and integrator, for
//! three cases with independent references, and the Pareto front of each.
//!
//! The cases:
//!
//! - **force** — a constant force crossing a simply supported span (the bridge of Yang &
//!   Wu: L = 25 m, EI = 2.943e10 N·m², m = 2303 kg/m, v = 27.78 m/s, P = 100 kN), `beam3d`
//!   elements with consistent mass and the `moving_force` load; error = largest midspan
//!   deflection difference from Frýba's modal series ([`fryba_midspan`]) over the crossing,
//!   relative to the series' peak.
//! - **sprung** — a mass M = 5750 kg on a spring k = 1.595 MN/m riding over the same span
//!   at the same speed, weighed down by gravity; the spring's foot follows the beam's
//!   Hermite deflection under the moving contact point (the `moving_sprung_mass` element,
//!   see `docs/moving-oscillators.md`). Reference: the beam's modal equations coupled
//!   with the mass, integrated by classical RK4 with a step far below anything the FE runs
//!   use ([`sprung_reference`]); error as for the force case.
//! - **curve** — the paper's curved-track case on the shortened (`--quick`) track, rigid
//!   track, error = largest relative difference of the wheels' normal forces from rigid-body
//!   statics on the arc ([`crate::curve`]). The track is rigid, so only the time step and
//!   the integrator vary.
//!
//! Integrators: average-acceleration Newmark, HHT with Hilber's α = −0.05 and generalized-α
//! with ρ∞ = 0.8. Each run's wall time covers building the model, the driver's set-up and
//! every step; the reference is computed outside the timed region. Timings depend on the
//! machine's load and are never asserted.

use crate::framework::builder::ModelBuilder;
use crate::framework::loads::{LoadSpec, TimeSeries};
use crate::framework::model::{AnalysisSpec, IntegratorKind};
use crate::framework::plot::{Corner, Figure, Panel, Series, Style};
use crate::framework::{Dof, DofSet, FemError, Model};
use crate::solvers::Driver;
use serde_json::json;
use std::f64::consts::PI;
use std::path::Path;
use std::time::Instant;

/// Span (m).
pub const SPAN: f64 = 25.0;
/// Bending stiffness EI (N·m²).
pub const EI: f64 = 2.943e10;
/// Mass per length (kg/m).
pub const MASS_PER_LENGTH: f64 = 2303.0;
/// Speed (m/s).
pub const SPEED: f64 = 27.78;
/// Moving force (N), downward.
pub const FORCE: f64 = 1.0e5;
/// Sprung mass (kg).
pub const SPRUNG_MASS: f64 = 5750.0;
/// Suspension stiffness (N/m).
pub const SPRUNG_K: f64 = 1.595e6;
/// Gravity (m/s²).
pub const GRAVITY: f64 = 9.81;

const E: f64 = 2.1e11;
const RHO: f64 = 7850.0;

/// Circular frequency of mode `n` of the simply supported span (rad/s):
/// `ω_n = (nπ/L)²·√(EI/m)`.
pub fn omega(n: usize) -> f64 {
    (n as f64 * PI / SPAN).powi(2) * (EI / MASS_PER_LENGTH).sqrt()
}

/// Period of the first mode (s), 0.1113 s.
pub fn period1() -> f64 {
    2.0 * PI / omega(1)
}

/// Which integrator a run uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Scheme {
    /// Average acceleration (β = ¼, γ = ½).
    Newmark,
    /// HHT, Hilber's α = −0.05 (railfem's `alpha` = 0.05).
    Hht,
    /// Generalized-α, ρ∞ = 0.8.
    GenAlpha,
}

impl Scheme {
    /// All three.
    pub const ALL: [Scheme; 3] = [Scheme::Newmark, Scheme::Hht, Scheme::GenAlpha];

    /// Short name for tables.
    pub fn name(self) -> &'static str {
        match self {
            Scheme::Newmark => "newmark",
            Scheme::Hht => "hht-0.05",
            Scheme::GenAlpha => "genalpha-0.8",
        }
    }

    fn analysis(self, dt: f64, duration: f64) -> AnalysisSpec {
        let mut a = AnalysisSpec {
            dt,
            duration,
            beta: 0.25,
            gamma: 0.5,
            ..Default::default()
        };
        match self {
            Scheme::Newmark => a.integrator = IntegratorKind::Newmark,
            Scheme::Hht => {
                a.integrator = IntegratorKind::Hht;
                a.alpha = 0.05;
            }
            Scheme::GenAlpha => {
                a.integrator = IntegratorKind::GeneralizedAlpha;
                a.rho_inf = 0.8;
            }
        }
        a
    }
}

/// One run of the grid.
#[derive(Debug, Clone, PartialEq)]
pub struct Run {
    /// `force`, `sprung` or `curve`.
    pub case: &'static str,
    /// The integrator.
    pub scheme: Scheme,
    /// Elements on the span (0 for the rigid-track curve case).
    pub elements: usize,
    /// Time step (s).
    pub dt: f64,
    /// Steps taken.
    pub steps: usize,
    /// Wall time of the run (s).
    pub wall: f64,
    /// Error against the case's reference (relative, see the module doc).
    pub error: f64,
    /// On the case's Pareto front (no other run is both faster and more accurate).
    pub pareto: bool,
}

/// Deflection at midspan (m, along the force) of the simply supported span under the
/// force `P` at `x = v·t`, from rest, `0 ≤ v·t ≤ L`: Frýba's modal series, `terms` modes.
///
/// With `w = Σ q_n(t)·sin(nπx/L)`, `EI·w'''' + m·ẅ = P·δ(x − vt)` projects to
/// `q̈_n + ω_n²·q_n = (2P/(mL))·sin(nωt)`, `ω = πv/L`. From rest the solution is
/// `q_n = (2P/(mL))/(ω_n² − n²ω²)·[sin(nωt) − (nω/ω_n)·sin(ω_n·t)]`. The neglected modes
/// add at most `Σ_{n>N} 2PL³/(π⁴EI·n⁴)`, below 1e-6 of the peak for N = 200.
pub fn fryba_midspan(t: f64, terms: usize) -> f64 {
    let w = PI * SPEED / SPAN;
    let c = 2.0 * FORCE / (MASS_PER_LENGTH * SPAN);
    (1..=terms)
        .map(|n| {
            let nf = n as f64;
            let wn = omega(n);
            let f = nf * w;
            let q = c / (wn * wn - f * f) * ((f * t).sin() - f / wn * (wn * t).sin());
            q * (nf * PI * 0.5).sin()
        })
        .sum()
}

/// The reference of the sprung-mass case: midspan deflection (m, up positive) on a
/// uniform grid of `samples + 1` times over the crossing `[0, L/v]`.
///
/// Equations. Beam `w(x,t) = Σ_{n≤N} q_n(t)·sin(nπx/L)`; the mass's vertical
/// displacement `z` (up) from where its spring is unstretched; contact point `x_c = v·t`,
/// spring stretch `δ = z − w(x_c)`, spring force on the beam `F = k·δ` (upward; δ < 0
/// under the weight pushes the beam down). Then
///
/// ```text
/// q̈_n + ω_n²·q_n = (2/(mL))·k·δ·sin(nπx_c/L)        (projection on sin(nπx/L))
/// M·z̈ = −M·g − k·δ
/// ```
///
/// from `q_n = q̇_n = 0`, `z = −Mg/k`, `ż = 0` (the mass at rest on its spring over the
/// support). Integrated with classical fourth-order Runge–Kutta, `substeps` steps between
/// samples. The FE model starts from the same state (its static solve at t = 0 with the
/// contact at the support node).
pub fn sprung_reference(modes: usize, samples: usize, substeps: usize) -> Vec<f64> {
    let n = modes;
    let t_end = SPAN / SPEED;
    let h = t_end / (samples * substeps) as f64;
    let w2: Vec<f64> = (1..=n).map(|i| omega(i).powi(2)).collect();
    let c = 2.0 / (MASS_PER_LENGTH * SPAN);
    // y = [q_1..q_n, q̇_1..q̇_n, z, ż]
    let rhs = |t: f64, y: &[f64], dy: &mut [f64]| {
        let xc = SPEED * t;
        let mut wc = 0.0;
        let shapes: Vec<f64> = (1..=n).map(|i| (i as f64 * PI * xc / SPAN).sin()).collect();
        for i in 0..n {
            wc += y[i] * shapes[i];
        }
        let f = SPRUNG_K * (y[2 * n] - wc);
        for i in 0..n {
            dy[i] = y[n + i];
            dy[n + i] = -w2[i] * y[i] + c * f * shapes[i];
        }
        dy[2 * n] = y[2 * n + 1];
        dy[2 * n + 1] = -GRAVITY - f / SPRUNG_MASS;
    };
    let m = 2 * n + 2;
    let mut y = vec![0.0; m];
    y[2 * n] = -SPRUNG_MASS * GRAVITY / SPRUNG_K;
    let mid = |y: &[f64]| {
        (0..n)
            .map(|i| y[i] * ((i + 1) as f64 * PI * 0.5).sin())
            .sum::<f64>()
    };
    let mut out = vec![mid(&y)];
    let (mut k1, mut k2, mut k3, mut k4, mut tmp) = (
        vec![0.0; m],
        vec![0.0; m],
        vec![0.0; m],
        vec![0.0; m],
        vec![0.0; m],
    );
    for s in 0..samples {
        for j in 0..substeps {
            let t = (s * substeps + j) as f64 * h;
            rhs(t, &y, &mut k1);
            for i in 0..m {
                tmp[i] = y[i] + 0.5 * h * k1[i];
            }
            rhs(t + 0.5 * h, &tmp, &mut k2);
            for i in 0..m {
                tmp[i] = y[i] + 0.5 * h * k2[i];
            }
            rhs(t + 0.5 * h, &tmp, &mut k3);
            for i in 0..m {
                tmp[i] = y[i] + h * k3[i];
            }
            rhs(t + h, &tmp, &mut k4);
            for i in 0..m {
                y[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
            }
        }
        out.push(mid(&y));
    }
    out
}

/// Linear interpolation in a history sampled uniformly over `[0, t_end]`.
pub fn sample_at(hist: &[f64], t_end: f64, t: f64) -> f64 {
    let n = hist.len() - 1;
    let s = (t / t_end * n as f64).clamp(0.0, n as f64);
    let i = (s.floor() as usize).min(n.saturating_sub(1));
    let f = s - i as f64;
    hist[i] * (1.0 - f) + hist[(i + 1).min(n)] * f
}

/// A simply supported span of `ne` `beam3d` elements along X, nodes `1..=ne+1`, element
/// ids `1..=ne`; only vertical bending is free (ux, uy, rx, rz held at every node; uz held
/// at both ends). Section: E = 210 GPa, ρ = 7850 kg/m³, `Iy = EI/E`, `A = m/ρ`.
pub(crate) fn span(ne: usize) -> ModelBuilder {
    let mut b = ModelBuilder::new(format!("pareto span ({ne} elements)"));
    let plane = DofSet::of(&[Dof::Ux, Dof::Uy, Dof::Rx, Dof::Rz]);
    for i in 0..=ne {
        let fixed = if i == 0 || i == ne {
            plane.with(Dof::Uz)
        } else {
            plane
        };
        b.node_fixed(i as u64 + 1, [SPAN * i as f64 / ne as f64, 0.0, 0.0], fixed);
    }
    let p = json!({"E": E, "G": E / 2.6, "A": MASS_PER_LENGTH / RHO, "Iy": EI / E,
                   "Iz": EI / E, "J": EI / E, "rho": RHO, "mass": "consistent"});
    for e in 1..=ne as u64 {
        b.element("beam3d", e, &[e, e + 1], &p);
    }
    b
}

/// Runs `model` for `steps` steps of `dt`, calling `probe(driver)` after each step;
/// returns the wall time of build-to-last-step (`t0` = when the model build began).
fn drive(
    model: Model,
    dt: f64,
    steps: usize,
    t0: Instant,
    probe: &mut dyn FnMut(&Driver),
) -> Result<f64, FemError> {
    let mut d = Driver::new(model)?;
    d.initialize()?;
    let mut inner = 0.0;
    for _ in 0..steps {
        d.step(dt)?;
        let s = Instant::now();
        probe(&d);
        inner += s.elapsed().as_secs_f64();
    }
    Ok(t0.elapsed().as_secs_f64() - inner)
}

/// Moving force on `ne` elements with step `dt`: `(wall s, error, steps)`.
pub fn force_run(ne: usize, dt: f64, scheme: Scheme) -> Result<(f64, f64, usize), FemError> {
    let t_end = SPAN / SPEED;
    let steps = (t_end / dt).floor() as usize;
    let t0 = Instant::now();
    let mut b = span(ne);
    b.load(LoadSpec::MovingForce {
        elements: (1..=ne as u64).collect(),
        force: [0.0, 0.0, -FORCE],
        speed: SPEED,
        start: 0.0,
    });
    b.analysis(scheme.analysis(dt, t_end));
    let model = b.build()?;
    let mid = (ne / 2 + 1) as u64;
    let (mut worst, mut peak) = (0.0f64, 0.0f64);
    let wall = drive(model, dt, steps, t0, &mut |d| {
        let fe = -d.displacement(mid, Dof::Uz).unwrap_or(f64::NAN);
        let exact = fryba_midspan(d.state.t, 200);
        worst = worst.max((fe - exact).abs());
        peak = peak.max(exact.abs());
    })?;
    Ok((wall, worst / peak, steps))
}

/// Samples of the sprung-mass reference (RK4 with `REF_SAMPLES · REF_SUBSTEPS` steps).
pub const REF_SAMPLES: usize = 20_000;
/// RK4 steps per reference sample.
pub const REF_SUBSTEPS: usize = 10;
/// Modes of the sprung-mass reference.
pub const REF_MODES: usize = 60;

/// Sprung mass on `ne` elements with step `dt` against the reference history `reference`
/// (from [`sprung_reference`]): `(wall s, error, steps)`.
pub fn sprung_run(
    ne: usize,
    dt: f64,
    scheme: Scheme,
    reference: &[f64],
) -> Result<(f64, f64, usize), FemError> {
    let t_end = SPAN / SPEED;
    let steps = (t_end / dt).floor() as usize;
    let t0 = Instant::now();
    let mut b = span(ne);
    let mass_node = ne as u64 + 2;
    b.node_fixed(
        mass_node,
        [0.0, 0.0, 1.0],
        DofSet::of(&[Dof::Ux, Dof::Uy, Dof::Rx, Dof::Ry, Dof::Rz]),
    );
    let path: Vec<u64> = (1..=ne as u64).collect();
    b.element(
        "moving_sprung_mass",
        ne as u64 + 2,
        &[mass_node],
        &json!({"m": SPRUNG_MASS, "k": SPRUNG_K, "speed": SPEED, "path": path}),
    );
    b.load(LoadSpec::Nodal {
        node: mass_node,
        dof: Dof::Uz,
        value: -SPRUNG_MASS * GRAVITY,
        series: TimeSeries::Constant,
    });
    let mut a = scheme.analysis(dt, t_end);
    a.initial_static = true;
    b.analysis(a);
    let model = b.build()?;
    let mid = (ne / 2 + 1) as u64;
    let (mut worst, mut peak) = (0.0f64, 0.0f64);
    let wall = drive(model, dt, steps, t0, &mut |d| {
        let fe = d.displacement(mid, Dof::Uz).unwrap_or(f64::NAN);
        let exact = sample_at(reference, t_end, d.state.t);
        worst = worst.max((fe - exact).abs());
    })?;
    for v in reference {
        peak = peak.max(v.abs());
    }
    Ok((wall, worst / peak, steps))
}

/// The curved-track case on the short track with step `dt`: `(wall s, error, steps)`.
pub fn curve_run(dt: f64, scheme: Scheme) -> Result<(f64, f64, usize), FemError> {
    let mut case = crate::curve::CurveCase {
        lengths: [60.0, 300.0, 700.0, 300.0, 60.0],
        dt,
        ..Default::default()
    };
    match scheme {
        Scheme::Newmark => case.integrator = IntegratorKind::Newmark,
        Scheme::Hht => {
            case.integrator = IntegratorKind::Hht;
            // curve.rs maps ρ∞ to HHT α = (1 − ρ∞)/(1 + ρ∞); α = 0.05 ⇔ ρ∞ = 0.95/1.05.
            case.rho_inf = 0.95 / 1.05;
        }
        Scheme::GenAlpha => {
            case.integrator = IntegratorKind::GeneralizedAlpha;
            case.rho_inf = 0.8;
        }
    }
    let t0 = Instant::now();
    let r = crate::curve::run(&case, None, &mut |_| {})?;
    Ok((
        t0.elapsed().as_secs_f64(),
        r.max_rel_normal_statics,
        r.steps,
    ))
}

/// The cases of [`Grid::cases`] (the train–bridge case has its own grid,
/// [`crate::pareto_train`]).
pub const CASES: [&str; 3] = ["force", "sprung", "curve"];

/// Parses a `--cases` list (`force,sprung`): the names, each one of `known`; an unknown
/// one is refused naming it and listing `known`.
pub fn parse_cases(spec: &str, known: &[&str]) -> Result<Vec<String>, FemError> {
    let cases: Vec<String> = spec.split(',').map(|x| x.trim().to_string()).collect();
    match cases.iter().find(|x| !known.contains(&x.as_str())) {
        Some(bad) => Err(FemError::input(
            "command line",
            format!(
                "--cases {spec}: unknown case `{bad}`; use any of {}",
                known.join(",")
            ),
        )),
        None => Ok(cases),
    }
}

/// The grid of one run of `railfem pareto`.
#[derive(Debug, Clone, PartialEq)]
pub struct Grid {
    /// Cases to run (`force`, `sprung`, `curve`).
    pub cases: Vec<String>,
    /// Elements on the span (force and sprung cases).
    pub elements: Vec<usize>,
    /// Steps per first-mode period T₁ (force and sprung cases): dt = T₁/value.
    pub steps_per_period: Vec<f64>,
    /// Time steps of the curve case (s).
    pub curve_dt: Vec<f64>,
}

impl Default for Grid {
    /// 5 meshes × 6 steps × 3 integrators per beam case, 3 steps × 3 integrators for the
    /// curve: a few minutes on two cores.
    fn default() -> Self {
        Grid {
            cases: vec!["force".into(), "sprung".into(), "curve".into()],
            elements: vec![2, 4, 8, 16, 32],
            steps_per_period: vec![10.0, 20.0, 40.0, 80.0, 160.0, 320.0],
            curve_dt: vec![0.04, 0.02, 0.01],
        }
    }
}

/// Marks the runs of each case that no other run of the case beats in both time and error.
pub fn mark_pareto(runs: &mut [Run]) {
    let n = runs.len();
    for i in 0..n {
        let (ci, wi, ei) = (runs[i].case, runs[i].wall, runs[i].error);
        let dominated = (0..n).any(|j| {
            j != i
                && runs[j].case == ci
                && runs[j].wall <= wi
                && runs[j].error <= ei
                && (runs[j].wall < wi || runs[j].error < ei)
        });
        runs[i].pareto = !dominated && ei.is_finite();
    }
}

/// Runs the grid; progress ([`crate::progress`]) and one line per run go to stderr.
pub fn run_grid(grid: &Grid) -> Result<Vec<Run>, FemError> {
    let mut runs = Vec::new();
    run_grid_into(grid, &mut runs)?;
    Ok(runs)
}

/// [`run_grid`] into `runs`. A stop request ([`crate::framework::interrupt`]) is honoured
/// between runs: `runs` then holds the completed runs (Pareto flags among them) and the
/// error is [`FemError::InterruptedAfter`]; a run cut inside is dropped, not reported as
/// "no result".
pub fn run_grid_into(grid: &Grid, runs: &mut Vec<Run>) -> Result<(), FemError> {
    let stop = |runs: &mut Vec<Run>, done: u64, total: usize| {
        mark_pareto(runs);
        crate::framework::interrupt::check_after(|| format!("{done} of {total} runs"))
    };
    let t1 = period1();
    let schemes = Scheme::ALL.len();
    let total: usize = grid
        .cases
        .iter()
        .map(|c| match c.as_str() {
            "curve" => grid.curve_dt.len() * schemes,
            _ => grid.elements.len() * grid.steps_per_period.len() * schemes,
        })
        .sum();
    let mut bar = crate::progress::Progress::new("pareto", total as u64, "runs");
    let mut done = 0u64;
    for case in &grid.cases {
        match case.as_str() {
            "force" | "sprung" => {
                let reference = if case == "sprung" {
                    sprung_reference(REF_MODES, REF_SAMPLES, REF_SUBSTEPS)
                } else {
                    Vec::new()
                };
                for &ne in &grid.elements {
                    for &spp in &grid.steps_per_period {
                        for scheme in Scheme::ALL {
                            let dt = t1 / spp;
                            let r = if case == "force" {
                                force_run(ne, dt, scheme)
                            } else {
                                sprung_run(ne, dt, scheme, &reference)
                            };
                            let (wall, error, steps) = match r {
                                // Cut inside by a stop request: dropped.
                                Err(FemError::Interrupted { .. }) => {
                                    return stop(runs, done, total)
                                }
                                r => r?,
                            };
                            done += 1;
                            bar.set(done);
                            bar.note(&format!(
                                "pareto {case}: {ne} elements, dt = T1/{spp} = {dt:.3e} s, {}: {wall:.4} s, error {error:.3e}",
                                scheme.name()
                            ));
                            runs.push(Run {
                                case: if case == "force" { "force" } else { "sprung" },
                                scheme,
                                elements: ne,
                                dt,
                                steps,
                                wall,
                                error,
                                pareto: false,
                            });
                            stop(runs, done, total)?;
                        }
                    }
                }
            }
            "curve" => {
                for &dt in &grid.curve_dt {
                    for scheme in Scheme::ALL {
                        // A step too coarse for the contact (Newton gives up) is a
                        // result, not a failure of the benchmark: report it and go on.
                        done += 1;
                        bar.set(done);
                        let (wall, error, steps) = match curve_run(dt, scheme) {
                            Ok(r) => r,
                            Err(FemError::Interrupted { .. }) => {
                                return stop(runs, done - 1, total);
                            }
                            Err(e) => {
                                bar.note(&format!(
                                    "pareto curve: dt = {dt} s, {}: no result ({e})",
                                    scheme.name()
                                ));
                                stop(runs, done, total)?;
                                continue;
                            }
                        };
                        bar.note(&format!(
                            "pareto curve: dt = {dt} s, {}: {wall:.3} s, error {error:.3e}",
                            scheme.name()
                        ));
                        runs.push(Run {
                            case: "curve",
                            scheme,
                            elements: 0,
                            dt,
                            steps,
                            wall,
                            error,
                            pareto: false,
                        });
                        stop(runs, done, total)?;
                    }
                }
            }
            other => {
                return Err(FemError::input(
                    "command line",
                    format!("--cases: unknown case `{other}`; use force, sprung, curve"),
                ))
            }
        }
    }
    mark_pareto(runs);
    Ok(())
}

/// The runs as CSV.
pub fn csv(runs: &[Run]) -> String {
    let mut s = String::from(
        "case [-],integrator [-],elements [-],dt [s],steps [-],wall [s],error [-],pareto [-]\n",
    );
    for r in runs {
        s.push_str(&format!(
            "{},{},{},{:.6e},{},{:.6e},{:.6e},{}\n",
            r.case,
            r.scheme.name(),
            r.elements,
            r.dt,
            r.steps,
            r.wall,
            r.error,
            r.pareto
        ));
    }
    s
}

/// The Pareto front of each case as a markdown table.
pub fn markdown(runs: &[Run]) -> String {
    let mut s = String::from(
        "| case | integrator | elements | dt (s) | steps | wall (s) | error |\n|---|---|---:|---:|---:|---:|---:|\n",
    );
    for r in runs.iter().filter(|r| r.pareto) {
        s.push_str(&format!(
            "| {} | {} | {} | {:.3e} | {} | {:.4} | {:.3e} |\n",
            r.case,
            r.scheme.name(),
            r.elements,
            r.dt,
            r.steps,
            r.wall,
            r.error
        ));
    }
    s
}

/// One figure per case: relative error against wall time on log–log axes, a marker series
/// per integrator and the Pareto front as a line.
pub fn figure(runs: &[Run], case: &str) -> Figure {
    let colors = ["#1f77b4", "#d62728", "#2ca02c"];
    let title = match case {
        "force" => "moving force on a simply supported span: error vs Frýba's series",
        "sprung" => "sprung mass on a simply supported span: error vs modal RK4 reference",
        _ => "curved track (short): wheel normal force vs rigid-body statics",
    };
    let mut p = Panel::new(title, "wall time (s)", "relative error (-)").log_log();
    p.legend = Corner::TopRight;
    for (scheme, color) in Scheme::ALL.iter().zip(colors) {
        let pts: Vec<&Run> = runs
            .iter()
            .filter(|r| r.case == case && r.scheme == *scheme)
            .collect();
        p = p.with(Series::new(
            scheme.name(),
            pts.iter().map(|r| r.wall).collect(),
            pts.iter().map(|r| r.error).collect(),
            Style::Markers,
            color,
        ));
    }
    let mut front: Vec<&Run> = runs.iter().filter(|r| r.case == case && r.pareto).collect();
    front.sort_by(|a, b| a.wall.total_cmp(&b.wall));
    p = p.with(Series::new(
        "Pareto front",
        front.iter().map(|r| r.wall).collect(),
        front.iter().map(|r| r.error).collect(),
        Style::Line,
        "black",
    ));
    Figure::new().with(p)
}

/// Runs the grid and writes `pareto.csv`, `pareto.md` and `pareto-<case>.svg` into `out`.
pub fn run(grid: &Grid, out: &Path) -> Result<Vec<Run>, FemError> {
    let mut runs = Vec::new();
    let done = run_grid_into(grid, &mut runs);
    // A stop between runs writes the completed runs; any other error, nothing.
    if let Err(e) = done {
        if !matches!(e, FemError::InterruptedAfter { .. }) {
            return Err(e);
        }
        write_outputs(grid, &runs, out)?;
        return Err(e);
    }
    write_outputs(grid, &runs, out)?;
    Ok(runs)
}

/// Writes `pareto.csv`, `pareto.md` and a figure per case of `runs`, prints the table.
fn write_outputs(grid: &Grid, runs: &[Run], out: &Path) -> Result<(), FemError> {
    std::fs::create_dir_all(out).map_err(|e| FemError::output(out, e))?;
    let p = out.join("pareto.csv");
    std::fs::write(&p, csv(runs)).map_err(|e| FemError::output(&p, e))?;
    let md = markdown(runs);
    let p = out.join("pareto.md");
    std::fs::write(&p, &md).map_err(|e| FemError::output(&p, e))?;
    for case in &grid.cases {
        let p = out.join(format!("pareto-{case}.svg"));
        figure(runs, case)
            .write_svg_and_png(&p)
            .map_err(|e| FemError::output(&p, e))?;
    }
    print!("{md}");
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The series at the end of the crossing: for α = ω/ω₁ → 0 it tends to the static
    /// deflection; here check its quasi-static value at mid-crossing against
    /// `PL³/(48EI)` within the dynamic amplification bound `1 + α/(1 − α)` (α = 0.062).
    #[test]
    fn fryba_midspan_is_near_static_at_mid_crossing() {
        let t = 0.5 * SPAN / SPEED;
        let w = fryba_midspan(t, 200);
        let stat = FORCE * SPAN.powi(3) / (48.0 * EI);
        let alpha = PI * SPEED / SPAN / omega(1);
        assert!(
            (w / stat - 1.0).abs() < alpha / (1.0 - alpha),
            "{w} vs {stat}"
        );
    }

    #[test]
    fn pareto_front_drops_dominated_runs() {
        let mk = |w: f64, e: f64| Run {
            case: "force",
            scheme: Scheme::Newmark,
            elements: 1,
            dt: 1.0,
            steps: 1,
            wall: w,
            error: e,
            pareto: false,
        };
        let mut r = vec![mk(1.0, 1.0), mk(2.0, 0.5), mk(2.0, 2.0), mk(3.0, 0.5)];
        mark_pareto(&mut r);
        let flags: Vec<bool> = r.iter().map(|x| x.pareto).collect();
        assert_eq!(flags, vec![true, true, false, false]);
    }
}

//! `railfem pareto --cases train-bridge`: run time against error for the train–bridge
//! model (`crate::train_bridge`) on a short crossing — one `sks700` carriage at 80 m/s over
//! three 29.75 m spans, straight track, no irregularity, no ground motion — over time step,
//! rail/slab/girder element length, integrator and linear solver.
//!
//! Every mesh has `h = SPACING / k`, so each 0.625 m fastener bay is split into `k` equal
//! elements and the support pattern is the same on every mesh (the track generator puts
//! the fasteners at their true stations whatever `h`; see `railfem_elements::rail::geometry::bridge`).
//!
//! Reference: the same model at a step and an element length below every grid point's
//! ([`REF_DT`], [`REF_H`], generalized-α ρ∞ = 0.8, partitioned solver). Its own error is
//! bounded over the whole crossing ([`reference_runs`]) by its two nearest coarser
//! neighbours: the next coarser mesh ([`CHECK_COARSE_K`] elements per bay) at its step, and
//! its mesh at twice its step (the grid's 0.25 ms run). If the error falls with order
//! `p` in a parameter refined by `r`, the reference's own error is `d/(r^p − 1)` of the
//! neighbour's difference `d` (Richardson); the differences are written into
//! `pareto-train-bridge.md`.
//!
//! Quantities, each compared with the reference at the reference's sample times (every
//! step of the reference from [`SETTLE`] to the shorter run's end), the compared run linearly
//! interpolated between its own samples (an interpolation error `≤ Δt²/8·max|ẍ|`, part of
//! what a user sampling at Δt would see, so it is counted in the error):
//!
//! - wheel force `Q` of each of the eight wheels: error `max |Q − Q_ref| / Q_static,ref`
//!   (`Q_static,ref` = the reference's wheel load at the initial equilibrium);
//! - `ΔQ/Q = (Q_static − Q)/Q_static` with each run's own static load: error
//!   `max |ΔQ/Q − ΔQ/Q_ref|`;
//! - girder midspan deflection `w_s` of every span `s` relative to the span's end nodes,
//!   from the self-weight state at t = 0 (`w_s(t) − w_s(0)`, the train's part): error
//!   `max over s and t of |w_s − w_s,ref| / max over s and t of |w_s,ref|` (one scale for
//!   all spans, so a span the train has not reached yet in a short window, with a tiny
//!   peak, does not blow up the error).
//!
//! Wall time covers building the model, the initial static solve and every step; so does
//! the run's cost, its CPU time ([`crate::cpu_time`]: the process's, every thread's). Run
//! on one core (`taskset -c N`: the solvers take their thread count from the cores the
//! process may use, [`crate::framework::parallel::threads`]) the run computes on one
//! thread, and its CPU time is its wall time on a quiet machine, and under load it is
//! the wall time the run would have taken alone. The grid's fronts and figures are
//! against CPU time; each run's wall time is kept beside it.

use crate::cpu_time::process_seconds;
use crate::framework::model::{IntegratorKind, SolverChoice};
use crate::framework::plot::{Corner, Figure, Panel, Series, Style};
use crate::framework::FemError;
use crate::pareto::Scheme;
use crate::train_bridge::{build, TrainBridgeCase};
use std::path::Path;
use std::time::Instant;

/// Spans of the short crossing.
pub const SPANS: usize = 3;
/// Speed (m/s), the paper's.
pub const SPEED: f64 = 80.0;
/// Fastener spacing of the track (m), `SlabTrack::default()`'s.
pub const SPACING: f64 = 0.625;
/// Elements per fastener bay of the grid's meshes (`h = SPACING / k`).
pub const MESH_K: [usize; 4] = [1, 2, 5, 9];
/// Time steps of the grid (s), longest first.
pub const STEPS: [f64; 5] = [4e-3, 2e-3, 1e-3, 5e-4, 2.5e-4];
/// The shortest step at which the grid runs the direct sparse solver on each mesh of
/// [`MESH_K`] (elements per bay, s). It costs 1.6–2.8, 2.1–4.6, 7.6–9.1 and 10–13 times
/// the partitioned solver's CPU time on 1, 2, 5 and 9 elements per bay (one thread), for
/// the same errors to three digits; the shorter steps on the fine meshes would cost about
/// twice the rest of the grid together (`docs/performance.md`).
pub const DIRECT_SHORTEST_DT: [(usize, f64); 4] = [(1, 2.5e-4), (2, 2.5e-4), (5, 1e-3), (9, 2e-3)];
/// Time step of the reference (s): half the grid's smallest.
pub const REF_DT: f64 = 1.25e-4;
/// Element length of the reference (m): nine per bay, 0.0694 m (the paper's "0.069"), the
/// grid's smallest.
pub const REF_H: f64 = SPACING / 9.0;
/// Elements per bay of the reference's coarser neighbour in the mesh check (0.125 m).
pub const CHECK_COARSE_K: usize = 5;
/// Elements per bay of the reference's finer neighbour in the mesh check (0.0347 m), run
/// with `--finer` only.
pub const CHECK_FINE_K: usize = 18;
/// Simulated time of every run (s): the whole crossing, from the carriage's centre 15 m
/// before the bridge until it is 23.75 m past its end (the rear axle, 10 m behind the
/// centre, leaves the bridge at 1.43 s).
pub const DURATION: f64 = 1.6;

/// Errors are measured from this time on (s). The run starts from the static equilibrium
/// with the carriage already at 80 m/s; the jump sets every wheel's 1e10 N/m penalty
/// spring ringing at ≈ 500 Hz, an artefact of the start, not of the crossing. Over the
/// first 0.01 s even the reference is off by 1–5e-3 of the static load (half its step
/// changes it by that), from 0.02 s by 7.7e-4; and counted from t = 0 the grid's largest
/// Q errors on the fine meshes all sat at t = 2–8 ms. The front wheelset reaches the
/// bridge at 0.0625 s.
pub const SETTLE: f64 = 0.02;

/// The settings of one run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Settings {
    /// Time step (s).
    pub dt: f64,
    /// Rail, slab and girder element length (m).
    pub h: f64,
    /// Integrator (the grid's three: Newmark, HHT α = −0.05, generalized-α ρ∞ = 0.8).
    pub scheme: Scheme,
    /// Linear solver.
    pub solver: SolverChoice,
}

/// The train–bridge case of `s` for `duration` s.
pub fn case(s: &Settings, duration: f64) -> TrainBridgeCase {
    let mut c = TrainBridgeCase {
        cars: 1,
        spans: SPANS,
        speed: SPEED,
        dt: s.dt,
        element_length: s.h,
        duration: Some(duration),
        midspans: (1..=SPANS).collect(),
        solver: s.solver,
        ..Default::default()
    };
    match s.scheme {
        Scheme::Newmark => c.integrator = IntegratorKind::Newmark,
        Scheme::Hht => {
            c.integrator = IntegratorKind::Hht;
            // train_bridge maps ρ∞ to Hilber's α = (1 − ρ∞)/(1 + ρ∞): 0.05 ⇔ ρ∞ = 0.95/1.05.
            c.rho_inf = 0.95 / 1.05;
        }
        Scheme::GenAlpha => {
            c.integrator = IntegratorKind::GeneralizedAlpha;
            c.rho_inf = 0.8;
        }
    }
    c
}

/// Histories of one run, sampled at every step from t = 0 (the initial equilibrium).
#[derive(Debug, Clone, PartialEq)]
pub struct History {
    /// Times (s).
    pub t: Vec<f64>,
    /// Wheel forces Q (N): `q[sample][wheel]`, wheels front to rear, left then right.
    pub q: Vec<Vec<f64>>,
    /// Each wheel's Q at the initial equilibrium (N).
    pub q_static: Vec<f64>,
    /// Midspan deflection of every span (m, down positive) minus its value at t = 0:
    /// `w[sample][span]`, spans in bridge order.
    pub w: Vec<Vec<f64>>,
    /// Wall time: build, static solve and every step (s).
    pub wall: f64,
    /// CPU time of the process over the same (s; NaN in a file written before it was
    /// recorded).
    pub cpu: f64,
    /// Computing threads the run could use ([`crate::framework::parallel::threads`]`(0)`;
    /// 0 when not recorded).
    pub threads: usize,
    /// Steps taken.
    pub steps: usize,
    /// Equations.
    pub dofs: usize,
}

/// Builds and runs `s` for `duration` s; see [`History`].
pub fn simulate(s: &Settings, duration: f64) -> Result<History, FemError> {
    let c = case(s, duration);
    let t0 = Instant::now();
    let c0 = process_seconds();
    let mut m = build(&c)?;
    let dofs = m.dofs;
    let steps = (m.duration / s.dt).round() as usize;
    let d = &mut m.driver;
    d.static_solve(0.0, 10)?;
    d.initialize()?;
    let names = d.model.elements[m.wheel_index[0]].element.output_names();
    let iq = names
        .iter()
        .position(|n| n == "Q")
        .ok_or_else(|| FemError::input("train-bridge case", "the wheel element has no Q"))?;
    let br = m
        .track
        .bridge
        .as_ref()
        .ok_or_else(|| FemError::input("train-bridge case", "no bridge in the model"))?;
    let spans: Vec<(u64, u64, u64)> = br
        .spans
        .iter()
        .map(|sp| (sp.first_node, sp.last_node, sp.midspan_node))
        .collect();
    let mut buf = Vec::new();
    let mut sample = |d: &crate::solvers::Driver| -> (Vec<f64>, Vec<f64>) {
        let q = m
            .wheel_index
            .iter()
            .map(|&ei| {
                buf.clear();
                d.model.elements[ei].element.outputs(&mut buf);
                buf[iq]
            })
            .collect();
        let w = |id: u64| {
            d.displacement(id, crate::framework::Dof::Uz)
                .unwrap_or(f64::NAN)
        };
        let mid = spans
            .iter()
            .map(|&(first, last, mid)| 0.5 * (w(first) + w(last)) - w(mid))
            .collect();
        (q, mid)
    };
    let (mut inner, mut inner_cpu) = (0.0, 0.0);
    let (q0, w0) = sample(d);
    let mut h = History {
        t: vec![0.0],
        q: vec![q0.clone()],
        q_static: q0,
        w: vec![vec![0.0; w0.len()]],
        wall: 0.0,
        cpu: 0.0,
        threads: crate::framework::parallel::threads(0),
        steps,
        dofs,
    };
    let mut bar = crate::progress::Progress::new("train-bridge run", steps as u64, "steps");
    for k in 1..=steps {
        d.step(s.dt)?;
        let s0 = Instant::now();
        let sc0 = process_seconds();
        let (q, w) = sample(d);
        h.t.push(d.state.t);
        h.q.push(q);
        h.w.push(w.iter().zip(&w0).map(|(a, b)| a - b).collect());
        bar.set(k as u64);
        inner += s0.elapsed().as_secs_f64();
        inner_cpu += process_seconds() - sc0;
    }
    bar.finish();
    h.wall = t0.elapsed().as_secs_f64() - inner;
    h.cpu = process_seconds() - c0 - inner_cpu;
    Ok(h)
}

/// Linear interpolation of samples `y` at times `t` (increasing) at time `x`, clamped to
/// the ends.
fn interp(t: &[f64], y: impl Fn(usize) -> f64, x: f64) -> f64 {
    let n = t.len();
    if x <= t[0] {
        return y(0);
    }
    if x >= t[n - 1] {
        return y(n - 1);
    }
    let i = t.partition_point(|v| *v <= x).clamp(1, n - 1);
    let f = (x - t[i - 1]) / (t[i] - t[i - 1]);
    y(i - 1) * (1.0 - f) + y(i) * f
}

/// Errors of `run` against `reference`: `[Q, ΔQ/Q, w]`, see the module doc.
pub fn errors(run: &History, reference: &History) -> [f64; 3] {
    errors_from(run, reference, 0.0)
}

/// [`errors`] over the samples at `t ≥ from` only (the peak of w still over all).
pub fn errors_from(run: &History, reference: &History, from: f64) -> [f64; 3] {
    let end = run.t[run.t.len() - 1].min(reference.t[reference.t.len() - 1]) + 1e-12;
    let nw = reference.q_static.len();
    let (mut eq, mut edqq, mut ew, mut wpk) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
    for (k, &t) in reference.t.iter().enumerate() {
        if t > end {
            break;
        }
        wpk = reference.w[k].iter().fold(wpk, |m, x| m.max(x.abs()));
        if t < from {
            continue;
        }
        for i in 0..nw {
            let q = interp(&run.t, |j| run.q[j][i], t);
            let qr = reference.q[k][i];
            let qs = reference.q_static[i];
            eq = eq.max((q - qr).abs() / qs);
            let dqq = (run.q_static[i] - q) / run.q_static[i];
            let dqq_ref = (qs - qr) / qs;
            edqq = edqq.max((dqq - dqq_ref).abs());
        }
        for (s, wr) in reference.w[k].iter().enumerate() {
            let w = interp(&run.t, |j| run.w[j][s], t);
            ew = ew.max((w - wr).abs());
        }
    }
    [eq, edqq, ew / wpk]
}

/// One run of the grid.
#[derive(Debug, Clone, PartialEq)]
pub struct TbRun {
    /// The settings.
    pub settings: Settings,
    /// Equations.
    pub dofs: usize,
    /// Steps.
    pub steps: usize,
    /// Wall time (s).
    pub wall: f64,
    /// CPU time (s): the cost the fronts are drawn against ([`History::cpu`]).
    pub cpu: f64,
    /// Computing threads of the run ([`History::threads`]).
    pub threads: usize,
    /// Errors `[Q, ΔQ/Q, w]`.
    pub errors: [f64; 3],
    /// On the Pareto front of each quantity.
    pub pareto: [bool; 3],
}

/// The quantities: short name, CSV column, title.
pub const QUANTITIES: [(&str, &str, &str); 3] = [
    ("Q", "err_Q [-] (of Q_static)", "wheel force Q"),
    ("dQQ", "err_dQQ [-]", "ΔQ/Q"),
    (
        "w",
        "err_w [-] (of max w over all spans)",
        "midspan deflection w",
    ),
];

/// The grid of `railfem pareto --cases train-bridge`: a list of runs.
#[derive(Debug, Clone, PartialEq)]
pub struct TbGrid {
    /// The runs.
    pub runs: Vec<Settings>,
    /// Compute nothing: evaluate only the runs whose files are already in the output
    /// directory (`--existing`: a look at a grid still running, or cut short).
    pub existing_only: bool,
    /// Also the reference's finer checks ([`finer_runs`], `--finer`).
    pub finer_checks: bool,
}

impl Default for TbGrid {
    /// Meshes `h = 0.625/k`, `k` = 1, 2, 5, 9 ([`MESH_K`]), integrators Newmark, HHT
    /// α = −0.05 and generalized-α ρ∞ = 0.8, time steps 4, 2, 1, 0.5 and 0.25 ms
    /// ([`STEPS`]): every combination with the partitioned solver, and with the direct
    /// sparse solver down to the step [`DIRECT_SHORTEST_DT`] gives for the mesh.
    fn default() -> Self {
        let mut runs = Vec::new();
        for k in MESH_K {
            let h = SPACING / k as f64;
            let direct_to = DIRECT_SHORTEST_DT
                .iter()
                .find(|d| d.0 == k)
                .map_or(f64::INFINITY, |d| d.1);
            for scheme in [Scheme::GenAlpha, Scheme::Newmark, Scheme::Hht] {
                for solver in [SolverChoice::Partitioned, SolverChoice::Direct] {
                    for dt in STEPS {
                        if solver == SolverChoice::Direct && dt < direct_to * (1.0 - 1e-9) {
                            continue;
                        }
                        runs.push(Settings {
                            dt,
                            h,
                            scheme,
                            solver,
                        });
                    }
                }
            }
        }
        TbGrid {
            runs,
            existing_only: false,
            finer_checks: false,
        }
    }
}

/// The reference's settings.
pub fn reference_settings() -> Settings {
    Settings {
        dt: REF_DT,
        h: REF_H,
        scheme: Scheme::GenAlpha,
        solver: SolverChoice::Partitioned,
    }
}

/// The reference and its two checks over the whole crossing ([`DURATION`]), with their
/// files: the reference; the next coarser mesh (`h = SPACING /` [`CHECK_COARSE_K`]) at its
/// step; its mesh at twice its step — the grid's generalized-α, partitioned 0.25 ms run on
/// that mesh, under the grid's file name, so the grid reads it back.
pub fn reference_runs() -> Vec<Job> {
    let r = reference_settings();
    let coarse = Settings {
        h: SPACING / CHECK_COARSE_K as f64,
        ..r
    };
    let double = Settings {
        dt: 2.0 * r.dt,
        ..r
    };
    vec![
        ("train-bridge-reference.csv".to_string(), r, DURATION),
        (
            format!("train-bridge-mesh-k{CHECK_COARSE_K}.csv"),
            coarse,
            DURATION,
        ),
        (grid_file(&double), double, DURATION),
    ]
}

/// The reference's finer neighbours over the whole crossing (`--finer`): the next finer
/// mesh (`h = SPACING /` [`CHECK_FINE_K`], twice the equations) at its step, and its mesh
/// at half its step. Their difference to the reference is, to leading order, the
/// reference's own error in h and in Δt, measured, not extrapolated from the coarser
/// neighbours: a quantity of order p in a parameter refined by r differs from the
/// unrefined one by `d = e·(1 − r^−p)`, so with r = 2 the reference's error is
/// `e = 1.33·d` for p = 2 and `2·d` for p = 1.
pub fn finer_runs() -> Vec<Job> {
    let r = reference_settings();
    let fine_mesh = SPACING / CHECK_FINE_K as f64;
    [
        (
            format!("train-bridge-mesh-k{CHECK_FINE_K}.csv"),
            fine_mesh,
            r.dt,
        ),
        ("train-bridge-half-step.csv".to_string(), r.h, 0.5 * r.dt),
    ]
    .into_iter()
    .map(|(file, h, dt)| (file, Settings { h, dt, ..r }, DURATION))
    .collect()
}

/// The reference runs a grid asks for: [`reference_runs`], then [`finer_runs`] with
/// `finer_checks`.
fn reference_jobs(grid: &TbGrid) -> Vec<Job> {
    let mut refs = reference_runs();
    if grid.finer_checks {
        refs.extend(finer_runs());
    }
    refs
}

/// Writes a history as CSV: a first line naming the run, a second with its size, wall
/// time, CPU time and threads, then `time [s], Q1..Q8 [N], w1..w3 [m]` (midspan deflection of each span), the
/// first row the static state.
pub fn write_history(
    path: &Path,
    s: &Settings,
    duration: f64,
    h: &History,
) -> Result<(), FemError> {
    let mut o = format!("{}\n", history_tag(s, duration));
    o.push_str(&format!(
        "# steps {} dofs {} wall {} cpu {} threads {}\n",
        h.steps, h.dofs, h.wall, h.cpu, h.threads
    ));
    o.push_str("time [s]");
    for i in 0..h.q_static.len() {
        o.push_str(&format!(",Q{} [N]", i + 1));
    }
    for s in 0..h.w[0].len() {
        o.push_str(&format!(",w{} [m]", s + 1));
    }
    o.push('\n');
    for k in 0..h.t.len() {
        o.push_str(&format!("{:e}", h.t[k]));
        for x in h.q[k].iter().chain(&h.w[k]) {
            o.push_str(&format!(",{x:e}"));
        }
        o.push('\n');
    }
    std::fs::write(path, o).map_err(|e| FemError::output(path, e))
}

fn history_tag(s: &Settings, duration: f64) -> String {
    format!(
        "# train-bridge history: dt {:e} h {} {} {} duration {} spans {SPANS} speed {SPEED} midspans all",
        s.dt,
        s.h,
        s.scheme.name(),
        s.solver.name(),
        duration
    )
}

/// Reads a history written by [`write_history`] for the same run; `None` if the file is
/// missing, unreadable or names another run.
pub fn read_history(path: &Path, s: &Settings, duration: f64) -> Option<History> {
    let text = std::fs::read_to_string(path).ok()?;
    let mut lines = text.lines();
    if lines.next()? != history_tag(s, duration) {
        return None;
    }
    let meta: Vec<&str> = lines.next()?.split_whitespace().collect();
    let mut h = History {
        t: Vec::new(),
        q: Vec::new(),
        q_static: Vec::new(),
        w: Vec::new(),
        wall: meta.get(6)?.parse().ok()?,
        // Files written before the CPU time was recorded end after the wall time.
        cpu: meta.get(8).map_or(Some(f64::NAN), |x| x.parse().ok())?,
        threads: meta.get(10).map_or(Some(0), |x| x.parse().ok())?,
        steps: meta.get(2)?.parse().ok()?,
        dofs: meta.get(4)?.parse().ok()?,
    };
    let header = lines.next()?;
    let nw = header.split(',').filter(|c| c.starts_with('w')).count();
    for l in lines {
        let v: Vec<f64> = l
            .split(',')
            .map(|x| x.parse().ok())
            .collect::<Option<_>>()?;
        let n = v.len();
        if n < nw + 2 || nw == 0 {
            return None;
        }
        h.t.push(v[0]);
        h.q.push(v[1..n - nw].to_vec());
        h.w.push(v[n - nw..].to_vec());
    }
    h.q_static = h.q.first()?.clone();
    Some(h)
}

/// Marks, per quantity, the runs that no other run beats in both CPU time and error (a
/// run without a CPU time is on no front).
pub fn mark_pareto(runs: &mut [TbRun]) {
    for q in 0..3 {
        let n = runs.len();
        for i in 0..n {
            let (ci, ei) = (runs[i].cpu, runs[i].errors[q]);
            let dominated = (0..n).any(|j| {
                j != i
                    && runs[j].cpu <= ci
                    && runs[j].errors[q] <= ei
                    && (runs[j].cpu < ci || runs[j].errors[q] < ei)
            });
            runs[i].pareto[q] = !dominated && ei.is_finite() && ci.is_finite();
        }
    }
}

/// One run to make: its file (relative to the output directory), settings and duration.
pub type Job = (String, Settings, f64);

/// The file of grid run `s` (relative to the output directory).
pub fn grid_file(s: &Settings) -> String {
    format!(
        "runs/tb-h{:.6}-dt{:e}-{}-{}.csv",
        s.h,
        s.dt,
        s.scheme.name(),
        s.solver.name()
    )
}

/// Takes `path` for this process: creates `path.lock` exclusively. `false` when another
/// process holds it (or the directory is not writable).
fn claim(path: &Path) -> bool {
    if let Some(dir) = path.parent() {
        let _ = std::fs::create_dir_all(dir);
    }
    std::fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(path.with_extension("lock"))
        .is_ok()
}

/// Simulates `job` into `path` (already claimed): the history, or the failure written
/// to `path.failed` so that a process waiting for it stops waiting (a later command
/// tries again).
fn make(path: &Path, job: &Job) -> Option<History> {
    let (_, s, duration) = job;
    let _ = std::fs::remove_file(path.with_extension("failed"));
    let r = simulate(s, *duration).and_then(|h| {
        if let Some(dir) = path.parent() {
            std::fs::create_dir_all(dir).map_err(|e| FemError::output(dir, e))?;
        }
        write_history(path, s, *duration, &h)?;
        Ok(h)
    });
    let out = match r {
        Ok(h) => {
            eprintln!(
                "pareto train-bridge: {} ({} eq, {} thread(s)): wall {:.2} s, cpu {:.2} s",
                history_tag(s, *duration),
                h.dofs,
                h.threads,
                h.wall,
                h.cpu
            );
            Some(h)
        }
        Err(e) => {
            eprintln!(
                "pareto train-bridge: {}: no result ({e})",
                history_tag(s, *duration)
            );
            // A stop request is no property of the run: leave no marker, so a later
            // command (or a waiting process) makes it again.
            if !matches!(e, FemError::InterruptedAfter { .. }) {
                let _ = std::fs::write(path.with_extension("failed"), e.to_string());
            }
            None
        }
    };
    let _ = std::fs::remove_file(path.with_extension("lock"));
    out
}

/// Makes every job whose file in `out` is missing, sharing the work with any other
/// process running the same jobs on the same directory: each job is claimed by a lock
/// file; jobs claimed elsewhere are polled every 10 s until their files appear (or a
/// lock disappears without a file: then this process makes the job).
/// A job's history is read back when its file already holds that run (delete the files
/// to recompute; delete a stale `.lock` left by a killed process). `None` for a run that
/// failed (Newton gave up), and for every job not made when a stop is asked for
/// (SIGINT/SIGTERM: the run in progress stops, no further job is claimed or waited for).
pub fn run_jobs(out: &Path, jobs: &[Job]) -> Vec<Option<History>> {
    let mut got: Vec<Option<Option<History>>> = vec![None; jobs.len()];
    let mut first = true;
    let stopped = crate::framework::interrupt::requested;
    while got.iter().any(Option::is_none) && !stopped() {
        if !first {
            std::thread::sleep(std::time::Duration::from_secs(10));
        }
        for (i, job) in jobs.iter().enumerate() {
            if got[i].is_some() {
                continue;
            }
            let path = out.join(&job.0);
            if let Some(h) = read_history(&path, &job.1, job.2) {
                got[i] = Some(Some(h));
            } else if !first && path.with_extension("failed").exists() {
                got[i] = Some(None);
            } else if !stopped() && claim(&path) {
                got[i] = Some(make(&path, job));
            }
        }
        first = false;
    }
    got.into_iter().map(Option::flatten).collect()
}

/// Runs the reference runs ([`reference_runs`], with `finer_checks` also [`finer_runs`])
/// and the grid (files `runs/*.csv` in
/// `out`) as one list of jobs ([`run_jobs`]), the most expensive first, so that two
/// processes on `out` share all of them; one line per run on stderr. Returns the
/// reference runs' histories (`None` for a failed one) and the grid's, in the grid's
/// order; a grid run that fails (Newton gives up at a coarse step) is reported and left
/// out.
pub fn run_all(grid: &TbGrid, out: &Path) -> (Vec<Option<History>>, Vec<(Settings, History)>) {
    let refs = reference_jobs(grid);
    let mut jobs: Vec<Job> = refs.clone();
    for s in &grid.runs {
        let job = (grid_file(s), *s, DURATION);
        if !jobs.iter().any(|j| j.0 == job.0) {
            jobs.push(job);
        }
    }
    // Cost ∝ steps × cost per step; with the condensed Newton a step on 0.0694 m (k = 9)
    // costs ≈ 1.7 times one on 0.625 m (k = 1), measured by the first study; the direct
    // solver's step ≈ 1 + 1.3·k times the partitioned one's (2.2, 3, 7.5 measured in CPU
    // time on k = 1, 2, 5), only an order to run in.
    // Cheapest first: a grid cut short (a deadline, a stop) still has every cheap point,
    // and `--existing` evaluates what is there.
    let cost = |s: &Settings| {
        let direct = match s.solver {
            SolverChoice::Direct => 1.3 * SPACING / s.h,
            _ => 0.0,
        };
        (1.0 + 0.1 * SPACING / s.h) * (1.0 + direct) / s.dt
    };
    jobs.sort_by(|a, b| cost(&a.1).total_cmp(&cost(&b.1)));
    let done = if grid.existing_only {
        jobs.iter()
            .map(|j| read_history(&out.join(&j.0), &j.1, j.2))
            .collect()
    } else {
        run_jobs(out, &jobs)
    };
    let find = |file: &str| {
        jobs.iter()
            .position(|j| j.0 == file)
            .and_then(|i| done[i].clone())
    };
    let ref_histories = refs.iter().map(|r| find(&r.0)).collect();
    let grid_histories = grid
        .runs
        .iter()
        .filter_map(|s| find(&grid_file(s)).map(|h| (*s, h)))
        .collect();
    (ref_histories, grid_histories)
}

/// The runs' errors against `reference`, with their Pareto fronts marked.
pub fn evaluate(histories: &[(Settings, History)], reference: &History) -> Vec<TbRun> {
    let mut runs: Vec<TbRun> = histories
        .iter()
        .map(|(s, h)| TbRun {
            settings: *s,
            dofs: h.dofs,
            steps: h.steps,
            wall: h.wall,
            cpu: h.cpu,
            threads: h.threads,
            errors: errors_from(h, reference, SETTLE),
            pareto: [false; 3],
        })
        .collect();
    mark_pareto(&mut runs);
    runs
}

/// The runs as CSV (units in the header).
pub fn csv(runs: &[TbRun]) -> String {
    let mut s = String::from(
        "case,integrator,solver,element_length [m],equations,dt [s],steps,wall [s],cpu [s] (process CPU time),threads",
    );
    for q in QUANTITIES {
        s.push_str(&format!(",{}", q.1));
    }
    s.push_str(",pareto_Q,pareto_dQQ,pareto_w\n");
    for r in runs {
        s.push_str(&format!(
            "train-bridge,{},{},{:.6},{},{:.6e},{},{:.6e},{:.6e},{},{:.6e},{:.6e},{:.6e},{},{},{}\n",
            r.settings.scheme.name(),
            r.settings.solver.name(),
            r.settings.h,
            r.dofs,
            r.settings.dt,
            r.steps,
            r.wall,
            r.cpu,
            r.threads,
            r.errors[0],
            r.errors[1],
            r.errors[2],
            r.pareto[0],
            r.pareto[1],
            r.pareto[2]
        ));
    }
    s
}

/// The Pareto front of each quantity as markdown tables.
pub fn markdown(runs: &[TbRun]) -> String {
    let mut s = String::new();
    for (q, (_, _, title)) in QUANTITIES.iter().enumerate() {
        s.push_str(&format!(
            "\nPareto front, {title} (against CPU time):\n\n| integrator | solver | h (m) | equations | dt (s) | CPU (s) | wall (s) | err Q | err ΔQ/Q | err w |\n|---|---|---:|---:|---:|---:|---:|---:|---:|---:|\n"
        ));
        let mut front: Vec<&TbRun> = runs.iter().filter(|r| r.pareto[q]).collect();
        front.sort_by(|a, b| a.cpu.total_cmp(&b.cpu));
        for r in front {
            s.push_str(&format!(
                "| {} | {} | {:.4} | {} | {:.2e} | {:.2} | {:.2} | {:.3e} | {:.3e} | {:.3e} |\n",
                r.settings.scheme.name(),
                r.settings.solver.name(),
                r.settings.h,
                r.dofs,
                r.settings.dt,
                r.cpu,
                r.wall,
                r.errors[0],
                r.errors[1],
                r.errors[2]
            ));
        }
    }
    s
}

/// The figure of quantity `q` (0 = Q, 1 = ΔQ/Q, 2 = w): error against CPU time, log–log
/// (runs without one left out),
/// every run in both of two stacked panels, the Pareto front as a line in each: on top
/// one colour per mesh, below one colour per integrator with circles for the partitioned
/// and squares for the direct solver (24 blocks are too many for one legend).
pub fn figure(runs: &[TbRun], q: usize) -> Figure {
    let colors = ["#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd"];
    let (_, _, title) = QUANTITIES[q];
    let ylabel = match q {
        0 => "max |Q − Q_ref| / Q_static (-)",
        1 => "max |ΔQ/Q − ref| (-)",
        _ => "max |w − w_ref| / max |w_ref| (-)",
    };
    let runs: Vec<&TbRun> = runs.iter().filter(|r| r.cpu.is_finite()).collect();
    let mut front: Vec<&TbRun> = runs.iter().copied().filter(|r| r.pareto[q]).collect();
    front.sort_by(|a, b| a.cpu.total_cmp(&b.cpu));
    let front = Series::new(
        "Pareto front",
        front.iter().map(|r| r.cpu).collect(),
        front.iter().map(|r| r.errors[q]).collect(),
        Style::Line,
        "black",
    );
    let panel = |by: &str, groups: Vec<(String, Style, &str, Vec<&TbRun>)>| {
        let mut p = Panel::new(
            &format!("train–bridge, 1 car × 3 spans: {title} error by {by}"),
            "CPU time of the run, one thread (s)",
            ylabel,
        )
        .log_log();
        p.legend = Corner::TopRight;
        for (label, style, color, pts) in groups {
            p = p.with(Series::new(
                &label,
                pts.iter().map(|r| r.cpu).collect(),
                pts.iter().map(|r| r.errors[q]).collect(),
                style,
                color,
            ));
        }
        p.with(front.clone())
    };
    let mut meshes: Vec<f64> = Vec::new();
    let mut schemes: Vec<Scheme> = Vec::new();
    for r in &runs {
        if !meshes.contains(&r.settings.h) {
            meshes.push(r.settings.h);
        }
        if !schemes.contains(&r.settings.scheme) {
            schemes.push(r.settings.scheme);
        }
    }
    let by_mesh = meshes
        .iter()
        .enumerate()
        .map(|(k, &h)| {
            let pts = runs.iter().copied().filter(|r| r.settings.h == h).collect();
            (
                format!("h = {h:.4} m"),
                Style::Markers,
                colors[k % colors.len()],
                pts,
            )
        })
        .collect();
    let mut by_scheme = Vec::new();
    for (k, &scheme) in schemes.iter().enumerate() {
        for (solver, style) in [
            (SolverChoice::Partitioned, Style::Markers),
            (SolverChoice::Direct, Style::Squares),
        ] {
            let pts: Vec<&TbRun> = runs
                .iter()
                .copied()
                .filter(|r| r.settings.scheme == scheme && r.settings.solver == solver)
                .collect();
            if !pts.is_empty() {
                by_scheme.push((
                    format!("{}, {}", scheme.name(), solver.name()),
                    style,
                    colors[k % colors.len()],
                    pts,
                ));
            }
        }
    }
    Figure::new()
        .with(panel("mesh", by_mesh))
        .with(panel("integrator and solver", by_scheme))
}

/// Runs the reference runs ([`reference_runs`], [`finer_runs`] with `--finer`; files
/// `train-bridge-*.csv` in `out`) and
/// the grid (`runs/*.csv`), reading those already there and sharing the rest with any other
/// process running the same command on `out` ([`run_all`]); then writes
/// `pareto-train-bridge.csv`, `pareto-train-bridge.md` and
/// `pareto-train-bridge-{Q,dQQ,w}.svg` into `out`.
pub fn run(grid: &TbGrid, out: &Path) -> Result<Vec<TbRun>, FemError> {
    std::fs::create_dir_all(out).map_err(|e| FemError::output(out, e))?;
    let refs = reference_jobs(grid);
    let (ref_histories, histories) = run_all(grid, out);
    let ref_histories: Vec<History> = ref_histories
        .into_iter()
        .zip(&refs)
        .map(|(h, r)| {
            h.ok_or_else(|| {
                FemError::input(
                    "pareto train-bridge",
                    format!(
                        "the reference run {} failed or (with --existing) is not in {} yet",
                        r.0,
                        out.display()
                    ),
                )
            })
        })
        .collect::<Result<_, _>>()?;
    let reference = &ref_histories[0];
    let runs = evaluate(&histories, reference);
    let p = out.join("pareto-train-bridge.csv");
    std::fs::write(&p, csv(&runs)).map_err(|e| FemError::output(&p, e))?;
    let base = refs[0].1;
    let mut md = format!(
        "Reference: h = {:.4} m (0.625/9), dt = {} s, generalized-α ρ∞ = 0.8, partitioned \
         solver ({} equations, {} steps over {} s, {:.0} s wall). Errors are measured from \
         t = {SETTLE} s on (after the start from rest).\n",
        base.h, base.dt, reference.dofs, reference.steps, DURATION, reference.wall,
    );
    md.push_str(&convergence_markdown(&refs, &ref_histories));
    md.push_str(&markdown(&runs));
    let p = out.join("pareto-train-bridge.md");
    std::fs::write(&p, &md).map_err(|e| FemError::output(&p, e))?;
    for (q, (name, _, _)) in QUANTITIES.iter().enumerate() {
        let p = out.join(format!("pareto-train-bridge-{name}.svg"));
        figure(&runs, q)
            .write_svg_and_png(&p)
            .map_err(|e| FemError::output(&p, e))?;
    }
    print!("{md}");
    Ok(runs)
}

/// The reference's checks over the whole crossing: each neighbour of
/// [`reference_runs`] and [`finer_runs`] (after the reference itself) against the reference, with its size
/// and wall time.
fn convergence_markdown(refs: &[Job], histories: &[History]) -> String {
    let mut s = format!(
        "\nThe reference against its neighbours over the whole {DURATION} s (coarser: its \
         error estimate with an order; finer, with --finer: its error measured):\n\n\
         | run | h (m) | dt (s) | equations | wall (s) | err Q | err ΔQ/Q | err w |\n\
         |---|---:|---:|---:|---:|---:|---:|---:|\n"
    );
    for (i, (job, h)) in refs.iter().zip(histories).enumerate() {
        let e = (i > 0).then(|| errors_from(h, &histories[0], SETTLE));
        let cell = |q: usize| e.map_or("—".to_string(), |e| format!("{:.3e}", e[q]));
        s.push_str(&format!(
            "| {} | {:.4} | {:e} | {} | {:.0} | {} | {} | {} |\n",
            job.0,
            job.1.h,
            job.1.dt,
            h.dofs,
            h.wall,
            cell(0),
            cell(1),
            cell(2)
        ));
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::PathBuf;

    fn history(dt: f64, n: usize, f: impl Fn(f64) -> (f64, f64)) -> History {
        let t: Vec<f64> = (0..=n).map(|k| k as f64 * dt).collect();
        History {
            q: t.iter().map(|&x| vec![f(x).0; 2]).collect(),
            q_static: vec![f(0.0).0; 2],
            w: t.iter().map(|&x| vec![f(x).1, 0.5 * f(x).1]).collect(),
            t,
            wall: 0.0,
            cpu: 1.5,
            threads: 1,
            steps: n,
            dofs: 0,
        }
    }

    /// Linear histories are interpolated exactly, so a coarse run of the same straight
    /// lines has zero error; a constant offset of w by 1e-5 m on a peak of 1e-3 m is an
    /// error of 1e-2; Q raised by 1 % of its static value is 1e-2 in Q.
    #[test]
    fn errors_of_linear_histories() {
        let line = |t: f64| (1e5 + 2e4 * t, 1e-3 * t);
        let fine = history(1e-3, 1000, line);
        let coarse = history(4e-3, 250, line);
        let e = errors(&coarse, &fine);
        assert!(e.iter().all(|x| *x < 1e-12), "{e:?}");
        let shifted = history(4e-3, 250, |t| (line(t).0 + 1e3, line(t).1 + 1e-5));
        let e = errors(&shifted, &fine);
        assert!((e[0] - 1e-2).abs() < 1e-12, "{e:?}");
        assert!((e[2] - 1e-2).abs() < 1e-9, "{e:?}");
    }

    /// The w error is the largest over the spans, on one scale (the largest peak of any
    /// span): span 2 (peak 5e-4 m) offset by 2e-5 m against span 1's peak of 1e-3 m is
    /// 2e-2, not span 2's own 4e-2; span 1 offset by 1e-5 m alone gives 1e-2.
    #[test]
    fn w_error_is_the_largest_over_spans() {
        let line = |t: f64| (1e5, 1e-3 * t);
        let fine = history(1e-3, 1000, line);
        let mut run = history(4e-3, 250, line);
        for w in &mut run.w {
            w[1] += 2e-5;
        }
        let e = errors(&run, &fine);
        assert!((e[2] - 2e-2).abs() < 1e-9, "{e:?}");
        let mut run = history(4e-3, 250, line);
        for w in &mut run.w {
            w[0] += 1e-5;
        }
        let e = errors(&run, &fine);
        assert!((e[2] - 1e-2).abs() < 1e-9, "{e:?}");
    }

    /// The finer checks are the reference refined once in h and once in Δt, each by 2
    /// and nothing else, so that each difference is the reference's own error in one
    /// parameter.
    #[test]
    fn finer_checks_halve_one_parameter_each() {
        let r = reference_settings();
        let f = finer_runs();
        assert_eq!(f.len(), 2);
        assert!((f[0].1.h - r.h / 2.0).abs() < 1e-15 && f[0].1.dt == r.dt);
        assert!(f[1].1.h == r.h && (f[1].1.dt - r.dt / 2.0).abs() < 1e-18);
        for (file, s, d) in &f {
            assert_eq!((s.scheme, s.solver, *d), (r.scheme, r.solver, DURATION));
            assert!(!reference_runs().iter().any(|j| &j.0 == file), "{file}");
        }
        let grid = TbGrid {
            finer_checks: true,
            ..TbGrid::default()
        };
        assert_eq!(reference_jobs(&grid).len(), 5);
        assert_eq!(reference_jobs(&TbGrid::default()).len(), 3);
    }

    /// `h` written as a run of 1 ms on 0.625 m with `solver`, for 0.01 s, into a fresh
    /// directory named by `tag`: the directory, the file and the settings.
    fn written(tag: &str, h: &History, solver: SolverChoice) -> (PathBuf, PathBuf, Settings) {
        let s = Settings {
            dt: 1e-3,
            h: SPACING,
            scheme: Scheme::GenAlpha,
            solver,
        };
        let dir = std::env::temp_dir().join(format!("railfem-tb-{tag}-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join("h.csv");
        write_history(&p, &s, 0.01, h).unwrap();
        (dir, p, s)
    }

    /// A history written and read back is the same run, to the digits written (`{:e}`
    /// prints the shortest exact representation), with one w column per span.
    #[test]
    fn history_round_trip() {
        let h = history(1e-3, 10, |t: f64| (1e5 + 3.3 * t, 1e-3 * t.sin()));
        let (dir, p, s) = written("new", &h, SolverChoice::Direct);
        let back = read_history(&p, &s, 0.01).expect("read back");
        assert_eq!(back, h);
        assert!(
            read_history(&p, &s, 0.02).is_none(),
            "another duration is another run"
        );
        let _ = std::fs::remove_dir_all(&dir);
    }

    /// A file written before the CPU time was recorded (the reference's, kept across the
    /// change) reads back as the same run with its wall time and no CPU time, so it is
    /// reused, not recomputed, and stays off the CPU-time fronts; a CPU time that does
    /// not parse makes the file no run.
    #[test]
    fn history_without_cpu_time_reads_back() {
        let h = history(1e-3, 10, |t: f64| (1e5 + 3.3 * t, 1e-3 * t));
        let (dir, p, s) = written("old", &h, SolverChoice::Partitioned);
        let text = std::fs::read_to_string(&p).unwrap();
        let old = text.replacen(" cpu 1.5 threads 1\n", "\n", 1);
        assert_ne!(old, text);
        std::fs::write(&p, &old).unwrap();
        let back = read_history(&p, &s, 0.01).expect("read back");
        assert!(back.cpu.is_nan() && back.threads == 0, "{back:?}");
        assert_eq!(
            (back.wall, back.steps, &back.q, &back.w),
            (h.wall, h.steps, &h.q, &h.w)
        );
        std::fs::write(&p, text.replacen("cpu 1.5", "cpu x", 1)).unwrap();
        assert!(read_history(&p, &s, 0.01).is_none());
        let _ = std::fs::remove_dir_all(&dir);
    }

    /// Every CSV row has as many fields as the header (no comma inside a column name),
    /// and the CPU time sits under its own column, beside the wall time.
    #[test]
    fn csv_rows_match_the_header() {
        let r = TbRun {
            settings: Settings {
                dt: 1e-3,
                h: SPACING,
                scheme: Scheme::Hht,
                solver: SolverChoice::Direct,
            },
            dofs: 5412,
            steps: 1600,
            wall: 30.0,
            cpu: 7.25,
            threads: 1,
            errors: [3e-2, 3e-2, 1e-3],
            pareto: [true, false, true],
        };
        let text = csv(&[r]);
        let lines: Vec<Vec<&str>> = text.lines().map(|l| l.split(',').collect()).collect();
        assert_eq!(lines.len(), 2);
        assert_eq!(lines[0].len(), lines[1].len(), "{text}");
        let col = |name: &str| lines[0].iter().position(|c| c.starts_with(name)).unwrap();
        assert_eq!(lines[1][col("cpu [s]")].parse::<f64>().unwrap(), 7.25);
        assert_eq!(lines[1][col("wall [s]")].parse::<f64>().unwrap(), 30.0);
        assert_eq!(lines[1][col("threads")], "1");
    }

    /// The fronts are against CPU time: a run cheaper in CPU but longer in wall time
    /// (it met more load) dominates; a run without a CPU time is on no front.
    #[test]
    fn fronts_are_against_cpu_time() {
        let run = |cpu: f64, wall: f64, e: f64| TbRun {
            settings: Settings {
                dt: 1e-3,
                h: SPACING,
                scheme: Scheme::GenAlpha,
                solver: SolverChoice::Partitioned,
            },
            dofs: 0,
            steps: 0,
            wall,
            cpu,
            threads: 1,
            errors: [e; 3],
            pareto: [false; 3],
        };
        let mut runs = [
            run(10.0, 50.0, 1e-2),
            run(20.0, 20.0, 2e-2),
            run(f64::NAN, 1.0, 1e-3),
        ];
        mark_pareto(&mut runs);
        assert_eq!(
            runs.iter().map(|r| r.pareto[0]).collect::<Vec<_>>(),
            [true, false, false]
        );
    }
}

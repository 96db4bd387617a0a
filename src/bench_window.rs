//! `railfem bench --case window`: how the train–bridge step's cost grows with the bridge
//! and with the train, with the activity window ([`crate::train_window`]) on and off.
//!
//! For each number of spans and of carriages the case is built twice and stepped with the
//! window off and then on, back to back in the same process, so that both runs see the
//! same machine: the ratio of their times is a same-run ratio. Each run solves the static
//! preload, takes one untimed step (the transient's block factorizations, once per Δt) and
//! then times `steps` steps: wall time per step, CPU time per step (all threads), and the
//! load average before and after, printed and written to `window.csv` and `window.md`.
//! The window runs once per reach asked for (`--window-ahead`, the default reach without
//! it), each after the same case's run without the window.

use crate::framework::model::SolverChoice;
use crate::framework::FemError;
use crate::train_bridge::{build, TrainBridgeCase};
use crate::train_window::{open, train_extent, LayerOptions, WindowChoice, WindowOptions};
use std::fmt::Write as _;
use std::path::Path;
use std::time::Instant;

/// One timed run.
#[derive(Debug, Clone, PartialEq)]
pub struct WindowRow {
    /// Spans and carriages.
    pub spans: usize,
    /// Carriages.
    pub cars: usize,
    /// Equations.
    pub dofs: usize,
    /// Whether the window was on.
    pub window: bool,
    /// The window's reach (m; 0 without the window).
    pub reach: f64,
    /// Wall and CPU seconds per timed step.
    pub wall_per_step: f64,
    /// CPU seconds per timed step (all threads).
    pub cpu_per_step: f64,
    /// Newton iterations per timed step.
    pub iterations_per_step: f64,
    /// Fraction of block-steps held (0 without the window).
    pub held: f64,
    /// Load average (1 min) before the run.
    pub load: String,
}

fn time_one(case: &TrainBridgeCase, steps: usize) -> Result<WindowRow, FemError> {
    let mut m = build(case)?;
    let d = &mut m.driver;
    d.static_solve(0.0, 10)?;
    d.initialize()?;
    let track = case.window_track();
    let mut window = open(d, case.window, &track)?;
    if let Some(w) = window.as_mut() {
        let reach = w.settings().ahead;
        w.set_absorbing_layer(crate::train_window::layer(reach, case.window_layer));
    }
    let mut step = |d: &mut crate::solvers::Driver| -> Result<usize, FemError> {
        if let Some(w) = window.as_mut() {
            let [rear, front] = train_extent(&track, d.state.t);
            w.update(d, rear, front)?;
            d.set_promotion_form(crate::train_window::promotion_form(w));
        }
        Ok(d.step(case.dt)?.iterations)
    };
    step(d)?;
    let load = std::fs::read_to_string("/proc/loadavg").map_or(String::new(), |l| {
        l.split_whitespace().take(3).collect::<Vec<_>>().join(" ")
    });
    let (t0, c0) = (Instant::now(), crate::cpu_time::process_seconds());
    let (tm0, p0) = (d.summary.timings, d.partition_stats().unwrap_or_default());
    let mut iterations = 0;
    for _ in 0..steps {
        iterations += step(d)?;
    }
    let wall = t0.elapsed().as_secs_f64();
    let cpu = crate::cpu_time::process_seconds() - c0;
    let (tm1, p1) = (d.summary.timings, d.partition_stats().unwrap_or_default());
    let ms = |x: f64| 1e3 * x / steps as f64;
    let per = |a: usize, b: usize| (b - a) as f64 / steps as f64;
    eprintln!(
        "  per step: assembly {:.1} ms, loads {:.1} ms, factor {:.1} ms (top form {:.1}, top factor {:.1}, blocks {:.1}, promotions {:.1}), solve {:.1} ms; top factorizations {:.2}, top symbolic analyses {:.2}, top constant forms {:.2} (pattern repeats {:.2}), refits {:.2}, block factorizations {:.2}, promotions {:.2} (columns solved {:.1}, kept {:.1}; forward paths mean {:.0}, longest {} rows, blocks of {:.0}); top equations {}, reduced {}",
        ms(tm1.assembly - tm0.assembly),
        ms(tm1.loads - tm0.loads),
        ms(tm1.factor - tm0.factor),
        ms(p1.time_top_form - p0.time_top_form),
        ms(p1.time_top_factor - p0.time_top_factor),
        ms(p1.time_blocks - p0.time_blocks),
        ms(p1.time_promote - p0.time_promote),
        ms(tm1.solve - tm0.solve),
        per(p0.top_factorizations, p1.top_factorizations),
        per(p0.top_symbolic_analyses, p1.top_symbolic_analyses),
        per(p0.top_constant_forms, p1.top_constant_forms),
        per(p0.top_pattern_repeats, p1.top_pattern_repeats),
        per(p0.top_refits, p1.top_refits),
        per(p0.block_factorizations, p1.block_factorizations),
        per(p0.promotions, p1.promotions),
        per(p0.promotion_columns_solved, p1.promotion_columns_solved),
        per(p0.promotion_columns_kept, p1.promotion_columns_kept),
        (p1.promotion_reach_rows - p0.promotion_reach_rows) as f64
            / (p1.promotion_columns_solved - p0.promotion_columns_solved).max(1) as f64,
        p1.promotion_reach_max,
        p1.interior_equations as f64 / p1.blocks.max(1) as f64,
        p1.top_equations,
        p1.top_reduced_equations,
    );
    let held = window.as_ref().map_or(0.0, |w| {
        let s = w.stats();
        s.held_block_steps as f64 / s.block_steps.max(1) as f64
    });
    Ok(WindowRow {
        spans: case.spans,
        cars: case.cars,
        dofs: m.dofs,
        window: window.is_some(),
        reach: window.as_ref().map_or(0.0, |w| w.settings().ahead),
        wall_per_step: wall / steps as f64,
        cpu_per_step: cpu / steps as f64,
        iterations_per_step: iterations as f64 / steps as f64,
        held,
        load,
    })
}

/// Times every `(spans, cars)` of the lists, window off then on, with `steps` timed steps
/// of `dt` on rails of element length `h`, the front carriage's centre starting at
/// `train_start` from the first abutment; the window on with each reach of `reaches` (m;
/// `None`: the default) and the absorbing `layer`; writes `window.csv` and `window.md` into
/// `out`.
pub fn run(
    spans: &[usize],
    cars: &[usize],
    steps: usize,
    [dt, h, train_start]: [f64; 3],
    (reaches, layer): (&[Option<f64>], LayerOptions),
    out: &Path,
) -> Result<Vec<WindowRow>, FemError> {
    std::fs::create_dir_all(out).map_err(|e| FemError::output(out, e))?;
    let mut rows = Vec::new();
    for &ns in spans {
        for &nc in cars {
            let on = reaches.iter().map(|&ahead| {
                WindowChoice::On(WindowOptions {
                    ahead,
                    ..Default::default()
                })
            });
            for window in std::iter::once(WindowChoice::Off).chain(on) {
                let case = TrainBridgeCase {
                    spans: ns,
                    cars: nc,
                    dt,
                    element_length: h,
                    train_start,
                    solver: SolverChoice::Partitioned,
                    window,
                    window_layer: layer,
                    ..Default::default()
                };
                let r = time_one(&case, steps)?;
                println!(
                    "{} spans, {} cars, {} DOF, window {}: {:.1} ms/step wall, {:.1} ms/step CPU, {:.2} iterations/step, {:.1} % of block-steps held; load {}",
                    r.spans,
                    r.cars,
                    r.dofs,
                    on_label(&r),
                    1e3 * r.wall_per_step,
                    1e3 * r.cpu_per_step,
                    r.iterations_per_step,
                    100.0 * r.held,
                    r.load
                );
                rows.push(r);
            }
        }
    }
    let mut csv = String::from(
        "spans [-],cars [-],dofs [-],window [-],reach [m],wall_per_step [s],cpu_per_step [s],iterations_per_step [-],held [-]\n",
    );
    let mut md = String::from(
        "| spans | cars | DOF | window | wall ms/step | CPU ms/step | iterations/step | held | on/off (CPU) | load before |\n|---|---|---|---|---|---|---|---|---|---|\n",
    );
    for (k, r) in rows.iter().enumerate() {
        let _ = writeln!(
            csv,
            "{},{},{},{},{},{:.6e},{:.6e},{:.4},{:.4}",
            r.spans,
            r.cars,
            r.dofs,
            u8::from(r.window),
            r.reach,
            r.wall_per_step,
            r.cpu_per_step,
            r.iterations_per_step,
            r.held
        );
        // Against the same case's run without the window (the last one before it).
        let off = rows[..k]
            .iter()
            .rev()
            .find(|o| !o.window && o.spans == r.spans && o.cars == r.cars);
        let ratio = match (r.window, off) {
            (true, Some(off)) => format!("{:.2}", r.cpu_per_step / off.cpu_per_step),
            _ => String::new(),
        };
        let _ = writeln!(
            md,
            "| {} | {} | {} | {} | {:.1} | {:.1} | {:.2} | {:.0} % | {ratio} | {} |",
            r.spans,
            r.cars,
            r.dofs,
            on_label(r),
            1e3 * r.wall_per_step,
            1e3 * r.cpu_per_step,
            r.iterations_per_step,
            100.0 * r.held,
            r.load
        );
    }
    for (name, text) in [("window.csv", csv), ("window.md", md)] {
        let p = out.join(name);
        std::fs::write(&p, text).map_err(|e| FemError::output(&p, e))?;
    }
    Ok(rows)
}

/// `off`, or `on (R m)` with the window's reach.
fn on_label(r: &WindowRow) -> String {
    if r.window {
        format!("on ({} m)", r.reach)
    } else {
        "off".to_string()
    }
}

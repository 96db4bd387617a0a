//! `railfem bench --case train-bridge`: where a Newton iteration's time goes on the
//! train–bridge model ([`crate::train_bridge`]), at growing sizes, and the paper's full case.
//!
//! Each size builds the viaduct with `dof_target` equations, lets the train settle (the
//! static preload, the initial accelerations and the first step, which factors every block
//! for the transient tangent — timed apart as *setup*), then times `steps`
//! steps at the paper's Δt = 0.5 ms. Per Newton iteration and per step the report splits the
//! wall time into the phases the issue names:
//!
//! - *search*: carriers moved and elements advanced — each wheel finds the rail nodes under
//!   it (`Assembler::advance`);
//! - *elements*: state determination of the variable elements (contact detection, forces,
//!   tangents), in parallel;
//! - *assembly*: products with the constant matrices (`K·q`, `M·a`, `C·v`), the residual and
//!   the variable elements' triplets;
//! - *blocks*: the partitioned solver's block work — promotions of the rail nodes a wheel
//!   moved onto (solves with the block's factor; blocks are refactored only for a new Δt) —
//!   and *top*: forming and factoring the condensed top system;
//! - *solve*: the block and top triangular solves;
//! - *loads*: external forces (gravity, Eq. 5 pseudo-loads, ground motion).
//!
//! Nothing here is asserted: times depend on the machine and on what else it is doing.

use crate::framework::FemError;
use crate::solvers::exchange::Exchange;
use crate::train_bridge::{build, TrainBridgeCase};
use std::io::Write;
use std::path::Path;
use std::sync::Arc;
use std::time::Instant;

/// One measured size.
#[derive(Debug, Clone, PartialEq)]
pub struct PhaseRow {
    /// Equations.
    pub dofs: usize,
    /// Elements and carriages.
    pub elements: usize,
    /// Carriages.
    pub cars: usize,
    /// Spans.
    pub spans: usize,
    /// Element length the DOF target gave (m).
    pub element_length: f64,
    /// Model build (s).
    pub build: f64,
    /// Static preload and initial acceleration (s).
    pub setup: f64,
    /// Steps timed and Newton iterations in them.
    pub steps: usize,
    /// Newton iterations in the timed steps.
    pub iterations: usize,
    /// Median over steps of (step time / its iterations) (s).
    pub median_iteration: f64,
    /// Median step time (s).
    pub median_step: f64,
    /// Seconds per iteration: search, elements, assembly, blocks, top, solve, loads, other.
    pub phases: [f64; 8],
    /// Promotions formed per step (a wheel entered new rail nodes of a block).
    pub blocks_per_step: f64,
    /// Block factorizations during the timed steps (zero while Δt is constant).
    pub refactorizations: usize,
    /// Blocks, top equations at the end.
    pub blocks: usize,
    /// Top-system equations at the last factorization.
    pub top: usize,
    /// Peak resident memory of the process after this size (MiB).
    pub peak_mib: f64,
    /// Every timed step, in order (`steps-<dofs>.csv`).
    pub timeline: Vec<StepTime>,
}

/// One timed step: what a user planning a long run needs to see where the time goes as
/// the train moves (entering the viaduct costs more iterations than running on it).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepTime {
    /// Time at the end of the step (s).
    pub t: f64,
    /// Newton iterations over its sub-steps.
    pub iterations: usize,
    /// Halvings of the step.
    pub cuts: usize,
    /// Block factorizations during the step.
    pub block_factorizations: usize,
    /// Wall time of the step (s).
    pub wall: f64,
}

/// Names of [`PhaseRow::phases`].
pub const PHASES: [&str; 8] = [
    "search", "elements", "assembly", "blocks", "top", "solve", "loads", "other",
];

fn median(v: &mut [f64]) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(|a, b| a.total_cmp(b));
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

/// Builds and times one case; with `ranks`, the partitioned solver shares its blocks
/// among them ([`crate::ranks`]) and each rank prints its share, memory and messages.
pub fn measure(
    case: &TrainBridgeCase,
    steps: usize,
    ranks: Option<Arc<dyn Exchange>>,
) -> Result<PhaseRow, FemError> {
    let t0 = Instant::now();
    // Across ranks each rank splits the blocks on the pattern and forms K, M, C on its own
    // columns only; it forms the residual of its own rows.
    let mut m = match &ranks {
        None => build(case)?,
        Some(ex) => crate::train_bridge::build_across_ranks(case, ex.clone(), None)?,
    };
    let t_build = t0.elapsed().as_secs_f64();
    let d = &mut m.driver;
    if let Some(ex) = ranks {
        // The refusal of a model on another solver (shared at the build otherwise).
        d.set_exchange(ex)?;
        d.keep_own_rows();
    }
    let t1 = Instant::now();
    d.static_solve(0.0, 10)?;
    d.initialize()?;
    // The first step factors every block for the transient's constant part (once per Δt);
    // it belongs to the set-up, not to the steady per-step cost.
    d.step(case.dt)?;
    let setup = t1.elapsed().as_secs_f64();
    let setup_memory = [
        crate::bench::resident_memory_mib().unwrap_or(f64::NAN),
        crate::bench::peak_memory_mib().unwrap_or(f64::NAN),
    ];
    let (s0, a0, p0) = (
        d.summary,
        d.asm.times,
        d.partition_stats().unwrap_or_default(),
    );
    let mut per_iter = Vec::with_capacity(steps);
    let mut per_step = Vec::with_capacity(steps);
    let mut timeline = Vec::with_capacity(steps);
    let t2 = Instant::now();
    for _ in 0..steps {
        // Every rank stops at the same step (a stop seen by one rank alone would leave the
        // others waiting in the next collective).
        if d.stop_requested() {
            return Err(FemError::Interrupted { t: d.state.t });
        }
        let ts = Instant::now();
        let f0 = d.partition_stats().unwrap_or_default().block_factorizations;
        let r = d.step(case.dt)?;
        let w = ts.elapsed().as_secs_f64();
        timeline.push(StepTime {
            t: d.state.t,
            iterations: r.iterations,
            cuts: r.cuts,
            block_factorizations: d.partition_stats().unwrap_or_default().block_factorizations - f0,
            wall: w,
        });
        per_step.push(w);
        per_iter.push(w / r.iterations.max(1) as f64);
        // A long segment reports as it goes (a segment of thousands of steps takes hours).
        let k = timeline.len();
        if k % 500 == 0 && k < steps && crate::ranks::writes_outputs() {
            let its: usize = timeline.iter().map(|s| s.iterations).sum();
            println!(
                "          step {k}: t = {:.4} s, {:.1} s wall so far, {:.2} iterations/step",
                d.state.t,
                t2.elapsed().as_secs_f64(),
                its as f64 / k as f64
            );
        }
    }
    let wall = t2.elapsed().as_secs_f64();
    let (s1, a1, p1) = (
        d.summary,
        d.asm.times,
        d.partition_stats().unwrap_or_default(),
    );
    let c = d.condensed_stats();
    let iters = (s1.iterations - s0.iterations).max(1);
    if p1.ranks > 1 {
        let per_it = |x: u64, y: u64| (x - y) as f64 / iters as f64;
        println!(
            "          rank {} of {}: {} of {} blocks ({} interior equations), {} of {} elements held, peak {:.0} MiB, per iteration {:.0} B sent, {:.0} B received, {:.0} collectives, {:.1} ms in them",
            crate::sidecar::launcher_rank().unwrap_or(0),
            p1.ranks,
            p1.owned_blocks,
            p1.blocks,
            p1.owned_interior_equations,
            d.elements_held(),
            d.model.elements.len(),
            crate::bench::peak_memory_mib().unwrap_or(f64::NAN),
            per_it(p1.comm.bytes_sent, p0.comm.bytes_sent),
            per_it(p1.comm.bytes_received, p0.comm.bytes_received),
            per_it(p1.comm.collectives, p0.comm.collectives),
            1e3 * (p1.comm.time - p0.comm.time) / iters as f64,
        );
    }
    print_memory(&m, setup_memory);
    if crate::ranks::writes_outputs() {
        let (stored, [k, mm, cc]) = m.driver.asm.constant_nonzeros();
        println!(
            "          constant matrices: {stored} stored entries (one pattern), non-zero values K {k}, M {mm}, C {cc}"
        );
    }
    if crate::ranks::writes_outputs() {
        println!(
            "          condensed Newton (whole run): {} steps, {} top-system iterations, {} full evaluations ({} predictors from the last verification's pass), {} rejected verifications, {} steps handed back",
            c.steps, c.top_iterations, c.full_evaluations, c.predictors_reused, c.rejected, c.fallbacks
        );
        let its = iters as f64;
        println!(
            "          top system (timed steps): {} equations, {} factored ({} of {} chain groups condensed, {} condensations), {} stored entries, factor {} entries; per iteration {:.2} ms forming, {:.2} ms factoring; {:.2} constant parts formed, {:.2} variable layouts refitted and {:.2} symbolic analyses per step",
            p1.top_equations,
            p1.top_reduced_equations,
            p1.top_groups_condensed,
            p1.top_groups,
            p1.top_group_condensations - p0.top_group_condensations,
            p1.top_nnz,
            p1.top_factor_nnz,
            1e3 * (p1.time_top_form - p0.time_top_form) / its,
            1e3 * (p1.time_top_factor - p0.time_top_factor) / its,
            (p1.top_constant_forms - p0.top_constant_forms) as f64 / steps.max(1) as f64,
            (p1.top_refits - p0.top_refits) as f64 / steps.max(1) as f64,
            (p1.top_symbolic_analyses - p0.top_symbolic_analyses) as f64 / steps.max(1) as f64,
        );
        println!(
            "          block factors: {} values of L stored by the factorization, {} off-diagonal non-zeros kept for the solves ({:.1} %)",
            p1.factor_values,
            p1.factor_nonzeros,
            100.0 * p1.factor_nonzeros as f64 / p1.factor_values.max(1) as f64
        );
    }
    let per = |x: f64| x / iters as f64;
    let search = a1.search - a0.search;
    let elements = a1.elements - a0.elements;
    let assembly = (s1.timings.assembly - s0.timings.assembly) - elements;
    let blocks = (p1.time_blocks - p0.time_blocks) + (p1.time_promote - p0.time_promote);
    let top = p1.time_top - p0.time_top;
    // The direct solver's factorization (no partition) is reported as "top".
    let factor = s1.timings.factor - s0.timings.factor;
    let top = if p1.blocks == 0 && p1.top_factorizations == 0 {
        factor
    } else {
        top.max(factor - blocks)
    };
    let solve = s1.timings.solve - s0.timings.solve;
    let loads = (s1.timings.loads - s0.timings.loads) - search;
    let other = wall - (search + elements + assembly + blocks + top + solve + loads);
    Ok(PhaseRow {
        dofs: m.dofs,
        elements: m.elements,
        cars: case.cars,
        spans: case.spans,
        element_length: m.element_length,
        build: t_build,
        setup,
        steps,
        iterations: iters,
        median_iteration: median(&mut per_iter),
        median_step: median(&mut per_step),
        phases: [search, elements, assembly, blocks, top, solve, loads, other].map(per),
        blocks_per_step: (p1.promotions - p0.promotions) as f64 / steps as f64,
        refactorizations: p1.block_factorizations - p0.block_factorizations,
        blocks: p1.blocks,
        top: p1.top_equations,
        peak_mib: crate::bench::peak_memory_mib().unwrap_or(f64::NAN),
        timeline,
    })
}

/// One line per rank: where its memory goes. Resident memory after each build phase and
/// the peaks after the build, after the set-up (static preload, initial accelerations,
/// first step) and after the timed steps (with the resident memory after the set-up and
/// after the steps), then the bytes of each part the driver holds
/// ([`crate::solvers::driver::Driver::memory`]); what the parts do not cover is mostly the
/// elements (in the model) and the top system's factor.
fn print_memory(m: &crate::train_bridge::TrainBridgeModel, setup: [f64; 2]) {
    let [gen, model, driver, build_peak] = m.build_memory_mib;
    let [setup_rss, setup_peak] = setup;
    let mib = |b: usize| b as f64 / (1024.0 * 1024.0);
    let parts = m.driver.memory();
    let counted: usize = parts.iter().map(|p| p.1).sum();
    let list: Vec<String> = parts
        .iter()
        .map(|(name, b)| format!("{name} {:.0}", mib(*b)))
        .collect();
    println!(
        "          memory of rank {} (MiB): resident after generation {gen:.0}, model {model:.0}, driver {driver:.0}, set-up {setup_rss:.0}, steps {:.0}; peak after build {build_peak:.0}, set-up {setup_peak:.0}, steps {:.0}; held by the driver {:.0}: {}",
        crate::sidecar::launcher_rank().unwrap_or(0),
        crate::bench::resident_memory_mib().unwrap_or(f64::NAN),
        crate::bench::peak_memory_mib().unwrap_or(f64::NAN),
        mib(counted),
        list.join(", ")
    );
}

/// Least-squares slope of `ln y` against `ln x`.
pub fn growth_exponent(points: &[(f64, f64)]) -> f64 {
    let n = points.len() as f64;
    let (sx, sy) = points
        .iter()
        .fold((0.0, 0.0), |(a, b), (x, y)| (a + x.ln(), b + y.ln()));
    let (mx, my) = (sx / n, sy / n);
    let (num, den) = points.iter().fold((0.0, 0.0), |(a, b), (x, y)| {
        let dx = x.ln() - mx;
        (a + dx * (y.ln() - my), b + dx * dx)
    });
    num / den
}

/// The case of one size: `cars` carriages, and as many 29.75 m spans as the paper's
/// 1 043 430-DOF mesh density (113 spans) gives for `dofs` equations.
pub fn case_for(
    dofs: usize,
    cars: usize,
    dt: f64,
    train_start: f64,
    geometry: crate::framework::model::Geometry,
) -> TrainBridgeCase {
    let per_span = 1_043_430.0 / 113.0;
    let spans = ((dofs as f64 / per_span).round() as usize).max(1);
    TrainBridgeCase {
        cars,
        spans,
        dof_target: Some(dofs),
        dt,
        // The same solver at every size (auto would use the direct one below 50 000
        // equations), so that the growth exponent compares like with like.
        solver: crate::framework::model::SolverChoice::Partitioned,
        // The whole model every step: this bench times the solver on the full viaduct
        // (the activity window's cost is `railfem bench --case window`).
        window: crate::train_window::WindowChoice::Off,
        geometry,
        train_start,
        ..Default::default()
    }
}

/// Runs the sizes and writes `phases.csv`, `phases.md` and, per size, every timed step in
/// `steps-<dofs>.csv` into `out`.
pub fn run(
    sizes: &[usize],
    cars: usize,
    steps: usize,
    dt: f64,
    train_start: f64,
    geometry: crate::framework::model::Geometry,
    out: &Path,
) -> Result<Vec<PhaseRow>, FemError> {
    let ranks = crate::ranks::launcher_exchange("bench --case train-bridge")?;
    // Under a launcher only rank 0 prints the table and writes the files.
    let root = crate::ranks::writes_outputs();
    if root {
        std::fs::create_dir_all(out).map_err(|e| FemError::output(out, e))?;
    } else {
        crate::progress::set_quiet(true);
    }
    let mut rows = Vec::new();
    macro_rules! say {
        ($($t:tt)*) => {
            if root {
                println!($($t)*);
            }
        };
    }
    say!(
        "train-bridge benchmark: {cars} carriage(s), Δt = {dt} s, {steps} steps per size, {} threads, vehicle geometry {}, front carriage starting {train_start} m from the bridge",
        crate::framework::parallel::threads(0),
        geometry.name()
    );
    let mut bar = crate::progress::Progress::new("bench train-bridge", sizes.len() as u64, "sizes");
    // A stop request between sizes, or inside one (dropped: part of its steps is no
    // measurement), writes the sizes done and returns InterruptedAfter.
    let mut stopped = false;
    for (k, &n) in sizes.iter().enumerate() {
        if crate::solvers::exchange::any_rank(
            ranks.as_deref(),
            crate::framework::interrupt::requested(),
        ) {
            stopped = true;
            break;
        }
        bar.set(k as u64);
        let case = case_for(n, cars, dt, train_start, geometry);
        let r = match measure(&case, steps, ranks.clone()) {
            Err(FemError::Interrupted { .. }) => {
                stopped = true;
                break;
            }
            r => r?,
        };
        say!(
            "{:>9} DOF ({} spans, h = {:.3} m): build {:.1} s, setup {:.1} s, {:.2} iterations/step, median {:.1} ms/iteration, {:.1} ms/step, {:.1} promotions/step, {} block refactorizations, peak {:.0} MiB",
            r.dofs,
            r.spans,
            r.element_length,
            r.build,
            r.setup,
            r.iterations as f64 / r.steps as f64,
            1e3 * r.median_iteration,
            1e3 * r.median_step,
            r.blocks_per_step,
            r.refactorizations,
            r.peak_mib
        );
        let parts: Vec<String> = PHASES
            .iter()
            .zip(r.phases)
            .map(|(k, v)| format!("{k} {:.1}", 1e3 * v))
            .collect();
        say!("          per iteration (ms): {}", parts.join(", "));
        rows.push(r);
        bar.set(rows.len() as u64);
    }
    if rows.len() >= 2 {
        let pts: Vec<(f64, f64)> = rows
            .iter()
            .map(|r| (r.dofs as f64, r.median_iteration))
            .collect();
        say!(
            "time per iteration grows as DOF^{:.2} (least squares over {} sizes)",
            growth_exponent(&pts),
            rows.len()
        );
    }
    if root {
        write(&rows, out)?;
    }
    if stopped {
        return Err(FemError::InterruptedAfter {
            after: format!("{} of {} sizes", rows.len(), sizes.len()),
        });
    }
    Ok(rows)
}

fn write(rows: &[PhaseRow], out: &Path) -> Result<(), FemError> {
    let p = out.join("phases.csv");
    let mut f = std::fs::File::create(&p).map_err(|e| FemError::output(&p, e))?;
    let mut head = String::from(
        "dofs [-],elements [-],cars [-],spans [-],element_length [m],build [s],setup [s],steps [-],iterations [-],median_iteration [s],median_step [s]",
    );
    for k in PHASES {
        head.push_str(&format!(",{k}_per_iteration [s]"));
    }
    head.push_str(",promotions_per_step [-],block_refactorizations [-],blocks [-],top_equations [-],peak [MiB]");
    let mut text = head + "\n";
    for r in rows {
        text.push_str(&format!(
            "{},{},{},{},{:.5},{:.3},{:.3},{},{},{:.6},{:.6}",
            r.dofs,
            r.elements,
            r.cars,
            r.spans,
            r.element_length,
            r.build,
            r.setup,
            r.steps,
            r.iterations,
            r.median_iteration,
            r.median_step
        ));
        for v in r.phases {
            text.push_str(&format!(",{v:.6}"));
        }
        text.push_str(&format!(
            ",{:.2},{},{},{},{:.0}\n",
            r.blocks_per_step, r.refactorizations, r.blocks, r.top, r.peak_mib
        ));
    }
    f.write_all(text.as_bytes())
        .map_err(|e| FemError::output(&p, e))?;
    let p = out.join("phases.md");
    let mut md =
        String::from("| DOF | iterations/step | ms/iteration (median) | ms/step (median) |");
    for k in PHASES {
        md.push_str(&format!(" {k} |"));
    }
    md.push_str(" promotions/step | top equations | peak MiB |\n|");
    for _ in 0..(7 + PHASES.len()) {
        md.push_str("---:|");
    }
    md.push('\n');
    for r in rows {
        md.push_str(&format!(
            "| {} | {:.2} | {:.1} | {:.1} |",
            r.dofs,
            r.iterations as f64 / r.steps as f64,
            1e3 * r.median_iteration,
            1e3 * r.median_step
        ));
        for v in r.phases {
            md.push_str(&format!(" {:.1} |", 1e3 * v));
        }
        md.push_str(&format!(
            " {:.1} | {} | {:.0} |\n",
            r.blocks_per_step, r.top, r.peak_mib
        ));
    }
    std::fs::write(&p, md).map_err(|e| FemError::output(&p, e))?;
    for r in rows {
        let p = out.join(format!("steps-{}.csv", r.dofs));
        let mut text =
            String::from("t [s],iterations [-],halvings [-],block_factorizations [-],wall [s]\n");
        for s in &r.timeline {
            text.push_str(&format!(
                "{:.6},{},{},{},{:.6}\n",
                s.t, s.iterations, s.cuts, s.block_factorizations, s.wall
            ));
        }
        std::fs::write(&p, text).map_err(|e| FemError::output(&p, e))?;
    }
    if rows.len() >= 2 {
        plot(rows, &out.join("phases.svg"))?;
    }
    Ok(())
}

/// `phases.svg`: the time per iteration (total and by phase) against the DOF count on
/// log–log axes, with the slope-1 line through the smallest size for reference.
fn plot(rows: &[PhaseRow], path: &Path) -> Result<(), FemError> {
    use crate::framework::plot::{Figure, Panel, Series, Style};
    let x: Vec<f64> = rows.iter().map(|r| r.dofs as f64).collect();
    let ms = |v: f64| (1e3 * v).max(1e-3);
    let mut p = Panel::new(
        "train–bridge: time per Newton iteration",
        "equations (-)",
        "time per iteration (ms)",
    )
    .log_log()
    .with(Series::new(
        "median total",
        x.clone(),
        rows.iter().map(|r| ms(r.median_iteration)).collect(),
        Style::Line,
        "#000000",
    ));
    let colors = [
        "#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b",
    ];
    let shown: [(usize, &str); 6] = [
        (2, "assembly"),
        (4, "top"),
        (5, "solve"),
        (7, "other"),
        (1, "elements"),
        (3, "blocks"),
    ];
    for ((k, name), color) in shown.into_iter().zip(colors) {
        p = p.with(Series::new(
            name,
            x.clone(),
            rows.iter().map(|r| ms(r.phases[k])).collect(),
            Style::Markers,
            color,
        ));
    }
    let y0 = ms(rows[0].median_iteration);
    p = p.with(Series::new(
        "∝ DOF (slope 1)",
        x.clone(),
        x.iter().map(|xi| y0 * xi / x[0]).collect(),
        Style::Dashed,
        "#7f7f7f",
    ));
    Figure::new()
        .with(p)
        .write_svg_and_png(path)
        .map_err(|e| FemError::output(path, e))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn growth_exponent_of_a_power_law() {
        let pts: Vec<(f64, f64)> = [1e4, 1e5, 1e6]
            .iter()
            .map(|&x: &f64| (x, 3.0 * x.powf(1.1)))
            .collect();
        assert!((growth_exponent(&pts) - 1.1).abs() < 1e-12);
    }

    #[test]
    fn median_odd_and_even() {
        assert_eq!(median(&mut [3.0, 1.0, 2.0]), 2.0);
        assert_eq!(median(&mut [4.0, 1.0, 2.0, 3.0]), 2.5);
    }
}

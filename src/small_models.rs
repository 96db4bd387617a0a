//! `railfem bench --case sprung`: what a moving linear element costs per step with each
//! linear solver — a sprung mass crossing the benchmark beam of [`crate::bench`].
//!
//! The beam is [`crate::bench::BenchBeam`] (25 m spans of ten `beam3d` elements on pins,
//! six DOF per node) under gravity; a `moving_sprung_mass` (m = 5750 kg on k = 1.595e6 N/m,
//! the `railfem pareto` vehicle) starts over the first support and crosses at 80 m/s, so it
//! moves onto new beam nodes every 2.5 m (every 16 steps of 2 ms). The same model runs with
//! `solver = "direct"` (the tangent refactored every step; every element crossing rebuilds
//! the pattern), `"low_rank"` (the beam factored once, the rider by a Woodbury solve) and,
//! from [`crate::solvers::thresholds::PARTITIONED_FROM`] equations, `"partitioned"`. Per
//! solver the report gives the time per step (after the initial static solve and first
//! step), the factorizations, and the largest difference of the displacement histories
//! from the direct solver's, relative to the largest displacement.

use crate::bench::{BenchBeam, DT};
use crate::framework::builder::ModelBuilder;
use crate::framework::model::{AnalysisSpec, IntegratorKind, SolverChoice};
use crate::framework::{DofSet, FemError, Model};
use crate::solvers::Driver;
use serde_json::json;
use std::path::Path;
use std::time::Instant;

/// Speed of the sprung mass (m/s).
pub const SPEED: f64 = 80.0;

/// The benchmark beam closest to `dof` equations with a sprung mass riding along it from
/// x = 0, under gravity (initial static solve), Newmark average acceleration at
/// [`crate::bench::DT`], running with `solver`.
pub fn sprung_beam(dof: usize, steps: usize, solver: SolverChoice) -> Result<Model, FemError> {
    let geo = BenchBeam::for_dof(dof);
    let mut b = ModelBuilder::new(format!("sprung mass on a beam ({} spans)", geo.spans));
    geo.add_beam(&mut b);
    let mass_node = geo.nodes() as u64 + 1;
    b.node_fixed(mass_node, [0.0, 0.0, 1.0], DofSet::NONE);
    let path: Vec<u64> = (1..=geo.elements() as u64).collect();
    b.element(
        "moving_sprung_mass",
        geo.elements() as u64 + 1,
        &[mass_node],
        &json!({"m": 5750.0, "k": 1.595e6, "path": path, "start": 0.0, "speed": SPEED}),
    );
    b.analysis(AnalysisSpec {
        integrator: IntegratorKind::Newmark,
        beta: 0.25,
        gamma: 0.5,
        dt: DT,
        duration: DT * steps.max(1) as f64,
        gravity: Some([0.0, 0.0, -9.81]),
        initial_static: true,
        solver,
        ..Default::default()
    });
    b.build()
}

/// One solver on one size.
#[derive(Debug, Clone, PartialEq)]
pub struct SprungRow {
    /// Requested DOF count.
    pub target: usize,
    /// Equations.
    pub equations: usize,
    /// The solver.
    pub solver: SolverChoice,
    /// Steps timed.
    pub steps: usize,
    /// Wall time per step over the timed steps (s).
    pub per_step: f64,
    /// Numeric factorizations of a sparse matrix of the model's size over the whole run
    /// (initial static solve included; the initial mass solve excluded).
    pub factorizations: usize,
    /// Sparsity patterns the assembler built (1 + one per element crossing in the direct
    /// mode).
    pub patterns: usize,
    /// Largest displacement difference from the direct solver's history, relative to the
    /// largest displacement (0 for the direct row).
    pub difference: f64,
}

/// Runs `steps` steps with `solver`; the displacement after each step and the row.
pub fn run_one(
    target: usize,
    steps: usize,
    solver: SolverChoice,
) -> Result<(SprungRow, Vec<Vec<f64>>), FemError> {
    let mut d = Driver::new(sprung_beam(target, steps + 1, solver)?)?;
    d.initialize()?;
    d.step(DT)?; // the first step carries the first transient factorization
    let mut history = vec![d.state.q.clone()];
    let t0 = Instant::now();
    for _ in 0..steps {
        d.step(DT)?;
        history.push(d.state.q.clone());
    }
    let per_step = t0.elapsed().as_secs_f64() / steps.max(1) as f64;
    let factorizations = match (d.lowrank_stats(), d.partition_stats()) {
        (Some(l), _) => l.base_factorizations,
        (None, Some(p)) => p.block_factorizations,
        (None, None) => d.solver_stats().numeric_factorizations,
    };
    Ok((
        SprungRow {
            target,
            equations: d.neq(),
            solver: d.asm.solver(),
            steps,
            per_step,
            factorizations,
            patterns: d.asm.stats.patterns,
            difference: 0.0,
        },
        history,
    ))
}

/// Largest `|a − b|` over two histories relative to the largest `|a|`.
pub fn history_difference(a: &[Vec<f64>], b: &[Vec<f64>]) -> f64 {
    let scale = a
        .iter()
        .flatten()
        .fold(0.0f64, |m, x| m.max(x.abs()))
        .max(f64::MIN_POSITIVE);
    let worst = a
        .iter()
        .zip(b)
        .flat_map(|(x, y)| x.iter().zip(y).map(|(u, v)| (u - v).abs()))
        .fold(0.0f64, f64::max);
    worst / scale
}

/// Every size with every applicable solver.
pub fn run(sizes: &[usize], steps: usize, out: &Path) -> Result<Vec<SprungRow>, FemError> {
    let mut rows = Vec::new();
    for &n in sizes {
        let (direct, reference) = run_one(n, steps, SolverChoice::Direct)?;
        eprintln!("{}", row_line(&direct));
        rows.push(direct);
        let mut others = vec![SolverChoice::LowRank];
        if n >= crate::solvers::thresholds::PARTITIONED_FROM {
            others.push(SolverChoice::Partitioned);
        }
        for s in others {
            let (mut row, h) = run_one(n, steps, s)?;
            row.difference = history_difference(&reference, &h);
            eprintln!("{}", row_line(&row));
            rows.push(row);
        }
    }
    let table = markdown(&rows);
    print!("{table}");
    std::fs::create_dir_all(out).map_err(|e| FemError::output(out, e))?;
    let p = out.join("sprung.md");
    std::fs::write(&p, &table).map_err(|e| FemError::output(&p, e))?;
    Ok(rows)
}

fn row_line(r: &SprungRow) -> String {
    format!(
        "sprung: {} equations, {:?}: {:.3} ms/step",
        r.equations,
        r.solver,
        r.per_step * 1e3
    )
}

/// The rows as a markdown table.
pub fn markdown(rows: &[SprungRow]) -> String {
    let mut s = String::from(
        "| target DOF | equations | solver | steps | step (ms) | speed-up vs direct | sparse factorizations | patterns | max difference vs direct |\n|---:|---:|---|---:|---:|---:|---:|---:|---:|\n",
    );
    let mut direct = f64::NAN;
    for r in rows {
        if r.solver == SolverChoice::Direct {
            direct = r.per_step;
        }
        s.push_str(&format!(
            "| {} | {} | {:?} | {} | {:.3} | {:.1} | {} | {} | {:.1e} |\n",
            r.target,
            r.equations,
            r.solver,
            r.steps,
            r.per_step * 1e3,
            direct / r.per_step,
            r.factorizations,
            r.patterns,
            r.difference
        ));
    }
    s
}

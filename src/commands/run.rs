//! `railfem run`: run a model file; its recorders write into `--out`.

use crate::command::{Command, Context};
use crate::framework::FemError;
use crate::solvers::exchange::Exchange;
use clap::Args;
use serde::Serialize;
use std::path::Path;
use std::path::PathBuf;
use std::sync::Arc;

/// `railfem run`.
#[derive(Args, Debug, Clone, PartialEq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub struct RunCmd {
    /// The model file (TOML or JSON).
    #[arg(value_name = "MODEL")]
    #[serde(serialize_with = "crate::command::path_text")]
    pub model: PathBuf,
    /// Output directory of the recorders and run.json [default: out].
    #[arg(long, value_name = "DIR")]
    #[serde(serialize_with = "crate::command::opt_path_text")]
    pub out: Option<PathBuf>,
    /// Assess the run's wheel forces afterwards with the defaults of `railfem assess`.
    #[arg(long)]
    pub assess: bool,
}

/// The one validation `check` and `run` share: read and build the model, number the
/// equations, assemble the pattern and the constant matrices, and run the preflight checks
/// (singularity, stability, size). Warnings go to stderr here, so both print them.
pub(super) fn prepare(
    path: &Path,
    estimate_factor: bool,
) -> Result<(crate::solvers::Driver, crate::solvers::preflight::Preflight), FemError> {
    prepare_on(path, estimate_factor, None)
}

/// [`prepare`] on one rank of `ranks` (`crate::prepare_on`).
fn prepare_on(
    path: &Path,
    estimate_factor: bool,
    ranks: Option<Arc<dyn Exchange>>,
) -> Result<(crate::solvers::Driver, crate::solvers::preflight::Preflight), FemError> {
    let file = path.display().to_string();
    let (driver, pre) = crate::prepare_on(crate::load_model(path), &file, estimate_factor, ranks)?;
    for w in &pre.warnings {
        eprintln!("warning: {w}");
    }
    Ok((driver, pre))
}

/// A model file's partitioned solver shared among the ranks of `mpirun -n P` (P > 1): each
/// rank factors and condenses its own blocks ([`crate::ranks`]) and forms the residual of
/// its own rows (`Driver::keep_own_rows`). A model on another solver is
/// refused with the fix.
fn share_among_ranks(
    driver: &mut crate::solvers::Driver,
    ex: Arc<dyn Exchange>,
    path: &Path,
) -> Result<(), FemError> {
    let size = ex.size();
    if driver.partition_stats().is_none() {
        return Err(FemError::input(
            path.display().to_string(),
            format!("[analysis]: under `mpirun -n {size}` the ranks share the partitioned solver's blocks, but `solver = \"{}\"` does not run it for this model's {} equations; set `solver = \"partitioned\"` (and `block_size`, interior equations per block, so that there are at least {size} blocks)", driver.model.analysis.solver.name(), driver.state.q.len()),
        ));
    }
    driver.set_exchange(ex)?;
    // Each rank forms the residual of its own rows, with its columns of K, M, C and its
    // elements; the energy balance is summed over the ranks' rows.
    driver.keep_own_rows();
    Ok(())
}

impl Command for RunCmd {
    const NAME: &'static str = "run";
    const STOPS_AT_STEP: bool = true;
    fn out_dir(&self) -> Option<PathBuf> {
        crate::command::out_or(&self.out, "out")
    }
    fn run(&self, ctx: &Context) -> Result<i32, FemError> {
        let path = self.model.as_path();
        let out = ctx.out();
        let ranks = crate::ranks::launcher_exchange("run")?;
        // Across ranks, K, M, C formed on each rank's columns only.
        let (mut driver, _) = prepare_on(path, false, ranks.clone())?;
        let shared = ranks.is_some();
        if let Some(ex) = ranks {
            share_among_ranks(&mut driver, ex, path)?;
        }
        // The activity window (`[analysis.window]`): decided alike on every rank.
        let file = path.display().to_string();
        let spec = driver.model.analysis.window;
        let mut window = crate::run_window::plan(&driver, &spec, &file)?;
        if shared && !crate::ranks::writes_outputs() {
            // Rank 0 alone prints and writes the recorders; the others compute.
            crate::progress::set_quiet(true);
            driver
                .run(None, &mut |_| {})
                .map_err(|e| e.in_file(&file))?;
            return Ok(0);
        }
        let an = &driver.model.analysis;
        let steps = match an.kind {
            crate::framework::model::AnalysisKind::Transient => {
                (an.duration / an.dt - 1e-9).ceil().max(1.0) as u64
            }
            _ => 1,
        };
        let mut bar = crate::progress::Progress::new("run", steps, "steps");
        let s = driver
            .run_preparing(
                Some(out),
                false,
                &mut |f| bar.fraction(f),
                &mut |_, _| {},
                &mut |d| window.before_step(d),
            )
            .map(|(s, _)| s)
            .map_err(|e| e.in_file(&file))?;
        bar.finish();
        println!(
            "{}: {} steps, {} Newton iterations, {} factorizations, {} equations, {:.3} s; results in {}",
            path.display(),
            s.steps,
            s.iterations,
            s.factorizations,
            s.equations,
            s.wall,
            out.display()
        );
        if let crate::run_window::Plan::On(w) = &window {
            if let Some(st) = w.stats() {
                println!("{}", crate::run_window::stats_line(&st));
            }
        }
        if let Some(why) = window.auto_off() {
            println!("activity window (auto): off here: {why}")
        }
        if let Some(e) = driver.energy.as_ref().filter(|e| e.started()) {
            println!("{}", e.summary());
        }
        if let Some(p) = driver.partition_stats().filter(|p| p.ranks > 1) {
            println!(
                "partitioned solver across {} ranks: rank 0 owns {} of {} blocks; it sent {} B and received {} B in {} collectives",
                p.ranks, p.owned_blocks, p.blocks, p.comm.bytes_sent, p.comm.bytes_received, p.comm.collectives
            );
        }
        if self.assess {
            crate::assess::after_run(out, None)?;
        }
        Ok(0)
    }
}

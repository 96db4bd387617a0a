//! `railfem bridge-check`: the EN 1991-2 dynamic check of a railway bridge ([`crate::bridge_check`]).

use crate::bridge_check::{RunOptions, DEFAULT_OUT};
use crate::command::{Command, Context};
use crate::framework::FemError;
use clap::Args;
use serde::Serialize;
use std::path::PathBuf;

/// `railfem bridge-check`.
#[derive(Args, Debug, Clone, PartialEq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub struct BridgeCheckCmd {
    /// The check's plan (TOML, docs/bridge-check.md).
    #[arg(value_name = "PLAN.toml")]
    #[serde(serialize_with = "crate::command::path_text")]
    pub plan: PathBuf,
    /// Computing threads [default: the available cores].
    #[arg(value_parser = crate::command::number(), long, value_name = "N")]
    pub threads: Option<f64>,
    /// Compute at most N train-speed runs, then stop; the journal keeps them and a rerun
    /// goes on [default: all].
    #[arg(value_parser = crate::command::number(), long, value_name = "N")]
    pub stop_after: Option<f64>,
    /// Start afresh: discard the journal (bridge-check.checkpoint) instead of resuming.
    #[arg(long)]
    pub restart: bool,
    /// Output directory: envelope.csv, acceleration.svg/.png, dynamic-factor.svg/.png,
    /// report.md, run.json, bridge-check.checkpoint [default: out/bridge_check].
    #[arg(long, value_name = "DIR")]
    #[serde(serialize_with = "crate::command::opt_path_text")]
    pub out: Option<PathBuf>,
}

impl Command for BridgeCheckCmd {
    const NAME: &'static str = "bridge-check";
    const STOPS_AT_STEP: bool = true;
    fn out_dir(&self) -> Option<PathBuf> {
        crate::command::out_or(&self.out, DEFAULT_OUT)
    }
    fn run(&self, ctx: &Context) -> Result<i32, FemError> {
        let cl = "command line";
        let threads = match self.threads {
            Some(t) if t >= 1.0 && t.fract() == 0.0 && t <= 1024.0 => t as usize,
            Some(t) => {
                return Err(FemError::input(
                    cl,
                    format!("--threads {t}: give a whole number of threads ≥ 1"),
                ))
            }
            None => std::thread::available_parallelism().map_or(1, |n| n.get()),
        };
        let stop_after = crate::command::whole(
            "stop-after",
            self.stop_after,
            1e9,
            "give a whole number of runs ≥ 1",
        )?;
        let opts = RunOptions {
            threads,
            stop_after,
            restart: self.restart,
        };
        crate::bridge_check::command(&self.plan, ctx.out(), opts)
    }
}

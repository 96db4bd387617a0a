//! `railfem study`: a parameter study over a plan's axes ([`crate::study`]), on threads or MPI ranks.

use crate::command::{Command, Context};
use crate::framework::FemError;
use crate::study::{Options, DEFAULT_OUT};
use clap::Args;
use serde::Serialize;
use std::path::PathBuf;

/// `railfem study`.
#[derive(Args, Debug, Clone, PartialEq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub struct StudyCmd {
    /// The study plan (TOML, docs/study.md).
    #[arg(value_name = "PLAN.toml")]
    #[serde(serialize_with = "crate::command::path_text")]
    pub plan: PathBuf,
    /// Computing threads of this process (under mpirun: of rank 0; the other ranks compute
    /// one case at a time) [default: the available cores].
    #[arg(value_parser = crate::command::number(), long, value_name = "N")]
    pub threads: Option<f64>,
    /// Hand out at most N cases in this run, then stop; the checkpoint keeps them and a
    /// rerun goes on [default: all].
    #[arg(value_parser = crate::command::number(), long, value_name = "N")]
    pub stop_after: Option<f64>,
    /// Start afresh: discard the checkpoint's rows instead of resuming from them (the way
    /// out when a resume refuses a damaged or foreign row).
    #[arg(long)]
    pub restart: bool,
    /// Output directory: study.csv, study.json, study.svg/.png, study.checkpoint, cases/
    /// [default: out/study].
    #[arg(long, value_name = "DIR")]
    #[serde(serialize_with = "crate::command::opt_path_text")]
    pub out: Option<PathBuf>,
}

impl StudyCmd {
    /// What the command line asks of the study.
    fn options(&self) -> Result<Options, FemError> {
        let whole = |key: &str, v: Option<f64>| {
            crate::command::whole(key, v, 1e6, "give a whole number ≥ 1")
        };
        let threads = whole("threads", self.threads)?
            .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()));
        if threads > 1024 {
            return Err(FemError::input(
                "command line",
                format!("--threads {threads}: give at most 1024"),
            ));
        }
        Ok(Options {
            plan: self.plan.clone(),
            out: self
                .out
                .clone()
                .unwrap_or_else(|| PathBuf::from(DEFAULT_OUT)),
            threads,
            stop_after: whole("stop-after", self.stop_after)?,
            restart: self.restart,
        })
    }
}

impl Command for StudyCmd {
    const NAME: &'static str = "study";
    const STOPS_AT_STEP: bool = true;
    fn out_dir(&self) -> Option<PathBuf> {
        crate::command::out_or(&self.out, DEFAULT_OUT)
    }
    fn run(&self, _: &Context) -> Result<i32, FemError> {
        crate::study::command(self.options()?)
    }
}

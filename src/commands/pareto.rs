//! `railfem pareto`: run time against error ([`crate::pareto`]) for `--cases`; `pareto.csv`, `pareto.md` and `pareto-<case>.svg` in `--out`. `train-bridge` ([`crate::pareto_train`], not in the default) writes `pareto-train-bridge.{csv,md}` and `pareto-train-bridge-{Q,dQQ,w}.svg` there.
// The doc comments are the --help text too, where `[s]` is a unit, not a link.
#![allow(rustdoc::broken_intra_doc_links)]

use crate::command::{Command, Context};
use crate::framework::FemError;
use clap::Args;
use serde::Serialize;
use std::path::PathBuf;

/// `railfem pareto`.
#[derive(Args, Debug, Clone, PartialEq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub struct ParetoCmd {
    /// Output directory [default: out/pareto].
    #[arg(long, value_name = "DIR")]
    #[serde(serialize_with = "crate::command::opt_path_text")]
    pub out: Option<PathBuf>,
    /// Cases, comma-separated, from force, sprung, curve, train-bridge [default:
    /// force,sprung,curve]. `--case` is the same option (`--case train-bridge`, as
    /// `railfem bench --case`).
    #[arg(
        value_parser = crate::command::text(),
        long,
        visible_alias = "case",
        value_name = "force,sprung,curve,train-bridge"
    )]
    pub cases: Option<String>,
    /// train-bridge only: compute nothing, evaluate the runs already in --out.
    #[arg(long)]
    pub existing: bool,
    /// train-bridge only: also check the reference against a finer mesh (18 elements per
    /// fastener bay) and half its step over the whole crossing (about an hour each).
    #[arg(long)]
    pub finer: bool,
}

impl Command for ParetoCmd {
    const NAME: &'static str = "pareto";
    const STOPS_AT_STEP: bool = true;
    fn out_dir(&self) -> Option<PathBuf> {
        crate::command::out_or(&self.out, "out/pareto")
    }
    fn run(&self, ctx: &Context) -> Result<i32, FemError> {
        let mut grid = crate::pareto::Grid::default();
        if let Some(c) = &self.cases {
            let known = [&crate::pareto::CASES[..], &["train-bridge"]].concat();
            grid.cases = crate::pareto::parse_cases(c, &known)?;
        }
        let out = ctx.out();
        // The train–bridge case has its own grid, files and figures (`crate::pareto_train`).
        let train = grid.cases.iter().any(|c| c == "train-bridge");
        grid.cases.retain(|c| c != "train-bridge");
        if !grid.cases.is_empty() {
            crate::pareto::run(&grid, out)?;
        }
        if train {
            let tb = crate::pareto_train::TbGrid {
                existing_only: self.existing,
                finer_checks: self.finer,
                ..Default::default()
            };
            crate::pareto_train::run(&tb, out)?;
        }
        println!("pareto: results in {}", out.display());
        Ok(0)
    }
}

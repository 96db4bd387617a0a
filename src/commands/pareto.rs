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
    /// A peer code's runs of the force case (CSV: peer, elements, dt [s], steps, wall [s],
    /// error [-]; scripts/opensees_compare.py --pareto writes it), drawn on
    /// pareto-force.svg and compared at equal error in pareto-peers.md.
    #[arg(long, value_name = "FILE")]
    #[serde(serialize_with = "crate::command::opt_path_text")]
    pub peer: Option<PathBuf>,
    /// train-bridge only: after the grid, time the cheapest generalized-α runs within 5 %
    /// and 1 % and their neighbours again, back to back, ROUNDS times in turn
    /// (pareto-train-bridge-retime.md) [default: 0, none].
    #[arg(value_parser = crate::command::number(), long, value_name = "ROUNDS")]
    pub retime: Option<f64>,
    /// train-bridge only: re-time these runs (element length : time step, generalized-α,
    /// partitioned) in turn, --retime rounds (default 1), without running the grid.
    #[arg(value_parser = crate::command::text(), long, value_name = "H:DT,H:DT,..")]
    pub retime_at: Option<String>,
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
            grid.cases = c.split(',').map(|x| x.trim().to_string()).collect();
            if let Some(bad) = grid
                .cases
                .iter()
                .find(|x| !["force", "sprung", "curve", "train-bridge"].contains(&x.as_str()))
            {
                return Err(FemError::input(
                    "command line",
                    format!(
                        "--cases {c}: unknown case `{bad}`; use any of force,sprung,curve,train-bridge"
                    ),
                ));
            }
        }
        // The peer file is read (and refused) before the grid runs for minutes.
        let peers = match self.peer.as_deref() {
            Some(p) if grid.cases.iter().any(|c| c == "force") => {
                Some(crate::pareto_peer::read_peer_csv(p)?)
            }
            Some(p) => {
                return Err(FemError::input(
                    "command line",
                    format!(
                        "--peer {}: the peer runs are of the force case; add force to --cases",
                        p.display()
                    ),
                ))
            }
            None => None,
        };
        let retime = match self.retime {
            None => 0,
            Some(r) if r >= 0.0 && r.fract() == 0.0 && r <= 100.0 => r as usize,
            Some(r) => {
                return Err(FemError::input(
                    "command line",
                    format!("--retime {r}: give a whole number of rounds, 0 to 100"),
                ))
            }
        };
        if retime > 0 && !grid.cases.iter().any(|c| c == "train-bridge") {
            return Err(FemError::input(
                "command line",
                "--retime times train-bridge runs; add train-bridge to --cases",
            ));
        }
        let out = ctx.out();
        if let Some(at) = &self.retime_at {
            if grid.cases != ["train-bridge"] {
                return Err(FemError::input(
                    "command line",
                    "--retime-at times train-bridge runs only; give --cases train-bridge",
                ));
            }
            let at = crate::pareto_retime::parse_at(at)?;
            crate::pareto_retime::run_at(&at, retime.max(1), out)?;
            println!("pareto: results in {}", out.display());
            return Ok(0);
        }
        // The train–bridge case has its own grid, files and figures (`crate::pareto_train`).
        let train = grid.cases.iter().any(|c| c == "train-bridge");
        grid.cases.retain(|c| c != "train-bridge");
        if !grid.cases.is_empty() {
            let runs = crate::pareto::run(&grid, out)?;
            if let Some(peers) = &peers {
                crate::pareto_peer::write(&runs, peers, out)?;
            }
        }
        if train {
            let tb = crate::pareto_train::TbGrid {
                existing_only: self.existing,
                finer_checks: self.finer,
                ..Default::default()
            };
            let runs = crate::pareto_train::run(&tb, out)?;
            if retime > 0 {
                crate::pareto_retime::run(&tb, &runs, retime, out)?;
            }
        }
        println!("pareto: results in {}", out.display());
        Ok(0)
    }
}

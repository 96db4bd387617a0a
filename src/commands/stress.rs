//! `railfem stress`: the numerical stress suite ([`crate::stress`]); the table on stdout and, with `--out`, in `DIR/stress.md`.

use crate::command::{Command, Context};
use crate::framework::FemError;
use clap::Args;
use serde::Serialize;
use std::path::PathBuf;

/// `railfem stress`.
#[derive(Args, Debug, Clone, PartialEq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub struct StressCmd {
    /// all, sdof, beam, penalty, speed, drop, stick-slip or dip [default: all].
    #[arg(value_parser = crate::command::text(), long, value_name = "CASE")]
    pub case: Option<String>,
    /// Integrator: newmark, hht:ALPHA, galpha:RHO_INF, bathe or bathe:GAMMA [default: newmark].
    #[arg(value_parser = crate::command::text(), long, value_name = "S")]
    pub scheme: Option<String>,
    /// ω·Δt of the sdof and beam cases [default: 1].
    #[arg(value_parser = crate::command::number(), long, value_name = "W")]
    pub omega_dt: Option<f64>,
    /// Contact penalty stiffness in N/m [default: 1e10].
    #[arg(value_parser = crate::command::number(), long, value_name = "K")]
    pub penalty: Option<f64>,
    /// Speed in m/s (speed case: 80; dip case: 15).
    #[arg(value_parser = crate::command::number(), long, value_name = "V")]
    pub speed: Option<f64>,
    /// Drop height in m [default: 0.01].
    #[arg(value_parser = crate::command::number(), long, value_name = "H")]
    pub height: Option<f64>,
    /// Rail joint dip depth in m [default: 0.002].
    #[arg(value_parser = crate::command::number(), long, value_name = "D")]
    pub depth: Option<f64>,
    /// Stick-slip load over the friction limit, as a factor [default: 1.5].
    #[arg(value_parser = crate::command::number(), long, value_name = "F")]
    pub overshoot: Option<f64>,
    /// Time steps (per case default: 2000, 500, 400, …).
    #[arg(value_parser = crate::command::number(), long, value_name = "N")]
    pub steps: Option<f64>,
    /// Duration in s (speed case: 0.3; drop case: 0.2).
    #[arg(value_parser = crate::command::number(), long, value_name = "T")]
    pub duration: Option<f64>,
    /// Time step in s of the drop case [default: 2e-5].
    #[arg(value_parser = crate::command::number(), long, value_name = "DT")]
    pub dt: Option<f64>,
    /// Also write the table to DIR/stress.md.
    #[arg(long, value_name = "DIR")]
    #[serde(serialize_with = "crate::command::opt_path_text")]
    pub out: Option<PathBuf>,
}

impl Command for StressCmd {
    const NAME: &'static str = "stress";
    const STOPS_AT_STEP: bool = true;
    fn out_dir(&self) -> Option<PathBuf> {
        self.out.clone()
    }
    fn run(&self, _: &Context) -> Result<i32, FemError> {
        let options = crate::stress::CaseOptions {
            omega_dt: self.omega_dt,
            steps: self.steps,
            penalty: self.penalty,
            speed: self.speed,
            duration: self.duration,
            height: self.height,
            dt: self.dt,
            overshoot: self.overshoot,
            depth: self.depth,
        };
        let mut rows = Vec::new();
        let done = crate::stress::run_cli(
            self.case.as_deref(),
            &options,
            self.scheme.as_deref().unwrap_or("newmark"),
            &mut rows,
        );
        // A stop between cases keeps the table of the completed ones; any other error, none.
        if let Err(e) = &done {
            if !matches!(e, FemError::InterruptedAfter { .. }) {
                return Err(done.unwrap_err());
            }
        }
        let table = crate::stress::table(&rows);
        print!("{table}");
        if let Some(dir) = &self.out {
            std::fs::create_dir_all(dir).map_err(|e| FemError::output(dir, e))?;
            let p = dir.join("stress.md");
            std::fs::write(&p, &table).map_err(|e| FemError::output(&p, e))?;
        }
        done.map(|_| 0)
    }
}

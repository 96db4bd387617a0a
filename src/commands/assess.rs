//! `railfem assess`: running-safety and track-loading assessment of a run's wheel forces (EN 14363, [`crate::assess`]).

use crate::assess::limits::AssessLimits;
use crate::assess::Section;
use crate::command::{Command, Context};
use crate::framework::FemError;
use clap::Args;
use serde::Serialize;
use std::path::PathBuf;

/// `railfem assess`.
#[derive(Args, Debug, Clone, PartialEq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub struct AssessCmd {
    /// The output directory of a run (railfem run, curve, train-bridge).
    #[arg(value_name = "RUN_DIR")]
    #[serde(serialize_with = "crate::command::path_text")]
    pub run_dir: PathBuf,
    /// Where to write the assessment [default: RUN_DIR].
    #[arg(long, value_name = "DIR")]
    #[serde(serialize_with = "crate::command::opt_path_text")]
    pub out: Option<PathBuf>,
    /// Speed in m/s, to measure distance as V·t where no station was recorded [default:
    /// none, the recorded station].
    #[arg(value_parser = crate::command::number(), long, value_name = "V")]
    pub speed: Option<f64>,
    /// Static wheel load Q0 in N [default: each wheelset's mean wheel load over the run].
    #[arg(value_parser = crate::command::number(), long, value_name = "N")]
    pub q0: Option<f64>,
    /// Low-pass cut-off of Y and Q in Hz [default: 20].
    #[arg(value_parser = crate::command::number(), long, value_name = "HZ")]
    pub cutoff: Option<f64>,
    /// Window of the sliding means of Y/Q and ΣY in m [default: 2].
    #[arg(value_parser = crate::command::number(), long, value_name = "M")]
    pub window: Option<f64>,
    /// Percentile of the quasi-static values over the section, in % [default: 50].
    #[arg(value_parser = crate::command::number(), long, value_name = "P")]
    pub qst_percentile: Option<f64>,
    /// Percentile of the maximum values, in % [default: 99.85].
    #[arg(value_parser = crate::command::number(), long, value_name = "P")]
    pub max_percentile: Option<f64>,
    /// First station of the quasi-static section in m [default: start of the run].
    #[arg(value_parser = crate::command::number(), long, value_name = "S")]
    pub from: Option<f64>,
    /// Last station of the quasi-static section in m [default: end of the run].
    #[arg(value_parser = crate::command::number(), long, value_name = "S")]
    pub to: Option<f64>,
    /// Flange angle of Nadal's limit in degrees [default: 70].
    #[arg(value_parser = crate::command::number(), long, value_name = "DEG")]
    pub flange_angle: Option<f64>,
    /// Friction coefficient of Nadal's limit [default: 0.36].
    #[arg(value_parser = crate::command::number(), long, value_name = "MU")]
    pub nadal_mu: Option<f64>,
    /// Y/Q limit given directly instead of Nadal's, e.g. 0.8 for R ≥ 250 m [default:
    /// Nadal's, 1.20].
    #[arg(value_parser = crate::command::number(), long, value_name = "L")]
    pub yq_limit: Option<f64>,
    /// Prud'homme's factor α: 1.0 passenger vehicles, 0.85 freight wagons [default: 1.0].
    #[arg(value_parser = crate::command::number(), long, value_name = "A")]
    pub alpha: Option<f64>,
}

impl Command for AssessCmd {
    const NAME: &'static str = "assess";
    fn run(&self, _: &Context) -> Result<i32, FemError> {
        let run_dir = self.run_dir.as_path();
        let bad = |key: &str, v: f64, fix: &str| {
            FemError::input("command line", format!("--{key} {v}: {fix}"))
        };
        let positive = |key: &str, v: Option<f64>| -> Result<Option<f64>, FemError> {
            match v {
                Some(v) if v <= 0.0 => Err(bad(key, v, "give a value > 0")),
                o => Ok(o),
            }
        };
        let pct = |key: &str, v: Option<f64>| -> Result<Option<f64>, FemError> {
            match v {
                Some(v) if !(0.0..=100.0).contains(&v) => {
                    Err(bad(key, v, "give a percentile from 0 to 100"))
                }
                o => Ok(o),
            }
        };
        let mut lim = AssessLimits::default();
        if let Some(v) = positive("cutoff", self.cutoff)? {
            lim.cutoff = v;
        }
        if let Some(v) = positive("window", self.window)? {
            lim.window = v;
        }
        if let Some(v) = pct("qst-percentile", self.qst_percentile)? {
            lim.quasi_static_percentile = v;
        }
        if let Some(v) = pct("max-percentile", self.max_percentile)? {
            lim.max_percentile = v;
        }
        if let Some(v) = self.flange_angle {
            if !(v > 0.0 && v < 90.0) {
                return Err(bad(
                    "flange-angle",
                    v,
                    "give the flange angle in degrees, 0 < γ < 90 (S1002: 70)",
                ));
            }
            lim.flange_angle = v.to_radians();
        }
        if let Some(v) = self.nadal_mu {
            if !(0.0..=1.0).contains(&v) {
                return Err(bad(
                    "nadal-mu",
                    v,
                    "give a friction coefficient from 0 to 1 (EN 14363's 1.2 uses 0.36)",
                ));
            }
            lim.nadal_mu = v;
        }
        lim.yq_limit = positive("yq-limit", self.yq_limit)?;
        if let Some(v) = positive("alpha", self.alpha)? {
            lim.alpha = v;
        }
        let section = Section {
            from: self.from,
            to: self.to,
        };
        if let (Some(f), Some(t)) = (section.from, section.to) {
            if t <= f {
                return Err(FemError::input(
                    "command line",
                    format!("--from {f} --to {t}: the section must end after it starts"),
                ));
            }
        }
        let out = self.out.clone().unwrap_or_else(|| run_dir.to_path_buf());
        crate::assess::run_assessment(
            run_dir,
            &out,
            positive("speed", self.speed)?,
            &lim,
            section,
            positive("q0", self.q0)?,
        )?;
        Ok(0)
    }
}

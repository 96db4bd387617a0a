//! `railfem critical-radius`: one point of the paper's Figure 7 or 9 ([`crate::critical`]), or with `--sweep` a whole figure.

use crate::command::{Command, Context};
use crate::critical::{Criterion, CriticalCase};
use crate::elements::rail::contact::creep::law::Tangential;
use crate::framework::FemError;
use clap::Args;
use serde::Serialize;
use std::path::Path;
use std::path::PathBuf;

/// `railfem critical-radius`.
#[derive(Args, Debug, Clone, PartialEq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub struct CriticalCmd {
    /// Onset criterion: sliding or separation [default: sliding].
    #[arg(value_parser = crate::command::text(), long, value_name = "sliding|separation")]
    pub criterion: Option<String>,
    /// Sweep speeds × cts × mus on all cores (a whole figure).
    #[arg(long)]
    pub sweep: bool,
    /// Sweep speeds in m/s, comma-separated [default: 100,140,180,220,260].
    #[arg(value_parser = crate::command::text(), long, value_name = "V1,V2,..")]
    pub speeds: Option<String>,
    /// Sweep Ct values in m, comma-separated [default: 200,400,900].
    #[arg(value_parser = crate::command::text(), long, value_name = "CT1,CT2,..")]
    pub cts: Option<String>,
    /// Sweep friction coefficients [default: 0.1,0.2,0.3 (sliding), 0.3 (separation)].
    #[arg(value_parser = crate::command::text(), long, value_name = "MU1,MU2,..")]
    pub mus: Option<String>,
    /// Output directory [default: out/critical for a sweep; none for one point].
    #[arg(long, value_name = "DIR")]
    #[serde(serialize_with = "crate::command::opt_path_text")]
    pub out: Option<PathBuf>,
    /// Speed V in m/s [default: 120].
    #[arg(value_parser = crate::command::number(), long, value_name = "V")]
    pub speed: Option<f64>,
    /// Cant parameter Ct in m [default: 200].
    #[arg(value_parser = crate::command::number(), long, value_name = "CT")]
    pub ct: Option<f64>,
    /// Friction coefficient μ [default: 0.3].
    #[arg(value_parser = crate::command::number(), long, value_name = "MU")]
    pub mu: Option<f64>,
    /// Tangential contact law of the wheels: coulomb (the paper's), kalker_linear, polach
    /// or fastsim (rolling-contact creep; sliding onset = every contact at 99 % of μN for the
    /// gross criterion, docs/creep.md) [default: coulomb]. Single runs only.
    #[arg(value_parser = crate::command::text(), long, value_name = "coulomb|kalker_linear|polach|fastsim")]
    pub tangential: Option<String>,
    /// Polach's spin term with `--tangential polach`: off (his 2005 law) or polach_1999 (his
    /// spin-corrected lateral creepage and force, docs/creep.md) [default: off].
    #[arg(value_parser = crate::command::text(), long, value_name = "off|polach_1999")]
    pub polach_spin: Option<String>,
    /// Clothoid length in m [default: 2000].
    #[arg(value_parser = crate::command::number(), long, value_name = "L")]
    pub clothoid: Option<f64>,
    /// Time step in s [default: 0.01].
    #[arg(value_parser = crate::command::number(), long, value_name = "DT")]
    pub dt: Option<f64>,
    /// Kinematics of the vehicle links: linear or nonlinear [default: linear].
    #[arg(value_parser = crate::command::text(), long, value_name = "linear|nonlinear")]
    pub geometry: Option<String>,
}

/// A `--speeds`/`--cts`/`--mus` list of positive numbers, or its default.
fn list(key: &str, given: Option<&str>, default: &[f64]) -> Result<Vec<f64>, FemError> {
    match given {
        None => Ok(default.to_vec()),
        Some(t) => t
            .split(',')
            .map(|x| {
                x.trim()
                    .parse::<f64>()
                    .ok()
                    .filter(|v| v.is_finite() && *v > 0.0)
            })
            .collect::<Option<Vec<f64>>>()
            .ok_or_else(|| {
                FemError::input(
                    "command line",
                    format!("--{key} {t}: give positive numbers, comma-separated"),
                )
            }),
    }
}

impl CriticalCmd {
    /// `--sweep`: speeds × cts × mus on all cores, into `out`.
    fn sweep(&self, criterion: Criterion, out: &Path) -> Result<i32, FemError> {
        if let Some(t) = self.tangential.as_deref().filter(|t| *t != "coulomb") {
            return Err(FemError::input(
                "command line",
                format!("--tangential {t} with --sweep: the sweep runs the paper's Coulomb law only; drop --sweep and run single points (--speed, --ct, --mu)"),
            ));
        }
        let speeds = list(
            "speeds",
            self.speeds.as_deref(),
            &[100.0, 140.0, 180.0, 220.0, 260.0],
        )?;
        let cts = list("cts", self.cts.as_deref(), &[200.0, 400.0, 900.0])?;
        let mus = match criterion {
            Criterion::Sliding => list("mus", self.mus.as_deref(), &[0.1, 0.2, 0.3])?,
            Criterion::Separation => list("mus", self.mus.as_deref(), &[0.3])?,
        };
        let points = speeds.len() * cts.len() * mus.len();
        let bar = std::sync::Mutex::new(crate::progress::Progress::new(
            "critical-radius",
            points as u64,
            "points",
        ));
        let progress = |f: f64| {
            if let Ok(mut b) = bar.lock() {
                b.fraction(f);
            }
        };
        let pts = crate::critical::sweep(
            criterion,
            &speeds,
            &cts,
            &mus,
            self.clothoid.unwrap_or(2000.0),
            self.dt.unwrap_or(0.01),
            crate::command::geometry(self.geometry.as_deref())?,
            std::thread::available_parallelism().map_or(2, |n| n.get()),
            &progress,
        );
        if let Ok(mut b) = bar.lock() {
            b.finish();
        }
        crate::critical::write_sweep(&pts, criterion, out)?;
        let mut worst = 0.0f64;
        for (_, r) in &pts {
            if let Ok(r) = r {
                let reference = match criterion {
                    Criterion::Sliding => r.theory,
                    Criterion::Separation => r.lean_at_contact.or(r.theory_at_contact),
                };
                if let (Some(fe), Some(th)) = (r.fe, reference) {
                    worst = worst.max((fe - th).abs() / th);
                }
            }
        }
        println!(
            "{} points; largest relative difference FE vs theory: {worst:.3e}; results in {}",
            pts.len(),
            out.display()
        );
        // Stopped between cases: the table holds the first cases, whole.
        crate::framework::interrupt::check_after(|| format!("{} of {points} cases", pts.len()))?;
        Ok(0)
    }
}

impl Command for CriticalCmd {
    const NAME: &'static str = "critical-radius";
    const STOPS_AT_STEP: bool = true;
    fn out_dir(&self) -> Option<PathBuf> {
        if self.sweep {
            crate::command::out_or(&self.out, "out/critical")
        } else {
            self.out.clone()
        }
    }
    fn run(&self, ctx: &Context) -> Result<i32, FemError> {
        let criterion = match self.criterion.as_deref().unwrap_or("sliding") {
            "sliding" => Criterion::Sliding,
            "separation" => Criterion::Separation,
            o => {
                return Err(FemError::input(
                    "command line",
                    format!("--criterion {o}: use sliding or separation"),
                ))
            }
        };
        let tangential: Tangential = crate::choice::parse(
            "command line",
            "--tangential",
            self.tangential.as_deref().unwrap_or("coulomb"),
        )?;
        if self.sweep {
            return self.sweep(criterion, ctx.out());
        }
        let case = CriticalCase {
            criterion,
            speed: self.speed.unwrap_or(120.0),
            ct: self.ct.unwrap_or(200.0),
            mu: self.mu.unwrap_or(0.3),
            clothoid: self.clothoid.unwrap_or(2000.0),
            dt: self.dt.unwrap_or(0.01),
            geometry: crate::command::geometry(self.geometry.as_deref())?,
            tangential,
            polach_spin: crate::command::polach_spin(self.polach_spin.as_deref(), tangential)?,
        };
        let out = ctx.out.as_deref();
        let r = crate::critical::run_with_sections(&case, out)?;
        if let Some(o) = out {
            println!("cross-sections at the onset written to {}", o.display());
        }
        let f = |x: Option<f64>| x.map_or("not reached".to_string(), |v| format!("{v:.1} m"));
        println!(
            "{:?}: V = {} m/s, Ct = {} m, mu = {}{}: FE {} (gross sliding {}), theory (statics) {}, Eq. 25 as printed {}",
            case.criterion, case.speed, case.ct, case.mu,
            if case.tangential == Tangential::Coulomb { String::new() } else { format!(", tangential {}", case.tangential.name()) },
            f(r.fe), f(r.fe_gross), f(r.theory), f(r.theory_printed)
        );
        if let (Some(fe), Some(th)) = (r.fe, r.theory) {
            println!(
                "relative difference FE vs theory: {:.3e}",
                (fe - th).abs() / th
            );
        }
        if let Some(c) = r.outer_contact {
            println!(
                "statics about the FE's outer contact point (y = {:.4} m, z = {:.4} m): {}",
                c[0],
                c[1],
                f(r.theory_at_contact)
            );
            if let (Some(fe), Some(th)) = (r.fe, r.theory_at_contact) {
                println!(
                    "relative difference FE vs statics about that point: {:.3e}",
                    (fe - th).abs() / th
                );
            }
            if let Some(lean) = r.lean_at_contact {
                let rel = r.fe.map_or(f64::NAN, |fe| (fe - lean).abs() / lean);
                println!(
                    "statics with body lean about that point: {lean:.1} m; relative difference FE vs it: {rel:.3e}"
                );
            }
        }
        Ok(0)
    }
}

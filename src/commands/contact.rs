//! `railfem contact`: wheel–rail contact of a wheelset on straight track over a lateral shift ([`crate::contact_tool`]).

use crate::command::{Command, Context};
use crate::contact_tool::profiles::{BuiltInProfiles, ProfileSet};
use crate::contact_tool::{sweep, write_shifts, Balance, ContactCase, CreepLaw};
use crate::elements::rail::contact::profiles::Inclination;
use crate::framework::FemError;
use clap::Args;
use serde::Serialize;
use std::path::PathBuf;

/// The values of `--balance`.
#[derive(serde::Deserialize, Debug, Clone, Copy, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
enum BalanceChoice {
    /// `N = Q/cos δ`.
    None,
    /// Kalker's linear theory, saturated.
    KalkerLinear,
    /// Polach.
    Polach,
    /// FASTSIM.
    Fastsim,
}

/// `railfem contact`.
#[derive(Args, Debug, Clone, PartialEq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub struct ContactCmd {
    /// Output directory [default: out-contact].
    #[arg(long, value_name = "DIR")]
    #[serde(serialize_with = "crate::command::opt_path_text")]
    pub out: Option<PathBuf>,
    /// Built-in profiles: s1002-60e1 or mbench (the Manchester contact benchmark's)
    /// [default: s1002-60e1].
    #[arg(value_parser = crate::command::text(), long, value_name = "SET")]
    pub profiles: Option<String>,
    /// Wheel profile CSV (with --rail), instead of the built-in profiles.
    #[arg(long, value_name = "FILE")]
    #[serde(serialize_with = "crate::command::opt_path_text")]
    pub wheel: Option<PathBuf>,
    /// Rail profile CSV, upright (with --wheel).
    #[arg(long, value_name = "FILE")]
    #[serde(serialize_with = "crate::command::opt_path_text")]
    pub rail: Option<PathBuf>,
    /// Rail inclination of 60E1 or a CSV rail: 1:40, 1:20 or none [default: 1:40].
    #[arg(value_parser = crate::command::text(), long, value_name = "I")]
    pub inclination: Option<String>,
    /// Track gauge in m, at 14 mm below the rail top [default: 1.435].
    #[arg(value_parser = crate::command::number(), long, value_name = "M")]
    pub gauge: Option<f64>,
    /// Back-to-back distance of the wheels in m [default: 1.360].
    #[arg(value_parser = crate::command::number(), long, value_name = "M")]
    pub back_to_back: Option<f64>,
    /// Nominal rolling radius in m [default: 0.46].
    #[arg(value_parser = crate::command::number(), long, value_name = "M")]
    pub radius: Option<f64>,
    /// One lateral shift of the axle centre in m (positive to the left) instead of a sweep
    /// [default: none, the sweep].
    #[arg(value_parser = crate::command::number(), long, value_name = "M")]
    pub y: Option<f64>,
    /// Sweep of the lateral shift from 0 to this value in m [default: 0.01].
    #[arg(value_parser = crate::command::number(), long, value_name = "M")]
    pub y_max: Option<f64>,
    /// Step of the sweep in m [default: 0.0005].
    #[arg(value_parser = crate::command::number(), long, value_name = "M")]
    pub y_step: Option<f64>,
    /// Yaw angle in rad, for the lateral creepage [default: 0].
    #[arg(value_parser = crate::command::number(), long, value_name = "RAD")]
    pub yaw: Option<f64>,
    /// Yaw per lateral shift in rad/m, added to --yaw (Manchester benchmark: 2.4) [default: 0].
    #[arg(value_parser = crate::command::number(), long, value_name = "RAD/M")]
    pub yaw_per_shift: Option<f64>,
    /// Pitch rate of the wheelset in rad/s [default: free rolling, speed/radius].
    #[arg(value_parser = crate::command::number(), long, value_name = "RAD/S")]
    pub pitch_rate: Option<f64>,
    /// Normal load from the vertical load with the lateral creep force of a law: none
    /// (N = Q/cos δ), kalker_linear, polach or fastsim [default: fastsim].
    #[arg(value_parser = crate::command::text(), long, value_name = "LAW")]
    pub balance: Option<String>,
    /// Vertical load on each wheel in N [default: 50000].
    #[arg(value_parser = crate::command::number(), long, value_name = "N")]
    pub load: Option<f64>,
    /// Speed in m/s [default: 20].
    #[arg(value_parser = crate::command::number(), long, value_name = "V")]
    pub speed: Option<f64>,
    /// Friction coefficient [default: 0.3].
    #[arg(value_parser = crate::command::number(), long, value_name = "MU")]
    pub mu: Option<f64>,
    /// Young's modulus of wheel and rail in Pa [default: 2.1e11].
    #[arg(value_parser = crate::command::number(), long, value_name = "PA")]
    pub young: Option<f64>,
    /// Poisson's ratio of wheel and rail [default: 0.28].
    #[arg(value_parser = crate::command::number(), long, value_name = "NU")]
    pub poisson: Option<f64>,
}

/// A positive value of `--key`, or its default.
fn positive(key: &str, v: Option<f64>, default: f64) -> Result<f64, FemError> {
    let v = v.unwrap_or(default);
    if v > 0.0 {
        Ok(v)
    } else {
        Err(FemError::input(
            "command line",
            format!("--{key} {v}: must be positive (SI units: m, N, m/s, Pa)"),
        ))
    }
}

impl ContactCmd {
    /// `--inclination` (default 1:40), read into [`Inclination`] as a model file's is.
    fn inclination(&self) -> Result<Inclination, FemError> {
        match self.inclination.as_deref() {
            None => Ok(Inclination::OneIn40),
            Some(v) => crate::choice::parse("command line", "--inclination", v),
        }
    }

    /// `--balance` (default fastsim): the law whose lateral creep force shares the vertical
    /// load with the normal force, or none.
    fn balance(&self) -> Result<Balance, FemError> {
        let choice = match self.balance.as_deref() {
            None => BalanceChoice::Fastsim,
            Some(v) => crate::choice::parse("command line", "--balance", v)?,
        };
        Ok(match choice {
            BalanceChoice::None => Balance::Vertical,
            BalanceChoice::KalkerLinear => Balance::Creep(CreepLaw::KalkerLinear),
            BalanceChoice::Polach => Balance::Creep(CreepLaw::Polach),
            BalanceChoice::Fastsim => Balance::Creep(CreepLaw::Fastsim),
        })
    }

    /// The case of the command line.
    pub fn case(&self) -> Result<ContactCase, FemError> {
        let d = ContactCase::default();
        let built_in = self
            .profiles
            .as_deref()
            .map(|v| crate::choice::parse::<BuiltInProfiles>("command line", "--profiles", v))
            .transpose()?;
        let profiles = match (built_in, &self.wheel, &self.rail) {
            (_, Some(w), Some(r)) => ProfileSet::Files {
                wheel: w.clone(),
                rail: r.clone(),
                inclination: self.inclination()?,
            },
            (_, Some(_), None) | (_, None, Some(_)) => {
                return Err(FemError::input(
                    "command line",
                    "--wheel and --rail go together; fix: give both CSV files or neither",
                ))
            }
            (None | Some(BuiltInProfiles::S1002On60E1), None, None) => {
                ProfileSet::S1002On60E1(self.inclination()?)
            }
            (Some(BuiltInProfiles::ManchesterBenchmark), None, None) => {
                ProfileSet::ManchesterBenchmark
            }
        };
        let poisson = self.poisson.unwrap_or(d.poisson);
        if !(0.0..0.5).contains(&poisson) {
            return Err(FemError::input(
                "command line",
                format!("--poisson {poisson}: must lie in [0, 0.5)"),
            ));
        }
        Ok(ContactCase {
            profiles,
            gauge: positive("gauge", self.gauge, d.gauge)?,
            back_to_back: positive("back-to-back", self.back_to_back, d.back_to_back)?,
            radius: positive("radius", self.radius, d.radius)?,
            yaw: self.yaw.unwrap_or(0.0),
            yaw_per_shift: self.yaw_per_shift.unwrap_or(0.0),
            pitch_rate: self.pitch_rate,
            balance: self.balance()?,
            load: positive("load", self.load, d.load)?,
            speed: positive("speed", self.speed, d.speed)?,
            mu: positive("mu", self.mu, d.mu)?,
            young: positive("young", self.young, d.young)?,
            poisson,
        })
    }
}

impl Command for ContactCmd {
    const NAME: &'static str = "contact";
    fn run(&self, _: &Context) -> Result<i32, FemError> {
        let case = self.case()?;
        let shifts = match (self.y, self.y_max) {
            (Some(_), Some(_)) => {
                return Err(FemError::input(
                    "command line",
                    "--y and --y-max exclude each other; fix: give one shift or a sweep",
                ))
            }
            (Some(y), None) => vec![y],
            (None, y_max) => sweep(
                y_max.unwrap_or(0.01),
                positive("y-step", self.y_step, 5e-4)?,
            ),
        };
        let out = self.out.clone().unwrap_or_else(|| "out-contact".into());
        write_shifts(&case, &shifts, &out)?;
        Ok(0)
    }
}

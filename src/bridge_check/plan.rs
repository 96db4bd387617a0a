//! The plan of `railfem bridge-check` (`PLAN.toml`): the bridge, the speeds, the trains
//! and the analysis settings, read and checked. Every key is described in
//! `docs/bridge-check.md`; a bad one gets one line naming the file, the key and the fix.

use super::bridge::BridgeSpec;
use super::interaction::{Models, SprungDefaults};
use crate::framework::FemError;
use serde::Deserialize;
use std::path::{Path, PathBuf};

/// `[speeds]`: the range the trains cross at.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Speeds {
    /// The line's maximum speed (km/h); the range ends at 1.2 times it (EN 1991-2
    /// §6.4.6.2(1)).
    pub max_line_speed: f64,
    /// Lowest speed (km/h) [default: 40].
    #[serde(default = "default_min")]
    pub min: f64,
    /// Step of the coarse pass (km/h) [default: 5].
    #[serde(default = "default_step")]
    pub step: f64,
    /// Halvings of the step around each local maximum [default: 2].
    #[serde(default = "default_refine")]
    pub refine: usize,
}

fn default_min() -> f64 {
    40.0
}
fn default_step() -> f64 {
    5.0
}
fn default_refine() -> usize {
    2
}

/// A user's train: a name and either an axle file (TOML or CSV, [`super::trains`]) or a
/// railfem vehicle file coupled `count` times ([`super::vehicle_train`]).
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct UserTrain {
    /// Name in the outputs.
    pub name: String,
    /// The axle file, relative to the plan.
    #[serde(default)]
    pub file: Option<PathBuf>,
    /// A vehicle file (docs/vehicles.md), relative to the plan.
    #[serde(default)]
    pub vehicle: Option<PathBuf>,
    /// How many of the vehicle, coupled [default: 1].
    #[serde(default)]
    pub count: Option<usize>,
}

/// `[analysis]`: numerical settings.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Analysis {
    /// Time steps per period of the cut-off frequency [default:
    /// [`DEFAULT_STEPS_PER_PERIOD`]].
    #[serde(default = "default_spp")]
    pub steps_per_period: f64,
    /// Modes computed for the frequencies [default: 12].
    #[serde(default = "default_modes")]
    pub modes: usize,
    /// Free vibration after the last axle leaves, in periods of the first frequency
    /// [default: 2].
    #[serde(default = "default_tail")]
    pub tail_periods: f64,
    /// Travel between the positions of the static crossing (m) [default: 0.05].
    #[serde(default = "default_ds")]
    pub static_step: f64,
    /// The trains as moving forces, moving sprung masses, both, full vehicles, or all three
    /// [default: moving forces].
    #[serde(default)]
    pub model: Models,
}

/// Default time steps per period of the cut-off frequency (`[analysis] steps_per_period`):
/// with [`super::bridge::DEFAULT_ELEMENTS_PER_SPAN`] the FE's peak filtered acceleration is
/// within 0.5 % of the converged modal reference at every speed (docs/bridge-check.md,
/// "Accuracy"; `fe_envelope_against_modal_reference` in `tests/bridge_check.rs`).
pub const DEFAULT_STEPS_PER_PERIOD: f64 = 60.0;

fn default_spp() -> f64 {
    DEFAULT_STEPS_PER_PERIOD
}
fn default_modes() -> usize {
    12
}
fn default_tail() -> f64 {
    2.0
}
fn default_ds() -> f64 {
    0.05
}

impl Default for Analysis {
    fn default() -> Self {
        Analysis {
            steps_per_period: default_spp(),
            modes: default_modes(),
            tail_periods: default_tail(),
            static_step: default_ds(),
            model: Models::default(),
        }
    }
}

/// The whole plan.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Plan {
    /// The bridge.
    pub bridge: BridgeSpec,
    /// The speed range.
    pub speeds: Speeds,
    /// Built-in trains by name [default: HSLM-A1 … A10, and HSLM-B on a simply supported
    /// span shorter than 7 m].
    pub trains: Option<Vec<String>>,
    /// The user's trains.
    #[serde(default)]
    pub train: Vec<UserTrain>,
    /// Numerical settings.
    #[serde(default)]
    pub analysis: Analysis,
    /// The suspension of the axles of trains without their own (sprung-mass model).
    #[serde(default)]
    pub sprung_masses: SprungDefaults,
}

impl Plan {
    /// Reads and checks `path`; relative files in it are resolved against its folder.
    pub fn read(path: &Path) -> Result<Plan, FemError> {
        let file = path.display().to_string();
        let text = std::fs::read_to_string(path).map_err(|e| {
            FemError::input(&file, format!("cannot read the plan ({e}); fix the path"))
        })?;
        let mut plan: Plan = toml::from_str(&text).map_err(|e| {
            let key = e
                .span()
                .map(|s| {
                    let line = text[..s.start].lines().count().max(1);
                    format!(" (line {line})")
                })
                .unwrap_or_default();
            FemError::input(
                format!("{file}{key}"),
                format!(
                    "{}; see docs/bridge-check.md for the plan's keys",
                    e.message().trim()
                ),
            )
        })?;
        let base = path.parent().unwrap_or(Path::new("."));
        if let Some(m) = &plan.bridge.model {
            plan.bridge.model = Some(base.join(m));
        }
        for t in &mut plan.train {
            t.file = t.file.as_ref().map(|f| base.join(f));
            t.vehicle = t.vehicle.as_ref().map(|f| base.join(f));
        }
        plan.validate(&file)?;
        Ok(plan)
    }

    /// Checks the values; errors name `file` and the key.
    pub fn validate(&self, file: &str) -> Result<(), FemError> {
        self.bridge.validate(file)?;
        self.sprung_masses.validate(file)?;
        for (i, t) in self.train.iter().enumerate() {
            let at = format!("{file}: train[{i}] \"{}\"", t.name);
            match (&t.file, &t.vehicle) {
                (Some(_), None) if t.count.is_none() => {}
                (Some(_), None) => {
                    return Err(FemError::input(
                        at,
                        "count goes with a vehicle file; remove it or give vehicle = \"FILE.toml\"",
                    ))
                }
                (None, Some(_)) if t.count.is_none_or(|n| (1..=100).contains(&n)) => {}
                (None, Some(_)) => {
                    return Err(FemError::input(at, "give count between 1 and 100 vehicles"))
                }
                _ => {
                    return Err(FemError::input(
                        at,
                        "give either file = \"AXLES.csv|toml\" or vehicle = \"VEHICLE.toml\"",
                    ))
                }
            }
        }
        let s = &self.speeds;
        let at = |k: &str| format!("{file}: {k}");
        if !(s.max_line_speed.is_finite() && s.max_line_speed > 0.0 && s.max_line_speed <= 600.0) {
            return Err(FemError::input(
                at("speeds.max_line_speed"),
                "give the line's maximum speed in km/h (0 < v ≤ 600)",
            ));
        }
        if !(s.min.is_finite() && s.min > 0.0 && s.min < 1.2 * s.max_line_speed) {
            return Err(FemError::input(
                at("speeds.min"),
                "give a lowest speed in km/h > 0 and below 1.2 × max_line_speed",
            ));
        }
        if !(s.step.is_finite()
            && s.step > 0.0
            && (1.2 * s.max_line_speed - s.min) / s.step <= 10_000.0)
        {
            return Err(FemError::input(
                at("speeds.step"),
                "give a speed step in km/h > 0 (at most 10 000 speeds)",
            ));
        }
        if s.refine > 8 {
            return Err(FemError::input(
                at("speeds.refine"),
                "give at most 8 halvings",
            ));
        }
        let a = &self.analysis;
        if !(a.steps_per_period.is_finite() && (8.0..=1000.0).contains(&a.steps_per_period)) {
            return Err(FemError::input(
                at("analysis.steps_per_period"),
                "give between 8 and 1000 steps per period of the cut-off frequency",
            ));
        }
        if !(3..=200).contains(&a.modes) {
            return Err(FemError::input(
                at("analysis.modes"),
                "give between 3 and 200 modes",
            ));
        }
        if !(a.tail_periods.is_finite() && (0.0..=100.0).contains(&a.tail_periods)) {
            return Err(FemError::input(
                at("analysis.tail_periods"),
                "give between 0 and 100 periods of free vibration",
            ));
        }
        if !(a.static_step.is_finite() && a.static_step > 0.0 && a.static_step <= 1.0) {
            return Err(FemError::input(
                at("analysis.static_step"),
                "give a travel step in m, 0 < step ≤ 1",
            ));
        }
        Ok(())
    }

    /// The speeds of the coarse pass (km/h): from `min` by `step` to 1.2 × the line speed
    /// (included).
    pub fn coarse_speeds(&self) -> Vec<f64> {
        let s = &self.speeds;
        let top = 1.2 * s.max_line_speed;
        let n = ((top - s.min) / s.step - 1e-9).ceil() as usize;
        (0..=n)
            .map(|i| (s.min + i as f64 * s.step).min(top))
            .collect()
    }
}

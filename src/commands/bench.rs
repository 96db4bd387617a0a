//! `railfem bench`: time per step of the benchmark cases ([`crate::bench`] and its siblings); per DOF count in `--sizes`, `--steps` linear transient steps of the benchmark beam by default, a table on stdout and `bench.md`, `bench.csv` in `--out`.

use crate::command::{Command, Context};
use crate::framework::FemError;
use clap::Args;
use serde::Serialize;
use std::path::Path;
use std::path::PathBuf;

/// `railfem bench`.
#[derive(Args, Debug, Clone, PartialEq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub struct BenchCmd {
    /// beam (linear multi-span beam), train-bridge, sprung (a sprung mass crossing the
    /// beam with each linear solver) or floor (time per step against the memory-bandwidth
    /// floor) [default: beam].
    #[arg(value_parser = crate::command::text(), long, value_name = "beam|train-bridge|sprung|floor|window")]
    pub case: Option<String>,
    /// DOF counts, comma-separated [default: 1e4,1e5,1e6].
    #[arg(value_parser = crate::command::text(), long, value_name = "N1,N2,..")]
    pub sizes: Option<String>,
    /// Time steps per size [default: 20].
    #[arg(value_parser = crate::command::number(), long, value_name = "N")]
    pub steps: Option<f64>,
    /// Output directory [default: out/bench].
    #[arg(long, value_name = "DIR")]
    #[serde(serialize_with = "crate::command::opt_path_text")]
    pub out: Option<PathBuf>,
    /// Carriages of the train-bridge case [default: 1]; with --case window a list
    /// [default: 12].
    #[arg(value_parser = crate::command::text(), long, value_name = "N")]
    pub cars: Option<String>,
    /// Spans of the window case, comma-separated [default: 113].
    #[arg(value_parser = crate::command::text(), long, value_name = "N1,N2,..")]
    pub spans: Option<String>,
    /// Rail element length of the window case in m [default: 0.625].
    #[arg(value_parser = crate::command::number(), long, value_name = "H")]
    pub element_length: Option<f64>,
    /// Time step of the train-bridge case in s [default: 5e-4].
    #[arg(value_parser = crate::command::number(), long, value_name = "DT")]
    pub dt: Option<f64>,
    /// Kinematics of the vehicle links: linear or nonlinear [default: linear].
    #[arg(value_parser = crate::command::text(), long, value_name = "linear|nonlinear")]
    pub geometry: Option<String>,
    /// Train-bridge case: station of the front carriage's centre at t = 0 from the bridge's
    /// first abutment, in m [default: -15, entering the viaduct].
    #[arg(value_parser = crate::command::number(), long, value_name = "X", allow_hyphen_values = true)]
    pub train_start: Option<f64>,
    /// Mass matrix of the beam case: consistent (cubic Hermite, as OpenSees -cMass) or
    /// lumped (rho*A*L/2 per node and translation, no rotary inertia, as OpenSees'
    /// elasticBeamColumn default) [default: consistent].
    #[arg(value_parser = crate::command::text(), long, value_name = "consistent|lumped")]
    pub mass: Option<String>,
    /// Window case: the activity window's reaches in m, comma-separated; the window runs
    /// once with each, after the run without it [default: 300].
    #[arg(value_parser = crate::command::text(), long, value_name = "M1,M2,..")]
    pub window_ahead: Option<String>,
    /// Window case: the absorbing layer's thickness in m; 0: none [default: a third of the
    /// reach].
    #[arg(value_parser = crate::command::number(), long, value_name = "M")]
    pub window_layer: Option<f64>,
}

/// The cases of `--case`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
enum BenchCase {
    /// The linear multi-span beam.
    Beam,
    /// The train on the viaduct.
    TrainBridge,
    /// A sprung mass crossing the beam, per linear solver.
    Sprung,
    /// Time per step against the memory-bandwidth floor.
    Floor,
    /// Train-bridge step time against spans and carriages, activity window off and on.
    Window,
}

/// `--cars` of the train-bridge case: one count (the window case takes a list).
fn number(key: &str, v: Option<&str>) -> Result<Option<f64>, FemError> {
    v.map(|t| {
        t.parse::<f64>()
            .ok()
            .filter(|x| x.is_finite())
            .ok_or_else(|| {
                FemError::input("command line", format!("--{key} {t}: not a finite number"))
            })
    })
    .transpose()
}

impl BenchCmd {
    /// `--case window` ([`crate::bench_window`]): `--spans` and `--cars` lists (default 113
    /// and 12), `--steps` timed steps (default 20), `--dt` (default 5e-4 s),
    /// `--element-length` (default 0.625 m), `--train-start` (default -15 m), the window's
    /// reaches `--window-ahead` and absorbing layer `--window-layer` (refused as
    /// `train-bridge` refuses them).
    fn window(&self, out: &Path) -> Result<i32, FemError> {
        let list =
            |key: &str, given: Option<&str>, default: &str| -> Result<Vec<usize>, FemError> {
                let spec = given.unwrap_or(default);
                spec.split(',')
                    .map(|x| match x.trim().parse::<usize>() {
                        Ok(v) if v >= 1 => Ok(v),
                        _ => Err(FemError::input(
                            "command line",
                            format!("--{key} {spec}: give whole numbers >= 1, comma-separated"),
                        )),
                    })
                    .collect()
            };
        let spans = list("spans", self.spans.as_deref(), "113")?;
        let cars = list("cars", self.cars.as_deref(), "12")?;
        let positive = |key: &str, given: Option<f64>, default: f64| -> Result<f64, FemError> {
            match given {
                None => Ok(default),
                Some(v) if v > 0.0 => Ok(v),
                Some(v) => Err(FemError::input(
                    "command line",
                    format!("--{key} {v}: give a value > 0"),
                )),
            }
        };
        let steps = positive("steps", self.steps, 20.0)?.round() as usize;
        let dt = positive("dt", self.dt, 5e-4)?;
        let h = positive("element-length", self.element_length, 0.625)?;
        let start = self.train_start.unwrap_or(-15.0);
        let keys = crate::train_window::COMMAND_LINE;
        let reaches: Vec<Option<f64>> = match self.window_ahead.as_deref() {
            None => vec![None],
            Some(spec) => spec
                .split(',')
                .map(|x| {
                    let ahead = x.trim().parse::<f64>().map_err(|_| {
                        FemError::input(
                            "command line",
                            format!("--window-ahead {spec}: give distances ≥ 0 m, comma-separated"),
                        )
                    })?;
                    crate::train_window::parse_options(keys, Some("on"), Some(ahead), None)?;
                    Ok(Some(ahead))
                })
                .collect::<Result<_, FemError>>()?,
        };
        let on = crate::train_window::WindowChoice::On(Default::default());
        let layer = crate::train_window::parse_layer(keys, on, self.window_layer, None)?;
        crate::bench_window::run(
            &spans,
            &cars,
            steps.max(1),
            [dt, h, start],
            (&reaches, layer),
            out,
        )?;
        Ok(0)
    }
}

impl Command for BenchCmd {
    const NAME: &'static str = "bench";
    const STOPS_AT_STEP: bool = true;
    fn out_dir(&self) -> Option<PathBuf> {
        crate::command::out_or(&self.out, "out/bench")
    }
    fn run(&self, ctx: &Context) -> Result<i32, FemError> {
        let case = match self.case.as_deref() {
            None => BenchCase::Beam,
            Some(v) => crate::choice::parse("command line", "--case", v)?,
        };
        let out = ctx.out();
        if case == BenchCase::Window {
            return self.window(out);
        }
        for (key, given) in [
            ("--window-ahead", self.window_ahead.is_some()),
            ("--window-layer", self.window_layer.is_some()),
        ] {
            if given {
                return Err(FemError::input(
                    "command line",
                    format!(
                        "{key}: only the window case takes {key}; drop it or use --case window"
                    ),
                ));
            }
        }
        let sizes = crate::bench::sizes(self.sizes.as_deref())?;
        let steps = crate::bench::steps(self.steps)?;
        let mass = match self.mass.as_deref() {
            None => crate::bench::BenchMass::Consistent,
            Some(m) => match crate::choice::parse("command line", "--mass", m)? {
                k if case == BenchCase::Beam || case == BenchCase::Floor => k,
                _ => {
                    return Err(FemError::input(
                        "command line",
                        format!(
                            "--mass {m}: only the beam and floor cases take --mass; drop it or use --case beam"
                        ),
                    ))
                }
            },
        };
        if case == BenchCase::TrainBridge {
            let cars = match number("cars", self.cars.as_deref())? {
                None => 1,
                Some(v) if v >= 1.0 && v.fract() == 0.0 => v as usize,
                Some(v) => {
                    return Err(FemError::input(
                        "command line",
                        format!("--cars {v}: give a whole number of carriages >= 1"),
                    ))
                }
            };
            let dt = match self.dt {
                None => 5e-4,
                Some(v) if v > 0.0 => v,
                Some(v) => {
                    return Err(FemError::input(
                        "command line",
                        format!("--dt {v}: give a time step > 0 s"),
                    ))
                }
            };
            let start = self.train_start.unwrap_or(-15.0);
            let geometry = crate::command::geometry(self.geometry.as_deref())?;
            crate::bench_train::run(&sizes, cars, steps, dt, start, geometry, out)?;
            return Ok(0);
        }
        if case == BenchCase::Floor {
            crate::floor::run(&sizes, steps, mass, out)?;
            return Ok(0);
        }
        if case == BenchCase::Sprung {
            crate::small_models::run(&sizes, steps, out)?;
            return Ok(0);
        }
        crate::bench::run(&sizes, steps, mass, out)?;
        Ok(0)
    }
}

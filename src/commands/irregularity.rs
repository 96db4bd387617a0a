//! `railfem irregularity`: a track irregularity from a standard spectrum ([`crate::irregularity`]).

use crate::command::{Command, Context};
use crate::elements::rail::geometry::irregularity::generate::PsdRequest;
use crate::elements::rail::geometry::irregularity::psd::{Component, PsdClass};
use crate::framework::FemError;
use clap::Args;
use serde::Serialize;
use std::path::PathBuf;

/// `railfem irregularity`.
#[derive(Args, Debug, Clone, PartialEq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub struct IrregularityCmd {
    /// Spectrum: fra1..fra6, german_low, german_high (required).
    #[arg(value_parser = crate::command::text(), long, value_name = "CLASS")]
    pub psd: Option<String>,
    /// Random seed [default: 1].
    #[arg(value_parser = crate::command::text(), long, value_name = "S")]
    pub seed: Option<String>,
    /// Wavelength band in m [default: 1,50].
    #[arg(value_parser = crate::command::text(), long, value_name = "MIN,MAX")]
    pub wavelengths: Option<String>,
    /// Sample spacing in m [default: MIN/8].
    #[arg(value_parser = crate::command::number(), long, value_name = "H")]
    pub step: Option<f64>,
    /// Track length in m [default: 2000].
    #[arg(value_parser = crate::command::number(), long, value_name = "L")]
    pub length: Option<f64>,
    /// Components, comma-separated (vertical, alignment, ...) [default: all of the class].
    #[arg(value_parser = crate::command::text(), long, value_name = "C1,C2,..")]
    pub components: Option<String>,
    /// Output directory [default: out/irregularity].
    #[arg(long, value_name = "DIR")]
    #[serde(serialize_with = "crate::command::opt_path_text")]
    pub out: Option<PathBuf>,
}

/// Parses a list `a,b` of numbers for `--key`.
fn pair(key: &str, v: &str) -> Result<[f64; 2], FemError> {
    let nums: Option<Vec<f64>> = v.split(',').map(|x| x.trim().parse().ok()).collect();
    match nums.as_deref() {
        Some([a, b]) if a.is_finite() && b.is_finite() => Ok([*a, *b]),
        _ => Err(FemError::input(
            "command line",
            format!("--{key} {v}: give two numbers `λmin,λmax` in m, e.g. 1,50"),
        )),
    }
}

impl Command for IrregularityCmd {
    const NAME: &'static str = "irregularity";
    const STOPS_AT_STEP: bool = true;
    fn out_dir(&self) -> Option<PathBuf> {
        crate::command::out_or(&self.out, "out/irregularity")
    }
    fn run(&self, ctx: &Context) -> Result<i32, FemError> {
        let cl = "command line";
        let name = self.psd.as_deref().ok_or_else(|| {
            FemError::input(
                cl,
                format!(
                    "`railfem irregularity` needs --psd CLASS; the spectra are: {}",
                    PsdClass::NAMES.join(", ")
                ),
            )
        })?;
        let class = PsdClass::parse(name).ok_or_else(|| {
            FemError::input(
                cl,
                format!(
                    "--psd {name} is not offered; the spectra are: {}",
                    PsdClass::NAMES.join(", ")
                ),
            )
        })?;
        let seed = match self.seed.as_deref() {
            None => 1,
            Some(v) => v
                .parse::<u64>()
                .map_err(|_| FemError::input(cl, format!("--seed {v}: give an integer ≥ 0")))?,
        };
        let wavelengths = match self.wavelengths.as_deref() {
            None => [1.0, 50.0],
            Some(v) => pair("wavelengths", v)?,
        };
        let req = PsdRequest {
            class,
            seed,
            wavelengths,
            step: self.step.unwrap_or(wavelengths[0] / 8.0),
            length: self.length.unwrap_or(2000.0),
        };
        req.validate().map_err(|m| {
            // The checks name the model-file keys; here they are options.
            let m = ["wavelengths", "step", "length"]
                .iter()
                .fold(m, |m, k| m.replace(&format!("`{k}`"), &format!("--{k}")));
            FemError::input(cl, m)
        })?;
        let components = match self.components.as_deref() {
            None => class.components().to_vec(),
            Some(list) => {
                let mut out = Vec::new();
                for n in list.split(',') {
                    let c = Component::parse(n)
                        .filter(|c| class.components().contains(c))
                        .ok_or_else(|| {
                            FemError::input(
                                cl,
                                format!(
                                    "--components: `{n}` is not given by {}; choose from {}",
                                    class.name(),
                                    class
                                        .components()
                                        .iter()
                                        .map(|c| c.name())
                                        .collect::<Vec<_>>()
                                        .join(",")
                                ),
                            )
                        })?;
                    if !out.contains(&c) {
                        out.push(c);
                    }
                }
                out
            }
        };
        let out = ctx.out();
        let reports = crate::irregularity::run(&req, &components, out)?;
        for r in &reports {
            println!(
                "{} {}: RMS {:.4} mm, target √∫S dΩ = {:.4} mm ({:+.2} %)",
                class.name(),
                r.component.name(),
                r.rms * 1e3,
                r.target_rms * 1e3,
                (r.rms / r.target_rms - 1.0) * 100.0
            );
        }
        println!(
            "irregularity.csv, psd.csv and irregularity-psd.svg in {}",
            out.display()
        );
        Ok(0)
    }
}

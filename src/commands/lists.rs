//! The listing commands, `railfem elements`, `loads`, `recorders` and `integrators`: each
//! registered kind with its documented keys (units, defaults).

use crate::command::{Command, Context};
use crate::framework::registry::ParamDoc;
use crate::framework::FemError;
use clap::Args;
use serde::Serialize;

/// Prints a registered kind and its documented keys.
fn print_kind(name: &str, description: &str, params: Vec<ParamDoc>) {
    println!("{name} — {description}");
    for p in params {
        let def = p
            .default
            .map(|d| format!(" (default {d})"))
            .unwrap_or_else(|| " (required)".into());
        println!("    {:<12} [{}]{}  {}", p.key, p.unit, def, p.doc);
    }
}

/// `railfem elements`.
#[derive(Args, Debug, Clone, PartialEq, Serialize)]
pub struct ElementsCmd {}

impl Command for ElementsCmd {
    const NAME: &'static str = "elements";
    fn run(&self, _: &Context) -> Result<i32, FemError> {
        for k in crate::framework::registry::kinds() {
            print_kind(k.name, k.description, (k.params)());
        }
        Ok(0)
    }
}

/// `railfem loads`.
#[derive(Args, Debug, Clone, PartialEq, Serialize)]
pub struct LoadsCmd {}

impl Command for LoadsCmd {
    const NAME: &'static str = "loads";
    fn run(&self, _: &Context) -> Result<i32, FemError> {
        for k in crate::framework::load_kind::kinds() {
            print_kind(k.name, k.description, (k.params)());
        }
        Ok(0)
    }
}

/// `railfem recorders`.
#[derive(Args, Debug, Clone, PartialEq, Serialize)]
pub struct RecordersCmd {}

impl Command for RecordersCmd {
    const NAME: &'static str = "recorders";
    fn run(&self, _: &Context) -> Result<i32, FemError> {
        for k in crate::framework::recorder_kind::kinds() {
            print_kind(k.name, k.description, (k.params)());
        }
        Ok(0)
    }
}

/// `railfem integrators`.
#[derive(Args, Debug, Clone, PartialEq, Serialize)]
pub struct IntegratorsCmd {}

impl Command for IntegratorsCmd {
    const NAME: &'static str = "integrators";
    fn run(&self, _: &Context) -> Result<i32, FemError> {
        print!("{}", crate::solvers::time_integrator::listing());
        Ok(0)
    }
}

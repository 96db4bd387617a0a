//! `railfem trains`: the built-in trains of the bridge check ([`crate::bridge_check`]).

use crate::command::{Command, Context};
use crate::framework::FemError;
use clap::Args;
use serde::Serialize;

/// `railfem trains`.
#[derive(Args, Debug, Clone, PartialEq, Serialize)]
pub struct TrainsCmd {}

impl Command for TrainsCmd {
    const NAME: &'static str = "trains";
    fn run(&self, _: &Context) -> Result<i32, FemError> {
        crate::bridge_check::trains_command()
    }
}

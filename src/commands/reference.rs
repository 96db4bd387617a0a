//! `railfem reference`: the book's generated reference pages ([`crate::reference`]).

use crate::command::{Command, Context};
use crate::framework::FemError;
use clap::Args;
use serde::Serialize;
use std::path::PathBuf;

/// `railfem reference`.
#[derive(Args, Debug, Clone, PartialEq, Serialize)]
pub struct ReferenceCmd {
    /// Output directory [default: docs/reference].
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
}

impl Command for ReferenceCmd {
    const NAME: &'static str = "reference";
    // No `out_dir`: the pages go into the book, without a `run.json` beside them.
    fn run(&self, _: &Context) -> Result<i32, FemError> {
        let dir = self
            .out
            .clone()
            .unwrap_or_else(|| PathBuf::from("docs/reference"));
        let n = crate::reference::write(&dir, &crate::commands::clap_command())?;
        println!("{n} reference pages in {}", dir.display());
        Ok(0)
    }
}

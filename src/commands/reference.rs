//! `railfem reference`: the book's generated reference pages ([`crate::reference`]).

use crate::command::{out_or, Command, Context};
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
    fn out_dir(&self) -> Option<PathBuf> {
        out_or(&self.out, "docs/reference")
    }
    fn run(&self, ctx: &Context) -> Result<i32, FemError> {
        let n = crate::reference::write(ctx.out())?;
        println!("{n} reference pages in {}", ctx.out().display());
        Ok(0)
    }
}

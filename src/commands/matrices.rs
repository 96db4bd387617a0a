//! `railfem matrices`: a model's K, M, C and load vector as Matrix Market files.

use crate::command::{Command, Context};
use crate::framework::FemError;
use clap::Args;
use serde::Serialize;
use std::path::PathBuf;

/// `railfem matrices`.
#[derive(Args, Debug, Clone, PartialEq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub struct MatricesCmd {
    /// The model file (TOML or JSON).
    #[arg(value_name = "MODEL")]
    #[serde(serialize_with = "crate::command::path_text")]
    pub model: PathBuf,
    /// Output directory: K.mtx, M.mtx, C.mtx, f.mtx, dofs.csv and run.json
    /// [default: out/matrices].
    #[arg(long, value_name = "DIR")]
    #[serde(serialize_with = "crate::command::opt_path_text")]
    pub out: Option<PathBuf>,
}

impl Command for MatricesCmd {
    const NAME: &'static str = "matrices";
    fn out_dir(&self) -> Option<PathBuf> {
        crate::command::out_or(&self.out, "out/matrices")
    }
    fn run(&self, ctx: &Context) -> Result<i32, FemError> {
        let path = self.model.as_path();
        let out = ctx.out();
        let n = crate::matrices::write(path, out)?;
        println!(
            "{}: {n} equations; K.mtx, M.mtx, C.mtx, f.mtx and dofs.csv in {}",
            path.display(),
            out.display()
        );
        Ok(0)
    }
}

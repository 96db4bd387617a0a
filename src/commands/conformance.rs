//! `railfem conformance`: the conformance kit on every registered element kind.

use crate::command::{Command, Context};
use crate::framework::FemError;
use clap::Args;
use serde::Serialize;

/// `railfem conformance`.
#[derive(Args, Debug, Clone, PartialEq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub struct ConformanceCmd {
    /// Check only the kinds whose name contains NAME [default: all].
    #[arg(value_parser = crate::command::text(), long, value_name = "NAME")]
    pub element: Option<String>,
}

impl Command for ConformanceCmd {
    const NAME: &'static str = "conformance";
    /// Prints the kit's table; exit code 1 if any check failed.
    fn run(&self, _: &Context) -> Result<i32, FemError> {
        let filter = self.element.as_deref();
        let report = crate::framework::conformance::check_all(filter);
        if report.results.is_empty() {
            return Err(FemError::input(
                "command line",
                match filter {
                    Some(f) => {
                        format!("no registered element type matches `{f}`; run `railfem elements`")
                    }
                    None => "no element types are registered; load a plugin with --plugin PATH"
                        .to_string(),
                },
            ));
        }
        print!("{}", report.table());
        Ok(if report.passed() { 0 } else { 1 })
    }
}

//! `railfem completions`: a shell completion script on stdout.

use crate::command::{Command, Context};
use crate::framework::FemError;
use clap::Args;
use serde::Serialize;

/// `railfem completions`.
#[derive(Args, Debug, Clone, PartialEq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub struct CompletionsCmd {
    /// The shell: bash, zsh, fish, elvish or powershell.
    #[arg(value_name = "SHELL")]
    #[serde(serialize_with = "crate::command::display_text")]
    pub shell: clap_complete::Shell,
}

impl Command for CompletionsCmd {
    const NAME: &'static str = "completions";
    fn run(&self, _: &Context) -> Result<i32, FemError> {
        clap_complete::generate(
            self.shell,
            &mut crate::commands::clap_command(),
            "railfem",
            &mut std::io::stdout(),
        );
        Ok(0)
    }
}

//! `railfem check`: validate a model file as `run` would, listing every problem.

use crate::command::{Command, Context};
use crate::framework::FemError;
use clap::Args;
use serde::Serialize;
use std::path::PathBuf;

/// `railfem check`.
#[derive(Args, Debug, Clone, PartialEq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub struct CheckCmd {
    /// The model file (TOML or JSON).
    #[arg(value_name = "MODEL")]
    #[serde(serialize_with = "crate::command::path_text")]
    pub model: PathBuf,
    /// Make the mechanism check (the run's first factorization) whatever the model's size;
    /// without it, models above 100 000 equations skip it.
    #[arg(long)]
    pub factor: bool,
}

/// Most problems `railfem check` lists.
pub const MAX_LISTED: usize = 20;

/// `check`'s mechanism check ([`crate::solvers::mechanism`]): the run's first
/// factorization, up to the size bound or at any size with `--factor`; above the bound
/// without it, the note that says it was skipped and how to force it.
fn mechanism_check(
    d: &mut crate::solvers::Driver,
    force: bool,
) -> Result<Option<String>, FemError> {
    let (n, limit) = (
        d.neq(),
        crate::solvers::mechanism::MECHANISM_CHECK_EQUATIONS,
    );
    if n > limit && !force {
        return Ok(Some(format!(
            "the mechanism check (the run's first factorization) was skipped: {n} equations is above {limit}; force it with `railfem check --factor`"
        )));
    }
    d.first_factorization().map(|()| None)
}

impl Command for CheckCmd {
    const NAME: &'static str = "check";
    fn run(&self, _: &Context) -> Result<i32, FemError> {
        let path = self.model.as_path();
        let file = path.display().to_string();
        let checked = super::run::prepare(path, true)
            // The activity window's refusals, as `run` makes them before its first step.
            .and_then(|(d, pre)| {
                crate::run_window::plan(&d, &d.model.analysis.window, &file).map(|_| (d, pre))
            })
            .and_then(|(mut d, pre)| mechanism_check(&mut d, self.factor).map(|note| (pre, note)));
        match checked {
            Ok((pre, note)) => {
                println!("{}: ok — {}", path.display(), pre.size);
                if let Some(note) = note {
                    println!("{}: {note}", path.display());
                }
                Ok(0)
            }
            Err(e) => {
                // Every problem on its own line (run stops at the first).
                let all = e.problems();
                for p in all.iter().take(MAX_LISTED) {
                    eprintln!("error: {}", p.to_string().replace('\n', " "));
                }
                if all.len() > MAX_LISTED {
                    eprintln!(
                        "error: {}: … and {} more problems; fix these first",
                        path.display(),
                        all.len() - MAX_LISTED
                    );
                }
                Ok(2)
            }
        }
    }
}

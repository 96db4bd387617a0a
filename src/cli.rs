//! The `railfem` command line: parse arguments, run a subcommand, turn any error into one
//! line and an exit code.
//!
//! Exit codes: 0 success; 2 bad input or a failed run (one line on stderr naming the file,
//! the place and the fix); 1 a check that ran and failed (the conformance kit).

use crate::framework::FemError;
use std::path::{Path, PathBuf};

/// Usage text printed by `railfem help` and on a usage error.
pub const USAGE: &str = "\
railfem — nonlinear dynamic finite elements for trains on curved, canted track

USAGE:
  railfem run MODEL [--out DIR] [--plugin PATH]...   run a model file (TOML or JSON)
  railfem check MODEL [--plugin PATH]...             validate a model file without running
  railfem elements [--plugin PATH]...                list registered element kinds and keys
  railfem conformance [--plugin PATH]... [--element NAME]
                                                     run the conformance kit on every kind
                                                     (or those whose name contains NAME);
                                                     exit 1 if a check fails
  railfem help                                       this text

Units are SI (m, kg, s, N, rad). Bad input exits with code 2 and one line naming the file,
the place and the fix.";

/// A parsed command line.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Args {
    /// The subcommand.
    pub command: String,
    /// Positional arguments after the subcommand.
    pub positional: Vec<String>,
    /// `--out DIR`.
    pub out: Option<PathBuf>,
    /// `--plugin PATH`, repeatable.
    pub plugins: Vec<PathBuf>,
    /// Other `--key value` options.
    pub options: Vec<(String, String)>,
    /// `--flag` options without value.
    pub flags: Vec<String>,
}

impl Args {
    /// Value of option `--key`, if given.
    pub fn opt(&self, key: &str) -> Option<&str> {
        self.options
            .iter()
            .rev()
            .find(|(k, _)| k == key)
            .map(|(_, v)| v.as_str())
    }

    /// Parses option `--key` as a number, with a clear error.
    pub fn num(&self, key: &str) -> Result<Option<f64>, FemError> {
        match self.opt(key) {
            None => Ok(None),
            Some(v) => v
                .parse::<f64>()
                .ok()
                .filter(|x| x.is_finite())
                .map(Some)
                .ok_or_else(|| {
                    FemError::input("command line", format!("--{key} {v}: not a finite number"))
                }),
        }
    }
}

/// Options that take no value.
const FLAGS: [&str; 4] = ["quick", "quiet", "help", "no-plot"];

/// Parses `argv` (without the program name).
pub fn parse(argv: &[String]) -> Result<Args, FemError> {
    let mut a = Args::default();
    let mut it = argv.iter();
    a.command = it.next().cloned().unwrap_or_else(|| "help".into());
    while let Some(x) = it.next() {
        if let Some(key) = x.strip_prefix("--") {
            if FLAGS.contains(&key) {
                a.flags.push(key.to_string());
                continue;
            }
            let Some(v) = it.next() else {
                return Err(FemError::input(
                    "command line",
                    format!("--{key} needs a value; see `railfem help`"),
                ));
            };
            match key {
                "out" => a.out = Some(PathBuf::from(v)),
                "plugin" => a.plugins.push(PathBuf::from(v)),
                _ => a.options.push((key.to_string(), v.clone())),
            }
        } else {
            a.positional.push(x.clone());
        }
    }
    Ok(a)
}

fn model_arg(a: &Args) -> Result<&Path, FemError> {
    a.positional.first().map(Path::new).ok_or_else(|| {
        FemError::input(
            "command line",
            format!("`railfem {}` needs a MODEL file", a.command),
        )
    })
}

/// Runs a parsed command; returns the process exit code.
pub fn run(a: &Args) -> Result<i32, FemError> {
    crate::elements::link();
    for p in &a.plugins {
        crate::framework::plugin::load(p)?;
    }
    match a.command.as_str() {
        "help" | "--help" | "-h" => {
            println!("{USAGE}");
            Ok(0)
        }
        "check" => {
            let path = model_arg(a)?;
            let model = crate::load_model(path)?;
            let driver = crate::solvers::Driver::new(model)?;
            println!(
                "{}: ok — {} nodes, {} elements, {} equations",
                path.display(),
                driver.model.nodes.len(),
                driver.model.elements.len(),
                driver.neq()
            );
            Ok(0)
        }
        "run" => {
            let path = model_arg(a)?;
            let out = a.out.clone().unwrap_or_else(|| PathBuf::from("out"));
            let model = crate::load_model(path)?;
            let mut driver = crate::solvers::Driver::new(model)?;
            let s = driver.run(Some(&out), &mut |_| {})?;
            println!(
                "{}: {} steps, {} Newton iterations, {} factorizations, {} equations, {:.3} s; results in {}",
                path.display(),
                s.steps,
                s.iterations,
                s.factorizations,
                s.equations,
                s.wall,
                out.display()
            );
            Ok(0)
        }
        "elements" => {
            for k in crate::framework::registry::kinds() {
                println!("{} — {}", k.name, k.description);
                for p in (k.params)() {
                    let def = p
                        .default
                        .map(|d| format!(" (default {d})"))
                        .unwrap_or_else(|| " (required)".into());
                    println!("    {:<12} [{}]{}  {}", p.key, p.unit, def, p.doc);
                }
            }
            Ok(0)
        }
        "conformance" => conformance(a),
        other => Err(FemError::input(
            "command line",
            format!("unknown command `{other}`; run `railfem help`"),
        )),
    }
}

/// `railfem conformance`: prints the kit's table; exit code 1 if any check failed.
fn conformance(a: &Args) -> Result<i32, FemError> {
    let report = crate::framework::conformance::check_all(a.opt("element"));
    if report.results.is_empty() {
        return Err(FemError::input(
            "command line",
            match a.opt("element") {
                Some(f) => {
                    format!("no registered element type matches `{f}`; run `railfem elements`")
                }
                None => {
                    "no element types are registered; load a plugin with --plugin PATH".to_string()
                }
            },
        ));
    }
    print!("{}", report.table());
    Ok(if report.passed() { 0 } else { 1 })
}

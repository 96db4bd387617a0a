//! A parsed command line as the commands read it: the subcommand, its positional
//! arguments, and its options by name ([`crate::cli::parse`] fills it from clap's matches).

use crate::framework::FemError;
use std::ffi::OsString;
use std::path::{Path, PathBuf};

/// A parsed command line. Paths stay `OsString`/`PathBuf` from `argv` to every message
/// (a path need not be UTF-8); every other value must be UTF-8.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Args {
    /// The subcommand.
    pub command: String,
    /// Positional arguments after the subcommand (the model file of `run` and `check`).
    pub positional: Vec<OsString>,
    /// `--out DIR`.
    pub out: Option<PathBuf>,
    /// `--plugin PATH`, repeatable.
    pub plugins: Vec<PathBuf>,
    /// Other `--key value` options whose value is text.
    pub options: Vec<(String, String)>,
    /// Options whose value is a path (fields typed `PathBuf` in [`crate::commands`]) other
    /// than `out` and `plugin`.
    pub paths: Vec<(String, PathBuf)>,
    /// `--flag` options without value.
    pub flags: Vec<String>,
    /// Text clap rendered for `--help`, `--version` or `railfem help`: printed by [`run`],
    /// which then exits 0 without running anything.
    pub message: Option<String>,
    /// `argv` as given (without the program name), for the run sidecar (`run.json`).
    pub argv: Vec<OsString>,
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

    /// Value of path option `--key` (e.g. `--quake FILE`), if given.
    pub fn path(&self, key: &str) -> Option<&Path> {
        self.paths
            .iter()
            .rev()
            .find(|(k, _)| k == key)
            .map(|(_, v)| v.as_path())
    }

    /// Whether `--flag` was given.
    pub fn flag(&self, flag: &str) -> bool {
        self.flags.iter().any(|f| f == flag)
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

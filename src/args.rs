//! A parsed command line: the typed command ([`crate::commands::Commands`]) the commands
//! run from, and beside it the command line as the user typed it (the subcommand, its
//! positional arguments, its options by name), which `run.json` records and the tests
//! compare with `argv` ([`crate::cli::parse`] fills both from clap's matches).

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
    /// Text clap rendered for `--help`, `--version` or `railfem help`: printed by [`crate::cli::run`],
    /// which then exits 0 without running anything.
    pub message: Option<String>,
    /// `argv` as given (without the program name), for the run sidecar (`run.json`).
    pub argv: Vec<OsString>,
    /// The options of every command, typed.
    pub global: crate::commands::Global,
    /// The command with its typed options (`None` for help text).
    pub cmd: Option<crate::commands::Commands>,
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
}

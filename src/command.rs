//! The contract every `railfem` command fulfils ([`Command`]), and the typed value parsers
//! its clap struct uses. A command is one clap struct in one file under `src/commands/`,
//! registered by one line in [`crate::commands`]; dispatch, the output folder, the
//! behaviour on SIGINT/SIGTERM and the options written to `run.json` all come from it.
//!
//! Values are checked where clap reads them: a number is a finite `f64`, a text is UTF-8;
//! a refusal reads `--dt abc: not a finite number` (turned into the one-line, exit-2
//! message by [`crate::cli::parse`]). What a value means (a time step > 0, a whole
//! number of carriages) is checked by the command, which names the option in its message.

use crate::framework::FemError;
use clap::builder::{OsStringValueParser, TypedValueParser};
use serde::Serializer;
use std::ffi::OsString;
use std::path::{Path, PathBuf};

/// One command of the command line: its clap struct (flags, defaults, help) and how it
/// runs. `Serialize` gives the options `run.json` records (field names in kebab case, as on
/// the command line; options not given and flags not set are left out).
pub trait Command: clap::Args + serde::Serialize {
    /// The name on the command line (`railfem NAME`).
    const NAME: &'static str;
    /// Whether the command stops at the end of its step (a time step, a load step, a case)
    /// on SIGINT/SIGTERM ([`crate::framework::interrupt`]); the others stop at once.
    const STOPS_AT_STEP: bool = false;
    /// The folder the command writes, `run.json` included: its `--out` or its default;
    /// `None` for commands that write no folder (and no `run.json`).
    fn out_dir(&self) -> Option<PathBuf> {
        None
    }
    /// Runs the command; returns the process exit code (0 done, 1 a check that ran and
    /// failed). Bad input is an `Err` ([`FemError::input`], exit code 2).
    fn run(&self, ctx: &Context) -> Result<i32, FemError>;
}

/// What a command is given besides its own options.
#[derive(Debug, Clone, Default)]
pub struct Context {
    /// The output folder as [`Command::out_dir`] resolved it.
    pub out: Option<PathBuf>,
}

impl Context {
    /// The output folder; `.` for a command without one (it writes nothing there).
    pub fn out(&self) -> &Path {
        self.out.as_deref().unwrap_or(Path::new("."))
    }
}

/// Resolves a command's `--out` against its default folder.
pub fn out_or(out: &Option<PathBuf>, default: &str) -> Option<PathBuf> {
    Some(out.clone().unwrap_or_else(|| PathBuf::from(default)))
}

/// Why clap refused a value (the text after `--key value: `).
#[derive(Debug, Clone)]
pub struct Refused(&'static str);

impl std::fmt::Display for Refused {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.0)
    }
}

impl std::error::Error for Refused {}

/// The refusal of a value that is not UTF-8.
const NOT_UTF8: Refused = Refused("not valid UTF-8; give it in plain text");

/// A UTF-8 text value (a choice, a list); other bytes are refused naming the option.
pub fn text() -> impl TypedValueParser<Value = String> {
    OsStringValueParser::new().try_map(|s: OsString| s.into_string().map_err(|_| NOT_UTF8))
}

/// A finite number (`1e4`, `-15`, `0.005`); `abc`, `nan`, `inf` and bytes that are not
/// UTF-8 are refused.
pub fn number() -> impl TypedValueParser<Value = f64> {
    OsStringValueParser::new().try_map(|s: OsString| {
        let t = s.to_str().ok_or(NOT_UTF8)?;
        t.parse::<f64>()
            .ok()
            .filter(|x| x.is_finite())
            .ok_or(Refused("not a finite number"))
    })
}

/// Serializes a path as text, byte for byte where it is UTF-8 (lossy otherwise, where
/// serde's own form would fail), for `run.json`.
pub fn path_text<S: Serializer>(p: &Path, s: S) -> Result<S::Ok, S::Error> {
    s.serialize_str(&p.to_string_lossy())
}

/// [`path_text`] of an optional path (`None` as null, left out of `run.json`).
pub fn opt_path_text<S: Serializer>(p: &Option<PathBuf>, s: S) -> Result<S::Ok, S::Error> {
    match p {
        Some(p) => path_text(p, s),
        None => s.serialize_none(),
    }
}

/// [`path_text`] of a list of paths.
pub fn paths_text<S: Serializer>(p: &[PathBuf], s: S) -> Result<S::Ok, S::Error> {
    s.collect_seq(p.iter().map(|p| p.to_string_lossy()))
}

/// The options of a command as `run.json` records them: the struct's fields that were given
/// (nulls, unset flags and empty lists left out).
pub fn options_json<C: serde::Serialize>(c: &C) -> serde_json::Map<String, serde_json::Value> {
    let mut o = match serde_json::to_value(c) {
        Ok(serde_json::Value::Object(o)) => o,
        _ => serde_json::Map::new(),
    };
    o.retain(|_, v| match v {
        serde_json::Value::Null | serde_json::Value::Bool(false) => false,
        serde_json::Value::Array(a) => !a.is_empty(),
        _ => true,
    });
    o
}

/// A whole count from a number option: `Some(n)` for a whole `v` in `[1, max]`, else the
/// refusal `--key v: fix`.
pub fn whole(key: &str, v: Option<f64>, max: f64, fix: &str) -> Result<Option<usize>, FemError> {
    match v {
        None => Ok(None),
        Some(v) if v >= 1.0 && v.fract() == 0.0 && v <= max => Ok(Some(v as usize)),
        Some(v) => Err(FemError::input(
            "command line",
            format!("--{key} {v}: {fix}"),
        )),
    }
}

/// Serializes a value by its `Display` form (a shell name).
pub fn display_text<T: std::fmt::Display, S: Serializer>(v: &T, s: S) -> Result<S::Ok, S::Error> {
    s.collect_str(v)
}

/// `--geometry linear|nonlinear` of the built-in vehicle cases [default: linear].
pub fn geometry(v: Option<&str>) -> Result<crate::framework::model::Geometry, FemError> {
    match v {
        None => Ok(Default::default()),
        Some(g) => crate::framework::model::Geometry::parse(g).map_err(|_| {
            FemError::input(
                "command line",
                format!("--geometry {g}: use linear (the default) or nonlinear"),
            )
        }),
    }
}

/// `--first-active-set committed|found`, or `default` when it is not given.
pub fn first_active_set(
    v: Option<&str>,
    default: crate::framework::model::FirstActiveSet,
) -> Result<crate::framework::model::FirstActiveSet, FemError> {
    match v {
        None => Ok(default),
        Some(w) => crate::framework::model::FirstActiveSet::parse(w).ok_or_else(|| {
            FemError::input(
                "command line",
                format!("--first-active-set {w}: use committed or found"),
            )
        }),
    }
}

/// `--polach-spin off|polach_1999` (the `moving_axle` key `polach_spin`), checked against
/// the law it belongs to: only `--tangential polach` has the term.
pub fn polach_spin(
    v: Option<&str>,
    tangential: crate::elements::rail::contact::creep::law::Tangential,
) -> Result<Option<crate::elements::rail::contact::creep::law::PolachSpin>, FemError> {
    use crate::elements::rail::contact::creep::law::Tangential;
    let Some(v) = v else {
        return Ok(None);
    };
    let spin = crate::choice::parse("command line", "--polach-spin", v)?;
    if tangential != Tangential::Polach {
        return Err(FemError::input(
            "command line",
            format!("--polach-spin {v} with --tangential {}: the spin term belongs to Polach's law; add --tangential polach or drop --polach-spin", tangential.name()),
        ));
    }
    Ok(Some(spin))
}

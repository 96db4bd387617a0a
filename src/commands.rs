//! The `railfem` command line: the global options, and the registry of commands. Each
//! command is one clap struct in its own file under `src/commands/`, implementing
//! [`Command`] (its name, output folder, signal behaviour and `run`); the
//! `commands!` list below registers it, in the order `railfem help` lists them. From these
//! declarations clap makes each command's `--help`, the shell completions (`railfem
//! completions bash|zsh|fish`) and the refusal of an unknown or misplaced option (with the
//! nearest valid one).
//!
//! Adding a command: a file `src/commands/NAME.rs` with its struct (a doc comment with unit
//! and default on every option, `value_parser = crate::command::number()` for a number,
//! `crate::command::text()` for a text) and its `impl Command`; then its `mod` line and
//! its line in `commands!` here.

use crate::command::{Command, Context};
use crate::framework::FemError;
use clap::{Args as ClapArgs, Parser, Subcommand};
use serde::Serialize;
use std::path::PathBuf;

/// `railfem --version`: the package version and the git revision it was built from.
pub const VERSION: &str = concat!(
    env!("CARGO_PKG_VERSION"),
    " (git ",
    env!("RAILFEM_GIT_REVISION"),
    ")"
);

/// The whole command line.
#[derive(Parser, Debug, Clone, PartialEq)]
#[command(
    name = "railfem",
    version = VERSION,
    about = "Nonlinear dynamic finite elements for trains on curved, canted track",
    long_about = "Nonlinear dynamic finite elements for trains on curved, canted track \
                  (Ju & Ro 2021). Units are SI throughout: m, kg, s, N, rad.",
    after_help = "Bad input exits with code 2 and one line naming the file, the place and the \
                  fix (docs/robustness.md). An interrupted run (Ctrl-C, SIGTERM) stops at the \
                  end of its step, keeps whole CSV lines, marks run.json and exits with 130.",
    max_term_width = 100
)]
pub struct Cli {
    /// Options every command accepts.
    #[command(flatten)]
    pub global: Global,
    /// The command; none prints this help.
    #[command(subcommand)]
    pub command: Option<Commands>,
}

/// Options of every command.
#[derive(ClapArgs, Debug, Clone, PartialEq, Default, Serialize)]
#[serde(rename_all = "kebab-case")]
pub struct Global {
    /// Load an element plugin (a shared library; repeatable).
    #[arg(
        long,
        global = true,
        help_heading = "Options of every command",
        value_name = "PATH"
    )]
    #[serde(serialize_with = "crate::command::paths_text")]
    pub plugin: Vec<PathBuf>,
    /// Memory a model may be estimated to need, in bytes (e.g. 8G) [default: half the
    /// available memory]; overrides a model file's `[limits] max_memory`.
    #[arg(
        long,
        global = true,
        help_heading = "Options of every command",
        value_name = "BYTES",
        value_parser = crate::command::text()
    )]
    pub max_memory: Option<String>,
    /// Most time or load steps of an analysis [default: 1e7; at most 1e9]; overrides
    /// `[limits] max_steps`.
    #[arg(
        long,
        global = true,
        help_heading = "Options of every command",
        value_name = "N",
        value_parser = crate::command::text()
    )]
    pub max_steps: Option<String>,
    /// No progress bar and no progress lines on stderr.
    #[arg(
        long,
        short = 'q',
        global = true,
        help_heading = "Options of every command"
    )]
    pub quiet: bool,
}

/// The clap command with the settings every subcommand shares: a value may start with `-`
/// (`--penalty -1` reaches the command, which says why it is refused).
pub fn clap_command() -> clap::Command {
    <Cli as clap::CommandFactory>::command().mut_subcommands(|c| c.allow_negative_numbers(true))
}

/// Registers the commands: one line per command, `Variant(module::Struct)` with its doc
/// comment (the summary `railfem help` shows). Generates the [`Commands`] enum clap parses
/// into, and its dispatch to each command's [`Command`] implementation.
macro_rules! commands {
    ($($(#[$doc:meta])* $variant:ident($module:ident::$ty:ident),)*) => {
        $(pub use $module::$ty;)*

        /// The commands, as registered.
        // Parsed once per process: the size of the largest command's options does not matter.
        #[allow(clippy::large_enum_variant)]
        #[derive(Subcommand, Debug, Clone, PartialEq)]
        pub enum Commands {
            $($(#[$doc])* #[command(name = <$ty as Command>::NAME)] $variant($ty),)*
        }

        impl Commands {
            /// The command's name (`railfem NAME`).
            pub fn name(&self) -> &'static str {
                match self {
                    $(Self::$variant(_) => <$ty as Command>::NAME,)*
                }
            }

            /// Whether the command stops at the end of a step on SIGINT/SIGTERM.
            pub fn stops_at_step(&self) -> bool {
                match self {
                    $(Self::$variant(_) => <$ty as Command>::STOPS_AT_STEP,)*
                }
            }

            /// The folder the command writes (its `--out` or default), if any.
            pub fn out_dir(&self) -> Option<PathBuf> {
                match self {
                    $(Self::$variant(c) => c.out_dir(),)*
                }
            }

            /// The command's options as `run.json` records them.
            pub fn options(&self) -> serde_json::Map<String, serde_json::Value> {
                match self {
                    $(Self::$variant(c) => crate::command::options_json(c),)*
                }
            }

            /// Runs the command.
            pub fn run(&self, ctx: &Context) -> Result<i32, FemError> {
                match self {
                    $(Self::$variant(c) => c.run(ctx),)*
                }
            }
        }
    };
}

commands! {
    /// Run a model file (TOML or JSON); recorders write CSV into --out.
    Run(run::RunCmd),
    /// Validate a model file as `run` would, without running: its size and every problem.
    Check(check::CheckCmd),
    /// List the registered element kinds and their keys (units, defaults).
    Elements(lists::ElementsCmd),
    /// List the registered load kinds (`[[load]] type`) and their keys (units, defaults).
    Loads(lists::LoadsCmd),
    /// List the registered recorder kinds (`[[recorder]] type`) and their keys (units,
    /// defaults).
    Recorders(lists::RecordersCmd),
    /// List the registered time integrators and their keys (units, defaults).
    Integrators(lists::IntegratorsCmd),
    /// The paper's curved-track validation (Fig. 6): FE against theory.
    Curve(curve::CurveCmd),
    /// Critical radius, FE against theory (Figs. 7, 9); `--sweep` for a whole figure.
    CriticalRadius(critical_radius::CriticalCmd),
    /// Run the conformance kit on every element kind; exit 1 if a check fails.
    Conformance(conformance::ConformanceCmd),
    /// The paper's five-segment track: track.csv and track.svg.
    Track(track::TrackCmd),
    /// Time linear transient steps per DOF count (bench.md, bench.csv), or the
    /// train-bridge model by phase (`--case train-bridge`).
    Bench(bench::BenchCmd),
    /// A train of sks700 carriages over a viaduct of simply supported spans.
    TrainBridge(train_bridge::TrainBridgeCmd),
    /// The numerical stress suite: one table row per case (docs/stability.md).
    Stress(stress::StressCmd),
    /// Run time against error over dt, mesh and integrator: pareto.csv and pareto-*.svg.
    Pareto(pareto::ParetoCmd),
    /// A track irregularity from a standard spectrum: irregularity.csv, psd.csv and
    /// irregularity-psd.svg (Welch estimate vs target).
    Irregularity(irregularity::IrregularityCmd),
    /// Write a model's K (tangent at the reference state), M and C (constant parts) and its
    /// load vector as Matrix Market files, with the DOF map (docs/matrices.md).
    Matrices(matrices::MatricesCmd),
    /// Run a parameter study: a base case over the Cartesian product of a plan's axes, on
    /// threads or MPI ranks; study.csv, study.json, study.svg (docs/study.md).
    Study(study::StudyCmd),
    /// The EN 1991-2 dynamic check of a railway bridge: HSLM and user trains over a speed
    /// range; envelope.csv, figures, report.md (docs/bridge-check.md).
    BridgeCheck(bridge_check::BridgeCheckCmd),
    /// List the built-in trains (HSLM-A1…A10, HSLM-B): axle counts, lengths, loads.
    Trains(trains::TrainsCmd),
    /// Running-safety and track-loading assessment of a run's wheel forces (EN 14363):
    /// assessment.csv, assessment-summary.csv, assessment.svg (docs/assessment.md).
    Assess(assess::AssessCmd),
    /// Wheel–rail contact of a wheelset on straight track over a lateral shift: contact
    /// points, rolling radii, contact angles, Δr(y), equivalent conicity, Hertz ellipses,
    /// creepages and creep forces; contact.csv, conicity.csv, contact.svg
    /// (docs/contact-tool.md).
    Contact(contact::ContactCmd),
    /// Write the book's generated reference pages (elements, loads, recorders, integrators,
    /// this command line) into --out.
    Reference(reference::ReferenceCmd),
    /// Print a shell completion script (e.g. `railfem completions bash > ~/.local/share/bash-completion/completions/railfem`).
    Completions(completions::CompletionsCmd),
}
mod assess;
mod bench;
mod bridge_check;
mod check;
mod completions;
mod conformance;
mod contact;
mod critical_radius;
mod curve;
mod irregularity;
mod lists;
mod matrices;
mod pareto;
mod reference;
mod run;
mod stress;
mod study;
mod track;
mod train_bridge;
mod trains;

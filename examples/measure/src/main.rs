//! `railfem-measure`: the measurements behind the railfem project's own claims, kept out of
//! the published crates (docs/performance.md says which claim each one backs).
//!
//! - `export DIR`: the benchmark beam of `railfem bench` written out for another code to
//!   rerun, with railfem's answer and timing ([`export`]; `scripts/opensees_compare.sh`);
//! - `peer FILE`: railfem's moving-force grid ([`railfem::pareto`]) beside another code's
//!   runs of the same case (OpenSees: `scripts/opensees_compare.sh pareto`), and the
//!   wall-time ratio at equal error ([`peer`]);
//! - `retime`, `retime-at H:DT,..`: the train–bridge grid's 1 % and 5 % picks (or given
//!   runs) timed again back to back, in turn, with the load average of every round
//!   ([`retime`]);
//! - `threshold`: dense against sparse factorization by size, the table the solvers' dense
//!   limit was chosen from ([`threshold`]);
//! - `window-front`, `far-field-front`: run time against error of the train–bridge model
//!   with the activity window (no ground motion) or the reduced far field (the synthetic
//!   record) beside full runs ([`window_front`]).
//!
//! The commands users run to time their own machine and model (`railfem bench`, `railfem
//! pareto`, `railfem stress`) stay in `railfem`. This crate depends on `railfem`'s library
//! and is never a dependency of it. Bad input is one line naming the option or file and
//! the fix, exit code 2, as in `railfem`.
#![deny(missing_docs)]

mod export;
mod load_average;
mod peer;
mod retime;
mod threshold;
mod window_front;

use clap::{Args, Parser, Subcommand};
use railfem::framework::FemError;
use std::path::PathBuf;

/// The command line.
#[derive(Parser, Debug)]
#[command(
    name = "railfem-measure",
    version,
    about = "The railfem project's own measurements: peer harnesses, re-timing, thresholds",
    max_term_width = 100
)]
struct Cli {
    /// What to measure.
    #[command(subcommand)]
    command: Measure,
}

/// The measurements.
#[derive(Subcommand, Debug)]
enum Measure {
    /// Write the benchmark beam of `railfem bench`, its load vectors and railfem's answer
    /// per size into DIR/dofN (for scripts/opensees_compare.sh), timing railfem's run.
    Export(ExportCmd),
    /// railfem's Pareto grid (with the force case) beside a peer code's runs of the force
    /// case: pareto-force.svg with both, pareto-peers.md with the wall-time ratio at equal
    /// error.
    Peer(PeerCmd),
    /// Run (or read) the train–bridge Pareto grid, then time its cheapest generalized-α runs
    /// within 5 % and 1 % and their neighbours again, back to back, in turn
    /// (pareto-train-bridge-retime.md).
    Retime(RetimeCmd),
    /// Time the given train–bridge runs (generalized-α, partitioned) back to back, in turn,
    /// without the grid (pareto-train-bridge-retime.md).
    RetimeAt(RetimeAtCmd),
    /// Dense LU against the sparse direct solver by size on two model families
    /// (threshold.md): where the dense solver stops paying.
    Threshold(ThresholdCmd),
    /// Run time against error of the train–bridge model, windowed runs beside full runs,
    /// on 3 carriages over 30 spans (window-front.csv, window-front.svg).
    WindowFront(WindowFrontCmd),
    /// The same under the synthetic ground motion, runs with the reduced far field beside
    /// full runs (far-field-front.csv, far-field-front.svg).
    FarFieldFront(WindowFrontCmd),
}

/// `railfem-measure export`.
#[derive(Args, Debug)]
struct ExportCmd {
    /// Output directory: one folder dofN per size.
    #[arg(value_name = "DIR")]
    dir: PathBuf,
    /// DOF counts, comma-separated [default: 1e4,1e5,1e6].
    #[arg(long, value_name = "N1,N2,..")]
    sizes: Option<String>,
    /// Time steps per size [default: 20].
    #[arg(long, value_name = "N", value_parser = railfem::command::number())]
    steps: Option<f64>,
    /// Mass matrix: consistent (cubic Hermite, as OpenSees -cMass) or lumped (rho*A*L/2
    /// per node and translation, as OpenSees' elasticBeamColumn default) [default:
    /// consistent].
    #[arg(long, value_name = "consistent|lumped")]
    mass: Option<String>,
}

/// `railfem-measure peer`.
// The doc comments are the --help text too, where `[s]` is a unit, not a link.
#[allow(rustdoc::broken_intra_doc_links)]
#[derive(Args, Debug)]
struct PeerCmd {
    /// The peer code's runs of the force case (CSV: peer, elements, dt [s], steps, wall [s],
    /// error [-]; scripts/opensees_compare.py --pareto writes it).
    #[arg(value_name = "FILE")]
    file: PathBuf,
    /// railfem's cases, comma-separated, from force, sprung, curve; force is needed
    /// [default: force].
    #[arg(long, value_name = "force,sprung,curve")]
    cases: Option<String>,
    /// Output directory [default: out/pareto-peer].
    #[arg(long, value_name = "DIR")]
    out: Option<PathBuf>,
}

/// `railfem-measure retime`.
#[derive(Args, Debug)]
struct RetimeCmd {
    /// Rounds: every run once per round, in turn [default: 1; at most 100].
    #[arg(long, value_name = "N")]
    rounds: Option<String>,
    /// Output directory, the grid's (`railfem pareto --cases train-bridge --out DIR`):
    /// runs already there are read, not computed again [default: out/pareto].
    #[arg(long, value_name = "DIR")]
    out: Option<PathBuf>,
    /// Compute no grid run: evaluate the runs already in --out, then re-time.
    #[arg(long)]
    existing: bool,
}

/// `railfem-measure retime-at`.
#[derive(Args, Debug)]
struct RetimeAtCmd {
    /// The runs: element length in m and time step in s, `H:DT`, comma-separated (e.g.
    /// 0.3125:1e-3,0.625:4e-3).
    #[arg(value_name = "H:DT,H:DT,..")]
    at: String,
    /// Rounds: every run once per round, in turn [default: 1; at most 100].
    #[arg(long, value_name = "N")]
    rounds: Option<String>,
    /// Output directory [default: out/pareto].
    #[arg(long, value_name = "DIR")]
    out: Option<PathBuf>,
}

/// `railfem-measure threshold`.
#[derive(Args, Debug)]
struct ThresholdCmd {
    /// Output directory [default: out/threshold].
    #[arg(long, value_name = "DIR")]
    out: Option<PathBuf>,
}

/// `railfem-measure window-front` and `far-field-front`.
#[derive(Args, Debug)]
struct WindowFrontCmd {
    /// Output directory: the runs in DIR/runs (read, not run again, when there), STEM.csv
    /// and STEM.svg [default: out/STEM], STEM the command's name.
    #[arg(long, value_name = "DIR")]
    out: Option<PathBuf>,
}

/// `--rounds N`: a whole number from 1 to 100, 1 when not given.
fn rounds(given: Option<&str>) -> Result<usize, FemError> {
    let Some(r) = given else {
        return Ok(1);
    };
    match r.trim().parse::<f64>() {
        Ok(v) if (1.0..=100.0).contains(&v) && v.fract() == 0.0 => Ok(v as usize),
        _ => Err(FemError::input(
            "command line",
            format!("--rounds {r}: give a whole number of rounds, 1 to 100"),
        )),
    }
}

/// `--out`, or `default`.
fn out(given: &Option<PathBuf>, default: &str) -> PathBuf {
    given.clone().unwrap_or_else(|| PathBuf::from(default))
}

impl ExportCmd {
    fn run(&self) -> Result<(), FemError> {
        let sizes = railfem::bench::sizes(self.sizes.as_deref())?;
        let steps = railfem::bench::steps(self.steps)?;
        let mass = match self.mass.as_deref() {
            None => railfem::bench::BenchMass::Consistent,
            Some(m) => railfem::choice::parse("command line", "--mass", m)?,
        };
        // One directory per size: the model, the load vectors and railfem's answer, for
        // scripts/opensees_compare.py.
        for &n in &sizes {
            let sub = self.dir.join(format!("dof{n}"));
            let r = export::export(n, steps, mass, &sub)?;
            println!(
                "export: {} equations, {} steps, first step {:.3} ms, then {:.3} ms/step; written to {}",
                r.equations,
                r.steps,
                r.first_step * 1e3,
                r.per_step * 1e3,
                sub.display()
            );
        }
        Ok(())
    }
}

impl PeerCmd {
    fn run(&self) -> Result<(), FemError> {
        let mut grid = railfem::pareto::Grid {
            cases: vec!["force".to_string()],
            ..Default::default()
        };
        if let Some(c) = &self.cases {
            grid.cases = railfem::pareto::parse_cases(c, &railfem::pareto::CASES)?;
        }
        if !grid.cases.iter().any(|c| c == "force") {
            return Err(FemError::input(
                "command line",
                format!(
                    "--cases {}: the peer runs are of the force case; add force to --cases",
                    grid.cases.join(",")
                ),
            ));
        }
        // The peer file is read (and refused) before the grid runs for minutes.
        let peers = peer::read_peer_csv(&self.file)?;
        let out = out(&self.out, "out/pareto-peer");
        eprintln!("load average at start: {}", load_average::loadavg());
        let runs = railfem::pareto::run(&grid, &out)?;
        eprintln!("load average at end: {}", load_average::loadavg());
        peer::write(&runs, &peers, &out)?;
        println!("railfem-measure peer: results in {}", out.display());
        Ok(())
    }
}

impl RetimeCmd {
    fn run(&self) -> Result<(), FemError> {
        let rounds = rounds(self.rounds.as_deref())?;
        let out = out(&self.out, "out/pareto");
        let tb = railfem::pareto_train::TbGrid {
            existing_only: self.existing,
            ..Default::default()
        };
        eprintln!("load average at start: {}", load_average::loadavg());
        let runs = railfem::pareto_train::run(&tb, &out)?;
        eprintln!("load average after the grid: {}", load_average::loadavg());
        retime::run(&tb, &runs, rounds, &out)?;
        println!("railfem-measure retime: results in {}", out.display());
        Ok(())
    }
}

impl RetimeAtCmd {
    fn run(&self) -> Result<(), FemError> {
        let at = retime::parse_at(&self.at)?;
        let rounds = rounds(self.rounds.as_deref())?;
        let out = out(&self.out, "out/pareto");
        retime::run_at(&at, rounds, &out)?;
        println!("railfem-measure retime-at: results in {}", out.display());
        Ok(())
    }
}

impl ThresholdCmd {
    fn run(&self) -> Result<(), FemError> {
        let out = out(&self.out, "out/threshold");
        eprintln!("load average at start: {}", load_average::loadavg());
        threshold::run(&out)?;
        eprintln!("load average at end: {}", load_average::loadavg());
        Ok(())
    }
}

impl WindowFrontCmd {
    fn run(&self, scene: window_front::Scene) -> Result<(), FemError> {
        let stem = scene.stem();
        let out = out(&self.out, &format!("out/{stem}"));
        eprintln!("load average at start: {}", load_average::loadavg());
        let points = window_front::measure(&window_front::default_set(scene), &out)?;
        eprintln!("load average at end: {}", load_average::loadavg());
        print!("{}", window_front::csv(scene, &points));
        println!("railfem-measure {stem}: results in {}", out.display());
        Ok(())
    }
}

/// Parses the command line and runs the measurement; the process exit code.
fn main_code(argv: Vec<std::ffi::OsString>) -> i32 {
    let cli = match Cli::try_parse_from(argv) {
        Ok(c) => c,
        Err(e) => {
            use clap::error::ErrorKind as K;
            if matches!(e.kind(), K::DisplayHelp | K::DisplayVersion) {
                print!("{}", e.render());
                return 0;
            }
            // clap's own report is several lines (usage, hint); its first line says what is
            // wrong and names the argument.
            let text = e.render().to_string();
            eprintln!(
                "{}",
                text.lines().next().unwrap_or("error: bad command line")
            );
            return 2;
        }
    };
    // SIGINT/SIGTERM: the run in progress stops at the end of its step; a shared grid's
    // lock files are removed on the way out.
    let _ = ctrlc::set_handler(railfem::framework::interrupt::request);
    let result = match &cli.command {
        Measure::Export(c) => c.run(),
        Measure::Peer(c) => c.run(),
        Measure::Retime(c) => c.run(),
        Measure::RetimeAt(c) => c.run(),
        Measure::Threshold(c) => c.run(),
        Measure::WindowFront(c) => c.run(window_front::Scene::Still),
        Measure::FarFieldFront(c) => c.run(window_front::Scene::Quake),
    };
    match result {
        Ok(()) => 0,
        Err(e @ (FemError::Interrupted { .. } | FemError::InterruptedAfter { .. })) => {
            eprintln!("railfem-measure: {e}");
            130
        }
        Err(e) => {
            eprintln!("error: {}", e.to_string().replace('\n', " "));
            2
        }
    }
}

fn main() {
    std::process::exit(main_code(std::env::args_os().collect()));
}

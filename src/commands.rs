//! The grammar of the `railfem` command line, declared with clap's derive: every command,
//! every option with its value name, unit and default. From these declarations clap makes
//! each command's `--help`, the shell completions (`railfem completions bash|zsh|fish`) and
//! the refusal of an unknown or misplaced option (with the nearest valid one).
//!
//! The values themselves reach the commands through [`crate::args::Args`], built generically
//! from clap's matches ([`crate::cli::parse`]): an option's value stays the text the user
//! typed until the command checks it, so every command keeps its own one-line messages
//! (`--dt -1: give a time step > 0 s`, docs/robustness.md). Adding an option is therefore
//! one field here (a doc comment with unit and default, a `long` name) and one read
//! (`a.num("key")`, `a.opt`, `a.path`, `a.flag`) in the command. Fields typed `PathBuf` are
//! paths (kept byte for byte, UTF-8 or not); `bool` fields are flags; `OsString` fields are
//! text, checked for UTF-8 by the parser so that the message names the option.
//!
//! The fields are never read from these structs (the matches are), hence `dead_code` allowed.
// The enum is a declaration (never built at run time), so its variant sizes do not matter.
#![allow(dead_code, clippy::large_enum_variant)]

use clap::{Args as ClapArgs, Parser, Subcommand};
use std::ffi::OsString;
use std::path::PathBuf;

/// `railfem --version`: the package version and the git revision it was built from.
pub const VERSION: &str = concat!(
    env!("CARGO_PKG_VERSION"),
    " (git ",
    env!("RAILFEM_GIT_REVISION"),
    ")"
);

/// The whole command line.
#[derive(Parser, Debug)]
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
    pub command: Option<Command>,
}

/// Options of every command.
#[derive(ClapArgs, Debug)]
pub struct Global {
    /// Load an element plugin (a shared library; repeatable).
    #[arg(
        long,
        global = true,
        help_heading = "Options of every command",
        value_name = "PATH"
    )]
    pub plugin: Vec<PathBuf>,
    /// Memory a model may be estimated to need, in bytes (e.g. 8G) [default: half the
    /// available memory]; overrides a model file's `[limits] max_memory`.
    #[arg(
        long,
        global = true,
        help_heading = "Options of every command",
        value_name = "BYTES"
    )]
    pub max_memory: Option<OsString>,
    /// Most time or load steps of an analysis [default: 1e7; at most 1e9]; overrides
    /// `[limits] max_steps`.
    #[arg(
        long,
        global = true,
        help_heading = "Options of every command",
        value_name = "N"
    )]
    pub max_steps: Option<OsString>,
    /// No progress bar and no progress lines on stderr.
    #[arg(
        long,
        short = 'q',
        global = true,
        help_heading = "Options of every command"
    )]
    pub quiet: bool,
}

/// The commands.
#[derive(Subcommand, Debug)]
pub enum Command {
    /// Run a model file (TOML or JSON); recorders write CSV into --out.
    Run(RunCmd),
    /// Validate a model file as `run` would, without running: its size and every problem.
    Check(CheckCmd),
    /// List the registered element kinds and their keys (units, defaults).
    Elements,
    /// List the registered load kinds (`[[load]] type`) and their keys (units, defaults).
    Loads,
    /// List the registered recorder kinds (`[[recorder]] type`) and their keys (units,
    /// defaults).
    Recorders,
    /// List the registered time integrators and their keys (units, defaults).
    Integrators,
    /// The paper's curved-track validation (Fig. 6): FE against theory.
    Curve(CurveCmd),
    /// Critical radius, FE against theory (Figs. 7, 9); `--sweep` for a whole figure.
    CriticalRadius(CriticalCmd),
    /// Run the conformance kit on every element kind; exit 1 if a check fails.
    Conformance(ConformanceCmd),
    /// The paper's five-segment track: track.csv and track.svg.
    Track(TrackCmd),
    /// Time linear transient steps per DOF count (bench.md, bench.csv), the train-bridge
    /// model by phase (`--case train-bridge`), or export the benchmark (`--export DIR`).
    Bench(BenchCmd),
    /// A train of sks700 carriages over a viaduct of simply supported spans.
    TrainBridge(TrainBridgeCmd),
    /// The numerical stress suite: one table row per case (docs/stability.md).
    Stress(StressCmd),
    /// Run time against error over dt, mesh and integrator: pareto.csv and pareto-*.svg.
    Pareto(ParetoCmd),
    /// A track irregularity from a standard spectrum: irregularity.csv, psd.csv and
    /// irregularity-psd.svg (Welch estimate vs target).
    Irregularity(IrregularityCmd),
    /// Write a model's K (tangent at the reference state), M and C (constant parts) and its
    /// load vector as Matrix Market files, with the DOF map (docs/matrices.md).
    Matrices(MatricesCmd),
    /// Run a parameter study: a base case over the Cartesian product of a plan's axes, on
    /// threads or MPI ranks; study.csv, study.json, study.svg (docs/scale-out.md).
    Study(StudyCmd),
    /// The EN 1991-2 dynamic check of a railway bridge: HSLM and user trains over a speed
    /// range; envelope.csv, figures, report.md (docs/bridge-check.md).
    BridgeCheck(BridgeCheckCmd),
    /// List the built-in trains (HSLM-A1…A10, HSLM-B): axle counts, lengths, loads.
    Trains,
    /// Running-safety and track-loading assessment of a run's wheel forces (EN 14363):
    /// assessment.csv, assessment-summary.csv, assessment.svg (docs/assessment.md).
    Assess(AssessCmd),
    /// Wheel–rail contact of a wheelset on straight track over a lateral shift: contact
    /// points, rolling radii, contact angles, Δr(y), equivalent conicity, Hertz ellipses,
    /// creepages and creep forces; contact.csv, conicity.csv, contact.svg
    /// (docs/contact-tool.md).
    Contact(ContactCmd),
    /// Print a shell completion script (e.g. `railfem completions bash > ~/.local/share/bash-completion/completions/railfem`).
    Completions(CompletionsCmd),
}

/// `railfem run`.
#[derive(ClapArgs, Debug)]
pub struct RunCmd {
    /// The model file (TOML or JSON).
    #[arg(value_name = "MODEL")]
    pub model: PathBuf,
    /// Output directory of the recorders and run.json [default: out].
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Assess the run's wheel forces afterwards with the defaults of `railfem assess`.
    #[arg(long)]
    pub assess: bool,
}

/// `railfem assess`.
#[derive(ClapArgs, Debug)]
pub struct AssessCmd {
    /// The output directory of a run (railfem run, curve, train-bridge).
    #[arg(value_name = "RUN_DIR")]
    pub run_dir: PathBuf,
    /// Where to write the assessment [default: RUN_DIR].
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Speed in m/s, to measure distance as V·t where no station was recorded [default:
    /// none, the recorded station].
    #[arg(long, value_name = "V")]
    pub speed: Option<OsString>,
    /// Static wheel load Q0 in N [default: each wheelset's mean wheel load over the run].
    #[arg(long, value_name = "N")]
    pub q0: Option<OsString>,
    /// Low-pass cut-off of Y and Q in Hz [default: 20].
    #[arg(long, value_name = "HZ")]
    pub cutoff: Option<OsString>,
    /// Window of the sliding means of Y/Q and ΣY in m [default: 2].
    #[arg(long, value_name = "M")]
    pub window: Option<OsString>,
    /// Percentile of the quasi-static values over the section, in % [default: 50].
    #[arg(long, value_name = "P")]
    pub qst_percentile: Option<OsString>,
    /// Percentile of the maximum values, in % [default: 99.85].
    #[arg(long, value_name = "P")]
    pub max_percentile: Option<OsString>,
    /// First station of the quasi-static section in m [default: start of the run].
    #[arg(long, value_name = "S")]
    pub from: Option<OsString>,
    /// Last station of the quasi-static section in m [default: end of the run].
    #[arg(long, value_name = "S")]
    pub to: Option<OsString>,
    /// Flange angle of Nadal's limit in degrees [default: 70].
    #[arg(long, value_name = "DEG")]
    pub flange_angle: Option<OsString>,
    /// Friction coefficient of Nadal's limit [default: 0.36].
    #[arg(long, value_name = "MU")]
    pub nadal_mu: Option<OsString>,
    /// Y/Q limit given directly instead of Nadal's, e.g. 0.8 for R ≥ 250 m [default:
    /// Nadal's, 1.20].
    #[arg(long, value_name = "L")]
    pub yq_limit: Option<OsString>,
    /// Prud'homme's factor α: 1.0 passenger vehicles, 0.85 freight wagons [default: 1.0].
    #[arg(long, value_name = "A")]
    pub alpha: Option<OsString>,
}

/// `railfem contact`.
#[derive(ClapArgs, Debug)]
pub struct ContactCmd {
    /// Output directory [default: out-contact].
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Built-in profiles: s1002-60e1 or mbench (the Manchester contact benchmark's)
    /// [default: s1002-60e1].
    #[arg(long, value_name = "SET")]
    pub profiles: Option<OsString>,
    /// Wheel profile CSV (with --rail), instead of the built-in profiles.
    #[arg(long, value_name = "FILE")]
    pub wheel: Option<PathBuf>,
    /// Rail profile CSV, upright (with --wheel).
    #[arg(long, value_name = "FILE")]
    pub rail: Option<PathBuf>,
    /// Rail inclination of 60E1 or a CSV rail: 1:40, 1:20 or none [default: 1:40].
    #[arg(long, value_name = "I")]
    pub inclination: Option<OsString>,
    /// Track gauge in m, at 14 mm below the rail top [default: 1.435].
    #[arg(long, value_name = "M")]
    pub gauge: Option<OsString>,
    /// Back-to-back distance of the wheels in m [default: 1.360].
    #[arg(long, value_name = "M")]
    pub back_to_back: Option<OsString>,
    /// Nominal rolling radius in m [default: 0.46].
    #[arg(long, value_name = "M")]
    pub radius: Option<OsString>,
    /// One lateral shift of the axle centre in m (positive to the left) instead of a sweep
    /// [default: none, the sweep].
    #[arg(long, value_name = "M")]
    pub y: Option<OsString>,
    /// Sweep of the lateral shift from 0 to this value in m [default: 0.01].
    #[arg(long, value_name = "M")]
    pub y_max: Option<OsString>,
    /// Step of the sweep in m [default: 0.0005].
    #[arg(long, value_name = "M")]
    pub y_step: Option<OsString>,
    /// Yaw angle in rad, for the lateral creepage [default: 0].
    #[arg(long, value_name = "RAD")]
    pub yaw: Option<OsString>,
    /// Yaw per lateral shift in rad/m, added to --yaw (Manchester benchmark: 2.4) [default: 0].
    #[arg(long, value_name = "RAD/M")]
    pub yaw_per_shift: Option<OsString>,
    /// Pitch rate of the wheelset in rad/s [default: free rolling, speed/radius].
    #[arg(long, value_name = "RAD/S")]
    pub pitch_rate: Option<OsString>,
    /// Normal load from the vertical load with the lateral creep force of a law: none
    /// (N = Q/cos δ), kalker_linear, polach or fastsim [default: fastsim].
    #[arg(long, value_name = "LAW")]
    pub balance: Option<OsString>,
    /// Vertical load on each wheel in N [default: 50000].
    #[arg(long, value_name = "N")]
    pub load: Option<OsString>,
    /// Speed in m/s [default: 20].
    #[arg(long, value_name = "V")]
    pub speed: Option<OsString>,
    /// Friction coefficient [default: 0.3].
    #[arg(long, value_name = "MU")]
    pub mu: Option<OsString>,
    /// Young's modulus of wheel and rail in Pa [default: 2.1e11].
    #[arg(long, value_name = "PA")]
    pub young: Option<OsString>,
    /// Poisson's ratio of wheel and rail [default: 0.28].
    #[arg(long, value_name = "NU")]
    pub poisson: Option<OsString>,
}

/// `railfem matrices`.
#[derive(ClapArgs, Debug)]
pub struct MatricesCmd {
    /// The model file (TOML or JSON).
    #[arg(value_name = "MODEL")]
    pub model: PathBuf,
    /// Output directory: K.mtx, M.mtx, C.mtx, f.mtx, dofs.csv and run.json
    /// [default: out/matrices].
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
}

/// `railfem check`.
#[derive(ClapArgs, Debug)]
pub struct CheckCmd {
    /// The model file (TOML or JSON).
    #[arg(value_name = "MODEL")]
    pub model: PathBuf,
    /// Make the mechanism check (the run's first factorization) whatever the model's size;
    /// without it, models above 100 000 equations skip it.
    #[arg(long)]
    pub factor: bool,
}

/// `railfem curve`.
#[derive(ClapArgs, Debug)]
pub struct CurveCmd {
    /// Output directory: curve.csv, figures, run.json [default: out/curve].
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Arc radius R in m [default: 6250].
    #[arg(long, value_name = "R")]
    pub radius: Option<OsString>,
    /// Cant parameter Ct in m (cant θ = Ct/R, Eq. 21) [default: 200].
    #[arg(long, value_name = "CT")]
    pub ct: Option<OsString>,
    /// Train speed V in m/s [default: 80].
    #[arg(long, value_name = "V")]
    pub speed: Option<OsString>,
    /// Wheel-rail friction coefficient μ [default: 0.3].
    #[arg(long, value_name = "MU")]
    pub mu: Option<OsString>,
    /// Time step in s [default: 0.01].
    #[arg(long, value_name = "DT")]
    pub dt: Option<OsString>,
    /// Contact penalty stiffness in N/m [default: 1e10].
    #[arg(long, value_name = "K")]
    pub penalty: Option<OsString>,
    /// Duration in s [default: 0 = the whole track].
    #[arg(long, value_name = "T")]
    pub duration: Option<OsString>,
    /// Write a VTK frame every N steps [default: 0 = none].
    #[arg(long, value_name = "EVERY")]
    pub vtk: Option<OsString>,
    /// The five segment lengths in m: straight, clothoid, arc, clothoid, straight
    /// [default: 500,2000,10908.3078,2000,800].
    #[arg(long, value_name = "L0,L1,L2,L3,L4")]
    pub lengths: Option<OsString>,
    /// Short track (60,300,700,300,60 m) for a quick look.
    #[arg(long)]
    pub quick: bool,
    /// Kinematics of the vehicle links: linear or nonlinear [default: linear].
    #[arg(long, value_name = "linear|nonlinear")]
    pub geometry: Option<OsString>,
    /// Contact statuses of each step's first Newton iteration: found (the rails are rigid,
    /// nothing to hold) or committed (those of the last converged step) [default: found].
    #[arg(long, value_name = "found|committed")]
    pub first_active_set: Option<OsString>,
    /// Anti-roll bar stiffness in N·m/rad [default: 0].
    #[arg(long, value_name = "K")]
    pub anti_roll: Option<OsString>,
    /// Tangential contact law of the wheels: coulomb (the paper's), kalker_linear, polach
    /// or fastsim (rolling-contact creep, docs/creep.md) [default: coulomb].
    #[arg(long, value_name = "coulomb|kalker_linear|polach|fastsim")]
    pub tangential: Option<OsString>,
    /// Polach's spin term with `--tangential polach`: off (his 2005 law) or polach_1999 (his
    /// spin-corrected lateral creepage and force, docs/creep.md) [default: off].
    #[arg(long, value_name = "off|polach_1999")]
    pub polach_spin: Option<OsString>,
    /// Assess the wheel forces afterwards with the defaults of `railfem assess`.
    #[arg(long)]
    pub assess: bool,
}

/// `railfem critical-radius`.
#[derive(ClapArgs, Debug)]
pub struct CriticalCmd {
    /// Onset criterion: sliding or separation [default: sliding].
    #[arg(long, value_name = "sliding|separation")]
    pub criterion: Option<OsString>,
    /// Sweep speeds × cts × mus on all cores (a whole figure).
    #[arg(long)]
    pub sweep: bool,
    /// Sweep speeds in m/s, comma-separated [default: 100,140,180,220,260].
    #[arg(long, value_name = "V1,V2,..")]
    pub speeds: Option<OsString>,
    /// Sweep Ct values in m, comma-separated [default: 200,400,900].
    #[arg(long, value_name = "CT1,CT2,..")]
    pub cts: Option<OsString>,
    /// Sweep friction coefficients [default: 0.1,0.2,0.3 (sliding), 0.3 (separation)].
    #[arg(long, value_name = "MU1,MU2,..")]
    pub mus: Option<OsString>,
    /// Output directory [default: out/critical for a sweep; none for one point].
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Speed V in m/s [default: 120].
    #[arg(long, value_name = "V")]
    pub speed: Option<OsString>,
    /// Cant parameter Ct in m [default: 200].
    #[arg(long, value_name = "CT")]
    pub ct: Option<OsString>,
    /// Friction coefficient μ [default: 0.3].
    #[arg(long, value_name = "MU")]
    pub mu: Option<OsString>,
    /// Tangential contact law of the wheels: coulomb (the paper's), kalker_linear, polach
    /// or fastsim (rolling-contact creep; sliding onset = every contact at 99 % of μN for the
    /// gross criterion, docs/creep.md) [default: coulomb]. Single runs only.
    #[arg(long, value_name = "coulomb|kalker_linear|polach|fastsim")]
    pub tangential: Option<OsString>,
    /// Polach's spin term with `--tangential polach`: off (his 2005 law) or polach_1999 (his
    /// spin-corrected lateral creepage and force, docs/creep.md) [default: off].
    #[arg(long, value_name = "off|polach_1999")]
    pub polach_spin: Option<OsString>,
    /// Clothoid length in m [default: 2000].
    #[arg(long, value_name = "L")]
    pub clothoid: Option<OsString>,
    /// Time step in s [default: 0.01].
    #[arg(long, value_name = "DT")]
    pub dt: Option<OsString>,
    /// Kinematics of the vehicle links: linear or nonlinear [default: linear].
    #[arg(long, value_name = "linear|nonlinear")]
    pub geometry: Option<OsString>,
}

/// `railfem conformance`.
#[derive(ClapArgs, Debug)]
pub struct ConformanceCmd {
    /// Check only the kinds whose name contains NAME [default: all].
    #[arg(long, value_name = "NAME")]
    pub element: Option<OsString>,
}

/// `railfem track`.
#[derive(ClapArgs, Debug)]
pub struct TrackCmd {
    /// Arc radius R in m [default: 6250].
    #[arg(long, value_name = "R")]
    pub radius: Option<OsString>,
    /// Cant parameter Ct in m [default: 200].
    #[arg(long, value_name = "CT")]
    pub ct: Option<OsString>,
    /// Output directory [default: out/track].
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
}

/// `railfem bench`.
#[derive(ClapArgs, Debug)]
pub struct BenchCmd {
    /// beam (linear multi-span beam), train-bridge, sprung (a sprung mass crossing the
    /// beam with each linear solver), threshold (dense against sparse solver by size) or
    /// floor (time per step against the memory-bandwidth floor) [default: beam].
    #[arg(long, value_name = "beam|train-bridge|sprung|threshold|floor|window")]
    pub case: Option<OsString>,
    /// DOF counts, comma-separated [default: 1e4,1e5,1e6].
    #[arg(long, value_name = "N1,N2,..")]
    pub sizes: Option<OsString>,
    /// Time steps per size [default: 20].
    #[arg(long, value_name = "N")]
    pub steps: Option<OsString>,
    /// Write the benchmark model, its load vectors and railfem's answer per size into
    /// DIR/dofN (for scripts/opensees_compare.sh) instead of timing.
    #[arg(long, value_name = "DIR")]
    pub export: Option<PathBuf>,
    /// Output directory [default: out/bench].
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Carriages of the train-bridge case [default: 1]; with --case window a list
    /// [default: 12].
    #[arg(long, value_name = "N")]
    pub cars: Option<OsString>,
    /// Spans of the window case, comma-separated [default: 113].
    #[arg(long, value_name = "N1,N2,..")]
    pub spans: Option<OsString>,
    /// Rail element length of the window case in m [default: 0.625].
    #[arg(long, value_name = "H")]
    pub element_length: Option<OsString>,
    /// Time step of the train-bridge case in s [default: 5e-4].
    #[arg(long, value_name = "DT")]
    pub dt: Option<OsString>,
    /// Kinematics of the vehicle links: linear or nonlinear [default: linear].
    #[arg(long, value_name = "linear|nonlinear")]
    pub geometry: Option<OsString>,
    /// Train-bridge case: station of the front carriage's centre at t = 0 from the bridge's
    /// first abutment, in m [default: -15, entering the viaduct].
    #[arg(long, value_name = "X", allow_hyphen_values = true)]
    pub train_start: Option<OsString>,
    /// Mass matrix of the beam case: consistent (cubic Hermite, as OpenSees -cMass) or
    /// lumped (rho*A*L/2 per node and translation, no rotary inertia, as OpenSees'
    /// elasticBeamColumn default) [default: consistent].
    #[arg(long, value_name = "consistent|lumped")]
    pub mass: Option<OsString>,
}

/// `railfem train-bridge`.
#[derive(ClapArgs, Debug)]
pub struct TrainBridgeCmd {
    /// Carriages [default: 12].
    #[arg(long, value_name = "N")]
    pub cars: Option<OsString>,
    /// Simply supported spans [default: 113].
    #[arg(long, value_name = "M")]
    pub spans: Option<OsString>,
    /// Span length in m [default: 29.75].
    #[arg(long, value_name = "L")]
    pub span: Option<OsString>,
    /// Largest beam element length in m; fasteners (every 0.625 m) are always nodes, so
    /// each bay gets ceil(0.625/H) equal elements [default: 0.625].
    #[arg(long, value_name = "H")]
    pub element_length: Option<OsString>,
    /// Aim at about N DOFs (sets the element length) [default: none; --element-length rules].
    #[arg(long, value_name = "N")]
    pub dof: Option<OsString>,
    /// Train speed in m/s [default: 80].
    #[arg(long, value_name = "V")]
    pub speed: Option<OsString>,
    /// Viaduct on an arc of radius R in m [default: straight].
    #[arg(long, value_name = "R")]
    pub radius: Option<OsString>,
    /// Cant parameter Ct in m [default: 200].
    #[arg(long, value_name = "CT")]
    pub ct: Option<OsString>,
    /// Duration in s [default: until the train has crossed].
    #[arg(long, value_name = "T")]
    pub duration: Option<OsString>,
    /// Time step in s [default: 0.005].
    #[arg(long, value_name = "DT")]
    pub dt: Option<OsString>,
    /// Record every N steps [default: 1].
    #[arg(long, value_name = "N")]
    pub record_every: Option<OsString>,
    /// Pier height in m [default: 10].
    #[arg(long, value_name = "H")]
    pub pier_height: Option<OsString>,
    /// Station of the front carriage's centre at t = 0 from the bridge's first abutment, in
    /// m [default: -15: the train starts on the approach and enters the viaduct].
    #[arg(long, value_name = "X", allow_hyphen_values = true)]
    pub train_start: Option<OsString>,
    /// Spans whose midspan is recorded (1-based, comma-separated) [default: a few].
    #[arg(long, value_name = "1,2,..")]
    pub midspans: Option<OsString>,
    /// Ground motion: a CSV file (t [s], ax, ay, az [m/s²]) or `synthetic` [default: none].
    #[arg(long, value_name = "FILE.csv|synthetic")]
    pub quake: Option<PathBuf>,
    /// Seed of the synthetic ground motion [default: 1].
    #[arg(long, value_name = "S")]
    pub seed: Option<OsString>,
    /// Peak ground acceleration of the synthetic motion in g [default: 0.3].
    #[arg(long, value_name = "G")]
    pub pga: Option<OsString>,
    /// Duration of the synthetic motion in s [default: 30].
    #[arg(long, value_name = "T")]
    pub quake_duration: Option<OsString>,
    /// Write the ground motion used to this CSV file.
    #[arg(long, value_name = "FILE.csv")]
    pub quake_out: Option<PathBuf>,
    /// Stop after N steps [default: all].
    #[arg(long, value_name = "N")]
    pub steps: Option<OsString>,
    /// Build the model, report its size and stop.
    #[arg(long)]
    pub build_only: bool,
    /// Kinematics of the vehicle links: linear or nonlinear [default: linear].
    #[arg(long, value_name = "linear|nonlinear")]
    pub geometry: Option<OsString>,
    /// Contact statuses of each step's first Newton iteration: committed (those of the
    /// last converged step; keeps a wheel on a deflecting bridge in contact for the first
    /// tangent) or found [default: committed].
    #[arg(long, value_name = "committed|found")]
    pub first_active_set: Option<OsString>,
    /// Linear solver of the Newton iterations: auto (partitioned from 50 000 equations),
    /// direct, partitioned or low_rank [default: auto]. Under `mpirun -n P` (P > 1, build
    /// with `--features mpi`) the partitioned solver's blocks are shared among the ranks.
    #[arg(long, value_name = "auto|direct|partitioned|low_rank")]
    pub solver: Option<OsString>,
    /// Target interior equations per block of the partitioned solver [default: 3000].
    #[arg(long, value_name = "N")]
    pub block_size: Option<OsString>,
    /// Activity window: on holds the partitioned solver's blocks far from the train at
    /// their state (straight track, no ground motion) [default: off].
    #[arg(long, value_name = "on|off")]
    pub window: Option<OsString>,
    /// With --window on: a block joins when the train's front is within M metres of it
    /// [default: two spans plus 3π times the rail's decay length].
    #[arg(long, value_name = "M")]
    pub window_ahead: Option<OsString>,
    /// With --window on: a block behind the train is held once its velocity norm is below
    /// X times its largest [default: 0.01].
    #[arg(long, value_name = "X")]
    pub window_tolerance: Option<OsString>,
    /// Output directory: wheels.csv, midspan.csv, summary.csv, run.json
    /// [default: out/train_bridge].
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Assess the wheel forces afterwards with the defaults of `railfem assess` (the
    /// train's speed measures distance).
    #[arg(long)]
    pub assess: bool,
}

/// `railfem stress`.
#[derive(ClapArgs, Debug)]
pub struct StressCmd {
    /// all, sdof, beam, penalty, speed, drop, stick-slip or dip [default: all].
    #[arg(long, value_name = "CASE")]
    pub case: Option<OsString>,
    /// Integrator: newmark, hht:ALPHA, galpha:RHO_INF, bathe or bathe:GAMMA [default: newmark].
    #[arg(long, value_name = "S")]
    pub scheme: Option<OsString>,
    /// ω·Δt of the sdof and beam cases [default: 1].
    #[arg(long, value_name = "W")]
    pub omega_dt: Option<OsString>,
    /// Contact penalty stiffness in N/m [default: 1e10].
    #[arg(long, value_name = "K")]
    pub penalty: Option<OsString>,
    /// Speed in m/s (speed case: 80; dip case: 15).
    #[arg(long, value_name = "V")]
    pub speed: Option<OsString>,
    /// Drop height in m [default: 0.01].
    #[arg(long, value_name = "H")]
    pub height: Option<OsString>,
    /// Rail joint dip depth in m [default: 0.002].
    #[arg(long, value_name = "D")]
    pub depth: Option<OsString>,
    /// Stick-slip load over the friction limit, as a factor [default: 1.5].
    #[arg(long, value_name = "F")]
    pub overshoot: Option<OsString>,
    /// Time steps (per case default: 2000, 500, 400, …).
    #[arg(long, value_name = "N")]
    pub steps: Option<OsString>,
    /// Duration in s (speed case: 0.3; drop case: 0.2).
    #[arg(long, value_name = "T")]
    pub duration: Option<OsString>,
    /// Time step in s of the drop case [default: 2e-5].
    #[arg(long, value_name = "DT")]
    pub dt: Option<OsString>,
    /// Also write the table to DIR/stress.md.
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
}

/// `railfem pareto`.
#[derive(ClapArgs, Debug)]
pub struct ParetoCmd {
    /// Output directory [default: out/pareto].
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Cases, comma-separated, from force, sprung, curve, train-bridge [default:
    /// force,sprung,curve]. `--case` is the same option (`--case train-bridge`, as
    /// `railfem bench --case`).
    #[arg(
        long,
        visible_alias = "case",
        value_name = "force,sprung,curve,train-bridge"
    )]
    pub cases: Option<OsString>,
    /// A peer code's runs of the force case (CSV: peer, elements, dt [s], steps, wall [s],
    /// error [-]; scripts/opensees_compare.py --pareto writes it), drawn on
    /// pareto-force.svg and compared at equal error in pareto-peers.md.
    #[arg(long, value_name = "FILE")]
    pub peer: Option<PathBuf>,
    /// train-bridge only: after the grid, time the cheapest generalized-α runs within 5 %
    /// and 1 % and their neighbours again, back to back, ROUNDS times in turn
    /// (pareto-train-bridge-retime.md) [default: 0, none].
    #[arg(long, value_name = "ROUNDS")]
    pub retime: Option<OsString>,
    /// train-bridge only: re-time these runs (element length : time step, generalized-α,
    /// partitioned) in turn, --retime rounds (default 1), without running the grid.
    #[arg(long, value_name = "H:DT,H:DT,..")]
    pub retime_at: Option<OsString>,
    /// train-bridge only: compute nothing, evaluate the runs already in --out.
    #[arg(long)]
    pub existing: bool,
    /// train-bridge only: also check the reference against a finer mesh (18 elements per
    /// fastener bay) and half its step over the whole crossing (about an hour each).
    #[arg(long)]
    pub finer: bool,
}

/// `railfem irregularity`.
#[derive(ClapArgs, Debug)]
pub struct IrregularityCmd {
    /// Spectrum: fra1..fra6, german_low, german_high (required).
    #[arg(long, value_name = "CLASS")]
    pub psd: Option<OsString>,
    /// Random seed [default: 1].
    #[arg(long, value_name = "S")]
    pub seed: Option<OsString>,
    /// Wavelength band in m [default: 1,50].
    #[arg(long, value_name = "MIN,MAX")]
    pub wavelengths: Option<OsString>,
    /// Sample spacing in m [default: MIN/8].
    #[arg(long, value_name = "H")]
    pub step: Option<OsString>,
    /// Track length in m [default: 2000].
    #[arg(long, value_name = "L")]
    pub length: Option<OsString>,
    /// Components, comma-separated (vertical, alignment, ...) [default: all of the class].
    #[arg(long, value_name = "C1,C2,..")]
    pub components: Option<OsString>,
    /// Output directory [default: out/irregularity].
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
}

/// `railfem completions`.
#[derive(ClapArgs, Debug)]
pub struct CompletionsCmd {
    /// The shell: bash, zsh, fish, elvish or powershell.
    #[arg(value_name = "SHELL")]
    pub shell: clap_complete::Shell,
}

/// `railfem study`.
#[derive(ClapArgs, Debug)]
pub struct StudyCmd {
    /// The study plan (TOML, docs/scale-out.md).
    #[arg(value_name = "PLAN.toml")]
    pub plan: PathBuf,
    /// Computing threads of this process (under mpirun: of rank 0; the other ranks compute
    /// one case at a time) [default: the available cores].
    #[arg(long, value_name = "N")]
    pub threads: Option<OsString>,
    /// Hand out at most N cases in this run, then stop; the checkpoint keeps them and a
    /// rerun goes on [default: all].
    #[arg(long, value_name = "N")]
    pub stop_after: Option<OsString>,
    /// Start afresh: discard the checkpoint's rows instead of resuming from them (the way
    /// out when a resume refuses a damaged or foreign row).
    #[arg(long)]
    pub restart: bool,
    /// Output directory: study.csv, study.json, study.svg/.png, study.checkpoint, cases/
    /// [default: out/study].
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
}

/// `railfem bridge-check`.
#[derive(ClapArgs, Debug)]
pub struct BridgeCheckCmd {
    /// The check's plan (TOML, docs/bridge-check.md).
    #[arg(value_name = "PLAN.toml")]
    pub plan: PathBuf,
    /// Computing threads [default: the available cores].
    #[arg(long, value_name = "N")]
    pub threads: Option<OsString>,
    /// Compute at most N train-speed runs, then stop; the journal keeps them and a rerun
    /// goes on [default: all].
    #[arg(long, value_name = "N")]
    pub stop_after: Option<OsString>,
    /// Start afresh: discard the journal (bridge-check.checkpoint) instead of resuming.
    #[arg(long)]
    pub restart: bool,
    /// Output directory: envelope.csv, acceleration.svg/.png, dynamic-factor.svg/.png,
    /// report.md, run.json, bridge-check.checkpoint [default: out/bridge_check].
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
}

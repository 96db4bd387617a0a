//! `railfem train-bridge`: a train of sks700 carriages over a viaduct ([`crate::train_bridge`]).
// The doc comments are the --help text too, where `[s]` is a unit, not a link.
#![allow(rustdoc::broken_intra_doc_links)]

use crate::command::{Command, Context};
use crate::framework::FemError;
use crate::train_bridge::{build, run, Quake, TrainBridgeCase};
use clap::Args;
use serde::Serialize;
use std::path::Path;
use std::path::PathBuf;

/// `railfem train-bridge`.
#[derive(Args, Debug, Clone, PartialEq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub struct TrainBridgeCmd {
    /// Carriages [default: 12].
    #[arg(value_parser = crate::command::number(), long, value_name = "N")]
    pub cars: Option<f64>,
    /// Simply supported spans [default: 113].
    #[arg(value_parser = crate::command::number(), long, value_name = "M")]
    pub spans: Option<f64>,
    /// Span length in m [default: 29.75].
    #[arg(value_parser = crate::command::number(), long, value_name = "L")]
    pub span: Option<f64>,
    /// Largest beam element length in m; fasteners (every 0.625 m) are always nodes, so
    /// each bay gets ceil(0.625/H) equal elements [default: 0.625].
    #[arg(value_parser = crate::command::number(), long, value_name = "H")]
    pub element_length: Option<f64>,
    /// Aim at about N DOFs (sets the element length) [default: none; --element-length rules].
    #[arg(value_parser = crate::command::number(), long, value_name = "N")]
    pub dof: Option<f64>,
    /// Train speed in m/s [default: 80].
    #[arg(value_parser = crate::command::number(), long, value_name = "V")]
    pub speed: Option<f64>,
    /// Viaduct on an arc of radius R in m [default: straight].
    #[arg(value_parser = crate::command::number(), long, value_name = "R")]
    pub radius: Option<f64>,
    /// Cant parameter Ct in m [default: 200].
    #[arg(value_parser = crate::command::number(), long, value_name = "CT")]
    pub ct: Option<f64>,
    /// Duration in s [default: until the train has crossed].
    #[arg(value_parser = crate::command::number(), long, value_name = "T")]
    pub duration: Option<f64>,
    /// Time step in s [default: 0.005].
    #[arg(value_parser = crate::command::number(), long, value_name = "DT")]
    pub dt: Option<f64>,
    /// Record every N steps [default: 1].
    #[arg(value_parser = crate::command::number(), long, value_name = "N")]
    pub record_every: Option<f64>,
    /// Pier height in m [default: 10].
    #[arg(value_parser = crate::command::number(), long, value_name = "H")]
    pub pier_height: Option<f64>,
    /// Station of the front carriage's centre at t = 0 from the bridge's first abutment, in
    /// m [default: -15: the train starts on the approach and enters the viaduct].
    #[arg(value_parser = crate::command::number(), long, value_name = "X", allow_hyphen_values = true)]
    pub train_start: Option<f64>,
    /// Spans whose midspan is recorded (1-based, comma-separated) [default: a few].
    #[arg(value_parser = crate::command::text(), long, value_name = "1,2,..")]
    pub midspans: Option<String>,
    /// Ground motion: a CSV file (t [s], ax, ay, az [m/s²]) or `synthetic` [default: none].
    #[arg(long, value_name = "FILE.csv|synthetic")]
    #[serde(serialize_with = "crate::command::opt_path_text")]
    pub quake: Option<PathBuf>,
    /// Seed of the synthetic ground motion [default: 1].
    #[arg(value_parser = crate::command::number(), long, value_name = "S")]
    pub seed: Option<f64>,
    /// Peak ground acceleration of the synthetic motion in g [default: 0.3].
    #[arg(value_parser = crate::command::number(), long, value_name = "G")]
    pub pga: Option<f64>,
    /// Duration of the synthetic motion in s [default: 30].
    #[arg(value_parser = crate::command::number(), long, value_name = "T")]
    pub quake_duration: Option<f64>,
    /// Write the ground motion used to this CSV file.
    #[arg(long, value_name = "FILE.csv")]
    #[serde(serialize_with = "crate::command::opt_path_text")]
    pub quake_out: Option<PathBuf>,
    /// Stop after N steps [default: all].
    #[arg(value_parser = crate::command::number(), long, value_name = "N")]
    pub steps: Option<f64>,
    /// Build the model, report its size and stop.
    #[arg(long)]
    pub build_only: bool,
    /// Kinematics of the vehicle links: linear or nonlinear [default: linear].
    #[arg(value_parser = crate::command::text(), long, value_name = "linear|nonlinear")]
    pub geometry: Option<String>,
    /// Contact statuses of each step's first Newton iteration: committed (those of the
    /// last converged step; keeps a wheel on a deflecting bridge in contact for the first
    /// tangent) or found [default: committed].
    #[arg(value_parser = crate::command::text(), long, value_name = "committed|found")]
    pub first_active_set: Option<String>,
    /// Linear solver of the Newton iterations: auto (partitioned from 50 000 equations),
    /// direct, partitioned or low_rank [default: auto]. Under `mpirun -n P` (P > 1, build
    /// with `--features mpi`) the partitioned solver's blocks are shared among the ranks.
    #[arg(value_parser = crate::command::text(), long, value_name = "auto|direct|partitioned|low_rank")]
    pub solver: Option<String>,
    /// Target interior equations per block of the partitioned solver [default: 3000].
    #[arg(value_parser = crate::command::number(), long, value_name = "N")]
    pub block_size: Option<f64>,
    /// Activity window: on holds the partitioned solver's blocks far from the train at
    /// their state (straight track, no ground motion); auto is on where it applies and
    /// off elsewhere (the partitioned solver on one process, a straight track, no ground
    /// motion); off solves every block [default: auto].
    #[arg(value_parser = crate::command::text(), long, value_name = "on|off|auto")]
    pub window: Option<String>,
    /// The activity window's reach: a block joins when the train's front is within M
    /// metres of it, and is held behind only once it is M metres behind the rear
    /// [default: 300].
    #[arg(value_parser = crate::command::number(), long, value_name = "M")]
    pub window_ahead: Option<f64>,
    /// A block behind the train is held once its velocity norm is below X times its
    /// largest [default: 0.01].
    #[arg(value_parser = crate::command::number(), long, value_name = "X")]
    pub window_tolerance: Option<f64>,
    /// The activity window's absorbing layer: damping growing over M metres towards a held
    /// block, so that it does not send the train's waves back; 0: none [default: a third
    /// of the reach].
    #[arg(value_parser = crate::command::number(), long, value_name = "M")]
    pub window_layer: Option<f64>,
    /// The absorbing layer's largest mass-proportional damping, in 1/s [default: derived
    /// from the thickness, docs/activity-window.md].
    #[arg(value_parser = crate::command::number(), long, value_name = "A")]
    pub window_layer_damping: Option<f64>,
    /// Far field: reduced runs the partitioned solver's blocks out of the train's reach
    /// (the activity window's) in Craig–Bampton form, switching them to full as the train
    /// comes near (docs/reduced-far-field.md); full solves every block in full
    /// [default: full].
    #[arg(value_parser = crate::command::text(), long, value_name = "full|reduced")]
    pub far_field: Option<String>,
    /// The reduced far field's cut-off: blocks keep their fixed-interface modes up to F
    /// Hz [default: from --dt, docs/reduced-far-field.md].
    #[arg(value_parser = crate::command::number(), long, value_name = "F")]
    pub far_field_cutoff: Option<f64>,
    /// The reduced far field's reach: blocks within M metres ahead of the train's front or
    /// behind its rear are full [default: the activity window's, 300].
    #[arg(value_parser = crate::command::number(), long, value_name = "M")]
    pub far_field_reach: Option<f64>,
    /// Output directory: wheels.csv, midspan.csv, summary.csv, energy.csv, run.json
    /// [default: out/train_bridge].
    #[arg(long, value_name = "DIR")]
    #[serde(serialize_with = "crate::command::opt_path_text")]
    pub out: Option<PathBuf>,
    /// Assess the wheel forces afterwards with the defaults of `railfem assess` (the
    /// train's speed measures distance).
    #[arg(long)]
    pub assess: bool,
}

impl TrainBridgeCmd {
    /// The case the options describe, from [`TrainBridgeCase::default`].
    fn case(&self) -> Result<TrainBridgeCase, FemError> {
        let mut c = TrainBridgeCase::default();
        let count = |key: &str, v: Option<f64>| {
            crate::command::whole(key, v, 999_999_999.0, "give a whole number ≥ 1")
        };
        let set = |x: &mut f64, v: Option<f64>| {
            if let Some(v) = v {
                *x = v;
            }
        };
        if let Some(v) = count("cars", self.cars)? {
            c.cars = v;
        }
        if let Some(v) = count("spans", self.spans)? {
            c.spans = v;
        }
        set(&mut c.span, self.span);
        set(&mut c.element_length, self.element_length);
        c.dof_target = count("dof", self.dof)?;
        set(&mut c.speed, self.speed);
        c.radius = self.radius;
        set(&mut c.ct, self.ct);
        c.duration = self.duration;
        set(&mut c.dt, self.dt);
        c.geometry = crate::command::geometry(self.geometry.as_deref())?;
        c.first_active_set =
            crate::command::first_active_set(self.first_active_set.as_deref(), c.first_active_set)?;
        if let Some(v) = count("record-every", self.record_every)? {
            c.record_every = v;
        }
        set(&mut c.pier_height, self.pier_height);
        set(&mut c.train_start, self.train_start);
        if let Some(list) = &self.midspans {
            c.midspans = list
                .split(',')
                .map(|x| x.trim().parse::<usize>())
                .collect::<Result<_, _>>()
                .map_err(|_| {
                    FemError::input(
                        "command line",
                        format!("--midspans {list}: give span numbers (1-based), comma-separated"),
                    )
                })?;
        }
        c.quake = match self.quake.as_deref() {
            None => Quake::None,
            Some(q) if q == Path::new("synthetic") => Quake::Synthetic {
                seed: count("seed", self.seed)?.unwrap_or(1) as u64,
                pga: self.pga.unwrap_or(0.3),
                duration: self.quake_duration.unwrap_or(30.0),
            },
            Some(file) => Quake::File(file.to_path_buf()),
        };
        if let Some(s) = &self.solver {
            c.solver = crate::framework::model::SolverChoice::parse(s).ok_or_else(|| {
                FemError::input(
                    "command line",
                    format!(
                        "--solver {s}: use auto (the default), direct, partitioned or low_rank"
                    ),
                )
            })?;
        }
        c.window = crate::train_window::parse_options(
            crate::train_window::COMMAND_LINE,
            self.window.as_deref(),
            self.window_ahead,
            self.window_tolerance,
        )?;
        c.window_layer = crate::train_window::parse_layer(
            crate::train_window::COMMAND_LINE,
            c.window,
            self.window_layer,
            self.window_layer_damping,
        )?;
        c.far_field = crate::far_field::parse(
            crate::far_field::COMMAND_LINE,
            self.far_field.as_deref(),
            self.far_field_cutoff,
            self.far_field_reach,
        )?;
        Ok(c)
    }
}

impl Command for TrainBridgeCmd {
    const NAME: &'static str = "train-bridge";
    const STOPS_AT_STEP: bool = true;
    fn out_dir(&self) -> Option<PathBuf> {
        crate::command::out_or(&self.out, "out/train_bridge")
    }
    fn run(&self, ctx: &Context) -> Result<i32, FemError> {
        let c = self.case()?;
        let count = |key: &str, v: Option<f64>| {
            crate::command::whole(key, v, 999_999_999.0, "give a whole number ≥ 1")
        };
        let steps = count("steps", self.steps)?;
        let out = ctx.out();
        let block_size = count("block-size", self.block_size)?;
        let ranks = crate::ranks::launcher_exchange("train-bridge")?;
        let options = block_size.map(|b| crate::solvers::partition::PartitionOptions {
            block_size: b,
            threads: 0,
            ..Default::default()
        });
        // Across ranks each rank splits the blocks on the pattern and forms K, M, C on its own
        // columns only.
        let mut m = match &ranks {
            None => build(&c)?,
            Some(ex) => crate::train_bridge::build_across_ranks(&c, ex.clone(), options)?,
        };
        if let (Some(o), None) = (options, &ranks) {
            m.driver.set_partition_options(o);
        }
        if let Some(ex) = ranks {
            let size = ex.size();
            if m.driver.partition_stats().is_none() {
                return Err(FemError::input(
                    "command line",
                    format!("`railfem train-bridge` across {size} ranks shares the partitioned solver's blocks, but this {}-DOF model uses another solver; give `--solver partitioned`", m.dofs),
                ));
            }
            // Shared at the build already: each rank forms the residual of its own rows, with
            // its columns of K, M, C.
            m.driver.set_exchange(ex)?;
            m.driver.keep_own_rows();
        }
        // Under a launcher rank 0 alone prints and writes the outputs; the others compute.
        if !crate::ranks::writes_outputs() {
            crate::progress::set_quiet(true);
            if !self.build_only {
                run(&mut m, &c, steps, None)?;
            }
            return Ok(0);
        }
        if let (Some(q), Some(p)) = (&m.quake, self.quake_out.as_deref()) {
            q.write_csv(p)?;
        }
        let [tg, tb, td] = m.build_seconds;
        println!(
            "train-bridge: {} cars, {} spans of {} m, element length {:.4} m: {} DOF, {} elements, {} nodes; build {:.2} s (generate {:.2}, framework {:.2}, driver {:.2}); peak memory {}",
            c.cars,
            c.spans,
            c.span,
            m.element_length,
            m.dofs,
            m.elements,
            m.nodes,
            tg + tb + td,
            tg,
            tb,
            td,
            crate::bench::peak_memory_mib().map_or("n/a".into(), |v| format!("{v:.0} MiB")),
        );
        if let Some(q) = &m.quake {
            let p = q.peaks();
            println!(
                "ground motion: {} samples over {:.2} s, peaks X {:.3} g, Y {:.3} g, Z {:.3} g",
                q.t.len(),
                q.t[q.t.len() - 1] - q.t[0],
                p[0] / crate::train_bridge::G0,
                p[1] / crate::train_bridge::G0,
                p[2] / crate::train_bridge::G0
            );
        }
        if self.build_only {
            return Ok(0);
        }
        let r = run(&mut m, &c, steps, Some(out))?;
        println!(
            "{} steps, {} Newton iterations, {:.2} s; results in {}",
            r.steps,
            r.iterations,
            r.wall,
            out.display()
        );
        if let Some(w) = r.window {
            println!("{}", crate::run_window::stats_line(&w));
        }
        if let Some(f) = r.far_field {
            println!(
                "far field: {} of {} block-steps reduced ({:.1} %); {} of {} blocks reducible, {} reductions ({} modes, {:.1} s; {} failed, kept full); {} switches to reduced, {} to full, E_res {:.4e} J",
                f.reduced_block_steps,
                f.block_steps,
                100.0 * f.reduced_block_steps as f64 / f.block_steps.max(1) as f64,
                f.candidates,
                f.blocks,
                f.reductions,
                f.modes,
                f.setup_seconds,
                f.failed,
                f.to_reduced,
                f.to_full,
                f.e_res
            );
        }
        if let Some(why) = r.window_off {
            println!("activity window (auto): off here: {why}");
        }
        if let Some(p) = m.driver.partition_stats().filter(|p| p.ranks > 1) {
            println!(
                "partitioned solver across {} ranks: rank 0 owns {} of {} blocks; it sent {} B and received {} B in {} collectives",
                p.ranks, p.owned_blocks, p.blocks, p.comm.bytes_sent, p.comm.bytes_received, p.comm.collectives
            );
        }
        println!("wheel   Q_static(N)   max Y/Q   t(s)   max dQ/Q   t(s)   min Q(N)   t(s)");
        for (i, e) in r.wheels.iter().enumerate() {
            println!(
                "{:<6} {:>12.1} {:>9.4} {:>6.3} {:>10.4} {:>6.3} {:>10.1} {:>6.3}",
                r.wheel_names[i],
                r.q_static[i],
                e.max_yq.0,
                e.max_yq.1,
                e.max_dqq.0,
                e.max_dqq.1,
                e.min_q.0,
                e.min_q.1
            );
        }
        if self.assess {
            crate::assess::after_run(out, Some(c.speed))?;
        }
        Ok(0)
    }
}

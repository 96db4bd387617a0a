//! The `railfem` command line: parse arguments (grammar in [`crate::commands`], clap),
//! run a subcommand, turn any error into one line and an exit code.
//!
//! Exit codes: 0 success; 2 bad input or a failed run (one line on stderr naming the file,
//! the place and the fix — clap's own usage errors included); 1 a check that ran and failed
//! (the conformance kit); 130 a run stopped by SIGINT or SIGTERM ([`crate::interrupt`]).

pub use crate::args::Args;
use crate::commands::Cli;
use crate::elements::rail::creep::law::{PolachSpin, Tangential};
use crate::framework::error::nearest;
use crate::framework::FemError;
use clap::parser::ValueSource;
use clap::{ArgAction, CommandFactory};
use std::ffi::{OsStr, OsString};
use std::path::{Path, PathBuf};

/// The clap command with the settings every subcommand shares: a value may start with `-`
/// (`--penalty -1` reaches the command, which says why it is refused).
pub fn clap_command() -> clap::Command {
    Cli::command().mut_subcommands(|c| c.allow_negative_numbers(true))
}

/// Turns a clap error into today's contract: one line naming the command line, the place
/// and the fix.
fn usage_error(e: &clap::Error, argv: &[OsString]) -> FemError {
    let text = e.render().to_string();
    // clap's message: the lines before its usage block, then its tips, on one line.
    let mut what = Vec::new();
    let mut tips = Vec::new();
    for l in text.lines().map(str::trim).filter(|l| !l.is_empty()) {
        if l.starts_with("Usage:") || l.starts_with("For more information") {
            break;
        }
        match l.strip_prefix("tip: ") {
            Some(t) => tips.push(t.to_string()),
            None => what.push(l.trim_start_matches("error: ").to_string()),
        }
    }
    let first = what.join(" ");
    let tip: String = tips.iter().map(|t| format!("; {t}")).collect();
    // The command the user meant, for the pointer to its help.
    let sub = argv
        .first()
        .and_then(|c| c.to_str())
        .filter(|c| clap_command().find_subcommand(c).is_some())
        .map(|c| format!(" {c}"))
        .unwrap_or_default();
    FemError::input(
        "command line",
        format!("{first}{tip}; see `railfem{sub} --help`"),
    )
}

/// An option `command` does not know, refused naming the nearest it does and listing its
/// options (its own, then those of every command).
fn unknown_option(command: &clap::Command, key: &str) -> FemError {
    let (global, own): (Vec<&clap::Arg>, Vec<&clap::Arg>) = command
        .get_arguments()
        .filter(|a| a.get_long().is_some_and(|l| l != "help"))
        .partition(|a| a.is_global_set());
    let valid: Vec<&str> = own
        .iter()
        .chain(&global)
        .filter_map(|a| a.get_long())
        .chain(["help"])
        .collect();
    let hint = nearest(key, &valid)
        .map(|n| format!("did you mean `--{n}`? "))
        .unwrap_or_default();
    let list: Vec<String> = valid.iter().map(|v| format!("--{v}")).collect();
    FemError::input(
        "command line",
        format!(
            "`railfem {}` has no option `--{key}`; {hint}its options are {}",
            command.get_name(),
            list.join(", ")
        ),
    )
}

/// Parses `argv` (without the program name).
pub fn parse<S: AsRef<OsStr>>(argv: &[S]) -> Result<Args, FemError> {
    let argv: Vec<OsString> = argv.iter().map(|s| s.as_ref().to_os_string()).collect();
    if let Some(c) = argv.first().filter(|c| c.to_str().is_none()) {
        return Err(FemError::input(
            "command line",
            format!(
                "the command {} is not valid UTF-8; give it in plain text",
                c.to_string_lossy()
            ),
        ));
    }
    let mut cmd = clap_command();
    let full = std::iter::once(OsString::from("railfem")).chain(argv.iter().cloned());
    let m = match cmd.try_get_matches_from_mut(full) {
        Ok(m) => m,
        Err(e) => {
            use clap::error::ErrorKind as K;
            return match e.kind() {
                K::DisplayHelp | K::DisplayVersion => Ok(Args {
                    command: "help".into(),
                    message: Some(e.render().to_string()),
                    argv,
                    ..Args::default()
                }),
                K::UnknownArgument => {
                    let key = match e.get(clap::error::ContextKind::InvalidArg) {
                        Some(clap::error::ContextValue::String(k)) => k.clone(),
                        _ => String::new(),
                    };
                    let key = key.split('=').next().unwrap_or("").to_string();
                    let sub = argv
                        .first()
                        .and_then(|c| c.to_str())
                        .and_then(|c| cmd.find_subcommand(c));
                    match (key.strip_prefix("--"), sub) {
                        (Some(k), Some(sub)) => Err(unknown_option(sub, k)),
                        _ => Err(usage_error(&e, &argv)),
                    }
                }
                _ => Err(usage_error(&e, &argv)),
            };
        }
    };
    let Some((name, sub)) = m.subcommand() else {
        return Ok(Args {
            command: "help".into(),
            message: Some(cmd.render_long_help().to_string()),
            argv,
            ..Args::default()
        });
    };
    let def = cmd
        .find_subcommand(name)
        .expect("clap matched a declared subcommand");
    let mut a = Args {
        command: name.to_string(),
        argv: argv.clone(),
        ..Args::default()
    };
    let text = |x: &OsStr, what: &str| -> Result<String, FemError> {
        x.to_str().map(str::to_string).ok_or_else(|| {
            FemError::input(
                "command line",
                format!(
                    "{what} {} is not valid UTF-8; give it in plain text",
                    x.to_string_lossy()
                ),
            )
        })
    };
    for arg in def.get_arguments() {
        let id = arg.get_id().as_str();
        if sub.value_source(id) != Some(ValueSource::CommandLine) {
            continue;
        }
        let Some(long) = arg.get_long() else {
            // Positional (the model file, the shell of `completions`).
            if let Some(vs) = sub.get_raw(id) {
                a.positional.extend(vs.map(OsStr::to_os_string));
            }
            continue;
        };
        if matches!(arg.get_action(), ArgAction::SetTrue) {
            if sub.get_flag(id) {
                a.flags.push(long.to_string());
            }
            continue;
        }
        let is_path = arg.get_value_parser().type_id() == clap::value_parser!(PathBuf).type_id();
        for v in sub.get_raw(id).into_iter().flatten() {
            match long {
                "out" => a.out = Some(PathBuf::from(v)),
                "plugin" => a.plugins.push(PathBuf::from(v)),
                _ if is_path => a.paths.push((long.to_string(), PathBuf::from(v))),
                _ => {
                    let v = text(v, &format!("the value of --{long}"))?;
                    a.options.push((long.to_string(), v));
                }
            }
        }
    }
    set_limits(&a)?;
    Ok(a)
}

/// Hands `--max-memory` and `--max-steps` to the size guards ([`crate::framework::limits`]).
fn set_limits(a: &Args) -> Result<(), FemError> {
    use crate::framework::limits::{set_command_line, set_from_text, LimitSpec, LIMIT_KEYS};
    let mut spec = LimitSpec::default();
    for key in LIMIT_KEYS {
        let flag = key.replace('_', "-");
        if let Some(v) = a.opt(&flag) {
            set_from_text(&mut spec, key, v)
                .map_err(|m| FemError::input("command line", format!("--{flag} {v}: {m}")))?;
        }
    }
    set_command_line(spec);
    Ok(())
}

fn model_arg(a: &Args) -> Result<&Path, FemError> {
    a.positional.first().map(Path::new).ok_or_else(|| {
        FemError::input(
            "command line",
            format!("`railfem {}` needs a MODEL file", a.command),
        )
    })
}

/// Most problems `railfem check` lists.
pub const MAX_LISTED: usize = 20;

/// The one validation `check` and `run` share: read and build the model, number the
/// equations, assemble the pattern and the constant matrices, and run the preflight checks
/// (singularity, stability, size). Warnings go to stderr here, so both print them.
fn prepare(
    path: &Path,
    estimate_factor: bool,
) -> Result<(crate::solvers::Driver, crate::solvers::preflight::Preflight), FemError> {
    prepare_on(path, estimate_factor, None)
}

/// [`prepare`] on one rank of `ranks` (`crate::prepare_on`).
fn prepare_on(
    path: &Path,
    estimate_factor: bool,
    ranks: Option<std::sync::Arc<dyn crate::solvers::exchange::Exchange>>,
) -> Result<(crate::solvers::Driver, crate::solvers::preflight::Preflight), FemError> {
    let file = path.display().to_string();
    let (driver, pre) = crate::prepare_on(crate::load_model(path), &file, estimate_factor, ranks)?;
    for w in &pre.warnings {
        eprintln!("warning: {w}");
    }
    Ok((driver, pre))
}

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

/// Commands that stop at the end of a step, a load step or a case when asked
/// ([`crate::framework::interrupt`]); the others stop at once on SIGINT/SIGTERM.
const STOPS_AT_STEP: [&str; 10] = [
    "run",
    "curve",
    "train-bridge",
    "critical-radius",
    "stress",
    "pareto",
    "bench",
    "irregularity",
    "study",
    "bridge-check",
];

/// The output directory of a command as it resolves it (its `--out` or its default);
/// `None` for commands that write no directory.
pub fn out_dir(a: &Args) -> Option<PathBuf> {
    if a.message.is_some() {
        return None;
    }
    let default = match a.command.as_str() {
        "run" => "out",
        "curve" => "out/curve",
        "critical-radius" if a.flag("sweep") => "out/critical",
        "track" => "out/track",
        "bench" if a.path("export").is_some() => return a.path("export").map(Path::to_path_buf),
        "bench" => "out/bench",
        "train-bridge" => "out/train_bridge",
        "pareto" => "out/pareto",
        "irregularity" => "out/irregularity",
        "matrices" => "out/matrices",
        "study" => crate::study::DEFAULT_OUT,
        "bridge-check" => crate::bridge_check::DEFAULT_OUT,
        "critical-radius" | "stress" => return a.out.clone(),
        _ => return None,
    };
    Some(a.out.clone().unwrap_or_else(|| PathBuf::from(default)))
}

/// What the sidecar says about the command's inputs: the options as parsed.
fn options_json(a: &Args, dir: &Path) -> serde_json::Value {
    let mut o = serde_json::Map::new();
    o.insert("out".into(), dir.display().to_string().into());
    for (k, v) in &a.options {
        o.insert(k.clone(), v.clone().into());
    }
    for (k, v) in &a.paths {
        o.insert(k.clone(), v.display().to_string().into());
    }
    for f in &a.flags {
        o.insert(f.clone(), true.into());
    }
    if !a.plugins.is_empty() {
        let p: Vec<String> = a.plugins.iter().map(|p| p.display().to_string()).collect();
        o.insert("plugin".into(), p.into());
    }
    if !a.positional.is_empty() {
        let p: Vec<String> = a
            .positional
            .iter()
            .map(|p| p.to_string_lossy().into_owned())
            .collect();
        o.insert("positional".into(), p.into());
    }
    serde_json::Value::Object(o)
}

/// The sidecar of the command running in this process, for the signal handler.
static RUNNING: std::sync::Mutex<Option<crate::sidecar::RunRecord>> = std::sync::Mutex::new(None);

/// SIGINT/SIGTERM: a command that stops at a step boundary is asked to
/// ([`crate::framework::interrupt::request`]); a second signal, or a command that cannot,
/// marks the sidecar and exits at once with 130.
fn install_interrupt_handler(command: &str) {
    let at_step = STOPS_AT_STEP.contains(&command);
    // An error means a handler is in place already (a test calling `run` twice): keep it.
    let _ = ctrlc::set_handler(move || {
        if at_step && !crate::framework::interrupt::requested() {
            crate::framework::interrupt::request();
            eprintln!("railfem: stopping at the end of this step (signal again to stop at once)");
            return;
        }
        if let Ok(g) = RUNNING.lock() {
            if let Some(r) = g.as_ref() {
                let _ = r.write("interrupted before the end; outputs may be incomplete");
            }
        }
        eprintln!("railfem: interrupted");
        std::process::exit(130);
    });
}

/// Runs a parsed command with its progress setting, interrupt handler and sidecar
/// (`run.json`, [`crate::sidecar`]); returns the process exit code.
pub fn run(a: &Args) -> Result<i32, FemError> {
    crate::progress::set_quiet(a.flag("quiet"));
    // Under an MPI launcher every rank runs the same command line into the same folder;
    // only rank 0 writes the sidecar (the ranks would otherwise overwrite each other's).
    let writes_sidecar = crate::sidecar::launcher_rank().unwrap_or(0) == 0;
    let record = out_dir(a).map(|dir| crate::sidecar::RunRecord {
        command: a.command.clone(),
        argv: a
            .argv
            .iter()
            .map(|s| s.to_string_lossy().into_owned())
            .collect(),
        options: options_json(a, &dir),
        dir,
        start: std::time::SystemTime::now(),
    });
    if let Some(r) = &record {
        if writes_sidecar {
            if let Ok(mut g) = RUNNING.lock() {
                *g = Some(r.clone());
            }
        }
        install_interrupt_handler(&a.command);
    }
    let record = record.filter(|_| writes_sidecar);
    let result = dispatch(a);
    if let Some(r) = &record {
        let status = match &result {
            Ok(0) => "completed".to_string(),
            Ok(code) => format!("failed: exit code {code}"),
            Err(e @ (FemError::Interrupted { .. } | FemError::InterruptedAfter { .. })) => {
                e.to_string()
            }
            Err(e) => format!("failed: {}", e.to_string().replace('\n', " ")),
        };
        let written = r.write(&status);
        if let Ok(mut g) = RUNNING.lock() {
            *g = None;
        }
        // A run that failed already keeps its own error (one line); otherwise a run.json
        // that cannot be written is the error.
        if let (Ok(_), Err(e)) = (&result, written) {
            return Err(FemError::output(r.dir.join(crate::sidecar::RUN_JSON), e));
        }
    }
    result
}

/// Runs a parsed command; returns the process exit code.
/// Prints a registered kind and its documented keys (`railfem elements`, `loads`,
/// `recorders`).
fn print_kind(name: &str, description: &str, params: Vec<crate::framework::registry::ParamDoc>) {
    println!("{name} — {description}");
    for p in params {
        let def = p
            .default
            .map(|d| format!(" (default {d})"))
            .unwrap_or_else(|| " (required)".into());
        println!("    {:<12} [{}]{}  {}", p.key, p.unit, def, p.doc);
    }
}

fn dispatch(a: &Args) -> Result<i32, FemError> {
    crate::elements::link();
    for p in &a.plugins {
        crate::framework::plugin::load(p)?;
    }
    if let Some(text) = &a.message {
        print!("{text}");
        return Ok(0);
    }
    match a.command.as_str() {
        "help" => {
            print!("{}", clap_command().render_long_help());
            Ok(0)
        }
        "completions" => {
            use clap::ValueEnum;
            let name = a.positional.first().and_then(|s| s.to_str()).unwrap_or("");
            let shell = clap_complete::Shell::from_str(name, true).map_err(|_| {
                FemError::input(
                    "command line",
                    format!("completions {name}: give bash, zsh, fish, elvish or powershell"),
                )
            })?;
            clap_complete::generate(
                shell,
                &mut clap_command(),
                "railfem",
                &mut std::io::stdout(),
            );
            Ok(0)
        }
        "check" => {
            let path = model_arg(a)?;
            let checked = prepare(path, true).and_then(|(mut d, pre)| {
                mechanism_check(&mut d, a.flag("factor")).map(|note| (pre, note))
            });
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
        "run" => {
            let path = model_arg(a)?;
            let out = a.out.clone().unwrap_or_else(|| PathBuf::from("out"));
            let ranks = crate::ranks::launcher_exchange("run")?;
            // Across ranks, K, M, C formed on each rank's columns only.
            let (mut driver, _) = prepare_on(path, false, ranks.clone())?;
            if let Some(ex) = ranks {
                share_among_ranks(&mut driver, ex, path)?;
                // Rank 0 alone prints and writes the recorders; the others compute.
                if !crate::ranks::writes_outputs() {
                    crate::progress::set_quiet(true);
                    driver
                        .run(None, &mut |_| {})
                        .map_err(|e| e.in_file(&path.display().to_string()))?;
                    return Ok(0);
                }
            }
            let an = &driver.model.analysis;
            let steps = match an.kind {
                crate::framework::model::AnalysisKind::Transient => {
                    (an.duration / an.dt - 1e-9).ceil().max(1.0) as u64
                }
                _ => 1,
            };
            let mut bar = crate::progress::Progress::new("run", steps, "steps");
            let s = driver
                .run(Some(&out), &mut |f| bar.fraction(f))
                .map_err(|e| e.in_file(&path.display().to_string()))?;
            bar.finish();
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
            if let Some(e) = driver.energy.as_ref().filter(|e| e.started()) {
                println!("{}", e.summary());
            }
            if let Some(p) = driver.partition_stats().filter(|p| p.ranks > 1) {
                println!(
                    "partitioned solver across {} ranks: rank 0 owns {} of {} blocks; it sent {} B and received {} B in {} collectives",
                    p.ranks, p.owned_blocks, p.blocks, p.comm.bytes_sent, p.comm.bytes_received, p.comm.collectives
                );
            }
            if a.flag("assess") {
                crate::assess::after_run(&out, None)?;
            }
            Ok(0)
        }
        "elements" => {
            for k in crate::framework::registry::kinds() {
                print_kind(k.name, k.description, (k.params)());
            }
            Ok(0)
        }
        "loads" => {
            for k in crate::framework::load_kind::kinds() {
                print_kind(k.name, k.description, (k.params)());
            }
            Ok(0)
        }
        "recorders" => {
            for k in crate::framework::recorder_kind::kinds() {
                print_kind(k.name, k.description, (k.params)());
            }
            Ok(0)
        }
        "integrators" => {
            print!("{}", crate::solvers::time_integrator::listing());
            Ok(0)
        }
        "curve" => curve(a),
        "critical-radius" => critical(a),
        "conformance" => conformance(a),
        "track" => track(a),
        "bench" => bench(a),
        "train-bridge" => train_bridge(a),
        "stress" => stress(a),
        "pareto" => pareto(a),
        "irregularity" => crate::irregularity::command(a),
        "study" => crate::study::command(a),
        "bridge-check" => crate::bridge_check::command(a),
        "trains" => crate::bridge_check::trains_command(),
        "assess" => crate::assess::command(a),
        "contact" => crate::contact_tool::command(a),
        "reference" => crate::reference::command(a),
        "matrices" => {
            let path = model_arg(a)?;
            let out = a
                .out
                .clone()
                .unwrap_or_else(|| PathBuf::from("out/matrices"));
            let n = crate::matrices::write(path, &out)?;
            println!(
                "{}: {n} equations; K.mtx, M.mtx, C.mtx, f.mtx and dofs.csv in {}",
                path.display(),
                out.display()
            );
            Ok(0)
        }
        other => Err(FemError::input(
            "command line",
            format!("unknown command `{other}`; run `railfem help`"),
        )),
    }
}

/// `railfem curve`: the paper's Section 4 case, FE against theory.
fn curve(a: &Args) -> Result<i32, FemError> {
    let mut case = crate::curve::CurveCase::default();
    if let Some(v) = a.num("radius")? {
        case.radius = v;
    }
    if let Some(v) = a.num("ct")? {
        case.ct = v;
    }
    if let Some(v) = a.num("speed")? {
        case.speed = v;
    }
    if let Some(v) = a.num("mu")? {
        case.mu = v;
    }
    if let Some(v) = a.num("dt")? {
        case.dt = v;
    }
    if let Some(v) = a.num("penalty")? {
        case.penalty = v;
    }
    if let Some(v) = a.num("duration")? {
        case.duration = v;
    }
    if let Some(v) = a.num("vtk")? {
        case.vtk_every = v as usize;
    }
    if let Some(v) = a.num("anti-roll")? {
        case.anti_roll = v;
    }
    if let Some(l) = a.opt("lengths") {
        let v: Vec<f64> = l.split(',').filter_map(|x| x.trim().parse().ok()).collect();
        if v.len() != 5 || v.iter().any(|x| !(x.is_finite() && *x > 0.0)) {
            return Err(FemError::input(
                "command line",
                format!("--lengths {l}: give five positive lengths in m, comma-separated"),
            ));
        }
        case.lengths = [v[0], v[1], v[2], v[3], v[4]];
    }
    if a.flags.iter().any(|f| f == "quick") {
        case.lengths = [60.0, 300.0, 700.0, 300.0, 60.0];
    }
    if let Some(t) = a.opt("tangential") {
        case.tangential = crate::choice::parse("command line", "--tangential", t)?;
    }
    case.polach_spin = polach_spin(a, case.tangential)?;
    case.geometry = geometry(a)?;
    case.first_active_set = first_active_set(a, case.first_active_set)?;
    let out = a.out.clone().unwrap_or_else(|| PathBuf::from("out/curve"));
    let steps = case.steps_estimate();
    let mut bar = crate::progress::Progress::new("curve", steps, "steps");
    let r = crate::curve::run(&case, Some(&out), &mut |f| bar.fraction(f))?;
    bar.finish();
    println!(
        "curve: R = {} m, Ct = {} m, V = {} m/s, mu = {}, dt = {} s{}: {} steps, {} Newton iterations, {:.2} s",
        case.radius, case.ct, case.speed, case.mu, case.dt,
        if case.tangential == Tangential::Coulomb { String::new() } else { format!(", tangential {}", case.tangential.name()) },
        r.steps, r.iterations, r.wall
    );
    println!(
        "on the arc, largest relative difference FE vs theory: normal vs statics {:.3e}, axle shear vs Eq. 26 {:.3e} (single wheel {:.3e}); normal vs Eq. 25 as printed {:.3e}",
        r.max_rel_normal_statics, r.max_rel_shear, r.max_rel_shear_wheel, r.max_rel_normal_printed
    );
    println!(
        "statics with body lean (quasi-static reference): normal FE vs reference {:.3e}; settled-arc mean FE normal inner {:.1} N, outer {:.1} N (geometry {})",
        r.max_rel_normal_lean,
        r.arc_mean_normal[0],
        r.arc_mean_normal[1],
        case.geometry.name()
    );
    let arc = crate::elements::rail::lean::ArcPoint {
        speed: case.speed,
        curvature: 1.0 / case.radius,
        cant: case.ct / case.radius,
        gravity: case.gravity,
        spacing: r.contact_spacing,
        pivot: None,
    };
    if let Some(l) = crate::elements::rail::lean::wheel_loads(&case.carriage(), &arc) {
        let (c, b) = (l.state.car_body, l.state.bogie);
        println!(
            "lean reference on the arc: car body lateral {:.4} m, vertical {:.4} m, roll {:.5} rad; bogie {:.4} m, {:.4} m, {:.5} rad; wheel loads inner {:.1} N, outer {:.1} N (statics {:.1} N, {:.1} N)",
            c[0], c[1], c[2], b[0], b[1], b[2], l.lean[0], l.lean[1], l.rigid[0], l.rigid[1]
        );
    }
    println!(
        "contact spacing used by the statics: {:.4} m; results in {}",
        r.contact_spacing,
        out.display()
    );
    if let Some(e) = &r.energy_summary {
        println!("{e}");
    }
    if a.flag("assess") {
        crate::assess::after_run(&out, None)?;
    }
    Ok(0)
}

/// `railfem track`: the paper's five-segment track with arc radius `--radius` (m, default
/// 6250) and cant θ = Ct/R (`--ct` m, default 200), written as `track.csv` and `track.svg`
/// into `--out` (default `out/track`).
fn track(a: &Args) -> Result<i32, FemError> {
    use crate::elements::rail::cant::Track;
    let radius = a.num("radius")?.unwrap_or(6250.0);
    let ct = a.num("ct")?.unwrap_or(200.0);
    let min = crate::elements::rail::alignment::MIN_RADIUS;
    if radius < min {
        return Err(FemError::input(
            "command line",
            format!("--radius {radius}: give the arc radius in m, ≥ {min} (the tightest curve a wheelset can take)"),
        ));
    }
    if ct < 0.0 || ct / radius >= std::f64::consts::FRAC_PI_2 {
        return Err(FemError::input(
            "command line",
            format!("--ct {ct}: give Ct in m, >= 0 and below R·π/2 (θ = Ct/R, Eq. 21)"),
        ));
    }
    let out = a.out.clone().unwrap_or_else(|| PathBuf::from("out/track"));
    let t = Track::paper(radius, ct);
    crate::elements::rail::railline::write_track_report(&t, &out)
        .map_err(|e| FemError::output(&out, e))?;
    println!(
        "track: R = {radius} m, Ct = {ct} m (θ = {:.6} rad on the arc), {:.4} m long; track.csv and track.svg in {}",
        ct / radius,
        t.alignment.length(),
        out.display()
    );
    Ok(0)
}

/// `railfem bench`: per DOF count in `--sizes` (default 1e4,1e5,1e6), `--steps` linear
/// transient steps (default 20) of the benchmark beam; table on stdout, `bench.md` and
/// `bench.csv` in `--out` (default `out/bench`).
fn bench(a: &Args) -> Result<i32, FemError> {
    let case = a.opt("case").unwrap_or("beam");
    if !matches!(
        case,
        "beam" | "train-bridge" | "sprung" | "threshold" | "floor" | "window"
    ) {
        return Err(FemError::input(
            "command line",
            format!("--case {case}: use beam (linear multi-span beam), train-bridge, sprung (a sprung mass crossing the beam, per solver), threshold (dense against sparse solver by size), floor (time per step against the memory-bandwidth floor) or window (train-bridge step time against spans and carriages, activity window on and off)"),
        ));
    }
    if case == "window" {
        return bench_window(a);
    }
    if case == "threshold" {
        let out = a.out.clone().unwrap_or_else(|| PathBuf::from("out/bench"));
        crate::threshold::run(&out)?;
        return Ok(0);
    }
    let spec = a.opt("sizes").unwrap_or("1e4,1e5,1e6");
    let mut sizes = Vec::new();
    for x in spec.split(',') {
        match x.trim().parse::<f64>() {
            Ok(v) if (1.0..=1e9).contains(&v) => sizes.push(v.round() as usize),
            _ => {
                return Err(FemError::input(
                    "command line",
                    format!("--sizes {spec}: give DOF counts >= 1, comma-separated (e.g. 1e4,1e5)"),
                ))
            }
        }
    }
    for &n in &sizes {
        crate::framework::limits::check_memory(
            &format!("--sizes {spec}"),
            n as f64,
            "DOFs",
            crate::framework::limits::BYTES_PER_DOF,
            "give smaller sizes",
        )
        .map_err(|m| FemError::input("command line", m))?;
    }
    let steps = match a.num("steps")? {
        None => 20,
        Some(v) if v >= 1.0 && v.fract() == 0.0 => v as usize,
        Some(v) => {
            return Err(FemError::input(
                "command line",
                format!("--steps {v}: give a whole number of steps >= 1"),
            ))
        }
    };
    let mass = match a.opt("mass") {
        None => crate::bench::BenchMass::Consistent,
        Some(m) => match crate::bench::BenchMass::parse(m) {
            Some(k) if case == "beam" || case == "floor" => k,
            Some(_) => {
                return Err(FemError::input(
                    "command line",
                    format!(
                        "--mass {m}: only the beam and floor cases take --mass; drop it or use --case beam"
                    ),
                ))
            }
            None => {
                return Err(FemError::input(
                    "command line",
                    format!("--mass {m}: use consistent (the default) or lumped"),
                ))
            }
        },
    };
    if let Some(dir) = a.path("export") {
        // One directory per size: the model, the load vectors and railfem's answer, for
        // scripts/opensees_compare.py.
        for &n in &sizes {
            let sub = dir.join(format!("dof{n}"));
            let r = crate::bench::export(n, steps, mass, &sub)?;
            println!(
                "bench export: {} equations, {} steps, first step {:.3} ms, then {:.3} ms/step; written to {}",
                r.equations,
                r.steps,
                r.first_step * 1e3,
                r.per_step * 1e3,
                sub.display()
            );
        }
        return Ok(0);
    }
    let out = a.out.clone().unwrap_or_else(|| PathBuf::from("out/bench"));
    if case == "train-bridge" {
        let cars = match a.num("cars")? {
            None => 1,
            Some(v) if v >= 1.0 && v.fract() == 0.0 => v as usize,
            Some(v) => {
                return Err(FemError::input(
                    "command line",
                    format!("--cars {v}: give a whole number of carriages >= 1"),
                ))
            }
        };
        let dt = match a.num("dt")? {
            None => 5e-4,
            Some(v) if v > 0.0 => v,
            Some(v) => {
                return Err(FemError::input(
                    "command line",
                    format!("--dt {v}: give a time step > 0 s"),
                ))
            }
        };
        let start = a.num("train-start")?.unwrap_or(-15.0);
        crate::bench_train::run(&sizes, cars, steps, dt, start, geometry(a)?, &out)?;
        return Ok(0);
    }
    if case == "floor" {
        crate::floor::run(&sizes, steps, mass, &out)?;
        return Ok(0);
    }
    if case == "sprung" {
        crate::small_models::run(&sizes, steps, &out)?;
        return Ok(0);
    }
    crate::bench::run(&sizes, steps, mass, &out)?;
    Ok(0)
}

/// `railfem bench --case window` ([`crate::bench_window`]): `--spans` and `--cars` lists
/// (default 113 and 12), `--steps` timed steps (default 20), `--dt` (default 5e-4 s),
/// `--element-length` (default 0.625 m), `--train-start` (default -15 m).
fn bench_window(a: &Args) -> Result<i32, FemError> {
    let list = |key: &str, default: &str| -> Result<Vec<usize>, FemError> {
        let spec = a.opt(key).unwrap_or(default);
        spec.split(',')
            .map(|x| match x.trim().parse::<usize>() {
                Ok(v) if v >= 1 => Ok(v),
                _ => Err(FemError::input(
                    "command line",
                    format!("--{key} {spec}: give whole numbers >= 1, comma-separated"),
                )),
            })
            .collect()
    };
    let (spans, cars) = (list("spans", "113")?, list("cars", "12")?);
    let positive = |key: &str, default: f64| -> Result<f64, FemError> {
        match a.num(key)? {
            None => Ok(default),
            Some(v) if v > 0.0 => Ok(v),
            Some(v) => Err(FemError::input(
                "command line",
                format!("--{key} {v}: give a value > 0"),
            )),
        }
    };
    let steps = positive("steps", 20.0)?.round() as usize;
    let (dt, h) = (positive("dt", 5e-4)?, positive("element-length", 0.625)?);
    let out = a.out.clone().unwrap_or_else(|| PathBuf::from("out/bench"));
    let start = a.num("train-start")?.unwrap_or(-15.0);
    crate::bench_window::run(&spans, &cars, steps.max(1), [dt, h, start], &out)?;
    Ok(0)
}

/// `railfem stress`: the stress suite ([`crate::stress`]); the table on stdout and, with
/// `--out`, in `DIR/stress.md`.
fn stress(a: &Args) -> Result<i32, FemError> {
    let mut rows = Vec::new();
    let done = crate::stress::run_cli(
        a.opt("case"),
        &|k| a.num(k),
        a.opt("scheme").unwrap_or("newmark"),
        &mut rows,
    );
    // A stop between cases keeps the table of the completed ones; any other error, none.
    if let Err(e) = &done {
        if !matches!(e, FemError::InterruptedAfter { .. }) {
            return Err(done.unwrap_err());
        }
    }
    let table = crate::stress::table(&rows);
    print!("{table}");
    if let Some(dir) = &a.out {
        std::fs::create_dir_all(dir).map_err(|e| FemError::output(dir, e))?;
        let p = dir.join("stress.md");
        std::fs::write(&p, &table).map_err(|e| FemError::output(&p, e))?;
    }
    done.map(|_| 0)
}

/// `railfem pareto`: run time against error (`crate::pareto`) for `--cases` (default
/// force,sprung,curve); `pareto.csv`, `pareto.md` and `pareto-<case>.svg` in `--out`
/// (default `out/pareto`). `train-bridge` (`crate::pareto_train`, not in the default) writes
/// `pareto-train-bridge.{csv,md}` and `pareto-train-bridge-{Q,dQQ,w}.svg` there.
fn pareto(a: &Args) -> Result<i32, FemError> {
    let mut grid = crate::pareto::Grid::default();
    if let Some(c) = a.opt("cases") {
        grid.cases = c.split(',').map(|x| x.trim().to_string()).collect();
        if let Some(bad) = grid
            .cases
            .iter()
            .find(|x| !["force", "sprung", "curve", "train-bridge"].contains(&x.as_str()))
        {
            return Err(FemError::input(
                "command line",
                format!(
                    "--cases {c}: unknown case `{bad}`; use any of force,sprung,curve,train-bridge"
                ),
            ));
        }
    }
    // The peer file is read (and refused) before the grid runs for minutes.
    let peers = match a.path("peer") {
        Some(p) if grid.cases.iter().any(|c| c == "force") => {
            Some(crate::pareto_peer::read_peer_csv(p)?)
        }
        Some(p) => {
            return Err(FemError::input(
                "command line",
                format!(
                    "--peer {}: the peer runs are of the force case; add force to --cases",
                    p.display()
                ),
            ))
        }
        None => None,
    };
    let retime = match a.num("retime")? {
        None => 0,
        Some(r) if r >= 0.0 && r.fract() == 0.0 && r <= 100.0 => r as usize,
        Some(r) => {
            return Err(FemError::input(
                "command line",
                format!("--retime {r}: give a whole number of rounds, 0 to 100"),
            ))
        }
    };
    if retime > 0 && !grid.cases.iter().any(|c| c == "train-bridge") {
        return Err(FemError::input(
            "command line",
            "--retime times train-bridge runs; add train-bridge to --cases",
        ));
    }
    let out = a.out.clone().unwrap_or_else(|| PathBuf::from("out/pareto"));
    if let Some(at) = a.opt("retime-at") {
        if grid.cases != ["train-bridge"] {
            return Err(FemError::input(
                "command line",
                "--retime-at times train-bridge runs only; give --cases train-bridge",
            ));
        }
        let at = crate::pareto_retime::parse_at(at)?;
        crate::pareto_retime::run_at(&at, retime.max(1), &out)?;
        println!("pareto: results in {}", out.display());
        return Ok(0);
    }
    // The train–bridge case has its own grid, files and figures (`crate::pareto_train`).
    let train = grid.cases.iter().any(|c| c == "train-bridge");
    grid.cases.retain(|c| c != "train-bridge");
    if !grid.cases.is_empty() {
        let runs = crate::pareto::run(&grid, &out)?;
        if let Some(peers) = &peers {
            crate::pareto_peer::write(&runs, peers, &out)?;
        }
    }
    if train {
        let tb = crate::pareto_train::TbGrid {
            existing_only: a.flag("existing"),
            finer_checks: a.flag("finer"),
            ..Default::default()
        };
        let runs = crate::pareto_train::run(&tb, &out)?;
        if retime > 0 {
            crate::pareto_retime::run(&tb, &runs, retime, &out)?;
        }
    }
    println!("pareto: results in {}", out.display());
    Ok(0)
}

/// `railfem critical-radius`: one point of the paper's Figure 7 or 9.
/// `--geometry linear|nonlinear` of the built-in vehicle cases (default linear).
/// `--first-active-set committed|found`, or `default` when it is not given.
fn first_active_set(
    a: &Args,
    default: crate::framework::model::FirstActiveSet,
) -> Result<crate::framework::model::FirstActiveSet, FemError> {
    match a.opt("first-active-set") {
        None => Ok(default),
        Some(w) => crate::framework::model::FirstActiveSet::parse(w).ok_or_else(|| {
            FemError::input(
                "command line",
                format!("--first-active-set {w}: use committed or found"),
            )
        }),
    }
}

fn geometry(a: &Args) -> Result<crate::framework::model::Geometry, FemError> {
    match a.opt("geometry") {
        None => Ok(Default::default()),
        Some(g) => crate::framework::model::Geometry::parse(g).map_err(|_| {
            FemError::input(
                "command line",
                format!("--geometry {g}: use linear (the default) or nonlinear"),
            )
        }),
    }
}

fn critical(a: &Args) -> Result<i32, FemError> {
    use crate::critical::{Criterion, CriticalCase};
    let criterion = match a.opt("criterion").unwrap_or("sliding") {
        "sliding" => Criterion::Sliding,
        "separation" => Criterion::Separation,
        o => {
            return Err(FemError::input(
                "command line",
                format!("--criterion {o}: use sliding or separation"),
            ))
        }
    };
    let tangential: Tangential = crate::choice::parse(
        "command line",
        "--tangential",
        a.opt("tangential").unwrap_or("coulomb"),
    )?;
    if a.flags.iter().any(|f| f == "sweep") {
        if let Some(t) = a.opt("tangential").filter(|t| *t != "coulomb") {
            return Err(FemError::input(
                "command line",
                format!("--tangential {t} with --sweep: the sweep runs the paper's Coulomb law only; drop --sweep and run single points (--speed, --ct, --mu)"),
            ));
        }
        let list = |key: &str, default: &[f64]| -> Result<Vec<f64>, FemError> {
            match a.opt(key) {
                None => Ok(default.to_vec()),
                Some(t) => t
                    .split(',')
                    .map(|x| {
                        x.trim()
                            .parse::<f64>()
                            .ok()
                            .filter(|v| v.is_finite() && *v > 0.0)
                    })
                    .collect::<Option<Vec<f64>>>()
                    .ok_or_else(|| {
                        FemError::input(
                            "command line",
                            format!("--{key} {t}: give positive numbers, comma-separated"),
                        )
                    }),
            }
        };
        let speeds = list("speeds", &[100.0, 140.0, 180.0, 220.0, 260.0])?;
        let cts = list("cts", &[200.0, 400.0, 900.0])?;
        let mus = match criterion {
            Criterion::Sliding => list("mus", &[0.1, 0.2, 0.3])?,
            Criterion::Separation => list("mus", &[0.3])?,
        };
        let out = a
            .out
            .clone()
            .unwrap_or_else(|| PathBuf::from("out/critical"));
        let points = speeds.len() * cts.len() * mus.len();
        let bar = std::sync::Mutex::new(crate::progress::Progress::new(
            "critical-radius",
            points as u64,
            "points",
        ));
        let progress = |f: f64| {
            if let Ok(mut b) = bar.lock() {
                b.fraction(f);
            }
        };
        let pts = crate::critical::sweep(
            criterion,
            &speeds,
            &cts,
            &mus,
            a.num("clothoid")?.unwrap_or(2000.0),
            a.num("dt")?.unwrap_or(0.01),
            geometry(a)?,
            std::thread::available_parallelism().map_or(2, |n| n.get()),
            &progress,
        );
        if let Ok(mut b) = bar.lock() {
            b.finish();
        }
        crate::critical::write_sweep(&pts, criterion, &out)?;
        let mut worst = 0.0f64;
        for (c, r) in &pts {
            if let Ok(r) = r {
                let reference = match criterion {
                    Criterion::Sliding => r.theory,
                    Criterion::Separation => r.lean_at_contact.or(r.theory_at_contact),
                };
                if let (Some(fe), Some(th)) = (r.fe, reference) {
                    worst = worst.max((fe - th).abs() / th);
                }
                let _ = c;
            }
        }
        println!(
            "{} points; largest relative difference FE vs theory: {worst:.3e}; results in {}",
            pts.len(),
            out.display()
        );
        // Stopped between cases: the table holds the first cases, whole.
        crate::framework::interrupt::check_after(|| format!("{} of {points} cases", pts.len()))?;
        return Ok(0);
    }
    let case = CriticalCase {
        criterion,
        speed: a.num("speed")?.unwrap_or(120.0),
        ct: a.num("ct")?.unwrap_or(200.0),
        mu: a.num("mu")?.unwrap_or(0.3),
        clothoid: a.num("clothoid")?.unwrap_or(2000.0),
        dt: a.num("dt")?.unwrap_or(0.01),
        geometry: geometry(a)?,
        tangential,
        polach_spin: polach_spin(a, tangential)?,
    };
    let out = a.out.clone();
    let r = crate::critical::run_with_sections(&case, out.as_deref())?;
    if let Some(o) = &out {
        println!("cross-sections at the onset written to {}", o.display());
    }
    let f = |x: Option<f64>| x.map_or("not reached".to_string(), |v| format!("{v:.1} m"));
    println!(
        "{:?}: V = {} m/s, Ct = {} m, mu = {}{}: FE {} (gross sliding {}), theory (statics) {}, Eq. 25 as printed {}",
        case.criterion, case.speed, case.ct, case.mu,
        if case.tangential == Tangential::Coulomb { String::new() } else { format!(", tangential {}", case.tangential.name()) },
        f(r.fe), f(r.fe_gross), f(r.theory), f(r.theory_printed)
    );
    if let (Some(fe), Some(th)) = (r.fe, r.theory) {
        println!(
            "relative difference FE vs theory: {:.3e}",
            (fe - th).abs() / th
        );
    }
    if let Some(c) = r.outer_contact {
        println!(
            "statics about the FE's outer contact point (y = {:.4} m, z = {:.4} m): {}",
            c[0],
            c[1],
            f(r.theory_at_contact)
        );
        if let (Some(fe), Some(th)) = (r.fe, r.theory_at_contact) {
            println!(
                "relative difference FE vs statics about that point: {:.3e}",
                (fe - th).abs() / th
            );
        }
        if let Some(lean) = r.lean_at_contact {
            let rel = r.fe.map_or(f64::NAN, |fe| (fe - lean).abs() / lean);
            println!(
                "statics with body lean about that point: {lean:.1} m; relative difference FE vs it: {rel:.3e}"
            );
        }
    }
    Ok(0)
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

/// `railfem train-bridge`: see [`crate::train_bridge`] and the usage text.
fn train_bridge(a: &Args) -> Result<i32, FemError> {
    use crate::train_bridge::{build, run, Quake, TrainBridgeCase};
    let mut c = TrainBridgeCase::default();
    let count = |key: &str| -> Result<Option<usize>, FemError> {
        match a.num(key)? {
            None => Ok(None),
            Some(v) if v >= 1.0 && v.fract() == 0.0 && v < 1e9 => Ok(Some(v as usize)),
            Some(v) => Err(FemError::input(
                "command line",
                format!("--{key} {v}: give a whole number ≥ 1"),
            )),
        }
    };
    if let Some(v) = count("cars")? {
        c.cars = v;
    }
    if let Some(v) = count("spans")? {
        c.spans = v;
    }
    if let Some(v) = a.num("span")? {
        c.span = v;
    }
    if let Some(v) = a.num("element-length")? {
        c.element_length = v;
    }
    c.dof_target = count("dof")?;
    if let Some(v) = a.num("speed")? {
        c.speed = v;
    }
    c.radius = a.num("radius")?;
    if let Some(v) = a.num("ct")? {
        c.ct = v;
    }
    c.duration = a.num("duration")?;
    if let Some(v) = a.num("dt")? {
        c.dt = v;
    }
    c.geometry = geometry(a)?;
    c.first_active_set = first_active_set(a, c.first_active_set)?;
    if let Some(v) = count("record-every")? {
        c.record_every = v;
    }
    if let Some(v) = a.num("pier-height")? {
        c.pier_height = v;
    }
    if let Some(v) = a.num("train-start")? {
        c.train_start = v;
    }
    if let Some(list) = a.opt("midspans") {
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
    c.quake = match a.path("quake") {
        None => Quake::None,
        Some(q) if q == Path::new("synthetic") => Quake::Synthetic {
            seed: count("seed")?.unwrap_or(1) as u64,
            pga: a.num("pga")?.unwrap_or(0.3),
            duration: a.num("quake-duration")?.unwrap_or(30.0),
        },
        Some(file) => Quake::File(file.to_path_buf()),
    };
    if let Some(s) = a.opt("solver") {
        c.solver = crate::framework::model::SolverChoice::parse(s).ok_or_else(|| {
            FemError::input(
                "command line",
                format!("--solver {s}: use auto (the default), direct, partitioned or low_rank"),
            )
        })?;
    }
    c.window = crate::train_window::parse_options(a)?;
    let steps = count("steps")?;
    let out = a
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from("out/train_bridge"));
    let block_size = count("block-size")?;
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
        if !a.flags.iter().any(|f| f == "build-only") {
            run(&mut m, &c, steps, None)?;
        }
        return Ok(0);
    }
    if let (Some(q), Some(p)) = (&m.quake, a.path("quake-out")) {
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
    if a.flags.iter().any(|f| f == "build-only") {
        return Ok(0);
    }
    let r = run(&mut m, &c, steps, Some(&out))?;
    println!(
        "{} steps, {} Newton iterations, {:.2} s; results in {}",
        r.steps,
        r.iterations,
        r.wall,
        out.display()
    );
    if let Some(w) = r.window {
        println!(
            "activity window: {} of {} block-steps held ({:.1} %), {} blocks joined, {} held behind",
            w.held_block_steps,
            w.block_steps,
            100.0 * w.held_block_steps as f64 / w.block_steps.max(1) as f64,
            w.joined,
            w.left
        );
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
    if a.flag("assess") {
        crate::assess::after_run(&out, Some(c.speed))?;
    }
    Ok(0)
}

/// `--polach-spin off|polach_1999` (the `moving_axle` key `polach_spin`), checked against
/// the law it belongs to: only `--tangential polach` has the term.
fn polach_spin(a: &Args, tangential: Tangential) -> Result<Option<PolachSpin>, FemError> {
    let Some(v) = a.opt("polach-spin") else {
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

/// A model file's partitioned solver shared among the ranks of `mpirun -n P` (P > 1): each
/// rank factors and condenses its own blocks ([`crate::ranks`]) and forms the residual of
/// its own rows (`Driver::keep_own_rows`). A model on another solver is
/// refused with the fix.
fn share_among_ranks(
    driver: &mut crate::solvers::Driver,
    ex: std::sync::Arc<dyn crate::solvers::exchange::Exchange>,
    path: &Path,
) -> Result<(), FemError> {
    let size = ex.size();
    if driver.partition_stats().is_none() {
        return Err(FemError::input(
            path.display().to_string(),
            format!("[analysis]: under `mpirun -n {size}` the ranks share the partitioned solver's blocks, but `solver = \"{}\"` does not run it for this model's {} equations; set `solver = \"partitioned\"` (and `block_size`, interior equations per block, so that there are at least {size} blocks)", driver.model.analysis.solver.name(), driver.state.q.len()),
        ));
    }
    driver.set_exchange(ex)?;
    // Each rank forms the residual of its own rows, with its columns of K, M, C and its
    // elements; the energy balance is summed over the ranks' rows.
    driver.keep_own_rows();
    Ok(())
}

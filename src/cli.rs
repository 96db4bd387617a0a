//! The `railfem` command line: parse arguments (grammar in [`crate::commands`], clap),
//! run a subcommand, turn any error into one line and an exit code.
//!
//! Exit codes: 0 success; 2 bad input or a failed run (one line on stderr naming the file,
//! the place and the fix — clap's own usage errors included); 1 a check that ran and failed
//! (the conformance kit); 130 a run stopped by SIGINT or SIGTERM ([`crate::framework::interrupt`]).

pub use crate::args::Args;
use crate::command::Context;
use crate::commands::{Cli, Commands, Global};
use crate::framework::error::nearest;
use crate::framework::FemError;
use clap::parser::ValueSource;
use clap::{ArgAction, FromArgMatches};
use std::ffi::{OsStr, OsString};
use std::path::{Path, PathBuf};

pub use crate::commands::clap_command;

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

/// A value clap's parser refused ([`crate::command::number`], [`crate::command::text`]):
/// `--dt abc: not a finite number`.
fn value_error(e: &clap::Error, argv: &[OsString]) -> FemError {
    use clap::error::{ContextKind, ContextValue};
    let arg = e.get(ContextKind::InvalidArg);
    let value = e.get(ContextKind::InvalidValue);
    match (arg, value, std::error::Error::source(e)) {
        (Some(ContextValue::String(arg)), Some(ContextValue::String(value)), Some(why)) => {
            // clap names the option with its value name: `--dt <DT>`.
            let key = arg.split(' ').next().unwrap_or(arg);
            FemError::input("command line", format!("{key} {value}: {why}"))
        }
        _ => usage_error(e, argv),
    }
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
                K::ValueValidation => Err(value_error(&e, &argv)),
                _ => Err(usage_error(&e, &argv)),
            };
        }
    };
    let typed = Cli::from_arg_matches(&m).map_err(|e| usage_error(&e, &argv))?;
    set_limits(&typed.global)?;
    let Some((name, sub)) = m.subcommand() else {
        return Ok(Args {
            command: "help".into(),
            message: Some(cmd.render_long_help().to_string()),
            argv,
            global: typed.global,
            ..Args::default()
        });
    };
    let def = cmd
        .find_subcommand(name)
        .expect("clap matched a declared subcommand");
    let mut a = Args {
        command: name.to_string(),
        argv: argv.clone(),
        global: typed.global,
        cmd: typed.command,
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
    Ok(a)
}

/// Hands `--max-memory` and `--max-steps` to the size guards ([`crate::framework::limits`]).
fn set_limits(g: &Global) -> Result<(), FemError> {
    use crate::framework::limits::{set_command_line, set_from_text, LimitSpec};
    let mut spec = LimitSpec::default();
    for (key, flag, given) in [
        ("max_memory", "max-memory", &g.max_memory),
        ("max_steps", "max-steps", &g.max_steps),
    ] {
        if let Some(v) = given {
            set_from_text(&mut spec, key, v)
                .map_err(|m| FemError::input("command line", format!("--{flag} {v}: {m}")))?;
        }
    }
    set_command_line(spec);
    Ok(())
}

/// What `run.json` says about the command's inputs: its options as parsed (those given),
/// the options of every command, and the output folder `dir` as resolved.
fn options_json(a: &Args, dir: &Path) -> serde_json::Value {
    let mut o = a.cmd.as_ref().map(Commands::options).unwrap_or_default();
    o.extend(crate::command::options_json(&a.global));
    o.insert("out".into(), dir.display().to_string().into());
    serde_json::Value::Object(o)
}

/// The sidecar of the command running in this process, for the signal handler.
static RUNNING: std::sync::Mutex<Option<crate::sidecar::RunRecord>> = std::sync::Mutex::new(None);

/// SIGINT/SIGTERM: a command that stops at a step boundary
/// ([`crate::command::Command::STOPS_AT_STEP`]) is asked to
/// ([`crate::framework::interrupt::request`]); a second signal, or a command that cannot,
/// marks the sidecar and exits at once with 130.
fn install_interrupt_handler(at_step: bool) {
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

/// The output folder of the parsed command as it resolves it (its `--out` or its
/// default); `None` for help text and for commands that write no folder.
pub fn out_dir(a: &Args) -> Option<PathBuf> {
    match (&a.message, &a.cmd) {
        (None, Some(c)) => c.out_dir(),
        _ => None,
    }
}

/// Runs a parsed command with its progress setting, interrupt handler and sidecar
/// (`run.json`, [`crate::sidecar`]); returns the process exit code.
pub fn run(a: &Args) -> Result<i32, FemError> {
    crate::progress::set_quiet(a.global.quiet);
    // Under an MPI launcher every rank runs the same command line into the same folder;
    // only rank 0 writes the sidecar (the ranks would otherwise overwrite each other's).
    let writes_sidecar = crate::sidecar::launcher_rank().unwrap_or(0) == 0;
    let out = out_dir(a);
    let record = out.clone().map(|dir| crate::sidecar::RunRecord {
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
        install_interrupt_handler(a.cmd.as_ref().is_some_and(Commands::stops_at_step));
    }
    let record = record.filter(|_| writes_sidecar);
    let result = dispatch(a, &Context { out });
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

/// Loads the plugins, then prints the help text or runs the command
/// ([`crate::command::Command::run`]); returns the exit code.
fn dispatch(a: &Args, ctx: &Context) -> Result<i32, FemError> {
    for p in &a.global.plugin {
        crate::framework::plugin::load(p)?;
    }
    if let Some(text) = &a.message {
        print!("{text}");
        return Ok(0);
    }
    match &a.cmd {
        Some(c) => c.run(ctx),
        None => {
            print!("{}", clap_command().render_long_help());
            Ok(0)
        }
    }
}

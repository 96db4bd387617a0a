//! The command line (issue 17): every command's `--help` documents every option it accepts
//! with a unit or a default; `--version` names the version and the git revision; the shell
//! completions know every command; today's invocations (README, docs/, tests, .ci) still
//! parse to the same options; clap's usage errors keep the one-line, exit-2 contract; a run
//! interrupted by SIGINT stops at a step boundary with whole CSV lines and a sidecar that
//! says so; an absurd step count is refused before the run starts.

mod common;

use common::{railfem, refused_with, temp_dir};
use std::io::BufRead;
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// The subcommands as declared, with their options' long names.
fn commands() -> Vec<(String, Vec<String>)> {
    let cmd = railfem::cli::clap_command();
    cmd.get_subcommands()
        .map(|s| {
            let longs = s
                .get_arguments()
                .filter_map(|a| a.get_long().map(str::to_string))
                .collect();
            (s.get_name().to_string(), longs)
        })
        .collect()
}

#[test]
fn every_command_has_help_naming_each_option_with_unit_or_default() {
    let cmds = commands();
    for expected in [
        "run",
        "check",
        "elements",
        "integrators",
        "curve",
        "critical-radius",
        "conformance",
        "track",
        "bench",
        "train-bridge",
        "stress",
        "pareto",
        "irregularity",
        "study",
        "assess",
        "contact",
        "completions",
    ] {
        assert!(
            cmds.iter().any(|(c, _)| c == expected),
            "{expected} missing"
        );
    }
    let cmd = railfem::cli::clap_command();
    for (name, longs) in &cmds {
        let o = railfem(&[name, "--help"]);
        let text = String::from_utf8_lossy(&o.stdout);
        assert_eq!(o.status.code(), Some(0), "{name} --help: {o:?}");
        assert!(
            text.contains(&format!("Usage: railfem {name}")),
            "{name}: {text}"
        );
        for l in longs {
            assert!(
                text.contains(&format!("--{l}")),
                "{name} --help lacks --{l}"
            );
        }
        // Each option that takes a number or a choice says its default (or that it has
        // none): the reader must not have to open the source.
        let sub = cmd.find_subcommand(name).unwrap();
        for a in sub.get_arguments() {
            let Some(long) = a.get_long() else { continue };
            if matches!(
                a.get_action(),
                clap::ArgAction::SetTrue | clap::ArgAction::Help
            ) {
                continue;
            }
            let help = a.get_help().map(|h| h.to_string()).unwrap_or_default();
            let said = [
                "default",
                "required",
                "repeatable",
                "per case",
                "case:",
                "FILE",
                "DIR",
            ]
            .iter()
            .any(|w| help.contains(w))
                || a.get_value_names()
                    .is_some_and(|v| v.iter().any(|n| n.contains("DIR") || n.contains("FILE")));
            assert!(said, "{name} --{long}: help `{help}` gives no default");
        }
    }
}

#[test]
fn version_names_the_package_version_and_git_revision() {
    let o = railfem(&["--version"]);
    assert_eq!(o.status.code(), Some(0));
    let text = String::from_utf8_lossy(&o.stdout).trim().to_string();
    // The revision the binary was built from: this checkout's HEAD, or "unknown" outside
    // a git checkout (a crates.io package).
    let head = Command::new("git")
        .args(["rev-parse", "--short", "HEAD"])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .ok()
        .filter(|o| o.status.success())
        .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
        .unwrap_or_else(|| "unknown".into());
    assert_eq!(
        text,
        format!("railfem {} (git {head})", env!("CARGO_PKG_VERSION"))
    );
}

#[test]
fn completions_know_every_command_and_option() {
    for shell in ["bash", "zsh", "fish"] {
        let o = railfem(&["completions", shell]);
        assert_eq!(o.status.code(), Some(0), "{shell}: {o:?}");
        let text = String::from_utf8_lossy(&o.stdout);
        for (name, longs) in commands() {
            assert!(text.contains(&name), "{shell}: no {name}");
            for l in longs {
                assert!(text.contains(&l), "{shell}: no {l} of {name}");
            }
        }
    }
    refused_with(
        "completions tcsh",
        &railfem(&["completions", "tcsh"]),
        &["tcsh", "bash"],
    );
}

/// Every invocation shown in README.md, docs/, .ci and the tests, with what it must parse to.
#[test]
fn todays_invocations_parse_to_the_same_options() {
    let table: &[&[&str]] = &[
        &["curve", "--ct", "200", "--out", "out/fig6_ct200"],
        &["curve", "--ct", "200", "--dt", "0.005", "--out", "out/x"],
        &[
            "curve",
            "--quick",
            "--geometry",
            "nonlinear",
            "--speed",
            "70",
            "--radius",
            "4000",
            "--ct",
            "0",
            "--out",
            "o",
        ],
        &["curve", "--quiet", "--out", "/tmp/x"],
        &["curve", "--quick", "--tangential", "kalker_linear"],
        &[
            "curve",
            "--lengths",
            "1,2,3,4,5",
            "--penalty",
            "1e9",
            "--mu",
            "0.2",
            "--vtk",
            "10",
            "--anti-roll",
            "1e6",
            "--duration",
            "3",
        ],
        &["run", "examples/models/sdof.toml", "--out", "out/sdof"],
        &[
            "run",
            "model.toml",
            "--plugin",
            "target/release/libmy_plugin.so",
        ],
        &["run", "m.toml", "--max-memory", "8G", "--max-steps", "1e8"],
        &["check", "MODEL.toml"],
        &[
            "matrices",
            "examples/models/cantilever.toml",
            "--out",
            "out/m",
        ],
        &["elements"],
        &["elements", "--plugin", "p.so"],
        &["conformance", "--element", "suspension"],
        &[
            "conformance",
            "--plugin",
            "target/release/libmy_plugin.so",
            "--element",
            "cable",
        ],
        &[
            "critical-radius",
            "--criterion",
            "separation",
            "--speed",
            "220",
            "--ct",
            "200",
            "--mu",
            "0.3",
            "--out",
            "out/fig10",
        ],
        &[
            "critical-radius",
            "--sweep",
            "--criterion",
            "sliding",
            "--clothoid",
            "1000",
            "--geometry",
            "nonlinear",
            "--out",
            "out/fig7_nl",
        ],
        &[
            "critical-radius",
            "--sweep",
            "--criterion",
            "separation",
            "--speeds",
            "180,200",
            "--cts",
            "200",
            "--mus",
            "0.3",
            "--dt",
            "0.02",
        ],
        &["track", "--radius", "3000", "--ct", "150", "--out", "d"],
        &[
            "bench",
            "--sizes",
            "1e4,1e5,1e6",
            "--steps",
            "20",
            "--out",
            "/tmp/b",
        ],
        &[
            "bench",
            "--case",
            "train-bridge",
            "--sizes",
            "1043430",
            "--cars",
            "12",
            "--steps",
            "20",
            "--geometry",
            "nonlinear",
            "--dt",
            "5e-4",
        ],
        &[
            "train-bridge",
            "--cars",
            "2",
            "--spans",
            "3",
            "--span",
            "20",
            "--element-length",
            "1",
            "--speed",
            "60",
            "--radius",
            "3000",
            "--ct",
            "100",
            "--duration",
            "1",
            "--dt",
            "0.01",
            "--record-every",
            "2",
            "--pier-height",
            "8",
            "--midspans",
            "1,2",
            "--steps",
            "5",
            "--geometry",
            "linear",
            "--out",
            "o",
        ],
        &[
            "train-bridge",
            "--dof",
            "1e6",
            "--quake",
            "synthetic",
            "--seed",
            "3",
            "--pga",
            "0.2",
            "--quake-duration",
            "10",
            "--quake-out",
            "q.csv",
            "--build-only",
        ],
        &["train-bridge", "--quake", "record.csv"],
        &[
            "stress",
            "--case",
            "beam",
            "--omega-dt",
            "1e-2",
            "--scheme",
            "newmark",
            "--steps",
            "2000",
        ],
        &[
            "stress",
            "--case",
            "drop",
            "--height",
            "0.01",
            "--dt",
            "2e-5",
            "--duration",
            "0.2",
            "--penalty",
            "1e10",
        ],
        &[
            "stress", "--case", "dip", "--speed", "15", "--depth", "0.002",
        ],
        &[
            "stress",
            "--case",
            "stick-slip",
            "--overshoot",
            "1.5",
            "--out",
            "o",
        ],
        &["pareto", "--out", "out/pareto", "--cases", "force,sprung"],
        &[
            "irregularity",
            "--psd",
            "fra4",
            "--seed",
            "1",
            "--wavelengths",
            "1,50",
            "--length",
            "2000",
            "--step",
            "0.1",
            "--components",
            "vertical",
            "--out",
            "out/irr",
        ],
        &[
            "study",
            "plan.toml",
            "--threads",
            "2",
            "--stop-after",
            "10",
            "--out",
            "out/s",
        ],
        &["help"],
        &[],
    ];
    const PATHS: [&str; 3] = ["quake", "quake-out", "plugin"];
    for argv in table {
        let a = railfem::cli::parse(argv).unwrap_or_else(|e| panic!("{argv:?}: {e}"));
        let Some(cmd) = argv.first() else {
            assert!(a.message.is_some(), "bare railfem prints help");
            continue;
        };
        assert_eq!(&a.command, cmd, "{argv:?}");
        // Each `--key value` and `--flag` of argv reaches the command unchanged.
        let mut i = 1;
        while i < argv.len() {
            let Some(key) = argv[i].strip_prefix("--") else {
                assert_eq!(a.positional[0], argv[i], "{argv:?}");
                i += 1;
                continue;
            };
            let next = argv.get(i + 1).filter(|v| !v.starts_with("--"));
            match (key, next) {
                ("out", Some(v)) => assert_eq!(a.out.as_deref(), Some(Path::new(v))),
                ("plugin", Some(v)) => assert!(a.plugins.iter().any(|p| p == Path::new(v))),
                (k, Some(v)) if PATHS.contains(&k) => {
                    assert_eq!(a.path(k), Some(Path::new(v)), "{argv:?}")
                }
                (k, Some(v)) => assert_eq!(a.opt(k), Some(*v), "{argv:?} --{k}"),
                (k, None) => assert!(a.flag(k), "{argv:?}: flag --{k}"),
            }
            i += if next.is_some() { 2 } else { 1 };
        }
    }
}

#[test]
fn usage_errors_are_one_line_with_the_fix_and_exit_2() {
    let cases: &[(&[&str], &[&str])] = &[
        (
            &["curve", "--spede", "3"],
            &["--spede", "did you mean `--speed`?", "--anti-roll"],
        ),
        (
            &["curve", "--dt"],
            &["--dt", "value", "railfem curve --help"],
        ),
        (&["run"], &["MODEL", "railfem run --help"]),
        (&["frobnicate"], &["frobnicate", "railfem --help"]),
        (
            &["track", "--sizes", "1e4"],
            &["`railfem track` has no option `--sizes`", "--radius"],
        ),
        (
            &["curve", "--dt", "abc"],
            &["--dt abc", "not a finite number"],
        ),
        (&["curve", "--max-steps", "1e12"], &["1e12", "at most"]),
        (
            &["train-bridge", "--first-active-set", "held", "--steps", "1"],
            &["--first-active-set held", "committed or found"],
        ),
        (
            &["curve", "--first-active-set", "Found"],
            &["--first-active-set Found", "committed or found"],
        ),
        // `--case` is `--cases` (issue 16 names `railfem pareto --case train-bridge`): the
        // value reaches the case check, which names the cases it knows.
        (
            &["pareto", "--case", "train-brigde"],
            &[
                "unknown case `train-brigde`",
                "force,sprung,curve,train-bridge",
            ],
        ),
    ];
    for (argv, expect) in cases {
        let err = refused_with(&format!("{argv:?}"), &railfem(argv), expect);
        assert!(err.starts_with("error: command line:"), "{err}");
    }
}

/// `[analysis] integrator` resolves through the integrator registry: `railfem integrators`
/// lists the registered names with their keys; an unknown name, or an unknown key of a
/// registered one, is refused with one line naming the file, the key and the valid
/// choices (exit 2); `"bathe"` with its `gamma` runs.
#[test]
fn integrators_are_listed_and_resolved_by_name() {
    let o = railfem(&["integrators"]);
    let text = String::from_utf8_lossy(&o.stdout);
    assert_eq!(o.status.code(), Some(0));
    for name in [
        "bathe",
        "generalized_alpha",
        "hht",
        "newmark",
        "gamma [-] (default 0.5)",
    ] {
        assert!(text.contains(name), "{name} missing from:\n{text}");
    }
    let dir = temp_dir("integrators");
    let sdof = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/models/sdof.toml"),
    )
    .unwrap();
    let with = |integrator: &str, table: &str| {
        sdof.replace(
            "integrator = \"newmark\"\nbeta = 0.25\ngamma = 0.5\n",
            &format!("integrator = \"{integrator}\"\n"),
        )
        .replace(
            "initial_static = false\n",
            &format!("initial_static = false\n{table}"),
        )
    };
    let run = |name: &str, text: String| {
        let path = dir.join(name);
        std::fs::write(&path, text).unwrap();
        railfem(&[
            "run",
            path.to_str().unwrap(),
            "--out",
            dir.join("out").to_str().unwrap(),
        ])
    };
    let o = run("unknown.toml", with("bathes", ""));
    refused_with(
        "unknown integrator",
        &o,
        &[
            "unknown.toml",
            "[analysis] integrator",
            "did you mean `bathe`",
            "newmark",
        ],
    );
    let o = run(
        "key.toml",
        with("bathe", "\n[analysis.integrator_parameters]\ngama = 0.5\n"),
    );
    refused_with(
        "unknown key",
        &o,
        &["key.toml", "`gama`", "valid keys: gamma"],
    );
    let o = run(
        "bathe.toml",
        with(
            "bathe",
            "\n[analysis.integrator_parameters]\ngamma = 0.5857864376\n",
        ),
    );
    assert_eq!(o.status.code(), Some(0), "{o:?}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A model file whose duration is absurd is refused before its first step: exit 2, one
/// line with the step count (1e300 s / 0.005 s = 2e302 steps) and the fix. Also from the
/// command line (the curve case) and through a raised `--max-steps` (capped at 1e9).
#[test]
fn an_absurd_duration_is_refused_before_the_run_starts() {
    let dir = temp_dir("absurd");
    let model = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/models/sdof.toml"),
    )
    .unwrap()
    .replace("duration = 2.0", "duration = 1e300");
    let path = dir.join("absurd.toml");
    std::fs::write(&path, model).unwrap();
    let out = dir.join("out");
    let t = Instant::now();
    let o = railfem(&[
        "run",
        path.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    refused_with(
        "duration 1e300",
        &o,
        &["absurd.toml", "2e302 steps", "duration", "dt"],
    );
    assert!(t.elapsed() < Duration::from_secs(30), "it ran");
    // Raising the budget does not let 1e10 steps through: the flag itself is capped.
    let o = railfem(&["run", path.to_str().unwrap(), "--max-steps", "1e10"]);
    refused_with("max-steps 1e10", &o, &["--max-steps", "1e9"]);
    let o = railfem(&[
        "curve",
        "--quick",
        "--duration",
        "1e300",
        "--out",
        out.to_str().unwrap(),
    ]);
    refused_with("curve duration", &o, &["steps", "duration"]);
    let _ = std::fs::remove_dir_all(&dir);
}

/// Starts `railfem ARGS`, waits for its first progress line on stderr (the run is under
/// way, its signal handler in place), sends `signal` and returns (exit code, stderr).
fn interrupt(args: &[&str], signal: libc::c_int) -> (Option<i32>, String) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_railfem"))
        .args(args)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start railfem");
    let stderr = child.stderr.take().unwrap();
    let (tx, rx) = std::sync::mpsc::channel();
    let reader = std::thread::spawn(move || {
        let mut all = String::new();
        for line in std::io::BufReader::new(stderr)
            .lines()
            .map_while(Result::ok)
        {
            let _ = tx.send(line.clone());
            all.push_str(&line);
            all.push('\n');
        }
        all
    });
    // The first progress line comes after 1 s and 10 % of the steps (or 10 s).
    let first = rx
        .recv_timeout(Duration::from_secs(300))
        .expect("no progress line");
    // In a pipe, progress is plain lines: `curve: 10 % (2021/20205 steps, …, ETA 16 s)`
    // (`points/s` for a sweep).
    assert!(
        first.contains(" % (") && first.contains("/s, ETA"),
        "{first}"
    );
    // SAFETY: kill(2) with a valid pid of our own child and a valid signal number.
    let r = unsafe { libc::kill(child.id() as libc::pid_t, signal) };
    assert_eq!(r, 0);
    let status = child.wait().unwrap();
    let err = reader.join().unwrap();
    assert!(!err.contains('\r'), "a progress frame in a pipe: {err:?}");
    (status.code(), err)
}

/// The time `t` of `interrupted at t = … s` in the sidecar's status.
fn interrupted_at(dir: &Path) -> f64 {
    let text = std::fs::read_to_string(dir.join("run.json")).expect("run.json");
    let v: serde_json::Value = serde_json::from_str(&text).expect("run.json is JSON");
    let status = v["status"].as_str().unwrap();
    assert_eq!(v["railfem"]["version"], env!("CARGO_PKG_VERSION"));
    assert!(v["start"].as_str().unwrap().ends_with('Z'));
    status
        .strip_prefix("interrupted at t = ")
        .and_then(|s| s.strip_suffix(" s"))
        .unwrap_or_else(|| panic!("status: {status}"))
        .parse()
        .unwrap()
}

/// Every line of a CSV is whole: ends with a newline, as many fields as the header, each
/// a number; returns the first column of the last row.
fn whole_lines(path: &Path) -> f64 {
    let text = std::fs::read_to_string(path).unwrap();
    assert!(text.ends_with('\n'), "{}: cut line", path.display());
    let mut lines = text.lines();
    let n = lines.next().unwrap().split(',').count();
    let mut last = f64::NAN;
    for l in lines {
        let f: Vec<&str> = l.split(',').collect();
        assert_eq!(f.len(), n, "{}: {l}", path.display());
        for x in &f {
            assert!(x.parse::<f64>().is_ok(), "{}: {l}", path.display());
        }
        last = f[0].parse().unwrap();
    }
    last
}

/// `railfem run` on the single-DOF model with 4e6 steps of 1 µs (far longer than the
/// test waits): SIGINT stops it at a step boundary. The recorder files end on whole lines,
/// their last time is the time of the step the sidecar names, before the end (4 s), and
/// the exit code is 130.
#[test]
fn sigint_stops_a_model_run_at_a_step_with_whole_files() {
    let dir = temp_dir("sigint_run");
    let model = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/models/sdof.toml"),
    )
    .unwrap()
    .replace("dt = 0.005", "dt = 1e-6\nrecord_every = 1000")
    .replace("duration = 2.0", "duration = 4.0");
    let path = dir.join("long.toml");
    std::fs::write(&path, model).unwrap();
    let out = dir.join("out");
    let (code, err) = interrupt(
        &[
            "run",
            path.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ],
        libc::SIGINT,
    );
    assert_eq!(code, Some(130), "{err}");
    assert!(err.contains("interrupted at t ="), "{err}");
    let t = interrupted_at(&out);
    assert!(t > 0.0 && t < 4.0, "t = {t}");
    for f in ["disp.csv", "vel.csv"] {
        let last = whole_lines(&out.join(f));
        assert!(
            (last - t).abs() < 1e-6,
            "{f}: last row at {last}, stopped at {t}"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// `railfem curve` (the paper's full case, 20 205 steps): SIGTERM stops it as SIGINT does;
/// curve.csv is written up to the step named by the sidecar, whole lines, exit 130.
#[test]
fn sigterm_stops_the_curve_case_with_whole_files() {
    let dir = temp_dir("sigterm_curve");
    let (code, err) = interrupt(&["curve", "--out", dir.to_str().unwrap()], libc::SIGTERM);
    assert_eq!(code, Some(130), "{err}");
    let t = interrupted_at(&dir);
    let last = whole_lines(&dir.join("curve.csv"));
    assert!(
        (last - t).abs() < 1e-3,
        "curve.csv ends at {last}, stopped at {t}"
    );
    assert!(t < 200.0, "t = {t}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A run refused after its output directory exists (here: made beforehand) leaves a
/// sidecar that says it failed and why; a completed one says `completed`, with its argv.
#[test]
fn the_sidecar_says_completed_or_failed() {
    let dir = temp_dir("sidecar");
    let bad = dir.join("bad.toml");
    std::fs::write(&bad, "[[node]]\nid = 1\n").unwrap();
    let out = dir.join("out");
    std::fs::create_dir_all(&out).unwrap();
    let o = railfem(&["run", bad.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    refused_with("bad model", &o, &["bad.toml"]);
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("run.json")).unwrap()).unwrap();
    let status = v["status"].as_str().unwrap();
    assert!(
        status.starts_with("failed: ") && status.contains("bad.toml"),
        "{status}"
    );
    assert_eq!(v["command"], "run");

    let good = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/models/sdof.toml");
    let out = dir.join("good");
    let o = railfem(&[
        "run",
        good.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--quiet",
    ]);
    assert_eq!(o.status.code(), Some(0));
    assert!(
        o.stderr.is_empty(),
        "--quiet: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("run.json")).unwrap()).unwrap();
    assert_eq!(v["status"], "completed");
    assert_eq!(v["argv"][1], good.to_str().unwrap());
    assert_eq!(v["options"]["out"], out.to_str().unwrap());
    assert_eq!(v["options"]["quiet"], true);
    // Start and end are UTC ISO 8601 to the second, end not before start.
    let (start, end) = (v["start"].as_str().unwrap(), v["end"].as_str().unwrap());
    for t in [start, end] {
        let b = t.as_bytes();
        assert!(
            t.len() == 20 && b[4] == b'-' && b[10] == b'T' && b[19] == b'Z',
            "{t}"
        );
    }
    assert!(end >= start, "{start} .. {end}");
    // The recorder's header carries units (quantity disp of ux: m).
    let head = std::fs::read_to_string(out.join("disp.csv")).unwrap();
    assert_eq!(head.lines().next(), Some("time [s],1_ux [m]"));
    let head = std::fs::read_to_string(out.join("vel.csv")).unwrap();
    assert_eq!(head.lines().next(), Some("time [s],1_ux [m/s]"));
    let _ = std::fs::remove_dir_all(&dir);
}

/// `railfem help` (and a bare `railfem`) lists every command.
#[test]
fn help_lists_every_command() {
    for argv in [&["help"][..], &[]] {
        let o = railfem(argv);
        assert_eq!(o.status.code(), Some(0));
        let text = String::from_utf8_lossy(&o.stdout);
        for (name, _) in commands() {
            assert!(text.contains(&name), "{argv:?}: {name} missing");
        }
    }
}

/// The data rows (after the header) of a CSV file, as text.
fn data_rows(path: &Path) -> Vec<String> {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    assert!(text.ends_with('\n'), "{}: cut line", path.display());
    text.lines().skip(1).map(str::to_string).collect()
}

/// `railfem train-bridge` (one carriage at 1 m/s over two spans: about 17 000 steps):
/// SIGINT stops it at a step boundary with exit 130. wheels.csv and midspan.csv hold whole
/// rows up to the time run.json names, and those rows are, byte for byte, the first rows
/// of an uninterrupted run that ends a few steps later (same time step, so the same
/// steps: the stop cuts the run, it does not change it).
#[test]
fn sigint_stops_the_train_bridge_case_with_the_rows_of_a_whole_run() {
    let dir = temp_dir("sigint_train_bridge");
    let cut = dir.join("cut");
    let base = [
        "train-bridge",
        "--cars",
        "1",
        "--spans",
        "2",
        "--speed",
        "1",
    ];
    let mut args = base.to_vec();
    args.extend(["--out", cut.to_str().unwrap()]);
    let (code, err) = interrupt(&args, libc::SIGINT);
    assert_eq!(code, Some(130), "{err}");
    let t = interrupted_at(&cut);
    assert!(t > 0.0, "t = {t}");
    let mut cut_rows = Vec::new();
    for f in ["wheels.csv", "midspan.csv"] {
        let last = whole_lines(&cut.join(f));
        assert!(
            (last - t).abs() < 1e-6,
            "{f}: last row at {last}, stopped at {t}"
        );
        cut_rows.push(data_rows(&cut.join(f)));
    }
    // The same case run to a little past t (the last, shortened step beyond the rows
    // compared).
    let whole = dir.join("whole");
    let duration = format!("{}", t + 0.025);
    let mut args = base.to_vec();
    args.extend(["--duration", &duration, "--out", whole.to_str().unwrap()]);
    let o = railfem(&args);
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    for (f, rows) in ["wheels.csv", "midspan.csv"].iter().zip(&cut_rows) {
        let full = data_rows(&whole.join(f));
        assert!(
            full.len() > rows.len(),
            "{f}: {} rows vs {}",
            full.len(),
            rows.len()
        );
        assert_eq!(&full[..rows.len()], &rows[..], "{f}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// `railfem critical-radius --sweep` over sixteen speeds: SIGINT stops it at a case
/// boundary (the cases under way finish, no new one starts) with exit 130 and run.json
/// saying how many cases are done. critical_separation.csv holds whole rows, fewer than
/// the sweep's, and they equal the rows of an uninterrupted sweep over those first speeds.
#[test]
fn sigint_stops_the_critical_radius_sweep_between_cases() {
    let dir = temp_dir("sigint_sweep");
    let speeds = [
        "180", "185", "190", "195", "200", "205", "210", "215", "220", "225", "230", "235", "240",
        "245", "250", "255",
    ];
    let sweep = |s: &str, out: &Path| -> Vec<String> {
        [
            "critical-radius",
            "--sweep",
            "--criterion",
            "separation",
            "--cts",
            "200",
            "--clothoid",
            "300",
            "--speeds",
            s,
            "--out",
            out.to_str().unwrap(),
        ]
        .iter()
        .map(|a| a.to_string())
        .collect()
    };
    let cut = dir.join("cut");
    let all = speeds.join(",");
    let args = sweep(&all, &cut);
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let (code, err) = interrupt(&args, libc::SIGINT);
    assert_eq!(code, Some(130), "{err}");
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(cut.join("run.json")).unwrap()).unwrap();
    let status = v["status"].as_str().unwrap().to_string();
    let rows = data_rows(&cut.join("critical_separation.csv"));
    assert_eq!(
        status,
        format!("interrupted after {} of {} cases", rows.len(), speeds.len())
    );
    assert!(!rows.is_empty() && rows.len() < speeds.len(), "{rows:?}");
    for r in &rows {
        assert_eq!(r.split(',').count(), 11, "{r}");
    }
    let whole = dir.join("whole");
    let first = speeds[..rows.len()].join(",");
    let args = sweep(&first, &whole);
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let o = railfem(&args);
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    assert_eq!(data_rows(&whole.join("critical_separation.csv")), rows);
    let _ = std::fs::remove_dir_all(&dir);
}

/// Under an MPI launcher every rank runs the same command into the same folder: only rank
/// 0 writes run.json (the launcher's rank variable, Open MPI's or PMI's, says which rank a
/// process is), while every rank still writes its outputs as asked.
#[test]
fn only_rank_zero_writes_the_sidecar() {
    let dir = temp_dir("sidecar-rank");
    let model = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/models/sdof.toml");
    for (var, rank, expect) in [
        ("OMPI_COMM_WORLD_RANK", "1", false),
        ("PMI_RANK", "3", false),
        ("OMPI_COMM_WORLD_RANK", "0", true),
    ] {
        let out = dir.join(format!("{var}-{rank}"));
        let o = std::process::Command::new(env!("CARGO_BIN_EXE_railfem"))
            .args(["run", model.to_str().unwrap(), "--quiet", "--out"])
            .arg(&out)
            .env(var, rank)
            .output()
            .expect("railfem runs");
        assert_eq!(o.status.code(), Some(0), "{var}={rank}");
        assert_eq!(out.join("run.json").exists(), expect, "{var}={rank}");
        assert!(
            std::fs::read_dir(&out).unwrap().count() > usize::from(expect),
            "{var}={rank}: outputs"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

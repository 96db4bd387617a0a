//! Hostile inputs generated, not listed: every shipped example model, mutated
//! ([`mutate`]: extreme numbers, deleted and duplicated keys, tables and array entries,
//! values of the wrong type, JSON keys written twice), is given to `railfem check` — and
//! every third case, with its step count capped, to `railfem run` — as a subprocess with a
//! time limit. Every case must end with exit code 0 or 2 (never a signal, a panic or a
//! hang), and a refusal must be one line per problem naming the file.
//!
//! The inputs beside the model files are mutated too ([`mutated_companion_inputs_end_in_exit_0_or_2`]):
//! vehicle files, train tables (`[[vehicle]]` with `vehicles = [...]` and a speed table),
//! irregularity CSVs, study plans and study checkpoints, each given to the command that
//! reads it (`check` for the first three, `study` for the last two).
//!
//! The default run is 600 cases from a fixed seed (about 15 s on two cores), and 100 of the
//! companion inputs.
//! `RAILFEM_MUTATIONS=N` sets the number of cases, `RAILFEM_MUTATION_SECONDS=T` runs cases
//! for T seconds instead, `RAILFEM_MUTATION_SEED=S` changes the seed; a failure prints the
//! seed of its case and the mutations, and keeps the file in the temp directory.

mod common;
#[path = "hostile/mutate.rs"]
mod mutate;

use mutate::{cap_work, case, Rng};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// Longest a case may take (the machine is shared; a healthy case takes well under 1 s).
const LIMIT: Duration = Duration::from_secs(30);
/// Steps a `run` case may take.
const RUN_STEPS: i64 = 30;

fn examples() -> Vec<(PathBuf, toml::Value)> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/models");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .expect("examples/models")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "toml" || e == "json"))
        .collect();
    files.sort();
    files
        .into_iter()
        .map(|p| {
            let text = std::fs::read_to_string(&p).expect("read example");
            let v: toml::Value = if p.extension().is_some_and(|e| e == "json") {
                serde_json::from_str(&text).expect("example JSON")
            } else {
                toml::from_str(&text).expect("example TOML")
            };
            (p, v)
        })
        .collect()
}

/// Whether the binary refuses an oversized track mesh by itself, in seconds (the size guard
/// of the generators, docs/robustness.md). Every mutated case relies on it.
fn size_guarded(dir: &Path) -> bool {
    let p = dir.join("probe.toml");
    std::fs::write(
        &p,
        "[analysis]\nkind = \"static\"\n[track]\nsegments = [{type = \"straight\", length = 1.0e13}]\n",
    )
    .expect("write probe");
    matches!(
        run_limited(&["check", p.to_str().expect("utf-8")], Duration::from_secs(5)),
        Some((Some(2), _, t)) if t < Duration::from_secs(10)
    )
}

/// Runs `railfem args`, killing it after `limit`: `(exit code or None for a signal,
/// stderr, elapsed)`; `None` overall for a hang.
fn run_limited(args: &[&str], limit: Duration) -> Option<(Option<i32>, String, Duration)> {
    let t0 = Instant::now();
    let mut child = Command::new(env!("CARGO_BIN_EXE_railfem"))
        .args(args)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("spawn railfem");
    let mut stderr = child.stderr.take().expect("stderr");
    let reader = std::thread::spawn(move || {
        let mut s = String::new();
        let _ = std::io::Read::read_to_string(&mut stderr, &mut s);
        s
    });
    loop {
        if let Some(status) = child.try_wait().expect("wait") {
            let err = reader.join().unwrap_or_default();
            return Some((status.code(), err, t0.elapsed()));
        }
        if t0.elapsed() > limit {
            let _ = child.kill();
            let _ = child.wait();
            return None;
        }
        std::thread::sleep(Duration::from_millis(5));
    }
}

/// Checks one outcome; `Err` describes the failure.
fn judge(out: Option<(Option<i32>, String, Duration)>, file: &str) -> Result<Duration, String> {
    judge_any(out, &[file])
}

/// [`judge`] for a case of several files: every line of a refusal names one of `files`.
fn judge_any(
    out: Option<(Option<i32>, String, Duration)>,
    files: &[&str],
) -> Result<Duration, String> {
    let Some((code, err, t)) = out else {
        return Err(format!("no end within {LIMIT:?}"));
    };
    match code {
        Some(0) => Ok(t),
        Some(2) => {
            if err.contains("internal error") || err.contains("panicked") {
                return Err(format!("panic: {err}"));
            }
            let lines: Vec<&str> = err.lines().filter(|l| !l.starts_with("warning:")).collect();
            if lines.is_empty() {
                return Err("exit 2 without a message".into());
            }
            if let Some(l) = lines.iter().find(|l| !files.iter().any(|f| l.contains(f))) {
                return Err(format!("a line does not name the file ({files:?}): {l}"));
            }
            Ok(t)
        }
        other => Err(format!("exit {other:?} (None: killed by a signal): {err}")),
    }
}

#[test]
fn mutated_examples_end_in_exit_0_or_2() {
    let env = |k: &str| std::env::var(k).ok().and_then(|v| v.parse::<u64>().ok());
    let seed = env("RAILFEM_MUTATION_SEED").unwrap_or(20);
    let seconds = env("RAILFEM_MUTATION_SECONDS");
    let cases = env("RAILFEM_MUTATIONS").unwrap_or(600);
    let models = examples();
    assert!(models.len() >= 5, "examples/models: {models:?}");
    let dir = common::temp_dir("mutations");
    assert!(
        size_guarded(&dir),
        "a 1e13 m track must be refused (exit 2) within 5 s by the size guard"
    );
    let t0 = Instant::now();
    let (mut done, mut ran) = (0u64, 0u64);
    let mut slowest = Duration::ZERO;
    let mut failures = Vec::new();
    for k in 0.. {
        let over = match seconds {
            Some(s) => t0.elapsed().as_secs() >= s,
            None => k >= cases,
        };
        if over {
            break;
        }
        let case_seed = seed.wrapping_mul(1_000_003).wrapping_add(k);
        let mut rng = Rng(case_seed);
        let (src, base) = &models[(k as usize) % models.len()];
        let c = case(base, &mut rng);
        let stem = src.file_stem().and_then(|s| s.to_str()).unwrap_or("m");
        let name = format!("{stem}-{case_seed}.{}", c.ext);
        let path = dir.join(&name);
        std::fs::write(&path, &c.text).expect("write case");
        let p = path.to_str().expect("utf-8 temp path");
        let mut outcome = judge(run_limited(&["check", p], LIMIT), &name);
        if let Ok(t) = &outcome {
            slowest = slowest.max(*t);
        }
        // Every third case also runs, a few steps long.
        if outcome.is_ok() && k % 3 == 0 {
            let capped = match c.ext {
                "toml" => toml::from_str::<toml::Value>(&c.text).ok(),
                _ => None,
            };
            if let Some(mut v) = capped {
                cap_work(&mut v, RUN_STEPS);
                if let Ok(text) = toml::to_string(&v) {
                    std::fs::write(&path, text).expect("write case");
                    let out = dir.join(format!("out-{case_seed}"));
                    outcome = judge(
                        run_limited(&["run", p, "--out", out.to_str().expect("utf-8")], LIMIT),
                        &name,
                    )
                    .map_err(|e| format!("run: {e}"));
                    ran += 1;
                    let _ = std::fs::remove_dir_all(&out);
                }
            }
        }
        match outcome {
            Ok(t) => {
                slowest = slowest.max(t);
                let _ = std::fs::remove_file(&path);
            }
            Err(e) => failures.push(format!(
                "{name} (seed {case_seed}; {}): {e}",
                c.what.join("; ")
            )),
        }
        done += 1;
    }
    println!(
        "{done} mutated models ({ran} also run) in {:.1} s, slowest case {:.2} s, {} failures",
        t0.elapsed().as_secs_f64(),
        slowest.as_secs_f64(),
        failures.len()
    );
    assert!(
        failures.is_empty(),
        "{} of {done} cases failed (files kept in {}):\n{}",
        failures.len(),
        dir.display(),
        failures.join("\n")
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// A train of two kinds of vehicle (`vehicles = [...]`) on a speed table, on rigid straight
/// track: the train table the companion cases mutate.
const TRAIN_TABLE: &str = r#"
[analysis]
kind = "static"

[track]
segments = [{type = "straight", length = 80.0}]
element_length = 0.6
support = {type = "rigid"}

[[vehicle]]
name = "mixed"
start = 50.0
speed_table = [[0.0, 0.0], [1.0, 2.0], [3.0, 2.0]]
wheel = {mu = 0.3}
coupler = {k = [5e7, 1e5, 1e5], c = [1e5, 1e4, 1e4]}
vehicles = [{preset = "sks700", count = 1}, {preset = "sks700", carriage = {car_length = 20.0}}]
record = {wheels = "wheels.csv"}
"#;

/// A model that rides a vehicle file `{file}` on rigid straight track.
const VEHICLE_FILE_MODEL: &str = r#"
[analysis]
kind = "static"

[track]
segments = [{type = "straight", length = 60.0}]
element_length = 0.6
support = {type = "rigid"}

[[vehicle]]
file = "{file}"
start = 30.0
speed = 0.0
"#;

/// A study of the single-DOF oscillator (`base = "sdof.toml"` beside it) over its mass and
/// stiffness: 3 × 2 cases, of which a run computes at most two (`--stop-after`).
const PLAN: &str = r#"
base = "sdof.toml"
histories = false

[[axis]]
name = "element.0.m"
values = [500.0, 1000.0, 2000.0]

[[axis]]
name = "element.1.k.0"
start = 2.0e6
stop = 4.0e6
count = 2
"#;

/// Runs `railfem study` on `plan` into `out` for at most `after` cases, one thread.
fn study(plan: &Path, out: &Path, after: &str) -> Option<(Option<i32>, String, Duration)> {
    run_limited(
        &[
            "study",
            plan.to_str().expect("utf-8"),
            "--out",
            out.to_str().expect("utf-8"),
            "--stop-after",
            after,
            "--threads",
            "1",
        ],
        LIMIT,
    )
}

#[test]
fn mutated_companion_inputs_end_in_exit_0_or_2() {
    let env = |k: &str| std::env::var(k).ok().and_then(|v| v.parse::<u64>().ok());
    let seed = env("RAILFEM_MUTATION_SEED").unwrap_or(36);
    let cases = env("RAILFEM_COMPANION_MUTATIONS").unwrap_or(100);
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let read = |p: &str| std::fs::read_to_string(root.join(p)).expect(p);
    let vehicles: Vec<toml::Value> = [
        "examples/vehicles/manchester_benchmark.toml",
        "elements/presets/sks700.toml",
    ]
    .iter()
    .map(|p| toml::from_str(&read(p)).expect("vehicle file"))
    .collect();
    let train: toml::Value = toml::from_str(TRAIN_TABLE).expect("train table");
    let irregularity = read("examples/models/irregular_straight.csv");
    let irregular_model = read("examples/models/irregular_straight.toml");
    let plan: toml::Value = toml::from_str(PLAN).expect("plan");
    let dir = common::temp_dir("companions");
    let sdof = read("examples/models/sdof.toml");
    std::fs::write(dir.join("sdof.toml"), &sdof).expect("write base");
    // A checkpoint to mutate: the first two cases of the plan, computed once.
    let good_plan = dir.join("good-plan.toml");
    std::fs::write(&good_plan, PLAN).expect("write plan");
    let first = dir.join("first");
    let o = study(&good_plan, &first, "2");
    assert!(
        matches!(&o, Some((Some(0), _, _))),
        "the unmutated study runs: {o:?}"
    );
    let checkpoint = std::fs::read_to_string(first.join("study.checkpoint")).expect("checkpoint");
    let t0 = Instant::now();
    let mut failures = Vec::new();
    let mut counts = [0usize; 5];
    for k in 0..cases {
        let case_seed = seed.wrapping_mul(1_000_003).wrapping_add(k);
        let mut rng = Rng(case_seed);
        let kind = (k % 5) as usize;
        counts[kind] += 1;
        let model = dir.join(format!("model-{case_seed}.toml"));
        let m = model.to_str().expect("utf-8").to_string();
        let (outcome, what, names): (_, Vec<String>, Vec<String>) = match kind {
            0 => {
                let c = mutate::toml_case(&vehicles[rng.below(vehicles.len())], &mut rng);
                let name = format!("vehicle-{case_seed}.toml");
                std::fs::write(dir.join(&name), &c.text).expect("write vehicle");
                std::fs::write(&model, VEHICLE_FILE_MODEL.replace("{file}", &name))
                    .expect("write model");
                (run_limited(&["check", &m], LIMIT), c.what, vec![name])
            }
            1 => {
                let c = case(&train, &mut rng);
                let model = dir.join(format!("train-{case_seed}.{}", c.ext));
                std::fs::write(&model, &c.text).expect("write train");
                let m = model.to_str().expect("utf-8");
                (run_limited(&["check", m], LIMIT), c.what, vec![])
            }
            2 => {
                let (text, what) = mutate::mutate_csv(&irregularity, &mut rng);
                let name = format!("irr-{case_seed}.csv");
                std::fs::write(dir.join(&name), text).expect("write csv");
                let text = irregular_model.replace("irregular_straight.csv", &name);
                std::fs::write(&model, text).expect("write model");
                (run_limited(&["check", &m], LIMIT), what, vec![name])
            }
            3 => {
                let c = mutate::toml_case(&plan, &mut rng);
                let name = format!("plan-{case_seed}.toml");
                let p = dir.join(&name);
                std::fs::write(&p, &c.text).expect("write plan");
                let out = dir.join(format!("out-{case_seed}"));
                let o = study(&p, &out, "2");
                let _ = std::fs::remove_dir_all(&out);
                (o, c.what, vec![name, "sdof.toml".into()])
            }
            _ => {
                let (text, what) = mutate::mutate_csv(&checkpoint, &mut rng);
                let out = dir.join(format!("out-{case_seed}"));
                std::fs::create_dir_all(&out).expect("out dir");
                std::fs::write(out.join("study.checkpoint"), text).expect("write checkpoint");
                let o = study(&good_plan, &out, "1");
                if o.is_some() {
                    let _ = std::fs::remove_dir_all(&out);
                }
                (
                    o,
                    what,
                    vec!["study.checkpoint".into(), "good-plan.toml".into()],
                )
            }
        };
        let stem = model
            .file_name()
            .and_then(|s| s.to_str())
            .unwrap_or("model");
        let mut all: Vec<&str> = names.iter().map(String::as_str).collect();
        all.push(stem);
        all.push("train-");
        if let Err(e) = judge_any(outcome, &all) {
            failures.push(format!(
                "kind {kind} (seed {case_seed}; {}): {e}",
                what.join("; ")
            ));
        }
    }
    println!(
        "{cases} mutated companion inputs (vehicle files, train tables, irregularity CSVs, plans, checkpoints: {counts:?}) in {:.1} s, {} failures",
        t0.elapsed().as_secs_f64(),
        failures.len()
    );
    assert!(
        failures.is_empty(),
        "{} of {cases} cases failed (files kept in {}):\n{}",
        failures.len(),
        dir.display(),
        failures.join("\n")
    );
    let _ = std::fs::remove_dir_all(&dir);
}

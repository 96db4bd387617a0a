//! Hostile inputs generated, not listed: every shipped example model, mutated
//! ([`mutate`]: extreme numbers, deleted and duplicated keys, tables and array entries,
//! values of the wrong type, JSON keys written twice), is given to `railfem check` — and
//! every third case, with its step count capped, to `railfem run` — as a subprocess with a
//! time limit. Every case must end with exit code 0 or 2 (never a signal, a panic or a
//! hang), and a refusal must be one line per problem naming the file.
//!
//! The default run is 600 cases from a fixed seed (about 15 s on two cores).
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
            if let Some(l) = lines.iter().find(|l| !l.contains(file)) {
                return Err(format!("a line does not name the file: {l}"));
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

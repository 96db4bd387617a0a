//! The study checkpoint verifies itself (issue 36 item 2, docs/robustness.md): a damaged
//! row, a row of another plan, a case beyond the plan and a case twice are refused on
//! resume with one line naming the checkpoint, the line and the fix, exit code 2, and no
//! table is published; `--restart` starts afresh. And a study killed with SIGKILL at 20
//! moments (pseudo-random, seeded) resumes to the same `study.csv`, byte for byte, as a
//! run that was never interrupted (item 7).

mod common;

use common::{railfem, refused_with, temp_dir};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// The single-DOF oscillator of examples/models/sdof.toml run for `duration` s.
fn sdof(dir: &Path, duration: f64) -> PathBuf {
    let text = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/models/sdof.toml"),
    )
    .expect("sdof.toml");
    let text = text.replace("duration = 2.0", &format!("duration = {duration}"));
    assert!(text.contains(&format!("duration = {duration}")));
    let p = dir.join("sdof.toml");
    std::fs::write(&p, text).expect("write model");
    p
}

/// A plan over the spring stiffness (`n` values) and the time step (2 values) of the
/// model in `dir`.
fn plan(dir: &Path, name: &str, n: usize) -> PathBuf {
    let ks: Vec<String> = (0..n).map(|i| format!("{}e6", 2 + i)).collect();
    let p = dir.join(name);
    std::fs::write(
        &p,
        format!(
            "base = \"sdof.toml\"\n[[axis]]\nname = \"element.1.k.0\"\nvalues = [{}]\n[[axis]]\nname = \"analysis.dt\"\nvalues = [0.005, 0.01]\n",
            ks.join(", ")
        ),
    )
    .expect("write plan");
    p
}

fn study_args<'a>(plan: &'a Path, out: &'a Path, extra: &[&'a str]) -> Vec<&'a str> {
    let mut a = vec![
        "study",
        plan.to_str().expect("utf-8"),
        "--out",
        out.to_str().expect("utf-8"),
        "-q",
        "--threads",
        "1",
    ];
    a.extend_from_slice(extra);
    a
}

fn ok(o: &std::process::Output) {
    assert_eq!(
        o.status.code(),
        Some(0),
        "stderr: {}",
        String::from_utf8_lossy(&o.stderr)
    );
}

/// Runs the plan into `out` after replacing line `line` (1-based) of its finished
/// checkpoint by `f(old)` and removing the table; asserts the refusal names the checkpoint,
/// that line and the fix, and that no table was published.
fn refused_after_edit(
    label: &str,
    plan: &Path,
    out: &Path,
    edit: &dyn Fn(&mut Vec<String>),
    expect: &[&str],
) {
    let ck = out.join("study.checkpoint");
    let original = std::fs::read_to_string(&ck).expect("checkpoint");
    let mut lines: Vec<String> = original.lines().map(str::to_string).collect();
    edit(&mut lines);
    std::fs::write(&ck, lines.join("\n") + "\n").unwrap();
    std::fs::remove_file(out.join("study.csv")).unwrap();
    let o = railfem(&study_args(plan, out, &[]));
    let mut want = vec![
        "study.checkpoint: line",
        "delete the row, or start afresh with `--restart`",
    ];
    want.extend_from_slice(expect);
    refused_with(label, &o, &want);
    assert!(
        !out.join("study.csv").exists(),
        "{label}: a table was published from a refused checkpoint"
    );
    // Put the good checkpoint back (and the table, by a resume that computes nothing).
    std::fs::write(&ck, &original).unwrap();
    ok(&railfem(&study_args(plan, out, &[])));
}

#[test]
fn damaged_foreign_and_out_of_range_rows_are_refused_and_restart_starts_afresh() {
    let dir = temp_dir("checkpoint-refusals");
    sdof(&dir, 0.2);
    let plan_a = plan(&dir, "a.toml", 3);
    let out = dir.join("a");
    ok(&railfem(&study_args(&plan_a, &out, &[])));
    let reference = std::fs::read_to_string(out.join("study.csv")).unwrap();
    assert_eq!(reference.lines().count(), 7, "{reference}");

    // A number of row 2 (checkpoint line 3) made non-numeric: its checksum fails.
    refused_after_edit(
        "non-numeric value",
        &plan_a,
        &out,
        &|l| l[2] = l[2].replacen("e-", "x-", 1),
        &["line 3", "checksum does not match"],
    );
    // The same row with its last three columns cut off.
    refused_after_edit(
        "wrong column count",
        &plan_a,
        &out,
        &|l| {
            let keep = l[2].rsplitn(4, ',').last().unwrap().to_string();
            l[2] = keep;
        },
        &["line 3", "columns"],
    );
    // A case id far beyond the plan's six (the summary once printed 2^64 − 1 not yet run).
    refused_after_edit(
        "case beyond the plan",
        &plan_a,
        &out,
        &|l| {
            let (sum, row) = l[1].split_at(17);
            let rest = row.split_once(',').unwrap().1;
            l.push(format!("{sum}99,{rest}"));
        },
        &["line 8", "case `99` is not one of the plan's 6 cases"],
    );
    // A case twice.
    refused_after_edit(
        "duplicate case",
        &plan_a,
        &out,
        &|l| {
            let row = l[1].clone();
            l.push(row);
        },
        &["line 8", "is in the checkpoint twice"],
    );
    // A line without its checksum (a row pasted from study.csv).
    refused_after_edit(
        "row without checksum",
        &plan_a,
        &out,
        &|l| l[4] = l[4][17..].to_string(),
        &["line 5", "does not start with its 16-digit checksum"],
    );
    // A row of another plan (other duration: same ids, values and columns; its checksum
    // was made under that plan's fingerprint).
    let other = temp_dir("checkpoint-foreign");
    sdof(&other, 0.3);
    let plan_b = plan(&other, "a.toml", 3);
    let out_b = other.join("a");
    ok(&railfem(&study_args(&plan_b, &out_b, &[])));
    let foreign = std::fs::read_to_string(out_b.join("study.checkpoint")).unwrap();
    let foreign_row = foreign.lines().nth(2).unwrap().to_string();
    refused_after_edit(
        "row of another plan",
        &plan_a,
        &out,
        &move |l| l[2] = foreign_row.clone(),
        &["line 3", "written for another plan"],
    );
    // The whole checkpoint of another plan.
    std::fs::copy(out_b.join("study.checkpoint"), out.join("study.checkpoint")).unwrap();
    let o = railfem(&study_args(&plan_a, &out, &[]));
    refused_with(
        "checkpoint of another plan",
        &o,
        &["study.checkpoint: line 1", "another plan", "--restart"],
    );
    // --restart: computed afresh, the same table.
    ok(&railfem(&study_args(&plan_a, &out, &["--restart"])));
    assert_eq!(
        std::fs::read_to_string(out.join("study.csv")).unwrap(),
        reference
    );
    let _ = std::fs::remove_dir_all(&dir);
    let _ = std::fs::remove_dir_all(&other);
}

/// A 64-bit linear congruential generator (Knuth's MMIX constants): the kill moments,
/// the same on every run of the test.
struct Lcg(u64);

impl Lcg {
    /// A number in [0, 1).
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

#[test]
fn a_study_killed_20_times_resumes_to_the_same_table() {
    let dir = temp_dir("checkpoint-kill");
    sdof(&dir, 10.0);
    let plan = plan(&dir, "plan.toml", 12);
    let whole = dir.join("whole");
    // The uninterrupted run, timed to its first kept case: start-up (reading the plan and
    // the checkpoint, building the first case's model) and the first case.
    let kept = |out: &Path| {
        std::fs::read_to_string(out.join("study.checkpoint"))
            .map_or(0, |t| t.lines().count().saturating_sub(1))
    };
    let t0 = Instant::now();
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_railfem"))
        .args(study_args(&plan, &whole, &[]))
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("start railfem");
    let mut first = None;
    while child.try_wait().expect("poll").is_none() {
        if first.is_none() && kept(&whole) > 0 {
            first = Some(t0.elapsed());
        }
        std::thread::sleep(std::time::Duration::from_micros(200));
    }
    let full = t0.elapsed();
    ok(&child.wait_with_output().expect("wait"));
    // A study that ended between two polls: its cases' mean time.
    let first = first.unwrap_or(full / 24);
    let reference = std::fs::read(whole.join("study.csv")).unwrap();
    assert_eq!(
        String::from_utf8_lossy(&reference).lines().count(),
        25,
        "24 cases and the header"
    );
    let killed = dir.join("killed");
    let mut rng = Lcg(36);
    let mut landed = 0;
    for _ in 0..20 {
        let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_railfem"))
            .args(study_args(&plan, &killed, &[]))
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .expect("start railfem");
        // Every other kill (at random) waits for the run to keep one more case, then a
        // random part of a case's time: it lands in the next case or its append. The
        // others land at a random moment of the start-up and the first case. So each run
        // keeps at most about one case, and the 20 together part of the study, on a fast
        // machine as on a slow one (the moments follow the study's own progress).
        let per_case = full.saturating_sub(first) / 23;
        if rng.next() < 0.5 {
            let before = kept(&killed);
            while kept(&killed) == before && child.try_wait().expect("poll").is_none() {
                std::thread::sleep(std::time::Duration::from_micros(200));
            }
            std::thread::sleep(per_case.mul_f64(rng.next()));
        } else {
            std::thread::sleep(first.mul_f64(rng.next()));
        }
        if child.try_wait().expect("poll").is_none() {
            landed += 1;
        }
        let _ = child.kill(); // SIGKILL
        let o = child.wait_with_output().expect("wait");
        // A run that ended before the kill must have ended well (a resume never refuses
        // what a killed run left).
        if let Some(code) = o.status.code() {
            assert_eq!(code, 0, "{}", String::from_utf8_lossy(&o.stderr));
        }
    }
    assert!(
        landed >= 10,
        "only {landed} of 20 kills hit a running study"
    );
    // The kills left a study part done: the last run resumes, it does not start or skip.
    let rows = kept(&killed);
    println!(
        "{landed} of 20 kills hit a running study; {rows} of 24 cases kept; uninterrupted {full:?}, first case kept at {first:?}"
    );
    assert!(
        rows > 0 && rows < 24,
        "{rows} of 24 cases done after the kills"
    );
    ok(&railfem(&study_args(&plan, &killed, &[])));
    let resumed = std::fs::read(killed.join("study.csv")).unwrap();
    assert!(
        resumed == reference,
        "resumed table differs:\n{}\nvs\n{}",
        String::from_utf8_lossy(&resumed),
        String::from_utf8_lossy(&reference)
    );
    let _ = std::fs::remove_dir_all(&dir);
}

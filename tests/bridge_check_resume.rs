//! `railfem bridge-check` is resumable: its journal (`bridge-check.checkpoint`) keeps every
//! finished train–speed run, a check stopped by `--stop-after` or killed with SIGKILL goes
//! on when the same command runs again and writes the uninterrupted run's `envelope.csv`
//! byte for byte; a changed row is refused with one line naming the journal's line and the
//! fix (exit 2), and `--restart` starts afresh.

mod common;
use common::{railfem, temp_dir};
use std::path::Path;
use std::time::{Duration, Instant};

/// HSLM-A1 and A5 as moving forces and sprung masses on a 20 m span, 200-240 km/h: 32 runs.
const PLAN: &str = "trains = [\"HSLM-A1\", \"HSLM-A5\"]\n[analysis]\nmodel = \"both\"\n[bridge]\nspans = [20.0]\nEI = 4.8e10\nmass = 15000.0\nkind = \"prestressed_concrete\"\ntrack = \"ballasted\"\n[speeds]\nmax_line_speed = 200.0\nmin = 200.0\nstep = 10.0\nrefine = 2\n";

fn check(plan: &Path, out: &Path, extra: &[&str]) -> std::process::Output {
    let mut args = vec![
        "bridge-check",
        plan.to_str().expect("utf-8"),
        "--threads",
        "2",
        "--out",
        out.to_str().expect("utf-8"),
    ];
    args.extend_from_slice(extra);
    railfem(&args)
}

fn rows(out: &Path) -> usize {
    std::fs::read_to_string(out.join("bridge-check.checkpoint"))
        .expect("journal")
        .lines()
        .count()
        - 1
}

#[test]
fn a_stopped_or_killed_check_resumes_to_the_same_envelope() {
    let dir = temp_dir("bridge-check-resume");
    let plan = dir.join("plan.toml");
    std::fs::write(&plan, PLAN).expect("write");
    let whole = dir.join("whole");
    let t0 = Instant::now();
    let o = check(&plan, &whole, &[]);
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let full = t0.elapsed();
    let reference = std::fs::read(whole.join("envelope.csv")).expect("envelope");
    let runs = rows(&whole);
    assert!(runs >= 30, "{runs} runs");

    // Stopped twice by --stop-after: 5 runs, then 7 more, then the rest.
    let part = dir.join("part");
    let o = check(&plan, &part, &["--stop-after", "5"]);
    assert_eq!(o.status.code(), Some(130));
    assert!(!part.join("envelope.csv").exists());
    assert_eq!(rows(&part), 5);
    let o = check(&plan, &part, &["--stop-after", "7"]);
    assert_eq!(o.status.code(), Some(130));
    assert_eq!(rows(&part), 12);

    // A changed row is refused (the checksum), naming the journal's line and the fix.
    let j = part.join("bridge-check.checkpoint");
    let good = std::fs::read_to_string(&j).expect("journal");
    let mut lines: Vec<String> = good.lines().map(String::from).collect();
    let last = lines[3].pop().expect("a digit");
    lines[3].push(if last == '0' { '1' } else { '0' });
    std::fs::write(&j, lines.join("\n") + "\n").expect("write");
    let o = check(&plan, &part, &[]);
    let err = common::refused_with(
        "changed row",
        &o,
        &["bridge-check.checkpoint: line 4", "--restart"],
    );
    assert_eq!(err.lines().count(), 1, "{err}");
    // A cut last line (a kill in the middle of an append) is dropped, not refused.
    std::fs::write(&j, &good[..good.len() - 20]).expect("write");
    let o = check(&plan, &part, &[]);
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    assert_eq!(
        std::fs::read(part.join("envelope.csv")).expect("csv"),
        reference
    );

    // Killed with SIGKILL at moments spread over the run, then finished.
    let killed = dir.join("killed");
    for k in 0..4 {
        let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_railfem"))
            .args([
                "bridge-check",
                plan.to_str().expect("utf-8"),
                "--threads",
                "2",
                "--out",
                killed.to_str().expect("utf-8"),
            ])
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::null())
            .spawn()
            .expect("start railfem");
        std::thread::sleep(
            full.mul_f64(0.15 + 0.05 * k as f64)
                .max(Duration::from_millis(50)),
        );
        let _ = child.kill();
        let _ = child.wait();
    }
    let o = check(&plan, &killed, &[]);
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    assert_eq!(
        std::fs::read(killed.join("envelope.csv")).expect("csv"),
        reference
    );

    // --restart discards the journal (and a journal of another plan is refused without it).
    std::fs::write(&plan, PLAN.replace("min = 200.0", "min = 205.0")).expect("write");
    let o = check(&plan, &part, &[]);
    common::refused_with(
        "another plan",
        &o,
        &["bridge-check.checkpoint: line 1", "--restart"],
    );
    let o = check(&plan, &part, &["--restart"]);
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
}

//! `railfem <command> --help` prints the usage and exits 0 without running anything (a
//! `--help` used to be taken as an option of the command, which then ran its default — a
//! 1M-DOF train–bridge run for `train-bridge --help`).

use std::process::Command;
use std::time::{Duration, Instant};

#[test]
fn help_after_any_command_prints_usage_and_runs_nothing() {
    let exe = env!("CARGO_BIN_EXE_railfem");
    for cmd in [
        "train-bridge",
        "curve",
        "critical-radius",
        "bench",
        "track",
        "run",
    ] {
        let t = Instant::now();
        let out = Command::new(exe).args([cmd, "--help"]).output().unwrap();
        let text = String::from_utf8_lossy(&out.stdout);
        assert_eq!(out.status.code(), Some(0), "{cmd}: {out:?}");
        assert!(text.contains("railfem"), "{cmd}: no usage printed");
        // Printing the usage takes milliseconds; any of these commands run for seconds
        // at least (a curve run, a 1M-DOF build). Generous against a loaded machine.
        assert!(
            t.elapsed() < Duration::from_secs(5),
            "{cmd} --help ran something"
        );
    }
}

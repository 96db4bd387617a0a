//! A full disk (issue 36 item 7, docs/robustness.md): when a recorder or `run.json` cannot
//! be written, the run stops with exit code 2 and one line naming the file and the fix,
//! and every file it wrote ends on a whole line.
//!
//! The disk is "full" in two ways that need no privilege or mounted file system: a file
//! size limit on the child process (`setrlimit(RLIMIT_FSIZE)`, what `prlimit --fsize`
//! sets), with SIGXFSZ left at its default, fatal disposition — railfem ignores it itself,
//! so that a write past the limit returns `EFBIG` instead of killing the process; and a
//! recorder file that is a link to `/dev/full`, whose every write fails with `ENOSPC`.

#![cfg(target_os = "linux")]

mod common;

use common::{refused_with, temp_dir};
use std::os::unix::process::CommandExt;
use std::path::{Path, PathBuf};

/// `railfem ARGS` with every file it writes limited to `limit` bytes.
fn railfem_limited(args: &[&str], limit: u64) -> std::process::Output {
    let mut cmd = std::process::Command::new(env!("CARGO_BIN_EXE_railfem"));
    cmd.args(args);
    // SAFETY: between fork and exec only async-signal-safe calls (signal, setrlimit).
    unsafe {
        cmd.pre_exec(move || {
            // As a shell leaves it: a write past the limit kills the process unless the
            // process ignores the signal itself.
            libc::signal(libc::SIGXFSZ, libc::SIG_DFL);
            let r = libc::rlimit {
                rlim_cur: limit as libc::rlim_t,
                rlim_max: limit as libc::rlim_t,
            };
            if libc::setrlimit(libc::RLIMIT_FSIZE, &r) != 0 {
                return Err(std::io::Error::last_os_error());
            }
            Ok(())
        });
    }
    cmd.output().expect("run railfem")
}

/// The single-DOF oscillator of examples/models/sdof.toml run for `duration` s.
fn sdof(dir: &Path, duration: f64) -> PathBuf {
    let text = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/models/sdof.toml"),
    )
    .expect("sdof.toml");
    let text = text.replace("duration = 2.0", &format!("duration = {duration}"));
    let p = dir.join("sdof.toml");
    std::fs::write(&p, text).expect("write model");
    p
}

/// Every `*.csv` of `out` is whole lines of its header's column count, and no temporary
/// file is left.
fn whole_lines(out: &Path) -> usize {
    let mut rows = 0;
    for e in std::fs::read_dir(out).expect("out") {
        let p = e.unwrap().path();
        let name = p.file_name().unwrap().to_string_lossy().to_string();
        assert!(!name.ends_with(".tmp"), "temporary file left: {name}");
        if !name.ends_with(".csv") {
            continue;
        }
        let text = std::fs::read_to_string(&p).unwrap();
        if text.is_empty() {
            continue;
        }
        assert!(text.ends_with('\n'), "{name} ends inside a line");
        let cols = text.lines().next().unwrap().split(',').count();
        for l in text.lines() {
            assert_eq!(l.split(',').count(), cols, "{name}: cut line {l:?}");
            rows += 1;
        }
    }
    rows
}

#[test]
fn a_recorder_that_cannot_be_written_stops_the_run_in_one_line_with_whole_lines() {
    let dir = temp_dir("full-disk-recorder");
    let model = sdof(&dir, 2.0);
    let out = dir.join("out");
    // 400 steps of rows of about 40 bytes: 16 kB per recorder, past a 6 kB limit.
    let o = railfem_limited(
        &[
            "run",
            model.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "-q",
        ],
        6000,
    );
    let line = refused_with(
        "recorder",
        &o,
        &[
            "output ",
            ".csv",
            "File too large",
            "make room there or write elsewhere (--out)",
        ],
    );
    assert!(line.contains(out.to_str().unwrap()), "{line}");
    let rows = whole_lines(&out);
    assert!(rows > 10, "the rows before the limit are kept: {rows}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_run_json_that_cannot_be_written_stops_the_run_in_one_line() {
    let dir = temp_dir("full-disk-run-json");
    // Two steps: recorders of a few hundred bytes, under a limit run.json is over.
    let model = sdof(&dir, 0.01);
    let out = dir.join("out");
    let o = railfem_limited(
        &[
            "run",
            model.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "-q",
        ],
        400,
    );
    refused_with(
        "run.json",
        &o,
        &[
            &format!("output {}", out.join("run.json").display()),
            "File too large",
            "make room there or write elsewhere (--out)",
        ],
    );
    assert!(!out.join("run.json").exists());
    assert!(whole_lines(&out) >= 4);
    let _ = std::fs::remove_dir_all(&dir);
}

/// `ENOSPC` itself: the displacement recorder's file is a link to `/dev/full`, which
/// accepts the open and fails every write with "No space left on device". The run stops
/// with exit code 2 and one line naming that file, and the other recorder's file (a
/// regular file) ends on a whole line.
#[test]
fn a_recorder_on_a_full_device_stops_the_run_in_one_line() {
    if !Path::new("/dev/full").exists() {
        eprintln!("no /dev/full on this system: skipped");
        return;
    }
    let dir = temp_dir("full-disk-dev-full");
    let model = sdof(&dir, 2.0);
    let out = dir.join("out");
    std::fs::create_dir_all(&out).unwrap();
    let disp = out.join("disp.csv");
    std::os::unix::fs::symlink("/dev/full", &disp).unwrap();
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_railfem"))
        .args([
            "run",
            model.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "-q",
        ])
        .output()
        .expect("run railfem");
    let line = refused_with(
        "/dev/full",
        &o,
        &[
            &format!("output {}", disp.display()),
            "No space left on device",
            "make room there or write elsewhere (--out)",
        ],
    );
    assert!(!line.contains("vel.csv"), "{line}");
    // Reading /dev/full gives zeros without end: drop the link before looking at the rest.
    std::fs::remove_file(&disp).unwrap();
    assert!(whole_lines(&out) > 10);
    let _ = std::fs::remove_dir_all(&dir);
}

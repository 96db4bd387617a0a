//! The activity window of `railfem run` (`[analysis.window]`, docs/model-format.md): a
//! windowed run of a model file against its full run, and the window off or left out
//! against a run without it, byte for byte.
//!
//! The model (`run_window/spans.rs`): a sprung mass crossing 12 spans whose supports are
//! clamped, so that the spans share no equation. A held span is then exactly what it is
//! in the full run as far as the mass is concerned, and the mass's contact force differs
//! between the two runs only by where each run's Newton iterations stop.

mod common;
#[path = "run_window/spans.rs"]
mod spans;

use common::{run_model_in, temp_dir, Csv};
use std::path::{Path, PathBuf};

/// Runs `railfem run` on `text` in a fresh directory; returns the output directory and
/// stdout. Panics when the run fails.
fn run(name: &str, text: &str) -> (PathBuf, String) {
    let (out, o) = run_model_in(&temp_dir(name), &format!("{name}.toml"), text);
    assert!(
        o.status.success(),
        "{name}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    (out, String::from_utf8_lossy(&o.stdout).into_owned())
}

/// The largest |a − b| over the samples of column `col`, and the largest |a| (`from_start`:
/// of `a − a(0)`, the part the moving load causes).
fn largest_difference(a: &Csv, b: &Csv, col: &str, from_start: bool) -> (f64, f64) {
    let (x, y) = (a.column(col), b.column(col));
    assert_eq!(x.len(), y.len(), "{col}: sample counts");
    let x0 = if from_start { x[0] } else { 0.0 };
    let diff = x
        .iter()
        .zip(&y)
        .map(|(p, q)| (p - q).abs())
        .fold(0.0, f64::max);
    let peak = x.iter().map(|p| (p - x0).abs()).fold(0.0, f64::max);
    (diff, peak)
}

/// The counters of the summary line `activity window: H of N block-steps held (…), J
/// blocks joined, L held behind`: `[H, N, J, L]`.
fn window_counters(stdout: &str) -> [usize; 4] {
    let line = stdout
        .lines()
        .find(|l| l.starts_with("activity window: "))
        .unwrap_or_else(|| panic!("no window line in {stdout}"));
    let words: Vec<&str> = line.split_whitespace().collect();
    let num = |i: usize| words[i].parse::<usize>().expect("a count");
    [num(2), num(4), num(9), num(12)]
}

/// The window on, 15 m ahead, against the same model without it. Spans ahead of the mass
/// are held at the self-weight state the full run keeps them at; spans behind are held
/// once their interiors' velocity norm is below `tolerance` (1 %) of its peak.
///
/// Bounds. The contact force and the mass's displacement: within 1e-8 of their peaks.
/// Both runs solve the same equations for the span under the mass; each step's Newton
/// stops at a relative residual of `tol` = 1e-10, over all rows in the full run and over
/// the rows not held in the windowed one, so the converged states differ by that
/// tolerance times the conditioning of the span under the mass, which the bound allows
/// a factor 100. Midspan deflections: a span held behind keeps the displacement it had;
/// it is held once the velocity norm of its free, decaying vibration is below 1 % of its
/// largest, and for the vibration of one dominant mode (ω) the amplitude left, |v|/ω, is
/// then below 1 % of the largest dynamic amplitude, which is the bound on `w − w(0)`.
/// Spans never held behind are the full run's to round-off.
#[test]
fn a_windowed_model_file_gives_the_full_runs_contact_force() {
    let window = "mode = \"on\"\nahead = 15.0\ntolerance = 0.01";
    let (full, _) = run("full", &spans::model(None, "partitioned", ""));
    let (on, stdout) = run("on", &spans::model(Some(window), "partitioned", ""));
    let [held, steps, joined, left] = window_counters(&stdout);
    // One block per span (block_size = 14 = the 7 interior nodes' uz, ry): the window
    // held some ahead and some behind.
    assert!(held > steps / 4 && held < steps, "held {held} of {steps}");
    assert_eq!(joined, spans::SPANS, "every span joined as the mass came");
    assert!(left >= spans::SPANS / 2, "{left} spans held behind");
    let read = |d: &Path, f: &str| Csv::read(&d.join(f));
    let (a, b) = (read(&full, "mass.csv"), read(&on, "mass.csv"));
    for col in ["1000_contact_force", "1000_mass_disp"] {
        let (diff, peak) = largest_difference(&a, &b, col, false);
        eprintln!("{col}: {diff:.3e} of {peak:.3e}");
        assert!(diff <= 1e-8 * peak, "{col}: {diff:e} of {peak:e}");
    }
    let (a, b) = (read(&full, "midspans.csv"), read(&on, "midspans.csv"));
    for k in 0..spans::SPANS {
        let col = format!("{}_uz", k * spans::ELEMENTS + spans::ELEMENTS / 2);
        let (diff, peak) = largest_difference(&a, &b, &col, true);
        eprintln!("{col}: {diff:.3e} of {peak:.3e}");
        assert!(diff <= 0.01 * peak, "{col}: {diff:e} of {peak:e}");
    }
}

/// `mode = "off"` runs the code of a model without the table: the same bytes in every
/// output file. So does `auto` where the window does not apply (here the direct solver),
/// which says so once in the summary.
#[test]
fn the_window_off_or_left_out_writes_the_bytes_of_a_run_without_it() {
    let files = ["mass.csv", "midspans.csv"];
    let same = |a: &Path, b: &Path, what: &str| {
        for f in files {
            let (x, y) = (std::fs::read(a.join(f)), std::fs::read(b.join(f)));
            assert_eq!(x.expect("written"), y.expect("written"), "{what}: {f}");
        }
    };
    let (none, _) = run("none", &spans::model(None, "partitioned", ""));
    let (off, stdout) = run(
        "off",
        &spans::model(Some("mode = \"off\""), "partitioned", ""),
    );
    same(&none, &off, "off");
    assert!(!stdout.contains("activity window"), "{stdout}");
    let (direct, _) = run("direct", &spans::model(None, "direct", ""));
    let (auto, stdout) = run("auto", &spans::model(Some("mode = \"auto\""), "direct", ""));
    same(&direct, &auto, "auto on the direct solver");
    let eq = spans::SPANS * (spans::ELEMENTS - 1) * 2 + 1;
    let line = format!("activity window (auto): off here: the window holds blocks of the partitioned solver, and `solver` = \"direct\" does not run it for this model's {eq} equations");
    assert_eq!(
        stdout
            .lines()
            .filter(|l| l.contains("activity window"))
            .collect::<Vec<_>>(),
        [line.as_str()],
        "{stdout}"
    );
}

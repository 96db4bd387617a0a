//! The activity window's options (`railfem train-bridge --window …`, docs/activity-window.md):
//! each refused combination exits with code 2 and one stderr line, naming the option and
//! the fix, before any stepping.

use super::train_bridge_refused as refused;

#[test]
fn a_window_mode_other_than_on_off_or_auto_is_refused() {
    refused(
        &["--window", "maybe"],
        "--window maybe: give on, off or auto",
    );
}

#[test]
fn window_settings_with_the_window_off_are_refused() {
    refused(
        &["--window", "off", "--window-ahead", "100"],
        "--window-ahead and --window-tolerance set the activity window, which --window off turns off; drop them, or give --window on or auto",
    );
    refused(
        &["--window-tolerance", "0.1", "--window", "off"],
        "--window-ahead and --window-tolerance set the activity window, which --window off turns off; drop them, or give --window on or auto",
    );
    refused(
        &["--window", "off", "--window-layer", "50"],
        "--window-layer and --window-layer-damping shape the activity window's absorbing layer, which --window off turns off; drop them, or give --window on or auto",
    );
}

#[test]
fn window_settings_out_of_range_are_refused() {
    refused(
        &["--window-ahead=-5"],
        "--window-ahead -5: give a distance ≥ 0 m",
    );
    refused(
        &["--window-tolerance", "1"],
        "--window-tolerance 1: give a value from 0 (never hold a block behind) to below 1",
    );
}

#[test]
fn the_window_asked_for_where_it_does_not_apply_is_refused() {
    refused(
        &["--window", "on", "--quake", "synthetic"],
        "--window on with --quake: under ground motion the whole viaduct moves; give --window off",
    );
    refused(
        &["--window", "on", "--radius", "1000"],
        "--window on with --radius: the window maps nodes to stations on a straight track only; give --window off",
    );
    refused(
        &["--window", "on", "--solver", "direct"],
        "--window on: the activity window needs the partitioned solver (solver = \"partitioned\") with at least one block; give --solver partitioned or --window off",
    );
}

/// `railfem bench --case window` with `args` added (the tiny case, so that a wrong
/// acceptance would show as a run, not a refusal); asserts the refusal `line` (exact).
fn bench_refused(args: &[&str], line: &str) {
    let mut all = vec![
        "bench", "--case", "window", "--spans", "2", "--cars", "1", "--steps", "1",
    ];
    all.extend_from_slice(args);
    let err = super::refused_with(&format!("{args:?}"), &super::railfem(&all), &[line]);
    assert_eq!(
        err.trim_end(),
        format!("error: command line: {line}"),
        "{args:?}"
    );
}

#[test]
fn the_window_benchmarks_reaches_and_layer_are_refused_as_train_bridges() {
    bench_refused(
        &["--window-ahead", "300,-5"],
        "--window-ahead -5: give a distance ≥ 0 m",
    );
    bench_refused(
        &["--window-ahead", "300,far"],
        "--window-ahead 300,far: give distances ≥ 0 m, comma-separated",
    );
    bench_refused(
        &["--window-layer=-1"],
        "--window-layer -1: give a value ≥ 0",
    );
    let o = super::railfem(&["bench", "--window-ahead", "150", "--sizes", "100"]);
    let err = super::refused_with("--window-ahead with the beam case", &o, &[]);
    assert_eq!(
        err.trim_end(),
        "error: command line: --window-ahead: only the window case takes --window-ahead; drop it or use --case window"
    );
}

//! The activity window's keys in a model file (`[analysis.window]`, docs/model-format.md):
//! each mistake, and `mode = "on"` where the window does not apply, exits with code 2 and
//! one stderr line naming the file, the key and the fix, before any stepping.

use super::check;

#[path = "../run_window/spans.rs"]
mod spans;

/// The spans model with `window` as its `[analysis.window]` body, on `solver`, `extra`
/// appended; asserts the refusal `line` (exact, after `error: …/run_window.toml: `).
fn refused(window: &str, solver: &str, extra: &str, line: &str) {
    refused_text(&spans::model(Some(window), solver, extra), line);
}

/// `railfem run` and `railfem check` refuse `text` with `line` (exact, after the file).
fn refused_text(text: &str, line: &str) {
    let name = "run_window.toml";
    let dir = super::common::temp_dir("run_window_check");
    let path = dir.join(name);
    std::fs::write(&path, text).expect("write model");
    let o = super::common::railfem(&["check", path.to_str().expect("utf-8")]);
    let checked = super::common::refused_with("check", &o, &[line]);
    let _ = std::fs::remove_dir_all(&dir);
    let err = check(name, text, &[line]);
    // The file is named by the path it was given as.
    for e in [&err, &checked] {
        let (head, tail) = e
            .trim_end()
            .split_once(&format!("{name}: "))
            .unwrap_or_else(|| panic!("the file is not named: {e}"));
        assert!(head.starts_with("error: "), "{e}");
        assert_eq!(tail, line);
    }
}

#[test]
fn unknown_keys_and_modes_are_refused_with_the_valid_ones() {
    refused(
        "mode = \"on\"\nreach = 5.0",
        "partitioned",
        "",
        "[analysis]: `analysis.window.reach`: unknown field `reach`, expected one of `mode`, `ahead`, `tolerance`, `layer`, `layer_damping`; remove or rename the key (docs/model-format.md lists every key, its type and unit)",
    );
    refused(
        "mode = \"maybe\"",
        "partitioned",
        "",
        "[analysis]: `analysis.window.mode`: unknown variant `maybe`, expected one of `off`, `on`, `auto`; give one of the values listed (docs/model-format.md lists every key, its type and unit)",
    );
}

#[test]
fn settings_out_of_range_or_without_the_window_are_refused() {
    refused(
        "mode = \"on\"\nahead = -5.0",
        "partitioned",
        "",
        "[analysis.window]: `ahead` = -5: give a distance ≥ 0 m",
    );
    refused(
        "mode = \"auto\"\ntolerance = 1.0",
        "partitioned",
        "",
        "[analysis.window]: `tolerance` = 1: give a value from 0 (never hold a block behind) to below 1",
    );
    refused(
        "ahead = 100.0",
        "partitioned",
        "",
        "[analysis.window]: `ahead`, `tolerance`, `layer` and `layer_damping` set the activity window, which is off unless `mode` is \"on\" or \"auto\"; add mode = \"on\" (or \"auto\"), or drop them",
    );
}

/// The absorbing layer's keys (`layer`, `layer_damping`): a thickness below zero, a
/// damping not above zero (numbers that are not finite are refused before, as for every
/// key), a damping for a layer `layer = 0` removes, and either
/// key with the window off.
#[test]
fn layer_settings_out_of_range_or_without_a_layer_are_refused() {
    let refused_on = |keys: &str, line: &str| {
        refused(&format!("mode = \"on\"\n{keys}"), "partitioned", "", line)
    };
    refused_on(
        "layer = -10.0",
        "[analysis.window]: `layer` = -10: give a thickness ≥ 0 m (0: no layer)",
    );
    refused_on(
        "layer_damping = 0.0",
        "[analysis.window]: `layer_damping` = 0: give a damping > 0 (1/s)",
    );
    refused_on(
        "layer_damping = -100.0",
        "[analysis.window]: `layer_damping` = -100: give a damping > 0 (1/s)",
    );
    refused_on(
        "layer = 0.0\nlayer_damping = 100.0",
        "[analysis.window]: `layer_damping` shapes the absorbing layer, which `layer` = 0 removes; drop `layer_damping`, or give a `layer` > 0",
    );
    for keys in [
        "layer = 40.0",
        "layer_damping = 100.0",
        "mode = \"off\"\nlayer = 0.0",
    ] {
        refused(
            keys,
            "partitioned",
            "",
            "[analysis.window]: `ahead`, `tolerance`, `layer` and `layer_damping` set the activity window, which is off unless `mode` is \"on\" or \"auto\"; add mode = \"on\" (or \"auto\"), or drop them",
        );
    }
}

#[test]
fn the_window_of_a_static_analysis_is_refused() {
    let text = super::edit(
        "kind = \"static\"",
        "kind = \"static\"\n\n[analysis.window]\nmode = \"on\"",
    );
    refused_text(
        &text,
        "[analysis.window]: the activity window follows what moves in a transient; remove [analysis.window] or set `kind` = \"transient\"",
    );
}

#[test]
fn the_window_on_without_the_partitioned_solver_is_refused() {
    let eq = spans::SPANS * (spans::ELEMENTS - 1) * 2 + 1;
    refused(
        "mode = \"on\"",
        "direct",
        "",
        &format!("[analysis.window]: mode = \"on\": the window holds blocks of the partitioned solver, and `solver` = \"direct\" does not run it for this model's {eq} equations; set [analysis] solver = \"partitioned\", or mode = \"off\""),
    );
}

#[test]
fn the_window_on_under_ground_motion_is_refused() {
    refused(
        "mode = \"on\"",
        "partitioned",
        "[[load]]\ntype = \"ground_motion\"\ndirection = [0.0, 0.0, 1.0]\nseries = {type = \"sine\", frequency = 2.0}\n",
        "[analysis.window]: mode = \"on\": under ground motion (load[0]) the whole structure moves; set mode = \"off\"",
    );
}

/// A moving force along a beam that runs along Y, and a train on a track that curves.
#[test]
fn the_window_on_off_a_straight_track_along_x_is_refused() {
    let beam_along_y = "[[node]]\nid = 2000\nxyz = [0.0, 0.0, 0.0]\nfix = \"all\"\n\n[[node]]\nid = 2001\nxyz = [0.0, 5.0, 0.0]\nfix = \"all\"\n\n[[element]]\ntype = \"beam3d\"\nid = 2000\nnodes = [2000, 2001]\nE = 2.1e11\nG = 8.1e10\nA = 7.686e-3\nIy = 3.038e-5\nIz = 5.123e-6\nJ = 2.0e-6\n\n[[load]]\ntype = \"moving_force\"\nelements = [2000]\nforce = [0.0, 0.0, -1.0e4]\nspeed = 1.0\n";
    refused(
        "mode = \"on\"",
        "partitioned",
        beam_along_y,
        "[analysis.window]: mode = \"on\": load[0] (moving_force) does not travel along +X on a straight path; the window maps nodes to stations by their X coordinate, on a straight track along +X only; set mode = \"off\"",
    );
    let curve = r#"
[analysis]
dt = 0.002
duration = 0.01
gravity = [0.0, 0.0, -9.81]
solver = "partitioned"

[analysis.window]
mode = "on"

[track]
segments = [{type = "straight", length = 20.0}, {type = "arc", length = 80.0, radius = 1000.0}]
ct = 100.0
support = {type = "discrete", spacing = 0.625, k = [3e7, 6e7, 2e7, 0, 0, 0]}

[[vehicle]]
preset = "sks700"
start = 15.0
speed = 20.0
"#;
    refused_text(
        curve,
        "[analysis.window]: mode = \"on\": `train` moves along a path that curves or turns away from +X at station 20.0 m; the window maps nodes to stations by their X coordinate, on a straight track along +X only; set mode = \"off\"",
    );
}

#[test]
fn the_window_on_with_nothing_moving_is_refused() {
    let text = spans::model(Some("mode = \"on\""), "partitioned", "");
    let still: Vec<&str> = text.split("\n\n").filter(|b| !b.contains("1000")).collect();
    refused_text(
        &still.join("\n\n"),
        "[analysis.window]: mode = \"on\": nothing in the model moves (no [[vehicle]], moving element or moving_force load) for the window to follow; set mode = \"off\"",
    );
}

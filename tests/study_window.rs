//! The activity window's absorbing layer as study keys (`window_layer`,
//! `window_layer_damping`, docs/study.md) reaches the case as the options of
//! `railfem train-bridge` do: a study's case writes the bytes of the command's run with the
//! same settings. The refusals are in `tests/bad_input/study_window.rs`.

mod common;

use common::{railfem, study, temp_dir};
use std::path::Path;

/// The case: one carriage entering 12 spans of 10 m, 20 steps of 10 ms, on the
/// partitioned solver (two blocks of at most 3 000 equations for the model's 6 474), the
/// window on with a reach of 30 m, so that the block ahead is held.
const OPTIONS: [(&str, &str); 8] = [
    ("cars", "1"),
    ("spans", "12"),
    ("span", "10"),
    ("dt", "0.01"),
    ("duration", "0.2"),
    ("solver", "partitioned"),
    ("window", "on"),
    ("window_ahead", "30"),
];

/// `railfem train-bridge` on the case with `--window-layer layer`, writing into `out`;
/// its `wheels.csv`.
fn command(out: &Path, layer: &str) -> String {
    let mut args = vec!["train-bridge".to_string(), "-q".into()];
    for (k, v) in OPTIONS {
        args.push(format!("--{}", k.replace('_', "-")));
        args.push(v.to_string());
    }
    args.extend(["--window-layer".into(), layer.to_string()]);
    args.extend(["--out".into(), out.to_str().expect("utf-8").to_string()]);
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let o = railfem(&args);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    std::fs::read_to_string(out.join("wheels.csv")).expect("wheels.csv")
}

/// A study over `window_layer` = 0 (no layer) and 10 m writes, for each case, the
/// `wheels.csv` of `railfem train-bridge --window on --window-layer` with that value, byte
/// for byte; the two differ from each other, so the comparison tells the settings apart
/// (the layer reached the case).
#[test]
fn a_study_case_with_a_window_layer_writes_the_bytes_of_the_command() {
    let dir = temp_dir("study-window-layer-bytes");
    let mut plan = String::from("case = \"train-bridge\"\nhistories = true\n[options]\n");
    for (k, v) in OPTIONS {
        let value = if v.parse::<f64>().is_ok() {
            v.to_string()
        } else {
            format!("\"{v}\"")
        };
        plan.push_str(&format!("{k} = {value}\n"));
    }
    plan.push_str("[[axis]]\nname = \"window_layer\"\nvalues = [0, 10]\n");
    let path = dir.join("plan.toml");
    std::fs::write(&path, plan).expect("write the plan");
    let out = dir.join("study");
    let o = study(&path, &out, &["--threads", "1"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let mut wheels = Vec::new();
    for (id, layer) in [("0000", "0"), ("0001", "10")] {
        let from_study = std::fs::read_to_string(out.join("cases").join(id).join("wheels.csv"))
            .expect("the case's wheels.csv");
        let from_command = command(&dir.join(format!("command-{layer}")), layer);
        assert!(
            from_study == from_command,
            "window_layer = {layer}: the study's case and the command differ"
        );
        wheels.push(from_study);
    }
    assert_ne!(wheels[0], wheels[1], "the layer changed nothing");
    let _ = std::fs::remove_dir_all(&dir);
}

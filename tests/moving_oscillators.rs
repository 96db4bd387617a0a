//! Moving oscillators against their independent modal solutions (railfem::oscillators,
//! derived in docs/moving-oscillators.md), the model-file route through `railfem run`, and
//! bad input. The long convergence study is `cargo run --release --example moving_oscillators`.
//!
//! Tolerances come from the measured convergence (docs/moving-oscillators.md): the modal
//! reference with 40 modes and RK4 at h = 1/ω_N is within 1e-5 of the 120-mode one, far
//! below the FE errors checked here; the FE errors of a 16-element span at dt = T1/320 were
//! measured at 2–8e-4 (midspan) and 3e-4–1e-3 (sprung mass acceleration), and the limits
//! below leave a factor of about three for round-off of the element crossings and machines.

mod common;

use common::{check_bad_model, railfem, temp_dir, Csv};
use railfem::oscillators::{compare, fe_run, modal, self_weight_midspan, Case, Histories};

fn t1() -> f64 {
    2.0 * std::f64::consts::PI / railfem::pareto::omega(1)
}

fn reference(case: &Case) -> Histories {
    modal(case, 40, 900, 1.0)
}

/// The sprung mass of Yang & Wu at constant speed: midspan deflection and the mass's
/// acceleration within 2e-3 of their peaks (measured ≈ 4e-4 and 3e-4).
#[test]
fn sprung_mass_at_constant_speed_matches_the_modal_solution() {
    let case = Case::sprung_constant();
    let r = reference(&case);
    let (em, ea) = compare(&fe_run(&case, 16, t1() / 320.0).expect("run"), &r);
    eprintln!("sprung, constant speed: midspan {em:.3e}, acceleration {ea:.3e}");
    assert!(em < 2e-3, "midspan error {em:e}");
    assert!(ea < 2e-3, "acceleration error {ea:e}");
}

/// The damped sprung mass braking at 6 m/s²: same limits (measured ≈ 4e-4 and 9e-4).
#[test]
fn braking_sprung_mass_matches_the_modal_solution() {
    let case = Case::sprung_braking();
    let r = reference(&case);
    let (em, ea) = compare(&fe_run(&case, 16, t1() / 320.0).expect("run"), &r);
    eprintln!("sprung, braking: midspan {em:.3e}, acceleration {ea:.3e}");
    assert!(em < 2e-3, "midspan error {em:e}");
    assert!(ea < 3e-3, "acceleration error {ea:e}");
}

/// A 20 t mass rolling on a speed table (40 → 30 m/s), convective terms in both models:
/// the midspan deflection within 2e-3 of its peak (measured ≈ 3e-4). The contact point's
/// acceleration is not compared: it does not converge in either model (see the docs).
#[test]
fn moving_mass_on_a_speed_table_matches_the_modal_solution() {
    let case = Case::rolling_table();
    let r = reference(&case);
    let fe = fe_run(&case, 16, t1() / 320.0).expect("run");
    let (em, _) = compare(&fe, &r);
    eprintln!("moving mass, speed table: midspan {em:.3e}");
    assert!(em < 2e-3, "midspan error {em:e}");
}

/// The time error falls as dt is refined: T1/40 → T1/160 divides it by more than four
/// (measured ≈ 8 on 32 elements; Newmark is second order, the element crossings cost some).
#[test]
fn errors_fall_with_the_time_step() {
    let case = Case::sprung_constant();
    let r = reference(&case);
    let coarse = compare(&fe_run(&case, 16, t1() / 40.0).expect("run"), &r).0;
    let fine = compare(&fe_run(&case, 16, t1() / 160.0).expect("run"), &r).0;
    eprintln!("dt = T1/40: {coarse:.3e}, T1/160: {fine:.3e}");
    assert!(fine < coarse / 4.0, "{coarse:e} → {fine:e}");
}

/// `railfem run` on the example model file (20 elements, dt = 2.5 ms ≈ T1/45): the
/// midspan history, less the self-weight sag, within 1e-2 of the modal solution's peak
/// (measured ≈ 6e-3 at T1/40 on 32 elements); the recorded contact force starts at the
/// weight m·g.
#[test]
fn the_example_model_file_runs_and_matches() {
    let out = temp_dir("sprung-model");
    let model = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/examples/models/moving_sprung_mass.toml"
    );
    let o = railfem(&["run", model, "--out", out.to_str().unwrap()]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let mid = Csv::read(&out.join("midspan.csv"));
    let fe = Histories {
        t: mid.column("time"),
        midspan: mid
            .column("10_uz")
            .iter()
            .map(|w| w - self_weight_midspan())
            .collect(),
        rider_acc: vec![0.0; mid.rows.len()],
    };
    let (em, _) = compare(&fe, &reference(&Case::sprung_constant()));
    eprintln!("model file: midspan {em:.3e}");
    assert!(em < 1e-2, "midspan error {em:e}");
    let rec = Csv::read(&out.join("sprung_mass.csv"));
    let p0 = rec.column("100_contact_force")[0];
    assert!((p0 - 5750.0 * 9.81).abs() < 1e-6 * p0, "contact force {p0}");
    let _ = std::fs::remove_dir_all(&out);
}

/// Two beams 1 → 2 → 3 and a sprung mass on node 9; `{OSC}` is replaced per case.
const BASE: &str = r#"
[analysis]
kind = "transient"
dt = 0.001
duration = 0.01

[[node]]
id = 1
xyz = [0.0, 0.0, 0.0]
fix = "all"

[[node]]
id = 2
xyz = [1.0, 0.0, 0.0]

[[node]]
id = 3
xyz = [2.0, 0.0, 0.0]
fix = "all"

[[node]]
id = 4
xyz = [5.0, 0.0, 0.0]
fix = "all"

[[node]]
id = 9
xyz = [0.0, 0.0, 1.0]

[[element]]
type = "beam3d"
id = 1
nodes = [1, 2]
E = 2.1e11
G = 8.1e10
A = 0.01
Iy = 1e-4
Iz = 1e-4
J = 1e-4
rho = 7850.0

[[element]]
type = "beam3d"
id = 2
nodes = [2, 3]
E = 2.1e11
G = 8.1e10
A = 0.01
Iy = 1e-4
Iz = 1e-4
J = 1e-4
rho = 7850.0

[[element]]
type = "beam3d"
id = 3
nodes = [3, 4]
E = 2.1e11
G = 8.1e10
A = 0.01
Iy = 1e-4
Iz = 1e-4
J = 1e-4
rho = 7850.0

[[element]]
type = "moving_sprung_mass"
id = 10
nodes = [9]
{OSC}
"#;

fn bad(name: &str, osc: &str, expect: &[&str]) {
    let line = check_bad_model(name, &BASE.replace("{OSC}", osc), expect);
    assert!(
        line.contains("element[3]") || line.contains("id 10"),
        "{line}"
    );
}

#[test]
fn bad_oscillators_are_refused_in_one_line() {
    bad(
        "missing_element.toml",
        "m = 100.0\nk = 1e5\nspeed = 1.0\npath = [1, 7]",
        &["`path`[1]", "element 7", "does not exist"],
    );
    bad(
        "not_a_chain.toml",
        "m = 100.0\nk = 1e5\nspeed = 1.0\npath = [1, 3]",
        &["`path`", "element 3", "does not share a node"],
    );
    bad(
        "negative_mass.toml",
        "m = -100.0\nk = 1e5\nspeed = 1.0\npath = [1, 2]",
        &["`m`", "> 0"],
    );
    bad(
        "backwards_table.toml",
        "m = 100.0\nk = 1e5\npath = [1, 2]\nspeed_table = [[0.0, 2.0], [0.5, 1.0], [0.4, 1.0]]",
        &["`speed_table`[2]", "backwards", "increasing"],
    );
    bad(
        "negative_speed.toml",
        "m = 100.0\nk = 1e5\npath = [1, 2]\nspeed_table = [[0.0, 2.0], [0.5, -1.0]]",
        &["`speed_table`[1]", "backwards", "≥ 0"],
    );
    bad(
        "off_the_path.toml",
        "m = 100.0\nk = 1e5\nspeed = 1.0\npath = [1, 2]\nstart = 2.5",
        &["`start`", "off the path", "0 m to 2 m"],
    );
    // A moving mass on a path whose element is not a beam.
    let text = BASE.replace(
        "[[element]]\ntype = \"moving_sprung_mass\"\nid = 10\nnodes = [9]\n{OSC}",
        "[[element]]\ntype = \"mass\"\nid = 11\nnodes = [9]\nm = 1.0\n\n[[element]]\ntype = \"moving_mass\"\nid = 10\nnodes = []\nm = 100.0\nspeed = 1.0\npath = [11]",
    );
    check_bad_model(
        "not_a_beam.toml",
        &text,
        &["`path`[0]", "not a two-node beam"],
    );
}

/// Running off the end of the path stops the run with one line naming the element and the
/// fix (never a silently wrong result).
#[test]
fn leaving_the_path_is_an_error_not_a_silent_result() {
    let text = BASE
        .replace("{OSC}", "m = 100.0\nk = 1e5\nspeed = 300.0\npath = [1, 2]")
        .replace("duration = 0.01", "duration = 0.02");
    let dir = temp_dir("off-end");
    let path = dir.join("off_end.toml");
    std::fs::write(&path, text).unwrap();
    let o = railfem(&[
        "run",
        path.to_str().unwrap(),
        "--out",
        dir.join("out").to_str().unwrap(),
    ]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success(), "{err}");
    assert!(
        err.contains("off its path") && err.contains("lengthen the path"),
        "{err}"
    );
    assert!(!err.contains("panicked"), "{err}");
}

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

/// Unilateral contact, closed form: a mass pulled up by a constant force P from rest
/// (no gravity) flies freely, `z = P·t²/(2m)` (average-acceleration Newmark is exact for a
/// constant acceleration), with no contact; bonded to a stiff spring it stays near `P/k`.
#[test]
fn a_unilateral_mass_pulled_up_flies_freely() {
    let run = |contact: &str| {
        let text = BASE
            .replace(
                "{OSC}",
                &format!("m = 100.0\nk = 1e7\nspeed = 1.0\npath = [1, 2]\ncontact = \"{contact}\""),
            )
            .replace("duration = 0.01", "duration = 0.01\ninitial_static = false")
            + "\n[[load]]\ntype = \"nodal\"\nnode = 9\ndof = \"uz\"\nvalue = 1000.0\n\n[[recorder]]\ntype = \"node\"\nnode = 9\ndofs = [\"uz\"]\nfile = \"z.csv\"\n\n[[recorder]]\ntype = \"element\"\nelement = 10\noutputs = [\"in_contact\", \"contact_force\"]\nfile = \"osc.csv\"\n";
        let dir = temp_dir("unilateral");
        let path = dir.join("m.toml");
        std::fs::write(&path, text).unwrap();
        let out = dir.join("out");
        let o = railfem(&[
            "run",
            path.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        (
            Csv::read(&out.join("z.csv")),
            Csv::read(&out.join("osc.csv")),
        )
    };
    let (z, osc) = run("unilateral");
    for (t, zi) in z.column("time").iter().zip(z.column("9_uz")) {
        let free = 1000.0 * t * t / 200.0;
        assert!(
            (zi - free).abs() < 1e-9 * 5e-4 + 1e-15,
            "t = {t}: {zi} vs {free}"
        );
    }
    let flags = osc.column("10_in_contact");
    assert!(flags[1..].iter().all(|f| *f == 0.0), "{flags:?}");
    assert!(osc.column("10_contact_force").iter().all(|p| *p == 0.0));
    let (zb, _) = run("bonded");
    let last = *zb.column("9_uz").last().unwrap();
    assert!(last.abs() < 2.5 * 1000.0 / 1e7, "bonded z = {last}");
}

/// On a rail of a rigid generated track (no rail DOFs), a slow, stiff, damped sprung mass
/// rides over a dipped joint: the contact follows the documented dip
/// `−depth·[½(1 + cos(2πx/length))]²` exactly at its station, and the mass follows it
/// quasi-statically, `z ≈ r(s) − m·g/k` (excitation at ≈ 6 rad/s against ω = 316 rad/s:
/// dynamic amplification below 1e-3, the start-up transient is damped at ζ = 0.2).
#[test]
fn a_sprung_mass_on_a_rigid_rail_follows_the_dip() {
    let text = r#"
[analysis]
kind = "transient"
dt = 0.005
duration = 2.4
gravity = [0.0, 0.0, -9.81]

[track]
segments = [{type = "straight", length = 60.0}]
dips = [{station = 30.0, depth = 0.002, length = 1.0}]

[[node]]
id = 9
xyz = [0.0, 0.0, 1.0]

[[element]]
type = "moving_sprung_mass"
id = 10
nodes = [9]
m = 1000.0
k = 1e8
c = 126491.0
track = "track"
rail = "left"
start = 29.2
speed = 0.5

[[recorder]]
type = "element"
element = 10
outputs = ["station", "contact_disp", "mass_disp"]
file = "osc.csv"
"#;
    let dir = temp_dir("rail-dip");
    let path = dir.join("m.toml");
    std::fs::write(&path, text).unwrap();
    let out = dir.join("out");
    let o = railfem(&[
        "run",
        path.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let c = Csv::read(&out.join("osc.csv"));
    let dip = |s: f64| {
        let x = s - 30.0;
        if x.abs() > 0.5 {
            0.0
        } else {
            -0.002 * (0.5 * (1.0 + (2.0 * std::f64::consts::PI * x).cos())).powi(2)
        }
    };
    let (s, r, z) = (
        c.column("10_station"),
        c.column("10_contact_disp"),
        c.column("10_mass_disp"),
    );
    let mut deepest = 0.0f64;
    for i in 0..s.len() {
        assert!(
            (r[i] - dip(s[i])).abs() < 1e-12,
            "s = {}: {} vs {}",
            s[i],
            r[i],
            dip(s[i])
        );
        let quasi = dip(s[i]) - 1000.0 * 9.81 / 1e8;
        assert!(
            (z[i] - quasi).abs() < 2e-5,
            "s = {}: z = {} vs {quasi}",
            s[i],
            z[i]
        );
        deepest = deepest.min(r[i]);
    }
    assert!(
        (deepest + 0.002).abs() < 1e-5,
        "the run crossed the dip: {deepest}"
    );
}

/// `railfem run` on the braking example (speed table 27.78 → 21.78 m/s in 1 s, 10 %
/// critical dashpot, 20 elements, dt = 2.5 ms): the recorded station is the table's exact
/// integral (24.78 m at 1 s) and the midspan history, less the sag, is within 1e-2 of the
/// modal solution with the same s(t) (measured ≈ 5e-3).
#[test]
fn the_braking_example_model_file_runs_and_matches() {
    use railfem::framework::speed::SpeedHistory;
    use railfem::oscillators::Rider;
    let out = temp_dir("braking-model");
    let model = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/examples/models/moving_sprung_mass_braking.toml"
    );
    let o = railfem(&["run", model, "--out", out.to_str().unwrap()]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let rec = Csv::read(&out.join("sprung_mass.csv"));
    let (t, s, v) = (
        rec.column("time"),
        rec.column("100_station"),
        rec.column("100_speed"),
    );
    for i in 0..t.len() {
        let want_v = 27.78 - 6.0 * t[i];
        assert!((v[i] - want_v).abs() < 1e-9, "t = {}: v = {}", t[i], v[i]);
        let want_s = 27.78 * t[i] - 3.0 * t[i] * t[i];
        assert!((s[i] - want_s).abs() < 1e-9, "t = {}: s = {}", t[i], s[i]);
    }
    let rows = [[0.0, 27.78], [1.0, 21.78]];
    let case = Case {
        name: "braking example",
        rider: Rider::Sprung {
            m: 5750.0,
            k: 1.595e6,
            c: 9577.0,
        },
        history: SpeedHistory::from_table(0.0, &rows, "speed_table").unwrap(),
        speed_keys: serde_json::json!({"speed_table": rows}),
        t_end: 1.0,
    };
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
    let (em, _) = compare(&fe, &reference(&case));
    eprintln!("braking model file: midspan {em:.3e}");
    assert!(em < 1e-2, "midspan error {em:e}");
    let _ = std::fs::remove_dir_all(&out);
}

//! `railfem study` (issue 15, docs/study.md): the table is the same bytes with one
//! thread, two threads, and after a stop and a resume (by `--stop-after` and by SIGINT);
//! its numbers obey vertical equilibrium, symmetry and the invariance of a zero-intensity
//! record to its seed, and equal `railfem train-bridge`'s summary for the same case; a
//! model-file base matches the closed-form static deflection F/k; failing and panicking
//! cases are recorded and the study goes on; bad plans are refused in one line.

mod common;

use common::{railfem, refused_with, study, temp_dir};
use std::path::{Path, PathBuf};

/// A 12-case plan: 3 synthetic seeds × intensity 0 and 1 × 2 speeds, one carriage on one
/// 10 m span for 0.2 s.
const SMALL: &str = r#"
case = "train-bridge"
[options]
cars = 1
spans = 1
span = 10.0
element_length = 2.5
dt = 0.01
duration = 0.2
pier_height = 5.0
quake_duration = 0.5
pga = 0.3
[[axis]]
name = "seed"
start = 1
stop = 3
step = 1
[[axis]]
name = "quake_scale"
values = [0.0, 1.0]
[[axis]]
name = "speed"
values = [60, 100]
"#;

fn write_plan(dir: &Path, text: &str) -> PathBuf {
    let p = dir.join("plan.toml");
    std::fs::write(&p, text).expect("write plan");
    p
}

/// `railfem train-bridge` on the plans' small case (one carriage on one 10 m span for
/// 0.2 s, seed 2 at 0.3 g, 100 m/s) with `extra` options, writing into `out`.
fn small_train_bridge(out: &Path, extra: &[&str]) -> std::process::Output {
    let mut args = vec![
        "train-bridge",
        "--cars",
        "1",
        "--spans",
        "1",
        "--span",
        "10",
        "--element-length",
        "2.5",
        "--dt",
        "0.01",
        "--duration",
        "0.2",
        "--pier-height",
        "5",
        "--speed",
        "100",
        "--quake",
        "synthetic",
        "--seed",
        "2",
        "--pga",
        "0.3",
        "--quake-duration",
        "0.5",
        "-q",
        "--out",
        out.to_str().expect("utf-8"),
    ];
    args.extend_from_slice(extra);
    railfem(&args)
}

fn ok(o: &std::process::Output) {
    assert_eq!(
        o.status.code(),
        Some(0),
        "stderr: {}",
        String::from_utf8_lossy(&o.stderr)
    );
}

fn table(out: &Path) -> String {
    std::fs::read_to_string(out.join("study.csv")).expect("study.csv")
}

/// The table as (header, rows of cells).
fn cells(text: &str) -> (Vec<String>, Vec<Vec<String>>) {
    let mut lines = text.lines();
    let h = lines
        .next()
        .unwrap()
        .split(',')
        .map(str::to_string)
        .collect();
    let rows = lines
        .map(|l| l.split(',').map(str::to_string).collect())
        .collect();
    (h, rows)
}

fn col(h: &[String], name: &str) -> usize {
    h.iter()
        .position(|c| c == name)
        .unwrap_or_else(|| panic!("no column {name}"))
}

#[test]
fn threads_stops_and_resumes_give_the_same_bytes_and_the_numbers_obey_statics() {
    let dir = temp_dir("study-small");
    let plan = write_plan(&dir, SMALL);
    let one = dir.join("one");
    ok(&study(&plan, &one, &["--threads", "1"]));
    let reference = table(&one);
    let (h, rows) = cells(&reference);
    assert_eq!(rows.len(), 12, "{reference}");
    // Two threads: the same bytes.
    let two = dir.join("two");
    ok(&study(&plan, &two, &["--threads", "2"]));
    assert_eq!(table(&two), reference, "2 threads");
    // Stop after 5 cases, then resume: the checkpoint has 5 rows, the final table the
    // same bytes.
    let part = dir.join("part");
    ok(&study(
        &plan,
        &part,
        &["--threads", "2", "--stop-after", "5"],
    ));
    let ck = std::fs::read_to_string(part.join("study.checkpoint")).unwrap();
    assert_eq!(ck.lines().count(), 1 + 5, "{ck}");
    assert_eq!(cells(&table(&part)).1.len(), 5);
    let o = study(&plan, &part, &["--threads", "1"]);
    ok(&o);
    assert_eq!(table(&part), reference, "resumed");
    // A rerun of a finished study computes nothing and keeps the table.
    let o = study(&plan, &part, &[]);
    ok(&o);
    assert!(
        String::from_utf8_lossy(&o.stdout).contains("0 computed now"),
        "{o:?}"
    );
    assert_eq!(table(&part), reference);
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(part.join("study.json")).unwrap()).unwrap();
    assert_eq!(json["ok"], 12);
    assert_eq!(json["failed"], 0);
    assert_eq!(json["status"], "completed");
    assert_eq!(json["plan"]["case"], "train-bridge");

    // Physics. Vertical equilibrium at the initial state: per wheel ΔQ/Q = (Q_s − Q)/Q_s
    // is largest where Q is smallest, so Q_s = min Q / (1 − max ΔQ/Q); the four wheelsets'
    // Q_s carry the carriage's weight (total mass × 9.81 m/s²; the track is straight and
    // level, so the contact normals are vertical).
    let weight = railfem::elements::rail::vehicle::CarriageData::sks700().total_mass() * 9.81;
    let (c_scale, c_speed, c_seed) = (
        col(&h, "quake_scale [-]"),
        col(&h, "speed [m/s]"),
        col(&h, "seed [-]"),
    );
    for r in &rows {
        assert_eq!(r[col(&h, "status")], "ok", "{r:?}");
        let mut sum = 0.0;
        for w in 1..=4 {
            for side in ["L", "R"] {
                let n = format!("w{w}{side}");
                let q: f64 = r[col(&h, &format!("{n}_min_Q [N]"))].parse().unwrap();
                let d: f64 = r[col(&h, &format!("{n}_max_dQQ [-]"))].parse().unwrap();
                sum += q / (1.0 - d);
            }
        }
        // Six significant digits printed per wheel: 1e-5 relative is ample.
        assert!(
            ((sum - weight) / weight).abs() < 1e-5,
            "case {}: ΣQ_s = {sum} N against the weight {weight} N",
            r[0]
        );
    }
    // Zero intensity: the record's seed cannot matter (same results, cell for cell), and a
    // symmetric carriage on straight, level track feels no lateral force (Y/Q ≈ 0, against
    // a shaken case's Y/Q that is far larger).
    let results = col(&h, "max_YQ [-]");
    let zero: Vec<&Vec<String>> = rows.iter().filter(|r| r[c_scale] == "0").collect();
    assert_eq!(zero.len(), 6);
    for a in &zero {
        for b in &zero {
            if a[c_speed] == b[c_speed] {
                assert_eq!(
                    a[results..],
                    b[results..],
                    "seeds {} {}",
                    a[c_seed],
                    b[c_seed]
                );
            }
        }
        let yq: f64 = a[results].parse().unwrap();
        // What remains is the solver's round-off and tolerance (Newton's 1e-6 relative on
        // forces of 7e4 N), nothing physical: five orders below the 0.8 limit.
        assert!(yq.abs() < 1e-4, "Y/Q at zero intensity: {yq}");
        let shaken = rows
            .iter()
            .find(|r| r[c_scale] == "1" && r[c_seed] == a[c_seed] && r[c_speed] == a[c_speed])
            .unwrap();
        let yq1: f64 = shaken[results].parse().unwrap();
        assert!(
            yq1 > 10.0 * yq,
            "case {}: Y/Q {yq1} under 0.3 g lateral shaking, {yq} without",
            shaken[0]
        );
    }

    // The same case through `railfem train-bridge`: its summary.csv gives the same
    // extremes per wheel (both printed to 7 significant digits from the same run).
    let r = rows
        .iter()
        .find(|r| r[c_seed] == "2" && r[c_scale] == "1" && r[c_speed] == "100")
        .unwrap();
    let tb = dir.join("tb");
    let o = small_train_bridge(&tb, &[]);
    ok(&o);
    let summary = std::fs::read_to_string(tb.join("summary.csv")).unwrap();
    for line in summary.lines().skip(1).take(8) {
        let f: Vec<&str> = line.split(',').collect();
        let n = f[0];
        for (k, name) in [(2, "max_YQ"), (4, "max_dQQ"), (6, "min_Q")] {
            let a: f64 = f[k].parse().unwrap();
            let unit = if name == "min_Q" { "[N]" } else { "[-]" };
            let b: f64 = r[col(&h, &format!("{n}_{name} {unit}"))].parse().unwrap();
            assert!(
                (a - b).abs() <= 1e-6 * a.abs().max(1e-12),
                "{n} {name}: train-bridge {a}, study {b}"
            );
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn sigint_stops_at_a_case_boundary_and_the_study_resumes_to_the_same_table() {
    let dir = temp_dir("study-sigint");
    let plan = write_plan(&dir, SMALL);
    let full = dir.join("full");
    ok(&study(&plan, &full, &["--threads", "2"]));
    let out = dir.join("cut");
    let child = std::process::Command::new(env!("CARGO_BIN_EXE_railfem"))
        .args([
            "study",
            plan.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--threads",
            "1",
            "-q",
        ])
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    // Wait for three finished cases, then interrupt.
    let ck = out.join("study.checkpoint");
    let t0 = std::time::Instant::now();
    loop {
        let n = std::fs::read_to_string(&ck).map_or(0, |t| t.lines().count());
        if n >= 4 || t0.elapsed().as_secs() > 120 {
            break;
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    unsafe {
        libc::kill(child.id() as i32, libc::SIGINT);
    }
    let o = child.wait_with_output().unwrap();
    let done = std::fs::read_to_string(&ck).unwrap().lines().count() - 1;
    if o.status.code() == Some(0) {
        // The study ended before the signal arrived (a very fast machine): nothing to resume.
        assert_eq!(done, 12);
    } else {
        assert_eq!(o.status.code(), Some(130), "{o:?}");
        assert!(done < 12, "{done} cases done before the stop");
        // Every checkpoint line is a whole row.
        let cols = table(&full).lines().next().unwrap().split(',').count();
        for l in std::fs::read_to_string(&ck).unwrap().lines().skip(1) {
            assert_eq!(l.split(',').count(), cols, "{l}");
        }
    }
    ok(&study(&plan, &out, &["--threads", "2"]));
    assert_eq!(table(&out), table(&full));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn failing_and_panicking_cases_are_recorded_and_the_study_goes_on() {
    let dir = temp_dir("study-fail");
    // Speed 0 is refused by the train–bridge case: that case fails, the others run.
    let plan = write_plan(
        &dir,
        &SMALL
            .replace("start = 1\nstop = 3\nstep = 1", "values = [1]")
            .replace("values = [60, 100]", "values = [0, 100]"),
    );
    let out = dir.join("o");
    let mut cmd = std::process::Command::new(env!("CARGO_BIN_EXE_railfem"));
    cmd.args([
        "study",
        plan.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "-q",
        "--threads",
        "2",
    ]);
    // Case 0003 (seed 1, scale 1, speed 100) panics on purpose.
    cmd.env("RAILFEM_STUDY_PANIC_CASE", "0003");
    let o = cmd.output().unwrap();
    ok(&o);
    let (h, rows) = cells(&table(&out));
    let (cs, ce) = (col(&h, "status"), col(&h, "error"));
    let status: Vec<&str> = rows.iter().map(|r| r[cs].as_str()).collect();
    assert_eq!(status, ["failed", "ok", "failed", "failed"], "{rows:?}");
    assert!(rows[0][ce].contains("speed"), "{:?}", rows[0]);
    assert!(rows[3][ce].contains("panic"), "{:?}", rows[3]);
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("study.json")).unwrap()).unwrap();
    assert_eq!(
        (json["ok"].as_u64(), json["failed"].as_u64()),
        (Some(1), Some(3))
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_model_file_base_varies_key_paths_and_matches_the_static_deflection() {
    // The single-DOF oscillator of examples/models/sdof.toml under a step force F = 10 kN:
    // ζω = c/(2m) = 3 s⁻¹ for every k, so at t = 2 s the ringing has decayed to
    // e^(−6) = 0.25 % and u(2 s) = F/k to within that.
    let dir = temp_dir("study-model");
    let model = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/models/sdof.toml"),
    )
    .unwrap();
    std::fs::write(dir.join("sdof.toml"), model).unwrap();
    let plan = write_plan(
        &dir,
        r#"
base = "sdof.toml"
[[axis]]
name = "element.1.k.0"
values = [2e6, 4e6, 8e6]
[[axis]]
name = "analysis.dt"
values = [0.005, 0.01]
"#,
    );
    let out = dir.join("o");
    ok(&study(&plan, &out, &["--threads", "2"]));
    let (h, rows) = cells(&table(&out));
    assert_eq!(rows.len(), 6);
    for r in &rows {
        let k: f64 = r[1].parse().unwrap();
        let dt: f64 = r[2].parse().unwrap();
        let steps: f64 = r[col(&h, "steps [-]")].parse().unwrap();
        assert_eq!(steps, (2.0 / dt).round(), "{r:?}");
        let u: f64 = r[col(&h, "max_abs_disp_end [m]")].parse().unwrap();
        let exact = 1e4 / k;
        assert!(
            ((u - exact) / exact).abs() < 5e-3,
            "k = {k}, dt = {dt}: u = {u} m, F/k = {exact} m"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn bad_plans_are_refused_in_one_line() {
    let dir = temp_dir("study-bad");
    let records = dir.join("empty");
    std::fs::create_dir_all(&records).unwrap();
    std::fs::write(records.join("notes.txt"), "no records here").unwrap();
    let cases: &[(&str, &str, &[&str])] = &[
        (
            "unknown axis",
            "case = \"train-bridge\"\n[[axis]]\nname = \"speeed\"\nvalues = [1]\n",
            &["[[axis]] 1", "speeed", "did you mean `speed`?"],
        ),
        (
            "unknown key",
            "case = \"train-bridge\"\nhistory = true\n",
            &["top level", "history", "did you mean `histories`?"],
        ),
        (
            "unknown option",
            "case = \"curve\"\n[options]\nradiuss = 3\n",
            &["[options]", "radiuss", "radius"],
        ),
        (
            "empty axis",
            "case = \"train-bridge\"\n[[axis]]\nname = \"speed\"\nvalues = []\n",
            &["[[axis]] 1 (speed)", "no values", "give at least one"],
        ),
        (
            "no csv",
            "case = \"train-bridge\"\n[[axis]]\nname = \"quake\"\ndir = \"empty\"\n",
            &["[[axis]] 1 (quake)", "no *.csv record", "examples/records"],
        ),
        (
            "missing model",
            "base = \"nowhere.toml\"\n",
            &["`base`", "nowhere.toml", "does not exist"],
        ),
        (
            "bad key path",
            "base = \"m.toml\"\n[[axis]]\nname = \"analysis.dtt\"\nvalues = [0.1]\n",
            &["analysis.dtt", "did you mean `dt`?"],
        ),
        (
            "two ways",
            "case = \"curve\"\n[[axis]]\nname = \"speed\"\nvalues = [1]\nstart = 1\nstop = 2\nstep = 1\n",
            &["exactly one of"],
        ),
    ];
    std::fs::write(
        dir.join("m.toml"),
        std::fs::read_to_string(
            Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/models/sdof.toml"),
        )
        .unwrap(),
    )
    .unwrap();
    for (label, text, expect) in cases {
        let plan = write_plan(&dir, text);
        let o = study(&plan, &dir.join("out"), &[]);
        let err = refused_with(label, &o, expect);
        assert!(err.contains("plan.toml"), "{label}: {err}");
    }
    // A checkpoint of another plan is refused, naming the file and the fix.
    let plan = write_plan(&dir, SMALL);
    let out = dir.join("ck");
    ok(&study(
        &plan,
        &out,
        &["--stop-after", "1", "--threads", "1"],
    ));
    let plan = write_plan(
        &dir,
        &SMALL.replace("values = [60, 100]", "values = [60, 90]"),
    );
    let o = study(&plan, &out, &[]);
    refused_with(
        "changed plan",
        &o,
        &["study.checkpoint", "another plan", "--restart"],
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_model_file_base_reports_its_wheels_extremes_as_its_recorders_see_them() {
    // A carriage of examples/models/irregular_straight.toml over two 2 mm bumps: the study
    // reads every wheel element's Q, Y/Q and ΔQ/Q after each step; the model's own element
    // recorder writes every wheel's Q each step (record_every = 1) by another path. The
    // table's min Q, its wheel and its time must be the recorder's (to the table's seven
    // digits); the bumps unload the wheels (at 10 m/s by 0.3 %: min Q at least 0.2 % under the first step's Q),
    // and with the same profile under both rails Y/Q stays at round-off (< 1e-3).
    let dir = temp_dir("study-wheels");
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/models");
    let model = std::fs::read_to_string(src.join("irregular_straight.toml")).unwrap();
    std::fs::write(dir.join("irregular_straight.toml"), model).unwrap();
    std::fs::copy(
        src.join("irregular_straight.csv"),
        dir.join("irregular_straight.csv"),
    )
    .unwrap();
    let plan = write_plan(
        &dir,
        "base = \"irregular_straight.toml\"\nhistories = true\n[[axis]]\nname = \"vehicle.0.speed\"\nvalues = [10.0, 20.0]\n",
    );
    let out = dir.join("o");
    ok(&study(&plan, &out, &["--threads", "2"]));
    let (h, rows) = cells(&table(&out));
    assert_eq!(rows.len(), 2);
    for r in &rows {
        let get = |k: &str| r[col(&h, k)].clone();
        let rec = std::fs::read_to_string(out.join("cases").join(&r[0]).join("wheels.csv"))
            .expect("the case's recorder file");
        let (rh, rr) = cells(&rec);
        // Element-recorder columns: `<id>_Q [N]`; each wheel's (min Q, t) as recorded.
        let mut mins: Vec<(String, f64, f64)> = Vec::new();
        let mut first = f64::INFINITY;
        for (j, name) in rh.iter().enumerate() {
            let Some(id) = name.strip_suffix("_Q [N]") else {
                continue;
            };
            first = first.min(rr[1][j].parse::<f64>().unwrap());
            let mut m = (f64::INFINITY, 0.0);
            for row in &rr[1..] {
                let q: f64 = row[j].parse().unwrap();
                if q < m.0 {
                    m = (q, row[0].parse().unwrap());
                }
            }
            mins.push((format!("e{id}"), m.0, m.1));
        }
        assert_eq!(mins.len(), 8, "eight wheels recorded");
        let lowest = mins.iter().map(|m| m.1).fold(f64::INFINITY, f64::min);
        let min_q: f64 = get("min_Q [N]").parse().unwrap();
        assert!(
            ((min_q - lowest) / lowest).abs() < 1e-6,
            "{r:?}: min Q {min_q} against the recorder's {lowest}"
        );
        // The table's wheel is one whose recorded minimum is the lowest (left and right
        // wheels tie to round-off under a profile common to both rails), at its time.
        let (_, q_w, t_w) = mins
            .iter()
            .find(|m| m.0 == get("min_Q_wheel"))
            .unwrap_or_else(|| panic!("{r:?}: no recorded wheel {}", get("min_Q_wheel")));
        assert!(((q_w - lowest) / lowest).abs() < 1e-9, "{r:?}: {q_w}");
        let t: f64 = get("t_min_Q [s]").parse().unwrap();
        assert!((t - t_w).abs() < 1e-9, "{r:?}: t {t} against {t_w}");
        assert!(
            min_q < 0.998 * first,
            "{r:?}: the bumps must unload a wheel"
        );
        let dqq: f64 = get("max_dQQ [-]").parse().unwrap();
        assert!(dqq > 2e-3, "{r:?}: max ΔQ/Q {dqq}");
        let yq: f64 = get("max_YQ [-]").parse().unwrap();
        assert!((0.0..1e-3).contains(&yq), "{r:?}: Y/Q {yq}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// `first_active_set` as a study axis and as `railfem train-bridge --first-active-set`: each
/// study case writes the history of the command-line run with the same setting, byte for
/// byte (one case, same code path), and the two settings converge to the same wheel forces
/// within Newton's tolerance (relative 1e-6 of the residual, `train_bridge::build`): the
/// setting changes only the first iterate's tangent, not the equations solved.
#[test]
fn first_active_set_reaches_the_case_from_a_plan_and_from_the_command_line() {
    let dir = temp_dir("study-first-active-set");
    // SMALL's options with one seed at full intensity and one speed, and the axis.
    let options = SMALL.split("[[axis]]").next().expect("options");
    let plan = write_plan(
        &dir,
        &format!(
            "{}speed = 100\nseed = 2\n[[axis]]\nname = \"first_active_set\"\nvalues = [\"committed\", \"found\"]\n",
            options.replace("case = \"train-bridge\"\n", "case = \"train-bridge\"\nhistories = true\n")
        ),
    );
    let out = dir.join("out");
    ok(&study(&plan, &out, &["--threads", "1"]));
    let (h, rows) = cells(&table(&out));
    let c_set = col(&h, "first_active_set [-]");
    let c_id = col(&h, "case");
    let mut wheels = Vec::new();
    for setting in ["committed", "found"] {
        let row = rows
            .iter()
            .find(|r| r[c_set] == setting)
            .unwrap_or_else(|| panic!("no {setting} row"));
        let from_study =
            std::fs::read_to_string(out.join("cases").join(&row[c_id]).join("wheels.csv"))
                .expect("the case's wheels.csv");
        let tb = dir.join(setting);
        ok(&small_train_bridge(&tb, &["--first-active-set", setting]));
        let from_cli = std::fs::read_to_string(tb.join("wheels.csv")).unwrap();
        assert_eq!(
            from_study, from_cli,
            "{setting}: study and command line differ"
        );
        wheels.push(from_cli);
    }
    // The settings differ in the first iterate only: the histories are not the same bytes
    // (so the comparison above tells them apart) but the same forces within tolerance.
    assert_ne!(wheels[0], wheels[1], "the setting changed nothing");
    let (hq, committed) = cells(&wheels[0]);
    let (_, found) = cells(&wheels[1]);
    let mut q_max = 0.0f64;
    let mut worst = 0.0f64;
    for (a, b) in committed.iter().zip(&found) {
        for (k, name) in hq.iter().enumerate() {
            if name.ends_with("_Q [N]") {
                let (x, y): (f64, f64) = (a[k].parse().unwrap(), b[k].parse().unwrap());
                q_max = q_max.max(x.abs());
                worst = worst.max((x - y).abs());
            }
        }
    }
    assert!(
        worst <= 1e-5 * q_max,
        "Q differs by {worst} N of {q_max} N between the settings"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

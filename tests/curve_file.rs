//! The curved-track case as a model file (`examples/models/curve_quick.toml`: `[track]`,
//! `[[vehicle]]` and an element recorder of every `moving_axle`), run through the CLI.
//!
//! Checks, against rigid-body statics: at t = 0 on the straight every wheel carries an
//! eighth of the carriage's weight, `W/8 = 56 062.5 kg · 9.81 / 8`, to 1e-9; on the arc,
//! once the whole carriage is 400 m in, every wheel's normal force equals the statics of
//! Eqs. 22–25 (moment arm: the contact spacing 1.507 m of S1002 on 60E1 1:40) within 0.5 %.

use railfem::elements::rail::vehicle::theory::{self, Carriage, Operation, TrackParams, Variant};
use std::process::Command;

#[test]
fn curve_model_file_matches_statics() {
    let root = env!("CARGO_MANIFEST_DIR");
    let out = std::env::temp_dir().join(format!("railfem-curve-file-{}", std::process::id()));
    let st = Command::new(env!("CARGO_BIN_EXE_railfem"))
        .args([
            "run",
            &format!("{root}/examples/models/curve_quick.toml"),
            "--out",
        ])
        .arg(&out)
        .output()
        .expect("runs");
    assert!(
        st.status.success(),
        "{}",
        String::from_utf8_lossy(&st.stderr)
    );
    let text = std::fs::read_to_string(out.join("wheels.csv")).expect("wheels.csv");
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().expect("header").split(',').collect();
    let rows: Vec<Vec<f64>> = lines
        .map(|l| l.split(',').map(|x| x.parse().expect("number")).collect())
        .collect();
    let n_wheels = (header.len() - 1) / 3;
    assert_eq!(n_wheels, 8);
    let w8 = 56_062.5 * 9.81 / 8.0;
    for k in 0..n_wheels {
        let q = rows[0][1 + 3 * k + 1];
        assert!(
            (q - w8).abs() < 1e-9 * w8,
            "wheel {k} at t = 0: {q} vs {w8}"
        );
    }
    let carriage = Carriage::sks700_standin_with_gravity(9.81);
    let op = Operation {
        speed: 80.0,
        cant_constant: 200.0,
        mu: 0.3,
    };
    let tp = TrackParams {
        gauge: 1.507,
        gravity: 9.81,
    };
    let th = theory::evaluate(&carriage, &tp, &op, 6250.0, Variant::Statics).expect("theory");
    let (arc0, arc1) = (360.0, 1060.0);
    let mut checked = 0;
    let mut worst: f64 = 0.0;
    for r in &rows {
        let stations: Vec<f64> = (0..n_wheels).map(|k| r[1 + 3 * k]).collect();
        if !stations.iter().all(|s| *s > arc0 + 400.0 && *s < arc1) {
            continue;
        }
        for k in 0..n_wheels {
            // Wheels are left, right per wheelset; the left one is inner on a left-hand curve.
            let expect = if k % 2 == 0 {
                th.normal_inner
            } else {
                th.normal_outer
            };
            let q = r[1 + 3 * k + 1];
            worst = worst.max((q - expect).abs() / expect);
        }
        checked += 1;
    }
    assert!(checked >= 20, "only {checked} rows on the settled arc");
    assert!(worst < 5e-3, "normal force vs statics: {worst:e}");
}

/// A train of two coupled carriages standing on a straight, level track (static analysis
/// under gravity): the couplers carry nothing and each of the 16 wheels carries an eighth
/// of its carriage's weight, to 1e-9.
#[test]
fn two_coupled_carriages_share_their_weight() {
    let dir = std::env::temp_dir().join(format!("railfem-train-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let model = dir.join("train.toml");
    std::fs::write(
        &model,
        r#"
[analysis]
kind = "static"
gravity = [0.0, 0.0, -9.81]

[track]
segments = [{type = "straight", length = 200.0}]
support = {type = "rigid"}

[[vehicle]]
preset = "sks700"
carriages = 2
start = 100.0
speed = 0.0

[[recorder]]
type = "element"
kind = "moving_axle"
outputs = ["Q"]
file = "wheels.csv"
"#,
    )
    .unwrap();
    let st = Command::new(env!("CARGO_BIN_EXE_railfem"))
        .args(["run"])
        .arg(&model)
        .arg("--out")
        .arg(dir.join("out"))
        .output()
        .expect("runs");
    assert!(
        st.status.success(),
        "{}",
        String::from_utf8_lossy(&st.stderr)
    );
    let text = std::fs::read_to_string(dir.join("out/wheels.csv")).unwrap();
    let row: Vec<f64> = text
        .lines()
        .nth(1)
        .unwrap()
        .split(',')
        .map(|x| x.parse().unwrap())
        .collect();
    assert_eq!(row.len(), 1 + 16);
    let w8 = 56_062.5 * 9.81 / 8.0;
    for q in &row[1..] {
        assert!((q - w8).abs() < 1e-9 * w8, "{q} vs {w8}");
    }
}

//! Vehicles defined from scratch: the preset written as a vehicle file gives the built-in
//! carriage's results bit for bit; a second vehicle with published data (the Manchester
//! Benchmark passenger vehicle, `examples/vehicles/manchester_benchmark.toml`) stands and
//! runs on the paper's curve and on a bridge as the statics say; and in nonlinear geometry
//! the static solve's preloads hold every body where the data put it.

mod common;
use common::{railfem, temp_dir, Csv};
use railfem::elements::rail::vehicle::theory::{self, Carriage, Operation, TrackParams, Variant};
use railfem::framework::modelfile;
use railfem::solvers::Driver;
use std::path::Path;

const ROOT: &str = env!("CARGO_MANIFEST_DIR");

/// Masses (kg) and mass-centre heights (m) of the Manchester vehicle, from its file.
const MANCHESTER: [(&str, f64, f64); 3] = [
    ("wheelsets", 4.0 * 1813.0, 0.46),
    ("bogies", 2.0 * 2615.0, 0.6),
    ("car body", 32000.0, 1.8),
];

fn manchester_mass() -> f64 {
    MANCHESTER.iter().map(|b| b.1).sum()
}

fn run_ok(model: &Path, out: &Path) {
    let o = railfem(&[
        "run",
        model.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(
        o.status.success(),
        "{}: {}",
        model.display(),
        String::from_utf8_lossy(&o.stderr)
    );
}

/// The built-in carriage (`preset` with `carriage` overrides: the Rust template
/// `CarriageData`, expanded) and the same carriage from `examples/vehicles/sks700.toml`
/// (`file = …`, and `preset = "sks700"` alone, which loads that file) give bitwise the same
/// wheel-force histories on a short canted curve: 60 transient steps, every wheel's
/// station, Q, Y, Y/Q and ΔQ/Q written with 13 significant digits.
#[test]
fn vehicle_file_gives_bitwise_the_builtin_case() {
    let dir = temp_dir("bitwise");
    let file = format!("{ROOT}/examples/vehicles/sks700.toml");
    let variants = [
        (
            "builtin",
            "preset = \"sks700\"\ncarriage = {anti_roll = 0.0}".to_string(),
        ),
        ("file", format!("file = {file:?}")),
        ("preset", "preset = \"sks700\"".to_string()),
    ];
    let mut texts = Vec::new();
    for (name, vehicle) in &variants {
        let model = dir.join(format!("{name}.toml"));
        std::fs::write(
            &model,
            format!(
                r#"
[analysis]
kind = "transient"
dt = 0.01
duration = 0.6
gravity = [0.0, 0.0, -9.81]

[track]
segments = [
  {{type = "straight", length = 40.0}},
  {{type = "clothoid", length = 60.0}},
  {{type = "arc", length = 100.0, radius = 1200.0, hand = "left"}},
]
ct = 60.0
support = {{type = "rigid"}}

[[vehicle]]
{vehicle}
start = 45.0
speed = 60.0
wheel = {{mu = 0.3}}
record = {{wheels = "wheels.csv"}}
"#
            ),
        )
        .unwrap();
        let out = dir.join(format!("out_{name}"));
        run_ok(&model, &out);
        texts.push(std::fs::read(out.join("wheels.csv")).unwrap());
    }
    let csv = Csv::read(&dir.join("out_builtin/wheels.csv"));
    assert_eq!(csv.rows.len(), 61, "one row per step and t = 0");
    assert_eq!(
        texts[0], texts[1],
        "file = sks700.toml differs from the built-in carriage"
    );
    assert_eq!(
        texts[0], texts[2],
        "preset = \"sks700\" differs from the built-in carriage"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// The Manchester vehicle on the paper's curve, shortened
/// (`examples/models/manchester_curve.toml`): at t = 0 on the straight every wheel carries
/// an eighth of its weight (a symmetric vehicle on level track), to 1e-9; on the arc, once
/// the whole vehicle is 400 m in, every wheel's Q equals the rigid-body statics of Eqs.
/// 22–25 with this vehicle's masses and heights (contact spacing 1.507 m) within 0.5 % —
/// the tolerance of the same check for the sks700 carriage (tests/curve_file.rs). The
/// sensors' file has three accelerations per sensor.
#[test]
fn manchester_vehicle_on_the_curve_follows_the_statics() {
    let out = temp_dir("manchester-curve");
    run_ok(
        Path::new(&format!("{ROOT}/examples/models/manchester_curve.toml")),
        &out,
    );
    let w = Csv::read(&out.join("wheels.csv"));
    let q_cols: Vec<usize> = (0..w.header.len())
        .filter(|&i| common::strip_unit(&w.header[i]).ends_with("_Q"))
        .collect();
    let s_cols: Vec<usize> = (0..w.header.len())
        .filter(|&i| common::strip_unit(&w.header[i]).ends_with("_station"))
        .collect();
    assert_eq!(q_cols.len(), 8);
    let g = 9.81;
    let w8 = manchester_mass() * g / 8.0;
    for &c in &q_cols {
        let q = w.rows[0][c];
        assert!((q - w8).abs() < 1e-9 * w8, "t = 0: {q} vs {w8}");
    }
    let carriage = Carriage::from_masses(&MANCHESTER, 8, g);
    let op = Operation {
        speed: 80.0,
        cant_constant: 200.0,
        mu: 0.3,
    };
    let tp = TrackParams {
        gauge: 1.507,
        gravity: g,
    };
    let th = theory::evaluate(&carriage, &tp, &op, 6250.0, Variant::Statics).expect("theory");
    let (arc0, arc1) = (360.0, 1060.0);
    let (mut checked, mut worst) = (0, 0.0f64);
    for r in &w.rows {
        if !s_cols.iter().all(|&c| r[c] > arc0 + 400.0 && r[c] < arc1) {
            continue;
        }
        for (k, &c) in q_cols.iter().enumerate() {
            // Left, right per wheelset; the left wheel is the inner one on a left-hand arc.
            let expect = if k % 2 == 0 {
                th.normal_inner
            } else {
                th.normal_outer
            };
            worst = worst.max((r[c] - expect).abs() / expect);
        }
        checked += 1;
    }
    assert!(checked >= 20, "only {checked} rows on the settled arc");
    assert!(worst < 5e-3, "Q vs statics: {worst:e}");
    // Sensors front (x = 9.5), centre (0) and rear (−9.5 m), same y and z, rigidly tied to
    // the car body: under linear links a point's acceleration is linear in its position,
    // so a_front + a_rear = 2·a_centre, component by component.
    let a = Csv::read(&out.join("car_acc.csv"));
    assert_eq!(a.header.len(), 1 + 3 * 3, "{:?}", a.header);
    let scale = a
        .rows
        .iter()
        .flat_map(|r| r[1..].iter())
        .fold(0.0f64, |m, v| m.max(v.abs()));
    assert!(scale > 1e-3, "the car body does not move: {scale}");
    for r in &a.rows {
        for c in 0..3 {
            let mismatch = r[1 + c] + r[7 + c] - 2.0 * r[4 + c];
            assert!(mismatch.abs() < 1e-9 * scale, "t = {}: {mismatch}", r[0]);
        }
    }
    let _ = std::fs::remove_dir_all(&out);
}

/// Two coupled Manchester vehicles standing on a one-span bridge (static analysis under
/// gravity): the 16 wheels' Q add up to the train's weight, to 1e-9 (equilibrium of the
/// whole train, whatever the girder's deflection does to the share of each wheel).
#[test]
fn manchester_train_on_a_bridge_carries_its_weight() {
    let dir = temp_dir("manchester-bridge");
    let model = dir.join("bridge.toml");
    std::fs::write(
        &model,
        format!(
            r#"
[analysis]
kind = "static"
gravity = [0.0, 0.0, -9.81]

[track]
segments = [{{type = "straight", length = 120.0}}]
element_length = 1.0
support = {{type = "bridge", start = 30.0, spans = 1, span = 40.0}}

[[vehicle]]
file = "{ROOT}/examples/vehicles/manchester_benchmark.toml"
count = 2
start = 62.5
speed = 0.0
record = {{wheels = "wheels.csv"}}
"#
        ),
    )
    .unwrap();
    run_ok(&model, &dir.join("out"));
    let w = Csv::read(&dir.join("out/wheels.csv"));
    let q: f64 = (0..w.header.len())
        .filter(|&i| common::strip_unit(&w.header[i]).ends_with("_Q"))
        .map(|i| w.rows[0][i])
        .sum();
    let weight = 2.0 * manchester_mass() * 9.81;
    assert!((q - weight).abs() < 1e-9 * weight, "ΣQ = {q} vs {weight}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Static state of the Manchester vehicle on straight, level, rigid track, in both
/// geometries. Linear: the car body sinks on its springs by about
/// `W_car/(4·k_2z) + (W_car + 2·W_bogie)/(8·k_1z)` ≈ 0.22 m. Nonlinear: each suspension
/// carries the preload of the static solve (the file gives no `carries`), so the bodies
/// stay where the data put them relative to the wheelsets (which only sink into the
/// contact springs): the car body moves with the front wheelset to within 1e-6 m.
#[test]
fn static_solve_preloads_hold_the_bodies_in_nonlinear_geometry() {
    let sag = |geometry: &str| -> (f64, f64) {
        let text = format!(
            r#"
[analysis]
kind = "static"
gravity = [0.0, 0.0, -9.81]

[track]
segments = [{{type = "straight", length = 80.0}}]
support = {{type = "rigid"}}

[[vehicle]]
file = "{ROOT}/examples/vehicles/manchester_benchmark.toml"
geometry = "{geometry}"
start = 40.0
speed = 0.0
"#
        );
        let value = modelfile::parse_toml(&text, "sag.toml").expect("toml");
        let b = modelfile::from_value(&value, "sag.toml", Path::new(ROOT)).expect("model");
        let model = b.build().expect("build");
        // Car body master at (40, 0, 1.8), front wheelset at (50.78, 0, 0.46).
        let find = |x: f64, z: f64| {
            model
                .nodes
                .iter()
                .find(|n| {
                    (n.position.x - x).abs() < 1e-6
                        && n.position.y.abs() < 1e-6
                        && (n.position.z - z).abs() < 1e-6
                })
                .map(|n| n.id)
                .expect("body node")
        };
        let (car, ws) = (find(40.0, 1.8), find(50.78, 0.46));
        let mut d = Driver::new(model).expect("driver");
        d.static_solve(0.0, 2).expect("static solve");
        // DOF 1 of a carried node: vertical deviation in the wheel frame.
        (
            d.displacement(car, railfem::framework::Dof::Uy).unwrap(),
            d.displacement(ws, railfem::framework::Dof::Uy).unwrap(),
        )
    };
    let (car_l, ws_l) = sag("linear");
    let expect = 32000.0 * 9.81 / (4.0 * 430e3) + 37230.0 * 9.81 / (8.0 * 1220e3);
    assert!(
        ((car_l - ws_l) + expect).abs() < 1e-3 * expect,
        "linear sag {} vs {expect}",
        ws_l - car_l
    );
    let (car_n, ws_n) = sag("nonlinear");
    assert!(
        (car_n - ws_n).abs() < 1e-6,
        "nonlinear: car {car_n}, wheelset {ws_n}"
    );
}

/// The sensors of a model file's trains are published by name for recorders (the comfort
/// hook): the Manchester file's three car-body sensors, twice for `count = 2`, each a
/// node of the model at its point — the front one 9.5 m ahead of the centre, 1.0 m above
/// the rail top.
#[test]
fn sensors_are_published_by_name() {
    let text = format!(
        r#"
[track]
segments = [{{type = "straight", length = 120.0}}]
support = {{type = "rigid"}}

[[vehicle]]
name = "pair"
file = "{ROOT}/examples/vehicles/manchester_benchmark.toml"
count = 2
start = 70.0
speed = 0.0
"#
    );
    let value = modelfile::parse_toml(&text, "s.toml").expect("toml");
    let b = modelfile::from_value(&value, "s.toml", Path::new(ROOT)).expect("model");
    let list = b
        .resource_get(railfem::elements::rail::vehicle::section::SENSORS_RESOURCE)
        .and_then(|r| r.downcast::<Vec<(String, u64)>>().ok())
        .expect("sensors published");
    let names: Vec<&str> = list.iter().map(|s| s.0.as_str()).collect();
    assert_eq!(
        names,
        [
            "pair/v0_floor_front",
            "pair/v0_floor_centre",
            "pair/v0_floor_rear",
            "pair/v1_floor_front",
            "pair/v1_floor_centre",
            "pair/v1_floor_rear"
        ]
    );
    let model = b.build().expect("build");
    // Second vehicle's centre at 70 − 25 = 45 m; its front sensor at 54.5 m, 1.0 m up.
    let i = model.node(list[3].1).expect("sensor node");
    let p = model.nodes[i].position;
    assert!(
        (p.x - 54.5).abs() < 1e-9 && p.y.abs() < 1e-9 && (p.z - 1.0).abs() < 1e-9,
        "{p:?}"
    );
}

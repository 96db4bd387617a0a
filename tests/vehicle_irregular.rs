//! A user's own vehicle on a generated irregular track, through `railfem run`: a two-axle
//! wagon written inline in the model file, riding on `hertz_wheel` point contacts over a
//! German low-disturbance vertical profile, with a floor sensor and its ride-comfort index.
//! The pieces come from four modules (vehicle builder, point wheels, irregularity,
//! comfort recorder); these checks tie them together with balances that hold whatever the
//! profile is.

mod common;
use common::{railfem, temp_dir, Csv};
use railfem::elements::rail::vehicle::comfort::{sperling_wz, Direction};

/// Body and axle masses of the wagon below (kg).
const BODY: f64 = 20_000.0;
const AXLE: f64 = 1_300.0;
const G: f64 = 9.81;

fn model(dir: &std::path::Path) -> std::path::PathBuf {
    let text = format!(
        r#"
[analysis]
kind = "transient"
dt = 0.002
duration = 6.0
gravity = [0.0, 0.0, -{G}]

[track]
segments = [{{type = "straight", length = 260.0}}]
support = {{type = "rigid"}}
irregularity = {{psd = "german_low", seed = 11, wavelengths = [2.0, 40.0], components = ["vertical"]}}

[[vehicle]]
name = "wagon"
start = 20.0
speed = 30.0
length = 12.0
record = {{wheels = "wheels.csv", sensors = "floor.csv", comfort = "comfort.csv"}}

[[vehicle.body]]
name = "body"
mass = {BODY}
ixx = 2.0e4
iyy = 2.0e5
izz = 2.0e5
z = 1.5

[[vehicle.body]]
name = "axle_1"
mass = {AXLE}
ixx = 700.0
iyy = 90.0
izz = 700.0
x = 3.0
z = 0.46

[[vehicle.body]]
name = "axle_2"
mass = {AXLE}
ixx = 700.0
iyy = 90.0
izz = 700.0
x = -3.0
z = 0.46

[[vehicle.suspension]]
lower = "axle_1"
upper = "body"
at = [3.0, 1.0, 0.46]
k = [5e6, 2e6, 1e6]
c = [0.0, 1e4, 1e4]
mirror = true

[[vehicle.suspension]]
lower = "axle_2"
upper = "body"
at = [-3.0, 1.0, 0.46]
k = [5e6, 2e6, 1e6]
c = [0.0, 1e4, 1e4]
mirror = true

[[vehicle.wheelset]]
body = "axle_1"
wheel = {{model = "hertz_wheel"}}

[[vehicle.wheelset]]
body = "axle_2"
wheel = {{model = "hertz_wheel"}}

[[vehicle.sensor]]
name = "floor"
body = "body"
at = [0.0, 0.0, 1.0]
"#
    );
    let path = dir.join("wagon.toml");
    std::fs::write(&path, text).unwrap();
    path
}

/// The four wheels' vertical forces: in the initial static state they carry the wagon's
/// weight (vertical equilibrium, to the Newton tolerance 1e-8); averaged over the run they
/// still do, up to the change of the bodies' vertical momentum over the run divided by
/// its length (|Δp|/T ≤ m·|Δv|/T: 21 600 kg · 0.02 m/s / 6 s ≈ 72 N, 3.4e-4 of the
/// weight; the assertion allows 1e-3). The floor sensor's Sperling index in the comfort
/// file is the index of the floor's recorded vertical acceleration (the recorder takes
/// `uy`, vertical in a vehicle node's axes), to the file's seven significant digits.
#[test]
fn wagon_on_generated_irregularity_balances_its_weight_and_rates_its_ride() {
    let dir = temp_dir("vehicle_irregular");
    let m = model(&dir);
    let out = dir.join("out");
    let o = railfem(&["run", m.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));

    let weight = (BODY + 2.0 * AXLE) * G;
    let w = Csv::read(&out.join("wheels.csv"));
    let q_cols: Vec<&String> = w
        .header
        .iter()
        .filter(|h| common::strip_unit(h).ends_with("_Q"))
        .collect();
    assert_eq!(q_cols.len(), 4, "four wheels: {:?}", w.header);
    let t = w.column("time");
    let total: Vec<f64> = (0..t.len())
        .map(|i| q_cols.iter().map(|c| w.column(c)[i]).sum())
        .collect();
    assert!(
        ((total[0] - weight) / weight).abs() < 1e-6,
        "static: ΣQ = {} N, weight {} N",
        total[0],
        weight
    );
    // The profile does excite the wagon: the wheel loads swing by more than 1 %.
    let (lo, hi) = total
        .iter()
        .fold((f64::MAX, f64::MIN), |(a, b), &x| (a.min(x), b.max(x)));
    assert!(hi - lo > 0.01 * weight, "ΣQ swings only {} N", hi - lo);
    let mut integral = 0.0;
    for i in 1..t.len() {
        integral += 0.5 * (total[i] + total[i - 1]) * (t[i] - t[i - 1]);
    }
    let mean = integral / (t[t.len() - 1] - t[0]);
    assert!(
        ((mean - weight) / weight).abs() < 1e-3,
        "mean ΣQ = {mean} N, weight {weight} N"
    );

    let floor = Csv::read(&out.join("floor.csv"));
    let vertical = floor
        .header
        .iter()
        .find(|h| common::strip_unit(h).ends_with("_uy"))
        .expect("uy column")
        .clone();
    // The header carries the unit of the sensors' quantity (acc): `12_uy [m/s²]`.
    assert!(vertical.ends_with(" [m/s²]"), "{vertical}");
    let node = common::strip_unit(&vertical)
        .trim_end_matches("_uy")
        .to_string();
    let wz = sperling_wz(
        &floor.column("time"),
        &floor.column(&vertical),
        Direction::Vertical,
    )
    .expect("Wz");
    let text = std::fs::read_to_string(out.join("comfort.csv")).unwrap();
    let mut header = text.lines().next().unwrap().split(',');
    let wz_col = header
        .position(|h| common::strip_unit(h) == "wz")
        .expect("wz column");
    let row = text
        .lines()
        .skip(1)
        .map(|l| l.split(',').collect::<Vec<_>>())
        .find(|r| r[0] == node && r[1] == "uy")
        .unwrap_or_else(|| panic!("no vertical row for node {node} in\n{text}"));
    let filed: f64 = row[wz_col].parse().unwrap();
    assert!(
        (filed - wz).abs() < 1e-6 * wz,
        "comfort file Wz {filed}, from the floor record {wz}"
    );
    // A German low-disturbance profile at 30 m/s on a stiffly sprung wagon is a ride,
    // not a standstill: the index is well above the threshold of perception (Wz ≈ 1).
    assert!(wz > 1.0, "Wz = {wz}");
}

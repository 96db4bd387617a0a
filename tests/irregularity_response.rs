//! A sprung mass on rigid track over a sinusoidal irregularity, through `railfem run`,
//! against the closed-form steady-state response of a base-excited oscillator.
//!
//! A `moving_sprung_mass` (m, k, c, bonded, no wheel mass) rides a rigid rail at constant
//! speed v over a vertical profile `r(s) = A·sin(2πs/λ)` read from a CSV table. Its foot
//! follows `r(v·t)`, so `m·z̈ + c·(ż − ṙ) + k·(z − r) = 0`: base excitation at
//! `ω = 2πv/λ`. Once the free vibration has decayed the mass moves harmonically with
//!
//! ```text
//! |Z| / A = √(k² + (c·ω)²) / √((k − m·ω²)² + (c·ω)²),      |Z̈| = ω²·|Z|.
//! ```
//!
//! Tolerance budget (relative): the free vibration `exp(−ζ·ω_n·t)` = e⁻¹⁴ ≈ 8e-7 at the
//! start of the measured window; Newmark's average acceleration keeps amplitudes and
//! lengthens periods by (ω·Δt)²/12 ≈ 5e-5, which shifts the response along the
//! resonance curve by about twice that; a peak read from steps of Δt misses the crest by
//! at most 1 − cos(ω·Δt/2) ≈ 2e-5; the cubic spline through the table (knots every 5 cm,
//! λ = 5 m) is within 5/384·(2πh/λ)⁴·A ≈ 5e-8·A of the sine. All together below 3e-4:
//! the assertion allows 1e-3.

mod common;
use common::{railfem, temp_dir, Csv};
use std::f64::consts::PI;

const M: f64 = 1000.0; // kg
const K: f64 = 1.0e5; // N/m
const C: f64 = 4.0e3; // N·s/m: ζ = c/(2√(km)) = 0.2
const V: f64 = 10.0; // m/s
const LAMBDA: f64 = 5.0; // m
const A: f64 = 0.002; // m
const DT: f64 = 0.002; // s
const DURATION: f64 = 12.0; // s

fn write_case(dir: &std::path::Path) -> std::path::PathBuf {
    let mut csv = String::from("station_m,vertical_mm\n");
    let h = 0.05;
    for i in 0..=4000 {
        let s = i as f64 * h;
        csv.push_str(&format!(
            "{s:.3},{:.12}\n",
            1e3 * A * (2.0 * PI * s / LAMBDA).sin()
        ));
    }
    std::fs::write(dir.join("sine.csv"), csv).unwrap();
    let model = format!(
        r#"
[analysis]
kind = "transient"
dt = {DT}
duration = {DURATION}
initial_static = false

[track]
segments = [{{type = "straight", length = 200.0}}]
support = {{type = "rigid"}}
irregularity = {{file = "sine.csv", components = ["vertical"]}}

[[node]]
id = 1
xyz = [0.0, 0.0, 1.0]

[[element]]
type = "moving_sprung_mass"
id = 1
nodes = [1]
m = {M}
k = {K}
c = {C}
track = "track"
rail = "left"
start = 20.0
speed = {V}

[[recorder]]
type = "element"
element = 1
outputs = ["mass_disp", "mass_acc", "contact_disp"]
file = "mass.csv"
"#
    );
    let path = dir.join("sine.toml");
    std::fs::write(&path, model).unwrap();
    path
}

#[test]
fn sprung_mass_over_a_sine_profile_has_the_closed_form_steady_state() {
    let dir = temp_dir("irregularity_response");
    let model = write_case(&dir);
    let out = dir.join("out");
    let o = railfem(&[
        "run",
        model.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let csv = Csv::read(&out.join("mass.csv"));
    let t = csv.column("time");
    let z = csv.column("1_mass_disp");
    let acc = csv.column("1_mass_acc");
    let foot = csv.column("1_contact_disp");

    let omega = 2.0 * PI * V / LAMBDA;
    let ratio = ((K * K + (C * omega).powi(2))
        / ((K - M * omega * omega).powi(2) + (C * omega).powi(2)))
    .sqrt();
    let z_amp = ratio * A;
    // The steady window: the last 5 s (from 7 s, after ζ·ω_n·t = 14).
    let window = |x: &[f64]| -> f64 {
        t.iter()
            .zip(x)
            .filter(|(ti, _)| **ti >= 7.0)
            .map(|(_, v)| v.abs())
            .fold(0.0, f64::max)
    };
    // The foot follows the profile itself: its amplitude is A.
    let foot_amp = window(&foot);
    assert!(
        (foot_amp - A).abs() < 1e-4 * A,
        "foot amplitude {foot_amp} m, profile {A} m"
    );
    let got = window(&z);
    assert!(
        (got - z_amp).abs() < 1e-3 * z_amp,
        "mass amplitude {got} m, closed form {z_amp} m (|Z|/A = {ratio})"
    );
    let got_acc = window(&acc);
    let acc_amp = omega * omega * z_amp;
    assert!(
        (got_acc - acc_amp).abs() < 1e-3 * acc_amp,
        "mass acceleration amplitude {got_acc} m/s², closed form {acc_amp} m/s²"
    );
}

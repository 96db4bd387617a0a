//! A train's motion along the track: a speed table (braking from 20 to 5 m/s and holding),
//! and a constant deceleration that stops the train and holds it at rest instead of
//! running it backwards. Each wheel reports its station; the stations must be the exact
//! integrals of the prescribed speed (the carrier integrates the table exactly), and a
//! table that runs backwards is refused in one line.

mod common;
use common::{railfem, refused_with, temp_dir, Csv};

/// A one-carriage sks700 train on rigid straight track with the given motion keys; returns
/// the model path.
fn model(dir: &std::path::Path, name: &str, motion: &str, duration: f64) -> std::path::PathBuf {
    let text = format!(
        r#"
[analysis]
kind = "transient"
dt = 0.01
duration = {duration}
gravity = [0.0, 0.0, -9.81]

[track]
segments = [{{type = "straight", length = 120.0}}]
support = {{type = "rigid"}}

[[vehicle]]
preset = "sks700"
start = 30.0
{motion}
record = {{wheels = "wheels.csv"}}
"#
    );
    let path = dir.join(format!("{name}.toml"));
    std::fs::write(&path, text).unwrap();
    path
}

/// Stations of the front left wheel and the times, from `wheels.csv`.
fn front_wheel(out: &std::path::Path) -> (Vec<f64>, Vec<f64>) {
    let w = Csv::read(&out.join("wheels.csv"));
    let col = w
        .header
        .iter()
        .find(|h| common::strip_unit(h).ends_with("_station"))
        .expect("a station column")
        .clone();
    (w.column("time"), w.column(&col))
}

/// Speed table [[0, 20], [2, 5], [3, 5]]: v falls linearly by 7.5 m/s² for 2 s, then
/// holds 5 m/s. Distance: ∫v = 20t − 3.75t² for t ≤ 2 (25 m at t = 2), then
/// 25 + 5(t − 2). The wheel keeps its offset from the carrier station, so its station
/// minus its station at t = 0 is that distance; 1e-9 m covers the 13 significant digits
/// of the recorder.
#[test]
fn a_speed_table_moves_the_train_by_its_exact_integral() {
    let dir = temp_dir("vehicle_speed_table");
    let m = model(
        &dir,
        "table",
        "speed_table = [[0.0, 20.0], [2.0, 5.0], [3.0, 5.0]]",
        3.0,
    );
    let out = dir.join("out");
    let o = railfem(&["run", m.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let (t, s) = front_wheel(&out);
    let exact = |t: f64| {
        if t <= 2.0 {
            20.0 * t - 3.75 * t * t
        } else {
            25.0 + 5.0 * (t - 2.0)
        }
    };
    let mut worst = 0.0f64;
    for (ti, si) in t.iter().zip(&s) {
        worst = worst.max((si - s[0] - exact(*ti)).abs());
    }
    assert!(
        worst < 1e-9,
        "station off the table's integral by {worst} m"
    );
    assert!((s[s.len() - 1] - s[0] - 30.0).abs() < 1e-9);
}

/// `speed = 10`, `accel = -5`: the train stops at t = 2 s after 10 m and stays there
/// (before this, s = s0 + v·t + ½·a·t² ran it backwards after the stop).
#[test]
fn a_deceleration_stops_the_train_and_holds_it() {
    let dir = temp_dir("vehicle_braking");
    let m = model(&dir, "brake", "speed = 10.0\naccel = -5.0", 3.0);
    let out = dir.join("out");
    let o = railfem(&["run", m.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let (t, s) = front_wheel(&out);
    for (ti, si) in t.iter().zip(&s) {
        let tc = ti.min(2.0);
        let exact = 10.0 * tc - 2.5 * tc * tc;
        assert!(
            (si - s[0] - exact).abs() < 1e-9,
            "t = {ti}: travelled {} m, expected {exact} m",
            si - s[0]
        );
    }
}

#[test]
fn a_speed_table_that_runs_backwards_is_refused() {
    let dir = temp_dir("vehicle_table_backwards");
    for (name, motion, expect) in [
        (
            "times",
            "speed_table = [[0.0, 20.0], [2.0, 10.0], [1.5, 5.0]]",
            &["speed_table", "increas"][..],
        ),
        (
            "negative",
            "speed_table = [[0.0, 20.0], [2.0, -5.0]]",
            &["speed_table", "backwards"][..],
        ),
        (
            "both",
            "speed = 20.0\nspeed_table = [[0.0, 20.0], [2.0, 5.0]]",
            &["speed_table", "remove `speed`"][..],
        ),
    ] {
        let m = model(&dir, name, motion, 1.0);
        let o = railfem(&["check", m.to_str().unwrap()]);
        refused_with(name, &o, expect);
    }
}

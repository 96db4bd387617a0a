//! Nonlinear suspensions (force tables, bump stops) and the ride-comfort recorder through
//! `railfem run`, against closed forms derived here: the static deflection of bilinear
//! springs, a mass dropping onto a bump stop (peak force and contact time from energy and
//! the harmonic motion in the stop), and Sperling's index of a mass driven by sine forces.

mod common;

use common::{check_bad_model, railfem, temp_dir, Csv};
use std::f64::consts::PI;
use std::path::{Path, PathBuf};

/// Writes `text` as a model file, runs it and asserts a clean exit; returns the output dir.
fn run_text(name: &str, text: &str) -> PathBuf {
    let dir = temp_dir(name);
    let path = dir.join(format!("{name}.toml"));
    std::fs::write(&path, text).expect("write model");
    let out = dir.join("out");
    let o = railfem(&[
        "run",
        path.to_str().expect("utf-8"),
        "--out",
        out.to_str().expect("utf-8"),
    ]);
    assert!(
        o.status.success(),
        "{name}: exit {:?}, stderr: {}",
        o.status.code(),
        String::from_utf8_lossy(&o.stderr)
    );
    out
}

/// Static equilibrium on piecewise-linear springs. A grounded `spring_damper` with the
/// table (0, 0), (0.01 m, 100 kN), (0.02 m, 500 kN) pulled by 300 kN sits in the second
/// segment (slope 40 MN/m): d = 0.01 + 200e3/40e6 = 0.015 m; a second one pushed by
/// −200 kN extrapolates the first segment (10 MN/m): d = −0.02 m. A `suspension` with a
/// table on axis 3 and a compression bump stop (gap 12 mm, 10 MN/m) under −200 kN: in
/// the segment (−0.02, −3e5)–(−0.01, −1e5) (slope 20 MN/m) with the stop engaged,
/// −1e5 + 2e7·(d + 0.01) + 1e7·(d + 0.012) = −2e5 gives d = −0.014 m. Piecewise linear
/// laws are solved exactly once Newton is in the right segment: 1e-9 relative.
#[test]
fn static_deflection_on_bilinear_springs() {
    let text = r#"
[analysis]
kind = "static"
steps = 4

[[node]]
id = 1
xyz = [0.0, 0.0, 0.0]
fix = ["ux", "uy", "rx", "ry", "rz"]

[[node]]
id = 2
xyz = [5.0, 0.0, 0.0]
fix = ["ux", "uy", "rx", "ry", "rz"]

[[node]]
id = 3
xyz = [10.0, 0.0, 0.0]
fix = ["all"]

[[node]]
id = 4
xyz = [10.0, 0.0, 1.0]
fix = ["ux", "uy", "rx", "ry", "rz"]

[[element]]
type = "spring_damper"
id = 1
nodes = [1]
k = [0.0, 0.0, 1.0, 0.0, 0.0, 0.0]
force_table = { uz = [[0.0, 0.0], [0.01, 1.0e5], [0.02, 5.0e5]] }

[[element]]
type = "spring_damper"
id = 2
nodes = [2]
k = [0.0, 0.0, 1.0, 0.0, 0.0, 0.0]
force_table = { uz = [[0.0, 0.0], [0.01, 1.0e5], [0.02, 5.0e5]] }

[[element]]
type = "suspension"
id = 3
nodes = [3, 4]
k = [1.0e6, 1.0e6, 1.0]
force_table = { 3 = [[-0.02, -3.0e5], [-0.01, -1.0e5], [0.0, 0.0], [0.01, 1.0e5]] }
bump_stop = { 3 = { gap = [0.012, 1.0], k = 1.0e7 } }

[[load]]
type = "nodal"
node = 1
dof = "uz"
value = 3.0e5
series = { type = "constant" }

[[load]]
type = "nodal"
node = 2
dof = "uz"
value = -2.0e5
series = { type = "constant" }

[[load]]
type = "nodal"
node = 4
dof = "uz"
value = -2.0e5
series = { type = "constant" }

[[recorder]]
type = "node"
nodes = [1, 2, 4]
dofs = ["uz"]
file = "d.csv"

[[recorder]]
type = "element"
elements = [1, 2]
outputs = ["fz"]
file = "f.csv"

[[recorder]]
type = "element"
element = 3
file = "s.csv"
"#;
    let out = run_text("bilinear_static", text);
    let d = Csv::read(&out.join("d.csv"));
    let f = Csv::read(&out.join("f.csv"));
    let s = Csv::read(&out.join("s.csv"));
    for (col, want) in [("1_uz", 0.015), ("2_uz", -0.02), ("4_uz", -0.014)] {
        let got = d.column(col)[0];
        assert!(
            (got - want).abs() <= 1e-9 * want.abs(),
            "{col}: {got} vs {want}"
        );
    }
    // The force outputs include the table (and stop) force: they balance the loads.
    for (col, want) in [("1_fz", 3e5), ("2_fz", -2e5)] {
        let got = f.column(col)[0];
        assert!(
            (got - want).abs() <= 1e-9 * want.abs(),
            "{col}: {got} vs {want}"
        );
    }
    let (d3, f3) = (s.column("3_d3")[0], s.column("3_f3")[0]);
    assert!(
        (d3 + 0.014).abs() <= 1e-9 * 0.014 && (f3 + 2e5).abs() <= 1e-9 * 2e5,
        "{d3} {f3}"
    );
}

/// A 1000 kg mass released at rest 50 mm above a bump stop (k = 1 MN/m, no other
/// spring), under gravity g = 9.81 m/s². Energy: m·g·(δ + x) = ½·k·x² gives the largest
/// penetration x = (mg/k)·(1 + √(1 + 2kδ/(mg))) and the peak force k·x = 42.63 kN. The
/// fall lasts t_f = √(2δ/g); in the stop the mass oscillates about the static point
/// (mg/k below contact) with ω = √(k/m), entering at y₀ = mg/k above it with speed
/// v₀ = g·t_f, so it leaves after t_c = (π + 2·atan(y₀·ω/v₀))/ω; then it rises back to
/// its release height (no dissipation). Newmark's trapezoidal rule conserves the energy
/// of each linear phase exactly; the error is the contact instant falling between steps,
/// an energy of order k·(v₀·dt)²/2 = 5e-3 J against m·g·δ = 490 J (1e-5 relative), so
/// 1e-4 is asserted on the peak force (which also sees the sampling of its peak,
/// 1 − cos(ω·dt/2) ≈ 1e-6); contact start and end within two steps; the rebound height
/// within 1e-5 m of the release point (1e-5 of the energy over m·g is 5e-7 m).
#[test]
fn mass_dropping_on_a_bump_stop() {
    let (m, k, gap, g, dt): (f64, f64, f64, f64, f64) = (1000.0, 1.0e6, 0.05, 9.81, 1e-4);
    let text = format!(
        r#"
[analysis]
kind = "transient"
integrator = "newmark"
beta = 0.25
gamma = 0.5
dt = {dt}
duration = 0.45
initial_static = false
gravity = [0.0, 0.0, -{g}]

[[node]]
id = 1
xyz = [0.0, 0.0, 0.0]
fix = ["ux", "uy", "rx", "ry", "rz"]

[[element]]
type = "mass"
id = 1
nodes = [1]
m = {m}

[[element]]
type = "spring_damper"
id = 2
nodes = [1]
k = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0]
bump_stop = {{ uz = {{ gap = [{gap}, 1.0], k = {k} }} }}

[[recorder]]
type = "node"
node = 1
dofs = ["uz"]
file = "u.csv"

[[recorder]]
type = "element"
element = 2
outputs = ["fz"]
file = "f.csv"
"#
    );
    let out = run_text("bump_drop", &text);
    let u = Csv::read(&out.join("u.csv"));
    let f = Csv::read(&out.join("f.csv"));
    let t = u.column("time");
    let uz = u.column("1_uz");
    let fz = f.column("2_fz");
    let w = m * g;
    let x = w / k * (1.0 + (1.0 + 2.0 * k * gap / w).sqrt());
    let peak = fz.iter().fold(0.0f64, |a, &b| a.max(-b));
    assert!(
        (peak - k * x).abs() <= 1e-4 * k * x,
        "peak {peak} vs {}",
        k * x
    );
    let t_f = (2.0 * gap / g).sqrt();
    let omega = (k / m).sqrt();
    let t_c = (PI + 2.0 * (w / k * omega / (g * t_f)).atan()) / omega;
    // The stop releases: the last step with force, after the first contact.
    let first = fz.iter().position(|&v| v < 0.0).expect("contact");
    let last = first + fz[first..].iter().position(|&v| v == 0.0).expect("release") - 1;
    assert!(
        (t[first] - t_f).abs() <= 2.0 * dt && (t[last] - (t_f + t_c)).abs() <= 2.0 * dt,
        "contact {} – {} s vs {t_f} – {} s",
        t[first],
        t[last],
        t_f + t_c
    );
    let rebound = uz[last..].iter().fold(f64::MIN, |a, &b| a.max(b));
    assert!(
        rebound.abs() <= 1e-5,
        "rebound to {rebound} m, released at 0"
    );
}

/// Sperling's index through the `comfort` recorder. A free 1000 kg mass driven by
/// 500·sin(2π·2.5·t) N vertically and 300·sin(2π·1.25·t) N laterally accelerates exactly
/// as F/m (Newmark enforces equilibrium at each step and there is no stiffness), so its
/// records are pure sines of 0.5 and 0.3 m/s² with 20 and 10 periods in 8 s; sampled at
/// 2⁹ steps per second (2¹² intervals, no resampling error), the index is Sperling's
/// single-harmonic value 0.896·(a³·F(f)/f)^(1/10), a in cm/s², with the vertical
/// F(2.5) = 0.325·2.5² and the lateral F(1.25) = 0.8·1.25². 1e-6 relative.
#[test]
fn comfort_recorder_gives_sperling_for_a_sine() {
    let text = r#"
[analysis]
kind = "transient"
integrator = "newmark"
beta = 0.25
gamma = 0.5
dt = 0.001953125
duration = 8.0
initial_static = false

[[node]]
id = 7
xyz = [0.0, 0.0, 0.0]
fix = ["ux", "rx", "ry", "rz"]

[[element]]
type = "mass"
id = 1
nodes = [7]
m = 1000.0

[[load]]
type = "nodal"
node = 7
dof = "uz"
value = 500.0
series = { type = "sine", frequency = 2.5 }

[[load]]
type = "nodal"
node = 7
dof = "uy"
value = 300.0
series = { type = "sine", frequency = 1.25 }

[[recorder]]
type = "comfort"
node = 7
vertical = ["uz"]
lateral = ["uy"]
file = "comfort/wz.csv"
"#;
    let out = run_text("comfort_sine", text);
    let text = std::fs::read_to_string(out.join("comfort/wz.csv")).expect("comfort file");
    let mut lines = text.lines();
    assert_eq!(
        lines.next(),
        Some("node [-],dof [-],weighting [-],wz [-],duration [s],samples [-]")
    );
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len(), 2);
    let closed = |a: f64, f: f64, ff: f64| 0.896 * ((100.0 * a).powi(3) * ff / f).powf(0.1);
    for (row, (dof, weighting, want)) in rows.iter().zip([
        ("uz", "vertical", closed(0.5, 2.5, 0.325 * 6.25)),
        ("uy", "lateral", closed(0.3, 1.25, 0.8 * 1.5625)),
    ]) {
        assert_eq!((row[0], row[1], row[2]), ("7", dof, weighting));
        let wz: f64 = row[3].parse().unwrap();
        assert!((wz - want).abs() <= 1e-6 * want, "{dof}: {wz} vs {want}");
        assert_eq!(row[5], "4097");
    }
}

/// |H(i·2πf)| of an ISO 8041 weighting from its parameters (written here from the
/// standard's product of band limiting, transition and step, independently of the
/// library): `(f1, f2, f3, f4, q4, step, k)`.
type IsoParams = (f64, f64, f64, f64, f64, Option<(f64, f64, f64, f64)>, f64);

fn iso_weighting(f: f64, p: IsoParams) -> f64 {
    let (f1, f2, f3, f4, q4, step, k) = p;
    let w = 2.0 * PI * f;
    // |a + i·b| of a second-order factor s² + ω·s/Q + ω² at s = iw: (ω² − w²) + i·w·ω/Q.
    let quad = |wc: f64, q: f64| ((wc * wc - w * w).powi(2) + (w * wc / q).powi(2)).sqrt();
    let (w1, w2, w3, w4) = (2.0 * PI * f1, 2.0 * PI * f2, 2.0 * PI * f3, 2.0 * PI * f4);
    let q = std::f64::consts::FRAC_1_SQRT_2;
    let high = w * w / quad(w1, q);
    let low = w2 * w2 / quad(w2, q);
    let transition = (1.0 + (w / w3).powi(2)).sqrt() * w4 * w4 / quad(w4, q4);
    let up = match step {
        Some((f5, q5, f6, q6)) => quad(2.0 * PI * f5, q5) / quad(2.0 * PI * f6, q6),
        None => 1.0,
    };
    k * high * low * transition * up
}

/// EN 12299's simplified N_MV through the `comfort` recorder. A free 1000 kg mass driven
/// by sines (ux 200 N at 2.4 Hz, uy 300 N at 0.8 Hz, uz 500 N at 4.8 Hz; whole periods
/// in every 5-s window) for 20 s accelerates exactly as F/m; each weighted 5-s rms is
/// `a·|W(f)|/√2` (W_d for X and Y, W_b for Z, evaluated here from the ISO 8041
/// parameters), so is the 95th percentile, and N_MV = 6·√(Σ a_P95²). The weighting is
/// applied in the frequency domain on the periodic record, exact for these bin
/// frequencies: 1e-6.
#[test]
fn comfort_recorder_gives_n_mv_for_sines() {
    let text = r#"
[analysis]
kind = "transient"
integrator = "newmark"
beta = 0.25
gamma = 0.5
dt = 0.00244140625
duration = 20.0
initial_static = false

[[node]]
id = 3
xyz = [0.0, 0.0, 0.0]
fix = ["rx", "ry", "rz"]

[[element]]
type = "mass"
id = 1
nodes = [3]
m = 1000.0

[[load]]
type = "nodal"
node = 3
dof = "ux"
value = 200.0
series = { type = "sine", frequency = 2.4 }

[[load]]
type = "nodal"
node = 3
dof = "uy"
value = 300.0
series = { type = "sine", frequency = 0.8 }

[[load]]
type = "nodal"
node = 3
dof = "uz"
value = 500.0
series = { type = "sine", frequency = 4.8 }

[[recorder]]
type = "comfort"
node = 3
method = "en12299"
longitudinal = ["ux"]
lateral = ["uy"]
vertical = ["uz"]
file = "nmv.csv"
"#;
    let out = run_text("comfort_en12299", text);
    let text = std::fs::read_to_string(out.join("nmv.csv")).expect("comfort file");
    let mut lines = text.lines();
    assert_eq!(
        lines.next(),
        Some(
            "node [-],n_mv [-],ax_p95 [m/s²],ay_p95 [m/s²],az_p95 [m/s²],windows [-],duration [s]"
        )
    );
    let row: Vec<f64> = lines
        .next()
        .unwrap()
        .split(',')
        .map(|v| v.parse().unwrap())
        .collect();
    let wd = (0.4, 100.0, 2.0, 2.0, 0.63, None, 1.0);
    let wb = (
        0.4,
        100.0,
        16.0,
        16.0,
        0.55,
        Some((2.5, 0.9, 4.0, 0.95)),
        1.024,
    );
    let r2 = std::f64::consts::SQRT_2;
    let want = [
        0.2 * iso_weighting(2.4, wd) / r2,
        0.3 * iso_weighting(0.8, wd) / r2,
        0.5 * iso_weighting(4.8, wb) / r2,
    ];
    assert_eq!(row[0], 3.0);
    for i in 0..3 {
        assert!(
            (row[2 + i] - want[i]).abs() <= 1e-6 * want[i],
            "{i}: {} vs {}",
            row[2 + i],
            want[i]
        );
    }
    let nmv = 6.0 * (want[0].powi(2) + want[1].powi(2) + want[2].powi(2)).sqrt();
    assert!((row[1] - nmv).abs() <= 1e-6 * nmv, "{} vs {nmv}", row[1]);
    assert_eq!(row[5], 4.0);
}

/// The example model runs, and its comfort file agrees with Sperling's index computed
/// here, independently, from the recorded accelerations: linear resampling onto 2¹⁴
/// points and a direct Fourier sum over the bins of 0.5–30 Hz.
#[test]
fn comfort_example_agrees_with_a_direct_fourier_sum() {
    let model =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/models/comfort_oscillator.toml");
    let out = temp_dir("comfort_example");
    let o = railfem(&[
        "run",
        model.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let acc = Csv::read(&out.join("body_acc.csv"));
    let t = acc.column("time");
    let text = std::fs::read_to_string(out.join("comfort.csv")).unwrap();
    for (line, (col, low, knee, high, flat)) in text.lines().skip(1).zip([
        ("1_uz", 0.325, 5.9, 400.0, 20.0),
        ("1_uy", 0.8, 5.4, 650.0, 26.0),
    ]) {
        let a = acc.column(col);
        let n = (t.len() - 1).next_power_of_two();
        let period = t[t.len() - 1] - t[0];
        let h = period / n as f64;
        let x: Vec<f64> = (0..n)
            .map(|j| {
                let tj = t[0] + j as f64 * h;
                let k = t.partition_point(|&s| s <= tj).clamp(1, t.len() - 1) - 1;
                a[k] + (tj - t[k]) / (t[k + 1] - t[k]) * (a[k + 1] - a[k])
            })
            .collect();
        let mean = x.iter().sum::<f64>() / n as f64;
        let mut sum = 0.0;
        let bins = (0.5 * period).ceil() as usize..=(30.0 * period).floor() as usize;
        for i in bins {
            let f = i as f64 / period;
            let (mut re, mut im) = (0.0, 0.0);
            for (j, v) in x.iter().enumerate() {
                let ang = 2.0 * PI * ((i * j) % n) as f64 / n as f64;
                re += (v - mean) * ang.cos();
                im -= (v - mean) * ang.sin();
            }
            let amp = 100.0 * 2.0 * re.hypot(im) / n as f64;
            let weight = if f < knee {
                low * f * f
            } else if f < flat {
                high / (f * f)
            } else {
                1.0
            };
            sum += amp.powi(3) * weight / f;
        }
        let want = 0.896 * sum.powf(0.1);
        let got: f64 = line.split(',').nth(3).unwrap().parse().unwrap();
        assert!((got - want).abs() <= 1e-5 * want, "{col}: {got} vs {want}");
    }
}

#[test]
fn bad_tables_stops_and_comfort_keys_are_refused_in_one_line() {
    let base = |extra: &str, analysis: &str, recorder: &str| {
        format!(
            r#"
[analysis]
{analysis}

[[node]]
id = 1
xyz = [0.0, 0.0, 0.0]
fix = ["ux", "rx", "ry", "rz"]

[[element]]
type = "mass"
id = 1
nodes = [1]
m = 1000.0

[[element]]
type = "spring_damper"
id = 2
nodes = [1]
k = [0.0, 1.0e5, 1.0e6, 0.0, 0.0, 0.0]
{extra}

{recorder}
"#
        )
    };
    let tr = "kind = \"transient\"\ndt = 0.005\nduration = 1.0";
    let rec = "[[recorder]]\ntype = \"node\"\nnode = 1\ndofs = [\"uz\"]\nfile = \"u.csv\"";
    for (name, extra, analysis, recorder, expect) in [
        (
            "unsorted.toml",
            "force_table = { uz = [[0.0, 0.0], [0.02, 1.0], [0.01, 2.0]] }",
            tr,
            rec,
            vec!["element[1]", "`force_table.uz`[2]", "sort the points"],
        ),
        (
            "neg_gap.toml",
            "bump_stop = { uz = { gap = -0.01, k = 1.0e7 } }",
            tr,
            rec,
            vec!["element[1]", "`bump_stop.uz` gap (compression)", "≥ 0"],
        ),
        (
            "direction.toml",
            "bump_stop = { vertical = { gap = 0.01, k = 1.0e7 } }",
            tr,
            rec,
            vec!["`vertical` is not a direction", "ux, uy, uz, rx, ry, rz"],
        ),
        (
            "method.toml",
            "",
            tr,
            "[[recorder]]\ntype = \"comfort\"\nnode = 1\nvertical = [\"uz\"]\nmethod = \"iso2631\"\nfile = \"c.csv\"",
            vec![
                "`recorder[0].method`",
                "unknown variant `iso2631`",
                "expected `sperling` or `en12299`",
            ],
        ),
        (
            "two_dofs.toml",
            "",
            "kind = \"transient\"\ndt = 0.005\nduration = 10.0",
            "[[recorder]]\ntype = \"comfort\"\nnode = 1\nmethod = \"en12299\"\nvertical = [\"uz\", \"uy\"]\nfile = \"c.csv\"",
            vec!["recorder[0]", "`vertical` names 2 DOFs", "one DOF per direction"],
        ),
        (
            "longitudinal.toml",
            "",
            tr,
            "[[recorder]]\ntype = \"comfort\"\nnode = 1\nvertical = [\"uz\"]\nlongitudinal = [\"ux\"]\nfile = \"c.csv\"",
            vec!["recorder[0]", "`longitudinal`", "en12299"],
        ),
        (
            "short.toml",
            "",
            tr,
            "[[recorder]]\ntype = \"comfort\"\nnode = 1\nmethod = \"en12299\"\nvertical = [\"uz\"]\nfile = \"c.csv\"",
            vec!["recorder[0]", "`duration` = 1 s", "5 s window"],
        ),
        (
            "rot.toml",
            "",
            tr,
            "[[recorder]]\ntype = \"comfort\"\nnode = 1\nlateral = [\"rx\"]\nfile = \"c.csv\"",
            vec!["recorder[0]", "`lateral` names `rx`", "ux, uy or uz"],
        ),
        (
            "static.toml",
            "",
            "kind = \"static\"",
            "[[recorder]]\ntype = \"comfort\"\nnode = 1\nvertical = [\"uz\"]\nfile = \"c.csv\"",
            vec!["recorder[0]", "transient"],
        ),
        (
            "coarse.toml",
            "",
            "kind = \"transient\"\ndt = 0.01\nrecord_every = 2\nduration = 1.0",
            "[[recorder]]\ntype = \"comfort\"\nnode = 1\nvertical = [\"uz\"]\nfile = \"c.csv\"",
            vec!["recorder[0]", "every 0.02 s", "record at least every"],
        ),
        (
            "nodir.toml",
            "",
            tr,
            "[[recorder]]\ntype = \"comfort\"\nnode = 1\nfile = \"c.csv\"",
            vec!["recorder[0]", "vertical = [\"uz\"]"],
        ),
    ] {
        check_bad_model(name, &base(extra, analysis, recorder), &expect);
    }
}

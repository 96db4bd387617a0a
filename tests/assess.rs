//! `railfem assess` (docs/assessment.md): every quantity against an analytic signal whose
//! sliding mean and percentiles are known in closed form, and the wear number summed over
//! a run against the friction work of the energy ledger.

use railfem::assess::limits::{nadal, prudhomme, AssessLimits};
use railfem::assess::read::Wheel;
use railfem::assess::{assess, Section};
use std::f64::consts::PI;

const V: f64 = 20.0; // m/s
const FS: f64 = 500.0; // Hz
const LAMBDA: f64 = 10.0; // m: 2 Hz at V
const Q0: f64 = 60e3;

fn wheel(name: &str, q: impl Fn(f64) -> f64, y: impl Fn(f64) -> f64) -> Wheel {
    let n = (200.0 / V * FS) as usize; // 200 m, 20 whole wavelengths
    let t: Vec<f64> = (0..=n).map(|i| i as f64 / FS).collect();
    let s: Vec<f64> = t.iter().map(|t| V * t).collect();
    Wheel {
        name: name.into(),
        q: s.iter().map(|&s| q(s)).collect(),
        y: s.iter().map(|&s| y(s)).collect(),
        t,
        s,
        t_gamma: None,
        first: None,
    }
}

fn value(a: &railfem::assess::Assessment, q: &str, item: &str) -> (f64, f64) {
    let r = a
        .summary
        .iter()
        .find(|r| r.quantity == q && r.item == item)
        .unwrap_or_else(|| panic!("no {q} of {item}"));
    (r.value, r.limit)
}

/// Wheelset 1: constant Q0, Y = c + A·sin(2πs/λ) (c = 12 kN left, 5 kN right,
/// A = 8 kN). Wheelset 2: Y = 0, Q = Q0 ∓ B·sin (B = 15 kN). Through the 20 Hz filter a
/// 2 Hz sine keeps the gain `g = 1/(1 + (tan(πf/fs)/tan(πfc/fs))⁴)` (signals.rs); a 2 m
/// sliding mean of a sine keeps `S = sin(πL/λ)/(πL/λ)` of its amplitude; the p-th
/// percentile of a sampled sine over whole periods is `−cos(πp)` of its amplitude, its
/// median the mean. Every quantity within 1e-3 of its amplitude (sampling of the peaks).
#[test]
fn quantities_against_analytic_signals() {
    let (c_l, c_r, amp, b) = (12e3, 5e3, 8e3, 15e3);
    let k = 2.0 * PI / LAMBDA;
    let wheels = vec![
        wheel("1L", |_| Q0, |s| c_l + amp * (k * s).sin()),
        wheel("1R", |_| Q0, |s| c_r + amp * (k * s).sin()),
        wheel("2L", |s| Q0 - b * (k * s).sin(), |_| 0.0),
        wheel("2R", |s| Q0 + b * (k * s).sin(), |_| 0.0),
    ];
    let lim = AssessLimits::default();
    let section = Section {
        from: Some(50.0),
        to: Some(150.0),
    };
    let a = assess(&wheels, &lim, section, None);
    let f = V / LAMBDA;
    let g = 1.0 / (1.0 + ((PI * f / FS).tan() / (PI * lim.cutoff / FS).tan()).powi(4));
    let x = PI * lim.window / LAMBDA;
    let sinc = x.sin() / x;
    let tol = 1e-3;
    // Y/Q on the 2 m sliding mean, against Nadal's closed form.
    let (v, l) = value(&a, "Y/Q 2 m", "1L");
    assert!(
        ((v - (c_l + amp * g * sinc) / Q0) * Q0).abs() < tol * amp,
        "{v}"
    );
    assert_eq!(l, nadal(70f64.to_radians(), 0.36));
    // ΣY on 2 m against Prud'homme with Q0 the wheelset's mean wheel load.
    let (v, l) = value(&a, "SumY 2 m", "1L+1R");
    assert!(
        (v - (c_l + c_r + 2.0 * amp * g * sinc)).abs() < tol * amp,
        "{v}"
    );
    assert!((l / prudhomme(1.0, Q0) - 1.0).abs() < 1e-9, "{l}");
    // Quasi-static Y over the section: the median, c.
    let (v, l) = value(&a, "Yqst", "1L");
    assert!((v - c_l).abs() < tol * amp, "{v}");
    assert_eq!(l, 60e3);
    let (v, _) = value(&a, "Ymax", "1R");
    assert!((v - (c_r + amp * g)).abs() < tol * amp, "{v}");
    // Wheel unloading, Qmax and its 99.85 % value, quasi-static Q.
    let (v, l) = value(&a, "dQ/Q0", "2L");
    assert!(((v - b * g / Q0) * Q0).abs() < tol * b, "{v}");
    assert_eq!(l, 0.6);
    let (v, l) = value(&a, "Qmax", "2R");
    assert!((v - (Q0 + b * g)).abs() < tol * b, "{v}");
    assert!((l - (90e3 + Q0)).abs() < 1e-6 * Q0);
    let (v, _) = value(&a, "Q 99.85%", "2R");
    let p = lim.max_percentile / 100.0;
    assert!((v - (Q0 - b * g * (PI * p).cos())).abs() < tol * b, "{v}");
    let (v, _) = value(&a, "Qqst", "2R");
    assert!((v - Q0).abs() < tol * b, "{v}");
    // Margins: positive inside the limit.
    let r = a.summary.iter().find(|r| r.quantity == "Y/Q 2 m").unwrap();
    assert!((r.margin() - (r.limit - r.value) / r.limit).abs() < 1e-15 && r.margin() > 0.0);
}

/// The wear number summed over a run, `Σ Tγ·Δs`, against the friction work of the energy
/// ledger (`energy.csv`, column `friction`): the same energy counted two ways — the
/// element dissipates `Tγ·ds` at each committed step, the ledger sums the elements'
/// dissipation. A free S1002 wheelset with FASTSIM released 2 mm off-centre on a rigid
/// straight track (the Klingel case of tests/rolling_contact.rs), 8 m at 20 m/s,
/// recorded every step: within 1 % (both count from the end of the first step).
#[test]
fn wear_number_sums_to_the_ledgers_friction_work() {
    use railfem::rolling_contact::{write_model, Case, Wheel as Profile};
    let dir = std::env::temp_dir().join(format!("railfem_assess_ledger_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let mut case = Case::klingel(Profile::S1002, 20.0, 8.0);
    case.tangential = railfem::elements::rail::contact::creep::law::Tangential::Fastsim;
    let model = write_model(&case, &dir).unwrap();
    let mut text = std::fs::read_to_string(&model).unwrap();
    text.push_str(
        "\n[[recorder]]\ntype = \"element\"\nkind = \"moving_axle\"\noutputs = [\"station\", \"Q\", \"Y\", \"t_gamma\", \"c1_fx\", \"c1_fy\", \"c1_a\", \"c1_b\", \"p1_fn\"]\nfile = \"wheels.csv\"\n",
    );
    std::fs::write(&model, text).unwrap();
    let out = dir.join("out");
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_railfem"))
        .arg("run")
        .arg(&model)
        .arg("--out")
        .arg(&out)
        .arg("--assess")
        .output()
        .expect("runs");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let wheels = railfem::assess::read::wheels(&out, None).unwrap();
    assert_eq!(wheels.len(), 2);
    let a = assess(&wheels, &AssessLimits::default(), Section::default(), None);
    let energy = std::fs::read_to_string(out.join("energy.csv")).unwrap();
    let head: Vec<&str> = energy.lines().next().unwrap().split(',').collect();
    let col = head.iter().position(|h| *h == "friction [J]").unwrap();
    let last = energy.lines().last().unwrap().split(',').nth(col).unwrap();
    let ledger: f64 = last.parse().unwrap();
    // The ledger's energies are relative to the state after its first step (the first
    // row of energy.csv, solvers/src/energy.rs): leave that step's work out of the sum too.
    let first_step: f64 = wheels
        .iter()
        .map(|w| w.t_gamma.as_ref().unwrap()[1] * (w.s[1] - w.s[0]))
        .sum();
    let sum = a.wear_work - first_step;
    eprintln!(
        "Σ Tγ·Δs = {:.6e} J (first step {first_step:.3e} J), ledger friction {ledger:.6e} J",
        a.wear_work
    );
    assert!(ledger > 0.1, "too little creep work to compare: {ledger} J");
    assert!((sum / ledger - 1.0).abs() < 0.01, "{sum} vs {ledger}");
    // --assess wrote the outputs, with units in every header.
    let summary = std::fs::read_to_string(out.join("assessment-summary.csv")).unwrap();
    assert!(summary.contains("FI_surf") && summary.contains("Tgamma"));
    let series = std::fs::read_to_string(out.join("assessment.csv")).unwrap();
    let h = series.lines().next().unwrap();
    assert!(h.split(',').all(|c| c.ends_with(']')), "{h}");
    assert!(out.join("assessment.png").exists());
    let _ = std::fs::remove_dir_all(&dir);
}

/// Bad options: one line, exit 2, naming the option and the fix.
#[test]
fn refuses_bad_options() {
    let dir = std::env::temp_dir().join(format!("railfem_assess_bad_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for (args, expect) in [
        (vec!["--window", "0"], "--window 0: give a value > 0"),
        (vec!["--max-percentile", "101"], "from 0 to 100"),
        (vec!["--flange-angle", "95"], "0 < γ < 90"),
        (
            vec!["--from", "10", "--to", "5"],
            "must end after it starts",
        ),
        (vec![], "no wheel forces found"),
    ] {
        let o = std::process::Command::new(env!("CARGO_BIN_EXE_railfem"))
            .arg("assess")
            .arg(&dir)
            .args(&args)
            .output()
            .expect("runs");
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
        assert_eq!(err.trim_end().lines().count(), 1, "{args:?}: {err}");
        assert!(err.contains(expect), "{args:?}: {err}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

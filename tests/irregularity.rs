//! Track irregularities (docs/irregularities.md): generated profiles against their target
//! spectra, reproducibility, the CSV round trip through `railfem irregularity`, a
//! measured-style CSV through `railfem run`, and the bad inputs.

mod common;

use common::{railfem, refused_with, temp_dir, Csv};
use railfem::elements::rail::geometry::irregularity::csv::read_table;
use railfem::elements::rail::geometry::irregularity::generate::{welch, PsdRequest};
use railfem::elements::rail::geometry::irregularity::psd::{band_variance, Component, PsdClass};
use std::f64::consts::PI;

/// 16384 samples at 0.25 m: the record is exactly one FFT (4096 m).
fn request(class: PsdClass, seed: u64) -> PsdRequest {
    PsdRequest {
        class,
        seed,
        wavelengths: [1.0, 25.0],
        step: 0.25,
        length: 16383.0 * 0.25,
    }
}

/// Averaged over 64 seeds, the Welch PSD (Hann, 2048-sample = 512 m segments, 50 %
/// overlap) is within ±10 % of the target across the band, for a steep spectrum (FRA 4
/// vertical, ~Ω⁻⁴ above Ω_c) and a band-pass one (German high, gauge).
///
/// Count: each seed gives 15 segments, so K = 960 periodograms. For a Gaussian profile a
/// Hann/50 % Welch bin has relative standard deviation √((1 + 2·0.167²)/K) = 0.033 (0.167
/// is the Hann window's overlap correlation); a random-phase sum of cosines with fixed
/// amplitudes varies less. The comparison is on groups of 8 adjacent bins (estimate and
/// target averaged over the same bins), which at least halves it (neighbouring Hann bins
/// correlate, so not by √8): σ ≤ 0.017, and 10 % is ≥ 6σ over the ~55 groups.
/// Bias: the Hann spectral window has an RMS width of 0.58 bins (σ_f² = 1/(3T²)); on
/// S ∝ Ω⁻⁴ at the lowest compared Ω (0.33 rad/m, S''/S = 20/Ω²) the smoothing bias is
/// ½·(S''/S)·σ_Ω² < 0.5 %. Edges: bins within 6 bins (0.074 rad/m) of a band edge are left
/// out — there the window smears the step of the band-limited spectrum.
#[test]
fn averaged_welch_psd_matches_target() {
    let seg = 2048;
    let seeds = 64u64;
    for (class, comp) in [
        (PsdClass::Fra(4), Component::Vertical),
        (PsdClass::GermanHigh, Component::Gauge),
    ] {
        let mut sum: Vec<f64> = Vec::new();
        let mut omega = Vec::new();
        for seed in 0..seeds {
            let req = request(class, seed);
            let z = req.generate(comp).unwrap();
            let (om, s) = welch(&z, req.step, seg).unwrap();
            if sum.is_empty() {
                sum = vec![0.0; s.len()];
                omega = om;
            }
            for (a, b) in sum.iter_mut().zip(&s) {
                *a += b / seeds as f64;
            }
        }
        let d = omega[1] - omega[0];
        let (lo, hi) = (2.0 * PI / 25.0 + 6.0 * d, 2.0 * PI / 1.0 - 6.0 * d);
        let idx: Vec<usize> = (0..omega.len())
            .filter(|&k| omega[k] >= lo && omega[k] <= hi)
            .collect();
        let mut worst = 0.0f64;
        for g in idx.chunks(8) {
            let est: f64 = g.iter().map(|&k| sum[k]).sum();
            let tgt: f64 = g
                .iter()
                .map(|&k| class.density(comp, omega[k]).unwrap())
                .sum();
            worst = worst.max((est / tgt - 1.0).abs());
        }
        eprintln!(
            "{} {}: worst group {:.2} %",
            class.name(),
            comp.name(),
            worst * 100.0
        );
        assert!(worst < 0.10, "{class:?} {comp:?}: {worst}");
    }
}

/// RMS of the generated profile against √(∫ S dΩ over the band) (Simpson in ln Ω, the
/// integral independent of the generator's sum) within 5 %, for every class and component
/// it offers. Over the full record the sample variance is exactly Σ S(Ω_k)·ΔΩ (the
/// harmonics are orthogonal), so what remains is the Riemann sum's error (ΔΩ =
/// 1.5e-3 rad/m) — the test catches a wrong amplitude (the factor 2 of one-sided
/// densities, cm² vs m², a lost ΔΩ). A second check on a record that is not a whole FFT
/// (1000 m of 1024 m), averaged over 16 seeds, holds to the same 5 %.
#[test]
fn rms_matches_integral_of_target() {
    let classes: Vec<PsdClass> = PsdClass::NAMES
        .iter()
        .map(|n| PsdClass::parse(n).unwrap())
        .collect();
    for class in classes {
        for &comp in class.components() {
            let req = request(class, 7);
            let z = req.generate(comp).unwrap();
            let rms = (z.iter().map(|v| v * v).sum::<f64>() / z.len() as f64).sqrt();
            let target = band_variance(class, comp, 2.0 * PI / 25.0, 2.0 * PI).sqrt();
            assert!(
                (rms / target - 1.0).abs() < 0.05,
                "{} {}: rms {rms} vs {target}",
                class.name(),
                comp.name()
            );
        }
    }
    let mut var = 0.0;
    for seed in 0..16 {
        let req = PsdRequest {
            length: 1000.0,
            ..request(PsdClass::Fra(6), seed)
        };
        let z = req.generate(Component::Alignment).unwrap();
        var += z.iter().map(|v| v * v).sum::<f64>() / z.len() as f64 / 16.0;
    }
    let target = band_variance(
        PsdClass::Fra(6),
        Component::Alignment,
        2.0 * PI / 25.0,
        2.0 * PI,
    );
    assert!(
        (var.sqrt() / target.sqrt() - 1.0).abs() < 0.05,
        "{var} vs {target}"
    );
}

/// Same seed, same bits; another seed, another profile (differing by about its RMS, not
/// by rounding); the components of one seed are independent streams.
#[test]
fn seeds_reproduce_and_differ() {
    let a = request(PsdClass::GermanLow, 42)
        .generate(Component::Vertical)
        .unwrap();
    let b = request(PsdClass::GermanLow, 42)
        .generate(Component::Vertical)
        .unwrap();
    assert!(a.iter().zip(&b).all(|(x, y)| x.to_bits() == y.to_bits()));
    let c = request(PsdClass::GermanLow, 43)
        .generate(Component::Vertical)
        .unwrap();
    let rms = (a.iter().map(|v| v * v).sum::<f64>() / a.len() as f64).sqrt();
    let diff =
        (a.iter().zip(&c).map(|(x, y)| (x - y).powi(2)).sum::<f64>() / a.len() as f64).sqrt();
    assert!(diff > 0.5 * rms, "seeds 42 and 43: {diff} vs rms {rms}");
    // Alignment of seed 42 is not the vertical profile rescaled: correlation near 0.
    let al = request(PsdClass::GermanLow, 42)
        .generate(Component::Alignment)
        .unwrap();
    let dot: f64 = a.iter().zip(&al).map(|(x, y)| x * y).sum();
    let na: f64 = a.iter().map(|x| x * x).sum::<f64>().sqrt();
    let nl: f64 = al.iter().map(|x| x * x).sum::<f64>().sqrt();
    assert!(
        (dot / (na * nl)).abs() < 0.2,
        "correlation {}",
        dot / (na * nl)
    );
}

/// `railfem irregularity` writes the profile in mm; read back it gives the generator's
/// values at the knots (to the decimal formatting of mm), and the plot and PSD table.
#[test]
fn command_writes_profile_that_reads_back() {
    let dir = temp_dir("irr-cmd");
    let out = dir.join("out");
    let o = railfem(&[
        "irregularity",
        "--psd",
        "fra5",
        "--seed",
        "3",
        "--wavelengths",
        "2,40",
        "--step",
        "0.5",
        "--length",
        "600",
        "--components",
        "vertical,cross_level",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(0), "{o:?}");
    let text = std::fs::read_to_string(out.join("irregularity.csv")).unwrap();
    let t = read_table(&text, "irregularity.csv").unwrap();
    let req = PsdRequest {
        class: PsdClass::Fra(5),
        seed: 3,
        wavelengths: [2.0, 40.0],
        step: 0.5,
        length: 600.0,
    };
    assert_eq!(t.stations.len(), 1201);
    for (c, v) in &t.columns {
        let z = req.generate(*c).unwrap();
        for (i, (x, y)) in v.iter().zip(&z).enumerate() {
            assert!(
                (x - y).abs() <= 1e-15 * y.abs().max(1e-6),
                "{c:?}[{i}]: {x} vs {y}"
            );
            assert_eq!(t.stations[i], i as f64 * 0.5);
        }
    }
    assert_eq!(t.columns[1].0, Component::CrossLevel);
    let svg = std::fs::read_to_string(out.join("irregularity-psd.svg")).unwrap();
    assert!(svg.contains("PSD S (m²/(rad/m))"));
    let psd = std::fs::read_to_string(out.join("psd.csv")).unwrap();
    assert!(psd.starts_with("component [-],omega [rad/m],welch [m²/(rad/m)],"));
    let _ = std::fs::remove_dir_all(&dir);
}

/// The example model: one sks700 carriage at 10 m/s (μ = 0.3), over a CSV
/// vertical profile of two C² bumps of 2 mm (examples/models/irregular_straight.csv). The
/// front wheelset's vertical displacement follows the profile at its station:
/// `u(t) − u(0) = z(s(t))` up to the change of the wheel–rail compression. Derivation of the
/// tolerance: at t = 0 (level rail) the axle sits `δ0 = −u(0)` below its reference, the
/// static compression of the Hertz spring in series with the contact penalty under the
/// static wheel load Q0; for stiffening springs the incremental compliance is at most the
/// secant one, so a change ΔQ of the wheel load changes the compression by at most
/// `δ0·|ΔQ|/Q0`. Add the spline's interpolation error of the 0.25 m table,
/// `(5/384)·h⁴·max|z''''| ≤ (5/384)·0.25⁴·2.5·A·k⁴ = 4e-8 m` (A = 2 mm, k = 2π/10 m), and
/// 2e-8 m for the Newton tolerance. An ignored irregularity (u = u(0)) misses by 2 mm, a
/// cross-level read as the mean by 1 mm.
#[test]
fn csv_irregularity_runs_and_wheelset_follows_it() {
    let dir = temp_dir("irr-run");
    let src = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/models");
    for f in ["irregular_straight.toml", "irregular_straight.csv"] {
        std::fs::copy(src.join(f), dir.join(f)).unwrap();
    }
    let out = dir.join("out");
    let o = railfem(&[
        "run",
        dir.join("irregular_straight.toml").to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(0), "{o:?}");
    let ws = Csv::read(&out.join("front_wheelset.csv"));
    let wheels = Csv::read(&out.join("wheels.csv"));
    let u = ws.column("2007_uy");
    let t = ws.column("time");
    // The front wheels: the largest station at t = 0.
    let first = &wheels.rows[0];
    let cols: Vec<usize> = (0..wheels.header.len())
        .filter(|&j| {
            common::strip_unit(&wheels.header[j]).ends_with("_station") && first[j] == 25.0
        })
        .collect();
    assert_eq!(cols.len(), 2, "two front wheels at 25 m");
    let q: Vec<f64> = wheels
        .rows
        .iter()
        .map(|r| cols.iter().map(|&j| r[j + 1]).sum::<f64>())
        .collect();
    let (q0, u0) = (q[0], u[0]);
    assert!(u0 < 0.0 && u0 > -1e-3, "static compression {u0}");
    let dq = q.iter().map(|x| (x - q0).abs()).fold(0.0, f64::max);
    let tol = -u0 * dq / q0 + 4e-8 + 2e-8;
    let profile = |s: f64| {
        let x = s - 40.0;
        if !(0.0..=20.0).contains(&x) {
            return 0.0;
        }
        let f = 0.5 * (1.0 - (2.0 * PI * x / 10.0).cos());
        2e-3 * f * f
    };
    let mut worst = 0.0f64;
    let mut peak = 0.0f64;
    for (i, &ti) in t.iter().enumerate() {
        let s = 25.0 + 10.0 * ti;
        worst = worst.max((u[i] - u0 - profile(s)).abs());
        peak = peak.max(u[i] - u0);
    }
    eprintln!(
        "worst {worst:.3e} m, tolerance {tol:.3e} m (ΔQ {dq:.1} N of {q0:.0} N), peak {peak:.3e} m"
    );
    assert!(
        peak > 1.9e-3,
        "the wheelset did not ride over the 2 mm bumps: {peak}"
    );
    assert!(worst < tol, "worst {worst} > {tol}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A model directory with `irr.csv` and a model whose `[track]` adds `irr`.
fn bad_case(name: &str, irr: &str, csv: Option<&str>, expect: &[&str]) {
    let dir = temp_dir(name);
    if let Some(text) = csv {
        std::fs::write(dir.join("irr.csv"), text).unwrap();
    }
    let model = format!(
        "[analysis]\nkind = \"transient\"\ndt = 0.01\nduration = 0.02\n\n[track]\nsegments = [{{type = \"straight\", length = 50.0}}]\nsupport = {{type = \"rigid\"}}\nirregularity = {irr}\n"
    );
    let path = dir.join(format!("{name}.toml"));
    std::fs::write(&path, model).unwrap();
    let o = railfem(&["check", path.to_str().unwrap()]);
    let err = refused_with(name, &o, expect);
    assert!(
        err.contains(&format!("{name}.toml")),
        "{name}: file not named: {err}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn bad_irregularities_are_refused() {
    bad_case(
        "psd_class",
        "{psd = \"fra7\", seed = 1, wavelengths = [1, 25]}",
        None,
        &[
            "`track.irregularity[0].psd`",
            "unknown spectrum `fra7`",
            "`fra1`, `fra2`, `fra3`, `fra4`, `fra5`, `fra6`, `german_low`, `german_high`",
        ],
    );
    bad_case(
        "unsorted",
        "{file = \"irr.csv\"}",
        Some("station_m,vertical_mm\n0,0\n1,0.5\n3,0.2\n2,0\n4,0\n"),
        &[
            "irr.csv:5",
            "station 2 m does not follow 3 m",
            "sort the rows",
        ],
    );
    bad_case(
        "mm_as_m",
        "{file = \"irr.csv\"}",
        Some("station_m,vertical_m\n0,0\n1,1.5\n2,2.5\n3,0\n"),
        &[
            "irr.csv:4",
            "look like millimetres",
            "declare `vertical_mm`",
        ],
    );
    bad_case(
        "missing",
        "{file = \"nowhere.csv\"}",
        None,
        &[
            "nowhere.csv",
            "cannot read the irregularity file",
            "check the path",
        ],
    );
    bad_case(
        "band",
        "{psd = \"german_low\", seed = 1, wavelengths = [30, 2]}",
        None,
        &[
            "irregularity[0]",
            "`wavelengths` = [30, 2]",
            "0 < λmin < λmax",
        ],
    );
    bad_case(
        "both",
        "[{psd = \"fra4\", seed = 1, wavelengths = [1, 25], file = \"irr.csv\"}]",
        None,
        &["irregularity[0]", "either `file` or `psd`"],
    );
    let o = railfem(&["irregularity", "--psd", "fra0"]);
    refused_with(
        "cli class",
        &o,
        &["--psd fra0 is not offered", "german_high"],
    );
    let o = railfem(&["irregularity", "--psd", "fra3", "--wavelengths", "5,5"]);
    refused_with("cli band", &o, &["--wavelengths", "λmin < λmax"]);
    // A profile no memory holds is refused before anything is allocated.
    let o = railfem(&[
        "irregularity",
        "--psd",
        "fra3",
        "--length",
        "1e15",
        "--max-memory",
        "1G",
    ]);
    refused_with(
        "cli size",
        &o,
        &["--length", "memory limit", "larger --step"],
    );
}

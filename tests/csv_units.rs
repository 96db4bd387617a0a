//! Every CSV file railfem writes names the unit of every column: the header fields read
//! `name [unit]` (`[-]` for a ratio, a count, a flag or a label). The test runs a set of
//! commands that together write every kind of CSV (recorders of nodes, of every element
//! family and comfort indices, energy, modes, the built-in cases' tables, the benchmark,
//! phase tables, the irregularity and PSD tables, the DOF map), walks every `.csv`
//! under their output directories and checks each header; plus the files only a failure
//! or a study writes, through the library functions that write them.

mod common;
use common::{railfem, temp_dir};
use std::path::{Path, PathBuf};

/// Every `.csv` under `dir`, recursively.
fn csv_files(dir: &Path, found: &mut Vec<PathBuf>) {
    for e in std::fs::read_dir(dir).unwrap().map_while(Result::ok) {
        let p = e.path();
        if p.is_dir() {
            csv_files(&p, found);
        } else if p.extension().is_some_and(|x| x == "csv") {
            found.push(p);
        }
    }
}

/// The header fields of `text` that do not end in a bracketed, declared unit. A header is
/// the first line and any line after a blank one (a file of several tables).
fn fields_without_unit(text: &str) -> Vec<String> {
    let mut bad = Vec::new();
    let mut header_next = true;
    for line in text.lines() {
        if line.trim().is_empty() {
            header_next = true;
            continue;
        }
        if header_next {
            for f in line.split(',') {
                let unit = f
                    .strip_suffix(']')
                    .and_then(|g| g.rsplit_once(" ["))
                    .map(|(name, u)| (name.trim(), u.trim()));
                match unit {
                    Some((name, u)) if !name.is_empty() && !u.is_empty() && u != "?" => {}
                    _ => bad.push(f.to_string()),
                }
            }
        }
        header_next = false;
    }
    bad
}

/// The checker itself: refuses bare names, empty and undeclared units.
#[test]
fn the_checker_finds_fields_without_units() {
    assert!(fields_without_unit("time [s],2_uz [m],5_Q [N]\n0,1,2\n").is_empty());
    assert_eq!(
        fields_without_unit("time [s],x,y []\n1,2,3\n\na [-],b_m\n"),
        vec!["x", "y []", "b_m"]
    );
    assert_eq!(fields_without_unit("t [s],5_f [?]\n"), vec!["5_f [?]"]);
}

fn run_ok(args: &[&str]) {
    let o = railfem(args);
    assert_eq!(
        o.status.code(),
        Some(0),
        "{args:?}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
}

/// The commands and models, each into its own directory; then every CSV is checked.
#[test]
fn every_csv_header_field_carries_a_unit() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let models = root.join("examples/models");
    let dir = temp_dir("csv_units");
    let out = |name: &str| dir.join(name).to_str().unwrap().to_string();
    // Model runs: node, element (beam3d, spring_damper, moving_sprung_mass, moving_axle
    // through a vehicle's wheels), sensor and comfort recorders (Sperling and EN 12299),
    // energy, modes.
    for model in [
        "comfort_oscillator.toml",
        "moving_force_beam.toml",
        "moving_sprung_mass_braking.toml",
        "ss_beam_modal.toml",
        "irregular_straight.toml",
        "cantilever.toml",
    ] {
        let m = models.join(model);
        run_ok(&["run", m.to_str().unwrap(), "--out", &out(model)]);
    }
    run_ok(&[
        "matrices",
        models.join("cantilever.toml").to_str().unwrap(),
        "--out",
        &out("matrices"),
    ]);
    run_ok(&["track", "--out", &out("track")]);
    run_ok(&[
        "irregularity",
        "--psd",
        "fra4",
        "--length",
        "200",
        "--out",
        &out("irregularity"),
    ]);
    run_ok(&[
        "train-bridge",
        "--cars",
        "1",
        "--spans",
        "2",
        "--steps",
        "10",
        "--out",
        &out("train_bridge"),
        "--assess",
    ]);
    run_ok(&["contact", "--y", "0.003", "--out", &out("contact")]);
    run_ok(&[
        "bench",
        "--sizes",
        "1e3",
        "--steps",
        "2",
        "--out",
        &out("bench"),
    ]);
    run_ok(&[
        "bench",
        "--case",
        "train-bridge",
        "--sizes",
        "1e4",
        "--steps",
        "2",
        "--out",
        &out("bench_train"),
    ]);
    // The per-step timeline adds up to the phase table's totals, one row per timed step,
    // each a paper step of 0.5 ms after the previous one.
    {
        let bt = dir.join("bench_train");
        let phases = std::fs::read_to_string(bt.join("phases.csv")).unwrap();
        let row: Vec<&str> = phases.lines().nth(1).unwrap().split(',').collect();
        let (dofs, steps, iterations) = (row[0], row[7], row[8]);
        let timeline = std::fs::read_to_string(bt.join(format!("steps-{dofs}.csv"))).unwrap();
        let rows: Vec<Vec<f64>> = timeline
            .lines()
            .skip(1)
            .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
            .collect();
        assert_eq!(rows.len().to_string(), steps);
        let its: f64 = rows.iter().map(|r| r[1]).sum();
        assert_eq!(its.to_string(), iterations);
        for w in rows.windows(2) {
            assert!((w[1][0] - w[0][0] - 5e-4).abs() < 1e-9, "{w:?}");
        }
    }
    run_ok(&[
        "critical-radius",
        "--sweep",
        "--criterion",
        "separation",
        "--speeds",
        "260",
        "--cts",
        "200",
        "--clothoid",
        "300",
        "--out",
        &out("critical"),
    ]);
    // Written by a failed step and by the studies: the library writers themselves.
    let lib = dir.join("lib");
    std::fs::create_dir_all(&lib).unwrap();
    let (mut d, _) = railfem::prepare(
        railfem::load_model(&models.join("sdof.toml")),
        "sdof.toml",
        false,
    )
    .unwrap();
    d.initialize().unwrap();
    d.write_state(&lib.join("last_converged_state.csv"))
        .unwrap();
    std::fs::write(lib.join("pareto.csv"), railfem::pareto::csv(&[])).unwrap();

    let mut files = Vec::new();
    csv_files(&dir, &mut files);
    let names: Vec<String> = files
        .iter()
        .map(|p| p.file_name().unwrap().to_string_lossy().into_owned())
        .collect();
    for expected in [
        "energy.csv",
        "modes.csv",
        "comfort.csv",
        "nmv.csv",
        "wheels.csv",
        "midspan.csv",
        "summary.csv",
        "bench.csv",
        "phases.csv",
        "irregularity.csv",
        "psd.csv",
        "track.csv",
        "dofs.csv",
        "critical_separation.csv",
        "last_converged_state.csv",
        "pareto.csv",
    ] {
        assert!(
            names.iter().any(|n| n == expected),
            "{expected} not written: {names:?}"
        );
    }
    let mut problems = Vec::new();
    for p in &files {
        let text = std::fs::read_to_string(p).unwrap();
        let bad = fields_without_unit(&text);
        if !bad.is_empty() {
            problems.push(format!(
                "{}: {bad:?}",
                p.strip_prefix(&dir).unwrap().display()
            ));
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
    assert!(files.len() >= 25, "only {} CSV files", files.len());
    let _ = std::fs::remove_dir_all(&dir);
}

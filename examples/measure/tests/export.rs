//! `railfem-measure export`: what another code reads to rerun the benchmark beam is
//! complete and consistent — every CSV header names its units, the equation count is what
//! the nodes and their supports leave, the load vector of every step carries the whole
//! moving force, and railfem's answer has one row per step.

use std::path::Path;
use std::process::Command;

/// The header fields of a CSV that do not read `name [unit]`.
fn fields_without_unit(header: &str) -> Vec<String> {
    header
        .split(',')
        .filter(|f| {
            !f.strip_suffix(']')
                .and_then(|g| g.rsplit_once(" ["))
                .is_some_and(|(name, u)| !name.trim().is_empty() && !u.trim().is_empty())
        })
        .map(str::to_string)
        .collect()
}

fn read(dir: &Path, name: &str) -> String {
    std::fs::read_to_string(dir.join(name)).unwrap_or_else(|e| panic!("{name}: {e}"))
}

/// A two-span beam (about 100 DOF) for 3 steps of 2 ms: the force enters at 0.08 m and
/// stays on the beam. Its consistent nodal forces sum to the force itself at every step
/// (the shape functions of a beam element sum to one), so the `uz` entries of each step in
/// `loads.csv` add up to −1e5 N to rounding (1e-6 N: 17 digits written).
#[test]
fn export_writes_a_consistent_model_with_units() {
    let dir = std::env::temp_dir().join(format!("railfem-measure-{}-export", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let o = Command::new(env!("CARGO_BIN_EXE_railfem-measure"))
        .args([
            "export",
            dir.to_str().unwrap(),
            "--sizes",
            "100",
            "--steps",
            "3",
        ])
        .output()
        .expect("run railfem-measure");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let d = dir.join("dof100");
    for name in ["nodes.csv", "elements.csv", "loads.csv", "railfem.csv"] {
        let text = read(&d, name);
        let header = text.lines().next().unwrap_or("");
        assert!(fields_without_unit(header).is_empty(), "{name}: {header}");
    }
    // Equations: six per node, less every DOF the supports hold.
    let nodes = read(&d, "nodes.csv");
    let rows: Vec<&str> = nodes.lines().skip(1).collect();
    let held: usize = rows
        .iter()
        .map(|r| r.rsplit(',').next().unwrap().split_whitespace().count())
        .sum();
    let model: serde_json::Value = serde_json::from_str(&read(&d, "model.json")).unwrap();
    assert_eq!(model["equations"], 6 * rows.len() - held);
    assert_eq!(model["mass_kind"], "consistent");
    let elements = read(&d, "elements.csv").lines().count() - 1;
    assert_eq!(
        elements + 1,
        rows.len(),
        "a continuous beam: one node more than elements"
    );
    // The whole force on the beam at every step.
    let loads = read(&d, "loads.csv");
    for step in 1..=3 {
        let fz: f64 = loads
            .lines()
            .skip(1)
            .map(|l| l.split(',').collect::<Vec<_>>())
            .filter(|f| f[0] == step.to_string() && f[3] == "uz")
            .map(|f| f[4].parse::<f64>().unwrap())
            .sum();
        assert!((fz + 1.0e5).abs() < 1e-6, "step {step}: {fz} N");
    }
    assert_eq!(read(&d, "railfem.csv").lines().count(), 1 + 3);
    let timing: serde_json::Value = serde_json::from_str(&read(&d, "timing.json")).unwrap();
    assert_eq!(timing["equations"], model["equations"]);
}

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

/// A two-span beam (about 100 DOF, elements of 2.5 m) for 20 steps of 2 ms: the force
/// enters at 0.08 m and reaches 3.12 m, crossing from the first element (whose first node,
/// the support, holds `uz`) onto the second. The consistent nodal forces of a point load
/// `F` at `ξ = (x − x_i)/h` on a cubic Hermite element are `F·N₁(ξ)` and `F·N₃(ξ)` with
/// `N₁ = 1 − 3ξ² + 2ξ³`, `N₃ = 3ξ² − 2ξ³` (they sum to `F`); `loads.csv` holds the entries
/// of free DOFs only, so each step's `uz` entries add up to `F` times the shape functions
/// of the nodes whose `uz` is free: `F·N₃` on the first element, `F` on the second. To
/// 1e-6 N (17 digits written, forces of 1e5 N).
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
            "20",
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
    // Node stations and whether `uz` is free, in order along the beam.
    let stations: Vec<(f64, bool)> = rows
        .iter()
        .map(|r| {
            let f: Vec<&str> = r.split(',').collect();
            (
                f[1].parse().unwrap(),
                !f[4].split_whitespace().any(|d| d == "uz"),
            )
        })
        .collect();
    let (v, dt) = (
        model["speed"].as_f64().unwrap(),
        model["dt"].as_f64().unwrap(),
    );
    let force = model["force_z"].as_f64().unwrap();
    // The bench starts the force at −v·dt/2, so that it enters just after t = 0.
    let start = -0.5 * v * dt;
    let loads = read(&d, "loads.csv");
    let mut by_step = std::collections::BTreeMap::<usize, (f64, f64)>::new();
    for l in loads.lines().skip(1) {
        let f: Vec<&str> = l.split(',').collect();
        let e = by_step.entry(f[0].parse().unwrap()).or_default();
        e.0 = f[1].parse().unwrap();
        if f[3] == "uz" {
            e.1 += f[4].parse::<f64>().unwrap();
        }
    }
    assert_eq!(by_step.len(), 20, "every step has loads");
    for (step, (t, fz)) in by_step {
        let x = start + v * t;
        let i = stations.iter().rposition(|s| s.0 <= x).unwrap();
        let ((xi, free_i), (xj, free_j)) = (stations[i], stations[i + 1]);
        let xi_ = (x - xi) / (xj - xi);
        let n1 = 1.0 - 3.0 * xi_ * xi_ + 2.0 * xi_.powi(3);
        let n3 = 3.0 * xi_ * xi_ - 2.0 * xi_.powi(3);
        let want = force * (if free_i { n1 } else { 0.0 } + if free_j { n3 } else { 0.0 });
        assert!(
            (fz - want).abs() < 1e-6,
            "step {step} at x = {x} m: {fz} N, want {want} N"
        );
    }
    assert_eq!(read(&d, "railfem.csv").lines().count(), 1 + 20);
    let timing: serde_json::Value = serde_json::from_str(&read(&d, "timing.json")).unwrap();
    assert_eq!(timing["equations"], model["equations"]);
}

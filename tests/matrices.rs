//! `railfem matrices`: the Matrix Market files read back with `sprs` satisfy relations that
//! hold independently of railfem's solvers.
//!
//! - A cantilever of four cubic beam elements under a tip load: the closed-form
//!   Euler–Bernoulli deflection `w(x) = P·x²·(3L − x)/(6EI)` and slope, put into the DOF
//!   vector through `dofs.csv`, satisfy `K·u = f` (cubic Hermite elements reproduce a cubic
//!   deflection exactly, so the residual is round-off).
//! - The same beam unsupported, with a tip mass and Rayleigh damping: a rigid translation
//!   `r` along Z gives `rᵀ·M·r = ρAL + m` (the total mass) and `K·r = 0`, so
//!   `C·r = α·M·r`.

mod common;
use common::{railfem, temp_dir};
use railfem::framework::matrix_market::{read_matrix, read_vector};
use std::path::Path;

const L: f64 = 2.5; // m
const E: f64 = 2.1e11; // Pa
const IY: f64 = 3.038e-5; // m⁴
const P: f64 = 1.0e4; // N
const RHO: f64 = 7850.0; // kg/m³
const AREA: f64 = 7.686e-3; // m²
const TIP_MASS: f64 = 350.0; // kg
const ALPHA: f64 = 0.3; // 1/s

/// A beam of four elements along X; `clamped` fixes node 1, else nothing is fixed and the
/// model is transient with mass and Rayleigh damping.
fn model(dir: &Path, clamped: bool) -> std::path::PathBuf {
    let mut s = String::new();
    if clamped {
        s.push_str("[analysis]\nkind = \"static\"\nsteps = 1\n");
    } else {
        s.push_str(&format!(
            "[analysis]\nkind = \"transient\"\nduration = 0.01\ndt = 0.001\nrayleigh = {{ alpha = {ALPHA}, beta = 1.0e-4 }}\n"
        ));
    }
    for i in 0..5 {
        let fix = if clamped && i == 0 {
            "fix = \"all\"\n"
        } else {
            ""
        };
        s.push_str(&format!(
            "[[node]]\nid = {}\nxyz = [{}, 0.0, 0.0]\n{fix}",
            i + 1,
            L * i as f64 / 4.0
        ));
    }
    for i in 0..4 {
        s.push_str(&format!(
            "[[element]]\ntype = \"beam3d\"\nid = {}\nnodes = [{}, {}]\nE = {E}\nG = 8.1e10\nA = {AREA}\nIy = {IY}\nIz = 5.123e-6\nJ = 2.0e-6\nrho = {RHO}\n",
            i + 1,
            i + 1,
            i + 2
        ));
    }
    if clamped {
        s.push_str(&format!(
            "[[load]]\ntype = \"nodal\"\nnode = 5\ndof = \"uz\"\nvalue = {P}\n"
        ));
    } else {
        s.push_str(&format!(
            "[[element]]\ntype = \"mass\"\nid = 9\nnodes = [5]\nm = {TIP_MASS}\n"
        ));
    }
    let p = dir.join(if clamped { "clamped.toml" } else { "free.toml" });
    std::fs::write(&p, s).unwrap();
    p
}

/// Runs `railfem matrices` on the model and returns the output directory.
fn matrices(dir: &Path, model: &Path) -> std::path::PathBuf {
    let out = dir.join(model.file_stem().unwrap());
    let o = railfem(&[
        "matrices",
        model.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{o:?}");
    out
}

/// `(node id, dof name)` of each equation, from `dofs.csv`.
fn dof_map(out: &Path) -> Vec<(u64, String)> {
    let text = std::fs::read_to_string(out.join("dofs.csv")).unwrap();
    let mut lines = text.lines();
    let header = lines.next().unwrap();
    assert!(header.starts_with("equation [") && header.contains("unit [m or rad]"));
    lines
        .enumerate()
        .map(|(k, l)| {
            let c: Vec<&str> = l.split(',').collect();
            assert_eq!(c[0].parse::<usize>().unwrap(), k + 1, "equations in order");
            let unit = if c[2].starts_with('u') { "m" } else { "rad" };
            assert_eq!(c[3], unit, "{l}");
            (c[1].parse().unwrap(), c[2].to_string())
        })
        .collect()
}

fn product(a: &sprs::CsMat<f64>, x: &[f64]) -> Vec<f64> {
    let mut y = vec![0.0; a.rows()];
    for (&v, (i, j)) in a.iter() {
        y[i] += v * x[j];
    }
    y
}

#[test]
fn cantilever_stiffness_times_closed_form_deflection_is_the_load() {
    let dir = temp_dir("matrices-clamped");
    let out = matrices(&dir, &model(&dir, true));
    let k = read_matrix(&out.join("K.mtx")).unwrap();
    let f = read_vector(&out.join("f.mtx")).unwrap();
    let map = dof_map(&out);
    assert_eq!(map.len(), 24, "4 free nodes × 6 DOFs");
    assert_eq!((k.rows(), k.cols(), f.len()), (24, 24, 24));
    let ei = E * IY;
    let u: Vec<f64> = map
        .iter()
        .map(|(node, dof)| {
            let x = L * (*node as f64 - 1.0) / 4.0;
            match dof.as_str() {
                "uz" => P * x * x * (3.0 * L - x) / (6.0 * ei),
                // Right-hand rule about Y: a slope up in +X is a negative ry.
                "ry" => -P * x * (2.0 * L - x) / (2.0 * ei),
                _ => 0.0,
            }
        })
        .collect();
    let ku = product(&k, &u);
    // Round-off: K's entries reach 12EI/h³ ≈ 3e9 N/m against u ≈ 1e-2 m, so sums of terms
    // of ~1e7 N cancel to the load; 1e-6 of P is ~1e4 ulps of those terms.
    for (i, (a, b)) in ku.iter().zip(&f).enumerate() {
        assert!(
            (a - b).abs() < 1e-6 * P,
            "row {i} {:?}: K·u = {a}, f = {b}",
            map[i]
        );
    }
    let tip = map.iter().position(|(n, d)| *n == 5 && d == "uz").unwrap();
    assert_eq!(f[tip], P);
    assert_eq!(f.iter().filter(|v| **v != 0.0).count(), 1);
}

#[test]
fn free_beam_mass_and_damping_of_a_rigid_translation() {
    let dir = temp_dir("matrices-free");
    let out = matrices(&dir, &model(&dir, false));
    let (k, m, c) = (
        read_matrix(&out.join("K.mtx")).unwrap(),
        read_matrix(&out.join("M.mtx")).unwrap(),
        read_matrix(&out.join("C.mtx")).unwrap(),
    );
    let map = dof_map(&out);
    assert_eq!(map.len(), 30);
    let r: Vec<f64> = map
        .iter()
        .map(|(_, d)| if d == "uz" { 1.0 } else { 0.0 })
        .collect();
    let mr = product(&m, &r);
    let total: f64 = r.iter().zip(&mr).map(|(a, b)| a * b).sum();
    let exact = RHO * AREA * L + TIP_MASS;
    assert!(
        (total - exact).abs() < 1e-10 * exact,
        "rᵀMr = {total} kg, ρAL + m = {exact} kg"
    );
    let kr = product(&k, &r);
    let k_scale = k.iter().fold(0.0f64, |a, (v, _)| a.max(v.abs()));
    assert!(kr.iter().all(|v| v.abs() < 1e-12 * k_scale), "K·r = 0");
    let cr = product(&c, &r);
    for (i, (a, b)) in cr.iter().zip(&mr).enumerate() {
        assert!(
            (a - ALPHA * b).abs() < 1e-9 * exact,
            "row {i}: C·r = {a}, α·M·r = {}",
            ALPHA * b
        );
    }
    let f = read_vector(&out.join("f.mtx")).unwrap();
    assert!(f.iter().all(|v| *v == 0.0), "no load, no gravity");
}

#[test]
fn matrices_without_a_model_is_refused() {
    let o = railfem(&["matrices"]);
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    assert!(
        err.contains("<MODEL>") && err.contains("railfem matrices --help"),
        "{err}"
    );
}

//! The example model files in `examples/models/` run from the command line
//! (`railfem run MODEL --out DIR`), exit 0, and their recorder CSV files agree with closed
//! forms derived here (not with numbers produced by the code under test).

mod common;

use common::{railfem, temp_dir, Csv};
use std::path::{Path, PathBuf};

fn model(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("examples/models")
        .join(name)
}

/// Runs `railfem run MODEL --out DIR` and asserts a clean exit; returns DIR.
fn run(name: &str) -> PathBuf {
    let out = temp_dir(name);
    let m = model(name);
    let o = railfem(&[
        "run",
        m.to_str().expect("utf-8 path"),
        "--out",
        out.to_str().expect("utf-8 path"),
    ]);
    assert!(
        o.status.success(),
        "{name}: exit {:?}, stderr: {}",
        o.status.code(),
        String::from_utf8_lossy(&o.stderr)
    );
    assert!(o.stderr.is_empty(), "{name}: stderr not empty");
    out
}

fn rel(got: f64, want: f64) -> f64 {
    (got - want).abs() / want.abs()
}

/// `cantilever.toml`: one `beam3d` (60E1: E = 2.1e11 Pa, Iy = 3.038e-5 m⁴), L = 2.5 m,
/// clamped at node 1, P = 10 kN along Z at node 2, static.
///
/// Euler–Bernoulli (`EI·w'' = P·(L − x)`, `w(0) = w'(0) = 0`): `uz = PL³/(3EIy)`, and the
/// slope `w'(L) = PL²/(2EIy)` is a rotation `ry = −w'` about +Y. Root resultants (on the
/// +x face of a cut just inside node 1, i.e. what the tip side exerts across it):
/// `Vz = P`, `My = −P·L`. One Hermite element is exact, so the tolerance 1e-9 covers only
/// round-off and the 13 significant digits of the CSV.
#[test]
fn cantilever_file_matches_euler_bernoulli() {
    let out = run("cantilever.toml");
    let (p, l, e, iy): (f64, f64, f64, f64) = (1.0e4, 2.5, 2.1e11, 3.038e-5);
    let tip = Csv::read(&out.join("tip.csv"));
    assert_eq!(tip.rows.len(), 1, "a static run records once");
    let uz = tip.column("2_uz")[0];
    let ry = tip.column("2_ry")[0];
    assert!(rel(uz, p * l.powi(3) / (3.0 * e * iy)) < 1e-9, "uz = {uz}");
    assert!(rel(ry, -p * l * l / (2.0 * e * iy)) < 1e-9, "ry = {ry}");
    let root = Csv::read(&out.join("root_forces.csv"));
    assert!(rel(root.column("1_Vz")[0], p) < 1e-9);
    assert!(rel(root.column("1_My")[0], -p * l) < 1e-9);
    let _ = std::fs::remove_dir_all(&out);
}

/// `sdof.toml`: m = 1000 kg, k = 4e6 N/m, c = 6000 N·s/m, step force F = 10 kN from rest,
/// Newmark average acceleration, Δt = 5 ms, 400 steps.
///
/// Discrete closed form. Average acceleration is the trapezoidal rule applied to
/// `y' = A·y`, `y = (u − F/k, v)`, `A = [[0, 1], [−ω², −2ζω]]` (the constant particular
/// solution `u = F/k` is reproduced exactly): `y_{n+1} = G·y_n` with
/// `G = (I − ΔtA/2)⁻¹(I + ΔtA/2)`. G has A's eigenvectors `(1, λ)` and eigenvalues
/// `μ = (1 + Δtλ/2)/(1 − Δtλ/2)` for `λ = −ζω ± iω_d`, `ω_d = ω√(1 − ζ²)`. The continuous
/// solution is `u − F/k = Re(C·e^{λt})`, `v = Re(C·λ·e^{λt})`, so the discrete one is the
/// same with `e^{λt_n}` replaced by `μⁿ`. From `u(0) = 0`, `v(0) = 0`:
/// `Re C = −F/k`, `Re(C·λ) = 0` ⇒ `C = −(F/k)·(1 − i·ζω/ω_d)`.
/// Tolerance: 1e-9 of F/k (the CSV carries 13 significant digits; round-off over 400
/// steps of a 1-DOF recursion is ~1e-14).
#[test]
fn sdof_file_matches_discrete_newmark_solution() {
    let out = run("sdof.toml");
    let (m, k, c, f, dt) = (1000.0f64, 4.0e6f64, 6000.0f64, 1.0e4f64, 0.005f64);
    let w = (k / m).sqrt();
    let zeta = c / (2.0 * (k * m).sqrt());
    let wd = w * (1.0 - zeta * zeta).sqrt();
    // C = cr + i·ci, λ = lr + i·li, μ = ρ·e^{iφ}.
    let (cr, ci) = (-f / k, f / k * zeta * w / wd);
    let (lr, li) = (-zeta * w, wd);
    let (x, y) = (lr * dt / 2.0, li * dt / 2.0);
    let rho = (((1.0 + x).powi(2) + y * y) / ((1.0 - x).powi(2) + y * y)).sqrt();
    let phi = y.atan2(1.0 + x) + y.atan2(1.0 - x);
    // C·λ
    let (clr, cli) = (cr * lr - ci * li, cr * li + ci * lr);
    let re = |ar: f64, ai: f64, n: f64| rho.powf(n) * (ar * (n * phi).cos() - ai * (n * phi).sin());

    let disp = Csv::read(&out.join("disp.csv"));
    let vel = Csv::read(&out.join("vel.csv"));
    let t = disp.column("time");
    let u = disp.column("1_ux");
    let v = vel.column("1_ux");
    assert_eq!(t.len(), 401, "t = 0 and 400 steps");
    let mut worst_u: f64 = 0.0;
    let mut worst_v: f64 = 0.0;
    let mut peak: f64 = 0.0;
    for (i, ((ti, ui), vi)) in t.iter().zip(&u).zip(&v).enumerate() {
        let n = i as f64;
        assert!((ti - n * dt).abs() < 1e-9, "row {i}: t = {ti}");
        let ue = f / k + re(cr, ci, n);
        let ve = re(clr, cli, n);
        worst_u = worst_u.max((ui - ue).abs());
        worst_v = worst_v.max((vi - ve).abs());
        peak = peak.max(ue);
    }
    // The step response overshoots to ≈ (1 + e^{−ζπ/√(1−ζ²)})·F/k: the run really rings.
    assert!(peak > 1.8 * f / k, "peak {peak}");
    assert!(worst_u < 1e-9 * f / k, "displacement error {worst_u:e} m");
    assert!(worst_v < 1e-9 * f / k * w, "velocity error {worst_v:e} m/s");
    let _ = std::fs::remove_dir_all(&out);
}

/// `moving_force_beam.toml`: P = 100 kN crossing the 25 m bridge (EI = 2.943e10 N·m²,
/// m = 2303 kg/m) at 27.78 m/s, 20 elements, Δt = 2.5 ms (T₁/44.5), Newmark average
/// acceleration. The midspan deflection agrees with Frýba's series ([`common::fryba`], 50
/// terms, derived there) within 1% of its peak at every recorded step with the force on
/// the span; see `closed_forms.rs` for the error budget (period elongation of average
/// acceleration acting on the free-vibration part, ≈ 0.6% at this Δt at the very worst).
#[test]
fn moving_force_file_matches_fryba_series() {
    let out = run("moving_force_beam.toml");
    let (p, v, l, ei, m): (f64, f64, f64, f64, f64) = (1.0e5, 27.78, 25.0, 2.943e10, 2303.0);
    let csv = Csv::read(&out.join("midspan.csv"));
    let t = csv.column("time");
    let w = csv.column("10_uz");
    let mut worst: f64 = 0.0;
    let mut peak: f64 = 0.0;
    let mut compared = 0;
    for (ti, wi) in t.iter().zip(&w) {
        if *ti > l / v {
            continue;
        }
        let exact = common::fryba(l / 2.0, *ti, p, v, l, ei, m, 50);
        worst = worst.max((-wi - exact).abs());
        peak = peak.max(exact.abs());
        compared += 1;
    }
    eprintln!(
        "moving_force_beam.toml: {compared} steps, max error / peak = {:.3e}",
        worst / peak
    );
    assert!(compared > 350, "{compared} rows compared");
    // The peak is near the static midspan deflection PL³/(48EI) times a small dynamic
    // amplification (α = 0.062).
    let stat = p * l.powi(3) / (48.0 * ei);
    assert!(
        peak > stat && peak < 1.15 * stat,
        "peak {peak} vs static {stat}"
    );
    assert!(
        worst < 0.01 * peak,
        "error {:.3e} of the peak",
        worst / peak
    );
    let _ = std::fs::remove_dir_all(&out);
}

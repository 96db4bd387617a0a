//! Helpers shared by the integration tests: unique temporary directories, running the
//! `railfem` binary, reading recorder CSV files, and the closed-form moving-force series.

#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::OnceLock;

// The one-line refusal check, shared with the railfem-measure member's tests.
mod refusal;
pub use refusal::refused_with;

/// A fresh, empty directory under the system temp dir, unique per process and call.
pub fn temp_dir(name: &str) -> PathBuf {
    static COUNTER: AtomicUsize = AtomicUsize::new(0);
    let k = COUNTER.fetch_add(1, Ordering::Relaxed);
    let d = std::env::temp_dir().join(format!("railfem-test-{}-{k}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).expect("create temp dir");
    d
}

/// The model's matrices about `d`'s reference state and block `b`'s Craig–Bampton
/// reduction (the library's cut-off for `dt`), both taken before `steps` steps of `dt`:
/// the reduced far field's tests' shaking block, about to be switched.
pub fn reduce_then_march(
    d: &mut railfem::solvers::Driver,
    b: usize,
    dt: f64,
    steps: usize,
) -> (
    railfem::solvers::ReferenceSystem,
    railfem::solvers::reduced::CraigBampton,
) {
    let sys = d.reference_system().expect("reference system");
    let cb = d
        .block_reduction(
            b,
            railfem::solvers::reduced::cutoff::CutOffRule::default().omega(dt),
        )
        .expect("partitioned")
        .expect("reduction");
    for _ in 0..steps {
        d.step(dt).expect("step");
    }
    (sys, cb)
}

/// Runs `railfem study PLAN --out OUT -q`, then `extra`.
pub fn study(plan: &Path, out: &Path, extra: &[&str]) -> Output {
    let mut args = vec![
        "study",
        plan.to_str().expect("utf-8"),
        "--out",
        out.to_str().expect("utf-8"),
        "-q",
    ];
    args.extend_from_slice(extra);
    railfem(&args)
}

/// Runs the `railfem` binary with `args`.
pub fn railfem(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_railfem"))
        .args(args)
        .output()
        .expect("run railfem")
}

/// A CSV header's name without its unit: `Q_fe [N]` → `Q_fe`.
pub fn strip_unit(header: &str) -> &str {
    header.split(" [").next().unwrap_or(header)
}

/// A recorder CSV: header names and rows of numbers.
pub struct Csv {
    /// Column names (`time`, `2_uz`, …).
    pub header: Vec<String>,
    /// Rows of values.
    pub rows: Vec<Vec<f64>>,
}

impl Csv {
    /// Reads a recorder file.
    pub fn read(path: &Path) -> Csv {
        let text = std::fs::read_to_string(path)
            .unwrap_or_else(|e| panic!("read {}: {e}", path.display()));
        let mut lines = text.lines();
        let header: Vec<String> = lines
            .next()
            .expect("header")
            .split(',')
            .map(str::to_string)
            .collect();
        let rows = lines
            .map(|l| {
                l.split(',')
                    .map(|x| x.parse::<f64>().expect("number"))
                    .collect()
            })
            .collect();
        Csv { header, rows }
    }

    /// The values of column `name`: the header's name before its unit (`time` finds
    /// `time [s]`), or the whole header text (`time [s]`).
    pub fn column(&self, name: &str) -> Vec<f64> {
        let j = self
            .header
            .iter()
            .position(|h| h == name || strip_unit(h) == name)
            .unwrap_or_else(|| panic!("no column {name} in {:?}", self.header));
        self.rows.iter().map(|r| r[j]).collect()
    }
}

/// Deflection `w(x, t)` (m, positive along the force) of a simply supported
/// Euler–Bernoulli beam under a constant force `p` (N) crossing it at speed `v` (m/s),
/// from rest, while the force is on the span (`0 ≤ v·t ≤ L`); Frýba's modal series
/// summed over `terms` modes. Span `l` (m), bending stiffness `ei` (N·m²), mass per
/// length `m` (kg/m), undamped.
///
/// Derivation. The beam obeys `EI·w'''' + m·ẅ = p·δ(x − v·t)`. With the simply supported
/// modes `w = Σ_n q_n(t)·sin(nπx/L)` (orthogonal, `∫₀ᴸ sin² = L/2`), projecting on mode n
/// gives `(mL/2)·q̈_n + (mL/2)·ω_n²·q_n = p·sin(nπvt/L)`, i.e.
/// `q̈_n + ω_n²·q_n = (2p/(mL))·sin(Ω_n·t)` with `ω_n = (nπ/L)²·√(EI/m)` and
/// `Ω_n = nπv/L = n·ω`, `ω = πv/L`. From rest (`q_n = q̇_n = 0`) the solution is the
/// particular part plus the free vibration that cancels its initial velocity:
/// `q_n = (2p/(mL))/(ω_n² − Ω_n²)·[sin(Ω_n·t) − (Ω_n/ω_n)·sin(ω_n·t)]`.
/// Since `2p/(mL·ω_n²) = 2pL³/(π⁴·EI·n⁴)` and, with `α = ω/ω_1`, `Ω_n/ω_n = α/n`:
/// `q_n = (2pL³/(π⁴EI))·1/(n⁴·(1 − α²/n²))·[sin(nωt) − (α/n)·sin(ω_n·t)]`.
/// The truncation error after N terms is below `Σ_{n>N} 2pL³/(π⁴EI n⁴) ≈
/// 2pL³/(3π⁴EI·N³)`, i.e. below 1e-5 of the static midspan deflection `pL³/(48EI)` for
/// N = 50.
#[allow(clippy::too_many_arguments)]
pub fn fryba(x: f64, t: f64, p: f64, v: f64, l: f64, ei: f64, m: f64, terms: usize) -> f64 {
    use std::f64::consts::PI;
    let w = PI * v / l;
    let w1 = (PI / l).powi(2) * (ei / m).sqrt();
    let alpha = w / w1;
    let scale = 2.0 * p * l.powi(3) / (PI.powi(4) * ei);
    (1..=terms)
        .map(|n| {
            let nf = n as f64;
            let wn = nf * nf * w1;
            let amp = scale / (nf.powi(4) * (1.0 - alpha * alpha / (nf * nf)));
            amp * ((nf * w * t).sin() - alpha / nf * (wn * t).sin()) * (nf * PI * x / l).sin()
        })
        .sum()
}

/// Writes `text` as `name` into `dir` and runs `railfem run` on it, its outputs into
/// `dir/out-NAME`: that directory and the process's output.
pub fn run_model_in(dir: &Path, name: &str, text: &str) -> (PathBuf, Output) {
    let path = dir.join(name);
    std::fs::write(&path, text).expect("write model");
    let out = dir.join(format!("out-{name}"));
    let o = railfem(&[
        "run",
        path.to_str().expect("utf-8"),
        "--out",
        out.to_str().expect("utf-8"),
    ]);
    (out, o)
}

/// Writes `text` as `name` into a fresh directory, runs `railfem run` on it and checks
/// the exit code (2), that stderr is one line, that it names the file, and that it contains
/// every string of `expect` (the place and the fix). Returns the line.
pub fn check_bad_model(name: &str, text: &str, expect: &[&str]) -> String {
    let dir = temp_dir(name.split('.').next().unwrap_or("case"));
    let (_, o) = run_model_in(&dir, name, text);
    let err = refused_with(name, &o, expect);
    assert!(err.contains(name), "{name}: the file is not named: {err}");
    let _ = std::fs::remove_dir_all(&dir);
    err
}

/// Builds the plugin once per test binary with the profile of this test binary's directory
/// (`target/debug` → `dev`, `target/release` → `release`) into the same target directory,
/// and returns the path of the shared library.
pub fn plugin_lib() -> &'static Path {
    static LIB: OnceLock<PathBuf> = OnceLock::new();
    LIB.get_or_init(|| {
        let exe = std::env::current_exe().expect("test executable path");
        // target/<profile>/deps/plugins-<hash>
        let profile_dir = exe
            .parent()
            .and_then(Path::parent)
            .expect("target/<profile>/deps layout")
            .to_path_buf();
        let target_dir = profile_dir.parent().expect("target dir").to_path_buf();
        let profile = match profile_dir.file_name().and_then(|n| n.to_str()) {
            Some("debug") => "dev".to_string(),
            Some(other) => other.to_string(),
            None => "dev".to_string(),
        };
        let status = Command::new(env!("CARGO"))
            .args([
                "build",
                "--quiet",
                "-p",
                "railfem-plugin-hysteretic",
                "--profile",
            ])
            .arg(&profile)
            .arg("--target-dir")
            .arg(&target_dir)
            .arg("--manifest-path")
            .arg(Path::new(env!("CARGO_MANIFEST_DIR")).join("Cargo.toml"))
            .status()
            .expect("cargo runs");
        assert!(status.success(), "building the plugin failed");
        let lib = profile_dir.join(format!(
            "{}railfem_plugin_hysteretic{}",
            std::env::consts::DLL_PREFIX,
            std::env::consts::DLL_SUFFIX
        ));
        assert!(lib.exists(), "{} missing", lib.display());
        lib
    })
}

/// For histories of states `[q, v, a]` (one per step): the largest difference over all steps
/// relative to the largest value, for q, v and a separately.
pub fn worst_relative(a: &[[Vec<f64>; 3]], b: &[[Vec<f64>; 3]]) -> [f64; 3] {
    let mut r = [0.0; 3];
    for (k, rk) in r.iter_mut().enumerate() {
        let (mut scale, mut diff) = (0.0f64, 0.0f64);
        for (x, y) in a.iter().zip(b) {
            for (u, w) in x[k].iter().zip(&y[k]) {
                scale = scale.max(u.abs());
                diff = diff.max((u - w).abs());
            }
        }
        assert!(scale > 0.0);
        *rk = diff / scale;
    }
    r
}

/// Largest difference of any energy (external work, kinetic, strain, damping, friction,
/// integrator) between the energy-balance rows `a` and `b`, relative to the largest energy
/// of `b` (`EnergyRow::scale`), which must be positive; the rows' times must agree.
pub fn energy_difference(
    a: &[railfem::solvers::energy::EnergyRow],
    b: &[railfem::solvers::energy::EnergyRow],
) -> f64 {
    assert_eq!(a.len(), b.len());
    let scale = b.iter().fold(0.0f64, |m, r| m.max(r.scale()));
    assert!(scale > 0.0);
    let mut worst = 0.0f64;
    for (x, y) in a.iter().zip(b) {
        assert_eq!(x.t, y.t);
        for (p, q) in [
            (x.external_work, y.external_work),
            (x.kinetic, y.kinetic),
            (x.strain, y.strain),
            (x.damping, y.damping),
            (x.friction, y.friction),
            (x.material, y.material),
            (x.integrator, y.integrator),
        ] {
            worst = worst.max((p - q).abs());
        }
    }
    worst / scale
}

/// Solves `b` statically, in one load step, under a point load `value` (N, positive up)
/// along global Z at `node`: the driver holds the solution.
pub fn solve_under_point_load(
    mut b: railfem::framework::builder::ModelBuilder,
    node: u64,
    value: f64,
) -> railfem::solvers::Driver {
    use railfem::framework::loads::{LoadSpec, TimeSeries};
    use railfem::framework::model::{AnalysisKind, AnalysisSpec};
    b.load(LoadSpec::Nodal {
        node,
        dof: railfem::framework::Dof::Uz,
        value,
        series: TimeSeries::Constant,
    });
    b.analysis(AnalysisSpec {
        kind: AnalysisKind::Static,
        ..Default::default()
    });
    let mut d = railfem::solvers::Driver::new(b.build().unwrap()).unwrap();
    d.static_solve(0.0, 1).unwrap();
    d
}

/// One classical Runge–Kutta (RK4) step of `y' = rhs(t, y)` from `t` to `t + h`, in place:
/// the independent time integration the modal references of the bridge tests use.
pub fn rk4_step(rhs: &dyn Fn(f64, &[f64]) -> Vec<f64>, t: f64, h: f64, y: &mut [f64]) {
    let k1 = rhs(t, y);
    let y2: Vec<f64> = y.iter().zip(&k1).map(|(a, k)| a + 0.5 * h * k).collect();
    let k2 = rhs(t + 0.5 * h, &y2);
    let y3: Vec<f64> = y.iter().zip(&k2).map(|(a, k)| a + 0.5 * h * k).collect();
    let k3 = rhs(t + 0.5 * h, &y3);
    let y4: Vec<f64> = y.iter().zip(&k3).map(|(a, k)| a + h * k).collect();
    let k4 = rhs(t + h, &y4);
    for k in 0..y.len() {
        y[k] += h / 6.0 * (k1[k] + 2.0 * k2[k] + 2.0 * k3[k] + k4[k]);
    }
}

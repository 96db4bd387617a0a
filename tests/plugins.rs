//! Dynamic plugins end to end: the example plugin `railfem-plugin-hysteretic` is built as a
//! cdylib by cargo from inside the test, loaded through a model file's `plugins` key, and
//! driven around a force-controlled hysteresis loop compared point by point with the closed
//! form; broken and foreign libraries are refused with clear messages; the CLI loads
//! plugins, refuses corrupt ones with exit code 2, and runs the conformance kit on them.

use railfem::framework::plugin::{self, PluginAbi};
use railfem::framework::{registry, FemError};
use railfem::solvers::Driver;
use std::path::{Path, PathBuf};
use std::process::Command;

mod common;
use common::plugin_lib;

fn tmp(name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("plugins")
        .join(name);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// A file of pseudo-random bytes with a shared-library name.
fn corrupt_lib() -> PathBuf {
    let p = tmp("corrupt").join("libcorrupt_plugin.so");
    let mut x: u64 = 0x9e37_79b9_7f4a_7c15;
    let bytes: Vec<u8> = (0..4096)
        .map(|_| {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            (x >> 24) as u8
        })
        .collect();
    std::fs::write(&p, bytes).unwrap();
    p
}

const K: f64 = 2.0e6;
const FY: f64 = 1.5e3;
const ALPHA: f64 = 0.05;
/// Force reversal points (N) of the load path, at t = 1, 2, 3, 4 s; linear in between.
const PEAKS: [f64; 4] = [2.0 * FY, -2.5 * FY, 3.0 * FY, -FY];

fn model_text(plugin: Option<&Path>) -> String {
    let plugins = plugin
        .map(|p| format!("plugins = [{:?}]\n", p.display().to_string()))
        .unwrap_or_default();
    let pts: Vec<String> = std::iter::once("[0.0, 0.0]".to_string())
        .chain(
            PEAKS
                .iter()
                .enumerate()
                .map(|(i, f)| format!("[{}.0, {f:e}]", i + 1)),
        )
        .collect();
    format!(
        r#"{plugins}
[analysis]
kind = "static"
steps = 1
[analysis.newton]
tol = 1e-12
abs_tol = 0.0

[[node]]
id = 1
xyz = [0.0, 0.0, 0.0]
fix = "all"

[[node]]
id = 2
xyz = [1.0, 0.0, 0.0]
fix = ["uy", "uz", "rx", "ry", "rz"]

[[element]]
type = "hysteretic_spring"
id = 1
nodes = [1, 2]
dof = "ux"
k = {K:e}
fy = {FY:e}
alpha = {ALPHA}

[[load]]
type = "nodal"
node = 2
dof = "ux"
value = 1.0
series = {{ type = "table", points = [{}] }}
"#,
        pts.join(", ")
    )
}

/// The applied force at time `t` (N): piecewise linear through 0 and [`PEAKS`].
fn applied(t: f64) -> f64 {
    let k = (t.floor() as usize).min(3);
    let f0 = if k == 0 { 0.0 } else { PEAKS[k - 1] };
    f0 + (PEAKS[k] - f0) * (t - k as f64)
}

/// Closed-form displacement of the bilinear kinematic-hardening spring under the force
/// path, at time `t`.
///
/// Derivation. Plastic states satisfy `|F − β| = fy` with `F = k(u − u_p)`,
/// `β = H·u_p`, `H = αk/(1 − α)`; eliminating `u_p` gives the bounding lines
/// `F = αk·u ± (1 − α)·fy`, so on a plastic branch `u = (F ∓ (1 − α)fy)/(αk)`. Inside the
/// elastic range `dF = k·du`. The elastic range is `|F − β| ≤ fy`, `2fy` wide: from the
/// origin the first yield is at `|F| = fy`; after a reversal at `(u_r, F_r)` from a plastic
/// state on the line of sign `s`, the spring unloads elastically, `u = u_r + (F − F_r)/k`,
/// until `F = F_r − 2s·fy`, where that elastic line meets the opposite bounding line
/// (`F_r + k·Δu = αk(u_r + Δu) − s(1 − α)fy` ⇔ `Δu = −2s·fy/k`), and then follows it.
/// Every peak of [`PEAKS`] lies beyond the previous elastic range, so each reversal starts
/// from a plastic state and these two rules give the whole path.
fn closed_form(t: f64) -> f64 {
    let f = applied(t);
    let line = |f: f64, s: f64| (f - s * (1.0 - ALPHA) * FY) / (ALPHA * K);
    let seg = (t.ceil() as usize).clamp(1, 4) - 1;
    if seg == 0 {
        return if f.abs() <= FY {
            f / K
        } else {
            line(f, f.signum())
        };
    }
    // Reversal at the end of the previous segment, on the line of that peak's sign.
    let fr = PEAKS[seg - 1];
    let s = fr.signum();
    let ur = line(fr, s);
    if s * (fr - f) <= 2.0 * FY {
        ur + (f - fr) / K
    } else {
        line(f, -s)
    }
}

/// Force-controlled cycles through the model file: at every 1/40 s of the load path the
/// static equilibrium from the last committed state matches the closed form to 1e-9 (the
/// Newton iterations on a piecewise-linear law end exactly on the right branch, so only
/// round-off remains), and the element's force equals the applied force.
#[test]
fn hysteresis_loop_matches_the_closed_form() {
    let dir = tmp("loop");
    let model = dir.join("loop.toml");
    std::fs::write(&model, model_text(Some(plugin_lib()))).unwrap();
    let m = railfem::load_model(&model).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(m.plugins.len(), 1);
    let mut d = Driver::new(m).unwrap();
    let uy = FY / K;
    let mut worst_u: f64 = 0.0;
    let mut worst_f: f64 = 0.0;
    let mut yielded_back = false;
    for i in 1..=160 {
        let t = i as f64 / 40.0;
        d.static_solve(t, 1)
            .unwrap_or_else(|e| panic!("t = {t}: {e}"));
        let u = d.displacement(2, railfem::framework::Dof::Ux).unwrap();
        let exact = closed_form(t);
        worst_u = worst_u.max((u - exact).abs() / exact.abs().max(uy));
        let mut out = Vec::new();
        d.model.elements[0].element.outputs(&mut out);
        let f = applied(t);
        worst_f = worst_f.max((out[0] - f).abs() / f.abs().max(FY));
        if t > 2.0 && t < 3.0 && out[2] < 0.0 {
            yielded_back = true;
        }
    }
    assert!(yielded_back, "the loop never yielded in reverse");
    assert!(worst_u < 1e-9, "displacement vs closed form: {worst_u:e}");
    assert!(
        worst_f < 1e-9,
        "element force vs applied force: {worst_f:e}"
    );
    // The dissipated energy after the full path: fy·Σ|Δu_p| with u_p = u − F/k at the
    // reversal points and the end (each branch is monotone in u_p).
    let up = |t: f64| closed_form(t) - applied(t) / K;
    let mut total = 0.0;
    let mut prev = 0.0;
    for t in [1.0, 2.0, 3.0, 4.0] {
        total += FY * (up(t) - prev).abs();
        prev = up(t);
    }
    let dissipated = d.model.elements[0].element.dissipated_energy();
    assert!(
        (dissipated - total).abs() < 1e-9 * total,
        "{dissipated} vs {total}"
    );
}

/// Loading the same file again is a no-op, and the loaded kind passes the conformance kit
/// through the plugin boundary (every call goes through the panic guard).
#[test]
fn loaded_plugin_is_registered_once_and_conforms() {
    plugin::load(plugin_lib()).unwrap();
    plugin::load(plugin_lib()).unwrap();
    let n = registry::kinds()
        .iter()
        .filter(|k| k.name == "hysteretic_spring")
        .count();
    assert_eq!(n, 1);
    let report = railfem::framework::conformance::check_all(Some("hysteretic_spring"));
    assert!(report.passed(), "{}", report.table());
    assert!(report.results.len() >= 8 * 4, "{}", report.table());
}

/// Random bytes with a `.so` name are refused with the path in a one-line message.
#[test]
fn corrupt_library_is_refused_with_its_path() {
    let p = corrupt_lib();
    let e = plugin::load(&p).unwrap_err();
    let m = e.to_string();
    assert!(matches!(e, FemError::Plugin(_)), "{e:?}");
    assert!(m.contains(&p.display().to_string()), "{m}");
    // On ELF systems the header check refuses it before dlopen; elsewhere the loader does.
    let why = if cfg!(any(target_os = "macos", windows)) {
        "not a loadable shared library"
    } else {
        "not an ELF file"
    };
    assert!(m.contains(why), "{m}");
    assert!(!m.contains('\n'), "{m}");
}

/// A library without the stamp (here: the C library) is not a railfem plugin.
#[test]
fn library_without_stamp_is_refused() {
    let libm = ["/lib/x86_64-linux-gnu/libm.so.6", "/usr/lib/libm.so.6"]
        .iter()
        .map(Path::new)
        .find(|p| p.exists());
    let Some(libm) = libm else { return };
    let m = plugin::load(libm).unwrap_err().to_string();
    assert!(m.contains("not a railfem plugin"), "{m}");
    assert!(m.contains("RAILFEM_PLUGIN_ABI"), "{m}");
}

/// A forged stamp (another compiler, another framework version) is refused with what the
/// plugin was built with, what this railfem is, and what to rebuild with.
#[test]
fn mismatched_stamp_is_refused_with_a_clear_message() {
    let mut forged = PluginAbi::CURRENT;
    forged.rustc_version = plugin::fixed("rustc 1.70.0 (90c541806 2023-05-31)");
    forged.framework_version = plugin::fixed("0.0.1");
    let p = Path::new("/plugins/libold.so");
    let m = plugin::check_stamp(p, &forged).unwrap_err().to_string();
    let host = PluginAbi::CURRENT;
    assert!(
        m.starts_with("plugin: /plugins/libold.so: built with framework 0.0.1 / rustc 1.70.0"),
        "{m}"
    );
    assert!(
        m.contains(&format!(
            "but this railfem is framework {} / {}",
            host.framework_version(),
            host.rustc_version()
        )),
        "{m}"
    );
    assert!(m.contains("rebuild the plugin with"), "{m}");
    let mut other_target = PluginAbi::CURRENT;
    other_target.target = plugin::fixed("riscv64gc-unknown-linux-gnu");
    assert!(plugin::check_stamp(p, &other_target).is_err());
    assert!(plugin::check_stamp(p, &PluginAbi::CURRENT).is_ok());
}

fn railfem() -> Command {
    Command::new(env!("CARGO_BIN_EXE_railfem"))
}

/// `railfem run MODEL --plugin PATH` runs a model whose element type only the plugin
/// provides; a corrupt plugin exits 2 with one line on stderr naming the file.
#[test]
fn cli_loads_plugins_and_refuses_corrupt_ones() {
    let dir = tmp("cli");
    let model = dir.join("cli.toml");
    std::fs::write(&model, model_text(None)).unwrap();
    let out = railfem()
        .arg("run")
        .arg(&model)
        .arg("--plugin")
        .arg(plugin_lib())
        .arg("--out")
        .arg(dir.join("out"))
        .output()
        .unwrap();
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );

    let bad = corrupt_lib();
    let out = railfem()
        .arg("run")
        .arg(&model)
        .arg("--plugin")
        .arg(&bad)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    assert!(err.contains(&bad.display().to_string()), "{err}");
}

/// `railfem conformance --plugin PATH --element NAME` prints the table and exits 0.
#[test]
fn cli_conformance_runs_the_kit_on_a_plugin() {
    let out = railfem()
        .arg("conformance")
        .arg("--plugin")
        .arg(plugin_lib())
        .arg("--element")
        .arg("hysteretic")
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(0), "{text}");
    assert!(text.contains("hysteretic_spring / yielding"), "{text}");
    assert!(text.contains("0 failed"), "{text}");
}

/// A 100 kg mass on the plugin's hysteretic spring, driven through the same force path in
/// a transient run (10 Hz elastic, the path's 1 s legs are quasi-static with ringing). The
/// energy ledger books the spring's dissipation under `material`, never `friction`, and
/// what it keeps as stored energy (the trapezoidal work of the spring force minus the
/// reported dissipation) equals the closed form `F²/(2k) + β²/(2H)` of the spring's elastic
/// and hardening energies (the module doc of the plugin), from its final force `F` and back
/// force `β`. The trapezoidal rule is exact on each linear branch; only the steps that
/// cross a yield point carry an error, of order `(k − αk)·Δu²` per crossing, so the two
/// agree to 1e-3 of the dissipated energy with 1 ms steps.
#[test]
fn energy_ledger_books_plastic_dissipation_as_material() {
    let dir = tmp("ledger");
    let model = dir.join("ledger.toml");
    let text = model_text(Some(plugin_lib())).replace(
        "[analysis]\nkind = \"static\"\nsteps = 1\n",
        "[analysis]\nkind = \"transient\"\ndt = 0.001\nduration = 4.0\ninitial_static = false\n",
    )
    // The static loop's 1e-12 with no absolute floor is below a transient residual's
    // round-off: the default convergence test.
    .replace("[analysis.newton]\ntol = 1e-12\nabs_tol = 0.0\n", "") + "\n[[element]]\ntype = \"mass\"\nid = 2\nnodes = [2]\nm = 100.0\n";
    std::fs::write(&model, text).unwrap();
    let m = railfem::load_model(&model).unwrap_or_else(|e| panic!("{e}"));
    let mut d = Driver::new(m).unwrap();
    d.run(None, &mut |_| {}).unwrap_or_else(|e| panic!("{e}"));
    let ledger = d.energy.as_ref().expect("a transient run keeps the ledger");
    let r = ledger.totals();
    assert_eq!(
        r.friction, 0.0,
        "a material law's dissipation booked as friction"
    );
    let mut out = Vec::new();
    d.model.elements[0].element.outputs(&mut out);
    let (force, back, dissipated) = (out[0], out[3], out[4]);
    assert!(
        dissipated > 10.0 * FY * FY / K,
        "the run should yield repeatedly: {dissipated} J"
    );
    assert!(
        (r.material - dissipated).abs() <= 1e-12 * dissipated,
        "ledger material {} J vs the element's {dissipated} J",
        r.material
    );
    let h = ALPHA * K / (1.0 - ALPHA);
    let stored = force * force / (2.0 * K) + back * back / (2.0 * h);
    assert!(
        (r.strain - stored).abs() <= 1e-3 * dissipated,
        "stored energy: ledger {} J vs closed form {stored} J (dissipated {dissipated} J)",
        r.strain
    );
}

/// A 50 kg rotor mass on springs in uy and uz (different stiffnesses), driven by
/// `m·e·ω²` rotating in the uz–uy plane.
fn unbalance_model(loads: &str, recorders: &str) -> String {
    format!(
        r#"
[analysis]
kind = "transient"
dt = 1e-3
duration = 0.5
initial_static = false

[[node]]
id = 1
xyz = [0.0, 0.0, 0.0]
fix = "all"

[[node]]
id = 2
xyz = [0.0, 0.0, 0.0]
fix = ["ux", "rx", "ry", "rz"]

[[element]]
type = "mass"
id = 1
nodes = [2]
m = 50.0

[[element]]
type = "spring_damper"
id = 2
nodes = [1, 2]
k = [0.0, 2.0e6, 3.0e6, 0.0, 0.0, 0.0]
c = [0.0, 400.0, 500.0, 0.0, 0.0, 0.0]

{loads}

[[recorder]]
type = "node"
nodes = [1, 2]
dofs = ["uy", "uz"]
quantity = "vel"
file = "node.csv"
{recorders}
"#
    )
}

/// Reads a CSV of numbers written by a recorder: header and rows.
fn read_numbers(path: &Path) -> (Vec<String>, Vec<Vec<f64>>) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header = lines
        .next()
        .unwrap()
        .split(',')
        .map(str::to_string)
        .collect();
    let rows = lines
        .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
        .collect();
    (header, rows)
}

/// The plugin's load and recorder kinds, used from a model file: `rotating_unbalance`
/// applies `F_z = m·e·ω²·cos(ωt + φ)`, `F_y = m·e·ω²·sin(ωt + φ)`, the same forces as two
/// built-in nodal loads with sine series of amplitude `m·e·ω²`, frequency `ω/2π` and phases
/// `φ + π/2` and `φ` (cos x = sin(x + π/2)); the two runs' velocities agree to round-off
/// (1e-9 of the peak: the series differ in the last bits only). The `relative_motion`
/// recorder's `2_1_duz` column is the difference of the node recorder's `2_uz` and `1_uz`
/// columns (node 1 is fixed, so `2_uz` itself), to the CSV's 13 significant digits.
/// `railfem loads` and `railfem recorders` list the plugin's kinds with their keys.
#[test]
fn plugin_load_and_recorder_kinds_run_from_a_model_file() {
    let (me, omega, phase) = (0.02, 120.0, 0.3);
    let amp = me * omega * omega;
    let dir = tmp("load-recorder");
    let plugin = format!(
        r#"[[load]]
type = "rotating_unbalance"
node = 2
me = {me}
omega = {omega}
phase = {phase}
"#
    );
    let relative = r#"
[[recorder]]
type = "relative_motion"
from = 1
to = 2
dofs = ["uz", "uy"]
quantity = "vel"
file = "relative.csv"
"#;
    let f = omega / (2.0 * std::f64::consts::PI);
    let builtin = format!(
        r#"[[load]]
type = "nodal"
node = 2
dof = "uz"
value = {amp:e}
series = {{ type = "sine", frequency = {f:e}, phase = {:e} }}

[[load]]
type = "nodal"
node = 2
dof = "uy"
value = {amp:e}
series = {{ type = "sine", frequency = {f:e}, phase = {phase:e} }}
"#,
        phase + std::f64::consts::FRAC_PI_2
    );
    let run = |name: &str, text: String| {
        let model = dir.join(format!("{name}.toml"));
        std::fs::write(&model, text).unwrap();
        let out_dir = dir.join(name);
        let out = railfem()
            .arg("run")
            .arg(&model)
            .arg("--plugin")
            .arg(plugin_lib())
            .arg("--out")
            .arg(&out_dir)
            .output()
            .unwrap();
        assert_eq!(
            out.status.code(),
            Some(0),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        out_dir
    };
    let a = run("plugin", unbalance_model(&plugin, relative));
    let b = run("builtin", unbalance_model(&builtin, ""));
    let (ha, ra) = read_numbers(&a.join("node.csv"));
    let (hb, rb) = read_numbers(&b.join("node.csv"));
    assert_eq!(ha, hb);
    assert_eq!(ra.len(), 501);
    let peak = ra
        .iter()
        .flat_map(|r| r[1..].iter())
        .fold(0.0f64, |m, x| m.max(x.abs()));
    // The rotor is driven near neither resonance; the velocity peaks are millimetres per
    // second, so a dropped or mis-signed component would show at order 1 of the peak.
    assert!(peak > 1e-3, "peak velocity {peak}");
    for (x, y) in ra.iter().zip(&rb) {
        for (u, v) in x.iter().zip(y) {
            assert!((u - v).abs() <= 1e-9 * peak, "{u} vs {v}");
        }
    }
    let (hr, rr) = read_numbers(&a.join("relative.csv"));
    assert_eq!(hr, ["time [s]", "2_1_duz [m/s]", "2_1_duy [m/s]"]);
    let col = |h: &[String], name: &str| h.iter().position(|c| c == name).unwrap();
    let (y1, y2, z1, z2) = (
        col(&ha, "1_uy [m/s]"),
        col(&ha, "2_uy [m/s]"),
        col(&ha, "1_uz [m/s]"),
        col(&ha, "2_uz [m/s]"),
    );
    for (r, n) in rr.iter().zip(&ra) {
        assert_eq!(r[0], n[0]);
        assert!(
            (r[1] - (n[z2] - n[z1])).abs() <= 1e-12 * peak,
            "{r:?} {n:?}"
        );
        assert!(
            (r[2] - (n[y2] - n[y1])).abs() <= 1e-12 * peak,
            "{r:?} {n:?}"
        );
    }

    for (cmd, kind, key) in [
        ("loads", "rotating_unbalance", "omega"),
        ("recorders", "relative_motion", "quantity"),
    ] {
        let out = railfem()
            .arg(cmd)
            .arg("--plugin")
            .arg(plugin_lib())
            .output()
            .unwrap();
        let text = String::from_utf8_lossy(&out.stdout);
        assert_eq!(out.status.code(), Some(0), "{text}");
        assert!(text.contains(kind) && text.contains(key), "{text}");
    }
}

/// A plugin load kind's bad key, and an unknown load type, are refused with exit 2 and
/// one line naming the file, the entry and the fix.
#[test]
fn plugin_load_bad_input_is_one_line() {
    let dir = tmp("load-bad");
    for (name, load, want) in [
        (
            "axes",
            "type = \"rotating_unbalance\"\nnode = 2\nme = 0.1\nomega = 10.0\naxes = [\"uz\", \"uw\"]",
            "axes",
        ),
        (
            "missing",
            "type = \"rotating_unbalance\"\nnode = 2\nomega = 10.0",
            "missing key `me`",
        ),
        (
            "unknown",
            "type = \"rotating_unbalence\"\nnode = 2",
            "rotating_unbalance",
        ),
    ] {
        let model = dir.join(format!("{name}.toml"));
        std::fs::write(&model, unbalance_model(&format!("[[load]]\n{load}\n"), "")).unwrap();
        let out = railfem()
            .arg("check")
            .arg(&model)
            .arg("--plugin")
            .arg(plugin_lib())
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{name}: {err}");
        assert_eq!(err.trim_end().lines().count(), 1, "{name}: {err}");
        assert!(err.contains(&format!("{name}.toml")) && err.contains("load[0]"), "{name}: {err}");
        assert!(err.contains(want), "{name}: {err}");
    }
}

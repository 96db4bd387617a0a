//! The framework core against closed forms: a one-element cantilever (static), the
//! frequencies of a simply supported beam (modal), a force crossing a simply supported
//! beam (transient, Newmark), and a model built in Rust, read from TOML and read from JSON
//! giving bitwise-identical results.
//!
//! Every reference value is derived in the doc comment of its test; none is produced by the
//! code under test.

mod common;

use railfem::framework::builder::ModelBuilder;
use railfem::framework::loads::{LoadSpec, TimeSeries};
use railfem::framework::model::AnalysisSpec;
use railfem::framework::recorder::{Quantity, RecorderSpec};
use railfem::framework::{Dof, DofSet};
use railfem::solvers::modal::{lowest_modes, ModalOptions};
use railfem::solvers::Driver;
use serde_json::json;
use std::f64::consts::PI;

/// Section of the cantilever: a 60E1-like rail section, steel (SI units).
const E: f64 = 2.1e11;
const G: f64 = 8.1e10;
const A: f64 = 7.686e-3;
const IY: f64 = 3.038e-5;
const IZ: f64 = 5.123e-6;
const J: f64 = 2.0e-6;
const L: f64 = 2.5;

fn beam_params() -> serde_json::Value {
    json!({"E": E, "G": G, "A": A, "Iy": IY, "Iz": IZ, "J": J})
}

/// Solves the one-element cantilever (node 1 clamped at the origin, node 2 free at
/// `(L, 0, 0)`) statically under one nodal load on node 2; returns the six tip DOFs.
fn cantilever_tip(dof: Dof, value: f64) -> [f64; 6] {
    let mut b = ModelBuilder::new("cantilever");
    b.node_fixed(1, [0.0; 3], DofSet::ALL);
    b.node(2, [L, 0.0, 0.0]);
    b.element("beam3d", 1, &[1, 2], &beam_params());
    b.load(LoadSpec::Nodal {
        node: 2,
        dof,
        value,
        series: TimeSeries::Constant,
    });
    b.analysis(AnalysisSpec {
        kind: railfem::framework::model::AnalysisKind::Static,
        ..Default::default()
    });
    let mut d = Driver::new(b.build().expect("model")).expect("driver");
    d.static_solve(0.0, 1).expect("static solve");
    std::array::from_fn(|k| d.displacement(2, Dof::ALL[k]).expect("node 2"))
}

fn assert_rel(got: f64, want: f64, tol: f64, what: &str) {
    let err = (got - want).abs() / want.abs();
    assert!(
        err <= tol,
        "{what}: got {got:e}, want {want:e}, relative error {err:e} > {tol:e}"
    );
}

/// All six tip DOFs other than the ones listed must stay zero (to round-off relative to
/// the largest tip value): the planes do not couple.
fn assert_only(tip: &[f64; 6], nonzero: &[usize], what: &str) {
    let scale = tip.iter().fold(0.0f64, |a, x| a.max(x.abs()));
    for (k, v) in tip.iter().enumerate() {
        if !nonzero.contains(&k) {
            assert!(
                v.abs() <= 1e-12 * scale,
                "{what}: DOF {k} = {v:e} should be 0"
            );
        }
    }
}

/// Cantilever of length L clamped at x = 0, one `beam3d` element, static.
///
/// Euler–Bernoulli: `EI·w'''' = 0` on the span, so `w` is a cubic. Clamped: `w(0) = w'(0) = 0`.
/// * Tip force P (transverse): bending moment `M(x) = P·(L − x)`, `EI·w'' = P·(L − x)`,
///   integrating twice with the clamped conditions: `w'(x) = P·(L·x − x²/2)/(EI)`,
///   `w(x) = P·(L·x²/2 − x³/6)/(EI)`, so `w(L) = PL³/(3EI)` and `w'(L) = PL²/(2EI)`.
/// * Tip moment M: `EI·w'' = M` (constant), `w'(L) = ML/(EI)`, `w(L) = ML²/(2EI)`.
/// * Axial force P: `EA·u' = P`, `u(L) = PL/(EA)`. Torque T: `GJ·θ' = T`, `θ(L) = TL/(GJ)`.
///
/// The cubic Hermite element contains every cubic, so one element reproduces these exactly
/// and the only error is round-off of a 6×6 solve (condition number of K ≈
/// (EA/L)/(EIz/L³)·const ≈ 1e7 here, so about 1e-9 at worst; the observed error is ~1e-15).
///
/// Signs: the beam lies along global X, so with the default orientation local y = global
/// Y and local z = global Z. Bending in the X-Y plane (`uy`, `rz = +dv/dx`) uses Iz;
/// bending in the X-Z plane (`uz`, `ry = −dw/dx`, right-hand rule) uses Iy. A tip moment
/// `My` therefore bends the tip to `−Z`: `uz = −My·L²/(2EIy)`, `ry = My·L/(EIy)`.
#[test]
fn cantilever_one_element_matches_euler_bernoulli() {
    let tol = 1e-9;
    let p = 1.0e4; // N
    let mo = 2.0e3; // N·m
                    // Force along Z: bending in X-Z with Iy.
    let t = cantilever_tip(Dof::Uz, p);
    assert_rel(t[2], p * L.powi(3) / (3.0 * E * IY), tol, "uz under Pz");
    assert_rel(t[4], -p * L * L / (2.0 * E * IY), tol, "ry under Pz");
    assert_only(&t, &[2, 4], "Pz");
    // Force along Y: bending in X-Y with Iz.
    let t = cantilever_tip(Dof::Uy, p);
    assert_rel(t[1], p * L.powi(3) / (3.0 * E * IZ), tol, "uy under Py");
    assert_rel(t[5], p * L * L / (2.0 * E * IZ), tol, "rz under Py");
    assert_only(&t, &[1, 5], "Py");
    // Moment about Y.
    let t = cantilever_tip(Dof::Ry, mo);
    assert_rel(t[4], mo * L / (E * IY), tol, "ry under My");
    assert_rel(t[2], -mo * L * L / (2.0 * E * IY), tol, "uz under My");
    assert_only(&t, &[2, 4], "My");
    // Moment about Z.
    let t = cantilever_tip(Dof::Rz, mo);
    assert_rel(t[5], mo * L / (E * IZ), tol, "rz under Mz");
    assert_rel(t[1], mo * L * L / (2.0 * E * IZ), tol, "uy under Mz");
    assert_only(&t, &[1, 5], "Mz");
    // Axial force and torque.
    let t = cantilever_tip(Dof::Ux, p);
    assert_rel(t[0], p * L / (E * A), tol, "ux under Px");
    assert_only(&t, &[0], "Px");
    let t = cantilever_tip(Dof::Rx, mo);
    assert_rel(t[3], mo * L / (G * J), tol, "rx under T");
    assert_only(&t, &[3], "T");
}

/// The bridge of the moving-force test (Yang & Wu's 25 m span), SI units:
/// `EI = 2.943e10 N·m²`, `m = 2303 kg/m`, written as a steel-like section
/// (`A = 0.3 m²`, `Iy = 0.14 m⁴`, so `E = EI/Iy`, `ρ = m/A`).
mod bridge {
    pub const L: f64 = 25.0;
    pub const EI: f64 = 2.943e10;
    pub const MASS: f64 = 2303.0;
    pub const A: f64 = 0.3;
    pub const IY: f64 = 0.14;
    pub const E: f64 = EI / IY;
    pub const RHO: f64 = MASS / A;
}

/// A simply supported `beam3d` span of `ne` elements along X, nodes `0..=ne`, element
/// ids `1..=ne`, consistent mass. Supports: node 0 holds ux, uy, uz, rx (a pin that also
/// stops axial drift and twisting); node `ne` holds uy, uz (a roller). Out-of-plane
/// bending (uy, rz, Iz), torsion (rx) and axial motion (ux) are thereby supported but
/// free; `restrain_out_of_plane` additionally fixes ux, uy, rx, rz at every node so that
/// only vertical bending (uz, ry) remains.
fn simply_supported(ne: usize, restrain_out_of_plane: bool) -> ModelBuilder {
    use bridge::*;
    let mut b = ModelBuilder::new("simply supported beam");
    let out_of_plane = DofSet::of(&[Dof::Ux, Dof::Uy, Dof::Rx, Dof::Rz]);
    for i in 0..=ne {
        let mut fixed = if restrain_out_of_plane {
            out_of_plane
        } else {
            DofSet::NONE
        };
        if i == 0 {
            fixed = fixed.union(DofSet::of(&[Dof::Ux, Dof::Uy, Dof::Uz, Dof::Rx]));
        }
        if i == ne {
            fixed = fixed.union(DofSet::of(&[Dof::Uy, Dof::Uz]));
        }
        b.node_fixed(i as u64, [L * i as f64 / ne as f64, 0.0, 0.0], fixed);
    }
    let params = json!({"E": E, "G": E / 2.6, "A": A, "Iy": IY, "Iz": 2.0 * IY,
                        "J": 0.5 * IY, "rho": RHO, "mass": "consistent"});
    for i in 1..=ne {
        b.element("beam3d", i as u64, &[i as u64 - 1, i as u64], &params);
    }
    b
}

/// First three bending frequencies of a simply supported beam, 20 elements, consistent
/// mass, against Euler–Bernoulli.
///
/// Closed form: `EI·w'''' + m·ẅ = 0` with `w = sin(nπx/L)·e^{iωt}` (which satisfies
/// `w = w'' = 0` at both ends) gives `EI·(nπ/L)⁴ = m·ω²`, so `ω_n = (nπ/L)²·√(EI/m)`.
///
/// Only vertical bending is left free (ux, uy, rx, rz fixed at every node), so the three
/// lowest modes are n = 1, 2, 3 of that plane; without this the lateral modes (Iz) and
/// torsion would interleave. Tolerance 0.1%: the consistent-mass Hermite element
/// overestimates `ω_n` by O((nh/L)⁴); for n = 3 with 20 elements (6.7 elements per
/// half-wave) that is ~1e-5. The mode shapes are also checked against `sin(nπx/L)` by the
/// modal assurance criterion (MAC > 0.9999).
#[test]
fn simply_supported_frequencies_match_euler_bernoulli() {
    use bridge::*;
    let ne = 20;
    let b = simply_supported(ne, true);
    let d = Driver::new(b.build().expect("model")).expect("driver");
    let modes =
        lowest_modes(&d.asm.k_const, &d.asm.m_const, 3, &ModalOptions::default()).expect("modal");
    for n in 1..=3 {
        let exact = (n as f64 * PI / L).powi(2) * (EI / MASS).sqrt();
        let got = modes.omega[n - 1];
        let err = (got - exact).abs() / exact;
        eprintln!("mode {n}: omega = {got:.6} rad/s, exact {exact:.6}, rel. error {err:.3e}");
        assert!(err < 1e-3, "mode {n}: {got} vs {exact} ({err:e})");
        // Shape: uz at the nodes against sin(nπx/L).
        let (mut pp, mut ss, mut ps) = (0.0, 0.0, 0.0);
        for i in 0..=ne {
            let node = d.model.node(i as u64).expect("node");
            let phi = d
                .asm
                .dofmap
                .value(modes.shapes.column(n - 1).as_slice(), node, Dof::Uz);
            let s = (n as f64 * PI * i as f64 / ne as f64).sin();
            pp += phi * phi;
            ss += s * s;
            ps += phi * s;
        }
        let mac = ps * ps / (pp * ss);
        assert!(mac > 0.9999, "mode {n}: MAC with sin(nπx/L) = {mac}");
    }
}

/// Runs the moving force over the simply supported bridge with `ne` elements and step
/// `dt`; returns the largest difference of the midspan deflection from Frýba's series
/// over all steps with the force on the span, relative to the series' peak.
fn moving_force_error(ne: usize, dt: f64) -> f64 {
    use bridge::*;
    let (p, v) = (1.0e5, 27.78);
    let mut b = simply_supported(ne, false);
    b.load(LoadSpec::MovingForce {
        elements: (1..=ne as u64).collect(),
        force: [0.0, 0.0, -p],
        speed: v,
        start: 0.0,
    });
    b.analysis(AnalysisSpec {
        dt,
        duration: L / v,
        ..Default::default() // Newmark, β = 1/4, γ = 1/2
    });
    let mut d = Driver::new(b.build().expect("model")).expect("driver");
    d.initialize().expect("initialize");
    let mid = (ne / 2) as u64;
    let steps = ((L / v) / dt).floor() as usize;
    let mut worst: f64 = 0.0;
    let mut peak: f64 = 0.0;
    for _ in 0..steps {
        d.step(dt).expect("step");
        let t = d.state.t;
        // The force acts along −Z, Frýba's w is along the force.
        let fe = -d.displacement(mid, Dof::Uz).expect("midspan");
        let exact = common::fryba(L / 2.0, t, p, v, L, EI, MASS, 50);
        worst = worst.max((fe - exact).abs());
        peak = peak.max(exact.abs());
    }
    worst / peak
}

/// A constant force P crossing a simply supported span at speed v (Yang & Wu's bridge:
/// L = 25 m, EI = 2.943e10 N·m², m = 2303 kg/m, v = 27.78 m/s, P = 1e5 N), Newmark
/// average acceleration (β = ¼, γ = ½), the `moving_force` load on the beam elements.
///
/// Reference: Frýba's modal series, derived in [`common::fryba`], 50 terms. Here
/// `ω_1 = 56.45 rad/s` (T₁ = 0.1113 s), `ω = πv/L = 3.49 rad/s`, `α = ω/ω_1 = 0.062`;
/// the force is on the span for `L/v = 0.9 s`.
///
/// Error sources of the FE run: (i) space — with consistent (Hermite) nodal forces the
/// quasi-static part of the nodal deflection is exact, and the consistent mass errs by
/// O((h/λ)⁴) on the low modes; (ii) time — average acceleration lengthens the period by
/// `(ω₁Δt)²/12`, so the free-vibration part (amplitude α ≈ 6% of the static deflection)
/// drifts in phase by `(ω₁Δt)²/12·ω₁·t`. With 20 elements and `Δt = T₁/40` (2.78 ms) the
/// phase drift at t = 0.9 s is ≈ 0.13 rad, i.e. ≈ 0.8% of the peak at the very worst; the
/// measured error is smaller (see the assertion message). The tolerance is 1% of the peak.
///
/// Refinement: halving both h and Δt must reduce the error each time (the time error
/// dominates and falls as Δt²).
#[test]
fn moving_force_matches_fryba_series() {
    let t1 = 2.0 * PI / ((PI / bridge::L).powi(2) * (bridge::EI / bridge::MASS).sqrt());
    let runs = [(10, t1 / 20.0), (20, t1 / 40.0), (40, t1 / 80.0)];
    let errs: Vec<f64> = runs
        .iter()
        .map(|&(ne, dt)| moving_force_error(ne, dt))
        .collect();
    for ((ne, dt), e) in runs.iter().zip(&errs) {
        eprintln!("moving force: {ne} elements, dt = {dt:.3e} s: max error / peak = {e:.3e}");
    }
    assert!(
        errs[1] < 0.01,
        "20 elements, dt = T1/40: error {:.3e} of the peak (limit 1%)",
        errs[1]
    );
    assert!(
        errs[0] > errs[1] && errs[1] > errs[2],
        "error must fall with refinement: {errs:?}"
    );
}

/// The model of the file-equivalence test, as a builder: a two-span continuous beam
/// (4 `beam3d`), a `mass` and a grounded `spring_damper` under the middle of the first
/// span, a sine nodal load and a moving force, with a node and an element recorder.
fn equivalence_builder() -> ModelBuilder {
    let mut b = ModelBuilder::new("builder");
    b.node_fixed(
        1,
        [0.0, 0.0, 0.0],
        DofSet::of(&[Dof::Ux, Dof::Uy, Dof::Uz, Dof::Rx]),
    );
    b.node(2, [3.3, 0.0, 0.0]);
    b.node_fixed(3, [6.6, 0.0, 0.0], DofSet::of(&[Dof::Uy, Dof::Uz]));
    b.node(4, [9.9, 0.0, 0.0]);
    b.node_fixed(5, [13.2, 0.0, 0.0], DofSet::of(&[Dof::Uy, Dof::Uz]));
    let beam = json!({"E": 2.1e11, "G": 8.1e10, "A": 7.686e-3, "Iy": 3.038e-5,
                      "Iz": 5.123e-6, "J": 2.0e-6, "rho": 7850.0});
    for i in 1..=4u64 {
        b.element("beam3d", i, &[i, i + 1], &beam);
    }
    b.element(
        "mass",
        10,
        &[2],
        &json!({"m": 350.7, "inertia": [1.1, 2.2, 3.3]}),
    );
    b.element(
        "spring_damper",
        11,
        &[2],
        &json!({"k": [0.0, 0.0, 1.7e7, 0.0, 0.0, 0.0], "c": [0.0, 0.0, 3.1e4, 0.0, 0.0, 0.0]}),
    );
    b.load(LoadSpec::Nodal {
        node: 4,
        dof: railfem::framework::Dof::Uz,
        value: -1234.5,
        series: TimeSeries::Sine {
            amplitude: 1.0,
            frequency: 7.3,
            phase: 0.1,
        },
    });
    b.load(LoadSpec::MovingForce {
        elements: vec![1, 2, 3, 4],
        force: [0.0, 0.0, -9.81e4],
        speed: 33.3,
        start: 0.0,
    });
    b.recorder(RecorderSpec::Node {
        node: None,
        nodes: vec![2, 4],
        dofs: DofSet::of(&[Dof::Uz, Dof::Ry]),
        quantity: Quantity::Disp,
        file: "nodes.csv".into(),
    });
    b.recorder(RecorderSpec::Element {
        element: Some(1),
        elements: vec![],
        kind: None,
        outputs: vec![],
        file: "beam1.csv".into(),
    });
    b.analysis(AnalysisSpec {
        dt: 1.0e-3,
        duration: 0.05,
        ..Default::default()
    });
    b
}

const EQUIVALENCE_TOML: &str = r#"
[analysis]
kind = "transient"
dt = 1.0e-3
duration = 0.05

[[node]]
id = 1
xyz = [0.0, 0.0, 0.0]
fix = ["ux", "uy", "uz", "rx"]
[[node]]
id = 2
xyz = [3.3, 0.0, 0.0]
[[node]]
id = 3
xyz = [6.6, 0.0, 0.0]
fix = ["uy", "uz"]
[[node]]
id = 4
xyz = [9.9, 0.0, 0.0]
[[node]]
id = 5
xyz = [13.2, 0.0, 0.0]
fix = ["uy", "uz"]

[[element]]
type = "beam3d"
id = 1
nodes = [1, 2]
E = 2.1e11
G = 8.1e10
A = 7.686e-3
Iy = 3.038e-5
Iz = 5.123e-6
J = 2.0e-6
rho = 7850.0
[[element]]
type = "beam3d"
id = 2
nodes = [2, 3]
E = 2.1e11
G = 8.1e10
A = 7.686e-3
Iy = 3.038e-5
Iz = 5.123e-6
J = 2.0e-6
rho = 7850.0
[[element]]
type = "beam3d"
id = 3
nodes = [3, 4]
E = 2.1e11
G = 8.1e10
A = 7.686e-3
Iy = 3.038e-5
Iz = 5.123e-6
J = 2.0e-6
rho = 7850.0
[[element]]
type = "beam3d"
id = 4
nodes = [4, 5]
E = 2.1e11
G = 8.1e10
A = 7.686e-3
Iy = 3.038e-5
Iz = 5.123e-6
J = 2.0e-6
rho = 7850.0
[[element]]
type = "mass"
id = 10
nodes = [2]
m = 350.7
inertia = [1.1, 2.2, 3.3]
[[element]]
type = "spring_damper"
id = 11
nodes = [2]
k = [0.0, 0.0, 1.7e7, 0.0, 0.0, 0.0]
c = [0.0, 0.0, 3.1e4, 0.0, 0.0, 0.0]

[[load]]
type = "nodal"
node = 4
dof = "uz"
value = -1234.5
series = { type = "sine", amplitude = 1.0, frequency = 7.3, phase = 0.1 }
[[load]]
type = "moving_force"
elements = [1, 2, 3, 4]
force = [0.0, 0.0, -9.81e4]
speed = 33.3

[[recorder]]
type = "node"
nodes = [2, 4]
dofs = ["uz", "ry"]
file = "nodes.csv"
[[recorder]]
type = "element"
element = 1
file = "beam1.csv"
"#;

/// The same model as JSON (written by hand, not converted by the code under test).
const EQUIVALENCE_JSON: &str = r#"{
  "analysis": {"kind": "transient", "dt": 1.0e-3, "duration": 0.05},
  "node": [
    {"id": 1, "xyz": [0.0, 0.0, 0.0], "fix": ["ux", "uy", "uz", "rx"]},
    {"id": 2, "xyz": [3.3, 0.0, 0.0]},
    {"id": 3, "xyz": [6.6, 0.0, 0.0], "fix": ["uy", "uz"]},
    {"id": 4, "xyz": [9.9, 0.0, 0.0]},
    {"id": 5, "xyz": [13.2, 0.0, 0.0], "fix": ["uy", "uz"]}
  ],
  "element": [
    {"type": "beam3d", "id": 1, "nodes": [1, 2], "E": 2.1e11, "G": 8.1e10, "A": 7.686e-3,
     "Iy": 3.038e-5, "Iz": 5.123e-6, "J": 2.0e-6, "rho": 7850.0},
    {"type": "beam3d", "id": 2, "nodes": [2, 3], "E": 2.1e11, "G": 8.1e10, "A": 7.686e-3,
     "Iy": 3.038e-5, "Iz": 5.123e-6, "J": 2.0e-6, "rho": 7850.0},
    {"type": "beam3d", "id": 3, "nodes": [3, 4], "E": 2.1e11, "G": 8.1e10, "A": 7.686e-3,
     "Iy": 3.038e-5, "Iz": 5.123e-6, "J": 2.0e-6, "rho": 7850.0},
    {"type": "beam3d", "id": 4, "nodes": [4, 5], "E": 2.1e11, "G": 8.1e10, "A": 7.686e-3,
     "Iy": 3.038e-5, "Iz": 5.123e-6, "J": 2.0e-6, "rho": 7850.0},
    {"type": "mass", "id": 10, "nodes": [2], "m": 350.7, "inertia": [1.1, 2.2, 3.3]},
    {"type": "spring_damper", "id": 11, "nodes": [2],
     "k": [0.0, 0.0, 1.7e7, 0.0, 0.0, 0.0], "c": [0.0, 0.0, 3.1e4, 0.0, 0.0, 0.0]}
  ],
  "load": [
    {"type": "nodal", "node": 4, "dof": "uz", "value": -1234.5,
     "series": {"type": "sine", "amplitude": 1.0, "frequency": 7.3, "phase": 0.1}},
    {"type": "moving_force", "elements": [1, 2, 3, 4], "force": [0.0, 0.0, -9.81e4],
     "speed": 33.3}
  ],
  "recorder": [
    {"type": "node", "nodes": [2, 4], "dofs": ["uz", "ry"], "file": "nodes.csv"},
    {"type": "element", "element": 1, "file": "beam1.csv"}
  ]
}"#;

/// Runs a model's transient with its recorders into `out`; returns the final state.
fn run_to(model: railfem::framework::Model, out: &std::path::Path) -> railfem::solvers::State {
    let mut d = Driver::new(model).expect("driver");
    d.run(Some(out), &mut |_| {}).expect("run");
    d.state
}

/// Builder, TOML file and JSON file describe the same model; the three runs (50 Newmark
/// steps with a moving force, a sine load, a mass and a damper) must agree bit for bit —
/// in the final state vectors (compared as `f64::to_bits`) and in every byte of the
/// recorder files. Any difference would mean a number was parsed or ordered differently.
#[test]
fn builder_toml_and_json_give_identical_results() {
    let dir = common::temp_dir("equivalence");
    let toml_path = dir.join("model.toml");
    let json_path = dir.join("model.json");
    std::fs::write(&toml_path, EQUIVALENCE_TOML).expect("write toml");
    std::fs::write(&json_path, EQUIVALENCE_JSON).expect("write json");
    let s_builder = run_to(
        equivalence_builder().build().expect("builder"),
        &dir.join("b"),
    );
    let s_toml = run_to(
        railfem::load_model(&toml_path).expect("toml"),
        &dir.join("t"),
    );
    let s_json = run_to(
        railfem::load_model(&json_path).expect("json"),
        &dir.join("j"),
    );
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<u64>>();
    assert!(s_builder.t > 0.049, "the run must reach its end");
    assert!(
        s_builder.q.iter().any(|x| x.abs() > 1e-6),
        "the run must actually move"
    );
    for (name, s) in [("toml", &s_toml), ("json", &s_json)] {
        assert_eq!(s.t.to_bits(), s_builder.t.to_bits(), "{name}: time");
        assert_eq!(bits(&s.q), bits(&s_builder.q), "{name}: displacements");
        assert_eq!(bits(&s.v), bits(&s_builder.v), "{name}: velocities");
        assert_eq!(bits(&s.a), bits(&s_builder.a), "{name}: accelerations");
    }
    for file in ["nodes.csv", "beam1.csv"] {
        let b = std::fs::read(dir.join("b").join(file)).expect("builder csv");
        assert!(b.len() > 1000, "{file} has the rows");
        for sub in ["t", "j"] {
            let o = std::fs::read(dir.join(sub).join(file)).expect("csv");
            assert!(o == b, "{file} differs between builder and {sub}");
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

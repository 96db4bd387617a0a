//! The built-in elements register without a `link()` call: this test binary names nothing
//! of the elements crate (no function, no type — the elements are asked for by their
//! registered names, as a model file does), builds a model through `ModelBuilder` and runs
//! it with the `Driver`. Were the elements' registrations dropped at link time, the build
//! would refuse `spring_damper` and `mass` as unknown element types.
//!
//! The model: two springs in series along `uz`, node 1 on a grounded spring `k1`, node 2
//! tied to node 1 by `k2` and carrying a mass `m`, under a static load `P` at node 2.
//! Closed forms (linear springs): `u1 = P/k1`, `u2 = P/k1 + P/k2`. Then, released from
//! rest at `u = 0` under the same constant load and with node 1 held, node 2 is a single
//! oscillator of period `T = 2π·√(m/k2)`, `u(t) = (P/k2)·(1 − cos ωt)`: Newmark's average
//! acceleration has no amplitude error and a period error `ε = (ωΔt)²/12` (Hughes, *The
//! Finite Element Method*, §9.3), so after one period (200 steps, `ε` = 8.2e-5) the mass
//! is back at `u = (P/k2)·(1 − cos 2πε)`, about 1e-7 of the amplitude. The bound, 1e-3 of
//! it, also covers a step more or less from rounding `T/Δt` (`1 − cos(2π/200)` = 4.9e-4).

use railfem::framework::builder::ModelBuilder;
use railfem::framework::loads::{LoadSpec, TimeSeries};
use railfem::framework::model::{AnalysisKind, AnalysisSpec};
use railfem::framework::{Dof, DofSet};
use railfem::solvers::Driver;
use serde_json::json;

const K1: f64 = 4.0e6;
const K2: f64 = 1.0e6;
const P: f64 = -2.5e3;
const M: f64 = 250.0;

fn springs(b: &mut ModelBuilder, hold_node_1: bool) {
    let free_z = DofSet::ALL
        .iter()
        .filter(|d| *d != Dof::Uz)
        .collect::<Vec<_>>();
    let node_1 = if hold_node_1 {
        DofSet::ALL
    } else {
        DofSet::of(&free_z)
    };
    b.node_fixed(1, [0.0; 3], node_1);
    b.node_fixed(2, [0.0, 0.0, 1.0], DofSet::of(&free_z));
    b.element(
        "spring_damper",
        1,
        &[1],
        &json!({"k": [0.0, 0.0, K1, 0.0, 0.0, 0.0]}),
    );
    b.element(
        "spring_damper",
        2,
        &[1, 2],
        &json!({"k": [0.0, 0.0, K2, 0.0, 0.0, 0.0]}),
    );
    b.element("mass", 3, &[2], &json!({"m": M}));
    b.load(LoadSpec::Nodal {
        node: 2,
        dof: Dof::Uz,
        value: P,
        series: TimeSeries::Constant,
    });
}

#[test]
fn built_in_elements_build_and_run_without_a_link_call() {
    let mut b = ModelBuilder::new("no link, static");
    springs(&mut b, false);
    b.analysis(AnalysisSpec {
        kind: AnalysisKind::Static,
        ..Default::default()
    });
    let mut d = Driver::new(b.build().expect("the built-in kinds are registered")).unwrap();
    d.static_solve(0.0, 1).unwrap();
    let (u1, u2) = (
        d.displacement(1, Dof::Uz).unwrap(),
        d.displacement(2, Dof::Uz).unwrap(),
    );
    // Linear springs, one solve: exact to round-off.
    assert!((u1 - P / K1).abs() <= 1e-12 * (P / K1).abs(), "u1 = {u1}");
    let u2_exact = P / K1 + P / K2;
    assert!((u2 - u2_exact).abs() <= 1e-12 * u2_exact.abs(), "u2 = {u2}");

    let period = 2.0 * std::f64::consts::PI * (M / K2).sqrt();
    let mut b = ModelBuilder::new("no link, transient");
    springs(&mut b, true);
    b.analysis(AnalysisSpec {
        dt: period / 200.0,
        duration: period,
        initial_static: false,
        ..Default::default()
    });
    let mut d = Driver::new(b.build().unwrap()).unwrap();
    d.run(None, &mut |_| {}).unwrap();
    let u = d.displacement(2, Dof::Uz).unwrap();
    let amplitude = (P / K2).abs();
    assert!(u.abs() <= 1e-3 * amplitude, "after one period u = {u:e} m");
}

//! The rolling-contact laws of `moving_axle` (issue 14) on a hand-made wheelset on straight,
//! level, rigid track: pure rolling carries no creep force and dissipates nothing; a
//! braking torque is balanced by the longitudinal creep forces (statics of the wheelset
//! about its axle) below the friction limit, and above it the wheels slide at μN. The
//! creepage kinematics against hand derivations and the laws against Kalker's table are
//! unit tests in `elements/src/rail/{rolling,creep/law}.rs`; the tangent is checked by the
//! conformance kit on rolling samples.

use railfem::elements::rail::alignment::Alignment;
use railfem::elements::rail::cant::{Cant, Track};
use railfem::elements::rail::track_model::{self, RailSupport, TrackMesh};
use railfem::framework::loads::{LoadSpec, TimeSeries};
use railfem::framework::model::{AnalysisSpec, IntegratorKind, ModelBuilder};
use railfem::framework::moving::{Carrier, Path};
use railfem::framework::DofSet;
use railfem::solvers::Driver;
use std::sync::Arc;

const R0: f64 = 0.43;
const MASS: f64 = 1850.0;
const INERTIA: [f64; 3] = [123.0, 967.0, 967.0];
const N_WHEEL: f64 = 50e3;
const MU: f64 = 0.3;
const SPEED: f64 = 20.0;
const DT: f64 = 1e-3;

struct Wheelset {
    d: Driver,
    wheels: [usize; 2],
}

/// A wheelset (mass and inertia at K, two `moving_axle` wheels with `law`) rolling at
/// [`SPEED`] on a rigid straight track, loaded by `2·N_WHEEL` downwards and the moment
/// `torque` about the axle (N·m). K is held longitudinally by a spring and dashpot to the
/// moving frame (a bogie's primary suspension, `k_long` N/m) when a net longitudinal
/// creep force needs something to push against.
fn build(law: &str, torque: f64, rail_nodes: usize, k_long: f64) -> Wheelset {
    railfem::elements::link();
    let track = Arc::new(Track::new(Alignment::straight(80.0), Cant::none()).unwrap());
    let mut b = ModelBuilder::new("creep test");
    let start = 10.0;
    let p = track.at(start);
    let xk = p.position + p.frame.column(1) * R0;
    b.node_fixed(1, [xk.x, xk.y, xk.z], DofSet::NONE);
    b.element(
        "mass",
        1,
        &[1],
        &serde_json::json!({"m": MASS, "inertia": INERTIA}),
    );
    for (id, side) in [(2, "left"), (3, "right")] {
        b.element(
            "moving_axle",
            id,
            &[1],
            &serde_json::json!({"side": side, "mu": MU, "tangential": law, "sliding_tangent": "consistent", "rail_nodes": rail_nodes}),
        );
    }
    // Lateral, longitudinal (k_long, N/m) and yaw held by the "bogie"; spin and roll free.
    b.element(
        "spring_damper",
        4,
        &[1],
        &serde_json::json!({"k": [1e6, 0.0, k_long, 0.0, 1e6, 0.0], "c": [1e4, 0.0, 1e5, 0.0, 1e4, 0.0]}),
    );
    let mesh = TrackMesh {
        support: RailSupport::Rigid,
        ..Default::default()
    };
    track_model::generate(&mut b, track.clone(), &mesh).unwrap();
    b.carrier(
        Carrier {
            name: "wheelset".into(),
            path: track.clone() as Arc<dyn Path>,
            start,
            speed: SPEED,
            accel: 0.0,
            speed_table: None,
            nodes: Vec::new(),
        },
        vec![(1, 0.0, [0.0, R0, 0.0])],
    );
    b.load(LoadSpec::Nodal {
        node: 1,
        dof: "uy".into(),
        value: -2.0 * N_WHEEL,
        series: TimeSeries::Constant,
    });
    if torque != 0.0 {
        b.load(LoadSpec::Nodal {
            node: 1,
            dof: "rx".into(),
            value: torque,
            series: TimeSeries::Constant,
        });
    }
    let mut analysis = AnalysisSpec::default();
    analysis.integrator = IntegratorKind::GeneralizedAlpha;
    analysis.rho_inf = 0.5;
    analysis.dt = DT;
    analysis.newton.tol = 1e-10;
    analysis.newton.abs_tol = 1e-6;
    analysis.newton.max_iter = 40;
    b.analysis(analysis);
    let model = b.build().unwrap();
    let idx = |id: u64| model.elements.iter().position(|e| e.id == id).unwrap();
    let wheels = [idx(2), idx(3)];
    let mut d = Driver::new(model).unwrap();
    d.static_solve(0.0, 10).unwrap();
    d.initialize().unwrap();
    Wheelset { d, wheels }
}

impl Wheelset {
    fn out(&self, w: usize, key: &str) -> f64 {
        let e = &self.d.model.elements[self.wheels[w]].element;
        let names = e.output_names();
        let mut v = Vec::new();
        e.outputs(&mut v);
        v[names.iter().position(|n| n == key).unwrap()]
    }

    /// Longitudinal creep force of wheel `w` summed over its reported contact points (N).
    fn fx(&self, w: usize) -> f64 {
        self.out(w, "c1_fx") + self.out(w, "c2_fx")
    }

    fn dissipated(&self) -> f64 {
        self.wheels
            .iter()
            .map(|&i| self.d.model.elements[i].element.dissipated_energy())
            .sum()
    }

    fn run(&mut self, steps: usize) {
        for _ in 0..steps {
            self.d.step(DT).unwrap();
        }
    }
}

/// Pure rolling: once the wheelset has found its rolling speed (the contact is not exactly
/// on the tape circle, so the spin settles at V/r rather than V/r0), the longitudinal
/// creep force and both creepages vanish and the contact dissipates nothing more. The
/// lateral force that remains is Kalker's spin force of the coned contact (`C23·φ`), equal
/// and opposite on the two wheels, and it does no work (ξy = 0). Scale: the creep force of
/// a creepage 1e-3 is ~1e4 N; zero to 1e-6 of the wheel load is far below it.
///
/// The rail profile is sampled coarsely (5 nodes) so that each wheel touches at a single
/// node: with two contact nodes at different rolling radii a rigid wheel cannot roll
/// without slip on both (each node is its own contact ellipse), see docs/creep.md.
#[test]
fn pure_rolling_carries_no_creep_force_and_dissipates_nothing() {
    for law in ["kalker_linear", "polach"] {
        let mut ws = build(law, 0.0, 5, 1e3);
        ws.run(200);
        let e0 = ws.dissipated();
        ws.run(100);
        let e1 = ws.dissipated();
        for w in 0..2 {
            let (fx, fy) = (ws.fx(w), ws.out(w, "c1_fy") + ws.out(w, "c2_fy"));
            println!(
                "{law} wheel {w}: Q {:.1} N, Fx {fx:.3e} N, Fy {fy:.3e} N, xi_x {:.3e}, radius {:.6} m",
                ws.out(w, "Q"),
                ws.out(w, "c1_xi_x"),
                ws.out(w, "rolling_radius")
            );
            assert_eq!(
                ws.out(w, "n_contact"),
                1.0,
                "{law}: one contact node per wheel"
            );
            assert!(fx.abs() < 1e-6 * N_WHEEL, "{law}: Fx {fx}");
            assert!(ws.out(w, "c1_xi_x").abs() < 1e-9, "{law}");
            assert!(ws.out(w, "c1_xi_y").abs() < 1e-9, "{law}");
            assert!((ws.out(w, "Q") - N_WHEEL).abs() < 1e-3 * N_WHEEL);
        }
        let fy: f64 = (0..2).map(|w| ws.out(w, "c1_fy")).sum();
        assert!(fy.abs() < 1e-6 * N_WHEEL, "{law}: net spin force {fy}");
        // Work of the creep forces over the last 0.1 s (2 m rolled): nothing, against
        // μ·N·2 m = 6e4 J for a sliding wheel.
        println!("{law}: dissipated over the last 0.1 s {:.3e} J", e1 - e0);
        assert!((e1 - e0).abs() < 1e-6, "{law}: {} J", e1 - e0);
    }
}

/// A driving torque M about the axle (positive about e1, the sense of rolling forwards)
/// below the friction limit: the wheelset turns faster than rolling until the longitudinal
/// creep forces balance M about the axle, Σ Fx·r = M (the moment of a force Fx·e3 at the
/// contact, r below the axle, is −r·Fx·e1). Above the limit (M > 2·μ·N·r) both wheels
/// slide: |Fx| = μ·N each.
#[test]
fn driving_torque_is_balanced_by_creep_then_saturates_at_mu_n() {
    for law in ["kalker_linear", "polach"] {
        let m = 0.3 * 2.0 * MU * N_WHEEL * R0;
        let mut ws = build(law, m, 41, 1e6);
        ws.run(300);
        let moment: f64 = (0..2).map(|w| ws.fx(w) * ws.out(w, "rolling_radius")).sum();
        println!(
            "{law}: M = {m:.1} N·m, Σ Fx·r = {moment:.1} N·m, xi_x {:.3e} {:.3e}",
            ws.out(0, "c1_xi_x"),
            ws.out(1, "c1_xi_x")
        );
        assert!((moment - m).abs() < 1e-3 * m, "{law}: {moment} vs {m}");
        // Driven: the wheel's contact runs backwards over the rail, ξx < 0, force forwards.
        for w in 0..2 {
            assert!(
                ws.out(w, "c1_xi_x") < 0.0 && ws.fx(w) > 0.0,
                "{law} wheel {w}"
            );
        }
    }
    let m = 1.3 * 2.0 * MU * N_WHEEL * R0;
    let mut ws = build("kalker_linear", m, 5, 1e6);
    ws.run(100);
    for w in 0..2 {
        // μ times the normal load (along the contact normal; Q is its vertical part).
        let (fx, n) = (ws.fx(w), ws.out(w, "p1_fn"));
        println!("sliding wheel {w}: Fx {fx:.1} N, μN {:.1} N", MU * n);
        assert_eq!(ws.out(w, "n_contact"), 1.0);
        assert!((fx.abs() - MU * n).abs() < 1e-6 * n, "{fx} vs {}", MU * n);
        assert!(ws.out(w, "n_slide") >= 1.0);
    }
}

//! Tests of the moving wheel-axle element (Ju & Ro 2021) on small models: a hand-made
//! wheelset (axle node K with a lumped mass, carried by a `Carrier`, and two `moving_axle`
//! wheels) on straight level track, against closed forms and conservation laws; the curved
//! track validation's independence of the penalty; and a cross-section picture.
//!
//! K's DOFs are in the wheel frame: ux lateral (axis 1, to the left), uy vertical (axis 2),
//! uz longitudinal (axis 3). The element's tangent against finite differences in every mode
//! is tested inside `moving_axle.rs` and is not repeated here.

use nalgebra::Vector3;
use railfem::elements::rail::contact::contact_law::Mode;
use railfem::elements::rail::contact::section_plot;
use railfem::elements::rail::geometry::alignment::Alignment;
use railfem::elements::rail::geometry::cant::{Cant, Track};
use railfem::elements::rail::geometry::track_model::{self, RailSupport, TrackMesh};
use railfem::elements::rail::wheels::moving_axle::MovingAxle;
use railfem::framework::builder::ModelBuilder;
use railfem::framework::loads::{LoadSpec, TimeSeries};
use railfem::framework::model::{AnalysisSpec, IntegratorKind};
use railfem::framework::moving::{Carrier, Path};
use railfem::framework::{Dof, DofSet};
use railfem::solvers::Driver;
use std::sync::Arc;

/// Height of the axle centre K above the rail-top plane (m): the wheel radius.
const R0: f64 = 0.43;
/// Wheelset mass (kg) and inertias about axes 1, 2, 3 (pitch, yaw, roll), sks700 data.
const MASS: f64 = 1850.0;
const INERTIA: [f64; 3] = [123.0, 967.0, 967.0];

/// A hand-made wheelset on a straight, level track.
struct Setup {
    /// Track length (m).
    length: f64,
    /// Station of the wheelset at t = 0 (m).
    start: f64,
    /// Speed (m/s).
    speed: f64,
    mesh: TrackMesh,
    /// `moving_axle` keys shared by both wheels.
    wheel: serde_json::Value,
    /// Loads on K: (dof, value, series).
    loads: Vec<(Dof, f64, TimeSeries)>,
    /// DOFs of K held fixed.
    fix: DofSet,
    /// Grounded springs and dashpots on K, [ux, uy, uz, rx, ry, rz] in the wheel frame.
    spring: Option<([f64; 6], [f64; 6])>,
    analysis: AnalysisSpec,
}

impl Default for Setup {
    fn default() -> Self {
        let mut analysis = AnalysisSpec::default();
        // Tight equilibrium: the checks below go to 1e-9 of the load.
        analysis.newton.tol = 1e-11;
        analysis.newton.abs_tol = 1e-7;
        analysis.newton.max_iter = 40;
        Setup {
            length: 40.0,
            start: 20.0,
            speed: 0.0,
            mesh: TrackMesh::default(),
            wheel: serde_json::json!({}),
            loads: Vec::new(),
            fix: DofSet::NONE,
            spring: None,
            analysis,
        }
    }
}

/// The built model: driver, K's node index and the wheels' element indices (left, right).
struct Wheelset {
    d: Driver,
    k: usize,
    wheels: [usize; 2],
}

const K_ID: u64 = 1;

fn build(s: &Setup) -> Wheelset {
    let track = Arc::new(Track::new(Alignment::straight(s.length), Cant::none()).unwrap());
    let mut b = ModelBuilder::new("wheelset test");
    let p = track.at(s.start);
    let xk = p.position + p.frame.column(1) * R0;
    b.node_fixed(K_ID, [xk.x, xk.y, xk.z], s.fix);
    b.element(
        "mass",
        1,
        &[K_ID],
        &serde_json::json!({"m": MASS, "inertia": INERTIA}),
    );
    for (id, side) in [(2, "left"), (3, "right")] {
        let mut w = s.wheel.as_object().cloned().unwrap_or_default();
        w.insert("side".into(), side.into());
        b.element("moving_axle", id, &[K_ID], &serde_json::Value::Object(w));
    }
    if let Some((k, c)) = s.spring {
        b.element(
            "spring_damper",
            4,
            &[K_ID],
            &serde_json::json!({"k": k, "c": c}),
        );
    }
    track_model::generate(&mut b, track.clone(), &s.mesh).unwrap();
    b.carrier(
        Carrier {
            name: "wheelset".into(),
            path: track.clone() as Arc<dyn Path>,
            start: s.start,
            speed: s.speed,
            accel: 0.0,
            speed_table: None,
            nodes: Vec::new(),
        },
        vec![(K_ID, 0.0, [0.0, R0, 0.0])],
    );
    for (dof, value, series) in &s.loads {
        b.load(LoadSpec::Nodal {
            node: K_ID,
            dof: *dof,
            value: *value,
            series: series.clone(),
        });
    }
    b.analysis(s.analysis.clone());
    let model = b.build().unwrap();
    let k = model.node(K_ID).unwrap();
    let idx = |id: u64| model.elements.iter().position(|e| e.id == id).unwrap();
    let wheels = [idx(2), idx(3)];
    let d = Driver::new(model).unwrap();
    Wheelset { d, k, wheels }
}

impl Wheelset {
    /// Output `key` of wheel `w` (0 left, 1 right) at the last evaluated state.
    fn out(&self, w: usize, key: &str) -> f64 {
        let e = &self.d.model.elements[self.wheels[w]].element;
        let names = e.output_names();
        let mut v = Vec::new();
        e.outputs(&mut v);
        v[names.iter().position(|n| n == key).unwrap()]
    }

    fn axle(&self, w: usize) -> &MovingAxle {
        self.d.model.elements[self.wheels[w]]
            .element
            .as_any()
            .and_then(|a| a.downcast_ref::<MovingAxle>())
            .unwrap()
    }

    /// Committed value of DOF `dof` of node index `node`.
    fn disp(&self, node: usize, dof: usize) -> f64 {
        self.d
            .asm
            .dofmap
            .value(&self.d.state.q, node, railfem::framework::Dof::ALL[dof])
    }

    fn acc(&self, node: usize, dof: usize) -> f64 {
        self.d
            .asm
            .dofmap
            .value(&self.d.state.a, node, railfem::framework::Dof::ALL[dof])
    }

    /// Node index of wheel `w`'s contact master B.
    fn b_node(&self, w: usize) -> usize {
        self.d.model.elements[self.wheels[w]].element.connectivity()[0].node
    }

    /// The A–B spring elongation δ = u_B − u_K − θ_K × (x_B − x_K) of wheel `w` (m, wheel
    /// frame), from the committed displacements.
    fn spring_delta(&self, w: usize) -> Vector3<f64> {
        let b = self.b_node(w);
        let ub = Vector3::from_fn(|i, _| self.disp(b, i));
        let uk = Vector3::from_fn(|i, _| self.disp(self.k, i));
        let th = Vector3::from_fn(|i, _| self.disp(self.k, 3 + i));
        let kin = self.d.asm.kinematics();
        let r = kin[self.k].frame.transpose() * (kin[b].position - kin[self.k].position);
        ub - uk - th.cross(&r)
    }
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

/// A piecewise-linear series through `(t, value)` points.
fn table(points: &[(f64, f64)]) -> TimeSeries {
    TimeSeries::Table {
        points: points.iter().map(|&(t, v)| [t, v]).collect(),
    }
}

// ---------------------------------------------------------------------------------------
// 1. Vertical load on rigid rails: symmetry, equilibrium and the A–B power law.
// ---------------------------------------------------------------------------------------

/// The approach of the spring k2 = a + b·f^{1/3} at force f, in closed form:
/// δ(f) = ∫₀^f dx/(a + b·x^{1/3}); with x = s³, dx = 3s² ds and
/// 3s²/(a + b·s) = (3/b)·(s − α + α²/(s + α)), α = a/b:
/// δ = (3/b)·(S²/2 − α·S + α²·ln(1 + S/α)), S = f^{1/3}.
fn approach_c_third(a: f64, b: f64, f: f64) -> f64 {
    let s = f.cbrt();
    let al = a / b;
    3.0 / b * (0.5 * s * s - al * s + al * al * (s / al).ln_1p())
}

#[test]
fn vertical_load_halves_and_follows_the_power_law() {
    let (a, b, c) = (1.0e5, 3.03e7, 1.0 / 3.0);
    // Total loads on K (N): 2·(10, 30, 60, 90, 130) kN.
    let levels = [20e3, 60e3, 120e3, 180e3, 260e3];
    let mut pts = vec![(0.0, 0.0)];
    for (i, p) in levels.iter().enumerate() {
        pts.push(((i + 1) as f64, *p));
    }
    let mut ws = build(&Setup {
        wheel: serde_json::json!({"a": a, "b": b, "c": c, "mu": 0.3}),
        loads: vec![(Dof::Uy, -1.0, table(&pts))],
        ..Default::default()
    });
    for (i, &p) in levels.iter().enumerate() {
        // Sub-steps from the previous level (static_solve scales from zero; one increment
        // per call keeps the path monotone).
        for j in 1..=4 {
            ws.d.static_solve(i as f64 + j as f64 / 4.0, 1).unwrap();
        }
        let (ql, qr) = (ws.out(0, "Q"), ws.out(1, "Q"));
        let (yl, yr) = (ws.out(0, "Y"), ws.out(1, "Y"));
        // Equilibrium of the wheelset (K plus both B): the contact forces carry the load.
        // Newton converges to 1e-11 of the load, so 1e-9 is a margin of 100.
        assert!(rel(ql + qr, p) < 1e-9, "ΣQ = {} vs {p}", ql + qr);
        // Mirror symmetry: the right wheel and rail are the exact mirror images of the
        // left ones, so each carries half.
        assert!(rel(ql, 0.5 * p) < 1e-9, "Q_L = {ql} vs {}", 0.5 * p);
        assert!(rel(qr, 0.5 * p) < 1e-9, "Q_R = {qr} vs {}", 0.5 * p);
        // Lateral components (conicity, rail inclination) cancel.
        assert!((yl + yr).abs() < 1e-9 * p, "Y_L + Y_R = {}", yl + yr);
        for w in 0..2 {
            let f2 = ws.out(w, "spring_f2");
            // B carries nothing but the spring and the contact: f2 = Q.
            assert!(rel(f2, 0.5 * p) < 1e-9, "f2 = {f2} vs {}", 0.5 * p);
            // The power law, from the displacements: f2 against δ2 in closed form. The
            // element inverts a Gauss–Legendre quadrature of δ(f) (its own unit test: 1e-10),
            // so 1e-8 in force is a margin of 100 (dδ/δ ≈ (2/3)·df/f).
            let delta = ws.spring_delta(w);
            let exact = approach_c_third(a, b, f2);
            println!(
                "P = {p:.0}: wheel {w} f2 = {f2:.6} N, δ2 = {:.9e} m, closed form δ = {exact:.9e} m",
                delta.y
            );
            assert!(rel(delta.y, exact) < 1e-8, "δ2 {} vs {exact}", delta.y);
            // a → 0 limit: Hertz f = (b(1−c)δ)^{1/(1−c)}. With α = a/b the closed form
            // differs from it by δ·(2α/S)(1 + O(α/S)), i.e. f by ≈ 3α/S relatively.
            let hertz = (b * (1.0 - c) * delta.y).powf(1.0 / (1.0 - c));
            let bound = 3.5 * (a / b) / f2.cbrt();
            assert!(
                rel(f2, hertz) < bound,
                "Hertz limit {hertz} vs {f2}, bound {bound}"
            );
        }
    }
}

// ---------------------------------------------------------------------------------------
// 2. Lateral push with friction: stick, Coulomb sliding, flange contact.
// ---------------------------------------------------------------------------------------

/// Wheel load per wheel (N), friction, and the stiffness of the loading device (N/m).
const N_WHEEL: f64 = 50e3;
const MU: f64 = 0.3;
const K_DEVICE: f64 = 2.0e7;
/// The symmetric sliding tangent (the default) gives singular systems on this static,
/// displacement-controlled slide (see the report); the consistent one converges.
const TANGENT: &str = "consistent";

/// A wheelset pressed down with `N_WHEEL` per wheel and pushed to the left (+axis 1)
/// through a grounded spring `K_DEVICE` whose far end moves by d(t) = t mm: the force
/// `K_DEVICE·(d − u)` on K is displacement-controlled, so the sliding plateau (almost zero
/// wheelset stiffness) can be followed statically. `fix` holds DOFs of K.
fn pushed_wheelset(fix: DofSet) -> Wheelset {
    build(&Setup {
        wheel: serde_json::json!({"mu": MU, "sliding_tangent": TANGENT}),
        fix,
        spring: Some(([K_DEVICE, 0.0, 0.0, 0.0, 0.0, 0.0], [0.0; 6])),
        loads: vec![
            // Vertical load ramped over t ∈ [−1, 0], then held.
            (
                Dof::Uy,
                -2.0 * N_WHEEL,
                table(&[(-1.0, 0.0), (0.0, 1.0), (100.0, 1.0)]),
            ),
            // Device: d = t mm for t ≥ 0.
            (
                Dof::Ux,
                K_DEVICE * 1e-3,
                table(&[(-1.0, 0.0), (0.0, 0.0), (100.0, 100.0)]),
            ),
        ],
        ..Default::default()
    })
}

/// One state of the push.
#[derive(Debug, Clone, Copy)]
struct PushState {
    u: f64,
    h: f64,
    y: [f64; 2],
    q: [f64; 2],
    n: [f64; 2],
    slide: [f64; 2],
    angle: [f64; 2],
}

fn push_state(ws: &Wheelset, d: f64) -> PushState {
    let u = ws.disp(ws.k, 0);
    let g = |k: &str| [ws.out(0, k), ws.out(1, k)];
    PushState {
        u,
        h: K_DEVICE * (d - u),
        y: g("Y"),
        q: g("Q"),
        n: g("n_contact"),
        slide: g("n_slide"),
        angle: g("max_contact_angle"),
    }
}

/// Loads the wheelset vertically (five increments over t ∈ [−1, 0]).
fn press(ws: &mut Wheelset) {
    for j in 1..=5 {
        ws.d.static_solve(-1.0 + j as f64 / 5.0, 1).unwrap();
    }
}

/// Stick: with K's rotations held, each wheel's B is tied to K by k1 laterally and to the
/// rigid rail by n sticking points, each an isotropic in-plane spring k (normal and
/// tangential penalty equal; the tangent follows the normal). Laterally the wheelset is
/// then two chains k1 + (n·k) in parallel: K_lat = Σ k1·n·k/(k1 + n·k).
#[test]
fn lateral_push_stick_stiffness_is_the_series_springs() {
    let mut ws = pushed_wheelset(DofSet::ROTATIONS);
    press(&mut ws);
    let s0 = push_state(&ws, 0.0);
    ws.d.static_solve(0.25, 1).unwrap();
    let s1 = push_state(&ws, 0.25e-3);
    assert_eq!(s1.slide, [0.0, 0.0], "still sticking");
    assert_eq!(s1.n, s0.n, "same contact points");
    let (k1, k) = (1.0e9, 1.0e10);
    let expect: f64 = s1.n.iter().map(|n| k1 * n * k / (k1 + n * k)).sum();
    let secant = (s1.h - s0.h) / (s1.u - s0.u);
    println!(
        "stick: n = {:?}, K_lat = {secant:.6e} N/m, closed form {expect:.6e}",
        s1.n
    );
    // The in-plane contact stiffness is k·I up to the curvature term k·g·∇²g (relative
    // |g|·κ ≈ 1e-6·3 m⁻¹) and the slip-frame terms (relative s·κ, smaller still); the load
    // transfer between the wheels (rotations held) changes k2 only, which does not act
    // laterally. 1e-4 is a wide margin over these.
    assert!(rel(secant, expect) < 1e-4, "{secant} vs {expect}");
    // Equilibrium: the wheels' lateral contact forces balance the device.
    let sum = s1.y[0] + s1.y[1];
    assert!((sum + s1.h).abs() < 1e-8 * s1.h, "ΣY = {sum}, H = {}", s1.h);
}

/// A free wheelset (roll free) pushed sideways: sticks, then every point slides at exactly
/// μ times its normal force (resolved on the current contact normal), the lateral force
/// stays on a plateau near μ·ΣQ while the wheelset slides, and when the flange closes a
/// steep second contact appears and the lateral stiffness jumps.
#[test]
fn lateral_push_slides_at_coulomb_then_flange_closes() {
    // The spin about the axle (rx) is held: rolling along the rail is a free motion that
    // statics cannot fix (its stiffness is k_v times the squared millimetre offsets of the
    // contact points from B). Roll and yaw are free.
    let mut ws = pushed_wheelset(DofSet::of(&[Dof::Rx]));
    press(&mut ws);
    let mut hist = vec![push_state(&ws, 0.0)];
    let mut sliding_steps = 0;
    for i in 1..=64 {
        let t = i as f64 * 0.25;
        ws.d.static_solve(t, 1).unwrap();
        let s = push_state(&ws, t * 1e-3);
        println!(
            "d {:.2} mm u {:.4} mm H {:.1} Y {:.1} {:.1} Q {:.1} {:.1} n {} {} slide {} {} angle {:.3} {:.3}",
            t, s.u * 1e3, s.h, s.y[0], s.y[1], s.q[0], s.q[1], s.n[0], s.n[1], s.slide[0], s.slide[1], s.angle[0], s.angle[1]
        );
        // Equilibrium of the wheelset at every converged step.
        assert!((s.y[0] + s.y[1] + s.h).abs() < 1e-8 * s.h.abs().max(1.0));
        // Coulomb per sliding point, on the current frame: the force φ splits into a
        // normal part and a part along the current tangent u (⊥ the current normal);
        // the latter is exactly μ times the former (rounding only: 1e-12).
        for w in 0..2 {
            for (_, st, _, _) in ws.axle(w).contact_points() {
                let phi = Vector3::new(st.phi.x, st.phi.y, 0.0);
                let ft = phi.dot(&st.u);
                let fnorm = (phi - st.u * ft).norm();
                assert!(
                    (fnorm - st.f_n).abs() < 1e-12 * st.f_n,
                    "normal {fnorm} vs {}",
                    st.f_n
                );
                if st.mode == Mode::Slide {
                    assert!(
                        (ft.abs() - MU * fnorm).abs() < 1e-12 * fnorm,
                        "sliding point: |f_t| = {} vs μ·f_n = {}",
                        ft.abs(),
                        MU * fnorm
                    );
                } else {
                    assert!(ft.abs() <= MU * fnorm * (1.0 + 1e-12));
                }
            }
        }
        if s.slide == s.n && s.n[0] > 0.0 && s.n[1] > 0.0 && s.angle[0] < 0.2 {
            sliding_steps += 1;
            // Every point of a wheel slides the same way, so each point force lies on the
            // edge of its friction cone, at atan μ from its normal; the normals are tilted
            // from axis 2 by at most γ (max_contact_angle), so the resultant satisfies
            // tan(atan μ − γ) ≤ |Y|/Q ≤ tan(atan μ + γ): the lateral force stays at μ·Q up to
            // the tilt of the contact (γ < 0.2 rad on the tread).
            for w in 0..2 {
                let (phi, g) = (MU.atan(), s.angle[w]);
                let r = s.y[w].abs() / s.q[w];
                assert!(
                    r >= (phi - g).tan() * (1.0 - 1e-9) && r <= (phi + g).tan() * (1.0 + 1e-9),
                    "wheel {w}: |Y|/Q = {r}, γ = {g}"
                );
            }
        }
        hist.push(s);
    }
    assert!(
        sliding_steps >= 8,
        "a sliding plateau: {sliding_steps} steps"
    );
    // Phases along the push, from the recorded states.
    let first_slide = hist.iter().position(|s| s.slide == s.n).unwrap();
    let flange = hist.iter().position(|s| s.angle[0] > 0.25).unwrap();
    // Before sliding: the plateau force is not reached; the stick stiffness is ~1e9 N/m.
    let stick = &hist[1];
    assert!(stick.u < 1e-5 && stick.slide == [0.0, 0.0]);
    // Sliding plateau: large motion for little force. Flange: the contact angle jumps
    // from the tread's < 0.15 rad to the gauge corner (> 0.25 rad, then up the 70° face).
    let (a, b) = (&hist[first_slide], &hist[flange - 1]);
    let k_slide = (b.h - a.h) / (b.u - a.u);
    let (c, e) = (&hist[flange], &hist[flange + 2]);
    let k_flange = (e.h - c.h) / (e.u - c.u);
    println!(
        "sliding from u = {:.3} mm to {:.3} mm: {k_slide:.3e} N/m; flange at u = {:.3} mm: {k_flange:.3e} N/m",
        a.u * 1e3,
        b.u * 1e3,
        c.u * 1e3
    );
    assert!(b.u - a.u > 4e-3, "the wheelset slides several mm");
    assert!(b.angle[0] < 0.15 && c.angle[0] > 0.25);
    // The stiffness jumps by far more than an order of magnitude at the flange.
    assert!(k_flange > 30.0 * k_slide, "{k_flange} vs {k_slide}");
    // On the flange face (70° = 1.22 rad) at the end of the push.
    let last = hist.last().unwrap();
    assert!(
        last.angle[0] > 1.15,
        "flange face reached: {}",
        last.angle[0]
    );
}

// ---------------------------------------------------------------------------------------
// 3. Lift-off and re-contact.
// ---------------------------------------------------------------------------------------

#[test]
fn lift_off_frees_the_wheelset_and_recontact_restores_equilibrium() {
    let down = -2.0 * N_WHEEL;
    let up = 40e3;
    // Vertical dashpot on K (half the critical damping of the bounce on the contact
    // springs, ≈ 2·m·1100 rad/s): lets the landing settle in a few ms.
    let c = 2.0e6;
    let mut analysis = Setup::default().analysis;
    analysis.dt = 1e-4;
    let mut ws = build(&Setup {
        wheel: serde_json::json!({"mu": MU}),
        fix: DofSet::of(&[Dof::Rx]),
        spring: Some(([0.0; 6], [0.0, c, 0.0, 0.0, 0.0, 0.0])),
        loads: vec![(
            Dof::Uy,
            1.0,
            table(&[
                (0.0, down),
                (1e-4, up),
                (4e-3, up),
                (4.1e-3, down),
                (1.0, down),
            ]),
        )],
        analysis,
        ..Default::default()
    });
    ws.d.initialize().unwrap();
    let before = (
        ws.disp(ws.k, 0),
        ws.disp(ws.k, 1),
        ws.out(0, "Q"),
        ws.out(1, "Q"),
    );
    let mut free_steps = 0;
    for _ in 0..40 {
        ws.d.step(1e-4).unwrap();
        let open = ws.out(0, "n_contact") == 0.0 && ws.out(1, "n_contact") == 0.0;
        if open {
            free_steps += 1;
            for w in 0..2 {
                assert_eq!(ws.out(w, "Q"), 0.0);
                assert_eq!(ws.out(w, "Y"), 0.0);
                // B is massless and touches nothing: its spring is slack.
                assert!(ws.out(w, "spring_f2").abs() < 1e-6);
            }
            // A free rigid body: m·a = F − c·v exactly (Newmark's equilibrium at the end
            // of the step, residual 1e-11 of the load); no other force acts.
            let (v, a) = (
                ws.d.asm
                    .dofmap
                    .value(&ws.d.state.v, ws.k, railfem::framework::Dof::Uy),
                ws.acc(ws.k, 1),
            );
            let expect = (up - c * v) / MASS;
            assert!(rel(a, expect) < 1e-8, "a = {a}, (F − c·v)/m = {expect}");
            assert!(ws.acc(ws.k, 0).abs() < 1e-8 * expect.abs());
        }
    }
    println!(
        "free flight for {free_steps} steps, K at {:.3e} m",
        ws.disp(ws.k, 1)
    );
    assert!(free_steps >= 10, "the wheelset lifted off");
    // Restore the load: land, settle, then the static equilibrium under the same load.
    for _ in 0..200 {
        ws.d.step(1e-4).unwrap();
    }
    let t = ws.d.state.t;
    ws.d.static_solve(t, 1).unwrap();
    let after = (
        ws.disp(ws.k, 0),
        ws.disp(ws.k, 1),
        ws.out(0, "Q"),
        ws.out(1, "Q"),
    );
    println!("before {before:?}\nafter  {after:?}");
    // The forces are those of before: statics fixes them (Q = half the load, 1e-9).
    assert!(rel(after.2, before.2) < 1e-9 && rel(after.3, before.3) < 1e-9);
    // The position too, up to the frictional memory: the stick anchors were reset when the
    // points opened, so the tangential elastic state after landing is not the one loaded
    // from rest. Its effect on K's height is at most the tilt γ ≈ 0.024 rad times the
    // tangential elastic slip μ·Q/(n·k) ≈ 7.5e-7 m, i.e. 1.8e-8 m, 2.6e-4 of the
    // deflection (measured: 1.5e-6).
    let bound = 0.024 * MU * N_WHEEL / (2.0 * 1e10);
    assert!(
        (after.1 - before.1).abs() < bound,
        "K vertical {after:?} vs {before:?}"
    );
    assert!(rel(after.1, before.1) < 1e-5);
}

// ---------------------------------------------------------------------------------------
// 7. Cross-section picture of a two-point contact.
// ---------------------------------------------------------------------------------------

#[test]
fn section_picture_of_two_point_contact() {
    let mut ws = pushed_wheelset(DofSet::of(&[Dof::Rx]));
    press(&mut ws);
    // Push until the left wheel touches both tread and gauge corner.
    let mut t = 0.0;
    while !(ws.out(0, "max_contact_angle") > 0.25 && ws.out(0, "min_contact_angle") < 0.15) {
        t += 0.25;
        assert!(t < 16.0, "no two-point contact found");
        ws.d.static_solve(t, 1).unwrap();
    }
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR"));
    let path = dir.join("section_two_point.svg");
    let axle = ws.axle(0);
    let sum = section_plot::write_section_svg(
        axle,
        &format!(
            "left wheel, wheelset moved {:.2} mm to the left: tread and gauge-corner contact",
            ws.disp(ws.k, 0) * 1e3
        ),
        &path,
    )
    .unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    let n_stick = text.matches("class=\"contact stick\"").count();
    let n_slide = text.matches("class=\"contact slide\"").count();
    println!("{}: {n_stick} stick, {n_slide} slide", path.display());
    assert_eq!(n_stick as f64, ws.out(0, "n_stick"));
    assert_eq!(n_slide as f64, ws.out(0, "n_slide"));
    assert_eq!((sum.stick, sum.slide), (n_stick, n_slide));
    assert!(n_stick + n_slide >= 2);
    assert!(text.contains("class=\"wheel\"") && text.contains("class=\"rail\""));
}

// ---------------------------------------------------------------------------------------
// 5. Rolling at 80 m/s on a finely meshed flexible rail.
// ---------------------------------------------------------------------------------------

/// A wheelset (load 2·50 kN on K) rolls at 80 m/s over rails of 0.2 m beam elements on
/// spring-damper supports at every node. Once the start-up transient has died, the contact
/// forces must not notice the element joints the wheel crosses (every 2.5 ms): the rail
/// point C is interpolated C¹ across joints (Hermite), and the element re-picks I and J.
///
/// Start-up: the wheelset starts from the *static* equilibrium, which differs slightly from
/// the steady moving one, so it bounces on the contact and support springs. Generalized-α
/// with ρ∞ = 0 removes the high-frequency part at once, and the support dashpots
/// (5e4 N·s/m per node) the rest within ~0.1 s; forces are compared after that.
#[test]
fn rolling_on_flexible_rail_forces_constant_across_elements() {
    let h = 0.125;
    let mut analysis = Setup::default().analysis;
    analysis.integrator = IntegratorKind::GeneralizedAlpha;
    analysis.rho_inf = 0.0;
    analysis.newton.tol = 1e-9;
    analysis.newton.abs_tol = 1e-6;
    // The direct solver, whose pattern each crossing rebuilds (checked below); "auto"
    // would pick the low-rank solver, which never rebuilds it.
    analysis.solver = railfem::framework::model::SolverChoice::Direct;
    let dt = 5e-4;
    analysis.dt = dt;
    let mut ws = build(&Setup {
        length: 24.0,
        start: 6.0,
        speed: 80.0,
        mesh: TrackMesh {
            element_length: h,
            support: RailSupport::Discrete {
                spacing: h,
                // Pads: lateral, vertical, longitudinal (N/m) and rotations (N·m/rad, the
                // rail would otherwise be free to twist about its axis).
                k: [5e7, 1e8, 5e7, 1e5, 1e5, 1e6],
                c: [5e4, 5e4, 5e4, 0.0, 0.0, 0.0],
            },
            ..Default::default()
        },
        wheel: serde_json::json!({"mu": MU}),
        fix: DofSet::of(&[Dof::Rx]),
        loads: vec![(Dof::Uy, -2.0 * N_WHEEL, TimeSeries::Constant)],
        analysis,
        ..Default::default()
    });
    // Preload in increments (the power-law spring is soft at zero force), then start.
    ws.d.static_solve(0.0, 10).unwrap();
    ws.d.initialize().unwrap();
    let patterns0 = ws.d.asm.stats.patterns;
    let mut settled = Vec::new();
    let mut elements = std::collections::BTreeSet::new();
    for k in 1..=250 {
        ws.d.step(dt).unwrap();
        let t = k as f64 * dt;
        if t > 0.1 + 1e-9 {
            let s = ws.out(0, "station");
            elements.insert((s / h).floor() as i64);
            settled.push([ws.out(0, "Q"), ws.out(1, "Q")]);
        }
    }
    let all: Vec<f64> = settled.iter().flatten().copied().collect();
    let mean = all.iter().sum::<f64>() / all.len() as f64;
    let spread = all.iter().fold(0.0f64, |m, q| m.max((q - mean).abs())) / mean;
    println!(
        "settled: mean Q = {mean:.3} N, max deviation {spread:.2e}; {} elements crossed, {} patterns",
        elements.len(),
        ws.d.asm.stats.patterns - patterns0
    );
    // Constant across the joints to 0.1 % (measured: ~1e-5).
    assert!(spread < 1e-3, "Q varies by {spread:e}");
    // And equal to the static share: the wheelset does not accelerate on average, and the
    // moving-load effect at 80 m/s (far below the track's critical speed) is small.
    assert!(rel(mean, N_WHEEL) < 1e-3, "mean Q {mean}");
    // The wheel crossed joints, and each crossing rebuilt the pattern (changing
    // connectivity: the element re-picked I and J).
    assert!(elements.len() >= 8);
    assert!(ws.d.asm.stats.patterns - patterns0 >= elements.len() - 1);
}

// ---------------------------------------------------------------------------------------
// 6. The curved-track validation does not depend on the penalty.
// ---------------------------------------------------------------------------------------

/// The curved-track validation (one sks700 carriage on a rigid, canted curve: V = 80 m/s,
/// Ct = 200 m, R = 6250 m, μ = 0.3) on a shortened alignment, run with the penalty
/// k = k_v = 1e10, 1e11 and 1e12 N/m. The carriage is on the arc at the end (station 630 m,
/// every wheel 290 m past the clothoid) and the quantities the validation reports — each
/// wheel's normal force and each wheelset's shear (the mean of its two wheels, which
/// statics fixes) — must not depend on the penalty once it is large. How the shear splits
/// between the two wheels of an axle does depend on the contact stiffness (it is statically
/// indeterminate), so single-wheel shear is not compared.
#[test]
fn curve_validation_is_penalty_independent() {
    use railfem::curve::{run, CurveCase};
    let mut res = Vec::new();
    for scale in [1.0, 10.0, 100.0] {
        let case = CurveCase {
            lengths: [60.0, 300.0, 700.0, 300.0, 60.0],
            duration: 7.5,
            penalty: 1e10 * scale,
            record_every: 50,
            sliding_tangent:
                railfem::elements::rail::contact::contact_law::SlidingTangent::Consistent,
            ..Default::default()
        };
        let r = run(&case, None, &mut |_| {}).unwrap();
        println!(
            "k = {:.0e}: FE vs statics on the settled arc: normal {:.3e}, axle shear {:.3e}",
            case.penalty, r.max_rel_normal_statics, r.max_rel_shear
        );
        res.push(r);
    }
    let last = |r: &railfem::curve::CurveReport| r.samples.last().unwrap().wheels.clone();
    let base = last(&res[0]);
    for r in &res[1..] {
        let w = last(r);
        for (i, (a, b)) in w.iter().zip(&base).enumerate() {
            // Normal forces: measured ≤ 2e-4 (the contact points move by the penetration,
            // µm, and the entry transient's remnant differs with the contact frequencies).
            assert!(rel(a.q, b.q) < 1e-3, "wheel {i}: Q {} vs {}", a.q, b.q);
        }
        for (i, (a, b)) in w.chunks(2).zip(base.chunks(2)).enumerate() {
            let (ya, yb) = (0.5 * (a[0].y + a[1].y), 0.5 * (b[0].y + b[1].y));
            // Axle shear: measured ~2e-5.
            assert!(rel(ya, yb) < 1e-3, "wheelset {i}: shear {ya} vs {yb}");
        }
        // The validation's own numbers (relative differences from the simple theory) move
        // by less than 1e-3 of the forces.
        assert!((r.max_rel_normal_statics - res[0].max_rel_normal_statics).abs() < 1e-3);
        assert!((r.max_rel_shear - res[0].max_rel_shear).abs() < 1e-3);
    }
}

// ---------------------------------------------------------------------------------------
// 7. The partitioned solver gives the direct solver's answer.
// ---------------------------------------------------------------------------------------

/// The rolling case of section 5 with a lateral force on the axle (so the contact points
/// slide and the tangent is unsymmetric), run once with the direct sparse solver and once
/// with the partitioned one (rails cut into blocks of 150 equations, the wheels' rail nodes
/// promoted to the top system as the wheelset moves through 60 block boundaries' worth of
/// rail). Both are exact linear solves of the same Newton iterations, so the histories agree
/// to the Newton tolerance's round-off, far inside 1e-8; and the partitioned run refactors
/// only the blocks the wheels enter or leave.
#[test]
fn partitioned_solver_reproduces_the_direct_solution() {
    use railfem::framework::model::SolverChoice;
    use railfem::solvers::partition::PartitionOptions;
    let h = 0.125;
    let dt = 5e-4;
    let steps = 120;
    let run = |solver: SolverChoice| {
        let mut analysis = Setup::default().analysis;
        analysis.integrator = IntegratorKind::GeneralizedAlpha;
        analysis.rho_inf = 0.5;
        analysis.newton.tol = 1e-10;
        analysis.newton.abs_tol = 1e-6;
        analysis.dt = dt;
        analysis.solver = solver;
        let mut ws = build(&Setup {
            length: 24.0,
            start: 6.0,
            speed: 80.0,
            mesh: TrackMesh {
                element_length: h,
                support: RailSupport::Discrete {
                    spacing: h,
                    k: [5e7, 1e8, 5e7, 1e5, 1e5, 1e6],
                    c: [5e4, 5e4, 5e4, 0.0, 0.0, 0.0],
                },
                ..Default::default()
            },
            wheel: serde_json::json!({"mu": MU, "sliding_tangent": "consistent"}),
            fix: DofSet::of(&[Dof::Rx]),
            loads: vec![
                (Dof::Uy, -2.0 * N_WHEEL, TimeSeries::Constant),
                (Dof::Ux, 0.4 * N_WHEEL, TimeSeries::Constant),
            ],
            analysis,
            ..Default::default()
        });
        ws.d.set_partition_options(PartitionOptions {
            block_size: 150,
            threads: 2,
            ..Default::default()
        });
        ws.d.static_solve(0.0, 10).unwrap();
        ws.d.initialize().unwrap();
        let mut q = Vec::new();
        for _ in 0..steps {
            ws.d.step(dt).unwrap();
            q.push([
                ws.out(0, "Q"),
                ws.out(1, "Q"),
                ws.out(0, "Y"),
                ws.out(1, "Y"),
            ]);
        }
        (ws, q)
    };
    let (direct, qd) = run(SolverChoice::Direct);
    let (part, qp) = run(SolverChoice::Partitioned);
    assert!(direct.d.partition_stats().is_none());
    let stats = part.d.partition_stats().expect("partitioned mode");
    let mut worst = 0.0f64;
    for (a, b) in qd.iter().zip(&qp) {
        for k in 0..4 {
            worst = worst.max((a[k] - b[k]).abs() / N_WHEEL);
        }
    }
    let dq = direct
        .d
        .state
        .q
        .iter()
        .zip(&part.d.state.q)
        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
    let scale = direct.d.state.q.iter().fold(0.0f64, |m, a| m.max(a.abs()));
    println!(
        "partitioned vs direct: forces {worst:.2e} of N, displacements {:.2e}; {stats:?}",
        dq / scale
    );
    assert!(worst < 1e-8, "forces differ by {worst:e} of N");
    assert!(
        dq / scale < 1e-8,
        "displacements differ by {:e}",
        dq / scale
    );
    // 2316 equations in blocks of ~150: at least 10 blocks. The wheels crossed ≥ 70 rail
    // elements (9.6 m) and re-picked their nodes at each crossing, yet every block was
    // factored only for the static and the transient tangents' constant parts (two keys):
    // the wheels' rail nodes enter the top system through promotions (solves with the
    // block's existing factor).
    assert!(stats.blocks >= 10, "{stats:?}");
    assert!(stats.block_factorizations <= 2 * stats.blocks, "{stats:?}");
    assert!(stats.promotions >= 70, "{stats:?}");
}

//! What the track issue must show, as integration tests against closed forms and independent
//! derivations:
//!
//! 1. the paper's five-segment track read from a model file's `[track]` table is the same
//!    geometry as [`Track::paper`] (the Fresnel ends, the total length and the joint continuity
//!    are unit tests in `elements/src/rail/geometry/alignment.rs` and `cant.rs`);
//! 2. a lumped mass carried at constant speed through a canted circular curve settles to the
//!    spring forces of the paper's Eqs. 22–23;
//! 3. a carried mass under a prescribed acceleration `a` feels `−m·a` along the track, and on a
//!    curve the yaw moment `I·a/R`;
//! 4. a rail on discrete elastic supports under a static point load matches (a) the Winkler
//!    beam with the support stiffness smeared, within the discrete-support difference that
//!    the exact infinite discretely supported beam (derived below) justifies, (b) a dense
//!    solution of the same discrete system assembled here from the textbook 2-D
//!    Euler–Bernoulli element, to 1e-9, and that exact infinite-beam solution, to 1e-9;
//! 5. `railfem track` writes the track report with the right header, length and cant.
//!
//! Tests build with `--release` (`cargo test --release --test track`).

mod common;

use railfem::elements::rail::geometry::alignment::{Alignment, Hand, Segment};
use railfem::elements::rail::geometry::cant::{Cant, Track};
use railfem::elements::rail::geometry::track_model::{
    self, mesh_stations, RailSection, RailSupport, TrackMesh, TrackModel,
};
use railfem::framework::builder::ModelBuilder;
use railfem::framework::model::{AnalysisKind, AnalysisSpec};
use railfem::framework::moving::{Carrier, Path};
use railfem::solvers::Driver;
use std::sync::Arc;

const G: f64 = 9.81;

// ------------------------------------------------------------------------------------------
// 1. The paper's track from a model file
// ------------------------------------------------------------------------------------------

/// The `[track]` table of a model file with the paper's five segments (clothoid curvatures
/// inferred from the neighbours) builds exactly `Track::paper(6250, 200)`, and the rigid
/// rail nodes it generates sit on that track's rail lines (±offset along wheel axis 1) at
/// stations that include every segment joint.
#[test]
fn model_file_track_is_the_paper_track() {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("track_modelfile");
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("paper.toml");
    std::fs::write(
        &file,
        r#"
[analysis]
kind = "static"

[track]
segments = [{type = "straight", length = 500}, {type = "clothoid", length = 2000},
            {type = "arc", length = 10908.3078, radius = 6250, hand = "left"},
            {type = "clothoid", length = 2000}, {type = "straight", length = 800}]
ct = 200
element_length = 25.0
support = {type = "rigid"}
"#,
    )
    .unwrap();
    let b = railfem::framework::modelfile::read(&file).unwrap();
    let tm = b
        .resource_get("track")
        .and_then(|r| r.downcast::<TrackModel>().ok())
        .expect("the [track] section registers the track resource");
    let paper = Track::paper(6250.0, 200.0);
    // Same segments, cant law and gauge, bit for bit (clothoid end curvatures inferred).
    assert_eq!(*tm.track, paper);
    assert!((tm.track.length() - 16_208.307_8).abs() < 1e-9);
    // Mesh stations: start, end and every joint are nodes.
    let joints = paper.alignment.joints();
    for j in &joints {
        assert!(
            tm.stations.iter().any(|s| (s - j).abs() < 1e-9),
            "joint {j} m is not a rail node"
        );
    }
    assert_eq!(
        tm.stations,
        mesh_stations(&paper, 0.0, paper.length(), 25.0)
    );
    // Node positions: rails at ±(G/2 + 0.036) along axis 1 of the paper track's wheel frame.
    let model = b.build().unwrap();
    let offset = 1.435 / 2.0 + 0.036;
    let mut worst: f64 = 0.0;
    for (r, sign) in [(0usize, 1.0), (1, -1.0)] {
        for (i, &s) in tm.stations.iter().enumerate() {
            let n = &model.nodes[model.node(tm.rails[r].first_id + i as u64).unwrap()];
            let p = paper.at(s);
            let expect = p.position + p.frame.column(0) * (sign * offset);
            worst = worst.max((n.position - expect).norm());
            assert!(n.fixed.count() == 6, "rigid rail nodes are fixed");
        }
    }
    // Both come from the same deterministic alignment code: agreement to round-off.
    assert!(worst < 1e-9, "rail node off the paper track by {worst:e} m");
    // On the arc the outer (right, for a left-hand curve) rail is raised by offset·sin(Ct/R).
    let mid = tm.stations.partition_point(|s| *s < 8000.0);
    let right = &model.nodes[model.node(tm.rails[1].first_id + mid as u64).unwrap()];
    let theta: f64 = 200.0 / 6250.0;
    assert!((right.position.z - offset * theta.sin()).abs() < 1e-12);
}

// ------------------------------------------------------------------------------------------
// 2, 3. A lumped mass on springs carried along the track
// ------------------------------------------------------------------------------------------

/// A carried body: mass `m`, principal moments `inertia` in the node (wheel-frame) axes, on a
/// grounded `spring_damper` in the same axes tuned to `freq` Hz in every DOF with damping
/// ratio `zeta`.
struct Body {
    m: f64,
    inertia: [f64; 3],
    freq: f64,
    zeta: f64,
}

impl Body {
    fn standard() -> Body {
        Body {
            m: 1200.0,
            inertia: [300.0, 800.0, 500.0],
            freq: 2.0,
            zeta: 0.7,
        }
    }

    /// Stiffnesses `[k1, k2, k3, kr1, kr2, kr3]`: `k = m·ω²` per DOF.
    fn k(&self) -> [f64; 6] {
        let w2 = (2.0 * std::f64::consts::PI * self.freq).powi(2);
        let i = self.inertia;
        [
            self.m * w2,
            self.m * w2,
            self.m * w2,
            i[0] * w2,
            i[1] * w2,
            i[2] * w2,
        ]
    }

    fn masses(&self) -> [f64; 6] {
        let i = self.inertia;
        [self.m, self.m, self.m, i[0], i[1], i[2]]
    }
}

/// A model with one node carried on `track` from station `start` at speed `speed` with
/// acceleration `accel`, holding `body`; gravity −9.81 Z. `initial_static = false`: the body
/// starts undeformed and at rest in the moving frame, so the run has a real transient.
fn carried_body(track: Track, start: f64, speed: f64, accel: f64, body: &Body) -> Driver {
    let path: Arc<dyn Path> = Arc::new(track);
    let p = path.at(start);
    let mut b = ModelBuilder::new("carried body");
    b.node(1, [p.position.x, p.position.y, p.position.z]);
    b.element(
        "mass",
        1,
        &[1],
        &serde_json::json!({"m": body.m, "inertia": body.inertia}),
    );
    let k = body.k();
    let mut c = [0.0; 6];
    for (i, mi) in body.masses().iter().enumerate() {
        c[i] = 2.0 * body.zeta * (k[i] * mi).sqrt();
    }
    // `axes = []`: the spring acts in the node's axes, the wheel frame 1-2-3.
    b.element(
        "spring_damper",
        2,
        &[1],
        &serde_json::json!({"k": k, "c": c}),
    );
    b.carrier(
        Carrier {
            name: "body".into(),
            path,
            start,
            speed,
            accel,
            speed_table: None,
            nodes: vec![],
        },
        vec![(1, 0.0, [0.0, 0.0, 0.0])],
    );
    b.analysis(AnalysisSpec {
        kind: AnalysisKind::Transient,
        dt: 0.01,
        duration: 4.0,
        gravity: Some([0.0, 0.0, -G]),
        initial_static: false,
        ..Default::default()
    });
    Driver::new(b.build().unwrap()).unwrap()
}

/// Spring forces `k_i·u_i` of node 1 in its axes (N, N·m): what the spring carries, equal in
/// equilibrium to the applied load on the body (gravity plus the Eq. 5 pseudo-loads).
fn spring_forces(d: &Driver, body: &Body) -> [f64; 6] {
    let k = body.k();
    let mut f = [0.0; 6];
    for (i, fi) in f.iter_mut().enumerate() {
        *fi = k[i] * d.displacement(1, railfem::framework::Dof::ALL[i]).unwrap();
    }
    f
}

/// Runs `seconds` of transient at dt = 0.01 s; returns the spring forces after the first
/// step (to show there was a transient) and at the end.
fn settle(d: &mut Driver, body: &Body, seconds: f64) -> ([f64; 6], [f64; 6]) {
    d.step(0.01).unwrap();
    let first = spring_forces(d, body);
    let n = (seconds / 0.01).round() as usize;
    for _ in 1..n {
        d.step(0.01).unwrap();
    }
    (first, spring_forces(d, body))
}

/// A single circular arc of radius `r` (m), `hand`, with θ = Ct/R.
fn arc_track(r: f64, hand: Hand, ct: f64, length: f64) -> Track {
    Track::new(
        Alignment::new(vec![Segment::Arc {
            length,
            radius: r,
            hand,
        }])
        .unwrap(),
        Cant::FromRadius { ct },
    )
    .unwrap()
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

/// Eqs. 22–23 with a carried mass on a canted arc at constant speed, both hands.
///
/// Derivation (the frame of `cant.rs`, left-hand curve, θ_s = θ): the track frame has x to
/// the left (towards the centre), y = Z up; the wheel frame is e1 = cosθ·x − sinθ·y,
/// e2 = sinθ·x + cosθ·y. The reference motion accelerates the body towards the centre,
/// a_ref = (v²/R)·x, so in the moving frame the body carries gravity and the d'Alembert
/// (centrifugal) force, f = m·(g − a_ref) = −m·g·y − m·(v²/R)·x. Resolved:
///
/// ```text
/// F1 = f·e1 = −m(v²/R)cosθ + m·g·sinθ          (Eq. 22)
/// F2 = f·e2 = −m(v²/R)sinθ − m·g·cosθ          (Eq. 23)
/// F3 = 0
/// ```
///
/// For a right-hand curve θ_s = −θ and x (still to the left) points away from the centre:
/// a_ref = −(v²/R)·x, e1 = cosθ·x + sinθ·y, e2 = −sinθ·x + cosθ·y, which gives −F1 along e1
/// and the same F2. In equilibrium the grounded spring carries exactly f: k_i·u_i = F_i.
///
/// The body starts at rest and undeformed (no initial static solve) and rings at 2 Hz with
/// 70 % damping: after 4 s the transient is down by exp(−0.7·2π·2·4) ≈ 6e-16, so the
/// recorded spring forces must equal Eqs. 22–23 to round-off. The tolerance, 1e-9 relative,
/// leaves room for the round-off of 400 steps and is still far below the 1e-6 asked for.
/// A static solve at the same time with the same pseudo-loads must agree too.
#[test]
fn carried_mass_on_canted_arc_settles_to_eqs_22_23() {
    let (r, ct, v) = (600.0, 60.0, 30.0);
    let theta: f64 = ct / r;
    let body = Body::standard();
    let m = body.m;
    let f1 = m * G * theta.sin() - m * v * v / r * theta.cos();
    let f2 = -m * G * theta.cos() - m * v * v / r * theta.sin();
    // Not a balanced cant: F1 is a sizeable fraction of the weight.
    assert!(f1.abs() > 0.04 * m * G);
    for hand in [Hand::Left, Hand::Right] {
        let expect1 = hand.sign() * f1;
        let track = arc_track(r, hand, ct, 1000.0);
        let mut d = carried_body(track.clone(), 100.0, v, 0.0, &body);
        let (first, f) = settle(&mut d, &body, 4.0);
        // A real transient: after one step the springs carry a small part of the load.
        assert!(
            rel(first[1], f2) > 0.5,
            "{hand:?}: no transient ({first:?})"
        );
        assert!(
            rel(f[0], expect1) < 1e-9,
            "{hand:?}: F1 = {} N, Eq. 22 gives {expect1} N",
            f[0]
        );
        assert!(
            rel(f[1], f2) < 1e-9,
            "{hand:?}: F2 = {} N, Eq. 23 gives {f2} N",
            f[1]
        );
        // Nothing along the track, no moments (constant speed on an arc: no yaw acceleration).
        for (i, fi) in f.iter().enumerate().skip(2) {
            assert!(fi.abs() < 1e-9 * m * G, "{hand:?}: component {i} = {fi}");
        }
        eprintln!(
            "{hand:?}: F1 {:.9e} vs {expect1:.9e} (rel {:.1e}), F2 {:.9e} vs {f2:.9e} (rel {:.1e})",
            f[0],
            rel(f[0], expect1),
            f[1],
            rel(f[1], f2)
        );
        // The static solve at the same time with the same pseudo-loads.
        let mut s = carried_body(track, 100.0, v, 0.0, &body);
        s.static_solve(4.0, 1).unwrap();
        let fs = spring_forces(&s, &body);
        assert!(
            rel(fs[0], expect1) < 1e-12 && rel(fs[1], f2) < 1e-12,
            "{fs:?}"
        );
    }
}

/// Along a straight track with the carrier accelerating at `a`, the body feels −m·a along
/// axis 3 (the d'Alembert force of the reference acceleration a·e3): the spring carries
/// k3·u3 = −m·a, i.e. it pushes the body forwards with m·a. Axis 2 carries the weight, axis 1
/// nothing. Settled transient as above (1e-9 relative: round-off only).
#[test]
fn carried_mass_accelerating_on_a_straight_feels_minus_m_a() {
    let body = Body::standard();
    let (m, a) = (body.m, 0.8);
    let track = Track::new(Alignment::straight(500.0), Cant::none()).unwrap();
    let mut d = carried_body(track.clone(), 50.0, 10.0, a, &body);
    let (first, f) = settle(&mut d, &body, 4.0);
    assert!(rel(first[2], -m * a) > 0.5, "no transient: {first:?}");
    assert!(
        rel(f[2], -m * a) < 1e-9,
        "k3·u3 = {} N, −m·a = {}",
        f[2],
        -m * a
    );
    assert!(rel(f[1], -m * G) < 1e-9, "k2·u2 = {} N", f[1]);
    assert!(f[0].abs() < 1e-9 * m * G);
    for (i, fi) in f.iter().enumerate().skip(3) {
        assert!(fi.abs() < 1e-9 * m * G, "moment {i} = {fi}");
    }
    let mut s = carried_body(track, 50.0, 10.0, a, &body);
    s.static_solve(2.5, 1).unwrap();
    let fs = spring_forces(&s, &body);
    assert!(rel(fs[2], -m * a) < 1e-12, "{fs:?}");
    eprintln!(
        "straight, a = {a}: k3·u3 = {:.12e} N, −m·a = {:.12e} N",
        f[2],
        -m * a
    );
}

/// On a circular arc with the carrier accelerating at `a`, the frame's yaw acceleration is
/// α = κ·a about global Z (κ = ±1/R), and the body's rotary inertia feels −I·α: the Eq. 5
/// moment I·a/R. In the node's axes, with principal moments (I1, I2, I3) along e1, e2, e3
/// and e1·Z = −sinθ_s, e2·Z = cosθ_s (θ_s = sign(κ)·θ):
///
/// ```text
/// M2 = −I2·κ·a·cosθ          (about the track-plane normal: −I2·a/R for a left-hand curve)
/// M1 = +I1·κ·a·sinθ_s = I1·|κ|·a·sinθ
/// M3 = 0
/// ```
///
/// With θ = 0 this is exactly ∓I·a/R about the vertical. The rotational springs carry
/// kr_i·φ_i = M_i after the transient (1e-9 relative), and axis 3 carries −m·a as on the
/// straight. The speed changes, so the lateral force m·v²/R is a ramp in time and is not
/// checked here (a damped spring lags a ramp by 2ζ/ω).
#[test]
fn carried_inertia_on_an_accelerating_arc_feels_i_a_over_r() {
    let body = Body::standard();
    let (r, a, v0) = (600.0, 0.8, 20.0);
    for (hand, ct) in [(Hand::Left, 0.0), (Hand::Right, 0.0), (Hand::Left, 60.0)] {
        let theta: f64 = ct / r;
        let kappa = hand.sign() / r;
        let track = arc_track(r, hand, ct, 1000.0);
        let mut d = carried_body(track.clone(), 100.0, v0, a, &body);
        let (first, f) = settle(&mut d, &body, 4.0);
        let m2 = -body.inertia[1] * kappa * a * theta.cos();
        let m1 = body.inertia[0] * kappa.abs() * a * theta.sin();
        assert!(rel(first[4], m2) > 0.5, "no transient: {first:?}");
        assert!(
            rel(f[4], m2) < 1e-9,
            "{hand:?}, Ct = {ct}: yaw spring {} N·m, −I2·κ·a·cosθ = {m2}",
            f[4]
        );
        if ct == 0.0 {
            assert!((m2.abs() - body.inertia[1] * a / r).abs() < 1e-12 * m2.abs());
            assert!(f[3].abs() < 1e-9 * m2.abs(), "roll {}", f[3]);
        } else {
            assert!(
                rel(f[3], m1) < 1e-9,
                "roll spring {} N·m, I1·a·sinθ/R = {m1}",
                f[3]
            );
        }
        assert!(f[5].abs() < 1e-9 * m2.abs(), "pitch {}", f[5]);
        assert!(rel(f[2], -body.m * a) < 1e-9, "k3·u3 = {}", f[2]);
        let mut s = carried_body(track, 100.0, v0, a, &body);
        s.static_solve(1.0, 1).unwrap();
        let fs = spring_forces(&s, &body);
        assert!(rel(fs[4], m2) < 1e-12, "{fs:?}");
        eprintln!(
            "{hand:?}, Ct = {ct}: yaw {:.12e} vs {m2:.12e} N·m, roll {:.3e} vs {m1:.3e}",
            f[4], f[3]
        );
    }
}

// ------------------------------------------------------------------------------------------
// 4. A rail on discrete supports under a static point load
// ------------------------------------------------------------------------------------------

/// Rail and supports of test 4: 60E1 on supports every 0.6 m, 40 MN/m each (vertical).
const SPACING: f64 = 0.6;
const K_SUPPORT: f64 = 4.0e7;
const P_LOAD: f64 = 100.0e3;
const RAIL_LENGTH: f64 = 60.0;
const ELEMENT: f64 = 0.3;

/// Builds the straight track (rails meshed at 0.3 m, discrete supports every 0.6 m), loads
/// the left rail's node `load_index` with −P (vertical, global Z, the rail nodes' axes on a
/// straight), solves statically, and returns the stations and the left rail's vertical
/// deflections.
fn rail_on_supports(load_index: usize) -> (Vec<f64>, Vec<f64>) {
    let track = Arc::new(Track::new(Alignment::straight(RAIL_LENGTH), Cant::none()).unwrap());
    let mut b = ModelBuilder::new("rail on supports");
    let k = K_SUPPORT;
    // Lateral and longitudinal springs and the torsion and yaw springs only keep those DOFs
    // from being free; the rotation about e1 (the vertical-bending slope) is left free so
    // that the supports are pure vertical springs, as in the Winkler model.
    let mesh = TrackMesh {
        element_length: ELEMENT,
        rail_offset: None,
        rail: RailSection::uic60(),
        support: RailSupport::Discrete {
            spacing: SPACING,
            k: [k, k, k, 0.0, 1.0e6, 1.0e6],
            c: [0.0; 6],
        },
        window: None,
        dips: Vec::new(),
    };
    let tm = track_model::generate(&mut b, track, &mesh).unwrap();
    let first = tm.rails[0].first_id;
    let d = common::solve_under_point_load(b, first + load_index as u64, -P_LOAD);
    let w = (0..tm.stations.len())
        .map(|i| {
            d.displacement(first + i as u64, railfem::framework::Dof::Uz)
                .unwrap()
        })
        .collect();
    (tm.stations.clone(), w)
}

/// The independent reference: the same discrete system assembled here from the textbook
/// 2-D Euler–Bernoulli element (DOFs w, φ = dw/dx per node),
///
/// ```text
///           EI  ⎡ 12    6L   −12    6L  ⎤
///   k_e  = ──── ⎢ 6L   4L²   −6L   2L²  ⎥
///           L³  ⎢−12   −6L    12   −6L  ⎥
///               ⎣ 6L   2L²   −6L   4L²  ⎦
/// ```
///
/// plus a vertical spring `K_SUPPORT` at every node whose station is a multiple of the
/// spacing, solved densely (LU). Returns the deflections w.
fn dense_reference(stations: &[f64], load_index: usize) -> Vec<f64> {
    let sec = RailSection::uic60();
    let ei = sec.e * sec.i_vertical;
    let n = stations.len();
    let mut k = nalgebra::DMatrix::<f64>::zeros(2 * n, 2 * n);
    for e in 0..n - 1 {
        let l = stations[e + 1] - stations[e];
        let c = ei / (l * l * l);
        let ke = [
            [12.0, 6.0 * l, -12.0, 6.0 * l],
            [6.0 * l, 4.0 * l * l, -6.0 * l, 2.0 * l * l],
            [-12.0, -6.0 * l, 12.0, -6.0 * l],
            [6.0 * l, 2.0 * l * l, -6.0 * l, 4.0 * l * l],
        ];
        for (a, row) in ke.iter().enumerate() {
            for (bb, v) in row.iter().enumerate() {
                k[(2 * e + a, 2 * e + bb)] += c * v;
            }
        }
    }
    let mut supports = 0;
    for (i, s) in stations.iter().enumerate() {
        let q = s / SPACING;
        if (q - q.round()).abs() < 1e-9 {
            k[(2 * i, 2 * i)] += K_SUPPORT;
            supports += 1;
        }
    }
    // Supports at 0, 0.6, …, 60 m: 101 of them.
    assert_eq!(supports, (RAIL_LENGTH / SPACING).round() as usize + 1);
    let mut f = nalgebra::DVector::<f64>::zeros(2 * n);
    f[2 * load_index] = -P_LOAD;
    let x = k
        .lu()
        .solve(&f)
        .expect("the supported beam is not singular");
    (0..n).map(|i| x[2 * i]).collect()
}

/// The exact deflection under the load of an INFINITE Euler–Bernoulli beam (EI) on springs
/// k every a, the load P over a support (`u = 0`) or mid-way between two (`u = ½`), from
/// our derivation:
///
/// `EI·w⁗ + k·Σ_n w_n·δ(x − n·a) = P·δ(x − x_P)`. With ŵ(ξ) the Fourier transform and
/// W(ξ) = Σ_n w_n·e^{−iξna} (period 2π/a), `ŵ = (P·e^{−iξx_P} − k·W)/(EI·ξ⁴)`; sampling at
/// the supports (Poisson summation, q_m = 2πm/a) gives W = (1/a)·Σ_m ŵ(ξ + q_m), hence
/// W = P·Ψ/(1 + k·Φ) with Φ = Σ_m (ξ + q_m)⁻⁴/(a·EI), Ψ = Σ_m e^{−i(ξ+q_m)x_P}(ξ + q_m)⁻⁴/(a·EI),
/// and, folding the inverse transform onto one period,
///
/// ```text
/// w(x_P) = (a/2π) ∫_{−π/a}^{π/a} P·[Φ − k·|Ψ|²/(1 + k·Φ)] dξ.
/// ```
///
/// With z = ξa/2 the lattice sums are closed: S0 = Σ (z + mπ)⁻⁴ = (2 + cos 2z)/(3 sin⁴z),
/// S1 = Σ (−1)^m (z + mπ)⁻⁴ = cos z·(5 + cos²z)/(6 sin⁴z) (the second derivatives of
/// Σ (z + mπ)⁻² = 1/sin²z and Σ (−1)^m (z + mπ)⁻² = cos z/sin²z, divided by 6), and
/// S0 − S1 = (1 − cos z)²(2 − cos z)/(6 sin⁴z) = (2 − cos z)/(24 cos⁴(z/2)). With
/// c = k·a³/(16·EI):
///
/// ```text
/// k·w/P = (1/π) ∫_{−π/2}^{π/2} f(z) dz,
///   u = 0:  f = c / (c + 1/S0)
///   u = ½:  f = [c + c²·(S0 − S1)·(1 + S1/S0)] / (c + 1/S0)
/// ```
///
/// written so that nothing is singular at z = 0 (1/S0 → 0, S1/S0 → 1, S0 − S1 → 1/24). As
/// c → 0 the u = 0 integral tends to ∫ c/(c + z⁴) dz/π = c^¼/√2 = βa/2: the Winkler beam.
/// f is analytic and π-periodic, so the midpoint rule over one period converges
/// geometrically; `n` points. Returns w (m) per unit load (N).
fn discrete_infinite_beam(ei: f64, k: f64, a: f64, u: f64, n: usize) -> f64 {
    let c = k * a.powi(3) / (16.0 * ei);
    let h = std::f64::consts::PI / n as f64;
    let mut sum = 0.0;
    for j in 0..n {
        let z = -std::f64::consts::FRAC_PI_2 + (j as f64 + 0.5) * h;
        let (sz, cz) = z.sin_cos();
        let inv_s0 = 3.0 * sz.powi(4) / (2.0 + (2.0 * z).cos());
        sum += if u == 0.0 {
            c / (c + inv_s0)
        } else {
            assert_eq!(u, 0.5, "only u = 0 and u = ½ are written out");
            let d = (2.0 - cz) / (24.0 * (z / 2.0).cos().powi(4));
            let s1_over_s0 = cz * (5.0 + cz * cz) / (2.0 * (2.0 + (2.0 * z).cos()));
            (c + c * c * d * (1.0 + s1_over_s0)) / (c + inv_s0)
        };
    }
    // (1/π)·Σ f·h = the mean of f.
    sum / n as f64 / k
}

/// The rail on discrete supports (60E1, a = 0.6 m, k = 40 MN/m, P = 100 kN, load mid-span
/// and over a support) against:
///
/// - (b) the dense reference assembled in this file: every node's deflection to 1e-9 of
///   the largest (both are exact for this system — the Hermite cubic is the exact
///   Euler–Bernoulli solution between nodes without load — so only round-off separates them);
/// - the exact infinite discretely supported beam of [`discrete_infinite_beam`], to 1e-9
///   (the FE rail is 60 m long with the load in the middle: the ends are 30 m away and
///   e^(−β·30) ≈ 3e-17 of the deflection reaches them, so it is infinite to round-off);
/// - (a) the continuous Winkler beam w0 = P·β/(2·k_f), k_f = k/a, β = (k_f/(4EI))^¼. The
///   exact solution above says how far a discretely supported rail is from it: for small βa,
///   evaluating the integral (not derived in closed form), w/w0 − 1 ≈ +(βa)⁴/72 with the
///   load mid-span (softer) and −(βa)⁴/144 over a support (stiffer), the coefficients
///   growing slowly with βa (+(βa)⁴/59 and −(βa)⁴/108 at βa = 0.76, +(βa)⁴/53 at βa = 1).
///   The tolerance we can justify for the Winkler closed form is therefore
///   |w/w0 − 1| ≤ (βa)⁴/50 (6.8e-3 here, βa = 0.763) with the sign set by the load
///   position. A support of 40 MN/m every 0.6 m is ordinary ballasted track; much stiffer
///   supports or wider spacing (βa → 1.2 and beyond) need the discrete solution.
#[test]
fn rail_on_discrete_supports_matches_winkler_and_dense_reference() {
    let sec = RailSection::uic60();
    let ei = sec.e * sec.i_vertical;
    let kf = K_SUPPORT / SPACING;
    let beta = (kf / (4.0 * ei)).powf(0.25);
    let ba4 = (beta * SPACING).powi(4);
    let w0 = P_LOAD * beta / (2.0 * kf);
    // The quadrature has converged: 400 and 4000 points agree to round-off.
    for u in [0.0, 0.5] {
        let (w1, w2) = (
            discrete_infinite_beam(ei, K_SUPPORT, SPACING, u, 400),
            discrete_infinite_beam(ei, K_SUPPORT, SPACING, u, 4000),
        );
        assert!((w1 - w2).abs() < 1e-13 * w2, "quadrature: {w1:e} vs {w2:e}");
    }
    // It tends to the Winkler beam for soft, dense supports, with the (βa)⁴/72 quoted below
    // (βa = 0.05: the (βa)² correction to the coefficient is about 0.1 %).
    {
        let a = 0.05;
        let k = 4.0 * ei * a; // k_f = 4EI: β = 1/m
        let w = discrete_infinite_beam(ei, k, a, 0.5, 4000);
        let d = w / (1.0 / (2.0 * k / a)) - 1.0;
        let coef = d / a.powi(4);
        assert!(
            (coef * 72.0 - 1.0).abs() < 5e-3,
            "βa = {a}: (w/w0 − 1)/(βa)⁴ = {coef:e}, 1/72 = {:e}",
            1.0 / 72.0
        );
    }
    // Node 101 is at 30.3 m, mid-way between the supports at 30.0 and 30.6 m; node 100 at
    // 30.0 m is over a support.
    for (load_index, u) in [(101usize, 0.5), (100, 0.0)] {
        let (stations, w) = rail_on_supports(load_index);
        assert!((stations[load_index] - (30.0 + u * SPACING)).abs() < 1e-9);
        // (b) The dense reference, every node.
        let wr = dense_reference(&stations, load_index);
        let scale = wr.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        let diff = w
            .iter()
            .zip(&wr)
            .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
        assert!(
            diff <= 1e-9 * scale,
            "u = {u}: FE vs dense reference differ by {diff:e} m (scale {scale:e} m)"
        );
        // The exact infinite discretely supported beam.
        let wd = P_LOAD * discrete_infinite_beam(ei, K_SUPPORT, SPACING, u, 2000);
        let under = -w[load_index];
        assert!(
            rel(under, wd) < 1e-9,
            "u = {u}: FE {under:e} m, infinite discrete beam {wd:e} m"
        );
        // (a) Winkler, within the discrete-support tolerance and on the right side.
        let ratio = under / w0;
        eprintln!(
            "u = {u}: βa = {:.4}, w = {under:.9e} m, discrete exact {wd:.9e} m (rel {:.1e}), Winkler {w0:.6e} m, w/w0 − 1 = {:.4e} = (βa)⁴/{:.1}; FE vs dense {:.1e}",
            beta * SPACING,
            rel(under, wd),
            ratio - 1.0,
            ba4 / (ratio - 1.0),
            diff / scale
        );
        assert!(
            (ratio - 1.0).abs() <= ba4 / 50.0,
            "u = {u}: w/w0 − 1 = {:e} exceeds (βa)⁴/50 = {:e}",
            ratio - 1.0,
            ba4 / 50.0
        );
        let softer = u == 0.5;
        assert_eq!(ratio > 1.0, softer, "u = {u}: w/w0 = {ratio}");
    }
}

// ------------------------------------------------------------------------------------------
// 5. `railfem track`
// ------------------------------------------------------------------------------------------

/// `railfem track --radius R --ct CT --out DIR` writes `track.csv` and `track.svg`: the CSV
/// has the documented header, its last station is the total length 16 208.3078 m (to the
/// printed precision of f64, 1e-9 m), the cant on the arc is Ct/R, zero on the straights, and
/// the radius column on the arc is R.
#[test]
fn cli_track_writes_the_report() {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("cli_track");
    let _ = std::fs::remove_dir_all(&dir);
    let argv: Vec<String> = ["track", "--radius", "3000", "--ct", "150", "--out"]
        .iter()
        .map(|s| s.to_string())
        .chain([dir.display().to_string()])
        .collect();
    let args = railfem::cli::parse(&argv).unwrap();
    assert_eq!(railfem::cli::run(&args).unwrap(), 0);
    let csv = std::fs::read_to_string(dir.join("track.csv")).unwrap();
    let svg = std::fs::read_to_string(dir.join("track.svg")).unwrap();
    assert!(svg.starts_with("<svg") || svg.starts_with("<?xml"));
    // The PNG beside it: the PNG signature, and the raster's size (IHDR width and height,
    // big-endian at bytes 16..24) equal to the SVG's declared width and height.
    let png = std::fs::read(dir.join("track.png")).unwrap();
    assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
    let be = |b: &[u8]| u32::from_be_bytes([b[0], b[1], b[2], b[3]]);
    let attr = |name: &str| -> u32 {
        let i = svg.find(&format!("{name}=\"")).unwrap() + name.len() + 2;
        svg[i..]
            .split('"')
            .next()
            .unwrap()
            .trim_end_matches("px")
            .parse()
            .unwrap()
    };
    assert_eq!(
        (be(&png[16..20]), be(&png[20..24])),
        (attr("width"), attr("height"))
    );
    let mut lines = csv.lines();
    assert_eq!(
        lines.next().unwrap(),
        "station [m],x [m],y [m],z [m],heading [rad],curvature [1/m],radius [m],cant [rad],e1x [-],e1y [-],e1z [-],e2x [-],e2y [-],e2z [-],e3x [-],e3y [-],e3z [-]"
    );
    let rows: Vec<Vec<f64>> = lines
        .map(|l| l.split(',').map(|x| x.parse::<f64>().unwrap()).collect())
        .collect();
    assert!(rows.iter().all(|r| r.len() == 17));
    let last = rows.last().unwrap();
    assert!(
        (last[0] - 16_208.307_8).abs() < 1e-9,
        "last station {}",
        last[0]
    );
    let (r, ct) = (3000.0, 150.0);
    let mut on_arc = 0;
    for row in &rows {
        let s = row[0];
        if (2500.0..=13_408.307_8).contains(&s) {
            on_arc += 1;
            assert!(rel(row[7], ct / r) < 1e-14, "cant {} at {s}", row[7]);
            assert!(rel(row[6], r) < 1e-12, "radius {} at {s}", row[6]);
        } else if !(500.0..=15_408.307_8).contains(&s) {
            assert_eq!(row[7], 0.0, "cant on a straight at {s}");
        }
    }
    assert!(on_arc > 1000, "{on_arc} rows on the arc");
    // Bad input is refused with a message, not a panic.
    for bad in [["--radius", "-5"], ["--ct", "-1"]] {
        let argv: Vec<String> = std::iter::once("track")
            .chain(bad)
            .map(String::from)
            .collect();
        let e = railfem::cli::run(&railfem::cli::parse(&argv).unwrap()).unwrap_err();
        assert!(e.to_string().contains(bad[0]), "{e}");
    }
}

//! Slab and bridge track models (issue 4) against closed forms:
//!
//! 1. one simply supported span under a midspan point load: `PL³/(48EI) + P/(2k_b)`;
//! 2. the same span under its self-weight: `5wL⁴/(384EI) + wL/(2k_b)`;
//! 3. a slab track under a point load on both rails: Hetényi's beam on an elastic
//!    foundation (rails and slab tied by stiff fasteners act as one beam);
//! 4. two spans: a load on span 1 bends span 2 only through the rails, and the girder end
//!    rotations at the joint are discontinuous (span 1 turns by `PL²/(16EI)`).
//!
//! In a bridge the girder and the slab share nodes, so their bending stiffnesses add:
//! `EI = E_g·I_g + E_s·I_s`. The continuous rails on their fasteners stiffen the span a
//! little more (rail–structure interaction): by their own bending `2·E_r·I_r` (3e-5 of EI),
//! by composite action through the fasteners' longitudinal springs at the slab depth `e`
//! (at most `2·E_r·A_r·e²`, 1e-3 of EI), and by restraining the girder end rotation where
//! they run on over the joint. Tests 1 and 4 therefore also run with fasteners 1e4 times
//! softer, which must bring the FE result onto the closed form.
//!
//! `cargo test --release --test bridge`.

use railfem::elements::rail::geometry::alignment::Alignment;
use railfem::elements::rail::geometry::bridge::{BridgeSpec, SlabTrack};
use railfem::elements::rail::geometry::cant::{Cant, Track};
use railfem::elements::rail::geometry::track_model::{
    self, RailSection, RailSupport, TrackMesh, TrackModel,
};
use railfem::framework::builder::ModelBuilder;
use railfem::framework::loads::{LoadSpec, TimeSeries};
use railfem::framework::model::{AnalysisKind, AnalysisSpec};
use railfem::framework::Dof;
use railfem::solvers::Driver;
use std::sync::Arc;

const SPAN: f64 = 30.0;
const APPROACH: f64 = 10.0;
const P: f64 = 1.0e6;
const GRAV: f64 = 9.81;

fn bridge_spec(spans: usize) -> BridgeSpec {
    BridgeSpec {
        span: SPAN,
        ..BridgeSpec::new(APPROACH, spans)
    }
}

/// A straight bridge of `spans` spans with 10 m approaches, meshed at 0.5 m, static.
fn bridge_model(spans: usize, gravity: bool) -> (ModelBuilder, Arc<TrackModel>) {
    let len = 2.0 * APPROACH + spans as f64 * SPAN;
    let track = Arc::new(Track::new(Alignment::straight(len), Cant::none()).unwrap());
    let mut b = ModelBuilder::new("bridge test");
    let mesh = TrackMesh {
        element_length: 0.5,
        support: RailSupport::Bridge(Box::new(bridge_spec(spans))),
        ..Default::default()
    };
    let tm = track_model::generate(&mut b, track, &mesh).unwrap();
    b.analysis(AnalysisSpec {
        kind: AnalysisKind::Static,
        gravity: gravity.then_some([0.0, 0.0, -GRAV]),
        ..Default::default()
    });
    (b, tm)
}

fn solve(b: ModelBuilder) -> Driver {
    let mut d = Driver::new(b.build().unwrap()).unwrap();
    d.static_solve(0.0, 1).unwrap();
    d
}

/// (lower, upper) bending stiffness of a span (N·m²), see the module documentation.
fn ei_bounds() -> (f64, f64) {
    let g = RailSection::pc_box_girder();
    let s = RailSection::concrete_slab();
    let r = RailSection::uic60();
    let e = SlabTrack::default().slab_depth;
    let low = g.e * g.i_vertical + s.e * s.i_vertical;
    (low, low + 2.0 * r.e * (r.i_vertical + r.a * e * e))
}

const K_BEARING: f64 = 1.0e10;

/// Midspan deflection of one span under a midspan load P: Euler–Bernoulli (exact at the
/// nodes for Hermite beams under nodal loads) plus the bearings: each end settles
/// `P/(2k_b)`, which moves midspan by the same amount. Tolerances: default fasteners 2e-3
/// (rail–structure interaction, module documentation; measured 1.3e-3); fasteners 1e4
/// times softer 1e-4 (what is left is of the order of the rails' own bending, 3.3e-5 of
/// EI; measured 3.4e-5). The bearings'
/// share (3.5 %) is far outside both.
#[test]
fn single_span_midspan_point_load() {
    for soft in [false, true] {
        let w = midspan_under_point_load(soft);
        let (lo, _) = ei_bounds();
        let cf = P * SPAN.powi(3) / (48.0 * lo) + P / (2.0 * K_BEARING);
        let rel = (w - cf).abs() / cf;
        println!("midspan (soft fasteners: {soft}): FE {w:.6e} m, closed form {cf:.6e} m, rel. {rel:.2e}");
        assert!(rel < if soft { 1e-4 } else { 2e-3 }, "{rel:e}");
        assert!((w - P * SPAN.powi(3) / (48.0 * lo)).abs() > 0.5 * P / (2.0 * K_BEARING));
    }
}

fn soften(tm_spec: &mut BridgeSpec) {
    for k in tm_spec.slab_track.fastener_k.iter_mut() {
        *k *= 1e-4;
    }
}

fn midspan_under_point_load(soft: bool) -> f64 {
    let len = 2.0 * APPROACH + SPAN;
    let track = Arc::new(Track::new(Alignment::straight(len), Cant::none()).unwrap());
    let mut b = ModelBuilder::new("bridge test");
    let mut spec = bridge_spec(1);
    if soft {
        soften(&mut spec);
    }
    let mesh = TrackMesh {
        element_length: 0.5,
        support: RailSupport::Bridge(Box::new(spec)),
        ..Default::default()
    };
    let tm = track_model::generate(&mut b, track, &mesh).unwrap();
    b.analysis(AnalysisSpec {
        kind: AnalysisKind::Static,
        ..Default::default()
    });
    let br = tm.bridge.as_ref().unwrap();
    let mid = br.midspan_node(0).unwrap();
    assert_eq!(br.spans[0].end - br.spans[0].start, SPAN);
    b.load(LoadSpec::Nodal {
        node: mid,
        dof: railfem::framework::Dof::Uz,
        value: -P,
        series: TimeSeries::Constant,
    });
    let d = solve(b);
    -d.displacement(mid, Dof::Uz).unwrap()
}

/// Self-weight: girder and slab weigh `w = g·(ρ_g·A_g + ρ_s·A_s)` per metre; the rails add
/// `2·g·ρ_r·A_r` (0.5 %), most of which the span carries. Closed form
/// `5wL⁴/(384EI) + wL/(2k_b)`; the FE result must lie between the form with
/// the lighter load (no rails) on the stiffer beam (upper EI bound) and the one with the
/// heavier load on the softer beam (girder and slab only). Consistent (Hermite) loads from the consistent mass make the nodal
/// deflections exact for a uniform load.
#[test]
fn single_span_self_weight() {
    let (b, tm) = bridge_model(1, true);
    let mid = tm.bridge.as_ref().unwrap().midspan_node(0).unwrap();
    let first = tm.bridge.as_ref().unwrap().spans[0].first_node;
    let d = solve(b);
    // Midspan deflection relative to the span ends (bearings) and absolute.
    let w = -d.displacement(mid, Dof::Uz).unwrap();
    let w_end = -d.displacement(first, Dof::Uz).unwrap();
    let (g, s, r) = (
        RailSection::pc_box_girder(),
        RailSection::concrete_slab(),
        RailSection::uic60(),
    );
    let q0 = GRAV * (g.rho * g.a + s.rho * s.a);
    let q1 = q0 + 2.0 * GRAV * r.rho * r.a;
    let (lo, hi) = ei_bounds();
    let cf = |q: f64, ei: f64| 5.0 * q * SPAN.powi(4) / (384.0 * ei) + q * SPAN / (2.0 * K_BEARING);
    println!(
        "self-weight: FE {w:.6e} m (ends {w_end:.3e}), closed form {:.6e} .. {:.6e} m",
        cf(q0, hi),
        cf(q1, lo)
    );
    assert!(w >= cf(q0, hi) * (1.0 - 1e-6) && w <= cf(q1, lo) * (1.0 + 1e-6));
    // Bearing settlement alone: q·L/(2k_b) (with or without rails).
    assert!(
        w_end >= q0 * SPAN / (2.0 * K_BEARING) * 0.999
            && w_end <= q1 * SPAN / (2.0 * K_BEARING) * 1.001
    );
}

/// A 200 m straight slab track meshed at 0.1 m with a fastener at every node, loaded by P
/// on both rails at 100 m. With very stiff fasteners (vertical 1e11 N/m) and no
/// longitudinal or pitch fastener stiffness (no composite action), rails and slab bend as
/// one beam `EI = E_s·I_s + 2·E_r·I_r` on the subgrade `k` (N/m per m), and Hetényi gives
/// `w(x) = (2P)·β/(2k)·e^{−βx}(cos βx + sin βx)`, `β = (k/(4EI))^{1/4}`.
///
/// Differences: the subgrade lumped at nodes (βh = 0.078: relative O((βh)²/12) ≈ 5e-4),
/// the fastener compliance under the load (P/k_f shared by several seats, < 1.3e-3 of w0),
/// the finite length (e^{−β·100} ≈ 1e-34). Tolerance 0.5 % of w(0) along the profile.
#[test]
fn slab_track_matches_hetenyi() {
    let len = 200.0;
    let h = 0.1;
    let k_sub = 1.0e8;
    let track = Arc::new(Track::new(Alignment::straight(len), Cant::none()).unwrap());
    let mut b = ModelBuilder::new("slab test");
    let slab = SlabTrack {
        fastener_spacing: h,
        fastener_k: [1.0e9, 1.0e11, 1.0e3, 0.0, 1.0e5, 1.0e6],
        fastener_c: [0.0; 6],
        subgrade_k: [5.0e8, k_sub, 5.0e8, 0.0, 0.0, 4.8e8],
        ..Default::default()
    };
    let mesh = TrackMesh {
        element_length: h,
        support: RailSupport::Slab(Box::new(slab.clone())),
        ..Default::default()
    };
    let tm = track_model::generate(&mut b, track, &mesh).unwrap();
    let i0 = tm.stations.partition_point(|s| *s < 100.0 - 1e-9);
    assert!((tm.stations[i0] - 100.0).abs() < 1e-9);
    for r in 0..2 {
        b.load(LoadSpec::Nodal {
            node: tm.rails[r].first_id + i0 as u64,
            dof: railfem::framework::Dof::Uz,
            value: -P / 10.0,
            series: TimeSeries::Constant,
        });
    }
    b.analysis(AnalysisSpec {
        kind: AnalysisKind::Static,
        ..Default::default()
    });
    let d = solve(b);
    let (s, r) = (slab.slab, RailSection::uic60());
    let ei = s.e * s.i_vertical + 2.0 * r.e * r.i_vertical;
    let beta = (k_sub / (4.0 * ei)).powf(0.25);
    let p2 = 2.0 * P / 10.0;
    let hetenyi = |x: f64| {
        p2 * beta / (2.0 * k_sub) * (-beta * x).exp() * ((beta * x).cos() + (beta * x).sin())
    };
    let w0 = hetenyi(0.0);
    let mut worst: f64 = 0.0;
    for di in 0..80 {
        let i = i0 + di;
        let x = tm.stations[i] - 100.0;
        let w = -d
            .displacement(tm.rails[0].first_id + i as u64, Dof::Uz)
            .unwrap();
        let w_right = -d
            .displacement(tm.rails[1].first_id + i as u64, Dof::Uz)
            .unwrap();
        // Symmetric load: both rails deflect alike.
        assert!((w - w_right).abs() < 1e-9 * w0);
        worst = worst.max((w - hetenyi(x)).abs() / w0);
    }
    println!("slab: w0 = {w0:.5e} m, largest difference {worst:.2e} of w0");
    assert!(worst < 5e-3, "slab track vs Hetényi: {worst:e}");
    // The slab node under the load follows the rails to within the fastener compression.
    let slab_node = tm.slab.as_ref().unwrap().node_at(i0).unwrap();
    let ws = -d.displacement(slab_node, Dof::Uz).unwrap();
    let wr = -d
        .displacement(tm.rails[0].first_id + i0 as u64, Dof::Uz)
        .unwrap();
    assert!(
        wr > ws && wr - ws < P / 10.0 / 1.0e11 * 1.001,
        "fastener: {wr} vs {ws}"
    );
}

/// Two spans, P at midspan of span 1. The girders are not continuous, so (a) span 1's end
/// turns by the simply supported slope `PL²/(16EI)`, to 1 % (the rails running on over the
/// joint restrain it, measured 0.27 %; the pier's axial shortening `(P/2)·H/(E_p·A_p)` over
/// L tilts the span by 0.2 % of the slope), (b) span 2's start turns by less than 2 % of that — a continuous
/// girder would turn it by the same amount, and (c) span 2's midspan moves by less than 1 %
/// of span 1's: only the rails and the shared pier connect them.
#[test]
fn adjacent_spans_are_independent() {
    let (mut b, tm) = bridge_model(2, false);
    let br = tm.bridge.as_ref().unwrap().clone();
    assert_eq!(br.spans.len(), 2);
    // Separate end nodes at the joint, same station.
    assert_ne!(br.spans[0].last_node, br.spans[1].first_node);
    assert_eq!(br.spans[0].end, br.spans[1].start);
    assert!(br.pier_tops[1].is_some() && br.pier_tops[0].is_none());
    b.load(LoadSpec::Nodal {
        node: br.midspan_node(0).unwrap(),
        dof: railfem::framework::Dof::Uz,
        value: -P,
        series: TimeSeries::Constant,
    });
    let d = solve(b);
    let ry = Dof::Ry;
    let th1 = d.displacement(br.spans[0].last_node, ry).unwrap().abs();
    let th2 = d.displacement(br.spans[1].first_node, ry).unwrap().abs();
    let (lo, hi) = ei_bounds();
    let pier = RailSection::rc_pier();
    let tilt = 0.5 * P * 10.0 / (pier.e * pier.a) / SPAN;
    let (slope_lo, slope_hi) = (P * SPAN * SPAN / (16.0 * hi), P * SPAN * SPAN / (16.0 * lo));
    println!("end rotations: span 1 {th1:.5e}, span 2 {th2:.5e} rad; closed form {slope_lo:.5e} .. {slope_hi:.5e}");
    let _ = slope_lo;
    assert!((th1 - slope_hi).abs() < 0.01 * slope_hi + tilt);
    assert!(th2 < 0.02 * th1);
    let w1 = d
        .displacement(br.midspan_node(0).unwrap(), Dof::Uz)
        .unwrap();
    let w2 = d
        .displacement(br.midspan_node(1).unwrap(), Dof::Uz)
        .unwrap();
    println!("midspan: span 1 {w1:.5e} m, span 2 {w2:.5e} m");
    assert!(w2.abs() < 0.01 * w1.abs());
}

/// The `[track]` table of a model file with `support = {type = "bridge", …}`: 120 m
/// straight, elements of 0.5 m, two 30 m spans from station 30, fasteners every 0.5 m.
/// Counted by hand: 241 stations (joints at 30, 60, 90 m fall on the mesh); rails 2·241
/// nodes; slab 241 + 3 (four segments: approach, two spans, approach, a second node at each
/// of the three joints); anchors 2·241; one pier (the middle joint) of 4 elements, 5 nodes
/// with the base fixed. Nodes 482 + 244 + 482 + 5 = 1213; equations 6·(482 + 244 + 4) =
/// 4380 (anchors are rigid-link slaves). An unknown key or a bridge off the track exits 2
/// with one line.
#[test]
fn model_file_bridge_counts_and_bad_keys() {
    let dir = std::env::temp_dir().join(format!("railfem_bridge_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let good = r#"
[track]
segments = [{type = "straight", length = 120}]
element_length = 0.5
support = {type = "bridge", start = 30, spans = 2, span = 30, slab_track = {fastener_spacing = 0.5}}

[analysis]
kind = "static"
"#;
    let f = dir.join("good.toml");
    std::fs::write(&f, good).unwrap();
    let model = railfem::load_model(&f).expect("model");
    assert_eq!(model.nodes.len(), 1213);
    let d = Driver::new(model).unwrap();
    assert_eq!(d.neq(), 4380);
    for (name, text, want) in [
        (
            "bad_key.toml",
            good.replace("span = 30,", "span = 30, spam = 1,"),
            "unknown field `spam`",
        ),
        (
            "bad_start.toml",
            good.replace("start = 30", "start = 80"),
            "outside the meshed track",
        ),
        (
            "bad_spans.toml",
            good.replace("spans = 2", "spans = 0"),
            "`spans` must be at least 1",
        ),
    ] {
        let p = dir.join(name);
        std::fs::write(&p, text).unwrap();
        let o = std::process::Command::new(env!("CARGO_BIN_EXE_railfem"))
            .arg("check")
            .arg(&p)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{name}: {err}");
        assert_eq!(err.trim().lines().count(), 1, "{name}: {err}");
        assert!(err.contains(name) && err.contains(want), "{name}: {err}");
    }
}

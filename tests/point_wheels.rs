//! Tests of the point-contact wheels `hertz_wheel` and `rigid_wheel` on small vehicles built
//! in Rust (`examples/wheel_models/case.rs`): static wheel loads against the lever rule,
//! the Hertz approach in closed form, the rail deflection under a slowly moving wheel
//! against the beam on elastic foundation, contact loss over a deep short dip (with the
//! wheelset's momentum balance), and the bad-input messages of both kinds. The elements'
//! tangents against finite differences and their re-picking of rail nodes are tested
//! inside `point_wheel.rs`.

#[path = "../examples/wheel_models/case.rs"]
#[allow(dead_code)]
mod case;
mod common;

use case::{build, Body, Case};
use common::check_bad_model;
use railfem::elements::rail::contact::point_contact_law::HERTZ_PRELOAD;
use railfem::elements::rail::geometry::track_model::{JointDip, RailSupport, TrackMesh};
use railfem::framework::model::IntegratorKind;

/// Hertz constant of the default (m/N^(2/3)).
const G: f64 = 4.95e-8;

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

/// A two-axle vehicle whose body centre is 3 m behind the front axle and 5 m ahead of the
/// rear one: the lever rule puts 5/8 of the body on the front wheelset and 3/8 on the rear.
fn two_axle(kind: &'static str) -> Case {
    Case {
        kind,
        axles: vec![3.0, -5.0],
        ws_mass: 1500.0,
        ws_load: 1500.0 * 9.81,
        body: Some(Body {
            mass: 30_000.0,
            inertia: [1.0e6, 1.0e6, 5.0e4],
            load: 30_000.0 * 9.81,
            k: [5e5, 1.2e6, 5e5, 0.0, 1e6, 1e6],
            c: [0.0; 6],
        }),
        ..Default::default()
    }
}

/// Static wheel loads equal the weight shares (lever rule plus the wheelset's own weight,
/// half per wheel), from zero load in a single Newton solve; the axle drops by the Hertz
/// approach `δ = G·Q^(2/3)` (hertz_wheel) or by the penalty's `Q/k` (rigid_wheel).
#[test]
fn static_wheel_loads_are_the_weight_shares_and_the_axle_drops_by_the_contact_law() {
    for kind in ["hertz_wheel", "rigid_wheel"] {
        let c = two_axle(kind);
        let mut v = build(&c).unwrap();
        // The whole load at once from the undeformed state: the Hertz wheel's tangent is
        // almost zero there (1 nm preload), so this is the hard start.
        let iters = v.d.static_solve(0.0, 1).unwrap();
        let body = c.body.as_ref().unwrap();
        let shares = [body.load * 5.0 / 8.0, body.load * 3.0 / 8.0];
        for (ws, share) in shares.iter().enumerate() {
            let q = 0.5 * (share + c.ws_load);
            for side in 0..2 {
                let got = v.out(ws, side, "Q");
                println!("{kind}: wheelset {ws} side {side}: Q = {got:.6} N, lever rule {q:.6} N ({iters} iterations)");
                // Newton stops at 1e-11 of the load: 1e-8 is a margin of 1000.
                assert!(rel(got, q) < 1e-8, "{kind} ws {ws}: Q {got} vs {q}");
                // Nothing pushes sideways or along the track.
                assert!(v.out(ws, side, "Y").abs() < 1e-6 * q);
                assert!(v.out(ws, side, "X").abs() < 1e-6 * q);
            }
            // The axle's drop (both wheels carry the same load, so K does not roll).
            let drop = -v.disp(v.ks[ws], 1);
            let expect = if kind == "hertz_wheel" {
                G * q.powf(2.0 / 3.0) - HERTZ_PRELOAD
            } else {
                q / 1e10
            };
            println!("{kind}: wheelset {ws}: drop {drop:.9e} m, closed form {expect:.9e} m");
            // dδ/δ = (2/3)·dQ/Q: 1e-8 in load is below 1e-8 in the drop.
            assert!(rel(drop, expect) < 1e-8, "{kind}: drop {drop} vs {expect}");
        }
    }
}

/// A wheelset (Q = 50 kN per wheel) on rails of 0.1 m beam elements on a vertical support
/// spring k_s = 1e7 N/m at every node (a foundation modulus k = k_s/0.1 m = 1e8 N/m²),
/// moved slowly — static solves at successive stations, forwards and backwards — sees the
/// deflection of a beam on an elastic foundation under a point load, Hetényi's
/// `w0 = Q·β/(2k)` with `β = (k/(4EI))^(1/4)`.
///
/// The wheels sit over the rails' beam lines (`contact_offset` = the rail offset), so the
/// load does not twist the rail. Two known differences, both small: the supports are
/// discrete (a separate beam-on-springs calculation gives 3e-6 relative for a load on a
/// support, 5e-6 midway, at β·h = 0.14), and between nodes the rail's Hermite elements
/// miss the deflection of the loaded element relative to its end nodes — exactly that of a
/// clamped-clamped beam of length h with the load at a, b from its ends,
/// `Q·a³·b³/(3·EI·h³)` (nodal values of Euler–Bernoulli elements with consistent loads are
/// exact), which is added back. What remains must be within 2e-5 (margin 4 on the
/// discreteness).
#[test]
fn rail_deflection_under_a_slowly_moving_wheel_is_the_beam_on_elastic_foundation() {
    let h = 0.1;
    let k_f: f64 = 1e8;
    let ei = 2.1e11 * 3.038e-5;
    let beta = (k_f / (4.0 * ei)).powf(0.25);
    let q = 50e3;
    let w0 = q * beta / (2.0 * k_f);
    for (kind, speed) in [
        ("hertz_wheel", 1.0),
        ("hertz_wheel", -1.0),
        ("rigid_wheel", 1.0),
    ] {
        let mut v = build(&Case {
            kind,
            wheel: serde_json::json!({"contact_offset": 1.435 / 2.0 + 0.036}),
            length: 14.0,
            start: 7.0,
            speed,
            mesh: TrackMesh {
                element_length: h,
                support: RailSupport::Discrete {
                    spacing: h,
                    // No rotational spring about the lateral axis: it would stiffen the
                    // rail's vertical bending (by 2 % here); torsion and lateral rotation
                    // are held.
                    k: [5e7, k_f * h, 5e7, 0.0, 1e5, 1e6],
                    c: [0.0; 6],
                },
                ..Default::default()
            },
            ws_load: 2.0 * q,
            ..Default::default()
        })
        .unwrap();
        let mut worst = 0.0f64;
        let mut elements = std::collections::BTreeSet::new();
        // Stations 7.0 to 8.2 m (forwards) or 7.0 to 5.8 m (backwards): on nodes and
        // between them, crossing elements in the direction of travel.
        for t in [0.0, 0.3, 0.45, 0.6, 0.77, 0.9, 1.2] {
            v.d.static_solve(t, 1).unwrap();
            let s = v.out(0, 0, "station");
            elements.insert((s / h).floor() as i64);
            for side in 0..2 {
                let got_q = v.out(0, side, "Q");
                assert!(rel(got_q, q) < 1e-8, "{kind}: Q {got_q}");
                // Rail deflection under the wheel: the axle's drop less the contact's
                // compression (Hertz δ − preload, or the penalty's Q/k).
                let contact = if kind == "hertz_wheel" {
                    v.out(0, side, "penetration") - HERTZ_PRELOAD
                } else {
                    q / 1e10
                };
                let w_fe = -v.disp(v.ks[0], 1) - contact;
                let (_, xi) = v.track.locate(s).unwrap();
                let (a, b) = (xi * h, (1.0 - xi) * h);
                let w_rail = w_fe + q * a.powi(3) * b.powi(3) / (3.0 * ei * h.powi(3));
                let e = rel(w_rail, w0);
                println!("{kind}: s = {s:.3} side {side}: w = {w_rail:.6e} m, relative difference {e:.2e}");
                worst = worst.max(e);
                // On a node, the rail node itself says the same.
                let i = ((s - v.track.stations[0]) / h).round() as usize;
                if (v.track.stations[i] - s).abs() < 1e-9 {
                    let node = -v.rail_up(side, i);
                    assert!(rel(node, w0) < 2e-5, "{kind}: rail node {node} vs {w0}");
                }
            }
        }
        println!(
            "{kind} at {speed} m/s: w0 = {w0:.6e} m, worst relative difference {worst:.2e}, {} elements",
            elements.len()
        );
        assert!(worst < 2e-5, "{kind}: {worst}");
        assert!(elements.len() >= 6, "the wheel must cross rail elements");
    }
}

/// The same static wheelset on a slab track (rails on fasteners on a slab): the rails are
/// flexible with a different support, both wheels carry half the load and the axle sinks
/// by more than the contact's own compression (the rails and the slab deflect, > 10 µm).
#[test]
fn wheelset_on_slab_track_carries_its_load() {
    for kind in ["hertz_wheel", "rigid_wheel"] {
        let mut v = build(&Case {
            kind,
            length: 20.0,
            start: 10.0,
            mesh: TrackMesh {
                element_length: 0.3,
                support: RailSupport::Slab(Box::default()),
                ..Default::default()
            },
            ws_load: 100e3,
            ..Default::default()
        })
        .unwrap();
        v.d.static_solve(0.0, 1).unwrap();
        for side in 0..2 {
            assert!(rel(v.out(0, side, "Q"), 50e3) < 1e-8);
        }
        // The contact's own compression: the Hertz approach or the penalty's Q/k.
        let contact = if kind == "hertz_wheel" {
            G * f64::powf(50e3, 2.0 / 3.0)
        } else {
            50e3 / 1e10
        };
        let drop = -v.disp(v.ks[0], 1);
        println!("{kind} on slab: drop {drop:.4e} m (contact alone {contact:.4e} m)");
        assert!(drop > contact + 1e-5, "{kind}: drop {drop}");
    }
}

/// A wheelset pressing 2 × 100 kN at the midspan of a single 29.75 m simply supported
/// girder (the bridge track's defaults: slab on fasteners on a PC box girder, EI =
/// 3.55e10 × 11 N·m², bearings 1e10 N/m vertically at each end). The girder's midspan
/// deflection is the simple span's `P·L³/(48·EI)` plus the mean bearing compression `P/(2k_b)`
/// (2.91e-4 m), less what the rail and slab gain by spreading the load: a load spread
/// evenly over a central length c deflects the span by `P(8L³ − 4Lc² + c³)/(384EI)`, a
/// fraction (c/L)²/2 less, 2.3e-3 for c = 2 m. Measured −1.4e-3 for both kinds; the test
/// allows −5e-3 to +1e-3.
#[test]
fn wheelset_at_midspan_of_a_bridge_bends_the_girder_as_a_simple_span() {
    let (span, start) = (29.75, 10.0);
    let p = 200e3;
    for kind in ["hertz_wheel", "rigid_wheel"] {
        let bridge: railfem::elements::rail::geometry::bridge::BridgeSpec =
            serde_json::from_value(serde_json::json!({"start": start, "spans": 1})).unwrap();
        let mut c = Case {
            kind,
            length: 2.0 * start + span,
            start: start + 0.5 * span,
            mesh: TrackMesh {
                element_length: 0.5,
                support: RailSupport::Bridge(Box::new(bridge)),
                ..Default::default()
            },
            ws_load: p,
            ..Default::default()
        };
        // The girder's stiffness (1e10 N/m and up) bounds the residual round-off near
        // 1e-6 N: an absolute tolerance of 1e-4 N is still 1e-9 of the load.
        c.analysis.newton.tol = 1e-10;
        c.analysis.newton.abs_tol = 1e-4;
        let mut v = build(&c).unwrap();
        v.d.static_solve(0.0, 1).unwrap();
        for side in 0..2 {
            assert!(rel(v.out(0, side, "Q"), 0.5 * p) < 1e-8);
        }
        let mid = v.track.bridge.as_ref().unwrap().midspan_node(0).unwrap();
        let n = v.d.model.node(mid).unwrap();
        // Straight, level track: up is global Z.
        let w = -v.disp(n, 2);
        let expect = p * span.powi(3) / (48.0 * 3.55e10 * 11.0) + p / (2.0 * 1e10);
        let e = (w - expect) / expect;
        println!(
            "{kind}: girder midspan deflection {w:.5e} m, simple span {expect:.5e} m ({e:+.2e})"
        );
        assert!((-5e-3..1e-3).contains(&e), "{kind}: {w} vs {expect}");
    }
}

/// A wheelset (2 × 50 kN) rolls at 50 m/s over rails of 0.125 m elements on a damped
/// support at every node. Once the start-up transient has died (after 0.15 s; it starts
/// from the static state, not the steady moving one), the wheel loads are periodic with
/// the passage of the supports, h/v = 2.5 ms = 5 steps: the wheel is stiffer over a support
/// than between two, a small parametric excitation (measured ±0.1 %). Periodicity (measured to
/// 3e-7) across 20 element joints says the element re-picks its rail nodes without a jump (the rail
/// point is C¹ across joints); the mean over whole periods equals the static load (the
/// wheelset does not accelerate on average, and 50 m/s is far below the track's critical
/// speed). Each crossing is a new sparsity pattern.
#[test]
fn rolling_on_flexible_rail_loads_are_periodic_with_the_supports() {
    use railfem::framework::model::IntegratorKind;
    let h: f64 = 0.125;
    let (speed, dt): (f64, f64) = (50.0, 5e-4);
    let period = (h / speed / dt).round() as usize;
    for kind in ["hertz_wheel", "rigid_wheel"] {
        let mut c = Case {
            kind,
            length: 24.0,
            start: 6.0,
            speed,
            mesh: TrackMesh {
                element_length: h,
                support: RailSupport::Discrete {
                    spacing: h,
                    k: [5e7, 1e8, 5e7, 1e5, 1e5, 1e6],
                    c: [5e4, 5e4, 5e4, 0.0, 0.0, 0.0],
                },
                ..Default::default()
            },
            ws_load: 100e3,
            ..Default::default()
        };
        c.analysis.integrator = IntegratorKind::GeneralizedAlpha;
        c.analysis.rho_inf = 0.0;
        c.analysis.newton.tol = 1e-10;
        c.analysis.newton.abs_tol = 1e-6;
        // The direct solver, whose pattern each crossing rebuilds (checked below).
        c.analysis.solver = railfem::framework::model::SolverChoice::Direct;
        c.analysis.dt = dt;
        let mut v = build(&c).unwrap();
        v.d.static_solve(0.0, 1).unwrap();
        v.d.initialize().unwrap();
        let patterns0 = v.d.asm.stats.patterns;
        let (mut q, mut elements) = (Vec::new(), std::collections::BTreeSet::new());
        for k in 1..=400 {
            v.d.step(dt).unwrap();
            if k as f64 * dt > 0.15 + 1e-9 {
                elements.insert((v.out(0, 0, "station") / h).floor() as i64);
                q.push([v.out(0, 0, "Q"), v.out(0, 1, "Q")]);
            }
        }
        let whole = q.len() / period * period;
        let mean = q[..whole].iter().map(|p| p[0] + p[1]).sum::<f64>() / (2 * whole) as f64;
        let spread = q
            .iter()
            .flatten()
            .fold(0.0f64, |m, x| m.max((x - mean).abs()))
            / mean;
        let periodic = q
            .windows(period + 1)
            .map(|w| {
                (w[period][0] - w[0][0])
                    .abs()
                    .max((w[period][1] - w[0][1]).abs())
            })
            .fold(0.0f64, f64::max)
            / mean;
        let patterns = v.d.asm.stats.patterns - patterns0;
        println!(
            "{kind}: mean Q {mean:.3} N, spread {spread:.2e}, periodicity error {periodic:.2e}, {} elements, {patterns} patterns",
            elements.len()
        );
        assert!(periodic < 1e-5, "{kind}: not periodic: {periodic:e}");
        assert!(spread < 5e-3, "{kind}: Q varies by {spread:e}");
        assert!(rel(mean, 50e3) < 1e-4, "{kind}: mean Q {mean}");
        assert!(elements.len() >= 20);
        assert!(patterns >= elements.len() - 1);
    }
}

/// A wheelset (1000 kg, pressed by 20 kN) runs at 30 m/s on rigid rails over a dipped
/// joint. The rail top falls away with acceleration `v²·w''`, at most `v²·depth·(2π/L)²`;
/// the wheelset can follow at most at `P/m` = 20 m/s². A 2 mm, 1 m dip (71 m/s²) throws the
/// wheels off the rail: Q reaches 0, the wheelset is then in free fall under P (its
/// acceleration is −P/m), and the wheels land again. A 0.1 mm dip (3.6 m/s²) keeps contact.
/// Over the whole run the wheelset's vertical momentum changes by exactly the impulse of
/// the contact forces and P (trapezoidal rule = the average-acceleration scheme).
#[test]
fn contact_is_lost_over_a_deep_short_dip_and_recovers() {
    let (m, p, v0) = (1000.0, 20e3, 30.0);
    for (depth, expect_loss) in [(2e-3, true), (1e-4, false)] {
        let mut c = Case {
            kind: "hertz_wheel",
            length: 30.0,
            start: 10.0,
            speed: v0,
            mesh: TrackMesh {
                dips: vec![JointDip {
                    station: 13.0,
                    depth,
                    length: 1.0,
                    ..Default::default()
                }],
                ..Default::default()
            },
            ws_mass: m,
            ws_inertia: [50.0, 400.0, 400.0],
            ws_load: p,
            ..Default::default()
        };
        c.analysis.integrator = IntegratorKind::Newmark;
        c.analysis.beta = 0.25;
        c.analysis.gamma = 0.5;
        c.analysis.newton.tol = 1e-10;
        c.analysis.newton.abs_tol = 1e-6;
        let mut v = build(&c).unwrap();
        v.d.static_solve(0.0, 1).unwrap();
        v.d.initialize().unwrap();
        let dt = 5e-5;
        let k = v.ks[0];
        let sum_q = |v: &case::Built| v.out(0, 0, "Q") + v.out(0, 1, "Q");
        assert!(rel(sum_q(&v), p) < 1e-8);
        let vel0 =
            v.d.asm
                .dofmap
                .value(&v.d.state.v, k, railfem::framework::Dof::Uy);
        let mut impulse = 0.0;
        let mut f_prev = sum_q(&v) - p;
        let (mut lost, mut landed_after_loss, mut free_fall_checked) = (false, false, 0);
        let mut q_min = f64::INFINITY;
        let mut q_max_after = 0.0f64;
        for _ in 0..2400 {
            v.d.step(dt).unwrap();
            let f = sum_q(&v) - p;
            impulse += 0.5 * dt * (f_prev + f);
            f_prev = f;
            q_min = q_min.min(v.out(0, 0, "Q"));
            let off = v.out(0, 0, "in_contact") == 0.0 && v.out(0, 1, "in_contact") == 0.0;
            if off {
                lost = true;
                // Free fall: the only force is P.
                let a = v.acc(k, 1);
                assert!((a + p / m).abs() < 1e-6 * p / m, "free fall: a = {a}");
                free_fall_checked += 1;
            } else if lost {
                landed_after_loss = true;
                q_max_after = q_max_after.max(v.out(0, 0, "Q"));
            }
        }
        let vel1 =
            v.d.asm
                .dofmap
                .value(&v.d.state.v, k, railfem::framework::Dof::Uy);
        let momentum = m * (vel1 - vel0);
        println!(
            "dip {depth} m: lost = {lost} ({free_fall_checked} steps off), min Q = {q_min:.1} N, max Q after landing {q_max_after:.0} N; m·Δv = {momentum:.6} N·s, impulse {impulse:.6} N·s"
        );
        assert!(
            (momentum - impulse).abs() < 1e-6 * p * 2400.0 * dt,
            "momentum {momentum} vs impulse {impulse}"
        );
        assert_eq!(lost, expect_loss, "dip {depth}");
        if expect_loss {
            assert!(landed_after_loss, "the wheels never came back");
            assert_eq!(q_min, 0.0);
            // The landing is an impact: more than the static load.
            assert!(q_max_after > 0.5 * p);
        } else {
            assert!(q_min > 0.5 * 0.5 * p, "min Q {q_min}");
        }
    }
}

/// Moved slowly across a dipped joint on rigid rails (static solves at successive
/// stations), the axle follows the rail top: its drop is the dip's depth there plus the
/// contact's compression under the unchanged load, `z(s) − G·Q^(2/3)` (Hertz, with its
/// 1 nm preload) or `z(s) − Q/k` (rigid), for both wheels' shared dip. The stations are
/// 1 cm apart: between two the rail drops by at most 3.1e-5 m (the dip's largest slope
/// is 3.06e-3), less than the Hertz compression of 6.7e-5 m, so each static solve starts in
/// contact (a Hertz wheel in the air has no vertical stiffness: statics needs contact).
#[test]
fn axle_follows_the_dip_at_low_speed() {
    let dip = JointDip {
        station: 21.0,
        depth: 1.5e-3,
        length: 2.0,
        ..Default::default()
    };
    let q = 50e3;
    for kind in ["hertz_wheel", "rigid_wheel"] {
        let mut v = build(&Case {
            kind,
            speed: 1.0,
            mesh: TrackMesh {
                dips: vec![dip],
                ..Default::default()
            },
            ws_load: 2.0 * q,
            ..Default::default()
        })
        .unwrap();
        let contact = if kind == "hertz_wheel" {
            G * q.powf(2.0 / 3.0) - HERTZ_PRELOAD
        } else {
            q / 1e10
        };
        let mut worst = 0.0f64;
        for j in 0..=240 {
            let t = 0.01 * j as f64;
            v.d.static_solve(t, 1).unwrap();
            let s = v.out(0, 0, "station");
            let expect = dip.height(s) - contact;
            let got = v.disp(v.ks[0], 1);
            worst = worst.max((got - expect).abs());
            assert!(rel(v.out(0, 0, "Q"), q) < 1e-8);
        }
        println!("{kind}: largest difference from the dip profile {worst:.2e} m");
        // Newton's tolerance on the load (1e-11) moves the axle by far less than 1e-12 m.
        assert!(worst < 1e-12, "{kind}: {worst}");
    }
}

/// A model with one hertz_wheel or rigid_wheel element and the track, for bad input.
fn wheel_model(kind: &str, keys: &str, track: bool) -> String {
    let t = if track {
        "[track]\nsegments = [{type = \"straight\", length = 30.0}]\n"
    } else {
        ""
    };
    format!(
        "[analysis]\nkind = \"static\"\n\n{t}\n[[node]]\nid = 1\nxyz = [15.0, 0.0, 0.43]\n\n[[element]]\ntype = \"{kind}\"\nid = 7\nnodes = [1]\n{keys}\n"
    )
}

/// Each bad wheel is refused in one line naming the file, the element, the key and the fix.
#[test]
fn bad_point_wheels_are_refused() {
    for kind in ["hertz_wheel", "rigid_wheel"] {
        check_bad_model(
            "side.toml",
            &wheel_model(kind, "side = \"middle\"", true),
            &[
                kind,
                "`side`",
                "unknown variant `middle`, expected `left` or `right`",
            ],
        );
        check_bad_model(
            "offtrack.toml",
            &wheel_model(kind, "side = \"left\"\ncontact_offset = 0.5", true),
            &[
                kind,
                "`contact_offset` = 0.5",
                "off the track",
                "0.7175 to 0.7895",
            ],
        );
        check_bad_model(
            "notrack.toml",
            &wheel_model(kind, "side = \"right\"", false),
            &[kind, "no track named `track`", "add a [track] table"],
        );
        check_bad_model(
            "carried.toml",
            &wheel_model(kind, "side = \"right\"", true),
            &[kind, "not carried by any vehicle"],
        );
    }
    for g in ["0.0", "-4.95e-8"] {
        check_bad_model(
            "hertz_g.toml",
            &wheel_model("hertz_wheel", &format!("side = \"left\"\nG = {g}"), true),
            &["hertz_wheel", "`G` = ", "give the Hertz constant > 0"],
        );
    }
    check_bad_model(
        "rigid_k.toml",
        &wheel_model("rigid_wheel", "side = \"left\"\nk = 0.0", true),
        &["rigid_wheel", "`k` = 0", "give a stiffness > 0 N/m"],
    );
    check_bad_model(
        "hertz_key.toml",
        &wheel_model("hertz_wheel", "side = \"left\"\nmu = 0.3", true),
        &["hertz_wheel", "unknown key `mu`"],
    );
}

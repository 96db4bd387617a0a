//! Checks of the wheel and rail defects (docs/defects.md) against independent references:
//!
//! - the P2 force of a dipped joint against Jenkins' formula, at three speeds;
//! - the speed at which a wheel with a rounded flat first leaves a rigid rail, against the
//!   geometric estimate and a one-mass Hertz model integrated here;
//! - the dynamic wheel load of a polygonal wheel against the receptance model of wheel,
//!   contact and a damped beam on an elastic foundation at the passing frequency.
//!
//! The vehicles are one wheelset built in Rust (`examples/wheel_models/case.rs`) with
//! `hertz_wheel` wheels; the defects are given as the wheels' `defect` key and the track's
//! `dips`, as a model file gives them.

#[path = "../examples/wheel_models/case.rs"]
#[allow(dead_code)]
mod case;
mod common;

use case::{build, Case, R0};
use common::check_bad_model;
use nalgebra::Complex;
use railfem::elements::rail::geometry::track_model::{
    DipShape, JointDip, RailSection, RailSide, RailSupport, TrackMesh,
};
use railfem::framework::model::IntegratorKind;
use std::f64::consts::PI;

/// Hertz constant of the default (m/N^(2/3)).
const G: f64 = 4.95e-8;

/// Jenkins et al. (1974)'s P2 force of a dipped joint, as Esveld (2001, *Modern Railway
/// Track*, §13) and the British literature give it:
///
/// ```text
/// P2 = P0 + 2α·V·√(Mu/(Mu + Mt))·[1 − C·π/(4·√(K·(Mu + Mt)))]·√(K·Mu)
/// ```
///
/// It is the lumped two-mass model's answer: the unsprung mass `Mu` rides rigidly on the
/// track mass `Mt`, which stands on the track spring `K` and damper `C`. The total joint
/// angle 2α turns the wheel's vertical velocity by `2αV` at the joint; with rigid contact
/// the two masses share the momentum, `(Mu + Mt)·v0 = Mu·2αV`, and then swing on `K`:
/// the spring force peaks at `K·v0/ω = 2αV·Mu·√(K/(Mu + Mt))` (the formula's product of
/// roots), reduced by the damping to first order in `ζ = C/(2√(K(Mu + Mt)))`,
/// `e^{−ζπ/2} ≈ 1 − Cπ/(4√(K(Mu + Mt)))`. The dynamic part returned here, `P2 − P0`, is
/// the track spring's force increment.
fn jenkins_p2_dynamic(two_alpha: f64, v: f64, mu: f64, mt: f64, k: f64, c: f64) -> f64 {
    let m = mu + mt;
    two_alpha * v * (mu / m).sqrt() * (1.0 - c * PI / (4.0 * (k * m).sqrt())) * (k * mu).sqrt()
}

/// A dipped joint given by its total angle 2α (`dips` with `angle` and the `vee` shape:
/// straight ramps of slope α into the joint, 12 m long), on a lumped track: each rail is
/// a 16 m beam made rigid (vertical I = 3 m⁴, so βℓ = 0.7: it moves as a block) of mass
/// Mt = 245 kg on 33 vertical springs of total stiffness K = 150 MN/m and dampers of total
/// C = 55.1 kN·s/m; the wheel's unsprung mass is Mu = 800 kg (a 1600 kg wheelset) under a
/// static load P0 = 100 kN per wheel. The P2 force is the track springs' force: the sum
/// over the rail's supports of k·(−w), its largest increment after the joint.
///
/// 2α = 0.4 mrad (1.2 mm deep): the formula, like the model, is linear in 2α, and the
/// stiff contact below must not bounce — the joint's P1 impact, `2αV·√(k_H·m_e)`
/// (`m_e = Mu·Mt/(Mu + Mt)`), is at most 82 kN at 40 m/s, below P0, so the wheel stays on
/// the rail (asserted at every step), as the formula assumes.
///
/// Jenkins' formula assumes what the lumped model has, plus three idealisations whose
/// sizes set the tolerance, 5 %:
/// - **rigid contact**: the wheels' Hertz constant is set 100 times stiffer than steel's
///   (G/100), so the contact's compliance shifts the P2 mode by K/k_H ≈ 1e-3 and its own
///   (P1) ringing enters the track force at ≈ 1.4 % of P2 (the ratio of the P1 mode's
///   track displacement to the P2 mode's, which scales as 1/√k_H: 14 % with steel's G);
/// - **damping to first order**: the exact peak of a damped impulse response,
///   `exp(−ζ·atan(√(1−ζ²)/ζ)/√(1−ζ²))`, is 0.900 at ζ = 0.070 against the formula's
///   0.891: 1 %;
/// - **a single kink**: a real dip also has the entry kink (α, half the joint's), 6 m
///   ahead of the joint; its P2 ringing decays by `e^{−ζω·6 m/V}` ≤ 0.02 at 40 m/s
///   before the joint: ≤ 1 %.
///
/// The block's pitch is held by stiff rotational springs at the supports (without them, the
/// pitching that the entry kink starts, 6 m off the block's centre, is still ringing when
/// the wheel crosses the joint, and the wheel sees the block's slope as a few per cent more
/// joint angle); they carry no vertical force, so the track spring is still K. The exact
/// lumped model (the two impulses, damping exact) gives +1.1, +0.9, +0.1 % against the
/// formula at 20, 30, 40 m/s.
#[test]
fn dipped_joint_p2_force_follows_jenkins() {
    let (mu, mt, k_total, c_total, p0) = (800.0, 245.0, 150e6, 55.1e3, 100e3);
    let two_alpha = 4e-4;
    let (length, spacing, ramp) = (16.0, 0.5, 12.0);
    let joint = 8.0;
    let n_supports = (length / spacing) as usize + 1;
    let sec = RailSection::uic60();
    let rail = RailSection {
        i_vertical: 3.0,
        i_lateral: 3.0,
        j: 3.0,
        rho: mt / (sec.a * length),
        ..sec
    };
    let ks = k_total / n_supports as f64;
    let cs = c_total / n_supports as f64;
    for v0 in [20.0, 30.0, 40.0] {
        let start = joint - 0.5 * ramp - 0.5;
        let mut c = Case {
            kind: "hertz_wheel",
            wheel: serde_json::json!({"G": G / 100.0, "contact_offset": 1.435 / 2.0 + 0.036}),
            length,
            start,
            speed: v0,
            mesh: TrackMesh {
                element_length: spacing,
                rail,
                support: RailSupport::Discrete {
                    spacing,
                    // A stiff rotational spring about the lateral axis holds the block's
                    // pitch: it carries moments, not vertical force, so K stays the sum
                    // of the vertical springs.
                    k: [1e9, ks, 1e9, 1e10, 1e8, 1e8],
                    c: [0.0, cs, 0.0, 0.0, 0.0, 0.0],
                },
                dips: vec![JointDip {
                    station: joint,
                    length: ramp,
                    angle: Some(two_alpha),
                    shape: DipShape::Vee,
                    ..Default::default()
                }],
                ..Default::default()
            },
            ws_mass: 2.0 * mu,
            ws_inertia: [100.0, 400.0, 400.0],
            ws_load: 2.0 * p0,
            ..Default::default()
        };
        c.analysis.integrator = IntegratorKind::GeneralizedAlpha;
        c.analysis.rho_inf = 0.8;
        // The rigid rail block's stiffness (12·EI/h³ ≈ 6e13 N/m) leaves rounding residuals
        // of some 1e-5 N: the absolute tolerance is 1e-3 N, 1e-8 of the load.
        c.analysis.newton.abs_tol = 1e-3;
        let mut v = build(&c).unwrap();
        v.d.static_solve(0.0, 1).unwrap();
        v.d.initialize().unwrap();
        let nodes = v.track.stations.len();
        let spring = |v: &case::Built| -> f64 { (0..nodes).map(|i| -ks * v.rail_up(0, i)).sum() };
        let static_force = spring(&v);
        assert!(
            (static_force - p0).abs() < 1e-6 * p0,
            "static {static_force}"
        );
        let dt = 1e-4;
        let t_end = (joint + 1.2 - start) / v0;
        let mut p2: f64 = 0.0;
        let mut t = 0.0;
        while t < t_end {
            v.d.step(dt).unwrap();
            t += dt;
            if start + v0 * t > joint {
                p2 = p2.max(spring(&v) - p0);
            }
            assert!(
                v.out(0, 0, "in_contact") == 1.0,
                "the wheel left the rail at {t} s"
            );
        }
        let jenkins = jenkins_p2_dynamic(two_alpha, v0, mu, mt, k_total, c_total);
        let e = (p2 - jenkins) / jenkins;
        println!(
            "V = {v0} m/s: P2 − P0 = {:.2} kN (railfem), {:.2} kN (Jenkins), difference {:+.2} %",
            p2 / 1e3,
            jenkins / 1e3,
            100.0 * e
        );
        assert!(e.abs() < 0.05, "V = {v0}: {p2} vs {jenkins}");
    }
}

/// A 1-mass Hertz wheel on a rigid rail over a tread deviation `e(x)`: `m·ÿ = Q − P0`,
/// `Q = (δ/G)^{3/2}` for `δ = G·P0^{2/3} + e(vt) − y > 0`, else 0 (y up from the static
/// state). Integrated by RK4 at 1 µs; returns the smallest Q.
fn hertz_wheel_min_load(m: f64, p0: f64, speed: f64, e: impl Fn(f64) -> f64, span: f64) -> f64 {
    let d0 = G * p0.powf(2.0 / 3.0);
    let q = |t: f64, y: f64| {
        let d = d0 + e(speed * t) - y;
        if d > 0.0 {
            (d / G).powf(1.5)
        } else {
            0.0
        }
    };
    let dt = 1e-6;
    let (mut y, mut w, mut t) = (0.0, 0.0, 0.0);
    let mut q_min = f64::INFINITY;
    let f = |t: f64, y: f64, w: f64| (w, (q(t, y) - p0) / m);
    while t < span / speed {
        let (k1y, k1w) = f(t, y, w);
        let (k2y, k2w) = f(t + 0.5 * dt, y + 0.5 * dt * k1y, w + 0.5 * dt * k1w);
        let (k3y, k3w) = f(t + 0.5 * dt, y + 0.5 * dt * k2y, w + 0.5 * dt * k2w);
        let (k4y, k4w) = f(t + dt, y + dt * k3y, w + dt * k3w);
        y += dt / 6.0 * (k1y + 2.0 * k2y + 2.0 * k3y + k4y);
        w += dt / 6.0 * (k1w + 2.0 * k2w + 2.0 * k3w + k4w);
        t += dt;
        q_min = q_min.min(q(t, y));
    }
    q_min
}

/// A wheelset (600 kg per wheel, static wheel load Q0 = 50 kN) with a rounded flat of
/// length L = 80 mm and depth d = 0.6 mm on both wheels rolls on rigid rails.
///
/// **Geometric estimate.** The flat's path `e(x) = −(d/2)(1 + cos(2πx/L))` asks the
/// wheel centre for the acceleration `v²·e''`; its largest downward value is at the flat's
/// ends, `v²·(d/2)(2π/L)²`. The contact can pull the wheel down by at most `Q0/m` (all of
/// its load gone; `g + P/m` with P the load the suspension puts on the unsprung mass m), so
/// the wheel follows the flat (quasi-statically) up to
/// `v_qs = (L/2π)·√(2·Q0/(m·d))`. That is the estimate when the contact is slow to respond
/// to the demand; but the demand jumps from zero to its largest value as the wheel enters
/// the flat (the rounded flat is C¹: its curvature steps), and an undamped contact spring
/// answers a step of demanded acceleration with twice its static unloading. A contact
/// infinitely stiff against the flat's time scale therefore leaves the rail from
/// `v_qs/√2`. The Hertz contact lies between (its period, 4.6 ms, against the 3.4 ms the
/// wheel takes from a flat's end to its quarter point at v_qs), so the check is two-fold:
/// - the first speed of contact loss of the one-mass Hertz model integrated here
///   (bisection on the speed), `v_ode`, lies between `v_qs/√2` and `v_qs`;
/// - railfem keeps contact at 0.97·v_ode and loses it at 1.03·v_ode, and its smallest
///   load at 0.97·v_ode equals the one-mass model's within 0.2 % of Q0. (The same model:
///   what differs is the time integration, average acceleration at 20 µs against RK4 at
///   1 µs, (ω·Δt)²/12 = 6e-5 in the contact's period, and the 1 nm Hertz start: 1e-5 of
///   Q0.)
#[test]
fn flat_wheel_leaves_the_rail_at_the_estimated_speed() {
    let (m, q0, l, d): (f64, f64, f64, f64) = (600.0, 50e3, 0.08, 0.6e-3);
    let v_qs = l / (2.0 * PI) * (2.0 * q0 / (m * d)).sqrt();
    let before = 0.05;
    let e = |x: f64| {
        let x = x - before - 0.5 * l;
        if x.abs() < 0.5 * l {
            -0.5 * d * (1.0 + (2.0 * PI * x / l).cos())
        } else {
            0.0
        }
    };
    let span = before + l + 0.1;
    let (mut lo, mut hi) = (0.5 * v_qs, 1.5 * v_qs);
    assert!(hertz_wheel_min_load(m, q0, lo, e, span) > 0.0);
    assert!(hertz_wheel_min_load(m, q0, hi, e, span) == 0.0);
    for _ in 0..30 {
        let mid = 0.5 * (lo + hi);
        if hertz_wheel_min_load(m, q0, mid, e, span) > 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let v_ode = 0.5 * (lo + hi);
    println!(
        "flat L = {l} m, d = {d} m: v_qs = {v_qs:.3} m/s, v_qs/√2 = {:.3} m/s, one-mass Hertz model {v_ode:.3} m/s",
        v_qs / 2f64.sqrt()
    );
    assert!(v_ode > v_qs / 2f64.sqrt() && v_ode < v_qs);
    // The flat's centre is at rolling angle (before + L/2)/R from the start.
    let angle = (before + 0.5 * l) / R0;
    for (factor, expect_loss) in [(0.97, false), (1.03, true)] {
        let speed = factor * v_ode;
        let mut c = Case {
            kind: "hertz_wheel",
            wheel: serde_json::json!({"defect": {"type": "flat", "length": l, "depth": d, "angle": angle}}),
            length: 10.0,
            start: 5.0,
            speed,
            ws_mass: 2.0 * m,
            ws_inertia: [100.0, 400.0, 400.0],
            ws_load: 2.0 * q0,
            ..Default::default()
        };
        c.analysis.integrator = IntegratorKind::Newmark;
        c.analysis.beta = 0.25;
        c.analysis.gamma = 0.5;
        let mut v = build(&c).unwrap();
        v.d.static_solve(0.0, 1).unwrap();
        v.d.initialize().unwrap();
        let dt = 2e-5;
        let steps = (span / speed / dt).ceil() as usize;
        let (mut q_min, mut lost) = (f64::INFINITY, false);
        for _ in 0..steps {
            v.d.step(dt).unwrap();
            q_min = q_min.min(v.out(0, 0, "Q"));
            lost |= v.out(0, 0, "in_contact") == 0.0;
        }
        let ode = hertz_wheel_min_load(m, q0, speed, e, span);
        println!(
            "{factor}·v_ode = {speed:.3} m/s: railfem min Q = {q_min:.0} N (contact lost: {lost}), one-mass model {ode:.0} N"
        );
        assert_eq!(lost, expect_loss, "at {speed} m/s");
        if !expect_loss {
            assert!((q_min - ode).abs() < 2e-3 * q0, "{q_min} vs {ode}");
        }
    }
}

/// A polygonal wheel (order n = 6, amplitude a = 20 µm) on both wheels of a 1200 kg
/// wheelset (Q0 = 60 kN per wheel) at 20 m/s on 60E1 rails on a vertical support of
/// k = 1e7 N/m and c = 2e3 N·s/m every 0.1 m (a foundation of 1e8 N/m² and 2e4 N·s/m²).
///
/// **Receptance model.** At the passing frequency ω = n·v/R, with all receptances
/// displacement per force in the direction of the force: the wheel (half the wheelset
/// moving as a rigid mass, both wheels in phase) `α_w = −1/(m·ω²)`; the contact, Hertz
/// linearised at Q0, `α_c = 1/k_H`, `k_H = dQ/dδ = (3/2)·Q0^{1/3}/G`; the rail, an infinite
/// Euler–Bernoulli beam on a damped Winkler foundation, `α_r = 1/(8·EI·β³)` with
/// `β⁴ = (k_f + iωc_f − ρA·ω²)/(4·EI)` (the principal root: Hetényi's point receptance, the
/// static `Q·β/(2k)` continued to the complex dynamic stiffness). A tread deviation `e`
/// compresses the contact by `δ = e − (α_w + α_r)·ΔQ` and `δ = α_c·ΔQ`, so
/// `|ΔQ| = a/|α_w + α_c + α_r|` (as e.g. Thompson, *Railway Noise and Vibration*, 2009,
/// ch. 5, writes it for roughness).
///
/// railfem's ΔQ is the amplitude of the harmonic at ω least-squares fitted to Q(t) over
/// the last 10 periods of a 0.36 s run. Tolerance 2 %: what the closed form leaves out is
/// the load's motion (a moving load at 20 m/s against the beam's critical speed of
/// 916 m/s: (v/v_cr)² = 5e-4), the supports' spacing (0.1 m against a wavelength of about
/// 4 m), the rail's ends (4 m from the wheel, β ≈ 1.4/m: e^{−2·1.4·4} ≈ 1e-5), the Hertz
/// law's curvature (ΔQ/Q0 ≈ 2.5 %, second order: ≈ 0.1 %), the start-up transient (its
/// decay over the 0.2 s before the fit) and the time step (72 steps per period).
#[test]
fn polygonal_wheel_load_matches_the_receptance_model() {
    let (order, a, v0) = (6u32, 20e-6, 20.0);
    let (m_ws, q0) = (1200.0, 60e3);
    let (h, k_f, c_f) = (0.1, 1e8, 2e4);
    let sec = RailSection::uic60();
    let ei = sec.e * sec.i_vertical;
    let rho_a = sec.rho * sec.a;
    let omega = order as f64 * v0 / R0;
    let mut c = Case {
        kind: "hertz_wheel",
        wheel: serde_json::json!({
            "contact_offset": 1.435 / 2.0 + 0.036,
            "defect": {"type": "polygon", "harmonics": [{"order": order, "amplitude": a}]},
        }),
        length: 16.0,
        start: 4.0,
        speed: v0,
        mesh: TrackMesh {
            element_length: h,
            support: RailSupport::Discrete {
                spacing: h,
                k: [5e7, k_f * h, 5e7, 0.0, 1e5, 1e6],
                c: [0.0, c_f * h, 0.0, 0.0, 0.0, 0.0],
            },
            ..Default::default()
        },
        ws_mass: m_ws,
        ws_inertia: [100.0, 400.0, 400.0],
        ws_load: 2.0 * q0,
        ..Default::default()
    };
    c.analysis.integrator = IntegratorKind::Newmark;
    c.analysis.beta = 0.25;
    c.analysis.gamma = 0.5;
    let mut v = build(&c).unwrap();
    v.d.static_solve(0.0, 1).unwrap();
    v.d.initialize().unwrap();
    let period = 2.0 * PI / omega;
    let dt = period / 72.0;
    let (fit_from, t_end) = (0.36 - 10.0 * period, 0.36);
    let (mut t, mut rows) = (0.0, Vec::new());
    while t < t_end - 0.5 * dt {
        v.d.step(dt).unwrap();
        t += dt;
        if t > fit_from {
            rows.push((t, v.out(0, 0, "Q")));
        }
    }
    // Least squares for Q = c0 + c1·cos ωt + c2·sin ωt.
    let mut ata = nalgebra::Matrix3::<f64>::zeros();
    let mut atb = nalgebra::Vector3::<f64>::zeros();
    for &(t, q) in &rows {
        let r = nalgebra::Vector3::new(1.0, (omega * t).cos(), (omega * t).sin());
        ata += r * r.transpose();
        atb += r * q;
    }
    let coef = ata.lu().solve(&atb).unwrap();
    let dq = (coef[1] * coef[1] + coef[2] * coef[2]).sqrt();
    // The receptances.
    let w = Complex::new(omega, 0.0);
    let alpha_w = Complex::new(-1.0 / (0.5 * m_ws * omega * omega), 0.0);
    let k_h = 1.5 * q0.powf(1.0 / 3.0) / G;
    let alpha_c = Complex::new(1.0 / k_h, 0.0);
    let kappa = Complex::new(k_f - rho_a * omega * omega, 0.0) + Complex::new(0.0, 1.0) * w * c_f;
    let beta = (kappa / (4.0 * ei)).powf(0.25);
    let alpha_r = Complex::new(1.0, 0.0) / (8.0 * ei * beta * beta * beta);
    let expect = a / (alpha_w + alpha_c + alpha_r).norm();
    let e = (dq - expect) / expect;
    println!(
        "f = {:.2} Hz: ΔQ = {dq:.1} N (railfem), {expect:.1} N (receptances: wheel {:.3e}, contact {:.3e}, rail {:.3e} m/N), difference {:+.2} %; mean Q {:.0} N",
        omega / (2.0 * PI),
        alpha_w.re,
        alpha_c.re,
        alpha_r.norm(),
        100.0 * e,
        coef[0]
    );
    assert!(e.abs() < 0.02, "{dq} vs {expect}");
}

/// The rail defects of `dips`: an angle gives the depth of each shape (its largest slope
/// is half the total angle), and a defect on one rail leaves the other alone.
#[test]
fn dip_angle_and_rail_side() {
    let two_alpha = 8e-3;
    for shape in [DipShape::SquaredCosine, DipShape::Cosine, DipShape::Vee] {
        let dip = JointDip {
            station: 10.0,
            length: 1.2,
            angle: Some(two_alpha),
            shape,
            rail: RailSide::Left,
            ..Default::default()
        };
        // Largest slope by central differences over the dip.
        let h = 1e-6;
        let slope = (0..=12000)
            .map(|i| 9.4 + i as f64 * 1e-4)
            .map(|s| ((dip.height(s + h) - dip.height(s - h)) / (2.0 * h)).abs())
            .fold(0.0, f64::max);
        let depth = dip.effective_depth();
        println!("{shape:?}: depth {depth:.4e} m, largest slope {slope:.6e}");
        assert!(
            (slope - 0.5 * two_alpha).abs() < 1e-4 * two_alpha,
            "{shape:?}: {slope}"
        );
        assert_eq!(dip.height_on(1, 10.0), 0.0);
        assert!((dip.height_on(0, 10.0) + depth).abs() < 1e-15);
    }
}

/// A model with a track (its `dips` line given) and one hertz_wheel with the keys given.
fn defect_model(dips: &str, keys: &str) -> String {
    format!(
        "[analysis]\nkind = \"static\"\n\n[track]\nsegments = [{{type = \"straight\", length = 30.0}}]\n{dips}\n\n[[node]]\nid = 1\nxyz = [15.0, 0.0, 0.43]\n\n[[element]]\ntype = \"hertz_wheel\"\nid = 7\nnodes = [1]\nside = \"left\"\n{keys}\n"
    )
}

/// Bad defects are refused in one line naming the file, the place and the fix (exit 2).
#[test]
fn bad_defects_are_refused() {
    check_bad_model(
        "fresh_depth.toml",
        &defect_model(
            "",
            "defect = {type = \"flat\", shape = \"fresh\", length = 0.05, depth = 0.001}",
        ),
        &["hertz_wheel", "fresh flat", "remove `depth`"],
    );
    check_bad_model(
        "rounded_no_depth.toml",
        &defect_model("", "defect = {type = \"flat\", length = 0.05}"),
        &["hertz_wheel", "needs `defect.depth`"],
    );
    check_bad_model(
        "square.toml",
        &defect_model("", "defect = {type = \"square\"}"),
        &["defect", "square", "polygon"],
    );
    check_bad_model(
        "polygon_order.toml",
        &defect_model(
            "",
            "defect = {type = \"polygon\", harmonics = [{order = 0, amplitude = 1e-4}]}",
        ),
        &["hertz_wheel", "`defect.harmonics[0].order` = 0"],
    );
    check_bad_model(
        "dip_both.toml",
        &defect_model(
            "dips = [{station = 10.0, depth = 0.001, angle = 0.01, length = 1.0}]",
            "",
        ),
        &["[track]", "dips[0]", "both `depth` and `angle`"],
    );
    check_bad_model(
        "dip_none.toml",
        &defect_model("dips = [{station = 10.0, length = 1.0}]", ""),
        &[
            "[track]",
            "dips[0]",
            "give a depth > 0 m, or the total joint angle",
        ],
    );
    check_bad_model(
        "dip_rail.toml",
        &defect_model(
            "dips = [{station = 10.0, depth = 0.001, length = 1.0, rail = \"middle\"}]",
            "",
        ),
        &["dips", "middle", "left"],
    );
}

/// The point wheels read the tread defect. A wheelset (50 kN per wheel) with a polygon of
/// order 20 and amplitude 0.1 mm on both wheels is moved slowly along rigid rails (static
/// solves every 5 mm): the load does not change, so neither does the contact's compression,
/// and the axle rises and falls with the tread deviation, `e(s) − e(s0)` with
/// `e = a·cos(n·s/R)`, R the axle height (0.43 m) — exactly, to Newton's tolerance (1e-12 m
/// asserted, as for the dips in `tests/point_wheels.rs`).
#[test]
fn point_wheels_follow_the_tread_at_low_speed() {
    let (a, order, q) = (1e-4, 20.0, 50e3);
    for kind in ["hertz_wheel", "rigid_wheel"] {
        let mut v = build(&Case {
            kind,
            speed: 1.0,
            wheel: serde_json::json!({"defect": {"type": "polygon", "harmonics": [{"order": 20, "amplitude": a}]}}),
            ws_load: 2.0 * q,
            ..Default::default()
        })
        .unwrap();
        v.d.static_solve(0.0, 1).unwrap();
        let u0 = v.disp(v.ks[0], 1);
        let s0 = v.out(0, 0, "station");
        let (mut worst, mut lo, mut hi) = (0.0f64, f64::INFINITY, f64::NEG_INFINITY);
        // Static solves along the track: the axle's travel and its largest difference.
        for j in 1..=60 {
            v.d.static_solve(0.005 * j as f64, 1).unwrap();
            let s = v.out(0, 0, "station");
            let du = v.disp(v.ks[0], 1) - u0;
            let e = |s: f64| a * (order * (s - s0) / R0).cos();
            worst = worst.max((du - (e(s) - e(s0))).abs());
            lo = lo.min(du);
            hi = hi.max(du);
        }
        println!(
            "{kind}: axle travel {:.4e} m (2a = {:.1e}), largest difference from e(s) − e(s0): {worst:.2e} m",
            hi - lo,
            2.0 * a
        );
        assert!(worst < 1e-12, "{kind}: {worst}");
    }
}

/// A two-axle wagon written inline, `hertz_wheel`s on rigid rails, the front wheelset
/// with a rounded flat (80 mm, 0.6 mm) on one wheel given by `[[vehicle.wheelset]]
/// defects`, at 10 m/s.
fn wagon_with_flat(side: &str) -> String {
    format!(
        r#"
[analysis]
kind = "transient"
dt = 1e-4
duration = 0.06
gravity = [0.0, 0.0, -9.81]

[track]
segments = [{{type = "straight", length = 30.0}}]
support = {{type = "rigid"}}

[[vehicle]]
name = "wagon"
start = 12.0
speed = 10.0
length = 12.0
record = {{wheels = "wheels.csv"}}

[[vehicle.body]]
name = "body"
mass = 20000.0
ixx = 2.0e4
iyy = 2.0e5
izz = 2.0e5
z = 1.5

[[vehicle.body]]
name = "axle_1"
mass = 1300.0
ixx = 700.0
iyy = 90.0
izz = 700.0
x = 3.0
z = 0.46

[[vehicle.body]]
name = "axle_2"
mass = 1300.0
ixx = 700.0
iyy = 90.0
izz = 700.0
x = -3.0
z = 0.46

[[vehicle.suspension]]
lower = "axle_1"
upper = "body"
at = [3.0, 1.0, 0.46]
k = [5e6, 2e6, 1e6]
c = [0.0, 1e4, 1e4]
mirror = true

[[vehicle.suspension]]
lower = "axle_2"
upper = "body"
at = [-3.0, 1.0, 0.46]
k = [5e6, 2e6, 1e6]
c = [0.0, 1e4, 1e4]
mirror = true

[[vehicle.wheelset]]
body = "axle_1"
wheel = {{model = "hertz_wheel"}}
defects = {{{side} = {{type = "flat", length = 0.08, depth = 0.0006, angle = 0.5}}}}

[[vehicle.wheelset]]
body = "axle_2"
wheel = {{model = "hertz_wheel"}}
"#
    )
}

/// A vehicle's per-wheel `defects` reach the wheel they name. The wagon and the track are
/// mirror-symmetric, so the flat on the left wheel must give the left wheel the loads the
/// same flat on the right wheel gives the right one (to 1e-6 of the static load: the two
/// runs differ only in the order of summation). The flat wheel loses contact — 10 m/s is
/// above the quasi-static bound `(L/2π)·√(2·Q0/(m·d))` = 6.8 m/s for Q0 ≈ 56 kN on
/// m = 650 kg, above which no wheel follows the flat (see the test above) — before the
/// other wheel of the axle does (that one leaves the rail too when the axle rebounds).
#[test]
fn vehicle_defects_reach_the_wheel_they_name() {
    let mut q = Vec::new();
    for side in ["left", "right"] {
        let dir = common::temp_dir(&format!("wagon_flat_{side}"));
        let model = dir.join("wagon.toml");
        std::fs::write(&model, wagon_with_flat(side)).unwrap();
        let out = dir.join("out");
        let o = common::railfem(&[
            "run",
            model.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let csv = common::Csv::read(&out.join("wheels.csv"));
        let cols: Vec<String> = csv
            .header
            .iter()
            .filter(|h| h.ends_with("_Q [N]"))
            .take(2)
            .cloned()
            .collect();
        q.push([csv.column(&cols[0]), csv.column(&cols[1])]);
        let _ = std::fs::remove_dir_all(&dir);
    }
    let (left_run, right_run) = (&q[0], &q[1]);
    let q0 = left_run[0][0];
    let worst = (0..left_run[0].len())
        .map(|i| {
            (left_run[0][i] - right_run[1][i])
                .abs()
                .max((left_run[1][i] - right_run[0][i]).abs())
        })
        .fold(0.0, f64::max);
    let min = |v: &[f64]| v.iter().copied().fold(f64::INFINITY, f64::min);
    println!(
        "static Q {q0:.1} N; mirror difference {:.2e} of it; smallest Q: flat wheel {:.1} N, other wheel {:.1} N",
        worst / q0,
        min(&left_run[0]),
        min(&left_run[1])
    );
    assert!(worst < 1e-6 * q0, "mirror: {worst}");
    // The flat is on one wheel only: the two wheels' loads part, and the flat wheel leaves
    // the rail first (the other one feels the flat only through the axle, afterwards).
    let apart = (0..left_run[0].len())
        .map(|i| (left_run[0][i] - left_run[1][i]).abs())
        .fold(0.0, f64::max);
    assert!(apart > 0.5 * q0, "the wheels' loads part by {apart} only");
    let first_off = |v: &[f64]| v.iter().position(|&x| x == 0.0);
    let (flat, other) = (first_off(&left_run[0]), first_off(&left_run[1]));
    println!("first step off the rail: flat wheel {flat:?}, other wheel {other:?}");
    assert!(flat.is_some());
    assert!(other.is_none() || other > flat, "{flat:?} {other:?}");
}

/// `moving_axle` reads the tread defect too. One sks700 carriage on `moving_axle` wheels
/// (μ = 0.3) at 10 m/s on rigid rails, every wheel eccentric (a polygon of order 1,
/// amplitude a = 1 mm), for 0.3 s (1.1 turns of the wheel): the front wheelset's axle rises
/// and falls by the tread deviation `a·(cos φ − 1)`, so it never rises above its start and
/// its travel is `2a`. The rolling radius (moving_axle's, from its wheel profile) does not
/// enter these two. Tolerance, as in `tests/irregularity.rs`: the wheel–rail compression
/// changes by at most `δ0·|ΔQ|/Q0` (δ0 the static compression, the axle's drop at t = 0),
/// on each side; the 0.05 m samples catch the extremes of a 2.7 m wave to
/// `1 − cos(π·0.05/2.7) = 1.7e-3` of 2a; 2e-8 m for Newton.
#[test]
fn moving_axle_follows_an_eccentric_tread() {
    let a = 1e-3;
    let dir = common::temp_dir("eccentric");
    let model = dir.join("ecc.toml");
    std::fs::write(
        &model,
        format!(
            r#"
[analysis]
kind = "transient"
dt = 0.005
duration = 0.3
gravity = [0.0, 0.0, -9.81]

[track]
segments = [{{type = "straight", length = 100.0}}]
element_length = 0.6
support = {{type = "rigid"}}

[[vehicle]]
preset = "sks700"
carriages = 1
start = 15.0
speed = 10.0
wheel = {{mu = 0.3, defect = {{type = "polygon", harmonics = [{{order = 1, amplitude = {a}}}]}}}}

[[recorder]]
type = "element"
kind = "moving_axle"
outputs = ["station", "Q"]
file = "wheels.csv"

[[recorder]]
type = "node"
node = 2007
dofs = ["uy"]
file = "front_wheelset.csv"
"#
        ),
    )
    .unwrap();
    let out = dir.join("out");
    let o = common::railfem(&[
        "run",
        model.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let u = common::Csv::read(&out.join("front_wheelset.csv")).column("2007_uy");
    let wheels = common::Csv::read(&out.join("wheels.csv"));
    let first = &wheels.rows[0];
    let cols: Vec<usize> = (0..wheels.header.len())
        .filter(|&j| {
            common::strip_unit(&wheels.header[j]).ends_with("_station") && first[j] == 25.0
        })
        .collect();
    assert_eq!(cols.len(), 2, "two front wheels at 25 m");
    let q: Vec<f64> = wheels
        .rows
        .iter()
        .map(|r| cols.iter().map(|&j| r[j + 1]).sum::<f64>())
        .collect();
    let (q0, u0) = (q[0], u[0]);
    let dq = q.iter().map(|x| (x - q0).abs()).fold(0.0, f64::max);
    let compression = -u0 * dq / q0;
    let hi = u.iter().map(|x| x - u0).fold(f64::NEG_INFINITY, f64::max);
    let lo = u.iter().map(|x| x - u0).fold(f64::INFINITY, f64::min);
    println!(
        "axle travel {:.5e} m (2a = {:.1e}), highest {hi:.2e} m; static compression {:.2e} m, ΔQ {dq:.0} N of {q0:.0} N",
        hi - lo,
        2.0 * a,
        -u0
    );
    assert!(hi < compression + 2e-8, "rose above its start by {hi}");
    let tol = 2.0 * compression + 1.7e-3 * 2.0 * a + 2e-8;
    assert!(
        ((hi - lo) - 2.0 * a).abs() < tol,
        "travel {} vs 2a, tolerance {tol}",
        hi - lo
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// The wagon of [`wagon_with_flat`] as a vehicle file (no defect), and a model running a
/// train of three copies of it with the train key `defects` given as `defects`.
fn wagon_train(defects: &str) -> (String, String) {
    let full = wagon_with_flat("left");
    let start = full.find("[[vehicle.body]]").unwrap();
    let vehicle = full[start..].replace("[[vehicle.", "[[").replace(
        "defects = {left = {type = \"flat\", length = 0.08, depth = 0.0006, angle = 0.5}}\n",
        "",
    );
    let vehicle = format!("length = 12.0\n\n{vehicle}");
    // The wagon's analysis and track, the track long enough for three wagons.
    let head = full[..full.find("[[vehicle]]").unwrap()].replace("length = 30.0", "length = 60.0");
    let model = format!(
        r#"{head}[[vehicle]]
name = "train"
start = 30.0
speed = 10.0
record = {{wheels = "wheels.csv"}}
vehicles = [{{file = "wagon.toml", count = 3}}]
{defects}
"#
    );
    (vehicle, model)
}

/// Every wheel's Q (columns `…_Q [N]`, front to back, left then right) of a train run.
fn train_wheel_loads(name: &str, defects: &str) -> Vec<Vec<f64>> {
    let dir = common::temp_dir(name);
    let (vehicle, model) = wagon_train(defects);
    std::fs::write(dir.join("wagon.toml"), vehicle).unwrap();
    std::fs::write(dir.join("train.toml"), model).unwrap();
    let out = dir.join("out");
    let o = common::railfem(&[
        "run",
        dir.join("train.toml").to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let csv = common::Csv::read(&out.join("wheels.csv"));
    let q = csv
        .header
        .iter()
        .filter(|h| h.ends_with("_Q [N]"))
        .map(|h| csv.column(h))
        .collect();
    let _ = std::fs::remove_dir_all(&dir);
    q
}

/// A train of three copies of one vehicle file with a flat given by the train's `defects`
/// to the left wheel of the first wheelset of vehicle 2 only. Against the same train
/// without it: that wheel's Q leaves the rail (Q = 0 at some step: 10 m/s is above the
/// speed at which a wheel can follow this flat, test above) while the wheels of vehicles 1
/// and 3, joined to vehicle 2 only by couplers, keep their loads within 1 % of the static
/// load (measured: within 5 N, 1e-4 of it, over these 0.06 s: the couplers' vertical rate
/// is 1e5 N/m against 2e6 N/m of the suspension, and the car bodies barely move in that
/// time); the flat's axle partner and the other axle of vehicle 2 move with the flat and
/// are not asserted.
#[test]
fn train_defects_reach_one_wheel_of_one_vehicle() {
    let flat = r#"defects = [{vehicle = 2, wheelset = 1, side = "left", defect = {type = "flat", length = 0.08, depth = 0.0006, angle = 0.5}}]"#;
    let with = train_wheel_loads("train_flat", flat);
    let without = train_wheel_loads("train_round", "");
    assert_eq!(with.len(), 12);
    let q0 = without[4][0];
    let dev = |k: usize| {
        with[k]
            .iter()
            .zip(&without[k])
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max)
    };
    for k in 0..12 {
        println!("wheel {k}: largest |ΔQ| {:.3e} N", dev(k));
    }
    assert!(with[4].contains(&0.0), "the flat wheel stays on the rail");
    assert!(without[4].iter().all(|&q| q > 0.5 * q0));
    for k in (0..4).chain(8..12) {
        assert!(dev(k) < 0.01 * q0, "wheel {k}: {}", dev(k));
    }
}

/// A train defect on a vehicle or wheelset that does not exist is refused with its key
/// path, the range and the fix (exit code 2, one line).
#[test]
fn train_defects_out_of_range_are_refused() {
    for (entry, expect) in [
        (
            r#"{vehicle = 4, wheelset = 1, side = "left", defect = {type = "flat", length = 0.08, depth = 0.0006}}"#,
            ["`vehicle[0].defects[0].vehicle` = 4", "1 … 3"],
        ),
        (
            r#"{vehicle = 2, wheelset = 3, side = "right", defect = {type = "flat", length = 0.08, depth = 0.0006}}"#,
            ["`vehicle[0].defects[0].wheelset` = 3", "1 … 2"],
        ),
    ] {
        let dir = common::temp_dir("train_defect_range");
        let (vehicle, model) = wagon_train(&format!("defects = [{entry}]"));
        std::fs::write(dir.join("wagon.toml"), vehicle).unwrap();
        std::fs::write(dir.join("train.toml"), model).unwrap();
        let o = common::railfem(&[
            "run",
            dir.join("train.toml").to_str().unwrap(),
            "--out",
            dir.join("out").to_str().unwrap(),
        ]);
        common::refused_with("train defect", &o, &expect);
        let _ = std::fs::remove_dir_all(&dir);
    }
}

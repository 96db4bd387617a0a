//! Rolling contact of the `moving_axle` element (`tangential = "kalker_linear"`) against
//! the linear wheelset theory (issue 14, docs/rolling-contact.md): the Klingel wavelength
//! of a free wheelset, and the linear critical speed of a suspended wheelset bracketed by
//! finite-element runs. Short versions; the tables come from
//! `cargo run --release --example rolling_contact -- klingel|hunting`.

mod common;
use common::temp_dir;
use railfem::elements::rail::contact::creep::linear_wheelset::{critical_speed, wheelset_system};
use railfem::rolling_contact::*;
use std::f64::consts::PI;

/// A cone whose slope is the crown's tangent at rail node 17 of 41 touches that node only
/// (a knife edge: the contact angles are those of a rolled cone, `atan λ ± φ`, and Δr = 2λy
/// holds exactly), so Klingel's `L = 2π√(r0·b/λ)` applies with the nominal λ and the
/// measured half distance `b` of the contact points. The FE wavelength (yaw zero crossings
/// over three half waves) agrees to 0.12 % at 5 m/s (docs/rolling-contact.md); 1 % is the
/// issue's tolerance, and leaves room for the penalty contact's compliance and the
/// finite-speed terms (O(mV²/(f22·L)) ≈ 1e-4).
#[test]
fn free_cone_wheelset_runs_at_the_klingel_wavelength() {
    let lambda = node_tangent_slope(41, 17);
    let case = Case::klingel(Wheel::Cone(lambda), 5.0, 40.0);
    let h = run(&case, &temp_dir("klingel")).unwrap();
    let b = 0.5
        * (mean_between(&h.station, &h.contact_left, START + 4.0, 1e9)
            + mean_between(&h.station, &h.contact_right, START + 4.0, 1e9));
    assert!((b - 0.747).abs() < 2e-3, "half contact distance {b}");
    let l = 2.0 * PI * (R0 * b / lambda).sqrt();
    let w = wavelength(&h.station, &h.yaw, START + 4.0).expect("three yaw zero crossings");
    assert!(
        (w / l - 1.0).abs() < 0.01,
        "FE wavelength {w} m, Klingel {l} m"
    );
}

/// A wheelset on primary springs (k_ψ = 1e6 N·m/rad, k_y = 1e6 N/m) to a frame held on the
/// track: the linear model (Kalker f11, f22, f23 of the FE's Hertz ellipse, gravitational
/// stiffness and spin terms of the knife-edge cone) has its critical speed at 73.1 m/s.
/// The FE runs bracket it: at 0.9·V_c the yaw oscillation decays, at 1.1·V_c it grows.
/// Measured (docs/rolling-contact.md): the FE growth rate crosses zero at 74.1 m/s with
/// dt = 0.5 ms and at 73.7 m/s with dt = 0.25 ms, so ±10 % is a bracket the time step
/// used here (0.5 ms) cannot close by itself, and a sign error in any creep or spin term
/// (each moves V_c by far more) would.
#[test]
fn fe_runs_bracket_the_linear_critical_speed() {
    let lambda = node_tangent_slope(41, 17);
    let mut case = Case::klingel(Wheel::Cone(lambda), 60.0, 110.0);
    case.dt = 5e-4;
    case.suspended = Some(Suspended {
        kx: 5e5,
        ky: 5e5,
        kz: 1e6,
        b1: 1.0,
        frame_mass: 8000.0,
    });
    let (ws, pr) = linear_model(&case, 0.74706).unwrap();
    let vc = critical_speed(|v| wheelset_system(&ws, &pr, v, 0.0, 0.0), 1.0, 300.0, 300).unwrap();
    assert!((vc - 73.1).abs() < 0.5, "linear critical speed {vc}");
    for (factor, grows) in [(0.9, false), (1.1, true)] {
        case.speed = factor * vc;
        let h = run(&case, &temp_dir("hunting")).unwrap();
        let sigma = growth_rate(&h.t, &h.yaw, 4.0 / case.speed + 0.3).expect("oscillation");
        assert_eq!(
            sigma > 0.0,
            grows,
            "V = {:.1} m/s: FE growth rate {sigma} 1/s",
            case.speed
        );
    }
}

/// Steady curving of the suspended wheelset (k_ψ = 1e6 N·m/rad, k_y = 1e6 N/m) on a
/// 1500 m left-hand curve at 10 m/s, no cant: the lateral offset and the angle of attack
/// against linear curving theory (Boocock/Wickens, `steady_curving`:
/// ψ = −2f11·b(λy/r0 + b/R)/k_ψ, y from the lateral balance with the cant deficiency).
/// The curving demand b/R enters the element through the wheel frame's rotation over each
/// step (`rolling::frame_rotation`); without it the FE offset is 0.0045 mm instead of
/// 4.7 mm, and a sign error in it puts y on the wrong side. Measured (docs/rolling-contact.md):
/// y −4.594 mm against −4.712 mm (2.5 %), ψ −0.302 mrad against −0.287 mrad (5.1 %). The
/// theory's omissions account for this size of gap: the cone on the 60E1 crown has an
/// effective conicity λ(1 + λR_crown/b) ≈ 1.02·λ (conicity.rs), and the theory leaves out
/// the spin creep and the gravitational stiffness that the FE contains. Tolerances: 5 % on
/// y and 10 % on ψ, twice the measured gaps; the missing-term and sign failures are 100 %
/// and 200 %.
#[test]
fn suspended_wheelset_curves_as_linear_theory_says() {
    use railfem::elements::rail::contact::creep::linear_wheelset::steady_curving;
    let (r, v) = (1500.0, 10.0);
    let lambda = node_tangent_slope(41, 17);
    let mut case = Case::klingel(Wheel::Cone(lambda), v, 60.0);
    case.dt = 0.002;
    case.suspended = Some(Suspended {
        kx: 5e5,
        ky: 5e5,
        kz: 1e6,
        b1: 1.0,
        frame_mass: 8000.0,
    });
    case.offset = 0.0;
    case.curve_radius = Some(r);
    case.distance = 160.0;
    let h = run(&case, &temp_dir("curving")).unwrap();
    let b = 0.5
        * (mean_between(&h.station, &h.contact_left, START + 4.0, 1e9)
            + mean_between(&h.station, &h.contact_right, START + 4.0, 1e9));
    let (ws, pr) = linear_model(&case, b).unwrap();
    let (y, psi) = steady_curving(&ws, &pr, 1.0 / r, -WHEELSET_MASS * v * v / r).unwrap();
    let end = START + case.distance;
    let y_fe = mean_between(&h.station, &h.y, end - 30.0, end);
    let psi_fe = mean_between(&h.station, &h.yaw, end - 30.0, end);
    assert!((y_fe / y - 1.0).abs() < 0.05, "y FE {y_fe} m, theory {y} m");
    assert!(
        (psi_fe / psi - 1.0).abs() < 0.10,
        "ψ FE {psi_fe} rad, theory {psi} rad"
    );
}

/// The sks700 carriage on straight track after a 2 mm alignment step (the example's
/// `sks700` case, shortened): below its critical speed (85–90 m/s by FE,
/// docs/rolling-contact.md) the leading wheel's angle of attack decays, above it it grows.
/// At 70 m/s the measured envelope rate is −4.1 1/s and the peak after the step 0.9 mrad;
/// at 100 m/s +0.37 1/s and 4.3 mrad. The thresholds (σ < −1 and a peak below 2 mrad;
/// σ > +0.1) sit well inside those and fail for a carriage that derails or drifts (the
/// sparse alignment table this case used before gave peaks of 16–50 mrad).
#[test]
fn sks700_hunting_decays_below_and_grows_above_its_critical_speed() {
    for (v, stable) in [(70.0, true), (100.0, false)] {
        let (t, s, a) = run_sks700(v, 1e-3, 2.5 * v, 2e-3, &temp_dir("sks700")).unwrap();
        // The ramp of the step ends at 44 m.
        let (sigma, peak, _) = step_response(&t, &s, &a, 50.0);
        let sigma = sigma.expect("three half waves after the step");
        println!(
            "V = {v} m/s: σ = {sigma:+.3} 1/s, peak {:.3} mrad",
            peak * 1e3
        );
        if stable {
            assert!(
                sigma < -1.0 && peak < 2e-3,
                "V = {v}: σ {sigma}, peak {peak}"
            );
        } else {
            assert!(sigma > 0.1, "V = {v}: σ {sigma}");
        }
    }
}

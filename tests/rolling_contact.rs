//! Rolling contact of the `moving_axle` element (`tangential = "kalker_linear"`) against
//! the linear wheelset theory (issue 14, docs/rolling-contact.md): the Klingel wavelength
//! of a free wheelset, and the linear critical speed of a suspended wheelset bracketed by
//! finite-element runs. Short versions; the tables come from
//! `cargo run --release --example rolling_contact -- klingel|hunting`.

mod common;
use common::temp_dir;
use railfem::elements::rail::creep::linear_wheelset::{critical_speed, wheelset_system};
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

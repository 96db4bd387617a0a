//! The long versions of the issue-14 checks of rolling contact against the linear wheelset
//! theory (docs/rolling-contact.md), printed as markdown tables:
//!
//! ```text
//! cargo run --release --example rolling_contact -- conicity
//! cargo run --release --example rolling_contact -- klingel
//! cargo run --release --example rolling_contact -- hunting [DT]
//! cargo run --release --example rolling_contact -- curving
//! cargo run --release --example rolling_contact -- sks700 [DT] [V1,V2,…]
//! ```
//!
//! Model files and histories go to `target/rolling-contact/<case>/`.

use railfem::elements::rail::contact::creep::conicity::{
    equivalent_conicity, secant_conicity, WheelsetGeometry,
};
use railfem::elements::rail::contact::creep::linear_wheelset::{
    critical_speed, max_real_part, steady_curving, wheelset_system, Wheelset,
};
use railfem::elements::rail::contact::profiles::Inclination;
use railfem::rolling_contact::*;
use std::f64::consts::PI;
use std::path::PathBuf;

fn dir(name: &str) -> PathBuf {
    PathBuf::from("target/rolling-contact").join(name)
}

/// Half the distance of the contact points, averaged after the offset ramp.
fn half_contact(h: &History) -> f64 {
    0.5 * (mean_between(&h.station, &h.contact_left, START + 4.0, 1e9)
        + mean_between(&h.station, &h.contact_right, START + 4.0, 1e9))
}

fn conicity() -> Result<(), Box<dyn std::error::Error>> {
    println!("| rail | amplitude (mm) | λ_e harmonic | Δr/2y secant |");
    println!("|---|---|---|---|");
    for (name, incl) in [
        ("1:40", Inclination::OneIn40),
        ("1:20", Inclination::OneIn20),
    ] {
        let g = WheelsetGeometry::s1002_60e1(201, incl, 1.435, R0)?;
        for amp in [1e-3, 2e-3, 3e-3, 4e-3, 6e-3] {
            println!(
                "| 60E1 {name} | {} | {:.4} | {:.4} |",
                amp * 1e3,
                equivalent_conicity(&g, amp)?,
                secant_conicity(&g, amp)?
            );
        }
    }
    Ok(())
}

fn klingel() -> Result<(), Box<dyn std::error::Error>> {
    println!(
        "| wheel | V (m/s) | dt (s) | b (m) | λ used | L FE (m) | L Klingel (m) | FE/Klingel − 1 |"
    );
    println!("|---|---|---|---|---|---|---|---|");
    let knife = node_tangent_slope(41, 17);
    for (wheel, v, dt) in [
        (Wheel::Cone(knife), 2.0, 0.004),
        (Wheel::Cone(knife), 5.0, 0.002),
        (Wheel::Cone(knife), 10.0, 0.001),
        (Wheel::Cone(0.05), 5.0, 0.002),
    ] {
        let mut case = Case::klingel(wheel, v, 60.0);
        case.dt = dt;
        let h = run(&case, &dir("klingel"))?;
        let b = half_contact(&h);
        let lam = match wheel {
            Wheel::Cone(l) => l,
            Wheel::S1002 => unreachable!(),
        };
        let l = 2.0 * PI * (R0 * b / lam).sqrt();
        let w = wavelength(&h.station, &h.yaw, START + 4.0).unwrap_or(f64::NAN);
        println!(
            "| cone {lam:.5} | {v} | {dt} | {b:.5} | {lam:.5} | {w:.4} | {l:.4} | {:+.2} % |",
            100.0 * (w / l - 1.0)
        );
    }
    // S1002: the wavelength between successive yaw zero crossings against the amplitude.
    let g = WheelsetGeometry::s1002_60e1(201, Inclination::OneIn40, 1.435, R0)?;
    for offset in [1e-3, 2e-3, 3e-3] {
        let mut case = Case::klingel(Wheel::S1002, 5.0, 60.0);
        case.offset = offset;
        let h = run(&case, &dir("klingel-s1002"))?;
        let b = half_contact(&h);
        let w = wavelength(&h.station, &h.yaw, START + 4.0).unwrap_or(f64::NAN);
        let m = mean_between(&h.station, &h.y, START + 4.0, 1e9);
        let amp =
            h.y.iter()
                .zip(&h.station)
                .filter(|(_, s)| **s > START + 4.0)
                .fold(0.0f64, |a, (y, _)| a.max((y - m).abs()));
        let le = equivalent_conicity(&g, amp)?;
        let l = 2.0 * PI * (R0 * b / le).sqrt();
        let implied = R0 * b * (2.0 * PI / w).powi(2);
        println!(
            "| S1002, offset {} mm (first amplitude {:.2} mm) | 5 | 0.002 | {b:.5} | λ_e = {le:.4} (FE implies {implied:.4}) | {w:.3} | {l:.3} | {:+.1} % |",
            offset * 1e3,
            amp * 1e3,
            100.0 * (w / l - 1.0)
        );
    }
    Ok(())
}

fn suspended_case(v: f64, dt: f64) -> Case {
    let mut case = Case::klingel(
        Wheel::Cone(node_tangent_slope(41, 17)),
        v,
        (5.0 * v).max(60.0),
    );
    case.dt = dt;
    case.suspended = Some(HUNTING_PRIMARY);
    case
}

/// Primary suspension of the hunting and curving checks: k_ψ = 2·5e5·1² = 1e6 N·m/rad,
/// k_y = 1e6 N/m, frame 8000 kg (axle load 96.2 kN).
pub const HUNTING_PRIMARY: Suspended = Suspended {
    kx: 5e5,
    ky: 5e5,
    kz: 1e6,
    b1: 1.0,
    frame_mass: 8000.0,
};

fn hunting(dt: f64) -> Result<(), Box<dyn std::error::Error>> {
    let probe = run(&suspended_case(20.0, 0.002), &dir("hunting"))?;
    let b = half_contact(&probe);
    let (ws, pr) = linear_model(&suspended_case(20.0, dt), b)?;
    let sys = |ws: Wheelset| move |v: f64| wheelset_system(&ws, &pr, v, 0.0, 0.0);
    let vc = critical_speed(sys(ws), 1.0, 300.0, 300)?;
    let vc0 = critical_speed(sys(Wheelset { f23: 0.0, ..ws }), 1.0, 300.0, 300)?;
    println!("linear: f11 {:.4e} N, f22 {:.4e} N, f23 {:.4e} N·m, k_g {:.1} N/m; critical speed {vc:.2} m/s (without spin {vc0:.2} m/s)", ws.f11, ws.f22, ws.f23, ws.gravitational_stiffness);
    println!("\n| V (m/s) | dt (s) | σ FE (1/s) | σ linear (1/s) | wavelength FE (m) |");
    println!("|---|---|---|---|---|");
    for v in [0.8 * vc, 0.9 * vc, 0.95 * vc, vc, 1.05 * vc, 1.1 * vc] {
        let h = run(&suspended_case(v, dt), &dir("hunting"))?;
        let g = growth_rate(&h.t, &h.yaw, 4.0 / v + 0.3).unwrap_or(f64::NAN);
        let re = max_real_part(&sys(ws), v)?;
        let w = wavelength(&h.station, &h.yaw, START + 4.0).unwrap_or(f64::NAN);
        println!("| {v:.2} | {dt} | {g:+.3} | {re:+.3} | {w:.3} |");
    }
    Ok(())
}

fn curving() -> Result<(), Box<dyn std::error::Error>> {
    println!("| R (m) | V (m/s) | y FE (mm) | y theory (mm) | ψ FE (mrad) | ψ theory (mrad) | pure rolling y (mm) |");
    println!("|---|---|---|---|---|---|---|");
    for (r, v) in [(3000.0, 10.0), (1500.0, 10.0), (800.0, 10.0)] {
        let mut case = suspended_case(v, 0.002);
        case.offset = 0.0;
        case.curve_radius = Some(r);
        case.distance = 160.0;
        let h = run(&case, &dir("curving"))?;
        let b = half_contact(&h);
        let (ws, pr) = linear_model(&case, b)?;
        let (y, psi) = steady_curving(&ws, &pr, 1.0 / r, -WHEELSET_MASS * v * v / r)?;
        let end = START + case.distance;
        let y_fe = mean_between(&h.station, &h.y, end - 30.0, end);
        let psi_fe = mean_between(&h.station, &h.yaw, end - 30.0, end);
        println!(
            "| {r} | {v} | {:.4} | {:.4} | {:.4} | {:.4} | {:.4} |",
            y_fe * 1e3,
            y * 1e3,
            psi_fe * 1e3,
            psi * 1e3,
            -R0 * b / (ws.conicity * r) * 1e3
        );
    }
    Ok(())
}

fn sks700(dt: f64, speeds: &[f64]) -> Result<(), Box<dyn std::error::Error>> {
    println!("| V (m/s) | dt (s) | σ of the leading wheel's attack angle (1/s) | peak attack angle after the step (mrad) | wavelength (m) |");
    println!("|---|---|---|---|---|");
    for &v in speeds {
        let (t, s, a) = run_sks700(v, dt, (2.5 * v).max(80.0), 2e-3, &dir("sks700"))?;
        // Stations of the leading wheel: the ramp ends at 44 m.
        let (g, peak, w) = step_response(&t, &s, &a, 50.0);
        let (g, w) = (g.unwrap_or(f64::NAN), w.unwrap_or(f64::NAN));
        println!("| {v} | {dt} | {g:+.3} | {:.3} | {w:.2} |", peak * 1e3);
    }
    Ok(())
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    match args.get(1).map(String::as_str) {
        Some("conicity") => conicity(),
        Some("klingel") => klingel(),
        Some("hunting") => hunting(args.get(2).map_or(Ok(0.0005), |s| s.parse())?),
        Some("curving") => curving(),
        Some("sks700") => {
            // Bad arguments: one line and exit code 2.
            let refuse = |what: &str| -> ! {
                eprintln!("rolling_contact sks700: {what}");
                std::process::exit(2)
            };
            let dt = match args.get(2).map(|s| s.parse::<f64>()) {
                None => 0.001,
                Some(Ok(dt)) if dt > 0.0 && dt.is_finite() => dt,
                _ => refuse("DT must be a time step > 0 s, e.g. 0.001"),
            };
            let speeds = match args.get(3) {
                Some(list) => match list
                    .split(',')
                    .map(str::parse::<f64>)
                    .collect::<Result<Vec<f64>, _>>()
                {
                    Ok(v) if v.iter().all(|x| *x > 0.0 && x.is_finite()) => v,
                    _ => refuse(
                        "speeds must be a comma-separated list of speeds > 0 m/s, e.g. 80,85,90",
                    ),
                },
                None => vec![30.0, 50.0, 70.0, 90.0, 110.0],
            };
            sks700(dt, &speeds)
        }
        _ => {
            eprintln!("usage: rolling_contact conicity|klingel|hunting [DT]|curving|sks700 [DT] [V1,V2,…]");
            std::process::exit(2);
        }
    }
}

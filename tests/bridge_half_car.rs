//! The full vehicle of `railfem bridge-check` (`railfem::bridge_check::half_car`, the
//! 10-DOF half car): its natural frequencies on rigid track against closed forms derived
//! here, and its static equilibrium against the axle loads of a hand sum and of the
//! framework's static solve of the same vehicle file.

mod common;

use railfem::bridge_check::half_car::{HalfCar, HalfCarParams};
use std::f64::consts::PI;
use std::path::Path;

/// The sks700 carriage (examples/vehicles/sks700.toml) as half-car parameters, read off
/// the file by hand: both sides of every suspension summed.
fn sks700() -> HalfCarParams {
    HalfCarParams {
        car_mass: 43862.5,
        car_pitch_inertia: 1.654e6,
        bogie_mass: 2400.0,
        bogie_pitch_inertia: 1314.0,
        wheelset_mass: 1850.0,
        secondary_stiffness: 2.0 * 0.19e6,
        secondary_damping: 2.0 * 40e3,
        primary_stiffness: 2.0 * 1.176e6,
        primary_damping: 2.0 * 13e3,
        bogie_half_distance: 8.75,
        semi_wheelbase: 1.25,
    }
}

/// The roots `λ = ω²` of `a·λ² − b·λ + c = 0`, ascending.
fn roots(a: f64, b: f64, c: f64) -> [f64; 2] {
    let d = (b * b - 4.0 * a * c).sqrt();
    [(b - d) / (2.0 * a), (b + d) / (2.0 * a)]
}

/// The six frequencies (Hz) of car body and bogies with the wheelsets held, derived by
/// hand. With `k1`, `k2` the primary (per wheelset) and secondary (per bogie) stiffness,
/// `a` half the bogie distance and `b` the semi-wheelbase:
/// - bogie pitch (each bogie, the secondary acting at its centre): `J_b·θ'' + 2·k1·b²·θ = 0`;
/// - bounce (bogies in phase, `z_b1 = z_b2`): `m_c·z_c'' + 2·k2·(z_c − z_b) = 0`,
///   `m_b·z_b'' + k2·(z_b − z_c) + 2·k1·z_b = 0`, whose determinant gives
///   `m_c·m_b·λ² − (m_c·(k2 + 2·k1) + 2·k2·m_b)·λ + 4·k1·k2 = 0`;
/// - pitch (bogies in opposition, `z_b1 = −z_b2`, the secondary stretched by
///   `z_b − a·θ_c`): `J_c·θ'' − 2·k2·a·(z_b − a·θ) = 0`, `m_b·z_b'' + k2·(z_b − a·θ) +
///   2·k1·z_b = 0`, whence `J_c·m_b·λ² − (J_c·(k2 + 2·k1) + 2·k2·a²·m_b)·λ + 4·k1·k2·a² = 0`.
fn held_frequencies(p: &HalfCarParams) -> Vec<f64> {
    let (k1, k2) = (p.primary_stiffness, p.secondary_stiffness);
    let (mc, jc, mb, jb) = (
        p.car_mass,
        p.car_pitch_inertia,
        p.bogie_mass,
        p.bogie_pitch_inertia,
    );
    let a = p.bogie_half_distance;
    let b = p.semi_wheelbase;
    let pitch_b = 2.0 * k1 * b * b / jb;
    let bounce = roots(mc * mb, mc * (k2 + 2.0 * k1) + 2.0 * k2 * mb, 4.0 * k1 * k2);
    let pitch = roots(
        jc * mb,
        jc * (k2 + 2.0 * k1) + 2.0 * k2 * a * a * mb,
        4.0 * k1 * k2 * a * a,
    );
    let mut f: Vec<f64> = [pitch_b, pitch_b, bounce[0], bounce[1], pitch[0], pitch[1]]
        .iter()
        .map(|l| l.sqrt() / (2.0 * PI))
        .collect();
    f.sort_by(f64::total_cmp);
    f
}

/// The half car's natural frequencies on rigid track against the closed forms above:
/// with the wheelsets held at the rail, to 1e-9 (the same system, solved two ways); with
/// the wheelsets on their Hertz contact springs (3.4e9 N/m, some 1500 times the primary
/// stiffness), the six lowest within 0.5 % of the held ones, and the
/// four wheelset modes near the wheelset on its contact and primary springs,
/// `√((k_H + k1)/m_w)/2π`, within 0.5 % (the bogie barely moves at those frequencies).
/// Both for the parameters and for the vehicle file they come from.
#[test]
fn half_car_frequencies_on_rigid_track_match_closed_forms() {
    let p = sks700();
    let file = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/vehicles/sks700.toml");
    let text = std::fs::read_to_string(&file).expect("vehicle file");
    let def =
        railfem::elements::rail::vehicle::section::parse_vehicle(&text, "sks700").expect("parse");
    let from_file = HalfCar::from_vehicle(&def, "sks700.toml", 0.43).expect("half car");
    let from_keys = HalfCar::symmetric(&p, 0.43);
    let want = held_frequencies(&p);
    for h in [&from_keys, &from_file] {
        let held = h.frequencies(true);
        assert_eq!(held.len(), 6);
        for (got, w) in held.iter().zip(&want) {
            assert!((got / w - 1.0).abs() < 1e-9, "held: {held:?} vs {want:?}");
        }
        let free = h.frequencies(false);
        let shift = free
            .iter()
            .zip(&want)
            .fold(0.0f64, |m, (got, w)| m.max((got / w - 1.0).abs()));
        eprintln!("held {held:?} Hz; on the contact springs {free:?} Hz, the six lowest within {shift:.2e}");
        for (got, w) in free.iter().zip(&want) {
            assert!(
                (got / w - 1.0).abs() < 5e-3,
                "on contact: {free:?} vs {want:?}"
            );
        }
        for (j, got) in free[6..].iter().enumerate() {
            let kh = h.contact[j];
            let w = ((kh + p.primary_stiffness) / p.wheelset_mass).sqrt() / (2.0 * PI);
            assert!((got / w - 1.0).abs() < 5e-3, "wheelset mode {got} vs {w}");
        }
    }
    // The file's half car is the parameters' one, matrix for matrix.
    for i in 0..10 {
        assert!((from_file.mass[i] / from_keys.mass[i] - 1.0).abs() < 1e-12);
        for j in 0..10 {
            let (a, b) = (from_file.k[i][j], from_keys.k[i][j]);
            assert!(
                (a - b).abs() <= 1e-9 * b.abs().max(1.0),
                "K[{i}][{j}] {a} vs {b}"
            );
            let (a, b) = (from_file.c[i][j], from_keys.c[i][j]);
            assert!(
                (a - b).abs() <= 1e-9 * b.abs().max(1.0),
                "C[{i}][{j}] {a} vs {b}"
            );
        }
    }
}

/// Static equilibrium on level rigid track under gravity: the contact forces of the
/// solved half car equal the axle loads of a hand sum (a quarter of car body plus half a
/// bogie plus the wheelset, the sks700 being symmetric) and those of the framework's
/// static solve of the same vehicle file (the bridge check's vehicle-file train), to 1e-9
/// relative; the loads of a car whose body sits off-centre (bogies at 9 m and −7 m, so the
/// front bogie carries 7/16 of the body by the lever rule) likewise.
#[test]
fn half_car_static_contact_forces_are_the_axle_loads() {
    let g = 9.81;
    let p = sks700();
    let axle = (p.car_mass / 4.0 + p.bogie_mass / 2.0 + p.wheelset_mass) * g;
    let file = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/vehicles/sks700.toml");
    let (train, _) =
        railfem::bridge_check::vehicle_train::read(&file, "sks", 1, 0.43).expect("train");
    let h = HalfCar::symmetric(&p, 0.43);
    let (_, forces) = h.static_on_rigid_track();
    for (j, f) in forces.iter().enumerate() {
        assert!((f / axle - 1.0).abs() < 1e-9, "axle {j}: {f} vs {axle}");
        let fw = train.axles[j].load;
        assert!(
            (f / fw - 1.0).abs() < 1e-9,
            "axle {j}: {f} vs the framework's {fw}"
        );
    }
    // Off-centre: the body's weight splits 7:9 between the front bogie (9 m ahead of the
    // body's centre) and the rear one (7 m behind).
    let h = shifted(&p, 9.0, 7.0);
    let (_, forces) = h.static_on_rigid_track();
    let front = (p.car_mass * 7.0 / 16.0 / 2.0 + p.bogie_mass / 2.0 + p.wheelset_mass) * g;
    let rear = (p.car_mass * 9.0 / 16.0 / 2.0 + p.bogie_mass / 2.0 + p.wheelset_mass) * g;
    for (j, f) in forces.iter().enumerate() {
        let want = if j < 2 { front } else { rear };
        assert!((f / want - 1.0).abs() < 1e-9, "axle {j}: {f} vs {want}");
    }
}

/// The sks700 written as a vehicle file with its bogies at `front` m ahead of and `rear` m
/// behind the car body's centre, read back as a half car.
fn shifted(p: &HalfCarParams, front: f64, rear: f64) -> HalfCar {
    let b = p.semi_wheelbase;
    let mut s = String::from("length = 25.0\n");
    let body = |s: &mut String, name: &str, m: f64, iyy: f64, x: f64| {
        s.push_str(&format!(
            "[[body]]\nname = \"{name}\"\nmass = {m}\nixx = 1000.0\niyy = {iyy}\nizz = 1000.0\nx = {x}\nz = 1.0\n"
        ));
    };
    body(&mut s, "car", p.car_mass, p.car_pitch_inertia, 0.0);
    body(&mut s, "bf", p.bogie_mass, p.bogie_pitch_inertia, front);
    body(&mut s, "br", p.bogie_mass, p.bogie_pitch_inertia, -rear);
    let ws = [front + b, front - b, -rear + b, -rear - b];
    for (j, x) in ws.iter().enumerate() {
        body(&mut s, &format!("w{j}"), p.wheelset_mass, 100.0, *x);
    }
    let spring = |s: &mut String, lo: &str, up: &str, x: f64, k: f64, c: f64| {
        s.push_str(&format!(
            "[[suspension]]\nlower = \"{lo}\"\nupper = \"{up}\"\nat = [{x}, 1.0, 0.5]\nk = [1e6, 1e6, {k}]\nc = [0.0, 0.0, {c}]\nmirror = true\n"
        ));
    };
    let (k2, c2) = (p.secondary_stiffness / 2.0, p.secondary_damping / 2.0);
    let (k1, c1) = (p.primary_stiffness / 2.0, p.primary_damping / 2.0);
    spring(&mut s, "bf", "car", front, k2, c2);
    spring(&mut s, "br", "car", -rear, k2, c2);
    for (j, x) in ws.iter().enumerate() {
        let up = if j < 2 { "bf" } else { "br" };
        spring(&mut s, &format!("w{j}"), up, *x, k1, c1);
    }
    for j in 0..4 {
        s.push_str(&format!("[[wheelset]]\nbody = \"w{j}\"\n"));
    }
    let def = railfem::elements::rail::vehicle::section::parse_vehicle(&s, "shifted")
        .expect("parse the shifted vehicle");
    HalfCar::from_vehicle(&def, "shifted", 0.43).expect("half car")
}

/// One sks700 (the half car of the parameters above) crossing Yang & Yau's beam (L = 25 m,
/// EI = 2.943e10 N·m², μ = 2303 kg/m, undamped: a light span, 58 t against the car's
/// 56 t, so the interaction is strong) at 200 km/h on the check's FE deck (20 elements,
/// Newmark, Δt = 0.1 ms) with the full-vehicle step, against an independent solution
/// written here: 10 sine modes of the beam and the half car's ten equations, the contact
/// forces `P_j + k_j·(w_j − z_wj)` on the deck, fourth-order Runge–Kutta at 1e-5 s. The
/// midspan deflection agrees to 1 % of its peak at every step of the crossing, and the
/// car body's bounce and pitch when the last wheelset leaves the span to 1 % of their
/// largest values over the crossing.
#[test]
fn full_vehicle_crossing_against_modal_runge_kutta() {
    use railfem::bridge_check::envelope::KMH;
    use railfem::bridge_check::fe::{described_model, Deck, Stepper, Work};
    use railfem::bridge_check::full_vehicles::{run, Vehicle, VehicleWork};
    let (l, ei, mu) = (25.0, 2.943e10, 2303.0);
    let p = sks700();
    let g = 9.81;
    let car = HalfCar::symmetric(&p, 0.43);
    let axle_load = (p.car_mass / 4.0 + p.bogie_mass / 2.0 + p.wheelset_mass) * g;
    let v = 200.0 / KMH;
    let model = described_model(&[l], ei, mu, 20).build().expect("model");
    let ids: Vec<u64> = (1..=20).collect();
    let deck = Deck::new(model, &ids, 6, "test").expect("deck");
    let dt = 1e-4;
    let st = Stepper::new(&deck, 0.0, 0.0, dt).expect("stepper");
    let vehicle = Vehicle {
        centre: car.axle_x[0],
        car: car.clone(),
    };
    let reach = vehicle.axle(3);
    let steps = ((l + reach) / v / dt).floor() as usize;
    let (mut w, mut x) = (Work::default(), VehicleWork::default());
    run(
        &st,
        &deck,
        std::slice::from_ref(&vehicle),
        v,
        steps,
        (&mut w, &mut x),
    );
    let mid = deck
        .stations
        .iter()
        .position(|s| (s.station - l / 2.0).abs() < 1e-9)
        .expect("midspan");
    // The modal solution: y = (q_1..q_N, z_1..z_10, their rates).
    let nm = 10;
    let nd = nm + 10;
    let omega: Vec<f64> = (1..=nm)
        .map(|n| (n as f64 * PI / l).powi(2) * (ei / mu).sqrt())
        .collect();
    let wheel_x: Vec<f64> = (0..4).map(|j| vehicle.axle(j)).collect();
    let rhs = |t: f64, y: &[f64]| -> Vec<f64> {
        let mut d = vec![0.0; 2 * nd];
        d[..nd].copy_from_slice(&y[nd..]);
        let (q, z, zd) = (&y[..nm], &y[nm..nd], &y[nd + nm..]);
        let mut fz = [0.0; 10];
        for (a, f) in fz.iter_mut().enumerate() {
            let mut s = 0.0;
            for b in 0..10 {
                s -= car.k[a][b] * z[b] + car.c[a][b] * zd[b];
            }
            *f = s;
        }
        for (j, wx) in wheel_x.iter().enumerate() {
            let xj = v * t - wx;
            let wi = 6 + j;
            let on = (0.0..=l).contains(&xj);
            let wj: f64 = if on {
                (0..nm)
                    .map(|n| ((n + 1) as f64 * PI * xj / l).sin() * q[n])
                    .sum()
            } else {
                0.0
            };
            let spring = car.contact[j] * (wj - z[wi]);
            fz[wi] += spring;
            if on {
                let f = axle_load + spring;
                for n in 0..nm {
                    d[nd + n] -= ((n + 1) as f64 * PI * xj / l).sin() * f / (mu * l / 2.0);
                }
            }
        }
        for n in 0..nm {
            d[nd + n] -= omega[n].powi(2) * q[n];
        }
        for a in 0..10 {
            d[nd + nm + a] = fz[a] / car.mass[a];
        }
        d
    };
    let h = 1e-5;
    let per = (dt / h).round() as usize;
    let mut y = vec![0.0; 2 * nd];
    let mut modal = vec![0.0; steps + 1];
    let mut body_peak = (0.0f64, 0.0f64);
    for i in 1..=steps * per {
        let t = (i - 1) as f64 * h;
        common::rk4_step(&rhs, t, h, &mut y);
        body_peak = (
            body_peak.0.max(y[nm].abs()),
            body_peak.1.max(y[nm + 1].abs()),
        );
        if i % per == 0 {
            modal[i / per] = (0..nm)
                .map(|n| ((n + 1) as f64 * PI / 2.0).sin() * y[n])
                .sum();
        }
    }
    let peak = modal.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let worst = (0..=steps)
        .map(|i| (w.deflection[mid][i] - modal[i]).abs())
        .fold(0.0f64, f64::max);
    let fe_body = (x.states[0][0][0], x.states[0][0][1]);
    let ref_body = (y[nm], y[nm + 1]);
    eprintln!(
        "midspan peak {peak:.4e} m, worst difference {:.3e} of it; car body at exit: bounce {:.4e} vs {:.4e} m (peak {:.3e}), pitch {:.4e} vs {:.4e} rad (peak {:.3e}); contact range {:?}",
        worst / peak,
        fe_body.0,
        ref_body.0,
        body_peak.0,
        fe_body.1,
        ref_body.1,
        body_peak.1,
        x.contact_range
    );
    assert!(worst < 1e-2 * peak, "{worst} vs {peak}");
    assert!((fe_body.0 - ref_body.0).abs() < 1e-2 * body_peak.0);
    assert!((fe_body.1 - ref_body.1).abs() < 1e-2 * body_peak.1);
}

/// The full-vehicle model through `railfem bridge-check`: two sks700 vehicles of their
/// vehicle file over the 20 m span at 100-120 km/h with `model = "all"` give rows of the
/// three models in envelope.csv, and the report compares the three at the governing train
/// and speed with the CSV's numbers; the same plan with the built-in HSLM trains, which
/// have no vehicles, is refused with one line naming `analysis.model` (exit 2).
#[test]
fn full_vehicles_through_the_command() {
    let dir = common::temp_dir("bridge-check-full");
    let vehicle = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/vehicles/sks700.toml");
    let bridge = "[bridge]\nspans = [20.0]\nEI = 4.8e10\nmass = 15000.0\nkind = \"prestressed_concrete\"\ntrack = \"ballasted\"\n\n[speeds]\nmax_line_speed = 100.0\nmin = 100.0\nstep = 10.0\nrefine = 0\n\n[analysis]\nmodel = \"all\"\n";
    let plan = dir.join("full.toml");
    std::fs::write(
        &plan,
        format!(
            "trains = []\n{bridge}\n[[train]]\nname = \"2 sks700\"\nvehicle = {:?}\ncount = 2\n",
            vehicle.display().to_string()
        ),
    )
    .expect("plan");
    let out = dir.join("out");
    let o = common::railfem(&[
        "bridge-check",
        plan.to_str().expect("utf-8"),
        "--threads",
        "2",
        "-q",
        "--out",
        out.to_str().expect("utf-8"),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let csv = std::fs::read_to_string(out.join("envelope.csv")).expect("csv");
    let rows: Vec<Vec<&str>> = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').collect())
        .collect();
    for m in ["moving_forces", "sprung_masses", "full_vehicles"] {
        assert_eq!(rows.iter().filter(|r| r[1] == m).count(), 3, "{m}: {csv}");
    }
    let num = |r: &Vec<&str>| r[3].parse::<f64>().expect("number");
    let g = rows
        .iter()
        .max_by(|a, b| num(a).total_cmp(&num(b)))
        .expect("rows");
    let at = |m: &str| {
        rows.iter()
            .find(|r| r[1] == m && r[2] == g[2])
            .map(num)
            .expect("row")
    };
    let report = std::fs::read_to_string(out.join("report.md")).expect("report");
    let line = format!(
        "moving forces {:.4} m/s², sprung masses {:.4} m/s² ({:+.2} % against the moving forces), full vehicles {:.4} m/s² ({:+.2} % against the moving forces)",
        at("moving_forces"),
        at("sprung_masses"),
        100.0 * (at("sprung_masses") / at("moving_forces") - 1.0),
        at("full_vehicles"),
        100.0 * (at("full_vehicles") / at("moving_forces") - 1.0)
    );
    assert!(report.contains(&line), "{line} not in {report}");
    let bad = dir.join("hslm.toml");
    std::fs::write(&bad, format!("trains = [\"HSLM-A1\"]\n{bridge}")).expect("plan");
    let o = common::railfem(&["bridge-check", bad.to_str().expect("utf-8"), "-q"]);
    common::refused_with(
        "full vehicles of HSLM-A1",
        &o,
        &["hslm.toml: analysis.model", "HSLM-A1"],
    );
}

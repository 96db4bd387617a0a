//! How close the check's FE envelope comes to the modal reference, by mesh and time step,
//! and how the reference converges in its mode count: HSLM-A1 and A5 on the 20 m span of
//! `examples/bridge-check/span20.toml` (EI = 4.8e10 N·m², μ = 15 t/m, ζ = 1 %), 215-285
//! km/h every 5 km/h (across their second resonances), the worst relative difference of
//! the peak filtered acceleration and of the peak deflection over the speeds.
//!
//! `cargo run --release --example bridge_accuracy` (docs/bridge-check.md, "Accuracy").

use railfem::bridge_check::envelope::{Check, KMH};
use railfem::bridge_check::fe::{described_model, rayleigh, Deck, Stepper};
use railfem::bridge_check::filter::{cutoff, LowPass};
use railfem::bridge_check::modal::{response, Span};
use railfem::bridge_check::trains::hslm_a;
use railfem::framework::FemError;
use std::f64::consts::PI;

/// The worst relative differences `(acceleration, deflection)` of the FE with `per`
/// elements and `spp` steps per cut-off period against the modal reference with `modes`.
fn worst(per: usize, spp: f64, modes: usize) -> Result<(f64, f64), FemError> {
    let (ei, mass) = (4.8e10, 15000.0);
    let span = Span {
        length: 20.0,
        ei,
        mass,
    };
    let model = described_model(&[20.0], ei, mass, per).build()?;
    let ids: Vec<u64> = (1..=per as u64).collect();
    let deck = Deck::new(model, &ids, 6, "bridge_accuracy")?;
    let n0 = deck.frequencies[0];
    let fc = cutoff(n0, deck.frequencies.get(2).copied());
    let (al, be) = rayleigh(0.01, 2.0 * PI * n0, 2.0 * PI * fc);
    let dt = 1.0 / (spp * fc);
    let st = Stepper::new(&deck, al, be, dt)?;
    let trains = [hslm_a(1).expect("A1"), hslm_a(5).expect("A5")];
    let c = Check {
        deck: &deck,
        stepper: &st,
        trains: &trains,
        statics: &[1.0, 1.0],
        cutoff: fc,
        tail: 0.3,
        vehicles: &[],
        full: &[],
        journal: None,
    };
    let stations: Vec<f64> = deck.stations.iter().map(|s| s.station).collect();
    let mut lp = LowPass::default();
    let mut scratch = Default::default();
    let mut out = (0.0f64, 0.0f64);
    for (i, train) in trains.iter().enumerate() {
        for k in 0..=14 {
            let kmh = 215.0 + 5.0 * k as f64;
            let fe = c.run(i, kmh, &mut scratch);
            let v = kmh / KMH;
            let zeta = |w: f64| al / (2.0 * w) + be * w / 2.0;
            let h = response(
                &span,
                train,
                v,
                dt,
                c.steps(train, v) + 1,
                &stations,
                modes,
                &zeta,
            );
            let (mut acc, mut defl) = (0.0f64, 0.0f64);
            for (a, y) in h.acceleration.iter().zip(&h.deflection) {
                let mut a = a.clone();
                lp.apply(&mut a, dt, fc);
                acc = a.iter().fold(acc, |m, x| m.max(x.abs()));
                defl = y.iter().fold(defl, |m, x| m.max(x.abs()));
            }
            out.0 = out.0.max((fe.acceleration / acc - 1.0).abs());
            out.1 = out.1.max((fe.deflection / defl - 1.0).abs());
        }
    }
    Ok(out)
}

fn main() -> Result<(), FemError> {
    println!("| elements per span | steps per cut-off period | modes of the reference | acceleration [%] | deflection [%] |");
    println!("|---|---|---|---|---|");
    // The defaults (12 elements, 60 steps per period) among meshes and steps around
    // them, then the reference's mode count at the defaults.
    let cases = [
        (10, 40.0, 30),
        (20, 40.0, 30),
        (10, 60.0, 30),
        (10, 80.0, 30),
        (10, 120.0, 30),
        (11, 60.0, 30),
        (12, 50.0, 30),
        (12, 56.0, 30),
        (12, 60.0, 30),
        (12, 70.0, 30),
        (12, 80.0, 30),
        (13, 60.0, 30),
        (14, 60.0, 30),
        (16, 60.0, 30),
        (20, 60.0, 30),
        (20, 80.0, 30),
        (40, 160.0, 30),
        (12, 60.0, 5),
        (12, 60.0, 10),
        (12, 60.0, 20),
        (12, 60.0, 25),
    ];
    for (per, spp, modes) in cases {
        let (a, d) = worst(per, spp, modes)?;
        println!(
            "| {per} | {spp:.0} | {modes} | {:.3} | {:.3} |",
            100.0 * a,
            100.0 * d
        );
    }
    Ok(())
}

//! The simplified methods of ERRI D214 (DER, LIR; `railfem::bridge_check::simplified`)
//! against the modal reference of `railfem bridge-check` for HSLM-A1…A10 on three simply
//! supported spans (docs/validation/closed-forms.md, "Simplified methods: DER and LIR"): per train, the
//! peak acceleration over 144–420 km/h (5 km/h steps) of the check's finite element deck
//! (10 elements, every node, Rayleigh damping, cut off), of the modal reference at midspan
//! (10 modes, constant ζ, cut off as the check does), of its first mode alone, and of DER
//! and LIR, with the ratios. Prints a Markdown table.
//!
//! `cargo run --release --example simplified_methods`

use railfem::bridge_check::bridge::{simply_supported_frequency, table_6_6, BridgeKind};
use railfem::bridge_check::envelope::{Check, KMH};
use railfem::bridge_check::fe::{described_model, rayleigh, Deck, Stepper};
use railfem::bridge_check::filter::{cutoff, LowPass};
use railfem::bridge_check::interaction::VehicleModel;
use railfem::bridge_check::modal::{response, Span};
use railfem::bridge_check::simplified::{self, estimate, Method};
use railfem::bridge_check::trains::hslm_a;
use std::f64::consts::PI;

/// Spans: length (m), EI (N·m²), mass (kg/m); n₀ ≈ 10, 5 and 3.5 Hz.
const SPANS: [(f64, f64, f64); 3] = [
    (10.0, 6.08e9, 15e3),
    (20.0, 3.24e10, 20e3),
    (30.0, 1.005e11, 25e3),
];

fn main() -> Result<(), Box<dyn std::error::Error>> {
    println!("| span | n₀ [Hz] | ζ [%] | train | FE [m/s²] | modal [m/s²] | mode 1 [m/s²] | DER [m/s²] | LIR [m/s²] | DER/FE | LIR/FE | DER/modal | LIR/modal |");
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|---|");
    for (l, ei, mass) in SPANS {
        let span = Span {
            length: l,
            ei,
            mass,
        };
        let n0 = simply_supported_frequency(1, l, ei, mass);
        let zeta = table_6_6(BridgeKind::PrestressedConcrete, l);
        let fc = cutoff(n0, Some(simply_supported_frequency(3, l, ei, mass)));
        let dt = 1.0 / (20.0 * fc);
        let simple = simplified::Span {
            length: l,
            n0,
            mass,
            zeta,
        };
        // The check's FE deck of this span (as `railfem bridge-check` builds it).
        let model = described_model(&[l], ei, mass, 10).build()?;
        let ids: Vec<u64> = (1..=10).collect();
        let deck = Deck::new(model, &ids, 6, "simplified_methods")?;
        let f = &deck.frequencies;
        let fc_fe = cutoff(f[0], f.get(2).copied());
        let r = rayleigh(zeta, 2.0 * PI * f[0], 2.0 * PI * fc_fe);
        let stepper = Stepper::new(&deck, r.0, r.1, 1.0 / (40.0 * fc_fe))?;
        let trains: Vec<_> = (1..=10)
            .map(|i| hslm_a(i).expect("HSLM-A1…A10 exist"))
            .collect();
        let statics = vec![1.0; trains.len()];
        let c = Check {
            deck: &deck,
            stepper: &stepper,
            trains: &trains,
            statics: &statics,
            cutoff: fc_fe,
            tail: 1.0,
            vehicles: &[],
            full: &[],
            journal: None,
        };
        let speeds: Vec<f64> = (0..=55).map(|k| 144.0 + 5.0 * k as f64).collect();
        let jobs: Vec<(usize, VehicleModel, f64)> = (0..trains.len())
            .flat_map(|i| {
                speeds
                    .iter()
                    .map(move |&s| (i, VehicleModel::MovingForces, s))
            })
            .collect();
        let outcomes = c.run_all(&jobs, 2)?;
        for i in 1..=10 {
            let train = hslm_a(i).expect("HSLM-A1…A10 exist");
            let fe = outcomes
                .iter()
                .filter(|o| o.train == i - 1)
                .fold(0.0f64, |m, o| m.max(o.acceleration));
            let mut peak = [0.0f64; 4];
            let mut lp = LowPass::default();
            let mut kmh = 144.0;
            while kmh <= 420.0 + 1e-9 {
                let v = kmh / KMH;
                let samples = ((train.length() + l) / v / dt + 1.0 / dt) as usize;
                for (j, modes) in [(0, 10), (1, 1)] {
                    let h = response(&span, &train, v, dt, samples, &[l / 2.0], modes, &|_| zeta);
                    let mut a = h.acceleration[0].clone();
                    lp.apply(&mut a, dt, fc);
                    peak[j] = a.iter().fold(peak[j], |m, x| m.max(x.abs()));
                }
                peak[2] = peak[2].max(estimate(Method::Der, &simple, &train, v).acceleration);
                peak[3] = peak[3].max(estimate(Method::Lir, &simple, &train, v).acceleration);
                kmh += 5.0;
            }
            println!(
                "| {l:.0} m | {n0:.2} | {:.2} | {} | {fe:.3} | {:.3} | {:.3} | {:.3} | {:.3} | {:.2} | {:.2} | {:.2} | {:.2} |",
                zeta * 100.0,
                train.name,
                peak[0],
                peak[1],
                peak[2],
                peak[3],
                peak[2] / fe,
                peak[3] / fe,
                peak[2] / peak[0],
                peak[3] / peak[0],
            );
        }
    }
    Ok(())
}

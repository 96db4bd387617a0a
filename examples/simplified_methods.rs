//! The simplified methods of ERRI D214 (DER, LIR; `railfem::bridge_check::simplified`)
//! against the modal reference of `railfem bridge-check` for HSLM-A1…A10 on three simply
//! supported spans (docs/validation.md, "Simplified methods: DER and LIR"): per train, the
//! peak midspan acceleration over 144–420 km/h (5 km/h steps) of the modal reference
//! (10 modes, cut off as the check does), of its first mode alone, and of DER and LIR, with
//! the ratios. Prints a Markdown table.
//!
//! `cargo run --release --example simplified_methods`

use railfem::bridge_check::bridge::{simply_supported_frequency, table_6_6, BridgeKind};
use railfem::bridge_check::envelope::KMH;
use railfem::bridge_check::filter::{cutoff, LowPass};
use railfem::bridge_check::modal::{response, Span};
use railfem::bridge_check::simplified::{self, estimate, Method};
use railfem::bridge_check::trains::hslm_a;

/// Spans: length (m), EI (N·m²), mass (kg/m); n₀ ≈ 10, 5 and 3.5 Hz.
const SPANS: [(f64, f64, f64); 3] = [
    (10.0, 6.08e9, 15e3),
    (20.0, 3.24e10, 20e3),
    (30.0, 1.005e11, 25e3),
];

fn main() {
    println!("| span | n₀ [Hz] | ζ [%] | train | modal [m/s²] | mode 1 [m/s²] | DER [m/s²] | LIR [m/s²] | DER/modal | LIR/modal | DER/mode 1 | LIR/mode 1 |");
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|");
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
        for i in 1..=10 {
            let train = hslm_a(i).expect("HSLM-A1…A10 exist");
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
                "| {l:.0} m | {n0:.2} | {:.2} | {} | {:.3} | {:.3} | {:.3} | {:.3} | {:.2} | {:.2} | {:.2} | {:.2} |",
                zeta * 100.0,
                train.name,
                peak[0],
                peak[1],
                peak[2],
                peak[3],
                peak[2] / peak[0],
                peak[3] / peak[0],
                peak[2] / peak[1],
                peak[3] / peak[1],
            );
        }
    }
}

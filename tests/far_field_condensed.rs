//! The condensed Newton with reduced blocks (`railfem_solvers::condensed`, *Reduced
//! blocks*): on the four-span case of `tests/far_field.rs` (one carriage from the
//! approach, 400-equation blocks cut at the joints, 20 m reach, the synthetic record,
//! Δt = 2 ms, 0.3 s), the run whose steps iterate on the top system alone takes the
//! full-residual Newton's iterates, so its answers differ by round-off only: every
//! midspan deflection within 1e-9 of the largest, the final state within 1e-9 of its
//! largest entry, every wheel's Q within 1e-8 of the static wheel load. A Newton step
//! converges to `tol` = 1e-6 of its forces, so a different iterate taken, or another
//! equation solved, would show far above these bounds; the same comparison without
//! reduced blocks (printed) measures the condensed Newton's own round-off on this case
//! (4.4e-10 of the wheel load). And the condensed Newton takes every step: none is
//! handed back to the full-residual Newton.
//!
//! `cargo test --release --test far_field_condensed -- --nocapture` prints the numbers.

use railfem::far_field::{FarFieldChoice, FarFieldOptions};
use railfem::framework::model::SolverChoice;
use railfem::solvers::partition::PartitionOptions;
use railfem::train_bridge::{build, run, Quake, TrainBridgeCase, TrainBridgeReport};

const STEPS: usize = 150;

struct Outcome {
    report: TrainBridgeReport,
    q: Vec<f64>,
    wheel_q: Vec<f64>,
    condensed_steps: usize,
    fallbacks: usize,
}

fn crossing(condense: bool, reduced: bool) -> Outcome {
    let case = TrainBridgeCase {
        cars: 1,
        spans: 4,
        dt: 0.002,
        quake: Quake::File("examples/records/synthetic_kt.csv".into()),
        solver: SolverChoice::Partitioned,
        far_field: if reduced {
            FarFieldChoice::Reduced(FarFieldOptions {
                cutoff_hz: None,
                reach: Some(20.0),
            })
        } else {
            FarFieldChoice::Full
        },
        ..Default::default()
    };
    let mut m = build(&case).expect("model");
    m.driver.set_partition_options(PartitionOptions {
        block_size: 400,
        threads: 0,
        ..Default::default()
    });
    m.driver.set_condense_residual(condense);
    let report = run(&mut m, &case, Some(STEPS), None).expect("run");
    let names = m.driver.model.elements[m.wheel_index[0]]
        .element
        .output_names();
    let at = names.iter().position(|n| n == "Q").expect("Q output");
    let wheel_q = m
        .wheel_index
        .iter()
        .map(|&e| {
            let mut out = Vec::new();
            m.driver.model.elements[e].element.outputs(&mut out);
            out[at]
        })
        .collect();
    let c = m.driver.condensed_stats();
    Outcome {
        report,
        q: m.driver.state.q.clone(),
        wheel_q,
        condensed_steps: c.steps,
        fallbacks: c.fallbacks,
    }
}

#[test]
fn the_condensed_newton_with_reduced_blocks_takes_the_full_newton_steps() {
    let (full, condensed) = (crossing(false, true), crossing(true, true));
    let baseline = differences(&crossing(false, false), &crossing(true, false));
    println!(
        "without reduced blocks, condensed − full: midspan {:.2e}, wheel Q {:.2e}, state {:.2e}",
        baseline[0], baseline[1], baseline[2]
    );
    let far = condensed.report.far_field.expect("far field");
    println!(
        "condensed Newton: {} of {STEPS} steps, {} handed back; far field: {} of {} block-steps reduced, {} switches to reduced, {} to full",
        condensed.condensed_steps,
        condensed.fallbacks,
        far.reduced_block_steps,
        far.block_steps,
        far.to_reduced,
        far.to_full
    );
    assert!(far.to_reduced > 0 && far.reduced_block_steps > 0);
    assert_eq!(condensed.fallbacks, 0);
    assert_eq!(condensed.condensed_steps, STEPS);
    assert_eq!(full.condensed_steps, 0);
    let [midspan, wheel, state] = differences(&full, &condensed);
    let total = full
        .report
        .midspan
        .iter()
        .flat_map(|(_, h)| h.iter().map(|p| p.1.abs()))
        .fold(0.0_f64, f64::max);
    let midspan_total = midspan * dynamic_peak(&full) / total;
    println!(
        "condensed − full: midspan {midspan:.2e} of the largest w − w(0) ({midspan_total:.2e} of the largest w), wheel Q {wheel:.2e}, state {state:.2e}"
    );
    assert!(midspan_total <= 1e-9, "midspan {midspan_total:e}");
    assert!(wheel <= 1e-8, "wheel Q {wheel:e}");
    assert!(state <= 1e-9, "state {state:e}");
}

/// The largest midspan `|w − w(0)|` of a run (m).
fn dynamic_peak(a: &Outcome) -> f64 {
    a.report
        .midspan
        .iter()
        .flat_map(|(_, h)| h.iter().map(|p| (p.1 - h[0].1).abs()))
        .fold(0.0_f64, f64::max)
}

/// The largest differences of two runs: midspan deflection against the largest `w − w(0)`,
/// wheel Q against the largest static wheel load, and the state against its largest entry.
fn differences(a: &Outcome, b: &Outcome) -> [f64; 3] {
    let (mut peak, mut worst) = (0.0_f64, 0.0_f64);
    for ((_, x), (_, y)) in a.report.midspan.iter().zip(&b.report.midspan) {
        for (u, v) in x.iter().zip(y) {
            peak = peak.max((u.1 - x[0].1).abs());
            worst = worst.max((u.1 - v.1).abs());
        }
    }
    let largest = |v: &[f64]| v.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
    let diff = |u: &[f64], v: &[f64]| {
        u.iter()
            .zip(v)
            .map(|(x, y)| (x - y).abs())
            .fold(0.0_f64, f64::max)
    };
    [
        worst / peak,
        diff(&a.wheel_q, &b.wheel_q) / largest(&a.report.q_static),
        diff(&a.q, &b.q) / largest(&a.q),
    ]
}

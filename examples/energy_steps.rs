//! The energy ledgers of two runs of one case, step by step (`energy.csv` of each, as
//! `railfem train-bridge` writes it): for each run its largest accumulated integrator
//! residual against its largest external work, and the range of one step's residual;
//! between the two, the largest difference of a step's residual and, from each switch
//! the second run booked (a block switched to its reduced form, column `switched`), the
//! six steps from it side by side (docs/reduced-far-field.md, "The energy balance after
//! a switch").
//!
//! `cargo run --release --example energy_steps -- OUT/entry-full OUT/entry-reduced`

use railfem::framework::outputs::ENERGY_CSV;
use railfem::framework::FemError;
use railfem::window_error::{read_columns, Columns};
use std::path::{Path, PathBuf};

/// The steps compared from each switch: the one from the switched state and five after.
const AFTER_SWITCH: usize = 6;

/// A run's ledger, one value per step: accumulated integrator residual, external work,
/// and energy booked at switches (zero without the column), in J.
struct Ledger {
    /// The time at the end of each step (s).
    time: Vec<f64>,
    integrator: Vec<f64>,
    external: Vec<f64>,
    switched: Vec<f64>,
}

impl Ledger {
    fn read(dir: &Path) -> Result<Ledger, FemError> {
        let path = dir.join(ENERGY_CSV);
        let c = read_columns(&path)?;
        let need = |name: &str| {
            column_of(&c, name).ok_or_else(|| {
                FemError::input(
                    path.display().to_string(),
                    format!("no column `{name}`; give the directory of a transient run"),
                )
            })
        };
        let integrator = need("integrator")?;
        let switched = column_of(&c, "switched").unwrap_or_else(|| vec![0.0; integrator.len()]);
        Ok(Ledger {
            time: need("time")?,
            external: need("external_work")?,
            integrator,
            switched,
        })
    }

    /// Each step's residual: the change of the accumulated one (the first row is the
    /// first step's).
    fn steps(&self) -> Vec<f64> {
        let mut last = 0.0;
        self.integrator
            .iter()
            .map(|&x| {
                let d = x - last;
                last = x;
                d
            })
            .collect()
    }
}

/// Column `name` (the header cell before its unit).
fn column_of(c: &Columns, name: &str) -> Option<Vec<f64>> {
    let i = c
        .head
        .iter()
        .position(|h| h.split(" [").next() == Some(name))?;
    Some(c.cols[i].clone())
}

fn largest(x: &[f64]) -> f64 {
    x.iter().fold(0.0f64, |m, v| m.max(v.abs()))
}

fn main() -> Result<(), FemError> {
    let dirs: Vec<PathBuf> = std::env::args_os().skip(1).map(PathBuf::from).collect();
    let [first, second] = dirs.as_slice() else {
        return Err(FemError::input(
            "command line",
            "give two runs' directories: the full run's, then the other's",
        ));
    };
    let runs = [Ledger::read(first)?, Ledger::read(second)?];
    let steps = runs.each_ref().map(Ledger::steps);
    for ((dir, run), step) in dirs.iter().zip(&runs).zip(&steps) {
        let (lo, hi) = step
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &x| {
                (l.min(x), h.max(x))
            });
        println!(
            "{}: {} steps; largest |integrator| {:.4e} J, largest |W_ext| {:.4e} J, ratio {:.3e}; at the end {:.5e} J; a step's residual from {lo:.3e} to {hi:.3e} J",
            dir.display(),
            step.len(),
            largest(&run.integrator),
            largest(&run.external),
            largest(&run.integrator) / largest(&run.external),
            run.integrator.last().copied().unwrap_or(0.0),
        );
    }
    let n = steps[0].len().min(steps[1].len());
    let diff = |k: usize| (steps[1][k] - steps[0][k]).abs();
    let worst = (0..n).map(diff).fold(0.0f64, f64::max);
    println!(
        "a step's residual, second run − first: largest {worst:.3e} J ({:.2e} of the first run's largest step)",
        worst / largest(&steps[0][..n])
    );
    let mut booked = 0.0;
    for k in 0..n {
        let now = runs[1].switched[k];
        if now == booked {
            continue;
        }
        let window = k..(k + AFTER_SWITCH).min(n);
        let show = |s: &[f64]| {
            s[window.clone()]
                .iter()
                .map(|x| format!("{x:.4e}"))
                .collect::<Vec<_>>()
                .join(", ")
        };
        let largest_full = largest(&steps[0][window.clone()]);
        let worst = window.clone().map(diff).fold(0.0f64, f64::max);
        println!(
            "switch booked before the step to t = {:.4} s ({:.4e} J): second run {}; first run {}; largest difference {worst:.3e} J ({:.2} % of the first run's largest of these)",
            runs[1].time[k],
            now - booked,
            show(&steps[1]),
            show(&steps[0]),
            100.0 * worst / largest_full
        );
        booked = now;
    }
    Ok(())
}

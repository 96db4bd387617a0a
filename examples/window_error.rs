//! The activity window's error against the full model (`railfem::window_error`): the
//! first directory is a `railfem train-bridge --window off` run, each further one a
//! windowed run of the same case; one markdown table row per windowed run, in percent of
//! the full run's peaks (docs/activity-window.md, "Error against the full model").
//!
//! `cargo run --release --example window_error -- out/entry-off out/entry-100 out/entry-150`

use railfem::framework::FemError;
use railfem::window_error::{case_of_run, compare, span_under_train};
use std::path::PathBuf;

fn main() -> Result<(), FemError> {
    let dirs: Vec<PathBuf> = std::env::args_os().skip(1).map(PathBuf::from).collect();
    let Some((full, windowed)) = dirs.split_first().filter(|(_, w)| !w.is_empty()) else {
        return Err(FemError::input(
            "command line",
            "give the full run's directory, then one or more windowed runs' directories",
        ));
    };
    let under = span_under_train(&case_of_run(full)?);
    println!("| run | samples | Q | ΔQ/Q | ΔQ/Q (own peak) | Y/Q (absolute; peak) | midspan w − w(0), spans under the train | every span | integrator residual full / windowed (J) | its difference / W_ext |");
    println!("|---|---|---|---|---|---|---|---|---|---|");
    for w in windowed {
        let e = compare(full, w, &under)?;
        let pct = |x: f64| format!("{:.3} %", 100.0 * x);
        let energy = e
            .energy
            .map_or(("n/a".to_string(), "n/a".to_string()), |[a, b, wext]| {
                (
                    format!("{a:.6e} / {b:.6e}"),
                    format!("{:.2e}", (b - a).abs() / wext.abs().max(f64::MIN_POSITIVE)),
                )
            });
        println!(
            "| {} | {} | {} | {} | {} | {:.1e} ({:.1e}) | {} | {} | {} | {} |",
            w.display(),
            e.samples,
            pct(e.q.relative()),
            pct(e.dqq.relative()),
            pct(e.dqq.own),
            e.yq.largest,
            e.yq.peak,
            pct(e.deflection_under.relative()),
            pct(e.deflection.relative()),
            energy.0,
            energy.1
        );
    }
    Ok(())
}

//! railfem: nonlinear dynamic finite elements for trains on curved, canted track.
//!
//! This facade re-exports the three packages — [`framework`] (model, element contract,
//! registry, assembly, loads, moving frames, recorders), [`elements`] (beam3d,
//! spring_damper, mass, and the rail toolkit with the moving wheel-axle element of Ju & Ro
//! 2021) and [`solvers`] (linear solvers, integrators, the driver) — and holds the
//! command-line interface ([`cli`]). Units are SI throughout: m, kg, s, N, rad.
#![deny(missing_docs)]
// Index loops are the clearest way to write small dense matrix algebra.
#![allow(clippy::needless_range_loop)]

pub use railfem_elements as elements;
pub use railfem_framework as framework;
pub use railfem_solvers as solvers;

pub mod args;
pub mod assess;
pub mod atomic_file;
pub mod bench;
pub mod bench_train;
pub mod bench_window;
pub mod bridge_check;
pub mod choice;
pub mod cli;
pub mod command;
pub mod commands;
pub mod contact_tool;
pub mod cpu_time;
pub mod critical;
pub mod curve;
pub mod far_field;
pub mod floor;
pub mod irregularity;
pub mod matrices;
pub mod oscillators;
pub mod pareto;
pub mod pareto_train;
pub mod progress;
pub mod ranks;
pub mod reference;
pub mod rolling_contact;
pub mod run_window;
pub mod sidecar;
pub mod small_models;
pub mod stress;
pub mod study;
pub mod train_bridge;
pub mod train_window;
pub mod window_error;

/// Loads a model file, building every element through the registry.
pub fn load_model(path: &std::path::Path) -> Result<framework::Model, framework::FemError> {
    framework::modelfile::read(path)?.build()
}

/// Builds a model from an already-parsed model-file value (the JSON form of the file;
/// `name` stands for the file in messages, `base` resolves relative plugin paths).
pub fn model_from_value(
    value: &serde_json::Value,
    name: &str,
    base: &std::path::Path,
) -> Result<framework::Model, framework::FemError> {
    framework::modelfile::from_value(value, name, base)?.build()
}

/// The one validation `railfem check`, `railfem run` and the Python bindings share: build
/// the driver for `model` (equation numbering, pattern, constant matrices) and run the
/// preflight checks (singularity, stability, size). Errors name `file`; the preflight's
/// warnings are returned for the caller to show.
pub fn prepare(
    model: Result<framework::Model, framework::FemError>,
    file: &str,
    estimate_factor: bool,
) -> Result<(solvers::Driver, solvers::preflight::Preflight), framework::FemError> {
    prepare_on(model, file, estimate_factor, None)
}

/// [`prepare`], and with `ranks` the driver of one rank of them
/// (`Driver::new_across_ranks`: the partitioned solver's blocks shared, `K`, `M`, `C`
/// formed on the rank's columns only; the preflight reads their whole diagonals).
pub fn prepare_on(
    model: Result<framework::Model, framework::FemError>,
    file: &str,
    estimate_factor: bool,
    ranks: Option<std::sync::Arc<dyn solvers::exchange::Exchange>>,
) -> Result<(solvers::Driver, solvers::preflight::Preflight), framework::FemError> {
    let model = model.map_err(|e| e.in_file(file))?;
    let mut driver = match ranks {
        None => solvers::Driver::new(model),
        Some(ex) => solvers::Driver::new_across_ranks(model, ex, None),
    }
    .map_err(|e| e.in_file(file))?;
    let pre = driver
        .preflight(estimate_factor)
        .map_err(|e| e.in_file(file))?;
    Ok((driver, pre))
}

#[doc = include_str!("../docs/custom-element.md")]
pub mod custom_element_tutorial {}

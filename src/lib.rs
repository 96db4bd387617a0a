//! railfem: nonlinear dynamic finite elements for trains on curved, canted track.
//!
//! This facade re-exports the three packages — [`framework`] (model, element contract,
//! registry, assembly, loads, moving frames, recorders), [`elements`] (beam3d,
//! spring_damper, mass, and the rail toolkit with the moving wheel-axle element of Ju & Ro
//! 2021) and [`solvers`] (linear solvers, integrators, the driver) — and holds the
//! command-line interface ([`cli`]). Units are SI throughout: m, kg, s, N, rad.

// Index loops are the clearest way to write small dense matrix algebra.
#![allow(clippy::needless_range_loop)]

pub use railfem_elements as elements;
pub use railfem_framework as framework;
pub use railfem_solvers as solvers;

pub mod bench;
pub mod bench_train;
pub mod cli;
pub mod critical;
pub mod curve;
pub mod irregularity;
pub mod matrices;
pub mod oscillators;
pub mod pareto;
pub mod stress;
pub mod train_bridge;

/// Loads a model file, building every element through the registry.
pub fn load_model(path: &std::path::Path) -> Result<framework::Model, framework::FemError> {
    elements::link();
    framework::modelfile::read(path)?.build()
}

#[doc = include_str!("../docs/custom-element.md")]
pub mod custom_element_tutorial {}

//! railfem-solvers: linear solvers, time integrators and the analysis driver.
//!
//! What lives here: sparse and dense linear solvers ([`linear`], [`dense`], the replayed LU
//! [`static_lu`]) and the driver's linear backend that holds them with the effective matrix
//! and the factor cache ([`linear_backend`]), the low-rank (Woodbury) solver for a few moving equations ([`lowrank`]), modal analysis ([`modal`]), the Craig–Bampton reduction of a linear block to its boundary
//! and its fixed-interface modes ([`reduced`]), the
//! generalized-α family of integrators ([`integrator`]) and the Bathe composite method
//! ([`bathe`]) behind the integrator trait and registry ([`time_integrator`]), the energy
//! balance of a run
//! ([`energy`]) and the driver that runs static and
//! transient analyses with Newton–Raphson and step cutting ([`driver`]), each attempt at a
//! step solved by a step method behind a trait ([`step_method`]: full Newton, the condensed
//! Newton [`condensed`], a lumped linear model's step in fused passes [`lumped_step`], the
//! held active set's retry [`held_active_set`]), and the checks made
//! before its first step ([`preflight`]); the committed state ([`state`]) and the solver
//! switch-over sizes ([`thresholds`]). What does not:
//! elements (railfem-elements) and the model itself (railfem-framework).
#![deny(missing_docs)]
// Index loops mirror the formulas of the dense kernels and the driver (rustc 1.95 clippy).
#![allow(clippy::needless_range_loop, clippy::explicit_counter_loop)]

pub mod bathe;
mod chunks;
pub mod compact_factor;
pub mod condensed;
pub mod condensed_cache;
pub mod dense;
pub mod driver;
pub mod energy;
pub mod exchange;
pub mod held_active_set;
pub mod held_rows;
pub mod integrator;
pub mod linear;
pub mod linear_backend;
pub mod lowrank;
pub mod lumped_step;
pub mod mechanism;
pub mod modal;
pub mod partition;
pub mod preflight;
pub mod reduced;
pub mod state;
pub mod static_lu;
pub mod step_method;
pub mod thresholds;
pub mod time_integrator;
pub mod top_chain;
pub mod window;

pub use driver::{Driver, ReferenceSystem, RunSummary, State, StepReport};
pub use step_method::{Accepted, Attempt, StepMethod};

//! The reduced far field of `train-bridge` (docs/reduced-far-field.md): what the case
//! needs to run blocks of the viaduct in their Craig–Bampton form
//! ([`crate::solvers::reduced::blocks`]).
//!
//! This module holds the viaduct alone under a ground motion ([`viaduct`]): the track on
//! the bridge and its approaches, no train, no gravity, so that the model is linear and
//! starts at rest — the case on which a driver with reduced blocks is checked against the
//! library's own march of the same reduced model (`tests/far_field.rs`).

use crate::elements::rail::geometry::track_model::{self, TrackModel};
use crate::framework::builder::ModelBuilder;
use crate::framework::model::{AnalysisSpec, SolverChoice};
use crate::framework::FemError;
use crate::solvers::Driver;
use crate::train_bridge::{ground_motion, QuakeRecord, TrainBridgeCase};
use std::sync::Arc;

/// The viaduct of `case` (its spans, approaches and mesh; no train, no gravity) under the
/// ground motion `quake`, with the partitioned solver at `block_size` interior equations
/// per block and `case`'s integrator and step: a driver ready to step, with the track
/// model (for its midspan nodes).
pub fn viaduct(
    case: &TrainBridgeCase,
    quake: &QuakeRecord,
    block_size: usize,
) -> Result<(Driver, Arc<TrackModel>), FemError> {
    let mut b = ModelBuilder::new("far-field viaduct");
    let tm = track_model::generate(
        &mut b,
        Arc::new(case.track()?),
        &case.mesh(case.element_length),
    )?;
    b.analysis(AnalysisSpec {
        dt: case.dt,
        duration: case.duration.unwrap_or(1.0),
        integrator: case.integrator.clone(),
        rho_inf: case.rho_inf,
        alpha: (1.0 - case.rho_inf) / (1.0 + case.rho_inf),
        solver: SolverChoice::Partitioned,
        block_size: Some(block_size),
        initial_static: false,
        ..Default::default()
    });
    ground_motion(&mut b, quake);
    Ok((Driver::new(b.build()?)?, tm))
}

//! Moving oscillators: a sprung mass ([`sprung_mass`], `moving_sprung_mass`) and a rolling
//! mass ([`moving_mass`], `moving_mass`) that ride along a beam path or a track rail at a
//! prescribed speed history — the first benchmark of every train–bridge code.
//!
//! What lives here: the path and the contact point under the oscillator ([`path`]), the two
//! elements, and what they share (the speed keys, the conformance context). What does not:
//! the speed history itself ([`railfem_framework::speed`]), the chain walking
//! ([`railfem_framework::beam_chain`]), vehicles with several bodies (the rail toolkit).
//! The derivation and the validation against modal solutions are in
//! `docs/moving-oscillators.md`.

pub mod moving_mass;
pub mod path;
pub mod sprung_mass;

use nalgebra::Vector3;
use railfem_framework::registry::{BuildContext, ElementSpec};
use railfem_framework::speed::SpeedHistory;
use railfem_framework::FemError;

/// The speed history from an oscillator's keys: `speed_table` when given (then `speed`
/// and `accel` must be left out or zero), else `speed` and `accel`.
pub(crate) fn speed_history(
    spec: &ElementSpec,
    kind: &str,
    start: f64,
    speed: f64,
    accel: f64,
    table: &[[f64; 2]],
) -> Result<SpeedHistory, FemError> {
    let bad = |m: String| FemError::input(&spec.origin, format!("{kind}: {m}"));
    if !table.is_empty() {
        if speed != 0.0 || accel != 0.0 {
            return Err(bad(
                "give either `speed_table` or `speed`/`accel`, not both; remove one".into(),
            ));
        }
        SpeedHistory::from_table(start, table, "speed_table").map_err(bad)
    } else {
        SpeedHistory::uniform(start, speed, accel).map_err(bad)
    }
}

/// `Σ aᵢ·bᵢ`.
pub(crate) fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// The build context of the conformance samples: node ids 1, 2, … at `pos`, and one beam
/// element, id 10, on nodes 2 and 3 (the path).
pub(crate) struct SampleContext {
    pub(crate) pos: Vec<Vector3<f64>>,
}

impl BuildContext for SampleContext {
    fn node_index(&self, id: u64) -> Option<usize> {
        let i = usize::try_from(id).ok()?.checked_sub(1)?;
        (i < self.pos.len()).then_some(i)
    }
    fn node_position(&self, index: usize) -> Vector3<f64> {
        self.pos[index]
    }
    fn add_internal_node(&mut self, position: Vector3<f64>, _like: Option<usize>) -> usize {
        self.pos.push(position);
        self.pos.len() - 1
    }
    fn resource(&self, _name: &str) -> Option<std::sync::Arc<dyn std::any::Any + Send + Sync>> {
        None
    }
    fn element_nodes(&self, id: u64) -> Option<(String, Vec<usize>)> {
        (id == 10).then(|| ("beam3d".to_string(), vec![1, 2]))
    }
}

/// Positions of the sample nodes: the mass node above a skew, inclined beam.
pub(crate) fn sample_positions() -> Vec<Vector3<f64>> {
    vec![
        Vector3::new(0.5, 0.0, 1.0),
        Vector3::new(0.0, 0.0, 0.0),
        Vector3::new(2.0, 0.4, 0.1),
    ]
}

//! The result of one train at one speed ([`Outcome`]): what the envelope tabulates and the
//! resume journal keeps.

use super::interaction::VehicleModel;

/// The result of one train at one speed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Outcome {
    /// Index of the train.
    pub train: usize,
    /// How the train's axles were modelled.
    pub model: VehicleModel,
    /// Speed (km/h).
    pub speed: f64,
    /// Peak filtered deck acceleration (m/s², magnitude).
    pub acceleration: f64,
    /// Where (m along the deck) and when (s after the first axle entered) it occurs.
    pub acc_station: f64,
    /// Time of the peak acceleration (s).
    pub acc_time: f64,
    /// Peak deflection (m, magnitude).
    pub deflection: f64,
    /// Where the peak deflection occurs (m along the deck).
    pub defl_station: f64,
    /// Largest static deflection of the same train (m).
    pub static_deflection: f64,
}

impl Outcome {
    /// The dynamic factor `max|y_dyn| / max|y_stat|` (= 1 + φ'_dyn).
    pub fn dynamic_factor(&self) -> f64 {
        self.deflection / self.static_deflection
    }
}

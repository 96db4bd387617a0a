//! Tread defects of one copy of a vehicle in a train: a train that repeats a vehicle file
//! (`count`, or several `vehicles` entries) gives a defect to one wheel of one carriage with
//! the train key `defects = [{vehicle = 2, wheelset = 1, side = "left", defect = {…}}]`
//! (docs/defects.md). `vehicle` counts the train's vehicles from the front, `wheelset` the
//! vehicle's `[[wheelset]]` entries in their order, both from 1. The defect replaces the
//! one the vehicle definition gives that wheel, in that copy only.

use super::definition::VehicleDef;
use crate::rail::wheels::wheel_defect::WheelDefect;
use railfem_framework::error::FemError;
use serde::Deserialize;

/// A wheel of a train.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Side {
    /// The left wheel (`"left"`).
    Left,
    /// The right wheel (`"right"`).
    Right,
}

/// One entry of a train's `defects`.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct InstanceDefect {
    /// The vehicle, counted from the front of the train from 1.
    pub vehicle: usize,
    /// The wheelset, counted in the vehicle's `[[wheelset]]` order from 1.
    pub wheelset: usize,
    /// The wheel.
    pub side: Side,
    /// The tread defect (the wheel elements' `defect` key).
    pub defect: WheelDefect,
}

/// Gives each entry of `defects` to its wheel of `vehicles` (the train, front to back).
/// `origin` names the train for messages and `at` its key path; an index out of range is
/// refused with its key path and the range.
pub fn apply(
    vehicles: &mut [VehicleDef],
    defects: &[InstanceDefect],
    origin: &str,
    at: &str,
) -> Result<(), FemError> {
    for (k, d) in defects.iter().enumerate() {
        let here = format!("{at}.defects[{k}]");
        let n = vehicles.len();
        if d.vehicle == 0 || d.vehicle > n {
            return Err(FemError::input(
                origin,
                format!(
                    "`{here}.vehicle` = {}: the train has {n} vehicle(s); fix: give 1 … {n}, counted from the front",
                    d.vehicle
                ),
            ));
        }
        let v = &mut vehicles[d.vehicle - 1];
        let m = v.wheelsets.len();
        if d.wheelset == 0 || d.wheelset > m {
            return Err(FemError::input(
                origin,
                format!(
                    "`{here}.wheelset` = {}: vehicle {} has {m} wheelset(s); fix: give 1 … {m}, in its [[wheelset]] order",
                    d.wheelset, d.vehicle
                ),
            ));
        }
        let w = &mut v.wheelsets[d.wheelset - 1].defects;
        match d.side {
            Side::Left => w.left = d.defect.clone(),
            Side::Right => w.right = d.defect.clone(),
        }
    }
    Ok(())
}

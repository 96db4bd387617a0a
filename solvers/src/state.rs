//! The committed state of a run: time, displacements, velocities, accelerations and the
//! internal and external forces at them, as equation vectors. The driver commits it after
//! each converged step; the energy ledger and the recorders read it.

/// The committed state of a run.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct State {
    /// Time (s).
    pub t: f64,
    /// Displacements (equation vector; m, rad).
    pub q: Vec<f64>,
    /// Velocities.
    pub v: Vec<f64>,
    /// Accelerations.
    pub a: Vec<f64>,
    /// Internal force at the state.
    pub f_int: Vec<f64>,
    /// External force at the state.
    pub f_ext: Vec<f64>,
}

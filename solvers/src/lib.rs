//! railfem solvers.

pub mod linear;
pub mod modal;

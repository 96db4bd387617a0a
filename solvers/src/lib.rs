//! railfem solvers.

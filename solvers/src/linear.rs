//! Placeholder: the sparse solvers land from the solvers branch.
use railfem_framework::sparse::CscMatrix;
use thiserror::Error;
/// Errors.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum SolverError {
    /// Singular.
    #[error("singular at equation {equation}")]
    Singular {
        /// Equation.
        equation: usize,
    },
    /// Failed.
    #[error("{0}")]
    Failed(String),
}
/// Stats.
#[derive(Debug, Clone, Copy, Default)]
pub struct SolverStats {
    /// Symbolic.
    pub symbolic: usize,
    /// Numeric.
    pub numeric: usize,
    /// Solves.
    pub solves: usize,
}
/// Solver.
pub trait LinearSolver: Send {
    /// Factor.
    fn factor(&mut self, a: &CscMatrix) -> Result<(), SolverError>;
    /// Solve.
    fn solve_in_place(&mut self, b: &mut [f64]) -> Result<(), SolverError>;
    /// Stats.
    fn stats(&self) -> SolverStats;
}
/// Factory.
pub fn solver_for(_symmetric: bool) -> Box<dyn LinearSolver> {
    Box::new(crate::dense::DenseLu::default())
}

//! The driver's linear backend ([`LinearBackend`]): the linear solver of the run (the
//! direct one, or the partitioned or low-rank solver when the variable elements are kept
//! off the pattern), the effective matrix handed to it and the cache of its factor.
//!
//! A factorization is two steps, as in faer's symbolic/numeric split:
//! [`LinearBackend::analyse`] takes a sparsity pattern and returns its [`Symbolic`]
//! analysis (the fill-reducing ordering and the symbolic factor of the sparse solvers,
//! made once per pattern), and [`LinearBackend::factor`] factors the values filled into
//! [`LinearBackend::values_mut`] on that pattern. The driver analyses again only when the
//! assembler's pattern changes (a moving element's new connectivity). The partitioned
//! solver splits the pattern into blocks in its own factorization
//! ([`crate::partition::Partitioned::prepare`]); the low-rank solver has no symbolic step.
//!
//! Where the memory comes from: the effective matrix is allocated on the pattern at its
//! analysis (in the direct mode) or at the first factorization (off the pattern, only the
//! columns a rank reads); the factors are the solvers' own ([`crate::linear`]).

use crate::linear::{LinearSolver, SolverError};
use crate::lowrank::LowRank;
use crate::partition::Partitioned;
use railfem_framework::sparse::CscMatrix;

/// The symbolic analysis of one sparsity pattern ([`LinearBackend::analyse`]): valid for
/// every matrix of that pattern, whatever its values.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Symbolic {
    /// The pattern's id ([`CscMatrix::pattern_id`]).
    pub pattern_id: u64,
    /// Number of equations.
    pub equations: usize,
    /// Stored entries of the pattern.
    pub entries: usize,
}

/// The linear solver of a run, its effective matrix and its factor cache (module
/// documentation).
pub struct LinearBackend {
    /// The solver of the whole tangent (the direct mode): dense or sparse by size
    /// ([`crate::driver::direct_solver`]).
    pub(crate) solver: Box<dyn LinearSolver>,
    /// The effective matrix last handed to a solver.
    pub(crate) k_eff: CscMatrix,
    /// The coefficients' [`railfem_framework::Coefficients::key`] and the pattern id the
    /// current factor belongs to, when it is still valid (for a one-stage integrator the key
    /// is a function of `dt` alone; a composite one's stages of the same length may
    /// differ).
    pub(crate) factored: Option<([f64; 3], u64)>,
    /// Coefficients `k_eff` holds the constant part for (partitioned and low-rank modes).
    pub(crate) a_key: Option<[f64; 3]>,
    /// Variable elements' effective triplets (partitioned and low-rank modes).
    pub(crate) triplets: Vec<(usize, usize, f64)>,
    /// The partitioned solver, when the assembler keeps variable elements off the pattern.
    pub(crate) partition: Option<Partitioned>,
    /// The low-rank solver, used instead of the partitioned one when the model resolves to
    /// `solver = "low_rank"` ([`crate::lowrank`]).
    pub(crate) lowrank: Option<LowRank>,
    /// The last analysis of the direct mode.
    symbolic: Option<Symbolic>,
}

impl LinearBackend {
    /// A backend with the direct solver `solver`, the effective matrix `k_eff` (empty off
    /// the pattern) and the partitioned or low-rank solver if the model uses one.
    pub(crate) fn new(
        solver: Box<dyn LinearSolver>,
        k_eff: CscMatrix,
        partition: Option<Partitioned>,
        lowrank: Option<LowRank>,
    ) -> LinearBackend {
        LinearBackend {
            solver,
            k_eff,
            factored: None,
            a_key: None,
            triplets: Vec::new(),
            partition,
            lowrank,
            symbolic: None,
        }
    }

    /// Replaces the direct solver; the next factorization analyses and factors anew.
    pub fn set_solver(&mut self, solver: Box<dyn LinearSolver>) {
        self.solver = solver;
        self.symbolic = None;
        self.factored = None;
    }

    /// The symbolic analysis of `pattern` by the direct solver (its values are not read,
    /// only their count checked),
    /// and the effective matrix allocated on it when it had another pattern.
    pub fn analyse(&mut self, pattern: &CscMatrix) -> Result<Symbolic, SolverError> {
        self.solver.analyse(pattern)?;
        if self.k_eff.pattern_id != pattern.pattern_id {
            self.k_eff = pattern.zeros_like();
        }
        let s = Symbolic {
            pattern_id: pattern.pattern_id,
            equations: pattern.n,
            entries: pattern.row_idx.len(),
        };
        self.symbolic = Some(s);
        Ok(s)
    }

    /// The last analysis, if it was of the pattern `pattern_id`.
    pub fn symbolic_of(&self, pattern_id: u64) -> Option<Symbolic> {
        self.symbolic.filter(|s| s.pattern_id == pattern_id)
    }

    /// The effective matrix on the pattern of `symbolic`, whose values the caller fills
    /// before [`LinearBackend::factor`].
    pub fn values_mut(&mut self, symbolic: &Symbolic) -> &mut CscMatrix {
        debug_assert_eq!(self.k_eff.pattern_id, symbolic.pattern_id);
        &mut self.k_eff
    }

    /// The numeric factorization of the values filled in ([`LinearBackend::values_mut`]),
    /// on the analysis `symbolic`; the factor is then valid for the coefficients `key`.
    pub fn factor(&mut self, symbolic: &Symbolic, key: [f64; 3]) -> Result<(), SolverError> {
        if self.k_eff.pattern_id != symbolic.pattern_id {
            return Err(SolverError::Failed(format!(
                "the effective matrix has pattern {} and the analysis is of pattern {}",
                self.k_eff.pattern_id, symbolic.pattern_id
            )));
        }
        self.factored = None;
        self.solver.factor(&self.k_eff)?;
        self.factored = Some((key, symbolic.pattern_id));
        Ok(())
    }

    /// Whether the factor held is that of the coefficients `key` on the pattern
    /// `pattern_id`.
    pub fn is_factored(&self, key: [f64; 3], pattern_id: u64) -> bool {
        self.factored == Some((key, pattern_id))
    }

    /// Forgets the factor: the next solve needs a new factorization.
    pub fn invalidate(&mut self) {
        self.factored = None;
    }

    /// Solves `A·x = b` in place with the factor held, by the solver of the run.
    pub fn solve_in_place(&mut self, b: &mut [f64]) -> Result<(), SolverError> {
        match (self.lowrank.as_mut(), self.partition.as_mut()) {
            (Some(l), _) => l.solve_in_place(b),
            (None, Some(p)) => p.solve_in_place(b),
            (None, None) => self.solver.solve_in_place(b),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linear::SparseCholesky;

    /// `s·T` with `T = tridiag(−1, 2, −1)` of order `n`.
    fn tridiagonal(n: usize, s: f64) -> CscMatrix {
        let mut t = Vec::new();
        for i in 0..n {
            t.push((i, i, 2.0 * s));
            if i + 1 < n {
                t.push((i + 1, i, -s));
                t.push((i, i + 1, -s));
            }
        }
        CscMatrix::from_triplets(n, &t)
    }

    /// One analysis serves every factorization of its pattern: two value sets (`T` and
    /// `3·T`) factored on it solve `T·x = b` and `3·T·x = b` for `b = T·x*`, `x*_i = i + 1`,
    /// to round-off (the exact answers `x*` and `x*/3`), with one symbolic analysis counted.
    #[test]
    fn one_analysis_serves_every_factorization_of_its_pattern() {
        let n = 40;
        let a = tridiagonal(n, 1.0);
        let exact: Vec<f64> = (0..n).map(|i| i as f64 + 1.0).collect();
        let mut b = vec![0.0; n];
        a.mul_vec(&exact, &mut b);
        let mut backend = LinearBackend::new(
            Box::new(SparseCholesky::new()),
            CscMatrix::from_columns(Vec::new()),
            None,
            None,
        );
        let symbolic = backend.analyse(&a).expect("analysis");
        assert_eq!(backend.symbolic_of(a.pattern_id), Some(symbolic));
        for scale in [1.0, 3.0] {
            let values = backend.values_mut(&symbolic);
            values.values.copy_from_slice(&tridiagonal(n, scale).values);
            backend
                .factor(&symbolic, [scale, 0.0, 0.0])
                .expect("factor");
            assert!(backend.is_factored([scale, 0.0, 0.0], a.pattern_id));
            let mut x = b.clone();
            backend.solve_in_place(&mut x).expect("solve");
            for (xi, ei) in x.iter().zip(&exact) {
                assert!(
                    (xi - ei / scale).abs() <= 1e-12 * n as f64,
                    "{xi} against {}",
                    ei / scale
                );
            }
        }
        let stats = backend.solver.stats();
        assert_eq!(stats.symbolic_analyses, 1);
        assert_eq!(stats.numeric_factorizations, 2);
        // A matrix of another pattern is refused by the analysis of this one.
        let other = tridiagonal(n, 1.0);
        assert!(backend.symbolic_of(other.pattern_id).is_none());
    }
}

//! The driver's linear backend ([`LinearBackend`]): the linear solver of the run in one of
//! three modes ([`Mode`]: the direct solver of the whole tangent, or the partitioned or
//! low-rank solver when the variable elements are kept off the pattern), the effective
//! matrix handed to it and the cache of its factor.
//!
//! A factorization is two steps in every mode, as in faer's symbolic/numeric split:
//! [`LinearBackend::analyse`] takes a sparsity pattern and returns its [`Symbolic`]
//! analysis, made once per pattern, and [`LinearBackend::factor`] factors the values filled
//! into [`LinearBackend::values_mut`] (and, off the pattern, the variable elements' triplets
//! of [`LinearBackend::triplets_mut`]) on that analysis. What the analysis is, by mode:
//!
//! - **direct**: the fill-reducing ordering and the symbolic factor of the sparse solver
//!   (nothing for the dense one), and the effective matrix allocated on the pattern;
//! - **partitioned**: the split of the equations into blocks and the top set, each block's
//!   boundary and the groups of the top chain ([`Partitioned::prepare`]). Each block's own
//!   ordering is made with its factor, once per set of coefficients: the block solves from a
//!   compact copy of its factor and releases faer's symbolic factor to save its memory
//!   ([`crate::linear::SparseCholesky::with_compact_solve`]); the top system's pattern
//!   follows the promoted equations and is analysed when they change
//!   ([`crate::partition::PartitionStats::top_symbolic_analyses`]);
//! - **low-rank**: the ordering and symbolic factor of the constant part's sparse solver
//!   ([`LowRank::analyse`]).
//!
//! The driver analyses again only when the assembler's pattern changes (a new split across
//! ranks, a rebuilt model). A second factorization on the same pattern performs no
//! analysis.
//!
//! Where the memory comes from: the effective matrix is allocated on the pattern at its
//! analysis (in the direct mode) or at the first factorization (off the pattern, only the
//! columns a rank reads); the symbolic analyses and the factors are the solvers' own
//! ([`crate::linear`], [`crate::partition`], [`crate::lowrank`]): a symbolic factor lives
//! as long as its pattern, a numeric factor until the next factorization or
//! [`LinearBackend::release_factors`].

use crate::linear::{LinearSolver, SolverError, SolverStats};
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

/// The solver a [`LinearBackend`] factors with.
// One per driver, held for the whole run: the variants' sizes differ, but boxing the
// partitioned solver would only add an indirection to each of its calls.
#[allow(clippy::large_enum_variant)]
pub enum Mode {
    /// The whole tangent on the assembler's pattern: dense or sparse by size
    /// ([`crate::driver::direct_solver`]).
    Direct(Box<dyn LinearSolver>),
    /// The partitioned solver ([`crate::partition`]): the constant part condensed in
    /// blocks, the variable elements on the top system.
    Partitioned(Partitioned),
    /// The low-rank solver ([`crate::lowrank`]): the constant part factored, the variable
    /// elements by a bordered solve.
    LowRank(LowRank),
}

impl Mode {
    /// The mode's name, as the model's `solver` key spells it.
    pub fn name(&self) -> &'static str {
        match self {
            Mode::Direct(_) => "direct",
            Mode::Partitioned(_) => "partitioned",
            Mode::LowRank(_) => "low-rank",
        }
    }
}

/// The linear solver of a run, its effective matrix and its factor cache (module
/// documentation).
pub struct LinearBackend {
    /// The solver.
    mode: Mode,
    /// The effective matrix last handed to the solver: the whole tangent in the direct
    /// mode, the constant part `A` off the pattern.
    pub(crate) k_eff: CscMatrix,
    /// The coefficients' [`railfem_framework::Coefficients::key`] and the pattern id the
    /// current factor belongs to, when it is still valid (for a one-stage integrator the key
    /// is a function of `dt` alone; a composite one's stages of the same length may
    /// differ).
    factored: Option<([f64; 3], u64)>,
    /// Off the pattern: the key of the values `k_eff` holds the constant part for (`NaN`s
    /// when the constant part changes between steps, which refactors it every time).
    a_key: Option<[f64; 3]>,
    /// Variable elements' effective triplets (partitioned and low-rank modes).
    pub(crate) triplets: Vec<(usize, usize, f64)>,
    /// Equations every factorization keeps among the variable ones (zero triplets on their
    /// diagonals): the condensed Newton's, which the top system must hold all step.
    on_top: Vec<usize>,
    /// The last analysis.
    symbolic: Option<Symbolic>,
    /// Low-rank mode: whether the constant part is expected symmetric (its solver is then
    /// sparse Cholesky, else LU), for its analysis ahead of any value.
    symmetric_hint: bool,
}

impl LinearBackend {
    /// A backend factoring with `mode`, on the effective matrix `k_eff` (empty off the
    /// pattern); `symmetric_hint` is whether the constant part is expected symmetric (the
    /// low-rank mode's analysis picks its solver by it).
    pub(crate) fn new(mode: Mode, k_eff: CscMatrix, symmetric_hint: bool) -> LinearBackend {
        LinearBackend {
            mode,
            k_eff,
            factored: None,
            a_key: None,
            triplets: Vec::new(),
            on_top: Vec::new(),
            symbolic: None,
            symmetric_hint,
        }
    }

    /// The solver the backend factors with.
    pub fn mode(&self) -> &Mode {
        &self.mode
    }

    /// Replaces the direct mode's solver; the next factorization analyses and factors
    /// anew. No effect in the partitioned and low-rank modes.
    pub fn set_solver(&mut self, solver: Box<dyn LinearSolver>) {
        if let Mode::Direct(s) = &mut self.mode {
            *s = solver;
            self.symbolic = None;
            self.factored = None;
        }
    }

    /// Puts the partitioned solver `p` in place of the backend's solver (new settings, or a
    /// split made across ranks); the next factorization analyses and factors anew.
    pub(crate) fn set_partitioned(&mut self, p: Partitioned) {
        self.mode = Mode::Partitioned(p);
        self.symbolic = None;
        self.factored = None;
    }

    /// The partitioned solver, in the partitioned mode.
    pub fn partitioned(&self) -> Option<&Partitioned> {
        match &self.mode {
            Mode::Partitioned(p) => Some(p),
            _ => None,
        }
    }

    /// The partitioned solver, in the partitioned mode (its condensation and the blocks
    /// held by the activity window are reached through it).
    pub fn partitioned_mut(&mut self) -> Option<&mut Partitioned> {
        match &mut self.mode {
            Mode::Partitioned(p) => Some(p),
            _ => None,
        }
    }

    /// The low-rank solver, in the low-rank mode.
    pub fn low_rank(&self) -> Option<&LowRank> {
        match &self.mode {
            Mode::LowRank(l) => Some(l),
            _ => None,
        }
    }

    /// Work counters of the direct mode's solver (all zero in the other modes, whose own
    /// counters are [`Partitioned::stats`] and [`LowRank::stats`]).
    pub fn solver_stats(&self) -> SolverStats {
        match &self.mode {
            Mode::Direct(s) => s.stats(),
            _ => SolverStats::default(),
        }
    }

    /// The symbolic analysis of `pattern` by the mode's solver (its values are not read,
    /// only their count checked; module documentation), and in the direct mode the
    /// effective matrix allocated on it when it had another pattern.
    pub fn analyse(&mut self, pattern: &CscMatrix) -> Result<Symbolic, SolverError> {
        self.symbolic = None;
        self.factored = None;
        match &mut self.mode {
            Mode::Direct(s) => {
                s.analyse(pattern)?;
                if self.k_eff.pattern_id != pattern.pattern_id {
                    self.k_eff = pattern.zeros_like();
                }
            }
            Mode::Partitioned(p) => p.prepare(pattern),
            Mode::LowRank(l) => l.analyse(pattern, self.symmetric_hint)?,
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

    /// After the analysis, in the partitioned mode across ranks: the columns of the
    /// constant part this rank's share of the blocks reads
    /// ([`Partitioned::columns_read`]); `None` (every column) otherwise.
    pub fn columns_read(&self) -> Option<Vec<bool>> {
        self.partitioned().and_then(Partitioned::columns_read)
    }

    /// The effective matrix on the pattern of `symbolic`, whose values the caller fills
    /// before [`LinearBackend::factor`]: the whole tangent in the direct mode.
    pub fn values_mut(&mut self, symbolic: &Symbolic) -> &mut CscMatrix {
        debug_assert_eq!(self.k_eff.pattern_id, symbolic.pattern_id);
        &mut self.k_eff
    }

    /// Off the pattern (partitioned and low-rank modes): whether the effective matrix
    /// must be formed for the constant part of the coefficients `key` (a new `key`, a new
    /// pattern, or factors released); it is formed once per set of coefficients.
    pub fn constant_values_stale(&self, symbolic: &Symbolic, key: [f64; 3]) -> bool {
        self.a_key != Some(key) || self.k_eff.pattern_id != symbolic.pattern_id
    }

    /// Off the pattern: the effective matrix, whose values the caller forms as the
    /// constant part for the coefficients `key`
    /// ([`railfem_framework::assembly::Assembler::effective`]).
    pub fn constant_values_mut(&mut self, key: [f64; 3]) -> &mut CscMatrix {
        self.a_key = Some(key);
        &mut self.k_eff
    }

    /// Off the pattern: the variable elements' effective triplets of the next
    /// factorization, filled in by the caller (cleared here).
    pub fn triplets_mut(&mut self) -> &mut Vec<(usize, usize, f64)> {
        self.triplets.clear();
        &mut self.triplets
    }

    /// Off the pattern: the equations every following factorization keeps among the
    /// variable ones ([`LinearBackend::add_kept_on_top`]); empty: none.
    pub fn keep_on_top(&mut self, equations: Vec<usize>) {
        self.on_top = equations;
    }

    /// The equations of [`LinearBackend::keep_on_top`].
    pub fn kept_on_top(&self) -> &[usize] {
        &self.on_top
    }

    /// Adds a zero triplet on the diagonal of each equation kept on top to the triplets
    /// filled in ([`LinearBackend::triplets_mut`]): the partitioned solver then keeps them
    /// on its top system.
    pub fn add_kept_on_top(&mut self) {
        self.triplets
            .extend(self.on_top.iter().map(|&e| (e, e, 0.0)));
    }

    /// The numeric factorization of the values filled in ([`LinearBackend::values_mut`],
    /// and off the pattern [`LinearBackend::constant_values_mut`] and
    /// [`LinearBackend::triplets_mut`]), on the analysis `symbolic`, which must be the
    /// backend's last; the factor is then valid for the coefficients `key`.
    pub fn factor(&mut self, symbolic: &Symbolic, key: [f64; 3]) -> Result<(), SolverError> {
        if self.symbolic != Some(*symbolic) {
            return Err(SolverError::Failed(format!(
                "the factorization is asked on an analysis of pattern {} that the backend no longer holds",
                symbolic.pattern_id
            )));
        }
        if self.k_eff.pattern_id != symbolic.pattern_id {
            return Err(SolverError::Failed(format!(
                "the effective matrix has pattern {} and the analysis is of pattern {}",
                self.k_eff.pattern_id, symbolic.pattern_id
            )));
        }
        self.factored = None;
        // Off the pattern the constant part's key: its factors are kept while it holds.
        let a_key = self.a_key.unwrap_or([f64::NAN; 3]);
        match &mut self.mode {
            Mode::Direct(s) => s.factor(&self.k_eff)?,
            Mode::Partitioned(p) => p.factor(&self.k_eff, a_key, &self.triplets)?,
            Mode::LowRank(l) => l.factor(&self.k_eff, a_key, &self.triplets)?,
        }
        self.factored = Some((key, symbolic.pattern_id));
        Ok(())
    }

    /// Whether the factor held is that of the coefficients `key` on the pattern
    /// `pattern_id`.
    pub fn is_factored(&self, key: [f64; 3], pattern_id: u64) -> bool {
        self.factored == Some((key, pattern_id))
    }

    /// Whether a factor is held, whatever its coefficients.
    pub fn has_factor(&self) -> bool {
        self.factored.is_some()
    }

    /// Forgets the factor: the next solve needs a new factorization.
    pub fn invalidate(&mut self) {
        self.factored = None;
    }

    /// Forgets the constant part's values and the factor (the constant matrices changed
    /// between steps, `crate::window::absorb`): the next factorization forms the
    /// constant part again. The partitioned mode's block factors are kept; the caller
    /// names the blocks to factor anew ([`Partitioned::constant_changed`]).
    pub fn forget_constant_values(&mut self) {
        self.a_key = None;
        self.factored = None;
    }

    /// Releases the partitioned mode's factors and the effective matrix they were made
    /// from, before another solver factors another matrix (the initial mass solve): two
    /// sets of block factors are then never held at once, and the next factorization
    /// factors every block anew (the split, the analysis, is kept). The direct and
    /// low-rank modes keep theirs.
    pub fn release_factors(&mut self) {
        if let Mode::Partitioned(p) = &mut self.mode {
            p.release_factors();
            self.k_eff = CscMatrix::from_columns(Vec::new());
            self.a_key = None;
            self.factored = None;
        }
    }

    /// Solves `A·x = b` in place with the factor held, by the solver of the run.
    pub fn solve_in_place(&mut self, b: &mut [f64]) -> Result<(), SolverError> {
        match &mut self.mode {
            Mode::Direct(s) => s.solve_in_place(b),
            Mode::Partitioned(p) => p.solve_in_place(b),
            Mode::LowRank(l) => l.solve_in_place(b),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linear::SparseCholesky;
    use crate::partition::PartitionOptions;

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

    /// [`tridiagonal`]`(n, s)` on the pattern (and pattern id) of `pattern`, its `T`.
    fn on_pattern(pattern: &CscMatrix, s: f64) -> CscMatrix {
        let mut a = pattern.clone();
        a.values = tridiagonal(pattern.n, s).values;
        a
    }

    /// `x*_i = i + 1` and `b = (s·T + k·e_w·e_wᵀ)·x*` for the matrix of [`tridiagonal`]
    /// plus a spring `k` at equation `w` (the variable part off the pattern).
    fn exact_and_load(n: usize, s: f64, spring: Option<(usize, f64)>) -> (Vec<f64>, Vec<f64>) {
        let exact: Vec<f64> = (0..n).map(|i| i as f64 + 1.0).collect();
        let mut b = vec![0.0; n];
        tridiagonal(n, s).mul_vec(&exact, &mut b);
        if let Some((w, k)) = spring {
            b[w] += k * exact[w];
        }
        (exact, b)
    }

    /// Solves with the backend's factor and checks `x*` to round-off: the condition
    /// number of `T` grows as `n²`, so `1e-10` relative to `|x*|_∞ = n` is far above it.
    fn check_solution(backend: &mut LinearBackend, b: &[f64], exact: &[f64]) {
        let mut x = b.to_vec();
        backend.solve_in_place(&mut x).expect("solve");
        let n = exact.len() as f64;
        for (xi, ei) in x.iter().zip(exact) {
            assert!((xi - ei).abs() <= 1e-10 * n, "{xi} against {ei}");
        }
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
            Mode::Direct(Box::new(SparseCholesky::new())),
            CscMatrix::from_columns(Vec::new()),
            true,
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
        let stats = backend.solver_stats();
        assert_eq!(stats.symbolic_analyses, 1);
        assert_eq!(stats.numeric_factorizations, 2);
        // A matrix of another pattern is refused by the analysis of this one.
        let other = tridiagonal(n, 1.0);
        assert!(backend.symbolic_of(other.pattern_id).is_none());
    }

    /// The partitioned mode's analysis is the split, made once per pattern. A chain of
    /// 400 equations with blocks of 100 splits (breadth-first levels of one equation each,
    /// from one end) into 4 blocks: a block closes at 100 equations with the next level as
    /// separator while more than `100/2 + 1` remain — after 100, 201 and 302 equations —
    /// and the last 97 form the fourth; 3 separators. Three factorizations on that one
    /// analysis: two sets of constant values (`T`, `3·T`: every block factored each time,
    /// 4 + 4), then the second set again with the spring moved to another block (no block
    /// factorization); the spring's equation is promoted to the top once per factorization
    /// (3), and the top system factored each time (3). Each solves `(s·T + k·e_w e_wᵀ)·x = b` for the exact `x*`.
    #[test]
    fn partitioned_mode_splits_once_per_pattern() {
        let n = 400;
        let options = PartitionOptions {
            block_size: 100,
            threads: 1,
            top_group_blocks: 0,
            ..Default::default()
        };
        let mut backend = LinearBackend::new(
            Mode::Partitioned(Partitioned::new(true, options)),
            CscMatrix::from_columns(Vec::new()),
            true,
        );
        let pattern = tridiagonal(n, 1.0);
        let symbolic = backend.analyse(&pattern).expect("analysis");
        let stats = backend.partitioned().expect("partitioned").stats();
        assert_eq!((stats.analyses, stats.blocks), (1, 4));
        assert_eq!(
            (stats.interior_equations, stats.base_top_equations),
            (397, 3)
        );
        for (scale, wheel) in [(1.0, 50), (3.0, 50), (3.0, 150)] {
            let key = [scale, 0.0, 0.0];
            if backend.constant_values_stale(&symbolic, key) {
                *backend.constant_values_mut(key) = on_pattern(&pattern, scale);
            }
            backend.triplets_mut().push((wheel, wheel, 5.0));
            backend.factor(&symbolic, key).expect("factor");
            let (exact, b) = exact_and_load(n, scale, Some((wheel, 5.0)));
            check_solution(&mut backend, &b, &exact);
        }
        let stats = backend.partitioned().expect("partitioned").stats();
        assert_eq!(stats.analyses, 1);
        assert_eq!(stats.block_factorizations, 8);
        assert_eq!(stats.promotions, 3);
        assert_eq!(stats.top_factorizations, 3);
        // Analysing the same pattern again splits nothing.
        backend.analyse(&pattern).expect("analysis");
        let stats = backend.partitioned().expect("partitioned").stats();
        assert_eq!(stats.analyses, 1);
    }

    /// The low-rank mode's analysis is that of its constant part's sparse solver: one,
    /// then two factorizations (`T` and `3·T` with a spring off the pattern) perform
    /// none. With a wrong guess of symmetry the first factorization analyses again with
    /// the solver the values call for (Cholesky for this symmetric `T`), and only then.
    #[test]
    fn low_rank_mode_analyses_its_constant_part_once() {
        let n = 60;
        for (hint, analyses) in [(true, 1), (false, 1)] {
            let mut backend = LinearBackend::new(
                Mode::LowRank(LowRank::new()),
                CscMatrix::from_columns(Vec::new()),
                hint,
            );
            let pattern = tridiagonal(n, 1.0);
            let symbolic = backend.analyse(&pattern).expect("analysis");
            let base = |b: &LinearBackend| b.low_rank().expect("low-rank").base_stats();
            assert_eq!(base(&backend).symbolic_analyses, 1);
            for scale in [1.0, 3.0] {
                let key = [scale, 0.0, 0.0];
                assert!(backend.constant_values_stale(&symbolic, key));
                *backend.constant_values_mut(key) = on_pattern(&pattern, scale);
                backend.triplets_mut().push((7, 7, 5.0));
                backend.factor(&symbolic, key).expect("factor");
                let (exact, b) = exact_and_load(n, scale, Some((7, 5.0)));
                check_solution(&mut backend, &b, &exact);
            }
            // The counters are the Cholesky solver's (a wrong guess replaced the LU one).
            let st = base(&backend);
            assert_eq!(
                (st.symbolic_analyses, st.numeric_factorizations),
                (analyses, 2),
                "hint {hint}"
            );
            assert_eq!(
                backend
                    .low_rank()
                    .expect("low-rank")
                    .stats()
                    .base_factorizations,
                2
            );
        }
    }
}

//! Sparse direct linear solvers for the assembled [`CscMatrix`] systems, behind the
//! [`LinearSolver`] trait.
//!
//! Two implementations wrap faer's low-level sparse API:
//!
//! * [`SparseCholesky`] — `A = L·Lᵀ` (or `L·D·Lᵀ`) for symmetric matrices, reading only the
//!   lower triangle. The fill-reducing ordering (AMD) and the symbolic factorization are
//!   computed once per sparsity pattern ([`CscMatrix::pattern_id`]). At the same time the
//!   pattern of the PERMUTED triangle `P·A·Pᵀ` that faer's numeric kernel reads is built,
//!   with a gather list into the caller's `values`; each refactorization is then one gather
//!   pass plus faer's raw simplicial/supernodal numeric kernel, into a kept factor buffer
//!   with kept scratch memory — no heap allocation, and no per-call permutation (faer's
//!   `SymbolicCholesky::factorize_numeric_llt` re-permutes the matrix on every call).
//!   A factor made once and solved with many times (the partitioned solver's blocks) can
//!   instead be kept as its non-zeros alone and solved with the same bits
//!   ([`SparseCholesky::with_compact_solve`], [`crate::compact_factor`]).
//! * [`SparseLu`] — `P·A·Q = L·U` with partial row pivoting for unsymmetric matrices (for
//!   example a tangent with friction). The column ordering (COLAMD) and the symbolic
//!   analysis are kept per pattern; faer's numeric LU storage is re-used (it grows but never
//!   shrinks), as is the scratch memory.
//!
//! Errors are typed ([`SolverError`]): a zero or non-positive pivot is reported as
//! [`SolverError::Singular`] with the equation in the caller's ORIGINAL numbering (faer's
//! pivot position is mapped back through the fill-reducing permutation). Non-finite input
//! values, malformed patterns and size mismatches are [`SolverError::Failed`].
//!
//! Time integration, Newton iterations and eigen-solvers live elsewhere (see `modal`); this
//! module only factors and solves.
//!
//! # faer API notes (0.24)
//!
//! * The simplicial Cholesky reports a failed pivot as a 1-based position
//!   (`NonPositivePivot { index: k + 1 }`) while the supernodal one reports it 0-based; both
//!   are in the permuted numbering. [`SparseCholesky`] corrects for both (tested).
//! * faer's numeric LU does not report numerically zero pivots (only structurally singular
//!   matrices); [`SparseLu`] therefore checks for empty rows/columns before factoring and
//!   checks the solution for non-finite values after solving.

use crate::compact_factor::CompactFactor;
use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::linalg::cholesky::ldlt::factor::{LdltError, LdltRegularization};
use faer::linalg::cholesky::llt::factor::{LltError, LltRegularization};
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, simplicial, supernodal, CholeskySymbolicParams, LdltRef, LltRef,
    SymbolicCholesky, SymbolicCholeskyRaw, SymmetricOrdering,
};
use faer::sparse::linalg::lu::{
    factorize_symbolic_lu, LuRef, LuSymbolicParams, NumericLu, SymbolicLu,
};
use faer::sparse::linalg::{LuError, SupernodalThreshold};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, MatMut, Par, Side};
use railfem_framework::sparse::CscMatrix;

/// Failure of a factorization or solve.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SolverError {
    /// A pivot was zero (or, for `L·Lᵀ`, not positive): the matrix is singular (or not
    /// positive definite). `equation` is the 0-based equation (row/column) index in the
    /// caller's original numbering at which elimination broke down.
    #[error("matrix is singular or not positive definite at equation {equation}")]
    Singular {
        /// 0-based equation index in the original numbering of the matrix.
        equation: usize,
    },
    /// Any other failure: malformed input, non-finite values, size mismatch, solve
    /// before factor, out of memory.
    #[error("linear solver failed: {0}")]
    Failed(String),
}

/// Work counters of a solver, for tests and profiling.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct SolverStats {
    /// Number of symbolic analyses (ordering + symbolic factorization) performed.
    pub symbolic_analyses: usize,
    /// Number of successful numeric factorizations.
    pub numeric_factorizations: usize,
    /// Number of right-hand sides solved.
    pub solves: usize,
    /// Number of stored factor entries of the last factorization (`L` for Cholesky,
    /// 0 for LU whose factor sizes faer does not expose).
    pub factor_nnz: usize,
}

/// A sparse direct solver: factor once, solve many times.
pub trait LinearSolver: Send {
    /// Factor `a`; symbolic analysis is redone only when `a.pattern_id` differs from the last
    /// one.
    fn factor(&mut self, a: &CscMatrix) -> Result<(), SolverError>;

    /// The symbolic analysis (fill-reducing ordering, symbolic factor) of `a`'s pattern,
    /// unless the solver holds that of the same pattern already; [`LinearSolver::factor`]
    /// of a matrix of this pattern then factors numerically only. The values are not read.
    /// The default does nothing (a dense solver has no symbolic step).
    fn analyse(&mut self, a: &CscMatrix) -> Result<(), SolverError> {
        let _ = a;
        Ok(())
    }

    /// Solve `A x = b` in place (`b` becomes `x`) with the last factorization.
    fn solve_in_place(&mut self, b: &mut [f64]) -> Result<(), SolverError>;

    /// Work counters: symbolic analyses, numeric factorizations, solves, last factor size.
    fn stats(&self) -> SolverStats;

    /// Solve `A X = B` in place for `ncols` right-hand sides stored column-major in `b`
    /// (`b.len() == n·ncols`). The default loops over [`LinearSolver::solve_in_place`].
    fn solve_columns_in_place(&mut self, b: &mut [f64], ncols: usize) -> Result<(), SolverError> {
        if ncols == 0 {
            return Ok(());
        }
        if b.len() % ncols != 0 {
            return Err(SolverError::Failed(format!(
                "right-hand side length {} is not a multiple of {ncols} columns",
                b.len()
            )));
        }
        let n = b.len() / ncols;
        for col in b.chunks_mut(n) {
            self.solve_in_place(col)?;
        }
        Ok(())
    }
}

/// A boxed solver suited to the matrix: [`SparseCholesky`] (`L·Lᵀ`) if `symmetric`
/// (positive definite is then expected), [`SparseLu`] otherwise.
pub fn solver_for(symmetric: bool) -> Box<dyn LinearSolver> {
    if symmetric {
        Box::new(SparseCholesky::new())
    } else {
        Box::new(SparseLu::new())
    }
}

/// Which symmetric factorization [`SparseCholesky`] computes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum CholeskyKind {
    /// `A = L·Lᵀ`; requires a positive definite matrix (every pivot > 0).
    #[default]
    Llt,
    /// `A = L·D·Lᵀ` without pivoting; accepts some indefinite matrices (for example
    /// quasi-definite saddle points) but fails on a zero pivot.
    Ldlt,
}

/// How faer organizes the numeric factorization.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Layout {
    /// Let faer choose from the estimated flop count per factor entry.
    #[default]
    Auto,
    /// Always column by column (good for very sparse factors).
    Simplicial,
    /// Always in dense supernode blocks (good for FE matrices with many DOF per node).
    Supernodal,
}

impl Layout {
    fn threshold(self) -> SupernodalThreshold {
        match self {
            Layout::Auto => SupernodalThreshold::AUTO,
            Layout::Simplicial => SupernodalThreshold::FORCE_SIMPLICIAL,
            Layout::Supernodal => SupernodalThreshold::FORCE_SUPERNODAL,
        }
    }
}

fn par_for(threads: usize) -> Par {
    if threads <= 1 {
        Par::Seq
    } else {
        Par::rayon(threads)
    }
}

/// Checks the structural invariants of `a` that faer relies on (square, monotone column
/// pointers, in-range strictly increasing row indices per column, values length).
fn validate_pattern(a: &CscMatrix) -> Result<(), SolverError> {
    let n = a.n;
    if a.col_ptr.len() != n + 1 || a.col_ptr[0] != 0 {
        return Err(SolverError::Failed(format!(
            "column pointer array has length {} (expected {}) or does not start at 0",
            a.col_ptr.len(),
            n + 1
        )));
    }
    if a.col_ptr[n] != a.row_idx.len() || a.values.len() != a.row_idx.len() {
        return Err(SolverError::Failed(format!(
            "inconsistent lengths: col_ptr[n] = {}, row_idx {}, values {}",
            a.col_ptr[n],
            a.row_idx.len(),
            a.values.len()
        )));
    }
    for j in 0..n {
        let (s, e) = (a.col_ptr[j], a.col_ptr[j + 1]);
        if s > e || e > a.row_idx.len() {
            return Err(SolverError::Failed(format!(
                "column pointers decrease at column {j}"
            )));
        }
        let rows = &a.row_idx[s..e];
        if rows.iter().any(|&i| i >= n) || rows.windows(2).any(|w| w[0] >= w[1]) {
            return Err(SolverError::Failed(format!(
                "row indices of column {j} are out of range or not strictly increasing"
            )));
        }
    }
    Ok(())
}

/// Cheap per-factor consistency check against the cached pattern.
fn same_pattern(a: &CscMatrix, id: u64, n: usize, nnz: usize) -> bool {
    a.pattern_id == id && a.n == n && a.row_idx.len() == nnz && a.col_ptr.len() == n + 1
}

fn non_finite_error(a: &CscMatrix, p: usize) -> SolverError {
    let j = a.col_ptr.partition_point(|&c| c <= p) - 1;
    SolverError::Failed(format!(
        "non-finite matrix value {} at ({}, {j})",
        a.values[p], a.row_idx[p]
    ))
}

/// Grows `buf` (allocated for the layout `cap`) so that it can hold `req`; no allocation
/// when it already can.
fn ensure_mem(buf: &mut MemBuffer, cap: &mut StackReq, req: StackReq) -> Result<(), SolverError> {
    if req.size_bytes() <= cap.size_bytes() && req.align_bytes() <= cap.align_bytes() {
        return Ok(());
    }
    let grown = cap.or(req);
    *buf = MemBuffer::try_new(grown)
        .map_err(|_| SolverError::Failed("out of memory for solver scratch".into()))?;
    *cap = grown;
    Ok(())
}

/// Per-pattern cache of the lower triangle of a symmetric [`CscMatrix`], either as is (for
/// the symbolic analysis) or already permuted by the fill-reducing ordering into the
/// triangle faer's numeric kernel reads (for every numeric factorization).
struct TrianglePattern {
    pattern_id: u64,
    n: usize,
    full_nnz: usize,
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    /// Position in the full matrix's `values` of each stored entry.
    gather: Vec<usize>,
    /// Values, refreshed every factorization through `gather`.
    values: Vec<f64>,
}

impl TrianglePattern {
    /// The entries `(i, j)`, `i >= j`, of `a`, renumbered `(inv[i], inv[j])` and stored in
    /// the `upper` or lower triangle, rows sorted in each column.
    ///
    /// Two counting passes, by row and then (stably) by column, sort the entries by
    /// `(column, row)` in `O(nnz + n)`; each `(column, row)` occurs once (`a` stores an
    /// entry once and the renumbering is a permutation), so the order is the one a
    /// comparison sort gives.
    fn build(a: &CscMatrix, inv: Option<&[usize]>, upper: bool) -> TrianglePattern {
        let n = a.n;
        if inv.is_none() && !upper {
            return TrianglePattern::lower(a);
        }
        let map = |i: usize| inv.map_or(i, |inv| inv[i]);
        // (column, row, source position); the lower triangle holds at most half the
        // off-diagonal entries and the diagonal.
        let mut entries = Vec::with_capacity(a.row_idx.len() / 2 + n);
        for j in 0..n {
            for p in a.col_ptr[j]..a.col_ptr[j + 1] {
                let i = a.row_idx[p];
                if i >= j {
                    let (r, c) = (map(i), map(j));
                    let (r, c) = if (r < c) == upper { (r, c) } else { (c, r) };
                    entries.push((c, r, p));
                }
            }
        }
        let starts = |key: &dyn Fn(&(usize, usize, usize)) -> usize| {
            let mut at = vec![0usize; n + 1];
            for e in &entries {
                at[key(e) + 1] += 1;
            }
            for j in 0..n {
                at[j + 1] += at[j];
            }
            at
        };
        let mut next = starts(&|e| e.1);
        let mut by_row = vec![(0, 0, 0); entries.len()];
        for &e in &entries {
            by_row[next[e.1]] = e;
            next[e.1] += 1;
        }
        let col_ptr = starts(&|e| e.0);
        let mut next = col_ptr.clone();
        let (mut row_idx, mut gather) = (vec![0; entries.len()], vec![0; entries.len()]);
        for &(c, r, p) in &by_row {
            row_idx[next[c]] = r;
            gather[next[c]] = p;
            next[c] += 1;
        }
        TrianglePattern {
            pattern_id: a.pattern_id,
            n,
            full_nnz: a.row_idx.len(),
            col_ptr,
            row_idx,
            gather,
            values: vec![0.0; entries.len()],
        }
    }

    /// [`TrianglePattern::build`] of the lower triangle as is: each column's rows are
    /// increasing already (a validated pattern), so its entries `i >= j` are taken in
    /// place, with no sort.
    fn lower(a: &CscMatrix) -> TrianglePattern {
        let n = a.n;
        let mut col_ptr = Vec::with_capacity(n + 1);
        col_ptr.push(0);
        let mut gather = Vec::new();
        for j in 0..n {
            let (lo, hi) = (a.col_ptr[j], a.col_ptr[j + 1]);
            let first = lo + a.row_idx[lo..hi].partition_point(|&i| i < j);
            gather.extend(first..hi);
            col_ptr.push(gather.len());
        }
        let row_idx = gather.iter().map(|&p| a.row_idx[p]).collect();
        TrianglePattern {
            pattern_id: a.pattern_id,
            n,
            full_nnz: a.row_idx.len(),
            col_ptr,
            row_idx,
            values: vec![0.0; gather.len()],
            gather,
        }
    }

    fn symbolic(&self) -> SymbolicSparseColMatRef<'_, usize> {
        SymbolicSparseColMatRef::new_checked(self.n, self.n, &self.col_ptr, None, &self.row_idx)
    }

    /// Refreshes `values` from `a` (same pattern).
    fn gather(&mut self, a: &CscMatrix) {
        for (v, &p) in self.values.iter_mut().zip(&self.gather) {
            *v = a.values[p];
        }
    }
}

/// Entries of the Cholesky factor of `a` (a symmetric pattern) with the fill-reducing
/// ordering the solver uses, from the symbolic analysis alone (no numbers): what the
/// direct solver's factor will store.
pub fn cholesky_factor_entries(a: &CscMatrix) -> Result<usize, SolverError> {
    validate_pattern(a)?;
    let lower = TrianglePattern::build(a, None, false);
    let symbolic = factorize_symbolic_cholesky(
        lower.symbolic(),
        Side::Lower,
        SymmetricOrdering::Amd,
        CholeskySymbolicParams::default(),
    )
    .map_err(|e| SolverError::Failed(format!("symbolic Cholesky: {e:?}")))?;
    Ok(symbolic.len_val())
}

/// Sparse symmetric direct solver (`L·Lᵀ` or `L·D·Lᵀ`) with symbolic and buffer re-use.
///
/// Only the lower triangle of the matrix passed to [`LinearSolver::factor`] is read; the
/// matrix is assumed symmetric.
pub struct SparseCholesky {
    kind: CholeskyKind,
    layout: Layout,
    par: Par,
    pattern: Option<TrianglePattern>,
    symbolic: Option<SymbolicCholesky<usize>>,
    l_values: Vec<f64>,
    factor_mem: MemBuffer,
    factor_mem_cap: StackReq,
    solve_mem: MemBuffer,
    solve_mem_cap: StackReq,
    factored: bool,
    stats: SolverStats,
    /// Solve from a copy of `L` without its exact zeros ([`CompactFactor`]) where the
    /// factor is simplicial `L·Lᵀ`; the values of `L`, the symbolic factor, the permuted
    /// pattern and the scratch are then released ([`SparseCholesky::with_compact_solve`]).
    compact_solve: bool,
    compact: Option<CompactFactor>,
}

impl Default for SparseCholesky {
    fn default() -> Self {
        Self::new()
    }
}

impl std::fmt::Debug for SparseCholesky {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SparseCholesky")
            .field("kind", &self.kind)
            .field("layout", &self.layout)
            .field("factored", &self.factored)
            .field("stats", &self.stats)
            .finish()
    }
}

impl SparseCholesky {
    /// An `L·Lᵀ` solver, automatic simplicial/supernodal choice, single-threaded.
    pub fn new() -> SparseCholesky {
        SparseCholesky {
            kind: CholeskyKind::Llt,
            layout: Layout::Auto,
            par: Par::Seq,
            pattern: None,
            symbolic: None,
            l_values: Vec::new(),
            factor_mem: MemBuffer::new(StackReq::empty()),
            factor_mem_cap: StackReq::empty(),
            solve_mem: MemBuffer::new(StackReq::empty()),
            solve_mem_cap: StackReq::empty(),
            factored: false,
            stats: SolverStats::default(),
            compact_solve: false,
            compact: None,
        }
    }

    /// Solves from a copy of the factor without its exact zeros, with 32-bit indices
    /// ([`crate::compact_factor`]): the same solutions to the bit (a zero may differ in
    /// sign) from fewer bytes, for a factor that is made once and solved with many times
    /// (the partitioned solver's blocks). Applies to the simplicial `L·Lᵀ` layout; the
    /// others keep faer's solve. Once the copy is made, everything else is released — the
    /// values of `L`, faer's symbolic factor (the row indices of `L`), the permuted pattern
    /// and the factorization's scratch — so the solver holds the copy alone; a later
    /// [`LinearSolver::factor`] analyses the pattern again.
    pub fn with_compact_solve(mut self, on: bool) -> SparseCholesky {
        self.compact_solve = on;
        self.compact = None;
        self
    }

    /// With [`SparseCholesky::with_compact_solve`] after a factorization it applied to: the
    /// off-diagonal non-zeros kept and the values faer stores for `L`.
    pub fn compact_counts(&self) -> Option<(usize, usize)> {
        let c = self.compact.as_ref()?;
        Some((c.nonzeros(), self.stats.factor_nnz))
    }

    /// The compact copy of the factor ([`SparseCholesky::with_compact_solve`]), after a
    /// factorization that made one.
    pub fn compact_mut(&mut self) -> Option<&mut CompactFactor> {
        self.compact.as_mut().filter(|_| self.factored)
    }

    /// The columns `A⁻¹·e_l` of the equations `locals`, column-major (`n` rows each, in
    /// the order of `locals`): with the compact copy, each forward pass starts at its unit
    /// entry's position in the elimination order, the same bits as solving the unit
    /// columns ([`crate::compact_factor::CompactFactor::solve_columns_from`]); without it,
    /// the unit columns solved.
    pub fn solve_unit_columns(&mut self, locals: &[usize]) -> Result<Vec<f64>, SolverError> {
        let n = match (&self.compact, &self.symbolic) {
            (Some(c), _) => c.n(),
            (None, Some(symbolic)) => symbolic.nrows(),
            (None, None) => {
                return Err(SolverError::Failed(
                    "solve called without a valid factorization".into(),
                ))
            }
        };
        let m = locals.len();
        if let Some(&l) = locals.iter().find(|&&l| l >= n) {
            return Err(SolverError::Failed(format!(
                "unit column {l} of {n} equations"
            )));
        }
        let mut out = vec![0.0; n * m];
        match (self.factored, self.compact.as_mut()) {
            (true, Some(c)) if m > 0 => {
                // In order of position, so that a group of columns starts late together.
                let mut order: Vec<usize> = (0..m).collect();
                order.sort_by_key(|&k| c.position(locals[k]));
                let from: Vec<usize> = order.iter().map(|&k| c.position(locals[k])).collect();
                let mut b = vec![0.0; n * m];
                for (q, &k) in order.iter().enumerate() {
                    b[q * n + locals[k]] = 1.0;
                }
                c.solve_columns_from(&mut b, m, &from);
                self.stats.solves += m;
                for (q, &k) in order.iter().enumerate() {
                    out[k * n..(k + 1) * n].copy_from_slice(&b[q * n..(q + 1) * n]);
                }
            }
            _ => {
                for (k, &l) in locals.iter().enumerate() {
                    out[k * n + l] = 1.0;
                }
                self.solve_columns_in_place(&mut out, m)?;
            }
        }
        Ok(out)
    }

    /// Same solver computing `L·D·Lᵀ` (no pivoting) instead of `L·Lᵀ`.
    pub fn ldlt() -> SparseCholesky {
        SparseCholesky::new().with_kind(CholeskyKind::Ldlt)
    }

    /// Selects `L·Lᵀ` or `L·D·Lᵀ`; forces a new symbolic analysis at the next factor.
    pub fn with_kind(mut self, kind: CholeskyKind) -> SparseCholesky {
        self.kind = kind;
        self.reset();
        self
    }

    /// Forces the simplicial or supernodal layout; forces a new symbolic analysis.
    pub fn with_layout(mut self, layout: Layout) -> SparseCholesky {
        self.layout = layout;
        self.reset();
        self
    }

    /// Number of threads for the numeric factorization and solves (rayon; `0` or `1` means
    /// sequential).
    pub fn with_threads(mut self, threads: usize) -> SparseCholesky {
        self.par = par_for(threads);
        self.factor_mem_cap = StackReq::empty(); // scratch size depends on parallelism
        self.solve_mem_cap = StackReq::empty();
        self
    }

    /// Bytes of the factor, as allocated (for memory reports): the values of `L`, the
    /// permuted pattern of the matrix with its gather list and values, and the scratch
    /// buffers. faer's symbolic structure (the row indices of `L`) is not counted: an
    /// undercount of at most `8·nnz(L)` for a simplicial factor, far less for a supernodal one.
    pub fn heap_bytes(&self) -> usize {
        let pattern = self.pattern.as_ref().map_or(0, |p| {
            8 * (p.col_ptr.capacity()
                + p.row_idx.capacity()
                + p.gather.capacity()
                + p.values.capacity())
        });
        pattern
            + self.compact.as_ref().map_or(0, CompactFactor::heap_bytes)
            + 8 * self.l_values.capacity()
            + self.factor_mem_cap.size_bytes()
            + self.solve_mem_cap.size_bytes()
    }

    /// Whether the current symbolic factorization is supernodal (`None` before the first
    /// factorization).
    pub fn is_supernodal(&self) -> Option<bool> {
        self.symbolic
            .as_ref()
            .map(|s| matches!(s.raw(), SymbolicCholeskyRaw::Supernodal(_)))
    }

    fn reset(&mut self) {
        self.pattern = None;
        self.symbolic = None;
        self.factored = false;
        self.compact = None;
    }

    fn analyse_pattern(&mut self, a: &CscMatrix) -> Result<(), SolverError> {
        self.reset();
        validate_pattern(a)?;
        let lower = TrianglePattern::build(a, None, false);
        let params = CholeskySymbolicParams {
            supernodal_flop_ratio_threshold: self.layout.threshold(),
            ..Default::default()
        };
        let symbolic = factorize_symbolic_cholesky(
            lower.symbolic(),
            Side::Lower,
            SymmetricOrdering::Amd,
            params,
        )
        .map_err(|e| SolverError::Failed(format!("symbolic Cholesky: {e:?}")))?;
        // The numeric kernels read P·A·Pᵀ in the upper (simplicial) or lower (supernodal)
        // triangle. faer's `SymbolicCholesky::factorize_numeric_*` would permute A into
        // scratch on every call; the permuted pattern and its gather list are built here
        // once instead, and the raw kernels are called directly.
        let (upper, req) = match (symbolic.raw(), self.kind) {
            (SymbolicCholeskyRaw::Simplicial(_), CholeskyKind::Llt) => (
                true,
                simplicial::factorize_simplicial_numeric_llt_scratch::<usize, f64>(a.n),
            ),
            (SymbolicCholeskyRaw::Simplicial(_), CholeskyKind::Ldlt) => (
                true,
                simplicial::factorize_simplicial_numeric_ldlt_scratch::<usize, f64>(a.n),
            ),
            (SymbolicCholeskyRaw::Supernodal(sn), CholeskyKind::Llt) => (
                false,
                supernodal::factorize_supernodal_numeric_llt_scratch::<usize, f64>(
                    sn,
                    self.par,
                    Default::default(),
                ),
            ),
            (SymbolicCholeskyRaw::Supernodal(sn), CholeskyKind::Ldlt) => (
                false,
                supernodal::factorize_supernodal_numeric_ldlt_scratch::<usize, f64>(
                    sn,
                    self.par,
                    Default::default(),
                ),
            ),
        };
        let permuted = TrianglePattern::build(a, symbolic.perm().map(|p| p.arrays().1), upper);
        self.factor_mem_cap = StackReq::empty();
        ensure_mem(&mut self.factor_mem, &mut self.factor_mem_cap, req)?;
        self.l_values.clear();
        self.l_values.resize(symbolic.len_val(), 0.0);
        self.pattern = Some(permuted);
        self.symbolic = Some(symbolic);
        self.stats.symbolic_analyses += 1;
        Ok(())
    }

    /// Maps faer's failed-pivot position (permuted numbering) to the original equation.
    fn failed_equation(symbolic: &SymbolicCholesky<usize>, index: usize) -> usize {
        let n = symbolic.nrows();
        // simplicial reports k + 1, supernodal reports k (see module doc)
        let k = match symbolic.raw() {
            SymbolicCholeskyRaw::Simplicial(_) => index.saturating_sub(1),
            SymbolicCholeskyRaw::Supernodal(_) => index,
        }
        .min(n.saturating_sub(1));
        match symbolic.perm() {
            Some(perm) => perm.arrays().0[k],
            None => k,
        }
    }
}

impl LinearSolver for SparseCholesky {
    fn analyse(&mut self, a: &CscMatrix) -> Result<(), SolverError> {
        if matches!(&self.pattern, Some(p) if same_pattern(a, p.pattern_id, p.n, p.full_nnz)) {
            return Ok(());
        }
        self.analyse_pattern(a)
    }

    fn factor(&mut self, a: &CscMatrix) -> Result<(), SolverError> {
        self.factored = false;
        self.compact = None;
        let reuse = matches!(&self.pattern, Some(p) if same_pattern(a, p.pattern_id, p.n, p.full_nnz))
            && a.values.len() == a.row_idx.len();
        if !reuse {
            self.analyse_pattern(a)?;
        }
        let (Some(permuted), Some(symbolic)) = (self.pattern.as_mut(), self.symbolic.as_ref())
        else {
            return Err(SolverError::Failed("no symbolic factorization".into()));
        };
        // the whole matrix is checked (a NaN in the unread upper triangle still means a
        // broken assembly), then P·A·Pᵀ is gathered
        if let Some(p) = a.values.iter().position(|x| !x.is_finite()) {
            return Err(non_finite_error(a, p));
        }
        permuted.gather(a);
        // Released after the last compact copy was made: faer writes every value of L.
        self.l_values.resize(symbolic.len_val(), 0.0);
        let mat = SparseColMatRef::new(permuted.symbolic(), &permuted.values);
        let stack = MemStack::new(&mut self.factor_mem);
        let l = &mut self.l_values[..];
        let result = match (symbolic.raw(), self.kind) {
            (SymbolicCholeskyRaw::Simplicial(sym), CholeskyKind::Llt) => {
                simplicial::factorize_simplicial_numeric_llt::<usize, f64>(
                    l,
                    mat,
                    LltRegularization::default(),
                    sym,
                    stack,
                )
                .map(|_| ())
                .map_err(|LltError::NonPositivePivot { index }| index)
            }
            (SymbolicCholeskyRaw::Simplicial(sym), CholeskyKind::Ldlt) => {
                simplicial::factorize_simplicial_numeric_ldlt::<usize, f64>(
                    l,
                    mat,
                    LdltRegularization::default(),
                    sym,
                    stack,
                )
                .map(|_| ())
                .map_err(|LdltError::ZeroPivot { index }| index)
            }
            (SymbolicCholeskyRaw::Supernodal(sym), CholeskyKind::Llt) => {
                supernodal::factorize_supernodal_numeric_llt::<usize, f64>(
                    l,
                    mat,
                    LltRegularization::default(),
                    sym,
                    self.par,
                    stack,
                    Default::default(),
                )
                .map(|_| ())
                .map_err(|LltError::NonPositivePivot { index }| index)
            }
            (SymbolicCholeskyRaw::Supernodal(sym), CholeskyKind::Ldlt) => {
                supernodal::factorize_supernodal_numeric_ldlt::<usize, f64>(
                    l,
                    mat,
                    LdltRegularization::default(),
                    sym,
                    self.par,
                    stack,
                    Default::default(),
                )
                .map(|_| ())
                .map_err(|LdltError::ZeroPivot { index }| index)
            }
        };
        if let Err(index) = result {
            return Err(SolverError::Singular {
                equation: Self::failed_equation(symbolic, index),
            });
        }
        self.factored = true;
        self.stats.numeric_factorizations += 1;
        self.stats.factor_nnz = self.l_values.len();
        if let (true, CholeskyKind::Llt, SymbolicCholeskyRaw::Simplicial(sym)) =
            (self.compact_solve, self.kind, symbolic.raw())
        {
            let perm = symbolic.perm().map(|p| p.arrays());
            self.compact = CompactFactor::new(sym.col_ptr(), sym.row_idx(), &self.l_values, perm);
            if self.compact.is_some() {
                self.l_values = Vec::new();
                self.pattern = None;
                self.symbolic = None;
                self.factor_mem = MemBuffer::new(StackReq::empty());
                self.factor_mem_cap = StackReq::empty();
            }
        }
        Ok(())
    }

    fn solve_in_place(&mut self, b: &mut [f64]) -> Result<(), SolverError> {
        self.solve_columns_in_place(b, 1)
    }

    fn solve_columns_in_place(&mut self, b: &mut [f64], ncols: usize) -> Result<(), SolverError> {
        if let (true, Some(c)) = (self.factored, self.compact.as_mut()) {
            if check_rhs(b.len(), c.n(), ncols)? {
                c.solve_columns(b, ncols);
                self.stats.solves += ncols;
            }
            return Ok(());
        }
        let (true, Some(symbolic)) = (self.factored, self.symbolic.as_ref()) else {
            return Err(SolverError::Failed(
                "solve called without a valid factorization".into(),
            ));
        };
        let n = symbolic.nrows();
        if !check_rhs(b.len(), n, ncols)? {
            return Ok(());
        }
        let req = symbolic.solve_in_place_scratch::<f64>(ncols, self.par);
        ensure_mem(&mut self.solve_mem, &mut self.solve_mem_cap, req)?;
        let rhs = MatMut::from_column_major_slice_mut(b, n, ncols);
        let stack = MemStack::new(&mut self.solve_mem);
        match self.kind {
            CholeskyKind::Llt => LltRef::new(symbolic, &self.l_values).solve_in_place_with_conj(
                Conj::No,
                rhs,
                self.par,
                stack,
            ),
            CholeskyKind::Ldlt => LdltRef::new(symbolic, &self.l_values).solve_in_place_with_conj(
                Conj::No,
                rhs,
                self.par,
                stack,
            ),
        }
        self.stats.solves += ncols;
        Ok(())
    }

    fn stats(&self) -> SolverStats {
        self.stats
    }
}

/// Sparse unsymmetric direct solver (`P·A·Q = L·U`, partial row pivoting) with symbolic and
/// buffer re-use.
pub struct SparseLu {
    layout: Layout,
    par: Par,
    /// `(pattern_id, n, nnz)` of the analysed pattern.
    pattern: Option<(u64, usize, usize)>,
    symbolic: Option<SymbolicLu<usize>>,
    numeric: NumericLu<usize, f64>,
    factor_mem: MemBuffer,
    factor_mem_cap: StackReq,
    solve_mem: MemBuffer,
    solve_mem_cap: StackReq,
    row_max: Vec<f64>,
    factored: bool,
    stats: SolverStats,
}

impl Default for SparseLu {
    fn default() -> Self {
        Self::new()
    }
}

impl std::fmt::Debug for SparseLu {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SparseLu")
            .field("layout", &self.layout)
            .field("factored", &self.factored)
            .field("stats", &self.stats)
            .finish()
    }
}

impl SparseLu {
    /// An LU solver, automatic simplicial/supernodal choice, single-threaded.
    pub fn new() -> SparseLu {
        SparseLu {
            layout: Layout::Auto,
            par: Par::Seq,
            pattern: None,
            symbolic: None,
            numeric: NumericLu::new(),
            factor_mem: MemBuffer::new(StackReq::empty()),
            factor_mem_cap: StackReq::empty(),
            solve_mem: MemBuffer::new(StackReq::empty()),
            solve_mem_cap: StackReq::empty(),
            row_max: Vec::new(),
            factored: false,
            stats: SolverStats::default(),
        }
    }

    /// Forces the simplicial or supernodal layout; forces a new symbolic analysis.
    pub fn with_layout(mut self, layout: Layout) -> SparseLu {
        self.layout = layout;
        self.pattern = None;
        self.symbolic = None;
        self.factored = false;
        self
    }

    /// Number of threads for the numeric factorization and solves (rayon; `0` or `1` means
    /// sequential).
    pub fn with_threads(mut self, threads: usize) -> SparseLu {
        self.par = par_for(threads);
        self.factor_mem_cap = StackReq::empty();
        self.solve_mem_cap = StackReq::empty();
        self
    }

    fn analyse_pattern(&mut self, a: &CscMatrix) -> Result<(), SolverError> {
        self.pattern = None;
        self.symbolic = None;
        validate_pattern(a)?;
        let sym = SymbolicSparseColMatRef::new_checked(a.n, a.n, &a.col_ptr, None, &a.row_idx);
        let params = LuSymbolicParams {
            supernodal_flop_ratio_threshold: self.layout.threshold(),
            ..Default::default()
        };
        let symbolic = factorize_symbolic_lu(sym, params)
            .map_err(|e| SolverError::Failed(format!("symbolic LU: {e:?}")))?;
        let req = symbolic.factorize_numeric_lu_scratch::<f64>(self.par, Default::default());
        self.factor_mem_cap = StackReq::empty();
        ensure_mem(&mut self.factor_mem, &mut self.factor_mem_cap, req)?;
        self.row_max.resize(a.n, 0.0);
        self.pattern = Some((a.pattern_id, a.n, a.row_idx.len()));
        self.symbolic = Some(symbolic);
        self.stats.symbolic_analyses += 1;
        Ok(())
    }

    /// Rejects non-finite values and reports an all-zero row or column as singular.
    fn check_values(&mut self, a: &CscMatrix) -> Result<(), SolverError> {
        self.row_max.iter_mut().for_each(|v| *v = 0.0);
        for j in 0..a.n {
            let mut col_max: f64 = 0.0;
            for p in a.col_ptr[j]..a.col_ptr[j + 1] {
                let x = a.values[p];
                if !x.is_finite() {
                    return Err(non_finite_error(a, p));
                }
                col_max = col_max.max(x.abs());
                let r = &mut self.row_max[a.row_idx[p]];
                *r = r.max(x.abs());
            }
            if col_max == 0.0 {
                return Err(SolverError::Singular { equation: j });
            }
        }
        if let Some(i) = self.row_max.iter().position(|&v| v == 0.0) {
            return Err(SolverError::Singular { equation: i });
        }
        Ok(())
    }
}

impl LinearSolver for SparseLu {
    fn analyse(&mut self, a: &CscMatrix) -> Result<(), SolverError> {
        if matches!(self.pattern, Some((id, n, nnz)) if same_pattern(a, id, n, nnz)) {
            return Ok(());
        }
        self.analyse_pattern(a)
    }

    fn factor(&mut self, a: &CscMatrix) -> Result<(), SolverError> {
        self.factored = false;
        let reuse = matches!(self.pattern, Some((id, n, nnz)) if same_pattern(a, id, n, nnz))
            && a.values.len() == a.row_idx.len()
            && a.col_ptr[a.n] == a.row_idx.len();
        if !reuse {
            self.analyse_pattern(a)?;
        }
        self.check_values(a)?;
        let Some(symbolic) = self.symbolic.as_ref() else {
            return Err(SolverError::Failed("no symbolic factorization".into()));
        };
        let sym = SymbolicSparseColMatRef::new_checked(a.n, a.n, &a.col_ptr, None, &a.row_idx);
        let mat = SparseColMatRef::new(sym, &a.values);
        let stack = MemStack::new(&mut self.factor_mem);
        match symbolic.factorize_numeric_lu::<f64>(
            &mut self.numeric,
            mat,
            self.par,
            stack,
            Default::default(),
        ) {
            Ok(_) => {}
            Err(LuError::SymbolicSingular { index }) => {
                let col = symbolic.col_perm().arrays().0[index.min(a.n.saturating_sub(1))];
                return Err(SolverError::Singular { equation: col });
            }
            Err(LuError::Generic(e)) => {
                return Err(SolverError::Failed(format!("numeric LU: {e:?}")));
            }
        }
        self.factored = true;
        self.stats.numeric_factorizations += 1;
        Ok(())
    }

    fn solve_in_place(&mut self, b: &mut [f64]) -> Result<(), SolverError> {
        self.solve_columns_in_place(b, 1)
    }

    fn solve_columns_in_place(&mut self, b: &mut [f64], ncols: usize) -> Result<(), SolverError> {
        let (true, Some(symbolic)) = (self.factored, self.symbolic.as_ref()) else {
            return Err(SolverError::Failed(
                "solve called without a valid factorization".into(),
            ));
        };
        let n = symbolic.nrows();
        if !check_rhs(b.len(), n, ncols)? {
            return Ok(());
        }
        let req = symbolic.solve_in_place_scratch::<f64>(ncols, self.par);
        ensure_mem(&mut self.solve_mem, &mut self.solve_mem_cap, req)?;
        let rhs = MatMut::from_column_major_slice_mut(b, n, ncols);
        let stack = MemStack::new(&mut self.solve_mem);
        LuRef::new_unchecked(symbolic, &self.numeric).solve_in_place_with_conj(
            Conj::No,
            rhs,
            self.par,
            stack,
        );
        self.stats.solves += ncols;
        if let Some(i) = b.iter().position(|x| !x.is_finite()) {
            return Err(SolverError::Failed(format!(
                "non-finite solution component {i}: the matrix is numerically singular"
            )));
        }
        Ok(())
    }

    fn stats(&self) -> SolverStats {
        self.stats
    }
}

/// Checks a right-hand side of `len` values against `n` unknowns × `ncols` columns;
/// `Ok(false)` when there is nothing to solve.
fn check_rhs(len: usize, n: usize, ncols: usize) -> Result<bool, SolverError> {
    if len != n * ncols {
        return Err(SolverError::Failed(format!(
            "right-hand side has length {len}, expected {n}×{ncols}"
        )));
    }
    Ok(ncols > 0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::DVector;

    /// Small deterministic xorshift generator, uniform in [-1, 1).
    struct Rng(u64);
    impl Rng {
        fn next(&mut self) -> f64 {
            self.0 ^= self.0 << 13;
            self.0 ^= self.0 >> 7;
            self.0 ^= self.0 << 17;
            (self.0 >> 11) as f64 / (1u64 << 52) as f64 - 1.0
        }
        fn vec(&mut self, n: usize) -> Vec<f64> {
            (0..n).map(|_| self.next()).collect()
        }
    }

    /// The triangle pattern of a matrix renumbered by a permutation, in either triangle:
    /// each column's rows strictly increasing, and the same `(column, row, source
    /// position)` list as the entries collected and sorted by a comparison sort (the
    /// independent reference).
    #[test]
    fn triangle_pattern_is_the_sorted_renumbered_triangle() {
        let a = laplacian(7, 5, 1.0, 0.5);
        let n = a.n;
        let shuffled: Vec<usize> = (0..n).map(|i| (i * 13 + 5) % n).collect();
        let identity: Vec<usize> = (0..n).collect();
        // The identity as a permutation and as none (the unsorted path of the lower
        // triangle) give the same triangles.
        let cases = [
            (Some(&shuffled[..]), &shuffled[..]),
            (Some(&identity[..]), &identity[..]),
            (None, &identity[..]),
        ];
        for ((perm, inv), upper) in cases.into_iter().flat_map(|c| [(c, false), (c, true)]) {
            let t = TrianglePattern::build(&a, perm, upper);
            let mut reference = Vec::new();
            for j in 0..n {
                for p in a.col_ptr[j]..a.col_ptr[j + 1] {
                    let i = a.row_idx[p];
                    if i >= j {
                        let (r, c) = (inv[i], inv[j]);
                        let (r, c) = if (r < c) == upper { (r, c) } else { (c, r) };
                        reference.push((c, r, p));
                    }
                }
            }
            reference.sort();
            let mut got = Vec::new();
            for c in 0..n {
                let rows = &t.row_idx[t.col_ptr[c]..t.col_ptr[c + 1]];
                assert!(rows.windows(2).all(|w| w[0] < w[1]), "column {c}");
                for k in t.col_ptr[c]..t.col_ptr[c + 1] {
                    let r = t.row_idx[k];
                    assert!(if upper { r <= c } else { r >= c }, "({r}, {c})");
                    got.push((c, t.row_idx[k], t.gather[k]));
                }
            }
            assert_eq!(got, reference);
        }
    }

    /// 5-point Laplacian on an `nx × ny` grid with Dirichlet boundaries, scaled by `scale`,
    /// plus `shift` on the diagonal. SPD for `scale > 0`, `shift >= 0`.
    fn laplacian(nx: usize, ny: usize, scale: f64, shift: f64) -> CscMatrix {
        let id = |i: usize, j: usize| i + nx * j;
        let mut t = Vec::new();
        for j in 0..ny {
            for i in 0..nx {
                let k = id(i, j);
                t.push((k, k, 4.0 * scale + shift));
                if i > 0 {
                    t.push((k, id(i - 1, j), -scale));
                }
                if i + 1 < nx {
                    t.push((k, id(i + 1, j), -scale));
                }
                if j > 0 {
                    t.push((k, id(i, j - 1), -scale));
                }
                if j + 1 < ny {
                    t.push((k, id(i, j + 1), -scale));
                }
            }
        }
        CscMatrix::from_triplets(nx * ny, &t)
    }

    /// Convection–diffusion operator (upwinded, so unsymmetric) on an `nx × ny` grid.
    fn convection_diffusion(nx: usize, ny: usize, c: f64) -> CscMatrix {
        let mut a = laplacian(nx, ny, 1.0, 0.0);
        for j in 0..ny {
            for i in 1..nx {
                let k = i + nx * j;
                let p = a.position(k, k - 1).unwrap();
                a.values[p] -= c;
                let d = a.position(k, k).unwrap();
                a.values[d] += c;
            }
        }
        a
    }

    fn rel_residual(a: &CscMatrix, x: &[f64], b: &[f64]) -> f64 {
        let mut r = b.to_vec();
        a.mul_vec_add(-1.0, x, &mut r);
        norm(&r) / norm(b)
    }

    fn norm(v: &[f64]) -> f64 {
        v.iter().map(|x| x * x).sum::<f64>().sqrt()
    }

    fn solve(s: &mut dyn LinearSolver, a: &CscMatrix, b: &[f64]) -> Vec<f64> {
        s.factor(a).unwrap();
        let mut x = b.to_vec();
        s.solve_in_place(&mut x).unwrap();
        x
    }

    /// All layouts and kinds that must solve an SPD system.
    fn spd_solvers() -> Vec<(&'static str, Box<dyn LinearSolver>)> {
        vec![
            ("llt auto", Box::new(SparseCholesky::new())),
            (
                "llt simplicial",
                Box::new(SparseCholesky::new().with_layout(Layout::Simplicial)),
            ),
            (
                "llt supernodal",
                Box::new(SparseCholesky::new().with_layout(Layout::Supernodal)),
            ),
            (
                "ldlt simplicial",
                Box::new(SparseCholesky::ldlt().with_layout(Layout::Simplicial)),
            ),
            (
                "ldlt supernodal",
                Box::new(SparseCholesky::ldlt().with_layout(Layout::Supernodal)),
            ),
            ("lu auto", Box::new(SparseLu::new())),
            (
                "lu simplicial",
                Box::new(SparseLu::new().with_layout(Layout::Simplicial)),
            ),
            (
                "lu supernodal",
                Box::new(SparseLu::new().with_layout(Layout::Supernodal)),
            ),
        ]
    }

    /// n = 2025 Laplacian: a backward-stable factorization gives a relative residual of
    /// order `eps · ‖A‖·‖x‖/‖b‖`; here ‖A‖ ≤ 8 and ‖A⁻¹‖ ≈ 1/(2π²/46²) ≈ 107, so the
    /// worst case is ~2e-13 and 1e-12 is a safe bound that still catches any wrong entry.
    #[test]
    fn laplacian_2000_residual() {
        let a = laplacian(45, 45, 1.0, 0.0);
        let b = Rng(7).vec(a.n);
        for (name, mut s) in spd_solvers() {
            let x = solve(s.as_mut(), &a, &b);
            let r = rel_residual(&a, &x, &b);
            assert!(r < 1e-12, "{name}: residual {r:e}");
            assert_eq!(s.stats().symbolic_analyses, 1, "{name}");
            assert_eq!(s.stats().solves, 1, "{name}");
        }
    }

    /// A random sparse SPD matrix (random symmetric pattern, diagonal made dominant so the
    /// condition number is O(10)) against nalgebra's dense Cholesky: the two solutions agree
    /// to `cond · eps` ≈ 1e-14, asserted at 1e-12.
    #[test]
    fn small_random_spd_matches_dense() {
        let n = 60;
        let mut rng = Rng(3);
        let mut t = Vec::new();
        let mut diag = vec![1.0; n];
        for _ in 0..200 {
            let i = ((rng.next() + 1.0) * 0.5 * n as f64) as usize % n;
            let j = ((rng.next() + 1.0) * 0.5 * n as f64) as usize % n;
            if i == j {
                continue;
            }
            let v = rng.next();
            t.push((i, j, v));
            t.push((j, i, v));
            diag[i] += 2.0 * v.abs();
            diag[j] += 2.0 * v.abs();
        }
        for (i, d) in diag.iter().enumerate() {
            t.push((i, i, *d));
        }
        let a = CscMatrix::from_triplets(n, &t);
        let b = rng.vec(n);
        let reference = a
            .to_dense()
            .cholesky()
            .unwrap()
            .solve(&DVector::from_vec(b.clone()));
        for (name, mut s) in spd_solvers() {
            let x = solve(s.as_mut(), &a, &b);
            let err = (DVector::from_vec(x) - &reference).norm() / reference.norm();
            assert!(err < 1e-12, "{name}: error {err:e}");
        }
    }

    /// Same pattern, new values: the answer follows the new values and no new symbolic
    /// analysis happens; a new pattern triggers one.
    #[test]
    fn refactor_reuses_symbolic_until_pattern_changes() {
        let a1 = laplacian(30, 30, 1.0, 0.0);
        let mut a2 = a1.zeros_like();
        let a_shift = laplacian(30, 30, 0.0, 1.0); // identity, different pattern id
                                                   // a2 = 3·A1 + 0.5·I (same pattern as a1)
        for j in 0..a1.n {
            for p in a1.col_ptr[j]..a1.col_ptr[j + 1] {
                a2.values[p] = 3.0 * a1.values[p] + if a1.row_idx[p] == j { 0.5 } else { 0.0 };
            }
        }
        assert_eq!(a2.pattern_id, a1.pattern_id);
        let b = Rng(11).vec(a1.n);
        for (name, mut s) in spd_solvers() {
            let x1 = solve(s.as_mut(), &a1, &b);
            assert!(rel_residual(&a1, &x1, &b) < 1e-12, "{name}");
            let x2 = solve(s.as_mut(), &a2, &b);
            assert!(rel_residual(&a2, &x2, &b) < 1e-12, "{name}");
            let st = s.stats();
            assert_eq!(
                (st.symbolic_analyses, st.numeric_factorizations),
                (1, 2),
                "{name}"
            );
            // different pattern (diagonal only): symbolic analysis is redone
            let x3 = solve(s.as_mut(), &a_shift, &b);
            assert!(rel_residual(&a_shift, &x3, &b) < 1e-15, "{name}");
            let st = s.stats();
            assert_eq!(
                (st.symbolic_analyses, st.numeric_factorizations),
                (2, 3),
                "{name}"
            );
            // and back to the first pattern
            let x4 = solve(s.as_mut(), &a1, &b);
            assert!(rel_residual(&a1, &x4, &b) < 1e-12, "{name}");
            assert_eq!(s.stats().symbolic_analyses, 3, "{name}");
        }
    }

    /// Zeroing row and column `e` (entries kept in the pattern) makes the matrix singular
    /// exactly at equation `e`: every solver must name it, whatever its internal ordering.
    #[test]
    fn zero_row_reports_original_equation() {
        for e in [0usize, 17, 311, 899] {
            let mut a = laplacian(30, 30, 1.0, 0.0);
            for j in 0..a.n {
                for p in a.col_ptr[j]..a.col_ptr[j + 1] {
                    if j == e || a.row_idx[p] == e {
                        a.values[p] = 0.0;
                    }
                }
            }
            for (name, mut s) in spd_solvers() {
                assert_eq!(
                    s.factor(&a),
                    Err(SolverError::Singular { equation: e }),
                    "{name}, e = {e}"
                );
                let mut x = vec![1.0; a.n];
                assert!(
                    s.solve_in_place(&mut x).is_err(),
                    "{name}: solve after failure"
                );
            }
        }
    }

    /// A decoupled equation `e` with a negative diagonal: `L·Lᵀ` must fail there (pivot
    /// not positive) and report `e`; `L·D·Lᵀ` succeeds and solves the indefinite system.
    #[test]
    fn negative_pivot_llt_fails_ldlt_solves() {
        let e = 123;
        let mut a = laplacian(20, 20, 1.0, 0.0);
        for j in 0..a.n {
            for p in a.col_ptr[j]..a.col_ptr[j + 1] {
                let i = a.row_idx[p];
                if (i == e) != (j == e) {
                    a.values[p] = 0.0;
                } else if i == e && j == e {
                    a.values[p] = -2.0;
                }
            }
        }
        for layout in [Layout::Simplicial, Layout::Supernodal] {
            let mut llt = SparseCholesky::new().with_layout(layout);
            assert_eq!(
                llt.factor(&a),
                Err(SolverError::Singular { equation: e }),
                "{layout:?}"
            );
            assert_eq!(llt.is_supernodal(), Some(layout == Layout::Supernodal));
            let b = Rng(5).vec(a.n);
            let x = solve(&mut SparseCholesky::ldlt().with_layout(layout), &a, &b);
            assert!(rel_residual(&a, &x, &b) < 1e-12, "{layout:?}");
            assert!((x[e] - b[e] / -2.0).abs() < 1e-15);
        }
    }

    /// Unsymmetric convection–diffusion, n = 2025: residual bound as for the Laplacian
    /// (the upwinded operator is an M-matrix of similar norm and conditioning); small case
    /// against nalgebra's dense LU.
    #[test]
    fn lu_unsymmetric() {
        let a = convection_diffusion(45, 45, 2.5);
        assert!(a.asymmetry() > 0.1);
        let b = Rng(9).vec(a.n);
        for layout in [Layout::Auto, Layout::Simplicial, Layout::Supernodal] {
            let mut s = SparseLu::new().with_layout(layout);
            let x = solve(&mut s, &a, &b);
            assert!(rel_residual(&a, &x, &b) < 1e-12, "{layout:?}");
            // refactor with new values, same pattern
            let mut a2 = a.clone();
            a2.values.iter_mut().for_each(|v| *v *= 2.0);
            let x2 = solve(&mut s, &a2, &b);
            for (u, v) in x.iter().zip(&x2) {
                assert!((u - 2.0 * v).abs() < 1e-12 * (1.0 + u.abs()), "{layout:?}");
            }
            assert_eq!(s.stats().symbolic_analyses, 1);
            assert_eq!(s.stats().numeric_factorizations, 2);
        }
        let small = convection_diffusion(6, 7, 3.0);
        let b = Rng(1).vec(small.n);
        let reference = small
            .to_dense()
            .lu()
            .solve(&DVector::from_vec(b.clone()))
            .unwrap();
        let x = solve(&mut SparseLu::new(), &small, &b);
        let err = (DVector::from_vec(x) - &reference).norm() / reference.norm();
        assert!(err < 1e-13, "error {err:e}");
    }

    /// Several right-hand sides at once equal the single solves.
    #[test]
    fn multiple_right_hand_sides() {
        let a = laplacian(12, 9, 1.0, 0.1);
        let n = a.n;
        let b = Rng(2).vec(3 * n);
        for (name, mut s) in spd_solvers() {
            s.factor(&a).unwrap();
            let mut many = b.clone();
            s.solve_columns_in_place(&mut many, 3).unwrap();
            for c in 0..3 {
                let mut one = b[c * n..(c + 1) * n].to_vec();
                s.solve_in_place(&mut one).unwrap();
                // blocked multi-column kernels may round differently: agree to a few ulps
                // of the solution's scale
                let scale = norm(&one);
                for (u, v) in many[c * n..(c + 1) * n].iter().zip(&one) {
                    assert!((u - v).abs() <= 1e-14 * scale, "{name}");
                }
            }
            assert_eq!(s.stats().solves, 6, "{name}");
        }
    }

    #[test]
    fn bad_input_is_an_error_not_a_panic() {
        let mut a = laplacian(5, 5, 1.0, 0.0);
        a.values[7] = f64::NAN;
        for (name, mut s) in spd_solvers() {
            assert!(
                matches!(s.factor(&a), Err(SolverError::Failed(_))),
                "{name}"
            );
        }
        let a = laplacian(5, 5, 1.0, 0.0);
        let mut s = solver_for(true);
        let mut short = vec![1.0; 3];
        assert!(s.solve_in_place(&mut short).is_err(), "solve before factor");
        s.factor(&a).unwrap();
        assert!(s.solve_in_place(&mut short).is_err(), "wrong length");
        let mut broken = a.clone();
        broken.pattern_id = u64::MAX; // force re-analysis of a malformed pattern
        broken.row_idx.swap(0, 1);
        assert!(matches!(s.factor(&broken), Err(SolverError::Failed(_))));
        assert!(matches!(
            solver_for(false).factor(&broken),
            Err(SolverError::Failed(_))
        ));
    }
}

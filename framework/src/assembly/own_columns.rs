//! The constant matrices of one rank of a model shared among processes: `K`, `M`, `C` kept
//! on the columns of the equations whose residual rows the rank forms, the other columns
//! dropped ([`Assembler::keep_constant_columns`]) or never formed
//! ([`Assembler::new_on_columns`]).
//!
//! The constant part is symmetric (every constant element is: checked), so column `i`
//! holds row `i`, and the products are formed as gathers, `(K·x)_i = Σ_j K_ji·x_j` over
//! column `i` ([`crate::sparse::symmetric_products`]). A row `i` whose column is kept is
//! therefore formed with the same terms in the same order as from the whole matrix — the
//! same value to the bit — while a row whose column was dropped comes out as zero. A rank
//! that keeps the columns of the rows it owns forms its rows of `K·q`, `M·a_w`, `C·v_w` and
//! holds about `1/P` of the three matrices.
//!
//! **Formed on the columns.** An entry of a kept column is the sum of the elements'
//! contributions in element order whether or not the other columns are formed, so forming
//! only the kept ones gives their values to the bit, and the whole matrices never exist on
//! the rank. What is a property of every column is settled apart: the diagonals of `K`,
//! `M`, `C` over every equation (a vector each, summed in the same order as the matrices'
//! diagonal entries: the data check reads them), and whether `C` is zero and `M` diagonal,
//! which the ranks agree on from their columns (together every column,
//! [`Assembler::settle_across_ranks`]).

use super::Assembler;
use crate::error::FemError;
use crate::model::{Model, SolverChoice, SolverResolver};
use crate::sparse::CscMatrix;

/// What a rank of a shared model is shown before the constant values are formed
/// ([`Assembler::new_on_columns`]).
pub struct ColumnChoice<'a> {
    /// The pattern `K`, `M`, `C` share (no values).
    pub pattern: &'a CscMatrix,
    /// Whether every element declares a symmetric tangent.
    pub symmetric: bool,
    /// The linear solver the model runs with (`auto` resolved).
    pub solver: SolverChoice,
}

/// Picks the columns of `K`, `M`, `C` to form from the pattern (`None`: every column).
pub type ColumnChooser<'a> = dyn FnMut(&ColumnChoice) -> Option<Vec<bool>> + 'a;

/// `a` with only the columns `j` where `keep[j]` (same size and pattern id; the pattern of
/// the kept columns and their values as they were).
pub(super) fn kept_columns(a: &CscMatrix, keep: &[bool]) -> CscMatrix {
    let kept = |j: usize| keep.get(j).copied().unwrap_or(false);
    let len: usize = (0..a.n)
        .filter(|&j| kept(j))
        .map(|j| a.col_ptr[j + 1] - a.col_ptr[j])
        .sum();
    let mut col_ptr = Vec::with_capacity(a.n + 1);
    let mut row_idx = Vec::with_capacity(len);
    let mut values = Vec::with_capacity(if a.values.is_empty() { 0 } else { len });
    col_ptr.push(0);
    for j in 0..a.n {
        if kept(j) {
            let r = a.col_ptr[j]..a.col_ptr[j + 1];
            row_idx.extend_from_slice(&a.row_idx[r.clone()]);
            if !a.values.is_empty() {
                values.extend_from_slice(&a.values[r]);
            }
        }
        col_ptr.push(row_idx.len());
    }
    CscMatrix {
        n: a.n,
        col_ptr,
        row_idx,
        values,
        pattern_id: a.pattern_id,
    }
}

impl Assembler {
    /// [`Assembler::new`] for one rank of a model shared among processes: once the pattern
    /// is known, `choose` is shown it and picks the columns this rank keeps, and `K`, `M`,
    /// `C` are formed on those columns only — their values to the bit, the others never
    /// formed (module documentation). Only where keeping columns is exact, as for
    /// [`Assembler::keep_constant_columns`] (and only then is `choose` called); otherwise,
    /// or if `choose` answers `None`, the build forms every column as `new` does.
    /// Afterwards every rank must call [`Assembler::settle_across_ranks`], the same number
    /// of times (once).
    pub fn new_on_columns(
        model: &mut Model,
        resolve: SolverResolver,
        choose: &mut ColumnChooser<'_>,
    ) -> Result<Assembler, FemError> {
        Self::new_choosing(model, resolve, Some(choose))
    }

    /// The build's choice of columns ([`Assembler::new_on_columns`]): asks `choose` when the
    /// constant part can be kept on columns exactly (every constant element symmetric, the
    /// variable elements off the pattern, no mass or damping re-formed on it). The pattern's
    /// values are dropped first: the choice reads its structure only.
    pub(super) fn choose_columns(
        &self,
        pattern: &mut CscMatrix,
        const_symmetric: bool,
        choose: Option<&mut ColumnChooser<'_>>,
    ) -> Option<Vec<bool>> {
        let choose = choose?;
        let exact = const_symmetric && self.off_pattern && !self.m_var_used && !self.c_var_used;
        if !exact {
            return None;
        }
        pattern.values = Vec::new();
        let keep = choose(&ColumnChoice {
            pattern,
            symmetric: self.symmetric,
            solver: self.solver,
        })?;
        (keep.len() == pattern.n).then_some(keep)
    }

    /// After [`Assembler::new_on_columns`], on every rank: whether `C` is zero and `M`
    /// diagonal, from every column. `any_rank(flag)` answers whether `flag` holds on any
    /// rank (a collective: every rank calls this once, in the same order); the kept
    /// columns of all ranks are every column, so the answers are those of the whole
    /// matrices, and with them the products take the same path (a diagonal `M` from its
    /// whole diagonal) as in one process. Nothing to do after a whole build.
    pub fn settle_across_ranks(&mut self, any_rank: &dyn Fn(bool) -> bool) {
        let Some([_, m_whole, _]) = &self.diagonals else {
            return;
        };
        let c_nonzero = any_rank(self.c_const.values.iter().any(|&c| c != 0.0));
        let m_coupled = any_rank(super::diagonal_of(&self.m_const).is_none());
        self.c_const_zero = !c_nonzero;
        self.m_diag = (!m_coupled).then(|| m_whole.clone());
    }

    /// The diagonals of the whole `K`, `M`, `C` (every equation), also after a build on
    /// some columns ([`Assembler::new_on_columns`]).
    pub fn constant_diagonals(&self) -> [Vec<f64>; 3] {
        match &self.diagonals {
            Some(d) => d.clone(),
            None => [&self.k_const, &self.m_const, &self.c_const]
                .map(|m| (0..m.n).map(|i| m.get(i, i)).collect()),
        }
    }

    /// Stored entries of `K` (`M` and `C` the same) at the largest build: the most of each
    /// constant matrix this process ever held — all of them after [`Assembler::new`], its
    /// columns' after [`Assembler::new_on_columns`].
    pub fn constant_entries_built(&self) -> usize {
        self.entries_built
    }

    /// Keeps `K`, `M`, `C` on the columns `j` with `keep[j]` only (module documentation):
    /// afterwards the products with the constant matrices are exact on the rows whose
    /// columns were kept and zero on the others, and [`Assembler::effective_columns`] may
    /// be asked for kept columns only. Done only where it is exact — every constant element
    /// symmetric (the gather form) and no variable matrix on the pattern (their values are
    /// scattered by positions of the whole pattern) — and then `true`; otherwise nothing
    /// changes and `false`.
    pub fn keep_constant_columns(&mut self, keep: &[bool]) -> bool {
        let n = self.k_const.n;
        let on_pattern = |m: &CscMatrix| m.n == n && !m.row_idx.is_empty();
        if !self.const_symmetric
            || keep.len() != n
            || self.m_var_used
            || self.c_var_used
            || on_pattern(&self.k_var)
            || on_pattern(&self.m_var)
            || on_pattern(&self.c_var)
        {
            return false;
        }
        self.k_const = kept_columns(&self.k_const, keep);
        self.m_const = kept_columns(&self.m_const, keep);
        self.c_const = kept_columns(&self.c_const, keep);
        if self.nonzero.is_some() {
            self.nonzero = self.nonzero_matrices();
        }
        self.columns_kept = true;
        true
    }

    /// Whether `K`, `M`, `C` hold only some columns ([`Assembler::keep_constant_columns`]).
    pub fn constant_columns_kept(&self) -> bool {
        self.columns_kept
    }

    /// Stored entries of the constant stiffness (`K`, `M`, `C` share its pattern).
    pub fn constant_entries(&self) -> usize {
        self.k_const.row_idx.len()
    }
}

#[cfg(test)]
mod tests {
    use super::kept_columns;
    use crate::sparse::{symmetric_products, CscMatrix};

    /// A symmetric tridiagonal matrix with distinct values.
    fn chain(n: usize) -> CscMatrix {
        let mut t = Vec::new();
        for i in 0..n {
            t.push((i, i, 4.0 + i as f64));
            if i + 1 < n {
                let v = -1.0 - 0.1 * i as f64;
                t.push((i, i + 1, v));
                t.push((i + 1, i, v));
            }
        }
        CscMatrix::from_triplets(n, &t)
    }

    #[test]
    fn kept_rows_of_the_gather_product_are_the_whole_matrix_rows_to_the_bit() {
        let a = chain(9);
        let keep: Vec<bool> = (0..9).map(|i| i % 3 != 1).collect();
        let b = kept_columns(&a, &keep);
        assert_eq!(b.pattern_id, a.pattern_id);
        assert_eq!(
            b.row_idx.len(),
            a.row_idx.len() - 3 * 3,
            "three interior columns of three entries dropped"
        );
        let x: Vec<f64> = (0..9).map(|i| (i as f64 * 0.7).sin()).collect();
        let (mut ya, mut yb) = (vec![0.0; 9], vec![0.0; 9]);
        symmetric_products(&[&a], &[&x], &mut [&mut ya], 1);
        symmetric_products(&[&b], &[&x], &mut [&mut yb], 1);
        for i in 0..9 {
            if keep[i] {
                assert_eq!(ya[i].to_bits(), yb[i].to_bits(), "row {i}");
            } else {
                assert_eq!(yb[i], 0.0, "row {i}");
            }
        }
    }
}

//! The constant matrices of one rank of a model shared among processes: `K`, `M`, `C` kept
//! on the columns of the equations whose residual rows the rank forms, the other columns
//! dropped ([`Assembler::keep_constant_columns`]).
//!
//! The constant part is symmetric (every constant element is: checked), so column `i`
//! holds row `i`, and the products are formed as gathers, `(K·x)_i = Σ_j K_ji·x_j` over
//! column `i` ([`crate::sparse::symmetric_products`]). A row `i` whose column is kept is
//! therefore formed with the same terms in the same order as from the whole matrix — the
//! same value to the bit — while a row whose column was dropped comes out as zero. A rank
//! that keeps the columns of the rows it owns forms its rows of `K·q`, `M·a_w`, `C·v_w` and
//! holds about `1/P` of the three matrices.

use super::Assembler;
use crate::sparse::CscMatrix;

/// `a` with only the columns `j` where `keep[j]` (same size and pattern id; the pattern of
/// the kept columns and their values as they were).
fn kept_columns(a: &CscMatrix, keep: &[bool]) -> CscMatrix {
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

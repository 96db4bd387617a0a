//! The rows a step's passes over the equations touch while the activity window holds
//! blocks ([`crate::window`]): every row but the *deep* held ones, whose values a step
//! does not change (`HeldRows`).
//!
//! **Why a deep held row needs no pass.** A held block's interior rows `H` keep `q` fixed
//! and `v = a = 0`, so their weighted kinematics `a_w = v_w = 0` as well. A held row `i`
//! is *deep* when every entry of its row of the constant matrices' pattern (the union of
//! `K`, `M` and `C`) lies in a held column. Its products are then constant while the
//! window does not change: `(K·q)_i = Σ_j K_ij·q_j` sums the same values in the same
//! order, so its bits do not change; `(M·a_w)_i`, `(C·v_w)_i`, `(M·v)_i`, `(C·v)_i` are
//! sums of zero terms, `0`; its residual is a reaction, set to zero; its correction is
//! zero (the solver skips the block). The held rows that are not deep (the *border*,
//! coupled to an active column) are formed as before: their internal force follows the
//! active side, and it enters the convergence test's force reference.
//!
//! **What a skipped pass relies on.** A vector a pass writes keeps the values of its deep
//! rows from an earlier pass, so every work vector must have been written over every
//! row at least once since the held set last changed. The driver's work vectors rotate
//! (the state's storage is the one from two steps before, the next predictor's products
//! take the place of the internal force), so after a change every row is formed for
//! [`SETTLE_STEPS`] committed steps, more than the longest rotation (two states, and the
//! internal force's storage cycling through the next predictor's), and only then are the
//! deep rows left out.
//!
//! **Norms.** The convergence test's `|q|`, `|f_int|` and `|f̄_ext|` include the deep
//! rows: their sums of squares over the deep rows are formed once, when the rows are
//! first left out, and added to the sums over the rows formed (the sum's order changes:
//! round-off of the norm only). The loads on a held block are taken as constant, as
//! holding the block already assumes (a held interior does not respond to a change of its
//! loads). Energy works `½·(f_n + f_{n+1})·Δq` and `vᵀ·M·v` have zero terms there.

use railfem_framework::row_set::RowSet;
use railfem_framework::sparse::CscMatrix;
use std::sync::Arc;

/// Committed steps after a change of the held set during which every row is formed
/// (module documentation).
pub const SETTLE_STEPS: usize = 3;

/// The rows formed while blocks are held, and the deep rows' constant sums.
#[derive(Debug, Clone)]
pub(crate) struct HeldRows {
    /// Every row but the deep held ones.
    compute: Arc<RowSet>,
    /// The deep held rows.
    deep: RowSet,
    /// Committed steps still to form every row.
    pending: usize,
    /// Sums of squares over the deep rows of `q`, `f_int` and `f̄_ext`, once formed.
    sums: Option<[f64; 3]>,
}

impl HeldRows {
    /// The rows for the `held` flags (one per equation) on the pattern of `pattern`
    /// (module documentation); every row is formed for the next [`SETTLE_STEPS`] steps.
    pub(crate) fn new(held: &[bool], pattern: &CscMatrix) -> HeldRows {
        let n = held.len();
        // Deep: held, and every entry of its column (the pattern is symmetric) held.
        let deep: Vec<bool> = (0..n)
            .map(|j| {
                held[j]
                    && pattern.row_idx[pattern.col_ptr[j]..pattern.col_ptr[j + 1]]
                        .iter()
                        .all(|&i| held[i])
            })
            .collect();
        let compute: Vec<bool> = deep.iter().map(|&d| !d).collect();
        HeldRows {
            compute: Arc::new(RowSet::from_mask(&compute)),
            deep: RowSet::from_mask(&deep),
            pending: SETTLE_STEPS,
            sums: None,
        }
    }

    /// The rows to form now: `None` (every row) until [`SETTLE_STEPS`] steps have been
    /// committed since the held set changed.
    pub(crate) fn rows(&self) -> Option<Arc<RowSet>> {
        (self.pending == 0).then(|| Arc::clone(&self.compute))
    }

    /// Number of deep (skipped) rows.
    pub(crate) fn deep_count(&self) -> usize {
        self.deep.count()
    }

    /// A step was committed.
    pub(crate) fn committed(&mut self) {
        self.pending = self.pending.saturating_sub(1);
    }

    /// The sums of squares over the deep rows of `q`, `f_int` and
    /// `f̄_ext = (1 − α_f)·f_ext + α_f·f_ext,0`, formed from the given vectors the first
    /// time (each in row order) and kept.
    pub(crate) fn deep_sums(
        &mut self,
        q: &[f64],
        f_int: &[f64],
        (f_ext, f_ext0, af): (&[f64], &[f64], f64),
    ) -> [f64; 3] {
        if let Some(s) = self.sums {
            return s;
        }
        let mut s = [0.0; 3];
        for r in self.deep.ranges() {
            for i in r.clone() {
                let fr = (1.0 - af) * f_ext[i] + af * f_ext0[i];
                s[0] += q[i] * q[i];
                s[1] += f_int[i] * f_int[i];
                s[2] += fr * fr;
            }
        }
        self.sums = Some(s);
        s
    }
}

/// The parts of `lo..hi` to form: all of it without `rows`.
pub(crate) fn parts(rows: Option<&RowSet>, lo: usize, hi: usize) -> Vec<std::ops::Range<usize>> {
    match rows {
        Some(r) => r.within(lo, hi).collect(),
        None => std::iter::once(lo..hi).collect(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A chain of 10 equations, each coupled to its neighbours: with 3..8 held, the deep
    /// rows are 4..7 (3 and 7 touch the free 2 and 8), and nothing is left out before
    /// three steps are committed.
    #[test]
    fn deep_rows_are_held_rows_without_a_free_neighbour() {
        let mut t = Vec::new();
        for i in 0..10 {
            t.push((i, i, 2.0));
            if i + 1 < 10 {
                t.push((i, i + 1, -1.0));
                t.push((i + 1, i, -1.0));
            }
        }
        let a = CscMatrix::from_triplets(10, &t);
        let held: Vec<bool> = (0..10).map(|i| (3..8).contains(&i)).collect();
        let mut h = HeldRows::new(&held, &a);
        assert_eq!(h.deep_count(), 3);
        for _ in 0..SETTLE_STEPS {
            assert!(h.rows().is_none());
            h.committed();
        }
        let rows = h.rows().expect("settled");
        assert_eq!(rows.ranges(), &[0..4, 7..10]);
        assert_eq!(parts(Some(&rows), 2, 9), vec![2..4, 7..9]);
        assert_eq!(parts(None, 2, 9), vec![2..9]);
        let q: Vec<f64> = (0..10).map(|i| i as f64).collect();
        let s = h.deep_sums(&q, &q, (&q, &q, 0.25));
        assert_eq!(s, [16.0 + 25.0 + 36.0; 3]);
    }
}

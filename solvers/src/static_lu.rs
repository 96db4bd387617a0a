//! LU with the row exchanges of an earlier factorization replayed, checked, on a precomputed
//! pattern, with a fallback to the pivoting dense LU (for the curve case's unsymmetric creep
//! tangent, refactored at every Newton iteration with nearly the same values).
//!
//! **What it computes.** [`DenseLu::fill_reducing`] renumbers the equations by the approximate
//! minimum degree order of the pattern of `A + Aᵀ`, `A' = P·A·Pᵀ`, and eliminates `A'` with
//! partial pivoting: at step `k` it takes the first row, in its current order starting at
//! row `k`, of largest `|a'_ik|`, and exchanges it with row `k`. Call the resulting row order
//! `Q` (`A'' = Q·A'`, so that `A'' = L·U` without exchanges). Given `Q` from an earlier
//! factorization, this solver eliminates `Q·A'` without exchanges and checks at each step that
//! partial pivoting would have chosen the same row: `|a''_kk| > |a''_ik|` for every candidate
//! `i > k` (strictly, so that a tie, which partial pivoting breaks by the current row order,
//! is never guessed), and that `|a''_kk|` exceeds `1e-14` times the largest entry of the
//! original column (the dense LU's singularity test). Every entry then sees the dense LU's
//! operations in its order — `a_ij −= l_ik·u_kj` for increasing `k`, one division per
//! multiplier — so the factor and the solution are the dense LU's to the bit (up to the sign
//! of a zero: the dense LU skips a zero multiplier or pivot-row entry, this one subtracts the
//! product). When a check fails, the factorization is redone by the dense LU, whose solves
//! are then used, and its `Q` is kept for the next call: a matrix the replay refuses is
//! solved (or reported singular) exactly as before.
//!
//! **Why it is cheaper.** Without exchanges the pattern of `L + U` depends only on the
//! pattern of `A''` and is computed once per (pattern, `Q`) by a boolean elimination
//! (`Symbolic`; `O(n³)` bit operations, 66³ at the curve case, repeated only when `Q`
//! changes). The numeric factorization then visits exactly the structural entries —
//! `Σ_k |L_k|·|U_k|` multiply-adds with `L_k` the rows below and `U_k` the columns right of
//! pivot `k` — with no scan of a dense column for nonzeros, no search for a row to exchange
//! beyond the check, and no exchange. The factor lives in a dense `n × n` column-major array
//! (35 kB at 66 equations) of which only the `L + U` pattern is ever written.

use crate::dense::{DenseLu, FillOrder};
use crate::linear::{LinearSolver, SolverError, SolverStats};
use railfem_framework::sparse::CscMatrix;

/// The pattern of `L + U` for one pattern of `A` and one row order `Q`.
#[derive(Debug)]
struct Symbolic {
    order: FillOrder,
    /// `Q`: position `k` holds row `q[k]` of `A'` (`A'' = Q·A'`).
    q: Vec<usize>,
    /// Rows of `L` below pivot `k`, ascending, at `l_rows[l_ptr[k]..l_ptr[k + 1]]`.
    l_ptr: Vec<usize>,
    l_rows: Vec<usize>,
    /// Columns of `U` right of pivot `k`, ascending, at `u_cols[u_ptr[k]..u_ptr[k + 1]]`.
    u_ptr: Vec<usize>,
    u_cols: Vec<usize>,
    /// Rows of `U` above the diagonal in column `j`, ascending, at
    /// `ut_rows[ut_ptr[j]..ut_ptr[j + 1]]` (for the back substitution by columns).
    ut_ptr: Vec<usize>,
    ut_rows: Vec<usize>,
    /// Offset in the dense factor of each stored entry of `A`.
    dest: Vec<usize>,
    /// Column of each stored entry of `A` in `A''` (for the column scale).
    dest_col: Vec<usize>,
}

/// Concatenates per-index lists into (pointers, entries).
fn compress(lists: &[Vec<usize>]) -> (Vec<usize>, Vec<usize>) {
    let mut ptr = Vec::with_capacity(lists.len() + 1);
    ptr.push(0);
    for l in lists {
        ptr.push(ptr.last().copied().unwrap_or(0) + l.len());
    }
    (ptr, lists.concat())
}

impl Symbolic {
    /// The `L + U` pattern of `Q·P·A·Pᵀ` eliminated without exchanges (`q` as in the field).
    fn of(a: &CscMatrix, order: FillOrder, q: Vec<usize>) -> Symbolic {
        let n = a.n;
        let mut pos = vec![0usize; n];
        for (k, &r) in q.iter().enumerate() {
            pos[r] = k;
        }
        // Structural pattern of A'' (column-major booleans) and the scatter map.
        let mut nz = vec![false; n * n];
        let (mut dest, mut dest_col) = (Vec::new(), Vec::new());
        for j in 0..n {
            let c = order.new[j];
            for &i in &a.row_idx[a.col_ptr[j]..a.col_ptr[j + 1]] {
                let r = pos[order.new[i]];
                nz[c * n + r] = true;
                dest.push(c * n + r);
                dest_col.push(c);
            }
        }
        let (mut l, mut u, mut ut) = (
            vec![Vec::new(); n],
            vec![Vec::new(); n],
            vec![Vec::new(); n],
        );
        for k in 0..n {
            l[k] = (k + 1..n).filter(|&i| nz[k * n + i]).collect();
            u[k] = (k + 1..n).filter(|&j| nz[j * n + k]).collect();
            for &j in &u[k] {
                ut[j].push(k);
                for &i in &l[k] {
                    nz[j * n + i] = true;
                }
            }
        }
        let (l_ptr, l_rows) = compress(&l);
        let (u_ptr, u_cols) = compress(&u);
        let (ut_ptr, ut_rows) = compress(&ut);
        Symbolic {
            order,
            q,
            l_ptr,
            l_rows,
            u_ptr,
            u_cols,
            ut_ptr,
            ut_rows,
            dest,
            dest_col,
        }
    }
}

/// LU replaying the last row exchanges, with the pivoting dense LU as fallback (module
/// documentation).
#[derive(Debug, Default)]
pub struct StaticLu {
    sym: Option<Symbolic>,
    /// The factor, dense column-major `n × n`; only the `L + U` pattern is ever nonzero.
    lu: Vec<f64>,
    /// Largest |entry| of each original column of `A''` (scratch).
    scale: Vec<f64>,
    /// The permuted right-hand side (scratch).
    work: Vec<f64>,
    /// The pivoting LU, for the factorizations the replay refuses.
    fallback: DenseLu,
    /// Whether the last factorization is the fallback's.
    fell_back: bool,
    /// How many factorizations fell back.
    fallbacks: usize,
    stats: SolverStats,
}

impl StaticLu {
    /// A solver with nothing factored yet.
    pub fn new() -> StaticLu {
        StaticLu {
            fallback: DenseLu::fill_reducing(),
            ..Default::default()
        }
    }

    /// How many factorizations were handed to the pivoting LU.
    pub fn fallbacks(&self) -> usize {
        self.fallbacks
    }

    /// The elimination of `Q·A'` without exchanges; `Ok(false)` when a check fails.
    fn eliminate(&mut self, a: &CscMatrix) -> Result<bool, SolverError> {
        let n = a.n;
        let sym = self
            .sym
            .as_ref()
            .expect("symbolic analysis before elimination");
        let lu = &mut self.lu;
        // Zero the pattern (nothing else is ever written), then scatter A''.
        for k in 0..n {
            lu[k * n + k] = 0.0;
            for &i in &sym.l_rows[sym.l_ptr[k]..sym.l_ptr[k + 1]] {
                lu[k * n + i] = 0.0;
            }
            for &j in &sym.u_cols[sym.u_ptr[k]..sym.u_ptr[k + 1]] {
                lu[j * n + k] = 0.0;
            }
        }
        self.scale.clear();
        self.scale.resize(n, 0.0);
        for (p, &v) in a.values.iter().enumerate() {
            if !v.is_finite() {
                return Err(SolverError::Failed(format!(
                    "matrix entry ({}, {}) is not finite",
                    a.row_idx[p],
                    a.col_ptr.partition_point(|&c| c <= p) - 1
                )));
            }
            lu[sym.dest[p]] = v;
            let c = sym.dest_col[p];
            self.scale[c] = self.scale[c].max(v.abs());
        }
        for k in 0..n {
            let rows = &sym.l_rows[sym.l_ptr[k]..sym.l_ptr[k + 1]];
            let (left, right) = lu.split_at_mut((k + 1) * n);
            let col = &mut left[k * n..];
            let d = col[k].abs();
            if d <= 1e-14 * self.scale[k] || d == 0.0 || rows.iter().any(|&i| col[i].abs() >= d) {
                return Ok(false);
            }
            let d = col[k];
            for &i in rows {
                col[i] /= d;
            }
            let l = &left[k * n..];
            // Column j > k starts at (j − k − 1)·n in `right`.
            for &j in &sym.u_cols[sym.u_ptr[k]..sym.u_ptr[k + 1]] {
                let c = &mut right[(j - k - 1) * n..(j - k) * n];
                let u = c[k];
                for &i in rows {
                    c[i] -= l[i] * u;
                }
            }
        }
        Ok(true)
    }
}

impl LinearSolver for StaticLu {
    fn factor(&mut self, a: &CscMatrix) -> Result<(), SolverError> {
        let key = (a.pattern_id, a.n, a.row_idx.len());
        if self.sym.as_ref().is_none_or(|s| s.order.pattern != key) {
            // A new pattern: no exchanges to replay yet (the identity, checked as any other).
            let order = FillOrder::of(a)?;
            self.sym = Some(Symbolic::of(a, order, (0..a.n).collect()));
            self.stats.symbolic_analyses += 1;
            self.lu.clear();
            self.lu.resize(a.n * a.n, 0.0);
        }
        self.fell_back = false;
        if !self.eliminate(a)? {
            self.fallback.factor(a)?;
            self.fell_back = true;
            self.fallbacks += 1;
            let sym = self.sym.take().expect("symbolic analysis");
            let q = self.fallback.row_perm();
            self.sym = Some(if q == sym.q {
                sym
            } else {
                Symbolic::of(a, sym.order, q.to_vec())
            });
        }
        self.stats.numeric_factorizations += 1;
        Ok(())
    }

    fn solve_in_place(&mut self, b: &mut [f64]) -> Result<(), SolverError> {
        if self.fell_back {
            self.stats.solves += 1;
            return self.fallback.solve_in_place(b);
        }
        let Some(sym) = &self.sym else {
            return Err(SolverError::Failed("solve before factor".into()));
        };
        let n = sym.q.len();
        if b.len() != n {
            return Err(SolverError::Failed(format!(
                "right-hand side has {} entries, the matrix {n} equations",
                b.len()
            )));
        }
        let (lu, x) = (&self.lu, &mut self.work);
        x.clear();
        x.extend(sym.q.iter().map(|&r| b[sym.order.old[r]]));
        // L·y = Q·P·b, then U·z = y, both by columns, a column skipped where the unknown it
        // carries is zero: the dense LU's substitutions, in its order.
        for k in 0..n {
            let xk = x[k];
            if xk != 0.0 {
                for &i in &sym.l_rows[sym.l_ptr[k]..sym.l_ptr[k + 1]] {
                    x[i] -= lu[k * n + i] * xk;
                }
            }
        }
        for j in (0..n).rev() {
            x[j] /= lu[j * n + j];
            let xj = x[j];
            if xj != 0.0 {
                for &i in &sym.ut_rows[sym.ut_ptr[j]..sym.ut_ptr[j + 1]] {
                    x[i] -= lu[j * n + i] * xj;
                }
            }
        }
        for (k, &xk) in x.iter().enumerate() {
            b[sym.order.old[k]] = xk;
        }
        self.stats.solves += 1;
        Ok(())
    }

    fn stats(&self) -> SolverStats {
        self.stats
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// [`crate::dense::tests::sparse_unsymmetric`] (40 % of the entries, values in
    /// `[-0.5, 0.5)`, the diagonal scaled by 1e-3 so that the elimination must exchange rows)
    /// with its diagonal entries `d` replaced by `scale·d + shift` (`shift` large: diagonally
    /// dominant).
    fn sparse_unsymmetric(n: usize, seed: u64, scale: f64, shift: f64) -> CscMatrix {
        let mut a = crate::dense::tests::sparse_unsymmetric(n, seed);
        for j in 0..n {
            for p in a.col_ptr[j]..a.col_ptr[j + 1] {
                if a.row_idx[p] == j {
                    a.values[p] = scale * a.values[p] + shift;
                }
            }
        }
        a
    }

    fn solve(s: &mut dyn LinearSolver, a: &CscMatrix, b: &[f64]) -> Vec<f64> {
        s.factor(a).unwrap();
        let mut x = b.to_vec();
        s.solve_in_place(&mut x).unwrap();
        x
    }

    /// Replaying the exchanges gives the pivoting LU's solution to the bit; the first
    /// factorization of a pattern (nothing to replay, rows must be exchanged) falls back, the
    /// next ones of nearby values replay; against the known solution the error is round-off.
    #[test]
    fn replay_equals_the_pivoting_lu_bitwise() {
        for (n, seed, scale) in [(41, 7u64, 1.0), (66, 99, 1.0), (66, 12345, 300.0)] {
            let mut s = StaticLu::new();
            let mut dense = DenseLu::fill_reducing();
            let a0 = sparse_unsymmetric(n, seed, scale, 0.0);
            let x: Vec<f64> = (0..n)
                .map(|i| 1.0 + (i % 7) as f64 - 0.3 * i as f64)
                .collect();
            for step in 0..5 {
                // Newton-like: the same pattern, values perturbed by 1e-6 relative.
                let mut a = a0.clone();
                for (p, v) in a.values.iter_mut().enumerate() {
                    *v *= 1.0 + 1e-6 * (step as f64) * ((p % 5) as f64 - 2.0);
                }
                let mut b = vec![0.0; n];
                a.mul_vec(&x, &mut b);
                let xs = solve(&mut s, &a, &b);
                let xd = solve(&mut dense, &a, &b);
                for i in 0..n {
                    assert_eq!(
                        xs[i].to_bits(),
                        xd[i].to_bits(),
                        "{n}/{seed} step {step} [{i}]"
                    );
                }
                let scale = x.iter().fold(0.0f64, |m, v| m.max(v.abs()));
                for i in 0..n {
                    assert!((xs[i] - x[i]).abs() < 1e-9 * scale, "{n}/{seed} x[{i}]");
                }
            }
            assert_eq!(s.stats().numeric_factorizations, 5);
            assert_eq!(s.stats().solves, 5);
            assert_eq!(s.stats().symbolic_analyses, 1);
            // Rows exchanged at the first factorization, replayed at the next four.
            assert_eq!(s.fallbacks(), 1, "{n}/{seed}");
        }
    }

    /// Diagonally dominant (condition number ≈ 1): replayed from the first factorization on
    /// (no exchanges), solution to 1e-12 relative.
    #[test]
    fn diagonally_dominant_needs_no_fallback() {
        let n = 66;
        // Off-diagonal column sums ≤ 0.5·n against a diagonal of 2n.
        let a = sparse_unsymmetric(n, 4242, 1.0, 2.0 * n as f64);
        let x: Vec<f64> = (0..n).map(|i| (i as f64 * 0.37).sin() + 2.0).collect();
        let mut b = vec![0.0; n];
        a.mul_vec(&x, &mut b);
        let mut s = StaticLu::new();
        let xs = solve(&mut s, &a, &b);
        assert_eq!(s.fallbacks(), 0);
        for i in 0..n {
            assert!((xs[i] - x[i]).abs() <= 1e-12 * x[i].abs(), "x[{i}]");
        }
    }

    /// A zero pivot in the replayed order (a matrix that needed no exchange, then one with a
    /// zero diagonal) falls back to the pivoting LU, which solves it; the next factorization
    /// of that matrix replays the new exchange.
    #[test]
    fn zero_pivot_falls_back() {
        let a1 = CscMatrix::from_triplets(2, &[(0, 0, 4.0), (1, 0, 1.0), (0, 1, 2.0), (1, 1, 3.0)]);
        // The same pattern (CSC order: a00, a10, a01, a11), the diagonal zeroed.
        let mut a2 = a1.clone();
        a2.values = vec![0.0, 1.0, 2.0, 0.0];
        let x = [1.0, -2.0];
        let mut s = StaticLu::new();
        let mut b = vec![0.0; 2];
        for (a, fallbacks) in [(&a1, 0), (&a2, 1), (&a2, 1)] {
            a.mul_vec(&x, &mut b);
            let xs = solve(&mut s, a, &b);
            assert_eq!(s.fallbacks(), fallbacks);
            for i in 0..2 {
                assert!((xs[i] - x[i]).abs() <= 1e-15 * 2.0, "{xs:?}");
            }
        }
        assert_eq!(s.stats().symbolic_analyses, 1);
    }

    /// A singular matrix is reported as the pivoting LU reports it, and a non-finite entry as
    /// a failure; a solve before any factorization fails.
    #[test]
    fn singular_and_bad_input() {
        let mut s = StaticLu::new();
        let mut b = vec![1.0; 3];
        assert!(matches!(
            s.solve_in_place(&mut b),
            Err(SolverError::Failed(_))
        ));
        let z = CscMatrix::from_triplets(3, &[(0, 0, 1.0), (1, 1, 2.0), (2, 1, 1.0)]);
        let mut dense = DenseLu::fill_reducing();
        let expected = dense.factor(&z).unwrap_err();
        assert!(matches!(expected, SolverError::Singular { .. }));
        assert_eq!(s.factor(&z), Err(expected));
        let mut nan = CscMatrix::from_triplets(2, &[(0, 0, 1.0), (1, 1, 2.0)]);
        nan.values[1] = f64::NAN;
        assert!(matches!(s.factor(&nan), Err(SolverError::Failed(_))));
    }
}

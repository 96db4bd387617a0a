//! A dense LU solver for small systems (a vehicle on a rigid track has a few dozen
//! unknowns, where a dense factorization beats any sparse one).
//!
//! Partial pivoting; a pivot smaller than `1e-14` times the largest entry of its column is
//! reported as singular at that equation.
//!
//! **Fill-reducing order** ([`DenseLu::fill_reducing`]): the equations are first renumbered
//! symmetrically by the approximate minimum degree order of the pattern of `A + Aᵀ` (faer's
//! AMD, computed once per pattern), `A' = P·A·Pᵀ`, and `A'` is factored with the same
//! partial-pivoting elimination. The elimination skips every update whose multiplier or
//! pivot-row entry is zero, so in a good order most of the dense matrix is never touched:
//! an unsymmetric tangent of a few dozen equations (the curve case's vehicle with creep
//! forces, 66) factors several times faster than the sparse LU, whose per-column pivoting
//! search dominates at that size. The plain order ([`DenseLu::default`]) is unchanged to the
//! bit.

use crate::linear::{LinearSolver, SolverError, SolverStats};
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::amd;
use faer::sparse::SymbolicSparseColMatRef;
use nalgebra::DMatrix;
use railfem_framework::sparse::CscMatrix;

/// Dense LU with partial pivoting, refactored in place.
#[derive(Debug, Default)]
pub struct DenseLu {
    lu: DMatrix<f64>,
    perm: Vec<usize>,
    stats: SolverStats,
    /// Whether the equations are renumbered by a fill-reducing order first.
    reorder: bool,
    /// The symmetric renumbering of the last pattern, when `reorder`.
    order: Option<FillOrder>,
    /// Rows with a nonzero multiplier in the current pivot column (scratch).
    rows: Vec<usize>,
    /// The permuted right-hand side of a reordered solve (scratch).
    work: Vec<f64>,
}

/// A symmetric renumbering of one sparsity pattern: `A'[k][l] = A[old[k]][old[l]]`.
#[derive(Debug)]
pub(crate) struct FillOrder {
    /// `(pattern_id, n, nnz)` of the pattern it was computed for.
    pub(crate) pattern: (u64, usize, usize),
    /// Old equation at each new position.
    pub(crate) old: Vec<usize>,
    /// New position of each old equation.
    pub(crate) new: Vec<usize>,
}

impl FillOrder {
    /// The approximate minimum degree order of `A + Aᵀ` (faer's AMD).
    pub(crate) fn of(a: &CscMatrix) -> Result<FillOrder, SolverError> {
        let n = a.n;
        let fail = |e| SolverError::Failed(format!("fill-reducing order: {e:?}"));
        let sym = SymbolicSparseColMatRef::new_checked(n, n, &a.col_ptr, None, &a.row_idx);
        let mut mem = MemBuffer::try_new(amd::order_maybe_unsorted_scratch::<usize>(
            n,
            a.row_idx.len(),
        ))
        .map_err(|_| SolverError::Failed("out of memory for the fill-reducing order".into()))?;
        let (mut old, mut new) = (vec![0usize; n], vec![0usize; n]);
        amd::order_maybe_unsorted(
            &mut old,
            &mut new,
            sym,
            amd::Control::default(),
            MemStack::new(&mut mem),
        )
        .map_err(fail)?;
        Ok(FillOrder {
            pattern: (a.pattern_id, n, a.row_idx.len()),
            old,
            new,
        })
    }
}

impl DenseLu {
    /// A dense LU that renumbers the equations by a fill-reducing order first (module
    /// documentation): for small unsymmetric systems.
    pub fn fill_reducing() -> DenseLu {
        DenseLu {
            reorder: true,
            ..Default::default()
        }
    }

    /// The row exchanges of the last factorization: position `k` of the factor holds row
    /// `perm[k]` (in the fill-reducing numbering when reordered).
    pub(crate) fn row_perm(&self) -> &[usize] {
        &self.perm
    }

    /// The order for `a`'s pattern (recomputed when the pattern changed), `None` without
    /// reordering.
    fn ensure_order(&mut self, a: &CscMatrix) -> Result<(), SolverError> {
        let key = (a.pattern_id, a.n, a.row_idx.len());
        if self.reorder && self.order.as_ref().is_none_or(|o| o.pattern != key) {
            self.order = Some(FillOrder::of(a)?);
            self.stats.symbolic_analyses += 1;
        }
        Ok(())
    }
}

impl LinearSolver for DenseLu {
    fn factor(&mut self, a: &CscMatrix) -> Result<(), SolverError> {
        let n = a.n;
        if self.lu.nrows() != n {
            self.lu = DMatrix::zeros(n, n);
            // With reordering, the analyses counted are the orders computed.
            if !self.reorder {
                self.stats.symbolic_analyses += 1;
            }
        } else {
            self.lu.fill(0.0);
        }
        self.ensure_order(a)?;
        let new_of = self.order.as_ref().map(|o| o.new.as_slice());
        let at = |i: usize| new_of.map_or(i, |m| m[i]);
        let mut scale = vec![0.0f64; n];
        for j in 0..n {
            for p in a.col_ptr[j]..a.col_ptr[j + 1] {
                let v = a.values[p];
                if !v.is_finite() {
                    return Err(SolverError::Failed(format!(
                        "matrix entry ({}, {j}) is not finite",
                        a.row_idx[p]
                    )));
                }
                self.lu[(at(a.row_idx[p]), at(j))] = v;
                scale[at(j)] = scale[at(j)].max(v.abs());
            }
        }
        self.perm = (0..n).collect();
        let lu = &mut self.lu;
        let sparse = self.reorder;
        for k in 0..n {
            // Reordered, most of column k is zero: its nonzero rows are listed first and the
            // pivot search, the division and the update visit only them (a zero is never a
            // larger pivot, so the pivot is the same). The plain order keeps its loops, and
            // with them the sign of every zero multiplier, bit for bit.
            self.rows.clear();
            if sparse {
                let col = &lu.as_slice()[k * n..(k + 1) * n];
                self.rows.extend((k + 1..n).filter(|&i| col[i] != 0.0));
            }
            let (mut piv, mut best) = (k, lu[(k, k)].abs());
            let below: &mut dyn Iterator<Item = usize> = if sparse {
                &mut self.rows.iter().copied()
            } else {
                &mut (k + 1..n)
            };
            for i in below {
                if lu[(i, k)].abs() > best {
                    best = lu[(i, k)].abs();
                    piv = i;
                }
            }
            if best <= 1e-14 * scale[k] || best == 0.0 {
                return Err(SolverError::Singular { equation: k });
            }
            if piv != k {
                lu.swap_rows(piv, k);
                self.perm.swap(piv, k);
                // Row `piv` of column k is now the old diagonal entry.
                if sparse {
                    self.rows.retain(|&i| i != piv);
                    if lu[(piv, k)] != 0.0 {
                        let at = self.rows.partition_point(|&i| i < piv);
                        self.rows.insert(at, piv);
                    }
                }
            }
            // Column-major storage: the multipliers fill column k below the pivot, then each
            // later column j is updated along its contiguous part, `a_ij −= l_ik·u_kj`.
            // Every entry sees the same operations in the same order of k as a row-by-row
            // elimination would give it, so the factor is the same to the bit.
            let a = lu.as_mut_slice();
            let d = a[k * n + k];
            if sparse {
                for &i in &self.rows {
                    a[k * n + i] /= d;
                }
            } else {
                for x in &mut a[k * n + k + 1..(k + 1) * n] {
                    *x /= d;
                }
            }
            let (left, right) = a.split_at_mut((k + 1) * n);
            let l = &left[k * n..(k + 1) * n];
            // Only the rows with a nonzero multiplier are updated (the same entries, in the
            // same order, as testing each multiplier in the column loop).
            if !sparse {
                self.rows.extend((k + 1..n).filter(|&i| l[i] != 0.0));
            } else {
                // A multiplier can underflow to zero in the division.
                self.rows.retain(|&i| l[i] != 0.0);
            }
            for col in right.chunks_exact_mut(n) {
                let u = col[k];
                if u == 0.0 {
                    continue;
                }
                for &i in &self.rows {
                    col[i] -= l[i] * u;
                }
            }
        }
        self.stats.numeric_factorizations += 1;
        Ok(())
    }

    fn solve_in_place(&mut self, b: &mut [f64]) -> Result<(), SolverError> {
        let n = self.lu.nrows();
        let Some(order) = &self.order else {
            let mut x: Vec<f64> = self.perm.iter().map(|&p| b[p]).collect();
            for i in 0..n {
                let mut s = x[i];
                for j in 0..i {
                    s -= self.lu[(i, j)] * x[j];
                }
                x[i] = s;
            }
            for i in (0..n).rev() {
                let mut s = x[i];
                for j in i + 1..n {
                    s -= self.lu[(i, j)] * x[j];
                }
                x[i] = s / self.lu[(i, i)];
            }
            b.copy_from_slice(&x);
            self.stats.solves += 1;
            return Ok(());
        };
        // Reordered: the substitutions by columns (contiguous in the column-major factor),
        // a column skipped where the unknown it carries is zero.
        let x = &mut self.work;
        x.clear();
        x.extend(self.perm.iter().map(|&p| b[order.old[p]]));
        let a = self.lu.as_slice();
        for j in 0..n {
            let xj = x[j];
            if xj != 0.0 {
                for (xi, &l) in x[j + 1..].iter_mut().zip(&a[j * n + j + 1..(j + 1) * n]) {
                    *xi -= l * xj;
                }
            }
        }
        for j in (0..n).rev() {
            x[j] /= a[j * n + j];
            let xj = x[j];
            if xj != 0.0 {
                for (xi, &u) in x[..j].iter_mut().zip(&a[j * n..j * n + j]) {
                    *xi -= u * xj;
                }
            }
        }
        for (k, &xk) in x.iter().enumerate() {
            b[order.old[k]] = xk;
        }
        self.stats.solves += 1;
        Ok(())
    }

    fn stats(&self) -> SolverStats {
        self.stats
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// The column-oriented elimination gives the row-by-row one's factor to the bit (the
    /// same operations on every entry, in the same order of pivots): a 37 × 37 matrix with
    /// zeros, pivoting forced by a small leading diagonal.
    #[test]
    fn factor_equals_row_by_row_elimination_bitwise() {
        let n = 37;
        let mut t = Vec::new();
        let mut seed = 12345u64;
        for j in 0..n {
            for i in 0..n {
                seed ^= seed << 13;
                seed ^= seed >> 7;
                seed ^= seed << 17;
                if seed % 3 != 0 || i == j {
                    let v = (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5;
                    t.push((i, j, if i == j { v * 1e-3 } else { v }));
                }
            }
        }
        let a = CscMatrix::from_triplets(n, &t);
        let mut s = DenseLu::default();
        s.factor(&a).unwrap();
        // Reference: row by row, as the kernel was first written.
        let mut lu = DMatrix::from_fn(n, n, |i, j| a.get(i, j));
        let mut perm: Vec<usize> = (0..n).collect();
        for k in 0..n {
            let (mut piv, mut best) = (k, lu[(k, k)].abs());
            for i in k + 1..n {
                if lu[(i, k)].abs() > best {
                    best = lu[(i, k)].abs();
                    piv = i;
                }
            }
            lu.swap_rows(piv, k);
            perm.swap(piv, k);
            let d = lu[(k, k)];
            for i in k + 1..n {
                let f = lu[(i, k)] / d;
                lu[(i, k)] = f;
                for j in k + 1..n {
                    lu[(i, j)] -= f * lu[(k, j)];
                }
            }
        }
        assert_eq!(s.perm, perm);
        for (x, y) in s.lu.iter().zip(lu.iter()) {
            assert_eq!(x.to_bits(), y.to_bits());
        }
    }

    /// A sparse unsymmetric `n × n` matrix (about a third of the entries, a small leading
    /// diagonal so that the elimination must pivot), pseudo-random from `seed`.
    pub(crate) fn sparse_unsymmetric(n: usize, mut seed: u64) -> CscMatrix {
        let mut t = Vec::new();
        for j in 0..n {
            for i in 0..n {
                seed ^= seed << 13;
                seed ^= seed >> 7;
                seed ^= seed << 17;
                if seed % 5 < 2 || i == j {
                    let v = (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5;
                    t.push((i, j, if i == j { v * 1e-3 } else { v }));
                }
            }
        }
        CscMatrix::from_triplets(n, &t)
    }

    /// The fill-reducing order solves what the plain order solves (to round-off: another
    /// order of elimination), with a pattern change in between (the order is recomputed).
    #[test]
    fn fill_reducing_order_solves_as_the_plain_order() {
        let mut ordered = DenseLu::fill_reducing();
        for (n, seed) in [(41, 7u64), (66, 99), (66, 12345)] {
            let a = sparse_unsymmetric(n, seed);
            let x: Vec<f64> = (0..n)
                .map(|i| 1.0 + (i % 7) as f64 - 0.3 * i as f64)
                .collect();
            let mut b = vec![0.0; n];
            a.mul_vec(&x, &mut b);
            let mut plain = DenseLu::default();
            plain.factor(&a).unwrap();
            ordered.factor(&a).unwrap();
            let (mut xp, mut xo) = (b.clone(), b.clone());
            plain.solve_in_place(&mut xp).unwrap();
            ordered.solve_in_place(&mut xo).unwrap();
            let scale = x.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            for i in 0..n {
                assert!((xo[i] - x[i]).abs() < 1e-9 * scale, "{n}/{seed} x[{i}]");
                assert!(
                    (xo[i] - xp[i]).abs() < 1e-9 * scale,
                    "{n}/{seed} vs plain [{i}]"
                );
            }
            // The order is a permutation, and not the identity (it reorders).
            let o = ordered.order.as_ref().unwrap();
            let mut seen = o.old.clone();
            seen.sort_unstable();
            assert_eq!(seen, (0..n).collect::<Vec<_>>());
            assert!(o.old.iter().enumerate().any(|(k, &i)| k != i));
            assert!(o.old.iter().enumerate().all(|(k, &i)| o.new[i] == k));
        }
        // Three patterns: three orders.
        assert_eq!(ordered.stats().symbolic_analyses, 3);
        assert_eq!(ordered.stats().numeric_factorizations, 3);
    }

    #[test]
    fn fill_reducing_order_reports_singular() {
        let z = CscMatrix::from_triplets(3, &[(0, 0, 1.0), (1, 1, 2.0), (2, 1, 1.0)]);
        let mut s = DenseLu::fill_reducing();
        assert!(matches!(s.factor(&z), Err(SolverError::Singular { .. })));
    }

    #[test]
    fn solves_and_reports_singular() {
        let a = CscMatrix::from_triplets(
            3,
            &[
                (0, 0, 4.0),
                (1, 0, 1.0),
                (0, 1, 2.0),
                (1, 1, 3.0),
                (2, 2, 5.0),
                (2, 0, 1.0),
            ],
        );
        let mut s = DenseLu::default();
        s.factor(&a).unwrap();
        let x = [1.0, -2.0, 0.5];
        let mut b = vec![0.0; 3];
        a.mul_vec(&x, &mut b);
        s.solve_in_place(&mut b).unwrap();
        for (u, v) in b.iter().zip(x) {
            assert!((u - v).abs() < 1e-14);
        }
        let z = CscMatrix::from_triplets(2, &[(0, 0, 1.0)]);
        assert_eq!(s.factor(&z), Err(SolverError::Singular { equation: 1 }));
    }
}

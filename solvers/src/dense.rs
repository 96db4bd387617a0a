//! A dense LU solver for small systems (a vehicle on a rigid track has a few dozen
//! unknowns, where a dense factorization beats any sparse one).
//!
//! Partial pivoting; a pivot smaller than `1e-14` times the largest entry of its column is
//! reported as singular at that equation.

use crate::linear::{LinearSolver, SolverError, SolverStats};
use nalgebra::DMatrix;
use railfem_framework::sparse::CscMatrix;

/// Dense LU with partial pivoting, refactored in place.
#[derive(Debug, Default)]
pub struct DenseLu {
    lu: DMatrix<f64>,
    perm: Vec<usize>,
    stats: SolverStats,
}

impl LinearSolver for DenseLu {
    fn factor(&mut self, a: &CscMatrix) -> Result<(), SolverError> {
        let n = a.n;
        if self.lu.nrows() != n {
            self.lu = DMatrix::zeros(n, n);
            self.stats.symbolic_analyses += 1;
        } else {
            self.lu.fill(0.0);
        }
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
                self.lu[(a.row_idx[p], j)] = v;
                scale[j] = scale[j].max(v.abs());
            }
        }
        self.perm = (0..n).collect();
        let lu = &mut self.lu;
        for k in 0..n {
            let (mut piv, mut best) = (k, lu[(k, k)].abs());
            for i in k + 1..n {
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
            }
            // Column-major storage: the multipliers fill column k below the pivot, then each
            // later column j is updated along its contiguous part, `a_ij −= l_ik·u_kj`.
            // Every entry sees the same operations in the same order of k as a row-by-row
            // elimination would give it, so the factor is the same to the bit.
            let a = lu.as_mut_slice();
            let d = a[k * n + k];
            for x in &mut a[k * n + k + 1..(k + 1) * n] {
                *x /= d;
            }
            let (left, right) = a.split_at_mut((k + 1) * n);
            let l = &left[k * n + k + 1..(k + 1) * n];
            for col in right.chunks_exact_mut(n) {
                let u = col[k];
                if u == 0.0 {
                    continue;
                }
                for (x, &f) in col[k + 1..].iter_mut().zip(l) {
                    if f != 0.0 {
                        *x -= f * u;
                    }
                }
            }
        }
        self.stats.numeric_factorizations += 1;
        Ok(())
    }

    fn solve_in_place(&mut self, b: &mut [f64]) -> Result<(), SolverError> {
        let n = self.lu.nrows();
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
        Ok(())
    }

    fn stats(&self) -> SolverStats {
        self.stats
    }
}

#[cfg(test)]
mod tests {
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

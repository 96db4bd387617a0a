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
            let d = lu[(k, k)];
            for i in k + 1..n {
                let f = lu[(i, k)] / d;
                if f == 0.0 {
                    continue;
                }
                lu[(i, k)] = f;
                for j in k + 1..n {
                    let u = lu[(k, j)];
                    if u != 0.0 {
                        lu[(i, j)] -= f * u;
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

//! The low-rank solver: the constant structure factored once per `Δt`, the few equations
//! of the moving and nonlinear elements handled by a bordered (Woodbury) solve.
//!
//! Write the effective tangent as `K = A + V` (as in [`crate::partition`]): `A = c_K·K +
//! c_M·M + c_C·C` of the constant elements, which changes only with the integrator's
//! coefficients, and `V` the variable elements' part, non-zero only on a small set `S` of
//! `s` equations (a sprung mass on a beam: its own `z` and the `uz`, `θy` of the two beam
//! nodes under it). With `P` the `n × s` selection of `S` and `E = Pᵀ·V·P` (`s × s`, dense),
//! `K = A + P·E·Pᵀ`. For `K·x = b` let `y = A⁻¹·b` and `W = A⁻¹·P` (`s` solves with `A`'s
//! factor), `W_S = Pᵀ·W`. Try `x = y − W·w`: then
//!
//! ```text
//! K·x = b − P·w + P·E·(y_S − W_S·w) = b + P·(E·y_S − (I + E·W_S)·w),
//! ```
//!
//! which is `b` exactly when the `s × s` *capacitance* system `(I + E·W_S)·w = E·y_S` holds.
//! This is the Sherman–Morrison–Woodbury identity written without `E⁻¹`, so `E` may be
//! singular (a rank-one spring) or unsymmetric (a dashpot moving at speed `v`); the
//! capacitance is factored densely with pivoting. `I + E·W_S` is singular exactly when `K`
//! is (`det K = det A · det(I + E·W_S)`), so a breakdown there is the model's.
//!
//! Costs: `A` is factored once per set of coefficients (a constant `Δt`: once per run). A
//! Newton iteration refreshes `E` and factors the `s × s` capacitance (`O(s³)`); a solve is
//! one pair of triangular solves plus `O(n·s)`. A column `A⁻¹·e_j` is kept while `j` stays
//! in `S`: an element moving onto new nodes costs a few triangular solves, never a
//! factorization, and never a new sparsity pattern (the assembler keeps variable elements
//! off the global pattern).
//!
//! Equations that only variable elements stiffen (the sprung mass's own DOF) have no
//! diagonal in `A`, which is then singular. Each such equation `j` gets a shift `d_j > 0`
//! in `A` (`A' = A + D`) and `−d_j` in `E` (`E' = E − D_S`), so that `A' + P·E'·Pᵀ = K`
//! still holds exactly; `d_j` is the variable part's diagonal at the first factorization
//! (the mass and spring of the sprung mass at that `Δt`), or `A`'s largest diagonal if
//! that is not positive.

use crate::linear::{LinearSolver, SolverError, SparseCholesky, SparseLu};
use nalgebra::DMatrix;
use railfem_framework::sparse::CscMatrix;
use std::collections::HashMap;

/// Work counters of the low-rank solver.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct LowRankStats {
    /// Numeric factorizations of the constant part `A` (sparse).
    pub base_factorizations: usize,
    /// Capacitance factorizations (`s × s`, dense): one per [`LowRank::factor`] call.
    pub capacitance_factorizations: usize,
    /// Columns `A⁻¹·e_j` computed (triangular solve pairs).
    pub column_solves: usize,
    /// Right-hand sides solved.
    pub solves: usize,
    /// Equations of the low-rank part at the last factorization (`s`).
    pub rank: usize,
}

/// The low-rank solver (see the module documentation).
pub struct LowRank {
    base: Box<dyn LinearSolver>,
    n: usize,
    pattern_id: u64,
    /// Coefficients `A` was factored for.
    key: Option<[f64; 3]>,
    /// After [`LowRank::analyse`]: whether its solver (Cholesky if `true`) still awaits the
    /// first factorization's check against the values (module documentation).
    unchecked: Option<bool>,
    /// Diagonal shifts `(equation, d_j)` added to `A`.
    shift: Vec<(usize, f64)>,
    /// The set `S` and each equation's place in it.
    set: Vec<usize>,
    /// `E' = Pᵀ·V·P − D_S`, `s × s`.
    e: DMatrix<f64>,
    /// `A'⁻¹·e_j` for `j` in `S` (and still kept from the previous set).
    columns: HashMap<usize, Vec<f64>>,
    /// LU of the capacitance `I + E'·W_S`.
    capacitance: Option<nalgebra::LU<f64, nalgebra::Dyn, nalgebra::Dyn>>,
    stats: LowRankStats,
}

impl Default for LowRank {
    fn default() -> Self {
        LowRank::new()
    }
}

impl LowRank {
    /// A solver whose constant part is factored by sparse Cholesky when symmetric (LU
    /// otherwise).
    pub fn new() -> LowRank {
        LowRank {
            base: Box::new(SparseCholesky::new()),
            n: 0,
            pattern_id: 0,
            key: None,
            unchecked: None,
            shift: Vec::new(),
            set: Vec::new(),
            e: DMatrix::zeros(0, 0),
            columns: HashMap::new(),
            capacitance: None,
            stats: LowRankStats::default(),
        }
    }

    /// Work counters.
    pub fn stats(&self) -> LowRankStats {
        self.stats
    }

    /// Work counters of the sparse solver of the constant part.
    pub fn base_stats(&self) -> crate::linear::SolverStats {
        self.base.stats()
    }

    /// The symbolic analysis of the constant part's pattern `pattern` (values unread):
    /// sparse Cholesky's if `symmetric`, else LU's, once per pattern; a factorization on
    /// it then factors numerically only. The first factorization checks the guess against
    /// the values (`A` exactly symmetric or not, the rule of a factorization without an
    /// analysis) and analyses again with the other solver if it was wrong.
    pub fn analyse(&mut self, pattern: &CscMatrix, symmetric: bool) -> Result<(), SolverError> {
        if pattern.n == self.n && pattern.pattern_id == self.pattern_id {
            return Ok(());
        }
        self.base = base_solver(symmetric);
        self.n = pattern.n;
        self.pattern_id = pattern.pattern_id;
        self.key = None;
        self.columns.clear();
        self.unchecked = Some(symmetric);
        self.base.analyse(pattern)
    }

    /// Factors `a + V`, `V` given by `(row, column, value)` triplets (duplicates summed),
    /// `key` identifying `a`'s values: `a` is refactored only when `key` or its pattern
    /// changes (a `NaN` key always refactors).
    pub fn factor(
        &mut self,
        a: &CscMatrix,
        key: [f64; 3],
        variable: &[(usize, usize, f64)],
    ) -> Result<(), SolverError> {
        self.capacitance = None;
        let n = a.n;
        if let Some(&(i, j, _)) = variable.iter().find(|t| t.0 >= n || t.1 >= n) {
            return Err(SolverError::Failed(format!(
                "variable entry ({i}, {j}) outside the {n} equations"
            )));
        }
        if self.key != Some(key) || a.pattern_id != self.pattern_id || a.n != self.n {
            self.factor_base(a, variable)?;
            self.key = Some(key);
        }
        // The set S: every equation the variable part touches, and every shifted one.
        let mut entries: HashMap<(usize, usize), f64> = HashMap::with_capacity(variable.len());
        for &(i, j, v) in variable {
            *entries.entry((i, j)).or_insert(0.0) += v;
        }
        for &(j, d) in &self.shift {
            *entries.entry((j, j)).or_insert(0.0) -= d;
        }
        let mut set: Vec<usize> = entries
            .iter()
            .filter(|(_, v)| **v != 0.0)
            .flat_map(|(&(i, j), _)| [i, j])
            .collect();
        set.sort_unstable();
        set.dedup();
        let s = set.len();
        let place: HashMap<usize, usize> = set.iter().enumerate().map(|(k, &j)| (j, k)).collect();
        let mut e: DMatrix<f64> = DMatrix::zeros(s, s);
        for (&(i, j), &v) in &entries {
            if let (Some(&r), Some(&c)) = (place.get(&i), place.get(&j)) {
                e[(r, c)] += v;
            }
        }
        // Columns of A'⁻¹ for the new equations; those that left S are dropped.
        self.columns.retain(|j, _| place.contains_key(j));
        let missing: Vec<usize> = set
            .iter()
            .copied()
            .filter(|j| !self.columns.contains_key(j))
            .collect();
        if !missing.is_empty() {
            let mut rhs = vec![0.0; n * missing.len()];
            for (k, &j) in missing.iter().enumerate() {
                rhs[k * n + j] = 1.0;
            }
            self.base.solve_columns_in_place(&mut rhs, missing.len())?;
            for (k, &j) in missing.iter().enumerate() {
                self.columns.insert(j, rhs[k * n..(k + 1) * n].to_vec());
            }
            self.stats.column_solves += missing.len();
        }
        // Capacitance I + E'·W_S.
        let mut w_s: DMatrix<f64> = DMatrix::zeros(s, s);
        for (c, j) in set.iter().enumerate() {
            let col = &self.columns[j];
            for (r, &i) in set.iter().enumerate() {
                w_s[(r, c)] = col[i];
            }
        }
        let cap: DMatrix<f64> = DMatrix::identity(s, s) + &e * w_s;
        let lu = cap.lu();
        if s > 0 {
            // A zero pivot of the capacitance is a singular K: name an equation of S.
            let u = lu.u();
            let big = u.diagonal().iter().fold(0.0f64, |m, x| m.max(x.abs()));
            if let Some(k) = (0..s).find(|&k| u[(k, k)].abs() <= 1e-14 * big.max(1.0)) {
                return Err(SolverError::Singular { equation: set[k] });
            }
        }
        self.capacitance = Some(lu);
        self.e = e;
        self.set = set;
        self.stats.capacitance_factorizations += 1;
        self.stats.rank = s;
        Ok(())
    }

    /// Factors `A' = a + D`, choosing the shifts `D` (see the module documentation).
    fn factor_base(
        &mut self,
        a: &CscMatrix,
        variable: &[(usize, usize, f64)],
    ) -> Result<(), SolverError> {
        if a.n != self.n || a.pattern_id != self.pattern_id {
            self.base = base_solver(a.asymmetry() == 0.0);
            self.n = a.n;
            self.pattern_id = a.pattern_id;
        } else if let Some(guess) = self.unchecked {
            let symmetric = a.asymmetry() == 0.0;
            if symmetric != guess {
                self.base = base_solver(symmetric);
            }
        }
        self.unchecked = None;
        self.columns.clear();
        let n = a.n;
        let mut diag = vec![0.0; n];
        for j in 0..n {
            diag[j] = a.get(j, j);
        }
        let largest = diag.iter().fold(0.0f64, |m, d| m.max(d.abs()));
        let mut var_diag: HashMap<usize, f64> = HashMap::new();
        for &(i, j, v) in variable {
            if i == j {
                *var_diag.entry(j).or_insert(0.0) += v;
            }
        }
        self.shift.clear();
        for (j, &d) in diag.iter().enumerate() {
            if d == 0.0 {
                let v = var_diag.get(&j).copied().unwrap_or(0.0);
                let shift = if v > 0.0 { v } else { largest.max(1.0) };
                self.shift.push((j, shift));
            }
        }
        let mut shifted = a.clone();
        for &(j, d) in &self.shift {
            let p = shifted
                .position(j, j)
                .expect("every diagonal is in the pattern");
            shifted.values[p] += d;
        }
        self.base.factor(&shifted)?;
        self.stats.base_factorizations += 1;
        Ok(())
    }

    /// Solves `(A + V)·x = b` in place with the last factorization.
    pub fn solve_in_place(&mut self, b: &mut [f64]) -> Result<(), SolverError> {
        let Some(cap) = self.capacitance.as_ref() else {
            return Err(SolverError::Failed(
                "solve called without a valid factorization".into(),
            ));
        };
        if b.len() != self.n {
            return Err(SolverError::Failed(format!(
                "right-hand side has length {}, expected {}",
                b.len(),
                self.n
            )));
        }
        self.base.solve_in_place(b)?;
        self.stats.solves += 1;
        let s = self.set.len();
        if s == 0 {
            return Ok(());
        }
        let y_s = nalgebra::DVector::from_iterator(s, self.set.iter().map(|&i| b[i]));
        let rhs = &self.e * y_s;
        let w = cap.solve(&rhs).ok_or(SolverError::Singular {
            equation: self.set[0],
        })?;
        for (k, j) in self.set.iter().enumerate() {
            let wk = w[k];
            if wk == 0.0 {
                continue;
            }
            for (x, c) in b.iter_mut().zip(&self.columns[j]) {
                *x -= wk * c;
            }
        }
        Ok(())
    }
}

/// The sparse solver of a constant part `A`: Cholesky when it is symmetric, LU otherwise.
fn base_solver(symmetric: bool) -> Box<dyn LinearSolver> {
    if symmetric {
        Box::new(SparseCholesky::new())
    } else {
        Box::new(SparseLu::new())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 1-D chain (tridiagonal, SPD) of `n` equations plus one free equation `n` that
    /// only the variable part stiffens.
    fn chain(n: usize) -> CscMatrix {
        let mut t = Vec::new();
        for i in 0..n {
            t.push((i, i, 2.5));
            if i + 1 < n {
                t.push((i, i + 1, -1.0));
                t.push((i + 1, i, -1.0));
            }
        }
        t.push((n, n, 0.0));
        CscMatrix::from_triplets(n + 1, &t)
    }

    /// A rider on equation `n` coupled to chain equations `at`, `at + 1` by an unsymmetric
    /// spring–dashpot-like block (rank one plus a skew part).
    fn rider(n: usize, at: usize, k: f64, skew: f64) -> Vec<(usize, usize, f64)> {
        let g = [(n, 1.0), (at, -0.6), (at + 1, -0.4)];
        let mut t = Vec::new();
        for &(i, gi) in &g {
            for &(j, gj) in &g {
                t.push((i, j, k * gi * gj));
            }
        }
        t.push((at, n, skew));
        t.push((n, n, 3.0)); // a mass term
        t
    }

    fn dense_solve(a: &CscMatrix, v: &[(usize, usize, f64)], b: &[f64]) -> Vec<f64> {
        let n = a.n;
        let mut m = DMatrix::from_fn(n, n, |i, j| a.get(i, j));
        for &(i, j, x) in v {
            m[(i, j)] += x;
        }
        m.lu()
            .solve(&nalgebra::DVector::from_column_slice(b))
            .unwrap()
            .as_slice()
            .to_vec()
    }

    /// The Woodbury solve equals a dense LU of the whole `A + V` (condition number of the
    /// chain ≲ 10, so 1e-12 relative is many ulps of margin), while the rider moves along
    /// the chain: `A` is factored once and the columns are computed only for equations new
    /// to `S`.
    #[test]
    fn equals_dense_solve_while_moving() {
        let n = 40;
        let a = chain(n);
        let mut lr = LowRank::new();
        let b: Vec<f64> = (0..=n).map(|i| ((i * 7 % 11) as f64) - 5.0).collect();
        for (step, at) in [3usize, 3, 4, 5, 5, 20, 38].into_iter().enumerate() {
            let v = rider(n, at, 1e3, 0.5 * step as f64);
            lr.factor(&a, [1.0, 2.0, 3.0], &v).unwrap();
            let mut x = b.clone();
            lr.solve_in_place(&mut x).unwrap();
            let reference = dense_solve(&a, &v, &b);
            let scale = reference.iter().fold(0.0f64, |m, x| m.max(x.abs()));
            for (u, r) in x.iter().zip(&reference) {
                assert!((u - r).abs() <= 1e-12 * scale, "at {at}: {u} vs {r}");
            }
        }
        let st = lr.stats();
        assert_eq!(st.base_factorizations, 1);
        assert_eq!(st.capacitance_factorizations, 7);
        // S = {rider, at, at + 1}: 3 columns first, then 1 (at 4), 1 (at 5), 2 (at 20), 2 (at 38).
        assert_eq!(st.column_solves, 3 + 1 + 1 + 2 + 2);
        // A new key refactors A.
        lr.factor(&a, [1.0, 2.0, 4.0], &rider(n, 10, 1.0, 0.0))
            .unwrap();
        assert_eq!(lr.stats().base_factorizations, 2);
    }

    /// A singular whole matrix (the rider's equation with nothing on it) is reported at an
    /// equation of `S`, not answered.
    #[test]
    fn singular_whole_matrix_is_reported() {
        let n = 10;
        let a = chain(n);
        let mut lr = LowRank::new();
        // Variable part that cancels exactly: the rider's equation stays empty.
        let v = vec![(n, n, 1.0), (n, n, -1.0), (2, 2, 0.5)];
        assert!(matches!(
            lr.factor(&a, [1.0, 0.0, 0.0], &v),
            Err(SolverError::Singular { equation }) if equation == n
        ));
    }
}

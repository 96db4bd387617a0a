//! Modal analysis: the lowest natural circular frequencies ω (rad/s) and mode shapes φ of
//! the generalized eigenproblem `K φ = ω² M φ`.
//!
//! `K` (N/m, N·m/rad, …) must be symmetric positive definite (supports applied, no rigid
//! body motion) and is factored once with a [`LinearSolver`]; `M` (kg, kg·m²) must be
//! symmetric positive SEMI-definite — lumped masses with zero rotary inertia, or massless
//! internal DOFs, are fine: such DOFs carry no inertia and are statically condensed by the
//! iteration itself.
//!
//! # Method: subspace iteration with inverse iteration (shift σ = 0) and Rayleigh–Ritz
//!
//! With `q = min(max(2p, p + 8), m)` trial vectors for `p` wanted modes (`m` = number of DOFs
//! with positive mass), starting from `X₀ = K⁻¹ M R` with pseudo-random `R`:
//!
//! 1. **M-orthonormalize** `X` (classical Gram–Schmidt in the `M` inner product, applied
//!    twice, keeping `M X` updated alongside so no extra products are needed). Working with
//!    `Xᵀ M X = I` avoids the badly conditioned projected mass matrix that plain subspace
//!    iteration produces once the columns have been scaled by very different `1/λ`.
//! 2. **Rayleigh–Ritz**: `K̂ = Xᵀ K X` (q × q, symmetric), dense symmetric eigen-solve
//!    `K̂ = V Λ Vᵀ` (nalgebra `SymmetricEigen`), Ritz vectors `X ← X V` (still
//!    M-orthonormal) sorted by ascending Ritz value `λ = ω²`.
//! 3. **Convergence** when for every wanted mode `|λᵢ⁽ᵏ⁾ − λᵢ⁽ᵏ⁻¹⁾| ≤ tol · λᵢ⁽ᵏ⁾`.
//!    Eigenvalue `i` converges linearly with ratio `(λᵢ/λ_{q+1})²` per iteration, so the
//!    remaining error after the test passes is smaller than the last change.
//! 4. Otherwise **inverse iteration**: `X ← K⁻¹ (M X)` (one multi-RHS solve with the kept
//!    factorization) and repeat.
//!
//! Each returned shape is M-normalized (`φᵀ M φ = 1`, units m/√kg for translations) and
//! signed so that its largest-magnitude component is positive.
//!
//! Linear solvers themselves live in [`crate::linear`]; time integration lives elsewhere.

use crate::linear::{LinearSolver, SolverError, SparseCholesky};
use nalgebra::{DMatrix, SymmetricEigen};
use railfem_framework::sparse::CscMatrix;

/// Failure of a modal analysis.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ModalError {
    /// Factoring `K` or solving with it failed (for example `K` is singular: a mechanism or
    /// missing support).
    #[error("stiffness factorization: {0}")]
    Solver(#[from] SolverError),
    /// The request or the matrices are inconsistent (sizes, more modes than massive DOFs,
    /// non-symmetric or indefinite mass).
    #[error("invalid modal analysis input: {0}")]
    InvalidInput(String),
    /// A stop was asked for ([`railfem_framework::interrupt`]); the iteration stopped
    /// after `iterations` (no modes: an unsettled subspace is no result).
    #[error("interrupted after {iterations} subspace iterations")]
    Interrupted {
        /// Iterations completed.
        iterations: usize,
    },
    /// The wanted eigenvalues did not settle within the iteration limit.
    #[error("subspace iteration did not converge in {iterations} iterations (worst relative change of ω² {change:e})")]
    NotConverged {
        /// Iterations performed.
        iterations: usize,
        /// Largest relative change of a wanted ω² in the last iteration (dimensionless).
        change: f64,
    },
}

/// Settings of the subspace iteration.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ModalOptions {
    /// Relative tolerance on the change of each wanted ω² between iterations
    /// (dimensionless; default `1e-10`).
    pub tolerance: f64,
    /// Maximum number of inverse iterations (default 500).
    pub max_iterations: usize,
    /// Number of trial vectors `q`; `None` uses `max(2p, p + 8)` for `p` wanted modes,
    /// capped at the number of DOFs with positive mass.
    pub subspace_size: Option<usize>,
}

impl Default for ModalOptions {
    fn default() -> Self {
        ModalOptions {
            tolerance: 1e-10,
            max_iterations: 500,
            subspace_size: None,
        }
    }
}

/// Result of a modal analysis.
#[derive(Debug, Clone, PartialEq)]
pub struct Modes {
    /// Natural circular frequencies ω (rad/s), ascending.
    pub omega: Vec<f64>,
    /// Mode shapes, one column per frequency (`n_dof × n_modes`), M-orthonormal
    /// (`Φᵀ M Φ = I`; m/√kg for translational DOFs, rad/√(kg) for rotations).
    pub shapes: DMatrix<f64>,
    /// Relative residual `‖K φ − ω² M φ‖ / ‖K φ‖` of each mode (dimensionless).
    pub residuals: Vec<f64>,
    /// Number of inverse iterations performed.
    pub iterations: usize,
}

impl Modes {
    /// Natural frequencies f = ω / 2π (Hz), ascending.
    pub fn frequencies_hz(&self) -> Vec<f64> {
        self.omega
            .iter()
            .map(|w| w / (2.0 * std::f64::consts::PI))
            .collect()
    }
}

/// Lowest `n_modes` eigenpairs of `K φ = ω² M φ`, factoring `K` with a new
/// [`SparseCholesky`]. See the module documentation for the method.
pub fn lowest_modes(
    k: &CscMatrix,
    m: &CscMatrix,
    n_modes: usize,
    options: &ModalOptions,
) -> Result<Modes, ModalError> {
    let mut solver = SparseCholesky::new();
    lowest_modes_with(&mut solver, k, m, n_modes, options)
}

/// Lowest `n_modes` eigenpairs of `K φ = ω² M φ`, factoring `K` with the given `solver`
/// (re-using its symbolic analysis when `K`'s pattern is unchanged).
pub fn lowest_modes_with(
    solver: &mut dyn LinearSolver,
    k: &CscMatrix,
    m: &CscMatrix,
    n_modes: usize,
    options: &ModalOptions,
) -> Result<Modes, ModalError> {
    let nd = k.n;
    if m.n != nd {
        return Err(ModalError::InvalidInput(format!(
            "K is {nd}×{nd} but M is {0}×{0}",
            m.n
        )));
    }
    if n_modes == 0 {
        return Ok(Modes {
            omega: Vec::new(),
            shapes: DMatrix::zeros(nd, 0),
            residuals: Vec::new(),
            iterations: 0,
        });
    }
    let mut massive = 0;
    for i in 0..nd {
        let d = m.get(i, i);
        if d.is_nan() || d < 0.0 || d.is_infinite() {
            return Err(ModalError::InvalidInput(format!(
                "mass matrix diagonal {i} is {d} (must be ≥ 0 and finite)"
            )));
        }
        if d > 0.0 {
            massive += 1;
        }
    }
    if n_modes > massive {
        return Err(ModalError::InvalidInput(format!(
            "{n_modes} modes requested but only {massive} DOFs carry mass"
        )));
    }
    let q = options
        .subspace_size
        .unwrap_or((2 * n_modes).max(n_modes + 8))
        .clamp(n_modes, massive);

    solver.factor(k)?;

    // starting block X = K⁻¹ M R
    let mut rng = 0x9E37_79B9_7F4A_7C15u64;
    let mut x = DMatrix::<f64>::zeros(nd, q);
    let mut mx = DMatrix::<f64>::zeros(nd, q);
    let mut kx = DMatrix::<f64>::zeros(nd, q);
    {
        let r = DMatrix::<f64>::from_fn(nd, q, |_, _| xorshift(&mut rng));
        mul_block(m, &r, &mut x);
    }
    solver.solve_columns_in_place(x.as_mut_slice(), q)?;

    let mut lambda_prev = vec![f64::NAN; n_modes];
    let mut change = f64::INFINITY;
    for iteration in 1..=options.max_iterations {
        if railfem_framework::interrupt::requested() {
            return Err(ModalError::Interrupted {
                iterations: iteration - 1,
            });
        }
        mul_block(m, &x, &mut mx);
        m_orthonormalize(m, &mut x, &mut mx, &mut rng)?;
        mul_block(k, &x, &mut kx);
        let mut kr = x.transpose() * &kx;
        symmetrize(&mut kr);
        let eig = SymmetricEigen::new(kr);
        let mut order: Vec<usize> = (0..q).collect();
        order.sort_by(|&a, &b| eig.eigenvalues[a].total_cmp(&eig.eigenvalues[b]));
        let v = DMatrix::from_fn(q, q, |i, j| eig.eigenvectors[(i, order[j])]);
        let lambda: Vec<f64> = order.iter().map(|&j| eig.eigenvalues[j]).collect();
        x = &x * &v;

        change = (0..n_modes)
            .map(|i| (lambda[i] - lambda_prev[i]).abs() / lambda[i].abs())
            .fold(
                0.0,
                |a: f64, c| if c.is_nan() { f64::INFINITY } else { a.max(c) },
            );
        lambda_prev.copy_from_slice(&lambda[..n_modes]);
        if change <= options.tolerance {
            if let Some(i) = lambda[..n_modes]
                .iter()
                .position(|&l| l.is_nan() || l <= 0.0)
            {
                return Err(ModalError::InvalidInput(format!(
                    "Ritz value {} of mode {i} is not positive: K or M is not definite",
                    lambda[i]
                )));
            }
            return Ok(finish(k, m, x, &lambda[..n_modes], iteration));
        }
        // inverse iteration X ← K⁻¹ M X
        mul_block(m, &x, &mut mx);
        x.copy_from(&mx);
        solver.solve_columns_in_place(x.as_mut_slice(), q)?;
    }
    Err(ModalError::NotConverged {
        iterations: options.max_iterations,
        change,
    })
}

/// Uniform pseudo-random number in [-1, 1).
fn xorshift(s: &mut u64) -> f64 {
    *s ^= *s << 13;
    *s ^= *s >> 7;
    *s ^= *s << 17;
    (*s >> 11) as f64 / (1u64 << 52) as f64 - 1.0
}

/// `out = A · X` column by column.
fn mul_block(a: &CscMatrix, x: &DMatrix<f64>, out: &mut DMatrix<f64>) {
    for j in 0..x.ncols() {
        a.mul_vec(x.column(j).as_slice(), out.column_mut(j).as_mut_slice());
    }
}

/// `(A + Aᵀ)/2` in place, for products that are symmetric up to round-off.
pub(crate) fn symmetrize(a: &mut DMatrix<f64>) {
    let n = a.nrows();
    for j in 0..n {
        for i in 0..j {
            let v = 0.5 * (a[(i, j)] + a[(j, i)]);
            a[(i, j)] = v;
            a[(j, i)] = v;
        }
    }
}

/// Makes the columns of `x` M-orthonormal (classical Gram–Schmidt in the M inner product,
/// two passes), updating `mx = M x` consistently. A column that collapses (numerically in
/// the span of the previous ones, or in the null space of M) is replaced by `M`-weighted
/// random data and orthogonalized again.
fn m_orthonormalize(
    m: &CscMatrix,
    x: &mut DMatrix<f64>,
    mx: &mut DMatrix<f64>,
    rng: &mut u64,
) -> Result<(), ModalError> {
    let q = x.ncols();
    for j in 0..q {
        let mut attempts = 0;
        loop {
            let norm0 = x.column(j).dot(&mx.column(j)).max(0.0).sqrt();
            for _pass in 0..2 {
                for i in 0..j {
                    let c = x.column(i).dot(&mx.column(j));
                    let (xi, mxi) = (x.column(i).clone_owned(), mx.column(i).clone_owned());
                    x.column_mut(j).axpy(-c, &xi, 1.0);
                    mx.column_mut(j).axpy(-c, &mxi, 1.0);
                }
            }
            let norm = x.column(j).dot(&mx.column(j));
            if norm.is_finite() && norm > 0.0 && norm.sqrt() > 1e-10 * norm0 {
                let s = 1.0 / norm.sqrt();
                x.column_mut(j).scale_mut(s);
                mx.column_mut(j).scale_mut(s);
                break;
            }
            attempts += 1;
            if attempts > 3 {
                return Err(ModalError::InvalidInput(
                    "cannot build an M-orthonormal basis: rank of M is smaller than the subspace \
                     size, or M is indefinite"
                        .into(),
                ));
            }
            let r: Vec<f64> = (0..x.nrows()).map(|_| xorshift(rng)).collect();
            let mut col = vec![0.0; x.nrows()];
            m.mul_vec(&r, &mut col);
            x.column_mut(j).as_mut_slice().copy_from_slice(&col);
            m.mul_vec(&col, mx.column_mut(j).as_mut_slice());
        }
    }
    Ok(())
}

/// Sign-normalizes the wanted Ritz vectors and computes their residuals.
fn finish(
    k: &CscMatrix,
    m: &CscMatrix,
    x: DMatrix<f64>,
    lambda: &[f64],
    iterations: usize,
) -> Modes {
    let nd = x.nrows();
    let p = lambda.len();
    let mut shapes = x.columns(0, p).into_owned();
    let mut residuals = Vec::with_capacity(p);
    let (mut kphi, mut mphi) = (vec![0.0; nd], vec![0.0; nd]);
    for (j, &l) in lambda.iter().enumerate() {
        let mut col = shapes.column_mut(j);
        let imax = col.iamax();
        if col[imax] < 0.0 {
            col.neg_mut();
        }
        k.mul_vec(col.as_slice(), &mut kphi);
        m.mul_vec(col.as_slice(), &mut mphi);
        let kn = kphi.iter().map(|v| v * v).sum::<f64>().sqrt();
        let rn = kphi
            .iter()
            .zip(&mphi)
            .map(|(a, b)| (a - l * b).powi(2))
            .sum::<f64>()
            .sqrt();
        residuals.push(rn / kn);
    }
    Modes {
        omega: lambda.iter().map(|l| l.sqrt()).collect(),
        shapes,
        residuals,
        iterations,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linear::SparseLu;
    use std::f64::consts::PI;

    /// Fixed-free chain: spring `i` (stiffness `k[i]`) joins DOF `i − 1` (the ground for
    /// `i = 0`) to DOF `i`; DOF `i` carries lumped mass `m[i]`.
    fn chain(k: &[f64], m: &[f64]) -> (CscMatrix, CscMatrix) {
        let n = k.len();
        let mut tk = Vec::new();
        for (i, &ki) in k.iter().enumerate() {
            tk.push((i, i, ki));
            if i > 0 {
                tk.push((i - 1, i - 1, ki));
                tk.push((i - 1, i, -ki));
                tk.push((i, i - 1, -ki));
            }
        }
        let tm: Vec<_> = m.iter().enumerate().map(|(i, &mi)| (i, i, mi)).collect();
        (
            CscMatrix::from_triplets(n, &tk),
            CscMatrix::from_triplets(n, &tm),
        )
    }

    /// Closed form for a fixed-free chain of `n` equal springs `k` and masses `m`.
    ///
    /// Try `u_i = sin(iθ)` (i = 0 is the ground, so `u_0 = 0`). An interior mass gives
    /// `k(2u_i − u_{i−1} − u_{i+1}) = ω² m u_i`, i.e. `ω² = (2k/m)(1 − cos θ) = (4k/m)
    /// sin²(θ/2)`. The free end `k(u_n − u_{n−1}) = ω² m u_n` is the interior equation with a
    /// fictitious `u_{n+1} = u_n`, i.e. `sin((n+1)θ) = sin(nθ)`, so `cos((2n+1)θ/2) = 0`,
    /// `θ_j = (2j−1)π/(2n+1)` and `ω_j = 2√(k/m)·sin((2j−1)π/(2(2n+1)))`.
    fn chain_omega(n: usize, k: f64, m: f64, j: usize) -> f64 {
        2.0 * (k / m).sqrt() * ((2 * j - 1) as f64 * PI / (2.0 * (2 * n + 1) as f64)).sin()
    }

    fn max_rel(a: f64, b: f64) -> f64 {
        (a - b).abs() / b.abs()
    }

    /// First five frequencies of a 300-mass chain to 1e-9 relative (the solver converges ω²
    /// to 1e-10, i.e. ω to 5e-11, and the closed form is exact); shapes are M-orthonormal
    /// and match `sin(iθ_j)` up to normalization.
    #[test]
    fn fixed_free_chain_closed_form() {
        let (n, k, m) = (300, 2.0e6, 15.0);
        let (kk, mm) = chain(&vec![k; n], &vec![m; n]);
        let modes = lowest_modes(&kk, &mm, 5, &ModalOptions::default()).unwrap();
        for j in 1..=5 {
            let exact = chain_omega(n, k, m, j);
            let e = max_rel(modes.omega[j - 1], exact);
            assert!(
                e < 1e-9,
                "mode {j}: {} vs {exact} ({e:e})",
                modes.omega[j - 1]
            );
            assert!(
                modes.residuals[j - 1] < 1e-6,
                "residual {}",
                modes.residuals[j - 1]
            );
            // shape: sin(iθ) scaled to unit modal mass, largest component positive
            let theta = (2 * j - 1) as f64 * PI / (2 * n + 1) as f64;
            let s: Vec<f64> = (1..=n).map(|i| (i as f64 * theta).sin()).collect();
            let scale = 1.0 / (m * s.iter().map(|v| v * v).sum::<f64>()).sqrt();
            let sign = if s
                .iter()
                .cloned()
                .fold(0.0, |a: f64, v| if v.abs() > a.abs() { v } else { a })
                > 0.0
            {
                1.0
            } else {
                -1.0
            };
            for (i, v) in s.iter().enumerate() {
                let d = (modes.shapes[(i, j - 1)] - sign * scale * v).abs();
                assert!(d < 1e-6 * scale, "mode {j} DOF {i}: {d:e}");
            }
        }
        let gram = modes.shapes.transpose() * mm.to_dense() * &modes.shapes;
        assert!((gram - DMatrix::identity(5, 5)).amax() < 1e-10);
    }

    /// Massless DOFs: a chain of 2n springs k with mass m only at every second DOF. Each
    /// massless DOF just joins two springs in series, so statically condensed this is the
    /// fixed-free chain of n springs k/2 and n masses m (the last DOF, the free end, is
    /// massive). Also checks the same result with the LU solver and that asking for more
    /// modes than massive DOFs is an error.
    #[test]
    fn zero_masses_condense_to_half_chain() {
        let (n, k, m) = (120, 5.0e5, 3.0);
        let masses: Vec<f64> = (0..2 * n)
            .map(|i| if i % 2 == 1 { m } else { 0.0 })
            .collect();
        let (kk, mm) = chain(&vec![k; 2 * n], &masses);
        let opts = ModalOptions::default();
        let a = lowest_modes(&kk, &mm, 6, &opts).unwrap();
        let b = lowest_modes_with(&mut SparseLu::new(), &kk, &mm, 6, &opts).unwrap();
        for j in 1..=6 {
            let exact = chain_omega(n, k / 2.0, m, j);
            assert!(
                max_rel(a.omega[j - 1], exact) < 1e-9,
                "mode {j}: {} vs {exact}",
                a.omega[j - 1]
            );
            assert!(max_rel(b.omega[j - 1], exact) < 1e-9, "LU mode {j}");
        }
        assert!(matches!(
            lowest_modes(&kk, &mm, n + 1, &opts),
            Err(ModalError::InvalidInput(_))
        ));
        // all massive DOFs requested: the subspace is the whole massive space
        let all = lowest_modes(&kk, &mm, n, &opts).unwrap();
        assert!(max_rel(all.omega[n - 1], chain_omega(n, k / 2.0, m, n)) < 1e-9);
    }

    /// Non-diagonal (consistent-like) mass on an irregular spring network against the dense
    /// reference: `M = LLᵀ` (nalgebra Cholesky), eigenvalues of `L⁻¹ K L⁻ᵀ` (nalgebra
    /// `SymmetricEigen`). Both are backward stable, so ω² agree to ~cond·eps; 1e-9 asserted.
    #[test]
    fn consistent_mass_matches_dense_reference() {
        let n = 80;
        let mut tk = Vec::new();
        let mut tm = Vec::new();
        let mut s = 12345u64;
        for i in 0..n {
            tk.push((i, i, 1.0e3 * (1.0 + 0.5 * xorshift(&mut s))));
            tm.push((i, i, 4.0 + xorshift(&mut s)));
            for off in [1usize, 7] {
                if i + off < n {
                    let kv = 1.0e4 * (1.5 + xorshift(&mut s));
                    let j = i + off;
                    tk.extend([(i, i, kv), (j, j, kv), (i, j, -kv), (j, i, -kv)]);
                    let mv = 0.5 + 0.4 * xorshift(&mut s); // consistent-mass style coupling
                    tm.extend([(i, i, 2.0 * mv), (j, j, 2.0 * mv), (i, j, mv), (j, i, mv)]);
                }
            }
        }
        let kk = CscMatrix::from_triplets(n, &tk);
        let mm = CscMatrix::from_triplets(n, &tm);
        let l = mm.to_dense().cholesky().unwrap().l();
        let linv = l.clone().try_inverse().unwrap();
        let c = &linv * kk.to_dense() * linv.transpose();
        let mut reference: Vec<f64> = SymmetricEigen::new(0.5 * (&c + c.transpose()))
            .eigenvalues
            .iter()
            .cloned()
            .collect();
        reference.sort_by(f64::total_cmp);
        let modes = lowest_modes(&kk, &mm, 8, &ModalOptions::default()).unwrap();
        for (j, (w, r)) in modes.omega.iter().zip(&reference).enumerate() {
            let e = max_rel(w.powi(2), *r);
            assert!(e < 1e-9, "mode {j}: {e:e}");
        }
    }

    #[test]
    fn singular_stiffness_is_reported() {
        // free-free chain: remove the ground spring by zeroing K's first diagonal share
        let (mut kk, mm) = chain(&[1.0, 1.0, 1.0], &[1.0, 1.0, 1.0]);
        let p = kk.position(0, 0).unwrap();
        kk.values[p] -= 1.0;
        assert!(matches!(
            lowest_modes(&kk, &mm, 1, &ModalOptions::default()),
            Err(ModalError::Solver(SolverError::Singular { .. }))
        ));
    }
}

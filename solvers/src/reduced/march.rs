//! The time march of a linear system `M·ẍ + C·ẋ + K·x = f(t)` (a reduced block, or a model
//! with reduced blocks) with the generalized-α family of
//! [`crate::integrator::Integrator`], the integrator the driver uses.
//!
//! One step solves the balance at the intermediate times
//! `M·a_{n+1−α_m} + C·v_{n+1−α_f} + K·x_{n+1−α_f} = f_{n+1−α_f}` for the increment `Δx`.
//! Starting from `Δx = 0` (the trial of [`Integrator::trial`]) the residual is
//! `r₀ = f_{n+1−α_f} − M·a_w⁰ − C·v_w⁰ − K·x_n`, and because the system is linear one
//! Newton step with the effective matrix `K_eff = c_k·K + c_m·M + c_c·C`
//! ([`Integrator::coefficients`]: the derivatives of the three terms with respect to `Δx`)
//! solves it exactly: `Δx = K_eff⁻¹·r₀`. `K_eff` is factored once: dense Cholesky for
//! [`DenseSystem`], the workspace's sparse Cholesky for [`SparseSystem`] (symmetric
//! positive definite for `Δt > 0` and positive definite `K`).

use super::switch::ReducedState;
use crate::integrator::Integrator;
use crate::linear::{LinearSolver, SolverError, SparseCholesky};
use nalgebra::{Cholesky, DMatrix, DVector, Dyn};
use railfem_framework::sparse::CscMatrix;

/// Why a march cannot be set up.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MarchError {
    /// `K_eff` (or `M`, for the initial acceleration) is not positive definite.
    #[error("the {0} matrix is not symmetric positive definite")]
    NotDefinite(&'static str),
    /// The sparse factor failed.
    #[error("sparse factor: {0}")]
    Solver(#[from] SolverError),
}

/// What the march needs of a linear system's matrices.
pub trait LinearSystem {
    /// `M·a + C·v + K·x`.
    fn balance(&self, x: &DVector<f64>, v: &DVector<f64>, a: &DVector<f64>) -> DVector<f64>;
    /// `K_eff⁻¹·r` with the factored effective matrix.
    fn solve_effective(&mut self, r: DVector<f64>) -> DVector<f64>;
    /// `M⁻¹·r` (the initial acceleration).
    fn solve_mass(&mut self, r: DVector<f64>) -> Result<DVector<f64>, MarchError>;
}

/// Dense `M`, `C`, `K` (a reduced block).
#[derive(Debug, Clone)]
pub struct DenseSystem {
    m: DMatrix<f64>,
    c: DMatrix<f64>,
    k: DMatrix<f64>,
    effective: Cholesky<f64, Dyn>,
}

impl DenseSystem {
    /// Factors `K_eff` of `integrator` at step `dt` (s).
    pub fn new(
        integrator: &Integrator,
        dt: f64,
        m: DMatrix<f64>,
        c: DMatrix<f64>,
        k: DMatrix<f64>,
    ) -> Result<DenseSystem, MarchError> {
        let w = integrator.coefficients(dt);
        let eff = &k * w.k + &m * w.m + &c * w.c;
        let effective = Cholesky::new(eff).ok_or(MarchError::NotDefinite("effective"))?;
        Ok(DenseSystem { m, c, k, effective })
    }
}

impl LinearSystem for DenseSystem {
    fn balance(&self, x: &DVector<f64>, v: &DVector<f64>, a: &DVector<f64>) -> DVector<f64> {
        &self.m * a + &self.c * v + &self.k * x
    }
    fn solve_effective(&mut self, r: DVector<f64>) -> DVector<f64> {
        self.effective.solve(&r)
    }
    fn solve_mass(&mut self, r: DVector<f64>) -> Result<DVector<f64>, MarchError> {
        let chol = Cholesky::new(self.m.clone()).ok_or(MarchError::NotDefinite("mass"))?;
        Ok(chol.solve(&r))
    }
}

/// Sparse `M`, `C`, `K` of one pattern (a model with reduced blocks, or the full model).
pub struct SparseSystem {
    m: CscMatrix,
    c: CscMatrix,
    k: CscMatrix,
    effective: SparseCholesky,
}

impl SparseSystem {
    /// Factors `K_eff` of `integrator` at step `dt` (s); the three matrices share a pattern.
    pub fn new(
        integrator: &Integrator,
        dt: f64,
        m: CscMatrix,
        c: CscMatrix,
        k: CscMatrix,
    ) -> Result<SparseSystem, MarchError> {
        let w = integrator.coefficients(dt);
        let mut eff = k.zeros_like();
        eff.set_combination(&w.weigh(&k, &m, &c));
        let mut effective = SparseCholesky::new();
        effective.factor(&eff)?;
        Ok(SparseSystem { m, c, k, effective })
    }
}

impl LinearSystem for SparseSystem {
    fn balance(&self, x: &DVector<f64>, v: &DVector<f64>, a: &DVector<f64>) -> DVector<f64> {
        let mut out = DVector::zeros(x.len());
        let o = out.as_mut_slice();
        self.m.mul_vec_add(1.0, a.as_slice(), o);
        self.c.mul_vec_add(1.0, v.as_slice(), o);
        self.k.mul_vec_add(1.0, x.as_slice(), o);
        out
    }
    fn solve_effective(&mut self, mut r: DVector<f64>) -> DVector<f64> {
        self.effective
            .solve_in_place(r.as_mut_slice())
            .expect("a factored matrix solves");
        r
    }
    fn solve_mass(&mut self, mut r: DVector<f64>) -> Result<DVector<f64>, MarchError> {
        let mut chol = SparseCholesky::new();
        chol.factor(&self.m)?;
        chol.solve_in_place(r.as_mut_slice())?;
        Ok(r)
    }
}

/// A linear system marched with fixed `Δt`.
pub struct LinearMarch<S> {
    integrator: Integrator,
    dt: f64,
    system: S,
}

impl LinearMarch<DenseSystem> {
    /// The march of dense `M·ẍ + C·ẋ + K·x = f` with step `dt` (s).
    pub fn new(
        integrator: Integrator,
        dt: f64,
        m: DMatrix<f64>,
        c: DMatrix<f64>,
        k: DMatrix<f64>,
    ) -> Result<Self, MarchError> {
        let system = DenseSystem::new(&integrator, dt, m, c, k)?;
        Ok(LinearMarch {
            integrator,
            dt,
            system,
        })
    }
}

impl LinearMarch<SparseSystem> {
    /// The march of sparse `M·ẍ + C·ẋ + K·x = f` (one pattern) with step `dt` (s).
    pub fn sparse(
        integrator: Integrator,
        dt: f64,
        m: CscMatrix,
        c: CscMatrix,
        k: CscMatrix,
    ) -> Result<Self, MarchError> {
        let system = SparseSystem::new(&integrator, dt, m, c, k)?;
        Ok(LinearMarch {
            integrator,
            dt,
            system,
        })
    }
}

impl<S: LinearSystem> LinearMarch<S> {
    /// The state at `x`, `v` with the acceleration that balances `f`:
    /// `M·a = f − C·v − K·x`.
    pub fn start(
        &mut self,
        x: DVector<f64>,
        v: DVector<f64>,
        f: &DVector<f64>,
    ) -> Result<ReducedState, MarchError> {
        let rhs = f - self.system.balance(&x, &v, &DVector::zeros(x.len()));
        if rhs.iter().all(|r| *r == 0.0) {
            // at rest and in balance: no solve (a mass with massless DOFs is singular)
            let a = DVector::zeros(rhs.len());
            return Ok(ReducedState { q: x, v, a });
        }
        let a = self.system.solve_mass(rhs)?;
        Ok(ReducedState { q: x, v, a })
    }

    /// One step from `t_n` to `t_n + Δt`, with the loads `f_n` and `f_{n+1}` at its ends.
    pub fn step(&mut self, s: &mut ReducedState, f_n: &DVector<f64>, f_next: &DVector<f64>) {
        let n = s.q.len();
        let af = self.integrator.alpha_f;
        let mut a_w = DVector::zeros(n);
        let mut v_w = DVector::zeros(n);
        for i in 0..n {
            let (_, _, aw, vw) = self.integrator.trial(self.dt, 0.0, s.v[i], s.a[i]);
            a_w[i] = aw;
            v_w[i] = vw;
        }
        let f_w = f_next * (1.0 - af) + f_n * af;
        let r = f_w - self.system.balance(&s.q, &v_w, &a_w);
        let dx = self.system.solve_effective(r);
        for i in 0..n {
            let (v, a) = self.integrator.kinematics(self.dt, dx[i], s.v[i], s.a[i]);
            s.q[i] += dx[i];
            s.v[i] = v;
            s.a[i] = a;
        }
    }
}

//! The time march of a small dense linear system `M·ẍ + C·ẋ + K·x = f(t)` (a reduced
//! block) with the generalized-α family of [`crate::integrator::Integrator`], the
//! integrator the driver uses.
//!
//! One step solves the balance at the intermediate times
//! `M·a_{n+1−α_m} + C·v_{n+1−α_f} + K·x_{n+1−α_f} = f_{n+1−α_f}` for the increment `Δx`.
//! Starting from `Δx = 0` (the trial of [`Integrator::trial`]) the residual is
//! `r₀ = f_{n+1−α_f} − M·a_w⁰ − C·v_w⁰ − K·x_n`, and because the system is linear one
//! Newton step with the effective matrix `K_eff = c_k·K + c_m·M + c_c·C`
//! ([`Integrator::coefficients`]: the derivatives of the three terms with respect to `Δx`)
//! solves it exactly: `Δx = K_eff⁻¹·r₀`. `K_eff` is factored once (Cholesky: it is
//! symmetric positive definite for positive `Δt` and positive definite `M`).

use super::switch::ReducedState;
use crate::integrator::Integrator;
use nalgebra::{Cholesky, DMatrix, DVector, Dyn};

/// A linear system and its factored effective matrix for one step size.
#[derive(Debug, Clone)]
pub struct LinearMarch {
    integrator: Integrator,
    dt: f64,
    m: DMatrix<f64>,
    c: DMatrix<f64>,
    k: DMatrix<f64>,
    effective: Cholesky<f64, Dyn>,
}

/// Why a march cannot be set up.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MarchError {
    /// `K_eff` (or `M`, for the initial acceleration) is not positive definite.
    #[error("the {0} matrix is not symmetric positive definite")]
    NotDefinite(&'static str),
}

impl LinearMarch {
    /// Sets up the march of `M·ẍ + C·ẋ + K·x = f` with step `dt` (s).
    pub fn new(
        integrator: Integrator,
        dt: f64,
        m: DMatrix<f64>,
        c: DMatrix<f64>,
        k: DMatrix<f64>,
    ) -> Result<LinearMarch, MarchError> {
        let w = integrator.coefficients(dt);
        let eff = &k * w.k + &m * w.m + &c * w.c;
        let effective = Cholesky::new(eff).ok_or(MarchError::NotDefinite("effective"))?;
        Ok(LinearMarch {
            integrator,
            dt,
            m,
            c,
            k,
            effective,
        })
    }

    /// The state at `x`, `v` with the acceleration that balances `f`:
    /// `M·a = f − C·v − K·x`.
    pub fn start(
        &self,
        x: DVector<f64>,
        v: DVector<f64>,
        f: &DVector<f64>,
    ) -> Result<ReducedState, MarchError> {
        let rhs = f - &self.c * &v - &self.k * &x;
        if rhs.iter().all(|r| *r == 0.0) {
            // at rest and in balance: no solve (a mass with massless DOFs is singular)
            let a = DVector::zeros(rhs.len());
            return Ok(ReducedState { q: x, v, a });
        }
        let chol = Cholesky::new(self.m.clone()).ok_or(MarchError::NotDefinite("mass"))?;
        Ok(ReducedState {
            q: x,
            v,
            a: chol.solve(&rhs),
        })
    }

    /// One step from `t_n` to `t_n + Δt`, with the loads `f_n` and `f_{n+1}` at its ends.
    pub fn step(&self, s: &mut ReducedState, f_n: &DVector<f64>, f_next: &DVector<f64>) {
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
        let r = f_w - &self.m * a_w - &self.c * v_w - &self.k * &s.q;
        let dx = self.effective.solve(&r);
        for i in 0..n {
            let (v, a) = self.integrator.kinematics(self.dt, dx[i], s.v[i], s.a[i]);
            s.q[i] += dx[i];
            s.v[i] = v;
            s.a[i] = a;
        }
    }
}

//! The mechanism check of `railfem check`: the first factorization a run makes, made
//! without running, so that a model `run` would stop on with a zero pivot is refused by
//! `check` with the same message (node and DOF, "mechanism").
//!
//! The preflight ([`crate::preflight`]) sees an equation without stiffness from the
//! diagonals alone. A mechanism spread over several equations — a cantilever free to twist
//! about its axis at the root, whose every torsional diagonal is positive — is a zero
//! pivot only the factorization finds. [`Driver::first_factorization`] forms the matrix
//! the run factors first (`K` at the initial state for a static or modal analysis and the
//! initial static equilibrium of a transient; otherwise `K_eff = c_K·K + c_M·M + c_C·C`
//! of the first step, with the integrator's coefficients), with the variable elements
//! evaluated at the initial state, and factors it with the run's solver. A transient also
//! factors the mass matrix of its initial acceleration before its first step (after the
//! static equilibrium, if it has one), as `run` does: a mass matrix singular on a
//! combination of DOFs (a rotation whose only inertia is a point mass carried at an offset
//! by a rigid link) is refused by `check` in the same words.
//!
//! A factorization costs time and memory the preflight does not, so `check` makes it up
//! to [`MECHANISM_CHECK_EQUATIONS`] equations and says above that it was skipped and how
//! to force it (`railfem check --factor`).

use crate::driver::Driver;
use crate::integrator::Coefficients;
use railfem_framework::error::FemError;
use railfem_framework::model::AnalysisKind;

/// Most equations for which `railfem check` makes the trial factorization unasked. A
/// banded beam or bridge model of this size factors in well under a second.
pub const MECHANISM_CHECK_EQUATIONS: usize = 100_000;

impl Driver {
    /// Forms and factors the first matrix a run factors (module documentation); an error
    /// names the DOF of a zero pivot as the run's would. Element trial states are changed
    /// (nothing is committed): use the driver for nothing else afterwards.
    pub fn first_factorization(&mut self) -> Result<(), FemError> {
        let n = self.neq();
        let t = self.state.t;
        let dt = self.model.analysis.dt;
        let static_first = self.static_first()?;
        let transient = self.model.analysis.kind == AnalysisKind::Transient;
        let zero = vec![0.0; n];
        let mut f_int = vec![0.0; n];
        if static_first {
            // Static: the tangent at `q` with zero velocities, as `static_solve` forms it.
            self.asm.advance(&mut self.model, t, 0.0)?;
            let q = self.state.q.clone();
            self.asm
                .update(&mut self.model, &q, &zero, &zero, t, 0.0, &mut f_int, true)?;
            self.factor_tangent(Coefficients::STATIC)?;
        }
        if transient {
            // The initial acceleration's mass matrix, formed and factored as `initialize`
            // does after the variable elements' update at the initial state.
            let (q, v, a) = (
                self.state.q.clone(),
                self.state.v.clone(),
                self.state.a.clone(),
            );
            self.asm.advance(&mut self.model, t, 0.0)?;
            self.asm
                .update(&mut self.model, &q, &v, &a, t, 0.0, &mut f_int, false)?;
            let mut rhs = zero;
            self.solve_initial_mass(&mut rhs)?;
            if !static_first {
                // The first step's `K_eff` with the integrator's coefficients.
                self.asm.advance(&mut self.model, t, dt)?;
                self.asm
                    .update(&mut self.model, &q, &v, &a, t, dt, &mut f_int, true)?;
                let coef = self
                    .integrator
                    .coefficients(self.integrator.stage_length(0, dt));
                self.factor_tangent(coef)?;
            }
        }
        Ok(())
    }
}

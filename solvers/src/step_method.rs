//! The step method: how one attempt at a step of length `Δt` is solved, behind the
//! [`StepMethod`] trait, and the built-in methods the driver picks from.
//!
//! The [`Driver`] keeps the time loop, the step cutting, the commit and the recording; an
//! attempt at one (sub-)step is the step method's. The driver picks its method once, before
//! the first transient step ([`Driver::default_step_method`]), or takes the one a caller
//! gives ([`Driver::set_step_method`]):
//!
//! | method | when the driver picks it | where |
//! |---|---|---|
//! | [`LumpedLinear`] | a linear model with a diagonal, constant mass and no damping | [`crate::lumped_step`] |
//! | [`CondensedNewton`] | the partitioned solver, full Newton, variable elements, a constant effective matrix of the constant elements | [`crate::condensed`] |
//! | [`FullNewton`] | everything else | [`crate::driver`] |
//!
//! each wrapped in [`HeldActiveSet`], the last resort of step cutting on frictional contact
//! ([`crate::held_active_set`]), which takes any method.
//!
//! A method of one's own implements [`StepMethod::attempt`] on the driver's public parts:
//! [`Driver::begin_step`] (the model moved to the step's end and its external force),
//! the integrator ([`Driver::integrator`]), the assembler ([`Driver::asm`]), the linear
//! solver ([`Driver::factor_effective`], [`Driver::solve_correction`]) and the Newton
//! settings of the model (`docs/solver-parts.md` has a plain Newton written this way).

use crate::driver::{Driver, State};
use railfem_framework::FemError;

/// A converged attempt: the state at the end of the (sub-)step, ready to be committed.
#[derive(Debug, Clone)]
pub struct Accepted {
    /// The converged state at the step's end (`t` set).
    pub state: State,
    /// Linear solves (Newton corrections) the attempt took.
    pub iterations: usize,
    /// Residual norm (N) of the accepted state, as [`crate::StepReport::residual`] reports it.
    pub residual: f64,
}

/// Why one attempt at a step failed. `NotConverged` lets the driver cut the step; `Fatal`
/// stops the run.
#[derive(Debug)]
pub enum Attempt {
    /// The iterations did not converge.
    NotConverged {
        /// The largest residual entry (N or N·m).
        residual: f64,
        /// The DOF it belongs to, by name (`"node 12 uz"`).
        dof: String,
        /// Linear solves spent.
        iterations: usize,
    },
    /// A hard error: stop at once.
    Fatal(FemError),
}

impl From<FemError> for Attempt {
    fn from(e: FemError) -> Self {
        Attempt::Fatal(e)
    }
}

/// How the last resort of step cutting ended when it did not give a state: why, for the
/// error message.
#[derive(Debug)]
pub struct LastResortFailure {
    /// The failure to report (its iterations count those of every round).
    pub attempt: Attempt,
    /// Why the last resort gave up, appended to the driver's message.
    pub why: String,
}

/// One attempt at a (sub-)step of length `dt` from the driver's committed state
/// ([`Driver::state`]), leaving that state as it is. On failure the driver reverts the
/// elements ([`railfem_framework::assembly::Assembler::revert`]) and cuts the step.
pub trait StepMethod: Send {
    /// The method's name (for traces and reports).
    fn name(&self) -> &'static str;

    /// Solves the step of length `dt` (module documentation).
    fn attempt(&mut self, d: &mut Driver, dt: f64) -> Result<Accepted, Attempt>;

    /// What to try when the smallest sub-step did not converge, after the elements were
    /// reverted: `None` (the default) when the method has nothing more to try.
    fn last_resort(
        &mut self,
        _d: &mut Driver,
        _dt: f64,
    ) -> Option<Result<Accepted, LastResortFailure>> {
        None
    }
}

/// Full Newton–Raphson on the whole residual, with backtracking when the residual rises
/// and the model's modified and initial-tangent variants (`[analysis.newton] kind`): the
/// general attempt ([`crate::driver`]).
#[derive(Debug, Default, Clone, Copy)]
pub struct FullNewton;

impl StepMethod for FullNewton {
    fn name(&self) -> &'static str {
        "full Newton"
    }

    fn attempt(&mut self, d: &mut Driver, dt: f64) -> Result<Accepted, Attempt> {
        let r = d.attempt_full_newton(dt);
        d.release_first_iteration();
        r
    }
}

/// The step of a linear model with a diagonal mass and no damping in three fused passes
/// ([`crate::lumped_step`]).
#[derive(Debug, Default, Clone, Copy)]
pub struct LumpedLinear;

impl StepMethod for LumpedLinear {
    fn name(&self) -> &'static str {
        "lumped linear step"
    }

    fn attempt(&mut self, d: &mut Driver, dt: f64) -> Result<Accepted, Attempt> {
        d.attempt_lumped(dt)
    }
}

/// Newton on the top system of the partitioned solver, the block interiors condensed out
/// of the residual ([`crate::condensed`]); a step it cannot condense (a top set that
/// changes, a rising residual, ...) is taken again by [`FullNewton`].
#[derive(Debug, Default, Clone, Copy)]
pub struct CondensedNewton;

impl StepMethod for CondensedNewton {
    fn name(&self) -> &'static str {
        "condensed Newton"
    }

    fn attempt(&mut self, d: &mut Driver, dt: f64) -> Result<Accepted, Attempt> {
        if let Some(accepted) = d.attempt_condensed_or_fall_back(dt) {
            return Ok(accepted);
        }
        FullNewton.attempt(d, dt)
    }
}

/// Any step method with the held active set as the last resort of step cutting
/// ([`crate::held_active_set`]): its rounds solve the step again with `inner`.
pub struct HeldActiveSet {
    /// The method each attempt and each held round takes.
    pub inner: Box<dyn StepMethod>,
}

impl HeldActiveSet {
    /// `inner` with the held retry.
    pub fn wrap(inner: Box<dyn StepMethod>) -> HeldActiveSet {
        HeldActiveSet { inner }
    }
}

impl StepMethod for HeldActiveSet {
    fn name(&self) -> &'static str {
        self.inner.name()
    }

    fn attempt(&mut self, d: &mut Driver, dt: f64) -> Result<Accepted, Attempt> {
        self.inner.attempt(d, dt)
    }

    fn last_resort(&mut self, d: &mut Driver, dt: f64) -> Option<Result<Accepted, LastResortFailure>> {
        d.attempt_held(dt, &mut *self.inner)
    }
}

impl Driver {
    /// The method the driver picks for a model (module documentation): the lumped linear
    /// step where it applies ([`Driver::lumped_linear_applies`]), the condensed Newton with
    /// the partitioned solver and variable elements ([`Driver::condense_residual`] on), else
    /// full Newton; each with the held active set's retry.
    pub fn default_step_method(&self) -> Box<dyn StepMethod> {
        let inner: Box<dyn StepMethod> = if self.lumped_linear_applies() {
            Box::new(LumpedLinear)
        } else if self.condense_residual && self.may_condense() {
            Box::new(CondensedNewton)
        } else {
            Box::new(FullNewton)
        };
        Box::new(HeldActiveSet::wrap(inner))
    }

    /// Replaces the step method (before the first step, or between steps). The driver's
    /// own methods come wrapped in [`HeldActiveSet`]; wrap `method` too to keep that
    /// retry.
    pub fn set_step_method(&mut self, method: Box<dyn StepMethod>) {
        self.method = Some(method);
    }

    /// The name of the step method the driver runs with (its pick if none was given yet).
    pub fn step_method_name(&mut self) -> &'static str {
        self.ensure_step_method();
        self.method.as_ref().map_or("", |m| m.name())
    }

    /// Picks the default step method if none was picked or given yet.
    pub(crate) fn ensure_step_method(&mut self) {
        if self.method.is_none() {
            self.method = Some(self.default_step_method());
        }
    }
}

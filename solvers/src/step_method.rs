//! The step method: how one attempt at a step of length `Δt` is solved, behind the
//! [`StepMethod`] trait, and the built-in methods the driver picks from.
//!
//! The driver ([`crate::driver::Driver`]) keeps the time loop, the step cutting, the commit
//! and the recording; an attempt at one (sub-)step is the step method's. The trait is
//! generic over the driver it runs on (`D`, the driver's type: this module stays below the
//! driver, which owns a `Box<dyn StepMethod<Driver>>`). The driver picks its method once,
//! before the first transient step (`Driver::default_step_method`), or takes the one a
//! caller gives (`Driver::set_step_method`):
//!
//! | method | when the driver picks it | where |
//! |---|---|---|
//! | [`LumpedLinear`] | a linear model with a diagonal, constant mass and no damping | `lumped_step.rs` |
//! | [`CondensedNewton`] | the partitioned solver, full Newton, variable elements | `condensed.rs` |
//! | [`FullNewton`] | everything else | `driver.rs` |
//!
//! each wrapped in [`HeldActiveSet`], the last resort of step cutting on frictional contact
//! (`held_active_set.rs`), which takes any method. The types are declared here and each
//! method's `impl StepMethod<Driver>` stands in the file named.
//!
//! A method of one's own implements [`StepMethod::attempt`] on the driver's public parts:
//! `Driver::begin_step` (the model moved to the step's end and its external force), the
//! integrator (`Driver::integrator`), the assembler (`Driver::asm`), the linear solver
//! (`Driver::factor_effective`, `Driver::solve_correction`) and the Newton settings of the
//! model (`docs/solver-parts.md` has a plain Newton written this way).

use crate::state::State;
use railfem_framework::FemError;

/// A converged attempt: the state at the end of the (sub-)step, ready to be committed.
#[derive(Debug, Clone)]
pub struct Accepted {
    /// The converged state at the step's end (`t` set).
    pub state: State,
    /// Linear solves (Newton corrections) the attempt took.
    pub iterations: usize,
    /// Residual norm (N) of the accepted state, as the driver's step report gives it.
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

/// One attempt at a (sub-)step of length `dt` on the driver `D` (the crate's
/// `Driver`) from its committed state, leaving that state as it is. On failure the driver
/// reverts the elements ([`railfem_framework::assembly::Assembler::revert`]) and cuts the
/// step.
pub trait StepMethod<D: ?Sized>: Send {
    /// The method's name (for traces and reports).
    fn name(&self) -> &'static str;

    /// Solves the step of length `dt` (module documentation).
    fn attempt(&mut self, d: &mut D, dt: f64) -> Result<Accepted, Attempt>;

    /// What to try when the smallest sub-step did not converge, after the elements were
    /// reverted: `None` (the default) when the method has nothing more to try.
    fn last_resort(&mut self, _d: &mut D, _dt: f64) -> Option<Result<Accepted, LastResortFailure>> {
        None
    }
}

/// Full Newton–Raphson on the whole residual, with backtracking when the residual rises
/// and the model's modified and initial-tangent variants (`[analysis.newton] kind`): the
/// general attempt (`driver.rs`).
#[derive(Debug, Default, Clone, Copy)]
pub struct FullNewton;

/// The step of a linear model with a diagonal mass and no damping in three fused passes
/// (`lumped_step.rs`).
#[derive(Debug, Default, Clone, Copy)]
pub struct LumpedLinear;

/// Newton on the top system of the partitioned solver, the block interiors condensed out
/// of the residual (`condensed.rs`); a step it cannot condense (a top set that
/// changes, a rising residual, ...) is taken again by [`FullNewton`].
/// It owns its caches between steps (the top equations' constant products, the products
/// formed ahead for the next predictor, scratch).
#[derive(Debug, Default)]
pub struct CondensedNewton {
    pub(crate) cache: crate::condensed_cache::CondensedCache,
}

/// Any step method with the held active set as the last resort of step cutting
/// (`held_active_set.rs`): its rounds solve the step again with `inner`.
pub struct HeldActiveSet<D: ?Sized> {
    /// The method each attempt and each held round takes.
    pub inner: Box<dyn StepMethod<D>>,
}

impl<D: ?Sized> HeldActiveSet<D> {
    /// `inner` with the held retry.
    pub fn wrap(inner: Box<dyn StepMethod<D>>) -> HeldActiveSet<D> {
        HeldActiveSet { inner }
    }
}

//! Holding the contact's active set: the last resort of step cutting when contact cycles
//! (the step solved again with the active set held fixed, then checked against the contact
//! law), and the first iteration of every transient step ([`FirstActiveSet`], the end of
//! this documentation).
//!
//! Newton on frictional penalty contact can cycle: each point's force is smooth within a
//! status (open, stick, slide along `+u` or `−u`) and kinked where its status changes, and
//! iterates that cross kinks can come back to where they were (issue 15: a wheel alternating
//! between sliding points whose lateral force has turned and points pressed in deep). When
//! the smallest sub-step still does not converge, the held retry ([`HeldActiveSet`]) solves it as an
//! active-set method does:
//!
//! 1. hold every contact element's statuses at those of the last converged step
//!    ([`ActiveSet::Committed`]); each status's branch of the law then holds beyond its
//!    range, so the equations are smooth and Newton converges as on a fixed set of springs;
//! 2. at convergence, ask each element how many points its own law puts in another status
//!    ([`railfem_framework::element::Element::active_set_changes`]);
//! 3. none: every held branch is the one the law takes there, so the held state is a
//!    converged state of the contact law itself (its forces are the law's, bit for bit:
//!    Coulomb's `|f_u| ≤ μ·f_n`, sliding force along the slip, no pull), and it is accepted;
//!    some: hold the statuses found at that state ([`ActiveSet::LastFound`]) and solve the
//!    step again from its start, up to [`HELD_ROUNDS`] times;
//! 4. when those rounds have not settled, up to [`HELD_ROUNDS`] more rounds in which a point
//!    found sliding against the direction it was held sliding in is held sticking
//!    ([`ActiveSet::LastFoundStickingReversals`]) instead of sliding the other way.
//!
//! Why step 4: the rounds of step 3 can cycle. In the one case seen (issue 15, seed 9 at
//! 0.6 g and 60 m/s, t = 0.3978 s) two neighbouring rail nodes under one wheel alternate
//! between two sets: node 20 held sliding at `+μ·f_n` (4.1 kN) comes out with its trial
//! friction `k·s_u` = −4.2 kN, held at `−μ·f_n` with +11.5 kN, so each round sends it to the
//! other slide, forever. Written as a function of the point's own friction force `f` (the
//! rest held), `g(f) = k·s_u(f) − f` is continuous, negative at `f = +μ·f_n` and positive at
//! `f = −μ·f_n`, so it has a root between: a sticking state (`f = k·s_u`, `|f| < μ·f_n`)
//! exists there, and sticking is the status to hold. The accepted state is still one whose
//! every point the law itself puts in its held status (step 3), so the answer is the
//! law's; only the guess of the next set changes, and only after step 3 gave up, so a step
//! that converged before does so in the same rounds with the same numbers.
//!
//! A step that converges today never gets here (it is tried only after the halvings gave
//! up), so every answer that converged before is unchanged.
//!
//! **The first iteration** (`Driver::hold_first_iteration`): with
//! `first_active_set = "committed"` (the default) a step's first evaluation holds every
//! point at its last converged status, and the next one releases them. The first tangent
//! then carries the contact that held each wheel, where `q⁰ = q_n` would find a wheel on a
//! moving rail lifted clear (framework::model::FirstActiveSet has the why). Only released
//! evaluations are accepted, so this changes Newton's path, not what it accepts: answers
//! move within the Newton tolerance where a step has one converged state, and, where the
//! time-discrete frictional contact has several (strong shaking at Δt = 5 ms), by up to
//! that Δt's own error (docs/scale-out.md, the study's rerun).

use crate::driver::{Accepted, Attempt, Driver};
use crate::step_method::{HeldActiveSet, LastResortFailure, StepMethod};
use railfem_framework::element::ActiveSet;
use railfem_framework::model::FirstActiveSet;

/// Rounds of holding and checking with [`ActiveSet::LastFound`], and then as many with
/// [`ActiveSet::LastFoundStickingReversals`], before the retry gives up.
pub const HELD_ROUNDS: usize = 8;

impl Driver {
    /// Holds (or, with [`ActiveSet::Found`], releases) the active set of every variable
    /// element; whether any has one.
    fn hold_active_sets(&mut self, set: ActiveSet) -> bool {
        self.holds.retry = set != ActiveSet::Found;
        self.set_active_sets(set)
    }

    fn set_active_sets(&mut self, set: ActiveSet) -> bool {
        let mut any = false;
        for &ei in self.asm.variable_elements() {
            any |= self.model.elements[ei].element.hold_active_set(set);
        }
        any
    }

    /// Holds every contact element's statuses at the last converged step's for a step's
    /// first iteration ([`FirstActiveSet::Committed`]; released by
    /// [`Driver::release_first_iteration`]). Not while the held retry holds them, nor for
    /// a linear model. Whether any element holds.
    pub(crate) fn hold_first_iteration(&mut self, linear: bool) -> bool {
        if linear
            || self.holds.retry
            || self.model.analysis.newton.first_active_set != FirstActiveSet::Committed
        {
            return false;
        }
        self.holds.first = self.set_active_sets(ActiveSet::Committed);
        self.holds.first
    }

    /// Releases what [`Driver::hold_first_iteration`] held (nothing if it held nothing).
    pub(crate) fn release_first_iteration(&mut self) {
        if std::mem::take(&mut self.holds.first) {
            self.set_active_sets(ActiveSet::Found);
        }
    }

    /// Points, over all elements, in another status than the held one at the last
    /// evaluation.
    fn active_set_changes(&self) -> usize {
        self.asm
            .variable_elements()
            .iter()
            .map(|&ei| self.model.elements[ei].element.active_set_changes())
            .sum()
    }

    /// The step of length `dt` solved with the active set held (module documentation).
    /// `None` when no element has an active set to hold. The active sets are released
    /// whatever the outcome; on failure the elements are reverted.
    pub(crate) fn attempt_held(
        &mut self,
        dt: f64,
        method: &mut dyn StepMethod<Driver>,
    ) -> Option<Result<Accepted, LastResortFailure>> {
        if !self.hold_active_sets(ActiveSet::Committed) {
            return None;
        }
        let mut iterations = 0;
        let mut changes = 0;
        for round in 1..=2 * HELD_ROUNDS {
            match method.attempt(self, dt) {
                Ok(Accepted {
                    state: s,
                    iterations: it,
                    residual: res,
                }) => {
                    iterations += it;
                    changes = self.active_set_changes();
                    if self.trace {
                        eprintln!(
                            "t = {:.6} s, held active set, round {round}: converged in {it} iterations, {changes} points in another status",
                            s.t
                        );
                    }
                    if changes == 0 {
                        self.hold_active_sets(ActiveSet::Found);
                        return Some(Ok(Accepted {
                            state: s,
                            iterations,
                            residual: res,
                        }));
                    }
                    // Converged with some points held outside their law's range: hold the
                    // statuses found there (after HELD_ROUNDS rounds, reversed slides as
                    // sticking) and solve the step again from its start.
                    self.hold_active_sets(if round < HELD_ROUNDS {
                        ActiveSet::LastFound
                    } else {
                        ActiveSet::LastFoundStickingReversals
                    });
                    self.asm.revert(&mut self.model);
                    self.linear.invalidate();
                }
                Err(attempt) => {
                    self.asm.revert(&mut self.model);
                    self.linear.invalidate();
                    self.hold_active_sets(ActiveSet::Found);
                    let attempt = match attempt {
                        Attempt::NotConverged {
                            residual,
                            dof,
                            iterations: more,
                        } => Attempt::NotConverged {
                            residual,
                            dof,
                            iterations: iterations + more,
                        },
                        fatal => fatal,
                    };
                    return Some(Err(LastResortFailure {
                        attempt,
                        why: "Newton did not converge with the contact's active set held either"
                            .into(),
                    }));
                }
            }
        }
        self.hold_active_sets(ActiveSet::Found);
        Some(Err(LastResortFailure {
            attempt: Attempt::NotConverged {
                residual: f64::NAN,
                dof: String::new(),
                iterations,
            },
            why: format!(
                "with the contact's active set held, {changes} contact points were still in another status after {} rounds",
                2 * HELD_ROUNDS
            ),
        }))
    }
}

impl StepMethod<Driver> for HeldActiveSet<Driver> {
    fn name(&self) -> &'static str {
        self.inner.name()
    }

    fn attempt(&mut self, d: &mut Driver, dt: f64) -> Result<Accepted, Attempt> {
        self.inner.attempt(d, dt)
    }

    fn last_resort(
        &mut self,
        d: &mut Driver,
        dt: f64,
    ) -> Option<Result<Accepted, LastResortFailure>> {
        d.attempt_held(dt, &mut *self.inner)
    }
}

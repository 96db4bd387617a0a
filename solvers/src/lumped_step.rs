//! The step of a linear model with a diagonal (lumped) mass and no damping, in three fused
//! passes over the equations instead of the general attempt's dozen.
//!
//! A linear model is solved exactly by one correction from the committed state
//! (`docs/performance.md`, "Lumped mass and the linear step"). With `M = diag(m)` and
//! `C = 0` that step needs no matrix but `K` and the factor:
//!
//! ```text
//! pass 1   a_w,i = a_{n+1−α_m}(Δu = 0),   r_i = f̄_ext,i − m_i·a_w,i − ((1−α_f)·f_int,i + α_f·f_int,n,i)
//! solve    K_eff·Δq = r
//! pass 2   q_i = q_n,i + Δq_i,   (v_i, a_i) = Newmark(Δq_i),   (M·v)_i = m_i·v_i
//! pass 3   f_int = K·q
//! ```
//!
//! (`f̄_ext = (1−α_f)·f_ext(t_{n+1}) + α_f·f_ext(t_n)`; `f_int` at `Δu = 0` is the committed
//! internal force.) Each value is formed by the same operations in the same order as in the
//! general attempt ([`crate::driver`]), so the states are the same to the bit; only the
//! passes over the equation vectors are fewer (at 10⁵ equations each pass moves 0.8 MB per
//! vector, about as much as the step's pass over `K` when a dozen are summed).

use crate::driver::{Accepted, Attempt, Driver, State, StepWork};
use crate::step_method::{LumpedLinear, StepMethod};
use crate::time_integrator::{Increment, BLOCK};
use railfem_framework::FemError;
use std::time::Instant;

impl Driver {
    /// Whether the next attempt takes the lumped linear step: no variable element, no
    /// finite rotation, a diagonal constant mass, no damping, no per-iteration trace, and
    /// [`Driver::set_lumped_step`] left on.
    pub fn lumped_linear_applies(&self) -> bool {
        self.choice.lumped_step
            && !self.trace
            && self.asm.variable_elements().is_empty()
            && !self.asm.dofmap.has_finite_rotations()
            && self.asm.mass_diagonal().is_some()
            && !self.asm.has_damping()
            && self.asm.mass_is_constant()
            && self.model.analysis.newton.max_iter > 0
    }

    /// One attempt at a step of length `dt` from `s0` (module documentation).
    pub(crate) fn attempt_lumped_linear(
        &mut self,
        dt: f64,
        s0: &State,
        w: &mut StepWork,
    ) -> Result<(State, usize, f64), Attempt> {
        let n = self.neq();
        let af = self.integrator.force_weight();
        let t1 = s0.t + dt;
        let mut next = self.begin_attempt(t1, dt, w)?;
        w.inertia_ready = false;
        let ta = Instant::now();
        // The internal force at the first iterate `q = q_n`: the committed one when the last
        // linear step formed it there, else `K·q_n` (the first step, after a static solve).
        let fresh = w.f_int_at != s0.q;
        if fresh {
            self.asm.constant_internal_force(&s0.q, &mut w.r);
        }
        let f_now: &[f64] = if fresh { &w.r } else { &s0.f_int };
        let m = self
            .asm
            .mass_diagonal()
            .expect("checked by lumped_linear_applies");
        let dq = &mut w.dq;
        let mut squares = -0.0f64;
        let mut baw = [0.0; BLOCK];
        for lo in (0..n).step_by(BLOCK) {
            let hi = (lo + BLOCK).min(n);
            let (v0, a0) = (&s0.v[lo..hi], &s0.a[lo..hi]);
            self.integrator
                .inertia_acceleration_at_rest(dt, lo, v0, a0, &mut baw[..hi - lo]);
            for i in lo..hi {
                let f_ref = (1.0 - af) * next.f_ext[i] + af * s0.f_ext[i];
                let a_w = baw[i - lo];
                let inertia = m[i] * a_w;
                let r = f_ref - inertia - ((1.0 - af) * f_now[i] + af * s0.f_int[i]);
                dq[i] = r;
                squares += r * r;
            }
        }
        let rn = squares.sqrt();
        self.summary.timings.assembly += ta.elapsed().as_secs_f64();
        if !rn.is_finite() {
            return Err(Attempt::Fatal(FemError::NonFinite(format!(
                "residual is not finite at t = {t1} s"
            ))));
        }
        let coef = self.integrator.coefficients(dt);
        if !self
            .linear
            .is_factored(coef.key(), self.asm.k_const.pattern_id)
        {
            self.factor_tangent(coef)?;
            self.summary.factorizations += 1;
        }
        self.solve_unchecked(dq)?;

        let ta = Instant::now();
        let m = self
            .asm
            .mass_diagonal()
            .expect("checked by lumped_linear_applies");
        w.f_int_at.resize(n, 0.0);
        let mut bad = None;
        for lo in (0..n).step_by(BLOCK) {
            let hi = (lo + BLOCK).min(n);
            for i in lo..hi {
                let d = dq[i];
                if !d.is_finite() && bad.is_none() {
                    bad = Some(i);
                }
                let q = s0.q[i] + d;
                next.q[i] = q;
                w.f_int_at[i] = q;
            }
            let du = Increment::Between {
                q: &next.q[lo..hi],
                q0: &s0.q[lo..hi],
            };
            let (v0, a0) = (&s0.v[lo..hi], &s0.a[lo..hi]);
            let (v, a) = (&mut next.v[lo..hi], &mut next.a[lo..hi]);
            self.integrator.kinematics(dt, lo, du, v0, a0, v, a);
            for i in lo..hi {
                w.mv[i] = m[i] * next.v[i];
            }
        }
        if let Some(i) = bad {
            w.f_int_at.clear();
            return Err(Attempt::Fatal(self.non_finite_solution(i)));
        }
        self.asm.constant_internal_force(&next.q, &mut next.f_int);
        w.mv_ready = true;
        self.summary.timings.assembly += ta.elapsed().as_secs_f64();
        next.t = t1;
        Ok((next, 1, rn))
    }
}

impl StepMethod<Driver> for LumpedLinear {
    fn name(&self) -> &'static str {
        "lumped linear step"
    }

    fn attempt(&mut self, d: &mut Driver, dt: f64) -> Result<Accepted, Attempt> {
        d.attempt_lumped(dt)
    }
}

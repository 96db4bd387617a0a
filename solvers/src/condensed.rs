//! The condensed Newton: a transient step of the partitioned solver
//! ([`crate::partition`]) that iterates only on the top system, the block interiors
//! condensed out of the residual as well as out of the tangent.
//!
//! **Why it is exact.** Number the equations as the partition does: block interiors `I`
//! (what remains after promotion) and the top set `T` (separators, carriages, and every
//! equation a variable element touches — this module promotes all of them, so the variable
//! elements live in `T × T`). Only constant, linear elements act on an interior equation,
//! so with `A = c_K·K + c_M·M + c_C·C` the effective matrix of those elements the interior
//! rows of the step's residual are *affine* in the unknowns, exactly:
//!
//! ```text
//! r_I(q) = r_I(q_b) − A_II·(q_I − q_bI) − A_IT·(q_T − q_bT)       (any base state q_b).
//! ```
//!
//! (No interior or separator equation is a finite-rotation one — checked — so `q − q_b` is
//! the plain difference there and the Newmark kinematics are linear in it.) One full Newton
//! correction from `q_b`, `(A + V)·Δ = r(q_b)`, satisfies the interior rows of that system,
//! `A_II·Δ_I + A_IT·Δ_T = r_I(q_b)`, so after it `r_I = 0` (to round-off), and every later
//! full-Newton correction keeps it zero: `Δ_I = −A_II⁻¹·A_IT·Δ_T`. Full Newton therefore
//! moves on the manifold `q_I = q_bI + δ_I(δ_T)`,
//!
//! ```text
//! δ_I(δ_T) = A_II⁻¹·(r_I(q_b) − A_IT·δ_T),        δ_T = q_T − q_bT,
//! ```
//!
//! and on it the top rows of the residual are a function of `q_T` alone:
//!
//! ```text
//! r̃_T(q_T) = g_T − S_A·δ_T + Corr·δ_T − [c_T(q) − c_T(q_b)] − [v_T(q) − v_T(q_b)],
//! g_T = r_T(q_b) − A_TI·A_II⁻¹·r_I(q_b)     (the partition's condensed right-hand side),
//! S_A = A_TT − Corr,  Corr = A_TI·A_II⁻¹·A_IT  (the top system without the variable part),
//! ```
//!
//! with `c_T` the constant elements' forces between top equations,
//! `(1−α_f)·K_TT·q_T + M_TT·a_w,T + C_TT·v_w,T`, evaluated with the true kinematics (so a
//! finite-rotation carriage body is right), and `v_T` the variable elements' forces
//! `(1−α_f)·f_var + M_var·a_w + C_var·v_w`. For a top equation without finite rotation
//! `c_T(q) − c_T(q_b) = A_TT·δ_T` and the two bracketed `A_TT` terms cancel; they are kept
//! so the formula holds for the carriages too. Newton on `r̃_T` with the tangent
//! `S = S_A + V` (the partition's top factor) then produces **the same iterates `q_T`** as
//! full Newton from `q_b`: its first correction is full Newton's (`r̃_T(q_bT) = g_T`), and at
//! every later iterate full Newton's condensed right-hand side is `r_T − A_TI·A_II⁻¹·r_I =
//! r_T = r̃_T` because `r_I = 0`. Per iteration this costs the variable elements, products
//! over the top equations (≈ 10⁴), one factorization and one solve of the top system;
//! nothing of size `n`. The interiors are recovered once, by the back-substitution
//! `δ_I(δ_T)` ([`crate::partition::Partitioned::back_substitute`]).
//!
//! **The convergence test is the full one.** The driver's test — `|r| ≤ tol·max(|f̄_ext|,
//! |f_int|, |M·a_w|) + abs_tol` and `|Δq| ≤ tol·|q| + disp_tol` on the last correction —
//! needs the interiors. The top iterations use a *screen*: `|r̃_T|` (which is `|r|`, since
//! `r_I = 0`) against twice the tolerance computed with the reference norms of the last
//! full evaluation and of the previous step, and `|Δq_T|` (a lower bound of `|Δq|`) against
//! twice `tol·|q|` estimated with the interiors of the base. When the screen passes, the
//! interiors and the last correction's interior part are recovered (one two-column
//! back-substitution), the residual is evaluated in full and the driver's own test decides.
//! It passes: the step ends with the state full Newton would have — same iterate, same
//! decision, differences of round-off only. It fails: that full evaluation becomes the new
//! base (full Newton's next correction is taken from it) and the top iterations go on. A
//! screen that passed too late would add an iteration and change the answer at the level
//! of the tolerance; the factor 2 covers changes of the reference norms within a step
//! (dominated by the static weight and its reaction), and the counter
//! [`CondensedStats::margin_exceeded`] records any verified step whose exact tolerance
//! exceeded the screen's by more than it.
//!
//! **Reduced blocks** (`partition/reduced.rs`). A reduced block's interior moves on
//! `δ_I = Ψ·δ_B + Φ·δη`, and what a correction zeroes is the modal rows `Φᵀ·r_I`, not
//! `r_I` (the rest are the constraint's reactions). The residual that must vanish is the
//! projected one, `Tᵀ·r`: the block's boundary rows `r_B + Ψᵀ·r_I`, its modal rows
//! `Φᵀ·r_I`. The argument above carries over with it. `r_I` is affine in the unknowns, so
//! on the manifold where the modal rows vanish, `δη = Â_ηη⁻¹·(Φᵀ·r_I(q_b) − Â_ηB·δ_B)`,
//! and substituting `δ_I` in `r_B + Ψᵀ·r_I` (`Â` the blocks of `Tᵀ·A·T`):
//!
//! ```text
//! r_B + Ψᵀ·r_I = [r_B(q_b) + Ψᵀ·r_I(q_b) − Â_Bη·Â_ηη⁻¹·Φᵀ·r_I(q_b)]
//!                − (Â_BB − Â_Bη·Â_ηη⁻¹·Â_ηB)·δ_B − (the top couplings, as before),
//! ```
//!
//! which is the partition's condensed right-hand side of the unprojected `r(q_b)` and its
//! top system for a reduced block (its forward pass and correction). So `r̃_T` is the top
//! part of `Tᵀ·r`, the rest of `Tᵀ·r` is zero on the manifold, the back-substitution is
//! the block's Galerkin back pass, and the iterates are the full-residual Newton's with
//! reduced blocks. The one change: the full evaluations' norm is that of `Tᵀ·r`
//! (`Driver::reduced_residual`, as the full-residual Newton's test), while the base's
//! residual stays `r` itself.
//!
//! **What is not condensed.** Anything unusual falls back to the full-residual attempt of
//! [`Driver`] for the whole step (elements reverted, the step taken again): a top set that
//! changes inside a step, the backtracking of a rising residual, the iteration limit, a
//! non-finite residual, an error — the counters say how often. Only full Newton with a
//! partitioned solver, variable elements and a constant `A` uses this path.

use crate::chunks::{par_chunks, Shared};
pub use crate::condensed_cache::CondensedStats;
use crate::condensed_cache::{CondensedCache, TopProducts};
use crate::driver::{Accepted, Attempt, Driver, State, StepWork};
use crate::held_rows;
use crate::step_method::{CondensedNewton, FullNewton, StepMethod};
use crate::time_integrator::{Increment, TimeIntegrator, Trial, BLOCK};
use railfem_framework::model::NewtonKind;
use railfem_framework::parallel::threads;
use railfem_framework::row_set::RowSet;
use std::time::Instant;

/// How a condensed attempt ended when it did not give a state.
enum Exit {
    /// Take the step again with the full-residual Newton.
    Fallback,
}

/// Work vectors of one full-size state: the driver's [`StepWork`] vectors, taken for the
/// attempt (nothing of size `n` is allocated per step once they exist).
struct Full {
    q: Vec<f64>,
    v: Vec<f64>,
    a: Vec<f64>,
    a_w: Vec<f64>,
    v_w: Vec<f64>,
    f_int: Vec<f64>,
    f_ext: Vec<f64>,
    f_ref_ext: Vec<f64>,
    inertia: Vec<f64>,
    damp: Vec<f64>,
    r: Vec<f64>,
    du: Vec<f64>,
    /// The full last correction of a verification.
    dq: Vec<f64>,
    /// The energy balance's `M·v` and `C·v` of the verified state.
    mv: Vec<f64>,
    cv: Vec<f64>,
}

impl Full {
    /// Takes the work vectors out of `sw` (the next state's storage included), at length `n`.
    fn take(sw: &mut StepWork, n: usize, finite: bool, energy: bool) -> Full {
        let next = std::mem::take(&mut sw.next);
        let mut w = Full {
            q: next.q,
            v: next.v,
            a: next.a,
            a_w: std::mem::take(&mut sw.a_w),
            v_w: std::mem::take(&mut sw.v_w),
            f_int: next.f_int,
            f_ext: next.f_ext,
            f_ref_ext: std::mem::take(&mut sw.f_ref_ext),
            inertia: std::mem::take(&mut sw.inertia),
            damp: std::mem::take(&mut sw.damp),
            r: std::mem::take(&mut sw.r),
            du: std::mem::take(&mut sw.du),
            dq: std::mem::take(&mut sw.dq),
            mv: std::mem::take(&mut sw.mv),
            cv: std::mem::take(&mut sw.cv),
        };
        for x in [
            &mut w.q,
            &mut w.v,
            &mut w.a,
            &mut w.a_w,
            &mut w.v_w,
            &mut w.f_int,
            &mut w.f_ext,
            &mut w.f_ref_ext,
            &mut w.inertia,
            &mut w.damp,
            &mut w.r,
            &mut w.dq,
        ] {
            x.resize(n, 0.0);
        }
        if finite {
            w.du.resize(n, 0.0);
        }
        if energy {
            w.mv.resize(n, 0.0);
            w.cv.resize(n, 0.0);
        }
        w
    }

    /// Gives the vectors back to `sw`; with `state`, the state's five go into the returned
    /// [`State`] instead (the driver gives that storage back after the commit).
    fn give_back(self, sw: &mut StepWork, state: Option<f64>) -> Option<State> {
        sw.a_w = self.a_w;
        sw.v_w = self.v_w;
        sw.f_ref_ext = self.f_ref_ext;
        sw.inertia = self.inertia;
        sw.damp = self.damp;
        sw.r = self.r;
        sw.du = self.du;
        sw.dq = self.dq;
        sw.mv = self.mv;
        sw.cv = self.cv;
        let s = State {
            t: state.unwrap_or(0.0),
            q: self.q,
            v: self.v,
            a: self.a,
            f_int: self.f_int,
            f_ext: self.f_ext,
        };
        match state {
            Some(_) => Some(s),
            None => {
                sw.next = s;
                None
            }
        }
    }
}

/// Which full evaluation: the step's first (the predictor `q = q_n`, whose products the
/// last verification may have formed) or a verification (which forms, in its pass, the
/// energy balance's products and the next predictor's).
#[derive(Clone, Copy, PartialEq, Eq)]
enum Evaluation {
    Predictor,
    Verification,
}

/// `dst = src` over fixed chunks on `nt` threads (`dst` takes `src`'s length), on the rows
/// of `rows` (every row: `None`).
fn par_copy(src: &[f64], dst: &mut Vec<f64>, rows: Option<&RowSet>, nt: usize) {
    dst.resize(src.len(), 0.0);
    let pd = Shared(dst.as_mut_ptr());
    par_chunks(src.len(), nt, |lo, hi| {
        for p in held_rows::parts(rows, lo, hi) {
            // SAFETY: chunks are disjoint.
            unsafe { pd.range(p.start, p.end) }.copy_from_slice(&src[p]);
        }
    });
}

/// `x = value` over fixed chunks on `nt` threads, on the rows of `rows` (every row:
/// `None`).
fn par_fill(x: &mut [f64], value: f64, rows: Option<&RowSet>, nt: usize) {
    let px = Shared(x.as_mut_ptr());
    par_chunks(x.len(), nt, |lo, hi| {
        for p in held_rows::parts(rows, lo, hi) {
            // SAFETY: chunks are disjoint.
            unsafe { px.range(p.start, p.end) }.fill(value);
        }
    });
}

/// After a verification's back-substitution: `q += dq` when `dq` holds the interiors' `δ_I`
/// from the base (`from_base`), then `(|dq|², |q|²)` over every equation, in one pass
/// (fixed chunks, so the sums do not depend on the thread count); with `rows`, on those
/// rows alone (the others' `dq` is zero: [`crate::held_rows`]).
fn recover_and_norms(
    q: &mut [f64],
    dq: &[f64],
    from_base: bool,
    rows: Option<&RowSet>,
    nt: usize,
) -> (f64, f64) {
    let pq = Shared(q.as_mut_ptr());
    let parts = par_chunks(q.len(), nt, |lo, hi| {
        // SAFETY: chunks are disjoint.
        let q = unsafe { pq.range(lo, hi) };
        let d = &dq[lo..hi];
        let (mut dn2, mut qn2) = (0.0, 0.0);
        for k in held_rows::parts(rows, lo, hi)
            .into_iter()
            .flatten()
            .map(|i| i - lo)
        {
            if from_base {
                q[k] += d[k];
            }
            dn2 += d[k] * d[k];
            qn2 += q[k] * q[k];
        }
        (dn2, qn2)
    });
    parts.iter().fold((0.0, 0.0), |a, p| (a.0 + p.0, a.1 + p.1))
}

impl Driver {
    /// Work counters of the condensed Newton.
    pub fn condensed_stats(&self) -> CondensedStats {
        self.condensed
    }

    /// Whether a verification of the condensed Newton forms, in its pass over the constant
    /// matrices, the energy balance's `M·v`, `C·v` and the next predictor's `K·q`, `M·a_w`,
    /// `C·v_w` (default `true`); `false` forms each in its own pass, as before (the same
    /// values: a comparison switch, no model key).
    pub fn set_products_ahead(&mut self, on: bool) {
        self.choice.products_ahead = on;
    }

    /// The condensed Newton's attempt ([`crate::step_method::CondensedNewton`]): the
    /// accepted state, or `None` when it does not apply to this step or hands the step back
    /// (the elements reverted; the caller takes the step by the full-residual Newton).
    pub(crate) fn attempt_condensed_or_fall_back(
        &mut self,
        cache: &mut CondensedCache,
        dt: f64,
    ) -> Option<Accepted> {
        if !self.condensed_applicable() {
            return None;
        }
        // The switch of the products ahead ([`Driver::set_products_ahead`]), applied: a
        // change forgets what was formed ahead.
        let no_ahead = !self.choice.products_ahead;
        if cache.no_products_ahead != no_ahead {
            cache.no_products_ahead = no_ahead;
            cache.ahead.dt = None;
        }
        // The constant damping changed (an absorbing layer): what was formed ahead is stale.
        if std::mem::take(&mut self.constant_changed) {
            cache.ahead.dt = None;
            cache.products = None;
        }
        let s0 = std::mem::take(&mut self.state);
        let mut sw = std::mem::take(&mut self.work);
        let n = self.neq();
        let finite = self.asm.dofmap.has_finite_rotations();
        let energy = self.energy.is_some() && !cache.no_products_ahead;
        let mut w = Full::take(&mut sw, n, finite, energy);
        // Whatever happens, the next predictor's products are valid only when this
        // attempt's accepted verification forms them again.
        let ahead_dt = cache.ahead.dt.take();
        let t1 = s0.t + dt;
        let r = self.attempt_condensed(cache, dt, &s0, &mut w, ahead_dt);
        self.release_first_iteration();
        self.state = s0;
        self.linear.keep_on_top(Vec::new());
        match r {
            Ok((iterations, residual)) => {
                cache.ahead.dt = (!cache.no_products_ahead).then_some(dt);
                let s = w.give_back(&mut sw, Some(t1));
                sw.mv_ready = energy;
                sw.cv_ready = energy;
                self.work = sw;
                self.condensed.steps += 1;
                Some(Accepted {
                    state: s.expect("state asked for"),
                    iterations,
                    residual,
                })
            }
            Err(Exit::Fallback) => {
                w.give_back(&mut sw, None);
                self.work = sw;
                self.asm.revert(&mut self.model);
                self.linear.invalidate();
                self.condensed.fallbacks += 1;
                None
            }
        }
    }

    fn condensed_applicable(&self) -> bool {
        let Some(p) = self.linear.partitioned() else {
            return false;
        };
        // Its iterations start from the committed state; another predictor takes the
        // full-residual attempt.
        if !self.model.analysis.newton.predictor.is_previous() {
            return false;
        }
        p.equations() == self.neq()
            && self.model.analysis.newton.kind == NewtonKind::Full
            && !self.asm.variable_elements().is_empty()
            && self.asm.constant_part_is_constant()
            && self
                .asm
                .dofmap
                .rotation_triples()
                .all(|t| t.iter().all(|&e| !p.in_block_interior(e)))
    }

    /// Kinematics of every equation, the full residual and its norms `(|r|, reference)`.
    /// The predictor (`q = q_n`) also forms `f̄_ext` and its norm, and takes its products
    /// from the last verification when they were formed for this state and `Δt` (compared
    /// bit for bit: `q`, `a_w`, `v_w`); a verification forms in its pass the energy
    /// balance's `M·v`, `C·v` and the next predictor's products (module documentation).
    #[allow(clippy::too_many_arguments)]
    fn full_evaluation(
        &mut self,
        cache: &mut CondensedCache,
        s0: &State,
        w: &mut Full,
        kind: Evaluation,
        ahead_dt: Option<f64>,
        (ext_norm, q2): (&mut f64, &mut f64),
        t1: f64,
        dt: f64,
    ) -> Result<(f64, f64, f64, f64), Exit> {
        let af = self.integrator.force_weight();
        let n = w.q.len();
        let nt = threads(0);
        let finite = self.asm.dofmap.has_finite_rotations();
        let predictor = kind == Evaluation::Predictor;
        // While blocks are held, the deep held rows are left as they are
        // ([`crate::held_rows`]); their sums of squares are added to the norms.
        let rows = self.held_rows.as_ref().and_then(|h| h.rows());
        let rows = rows.as_deref();
        let deep = match (rows, self.held_rows.as_mut()) {
            (Some(_), Some(h)) => h.deep_sums(&s0.q, &s0.f_int, (&w.f_ext, &s0.f_ext, af)),
            _ => [0.0; 3],
        };
        if finite {
            if predictor {
                w.q.copy_from_slice(&s0.q);
            }
            self.asm.dofmap.increment(&s0.q, &w.q, &mut w.du);
        }
        let reuse = predictor && ahead_dt == Some(dt) && cache.ahead.q.len() == n;
        let verification = !predictor && !cache.no_products_ahead;
        if verification {
            cache.ahead.resize(n);
        }
        let same = {
            let ahead = &mut cache.ahead;
            let (pq, pv, pa, paw, pvw, pfr) = (
                Shared(w.q.as_mut_ptr()),
                Shared(w.v.as_mut_ptr()),
                Shared(w.a.as_mut_ptr()),
                Shared(w.a_w.as_mut_ptr()),
                Shared(w.v_w.as_mut_ptr()),
                Shared(w.f_ref_ext.as_mut_ptr()),
            );
            let (nawp, nvwp) = (
                Shared(ahead.a_w.as_mut_ptr()),
                Shared(ahead.v_w.as_mut_ptr()),
            );
            let (du, f_ext) = (&w.du, &w.f_ext);
            let (aq, aaw, avw) = (&ahead.q, &ahead.a_w, &ahead.v_w);
            let ig: &dyn TimeIntegrator = &*self.integrator;
            let parts = par_chunks(n, nt, |lo, hi| {
                // SAFETY: chunks are disjoint.
                let (q, v, a, a_w, v_w, f_ref) = unsafe {
                    (
                        pq.range(lo, hi),
                        pv.range(lo, hi),
                        pa.range(lo, hi),
                        paw.range(lo, hi),
                        pvw.range(lo, hi),
                        pfr.range(lo, hi),
                    )
                };
                let mut same = reuse;
                let (mut ext2, mut qq) = (0.0, 0.0);
                // A block at a time: the integrator's call, then the checks, while the
                // block is in the cache.
                let parts = held_rows::parts(rows, lo, hi);
                for part in &parts {
                    for b in part.clone().step_by(BLOCK) {
                        let e = (b + BLOCK).min(part.end);
                        let (kb, ke) = (b - lo, e - lo);
                        if predictor {
                            for k in kb..ke {
                                let i = lo + k;
                                if !finite {
                                    q[k] = s0.q[i];
                                }
                                let fr = (1.0 - af) * f_ext[i] + af * s0.f_ext[i];
                                f_ref[k] = fr;
                                ext2 += fr * fr;
                                qq += q[k] * q[k];
                            }
                        }
                        let inc = if finite {
                            Increment::Given(&du[b..e])
                        } else {
                            Increment::Between {
                                q: &q[kb..ke],
                                q0: &s0.q[b..e],
                            }
                        };
                        let out = Trial {
                            v: &mut v[kb..ke],
                            a: &mut a[kb..ke],
                            a_w: &mut a_w[kb..ke],
                            v_w: &mut v_w[kb..ke],
                        };
                        ig.trial(dt, b, inc, &s0.v[b..e], &s0.a[b..e], out);
                        for k in kb..ke {
                            if !same {
                                break;
                            }
                            let i = lo + k;
                            same = q[k].to_bits() == aq[i].to_bits()
                                && a_w[k].to_bits() == aaw[i].to_bits()
                                && v_w[k].to_bits() == avw[i].to_bits();
                        }
                    }
                }
                if verification {
                    // The next predictor's kinematics, `Δu = 0` from this state.
                    for p in &parts {
                        let (a0, b0) = (p.start - lo, p.end - lo);
                        // SAFETY: chunks are disjoint.
                        let (naw, nvw) =
                            unsafe { (nawp.range(p.start, p.end), nvwp.range(p.start, p.end)) };
                        ig.next_at_rest(dt, &v[a0..b0], &a[a0..b0], naw, Some(nvw));
                    }
                }
                (same, ext2, qq)
            });
            if predictor {
                *ext_norm = (parts.iter().map(|p| p.1).sum::<f64>() + deep[2]).sqrt();
                *q2 = parts.iter().map(|p| p.2).sum::<f64>() + deep[0];
            }
            reuse && parts.iter().all(|p| p.0)
        };
        let ta = Instant::now();
        let energy = self.energy.is_some() && verification;
        if same {
            // K·q_n, M·a_w and C·v_w as the last verification formed them (the same values,
            // bit for bit, a pass over the matrices would give); the variable parts added as
            // `update_transient` adds them.
            let ahead = &mut cache.ahead;
            std::mem::swap(&mut w.f_int, &mut ahead.kq);
            std::mem::swap(&mut w.inertia, &mut ahead.inertia);
            std::mem::swap(&mut w.damp, &mut ahead.damp);
            self.asm
                .add_variable_inertia_damping(&w.a_w, &w.v_w, &mut w.inertia, &mut w.damp);
            self.condensed.predictors_reused += 1;
        } else if !verification {
            self.asm.transient_products_on(
                rows,
                (&w.q, &mut w.f_int),
                (&w.a_w, &w.v_w),
                (&mut w.inertia, &mut w.damp),
                &mut [],
                &mut [],
            );
        } else {
            let ahead = &mut cache.ahead;
            let mut mass_more: Vec<(&[f64], &mut [f64])> = vec![(&ahead.a_w, &mut ahead.inertia)];
            let mut damping_more: Vec<(&[f64], &mut [f64])> = vec![(&ahead.v_w, &mut ahead.damp)];
            if energy {
                mass_more.push((&w.v, &mut w.mv));
                damping_more.push((&w.v, &mut w.cv));
            }
            self.asm.transient_products_on(
                rows,
                (&w.q, &mut w.f_int),
                (&w.a_w, &w.v_w),
                (&mut w.inertia, &mut w.damp),
                &mut mass_more,
                &mut damping_more,
            );
            drop((mass_more, damping_more));
            if energy {
                // The energy balance's variable masses and dashpots (formed in `advance`,
                // the same after the commit).
                self.asm
                    .add_variable_inertia_damping(&w.v, &w.v, &mut w.mv, &mut w.cv);
            }
            // K·q before the variable elements add their forces: the next predictor's.
            par_copy(&w.f_int, &mut ahead.kq, rows, nt);
            par_copy(&w.q, &mut ahead.q, rows, nt);
        }
        self.asm
            .update_variable(
                &mut self.model,
                &w.q,
                &w.v,
                &w.a,
                t1,
                dt,
                &mut w.f_int,
                true,
            )
            .map_err(|_| Exit::Fallback)?;
        let pr = Shared(w.r.as_mut_ptr());
        let (f_int, inertia, damp, f_ref_ext) = (&w.f_int, &w.inertia, &w.damp, &w.f_ref_ext);
        let held = &self.frozen_rows;
        let sums = par_chunks(n, nt, |lo, hi| {
            // SAFETY: chunks are disjoint.
            let r = unsafe { pr.range(lo, hi) };
            let (mut sr, mut sf, mut si) = (0.0, 0.0, 0.0);
            for i in held_rows::parts(rows, lo, hi).into_iter().flatten() {
                let k = i - lo;
                // A row the activity window holds is a reaction ([`crate::window`]).
                let ri = if held.get(i) == Some(&true) {
                    0.0
                } else {
                    f_ref_ext[i] - inertia[i] - damp[i] - ((1.0 - af) * f_int[i] + af * s0.f_int[i])
                };
                r[k] = ri;
                sr += ri * ri;
                sf += f_int[i] * f_int[i];
                si += inertia[i] * inertia[i];
            }
            (sr, sf, si)
        });
        let (sr, sf, si) = sums.iter().fold((0.0, deep[1], 0.0), |a, s| {
            (a.0 + s.0, a.1 + s.1, a.2 + s.2)
        });
        // With reduced blocks the test reads the residual in their coordinates, as the
        // full-residual Newton's does (*Reduced blocks* above); `w.r` stays the residual.
        // The predictor's norm is no test (it seeds the rising-residual check only), so it
        // skips the projection's products with every reduced block's `Ψ` and `Φ`.
        let projected = if predictor {
            None
        } else {
            self.reduced_residual(&w.r)
        };
        let sr = projected
            .as_ref()
            .map_or(sr, |p| p.iter().map(|x| x * x).sum());
        let r_test: &[f64] = projected.as_deref().unwrap_or(&w.r);
        // Each rank's rows alone, when the ranks keep their own rows.
        // The elements' own forces count with the assembled internal force (the driver's
        // reference, [`Driver::force_norms`]), reduced over the ranks with their norms.
        let (rn, fn_, inn, elem) = if self.ranks.own_rows {
            let (v, elem) = self.force_norms(&[r_test, &w.f_int, &w.inertia]);
            (v[0], v[1], v[2], elem)
        } else {
            let elem = self.asm.element_force_norm();
            (sr.sqrt(), sf.sqrt(), si.sqrt(), elem)
        };
        self.summary.timings.assembly += ta.elapsed().as_secs_f64();
        self.condensed.full_evaluations += 1;
        let fn_ = fn_.max(elem);
        Ok((rn, ext_norm.max(fn_).max(inn), fn_, inn))
    }

    fn top_products(&mut self, cache: &mut CondensedCache) {
        let p = self.linear.partitioned().expect("partitioned");
        let gen = p.top_generation();
        if cache.products.as_ref().is_some_and(|t| t.generation == gen) {
            return;
        }
        let (k, m, c) = (&self.asm.k_const, &self.asm.m_const, &self.asm.c_const);
        let mut tp = TopProducts {
            generation: gen,
            col_ptr: vec![0],
            rows: Vec::new(),
            k: Vec::new(),
            m: Vec::new(),
            c: Vec::new(),
        };
        let same = |x: &railfem_framework::sparse::CscMatrix| {
            x.n == k.n && x.col_ptr == k.col_ptr && x.row_idx == k.row_idx
        };
        debug_assert!(same(m) && same(c));
        // Across ranks, column `j` between top equations as sent: (top row, K, M, C) per
        // entry, the top row found by `top_row`.
        let column = |j: usize, top_row: &dyn Fn(usize) -> Option<usize>| {
            let mut col = Vec::new();
            for pos in k.col_ptr[j]..k.col_ptr[j + 1] {
                if let Some(ti) = top_row(k.row_idx[pos]) {
                    col.extend([
                        ti as f64,
                        k.values[pos],
                        m.values.get(pos).copied().unwrap_or(0.0),
                        c.values.get(pos).copied().unwrap_or(0.0),
                    ]);
                }
            }
            col
        };
        if self.asm.constant_columns_kept() {
            // A promoted equation's column is kept by its block's owner alone, which sends
            // it (the top set is sorted: a top row is its position there).
            let p = self.linear.partitioned_mut().expect("partitioned");
            let top = p.top_equations().to_vec();
            let top_row = |i: usize| top.binary_search(&i).ok();
            let columns = p
                .share_top_columns(&mut |j| column(j, &top_row))
                .expect("across ranks");
            for col in columns {
                for e in col.chunks(4) {
                    tp.rows.push(e[0] as u32);
                    tp.k.push(e[1]);
                    tp.m.push(e[2]);
                    tp.c.push(e[3]);
                }
                tp.col_ptr.push(tp.rows.len());
            }
        } else {
            for &j in p.top_equations() {
                for pos in k.col_ptr[j]..k.col_ptr[j + 1] {
                    if let Some(ti) = p.top_position(k.row_idx[pos]) {
                        tp.rows.push(ti as u32);
                        tp.k.push(k.values[pos]);
                        tp.m.push(m.values.get(pos).copied().unwrap_or(0.0));
                        tp.c.push(c.values.get(pos).copied().unwrap_or(0.0));
                    }
                }
                tp.col_ptr.push(tp.rows.len());
            }
        }
        cache.products = Some(tp);
    }

    /// One step by the condensed Newton (module documentation) from the committed `s0`,
    /// in the work vectors `w`; on success `w` holds the new state and the result is
    /// `(iterations, |r|)`.
    fn attempt_condensed(
        &mut self,
        cache: &mut CondensedCache,
        dt: f64,
        s0: &State,
        w: &mut Full,
        ahead_dt: Option<f64>,
    ) -> Result<(usize, f64), Exit> {
        let n = self.neq();
        let t1 = s0.t + dt;
        let tl = Instant::now();
        self.asm
            .advance(&mut self.model, t1, dt)
            .map_err(|_| Exit::Fallback)?;
        // While blocks are held, the deep held rows keep their constant load
        // ([`crate::held_rows`]): formed on the other rows where no load reaches them.
        let rows = self.held_rows.as_ref().and_then(|h| h.rows());
        let formed = match rows.as_deref() {
            Some(r) => self.asm.external_force_on(&self.model, t1, &mut w.f_ext, r),
            None => Ok(false),
        };
        if !formed.map_err(|_| Exit::Fallback)? {
            self.asm
                .external_force(&self.model, t1, 1.0, &mut w.f_ext)
                .map_err(|_| Exit::Fallback)?;
        }
        self.summary.timings.loads += tl.elapsed().as_secs_f64();
        self.linear.keep_on_top(self.asm.variable_equations());
        // Scratch for the variable elements' forces: zero between uses.
        let mut scratch = std::mem::take(&mut cache.var_scratch);
        for x in &mut scratch {
            if x.len() != n {
                *x = vec![0.0; n];
            }
        }
        let r = self.condensed_iterations(cache, dt, s0, w, ahead_dt, &mut scratch);
        // Every path that writes the scratch zeroes it again before it can return `Ok`; a
        // fallback may leave values in it, and it is then dropped (formed afresh next time).
        if r.is_ok() {
            cache.var_scratch = scratch;
        }
        r
    }

    /// The iterations of [`Driver::attempt_condensed`], after the model was advanced to
    /// `t1` and `f_ext(t1)` formed into `w.f_ext`.
    fn condensed_iterations(
        &mut self,
        cache: &mut CondensedCache,
        dt: f64,
        s0: &State,
        w: &mut Full,
        ahead_dt: Option<f64>,
        [f_var, in_var, damp_var]: &mut [Vec<f64>; 3],
    ) -> Result<(usize, f64), Exit> {
        let t1 = s0.t + dt;
        let nt = threads(0);
        let af = self.integrator.force_weight();
        let settings = self.model.analysis.newton;
        let coef = self.integrator.coefficients(dt);
        let finite = self.asm.dofmap.has_finite_rotations();
        // `f̄_ext` and its norm: formed by the predictor's evaluation.
        let mut ext_norm: f64 = 0.0;
        let mut iters = 0;
        let mut rn_prev = f64::INFINITY;
        // The base of the top iterations and the last correction.
        let mut top: Vec<usize> = Vec::new();
        let mut generation = 0;
        let mut g: Vec<f64> = Vec::new();
        let (mut qb, mut awb, mut vwb, mut varb) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        let mut qbi_norm2 = 0.0;
        // |q|² of the base (formed in the passes that produce the base's q).
        let mut base_q2 = 0.0;
        let mut last_dq: Vec<f64> = Vec::new();
        let mut last_from_base = true;
        let mut full_now = true;
        // Reference norms for the screen: the previous step's and the last full evaluation
        // after a correction (the predictor's inertia is not representative).
        let (mut f_norm_est, mut in_norm_est) = cache.last_norms.unwrap_or((0.0, 0.0));
        // The predictor and the first base with the contact's statuses of the last
        // converged step (`FirstActiveSet`); released once the base's variable forces are
        // read, before any other evaluation.
        self.hold_first_iteration(false);
        for it in 0..=settings.max_iter {
            if !full_now {
                // --- An iteration on the top system alone.
                let ta = Instant::now();
                if finite {
                    self.asm.dofmap.increment(&s0.q, &w.q, &mut w.du);
                }
                // The top equations are few and scattered: one call each.
                for &i in &top {
                    let (j, ig) = (i + 1, &*self.integrator);
                    let inc = if finite {
                        Increment::Given(&w.du[i..j])
                    } else {
                        Increment::Between {
                            q: &w.q[i..j],
                            q0: &s0.q[i..j],
                        }
                    };
                    let out = Trial {
                        v: &mut w.v[i..j],
                        a: &mut w.a[i..j],
                        a_w: &mut w.a_w[i..j],
                        v_w: &mut w.v_w[i..j],
                    };
                    ig.trial(dt, i, inc, &s0.v[i..j], &s0.a[i..j], out);
                }
                self.asm
                    .update_variable(&mut self.model, &w.q, &w.v, &w.a, t1, dt, f_var, true)
                    .map_err(|_| Exit::Fallback)?;
                self.asm
                    .add_variable_inertia_damping(&w.a_w, &w.v_w, in_var, damp_var);
                let nt_top = top.len();
                let delta: Vec<f64> = (0..nt_top).map(|k| w.q[top[k]] - qb[k]).collect();
                let p = self.linear.partitioned_mut().expect("partitioned");
                let mut rt = vec![0.0; nt_top];
                p.top_constant_times(&delta, &mut rt);
                // rt = g − S_A·δ + (A_TT·δ − Δc_T) − Δv_T
                for k in 0..nt_top {
                    rt[k] = g[k] - rt[k];
                }
                let tp = cache.products.as_ref().expect("built at the base");
                for (j, &gj) in top.iter().enumerate() {
                    let dk = coef.k * delta[j] - (1.0 - af) * (w.q[gj] - qb[j]);
                    let dm = coef.m * delta[j] - (w.a_w[gj] - awb[j]);
                    let dc = coef.c * delta[j] - (w.v_w[gj] - vwb[j]);
                    if dk == 0.0 && dm == 0.0 && dc == 0.0 {
                        continue;
                    }
                    for pos in tp.col_ptr[j]..tp.col_ptr[j + 1] {
                        rt[tp.rows[pos] as usize] +=
                            tp.k[pos] * dk + tp.m[pos] * dm + tp.c[pos] * dc;
                    }
                }
                for (k, &gk) in top.iter().enumerate() {
                    let var = (1.0 - af) * f_var[gk] + in_var[gk] + damp_var[gk];
                    rt[k] -= var - varb[k];
                    f_var[gk] = 0.0;
                    in_var[gk] = 0.0;
                    damp_var[gk] = 0.0;
                }
                self.summary.timings.assembly += ta.elapsed().as_secs_f64();
                let rn = rt.iter().map(|x| x * x).sum::<f64>().sqrt();
                if !rn.is_finite() {
                    return Err(Exit::Fallback);
                }
                let reference = ext_norm.max(f_norm_est).max(in_norm_est);
                let force_screen = rn <= 2.0 * settings.tol * reference + settings.abs_tol;
                let dn_top = last_dq.iter().map(|x| x * x).sum::<f64>().sqrt();
                let qt2: f64 = top.iter().map(|&i| w.q[i] * w.q[i]).sum();
                let q_est = (qt2 + qbi_norm2).sqrt();
                let disp_screen = dn_top <= 2.0 * settings.tol * q_est + settings.disp_tol;
                if self.trace {
                    eprintln!(
                        "t = {t1:.6} s, dt = {dt:.3e} s, iteration {it} (top system): |R| = {rn:.3e} N (screen {:.3e})",
                        2.0 * settings.tol * reference + settings.abs_tol
                    );
                }
                if force_screen && disp_screen {
                    // Verify with the full residual: recover the interiors (and the last
                    // correction's interior part) first.
                    let tr = Instant::now();
                    let delta_now: Vec<f64> = (0..nt_top).map(|k| w.q[top[k]] - qb[k]).collect();
                    let rows = self.held_rows.as_ref().and_then(|h| h.rows());
                    par_fill(&mut w.dq, 0.0, rows.as_deref(), nt);
                    let p = self.linear.partitioned_mut().expect("partitioned");
                    let res = if last_from_base {
                        p.back_substitute(&[(Some(&w.r), &delta_now)], &mut [&mut w.dq], true)
                    } else {
                        p.back_substitute(
                            &[(Some(&w.r), &delta_now), (None, &last_dq)],
                            &mut [&mut w.q, &mut w.dq],
                            true,
                        )
                    };
                    res.map_err(|_| Exit::Fallback)?;
                    // Interiors of `dq` hold δ_I when the last correction came from the base
                    // (add them to the base's interiors), else the last correction's interior
                    // part; its top entries are zero (the top part is `last_dq`).
                    let (dn2, mut qn2) =
                        recover_and_norms(&mut w.q, &w.dq, last_from_base, rows.as_deref(), nt);
                    if let (Some(_), Some(h)) = (&rows, self.held_rows.as_mut()) {
                        qn2 += h.deep_sums(&s0.q, &s0.f_int, (&w.f_ext, &s0.f_ext, af))[0];
                    }
                    let dn2 = dn2 + last_dq.iter().map(|x| x * x).sum::<f64>();
                    self.summary.timings.solve += tr.elapsed().as_secs_f64();
                    let (dn, qn) = (dn2.sqrt(), qn2.sqrt());
                    // A rejected verification's state is the next base.
                    base_q2 = qn2;
                    let disp_ok = dn <= settings.tol * qn + settings.disp_tol;
                    let (rn_full, reference_full, fn_, inn) = self.full_evaluation(
                        cache,
                        s0,
                        w,
                        Evaluation::Verification,
                        None,
                        (&mut ext_norm, &mut 0.0),
                        t1,
                        dt,
                    )?;
                    let force_ok = rn_full <= settings.tol * reference_full + settings.abs_tol;
                    if settings.tol * reference_full > 2.0 * settings.tol * reference
                        || settings.tol * qn > 2.0 * settings.tol * q_est
                    {
                        self.condensed.margin_exceeded += 1;
                    }
                    if self.trace {
                        eprintln!(
                            "t = {t1:.6} s, iteration {it} verified in full: |R| = {rn_full:.3e} N (tolerance {:.3e} = tol {:.1e} · max(|f_ext|, |f_int|, |f_e|, |M·a|) {reference_full:.3e} + abs_tol {:.1e}), |dq| = {dn:.3e}",
                            settings.tol * reference_full + settings.abs_tol,
                            settings.tol,
                            settings.abs_tol
                        );
                    }
                    if force_ok && disp_ok {
                        cache.last_norms = Some((fn_, inn));
                        return Ok((iters, rn_full));
                    }
                    self.condensed.rejected += 1;
                    f_norm_est = fn_;
                    in_norm_est = inn;
                    // The full evaluation is the new base: continue as after one.
                    if it == settings.max_iter || (it >= 2 && rn_full > rn_prev) {
                        return Err(Exit::Fallback);
                    }
                    rn_prev = rn_full;
                } else {
                    if it == settings.max_iter || (it >= 2 && rn > rn_prev) {
                        return Err(Exit::Fallback);
                    }
                    self.factor_tangent(coef).map_err(|_| Exit::Fallback)?;
                    self.summary.factorizations += 1;
                    let p = self.linear.partitioned_mut().expect("partitioned");
                    if p.top_generation() != generation {
                        return Err(Exit::Fallback);
                    }
                    let ts = Instant::now();
                    p.solve_top(&mut rt).map_err(|_| Exit::Fallback)?;
                    self.summary.timings.solve += ts.elapsed().as_secs_f64();
                    self.condensed.top_iterations += 1;
                    iters += 1;
                    rn_prev = rn;
                    self.top_correction(&top, &rt, &mut w.q);
                    last_dq = rt;
                    last_from_base = false;
                    continue;
                }
            } else {
                // --- A full evaluation (the predictor).
                let (rn, _reference, fn_, _inn) = self.full_evaluation(
                    cache,
                    s0,
                    w,
                    Evaluation::Predictor,
                    ahead_dt,
                    (&mut ext_norm, &mut base_q2),
                    t1,
                    dt,
                )?;
                if !rn.is_finite() || it == settings.max_iter {
                    return Err(Exit::Fallback);
                }
                f_norm_est = f_norm_est.max(fn_);
                if self.trace {
                    eprintln!(
                        "t = {t1:.6} s, dt = {dt:.3e} s, iteration {it} (full): |R| = {rn:.3e} N"
                    );
                }
                rn_prev = rn;
            }
            // --- A new base at the full state `w.q` with the full residual `w.r`: factor,
            // condense the residual, solve the top system.
            self.factor_tangent(coef).map_err(|_| Exit::Fallback)?;
            self.summary.factorizations += 1;
            self.top_products(cache);
            let off_top = {
                let p = self.linear.partitioned().expect("partitioned");
                let on_top = self.linear.kept_on_top();
                on_top.iter().any(|&e| p.top_position(e).is_none())
            };
            let p = self.linear.partitioned_mut().expect("partitioned");
            generation = p.top_generation();
            top = p.top_equations().to_vec();
            if off_top {
                return Err(Exit::Fallback);
            }
            let ts = Instant::now();
            g = p.condense_rhs(&w.r).map_err(|_| Exit::Fallback)?;
            let mut dq = g.clone();
            p.solve_top(&mut dq).map_err(|_| Exit::Fallback)?;
            self.summary.timings.solve += ts.elapsed().as_secs_f64();
            // The base's top values and variable forces.
            qb = top.iter().map(|&i| w.q[i]).collect();
            awb = top.iter().map(|&i| w.a_w[i]).collect();
            vwb = top.iter().map(|&i| w.v_w[i]).collect();
            self.asm.add_variable_resisting(&self.model, f_var);
            self.asm
                .add_variable_inertia_damping(&w.a_w, &w.v_w, in_var, damp_var);
            varb = top
                .iter()
                .map(|&i| {
                    let x = (1.0 - af) * f_var[i] + in_var[i] + damp_var[i];
                    f_var[i] = 0.0;
                    in_var[i] = 0.0;
                    damp_var[i] = 0.0;
                    x
                })
                .collect();
            let qall2 = base_q2;
            let qt2: f64 = qb.iter().map(|x| x * x).sum();
            qbi_norm2 = (qall2 - qt2).max(0.0);
            self.release_first_iteration();
            iters += 1;
            self.top_correction(&top, &dq, &mut w.q);
            last_dq = dq;
            last_from_base = true;
            full_now = false;
        }
        Err(Exit::Fallback)
    }

    /// `q ← q ⊕ dq` on the top equations (finite rotations composed).
    fn top_correction(&self, top: &[usize], dq_top: &[f64], q: &mut [f64]) {
        if self.asm.dofmap.has_finite_rotations() {
            let mut dq = vec![0.0; q.len()];
            for (&i, &d) in top.iter().zip(dq_top) {
                dq[i] = d;
            }
            self.asm.dofmap.add_correction(q, &dq);
        } else {
            for (&i, &d) in top.iter().zip(dq_top) {
                q[i] += d;
            }
        }
    }
}

impl StepMethod<Driver> for CondensedNewton {
    fn name(&self) -> &'static str {
        "condensed Newton"
    }

    fn attempt(&mut self, d: &mut Driver, dt: f64) -> Result<Accepted, Attempt> {
        if let Some(accepted) = d.attempt_condensed_or_fall_back(&mut self.cache, dt) {
            return Ok(accepted);
        }
        FullNewton.attempt(d, dt)
    }
}

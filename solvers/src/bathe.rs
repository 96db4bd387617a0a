//! The Bathe composite implicit method (Bathe & Baig 2005; Bathe 2007): each step of `Δt`
//! is two implicit sub-steps, a trapezoidal one to `t + γ·Δt` and a three-point backward
//! Euler one to `t + Δt`. It dissipates high frequencies (spectral radius → 0 as
//! `Δt/T → ∞`) with little period error in the low ones, and keeps the trapezoidal rule's
//! stability in nonlinear runs where that rule alone can blow up (Bathe 2007).
//!
//! **Sub-step 1** (stage 0, length `h₁ = γ·Δt`) is the trapezoidal rule, Newmark's method
//! with `β = ¼`, `γ_N = ½` ([`crate::integrator::Integrator::newmark`]), balance at
//! `t + γΔt`.
//!
//! **Sub-step 2** (stage 1, length `h₂ = (1−γ)·Δt`) differentiates the quadratic through
//! `(t, u_n)`, `(t+γΔt, u_γ)`, `(t+Δt, u_{n+1})` at its end: the Lagrange weights'
//! derivatives at `x₂ = Δt` (nodes `x₀ = 0`, `x₁ = γΔt`) are
//!
//! ```text
//! c1 = (x₂−x₁)/((x₀−x₁)(x₀−x₂)) =  (1−γ)/(γ·Δt)
//! c2 = (x₂−x₀)/((x₁−x₀)(x₁−x₂)) = −1/(γ·(1−γ)·Δt)
//! c3 = 1/(x₂−x₀) + 1/(x₂−x₁)    =  (2−γ)/((1−γ)·Δt)
//! v_{n+1} = c1·u_n + c2·u_γ + c3·u_{n+1}
//! a_{n+1} = c1·v_n + c2·v_γ + c3·v_{n+1}
//! ```
//!
//! (Bathe 2007 with γ = ½; Bathe & Noh 2012 for general γ), and the balance is
//! `M·a_{n+1} + C·v_{n+1} + f_int(u_{n+1}) = f_ext(t+Δt)`. Since `c1 + c2 + c3 = 0`, with
//! the increment `Δu = u_{n+1} − u_γ` from the stage's start:
//!
//! ```text
//! v = c3·Δu + c1·(u_n − u_γ)        a = c3·v + (c1·v_n + c2·v_γ)
//! ∂v/∂Δu = c3,   ∂a/∂Δu = c3²   ⇒   Coefficients { k: 1, c: c3, m: c3² }
//! ```
//!
//! The two history terms `c1·(u_n − u_γ)` and `c1·v_n + c2·v_γ` are formed once per step at
//! the start of sub-step 2 ([`TimeIntegrator::begin_stage`]). With `γ = 2 − √2` the two
//! sub-steps have the same effective matrix (`2/h₁ = c3 = (2+√2)/Δt`, so `4/h₁² = c3²`), one
//! factorization serves both (Bathe & Noh 2012); `γ = ½` is the original form.
//!
//! Each sub-step is a Newton solve of its own, committed on its own (the energy ledger
//! records both). When a sub-step does not converge, the driver takes the rest of the step
//! as shorter Bathe steps ([`crate::driver`]).
//!
//! References: K. J. Bathe, M. M. I. Baig, "On a composite implicit time integration
//! procedure for nonlinear dynamics", Computers & Structures 83 (2005) 2513–2524;
//! K. J. Bathe, "Conserving energy and momentum in nonlinear dynamics: a simple implicit
//! time integration scheme", Computers & Structures 85 (2007) 437–445; K. J. Bathe,
//! G. Noh, "Insight into an implicit time integration scheme for structural dynamics",
//! Computers & Structures 98–99 (2012) 1–6.

use crate::integrator::Integrator;
use crate::state::State;
use crate::time_integrator::{Increment, IntegratorEntry, TimeIntegrator, Trial};
use railfem_framework::model::AnalysisSpec;
use railfem_framework::{Coefficients, FemError};

railfem_framework::element_params! {
    /// Parameters of the Bathe composite method (`[analysis.integrator_parameters]`).
    pub struct BatheParams {
        /// Splitting ratio γ in (0, 1): sub-step 1 ends at t + γ·Δt (0.5: Bathe 2007; 2 − √2 ≈ 0.5858: one factorization for both sub-steps)
        gamma: f64 ["-"] = 0.5,
    }
}

/// The Bathe composite method with splitting ratio `γ` (module documentation).
#[derive(Debug, Clone)]
pub struct Bathe {
    /// Splitting ratio γ.
    gamma: f64,
    /// The trapezoidal rule of sub-step 1.
    trapezoidal: Integrator,
    /// The stage the next attempts solve (0 or 1).
    stage: usize,
    /// The whole step's `Δt` (sub-step 2's weights depend on it).
    dt: f64,
    /// `u_n` and `v_n`, kept at the start of sub-step 1.
    q_n: Vec<f64>,
    v_n: Vec<f64>,
    /// Sub-step 2's history terms `c1·(u_n − u_γ)` and `c1·v_n + c2·v_γ`.
    hist_v: Vec<f64>,
    hist_a: Vec<f64>,
}

impl Bathe {
    /// The method with splitting ratio `gamma` in (0, 1).
    pub fn new(gamma: f64) -> Self {
        Bathe {
            gamma,
            trapezoidal: Integrator::newmark(0.25, 0.5),
            stage: 0,
            dt: f64::NAN,
            q_n: Vec::new(),
            v_n: Vec::new(),
            hist_v: Vec::new(),
            hist_a: Vec::new(),
        }
    }

    /// Sub-step 2's weights `(c1, c2, c3)` for a step of `dt` (module documentation).
    pub fn weights(&self, dt: f64) -> (f64, f64, f64) {
        let g = self.gamma;
        (
            (1.0 - g) / (g * dt),
            -1.0 / ((1.0 - g) * g * dt),
            (2.0 - g) / ((1.0 - g) * dt),
        )
    }

    /// `c3` of the current step from sub-step 2's length `h = (1−γ)·Δt`.
    fn c3(&self, h: f64) -> f64 {
        (2.0 - self.gamma) / h
    }
}

impl TimeIntegrator for Bathe {
    fn name(&self) -> &'static str {
        "bathe"
    }

    fn stages(&self) -> usize {
        2
    }

    fn stage_length(&self, stage: usize, dt: f64) -> f64 {
        if stage == 0 {
            self.gamma * dt
        } else {
            (1.0 - self.gamma) * dt
        }
    }

    fn begin_stage(&mut self, stage: usize, dt: f64, start: &State) {
        self.stage = stage;
        self.dt = dt;
        if stage == 0 {
            self.q_n.clone_from(&start.q);
            self.v_n.clone_from(&start.v);
            return;
        }
        let (c1, c2, _) = self.weights(dt);
        let n = start.q.len();
        self.hist_v.resize(n, 0.0);
        self.hist_a.resize(n, 0.0);
        for i in 0..n {
            self.hist_v[i] = c1 * (self.q_n[i] - start.q[i]);
            self.hist_a[i] = c1 * self.v_n[i] + c2 * start.v[i];
        }
    }

    fn coefficients(&self, h: f64) -> Coefficients {
        if self.stage == 0 {
            return self.trapezoidal.coefficients(h);
        }
        let c3 = self.c3(h);
        Coefficients {
            k: 1.0,
            m: c3 * c3,
            c: c3,
        }
    }

    fn force_weight(&self) -> f64 {
        0.0
    }

    fn trial(&self, h: f64, lo: usize, du: Increment<'_>, v0: &[f64], a0: &[f64], out: Trial<'_>) {
        if self.stage == 0 {
            return TimeIntegrator::trial(&self.trapezoidal, h, lo, du, v0, a0, out);
        }
        // The balance is at the sub-step's end: the weighted values are the end's.
        let Trial { v, a, a_w, v_w } = out;
        self.kinematics(h, lo, du, v0, a0, v, a);
        a_w.copy_from_slice(a);
        v_w.copy_from_slice(v);
    }

    fn kinematics(
        &self,
        h: f64,
        lo: usize,
        du: Increment<'_>,
        v0: &[f64],
        a0: &[f64],
        v: &mut [f64],
        a: &mut [f64],
    ) {
        if self.stage == 0 {
            return TimeIntegrator::kinematics(&self.trapezoidal, h, lo, du, v0, a0, v, a);
        }
        let n = v.len();
        let (hv, ha) = (&self.hist_v[lo..lo + n], &self.hist_a[lo..lo + n]);
        let c3 = self.c3(h);
        du.for_each(n, |i, d| {
            v[i] = c3 * d + hv[i];
            a[i] = c3 * v[i] + ha[i];
        });
    }

    fn inertia_acceleration_at_rest(
        &self,
        h: f64,
        lo: usize,
        v0: &[f64],
        a0: &[f64],
        a_w: &mut [f64],
    ) {
        if self.stage == 0 {
            return self
                .trapezoidal
                .inertia_acceleration_at_rest(h, lo, v0, a0, a_w);
        }
        // Δu = 0: v = c1·(u_n − u_γ), a = c3·v + (c1·v_n + c2·v_γ).
        let n = a_w.len();
        let (hv, ha) = (&self.hist_v[lo..lo + n], &self.hist_a[lo..lo + n]);
        let c3 = self.c3(h);
        for i in 0..n {
            a_w[i] = c3 * hv[i] + ha[i];
        }
    }

    fn next_at_rest(
        &self,
        _h: f64,
        _v: &[f64],
        _a: &[f64],
        a_w: &mut [f64],
        v_w: Option<&mut [f64]>,
    ) {
        // The next stage is the other sub-step: nothing to form ahead.
        a_w.fill(f64::NAN);
        if let Some(v_w) = v_w {
            v_w.fill(f64::NAN);
        }
    }
}

fn make(a: &AnalysisSpec, origin: &str) -> Result<Box<dyn TimeIntegrator>, FemError> {
    let p: BatheParams = crate::time_integrator::parameters(a, "bathe", origin)?;
    if !(p.gamma > 0.0 && p.gamma < 1.0) {
        return Err(FemError::input(
            format!("{origin}: [analysis.integrator_parameters] gamma"),
            format!(
                "γ = {} is outside (0, 1); give 0.5 (Bathe 2007) or 2 − √2 ≈ 0.5858579",
                p.gamma
            ),
        ));
    }
    Ok(Box::new(Bathe::new(p.gamma)))
}

fn keys() -> Vec<railfem_framework::registry::ParamDoc> {
    <BatheParams as railfem_framework::registry::Params>::docs()
}

inventory::submit! {
    IntegratorEntry {
        name: "bathe",
        description: "Bathe composite implicit method (Bathe & Baig 2005; Bathe 2007): trapezoidal sub-step to t + γΔt, then three-point backward Euler; L-stable",
        params: keys,
        own_table: true,
        make,
    }
}

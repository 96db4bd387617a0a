//! Time integrators of the generalized-α family: Newmark-β, HHT-α and Chung–Hulbert
//! generalized-α, as one set of four coefficients.
//!
//! The balance is enforced at the intermediate times `n+1−α_m` (inertia) and `n+1−α_f`
//! (damping, internal and external forces):
//!
//! `M·a_{n+1−α_m} + C·v_{n+1−α_f} + f_int,{n+1−α_f} = f_ext,{n+1−α_f}`,
//!
//! with `x_{n+1−α} = (1−α)·x_{n+1} + α·x_n` (forces of a nonlinear element averaged the same
//! way) and Newmark's updates `u_{n+1} = u_n + Δt·v_n + Δt²·((½−β)·a_n + β·a_{n+1})`,
//! `v_{n+1} = v_n + Δt·((1−γ)·a_n + γ·a_{n+1})`. With `α_m = α_f = 0` this is Newmark's
//! method, which in incremental form is the paper's Eqs. 3–4: the out-of-balance force
//! `ΔF = F_ext(n+1) − F_M(n) − F_C(n) − F_K(n) − F_rigid` is removed by
//! `M·ä + C·ḋ + K·Δd` with the current matrices.

use crate::time_integrator::{Increment, IntegratorEntry, TimeIntegrator, Trial};
use railfem_framework::model::{AnalysisSpec, IntegratorKind};
use railfem_framework::registry::ParamDoc;
pub use railfem_framework::Coefficients;
use railfem_framework::FemError;

/// The four coefficients of a generalized-α integrator.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Integrator {
    /// Newmark β.
    pub beta: f64,
    /// Newmark γ.
    pub gamma: f64,
    /// Weight of the old step in the inertia term.
    pub alpha_m: f64,
    /// Weight of the old step in the force terms.
    pub alpha_f: f64,
}

impl Integrator {
    /// Newmark-β with the given β and γ.
    pub fn newmark(beta: f64, gamma: f64) -> Self {
        Integrator {
            beta,
            gamma,
            alpha_m: 0.0,
            alpha_f: 0.0,
        }
    }

    /// Hilber–Hughes–Taylor with `α ∈ [0, 1/3]` (Hilber's α = −α here):
    /// `γ = ½ + α`, `β = ¼·(1 + α)²`.
    pub fn hht(alpha: f64) -> Self {
        Integrator {
            beta: 0.25 * (1.0 + alpha).powi(2),
            gamma: 0.5 + alpha,
            alpha_m: 0.0,
            alpha_f: alpha,
        }
    }

    /// Chung–Hulbert generalized-α with high-frequency spectral radius `ρ∞ ∈ [0, 1]`:
    /// `α_m = (2ρ∞ − 1)/(ρ∞ + 1)`, `α_f = ρ∞/(ρ∞ + 1)`, `γ = ½ − α_m + α_f`,
    /// `β = ¼·(1 − α_m + α_f)²`.
    pub fn generalized_alpha(rho_inf: f64) -> Self {
        let am = (2.0 * rho_inf - 1.0) / (rho_inf + 1.0);
        let af = rho_inf / (rho_inf + 1.0);
        Integrator {
            beta: 0.25 * (1.0 - am + af).powi(2),
            gamma: 0.5 - am + af,
            alpha_m: am,
            alpha_f: af,
        }
    }

    /// The generalized-α integrator an `[analysis]` table asks for; `None` when it names
    /// another registered integrator ([`crate::time_integrator::resolve`] finds any).
    pub fn from_spec(a: &AnalysisSpec) -> Option<Self> {
        match a.integrator {
            IntegratorKind::Newmark => Some(Integrator::newmark(a.beta, a.gamma)),
            IntegratorKind::Hht => Some(Integrator::hht(a.alpha)),
            IntegratorKind::GeneralizedAlpha => Some(Integrator::generalized_alpha(a.rho_inf)),
            IntegratorKind::Registered(_) => None,
        }
    }

    /// The effective tangent's weights for step `dt`: the derivatives of the balance's
    /// `f_int`, `C·v` and `M·a` terms with respect to the displacement increment, `k = 1−α_f`
    /// (`u_{n+1−α_f}`), `c = (1−α_f)·γ/(β·Δt)` (`v_{n+1−α_f}`) and
    /// `m = (1−α_m)/(β·Δt²)` (`a_{n+1−α_m}`), from Newmark's updates above.
    pub fn coefficients(&self, dt: f64) -> Coefficients {
        Coefficients {
            k: 1.0 - self.alpha_f,
            m: (1.0 - self.alpha_m) / (self.beta * dt * dt),
            c: (1.0 - self.alpha_f) * self.gamma / (self.beta * dt),
        }
    }

    /// Acceleration and velocity at `n+1` from the displacement increment `Δu = u − u_n`.
    #[inline]
    pub fn kinematics(&self, dt: f64, du: f64, vn: f64, an: f64) -> (f64, f64) {
        let a = du / (self.beta * dt * dt) - vn / (self.beta * dt) - (0.5 / self.beta - 1.0) * an;
        let v = vn + dt * ((1.0 - self.gamma) * an + self.gamma * a);
        (v, a)
    }

    /// The trial state of one equation from its increment `Δu`: velocity and acceleration
    /// at `n+1`, then the acceleration and velocity at the intermediate times where the
    /// α-methods weigh inertia and damping, `a_{n+1−α_m}` and `v_{n+1−α_f}`.
    #[inline]
    pub fn trial(&self, dt: f64, du: f64, vn: f64, an: f64) -> (f64, f64, f64, f64) {
        let (v, a) = self.kinematics(dt, du, vn, an);
        let a_w = (1.0 - self.alpha_m) * a + self.alpha_m * an;
        let v_w = (1.0 - self.alpha_f) * v + self.alpha_f * vn;
        (v, a, a_w, v_w)
    }
}

/// The family behind the trait: each slice call runs the per-equation formulas above in a
/// loop of its own, so the values are those of the inline calls, to the bit.
impl TimeIntegrator for Integrator {
    fn name(&self) -> &'static str {
        if self.alpha_m != 0.0 {
            "generalized_alpha"
        } else if self.alpha_f != 0.0 {
            "hht"
        } else {
            "newmark"
        }
    }

    fn coefficients(&self, h: f64) -> Coefficients {
        Integrator::coefficients(self, h)
    }

    fn force_weight(&self) -> f64 {
        self.alpha_f
    }

    #[inline]
    fn trial(&self, h: f64, _lo: usize, du: Increment<'_>, v0: &[f64], a0: &[f64], out: Trial<'_>) {
        let Trial { v, a, a_w, v_w } = out;
        let n = v.len();
        let (v0, a0, a, a_w, v_w) = (
            &v0[..n],
            &a0[..n],
            &mut a[..n],
            &mut a_w[..n],
            &mut v_w[..n],
        );
        du.for_each(n, |i, d| {
            (v[i], a[i], a_w[i], v_w[i]) = Integrator::trial(self, h, d, v0[i], a0[i]);
        });
    }

    #[inline]
    fn kinematics(
        &self,
        h: f64,
        _lo: usize,
        du: Increment<'_>,
        v0: &[f64],
        a0: &[f64],
        v: &mut [f64],
        a: &mut [f64],
    ) {
        let n = v.len();
        let (v0, a0, a) = (&v0[..n], &a0[..n], &mut a[..n]);
        du.for_each(n, |i, d| {
            (v[i], a[i]) = Integrator::kinematics(self, h, d, v0[i], a0[i]);
        });
    }

    #[inline]
    fn inertia_acceleration_at_rest(
        &self,
        h: f64,
        _lo: usize,
        v0: &[f64],
        a0: &[f64],
        a_w: &mut [f64],
    ) {
        self.next_at_rest(h, v0, a0, a_w, None);
    }

    #[inline]
    fn next_at_rest(&self, h: f64, v: &[f64], a: &[f64], a_w: &mut [f64], v_w: Option<&mut [f64]>) {
        let n = a_w.len();
        let (v, a) = (&v[..n], &a[..n]);
        match v_w {
            None => {
                for i in 0..n {
                    a_w[i] = Integrator::trial(self, h, 0.0, v[i], a[i]).2;
                }
            }
            Some(v_w) => {
                let v_w = &mut v_w[..n];
                for i in 0..n {
                    (_, _, a_w[i], v_w[i]) = Integrator::trial(self, h, 0.0, v[i], a[i]);
                }
            }
        }
    }
}

fn newmark_keys() -> Vec<ParamDoc> {
    vec![
        ParamDoc {
            key: "beta",
            unit: "-",
            default: Some(serde_json::json!(0.25)),
            doc: "Newmark β",
        },
        ParamDoc {
            key: "gamma",
            unit: "-",
            default: Some(serde_json::json!(0.5)),
            doc: "Newmark γ",
        },
    ]
}

fn hht_keys() -> Vec<ParamDoc> {
    vec![ParamDoc {
        key: "alpha",
        unit: "-",
        default: Some(serde_json::json!(0.05)),
        doc: "HHT α in [0, 1/3] (0 is the trapezoidal rule); γ = ½ + α, β = ¼·(1 + α)²",
    }]
}

fn generalized_alpha_keys() -> Vec<ParamDoc> {
    vec![ParamDoc {
        key: "rho_inf",
        unit: "-",
        default: Some(serde_json::json!(0.8)),
        doc: "spectral radius at infinite frequency, in [0, 1]",
    }]
}

fn make_newmark(a: &AnalysisSpec, _origin: &str) -> Result<Box<dyn TimeIntegrator>, FemError> {
    Ok(Box::new(Integrator::newmark(a.beta, a.gamma)))
}

fn make_hht(a: &AnalysisSpec, _origin: &str) -> Result<Box<dyn TimeIntegrator>, FemError> {
    Ok(Box::new(Integrator::hht(a.alpha)))
}

fn make_generalized_alpha(a: &AnalysisSpec, _o: &str) -> Result<Box<dyn TimeIntegrator>, FemError> {
    Ok(Box::new(Integrator::generalized_alpha(a.rho_inf)))
}

inventory::submit! {
    IntegratorEntry {
        name: "newmark",
        description: "Newmark-β (Newmark 1959); β = ¼, γ = ½ is the trapezoidal rule (average acceleration)",
        params: newmark_keys,
        own_table: false,
        make: make_newmark,
    }
}

inventory::submit! {
    IntegratorEntry {
        name: "hht",
        description: "Hilber–Hughes–Taylor α (Hilber, Hughes & Taylor 1977): numerical damping of high modes",
        params: hht_keys,
        own_table: false,
        make: make_hht,
    }
}

inventory::submit! {
    IntegratorEntry {
        name: "generalized_alpha",
        description: "Chung–Hulbert generalized-α (Chung & Hulbert 1993), set by ρ∞",
        params: generalized_alpha_keys,
        own_table: false,
        make: make_generalized_alpha,
    }
}

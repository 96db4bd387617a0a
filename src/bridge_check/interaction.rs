//! Vehicle–bridge interaction with moving sprung masses: each axle is an unsprung mass on
//! a linear contact spring, carrying its share of the sprung mass on a primary
//! spring-damper, and the finite element deck's step with these axles coupled to it.
//!
//! # The model (Yang, Yau & Wu, *Vehicle–Bridge Interaction Dynamics*, 2004, ch. 2-3;
//! ERRI D214 RP9 §3)
//!
//! Axle `k` at `x_k(t) = v·t − s_k` has an unsprung mass `m_w` (the wheelset), a sprung
//! mass `m_s` (its share of the bogie and car body), a primary stiffness `k_p` and damping
//! `c_p` between them, and a contact spring `k_H` to the deck. Displacements are vertical,
//! up positive, measured from the static state on a rigid support, so gravity is in the
//! static axle load `P = (m_w + m_s)·g` alone. With `w_k = g_kᵀ·u` the deck's vertical
//! displacement under the axle (`g_k` the deck's interpolation at `x_k`, the same shape
//! functions as the consistent nodal forces of a moving force, so `−g_k·P` is the moving
//! force's load vector), the contact force on the deck (down) and on the wheel (up) is
//! `F_k = P + k_H·(w_k − z_w)`, and
//!
//! ```text
//! deck     M·ü + C·u̇ + K·u = −Σ_k g_k·F_k
//! wheel    m_w·z̈_w = k_H·(w_k − z_w) − k_p·(z_w − z_s) − c_p·(ż_w − ż_s)
//! sprung   m_s·z̈_s = k_p·(z_w − z_s) + c_p·(ż_w − ż_s)
//! ```
//!
//! summed over the axles on the deck; an axle before the deck stands at rest on rigid
//! ground, and one past it no longer acts on the deck.
//!
//! # The step
//!
//! Newmark's average acceleration (β = ¼, γ = ½) on the whole system: with `a₀ = 4/h²`,
//! `a₁ = 2/h`, `a₂ = 4/h`, each axle's two equations at `t + h` read
//! `A·(z_w, z_s) − (k_H·w, 0) = r` with the constant
//! `A = [[a₀m_w + a₁c_p + k_p + k_H, −(a₁c_p + k_p)], [−(a₁c_p + k_p), a₀m_s + a₁c_p + k_p]]`
//! and `r` from the axle's state at `t` (`M(a₀z + a₂ż + z̈) + C(a₁z + ż)`, as for the deck).
//! Eliminating the axle (`z_w = A⁻¹₁₁·(r₁ + k_H·w) + A⁻¹₁₂·r₂`) leaves the deck's
//! effective system with a rank-one term per axle,
//! `(K_eff + Σ_k s·g_k·g_kᵀ)·u = R − Σ_k g_k·(P − k_H·ζ_k)`, `s = k_H − k_H²·A⁻¹₁₁`,
//! `ζ_k = A⁻¹₁₁·r₁ + A⁻¹₁₂·r₂`. An axle's `g_k` touches the DOFs of one element only, so
//! the term stays within the band: each step adds the terms to a copy of `K_eff` and
//! factors it (band Cholesky), then recovers the axles' states from `u`. With `m_w`,
//! `m_s` → 0 the contact force is `P` and the step is the moving-force step
//! (tests/bridge_check.rs checks both this limit and a modal solution of the same system).

use super::fe::{Band, Deck, Stepper, Work};
use super::trains::Train;
use crate::framework::FemError;
use serde::Deserialize;

/// Standard gravity (m/s²).
pub const G: f64 = 9.81;

/// The models a train can be run with.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum VehicleModel {
    /// Every axle a constant moving force.
    MovingForces,
    /// Every axle a moving sprung mass coupled to the deck (this module).
    SprungMasses,
    /// Every vehicle a 10-DOF half car coupled to the deck ([`super::full_vehicles`]).
    FullVehicles,
}

impl VehicleModel {
    /// The name in `envelope.csv` and the report.
    pub fn name(self) -> &'static str {
        match self {
            VehicleModel::MovingForces => "moving_forces",
            VehicleModel::SprungMasses => "sprung_masses",
            VehicleModel::FullVehicles => "full_vehicles",
        }
    }
}

/// The plan's choice of models (`[analysis] model`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum Models {
    /// Moving forces only (the default).
    #[default]
    MovingForces,
    /// Moving sprung masses only.
    SprungMasses,
    /// Both, side by side.
    Both,
    /// Full vehicles only (trains of vehicle files).
    FullVehicles,
    /// Moving forces, sprung masses and full vehicles, side by side.
    All,
}

impl Models {
    /// The models run, in order.
    pub fn list(self) -> Vec<VehicleModel> {
        match self {
            Models::MovingForces => vec![VehicleModel::MovingForces],
            Models::SprungMasses => vec![VehicleModel::SprungMasses],
            Models::Both => vec![VehicleModel::MovingForces, VehicleModel::SprungMasses],
            Models::FullVehicles => vec![VehicleModel::FullVehicles],
            Models::All => vec![
                VehicleModel::MovingForces,
                VehicleModel::SprungMasses,
                VehicleModel::FullVehicles,
            ],
        }
    }
}

/// The suspension of one axle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AxleSuspension {
    /// Unsprung mass `m_w` (kg).
    pub unsprung: f64,
    /// Sprung mass share `m_s` (kg).
    pub sprung: f64,
    /// Primary stiffness `k_p` (N/m).
    pub stiffness: f64,
    /// Primary damping `c_p` (N·s/m).
    pub damping: f64,
    /// Contact stiffness `k_H` (N/m).
    pub contact: f64,
}

/// Zhai's Hertz constant `G` (m/N^(2/3)) of a worn-tread wheel of radius `r` (m):
/// `G = 3.86·R^−0.115·10⁻⁸` (W. Zhai, *Vehicle–Track Coupled Dynamics*, 2020, §2.4.1).
pub fn hertz_constant(r: f64) -> f64 {
    3.86e-8 * r.powf(-0.115)
}

/// The contact stiffness (N/m) of an axle of static load `p` (N, two wheels) linearised
/// about the static state: each wheel's Hertz law `δ = G·F^{2/3}` has the tangent
/// `dF/dδ = 3/(2G)·F₀^{1/3}` at its static load `F₀ = p/2`; the two wheels act in parallel.
pub fn linear_contact(p: f64, wheel_radius: f64) -> f64 {
    2.0 * 1.5 / hertz_constant(wheel_radius) * (p / 2.0).cbrt()
}

/// `[sprung_masses]` of a plan: the suspension given to every axle of a train that has
/// none of its own (the built-in HSLM trains, the user's axle tables). The defaults are
/// the per-axle values of the `sks700` vehicle file (`examples/vehicles/sks700.toml`: a
/// wheelset of 1850 kg, two primary springs of 1.176 MN/m and dampers of 13 kN·s/m), since
/// EN 1991-2 gives the HSLM no suspension.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SprungDefaults {
    /// Unsprung mass per axle (kg) [default: 1850].
    #[serde(default = "default_unsprung")]
    pub unsprung_mass: f64,
    /// Primary stiffness per axle (N/m) [default: 2.352e6].
    #[serde(default = "default_k")]
    pub primary_stiffness: f64,
    /// Primary damping per axle (N·s/m) [default: 26e3].
    #[serde(default = "default_c")]
    pub primary_damping: f64,
    /// Contact stiffness per axle (N/m) [default: Hertz linearised at the static load].
    #[serde(default)]
    pub contact_stiffness: Option<f64>,
    /// Wheel radius for the Hertz contact (m) [default: 0.43].
    #[serde(default = "default_radius")]
    pub wheel_radius: f64,
}

fn default_unsprung() -> f64 {
    1850.0
}
fn default_k() -> f64 {
    2.352e6
}
fn default_c() -> f64 {
    26e3
}
fn default_radius() -> f64 {
    0.43
}

impl Default for SprungDefaults {
    fn default() -> Self {
        SprungDefaults {
            unsprung_mass: default_unsprung(),
            primary_stiffness: default_k(),
            primary_damping: default_c(),
            contact_stiffness: None,
            wheel_radius: default_radius(),
        }
    }
}

impl SprungDefaults {
    /// Checks the values; errors name `file` and the key.
    pub fn validate(&self, file: &str) -> Result<(), FemError> {
        let at = |k: &str| format!("{file}: sprung_masses.{k}");
        let checks = [
            ("unsprung_mass", self.unsprung_mass, "kg"),
            ("primary_stiffness", self.primary_stiffness, "N/m"),
            ("wheel_radius", self.wheel_radius, "m"),
            (
                "contact_stiffness",
                self.contact_stiffness.unwrap_or(1.0),
                "N/m",
            ),
        ];
        for (k, v, unit) in checks {
            if !(v.is_finite() && v > 0.0) {
                return Err(FemError::input(at(k), format!("give a value > 0 ({unit})")));
            }
        }
        if !(self.primary_damping.is_finite() && self.primary_damping >= 0.0) {
            return Err(FemError::input(
                at("primary_damping"),
                "give a value ≥ 0 (N·s/m)",
            ));
        }
        Ok(())
    }

    /// The suspension of every axle of `train`: the unsprung mass, the rest of the axle's
    /// static load as sprung mass. Errors name `file` when an axle is lighter than its
    /// unsprung mass.
    pub fn for_train(&self, train: &Train, file: &str) -> Result<Vec<AxleSuspension>, FemError> {
        train
            .axles
            .iter()
            .map(|a| {
                let sprung = a.load / G - self.unsprung_mass;
                if sprung <= 0.0 {
                    return Err(FemError::input(
                        format!("{file}: sprung_masses.unsprung_mass"),
                        format!(
                            "train {}: an axle of {:.0} N is lighter than the unsprung mass; give a smaller unsprung_mass (kg)",
                            train.name, a.load
                        ),
                    ));
                }
                Ok(AxleSuspension {
                    unsprung: self.unsprung_mass,
                    sprung,
                    stiffness: self.primary_stiffness,
                    damping: self.primary_damping,
                    contact: self
                        .contact_stiffness
                        .unwrap_or_else(|| linear_contact(a.load, self.wheel_radius)),
                })
            })
            .collect()
    }
}

/// One axle's Newmark constants: the inverse of its `A` and the rank-one coefficient `s`.
#[derive(Debug, Clone, Copy)]
struct AxleStep {
    inv: [f64; 3],
    s: f64,
}

impl AxleStep {
    fn new(a: &AxleSuspension, h: f64) -> AxleStep {
        let (a0, a1) = (4.0 / (h * h), 2.0 / h);
        let coupling = a1 * a.damping + a.stiffness;
        let a11 = a0 * a.unsprung + coupling + a.contact;
        let a22 = a0 * a.sprung + coupling;
        let det = a11 * a22 - coupling * coupling;
        let inv = [a22 / det, coupling / det, a11 / det];
        AxleStep {
            inv,
            s: a.contact - a.contact * a.contact * inv[0],
        }
    }
}

/// Per-run buffers of the interaction step beyond the deck's [`Work`].
#[derive(Debug, Clone, Default)]
pub struct AxleWork {
    /// Per axle `(z_w, ż_w, z̈_w, z_s, ż_s, z̈_s)` (m, m/s, m/s²).
    pub states: Vec<[f64; 6]>,
    /// Per axle its `r` of the current step.
    r: Vec<[f64; 2]>,
    /// Per axle on the deck its interpolation terms `(equation, g)`.
    terms: Vec<Vec<(usize, f64)>>,
    /// The effective matrix of the step.
    keff: Option<Band>,
    /// Largest and smallest contact force over the run, relative to the static load.
    pub contact_range: (f64, f64),
}

/// Runs `train` with the axle suspensions `axles` over `deck` at `v` (m/s) for `steps`
/// steps from rest (the first axle on the path's start at t = 0); fills the deck's
/// `w.deflection` and `w.acceleration` as [`Stepper::run`] does, and the axles' states in
/// `x`.
pub fn run(
    st: &Stepper,
    deck: &Deck,
    train: &Train,
    axles: &[AxleSuspension],
    v: f64,
    steps: usize,
    (w, x): (&mut Work, &mut AxleWork),
) {
    let h = st.dt;
    let (a0, a1, a2) = (4.0 / (h * h), 2.0 / h, 4.0 / h);
    st.start(deck, steps, w);
    let na = train.axles.len();
    let consts: Vec<AxleStep> = axles.iter().map(|a| AxleStep::new(a, h)).collect();
    x.states.clear();
    x.states.resize(na, [0.0; 6]);
    x.r.clear();
    x.r.resize(na, [0.0; 2]);
    x.terms.resize(na, Vec::new());
    x.contact_range = (1.0, 1.0);
    let length = deck.length();
    let (mut first, mut last) = (0usize, 0usize);
    for i in 1..=steps {
        let front = v * i as f64 * h;
        while last < na && train.axles[last].position <= front {
            last += 1;
        }
        while first < last && front - train.axles[first].position > length {
            first += 1;
        }
        w.r.fill(0.0);
        st.history(w);
        let keff = st.effective(&mut x.keff);
        let b = keff.b;
        for k in first..last {
            let (ax, su, c) = (&train.axles[k], &axles[k], &consts[k]);
            let xk = front - ax.position;
            let g = &mut x.terms[k];
            deck.unit_terms(xk, g);
            let z = &x.states[k];
            let rel = a1 * (z[0] - z[3]) + z[1] - z[4];
            let r1 = su.unsprung * (a0 * z[0] + a2 * z[1] + z[2]) + su.damping * rel;
            let r2 = su.sprung * (a0 * z[3] + a2 * z[4] + z[5]) - su.damping * rel;
            x.r[k] = [r1, r2];
            let zeta = c.inv[0] * r1 + c.inv[1] * r2;
            let f = ax.load - su.contact * zeta;
            for &(e, ge) in g.iter() {
                // g is the upward interpolation; a downward load f adds −g·f.
                w.r[e] -= ge * f;
                for &(e2, g2) in g.iter() {
                    if e >= e2 {
                        keff.a[e * (b + 1) + (e2 + b - e)] += c.s * ge * g2;
                    }
                }
            }
        }
        // K_eff is positive definite and every added term s·g·gᵀ is positive
        // semi-definite (s ≥ 0: k_H·A⁻¹₁₁ ≤ 1 for masses ≥ 0), so the factor exists.
        let factored = keff.cholesky();
        debug_assert!(factored.is_ok(), "interaction matrix not positive definite");
        keff.solve(&mut w.r);
        st.advance(w);
        for k in first..last {
            let (ax, su, c) = (&train.axles[k], &axles[k], &consts[k]);
            let wk: f64 = x.terms[k].iter().map(|&(e, g)| g * w.q[e]).sum();
            let [r1, r2] = x.r[k];
            let rhs1 = r1 + su.contact * wk;
            let zw = c.inv[0] * rhs1 + c.inv[1] * r2;
            let zs = c.inv[1] * rhs1 + c.inv[2] * r2;
            let s = &mut x.states[k];
            for (j, znew) in [(0, zw), (3, zs)] {
                let an = a0 * (znew - s[j]) - a2 * s[j + 1] - s[j + 2];
                s[j + 1] += 0.5 * h * (s[j + 2] + an);
                s[j + 2] = an;
                s[j] = znew;
            }
            let rel = (ax.load + su.contact * (wk - zw)) / ax.load;
            x.contact_range.0 = x.contact_range.0.max(rel);
            x.contact_range.1 = x.contact_range.1.min(rel);
        }
        st.record(deck, i, w);
    }
}

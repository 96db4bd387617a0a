//! The time-integrator extension point: the [`TimeIntegrator`] trait the driver, the
//! condensed Newton and the lumped linear step call, and the registry that turns a model
//! file's `[analysis] integrator = "..."` into one.
//!
//! An implicit integrator is seen by the Newton iterations through four things:
//!
//! - the weights of the effective tangent, [`Coefficients`] `{ k, m, c }`, for a stage of
//!   length `h`;
//! - the trial kinematics, affine in the increment `Δu = u − u_start` of the stage: the
//!   velocity and acceleration at the stage's end and the ones the balance weighs (the
//!   generalized-α family evaluates inertia at `n+1−α_m` and damping at `n+1−α_f`);
//! - the weight `α_f` of the stage's start in the force terms
//!   (`f̄ = (1−α_f)·f(end) + α_f·f(start)`);
//! - its stages: a one-step scheme has one; a composite scheme ([`crate::bathe`]) solves
//!   a step as several Newton solves, each from the state the previous one committed, and
//!   keeps the history it needs ([`TimeIntegrator::begin_stage`]).
//!
//! The kinematics are asked for **at slice level**: one call forms a block of equations,
//! so the hot loops pay one dynamic call per block, not one per equation, and the
//! implementation's inner loop is compiled for its own formulas. Equation `i` of a block
//! that starts at `lo` is `lo + i` of the model (a composite scheme's history is indexed
//! by it).
//!
//! Registration follows the elements' ([`railfem_framework::registry`]): one
//! `inventory::submit!` of an [`IntegratorEntry`] (name, description, documented keys and a
//! constructor) next to the implementation; [`resolve`] finds a model's integrator by name
//! and refuses an unknown one with the list of registered names.

use crate::state::State;
use railfem_framework::model::AnalysisSpec;
use railfem_framework::registry::ParamDoc;
pub use railfem_framework::Coefficients;
use railfem_framework::FemError;

/// Equations per call where a pass fuses the integrator's kinematics with other work: the
/// block's outputs are still in the cache when the pass reads them.
pub const BLOCK: usize = 512;

/// The increment `Δu` of a block of equations from the stage's start.
#[derive(Debug, Clone, Copy)]
pub enum Increment<'a> {
    /// `Δu = 0` (the first iterate is the start).
    Zero,
    /// `Δu_i = q_i − q0_i`, formed inline.
    Between {
        /// The iterate.
        q: &'a [f64],
        /// The stage's start.
        q0: &'a [f64],
    },
    /// `Δu` given (finite-rotation models form it as a rotation vector).
    Given(&'a [f64]),
}

impl Increment<'_> {
    /// Calls `f(i, Δu_i)` for every equation `i` of a block of `n`, the match on the kind
    /// made once outside the loop.
    #[inline(always)]
    pub fn for_each(self, n: usize, mut f: impl FnMut(usize, f64)) {
        match self {
            Increment::Zero => (0..n).for_each(|i| f(i, 0.0)),
            Increment::Between { q, q0 } => {
                let (q, q0) = (&q[..n], &q0[..n]);
                (0..n).for_each(|i| f(i, q[i] - q0[i]))
            }
            Increment::Given(du) => {
                let du = &du[..n];
                (0..n).for_each(|i| f(i, du[i]))
            }
        }
    }
}

/// The trial kinematics of a block: the outputs of [`TimeIntegrator::trial`].
#[derive(Debug)]
pub struct Trial<'a> {
    /// Velocity at the stage's end.
    pub v: &'a mut [f64],
    /// Acceleration at the stage's end.
    pub a: &'a mut [f64],
    /// The acceleration the balance's inertia term takes (`a_{n+1−α_m}`).
    pub a_w: &'a mut [f64],
    /// The velocity the balance's damping term takes (`v_{n+1−α_f}`).
    pub v_w: &'a mut [f64],
}

/// A time integrator as the Newton iterations see it (module documentation).
///
/// Every slice argument of one call has the block's length; `lo` is the block's first
/// equation in the model.
pub trait TimeIntegrator: std::fmt::Debug + Send + Sync {
    /// The registered name.
    fn name(&self) -> &'static str;

    /// Newton solves per step (1 for a one-step scheme).
    fn stages(&self) -> usize {
        1
    }

    /// The length of stage `stage` of a step of `dt`.
    fn stage_length(&self, stage: usize, dt: f64) -> f64 {
        let _ = stage;
        dt
    }

    /// Called before the attempts of stage `stage` of a step of `dt`, with the committed
    /// state the stage starts from: a composite scheme keeps the history it needs. A
    /// failed stage is not retried by itself: the driver solves the rest of the step as
    /// shorter steps, which start again at stage 0.
    fn begin_stage(&mut self, stage: usize, dt: f64, start: &State) {
        let _ = (stage, dt, start);
    }

    /// The effective tangent's weights for the current stage, of length `h`.
    fn coefficients(&self, h: f64) -> Coefficients;

    /// The weight `α_f` of the stage's start in the force terms of the balance.
    fn force_weight(&self) -> f64;

    /// The trial kinematics of a block from its increment, the start's velocity `v0` and
    /// acceleration `a0`.
    fn trial(&self, h: f64, lo: usize, du: Increment<'_>, v0: &[f64], a0: &[f64], out: Trial<'_>);

    /// Velocity and acceleration at the stage's end only (a solved linear step).
    #[allow(clippy::too_many_arguments)]
    fn kinematics(
        &self,
        h: f64,
        lo: usize,
        du: Increment<'_>,
        v0: &[f64],
        a0: &[f64],
        v: &mut [f64],
        a: &mut [f64],
    );

    /// The acceleration the balance's inertia term takes at `Δu = 0` (`a_w` of
    /// [`TimeIntegrator::trial`] with a zero increment): the first residual of the lumped
    /// linear step, which needs nothing else of the trial state.
    fn inertia_acceleration_at_rest(
        &self,
        h: f64,
        lo: usize,
        v0: &[f64],
        a0: &[f64],
        a_w: &mut [f64],
    );

    /// The weighted acceleration (and, when asked, velocity) that the *next* step of the
    /// same length would start with from the state `(v, a)`, at `Δu = 0`: the linear step
    /// and the condensed Newton form the next step's first products with them. A scheme
    /// whose next stage is not this one fills NaN, which never matches, so the next step
    /// forms its products anew.
    fn next_at_rest(&self, h: f64, v: &[f64], a: &[f64], a_w: &mut [f64], v_w: Option<&mut [f64]>);
}

/// One registered integrator.
#[derive(Clone, Copy)]
pub struct IntegratorEntry {
    /// The name a model file gives as `[analysis] integrator`.
    pub name: &'static str,
    /// One-line description with its source.
    pub description: &'static str,
    /// The keys it reads: top-level `[analysis]` keys for the built-in three, the keys of
    /// `[analysis.integrator_parameters]` for the others.
    pub params: fn() -> Vec<ParamDoc>,
    /// Whether its keys live in `[analysis.integrator_parameters]` (`false`: in
    /// `[analysis]` itself, as the built-in three have always read them).
    pub own_table: bool,
    /// The constructor, from the `[analysis]` table; `origin` names it in messages.
    pub make: Constructor,
}

/// An integrator's constructor: from the `[analysis]` table and the model's name for
/// messages.
pub type Constructor = fn(&AnalysisSpec, &str) -> Result<Box<dyn TimeIntegrator>, FemError>;

inventory::collect!(IntegratorEntry);

/// Every registered integrator, sorted by name.
pub fn entries() -> Vec<IntegratorEntry> {
    let mut v: Vec<IntegratorEntry> = inventory::iter::<IntegratorEntry>
        .into_iter()
        .copied()
        .collect();
    v.sort_by_key(|e| e.name);
    v
}

/// The integrator `[analysis]` asks for; `origin` names the model (file) in messages.
pub fn resolve(spec: &AnalysisSpec, origin: &str) -> Result<Box<dyn TimeIntegrator>, FemError> {
    let o = format!("{origin}: [analysis] integrator");
    let name = spec.integrator.name();
    let all = entries();
    let Some(e) = all.iter().find(|e| e.name == name) else {
        let names: Vec<&str> = all.iter().map(|e| e.name).collect();
        let near = railfem_framework::error::nearest(name, &names);
        return Err(FemError::input(
            o,
            format!(
                "unknown integrator `{name}`{}; registered: {} (`railfem integrators` lists their keys)",
                near.map(|n| format!(" (did you mean `{n}`?)")).unwrap_or_default(),
                names.join(", ")
            ),
        ));
    };
    if !e.own_table && spec.integrator_parameters.is_some() {
        return Err(FemError::input(
            format!("{origin}: [analysis.integrator_parameters]"),
            format!(
                "`{name}` reads its keys from [analysis] itself, not from this table; move them there or remove the table"
            ),
        ));
    }
    (e.make)(spec, origin)
}

/// The typed parameters of a registered integrator from `[analysis.integrator_parameters]`:
/// documented defaults filled in, unknown keys refused with the list of valid ones.
pub fn parameters<P: railfem_framework::registry::Params>(
    spec: &AnalysisSpec,
    name: &str,
    origin: &str,
) -> Result<P, FemError> {
    let o = format!("{origin}: [analysis.integrator_parameters]");
    let map = spec.integrator_parameters.clone().unwrap_or_default();
    railfem_framework::registry::parse_params(&map, &o, &format!("integrator `{name}`"))
}

/// The registered integrators and their keys, as `railfem integrators` prints them.
pub fn listing() -> String {
    let mut s = String::new();
    for e in entries() {
        s.push_str(&format!("{}\n    {}\n", e.name, e.description));
        let table = if e.own_table {
            "[analysis.integrator_parameters]"
        } else {
            "[analysis]"
        };
        for d in (e.params)() {
            let default = d
                .default
                .as_ref()
                .map_or("required".to_string(), |v| format!("default {v}"));
            s.push_str(&format!(
                "    {table} {} [{}] ({default}): {}\n",
                d.key, d.unit, d.doc
            ));
        }
    }
    s
}

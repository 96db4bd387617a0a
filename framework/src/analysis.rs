//! Analysis settings: what a model asks the solvers to do — the kind of analysis, the time
//! integrator and its parameters, Newton's settings, the linear solver choice, Rayleigh
//! damping, gravity and the step counts — as the `[analysis]` table of a model file states
//! them ([`AnalysisSpec`]), with their validation.
//!
//! It knows nothing of the model's nodes and elements, so the model, the recorders and the
//! assembler can all read it.

use crate::error::FemError;
use crate::limits::{self, fmt_num};
use serde::{Deserialize, Serialize};

/// Kind of analysis a model asks for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum AnalysisKind {
    /// Static equilibrium in load steps.
    Static,
    /// Direct time integration.
    #[default]
    Transient,
    /// Lowest natural frequencies and modes.
    Modal,
}

/// Time integrator of a transient analysis, by its registered name (`railfem integrators`
/// lists them; the solvers crate resolves the name through its integrator registry).
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum IntegratorKind {
    /// Newmark-β with the user's β and γ (default average acceleration, β = ¼, γ = ½).
    #[default]
    Newmark,
    /// Hilber–Hughes–Taylor α (`alpha` in [0, 1/3], numerical damping of high modes).
    Hht,
    /// Chung–Hulbert generalized-α, set by the high-frequency spectral radius `rho_inf`.
    GeneralizedAlpha,
    /// Any other registered integrator (e.g. `"bathe"`), its parameters in
    /// `[analysis.integrator_parameters]`. A name nobody registered is refused when the
    /// model is built, with the list of registered names.
    #[serde(untagged)]
    Registered(String),
}

impl IntegratorKind {
    /// The name a model file spells it with.
    pub fn name(&self) -> &str {
        match self {
            IntegratorKind::Newmark => "newmark",
            IntegratorKind::Hht => "hht",
            IntegratorKind::GeneralizedAlpha => "generalized_alpha",
            IntegratorKind::Registered(s) => s,
        }
    }
}

/// Newton–Raphson variant.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum NewtonKind {
    /// Refactor the tangent every iteration.
    #[default]
    Full,
    /// Factor once per step and reuse it for the step's iterations.
    Modified,
    /// Reuse the factor across steps while it keeps converging; refactor when it does not.
    Initial,
}

/// The first iterate of a transient step (`[analysis.newton] predictor`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum Predictor {
    /// The committed displacements: `q⁰ = q_n` (the integrator's kinematics then give the
    /// trial velocity and acceleration of a zero increment).
    #[default]
    Previous,
    /// The last step's increment again, scaled to this step's length:
    /// `q⁰ = q_n + (dt/dt_prev)·(q_n − q_{n−1})` (on finite-rotation triples the
    /// incremental rotation vector, composed). Exact for a motion at constant rate, so the
    /// first correction is of the order of the increment's change over a step instead of
    /// the increment itself. It pays where a steady drift meets a nonlinear law: a rolling
    /// wheelset's spin and contact masters advance every step, and the creep laws are
    /// nonlinear in that advance (docs/performance.md, "Rolling-contact laws in the curve
    /// case"). Not used by the condensed Newton (which then hands the step to the
    /// full-residual attempt).
    Increment,
}

impl Predictor {
    /// Whether this is the default (kept out of serialized settings, so a model that
    /// does not choose a predictor serializes as it always did).
    pub fn is_previous(&self) -> bool {
        *self == Predictor::Previous
    }
}

/// Which linear solver the Newton iterations use (`[analysis] solver`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum SolverChoice {
    /// Decided by the model's size: `partitioned` for large models with moving or
    /// nonlinear elements, `low_rank` for a smaller transient whose moving or nonlinear
    /// elements have few DOFs in all, `direct` otherwise. The sizes are the solvers
    /// crate's (`railfem_solvers::thresholds`), which resolves the choice
    /// ([`SolverResolver`]).
    #[default]
    Auto,
    /// One sparse factorization of the whole effective tangent (variable elements inside
    /// the global pattern; a moving element's new connectivity rebuilds the pattern).
    Direct,
    /// Static condensation of the constant structure in blocks, refactoring only the blocks
    /// a moving or nonlinear element touches (`railfem_solvers::partition`).
    Partitioned,
    /// The constant structure factored once per `Δt`, the variable elements' few equations
    /// by a bordered (Woodbury) solve (`railfem_solvers::lowrank`).
    LowRank,
}

impl SolverChoice {
    /// Every choice, in the order the docs list them.
    pub const ALL: [SolverChoice; 4] = [
        SolverChoice::Auto,
        SolverChoice::Direct,
        SolverChoice::Partitioned,
        SolverChoice::LowRank,
    ];

    /// The name a model file and the command line use (`[analysis] solver`).
    pub fn name(self) -> &'static str {
        match self {
            SolverChoice::Auto => "auto",
            SolverChoice::Direct => "direct",
            SolverChoice::Partitioned => "partitioned",
            SolverChoice::LowRank => "low_rank",
        }
    }

    /// The choice of that name, if any.
    pub fn parse(name: &str) -> Option<SolverChoice> {
        SolverChoice::ALL.into_iter().find(|s| s.name() == name)
    }
}

/// Geometry of rigid links and of the vehicle builder's suspensions (`[analysis] geometry`,
/// a `[[link]]`'s `geometry`, the `--geometry` option of the built-in cases).
///
/// `linear`: small rotations, `u_s = u_m + θ_m × r` (the default; today's numbers).
/// `nonlinear`: the slave follows the master's current finite rotation,
/// `u_s = u_m + (R(ψ_m) − I)·r`, and vehicle suspensions balance in the displaced
/// configuration (the `suspension` element).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(try_from = "String", into = "String")]
pub enum Geometry {
    /// Small displacements and rotations.
    #[default]
    Linear,
    /// Finite rotations of rigid bodies.
    Nonlinear,
}

impl Geometry {
    /// The name as written in a model file.
    pub fn name(self) -> &'static str {
        match self {
            Geometry::Linear => "linear",
            Geometry::Nonlinear => "nonlinear",
        }
    }

    /// Parses a name; the error is the message (the caller adds the place).
    pub fn parse(s: &str) -> Result<Geometry, String> {
        match s {
            "linear" => Ok(Geometry::Linear),
            "nonlinear" => Ok(Geometry::Nonlinear),
            other => Err(format!(
                "`geometry` = \"{other}\" is not known; give \"linear\" (the default) or \"nonlinear\""
            )),
        }
    }
}

impl TryFrom<String> for Geometry {
    type Error = String;
    fn try_from(s: String) -> Result<Self, String> {
        Geometry::parse(&s)
    }
}

impl From<Geometry> for String {
    fn from(g: Geometry) -> String {
        g.name().to_string()
    }
}

/// What the linear solver of a model is chosen from: the user's choice and the model's
/// size, known once its equations are numbered (by the assembler).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SolverInputs {
    /// The model's `[analysis] solver`.
    pub choice: SolverChoice,
    /// Number of equations.
    pub equations: usize,
    /// Total DOF count of the moving and nonlinear elements (`None`: there are none).
    pub variable_dofs: Option<usize>,
    /// Whether the analysis is a transient one.
    pub transient: bool,
}

/// Resolves `auto` into the solver a model runs with (never returns
/// [`SolverChoice::Auto`]): the solvers crate's `railfem_solvers::thresholds::resolve`,
/// which holds the sizes the choice is made by.
pub type SolverResolver = fn(&SolverInputs) -> SolverChoice;

/// Newton–Raphson settings (`[analysis.newton]`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct NewtonSettings {
    /// Relative tolerance on the residual force and the displacement increment.
    pub tol: f64,
    /// Absolute tolerance on the residual force (N).
    pub abs_tol: f64,
    /// Absolute tolerance on the displacement increment (m).
    pub disp_tol: f64,
    /// Iterations before a step is declared not converged.
    pub max_iter: usize,
    /// Full, modified or initial-tangent Newton.
    pub kind: NewtonKind,
    /// How many times a failing step is halved before the run stops.
    pub max_cuts: usize,
    /// First iterate of a transient step: `"previous"` (default) or `"increment"`.
    #[serde(skip_serializing_if = "Predictor::is_previous")]
    pub predictor: Predictor,
    /// Contact statuses of a transient step's first iteration: `"committed"` (default)
    /// or `"found"`.
    #[serde(skip_serializing_if = "FirstActiveSet::is_committed")]
    pub first_active_set: FirstActiveSet,
}

/// The contact statuses a transient step's first Newton iteration evaluates with
/// (`[analysis.newton] first_active_set`).
///
/// The first iterate `q⁰ = q_n` keeps a wheel's contact master where it was while the
/// wheel has moved on to rail that sits higher or lower (a deflected bridge's slope, the
/// rail's bending between fasteners): the gap changes by up to tens of micrometres, while
/// the penalty contact (1e10 N/m) holds the wheel on the rail with penetrations of a few
/// micrometres. Every point of the wheel can then
/// open at `q⁰`; a tangent without contact stiffness drives the master deep into the rail
/// and Newton walks back through the active sets, seven iterations a step where three
/// would do (docs/performance.md, "Seven iterations a step"). Holding the last converged
/// step's statuses for the first iteration linearizes about the contact that holds the
/// wheel; every later iteration finds each point's own status, and only those are ever
/// accepted, so the converged state satisfies the contact law as before.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum FirstActiveSet {
    /// Held at the statuses of the last converged step for the first iteration.
    #[default]
    Committed,
    /// Each evaluation finds every point's status, the first one too.
    Found,
}

impl FirstActiveSet {
    /// Whether this is the default (kept out of serialized settings).
    pub fn is_committed(&self) -> bool {
        *self == FirstActiveSet::Committed
    }

    /// The setting a command-line word or a study value names (`committed`, `found`).
    pub fn parse(word: &str) -> Option<Self> {
        match word {
            "committed" => Some(FirstActiveSet::Committed),
            "found" => Some(FirstActiveSet::Found),
            _ => None,
        }
    }
}

impl Default for NewtonSettings {
    fn default() -> Self {
        NewtonSettings {
            tol: 1e-8,
            abs_tol: 1e-6,
            disp_tol: 1e-12,
            max_iter: 25,
            kind: NewtonKind::Full,
            max_cuts: 4,
            predictor: Predictor::Previous,
            first_active_set: FirstActiveSet::Committed,
        }
    }
}

/// Rayleigh damping `C = alpha·M + beta·K` (K the constant stiffness).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub struct Rayleigh {
    /// Mass-proportional coefficient (1/s).
    pub alpha: f64,
    /// Stiffness-proportional coefficient (s).
    pub beta: f64,
}

/// Whether the activity window runs (`[analysis.window] mode`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum WindowMode {
    /// Every block of the partitioned solver solved every step: the run is that of a
    /// model without the window, bit for bit (the default).
    #[default]
    Off,
    /// Blocks far from what moves held at their state; a model the window does not apply
    /// to is refused.
    On,
    /// [`WindowMode::On`] where the window applies, [`WindowMode::Off`] elsewhere (the run's
    /// summary says why, once).
    Auto,
}

impl WindowMode {
    /// The name a model file spells it with.
    pub fn name(self) -> &'static str {
        match self {
            WindowMode::Off => "off",
            WindowMode::On => "on",
            WindowMode::Auto => "auto",
        }
    }

    /// The mode a command line or a study spells `word` (`off`, `on`, `auto`); `None` for
    /// any other word.
    pub fn parse(word: &str) -> Option<WindowMode> {
        [WindowMode::Off, WindowMode::On, WindowMode::Auto]
            .into_iter()
            .find(|m| m.name() == word)
    }
}

/// The activity window of a transient on the partitioned solver (`[analysis.window]`):
/// blocks far from the model's moving elements are held at their state
/// (`railfem_solvers::window`; what moves and where is `railfem::run_window`'s).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, Default)]
#[serde(deny_unknown_fields, default)]
pub struct WindowSpec {
    /// `"off"` (the default), `"on"` or `"auto"`.
    pub mode: WindowMode,
    /// The reach (m): a block joins when the front of what moves comes within this
    /// distance, and is held behind only once it is this far behind the rear (`None`: the
    /// default reach of `railfem train-bridge --window`, 300 m).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ahead: Option<f64>,
    /// A block behind is held once its interior's velocity norm is below this fraction of
    /// the largest it reached, in `[0, 1)` (`None`: the default, 0.01).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tolerance: Option<f64>,
    /// Thickness (m) of the absorbing layer at the window's edges, `0`: none (`None`: the
    /// default of `railfem train-bridge --window-layer`, a third of the reach).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub layer: Option<f64>,
    /// The absorbing layer's largest mass-proportional damping `α_max` (1/s, `None`: the
    /// default of `railfem train-bridge --window-layer-damping`, from the thickness).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub layer_damping: Option<f64>,
}

impl WindowSpec {
    /// Whether the window is off with no setting given (the table left out, as before it
    /// existed; kept out of serialized settings).
    pub fn is_off(&self) -> bool {
        *self == WindowSpec::default()
    }

    /// The checks of the keys alone (ranges, settings without the window, the analysis
    /// kind): one error per problem, naming `origin`'s `[analysis.window]` key and the fix.
    /// Whether the window applies to the model is checked where the model is known.
    pub fn check(&self, kind: AnalysisKind, origin: &str) -> Vec<FemError> {
        let o = format!("{origin}: [analysis.window]");
        let mut errors = Vec::new();
        if let Some(a) = self.ahead.filter(|a| !(a.is_finite() && *a >= 0.0)) {
            errors.push(FemError::input(
                &o,
                format!("`ahead` = {}: give a distance ≥ 0 m", fmt_num(a)),
            ));
        }
        if let Some(t) = self
            .tolerance
            .filter(|t| !(t.is_finite() && (0.0..1.0).contains(t)))
        {
            errors.push(FemError::input(
                &o,
                format!(
                    "`tolerance` = {}: give a value from 0 (never hold a block behind) to below 1",
                    fmt_num(t)
                ),
            ));
        }
        if let Some(l) = self.layer.filter(|l| !(l.is_finite() && *l >= 0.0)) {
            errors.push(FemError::input(
                &o,
                format!(
                    "`layer` = {}: give a thickness ≥ 0 m (0: no layer)",
                    fmt_num(l)
                ),
            ));
        }
        if let Some(a) = self.layer_damping.filter(|a| !(a.is_finite() && *a > 0.0)) {
            errors.push(FemError::input(
                &o,
                format!("`layer_damping` = {}: give a damping > 0 (1/s)", fmt_num(a)),
            ));
        }
        if self.layer == Some(0.0) && self.layer_damping.is_some() {
            errors.push(FemError::input(
                &o,
                "`layer_damping` shapes the absorbing layer, which `layer` = 0 removes; drop `layer_damping`, or give a `layer` > 0",
            ));
        }
        let settings = self.ahead.is_some()
            || self.tolerance.is_some()
            || self.layer.is_some()
            || self.layer_damping.is_some();
        if self.mode == WindowMode::Off && settings {
            errors.push(FemError::input(
                &o,
                "`ahead`, `tolerance`, `layer` and `layer_damping` set the activity window, which is off unless `mode` is \"on\" or \"auto\"; add mode = \"on\" (or \"auto\"), or drop them",
            ));
        }
        if kind != AnalysisKind::Transient && (self.mode != WindowMode::Off || settings) {
            errors.push(FemError::input(
                &o,
                "the activity window follows what moves in a transient; remove [analysis.window] or set `kind` = \"transient\"",
            ));
        }
        errors
    }
}

/// The `[analysis]` table.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct AnalysisSpec {
    /// `"static"`, `"transient"` or `"modal"`.
    pub kind: AnalysisKind,
    /// Time step (s).
    pub dt: f64,
    /// Duration of a transient (s).
    pub duration: f64,
    /// Time integrator.
    pub integrator: IntegratorKind,
    /// Newmark β.
    pub beta: f64,
    /// Newmark γ.
    pub gamma: f64,
    /// HHT α (0 ≤ α ≤ 1/3; 0 is the trapezoidal rule).
    pub alpha: f64,
    /// Generalized-α spectral radius at infinite frequency (0 ≤ ρ∞ ≤ 1).
    pub rho_inf: f64,
    /// Parameters of a registered integrator other than the built-in three
    /// (`[analysis.integrator_parameters]`), read by that integrator's typed parameter
    /// struct (`railfem integrators` lists its keys).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub integrator_parameters: Option<serde_json::Map<String, serde_json::Value>>,
    /// Gravitational acceleration vector in global axes (m/s²), e.g. `[0, 0, -9.81]`.
    pub gravity: Option<[f64; 3]>,
    /// Solve static equilibrium under the t = 0 loads (gravity, the t = 0 pseudo-loads)
    /// before a transient.
    pub initial_static: bool,
    /// Load steps of a static analysis.
    pub steps: usize,
    /// Number of modes of a modal analysis.
    pub modes: usize,
    /// Newton–Raphson settings.
    pub newton: NewtonSettings,
    /// Rayleigh damping.
    pub rayleigh: Option<Rayleigh>,
    /// Record every n-th step.
    pub record_every: usize,
    /// Linear solver of the Newton iterations.
    pub solver: SolverChoice,
    /// Target interior equations per block of the partitioned solver (`None`: 3000). Under
    /// `mpirun -n P` the ranks share the blocks, so a model needs at least P blocks to give
    /// every rank work.
    pub block_size: Option<usize>,
    /// Geometry of rigid links and vehicle suspensions: "linear" or "nonlinear".
    pub geometry: Geometry,
    /// The activity window (`[analysis.window]`): off unless asked for.
    #[serde(skip_serializing_if = "WindowSpec::is_off")]
    pub window: WindowSpec,
}

impl Default for AnalysisSpec {
    fn default() -> Self {
        AnalysisSpec {
            kind: AnalysisKind::Transient,
            dt: 0.01,
            duration: 1.0,
            integrator: IntegratorKind::Newmark,
            beta: 0.25,
            gamma: 0.5,
            alpha: 0.05,
            rho_inf: 0.8,
            integrator_parameters: None,
            gravity: None,
            initial_static: true,
            steps: 1,
            modes: 3,
            newton: NewtonSettings::default(),
            rayleigh: None,
            record_every: 1,
            solver: SolverChoice::Auto,
            block_size: None,
            geometry: Geometry::Linear,
            window: WindowSpec::default(),
        }
    }
}

impl AnalysisSpec {
    /// Checks ranges; `origin` names the file. Every problem is reported
    /// ([`FemError::Many`] for several).
    pub fn validate(&self, origin: &str) -> Result<(), FemError> {
        let o = format!("{origin}: [analysis]");
        let mut errors = Vec::new();
        let mut bad = |m: String| errors.push(FemError::input(&o, m));
        let pos = |v: f64| v.is_finite() && v > 0.0;
        if self.kind == AnalysisKind::Transient {
            for (v, k) in [(self.dt, "dt"), (self.duration, "duration")] {
                if !pos(v) {
                    bad(format!(
                        "`{k}` must be a positive number (got {})",
                        fmt_num(v)
                    ));
                }
            }
            if !(self.gamma >= 0.5
                && self.beta > 0.0
                && self.beta.is_finite()
                && self.gamma.is_finite())
            {
                bad(format!(
                    "Newmark needs gamma >= 0.5 and beta > 0 (got beta = {}, gamma = {}); average acceleration is beta = 0.25, gamma = 0.5",
                    fmt_num(self.beta),
                    fmt_num(self.gamma)
                ));
            }
            if !(0.0..=1.0 / 3.0 + 1e-12).contains(&self.alpha) {
                bad(format!(
                    "`alpha` (HHT) = {} must lie in [0, 1/3]",
                    self.alpha
                ));
            }
            if !(0.0..=1.0).contains(&self.rho_inf) {
                bad(format!("`rho_inf` = {} must lie in [0, 1]", self.rho_inf));
            }
        }
        if self.kind == AnalysisKind::Modal && self.modes == 0 {
            bad("`modes` must be at least 1".into());
        }
        if let Some(g) = self.gravity {
            if g.iter().any(|x| !x.is_finite()) {
                bad("`gravity` must be three finite numbers (m/s²)".into());
            }
        }
        if let Some(r) = self.rayleigh {
            // C = αM + βK with a negative coefficient is not positive semi-definite: it
            // feeds energy into the modes it should damp.
            for (v, k, unit) in [(r.alpha, "alpha", "1/s"), (r.beta, "beta", "s")] {
                if !(v.is_finite() && v >= 0.0) {
                    bad(format!(
                        "`rayleigh.{k}` = {}: a negative or non-finite Rayleigh coefficient pumps energy in; give a value ≥ 0 {unit} (0 for none)",
                        fmt_num(v)
                    ));
                }
            }
        }
        let n = &self.newton;
        if !(n.tol > 0.0 && n.abs_tol >= 0.0 && n.max_iter > 0) {
            bad("[analysis.newton]: `tol` must be > 0, `abs_tol` >= 0 and `max_iter` >= 1".into());
        }
        if self.steps == 0 || self.record_every == 0 {
            bad("`steps` and `record_every` must be at least 1".into());
        }
        if self.block_size == Some(0) {
            bad("`block_size` must be at least 1 (interior equations per block of the partitioned solver; leave it out for 3000)".into());
        }
        errors.extend(self.window.check(self.kind, origin));
        // The step count means something only once `dt` and `duration` are valid.
        if errors.is_empty() {
            if let Err(e) = self.check_step_count(&o) {
                errors.push(e);
            }
        }
        FemError::from_list(errors)
    }

    /// The size guard of an analysis: its step count against [`limits::max_steps`].
    fn check_step_count(&self, o: &str) -> Result<(), FemError> {
        let (cause, steps, fix) = match self.kind {
            AnalysisKind::Transient => (
                format!(
                    "`duration` = {} s at `dt` = {} s",
                    fmt_num(self.duration),
                    fmt_num(self.dt)
                ),
                (self.duration / self.dt).ceil(),
                "give a larger `dt` or a shorter `duration`",
            ),
            AnalysisKind::Static => (
                format!("`steps` = {}", self.steps),
                self.steps as f64,
                "give fewer load `steps`",
            ),
            AnalysisKind::Modal => return Ok(()),
        };
        limits::check_steps(&cause, steps, fix).map_err(|m| FemError::input(o, m))
    }
}

#[cfg(test)]
mod solver_choice_tests {
    use super::SolverChoice;

    /// The names the command line parses are the ones a model file's serde reads.
    #[test]
    fn names_are_the_model_files_names() {
        for s in SolverChoice::ALL {
            let json = serde_json::to_string(&s).unwrap();
            assert_eq!(json, format!("\"{}\"", s.name()));
            assert_eq!(SolverChoice::parse(s.name()), Some(s));
        }
        assert_eq!(SolverChoice::parse("lowrank"), None);
    }
}

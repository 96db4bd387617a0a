//! The model: nodes, rigid links, elements, loads, carriers and recorders, and the typed
//! builder that makes one.
//!
//! A [`Model`] is what the solvers run. It is built either from a model file
//! ([`crate::modelfile`]) or in Rust code with a [`ModelBuilder`]; both go through the same
//! path (element entries are JSON maps handed to the registry), so the same model built
//! either way gives identical results. Elements may add internal nodes while being built
//! (the wheel node B of the moving axle). Validation that needs the whole model (missing
//! nodes, duplicate ids, non-finite coordinates) happens here and names the place.

use crate::dof::DofSet;
use crate::element::{Element, NodeKinematics};
use crate::error::FemError;
use crate::limits::{self, fmt_num};
use crate::loads::Load;
use crate::moving::{CarriedNode, Carrier};
use crate::recorder::RecorderSpec;
use crate::registry::{self, BuildContext, ElementSpec};
use nalgebra::{Matrix3, Vector3};
use serde::{Deserialize, Serialize};
use std::any::Any;
use std::collections::HashMap;
use std::sync::Arc;

/// A node: a user id, a reference position and the DOFs held fixed.
#[derive(Debug, Clone, PartialEq)]
pub struct Node {
    /// User id (unique in the model).
    pub id: u64,
    /// Reference position in global X-Y-Z (m) at t = 0.
    pub position: Vector3<f64>,
    /// DOFs held at zero.
    pub fixed: DofSet,
    /// Whether an element owns this node (not written in model files).
    pub internal: bool,
}

/// A rigid link: the slave's DOFs follow the master's as a rigid body,
/// `u_s = u_m + θ_m × (x_s − x_m)`, `θ_s = θ_m` (small rotations), eliminated by
/// transformation when equations are numbered (never by penalty).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RigidLink {
    /// Master node index.
    pub master: usize,
    /// Slave node index.
    pub slave: usize,
    /// Which of the slave's DOFs are constrained (the others stay free).
    pub dofs: DofSet,
}

/// One element of the model with its user id and where it came from.
pub struct ElementEntry {
    /// User id.
    pub id: u64,
    /// The element.
    pub element: Box<dyn Element>,
    /// Where it was defined, for messages.
    pub origin: String,
}

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
    /// `partitioned` for large models with moving or nonlinear elements (at least
    /// [`PARTITIONED_FROM`] equations); `low_rank` for a transient below that size whose
    /// moving or nonlinear elements have at most [`LOW_RANK_MAX_DOFS`] DOFs in all and
    /// which is too large for the dense solver; `direct` otherwise.
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

/// Equation count from which `solver = "auto"` picks the partitioned solver.
pub const PARTITIONED_FROM: usize = 50_000;

/// Largest total DOF count of the moving and nonlinear elements for which `solver = "auto"`
/// picks the low-rank solver (below [`PARTITIONED_FROM`] equations): a few riders on a
/// bridge. The bordered solve costs `O(n·s)` per solve and `O(s³)` per iteration for `s`
/// such equations, against a sparse refactorization per iteration.
pub const LOW_RANK_MAX_DOFS: usize = 64;

/// Systems of at most this many equations are factored densely by the driver. Measured
/// (`railfem bench --case threshold`, docs/performance.md, "Small models and the bandwidth
/// floor"): on a beam's effective tangent the dense LU's factorization + solve costs 0.79,
/// 0.85, 0.99, 1.10, 1.26 times the sparse solver's at n = 6, 12, 18, 24, 30 equations and
/// 6.2 times at 198; on vehicles (66 equations a carriage) 2.7 times at 66. One solve alone
/// crosses over sooner (dense 1.2 times slower at 12). 16 is where the two are even.
pub const DENSE_UP_TO: usize = 16;

/// Equation count above which `solver = "auto"` may pick the low-rank solver: up to it the
/// driver factors the whole tangent densely, which is as cheap.
pub const LOW_RANK_FROM: usize = DENSE_UP_TO;

impl SolverChoice {
    /// The solver a model of `n` equations runs with: `auto` resolved (never returns
    /// `Auto`). `variable_dofs` is the total DOF count of the moving and nonlinear
    /// elements (`None`: there are none), `transient` whether the analysis is one.
    pub fn resolve(self, n: usize, variable_dofs: Option<usize>, transient: bool) -> SolverChoice {
        match (self, variable_dofs) {
            (SolverChoice::Auto, None) => SolverChoice::Direct,
            (SolverChoice::Auto, Some(_)) if n >= PARTITIONED_FROM => SolverChoice::Partitioned,
            (SolverChoice::Auto, Some(d))
                if transient && n > LOW_RANK_FROM && d <= LOW_RANK_MAX_DOFS =>
            {
                SolverChoice::LowRank
            }
            (SolverChoice::Auto, Some(_)) => SolverChoice::Direct,
            (other, _) => other,
        }
    }
}

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

/// A finished model, ready for a solver.
pub struct Model {
    /// Name of the file (or builder) it came from, for messages.
    pub origin: String,
    /// Nodes, indexed by node index.
    pub nodes: Vec<Node>,
    /// Node user id → index.
    pub node_index: HashMap<u64, usize>,
    /// Rigid links.
    pub links: Vec<RigidLink>,
    /// Elements.
    pub elements: Vec<ElementEntry>,
    /// Loads.
    pub loads: Vec<Load>,
    /// Moving reference frames.
    pub carriers: Vec<Carrier>,
    /// Recorders.
    pub recorders: Vec<RecorderSpec>,
    /// Analysis settings.
    pub analysis: AnalysisSpec,
    /// Plugins the model file asked for (paths), already loaded.
    pub plugins: Vec<String>,
    /// Nodes whose rotational DOFs hold finite rotations although no attached element
    /// declares [`crate::ElementProperties::finite_rotations`] (a nonlinear rigid link's
    /// master, for instance): see [`Model::mark_finite_rotation`] and
    /// [`crate::dofmap::DofMap::finite_rotation`].
    pub finite_rotation_nodes: Vec<usize>,
}

impl Model {
    /// Index of the node with user id `id`.
    pub fn node(&self, id: u64) -> Option<usize> {
        self.node_index.get(&id).copied()
    }

    /// Node kinematics at time `t`: reference positions and axes, following the carriers.
    pub fn kinematics(&self, t: f64) -> Vec<NodeKinematics> {
        let mut k: Vec<NodeKinematics> = self
            .nodes
            .iter()
            .map(|n| NodeKinematics::fixed(n.position))
            .collect();
        for c in &self.carriers {
            for cn in &c.nodes {
                let r = c.reference(cn, t);
                k[cn.node] = NodeKinematics {
                    position: r.position,
                    frame: r.point.frame,
                    carried: true,
                    station: Some(r.point.station),
                };
            }
        }
        k
    }

    /// For each node, the carrier and carried-node record that carries it, if any.
    pub fn carried_by(&self) -> Vec<Option<(usize, CarriedNode)>> {
        let mut v = vec![None; self.nodes.len()];
        for (ci, c) in self.carriers.iter().enumerate() {
            for cn in &c.nodes {
                v[cn.node] = Some((ci, *cn));
            }
        }
        v
    }

    /// Marks node index `node` as a finite-rotation node: its three rotational DOFs hold
    /// the total rotation vector and the driver updates them by composition
    /// ([`crate::rotation`]). Elements declaring `finite_rotations` mark their nodes
    /// themselves; this is for anything else that needs it (nonlinear rigid links mark
    /// their masters). Call before the model is handed to a driver (equations are numbered
    /// once).
    pub fn mark_finite_rotation(&mut self, node: usize) {
        if !self.finite_rotation_nodes.contains(&node) {
            self.finite_rotation_nodes.push(node);
        }
    }

    /// A human name for DOF `dof` of node index `node` (`"node 12 uz"`).
    pub fn dof_name(&self, node: usize, dof: usize) -> String {
        let d = crate::dof::Dof::from_index(dof)
            .map(|d| d.name())
            .unwrap_or("?");
        match self.nodes.get(node) {
            Some(n) if n.internal => format!("internal node {} {d}", n.id),
            Some(n) => format!("node {} {d}", n.id),
            None => format!("node #{node} {d}"),
        }
    }
}

/// Shared resources elements may ask for while being built (a track, profiles).
pub type Resources = HashMap<String, Arc<dyn Any + Send + Sync>>;

/// Builds a [`Model`] step by step, in Rust code or from a model file.
pub struct ModelBuilder {
    origin: String,
    nodes: Vec<Node>,
    node_index: HashMap<u64, usize>,
    links: Vec<(u64, u64, DofSet, Option<Geometry>, String)>,
    element_specs: Vec<ElementSpec>,
    loads: Vec<crate::loads::LoadSpec>,
    carriers: Vec<CarrierSpec>,
    recorders: Vec<RecorderSpec>,
    analysis: AnalysisSpec,
    resources: Resources,
    plugins: Vec<String>,
    errors: Vec<FemError>,
}

/// A carrier before its node ids are resolved.
#[derive(Debug, Clone)]
pub struct CarrierSpec {
    /// The carrier, with `nodes` empty.
    pub carrier: Carrier,
    /// Node ids with their station offsets and wheel-frame offsets
    /// `[lateral, vertical, longitudinal]` (m).
    pub nodes: Vec<(u64, f64, [f64; 3])>,
}

impl ModelBuilder {
    /// An empty model; `origin` names it in messages (a file name, or `"builder"`).
    pub fn new(origin: impl Into<String>) -> Self {
        ModelBuilder {
            origin: origin.into(),
            nodes: Vec::new(),
            node_index: HashMap::new(),
            links: Vec::new(),
            element_specs: Vec::new(),
            loads: Vec::new(),
            carriers: Vec::new(),
            recorders: Vec::new(),
            analysis: AnalysisSpec::default(),
            resources: HashMap::new(),
            plugins: Vec::new(),
            errors: Vec::new(),
        }
    }

    /// Name used in messages.
    pub fn origin(&self) -> &str {
        &self.origin
    }

    /// Adds a node at `xyz` (m) with no fixity. Duplicate ids and non-finite coordinates
    /// are reported when the model is built.
    pub fn node(&mut self, id: u64, xyz: [f64; 3]) -> &mut Self {
        self.node_fixed(id, xyz, DofSet::NONE)
    }

    /// Adds a node with the given fixed DOFs.
    pub fn node_fixed(&mut self, id: u64, xyz: [f64; 3], fixed: DofSet) -> &mut Self {
        let place = format!("{}: node {id}", self.origin);
        if self.node_index.contains_key(&id) {
            self.errors.push(FemError::input(
                place,
                "duplicate node id; every node needs its own id",
            ));
            return self;
        }
        if xyz.iter().any(|v| !v.is_finite()) {
            self.errors.push(FemError::input(
                place,
                format!("`xyz` = {xyz:?} is not finite; give three finite coordinates in m"),
            ));
            return self;
        }
        self.node_index.insert(id, self.nodes.len());
        self.nodes.push(Node {
            id,
            position: Vector3::from(xyz),
            fixed,
            internal: false,
        });
        self
    }

    /// Fixes more DOFs of an existing node.
    pub fn fix(&mut self, id: u64, dofs: DofSet) -> &mut Self {
        match self.node_index.get(&id) {
            Some(&i) => self.nodes[i].fixed = self.nodes[i].fixed.union(dofs),
            None => self.errors.push(FemError::input(
                format!("{}: fix", self.origin),
                format!("node {id} does not exist; define it before fixing it"),
            )),
        }
        self
    }

    /// Whether a node id exists.
    pub fn has_node(&self, id: u64) -> bool {
        self.node_index.contains_key(&id)
    }

    /// Reference position of a node id, if it exists.
    pub fn node_position(&self, id: u64) -> Option<Vector3<f64>> {
        self.node_index.get(&id).map(|&i| self.nodes[i].position)
    }

    /// The largest node id so far (0 if none), for generators that add nodes.
    pub fn max_node_id(&self) -> u64 {
        self.nodes.iter().map(|n| n.id).max().unwrap_or(0)
    }

    /// The largest element id so far (0 if none).
    pub fn max_element_id(&self) -> u64 {
        self.element_specs.iter().map(|e| e.id).max().unwrap_or(0)
    }

    /// The elements added so far, in order (what a generator made, for inspection).
    pub fn element_specs(&self) -> &[ElementSpec] {
        &self.element_specs
    }

    /// Adds an element of registered type `kind` with parameters `params` (any serde
    /// struct or JSON object with the kind's keys).
    pub fn element<P: Serialize>(
        &mut self,
        kind: &str,
        id: u64,
        nodes: &[u64],
        params: &P,
    ) -> &mut Self {
        let origin = format!("{}: element {id} ({kind})", self.origin);
        match serde_json::to_value(params) {
            Ok(serde_json::Value::Object(map)) => self.element_spec(ElementSpec {
                id,
                kind: kind.to_string(),
                nodes: nodes.to_vec(),
                params: map,
                origin,
            }),
            Ok(serde_json::Value::Null) => self.element_spec(ElementSpec {
                id,
                kind: kind.to_string(),
                nodes: nodes.to_vec(),
                params: serde_json::Map::new(),
                origin,
            }),
            Ok(_) | Err(_) => {
                self.errors.push(FemError::input(
                    origin,
                    "parameters must serialise to a table of keys",
                ));
                self
            }
        }
    }

    /// Adds an element from a ready spec (the model-file path).
    pub fn element_spec(&mut self, spec: ElementSpec) -> &mut Self {
        self.element_specs.push(spec);
        self
    }

    /// Adds a rigid link: `slave` follows `master` on `dofs`.
    pub fn rigid_link(&mut self, master: u64, slave: u64, dofs: DofSet) -> &mut Self {
        let origin = format!("{}: link {master} -> {slave}", self.origin);
        self.rigid_link_with(master, slave, dofs, None, origin)
    }

    /// Adds a rigid link with its own geometry (`None`: the `[analysis]` one); `origin`
    /// names it in messages (`file: link[3]`).
    pub fn rigid_link_with(
        &mut self,
        master: u64,
        slave: u64,
        dofs: DofSet,
        geometry: Option<Geometry>,
        origin: String,
    ) -> &mut Self {
        self.links.push((master, slave, dofs, geometry, origin));
        self
    }

    /// Adds a load.
    pub fn load(&mut self, load: crate::loads::LoadSpec) -> &mut Self {
        self.loads.push(load);
        self
    }

    /// Adds a carrier (moving reference frame) with its nodes given by user id:
    /// `(id, station offset, [lateral, vertical, longitudinal] offsets)` in m.
    pub fn carrier(&mut self, carrier: Carrier, nodes: Vec<(u64, f64, [f64; 3])>) -> &mut Self {
        self.carriers.push(CarrierSpec { carrier, nodes });
        self
    }

    /// Adds a recorder.
    pub fn recorder(&mut self, r: RecorderSpec) -> &mut Self {
        self.recorders.push(r);
        self
    }

    /// Sets the analysis.
    pub fn analysis(&mut self, a: AnalysisSpec) -> &mut Self {
        self.analysis = a;
        self
    }

    /// The analysis settings so far.
    pub fn analysis_mut(&mut self) -> &mut AnalysisSpec {
        &mut self.analysis
    }

    /// Makes a shared resource available to element factories under `name`.
    pub fn resource(&mut self, name: &str, r: Arc<dyn Any + Send + Sync>) -> &mut Self {
        self.resources.insert(name.to_string(), r);
        self
    }

    /// A shared resource registered under `name`, if any.
    pub fn resource_get(&self, name: &str) -> Option<Arc<dyn Any + Send + Sync>> {
        self.resources.get(name).cloned()
    }

    /// Records a plugin path the model uses (it must already be loaded).
    pub fn plugin(&mut self, path: &str) -> &mut Self {
        self.plugins.push(path.to_string());
        self
    }

    /// Records an error found by a generator or a model-file section.
    pub fn error(&mut self, e: FemError) -> &mut Self {
        self.errors.push(e);
        self
    }

    /// Resolves ids, builds every element through the registry and checks the whole.
    ///
    /// Problems are collected, not returned at the first: the builder's own (reading the
    /// file), then every element, link and carrier, then every load and recorder. A stage
    /// runs only if the one before it was clean, so that one mistake is not reported again
    /// by everything that refers to it. Several problems come back as [`FemError::Many`].
    pub fn build(self) -> Result<Model, FemError> {
        let ModelBuilder {
            origin,
            nodes,
            node_index,
            links,
            element_specs,
            loads,
            carriers,
            recorders,
            analysis,
            resources,
            plugins,
            errors,
        } = self;
        // The `[analysis]` settings are independent of the nodes and elements: their
        // problems are listed with those of the next stage instead of hiding them.
        // So are the names of the recorders' files (inside `--out`, unique, not railfem's own).
        let analysis_problem = analysis.validate(&origin).err();
        let files: Vec<&str> = recorders.iter().map(RecorderSpec::file).collect();
        let output_problem = crate::outputs::check_recorder_files(&files)
            .err()
            .map(|(i, m)| FemError::input(format!("{origin}: recorder[{i}]"), m));
        FemError::from_list(errors)?;
        let mut errors: Vec<FemError> =
            analysis_problem.into_iter().chain(output_problem).collect();
        // Carriers first: internal nodes inherit them.
        let mut carried: Vec<Option<(usize, CarriedNode)>> = vec![None; nodes.len()];
        let mut carrier_list = Vec::new();
        for (ci, cs) in carriers.into_iter().enumerate() {
            let mut c = cs.carrier;
            for (id, ds, [lat, vert, long]) in cs.nodes {
                let Some(&ni) = node_index.get(&id) else {
                    errors.push(FemError::input(
                        format!("{origin}: carrier `{}`", c.name),
                        format!(
                            "node {id} does not exist; define it or remove it from the carrier"
                        ),
                    ));
                    continue;
                };
                if !(ds.is_finite() && lat.is_finite() && vert.is_finite() && long.is_finite()) {
                    errors.push(FemError::input(
                        format!("{origin}: carrier `{}`", c.name),
                        format!("offsets of node {id} are not finite"),
                    ));
                    continue;
                }
                let cn = CarriedNode {
                    node: ni,
                    station_offset: ds,
                    lateral: lat,
                    vertical: vert,
                    longitudinal: long,
                };
                carried[ni] = Some((ci, cn));
                c.nodes.push(cn);
            }
            carrier_list.push(c);
        }
        let element_nodes = element_specs
            .iter()
            .map(|e| (e.id, (e.kind.clone(), e.nodes.clone())))
            .collect();
        let mut ctx = Ctx {
            nodes,
            node_index,
            carried,
            resources,
            carriers: carrier_list.clone(),
            element_nodes,
        };
        let mut elements = Vec::with_capacity(element_specs.len());
        let mut seen_ids = HashMap::new();
        for spec in element_specs {
            if let Some(prev) = seen_ids.insert(spec.id, spec.origin.clone()) {
                errors.push(FemError::input(
                    &spec.origin,
                    format!(
                        "duplicate element id {} (also {prev}); give each element its own id",
                        spec.id
                    ),
                ));
                continue;
            }
            if let Some(e) = element_nodes_problem(&spec, &ctx.node_index) {
                errors.push(e);
                continue;
            }
            match registry::build(&spec, &mut ctx) {
                Ok(element) => elements.push(ElementEntry {
                    id: spec.id,
                    element,
                    origin: spec.origin,
                }),
                Err(e) => errors.push(e),
            }
        }
        let Ctx {
            nodes,
            node_index,
            carried,
            ..
        } = ctx;
        // Internal nodes that inherited a carrier.
        for (ni, c) in carried.iter().enumerate() {
            if let Some((ci, cn)) = c {
                if !carrier_list[*ci].nodes.iter().any(|x| x.node == ni) {
                    carrier_list[*ci].nodes.push(*cn);
                }
            }
        }
        let mut link_list = Vec::new();
        let mut nonlinear_links = Vec::new();
        for (m, s, dofs, geometry, lorigin) in links {
            let link = match resolve_link(&nodes, &node_index, m, s, dofs, &lorigin) {
                Ok(l) => l,
                Err(e) => {
                    errors.push(e);
                    continue;
                }
            };
            if geometry.unwrap_or(analysis.geometry) == Geometry::Nonlinear {
                if dofs != DofSet::ALL {
                    errors.push(FemError::input(
                        lorigin,
                        "a geometry = \"nonlinear\" link makes the slave part of the master's rigid body and must constrain all six DOFs: drop `dofs`, or give the link geometry = \"linear\"",
                    ));
                    continue;
                }
                nonlinear_links.push((link.master, link.slave, lorigin));
                continue;
            }
            link_list.push(link);
        }
        FemError::from_list(errors)?;
        let mut errors = Vec::new();
        let mut model = Model {
            origin,
            nodes,
            node_index,
            links: link_list,
            elements,
            loads: Vec::new(),
            carriers: carrier_list,
            recorders: Vec::new(),
            analysis,
            plugins,
            finite_rotation_nodes: Vec::new(),
        };
        if !nonlinear_links.is_empty() {
            crate::finite_link::apply(&mut model, &nonlinear_links, &loads, &recorders)?;
        }
        for (i, l) in loads.iter().enumerate() {
            match l.resolve_at(&model, Some(i)) {
                Ok(load) => model.loads.push(load),
                Err(e) => errors.push(e),
            }
        }
        for (i, r) in recorders.iter().enumerate() {
            if let Err(e) = r.validate_at(&model, Some(i)) {
                errors.push(e);
            }
        }
        FemError::from_list(errors)?;
        model.recorders = recorders;
        Ok(model)
    }
}

/// A problem with an element's `nodes`: a node that does not exist, or one listed twice
/// (a spring from a node to itself is no spring; a grounded spring lists one node).
fn element_nodes_problem(spec: &ElementSpec, index: &HashMap<u64, usize>) -> Option<FemError> {
    for (k, nid) in spec.nodes.iter().enumerate() {
        if !index.contains_key(nid) {
            return Some(FemError::input(
                &spec.origin,
                format!("node {nid} does not exist; define it in a [[node]] table or fix the id"),
            ));
        }
        if spec.nodes[..k].contains(nid) {
            return Some(FemError::input(
                &spec.origin,
                format!(
                    "`nodes` lists node {nid} twice; an element joins distinct nodes (a spring to the ground lists one node: `nodes = [{nid}]`)"
                ),
            ));
        }
    }
    None
}

/// Resolves a link's node ids and refuses a slave that is also fixed on a DOF the link
/// constrains: the link would override the `fix` without a word.
fn resolve_link(
    nodes: &[Node],
    index: &HashMap<u64, usize>,
    m: u64,
    s: u64,
    dofs: DofSet,
    origin: &str,
) -> Result<RigidLink, FemError> {
    let (Some(&mi), Some(&si)) = (index.get(&m), index.get(&s)) else {
        let missing = if index.contains_key(&m) { s } else { m };
        return Err(FemError::input(
            origin,
            format!("node {missing} does not exist; define it or fix the link"),
        ));
    };
    if mi == si {
        return Err(FemError::input(origin, "a node cannot be linked to itself"));
    }
    let both = DofSet::from_bits(nodes[si].fixed.bits() & dofs.bits());
    if !both.is_empty() {
        let names: Vec<&str> = both.iter().map(|d| d.name()).collect();
        return Err(FemError::input(
            origin,
            format!(
                "slave node {s} is fixed on {} which the link also constrains (a slave follows its master; the `fix` would be ignored); fix the master node {m} instead, or remove {} from the slave's `fix` or from the link's `dofs`",
                names.join(", "),
                names.join(", ")
            ),
        ));
    }
    Ok(RigidLink {
        master: mi,
        slave: si,
        dofs,
    })
}

struct Ctx {
    nodes: Vec<Node>,
    node_index: HashMap<u64, usize>,
    carried: Vec<Option<(usize, CarriedNode)>>,
    resources: Resources,
    carriers: Vec<Carrier>,
    /// Type and node ids of every element spec, by element id.
    element_nodes: HashMap<u64, (String, Vec<u64>)>,
}

impl BuildContext for Ctx {
    fn element_nodes(&self, id: u64) -> Option<(String, Vec<usize>)> {
        let (kind, ids) = self.element_nodes.get(&id)?;
        let idx = ids
            .iter()
            .map(|n| self.node_index.get(n).copied())
            .collect::<Option<Vec<usize>>>()?;
        Some((kind.clone(), idx))
    }
    fn node_index(&self, id: u64) -> Option<usize> {
        self.node_index.get(&id).copied()
    }
    fn node_carried(&self, index: usize) -> Option<bool> {
        self.carried.get(index).map(Option::is_some)
    }
    fn node_position(&self, index: usize) -> Vector3<f64> {
        self.nodes[index].position
    }
    fn add_internal_node(&mut self, position: Vector3<f64>, like: Option<usize>) -> usize {
        let id = self
            .nodes
            .iter()
            .map(|n| n.id)
            .max()
            .unwrap_or(0)
            .max(1 << 40)
            + 1;
        let idx = self.nodes.len();
        self.node_index.insert(id, idx);
        self.nodes.push(Node {
            id,
            position,
            fixed: DofSet::NONE,
            internal: true,
        });
        // An internal node rides with `like` at the same station, offset in the wheel
        // frame by its position relative to `like` at t = 0.
        let like_pos = like.map(|l| self.nodes[l].position);
        let inherited = like.and_then(|l| self.carried[l]).map(|(ci, cn)| {
            let c = &self.carriers[ci];
            let frame = c.path.at(c.station(0.0) + cn.station_offset).frame;
            let d = position - like_pos.unwrap_or(position);
            (
                ci,
                CarriedNode {
                    node: idx,
                    lateral: cn.lateral + frame.column(0).dot(&d),
                    vertical: cn.vertical + frame.column(1).dot(&d),
                    longitudinal: cn.longitudinal + frame.column(2).dot(&d),
                    ..cn
                },
            )
        });
        self.carried.push(inherited);
        idx
    }
    fn resource(&self, name: &str) -> Option<Arc<dyn Any + Send + Sync>> {
        self.resources.get(name).cloned()
    }
}

/// The frame of node `i` as a 3×3 rotation (identity when not carried).
pub fn node_frame(k: &[NodeKinematics], i: usize) -> Matrix3<f64> {
    k[i].frame
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

//! The element contract: what every element, built-in or plugin, provides to the framework.
//!
//! An element knows its nodes and the DOFs it uses at each, and for a trial state returns
//! its resisting force and tangent stiffness, its mass and its damping. It commits or
//! reverts its history (stick anchors, plastic strain) when the driver says so, and it
//! declares what it is ([`ElementProperties`]) so the framework can skip work: constant
//! matrices are assembled once, elements without mass or damping are never asked for them,
//! and only elements whose connectivity may change cause the sparsity pattern to be
//! rebuilt. The shape follows OpenSees' `Element` (`setTrial…`, `getResistingForce`,
//! `getTangentStiff`, `commitState`, `revertToLastCommit`), with typed errors instead of
//! return codes and the capability flags added.
//!
//! **Axes.** Element vectors and matrices are expressed in the axes of the element's nodes
//! (the node's *frame*). For ordinary nodes that frame is the global X-Y-Z; nodes carried by
//! a moving vehicle have the track's wheel frame 1-2-3 at their station as their axes (see
//! [`crate::moving`]). An element that needs global geometry (the moving axle, for instance)
//! reads the current frames from the [`StepContext`] passed to [`Element::advance`].
//!
//! **Ordering.** Element vectors list the nodes in the order of
//! [`Element::connectivity`], and within a node the DOFs it uses in the order
//! ux, uy, uz, rx, ry, rz.

use crate::dof::DofSet;
use nalgebra::{DMatrix, Matrix3, Vector3};
use thiserror::Error;

/// A node of an element and the DOFs the element uses there.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct NodeDofs {
    /// Index of the node in the model's node list.
    pub node: usize,
    /// The DOFs the element couples at that node.
    pub dofs: DofSet,
}

impl NodeDofs {
    /// All six DOFs at `node`.
    pub fn all(node: usize) -> Self {
        NodeDofs {
            node,
            dofs: DofSet::ALL,
        }
    }

    /// The three translations at `node`.
    pub fn translations(node: usize) -> Self {
        NodeDofs {
            node,
            dofs: DofSet::TRANSLATIONS,
        }
    }
}

/// What an element declares about itself so the framework can skip work.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ElementProperties {
    /// The resisting force is `K·u` with a constant `K` (a linear element on fixed nodes):
    /// the framework assembles `K` once and never calls [`Element::update`] for it.
    pub linear: bool,
    /// The mass matrix never changes (assembled once).
    pub constant_mass: bool,
    /// The damping matrix never changes (assembled once).
    pub constant_damping: bool,
    /// The element has a mass matrix at all.
    pub has_mass: bool,
    /// The element has a damping matrix at all.
    pub has_damping: bool,
    /// The tangent stiffness is symmetric.
    pub symmetric: bool,
    /// The element may change its nodes between steps ([`Element::advance`] returns `true`).
    pub connectivity_may_change: bool,
    /// Rigid-body translations and rotations of its nodes produce no resisting force
    /// (checked by the conformance kit).
    pub objective: bool,
    /// The translational mass the element represents (kg), if it has one; the conformance
    /// kit checks the mass matrix against it.
    pub declared_mass: Option<f64>,
    /// The element reads the rotational DOFs of its nodes as finite rotations: total rotation
    /// vectors whose increments the driver composes, with force and tangent conjugate to the
    /// spatial spin (see [`crate::rotation`]). Nodes of such elements are finite-rotation
    /// nodes for every element attached to them.
    pub finite_rotations: bool,
}

impl Default for ElementProperties {
    /// A nonlinear, massless, undamped, symmetric, objective element with fixed nodes.
    fn default() -> Self {
        ElementProperties {
            linear: false,
            constant_mass: true,
            constant_damping: true,
            has_mass: false,
            has_damping: false,
            symmetric: true,
            connectivity_may_change: false,
            objective: true,
            declared_mass: None,
            finite_rotations: false,
        }
    }
}

/// Current reference position and axes of one node.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NodeKinematics {
    /// Reference position in global X-Y-Z (m). For a carried node it moves with the carrier.
    pub position: Vector3<f64>,
    /// The node's axes in global coordinates: column `i` is the unit vector of axis `i`.
    /// Identity for ordinary nodes.
    pub frame: Matrix3<f64>,
    /// Whether the node is carried by a moving reference frame.
    pub carried: bool,
    /// Station along the carrier's path (m), for a carried node.
    pub station: Option<f64>,
}

impl NodeKinematics {
    /// A fixed node at `position` with global axes.
    pub fn fixed(position: Vector3<f64>) -> Self {
        NodeKinematics {
            position,
            frame: Matrix3::identity(),
            carried: false,
            station: None,
        }
    }
}

/// What the framework tells an element at the start of each step.
pub struct StepContext<'a> {
    /// Time at the end of the step about to be solved (s).
    pub time: f64,
    /// Step length (s); zero in a static analysis.
    pub dt: f64,
    /// Kinematics of every node of the model, indexed by node index.
    pub nodes: &'a [NodeKinematics],
}

/// A trial state of an element's DOFs, in element order and nodal axes.
pub struct TrialState<'a> {
    /// Time of the trial state (s).
    pub time: f64,
    /// Step length (s); zero in a static analysis.
    pub dt: f64,
    /// Total displacements (m, rad) from the reference configuration.
    pub disp: &'a [f64],
    /// Velocities (m/s, rad/s).
    pub vel: &'a [f64],
    /// Accelerations (m/s², rad/s²).
    pub acc: &'a [f64],
}

/// What can go wrong inside an element.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum ElementError {
    /// A NaN or infinity appeared in the element's state or output.
    #[error("non-finite value in {what}")]
    NonFinite {
        /// Which quantity went non-finite.
        what: String,
    },
    /// The element cannot be evaluated at this state (e.g. a wheel off the end of the track).
    #[error("{0}")]
    Invalid(String),
}

/// The unit an element writes for an output whose unit it does not declare
/// ([`Element::output_units`]' default): the recorder header reads `5_force [?]`.
pub const UNIT_UNDECLARED: &str = "?";

/// The active set a contact element evaluates with ([`Element::hold_active_set`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ActiveSet {
    /// Each evaluation finds every point's status from its gap and slip.
    Found,
    /// Held at the statuses of the last converged step.
    Committed,
    /// Held at the statuses the last evaluation found.
    LastFound,
    /// Held at the statuses the last evaluation found, except that a point held sliding
    /// one way and found sliding the other way is held sticking: the status between the
    /// two (solvers/src/held_active_set.rs, when the [`ActiveSet::LastFound`] rounds did
    /// not settle).
    LastFoundStickingReversals,
}

/// Where an element's dissipated energy goes in the energy ledger.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DissipationKind {
    /// Sliding friction at contact points (the moving wheel-axle element).
    Friction,
    /// Dissipation inside the material: plasticity, hysteresis.
    Material,
}

/// The element contract. See the module documentation for axes and ordering.
///
/// # Example
///
/// A linear spring of stiffness `k` from a node's `uz` to the ground: one DOF, resisting
/// force `k·u`, tangent `k`. (Registering it as a kind with parameters and samples, and
/// shipping it as a plugin: `docs/custom-element.md`.)
///
/// ```
/// use nalgebra::DMatrix;
/// use railfem_framework::element::{Element, ElementError, ElementProperties, NodeDofs, TrialState};
/// use railfem_framework::{Dof, DofSet};
///
/// struct GroundSpring {
///     nodes: [NodeDofs; 1],
///     k: f64, // N/m
///     u: f64, // trial displacement (m)
/// }
///
/// impl Element for GroundSpring {
///     fn kind(&self) -> &str {
///         "ground_spring"
///     }
///     fn connectivity(&self) -> &[NodeDofs] {
///         &self.nodes
///     }
///     fn properties(&self) -> ElementProperties {
///         ElementProperties::default()
///     }
///     fn update(&mut self, trial: &TrialState) -> Result<(), ElementError> {
///         self.u = trial.disp[0];
///         Ok(())
///     }
///     fn resisting_force(&self, f: &mut [f64]) {
///         f[0] = self.k * self.u;
///     }
///     fn tangent_stiffness(&self, k: &mut DMatrix<f64>) {
///         k[(0, 0)] = self.k;
///     }
/// }
///
/// let node = NodeDofs { node: 0, dofs: DofSet::of(&[Dof::Uz]) };
/// let mut spring = GroundSpring { nodes: [node], k: 5.0e5, u: 0.0 };
/// assert_eq!(spring.ndof(), 1);
/// let trial = TrialState { time: 0.0, dt: 0.0, disp: &[2.0e-3], vel: &[0.0], acc: &[0.0] };
/// spring.update(&trial).unwrap();
/// let mut f = [0.0];
/// spring.resisting_force(&mut f);
/// // Hooke: 5e5 N/m × 2 mm = 1 kN.
/// assert!((f[0] - 1000.0).abs() < 1e-9, "{}", f[0]);
/// ```
pub trait Element: Send + Sync {
    /// The registered type name (`"beam3d"`, `"moving_axle"`, …).
    fn kind(&self) -> &str;

    /// The element's nodes and the DOFs used at each, in element order.
    fn connectivity(&self) -> &[NodeDofs];

    /// What the element declares about itself.
    fn properties(&self) -> ElementProperties;

    /// Number of element DOFs (the sum over nodes of the DOFs used).
    fn ndof(&self) -> usize {
        self.connectivity().iter().map(|n| n.dofs.count()).sum()
    }

    /// Called at the start of each step with the new time and the current node kinematics.
    /// Returns `true` if the element's connectivity changed (it re-picked its nodes).
    fn advance(&mut self, _ctx: &StepContext) -> Result<bool, ElementError> {
        Ok(false)
    }

    /// Sets the trial state and computes what the following accessors return.
    fn update(&mut self, trial: &TrialState) -> Result<(), ElementError>;

    /// Resisting force at the trial state (N, N·m), length [`Element::ndof`].
    fn resisting_force(&self, f: &mut [f64]);

    /// Tangent stiffness at the trial state (N/m, N·m/rad), `ndof × ndof`, already zeroed.
    fn tangent_stiffness(&self, k: &mut DMatrix<f64>);

    /// Mass matrix (kg, kg·m²), `ndof × ndof`, already zeroed.
    fn mass(&self, _m: &mut DMatrix<f64>) {}

    /// Damping matrix (N·s/m, N·m·s/rad), `ndof × ndof`, already zeroed.
    fn damping(&self, _c: &mut DMatrix<f64>) {}

    /// Accepts the trial state as the new committed state (a step converged).
    fn commit(&mut self) {}

    /// Returns to the last committed state (a step is being retried). An active set held by
    /// [`Element::hold_active_set`] stays held.
    fn revert(&mut self) {}

    /// How a contact element sets its points' statuses (open, stick, slide and its
    /// direction) in the evaluations that follow: found at each evaluation (the default,
    /// and again after every commit) or held fixed. Returns whether the element has an
    /// active set (elements without contact ignore the call and return `false`).
    fn hold_active_set(&mut self, _set: ActiveSet) -> bool {
        false
    }

    /// How many of the element's points the last evaluation found in a status other than
    /// the held one (0 when nothing is held): 0 means the held evaluation was the element's
    /// own law.
    fn active_set_changes(&self) -> usize {
        0
    }

    /// Names of the scalar results the element reports (for element recorders).
    fn output_names(&self) -> Vec<String> {
        Vec::new()
    }

    /// The SI unit of each output, in the order of [`Element::output_names`], as recorder
    /// headers write it after the name (`5_Q [N]`): `"N"`, `"m"`, `"N·m"`, `"m/s²"`, `"-"`
    /// for a ratio, a count or a flag. The default, for an element that declares none, is
    /// [`UNIT_UNDECLARED`] (`"?"`) for every output, so the header says the unit is not known
    /// rather than guess one.
    fn output_units(&self) -> Vec<String> {
        vec![UNIT_UNDECLARED.to_string(); self.output_names().len()]
    }

    /// The scalar results at the trial state, in the order of [`Element::output_names`].
    fn outputs(&self, _out: &mut Vec<f64>) {}

    /// The element's parameters as JSON (used for the serde round trip and for echoing
    /// inputs beside outputs).
    fn parameters(&self) -> serde_json::Value {
        serde_json::Value::Null
    }

    /// Energy dissipated inside the element since the start (J): friction, plasticity.
    /// Say which of the two it is with [`Element::dissipation_kind`].
    fn dissipated_energy(&self) -> f64 {
        0.0
    }

    /// What [`Element::dissipated_energy`] is: the energy ledger books it under that
    /// heading (`energy.csv`'s `friction [J]` or `material [J]`). Material (plasticity,
    /// hysteresis) unless the element says friction, as a contact element does.
    fn dissipation_kind(&self) -> DissipationKind {
        DissipationKind::Material
    }

    /// The concrete element, for callers that know its type (tests, plots of one element's
    /// state). `None` unless the element opts in.
    fn as_any(&self) -> Option<&dyn std::any::Any> {
        None
    }
}

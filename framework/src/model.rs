//! The model: nodes, rigid links, elements, loads, carriers, recorders and analysis
//! settings ([`Model`]), what the solvers run.
//!
//! A model is built either from a model file ([`crate::modelfile`]) or in Rust code with a
//! [`crate::builder::ModelBuilder`]. The analysis settings live in [`crate::analysis`] and are
//! re-exported here.

pub use crate::analysis::{
    AnalysisKind, AnalysisSpec, FirstActiveSet, Geometry, IntegratorKind, NewtonKind,
    NewtonSettings, Predictor, Rayleigh, SolverChoice, SolverInputs, SolverResolver,
};
use crate::dof::DofSet;
use crate::element::{Element, NodeKinematics};
use crate::loads::Load;
use crate::moving::{CarriedNode, Carrier};
use crate::recorder::RecorderSpec;
use nalgebra::{Matrix3, Vector3};
use std::collections::HashMap;

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

impl crate::lookup::ModelLookup for Model {
    fn origin(&self) -> &str {
        &self.origin
    }
    fn node_index(&self, id: u64) -> Option<usize> {
        self.node(id)
    }
    fn node_position(&self, index: usize) -> Vector3<f64> {
        self.nodes[index].position
    }
    fn element_indices(&self, ids: &[u64]) -> Vec<Option<usize>> {
        let wanted: HashMap<u64, usize> = ids.iter().enumerate().map(|(k, id)| (*id, k)).collect();
        let mut found = vec![None; ids.len()];
        for (i, e) in self.elements.iter().enumerate() {
            if let Some(&k) = wanted.get(&e.id) {
                found[k] = Some(i);
            }
        }
        // A repeated id in `ids` is found at each of its places.
        ids.iter()
            .map(|id| wanted.get(id).and_then(|&k| found[k]))
            .collect()
    }
    fn element_nodes(&self, index: usize) -> Vec<usize> {
        self.elements[index]
            .element
            .connectivity()
            .iter()
            .map(|c| c.node)
            .collect()
    }
    fn element_kind(&self, index: usize) -> &str {
        self.elements[index].element.kind()
    }
    fn element_output_names(&self, index: usize) -> Vec<String> {
        self.elements[index].element.output_names()
    }
    fn element_output_units(&self, index: usize) -> Vec<String> {
        self.elements[index].element.output_units()
    }
    fn element_ids_of_kind(&self, kind: &str) -> Vec<u64> {
        self.elements
            .iter()
            .filter(|e| e.element.kind() == kind)
            .map(|e| e.id)
            .collect()
    }
    fn analysis(&self) -> &AnalysisSpec {
        &self.analysis
    }
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

    /// A human name for DOF `d` of node index `node` (`"node 12 uz"`).
    pub fn dof_name(&self, node: usize, d: crate::dof::Dof) -> String {
        match self.nodes.get(node) {
            Some(n) if n.internal => format!("internal node {} {d}", n.id),
            Some(n) => format!("node {} {d}", n.id),
            None => format!("node #{node} {d}"),
        }
    }
}

/// The frame of node `i` as a 3×3 rotation (identity when not carried).
pub fn node_frame(k: &[NodeKinematics], i: usize) -> Matrix3<f64> {
    k[i].frame
}

//! `rotating_unbalance`, the plugin's load kind: the force of an unbalanced rotor (a mass
//! `m` at eccentricity `e` spinning at `ω`) on one node.
//!
//! The rotating mass's centripetal force, reacted by the node, has the constant magnitude
//! `m·e·ω²` and turns with the rotor: in the plane of the node DOFs `axes = [a, b]`, at
//! angle `ω·t + phase` from `a`,
//!
//! `F_a = m·e·ω²·cos(ω·t + phase)`, `F_b = m·e·ω²·sin(ω·t + phase)` (N).
//!
//! A washing machine on its springs, a wheelset's out-of-balance, a motor on a floor: the
//! textbook forced vibration (e.g. Rao, *Mechanical Vibrations*, §3.7).

use railfem_framework::load_kind::{AppliedLoad, LoadBuild, LoadEntry, LoadKind};
use railfem_framework::lookup::ModelLookup;
use railfem_framework::registry::Params;
use railfem_framework::{Dof, FemError};

railfem_framework::element_params! {
    /// Model-file keys of `rotating_unbalance`.
    pub struct UnbalanceParams {
        /// Node id the rotor acts on.
        node: u64 [""],
        /// Unbalance: rotating mass times its eccentricity.
        me: f64 ["kg*m"],
        /// Spin rate.
        omega: f64 ["rad/s"],
        /// Angle of the rotor at t = 0, from the first axis towards the second.
        phase: f64 ["rad"] = 0.0,
        /// The two translational DOFs of the rotor's plane, in the node's axes.
        axes: [Dof; 2] [""] = ["uz", "uy"],
    }
}

/// A resolved unbalance: node index, plane and force amplitude.
#[derive(Debug, Clone, PartialEq)]
pub struct RotatingUnbalance {
    node: usize,
    axes: [Dof; 2],
    /// `m·e·ω²` (N).
    amplitude: f64,
    omega: f64,
    phase: f64,
}

impl AppliedLoad for RotatingUnbalance {
    fn nodal_forces(&self, t: f64, add: &mut dyn FnMut(usize, Dof, f64)) -> Result<(), FemError> {
        let angle = self.omega * t + self.phase;
        add(self.node, self.axes[0], self.amplitude * angle.cos());
        add(self.node, self.axes[1], self.amplitude * angle.sin());
        Ok(())
    }

    fn nodes(&self) -> Vec<usize> {
        vec![self.node]
    }
}

fn build(
    entry: &LoadEntry,
    model: &dyn ModelLookup,
    origin: &str,
) -> Result<Box<dyn AppliedLoad>, FemError> {
    let p: UnbalanceParams = entry.parse(origin)?;
    let node = model.node_index(p.node).ok_or_else(|| {
        FemError::input(
            origin,
            format!(
                "node {} does not exist; define it in a [[node]] table or fix `node`",
                p.node
            ),
        )
    })?;
    if p.axes.iter().any(|d| d.index() >= 3) || p.axes[0] == p.axes[1] {
        return Err(FemError::input(
            origin,
            "`axes` must be two different translational DOFs, e.g. [\"uz\", \"uy\"]",
        ));
    }
    if p.me < 0.0 || p.omega < 0.0 {
        return Err(FemError::input(
            origin,
            "`me` and `omega` must not be negative (turn the rotor the other way with `axes` reversed)",
        ));
    }
    Ok(Box::new(RotatingUnbalance {
        node,
        axes: p.axes,
        amplitude: p.me * p.omega * p.omega,
        omega: p.omega,
        phase: p.phase,
    }))
}

/// The load kind this plugin exports.
pub const ROTATING_UNBALANCE: LoadKind = LoadKind {
    name: "rotating_unbalance",
    description: "force m·e·ω² of an unbalanced rotor turning in the plane of two node DOFs",
    params: <UnbalanceParams as Params>::docs,
    build: LoadBuild::Factory(build),
};

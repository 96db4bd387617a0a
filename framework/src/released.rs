//! The slot of an element that a rank of a shared model has let go of: what stays in
//! `Model::elements` at that index once the element itself is dropped
//! ([`crate::assembly::Assembler::release_elements`]).
//!
//! Element indices are identities across the program (the assembler's maps, recorders,
//! messages), so a released element keeps its place, its user id and origin (in the
//! [`crate::model::ElementEntry`]), and here its type name, connectivity and declared
//! properties: enough for anything that lists or names elements. It has no state and no
//! matrices. Only elements whose matrices are already in the constant `K`, `M`, `C` are
//! released, and the driver never evaluates those again; asking a released element for a
//! force or a matrix is a bug of the caller, and it says so rather than answer with zeros.

use crate::element::{Element, ElementError, ElementProperties, NodeDofs, TrialState};
use crate::model::Model;
use nalgebra::DMatrix;

/// Elements of `model` held whole on this rank (not released).
pub fn elements_held(model: &Model) -> usize {
    model
        .elements
        .iter()
        .filter(|e| !Released::is(&*e.element))
        .count()
}

/// What is left of a released element (module documentation).
#[derive(Debug, Clone)]
pub struct Released {
    kind: String,
    connectivity: Vec<NodeDofs>,
    properties: ElementProperties,
}

impl Released {
    /// The slot of `e`: its type name, connectivity and properties.
    pub fn of(e: &dyn Element) -> Released {
        Released {
            kind: e.kind().to_string(),
            connectivity: e.connectivity().to_vec(),
            properties: e.properties(),
        }
    }

    /// Whether `e` is a released slot.
    pub fn is(e: &dyn Element) -> bool {
        e.as_any().is_some_and(|a| a.is::<Released>())
    }

    fn evaluated(&self, what: &str) -> ! {
        panic!(
            "a `{}` element released on this rank (its rows belong to another rank) was asked for its {what}",
            self.kind
        )
    }
}

impl Element for Released {
    fn kind(&self) -> &str {
        &self.kind
    }

    fn connectivity(&self) -> &[NodeDofs] {
        &self.connectivity
    }

    fn properties(&self) -> ElementProperties {
        self.properties
    }

    fn update(&mut self, _trial: &TrialState) -> Result<(), ElementError> {
        Err(ElementError::Invalid(format!(
            "this `{}` element was released on this rank (its rows belong to another rank) and cannot be evaluated here",
            self.kind
        )))
    }

    fn resisting_force(&self, _f: &mut [f64]) {
        self.evaluated("resisting force")
    }

    fn tangent_stiffness(&self, _k: &mut DMatrix<f64>) {
        self.evaluated("tangent stiffness")
    }

    fn mass(&self, _m: &mut DMatrix<f64>) {
        self.evaluated("mass")
    }

    fn damping(&self, _c: &mut DMatrix<f64>) {
        self.evaluated("damping")
    }

    fn as_any(&self) -> Option<&dyn std::any::Any> {
        Some(self)
    }
}

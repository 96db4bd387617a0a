//! Recorder specs: what a run is asked to write, one CSV file per `[[recorder]]`
//! ([`RecorderSpec`]), checked against the model before the run ([`RecorderSpec::validate`]).
//! Writing them during the run is [`crate::recording`]'s job.
//!
//! Every file has a header `time [s],<column>…` and one row per recorded step, SI units.
//! Node recorders write displacements, velocities or accelerations of chosen DOFs (in the
//! node's axes; for a carried node, the deviation from its reference motion), each column
//! with its unit (`2_uz [m]`, [`Quantity::unit`]); element recorders write the named outputs
//! an element reports ([`crate::Element::output_names`]), each with the unit the element
//! declares for it (`5_Q [N]`, [`crate::Element::output_units`]; `[?]` if it declares none).
//! Every other kind (a plugin's, or the railway ride-comfort recorder the elements crate
//! registers) is a registered kind ([`crate::recorder_kind`]), held here as its keys
//! ([`RecorderSpec::Registered`]).

use crate::dof::{Dof, DofSet};
use crate::error::FemError;
use crate::lookup::ModelLookup;
pub use crate::recorder_kind::Quantity;
use crate::recorder_kind::RecorderEntry;
use serde::{Deserialize, Serialize};

/// A `[[recorder]]` entry.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum RecorderSpec {
    /// DOFs of one or more nodes.
    Node {
        /// Node ids (`node = 3` or `nodes = [3, 4]`).
        #[serde(default)]
        node: Option<u64>,
        /// More node ids.
        #[serde(default)]
        nodes: Vec<u64>,
        /// The DOFs to write (`dofs = ["uz", "ry"]`, `"all"`, `"translations"`,
        /// `"rotations"`), in canonical order.
        dofs: DofSet,
        /// `"disp"`, `"vel"` or `"acc"`.
        #[serde(default)]
        quantity: Quantity,
        /// Output file name, relative to the output directory.
        file: String,
    },
    /// Named outputs of one or more elements.
    Element {
        /// Element ids (`element = 3` or `elements = [3, 4]`).
        #[serde(default)]
        element: Option<u64>,
        /// More element ids.
        #[serde(default)]
        elements: Vec<u64>,
        /// Every element of this registered type (e.g. `"moving_axle"`: all wheels of all
        /// vehicles), in model order, besides the ids above.
        #[serde(default)]
        kind: Option<String>,
        /// Output names to write (default: all the element reports).
        #[serde(default)]
        outputs: Vec<String>,
        /// Output file name, relative to the output directory.
        file: String,
    },
    /// A recorder of a registered kind (a plugin's, the ride-comfort recorder): its keys,
    /// built by the kind's factory
    /// ([`crate::recorder_kind`]). Model files reach it by the kind's `type`; it has no
    /// serde form of its own.
    #[serde(skip)]
    Registered(RecorderEntry),
}

impl RecorderSpec {
    /// A node recorder of `dofs` of the nodes with user ids `nodes`: their displacements,
    /// velocities or accelerations (`quantity`), written to `file`.
    pub fn node(nodes: &[u64], dofs: &[Dof], quantity: Quantity, file: impl Into<String>) -> Self {
        RecorderSpec::Node {
            node: None,
            nodes: nodes.to_vec(),
            dofs: DofSet::of(dofs),
            quantity,
            file: file.into(),
        }
    }

    /// An element recorder of every output of the elements with user ids `elements`.
    pub fn element(elements: &[u64], file: impl Into<String>) -> Self {
        RecorderSpec::Element {
            element: None,
            elements: elements.to_vec(),
            kind: None,
            outputs: Vec::new(),
            file: file.into(),
        }
    }

    /// An element recorder of every element of registered type `kind` (all wheels of all
    /// vehicles: `"moving_axle"`), restricted to `outputs` unless empty.
    pub fn elements_of_kind(kind: &str, outputs: &[&str], file: impl Into<String>) -> Self {
        RecorderSpec::Element {
            element: None,
            elements: Vec::new(),
            kind: Some(kind.to_string()),
            outputs: outputs.iter().map(|s| s.to_string()).collect(),
            file: file.into(),
        }
    }

    /// The node ids (node recorder) or element ids (element recorder) the recorder names.
    pub(crate) fn node_ids(&self, model: &dyn ModelLookup) -> Vec<u64> {
        match self {
            RecorderSpec::Node { node, nodes, .. } => node.iter().chain(nodes).copied().collect(),
            RecorderSpec::Element {
                element,
                elements,
                kind,
                ..
            } => {
                let mut ids: Vec<u64> = element.iter().chain(elements).copied().collect();
                if let Some(k) = kind {
                    ids.extend(model.element_ids_of_kind(k));
                }
                ids
            }
            RecorderSpec::Registered(_) => Vec::new(),
        }
    }

    /// The user ids of the elements the recorder reads: an element recorder's (by id and
    /// by type), none for the others.
    pub fn elements_read(&self, model: &dyn ModelLookup) -> Vec<u64> {
        match self {
            RecorderSpec::Element { .. } => self.node_ids(model),
            _ => Vec::new(),
        }
    }

    /// Output file name.
    pub fn file(&self) -> &str {
        match self {
            RecorderSpec::Node { file, .. } | RecorderSpec::Element { file, .. } => file,
            RecorderSpec::Registered(e) => &e.file,
        }
    }

    /// Checks ids and names against the model.
    pub fn validate(&self, model: &dyn ModelLookup) -> Result<(), FemError> {
        self.validate_at(model, None)
    }

    /// As [`RecorderSpec::validate`]; `index` (the position among the model's recorders,
    /// the `[[recorder]]` table number of a model file) is named in messages as
    /// `recorder[i]`.
    pub fn validate_at(
        &self,
        model: &dyn ModelLookup,
        index: Option<usize>,
    ) -> Result<(), FemError> {
        let o = match index {
            Some(i) => format!("{}: recorder[{i}] (`{}`)", model.origin(), self.file()),
            None => format!("{}: recorder `{}`", model.origin(), self.file()),
        };
        if let RecorderSpec::Registered(e) = self {
            return crate::recorder_kind::build(e, model, &o).map(|_| ());
        }
        let ids = self.node_ids(model);
        if ids.is_empty() {
            return Err(FemError::input(
                &o,
                "names no node or element; add `node = …`, `element = …` or `kind = …` (a type with elements in the model)",
            ));
        }
        // The file name is checked with every other output name ([`crate::outputs`]).
        match self {
            RecorderSpec::Registered(_) => {}
            RecorderSpec::Node { .. } => {
                for id in ids {
                    if model.node_index(id).is_none() {
                        return Err(FemError::input(
                            &o,
                            format!("node {id} does not exist; define it in a [[node]] table or fix the id"),
                        ));
                    }
                }
            }
            RecorderSpec::Element { outputs, .. } => {
                let found = model.element_indices(&ids);
                for (id, at) in ids.into_iter().zip(found) {
                    let Some(e) = at else {
                        return Err(FemError::input(
                            &o,
                            format!("element {id} does not exist; define it in an [[element]] table or fix the id"),
                        ));
                    };
                    let names = model.element_output_names(e);
                    for n in outputs {
                        if !names.contains(n) {
                            let cands: Vec<&str> = names.iter().map(|s| s.as_str()).collect();
                            return Err(FemError::input(
                                &o,
                                format!(
                                    "element {id} ({}) has no output `{n}`; it reports: {}",
                                    model.element_kind(e),
                                    cands.join(", ")
                                ),
                            ));
                        }
                    }
                }
            }
        }
        Ok(())
    }
}

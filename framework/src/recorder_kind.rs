//! The recorder registry: every recorder kind a model file can name in `[[recorder]]`,
//! built in or added by a plugin, with its documented keys ([`RecorderKind`]), and the trait
//! a plugin's recorder implements ([`RecordedColumns`]).
//!
//! The framework's own kinds (`node`, `element`) register their documentation here and
//! keep their typed spec ([`crate::recorder::RecorderSpec`]). Every other kind (a plugin's,
//! or the railway ride-comfort recorder of the elements crate) registers a factory: from its
//! keys (parsed into a [`Params`] struct) and the model's ids ([`ModelLookup`]) it builds a
//! [`RecordedColumns`], whose columns [`crate::recording::Recorders`] writes to the entry's
//! `file` like any other recorder's (same number format, same behaviour on a full disk, same
//! in-memory histories), or which keeps its rows and writes a summary of them when the run
//! finishes ([`RecordedColumns::writes_rows`], [`RecordedColumns::finish`]).
//! `railfem recorders` prints every registered kind.

use crate::dof::Dof;
use crate::error::FemError;
use crate::kind_list::KindList;
use crate::lookup::ModelLookup;
use crate::registry::{ParamDoc, Params};
use serde::{Deserialize, Serialize};
use std::path::Path;

/// Which kinematic quantity a recorder reads.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum Quantity {
    /// Displacement (m, rad).
    #[default]
    Disp,
    /// Velocity (m/s, rad/s).
    Vel,
    /// Acceleration (m/s², rad/s²).
    Acc,
}

impl Quantity {
    /// The unit of this quantity of a translation (`m`, `m/s`, `m/s²`) or of a rotation
    /// (`rad`, `rad/s`, `rad/s²`), as CSV headers write it (`2_uz [m]`).
    pub fn unit(self, rotation: bool) -> &'static str {
        match (self, rotation) {
            (Quantity::Disp, false) => "m",
            (Quantity::Vel, false) => "m/s",
            (Quantity::Acc, false) => "m/s²",
            (Quantity::Disp, true) => "rad",
            (Quantity::Vel, true) => "rad/s",
            (Quantity::Acc, true) => "rad/s²",
        }
    }
}

/// Reads a node's kinematics: `(node index, DOF, quantity) → value`.
pub type NodeReader<'a> = &'a dyn Fn(usize, Dof, Quantity) -> f64;

/// Fills an element's outputs at the recorded state: `(element index, out)`.
pub type OutputReader<'a> = &'a mut dyn FnMut(usize, &mut Vec<f64>) -> Result<(), FemError>;

/// The state a recorder reads at a recorded step.
pub struct RecordState<'a> {
    /// Time (s).
    pub t: f64,
    node_value: NodeReader<'a>,
    element_outputs: OutputReader<'a>,
}

impl<'a> RecordState<'a> {
    /// The state at time `t`: `node_value(node, dof, quantity)` reads a node's kinematics
    /// (node axes; a carried node's deviation from its reference motion) and
    /// `element_outputs(element, out)` fills an element's outputs at this state.
    pub fn new(
        t: f64,
        node_value: NodeReader<'a>,
        element_outputs: OutputReader<'a>,
    ) -> RecordState<'a> {
        RecordState {
            t,
            node_value,
            element_outputs,
        }
    }

    /// Displacement, velocity or acceleration of DOF `dof` of node index `node`.
    pub fn node(&self, node: usize, dof: Dof, quantity: Quantity) -> f64 {
        (self.node_value)(node, dof, quantity)
    }

    /// The outputs of element index `element` at this state
    /// ([`crate::Element::outputs`], in [`crate::Element::output_names`] order).
    pub fn element_outputs(&mut self, element: usize, out: &mut Vec<f64>) -> Result<(), FemError> {
        (self.element_outputs)(element, out)
    }
}

/// A recorder built by a registered factory: named columns, one row per recorded step.
pub trait RecordedColumns: Send {
    /// Column names, each with its unit (`"2_3_duz [m]"`), without the leading time.
    fn columns(&self) -> Vec<String>;
    /// Appends one value per column for the state `s` to `out`.
    fn row(&mut self, s: &mut RecordState, out: &mut Vec<f64>) -> Result<(), FemError>;
    /// Whether the file holds the rows, one per recorded step (the default). A recorder
    /// that returns `false` writes nothing per step: its rows are still kept in memory when
    /// asked ([`crate::recording::History`]), and its file is written by
    /// [`RecordedColumns::finish`] (a summary of the whole run, e.g. a ride-comfort index).
    fn writes_rows(&self) -> bool {
        true
    }
    /// Called once when the run finishes, with the recorder's file (`path` names it in
    /// messages), when the run writes files: after the rows for a recorder that
    /// [writes rows](RecordedColumns::writes_rows), the whole file for one that does not.
    /// Does nothing by default.
    fn finish(&mut self, out: &mut dyn std::io::Write, path: &Path) -> Result<(), FemError> {
        let _ = (out, path);
        Ok(())
    }
    /// Indices of the nodes the recorder reads (none by default): a node that is the slave
    /// of a geometry = "nonlinear" link is refused, as for a node recorder.
    fn nodes(&self) -> Vec<usize> {
        Vec::new()
    }
}

/// A `[[recorder]]` entry of a registered (plugin) kind, as the registry sees it.
#[derive(Debug, Clone, PartialEq)]
pub struct RecorderEntry {
    /// Registered type name.
    pub kind: String,
    /// Output file name, relative to the output directory.
    pub file: String,
    /// The recorder's own keys (everything but `type` and `file`).
    pub params: serde_json::Map<String, serde_json::Value>,
    /// The entry's key path in its model file (`"recorder[3]"`), which a refused key's
    /// message names (`recorder[3].method`); empty for an entry made in code.
    pub at: String,
}

impl RecorderEntry {
    /// Deserializes the keys into `P`, filling documented defaults first; errors name
    /// `origin`, the key and the kind ([`crate::registry::parse_params`]).
    pub fn parse<P: Params>(&self, origin: &str) -> Result<P, FemError> {
        crate::registry::parse_params_at(
            &self.params,
            origin,
            &format!("recorder type `{}`", self.kind),
            &self.at,
        )
    }
}

/// Builds a registered kind's recorder; `origin` names the entry in messages.
pub type RecorderFactory =
    fn(&RecorderEntry, &dyn ModelLookup, &str) -> Result<Box<dyn RecordedColumns>, FemError>;

/// How a kind's recorders are built.
#[derive(Clone, Copy)]
pub enum RecorderBuild {
    /// A built-in kind, read through its typed [`crate::recorder::RecorderSpec`] variant.
    BuiltIn,
    /// A registered factory (plugins).
    Factory(RecorderFactory),
}

/// One registered recorder kind.
#[derive(Clone, Copy)]
pub struct RecorderKind {
    /// Type name used in model files (`type = "…"`).
    pub name: &'static str,
    /// One-line description.
    pub description: &'static str,
    /// Documentation of the model-file keys (besides `type`; `file` is listed).
    pub params: fn() -> Vec<ParamDoc>,
    /// How its recorders are built.
    pub build: RecorderBuild,
}

inventory::collect!(RecorderKind);

impl crate::kind_list::Kind for RecorderKind {
    const WHAT: &'static str = "recorder";
    fn name(&self) -> &'static str {
        self.name
    }
}

static KINDS: KindList<RecorderKind> = KindList::new();

/// Registers a kind at run time (the path plugins take); a taken name is refused.
pub fn register(kind: RecorderKind) -> Result<(), FemError> {
    KINDS.register(kind)
}

/// Every registered kind: built-in ones first, sorted by name within each source.
pub fn kinds() -> Vec<RecorderKind> {
    KINDS.kinds()
}

/// The kind registered under `name`.
pub fn find(name: &str) -> Option<RecorderKind> {
    KINDS.find(name)
}

/// Builds `entry` through its kind's factory; an unknown or built-in kind is refused with
/// the registered names.
pub fn build(
    entry: &RecorderEntry,
    model: &dyn ModelLookup,
    origin: &str,
) -> Result<Box<dyn RecordedColumns>, FemError> {
    match find(&entry.kind).map(|k| k.build) {
        Some(RecorderBuild::Factory(f)) => f(entry, model, origin),
        _ => Err(unknown(&entry.kind, origin)),
    }
}

/// The message for a `type` no recorder kind is registered under.
pub fn unknown(kind: &str, origin: &str) -> FemError {
    crate::kind_list::unknown(&KINDS, kind, origin)
}

fn doc(
    key: &'static str,
    unit: &'static str,
    default: Option<serde_json::Value>,
    doc: &'static str,
) -> ParamDoc {
    ParamDoc {
        key,
        unit,
        default,
        doc,
    }
}

/// The documentation of every recorder's `file` key, for a kind that lists it with its own.
pub fn file_doc() -> ParamDoc {
    doc(
        "file",
        "",
        None,
        "Output file name, relative to the output directory.",
    )
}

fn ids_docs(one: &'static str, many: &'static str, what: &'static str) -> [ParamDoc; 2] {
    [
        doc(one, "", Some(serde_json::Value::Null), what),
        doc(
            many,
            "",
            Some(serde_json::json!([])),
            "More ids (give `node`/`element`, this list, or both).",
        ),
    ]
}

fn node_docs() -> Vec<ParamDoc> {
    let mut v = ids_docs("node", "nodes", "Node id.").to_vec();
    v.push(doc(
        "dofs",
        "",
        None,
        "DOF names (ux … rz) or [\"all\"], node axes.",
    ));
    v.push(doc(
        "quantity",
        "",
        Some(serde_json::json!("disp")),
        "disp, vel or acc.",
    ));
    v.push(file_doc());
    v
}

fn element_docs() -> Vec<ParamDoc> {
    let mut v = ids_docs("element", "elements", "Element id.").to_vec();
    v.push(doc(
        "kind",
        "",
        Some(serde_json::Value::Null),
        "Every element of this registered type, besides the ids.",
    ));
    v.push(doc(
        "outputs",
        "",
        Some(serde_json::json!([])),
        "Output names to write (empty: all the element reports).",
    ));
    v.push(file_doc());
    v
}

inventory::submit! {
    RecorderKind {
        name: "node",
        description: "displacements, velocities or accelerations of node DOFs",
        params: node_docs,
        build: RecorderBuild::BuiltIn,
    }
}

inventory::submit! {
    RecorderKind {
        name: "element",
        description: "named outputs of elements (by id or by type)",
        params: element_docs,
        build: RecorderBuild::BuiltIn,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::recorder::RecorderSpec;

    /// The documented keys of each built-in kind are exactly the keys its typed spec
    /// writes when every key is given.
    #[test]
    fn built_in_docs_match_the_typed_specs() {
        let specs = [
            RecorderSpec::Node {
                node: Some(1),
                nodes: vec![],
                dofs: crate::dof::DofSet::of(&[crate::dof::Dof::Uz]),
                quantity: Quantity::Disp,
                file: "a.csv".into(),
            },
            RecorderSpec::Element {
                element: Some(1),
                elements: vec![],
                kind: None,
                outputs: vec![],
                file: "b.csv".into(),
            },
        ];
        for s in specs {
            let v = serde_json::to_value(&s).unwrap();
            let m = v.as_object().unwrap();
            let kind = m["type"].as_str().unwrap();
            let k = find(kind).unwrap_or_else(|| panic!("{kind} not registered"));
            let mut keys: Vec<&str> = m
                .keys()
                .map(|s| s.as_str())
                .filter(|s| *s != "type")
                .collect();
            keys.sort_unstable();
            let mut docs: Vec<&str> = (k.params)().iter().map(|d| d.key).collect();
            docs.sort_unstable();
            assert_eq!(keys, docs, "{kind}");
        }
    }
}

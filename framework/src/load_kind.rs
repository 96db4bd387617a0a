//! The load registry: every load kind a model file can name in `[[load]]`, built in or
//! added by a plugin, with its documented keys ([`LoadKind`]), and the trait a plugin's
//! load implements ([`AppliedLoad`]).
//!
//! The built-in kinds (`nodal`, `ground_motion`, `moving_force`) register their
//! documentation here and keep their typed spec ([`crate::loads::LoadSpec`]) and their own
//! arithmetic in the assembler. A plugin kind registers a factory: from its keys (parsed
//! into a [`Params`] struct declared with [`element_params!`](crate::element_params)) and
//! the model's ids ([`ModelLookup`]) it builds an [`AppliedLoad`], which the assembler asks
//! for its nodal forces at each time. `railfem loads` prints every registered kind.
//!
//! Built-in kinds register with `inventory::submit!`; plugins hand theirs to the host
//! through [`export_plugin!`](crate::export_plugin), as for elements ([`crate::plugin`]).

use crate::dof::Dof;
use crate::error::FemError;
use crate::kind_list::KindList;
use crate::lookup::ModelLookup;
use crate::registry::{ParamDoc, Params};
use std::sync::Arc;

/// A load built by a registered factory: nodal forces and moments as functions of time.
pub trait AppliedLoad: Send + Sync + std::fmt::Debug {
    /// Calls `add(node, dof, value)` for every nodal force (N) or moment (N·m) the load
    /// applies at time `t` (s), in the node's axes; `node` is a node index. An error stops
    /// the run with its message.
    fn nodal_forces(&self, t: f64, add: &mut dyn FnMut(usize, Dof, f64)) -> Result<(), FemError>;
    /// The node indices the load acts on (checked against nonlinear-link slaves).
    fn nodes(&self) -> Vec<usize>;
}

/// A `[[load]]` entry of a registered (plugin) kind, as the registry sees it.
#[derive(Debug, Clone, PartialEq)]
pub struct LoadEntry {
    /// Registered type name.
    pub kind: String,
    /// The load's own keys (everything but `type`).
    pub params: serde_json::Map<String, serde_json::Value>,
}

impl LoadEntry {
    /// Deserializes the keys into `P`, filling documented defaults first; errors name
    /// `origin`, the key and the kind ([`crate::registry::parse_params`]).
    pub fn parse<P: Params>(&self, origin: &str) -> Result<P, FemError> {
        crate::registry::parse_params(&self.params, origin, &format!("load type `{}`", self.kind))
    }
}

/// Builds a registered kind's load from its keys; `origin` names the entry in messages.
pub type LoadFactory =
    fn(&LoadEntry, &dyn ModelLookup, &str) -> Result<Box<dyn AppliedLoad>, FemError>;

/// How a kind's loads are built.
#[derive(Clone, Copy)]
pub enum LoadBuild {
    /// A built-in kind: its typed [`crate::loads::LoadSpec`] variant and the assembler's own
    /// arithmetic.
    BuiltIn,
    /// A registered factory (plugins).
    Factory(LoadFactory),
}

/// One registered load kind.
#[derive(Clone, Copy)]
pub struct LoadKind {
    /// Type name used in model files (`type = "…"`).
    pub name: &'static str,
    /// One-line description.
    pub description: &'static str,
    /// Documentation of the model-file keys (besides `type`).
    pub params: fn() -> Vec<ParamDoc>,
    /// How its loads are built.
    pub build: LoadBuild,
}

inventory::collect!(LoadKind);

impl crate::kind_list::Kind for LoadKind {
    const WHAT: &'static str = "load";
    fn name(&self) -> &'static str {
        self.name
    }
}

static KINDS: KindList<LoadKind> = KindList::new();

/// Registers a kind at run time (the path plugins take); a taken name is refused.
pub fn register(kind: LoadKind) -> Result<(), FemError> {
    KINDS.register(kind)
}

/// Every registered kind: built-in ones first, sorted by name within each source.
pub fn kinds() -> Vec<LoadKind> {
    KINDS.kinds()
}

/// The kind registered under `name`.
pub fn find(name: &str) -> Option<LoadKind> {
    KINDS.find(name)
}

/// A load of a registered kind, resolved against the model.
#[derive(Debug, Clone)]
pub struct RegisteredLoad {
    /// The entry it was built from (compared by [`PartialEq`]).
    pub entry: LoadEntry,
    /// The built load.
    pub load: Arc<dyn AppliedLoad>,
}

impl PartialEq for RegisteredLoad {
    fn eq(&self, other: &Self) -> bool {
        self.entry == other.entry
    }
}

/// Builds `entry` through its kind's factory; an unknown or built-in kind is refused with
/// the registered names (the built-in kinds are read by their typed spec instead).
pub fn build(
    entry: &LoadEntry,
    model: &dyn ModelLookup,
    origin: &str,
) -> Result<RegisteredLoad, FemError> {
    match find(&entry.kind).map(|k| k.build) {
        Some(LoadBuild::Factory(f)) => Ok(RegisteredLoad {
            entry: entry.clone(),
            load: Arc::from(f(entry, model, origin)?),
        }),
        _ => Err(unknown(&entry.kind, origin)),
    }
}

/// The message for a `type` no load kind is registered under.
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

fn nodal_docs() -> Vec<ParamDoc> {
    vec![
        doc("node", "", None, "Node id."),
        doc(
            "dof",
            "",
            None,
            "DOF name: ux, uy, uz, rx, ry or rz (node axes).",
        ),
        doc(
            "value",
            "N or N*m",
            None,
            "Magnitude: force (N) or moment (N·m).",
        ),
        doc(
            "series",
            "",
            Some(serde_json::json!({"type": "constant"})),
            "Time series multiplying the value (constant, ramp, sine or table).",
        ),
    ]
}

fn ground_motion_docs() -> Vec<ParamDoc> {
    vec![
        doc(
            "direction",
            "-",
            None,
            "Direction of the ground acceleration, global (normalised).",
        ),
        doc(
            "series",
            "m/s^2",
            None,
            "Ground acceleration history before scaling (ramp, sine or table).",
        ),
        doc(
            "scale",
            "-",
            Some(serde_json::json!(1.0)),
            "Multiplier of the series (9.81 for a record in g).",
        ),
    ]
}

fn moving_force_docs() -> Vec<ParamDoc> {
    vec![
        doc(
            "elements",
            "",
            None,
            "Beam element ids of the path, in order of travel.",
        ),
        doc("force", "N", None, "Force vector, global axes."),
        doc("speed", "m/s", None, "Speed along the path."),
        doc(
            "start",
            "m",
            Some(serde_json::json!(0.0)),
            "Distance along the path at t = 0 (negative: enters later).",
        ),
    ]
}

inventory::submit! {
    LoadKind {
        name: "nodal",
        description: "a force or moment on one DOF of one node, value · series(t)",
        params: nodal_docs,
        build: LoadBuild::BuiltIn,
    }
}

inventory::submit! {
    LoadKind {
        name: "ground_motion",
        description: "uniform support excitation: every mass feels −M·r·a_g(t)",
        params: ground_motion_docs,
        build: LoadBuild::BuiltIn,
    }
}

inventory::submit! {
    LoadKind {
        name: "moving_force",
        description: "a constant force travelling along a chain of beams at constant speed",
        params: moving_force_docs,
        build: LoadBuild::BuiltIn,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::loads::{LoadSpec, TimeSeries};

    /// The documented keys of each built-in kind are exactly the keys its typed spec
    /// reads and writes: a serialised spec with every key given names the same set.
    #[test]
    fn built_in_docs_match_the_typed_specs() {
        let specs = [
            LoadSpec::Nodal {
                node: 1,
                dof: Dof::Uz,
                value: 1.0,
                series: TimeSeries::default(),
            },
            LoadSpec::GroundMotion {
                direction: [1.0, 0.0, 0.0],
                series: TimeSeries::default(),
                scale: 1.0,
            },
            LoadSpec::MovingForce {
                elements: vec![1],
                force: [0.0, 0.0, -1.0],
                speed: 1.0,
                start: 0.0,
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
            assert!(matches!(k.build, LoadBuild::BuiltIn));
        }
    }

    #[test]
    fn unknown_kind_lists_the_registered_ones() {
        let e = unknown("nodel", "m.toml: load[0]").to_string();
        assert!(e.contains("m.toml: load[0]"), "{e}");
        assert!(
            e.contains("nodal, ground_motion") || e.contains("ground_motion"),
            "{e}"
        );
        assert!(e.contains("railfem loads"), "{e}");
    }
}

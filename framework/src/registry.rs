//! The element registry: every element kind registers itself at startup, and model files
//! name elements by type.
//!
//! Built-in kinds register with one `inventory::submit!` of an [`ElementKind`]; dynamic
//! plugins hand the same [`ElementKind`] values to [`register`] from their entry point
//! (see [`crate::plugin`]), because `inventory` inside a `cdylib` collects into the plugin's
//! own copy of the framework, never into the host's. No framework code lists element kinds
//! by hand: [`kinds`] is the union of both sources.
//!
//! Parameters are declared with [`crate::element_params!`], which generates a serde struct whose
//! doc comments, units and defaults also become the model-file documentation
//! ([`ParamDoc`]) printed by `railfem elements`.

use crate::element::Element;
use crate::error::FemError;
use nalgebra::Vector3;
use serde::de::DeserializeOwned;

/// Documentation of one model-file key of an element kind.
#[derive(Debug, Clone, PartialEq)]
pub struct ParamDoc {
    /// The key as written in the model file.
    pub key: &'static str,
    /// SI unit (`"Pa"`, `"m^4"`, `"-"` for dimensionless, `""` for non-numeric).
    pub unit: &'static str,
    /// Default value as JSON, or `None` when the key is required.
    pub default: Option<serde_json::Value>,
    /// One-line description (the field's doc comment).
    pub doc: &'static str,
}

/// A parameter struct declared with [`crate::element_params!`].
pub trait Params: DeserializeOwned + serde::Serialize {
    /// Documentation of every key.
    fn docs() -> Vec<ParamDoc>;
}

/// A parameter struct tied to the element kind it builds, so that
/// [`crate::builder::ModelBuilder::add`] takes it without a type name:
/// `b.add(7, &[1, 2], &beam)` with `beam: Beam3dParams`.
pub trait ElementParams: Params {
    /// The registered type name these parameters build.
    const KIND: &'static str;
}

/// Declares an element's parameter struct: serde (unknown keys refused), documented keys,
/// units and defaults in one place.
///
/// ```
/// railfem_framework::element_params! {
///     /// Parameters of a linear spring.
///     pub struct SpringParams {
///         /// Axial stiffness.
///         k: f64 ["N/m"],
///         /// Viscous damping coefficient.
///         c: f64 ["N*s/m"] = 0.0,
///     }
/// }
/// use railfem_framework::registry::Params;
/// let docs = SpringParams::docs();
/// assert_eq!(docs[0].key, "k");
/// assert!(docs[0].default.is_none() && docs[1].default.is_some());
/// ```
#[macro_export]
macro_rules! element_params {
    (
        $(#[doc = $sdoc:literal])*
        $vis:vis struct $name:ident {
            $(
                $(#[doc = $fdoc:literal])*
                $field:ident $(as $key:literal)? : $ty:ty [$unit:literal] $(= $default:expr)?
            ),* $(,)?
        }
    ) => {
        $(#[doc = $sdoc])*
        #[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
        #[serde(deny_unknown_fields)]
        #[allow(non_snake_case)]
        $vis struct $name {
            $(
                $(#[doc = $fdoc])*
                $(#[serde(rename = $key)])?
                pub $field: $ty,
            )*
        }
        impl $crate::registry::Params for $name {
            fn docs() -> Vec<$crate::registry::ParamDoc> {
                vec![$(
                    $crate::registry::ParamDoc {
                        key: $crate::element_params!(@key $field $($key)?),
                        unit: $unit,
                        default: $crate::element_params!(@default $($default)?),
                        doc: $crate::element_params!(@doc $($fdoc)*),
                    }
                ),*]
            }
        }
    };
    (@key $field:ident) => { stringify!($field) };
    (@key $field:ident $key:literal) => { $key };
    (@default) => { None };
    (@default $d:expr) => { Some($crate::serde_json::json!($d)) };
    (@doc) => { "" };
    (@doc $first:literal $($rest:literal)*) => { $first.trim() };
}

/// An `[[element]]` entry of a model file, as the registry sees it.
#[derive(Debug, Clone)]
pub struct ElementSpec {
    /// User id of the element.
    pub id: u64,
    /// Registered type name.
    pub kind: String,
    /// User ids of the nodes, in order.
    pub nodes: Vec<u64>,
    /// The element's own keys (everything but `type`, `id`, `nodes`).
    pub params: serde_json::Map<String, serde_json::Value>,
    /// Where the entry came from, for messages (`"model.toml: element[3] (id 7)"`).
    pub origin: String,
}

impl ElementSpec {
    /// Deserializes the element's keys into `P`, filling documented defaults first.
    /// Errors name the origin, the offending key and the valid keys.
    pub fn parse<P: Params>(&self) -> Result<P, FemError> {
        parse_params(
            &self.params,
            &self.origin,
            &format!("element type `{}`", self.kind),
        )
    }
}

/// Deserializes a registered kind's keys `params` into `P`, filling documented defaults
/// first: what element, load and recorder kinds share. Unknown keys (with the nearest
/// valid one), missing required keys and non-finite numbers are refused with one line
/// naming `origin`, the key and `what` (`"element type `beam3d`"`, `"load type `x`"`).
pub fn parse_params<P: Params>(
    params: &serde_json::Map<String, serde_json::Value>,
    origin: &str,
    what: &str,
) -> Result<P, FemError> {
    parse_params_at(params, origin, what, "")
}

/// As [`parse_params`], for keys at key path `at` of their file (`"recorder[3]"`): a value
/// serde refuses is named by its full path (`recorder[3].method`).
pub fn parse_params_at<P: Params>(
    params: &serde_json::Map<String, serde_json::Value>,
    origin: &str,
    what: &str,
    at: &str,
) -> Result<P, FemError> {
    let docs = P::docs();
    let mut map = params.clone();
    // Unknown keys first: a misspelt key (`Iyy`) also leaves its correct key missing,
    // and "did you mean `Iy`?" is the useful message then.
    for k in map.keys() {
        if !docs.iter().any(|d| d.key == k) {
            let names: Vec<&str> = docs.iter().map(|d| d.key).collect();
            let near = crate::error::nearest(k, &names);
            return Err(FemError::input(
                origin,
                format!(
                    "unknown key `{k}` for {what}{}; valid keys: {}",
                    near.map(|n| format!(" (did you mean `{n}`?)"))
                        .unwrap_or_default(),
                    names.join(", ")
                ),
            ));
        }
    }
    for d in &docs {
        if !map.contains_key(d.key) {
            match &d.default {
                Some(v) => {
                    map.insert(d.key.to_string(), v.clone());
                }
                None => {
                    return Err(FemError::input(
                        origin,
                        format!(
                            "missing key `{}` ({}) for {what}; add it, e.g. `{} = …` [{}]",
                            d.key, d.doc, d.key, d.unit
                        ),
                    ))
                }
            }
        }
    }
    let p: P = crate::keypath::from_value(&serde_json::Value::Object(map), origin, at).map_err(
        |e| match e {
            FemError::Input { origin, message } => {
                FemError::input(origin, format!("{what}: {message}"))
            }
            e => e,
        },
    )?;
    // Refuse NaN / infinity in any numeric key. A key documented with a null default (an
    // optional id left out) may stay null.
    let mut v = serde_json::to_value(&p).unwrap_or(serde_json::Value::Null);
    if let serde_json::Value::Object(m) = &mut v {
        for d in docs
            .iter()
            .filter(|d| d.default == Some(serde_json::Value::Null))
        {
            if m.get(d.key).is_some_and(serde_json::Value::is_null) {
                m.remove(d.key);
            }
        }
    }
    if let Some(bad) = first_non_finite(&v, "") {
        return Err(FemError::input(
            origin,
            format!("key `{bad}` is not a finite number; give a finite value in SI units"),
        ));
    }
    Ok(p)
}

fn first_non_finite(v: &serde_json::Value, path: &str) -> Option<String> {
    match v {
        // serde_json serialises non-finite floats as null; a null where a number was
        // deserialised means the number was not finite.
        serde_json::Value::Null if !path.is_empty() => Some(path.to_string()),
        serde_json::Value::Object(m) => m.iter().find_map(|(k, x)| {
            let p = if path.is_empty() {
                k.clone()
            } else {
                format!("{path}.{k}")
            };
            first_non_finite(x, &p)
        }),
        serde_json::Value::Array(a) => a
            .iter()
            .enumerate()
            .find_map(|(i, x)| first_non_finite(x, &format!("{path}[{i}]"))),
        _ => None,
    }
}

/// What a factory may ask of the model while building an element.
pub trait BuildContext {
    /// Index of the node with user id `id`.
    fn node_index(&self, id: u64) -> Option<usize>;
    /// Reference position of the node with index `index` (m).
    fn node_position(&self, index: usize) -> Vector3<f64>;
    /// Adds an internal node owned by the element at `position`; returns its index.
    /// An internal node is carried by the same carrier as `like` (if any).
    fn add_internal_node(&mut self, position: Vector3<f64>, like: Option<usize>) -> usize;
    /// A shared resource the model defines (the track, profiles), by name.
    fn resource(&self, name: &str) -> Option<std::sync::Arc<dyn std::any::Any + Send + Sync>>;
    /// The type and node indices of the model's element with user id `id` (built yet or
    /// not), for elements that ride along other elements (a path of beams); `None` if there
    /// is no such element or the context does not know.
    fn element_nodes(&self, id: u64) -> Option<(String, Vec<usize>)> {
        let _ = id;
        None
    }
    /// Whether the node with index `index` rides on a carrier (a vehicle's moving frame);
    /// `None` where the context does not know (a test or conformance context).
    fn node_carried(&self, index: usize) -> Option<bool> {
        let _ = index;
        None
    }
}

/// Builds an element from its model-file entry.
pub type Factory = fn(&ElementSpec, &mut dyn BuildContext) -> Result<Box<dyn Element>, FemError>;

/// A sample admissible state of an element for the conformance kit. Start from
/// [`Sample::new`] and add what the state needs ([`Sample::with_fd_step`],
/// [`Sample::committed_at`], [`Sample::rebuilt_by`]).
///
/// The element's connectivity indexes `nodes`: node index `i` of the element is
/// `nodes[i]`. Where the kit rebuilds the element from its `parameters()` (the serde
/// check), it hands the kind's factory a model context in which node index `i` has user id
/// `i + 1`.
pub struct Sample {
    /// Short name of the state (`"stick"`, `"two-point contact"`).
    pub name: String,
    /// The element, built and advanced to the state's time.
    pub element: Box<dyn Element>,
    /// Node kinematics the element was built against.
    pub nodes: Vec<crate::element::NodeKinematics>,
    /// Displacements (element order) of the sample state.
    pub disp: Vec<f64>,
    /// Velocities (element order) of the sample state.
    pub vel: Vec<f64>,
    /// Relative finite-difference step to use for this state (scaled by the DOF size).
    pub fd_step: f64,
    /// Actions to take before the check: commit the state at `disp` first, so that the
    /// sample sits on a committed history (a stick anchor, a plastic strain).
    pub committed_disp: Option<Vec<f64>>,
    /// Rebuilds the sample's element from parameters (the serde check), for kinds whose
    /// factory needs model context the kit cannot supply (internal nodes, a track). `None`:
    /// the kit calls the kind's factory.
    pub rebuild: Option<Rebuild>,
}

impl Sample {
    /// The finite-difference step [`Sample::new`] uses, relative to the DOF's size.
    pub const DEFAULT_FD_STEP: f64 = 1e-6;

    /// A sample state: `element` built against `nodes` (node index `i` is `nodes[i]`), at
    /// displacements `disp` and velocities `vel` (element DOF order), with no committed
    /// history, the default finite-difference step and the kind's own factory for the
    /// serde check.
    pub fn new(
        name: impl Into<String>,
        element: Box<dyn Element>,
        nodes: Vec<crate::element::NodeKinematics>,
        disp: Vec<f64>,
        vel: Vec<f64>,
    ) -> Sample {
        Sample {
            name: name.into(),
            element,
            nodes,
            disp,
            vel,
            fd_step: Self::DEFAULT_FD_STEP,
            committed_disp: None,
            rebuild: None,
        }
    }

    /// The relative finite-difference step of the tangent check (for a law with a kink
    /// near the state, a smaller one; for a stiff one with round-off, a larger one).
    pub fn with_fd_step(mut self, fd_step: f64) -> Sample {
        self.fd_step = fd_step;
        self
    }

    /// Commits the state at `disp` before the checks, so that the sample sits on a
    /// committed history (a stick anchor, a plastic strain).
    pub fn committed_at(mut self, disp: Vec<f64>) -> Sample {
        self.committed_disp = Some(disp);
        self
    }

    /// Rebuilds the element from its parameters with `rebuild` in the serde check, for a
    /// kind whose factory needs model context the kit cannot supply.
    pub fn rebuilt_by(mut self, rebuild: Rebuild) -> Sample {
        self.rebuild = Some(rebuild);
        self
    }
}

/// Rebuilds a sample element from its `parameters()`.
pub type Rebuild = fn(&serde_json::Value) -> Result<Box<dyn Element>, FemError>;

/// Generates the conformance samples of a kind.
pub type SampleGenerator = fn() -> Vec<Sample>;

/// One registered element kind.
#[derive(Clone, Copy)]
pub struct ElementKind {
    /// Type name used in model files.
    pub name: &'static str,
    /// One-line description.
    pub description: &'static str,
    /// Documentation of the model-file keys.
    pub params: fn() -> Vec<ParamDoc>,
    /// The factory.
    pub build: Factory,
    /// Sample states for the conformance kit.
    pub samples: SampleGenerator,
}

inventory::collect!(ElementKind);

impl crate::kind_list::Kind for ElementKind {
    const WHAT: &'static str = "element";
    fn name(&self) -> &'static str {
        self.name
    }
}

static KINDS: crate::kind_list::KindList<ElementKind> = crate::kind_list::KindList::new();

/// Registers a kind at run time (the path dynamic plugins take).
/// A name that is already registered is refused.
pub fn register(kind: ElementKind) -> Result<(), FemError> {
    KINDS.register(kind)
}

/// Every registered kind, static ones first, sorted by name within each source.
pub fn kinds() -> Vec<ElementKind> {
    KINDS.kinds()
}

/// The kind registered under `name`.
pub fn find(name: &str) -> Option<ElementKind> {
    KINDS.find(name)
}

/// Builds an element from its spec through the registry; an unknown type lists the
/// nearest registered names.
pub fn build(spec: &ElementSpec, ctx: &mut dyn BuildContext) -> Result<Box<dyn Element>, FemError> {
    match find(&spec.kind) {
        Some(k) => (k.build)(spec, ctx),
        None => {
            let all = kinds();
            let names: Vec<&str> = all.iter().map(|k| k.name).collect();
            let near = crate::error::nearest_n(&spec.kind, &names, 3);
            Err(FemError::input(
                &spec.origin,
                format!(
                    "unknown element type `{}`; nearest registered: {} (run `railfem elements` for all; a plugin's type needs --plugin PATH)",
                    spec.kind,
                    if near.is_empty() { "none".to_string() } else { near.join(", ") }
                ),
            ))
        }
    }
}

//! The typed builder of a [`Model`]: nodes, rigid links, elements (through the registry),
//! loads, carriers, recorders and analysis settings, added step by step in Rust code or by
//! a model file ([`crate::modelfile`]), then resolved and validated at once by
//! [`ModelBuilder::build`].
//!
//! Both ways go through the same path (element entries are JSON maps handed to the
//! registry), so the same model built either way gives identical results. Elements may add
//! internal nodes while being built (the wheel node B of the moving axle). Validation that
//! needs the whole model (missing nodes, duplicate ids, non-finite coordinates) happens here
//! and names the place.

use crate::analysis::{AnalysisSpec, Geometry};
use crate::dof::DofSet;
use crate::error::FemError;
use crate::model::{ElementEntry, Model, Node, RigidLink};
use crate::moving::{CarriedNode, Carrier};
use crate::recorder::RecorderSpec;
use crate::registry::{self, BuildContext, ElementSpec};
use nalgebra::Vector3;
use serde::Serialize;
use std::any::Any;
use std::collections::HashMap;
use std::sync::Arc;

/// Shared resources elements may ask for while being built (a track, profiles).
pub type Resources = HashMap<String, Arc<dyn Any + Send + Sync>>;

/// Builds a [`Model`] step by step, in Rust code or from a model file.
///
/// # Example
///
/// A node on a grounded spring of stiffness `k`, free along `z` only, under a force `F`:
/// the static displacement is `u = F/k` (Hooke's law).
///
/// ```
/// use railfem_framework::builder::ModelBuilder;
/// use railfem_framework::loads::{LoadSpec, TimeSeries};
/// use railfem_framework::model::{AnalysisKind, AnalysisSpec};
/// use railfem_framework::{Dof, DofSet};
/// use railfem_elements::spring_damper::SpringDamperParams;
///
/// let (k, force) = (2.0e6, -1.0e4); // N/m, N
/// let mut b = ModelBuilder::new("spring");
/// b.node_fixed(1, [0.0, 0.0, 0.0], DofSet::of(&[Dof::Ux, Dof::Uy, Dof::Rx, Dof::Ry, Dof::Rz]));
/// // A spring on one node acts between the node and the ground; its parameters name
/// // their kind (`spring_damper`), every key but `k` at its documented default.
/// b.add(1, &[1], &SpringDamperParams::new([0.0, 0.0, k, 0.0, 0.0, 0.0]));
/// b.load(LoadSpec::Nodal { node: 1, dof: Dof::Uz, value: force, series: TimeSeries::Constant });
/// b.analysis(AnalysisSpec { kind: AnalysisKind::Static, steps: 1, ..Default::default() });
/// let model = b.build()?;
///
/// let mut driver = railfem_solvers::Driver::new(model)?;
/// driver.run(None, &mut |_| {})?;
/// let u = driver.displacement(1, Dof::Uz).expect("node 1 moves along z");
/// assert!((u - force / k).abs() <= 1e-12 * (force / k).abs(), "u = {u} m");
/// # Ok::<(), railfem_framework::FemError>(())
/// ```
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

    /// Adds an element whose typed parameters name their kind
    /// ([`crate::registry::ElementParams`]): `b.add(7, &[1, 2], &beam)`.
    ///
    /// A struct cannot leave a key out, so a field at its documented default reads as not
    /// given, as in a model file that omits the key: the element is the one the same keys
    /// build from a file, and a kind that refuses a key nothing would read (a `rail`
    /// beside a `path`) is not given it.
    pub fn add<P: crate::registry::ElementParams>(
        &mut self,
        id: u64,
        nodes: &[u64],
        params: &P,
    ) -> &mut Self {
        let Ok(serde_json::Value::Object(mut keys)) = serde_json::to_value(params) else {
            // Not a table: `element` reports it.
            return self.element(P::KIND, id, nodes, params);
        };
        for d in P::docs() {
            if d.default.is_some() && keys.get(d.key) == d.default.as_ref() {
                keys.remove(d.key);
            }
        }
        self.element(P::KIND, id, nodes, &keys)
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
                Ok(crate::loads::Load::Registered(r))
                    if r.load
                        .nodes()
                        .iter()
                        .any(|n| nonlinear_links.iter().any(|l| l.1 == *n)) =>
                {
                    errors.push(FemError::input(
                        format!("{}: load[{i}]", model.origin),
                        format!("a `{}` load acts on the slave of a geometry = \"nonlinear\" link; it must act on its master instead", r.entry.kind),
                    ));
                }
                Ok(load) => model.loads.push(load),
                Err(e) => errors.push(e),
            }
        }
        for (i, r) in recorders.iter().enumerate() {
            if let Err(e) = r.validate_at(&model, Some(i)) {
                errors.push(e);
            } else if let Some(e) = registered_reads_slave(&model, r, i, &nonlinear_links) {
                errors.push(e);
            }
        }
        FemError::from_list(errors)?;
        model.recorders = recorders;
        Ok(model)
    }
}

/// A registered recorder (`recorder[i]`) reading a node that is the slave of a
/// geometry = "nonlinear" link, refused as a node recorder on one is
/// ([`crate::finite_link`]): the slave's DOFs are its master's rigid-body motion.
fn registered_reads_slave(
    model: &Model,
    r: &crate::recorder::RecorderSpec,
    i: usize,
    nonlinear_links: &[(usize, usize, String)],
) -> Option<FemError> {
    let crate::recorder::RecorderSpec::Registered(e) = r else {
        return None;
    };
    if nonlinear_links.is_empty() {
        return None;
    }
    let origin = format!("{}: recorder[{i}]", model.origin);
    let built = crate::recorder_kind::build(e, model, &origin).ok()?;
    let slave = built
        .nodes()
        .into_iter()
        .find(|n| nonlinear_links.iter().any(|l| l.1 == *n))?;
    Some(FemError::input(
        origin,
        format!(
            "node {} is the slave of a geometry = \"nonlinear\" link; a `{}` recorder must read its master instead",
            model.nodes[slave].id, e.kind
        ),
    ))
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

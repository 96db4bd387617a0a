//! Recorders: what a run writes, one CSV file per recorder.
//!
//! Every file has a header `time,<column>…` and one row per recorded step, SI units. Node
//! recorders write displacements, velocities or accelerations of chosen DOFs (in the node's
//! axes; for a carried node, the deviation from its reference motion); element recorders
//! write the named outputs an element reports ([`crate::Element::output_names`]).

use crate::assembly::Assembler;
use crate::dof::{Dof, DofSet};
use crate::error::FemError;
use crate::model::Model;
use serde::{Deserialize, Serialize};
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

/// Which kinematic quantity a node recorder writes.
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
        /// DOF names, or `["all"]`.
        dofs: Vec<String>,
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
}

impl RecorderSpec {
    /// The node ids (node recorder) or element ids (element recorder) the recorder names.
    fn node_ids(&self, model: &Model) -> Vec<u64> {
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
                    ids.extend(
                        model
                            .elements
                            .iter()
                            .filter(|e| e.element.kind() == k)
                            .map(|e| e.id),
                    );
                }
                ids
            }
        }
    }

    /// Output file name.
    pub fn file(&self) -> &str {
        match self {
            RecorderSpec::Node { file, .. } | RecorderSpec::Element { file, .. } => file,
        }
    }

    /// Checks ids and names against the model.
    pub fn validate(&self, model: &Model) -> Result<(), FemError> {
        self.validate_at(model, None)
    }

    /// As [`RecorderSpec::validate`]; `index` (the position among the model's recorders,
    /// the `[[recorder]]` table number of a model file) is named in messages as
    /// `recorder[i]`.
    pub fn validate_at(&self, model: &Model, index: Option<usize>) -> Result<(), FemError> {
        let o = match index {
            Some(i) => format!("{}: recorder[{i}] (`{}`)", model.origin, self.file()),
            None => format!("{}: recorder `{}`", model.origin, self.file()),
        };
        let ids = self.node_ids(model);
        if ids.is_empty() {
            return Err(FemError::input(
                &o,
                "names no node or element; add `node = …`, `element = …` or `kind = …` (a type with elements in the model)",
            ));
        }
        // The file name is checked with every other output name ([`crate::outputs`]).
        match self {
            RecorderSpec::Node { dofs, .. } => {
                for id in ids {
                    if model.node(id).is_none() {
                        return Err(FemError::input(
                            &o,
                            format!("node {id} does not exist; define it in a [[node]] table or fix the id"),
                        ));
                    }
                }
                DofSet::parse_names(dofs).map_err(|bad| {
                    FemError::input(
                        &o,
                        format!("`{bad}` is not a DOF; use ux, uy, uz, rx, ry, rz or all"),
                    )
                })?;
            }
            RecorderSpec::Element { outputs, .. } => {
                for id in ids {
                    let Some(e) = model.elements.iter().find(|e| e.id == id) else {
                        return Err(FemError::input(
                            &o,
                            format!("element {id} does not exist; define it in an [[element]] table or fix the id"),
                        ));
                    };
                    let names = e.element.output_names();
                    for n in outputs {
                        if !names.contains(n) {
                            let cands: Vec<&str> = names.iter().map(|s| s.as_str()).collect();
                            return Err(FemError::input(
                                &o,
                                format!(
                                    "element {id} ({}) has no output `{n}`; it reports: {}",
                                    e.element.kind(),
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

enum Column {
    Node { node: usize, dof: usize },
    Element { elem: usize, output: usize },
}

struct Open {
    quantity: Quantity,
    columns: Vec<Column>,
    out: BufWriter<File>,
    path: PathBuf,
}

/// The open recorders of a run.
pub struct Recorders {
    open: Vec<Open>,
    buf: Vec<f64>,
}

impl Recorders {
    /// Opens every recorder of `model` in `dir` (created if needed) and writes headers.
    pub fn open(model: &Model, dir: &Path) -> Result<Recorders, FemError> {
        std::fs::create_dir_all(dir).map_err(|e| FemError::output(dir, e))?;
        let mut open = Vec::new();
        for spec in &model.recorders {
            let path = dir.join(spec.file());
            // A file in a subdirectory of the output directory (`wheels/left.csv`).
            if let Some(parent) = path.parent() {
                std::fs::create_dir_all(parent).map_err(|e| FemError::output(parent, e))?;
            }
            let f = File::create(&path).map_err(|e| FemError::output(&path, e))?;
            let mut out = BufWriter::new(f);
            let mut header = vec!["time".to_string()];
            let mut columns = Vec::new();
            let quantity = match spec {
                RecorderSpec::Node { dofs, quantity, .. } => {
                    let set = DofSet::parse_names(dofs).unwrap_or(DofSet::NONE);
                    for id in spec.node_ids(model) {
                        let n = model.node(id).expect("validated");
                        for d in set.iter() {
                            header.push(format!("{id}_{}", d.name()));
                            columns.push(Column::Node {
                                node: n,
                                dof: d.index(),
                            });
                        }
                    }
                    *quantity
                }
                RecorderSpec::Element { outputs, .. } => {
                    for id in spec.node_ids(model) {
                        let ei = model
                            .elements
                            .iter()
                            .position(|e| e.id == id)
                            .expect("validated");
                        let names = model.elements[ei].element.output_names();
                        for (k, n) in names.iter().enumerate() {
                            if outputs.is_empty() || outputs.contains(n) {
                                header.push(format!("{id}_{n}"));
                                columns.push(Column::Element {
                                    elem: ei,
                                    output: k,
                                });
                            }
                        }
                    }
                    Quantity::Disp
                }
            };
            writeln!(out, "{}", header.join(",")).map_err(|e| FemError::output(&path, e))?;
            open.push(Open {
                quantity,
                columns,
                out,
                path,
            });
        }
        Ok(Recorders {
            open,
            buf: Vec::new(),
        })
    }

    /// Writes one row per recorder for the state `(q, v, a)` at time `t`. Recorded
    /// constant elements are first brought to that state (see
    /// [`Assembler::refresh_constant`]), hence `&mut Model`.
    pub fn record(
        &mut self,
        model: &mut Model,
        asm: &Assembler,
        t: f64,
        q: &[f64],
        v: &[f64],
        a: &[f64],
    ) -> Result<(), FemError> {
        for o in &mut self.open {
            let src = match o.quantity {
                Quantity::Disp => q,
                Quantity::Vel => v,
                Quantity::Acc => a,
            };
            let mut line = format!("{t:.9e}");
            let mut cached: Option<usize> = None;
            for c in &o.columns {
                let val = match c {
                    Column::Node { node, dof } => asm.dofmap.value(src, *node, *dof),
                    Column::Element { elem, output } => {
                        if cached != Some(*elem) {
                            asm.refresh_constant(model, *elem, t, q, v, a)?;
                            self.buf.clear();
                            model.elements[*elem].element.outputs(&mut self.buf);
                            cached = Some(*elem);
                        }
                        self.buf.get(*output).copied().unwrap_or(f64::NAN)
                    }
                };
                line.push(',');
                line.push_str(&format!("{val:.12e}"));
            }
            writeln!(o.out, "{line}").map_err(|e| FemError::output(&o.path, e))?;
        }
        Ok(())
    }

    /// Flushes every file.
    pub fn finish(&mut self) -> Result<(), FemError> {
        for o in &mut self.open {
            o.out.flush().map_err(|e| FemError::output(&o.path, e))?;
        }
        Ok(())
    }
}

/// Parses a DOF name list for recorders and loads (re-exported helper).
pub fn parse_dof(name: &str) -> Option<Dof> {
    Dof::parse(name)
}

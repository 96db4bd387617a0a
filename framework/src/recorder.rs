//! Recorders: what a run writes, one CSV file per recorder.
//!
//! Every file has a header `time [s],<column>…` and one row per recorded step, SI units.
//! Node recorders write displacements, velocities or accelerations of chosen DOFs (in the
//! node's axes; for a carried node, the deviation from its reference motion), each column
//! with its unit (`2_uz [m]`, [`Quantity::unit`]); element recorders write the named outputs
//! an element reports ([`crate::Element::output_names`]), each with the unit the element
//! declares for it (`5_Q [N]`, [`crate::Element::output_units`]; `[?]` if it declares none).
//!
//! The `comfort` recorder is the exception: it keeps the acceleration histories of its
//! node DOFs through the run and writes, when the run finishes, a ride-comfort index
//! (Sperling's `Wz` per node and DOF, or EN 12299's `N_MV` per node; [`crate::comfort`]).
//!
//! A run may also keep every recorder's rows in memory ([`Recorders::open_with`],
//! [`History`]) — the exact doubles, where the CSV holds 13 significant digits — with or
//! without writing the files; the Python bindings hand these to numpy.

use crate::assembly::Assembler;
use crate::comfort::{
    en12299_p95, n_mv, sperling_wz, ComfortMethod, Direction, EN12299_WINDOW_S, W_B, W_D,
};
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
    /// Ride comfort index of node accelerations, written at the end of the run.
    Comfort {
        /// Node ids (`node = 3` or `nodes = [3, 4]`).
        #[serde(default)]
        node: Option<u64>,
        /// More node ids.
        #[serde(default)]
        nodes: Vec<u64>,
        /// Translational DOFs weighted as vertical (`["uz"]`).
        #[serde(default)]
        vertical: Vec<String>,
        /// Translational DOFs weighted as lateral (`["uy"]`).
        #[serde(default)]
        lateral: Vec<String>,
        /// The longitudinal DOF (`["ux"]`), EN 12299 only.
        #[serde(default)]
        longitudinal: Vec<String>,
        /// `"sperling"` (Sperling's Wz) or `"en12299"` (the simplified N_MV).
        #[serde(default)]
        method: ComfortMethod,
        /// Output file name, relative to the output directory.
        file: String,
    },
}

/// Bytes a comfort recorder keeps or allocates per column and recorded step: the
/// history, its resampled copy (up to twice as long) and the transform's two buffers.
const COMFORT_BYTES_PER_SAMPLE: f64 = 8.0 * 7.0;

/// Sperling's weightings reach 30 Hz: the recorded steps must resolve it (Nyquist).
const COMFORT_MAX_INTERVAL: f64 = 1.0 / (2.0 * crate::comfort::BAND_HZ.1);

impl RecorderSpec {
    /// The node ids (node and comfort recorders) or element ids (element recorder) the
    /// recorder names.
    fn node_ids(&self, model: &Model) -> Vec<u64> {
        match self {
            RecorderSpec::Node { node, nodes, .. } | RecorderSpec::Comfort { node, nodes, .. } => {
                node.iter().chain(nodes).copied().collect()
            }
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

    /// The user ids of the elements the recorder reads: an element recorder's (by id and
    /// by type), none for the others.
    pub fn elements_read(&self, model: &Model) -> Vec<u64> {
        match self {
            RecorderSpec::Element { .. } => self.node_ids(model),
            _ => Vec::new(),
        }
    }

    /// Output file name.
    pub fn file(&self) -> &str {
        match self {
            RecorderSpec::Node { file, .. }
            | RecorderSpec::Element { file, .. }
            | RecorderSpec::Comfort { file, .. } => file,
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
            RecorderSpec::Comfort {
                vertical,
                lateral,
                longitudinal,
                method,
                ..
            } => {
                for id in &ids {
                    if model.node(*id).is_none() {
                        return Err(FemError::input(
                            &o,
                            format!("node {id} does not exist; define it in a [[node]] table or fix the id"),
                        ));
                    }
                }
                validate_comfort(
                    model,
                    &o,
                    ids.len(),
                    [vertical, lateral, longitudinal],
                    *method,
                )?;
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

/// Checks a comfort recorder's directions, method, analysis and size (`o` names it).
fn validate_comfort(
    model: &Model,
    o: &str,
    nodes: usize,
    [vertical, lateral, longitudinal]: [&Vec<String>; 3],
    method: ComfortMethod,
) -> Result<(), FemError> {
    let bad = |m: String| FemError::input(o, m);
    let en = method == ComfortMethod::En12299;
    if vertical.is_empty() && lateral.is_empty() && longitudinal.is_empty() {
        return Err(bad(
            "names no direction; add `vertical = [\"uz\"]` and/or `lateral = [\"uy\"]` (translational DOFs)".into(),
        ));
    }
    if !en && !longitudinal.is_empty() {
        return Err(bad(
            "`longitudinal` is read by `method = \"en12299\"` only (Sperling rates vertical and lateral motion); remove it or change the method".into(),
        ));
    }
    for (key, list) in [
        ("vertical", vertical),
        ("lateral", lateral),
        ("longitudinal", longitudinal),
    ] {
        for name in list {
            if !matches!(name.as_str(), "ux" | "uy" | "uz") {
                return Err(bad(format!(
                    "`{key}` names `{name}`; the comfort indices weight translational accelerations: use ux, uy or uz"
                )));
            }
        }
        if en && list.len() > 1 {
            return Err(bad(format!(
                "`{key}` names {} DOFs; EN 12299's N_MV takes one DOF per direction (e.g. `{key} = [\"{}\"]`)",
                list.len(),
                list[0]
            )));
        }
    }
    let a = &model.analysis;
    if a.kind != crate::model::AnalysisKind::Transient {
        return Err(bad(
            "a comfort recorder needs a transient analysis (accelerations over time); set `[analysis] kind = \"transient\"` or remove it".into(),
        ));
    }
    if en && a.duration < EN12299_WINDOW_S {
        return Err(bad(format!(
            "`duration` = {} s is shorter than one {} s window of EN 12299; run at least {} s (the standard asks for 5 min)",
            crate::limits::fmt_num(a.duration),
            EN12299_WINDOW_S,
            EN12299_WINDOW_S
        )));
    }
    let interval = a.dt * a.record_every as f64;
    if interval > COMFORT_MAX_INTERVAL {
        return Err(bad(format!(
            "records every {} s (`dt`·`record_every`), too coarse to resolve Sperling's band up to {} Hz; record at least every {} s",
            crate::limits::fmt_num(interval),
            crate::limits::fmt_num(crate::comfort::BAND_HZ.1),
            crate::limits::fmt_num(COMFORT_MAX_INTERVAL)
        )));
    }
    let samples = (a.duration / interval).ceil() + 2.0;
    let columns = (nodes * (vertical.len() + lateral.len() + longitudinal.len())) as f64;
    crate::limits::check_memory(
        &format!(
            "`duration` = {} s recorded every {} s",
            crate::limits::fmt_num(a.duration),
            crate::limits::fmt_num(interval)
        ),
        samples * columns,
        "comfort samples",
        COMFORT_BYTES_PER_SAMPLE,
        "record fewer nodes or directions, or a shorter run",
    )
    .map_err(bad)
}

/// One column of a comfort recorder: the node (id, index), the DOF and its weighting.
struct ComfortColumn {
    id: u64,
    node: usize,
    dof: Dof,
    direction: Direction,
}

/// The histories of a comfort recorder, turned into indices by [`Recorders::finish`].
struct ComfortHistory {
    /// EN 12299's N_MV (else Sperling's Wz).
    en12299: bool,
    columns: Vec<ComfortColumn>,
    time: Vec<f64>,
    values: Vec<Vec<f64>>,
}

impl ComfortHistory {
    fn push(&mut self, asm: &Assembler, t: f64, a: &[f64]) {
        self.time.push(t);
        for (c, v) in self.columns.iter().zip(&mut self.values) {
            v.push(asm.dofmap.value(a, c.node, c.dof.index()));
        }
    }

    /// Writes the indices: Sperling's as `node [-],dof [-],weighting [-],wz [-],duration [s],samples [-]`, one
    /// row per column; EN 12299's as
    /// `node [-],n_mv [-],ax_p95 [m/s²],ay_p95 [m/s²],az_p95 [m/s²],windows [-],duration [s]`, one row per node.
    fn write(&self, out: &mut BufWriter<File>, path: &Path) -> Result<(), FemError> {
        if self.en12299 {
            return self.write_en12299(out, path);
        }
        let io = |e: std::io::Error| FemError::output(path, e);
        writeln!(
            out,
            "node [-],dof [-],weighting [-],wz [-],duration [s],samples [-]"
        )
        .map_err(io)?;
        let duration = match (self.time.first(), self.time.last()) {
            (Some(a), Some(b)) => b - a,
            _ => 0.0,
        };
        for (c, v) in self.columns.iter().zip(&self.values) {
            let wz = sperling_wz(&self.time, v, c.direction).map_err(|e| {
                FemError::output(path, format!("node {} {}: {e}", c.id, c.dof.name()))
            })?;
            writeln!(
                out,
                "{},{},{},{wz:.6},{duration:.6e},{}",
                c.id,
                c.dof.name(),
                c.direction.name(),
                self.time.len()
            )
            .map_err(io)?;
        }
        Ok(())
    }
}

impl ComfortHistory {
    fn write_en12299(&self, out: &mut BufWriter<File>, path: &Path) -> Result<(), FemError> {
        let io = |e: std::io::Error| FemError::output(path, e);
        writeln!(
            out,
            "node [-],n_mv [-],ax_p95 [m/s²],ay_p95 [m/s²],az_p95 [m/s²],windows [-],duration [s]"
        )
        .map_err(io)?;
        let duration = match (self.time.first(), self.time.last()) {
            (Some(a), Some(b)) => b - a,
            _ => 0.0,
        };
        let mut ids: Vec<u64> = self.columns.iter().map(|c| c.id).collect();
        ids.dedup();
        for id in ids {
            // [longitudinal (Wd), lateral (Wd), vertical (Wb)]; a direction not given is 0.
            let mut p95 = [0.0; 3];
            let mut windows = 0;
            for (c, v) in self.columns.iter().zip(&self.values) {
                if c.id != id {
                    continue;
                }
                let (slot, w) = match c.direction {
                    Direction::Longitudinal => (0, &W_D),
                    Direction::Lateral => (1, &W_D),
                    Direction::Vertical => (2, &W_B),
                };
                let (p, n) = en12299_p95(&self.time, v, w).map_err(|e| {
                    FemError::output(path, format!("node {} {}: {e}", c.id, c.dof.name()))
                })?;
                p95[slot] = p;
                windows = n;
            }
            writeln!(
                out,
                "{id},{:.6},{:.6e},{:.6e},{:.6e},{windows},{duration:.6e}",
                n_mv(p95[0], p95[1], p95[2]),
                p95[0],
                p95[1],
                p95[2]
            )
            .map_err(io)?;
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
    /// A comfort recorder's histories (its file is written at the end).
    comfort: Option<ComfortHistory>,
    columns: Vec<Column>,
    /// The CSV file, when the run writes files.
    out: Option<BufWriter<File>>,
    path: PathBuf,
    /// The rows kept in memory, when asked for.
    kept: Option<History>,
}

/// One recorder's rows kept in memory: the recorded values exactly as computed.
#[derive(Debug, Clone, PartialEq)]
pub struct History {
    /// The recorder's file name (`file` in the model), which names it.
    pub file: String,
    /// Column names, the CSV header without its leading `time`. A comfort recorder keeps
    /// its acceleration histories (`<node>_<dof>`, m/s² or rad/s²), not its indices.
    pub columns: Vec<String>,
    /// Recorded times (s), one per row.
    pub time: Vec<f64>,
    /// The values, row-major: `time.len()` rows of `columns.len()` values.
    pub values: Vec<f64>,
}

/// The open recorders of a run.
pub struct Recorders {
    open: Vec<Open>,
    buf: Vec<f64>,
}

impl Recorders {
    /// Opens every recorder of `model` in `dir` (created if needed) and writes headers.
    pub fn open(model: &Model, dir: &Path) -> Result<Recorders, FemError> {
        Recorders::open_with(model, Some(dir), false)
    }

    /// Opens every recorder of `model`: writing CSV files into `dir` when given, keeping
    /// the rows in memory when `keep` ([`Recorders::histories`]).
    pub fn open_with(model: &Model, dir: Option<&Path>, keep: bool) -> Result<Recorders, FemError> {
        if let Some(dir) = dir {
            std::fs::create_dir_all(dir).map_err(|e| FemError::output(dir, e))?;
        }
        let mut open = Vec::new();
        for spec in &model.recorders {
            let path = dir.unwrap_or(Path::new("")).join(spec.file());
            let mut out = match dir {
                Some(_) => {
                    // A file in a subdirectory of the output directory (`wheels/left.csv`).
                    if let Some(parent) = path.parent() {
                        std::fs::create_dir_all(parent).map_err(|e| FemError::output(parent, e))?;
                    }
                    let f = File::create(&path).map_err(|e| FemError::output(&path, e))?;
                    Some(BufWriter::new(f))
                }
                None => None,
            };
            let mut header = vec!["time [s]".to_string()];
            let mut columns = Vec::new();
            let mut comfort = None;
            let quantity = match spec {
                RecorderSpec::Comfort {
                    vertical,
                    lateral,
                    longitudinal,
                    method,
                    ..
                } => {
                    let mut cols = Vec::new();
                    for id in spec.node_ids(model) {
                        let n = model.node(id).expect("validated");
                        for (list, direction) in [
                            (vertical, Direction::Vertical),
                            (lateral, Direction::Lateral),
                            (longitudinal, Direction::Longitudinal),
                        ] {
                            for name in list {
                                if let Some(dof) = Dof::parse(name) {
                                    cols.push(ComfortColumn {
                                        id,
                                        node: n,
                                        dof,
                                        direction,
                                    });
                                }
                            }
                        }
                    }
                    comfort = Some(ComfortHistory {
                        en12299: *method == ComfortMethod::En12299,
                        values: vec![Vec::new(); cols.len()],
                        columns: cols,
                        time: Vec::new(),
                    });
                    Quantity::Acc
                }
                RecorderSpec::Node { dofs, quantity, .. } => {
                    let set = DofSet::parse_names(dofs).unwrap_or(DofSet::NONE);
                    for id in spec.node_ids(model) {
                        let n = model.node(id).expect("validated");
                        for d in set.iter() {
                            header.push(format!(
                                "{id}_{} [{}]",
                                d.name(),
                                quantity.unit(d.index() >= 3)
                            ));
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
                        let element = &model.elements[ei].element;
                        let names = element.output_names();
                        let units = element.output_units();
                        for (k, n) in names.iter().enumerate() {
                            if outputs.is_empty() || outputs.contains(n) {
                                let unit = units
                                    .get(k)
                                    .map_or(crate::element::UNIT_UNDECLARED, |u| u.as_str());
                                header.push(format!("{id}_{n} [{unit}]"));
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
            if let (None, Some(out)) = (&comfort, out.as_mut()) {
                writeln!(out, "{}", header.join(",")).map_err(|e| FemError::output(&path, e))?;
            }
            let kept = keep.then(|| History {
                file: spec.file().to_string(),
                columns: match &comfort {
                    Some(c) => c
                        .columns
                        .iter()
                        .map(|k| format!("{}_{}", k.id, k.dof.name()))
                        .collect(),
                    None => header[1..].to_vec(),
                },
                time: Vec::new(),
                values: Vec::new(),
            });
            open.push(Open {
                quantity,
                comfort,
                columns,
                out,
                path,
                kept,
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
            if let Some(c) = o.comfort.as_mut() {
                c.push(asm, t, a);
                continue;
            }
            let src = match o.quantity {
                Quantity::Disp => q,
                Quantity::Vel => v,
                Quantity::Acc => a,
            };
            let mut line = match o.out {
                Some(_) => format!("{t:.9e}"),
                None => String::new(),
            };
            if let Some(k) = o.kept.as_mut() {
                k.time.push(t);
            }
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
                if o.out.is_some() {
                    line.push(',');
                    line.push_str(&format!("{val:.12e}"));
                }
                if let Some(k) = o.kept.as_mut() {
                    k.values.push(val);
                }
            }
            if let Some(out) = o.out.as_mut() {
                if let Err(e) = writeln!(out, "{line}") {
                    let err = FemError::output(&o.path, e);
                    self.stop_writing();
                    return Err(err);
                }
            }
        }
        Ok(())
    }

    /// After a failed write (a full disk, a file size limit): every file is left ending
    /// on a whole line and nothing more is written to it. Each is flushed; one whose flush
    /// fails (the one that failed first among them) drops what it still buffers and is
    /// cut back to its last line end ([`cut_to_whole_lines`]).
    fn stop_writing(&mut self) {
        for o in &mut self.open {
            let Some(mut out) = o.out.take() else {
                continue;
            };
            if out.flush().is_err() {
                // The buffer is dropped unwritten (a drop would try to write it again).
                let _ = out.into_parts();
                let _ = cut_to_whole_lines(&o.path);
            }
        }
    }

    /// Writes the comfort recorders' indices (once) and flushes every file; after a
    /// failed write every file ends on a whole line ([`Recorders::stop_writing`]).
    pub fn finish(&mut self) -> Result<(), FemError> {
        let r = self.finish_files();
        if r.is_err() {
            self.stop_writing();
        }
        r
    }

    fn finish_files(&mut self) -> Result<(), FemError> {
        for o in &mut self.open {
            let Some(c) = o.comfort.take() else {
                if let Some(out) = o.out.as_mut() {
                    out.flush().map_err(|e| FemError::output(&o.path, e))?;
                }
                continue;
            };
            if let Some(k) = o.kept.as_mut() {
                k.time.clone_from(&c.time);
                k.values = (0..c.time.len())
                    .flat_map(|i| c.values.iter().map(move |v| v[i]))
                    .collect();
            }
            if let Some(out) = o.out.as_mut() {
                c.write(out, &o.path)?;
                out.flush().map_err(|e| FemError::output(&o.path, e))?;
            }
        }
        Ok(())
    }

    /// The rows kept in memory, one [`History`] per recorder in the model's order (empty
    /// unless opened with `keep`). Call after [`Recorders::finish`].
    pub fn histories(self) -> Vec<History> {
        self.open.into_iter().filter_map(|o| o.kept).collect()
    }
}

/// Parses a DOF name list for recorders and loads (re-exported helper).
pub fn parse_dof(name: &str) -> Option<Dof> {
    Dof::parse(name)
}

/// Cuts the file at `path` back to just after its last line end (to nothing if it has
/// none): what a write cut short by a full disk or a size limit leaves is whole lines.
pub fn cut_to_whole_lines(path: &Path) -> std::io::Result<()> {
    use std::io::{Read, Seek, SeekFrom};
    let mut f = std::fs::OpenOptions::new()
        .read(true)
        .write(true)
        .open(path)?;
    let mut end = f.metadata()?.len();
    let mut buf = vec![0u8; 1 << 16];
    while end > 0 {
        let start = end.saturating_sub(buf.len() as u64);
        let chunk = &mut buf[..(end - start) as usize];
        f.seek(SeekFrom::Start(start))?;
        f.read_exact(chunk)?;
        if let Some(i) = chunk.iter().rposition(|b| *b == b'\n') {
            return f.set_len(start + i as u64 + 1);
        }
        end = start;
    }
    f.set_len(0)
}

//! The `comfort` recorder kind: it keeps the acceleration histories of chosen node DOFs
//! through a transient run and, when the run finishes, writes a ride-comfort index of them
//! (Sperling's `Wz` per node and DOF, or EN 12299's `N_MV` per node; [`super`]). It is a
//! registered recorder kind ([`railfem_framework::recorder_kind`]), the extension point a
//! plugin's recorder takes: the framework knows nothing of ride comfort.
//!
//! A model file names it as `[[recorder]] type = "comfort"`; Rust code builds its spec with
//! [`ComfortParams::spec`]; a train's `record.comfort` adds one over its sensors
//! ([`crate::rail::vehicle::section`]).

use super::{en12299_p95, n_mv, sperling_wz, ComfortMethod, Direction, W_B, W_D};
use railfem_framework::analysis::AnalysisKind;
use railfem_framework::limits::{check_memory, fmt_num};
use railfem_framework::lookup::ModelLookup;
use railfem_framework::recorder::RecorderSpec;
use railfem_framework::recorder_kind::{
    file_doc, RecordState, RecordedColumns, RecorderBuild, RecorderEntry, RecorderKind,
};
use railfem_framework::registry::{ParamDoc, Params};
use railfem_framework::{Dof, DofSet, FemError};
use std::io::Write;
use std::path::Path;

/// The registered type name (`[[recorder]] type = "comfort"`).
pub const KIND: &str = "comfort";

railfem_framework::element_params! {
    /// Model-file keys of the `comfort` recorder (besides `type` and `file`).
    pub struct ComfortParams {
        /// Node id.
        node: Option<u64> [""] = Option::<u64>::None,
        /// More ids (give `node`/`element`, this list, or both).
        nodes: Vec<u64> [""] = Vec::<u64>::new(),
        /// Translational DOFs weighted as vertical (["uz"]).
        vertical: Vec<Dof> [""] = Vec::<Dof>::new(),
        /// Translational DOFs weighted as lateral (["uy"]).
        lateral: Vec<Dof> [""] = Vec::<Dof>::new(),
        /// The longitudinal DOF (["ux"]), EN 12299 only.
        longitudinal: Vec<Dof> [""] = Vec::<Dof>::new(),
        /// sperling (Sperling's Wz) or en12299 (the simplified N_MV).
        method: ComfortMethod [""] = "sperling",
    }
}

/// Every key at its documented default: no node, no direction, Sperling's method (give
/// the nodes and directions with struct update syntax).
impl Default for ComfortParams {
    fn default() -> ComfortParams {
        ComfortParams {
            node: None,
            nodes: Vec::new(),
            vertical: Vec::new(),
            lateral: Vec::new(),
            longitudinal: Vec::new(),
            method: ComfortMethod::Sperling,
        }
    }
}

impl ComfortParams {
    /// Sperling's index of the nodes with user ids `nodes`, weighted as vertical along
    /// `vertical` and as lateral along `lateral` (translational DOFs); set `method` and
    /// `longitudinal` with struct update syntax for EN 12299.
    pub fn new(nodes: &[u64], vertical: &[Dof], lateral: &[Dof]) -> ComfortParams {
        ComfortParams {
            nodes: nodes.to_vec(),
            vertical: vertical.to_vec(),
            lateral: lateral.to_vec(),
            ..ComfortParams::default()
        }
    }

    /// The recorder spec that writes this index to `file` (relative to the output
    /// directory), for [`railfem_framework::ModelBuilder::recorder`].
    pub fn spec(&self, file: impl Into<String>) -> RecorderSpec {
        let params = match serde_json::to_value(self) {
            Ok(serde_json::Value::Object(m)) => m,
            _ => unreachable!("a struct of ids, DOF lists and a method serializes to a table"),
        };
        RecorderSpec::Registered(RecorderEntry {
            kind: KIND.to_string(),
            file: file.into(),
            params,
            at: String::new(),
        })
    }
}

/// Bytes a comfort recorder keeps or allocates per column and recorded step: the
/// history, its resampled copy (up to twice as long) and the transform's two buffers.
const BYTES_PER_SAMPLE: f64 = 8.0 * 7.0;

/// Sperling's weightings reach 30 Hz: the recorded steps must resolve it (Nyquist).
const MAX_INTERVAL: f64 = 1.0 / (2.0 * super::BAND_HZ.1);

/// One column: the node (id, index), the DOF and its weighting.
struct Column {
    id: u64,
    node: usize,
    dof: Dof,
    direction: Direction,
}

/// A resolved comfort recorder: its columns and the histories it has kept.
pub struct ComfortRecorder {
    /// EN 12299's N_MV (else Sperling's Wz).
    en12299: bool,
    columns: Vec<Column>,
    time: Vec<f64>,
    values: Vec<Vec<f64>>,
}

impl RecordedColumns for ComfortRecorder {
    /// The acceleration histories it keeps, `<node>_<dof>` (the rows an in-memory run
    /// returns; the file holds the index).
    fn columns(&self) -> Vec<String> {
        self.columns
            .iter()
            .map(|c| format!("{}_{}", c.id, c.dof.name()))
            .collect()
    }

    fn row(&mut self, s: &mut RecordState, out: &mut Vec<f64>) -> Result<(), FemError> {
        self.time.push(s.t);
        for (c, v) in self.columns.iter().zip(&mut self.values) {
            let a = s.node(c.node, c.dof, railfem_framework::recorder::Quantity::Acc);
            v.push(a);
            out.push(a);
        }
        Ok(())
    }

    fn writes_rows(&self) -> bool {
        false
    }

    fn finish(&mut self, out: &mut dyn Write, path: &Path) -> Result<(), FemError> {
        if self.en12299 {
            self.write_en12299(out, path)
        } else {
            self.write_sperling(out, path)
        }
    }

    fn nodes(&self) -> Vec<usize> {
        self.columns.iter().map(|c| c.node).collect()
    }
}

impl ComfortRecorder {
    /// The recorded duration (s).
    fn duration(&self) -> f64 {
        match (self.time.first(), self.time.last()) {
            (Some(a), Some(b)) => b - a,
            _ => 0.0,
        }
    }

    /// Sperling's indices as `node [-],dof [-],weighting [-],wz [-],duration [s],samples [-]`,
    /// one row per column.
    fn write_sperling(&self, out: &mut dyn Write, path: &Path) -> Result<(), FemError> {
        let io = |e: std::io::Error| FemError::output(path, e);
        writeln!(
            out,
            "node [-],dof [-],weighting [-],wz [-],duration [s],samples [-]"
        )
        .map_err(io)?;
        let duration = self.duration();
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

    /// EN 12299's indices as
    /// `node [-],n_mv [-],ax_p95 [m/s²],ay_p95 [m/s²],az_p95 [m/s²],windows [-],duration [s]`,
    /// one row per node.
    fn write_en12299(&self, out: &mut dyn Write, path: &Path) -> Result<(), FemError> {
        let io = |e: std::io::Error| FemError::output(path, e);
        writeln!(
            out,
            "node [-],n_mv [-],ax_p95 [m/s²],ay_p95 [m/s²],az_p95 [m/s²],windows [-],duration [s]"
        )
        .map_err(io)?;
        let duration = self.duration();
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

/// Builds a comfort recorder from its keys, checking ids, directions, method, analysis
/// and size against the model; `origin` names the entry in messages.
fn build(
    entry: &RecorderEntry,
    model: &dyn ModelLookup,
    origin: &str,
) -> Result<Box<dyn RecordedColumns>, FemError> {
    let p: ComfortParams = entry.parse(origin)?;
    let ids: Vec<u64> = p.node.iter().chain(&p.nodes).copied().collect();
    if ids.is_empty() {
        return Err(FemError::input(
            origin,
            "names no node or element; add `node = …`, `element = …` or `kind = …` (a type with elements in the model)",
        ));
    }
    let mut nodes = Vec::with_capacity(ids.len());
    for &id in &ids {
        let Some(n) = model.node_index(id) else {
            return Err(FemError::input(
                origin,
                format!("node {id} does not exist; define it in a [[node]] table or fix the id"),
            ));
        };
        nodes.push(n);
    }
    validate(model, origin, &p)?;
    let mut columns = Vec::new();
    for (&id, &node) in ids.iter().zip(&nodes) {
        for (list, direction) in [
            (&p.vertical, Direction::Vertical),
            (&p.lateral, Direction::Lateral),
            (&p.longitudinal, Direction::Longitudinal),
        ] {
            for &dof in list {
                columns.push(Column {
                    id,
                    node,
                    dof,
                    direction,
                });
            }
        }
    }
    Ok(Box::new(ComfortRecorder {
        en12299: p.method == ComfortMethod::En12299,
        values: vec![Vec::new(); columns.len()],
        columns,
        time: Vec::new(),
    }))
}

/// Checks the directions, method, analysis and size of the recorder `p` (`o` names it).
fn validate(model: &dyn ModelLookup, o: &str, p: &ComfortParams) -> Result<(), FemError> {
    let bad = |m: String| FemError::input(o, m);
    let (vertical, lateral, longitudinal) = (&p.vertical, &p.lateral, &p.longitudinal);
    let en = p.method == ComfortMethod::En12299;
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
        for dof in list {
            if !DofSet::TRANSLATIONS.contains(*dof) {
                return Err(bad(format!(
                    "`{key}` names `{dof}`; the comfort indices weight translational accelerations: use ux, uy or uz"
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
    let a = model.analysis();
    if a.kind != AnalysisKind::Transient {
        return Err(bad(
            "a comfort recorder needs a transient analysis (accelerations over time); set `[analysis] kind = \"transient\"` or remove it".into(),
        ));
    }
    if en && a.duration < super::EN12299_WINDOW_S {
        return Err(bad(format!(
            "`duration` = {} s is shorter than one {} s window of EN 12299; run at least {} s (the standard asks for 5 min)",
            fmt_num(a.duration),
            super::EN12299_WINDOW_S,
            super::EN12299_WINDOW_S
        )));
    }
    let interval = a.dt * a.record_every as f64;
    if interval > MAX_INTERVAL {
        return Err(bad(format!(
            "records every {} s (`dt`·`record_every`), too coarse to resolve Sperling's band up to {} Hz; record at least every {} s",
            fmt_num(interval),
            fmt_num(super::BAND_HZ.1),
            fmt_num(MAX_INTERVAL)
        )));
    }
    let samples = (a.duration / interval).ceil() + 2.0;
    let nodes = p.node.iter().count() + p.nodes.len();
    let columns = (nodes * (vertical.len() + lateral.len() + longitudinal.len())) as f64;
    check_memory(
        &format!(
            "`duration` = {} s recorded every {} s",
            fmt_num(a.duration),
            fmt_num(interval)
        ),
        samples * columns,
        "comfort samples",
        BYTES_PER_SAMPLE,
        "record fewer nodes or directions, or a shorter run",
    )
    .map_err(bad)
}

/// The documented keys: the parameters' and `file`.
fn docs() -> Vec<ParamDoc> {
    let mut v = ComfortParams::docs();
    v.push(file_doc());
    v
}

railfem_framework::inventory::submit! {
    RecorderKind {
        name: KIND,
        description: "ride-comfort index of node accelerations, written at the end of the run",
        params: docs,
        build: RecorderBuild::Factory(build),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The typed constructor gives the keys a model file gives with only `nodes`,
    /// `vertical` and `lateral` (every other key at its documented default).
    #[test]
    fn constructor_matches_the_documented_defaults() {
        let typed = ComfortParams::new(&[3], &[Dof::Uz], &[Dof::Uy]);
        let keys = serde_json::json!({"nodes": [3], "vertical": ["uz"], "lateral": ["uy"]});
        let parsed: ComfortParams =
            railfem_framework::registry::parse_params(keys.as_object().unwrap(), "t", "comfort")
                .unwrap();
        assert_eq!(typed, parsed);
    }
}

//! Writing recorders during a run ([`Recorders`]): one CSV file per recorder spec
//! ([`crate::recorder::RecorderSpec`]), one row per recorded step, or the rows kept in
//! memory ([`Recorders::open_with`], [`History`]) — the exact doubles, where the CSV holds 13
//! significant digits — with or without writing the files; the Python bindings hand these to
//! numpy. After a failed write (a full disk, a size limit) every file ends on a whole line.

use crate::assembly::Assembler;
use crate::comfort::{en12299_p95, n_mv, sperling_wz, ComfortMethod, Direction, W_B, W_D};
use crate::dof::Dof;
use crate::error::FemError;
use crate::model::Model;
use crate::recorder::{Quantity, RecorderSpec};
use crate::recorder_kind::{RecordState, RecordedColumns};
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

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
            v.push(asm.dofmap.value(a, c.node, c.dof));
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
    Node { node: usize, dof: Dof },
    Element { elem: usize, output: usize },
}

struct Open {
    quantity: Quantity,
    /// A comfort recorder's histories (its file is written at the end).
    comfort: Option<ComfortHistory>,
    /// A registered kind's recorder, which computes its own row.
    custom: Option<Box<dyn RecordedColumns>>,
    /// Values per row (the header's columns after `time`).
    width: usize,
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

impl History {
    /// The values of the column named `name`, with or without its unit (`"2_uz"` or
    /// `"2_uz [m]"`), one per recorded time; `None` if the recorder has no such column.
    pub fn column(&self, name: &str) -> Option<Vec<f64>> {
        let k = self
            .columns
            .iter()
            .position(|c| c == name || c.split_once(" [").is_some_and(|(bare, _)| bare == name))?;
        let width = self.columns.len();
        Some(self.values.iter().skip(k).step_by(width).copied().collect())
    }

    /// A node recorder's history of DOF `dof` of node user id `node`.
    pub fn node(&self, node: u64, dof: Dof) -> Option<Vec<f64>> {
        self.column(&format!("{node}_{}", dof.name()))
    }

    /// An element recorder's history of output `output` of element user id `element`.
    pub fn element(&self, element: u64, output: &str) -> Option<Vec<f64>> {
        self.column(&format!("{element}_{output}"))
    }

    /// The unit of the column named `name` (without its unit), as its header gives it.
    pub fn unit(&self, name: &str) -> Option<&str> {
        self.columns.iter().find_map(|c| {
            let (bare, rest) = c.split_once(" [")?;
            (bare == name).then(|| rest.trim_end_matches(']'))
        })
    }
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
            let mut custom: Option<Box<dyn RecordedColumns>> = None;
            let quantity = match spec {
                RecorderSpec::Registered(e) => {
                    let o = format!("{}: recorder `{}`", model.origin, e.file);
                    let c = crate::recorder_kind::build(e, model, &o)?;
                    header.extend(c.columns());
                    custom = Some(c);
                    Quantity::Disp
                }
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
                            for &dof in list {
                                cols.push(ComfortColumn {
                                    id,
                                    node: n,
                                    dof,
                                    direction,
                                });
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
                    let set = *dofs;
                    for id in spec.node_ids(model) {
                        let n = model.node(id).expect("validated");
                        for d in set.iter() {
                            header.push(format!(
                                "{id}_{} [{}]",
                                d.name(),
                                quantity.unit(d.index() >= 3)
                            ));
                            columns.push(Column::Node { node: n, dof: d });
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
                custom,
                width: header.len() - 1,
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
            if let Some(c) = o.custom.as_mut() {
                let node_value = |node: usize, dof: Dof, quantity: Quantity| {
                    let src = match quantity {
                        Quantity::Disp => q,
                        Quantity::Vel => v,
                        Quantity::Acc => a,
                    };
                    asm.dofmap.value(src, node, dof)
                };
                let model = &mut *model;
                let mut element_outputs = |ei: usize, out: &mut Vec<f64>| {
                    asm.refresh_constant(model, ei, t, q, v, a)?;
                    out.clear();
                    model.elements[ei].element.outputs(out);
                    Ok(())
                };
                let mut state = RecordState::new(t, &node_value, &mut element_outputs);
                self.buf.clear();
                c.row(&mut state, &mut self.buf)?;
                if self.buf.len() != o.width {
                    return Err(FemError::output(
                        &o.path,
                        format!(
                            "the recorder wrote {} values for its {} columns at t = {t} s (a fault of the recorder kind)",
                            self.buf.len(),
                            o.width
                        ),
                    ));
                }
            }
            let mut cached: Option<usize> = None;
            if o.custom.is_some() {
                for val in &self.buf {
                    if o.out.is_some() {
                        line.push(',');
                        line.push_str(&format!("{val:.12e}"));
                    }
                    if let Some(k) = o.kept.as_mut() {
                        k.values.push(*val);
                    }
                }
            }
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
    /// failed write every file ends on a whole line (`Recorders::stop_writing`).
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

#[cfg(test)]
mod tests {
    use super::*;

    /// Columns are read back by name (with or without the unit), by node and DOF, and by
    /// element output, from the row-major values.
    #[test]
    fn history_columns_by_name_node_and_output() {
        let h = History {
            file: "a.csv".into(),
            columns: vec!["2_uz [m]".into(), "2_ry [rad]".into(), "5_Q [N]".into()],
            time: vec![0.0, 0.1],
            values: vec![1.0, 2.0, 3.0, 4.0, 5.0, 6.0],
        };
        assert_eq!(h.column("2_uz [m]"), Some(vec![1.0, 4.0]));
        assert_eq!(h.node(2, Dof::Ry), Some(vec![2.0, 5.0]));
        assert_eq!(h.element(5, "Q"), Some(vec![3.0, 6.0]));
        assert_eq!(h.unit("5_Q"), Some("N"));
        assert_eq!(h.node(2, Dof::Ux), None);
    }
}

//! Writing recorders during a run ([`Recorders`]): one CSV file per recorder spec
//! ([`crate::recorder::RecorderSpec`]), one row per recorded step, or the rows kept in
//! memory ([`Recorders::open_with`], [`History`]) — the exact doubles, where the CSV holds 13
//! significant digits — with or without writing the files; the Python bindings hand these to
//! numpy. After a failed write (a full disk, a size limit) every file ends on a whole line.

use crate::assembly::Assembler;
use crate::dof::Dof;
use crate::error::FemError;
use crate::model::Model;
use crate::recorder::{Quantity, RecorderSpec};
use crate::recorder_kind::{RecordState, RecordedColumns};
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

enum Column {
    Node { node: usize, dof: Dof },
    Element { elem: usize, output: usize },
}

struct Open {
    quantity: Quantity,
    /// A registered kind's recorder, which computes its own row.
    custom: Option<Box<dyn RecordedColumns>>,
    /// Whether the rows go to the file (all but a registered kind that writes a summary
    /// at the end, [`RecordedColumns::writes_rows`]).
    rows_to_file: bool,
    /// Whether [`RecordedColumns::finish`] has run (it runs once).
    finished: bool,
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
    /// Column names, the CSV header without its leading `time`. A recorder that writes a
    /// summary at the end (the ride-comfort recorder) keeps the rows it summarised (its
    /// acceleration histories, `<node>_<dof>`, m/s² or rad/s²), not the summary.
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
            let mut custom: Option<Box<dyn RecordedColumns>> = None;
            let quantity = match spec {
                RecorderSpec::Registered(e) => {
                    let o = format!("{}: recorder `{}`", model.origin, e.file);
                    let c = crate::recorder_kind::build(e, model, &o)?;
                    header.extend(c.columns());
                    custom = Some(c);
                    Quantity::Disp
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
            let rows_to_file = custom.as_ref().is_none_or(|c| c.writes_rows());
            if let (true, Some(out)) = (rows_to_file, out.as_mut()) {
                writeln!(out, "{}", header.join(",")).map_err(|e| FemError::output(&path, e))?;
            }
            let kept = keep.then(|| History {
                file: spec.file().to_string(),
                columns: header[1..].to_vec(),
                time: Vec::new(),
                values: Vec::new(),
            });
            open.push(Open {
                quantity,
                custom,
                rows_to_file,
                finished: false,
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
            let src = match o.quantity {
                Quantity::Disp => q,
                Quantity::Vel => v,
                Quantity::Acc => a,
            };
            let to_file = o.rows_to_file && o.out.is_some();
            let mut line = match to_file {
                true => format!("{t:.9e}"),
                false => String::new(),
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
                    if to_file {
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
                if to_file {
                    line.push(',');
                    line.push_str(&format!("{val:.12e}"));
                }
                if let Some(k) = o.kept.as_mut() {
                    k.values.push(val);
                }
            }
            if let (true, Some(out)) = (to_file, o.out.as_mut()) {
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

    /// Lets each registered kind finish its file ([`RecordedColumns::finish`]: a summary
    /// such as a ride-comfort index) and flushes every file; after a failed write every
    /// file ends on a whole line (`Recorders::stop_writing`).
    pub fn finish(&mut self) -> Result<(), FemError> {
        let r = self.finish_files();
        if r.is_err() {
            self.stop_writing();
        }
        r
    }

    fn finish_files(&mut self) -> Result<(), FemError> {
        for o in &mut self.open {
            let Some(out) = o.out.as_mut() else {
                continue;
            };
            if let (Some(c), false) = (o.custom.as_mut(), o.finished) {
                o.finished = true;
                c.finish(out, &o.path)?;
            }
            out.flush().map_err(|e| FemError::output(&o.path, e))?;
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

//! ParaView output: a time series of VTK unstructured grids (`.vtu`, ASCII) with a `.pvd`
//! index, so a run can be watched — the carriage leaning into the curve.
//!
//! Points are the nodes at their current reference positions (a carried node moves with
//! its carrier); the point field `displacement` is the nodal displacement in global axes
//! (a carried node's deviation rotated out of its wheel frame), so ParaView's *Warp By
//! Vector* shows the deformed shape at any exaggeration. Cells are the elements: a vertex
//! for one-node elements, a line for two-node elements, a poly-line otherwise. A filter
//! chooses the nodes to write (a 16 km track need not be written at every step); an element
//! is written when all its nodes are.

use crate::assembly::Assembler;
use crate::error::FemError;
use crate::model::Model;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// Writes one `.vtu` per call and the `.pvd` index at the end.
pub struct VtkSeries {
    dir: PathBuf,
    stem: String,
    steps: Vec<(f64, String)>,
}

impl VtkSeries {
    /// A series `DIR/STEM_NNNNN.vtu` indexed by `DIR/STEM.pvd`.
    pub fn new(dir: &Path, stem: &str) -> Result<VtkSeries, FemError> {
        std::fs::create_dir_all(dir).map_err(|e| FemError::output(dir, e))?;
        Ok(VtkSeries {
            dir: dir.to_path_buf(),
            stem: stem.to_string(),
            steps: Vec::new(),
        })
    }

    /// Writes the state `q` at time `t` for the nodes `keep` accepts; returns the number of
    /// points written.
    pub fn write(
        &mut self,
        model: &Model,
        asm: &Assembler,
        q: &[f64],
        t: f64,
        keep: &dyn Fn(usize) -> bool,
    ) -> Result<usize, FemError> {
        let kin = asm.kinematics();
        let mut index = vec![u32::MAX; model.nodes.len()];
        let mut pts = String::new();
        let mut disp = String::new();
        let mut n = 0u32;
        for (i, slot) in index.iter_mut().enumerate() {
            if !keep(i) {
                continue;
            }
            *slot = n;
            n += 1;
            let p = kin[i].position;
            let _ = write!(pts, "{:.6} {:.6} {:.6} ", p.x, p.y, p.z);
            let u = nalgebra::Vector3::from_fn(|d, _| asm.dofmap.value(q, i, d));
            let g = kin[i].frame * u;
            let _ = write!(disp, "{:.10e} {:.10e} {:.10e} ", g.x, g.y, g.z);
        }
        let (mut conn, mut offs, mut types) = (String::new(), String::new(), String::new());
        let (mut off, mut cells) = (0usize, 0usize);
        for e in &model.elements {
            let mut ids: Vec<u32> = Vec::new();
            for nd in e.element.connectivity() {
                if !ids.contains(&index[nd.node]) {
                    ids.push(index[nd.node]);
                }
            }
            if ids.is_empty() || ids.contains(&u32::MAX) {
                continue;
            }
            for id in &ids {
                let _ = write!(conn, "{id} ");
            }
            off += ids.len();
            let _ = write!(offs, "{off} ");
            let ty = match ids.len() {
                1 => 1,
                2 => 3,
                _ => 4,
            };
            let _ = write!(types, "{ty} ");
            cells += 1;
        }
        let name = format!("{}_{:05}.vtu", self.stem, self.steps.len());
        let mut s = String::new();
        let _ = write!(
            s,
            "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n<UnstructuredGrid>\n<Piece NumberOfPoints=\"{n}\" NumberOfCells=\"{cells}\">\n<Points>\n<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n{pts}\n</DataArray>\n</Points>\n<Cells>\n<DataArray type=\"Int32\" Name=\"connectivity\" format=\"ascii\">\n{conn}\n</DataArray>\n<DataArray type=\"Int32\" Name=\"offsets\" format=\"ascii\">\n{offs}\n</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n{types}\n</DataArray>\n</Cells>\n<PointData Vectors=\"displacement\">\n<DataArray type=\"Float64\" Name=\"displacement\" NumberOfComponents=\"3\" format=\"ascii\">\n{disp}\n</DataArray>\n</PointData>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n"
        );
        let path = self.dir.join(&name);
        std::fs::write(&path, s).map_err(|e| FemError::output(&path, e))?;
        self.steps.push((t, name));
        Ok(n as usize)
    }

    /// Writes the `.pvd` index of every step written so far.
    pub fn finish(&self) -> Result<(), FemError> {
        let mut s = String::from(
            "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\">\n<Collection>\n",
        );
        for (t, f) in &self.steps {
            let _ = writeln!(
                s,
                "<DataSet timestep=\"{t}\" group=\"\" part=\"0\" file=\"{f}\"/>"
            );
        }
        s.push_str("</Collection>\n</VTKFile>\n");
        let path = self.dir.join(format!("{}.pvd", self.stem));
        std::fs::write(&path, s).map_err(|e| FemError::output(&path, e))
    }
}

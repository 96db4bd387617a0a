//! ParaView output: a time series of VTK unstructured grids (`.vtu`, XML with appended raw
//! binary data) with a `.pvd` index, so a run can be watched — the carriage leaning into the
//! curve, a train crossing a 1M-DOF viaduct.
//!
//! Points are the nodes at their current reference positions (a carried node moves with
//! its carrier). Point data, in global axes (a carried node's values rotated out of its
//! wheel frame): `displacement` (m), so ParaView's *Warp By Vector* shows the deformed shape
//! at any exaggeration, and `velocity` (m/s, relative to the node's reference motion).
//! Cells are the elements: a vertex for one-node elements, a line for two-node elements, a
//! poly-line otherwise. Cell data: `force_norm`, the Euclidean norm of the element's
//! resisting-force vector (N and N·m mixed: a quick map of where the structure works),
//! `contact`, the number of a wheel's contact points in contact (0: the wheel is off the
//! rail; −1: the element has no contact), and `contact_force` (N), a wheel's normal force
//! `Q` or a moving oscillator's contact force (NaN for other elements).
//!
//! A filter chooses the nodes to write (a 16 km track need not be written at every step);
//! an element is written when all its nodes are. The binary layout is VTK's XML format
//! version 1.0, little-endian, `header_type="UInt64"`: every array in `<AppendedData
//! encoding="raw">` is an 8-byte byte count followed by the values, and each `DataArray`
//! gives its `offset` into that block. No compression: a frame is written as fast as the
//! disk takes it and read by ParaView without decoding. [`Encoding::Base64`] writes the same
//! arrays base64-encoded (a third larger, slower), for readers that scan the appended block
//! as text: the `vtkio` crate, for one, stops at the first `<` byte of raw data.

use crate::assembly::Assembler;
use crate::error::FemError;
use crate::model::Model;
use std::fmt::Write as _;
use std::io::Write as _;
use std::path::{Path, PathBuf};

/// Names of an element's outputs the cell data reads, resolved once per element.
#[derive(Debug, Clone, Copy, Default)]
struct OutputSlots {
    /// Index of `n_contact` (multi-point wheels) or `in_contact` (point wheels, oscillators).
    contact: Option<usize>,
    /// Index of `Q` (wheels) or `contact_force` (moving oscillators).
    force: Option<usize>,
}

/// How the appended arrays are stored.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Encoding {
    /// Raw little-endian bytes (the default: smallest and fastest).
    #[default]
    Raw,
    /// Base64 text, each array with its byte count encoded in one run.
    Base64,
}

/// Base64 (RFC 4648, with padding) of `bytes`, appended to `out`.
fn base64_into(bytes: &[u8], out: &mut Vec<u8>) {
    const ABC: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    for c in bytes.chunks(3) {
        let b = [c[0], *c.get(1).unwrap_or(&0), *c.get(2).unwrap_or(&0)];
        let n = (b[0] as u32) << 16 | (b[1] as u32) << 8 | b[2] as u32;
        for k in 0..4 {
            if k <= c.len() {
                out.push(ABC[(n >> (18 - 6 * k) & 63) as usize]);
            } else {
                out.push(b'=');
            }
        }
    }
}

/// Writes one `.vtu` per call and the `.pvd` index at the end.
pub struct VtkSeries {
    /// Storage of the appended arrays.
    pub encoding: Encoding,
    dir: PathBuf,
    stem: String,
    steps: Vec<(f64, String)>,
    /// Output slots per element index, filled the first time the element is written.
    slots: Vec<Option<OutputSlots>>,
}

/// The state a frame shows: time and the equation vectors.
#[derive(Debug, Clone, Copy)]
pub struct Frame<'a> {
    /// Time (s).
    pub t: f64,
    /// Displacements (m, rad).
    pub q: &'a [f64],
    /// Velocities (m/s, rad/s).
    pub v: &'a [f64],
    /// Accelerations (m/s², rad/s²); constant elements are brought to this state before
    /// their forces are read.
    pub a: &'a [f64],
}

/// One array of the appended block: its XML attributes and its little-endian bytes.
struct Array {
    attrs: String,
    bytes: Vec<u8>,
}

fn f64_array(name: &str, components: usize, values: &[f64]) -> Array {
    let mut bytes = Vec::with_capacity(8 * values.len());
    for v in values {
        bytes.extend_from_slice(&v.to_le_bytes());
    }
    Array {
        attrs: format!(r#"type="Float64" Name="{name}" NumberOfComponents="{components}""#),
        bytes,
    }
}

fn i64_array(name: &str, values: &[i64]) -> Array {
    let mut bytes = Vec::with_capacity(8 * values.len());
    for v in values {
        bytes.extend_from_slice(&v.to_le_bytes());
    }
    Array {
        attrs: format!(r#"type="Int64" Name="{name}""#),
        bytes,
    }
}

fn i32_array(name: &str, values: &[i32]) -> Array {
    let mut bytes = Vec::with_capacity(4 * values.len());
    for v in values {
        bytes.extend_from_slice(&v.to_le_bytes());
    }
    Array {
        attrs: format!(r#"type="Int32" Name="{name}""#),
        bytes,
    }
}

impl VtkSeries {
    /// A series `DIR/STEM_NNNNN.vtu` indexed by `DIR/STEM.pvd`.
    pub fn new(dir: &Path, stem: &str) -> Result<VtkSeries, FemError> {
        std::fs::create_dir_all(dir).map_err(|e| FemError::output(dir, e))?;
        Ok(VtkSeries {
            encoding: Encoding::Raw,
            dir: dir.to_path_buf(),
            stem: stem.to_string(),
            steps: Vec::new(),
            slots: Vec::new(),
        })
    }

    /// Writes the state `frame` for the nodes `keep` accepts; returns the number of points
    /// written. Constant elements are brought to the frame's state first (as recorders do,
    /// [`Assembler::refresh_constant`]) so that their forces are the current ones.
    pub fn write(
        &mut self,
        model: &mut Model,
        asm: &Assembler,
        frame: Frame,
        keep: &dyn Fn(usize) -> bool,
    ) -> Result<usize, FemError> {
        let kin = asm.kinematics();
        let nn = model.nodes.len();
        let mut index = vec![u32::MAX; nn];
        let mut pts = Vec::new();
        let (mut disp, mut vel) = (Vec::new(), Vec::new());
        let mut n = 0u32;
        for (i, slot) in index.iter_mut().enumerate() {
            if !keep(i) {
                continue;
            }
            *slot = n;
            n += 1;
            let p = kin[i].position;
            pts.extend_from_slice(&[p.x, p.y, p.z]);
            for (src, out) in [(frame.q, &mut disp), (frame.v, &mut vel)] {
                let u = nalgebra::Vector3::from_fn(|d, _| asm.dofmap.value_at(src, i, d));
                let g = kin[i].frame * u;
                out.extend_from_slice(&[g.x, g.y, g.z]);
            }
        }
        if self.slots.len() != model.elements.len() {
            self.slots = vec![None; model.elements.len()];
        }
        let (mut conn, mut offs, mut types) = (Vec::new(), Vec::new(), Vec::new());
        let (mut force_norm, mut contact, mut contact_force) = (Vec::new(), Vec::new(), Vec::new());
        let (mut f, mut outs, mut ids) = (Vec::new(), Vec::new(), Vec::new());
        for ei in 0..model.elements.len() {
            ids.clear();
            for nd in model.elements[ei].element.connectivity() {
                if !ids.contains(&index[nd.node]) {
                    ids.push(index[nd.node]);
                }
            }
            if ids.is_empty() || ids.contains(&u32::MAX) {
                continue;
            }
            conn.extend(ids.iter().map(|&i| i as i64));
            offs.push(conn.len() as i64);
            types.push(match ids.len() {
                1 => 1u8,
                2 => 3,
                _ => 4,
            });
            asm.refresh_constant(model, ei, frame.t, frame.q, frame.v, frame.a)?;
            let e = &model.elements[ei].element;
            f.clear();
            f.resize(e.ndof(), 0.0);
            e.resisting_force(&mut f);
            force_norm.push(f.iter().map(|x| x * x).sum::<f64>().sqrt());
            let slots = *self.slots[ei].get_or_insert_with(|| {
                let names = e.output_names();
                let at =
                    |keys: &[&str]| keys.iter().find_map(|k| names.iter().position(|n| n == k));
                OutputSlots {
                    contact: at(&["n_contact", "in_contact"]),
                    force: at(&["Q", "contact_force"]),
                }
            });
            if slots.contact.is_some() || slots.force.is_some() {
                outs.clear();
                e.outputs(&mut outs);
            }
            let read = |k: Option<usize>| k.and_then(|k| outs.get(k).copied());
            contact.push(read(slots.contact).map_or(-1, |c| c.round() as i32));
            contact_force.push(read(slots.force).unwrap_or(f64::NAN));
        }
        let cells = types.len();
        let arrays_point = [
            f64_array("displacement", 3, &disp),
            f64_array("velocity", 3, &vel),
        ];
        let arrays_cell = [
            f64_array("force_norm", 1, &force_norm),
            i32_array("contact", &contact),
            f64_array("contact_force", 1, &contact_force),
        ];
        let points = f64_array("Points", 3, &pts);
        let cell_arrays = [
            i64_array("connectivity", &conn),
            i64_array("offsets", &offs),
            Array {
                attrs: r#"type="UInt8" Name="types""#.to_string(),
                bytes: types,
            },
        ];
        // The XML head with each array's offset into the appended block (8-byte count
        // before each array's bytes).
        let mut head = String::new();
        let mut offset = 0usize;
        let encoding = self.encoding;
        let mut tag = |head: &mut String, a: &Array| {
            let _ = writeln!(
                head,
                r#"<DataArray {} format="appended" offset="{offset}"/>"#,
                a.attrs
            );
            offset += match encoding {
                Encoding::Raw => 8 + a.bytes.len(),
                Encoding::Base64 => 4 * (8 + a.bytes.len()).div_ceil(3),
            };
        };
        let _ = write!(
            head,
            "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n<UnstructuredGrid>\n<Piece NumberOfPoints=\"{n}\" NumberOfCells=\"{cells}\">\n<PointData Vectors=\"displacement\">\n"
        );
        for a in &arrays_point {
            tag(&mut head, a);
        }
        head.push_str("</PointData>\n<CellData Scalars=\"force_norm\">\n");
        for a in &arrays_cell {
            tag(&mut head, a);
        }
        head.push_str("</CellData>\n<Points>\n");
        tag(&mut head, &points);
        head.push_str("</Points>\n<Cells>\n");
        for a in &cell_arrays {
            tag(&mut head, a);
        }
        head.push_str("</Cells>\n</Piece>\n</UnstructuredGrid>\n");
        head.push_str(match encoding {
            Encoding::Raw => "<AppendedData encoding=\"raw\">\n_",
            Encoding::Base64 => "<AppendedData encoding=\"base64\">\n_",
        });
        let name = format!("{}_{:05}.vtu", self.stem, self.steps.len());
        let path = self.dir.join(&name);
        let io = |e: std::io::Error| FemError::output(&path, e);
        let file = std::fs::File::create(&path).map_err(io)?;
        let mut w = std::io::BufWriter::with_capacity(1 << 20, file);
        w.write_all(head.as_bytes()).map_err(io)?;
        for a in arrays_point
            .iter()
            .chain(&arrays_cell)
            .chain(std::iter::once(&points))
            .chain(&cell_arrays)
        {
            let count = (a.bytes.len() as u64).to_le_bytes();
            match encoding {
                Encoding::Raw => {
                    w.write_all(&count).map_err(io)?;
                    w.write_all(&a.bytes).map_err(io)?;
                }
                Encoding::Base64 => {
                    let mut run = count.to_vec();
                    run.extend_from_slice(&a.bytes);
                    let mut text = Vec::with_capacity(4 * run.len() / 3 + 4);
                    base64_into(&run, &mut text);
                    w.write_all(&text).map_err(io)?;
                }
            }
        }
        w.write_all(b"\n</AppendedData>\n</VTKFile>\n")
            .map_err(io)?;
        w.flush().map_err(io)?;
        self.steps.push((frame.t, name));
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

#[cfg(test)]
mod tests {
    use super::base64_into;

    /// RFC 4648's test vectors.
    #[test]
    fn base64_matches_the_rfc_vectors() {
        for (plain, code) in [
            ("", ""),
            ("f", "Zg=="),
            ("fo", "Zm8="),
            ("foo", "Zm9v"),
            ("foob", "Zm9vYg=="),
            ("fooba", "Zm9vYmE="),
            ("foobar", "Zm9vYmFy"),
        ] {
            let mut out = Vec::new();
            base64_into(plain.as_bytes(), &mut out);
            assert_eq!(String::from_utf8(out).unwrap(), code, "{plain}");
        }
    }
}

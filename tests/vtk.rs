//! ParaView output: a static cantilever written as one binary VTU step, read back with
//! `vtkio` (an independent reader of the format): the counts, the displacement field against
//! the closed form, the velocity (zero) and each element's resisting-force norm against the
//! statics of a cantilever under a tip load.
//!
//! `vtkio` reads the base64 encoding; it scans raw appended data as XML text and stops at
//! the first `<` byte, so the raw file (what ParaView is given by default) is checked
//! through a few lines here that follow each array's `offset` and byte count, against the
//! arrays `vtkio` read from the base64 file of the same frame.

use railfem::framework::builder::ModelBuilder;
use railfem::framework::loads::{LoadSpec, TimeSeries};
use railfem::framework::model::{AnalysisKind, AnalysisSpec};
use railfem::framework::vtk::{Encoding, Frame, VtkSeries};
use railfem::framework::DofSet;
use railfem::solvers::Driver;
use std::collections::HashMap;
use std::path::Path;
use vtkio::model::{Attribute, DataSet, VertexNumbers};

const P: f64 = 1e3; // N, tip load along −Z
const EI: f64 = 2e11 * 1e-5; // N·m²

/// The named array of a list of attributes as `f64`s.
fn array(attrs: &[Attribute], name: &str) -> Vec<f64> {
    attrs
        .iter()
        .find_map(|a| match a {
            Attribute::DataArray(d) if d.name == name => d.data.clone().cast_into::<f64>(),
            _ => None,
        })
        .unwrap_or_else(|| panic!("no array {name}"))
}

/// The arrays of a raw-appended VTU file, by name: each `DataArray`'s `offset` into the
/// block after `<AppendedData encoding="raw">` and `_` points at an 8-byte little-endian
/// byte count followed by that many bytes.
fn raw_arrays(path: &Path) -> HashMap<String, Vec<u8>> {
    let bytes = std::fs::read(path).unwrap();
    let mark = b"<AppendedData encoding=\"raw\">";
    let at = bytes
        .windows(mark.len())
        .position(|w| w == mark)
        .expect("raw appended data");
    let base = at + bytes[at..].iter().position(|&b| b == b'_').unwrap() + 1;
    let head = std::str::from_utf8(&bytes[..at]).unwrap();
    let attr = |line: &str, key: &str| -> String {
        let k = line.find(&format!("{key}=\"")).unwrap() + key.len() + 2;
        line[k..k + line[k..].find('"').unwrap()].to_string()
    };
    head.lines()
        .filter(|l| l.starts_with("<DataArray"))
        .map(|l| {
            let off = base + attr(l, "offset").parse::<usize>().unwrap();
            let n = u64::from_le_bytes(bytes[off..off + 8].try_into().unwrap()) as usize;
            (attr(l, "Name"), bytes[off + 8..off + 8 + n].to_vec())
        })
        .collect()
}

fn f64s(bytes: &[u8]) -> Vec<f64> {
    bytes
        .chunks(8)
        .map(|c| f64::from_le_bytes(c.try_into().unwrap()))
        .collect()
}

fn i64s(bytes: &[u8]) -> Vec<i64> {
    bytes
        .chunks(8)
        .map(|c| i64::from_le_bytes(c.try_into().unwrap()))
        .collect()
}

#[test]
fn binary_vtu_reads_back_with_displacements_and_element_forces() {
    let mut b = ModelBuilder::new("vtk");
    b.node_fixed(1, [0.0, 0.0, 0.0], DofSet::ALL);
    b.node(2, [1.0, 0.0, 0.0]);
    b.node(3, [2.0, 0.0, 0.0]);
    let beam =
        serde_json::json!({"E": 2e11, "G": 8e10, "A": 1e-2, "Iy": 1e-5, "Iz": 1e-5, "J": 2e-5});
    b.element("beam3d", 1, &[1, 2], &beam);
    b.element("beam3d", 2, &[2, 3], &beam);
    b.load(LoadSpec::Nodal {
        node: 3,
        dof: railfem::framework::Dof::Uz,
        value: -P,
        series: TimeSeries::Constant,
    });
    b.analysis(AnalysisSpec {
        kind: AnalysisKind::Static,
        ..Default::default()
    });
    let mut d = Driver::new(b.build().unwrap()).unwrap();
    d.run(None, &mut |_| {}).unwrap();
    let dir = std::env::temp_dir().join(format!("railfem-vtk-{}", std::process::id()));
    let mut v = VtkSeries::new(&dir, "beam").unwrap();
    let raw = dir.join("raw");
    let mut r = VtkSeries::new(&raw, "beam").unwrap();
    v.encoding = Encoding::Base64;
    let frame = Frame {
        t: 0.0,
        q: &d.state.q,
        v: &d.state.v,
        a: &d.state.a,
    };
    let n = v.write(&mut d.model, &d.asm, frame, &|_| true).unwrap();
    assert_eq!(r.write(&mut d.model, &d.asm, frame, &|_| true).unwrap(), n);
    v.finish().unwrap();
    assert_eq!(n, 3);

    let vtk = vtkio::Vtk::import(dir.join("beam_00000.vtu")).expect("vtkio reads the file");
    let DataSet::UnstructuredGrid { pieces, .. } = vtk.data else {
        panic!("not an unstructured grid")
    };
    let piece = pieces[0].load_piece_data(None).unwrap();
    let pts = piece.points.clone().cast_into::<f64>().unwrap();
    assert_eq!(pts, vec![0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 2.0, 0.0, 0.0]);
    match &piece.cells.cell_verts {
        VertexNumbers::XML {
            connectivity,
            offsets,
        } => {
            assert_eq!(connectivity, &vec![0, 1, 1, 2]);
            assert_eq!(offsets, &vec![2, 4]);
        }
        other => panic!("unexpected cells {other:?}"),
    }
    assert_eq!(piece.cells.types.len(), 2);

    // w(x) = −P·x²·(3L − x)/(6EI), L = 2 m: nodes 2 and 3.
    let disp = array(&piece.data.point, "displacement");
    assert_eq!(disp.len(), 9);
    let w = |x: f64| -P * x * x * (3.0 * 2.0 - x) / (6.0 * EI);
    for (k, x) in [(5, 1.0), (8, 2.0)] {
        assert!(
            (disp[k] - w(x)).abs() < 1e-9 * w(2.0).abs(),
            "uz({x}) = {} vs {}",
            disp[k],
            w(x)
        );
    }
    assert!(array(&piece.data.point, "velocity")
        .iter()
        .all(|&x| x == 0.0));

    // End forces of each element: shear P at both ends, bending moment P·(L − x) at an end
    // at x. Element 1 (x = 0..1): moments 2P·1 m and P·1 m; element 2: P·1 m and 0.
    let norms = array(&piece.data.cell, "force_norm");
    let exact = [P * 7f64.sqrt(), P * 3f64.sqrt()];
    for (e, (got, want)) in norms.iter().zip(exact).enumerate() {
        assert!(
            (got - want).abs() < 1e-6 * want,
            "element {e}: {got} vs {want}"
        );
    }
    let contact = array(&piece.data.cell, "contact");
    assert_eq!(contact, vec![-1.0, -1.0], "beams have no contact state");
    assert!(array(&piece.data.cell, "contact_force")
        .iter()
        .all(|x| x.is_nan()));

    let pvd = std::fs::read_to_string(dir.join("beam.pvd")).unwrap();
    assert!(pvd.contains("file=\"beam_00000.vtu\""));

    // The raw file holds the very arrays vtkio read from the base64 one.
    let raw = raw_arrays(&raw.join("beam_00000.vtu"));
    assert_eq!(f64s(&raw["Points"]), pts);
    for name in ["displacement", "velocity"] {
        let want = array(&piece.data.point, name);
        assert_eq!(f64s(&raw[name]), want, "{name}");
    }
    for name in ["force_norm", "contact_force"] {
        let (got, want) = (f64s(&raw[name]), array(&piece.data.cell, name));
        assert_eq!(got.len(), want.len());
        assert!(got
            .iter()
            .zip(&want)
            .all(|(a, b)| a.to_bits() == b.to_bits()));
    }
    assert_eq!(i64s(&raw["connectivity"]), vec![0, 1, 1, 2]);
    assert_eq!(i64s(&raw["offsets"]), vec![2, 4]);
    assert_eq!(raw["types"], vec![3u8, 3]);
    let contact: Vec<f64> = raw["contact"]
        .chunks(4)
        .map(|c| i32::from_le_bytes(c.try_into().unwrap()) as f64)
        .collect();
    assert_eq!(contact, array(&piece.data.cell, "contact"));
    let _ = std::fs::remove_dir_all(&dir);
}

/// A sprung mass resting on a simply supported beam (examples/models/moving_sprung_mass.toml)
/// after the static solve at t = 0: its cell says "in contact" and carries the weight
/// `m·g` as contact force; the beams say "no contact state".
#[test]
fn wheel_cells_carry_contact_state_and_force() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("examples/models/moving_sprung_mass.toml");
    let mut d = Driver::new(railfem::load_model(&path).unwrap()).unwrap();
    d.initialize().unwrap();
    let dir = std::env::temp_dir().join(format!("railfem-vtk-wheel-{}", std::process::id()));
    let mut v = VtkSeries::new(&dir, "sprung").unwrap();
    v.encoding = Encoding::Base64;
    let frame = Frame {
        t: d.state.t,
        q: &d.state.q,
        v: &d.state.v,
        a: &d.state.a,
    };
    v.write(&mut d.model, &d.asm, frame, &|_| true).unwrap();
    let vtk = vtkio::Vtk::import(dir.join("sprung_00000.vtu")).unwrap();
    let DataSet::UnstructuredGrid { pieces, .. } = vtk.data else {
        panic!("not an unstructured grid")
    };
    let piece = pieces[0].load_piece_data(None).unwrap();
    let contact = array(&piece.data.cell, "contact");
    let force = array(&piece.data.cell, "contact_force");
    let wheels: Vec<usize> = (0..contact.len()).filter(|&i| contact[i] >= 0.0).collect();
    assert_eq!(
        wheels.len(),
        1,
        "one cell with a contact state: {contact:?}"
    );
    let w = wheels[0];
    assert_eq!(contact[w], 1.0, "resting on the beam");
    let weight = 5750.0 * 9.81;
    assert!(
        (force[w].abs() - weight).abs() < 1e-6 * weight,
        "contact force {} vs m·g = {weight}",
        force[w]
    );
    assert_eq!(
        force.iter().filter(|x| x.is_nan()).count(),
        contact.len() - 1
    );
    let _ = std::fs::remove_dir_all(&dir);
}

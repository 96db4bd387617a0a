//! ParaView output: a small static model written as one VTU step; the file parses as the
//! counts say and the displacement field equals the solver's nodal displacements.

use railfem::framework::loads::{LoadSpec, TimeSeries};
use railfem::framework::model::{AnalysisKind, AnalysisSpec, ModelBuilder};
use railfem::framework::vtk::VtkSeries;
use railfem::framework::DofSet;
use railfem::solvers::Driver;

#[test]
fn vtu_step_holds_points_cells_and_displacements() {
    railfem::elements::link();
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
        dof: "uz".into(),
        value: -1e3,
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
    let n = v
        .write(&d.model, &d.asm, &d.state.q, 0.0, &|_| true)
        .unwrap();
    v.finish().unwrap();
    assert_eq!(n, 3);
    let text = std::fs::read_to_string(dir.join("beam_00000.vtu")).unwrap();
    assert!(text.contains("NumberOfPoints=\"3\" NumberOfCells=\"2\""));
    // The displacement array is the last DataArray: 9 numbers, node 3's uz = −P·L³/(3EI).
    let block = text.split("Name=\"displacement\"").nth(1).unwrap();
    let nums: Vec<f64> = block
        .split('>')
        .nth(1)
        .unwrap()
        .split('<')
        .next()
        .unwrap()
        .split_whitespace()
        .map(|x| x.parse().unwrap())
        .collect();
    assert_eq!(nums.len(), 9);
    let exact = -1e3 * 8.0 / (3.0 * 2e11 * 1e-5);
    assert!(
        (nums[8] - exact).abs() < 1e-9 * exact.abs() + 1e-12,
        "{} vs {exact}",
        nums[8]
    );
    let pvd = std::fs::read_to_string(dir.join("beam.pvd")).unwrap();
    assert!(pvd.contains("file=\"beam_00000.vtu\""));
}

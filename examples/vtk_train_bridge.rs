//! Times one ParaView frame of the train–bridge model (docs/performance.md, "ParaView
//! frames"): builds `railfem train-bridge`'s model at a DOF target (default 1 043 430,
//! 12 cars), settles it statically, takes a few transient steps, then writes the whole
//! model — every node, every element — as one binary VTU frame (raw, then base64) and
//! prints the time and the size of each.
//!
//! `cargo run --release --example vtk_train_bridge -- [DOF] [STEPS] [DIR]`
//! (defaults 1043430, 2, /tmp/railfem-vtk-frame).

use railfem::framework::vtk::{Encoding, Frame, VtkSeries};
use railfem::train_bridge::{build, TrainBridgeCase};
use std::time::Instant;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let dof: usize = args.first().map_or(Ok(1_043_430), |s| s.parse())?;
    let steps: usize = args.get(1).map_or(Ok(2), |s| s.parse())?;
    let dir = std::path::PathBuf::from(
        args.get(2)
            .cloned()
            .unwrap_or_else(|| "/tmp/railfem-vtk-frame".into()),
    );
    let case = TrainBridgeCase {
        dof_target: Some(dof),
        ..Default::default()
    };
    let t0 = Instant::now();
    let mut m = build(&case)?;
    println!(
        "model: {} equations, {} nodes, {} elements, built in {:.1} s",
        m.dofs,
        m.nodes,
        m.elements,
        t0.elapsed().as_secs_f64()
    );
    let d = &mut m.driver;
    let t1 = Instant::now();
    d.static_solve(0.0, 10)?;
    d.initialize()?;
    for _ in 0..steps {
        d.step(case.dt)?;
    }
    println!(
        "static solve and {steps} steps: {:.1} s (t = {:.3} s)",
        t1.elapsed().as_secs_f64(),
        d.state.t
    );
    for (encoding, sub) in [(Encoding::Raw, "raw"), (Encoding::Base64, "base64")] {
        let mut series = VtkSeries::new(&dir.join(sub), "train_bridge")?;
        series.encoding = encoding;
        let frame = Frame {
            t: d.state.t,
            q: &d.state.q,
            v: &d.state.v,
            a: &d.state.a,
        };
        let t = Instant::now();
        let n = series.write(&mut d.model, &d.asm, frame, &|_| true)?;
        series.finish()?;
        let secs = t.elapsed().as_secs_f64();
        let bytes = std::fs::metadata(dir.join(sub).join("train_bridge_00000.vtu"))?.len();
        println!(
            "{sub:>6}: {n} points, {:.1} MiB, written in {secs:.2} s",
            bytes as f64 / (1024.0 * 1024.0)
        );
    }
    Ok(())
}

//! `railfem-measure export DIR`: the benchmark beam of `railfem bench` ([`railfem::bench`])
//! written out for another code to rebuild and rerun (`scripts/opensees_compare.sh`), with
//! railfem's answer and its own timing, one directory per size.

use railfem::bench::{BenchBeam, BenchMass, DT, SPAN, SPEED};
use railfem::framework::{Dof, FemError};
use railfem::solvers::Driver;
use serde_json::json;
use std::path::Path;
use std::time::Instant;

/// Node ids whose vertical displacement the export records: the midspan of the first span
/// and of the second (when there is one).
pub fn monitor_nodes(geo: &BenchBeam) -> Vec<u64> {
    let half = (geo.elements_per_span / 2) as u64;
    let mut v = vec![half + 1];
    if geo.spans > 1 {
        v.push(geo.elements_per_span as u64 + half + 1);
    }
    v
}

/// What the export measured for one size.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ExportRow {
    /// Equations.
    pub equations: usize,
    /// Steps run.
    pub steps: usize,
    /// The first step, which includes the one factorization of `K_eff` (s).
    pub first_step: f64,
    /// Mean wall time of steps 2..=N (s).
    pub per_step: f64,
}

/// Runs the benchmark beam of `target` DOF for `steps` steps
/// and writes, into `dir`, everything another code needs to rebuild and rerun the same
/// problem, plus railfem's answer:
///
/// - `model.json`: section, material, the Newmark settings, `dt`, `steps`, the monitored
///   nodes, the mass matrix (`mass_kind`: `consistent` or `lumped`) and the conventions
///   (local axes, mass matrix) in words;
/// - `nodes.csv`: `id,x,y,z,fixed` (`fixed` lists the held DOFs, e.g. `uy uz`);
/// - `elements.csv`: `id,node_i,node_j`;
/// - `loads.csv`: `step,t,node,dof,value`, every non-zero entry of the external force
///   vector the driver used at the end of each step (the consistent nodal forces of the
///   moving force), so the other code applies the identical load vector;
/// - `railfem.csv`: `step,t,uz_<node>...`, the monitored vertical displacements (m);
/// - every CSV header carries its units in brackets (`x [m]`, `uz_<node> [m]`), as the
///   other outputs do;
/// - `timing.json`: equations, the first step (which factors `K_eff` once) and the mean
///   wall time of the other steps.
pub fn export(
    target: usize,
    steps: usize,
    mass: BenchMass,
    dir: &Path,
) -> Result<ExportRow, FemError> {
    use std::fmt::Write as _;
    let geo = BenchBeam {
        mass,
        ..BenchBeam::for_dof(target)
    };
    let model = geo.model(steps)?;
    std::fs::create_dir_all(dir).map_err(|e| FemError::output(dir, e))?;
    let write = |name: &str, text: &str| {
        let p = dir.join(name);
        std::fs::write(&p, text).map_err(|e| FemError::output(&p, e))
    };
    let mut nodes = String::from("id [-],x [m],y [m],z [m],fixed [-]\n");
    for n in &model.nodes {
        let fixed: Vec<&str> = n.fixed.iter().map(|d| d.name()).collect();
        let _ = writeln!(
            nodes,
            "{},{:.17e},{:.17e},{:.17e},{}",
            n.id,
            n.position.x,
            n.position.y,
            n.position.z,
            fixed.join(" ")
        );
    }
    write("nodes.csv", &nodes)?;
    let mut elems = String::from("id [-],node_i [-],node_j [-]\n");
    for e in &model.elements {
        let c = e.element.connectivity();
        let _ = writeln!(
            elems,
            "{},{},{}",
            e.id, model.nodes[c[0].node].id, model.nodes[c[1].node].id
        );
    }
    write("elements.csv", &elems)?;
    let monitors = monitor_nodes(&geo);
    let spec = json!({
        "spans": geo.spans, "elements_per_span": geo.elements_per_span, "span": SPAN,
        "E": 2.1e11, "G": 8.1e10, "A": 7.686e-3, "Iy": 3.038e-5, "Iz": 5.123e-6, "J": 2.0e-6,
        "rho": 7850.0, "mass": mass.describe(), "mass_kind": mass.name(),
        "local_axes": "x along the beam (global X); local z = global Z (vecxz = [0,0,1]); Iy is vertical bending",
        "integrator": "newmark", "beta": 0.25, "gamma": 0.5, "dt": DT, "steps": steps,
        "speed": SPEED, "force_z": -1.0e5, "monitor_nodes": monitors, "equations": geo.equations(),
    });
    write(
        "model.json",
        &serde_json::to_string_pretty(&spec).unwrap_or_default(),
    )?;
    let mut d = Driver::new(model)?;
    d.initialize()?;
    let mon: Vec<usize> = monitors.iter().filter_map(|&id| d.model.node(id)).collect();
    let mut loads = String::from("step [-],t [s],node [-],dof [-],value [N or N·m]\n");
    let mut hist = String::from("step [-],t [s]");
    for id in &monitors {
        let _ = write!(hist, ",uz_{id} [m]");
    }
    hist.push('\n');
    let (mut first_step, mut rest) = (0.0, 0.0);
    for k in 1..=steps {
        railfem::framework::interrupt::check(d.state.t)?;
        let t0 = Instant::now();
        d.step(DT)?;
        let el = t0.elapsed().as_secs_f64();
        if k == 1 {
            first_step = el;
        } else {
            rest += el;
        }
        let t = d.state.t;
        for (eq, f) in d.state.f_ext.iter().enumerate() {
            if *f != 0.0 {
                let (n, dof) = d.asm.dofmap.dof_of(eq);
                let _ = writeln!(
                    loads,
                    "{k},{t:.17e},{},{},{f:.17e}",
                    d.model.nodes[n].id,
                    dof.name()
                );
            }
        }
        let _ = write!(hist, "{k},{t:.17e}");
        for &n in &mon {
            let _ = write!(hist, ",{:.17e}", d.asm.dofmap.value(&d.state.q, n, Dof::Uz));
        }
        hist.push('\n');
    }
    write("loads.csv", &loads)?;
    write("railfem.csv", &hist)?;
    let row = ExportRow {
        equations: d.neq(),
        steps,
        first_step,
        per_step: rest / (steps.max(2) - 1) as f64,
    };
    let timing = json!({"equations": row.equations, "steps": steps,
        "first_step_s": first_step, "per_step_s": row.per_step,
        "threads": "railfem's driver factors and solves single-threaded (faer Par::Seq); assembly is serial"});
    write(
        "timing.json",
        &serde_json::to_string_pretty(&timing).unwrap_or_default(),
    )?;
    Ok(row)
}

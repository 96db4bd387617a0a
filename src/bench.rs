//! `railfem bench`: how a linear transient run scales with the number of equations.
//!
//! The benchmark model is a long continuous beam of `beam3d` elements (six DOF per node,
//! consistent or lumped mass ([`BenchMass`]), 60E1-like steel rail section) on pin supports every [`SPAN`] m, with
//! [`ELEMENTS_PER_SPAN`] elements per span, crossed by a `moving_force`. It is integrated
//! with average-acceleration Newmark (β = ¼, γ = ½) at a constant step, so the effective
//! tangent is factored once and every later step is one assembly of the residual and one
//! pair of triangular solves.
//!
//! Per size the report gives: equations, non-zeros of K, the model build and driver set-up
//! times, the time per step split into the driver's phases (assembly, factorization,
//! solve, loads), the factorizations the driver performed, the time of one forced full
//! factorization (symbolic + numeric), of one numeric refactorization plus solve, and the
//! process's peak resident memory (`VmHWM`) after the size ran. Timings are wall-clock and
//! depend on what else the machine is doing; nothing here asserts them.

use crate::framework::builder::ModelBuilder;
use crate::framework::loads::LoadSpec;
use crate::framework::model::{AnalysisSpec, IntegratorKind};
use crate::framework::{Dof, DofSet, FemError, Model};
use crate::solvers::linear::solver_for;
use crate::solvers::Driver;
use serde_json::json;
use std::path::Path;
use std::time::Instant;

/// Span between supports (m).
pub const SPAN: f64 = 25.0;
/// Beam elements per span.
pub const ELEMENTS_PER_SPAN: usize = 10;
/// Time step of the benchmark run (s).
pub const DT: f64 = 2.0e-3;
/// Speed of the moving force (m/s).
pub const SPEED: f64 = 80.0;

/// The mass matrix of the benchmark beam (`railfem bench --mass`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum BenchMass {
    /// `beam3d` `mass = "consistent"`: cubic Hermite bending mass, as OpenSees'
    /// `elasticBeamColumn ... -cMass`.
    #[default]
    Consistent,
    /// `beam3d` `mass = "lumped_translational"`: `ρAL/2` per node and translation, no
    /// rotary inertia, as OpenSees' `elasticBeamColumn` without `-cMass` (its default).
    Lumped,
}

impl BenchMass {
    /// The name on the command line and in `model.json` (`mass_kind`).
    pub fn name(self) -> &'static str {
        match self {
            BenchMass::Consistent => "consistent",
            BenchMass::Lumped => "lumped",
        }
    }

    /// The `beam3d` `mass` value that gives this matrix.
    pub fn beam3d_mass(self) -> &'static str {
        match self {
            BenchMass::Consistent => "consistent",
            BenchMass::Lumped => "lumped_translational",
        }
    }

    /// The matrix in words, for `model.json`.
    fn describe(self) -> &'static str {
        match self {
            BenchMass::Consistent => {
                "consistent (cubic Hermite bending, linear axial; torsion rho*(Iy+Iz))"
            }
            BenchMass::Lumped => {
                "lumped, translations only: rho*A*L/2 per node and translation, no rotary inertia (OpenSees elasticBeamColumn without -cMass)"
            }
        }
    }
}

/// Geometry of a benchmark beam.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct BenchBeam {
    /// Number of spans.
    pub spans: usize,
    /// Elements per span.
    pub elements_per_span: usize,
    /// Mass matrix.
    pub mass: BenchMass,
}

impl BenchBeam {
    /// The beam whose equation count is closest to `dof` (at least one span).
    pub fn for_dof(dof: usize) -> BenchBeam {
        let per_span = Self::equations_per_span(ELEMENTS_PER_SPAN);
        let spans = ((dof.saturating_sub(2) as f64) / per_span as f64).round() as usize;
        BenchBeam {
            spans: spans.max(1),
            elements_per_span: ELEMENTS_PER_SPAN,
            mass: BenchMass::Consistent,
        }
    }

    fn equations_per_span(elements_per_span: usize) -> usize {
        // Each span adds `elements_per_span` nodes of 6 DOF; its end support fixes uy, uz.
        6 * elements_per_span - 2
    }

    /// Number of nodes.
    pub fn nodes(&self) -> usize {
        self.spans * self.elements_per_span + 1
    }

    /// Number of elements.
    pub fn elements(&self) -> usize {
        self.spans * self.elements_per_span
    }

    /// Equations: six per node, less ux, uy, uz, rx at the first support and uy, uz at each
    /// of the other `spans` supports.
    pub fn equations(&self) -> usize {
        6 * self.nodes() - 4 - 2 * self.spans
    }

    /// Length (m).
    pub fn length(&self) -> f64 {
        self.spans as f64 * SPAN
    }

    /// Adds the beam's nodes (with their supports) and `beam3d` elements to `b`: node `i + 1`
    /// at `x = i·h`, element `e` from node `e` to `e + 1`.
    pub fn add_beam(&self, b: &mut ModelBuilder) {
        let h = SPAN / self.elements_per_span as f64;
        let first = DofSet::of(&[Dof::Ux, Dof::Uy, Dof::Uz, Dof::Rx]);
        let pin = DofSet::of(&[Dof::Uy, Dof::Uz]);
        for i in 0..self.nodes() {
            let x = [i as f64 * h, 0.0, 0.0];
            let id = i as u64 + 1;
            if i == 0 {
                b.node_fixed(id, x, first);
            } else if i % self.elements_per_span == 0 {
                b.node_fixed(id, x, pin);
            } else {
                b.node(id, x);
            }
        }
        let beam = json!({"E": 2.1e11, "G": 8.1e10, "A": 7.686e-3, "Iy": 3.038e-5,
                          "Iz": 5.123e-6, "J": 2.0e-6, "rho": 7850.0,
                          "mass": self.mass.beam3d_mass()});
        for e in 1..=self.elements() as u64 {
            b.element("beam3d", e, &[e, e + 1], &beam);
        }
    }

    /// The model: nodes along global x, beams, the moving force (entering at x = 0 just
    /// after t = 0, so there is no initial static solve) and the Newmark analysis.
    pub fn model(&self, steps: usize) -> Result<Model, FemError> {
        let mut b = ModelBuilder::new(format!("bench ({} spans)", self.spans));
        self.add_beam(&mut b);
        b.load(LoadSpec::MovingForce {
            elements: (1..=self.elements() as u64).collect(),
            force: [0.0, 0.0, -1.0e5],
            speed: SPEED,
            start: -0.5 * SPEED * DT,
        });
        b.analysis(AnalysisSpec {
            integrator: IntegratorKind::Newmark,
            beta: 0.25,
            gamma: 0.5,
            dt: DT,
            duration: DT * steps.max(1) as f64,
            initial_static: false,
            ..Default::default()
        });
        b.build()
    }
}

/// Results of one size.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct BenchRow {
    /// Requested DOF count.
    pub target: usize,
    /// Equations of the model.
    pub equations: usize,
    /// Non-zeros of K (full pattern as stored).
    pub nnz_k: usize,
    /// Nodes, elements.
    pub nodes: usize,
    /// Elements.
    pub elements: usize,
    /// Steps run.
    pub steps: usize,
    /// ModelBuilder + build (s).
    pub build: f64,
    /// `Driver::new`: numbering, pattern, constant matrices (s).
    pub setup: f64,
    /// `Driver::initialize`: initial acceleration, one factorization of M (s).
    pub init: f64,
    /// Wall time per step (s).
    pub per_step: f64,
    /// Per step: assembly (s).
    pub assembly: f64,
    /// Per step: factorization (s).
    pub factor: f64,
    /// Per step: triangular solves (s).
    pub solve: f64,
    /// Per step: loads (s).
    pub loads: f64,
    /// Factorizations performed by the driver.
    pub factorizations: usize,
    /// Symbolic analyses performed by the driver's solver.
    pub symbolic: usize,
    /// One forced factorization of K_eff from scratch, symbolic + numeric (s).
    pub full_factor: f64,
    /// One numeric refactorization of K_eff plus one solve (s).
    pub refactor_solve: f64,
    /// Peak resident memory of the process after this size (MiB).
    pub peak_mib: f64,
}

/// `VmHWM` from `/proc/self/status` (MiB), if readable.
pub fn peak_memory_mib() -> Option<f64> {
    status_mib("VmHWM:")
}

/// `VmRSS` (resident memory now) from `/proc/self/status` (MiB), if readable.
pub fn resident_memory_mib() -> Option<f64> {
    status_mib("VmRSS:")
}

/// A `kB` line of `/proc/self/status` in MiB.
fn status_mib(key: &str) -> Option<f64> {
    let s = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = s.lines().find(|l| l.starts_with(key))?;
    let kb: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb / 1024.0)
}

/// Runs one size.
pub fn run_size(target: usize, steps: usize, mass: BenchMass) -> Result<BenchRow, FemError> {
    let geo = BenchBeam {
        mass,
        ..BenchBeam::for_dof(target)
    };
    let t0 = Instant::now();
    let model = geo.model(steps)?;
    let build = t0.elapsed().as_secs_f64();
    let t0 = Instant::now();
    let mut d = Driver::new(model)?;
    let setup = t0.elapsed().as_secs_f64();
    let t0 = Instant::now();
    d.initialize()?;
    let init = t0.elapsed().as_secs_f64();
    let t0 = Instant::now();
    for _ in 0..steps {
        crate::framework::interrupt::check(d.state.t)?;
        d.step(DT)?;
    }
    let wall = t0.elapsed().as_secs_f64();
    let n = steps.max(1) as f64;
    let tm = d.summary.timings;

    // A forced factorization of the same K_eff with a fresh solver (symbolic + numeric),
    // then a numeric refactorization and one solve with that solver.
    let coef = d.integrator.coefficients(DT);
    let mut k_eff = d.asm.k_const.zeros_like();
    d.asm.effective(coef, &mut k_eff);
    let mut solver = solver_for(d.asm.symmetric());
    let singular = |e| FemError::Singular(format!("bench: {e}"));
    let t0 = Instant::now();
    solver.factor(&k_eff).map_err(singular)?;
    let full_factor = t0.elapsed().as_secs_f64();
    let mut b = d.state.f_ext.clone();
    let t0 = Instant::now();
    solver.factor(&k_eff).map_err(singular)?;
    solver.solve_in_place(&mut b).map_err(singular)?;
    let refactor_solve = t0.elapsed().as_secs_f64();

    Ok(BenchRow {
        target,
        equations: d.neq(),
        nnz_k: d.asm.k_const.nnz(),
        nodes: geo.nodes(),
        elements: geo.elements(),
        steps,
        build,
        setup,
        init,
        per_step: wall / n,
        assembly: tm.assembly / n,
        factor: tm.factor / n,
        solve: tm.solve / n,
        loads: tm.loads / n,
        factorizations: d.summary.factorizations,
        symbolic: d.solver_stats().symbolic_analyses,
        full_factor,
        refactor_solve,
        peak_mib: peak_memory_mib().unwrap_or(f64::NAN),
    })
}

/// Least-squares slope of `ln y` against `ln x` (the growth exponent), if at least two
/// points with positive values.
pub fn loglog_slope(points: &[(f64, f64)]) -> Option<f64> {
    let p: Vec<(f64, f64)> = points
        .iter()
        .filter(|(x, y)| *x > 0.0 && *y > 0.0)
        .map(|(x, y)| (x.ln(), y.ln()))
        .collect();
    if p.len() < 2 {
        return None;
    }
    let m = p.len() as f64;
    let (sx, sy) = p.iter().fold((0.0, 0.0), |a, (x, y)| (a.0 + x, a.1 + y));
    let (mx, my) = (sx / m, sy / m);
    let sxy: f64 = p.iter().map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = p.iter().map(|(x, _)| (x - mx) * (x - mx)).sum();
    (sxx > 0.0).then(|| sxy / sxx)
}

fn ms(s: f64) -> String {
    format!("{:.3}", s * 1e3)
}

/// The results as a markdown table.
pub fn markdown(rows: &[BenchRow]) -> String {
    let mut s = String::from(
        "| target DOF | equations | nnz(K) | build (s) | setup (s) | init (s) | step (ms) | assembly (ms/step) | factor (ms/step) | solve (ms/step) | loads (ms/step) | factorizations | full factor (ms) | refactor + solve (ms) | VmHWM (MiB) |\n\
         |---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n",
    );
    for r in rows {
        s.push_str(&format!(
            "| {:.0e} | {} | {} | {:.3} | {:.3} | {:.3} | {} | {} | {} | {} | {} | {} | {} | {} | {:.0} |\n",
            r.target as f64,
            r.equations,
            r.nnz_k,
            r.build,
            r.setup,
            r.init,
            ms(r.per_step),
            ms(r.assembly),
            ms(r.factor),
            ms(r.solve),
            ms(r.loads),
            r.factorizations,
            ms(r.full_factor),
            ms(r.refactor_solve),
            r.peak_mib
        ));
    }
    s
}

/// The results as CSV (times in s, memory in MiB).
pub fn csv(rows: &[BenchRow]) -> String {
    let mut s = String::from(
        "target_dof [-],equations [-],nnz_k [-],nodes [-],elements [-],steps [-],build [s],setup [s],init [s],step [s],assembly_per_step [s],factor_per_step [s],solve_per_step [s],loads_per_step [s],factorizations [-],symbolic [-],full_factor [s],refactor_solve [s],vmhwm [MiB]\n",
    );
    for r in rows {
        s.push_str(&format!(
            "{},{},{},{},{},{},{:.6e},{:.6e},{:.6e},{:.6e},{:.6e},{:.6e},{:.6e},{:.6e},{},{},{:.6e},{:.6e},{:.1}\n",
            r.target,
            r.equations,
            r.nnz_k,
            r.nodes,
            r.elements,
            r.steps,
            r.build,
            r.setup,
            r.init,
            r.per_step,
            r.assembly,
            r.factor,
            r.solve,
            r.loads,
            r.factorizations,
            r.symbolic,
            r.full_factor,
            r.refactor_solve,
            r.peak_mib
        ));
    }
    s
}

/// Runs every size, prints the table and writes `bench.md` and `bench.csv` into `out`.
pub fn run(
    sizes: &[usize],
    steps: usize,
    mass: BenchMass,
    out: &Path,
) -> Result<Vec<BenchRow>, FemError> {
    let load = std::fs::read_to_string("/proc/loadavg").unwrap_or_default();
    eprintln!("load average at start: {}", load.trim());
    let mut rows = Vec::new();
    let mut bar = crate::progress::Progress::new("bench", sizes.len() as u64, "sizes");
    // A stop request between sizes, or inside one (that size is dropped: a timing of part
    // of its steps is not comparable), writes the sizes done and returns InterruptedAfter.
    let mut stopped = false;
    for &n in sizes {
        if crate::framework::interrupt::requested() {
            stopped = true;
            break;
        }
        bar.note(&format!("bench: {n} DOF, {steps} steps ..."));
        let r = match run_size(n, steps, mass) {
            Err(FemError::Interrupted { .. }) => {
                stopped = true;
                break;
            }
            r => r?,
        };
        bar.note(&format!(
            "bench: {} equations, {:.3} ms/step, peak {:.0} MiB",
            r.equations,
            r.per_step * 1e3,
            r.peak_mib
        ));
        rows.push(r);
        bar.set(rows.len() as u64);
    }
    bar.finish();
    let mut md = markdown(&rows);
    let pts: Vec<(f64, f64)> = rows
        .iter()
        .map(|r| (r.equations as f64, r.per_step))
        .collect();
    if let Some(p) = loglog_slope(&pts) {
        md.push_str(&format!(
            "\nTime per step grows as DOF^{p:.3} (least squares on log–log over {} sizes).\n",
            rows.len()
        ));
    }
    let load = std::fs::read_to_string("/proc/loadavg").unwrap_or_default();
    md.push_str(&format!(
        "\n{steps} steps of dt = {DT} s per size, {} mass; VmHWM is the peak of the whole process so far. Load average at the end: {}\n",
        mass.name(),
        load.trim()
    ));
    print!("{md}");
    std::fs::create_dir_all(out).map_err(|e| FemError::output(out, e))?;
    let p = out.join("bench.md");
    std::fs::write(&p, &md).map_err(|e| FemError::output(&p, e))?;
    let p = out.join("bench.csv");
    std::fs::write(&p, csv(&rows)).map_err(|e| FemError::output(&p, e))?;
    if stopped {
        return Err(FemError::InterruptedAfter {
            after: format!("{} of {} sizes", rows.len(), sizes.len()),
        });
    }
    Ok(rows)
}

/// Node ids whose vertical displacement `--export` records: the midspan of the first span
/// and of the second (when there is one).
pub fn monitor_nodes(geo: &BenchBeam) -> Vec<u64> {
    let half = (geo.elements_per_span / 2) as u64;
    let mut v = vec![half + 1];
    if geo.spans > 1 {
        v.push(geo.elements_per_span as u64 + half + 1);
    }
    v
}

/// What `--export` measured for one size.
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

/// `railfem bench --export DIR`: runs the benchmark beam of `target` DOF for `steps` steps
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
        crate::framework::interrupt::check(d.state.t)?;
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tiny_bench_beam_has_closed_form_equation_count() {
        for spans in [1, 2, 3] {
            let geo = BenchBeam {
                spans,
                elements_per_span: 4,
                mass: BenchMass::Consistent,
            };
            // nodes = 4·spans + 1; 6 DOF each, less 4 at the first support and 2 at each
            // of the `spans` other supports.
            let nodes = 4 * spans + 1;
            let want = 6 * nodes - 4 - 2 * spans;
            assert_eq!(geo.nodes(), nodes);
            assert_eq!(geo.equations(), want);
            let d = Driver::new(geo.model(2).expect("model")).expect("driver");
            assert_eq!(d.neq(), want, "{spans} spans");
            assert_eq!(d.model.nodes.len(), nodes);
            assert_eq!(d.model.elements.len(), 4 * spans);
        }
        let geo = BenchBeam::for_dof(10_000);
        assert_eq!(geo.equations(), 58 * geo.spans + 2);
        assert!((geo.equations() as i64 - 10_000).abs() <= 29);
    }

    #[test]
    fn tiny_bench_runs_linear_with_one_factorization() {
        let geo = BenchBeam {
            spans: 3,
            elements_per_span: ELEMENTS_PER_SPAN,
            mass: BenchMass::Consistent,
        };
        let mut d = Driver::new(geo.model(3).expect("model")).expect("driver");
        for _ in 0..3 {
            d.step(DT).expect("step");
        }
        assert_eq!(d.summary.factorizations, 1);
    }

    #[test]
    fn loglog_slope_of_a_power_law() {
        let pts: Vec<(f64, f64)> = [1e2, 1e3, 1e4]
            .iter()
            .map(|&x: &f64| (x, 3.0 * x.powf(1.25)))
            .collect();
        assert!((loglog_slope(&pts).unwrap() - 1.25).abs() < 1e-12);
    }
}

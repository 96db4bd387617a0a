//! `railfem-measure window-front` and `far-field-front`: run time against error of the
//! train–bridge model with the activity window (`railfem train-bridge --window on`, no
//! ground motion) or the reduced far field (`--far-field reduced`, under the synthetic
//! record) beside full runs of the same scene, on a case long enough for either to leave
//! blocks out: 3 carriages started in the middle of 30 spans, the partitioned solver's
//! blocks of 500 equations (about a fifth of a span; the reduced far field cuts its
//! blocks at span joints, one span a block).
//!
//! Full runs at a few (element length, Δt) and windowed or reduced runs at several reaches
//! and steps are each compared with the finest full run of the set (the smallest element
//! length, then the smallest step), over the reference's samples: each run's
//! `wheels.csv` and `midspan.csv` linearly interpolated at the reference's sample times
//! ([`resample`]; the interpolation error, `≤ Δt²/8·max|ẍ|`, is part of what a user
//! sampling at Δt sees, so it is counted), then `railfem::window_error::difference_where`:
//! the largest |difference| of `Q`, of `ΔQ/Q` over every wheel and sample, and of every
//! span's midspan deflection `w − w(0)`, each against the largest |value| of the quantity
//! in the reference, from [`SETTLE`] on. Each run's wall and CPU time (the process's, every thread's) cover building
//! the model, the static solve (and the far field's reductions), every step and writing its
//! CSV files.
//!
//! Output: `window-front.csv` and `window-front.svg`, or `far-field-front.csv` and
//! `far-field-front.svg` (one row per run; error against CPU time, full runs and windowed
//! or reduced runs as their own points, one panel per quantity).

use railfem::far_field::{FarFieldChoice, FarFieldOptions};
use railfem::framework::plot::{Corner, Figure, Panel, Series, Style};
use railfem::framework::FemError;
use railfem::solvers::partition::PartitionOptions;
use railfem::train_bridge::{build, run, Quake, TrainBridgeCase};
use railfem::train_window::{WindowChoice, WindowOptions};
use railfem::window_error::{difference_where, read_columns, Columns};
use std::path::Path;
use std::time::Instant;

/// Carriages of the case.
pub const CARS: usize = 3;
/// Spans of the case.
pub const SPANS: usize = 30;
/// Station of the front carriage's centre at t = 0 from the first abutment (m): the train
/// on spans 13 to 16, from the static equilibrium under it, so that blocks are held ahead
/// of it and, once rung down, behind it: both abutments stay more than three times the
/// largest reach (120 m) from the train, so the structure's ends
/// (`railfem_solvers::window`) keep nothing active that the reach would hold.
pub const TRAIN_START: f64 = 450.0;
/// Simulated time of every run (s): the train moves on by 48 m.
pub const DURATION: f64 = 0.6;
/// Interior equations per block of the partitioned solver.
pub const BLOCK_SIZE: usize = 500;

/// What the scene has, and so what leaves blocks out of a run.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Scene {
    /// No ground motion: the activity window holds the blocks out of reach.
    Still,
    /// The synthetic record (`--quake synthetic`: Kanai–Tajimi, seed 1, 0.3 g horizontal,
    /// 0.2 g vertical): the reduced far field runs the blocks out of reach in
    /// Craig–Bampton form.
    Quake,
}

impl Scene {
    /// The stem of the output files.
    pub fn stem(self) -> &'static str {
        match self {
            Scene::Still => "window-front",
            Scene::Quake => "far-field-front",
        }
    }

    /// What a run with a reach is called (run names, CSV, legend).
    fn method(self) -> &'static str {
        match self {
            Scene::Still => "window",
            Scene::Quake => "reduced",
        }
    }
}

/// One run of the set: the scene, element length (m), time step (s) and the window's or
/// the far field's reach (m; `None`: the full model).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RunSpec {
    /// The scene.
    pub scene: Scene,
    /// Rail, slab and girder element length (m).
    pub h: f64,
    /// Time step (s).
    pub dt: f64,
    /// The window's or the far field's reach (m), or the full model.
    pub reach: Option<f64>,
}

impl RunSpec {
    /// The directory name of the run's outputs.
    fn name(&self) -> String {
        match self.reach {
            None => format!("full-h{}-dt{}", self.h, self.dt),
            Some(d) => format!("{}{d}-h{}-dt{}", self.scene.method(), self.h, self.dt),
        }
    }

    /// The train–bridge case of the run.
    pub fn case(&self) -> TrainBridgeCase {
        TrainBridgeCase {
            cars: CARS,
            spans: SPANS,
            dt: self.dt,
            element_length: self.h,
            duration: Some(DURATION),
            train_start: TRAIN_START,
            midspans: (1..=SPANS).collect(),
            solver: railfem::framework::model::SolverChoice::Partitioned,
            window: match (self.scene, self.reach) {
                (Scene::Still, Some(d)) => WindowChoice::On(WindowOptions {
                    ahead: Some(d),
                    tolerance: None,
                }),
                _ => WindowChoice::Off,
            },
            quake: match self.scene {
                Scene::Still => Quake::None,
                Scene::Quake => Quake::Synthetic {
                    seed: 1,
                    pga: 0.3,
                    duration: 30.0,
                },
            },
            far_field: match (self.scene, self.reach) {
                (Scene::Quake, Some(d)) => FarFieldChoice::Reduced(FarFieldOptions {
                    cutoff_hz: None,
                    reach: Some(d),
                }),
                _ => FarFieldChoice::Full,
            },
            ..Default::default()
        }
    }
}

/// The default set of a scene: full runs at four steps on the 0.625 m mesh and at three on
/// the 0.3125 m mesh (the finest, at 0.25 ms, is the reference), windowed or reduced runs
/// at reaches of 30, 60 and 120 m at three steps on the 0.625 m mesh.
pub fn default_set(scene: Scene) -> Vec<RunSpec> {
    let mut set = Vec::new();
    for (h, dt) in [
        (0.625, 2e-3),
        (0.625, 1e-3),
        (0.625, 5e-4),
        (0.625, 2.5e-4),
        (0.3125, 1e-3),
        (0.3125, 5e-4),
        (0.3125, 2.5e-4),
    ] {
        set.push(RunSpec {
            scene,
            h,
            dt,
            reach: None,
        });
    }
    for dt in [1e-3, 5e-4, 2.5e-4] {
        for d in [30.0, 60.0, 120.0] {
            set.push(RunSpec {
                scene,
                h: 0.625,
                dt,
                reach: Some(d),
            });
        }
    }
    set
}

/// What one run cost and what the window held.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Cost {
    /// Equations.
    pub dofs: usize,
    /// Steps.
    pub steps: usize,
    /// Wall time (s).
    pub wall: f64,
    /// CPU time of the process over the same (s).
    pub cpu: f64,
    /// Fraction of the block-steps held by the window or reduced by the far field (0 for a
    /// full run).
    pub held: f64,
}

/// Runs `r`, its outputs into `dir`.
pub fn run_one(r: &RunSpec, dir: &Path) -> Result<Cost, FemError> {
    let case = r.case();
    let (t0, c0) = (Instant::now(), railfem::cpu_time::process_seconds());
    let mut m = build(&case)?;
    m.driver.set_partition_options(PartitionOptions {
        block_size: BLOCK_SIZE,
        threads: 0,
        ..Default::default()
    });
    let report = run(&mut m, &case, None, Some(dir))?;
    let held = match (report.window, report.far_field) {
        (Some(w), _) => w.held_block_steps as f64 / w.block_steps.max(1) as f64,
        (None, Some(f)) => f.reduced_block_steps as f64 / f.block_steps.max(1) as f64,
        (None, None) => 0.0,
    };
    Ok(Cost {
        dofs: m.dofs,
        steps: report.steps,
        wall: t0.elapsed().as_secs_f64(),
        cpu: railfem::cpu_time::process_seconds() - c0,
        held,
    })
}

/// `c`'s columns linearly interpolated at `times` (column 0, the time, becomes `times`);
/// a time outside `c`'s samples takes the nearest end's value.
pub fn resample(c: &Columns, times: &[f64]) -> Columns {
    let t = &c.cols[0];
    let at = |col: &[f64], x: f64| -> f64 {
        let n = t.len();
        if x <= t[0] {
            return col[0];
        }
        if x >= t[n - 1] {
            return col[n - 1];
        }
        let i = t.partition_point(|v| *v <= x).clamp(1, n - 1);
        let f = (x - t[i - 1]) / (t[i] - t[i - 1]);
        col[i - 1] * (1.0 - f) + col[i] * f
    };
    let mut cols = vec![times.to_vec()];
    for col in &c.cols[1..] {
        cols.push(times.iter().map(|&x| at(col, x)).collect());
    }
    Columns {
        head: c.head.clone(),
        cols,
    }
}

/// Errors are measured from this time on (s): the run starts from the static
/// equilibrium with the train already at speed, and the jump sets every wheel's penalty
/// spring ringing at about 500 Hz, an artefact of the start
/// ([`railfem::pareto_train::SETTLE`]). The deflection's `w(0)` is still the first sample.
pub const SETTLE: f64 = railfem::pareto_train::SETTLE;

/// The errors of a run against the reference over the reference's samples from `from`
/// (s): `[Q, ΔQ/Q, w]`, each the largest |difference| against the reference's largest
/// |value| over the same samples (module documentation). `wheels` and `midspan` are
/// `[reference, run]`.
pub fn errors(
    wheels: [&Columns; 2],
    midspan: [&Columns; 2],
    from: f64,
) -> Result<[f64; 3], FemError> {
    let w = resample(wheels[1], &wheels[0].cols[0]);
    let m = resample(midspan[1], &midspan[0].cols[0]);
    let (nw, nm) = (wheels[0].cols[0].len(), midspan[0].cols[0].len());
    let (tw, tm) = (&wheels[0].cols[0], &midspan[0].cols[0]);
    let (kw, km) = (
        |_: usize, k: usize| tw[k] >= from,
        |_: usize, k: usize| tm[k] >= from,
    );
    Ok([
        difference_where(wheels[0], &w, "_Q [N]", false, nw, &kw)?.relative(),
        difference_where(wheels[0], &w, "_dQQ [-]", false, nw, &kw)?.relative(),
        difference_where(midspan[0], &m, " [m]", true, nm, &km)?.relative(),
    ])
}

/// One row of the set: the run, its cost and its errors.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Point {
    /// The run.
    pub spec: RunSpec,
    /// Its cost.
    pub cost: Cost,
    /// `[Q, ΔQ/Q, w]` errors against the reference (-).
    pub errors: [f64; 3],
    /// A windowed or reduced run's `[Q, ΔQ/Q, w]` errors against the full run at its element
    /// length and step: the window's or reduction's own error (`None`: a full run, or no
    /// such full run in the set).
    pub window_errors: Option<[f64; 3]>,
}

/// The rows as CSV (units in the header; reach 0 for a full run, and its own errors 0).
/// `held` and `Q_window`… for the window, `reduced` and `Q_reduced`… for the far field.
pub fn csv(scene: Scene, points: &[Point]) -> String {
    let (share, own) = match scene {
        Scene::Still => ("held", "window"),
        Scene::Quake => ("reduced", "reduced"),
    };
    let mut s = format!(
        "run [-],element_length [m],dt [s],reach [m],DOF [-],steps [-],wall [s],cpu [s],{share} [-],Q_error [-],dQQ_error [-],w_error [-],Q_{own} [-],dQQ_{own} [-],w_{own} [-]\n",
    );
    for p in points {
        let [eq, edqq, ew] = p.errors;
        let [wq, wdqq, ww] = p.window_errors.unwrap_or([0.0; 3]);
        s.push_str(&format!(
            "{},{},{},{},{},{},{:.3},{:.3},{:.4},{:.4e},{:.4e},{:.4e},{:.4e},{:.4e},{:.4e}\n",
            if p.spec.reach.is_some() {
                p.spec.scene.method()
            } else {
                "full"
            },
            p.spec.h,
            p.spec.dt,
            p.spec.reach.unwrap_or(0.0),
            p.cost.dofs,
            p.cost.steps,
            p.cost.wall,
            p.cost.cpu,
            p.cost.held,
            eq,
            edqq,
            ew,
            wq,
            wdqq,
            ww
        ));
    }
    s
}

/// Error against CPU time, log–log, one panel per quantity: the full runs as squares
/// (one colour per element length), the windowed or reduced runs as circles (one colour
/// per reach). Runs with a zero error (the reference) are left out of the log axes.
pub fn figure(scene: Scene, points: &[Point]) -> Figure {
    let (what, legend) = match scene {
        Scene::Still => ("full and windowed", "window"),
        Scene::Quake => ("synthetic record, full and reduced", "reduced far field"),
    };
    let quantities = [
        ("Q", "max |Q − Q_ref| / max |Q_ref| (-)"),
        ("ΔQ/Q", "max |ΔQ/Q − ref| / max |ΔQ/Q_ref| (-)"),
        ("midspan w", "max |w − w_ref| / max |w_ref| (-)"),
    ];
    let full_colors = ["#1f77b4", "#9467bd"];
    let window_colors = ["#ff7f0e", "#2ca02c", "#d62728", "#8c564b"];
    let mut fig = Figure::new();
    for (q, (name, ylabel)) in quantities.iter().enumerate() {
        let mut p = Panel::new(
            &format!(
                "train–bridge, {CARS} cars on {SPANS} spans, {DURATION} s: {name} error, {what}"
            ),
            "CPU time of the run (s)",
            ylabel,
        )
        .log_log();
        p.legend = Corner::TopRight;
        let mut groups: Vec<(String, Style, &str, Vec<&Point>)> = Vec::new();
        let mut meshes: Vec<f64> = Vec::new();
        let mut reaches: Vec<f64> = Vec::new();
        for pt in points.iter().filter(|p| p.errors[q] > 0.0) {
            match pt.spec.reach {
                None if !meshes.contains(&pt.spec.h) => meshes.push(pt.spec.h),
                Some(d) if !reaches.contains(&d) => reaches.push(d),
                _ => {}
            }
        }
        for (k, &h) in meshes.iter().enumerate() {
            let pts = points
                .iter()
                .filter(|p| p.spec.reach.is_none() && p.spec.h == h && p.errors[q] > 0.0)
                .collect();
            groups.push((
                format!("full, h = {h} m"),
                Style::Squares,
                full_colors[k % full_colors.len()],
                pts,
            ));
        }
        for (k, &d) in reaches.iter().enumerate() {
            let pts = points
                .iter()
                .filter(|p| p.spec.reach == Some(d) && p.errors[q] > 0.0)
                .collect();
            groups.push((
                format!("{legend}, reach {d} m"),
                Style::Markers,
                window_colors[k % window_colors.len()],
                pts,
            ));
        }
        for (label, style, color, pts) in groups {
            p = p.with(Series::new(
                &label,
                pts.iter().map(|r| r.cost.cpu).collect(),
                pts.iter().map(|r| r.errors[q]).collect(),
                style,
                color,
            ));
        }
        fig = fig.with(p);
    }
    fig
}

/// Runs `set` (one scene's; outputs in `out/runs/NAME`), compares each run with the finest
/// full run and writes `STEM.csv` and `STEM.svg` into `out` ([`Scene::stem`]). A run whose directory
/// already holds `summary.csv` is read, not run again (its cost from
/// `out/runs/NAME/cost.json`).
pub fn measure(set: &[RunSpec], out: &Path) -> Result<Vec<Point>, FemError> {
    let reference = set
        .iter()
        .filter(|r| r.reach.is_none())
        .min_by(|a, b| a.h.total_cmp(&b.h).then(a.dt.total_cmp(&b.dt)))
        .copied()
        .ok_or_else(|| {
            FemError::input(
                "command line",
                "--full: give at least one full run (the finest is the reference)",
            )
        })?;
    let dir_of = |r: &RunSpec| out.join("runs").join(r.name());
    let mut costs = Vec::new();
    for r in set {
        let dir = dir_of(r);
        let cost_file = dir.join("cost.json");
        let cost = match std::fs::read_to_string(&cost_file)
            .ok()
            .and_then(|t| serde_json::from_str::<serde_json::Value>(&t).ok())
        {
            Some(v) if dir.join("summary.csv").exists() => Cost {
                dofs: v["dofs"].as_u64().unwrap_or(0) as usize,
                steps: v["steps"].as_u64().unwrap_or(0) as usize,
                wall: v["wall"].as_f64().unwrap_or(f64::NAN),
                cpu: v["cpu"].as_f64().unwrap_or(f64::NAN),
                held: v["held"].as_f64().unwrap_or(0.0),
            },
            _ => {
                eprintln!("{}: {}", r.scene.stem(), r.name());
                let c = run_one(r, &dir)?;
                let v = serde_json::json!({"dofs": c.dofs, "steps": c.steps, "wall": c.wall, "cpu": c.cpu, "held": c.held});
                std::fs::write(&cost_file, v.to_string())
                    .map_err(|e| FemError::output(&cost_file, e))?;
                c
            }
        };
        costs.push(cost);
    }
    let read = |r: &RunSpec| -> Result<[Columns; 2], FemError> {
        let d = dir_of(r);
        Ok([
            read_columns(&d.join("wheels.csv"))?,
            read_columns(&d.join("midspan.csv"))?,
        ])
    };
    let [rw, rm] = read(&reference)?;
    let mut points = Vec::new();
    for (r, cost) in set.iter().zip(costs) {
        let [w, m] = read(r)?;
        let full = set
            .iter()
            .find(|f| f.reach.is_none() && f.h == r.h && f.dt == r.dt)
            .filter(|_| r.reach.is_some());
        let window_errors = match full {
            Some(f) => {
                let [fw, fm] = read(f)?;
                Some(errors([&fw, &w], [&fm, &m], SETTLE)?)
            }
            None => None,
        };
        points.push(Point {
            spec: *r,
            cost,
            errors: errors([&rw, &w], [&rm, &m], SETTLE)?,
            window_errors,
        });
    }
    let scene = reference.scene;
    let p = out.join(format!("{}.csv", scene.stem()));
    std::fs::write(&p, csv(scene, &points)).map_err(|e| FemError::output(&p, e))?;
    let p = out.join(format!("{}.svg", scene.stem()));
    figure(scene, &points)
        .write_svg(&p)
        .map_err(|e| FemError::output(&p, e))?;
    Ok(points)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn columns(head: &[&str], rows: &[&[f64]]) -> Columns {
        let cols = (0..head.len())
            .map(|j| rows.iter().map(|r| r[j]).collect())
            .collect();
        Columns {
            head: head.iter().map(|h| h.to_string()).collect(),
            cols,
        }
    }

    /// By hand: the reference samples every 1 s, the run every 2 s. At t = 1 the run's Q
    /// is interpolated halfway, (100 + 80)/2 = 90 against the reference's 92: the
    /// differences are 0, 2, 4 (at t = 2: 80 against 84), so the Q error is 4 over the
    /// reference's peak 100 = 0.04. ΔQ/Q: reference 0, 0.08, 0.16, run 0, 0.1, 0.2
    /// (interpolated at t = 1 to 0.1 against 0.08): largest 0.04 at t = 2, over the peak
    /// 0.16 = 0.25. Deflection from its first sample: reference 0, 1, 3 (from 5: 6, 8),
    /// run 0, 1 (interpolated), 2: largest 1 at t = 2, over the peak 3 = 1/3.
    #[test]
    fn errors_against_a_hand_computed_case() {
        let head = ["time [s]", "w1L_Q [N]", "w1L_dQQ [-]"];
        let rw = columns(
            &head,
            &[&[0.0, 100.0, 0.0], &[1.0, 92.0, 0.08], &[2.0, 84.0, 0.16]],
        );
        let w = columns(&head, &[&[0.0, 100.0, 0.0], &[2.0, 80.0, 0.2]]);
        let mhead = ["time [s]", "span1 [m]"];
        let rm = columns(&mhead, &[&[0.0, 5.0], &[1.0, 6.0], &[2.0, 8.0]]);
        let m = columns(&mhead, &[&[0.0, 4.0], &[2.0, 6.0]]);
        let [eq, edqq, ew] = errors([&rw, &w], [&rm, &m], 0.0).expect("same headers");
        assert!((eq - 0.04).abs() < 1e-15, "{eq}");
        assert!((edqq - 0.25).abs() < 1e-15, "{edqq}");
        assert!((ew - 1.0 / 3.0).abs() < 1e-15, "{ew}");
        // From t = 0.5 s the first sample is out: Q's peak is 92 (4/92), the others keep
        // theirs (ΔQ/Q's and w's peaks are at t = 2, w still from w(0)).
        let [eq, edqq, ew] = errors([&rw, &w], [&rm, &m], 0.5).expect("same headers");
        assert!((eq - 4.0 / 92.0).abs() < 1e-15, "{eq}");
        assert!((edqq - 0.25).abs() < 1e-15, "{edqq}");
        assert!((ew - 1.0 / 3.0).abs() < 1e-15, "{ew}");
    }

    /// Times outside the run's samples take the nearest end's value.
    #[test]
    fn resampling_holds_the_ends() {
        let c = columns(&["time [s]", "x [m]"], &[&[1.0, 10.0], &[3.0, 30.0]]);
        let r = resample(&c, &[0.0, 2.0, 4.0]);
        assert_eq!(r.cols[0], vec![0.0, 2.0, 4.0]);
        assert_eq!(r.cols[1], vec![10.0, 20.0, 30.0]);
    }
}

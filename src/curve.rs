//! The paper's Section 4 validation: a carriage on the five-segment curved, canted track,
//! finite elements against the simple theory (Eqs. 21–26).
//!
//! [`CurveCase`] holds the inputs (radius of the arc, cant constant Ct, speed, friction,
//! step, segment lengths); [`run`] builds the model — a rigid track (the theory assumes
//! rigid rails) and one `sks700` carriage carried at constant speed — runs it with Newmark
//! and Newton–Raphson, and compares every wheel's normal and shear force with both variants
//! of the theory at the wheel's own station (radius and cant there). The comparison on the
//! circular arc, once the entry transient has decayed, is the number the paper's Figure 6
//! shows. With `geometry = nonlinear` the carriage's bodies lean on their suspensions and
//! the wheel loads are also compared with the quasi-static reference with body lean
//! ([`crate::elements::rail::vehicle::lean`]).

use crate::elements::rail::contact::creep::law::Tangential;
use crate::elements::rail::geometry::alignment::{Alignment, Segment};
use crate::elements::rail::geometry::cant::{Cant, Track};
use crate::elements::rail::geometry::track_model::{self, TrackMesh};
use crate::elements::rail::vehicle::lean::{self, ArcPoint};
use crate::elements::rail::vehicle::theory::{self, Carriage, Operation, TrackParams, Variant};
use crate::elements::rail::vehicle::{build_train, CarriageData, TrainIds, TrainSpec};
use crate::framework::builder::ModelBuilder;
use crate::framework::model::{AnalysisSpec, Geometry, IntegratorKind, Predictor};
use crate::framework::moving::Path;
use crate::framework::FemError;
use crate::solvers::Driver;
use serde::{Deserialize, Serialize};
use std::io::Write;
use std::path::Path as FsPath;
use std::sync::Arc;

/// Inputs of one curved-track run. SI units.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct CurveCase {
    /// Radius of the circular arc (m).
    pub radius: f64,
    /// Cant constant Ct (m): θ = Ct/R (Eq. 21).
    pub ct: f64,
    /// Speed V (m/s).
    pub speed: f64,
    /// Friction coefficient μ.
    pub mu: f64,
    /// Time step (s).
    pub dt: f64,
    /// Segment lengths: straight, clothoid, arc, clothoid, straight (m).
    pub lengths: [f64; 5],
    /// Station of the carriage centre at t = 0 (m).
    pub start: f64,
    /// Contact penalty k = k_v (N/m).
    pub penalty: f64,
    /// Gravity (m/s²), also used by the theory.
    pub gravity: f64,
    /// Time integrator: "newmark", "hht" or "generalized_alpha".
    pub integrator: IntegratorKind,
    /// Generalized-α ρ∞ / HHT α.
    pub rho_inf: f64,
    /// Stop after this time (s); 0 = run to the end of the track.
    pub duration: f64,
    /// Record every n-th step.
    pub record_every: usize,
    /// Sliding tangent of the wheels: "symmetric" (Eq. 8) or "consistent".
    pub sliding_tangent: crate::elements::rail::contact::contact_law::SlidingTangent,
    /// Write ParaView output (`paraview/carriage.pvd`) every this many steps (0: none).
    pub vtk_every: usize,
    /// Distance into the arc after which the comparison with theory starts (m): the
    /// entry transient of the suspension (≈ 1 s time constant) has decayed by then.
    pub settle: f64,
    /// Geometry of the carriage: "linear" (the paper's model) or "nonlinear" (bodies lean
    /// on suspensions that balance in the displaced configuration).
    pub geometry: Geometry,
    /// Contact statuses of each step's first Newton iteration (`[analysis.newton]
    /// first_active_set`). `Found` by default: the curve's rails are rigid, so the rail
    /// under a wheel never moves and the first iteration has no lifted wheel to hold down,
    /// while at lift-off (`critical-radius --criterion separation`) holding the committed
    /// contact costs iterations (1 462 against 1 341) and moves the onset by 3.5 %
    /// (docs/performance.md, "The first iteration's active set").
    pub first_active_set: crate::framework::model::FirstActiveSet,
    /// Roll stiffness of an anti-roll bar per bogie (N·m/rad) added to the `sks700`
    /// carriage; 0 = none (the stand-in data have none).
    pub anti_roll: f64,
    /// Tangential law of the wheels (`moving_axle` key `tangential`): "coulomb" (the
    /// paper's), "kalker_linear" or "polach" (docs/creep.md).
    pub tangential: crate::elements::rail::contact::creep::law::Tangential,
    /// Polach's spin term (`moving_axle` key `polach_spin`, with `tangential = "polach"`):
    /// `None` leaves the element's default ("off").
    pub polach_spin: Option<crate::elements::rail::contact::creep::law::PolachSpin>,
}

impl CurveCase {
    /// Time steps of the run, for progress displays: `duration / dt`, the duration being
    /// the time the carriage takes to the track's end when not given (as [`CurveCase::build`]
    /// sets it, with the track's length taken as the sum of its five segments).
    pub fn steps_estimate(&self) -> u64 {
        let end = self.lengths.iter().sum::<f64>() - 15.0 - self.start;
        let duration = if self.duration > 0.0 {
            self.duration
        } else {
            end / self.speed.max(1e-9)
        };
        let n = (duration / self.dt).ceil();
        if n.is_finite() && n >= 1.0 {
            n.min(u64::MAX as f64) as u64
        } else {
            1
        }
    }
}

impl Default for CurveCase {
    /// The Fig. 6 case: V = 80 m/s, Ct = 200 m, arc radius 6250 m (100° over
    /// 10 908.3078 m), μ = 0.3, dt = 0.01 s.
    fn default() -> Self {
        CurveCase {
            radius: 6250.0,
            ct: 200.0,
            speed: 80.0,
            mu: 0.3,
            dt: 0.01,
            lengths: [500.0, 2000.0, 10_908.307_8, 2000.0, 800.0],
            start: 30.0,
            penalty: 1e10,
            gravity: 9.81,
            integrator: IntegratorKind::Newmark,
            rho_inf: 0.8,
            duration: 0.0,
            record_every: 10,
            sliding_tangent: crate::elements::rail::contact::contact_law::SlidingTangent::Symmetric,
            settle: 400.0,
            vtk_every: 0,
            geometry: Geometry::Linear,
            first_active_set: crate::framework::model::FirstActiveSet::Found,
            anti_roll: 0.0,
            tangential: crate::elements::rail::contact::creep::law::Tangential::Coulomb,
            polach_spin: None,
        }
    }
}

/// One recorded instant.
#[derive(Debug, Clone, PartialEq)]
pub struct Sample {
    /// Time (s).
    pub t: f64,
    /// Station of the carriage centre (m).
    pub station: f64,
    /// Per wheel (left, right per wheelset, front to rear): station, radius (m, inf on a
    /// straight), cant (rad), FE normal Q (N), FE shear Y (N), contact points, sliding
    /// points, theory normal and shear (statics), theory normal (printed Eq. 25).
    pub wheels: Vec<WheelSample>,
}

/// One wheel at one instant.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct WheelSample {
    /// Station of the wheel (m).
    pub station: f64,
    /// Radius at the wheel (m).
    pub radius: f64,
    /// Cant at the wheel (rad).
    pub cant: f64,
    /// FE normal force (N), along wheel axis 2.
    pub q: f64,
    /// FE shear force (N), along wheel axis 1 (towards the curve centre).
    pub y: f64,
    /// Contact points.
    pub n_contact: f64,
    /// Sliding points.
    pub n_slide: f64,
    /// Theory, rigid-body statics: normal (N).
    pub q_statics: f64,
    /// Theory, Eq. 25 as printed: normal (N).
    pub q_printed: f64,
    /// Theory shear (Eq. 26) (N).
    pub y_theory: f64,
    /// Quasi-static reference with body lean: normal (N) ([`crate::elements::rail::vehicle::lean`]).
    pub q_lean: f64,
    /// Whether the wheel is the inner one.
    pub inner: bool,
}

/// What a run found.
#[derive(Debug, Clone, PartialEq)]
pub struct CurveReport {
    /// Recorded samples.
    pub samples: Vec<Sample>,
    /// Largest relative difference of the FE normal force from statics on the settled arc.
    pub max_rel_normal_statics: f64,
    /// Largest relative difference of the FE axle shear (mean of the wheelset's two wheels)
    /// from Eq. 26 on the settled arc. Statics fixes only this sum; how it splits between
    /// the two wheels depends on their contact stiffness ([`CurveReport::max_rel_shear_wheel`]).
    pub max_rel_shear: f64,
    /// Largest relative difference of a single wheel's shear from Eq. 26 on the settled arc.
    pub max_rel_shear_wheel: f64,
    /// Largest relative difference of the FE normal force from the printed Eq. 25 on the arc.
    pub max_rel_normal_printed: f64,
    /// Largest relative difference of the FE normal force from the quasi-static reference
    /// with body lean on the settled arc.
    pub max_rel_normal_lean: f64,
    /// Mean over the settled arc of the FE inner and outer normal forces (N), (inner, outer).
    pub arc_mean_normal: [f64; 2],
    /// Lateral spacing of the inner and outer contact points used by the statics (m).
    pub contact_spacing: f64,
    /// Steps, Newton iterations, wall time (s).
    pub steps: usize,
    /// Newton iterations.
    pub iterations: usize,
    /// Wall time of the run (s).
    pub wall: f64,
    /// First time any wheel slid (s), if any.
    pub first_slide: Option<f64>,
    /// First time an inner wheel's normal force reached zero (s), if any.
    pub first_separation: Option<f64>,
    /// The run's energy balance as printed (see [`crate::solvers::energy`]).
    pub energy_summary: Option<String>,
}

/// The model of a case: builder, ids and the track.
pub struct CurveModel {
    /// The driver, ready to step.
    pub driver: Driver,
    /// Ids of the train.
    pub ids: TrainIds,
    /// The track.
    pub track: Arc<Track>,
    /// Element indices of the wheels in the model.
    pub wheel_index: Vec<usize>,
}

impl CurveCase {
    /// The alignment: the five segments, left-hand.
    pub fn track(&self) -> Result<Track, FemError> {
        let k = 1.0 / self.radius;
        let [l0, l1, l2, l3, l4] = self.lengths;
        let segs = vec![
            Segment::Straight { length: l0 },
            Segment::Clothoid {
                length: l1,
                from_curvature: 0.0,
                to_curvature: k,
            },
            Segment::Arc {
                length: l2,
                radius: self.radius,
                hand: crate::elements::rail::geometry::alignment::Hand::Left,
            },
            Segment::Clothoid {
                length: l3,
                from_curvature: k,
                to_curvature: 0.0,
            },
            Segment::Straight { length: l4 },
        ];
        let al = Alignment::new(segs).map_err(|e| FemError::input("curve case", e.to_string()))?;
        Track::new(al, Cant::FromRadius { ct: self.ct })
            .map_err(|e| FemError::input("curve case", e.to_string()))
    }

    /// The carriage: `sks700` with this case's anti-roll bar.
    pub fn carriage(&self) -> CarriageData {
        CarriageData {
            anti_roll: self.anti_roll,
            ..CarriageData::sks700()
        }
    }

    /// Builds the model.
    pub fn build(&self) -> Result<CurveModel, FemError> {
        if !(self.speed.is_finite() && self.speed > 0.0) {
            return Err(FemError::input(
                "curve case",
                format!("--speed {}: give a speed > 0 m/s", self.speed),
            ));
        }
        if !(self.radius.is_finite() && self.radius > 0.0 && self.ct.is_finite() && self.ct >= 0.0)
        {
            return Err(FemError::input(
                "curve case",
                format!(
                    "--radius {} / --ct {}: give a radius > 0 m and Ct ≥ 0 m",
                    self.radius, self.ct
                ),
            ));
        }
        let track = Arc::new(self.track()?);
        let mut b = ModelBuilder::new("curve case");
        let tm = track_model::generate(&mut b, track.clone(), &TrackMesh::default())?;
        let mut wheel = serde_json::json!({
            "mu": self.mu, "k": self.penalty, "k_v": self.penalty,
            "sliding_tangent": self.sliding_tangent,
        });
        if self.tangential != Tangential::Coulomb {
            wheel["tangential"] = serde_json::json!(self.tangential);
        }
        if let Some(s) = self.polach_spin {
            wheel["polach_spin"] = serde_json::json!(s);
        }
        let spec = TrainSpec {
            name: "sks700".into(),
            carriage: self.carriage(),
            carriages: 1,
            start: self.start,
            speed: self.speed,
            accel: 0.0,
            speed_table: None,
            wheel,
            first_node_id: 0,
            geometry: Some(self.geometry),
            suspension_tangent: crate::elements::suspension::SuspensionTangent::Symmetric,
        };
        let end = track.length() - 15.0 - self.start;
        let duration = if self.duration > 0.0 {
            self.duration
        } else {
            end / self.speed.max(1e-9)
        };
        b.analysis(AnalysisSpec {
            dt: self.dt,
            duration,
            gravity: Some([0.0, 0.0, -self.gravity]),
            integrator: self.integrator.clone(),
            rho_inf: self.rho_inf,
            alpha: (1.0 - self.rho_inf) / (1.0 + self.rho_inf),
            record_every: self.record_every.max(1),
            newton: crate::framework::model::NewtonSettings {
                max_iter: 60,
                // A creep law is nonlinear in the wheelsets' steady advance over a step
                // (spin, contact masters); predicting it from the last step saves about
                // one Newton iteration per step (docs/performance.md). Coulomb keeps the
                // paper's run as it was.
                predictor: if self.tangential == Tangential::Coulomb {
                    Predictor::Previous
                } else {
                    Predictor::Increment
                },
                first_active_set: self.first_active_set,
                ..Default::default()
            },
            ..Default::default()
        });
        let ids = build_train(&mut b, &tm, &spec)?;
        let model = b.build()?;
        let wheel_index = ids
            .wheels
            .iter()
            .map(|id| {
                model
                    .elements
                    .iter()
                    .position(|e| e.id == *id)
                    .expect("wheel exists")
            })
            .collect();
        let driver = Driver::new(model)?;
        Ok(CurveModel {
            driver,
            ids,
            track,
            wheel_index,
        })
    }
}

fn output(d: &Driver, ei: usize, names: &[String], key: &str, buf: &mut Vec<f64>) -> f64 {
    buf.clear();
    d.model.elements[ei].element.outputs(buf);
    names
        .iter()
        .position(|n| n == key)
        .map_or(f64::NAN, |i| buf[i])
}

/// Runs a case; writes `curve.csv`, `curve.svg` and `case.json` into `out` when given.
pub fn run(
    case: &CurveCase,
    out: Option<&FsPath>,
    progress: &mut dyn FnMut(f64),
) -> Result<CurveReport, FemError> {
    let start = std::time::Instant::now();
    let mut m = case.build()?;
    let d = &mut m.driver;
    d.initialize()?;
    let names = d.model.elements[m.wheel_index[0]].element.output_names();
    let carriage = Carriage::sks700_standin_with_gravity(case.gravity);
    let n_w = m.wheel_index.len();
    let mut buf = Vec::new();
    // Contact spacing from the initial (straight, symmetric) state: force-weighted lateral
    // positions of the contact points on the two rails.
    let tm_offset = m.track.gauge / 2.0 + 0.036;
    let mut spacing_sum = 0.0;
    for (k, &ei) in m.wheel_index.iter().enumerate() {
        let y = output(d, ei, &names, "p1_rail_y", &mut buf);
        let _ = k;
        spacing_sum += tm_offset + if y.is_finite() { y } else { 0.0 };
    }
    let spacing = 2.0 * spacing_sum / n_w as f64;
    let tp_statics = TrackParams {
        gauge: spacing,
        gravity: case.gravity,
    };
    let tp_printed = TrackParams {
        gauge: 1.435,
        gravity: case.gravity,
    };
    let op = Operation {
        speed: case.speed,
        cant_constant: case.ct,
        mu: case.mu,
    };
    let spec = d.model.analysis.clone();
    let nsteps = (spec.duration / spec.dt).ceil() as usize;
    let mut samples = Vec::new();
    let (mut rel_q, mut rel_y, mut rel_p, mut rel_yw) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
    let mut rel_lean = 0.0f64;
    let (mut arc_sum, mut arc_n) = ([0.0f64; 2], 0usize);
    // The lean reference per (curvature, cant) met by a wheel, solved once each.
    let mut lean_cache: std::collections::HashMap<(u64, u64), Option<[f64; 2]>> =
        std::collections::HashMap::new();
    let carriage_data = case.carriage();
    let (mut first_slide, mut first_sep) = (None, None);
    let l = case.lengths;
    let arc = (l[0] + l[1], l[0] + l[1] + l[2]);
    // ParaView: the carriage and the rails within 25 m of its car body.
    let mut vtk = match (out, case.vtk_every) {
        (Some(dir), n) if n > 0 => Some(crate::framework::vtk::VtkSeries::new(
            &dir.join("paraview"),
            "carriage",
        )?),
        _ => None,
    };
    let body = m.ids.car_bodies.first().and_then(|id| d.model.node(*id));
    let mut interrupted = None;
    for k in 1..=nsteps {
        d.step(spec.dt)?;
        if let (Some(v), Some(b)) = (vtk.as_mut(), body) {
            if k % case.vtk_every == 0 {
                let kin = d.asm.kinematics();
                let centre = kin[b].position;
                let frame = crate::framework::vtk::Frame {
                    t: d.state.t,
                    q: &d.state.q,
                    v: &d.state.v,
                    a: &d.state.a,
                };
                v.write(&mut d.model, &d.asm, frame, &|i| {
                    (kin[i].position - centre).norm() < 25.0
                })?;
            }
        }
        let t = d.state.t;
        let mut wheels = Vec::with_capacity(n_w);
        for (w, &ei) in m.wheel_index.iter().enumerate() {
            let s = output(d, ei, &names, "station", &mut buf);
            let q = output(d, ei, &names, "Q", &mut buf);
            let y = output(d, ei, &names, "Y", &mut buf);
            let nc = output(d, ei, &names, "n_contact", &mut buf);
            let ns = output(d, ei, &names, "n_slide", &mut buf);
            let p = m.track.at(s);
            let radius = if p.curvature.abs() > 1e-12 {
                1.0 / p.curvature.abs()
            } else {
                f64::INFINITY
            };
            let inner = (w % 2 == 0) == (p.curvature >= 0.0);
            let st = theory::evaluate(&carriage, &tp_statics, &op, radius, Variant::Statics);
            let pr = theory::evaluate(&carriage, &tp_printed, &op, radius, Variant::Printed);
            let (qs, ys, qp) = match (st, pr) {
                (Ok(a), Ok(b)) => (
                    if inner {
                        a.normal_inner
                    } else {
                        a.normal_outer
                    },
                    a.shear,
                    if inner {
                        b.normal_inner
                    } else {
                        b.normal_outer
                    },
                ),
                _ => (f64::NAN, f64::NAN, f64::NAN),
            };
            let key = (p.curvature.abs().to_bits(), p.cant.to_bits());
            let lean = *lean_cache.entry(key).or_insert_with(|| {
                let op = ArcPoint {
                    speed: case.speed,
                    curvature: p.curvature.abs(),
                    cant: p.cant,
                    gravity: case.gravity,
                    spacing,
                    pivot: None,
                };
                lean::wheel_loads(&carriage_data, &op).map(|r| r.lean)
            });
            let q_lean = lean.map_or(f64::NAN, |l| if inner { l[0] } else { l[1] });
            if ns > 0.0 && first_slide.is_none() {
                first_slide = Some(t);
            }
            if inner && q <= 0.0 && first_sep.is_none() {
                first_sep = Some(t);
            }
            wheels.push(WheelSample {
                station: s,
                radius,
                cant: p.cant,
                q,
                y,
                n_contact: nc,
                n_slide: ns,
                q_statics: qs,
                q_printed: qp,
                y_theory: ys,
                q_lean,
                inner,
            });
        }
        // Settled arc: the whole carriage at least `settle` into the arc and not yet at
        // its end — the theory is two-dimensional and holds for a carriage on one radius.
        let settled = wheels
            .iter()
            .all(|w| w.station > arc.0 + case.settle && w.station < arc.1);
        if settled {
            arc_n += 1;
            for w in &wheels {
                arc_sum[usize::from(!w.inner)] += w.q / (wheels.len() / 2) as f64;
                rel_lean = rel_lean.max((w.q - w.q_lean).abs() / w.q_lean.abs());
                rel_q = rel_q.max((w.q - w.q_statics).abs() / w.q_statics.abs());
                rel_p = rel_p.max((w.q - w.q_printed).abs() / w.q_printed.abs());
                rel_yw = rel_yw
                    .max((w.y - w.y_theory).abs() / w.y_theory.abs().max(1e-9 * w.q_statics.abs()));
            }
            for pair in wheels.chunks(2) {
                let mean = 0.5 * (pair[0].y + pair[1].y);
                let ys = pair[0].y_theory;
                rel_y = rel_y.max((mean - ys).abs() / ys.abs().max(1e-9 * pair[0].q_statics.abs()));
            }
        }
        // Asked to stop (SIGINT/SIGTERM): this step is kept and recorded, then the loop
        // ends and the outputs are written as for a whole run.
        let stop = crate::framework::interrupt::requested() && k < nsteps;
        if k % spec.record_every == 0 || k == nsteps || stop {
            samples.push(Sample {
                t,
                station: case.start + case.speed * t,
                wheels,
            });
        }
        progress(k as f64 / nsteps as f64);
        if stop {
            interrupted = Some(t);
            break;
        }
    }
    if let Some(v) = &vtk {
        v.finish()?;
    }
    let report = CurveReport {
        samples,
        max_rel_normal_statics: rel_q,
        max_rel_shear: rel_y,
        max_rel_shear_wheel: rel_yw,
        max_rel_normal_printed: rel_p,
        max_rel_normal_lean: rel_lean,
        arc_mean_normal: arc_sum.map(|x| x / arc_n.max(1) as f64),
        contact_spacing: spacing,
        steps: d.summary.steps,
        iterations: d.summary.iterations,
        wall: start.elapsed().as_secs_f64(),
        first_slide,
        first_separation: first_sep,
        energy_summary: d
            .energy
            .as_ref()
            .filter(|e| e.started())
            .map(|e| e.summary()),
    };
    if let Some(dir) = out {
        write_outputs(case, &report, dir)?;
        d.write_energy(dir)?;
    }
    if let Some(t) = interrupted {
        return Err(FemError::Interrupted { t });
    }
    Ok(report)
}

/// Writes `curve.csv` (one row per recorded step), `curve.svg` and `case.json`.
pub fn write_outputs(case: &CurveCase, r: &CurveReport, dir: &FsPath) -> Result<(), FemError> {
    std::fs::create_dir_all(dir).map_err(|e| FemError::output(dir, e))?;
    let path = dir.join("curve.csv");
    let f = std::fs::File::create(&path).map_err(|e| FemError::output(&path, e))?;
    let mut w = std::io::BufWriter::new(f);
    let n = r.samples.first().map_or(0, |s| s.wheels.len());
    let mut header = vec!["time [s]".to_string(), "station [m]".to_string()];
    for i in 0..n {
        let side = if i % 2 == 0 { "L" } else { "R" };
        let ax = i / 2 + 1;
        for (c, unit) in [
            ("station", "m"),
            ("radius", "m"),
            ("cant", "rad"),
            ("Q_fe", "N"),
            ("Y_fe", "N"),
            ("n_contact", "-"),
            ("n_slide", "-"),
            ("Q_statics", "N"),
            ("Q_printed", "N"),
            ("Y_theory", "N"),
            ("Q_lean", "N"),
        ] {
            header.push(format!("w{ax}{side}_{c} [{unit}]"));
        }
    }
    let io = |e: std::io::Error| FemError::output(&path, e);
    writeln!(w, "{}", header.join(",")).map_err(io)?;
    for s in &r.samples {
        let mut row = format!("{:.4},{:.4}", s.t, s.station);
        for x in &s.wheels {
            row.push_str(&format!(
                ",{:.4},{:.6e},{:.6e},{:.6e},{:.6e},{},{},{:.6e},{:.6e},{:.6e},{:.6e}",
                x.station,
                x.radius,
                x.cant,
                x.q,
                x.y,
                x.n_contact,
                x.n_slide,
                x.q_statics,
                x.q_printed,
                x.y_theory,
                x.q_lean
            ));
        }
        writeln!(w, "{row}").map_err(io)?;
    }
    w.flush().map_err(io)?;
    let json = serde_json::to_string_pretty(case).unwrap_or_default();
    std::fs::write(dir.join("case.json"), json)
        .map_err(|e| FemError::output(dir.join("case.json"), e))?;
    plot(r, &dir.join("curve.svg"))?;
    Ok(())
}

fn plot(r: &CurveReport, path: &FsPath) -> Result<(), FemError> {
    use crate::framework::plot::{Figure, Panel, Series, Style};
    let t: Vec<f64> = r.samples.iter().map(|s| s.t).collect();
    let col = |f: &dyn Fn(&WheelSample) -> f64, w: usize| -> Vec<f64> {
        r.samples.iter().map(|s| f(&s.wheels[w]) / 1e3).collect()
    };
    let normal = Panel::new("Normal contact force, wheelset 1", "time (s)", "force (kN)")
        .with(Series::new(
            "FE, inner (left) wheel",
            t.clone(),
            col(&|w| w.q, 0),
            Style::Line,
            "#1f77b4",
        ))
        .with(Series::new(
            "FE, outer (right) wheel",
            t.clone(),
            col(&|w| w.q, 1),
            Style::Line,
            "#d62728",
        ))
        .with(Series::new(
            "statics, inner",
            t.clone(),
            col(&|w| w.q_statics, 0),
            Style::Dashed,
            "#17becf",
        ))
        .with(Series::new(
            "statics, outer",
            t.clone(),
            col(&|w| w.q_statics, 1),
            Style::Dashed,
            "#ff7f0e",
        ))
        .with(Series::new(
            "Eq. 25 as printed, inner",
            t.clone(),
            col(&|w| w.q_printed, 0),
            Style::Dashed,
            "#7f7f7f",
        ))
        .with(Series::new(
            "Eq. 25 as printed, outer",
            t.clone(),
            col(&|w| w.q_printed, 1),
            Style::Dashed,
            "#bcbd22",
        ));
    let shear = Panel::new(
        "Shear (lateral) contact force, wheelset 1",
        "time (s)",
        "force (kN)",
    )
    .with(Series::new(
        "FE, inner wheel",
        t.clone(),
        col(&|w| w.y, 0),
        Style::Line,
        "#1f77b4",
    ))
    .with(Series::new(
        "FE, outer wheel",
        t.clone(),
        col(&|w| w.y, 1),
        Style::Line,
        "#d62728",
    ))
    .with(Series::new(
        "theory (Eq. 26)",
        t.clone(),
        col(&|w| w.y_theory, 0),
        Style::Dashed,
        "#2ca02c",
    ));
    let fig = Figure::new().with(normal).with(shear);
    fig.write_svg_and_png(path)
        .map_err(|e| FemError::output(path, e))
}

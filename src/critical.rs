//! Critical radii for sliding (the paper's Figure 7) and for separation of the inner wheel
//! (Figure 9), finite elements against the simple theory.
//!
//! No bisection over R is needed: along a clothoid the radius falls continuously from
//! infinity to the arc's, so one run at fixed V, Ct and μ into an arc tighter than the
//! theory's critical radius finds the FE's critical radius as the radius at the station
//! where the criterion is first met. The clothoid is long enough for the onset to be
//! quasi-static; [`CriticalCase::clothoid`] can be doubled to show it (the tests do).
//!
//! Criteria:
//! - **sliding, the paper's way**: Eq. 24 applied to the FE wheel forces, `|ΣY| ≥ μ·ΣQ`
//!   over the carriage's wheels (the paper: "Equation (24) \[is\] used to both theoretical and
//!   finite element results");
//! - **sliding, mechanistic**: the first time every contact point of every wheel slides
//!   (gross sliding of the carriage). Friction acts in each contact's tangent plane, tilted
//!   from the track plane by the contact angle (≈ 0.03 rad on an S1002 tread), so this
//!   onset differs from Eq. 24's by about the contact angle times the load difference of the
//!   inner and outer wheels; it is reported, not compared;
//! - **separation**: the first time an inner wheel's normal force reaches zero.

use crate::curve::CurveCase;
use crate::elements::rail::vehicle::theory::{
    self, Carriage, CriticalRadius, Operation, RadiusBracket, SlidingDirection, TrackParams,
    Variant, WheelSide,
};
use crate::framework::model::Geometry;
use crate::framework::moving::Path;
use crate::framework::FemError;
use serde::{Deserialize, Serialize};

/// Which critical radius to find.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Criterion {
    /// Sliding of the carriage (Fig. 7).
    Sliding,
    /// Separation of the inner wheel (Fig. 9).
    Separation,
}

/// One point of a Fig. 7 / Fig. 9 sweep.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CriticalCase {
    /// Which radius.
    pub criterion: Criterion,
    /// Speed V (m/s).
    pub speed: f64,
    /// Cant constant Ct (m).
    pub ct: f64,
    /// Friction coefficient μ.
    pub mu: f64,
    /// Clothoid length (m).
    pub clothoid: f64,
    /// Time step (s).
    pub dt: f64,
    /// Geometry of the carriage ("linear" or "nonlinear").
    #[serde(default)]
    pub geometry: Geometry,
    /// Tangential law of the wheels (`moving_axle` key `tangential`): "coulomb" (the
    /// paper's), "kalker_linear" or "polach" (docs/creep.md).
    #[serde(default)]
    pub tangential: crate::elements::rail::contact::creep::law::Tangential,
    /// Polach's spin term (`moving_axle` key `polach_spin`); `None`: the element's default.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub polach_spin: Option<crate::elements::rail::contact::creep::law::PolachSpin>,
}

/// What one run found (radii in m; `None` when not reached).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct CriticalResult {
    /// FE critical radius (Eq. 24 on FE forces for sliding; inner wheel Q = 0 for separation).
    pub fe: Option<f64>,
    /// FE radius of gross sliding (every contact point sliding), sliding runs only.
    pub fe_gross: Option<f64>,
    /// Theory, rigid-body statics (contact spacing of the FE model).
    pub theory: Option<f64>,
    /// Theory with Eq. 25 as printed (separation only).
    pub theory_printed: Option<f64>,
    /// Radius of the arc the run went into (m).
    pub arc_radius: f64,
    /// Separation: statics about the FE's outer contact point at the onset (m): the
    /// overturning radius of a rigid carriage pivoting on the contact points the FE found
    /// (after sliding, on the flanges).
    pub theory_at_contact: Option<f64>,
    /// The outer wheels' contact point at the onset, wheel frame relative to the centre
    /// line at rail-top level (lateral, vertical) (m).
    pub outer_contact: Option<[f64; 2]>,
    /// Separation, nonlinear geometry: the overturning radius about the same contact point
    /// of the carriage with its bodies leaning on their suspensions
    /// ([`crate::elements::rail::vehicle::lean`]) (m).
    pub lean_at_contact: Option<f64>,
}

fn found(c: Result<CriticalRadius, theory::TheoryError>) -> Option<f64> {
    match c {
        Ok(CriticalRadius::Found { radius, .. }) => Some(radius),
        _ => None,
    }
}

/// The theory's critical radius for a case (statics with contact spacing `spacing`, and
/// printed Eq. 25 with G = 1.435 m for separation).
pub fn theory_radius(case: &CriticalCase, spacing: f64, g: f64) -> (Option<f64>, Option<f64>) {
    let carriage = Carriage::sks700_standin_with_gravity(g);
    let op = Operation {
        speed: case.speed,
        cant_constant: case.ct,
        mu: case.mu,
    };
    let bracket = RadiusBracket {
        r_min: case.ct.max(10.0),
        r_max: 1e6,
        samples: 4000,
    };
    let st = TrackParams {
        gauge: spacing,
        gravity: g,
    };
    let pr = TrackParams {
        gauge: 1.435,
        gravity: g,
    };
    match case.criterion {
        Criterion::Sliding => (
            found(theory::critical_radius_sliding(
                &carriage,
                &st,
                &op,
                SlidingDirection::Outwards,
                &bracket,
            )),
            None,
        ),
        Criterion::Separation => (
            found(theory::critical_radius_separation(
                &carriage,
                &st,
                &op,
                Variant::Statics,
                WheelSide::Inner,
                &bracket,
            )),
            found(theory::critical_radius_separation(
                &carriage,
                &pr,
                &op,
                Variant::Printed,
                WheelSide::Inner,
                &bracket,
            )),
        ),
    }
}

/// Runs one point: a clothoid from a straight into an arc at 0.7 × the theory's radius.
pub fn run(case: &CriticalCase) -> Result<CriticalResult, FemError> {
    run_with_sections(case, None)
}

/// [`run`], and when `sections` is given, writes cross-section pictures of the leading
/// wheelset's two wheels at the onset (the paper's Figures 8 and 10) into that folder.
pub fn run_with_sections(
    case: &CriticalCase,
    sections: Option<&std::path::Path>,
) -> Result<CriticalResult, FemError> {
    let g = 9.81;
    let spacing = 1.507;
    let (theory_r, printed_r) = theory_radius(case, spacing, g);
    let target = theory_r.ok_or_else(|| {
        FemError::input(
            "critical-radius",
            format!(
                "the theory finds no critical radius for V = {} m/s, Ct = {} m, mu = {}; pick a higher speed",
                case.speed, case.ct, case.mu
            ),
        )
    })?;
    let arc_radius = 0.7 * target;
    let lead = 40.0;
    let curve = CurveCase {
        radius: arc_radius,
        ct: case.ct,
        speed: case.speed,
        mu: case.mu,
        dt: case.dt,
        lengths: [lead, case.clothoid, 200.0, 50.0, 50.0],
        start: 20.0,
        duration: (lead + case.clothoid + 150.0 - 20.0) / case.speed,
        sliding_tangent: crate::elements::rail::contact::contact_law::SlidingTangent::Consistent,
        geometry: case.geometry,
        tangential: case.tangential,
        polach_spin: case.polach_spin,
        ..CurveCase::default()
    };
    let mut m = curve.build()?;
    let d = &mut m.driver;
    d.initialize()?;
    let names = d.model.elements[m.wheel_index[0]].element.output_names();
    let idx = |k: &str| names.iter().position(|n| n == k).unwrap_or(0);
    let (iq, iy, ist, inc, ins) = (
        idx("Q"),
        idx("Y"),
        idx("station"),
        idx("n_contact"),
        idx("n_slide"),
    );
    let (icy, icz) = (idx("contact_y"), idx("contact_z"));
    let spec = d.model.analysis.clone();
    let nsteps = (spec.duration / spec.dt).ceil() as usize;
    let radius_at = |s: f64| {
        let k = m.track.at(s).curvature.abs();
        if k > 0.0 {
            1.0 / k
        } else {
            f64::INFINITY
        }
    };
    let mut res = CriticalResult {
        fe: None,
        fe_gross: None,
        theory: theory_r,
        theory_printed: printed_r,
        arc_radius,
        theory_at_contact: None,
        outer_contact: None,
        lean_at_contact: None,
    };
    let mut buf = Vec::new();
    // Linear interpolation of the onset between the last two steps.
    let mut prev: Option<(f64, f64, f64)> = None; // (margin, station, margin2)
                                                  // A stop request does not cut a case (its rows would be no result): the sweep stops
                                                  // between cases, a single point runs to its end.
    for _ in 0..nsteps {
        if let Err(e) = d.step(spec.dt) {
            // After the onset the carriage may slide into flange contact violently; the
            // onset is what this run is for.
            if res.fe.is_some() {
                break;
            }
            return Err(e);
        }
        let (mut sy, mut sq, mut all_slide, mut s_mean) = (0.0, 0.0, true, 0.0);
        let mut worst_inner = (f64::INFINITY, 0.0);
        let mut outer = (0.0, 0.0, 0.0);
        for (w, &ei) in m.wheel_index.iter().enumerate() {
            buf.clear();
            d.model.elements[ei].element.outputs(&mut buf);
            sy += buf[iy];
            sq += buf[iq];
            s_mean += buf[ist];
            if buf[inc] == 0.0 || buf[ins] < buf[inc] {
                all_slide = false;
            }
            // Left wheels (even index) are inner on the left-hand curve.
            if w % 2 == 0 && buf[iq] < worst_inner.0 {
                worst_inner = (buf[iq], buf[ist]);
            }
            if w % 2 == 1 {
                outer = (
                    outer.0 + buf[icy] * buf[iq],
                    outer.1 + buf[icz] * buf[iq],
                    outer.2 + buf[iq],
                );
            }
        }
        s_mean /= m.wheel_index.len() as f64;
        match case.criterion {
            Criterion::Sliding => {
                let margin = sy.abs() - case.mu * sq;
                if res.fe.is_none() && margin >= 0.0 {
                    let s = match prev {
                        Some((m0, s0, _)) if m0 < 0.0 => s0 + (s_mean - s0) * (-m0) / (margin - m0),
                        _ => s_mean,
                    };
                    res.fe = Some(radius_at(s));
                    if let Some(dir) = sections {
                        write_sections(d, &m.wheel_index, dir, "sliding onset")?;
                    }
                }
                if res.fe_gross.is_none() && all_slide {
                    res.fe_gross = Some(radius_at(s_mean));
                }
                prev = Some((margin, s_mean, 0.0));
                if res.fe.is_some() && res.fe_gross.is_some() {
                    break;
                }
            }
            Criterion::Separation => {
                let (q, s) = worst_inner;
                if q <= 0.0 {
                    let s_on = match prev {
                        Some((q0, s0, _)) if q0 > 0.0 => s0 + (s - s0) * q0 / (q0 - q),
                        _ => s,
                    };
                    res.fe = Some(radius_at(s_on));
                    if let Some(dir) = sections {
                        write_sections(d, &m.wheel_index, dir, "inner wheel separates")?;
                    }
                    if outer.2 > 0.0 {
                        let (yo, zo) = (outer.0 / outer.2, outer.1 / outer.2);
                        res.outer_contact = Some([yo, zo]);
                        res.theory_at_contact = separation_about(case, yo, zo, g);
                        if case.geometry == Geometry::Nonlinear {
                            res.lean_at_contact = lean_separation_about(case, yo, zo, g);
                        }
                    }
                    break;
                }
                prev = Some((q, s, 0.0));
            }
        }
    }
    Ok(res)
}

/// Overturning radius of the rigid carriage pivoting on an outer contact point at
/// `(y_o, z_o)` (wheel frame, relative to the centre line at rail-top level, m): with the
/// inner wheels unloaded, moments about the outer contact line give
/// `−y_o·ΣF2_i − Σ(H_i − z_o)·F1_i = 0` (Eqs. 22–23 for F1, F2; bodies on the centre line
/// at heights H_i). With `y_o = −b/2`, `z_o = 0` this is the statics variant of Eq. 25 with
/// the inner force set to zero. Found by bisection on R (θ = Ct/R follows R).
pub fn separation_about(case: &CriticalCase, y_o: f64, z_o: f64, g: f64) -> Option<f64> {
    let carriage = Carriage::sks700_standin_with_gravity(g);
    let f = |r: f64| {
        let theta = case.ct / r;
        carriage.bodies.iter().fold(0.0, |acc, b| {
            let (f1, f2) = theory::body_forces(b.weight, theta, 1.0 / r, case.speed, g);
            acc - y_o * f2 - (b.cg_height - z_o) * f1
        })
    };
    first_root(&f, case.ct)
}

/// [`separation_about`] for the carriage whose bodies lean on their suspensions: the
/// moment about the contact point of the body loads at their displaced mass centres
/// ([`crate::elements::rail::vehicle::lean::wheel_loads`]) vanishes. `None` where the lean
/// reference has no equilibrium.
pub fn lean_separation_about(case: &CriticalCase, y_o: f64, z_o: f64, g: f64) -> Option<f64> {
    let data = crate::elements::rail::vehicle::CarriageData::sks700();
    let f = |r: f64| {
        let op = crate::elements::rail::vehicle::lean::ArcPoint {
            speed: case.speed,
            curvature: 1.0 / r,
            cant: case.ct / r,
            gravity: g,
            spacing: -2.0 * y_o,
            pivot: Some((y_o, z_o)),
        };
        crate::elements::rail::vehicle::lean::wheel_loads(&data, &op)
            .map_or(f64::NAN, |l| l.pivot_moment)
    };
    first_root(&f, case.ct)
}

/// The largest radius below 1e6 m where `f` changes sign (scanning down by 3 %), refined
/// by bisection; radii stay above `max(ct, 10)` m.
fn first_root(f: &dyn Fn(f64) -> f64, ct: f64) -> Option<f64> {
    let (mut hi, mut lo) = (1e6, 1e6);
    let f_hi = f(hi);
    while lo > ct.max(10.0) {
        lo = hi * 0.97;
        if f(lo).signum() != f_hi.signum() {
            break;
        }
        hi = lo;
    }
    let f_lo = f(lo);
    if !f_lo.is_finite() || f_lo.signum() == f_hi.signum() {
        return None;
    }
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if f(mid).signum() == f_hi.signum() {
            hi = mid;
        } else {
            lo = mid;
        }
        if (hi - lo) < 1e-10 * hi {
            break;
        }
    }
    Some(0.5 * (lo + hi))
}

/// One point of a sweep: the case and what it found (or why it could not run).
pub type SweepPoint = (CriticalCase, Result<CriticalResult, FemError>);

/// Runs every combination of `speeds × cts × mus` on `threads` worker threads (each point
/// a whole FE analysis); `progress` gets the fraction done. Points whose theory has no
/// critical radius are returned with that error. On a stop request
/// ([`crate::framework::interrupt`]) the workers finish their cases and start no more:
/// the points returned are then the first ones of the full sweep, in its order.
#[allow(clippy::too_many_arguments)]
pub fn sweep(
    criterion: Criterion,
    speeds: &[f64],
    cts: &[f64],
    mus: &[f64],
    clothoid: f64,
    dt: f64,
    geometry: Geometry,
    threads: usize,
    progress: &(dyn Fn(f64) + Sync),
) -> Vec<SweepPoint> {
    use std::sync::atomic::{AtomicUsize, Ordering};
    use std::sync::Mutex;
    let mut cases = Vec::new();
    for &ct in cts {
        for &mu in mus {
            for &speed in speeds {
                cases.push(CriticalCase {
                    criterion,
                    speed,
                    ct,
                    mu,
                    clothoid,
                    dt,
                    geometry,
                    tangential: crate::elements::rail::contact::creep::law::Tangential::Coulomb,
                    polach_spin: None,
                });
            }
        }
    }
    let next = AtomicUsize::new(0);
    let done = AtomicUsize::new(0);
    let results: Mutex<Vec<Option<SweepPoint>>> =
        Mutex::new((0..cases.len()).map(|_| None).collect());
    std::thread::scope(|s| {
        for _ in 0..threads.max(1) {
            s.spawn(|| loop {
                // A stop request: finish the case in hand, start no other (the cases done
                // are then the first ones, in order).
                if crate::framework::interrupt::requested() {
                    break;
                }
                let i = next.fetch_add(1, Ordering::Relaxed);
                if i >= cases.len() {
                    break;
                }
                let r = run(&cases[i]);
                if let Ok(mut v) = results.lock() {
                    v[i] = Some((cases[i].clone(), r));
                }
                let k = done.fetch_add(1, Ordering::Relaxed) + 1;
                progress(k as f64 / cases.len() as f64);
            });
        }
    });
    results
        .into_inner()
        .unwrap_or_default()
        .into_iter()
        .flatten()
        .collect()
}

/// Writes a sweep as `critical_<criterion>.csv` and `.svg` (FE points over the theory's
/// curves of radius against speed) into `dir`, and `cases.json` with the inputs.
pub fn write_sweep(
    points: &[SweepPoint],
    criterion: Criterion,
    dir: &std::path::Path,
) -> Result<(), FemError> {
    use crate::framework::plot::{Figure, Panel, Series, Style};
    std::fs::create_dir_all(dir).map_err(|e| FemError::output(dir, e))?;
    let name = match criterion {
        Criterion::Sliding => "sliding",
        Criterion::Separation => "separation",
    };
    let mut csv = String::from(
        "speed [m/s],ct [m],mu [-],r_fe [m],r_theory_statics [m],r_theory_at_contact [m],r_theory_printed [m],r_fe_gross_sliding [m],r_lean_at_contact [m],rel_diff [-],note [-]\n",
    );
    let opt = |x: Option<f64>| x.map_or(String::new(), |v| format!("{v:.3}"));
    for (c, r) in points {
        match r {
            Ok(r) => {
                let reference = match criterion {
                    Criterion::Sliding => r.theory,
                    Criterion::Separation => r.lean_at_contact.or(r.theory_at_contact),
                };
                let rel = match (r.fe, reference) {
                    (Some(a), Some(b)) => format!("{:.3e}", (a - b).abs() / b),
                    _ => String::new(),
                };
                csv.push_str(&format!(
                    "{},{},{},{},{},{},{},{},{},{},\n",
                    c.speed,
                    c.ct,
                    c.mu,
                    opt(r.fe),
                    opt(r.theory),
                    opt(r.theory_at_contact),
                    opt(r.theory_printed),
                    opt(r.fe_gross),
                    opt(r.lean_at_contact),
                    rel
                ));
            }
            Err(e) => csv.push_str(&format!(
                "{},{},{},,,,,,,,\"{}\"\n",
                c.speed,
                c.ct,
                c.mu,
                e.to_string().replace('"', "'")
            )),
        }
    }
    let path = dir.join(format!("critical_{name}.csv"));
    std::fs::write(&path, csv).map_err(|e| FemError::output(&path, e))?;
    let cases: Vec<&CriticalCase> = points.iter().map(|p| &p.0).collect();
    let json = serde_json::to_string_pretty(&cases).unwrap_or_default();
    std::fs::write(dir.join("cases.json"), json)
        .map_err(|e| FemError::output(dir.join("cases.json"), e))?;
    // Figure: one series pair per (Ct, μ).
    let colors = [
        "#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b", "#e377c2", "#7f7f7f",
        "#17becf",
    ];
    let mut groups: Vec<(f64, f64)> = Vec::new();
    for (c, _) in points {
        if !groups.contains(&(c.ct, c.mu)) {
            groups.push((c.ct, c.mu));
        }
    }
    let title = match criterion {
        Criterion::Sliding => "Critical radius for sliding (Fig. 7): FE points, theory lines",
        Criterion::Separation => {
            "Critical radius for inner-wheel separation (Fig. 9): FE points, statics lines"
        }
    };
    let mut panel = Panel::new(title, "speed V (m/s)", "critical radius R (m)");
    panel.legend = crate::framework::plot::Corner::TopLeft;
    for (gi, &(ct, mu)) in groups.iter().enumerate() {
        let color = colors[gi % colors.len()];
        let pts: Vec<(f64, f64)> = points
            .iter()
            .filter(|(c, _)| c.ct == ct && c.mu == mu)
            .filter_map(|(c, r)| r.as_ref().ok().and_then(|r| r.fe).map(|fe| (c.speed, fe)))
            .collect();
        let (lo, hi) = points
            .iter()
            .filter(|(c, _)| c.ct == ct && c.mu == mu)
            .fold((f64::INFINITY, 0.0f64), |(a, b), (c, _)| {
                (a.min(c.speed), b.max(c.speed))
            });
        let mut xs = Vec::new();
        let mut ys = Vec::new();
        for k in 0..=40 {
            let v = lo + (hi - lo) * k as f64 / 40.0;
            let case = CriticalCase {
                criterion,
                speed: v,
                ct,
                mu,
                clothoid: 0.0,
                dt: 0.0,
                geometry: Geometry::Linear,
                tangential: crate::elements::rail::contact::creep::law::Tangential::Coulomb,
                polach_spin: None,
            };
            let (st, _) = theory_radius(&case, 1.507, 9.81);
            xs.push(v);
            ys.push(st.unwrap_or(f64::NAN));
        }
        panel = panel
            .with(Series::new(
                &format!("theory, Ct = {ct} m, mu = {mu}"),
                xs,
                ys,
                Style::Line,
                color,
            ))
            .with(Series::new(
                &format!("FE, Ct = {ct} m, mu = {mu}"),
                pts.iter().map(|p| p.0).collect(),
                pts.iter().map(|p| p.1).collect(),
                Style::Markers,
                color,
            ));
    }
    let svg = dir.join(format!("critical_{name}.svg"));
    Figure::new()
        .with(panel)
        .write_svg_and_png(&svg)
        .map_err(|e| FemError::output(&svg, e))
}

fn write_sections(
    d: &crate::solvers::Driver,
    wheels: &[usize],
    dir: &std::path::Path,
    what: &str,
) -> Result<(), FemError> {
    use crate::elements::rail::contact::section_plot::write_section_svg;
    use crate::elements::rail::wheels::moving_axle::MovingAxle;
    std::fs::create_dir_all(dir).map_err(|e| FemError::output(dir, e))?;
    for (k, side) in [(0, "left (inner)"), (1, "right (outer)")] {
        let Some(ei) = wheels.get(k) else { continue };
        let e = &d.model.elements[*ei].element;
        if let Some(axle) = e.as_any().and_then(|a| a.downcast_ref::<MovingAxle>()) {
            let path = dir.join(format!(
                "section_wheelset1_{}.svg",
                if k == 0 { "left" } else { "right" }
            ));
            let title = format!("Wheelset 1, {side} wheel at t = {:.2} s: {what}", d.state.t);
            write_section_svg(axle, &title, &path).map_err(|e| FemError::output(&path, e))?;
        }
    }
    Ok(())
}

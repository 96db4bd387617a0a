//! The built-in cases as functions: `curve` (the paper's Fig. 6 case), `critical_radius`
//! (one point of Fig. 7 / Fig. 9) and `train_bridge` (the train on a viaduct).
//!
//! Each starts from the same defaults as its command (`railfem curve`, `critical-radius`,
//! `train-bridge`), sets the keyword arguments given, and calls the same library entry
//! point ([`railfem::curve::run`], [`railfem::critical::run_with_sections`],
//! [`railfem::train_bridge::build`] and [`railfem::train_bridge::run`]) with the GIL
//! released; with `out`, the same files are written. Results are raw dicts of numbers and
//! numpy arrays; `railfem/__init__.py` documents them.

use crate::model::table;
use crate::{guarded, to_py_err, value};
use numpy::ndarray::Array2;
use numpy::IntoPyArray;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use railfem::framework::model::Geometry;
use railfem::framework::FemError;
use std::path::PathBuf;

/// `geometry="linear"|"nonlinear"`, refused with the command line's wording.
fn geometry(g: &str, call: &str) -> PyResult<Geometry> {
    Geometry::parse(g).map_err(|_| {
        to_py_err(FemError::input(
            call,
            format!("geometry={g:?}: use \"linear\" (the default) or \"nonlinear\""),
        ))
    })
}

/// The curved-track validation (Fig. 6) for one speed, radius and cant constant.
#[pyfunction]
#[pyo3(signature = (*, speed = None, radius = None, ct = None, mu = None, dt = None,
    penalty = None, duration = None, lengths = None, quick = false, geometry = "linear",
    anti_roll = None, out = None))]
#[allow(clippy::too_many_arguments)]
pub fn curve<'py>(
    py: Python<'py>,
    speed: Option<f64>,
    radius: Option<f64>,
    ct: Option<f64>,
    mu: Option<f64>,
    dt: Option<f64>,
    penalty: Option<f64>,
    duration: Option<f64>,
    lengths: Option<[f64; 5]>,
    quick: bool,
    geometry: &str,
    anti_roll: Option<f64>,
    out: Option<PathBuf>,
) -> PyResult<Bound<'py, PyDict>> {
    let mut case = railfem::curve::CurveCase::default();
    let set = |slot: &mut f64, v: Option<f64>| {
        if let Some(v) = v {
            *slot = v;
        }
    };
    set(&mut case.speed, speed);
    set(&mut case.radius, radius);
    set(&mut case.ct, ct);
    set(&mut case.mu, mu);
    set(&mut case.dt, dt);
    set(&mut case.penalty, penalty);
    set(&mut case.duration, duration);
    set(&mut case.anti_roll, anti_roll);
    if let Some(l) = lengths {
        if l.iter().any(|x| !(x.is_finite() && *x > 0.0)) {
            return Err(to_py_err(FemError::input(
                "curve()",
                format!("lengths={l:?}: give five positive lengths in m"),
            )));
        }
        case.lengths = l;
    }
    if quick {
        // `railfem curve --quick`: a short track.
        case.lengths = [60.0, 300.0, 700.0, 300.0, 60.0];
    }
    case.geometry = self::geometry(geometry, "curve()")?;
    let r = guarded(py, || {
        railfem::curve::run(&case, out.as_deref(), &mut |_| {})
    })?
    .map_err(to_py_err)?;

    let d = PyDict::new(py);
    d.set_item("case", value::serialize_to_py(py, &case)?)?;
    let n = r.samples.len();
    let nw = r.samples.first().map_or(0, |s| s.wheels.len());
    let names: Vec<String> = (0..nw)
        .map(|i| format!("w{}{}", i / 2 + 1, if i % 2 == 0 { "L" } else { "R" }))
        .collect();
    d.set_item("wheel_names", names)?;
    let inner: Vec<bool> = r
        .samples
        .first()
        .map(|s| s.wheels.iter().map(|w| w.inner).collect())
        .unwrap_or_default();
    d.set_item("inner", inner)?;
    d.set_item(
        "time",
        r.samples
            .iter()
            .map(|s| s.t)
            .collect::<Vec<_>>()
            .into_pyarray(py),
    )?;
    d.set_item(
        "station",
        r.samples
            .iter()
            .map(|s| s.station)
            .collect::<Vec<_>>()
            .into_pyarray(py),
    )?;
    // Per wheel quantity, (samples, wheels), named as the curve.csv columns are.
    type Field = fn(&railfem::curve::WheelSample) -> f64;
    let fields: [(&str, Field); 11] = [
        ("station", |w| w.station),
        ("radius", |w| w.radius),
        ("cant", |w| w.cant),
        ("Q_fe", |w| w.q),
        ("Y_fe", |w| w.y),
        ("n_contact", |w| w.n_contact),
        ("n_slide", |w| w.n_slide),
        ("Q_statics", |w| w.q_statics),
        ("Q_printed", |w| w.q_printed),
        ("Y_theory", |w| w.y_theory),
        ("Q_lean", |w| w.q_lean),
    ];
    let wheels = PyDict::new(py);
    for (key, f) in fields {
        let v: Vec<f64> = r
            .samples
            .iter()
            .flat_map(|s| s.wheels.iter().map(f))
            .collect();
        let a = Array2::from_shape_vec((n, nw), v)
            .map_err(|e| pyo3::exceptions::PyValueError::new_err(e.to_string()))?;
        wheels.set_item(key, a.into_pyarray(py))?;
    }
    d.set_item("wheels", wheels)?;
    let m = PyDict::new(py);
    m.set_item("max_rel_normal_statics", r.max_rel_normal_statics)?;
    m.set_item("max_rel_shear", r.max_rel_shear)?;
    m.set_item("max_rel_shear_wheel", r.max_rel_shear_wheel)?;
    m.set_item("max_rel_normal_printed", r.max_rel_normal_printed)?;
    m.set_item("max_rel_normal_lean", r.max_rel_normal_lean)?;
    m.set_item("arc_mean_normal_inner", r.arc_mean_normal[0])?;
    m.set_item("arc_mean_normal_outer", r.arc_mean_normal[1])?;
    m.set_item("contact_spacing", r.contact_spacing)?;
    m.set_item("first_slide", r.first_slide)?;
    m.set_item("first_separation", r.first_separation)?;
    d.set_item("metrics", m)?;
    let s = PyDict::new(py);
    s.set_item("steps", r.steps)?;
    s.set_item("iterations", r.iterations)?;
    s.set_item("wall", r.wall)?;
    d.set_item("stats", s)?;
    d.set_item("energy_summary", r.energy_summary)?;
    Ok(d)
}

/// One critical-radius run (a point of Fig. 7 for `criterion="sliding"`, Fig. 9 for
/// `"separation"`); with `out`, the cross-sections at the onset are drawn there.
#[pyfunction]
#[pyo3(signature = (*, criterion = "sliding", speed = 120.0, ct = 200.0, mu = 0.3,
    clothoid = 2000.0, dt = 0.01, geometry = "linear", out = None))]
#[allow(clippy::too_many_arguments)]
pub fn critical_radius<'py>(
    py: Python<'py>,
    criterion: &str,
    speed: f64,
    ct: f64,
    mu: f64,
    clothoid: f64,
    dt: f64,
    geometry: &str,
    out: Option<PathBuf>,
) -> PyResult<Bound<'py, PyAny>> {
    use railfem::critical::{Criterion, CriticalCase};
    let criterion = match criterion {
        "sliding" => Criterion::Sliding,
        "separation" => Criterion::Separation,
        o => {
            return Err(to_py_err(FemError::input(
                "critical_radius()",
                format!("criterion={o:?}: use \"sliding\" or \"separation\""),
            )))
        }
    };
    let case = CriticalCase {
        criterion,
        speed,
        ct,
        mu,
        clothoid,
        dt,
        geometry: self::geometry(geometry, "critical_radius()")?,
        tangential: Default::default(),
        polach_spin: None,
    };
    let r = guarded(py, || {
        railfem::critical::run_with_sections(&case, out.as_deref())
    })?
    .map_err(to_py_err)?;
    let d = value::serialize_to_py(py, &r)?;
    d.set_item("case", value::serialize_to_py(py, &case)?)?;
    Ok(d)
}

/// The train on a viaduct (`railfem train-bridge`). The defaults are the command's: the
/// 1M-DOF case (12 cars, 113 spans); give `cars`, `spans` (and `steps`) for a small one.
#[pyfunction]
#[pyo3(signature = (*, cars = None, spans = None, span = None, element_length = None,
    dof = None, speed = None, radius = None, ct = None, duration = None, dt = None,
    record_every = None, pier_height = None, midspans = None, quake = None, seed = 1,
    pga = 0.3, quake_duration = 30.0, geometry = "linear", steps = None, out = None))]
#[allow(clippy::too_many_arguments)]
pub fn train_bridge<'py>(
    py: Python<'py>,
    cars: Option<usize>,
    spans: Option<usize>,
    span: Option<f64>,
    element_length: Option<f64>,
    dof: Option<usize>,
    speed: Option<f64>,
    radius: Option<f64>,
    ct: Option<f64>,
    duration: Option<f64>,
    dt: Option<f64>,
    record_every: Option<usize>,
    pier_height: Option<f64>,
    midspans: Option<Vec<usize>>,
    quake: Option<PathBuf>,
    seed: u64,
    pga: f64,
    quake_duration: f64,
    geometry: &str,
    steps: Option<usize>,
    out: Option<PathBuf>,
) -> PyResult<Bound<'py, PyDict>> {
    use railfem::train_bridge::{build, run, Quake, TrainBridgeCase};
    let mut c = TrainBridgeCase::default();
    let whole = |key: &str, v: Option<usize>| -> PyResult<Option<usize>> {
        match v {
            Some(0) => Err(to_py_err(FemError::input(
                "train_bridge()",
                format!("{key}=0: give a whole number ≥ 1"),
            ))),
            v => Ok(v),
        }
    };
    if let Some(v) = whole("cars", cars)? {
        c.cars = v;
    }
    if let Some(v) = whole("spans", spans)? {
        c.spans = v;
    }
    if let Some(v) = span {
        c.span = v;
    }
    if let Some(v) = element_length {
        c.element_length = v;
    }
    c.dof_target = whole("dof", dof)?;
    if let Some(v) = speed {
        c.speed = v;
    }
    c.radius = radius;
    if let Some(v) = ct {
        c.ct = v;
    }
    c.duration = duration;
    if let Some(v) = dt {
        c.dt = v;
    }
    if let Some(v) = whole("record_every", record_every)? {
        c.record_every = v;
    }
    if let Some(v) = pier_height {
        c.pier_height = v;
    }
    if let Some(v) = midspans {
        c.midspans = v;
    }
    c.geometry = self::geometry(geometry, "train_bridge()")?;
    c.quake = match quake {
        None => Quake::None,
        Some(q) if q == std::path::Path::new("synthetic") => Quake::Synthetic {
            seed,
            pga,
            duration: quake_duration,
        },
        Some(file) => Quake::File(file),
    };
    let steps = whole("steps", steps)?;
    let (m, r) = guarded(py, || -> Result<_, FemError> {
        let mut m = build(&c)?;
        let r = run(&mut m, &c, steps, out.as_deref())?;
        Ok((
            (
                m.dofs,
                m.elements,
                m.nodes,
                m.element_length,
                m.build_seconds,
            ),
            r,
        ))
    })?
    .map_err(to_py_err)?;
    let d = PyDict::new(py);
    d.set_item("dofs", m.0)?;
    d.set_item("elements", m.1)?;
    d.set_item("nodes", m.2)?;
    d.set_item("element_length", m.3)?;
    d.set_item("build_seconds", m.4.to_vec())?;
    d.set_item("wheel_names", r.wheel_names.clone())?;
    d.set_item("q_static", r.q_static.clone().into_pyarray(py))?;
    let col = |f: fn(&railfem::train_bridge::WheelExtremes) -> f64| {
        r.wheels
            .iter()
            .map(f)
            .collect::<Vec<f64>>()
            .into_pyarray(py)
    };
    let w = PyDict::new(py);
    w.set_item("max_yq", col(|e| e.max_yq.0))?;
    w.set_item("t_max_yq", col(|e| e.max_yq.1))?;
    w.set_item("max_dqq", col(|e| e.max_dqq.0))?;
    w.set_item("t_max_dqq", col(|e| e.max_dqq.1))?;
    w.set_item("min_q", col(|e| e.min_q.0))?;
    w.set_item("t_min_q", col(|e| e.min_q.1))?;
    w.set_item("mean_q", col(|e| e.mean_q))?;
    d.set_item("wheels", w)?;
    let spans = PyDict::new(py);
    for (k, rows) in &r.midspan {
        let t: Vec<f64> = rows.iter().map(|x| x.0).collect();
        let v: Vec<f64> = rows.iter().map(|x| x.1).collect();
        spans.set_item(
            k,
            table(py, "midspan.csv", vec!["deflection".into()], t, v)?,
        )?;
    }
    d.set_item("midspan", spans)?;
    let s = PyDict::new(py);
    s.set_item("steps", r.steps)?;
    s.set_item("iterations", r.iterations)?;
    s.set_item("wall", r.wall)?;
    d.set_item("stats", s)?;
    Ok(d)
}

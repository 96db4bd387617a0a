//! The cases of a study: the Cartesian product of the plan's axes, each with a stable id
//! (its index in the product, first axis slowest, zero-padded), the mapping of an axis value
//! onto the base case (a case key, or a dotted key path of a model file), a cost estimate
//! for handing out the longest cases first, and the plan's fingerprint that a checkpoint
//! must match.

use super::plan::{AxisValue, Base, Plan};
use crate::curve::CurveCase;
use crate::framework::FemError;
use crate::train_bridge::{Quake, TrainBridgeCase};
use serde_json::Value;

/// One case of a study.
#[derive(Debug, Clone, PartialEq)]
pub struct Case {
    /// Index in the Cartesian product (first axis slowest).
    pub index: usize,
    /// The stable id: the index, zero-padded to the width of the largest.
    pub id: String,
    /// One value per axis, in the plan's axis order.
    pub values: Vec<AxisValue>,
}

/// Every case of `plan`, in id order.
pub fn expand(plan: &Plan) -> Vec<Case> {
    let total: usize = plan.axes.iter().map(|a| a.values.len()).product();
    let width = (total.saturating_sub(1)).to_string().len().max(4);
    (0..total)
        .map(|index| {
            let mut rest = index;
            let mut values = vec![AxisValue::Num(0.0); plan.axes.len()];
            for (k, axis) in plan.axes.iter().enumerate().rev() {
                let n = axis.values.len();
                values[k] = axis.values[rest % n].clone();
                rest /= n;
            }
            Case {
                index,
                id: format!("{index:0width$}"),
                values,
            }
        })
        .collect()
}

/// The (key, value) settings of a case: the plan's options, then its axis values.
pub fn settings<'a>(plan: &'a Plan, case: &'a Case) -> Vec<(&'a str, &'a AxisValue)> {
    plan.options
        .iter()
        .map(|(k, v)| (k.as_str(), v))
        .chain(plan.axes.iter().map(|a| a.name.as_str()).zip(&case.values))
        .collect()
}

fn num(key: &str, v: &AxisValue) -> Result<f64, FemError> {
    match v {
        AxisValue::Num(x) => Ok(*x),
        other => Err(FemError::input(
            "study case",
            format!("`{key}` = {}: give a number", other.label()),
        )),
    }
}

fn count(key: &str, v: &AxisValue) -> Result<usize, FemError> {
    let x = num(key, v)?;
    if x >= 1.0 && x.fract() == 0.0 && x < 1e9 {
        Ok(x as usize)
    } else {
        Err(FemError::input(
            "study case",
            format!("`{key}` = {x}: give a whole number ≥ 1"),
        ))
    }
}

/// A train–bridge case with its ground motion resolved: the record read (file) or made
/// (synthetic seed), times `quake_scale`.
pub fn train_bridge(plan: &Plan, case: &Case) -> Result<TrainBridgeCase, FemError> {
    let mut c = TrainBridgeCase::default();
    let (mut record, mut seed, mut pga, mut qdur, mut scale) = (None, None, 0.3, 30.0, 1.0);
    let mut synthetic = false;
    let (mut window, mut ahead, mut tolerance) = (None, None, None);
    let (mut layer, mut layer_damping) = (None, None);
    let (mut far_field, mut far_cutoff, mut far_reach) = (None, None, None);
    for (k, v) in settings(plan, case) {
        match k {
            "cars" => c.cars = count(k, v)?,
            "spans" => c.spans = count(k, v)?,
            "span" => c.span = num(k, v)?,
            "element_length" => c.element_length = num(k, v)?,
            "speed" => c.speed = num(k, v)?,
            "radius" => c.radius = Some(num(k, v)?),
            "ct" => c.ct = num(k, v)?,
            "duration" => c.duration = Some(num(k, v)?),
            "dt" => c.dt = num(k, v)?,
            "pier_height" => c.pier_height = num(k, v)?,
            "mu" => c.mu = num(k, v)?,
            "penalty" => c.penalty = num(k, v)?,
            "quake" => match v {
                AxisValue::Record(p) => record = Some(p.clone()),
                AxisValue::Text(t) if t == "synthetic" => synthetic = true,
                other => {
                    return Err(FemError::input(
                        "study case",
                        format!(
                            "`quake` = {}: give a CSV record or \"synthetic\"",
                            other.label()
                        ),
                    ))
                }
            },
            "quake_scale" => scale = num(k, v)?,
            "seed" => seed = Some(num(k, v)?),
            "pga" => pga = num(k, v)?,
            "quake_duration" => qdur = num(k, v)?,
            "midspans" => {
                let text = match v {
                    AxisValue::Num(x) => format!("{x}"),
                    other => other.label(),
                };
                c.midspans = text
                    .split(',')
                    .map(|x| x.trim().parse::<usize>())
                    .collect::<Result<_, _>>()
                    .map_err(|_| {
                        FemError::input(
                            "study case",
                            format!("`midspans` = {text}: give span numbers (1-based)"),
                        )
                    })?;
            }
            "first_active_set" => c.first_active_set = first_active_set(v)?,
            "solver" => c.solver = solver(v)?,
            "window" => window = Some(v.label()),
            "window_ahead" => ahead = Some(num(k, v)?),
            "window_tolerance" => tolerance = Some(num(k, v)?),
            "window_layer" => layer = Some(num(k, v)?),
            "window_layer_damping" => layer_damping = Some(num(k, v)?),
            "far_field" => far_field = Some(v.label()),
            "far_field_cutoff" => far_cutoff = Some(num(k, v)?),
            "far_field_reach" => far_reach = Some(num(k, v)?),
            _ => unreachable!("plan.rs admits only train-bridge keys"),
        }
    }
    if !(scale.is_finite() && scale >= 0.0) {
        return Err(FemError::input(
            "study case",
            format!("`quake_scale` = {scale}: give a factor ≥ 0"),
        ));
    }
    let mut rec = match (record, synthetic || seed.is_some()) {
        (Some(p), false) => Some(crate::train_bridge::read_quake(&p)?),
        (Some(p), true) => {
            return Err(FemError::input(
                "study case",
                format!(
                "`quake` = {} and a synthetic motion (`seed` or quake = \"synthetic\"): give one",
                p.display()
            ),
            ))
        }
        (None, true) => {
            let s = seed.unwrap_or(1.0);
            if !(s >= 0.0 && s.fract() == 0.0 && s < 1e15) {
                return Err(FemError::input(
                    "study case",
                    format!("`seed` = {s}: give a whole number ≥ 0"),
                ));
            }
            if !(pga.is_finite() && pga >= 0.0 && qdur > 0.0 && qdur <= 1e4) {
                return Err(FemError::input(
                    "study case",
                    format!("`pga` = {pga}, `quake_duration` = {qdur}: give pga ≥ 0 g and 0 < duration ≤ 10000 s"),
                ));
            }
            Some(crate::train_bridge::synthetic_quake(s as u64, pga, qdur))
        }
        (None, false) => None,
    };
    if let Some(r) = rec.as_mut() {
        for col in r.a.iter_mut() {
            for x in col.iter_mut() {
                *x *= scale;
            }
        }
    }
    c.quake = rec.map_or(Quake::None, Quake::Record);
    c.window = crate::train_window::parse_options(
        crate::train_window::STUDY,
        window.as_deref(),
        ahead,
        tolerance,
    )?;
    c.window_layer = crate::train_window::parse_layer(
        crate::train_window::STUDY,
        c.window,
        layer,
        layer_damping,
    )?;
    c.far_field = crate::far_field::parse(
        crate::far_field::STUDY,
        far_field.as_deref(),
        far_cutoff,
        far_reach,
    )?;
    c.record_every = 1;
    Ok(c)
}

/// The `first_active_set` value of a case: `committed` or `found`.
fn first_active_set(v: &AxisValue) -> Result<crate::framework::model::FirstActiveSet, FemError> {
    let t = v.label();
    crate::framework::model::FirstActiveSet::parse(&t).ok_or_else(|| {
        FemError::input(
            "study case",
            format!("`first_active_set` = {t}: use committed or found"),
        )
    })
}

/// The `solver` value of a case: as `railfem train-bridge --solver`.
fn solver(v: &AxisValue) -> Result<crate::framework::model::SolverChoice, FemError> {
    let t = v.label();
    crate::framework::model::SolverChoice::parse(&t).ok_or_else(|| {
        FemError::input(
            "study case",
            format!("`solver` = {t}: use auto (the default), direct, partitioned or low_rank"),
        )
    })
}

/// A curve case.
pub fn curve(plan: &Plan, case: &Case) -> Result<CurveCase, FemError> {
    let mut c = CurveCase::default();
    for (k, v) in settings(plan, case) {
        match k {
            "radius" => c.radius = num(k, v)?,
            "ct" => c.ct = num(k, v)?,
            "speed" => c.speed = num(k, v)?,
            "mu" => c.mu = num(k, v)?,
            "dt" => c.dt = num(k, v)?,
            "penalty" => c.penalty = num(k, v)?,
            "duration" => c.duration = num(k, v)?,
            "anti_roll" => c.anti_roll = num(k, v)?,
            "lengths" => {
                let t = v.label();
                let l: Vec<f64> = t
                    .split(',')
                    .filter_map(|x| x.trim().parse::<f64>().ok())
                    .filter(|x| x.is_finite() && *x > 0.0)
                    .collect();
                c.lengths = l.try_into().map_err(|_| {
                    FemError::input(
                        "study case",
                        format!("`lengths` = {t}: give five lengths > 0 m"),
                    )
                })?;
            }
            "tangential" => {
                c.tangential = crate::choice::parse("study case", "`tangential` =", &v.label())?;
            }
            "geometry" => {
                let t = v.label();
                c.geometry = crate::framework::model::Geometry::parse(&t).map_err(|_| {
                    FemError::input(
                        "study case",
                        format!("`geometry` = {t}: use linear or nonlinear"),
                    )
                })?;
            }
            "first_active_set" => c.first_active_set = first_active_set(v)?,
            _ => unreachable!("plan.rs admits only curve keys"),
        }
    }
    Ok(c)
}

/// The base model with the case's axis values set at their key paths.
pub fn model_value(base: &Value, plan: &Plan, case: &Case) -> Value {
    let mut v = base.clone();
    for (axis, value) in plan.axes.iter().zip(&case.values) {
        let mut at = &mut v;
        for part in axis.name.split('.') {
            at = match at {
                Value::Object(o) => o.get_mut(part).expect("checked by plan.rs"),
                Value::Array(a) => &mut a[part.parse::<usize>().expect("checked by plan.rs")],
                _ => unreachable!("checked by plan.rs"),
            };
        }
        *at = value.json();
    }
    v
}

/// A relative cost of a case (time steps times a size), to hand out the longest first.
pub fn cost(plan: &Plan, case: &Case) -> f64 {
    match &plan.base {
        Base::TrainBridge => match train_bridge_estimate(plan, case) {
            Some((steps, size)) => steps * size,
            None => 0.0,
        },
        Base::Curve => curve(plan, case).map_or(0.0, |c| c.steps_estimate() as f64),
        Base::Model { value, .. } => {
            let v = model_value(value, plan, case);
            let a = v.get("analysis");
            let get = |k: &str| a.and_then(|a| a.get(k)).and_then(Value::as_f64);
            match (get("duration"), get("dt")) {
                (Some(d), Some(dt)) if dt > 0.0 => d / dt,
                _ => 1.0,
            }
        }
    }
}

/// Steps and a size measure of a train–bridge case, without reading any record.
fn train_bridge_estimate(plan: &Plan, case: &Case) -> Option<(f64, f64)> {
    let mut c = TrainBridgeCase::default();
    let mut scale = 1.0;
    for (k, v) in settings(plan, case) {
        let x = match v {
            AxisValue::Num(x) => *x,
            _ => continue,
        };
        match k {
            "cars" => c.cars = x as usize,
            "spans" => c.spans = x as usize,
            "span" => c.span = x,
            "element_length" => c.element_length = x,
            "speed" => c.speed = x,
            "duration" => c.duration = Some(x),
            "dt" => c.dt = x,
            // Stronger shaking takes more Newton iterations per step.
            "quake_scale" => scale = 1.0 + x,
            _ => {}
        }
    }
    let len = c.spans as f64 * c.span + c.cars as f64 * 25.0 + 15.0;
    let duration = c.duration.unwrap_or(len / c.speed);
    // Every fastener is a node: each bay gets ceil(spacing / element_length) elements.
    let spacing = crate::elements::rail::geometry::bridge::SlabTrack::default().fastener_spacing;
    let per_metre = (spacing / c.element_length).ceil() / spacing;
    let size = (2.0 * c.approach() + c.spans as f64 * c.span) * per_metre + 66.0 * c.cars as f64;
    Some((duration / c.dt * scale, size))
}

/// A value with its kind, independent of the folder the plan was read from.
fn tagged(v: &AxisValue) -> String {
    match v {
        AxisValue::Num(x) => format!("n{x}"),
        AxisValue::Text(t) => format!("t{t}"),
        AxisValue::Record(_) => format!("r{}", v.label()),
    }
}

/// FNV-1a, 64 bits: a fingerprint that is the same on every machine and every run.
pub fn fnv1a(bytes: &[u8]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for b in bytes {
        h ^= u64::from(*b);
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    h
}

/// The fingerprint of what a study computes: the base (case name or model contents), the
/// options, every case's values and the bytes of every record file. A checkpoint written
/// under another fingerprint belongs to another plan.
pub fn fingerprint(plan: &Plan, cases: &[Case]) -> Result<u64, FemError> {
    let mut s = String::new();
    match &plan.base {
        Base::Model { value, .. } => s.push_str(&value.to_string()),
        b => s.push_str(&b.name()),
    }
    s.push_str(&format!("|histories={}|", plan.histories));
    for (k, v) in &plan.options {
        s.push_str(&format!("{k}={};", tagged(v)));
    }
    for a in &plan.axes {
        s.push_str(&format!("axis {}:", a.name));
        for v in &a.values {
            s.push_str(&format!("{};", tagged(v)));
        }
    }
    s.push_str(&format!("|{} cases", cases.len()));
    let mut h = fnv1a(s.as_bytes());
    let mut records: Vec<&std::path::PathBuf> = plan
        .options
        .iter()
        .map(|(_, v)| v)
        .chain(plan.axes.iter().flat_map(|a| &a.values))
        .filter_map(|v| match v {
            AxisValue::Record(p) => Some(p),
            _ => None,
        })
        .collect();
    records.sort();
    records.dedup();
    for p in records {
        let bytes = std::fs::read(p).map_err(|e| {
            FemError::input(
                p.display().to_string(),
                format!("cannot read the record ({e}); give a readable CSV file"),
            )
        })?;
        h ^= fnv1a(&bytes);
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    Ok(h)
}

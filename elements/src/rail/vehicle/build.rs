//! The generic builder: a train of [`VehicleDef`]s into a model — master nodes with `mass`
//! elements, suspensions (`spring_damper` between rigidly linked slave nodes in linear
//! geometry, `suspension` between masters with preloads in nonlinear geometry), anti-roll
//! bars, couplers, wheel elements, sensor nodes and the one carrier of the train.
//!
//! **Order.** Vehicles front to back; in a vehicle, bodies in their listed order. After a
//! body's node and mass come: a wheelset's spin spring; the coupler to the vehicle in front
//! (after the coupler body); every suspension, then every anti-roll bar, whose later-listed
//! body is this one (in listed order); a wheelset's two wheel elements (left, right).
//! Sensor nodes come after every vehicle. A slave node is made on the upper body first.
//!
//! **Positions.** Vehicle centres are at `start − i·L` (equal lengths) or spaced by the mean
//! of consecutive lengths. A body's node is carried at station `s_v + x` and offset
//! `[y, z, 0]` in the wheel frame (axis 1 left, 2 up, 3 forwards); a slave node of a body at
//! its body's station with offset `[y, z, Δs]`, Δs the attachment's station less the
//! body's. Springs act in the lower body's axes (vehicle x, y, z = element axes 3, 1, 2).

use super::definition::{VehicleDef, VehicleDirection, WheelModel};
use super::statics;
use super::track_model::TrackModel;
use super::{TrainIds, SPIN_STIFFNESS};
use crate::suspension::SuspensionTangent;
use railfem_framework::builder::ModelBuilder;
use railfem_framework::error::FemError;
use railfem_framework::limits::fmt_num;
use railfem_framework::model::Geometry;
use railfem_framework::moving::{Carrier, Path};
use railfem_framework::registry::ElementSpec;
use railfem_framework::speed::SpeedHistory;
use railfem_framework::DofSet;
use serde::Serialize;
use serde_json::{json, Map, Value};
use std::collections::BTreeMap;
use std::sync::Arc;

/// Half the width of a 60E1 rail head (m): a contact point farther than this from the rail
/// line is not over the rail head.
pub const HALF_HEAD_WIDTH: f64 = 0.036;
/// Default contact offset of a wheel (m), the moving-axle default.
pub const DEFAULT_CONTACT_OFFSET: f64 = 0.75;

/// Coupler rates and dashpots in vehicle axes x, y, z (N/m, N·s/m).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CouplerDef {
    /// Stiffnesses [kx, ky, kz] (N/m).
    #[serde(default = "default_coupler_k")]
    pub k: [f64; 3],
    /// Dashpots [cx, cy, cz] (N·s/m).
    #[serde(default = "default_coupler_c")]
    pub c: [f64; 3],
}

fn default_coupler_k() -> [f64; 3] {
    [5e7, 1e5, 1e5]
}
fn default_coupler_c() -> [f64; 3] {
    [1e5, 1e4, 1e4]
}

impl Default for CouplerDef {
    fn default() -> Self {
        CouplerDef {
            k: default_coupler_k(),
            c: default_coupler_c(),
        }
    }
}

/// A train of generic vehicles and its motion.
#[derive(Debug, Clone, PartialEq)]
pub struct Train {
    /// Name (messages, carrier).
    pub name: String,
    /// Vehicles front to back, normalized ([`VehicleDef::normalized`]).
    pub vehicles: Vec<VehicleDef>,
    /// Couplers between consecutive vehicles.
    pub coupler: CouplerDef,
    /// Station of the first vehicle's centre at t = 0 (m).
    pub start: f64,
    /// Speed at t = 0 (m/s).
    pub speed: f64,
    /// Acceleration (m/s²); a deceleration brings the train to rest and holds it there.
    pub accel: f64,
    /// Speed table `[[t s, v m/s], …]` replacing `speed` and `accel` (piecewise-linear
    /// speed from `start`; [`SpeedHistory`]).
    pub speed_table: Option<Vec<[f64; 2]>>,
    /// Wheel keys for every wheel (override the wheelsets' own).
    pub wheel: Map<String, Value>,
    /// First node id.
    pub first_node_id: u64,
    /// Geometry; default the model's.
    pub geometry: Option<Geometry>,
    /// Tangent of nonlinear suspensions.
    pub suspension_tangent: SuspensionTangent,
}

/// Vehicle-axes directions to element keys: `spring_damper` (ux lateral, uy vertical,
/// uz longitudinal) and `suspension` (1, 2, 3).
fn element_direction(d: VehicleDirection, nonlinear: bool) -> &'static str {
    use VehicleDirection as D;
    let (lin, nl) = match d {
        D::X => ("uz", "3"),
        D::Y => ("ux", "1"),
        D::Z => ("uy", "2"),
        // Rotations: spring_damper only (refused on nonlinear suspensions before this).
        D::Rx => ("rz", "rz"),
        D::Ry => ("rx", "rx"),
        D::Rz => ("ry", "ry"),
    };
    if nonlinear {
        nl
    } else {
        lin
    }
}

/// A table keyed by vehicle directions as the element's parameter, keyed by its own.
fn remap<T: Serialize>(m: &BTreeMap<VehicleDirection, T>, nonlinear: bool) -> Value {
    Value::Object(
        m.iter()
            .map(|(&d, v)| (element_direction(d, nonlinear).to_string(), json!(v)))
            .collect(),
    )
}

fn mass_params(b: &super::definition::BodyDef) -> Value {
    // Wheel-frame axes: 1 lateral (pitch), 2 vertical (yaw), 3 longitudinal (roll). Vehicle
    // products map as ∫x·y → ∫3·1 (Ixz), ∫y·z → ∫1·2 (Ixy), ∫x·z → ∫3·2 (Iyz).
    let mut p = json!({"m": b.mass, "inertia": [b.iyy, b.izz, b.ixx]});
    if b.ixy != 0.0 || b.iyz != 0.0 || b.ixz != 0.0 {
        p["Ixz"] = json!(b.ixy);
        p["Ixy"] = json!(b.iyz);
        p["Iyz"] = json!(b.ixz);
    }
    p
}

/// Checks the train against the track before building: every wheel must start on the rail
/// mesh and over a rail head. `Err((place, message))`.
fn check_on_track(train: &Train, track: &TrackModel, s_v: &[f64]) -> Result<(), (String, String)> {
    let (Some(&lo), Some(&hi)) = (track.stations.first(), track.stations.last()) else {
        return Err((String::new(), "the track has no rail mesh".into()));
    };
    for (vi, v) in train.vehicles.iter().enumerate() {
        for (wi, w) in v.wheelsets.iter().enumerate() {
            let x = v.bodies[v.body_index(&w.body).expect("validated")].x;
            let s = train.start + s_v[vi] + x;
            if !(lo..=hi).contains(&s) {
                return Err((
                    format!("vehicle {vi}, wheelset[{wi}] (body \"{}\")", w.body),
                    format!(
                        "`start` = {}: the wheelset starts at station {} m but the rail mesh covers {lo:.3} to {hi:.3} m; move `start` or lengthen the track",
                        fmt_num(train.start),
                        fmt_num(s)
                    ),
                ));
            }
            let b = w.contact_offset.unwrap_or(DEFAULT_CONTACT_OFFSET);
            for (r, rail) in track.rails.iter().enumerate() {
                let off = rail.offset.abs();
                if (b - off).abs() > HALF_HEAD_WIDTH {
                    return Err((
                        format!("vehicle {vi}, wheelset[{wi}] (body \"{}\")", w.body),
                        format!(
                            "`contact_offset` = {} m puts the {} wheel {} m from the rail line at {} m, off the rail head (±{HALF_HEAD_WIDTH} m); give a contact offset within the head",
                            fmt_num(b),
                            ["left", "right"][r],
                            fmt_num((b - off).abs()),
                            fmt_num(off)
                        ),
                    ));
                }
            }
        }
    }
    Ok(())
}

/// Builds the train into `b`; `origin` names the place (`"m.toml: [vehicle][0]"`).
pub fn build(
    b: &mut ModelBuilder,
    track: &Arc<TrackModel>,
    train: &Train,
    origin: &str,
) -> Result<TrainIds, FemError> {
    let fail = |place: &str, m: &str| {
        if place.is_empty() {
            FemError::input(origin, m)
        } else {
            FemError::input(format!("{origin} {place}"), m)
        }
    };
    if train.vehicles.is_empty() {
        return Err(fail("", "the train has no vehicles; give at least one"));
    }
    if !(train.speed.is_finite() && train.start.is_finite() && train.accel.is_finite()) {
        return Err(fail("", "`speed`, `start` and `accel` must be finite"));
    }
    let train_speed_table = match &train.speed_table {
        Some(rows) => Some(Arc::new(
            SpeedHistory::from_table(train.start, rows, "speed_table").map_err(|m| fail("", &m))?,
        )),
        None => None,
    };
    for (vi, v) in train.vehicles.iter().enumerate() {
        v.validate()
            .map_err(|(p, m)| fail(&format!("vehicle {vi}, {p}"), &m))?;
    }
    for (k, name) in [(train.coupler.k, "k"), (train.coupler.c, "c")] {
        if k.iter().any(|v| !(v.is_finite() && *v >= 0.0)) {
            return Err(fail(
                "coupler",
                &format!("`{name}` needs three finite values ≥ 0"),
            ));
        }
    }
    // Size guard: six DOFs per body and six per wheel's contact nodes.
    let dofs: usize = train.vehicles.iter().map(VehicleDef::dofs).sum();
    railfem_framework::limits::check_memory(
        &format!("{} vehicles", train.vehicles.len()),
        dofs as f64,
        "vehicle DOFs",
        railfem_framework::limits::BYTES_PER_DOF,
        "give fewer vehicles",
    )
    .map_err(|m| fail("", &m))?;
    // Vehicle centres relative to the first.
    let equal = train
        .vehicles
        .iter()
        .all(|v| v.length == train.vehicles[0].length);
    let mut s_v = Vec::with_capacity(train.vehicles.len());
    for (i, v) in train.vehicles.iter().enumerate() {
        let s = if i == 0 {
            -0.0
        } else if equal {
            -(i as f64) * v.length
        } else {
            s_v[i - 1] - 0.5 * (train.vehicles[i - 1].length + v.length)
        };
        s_v.push(s);
    }
    check_on_track(train, track, &s_v).map_err(|(p, m)| fail(&p, &m))?;
    let geometry = train.geometry.unwrap_or(b.analysis_mut().geometry);
    let nonlinear = geometry == Geometry::Nonlinear;
    let g = b
        .analysis_mut()
        .gravity
        .map_or(0.0, |v| (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt());
    // The train's `wheel.model`, if given, overrides every wheelset's (each validated).
    let train_model = WheelModel::of(&train.wheel).map_err(|m| fail("", &m))?;
    let model_of = |w: &super::definition::WheelsetDef| -> WheelModel {
        if train.wheel.contains_key("model") {
            train_model
        } else {
            WheelModel::of(&w.wheel).unwrap_or_default()
        }
    };
    // Static state where it is needed: preloads of suspensions without `carries` in
    // nonlinear geometry, static loads of wheels other than moving_axle (which measures its
    // own at the first converged state).
    let mut states: Vec<Option<statics::StaticState>> = Vec::new();
    for (vi, v) in train.vehicles.iter().enumerate() {
        let need = (nonlinear && v.suspensions.iter().any(|s| s.carries.is_none()))
            || v.wheelsets
                .iter()
                .any(|w| model_of(w) != WheelModel::MovingAxle);
        if !need {
            states.push(None);
            continue;
        }
        let offsets: Vec<f64> = v
            .wheelsets
            .iter()
            .map(|w| w.contact_offset.unwrap_or(DEFAULT_CONTACT_OFFSET))
            .collect();
        let st = statics::solve(v, g, &offsets).map_err(|m| fail(&format!("vehicle {vi}"), &m))?;
        states.push(Some(st));
    }

    let mut next_node = train.first_node_id.max((b.max_node_id() / 1000 + 1) * 1000);
    let mut next_elem = (b.max_element_id() / 1000 + 1) * 1000;
    let mut carried: Vec<(u64, f64, [f64; 3])> = Vec::new();
    let mut ids = TrainIds::default();
    let path = track.track.clone();
    let start = train.start;
    // A node at (station offset ds, lateral, vertical, longitudinal); positions at t = 0.
    let mut add_node = |b: &mut ModelBuilder,
                        carried: &mut Vec<(u64, f64, [f64; 3])>,
                        ds: f64,
                        off: [f64; 3]|
     -> u64 {
        next_node += 1;
        let p = path.at(start + ds);
        let x = p.position
            + p.frame.column(0) * off[0]
            + p.frame.column(1) * off[1]
            + p.frame.column(2) * off[2];
        b.node(next_node, [x.x, x.y, x.z]);
        carried.push((next_node, ds, off));
        next_node
    };
    // An element of `kind`; a wheel (`wheel` = Some(side)) is named after the vehicle's
    // `wheel` table, where its keys come from.
    let mut elem =
        |b: &mut ModelBuilder, kind: &str, nodes: &[u64], p: Value, wheel: Option<&str>| {
            next_elem += 1;
            match (p, wheel) {
                (Value::Object(params), Some(side)) => {
                    let origin =
                        format!("{origin}: `wheel` (element {next_elem}, {kind}, {side} wheel)");
                    b.element_spec(ElementSpec {
                        id: next_elem,
                        kind: kind.into(),
                        nodes: nodes.to_vec(),
                        params,
                        origin,
                    });
                }
                (p, _) => {
                    b.element(kind, next_elem, nodes, &p);
                }
            }
            next_elem
        };
    let tangent = train.suspension_tangent;
    // `suspension` keys between master `lower` and master `upper` (each (station offset,
    // height)), attached at `at` = (lateral, height, station offset); k, c, k_rot in element
    // axes.
    let body_spring = |lower: (f64, f64),
                       upper: (f64, f64),
                       at: [f64; 3],
                       k: [f64; 3],
                       cd: [f64; 3],
                       preload: f64,
                       k_rot: [f64; 3]| {
        let [lat, h, s_at] = at;
        json!({
            "offset_i": [lat, h - lower.1, s_at - lower.0],
            "offset_j": [lat, h - upper.1, s_at - upper.0],
            "j_from_i": [0.0, upper.1 - lower.1, upper.0 - lower.0],
            "k": k, "c": cd, "preload": [0.0, -preload, 0.0],
            "k_rot": k_rot, "tangent": tangent,
        })
    };
    let mut prev: Option<(u64, f64, f64, f64)> = None; // coupler body: node, station, height, length
    let mut masters: Vec<Vec<u64>> = Vec::new();
    for (vi, v) in train.vehicles.iter().enumerate() {
        let sv = s_v[vi];
        let n = v.bodies.len();
        let idx = |name: &str| v.body_index(name).expect("validated");
        let coupler_body = v.coupler_body.as_deref().map_or(0, idx);
        let station = |i: usize| sv + v.bodies[i].x;
        let mut node = vec![0u64; n];
        let completes = |a: &str, c: &str, i: usize| idx(a).max(idx(c)) == i;
        for i in 0..n {
            let bd = &v.bodies[i];
            let k = add_node(b, &mut carried, station(i), [bd.y, bd.z, 0.0]);
            node[i] = k;
            elem(b, "mass", &[k], mass_params(bd), None);
            let wheelset = v.wheelsets.iter().position(|w| w.body == bd.name);
            if wheelset.is_some() {
                // Spin about the axle (axis 1): rolling along the rail is a free motion
                // whose only static stiffness is the contact penalty times micrometre
                // offsets, so a static solve would be singular; a weak spring on the spin
                // deviation makes it well posed, far below every other stiffness.
                elem(
                    b,
                    "spring_damper",
                    &[k],
                    json!({"k": [0.0, 0.0, 0.0, SPIN_STIFFNESS, 0.0, 0.0]}),
                    None,
                );
                ids.wheelsets.push(k);
                ids.wheelset_offsets.push(station(i));
            }
            if i == coupler_body {
                ids.car_bodies.push(k);
                if let Some((pk, ps, ph, pl)) = prev {
                    // Coupler between the car ends, at the mean of the two bodies' heights.
                    let (s_car, h_car) = (station(i), bd.z);
                    let h = 0.5 * (ph + h_car);
                    let (half_prev, half) = (0.5 * pl, 0.5 * v.length);
                    let cp = &train.coupler;
                    let (ke, ce) = ([cp.k[1], cp.k[2], cp.k[0]], [cp.c[1], cp.c[2], cp.c[0]]);
                    if nonlinear {
                        let at = [0.0, h, s_car + half];
                        let p = body_spring((ps, ph), (s_car, h_car), at, ke, ce, 0.0, [0.0; 3]);
                        elem(b, "suspension", &[pk, k], p, None);
                    } else {
                        let a = add_node(b, &mut carried, ps, [0.0, h, -half_prev]);
                        b.rigid_link(pk, a, DofSet::ALL);
                        let bb = add_node(b, &mut carried, s_car, [0.0, h, half]);
                        b.rigid_link(k, bb, DofSet::ALL);
                        let p = json!({"k": [ke[0], ke[1], ke[2], 0.0, 0.0, 0.0], "c": [ce[0], ce[1], ce[2], 0.0, 0.0, 0.0]});
                        elem(b, "spring_damper", &[a, bb], p, None);
                    }
                }
                prev = Some((k, station(i), bd.z, v.length));
            } else if wheelset.is_none() {
                ids.bogies.push(k);
            }
            for (si, s) in v.suspensions.iter().enumerate() {
                if !completes(&s.lower, &s.upper, i) {
                    continue;
                }
                let (lo, up) = (idx(&s.lower), idx(&s.upper));
                let [x, y, z] = s.at;
                let s_at = sv + x;
                let ke = [s.k[1], s.k[2], s.k[0]];
                let ce = [s.c[1], s.c[2], s.c[0]];
                let kr = [s.k_rot[1], s.k_rot[2], s.k_rot[0]];
                let cr = [s.c_rot[1], s.c_rot[2], s.c_rot[0]];
                let mut p = if nonlinear {
                    let rot_table = (s.force_table.iter().flat_map(|m| m.keys()))
                        .chain(s.bump_stop.iter().flat_map(|m| m.keys()))
                        .find(|d| d.is_rotation())
                        .map(|d| d.key());
                    if let Some(d) = rot_table {
                        return Err(fail(
                            &format!("vehicle {vi}, {}", v.suspension_label(si)),
                            &format!("a table or stop on `{d}` is not available in nonlinear geometry (the `suspension` element has them on its three translations only); remove it or use geometry = \"linear\""),
                        ));
                    }
                    if cr.iter().any(|&c| c != 0.0) {
                        return Err(fail(
                            &format!("vehicle {vi}, {}", v.suspension_label(si)),
                            "`c_rot` is not available in nonlinear geometry (the `suspension` element has no rotational dashpots); remove it or use geometry = \"linear\"",
                        ));
                    }
                    let preload = match (s.carries, &states[vi]) {
                        (Some(m), _) => m * g,
                        (None, Some(st)) => st.suspension[si],
                        (None, None) => 0.0,
                    };
                    let lower = (station(lo), v.bodies[lo].z);
                    let upper = (station(up), v.bodies[up].z);
                    body_spring(lower, upper, [y, z, s_at], ke, ce, preload, kr)
                } else {
                    json!({"k": [ke[0], ke[1], ke[2], kr[0], kr[1], kr[2]], "c": [ce[0], ce[1], ce[2], cr[0], cr[1], cr[2]]})
                };
                if let Some(t) = &s.force_table {
                    p["force_table"] = remap(t, nonlinear);
                }
                if let Some(t) = &s.bump_stop {
                    p["bump_stop"] = remap(t, nonlinear);
                }
                if nonlinear {
                    elem(b, "suspension", &[node[lo], node[up]], p, None);
                } else {
                    let u = add_node(b, &mut carried, station(up), [y, z, s_at - station(up)]);
                    b.rigid_link(node[up], u, DofSet::ALL);
                    let l = add_node(b, &mut carried, station(lo), [y, z, s_at - station(lo)]);
                    b.rigid_link(node[lo], l, DofSet::ALL);
                    elem(b, "spring_damper", &[l, u], p, None);
                }
            }
            for a in &v.anti_roll_bars {
                if !completes(&a.lower, &a.upper, i) {
                    continue;
                }
                let (lo, up) = (idx(&a.lower), idx(&a.upper));
                // Roll stiffness (about axis 3) between the two bodies.
                if nonlinear {
                    let at = [0.0, v.bodies[lo].z, station(lo)];
                    let lower = (station(lo), v.bodies[lo].z);
                    let upper = (station(up), v.bodies[up].z);
                    let p = body_spring(
                        lower,
                        upper,
                        at,
                        [0.0; 3],
                        [0.0; 3],
                        0.0,
                        [0.0, 0.0, a.k_roll],
                    );
                    elem(b, "suspension", &[node[lo], node[up]], p, None);
                } else {
                    let kk = [0.0, 0.0, 0.0, 0.0, 0.0, a.k_roll];
                    elem(
                        b,
                        "spring_damper",
                        &[node[lo], node[up]],
                        json!({"k": kk}),
                        None,
                    );
                }
            }
            if let Some(wi) = wheelset {
                let w = &v.wheelsets[wi];
                let model = model_of(w);
                for (j, side) in ["left", "right"].into_iter().enumerate() {
                    let mut p = w.wheel.clone();
                    p.remove("model");
                    for (key, val) in &train.wheel {
                        if key != "model" {
                            p.insert(key.clone(), val.clone());
                        }
                    }
                    p.insert("side".into(), Value::String(side.into()));
                    let defect = w.defects.side(j);
                    if !defect.is_none() {
                        p.insert("defect".into(), json!(defect));
                    }
                    if let Some(c) = w.contact_offset {
                        p.insert("contact_offset".into(), json!(c));
                    }
                    if model != WheelModel::MovingAxle {
                        p.entry("contact_offset")
                            .or_insert(json!(DEFAULT_CONTACT_OFFSET));
                        if let Some(st) = &states[vi] {
                            p.entry("static_load")
                                .or_insert(json!(st.wheels[2 * wi + j]));
                        }
                    }
                    let id = elem(b, model.kind(), &[k], Value::Object(p), Some(side));
                    ids.wheels.push(id);
                }
            }
        }
        masters.push(node);
    }
    // Sensors: slave nodes rigidly tied to their bodies, after every vehicle.
    for (vi, v) in train.vehicles.iter().enumerate() {
        for s in &v.sensors {
            let i = v.body_index(&s.body).expect("validated");
            let sb = s_v[vi] + v.bodies[i].x;
            let [x, y, z] = s.at;
            let n = add_node(b, &mut carried, sb, [y, z, (s_v[vi] + x) - sb]);
            b.rigid_link(masters[vi][i], n, DofSet::ALL);
            let name = if train.vehicles.len() > 1 {
                format!("v{vi}_{}", s.name)
            } else {
                s.name.clone()
            };
            ids.sensors.push((name, n));
        }
    }
    b.carrier(
        Carrier {
            name: train.name.clone(),
            path: track.track.clone(),
            start: train.start,
            speed: train.speed,
            accel: train.accel,
            speed_table: train_speed_table,
            nodes: Vec::new(),
        },
        carried,
    );
    Ok(ids)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Vehicle directions land on the element axes of the wheel frame (1 lateral = y,
    /// 2 vertical = z, 3 longitudinal = x): `spring_damper` ux/uy/uz and rx/ry/rz,
    /// `suspension` 1/2/3.
    #[test]
    fn table_directions_map_to_element_axes() {
        let lin: Vec<&str> = VehicleDirection::ALL
            .iter()
            .map(|&d| element_direction(d, false))
            .collect();
        assert_eq!(lin, ["uz", "ux", "uy", "rz", "rx", "ry"]);
        let nl: Vec<&str> = VehicleDirection::ALL[..3]
            .iter()
            .map(|&d| element_direction(d, true))
            .collect();
        assert_eq!(nl, ["3", "1", "2"]);
    }

    /// A vehicle's table and stop reach the element under the element's direction names
    /// with their values unchanged (a vertical table is `spring_damper`'s `uy`,
    /// `suspension`'s `2`).
    #[test]
    fn tables_and_stops_reach_the_element_unchanged() {
        use crate::force_law::{BumpStopSpec, Gap};
        let table = BTreeMap::from([(VehicleDirection::Z, vec![[-0.05, -8e4], [0.0, 0.0]])]);
        assert_eq!(
            remap(&table, false),
            json!({"uy": [[-0.05, -8e4], [0.0, 0.0]]})
        );
        assert_eq!(
            remap(&table, true),
            json!({"2": [[-0.05, -8e4], [0.0, 0.0]]})
        );
        let stop = BTreeMap::from([(
            VehicleDirection::Y,
            BumpStopSpec {
                gap: Gap::Sides([0.01, 0.03]),
                k: 5e6,
            },
        )]);
        assert_eq!(
            remap(&stop, false),
            json!({"ux": {"gap": [0.01, 0.03], "k": 5e6}})
        );
    }
}

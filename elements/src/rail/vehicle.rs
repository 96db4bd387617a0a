//! Vehicles: carriages of rigid bodies on suspensions, riding the track on moving-axle
//! elements, carried by a moving reference frame (the paper's Section 4 model).
//!
//! A carriage is a car body, two bogies and four wheelsets, each a rigid body: a master
//! node at its mass centre with a lumped `mass` element (mass and inertia), and slave nodes
//! rigidly linked to it where springs attach. Primary suspensions (axle box to bogie, at
//! `±primary_span` laterally) and secondary suspensions (bogie to car body, at
//! `±secondary_span`) are zero-length `spring_damper` elements between coincident slave
//! nodes of the two bodies. Each wheelset carries two `moving_axle` elements (left and
//! right wheel) that share its axle node K. Carriages of a train follow each other at
//! `car_length` and are coupled by a spring-damper between car bodies.
//!
//! All nodes of a train are carried by one carrier, each at its own body's station, so
//! their DOFs are deviations in the wheel frame 1-2-3 there: axis 1 lateral (left),
//! axis 2 up from the rail-top plane, axis 3 forwards. Body inertias are given in the
//! vehicle convention (x forwards, y lateral, z up: roll `Ixx`, pitch `Iyy`, yaw `Izz`) and
//! mapped to the wheel-frame axes (pitch about 1, yaw about 2, roll about 3).
//!
//! Slaves of a body share the master's station (and frame) and sit at a longitudinal
//! offset from it; the suspension springs join slaves of two bodies whose frames differ by
//! the heading change between their stations (`Δs/R`, 1.4e-3 rad for 8.75 m at
//! R = 6250 m) — the springs act in the lower body's axes and that angle is neglected.
//!
//! **Geometry.** With `geometry = "linear"` (the default) the carriage is built as above
//! and reproduces the paper's model. With `"nonlinear"` the bodies keep their finite
//! rotations and every spring is a `suspension` element attached directly to the two
//! bodies' master nodes at offsets (no slave nodes): its axes turn with the lower body and
//! its forces and moments balance in the displaced configuration. Each suspension carries
//! the static preload of straight, level track (the share of the weight above it under
//! the `[analysis]` gravity), so the heights in the data are the loaded ride heights: on
//! straight, level track the bodies stay where the data put them and only deviations from
//! that state move them. The loads (gravity and Eq. 5) act at the master nodes, which are
//! the bodies' mass centres, so they act where the bodies currently are.
//!
//! **Anti-roll bar.** `anti_roll` (N·m/rad per bogie) adds a roll stiffness between each
//! bogie and the car body: a rotational `spring_damper` between the two masters (linear)
//! or the `k_rot` of a `suspension` (nonlinear). The `sks700` stand-in has none.

use super::track_model::TrackModel;
use railfem_framework::error::FemError;
use railfem_framework::limits::fmt_num;
use railfem_framework::model::{Geometry, ModelBuilder};
use railfem_framework::moving::{Carrier, Path};
use railfem_framework::registry::ElementSpec;
use railfem_framework::DofSet;
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// Mass and inertia of a rigid body, vehicle convention (kg, kg·m²).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BodyData {
    /// Mass (kg).
    pub mass: f64,
    /// Roll inertia about the longitudinal axis (kg·m²).
    pub ixx: f64,
    /// Pitch inertia about the lateral axis (kg·m²).
    pub iyy: f64,
    /// Yaw inertia about the vertical axis (kg·m²).
    pub izz: f64,
    /// Height of the mass centre above the rail-top plane (m).
    pub height: f64,
}

/// Three spring rates and dampers of a suspension in vehicle convention: longitudinal `x`,
/// lateral `y`, vertical `z` (N/m, N·s/m).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Suspension {
    /// Longitudinal stiffness (N/m).
    pub kx: f64,
    /// Lateral stiffness (N/m).
    pub ky: f64,
    /// Vertical stiffness (N/m).
    pub kz: f64,
    /// Longitudinal damping (N·s/m).
    #[serde(default)]
    pub cx: f64,
    /// Lateral damping (N·s/m).
    #[serde(default)]
    pub cy: f64,
    /// Vertical damping (N·s/m).
    #[serde(default)]
    pub cz: f64,
    /// Height of the spring above the rail-top plane (m).
    pub height: f64,
}

/// A carriage: bodies, geometry and suspensions. Every number can be overridden from a
/// model file (`[[vehicle]]` with `preset = "sks700"` and then any key).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CarriageData {
    /// Car body.
    pub car_body: BodyData,
    /// Each bogie.
    pub bogie: BodyData,
    /// Each wheelset.
    pub wheelset: BodyData,
    /// Half the wheelbase of a bogie (m).
    pub semi_wheelbase: f64,
    /// Half the distance between bogie centres (m).
    pub half_bogie_distance: f64,
    /// Lateral semi-span of the primary springs (m).
    pub primary_span: f64,
    /// Lateral semi-span of the secondary springs (m).
    pub secondary_span: f64,
    /// Primary suspension, per axle box.
    pub primary: Suspension,
    /// Secondary suspension, per side of a bogie.
    pub secondary: Suspension,
    /// Length of a carriage, coupler to coupler (m).
    pub car_length: f64,
    /// Roll stiffness of the anti-roll bar between each bogie and the car body (N·m/rad);
    /// 0 = none.
    #[serde(default)]
    pub anti_roll: f64,
}

impl CarriageData {
    /// The `sks700` preset: **stand-in values** for the THSR 700T carriage of the paper
    /// (whose Figure 5 did not survive), taken from the CRH380A of the same Shinkansen
    /// family; see `shared/spec/vehicle-track-profiles.md`. Axle load 14.0 t.
    pub fn sks700() -> Self {
        CarriageData {
            car_body: BodyData {
                mass: 43_862.5,
                ixx: 1.094e5,
                iyy: 1.654e6,
                izz: 1.561e6,
                height: 1.51,
            },
            bogie: BodyData {
                mass: 2_400.0,
                ixx: 1_944.0,
                iyy: 1_314.0,
                izz: 2_400.0,
                height: 0.48,
            },
            wheelset: BodyData {
                mass: 1_850.0,
                ixx: 967.0,
                iyy: 123.0,
                izz: 967.0,
                height: 0.43,
            },
            semi_wheelbase: 1.25,
            half_bogie_distance: 8.75,
            primary_span: 1.0,
            secondary_span: 1.23,
            primary: Suspension {
                kx: 14.68e6,
                ky: 6.47e6,
                kz: 1.176e6,
                cx: 0.0,
                cy: 0.0,
                cz: 13e3,
                height: 0.43,
            },
            secondary: Suspension {
                kx: 0.16e6,
                ky: 0.16e6,
                kz: 0.19e6,
                cx: 0.0,
                cy: 58.8e3,
                cz: 40e3,
                height: 0.9,
            },
            car_length: 25.0,
            anti_roll: 0.0,
        }
    }

    /// Total mass of one carriage (kg).
    pub fn total_mass(&self) -> f64 {
        self.car_body.mass + 2.0 * self.bogie.mass + 4.0 * self.wheelset.mass
    }
}

/// A train on the track: carriages, motion and the wheels' contact settings.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TrainSpec {
    /// Name (for messages and outputs).
    #[serde(default = "default_name")]
    pub name: String,
    /// Carriage data (a preset with overrides).
    pub carriage: CarriageData,
    /// Number of carriages.
    pub carriages: usize,
    /// Station of the first carriage's centre at t = 0 (m).
    pub start: f64,
    /// Speed at t = 0 (m/s).
    pub speed: f64,
    /// Acceleration along the track (m/s²).
    #[serde(default)]
    pub accel: f64,
    /// Contact settings of every wheel (the `moving_axle` keys except `side`).
    pub wheel: serde_json::Value,
    /// First node id to use.
    #[serde(default)]
    pub first_node_id: u64,
    /// Geometry of the bodies and suspensions; default: the model's `[analysis] geometry`.
    #[serde(default)]
    pub geometry: Option<Geometry>,
    /// Tangent of the nonlinear suspensions: "symmetric" (keeps a symmetric model's
    /// Cholesky factorization) or "consistent".
    #[serde(default = "default_suspension_tangent")]
    pub suspension_tangent: String,
}

fn default_suspension_tangent() -> String {
    "symmetric".to_string()
}

fn default_name() -> String {
    "train".to_string()
}

/// Node and element ids of a built train, for recorders and checks.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct TrainIds {
    /// Car body master node per carriage.
    pub car_bodies: Vec<u64>,
    /// Bogie master nodes (front, rear per carriage).
    pub bogies: Vec<u64>,
    /// Wheelset axle nodes K (front to rear).
    pub wheelsets: Vec<u64>,
    /// Wheel elements (left, right per wheelset).
    pub wheels: Vec<u64>,
    /// Station offset of each wheelset from the carrier station (m).
    pub wheelset_offsets: Vec<f64>,
}

/// Coupler between car bodies: rates along axes 1, 2, 3 (N/m), stiff axially, soft otherwise.
const COUPLER_K: [f64; 3] = [1e5, 1e5, 5e7];
/// Coupler dashpots along axes 1, 2, 3 (N·s/m).
const COUPLER_C: [f64; 3] = [1e4, 1e4, 1e5];

/// Stiffness of the weak spring on each wheelset's spin deviation about its axle (N·m/rad).
pub const SPIN_STIFFNESS: f64 = 1.0e4;

fn is_wheel(kind: &str) -> bool {
    kind == "moving_axle"
}

fn mass_params(b: &BodyData) -> serde_json::Value {
    // Wheel-frame axes: 1 lateral (pitch), 2 vertical (yaw), 3 longitudinal (roll).
    serde_json::json!({"m": b.mass, "inertia": [b.iyy, b.izz, b.ixx]})
}

/// Checks a train's numbers before anything is built, so that a bad value is reported
/// under its own key (`carriage.bogie.ixx`) rather than by the `mass` or `spring_damper`
/// element generated from it. Returns the message (the caller adds the place).
fn validate(spec: &TrainSpec, track: &TrackModel) -> Result<(), String> {
    let c = &spec.carriage;
    let positive = |v: f64, key: &str| -> Result<(), String> {
        if v.is_finite() && v > 0.0 {
            Ok(())
        } else {
            Err(format!(
                "`{key}` = {}; give a positive finite value",
                fmt_num(v)
            ))
        }
    };
    let non_negative = |v: f64, key: &str| -> Result<(), String> {
        if v.is_finite() && v >= 0.0 {
            Ok(())
        } else {
            Err(format!("`{key}` = {}; give a finite value ≥ 0", fmt_num(v)))
        }
    };
    for (body, name) in [
        (&c.car_body, "car_body"),
        (&c.bogie, "bogie"),
        (&c.wheelset, "wheelset"),
    ] {
        positive(body.mass, &format!("carriage.{name}.mass"))?;
        for (v, k) in [(body.ixx, "ixx"), (body.iyy, "iyy"), (body.izz, "izz")] {
            non_negative(v, &format!("carriage.{name}.{k}"))?;
        }
        // Heights are above the rail-top plane: a body at or below it is a sign error.
        positive(body.height, &format!("carriage.{name}.height"))?;
    }
    for (s, name) in [(&c.primary, "primary"), (&c.secondary, "secondary")] {
        for (v, k) in [
            (s.kx, "kx"),
            (s.ky, "ky"),
            (s.kz, "kz"),
            (s.cx, "cx"),
            (s.cy, "cy"),
            (s.cz, "cz"),
        ] {
            non_negative(v, &format!("carriage.{name}.{k}"))?;
        }
        positive(s.height, &format!("carriage.{name}.height"))?;
    }
    non_negative(c.anti_roll, "carriage.anti_roll")?;
    if !["symmetric", "consistent"].contains(&spec.suspension_tangent.as_str()) {
        return Err(format!(
            "`suspension_tangent` = \"{}\" is not known; give \"symmetric\" or \"consistent\"",
            spec.suspension_tangent
        ));
    }
    // A zero span puts both springs of a pair on the centre line: no roll stiffness.
    for (v, k) in [
        (c.semi_wheelbase, "carriage.semi_wheelbase"),
        (c.half_bogie_distance, "carriage.half_bogie_distance"),
        (c.primary_span, "carriage.primary_span"),
        (c.secondary_span, "carriage.secondary_span"),
        (c.car_length, "carriage.car_length"),
    ] {
        positive(v, k)?;
    }
    if spec.carriages == 0 {
        return Err("`carriages` must be at least 1".into());
    }
    // Size guard: a carriage is 66 DOFs (car body, two bogies, four wheelsets, eight
    // wheels' contact nodes).
    railfem_framework::limits::check_memory(
        &format!("`carriages` = {}", spec.carriages),
        66.0 * spec.carriages as f64,
        "vehicle DOFs",
        railfem_framework::limits::BYTES_PER_DOF,
        "give fewer `carriages`",
    )?;
    if !(spec.speed.is_finite() && spec.start.is_finite() && spec.accel.is_finite()) {
        return Err("`speed`, `start` and `accel` must be finite".into());
    }
    // Every wheelset must start on the rail mesh: the front one at start + d, the rear one
    // at start − (n − 1)·car_length − d, d = half_bogie_distance + semi_wheelbase.
    let (Some(&lo), Some(&hi)) = (track.stations.first(), track.stations.last()) else {
        return Err("the track has no rail mesh".into());
    };
    let d = c.half_bogie_distance + c.semi_wheelbase;
    let front = spec.start + d;
    let rear = spec.start - (spec.carriages - 1) as f64 * c.car_length - d;
    if rear < lo || front > hi {
        return Err(format!(
            "`start` = {}: the wheelsets span stations {} to {} m but the rail mesh covers {lo:.3} to {hi:.3} m; move `start` or lengthen the track",
            fmt_num(spec.start),
            fmt_num(rear),
            fmt_num(front)
        ));
    }
    Ok(())
}

/// Builds a train into `b` on `track`: nodes, links, masses, springs, wheels and the
/// carrier. Returns the ids.
pub fn build_train(
    b: &mut ModelBuilder,
    track: &Arc<TrackModel>,
    spec: &TrainSpec,
) -> Result<TrainIds, FemError> {
    let origin = format!("{}: vehicle `{}`", b.origin(), spec.name);
    build_train_at(b, track, spec, &origin)
}

/// [`build_train`] with the place messages name (`"m.toml: [vehicle][0]"`); a wheel's
/// problem is reported there too, as its `wheel` table.
pub fn build_train_at(
    b: &mut ModelBuilder,
    track: &Arc<TrackModel>,
    spec: &TrainSpec,
    origin: &str,
) -> Result<TrainIds, FemError> {
    let c = &spec.carriage;
    validate(spec, track).map_err(|m| FemError::input(origin, m))?;
    let mut next_node = spec.first_node_id.max((b.max_node_id() / 1000 + 1) * 1000);
    let mut next_elem = (b.max_element_id() / 1000 + 1) * 1000;
    let mut carried: Vec<(u64, f64, [f64; 3])> = Vec::new();
    let mut ids = TrainIds::default();
    let path = track.track.clone();
    let start = spec.start;
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
    // An element of `kind`; a wheel (`side` given) is named after the vehicle's `wheel`
    // table, where its keys come from.
    let mut elem = |b: &mut ModelBuilder, kind: &str, nodes: &[u64], p: serde_json::Value| {
        next_elem += 1;
        match (p, is_wheel(kind)) {
            (serde_json::Value::Object(params), true) => {
                let side = params.get("side").and_then(|v| v.as_str()).unwrap_or("");
                let origin =
                    format!("{origin}: `wheel` (element {next_elem}, moving_axle, {side} wheel)");
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
    let geometry = spec.geometry.unwrap_or(b.analysis_mut().geometry);
    let nonlinear = geometry == Geometry::Nonlinear;
    let g = b
        .analysis_mut()
        .gravity
        .map_or(0.0, |v| (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt());
    // Static preloads on straight, level track (N, compressive): each of the four
    // secondaries carries a quarter of the car body, each of the eight axle boxes an
    // eighth of the car body and both bogies.
    let w_secondary = c.car_body.mass * g / 4.0;
    let w_primary = (c.car_body.mass + 2.0 * c.bogie.mass) * g / 8.0;
    // `suspension` keys between master `lower` and master `upper` (each (station offset,
    // height)), attached at `at` = (lateral, height, station offset).
    let tangent = spec.suspension_tangent.clone();
    let body_spring = |lower: (f64, f64),
                       upper: (f64, f64),
                       at: [f64; 3],
                       k: [f64; 3],
                       cd: [f64; 3],
                       preload: f64,
                       k_roll: f64| {
        let [lat, h, s_at] = at;
        serde_json::json!({
            "offset_i": [lat, h - lower.1, s_at - lower.0],
            "offset_j": [lat, h - upper.1, s_at - upper.0],
            "j_from_i": [0.0, upper.1 - lower.1, upper.0 - lower.0],
            "k": k, "c": cd, "preload": [0.0, -preload, 0.0],
            "k_rot": [0.0, 0.0, k_roll], "tangent": tangent,
        })
    };
    // A primary or secondary spring at lateral `lat`, at its height, at the lower body's
    // station; wheel-frame axes: 1 lateral (ky), 2 vertical (kz), 3 longitudinal (kx).
    let seat = |lower: (f64, f64), upper: (f64, f64), lat: f64, s: &Suspension, preload: f64| {
        let (k, cd) = ([s.ky, s.kz, s.kx], [s.cy, s.cz, s.cx]);
        body_spring(lower, upper, [lat, s.height, lower.0], k, cd, preload, 0.0)
    };
    let spring = |s: &Suspension| {
        // Wheel-frame axes: 1 lateral (ky), 2 vertical (kz), 3 longitudinal (kx).
        serde_json::json!({"k": [s.ky, s.kz, s.kx, 0.0, 0.0, 0.0], "c": [s.cy, s.cz, s.cx, 0.0, 0.0, 0.0]})
    };
    let mut prev_body: Option<(u64, f64)> = None;
    for car in 0..spec.carriages {
        let s_car = -(car as f64) * c.car_length;
        let body = add_node(b, &mut carried, s_car, [0.0, c.car_body.height, 0.0]);
        elem(b, "mass", &[body], mass_params(&c.car_body));
        ids.car_bodies.push(body);
        if let Some((prev, s_prev)) = prev_body {
            // Coupler: between the car ends, stiff axially, soft otherwise.
            let half = 0.5 * c.car_length;
            if nonlinear {
                let h = c.car_body.height;
                let at = [0.0, h, s_car + half];
                let p = body_spring((s_prev, h), (s_car, h), at, COUPLER_K, COUPLER_C, 0.0, 0.0);
                elem(b, "suspension", &[prev, body], p);
            } else {
                let a = add_node(b, &mut carried, s_prev, [0.0, c.car_body.height, -half]);
                b.rigid_link(prev, a, DofSet::ALL);
                let bb = add_node(b, &mut carried, s_car, [0.0, c.car_body.height, half]);
                b.rigid_link(body, bb, DofSet::ALL);
                elem(
                    b,
                    "spring_damper",
                    &[a, bb],
                    serde_json::json!({"k": [COUPLER_K[0], COUPLER_K[1], COUPLER_K[2], 0.0, 0.0, 0.0], "c": [COUPLER_C[0], COUPLER_C[1], COUPLER_C[2], 0.0, 0.0, 0.0]}),
                );
            }
        }
        prev_body = Some((body, s_car));
        for side_b in [1.0, -1.0] {
            let s_bogie = s_car + side_b * c.half_bogie_distance;
            let bogie = add_node(b, &mut carried, s_bogie, [0.0, c.bogie.height, 0.0]);
            elem(b, "mass", &[bogie], mass_params(&c.bogie));
            ids.bogies.push(bogie);
            // Secondary suspension: car-body slave and bogie slave at each side (linear),
            // or a suspension between the two masters (nonlinear).
            for lat in [c.secondary_span, -c.secondary_span] {
                if nonlinear {
                    let (lower, upper) = ((s_bogie, c.bogie.height), (s_car, c.car_body.height));
                    let p = seat(lower, upper, lat, &c.secondary, w_secondary);
                    elem(b, "suspension", &[bogie, body], p);
                    continue;
                }
                let up = add_node(
                    b,
                    &mut carried,
                    s_car,
                    [lat, c.secondary.height, side_b * c.half_bogie_distance],
                );
                b.rigid_link(body, up, DofSet::ALL);
                let lo = add_node(b, &mut carried, s_bogie, [lat, c.secondary.height, 0.0]);
                b.rigid_link(bogie, lo, DofSet::ALL);
                elem(b, "spring_damper", &[lo, up], spring(&c.secondary));
            }
            if c.anti_roll > 0.0 {
                // Anti-roll bar: roll stiffness (about axis 3) between bogie and car body.
                if nonlinear {
                    let at = [0.0, c.bogie.height, s_bogie];
                    let lower = (s_bogie, c.bogie.height);
                    let upper = (s_car, c.car_body.height);
                    let p = body_spring(lower, upper, at, [0.0; 3], [0.0; 3], 0.0, c.anti_roll);
                    elem(b, "suspension", &[bogie, body], p);
                } else {
                    let k = [0.0, 0.0, 0.0, 0.0, 0.0, c.anti_roll];
                    elem(
                        b,
                        "spring_damper",
                        &[bogie, body],
                        serde_json::json!({"k": k}),
                    );
                }
            }
            for side_w in [1.0, -1.0] {
                let dw = side_b * c.half_bogie_distance + side_w * c.semi_wheelbase;
                let s_ws = s_car + dw;
                let k = add_node(b, &mut carried, s_ws, [0.0, c.wheelset.height, 0.0]);
                elem(b, "mass", &[k], mass_params(&c.wheelset));
                // Spin about the axle (axis 1): rolling along the rail is a free motion
                // whose only static stiffness is k_v times the squared micrometre offsets of
                // the contact nodes from B, so a static solve (the initial equilibrium) is
                // singular for large penalties. A weak spring on the spin deviation makes it
                // well posed; it is far below every other stiffness of the wheelset.
                elem(
                    b,
                    "spring_damper",
                    &[k],
                    serde_json::json!({"k": [0.0, 0.0, 0.0, SPIN_STIFFNESS, 0.0, 0.0]}),
                );
                ids.wheelsets.push(k);
                ids.wheelset_offsets.push(s_ws);
                for lat in [c.primary_span, -c.primary_span] {
                    if nonlinear {
                        let (lower, upper) = ((s_ws, c.wheelset.height), (s_bogie, c.bogie.height));
                        let p = seat(lower, upper, lat, &c.primary, w_primary);
                        elem(b, "suspension", &[k, bogie], p);
                        continue;
                    }
                    let up = add_node(
                        b,
                        &mut carried,
                        s_bogie,
                        [lat, c.primary.height, side_w * c.semi_wheelbase],
                    );
                    b.rigid_link(bogie, up, DofSet::ALL);
                    let lo = add_node(b, &mut carried, s_ws, [lat, c.primary.height, 0.0]);
                    b.rigid_link(k, lo, DofSet::ALL);
                    elem(b, "spring_damper", &[lo, up], spring(&c.primary));
                }
                for side in ["left", "right"] {
                    let mut w = match &spec.wheel {
                        serde_json::Value::Object(m) => m.clone(),
                        serde_json::Value::Null => serde_json::Map::new(),
                        _ => {
                            return Err(FemError::input(
                                origin,
                                "`wheel` must be a table of moving_axle keys",
                            ))
                        }
                    };
                    w.insert("side".into(), serde_json::Value::String(side.into()));
                    let id = elem(b, "moving_axle", &[k], serde_json::Value::Object(w));
                    ids.wheels.push(id);
                }
            }
        }
    }
    b.carrier(
        Carrier {
            name: spec.name.clone(),
            path: track.track.clone(),
            start: spec.start,
            speed: spec.speed,
            accel: spec.accel,
            nodes: Vec::new(),
        },
        carried,
    );
    Ok(ids)
}

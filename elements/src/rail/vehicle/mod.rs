//! Vehicles: trains of rigid bodies on suspensions, riding the track on wheel elements,
//! carried by a moving reference frame (the paper's Section 4 model).
//!
//! A vehicle is defined from scratch ([`definition::VehicleDef`]: named bodies,
//! suspensions, anti-roll bars, wheelsets, sensors) and built by one generic builder
//! ([`build`]); the two-bogie carriage of the paper ([`CarriageData`], the `sks700`
//! preset) is a template that expands into that definition ([`carriage`]). The static
//! preloads of nonlinear geometry come from the template's share rule or a static solve
//! ([`statics`]); `[[vehicle]]` in a model file is read by [`section`]. The ride-comfort
//! indices of the sensors' accelerations, and the recorder that writes them, are in
//! [`comfort`].
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

pub mod build;
pub mod carriage;
pub mod comfort;
pub mod definition;
pub mod instance_defect;
pub mod lean;
pub mod section;
pub mod statics;
pub mod theory;

pub use carriage::{BodyData, CarriageData, Suspension};

use crate::rail::geometry::track_model;
use crate::suspension::SuspensionTangent;
use railfem_framework::builder::ModelBuilder;
use railfem_framework::error::FemError;
use railfem_framework::limits::fmt_num;
use railfem_framework::model::Geometry;
use serde::{Deserialize, Serialize};
use std::sync::Arc;
use track_model::TrackModel;

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
    /// Acceleration along the track (m/s²); a deceleration stops the train at rest.
    #[serde(default)]
    pub accel: f64,
    /// Speed table `[[t s, v m/s], …]` replacing `speed` and `accel` when given.
    #[serde(default)]
    pub speed_table: Option<Vec<[f64; 2]>>,
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
    pub suspension_tangent: SuspensionTangent,
}

fn default_suspension_tangent() -> SuspensionTangent {
    SuspensionTangent::Symmetric
}

fn default_name() -> String {
    "train".to_string()
}

/// Node and element ids of a built train, for recorders and checks.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct TrainIds {
    /// Car body (coupler body) master node per vehicle.
    pub car_bodies: Vec<u64>,
    /// Master nodes of the other bodies that are not wheelsets (bogies: front, rear).
    pub bogies: Vec<u64>,
    /// Wheelset axle nodes K (front to rear).
    pub wheelsets: Vec<u64>,
    /// Wheel elements (left, right per wheelset).
    pub wheels: Vec<u64>,
    /// Sensor nodes (name, node id), rigidly tied to their bodies: the hook for body
    /// accelerations and comfort indices.
    pub sensors: Vec<(String, u64)>,
    /// Station offset of each wheelset from the carrier station (m).
    pub wheelset_offsets: Vec<f64>,
}

/// Stiffness of the weak spring on each wheelset's spin deviation about its axle (N·m/rad).
pub const SPIN_STIFFNESS: f64 = 1.0e4;

/// Checks the train-level numbers of a carriage train (`carriages`, motion, where the
/// wheelsets start) with the template's messages. Returns the message.
fn validate(spec: &TrainSpec, track: &TrackModel) -> Result<(), String> {
    let c = &spec.carriage;
    c.validate()?;
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

/// Builds a train of carriages into `b` on `track`: nodes, links, masses, springs, wheels
/// and the carrier. Returns the ids.
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
    validate(spec, track).map_err(|m| FemError::input(origin, m))?;
    let wheel = match &spec.wheel {
        serde_json::Value::Object(m) => m.clone(),
        serde_json::Value::Null => serde_json::Map::new(),
        _ => {
            return Err(FemError::input(
                origin,
                "`wheel` must be a table of moving_axle keys",
            ))
        }
    };
    let car = spec.carriage.expand();
    let train = build::Train {
        name: spec.name.clone(),
        vehicles: vec![car; spec.carriages],
        coupler: build::CouplerDef::default(),
        start: spec.start,
        speed: spec.speed,
        accel: spec.accel,
        speed_table: spec.speed_table.clone(),
        wheel,
        first_node_id: spec.first_node_id,
        geometry: spec.geometry,
        suspension_tangent: spec.suspension_tangent,
    };
    build::build(b, track, &train, origin)
}

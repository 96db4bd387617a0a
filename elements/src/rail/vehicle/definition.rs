//! The generic vehicle definition: named rigid bodies, suspensions between them, anti-roll
//! bars, wheelsets with their wheel model, and sensor points, as a model file or a vehicle
//! file writes them (vehicle axes: x forwards from the vehicle centre, y left, z up from the
//! rail-top plane). Also the checks of its numbers before anything is built.
//!
//! The order of `body`, `suspension` and `anti_roll_bar` entries is the build order (see
//! [`super::build`]); a suspension with `mirror = true` stands for itself and its mirror
//! image at −y, built right after it ([`VehicleDef::normalized`]).

use crate::force_law::{build_laws, BumpStopSpec, BumpStops, ForceTables};
use crate::rail::wheels::wheel_defect::WheelDefect;
use railfem_framework::limits::fmt_num;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// A rigid body: mass, inertia about its mass centre in vehicle axes, and the mass centre.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BodyDef {
    /// Name, unique in the vehicle.
    pub name: String,
    /// Mass (kg).
    pub mass: f64,
    /// Roll inertia about x (kg·m²).
    pub ixx: f64,
    /// Pitch inertia about y (kg·m²).
    pub iyy: f64,
    /// Yaw inertia about z (kg·m²).
    pub izz: f64,
    /// Product of inertia ∫x·y dm (kg·m²).
    #[serde(default)]
    pub ixy: f64,
    /// Product of inertia ∫x·z dm (kg·m²).
    #[serde(default)]
    pub ixz: f64,
    /// Product of inertia ∫y·z dm (kg·m²).
    #[serde(default)]
    pub iyz: f64,
    /// Mass centre forwards of the vehicle centre (m).
    #[serde(default)]
    pub x: f64,
    /// Mass centre left of the track centre line (m).
    #[serde(default)]
    pub y: f64,
    /// Mass centre above the rail-top plane (m).
    pub z: f64,
}

/// A suspension between two bodies, attached at one point `at` of both.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SuspensionDef {
    /// Name (for messages); default `suspension[i]`.
    #[serde(default)]
    pub name: Option<String>,
    /// The lower body (its axes carry the spring in nonlinear geometry).
    pub lower: String,
    /// The upper body.
    pub upper: String,
    /// Attachment point [x, y, z] in vehicle axes (m).
    pub at: [f64; 3],
    /// Translational stiffnesses [kx, ky, kz] (N/m).
    pub k: [f64; 3],
    /// Translational dampers [cx, cy, cz] (N·s/m).
    #[serde(default)]
    pub c: [f64; 3],
    /// Rotational stiffnesses about x, y, z (N·m/rad).
    #[serde(default)]
    pub k_rot: [f64; 3],
    /// Rotational dampers about x, y, z (N·m·s/rad); linear geometry only.
    #[serde(default)]
    pub c_rot: [f64; 3],
    /// Also build the mirror image at −y right after this one.
    #[serde(default)]
    pub mirror: bool,
    /// Mass this suspension carries in the static state (kg): its preload in nonlinear
    /// geometry is `carries·g`. Absent: the preload comes from the static solve.
    #[serde(default)]
    pub carries: Option<f64>,
    /// Nonlinear force–deflection tables by vehicle direction: `[[d, F], …]` (m, N or
    /// rad, N·m), passed to the element as its `force_table`.
    #[serde(default)]
    pub force_table: Option<BTreeMap<VehicleDirection, Vec<[f64; 2]>>>,
    /// Bump stops by vehicle direction: `{gap = m or [compression, extension], k = N/m}`.
    #[serde(default)]
    pub bump_stop: Option<BTreeMap<VehicleDirection, BumpStopSpec>>,
}

/// An anti-roll bar: a roll stiffness between two bodies.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AntiRollBarDef {
    /// The lower body.
    pub lower: String,
    /// The upper body.
    pub upper: String,
    /// Roll stiffness (N·m/rad).
    pub k_roll: f64,
}

/// A wheelset: which body it is, where its wheels touch the rails and the wheel model.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WheelsetDef {
    /// The body that is the wheelset (its node is the axle node K).
    pub body: String,
    /// Lateral distance of each wheel's contact point from the centre line (m); default
    /// the wheel model's (0.75 m).
    #[serde(default)]
    pub contact_offset: Option<f64>,
    /// The wheel model and its keys: `model` = "moving_axle" (default), "hertz_wheel" or
    /// "rigid_wheel", any other key passed to both wheel elements.
    #[serde(default)]
    pub wheel: serde_json::Map<String, serde_json::Value>,
    /// Tread defects of this wheelset's wheels, each passed to its wheel element as its
    /// `defect` key (docs/defects.md).
    #[serde(default)]
    pub defects: WheelsetDefects,
}

/// The tread defects of a wheelset's two wheels.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WheelsetDefects {
    /// The left wheel's defect (default none).
    #[serde(default)]
    pub left: WheelDefect,
    /// The right wheel's defect (default none).
    #[serde(default)]
    pub right: WheelDefect,
}

impl WheelsetDefects {
    /// The defect of side `j` (0 left, 1 right).
    pub fn side(&self, j: usize) -> &WheelDefect {
        if j == 0 {
            &self.left
        } else {
            &self.right
        }
    }
}

/// A point of a body whose acceleration is recorded.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SensorDef {
    /// Name (column prefix and comfort hook).
    pub name: String,
    /// The body.
    pub body: String,
    /// Position [x, y, z] in vehicle axes (m).
    pub at: [f64; 3],
}

/// A vehicle from scratch.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct VehicleDef {
    /// What the vehicle is and where its data come from (free text).
    #[serde(default)]
    pub description: String,
    /// Length coupler to coupler (m): the distance between consecutive vehicle centres is
    /// the mean of the two lengths.
    pub length: f64,
    /// The body couplers attach to; default the first body.
    #[serde(default)]
    pub coupler_body: Option<String>,
    /// Rigid bodies, in build order.
    #[serde(rename = "body")]
    pub bodies: Vec<BodyDef>,
    /// Suspensions.
    #[serde(rename = "suspension", default)]
    pub suspensions: Vec<SuspensionDef>,
    /// Anti-roll bars.
    #[serde(rename = "anti_roll_bar", default)]
    pub anti_roll_bars: Vec<AntiRollBarDef>,
    /// Wheelsets.
    #[serde(rename = "wheelset", default)]
    pub wheelsets: Vec<WheelsetDef>,
    /// Acceleration sensors.
    #[serde(rename = "sensor", default)]
    pub sensors: Vec<SensorDef>,
}

/// The wheel model a wheelset's (or the train's) `wheel.model` names: the registered
/// element kind its two wheels are built as.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum WheelModel {
    /// Ju & Ro's moving wheel-axle contact element (the default).
    #[default]
    MovingAxle,
    /// A point wheel on a Hertzian spring.
    HertzWheel,
    /// A point wheel rigidly following the rail.
    RigidWheel,
}

impl WheelModel {
    /// The model the table `wheel` names (`model`; `moving_axle` without it). A name
    /// outside the list is refused with the list of valid ones, as one line's message.
    pub fn of(wheel: &serde_json::Map<String, serde_json::Value>) -> Result<WheelModel, String> {
        match wheel.get("model") {
            None => Ok(WheelModel::MovingAxle),
            Some(v) => WheelModel::deserialize(v)
                .map_err(|e| format!("`wheel.model`: {e}; give one of the values listed")),
        }
    }

    /// The element kind of the wheels (`"moving_axle"`, `"hertz_wheel"`, `"rigid_wheel"`).
    pub fn kind(self) -> &'static str {
        match self {
            WheelModel::MovingAxle => "moving_axle",
            WheelModel::HertzWheel => "hertz_wheel",
            WheelModel::RigidWheel => "rigid_wheel",
        }
    }
}
/// A direction of the vehicle's axes (x forward, y left, z up; `r`: the rotation about
/// it), the key of a suspension's `force_table` and `bump_stop`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum VehicleDirection {
    /// Longitudinal translation.
    X,
    /// Lateral translation.
    Y,
    /// Vertical translation.
    Z,
    /// Roll.
    Rx,
    /// Pitch.
    Ry,
    /// Yaw.
    Rz,
}

impl VehicleDirection {
    /// Every direction, in the order of the keys.
    pub const ALL: [VehicleDirection; 6] = [
        VehicleDirection::X,
        VehicleDirection::Y,
        VehicleDirection::Z,
        VehicleDirection::Rx,
        VehicleDirection::Ry,
        VehicleDirection::Rz,
    ];

    /// The key as written in a vehicle file.
    pub fn key(self) -> &'static str {
        match self {
            VehicleDirection::X => "x",
            VehicleDirection::Y => "y",
            VehicleDirection::Z => "z",
            VehicleDirection::Rx => "rx",
            VehicleDirection::Ry => "ry",
            VehicleDirection::Rz => "rz",
        }
    }

    /// Whether it is a rotation.
    pub fn is_rotation(self) -> bool {
        matches!(
            self,
            VehicleDirection::Rx | VehicleDirection::Ry | VehicleDirection::Rz
        )
    }
}

impl VehicleDef {
    /// The definition with every `mirror = true` suspension written out as two (itself,
    /// then its image at −y, named `<stem>_right` for `<stem>_left`, else `<name>_mirror`), so that a file using `mirror` and one
    /// writing both sides compare equal.
    pub fn normalized(&self) -> VehicleDef {
        let mut v = self.clone();
        v.suspensions.clear();
        for s in &self.suspensions {
            let mut a = s.clone();
            a.mirror = false;
            v.suspensions.push(a.clone());
            if s.mirror {
                let mut m = a;
                m.at[1] = -m.at[1];
                m.name = s.name.as_ref().map(|n| match n.strip_suffix("_left") {
                    Some(stem) => format!("{stem}_right"),
                    None => format!("{n}_mirror"),
                });
                v.suspensions.push(m);
            }
        }
        v
    }

    /// Index of the body called `name`.
    pub fn body_index(&self, name: &str) -> Option<usize> {
        self.bodies.iter().position(|b| b.name == name)
    }

    /// DOFs the vehicle adds to a model: six per body, per wheel's contact nodes (two
    /// wheels a wheelset) and per sensor node (what the train's size guard counts).
    pub fn dofs(&self) -> usize {
        6 * (self.bodies.len() + 2 * self.wheelsets.len() + self.sensors.len())
    }

    /// Total mass (kg).
    pub fn total_mass(&self) -> f64 {
        self.bodies.iter().map(|b| b.mass).sum()
    }

    /// The name of suspension `i` for messages.
    pub fn suspension_label(&self, i: usize) -> String {
        match &self.suspensions[i].name {
            Some(n) => format!("suspension[{i}] \"{n}\""),
            None => format!("suspension[{i}]"),
        }
    }

    /// Checks the numbers and names (a normalized definition). `Err((place, message))`:
    /// the place inside the vehicle (`body "bogie_front"`) and what to do.
    pub fn validate(&self) -> Result<(), (String, String)> {
        let err = |place: String, m: String| Err((place, m));
        if !(self.length.is_finite() && self.length > 0.0) {
            return err(
                "length".into(),
                format!(
                    "= {}; give the coupler-to-coupler length (m), > 0",
                    fmt_num(self.length)
                ),
            );
        }
        if self.bodies.is_empty() {
            return err(
                "body".into(),
                "no bodies; give at least one [[body]]".into(),
            );
        }
        let names: Vec<&str> = self.bodies.iter().map(|b| b.name.as_str()).collect();
        let known = || names.join(", ");
        for (i, b) in self.bodies.iter().enumerate() {
            let place = format!("body \"{}\"", b.name);
            if names[..i].contains(&b.name.as_str()) {
                return err(place, "appears twice; give every body its own name".into());
            }
            if !(b.mass.is_finite() && b.mass > 0.0) {
                return err(
                    place,
                    format!("`mass` = {}; give a positive mass (kg)", fmt_num(b.mass)),
                );
            }
            let all = [b.ixx, b.iyy, b.izz, b.ixy, b.ixz, b.iyz, b.x, b.y, b.z];
            if all.iter().any(|v| !v.is_finite()) {
                return err(
                    place,
                    "has a non-finite inertia or position; give finite numbers".into(),
                );
            }
            // Inertia tensor [[ixx, -ixy, -ixz], [-ixy, iyy, -iyz], [-ixz, -iyz, izz]]:
            // positive definite iff its leading principal minors are (Sylvester).
            let m1 = b.ixx;
            let m2 = b.ixx * b.iyy - b.ixy * b.ixy;
            let m3 = b.ixx * (b.iyy * b.izz - b.iyz * b.iyz)
                - b.ixy * (b.ixy * b.izz + b.iyz * b.ixz)
                - b.ixz * (b.ixy * b.iyz + b.iyy * b.ixz);
            if !(m1 > 0.0 && m2 > 0.0 && m3 > 0.0) {
                return err(
                    place,
                    format!(
                        "inertia (ixx {}, iyy {}, izz {}, ixy {}, ixz {}, iyz {} kg·m²) is not positive definite; give positive moments larger than the products",
                        fmt_num(b.ixx), fmt_num(b.iyy), fmt_num(b.izz), fmt_num(b.ixy), fmt_num(b.ixz), fmt_num(b.iyz)
                    ),
                );
            }
            if b.z <= 0.0 {
                return err(
                    place,
                    format!(
                        "`z` = {}; the mass centre must be above the rail-top plane (m)",
                        fmt_num(b.z)
                    ),
                );
            }
        }
        if let Some(c) = &self.coupler_body {
            if self.body_index(c).is_none() {
                return err(
                    "coupler_body".into(),
                    format!(
                        "names body \"{c}\", which does not exist; the bodies are: {}",
                        known()
                    ),
                );
            }
        }
        let check_body = |place: &str, key: &str, name: &str| -> Result<usize, (String, String)> {
            self.body_index(name).ok_or_else(|| {
                (
                    place.to_string(),
                    format!(
                        "`{key}` names body \"{name}\", which does not exist; the bodies are: {}",
                        known()
                    ),
                )
            })
        };
        for (i, s) in self.suspensions.iter().enumerate() {
            let place = self.suspension_label(i);
            let lo = check_body(&place, "lower", &s.lower)?;
            let up = check_body(&place, "upper", &s.upper)?;
            if lo == up {
                return err(
                    place,
                    "joins a body to itself; give two different bodies".into(),
                );
            }
            for (v, key) in
                s.k.iter()
                    .map(|v| (v, "k"))
                    .chain(s.c.iter().map(|v| (v, "c")))
                    .chain(s.k_rot.iter().map(|v| (v, "k_rot")))
                    .chain(s.c_rot.iter().map(|v| (v, "c_rot")))
            {
                if !(v.is_finite() && *v >= 0.0) {
                    return err(
                        place,
                        format!("`{key}` has {}; give finite values ≥ 0", fmt_num(*v)),
                    );
                }
            }
            if s.at.iter().any(|v| !v.is_finite()) || s.at[2] <= 0.0 {
                return err(
                    place,
                    "`at` must be finite with z above the rail-top plane (m)".into(),
                );
            }
            if let Some(m) = s.carries {
                if !(m.is_finite() && m >= 0.0) {
                    return err(
                        place,
                        format!(
                            "`carries` = {}; give the carried mass (kg), ≥ 0",
                            fmt_num(m)
                        ),
                    );
                }
            }
            check_laws(&place, s.force_table.as_ref(), s.bump_stop.as_ref())?;
        }
        for (i, a) in self.anti_roll_bars.iter().enumerate() {
            let place = format!("anti_roll_bar[{i}]");
            let lo = check_body(&place, "lower", &a.lower)?;
            let up = check_body(&place, "upper", &a.upper)?;
            if lo == up {
                return err(
                    place,
                    "joins a body to itself; give two different bodies".into(),
                );
            }
            if !(a.k_roll.is_finite() && a.k_roll >= 0.0) {
                return err(
                    place,
                    format!("`k_roll` = {}; give N·m/rad ≥ 0", fmt_num(a.k_roll)),
                );
            }
        }
        for (i, w) in self.wheelsets.iter().enumerate() {
            let place = format!("wheelset[{i}]");
            check_body(&place, "body", &w.body)?;
            if self.wheelsets[..i].iter().any(|o| o.body == w.body) {
                return err(
                    place,
                    format!(
                        "body \"{}\" is already a wheelset; give each wheelset its own body",
                        w.body
                    ),
                );
            }
            if let Err(m) = WheelModel::of(&w.wheel) {
                return err(place, m);
            }
            if w.wheel.contains_key("side") {
                return err(place, "`wheel.side` would be ignored: every wheelset has a left and a right wheel; remove it".into());
            }
            if let Some(c) = w.contact_offset {
                if !(c.is_finite() && c > 0.0) {
                    return err(place, format!("`contact_offset` = {}; give the lateral distance of the contact points from the centre line (m), > 0", fmt_num(c)));
                }
            }
        }
        if self.wheelsets.is_empty() {
            return err(
                "wheelset".into(),
                "no wheelsets; give at least one [[wheelset]] so the vehicle rests on the rails"
                    .into(),
            );
        }
        for (i, s) in self.sensors.iter().enumerate() {
            let place = format!("sensor[{i}] \"{}\"", s.name);
            check_body(&place, "body", &s.body)?;
            if s.at.iter().any(|v| !v.is_finite()) {
                return err(place, "`at` must be finite (m)".into());
            }
            if self.sensors[..i].iter().any(|o| o.name == s.name) {
                return err(
                    place,
                    "appears twice; give every sensor its own name".into(),
                );
            }
        }
        Ok(())
    }
}

/// The tables' and stops' values checked as the elements will check them
/// ([`build_laws`]: at least two points, finite, deflections increasing, forces not
/// falling; gaps and stiffness finite and ≥ 0), so that a bad one is refused at the
/// vehicle's own place.
fn check_laws(
    place: &str,
    tables: Option<&BTreeMap<VehicleDirection, Vec<[f64; 2]>>>,
    stops: Option<&BTreeMap<VehicleDirection, BumpStopSpec>>,
) -> Result<(), (String, String)> {
    let names = VehicleDirection::ALL.map(VehicleDirection::key);
    let tables: ForceTables = tables
        .into_iter()
        .flatten()
        .map(|(d, t)| (d.key().to_string(), t.clone()))
        .collect();
    let stops: BumpStops = stops
        .into_iter()
        .flatten()
        .map(|(d, s)| (d.key().to_string(), *s))
        .collect();
    build_laws(&names, &[0.0; 6], &tables, &stops)
        .map(|_| ())
        .map_err(|m| (place.to_string(), m))
}

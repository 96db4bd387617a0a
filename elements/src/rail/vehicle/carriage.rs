//! The two-bogie carriage template (`CarriageData`, the `sks700` preset and its
//! `carriage = {...}` overrides) and its expansion into the generic [`VehicleDef`]: a car
//! body, two bogies and four wheelsets, primary suspensions (axle box to bogie, at
//! `±primary_span`), secondary suspensions (bogie to car body, at `±secondary_span`) and
//! the optional anti-roll bars. The expansion lists bodies and springs in the order the
//! carriage was always built (car body; front bogie, its secondaries, its anti-roll bar,
//! its wheelsets each with its primaries; then the rear bogie), so the generic builder
//! makes the same nodes and elements with the same numbers.
//!
//! In nonlinear geometry each suspension carries the share rule's static preload: each of
//! the four secondaries a quarter of the car body, each of the eight axle boxes an eighth
//! of the car body and both bogies (`carries`, kg).

use super::definition::{AntiRollBarDef, BodyDef, SuspensionDef, VehicleDef, WheelsetDef};
use railfem_framework::limits::fmt_num;
use serde::{Deserialize, Serialize};

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

impl CarriageData {
    /// Checks the template's numbers, so that a bad value is reported under its own key
    /// (`carriage.bogie.ixx`) rather than by the body or spring generated from it.
    pub fn validate(&self) -> Result<(), String> {
        let c = self;
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
        Ok(())
    }

    /// The carriage as a generic vehicle (see the module documentation for the order).
    pub fn expand(&self) -> VehicleDef {
        let c = self;
        let body = |name: &str, d: &BodyData, x: f64| BodyDef {
            name: name.into(),
            mass: d.mass,
            ixx: d.ixx,
            iyy: d.iyy,
            izz: d.izz,
            ixy: 0.0,
            ixz: 0.0,
            iyz: 0.0,
            x,
            y: 0.0,
            z: d.height,
        };
        let spring = |name: String,
                      lower: &str,
                      upper: &str,
                      x: f64,
                      y: f64,
                      s: &Suspension,
                      carries: f64| {
            SuspensionDef {
                name: Some(name),
                lower: lower.into(),
                upper: upper.into(),
                at: [x, y, s.height],
                k: [s.kx, s.ky, s.kz],
                c: [s.cx, s.cy, s.cz],
                k_rot: [0.0; 3],
                c_rot: [0.0; 3],
                mirror: false,
                carries: Some(carries),
                force_table: None,
                bump_stop: None,
            }
        };
        // Share rule (module documentation); divisions by 4 and 8 are exact in binary, so
        // `carries·g` equals the weight share computed the other way round.
        let secondary_share = c.car_body.mass / 4.0;
        let primary_share = (c.car_body.mass + 2.0 * c.bogie.mass) / 8.0;
        let mut v = VehicleDef {
            description: "two-bogie carriage (template expansion)".into(),
            length: c.car_length,
            coupler_body: Some("car_body".into()),
            bodies: vec![body("car_body", &c.car_body, 0.0)],
            suspensions: Vec::new(),
            anti_roll_bars: Vec::new(),
            wheelsets: Vec::new(),
            sensors: Vec::new(),
        };
        let mut n_ws = 0;
        for (side_b, bogie) in [(1.0, "bogie_front"), (-1.0, "bogie_rear")] {
            let x_bogie = side_b * c.half_bogie_distance;
            v.bodies.push(body(bogie, &c.bogie, x_bogie));
            for (lat, side) in [(c.secondary_span, "left"), (-c.secondary_span, "right")] {
                let name = format!("secondary_{}_{side}", &bogie[6..]);
                v.suspensions.push(spring(
                    name,
                    bogie,
                    "car_body",
                    x_bogie,
                    lat,
                    &c.secondary,
                    secondary_share,
                ));
            }
            if c.anti_roll > 0.0 {
                v.anti_roll_bars.push(AntiRollBarDef {
                    lower: bogie.into(),
                    upper: "car_body".into(),
                    k_roll: c.anti_roll,
                });
            }
            for side_w in [1.0, -1.0] {
                n_ws += 1;
                let ws = format!("wheelset_{n_ws}");
                let x_ws = side_b * c.half_bogie_distance + side_w * c.semi_wheelbase;
                v.bodies.push(body(&ws, &c.wheelset, x_ws));
                for (lat, side) in [(c.primary_span, "left"), (-c.primary_span, "right")] {
                    let name = format!("primary_{n_ws}_{side}");
                    v.suspensions.push(spring(
                        name,
                        &ws,
                        bogie,
                        x_ws,
                        lat,
                        &c.primary,
                        primary_share,
                    ));
                }
                v.wheelsets.push(WheelsetDef {
                    body: ws,
                    contact_offset: None,
                    wheel: Default::default(),
                    defects: Default::default(),
                });
            }
        }
        v
    }
}

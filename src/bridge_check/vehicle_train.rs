//! A train of railfem vehicle files (docs/vehicles.md) for the check: the axles of `count`
//! coupled vehicles with their static loads, and each axle's suspension for the
//! sprung-mass model ([`super::interaction`]).
//!
//! - Axle positions: the wheelset bodies' `x` (forwards from the vehicle centre), the
//!   vehicles' centres one vehicle `length` apart, measured back from the front axle.
//! - Static axle loads: the wheel loads of the vehicle standing on level track under
//!   g = 9.81 m/s² (the framework's static solve of the bodies on their springs,
//!   `railfem_elements::rail::vehicle::statics`), left plus right.
//! - Suspension of an axle: the unsprung mass is the wheelset body's mass; the primary
//!   stiffness and damping are the sums of the vertical `k` and `c` of the suspensions
//!   attached to the wheelset; the sprung mass is the rest of the static axle load, i.e.
//!   the axle's share of bogie and car body (their secondary suspension and pitch are not
//!   modelled: above the bogie the axle sees one mass on its primary springs); the contact
//!   is Hertz's, linearised at the static wheel load, as for the built-in trains.
//! - Full vehicles ([`full`]): each vehicle the file's half car
//!   ([`HalfCar::from_vehicle`]), one vehicle length apart, its front wheelset where the
//!   axles above put it.

use super::full_vehicles::Vehicle;
use super::half_car::HalfCar;
use super::interaction::{linear_contact, AxleSuspension, G};
use super::trains::{user_train, Axle, Train};
use crate::elements::rail::vehicle::build::DEFAULT_CONTACT_OFFSET;
use crate::elements::rail::vehicle::{section::parse_vehicle, statics};
use crate::framework::FemError;
use std::path::Path;

/// The train of `count` vehicles of the file at `path`, named `name`, with one suspension
/// per axle; `wheel_radius` (m) sets the Hertz contact. Errors name the file.
pub fn read(
    path: &Path,
    name: &str,
    count: usize,
    wheel_radius: f64,
) -> Result<(Train, Vec<AxleSuspension>), FemError> {
    let file = path.display().to_string();
    let text = std::fs::read_to_string(path).map_err(|e| {
        FemError::input(
            &file,
            format!("cannot read the vehicle file ({e}); fix the path"),
        )
    })?;
    let v = parse_vehicle(&text, &file)?;
    if v.wheelsets.is_empty() {
        return Err(FemError::input(
            format!("{file}: wheelset"),
            "the vehicle has no wheelset; give [[wheelset]] tables",
        ));
    }
    let offsets: Vec<f64> = v
        .wheelsets
        .iter()
        .map(|w| w.contact_offset.unwrap_or(DEFAULT_CONTACT_OFFSET))
        .collect();
    let st = statics::solve(&v, G, &offsets).map_err(|m| FemError::input(&file, m))?;
    // (x in vehicle axes, axle load, suspension) per wheelset.
    let mut one: Vec<(f64, f64, AxleSuspension)> = Vec::new();
    for (i, w) in v.wheelsets.iter().enumerate() {
        let body = v.body_index(&w.body).map(|b| &v.bodies[b]).ok_or_else(|| {
            FemError::input(
                format!("{file}: wheelset[{i}].body"),
                format!("no body `{}`; name one of the [[body]] tables", w.body),
            )
        })?;
        let load = st.wheels[2 * i] + st.wheels[2 * i + 1];
        let (mut k, mut c) = (0.0, 0.0);
        for s in &v.suspensions {
            if s.lower == w.body || s.upper == w.body {
                k += s.k[2];
                c += s.c[2];
            }
        }
        let sprung = load / G - body.mass;
        if !(k > 0.0 && sprung > 0.0) {
            return Err(FemError::input(
                format!("{file}: wheelset[{i}] \"{}\"", w.body),
                "the sprung-mass model needs a vertical primary suspension (k[2] > 0) on the wheelset and a static axle load above the wheelset's weight",
            ));
        }
        one.push((
            body.x,
            load,
            AxleSuspension {
                unsprung: body.mass,
                sprung,
                stiffness: k,
                damping: c,
                contact: linear_contact(load, wheel_radius),
            },
        ));
    }
    one.sort_by(|a, b| b.0.total_cmp(&a.0));
    let front = one[0].0;
    let mut axles = Vec::new();
    let mut susp = Vec::new();
    for j in 0..count {
        for (x, load, s) in &one {
            axles.push(Axle {
                position: front - x + j as f64 * v.length,
                load: *load,
            });
            susp.push(*s);
        }
    }
    let train = user_train(name, axles, &file)?;
    Ok((train, susp))
}

/// The `count` full vehicles of the vehicle file at `path` ([`HalfCar::from_vehicle`]),
/// placed as [`read`] places their axles: the first vehicle's front wheelset at the
/// train's front, the next vehicles one vehicle `length` behind each other.
pub fn full(path: &Path, count: usize, wheel_radius: f64) -> Result<Vec<Vehicle>, FemError> {
    let file = path.display().to_string();
    let text = std::fs::read_to_string(path).map_err(|e| {
        FemError::input(
            &file,
            format!("cannot read the vehicle file ({e}); fix the path"),
        )
    })?;
    let v = parse_vehicle(&text, &file)?;
    let car = HalfCar::from_vehicle(&v, &file, wheel_radius)?;
    let front = car.axle_x.iter().fold(f64::NEG_INFINITY, |m, &x| m.max(x));
    Ok((0..count)
        .map(|j| Vehicle {
            car: car.clone(),
            centre: front + j as f64 * v.length,
        })
        .collect())
}

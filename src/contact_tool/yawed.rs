//! The contact of a yawed wheelset on straight track: rigid profiles, each wheel a surface
//! of revolution about the yawed and rolled axle, each rail a cylinder along the track. For
//! a yaw ψ the contact leaves the vertical plane through the axle and runs ahead of it by
//! about `r·tan δ·ψ` (Wang's and Shabana's formulation, below); with ψ = 0 the search is
//! that of `creep::conicity` (same profiles, pose, lift/roll iteration and outputs).
//!
//! # The nearest point of one wheel section
//!
//! Track frame `x` ahead, `y` left, `z` up; wheelset frame the same before its rotation
//! `R = Rz(ψ)·Rx(φ)` (roll φ raising the left wheel) about its tape-circle reference point,
//! which is shifted by `(0, y, z)`; the axle's axis is at height `r0` in the wheelset frame.
//! The wheel profile point at parameter `t` (lateral `p_y` from the tape circle, height
//! `p_z`) is the circle of radius `ρ = r0 − p_z` at axle coordinate `Y = s·(c + p_y)`
//! (`s` = +1 left, −1 right, `c` the tape circle's distance from the centre). Its points
//! are `P(θ) = (ρ sin θ, Y, r0 − ρ cos θ)` in the wheelset frame, `θ` the angle ahead of the
//! bottom. Straight rails are cylinders `z = z_r(y_r)` along `x`, `y_r = s·y − c_r` the
//! rail's profile coordinate. The vertical gap of the section is the smallest
//! `G(θ) = z(θ) − z_r(y_r(θ))`; at its minimum `dz/dθ = s·z_r'·dy/dθ`. With
//! `dP/dθ = (ρ cos θ, 0, ρ sin θ)` rotated by `R`:
//! `dy/dθ = ρ(cos θ sin ψ − sin θ sin φ cos ψ)`, `dz/dθ = ρ sin θ cos φ`, so
//!
//! ```text
//! tan θ = s·z_r'·sin ψ / (cos φ + s·z_r'·sin φ·cos ψ)
//! ```
//!
//! with `z_r'` the rail's slope at the point, i.e. `tan δ` of the contact angle; for small
//! roll `tan θ ≈ s·tan δ·sin ψ` and the point leads the axle's vertical plane by
//! `ρ·sin θ ≈ r·tan δ·tan ψ` (Shabana, Zaazaa & Sugiyama, *Railroad vehicle dynamics: a
//! computational approach*, 2008, ch. 4; Wang, *Kinematics of a railway wheelset on a
//! track*, as the "contact point ahead of the axle"). `z_r'` depends on `θ` through
//! `y_r(θ)` (a second-order effect, `ρ·θ·ψ`): the equation is solved by fixed-point
//! iteration from `θ = 0`. The section's gap is `G(θ)`; the contact is the section of
//! smallest gap (sampled, then refined by golden section), and the lift and the roll that
//! close both wheels' gaps come from the iteration of `creep::conicity`.
//!
//! The lead `ρ sin θ` is measured along the wheelset's own longitudinal axis
//! `R·x̂ = (cos ψ, sin ψ, 0)`; `x` of the contact in the track frame (from the wheelset's
//! reference point) adds the wheel's own position `−Y·sin ψ` along the track.

use crate::elements::rail::contact::creep::conicity::{
    ConicityError, SideContact, WheelsetContact, WheelsetGeometry,
};

/// Samples of the wheel profile in the search (as `creep::conicity::SAMPLES`).
pub const SAMPLES: usize = 2000;
/// Fixed-point steps for the lead angle `θ` at most.
const THETA_STEPS: usize = 30;
/// Golden-section steps refining the section of smallest gap.
const GOLDEN_STEPS: usize = 80;
/// Lift/roll iterations at most.
const POSE_STEPS: usize = 200;
/// Gap below which both wheels touch (m).
const GAP_TOL: f64 = 1e-13;

/// Where one wheel's contact lies along the track.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Lead {
    /// Angle of the contact ahead of the wheel's bottom `θ` (rad).
    pub theta: f64,
    /// Distance ahead of the axle's vertical plane `ρ sin θ` (m).
    pub lead: f64,
    /// Longitudinal coordinate in the track frame from the wheelset's reference point (m).
    pub x: f64,
}

/// A second point where a wheel nearly touches its rail: the local minimum of the gap over
/// the wheel's sections, other than the contact and at least [`SAME_PATCH`] from it on the
/// wheel, with the smallest gap (a two-point contact when that gap is within the elastic
/// approach of the first patch, `contact_tool::two_point`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SecondPoint {
    /// Its geometry.
    pub contact: SideContact,
    /// Its lead.
    pub lead: Lead,
    /// Its vertical gap while the first point touches (m).
    pub gap: f64,
}

/// A yawed wheelset's contact: the geometry as `creep::conicity` gives it, and the leads.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct YawedContact {
    /// Positions, radii, angles, roll and lift (`contact_angle` from the rail's slope).
    pub contact: WheelsetContact,
    /// Yaw ψ (rad).
    pub yaw: f64,
    /// Left wheel's lead.
    pub left: Lead,
    /// Right wheel's lead.
    pub right: Lead,
}

/// Each wheel's (left, right) second local minimum of the gap at the pose of `found`, if
/// any (module doc of [`SecondPoint`]).
pub fn second_points(geom: &WheelsetGeometry, found: &YawedContact) -> [Option<SecondPoint>; 2] {
    let pose = Pose {
        y: found.contact.shift,
        z: found.contact.lift,
        roll: found.contact.roll,
        yaw: found.yaw,
    };
    let second = |s: f64, first: &SideContact| {
        second_minimum(geom, s, &pose, first.wheel_t).map(|(t, p)| {
            let (contact, lead) = side_contact(geom, s, t, &p);
            SecondPoint {
                contact,
                lead,
                gap: p.gap,
            }
        })
    };
    [
        second(1.0, &found.contact.left),
        second(-1.0, &found.contact.right),
    ]
}

/// A pose of the wheelset: shift, lift, roll, yaw.
#[derive(Debug, Clone, Copy)]
struct Pose {
    y: f64,
    z: f64,
    roll: f64,
    yaw: f64,
}

/// One section's nearest point: gap, lead angle, rail coordinate, track point.
#[derive(Debug, Clone, Copy)]
struct SectionPoint {
    gap: f64,
    theta: f64,
    rail_y: f64,
    track: [f64; 3],
}

fn section(geom: &WheelsetGeometry, s: f64, t: f64, pose: &Pose) -> Option<SectionPoint> {
    let p = geom.wheel.spline().point(t);
    let r0 = geom.nominal_radius;
    let (rho, big_y) = (r0 - p.y, s * (geom.contact_offset + p.x));
    let (sf, cf) = pose.roll.sin_cos();
    let (sp, cp) = pose.yaw.sin_cos();
    let rail = geom.rail_surface();
    let (lo, hi) = rail.domain();
    let at = |theta: f64| {
        let (st, ct) = theta.sin_cos();
        let (a, b, c) = (rho * st, big_y, r0 - rho * ct);
        let (b, c) = (b * cf - c * sf, b * sf + c * cf);
        let track = [a * cp - b * sp, pose.y + a * sp + b * cp, pose.z + c];
        (track, s * track[1] - geom.rail_offset)
    };
    let mut theta = 0.0;
    for _ in 0..THETA_STEPS {
        let (_, yr) = at(theta);
        if !(lo..=hi).contains(&yr) {
            return None;
        }
        let k = s * rail.derivative(yr);
        let next = (k * sp).atan2(cf + k * sf * cp);
        let done = (next - theta).abs() <= 1e-15;
        theta = next;
        if done {
            break;
        }
    }
    let (track, yr) = at(theta);
    (lo..=hi).contains(&yr).then(|| SectionPoint {
        gap: track[2] - rail.value(yr),
        theta,
        rail_y: yr,
        track,
    })
}

/// The wheel's point of smallest gap: the best of [`SAMPLES`] sections, refined by golden
/// section between its neighbours.
fn nearest(geom: &WheelsetGeometry, s: f64, pose: &Pose) -> Option<(f64, SectionPoint)> {
    let gaps = sampled(geom, s, pose);
    let k = (0..SAMPLES)
        .filter(|&k| gaps[k].is_finite())
        .min_by(|&a, &b| gaps[a].total_cmp(&gaps[b]))?;
    refine(geom, s, pose, k)
}

/// The gap of each of the [`SAMPLES`] sections (infinite where not over the rail).
fn sampled(geom: &WheelsetGeometry, s: f64, pose: &Pose) -> Vec<f64> {
    let (t0, t1) = geom.wheel.spline().domain();
    let dt = (t1 - t0) / (SAMPLES - 1) as f64;
    (0..SAMPLES)
        .map(|k| section(geom, s, t0 + dt * k as f64, pose).map_or(f64::INFINITY, |p| p.gap))
        .collect()
}

/// Lateral distance on the wheel (m) below which two local minima of the gap belong to
/// one patch.
pub const SAME_PATCH: f64 = 2e-3;

/// The wheel's second contact candidate: the local minimum of the sampled gap, refined,
/// that lies at least [`SAME_PATCH`] from the first (`t_first`) on the wheel and has the
/// smallest gap; `None` if the gap has one minimum.
fn second_minimum(
    geom: &WheelsetGeometry,
    s: f64,
    pose: &Pose,
    t_first: f64,
) -> Option<(f64, SectionPoint)> {
    let gaps = sampled(geom, s, pose);
    let wheel = geom.wheel.spline();
    let y_first = wheel.point(t_first).x;
    let (t0, t1) = wheel.domain();
    let dt = (t1 - t0) / (SAMPLES - 1) as f64;
    let mut best: Option<(f64, SectionPoint)> = None;
    for k in 1..SAMPLES - 1 {
        let (g, l, r) = (gaps[k], gaps[k - 1], gaps[k + 1]);
        let far = (wheel.point(t0 + dt * k as f64).x - y_first).abs() >= SAME_PATCH;
        if g.is_finite() && g < l && g <= r && far {
            if let Some((t, p)) = refine(geom, s, pose, k) {
                let distinct = (wheel.point(t).x - y_first).abs() >= SAME_PATCH;
                if distinct && best.is_none_or(|(_, b)| p.gap < b.gap) {
                    best = Some((t, p));
                }
            }
        }
    }
    best
}

/// Golden section on the gap between the neighbours of sample `k`.
fn refine(geom: &WheelsetGeometry, s: f64, pose: &Pose, k: usize) -> Option<(f64, SectionPoint)> {
    let (t0, t1) = geom.wheel.spline().domain();
    let dt = (t1 - t0) / (SAMPLES - 1) as f64;
    let gap = |t: f64| section(geom, s, t, pose).map_or(f64::INFINITY, |p| p.gap);
    let (mut a, mut b) = (
        (t0 + dt * (k as f64 - 1.0)).max(t0),
        (t0 + dt * (k as f64 + 1.0)).min(t1),
    );
    let golden = 0.5 * (5f64.sqrt() - 1.0);
    for _ in 0..GOLDEN_STEPS {
        let (c, d) = (b - golden * (b - a), a + golden * (b - a));
        if gap(c) < gap(d) {
            b = d;
        } else {
            a = c;
        }
    }
    let t = 0.5 * (a + b);
    section(geom, s, t, pose).map(|p| (t, p))
}

fn side_contact(geom: &WheelsetGeometry, s: f64, t: f64, p: &SectionPoint) -> (SideContact, Lead) {
    let q = geom.wheel.spline().point(t);
    let rho = geom.nominal_radius - q.y;
    (
        SideContact {
            wheel_y: q.x,
            rail_y: p.rail_y,
            wheel_t: t,
            rolling_radius: rho,
            // Wheel and rail are tangent at the contact: the rail's slope, rising towards
            // the field side (its profile coordinate's direction) for a positive angle.
            contact_angle: geom.rail_surface().derivative(p.rail_y).atan(),
            lateral_position: s * p.track[1],
        },
        Lead {
            theta: p.theta,
            lead: rho * p.theta.sin(),
            x: p.track[0],
        },
    )
}

/// The contact of the wheelset at lateral shift `y` (m, of its tape-circle level, as
/// `WheelsetGeometry::contact`) and yaw `yaw` (rad).
pub fn contact(geom: &WheelsetGeometry, y: f64, yaw: f64) -> Result<YawedContact, ConicityError> {
    let no = |side| ConicityError::NoOverlap { side, shift: y };
    let mut pose = Pose {
        y,
        z: 0.0,
        roll: 0.0,
        yaw,
    };
    for _ in 0..POSE_STEPS {
        let (tl, l) = nearest(geom, 1.0, &pose).ok_or(no("left"))?;
        let (tr, r) = nearest(geom, -1.0, &pose).ok_or(no("right"))?;
        if l.gap.abs() < GAP_TOL && r.gap.abs() < GAP_TOL {
            let (left, lead_l) = side_contact(geom, 1.0, tl, &l);
            let (right, lead_r) = side_contact(geom, -1.0, tr, &r);

            return Ok(YawedContact {
                contact: WheelsetContact {
                    shift: y,
                    roll: pose.roll,
                    lift: pose.z,
                    left,
                    right,
                },
                yaw,
                left: lead_l,
                right: lead_r,
            });
        }
        pose.z -= 0.5 * (l.gap + r.gap);
        pose.roll -= (l.gap - r.gap) / (2.0 * geom.contact_offset);
    }
    let l = nearest(geom, 1.0, &pose).ok_or(no("left"))?.1;
    let r = nearest(geom, -1.0, &pose).ok_or(no("right"))?.1;
    Err(ConicityError::NotConverged {
        shift: y,
        gap_left: l.gap,
        gap_right: r.gap,
    })
}

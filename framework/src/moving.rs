//! Moving reference frames: carriers that move along a path and the nodes they carry
//! (the paper's Section 2.2 and Eq. 5).
//!
//! A train's gross motion along the track is prescribed: station `s(t) = s0 + v·t + ½·a·t²`.
//! The finite element unknowns of the nodes a carrier carries are deviations from that
//! motion, expressed in the wheel frame 1-2-3 at the node's own station. The inertia of the
//! prescribed motion enters as loads, exactly: for every element with mass on carried nodes,
//! `f = M·(g − a_ref)` with `a_ref` the acceleration of the reference motion at each DOF
//! (centripetal `v²κ` across the track, `a` along it, and the yaw angular acceleration
//! `κ·a + v²·dκ/ds` about the vertical). For a lumped mass `m` with yaw inertia `I` this is
//! exactly Eq. 5: `m·v²/R` outwards, `m·a` along the track and `I·a/R` about the vertical
//! (on a circular arc, where `dκ/ds = 0`). The rotating frame's Coriolis and transport terms
//! acting on the (small) deviations are neglected; at `v = 80 m/s`, `R = 6250 m` the frame
//! turns at `v/R = 0.013 rad/s`.
//!
//! What lives here is the [`Path`] contract (implemented by the track alignment in the
//! elements crate) and the [`Carrier`]; the loads they produce are assembled in
//! [`crate::loads`].

use crate::speed::SpeedHistory;
use nalgebra::{Matrix3, Vector3};
use std::fmt::Debug;
use std::sync::Arc;

/// The geometry of a path at one station.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PathPoint {
    /// Station along the path (m).
    pub station: f64,
    /// Position of the track centre line in global X-Y-Z (m), at rail-top level.
    pub position: Vector3<f64>,
    /// Unit tangent (direction of travel), global.
    pub tangent: Vector3<f64>,
    /// Signed plan curvature κ (1/m), positive for a left-hand curve.
    pub curvature: f64,
    /// dκ/ds (1/m²).
    pub curvature_rate: f64,
    /// Cant angle θ (rad), positive when the outer rail is higher.
    pub cant: f64,
    /// Wheel frame 1-2-3 in global coordinates (columns): axis 1 across the canted track
    /// plane towards the left of travel, axis 2 normal to the track plane (up), axis 3 the
    /// tangent.
    pub frame: Matrix3<f64>,
}

/// Anything a carrier can move along: a track alignment with cant.
pub trait Path: Send + Sync + Debug {
    /// Total length (m).
    fn length(&self) -> f64;
    /// Geometry at `station` (m); stations outside `[0, length]` extrapolate the end
    /// segments as straight lines.
    fn at(&self, station: f64) -> PathPoint;
}

/// A node carried by a carrier: its station offset from the carrier's station and its
/// offset in the wheel frame at that station.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CarriedNode {
    /// Node index in the model.
    pub node: usize,
    /// Station offset from the carrier's reference station (m), positive forwards.
    pub station_offset: f64,
    /// Offset along wheel-frame axis 1 (m, towards the left of travel).
    pub lateral: f64,
    /// Offset along wheel-frame axis 2 (m, up from the rail-top plane).
    pub vertical: f64,
    /// Offset along wheel-frame axis 3 (m, forwards) at the node's station: lets a slave
    /// share its master's frame while sitting elsewhere on the rigid body.
    pub longitudinal: f64,
}

/// A moving reference frame: prescribed motion `s(t) = s0 + v·t + ½·a·t²` along a path
/// (a deceleration stops at rest at `t = v/|a|` and stays there), or a speed table.
#[derive(Debug, Clone)]
pub struct Carrier {
    /// Name used in messages and outputs.
    pub name: String,
    /// The path it moves along.
    pub path: Arc<dyn Path>,
    /// Station at t = 0 (m).
    pub start: f64,
    /// Speed at t = 0 (m/s).
    pub speed: f64,
    /// Constant acceleration along the path (m/s²).
    pub accel: f64,
    /// A speed history that replaces `start`, `speed` and `accel` when given (a table of
    /// speed against time, [`SpeedHistory`]).
    pub speed_table: Option<Arc<SpeedHistory>>,
    /// The nodes it carries.
    pub nodes: Vec<CarriedNode>,
}

/// Reference kinematics of a carried point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ReferenceMotion {
    /// The path geometry at the point's station.
    pub point: PathPoint,
    /// Reference position (m), global.
    pub position: Vector3<f64>,
    /// Reference linear acceleration (m/s²), global.
    pub acceleration: Vector3<f64>,
    /// Reference angular acceleration (rad/s²), global.
    pub angular_acceleration: Vector3<f64>,
}

impl Carrier {
    /// Time at which a deceleration brings the carrier to rest (s), as [`SpeedHistory`]
    /// has it ([`crate::speed::braking_stop`]).
    fn stop_time(&self) -> f64 {
        crate::speed::braking_stop(self.speed, self.accel)
    }

    /// Station of the carrier's reference point at time `t` (s).
    pub fn station(&self, t: f64) -> f64 {
        if let Some(h) = &self.speed_table {
            return h.station(t);
        }
        let t = t.min(self.stop_time());
        self.start + self.speed * t + 0.5 * self.accel * t * t
    }

    /// Speed at time `t` (m/s).
    pub fn speed_at(&self, t: f64) -> f64 {
        if let Some(h) = &self.speed_table {
            return h.speed(t);
        }
        if t >= self.stop_time() {
            return 0.0;
        }
        self.speed + self.accel * t
    }

    /// Acceleration along the path at time `t` (m/s²): zero once a deceleration has
    /// brought the carrier to rest.
    pub fn accel_at(&self, t: f64) -> f64 {
        if let Some(h) = &self.speed_table {
            return h.accel(t);
        }
        if t >= self.stop_time() {
            return 0.0;
        }
        self.accel
    }

    /// Reference motion of a carried node at time `t`.
    ///
    /// The point rides on the centre line at station `s = s(t) + Δs`, offset by
    /// `lateral·e1 + vertical·e2 + longitudinal·e3` in the wheel frame. Its acceleration is that of the
    /// centre-line point: `a·t̂ + v²κ·n̂` with `n̂ = Z × t̂` the horizontal left normal
    /// (Eq. 5's centripetal term, signed by κ), and the frame's yaw angular acceleration
    /// `(κ·a + v²·κ')·Z`.
    pub fn reference(&self, cn: &CarriedNode, t: f64) -> ReferenceMotion {
        let s = self.station(t) + cn.station_offset;
        let p = self.path.at(s);
        let v = self.speed_at(t);
        let a = self.accel_at(t);
        let up = Vector3::z();
        let normal = up.cross(&p.tangent);
        let position = p.position
            + p.frame.column(0) * cn.lateral
            + p.frame.column(1) * cn.vertical
            + p.frame.column(2) * cn.longitudinal;
        let acceleration = p.tangent * a + normal * (v * v * p.curvature);
        let angular_acceleration = up * (p.curvature * a + v * v * p.curvature_rate);
        ReferenceMotion {
            point: p,
            position,
            acceleration,
            angular_acceleration,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Debug)]
    struct Line;

    impl Path for Line {
        fn length(&self) -> f64 {
            1000.0
        }
        fn at(&self, station: f64) -> PathPoint {
            PathPoint {
                station,
                position: Vector3::new(station, 0.0, 0.0),
                tangent: Vector3::x(),
                curvature: 0.0,
                curvature_rate: 0.0,
                cant: 0.0,
                frame: Matrix3::new(0.0, 0.0, 1.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0),
            }
        }
    }

    fn carrier(speed: f64, accel: f64) -> Carrier {
        Carrier {
            name: "c".into(),
            path: Arc::new(Line),
            start: 10.0,
            speed,
            accel,
            speed_table: None,
            nodes: Vec::new(),
        }
    }

    /// A deceleration stops the carrier at t = v/|a| after v²/(2|a|) and holds it there
    /// (speed and acceleration zero); a carrier at rest stays at rest; without a
    /// deceleration the motion is the closed form s0 + v·t + ½·a·t².
    #[test]
    fn braking_stops_at_rest_and_holds() {
        let c = carrier(10.0, -5.0);
        assert_eq!(c.station(1.0), 10.0 + 10.0 - 2.5);
        assert_eq!(c.station(2.0), 20.0);
        assert_eq!(c.station(7.0), 20.0);
        assert_eq!((c.speed_at(3.0), c.accel_at(3.0)), (0.0, 0.0));
        assert_eq!((c.speed_at(1.0), c.accel_at(1.0)), (5.0, -5.0));
        let rest = carrier(0.0, -5.0);
        assert_eq!((rest.station(4.0), rest.speed_at(4.0)), (10.0, 0.0));
        let go = carrier(3.0, 2.0);
        assert_eq!(go.station(4.0), 10.0 + 12.0 + 16.0);
        assert_eq!(go.speed_at(4.0), 11.0);
    }
}

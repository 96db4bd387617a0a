//! Cant (superelevation) and the [`Track`]: an alignment with cant, the frames of the
//! paper's Section 2.1, and the [`Path`] a moving carrier follows.
//!
//! What lives here: [`Cant`] (θ = Ct/R of Eq. 21, or a table), [`Track`] (alignment + cant +
//! gauge) with its track frame x-y-z (Eq. 1) and wheel frame 1-2-3, `impl Path for Track`, and
//! the model-file spec [`TrackSpec`].
//!
//! # Frames and the sense of the cant
//!
//! Track frame at station s (Eq. 1): z = the unit tangent t = (cos ψ, sin ψ, 0); y = global Z
//! (up); x = y × z = (−sin ψ, cos ψ, 0), to the left of travel (towards the centre of a
//! left-hand curve).
//!
//! Cant raises the OUTER rail: the track plane dips towards the centre of the curve. With the
//! signed cant θ_s = sign(κ)·θ (θ ≥ 0 the cant magnitude; sign(0) taken as +1) the wheel frame
//! is x-y rolled about z:
//!
//! ```text
//! e1 = cos θ_s · x − sin θ_s · y     (across the canted plane, to the left of travel)
//! e2 = sin θ_s · x + cos θ_s · y     (normal to the canted plane, up)
//! e3 = z
//! ```
//!
//! For a left-hand curve (θ_s = θ) e1 points left and down, towards the lower inner rail, and
//! e2 leans towards the centre: with gravity −W·Z and the centrifugal force (W/g)·V²/R pointing
//! outwards these axes reproduce Eqs. 22–23 exactly. The printed Eq. 2 has the opposite sign
//! of θ and is NOT followed (see `shared/spec/moving-axle.md`). For a right-hand curve
//! (θ_s = −θ) the left rail is the outer, higher one and F1 of Eq. 22 changes sign (it is
//! measured along e1, which still points left). The track centre line stays at Z = 0 and the
//! rails roll about it: the outer rail is (G/2)·sin θ above it, the inner one as much below.

use crate::rail::geometry::alignment::{Alignment, AlignmentError, SegmentSpec};
use nalgebra::{Matrix3, Vector3};
use railfem_framework::moving::{Path, PathPoint};
use serde::Deserialize;

/// Standard gauge G (m), the paper's Section 3.1.
pub const STANDARD_GAUGE: f64 = 1.435;

/// The cant law along a track. Angles in rad, always as a magnitude θ ≥ 0 (outer rail
/// higher); the hand comes from the sign of the curvature.
#[derive(Debug, Clone, PartialEq)]
pub enum Cant {
    /// θ = Ct·|κ| = Ct/R (Eq. 21), `ct` in metres: zero on straights, linear in curvature
    /// (hence in station) along a clothoid, constant on an arc.
    FromRadius {
        /// The designer's constant Ct (m), ≥ 0.
        ct: f64,
    },
    /// θ interpolated linearly in station from `(station m, θ rad)` points (stations
    /// strictly increasing), held constant beyond the first and last points. Where κ = 0 a
    /// positive θ raises the right rail (as on a left-hand curve).
    Table(Vec<(f64, f64)>),
}

impl Cant {
    /// No cant.
    pub fn none() -> Self {
        Cant::FromRadius { ct: 0.0 }
    }

    /// Cant magnitude θ (rad) at `station` where the curvature is `curvature` (1/m).
    pub fn angle(&self, station: f64, curvature: f64) -> f64 {
        match self {
            Cant::FromRadius { ct } => ct * curvature.abs(), // Eq. 21
            Cant::Table(points) => {
                let k = points.partition_point(|p| p.0 <= station);
                if k == 0 {
                    points[0].1
                } else if k == points.len() {
                    points[k - 1].1
                } else {
                    let ((s0, t0), (s1, t1)) = (points[k - 1], points[k]);
                    t0 + (t1 - t0) * (station - s0) / (s1 - s0)
                }
            }
        }
    }

    /// Checks the data: Ct finite and ≥ 0; a table non-empty, finite, stations strictly
    /// increasing and |θ| < π/2.
    pub fn validate(&self) -> Result<(), AlignmentError> {
        match self {
            Cant::FromRadius { ct } => {
                if !ct.is_finite() || *ct < 0.0 {
                    return Err(AlignmentError::Cant(format!(
                        "Ct = {ct}; give a finite Ct ≥ 0 m (θ = Ct/R, Eq. 21)"
                    )));
                }
            }
            Cant::Table(points) => {
                if points.is_empty() {
                    return Err(AlignmentError::Cant(
                        "the cant table is empty; give [[station, angle], ...]".into(),
                    ));
                }
                for (i, &(s, t)) in points.iter().enumerate() {
                    if !s.is_finite() || !t.is_finite() || t.abs() >= std::f64::consts::FRAC_PI_2 {
                        return Err(AlignmentError::Cant(format!(
                            "table point {i} ({s}, {t}) must be finite with |angle| < π/2 rad"
                        )));
                    }
                    if i > 0 && s <= points[i - 1].0 {
                        return Err(AlignmentError::Cant(format!(
                            "table stations must increase strictly; point {i} at {s} m follows {} m",
                            points[i - 1].0
                        )));
                    }
                }
            }
        }
        Ok(())
    }
}

/// A track: plan alignment, cant and gauge. Implements [`Path`].
#[derive(Debug, Clone, PartialEq)]
pub struct Track {
    /// The plan alignment.
    pub alignment: Alignment,
    /// The cant law.
    pub cant: Cant,
    /// Gauge G (m): the rail lines are at ±G/2 along wheel axis 1.
    pub gauge: f64,
}

impl Track {
    /// A track of standard gauge from an alignment and a cant law (checked).
    pub fn new(alignment: Alignment, cant: Cant) -> Result<Self, AlignmentError> {
        cant.validate()?;
        Ok(Self {
            alignment,
            cant,
            gauge: STANDARD_GAUGE,
        })
    }

    /// The same track with another gauge (m).
    ///
    /// # Panics
    /// If `gauge` is not a finite number > 0.
    pub fn with_gauge(mut self, gauge: f64) -> Self {
        assert!(gauge.is_finite() && gauge > 0.0, "gauge must be > 0 m");
        self.gauge = gauge;
        self
    }

    /// The paper's track: [`Alignment::paper`] (left-hand, arc radius `radius` m) with
    /// θ = Ct/R (Eq. 21, `ct` in m) and standard gauge.
    ///
    /// # Panics
    /// If `radius` is not a finite number > 0 or `ct` not a finite number ≥ 0.
    pub fn paper(radius: f64, ct: f64) -> Self {
        Self::new(Alignment::paper(radius), Cant::FromRadius { ct })
            .expect("Track::paper: Ct must be a finite number >= 0 m")
    }

    /// Signed cant θ_s = sign(κ)·θ (rad) at `station`, sign(0) = +1: the roll of the wheel
    /// frame about the tangent.
    pub fn signed_cant(&self, station: f64) -> f64 {
        let k = self.alignment.at(station).curvature;
        let theta = self.cant.angle(station, k);
        if k < 0.0 {
            -theta
        } else {
            theta
        }
    }

    /// Track frame x-y-z (Eq. 1) at `station` as matrix columns, global components.
    pub fn track_frame(&self, station: f64) -> Matrix3<f64> {
        track_frame(self.alignment.at(station).heading)
    }
}

/// Track frame x-y-z (Eq. 1) for heading ψ (rad): columns x = (−sin ψ, cos ψ, 0),
/// y = (0, 0, 1), z = (cos ψ, sin ψ, 0).
pub fn track_frame(heading: f64) -> Matrix3<f64> {
    let (s, c) = heading.sin_cos();
    Matrix3::from_columns(&[
        Vector3::new(-s, c, 0.0),
        Vector3::z(),
        Vector3::new(c, s, 0.0),
    ])
}

/// Wheel frame 1-2-3 for heading ψ and signed cant θ_s (rad), as matrix columns:
/// e1 = cos θ_s·x − sin θ_s·y, e2 = sin θ_s·x + cos θ_s·y, e3 = z (see the module doc; the
/// printed Eq. 2 has the opposite sign of θ).
pub fn wheel_frame(heading: f64, signed_cant: f64) -> Matrix3<f64> {
    let t = track_frame(heading);
    let (x, y, z) = (t.column(0), t.column(1), t.column(2));
    let (s, c) = signed_cant.sin_cos();
    Matrix3::from_columns(&[x * c - y * s, x * s + y * c, z.into_owned()])
}

impl Path for Track {
    fn length(&self) -> f64 {
        self.alignment.length()
    }

    /// Geometry at `station`. `cant` is the magnitude θ ≥ 0 (outer rail higher); the hand is
    /// in the frame (θ_s = sign(κ)·θ). The position is the centre line at Z = 0.
    fn at(&self, station: f64) -> PathPoint {
        let p = self.alignment.at(station);
        let theta = self.cant.angle(station, p.curvature);
        let signed = if p.curvature < 0.0 { -theta } else { theta };
        PathPoint {
            station,
            position: Vector3::new(p.x, p.y, 0.0),
            tangent: Vector3::new(p.heading.cos(), p.heading.sin(), 0.0),
            curvature: p.curvature,
            curvature_rate: p.curvature_rate,
            cant: theta,
            frame: wheel_frame(p.heading, signed),
        }
    }
}

fn default_gauge() -> f64 {
    STANDARD_GAUGE
}

/// The `[track]` table of a model file:
///
/// ```toml
/// [track]
/// segments = [{type = "straight", length = 500}, {type = "clothoid", length = 2000},
///             {type = "arc", length = 10908.3078, radius = 6250, hand = "left"},
///             {type = "clothoid", length = 2000}, {type = "straight", length = 800}]
/// ct = 200            # θ = Ct/R (Eq. 21), m; or
/// # cant_table = [[0, 0], [2500, 0.032]]   # (station m, θ rad)
/// gauge = 1.435       # m, default standard gauge
/// ```
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TrackSpec {
    /// The segments, in order of travel.
    pub segments: Vec<SegmentSpec>,
    /// Cant constant Ct (m) of Eq. 21.
    #[serde(default)]
    pub ct: Option<f64>,
    /// Cant table of (station m, θ rad) points.
    #[serde(default)]
    pub cant_table: Option<Vec<(f64, f64)>>,
    /// Gauge (m).
    #[serde(default = "default_gauge")]
    pub gauge: f64,
}

impl TrackSpec {
    /// Builds the track; no cant given means none.
    pub fn build(&self) -> Result<Track, AlignmentError> {
        let cant = match (&self.ct, &self.cant_table) {
            (Some(_), Some(_)) => {
                return Err(AlignmentError::Cant(
                    "give either ct or cant_table, not both".into(),
                ))
            }
            (Some(ct), None) => Cant::FromRadius { ct: *ct },
            (None, Some(t)) => Cant::Table(t.clone()),
            (None, None) => Cant::none(),
        };
        if !self.gauge.is_finite() || self.gauge <= 0.0 {
            return Err(AlignmentError::Cant(format!(
                "gauge = {}; give a finite gauge > 0 m",
                self.gauge
            )));
        }
        Ok(Track::new(SegmentSpec::build(&self.segments)?, cant)?.with_gauge(self.gauge))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rail::geometry::alignment::{Hand, Segment};

    const G: f64 = 9.81;

    #[test]
    fn paper_cant_values() {
        for (ct, want) in [(200.0, 0.032), (900.0, 0.144)] {
            let t = Track::paper(6250.0, ct);
            assert!((t.at(7000.0).cant - want).abs() < 1e-15);
            assert_eq!(t.at(100.0).cant, 0.0);
            assert_eq!(t.at(16_000.0).cant, 0.0);
            // Linear on the clothoids.
            for f in [0.0, 0.3, 0.5, 1.0] {
                assert!((t.at(500.0 + 2000.0 * f).cant - want * f).abs() < 1e-15);
                assert!((t.at(13_408.307_8 + 2000.0 * f).cant - want * (1.0 - f)).abs() < 1e-12);
            }
        }
    }

    #[test]
    fn frames_orthonormal_right_handed_and_tangent() {
        for hand in [Hand::Left, Hand::Right] {
            let t = Track::new(
                Alignment::paper_hand(300.0, hand),
                Cant::FromRadius { ct: 100.0 },
            )
            .unwrap();
            for s in [
                -10.0,
                0.0,
                250.0,
                700.0,
                2500.0,
                9000.0,
                14_000.0,
                16_208.307_8,
                17_000.0,
            ] {
                let p = t.at(s);
                let f = p.frame;
                assert!((f.transpose() * f - Matrix3::identity()).norm() < 1e-14);
                assert!((f.determinant() - 1.0).abs() < 1e-14);
                assert!((f.column(2) - p.tangent).norm() < 1e-15);
                // Axis 1 is across the track to the left of travel: positive on Z × t.
                assert!(f.column(0).dot(&Vector3::z().cross(&p.tangent)) > 0.0);
                // Roll angle about the tangent equals the signed cant.
                let roll = (-f[(2, 0)]).asin();
                assert!((roll - t.signed_cant(s)).abs() < 1e-14);
            }
        }
    }

    /// Eqs. 22–23: gravity −W·Z and the centrifugal force (W/g)V²/R pointing away from the
    /// centre, resolved on the wheel axes 1 and 2.
    #[test]
    fn gravity_and_centrifugal_reproduce_eqs_22_23() {
        let (w, v, r) = (1.0e5, 80.0, 6250.0);
        for ct in [200.0, 900.0] {
            for hand in [Hand::Left, Hand::Right] {
                let t =
                    Track::new(Alignment::paper_hand(r, hand), Cant::FromRadius { ct }).unwrap();
                let p = t.at(7000.0);
                let theta = p.cant;
                assert!((theta - ct / r).abs() < 1e-15);
                // Outwards = away from the centre = −sign(κ)·(Z × t).
                let n_left = Vector3::z().cross(&p.tangent);
                let outwards = -n_left * p.curvature.signum();
                let force = -Vector3::z() * w + outwards * (w / G) * v * v / r;
                let f1 = force.dot(&p.frame.column(0));
                let f2 = force.dot(&p.frame.column(1));
                let f1_eq22 = w * theta.sin() - (w / G) * v * v * theta.cos() / r;
                let f2_eq23 = -w * theta.cos() - (w / G) * v * v * theta.sin() / r;
                let mirror = hand.sign(); // F1 along e1 (left) changes sign for a right-hand curve.
                assert!(
                    (f1 - mirror * f1_eq22).abs() < 1e-9 * w,
                    "{hand:?} {f1} {f1_eq22}"
                );
                assert!((f2 - f2_eq23).abs() < 1e-9 * w, "{hand:?} {f2} {f2_eq23}");
            }
        }
    }

    #[test]
    fn outer_rail_is_higher() {
        for hand in [Hand::Left, Hand::Right] {
            let t = Track::new(
                Alignment::paper_hand(6250.0, hand),
                Cant::FromRadius { ct: 900.0 },
            )
            .unwrap();
            let e1 = t.at(7000.0).frame.column(0).into_owned();
            // The left rail at +G/2·e1: lower on a left-hand curve (it is the inner rail).
            let left_z = 0.5 * t.gauge * e1.z;
            let want = -hand.sign() * 0.5 * t.gauge * (0.144f64).sin();
            assert!((left_z - want).abs() < 1e-15);
        }
    }

    #[test]
    fn cant_table_and_spec() {
        let a = Alignment::new(vec![
            Segment::Straight { length: 100.0 },
            Segment::Arc {
                length: 100.0,
                radius: 500.0,
                hand: Hand::Right,
            },
        ])
        .unwrap();
        let t = Track::new(a, Cant::Table(vec![(50.0, 0.0), (150.0, 0.1)])).unwrap();
        assert_eq!(t.at(0.0).cant, 0.0);
        assert!((t.at(100.0).cant - 0.05).abs() < 1e-15);
        assert!((t.at(200.0).cant - 0.1).abs() < 1e-15);
        assert!((t.signed_cant(120.0) + 0.07).abs() < 1e-15);
        assert!(Cant::Table(vec![(1.0, 0.0), (1.0, 0.1)])
            .validate()
            .is_err());
        assert!(Cant::FromRadius { ct: f64::NAN }.validate().is_err());

        let json = r#"{"segments":[{"type":"straight","length":500},{"type":"clothoid","length":2000},
            {"type":"arc","length":10908.3078,"radius":6250,"hand":"left"},
            {"type":"clothoid","length":2000},{"type":"straight","length":800}], "ct": 200}"#;
        let spec: TrackSpec = railfem_framework::serde_json::from_str(json).unwrap();
        assert_eq!(spec.build().unwrap(), Track::paper(6250.0, 200.0));
        let both = r#"{"segments":[{"type":"straight","length":5}],"ct":1,"cant_table":[[0,0]]}"#;
        let spec: TrackSpec = railfem_framework::serde_json::from_str(both).unwrap();
        assert!(spec.build().unwrap_err().to_string().contains("not both"));
    }

    #[test]
    fn carrier_on_track_accelerates_towards_the_centre() {
        use railfem_framework::moving::{CarriedNode, Carrier};
        for hand in [Hand::Left, Hand::Right] {
            let track = Track::new(
                Alignment::paper_hand(6250.0, hand),
                Cant::FromRadius { ct: 200.0 },
            )
            .unwrap();
            let c = Carrier {
                name: "car".into(),
                path: std::sync::Arc::new(track.clone()),
                start: 7000.0,
                speed: 80.0,
                accel: 0.0,
                speed_table: None,
                nodes: vec![],
            };
            let node = CarriedNode {
                node: 0,
                station_offset: 0.0,
                lateral: 0.0,
                vertical: 0.0,
                longitudinal: 0.0,
            };
            let m = c.reference(&node, 0.0);
            // Centripetal v²/R towards the centre: the centre is at position + R·(Z × t)·sign(κ).
            let p = track.at(7000.0);
            let to_centre = Vector3::z().cross(&p.tangent) * hand.sign();
            assert!((m.acceleration - to_centre * 80.0 * 80.0 / 6250.0).norm() < 1e-12);
        }
    }
}

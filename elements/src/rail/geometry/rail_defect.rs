//! Rail-top defects, the entries of `[track] dips`: dipped rail joints and isolated defects
//! of one rail's head (squats, local dips), as a vertical deviation of the rail top that
//! every wheel sees at its station (docs/defects.md).
//!
//! A defect lowers the rail top around `station` over `length` by one of three shapes
//! (`x = s − station`, `|x| ≤ length/2`, zero outside; `d` the depth):
//!
//! | shape | `w(x)` | smoothness | largest slope |
//! |---|---|---|---|
//! | `squared_cosine` (default) | `−d·[½(1 + cos(2πx/L))]²` | C² | `(3√3π/4)·d/L` at `|x| = L/6` |
//! | `cosine` | `−(d/2)·(1 + cos(2πx/L))` | C¹ | `π·d/L` at `|x| = L/4` |
//! | `vee` | `−d·(1 − 2|x|/L)` | C⁰ | `2d/L` on both ramps |
//!
//! The slopes: for the squared cosine `w' = (d·k/2)(1 + cos θ) sin θ` (`θ = kx`,
//! `k = 2π/L`), largest where `d/dθ[(1 + cos θ) sin θ] = 2cos²θ + cos θ − 1 = 0`, i.e.
//! `cos θ = ½`, where `(1 + cos θ) sin θ = 3√3/4`; for the cosine `w' = (d·k/2) sin θ`.
//!
//! **Angle.** A dipped joint is usually described by its total angle `2α` (rad): the rail
//! ends meet at the joint each sloping down by `α`, so a wheel's vertical velocity turns by
//! `2αV` there — the input of Jenkins et al. (1974)'s P2 formula. Given `angle = 2α`, the
//! depth is the one whose largest slope is `α`: `d = 2α·L/4` (vee), `2α·L/(2π)` (cosine),
//! `2α·2L/(3√3π)` (squared cosine). Only the `vee` is the formula's idealisation (a slope
//! step of 2α at one point, and α at the dip's two ends); the smooth shapes spread the
//! turn over a length (L/3 for the squared cosine, L/2 for the cosine), which lowers the
//! P2 force once that length is not short against the P2 wavelength `V/f_P2`.
//!
//! **Rails.** `rail = "both"` (default: a joint dipped on both rails, as `dips` always was),
//! `"left"` or `"right"` (an isolated defect of one rail head).

use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// Which rail a defect lowers.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum RailSide {
    /// Both rails (a joint dipped across the track).
    #[default]
    Both,
    /// The left rail (rail 0, axis 1 positive).
    Left,
    /// The right rail (rail 1).
    Right,
}

impl RailSide {
    /// Whether the defect lies on rail `rail` (0 left, 1 right).
    pub fn includes(self, rail: usize) -> bool {
        match self {
            RailSide::Both => true,
            RailSide::Left => rail == 0,
            RailSide::Right => rail == 1,
        }
    }
}

/// The shape of a rail-top defect (module doc).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum DipShape {
    /// `−d·[½(1 + cos(2πx/L))]²`, C².
    #[default]
    SquaredCosine,
    /// `−(d/2)·(1 + cos(2πx/L))`, C¹ (the rounded shape of squats and flats).
    Cosine,
    /// `−d·(1 − 2|x|/L)`: straight ramps into the joint.
    Vee,
}

impl DipShape {
    /// Largest slope of the shape per unit depth, times the length (-): module doc.
    pub fn slope_factor(self) -> f64 {
        match self {
            DipShape::SquaredCosine => 3.0 * 3f64.sqrt() * PI / 4.0,
            DipShape::Cosine => PI,
            DipShape::Vee => 2.0,
        }
    }
}

/// One rail-top defect of `[track] dips` (a dipped joint by default: both rails, squared
/// cosine).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct JointDip {
    /// Station of the joint or the defect's centre (m).
    pub station: f64,
    /// Depth (m, > 0); give this or `angle`.
    #[serde(default)]
    pub depth: f64,
    /// Length of the lowered zone (m, > 0).
    pub length: f64,
    /// Total joint angle 2α (rad); the depth then follows from the shape (module doc).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub angle: Option<f64>,
    /// Which rail: both (default), left or right.
    #[serde(default)]
    pub rail: RailSide,
    /// Shape (default the C² squared cosine).
    #[serde(default)]
    pub shape: DipShape,
}

impl JointDip {
    /// The depth (m): `depth`, or the one whose largest slope is half of `angle`.
    pub fn effective_depth(&self) -> f64 {
        match self.angle {
            Some(a) => 0.5 * a * self.length / self.shape.slope_factor(),
            None => self.depth,
        }
    }

    /// Checks the numbers; the message names the key and the fix.
    pub fn validate(&self) -> Result<(), String> {
        if !self.station.is_finite() {
            return Err("`station` is not finite; give the joint's station in m".into());
        }
        if !(self.length.is_finite() && self.length > 0.0) {
            return Err(format!(
                "`length` = {}; give the length of the lowered zone, > 0 m",
                self.length
            ));
        }
        match self.angle {
            Some(_) if self.depth != 0.0 => Err(
                "both `depth` and `angle` are given; give one (the angle sets the depth through the shape)".into(),
            ),
            Some(a) if !(a.is_finite() && a > 0.0 && a < 0.2) => Err(format!(
                "`angle` = {a}; give the total joint angle 2α in rad, 0 < 2α < 0.2 (dipped joints are some mrad)"
            )),
            None if !(self.depth.is_finite() && self.depth > 0.0) => Err(format!(
                "`depth` = {}; give a depth > 0 m, or the total joint angle `angle` (rad)",
                self.depth
            )),
            _ => Ok(()),
        }
    }

    /// Rail-top height change at station `s` (m, negative down), whichever rail.
    pub fn height(&self, s: f64) -> f64 {
        let x = s - self.station;
        if x.abs() >= 0.5 * self.length {
            return 0.0;
        }
        let d = self.effective_depth();
        let c = (2.0 * PI * x / self.length).cos();
        match self.shape {
            DipShape::SquaredCosine => {
                let f = 0.5 * (1.0 + c);
                -d * f * f
            }
            DipShape::Cosine => -0.5 * d * (1.0 + c),
            DipShape::Vee => -d * (1.0 - 2.0 * x.abs() / self.length),
        }
    }

    /// Rail-top height change of rail `rail` (0 left, 1 right) at station `s` (m): zero on
    /// the rail the defect is not on.
    pub fn height_on(&self, rail: usize, s: f64) -> f64 {
        if self.rail.includes(rail) {
            self.height(s)
        } else {
            0.0
        }
    }

    /// Second derivative of [`JointDip::height`] along the track (1/m); at the vee's kinks
    /// (Dirac impulses of curvature) it is zero.
    pub fn curvature(&self, s: f64) -> f64 {
        let x = s - self.station;
        if x.abs() >= 0.5 * self.length {
            return 0.0;
        }
        let d = self.effective_depth();
        let k = 2.0 * PI / self.length;
        let (sn, c) = (k * x).sin_cos();
        match self.shape {
            DipShape::SquaredCosine => -0.5 * d * k * k * (sn * sn - c - c * c),
            DipShape::Cosine => 0.5 * d * k * k * c,
            DipShape::Vee => 0.0,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The curvature is the second difference of the height, for the smooth shapes.
    #[test]
    fn curvature_is_the_second_derivative() {
        for shape in [DipShape::SquaredCosine, DipShape::Cosine] {
            let d = JointDip {
                station: 3.0,
                depth: 2e-3,
                length: 1.0,
                shape,
                ..Default::default()
            };
            let h = 1e-4;
            for s in [2.7, 2.9, 3.0, 3.2, 3.4] {
                let fd = (d.height(s + h) - 2.0 * d.height(s) + d.height(s - h)) / (h * h);
                assert!(
                    (fd - d.curvature(s)).abs() < 1e-5 * 2e-3 * 40.0,
                    "{shape:?} {s}"
                );
            }
        }
    }

    #[test]
    fn bad_dips_are_refused() {
        let base = JointDip {
            station: 1.0,
            depth: 1e-3,
            length: 1.0,
            ..Default::default()
        };
        let both = JointDip {
            angle: Some(0.01),
            ..base
        };
        assert!(both.validate().unwrap_err().contains("give one"));
        let none = JointDip { depth: 0.0, ..base };
        assert!(none.validate().unwrap_err().contains("`angle`"));
        let long = JointDip {
            length: -1.0,
            ..base
        };
        assert!(long.validate().unwrap_err().contains("`length`"));
        assert!(base.validate().is_ok());
    }
}

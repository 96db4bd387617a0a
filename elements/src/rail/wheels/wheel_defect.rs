//! Wheel tread defects — wheel flats and polygonal (out-of-round) wheels — as the radial
//! deviation of the tread that a rolling wheel brings into its contact with the rail.
//!
//! # What a defect is here
//!
//! A defect is a deviation `e(φ)` of the wheel's running surface from the circle, a
//! function of the wheel's rolling angle `φ = s/R` (`s` the distance the wheel has rolled
//! from its start, `R` its rolling radius), periodic in `2π` (in `s`: one circumference
//! `2πR`). Negative `e` is missing material. A point-contact wheel rolling on a rail whose
//! top is at height `z(s)` has its centre at `z(s) + e(s/R) + R` above the rail's reference:
//! a tread deviation acts on the contact exactly as a rail-top deviation of the same sign
//! does, so every wheel element adds `e` to the rail-top irregularity it already reads
//! (`moving_axle`, `hertz_wheel`, `rigid_wheel`: docs/defects.md). Like the rail-top
//! offsets, `e` is measured from its value where the wheel starts ([`TreadOffset`]), so a
//! wheel starts just touching the rail.
//!
//! # Wheel flats
//!
//! A flat of length `L` (along the tread) centred at rolling angle `φc`. With
//! `x = R·wrap(φ − φc)` the arc length from the flat's centre (`wrap` into `(−π, π]`):
//!
//! - **fresh** (a chord, as a sliding wheel grinds it): the chord's sagitta is the depth,
//!   `d = R − √(R² − L²/4) ≈ L²/(8R)` (plane geometry of a chord of length `L` in a circle
//!   of radius `R`). The wheel does not follow the chord itself: it rolls on its circle
//!   until the flat's leading corner touches the rail, pivots about that corner until the
//!   flat lies on the rail, then pivots about the trailing corner. Pivoting about a corner
//!   at horizontal distance `ξ` behind the centre puts the centre `√(R² − ξ²)` above it, so
//!   the centre's path, as a deviation, is
//!
//!   ```text
//!   e(x) = −(R − √(R² − ξ²)),   ξ = L/2 − |x|,   |x| ≤ L/2,
//!   ```
//!
//!   zero with zero slope at the corners, the full depth `d` at the centre, where its
//!   slope jumps from `−tan θ0` to `+tan θ0`, `sin θ0 = L/(2R)`, i.e. by about `L/R` (the
//!   trailing corner strikes the rail). The
//!   rolled arc `x` and the centre's travel differ by `R·(θ − sin θ) = O(L³/R²)` over the
//!   flat (under 0.1 µm for L = 50 mm on R = 0.46 m), neglected. This is the wheel-centre
//!   trajectory of a new flat in Newton & Clark (1979) and Wu & Thompson (2002).
//! - **rounded** (the worn, rounded flat of Newton & Clark 1979, used by Wu & Thompson
//!   2002): `e(x) = −(d/2)·(1 + cos(2πx/L))` for `|x| ≤ L/2`, i.e. `−(d/2)(1 − cos(2πx'/L))`
//!   with `x'` from the flat's start. C¹: zero value and slope at both ends; its curvature
//!   `(d/2)(2π/L)²` at the ends (the wheel is pulled away from the rail there) and
//!   `−(d/2)(2π/L)²` at the centre. Length and depth are independent (rounding lengthens a
//!   flat at about its depth).
//!
//! Contact loss: on a rigid rail at speed `v` the flat asks the wheel centre to accelerate
//! downwards at `v²·e''` where `e''` is the largest downward curvature of the path; the
//! contact can supply at most `g + P0/m` (static load `P0` on the unsprung mass `m`), so the
//! wheel leaves the rail above `v = √((g + P0/m)/max e'')` — for the rounded flat
//! `v_crit = (L/2π)·√(2(g + P0/m)/d)` (tested in `tests/defects.rs`).
//!
//! # Polygonal wheels
//!
//! Out-of-roundness as a sum of harmonics of the rolling angle:
//! `e(φ) = Σ aₙ·cos(n·φ + ϕₙ)`, order `n` (the number of lobes), amplitude `aₙ` (m),
//! phase `ϕₙ` (rad). A wheel rolling at `v` meets it at the passing frequencies
//! `fₙ = n·v/(2πR)`.

use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// Longest flat accepted (m): a quarter of a metre is far beyond any flat in service (they
/// are condemned at some tens of millimetres) but keeps the chord on the tread.
pub const MAX_FLAT_LENGTH: f64 = 0.25;
/// Largest depth or harmonic amplitude accepted (m): 10 mm.
pub const MAX_DEPTH: f64 = 0.01;
/// Largest polygon order accepted.
pub const MAX_ORDER: u32 = 100;

/// The shape of a wheel flat.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FlatShape {
    /// A chord: the wheel pivots about its corners; depth follows from length and radius.
    Fresh,
    /// The rounded (worn) flat `−(d/2)(1 + cos(2πx/L))`.
    #[default]
    Rounded,
}

/// One harmonic of a polygonal wheel.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Harmonic {
    /// Order `n`: lobes per revolution (1 = eccentricity).
    pub order: u32,
    /// Radial amplitude `aₙ` (m).
    pub amplitude: f64,
    /// Phase `ϕₙ` (rad).
    #[serde(default)]
    pub phase: f64,
}

fn default_flat_angle() -> f64 {
    PI
}

/// A wheel's tread defect (the element key `defect`, a vehicle's `[[wheelset]] defects`).
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum WheelDefect {
    /// A round wheel (the default).
    #[default]
    None,
    /// A wheel flat.
    Flat {
        /// Length along the tread (m).
        length: f64,
        /// Depth (m): required for a rounded flat; a fresh flat's follows from its length.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        depth: Option<f64>,
        /// Shape: "rounded" (default) or "fresh".
        #[serde(default)]
        shape: FlatShape,
        /// Rolling angle of the flat's centre from the wheel's start (rad); default π: the
        /// flat starts on top and first strikes after half a revolution.
        #[serde(default = "default_flat_angle")]
        angle: f64,
    },
    /// A polygonal (out-of-round) wheel.
    Polygon {
        /// The harmonics, summed.
        harmonics: Vec<Harmonic>,
    },
}

impl WheelDefect {
    /// Checks the numbers; the message names the key and the fix.
    pub fn validate(&self) -> Result<(), String> {
        match self {
            WheelDefect::None => Ok(()),
            WheelDefect::Flat {
                length,
                depth,
                shape,
                angle,
            } => {
                if !(length.is_finite() && *length > 0.0 && *length <= MAX_FLAT_LENGTH) {
                    return Err(format!(
                        "`defect.length` = {length}; give the flat's length along the tread, 0 < L ≤ {MAX_FLAT_LENGTH} m (e.g. 0.05)"
                    ));
                }
                if !angle.is_finite() {
                    return Err("`defect.angle` is not finite; give a rolling angle in rad".into());
                }
                match (shape, depth) {
                    (FlatShape::Fresh, Some(_)) => Err(
                        "`defect.depth` is given for a fresh flat, whose depth follows from its length and the wheel radius (the chord's sagitta ≈ L²/(8R)); remove `depth`, or give `shape = \"rounded\"`".into(),
                    ),
                    (FlatShape::Fresh, None) => Ok(()),
                    (FlatShape::Rounded, None) => Err(
                        "a rounded flat needs `defect.depth` (m), e.g. {type = \"flat\", length = 0.05, depth = 0.0007}".into(),
                    ),
                    (FlatShape::Rounded, Some(d)) => {
                        if d.is_finite() && *d > 0.0 && *d <= MAX_DEPTH && *d < *length {
                            Ok(())
                        } else {
                            Err(format!(
                                "`defect.depth` = {d}; give 0 < depth ≤ {MAX_DEPTH} m and below the length (a flat is millimetres deep, tens of millimetres long)"
                            ))
                        }
                    }
                }
            }
            WheelDefect::Polygon { harmonics } => {
                if harmonics.is_empty() {
                    return Err("`defect.harmonics` is empty; give at least one {order = 8, amplitude = 1e-4, phase = 0}".into());
                }
                for (i, h) in harmonics.iter().enumerate() {
                    if !(1..=MAX_ORDER).contains(&h.order) {
                        return Err(format!(
                            "`defect.harmonics[{i}].order` = {}; give 1 ≤ order ≤ {MAX_ORDER} (lobes per revolution)",
                            h.order
                        ));
                    }
                    if !(h.amplitude.is_finite() && h.amplitude.abs() <= MAX_DEPTH) {
                        return Err(format!(
                            "`defect.harmonics[{i}].amplitude` = {}; give |amplitude| ≤ {MAX_DEPTH} m (out-of-roundness is tenths of a millimetre)",
                            h.amplitude
                        ));
                    }
                    if !h.phase.is_finite() {
                        return Err(format!(
                            "`defect.harmonics[{i}].phase` is not finite; give an angle in rad"
                        ));
                    }
                }
                Ok(())
            }
        }
    }

    /// Depth of a flat on a wheel of rolling radius `r` (m): the given one for a rounded
    /// flat, the chord's sagitta `R − √(R² − L²/4)` for a fresh one; 0 otherwise.
    pub fn flat_depth(&self, r: f64) -> f64 {
        match self {
            WheelDefect::Flat {
                length,
                depth,
                shape,
                ..
            } => match shape {
                FlatShape::Rounded => depth.unwrap_or(0.0),
                FlatShape::Fresh => r - (r * r - 0.25 * length * length).max(0.0).sqrt(),
            },
            _ => 0.0,
        }
    }

    /// Radial deviation `e` of the tread at the contact (m, negative = material missing)
    /// after the wheel has rolled `s` (m) on rolling radius `r` (m): module doc.
    pub fn deviation(&self, s: f64, r: f64) -> f64 {
        let phi = s / r;
        match self {
            WheelDefect::None => 0.0,
            WheelDefect::Flat {
                length,
                shape,
                angle,
                ..
            } => {
                let x = r * wrap(phi - angle);
                let half = 0.5 * length;
                if x.abs() >= half {
                    return 0.0;
                }
                match shape {
                    FlatShape::Rounded => {
                        let d = self.flat_depth(r);
                        -0.5 * d * (1.0 + (2.0 * PI * x / length).cos())
                    }
                    FlatShape::Fresh => {
                        let xi = half - x.abs();
                        -(r - (r * r - xi * xi).max(0.0).sqrt())
                    }
                }
            }
            WheelDefect::Polygon { harmonics } => harmonics
                .iter()
                .map(|h| h.amplitude * (h.order as f64 * phi + h.phase).cos())
                .sum(),
        }
    }

    /// Whether this is a round wheel.
    pub fn is_none(&self) -> bool {
        matches!(self, WheelDefect::None)
    }
}

/// `a` wrapped into `(−π, π]`.
fn wrap(a: f64) -> f64 {
    let t = a.rem_euclid(2.0 * PI);
    if t > PI {
        t - 2.0 * PI
    } else {
        t
    }
}

/// A wheel's tread deviation as it rolls, measured from its value at the wheel's first
/// station (as the rail-top offsets are, [`crate::rail::geometry::track_model::OffsetFromStart`]). The
/// first call fixes the start station and the rolling radius. One per wheel.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct TreadOffset {
    /// Station, rolling radius and deviation at the start.
    start: Option<[f64; 3]>,
}

impl TreadOffset {
    /// Deviation (m) at station `s` of a wheel of rolling radius `r` (used on the first call
    /// only), minus its value at the first station. Rolling without slip: the distance
    /// rolled is the distance travelled.
    pub fn at(&mut self, defect: &WheelDefect, s: f64, r: f64) -> f64 {
        if defect.is_none() {
            return 0.0;
        }
        let [s0, r0, e0] = *self
            .start
            .get_or_insert_with(|| [s, r, defect.deviation(0.0, r)]);
        defect.deviation(s - s0, r0) - e0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn flat(shape: FlatShape, depth: Option<f64>) -> WheelDefect {
        WheelDefect::Flat {
            length: 0.06,
            depth,
            shape,
            angle: PI,
        }
    }

    /// The fresh flat's path reaches the chord's sagitta at its centre, is zero at the
    /// corners and beyond, and its slope at the centre is ±tan θ0 (sin θ0 = L/(2R)).
    #[test]
    fn fresh_flat_is_the_pivot_path() {
        let r = 0.46;
        let f = flat(FlatShape::Fresh, None);
        let centre = PI * r;
        let d = r - (r * r - 0.03f64 * 0.03).sqrt();
        assert!((f.deviation(centre, r) + d).abs() < 1e-15);
        // L²/(8R) is the series' first term; the next is L²/(16R²) = 1.06e-3 relative.
        assert!((d - 0.06f64.powi(2) / (8.0 * r)).abs() < 1.2e-3 * d);
        assert_eq!(f.deviation(centre + 0.0301, r), 0.0);
        assert_eq!(f.deviation(centre - 0.0301, r), 0.0);
        let h = 1e-7;
        let slope = (f.deviation(centre + h, r) - f.deviation(centre, r)) / h;
        // tan θ0 of the corner's radius, sin θ0 = L/(2R): ≈ L/(2R).
        let exact = 0.03 / (r * r - 0.03 * 0.03).sqrt();
        assert!((slope - exact).abs() < 1e-5 * exact, "{slope} vs {exact}");
        // Periodic in the circumference.
        let c = 2.0 * PI * r;
        assert!((f.deviation(centre + 3.0 * c, r) - f.deviation(centre, r)).abs() < 1e-15);
    }

    /// The rounded flat is −d at its centre, −d/2 at a quarter length, zero at its ends.
    #[test]
    fn rounded_flat_is_the_raised_cosine() {
        let r = 0.46;
        let f = flat(FlatShape::Rounded, Some(1e-3));
        let c = PI * r;
        assert!((f.deviation(c, r) + 1e-3).abs() < 1e-15);
        assert!((f.deviation(c + 0.015, r) + 0.5e-3).abs() < 1e-15);
        assert!(f.deviation(c + 0.03, r).abs() < 1e-15);
    }

    #[test]
    fn polygon_sums_its_harmonics_and_tread_offset_starts_at_zero() {
        let r: f64 = 0.5;
        let p = WheelDefect::Polygon {
            harmonics: vec![
                Harmonic {
                    order: 3,
                    amplitude: 1e-4,
                    phase: 0.3,
                },
                Harmonic {
                    order: 20,
                    amplitude: 2e-5,
                    phase: 0.0,
                },
            ],
        };
        let s: f64 = 0.37;
        let want = 1e-4 * (3.0 * s / r + 0.3).cos() + 2e-5 * (20.0 * s / r).cos();
        assert!((p.deviation(s, r) - want).abs() < 1e-18);
        let mut t = TreadOffset::default();
        assert_eq!(t.at(&p, 10.0, r), 0.0);
        assert!((t.at(&p, 10.0 + s, 0.9) - (want - p.deviation(0.0, r))).abs() < 1e-18);
    }

    #[test]
    fn bad_defects_are_refused() {
        let e = |d: WheelDefect| d.validate().unwrap_err();
        assert!(e(flat(FlatShape::Fresh, Some(1e-3))).contains("remove `depth`"));
        assert!(e(flat(FlatShape::Rounded, None)).contains("needs `defect.depth`"));
        assert!(e(flat(FlatShape::Rounded, Some(0.02))).contains("`defect.depth` = 0.02"));
        assert!(e(WheelDefect::Polygon { harmonics: vec![] }).contains("empty"));
        assert!(e(WheelDefect::Polygon {
            harmonics: vec![Harmonic {
                order: 0,
                amplitude: 1e-4,
                phase: 0.0
            }]
        })
        .contains("order"));
        assert!(flat(FlatShape::Fresh, None).validate().is_ok());
    }
}

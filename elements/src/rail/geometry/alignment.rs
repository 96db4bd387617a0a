//! Plan alignment of a track: straights, clothoids and circular arcs joined end to end.
//!
//! What lives here: the [`Segment`]s of a horizontal alignment, the [`Alignment`] built from
//! them (station → position, heading, signed curvature), the paper's five-segment layout
//! ([`Alignment::paper`], Ju & Ro 2021, Section 4 and Figure 3) and the serde specs of the
//! model file's `[track] segments = [...]` ([`SegmentSpec`]).
//!
//! Conventions (paper Section 2.1): global X-Y-Z with Z up and X along the first straight;
//! the alignment starts at the origin with heading ψ = 0. The signed curvature κ is positive
//! for a left-hand curve (the centre of curvature to the left of the direction of travel).
//! The heading is ψ(s) = ∫κ ds and the plan position is ∫(cos ψ, sin ψ) ds. Stations are in
//! metres from the start; outside `[0, L]` the end tangents are extended as straights.
//!
//! # Accuracy
//!
//! Within a segment the curvature is linear in the local arc length `t`, so the heading
//! `ψ(t) = ψ0 + κ0·t + ½·κ'·t²` is evaluated exactly (no integration). Only the position
//! needs quadrature. Each segment is cut into equal knot intervals no longer than 20 m and
//! over which the heading changes by at most 0.05 rad; a table of positions at the knots is
//! built once with a 6-point Gauss–Legendre rule per interval, and [`Alignment::at`] finds
//! the knot at or before the station by binary search (O(log n)) and integrates the short
//! rest with the same rule. For `f = cos ψ` the rule's error is
//! `h^13·(6!)^4 / (13·(12!)^3)·f^(12) ≈ 2e-16·h·(h·κ)^12`, i.e. far below 1e-20 m per interval
//! for `h·κ ≤ 0.05`; what remains is floating-point round-off of the running sum (about
//! 1e-11 m over 16 km). Position, heading and curvature are continuous at the joints by
//! construction (a joint's knot is the end of the previous segment's integration); the
//! curvature is continuous when the segment data say so (a clothoid between a straight and an
//! arc), which [`SegmentSpec`] ensures by inferring the clothoid's end curvatures.

use railfem_framework::limits::{self, fmt_num};
use serde::Deserialize;
use thiserror::Error;

/// Hand of a curve, seen in the direction of travel.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Hand {
    /// The curve turns left (centre to the left; κ > 0).
    Left,
    /// The curve turns right (centre to the right; κ < 0).
    Right,
}

impl Hand {
    /// +1 for left, −1 for right: the sign of the curvature.
    pub fn sign(self) -> f64 {
        match self {
            Hand::Left => 1.0,
            Hand::Right => -1.0,
        }
    }
}

/// One piece of a plan alignment. Lengths in m, curvatures in 1/m (signed, positive left).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Segment {
    /// A straight (tangent) of `length` m.
    Straight {
        /// Length (m).
        length: f64,
    },
    /// A clothoid (Euler spiral): curvature linear in arc length from `from_curvature` to
    /// `to_curvature` (1/m, signed) over `length` m.
    Clothoid {
        /// Length (m).
        length: f64,
        /// Signed curvature at the start (1/m).
        from_curvature: f64,
        /// Signed curvature at the end (1/m).
        to_curvature: f64,
    },
    /// A circular arc of `radius` m turning to `hand`, `length` m long.
    Arc {
        /// Length (m).
        length: f64,
        /// Radius (m), positive.
        radius: f64,
        /// Hand of the curve.
        hand: Hand,
    },
}

impl Segment {
    /// Length (m).
    pub fn length(&self) -> f64 {
        match *self {
            Segment::Straight { length }
            | Segment::Clothoid { length, .. }
            | Segment::Arc { length, .. } => length,
        }
    }

    /// Signed curvature at the start of the segment (1/m).
    pub fn start_curvature(&self) -> f64 {
        match *self {
            Segment::Straight { .. } => 0.0,
            Segment::Clothoid { from_curvature, .. } => from_curvature,
            Segment::Arc { radius, hand, .. } => hand.sign() / radius,
        }
    }

    /// Signed curvature at the end of the segment (1/m).
    pub fn end_curvature(&self) -> f64 {
        match *self {
            Segment::Straight { .. } => 0.0,
            Segment::Clothoid { to_curvature, .. } => to_curvature,
            Segment::Arc { radius, hand, .. } => hand.sign() / radius,
        }
    }

    /// Largest |κ| along the segment (1/m).
    pub fn max_curvature(&self) -> f64 {
        self.start_curvature().abs().max(self.end_curvature().abs())
    }

    /// Name of the kind, for messages.
    pub fn kind(&self) -> &'static str {
        match self {
            Segment::Straight { .. } => "straight",
            Segment::Clothoid { .. } => "clothoid",
            Segment::Arc { .. } => "arc",
        }
    }

    /// Checks the data of segment number `index`.
    fn validate(&self, index: usize) -> Result<(), AlignmentError> {
        let length = self.length();
        if !length.is_finite() || length <= 0.0 {
            return Err(AlignmentError::Length { index, length });
        }
        match *self {
            Segment::Straight { .. } => {}
            Segment::Clothoid {
                from_curvature,
                to_curvature,
                ..
            } => {
                for (what, v) in [
                    ("from_curvature", from_curvature),
                    ("to_curvature", to_curvature),
                ] {
                    if !v.is_finite() {
                        return Err(AlignmentError::NonFinite { index, what });
                    }
                }
            }
            Segment::Arc { radius, .. } => {
                if radius.is_nan() || radius <= 0.0 || radius.is_infinite() {
                    return Err(AlignmentError::Radius { index, radius });
                }
            }
        }
        let kmax = self.max_curvature();
        if kmax > 1.0 / MIN_RADIUS {
            return Err(AlignmentError::TooTight {
                index,
                radius: fmt_num(1.0 / kmax),
            });
        }
        Ok(())
    }
}

/// Smallest radius of curvature a track may have (m). The tightest railway curves built
/// for wheelsets are tram curves of about 15 m (depot curves of light rail ~ 10 m). Below
/// 5 m the rails of a standard-gauge track (G = 1.435 m) differ in radius by more than
/// 30 % (R ± G/2), which no wheel's rolling-radius difference can roll (S1002 on 60E1
/// reaches about 6 %), and the wheel frame of a rigid axle 1.5 m long no longer
/// approximates both contact points; such a curvature is a unit mistake (mm for m, 1/mm
/// for 1/m).
pub const MIN_RADIUS: f64 = 5.0;

/// What is wrong with an alignment's (or a track's) data. Segment indices count from 0.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum AlignmentError {
    /// No segments were given.
    #[error("track: the alignment has no segments; give at least one, e.g. segments = [{{type = \"straight\", length = 100}}]")]
    Empty,
    /// A length is zero, negative or not a number.
    #[error("track: segment[{index}] has length {}; a segment's length must be a finite number > 0 m", fmt_num(*.length))]
    Length {
        /// Segment index.
        index: usize,
        /// The offending length (m).
        length: f64,
    },
    /// An arc radius is zero, negative, infinite or not a number.
    #[error("track: segment[{index}] (arc) has radius {}; the radius must be a finite number > 0 m (use a straight for an infinite radius)", fmt_num(*.radius))]
    Radius {
        /// Segment index.
        index: usize,
        /// The offending radius (m).
        radius: f64,
    },
    /// A curvature is not finite.
    #[error("track: segment[{index}] has a non-finite {what}; give a finite curvature in 1/m (0 for a straight end)")]
    NonFinite {
        /// Segment index.
        index: usize,
        /// Which value.
        what: &'static str,
    },
    /// A clothoid's end curvature cannot be inferred from its neighbour.
    #[error("track: segment[{index}] (clothoid): cannot infer its {what} from the neighbouring clothoid; give it explicitly (1/m, positive for a left-hand curve)")]
    CannotInfer {
        /// Segment index.
        index: usize,
        /// `"from_curvature"` or `"to_curvature"`.
        what: &'static str,
    },
    /// Bad cant data.
    #[error("track: cant: {0}")]
    Cant(String),
    /// Bad mesh data (node stations of a rail lookup).
    #[error("track: {0}")]
    Mesh(String),
    /// A curvature tighter than [`MIN_RADIUS`].
    #[error("track: segment[{index}] has a radius of curvature of {radius} m, below the {min} m a wheelset can negotiate; check the units (m, 1/m) or give a larger radius", min = MIN_RADIUS)]
    TooTight {
        /// Segment index.
        index: usize,
        /// The radius, formatted to show its size (m).
        radius: String,
    },
    /// The alignment would be too large to build (the message of [`limits::check_memory`]).
    #[error("track: {0}")]
    TooLarge(String),
    /// Bad element length for meshing.
    #[error("track: element length {} must be a finite number > 0 m", fmt_num(*.0))]
    ElementLength(f64),
}

/// The plan geometry at one station.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlanPoint {
    /// Station (m).
    pub station: f64,
    /// Global X (m).
    pub x: f64,
    /// Global Y (m).
    pub y: f64,
    /// Heading ψ (rad): angle of the tangent from global X, counter-clockwise seen from +Z.
    pub heading: f64,
    /// Signed curvature κ (1/m), positive for a left-hand curve; 0 outside `[0, L]`.
    pub curvature: f64,
    /// dκ/ds (1/m²); 0 outside `[0, L]`.
    pub curvature_rate: f64,
}

/// A segment placed on the alignment: its start and the polynomial coefficients of κ and ψ.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Placed {
    start: f64,
    length: f64,
    kappa0: f64,
    kappa_rate: f64,
    psi0: f64,
}

impl Placed {
    fn heading(&self, t: f64) -> f64 {
        self.psi0 + t * (self.kappa0 + 0.5 * self.kappa_rate * t)
    }
}

/// A tabulated position at a knot.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Knot {
    station: f64,
    x: f64,
    y: f64,
    segment: usize,
}

/// Largest knot interval (m).
const KNOT_MAX: f64 = 20.0;
/// Largest heading change over a knot interval (rad).
const KNOT_TURN: f64 = 0.05;

/// 6-point Gauss–Legendre abscissae (on [−1, 1]) and weights.
const GL6: [(f64, f64); 6] = [
    (-0.932_469_514_203_152, 0.171_324_492_379_170_4),
    (-0.661_209_386_466_264_5, 0.360_761_573_048_138_6),
    (-0.238_619_186_083_197, 0.467_913_934_572_691),
    (0.238_619_186_083_197, 0.467_913_934_572_691),
    (0.661_209_386_466_264_5, 0.360_761_573_048_138_6),
    (0.932_469_514_203_152, 0.171_324_492_379_170_4),
];

/// Knot intervals of a segment: no longer than [`KNOT_MAX`], turning at most [`KNOT_TURN`].
fn knot_count(seg: &Segment) -> f64 {
    let kmax = seg.max_curvature();
    let h = if kmax > 0.0 {
        KNOT_MAX.min(KNOT_TURN / kmax)
    } else {
        KNOT_MAX
    };
    (seg.length() / h).ceil().max(1.0)
}

/// ∫ (cos ψ, sin ψ) dt over local arc lengths `[a, b]` of a placed segment (Gauss–Legendre).
fn chord(p: &Placed, a: f64, b: f64) -> (f64, f64) {
    let (mid, half) = (0.5 * (a + b), 0.5 * (b - a));
    GL6.iter().fold((0.0, 0.0), |(x, y), &(xi, w)| {
        let psi = p.heading(mid + half * xi);
        (x + w * half * psi.cos(), y + w * half * psi.sin())
    })
}

/// A plan alignment: segments joined with continuous position and heading, starting at the
/// global origin heading along +X.
#[derive(Debug, Clone, PartialEq)]
pub struct Alignment {
    segments: Vec<Segment>,
    placed: Vec<Placed>,
    knots: Vec<Knot>,
    length: f64,
    end: PlanPoint,
}

impl Alignment {
    /// Builds an alignment from its segments, in order of travel.
    ///
    /// Position and heading are continuous at every joint; curvature is continuous where
    /// the segments' end curvatures agree (a jump, as between a straight and an arc without
    /// transition, is allowed but gives a jump in cant).
    pub fn new(segments: Vec<Segment>) -> Result<Self, AlignmentError> {
        if segments.is_empty() {
            return Err(AlignmentError::Empty);
        }
        for (i, seg) in segments.iter().enumerate() {
            seg.validate(i)?;
        }
        // Size guard: the knot table is built before anything else is known of the track.
        let knots: Vec<f64> = segments.iter().map(knot_count).collect();
        let total: f64 = knots.iter().sum();
        let worst = (0..segments.len())
            .max_by(|&a, &b| knots[a].total_cmp(&knots[b]))
            .unwrap_or(0);
        limits::check_memory(
            &match segments[worst].max_curvature() {
                k if k > 0.0 => format!(
                    "segment[{worst}] ({}, `length` = {} m, curvature up to {} 1/m)",
                    segments[worst].kind(),
                    fmt_num(segments[worst].length()),
                    fmt_num(k)
                ),
                _ => format!(
                    "segment[{worst}] ({}, `length` = {} m)",
                    segments[worst].kind(),
                    fmt_num(segments[worst].length())
                ),
            },
            total,
            "alignment knots",
            std::mem::size_of::<Knot>() as f64,
            "give shorter segments",
        )
        .map_err(AlignmentError::TooLarge)?;
        let mut placed = Vec::with_capacity(segments.len());
        let mut knots = Vec::new();
        let (mut s, mut x, mut y, mut psi) = (0.0, 0.0, 0.0, 0.0);
        for (i, seg) in segments.iter().enumerate() {
            let length = seg.length();
            let kappa0 = seg.start_curvature();
            let kappa1 = seg.end_curvature();
            let p = Placed {
                start: s,
                length,
                kappa0,
                kappa_rate: (kappa1 - kappa0) / length,
                psi0: psi,
            };
            let n = knot_count(seg) as usize;
            let mut t_prev = 0.0;
            for k in 0..n {
                let t = length * k as f64 / n as f64;
                if k > 0 {
                    let (dx, dy) = chord(&p, t_prev, t);
                    x += dx;
                    y += dy;
                }
                knots.push(Knot {
                    station: s + t,
                    x,
                    y,
                    segment: i,
                });
                t_prev = t;
            }
            let (dx, dy) = chord(&p, t_prev, length);
            x += dx;
            y += dy;
            psi = p.heading(length);
            s += length;
            placed.push(p);
        }
        let end = PlanPoint {
            station: s,
            x,
            y,
            heading: psi,
            curvature: 0.0,
            curvature_rate: 0.0,
        };
        Ok(Self {
            segments,
            placed,
            knots,
            length: s,
            end,
        })
    }

    /// A single straight of `length` m along +X.
    ///
    /// # Panics
    /// If `length` is not a finite number > 0.
    pub fn straight(length: f64) -> Self {
        Self::new(vec![Segment::Straight { length }]).expect("Alignment::straight: bad length")
    }

    /// The paper's five segments (Section 4, Figure 3) with a circular arc of `radius` m,
    /// turning LEFT (κ > 0; the choice of hand is ours, the paper's results do not depend on
    /// it): 500 m straight, 2000 m clothoid (0 → 1/R), 10 908.3078 m arc, 2000 m clothoid
    /// (1/R → 0), 800 m straight; 16 208.3078 m in all. At R = 6250 m the arc turns 100°.
    ///
    /// # Panics
    /// If `radius` is not a finite number ≥ [`MIN_RADIUS`].
    pub fn paper(radius: f64) -> Self {
        Self::paper_hand(radius, Hand::Left)
    }

    /// [`Alignment::paper`] with a chosen hand.
    ///
    /// # Panics
    /// If `radius` is not a finite number ≥ [`MIN_RADIUS`].
    pub fn paper_hand(radius: f64, hand: Hand) -> Self {
        let k = hand.sign() / radius;
        Self::new(vec![
            Segment::Straight { length: 500.0 },
            Segment::Clothoid {
                length: 2000.0,
                from_curvature: 0.0,
                to_curvature: k,
            },
            Segment::Arc {
                length: 10_908.307_8,
                radius,
                hand,
            },
            Segment::Clothoid {
                length: 2000.0,
                from_curvature: k,
                to_curvature: 0.0,
            },
            Segment::Straight { length: 800.0 },
        ])
        .expect("Alignment::paper: the radius must be a finite number >= MIN_RADIUS")
    }

    /// Total length L (m).
    pub fn length(&self) -> f64 {
        self.length
    }

    /// The segments, in order.
    pub fn segments(&self) -> &[Segment] {
        &self.segments
    }

    /// Stations of the segment ends: `0`, the joints, and `L` (m); `segments().len() + 1`
    /// values.
    pub fn joints(&self) -> Vec<f64> {
        let mut v: Vec<f64> = self.placed.iter().map(|p| p.start).collect();
        v.push(self.length);
        v
    }

    /// Index of the segment containing `station` (a joint belongs to the segment that starts
    /// there; stations outside `[0, L]` give the first or last segment).
    pub fn segment_index(&self, station: f64) -> usize {
        self.placed
            .partition_point(|p| p.start <= station)
            .saturating_sub(1)
    }

    /// Plan geometry at `station` (m): O(log n) knot search plus a 6-point quadrature over at
    /// most one knot interval. Outside `[0, L]` the end tangents are extended straight (and
    /// κ = 0 there).
    pub fn at(&self, station: f64) -> PlanPoint {
        if station < 0.0 {
            return PlanPoint {
                station,
                x: station,
                y: 0.0,
                heading: 0.0,
                curvature: 0.0,
                curvature_rate: 0.0,
            };
        }
        if station > self.length {
            let d = station - self.length;
            let e = self.end;
            return PlanPoint {
                station,
                x: e.x + d * e.heading.cos(),
                y: e.y + d * e.heading.sin(),
                ..e
            };
        }
        let k = self
            .knots
            .partition_point(|k| k.station <= station)
            .saturating_sub(1);
        let knot = self.knots[k];
        let p = &self.placed[knot.segment];
        let (t0, t) = (knot.station - p.start, station - p.start);
        let (dx, dy) = chord(p, t0, t);
        PlanPoint {
            station,
            x: knot.x + dx,
            y: knot.y + dy,
            heading: p.heading(t),
            curvature: p.kappa0 + p.kappa_rate * t,
            curvature_rate: p.kappa_rate,
        }
    }

    /// Plan geometry at the end station L (the end of the last segment, with its curvature).
    pub fn end(&self) -> PlanPoint {
        self.at(self.length)
    }
}

/// A segment as written in a model file: `{type = "straight", length = 500}`,
/// `{type = "clothoid", length = 2000}` (end curvatures inferred from the neighbours unless
/// `from_curvature` / `to_curvature` are given), `{type = "arc", length = 10908.3078,
/// radius = 6250, hand = "left"}` (hand defaults to left).
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(tag = "type", rename_all = "lowercase", deny_unknown_fields)]
pub enum SegmentSpec {
    /// A straight.
    Straight {
        /// Length (m).
        length: f64,
    },
    /// A clothoid; missing end curvatures are taken from the neighbouring segments (0 at an
    /// end of the alignment).
    Clothoid {
        /// Length (m).
        length: f64,
        /// Signed start curvature (1/m); default: the previous segment's end curvature.
        #[serde(default)]
        from_curvature: Option<f64>,
        /// Signed end curvature (1/m); default: the next segment's start curvature.
        #[serde(default)]
        to_curvature: Option<f64>,
    },
    /// A circular arc.
    Arc {
        /// Length (m).
        length: f64,
        /// Radius (m).
        radius: f64,
        /// Hand (`"left"` or `"right"`), default left.
        #[serde(default = "default_hand")]
        hand: Hand,
    },
}

fn default_hand() -> Hand {
    Hand::Left
}

impl SegmentSpec {
    /// The segment's length as given (m).
    pub fn length(&self) -> f64 {
        match self {
            SegmentSpec::Straight { length }
            | SegmentSpec::Clothoid { length, .. }
            | SegmentSpec::Arc { length, .. } => *length,
        }
    }

    /// Resolves a list of specs into segments (inferring clothoid end curvatures) and builds
    /// the alignment.
    pub fn build(specs: &[SegmentSpec]) -> Result<Alignment, AlignmentError> {
        Alignment::new(Self::resolve(specs)?)
    }

    /// Resolves a list of specs into segments, inferring each clothoid's missing end
    /// curvatures from its neighbours (0 at the ends of the alignment). A clothoid next to a
    /// clothoid must give the shared curvature on at least one side.
    pub fn resolve(specs: &[SegmentSpec]) -> Result<Vec<Segment>, AlignmentError> {
        // Known start / end curvature of each spec, if known without inference.
        let start = |s: &SegmentSpec| match *s {
            SegmentSpec::Straight { .. } => Some(0.0),
            SegmentSpec::Clothoid { from_curvature, .. } => from_curvature,
            SegmentSpec::Arc { radius, hand, .. } => Some(hand.sign() / radius),
        };
        let end = |s: &SegmentSpec| match *s {
            SegmentSpec::Straight { .. } => Some(0.0),
            SegmentSpec::Clothoid { to_curvature, .. } => to_curvature,
            SegmentSpec::Arc { radius, hand, .. } => Some(hand.sign() / radius),
        };
        specs
            .iter()
            .enumerate()
            .map(|(i, spec)| {
                Ok(match *spec {
                    SegmentSpec::Straight { length } => Segment::Straight { length },
                    SegmentSpec::Arc {
                        length,
                        radius,
                        hand,
                    } => Segment::Arc {
                        length,
                        radius,
                        hand,
                    },
                    SegmentSpec::Clothoid {
                        length,
                        from_curvature,
                        to_curvature,
                    } => {
                        let from = match (from_curvature, i.checked_sub(1)) {
                            (Some(k), _) => k,
                            (None, None) => 0.0,
                            (None, Some(j)) => {
                                end(&specs[j]).ok_or(AlignmentError::CannotInfer {
                                    index: i,
                                    what: "from_curvature",
                                })?
                            }
                        };
                        let to = match (to_curvature, specs.get(i + 1)) {
                            (Some(k), _) => k,
                            (None, None) => 0.0,
                            (None, Some(next)) => {
                                start(next).ok_or(AlignmentError::CannotInfer {
                                    index: i,
                                    what: "to_curvature",
                                })?
                            }
                        };
                        Segment::Clothoid {
                            length,
                            from_curvature: from,
                            to_curvature: to,
                        }
                    }
                })
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    /// Fresnel integrals C(u) = ∫0^u cos(πt²/2) dt, S(u) = ∫0^u sin(πt²/2) dt by their power
    /// series (alternating, terms fall fast for u < 1; summed until they vanish).
    fn fresnel(u: f64) -> (f64, f64) {
        let a = PI / 2.0;
        let (mut c, mut s) = (0.0, 0.0);
        // term_n = (−1)^n a^n u^(2n+1) / (n! (2n+1)) for ∫ e^{i a t²}: even n → C, odd n → S.
        let mut fact_pow = 1.0; // a^n u^(2n) / n!
        for n in 0..60 {
            if n > 0 {
                fact_pow *= a * u * u / n as f64;
            }
            let term = fact_pow * u / (2 * n + 1) as f64;
            match n % 4 {
                0 => c += term,
                1 => s += term,
                2 => c -= term,
                _ => s -= term,
            }
            if term < 1e-300 {
                break;
            }
        }
        (c, s)
    }

    /// Closed form of a clothoid from curvature 0 to 1/R over L, starting at the origin with
    /// heading 0: (a·C(L/a), a·S(L/a)) with a = √(π·R·L).
    fn clothoid_end(radius: f64, length: f64) -> (f64, f64) {
        let a = (PI * radius * length).sqrt();
        let (c, s) = fresnel(length / a);
        (a * c, a * s)
    }

    #[test]
    fn fresnel_series_matches_known_values() {
        // Tabulated values (Abramowitz & Stegun 7.3; rechecked with a 2e5-step trapezoid
        // rule): C(0.5) = 0.4923442258, S(0.5) = 0.0647324329;
        // C(1) = 0.7798934004, S(1) = 0.4382591474.
        let (c, s) = fresnel(0.5);
        assert!((c - 0.492_344_225_8).abs() < 1e-10 && (s - 0.064_732_432_9).abs() < 1e-10);
        let (c, s) = fresnel(1.0);
        assert!((c - 0.779_893_400_4).abs() < 1e-10 && (s - 0.438_259_147_4).abs() < 1e-10);
    }

    #[test]
    fn gauss_legendre_rule_is_degree_eleven_exact() {
        let w: f64 = GL6.iter().map(|p| p.1).sum();
        assert!((w - 2.0).abs() < 1e-15);
        let i10: f64 = GL6.iter().map(|&(x, w)| w * x.powi(10)).sum();
        assert!((i10 - 2.0 / 11.0).abs() < 1e-15);
    }

    #[test]
    fn paper_length_and_arc_turn() {
        let a = Alignment::paper(6250.0);
        assert!((a.length() - 16_208.307_8).abs() < 1e-9);
        let turn_deg = 10_908.307_8_f64 / 6250.0 * 180.0 / PI;
        assert!((turn_deg - 100.0).abs() < 1e-6, "{turn_deg}");
        let j = a.joints();
        assert_eq!(
            j,
            vec![0.0, 500.0, 2500.0, 13_408.307_8, 15_408.307_8, 16_208.307_8]
        );
        // Heading at the arc start = Lc/(2R); over the arc it turns L_arc/R; the exit
        // clothoid adds Lc/(2R) again.
        let h0 = a.at(2500.0).heading;
        assert!((h0 - 2000.0 / (2.0 * 6250.0)).abs() < 1e-15);
        let h1 = a.at(j[3]).heading;
        assert!((h1 - h0 - 10_908.307_8 / 6250.0).abs() < 1e-13);
        assert!((a.end().heading - (h1 + 0.16)).abs() < 1e-13);
    }

    #[test]
    fn clothoid_ends_match_fresnel_closed_form() {
        let r = 6250.0;
        let a = Alignment::paper(r);
        let (cx, cy) = clothoid_end(r, 2000.0);
        let p = a.at(2500.0);
        let err = ((p.x - 500.0 - cx).powi(2) + (p.y - cy).powi(2)).sqrt();
        assert!(err < 1e-6, "entry clothoid end error {err:e} m");
        // Exit clothoid (1/R → 0), reversed: from its end it is a clothoid 0 → 1/R turning
        // the other way, so end − start = Rot(ψ_end)·(a·C, −a·S).
        let (s0, s1) = (13_408.307_8, 15_408.307_8);
        let (p0, p1) = (a.at(s0), a.at(s1));
        let (sn, cs) = p1.heading.sin_cos();
        let (dx, dy) = (cs * cx + sn * cy, sn * cx - cs * cy);
        let err2 = ((p1.x - p0.x - dx).powi(2) + (p1.y - p0.y - dy).powi(2)).sqrt();
        assert!(err2 < 1e-6, "exit clothoid error {err2:e} m");
        // The whole layout in closed form: straights and the arc are elementary.
        let psi_a = 0.16;
        let arc_turn = 10_908.307_8 / r;
        let (mut x, mut y) = (500.0 + cx, cy);
        x += r * ((psi_a + arc_turn).sin() - psi_a.sin());
        y += r * (psi_a.cos() - (psi_a + arc_turn).cos());
        let arc_end = a.at(s0);
        let err3 = ((arc_end.x - x).powi(2) + (arc_end.y - y).powi(2)).sqrt();
        assert!(err3 < 1e-6, "arc end error {err3:e} m");
        eprintln!("paper R=6250: entry {err:.2e} m, exit {err2:.2e} m, arc end {err3:.2e} m");
    }

    #[test]
    fn sharp_clothoid_matches_fresnel() {
        let (r, l) = (300.0, 200.0);
        for hand in [Hand::Left, Hand::Right] {
            let a = Alignment::new(vec![
                Segment::Straight { length: 50.0 },
                Segment::Clothoid {
                    length: l,
                    from_curvature: 0.0,
                    to_curvature: hand.sign() / r,
                },
                Segment::Arc {
                    length: 100.0,
                    radius: r,
                    hand,
                },
            ])
            .unwrap();
            let (cx, cy) = clothoid_end(r, l);
            let p = a.at(250.0);
            let err = ((p.x - 50.0 - cx).powi(2) + (p.y - hand.sign() * cy).powi(2)).sqrt();
            assert!(err < 1e-6, "sharp clothoid error {err:e}");
            // Mid-clothoid too (the local quadrature from a knot): a clothoid of L/2 reaching
            // curvature 1/(2R) is the first half of this one.
            let (mx, my) = clothoid_end(2.0 * r, l / 2.0);
            let q = a.at(150.0);
            let err_mid = ((q.x - 50.0 - mx).powi(2) + (q.y - hand.sign() * my).powi(2)).sqrt();
            assert!(err_mid < 1e-6, "mid clothoid error {err_mid:e}");
            eprintln!("sharp R=300 L=200: end {err:.2e} m, mid {err_mid:.2e} m");
        }
    }

    #[test]
    fn continuity_at_every_joint() {
        let a = Alignment::paper(6250.0);
        let eps = 1e-7;
        for &s in &a.joints()[1..5] {
            let (p, q) = (a.at(s - eps), a.at(s));
            let dpos = ((q.x - p.x).powi(2) + (q.y - p.y).powi(2)).sqrt();
            assert!((dpos - eps).abs() < 1e-9, "position jump at {s}: {dpos:e}");
            assert!((q.heading - p.heading).abs() < 1e-10, "heading jump at {s}");
            assert!(
                (q.curvature - p.curvature).abs() < 1e-12,
                "curvature jump at {s}"
            );
        }
        // Extrapolation beyond the ends is straight and continuous.
        let (e, f) = (a.end(), a.at(a.length() + 10.0));
        assert!((f.x - e.x - 10.0 * e.heading.cos()).abs() < 1e-12);
        assert_eq!(f.heading, e.heading);
        let b = a.at(-5.0);
        assert_eq!((b.x, b.y, b.heading), (-5.0, 0.0, 0.0));
    }

    #[test]
    fn curvature_linear_on_clothoids() {
        let a = Alignment::paper(6250.0);
        for f in [0.0, 0.25, 0.5, 1.0] {
            let k = a.at(500.0 + 2000.0 * f).curvature;
            assert!((k - f / 6250.0).abs() < 1e-18);
            let k2 = a.at(13_408.307_8 + 2000.0 * f).curvature;
            assert!((k2 - (1.0 - f) / 6250.0).abs() < 1e-18);
        }
        assert_eq!(a.at(100.0).curvature, 0.0);
        assert_eq!(a.at(7000.0).curvature, 1.0 / 6250.0);
        assert!((a.at(600.0).curvature_rate - 1.0 / (6250.0 * 2000.0)).abs() < 1e-22);
    }

    #[test]
    fn specs_infer_clothoid_curvatures_and_reject_bad_data() {
        let json = r#"[{"type":"straight","length":500},{"type":"clothoid","length":2000},
            {"type":"arc","length":10908.3078,"radius":6250,"hand":"left"},
            {"type":"clothoid","length":2000},{"type":"straight","length":800}]"#;
        let specs: Vec<SegmentSpec> = railfem_framework::serde_json::from_str(json).unwrap();
        let a = SegmentSpec::build(&specs).unwrap();
        assert_eq!(a, Alignment::paper(6250.0));
        let bad = |j: &str| {
            let specs: Vec<SegmentSpec> = railfem_framework::serde_json::from_str(j).unwrap();
            SegmentSpec::build(&specs).unwrap_err()
        };
        assert!(matches!(
            bad(r#"[{"type":"straight","length":0}]"#),
            AlignmentError::Length { index: 0, .. }
        ));
        assert!(matches!(
            bad(r#"[{"type":"straight","length":1},{"type":"arc","length":5,"radius":-3}]"#),
            AlignmentError::Radius { index: 1, .. }
        ));
        assert!(matches!(
            bad(r#"[{"type":"clothoid","length":5},{"type":"clothoid","length":5}]"#),
            AlignmentError::CannotInfer { index: 0, .. }
        ));
        assert_eq!(bad("[]"), AlignmentError::Empty);
        let nan = Alignment::new(vec![Segment::Straight { length: f64::NAN }]).unwrap_err();
        assert!(nan.to_string().contains("finite number > 0"), "{nan}");
        // Unknown keys and types are serde errors.
        assert!(railfem_framework::serde_json::from_str::<Vec<SegmentSpec>>(
            r#"[{"type":"spiral","length":5}]"#
        )
        .is_err());
    }

    #[test]
    fn lookup_is_consistent_across_knots() {
        // Positions from different knots agree: integrate a clothoid from the segment start
        // with many small steps, independent of the knot table.
        let a = Alignment::paper(300.0);
        let p = &a.placed[1];
        let (mut x, mut y) = (a.at(500.0).x, a.at(500.0).y);
        let n = 20_000;
        for i in 0..n {
            let (t0, t1) = (
                2000.0 * i as f64 / n as f64,
                2000.0 * (i + 1) as f64 / n as f64,
            );
            let (dx, dy) = chord(p, t0, t1);
            x += dx;
            y += dy;
        }
        let q = a.at(2500.0);
        assert!(((q.x - x).powi(2) + (q.y - y).powi(2)).sqrt() < 1e-9);
    }
}

//! The bridge of a check: its description in a plan (`[bridge]`), and the rules of the
//! standards that follow from it — the acceleration limit of the track (EN 1990
//! A2.4.4.2.1), the lower bound of damping (EN 1991-2 Table 6.6), the additional damping
//! of vehicle–bridge interaction (EN 1991-2 Eq. 6.13), the determinant length of a
//! continuous deck (EN 1991-2 Table 6.2), and the limits of the first natural frequency
//! within which a dynamic analysis may not be needed (EN 1991-2 Fig. 6.10).
//!
//! A bridge is either a short description (spans, `EI`, mass per metre) that the check
//! meshes itself into planar beams, or any railfem model file with a named deck path.

use crate::framework::FemError;
use serde::Deserialize;
use std::f64::consts::PI;
use std::path::PathBuf;

/// The track on the deck; it sets the deck-acceleration limit.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum TrackType {
    /// Ballasted track: 3.5 m/s² (EN 1990 A2.4.4.2.1(4)P).
    Ballasted,
    /// Direct-fastened track: 5 m/s² (EN 1990 A2.4.4.2.1(4)P).
    DirectFastened,
}

impl TrackType {
    /// The peak deck acceleration allowed (m/s²), EN 1990 A2.4.4.2.1(4)P.
    pub fn acceleration_limit(self) -> f64 {
        match self {
            TrackType::Ballasted => 3.5,
            TrackType::DirectFastened => 5.0,
        }
    }

    /// Words for the report.
    pub fn name(self) -> &'static str {
        match self {
            TrackType::Ballasted => "ballasted",
            TrackType::DirectFastened => "direct fastened",
        }
    }
}

/// The bridge type of EN 1991-2 Table 6.6.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum BridgeKind {
    /// Steel and composite.
    SteelComposite,
    /// Prestressed concrete.
    PrestressedConcrete,
    /// Filler beam and reinforced concrete.
    ReinforcedConcrete,
}

impl BridgeKind {
    /// Words for the report.
    pub fn name(self) -> &'static str {
        match self {
            BridgeKind::SteelComposite => "steel and composite",
            BridgeKind::PrestressedConcrete => "prestressed concrete",
            BridgeKind::ReinforcedConcrete => "filler beam and reinforced concrete",
        }
    }
}

/// How the spans of a described deck are supported.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum Support {
    /// Each span simply supported on its own.
    #[default]
    SimplySupported,
    /// One beam continuous over the inner supports.
    Continuous,
}

/// The `[bridge]` table of a plan.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BridgeSpec {
    /// Span lengths (m), in order of travel.
    #[serde(default)]
    pub spans: Vec<f64>,
    /// Support of the described deck.
    #[serde(default)]
    pub support: Support,
    /// Bending stiffness (N·m²) of the described deck.
    #[serde(rename = "EI")]
    pub ei: Option<f64>,
    /// Mass per metre (kg/m) of the described deck.
    pub mass: Option<f64>,
    /// Bridge type (Table 6.6 damping).
    pub kind: BridgeKind,
    /// Track type (acceleration limit).
    pub track: TrackType,
    /// Damping ratio (fraction of critical) instead of Table 6.6's lower bound.
    pub damping: Option<f64>,
    /// Add the interaction damping Δζ of EN 1991-2 Eq. 6.13 (spans < 30 m).
    #[serde(default)]
    pub additional_damping: bool,
    /// Beam elements per span of the described deck [default:
    /// [`DEFAULT_ELEMENTS_PER_SPAN`]].
    pub elements_per_span: Option<usize>,
    /// A railfem model file (relative to the plan) whose deck path is the bridge.
    pub model: Option<PathBuf>,
    /// Element ids of the deck path in the model file, in order of travel.
    #[serde(default)]
    pub deck: Vec<u64>,
}

/// Default beam elements per span of a described deck (`[bridge] elements_per_span`; with
/// [`super::plan::DEFAULT_STEPS_PER_PERIOD`], within 0.5 % of the modal reference).
pub const DEFAULT_ELEMENTS_PER_SPAN: usize = 12;

/// Lower bound of the damping ratio ζ (fraction, not %) for a span `L` (m), EN 1991-2
/// Table 6.6: steel and composite `0.5 + 0.125·(20 − L)` %, prestressed concrete
/// `1.0 + 0.07·(20 − L)` %, filler beam and reinforced concrete `1.5 + 0.07·(20 − L)` %
/// for `L < 20 m`; 0.5, 1.0 and 1.5 % from 20 m on.
pub fn table_6_6(kind: BridgeKind, span: f64) -> f64 {
    let short = (20.0 - span).max(0.0);
    let percent = match kind {
        BridgeKind::SteelComposite => 0.5 + 0.125 * short,
        BridgeKind::PrestressedConcrete => 1.0 + 0.07 * short,
        BridgeKind::ReinforcedConcrete => 1.5 + 0.07 * short,
    };
    percent / 100.0
}

/// Additional damping Δζ (fraction) for vehicle–bridge interaction, EN 1991-2 Eq. 6.13:
/// `Δζ = (0.0187·L − 0.00064·L²) / (1 − 0.0441·L − 0.0044·L² + 0.000255·L³)` %, for
/// simply supported spans `L < 30 m` (0 from 30 m on).
pub fn additional_damping(span: f64) -> f64 {
    if span >= 30.0 {
        return 0.0;
    }
    let l = span;
    let percent =
        (0.0187 * l - 0.00064 * l * l) / (1.0 - 0.0441 * l - 0.0044 * l * l + 0.000255 * l * l * l);
    percent.max(0.0) / 100.0
}

/// The determinant length `L_Φ` (m) of EN 1991-2 Table 6.2 case 5.1: a single span's
/// length, or for `n ≥ 2` continuous spans `k·L_m`, `L_m` the mean span and
/// `k = 1.2, 1.3, 1.4, 1.5` for 2, 3, 4 and ≥ 5 spans.
pub fn determinant_length(spans: &[f64], support: Support) -> f64 {
    let n = spans.len();
    if n == 0 {
        return 0.0;
    }
    if support == Support::SimplySupported {
        return spans.iter().fold(0.0, |m: f64, &s| m.max(s));
    }
    let mean = spans.iter().sum::<f64>() / n as f64;
    let k = match n {
        1 => 1.0,
        2 => 1.2,
        3 => 1.3,
        4 => 1.4,
        _ => 1.5,
    };
    k * mean
}

/// The band of EN 1991-2 Fig. 6.10 for a span `L` (m), 4 m ≤ L ≤ 100 m: `(lower, upper)`
/// first natural frequency (Hz): upper `94.76·L^−0.748`; lower `80/L` for L ≤ 20 m and
/// `23.58·L^−0.592` above. `None` outside the figure's range.
pub fn frequency_limits(span: f64) -> Option<(f64, f64)> {
    if !(4.0..=100.0).contains(&span) {
        return None;
    }
    let upper = 94.76 * span.powf(-0.748);
    let lower = if span <= 20.0 {
        80.0 / span
    } else {
        23.58 * span.powf(-0.592)
    };
    Some((lower, upper))
}

/// Natural frequency (Hz) of bending mode `n` of a simply supported Euler–Bernoulli span:
/// `f_n = (n²·π/(2L²))·√(EI/μ)`.
pub fn simply_supported_frequency(n: usize, span: f64, ei: f64, mass: f64) -> f64 {
    let k = n as f64 * PI / span;
    k * k * (ei / mass).sqrt() / (2.0 * PI)
}

/// The damping a check uses for the plan's bridge: the given value, or Table 6.6 at the
/// determinant length, plus Eq. 6.13 when asked. Returns `(ζ, words for the report)`.
pub fn damping(spec: &BridgeSpec, length: f64) -> (f64, String) {
    let (base, from) = match spec.damping {
        Some(z) => (z, "given in the plan".to_string()),
        None => (
            table_6_6(spec.kind, length),
            format!(
                "EN 1991-2 Table 6.6 lower bound ({}, L = {length:.2} m)",
                spec.kind.name()
            ),
        ),
    };
    if spec.additional_damping {
        let dz = additional_damping(length);
        (
            base + dz,
            format!("{from} + Δζ = {:.3} % (EN 1991-2 Eq. 6.13)", dz * 100.0),
        )
    } else {
        (base, from)
    }
}

impl BridgeSpec {
    /// Checks the description; errors name `file` and the key.
    pub fn validate(&self, file: &str) -> Result<(), FemError> {
        let at = |k: &str| format!("{file}: bridge.{k}");
        if self.model.is_none() {
            if self.spans.is_empty() {
                return Err(FemError::input(
                    at("spans"),
                    "give the span lengths in m, e.g. spans = [20.0] (or a `model` file with a `deck`)",
                ));
            }
            for (k, v) in [("EI", self.ei), ("mass", self.mass)] {
                match v {
                    Some(x) if x.is_finite() && x > 0.0 => {}
                    _ => {
                        return Err(FemError::input(
                            at(k),
                            format!("give {k} > 0 ({})", if k == "EI" { "N·m²" } else { "kg/m" }),
                        ))
                    }
                }
            }
        } else if self.deck.is_empty() {
            return Err(FemError::input(
                at("deck"),
                "a model-file bridge needs the deck path: deck = [element ids in order of travel]",
            ));
        }
        if self.spans.iter().any(|s| !(s.is_finite() && *s > 0.0)) {
            return Err(FemError::input(at("spans"), "every span must be > 0 m"));
        }
        if self.model.is_some() && self.spans.is_empty() {
            return Err(FemError::input(
                at("spans"),
                "give the span lengths of the model's deck (m): they set the damping and the frequency limits",
            ));
        }
        if let Some(z) = self.damping {
            if !(z.is_finite() && z > 0.0 && z < 0.5) {
                return Err(FemError::input(
                    at("damping"),
                    "give a damping ratio between 0 and 0.5 (a fraction of critical, 0.01 = 1 %)",
                ));
            }
        }
        if let Some(n) = self.elements_per_span {
            if !(2..=200).contains(&n) {
                return Err(FemError::input(
                    at("elements_per_span"),
                    "give between 2 and 200 elements per span",
                ));
            }
        }
        Ok(())
    }
}

//! The simple theory of Ju & Ro (2021), Section 3 (Eqs. 21–26): the quasi-static wheel
//! forces of a carriage of lumped rigid bodies on a canted curve, the sliding check (both
//! directions), the normal force per wheel in the printed form of Eq. 25 and in the form
//! rigid-body statics gives, the critical radii of sliding and of separation (inner-wheel
//! unloading, the onset of overturning) by bracketing and bisection, the stand-in carriage
//! preset, and the derailment indices (Nadal's limit, Y/Q, ΔQ/Q). What does not live here:
//! anything dynamic or finite-element (the moving-axle element and the vehicle models).
//!
//! Units: N, m, s, rad. Gravity g is a parameter ([`TrackParams::gravity`], 9.81 m/s² by
//! default); it converts the weights W_i into masses W_i/g in Eqs. 22–23 (and the preset's
//! masses into weights), so a consistent g must be used for both.
//!
//! # Frames and signs
//!
//! The plane of the theory is the wheel frame's 1-2 plane (see `moving-axle.md`): axis 1
//! lies in the canted track plane and points **towards the centre of the curve** (inwards),
//! axis 2 is normal to the track plane, up. The track plane dips towards the centre by the
//! cant θ = Ct/R (Eq. 21). F1 > 0 is inwards (gravity's share down the cant), F1 < 0
//! outwards (centrifugal). The **inner** wheels (N/2, on the inner rail) touch the rails at
//! `x1 = +G/2`, the **outer** ones at `x1 = −G/2`; the body mass centres sit at `(0, H_i)`.
//! Wheel forces are the rails' forces **on** the wheels: the normal force F_N along +2
//! (positive in contact), the shear F_S along +1.

use serde::{Deserialize, Serialize};
use thiserror::Error;

/// Default gravitational acceleration g (m/s²), the paper's value.
pub const STANDARD_GRAVITY: f64 = 9.81;

/// Standard track gauge G (m). The theory's G is the lateral spacing of the two rails'
/// contact points, so the nominal contact-point spacing of about 1.50 m is an equally
/// valid choice; the paper uses 1.435 m.
pub const STANDARD_GAUGE: f64 = 1.435;

/// Invalid input to the simple theory (one line: what, and the fix).
#[derive(Debug, Clone, PartialEq, Error)]
pub enum TheoryError {
    /// A parameter is out of its range.
    #[error("simple theory: {what} = {value} is invalid; fix: {fix}")]
    Invalid {
        /// Which parameter.
        what: &'static str,
        /// Its value.
        value: f64,
        /// How to fix it.
        fix: &'static str,
    },
}

fn check(ok: bool, what: &'static str, value: f64, fix: &'static str) -> Result<(), TheoryError> {
    if ok {
        Ok(())
    } else {
        Err(TheoryError::Invalid { what, value, fix })
    }
}

/// One lumped rigid body of the carriage (the paper's W_i, H_i).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Body {
    /// A name for reports ("wheelsets", "bogies", "car body").
    pub name: String,
    /// Weight W_i (N).
    pub weight: f64,
    /// Height H_i of the mass centre above the rail top, normal to the track plane (m).
    pub cg_height: f64,
}

/// A carriage for the simple theory: its bodies and its number of wheels N.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Carriage {
    /// The lumped bodies (the paper: all wheelsets, both bogies, the car body).
    pub bodies: Vec<Body>,
    /// Number of wheels N (even; half on each rail). The paper: 8.
    pub n_wheels: usize,
}

impl Carriage {
    /// A carriage from `(name, mass kg, CG height m)` triples, weights W = m·g (N).
    pub fn from_masses(items: &[(&str, f64, f64)], n_wheels: usize, gravity: f64) -> Self {
        Self {
            bodies: items
                .iter()
                .map(|&(name, m, h)| Body {
                    name: name.into(),
                    weight: m * gravity,
                    cg_height: h,
                })
                .collect(),
            n_wheels,
        }
    }

    /// The paper's SKS-700 (THSR 700T) intermediate carriage, **stand-in values; see the
    /// spec** (`vehicle-track-profiles.md`: CRH380A data): 4 wheelsets × 1 850 kg at
    /// H = 0.43 m, 2 bogies × 2 400 kg at 0.48 m, car body 43 862.5 kg at 1.51 m, N = 8
    /// wheels, g = 9.81 m/s². These add up to 56 062.5 kg (a 14.0 t axle load); the spec's
    /// total "56 060 kg" (56.06 t) is the same figure rounded, 2.5 kg less.
    pub fn sks700_standin() -> Self {
        Self::sks700_standin_with_gravity(STANDARD_GRAVITY)
    }

    /// [`Carriage::sks700_standin`] with the weights computed with gravity `g` (m/s²).
    pub fn sks700_standin_with_gravity(g: f64) -> Self {
        Self::from_masses(
            &[
                ("wheelsets", 4.0 * 1850.0, 0.43),
                ("bogies", 2.0 * 2400.0, 0.48),
                ("car body", 43_862.5, 1.51),
            ],
            8,
            g,
        )
    }

    /// Total weight ΣW_i (N).
    pub fn total_weight(&self) -> f64 {
        self.bodies.iter().map(|b| b.weight).sum()
    }

    fn validate(&self) -> Result<(), TheoryError> {
        let n = self.n_wheels as f64;
        check(
            self.n_wheels >= 2 && self.n_wheels % 2 == 0,
            "number of wheels N",
            n,
            "give an even number of wheels, at least 2",
        )?;
        check(
            !self.bodies.is_empty(),
            "number of bodies",
            0.0,
            "give at least one body",
        )?;
        for b in &self.bodies {
            check(
                b.weight.is_finite() && b.weight > 0.0,
                "body weight W_i (N)",
                b.weight,
                "give a positive weight",
            )?;
            check(
                b.cg_height.is_finite(),
                "body CG height H_i (m)",
                b.cg_height,
                "give a finite height",
            )?;
        }
        Ok(())
    }
}

/// Track constants of the theory.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct TrackParams {
    /// Lateral spacing G of the inner and outer contact points (m); default 1.435.
    pub gauge: f64,
    /// Gravitational acceleration g (m/s²); default 9.81.
    pub gravity: f64,
}

impl Default for TrackParams {
    fn default() -> Self {
        Self {
            gauge: STANDARD_GAUGE,
            gravity: STANDARD_GRAVITY,
        }
    }
}

/// The operating point apart from the radius.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Operation {
    /// Speed V (m/s).
    pub speed: f64,
    /// Cant constant Ct (m): θ = Ct/R (Eq. 21).
    pub cant_constant: f64,
    /// Coefficient of friction μ (–).
    pub mu: f64,
}

/// Which form of Eq. 25 gives the normal force per wheel.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum Variant {
    /// Eq. 25 as printed: F_N = −ΣF2_i/N ± ΣF1_i·H_i/(N·G) (+ inner, − outer).
    Printed,
    /// Rigid-body statics of the whole carriage: F_N = −ΣF2_i/N ± 2·ΣF1_i·H_i/(N·G).
    ///
    /// Derivation (frames and signs of the module doc). Free body: the carriage. Loads:
    /// F1_i e1 + F2_i e2 at (0, H_i). Reactions: N/2 inner wheels at (+G/2, 0) each with
    /// F_in e2 + F_S e1, N/2 outer wheels at (−G/2, 0) each with F_out e2 + F_S e1.
    /// - Forces along 1: ΣF1_i + N·F_S = 0 ⇒ F_S = −ΣF1_i/N (Eq. 26).
    /// - Forces along 2: ΣF2_i + (N/2)(F_in + F_out) = 0 ⇒ F_in + F_out = −2ΣF2_i/N.
    /// - Moments about the track centre line (0, 0), counter-clockwise positive in the
    ///   (1, 2) plane, moment of a force (f1, f2) at (x1, x2) = x1·f2 − x2·f1:
    ///   bodies −ΣH_i·F1_i; inner wheels (N/2)(G/2)F_in; outer wheels −(N/2)(G/2)F_out;
    ///   the shears act at x2 = 0 and have no moment. Sum = 0 ⇒
    ///   F_in − F_out = 4·ΣF1_i·H_i/(N·G).
    ///
    /// Hence F_in = −ΣF2_i/N + 2ΣF1_i·H_i/(N·G) and F_out = −ΣF2_i/N − 2ΣF1_i·H_i/(N·G):
    /// twice the printed moment term, with the printed signs (+ inner). At speed F1 < 0
    /// (outwards) and the inner wheel unloads. The equal split of the shear between the
    /// wheels is an assumption of Eq. 26 and does not enter the moment. The test
    /// `statics_free_body_balances` checks the result independently.
    Statics,
}

/// Whether (and which way) the carriage slides across the rails (Eq. 24 generalised).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum Sliding {
    /// |ΣF1| < μ·|ΣF2|: the wheels stick.
    None,
    /// −ΣF1 ≥ μ·(−ΣF2): the resultant pushes outwards hard enough (Eq. 24).
    Outwards,
    /// ΣF1 ≥ μ·(−ΣF2): slow on a steep cant, the resultant pushes inwards.
    Inwards,
}

/// A direction of sliding, for [`critical_radius_sliding`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum SlidingDirection {
    /// Away from the curve centre (Eq. 24).
    Outwards,
    /// Towards the curve centre.
    Inwards,
}

/// Which wheel (rail) side, for [`critical_radius_separation`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum WheelSide {
    /// On the inner rail (x1 = +G/2); unloads at speed.
    Inner,
    /// On the outer rail (x1 = −G/2); unloads when slow on a steep cant.
    Outer,
}

/// The cant angle θ = Ct/R (rad) of Eq. 21; 0 for an infinite radius (straight).
pub fn cant_angle(cant_constant: f64, radius: f64) -> f64 {
    if radius.is_infinite() {
        0.0
    } else {
        cant_constant / radius
    }
}

/// Eqs. 22–23: the forces (F1, F2) (N) on a body of weight `weight` (N) at cant `theta`
/// (rad), curvature `curvature` = 1/R (1/m; 0 on a straight), speed `speed` (m/s) and
/// gravity `g` (m/s²): F1 = W sinθ − (W/g)V² cosθ/R, F2 = −W cosθ − (W/g)V² sinθ/R.
pub fn body_forces(weight: f64, theta: f64, curvature: f64, speed: f64, g: f64) -> (f64, f64) {
    let (s, c) = theta.sin_cos();
    let centripetal = weight / g * speed * speed * curvature;
    (weight * s - centripetal * c, -weight * c - centripetal * s) // Eqs. 22, 23
}

/// The simple theory's result at one operating point and radius (forces in N).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct WheelForces {
    /// Cant θ (rad).
    pub theta: f64,
    /// Curvature 1/R (1/m).
    pub curvature: f64,
    /// ΣF1_i (N), along axis 1 (inwards positive).
    pub sum_f1: f64,
    /// ΣF2_i (N), along axis 2 (negative: pressing on the rails).
    pub sum_f2: f64,
    /// ΣF1_i·H_i (N·m).
    pub sum_f1_h: f64,
    /// Shear per wheel F_S = −ΣF1/N (N), the rails' force on each wheel along axis 1 (Eq. 26).
    pub shear: f64,
    /// Normal force of each inner wheel (N; > 0 in contact; ≤ 0: separation).
    pub normal_inner: f64,
    /// Normal force of each outer wheel (N).
    pub normal_outer: f64,
    /// Whether the carriage slides, and which way (Eq. 24 in both directions).
    pub sliding: Sliding,
    /// The form of Eq. 25 used.
    pub variant: Variant,
}

impl WheelForces {
    /// Mean normal force per wheel −ΣF2/N (N).
    pub fn mean_normal(&self) -> f64 {
        0.5 * (self.normal_inner + self.normal_outer)
    }

    /// Whether a wheel has separated: the inner (or outer) normal force ≤ 0.
    pub fn separation(&self) -> bool {
        self.normal_inner <= 0.0 || self.normal_outer <= 0.0
    }

    /// Derailment quotient Y/Q of the inner and outer wheels (|F_S|/F_N; +∞ when unloaded).
    pub fn derailment_quotients(&self) -> (f64, f64) {
        (
            derailment_quotient(self.shear, self.normal_inner),
            derailment_quotient(self.shear, self.normal_outer),
        )
    }

    /// Wheel unloading ratio ΔQ/Q of the inner wheel against the mean load (–).
    pub fn unloading_ratio(&self) -> f64 {
        unloading_ratio(self.mean_normal(), self.normal_inner)
    }
}

/// Evaluates Eqs. 21–26 for `carriage` at `radius` R (m; `f64::INFINITY` for a straight)
/// with the given operating point and variant of Eq. 25.
pub fn evaluate(
    carriage: &Carriage,
    track: &TrackParams,
    op: &Operation,
    radius: f64,
    variant: Variant,
) -> Result<WheelForces, TheoryError> {
    carriage.validate()?;
    check(
        radius > 0.0 && !radius.is_nan(),
        "radius R (m)",
        radius,
        "give a positive radius (infinity for a straight)",
    )?;
    check(
        track.gauge.is_finite() && track.gauge > 0.0,
        "gauge G (m)",
        track.gauge,
        "give a positive gauge, e.g. 1.435",
    )?;
    check(
        track.gravity.is_finite() && track.gravity > 0.0,
        "gravity g (m/s²)",
        track.gravity,
        "give a positive g, e.g. 9.81",
    )?;
    check(
        op.speed.is_finite(),
        "speed V (m/s)",
        op.speed,
        "give a finite speed",
    )?;
    check(
        op.mu.is_finite() && op.mu >= 0.0,
        "friction coefficient μ",
        op.mu,
        "give μ ≥ 0",
    )?;
    let theta = cant_angle(op.cant_constant, radius); // Eq. 21
    check(
        theta.abs() < std::f64::consts::FRAC_PI_2,
        "cant angle θ = Ct/R (rad)",
        theta,
        "the cant must stay below 90°: lower Ct or raise R",
    )?;
    Ok(forces_unchecked(carriage, track, op, radius, variant))
}

fn forces_unchecked(
    carriage: &Carriage,
    track: &TrackParams,
    op: &Operation,
    radius: f64,
    variant: Variant,
) -> WheelForces {
    let curvature = if radius.is_infinite() {
        0.0
    } else {
        1.0 / radius
    };
    let theta = cant_angle(op.cant_constant, radius); // Eq. 21
    let (mut sum_f1, mut sum_f2, mut sum_f1_h) = (0.0, 0.0, 0.0);
    for b in &carriage.bodies {
        let (f1, f2) = body_forces(b.weight, theta, curvature, op.speed, track.gravity);
        sum_f1 += f1;
        sum_f2 += f2;
        sum_f1_h += f1 * b.cg_height;
    }
    let n = carriage.n_wheels as f64;
    let mean = -sum_f2 / n;
    let factor = match variant {
        Variant::Printed => 1.0,
        Variant::Statics => 2.0,
    };
    let moment = factor * sum_f1_h / (n * track.gauge); // Eq. 25 (± term)
    let sliding = if -sum_f1 >= op.mu * -sum_f2 {
        Sliding::Outwards // Eq. 24
    } else if sum_f1 >= op.mu * -sum_f2 {
        Sliding::Inwards
    } else {
        Sliding::None
    };
    WheelForces {
        theta,
        curvature,
        sum_f1,
        sum_f2,
        sum_f1_h,
        shear: -sum_f1 / n, // Eq. 26
        normal_inner: mean + moment,
        normal_outer: mean - moment,
        sliding,
        variant,
    }
}

/// The radius range searched for a critical radius, and the scan density.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct RadiusBracket {
    /// Smallest radius (m). Raised, if needed, so that θ = Ct/R ≤ 1 rad.
    pub r_min: f64,
    /// Largest radius (m), where the search starts (the train comes from the straight).
    pub r_max: f64,
    /// Number of log-spaced scan intervals between them.
    pub samples: usize,
}

impl Default for RadiusBracket {
    /// 50 m to 10⁶ m in 2000 log-spaced intervals.
    fn default() -> Self {
        Self {
            r_min: 50.0,
            r_max: 1.0e6,
            samples: 2000,
        }
    }
}

/// The outcome of a critical radius search.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum CriticalRadius {
    /// The largest radius R (m) in the bracket where the condition starts, as R falls from
    /// `r_max` (to relative 1e-12), with its cant θ (rad).
    Found {
        /// Critical radius (m).
        radius: f64,
        /// Cant θ = Ct/R there (rad).
        theta: f64,
    },
    /// The condition already holds at the largest radius of the bracket (m).
    AlreadyAtMaxRadius {
        /// The bracket's `r_max` (m).
        r_max: f64,
    },
    /// The condition does not arise anywhere in the bracket (down to `r_min`, m).
    NotReached {
        /// The smallest radius searched (m).
        r_min: f64,
    },
}

impl CriticalRadius {
    /// The radius if one was found (m).
    pub fn radius(&self) -> Option<f64> {
        match *self {
            CriticalRadius::Found { radius, .. } => Some(radius),
            _ => None,
        }
    }
}

/// Scans `margin(R)` (≥ 0 where the condition holds) from `r_max` down in log steps and
/// bisects the first change to relative 1e-12 in R.
fn search(
    bracket: &RadiusBracket,
    cant_constant: f64,
    margin: impl Fn(f64) -> f64,
) -> Result<CriticalRadius, TheoryError> {
    check(
        bracket.r_min > 0.0 && bracket.r_min.is_finite(),
        "bracket r_min (m)",
        bracket.r_min,
        "give a positive, finite r_min",
    )?;
    check(
        bracket.r_max > bracket.r_min && bracket.r_max.is_finite(),
        "bracket r_max (m)",
        bracket.r_max,
        "give a finite r_max above r_min",
    )?;
    check(
        bracket.samples >= 1,
        "bracket samples",
        bracket.samples as f64,
        "give at least 1 scan interval",
    )?;
    let r_min = bracket.r_min.max(cant_constant.abs());
    if r_min >= bracket.r_max {
        return Ok(CriticalRadius::NotReached { r_min });
    }
    if margin(bracket.r_max) >= 0.0 {
        return Ok(CriticalRadius::AlreadyAtMaxRadius {
            r_max: bracket.r_max,
        });
    }
    let ratio = (r_min / bracket.r_max).powf(1.0 / bracket.samples as f64);
    let mut hi = bracket.r_max; // margin < 0 (condition not met)
    for k in 1..=bracket.samples {
        let lo = if k == bracket.samples {
            r_min
        } else {
            bracket.r_max * ratio.powi(k as i32)
        };
        if margin(lo) >= 0.0 {
            // Bisection between lo (met) and hi (not met).
            let (mut met, mut not_met) = (lo, hi);
            while (not_met - met) > 1e-12 * met {
                let mid = 0.5 * (met + not_met);
                if margin(mid) >= 0.0 {
                    met = mid;
                } else {
                    not_met = mid;
                }
            }
            let radius = 0.5 * (met + not_met);
            return Ok(CriticalRadius::Found {
                radius,
                theta: cant_angle(cant_constant, radius),
            });
        }
        hi = lo;
    }
    Ok(CriticalRadius::NotReached { r_min })
}

/// The sliding margin of `forces` in `direction`, divided by the weight scale −ΣF2:
/// outwards (−ΣF1 − μ(−ΣF2))/(−ΣF2) (Eq. 24), inwards (ΣF1 − μ(−ΣF2))/(−ΣF2); ≥ 0 slides.
pub fn sliding_margin(forces: &WheelForces, mu: f64, direction: SlidingDirection) -> f64 {
    let s = match direction {
        SlidingDirection::Outwards => -forces.sum_f1,
        SlidingDirection::Inwards => forces.sum_f1,
    };
    (s - mu * -forces.sum_f2) / -forces.sum_f2
}

/// The critical radius of sliding in `direction` (m): the largest R in the bracket, met
/// as R falls from `bracket.r_max`, at which Eq. 24 (outwards) or its mirror (inwards)
/// starts to hold, with θ = Ct/R varying with R. Outwards at speed, inwards when slow on
/// a steep cant. Independent of the body heights and of the variant of Eq. 25.
pub fn critical_radius_sliding(
    carriage: &Carriage,
    track: &TrackParams,
    op: &Operation,
    direction: SlidingDirection,
    bracket: &RadiusBracket,
) -> Result<CriticalRadius, TheoryError> {
    evaluate(carriage, track, op, bracket.r_max, Variant::Statics)?;
    search(bracket, op.cant_constant, |r| {
        let f = forces_unchecked(carriage, track, op, r, Variant::Statics);
        sliding_margin(&f, op.mu, direction)
    })
}

/// The critical radius of separation (m): the largest R in the bracket, met as R falls
/// from `bracket.r_max`, at which the `side` wheel's normal force (per `variant` of
/// Eq. 25) reaches 0. The inner wheel at speed (overturning outwards), the outer one when
/// slow on a steep cant. θ = Ct/R varies with R.
pub fn critical_radius_separation(
    carriage: &Carriage,
    track: &TrackParams,
    op: &Operation,
    variant: Variant,
    side: WheelSide,
    bracket: &RadiusBracket,
) -> Result<CriticalRadius, TheoryError> {
    evaluate(carriage, track, op, bracket.r_max, variant)?;
    let scale = carriage.total_weight() / carriage.n_wheels as f64;
    search(bracket, op.cant_constant, |r| {
        let f = forces_unchecked(carriage, track, op, r, variant);
        let normal = match side {
            WheelSide::Inner => f.normal_inner,
            WheelSide::Outer => f.normal_outer,
        };
        -normal / scale
    })
}

/// Nadal's limit of the derailment quotient, (tan γ − μ)/(1 + μ tan γ) (–), for flange
/// angle `flange_angle` γ (rad; 70° for S1002) and friction μ: flange climb is possible
/// when Y/Q exceeds it (1.20 at γ = 70°, μ = 0.36).
pub fn nadal_limit(flange_angle: f64, mu: f64) -> f64 {
    let t = flange_angle.tan();
    (t - mu) / (1.0 + mu * t)
}

/// Derailment quotient Y/Q (–): lateral over vertical wheel–rail force (N/N), `|Y|/Q`;
/// +∞ when Q ≤ 0 (unloaded wheel).
pub fn derailment_quotient(lateral: f64, vertical: f64) -> f64 {
    if vertical > 0.0 {
        lateral.abs() / vertical
    } else {
        f64::INFINITY
    }
}

/// Wheel unloading ratio ΔQ/Q = (Q_ref − Q)/Q_ref (–) of a wheel carrying Q (N) against
/// its reference (static or mean) load Q_ref (N); 1 when the wheel is fully unloaded.
pub fn unloading_ratio(reference_load: f64, load: f64) -> f64 {
    (reference_load - load) / reference_load
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Vector2;

    fn op(speed: f64, ct: f64, mu: f64) -> Operation {
        Operation {
            speed,
            cant_constant: ct,
            mu,
        }
    }

    #[test]
    fn preset_totals() {
        let c = Carriage::sks700_standin();
        let mass = c.total_weight() / STANDARD_GRAVITY;
        // 7 400 + 4 800 + 43 862.5 = 56 062.5 kg (the spec's "56.06 t", rounded).
        assert!((mass - 56_062.5).abs() < 1e-9 * 56_062.5);
        assert_eq!(c.n_wheels, 8);
        // 14.0 t axle load (56 062.5 kg / 4 axles = 14 015.6 kg).
        assert!((mass / 4.0 - 14_015.625).abs() < 1e-9 * 14_015.0);
    }

    /// Hand-computed case: stand-in carriage, V = 80 m/s, R = 6250 m, Ct = 200 m,
    /// μ = 0.2, G = 1.435 m, g = 9.81 m/s².
    ///
    /// θ = 200/6250 = 0.032 rad, sin θ = 0.031994539, cos θ = 0.999488044, V²/R = 1.024.
    /// Wheelsets m = 7400 kg, W = 72 594 N:
    ///   F1 = 72594·0.031994539 − 7400·1.024·0.999488044 = 2322.68 − 7573.79 = −5251.109 N,
    ///   F2 = −72594·0.999488044 − 7400·1.024·0.031994539 = −72556.83 − 242.44 = −72799.277 N.
    /// Bogies m = 4800 kg: F1 = −3406.125 N, F2 = −47221.153 N.
    /// Car body m = 43 862.5 kg: F1 = −31125.239 N, F2 = −431507.876 N.
    /// ΣF1 = −39782.473 N, ΣF2 = −551528.305 N,
    /// ΣF1·H = −5251.109·0.43 − 3406.125·0.48 − 31125.239·1.51 = −50892.028 N·m.
    /// F_S = 39782.473/8 = 4972.809 N; mean F_N = 551528.305/8 = 68941.038 N;
    /// printed term ΣF1H/(8·1.435) = −4433.103 N → inner 64507.935, outer 73374.142 N;
    /// statics term twice that, −8866.207 N → inner 60074.831, outer 77807.245 N.
    /// Sliding ratio −ΣF1/−ΣF2 = 0.0721 < μ = 0.2: no sliding.
    #[test]
    fn hand_computed_case() {
        let c = Carriage::sks700_standin();
        let t = TrackParams::default();
        let o = op(80.0, 200.0, 0.2);
        let p = evaluate(&c, &t, &o, 6250.0, Variant::Printed).unwrap();
        let s = evaluate(&c, &t, &o, 6250.0, Variant::Statics).unwrap();
        let close = |a: f64, b: f64| (a - b).abs() < 1e-3;
        assert!(close(p.theta, 0.032));
        assert!(close(p.sum_f1, -39782.473));
        assert!(close(p.sum_f2, -551528.305));
        assert!(close(p.sum_f1_h, -50892.028));
        assert!(close(p.shear, 4972.809));
        assert!(close(p.normal_inner, 64507.935));
        assert!(close(p.normal_outer, 73374.142));
        assert!(close(s.normal_inner, 60074.831));
        assert!(close(s.normal_outer, 77807.245));
        assert_eq!(p.sliding, Sliding::None);
        assert!(!s.separation());
        let (yq_in, _) = s.derailment_quotients();
        let rel = |a: f64, b: f64| (a - b).abs() < 1e-6 * b.abs();
        assert!(rel(yq_in, 4972.809 / 60074.831));
        assert!(rel(s.unloading_ratio(), 8866.207 / 68941.038));
    }

    /// Independent free-body check of the Statics variant: the rails' forces on the wheels
    /// (N/2 inner at (+G/2, 0), N/2 outer at (−G/2, 0); normal F_N along +2, shear F_S
    /// along +1) and the body forces (F1_i, F2_i) at (0, H_i) have zero resultant and zero
    /// moment about any point, to 1e-12 relative to W·G. The Printed variant does not.
    #[test]
    fn statics_free_body_balances() {
        let c = Carriage::sks700_standin();
        let t = TrackParams {
            gauge: 1.5,
            gravity: 9.80665,
        };
        for (v, r, ct) in [
            (80.0, 6250.0, 200.0),
            (120.0, 3000.0, 900.0),
            (5.0, 800.0, 150.0),
            (60.0, f64::INFINITY, 0.0),
        ] {
            let o = op(v, ct, 0.3);
            for variant in [Variant::Statics, Variant::Printed] {
                let f = evaluate(&c, &t, &o, r, variant).unwrap();
                let half = c.n_wheels as f64 / 2.0;
                let curv = if r.is_infinite() { 0.0 } else { 1.0 / r };
                let mut loads: Vec<(Vector2<f64>, Vector2<f64>)> = c
                    .bodies
                    .iter()
                    .map(|b| {
                        let (f1, f2) = body_forces(b.weight, f.theta, curv, v, t.gravity);
                        (Vector2::new(0.0, b.cg_height), Vector2::new(f1, f2))
                    })
                    .collect();
                loads.push((
                    Vector2::new(t.gauge / 2.0, 0.0),
                    half * Vector2::new(f.shear, f.normal_inner),
                ));
                loads.push((
                    Vector2::new(-t.gauge / 2.0, 0.0),
                    half * Vector2::new(f.shear, f.normal_outer),
                ));
                let scale = c.total_weight() * t.gauge;
                let net: Vector2<f64> = loads.iter().map(|l| l.1).sum();
                assert!(net.norm() < 1e-12 * c.total_weight());
                for about in [Vector2::new(0.0, 0.0), Vector2::new(3.7, -1.2)] {
                    let m: f64 = loads
                        .iter()
                        .map(|(x, fo)| {
                            let d = x - about;
                            d.x * fo.y - d.y * fo.x
                        })
                        .sum();
                    match variant {
                        Variant::Statics => assert!(m.abs() < 1e-12 * scale, "{m}"),
                        Variant::Printed => {
                            // Unbalanced by half the moment: ΣF1·H/2 ≠ 0 unless ΣF1·H = 0.
                            let expected = -f.sum_f1_h / 2.0;
                            assert!((m - expected).abs() < 1e-12 * scale, "{m}");
                        }
                    }
                }
            }
        }
    }

    /// The two variants differ exactly by the factor 2 in the moment term.
    #[test]
    fn printed_and_statics_differ_by_two() {
        let c = Carriage::sks700_standin();
        let t = TrackParams::default();
        for (v, r) in [(80.0, 6250.0), (150.0, 4000.0), (10.0, 1000.0)] {
            let o = op(v, 400.0, 0.3);
            let p = evaluate(&c, &t, &o, r, Variant::Printed).unwrap();
            let s = evaluate(&c, &t, &o, r, Variant::Statics).unwrap();
            let m = p.mean_normal();
            assert!((m - s.mean_normal()).abs() <= 1e-12 * m);
            let dp = p.normal_inner - p.mean_normal();
            let ds = s.normal_inner - s.mean_normal();
            // (the differences of forces of ~7e4 N carry ~1e-11 N of rounding)
            assert!((ds - 2.0 * dp).abs() <= 1e-12 * m, "{ds} {dp}");
            let dq = p.normal_outer - p.mean_normal();
            assert!((dq + dp).abs() <= 1e-12 * m);
        }
    }

    /// At the balanced speed V² = g·R·tan θ every F1_i vanishes: no shear, equal loads.
    #[test]
    fn balanced_speed_gives_zero_shear() {
        let c = Carriage::sks700_standin();
        let t = TrackParams::default();
        let (r, ct) = (3000.0, 400.0);
        let v = (t.gravity * r * (ct / r).tan()).sqrt();
        let f = evaluate(&c, &t, &op(v, ct, 0.2), r, Variant::Statics).unwrap();
        assert!(f.sum_f1.abs() < 1e-9 * c.total_weight());
        assert!(f.shear.abs() < 1e-9 * c.total_weight());
        assert!((f.normal_inner - f.normal_outer).abs() < 1e-9 * c.total_weight());
        assert_eq!(f.sliding, Sliding::None);
    }

    /// Critical radii satisfy their defining equations to 1e-9 (relative to the weight
    /// scale), and just above them the condition does not hold.
    #[test]
    fn critical_radii_satisfy_their_equations() {
        let c = Carriage::sks700_standin();
        let t = TrackParams::default();
        let b = RadiusBracket::default();
        // Sliding outwards: V = 180 m/s, Ct = 400 m, μ = 0.2 (the paper's Figure 8 case).
        let o = op(180.0, 400.0, 0.2);
        let r = critical_radius_sliding(&c, &t, &o, SlidingDirection::Outwards, &b)
            .unwrap()
            .radius()
            .unwrap();
        let f = evaluate(&c, &t, &o, r, Variant::Statics).unwrap();
        let res = -f.sum_f1 - o.mu * -f.sum_f2; // Eq. 24 as an equality
        assert!(res.abs() < 1e-9 * c.total_weight(), "{res}");
        // Closed form for the check: with a = V²/(gR), θ = Ct/R:
        // a cos θ − sin θ = μ (cos θ + a sin θ), i.e. a = (tan θ + μ)/(1 − μ tan θ).
        let (a, th) = (180.0f64.powi(2) / (t.gravity * r), 400.0 / r);
        assert!((a - (th.tan() + 0.2) / (1.0 - 0.2 * th.tan())).abs() < 1e-9);
        let above = evaluate(&c, &t, &o, r * (1.0 + 1e-6), Variant::Statics).unwrap();
        assert_eq!(above.sliding, Sliding::None);
        eprintln!("sliding outwards V=180 Ct=400 mu=0.2: R* = {r:.4} m");
        // Separation of the inner wheel, both variants: V = 220, Ct = 200 (Figure 10 case).
        let o = op(220.0, 200.0, 0.3);
        for variant in [Variant::Printed, Variant::Statics] {
            let r = critical_radius_separation(&c, &t, &o, variant, WheelSide::Inner, &b)
                .unwrap()
                .radius()
                .unwrap();
            let f = evaluate(&c, &t, &o, r, variant).unwrap();
            assert!(f.normal_inner.abs() < 1e-9 * c.total_weight(), "{f:?}");
            eprintln!("separation V=220 Ct=200 {variant:?}: R* = {r:.4} m");
        }
    }

    /// Slow on a steep cant the carriage slides inwards: V = 0, μ = 0.1 gives
    /// tan θ = μ, θ = atan 0.1 = 0.0996687 rad, R = Ct/θ = 900/0.0996687 = 9029.91 m.
    #[test]
    fn inward_sliding_at_low_speed() {
        let c = Carriage::sks700_standin();
        let t = TrackParams::default();
        let o = op(0.0, 900.0, 0.1);
        let b = RadiusBracket::default();
        let r = critical_radius_sliding(&c, &t, &o, SlidingDirection::Inwards, &b)
            .unwrap()
            .radius()
            .unwrap();
        assert!((r - 900.0 / 0.1f64.atan()).abs() < 1e-8 * r);
        let f = evaluate(&c, &t, &o, r * 0.999, Variant::Statics).unwrap();
        assert_eq!(f.sliding, Sliding::Inwards);
        // Never outwards at standstill.
        let none = critical_radius_sliding(&c, &t, &o, SlidingDirection::Outwards, &b).unwrap();
        assert!(matches!(none, CriticalRadius::NotReached { .. }));
    }

    #[test]
    fn typed_results_and_errors() {
        let c = Carriage::sks700_standin();
        let t = TrackParams::default();
        // Already sliding on the largest radius: μ = 0.
        let o = op(100.0, 0.0, 0.0);
        let b = RadiusBracket {
            r_min: 100.0,
            r_max: 1e5,
            samples: 100,
        };
        let res = critical_radius_sliding(&c, &t, &o, SlidingDirection::Outwards, &b).unwrap();
        assert!(matches!(res, CriticalRadius::AlreadyAtMaxRadius { .. }));
        assert!(evaluate(&c, &t, &o, -1.0, Variant::Statics).is_err());
        assert!(evaluate(&c, &t, &o, 100.0, Variant::Statics).is_ok());
        assert!(evaluate(&c, &t, &op(10.0, 900.0, 0.1), 500.0, Variant::Statics).is_err());
        let bad = Carriage {
            bodies: vec![],
            n_wheels: 8,
        };
        let e = evaluate(&bad, &t, &o, 100.0, Variant::Statics).unwrap_err();
        assert!(!e.to_string().contains('\n') && e.to_string().contains("fix:"));
        let odd = Carriage {
            n_wheels: 7,
            ..c.clone()
        };
        assert!(evaluate(&odd, &t, &o, 100.0, Variant::Statics).is_err());
        // A straight: θ = 0, no shear.
        let f = evaluate(
            &c,
            &t,
            &op(80.0, 200.0, 0.2),
            f64::INFINITY,
            Variant::Statics,
        )
        .unwrap();
        assert_eq!(f.theta, 0.0);
        assert_eq!(f.shear, 0.0);
    }

    /// Nadal: γ = 70°, μ = 0.36: tan 70° = 2.747477, (2.747477 − 0.36)/(1 + 0.989092)
    /// = 2.387477/1.989092 = 1.20029.
    #[test]
    fn derailment_indices() {
        let n = nadal_limit(70f64.to_radians(), 0.36);
        assert!((n - 1.20029).abs() < 1e-5, "{n}");
        assert!((derailment_quotient(-30.0, 60.0) - 0.5).abs() < 1e-15);
        assert_eq!(derailment_quotient(1.0, 0.0), f64::INFINITY);
        assert!((unloading_ratio(70.0, 21.0) - 0.7).abs() < 1e-15);
    }
}

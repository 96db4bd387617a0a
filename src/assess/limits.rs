//! The closed-form limits and indices of a running-safety and track-loading assessment:
//! Nadal's derailment limit, Prud'homme's track-shift limit in its EN 14363 form, the wear
//! number Tγ and the shakedown surface-fatigue index. Each function cites its source; the
//! defaults the `assess` command applies are in [`AssessLimits::default`].

use serde::Serialize;

/// Nadal's limit of the flange-climbing ratio Y/Q (M. J. Nadal, "Locomotives à vapeur",
/// Collection Encyclopédie Scientifique, Paris 1908; in EN 14363 and UIC 518 as the basis
/// of the Y/Q limit): at the flange contact with flange angle `γ` and friction `μ`, the
/// wheel climbs once `Y/Q > (tan γ − μ)/(1 + μ·tan γ)`.
pub fn nadal(flange_angle: f64, mu: f64) -> f64 {
    let t = flange_angle.tan();
    (t - mu) / (1.0 + mu * t)
}

/// Prud'homme's limit of the track-shifting force of one wheelset, in its EN 14363 form
/// `(ΣY)_lim = α·(10 kN + P0/3)` with the static axle load `P0 = 2·Q0` (A. Prud'homme,
/// "La résistance de la voie aux efforts transversaux exercés par le matériel roulant",
/// Revue générale des chemins de fer, 1967; EN 14363:2016 and UIC 518, `α = 1` for
/// passenger vehicles and locomotives, `0.85` for freight wagons). In N.
pub fn prudhomme(alpha: f64, q0: f64) -> f64 {
    alpha * (10e3 + 2.0 * q0 / 3.0)
}

/// The wear number of a contact patch, `Tγ = |Fx·ξx + Fy·ξy|` (N, = J/m): the frictional
/// power per unit rolled distance (spin left out, as in the usual Tγ of wear and RCF
/// models, e.g. the WLRM of Burstow 2004). With Kalker's sign (the force opposes the
/// creepage) the product is ≤ 0 and Tγ its magnitude.
pub fn t_gamma(fx: f64, fy: f64, xi_x: f64, xi_y: f64) -> f64 {
    (fx * xi_x + fy * xi_y).abs()
}

/// The surface fatigue index of shakedown theory (A. Ekberg, E. Kabo & H. Andersson, "An
/// engineering model for prediction of rolling contact fatigue of railway wheels",
/// Fatigue Fract. Engng Mater. Struct. 25 (2002) 899–909, Eq. 3):
/// `FI_surf = f − 2π·a·b·k/(3·Fz)`, the traction coefficient `f = √(Fx² + Fy²)/Fz` minus
/// the shakedown limit of a Hertzian patch of semi-axes `a, b` under `Fz` for a material
/// of yield stress in shear `k`. Surface-initiated RCF is predicted where `FI_surf > 0`.
pub fn surface_fatigue_index(ft: f64, fz: f64, a: f64, b: f64, k: f64) -> f64 {
    if !(fz > 0.0 && a > 0.0 && b > 0.0) {
        return f64::NAN;
    }
    ft / fz - 2.0 * std::f64::consts::PI * a * b * k / (3.0 * fz)
}

/// The options of an assessment with their defaults (docs/assessment.md cites each).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct AssessLimits {
    /// Low-pass cut-off of Y and Q before any evaluation (Hz); EN 14363: 20 Hz.
    pub cutoff: f64,
    /// Window of the sliding means of Y/Q and ΣY (m); EN 14363: 2 m.
    pub window: f64,
    /// Percentile taken as the quasi-static value over the section (%); EN 14363: 50.
    pub quasi_static_percentile: f64,
    /// Percentile taken as the maximum of a filtered signal (%); EN 14363: 99.85.
    pub max_percentile: f64,
    /// Flange angle for Nadal's limit (rad); S1002: 70°.
    pub flange_angle: f64,
    /// Friction for Nadal's limit (-); the 0.36 behind EN 14363's 1.2.
    pub nadal_mu: f64,
    /// Y/Q limit given directly, overriding Nadal's (e.g. 0.8 for R ≥ 250 m).
    pub yq_limit: Option<f64>,
    /// Prud'homme's factor α (-): 1.0 passenger vehicles, 0.85 freight wagons.
    pub alpha: f64,
    /// Limit of the wheel unloading ΔQ/Q0 (-); EN 14363: 0.6.
    pub dqq_limit: f64,
    /// Quasi-static guiding force limit (N); EN 14363: 60 kN.
    pub y_qst_limit: f64,
    /// Quasi-static wheel force limit (N); EN 14363: 145 kN.
    pub q_qst_limit: f64,
    /// The addition to Q0 of the maximum wheel force limit (N): `Q_lim = 90 kN + Q0`
    /// (UIC 518, V ≤ 160 km/h).
    pub q_max_add: f64,
    /// Yield stress in shear of the rail steel for the surface fatigue index (Pa);
    /// Ekberg et al. (2002): about 300 MPa for wheel and rail steels.
    pub shear_yield: f64,
}

impl Default for AssessLimits {
    fn default() -> Self {
        AssessLimits {
            cutoff: 20.0,
            window: 2.0,
            quasi_static_percentile: 50.0,
            max_percentile: 99.85,
            flange_angle: 70f64.to_radians(),
            nadal_mu: 0.36,
            yq_limit: None,
            alpha: 1.0,
            dqq_limit: 0.6,
            y_qst_limit: 60e3,
            q_qst_limit: 145e3,
            q_max_add: 90e3,
            shear_yield: 300e6,
        }
    }
}

impl AssessLimits {
    /// The Y/Q limit in force: the one given, or Nadal's.
    pub fn yq(&self) -> f64 {
        self.yq_limit
            .unwrap_or_else(|| nadal(self.flange_angle, self.nadal_mu))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Nadal's closed form at the textbook points: 70° and μ = 0.36 give 1.20 (EN 14363's
    /// limit in tight curves), and the friction-free limit is tan γ; the ratio falls with μ.
    #[test]
    fn nadal_closed_form() {
        let l = nadal(70f64.to_radians(), 0.36);
        let t = 70f64.to_radians().tan(); // 2.7475
        assert!((l - (t - 0.36) / (1.0 + 0.36 * t)).abs() < 1e-15);
        assert!((l - 1.2).abs() < 0.005, "{l}");
        assert!((nadal(0.9, 0.0) - 0.9f64.tan()).abs() < 1e-15);
        // 45° and μ = 0: Y/Q = 1; μ = 1 at 45°: 0 (the friction cone reaches the flank).
        assert!((nadal(std::f64::consts::FRAC_PI_4, 0.0) - 1.0).abs() < 1e-15);
        assert!(nadal(std::f64::consts::FRAC_PI_4, 1.0).abs() < 1e-15);
        assert!(nadal(1.2, 0.5) < nadal(1.2, 0.3));
    }

    /// Prud'homme: a 22.5 t axle (Q0 = 110.3 kN) with α = 0.85 gives 71.0 kN; α = 1 and
    /// Q0 = 60 kN give 50 kN.
    #[test]
    fn prudhomme_en14363_form() {
        assert!((prudhomme(1.0, 60e3) - 50e3).abs() < 1e-9);
        let q0 = 22.5e3 * 9.80665 / 2.0;
        assert!((prudhomme(0.85, q0) - 0.85 * (10e3 + 2.0 * q0 / 3.0)).abs() < 1e-9);
        assert!((prudhomme(0.85, q0) / 1e3 - 71.0).abs() < 0.1);
    }

    /// The surface index at the shakedown boundary is zero: a patch whose traction
    /// coefficient equals `2πabk/(3Fz)` sits on it.
    #[test]
    fn surface_index_is_zero_on_the_shakedown_limit() {
        let (a, b, fz, k) = (6e-3, 4e-3, 80e3, 300e6);
        let limit = 2.0 * std::f64::consts::PI * a * b * k / (3.0 * fz);
        assert!(surface_fatigue_index(limit * fz, fz, a, b, k).abs() < 1e-12);
        assert!(surface_fatigue_index(0.0, fz, a, b, k) < 0.0);
        assert!(surface_fatigue_index(1.0, 0.0, a, b, k).is_nan());
    }
}

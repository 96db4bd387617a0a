//! Kalker's linear creep coefficients `C11, C22, C23` of an elliptic contact, the creep forces
//! of Kalker's linear theory and their Shen–Hedrick–Elkins saturation at `μN`.
//!
//! **Table.** Kalker, *Three-dimensional elastic bodies in rolling contact*, Kluwer 1990,
//! Table E.3 (the values of Kalker's 1967 thesis, *On the rolling contact of two elastic
//! bodies in the presence of dry friction*, Delft), `c_ij` for Poisson's ratio
//! `ν = 0, 0.25, 0.5` and `g = min(a/b, b/a) = 0.1, 0.2, …, 1.0`, `a` the semi-axis in the
//! rolling direction. Transcribed here from the machine-readable copy in the `linrol`
//! routine of Vollebregt & Kalker's open-source CONTACT (module `m_hertz`), checked entry by
//! entry against an older release of the same routine: the two agree everywhere except
//! `C23(a/b = 0.8, ν = 0.25)`, where the older copy has 1.15, which breaks the monotone run
//! 1.03, 1.14, ·, 1.36, 1.47 of its neighbours; the newer 1.25 is used. Only `C11, C22, C23`
//! are in that table: **`C33` (spin moment) was not found in a source that could be
//! cross-checked, so the spin moment `Mz` is not provided** (see docs/creep.md).
//!
//! **Interpolation.** In `g` by piecewise cubic Lagrange interpolation on the four nearest
//! knots (continuous, exact at the knots). For `a > b` the coefficients grow like `1/g`
//! (`C11, C22`) and `g^{-3/2}` (`C23`) as `g → 0` (Kalker's asymptotes), so the smooth
//! quantities `g·C11`, `g·C22`, `g^{3/2}·C23` are interpolated there; for `a ≤ b` the
//! coefficients stay bounded and are interpolated directly. In `ν` by the quadratic through
//! the three columns. Outside `0 ≤ ν ≤ 0.5` the functions refuse.
//!
//! **Slender ellipses, `g < 0.1`** ([`slender_asymptote`]): Kalker's `g → 0` expressions
//! of the same Table E.3, with `Λ = ln(16/g²)`:
//! - `a ≪ b`: `C11 = π²/(4(1 − ν))`, `C22 = π²/4`,
//!   `C23 = π√g/(3(1 − ν))·[1 + ν(Λ/2 + ln 4 − 5)]`;
//! - `a ≫ b`: `C11 = 2π/((Λ − 2ν)·g)·[1 + (3 − ln 4)/(Λ − 2ν)]`,
//!   `C22 = 2π/(g·W)·[1 + (1 − ν)(3 − ln 4)/W]` with `W = (1 − ν)Λ + 2ν`,
//!   `C23 = 2π/(3g^{3/2}·((1 − ν)Λ − 2 + 4ν))`.
//!
//! Transcribed from the same `linrol` routine of CONTACT (which switches to them abruptly
//! below `g = 0.101`); the ORVD wheel–rail library documents the same expressions (not an
//! independent transcription). At `g = 0.1` they lie 0.07–6.4 % from the table (they are the
//! leading terms of an expansion in `g`), so switching would put a jump of that size into
//! the creep force. Here the asymptote is corrected by a factor that fades linearly in `g`:
//! `C(g) = C_asym(g)·[1 + (r − 1)·g/0.1]`, `r = C_table(0.1)/C_asym(0.1)` (per coefficient,
//! side and `ν`): equal to the table at `g = 0.1`, to Kalker's asymptote as `g → 0`.
//!
//! **Forces** (Kalker's linear theory, e.g. Garg & Dukkipati 1984, §5.4; creepages `ξx, ξy`
//! dimensionless, spin `φ` in 1/m, shear modulus `G`):
//! `Fx = −G·a·b·C11·ξx`, `Fy = −G·a·b·C22·ξy − G·(ab)^{3/2}·C23·φ`.
//!
//! **Saturation** (Shen, Hedrick & Elkins, *A comparison of alternative creep force models
//! for rail vehicle dynamic analysis*, Proc. 8th IAVSD Symposium, 1983): with the linear
//! resultant `F = √(Fx² + Fy²)` and `u = F/(μN)`, the saturated resultant is
//! `F' = μN·(u − u²/3 + u³/27)` for `u < 3`, `F' = μN` beyond, and both components are
//! scaled by `ε = F'/F`. `dF'/dF = (1 − u/3)² ≥ 0`: monotone, equal to the linear law at
//! small `u` and reaching `μN` with zero slope at `u = 3`.

use thiserror::Error;

/// Why a creep coefficient or force cannot be computed.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum KalkerError {
    /// The semi-axis ratio is not a positive finite number.
    #[error("contact-ellipse ratio a/b = {0} must be positive and finite")]
    BadRatio(f64),
    /// Poisson's ratio outside [0, 0.5].
    #[error("Poisson's ratio {0} is outside [0, 0.5]; give a value such as 0.28 for steel")]
    Poisson(f64),
    /// A positive quantity (shear modulus, semi-axis, load) is not positive and finite.
    #[error("{name} = {value} must be positive and finite")]
    NotPositive {
        /// The quantity's name.
        name: &'static str,
        /// Its value.
        value: f64,
    },
    /// Friction coefficient outside 0–2.
    #[error("friction coefficient {0} is outside [0, 2]")]
    Friction(f64),
}

/// Kalker's coefficients of the linear theory (dimensionless).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CreepCoefficients {
    /// Longitudinal creepage → longitudinal force.
    pub c11: f64,
    /// Lateral creepage → lateral force.
    pub c22: f64,
    /// Spin → lateral force (and lateral creepage → spin moment).
    pub c23: f64,
}

/// The tabulated `g = min(a/b, b/a)`.
pub const G_KNOTS: [f64; 10] = [0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0];

/// The tabulated Poisson's ratios.
pub const NU_KNOTS: [f64; 3] = [0.0, 0.25, 0.5];

/// Kalker 1990, Table E.3, `a ≤ b` (`g = a/b`): per row `[C11; C22; C23]`, each for
/// `ν = 0, 0.25, 0.5`.
#[allow(clippy::approx_constant)] // tabulated 3.14, not π
pub const TABLE_A_LE_B: [[[f64; 3]; 3]; 10] = [
    [
        [2.51, 3.31, 4.85],
        [2.51, 2.52, 2.53],
        [0.334, 0.473, 0.731],
    ],
    [
        [2.59, 3.37, 4.81],
        [2.59, 2.63, 2.66],
        [0.483, 0.603, 0.809],
    ],
    [
        [2.68, 3.44, 4.80],
        [2.68, 2.75, 2.81],
        [0.607, 0.715, 0.889],
    ],
    [
        [2.78, 3.53, 4.82],
        [2.78, 2.88, 2.98],
        [0.720, 0.823, 0.977],
    ],
    [[2.88, 3.62, 4.83], [2.88, 3.01, 3.14], [0.827, 0.929, 1.07]],
    [[2.98, 3.72, 4.91], [2.98, 3.14, 3.31], [0.930, 1.03, 1.18]],
    [[3.09, 3.81, 4.97], [3.09, 3.28, 3.48], [1.03, 1.14, 1.29]],
    [[3.19, 3.91, 5.05], [3.19, 3.41, 3.65], [1.13, 1.25, 1.40]],
    [[3.29, 4.01, 5.12], [3.29, 3.54, 3.82], [1.23, 1.36, 1.51]],
    [[3.40, 4.12, 5.20], [3.40, 3.67, 3.98], [1.33, 1.47, 1.63]],
];

/// Kalker 1990, Table E.3, `a > b` (`g = b/a`), same layout.
#[allow(clippy::approx_constant)] // tabulated 3.14, not π
pub const TABLE_A_GT_B: [[[f64; 3]; 3]; 10] = [
    [[10.7, 11.7, 12.9], [10.7, 12.8, 16.0], [12.2, 14.6, 18.0]],
    [[6.96, 7.78, 8.82], [6.96, 8.14, 9.79], [5.72, 6.63, 7.89]],
    [[5.57, 6.34, 7.34], [5.57, 6.40, 7.51], [3.79, 4.32, 5.01]],
    [[4.84, 5.57, 6.57], [4.84, 5.48, 6.31], [2.88, 3.24, 3.70]],
    [[4.37, 5.10, 6.11], [4.37, 4.90, 5.56], [2.35, 2.62, 2.96]],
    [[4.06, 4.78, 5.80], [4.06, 4.50, 5.04], [2.01, 2.23, 2.50]],
    [[3.82, 4.54, 5.58], [3.82, 4.21, 4.67], [1.76, 1.95, 2.18]],
    [[3.65, 4.36, 5.42], [3.65, 3.99, 4.39], [1.58, 1.75, 1.94]],
    [[3.51, 4.22, 5.30], [3.51, 3.81, 4.16], [1.44, 1.59, 1.77]],
    [[3.40, 4.12, 5.20], [3.40, 3.67, 3.98], [1.33, 1.47, 1.63]],
];

/// Power `q` of `g` multiplying coefficient `j` before interpolation (see the module doc).
fn scale_power(a_gt_b: bool, j: usize) -> f64 {
    match (a_gt_b, j) {
        (false, _) => 0.0,
        (true, 2) => 1.5,
        (true, _) => 1.0,
    }
}

/// Piecewise cubic Lagrange interpolation through the points `(xs[i], ys[i])` (`xs`
/// increasing, at least four): on the interval holding `x`, the cubic through the four
/// nearest knots (the interval's ends and one more on each side, shifted inwards at the ends).
fn local_cubic(xs: &[f64], ys: &[f64], x: f64) -> f64 {
    let n = xs.len();
    let interval = xs[1..n - 1].iter().take_while(|&&xi| xi <= x).count();
    let start = interval.saturating_sub(1).min(n - 4);
    let mut sum = 0.0;
    for i in start..start + 4 {
        let mut l = 1.0;
        for k in start..start + 4 {
            if k != i {
                l *= (x - xs[k]) / (xs[i] - xs[k]);
            }
        }
        sum += ys[i] * l;
    }
    sum
}

/// Coefficient `j` for the `ν` column `k` at `g`, interpolated from the table rows `rows`
/// (all ten in use; the tests also leave one out).
fn coefficient_in_g(a_gt_b: bool, j: usize, k: usize, g: f64, rows: &[usize]) -> f64 {
    let table = if a_gt_b { &TABLE_A_GT_B } else { &TABLE_A_LE_B };
    let q = scale_power(a_gt_b, j);
    let xs: Vec<f64> = rows.iter().map(|&r| G_KNOTS[r]).collect();
    let ys: Vec<f64> = rows
        .iter()
        .map(|&r| table[r][j][k] * G_KNOTS[r].powf(q))
        .collect();
    local_cubic(&xs, &ys, g) / g.powf(q)
}

/// Quadratic through the three `ν` columns.
fn quadratic_in_nu(c: [f64; 3], nu: f64) -> f64 {
    let [n0, n1, n2] = NU_KNOTS;
    c[0] * (nu - n1) * (nu - n2) / ((n0 - n1) * (n0 - n2))
        + c[1] * (nu - n0) * (nu - n2) / ((n1 - n0) * (n1 - n2))
        + c[2] * (nu - n0) * (nu - n1) / ((n2 - n0) * (n2 - n1))
}

/// Kalker's `C11, C22, C23` for the semi-axis ratio `a_over_b` (`a` along the rolling
/// direction) and Poisson's ratio `poisson`: interpolated in Table E.3 for
/// `0.1 ≤ g ≤ 1`, the corrected slender-ellipse asymptotes below (module doc).
pub fn kalker_coefficients(a_over_b: f64, poisson: f64) -> Result<CreepCoefficients, KalkerError> {
    if !(a_over_b.is_finite() && a_over_b > 0.0) {
        return Err(KalkerError::BadRatio(a_over_b));
    }
    if !(poisson.is_finite() && (0.0..=0.5).contains(&poisson)) {
        return Err(KalkerError::Poisson(poisson));
    }
    let a_gt_b = a_over_b > 1.0;
    let g = if a_gt_b { 1.0 / a_over_b } else { a_over_b };
    // 1e-12: ratios computed as 1/(1/0.1) still count as on the table.
    if g >= G_KNOTS[0] * (1.0 - 1e-12) {
        return Ok(tabulated(a_gt_b, g.clamp(G_KNOTS[0], 1.0), poisson));
    }
    let edge = tabulated(a_gt_b, G_KNOTS[0], poisson);
    let edge_asym = slender_asymptote(a_gt_b, G_KNOTS[0], poisson);
    let asym = slender_asymptote(a_gt_b, g, poisson);
    let fade = g / G_KNOTS[0];
    let blend = |c: f64, r_table: f64, r_asym: f64| c * (1.0 + (r_table / r_asym - 1.0) * fade);
    Ok(CreepCoefficients {
        c11: blend(asym.c11, edge.c11, edge_asym.c11),
        c22: blend(asym.c22, edge.c22, edge_asym.c22),
        c23: blend(asym.c23, edge.c23, edge_asym.c23),
    })
}

/// Table E.3 interpolated at `0.1 ≤ g ≤ 1` (no checks).
fn tabulated(a_gt_b: bool, g: f64, poisson: f64) -> CreepCoefficients {
    const ALL_ROWS: [usize; 10] = [0, 1, 2, 3, 4, 5, 6, 7, 8, 9];
    let mut out = [0.0; 3];
    for (j, slot) in out.iter_mut().enumerate() {
        let mut by_nu = [0.0; 3];
        for (k, v) in by_nu.iter_mut().enumerate() {
            *v = coefficient_in_g(a_gt_b, j, k, g, &ALL_ROWS);
        }
        *slot = quadratic_in_nu(by_nu, poisson);
    }
    CreepCoefficients {
        c11: out[0],
        c22: out[1],
        c23: out[2],
    }
}

/// Kalker's `g → 0` asymptotes (1990, Table E.3; module doc) for the side `a_gt_b`
/// (`g = b/a` if true, `a/b` if false), `0 < g`, `0 ≤ ν ≤ 0.5`.
pub fn slender_asymptote(a_gt_b: bool, g: f64, nu: f64) -> CreepCoefficients {
    use std::f64::consts::PI;
    let lambda = (16.0 / (g * g)).ln();
    let ln4 = 4.0_f64.ln();
    if a_gt_b {
        let s = lambda - 2.0 * nu;
        let w = (1.0 - nu) * lambda + 2.0 * nu;
        CreepCoefficients {
            c11: 2.0 * PI / (s * g) * (1.0 + (3.0 - ln4) / s),
            c22: 2.0 * PI / (g * w) * (1.0 + (1.0 - nu) * (3.0 - ln4) / w),
            c23: 2.0 * PI / (3.0 * g.powf(1.5) * ((1.0 - nu) * lambda - 2.0 + 4.0 * nu)),
        }
    } else {
        CreepCoefficients {
            c11: PI * PI / (4.0 * (1.0 - nu)),
            c22: PI * PI / 4.0,
            c23: PI * g.sqrt() / (3.0 * (1.0 - nu)) * (1.0 + nu * (lambda / 2.0 + ln4 - 5.0)),
        }
    }
}

/// The creepages at a contact point.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Creepages {
    /// Longitudinal creepage `ξx` (−).
    pub xi_x: f64,
    /// Lateral creepage `ξy` (−).
    pub xi_y: f64,
    /// Spin creepage `φ` (1/m).
    pub spin: f64,
}

/// Tangential contact forces (N) in the contact plane, `x` rolling, `y` lateral.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CreepForces {
    /// Longitudinal creep force (N).
    pub fx: f64,
    /// Lateral creep force (N).
    pub fy: f64,
}

/// Kalker's linear creep forces for an ellipse with semi-axes `a`, `b` (m) and shear modulus
/// `shear_modulus` (Pa).
pub fn linear_creep_forces(
    shear_modulus: f64,
    a: f64,
    b: f64,
    c: &CreepCoefficients,
    cr: &Creepages,
) -> Result<CreepForces, KalkerError> {
    for (name, value) in [("shear modulus", shear_modulus), ("a", a), ("b", b)] {
        if !(value.is_finite() && value > 0.0) {
            return Err(KalkerError::NotPositive { name, value });
        }
    }
    let ab = a * b;
    let gab = shear_modulus * ab;
    Ok(CreepForces {
        fx: -gab * c.c11 * cr.xi_x,
        fy: -gab * c.c22 * cr.xi_y - shear_modulus * ab.powf(1.5) * c.c23 * cr.spin,
    })
}

/// Shen–Hedrick–Elkins reduction factor `ε = F'/F` for a linear resultant `f_linear` (N)
/// and friction limit `mu_n = μN` (N); 1 at `F = 0`.
pub fn she_factor(f_linear: f64, mu_n: f64) -> f64 {
    if f_linear <= 0.0 || mu_n <= 0.0 {
        return if mu_n <= 0.0 && f_linear > 0.0 {
            0.0
        } else {
            1.0
        };
    }
    let u = f_linear / mu_n;
    if u >= 3.0 {
        mu_n / f_linear
    } else {
        1.0 - u / 3.0 + u * u / 27.0
    }
}

/// Saturate the linear creep forces at `μ·N` by Shen–Hedrick–Elkins.
pub fn saturate(
    linear: CreepForces,
    friction: f64,
    normal_load: f64,
) -> Result<CreepForces, KalkerError> {
    if !(friction.is_finite() && (0.0..=2.0).contains(&friction)) {
        return Err(KalkerError::Friction(friction));
    }
    if !(normal_load.is_finite() && normal_load >= 0.0) {
        return Err(KalkerError::NotPositive {
            name: "normal load",
            value: normal_load,
        });
    }
    let f = linear.fx.hypot(linear.fy);
    let eps = she_factor(f, friction * normal_load);
    Ok(CreepForces {
        fx: eps * linear.fx,
        fy: eps * linear.fy,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn coef(c: &CreepCoefficients, j: usize) -> f64 {
        [c.c11, c.c22, c.c23][j]
    }

    #[test]
    fn interpolation_reproduces_every_knot_of_the_table() {
        for (r, &g) in G_KNOTS.iter().enumerate() {
            for (k, &nu) in NU_KNOTS.iter().enumerate() {
                let lo = kalker_coefficients(g, nu).unwrap();
                let hi = kalker_coefficients(1.0 / g, nu).unwrap();
                for j in 0..3 {
                    let (t_lo, t_hi) = (TABLE_A_LE_B[r][j][k], TABLE_A_GT_B[r][j][k]);
                    assert!(
                        (coef(&lo, j) - t_lo).abs() <= 1e-12 * t_lo,
                        "a/b={g} ν={nu} j={j}"
                    );
                    assert!(
                        (coef(&hi, j) - t_hi).abs() <= 1e-12 * t_hi,
                        "b/a={g} ν={nu} j={j}"
                    );
                }
            }
        }
    }

    /// The check: coefficients at ellipse ratios that are not knots of the
    /// interpolant, compared with Kalker's published value there. Each interior knot is
    /// removed in turn, the coefficient is interpolated from the remaining nine (twice the
    /// table spacing around it, so a pessimistic measure of the interpolation error), and
    /// compared with the published value: within 1 %.
    #[test]
    fn interpolation_within_one_percent_of_held_out_table_values() {
        let mut worst: f64 = 0.0;
        for a_gt_b in [false, true] {
            let table = if a_gt_b { &TABLE_A_GT_B } else { &TABLE_A_LE_B };
            for held in 1..9 {
                let keep: Vec<usize> = (0..10).filter(|&r| r != held).collect();
                let g = G_KNOTS[held];
                for j in 0..3 {
                    for k in 0..3 {
                        let c = coefficient_in_g(a_gt_b, j, k, g, &keep);
                        let published = table[held][j][k];
                        let err = (c / published - 1.0).abs();
                        worst = worst.max(err);
                        assert!(
                            err < 0.01,
                            "a>b={a_gt_b} g={g} coef {j} ν={}: {c} vs {published}",
                            NU_KNOTS[k]
                        );
                    }
                }
            }
        }
        eprintln!("held-out interpolation: worst relative error {worst:.4}");
    }

    #[test]
    fn table_obeys_kalker_exact_properties() {
        for r in 0..10 {
            // ν = 0: longitudinal and lateral creep are the same problem, C11 = C22.
            assert_eq!(TABLE_A_LE_B[r][0][0], TABLE_A_LE_B[r][1][0]);
            assert_eq!(TABLE_A_GT_B[r][0][0], TABLE_A_GT_B[r][1][0]);
        }
        // Circle: both halves of the table meet.
        assert_eq!(TABLE_A_LE_B[9], TABLE_A_GT_B[9]);
        // Kalker's asymptotes for a/b → 0 (the ellipse narrow in the rolling direction),
        // at ν = 0: C11 = C22 = π²/4, C23 = π√g/3. At g = 0.1 the table lies within 2 %
        // (the asymptotes are the g → 0 limit, not exact at 0.1).
        let pi = std::f64::consts::PI;
        let c = kalker_coefficients(0.1, 0.0).unwrap();
        assert!((c.c11 / (pi * pi / 4.0) - 1.0).abs() < 0.02);
        assert!((c.c22 / (pi * pi / 4.0) - 1.0).abs() < 0.02);
        assert!((c.c23 / (pi * 0.1_f64.sqrt() / 3.0) - 1.0).abs() < 0.02);
        // Interpolated values between knots lie between their neighbours (monotone table).
        for k in 0..3 {
            let nu = NU_KNOTS[k];
            for r in 0..9 {
                let g = 0.5 * (G_KNOTS[r] + G_KNOTS[r + 1]);
                let c = kalker_coefficients(g, nu).unwrap();
                for j in 0..3 {
                    let (y0, y1) = (TABLE_A_LE_B[r][j][k], TABLE_A_LE_B[r + 1][j][k]);
                    let v = coef(&c, j);
                    assert!(
                        v >= y0.min(y1) - 1e-3 && v <= y0.max(y1) + 1e-3,
                        "g={g} j={j}"
                    );
                }
            }
        }
    }

    #[test]
    fn refuses_bad_input() {
        for r in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            assert!(matches!(
                kalker_coefficients(r, 0.3),
                Err(KalkerError::BadRatio(_))
            ));
        }
        assert!(matches!(
            kalker_coefficients(0.5, 0.6),
            Err(KalkerError::Poisson(_))
        ));
        let lin = CreepForces { fx: 1.0, fy: 0.0 };
        assert!(matches!(
            saturate(lin, 2.5, 1e4),
            Err(KalkerError::Friction(_))
        ));
    }

    /// Kalker's slender-ellipse asymptotes against his own table at its edge g = 0.1 (an
    /// independent check of the transcribed expressions: the asymptotes are the leading
    /// terms in g, the table is his numerical solution): every one of the 18 entries
    /// within 6.5 % (measured 0.07–6.4 %). At ν = 0 longitudinal and lateral creep are the
    /// same problem, C11 = C22, which both asymptotes satisfy exactly.
    #[test]
    fn slender_asymptotes_meet_the_table_edge() {
        for a_gt_b in [false, true] {
            let table = if a_gt_b { &TABLE_A_GT_B } else { &TABLE_A_LE_B };
            for (k, &nu) in NU_KNOTS.iter().enumerate() {
                let c = slender_asymptote(a_gt_b, 0.1, nu);
                for j in 0..3 {
                    let err = (table[0][j][k] / coef(&c, j) - 1.0).abs();
                    assert!(err < 0.065, "a>b={a_gt_b} ν={nu} coef {j}: {err}");
                }
            }
            for g in [1e-4, 1e-2, 0.1] {
                let c = slender_asymptote(a_gt_b, g, 0.0);
                assert!((c.c11 / c.c22 - 1.0).abs() < 1e-14);
            }
        }
    }

    /// Beyond the table: continuous at g = 0.1 (the jump of an abrupt switch would be up
    /// to 6.4 %), Kalker's asymptote in the limit, and the asymptote's trend in between
    /// (monotone: for a ≫ b all three grow as g falls, like 1/(g·ln(16/g²)) and g^{-3/2};
    /// for a ≪ b C23 falls like √g and C11, C22 move to their constant limits).
    #[test]
    fn beyond_the_table_continuous_and_asymptotic() {
        for a_gt_b in [false, true] {
            for nu in [0.0, 0.25, 0.28, 0.5] {
                let ratio = |g: f64| if a_gt_b { 1.0 / g } else { g };
                let at = |g: f64| kalker_coefficients(ratio(g), nu).unwrap();
                let (inside, outside) = (at(0.1), at(0.1 * (1.0 - 1e-9)));
                for j in 0..3 {
                    let jump = (coef(&outside, j) / coef(&inside, j) - 1.0).abs();
                    assert!(jump < 1e-7, "a>b={a_gt_b} ν={nu} coef {j}: jump {jump}");
                }
                let (tiny, asym) = (at(1e-5), slender_asymptote(a_gt_b, 1e-5, nu));
                for j in 0..3 {
                    assert!((coef(&tiny, j) / coef(&asym, j) - 1.0).abs() < 1e-5);
                }
                let mut prev = at(0.1);
                for i in 1..=200 {
                    let g = 0.1 * (1e-4_f64).powf(i as f64 / 200.0);
                    let c = at(g);
                    for j in 0..3 {
                        let (p, v) = (coef(&prev, j), coef(&c, j));
                        if a_gt_b {
                            assert!(v > p, "a>b ν={nu} coef {j} at g={g}");
                        } else if j == 2 {
                            assert!(v < p, "a<b ν={nu} C23 at g={g}");
                        } else {
                            let limit = coef(&slender_asymptote(false, g, nu), j);
                            assert!((v - limit).abs() <= (p - limit).abs() + 1e-12);
                        }
                    }
                    prev = c;
                }
            }
        }
    }

    #[test]
    fn linear_forces_follow_the_coefficients() {
        let c = CreepCoefficients {
            c11: 4.0,
            c22: 3.5,
            c23: 1.5,
        };
        let (g, a, b) = (8.1e10, 6e-3, 4e-3);
        let f = linear_creep_forces(
            g,
            a,
            b,
            &c,
            &Creepages {
                xi_x: 1e-3,
                xi_y: -2e-3,
                spin: 0.5,
            },
        )
        .unwrap();
        // Hand-evaluated: G·a·b = 8.1e10·2.4e-5 = 1.944e6 N; (ab)^{3/2} = 1.1758e-7 m³.
        assert!((f.fx - (-1.944e6 * 4.0 * 1e-3)).abs() < 1e-6);
        let fy = 1.944e6 * 3.5 * 2e-3 - 8.1e10 * 2.4e-5_f64.powf(1.5) * 1.5 * 0.5;
        assert!((f.fy - fy).abs() < 1e-6 * fy.abs());
    }

    #[test]
    fn saturation_limits_continuity_and_monotonicity() {
        let (mu, n) = (0.3, 1e5);
        let mu_n = mu * n;
        // Small creep: the saturated force is the linear one (ε = 1 − u/3 + …).
        let small = CreepForces {
            fx: 1e-3 * mu_n,
            fy: -2e-3 * mu_n,
        };
        let s = saturate(small, mu, n).unwrap();
        assert!((s.fx / small.fx - 1.0).abs() < 1e-3);
        assert!((s.fy / small.fy - 1.0).abs() < 1e-3);
        // Large creep: the resultant tends to μN, direction kept.
        let big = CreepForces {
            fx: 30.0 * mu_n,
            fy: 40.0 * mu_n,
        };
        let s = saturate(big, mu, n).unwrap();
        assert!((s.fx.hypot(s.fy) - mu_n).abs() < 1e-9 * mu_n);
        assert!((s.fy / s.fx - 4.0 / 3.0).abs() < 1e-12);
        // Continuous and monotone along a ray of linear forces, through u = 3.
        let mut prev = 0.0;
        for i in 1..=4000 {
            let f = i as f64 * 1e-3 * mu_n; // u up to 4
            let fs = she_factor(f, mu_n) * f;
            assert!(fs >= prev - 1e-9 * mu_n, "not monotone at u = {}", f / mu_n);
            assert!(fs - prev <= 1e-3 * mu_n + 1e-9, "jump at u = {}", f / mu_n);
            assert!(fs <= mu_n * (1.0 + 1e-12));
            prev = fs;
        }
        let below = she_factor(3.0 * mu_n * (1.0 - 1e-9), mu_n) * 3.0 * mu_n;
        assert!((below - mu_n).abs() < 1e-6 * mu_n);
    }
}

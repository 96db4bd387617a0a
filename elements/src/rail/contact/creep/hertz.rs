//! The Hertz contact ellipse of a wheel on a rail: semi-axes `a` (rolling direction `x`) and
//! `b` (lateral `y`) from the principal curvatures of the two bodies, the normal load and the
//! (common) elastic constants.
//!
//! Derivation (Johnson, *Contact Mechanics*, 1985, §4.2, Eqs. 4.39–4.41; the same relations
//! are tabulated as Hertz's `m`, `n` in Timoshenko & Goodier and in Garg & Dukkipati,
//! *Dynamics of Railway Vehicle Systems*, 1984, ch. 5). The initial gap between the
//! surfaces is `h = A·x² + B·y²` with, for aligned principal planes (wheel and rail axes
//! parallel, no yaw),
//!
//! ```text
//! A = ½·(1/r_w + 1/R_rx),   B = ½·(κ_wy + κ_ry)
//! ```
//!
//! where `r_w` is the wheel rolling radius, `1/R_rx = 0` the rail's longitudinal curvature,
//! `κ_wy` the wheel's transverse profile curvature and `κ_ry` the rail head's transverse
//! curvature (convex positive; a concave wheel throat has `κ_wy < 0`, allowed as long as
//! `B > 0`). Both are positive for contact at a single point. The angle `θ` of the
//! classical tables is `cos θ = |B − A| / (A + B)`.
//!
//! With `e` the eccentricity of the ellipse (major semi-axis `a_M`, minor `b_m`,
//! `b_m/a_M = √(1 − e²)`) and `K(e)`, `E(e)` the complete elliptic integrals of the first
//! and second kind (modulus `e`), Hertz's solution for an ellipse whose major axis lies in
//! the direction of the smaller relative curvature `A_s ≤ B_l` is
//!
//! ```text
//! B_l / A_s = [E(e)/(1 − e²) − K(e)] / [K(e) − E(e)]          (eccentricity equation)
//! A + B     = p0 · E(e) / (E*·b_m)
//! N         = (2/3)·π·a_M·b_m·p0
//! ```
//!
//! Eliminating the peak pressure `p0`:
//! `b_m³ = 3·N·E(e)·√(1 − e²) / (2π·E*·(A + B))`, `a_M = b_m / √(1 − e²)`.
//! In the classical form `a_M = m·Δ^{1/3}`, `b_m = n·Δ^{1/3}` with `Δ = 3N/(4E*(A+B))`,
//! `m = (2E(e)/(π(1 − e²)))^{1/3}` and `n = (2E(e)√(1 − e²)/π)^{1/3}`.
//! For two bodies of the same steel `1/E* = 2(1 − ν²)/E`, so
//! `Δ = 3N(1 − ν²)/(2E(A + B))` (no factor π: the π of the Timoshenko form
//! `3πN(k₁ + k₂)/(4(A + B))` cancels against `k = (1 − ν²)/(πE)`).
//!
//! `K` and `E` come from the arithmetic–geometric mean (Abramowitz & Stegun 17.6); the
//! eccentricity equation is solved for `ln(b_m/a_M)`, on which its left side is monotone, by
//! a bracketed Newton iteration ([`axis_ratio`]).

use thiserror::Error;

/// Why a Hertz ellipse cannot be computed.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum HertzError {
    /// A quantity that must be positive and finite is not.
    #[error("{name} = {value} must be positive and finite; give a {hint}")]
    NotPositive {
        /// The quantity's name.
        name: &'static str,
        /// Its value.
        value: f64,
        /// What to give instead.
        hint: &'static str,
    },
    /// Poisson's ratio outside the physical range of the half-space theory.
    #[error("Poisson's ratio {0} is outside [0, 0.5); give a value such as 0.28 for steel")]
    Poisson(f64),
    /// The curvature sum `A` or `B` is not positive: the surfaces do not touch at one point.
    #[error(
        "relative curvature {name} = {value} 1/m is not positive: the bodies conform (line or \
         area contact), Hertz's point-contact ellipse does not apply; check the profile radii"
    )]
    Conforming {
        /// `A` or `B`.
        name: &'static str,
        /// Its value (1/m).
        value: f64,
    },
    /// The ellipse is more slender than the solver resolves (curvature ratio above 1e12).
    #[error("curvature ratio {0} above 1e12: the contact is a line, not an ellipse")]
    TooSlender(f64),
}

/// The principal curvatures of wheel and rail at the contact point (1/m), axes aligned.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Curvatures {
    /// Wheel rolling radius `r_w` (m): the wheel's longitudinal curvature is `1/r_w`.
    pub wheel_rolling_radius: f64,
    /// Wheel transverse profile curvature `κ_wy` (1/m), convex positive, concave negative.
    pub wheel_transverse: f64,
    /// Rail head transverse curvature `κ_ry` (1/m), convex positive (`1/R` of the crown).
    pub rail_transverse: f64,
}

/// The Hertz contact ellipse.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HertzEllipse {
    /// Relative curvature in the rolling direction `A` (1/m).
    pub a_curv: f64,
    /// Relative curvature in the lateral direction `B` (1/m).
    pub b_curv: f64,
    /// Angle `θ = acos(|B − A|/(A + B))` (rad) of the classical `m, n` tables.
    pub theta: f64,
    /// Eccentricity `e` of the ellipse.
    pub eccentricity: f64,
    /// Hertz coefficient of the major semi-axis `m`.
    pub m: f64,
    /// Hertz coefficient of the minor semi-axis `n`.
    pub n: f64,
    /// Semi-axis in the rolling direction `a` (m).
    pub a: f64,
    /// Lateral semi-axis `b` (m).
    pub b: f64,
    /// Peak pressure `p0 = 3N/(2πab)` (Pa).
    pub p0: f64,
}

impl HertzEllipse {
    /// Semi-axis ratio `a/b` (rolling over lateral).
    pub fn ratio(&self) -> f64 {
        self.a / self.b
    }
}

/// Complete elliptic integrals `(K(k), E(k))` of modulus `k ∈ [0, 1)` by the
/// arithmetic–geometric mean: `K = π/(2·AGM(1, k'))`,
/// `E = K·(1 − Σₙ 2^{n−1}·cₙ²)` with `c₀ = k`, `cₙ₊₁ = (aₙ − bₙ)/2`.
pub fn elliptic_ke(k: f64) -> (f64, f64) {
    let kp = (1.0 - k * k).max(0.0).sqrt();
    let (mut a, mut b) = (1.0_f64, kp);
    let mut c = k;
    let mut sum = 0.5 * c * c; // n = 0 term: 2^{-1}·c₀²
    let mut pow2 = 0.5;
    // Quadratic convergence: stop once the terms are below round-off (a fixed count would
    // multiply the 1-ulp residue of `aₙ − bₙ` by 2ⁿ).
    for _ in 0..64 {
        if c.abs() <= 1e-15 * a {
            break;
        }
        let an = 0.5 * (a + b);
        let bn = (a * b).sqrt();
        c = 0.5 * (a - b);
        a = an;
        b = bn;
        pow2 *= 2.0;
        sum += pow2 * c * c;
    }
    let kk = std::f64::consts::PI / (2.0 * a);
    (kk, kk * (1.0 - sum))
}

/// Left side of the eccentricity equation `B_l/A_s` as a function of the axis ratio
/// `g = b_m/a_M ∈ (0, 1)`, with `e² = 1 − g²`.
#[cfg(test)]
fn curvature_ratio_of_axis_ratio(g: f64) -> f64 {
    let e2 = 1.0 - g * g;
    let (k, e) = elliptic_ke(e2.sqrt());
    (e / (g * g) - k) / (k - e)
}

/// `B_l/A_s` and its derivative with respect to `u = ln g`. With `e² = 1 − g²`,
/// `dE/de = (E − K)/e`, `dK/de = E/(e·g²) − K/e` (Abramowitz & Stegun 17.3.43–44) and
/// `de/dg = −g/e`: `dE/dg = g·D/e²` and `dK/dg = −g·N/e²` for the numerator
/// `N = E/g² − K` and the denominator `D = K − E` of the ratio `R = N/D`, so
/// `dN/dg = D/(g·e²) − 2E/g³ + g·N/e²`, `dD/dg = −g·(N + D)/e²` and
/// `dR/du = g·(N'·D − N·D')/D²`.
fn curvature_ratio_and_slope(g: f64) -> (f64, f64) {
    let e2 = 1.0 - g * g;
    let (k, e) = elliptic_ke(e2.sqrt());
    let (num, den) = (e / (g * g) - k, k - e);
    let dnum = den / (g * e2) - 2.0 * e / (g * g * g) + g * num / e2;
    let dden = -g * (num + den) / e2;
    (num / den, g * (dnum * den - num * dden) / (den * den))
}

/// The axis ratio `g = b_m/a_M ∈ (0, 1]` of the ellipse whose eccentricity equation has the
/// left side `ratio = B_l/A_s ≥ 1`: the root of `R(e^u) = ratio` in `u = ln g ∈ [ln 1e-9,
/// 0]`, on which `R` falls monotonically. Newton on `u`, started from Hertz's slender-ellipse
/// estimate `g ≈ ratio^{−2/3}` and kept inside a bracket that shrinks with the sign of the
/// residual (bisection whenever the Newton step would leave it); it stops when the step or
/// the bracket is below 1e-15 in `u`, the tolerance of the bisection it replaced (which took
/// ~50 evaluations of `K` and `E`; Newton converges quadratically from the estimate).
pub fn axis_ratio(ratio: f64) -> f64 {
    if ratio - 1.0 < 1e-9 {
        return 1.0;
    }
    let (mut lo, mut hi) = ((1e-9_f64).ln(), 0.0_f64);
    let mut u = (-2.0 / 3.0 * ratio.ln()).clamp(lo, hi);
    for _ in 0..200 {
        let g = u.exp();
        if g >= 1.0 {
            hi = u;
            u = 0.5 * (lo + hi);
            continue;
        }
        let (r, slope) = curvature_ratio_and_slope(g);
        let h = r - ratio;
        if h == 0.0 {
            return g;
        }
        // h < 0: the ratio is too small, the ellipse must be more slender (smaller u).
        if h < 0.0 {
            hi = u;
        } else {
            lo = u;
        }
        let newton = u - h / slope;
        let next = if slope < 0.0 && newton > lo && newton < hi {
            newton
        } else {
            0.5 * (lo + hi)
        };
        if (next - u).abs() < 1e-15 || hi - lo < 1e-15 {
            return next.exp();
        }
        u = next;
    }
    u.exp()
}

fn positive(name: &'static str, value: f64, hint: &'static str) -> Result<f64, HertzError> {
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(HertzError::NotPositive { name, value, hint })
    }
}

/// Hertz's contact ellipse of two bodies of the same material (Young's modulus `young`, Pa;
/// Poisson's ratio `poisson`) pressed together by the normal load `normal_load` (N).
pub fn hertz_ellipse(
    curv: &Curvatures,
    normal_load: f64,
    young: f64,
    poisson: f64,
) -> Result<HertzEllipse, HertzError> {
    let r_w = positive(
        "wheel rolling radius",
        curv.wheel_rolling_radius,
        "radius in metres",
    )?;
    let n_load = positive("normal load", normal_load, "compressive load in newtons")?;
    let young = positive("Young's modulus", young, "modulus in pascals")?;
    if !(poisson.is_finite() && (0.0..0.5).contains(&poisson)) {
        return Err(HertzError::Poisson(poisson));
    }
    if !curv.wheel_transverse.is_finite() || !curv.rail_transverse.is_finite() {
        return Err(HertzError::NotPositive {
            name: "transverse curvature",
            value: f64::NAN,
            hint: "finite curvature in 1/m",
        });
    }
    let a_curv = 0.5 * (1.0 / r_w); // rail longitudinal curvature is 0
    let b_curv = 0.5 * (curv.wheel_transverse + curv.rail_transverse);
    if b_curv <= 0.0 {
        return Err(HertzError::Conforming {
            name: "B",
            value: b_curv,
        });
    }
    let sum = a_curv + b_curv;
    let theta = ((b_curv - a_curv).abs() / sum).clamp(0.0, 1.0).acos();
    // Major axis along the direction of the smaller relative curvature.
    let (small, large) = if a_curv <= b_curv {
        (a_curv, b_curv)
    } else {
        (b_curv, a_curv)
    };
    let ratio = large / small;
    if ratio > 1e12 {
        return Err(HertzError::TooSlender(ratio));
    }
    let g = axis_ratio(ratio);
    let ecc = (1.0 - g * g).max(0.0).sqrt();
    let (_, ee) = elliptic_ke(ecc);
    let e_star = young / (2.0 * (1.0 - poisson * poisson));
    let delta = 3.0 * n_load / (4.0 * e_star * sum);
    let pi = std::f64::consts::PI;
    let m = (2.0 * ee / (pi * g * g)).cbrt();
    let n = (2.0 * ee * g / pi).cbrt();
    let major = m * delta.cbrt();
    let minor = n * delta.cbrt();
    let (a, b) = if a_curv <= b_curv {
        (major, minor)
    } else {
        (minor, major)
    };
    Ok(HertzEllipse {
        a_curv,
        b_curv,
        theta,
        eccentricity: ecc,
        m,
        n,
        a,
        b,
        p0: 3.0 * n_load / (2.0 * pi * a * b),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    const E_STEEL: f64 = 2.1e11;
    const NU: f64 = 0.28;

    /// `K(k)`, `E(k)` by composite Gauss–Legendre quadrature in the amplitude φ, a route
    /// independent of the AGM (the integrands are smooth for k < 1).
    fn ke_quadrature(k: f64) -> (f64, f64) {
        let x = [
            -0.906_179_845_938_664,
            -0.538_469_310_105_683,
            0.0,
            0.538_469_310_105_683,
            0.906_179_845_938_664,
        ];
        let w = [
            0.236_926_885_056_189,
            0.478_628_670_499_366,
            0.568_888_888_888_889,
            0.478_628_670_499_366,
            0.236_926_885_056_189,
        ];
        let panels = 400;
        let h = std::f64::consts::FRAC_PI_2 / panels as f64;
        let (mut kk, mut ee) = (0.0, 0.0);
        for p in 0..panels {
            let mid = (p as f64 + 0.5) * h;
            for (xi, wi) in x.iter().zip(w.iter()) {
                let phi = mid + 0.5 * h * xi;
                let d = (1.0 - k * k * phi.sin().powi(2)).sqrt();
                kk += 0.5 * h * wi / d;
                ee += 0.5 * h * wi * d;
            }
        }
        (kk, ee)
    }

    #[test]
    fn elliptic_integrals_match_quadrature_and_known_values() {
        let pi = std::f64::consts::PI;
        let (k0, e0) = elliptic_ke(0.0);
        assert!((k0 - pi / 2.0).abs() < 1e-15 && (e0 - pi / 2.0).abs() < 1e-15);
        for &k in &[0.1, 0.5, 0.8, 0.95, 0.99] {
            let (ka, ea) = elliptic_ke(k);
            let (kq, eq) = ke_quadrature(k);
            assert!((ka - kq).abs() < 1e-10 * kq, "K({k}): {ka} vs {kq}");
            assert!((ea - eq).abs() < 1e-10 * eq, "E({k}): {ea} vs {eq}");
        }
        // Legendre's relation E K' + E' K − K K' = π/2 at k = k' = 1/√2.
        let (k, e) = elliptic_ke(std::f64::consts::FRAC_1_SQRT_2);
        assert!((2.0 * e * k - k * k - pi / 2.0).abs() < 1e-13);
    }

    #[test]
    fn sphere_on_plane_is_the_closed_form_circle() {
        // A ball of radius R (wheel longitudinal and transverse curvature 1/R) on a flat rail:
        // a = b = (3NR/(4E*))^{1/3} with 1/E* = 2(1 − ν²)/E, i.e. (3NR(1 − ν²)/(2E))^{1/3}.
        let r = 0.45;
        let n = 80e3;
        let c = Curvatures {
            wheel_rolling_radius: r,
            wheel_transverse: 1.0 / r,
            rail_transverse: 0.0,
        };
        let h = hertz_ellipse(&c, n, E_STEEL, NU).unwrap();
        let exact = (3.0 * n * r * (1.0 - NU * NU) / (2.0 * E_STEEL)).cbrt();
        assert!((h.a - exact).abs() < 1e-12 * exact, "{} vs {exact}", h.a);
        assert!((h.b - exact).abs() < 1e-12 * exact);
        assert!(h.eccentricity < 1e-6);
        assert!((h.theta - std::f64::consts::FRAC_PI_2).abs() < 1e-12);
        // Peak pressure of the circle: p0 = (6 N E*² / (π³ R²))^{1/3}.
        let e_star = E_STEEL / (2.0 * (1.0 - NU * NU));
        let p0 = (6.0 * n * e_star * e_star / (std::f64::consts::PI.powi(3) * r * r)).cbrt();
        assert!((h.p0 - p0).abs() < 1e-10 * p0);
    }

    #[test]
    fn swapping_the_curvatures_swaps_the_axes() {
        // A = ½/r_w; B = ½(κ_w + κ_r). Choose pairs with (A, B) exchanged.
        let n = 60e3;
        let c1 = Curvatures {
            wheel_rolling_radius: 0.5, // A = 1.0
            wheel_transverse: 0.0,
            rail_transverse: 1.0 / 0.3, // B = 1.6667
        };
        let c2 = Curvatures {
            wheel_rolling_radius: 0.3, // A = 1.6667
            wheel_transverse: 0.0,
            rail_transverse: 2.0, // B = 1.0
        };
        let h1 = hertz_ellipse(&c1, n, E_STEEL, NU).unwrap();
        let h2 = hertz_ellipse(&c2, n, E_STEEL, NU).unwrap();
        assert!((h1.a - h2.b).abs() < 1e-12 * h1.a);
        assert!((h1.b - h2.a).abs() < 1e-12 * h1.b);
        assert!(h1.a > h1.b, "major axis along the smaller curvature");
        assert!((h1.theta - h2.theta).abs() < 1e-14);
        // Scaling: a, b ∝ N^{1/3}.
        let h8 = hertz_ellipse(&c1, 8.0 * n, E_STEEL, NU).unwrap();
        assert!((h8.a - 2.0 * h1.a).abs() < 1e-12 * h1.a);
        assert!((h8.b - 2.0 * h1.b).abs() < 1e-12 * h1.b);
    }

    #[test]
    fn axis_ratio_solves_the_eccentricity_equation_found_by_bisection_on_e() {
        // Independent solution: bisection on e of
        // (B/A)(K − E) = E/(1 − e²) − K, with K, E by quadrature.
        let n = 70e3;
        for &rail_r in &[0.08, 0.2, 0.3, 0.6, 2.0, 10.0] {
            let c = Curvatures {
                wheel_rolling_radius: 0.46,
                wheel_transverse: 0.0,
                rail_transverse: 1.0 / rail_r,
            };
            let a_c = 0.5 / 0.46;
            let b_c = 0.5 / rail_r;
            let (small, large) = if a_c < b_c { (a_c, b_c) } else { (b_c, a_c) };
            let ratio = large / small;
            let f = |e: f64| {
                let (k, ee) = ke_quadrature(e);
                ee / (1.0 - e * e) - k - ratio * (k - ee)
            };
            let (mut lo, mut hi) = (1e-6, 0.999_999_9);
            assert!(f(lo) < 0.0 && f(hi) > 0.0);
            for _ in 0..100 {
                let mid = 0.5 * (lo + hi);
                if f(mid) > 0.0 {
                    hi = mid
                } else {
                    lo = mid
                }
            }
            let e_ref = 0.5 * (lo + hi);
            let g_ref = (1.0 - e_ref * e_ref).sqrt(); // minor/major
            let h = hertz_ellipse(&c, n, E_STEEL, NU).unwrap();
            let g = h.a.min(h.b) / h.a.max(h.b);
            assert!(
                (g - g_ref).abs() < 1e-8 * g_ref,
                "rail radius {rail_r}: b/a {g} vs {g_ref}"
            );
            // The load balance N = (2/3)π a b p0 with p0 = (A+B) b_m E*/E(e).
            let e_star = E_STEEL / (2.0 * (1.0 - NU * NU));
            let (_, ee) = ke_quadrature(e_ref);
            let p0 = (a_c + b_c) * h.a.min(h.b) * e_star / ee;
            let load = 2.0 / 3.0 * std::f64::consts::PI * h.a * h.b * p0;
            assert!((load - n).abs() < 1e-7 * n, "load {load} vs {n}");
        }
    }

    /// The Newton solution of the eccentricity equation is the bisection's (the solver it
    /// replaced, kept here as the reference) to round-off, from a nearly round ellipse to
    /// one of ratio 1e-8, and its slope is the finite difference of the ratio. Near a
    /// circle the equation itself is ill-conditioned: `R − 1 ≈ (3/2)(1 − g)` is a
    /// difference of `K` and `E` that cancel to `e²`, so `R` carries an absolute error
    /// of ~1e-16/e² and both solvers find `g` only to ~1e-16/(R − 1); that is the bound
    /// there, 1e-11 elsewhere.
    #[test]
    fn axis_ratio_equals_the_bisection_it_replaced() {
        let bisection = |ratio: f64| {
            let (mut lo, mut hi) = ((1e-9_f64).ln(), 0.0_f64);
            for _ in 0..200 {
                let mid = 0.5 * (lo + hi);
                let g = mid.exp();
                if g >= 1.0 || curvature_ratio_of_axis_ratio(g) < ratio {
                    hi = mid;
                } else {
                    lo = mid;
                }
                if hi - lo < 1e-15 {
                    break;
                }
            }
            (0.5 * (lo + hi)).exp()
        };
        for i in 0..=400 {
            // 1 + 1e-8 … 1e11, log-spaced.
            let excess = 10f64.powf(-8.0 + 19.0 * i as f64 / 400.0);
            let ratio = 1.0 + excess;
            let (g, g_ref) = (axis_ratio(ratio), bisection(ratio));
            let bound = 1e-11 + 1e-15 / excess;
            assert!(
                (g - g_ref).abs() <= bound * g_ref,
                "ratio {ratio:e}: {g} vs {g_ref}"
            );
        }
        for g in [0.01, 0.1, 0.3, 0.5, 0.8, 0.95] {
            let (_, slope) = curvature_ratio_and_slope(g);
            let hu = 1e-6_f64;
            let fd = (curvature_ratio_of_axis_ratio(g * hu.exp())
                - curvature_ratio_of_axis_ratio(g * (-hu).exp()))
                / (2.0 * hu);
            assert!(
                (slope - fd).abs() < 1e-6 * fd.abs(),
                "g {g}: {slope} vs {fd}"
            );
        }
    }

    #[test]
    fn refuses_conforming_or_unphysical_input() {
        let ok = Curvatures {
            wheel_rolling_radius: 0.46,
            wheel_transverse: 0.0,
            rail_transverse: 1.0 / 0.3,
        };
        assert!(matches!(
            hertz_ellipse(&ok, -1.0, E_STEEL, NU),
            Err(HertzError::NotPositive { .. })
        ));
        assert!(matches!(
            hertz_ellipse(&ok, 1e4, E_STEEL, 0.5),
            Err(HertzError::Poisson(_))
        ));
        let conform = Curvatures {
            wheel_transverse: -1.0 / 0.29,
            ..ok
        };
        assert!(matches!(
            hertz_ellipse(&conform, 1e4, E_STEEL, NU),
            Err(HertzError::Conforming { .. })
        ));
    }
}

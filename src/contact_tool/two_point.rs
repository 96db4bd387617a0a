//! Two-point contact of one wheel: the tread and the flange root (or any two separate
//! zones of the profiles) touching the rail at once, the wheel load shared by the two
//! patches as by two Hertz springs in parallel under the same vertical approach of the
//! wheel.
//!
//! # The springs
//!
//! Hertz's approach of two bodies pressed together by `N` is
//! `d = b·p0·K(e)/E*` (Johnson, *Contact Mechanics*, 1985, Eq. 4.41 and §4.2: `b` the minor
//! semi-axis, `p0` the peak pressure, `K(e)` the complete elliptic integral of the first
//! kind of the eccentricity, `1/E* = 2(1 − ν²)/E` for two bodies of one steel). With
//! `b ∝ N^{1/3}` and `p0 ∝ N^{1/3}`, `d ∝ N^{2/3}`: `N = N_ref·(d/d_ref)^{3/2}` from one
//! ellipse at a reference load. A rigid vertical approach `d_v` of the wheel closes the
//! vertical gap `g` of a patch and presses it along its normal by `(d_v − g)·cos δ`
//! (`δ` its contact angle), so
//!
//! ```text
//! N_i(d_v) = N_ref,i·(max(0, d_v − g_i)·cos δ_i / d_ref,i)^{3/2}
//! ```
//!
//! and the vertical balance of the wheel, as for one patch ([`super::balance`]), is
//! `Σ_i [N_i cos δ_i + s·Fy_i(N_i)·sin δ_i] = Q` (`s` = +1 left, −1 right). It is solved for
//! `d_v` by bisection (its left side grows with `d_v` unless a creep force pulls the wheel
//! down a steep flange, the case where [`share`] returns `None`). A second point whose gap
//! exceeds the approach carries nothing: `N_2 = 0`, one patch.

use crate::elements::rail::contact::creep::hertz::{elliptic_ke, HertzEllipse};

/// Bisection steps of [`share`] at most.
const STEPS: usize = 200;
/// Doublings of the upper end of the approach's bracket at most.
const DOUBLINGS: usize = 60;

/// One patch as a Hertz spring.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Spring {
    /// Contact angle δ (rad).
    pub delta: f64,
    /// Vertical gap while the wheel is unloaded (m).
    pub gap: f64,
    /// Reference normal load (N).
    pub n_ref: f64,
    /// Hertz's approach at the reference load (m).
    pub approach_ref: f64,
}

impl Spring {
    /// The spring of a patch with Hertz ellipse `h` at load `n_ref`.
    pub fn new(
        delta: f64,
        gap: f64,
        n_ref: f64,
        h: &HertzEllipse,
        young: f64,
        poisson: f64,
    ) -> Self {
        Spring {
            delta,
            gap,
            n_ref,
            approach_ref: hertz_approach(h, young, poisson),
        }
    }

    /// Normal load (N) at the wheel's vertical approach `d_v` (m).
    pub fn normal(&self, d_v: f64) -> f64 {
        let d = (d_v - self.gap).max(0.0) * self.delta.cos();
        self.n_ref * (d / self.approach_ref).powf(1.5)
    }
}

/// Hertz's approach `d = b·p0·K(e)/E*` (m) of the ellipse `h` (module doc).
pub fn hertz_approach(h: &HertzEllipse, young: f64, poisson: f64) -> f64 {
    let e_star = young / (2.0 * (1.0 - poisson * poisson));
    let (k, _) = elliptic_ke(h.eccentricity);
    h.a.min(h.b) * h.p0 * k / e_star
}

/// The normal loads `[N_1, N_2]` (N) of two patches of a wheel on side `side` under the
/// vertical load `q` (N), `fy(i, N)` the lateral creep force of patch `i` at normal load
/// `N` (0 without creep); `None` where no approach balances `q`.
pub fn share(
    q: f64,
    side: f64,
    springs: &[Spring; 2],
    fy: impl Fn(usize, f64) -> f64,
) -> Option<[f64; 2]> {
    let loads = |d_v: f64| springs.map(|s| s.normal(d_v));
    let excess = |d_v: f64| {
        let n = loads(d_v);
        (0..2)
            .map(|i| {
                let (c, s) = (springs[i].delta.cos(), springs[i].delta.sin());
                n[i] * c + side * fy(i, n[i]) * s
            })
            .sum::<f64>()
            - q
    };
    let gap = springs[0].gap.min(springs[1].gap);
    let mut hi = gap + springs[0].approach_ref + springs[1].approach_ref;
    let mut lo = gap;
    let mut doublings = 0;
    while excess(hi) < 0.0 {
        lo = hi;
        hi = gap + 2.0 * (hi - gap);
        doublings += 1;
        if doublings > DOUBLINGS {
            return None;
        }
    }
    for _ in 0..STEPS {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            break;
        }
        if excess(mid) < 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    Some(loads(0.5 * (lo + hi)))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A sphere of radius `R` on a plane: `d = a²/R` with `a = (3NR/(4E*))^{1/3}` (Hertz).
    #[test]
    fn approach_of_a_sphere_on_a_plane() {
        use crate::elements::rail::contact::creep::hertz::{hertz_ellipse, Curvatures};
        let (r, n, e, nu) = (0.3, 5e4, 2.1e11, 0.28);
        let c = Curvatures {
            wheel_rolling_radius: r,
            wheel_transverse: 1.0 / r,
            rail_transverse: 0.0,
        };
        let h = hertz_ellipse(&c, n, e, nu).unwrap();
        let e_star = e / (2.0 * (1.0 - nu * nu));
        let a = (3.0 * n * r / (4.0 * e_star)).cbrt();
        let d = hertz_approach(&h, e, nu);
        assert!((d / (a * a / r) - 1.0).abs() < 1e-9, "{d} vs {}", a * a / r);
    }

    /// Two equal springs at equal gaps share the load equally; a second spring whose gap
    /// exceeds the approach carries nothing.
    #[test]
    fn equal_springs_share_equally_and_a_far_one_carries_nothing() {
        let s = Spring {
            delta: 0.1,
            gap: 0.0,
            n_ref: 1e4,
            approach_ref: 5e-5,
        };
        let n = share(2e4, 1.0, &[s, s], |_, _| 0.0).unwrap();
        assert!((n[0] / n[1] - 1.0).abs() < 1e-12);
        assert!(((n[0] + n[1]) * 0.1f64.cos() / 2e4 - 1.0).abs() < 1e-12);
        let far = Spring { gap: 1e-3, ..s };
        let n = share(2e4, 1.0, &[s, far], |_, _| 0.0).unwrap();
        assert_eq!(n[1], 0.0);
    }
}

//! The normal load of one wheel from its vertical load: the vertical balance of the normal
//! force and the lateral creep force, both acting on the wheel in the inclined contact
//! plane.
//!
//! # The balance
//!
//! The rail pushes on the wheel with the normal force `N` along the contact normal and with
//! the creep forces `Fx` (horizontal, along the track) and `Fy` (in the contact plane,
//! across the track). In the track frame (`y` to the left, `z` up) the contact normal of the
//! left wheel at contact angle `δ` is `n = (0, −sin δ, cos δ)` and its lateral axis in the
//! contact plane `t = (0, cos δ, sin δ)`; the right wheel is the mirror image,
//! `n = (0, sin δ, cos δ)`, `t = (0, cos δ, −sin δ)` (`Fy` positive to the left on both
//! wheels, as the creep laws give it). The vertical components carry the wheel load `Q`:
//!
//! ```text
//! g(N) = N·cos δ + s·Fy(N)·sin δ − Q = 0,     s = +1 left, −1 right
//! ```
//!
//! (CONTACT's `Fz = Fn cos δ − Fs sin δ` in its own frame, where `Fs` is the force on the
//! rail.) `Fy` depends on `N` through the traction bound `μN` and through the Hertz patch,
//! whose semi-axes grow as `N^{1/3}`; the laws give `∂Fy/∂N` exactly (dual numbers,
//! `creep::law`), so `g` is solved by Newton's method from `N = Q/cos δ`, safeguarded by a
//! bracket `[0, N_hi]` on which `g` changes sign: a step that leaves the bracket is replaced
//! by bisection. `g(0) = −Q < 0`; `N_hi` is found by doubling. If `g` stays negative the
//! creep force pulls the wheel down its flange faster than the normal force can lift it
//! (`μ·tan δ > 1` with `Fy` against the normal's lateral push): there is no balance and
//! [`normal_load`] returns `None`.

/// Newton/bisection steps of [`normal_load`] at most.
pub const MAX_STEPS: usize = 100;
/// Relative tolerance on the balance `|g| ≤ TOL·Q`.
pub const TOL: f64 = 1e-12;
/// Doublings of the upper end of the bracket at most (`N_hi ≤ 2^40·Q/cos δ`).
const MAX_DOUBLINGS: usize = 40;

/// The normal load `N` (N) that balances the vertical load `q` (N) of a wheel at contact
/// angle `delta` (rad) on side `side` (+1 left, −1 right), with `fy(N) = (Fy, ∂Fy/∂N)` the
/// lateral creep force of the law on the wheel at that normal load (module doc); `None`
/// where no `N` balances `q`.
pub fn normal_load(q: f64, delta: f64, side: f64, fy: impl Fn(f64) -> (f64, f64)) -> Option<f64> {
    let (c, s) = (delta.cos(), side * delta.sin());
    let g = |n: f64| {
        let (f, df) = fy(n);
        (n * c + s * f - q, c + s * df)
    };
    let (mut lo, mut hi) = (0.0, q / c.max(1e-3));
    let mut doublings = 0;
    while g(hi).0 < 0.0 {
        lo = hi;
        hi *= 2.0;
        doublings += 1;
        if doublings > MAX_DOUBLINGS {
            return None;
        }
    }
    let mut n = (q / c.max(1e-3)).clamp(lo, hi);
    for _ in 0..MAX_STEPS {
        let (v, dv) = g(n);
        if v.abs() <= TOL * q {
            return Some(n);
        }
        if v < 0.0 {
            lo = n;
        } else {
            hi = n;
        }
        let newton = n - v / dv;
        n = if dv > 0.0 && newton > lo && newton < hi {
            newton
        } else {
            0.5 * (lo + hi)
        };
        if hi - lo <= TOL * hi {
            return Some(n);
        }
    }
    let v = g(n).0;
    (v.abs() <= 1e-9 * q).then_some(n)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A creep force saturated along the lateral axis, `Fy = k·μN` (`k = ±1`), makes the
    /// balance linear: `N = Q/(cos δ + s·k·μ·sin δ)`.
    #[test]
    fn saturated_creep_force_gives_the_closed_form() {
        let (q, mu) = (10e3, 0.3);
        for (delta, side, k) in [(1.16, 1.0, 1.0), (1.16, -1.0, -1.0), (0.02, -1.0, 1.0)] {
            let n = normal_load(q, delta, side, |n| (k * mu * n, k * mu)).unwrap();
            let exact = q / (delta.cos() + side * k * mu * delta.sin());
            assert!((n / exact - 1.0).abs() < 1e-12, "{n} vs {exact}");
        }
    }

    /// Steep flange, creep force against the normal's lift with `μ·tan δ > 1`: no balance.
    #[test]
    fn no_balance_beyond_the_flange_limit() {
        let f = |n: f64| (-0.5 * n, -0.5);
        assert!(normal_load(10e3, 1.3, 1.0, f).is_none());
    }
}

//! The vertical wheel–rail spring `k2 = a + b·f2^c` (the paper's Eq. 15): the local
//! flexibility of wheel and rail, a power law fitted to 3-D contact analyses (Hertz theory
//! gives `a = 0`, `c = 1/3`).
//!
//! Eq. 15 gives the tangent stiffness as a function of the force; the force for a given
//! approach δ follows by integrating `dδ = df / k2(f)`:
//! `δ(f) = ∫₀^f dx / (a + b·x^c)`. For `a = 0` this is `δ = f^{1−c} / (b·(1−c))`, i.e.
//! `f = (b·(1−c)·δ)^{1/(1−c)}` (Hertz: `f ∝ δ^{3/2}`). In general the integral is
//! evaluated by Gauss–Legendre quadrature on graded panels after the substitution
//! `x = f·r^{1/c}`, which makes the integrand smooth (rational when `1/c` is an integer), and `f(δ)` is
//! found by safeguarded Newton. In tension (`δ < 0`, the wheel lifting off its seat) the
//! spring is linear with stiffness `a`, so `a > 0` keeps a lifted wheel's node B
//! restrained.

use serde::{Deserialize, Serialize};

/// The power-law spring of Eq. 15.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct HertzSpring {
    /// Constant part `a` (N/m), > 0.
    pub a: f64,
    /// Coefficient `b` (N^{1−c}/m).
    pub b: f64,
    /// Exponent `c` (−), `0 ≤ c < 1`.
    pub c: f64,
}

// 8-point Gauss–Legendre on [0, 1] (nodes and weights to 17 digits).
#[allow(clippy::excessive_precision)]
const GL_X: [f64; 8] = [
    0.019_855_071_751_231_856,
    0.101_666_761_293_186_63,
    0.237_233_795_041_835_5,
    0.408_282_678_752_175_1,
    0.591_717_321_247_824_9,
    0.762_766_204_958_164_5,
    0.898_333_238_706_813_4,
    0.980_144_928_248_768_2,
];
#[allow(clippy::excessive_precision)]
const GL_W: [f64; 8] = [
    0.050_614_268_145_188_13,
    0.111_190_517_226_687_24,
    0.156_853_322_938_943_64,
    0.181_341_891_689_180_99,
    0.181_341_891_689_180_99,
    0.156_853_322_938_943_64,
    0.111_190_517_226_687_24,
    0.050_614_268_145_188_13,
];

impl HertzSpring {
    /// Tangent stiffness at compressive force `f ≥ 0` (N/m): `a + b·f^c`.
    pub fn stiffness_at(&self, f: f64) -> f64 {
        self.a + self.b * f.max(0.0).powf(self.c)
    }

    /// Approach δ (m) at compressive force `f ≥ 0`.
    pub fn approach(&self, f: f64) -> f64 {
        if f <= 0.0 {
            return f / self.a;
        }
        if self.a == 0.0 {
            return f.powf(1.0 - self.c) / (self.b * (1.0 - self.c));
        }
        if self.c == 0.0 {
            return f / (self.a + self.b);
        }
        // x = f·r^m with m = 1/c: dx = f·m·r^{m−1} dr and b·x^c = b·f^c·r, so the integrand
        // f·m·r^{m−1}/(a + b·f^c·r) is smooth (rational for 1/c integer). Graded panels
        // resolve the scale r ~ a/(b·f^c) where the two parts of the stiffness cross.
        let m = 1.0 / self.c;
        let bf = self.b * f.powf(self.c);
        let panels = [0.0, 1e-3, 1e-2, 0.1, 0.4, 1.0];
        let mut sum = 0.0;
        for w in panels.windows(2) {
            let (r0, r1) = (w[0], w[1]);
            for (x, wt) in GL_X.iter().zip(GL_W) {
                let r = r0 + (r1 - r0) * x;
                sum += wt * (r1 - r0) * f * m * r.powf(m - 1.0) / (self.a + bf * r);
            }
        }
        sum
    }

    /// Force (N, compressive positive) and tangent stiffness (N/m) at approach `delta` (m).
    pub fn force(&self, delta: f64) -> (f64, f64) {
        if delta <= 0.0 {
            return (self.a * delta, self.a);
        }
        if self.a == 0.0 {
            let f = (self.b * (1.0 - self.c) * delta).powf(1.0 / (1.0 - self.c));
            return (f, self.stiffness_at(f));
        }
        // Bracket: the spring is stiffer than each of its parts, so f is at least both the
        // linear (a·δ) and the Hertz force; grow an upper bound until it overshoots.
        let hertz = if self.b > 0.0 {
            (self.b * (1.0 - self.c) * delta).powf(1.0 / (1.0 - self.c))
        } else {
            0.0
        };
        let mut lo = (self.a * delta).max(hertz);
        let mut hi = 2.0 * lo;
        while self.approach(hi) < delta {
            lo = hi;
            hi *= 2.0;
        }
        let mut f = lo;
        for _ in 0..60 {
            let r = self.approach(f) - delta;
            if r > 0.0 {
                hi = f;
            } else {
                lo = f;
            }
            let k = self.stiffness_at(f);
            let mut next = f - r * k;
            if !(next > lo && next < hi) {
                next = 0.5 * (lo + hi);
            }
            if (next - f).abs() <= 1e-14 * next.abs().max(1e-300) {
                f = next;
                break;
            }
            f = next;
        }
        (f, self.stiffness_at(f))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// With `a = 0` the law is Hertz's `f = (b(1−c)δ)^{1/(1−c)}`; the spec's example
    /// `b = 3.03e7`, `c = 1/3` gives `k2 ≈ 1.24e9 N/m` at 68.7 kN.
    #[test]
    fn hertz_closed_form() {
        let s = HertzSpring {
            a: 0.0,
            b: 3.03e7,
            c: 1.0 / 3.0,
        };
        let k = s.stiffness_at(68.7e3);
        assert!((k - 1.241e9).abs() / 1.241e9 < 2e-3, "{k}");
        let d = s.approach(68.7e3);
        let (f, kk) = s.force(d);
        assert!((f - 68.7e3).abs() < 1e-6);
        assert!((kk - k).abs() / k < 1e-12);
    }

    /// General `a > 0`: `force` inverts `approach`, and its tangent is `df/dδ`
    /// (central differences) — the law the element uses is self-consistent.
    #[test]
    fn general_law_inverts_and_differentiates() {
        let s = HertzSpring {
            a: 1e7,
            b: 3.03e7,
            c: 1.0 / 3.0,
        };
        for f in [10.0, 1e3, 5e4, 2e5] {
            let d = s.approach(f);
            let (ff, k) = s.force(d);
            assert!((ff - f).abs() / f < 1e-10, "{ff} vs {f}");
            let h = d * 1e-6;
            let fd = (s.force(d + h).0 - s.force(d - h).0) / (2.0 * h);
            assert!((fd - k).abs() / k < 1e-6, "{fd} vs {k}");
        }
        // Quadrature vs the exact integral for c = 1 is not smooth-free; check c = 0.5,
        // a = b: δ(f) = ∫ dx/(a(1+√x)) = (2/a)(√f − ln(1+√f)).
        let s = HertzSpring {
            a: 2.0,
            b: 2.0,
            c: 0.5,
        };
        let f: f64 = 9.0;
        let exact = (2.0 / 2.0) * (f.sqrt() - (1.0 + f.sqrt()).ln());
        assert!((s.approach(f) - exact).abs() / exact < 1e-9);
        // Tension: linear with a.
        assert_eq!(s.force(-0.5), (-1.0, 2.0));
    }
}

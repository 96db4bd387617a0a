//! Forward-mode dual numbers with four partial derivatives, so that each tangential law is
//! written once and its exact gradient with respect to `(ξx, ξy, φ, N)` comes with it. The
//! creep laws are closed-form compositions of `+ − × ÷`, `sqrt`, `exp`, `atan` and powers,
//! and every rule below is the ordinary chain rule: `d(f∘g) = f'(g)·dg`.

use std::ops::{Add, Div, Mul, Neg, Sub};

/// A value and its partial derivatives with respect to four inputs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct D4 {
    /// The value.
    pub v: f64,
    /// `∂v/∂input_i`.
    pub d: [f64; 4],
}

impl D4 {
    /// A constant (zero gradient).
    pub fn c(v: f64) -> D4 {
        D4 { v, d: [0.0; 4] }
    }

    /// Input number `i` with value `v` (unit gradient along `i`).
    pub fn var(v: f64, i: usize) -> D4 {
        let mut d = [0.0; 4];
        d[i] = 1.0;
        D4 { v, d }
    }

    fn chain(self, v: f64, slope: f64) -> D4 {
        D4 {
            v,
            d: self.d.map(|x| x * slope),
        }
    }

    /// Square root; the gradient at 0 is set to 0 (callers guard that point).
    pub fn sqrt(self) -> D4 {
        let r = self.v.sqrt();
        self.chain(r, if r > 0.0 { 0.5 / r } else { 0.0 })
    }

    /// `e^x`.
    pub fn exp(self) -> D4 {
        let e = self.v.exp();
        self.chain(e, e)
    }

    /// `atan x`.
    pub fn atan(self) -> D4 {
        self.chain(self.v.atan(), 1.0 / (1.0 + self.v * self.v))
    }

    /// `∛x`, `x > 0` (the libm cube root: cheaper than `powf(1/3)`).
    pub fn cbrt(self) -> D4 {
        let y = self.v.cbrt();
        self.chain(y, y / (3.0 * self.v))
    }

    /// `x^p` for a constant `p`, `x > 0`.
    pub fn powf(self, p: f64) -> D4 {
        let y = self.v.powf(p);
        self.chain(y, p * y / self.v)
    }

    /// `|x|`; the gradient at 0 is that of `+x` (callers multiply it by a factor that
    /// vanishes there).
    pub fn abs(self) -> D4 {
        if self.v < 0.0 {
            -self
        } else {
            self
        }
    }

    /// `x · k` for a constant `k`.
    pub fn scale(self, k: f64) -> D4 {
        self.chain(self.v * k, k)
    }
}

impl Add for D4 {
    type Output = D4;
    fn add(self, o: D4) -> D4 {
        D4 {
            v: self.v + o.v,
            d: std::array::from_fn(|i| self.d[i] + o.d[i]),
        }
    }
}

impl Sub for D4 {
    type Output = D4;
    fn sub(self, o: D4) -> D4 {
        D4 {
            v: self.v - o.v,
            d: std::array::from_fn(|i| self.d[i] - o.d[i]),
        }
    }
}

impl Mul for D4 {
    type Output = D4;
    // The product rule: d(xy) = y·dx + x·dy.
    #[allow(clippy::suspicious_arithmetic_impl)]
    fn mul(self, o: D4) -> D4 {
        D4 {
            v: self.v * o.v,
            d: std::array::from_fn(|i| self.d[i] * o.v + self.v * o.d[i]),
        }
    }
}

impl Div for D4 {
    type Output = D4;
    // The quotient rule: d(x/y) = (dx − (x/y)·dy)/y.
    #[allow(clippy::suspicious_arithmetic_impl)]
    fn div(self, o: D4) -> D4 {
        let q = self.v / o.v;
        D4 {
            v: q,
            d: std::array::from_fn(|i| (self.d[i] - q * o.d[i]) / o.v),
        }
    }
}

impl Neg for D4 {
    type Output = D4;
    fn neg(self) -> D4 {
        self.scale(-1.0)
    }
}

impl Add<f64> for D4 {
    type Output = D4;
    fn add(self, o: f64) -> D4 {
        D4 {
            v: self.v + o,
            ..self
        }
    }
}

impl Sub<f64> for D4 {
    type Output = D4;
    fn sub(self, o: f64) -> D4 {
        self + (-o)
    }
}

impl Mul<f64> for D4 {
    type Output = D4;
    fn mul(self, k: f64) -> D4 {
        self.scale(k)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every rule against a central difference of the same composition.
    #[test]
    fn gradients_match_central_differences() {
        let f = |x: [f64; 4]| -> D4 {
            let a = D4::var(x[0], 0);
            let b = D4::var(x[1], 1);
            let c = D4::var(x[2], 2);
            let n = D4::var(x[3], 3);
            let s = (a * a + b * b).sqrt();
            ((s * c).atan() + (-n).exp() * 2.0) / (n.powf(1.0 / 3.0) + n.cbrt() + 1.0) - a * b
                + (b - 0.2).abs()
                + (a - 0.1).abs()
        };
        let x0 = [0.3, -0.7, 1.9, 0.8];
        let y = f(x0);
        for i in 0..4 {
            let h = 1e-6;
            let mut p = x0;
            p[i] += h;
            let mut m = x0;
            m[i] -= h;
            let fd = (f(p).v - f(m).v) / (2.0 * h);
            assert!((fd - y.d[i]).abs() < 1e-8, "input {i}: {fd} vs {}", y.d[i]);
        }
    }
}

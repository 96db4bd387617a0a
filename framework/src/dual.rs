//! Forward-mode dual numbers and small 3-D algebra generic over the scalar, so one routine
//! gives a value (with `f64`) and its exact directional derivative (with [`Dual`], seeded
//! with one direction): the corotational beam's force and tangent columns are written this
//! way, and [`crate::rotation`]'s logarithm and inverse Jacobian are the `f64` instances of
//! [`log`] and [`inv_jacobian_times`].
//!
//! A dual number `a + b·ε` with `ε² = 0` carries a value and a directional derivative;
//! every operation applies the chain rule to the second part, so evaluating a function at
//! `x + ε·e` returns `f(x) + ε·∇f(x)·e` to machine precision (no step, no truncation error).
//! Branches (the small-angle series, Shepperd's pivot) are taken on the value part.

use std::ops::{Add, Div, Mul, Neg, Sub};

/// The scalar operations the corotational kinematics need.
pub trait Scalar:
    Copy
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
{
    /// A constant.
    fn c(x: f64) -> Self;
    /// The value part.
    fn re(self) -> f64;
    /// Square root.
    fn sqrt(self) -> Self;
    /// Sine.
    fn sin(self) -> Self;
    /// Cosine.
    fn cos(self) -> Self;
    /// `atan2(self, x)`.
    fn atan2(self, x: Self) -> Self;
}

impl Scalar for f64 {
    fn c(x: f64) -> Self {
        x
    }
    fn re(self) -> f64 {
        self
    }
    fn sqrt(self) -> Self {
        f64::sqrt(self)
    }
    fn sin(self) -> Self {
        f64::sin(self)
    }
    fn cos(self) -> Self {
        f64::cos(self)
    }
    fn atan2(self, x: Self) -> Self {
        f64::atan2(self, x)
    }
}

/// A dual number `v + d·ε`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Dual {
    /// Value.
    pub v: f64,
    /// Directional derivative.
    pub d: f64,
}

impl Dual {
    /// `v + d·ε`.
    pub fn new(v: f64, d: f64) -> Self {
        Dual { v, d }
    }
}

impl Add for Dual {
    type Output = Dual;
    fn add(self, o: Dual) -> Dual {
        Dual::new(self.v + o.v, self.d + o.d)
    }
}
impl Sub for Dual {
    type Output = Dual;
    fn sub(self, o: Dual) -> Dual {
        Dual::new(self.v - o.v, self.d - o.d)
    }
}
impl Mul for Dual {
    type Output = Dual;
    fn mul(self, o: Dual) -> Dual {
        Dual::new(self.v * o.v, self.d * o.v + self.v * o.d)
    }
}
impl Div for Dual {
    type Output = Dual;
    fn div(self, o: Dual) -> Dual {
        Dual::new(self.v / o.v, (self.d * o.v - self.v * o.d) / (o.v * o.v))
    }
}
impl Neg for Dual {
    type Output = Dual;
    fn neg(self) -> Dual {
        Dual::new(-self.v, -self.d)
    }
}

impl Scalar for Dual {
    fn c(x: f64) -> Self {
        Dual::new(x, 0.0)
    }
    fn re(self) -> f64 {
        self.v
    }
    fn sqrt(self) -> Self {
        let s = self.v.sqrt();
        Dual::new(s, self.d / (2.0 * s))
    }
    fn sin(self) -> Self {
        Dual::new(self.v.sin(), self.d * self.v.cos())
    }
    fn cos(self) -> Self {
        Dual::new(self.v.cos(), -self.d * self.v.sin())
    }
    fn atan2(self, x: Self) -> Self {
        let r2 = self.v * self.v + x.v * x.v;
        Dual::new(self.v.atan2(x.v), (x.v * self.d - self.v * x.d) / r2)
    }
}

/// A 3-vector.
pub type V3<S> = [S; 3];
/// A 3×3 matrix, row-major: `m[row][col]`.
pub type M3<S> = [[S; 3]; 3];

/// `a + b`.
pub fn add<S: Scalar>(a: &V3<S>, b: &V3<S>) -> V3<S> {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}
/// `a − b`.
pub fn sub<S: Scalar>(a: &V3<S>, b: &V3<S>) -> V3<S> {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
/// `s·a`.
pub fn scale<S: Scalar>(s: S, a: &V3<S>) -> V3<S> {
    [s * a[0], s * a[1], s * a[2]]
}
/// `a·b`.
pub fn dot<S: Scalar>(a: &V3<S>, b: &V3<S>) -> S {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
/// `a × b`.
pub fn cross<S: Scalar>(a: &V3<S>, b: &V3<S>) -> V3<S> {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
/// `a / |a|`.
pub fn unit<S: Scalar>(a: &V3<S>) -> V3<S> {
    let n = dot(a, a).sqrt();
    [a[0] / n, a[1] / n, a[2] / n]
}
/// `m·a`.
pub fn mul_v<S: Scalar>(m: &M3<S>, a: &V3<S>) -> V3<S> {
    [dot(&m[0], a), dot(&m[1], a), dot(&m[2], a)]
}
/// `mᵀ·a`.
pub fn mul_tv<S: Scalar>(m: &M3<S>, a: &V3<S>) -> V3<S> {
    let mut o = [S::c(0.0); 3];
    for i in 0..3 {
        for k in 0..3 {
            o[i] = o[i] + m[k][i] * a[k];
        }
    }
    o
}
/// `a·b`.
pub fn mul<S: Scalar>(a: &M3<S>, b: &M3<S>) -> M3<S> {
    let mut o = [[S::c(0.0); 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            for k in 0..3 {
                o[i][j] = o[i][j] + a[i][k] * b[k][j];
            }
        }
    }
    o
}
/// `aᵀ·b`.
pub fn mul_tn<S: Scalar>(a: &M3<S>, b: &M3<S>) -> M3<S> {
    let mut o = [[S::c(0.0); 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            for k in 0..3 {
                o[i][j] = o[i][j] + a[k][i] * b[k][j];
            }
        }
    }
    o
}
/// The matrix whose columns are `a, b, c`.
pub fn from_columns<S: Scalar>(a: &V3<S>, b: &V3<S>, c: &V3<S>) -> M3<S> {
    [[a[0], b[0], c[0]], [a[1], b[1], c[1]], [a[2], b[2], c[2]]]
}
/// Column `j` of `m`.
pub fn column<S: Scalar>(m: &M3<S>, j: usize) -> V3<S> {
    [m[0][j], m[1][j], m[2][j]]
}

/// Unit quaternion `[w, x, y, z]` of a rotation matrix (Shepperd's method: the pivot is the
/// largest of the trace and the diagonal, chosen on the value part).
pub fn quaternion<S: Scalar>(r: &M3<S>) -> [S; 4] {
    let half = S::c(0.5);
    let one = S::c(1.0);
    let tr = r[0][0] + r[1][1] + r[2][2];
    let d = [tr.re(), r[0][0].re(), r[1][1].re(), r[2][2].re()];
    let mut k = 0;
    for i in 1..4 {
        if d[i] > d[k] {
            k = i;
        }
    }
    let q = match k {
        0 => {
            let w = half * (one + tr).sqrt();
            let f = S::c(0.25) / w;
            [
                w,
                (r[2][1] - r[1][2]) * f,
                (r[0][2] - r[2][0]) * f,
                (r[1][0] - r[0][1]) * f,
            ]
        }
        1 => {
            let x = half * (one + S::c(2.0) * r[0][0] - tr).sqrt();
            let f = S::c(0.25) / x;
            [
                (r[2][1] - r[1][2]) * f,
                x,
                (r[0][1] + r[1][0]) * f,
                (r[0][2] + r[2][0]) * f,
            ]
        }
        2 => {
            let y = half * (one + S::c(2.0) * r[1][1] - tr).sqrt();
            let f = S::c(0.25) / y;
            [
                (r[0][2] - r[2][0]) * f,
                (r[0][1] + r[1][0]) * f,
                y,
                (r[1][2] + r[2][1]) * f,
            ]
        }
        _ => {
            let z = half * (one + S::c(2.0) * r[2][2] - tr).sqrt();
            let f = S::c(0.25) / z;
            [
                (r[1][0] - r[0][1]) * f,
                (r[0][2] + r[2][0]) * f,
                (r[1][2] + r[2][1]) * f,
                z,
            ]
        }
    };
    let n = (q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]).sqrt();
    [q[0] / n, q[1] / n, q[2] / n, q[3] / n]
}

/// The rotation vector of a rotation matrix, `|ψ| ≤ π`, through the unit quaternion
/// ([`quaternion`]): accurate at every angle, including near π where the skew part vanishes.
pub fn log<S: Scalar>(r: &M3<S>) -> V3<S> {
    let q = quaternion(r);
    // Keep w ≥ 0 so that the angle 2·atan2(|v|, w) lies in [0, π].
    let (w, v) = if q[0].re() < 0.0 {
        (-q[0], [-q[1], -q[2], -q[3]])
    } else {
        (q[0], [q[1], q[2], q[3]])
    };
    let s2 = dot(&v, &v);
    if s2.re() < 1e-24 {
        // φ ≈ 2·s/w: ψ ≈ 2·v/w, exact to O(φ³).
        return scale(S::c(2.0) / w, &v);
    }
    let s = s2.sqrt();
    let phi = S::c(2.0) * s.atan2(w);
    scale(phi / s, &v)
}

/// `T⁻¹(ψ)·a`: the inverse of the left Jacobian of SO(3) applied to `a`,
/// `T⁻¹ = I − ½[ψ]× + (1/φ² − (1 + cos φ)/(2φ·sin φ))·[ψ]×²` (see
/// [`crate::rotation::rotation_vector_from_spin`]), and its transpose when `transpose` is
/// set. Series below φ² = 1e-8.
pub fn inv_jacobian_times<S: Scalar>(psi: &V3<S>, a: &V3<S>, transpose: bool) -> V3<S> {
    let phi2 = dot(psi, psi);
    let c = if phi2.re() < 1e-8 {
        S::c(1.0 / 12.0) + phi2 / S::c(720.0)
    } else {
        let phi = phi2.sqrt();
        S::c(1.0) / phi2 - (S::c(1.0) + phi.cos()) / (S::c(2.0) * phi * phi.sin())
    };
    // [ψ]×·a = ψ × a; [ψ]×ᵀ = −[ψ]×; [ψ]×² is symmetric.
    let pa = cross(psi, a);
    let ppa = cross(psi, &pa);
    let h = if transpose { S::c(0.5) } else { S::c(-0.5) };
    add(&add(a, &scale(h, &pa)), &scale(c, &ppa))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Dual derivatives of a composite function equal the hand derivative.
    #[test]
    fn chain_rule() {
        let x = Dual::new(0.7, 1.0);
        let f = (x * x).sin() / (x + Dual::c(1.0)) + x.sqrt().atan2(Dual::c(2.0));
        let v: f64 = 0.7;
        let df = 2.0 * v * (v * v).cos() / (v + 1.0) - (v * v).sin() / (v + 1.0).powi(2)
            + (0.5 / v.sqrt()) * 2.0 / (4.0 + v);
        assert!((f.d - df).abs() < 1e-14, "{} vs {df}", f.d);
    }

    /// Dual derivatives of `log` match central differences of the `f64` instance along a
    /// spin direction (`R + ε·[e]×·R`).
    #[test]
    fn log_derivative_matches_differences() {
        use nalgebra::Vector3;
        let psi = Vector3::new(0.3, -1.1, 2.0);
        let r = crate::rotation::exp(&psi);
        let e = crate::rotation::skew(&Vector3::new(0.2, 0.5, -0.7));
        let dr = e * r;
        let md: M3<Dual> =
            std::array::from_fn(|i| std::array::from_fn(|j| Dual::new(r[(i, j)], dr[(i, j)])));
        let l = log(&md);
        let h = 1e-6;
        let at = |t: f64| -> V3<f64> {
            let m = crate::rotation::exp(&(Vector3::new(0.2, 0.5, -0.7) * t)) * r;
            log(&std::array::from_fn(|i| std::array::from_fn(|j| m[(i, j)])))
        };
        let (p, m) = (at(h), at(-h));
        for k in 0..3 {
            assert!(
                (l[k].d - (p[k] - m[k]) / (2.0 * h)).abs() < 1e-8,
                "component {k}"
            );
        }
    }
}

//! Wheel and rail cross-section profiles: the C² cubic splines that interpolate them, the
//! S1002 wheel (EN 13715) and 60E1/UIC60 rail head built from their published piecewise
//! definitions, CSV input with unit checks, rail inclination and left/right mirroring.
//! What does not live here: the contact search between a rail node and the wheel spline
//! (see [`crate::rail::contact::contact_geometry`]) and the mapping of 3-D positions into the profile
//! plane (the moving-axle element does that).
//!
//! # Profile coordinates (one convention for wheel and rail)
//!
//! Every profile is a curve in its body's cross-section plane with coordinates `(y, z)` in
//! metres, stored as `nalgebra::Vector2` `[y, z]`:
//!
//! - `y` lateral, **positive towards the field side** (away from the track centre line),
//!   so the wheel flange and the rail's gauge side are at negative `y`;
//! - `z` vertical (normal to the track plane for an upright rail), positive up.
//!
//! The wheel origin is its nominal contact point on the tape circle (S1002: `y = 0` on the
//! tape-circle plane, on the nominal rolling radius r0); the wheel surface is
//! `z = −F(y)`, so the flange (larger radius) hangs below `z = 0`; the axle centre is at
//! `z = +r0`. The rail origin is the top centre of the upright head.
//!
//! In these coordinates both sides of the track use the same profile. The moving-axle
//! element works in the wheel frame 1-2-3 whose axis 1 points to the left of the direction
//! of travel: the **left** wheel and rail use a profile as it is (their field side is +1),
//! the **right** ones use [`WheelProfile::mirrored`] / [`RailProfile::mirrored`]
//! (`y → −y`).
//!
//! # Orientation (which side is material)
//!
//! A wheel profile is stored so that the wheel material lies on the **left** of the curve
//! when it is traversed with increasing spline parameter (the outward normal, towards the
//! rail, is the unit tangent rotated clockwise by 90°). A rail profile's nodes are stored
//! with strictly increasing `y`; the rail material lies on their **right** (below).
//! Mirroring reverses the order of the points so that both rules still hold.

use nalgebra::Vector2;
use railfem_framework::limits;
use std::path::Path;
use thiserror::Error;

/// The file name used in errors for profiles built in memory rather than read from a file.
pub const IN_MEMORY: &str = "<in-memory>";

/// Everything that can be wrong with a profile or spline input. Each message is one line:
/// the file (or `<in-memory>`), the 1-based line (or point number for in-memory input;
/// 0 when it concerns the whole input), what is wrong, and how to fix it.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum ProfileError {
    /// The file could not be read.
    #[error(
        "{file}:{line}: cannot read the profile ({what}); fix: check the path and its permissions"
    )]
    Io {
        /// File name.
        file: String,
        /// Line number (0: the whole file).
        line: usize,
        /// The operating system's message.
        what: String,
    },
    /// The units are not stated, or are not `mm` or `m`.
    #[error("{file}:{line}: unknown units ({what}); fix: state them before the first point, as `# units: mm` / `# units: m` or a header `y_mm,z_mm` / `y_m,z_m`")]
    UnknownUnits {
        /// File name.
        file: String,
        /// Line number.
        line: usize,
        /// What was found.
        what: String,
    },
    /// A data line is not two numbers.
    #[error("{file}:{line}: cannot read {what:?} as a point; fix: write one point per line as two comma-separated numbers `y,z`")]
    Parse {
        /// File name.
        file: String,
        /// Line number.
        line: usize,
        /// The offending text.
        what: String,
    },
    /// A coordinate is NaN or infinite.
    #[error("{file}:{line}: a coordinate is not a finite number ({what}); fix: correct or remove that point")]
    NotFinite {
        /// File name.
        file: String,
        /// Line (or point) number.
        line: usize,
        /// The offending values.
        what: String,
    },
    /// A coordinate beyond [`MAX_PROFILE_EXTENT`] in its declared unit.
    #[error("{file}:{line}: {what}")]
    OutOfBounds {
        /// File name.
        file: String,
        /// Line number.
        line: usize,
        /// The column, the value, the bound and the fix ([`railfem_framework::csv_input`]).
        what: String,
    },
    /// More points than [`MAX_PROFILE_POINTS`], or a file larger than the memory budget.
    #[error("{file}:{line}: {what}")]
    TooLarge {
        /// File name.
        file: String,
        /// Line of the first point past the cap (0: the whole file).
        line: usize,
        /// The estimate, the cap and the fix ([`railfem_framework::limits`]).
        what: String,
    },
    /// Fewer than four points (a not-a-knot cubic spline needs four).
    #[error("{file}:{line}: only {count} points; fix: give at least 4 points along the profile")]
    TooFewPoints {
        /// File name.
        file: String,
        /// Line number of the last point (0 if none).
        line: usize,
        /// How many points were given.
        count: usize,
    },
    /// A parameter that must increase strictly does not (spline knots, rail lateral coordinate).
    #[error("{file}:{line}: {what} is not strictly increasing ({prev} then {this}); fix: sort the points along the profile and remove repeats")]
    NonMonotonic {
        /// File name.
        file: String,
        /// Line (or point) number of the offending point.
        line: usize,
        /// Which quantity.
        what: String,
        /// The previous value.
        prev: f64,
        /// The offending value.
        this: f64,
    },
    /// Two consecutive points coincide (zero chord length).
    #[error("{file}:{line}: the point repeats the previous one; fix: remove the repeated point")]
    RepeatedPoint {
        /// File name.
        file: String,
        /// Line (or point) number of the repeat.
        line: usize,
    },
    /// The profile read from a file is far wider or narrower than any wheel or rail head
    /// (S1002 spans 130 mm, 60E1's head 72 mm): almost always millimetres declared as
    /// metres or the other way round.
    #[error("{file}:{line}: the profile spans {width} m laterally, outside the {min} m to {max} m of a wheel or rail head; fix: check the units (`# units: mm` or `# units: m`)")]
    ImplausibleWidth {
        /// File name.
        file: String,
        /// Line number of the last point.
        line: usize,
        /// Lateral extent max y − min y (m).
        width: f64,
        /// Smallest accepted extent (m).
        min: f64,
        /// Largest accepted extent (m).
        max: f64,
    },
    /// The polyline through the points crosses or folds back on itself.
    #[error("{file}:{line}: the segment ending here crosses the segment ending at line {other}; fix: list the points in order along the profile, without loops")]
    SelfIntersecting {
        /// File name.
        file: String,
        /// Line (or point) number of the end of the first segment.
        line: usize,
        /// Line (or point) number of the end of the second segment.
        other: usize,
    },
}

// ---------------------------------------------------------------------------------------
// Cubic spline y(t)
// ---------------------------------------------------------------------------------------

/// A C² interpolating cubic spline `y(t)` through points `(t_i, y_i)` with strictly
/// increasing `t` (any units; profiles use metres).
///
/// End conditions: **not-a-knot** (the third derivative is continuous at the second and
/// the last-but-one knot). Chosen over the natural spline because it has no artificial
/// `y'' = 0` at the ends, so it keeps fourth-order accuracy up to the ends of a profile
/// (the flange back and the field side) and reproduces any cubic exactly (tested).
/// It needs at least 4 points.
///
/// Evaluation finds the interval by binary search (O(log n)); outside `[t_0, t_{n−1}]`
/// the end cubics are extrapolated.
#[derive(Debug, Clone, PartialEq)]
pub struct CubicSpline {
    t: Vec<f64>,
    y: Vec<f64>,
    /// Slopes y'(t_i).
    s: Vec<f64>,
    /// Per interval: y = y_i + s_i d + c2 d² + c3 d³, d = t − t_i.
    c2: Vec<f64>,
    c3: Vec<f64>,
}

impl CubicSpline {
    /// Builds the not-a-knot spline through `(t[i], y[i])`. Errors (with `<in-memory>` and
    /// the 1-based point number): unequal lengths or fewer than 4 points, non-finite
    /// values, `t` not strictly increasing.
    pub fn new(t: &[f64], y: &[f64]) -> Result<Self, ProfileError> {
        let n = t.len().min(y.len());
        if n < 4 || t.len() != y.len() {
            return Err(ProfileError::TooFewPoints {
                file: IN_MEMORY.into(),
                line: n,
                count: n,
            });
        }
        for i in 0..n {
            if !t[i].is_finite() || !y[i].is_finite() {
                return Err(ProfileError::NotFinite {
                    file: IN_MEMORY.into(),
                    line: i + 1,
                    what: format!("t = {}, y = {}", t[i], y[i]),
                });
            }
            if i > 0 && t[i] <= t[i - 1] {
                return Err(ProfileError::NonMonotonic {
                    file: IN_MEMORY.into(),
                    line: i + 1,
                    what: "the spline parameter t".into(),
                    prev: t[i - 1],
                    this: t[i],
                });
            }
        }
        let h: Vec<f64> = (0..n - 1).map(|i| t[i + 1] - t[i]).collect();
        let d: Vec<f64> = (0..n - 1).map(|i| (y[i + 1] - y[i]) / h[i]).collect();
        // Tridiagonal system for the slopes s_i: sub a, diagonal b, super c, right side r.
        let mut a = vec![0.0; n];
        let mut b = vec![0.0; n];
        let mut c = vec![0.0; n];
        let mut r = vec![0.0; n];
        // Interior rows (C² at t_i): h_i s_{i−1} + 2(h_{i−1}+h_i) s_i + h_{i−1} s_{i+1}
        //                            = 3 (h_i d_{i−1} + h_{i−1} d_i).
        for i in 1..n - 1 {
            a[i] = h[i];
            b[i] = 2.0 * (h[i - 1] + h[i]);
            c[i] = h[i - 1];
            r[i] = 3.0 * (h[i] * d[i - 1] + h[i - 1] * d[i]);
        }
        // Not-a-knot at t_1 (y''' continuous), eliminated to two unknowns:
        // h_1 s_0 + (h_0+h_1) s_1 = ((h_0 + 2(h_0+h_1)) h_1 d_0 + h_0² d_1) / (h_0+h_1).
        let (h0, h1) = (h[0], h[1]);
        b[0] = h1;
        c[0] = h0 + h1;
        r[0] = ((h0 + 2.0 * (h0 + h1)) * h1 * d[0] + h0 * h0 * d[1]) / (h0 + h1);
        // Not-a-knot at t_{n−2}, mirrored.
        let (hl, hp) = (h[n - 2], h[n - 3]);
        a[n - 1] = hl + hp;
        b[n - 1] = hp;
        r[n - 1] = (hl * hl * d[n - 3] + (2.0 * (hp + hl) + hl) * hp * d[n - 2]) / (hp + hl);
        // Thomas algorithm: after the first row every pivot is positive (the interior rows
        // are diagonally dominant), see the module tests for the reproduction of cubics.
        for i in 1..n {
            let m = a[i] / b[i - 1];
            b[i] -= m * c[i - 1];
            r[i] -= m * r[i - 1];
        }
        let mut s = vec![0.0; n];
        s[n - 1] = r[n - 1] / b[n - 1];
        for i in (0..n - 1).rev() {
            s[i] = (r[i] - c[i] * s[i + 1]) / b[i];
        }
        let c2 = (0..n - 1)
            .map(|i| (3.0 * d[i] - 2.0 * s[i] - s[i + 1]) / h[i])
            .collect();
        let c3 = (0..n - 1)
            .map(|i| (s[i] + s[i + 1] - 2.0 * d[i]) / (h[i] * h[i]))
            .collect();
        Ok(Self {
            t: t.to_vec(),
            y: y.to_vec(),
            s,
            c2,
            c3,
        })
    }

    /// The knots `t_i`.
    pub fn knots(&self) -> &[f64] {
        &self.t
    }

    /// The interpolated values `y_i`.
    pub fn values(&self) -> &[f64] {
        &self.y
    }

    /// The parameter range `(t_0, t_{n−1})`.
    pub fn domain(&self) -> (f64, f64) {
        (self.t[0], self.t[self.t.len() - 1])
    }

    /// Index `i` of the interval `[t_i, t_{i+1}]` holding `t` (binary search, O(log n));
    /// clamped to the first / last interval outside the domain.
    pub fn interval(&self, t: f64) -> usize {
        let k = self.t.partition_point(|&ti| ti <= t);
        k.saturating_sub(1).min(self.t.len() - 2)
    }

    /// [`CubicSpline::interval`] when the caller knows where `t` probably lies: `i` if it
    /// is the interval `interval(t)` would return (checked against the knots by the same
    /// rule, O(1)), otherwise the binary search. The same index in every case.
    pub fn interval_near(&self, t: f64, i: usize) -> usize {
        let last = self.t.len() - 2;
        if i <= last && (i == 0 || self.t[i] <= t) && (i == last || t < self.t[i + 1]) {
            i
        } else {
            self.interval(t)
        }
    }

    /// Value, first and second derivative at `t`: `[y, y', y'']`.
    pub fn eval_all(&self, t: f64) -> [f64; 3] {
        self.eval_in(self.interval(t), t)
    }

    /// [`CubicSpline::eval_all`] on the cubic of interval `i` (`i = interval(t)` gives
    /// `eval_all(t)` to the bit; another `i` extrapolates that interval's cubic).
    pub fn eval_in(&self, i: usize, t: f64) -> [f64; 3] {
        let d = t - self.t[i];
        let (s, c2, c3) = (self.s[i], self.c2[i], self.c3[i]);
        [
            self.y[i] + d * (s + d * (c2 + d * c3)),
            s + d * (2.0 * c2 + 3.0 * c3 * d),
            2.0 * c2 + 6.0 * c3 * d,
        ]
    }

    /// Value `y(t)`.
    pub fn value(&self, t: f64) -> f64 {
        self.eval_all(t)[0]
    }

    /// First derivative `y'(t)`.
    pub fn derivative(&self, t: f64) -> f64 {
        self.eval_all(t)[1]
    }

    /// Second derivative `y''(t)`.
    pub fn second_derivative(&self, t: f64) -> f64 {
        self.eval_all(t)[2]
    }
}

// ---------------------------------------------------------------------------------------
// Parametric spline c(t) = (y(t), z(t))
// ---------------------------------------------------------------------------------------

/// A plane C² curve `c(t) = (y(t), z(t))` through points `P_i`, parametrised by cumulative
/// chord length `t_i = Σ |P_{k+1} − P_k|` (so `t` is close to arc length, in the points'
/// units: metres for profiles). Each coordinate is a not-a-knot [`CubicSpline`] in `t`.
/// Unlike a function `z(y)` it represents steep or overhanging parts (the flange face)
/// without trouble.
#[derive(Debug, Clone, PartialEq)]
pub struct ParametricSpline {
    y: CubicSpline,
    z: CubicSpline,
    points: Vec<Vector2<f64>>,
}

impl ParametricSpline {
    /// Builds the chord-length parametrised spline through `points`, after checking them
    /// with [`validate_polyline`] (at least 4 points, finite, no repeats, no crossings).
    pub fn new(points: &[Vector2<f64>]) -> Result<Self, ProfileError> {
        let lines: Vec<usize> = (1..=points.len()).collect();
        validate_polyline(points, &lines, IN_MEMORY)?;
        Ok(Self::build(points))
    }

    /// Builds without validation (the caller has validated).
    fn build(points: &[Vector2<f64>]) -> Self {
        let mut t = Vec::with_capacity(points.len());
        let mut acc = 0.0;
        t.push(0.0);
        for w in points.windows(2) {
            acc += (w[1] - w[0]).norm();
            t.push(acc);
        }
        let ys: Vec<f64> = points.iter().map(|p| p.x).collect();
        let zs: Vec<f64> = points.iter().map(|p| p.y).collect();
        // Validated input: knots strictly increasing, at least 4 points.
        let y = CubicSpline::new(&t, &ys).expect("validated points");
        let z = CubicSpline::new(&t, &zs).expect("validated points");
        Self {
            y,
            z,
            points: points.to_vec(),
        }
    }

    /// The interpolated points `P_i` (`[y, z]`, m).
    pub fn points(&self) -> &[Vector2<f64>] {
        &self.points
    }

    /// The knots `t_i` (cumulative chord length, m).
    pub fn knots(&self) -> &[f64] {
        self.y.knots()
    }

    /// The parameter range `(0, total chord length)` (m).
    pub fn domain(&self) -> (f64, f64) {
        self.y.domain()
    }

    /// Index of the interval `[t_i, t_{i+1}]` holding `t` (O(log n), clamped).
    pub fn interval(&self, t: f64) -> usize {
        self.y.interval(t)
    }

    /// [`ParametricSpline::interval`] checked against a guess `i` first (O(1) when right;
    /// the same index in every case, see [`CubicSpline::interval_near`]).
    pub fn interval_near(&self, t: f64, i: usize) -> usize {
        self.y.interval_near(t, i)
    }

    /// The point `c(t)` (m).
    pub fn point(&self, t: f64) -> Vector2<f64> {
        self.eval_all(t)[0]
    }

    /// `[c(t), c'(t), c''(t)]` (m, dimensionless, 1/m). Both coordinates share the knots,
    /// so one interval search serves both.
    pub fn eval_all(&self, t: f64) -> [Vector2<f64>; 3] {
        self.eval_in(self.interval(t), t)
    }

    /// [`ParametricSpline::eval_all`] on the cubics of interval `i` (`i = interval(t)`, as
    /// [`ParametricSpline::interval_near`] returns it, gives `eval_all(t)` to the bit).
    pub fn eval_in(&self, i: usize, t: f64) -> [Vector2<f64>; 3] {
        let y = self.y.eval_in(i, t);
        let z = self.z.eval_in(i, t);
        [
            Vector2::new(y[0], z[0]),
            Vector2::new(y[1], z[1]),
            Vector2::new(y[2], z[2]),
        ]
    }

    /// The derivative `c'(t)` (close to a unit vector for chord-length parameters).
    pub fn derivative(&self, t: f64) -> Vector2<f64> {
        self.eval_all(t)[1]
    }

    /// The second derivative `c''(t)` (1/m).
    pub fn second_derivative(&self, t: f64) -> Vector2<f64> {
        self.eval_all(t)[2]
    }

    /// The unit tangent `c'/|c'|` at `t`.
    pub fn unit_tangent(&self, t: f64) -> Vector2<f64> {
        self.derivative(t).normalize()
    }

    /// The lateral extent `(min y, max y)` of the interpolated points (m). The spline may
    /// overshoot the points by a fraction of the curve's sag between them; callers that
    /// need a safe bound add a margin.
    pub fn lateral_extent(&self) -> (f64, f64) {
        self.points
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
                (lo.min(p.x), hi.max(p.x))
            })
    }

    /// The curve mirrored in the lateral coordinate (`y → −y`), with the point order
    /// reversed so that the material stays on the same side of the direction of travel.
    pub fn mirrored(&self) -> Self {
        let pts: Vec<Vector2<f64>> = self
            .points
            .iter()
            .rev()
            .map(|p| Vector2::new(-p.x, p.y))
            .collect();
        Self::build(&pts)
    }
}

/// Checks a polyline for use as a profile: at least 4 points, all finite, no two
/// consecutive points equal, no two segments crossing, no segment folding back onto its
/// neighbour. `lines[i]` is the source line (or point number) of `points[i]` for the error
/// message, `file` the source name. O(n²) in the number of points.
pub fn validate_polyline(
    points: &[Vector2<f64>],
    lines: &[usize],
    file: &str,
) -> Result<(), ProfileError> {
    let line = |i: usize| lines.get(i).copied().unwrap_or(i + 1);
    if points.len() < 4 {
        return Err(ProfileError::TooFewPoints {
            file: file.into(),
            line: points.len().checked_sub(1).map_or(0, line),
            count: points.len(),
        });
    }
    for (i, p) in points.iter().enumerate() {
        if !p.x.is_finite() || !p.y.is_finite() {
            return Err(ProfileError::NotFinite {
                file: file.into(),
                line: line(i),
                what: format!("{}, {}", p.x, p.y),
            });
        }
        if i > 0 && *p == points[i - 1] {
            return Err(ProfileError::RepeatedPoint {
                file: file.into(),
                line: line(i),
            });
        }
    }
    let n = points.len();
    for i in 0..n - 1 {
        let (a, b) = (points[i], points[i + 1]);
        // Adjacent segment: folds back if collinear and opposite.
        if i + 2 < n {
            let c = points[i + 2];
            let (u, v) = (b - a, c - b);
            if cross(u, v).abs() <= 1e-14 * u.norm() * v.norm() && u.dot(&v) < 0.0 {
                return Err(ProfileError::SelfIntersecting {
                    file: file.into(),
                    line: line(i + 1),
                    other: line(i + 2),
                });
            }
        }
        for j in i + 2..n - 1 {
            if segments_intersect(a, b, points[j], points[j + 1]) {
                return Err(ProfileError::SelfIntersecting {
                    file: file.into(),
                    line: line(i + 1),
                    other: line(j + 1),
                });
            }
        }
    }
    Ok(())
}

/// z-component of the cross product of two plane vectors.
fn cross(u: Vector2<f64>, v: Vector2<f64>) -> f64 {
    u.x * v.y - u.y * v.x
}

/// Whether the closed segments `[a, b]` and `[c, d]` share a point (orientation tests,
/// collinear overlaps included).
fn segments_intersect(a: Vector2<f64>, b: Vector2<f64>, c: Vector2<f64>, d: Vector2<f64>) -> bool {
    let o1 = cross(b - a, c - a);
    let o2 = cross(b - a, d - a);
    let o3 = cross(d - c, a - c);
    let o4 = cross(d - c, b - c);
    let on = |p: Vector2<f64>, q: Vector2<f64>, r: Vector2<f64>| {
        // r collinear with p-q: within the bounding box?
        r.x >= p.x.min(q.x) && r.x <= p.x.max(q.x) && r.y >= p.y.min(q.y) && r.y <= p.y.max(q.y)
    };
    if ((o1 > 0.0 && o2 < 0.0) || (o1 < 0.0 && o2 > 0.0))
        && ((o3 > 0.0 && o4 < 0.0) || (o3 < 0.0 && o4 > 0.0))
    {
        return true;
    }
    (o1 == 0.0 && on(a, b, c))
        || (o2 == 0.0 && on(a, b, d))
        || (o3 == 0.0 && on(c, d, a))
        || (o4 == 0.0 && on(c, d, b))
}

// ---------------------------------------------------------------------------------------
// CSV input
// ---------------------------------------------------------------------------------------

/// Lateral extent accepted for a profile read from a file (m): a wheel or rail head spans
/// tens of millimetres (60E1 head 72 mm, S1002 130 mm), so 10 mm to 1 m leaves a factor of
/// seven either side and still catches a unit slip (a factor of 1000).
pub const CSV_WIDTH_RANGE: (f64, f64) = (0.01, 1.0);

/// Refuses a profile read from `file` whose lateral extent lies outside [`CSV_WIDTH_RANGE`].
fn check_width(points: &[Vector2<f64>], lines: &[usize], file: &str) -> Result<(), ProfileError> {
    let (lo, hi) = points
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
            (a.min(p.x), b.max(p.x))
        });
    let width = hi - lo;
    let (min, max) = CSV_WIDTH_RANGE;
    if (min..=max).contains(&width) {
        Ok(())
    } else {
        Err(ProfileError::ImplausibleWidth {
            file: file.into(),
            line: lines.last().copied().unwrap_or(0),
            width,
            min,
            max,
        })
    }
}

/// Length unit of a profile file.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Unit {
    Millimetre,
    Metre,
}

impl Unit {
    fn parse(s: &str) -> Option<Self> {
        match s.trim().to_ascii_lowercase().as_str() {
            "mm" => Some(Unit::Millimetre),
            "m" => Some(Unit::Metre),
            _ => None,
        }
    }
    fn scale(self) -> f64 {
        match self {
            Unit::Millimetre => 1e-3,
            Unit::Metre => 1.0,
        }
    }
    fn name(self) -> &'static str {
        match self {
            Unit::Millimetre => "mm",
            Unit::Metre => "m",
        }
    }
}

/// Reads `y,z` points from CSV text and converts them to metres. Format: blank lines and
/// `#` comments are skipped; the units are stated before the first point, either by a
/// comment `# units: mm` (or `m`) or by a column header `y_mm,z_mm` (or `y_m,z_m`); then
/// one point per line, two numbers separated by a comma (spaces around them allowed).
/// Returns the points and their 1-based line numbers. Checks only the syntax, the units
/// and finiteness; the geometric checks are the profile constructors'.
pub fn read_points_csv(
    text: &str,
    file: &str,
) -> Result<(Vec<Vector2<f64>>, Vec<usize>), ProfileError> {
    let text = railfem_framework::csv_input::strip_bom(text);
    let mut unit: Option<Unit> = None;
    let mut points = Vec::new();
    let mut lines = Vec::new();
    for (k, raw) in text.lines().enumerate() {
        let line = k + 1;
        let s = raw.trim();
        if s.is_empty() {
            continue;
        }
        if let Some(comment) = s.strip_prefix('#') {
            let c = comment.trim();
            if let Some(rest) = c
                .strip_prefix("units:")
                .or_else(|| c.strip_prefix("units :"))
            {
                let u = Unit::parse(rest).ok_or_else(|| ProfileError::UnknownUnits {
                    file: file.into(),
                    line,
                    what: format!("`{}`", rest.trim()),
                })?;
                unit = Some(u);
            }
            continue;
        }
        let fields: Vec<&str> = s.split(',').map(str::trim).collect();
        let numbers: Option<Vec<f64>> = fields.iter().map(|f| f.parse::<f64>().ok()).collect();
        match numbers {
            Some(v) if v.len() == 2 => {
                let u = unit.ok_or_else(|| ProfileError::UnknownUnits {
                    file: file.into(),
                    line,
                    what: "no units stated before the first point".into(),
                })?;
                if !v[0].is_finite() || !v[1].is_finite() {
                    return Err(ProfileError::NotFinite {
                        file: file.into(),
                        line,
                        what: s.into(),
                    });
                }
                if points.len() == MAX_PROFILE_POINTS {
                    // Size guard before the quadratic geometric checks: count the rest.
                    let total = MAX_PROFILE_POINTS
                        + 1
                        + text
                            .lines()
                            .skip(line)
                            .filter(|l| {
                                let t = l.trim();
                                !t.is_empty() && !t.starts_with('#')
                            })
                            .count();
                    let what = limits::check_count(
                        "the file",
                        total as f64,
                        "points",
                        MAX_PROFILE_POINTS as f64,
                        "resample the profile (120 points already interpolate it to 1e-6 m)",
                    )
                    .err()
                    .unwrap_or_default();
                    return Err(ProfileError::TooLarge {
                        file: file.into(),
                        line,
                        what,
                    });
                }
                for (column, x) in ["y", "z"].iter().zip(&v) {
                    railfem_framework::csv_input::check_bound(
                        column,
                        *x,
                        u.name(),
                        u.scale(),
                        &PROFILE_BOUND,
                    )
                    .map_err(|what| ProfileError::OutOfBounds {
                        file: file.into(),
                        line,
                        what,
                    })?;
                }
                points.push(Vector2::new(v[0], v[1]) * u.scale());
                lines.push(line);
            }
            Some(_) => {
                return Err(ProfileError::Parse {
                    file: file.into(),
                    line,
                    what: s.into(),
                })
            }
            None if points.is_empty() && fields.len() == 2 => {
                // A column header: both columns must carry the same known unit suffix.
                let units: Vec<Option<Unit>> = fields
                    .iter()
                    .map(|f| f.rsplit_once('_').and_then(|(_, u)| Unit::parse(u)))
                    .collect();
                match (units[0], units[1]) {
                    (Some(a), Some(b)) if a == b && unit.is_none_or(|u| u == a) => unit = Some(a),
                    _ => {
                        return Err(ProfileError::UnknownUnits {
                            file: file.into(),
                            line,
                            what: format!("header `{s}`"),
                        })
                    }
                }
            }
            None => {
                return Err(ProfileError::Parse {
                    file: file.into(),
                    line,
                    what: s.into(),
                })
            }
        }
    }
    if points.len() < 4 {
        return Err(ProfileError::TooFewPoints {
            file: file.into(),
            line: lines.last().copied().unwrap_or(0),
            count: points.len(),
        });
    }
    Ok((points, lines))
}

/// Largest coordinate magnitude of a profile point read from a file (m): a wheel or rail
/// cross-section is a few hundred millimetres (S1002 spans about 140 mm, a 60E1 rail is
/// 172 mm high), so a point a metre from the profile's origin is a unit slip.
pub const MAX_PROFILE_EXTENT: f64 = 1.0;

const PROFILE_BOUND: railfem_framework::csv_input::Bound = railfem_framework::csv_input::Bound {
    max_si: MAX_PROFILE_EXTENT,
    si_unit: "m",
    why: "a wheel or rail cross-section is a few hundred millimetres",
};

/// Most points a wheel or rail profile may have, sampled (`wheel_points`, `rail_nodes`) or
/// read from a file: beyond a few thousand points a profile is no more accurate (the
/// spline error of 120 points is already below 1e-6 m), and its checks are quadratic.
pub const MAX_PROFILE_POINTS: usize = 5000;

fn read_file(path: &Path) -> Result<String, ProfileError> {
    limits::check_file(path, "the profile").map_err(|what| ProfileError::TooLarge {
        file: path.display().to_string(),
        line: 0,
        what,
    })?;
    std::fs::read_to_string(path).map_err(|e| ProfileError::Io {
        file: path.display().to_string(),
        line: 0,
        what: e.to_string(),
    })
}

// ---------------------------------------------------------------------------------------
// Wheel profile
// ---------------------------------------------------------------------------------------

/// A wheel's cross-section profile: points `[y, z]` (m) in the profile coordinates of the
/// module doc (y towards the field side, z up, origin at the nominal contact point on the
/// tape circle), interpolated by a chord-length [`ParametricSpline`]. The points are
/// ordered so that the wheel material is on the left of increasing parameter (for an
/// ordinary profile: from the flange back to the field side).
#[derive(Debug, Clone, PartialEq)]
pub struct WheelProfile {
    spline: ParametricSpline,
}

/// Section breakpoints of the S1002 profile, `y` in mm from the flange back (H) to the
/// field side (A): H | G | F | E | D | C | B | A.
pub const S1002_BREAKPOINTS_MM: [f64; 9] = [
    -70.0,
    -62.764_705_882,
    -49.662_510_381,
    -39.764_473_993,
    -38.426_669_071,
    -35.0,
    -26.0,
    32.157_96,
    60.0,
];

/// The S1002 section letter holding `y_mm` (breakpoints belong to the section towards the
/// field side), from the table in `vehicle-track-profiles.md`.
fn s1002_section(y: f64) -> char {
    let b = &S1002_BREAKPOINTS_MM;
    if y < b[1] {
        'H'
    } else if y < b[2] {
        'G'
    } else if y < b[3] {
        'F'
    } else if y < b[4] {
        'E'
    } else if y < b[5] {
        'D'
    } else if y < b[6] {
        'C'
    } else if y < b[7] {
        'B'
    } else {
        'A'
    }
}

/// Evaluates S1002 section `sec` ('A'..='H') at `y` mm, giving F in mm (radial offset from
/// the nominal rolling radius, positive towards the flange tip). Outside a circle's range
/// the square root is clamped at 0.
pub fn s1002_section_height_mm(sec: char, y: f64) -> f64 {
    let root = |r: f64, c: f64| (r * r - (y + c) * (y + c)).max(0.0).sqrt();
    match sec {
        'A' => 1.364_323_640 - 0.066_666_667 * y,
        'B' => {
            let c = [
                0.0,
                -3.358_537_058e-2,
                1.565_681_624e-3,
                -2.810_427_944e-5,
                5.844_240_864e-8,
                -1.562_379_023e-8,
                5.309_217_349e-15,
                -5.957_839_843e-12,
                2.646_656_573e-13,
            ];
            c.iter().rev().fold(0.0, |acc, &ci| acc * y + ci)
        }
        'C' => {
            let c = [
                4.320_221_063e3,
                1.038_384_026e3,
                1.065_501_873e2,
                6.051_367_875,
                2.054_332_446e-1,
                4.169_739_389e-3,
                4.687_195_829e-5,
                2.252_755_540e-7,
            ];
            -c.iter().rev().fold(0.0, |acc, &ci| acc * y + ci)
        }
        'D' => 16.446 - root(13.0, 26.210_665),
        'E' => -93.576_667_419 - 2.747_477_419 * y,
        'F' => 8.834_924_130 + root(20.0, 58.558_326_413),
        'G' => 16.0 + root(12.0, 55.0),
        _ => 9.519_259_302 + root(20.5, 49.5),
    }
}

/// The S1002 height function F(y) (mm, radial offset from the nominal rolling radius,
/// positive towards the flange tip) at `y_mm` (mm from the tape-circle plane, positive
/// towards the field side), valid for −70 ≤ y ≤ 60.
pub fn s1002_height_mm(y_mm: f64) -> f64 {
    s1002_section_height_mm(s1002_section(y_mm), y_mm)
}

/// Default number of points for [`WheelProfile::s1002`].
pub const DEFAULT_WHEEL_POINTS: usize = 201;

impl WheelProfile {
    /// A wheel profile through `points` (`[y, z]`, m). Validated with
    /// [`validate_polyline`]; if the first point lies on the field side of the last
    /// (`y_first > y_last`) the order is reversed so that the material (above the tread)
    /// is on the left of increasing parameter.
    pub fn from_points(points: &[Vector2<f64>]) -> Result<Self, ProfileError> {
        let lines: Vec<usize> = (1..=points.len()).collect();
        Self::from_points_lines(points.to_vec(), lines, IN_MEMORY)
    }

    fn from_points_lines(
        mut points: Vec<Vector2<f64>>,
        mut lines: Vec<usize>,
        file: &str,
    ) -> Result<Self, ProfileError> {
        validate_polyline(&points, &lines, file)?;
        if points[0].x > points[points.len() - 1].x {
            points.reverse();
            lines.reverse();
        }
        Ok(Self {
            spline: ParametricSpline::build(&points),
        })
    }

    /// The S1002 wheel (EN 13715) from its piecewise definition (sections A–H, see the
    /// spec), sampled at `n_points` points (at least 8; fewer are raised to 8) equally
    /// spaced in arc length from the flange back (y = −70 mm) to the field side
    /// (y = +60 mm); each point lies exactly on the analytic profile. Converted to the
    /// profile coordinates: `y = y_mm / 1000`, `z = −F(y_mm) / 1000` (m).
    pub fn s1002(n_points: usize) -> Self {
        let n = n_points.max(8);
        // Dense table of arc length over y, then invert it.
        const DENSE: usize = 20_000;
        let (y0, y1) = (S1002_BREAKPOINTS_MM[0], S1002_BREAKPOINTS_MM[8]);
        let ys: Vec<f64> = (0..=DENSE)
            .map(|k| y0 + (y1 - y0) * k as f64 / DENSE as f64)
            .collect();
        let mut s = vec![0.0; ys.len()];
        for k in 1..ys.len() {
            let dy = ys[k] - ys[k - 1];
            let dz = s1002_height_mm(ys[k]) - s1002_height_mm(ys[k - 1]);
            s[k] = s[k - 1] + dy.hypot(dz);
        }
        let total = s[DENSE];
        let points: Vec<Vector2<f64>> = (0..n)
            .map(|j| {
                let target = total * j as f64 / (n - 1) as f64;
                let k = s.partition_point(|&sk| sk < target).clamp(1, DENSE);
                let w = (target - s[k - 1]) / (s[k] - s[k - 1]);
                let y = ys[k - 1] + w * (ys[k] - ys[k - 1]);
                Vector2::new(y * 1e-3, -s1002_height_mm(y) * 1e-3)
            })
            .collect();
        Self {
            spline: ParametricSpline::build(&points),
        }
    }

    /// Reads a wheel profile from CSV text (format: [`read_points_csv`]); `file` names the
    /// source in errors.
    pub fn from_csv_str(text: &str, file: &str) -> Result<Self, ProfileError> {
        let (points, lines) = read_points_csv(text, file)?;
        validate_polyline(&points, &lines, file)?;
        check_width(&points, &lines, file)?;
        Self::from_points_lines(points, lines, file)
    }

    /// Reads a wheel profile from a CSV file (format: [`read_points_csv`]).
    pub fn from_csv_file(path: impl AsRef<Path>) -> Result<Self, ProfileError> {
        let path = path.as_ref();
        Self::from_csv_str(&read_file(path)?, &path.display().to_string())
    }

    /// The profile's points `[y, z]` (m).
    pub fn points(&self) -> &[Vector2<f64>] {
        self.spline.points()
    }

    /// The C² curve through the points (parameter: chord length, m).
    pub fn spline(&self) -> &ParametricSpline {
        &self.spline
    }

    /// The profile of the wheel on the other side: `y → −y`, point order reversed.
    pub fn mirrored(&self) -> Self {
        Self {
            spline: self.spline.mirrored(),
        }
    }
}

// ---------------------------------------------------------------------------------------
// Rail profile
// ---------------------------------------------------------------------------------------

/// Rail inclination (cant of the rail in its seat), which turns the head towards the track
/// centre. In the profile coordinates (y towards the field side) the gauge side is −y, and
/// the inclination rotates the head about the origin (the top centre of the upright head)
/// counter-clockwise by `atan(1/40)` or `atan(1/20)`: the rail's own up axis becomes
/// `(−sin α, cos α)`, i.e. it leans towards the gauge side, and the crown rises towards the
/// field side to match the conicity of the wheel tread.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
pub enum Inclination {
    /// Upright rail (`"none"` in a model file).
    #[default]
    #[serde(rename = "none")]
    None,
    /// 1:40 (common in Europe and on high-speed lines; `"1:40"`).
    #[serde(rename = "1:40")]
    OneIn40,
    /// 1:20 (`"1:20"`).
    #[serde(rename = "1:20")]
    OneIn20,
}

impl Inclination {
    /// The inclination angle α (rad): 0, atan(1/40) or atan(1/20).
    pub fn angle(self) -> f64 {
        match self {
            Inclination::None => 0.0,
            Inclination::OneIn40 => (1.0f64 / 40.0).atan(),
            Inclination::OneIn20 => (1.0f64 / 20.0).atan(),
        }
    }

    /// Applies the inclination to a point of the upright head (m).
    pub fn rotate(self, p: Vector2<f64>) -> Vector2<f64> {
        let (s, c) = self.angle().sin_cos();
        Vector2::new(c * p.x - s * p.y, s * p.x + c * p.y)
    }
}

/// Default number of rail nodes for [`RailProfile::uic60`] (the paper's Figure 4 uses 30–60).
pub const DEFAULT_RAIL_NODES: usize = 41;

/// A rail head profile: nodes `[y, z]` (m) in the profile coordinates of the module doc
/// (y towards the field side, z up, origin at the top centre of the upright head), with
/// strictly increasing `y` (so a contact search can window them by lateral coordinate);
/// the rail material is below (on the right of increasing `y`). These are the paper's
/// rail slave nodes SC (Figure 4).
#[derive(Debug, Clone, PartialEq)]
pub struct RailProfile {
    nodes: Vec<Vector2<f64>>,
    inclination: Inclination,
}

/// One circular arc of the 60E1 head: centre (mm), radius (mm), start and end angle (rad),
/// traversed clockwise (decreasing angle) from the gauge side to the field side.
struct Arc {
    centre: Vector2<f64>,
    radius: f64,
    from: f64,
    to: f64,
}

impl Arc {
    fn through(centre: (f64, f64), radius: f64, from: (f64, f64), to: (f64, f64)) -> Self {
        let c = Vector2::new(centre.0, centre.1);
        Self {
            centre: c,
            radius,
            from: (from.1 - c.y).atan2(from.0 - c.x),
            to: (to.1 - c.y).atan2(to.0 - c.x),
        }
    }
    fn length(&self) -> f64 {
        self.radius * (self.from - self.to).abs()
    }
    fn at(&self, s: f64) -> Vector2<f64> {
        let a = self.from - s / self.radius;
        self.centre + self.radius * Vector2::new(a.cos(), a.sin())
    }
}

/// The 60E1 head arcs, gauge side (−y) to field side (+y), in mm.
fn uic60_arcs() -> Vec<Arc> {
    // Junction heights from the arcs' own equations.
    let crown_z = |x: f64| -300.0 + (300.0f64 * 300.0 - x * x).sqrt();
    let shoulder_z = |x: f64| -80.128 + (80.0f64 * 80.0 - (x - 7.5005) * (x - 7.5005)).sqrt();
    let (x1, x2, x3) = (10.228, 26.0265, 36.000);
    let (z1, z2, z3) = (crown_z(x1), shoulder_z(x2), -14.300);
    vec![
        Arc::through((-23.016, -14.949), 13.0, (-x3, z3), (-x2, z2)),
        Arc::through((-7.5005, -80.128), 80.0, (-x2, z2), (-x1, z1)),
        Arc::through((0.0, -300.0), 300.0, (-x1, z1), (x1, z1)),
        Arc::through((7.5005, -80.128), 80.0, (x1, z1), (x2, z2)),
        Arc::through((23.016, -14.949), 13.0, (x2, z2), (x3, z3)),
    ]
}

impl RailProfile {
    /// The 60E1 (UIC60) head from its arcs (crown R300 centred (0, −300) for |y| ≤ 10.228;
    /// shoulders R80 centred (±7.5005, −80.128) to |y| = 26.0265; gauge corners R13
    /// centred (±23.016, −14.949) down to the 1:20 flanks at (±36.000, −14.300); mm),
    /// sampled at `n_nodes` nodes (at least 4; fewer are raised to 4) equally spaced in arc
    /// length from the gauge-side flank to the field-side flank, converted to m and turned
    /// by `inclination` (see [`Inclination`]).
    pub fn uic60(n_nodes: usize, inclination: Inclination) -> Self {
        let n = n_nodes.max(4);
        let arcs = uic60_arcs();
        let total: f64 = arcs.iter().map(Arc::length).sum();
        let nodes = (0..n)
            .map(|j| {
                let mut s = total * j as f64 / (n - 1) as f64;
                let mut p = Vector2::zeros();
                for (k, arc) in arcs.iter().enumerate() {
                    if s <= arc.length() || k == arcs.len() - 1 {
                        p = arc.at(s.min(arc.length()));
                        break;
                    }
                    s -= arc.length();
                }
                inclination.rotate(p * 1e-3)
            })
            .collect();
        Self { nodes, inclination }
    }

    /// A rail profile through `nodes` (`[y, z]`, m, upright), turned by `inclination`.
    /// Errors: fewer than 4 nodes, non-finite, `y` not strictly increasing (before the
    /// inclination), crossings.
    pub fn from_nodes(
        nodes: &[Vector2<f64>],
        inclination: Inclination,
    ) -> Result<Self, ProfileError> {
        let lines: Vec<usize> = (1..=nodes.len()).collect();
        Self::from_nodes_lines(nodes.to_vec(), &lines, IN_MEMORY, inclination)
    }

    fn from_nodes_lines(
        nodes: Vec<Vector2<f64>>,
        lines: &[usize],
        file: &str,
        inclination: Inclination,
    ) -> Result<Self, ProfileError> {
        validate_polyline(&nodes, lines, file)?;
        let nodes: Vec<Vector2<f64>> = nodes.into_iter().map(|p| inclination.rotate(p)).collect();
        for i in 1..nodes.len() {
            if nodes[i].x <= nodes[i - 1].x {
                return Err(ProfileError::NonMonotonic {
                    file: file.into(),
                    line: lines[i],
                    what: "the lateral coordinate y of the (inclined) rail nodes".into(),
                    prev: nodes[i - 1].x,
                    this: nodes[i].x,
                });
            }
        }
        Ok(Self { nodes, inclination })
    }

    /// Reads rail nodes from CSV text (format: [`read_points_csv`], upright head, `y`
    /// strictly increasing from the gauge side to the field side) and turns them by
    /// `inclination`; `file` names the source in errors.
    pub fn from_csv_str(
        text: &str,
        file: &str,
        inclination: Inclination,
    ) -> Result<Self, ProfileError> {
        let (points, lines) = read_points_csv(text, file)?;
        validate_polyline(&points, &lines, file)?;
        check_width(&points, &lines, file)?;
        Self::from_nodes_lines(points, &lines, file, inclination)
    }

    /// Reads rail nodes from a CSV file (see [`RailProfile::from_csv_str`]).
    pub fn from_csv_file(
        path: impl AsRef<Path>,
        inclination: Inclination,
    ) -> Result<Self, ProfileError> {
        let path = path.as_ref();
        Self::from_csv_str(&read_file(path)?, &path.display().to_string(), inclination)
    }

    /// The nodes `[y, z]` (m), `y` strictly increasing.
    pub fn nodes(&self) -> &[Vector2<f64>] {
        &self.nodes
    }

    /// The inclination the nodes carry.
    pub fn inclination(&self) -> Inclination {
        self.inclination
    }

    /// Outward unit normals (out of the rail material, towards the wheel) at the nodes,
    /// from the chord between the neighbouring nodes (one-sided at the ends).
    pub fn outward_normals(&self) -> Vec<Vector2<f64>> {
        let n = self.nodes.len();
        (0..n)
            .map(|i| {
                let d = self.nodes[(i + 1).min(n - 1)] - self.nodes[i.saturating_sub(1)];
                // Material on the right of increasing y: outward = tangent turned +90°.
                Vector2::new(-d.y, d.x).normalize()
            })
            .collect()
    }

    /// The rail on the other side: `y → −y`, node order reversed (y stays increasing).
    pub fn mirrored(&self) -> Self {
        Self {
            nodes: self
                .nodes
                .iter()
                .rev()
                .map(|p| Vector2::new(-p.x, p.y))
                .collect(),
            inclination: self.inclination,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(y: f64, z: f64) -> Vector2<f64> {
        Vector2::new(y, z)
    }

    /// The checked interval guess returns the binary search's interval for every guess:
    /// at every knot, between knots, outside the domain and for NaN; and the spline
    /// evaluated there is the plain evaluation to the bit.
    #[test]
    fn interval_near_is_the_binary_search_for_every_guess() {
        let w = WheelProfile::s1002(40);
        let sp = w.spline();
        let k = sp.knots();
        let mut ts = vec![k[0] - 1.0, f64::NAN, k[k.len() - 1] + 1.0, -0.0];
        for i in 0..k.len() {
            ts.push(k[i]);
            ts.push(k[i] - 1e-17);
            if i + 1 < k.len() {
                ts.push(0.5 * (k[i] + k[i + 1]));
            }
        }
        for &t in &ts {
            let want = sp.interval(t);
            for guess in 0..k.len() + 2 {
                assert_eq!(sp.interval_near(t, guess), want, "t {t}, guess {guess}");
            }
            let a = sp.eval_in(sp.interval_near(t, want), t);
            let b = sp.eval_all(t);
            for (x, y) in a.iter().zip(&b) {
                assert!(x.x.to_bits() == y.x.to_bits() || (x.x.is_nan() && y.x.is_nan()));
                assert!(x.y.to_bits() == y.y.to_bits() || (x.y.is_nan() && y.y.is_nan()));
            }
        }
    }

    /// A not-a-knot spline reproduces any cubic exactly, on uneven knots, n = 4 and n = 9.
    #[test]
    fn spline_reproduces_cubics() {
        let f = |t: f64| 0.3 - 1.2 * t + 0.7 * t * t - 0.25 * t * t * t;
        let df = |t: f64| -1.2 + 1.4 * t - 0.75 * t * t;
        let ddf = |t: f64| 1.4 - 1.5 * t;
        for ts in [
            vec![0.0, 0.3, 1.1, 2.0],
            vec![-1.0, -0.7, 0.0, 0.2, 0.9, 1.0, 1.8, 2.5, 3.1],
        ] {
            let ys: Vec<f64> = ts.iter().map(|&t| f(t)).collect();
            let s = CubicSpline::new(&ts, &ys).unwrap();
            for k in 0..=100 {
                let t = ts[0] + (ts[ts.len() - 1] - ts[0]) * k as f64 / 100.0;
                let [y, dy, ddy] = s.eval_all(t);
                assert!((y - f(t)).abs() < 1e-12, "{t}: {y} vs {}", f(t));
                assert!((dy - df(t)).abs() < 1e-11);
                assert!((ddy - ddf(t)).abs() < 1e-10);
            }
        }
    }

    /// C² continuity at the knots and O(log n) interval lookup consistency.
    #[test]
    fn spline_is_c2_and_interpolates() {
        let ts: Vec<f64> = (0..20).map(|i| (i as f64).powf(1.3)).collect();
        let ys: Vec<f64> = ts.iter().map(|t| (0.4 * t).sin()).collect();
        let s = CubicSpline::new(&ts, &ys).unwrap();
        for i in 0..ts.len() {
            assert!((s.value(ts[i]) - ys[i]).abs() < 1e-13);
        }
        for &t in &ts[1..ts.len() - 1] {
            let e = 1e-9;
            let (l, r) = (s.eval_all(t - e), s.eval_all(t + e));
            assert!((l[1] - r[1]).abs() < 1e-7);
            assert!((l[2] - r[2]).abs() < 1e-6);
        }
        assert_eq!(s.interval(-5.0), 0);
        assert_eq!(s.interval(1e9), ts.len() - 2);
        assert_eq!(s.interval(ts[3]), 3);
    }

    #[test]
    fn spline_rejects_bad_input() {
        assert!(matches!(
            CubicSpline::new(&[0.0, 1.0, 2.0], &[0.0; 3]),
            Err(ProfileError::TooFewPoints { .. })
        ));
        assert!(matches!(
            CubicSpline::new(&[0.0, 1.0, 1.0, 2.0], &[0.0; 4]),
            Err(ProfileError::NonMonotonic { line: 3, .. })
        ));
        assert!(matches!(
            CubicSpline::new(&[0.0, 1.0, 2.0, 3.0], &[0.0, f64::NAN, 0.0, 0.0]),
            Err(ProfileError::NotFinite { line: 2, .. })
        ));
    }

    /// The S1002 pieces join within 2e-4 mm (measured worst: 1.18e-4 mm at C|D, y = −35;
    /// 3.7e-5 mm at B|C; the others below 1e-7 mm).
    #[test]
    fn s1002_pieces_join() {
        let secs = ['H', 'G', 'F', 'E', 'D', 'C', 'B', 'A'];
        let mut worst: f64 = 0.0;
        for k in 1..8 {
            let y = S1002_BREAKPOINTS_MM[k];
            let jump =
                s1002_section_height_mm(secs[k - 1], y) - s1002_section_height_mm(secs[k], y);
            worst = worst.max(jump.abs());
        }
        assert!(worst < 2e-4, "worst join {worst} mm");
        assert!(worst > 1e-4, "the published data join to about 1e-4 mm");
    }

    /// Flange tip 28 mm high at y = −55 mm (the maximum of F); section E a 70° line.
    #[test]
    fn s1002_flange_tip_and_face() {
        assert!((s1002_height_mm(-55.0) - 28.0).abs() < 1e-12);
        let max = (0..=1300)
            .map(|k| s1002_height_mm(-70.0 + 0.1 * k as f64))
            .fold(f64::MIN, f64::max);
        assert!((max - 28.0).abs() < 1e-9);
        // Section E: F = −93.58 − 2.7475 y, slope angle atan(2.7475) = 70.000°.
        let slope = (s1002_height_mm(-39.5) - s1002_height_mm(-38.5)) / (-1.0);
        assert!((slope.abs().atan().to_degrees() - 70.0).abs() < 1e-6);
        // The wheel profile: the tip is the lowest point, 28 mm below the origin.
        let w = WheelProfile::s1002(DEFAULT_WHEEL_POINTS);
        let sp = w.spline();
        let (t0, t1) = sp.domain();
        let lowest = (0..=20_000)
            .map(|k| sp.point(t0 + (t1 - t0) * k as f64 / 20_000.0).y)
            .fold(f64::MAX, f64::min);
        assert!((lowest + 0.028).abs() < 1e-6, "tip z = {lowest}");
        // At y = 0 the spline passes through z = 0 (F(0) = 0).
        assert!(w.points()[0].x < w.points()[w.points().len() - 1].x);
    }

    /// The S1002 spline follows the analytic profile between its points: with 201 points
    /// (about 0.85 mm apart) the vertical error at mid-interval is below 1e-3 mm (measured
    /// 7.6e-4 mm, at the G|H join) except around section E, where the straight 70° face
    /// meets the R13 and R20 arcs (a curvature jump the C² spline smooths) and a vertical
    /// error is 1/cos 70° ≈ 2.9 times the normal error: measured 2.7e-3 mm vertical there.
    #[test]
    fn s1002_spline_accuracy() {
        let w = WheelProfile::s1002(DEFAULT_WHEEL_POINTS);
        let sp = w.spline();
        let (mut worst, mut away): (f64, f64) = (0.0, 0.0);
        for i in 0..sp.points().len() - 1 {
            let t = 0.5 * (sp.knots()[i] + sp.knots()[i + 1]);
            let p = sp.point(t);
            let y_mm = p.x * 1e3;
            if (-69.5..59.5).contains(&y_mm) {
                let e = (-s1002_height_mm(y_mm) * 1e-3 - p.y).abs();
                let near_e = (-40.5..-37.5).contains(&y_mm);
                if !near_e {
                    away = away.max(e);
                }
                worst = worst.max(e);
            }
        }
        eprintln!("S1002 spline: worst vertical error {worst:.3e} m, away from E {away:.3e} m");
        assert!(worst < 3e-6, "worst mid-interval error {worst} m");
        assert!(away < 1e-6, "worst error away from section E {away} m");
    }

    #[test]
    fn uic60_head_geometry() {
        let arcs = uic60_arcs();
        // The arcs join (the published centres are given to 0.1 µm, so within 1e-3 mm).
        for w in arcs.windows(2) {
            let gap = (w[0].at(w[0].length()) - w[1].at(0.0)).norm();
            assert!(gap < 1e-3, "join gap {gap} mm");
        }
        let r = RailProfile::uic60(DEFAULT_RAIL_NODES, Inclination::None);
        let n = r.nodes();
        assert_eq!(n.len(), DEFAULT_RAIL_NODES);
        // (−36, −14.3) is 13.0002 mm from the R13 centre: the arc starts 0.2 µm from it.
        assert!((n[0] - v(-0.036, -0.0143)).norm() < 1e-6);
        assert!((n[n.len() - 1] - v(0.036, -0.0143)).norm() < 1e-6);
        // Odd node count: the middle node is the top centre.
        assert!(n[n.len() / 2].norm() < 1e-12);
        assert!(n.windows(2).all(|w| w[1].x > w[0].x));
        // Symmetric.
        for i in 0..n.len() {
            let m = n[n.len() - 1 - i];
            assert!((n[i].x + m.x).abs() < 1e-9 && (n[i].y - m.y).abs() < 1e-9);
        }
        // Outward normal at the top points up.
        assert!((r.outward_normals()[n.len() / 2] - v(0.0, 1.0)).norm() < 1e-12);
        // The mirrored upright head is itself.
        let m = r.mirrored();
        for (a, b) in m.nodes().iter().zip(n) {
            assert!((a - b).norm() < 1e-9);
        }
    }

    /// 1:40 turns the head towards the gauge side (−y): the gauge corner drops, the field
    /// side rises, the top normal leans to −y by atan(1/40).
    #[test]
    fn inclination_leans_to_the_gauge_side() {
        let up = RailProfile::uic60(41, Inclination::None);
        let inc = RailProfile::uic60(41, Inclination::OneIn40);
        let (n0, n1) = (up.nodes(), inc.nodes());
        assert!(n1[5].y < n0[5].y);
        assert!(n1[35].y > n0[35].y);
        let top = inc.outward_normals()[20];
        assert!((top.x / top.y + 1.0 / 40.0).abs() < 1e-12);
        // 1:20 makes the gauge-side flank vertical but y still increases strictly.
        let steep = RailProfile::uic60(41, Inclination::OneIn20);
        assert!(steep.nodes().windows(2).all(|w| w[1].x > w[0].x));
        // The mirror of the inclined right rail leans the other way (towards +y).
        let m = inc.mirrored();
        let top = m.outward_normals()[20];
        assert!((top.x / top.y - 1.0 / 40.0).abs() < 1e-12);
    }

    #[test]
    fn mirrored_wheel_keeps_material_on_the_left() {
        let w = WheelProfile::s1002(101);
        let m = w.mirrored();
        // Tread near the nominal point: tangent along the parameter turned +90° points up.
        let sp = m.spline();
        let (t0, t1) = sp.domain();
        let mut t_best = t0;
        for k in 0..=1000 {
            let t = t0 + (t1 - t0) * k as f64 / 1000.0;
            if sp.point(t).x.abs() < sp.point(t_best).x.abs() {
                t_best = t;
            }
        }
        let tan = sp.unit_tangent(t_best);
        let left = v(-tan.y, tan.x);
        assert!(left.y > 0.99);
        // The mirrored flange is at +y.
        assert!(m.points().iter().any(|p| p.x > 0.065));
        assert!((m.mirrored().points()[7] - w.points()[7]).norm() < 1e-15);
    }

    #[test]
    fn csv_reading() {
        let text = "# S1002 excerpt\n# units: mm\n-10, 0.5\n0,0\n10,-0.3\n20,-0.6\n";
        let w = WheelProfile::from_csv_str(text, "w.csv").unwrap();
        assert!((w.points()[2] - v(0.010, -0.0003)).norm() < 1e-15);
        let text = "y_m,z_m\n0.02,-0.0006\n0.01,-0.0003\n0,0\n-0.01,0.0005\n";
        let w = WheelProfile::from_csv_str(text, "w.csv").unwrap();
        // Reversed so that the flange side comes first.
        assert!((w.points()[0] - v(-0.01, 0.0005)).norm() < 1e-15);
        let r = RailProfile::from_csv_str(
            "y_mm,z_mm\n-30,-5\n-10,-0.2\n0,0\n10,-0.2\n30,-5\n",
            "r.csv",
            Inclination::None,
        )
        .unwrap();
        assert_eq!(r.nodes().len(), 5);
    }

    #[test]
    fn a_point_beyond_a_metre_names_its_row_and_column() {
        // 1500 mm = 1.5 m from the origin: beyond any cross-section, a unit slip.
        let e = WheelProfile::from_csv_str("\u{feff}y_mm,z_mm\n0,0\n1500,1\n", "a.csv")
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("a.csv:3: column `y` = 1500 mm is beyond ±1 m (1000 mm)"),
            "{e}"
        );
    }

    #[test]
    fn csv_errors_are_clear() {
        let e = WheelProfile::from_csv_str("0,0\n1,1\n2,2\n3,3\n", "a.csv").unwrap_err();
        assert!(matches!(e, ProfileError::UnknownUnits { line: 1, .. }));
        let msg = e.to_string();
        assert!(msg.starts_with("a.csv:1: unknown units") && msg.contains("fix:"));
        assert!(!msg.contains('\n'));
        let e = WheelProfile::from_csv_str("# units: inch\n0,0\n", "a.csv").unwrap_err();
        assert!(matches!(e, ProfileError::UnknownUnits { line: 1, .. }));
        let e = WheelProfile::from_csv_str("y_mm,z_m\n0,0\n", "a.csv").unwrap_err();
        assert!(matches!(e, ProfileError::UnknownUnits { line: 1, .. }));
        let e = WheelProfile::from_csv_str("# units: m\n0,0\n0.01,0.01\n0.02,0.02\n", "a.csv")
            .unwrap_err();
        assert!(matches!(
            e,
            ProfileError::TooFewPoints {
                line: 4,
                count: 3,
                ..
            }
        ));
        let e =
            WheelProfile::from_csv_str("# units: m\n0,0\n1,NaN\n2,2\n3,3\n", "a.csv").unwrap_err();
        assert!(matches!(e, ProfileError::NotFinite { line: 3, .. }));
        let e =
            WheelProfile::from_csv_str("# units: m\n0,0\n1;1\n2,2\n3,3\n", "a.csv").unwrap_err();
        assert!(matches!(e, ProfileError::Parse { line: 3, .. }));
        // A bow tie: segment 1-2 crosses segment 3-4.
        let e =
            WheelProfile::from_csv_str("# units: m\n0,0\n1,1\n1,0\n0,1\n", "a.csv").unwrap_err();
        assert!(matches!(
            e,
            ProfileError::SelfIntersecting {
                line: 3,
                other: 5,
                ..
            }
        ));
        // Folding back on itself.
        let e = WheelProfile::from_csv_str("# units: m\n0,0\n0.1,0\n0.05,0\n0.2,0.1\n", "a.csv")
            .unwrap_err();
        assert!(matches!(e, ProfileError::SelfIntersecting { .. }));
        let e = RailProfile::from_csv_str(
            "# units: mm\n-30,-5\n-10,-0.2\n-12,0\n10,-0.2\n30,-5\n",
            "r.csv",
            Inclination::None,
        )
        .unwrap_err();
        assert!(matches!(e, ProfileError::NonMonotonic { line: 4, .. }));
        let e = RailProfile::from_csv_file("/nonexistent/rail.csv", Inclination::None).unwrap_err();
        assert!(matches!(e, ProfileError::Io { .. }));
        let e = WheelProfile::from_csv_str("# units: m\n0,0\n0.1,0\n0.1,0\n0.2,0.1\n", "a.csv")
            .unwrap_err();
        assert!(matches!(e, ProfileError::RepeatedPoint { line: 4, .. }));
        // Millimetres declared as metres, within the ±1 m bound: a 1.2 m wide rail head.
        let e = RailProfile::from_csv_str(
            "# units: m\n-0.6,-0.1\n-0.2,-0.004\n0,0\n0.2,-0.004\n0.6,-0.1\n",
            "r.csv",
            Inclination::None,
        )
        .unwrap_err();
        assert!(
            matches!(e, ProfileError::ImplausibleWidth { line: 6, .. }),
            "{e}"
        );
        assert!(e.to_string().contains("check the units"));
        // Metres declared as millimetres: a 0.13 mm wide wheel.
        let e = WheelProfile::from_csv_str(
            "y_mm,z_mm\n-0.07,0.03\n-0.06,0.02\n0,0\n0.06,-0.0005\n",
            "w.csv",
        )
        .unwrap_err();
        assert!(matches!(e, ProfileError::ImplausibleWidth { .. }), "{e}");
    }
}

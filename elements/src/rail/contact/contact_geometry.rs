//! The contact search primitive of the moving-axle element (Ju & Ro 2021, Sections 2.3 and
//! 3.2; Ju 1998's node-to-cubic-spline contact): the closest point on the wheel's profile
//! spline to a rail node, the wheel's outward normal and tangent there, the signed gap, and
//! the O(log n) window of rail nodes that can touch a wheel. What lives here are pure
//! functions over 2-D geometry (`nalgebra::Vector2`, metres) in one cross-section plane;
//! what does not: mapping 3-D positions into that plane, contact forces and stiffness (the
//! moving-axle element does those).
//!
//! # Conventions
//!
//! - Coordinates `[y, z]` (m) in the wheel's cross-section plane, as in
//!   [`crate::rail::contact::profiles`]; the wheel curve and the rail node must be in the same frame.
//! - The wheel material lies on the **left** of the curve traversed with increasing
//!   parameter (this is how [`WheelProfile`](crate::rail::contact::profiles::WheelProfile) stores it).
//!   The **outward normal** `n` points out of the wheel material, towards the rail: it is
//!   the unit tangent `τ = c'/|c'|` turned clockwise by 90°, `n = (τ_z, −τ_y)`. On a flat
//!   tread traversed towards +y, `τ = (1, 0)` and `n = (0, −1)` (down, towards the rail).
//! - The **signed gap** of a rail node `p` is `g = (p − c(t*))·n(t*)` with `t*` the closest
//!   point: positive when the node is outside the wheel (open gap), negative when it has
//!   penetrated, `|g|` the distance to the curve. A rail node is a contact point when
//!   `g ≤ 0`.
//! - The tangent returned is `τ`, along increasing parameter; `(τ, n)` is a left-handed
//!   pair in the `(y, z)` plane (`τ × n = −1`), i.e. `n` is `τ` turned clockwise.

use crate::rail::contact::profiles::ParametricSpline;
use nalgebra::Vector2;
use std::ops::Range;

/// Where the closest point lies on the curve.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Projection {
    /// A stationary point of the distance inside the curve: `(c − p)·c' = 0`.
    Interior,
    /// The node projects beyond the start of the curve; the closest point is clamped to it.
    ClampedStart,
    /// The node projects beyond the end of the curve; the closest point is clamped to it.
    ClampedEnd,
}

/// The closest point on a curve to a given point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ClosestPoint {
    /// Spline parameter `t*` (chord length, m).
    pub t: f64,
    /// The point `c(t*)` (m).
    pub point: Vector2<f64>,
    /// The distance `|p − c(t*)|` (m).
    pub distance: f64,
    /// Interior or clamped to an end.
    pub projection: Projection,
    /// Newton / bisection iterations spent (for diagnostics).
    pub iterations: usize,
}

/// A rail node measured against the wheel curve: closest point, frame and signed gap.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WheelContactPoint {
    /// Spline parameter of the closest point (chord length, m).
    pub t: f64,
    /// The closest point on the wheel surface (m).
    pub point: Vector2<f64>,
    /// Outward unit normal of the wheel surface there (out of the wheel, towards the rail).
    pub normal: Vector2<f64>,
    /// Unit tangent along increasing parameter (`normal` is it turned clockwise by 90°).
    pub tangent: Vector2<f64>,
    /// Signed gap `(p − point)·normal` (m): negative = penetration.
    pub gap: f64,
}

/// Outward unit normal of a wheel curve at parameter `t` (the unit tangent turned
/// clockwise by 90°; see the module conventions).
pub fn outward_normal(curve: &ParametricSpline, t: f64) -> Vector2<f64> {
    let tau = curve.unit_tangent(t);
    Vector2::new(tau.y, -tau.x)
}

/// `f(t) = (c(t) − p)·c'(t)` (half the derivative of the squared distance) and its
/// derivative `f'(t) = |c'|² + (c − p)·c''`; `near` is the spline interval `t` probably
/// lies in (checked, so only the speed depends on it: the search below knows it).
fn stationarity(curve: &ParametricSpline, p: Vector2<f64>, t: f64, near: usize) -> (f64, f64) {
    let [c, d1, d2] = curve.eval_in(curve.interval_near(t, near), t);
    let r = c - p;
    (r.dot(&d1), d1.norm_squared() + r.dot(&d2))
}

/// The point `c(t)`, with the interval guess `near` as in [`stationarity`].
fn point_near(curve: &ParametricSpline, t: f64, near: usize) -> Vector2<f64> {
    curve.eval_in(curve.interval_near(t, near), t)[0]
}

/// Closest point of the segment `[a, b]` to `p`, as the fraction `u ∈ [0, 1]` and the
/// squared distance.
fn segment_projection(a: Vector2<f64>, b: Vector2<f64>, p: Vector2<f64>) -> (f64, f64) {
    let ab = b - a;
    let u = ((p - a).dot(&ab) / ab.norm_squared()).clamp(0.0, 1.0);
    (u, (a + u * ab - p).norm_squared())
}

/// Safeguarded Newton for a root of `f` in `[lo, hi]` where `f(lo) < 0 < f(hi)` (a
/// minimum of the distance), started at `t0`. A Newton step that leaves the bracket, or a
/// non-positive `f'`, is replaced by bisection; the bracket shrinks by the sign of `f`.
fn newton_in_bracket(
    curve: &ParametricSpline,
    p: Vector2<f64>,
    (mut lo, mut hi): (f64, f64),
    t0: f64,
    near: usize,
) -> (f64, usize) {
    let tol = 1e-15 * (1.0 + curve.domain().1.abs());
    let mut t = t0.clamp(lo, hi);
    for it in 1..=100 {
        let (f, fp) = stationarity(curve, p, t, near);
        if f == 0.0 {
            return (t, it);
        }
        if f < 0.0 {
            lo = t;
        } else {
            hi = t;
        }
        let newton = t - f / fp;
        let next = if fp > 0.0 && newton > lo && newton < hi {
            newton
        } else {
            0.5 * (lo + hi)
        };
        if (next - t).abs() <= tol || hi - lo <= tol {
            return (next, it);
        }
        t = next;
    }
    (t, 100)
}

/// The closest point on `curve` to `p` (m). Search: the nearest segment of the polyline
/// through the spline's points (O(n)); then on that interval and its two neighbours, a
/// guarded Newton iteration on `(c(t) − p)·c'(t) = 0` inside every interval where that
/// function changes sign from − to + (a distance minimum), bisection as the fallback;
/// the interval ends are candidates too. If the best candidate is at the edge of the
/// window the window grows towards it until a minimum is enclosed or an end of the curve
/// is reached (then the result is [`Projection::ClampedStart`] / `ClampedEnd`).
///
/// This finds the local distance minimum next to the nearest polyline segment, which is
/// the global one for nodes closer to the curve than its local radius of curvature (all
/// contact candidates). Returns `None` only if `p` is not finite. Never panics.
pub fn closest_point(curve: &ParametricSpline, p: Vector2<f64>) -> Option<ClosestPoint> {
    closest_point_near(curve, p, None)
}

/// [`closest_point`] started from the spline interval `hint` (the one found for this node
/// at the previous evaluation) instead of a scan of every segment: O(1) when the node has
/// moved little, which is the case between Newton iterations. The window grows from the
/// hint exactly as it grows from the scanned segment, so the result is the local distance
/// minimum next to the hint.
pub fn closest_point_near(
    curve: &ParametricSpline,
    p: Vector2<f64>,
    hint: Option<usize>,
) -> Option<ClosestPoint> {
    if !p.x.is_finite() || !p.y.is_finite() {
        return None;
    }
    let pts = curve.points();
    let knots = curve.knots();
    let n_seg = pts.len() - 1;
    let (seg, seg_u) = match hint {
        Some(h) if h < n_seg => (h, segment_projection(pts[h], pts[h + 1], p).0),
        _ => {
            let (mut seg, mut seg_u, mut best_d2) = (0, 0.0, f64::INFINITY);
            for i in 0..n_seg {
                let (u, d2) = segment_projection(pts[i], pts[i + 1], p);
                if d2 < best_d2 {
                    (seg, seg_u, best_d2) = (i, u, d2);
                }
            }
            (seg, seg_u)
        }
    };
    let t_seed = knots[seg] + seg_u * (knots[seg + 1] - knots[seg]);
    let (mut first, mut last) = (seg.saturating_sub(1), (seg + 1).min(n_seg - 1));
    let mut iterations = 0;
    loop {
        // Candidates: every knot in the window and the interior minima.
        let mut best = (f64::INFINITY, knots[first]);
        let consider = |t: f64, near: usize, best: &mut (f64, f64)| {
            let d2 = (point_near(curve, t, near) - p).norm_squared();
            if d2 < best.0 {
                *best = (d2, t);
            }
        };
        // Squared distance and `f` at knot `k`, from one evaluation of the spline there (a
        // knot belongs to the interval it starts, the last knot to the last one). Each
        // knot is evaluated once: the end of one interval is the start of the next, and
        // considering the same point twice changes nothing.
        let at_knot = |k: usize| {
            let t = knots[k];
            let [c, d1, _] = curve.eval_in(curve.interval_near(t, k.min(n_seg - 1)), t);
            let r = c - p;
            (r.norm_squared(), r.dot(&d1))
        };
        let (mut d2a, mut fa) = at_knot(first);
        for i in first..=last {
            let (a, b) = (knots[i], knots[i + 1]);
            if d2a < best.0 {
                best = (d2a, a);
            }
            let (d2b, fb) = at_knot(i + 1);
            if d2b < best.0 {
                best = (d2b, b);
            }
            if fa < 0.0 && fb > 0.0 {
                let t0 = if i == seg { t_seed } else { 0.5 * (a + b) };
                let (t, it) = newton_in_bracket(curve, p, (a, b), t0, i);
                iterations += it;
                consider(t, i, &mut best);
            }
            (d2a, fa) = (d2b, fb);
        }
        let mut t = best.1;
        let (mut f, _) = stationarity(curve, p, t, seg);
        // A knot at which the distance still falls into a segment of the window: that
        // segment holds a lower point its end values did not bracket (a coarse, wiggly
        // spline: f goes −, +, − across it). Find the first sign change from the knot's side
        // on a fine subdivision and refine it.
        if let Some(k) = (first..=last + 1).find(|&k| knots[k] == t) {
            // The segment walked into, and its interval.
            let inward = if f < 0.0 && k <= last {
                Some((knots[k], knots[k + 1], k))
            } else if f > 0.0 && k > first {
                Some((knots[k], knots[k - 1], k - 1))
            } else {
                None
            };
            if let Some((from, to, interval)) = inward {
                const PARTS: usize = 16;
                let mut prev = (from, f);
                for j in 1..=PARTS {
                    let s = from + (to - from) * j as f64 / PARTS as f64;
                    let fs = stationarity(curve, p, s, interval).0;
                    // Forward (f < 0 at the knot): a minimum where f turns positive;
                    // backward (f > 0): where f, walking back, turns negative.
                    let turned = if f < 0.0 { fs >= 0.0 } else { fs <= 0.0 };
                    if turned {
                        let (lo, hi) = if from < to { (prev.0, s) } else { (s, prev.0) };
                        let (tm, it) =
                            newton_in_bracket(curve, p, (lo, hi), 0.5 * (lo + hi), interval);
                        iterations += it;
                        consider(tm, interval, &mut best);
                        break;
                    }
                    prev = (s, fs);
                }
                t = best.1;
                f = stationarity(curve, p, t, interval).0;
            }
        }
        // Grow the window if the best is its edge knot and the distance falls outwards.
        if t == knots[first] && first > 0 && f > 0.0 {
            first -= 1;
            continue;
        }
        if t == knots[last + 1] && last + 1 < n_seg && f < 0.0 {
            last += 1;
            continue;
        }
        let projection = if t == knots[0] && f > 0.0 {
            Projection::ClampedStart
        } else if t == knots[n_seg] && f < 0.0 {
            Projection::ClampedEnd
        } else {
            Projection::Interior
        };
        let point = curve.point(t);
        return Some(ClosestPoint {
            t,
            point,
            distance: (point - p).norm(),
            projection,
            iterations,
        });
    }
}

/// Measures rail node `p` against the wheel curve: closest point, outward normal, tangent
/// and signed gap (negative = penetration), all in the common cross-section frame (m).
///
/// Returns `None` when `p` is not finite or projects beyond either end of the wheel curve
/// (the closest point is then an end point, where the normal does not carry the gap: the
/// node is outside the modelled part of the wheel and cannot be a contact point). Points
/// far from the wheel get `Some` with a large positive (or negative) gap.
pub fn rail_node_gap(wheel: &ParametricSpline, p: Vector2<f64>) -> Option<WheelContactPoint> {
    rail_node_gap_near(wheel, p, None)
}

/// [`rail_node_gap`] with the search started from spline interval `hint`
/// (see [`closest_point_near`]).
pub fn rail_node_gap_near(
    wheel: &ParametricSpline,
    p: Vector2<f64>,
    hint: Option<usize>,
) -> Option<WheelContactPoint> {
    let cp = closest_point_near(wheel, p, hint)?;
    if cp.projection != Projection::Interior {
        return None;
    }
    let tangent = wheel.unit_tangent(cp.t);
    let normal = Vector2::new(tangent.y, -tangent.x);
    Some(WheelContactPoint {
        t: cp.t,
        point: cp.point,
        normal,
        tangent,
        gap: (p - cp.point).dot(&normal),
    })
}

/// The index range of rail nodes (sorted by strictly increasing lateral coordinate `y`)
/// whose `y` lies in `[y_min, y_max]` (m): the only nodes that can touch a wheel whose
/// lateral extent (with any margin the caller adds) is that interval. Two binary searches,
/// O(log n). An empty or inverted interval gives an empty range.
pub fn candidate_window(rail_nodes: &[Vector2<f64>], y_min: f64, y_max: f64) -> Range<usize> {
    let lo = rail_nodes.partition_point(|q| q.x < y_min);
    let hi = rail_nodes.partition_point(|q| q.x <= y_max);
    lo..hi.max(lo)
}

/// A rail node in contact with the wheel: its index and its measurement.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NodeContact {
    /// Index of the rail node.
    pub node: usize,
    /// Closest point, frame and gap (`gap ≤ gap_tolerance`).
    pub contact: WheelContactPoint,
}

/// All rail nodes (sorted by `y`, same frame as the wheel) with gap `≤ gap_tolerance` (m;
/// 0 for touching or penetrating nodes, a small positive value to pre-select nodes about
/// to touch). Only nodes inside the wheel's lateral extent widened by `margin` (m) are
/// measured ([`candidate_window`]).
pub fn contact_nodes(
    wheel: &ParametricSpline,
    rail_nodes: &[Vector2<f64>],
    margin: f64,
    gap_tolerance: f64,
) -> Vec<NodeContact> {
    let (y0, y1) = wheel.lateral_extent();
    candidate_window(rail_nodes, y0 - margin, y1 + margin)
        .filter_map(|i| {
            let c = rail_node_gap(wheel, rail_nodes[i])?;
            (c.gap <= gap_tolerance).then_some(NodeContact {
                node: i,
                contact: c,
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::super::profiles::{
        s1002_height_mm, Inclination, RailProfile, WheelProfile, DEFAULT_WHEEL_POINTS,
    };
    use super::*;

    const R: f64 = 0.43;

    /// A "wheel" that is a circle of radius R = 0.43 m centred at (0, R): its lowest point
    /// is the origin; `n` points over the angle range ±`half` about the bottom, traversed
    /// towards +y (counter-clockwise), so the material (the disc) is on the left.
    fn circle_wheel(n: usize, half: f64) -> ParametricSpline {
        let c = Vector2::new(0.0, R);
        let pts: Vec<Vector2<f64>> = (0..n)
            .map(|k| {
                let a =
                    -std::f64::consts::FRAC_PI_2 - half + 2.0 * half * k as f64 / (n - 1) as f64;
                c + R * Vector2::new(a.cos(), a.sin())
            })
            .collect();
        ParametricSpline::new(&pts).unwrap()
    }

    /// Against a circle the exact gap is `|p − centre| − R` and the exact outward normal
    /// `(p − centre)/|p − centre|`. With 41 points over ±0.2 rad (4.3 mm apart) the spline
    /// gap is within 1e-10 m of exact for nodes from 20 mm outside to 10 mm inside, over
    /// the interior of the arc (measured worst about 2e-11 m; the radial error of a
    /// chord-length not-a-knot spline on a circle falls as h⁴).
    #[test]
    fn circle_gap_is_exact_to_spline_accuracy() {
        let sp = circle_wheel(41, 0.2);
        let centre = Vector2::new(0.0, R);
        let mut worst: f64 = 0.0;
        let mut worst_n: f64 = 0.0;
        for k in 0..=60 {
            let a = -std::f64::consts::FRAC_PI_2 - 0.18 + 0.36 * k as f64 / 60.0;
            let dir = Vector2::new(a.cos(), a.sin());
            for off in [-0.010, -0.001, 0.0, 0.0005, 0.005, 0.020] {
                let p = centre + (R + off) * dir;
                let c = rail_node_gap(&sp, p).expect("interior");
                worst = worst.max((c.gap - off).abs());
                worst_n = worst_n.max((c.normal - dir).norm());
            }
        }
        assert!(worst < 1e-10, "worst gap error {worst} m");
        assert!(worst_n < 5e-8, "worst normal error {worst_n}");
        eprintln!("circle: worst gap error {worst:.3e} m, normal {worst_n:.3e}");
    }

    /// Halving the point spacing cuts the worst radial error by about 16 (h⁴).
    #[test]
    fn circle_error_converges_fourth_order() {
        let err = |n: usize| {
            let sp = circle_wheel(n, 0.2);
            let centre = Vector2::new(0.0, R);
            (0..=200)
                .map(|k| {
                    let a = -std::f64::consts::FRAC_PI_2 - 0.15 + 0.30 * k as f64 / 200.0;
                    let p = centre + R * Vector2::new(a.cos(), a.sin());
                    rail_node_gap(&sp, p).unwrap().gap.abs()
                })
                .fold(0.0, f64::max)
        };
        let (e1, e2) = (err(11), err(21));
        let ratio = e1 / e2;
        eprintln!("circle errors {e1:.3e} (11 pts), {e2:.3e} (21 pts), ratio {ratio:.1}");
        assert!(ratio > 12.0, "ratio {ratio}");
    }

    #[test]
    fn flat_tread_normals_and_gaps() {
        let pts: Vec<Vector2<f64>> = (0..6)
            .map(|k| Vector2::new(-0.02 + 0.01 * k as f64, 0.0))
            .collect();
        let sp = ParametricSpline::new(&pts).unwrap();
        for (p, g) in [
            (Vector2::new(0.003, -0.002), 0.002),
            (Vector2::new(-0.011, 0.0005), -0.0005),
            (Vector2::new(0.0, 0.0), 0.0),
        ] {
            let c = rail_node_gap(&sp, p).unwrap();
            assert!((c.normal - Vector2::new(0.0, -1.0)).norm() < 1e-14);
            assert!((c.tangent - Vector2::new(1.0, 0.0)).norm() < 1e-14);
            assert!((c.gap - g).abs() < 1e-15, "{} vs {g}", c.gap);
            assert!((c.point.x - p.x).abs() < 1e-15);
        }
    }

    /// On section E of S1002 (the 70° flange face, −39.76 < y < −38.43 mm) the face that
    /// meets the rail's gauge corner looks towards +y (the rail lies on the field side of
    /// the flange) and down, so the outward normal is (sin 70°, −cos 70°): 70° from the
    /// downward vertical. Measured with 201 points: 70.01° (the C² spline rounds the
    /// 3.9 mm long straight face into its neighbouring arcs).
    #[test]
    fn s1002_flange_face_normal_is_70_degrees() {
        let w = WheelProfile::s1002(DEFAULT_WHEEL_POINTS);
        let sp = w.spline();
        let y = -39.1; // mid section E, mm
        let on = Vector2::new(y * 1e-3, -s1002_height_mm(y) * 1e-3);
        let expected = Vector2::new(70f64.to_radians().sin(), -70f64.to_radians().cos());
        // A node 0.5 mm outside the face along the normal.
        let p = on + 0.0005 * expected;
        let c = rail_node_gap(sp, p).unwrap();
        let angle = c.normal.x.atan2(-c.normal.y).to_degrees();
        eprintln!(
            "S1002 face: normal {angle:.4}° from the downward vertical, gap {:.3e}",
            c.gap
        );
        assert!((angle - 70.0).abs() < 0.05, "{angle}");
        assert!((c.gap - 0.0005).abs() < 1e-7);
        // A point exactly on the surface (a spline knot) has zero gap.
        let k = sp.points()[100];
        let c = rail_node_gap(sp, k).unwrap();
        assert!(c.gap.abs() < 1e-15 && (c.point - k).norm() < 1e-15);
        // And on the tread at y = 0: F(0) = 0, normal nearly straight down.
        // The exact distance to the analytic profile by a fine scan (y step 1e-5 mm).
        let p = Vector2::new(0.0, -0.001);
        let c = rail_node_gap(sp, p).unwrap();
        let expected = (0..=400_000)
            .map(|k| {
                let y = -2.0 + 1e-5 * k as f64;
                (Vector2::new(y * 1e-3, -s1002_height_mm(y) * 1e-3) - p).norm()
            })
            .fold(f64::INFINITY, f64::min);
        eprintln!("S1002 tread: gap {:.6e}, exact {expected:.6e}", c.gap);
        assert!((c.gap - expected).abs() < 1e-9, "{}", c.gap - expected);
        assert!(c.normal.y < -0.999);
    }

    #[test]
    fn robust_far_away_and_at_the_ends() {
        let w = WheelProfile::s1002(101);
        let sp = w.spline();
        // Beyond the field-side end: clamped, no gap.
        let cp = closest_point(sp, Vector2::new(0.2, 0.0)).unwrap();
        assert_eq!(cp.projection, Projection::ClampedEnd);
        assert!(rail_node_gap(sp, Vector2::new(0.2, 0.0)).is_none());
        // Beyond the flange back.
        let cp = closest_point(sp, Vector2::new(-0.2, -0.0095)).unwrap();
        assert_eq!(cp.projection, Projection::ClampedStart);
        // Far below: a large positive gap, no panic.
        let c = rail_node_gap(sp, Vector2::new(0.0, -1e3)).unwrap();
        assert!(c.gap > 999.0);
        // Far above (deep inside the wheel): negative gap.
        let c = rail_node_gap(sp, Vector2::new(0.01, 0.5)).unwrap();
        assert!(c.gap < -0.4);
        assert!(closest_point(sp, Vector2::new(f64::NAN, 0.0)).is_none());
        assert!(rail_node_gap(sp, Vector2::new(0.0, f64::INFINITY)).is_none());
        // Exactly the end points.
        let pts = sp.points();
        for p in [pts[0], pts[pts.len() - 1]] {
            let cp = closest_point(sp, p).unwrap();
            assert!(cp.distance < 1e-15);
        }
    }

    #[test]
    fn window_is_the_lateral_overlap() {
        let rail = RailProfile::uic60(41, Inclination::None);
        let nodes = rail.nodes();
        let r = candidate_window(nodes, -0.010, 0.010);
        assert!(r.clone().all(|i| nodes[i].x.abs() <= 0.010));
        assert!(r.start == 0 || nodes[r.start - 1].x < -0.010);
        assert!(r.end == nodes.len() || nodes[r.end].x > 0.010);
        assert!(candidate_window(nodes, 1.0, 2.0).is_empty());
        assert!(candidate_window(nodes, 0.01, -0.01).is_empty());
        assert_eq!(candidate_window(nodes, -1.0, 1.0), 0..nodes.len());
    }

    /// The S1002 wheel lowered by 0.1 mm over the 60E1 head: on the tread, where the
    /// wheel is a function z_w(y) = −F(y), each rail node's signed gap has the sign of the
    /// vertical clearance z_w(y_p) − z_p and a magnitude between |n_z| (the cosine of the
    /// wheel's slope there) and 1 times it, up to the surface's curvature (0.1 % allowed);
    /// the nodes with gap ≤ 0 are exactly
    /// the ones with negative clearance.
    #[test]
    fn s1002_over_uic60_gap_signs() {
        let w = WheelProfile::s1002(DEFAULT_WHEEL_POINTS);
        let rail = RailProfile::uic60(61, Inclination::OneIn40);
        let drop = 0.0001;
        let lowered: Vec<Vector2<f64>> = w
            .points()
            .iter()
            .map(|p| p + Vector2::new(0.0, -drop))
            .collect();
        let sp = ParametricSpline::new(&lowered).unwrap();
        let contacts = contact_nodes(&sp, rail.nodes(), 0.001, 0.0);
        let mut checked = 0;
        for (i, p) in rail.nodes().iter().enumerate() {
            let y_mm = p.x * 1e3;
            if y_mm.abs() > 30.0 {
                continue;
            }
            let clearance = -s1002_height_mm(y_mm) * 1e-3 - drop - p.y;
            if clearance.abs() < 1e-7 {
                continue;
            }
            let c = rail_node_gap(&sp, *p).unwrap();
            assert_eq!(c.gap > 0.0, clearance > 0.0, "node {i}");
            assert!(c.gap.abs() <= clearance.abs() * (1.0 + 1e-6) + 1e-9);
            assert!(c.gap.abs() >= clearance.abs() * c.normal.y.abs() * 0.999 - 1e-9);
            assert_eq!(contacts.iter().any(|k| k.node == i), clearance < 0.0);
            checked += 1;
        }
        assert!(checked > 30);
        assert!(!contacts.is_empty());
    }
}

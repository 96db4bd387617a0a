//! Nonlinear force–deflection laws of one spring direction: a piecewise-linear
//! force table and a bump stop with a gap, shared by `spring_damper` and `suspension`.
//!
//! What does not live here: the elements' kinematics (how a deflection is measured), the
//! dashpots, and the linear path (an element with neither a table nor a bump stop in any
//! direction never builds a [`ForceLaw`] and keeps its constant stiffness).
//!
//! # The law
//!
//! In one direction with deflection `d` (m or rad; positive = extension, node J moving
//! along the positive local axis from I) the spring force is
//!
//! `F(d) = F_table(d) + F_stop(d)`, or `k·d + F_stop(d)` without a table,
//!
//! * `F_table` interpolates the points `(d_i, F_i)` linearly, and beyond the first or the
//!   last point continues with the slope of the first or the last segment. The table is
//!   used as given: it need not pass through `(0, 0)`; `F_table(0)` is a force the spring
//!   carries at zero deflection (an offset, like a preload).
//! * `F_stop` is zero inside the gap `−g_c ≤ d ≤ g_e` and a linear spring `k_s` beyond
//!   it: `k_s·(d + g_c)` for `d < −g_c` (compression), `k_s·(d − g_e)` for `d > g_e`
//!   (extension). The contact is not smoothed.
//!
//! The tangent `dF/dd` is the slope of the segment that contains `d` (the right-hand
//! segment at a breakpoint itself), so it is exact everywhere but on the kinks.
//!
//! **Why piecewise linear, not a monotone cubic.** A measured suspension curve is a list
//! of points; linear interpolation reproduces every point and adds no shape the data do
//! not have, and the force is monotone whenever the points are. The price is a tangent
//! that jumps at the kinks. Newton's method on a monotone piecewise-linear law still
//! converges: inside a segment the law is linear, so an iterate that lands in the
//! segment of the solution finishes in one more iteration, and the slopes are required to
//! be ≥ 0 (below) so the tangent never loses definiteness. A cubic would smooth the
//! tangent but move the force between the user's points.
//!
//! # Validation
//!
//! A table needs at least 2 points, at most [`MAX_TABLE_POINTS`], finite values,
//! strictly increasing deflections and non-decreasing forces (a falling force–deflection
//! curve is an unstable spring, refused rather than left to make Newton diverge). A bump
//! stop needs gaps ≥ 0 and `k ≥ 0`, finite. Direction names must be the element's own.

use railfem_framework::limits::{fmt_num, fmt_vec};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// Most points a force table may have (a size guard: a suspension curve is tens of
/// points; a table beyond this is a mistaken file, not a curve).
pub const MAX_TABLE_POINTS: usize = 10_000;

/// The gap of a bump stop: one number (the same on both sides) or `[compression,
/// extension]` (m or rad).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum Gap {
    /// The same gap in compression and extension.
    Both(f64),
    /// `[compression, extension]`.
    Sides([f64; 2]),
}

impl Gap {
    /// `(compression, extension)` gaps.
    pub fn sides(&self) -> (f64, f64) {
        match *self {
            Gap::Both(g) => (g, g),
            Gap::Sides([c, e]) => (c, e),
        }
    }
}

/// A `bump_stop` entry of one direction, as written in a model file.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BumpStopSpec {
    /// Free travel before the stop engages (m or rad).
    pub gap: Gap,
    /// Stiffness of the stop once engaged (N/m or N·m/rad).
    pub k: f64,
}

/// Force tables by direction name: `[[d, F], …]`.
pub type ForceTables = BTreeMap<String, Vec<[f64; 2]>>;
/// Bump stops by direction name.
pub type BumpStops = BTreeMap<String, BumpStopSpec>;

/// The force law of one direction. See the module documentation.
#[derive(Debug, Clone, PartialEq)]
pub struct ForceLaw {
    /// Linear rate used when there is no table (N/m or N·m/rad).
    k: f64,
    /// Table deflections (strictly increasing) and forces; empty = linear `k`.
    d: Vec<f64>,
    f: Vec<f64>,
    /// Bump stop: compression gap, extension gap, stiffness.
    stop: Option<(f64, f64, f64)>,
}

impl ForceLaw {
    /// A linear law `k·d` with no stop.
    pub fn linear(k: f64) -> ForceLaw {
        ForceLaw {
            k,
            d: Vec::new(),
            f: Vec::new(),
            stop: None,
        }
    }

    /// Force `F(d)` and tangent `dF/dd` at deflection `d`.
    pub fn force_and_tangent(&self, d: f64) -> (f64, f64) {
        let (mut f, mut k) = if self.d.is_empty() {
            (self.k * d, self.k)
        } else {
            // Segment j: [d_j, d_{j+1}], clamped to the end segments for extrapolation.
            let n = self.d.len();
            let j = self.d.partition_point(|&x| x <= d).clamp(1, n - 1) - 1;
            let slope = (self.f[j + 1] - self.f[j]) / (self.d[j + 1] - self.d[j]);
            (self.f[j] + slope * (d - self.d[j]), slope)
        };
        if let Some((gc, ge, ks)) = self.stop {
            if d < -gc {
                f += ks * (d + gc);
                k += ks;
            } else if d > ge {
                f += ks * (d - ge);
                k += ks;
            }
        }
        (f, k)
    }

    /// Deflections where the tangent jumps (table breakpoints and stop contacts).
    pub fn kinks(&self) -> Vec<f64> {
        let mut out = self.d.clone();
        if let Some((gc, ge, _)) = self.stop {
            out.push(-gc);
            out.push(ge);
        }
        out
    }
}

/// Whether every law carries no force at zero deflection (no table offset): an element
/// whose laws all do so keeps its objectivity.
pub fn zero_at_rest(laws: &Option<Vec<ForceLaw>>) -> bool {
    laws.iter()
        .flatten()
        .all(|l| l.force_and_tangent(0.0).0 == 0.0)
}

/// The laws of an element's directions `names` (with linear rates `k`), from its
/// `force_table` and `bump_stop` keys; `None` when both are empty (the element stays
/// linear). Errors name the key, the direction and the fix.
pub fn build_laws(
    names: &[&str],
    k: &[f64],
    tables: &ForceTables,
    stops: &BumpStops,
) -> Result<Option<Vec<ForceLaw>>, String> {
    if tables.is_empty() && stops.is_empty() {
        return Ok(None);
    }
    let index = |key: &str, dir: &str| {
        names.iter().position(|n| *n == dir).ok_or_else(|| {
            format!(
                "`{key}`: `{dir}` is not a direction of this element; use {}",
                names.join(", ")
            )
        })
    };
    let mut laws: Vec<ForceLaw> = k.iter().map(|&k| ForceLaw::linear(k)).collect();
    for (dir, pts) in tables {
        let i = index("force_table", dir)?;
        let at = format!("`force_table.{dir}`");
        if pts.len() < 2 {
            return Err(format!(
                "{at} has {} point(s); give at least 2 [deflection, force] pairs",
                pts.len()
            ));
        }
        if pts.len() > MAX_TABLE_POINTS {
            return Err(format!(
                "{at} has {} points, more than the {MAX_TABLE_POINTS} allowed; thin the curve",
                pts.len()
            ));
        }
        for (j, p) in pts.iter().enumerate() {
            if !(p[0].is_finite() && p[1].is_finite()) {
                return Err(format!(
                    "{at}[{j}] = {} is not finite; give finite numbers",
                    fmt_vec(p)
                ));
            }
        }
        for j in 1..pts.len() {
            if pts[j][0] <= pts[j - 1][0] {
                return Err(format!(
                    "{at}[{j}]: deflection {} does not increase from {}; sort the points by strictly increasing deflection",
                    fmt_num(pts[j][0]),
                    fmt_num(pts[j - 1][0])
                ));
            }
            if pts[j][1] < pts[j - 1][1] {
                return Err(format!(
                    "{at}[{j}]: force {} falls from {} (an unstable spring); give forces that never decrease with deflection",
                    fmt_num(pts[j][1]),
                    fmt_num(pts[j - 1][1])
                ));
            }
        }
        laws[i].d = pts.iter().map(|p| p[0]).collect();
        laws[i].f = pts.iter().map(|p| p[1]).collect();
    }
    for (dir, s) in stops {
        let i = index("bump_stop", dir)?;
        let (gc, ge) = s.gap.sides();
        for (what, v) in [("gap (compression)", gc), ("gap (extension)", ge)] {
            if !(v.is_finite() && v >= 0.0) {
                return Err(format!(
                    "`bump_stop.{dir}` {what} = {} must be ≥ 0 and finite; give the free travel before the stop (a large number for no stop on that side)",
                    fmt_num(v)
                ));
            }
        }
        if !(s.k.is_finite() && s.k >= 0.0) {
            return Err(format!(
                "`bump_stop.{dir}.k` = {} must be ≥ 0 and finite (the stop's stiffness)",
                fmt_num(s.k)
            ));
        }
        laws[i].stop = Some((gc, ge, s.k));
    }
    Ok(Some(laws))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn table(pts: &[[f64; 2]]) -> ForceTables {
        [("uz".to_string(), pts.to_vec())].into_iter().collect()
    }

    const NAMES: [&str; 2] = ["ux", "uz"];

    /// A bilinear table: the force and the tangent equal the line of each segment,
    /// including the extrapolation beyond both ends, exactly (1e-12 relative).
    #[test]
    fn table_interpolates_and_extrapolates_linearly() {
        let t = table(&[[-0.01, -2e4], [0.0, 0.0], [0.02, 1e5]]);
        let laws = build_laws(&NAMES, &[3.0, 7.0], &t, &BTreeMap::new())
            .unwrap()
            .unwrap();
        assert_eq!(laws[0].force_and_tangent(0.5), (1.5, 3.0));
        for (d, f, k) in [
            (-0.03, -6e4, 2e6),
            (-0.005, -1e4, 2e6),
            (0.01, 5e4, 5e6),
            (0.05, 2.5e5, 5e6),
        ] {
            let (ff, kk) = laws[1].force_and_tangent(d);
            assert!((ff - f).abs() <= 1e-12 * f.abs(), "{d}: {ff} vs {f}");
            assert!((kk - k).abs() <= 1e-9 * k, "{d}: {kk} vs {k}");
        }
        // At the kink the right-hand segment's slope.
        assert_eq!(laws[1].force_and_tangent(0.0), (0.0, 5e6));
    }

    /// A bump stop: zero force in the gap, `k_s·(overtravel)` beyond it on each side
    /// with its own gap, added to the linear spring.
    #[test]
    fn bump_stop_engages_beyond_each_gap() {
        let s: BumpStops = [(
            "uz".to_string(),
            BumpStopSpec {
                gap: Gap::Sides([0.01, 0.03]),
                k: 1e6,
            },
        )]
        .into_iter()
        .collect();
        let laws = build_laws(&NAMES, &[0.0, 100.0], &BTreeMap::new(), &s)
            .unwrap()
            .unwrap();
        let l = &laws[1];
        assert_eq!(l.force_and_tangent(-0.005), (100.0 * -0.005, 100.0));
        assert_eq!(l.force_and_tangent(0.025), (100.0 * 0.025, 100.0));
        let (f, k) = l.force_and_tangent(-0.015);
        assert!((f - (-1.5 - 1e6 * 0.005)).abs() < 1e-9 && k == 1e6 + 100.0);
        let (f, k) = l.force_and_tangent(0.04);
        assert!((f - (4.0 + 1e6 * 0.01)).abs() < 1e-9 && k == 1e6 + 100.0);
        assert_eq!(l.kinks(), vec![-0.01, 0.03]);
    }

    #[test]
    fn no_keys_means_no_laws() {
        assert!(
            build_laws(&NAMES, &[1.0, 2.0], &BTreeMap::new(), &BTreeMap::new())
                .unwrap()
                .is_none()
        );
    }

    #[test]
    fn bad_tables_and_stops_are_refused_with_the_place() {
        let e = |t: ForceTables, s: BumpStops| build_laws(&NAMES, &[1.0, 1.0], &t, &s).unwrap_err();
        let m = e(table(&[[0.0, 0.0]]), BumpStops::new());
        assert!(
            m.contains("`force_table.uz`") && m.contains("at least 2"),
            "{m}"
        );
        let m = e(
            table(&[[0.0, 0.0], [0.02, 1.0], [0.01, 2.0]]),
            BumpStops::new(),
        );
        assert!(
            m.contains("`force_table.uz`[2]") && m.contains("sort"),
            "{m}"
        );
        let m = e(
            table(&[[0.0, 0.0], [0.02, 1.0], [0.03, 0.5]]),
            BumpStops::new(),
        );
        assert!(
            m.contains("`force_table.uz`[2]") && m.contains("falls"),
            "{m}"
        );
        let big: Vec<[f64; 2]> = (0..=MAX_TABLE_POINTS).map(|i| [i as f64, 0.0]).collect();
        let m = e(table(&big), BumpStops::new());
        assert!(m.contains("more than"), "{m}");
        let m = e(table(&[[0.0, 0.0], [f64::NAN, 1.0]]), BumpStops::new());
        assert!(m.contains("[1]") && m.contains("finite"), "{m}");
        let t: ForceTables = [("uw".to_string(), vec![[0.0, 0.0], [1.0, 1.0]])]
            .into_iter()
            .collect();
        let m = e(t, BumpStops::new());
        assert!(
            m.contains("`uw` is not a direction") && m.contains("ux, uz"),
            "{m}"
        );
        let stop = |gap, k| -> BumpStops {
            [("uz".to_string(), BumpStopSpec { gap, k })]
                .into_iter()
                .collect()
        };
        let m = e(ForceTables::new(), stop(Gap::Both(-0.01), 1e6));
        assert!(m.contains("`bump_stop.uz` gap (compression)"), "{m}");
        let m = e(ForceTables::new(), stop(Gap::Sides([0.01, -1.0]), 1e6));
        assert!(m.contains("gap (extension)"), "{m}");
        let m = e(ForceTables::new(), stop(Gap::Both(0.01), -1.0));
        assert!(m.contains("`bump_stop.uz.k`"), "{m}");
    }
}

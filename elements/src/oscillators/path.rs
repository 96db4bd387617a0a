//! The path a moving oscillator rides on, and the contact point on it at a time: which two
//! beam nodes carry it and how the vertical displacement under it depends on theirs.
//!
//! A path is either a chain of two-node beams (`path = [element ids]`, walked by
//! [`railfem_framework::beam_chain`], either direction) or one rail of the generated track
//! (`track = "track"`, `rail = "left" | "right"`; the rail nodes `first_id + i` at the
//! track's stations, fixed when the rails are rigid). The station at time `t` comes from a
//! [`SpeedHistory`].
//!
//! # Interpolation under the contact point
//!
//! On the segment from node A to node B (length `L`, axes `R`: x along A→B), the point at
//! `ξ` has the local displacement `u_x = (1−ξ)·u_xA + ξ·u_xB`,
//! `u_y = N1·v_A + N2·θz_A + N3·v_B + N4·θz_B`, `u_z = N1·w_A − N2·θy_A + N3·w_B − N4·θy_B`
//! with the cubic Hermite functions `N` of the beam (`beam3d::hermite`). The oscillator
//! acts along global Z; its contact displacement is `w_c = ẑ·R·u_loc = bᵀ·q` with `q` the
//! twelve global DOFs of A and B: `b` block `j` is `R·T_jᵀ·c`, `c = Rᵀẑ`, `T_j` the
//! interpolation columns of node block `j`. The path derivatives `b' = db/ds` and
//! `b'' = d²b/ds²` use `N'`, `N''` (`hermite_d`, `hermite_dd`) and the linear functions'
//! `(−1/L, 1/L)`, `(0, 0)`: `∂w_c/∂s = b'ᵀ·q`, `∂²w_c/∂s² = b''ᵀ·q`. Within a segment the
//! cubic is exact for every cubic deflection; `b''` jumps at the nodes (the Hermite
//! curvature is only piecewise linear), which is the usual price of `C¹` elements.
//!
//! # Irregularity
//!
//! On a track rail the contact sees the rail-top profile `r(s)` at its station (the rail's
//! vertical irregularity and the dipped joints), read in
//! one place, [`rail_profile`]; its derivatives by central differences. A beam path has
//! `r = 0`.

use crate::beam3d::{hermite, hermite_d, hermite_dd};
use crate::rail::geometry::railline::RailSide;
use crate::rail::geometry::track_model::TrackModel;
use crate::rail::wheels::rail_point::beam_axes;
use nalgebra::{Matrix3, Vector3};
use railfem_framework::beam_chain::BeamChain;
use railfem_framework::limits::fmt_num;
use railfem_framework::registry::{BuildContext, ElementSpec};
use railfem_framework::speed::SpeedHistory;
use railfem_framework::FemError;
use std::sync::Arc;

/// Relative slack at the ends of a path, so that a station at `L·(1 + 1e-12)` from
/// `v·t` round-off still counts as on it.
const END_SLACK: f64 = 1e-9;

/// An oscillator's parameters as JSON for `Element::parameters`, without `rail` when it
/// rides a beam `path` (no `track`): the model file refuses `rail` beside `path`, so a key
/// that only its default put there would not read back.
pub fn path_parameters<P: serde::Serialize>(params: &P) -> serde_json::Value {
    let mut v = serde_json::to_value(params).unwrap_or(serde_json::Value::Null);
    if let Some(map) = v.as_object_mut() {
        let on_track = map
            .get("track")
            .and_then(|t| t.as_str())
            .is_some_and(|t| !t.is_empty());
        if !on_track {
            map.remove("rail");
        }
    }
    v
}

/// The rail-top profile (m, up) of rail `rail` at station `s`: the one place where a
/// moving oscillator reads the track's irregularity (the vertical part of
/// [`TrackModel::rail_offset`]: the `[track] irregularity` of that rail and the dipped
/// joints).
pub fn rail_profile(track: &TrackModel, rail: usize, s: f64) -> f64 {
    track.rail_offset(rail, s)[1]
}

/// What the oscillator rides on.
#[derive(Debug, Clone)]
enum Support {
    /// A chain of beams; the station is the distance along it.
    Beams(BeamChain),
    /// A rail of the generated track; `nodes[i]` the node index at `stations[i]`.
    Rail {
        track: Arc<TrackModel>,
        rail: usize,
        nodes: Vec<usize>,
        positions: Vec<Vector3<f64>>,
    },
}

/// A path with its speed history.
#[derive(Debug, Clone)]
pub struct ContactPath {
    support: Support,
    history: SpeedHistory,
}

/// The contact point at one time.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactPoint {
    /// Station (m).
    pub station: f64,
    /// Speed (m/s).
    pub speed: f64,
    /// Acceleration along the path (m/s²).
    pub accel: f64,
    /// Segment index on the path.
    pub segment: usize,
    /// Node indices (A, B) of the segment.
    pub nodes: (usize, usize),
    /// `w_c = bᵀ·q`: vertical displacement under the point from the 12 DOFs of A and B.
    pub b: [f64; 12],
    /// `db/ds` (1/m on translations).
    pub b1: [f64; 12],
    /// `d²b/ds²`.
    pub b2: [f64; 12],
    /// Rail-top profile `r(s)` (m) and its derivatives `r'`, `r''`.
    pub profile: [f64; 3],
}

/// Interpolation row of order `k` (0: value, 1: d/ds, 2: d²/ds²) of the global-Z
/// displacement at `ξ` on a segment of length `l` with axes `r`.
fn row(k: usize, xi: f64, l: f64, r: &Matrix3<f64>) -> [f64; 12] {
    let n = match k {
        0 => hermite(xi, l),
        1 => hermite_d(xi, l),
        _ => hermite_dd(xi, l),
    };
    let lin = match k {
        0 => [1.0 - xi, xi],
        1 => [-1.0 / l, 1.0 / l],
        _ => [0.0, 0.0],
    };
    // Local interpolation, rows (u_x, u_y, u_z), columns the 12 local DOFs.
    let mut t = [[0.0; 12]; 3];
    t[0][0] = lin[0];
    t[0][6] = lin[1];
    t[1][1] = n[0];
    t[1][5] = n[1];
    t[1][7] = n[2];
    t[1][11] = n[3];
    t[2][2] = n[0];
    t[2][4] = -n[1];
    t[2][8] = n[2];
    t[2][10] = -n[3];
    let c = r.transpose() * Vector3::z();
    let mut out = [0.0; 12];
    for blk in 0..4 {
        let local = Vector3::from_fn(|j, _| (0..3).map(|i| t[i][3 * blk + j] * c[i]).sum());
        let g = r * local;
        out[3 * blk..3 * blk + 3].copy_from_slice(g.as_slice());
    }
    out
}

impl ContactPath {
    /// Resolves the path keys of an oscillator: `path` (beam element ids) or `track` +
    /// `rail`, exactly one of them. Refuses a missing or non-beam element, a broken chain, a
    /// missing track, and a start off the path, naming the key.
    pub fn resolve(
        spec: &ElementSpec,
        ctx: &dyn BuildContext,
        kind: &str,
        path: &[u64],
        track: &str,
        rail: RailSide,
        history: SpeedHistory,
    ) -> Result<ContactPath, FemError> {
        let bad = |m: String| FemError::input(&spec.origin, format!("{kind}: {m}"));
        let support = match (path.is_empty(), track.is_empty()) {
            (true, true) | (false, false) => {
                return Err(bad(
                    "give exactly one of `path` (beam element ids) and `track` (a generated track, with `rail`)".into(),
                ))
            }
            (false, true) => {
                if spec.params.contains_key("rail") {
                    return Err(bad(
                        "`rail` would be ignored: it picks a rail of `track`, and this oscillator rides the beams of `path`; remove `rail`, or give `track` instead of `path`".into(),
                    ));
                }
                let mut pairs = Vec::with_capacity(path.len());
                for (i, &id) in path.iter().enumerate() {
                    let Some((k, nodes)) = ctx.element_nodes(id) else {
                        return Err(bad(format!(
                            "`path`[{i}] names element {id}, which does not exist; list the ids of existing beam elements"
                        )));
                    };
                    if nodes.len() != 2 || !k.starts_with("beam") {
                        return Err(bad(format!(
                            "`path`[{i}]: element {id} ({k}) is not a two-node beam; list beam elements only"
                        )));
                    }
                    pairs.push((nodes[0], nodes[1]));
                }
                let chain = BeamChain::walk(path, pairs, &|n| ctx.node_position(n))
                    .map_err(|m| bad(format!("`path`: {m}; list the beams in order along the path")))?;
                Support::Beams(chain)
            }
            (true, false) => {
                let r = rail.index();
                let tm = ctx
                    .resource(track)
                    .and_then(|x| x.downcast::<TrackModel>().ok())
                    .ok_or_else(|| {
                        bad(format!(
                            "`track` = \"{track}\": no such track; add a [track] table to the model, or use `path`"
                        ))
                    })?;
                let mut nodes = Vec::with_capacity(tm.stations.len());
                for i in 0..tm.stations.len() {
                    let id = tm.rails[r].first_id + i as u64;
                    let n = ctx.node_index(id).ok_or_else(|| {
                        bad(format!("rail node {id} of the track does not exist"))
                    })?;
                    nodes.push(n);
                }
                let positions = nodes.iter().map(|&n| ctx.node_position(n)).collect();
                Support::Rail {
                    track: tm,
                    rail: r,
                    nodes,
                    positions,
                }
            }
        };
        let p = ContactPath { support, history };
        let s0 = p.history.start();
        if p.point(0.0).is_err() {
            let (a, b) = p.range();
            return Err(bad(format!(
                "`start` = {} m is off the path ({} m to {} m); start the oscillator on its path",
                fmt_num(s0),
                fmt_num(a),
                fmt_num(b)
            )));
        }
        Ok(p)
    }

    /// First and last station of the path (m).
    pub fn range(&self) -> (f64, f64) {
        match &self.support {
            Support::Beams(c) => (0.0, c.length()),
            Support::Rail { track, .. } => (
                track.stations.first().copied().unwrap_or(0.0),
                track.stations.last().copied().unwrap_or(0.0),
            ),
        }
    }

    /// The speed history.
    pub fn history(&self) -> &SpeedHistory {
        &self.history
    }

    /// The contact point at time `t`; an error (one sentence) off the path.
    pub fn point(&self, t: f64) -> Result<ContactPoint, String> {
        let s = self.history.station(t);
        let (a, b) = self.range();
        let slack = END_SLACK * (b - a).abs().max(1.0);
        if !(s >= a - slack && s <= b + slack) {
            return Err(format!(
                "the oscillator is at station {} m at t = {} s, off its path ({} m to {} m); end the analysis before it leaves, or lengthen the path",
                fmt_num(s),
                fmt_num(t),
                fmt_num(a),
                fmt_num(b)
            ));
        }
        let sc = s.clamp(a, b);
        let (segment, xi, nodes, (xa, xb), profile) = match &self.support {
            Support::Beams(c) => {
                let (k, xi) = c.locate(sc).ok_or("empty path")?;
                (k, xi, c.segments[k], c.ends[k], [0.0; 3])
            }
            Support::Rail {
                track,
                rail,
                nodes,
                positions,
            } => {
                let (k, xi) = track.locate(sc).ok_or("empty track")?;
                let h = 1e-3;
                let f = |x: f64| rail_profile(track, *rail, x);
                let (rm, r0, rp) = (f(s - h), f(s), f(s + h));
                (
                    k,
                    xi,
                    (nodes[k], nodes[k + 1]),
                    (positions[k], positions[k + 1]),
                    [r0, (rp - rm) / (2.0 * h), (rp - 2.0 * r0 + rm) / (h * h)],
                )
            }
        };
        let l = (xb - xa).norm();
        let axes = beam_axes(&xa, &xb);
        Ok(ContactPoint {
            station: s,
            speed: self.history.speed(t),
            accel: self.history.accel(t),
            segment,
            nodes,
            b: row(0, xi, l, &axes),
            b1: row(1, xi, l, &axes),
            b2: row(2, xi, l, &axes),
            profile,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// On an inclined, skew segment the rows reproduce a rigid translation along Z (`bᵀr = 1`,
    /// no slope or curvature) and differentiate a cubic bending shape exactly (compared
    /// with central differences of the value row along the path).
    #[test]
    fn rows_are_exact_and_consistent() {
        let xa = Vector3::new(0.0, 0.0, 0.0);
        let xb = Vector3::new(3.0, 1.0, 0.5);
        let l = (xb - xa).norm();
        let r = beam_axes(&xa, &xb);
        let mut tz = [0.0; 12];
        tz[2] = 1.0;
        tz[8] = 1.0;
        let dot = |a: &[f64; 12], b: &[f64; 12]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
        let q: Vec<f64> = (0..12).map(|i| ((i * 7 % 5) as f64 - 2.0) * 1e-3).collect();
        let q: [f64; 12] = q.try_into().unwrap();
        for xi in [0.0, 0.3, 0.77, 1.0] {
            assert!((dot(&row(0, xi, l, &r), &tz) - 1.0).abs() < 1e-14);
            assert!(dot(&row(1, xi, l, &r), &tz).abs() < 1e-14);
            assert!(dot(&row(2, xi, l, &r), &tz).abs() < 1e-13);
        }
        for xi in [0.02, 0.3, 0.77, 0.98] {
            let h = 1e-4;
            let (x0, x1) = (xi - h, xi + h);
            let w = |x: f64| dot(&row(0, x, l, &r), &q);
            let d1 = (w(x1) - w(x0)) / ((x1 - x0) * l);
            assert!((d1 - dot(&row(1, xi, l, &r), &q)).abs() < 1e-9, "ξ = {xi}");
            let wd = |x: f64| dot(&row(1, x, l, &r), &q);
            let d2 = (wd(x1) - wd(x0)) / ((x1 - x0) * l);
            assert!((d2 - dot(&row(2, xi, l, &r), &q)).abs() < 1e-9, "ξ = {xi}");
        }
    }
}

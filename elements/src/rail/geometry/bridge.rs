//! Slab track and bridge components under the rails: a concrete slab on the subgrade or on
//! simply supported girders, fasteners, bearings and piers, generated beside the rails of
//! [`crate::rail::geometry::track_model::generate`].
//!
//! # Slab track (`support = {type = "slab", …}`)
//!
//! The slab is a `beam3d` along the track centre line, `slab_depth` below the rail-top
//! reference line, with one node per rail station. On the ground every slab node has a
//! grounded `spring_damper` (the subgrade), whose rates are the given rates per metre times
//! the node's tributary length (half of each adjacent element), so the slab sees a Winkler
//! foundation. Each rail is tied to the slab by a FASTENER at every multiple of
//! `fastener_spacing` (m of station; the mesh has a rail and slab node at each, whatever the
//! element length, so the support pattern does not change with the mesh): a two-node
//! `spring_damper` between the rail node and an
//! ANCHOR node at the same position, the anchor rigidly linked (all six DOFs) to the slab
//! node of that station. The rigid link carries the lateral and vertical offset (a slab roll
//! lifts one rail and lowers the other); the spring joins coincident nodes, so it is
//! objective. Springs act in the wheel frame: `[lateral, vertical, longitudinal, about
//! lateral, about vertical, about longitudinal]`.
//!
//! # Bridge (`support = {type = "bridge", …}`)
//!
//! `spans` simply supported spans of length `span` from station `start`. Each span is its
//! own girder: `beam3d` elements between the slab nodes of the span, so the slab and the
//! girder share nodes on the centre line (the rigid-link limit with zero offset: the slab's
//! eccentricity above the girder centroid is neglected and their bending stiffnesses add,
//! without composite action). Adjacent spans have separate end nodes at the joint station —
//! slab and girder are discontinuous there, only the rails run on. Off the bridge the slab
//! lies on the subgrade (approaches). Bearings are `spring_damper`s from each girder end
//! node to the pier-top node at the same position (abutments: to the ground): the start of a
//! span sits on a FIXED bearing, its end on a ROLLER (soft longitudinally). Piers are
//! `beam3d` columns of `pier_height` under every interior joint, fixed at the base, where a
//! ground motion acts. Stations of every joint and every midspan are mesh nodes.
//!
//! # Numbering
//!
//! With `n` rail stations and `base` the first rail node: rails `base + i` (left) and
//! `base + n + i` (right); then the slab nodes segment after segment in station order
//! (approach, span 1, span 2, …, approach; a joint station has one node per segment); then
//! the anchors in station order (left, right per fastener); then the piers in station order,
//! each from its top down to its base. Elements: rails (left then right), slab (and
//! girder) elements in station order, fasteners, subgrade springs, bearings, piers. Every
//! id block increases with station, so "the midspan girder node of span k" is an index
//! computation ([`BridgeLayout::midspan_node`]).

use crate::rail::geometry::cant::Track;
use crate::rail::geometry::rail_section::RailSection;
use railfem_framework::builder::ModelBuilder;
use railfem_framework::error::FemError;
use railfem_framework::limits;
use railfem_framework::moving::Path;
use railfem_framework::DofSet;
use serde::{Deserialize, Serialize};

impl RailSection {
    /// A 2.4 m × 0.2 m concrete slab: E = 3.45e10 Pa, ν = 0.2 (G = E/2.4), ρ = 2500 kg/m³,
    /// A = 0.48 m², i_vertical = b·h³/12 = 1.6e-3 m⁴, i_lateral = h·b³/12 = 0.2304 m⁴,
    /// J = (b·h³/3)·(1 − 0.63·h/b) = 6.06e-3 m⁴ (thin-rectangle torsion).
    pub fn concrete_slab() -> Self {
        let (b, h, e) = (2.4f64, 0.2f64, 3.45e10);
        RailSection {
            e,
            g: e / 2.4,
            a: b * h,
            i_vertical: b * h.powi(3) / 12.0,
            i_lateral: h * b.powi(3) / 12.0,
            j: b * h.powi(3) / 3.0 * (1.0 - 0.63 * h / b),
            rho: 2500.0,
        }
    }

    /// A prestressed-concrete single-cell box girder of a ~30 m double-track high-speed
    /// span (stand-in values of that class, not a specific drawing): E = 3.55e10 Pa (C50),
    /// G = E/2.4, A = 8.9 m², i_vertical = 11.0 m⁴, i_lateral = 95 m⁴, J = 24 m⁴,
    /// ρ = 2600 kg/m³ (23.1 t/m with the reinforcement).
    pub fn pc_box_girder() -> Self {
        RailSection {
            e: 3.55e10,
            g: 3.55e10 / 2.4,
            a: 8.9,
            i_vertical: 11.0,
            i_lateral: 95.0,
            j: 24.0,
            rho: 2600.0,
        }
    }

    /// A solid rectangular pier 2.5 m (along the track) × 6 m (across): E = 3.25e10 Pa
    /// (C35), G = E/2.4, A = 15 m², i_vertical (sway along the track) = 6·2.5³/12 =
    /// 7.8125 m⁴, i_lateral (sway across) = 2.5·6³/12 = 45 m⁴, J = 0.249·6·2.5³ = 23.3 m⁴
    /// (Saint-Venant, b/a = 2.4), ρ = 2500 kg/m³.
    pub fn rc_pier() -> Self {
        RailSection {
            e: 3.25e10,
            g: 3.25e10 / 2.4,
            a: 15.0,
            i_vertical: 6.0 * 2.5f64.powi(3) / 12.0,
            i_lateral: 2.5 * 6.0f64.powi(3) / 12.0,
            j: 0.249 * 6.0 * 2.5f64.powi(3),
            rho: 2500.0,
        }
    }
}

/// Slab, fasteners and subgrade of a slab track (SI units; keys of `support` when
/// `type = "slab"`, and of `slab_track` in a bridge).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SlabTrack {
    /// Slab section (default [`RailSection::concrete_slab`]).
    #[serde(default = "RailSection::concrete_slab")]
    pub slab: RailSection,
    /// Distance from the rail-top reference line down to the slab's beam line (m).
    #[serde(default = "default_slab_depth")]
    pub slab_depth: f64,
    /// Fastener spacing along the track (m).
    #[serde(default = "default_fastener_spacing")]
    pub fastener_spacing: f64,
    /// Fastener springs per rail seat, wheel frame (N/m, N·m/rad).
    #[serde(default = "default_fastener_k")]
    pub fastener_k: [f64; 6],
    /// Fastener dampers per rail seat (N·s/m, N·m·s/rad).
    #[serde(default = "default_fastener_c")]
    pub fastener_c: [f64; 6],
    /// Subgrade springs per metre of slab, wheel frame (N/m per m, N·m/rad per m).
    #[serde(default = "default_subgrade_k")]
    pub subgrade_k: [f64; 6],
    /// Subgrade dampers per metre of slab (N·s/m per m, N·m·s/rad per m).
    #[serde(default = "default_subgrade_c")]
    pub subgrade_c: [f64; 6],
}

fn default_slab_depth() -> f64 {
    0.35
}
fn default_fastener_spacing() -> f64 {
    0.625
}
fn default_fastener_k() -> [f64; 6] {
    [3.0e7, 6.0e7, 2.0e7, 0.0, 1.0e5, 1.0e6]
}
fn default_fastener_c() -> [f64; 6] {
    [5.0e4, 7.5e4, 5.0e4, 0.0, 0.0, 0.0]
}
fn default_subgrade_k() -> [f64; 6] {
    // Vertical 1e9 N/m² under a 2.4 m slab gives a roll stiffness k·b²/12 = 4.8e8 N·m/rad
    // per metre.
    [5.0e8, 1.0e9, 5.0e8, 0.0, 0.0, 4.8e8]
}
fn default_subgrade_c() -> [f64; 6] {
    [5.0e4, 1.0e5, 5.0e4, 0.0, 0.0, 0.0]
}

impl Default for SlabTrack {
    fn default() -> Self {
        SlabTrack {
            slab: RailSection::concrete_slab(),
            slab_depth: default_slab_depth(),
            fastener_spacing: default_fastener_spacing(),
            fastener_k: default_fastener_k(),
            fastener_c: default_fastener_c(),
            subgrade_k: default_subgrade_k(),
            subgrade_c: default_subgrade_c(),
        }
    }
}

/// A viaduct of simply supported spans (SI units; keys of `support` when
/// `type = "bridge"`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BridgeSpec {
    /// Station of the first abutment (m).
    pub start: f64,
    /// Number of spans.
    pub spans: usize,
    /// Span length, bearing to bearing (m).
    #[serde(default = "default_span")]
    pub span: f64,
    /// Girder section (default [`RailSection::pc_box_girder`]).
    #[serde(default = "RailSection::pc_box_girder")]
    pub girder: RailSection,
    /// Fixed bearing springs per girder end, wheel frame (N/m, N·m/rad).
    #[serde(default = "default_bearing_fixed")]
    pub bearing_fixed: [f64; 6],
    /// Roller bearing springs per girder end (N/m, N·m/rad).
    #[serde(default = "default_bearing_roller")]
    pub bearing_roller: [f64; 6],
    /// Bearing dampers, both kinds (N·s/m, N·m·s/rad).
    #[serde(default)]
    pub bearing_c: [f64; 6],
    /// Pier height, base to girder line (m).
    #[serde(default = "default_pier_height")]
    pub pier_height: f64,
    /// Pier section (default [`RailSection::rc_pier`]); `i_vertical` is for sway along the
    /// track, `i_lateral` for sway across it.
    #[serde(default = "RailSection::rc_pier")]
    pub pier: RailSection,
    /// Beam elements per pier.
    #[serde(default = "default_pier_elements")]
    pub pier_elements: usize,
    /// Slab, fasteners and the approaches' subgrade.
    #[serde(default)]
    pub slab_track: SlabTrack,
}

fn default_span() -> f64 {
    29.75
}
fn default_bearing_fixed() -> [f64; 6] {
    // Two pot bearings 2.5 m either side of the centre line, 5e9 N/m vertically each:
    // roll 2·5e9·2.5² ≈ 6e10 N·m/rad; bending rotations free.
    [5.0e9, 1.0e10, 5.0e9, 0.0, 0.0, 6.0e10]
}
fn default_bearing_roller() -> [f64; 6] {
    [5.0e9, 1.0e10, 1.0e6, 0.0, 0.0, 6.0e10]
}
fn default_pier_height() -> f64 {
    10.0
}
fn default_pier_elements() -> usize {
    4
}

impl BridgeSpec {
    /// DOFs of the girders, bearings and piers, from the keys alone: spans + 1 piers of
    /// `pier_elements` + 1 nodes, two girder ends and a bearing per joint, six DOFs each
    /// (the rails and the slab are the track mesh's). The bridge's size guard and the
    /// model's size estimate count it so.
    pub fn estimated_dofs(&self) -> f64 {
        6.0 * (self.spans as f64 + 1.0) * (self.pier_elements as f64 + 3.0)
    }

    /// `spans` spans from station `start` (m), every other key at its model-file default:
    /// 29.75 m spans of [`RailSection::pc_box_girder`] on pot bearings, 10 m piers of four
    /// elements, the default slab track.
    pub fn new(start: f64, spans: usize) -> Self {
        BridgeSpec {
            start,
            spans,
            span: default_span(),
            girder: RailSection::pc_box_girder(),
            bearing_fixed: default_bearing_fixed(),
            bearing_roller: default_bearing_roller(),
            bearing_c: [0.0; 6],
            pier_height: default_pier_height(),
            pier: RailSection::rc_pier(),
            pier_elements: default_pier_elements(),
            slab_track: SlabTrack::default(),
        }
    }

    /// Stations of the joints (abutments and piers), `spans + 1` of them (m).
    pub fn joints(&self) -> Vec<f64> {
        (0..=self.spans)
            .map(|k| self.start + k as f64 * self.span)
            .collect()
    }

    /// Stations of the midspans, one per span (m).
    pub fn midspans(&self) -> Vec<f64> {
        (0..self.spans)
            .map(|k| self.start + (k as f64 + 0.5) * self.span)
            .collect()
    }
}

/// One slab segment: the stations `first..=last` (indices into the rail stations) with
/// consecutive slab node ids from `first_id`, on the ground or on span `span`.
#[derive(Debug, Clone, PartialEq)]
pub struct SlabSegment {
    /// First station index.
    pub first: usize,
    /// Last station index (inclusive).
    pub last: usize,
    /// Node id of the slab at station `first`.
    pub first_id: u64,
    /// The span the segment lies on (`None`: on the subgrade).
    pub span: Option<usize>,
}

impl SlabSegment {
    /// Slab node id at station index `i` (which must lie in the segment).
    pub fn node(&self, i: usize) -> u64 {
        self.first_id + (i - self.first) as u64
    }
}

/// The slab of a slab or bridge track: segments in station order.
#[derive(Debug, Clone, PartialEq)]
pub struct SlabLayout {
    /// Segments in station order.
    pub segments: Vec<SlabSegment>,
}

impl SlabLayout {
    /// The slab node a fastener at station index `i` attaches to: the segment that holds
    /// `i`, the later one at a joint (the last segment keeps its end).
    pub fn node_at(&self, i: usize) -> Option<u64> {
        let k = self.segments.partition_point(|g| g.last <= i);
        let g = self
            .segments
            .get(k)
            .filter(|g| g.first <= i)
            .or_else(|| self.segments.last().filter(|g| g.last == i))?;
        Some(g.node(i))
    }
}

/// One span of a bridge.
#[derive(Debug, Clone, PartialEq)]
pub struct SpanLayout {
    /// Station of the start bearing (m).
    pub start: f64,
    /// Station of the end bearing (m).
    pub end: f64,
    /// Index of the span's slab segment in [`SlabLayout::segments`].
    pub segment: usize,
    /// Girder node ids, start to end, consecutive.
    pub first_node: u64,
    /// Last girder node id.
    pub last_node: u64,
    /// Girder node at midspan (a mesh cut puts one there).
    pub midspan_node: u64,
}

/// The generated bridge: spans, piers and their ids.
#[derive(Debug, Clone, PartialEq)]
pub struct BridgeLayout {
    /// Spans in station order.
    pub spans: Vec<SpanLayout>,
    /// Per joint (abutment, piers…, abutment): the pier-top node, `None` at abutments.
    pub pier_tops: Vec<Option<u64>>,
    /// Per joint: the pier-base node (fixed; where the ground motion acts).
    pub pier_bases: Vec<Option<u64>>,
}

impl BridgeLayout {
    /// Girder node at midspan of span `k` (0-based).
    pub fn midspan_node(&self, k: usize) -> Option<u64> {
        self.spans.get(k).map(|s| s.midspan_node)
    }
}

/// Checks a section: every constant finite and positive (ρ ≥ 0).
pub(super) fn check_section(s: &RailSection, what: &str, origin: &str) -> Result<(), FemError> {
    let ok = [s.e, s.g, s.a, s.i_vertical, s.i_lateral, s.j]
        .iter()
        .all(|v| v.is_finite() && *v > 0.0)
        && s.rho.is_finite()
        && s.rho >= 0.0;
    if ok {
        Ok(())
    } else {
        Err(FemError::input(
            origin,
            format!(
                "`{what}`: E, G, A, i_vertical, i_lateral, J must be finite and > 0 and rho ≥ 0"
            ),
        ))
    }
}

fn check_rates(v: &[f64; 6], what: &str, origin: &str) -> Result<(), FemError> {
    if v.iter().all(|x| x.is_finite() && *x >= 0.0) {
        Ok(())
    } else {
        Err(FemError::input(
            origin,
            format!("`{what}`: give six finite values ≥ 0"),
        ))
    }
}

impl SlabTrack {
    pub(super) fn validate(&self, origin: &str) -> Result<(), FemError> {
        check_section(&self.slab, "slab", origin)?;
        if !(self.slab_depth.is_finite() && self.slab_depth >= 0.0) {
            return Err(FemError::input(origin, "`slab_depth` must be ≥ 0 m"));
        }
        if !(self.fastener_spacing.is_finite() && self.fastener_spacing > 0.0) {
            return Err(FemError::input(origin, "`fastener_spacing` must be > 0 m"));
        }
        check_rates(&self.fastener_k, "fastener_k", origin)?;
        check_rates(&self.fastener_c, "fastener_c", origin)?;
        check_rates(&self.subgrade_k, "subgrade_k", origin)?;
        check_rates(&self.subgrade_c, "subgrade_c", origin)
    }
}

impl BridgeSpec {
    pub(super) fn validate(&self, origin: &str, from: f64, to: f64) -> Result<(), FemError> {
        if self.spans == 0 {
            return Err(FemError::input(origin, "`spans` must be at least 1"));
        }
        if !(self.span.is_finite() && self.span > 0.0 && self.start.is_finite()) {
            return Err(FemError::input(
                origin,
                "`span` must be > 0 m and `start` finite (m)",
            ));
        }
        let end = self.start + self.spans as f64 * self.span;
        if self.start < from - 1e-9 || end > to + 1e-9 {
            return Err(FemError::input(
                origin,
                format!(
                    "the bridge [{}, {end}] m lies outside the meshed track [{from}, {to}] m; move `start` or lengthen the track",
                    self.start
                ),
            ));
        }
        check_section(&self.girder, "girder", origin)?;
        check_section(&self.pier, "pier", origin)?;
        check_rates(&self.bearing_fixed, "bearing_fixed", origin)?;
        check_rates(&self.bearing_roller, "bearing_roller", origin)?;
        check_rates(&self.bearing_c, "bearing_c", origin)?;
        if !(self.pier_height.is_finite() && self.pier_height > 0.0) {
            return Err(FemError::input(origin, "`pier_height` must be > 0 m"));
        }
        if self.pier_elements == 0 {
            return Err(FemError::input(
                origin,
                "`pier_elements` must be at least 1",
            ));
        }
        limits::check_memory(
            &format!(
                "`spans` = {} with `pier_elements` = {}",
                self.spans, self.pier_elements
            ),
            self.estimated_dofs(),
            "bridge DOFs",
            limits::BYTES_PER_DOF,
            "give fewer `spans` or `pier_elements`",
        )
        .map_err(|m| FemError::input(origin, m))?;
        self.slab_track.validate(origin)
    }
}

/// The wheel frame at station `s` as the two `axes` rows of a `spring_damper` (lateral,
/// vertical).
fn spring_axes_at(track: &Track, s: f64) -> [[f64; 3]; 2] {
    let f = track.at(s).frame;
    [
        [f[(0, 0)], f[(1, 0)], f[(2, 0)]],
        [f[(0, 1)], f[(1, 1)], f[(2, 1)]],
    ]
}

/// The beam parameters of a section with `orient` = the local vertical.
fn beam_params(s: &RailSection, up: [f64; 3]) -> serde_json::Value {
    serde_json::json!({
        "E": s.e, "G": s.g, "A": s.a, "Iz": s.i_vertical, "Iy": s.i_lateral, "J": s.j,
        "rho": s.rho, "orient": up,
    })
}

/// What [`generate_structure`] needs to know of the rails.
pub(super) struct RailsInfo<'a> {
    pub track: &'a Track,
    pub stations: &'a [f64],
    pub rail_first: [u64; 2],
    /// Next free node id.
    pub next_node: u64,
}

/// Stations of the rail supports (discrete supports or fasteners) on `[from, to]` (m):
/// every multiple of `spacing`, `m·spacing`, whatever the element length. The mesh makes
/// each of them a node ([`crate::rail::geometry::track_model::TrackMesh::cuts`]).
pub fn support_stations(from: f64, to: f64, spacing: f64) -> Vec<f64> {
    let first = (from / spacing - 1e-9).ceil() as i64;
    let last = (to / spacing + 1e-9).floor() as i64;
    (first..=last).map(|m| m as f64 * spacing).collect()
}

/// The node index of each support station in `stations` (which hold every one of them,
/// see [`support_stations`]). A support that is not a node is a bug of the mesher, reported
/// as an internal error rather than moved to a neighbour.
pub(super) fn support_nodes(
    stations: &[f64],
    spacing: f64,
    origin: &str,
) -> Result<Vec<usize>, FemError> {
    let (from, to) = (stations[0], stations[stations.len() - 1]);
    support_stations(from, to, spacing)
        .into_iter()
        .map(|s| {
            let i = stations
                .partition_point(|x| *x < s - 1e-6)
                .min(stations.len() - 1);
            if (stations[i] - s).abs() <= 1e-6 {
                Ok(i)
            } else {
                Err(FemError::input(
                    origin,
                    format!("internal: the rail support at {s} m is not a mesh station"),
                ))
            }
        })
        .collect()
}

/// Generates slab, fasteners, subgrade and (with `bridge`) girders, bearings and piers.
/// Element ids continue from `*eid`.
pub(super) fn generate_structure(
    b: &mut ModelBuilder,
    rails: &RailsInfo,
    slab: &SlabTrack,
    bridge: Option<&BridgeSpec>,
    eid: &mut u64,
    origin: &str,
) -> Result<(SlabLayout, Option<BridgeLayout>), FemError> {
    let st = rails.stations;
    let track = rails.track;
    let n = st.len();
    let index_of = |s: f64| -> usize {
        let i = st.partition_point(|x| *x < s - 1e-6);
        i.min(n - 1)
    };
    // Segments: cut at every joint of the bridge.
    let mut bounds: Vec<(usize, Option<usize>)> = Vec::new(); // (first index, span)
    let mut joints_idx = Vec::new();
    if let Some(br) = bridge {
        let joints = br.joints();
        for &s in &joints {
            let i = index_of(s);
            if (st[i] - s).abs() > 1e-6 {
                return Err(FemError::input(
                    origin,
                    format!("internal: bridge joint at {s} m is not a mesh station"),
                ));
            }
            joints_idx.push(i);
        }
        if joints_idx[0] > 0 {
            bounds.push((0, None));
        }
        for k in 0..br.spans {
            bounds.push((joints_idx[k], Some(k)));
        }
        if joints_idx[br.spans] < n - 1 {
            bounds.push((joints_idx[br.spans], None));
        }
    } else {
        bounds.push((0, None));
    }
    let mut segments = Vec::with_capacity(bounds.len());
    let mut next_node = rails.next_node;
    for (g, &(first, span)) in bounds.iter().enumerate() {
        let last = bounds.get(g + 1).map_or(n - 1, |x| x.0);
        segments.push(SlabSegment {
            first,
            last,
            first_id: next_node,
            span,
        });
        next_node += (last - first + 1) as u64;
    }
    let layout = SlabLayout { segments };
    let down = slab.slab_depth;
    let slab_pos = |i: usize| {
        let p = track.at(st[i]);
        let x = p.position - p.frame.column(1) * down;
        [x.x, x.y, x.z]
    };
    for g in &layout.segments {
        for i in g.first..=g.last {
            b.node(g.node(i), slab_pos(i));
        }
    }
    // Slab and girder elements.
    for g in &layout.segments {
        for i in g.first..g.last {
            let up = track
                .at(0.5 * (st[i] + st[i + 1]))
                .frame
                .column(1)
                .into_owned();
            let up = [up.x, up.y, up.z];
            let nodes = [g.node(i), g.node(i + 1)];
            *eid += 1;
            b.element("beam3d", *eid, &nodes, &beam_params(&slab.slab, up));
            if let (Some(_), Some(br)) = (g.span, bridge) {
                *eid += 1;
                b.element("beam3d", *eid, &nodes, &beam_params(&br.girder, up));
            }
        }
    }
    // Fasteners: anchor nodes rigidly linked to the slab, springs to the rails.
    let fasteners = support_nodes(st, slab.fastener_spacing, origin)?;
    let anchor_first = next_node;
    next_node += 2 * fasteners.len() as u64;
    for (p, &i) in fasteners.iter().enumerate() {
        let master = layout
            .node_at(i)
            .expect("every station lies on a slab segment");
        let axes = spring_axes_at(track, st[i]);
        for r in 0..2 {
            let rail = rails.rail_first[r] + i as u64;
            let anchor = anchor_first + 2 * p as u64 + r as u64;
            let x = b
                .node_position(rail)
                .expect("rail nodes are generated first");
            b.node(anchor, [x.x, x.y, x.z]);
            b.rigid_link(master, anchor, DofSet::ALL);
            *eid += 1;
            b.element(
                "spring_damper",
                *eid,
                &[anchor, rail],
                &serde_json::json!({"k": slab.fastener_k, "c": slab.fastener_c, "axes": axes}),
            );
        }
    }
    // Subgrade under the slab off the bridge: rates per metre × tributary length.
    if slab.subgrade_k.iter().any(|v| *v > 0.0) || slab.subgrade_c.iter().any(|v| *v > 0.0) {
        for g in layout.segments.iter().filter(|g| g.span.is_none()) {
            for i in g.first..=g.last {
                let left = if i > g.first { st[i] - st[i - 1] } else { 0.0 };
                let right = if i < g.last { st[i + 1] - st[i] } else { 0.0 };
                let trib = 0.5 * (left + right);
                let k: Vec<f64> = slab.subgrade_k.iter().map(|v| v * trib).collect();
                let c: Vec<f64> = slab.subgrade_c.iter().map(|v| v * trib).collect();
                *eid += 1;
                b.element(
                    "spring_damper",
                    *eid,
                    &[g.node(i)],
                    &serde_json::json!({"k": k, "c": c, "axes": spring_axes_at(track, st[i])}),
                );
            }
        }
    }
    let Some(br) = bridge else {
        return Ok((layout, None));
    };
    // Piers: top at the girder line of every interior joint, base pier_height below (global Z).
    let mut pier_tops = vec![None; br.spans + 1];
    let mut pier_bases = vec![None; br.spans + 1];
    let ne = br.pier_elements;
    let mut pier_nodes = Vec::new();
    for (j, &i) in joints_idx.iter().enumerate() {
        if j == 0 || j == br.spans {
            continue;
        }
        let top = slab_pos(i);
        let ids: Vec<u64> = (0..=ne).map(|q| next_node + q as u64).collect();
        next_node += ne as u64 + 1;
        for (q, id) in ids.iter().enumerate() {
            let z = top[2] - br.pier_height * q as f64 / ne as f64;
            let fixed = if q == ne { DofSet::ALL } else { DofSet::NONE };
            b.node_fixed(*id, [top[0], top[1], z], fixed);
        }
        pier_tops[j] = Some(ids[0]);
        pier_bases[j] = Some(ids[ne]);
        pier_nodes.push((i, ids));
    }
    // Bearings: span start fixed, span end roller; to the pier top or the ground.
    let mut spans = Vec::with_capacity(br.spans);
    for (gi, g) in layout.segments.iter().enumerate() {
        let Some(k) = g.span else { continue };
        for (end, i, kind) in [
            (0, g.first, &br.bearing_fixed),
            (1, g.last, &br.bearing_roller),
        ] {
            let girder = g.node(i);
            let axes = spring_axes_at(track, st[i]);
            let p = serde_json::json!({"k": kind, "c": br.bearing_c, "axes": axes});
            *eid += 1;
            match pier_tops[k + end] {
                Some(top) => b.element("spring_damper", *eid, &[top, girder], &p),
                None => b.element("spring_damper", *eid, &[girder], &p),
            };
        }
        let mid = 0.5 * (st[g.first] + st[g.last]);
        let im = (g.first..=g.last)
            .min_by(|a, c| (st[*a] - mid).abs().total_cmp(&(st[*c] - mid).abs()))
            .unwrap_or(g.first);
        spans.push(SpanLayout {
            start: st[g.first],
            end: st[g.last],
            segment: gi,
            first_node: g.node(g.first),
            last_node: g.node(g.last),
            midspan_node: g.node(im),
        });
    }
    // Pier columns, base (I) to top (J) per element; local y along the track.
    for (i, ids) in &pier_nodes {
        let t = track.at(st[*i]).frame.column(2).into_owned();
        let p = beam_params(&br.pier, [t.x, t.y, t.z]);
        for q in 0..ne {
            *eid += 1;
            b.element("beam3d", *eid, &[ids[q + 1], ids[q]], &p);
        }
    }
    Ok((
        layout,
        Some(BridgeLayout {
            spans,
            pier_tops,
            pier_bases,
        }),
    ))
}

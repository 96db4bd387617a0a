//! The track model generator: two rails as `beam3d` elements along a canted alignment, on
//! discrete supports, plus the lookup a moving wheel uses to find the rail element under it.
//!
//! Rails are meshed at stations common to both rails. Segment joints, every rail support
//! (each multiple of the support or fastener spacing) and, on a bridge, every span joint
//! and midspan are nodes ([`TrackMesh::cuts`]); between two such cuts the interval is split
//! into `ceil(length / element_length)` equal elements. `element_length` is thus an upper
//! bound: the supports sit at their true stations on every mesh, and with `element_length`
//! above the support spacing each bay is one element ([`TrackModel::longest_element`]
//! gives the length actually used). A rail's beam line is the top centre of its
//! head, at `±rail_offset` along the wheel frame's axis 1 (in the canted plane), so the
//! outer rail is raised by the cant. The default offset `G/2 + 36 mm` puts the gauge faces
//! of 60E1 heads (14 mm below the top) `G` apart. Supports:
//!
//! - `rigid`: rail nodes fixed, no beam elements at all — the wheels roll on the exact
//!   alignment and the scene pays nothing for the rails (the validation of Section 4);
//! - `discrete`: a grounded `spring_damper` (vertical, lateral, longitudinal and rotational
//!   springs in the wheel frame, with dampers) every `spacing` metres of track;
//! - `slab`: rails on fasteners on a concrete slab on the subgrade, and `bridge`: the same
//!   slab on simply supported girders with bearings and piers ([`crate::rail::geometry::bridge`], which
//!   also documents the numbering of those components).
//!
//! Node ids of rail `r` are `first_id[r] + i` for station `i`, consecutive, so that a
//! moving wheel can re-pick its nodes by index in O(log n) ([`TrackModel::locate`]).

use crate::rail::geometry::bridge::{
    generate_structure, support_nodes, support_stations, BridgeLayout, BridgeSpec, RailsInfo,
    SlabLayout, SlabTrack,
};
use crate::rail::geometry::cant::Track;
use crate::rail::geometry::irregularity::Irregularity;
pub use crate::rail::geometry::rail_defect::{DipShape, JointDip, RailSide};
pub use crate::rail::geometry::rail_section::RailSection;
use railfem_framework::builder::ModelBuilder;
use railfem_framework::error::FemError;
use railfem_framework::limits::{self, fmt_num};
use railfem_framework::moving::Path;
use railfem_framework::DofSet;
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// How the rails are supported.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum RailSupport {
    /// Rails fixed in space: no rail DOFs, no rail elements.
    Rigid,
    /// Grounded spring-dampers at a spacing.
    Discrete {
        /// Support spacing along the track (m); supports sit at the mesh node nearest to
        /// each multiple of the spacing.
        spacing: f64,
        /// Springs `[lateral (axis 1), vertical (axis 2), longitudinal (axis 3), roll, yaw?, …]`
        /// as six values in the wheel frame: `[k1, k2, k3, kr1, kr2, kr3]` (N/m, N·m/rad).
        k: [f64; 6],
        /// Dampers, same order (N·s/m, N·m·s/rad).
        #[serde(default)]
        c: [f64; 6],
    },
    /// Rails on fasteners on a slab on the subgrade.
    Slab(Box<SlabTrack>),
    /// Rails on fasteners on a slab on simply supported girders, bearings and piers.
    Bridge(Box<BridgeSpec>),
}

/// Mesh settings of the `[track]` table.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TrackMesh {
    /// Largest rail element length (m): every interval between cuts (segment joints,
    /// supports, bridge joints and midspans) is split into equal elements no longer than it.
    #[serde(default = "default_element_length")]
    pub element_length: f64,
    /// Lateral offset of each rail's beam line from the centre line (m); default
    /// `G/2 + 0.036`.
    #[serde(default)]
    pub rail_offset: Option<f64>,
    /// Rail section (default 60E1).
    #[serde(default = "RailSection::uic60")]
    pub rail: RailSection,
    /// Supports (default rigid).
    #[serde(default = "default_support")]
    pub support: RailSupport,
    /// Mesh only stations in `[from, to]` (m); default the whole track.
    #[serde(default)]
    pub window: Option<[f64; 2]>,
    /// Dipped rail joints and isolated rail-top defects (squats, dips), per rail: vertical
    /// irregularities of the rail top under the wheels ([`crate::rail::geometry::rail_defect`]).
    #[serde(default)]
    pub dips: Vec<JointDip>,
}

fn default_element_length() -> f64 {
    0.6
}

fn default_support() -> RailSupport {
    RailSupport::Rigid
}

impl Default for TrackMesh {
    fn default() -> Self {
        TrackMesh {
            element_length: 0.6,
            rail_offset: None,
            rail: RailSection::uic60(),
            support: RailSupport::Rigid,
            window: None,
            dips: Vec::new(),
        }
    }
}

impl TrackMesh {
    /// Spacing of the rail supports (m): the discrete supports' or the fasteners'; `None`
    /// on a rigid track.
    pub fn support_spacing(&self) -> Option<f64> {
        match &self.support {
            RailSupport::Rigid => None,
            RailSupport::Discrete { spacing, .. } => Some(*spacing),
            RailSupport::Slab(sl) => Some(sl.fastener_spacing),
            RailSupport::Bridge(br) => Some(br.slab_track.fastener_spacing),
        }
    }

    /// Stations on `[from, to]` that must be nodes besides the alignment's segment joints:
    /// every rail support (each multiple of [`TrackMesh::support_spacing`]) and, on a
    /// bridge, every joint and midspan (m, unsorted).
    pub fn cuts(&self, [from, to]: [f64; 2]) -> Vec<f64> {
        let mut out = self
            .support_spacing()
            .map_or_else(Vec::new, |sp| support_stations(from, to, sp));
        if let RailSupport::Bridge(br) = &self.support {
            out.extend(br.joints());
            out.extend(br.midspans());
        }
        out
    }

    /// The rail node stations on `[from, to]` (m): [`mesh_stations_cut`] at
    /// `element_length` with [`TrackMesh::cuts`]. The support spacing must be valid (as
    /// [`generate`] checks).
    pub fn stations(&self, track: &Track, [from, to]: [f64; 2]) -> Vec<f64> {
        let cuts = self.cuts([from, to]);
        mesh_stations_cut(track, from, to, self.element_length, &cuts)
    }
}

/// One rail of the mesh.
#[derive(Debug, Clone, PartialEq)]
pub struct RailLine {
    /// Signed lateral offset along axis 1 (m): positive = left rail.
    pub offset: f64,
    /// Node id of station 0; node `i` has id `first_id + i`.
    pub first_id: u64,
}

/// The generated track: geometry, stations and rails. Shared with the elements that ride
/// on it (as the model resource `"track"`).
#[derive(Debug, Clone)]
pub struct TrackModel {
    /// The track geometry (alignment and cant).
    pub track: Arc<Track>,
    /// Stations of the rail nodes (m), increasing.
    pub stations: Vec<f64>,
    /// Left rail (index 0) and right rail (index 1).
    pub rails: [RailLine; 2],
    /// Whether rails are rigid (no DOFs).
    pub rigid: bool,
    /// The slab of a slab or bridge track.
    pub slab: Option<SlabLayout>,
    /// The bridge: spans, girder and pier node ids.
    pub bridge: Option<BridgeLayout>,
    /// Dipped rail joints and isolated rail-top defects.
    pub dips: Vec<JointDip>,
    /// The track irregularity (`[track] irregularity`), if any.
    pub irregularity: Option<Arc<Irregularity>>,
}

impl TrackModel {
    /// The rail element under station `s` and the local coordinate `ξ ∈ [0, 1]`; O(log n).
    /// A station exactly on a node belongs to the element that starts there (the last
    /// node to the last element). `None` off the mesh.
    pub fn locate(&self, s: f64) -> Option<(usize, f64)> {
        crate::rail::geometry::railline::locate_in(&self.stations, s)
    }

    /// The longest rail element (m): `element_length` or less, the support spacing when
    /// `element_length` exceeds it (supports are always nodes).
    pub fn longest_element(&self) -> f64 {
        self.stations
            .windows(2)
            .map(|w| w[1] - w[0])
            .fold(0.0, f64::max)
    }

    /// Reference position of rail `r` at station `s` (m), global.
    pub fn rail_position(&self, r: usize, s: f64) -> nalgebra::Vector3<f64> {
        let p = self.track.at(s);
        p.position + p.frame.column(0) * self.rails[r].offset
    }

    /// Rail-top height change of the dips on rail `rail` (0 left, 1 right) at station `s`
    /// (m, negative down).
    pub fn rail_top_height(&self, rail: usize, s: f64) -> f64 {
        self.dips.iter().map(|d| d.height_on(rail, s)).sum()
    }

    /// `[lateral (axis 1), vertical (axis 2)]` displacement of the head of rail `rail`
    /// (0 left, 1 right) at station `s` (m) in the wheel frame: the irregularity
    /// ([`crate::rail::geometry::irregularity`]) plus the dipped joints (vertical). A wheel's contact
    /// point C is moved by it; the rails' beam lines are not.
    pub fn rail_offset(&self, rail: usize, s: f64) -> [f64; 2] {
        let dip = self.rail_top_height(rail, s);
        match &self.irregularity {
            None => [0.0, dip],
            Some(irr) => {
                let [y, z] = irr.rail_offset(rail, s);
                [y, z + dip]
            }
        }
    }
}

/// The rail-head offsets ([`TrackModel::rail_offset`]) a wheel rides over, measured from
/// their value at the wheel's first station, so that every wheel starts just touching the
/// rail where it stands (zero there unless it starts on an irregularity or in a dip).
/// Differences of rail height between the wheels at t = 0 therefore do not preload the
/// suspensions. One per wheel: the first call fixes the reference.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct OffsetFromStart {
    start: Option<[f64; 2]>,
}

impl OffsetFromStart {
    /// `[lateral, vertical]` offset of rail `rail` at station `s` minus its value at the
    /// station of the first call (m, wheel frame).
    pub fn at(&mut self, track: &TrackModel, rail: usize, s: f64) -> [f64; 2] {
        let [lat, vert] = track.rail_offset(rail, s);
        let [lat0, vert0] = *self.start.get_or_insert([lat, vert]);
        [lat - lat0, vert - vert0]
    }
}

/// Mesh stations on `[a, b]`: every segment joint inside, the rest evenly at about `h`.
pub fn mesh_stations(track: &Track, a: f64, b: f64, h: f64) -> Vec<f64> {
    mesh_stations_cut(track, a, b, h, &[])
}

/// Mesh stations on `[a, b]` cut at every segment joint and at `extra` stations; each
/// interval between cuts is split into `ceil(length / h)` equal elements.
pub fn mesh_stations_cut(track: &Track, a: f64, b: f64, h: f64, extra: &[f64]) -> Vec<f64> {
    let mut cuts = vec![a];
    let mut s0 = 0.0;
    for seg in track.alignment.segments() {
        s0 += seg.length();
        if s0 > a + 1e-9 && s0 < b - 1e-9 {
            cuts.push(s0);
        }
    }
    cuts.extend(
        extra
            .iter()
            .copied()
            .filter(|s| *s > a + 1e-9 && *s < b - 1e-9),
    );
    cuts.push(b);
    cuts.sort_by(f64::total_cmp);
    cuts.dedup_by(|x, y| (*x - *y).abs() < 1e-6);
    let mut out = vec![a];
    for w in cuts.windows(2) {
        // Less a round-off allowance: a bay of m·0.1 − (m − 1)·0.1 = 0.10000000000000003 m
        // meshed at h = 0.1 is one element, not two.
        let n = ((w[1] - w[0]) / h - 1e-9).ceil().max(1.0) as usize;
        for i in 1..=n {
            out.push(w[0] + (w[1] - w[0]) * i as f64 / n as f64);
        }
    }
    out
}

/// The size guard of [`generate`]: the stations `[from, to]` meshed at `element_length`
/// plus at most one per cut (segment joint, rail support, bridge joint or midspan; counted
/// twice, a margin), each carrying two rail nodes — fixed for a rigid support, else 12
/// DOFs of rails plus 6 of the slab or girder — against the memory budget
/// ([`limits::check_memory`]). Counted, not generated, so that a tiny spacing is refused
/// before its stations are allocated.
pub fn check_mesh_size(
    track: &Track,
    mesh: &TrackMesh,
    [from, to]: [f64; 2],
) -> Result<(), String> {
    let h = mesh.element_length;
    let supports = mesh
        .support_spacing()
        .map_or(0.0, |sp| (to - from) / sp + 1.0);
    let bridge = match &mesh.support {
        RailSupport::Bridge(br) => 2 * br.spans + 1,
        _ => 0,
    };
    let cuts = (track.alignment.segments().len() + bridge + 1) as f64 + supports;
    let stations = (to - from) / h + 2.0 * cuts + 1.0;
    let (per_station, what) = match mesh.support {
        RailSupport::Rigid => (2.0 * limits::BYTES_PER_NODE, "rail nodes"),
        RailSupport::Discrete { .. } => (12.0 * limits::BYTES_PER_DOF, "rail stations"),
        _ => (18.0 * limits::BYTES_PER_DOF, "rail and slab stations"),
    };
    let span = match mesh.window {
        Some(_) => format!("the `window` [{}, {}] m", fmt_num(from), fmt_num(to)),
        None => format!("{} m of track", fmt_num(to - from)),
    };
    // Every support is a node: a tiny spacing is named, not blamed on the element length.
    let (subject, hint) = match mesh.support_spacing() {
        Some(sp) => (
            format!(
                "`element_length` = {} m with a rail support every {} m over {span}",
                fmt_num(h),
                fmt_num(sp)
            ),
            "give a larger `element_length` or support spacing, or mesh a shorter `window`",
        ),
        None => (
            format!("`element_length` = {} m over {span}", fmt_num(h)),
            "give a larger `element_length` or mesh a shorter `window`",
        ),
    };
    limits::check_memory(&subject, stations, what, per_station, hint)
}

/// Generates the rails of `track` into `b` and registers the resource `"track"`. Node ids
/// start above every id already in the builder; element ids likewise.
pub fn generate(
    b: &mut ModelBuilder,
    track: Arc<Track>,
    mesh: &TrackMesh,
) -> Result<Arc<TrackModel>, FemError> {
    generate_with(b, track, mesh, None)
}

/// [`generate`] with a track irregularity that every wheel sees at its station.
pub fn generate_with(
    b: &mut ModelBuilder,
    track: Arc<Track>,
    mesh: &TrackMesh,
    irregularity: Option<Arc<Irregularity>>,
) -> Result<Arc<TrackModel>, FemError> {
    let origin = format!("{}: [track]", b.origin());
    let h = mesh.element_length;
    if !(h.is_finite() && h > 0.0) {
        return Err(FemError::input(
            &origin,
            format!("element_length = {}; give a length > 0 m", fmt_num(h)),
        ));
    }
    let len = track.length();
    let [from, to] = mesh.window.unwrap_or([0.0, len]);
    if !(from.is_finite() && to.is_finite() && to > from) {
        return Err(FemError::input(
            &origin,
            "window must be [from, to] with from < to (m)",
        ));
    }
    match &mesh.support {
        RailSupport::Bridge(br) => br.validate(&origin, from, to)?,
        RailSupport::Slab(sl) => sl.validate(&origin)?,
        RailSupport::Discrete { spacing, .. } => {
            if !(spacing.is_finite() && *spacing > 0.0) {
                return Err(FemError::input(&origin, "support spacing must be > 0 m"));
            }
        }
        RailSupport::Rigid => {}
    }
    check_mesh_size(&track, mesh, [from, to]).map_err(|m| FemError::input(&origin, m))?;
    let stations = mesh.stations(&track, [from, to]);
    let offset = mesh.rail_offset.unwrap_or(track.gauge / 2.0 + 0.036);
    if !(offset.is_finite() && offset > 0.0) {
        return Err(FemError::input(&origin, "rail_offset must be > 0 m"));
    }
    let rigid = matches!(mesh.support, RailSupport::Rigid);
    let n = stations.len() as u64;
    let base = (b.max_node_id() / 1000 + 1) * 1000;
    let rails = [
        RailLine {
            offset,
            first_id: base,
        },
        RailLine {
            offset: -offset,
            first_id: base + n,
        },
    ];
    let mut model = TrackModel {
        track: track.clone(),
        stations,
        rails,
        rigid,
        slab: None,
        bridge: None,
        dips: mesh.dips.clone(),
        irregularity,
    };
    for (i, d) in mesh.dips.iter().enumerate() {
        d.validate()
            .map_err(|m| FemError::input(&origin, format!("dips[{i}]: {m}")))?;
    }
    let fix = if rigid { DofSet::ALL } else { DofSet::NONE };
    for (r, rail) in model.rails.iter().enumerate() {
        for (i, &s) in model.stations.iter().enumerate() {
            let p = model.rail_position(r, s);
            b.node_fixed(rail.first_id + i as u64, [p.x, p.y, p.z], fix);
        }
    }
    if !rigid {
        let sec = mesh.rail;
        let mut eid = (b.max_element_id() / 1000 + 1) * 1000;
        for (r, rail) in model.rails.iter().enumerate() {
            for i in 0..model.stations.len() - 1 {
                let sm = 0.5 * (model.stations[i] + model.stations[i + 1]);
                let up = track.at(sm).frame.column(1).into_owned();
                eid += 1;
                b.element(
                    "beam3d",
                    eid,
                    &[rail.first_id + i as u64, rail.first_id + i as u64 + 1],
                    &serde_json::json!({
                        "E": sec.e, "G": sec.g, "A": sec.a,
                        "Iz": sec.i_vertical, "Iy": sec.i_lateral, "J": sec.j,
                        "rho": sec.rho, "orient": [up.x, up.y, up.z],
                    }),
                );
            }
            let _ = r;
        }
        match &mesh.support {
            RailSupport::Discrete { spacing, k, c } => {
                let picks = support_nodes(&model.stations, *spacing, &origin)?;
                for rail in &model.rails {
                    for &i in &picks {
                        let f = track.at(model.stations[i]).frame;
                        let rows: Vec<[f64; 3]> =
                            (0..3).map(|c| [f[(0, c)], f[(1, c)], f[(2, c)]]).collect();
                        eid += 1;
                        b.element(
                            "spring_damper",
                            eid,
                            &[rail.first_id + i as u64],
                            &serde_json::json!({"k": k, "c": c, "axes": [rows[0], rows[1]]}),
                        );
                    }
                }
            }
            RailSupport::Slab(slab) => {
                let info = RailsInfo {
                    track: &track,
                    stations: &model.stations,
                    rail_first: [model.rails[0].first_id, model.rails[1].first_id],
                    next_node: base + 2 * n,
                };
                let (layout, _) = generate_structure(b, &info, slab, None, &mut eid, &origin)?;
                model.slab = Some(layout);
            }
            RailSupport::Bridge(br) => {
                let info = RailsInfo {
                    track: &track,
                    stations: &model.stations,
                    rail_first: [model.rails[0].first_id, model.rails[1].first_id],
                    next_node: base + 2 * n,
                };
                let (layout, bl) =
                    generate_structure(b, &info, &br.slab_track, Some(&**br), &mut eid, &origin)?;
                model.slab = Some(layout);
                model.bridge = bl;
            }
            RailSupport::Rigid => {}
        }
    }
    let model = Arc::new(model);
    b.resource("track", model.clone());
    Ok(model)
}

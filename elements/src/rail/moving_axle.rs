//! The moving wheel-axle contact element of Ju & Ro (2021), Section 2.3: one wheel of a
//! wheelset rolling on a rail, with multi-point profile contact that sticks, slides or
//! separates under Coulomb friction.
//!
//! # Nodes and DOFs (21)
//!
//! In element order: node **B** (the wheel's contact master, internal, 3 translations),
//! node **K** (the axle centre, 6 DOFs, shared by both wheels of a wheelset), and the rail
//! nodes **I** and **J** (6 DOFs each) of the rail element under the wheel. B and K are
//! carried by the vehicle's moving frame at the wheelset's station, so their DOFs are in the
//! wheel frame 1-2-3 there; I and J are ordinary nodes in global axes. B's rotations are
//! K's (the wheelset is rigid); node A is a slave of K at B's position that only anchors
//! the springs `k1, k2, k3` (Eqs. 16–20).
//!
//! # What the element computes
//!
//! - **Springs A–B** (Eqs. 15–18): with `δ = u_B − u_A`, `u_A = u_K + θ_K × (x_B − x_K)`,
//!   lateral `k1·δ1`, longitudinal `k3·δ3` and the power law `k2 = a + b·f2^c` vertically
//!   ([`super::hertz_spring`]).
//! - **Contact** (Eqs. 6–13): every rail profile node (attached rigidly to the rail point
//!   C, which moves with the rail beam I–J by [`super::rail_point`], Eq. 14) is tested
//!   against the wheel profile spline (attached rigidly to B). The relative displacement of
//!   node `k`, `Δ_k = (u_C + θ_C × ρ_C) − (u_B + θ_K × ρ_B)` in the wheel frame, is linear
//!   in the 21 DOFs (`Δ_k = T_k·q`, the reconstructed Eq. 12); its position in the wheel's
//!   profile plane is `p_k = p_k⁰ + (Δ_k·e1, Δ_k·e2)`, whose signed distance to the wheel
//!   spline is the gap. Each penetrating node is a contact point with the frictional penalty
//!   law of [`super::contact_law`]; tread and flange contact happen together. The element
//!   force and tangent are `Σ T_kᵀ·φ_k` and `Σ T_kᵀ·D_k·T_k`.
//! - **Moving**: at each step the element reads the wheelset's station and frame, finds
//!   the rail element under the wheel in O(log n), and re-picks I and J when the wheel
//!   crosses into the next element (connectivity change). On a rigid track the rail nodes
//!   have no DOFs and the element never asks for a new pattern.
//!
//! Only rail nodes inside the wheel's lateral reach are searched (a binary-search window),
//! and nodes below the wheel's lowest point are skipped without a closest-point search, so
//! a wheel lifted clear costs almost nothing.
//!
//! # Reference geometry
//!
//! The wheel profile's origin (the tape-circle contact point) is at B, `contact_offset`
//! from the track centre line on axis 1; the rail profile's origin (top of the head) is at
//! C on the rail's beam line. At build time the wheel profile is shifted along axis 2 so
//! that its smallest gap to the rail is −1 nm: the wheel starts just touching.

use super::contact_geometry::{candidate_window, rail_node_gap};
use super::contact_law::{Anchor, Mode, PenaltyLaw, PointState, SlidingTangent};
use super::hertz_spring::HertzSpring;
use super::profiles::{Inclination, RailProfile, WheelProfile};
use super::rail_point::{beam_axes, rail_point_matrix};
use super::track_model::{OffsetFromStart, TrackModel};
use nalgebra::{DMatrix, Matrix3, SMatrix, Vector2, Vector3};
use railfem_framework::element::*;
use railfem_framework::error::FemError;
use railfem_framework::limits::fmt_num;
use railfem_framework::moving::Path;
use railfem_framework::registry::{BuildContext, ElementKind, ElementSpec, Params, Sample};
use std::sync::Arc;

railfem_framework::element_params! {
    /// Model-file keys of `moving_axle` (SI units). Defaults are the stand-in values of
    /// `shared/spec/vehicle-track-profiles.md` (documented assumptions, not the paper's).
    pub struct MovingAxleParams {
        /// Which wheel of the wheelset: "left" (axis 1 positive) or "right".
        side: String [""],
        /// Lateral distance of the wheel's tape-circle contact point from the centre line (m).
        contact_offset: f64 ["m"] = 0.75,
        /// Wheel profile: "s1002" or a CSV file (header states the units).
        wheel_profile: String [""] = "s1002",
        /// Number of points sampling a built-in wheel profile.
        wheel_points: usize ["-"] = 120,
        /// Rail profile: "60e1" or a CSV file of rail nodes.
        rail_profile: String [""] = "60e1",
        /// Number of rail profile nodes (30–60 in the paper's Figure 4).
        rail_nodes: usize ["-"] = 41,
        /// Rail inclination: "none", "1:40" or "1:20".
        inclination: String [""] = "1:40",
        /// Lateral spring k1 between A and B (N/m).
        k1: f64 ["N/m"] = 1.0e9,
        /// Longitudinal spring k3 between A and B (N/m).
        k3: f64 ["N/m"] = 1.0e9,
        /// Vertical spring law k2 = a + b·f2^c: constant a (N/m), > 0.
        a: f64 ["N/m"] = 1.0e7,
        /// Vertical spring law: coefficient b (N^(1-c)/m); Hertz for R 0.43 m on R 0.30 m.
        b: f64 ["N^(1-c)/m"] = 3.03e7,
        /// Vertical spring law: exponent c (-), 0 ≤ c < 1.
        c: f64 ["-"] = 0.333_333_333_333_333_3,
        /// Contact penalty k, normal and in-plane tangential (N/m).
        k: f64 ["N/m"] = 1.0e10,
        /// Contact penalty k_v, longitudinal (N/m).
        k_v: f64 ["N/m"] = 1.0e10,
        /// Coefficient of friction μ (-).
        mu: f64 ["-"] = 0.3,
        /// Sliding tangent: "symmetric" (Ju & Rowlands, Eq. 8) or "consistent".
        sliding_tangent: String [""] = "symmetric",
        /// Name of the track resource the wheel rides on.
        track: String [""] = "track",
        /// Static wheel load for ΔQ/Q (N); 0 = the load at the first converged state.
        static_load: f64 ["N"] = 0.0,
    }
}

/// Settings of one wheel that do not change while it runs.
#[derive(Debug, Clone)]
struct Setup {
    params: MovingAxleParams,
    law: PenaltyLaw,
    spring: HertzSpring,
    /// 0 = left rail, 1 = right rail.
    rail: usize,
    /// Wheel profile, in its side's orientation.
    wheel: WheelProfile,
    /// Shift of the wheel profile origin relative to B in the profile plane (m).
    wheel_shift: Vector2<f64>,
    /// Lateral reach of the wheel profile (m), for the search window.
    wheel_y: (f64, f64),
    /// Lowest point of the wheel profile (m), after the shift.
    wheel_z_min: f64,
    /// Rail profile nodes, in their side's orientation (sorted by y).
    rail_nodes: Vec<Vector2<f64>>,
}

/// The committed (history) state of the element.
#[derive(Debug, Clone, PartialEq)]
struct History {
    anchors: Vec<Anchor>,
    dissipated: f64,
    static_load: f64,
}

/// The moving wheel-axle element (one wheel).
pub struct MovingAxle {
    setup: Arc<Setup>,
    track: Arc<TrackModel>,
    /// Node indices: B, K, and the first node of each rail.
    b: usize,
    k: usize,
    rail_first: usize,
    conn: [NodeDofs; 4],
    /// Current rail element and local coordinate.
    elem: usize,
    xi: f64,
    station: f64,
    /// Rail-head offsets (dips and irregularity) measured from the wheel's first station.
    start_offset: OffsetFromStart,
    /// Prescribed vertical displacement of the rail head under the wheel from the dips and
    /// the irregularity, measured from `start_offset` (wheel frame: 0, vertical, 0; m).
    rail_offset: Vector3<f64>,
    /// Wheel frame at the station (columns e1 e2 e3, global).
    frame: Matrix3<f64>,
    /// B − K and C − B at the reference, wheel-frame components (m).
    r_bk: Vector3<f64>,
    r_cb: Vector3<f64>,
    /// Rail-point interpolation premultiplied into the wheel frame: 6×12.
    rail_map: SMatrix<f64, 6, 12>,
    committed: History,
    trial: History,
    /// Whether `update` ran since the last commit or revert.
    dirty: bool,
    // Trial results.
    force: Vec<f64>,
    tangent: DMatrix<f64>,
    points: Vec<(usize, PointState, f64, f64)>,
    /// Contact angle of each point (rad): between the contact normal and axis 2.
    angles: Vec<f64>,
    /// Position of each contact point in the wheel frame relative to the track centre line
    /// at rail-top level: (lateral, vertical) (m).
    positions: Vec<Vector2<f64>>,
    spring_force: Vector3<f64>,
    contact_force: Vector3<f64>,
    deltas: Vec<Vector3<f64>>,
    frames: Vec<(Vector3<f64>, Vector3<f64>)>,
    /// In-plane rigid motion of the wheel relative to the rail at the trial state: the
    /// wheel's displacement at C's reference position (m, axes 1-2) and its roll relative
    /// to the rail (rad, about axis 3). For drawing cross-sections.
    relative: (Vector2<f64>, f64),
    /// Position and gap of each rail node at its last closest-point search: the signed
    /// distance is 1-Lipschitz, so a node whose gap exceeds how far it has moved since is
    /// still open and needs no search.
    last_gap: Vec<Option<(Vector2<f64>, f64)>>,
}

pub use super::profiles::MAX_PROFILE_POINTS;
/// Fewest points of the built-in wheel profile (`wheel_points`).
pub const MIN_WHEEL_POINTS: usize = 20;
/// Fewest nodes of the built-in rail profile (`rail_nodes`).
pub const MIN_RAIL_NODES: usize = 4;

/// Keys a `moving_axle` table may not give in the situation at hand, because nothing
/// would read them (the documentation says so): the sampling counts of a built-in
/// profile when the profile is a CSV file. Returns the message for the first.
pub fn ignored_keys(params: &serde_json::Map<String, serde_json::Value>) -> Option<String> {
    let is_file = |key: &str, builtin: &[&str]| {
        params
            .get(key)
            .and_then(|v| v.as_str())
            .is_some_and(|s| !builtin.contains(&s.to_ascii_lowercase().as_str()))
    };
    for (count, profile, builtin) in [
        ("wheel_points", "wheel_profile", &["s1002"][..]),
        ("rail_nodes", "rail_profile", &["60e1", "uic60"][..]),
    ] {
        if params.contains_key(count) && is_file(profile, builtin) {
            return Some(format!(
                "`{count}` would be ignored: it samples the built-in profile, but `{profile}` is a CSV file (its points are used as they are); remove `{count}`"
            ));
        }
    }
    None
}

fn skew(r: &Vector3<f64>) -> Matrix3<f64> {
    // [r]ₓ such that [r]ₓ·θ = r × θ.
    Matrix3::new(0.0, -r.z, r.y, r.z, 0.0, -r.x, -r.y, r.x, 0.0)
}

fn bad(spec: &ElementSpec, m: impl Into<String>) -> FemError {
    FemError::input(&spec.origin, m.into())
}

impl Setup {
    fn new(params: MovingAxleParams, origin: &str, rail_offset: f64) -> Result<Setup, FemError> {
        let err = |m: String| FemError::input(origin, m);
        let side = match params.side.to_ascii_lowercase().as_str() {
            "left" => 0,
            "right" => 1,
            s => return Err(err(format!("`side` = \"{s}\"; use \"left\" or \"right\""))),
        };
        for (key, v, min) in [
            ("k1", params.k1, 0.0),
            ("k3", params.k3, 0.0),
            ("a", params.a, 0.0),
            ("k", params.k, 0.0),
            ("k_v", params.k_v, 0.0),
        ] {
            if !(v.is_finite() && v > min) {
                return Err(err(format!(
                    "`{key}` = {}; give a stiffness > 0 N/m",
                    fmt_num(v)
                )));
            }
        }
        if !(params.b.is_finite() && params.b >= 0.0) {
            return Err(err(format!("`b` = {}; give b ≥ 0", fmt_num(params.b))));
        }
        if !(params.c.is_finite() && (0.0..1.0).contains(&params.c)) {
            return Err(err(format!(
                "`c` = {}; the exponent must satisfy 0 ≤ c < 1",
                fmt_num(params.c)
            )));
        }
        if !(params.mu.is_finite() && params.mu >= 0.0) {
            return Err(err(format!(
                "`mu` = {}; give a friction coefficient ≥ 0",
                fmt_num(params.mu)
            )));
        }
        if !(params.contact_offset.is_finite() && params.contact_offset > 0.0) {
            return Err(err("`contact_offset` must be > 0 m".into()));
        }
        let tangent = match params.sliding_tangent.as_str() {
            "symmetric" => SlidingTangent::Symmetric,
            "consistent" => SlidingTangent::Consistent,
            s => {
                return Err(err(format!(
                    "`sliding_tangent` = \"{s}\"; use \"symmetric\" or \"consistent\""
                )))
            }
        };
        let incl = match params.inclination.as_str() {
            "none" | "0" => Inclination::None,
            "1:40" => Inclination::OneIn40,
            "1:20" => Inclination::OneIn20,
            s => {
                return Err(err(format!(
                    "`inclination` = \"{s}\"; use \"none\", \"1:40\" or \"1:20\""
                )))
            }
        };
        // Sampling counts: beyond a few thousand points the profile is no more accurate
        // (the spline error of 120 points is already below 1e-6 m) and only costs memory.
        // Below the minimum the built-in sampling is meaningless (a not-a-knot spline needs
        // four points; the S1002 flange needs about twenty): refused, not replaced.
        for (key, v, min) in [
            ("wheel_points", params.wheel_points, MIN_WHEEL_POINTS),
            ("rail_nodes", params.rail_nodes, MIN_RAIL_NODES),
        ] {
            if !(min..=MAX_PROFILE_POINTS).contains(&v) {
                return Err(err(format!(
                    "`{key}` = {v}; give at least {min} and at most {MAX_PROFILE_POINTS} points"
                )));
            }
        }
        let wheel = match params.wheel_profile.to_ascii_lowercase().as_str() {
            "s1002" => WheelProfile::s1002(params.wheel_points),
            path => WheelProfile::from_csv_file(path)
                .map_err(|e| err(format!("`wheel_profile`: {e}")))?,
        };
        let rail = match params.rail_profile.to_ascii_lowercase().as_str() {
            "60e1" | "uic60" => RailProfile::uic60(params.rail_nodes, incl),
            path => RailProfile::from_csv_file(path, incl)
                .map_err(|e| err(format!("`rail_profile`: {e}")))?,
        };
        let (wheel, rail) = if side == 0 {
            (wheel, rail)
        } else {
            (wheel.mirrored(), rail.mirrored())
        };
        let rail_nodes = rail.nodes().to_vec();
        // Reference: rail origin relative to the wheel origin in the profile plane. For the
        // left wheel (axis 1 towards the field side) the rail lies `rail_offset −
        // contact_offset` further out; mirrored for the right one.
        let sign = if side == 0 { 1.0 } else { -1.0 };
        let c_rel_b = Vector2::new(sign * (rail_offset - params.contact_offset), 0.0);
        // Smallest gap of the rail nodes to the unshifted wheel: shift the wheel by it.
        let mut min_gap = f64::INFINITY;
        let (wheel_lo, wheel_hi) = wheel.spline().lateral_extent();
        for p in &rail_nodes {
            // Only nodes within the wheel's lateral reach are under it.
            let y = c_rel_b.x + p.x;
            if y < wheel_lo || y > wheel_hi {
                continue;
            }
            if let Some(c) = rail_node_gap(wheel.spline(), c_rel_b + p) {
                min_gap = min_gap.min(c.gap);
            }
        }
        if !min_gap.is_finite() {
            return Err(err(
                "no rail node lies under the wheel profile; check contact_offset and the track's rail_offset".into(),
            ));
        }
        // Moving the wheel by −g along its normal ≈ along −e2 for a tread contact; shift
        // the wheel down by the smallest gap (vertical), then refine once.
        let mut shift = Vector2::new(0.0, -min_gap);
        for _ in 0..3 {
            let mut g = f64::INFINITY;
            for p in &rail_nodes {
                if let Some(c) = rail_node_gap(wheel.spline(), c_rel_b + p - shift) {
                    g = g.min(c.gap);
                }
            }
            shift.y -= g;
        }
        // Start 1 nm into the rail, so that the first Newton iteration already has the
        // contact's stiffness (a force of k·1e-9 m, 10 N at k = 1e10 N/m).
        shift.y -= 1e-9;
        let pts = wheel.spline().points();
        let wheel_y = pts
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
                (a.min(p.x), b.max(p.x))
            });
        let wheel_z_min = pts.iter().map(|p| p.y).fold(f64::INFINITY, f64::min) + shift.y;
        Ok(Setup {
            law: PenaltyLaw {
                k: params.k,
                k_v: params.k_v,
                mu: params.mu,
                tangent,
            },
            spring: HertzSpring {
                a: params.a,
                b: params.b,
                c: params.c,
            },
            params,
            rail: side,
            wheel,
            wheel_shift: shift,
            wheel_y: (wheel_y.0 + shift.x, wheel_y.1 + shift.x),
            wheel_z_min,
            rail_nodes,
        })
    }
}

impl MovingAxle {
    /// Builds a wheel on `track` with axle node index `k` and internal node index `b`
    /// (already created at the wheel's contact point), rails starting at node index
    /// `rail_first` (rail `r`'s node `i` is `rail_first + r·n + i`).
    fn with(
        setup: Arc<Setup>,
        track: Arc<TrackModel>,
        b: usize,
        k: usize,
        rail_first: usize,
    ) -> MovingAxle {
        let n = setup.rail_nodes.len();
        let anchors = vec![
            Anchor {
                delta: Vector3::zeros(),
                u: Vector3::x(),
                v: Vector3::z(),
            };
            n
        ];
        let hist = History {
            anchors,
            dissipated: 0.0,
            static_load: setup.params.static_load,
        };
        MovingAxle {
            setup,
            track,
            b,
            k,
            rail_first,
            conn: [
                NodeDofs::translations(b),
                NodeDofs::all(k),
                NodeDofs::all(rail_first),
                NodeDofs::all(rail_first + 1),
            ],
            elem: 0,
            xi: 0.0,
            station: f64::NAN,
            start_offset: OffsetFromStart::default(),
            rail_offset: Vector3::zeros(),
            frame: Matrix3::identity(),
            r_bk: Vector3::zeros(),
            r_cb: Vector3::zeros(),
            rail_map: SMatrix::zeros(),
            committed: hist.clone(),
            trial: hist,
            dirty: false,
            force: vec![0.0; 21],
            tangent: DMatrix::zeros(21, 21),
            points: Vec::new(),
            angles: Vec::new(),
            positions: Vec::new(),
            spring_force: Vector3::zeros(),
            contact_force: Vector3::zeros(),
            deltas: vec![Vector3::zeros(); n],
            frames: vec![(Vector3::x(), Vector3::z()); n],
            relative: (Vector2::zeros(), 0.0),
            last_gap: vec![None; n],
        }
    }

    fn rail_node(&self, i: usize) -> usize {
        self.rail_first + self.setup.rail * self.track.stations.len() + i
    }

    /// Station of the wheel (m).
    pub fn station(&self) -> f64 {
        self.station
    }

    /// Total contact force on the wheel in the wheel frame (N): (lateral, normal, longitudinal).
    pub fn contact_force(&self) -> Vector3<f64> {
        self.contact_force
    }

    /// Contact points of the trial state: (rail node index, state, rail profile y, wheel
    /// profile y).
    pub fn contact_points(&self) -> impl Iterator<Item = (usize, &PointState, f64, f64)> {
        self.points.iter().map(|(i, s, yr, yw)| (*i, s, *yr, *yw))
    }

    /// Wheel profile points in the profile plane relative to B, rail profile nodes relative
    /// to C, and the reference offset C − B: for drawing cross-sections.
    pub fn profiles(&self) -> (Vec<Vector2<f64>>, Vec<Vector2<f64>>, Vector2<f64>) {
        let w: Vec<Vector2<f64>> = self
            .setup
            .wheel
            .spline()
            .points()
            .iter()
            .map(|p| p + self.setup.wheel_shift)
            .collect();
        (
            w,
            self.setup.rail_nodes.clone(),
            Vector2::new(self.r_cb.x, self.r_cb.y),
        )
    }

    /// The wheel's in-plane rigid motion relative to the rail at the trial state: its
    /// displacement at the rail point C (m, wheel-frame axes 1 and 2) and its roll relative
    /// to the rail (rad, about axis 3, positive from axis 1 to axis 2). A wheel point at
    /// `x` (profile plane, relative to B's reference) is displaced relative to the rail by
    /// `d + roll·ẑ × (x − (C − B))`. For drawing cross-sections ([`super::section_plot`]).
    pub fn relative_motion(&self) -> (Vector2<f64>, f64) {
        self.relative
    }

    /// The 3×21 map of rail profile node `k` from element DOFs to `Δ_k` (wheel frame).
    fn t_matrix(&self, rho_c: &Vector3<f64>) -> SMatrix<f64, 3, 21> {
        let rho_b = self.r_cb + rho_c;
        let mut t = SMatrix::<f64, 3, 21>::zeros();
        // Wheel point: u_B − [ρ_B]ₓ·θ_K, subtracted.
        t.fixed_view_mut::<3, 3>(0, 0)
            .copy_from(&(-Matrix3::identity()));
        t.fixed_view_mut::<3, 3>(0, 6).copy_from(&skew(&rho_b));
        if !self.track.rigid {
            // Rail point: Wᵀ·u_C − [ρ_C]ₓ·Wᵀ·θ_C, with (u_C, θ_C) = RP·q_IJ (global).
            let a = self.rail_map.fixed_view::<3, 12>(0, 0).into_owned();
            let b = self.rail_map.fixed_view::<3, 12>(3, 0).into_owned();
            let rail = a - skew(rho_c) * b;
            t.fixed_view_mut::<3, 12>(0, 9).copy_from(&rail);
        }
        t
    }

    /// The 3×21 map to the A–B spring elongation `δ = u_B − u_K + (x_B − x_K) × θ_K`.
    fn s_matrix(&self) -> SMatrix<f64, 3, 21> {
        let mut s = SMatrix::<f64, 3, 21>::zeros();
        s.fixed_view_mut::<3, 3>(0, 0)
            .copy_from(&Matrix3::identity());
        s.fixed_view_mut::<3, 3>(0, 3)
            .copy_from(&(-Matrix3::identity()));
        s.fixed_view_mut::<3, 3>(0, 6).copy_from(&skew(&self.r_bk));
        s
    }

    fn place(&mut self, kin: &[NodeKinematics]) -> Result<bool, ElementError> {
        let kk = &kin[self.k];
        let s = kk.station.ok_or_else(|| {
            ElementError::Invalid("the axle node is not carried by a vehicle (no station)".into())
        })?;
        let Some((e, xi)) = self.track.locate(s) else {
            let st = &self.track.stations;
            return Err(ElementError::Invalid(format!(
                "wheel at station {s:.3} m is off the rail mesh [{:.3}, {:.3}] m; extend the track or shorten the run",
                st[0],
                st[st.len() - 1]
            )));
        };
        self.station = s;
        self.frame = kk.frame;
        let w = self.frame;
        let xb = kin[self.b].position;
        self.r_bk = w.transpose() * (xb - kk.position);
        // Dipped joints and the track irregularity move the rail head under the wheel
        // (prescribed functions of the station): lateral along axis 1, vertical along 2.
        // The wheel profile was placed just touching the nominal rail, so the offsets are
        // measured from their values at the wheel's first station ([`OffsetFromStart`]).
        let [lat, vert] = self.start_offset.at(&self.track, self.setup.rail, s);
        // The vertical offset is a prescribed displacement of the rail head: it enters
        // every rail node's relative displacement Δ in `evaluate` (as the rail beam's own
        // deflection under the wheel does), so a wheel that rises and falls with the rail
        // has no relative motion and the stick anchors see no slip. The lateral offset
        // (alignment, gauge) moves the reference geometry instead: the wheel meets the
        // rail profile elsewhere (normal force and contact position change), but Coulomb
        // sticking does not drag the wheelset after every lateral wiggle of the rail —
        // with no rolling kinematics (the paper's law) that would be a false slip of
        // v·dy/ds per second (docs/irregularities.md).
        self.rail_offset = Vector3::new(0.0, vert, 0.0);
        let xc = self.track.rail_position(self.setup.rail, s) + w.column(0) * lat;
        self.r_cb = w.transpose() * (xc - xb);
        let (ni, nj) = (self.rail_node(e), self.rail_node(e + 1));
        if !self.track.rigid {
            let (pi, pj) = (kin[ni].position, kin[nj].position);
            let axes = beam_axes(&pi, &pj);
            let rp = rail_point_matrix(xi, (pj - pi).norm(), &axes);
            // Rotate outputs into the wheel frame.
            let mut m = rp;
            for blk in 0..2 {
                let v = w.transpose() * rp.fixed_view::<3, 12>(3 * blk, 0);
                m.fixed_view_mut::<3, 12>(3 * blk, 0).copy_from(&v);
            }
            self.rail_map = m;
        }
        let changed = e != self.elem || self.conn[2].node != ni;
        self.elem = e;
        self.xi = xi;
        self.conn[2] = NodeDofs::all(ni);
        self.conn[3] = NodeDofs::all(nj);
        Ok(changed && !self.track.rigid)
    }

    #[allow(clippy::needless_range_loop)]
    fn evaluate(&mut self, q: &[f64], form_tangent: bool) {
        let set = self.setup.clone();
        self.force.iter_mut().for_each(|x| *x = 0.0);
        if form_tangent {
            self.tangent.fill(0.0);
        }
        // Springs A–B.
        let s = self.s_matrix();
        let qv = nalgebra::DVector::from_column_slice(q);
        let delta_ab: Vector3<f64> =
            Vector3::from_fn(|i, _| (0..21).map(|j| s[(i, j)] * qv[j]).sum());
        let (f2, k2) = set.spring.force(delta_ab.y);
        let fs = Vector3::new(set.params.k1 * delta_ab.x, f2, set.params.k3 * delta_ab.z);
        self.spring_force = fs;
        let ks = Matrix3::from_diagonal(&Vector3::new(set.params.k1, k2, set.params.k3));
        let fs21 = s.transpose() * fs;
        for i in 0..21 {
            self.force[i] += fs21[i];
        }
        if form_tangent {
            let kst = s.transpose() * ks * s;
            for j in 0..21 {
                for i in 0..21 {
                    self.tangent[(i, j)] += kst[(i, j)];
                }
            }
        }
        // Relative rigid motion of the wheel (for pictures): Δ(ρ) = Δ(0) + ω × ρ is the
        // rail-minus-wheel displacement at ρ from C, so the wheel moves by −Δ.
        {
            let map = |rho: Vector3<f64>| -> Vector3<f64> {
                let t = self.t_matrix(&rho);
                Vector3::from_fn(|i, _| (0..21).map(|j| t[(i, j)] * qv[j]).sum())
            };
            let d0 = map(Vector3::zeros());
            let d1 = map(Vector3::x());
            self.relative = (Vector2::new(-d0.x, -d0.y), -(d1.y - d0.y));
        }
        // Contact.
        self.points.clear();
        self.angles.clear();
        self.positions.clear();
        self.contact_force = Vector3::zeros();
        let n = set.rail_nodes.len();
        // Relative displacements of every rail node (needed for anchors even when open).
        let origin = Vector2::new(self.r_cb.x, self.r_cb.y) - set.wheel_shift;
        let margin = 0.01;
        let ys: Vec<Vector2<f64>> = set.rail_nodes.iter().map(|p| p + origin).collect();
        let window = candidate_window(&ys, set.wheel_y.0 - margin, set.wheel_y.1 + margin);
        for kx in 0..n {
            let rho_c = Vector3::new(set.rail_nodes[kx].x, set.rail_nodes[kx].y, 0.0);
            let t = self.t_matrix(&rho_c);
            let delta: Vector3<f64> =
                Vector3::from_fn(|i, _| (0..21).map(|j| t[(i, j)] * qv[j]).sum())
                    + self.rail_offset;
            self.deltas[kx] = delta;
            if !window.contains(&kx) {
                continue;
            }
            let p = ys[kx] + Vector2::new(delta.x, delta.y);
            // Below the wheel's lowest point: cannot touch.
            if p.y < set.wheel_z_min - margin {
                continue;
            }
            if let Some((p0, g0)) = self.last_gap[kx] {
                if g0 - (p - p0).norm() > 0.0 {
                    continue;
                }
            }
            let Some(cp) = rail_node_gap(set.wheel.spline(), p) else {
                self.last_gap[kx] = None;
                continue;
            };
            self.last_gap[kx] = Some((p, cp.gap));
            let w3 = Vector3::new(cp.normal.x, cp.normal.y, 0.0);
            let u3 = Vector3::new(cp.tangent.x, cp.tangent.y, 0.0);
            self.frames[kx] = (u3, Vector3::z());
            if cp.gap >= 0.0 {
                continue;
            }
            // Curvature term of the signed distance: ∇²g = −κ/(1 − κg)·ττᵀ, κ = c''·n/|c'|².
            let [_, d1, d2] = set.wheel.spline().eval_all(cp.t);
            let kappa = d2.dot(&cp.normal) / d1.norm_squared();
            let hscale = -kappa / (1.0 - kappa * cp.gap);
            let hess = u3 * u3.transpose() * hscale;
            let anchor = self.committed.anchors[kx];
            let st = set.law.evaluate(cp.gap, &w3, &hess, &delta, &anchor);
            let f21 = t.transpose() * st.phi;
            for i in 0..21 {
                self.force[i] += f21[i];
            }
            if form_tangent {
                let kt = t.transpose() * st.d * t;
                for j in 0..21 {
                    for i in 0..21 {
                        self.tangent[(i, j)] += kt[(i, j)];
                    }
                }
            }
            self.contact_force += st.phi;
            self.points
                .push((kx, st, set.rail_nodes[kx].x, cp.point.x + set.wheel_shift.x));
            // Contact angle: between the normal and axis 2 (0 on a flat tread).
            self.angles.push(cp.normal.x.abs().atan2(-cp.normal.y));
            let side = if set.rail == 0 { 1.0 } else { -1.0 };
            self.positions.push(Vector2::new(
                side * set.params.contact_offset + self.r_cb.x + set.rail_nodes[kx].x,
                self.r_cb.y + set.rail_nodes[kx].y,
            ));
        }
    }
}

impl Element for MovingAxle {
    fn kind(&self) -> &str {
        "moving_axle"
    }

    fn connectivity(&self) -> &[NodeDofs] {
        &self.conn
    }

    fn properties(&self) -> ElementProperties {
        ElementProperties {
            linear: false,
            symmetric: self.setup.law.tangent == SlidingTangent::Symmetric,
            connectivity_may_change: !self.track.rigid,
            objective: true,
            ..Default::default()
        }
    }

    fn advance(&mut self, ctx: &StepContext) -> Result<bool, ElementError> {
        self.place(ctx.nodes)
    }

    fn update(&mut self, trial: &TrialState) -> Result<(), ElementError> {
        if let Some(i) = trial.disp.iter().position(|x| !x.is_finite()) {
            return Err(ElementError::NonFinite {
                what: format!("trial displacement at element DOF {i}"),
            });
        }
        self.evaluate(trial.disp, true);
        self.dirty = true;
        Ok(())
    }

    fn resisting_force(&self, f: &mut [f64]) {
        f.copy_from_slice(&self.force);
    }

    fn tangent_stiffness(&self, k: &mut DMatrix<f64>) {
        k.copy_from(&self.tangent);
    }

    fn commit(&mut self) {
        // Accept the trial state once: a second commit (or a commit after a revert) with no
        // update in between has nothing new to accept.
        if !self.dirty {
            return;
        }
        self.dirty = false;
        let law = self.setup.law;
        let mut next = self.committed.clone();
        let in_contact: std::collections::HashMap<usize, PointState> =
            self.points.iter().map(|(k, st, _, _)| (*k, *st)).collect();
        for kx in 0..self.deltas.len() {
            let open = PointState {
                mode: Mode::Open,
                phi: Vector3::zeros(),
                d: Matrix3::zeros(),
                f_n: 0.0,
                f_u: 0.0,
                f_v: 0.0,
                s_u: 0.0,
                u: self.frames[kx].0,
            };
            let st = in_contact.get(&kx).copied().unwrap_or(open);
            let (a, w) = law.commit_anchor(
                &st,
                &self.deltas[kx],
                &self.committed.anchors[kx],
                self.frames[kx],
            );
            next.anchors[kx] = a;
            next.dissipated += w;
        }
        if next.static_load == 0.0 && self.contact_force.y > 0.0 {
            next.static_load = self.contact_force.y;
        }
        self.committed = next.clone();
        self.trial = next;
    }

    fn revert(&mut self) {
        self.dirty = false;
        self.trial = self.committed.clone();
    }

    fn output_names(&self) -> Vec<String> {
        let mut v: Vec<String> = [
            "station",
            "Q",
            "Y",
            "X",
            "YQ",
            "dQQ",
            "n_contact",
            "n_stick",
            "n_slide",
            "spring_f2",
            "max_contact_angle",
            "min_contact_angle",
            "contact_y",
            "contact_z",
        ]
        .iter()
        .map(|s| s.to_string())
        .collect();
        for i in 1..=3 {
            for f in ["rail_y", "wheel_y", "fn", "mode"] {
                v.push(format!("p{i}_{f}"));
            }
        }
        v
    }

    fn outputs(&self, out: &mut Vec<f64>) {
        let f = self.contact_force;
        let q = f.y;
        // Y/Q of a wheel that carries no load is reported as 0 (n_contact says it is off).
        let yq = if q > 0.0 { f.x.abs() / q } else { 0.0 };
        let q0 = self.committed.static_load;
        let dqq = if q0 > 0.0 { (q0 - q) / q0 } else { 0.0 };
        let n_stick = self
            .points
            .iter()
            .filter(|p| p.1.mode == Mode::Stick)
            .count();
        let n_slide = self
            .points
            .iter()
            .filter(|p| p.1.mode == Mode::Slide)
            .count();
        out.extend_from_slice(&[
            self.station,
            q,
            f.x,
            f.z,
            yq,
            dqq,
            self.points.len() as f64,
            n_stick as f64,
            n_slide as f64,
            self.spring_force.y,
            self.angles.iter().copied().fold(0.0, f64::max),
            self.angles.iter().copied().reduce(f64::min).unwrap_or(0.0),
        ]);
        // Resultant contact position: normal-force-weighted mean of the contact points.
        let fsum: f64 = self.points.iter().map(|p| p.1.f_n).sum();
        let c = if fsum > 0.0 {
            self.points
                .iter()
                .zip(&self.positions)
                .fold(Vector2::zeros(), |acc, (p, x)| acc + x * p.1.f_n)
                / fsum
        } else {
            Vector2::zeros()
        };
        out.extend_from_slice(&[c.x, c.y]);
        let mut order: Vec<usize> = (0..self.points.len()).collect();
        order.sort_by(|a, b| self.points[*b].1.f_n.total_cmp(&self.points[*a].1.f_n));
        for i in 0..3 {
            match order.get(i).map(|&k| &self.points[k]) {
                Some((_, st, yr, yw)) => out.extend_from_slice(&[*yr, *yw, st.f_n, st.mode.code()]),
                None => out.extend_from_slice(&[0.0, 0.0, 0.0, 0.0]),
            }
        }
    }

    fn parameters(&self) -> serde_json::Value {
        serde_json::to_value(&self.setup.params).unwrap_or(serde_json::Value::Null)
    }

    fn dissipated_energy(&self) -> f64 {
        self.committed.dissipated
    }

    fn as_any(&self) -> Option<&dyn std::any::Any> {
        Some(self)
    }
}

fn build(spec: &ElementSpec, ctx: &mut dyn BuildContext) -> Result<Box<dyn Element>, FemError> {
    let params: MovingAxleParams = spec.parse()?;
    if let Some(m) = ignored_keys(&spec.params) {
        return Err(bad(spec, m));
    }
    if spec.nodes.len() != 1 {
        return Err(bad(
            spec,
            "`nodes` must hold exactly one id: the axle-centre node K",
        ));
    }
    let track = ctx
        .resource(&params.track)
        .and_then(|r| r.downcast::<TrackModel>().ok())
        .ok_or_else(|| {
            bad(
                spec,
                format!(
                    "no track named `{}`; add a [track] table before the wheels",
                    params.track
                ),
            )
        })?;
    let k = ctx
        .node_index(spec.nodes[0])
        .ok_or_else(|| bad(spec, "node does not exist"))?;
    if ctx.node_carried(k) == Some(false) {
        return Err(bad(
            spec,
            format!(
                "`nodes` = [{}]: node {} is not carried by any vehicle, so the wheel has no station on the track; list the wheel in a [[vehicle]] table (its `wheel` keys), which generates carried axle nodes",
                spec.nodes[0], spec.nodes[0]
            ),
        ));
    }
    let rail_offset = track.rails[0].offset;
    let setup = Setup::new(params, &spec.origin, rail_offset)?;
    let first = ctx
        .node_index(track.rails[0].first_id)
        .ok_or_else(|| bad(spec, "the track's rail nodes are missing"))?;
    let n = track.stations.len();
    if ctx.node_index(track.rails[1].first_id + n as u64 - 1) != Some(first + 2 * n - 1) {
        return Err(bad(spec, "the track's rail nodes are not consecutive; generate the track with the track generator"));
    }
    // B at the wheel's contact point: lateral ±contact_offset at rail-top level, in the
    // wheel frame of the axle node's station at t = 0 (the builder places K at height r0).
    let xk = ctx.node_position(k);
    let sign = if setup.rail == 0 { 1.0 } else { -1.0 };
    let frame = guess_frame(&track, &xk);
    let up = frame.column(1).into_owned();
    // Height of K above the rail-top plane through the centre line.
    let p = track.track.at(station_of(&track, &xk));
    let h = (xk - p.position).dot(&up);
    let xb = xk + frame.column(0) * (sign * setup.params.contact_offset) - up * h;
    let b = ctx.add_internal_node(xb, Some(k));
    Ok(Box::new(MovingAxle::with(
        Arc::new(setup),
        track,
        b,
        k,
        first,
    )))
}

/// The station of the centre-line point nearest to `x` (m), by a coarse search along the
/// rail mesh stations refined by projection.
fn station_of(track: &TrackModel, x: &Vector3<f64>) -> f64 {
    let st = &track.stations;
    let mut best = (f64::INFINITY, st[0]);
    let step = (st.len() / 2000).max(1);
    for s in st.iter().step_by(step) {
        let d = (track.track.at(*s).position - x).norm();
        if d < best.0 {
            best = (d, *s);
        }
    }
    let mut s = best.1;
    for _ in 0..20 {
        let p = track.track.at(s);
        s += (x - p.position).dot(&p.tangent);
    }
    s
}

fn guess_frame(track: &TrackModel, x: &Vector3<f64>) -> Matrix3<f64> {
    track.track.at(station_of(track, x)).frame
}

fn samples() -> Vec<Sample> {
    sample_states(SlidingTangent::Consistent)
}

fn sample_wheel(
    params: &MovingAxleParams,
    tm: &Arc<TrackModel>,
    nodes: &[NodeKinematics],
    offset: f64,
) -> MovingAxle {
    let setup = Setup::new(params.clone(), "sample", offset).expect("sample setup");
    let mut e = MovingAxle::with(Arc::new(setup), tm.clone(), 7, 6, 0);
    let ctx = StepContext {
        time: 0.0,
        dt: 0.0,
        nodes,
    };
    e.advance(&ctx).expect("on the mesh");
    e
}

/// Sample states of a wheel on a short straight track with flexible rails: stick, slide,
/// separated and two-point (tread + flange) contact. Public for the element's tests.
/// The sample track, rails and wheel nodes: (track model, node kinematics, rail offset).
fn sample_scene() -> (Arc<TrackModel>, Vec<NodeKinematics>, f64) {
    use super::alignment::Alignment;
    use super::cant::{Cant, Track};
    let track =
        Arc::new(Track::new(Alignment::straight(10.0), Cant::none()).expect("straight track"));
    let stations = vec![2.0, 2.6, 3.2];
    let offset = track.gauge / 2.0 + 0.036;
    let tm = Arc::new(TrackModel {
        track: track.clone(),
        stations: stations.clone(),
        rails: [
            super::track_model::RailLine {
                offset,
                first_id: 100,
            },
            super::track_model::RailLine {
                offset: -offset,
                first_id: 103,
            },
        ],
        rigid: false,
        slab: None,
        bridge: None,
        dips: Vec::new(),
        irregularity: None,
    });
    let s = 2.45;
    let p = track.at(s);
    let mut nodes = Vec::new();
    for r in 0..2 {
        for st in &stations {
            nodes.push(NodeKinematics::fixed(tm.rail_position(r, *st)));
        }
    }
    let xk = p.position + p.frame.column(1) * 0.43;
    let xb = p.position + p.frame.column(0) * 0.75;
    nodes.push(NodeKinematics {
        position: xk,
        frame: p.frame,
        carried: true,
        station: Some(s),
    });
    nodes.push(NodeKinematics {
        position: xb,
        frame: p.frame,
        carried: true,
        station: Some(s),
    });
    (tm, nodes, offset)
}

/// Rebuilds a sample wheel from its parameters (the conformance kit's serde check).
fn rebuild_sample(params: &serde_json::Value) -> Result<Box<dyn Element>, FemError> {
    let spec = ElementSpec {
        id: 1,
        kind: "moving_axle".into(),
        nodes: vec![1],
        params: params.as_object().cloned().unwrap_or_default(),
        origin: "conformance sample".into(),
    };
    let p: MovingAxleParams = spec.parse()?;
    let (tm, nodes, offset) = sample_scene();
    Ok(Box::new(sample_wheel(&p, &tm, &nodes, offset)))
}

pub fn sample_states(tangent: SlidingTangent) -> Vec<Sample> {
    let (tm, nodes, offset) = sample_scene();
    let mut params: MovingAxleParams = ElementSpec {
        id: 1,
        kind: "moving_axle".into(),
        nodes: vec![1],
        params: serde_json::json!({"side": "left"})
            .as_object()
            .cloned()
            .unwrap_or_default(),
        origin: "sample".into(),
    }
    .parse()
    .expect("defaults parse");
    params.sliding_tangent = match tangent {
        SlidingTangent::Symmetric => "symmetric".into(),
        SlidingTangent::Consistent => "consistent".into(),
    };
    params.k = 1e9;
    params.k_v = 1e9;
    let make = |params: &MovingAxleParams| -> Box<dyn Element> {
        Box::new(sample_wheel(params, &tm, &nodes, offset))
    };
    // Element DOFs: B(0..3), K(3..9), I(9..15), J(15..21). Press B down (into the rail)
    // by δ along −e2 relative to the rail.
    let press = |dz: f64, dy: f64| -> Vec<f64> {
        let mut u = vec![0.0; 21];
        // B less far down than K: the A–B spring is compressed (δ2 = 1e-5 m), away
        // from the non-smooth point of the power law at zero force.
        u[1] = -dz + 1e-5;
        u[4] = -dz;
        u[0] = dy;
        u[3] = dy;
        // A little rail bending so that every block is exercised.
        u[10] = 1e-6;
        u[16] = -2e-6;
        u[14] = 1e-6;
        u
    };
    let mut out = Vec::new();
    let mk =
        |name: &str, disp: Vec<f64>, committed: Option<Vec<f64>>, p: &MovingAxleParams| Sample {
            name: name.to_string(),
            element: make(p),
            nodes: nodes.clone(),
            vel: vec![0.0; 21],
            disp,
            fd_step: 1e-4,
            committed_disp: committed,
            rebuild: Some(rebuild_sample),
        };
    out.push(mk("stick", press(3e-5, 1e-7), None, &params));
    out.push(mk(
        "slide",
        press(3e-5, 1e-4),
        Some(press(3e-5, 0.0)),
        &params,
    ));
    out.push(mk("separated", press(-1e-3, 0.0), None, &params));
    // Two-point contact: shift the wheelset towards the flange side (−e1 for the left wheel)
    // until the flange root touches the gauge corner.
    out.push(mk("two-point contact", press(-6e-4, 7e-3), None, &params));
    out
}

railfem_framework::inventory::submit! {
    ElementKind {
        name: "moving_axle",
        description: "one wheel of a wheelset on a rail: multi-point profile contact with stick, slide and separation (Ju & Ro 2021)",
        params: <MovingAxleParams as Params>::docs,
        build,
        samples,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn eval(e: &mut dyn Element, u: &[f64]) -> (Vec<f64>, DMatrix<f64>) {
        railfem_framework::conformance::static_force_tangent(e, u).unwrap()
    }

    fn prepare(s: &mut Sample) {
        if let Some(c) = s.committed_disp.clone() {
            eval(s.element.as_mut(), &c);
            s.element.commit();
        }
    }

    /// In every mode, the tangent equals central differences of the resisting force
    /// (consistent sliding tangent), to a tolerance set by the FD truncation error.
    #[test]
    fn tangent_matches_finite_differences_in_each_mode() {
        for mut s in sample_states(SlidingTangent::Consistent) {
            prepare(&mut s);
            let (f0, k) = eval(s.element.as_mut(), &s.disp);
            let n = s.disp.len();
            let mut fd = DMatrix::zeros(n, n);
            for j in 0..n {
                let h = if j % 6 >= 3 && j >= 3 { 1e-9 } else { 1e-10 };
                let mut up = s.disp.clone();
                up[j] += h;
                let mut dn = s.disp.clone();
                dn[j] -= h;
                let (fp, _) = eval(s.element.as_mut(), &up);
                let (fm, _) = eval(s.element.as_mut(), &dn);
                for i in 0..n {
                    fd[(i, j)] = (fp[i] - fm[i]) / (2.0 * h);
                }
            }
            let scale = k.amax().max(1.0);
            let diff = &fd - &k;
            let err = diff.amax() / scale;
            let fmax = f0.iter().fold(0.0f64, |a, b| a.max(b.abs()));
            println!(
                "{}: |K| = {scale:.3e}, |f| = {fmax:.3e}, FD error {err:.3e}",
                s.name
            );
            assert!(err < 1e-5, "{}: FD error {err:e}", s.name);
        }
    }
}
#[cfg(test)]
mod geometry_tests {
    use super::*;

    /// The two-point sample really has tread and flange contact at once (the multi-point
    /// contact the paper is about): rail nodes on the crown (y > −15 mm) and on the gauge
    /// corner (y < −20 mm) both penetrate.
    #[test]
    fn two_point_sample_touches_tread_and_flange() {
        let mut s = sample_states(SlidingTangent::Consistent).remove(3);
        assert_eq!(s.name, "two-point contact");
        let z = vec![0.0; 21];
        s.element
            .update(&TrialState {
                time: 0.0,
                dt: 0.0,
                disp: &s.disp,
                vel: &z,
                acc: &z,
            })
            .unwrap();
        let mut o = Vec::new();
        s.element.outputs(&mut o);
        let names = s.element.output_names();
        let at = |k: &str| o[names.iter().position(|n| n == k).unwrap()];
        // S1002's flange face is a 70° line; its tread slope is a few degrees.
        let (hi, lo) = (at("max_contact_angle"), at("min_contact_angle"));
        assert!(hi > 1.0, "no flange contact: max angle {hi}");
        assert!(lo < 0.2, "no tread contact: min angle {lo}");
        let n = o[names.iter().position(|n| n == "n_contact").unwrap()];
        assert!(n >= 4.0);
    }
}

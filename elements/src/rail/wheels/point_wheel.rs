//! Point-contact wheels: `hertz_wheel` and `rigid_wheel`, the two light alternatives to
//! `moving_axle` (the 3-D profile contact) a wheelset can choose.
//!
//! # Nodes and DOFs (18)
//!
//! In element order: node **K** (the wheelset's axle centre, 6 DOFs, carried by the vehicle,
//! so its DOFs are in the wheel frame 1 lateral, 2 up, 3 forwards at its station) and the
//! rail nodes **I** and **J** (6 DOFs each, global axes) of the rail element under the
//! wheel. No internal node: the wheel is one point P of the rigid wheelset.
//!
//! # Kinematics
//!
//! The contact point P is at the rail-top level under K, `contact_offset` from the centre
//! line (left wheel: +axis 1): `r = x_P − x_K = (±contact_offset, −h, 0)` in the wheel
//! frame, `h` the height of K above the rail-top plane. The rail point C is on the rail's
//! beam line (the top of the head) at the wheel's station; its displacement and rotation
//! come from I and J by the Hermite interpolation of [`crate::rail::wheels::rail_point`] (Eq. 14), and the
//! rail's material point under P is `u_C + θ_C × ρ` with `ρ = x_P − x_C` (the small lateral
//! step between the contact point and the head centre). The rail-minus-wheel displacement
//!
//! ```text
//! Δ = Wᵀ(u_C + θ_C × ρ) − (u_K + θ_K × r) + z(s) = T·q + z(s),
//! ```
//!
//! `W` the wheel frame, `z(s)` the irregularity of the rail head at the station as a
//! wheel-frame displacement (the track's irregularity and dipped joints; `rail_irregularity` is
//! the one place it is read), is linear in the 18 DOFs.
//! The contact law ([`crate::rail::contact::point_contact_law`]) gives the force on the wheel `φ(Δ)` and
//! `D = ∂φ/∂Δ`; the element force and tangent are `Tᵀ·φ` and `Tᵀ·D·T` (symmetric). A rigid
//! motion of K and the rail leaves `Δ` unchanged, so the element is objective.
//!
//! # Moving
//!
//! At each step the element reads K's station and frame, finds the rail element under it
//! with [`TrackModel::locate`] (O(log n)) and re-picks I and J when the wheel crosses into
//! the next element — in either direction of travel (a connectivity change the assembler
//! follows). On a rigid track the rail nodes have no DOFs and nothing changes.
//!
//! # Initial state
//!
//! Like `moving_axle`, the wheel starts just touching: at zero displacement P sits on the
//! rail top. The initial static solve then compresses the contact under the vehicle's
//! weight. The Hertz law has zero stiffness at zero penetration, so the `hertz_wheel`
//! starts 1 nm into the rail ([`crate::rail::contact::point_contact_law::HERTZ_PRELOAD`]): from there
//! Newton's first step overshoots into the rail and the next ones come back monotonically
//! (the 3/2 law is convex), which converges from zero load in one load step (tested: 10
//! iterations for a two-axle vehicle). A wheel in the air has no vertical stiffness, so a
//! static solve needs its wheels in contact at the first iterate (docs/wheel-models.md).
//! The same holds on an irregular rail: the wheel starts just touching the rail head at
//! its first station, irregularity included (the irregularity is measured from its value
//! there, as `moving_axle` does), so differences of
//! the rail height between the wheels at t = 0 do not preload the suspensions; start a
//! vehicle on smooth track (or where the profile is flat) when that matters.
//! `rigid_wheel` is linear and needs nothing. Like every wheel model, neither holds the
//! wheelset's rolling (spin about the axle with the matching forward motion of K): the
//! vehicle's spin spring does, in statics.

use crate::rail::contact::point_contact_law::{ContactForce, PointLaw};
use crate::rail::geometry::railline::RailSide;
use crate::rail::geometry::track_model::{OffsetFromStart, TrackModel};
use crate::rail::wheels::rail_point::{beam_axes, rail_point_matrix};
use crate::rail::wheels::wheel_defect::{TreadOffset, WheelDefect};
use nalgebra::{DMatrix, Matrix3, SMatrix, Vector3};
use railfem_framework::element::*;
use railfem_framework::error::FemError;
use railfem_framework::limits::fmt_num;
use railfem_framework::moving::Path;
use railfem_framework::registry::{BuildContext, ElementKind, ElementSpec, Params, Sample};
use std::sync::Arc;

railfem_framework::element_params! {
    /// Model-file keys of `hertz_wheel` (SI units).
    pub struct HertzWheelParams {
        /// Which wheel of the wheelset: "left" (axis 1 positive) or "right".
        side: RailSide [""],
        /// Lateral distance of the wheel's contact point from the centre line (m); must lie
        /// over the rail head (within 36 mm of the rail's beam line).
        contact_offset: f64 ["m"] = 0.75,
        /// Hertz constant G (m/N^(2/3)): δ = G·Q^(2/3); R 0.43 m wheel on R 0.30 m crown.
        G: f64 ["m/N^(2/3)"] = 4.95e-8,
        /// Lateral guidance spring between wheel and rail (N/m).
        k1: f64 ["N/m"] = 1.0e9,
        /// Longitudinal guidance spring between wheel and rail (N/m).
        k3: f64 ["N/m"] = 1.0e9,
        /// Name of the track resource the wheel rides on.
        track: String [""] = "track",
        /// Static wheel load for ΔQ/Q (N); 0 = the load at the first converged state.
        static_load: f64 ["N"] = 0.0,
        /// Tread defect: {type = "none"}, a flat {type = "flat", length, depth, shape,
        /// angle} or a polygon {type = "polygon", harmonics = [{order, amplitude, phase}]}
        /// (docs/defects.md).
        defect: WheelDefect [""] = serde_json::json!({"type": "none"}),
    }
}

impl railfem_framework::registry::ElementParams for HertzWheelParams {
    const KIND: &'static str = "hertz_wheel";
}

impl HertzWheelParams {
    /// The wheel on `side` (the one required key) with every other key at its documented
    /// default (module documentation of each key).
    pub fn new(side: RailSide) -> HertzWheelParams {
        HertzWheelParams {
            side,
            contact_offset: 0.75,
            G: 4.95e-8,
            k1: 1.0e9,
            k3: 1.0e9,
            track: "track".to_string(),
            static_load: 0.0,
            defect: WheelDefect::None,
        }
    }
}

railfem_framework::element_params! {
    /// Model-file keys of `rigid_wheel` (SI units).
    pub struct RigidWheelParams {
        /// Which wheel of the wheelset: "left" (axis 1 positive) or "right".
        side: RailSide [""],
        /// Lateral distance of the wheel's contact point from the centre line (m); must lie
        /// over the rail head (within 36 mm of the rail's beam line).
        contact_offset: f64 ["m"] = 0.75,
        /// Penalty stiffness tying the wheel point to the rail head in all directions (N/m).
        k: f64 ["N/m"] = 1.0e10,
        /// Name of the track resource the wheel rides on.
        track: String [""] = "track",
        /// Static wheel load for ΔQ/Q (N); 0 = the load at the first converged state.
        static_load: f64 ["N"] = 0.0,
        /// Tread defect: {type = "none"}, a flat {type = "flat", length, depth, shape,
        /// angle} or a polygon {type = "polygon", harmonics = [{order, amplitude, phase}]}
        /// (docs/defects.md).
        defect: WheelDefect [""] = serde_json::json!({"type": "none"}),
    }
}

impl railfem_framework::registry::ElementParams for RigidWheelParams {
    const KIND: &'static str = "rigid_wheel";
}

impl RigidWheelParams {
    /// The wheel on `side` (the one required key) with every other key at its documented
    /// default.
    pub fn new(side: RailSide) -> RigidWheelParams {
        RigidWheelParams {
            side,
            contact_offset: 0.75,
            k: 1.0e10,
            track: "track".to_string(),
            static_load: 0.0,
            defect: WheelDefect::None,
        }
    }
}

/// Half the width of the rail head (m): 60E1's head is 72 mm wide. A contact point farther
/// than this from the rail's beam line (the head's centre) is off the rail.
pub const RAIL_HEAD_HALF_WIDTH: f64 = 0.036;

/// Which point wheel.
#[derive(Debug, Clone, PartialEq)]
enum Kind {
    Hertz(HertzWheelParams),
    Rigid(RigidWheelParams),
}

/// Settings of one wheel that do not change while it runs.
#[derive(Debug, Clone)]
struct Setup {
    kind: Kind,
    law: PointLaw,
    /// 0 = left rail (axis 1 positive), 1 = right rail.
    rail: usize,
    contact_offset: f64,
    static_load: f64,
    /// The wheel's tread defect.
    defect: WheelDefect,
}

impl Setup {
    fn name(&self) -> &'static str {
        match self.kind {
            Kind::Hertz(_) => "hertz_wheel",
            Kind::Rigid(_) => "rigid_wheel",
        }
    }

    fn parameters(&self) -> serde_json::Value {
        match &self.kind {
            Kind::Hertz(p) => serde_json::to_value(p),
            Kind::Rigid(p) => serde_json::to_value(p),
        }
        .unwrap_or(serde_json::Value::Null)
    }

    /// Checks the keys shared by both kinds and the law's constants; `rail_offset` is the
    /// track's (unsigned) rail offset, for the "over the rail head" check (skipped when
    /// `None`: the keys are checked before the track is looked up).
    fn new(kind: Kind, origin: &str, rail_offset: Option<f64>) -> Result<Setup, FemError> {
        let err = |m: String| FemError::input(origin, m);
        let (side, offset, static_load, defect) = match &kind {
            Kind::Hertz(p) => (p.side, p.contact_offset, p.static_load, p.defect.clone()),
            Kind::Rigid(p) => (p.side, p.contact_offset, p.static_load, p.defect.clone()),
        };
        defect.validate().map_err(err)?;
        let rail = side.index();
        let stiff = |key: &str, v: f64| -> Result<(), FemError> {
            if v.is_finite() && v > 0.0 {
                Ok(())
            } else {
                Err(err(format!(
                    "`{key}` = {}; give a stiffness > 0 N/m",
                    fmt_num(v)
                )))
            }
        };
        let law = match &kind {
            Kind::Hertz(p) => {
                if !(p.G.is_finite() && p.G > 0.0) {
                    return Err(err(format!(
                        "`G` = {}; give the Hertz constant > 0 m/N^(2/3) (4.95e-8 for a 0.43 m wheel on a 0.30 m rail crown)",
                        fmt_num(p.G)
                    )));
                }
                stiff("k1", p.k1)?;
                stiff("k3", p.k3)?;
                PointLaw::Hertz {
                    g: p.G,
                    k1: p.k1,
                    k3: p.k3,
                }
            }
            Kind::Rigid(p) => {
                stiff("k", p.k)?;
                PointLaw::Rigid { k: p.k }
            }
        };
        if !(offset.is_finite() && offset > 0.0) {
            return Err(err(format!(
                "`contact_offset` = {}; give the lateral distance of the contact point from the centre line, > 0 m",
                fmt_num(offset)
            )));
        }
        if !(static_load.is_finite() && static_load >= 0.0) {
            return Err(err(format!(
                "`static_load` = {}; give a load ≥ 0 N (0 = the first converged load)",
                fmt_num(static_load)
            )));
        }
        let Some(rail_offset) = rail_offset else {
            return Ok(Setup {
                kind,
                law,
                rail,
                contact_offset: offset,
                static_load,
                defect,
            });
        };
        if (offset - rail_offset).abs() > RAIL_HEAD_HALF_WIDTH {
            return Err(err(format!(
                "`contact_offset` = {} m puts the wheel off the track: the rail head spans {} to {} m from the centre line; give a contact_offset in that range (or change the track's rail_offset)",
                fmt_num(offset),
                fmt_num(rail_offset - RAIL_HEAD_HALF_WIDTH),
                fmt_num(rail_offset + RAIL_HEAD_HALF_WIDTH)
            )));
        }
        Ok(Setup {
            kind,
            law,
            rail,
            contact_offset: offset,
            static_load,
            defect,
        })
    }
}

/// A point-contact wheel (one wheel of a wheelset): `hertz_wheel` or `rigid_wheel`.
pub struct PointWheel {
    setup: Arc<Setup>,
    track: Arc<TrackModel>,
    /// Node index of K and of the first rail node.
    k: usize,
    rail_first: usize,
    conn: [NodeDofs; 3],
    /// Current rail element and local coordinate.
    elem: usize,
    xi: f64,
    station: f64,
    /// Irregularity of the rail head at the station, wheel frame (m): (lateral, up, 0),
    /// measured from its value at the wheel's first station.
    irregularity: Vector3<f64>,
    /// Rail-head offsets (dips and irregularity) measured from the wheel's first station.
    start_offset: OffsetFromStart,
    /// The tread defect's deviation, measured from the wheel's first station.
    tread: TreadOffset,
    /// x_P − x_K and x_P − x_C in the wheel frame (m).
    r_pk: Vector3<f64>,
    rho: Vector3<f64>,
    /// Rail-point interpolation, rows rotated into the wheel frame: 6×12.
    rail_map: SMatrix<f64, 6, 12>,
    /// The map T of Δ = T·q + z (3×18).
    t: SMatrix<f64, 3, 18>,
    committed_static: f64,
    dirty: bool,
    // Trial results.
    delta: Vector3<f64>,
    contact: ContactForce,
    force: Vec<f64>,
    tangent: DMatrix<f64>,
}

fn skew(r: &Vector3<f64>) -> Matrix3<f64> {
    // [r]ₓ such that [r]ₓ·θ = r × θ.
    Matrix3::new(0.0, -r.z, r.y, r.z, 0.0, -r.x, -r.y, r.x, 0.0)
}

impl PointWheel {
    fn with(setup: Arc<Setup>, track: Arc<TrackModel>, k: usize, rail_first: usize) -> Self {
        let static_load = setup.static_load;
        let contact = setup.law.evaluate(&Vector3::zeros());
        PointWheel {
            setup,
            track,
            k,
            rail_first,
            conn: [
                NodeDofs::all(k),
                NodeDofs::all(rail_first),
                NodeDofs::all(rail_first + 1),
            ],
            elem: usize::MAX,
            xi: 0.0,
            station: f64::NAN,
            irregularity: Vector3::zeros(),
            start_offset: OffsetFromStart::default(),
            tread: TreadOffset::default(),
            r_pk: Vector3::zeros(),
            rho: Vector3::zeros(),
            rail_map: SMatrix::zeros(),
            t: SMatrix::zeros(),
            committed_static: static_load,
            dirty: false,
            delta: Vector3::zeros(),
            contact,
            force: vec![0.0; 18],
            tangent: DMatrix::zeros(18, 18),
        }
    }

    fn rail_node(&self, i: usize) -> usize {
        self.rail_first + self.setup.rail * self.track.stations.len() + i
    }

    /// Station of the wheel (m).
    pub fn station(&self) -> f64 {
        self.station
    }

    /// The rail element under the wheel and the local coordinate ξ there.
    pub fn rail_element(&self) -> (usize, f64) {
        (self.elem, self.xi)
    }

    /// Force of the rail on the wheel at the trial state (N), wheel frame (lateral, up,
    /// forwards).
    pub fn contact_force(&self) -> Vector3<f64> {
        self.contact.phi
    }

    /// Vertical penetration of the trial state (m): Hertz `δ` (with its 1 nm preload), or
    /// the penalty's vertical violation `Δ2`.
    pub fn penetration(&self) -> f64 {
        self.contact.penetration
    }

    /// The irregularity of this wheel's rail head at station `s`, as a displacement of the
    /// rail in the wheel frame (m): (lateral along axis 1, up, 0), measured from its value
    /// at the wheel's first station. The one place a point wheel reads it: the track's
    /// irregularity of this rail plus the dipped joints ([`OffsetFromStart`]).
    fn rail_irregularity(&mut self, s: f64) -> Vector3<f64> {
        let [lateral, vertical] = self.start_offset.at(&self.track, self.setup.rail, s);
        Vector3::new(lateral, vertical, 0.0)
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
        let w = kk.frame;
        let p = self.track.track.at(s);
        // Height of K above the rail-top plane through the centre line: the rolling radius.
        let h = (kk.position - p.position).dot(&w.column(1));
        // The wheel starts just touching the rail where it stands (see "Initial state"):
        // the irregularity is measured from its value at the first station. A tread
        // defect acts on the contact as a rail-top deviation of the same sign does
        // ([`crate::rail::wheels::wheel_defect`]).
        self.irregularity = self.rail_irregularity(s);
        self.irregularity.y += self.tread.at(&self.setup.defect, s, h);
        let sign = if self.setup.rail == 0 { 1.0 } else { -1.0 };
        self.r_pk = Vector3::new(sign * self.setup.contact_offset, -h, 0.0);
        let xp = kk.position + w * self.r_pk;
        let (ni, nj) = (self.rail_node(e), self.rail_node(e + 1));
        let mut t = SMatrix::<f64, 3, 18>::zeros();
        // Wheel point: −(u_K − [r]ₓ·θ_K).
        t.fixed_view_mut::<3, 3>(0, 0)
            .copy_from(&(-Matrix3::identity()));
        t.fixed_view_mut::<3, 3>(0, 3).copy_from(&skew(&self.r_pk));
        if !self.track.rigid {
            let (pi, pj) = (kin[ni].position, kin[nj].position);
            let axes = beam_axes(&pi, &pj);
            let rp = rail_point_matrix(xi, (pj - pi).norm(), &axes);
            let mut m = rp;
            for blk in 0..2 {
                let v = w.transpose() * rp.fixed_view::<3, 12>(3 * blk, 0);
                m.fixed_view_mut::<3, 12>(3 * blk, 0).copy_from(&v);
            }
            self.rail_map = m;
            // The rail's material point under P: u_C − [ρ]ₓ·θ_C, ρ = x_P − x_C (C on the
            // chord I–J the interpolation reproduces rigid motions about).
            let xc = pi + (pj - pi) * xi;
            self.rho = w.transpose() * (xp - xc);
            let a = m.fixed_view::<3, 12>(0, 0).into_owned();
            let b = m.fixed_view::<3, 12>(3, 0).into_owned();
            t.fixed_view_mut::<3, 12>(0, 6)
                .copy_from(&(a - skew(&self.rho) * b));
        }
        self.t = t;
        let changed = e != self.elem || self.conn[1].node != ni;
        self.elem = e;
        self.xi = xi;
        self.conn[1] = NodeDofs::all(ni);
        self.conn[2] = NodeDofs::all(nj);
        Ok(changed && !self.track.rigid)
    }

    fn evaluate(&mut self, q: &[f64]) {
        let qv = SMatrix::<f64, 18, 1>::from_column_slice(q);
        self.delta = self.t * qv + self.irregularity;
        self.contact = self.setup.law.evaluate(&self.delta);
        let f = self.t.transpose() * self.contact.phi;
        self.force.copy_from_slice(f.as_slice());
        let k = self.t.transpose() * self.contact.d * self.t;
        self.tangent.copy_from(&k);
    }
}

impl Element for PointWheel {
    fn kind(&self) -> &str {
        self.setup.name()
    }

    fn connectivity(&self) -> &[NodeDofs] {
        &self.conn
    }

    fn properties(&self) -> ElementProperties {
        ElementProperties {
            linear: false,
            symmetric: true,
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
        self.evaluate(trial.disp);
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
        if !self.dirty {
            return;
        }
        self.dirty = false;
        if self.committed_static == 0.0 && self.contact.phi.y > 0.0 {
            self.committed_static = self.contact.phi.y;
        }
    }

    fn revert(&mut self) {
        self.dirty = false;
    }

    fn output_names(&self) -> Vec<String> {
        [
            "station",
            "Q",
            "Y",
            "X",
            "YQ",
            "dQQ",
            "penetration",
            "in_contact",
        ]
        .iter()
        .map(|s| s.to_string())
        .collect()
    }

    fn output_units(&self) -> Vec<String> {
        ["m", "N", "N", "N", "-", "-", "m", "-"]
            .iter()
            .map(|s| s.to_string())
            .collect()
    }

    fn outputs(&self, out: &mut Vec<f64>) {
        let f = self.contact.phi;
        let q = f.y;
        // Y/Q of a wheel that carries no load is reported as 0 (in_contact says it is off).
        let yq = if q > 0.0 { f.x.abs() / q } else { 0.0 };
        let q0 = self.committed_static;
        let dqq = if q0 > 0.0 { (q0 - q) / q0 } else { 0.0 };
        out.extend_from_slice(&[
            self.station,
            q,
            f.x,
            f.z,
            yq,
            dqq,
            self.contact.penetration,
            if self.contact.in_contact { 1.0 } else { 0.0 },
        ]);
    }

    fn parameters(&self) -> serde_json::Value {
        self.setup.parameters()
    }

    fn as_any(&self) -> Option<&dyn std::any::Any> {
        Some(self)
    }
}

fn bad(spec: &ElementSpec, m: impl Into<String>) -> FemError {
    FemError::input(&spec.origin, m.into())
}

fn parse_kind(spec: &ElementSpec) -> Result<Kind, FemError> {
    Ok(match spec.kind.as_str() {
        "hertz_wheel" => Kind::Hertz(spec.parse()?),
        _ => Kind::Rigid(spec.parse()?),
    })
}

fn track_name(kind: &Kind) -> &str {
    match kind {
        Kind::Hertz(p) => &p.track,
        Kind::Rigid(p) => &p.track,
    }
}

/// Builds a point wheel. Checks in the order a user fixes them: the keys themselves, the
/// track resource, the wheel's place over a rail head, then that K rides on a vehicle.
fn build(spec: &ElementSpec, ctx: &mut dyn BuildContext) -> Result<Box<dyn Element>, FemError> {
    let kind = parse_kind(spec)?;
    if spec.nodes.len() != 1 {
        return Err(bad(
            spec,
            "`nodes` must hold exactly one id: the axle-centre node K",
        ));
    }
    // The keys alone (the off-track check needs the track: below).
    Setup::new(kind.clone(), &spec.origin, None)?;
    let name = track_name(&kind).to_string();
    let track = ctx
        .resource(&name)
        .and_then(|r| r.downcast::<TrackModel>().ok())
        .ok_or_else(|| {
            bad(
                spec,
                format!("no track named `{name}`; add a [track] table before the wheels"),
            )
        })?;
    let setup = Setup::new(kind, &spec.origin, Some(track.rails[0].offset.abs()))?;
    let k = ctx
        .node_index(spec.nodes[0])
        .ok_or_else(|| bad(spec, "node does not exist"))?;
    if ctx.node_carried(k) == Some(false) {
        return Err(bad(
            spec,
            format!(
                "`nodes` = [{}]: node {} is not carried by any vehicle, so the wheel has no station on the track; list the wheel in a [[vehicle]] table, which generates carried axle nodes",
                spec.nodes[0], spec.nodes[0]
            ),
        ));
    }
    let first = ctx
        .node_index(track.rails[0].first_id)
        .ok_or_else(|| bad(spec, "the track's rail nodes are missing"))?;
    let n = track.stations.len();
    if ctx.node_index(track.rails[1].first_id + n as u64 - 1) != Some(first + 2 * n - 1) {
        return Err(bad(spec, "the track's rail nodes are not consecutive; generate the track with the track generator"));
    }
    Ok(Box::new(PointWheel::with(Arc::new(setup), track, k, first)))
}

// ---------------------------------------------------------------------------------------
// Conformance samples.
// ---------------------------------------------------------------------------------------

/// The sample scene: a straight 10 m track with flexible rails meshed at stations 2, 2.6
/// and 3.2 m (rail node indices 0–2 left, 3–5 right) and the axle node K (index 6) at
/// station `s`, 0.43 m above the rail top. Public to the crate's tests.
pub(crate) fn sample_scene(s: f64, rigid: bool) -> (Arc<TrackModel>, Vec<NodeKinematics>) {
    use crate::rail::geometry::alignment::Alignment;
    use crate::rail::geometry::cant::{Cant, Track};
    let track =
        Arc::new(Track::new(Alignment::straight(10.0), Cant::none()).expect("straight track"));
    let stations = vec![2.0, 2.6, 3.2];
    let offset = track.gauge / 2.0 + 0.036;
    let tm = Arc::new(TrackModel {
        track: track.clone(),
        stations: stations.clone(),
        rails: [
            crate::rail::geometry::track_model::RailLine {
                offset,
                first_id: 100,
            },
            crate::rail::geometry::track_model::RailLine {
                offset: -offset,
                first_id: 103,
            },
        ],
        rigid,
        slab: None,
        bridge: None,
        dips: Vec::new(),
        irregularity: None,
    });
    let mut nodes = Vec::new();
    for r in 0..2 {
        for st in &stations {
            nodes.push(NodeKinematics::fixed(tm.rail_position(r, *st)));
        }
    }
    let p = track.at(s);
    nodes.push(NodeKinematics {
        position: p.position + p.frame.column(1) * 0.43,
        frame: p.frame,
        carried: true,
        station: Some(s),
    });
    (tm, nodes)
}

/// A sample wheel of `kind` ("hertz_wheel" or "rigid_wheel") with keys `params`, placed in
/// the sample scene.
pub(crate) fn sample_wheel(
    kind: &str,
    params: &serde_json::Value,
    tm: &Arc<TrackModel>,
    nodes: &[NodeKinematics],
) -> Result<PointWheel, FemError> {
    let spec = ElementSpec {
        id: 1,
        kind: kind.into(),
        nodes: vec![1],
        params: params.as_object().cloned().unwrap_or_default(),
        origin: "conformance sample".into(),
    };
    let k = parse_kind(&spec)?;
    let setup = Setup::new(k, &spec.origin, Some(tm.rails[0].offset.abs()))?;
    let mut e = PointWheel::with(Arc::new(setup), tm.clone(), 6, 0);
    e.place(nodes)
        .map_err(|m| FemError::input("conformance sample", m.to_string()))?;
    Ok(e)
}

fn rebuild_hertz(params: &serde_json::Value) -> Result<Box<dyn Element>, FemError> {
    let (tm, nodes) = sample_scene(SAMPLE_STATION, false);
    Ok(Box::new(sample_wheel("hertz_wheel", params, &tm, &nodes)?))
}

fn rebuild_rigid(params: &serde_json::Value) -> Result<Box<dyn Element>, FemError> {
    let (tm, nodes) = sample_scene(SAMPLE_STATION, false);
    Ok(Box::new(sample_wheel("rigid_wheel", params, &tm, &nodes)?))
}

/// Station of the sample wheels (m): inside the first rail element, off its middle.
const SAMPLE_STATION: f64 = 2.45;

/// Element displacements of a sample: K moved by (lateral, vertical) = (dy, −dz) with a
/// small roll and pitch, and a little rail bending so every block of T is exercised.
fn sample_disp(dz: f64, dy: f64) -> Vec<f64> {
    let mut u = vec![0.0; 18];
    u[0] = dy;
    u[1] = -dz;
    u[2] = 2e-6;
    u[3] = 1e-6;
    u[5] = -2e-5;
    // Rail I: vertical (global z) and a rotation; rail J: vertical.
    u[8] = 1e-6;
    u[10] = -3e-6;
    u[14] = -2e-6;
    u[15] = 1e-6;
    u
}

fn samples_of(
    kind: &str,
    rebuild: fn(&serde_json::Value) -> Result<Box<dyn Element>, FemError>,
) -> Vec<Sample> {
    let (tm, nodes) = sample_scene(SAMPLE_STATION, false);
    let mk = |name: &str, side: &str, disp: Vec<f64>| Sample {
        name: name.to_string(),
        element: Box::new(
            sample_wheel(kind, &serde_json::json!({"side": side}), &tm, &nodes)
                .expect("sample wheel"),
        ),
        nodes: nodes.clone(),
        vel: vec![0.0; 18],
        disp,
        fd_step: 1e-4,
        committed_disp: None,
        rebuild: Some(rebuild),
    };
    vec![
        mk("pressed, left", "left", sample_disp(8e-5, 1e-6)),
        mk("pressed, right", "right", sample_disp(8e-5, -1e-6)),
        mk(
            if kind == "hertz_wheel" {
                "separated"
            } else {
                "pulled up"
            },
            "left",
            sample_disp(-5e-5, 0.0),
        ),
    ]
}

fn hertz_samples() -> Vec<Sample> {
    samples_of("hertz_wheel", rebuild_hertz)
}

fn rigid_samples() -> Vec<Sample> {
    samples_of("rigid_wheel", rebuild_rigid)
}

railfem_framework::inventory::submit! {
    ElementKind {
        name: "hertz_wheel",
        description: "one wheel of a wheelset as a vertical Hertz point contact following the rail, with contact loss and linear lateral/longitudinal guidance (vertical dynamics)",
        params: <HertzWheelParams as Params>::docs,
        build,
        samples: hertz_samples,
    }
}

railfem_framework::inventory::submit! {
    ElementKind {
        name: "rigid_wheel",
        description: "one wheel of a wheelset as a rigid point tied to the rail head by a stiff bilateral penalty (no separation)",
        params: <RigidWheelParams as Params>::docs,
        build,
        samples: rigid_samples,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rail::contact::point_contact_law::HERTZ_PRELOAD;

    fn eval(e: &mut dyn Element, u: &[f64]) -> (Vec<f64>, DMatrix<f64>) {
        railfem_framework::conformance::static_force_tangent(e, u).unwrap()
    }

    /// The vertical contact force equals the law at the penetration computed by hand from
    /// the DOFs: the rail's vertical displacement under P by the Hermite functions (the
    /// rail point at ξ = 0.75 of a 0.6 m element) minus K's drop, for a pure vertical state.
    #[test]
    fn penetration_is_rail_hermite_deflection_minus_wheel_drop() {
        let (tm, nodes) = sample_scene(SAMPLE_STATION, false);
        let mut e = sample_wheel(
            "hertz_wheel",
            &serde_json::json!({"side": "left"}),
            &tm,
            &nodes,
        )
        .unwrap();
        let (wi, wj, drop) = (-2e-5, -5e-5, 8e-5);
        let mut u = vec![0.0; 18];
        u[1] = -drop;
        u[8] = wi;
        u[14] = wj;
        eval(&mut e, &u);
        // Hermite N1, N3 at ξ = 0.75 (slopes zero): N1 = 1 − 3ξ² + 2ξ³, N3 = 1 − N1.
        let xi: f64 = 0.75;
        let n1 = 1.0 - 3.0 * xi * xi + 2.0 * xi.powi(3);
        let w_rail = n1 * wi + (1.0 - n1) * wj;
        let delta = w_rail + drop + HERTZ_PRELOAD;
        let q = (delta / 4.95e-8).powf(1.5);
        let got = e.contact_force();
        assert!((got.y - q).abs() < 1e-9 * q, "Q {} vs {q}", got.y);
        assert!(got.x.abs() < 1e-9 && got.z.abs() < 1e-9);
    }

    /// The element's tangent equals central differences of its force in every sample state
    /// (both kinds, both sides, in contact and separated).
    #[test]
    fn tangent_matches_finite_differences() {
        for (kind, samples) in [("hertz", hertz_samples()), ("rigid", rigid_samples())] {
            for mut s in samples {
                let (_, k) = eval(s.element.as_mut(), &s.disp);
                let n = s.disp.len();
                let mut worst = 0.0f64;
                for j in 0..n {
                    let h = 1e-10;
                    let mut up = s.disp.clone();
                    up[j] += h;
                    let mut dn = s.disp.clone();
                    dn[j] -= h;
                    let (fp, _) = eval(s.element.as_mut(), &up);
                    let (fm, _) = eval(s.element.as_mut(), &dn);
                    for i in 0..n {
                        worst = worst.max(((fp[i] - fm[i]) / (2.0 * h) - k[(i, j)]).abs());
                    }
                }
                let scale = k.amax().max(1.0);
                println!(
                    "{kind} {}: |K| = {scale:.3e}, FD error {:.2e}",
                    s.name,
                    worst / scale
                );
                assert!(worst / scale < 1e-5, "{kind} {}: {}", s.name, worst / scale);
            }
        }
    }

    /// Crossing a rail node re-picks I and J (a connectivity change) in both directions of
    /// travel; within an element nothing changes; on rigid rails never.
    #[test]
    fn crossing_a_rail_node_changes_connectivity() {
        for rigid in [false, true] {
            let (tm, nodes) = sample_scene(2.3, rigid);
            let mut e = sample_wheel(
                "rigid_wheel",
                &serde_json::json!({"side": "right"}),
                &tm,
                &nodes,
            )
            .unwrap();
            // Right rail nodes are indices 3, 4, 5.
            assert_eq!((e.conn[1].node, e.conn[2].node), (3, 4));
            let mut go = |s: f64| {
                let (_, n) = sample_scene(s, rigid);
                let changed = e.place(&n).unwrap();
                (changed, e.conn[1].node, e.conn[2].node)
            };
            assert_eq!(go(2.5), (false, 3, 4));
            assert_eq!(go(2.9), (!rigid, 4, 5));
            assert_eq!(go(2.7), (false, 4, 5));
            // Backwards into the first element.
            assert_eq!(go(2.2), (!rigid, 3, 4));
            // Off the mesh: a clear error, not a panic.
            let (_, n) = sample_scene(3.5, rigid);
            let err = e.place(&n).unwrap_err().to_string();
            assert!(err.contains("off the rail mesh"), "{err}");
        }
    }

    /// On rigid rails the rigid wheel's force is k times the wheel's own displacement
    /// (sign: a wheel pushed down by d gets k·d upwards), for every direction.
    #[test]
    fn rigid_wheel_on_rigid_rail_is_a_penalty_spring() {
        let (tm, nodes) = sample_scene(SAMPLE_STATION, true);
        let mut e = sample_wheel(
            "rigid_wheel",
            &serde_json::json!({"side": "left", "k": 2e9}),
            &tm,
            &nodes,
        )
        .unwrap();
        let mut u = vec![0.0; 18];
        u[0] = 1e-6;
        u[1] = -3e-6;
        u[2] = 2e-6;
        eval(&mut e, &u);
        let f = e.contact_force();
        assert!((f - Vector3::new(-2e3, 6e3, -4e3)).norm() < 1e-9);
    }
}

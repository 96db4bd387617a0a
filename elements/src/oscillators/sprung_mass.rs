//! `moving_sprung_mass`: a mass `m` on a spring `k` and dashpot `c` whose lower end (an
//! optional wheel mass `m_w`) rides along a beam path or a track rail at a prescribed speed.
//!
//! # Formulation
//!
//! Element DOFs `q = (z, q_A, q_B)`: the mass node's global `uz` and the twelve DOFs of the
//! two beam nodes under the contact point (see [`super::path`]: `w_c = bᵀq_AB`, its path
//! derivatives `b'`, `b''`, the rail profile `r(s)`). With the station `s(t)`, speed `v`
//! and acceleration `a` of the speed history, the contact point's vertical position and
//! velocity are
//!
//! ```text
//! y_c = bᵀq + r,       ẏ_c = bᵀq̇ + v·b'ᵀq + v·r'
//! ÿ_c = bᵀq̈ + 2v·b'ᵀq̇ + (v²·b'' + a·b')ᵀq + v²·r'' + a·r'
//! ```
//!
//! The spring stretch is `δ = z − y_c` (tension positive), the spring–dashpot force
//! `F = k·δ + c·δ̇`. With `g = (1, −b)` and `h = (0, −v·b')`: `δ = gᵀq − r`,
//! `δ̇ = gᵀq̇ + hᵀq − v·r'`. Work-equivalence (`δy_c = bᵀδq`) gives the element force
//! `F·g`, split between what the framework forms from matrices and what the element
//! returns:
//!
//! - damping matrix `C = c·g·gᵀ` (the `c·gᵀq̇` part of `F`);
//! - resisting force `(k·δ + c·(hᵀq − v·r'))·g`, tangent `K = g·(k·g + c·h)ᵀ` (not
//!   symmetric when `c·v ≠ 0`).
//!
//! The wheel mass `m_w` rolls with the contact point (bonded): its inertia on the beam is
//! `m_w·ÿ_c` distributed by `b`, i.e. mass `m_w·b·bᵀ`, gyroscopic damping `2v·m_w·b·b'ᵀ`,
//! stiffness `m_w·b·(v²·b'' + a·b')ᵀ` and the profile load `m_w·(v²·r'' + a·r')·b` in the
//! resisting force (the moving-mass terms of [`super::moving_mass`]). The weights come from
//! `[analysis] gravity` through the mass matrix (`M·g`), or from loads.
//!
//! The contact force (wheel on beam, compression positive) is
//! `P = −F + m_w·(gravity + ÿ_c)`, with `gravity` the key of that name (used only for this
//! output).
//!
//! # Unilateral contact
//!
//! With `contact = "unilateral"` (and `m_w = 0`) the wheel cannot pull: when the
//! spring–dashpot would pull the beam up (`P < 0`) the force is zero and the mass flies; it
//! lands when the spring is compressed again. The resisting force is then `F_eff·g − C·q̇`
//! with `F_eff = F` in contact and `0` lifted, and `C` the damping matrix of the last
//! converged state (contact or not: the framework forms `C·q̇` per step), so the total force
//! is exactly `F_eff·g` at every iteration; only the Newton tangent lags by one step at the
//! switch. A wheel mass with unilateral contact would need a wheel DOF and a contact spring;
//! it is refused.

use super::path::{ContactPath, ContactPoint};
use super::{dot, sample_positions, speed_history, SampleContext};
use crate::beam3d::support;
use crate::rail::geometry::railline::RailSide;
use nalgebra::DMatrix;
use railfem_framework::element::{
    Element, ElementError, ElementProperties, NodeDofs, StepContext, TrialState,
};
use railfem_framework::limits::fmt_num;
use railfem_framework::registry::{BuildContext, ElementKind, ElementSpec, Params, Sample};
use railfem_framework::{serde_json, Dof, DofSet, FemError};

railfem_framework::element_params! {
    /// Model-file keys of `moving_sprung_mass` (SI units).
    pub struct SprungMassParams {
        /// Sprung mass m (kg), > 0, on the element's node (its global uz).
        m: f64 ["kg"],
        /// Spring stiffness k (N/m), > 0.
        k: f64 ["N/m"],
        /// Dashpot coefficient c (N·s/m), ≥ 0.
        c: f64 ["N*s/m"] = 0.0,
        /// Unsprung (wheel) mass m_w riding on the beam (kg), ≥ 0.
        m_w: f64 ["kg"] = 0.0,
        /// Contact: "bonded" (bilateral) or "unilateral" (cannot pull; the mass may lift off).
        contact: Contact [""] = Contact::Bonded,
        /// Beam element ids of the path, in order of travel (either direction); or use `track`.
        path: Vec<u64> ["-"] = Vec::<u64>::new(),
        /// Name of a generated track to ride on instead of `path` (with `rail`).
        track: String [""] = "",
        /// Rail of `track`: "left" or "right" (only with `track`).
        rail: RailSide [""] = RailSide::Left,
        /// Station of the contact point at t = 0 (m): distance along `path`, or track station.
        start: f64 ["m"] = 0.0,
        /// Speed at t = 0 (m/s), ≥ 0.
        speed: f64 ["m/s"] = 0.0,
        /// Constant acceleration (m/s²); negative brakes to a stop.
        accel: f64 ["m/s^2"] = 0.0,
        /// Speed table [[t (s), v (m/s)], …], piecewise linear; replaces `speed` and `accel`.
        speed_table: Vec<[f64; 2]> ["s, m/s"] = Vec::<[f64; 2]>::new(),
        /// Gravitational acceleration used in the reported contact force of m_w (m/s²).
        gravity: f64 ["m/s^2"] = 9.81,
    }
}

impl railfem_framework::registry::ElementParams for SprungMassParams {
    const KIND: &'static str = "moving_sprung_mass";
}

impl SprungMassParams {
    /// A sprung mass `m` (kg) on a spring `k` (N/m), the two required keys, with every
    /// other key at its documented default: no dashpot or wheel mass, bonded, at rest at
    /// station 0 of an empty `path`. Give the path (or `track`) and the motion with struct
    /// update syntax, `SprungMassParams { path, speed, ..SprungMassParams::new(m, k) }`.
    pub fn new(m: f64, k: f64) -> SprungMassParams {
        SprungMassParams {
            m,
            k,
            c: 0.0,
            m_w: 0.0,
            contact: Contact::Bonded,
            path: Vec::new(),
            track: String::new(),
            rail: RailSide::Left,
            start: 0.0,
            speed: 0.0,
            accel: 0.0,
            speed_table: Vec::new(),
            gravity: 9.81,
        }
    }
}

/// How the wheel meets the beam (`contact`): `"bonded"` (bilateral) or `"unilateral"` (the
/// wheel cannot pull and may lift off).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Contact {
    /// Bilateral: the contact force may pull.
    Bonded,
    /// Compression only: the wheel lifts off when the force would pull.
    Unilateral,
}

/// Number of element DOFs: z and the 12 DOFs of the segment's two nodes.
const N: usize = 13;

/// The `moving_sprung_mass` element. See the module documentation.
#[derive(Debug, Clone)]
pub struct MovingSprungMass {
    params: SprungMassParams,
    path: ContactPath,
    unilateral: bool,
    conn: [NodeDofs; 3],
    point: ContactPoint,
    /// Trial displacements, velocities, accelerations (element order).
    q: [f64; N],
    qd: [f64; N],
    qdd: [f64; N],
    /// Trial spring–dashpot force F (N, tension positive) before the contact switch.
    force: f64,
    /// Whether the trial state is in contact, and the last converged one.
    contact: bool,
    contact_committed: bool,
}

impl MovingSprungMass {
    /// Builds the element on mass node index `node` along `path`.
    pub fn new(
        params: SprungMassParams,
        node: usize,
        path: ContactPath,
        origin: &str,
    ) -> Result<MovingSprungMass, FemError> {
        let bad = |m: String| Err(FemError::input(origin, format!("moving_sprung_mass: {m}")));
        if !(params.m.is_finite() && params.m > 0.0) {
            return bad(format!("`m` = {} kg must be > 0", fmt_num(params.m)));
        }
        if !(params.k.is_finite() && params.k > 0.0) {
            return bad(format!("`k` = {} N/m must be > 0", fmt_num(params.k)));
        }
        for (key, v) in [
            ("c", params.c),
            ("m_w", params.m_w),
            ("gravity", params.gravity),
        ] {
            if v < 0.0 {
                return bad(format!("`{key}` = {} must be ≥ 0", fmt_num(v)));
            }
        }
        let unilateral = params.contact == Contact::Unilateral;
        if unilateral && params.m_w > 0.0 {
            return bad("`contact` = \"unilateral\" with `m_w` > 0 is not offered (the wheel would need its own DOF); set `m_w` = 0 or use \"bonded\"".into());
        }
        let point = path.point(0.0).map_err(|m| FemError::input(origin, m))?;
        let mut e = MovingSprungMass {
            params,
            path,
            unilateral,
            conn: [NodeDofs {
                node,
                dofs: DofSet::of(&[Dof::Uz]),
            }; 3],
            point,
            q: [0.0; N],
            qd: [0.0; N],
            qdd: [0.0; N],
            force: 0.0,
            contact: true,
            contact_committed: true,
        };
        e.place(point);
        Ok(e)
    }

    fn place(&mut self, p: ContactPoint) -> bool {
        let changed = p.nodes != self.point.nodes;
        self.point = p;
        self.conn[1] = NodeDofs::all(p.nodes.0);
        self.conn[2] = NodeDofs::all(p.nodes.1);
        changed
    }

    /// `g = (1, −b)`.
    fn g(&self) -> [f64; N] {
        let mut g = [0.0; N];
        g[0] = 1.0;
        for i in 0..12 {
            g[i + 1] = -self.point.b[i];
        }
        g
    }

    /// `h = (0, −v·b')`.
    fn h(&self) -> [f64; N] {
        let mut h = [0.0; N];
        for i in 0..12 {
            h[i + 1] = -self.point.speed * self.point.b1[i];
        }
        h
    }

    /// `v²·b'' + a·b'` (the convective stiffness row of the contact acceleration).
    fn convective(&self) -> [f64; 12] {
        let p = &self.point;
        std::array::from_fn(|i| p.speed * p.speed * p.b2[i] + p.accel * p.b1[i])
    }

    /// Vertical acceleration of the contact point ÿ_c at the trial state (m/s²).
    fn contact_acceleration(&self) -> f64 {
        let p = &self.point;
        let [_, r1, r2] = p.profile;
        dot(&p.b, &self.qdd[1..])
            + 2.0 * p.speed * dot(&p.b1, &self.qd[1..])
            + dot(&self.convective(), &self.q[1..])
            + p.speed * p.speed * r2
            + p.accel * r1
    }

    /// Contact force P (N, compression positive) at the trial state.
    fn contact_force(&self) -> f64 {
        let f = if self.contact { self.force } else { 0.0 };
        -f + self.params.m_w * (self.params.gravity + self.contact_acceleration())
    }

    /// The element's current contact point.
    pub fn point(&self) -> &ContactPoint {
        &self.point
    }

    fn damping_on(&self) -> bool {
        !self.unilateral || self.contact_committed
    }
}

impl Element for MovingSprungMass {
    fn kind(&self) -> &str {
        "moving_sprung_mass"
    }

    fn connectivity(&self) -> &[NodeDofs] {
        &self.conn
    }

    fn properties(&self) -> ElementProperties {
        let p = &self.params;
        ElementProperties {
            linear: false,
            constant_mass: p.m_w == 0.0,
            constant_damping: false,
            has_mass: true,
            has_damping: p.c > 0.0 || p.m_w > 0.0,
            symmetric: p.c == 0.0 && p.m_w == 0.0,
            connectivity_may_change: true,
            objective: false,
            declared_mass: None,
            finite_rotations: false,
        }
    }

    fn advance(&mut self, ctx: &StepContext) -> Result<bool, ElementError> {
        let p = self.path.point(ctx.time).map_err(ElementError::Invalid)?;
        Ok(self.place(p))
    }

    fn update(&mut self, trial: &TrialState) -> Result<(), ElementError> {
        support::check_trial(trial, N)?;
        self.q.copy_from_slice(trial.disp);
        if trial.vel.len() == N {
            self.qd.copy_from_slice(trial.vel);
        }
        if trial.acc.len() == N {
            self.qdd.copy_from_slice(trial.acc);
        }
        let [r0, r1, _] = self.point.profile;
        let (g, h) = (self.g(), self.h());
        let delta = dot(&g, &self.q) - r0;
        let delta_dot = dot(&g, &self.qd) + dot(&h, &self.q) - self.point.speed * r1;
        self.force = self.params.k * delta + self.params.c * delta_dot;
        if !self.force.is_finite() {
            return Err(ElementError::NonFinite {
                what: "spring force".into(),
            });
        }
        self.contact = !self.unilateral || self.force <= 0.0;
        Ok(())
    }

    fn resisting_force(&self, f: &mut [f64]) {
        let (g, h) = (self.g(), self.h());
        let [r0, r1, r2] = self.point.profile;
        let (k, c, v) = (self.params.k, self.params.c, self.point.speed);
        // Spring and dashpot, less the part C·q̇ the framework adds.
        let spring = if !self.unilateral {
            k * (dot(&g, &self.q) - r0) + c * (dot(&h, &self.q) - v * r1)
        } else if self.contact {
            self.force
        } else {
            0.0
        };
        let cqd = if self.unilateral && self.damping_on() {
            c * dot(&g, &self.qd)
        } else {
            0.0
        };
        for i in 0..N {
            f[i] = (spring - cqd) * g[i];
        }
        // Wheel mass: m_w·b·((v²b'' + a·b')ᵀq + v²r'' + a·r').
        if self.params.m_w > 0.0 {
            let p = &self.point;
            let load = dot(&self.convective(), &self.q[1..]) + v * v * r2 + p.accel * r1;
            for i in 0..12 {
                f[i + 1] += self.params.m_w * p.b[i] * load;
            }
        }
    }

    fn tangent_stiffness(&self, kt: &mut DMatrix<f64>) {
        if self.contact {
            let (g, h) = (self.g(), self.h());
            let (k, c) = (self.params.k, self.params.c);
            for i in 0..N {
                for j in 0..N {
                    kt[(i, j)] = g[i] * (k * g[j] + c * h[j]);
                }
            }
        }
        if self.params.m_w > 0.0 {
            let row = self.convective();
            for i in 0..12 {
                for j in 0..12 {
                    kt[(i + 1, j + 1)] += self.params.m_w * self.point.b[i] * row[j];
                }
            }
        }
    }

    fn mass(&self, m: &mut DMatrix<f64>) {
        m[(0, 0)] = self.params.m;
        let b = &self.point.b;
        for i in 0..12 {
            for j in 0..12 {
                m[(i + 1, j + 1)] = self.params.m_w * b[i] * b[j];
            }
        }
    }

    fn damping(&self, cm: &mut DMatrix<f64>) {
        if self.damping_on() && self.params.c > 0.0 {
            let g = self.g();
            for i in 0..N {
                for j in 0..N {
                    cm[(i, j)] = self.params.c * g[i] * g[j];
                }
            }
        }
        let p = &self.point;
        let s = 2.0 * p.speed * self.params.m_w;
        for i in 0..12 {
            for j in 0..12 {
                cm[(i + 1, j + 1)] += s * p.b[i] * p.b1[j];
            }
        }
    }

    fn commit(&mut self) {
        self.contact_committed = self.contact;
    }

    fn revert(&mut self) {
        self.contact = self.contact_committed;
    }

    fn output_names(&self) -> Vec<String> {
        [
            "station",
            "speed",
            "contact_force",
            "spring_force",
            "mass_disp",
            "mass_vel",
            "mass_acc",
            "contact_disp",
            "in_contact",
        ]
        .iter()
        .map(|s| s.to_string())
        .collect()
    }

    fn output_units(&self) -> Vec<String> {
        ["m", "m/s", "N", "N", "m", "m/s", "m/s²", "m", "-"]
            .iter()
            .map(|s| s.to_string())
            .collect()
    }

    fn outputs(&self, out: &mut Vec<f64>) {
        let p = &self.point;
        let spring = if self.contact { -self.force } else { 0.0 };
        out.extend_from_slice(&[
            p.station,
            p.speed,
            self.contact_force(),
            spring,
            self.q[0],
            self.qd[0],
            self.qdd[0],
            dot(&p.b, &self.q[1..]) + p.profile[0],
            if self.contact { 1.0 } else { 0.0 },
        ]);
    }

    fn parameters(&self) -> serde_json::Value {
        super::path::path_parameters(&self.params)
    }

    fn as_any(&self) -> Option<&dyn std::any::Any> {
        Some(self)
    }
}

/// Factory: one node (the mass node), the path keys and the speed keys.
fn build(spec: &ElementSpec, ctx: &mut dyn BuildContext) -> Result<Box<dyn Element>, FemError> {
    let p: SprungMassParams = spec.parse()?;
    const KIND: &str = "moving_sprung_mass";
    let n = support::resolve_nodes(spec, ctx, &[1], KIND, "the node of the sprung mass")?;
    let history = speed_history(spec, KIND, p.start, p.speed, p.accel, &p.speed_table)?;
    let path = ContactPath::resolve(spec, ctx, KIND, &p.path, &p.track, p.rail, history)?;
    Ok(Box::new(MovingSprungMass::new(
        p,
        n[0],
        path,
        &spec.origin,
    )?))
}

fn sample_params() -> [(&'static str, serde_json::Value); 3] {
    [
        (
            "bonded, wheel mass, braking",
            serde_json::json!({"m": 5750.0, "k": 1.595e6, "c": 2.0e4, "m_w": 800.0,
                "path": [10], "start": 0.7, "speed": 12.0, "accel": -1.5}),
        ),
        (
            "unilateral, in contact",
            serde_json::json!({"m": 5750.0, "k": 1.595e6, "c": 2.0e4, "contact": "unilateral",
                "path": [10], "start": 1.2, "speed_table": [[0.0, 8.0], [1.0, 10.0]]}),
        ),
        (
            "undamped",
            serde_json::json!({"m": 5750.0, "k": 1.595e6, "path": [10], "start": 0.3, "speed": 20.0}),
        ),
    ]
}

fn rebuild(params: &serde_json::Value) -> Result<Box<dyn Element>, FemError> {
    let mut ctx = SampleContext {
        pos: sample_positions(),
    };
    build(
        &support::spec("moving_sprung_mass", &[1], params.clone()),
        &mut ctx,
    )
}

/// Conformance samples: a braking sprung mass with a wheel mass and damping, a unilateral
/// one pressed on the beam (the weight on the mass node compresses the spring: z < 0), an
/// undamped one, all on a skew inclined beam.
fn samples() -> Vec<Sample> {
    sample_params()
        .into_iter()
        .enumerate()
        .filter_map(|(i, (name, params))| {
            let element = rebuild(&params).ok()?;
            let pos = sample_positions();
            let mut s =
                support::sample_on_points(name, element, &pos, 700 + i as u64, (1e-3, 1e-3));
            // Element order: z, then the two beam nodes; compress the spring (z down).
            let n = s.element.ndof();
            s.disp = std::iter::once(-0.02)
                .chain(support::pseudo_random_state(700 + i as u64, 2, 1e-4, 1e-4))
                .take(n)
                .collect();
            s.vel = std::iter::once(-0.01)
                .chain(support::pseudo_random_state(800 + i as u64, 2, 1e-3, 1e-3))
                .take(n)
                .collect();
            s.rebuild = Some(rebuild);
            Some(s)
        })
        .collect()
}

railfem_framework::inventory::submit! {
    ElementKind {
        name: "moving_sprung_mass",
        description: "mass on a spring–dashpot whose foot (and wheel mass) rides along a beam path or track rail at a prescribed speed history",
        params: <SprungMassParams as Params>::docs,
        build,
        samples,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn make(p: serde_json::Value) -> Result<Box<dyn Element>, FemError> {
        rebuild(&p)
    }

    /// Static check on a straight horizontal beam: with the beam held (q_AB = 0), a mass
    /// displacement z gives the spring force k·z at the mass and −k·z distributed by the
    /// Hermite functions (N1, N3 sum to one) on the beam nodes' uz.
    #[test]
    fn spring_force_distribution() {
        let mut e =
            make(serde_json::json!({"m": 1000.0, "k": 2.0e6, "path": [10], "start": 0.5})).unwrap();
        let mut q = vec![0.0; 13];
        q[0] = -0.01;
        let z = vec![0.0; 13];
        e.update(&TrialState {
            time: 0.0,
            dt: 1e-3,
            disp: &q,
            vel: &z,
            acc: &z,
        })
        .unwrap();
        let mut f = vec![0.0; 13];
        e.resisting_force(&mut f);
        assert!((f[0] + 2.0e4).abs() < 1e-9);
        // Global uz of A and B (element DOFs 3 and 9) carry +2e4 N in total.
        assert!((f[3] + f[9] - 2.0e4).abs() < 1e-6 * 2.0e4);
        let mut out = Vec::new();
        e.outputs(&mut out);
        assert!((out[2] - 2.0e4).abs() < 1e-6, "contact force {}", out[2]);
    }

    /// A unilateral spring that would pull lifts off: no force, no stiffness.
    #[test]
    fn unilateral_lifts_off() {
        let mut e = make(
            serde_json::json!({"m": 1000.0, "k": 2.0e6, "contact": "unilateral",
            "path": [10], "start": 0.5}),
        )
        .unwrap();
        let mut q = vec![0.0; 13];
        q[0] = 0.01;
        let z = vec![0.0; 13];
        e.update(&TrialState {
            time: 0.0,
            dt: 1e-3,
            disp: &q,
            vel: &z,
            acc: &z,
        })
        .unwrap();
        let mut f = vec![1.0; 13];
        e.resisting_force(&mut f);
        assert!(f.iter().all(|x| *x == 0.0));
        let mut k = DMatrix::zeros(13, 13);
        e.tangent_stiffness(&mut k);
        assert_eq!(k.amax(), 0.0);
        let mut out = Vec::new();
        e.outputs(&mut out);
        assert_eq!((out[2], out[8]), (0.0, 0.0));
    }

    #[test]
    fn bad_input_is_refused_naming_the_key() {
        let err = |p: serde_json::Value| make(p).err().expect("refused").to_string();
        let e = err(serde_json::json!({"m": -1.0, "k": 1.0, "path": [10]}));
        assert!(e.contains("`m`"), "{e}");
        let e = err(serde_json::json!({"m": 1.0, "k": 1.0, "path": [11]}));
        assert!(e.contains("`path`[0]") && e.contains("11"), "{e}");
        let e = err(serde_json::json!({"m": 1.0, "k": 1.0, "path": [10], "start": 5.0}));
        assert!(e.contains("`start`") && e.contains("off the path"), "{e}");
        let e = err(serde_json::json!({"m": 1.0, "k": 1.0, "path": [10],
            "speed_table": [[0.0, 1.0], [1.0, -1.0]]}));
        assert!(
            e.contains("`speed_table`[1]") && e.contains("backwards"),
            "{e}"
        );
        let e = err(serde_json::json!({"m": 1.0, "k": 1.0, "path": [10], "contact": "sticky"}));
        assert!(e.contains("`contact`"), "{e}");
        let e = err(serde_json::json!({"m": 1.0, "k": 1.0}));
        assert!(e.contains("`path`") && e.contains("`track`"), "{e}");
    }
}

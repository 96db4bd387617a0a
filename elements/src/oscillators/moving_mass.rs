//! `moving_mass`: a mass rolling along a beam path or a track rail at a prescribed speed
//! history, with its full inertia on the beam (bonded contact).
//!
//! # Formulation
//!
//! The mass follows the contact point (see [`super::path`]: `w_c = bᵀq`, `b' = db/ds`,
//! `b'' = d²b/ds²`, the rail profile `r(s)`), so its vertical acceleration is the total
//! time derivative of `y_c(s(t), t) = bᵀq + r` along `ṡ = v`, `v̇ = a`:
//!
//! ```text
//! ÿ_c = bᵀq̈ + 2v·b'ᵀq̇ + (v²·b'' + a·b')ᵀq + v²·r'' + a·r'
//! ```
//!
//! (`ẅ + 2vẇ' + v²w'' + a·w'` of the continuous beam). The inertia force `−m·ÿ_c` acts on
//! the beam at the point; work-equivalence (`δy_c = bᵀδq`) distributes it by `b`. Moving it
//! to the left-hand side gives the element's contributions, all kept:
//!
//! - mass `M = m·b·bᵀ` (symmetric, rank one);
//! - gyroscopic damping `C = 2v·m·b·b'ᵀ` (not symmetric; Coriolis-like coupling of the
//!   beam slope rate);
//! - stiffness `K = m·b·(v²·b'' + a·b')ᵀ` (not symmetric; the centripetal term of the
//!   path's curvature `v²w''` softens the beam, the tangential one `a·w'`);
//! - resisting force `K·q + m·(v²·r'' + a·r')·b` (the profile's inertia load).
//!
//! The weight `m·g` comes from `[analysis] gravity` through the mass matrix (`M·g = −m·g·b`
//! on a horizontal beam: the consistent nodal forces of the weight), or from loads. The
//! contact force output is `P = m·(gravity + ÿ_c)` (compression positive), with `gravity`
//! the key of that name (used only for this output). The contact never opens.

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
use railfem_framework::{serde_json, FemError};

railfem_framework::element_params! {
    /// Model-file keys of `moving_mass` (SI units).
    pub struct MovingMassParams {
        /// Mass m (kg), > 0.
        m: f64 ["kg"],
        /// Beam element ids of the path, in order of travel (either direction); or use `track`.
        path: Vec<u64> ["-"] = Vec::<u64>::new(),
        /// Name of a generated track to ride on instead of `path` (with `rail`).
        track: String [""] = "",
        /// Rail of `track`: "left" or "right" (only with `track`).
        rail: RailSide [""] = RailSide::Left,
        /// Station of the mass at t = 0 (m): distance along `path`, or track station.
        start: f64 ["m"] = 0.0,
        /// Speed at t = 0 (m/s), ≥ 0.
        speed: f64 ["m/s"] = 0.0,
        /// Constant acceleration (m/s²); negative brakes to a stop.
        accel: f64 ["m/s^2"] = 0.0,
        /// Speed table [[t (s), v (m/s)], …], piecewise linear; replaces `speed` and `accel`.
        speed_table: Vec<[f64; 2]> ["s, m/s"] = Vec::<[f64; 2]>::new(),
        /// Gravitational acceleration used in the reported contact force (m/s²).
        gravity: f64 ["m/s^2"] = 9.81,
    }
}

impl railfem_framework::registry::ElementParams for MovingMassParams {
    const KIND: &'static str = "moving_mass";
}

impl MovingMassParams {
    /// A moving mass `m` (kg; the one required key) with every other key at its
    /// documented default: at rest at station 0 of an empty `path`. Give the path (or
    /// `track`) and the motion with struct update syntax,
    /// `MovingMassParams { path, speed, ..MovingMassParams::new(m) }`.
    pub fn new(m: f64) -> MovingMassParams {
        MovingMassParams {
            m,
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

/// Element DOFs: the 12 DOFs of the segment's two nodes.
const N: usize = 12;

/// The `moving_mass` element. See the module documentation.
#[derive(Debug, Clone)]
pub struct MovingMass {
    params: MovingMassParams,
    path: ContactPath,
    conn: [NodeDofs; 2],
    point: ContactPoint,
    q: [f64; N],
    qd: [f64; N],
    qdd: [f64; N],
}

impl MovingMass {
    /// Builds the element along `path`.
    pub fn new(
        params: MovingMassParams,
        path: ContactPath,
        origin: &str,
    ) -> Result<MovingMass, FemError> {
        if !(params.m.is_finite() && params.m > 0.0) {
            return Err(FemError::input(
                origin,
                format!("moving_mass: `m` = {} kg must be > 0", fmt_num(params.m)),
            ));
        }
        let point = path.point(0.0).map_err(|m| FemError::input(origin, m))?;
        Ok(MovingMass {
            params,
            path,
            conn: [NodeDofs::all(point.nodes.0), NodeDofs::all(point.nodes.1)],
            point,
            q: [0.0; N],
            qd: [0.0; N],
            qdd: [0.0; N],
        })
    }

    /// `v²·b'' + a·b'`.
    fn convective(&self) -> [f64; N] {
        let p = &self.point;
        std::array::from_fn(|i| p.speed * p.speed * p.b2[i] + p.accel * p.b1[i])
    }

    /// `v²·r'' + a·r'` (m/s²).
    fn profile_acceleration(&self) -> f64 {
        let p = &self.point;
        p.speed * p.speed * p.profile[2] + p.accel * p.profile[1]
    }

    /// ÿ_c at the trial state (m/s²).
    fn contact_acceleration(&self) -> f64 {
        let p = &self.point;
        dot(&p.b, &self.qdd)
            + 2.0 * p.speed * dot(&p.b1, &self.qd)
            + dot(&self.convective(), &self.q)
            + self.profile_acceleration()
    }

    /// The element's current contact point.
    pub fn point(&self) -> &ContactPoint {
        &self.point
    }
}

impl Element for MovingMass {
    fn kind(&self) -> &str {
        "moving_mass"
    }

    fn connectivity(&self) -> &[NodeDofs] {
        &self.conn
    }

    fn properties(&self) -> ElementProperties {
        ElementProperties {
            linear: false,
            constant_mass: false,
            constant_damping: false,
            has_mass: true,
            has_damping: true,
            symmetric: false,
            connectivity_may_change: true,
            objective: false,
            declared_mass: None,
            finite_rotations: false,
        }
    }

    fn advance(&mut self, ctx: &StepContext) -> Result<bool, ElementError> {
        let p = self.path.point(ctx.time).map_err(ElementError::Invalid)?;
        let changed = p.nodes != self.point.nodes;
        self.point = p;
        self.conn = [NodeDofs::all(p.nodes.0), NodeDofs::all(p.nodes.1)];
        Ok(changed)
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
        Ok(())
    }

    fn resisting_force(&self, f: &mut [f64]) {
        let load = dot(&self.convective(), &self.q) + self.profile_acceleration();
        for i in 0..N {
            f[i] = self.params.m * self.point.b[i] * load;
        }
    }

    fn tangent_stiffness(&self, k: &mut DMatrix<f64>) {
        let row = self.convective();
        for i in 0..N {
            for j in 0..N {
                k[(i, j)] = self.params.m * self.point.b[i] * row[j];
            }
        }
    }

    fn mass(&self, m: &mut DMatrix<f64>) {
        let b = &self.point.b;
        for i in 0..N {
            for j in 0..N {
                m[(i, j)] = self.params.m * b[i] * b[j];
            }
        }
    }

    fn damping(&self, c: &mut DMatrix<f64>) {
        let p = &self.point;
        let s = 2.0 * p.speed * self.params.m;
        for i in 0..N {
            for j in 0..N {
                c[(i, j)] = s * p.b[i] * p.b1[j];
            }
        }
    }

    fn output_names(&self) -> Vec<String> {
        [
            "station",
            "speed",
            "contact_force",
            "contact_disp",
            "contact_acc",
        ]
        .iter()
        .map(|s| s.to_string())
        .collect()
    }

    fn output_units(&self) -> Vec<String> {
        ["m", "m/s", "N", "m", "m/s²"]
            .iter()
            .map(|s| s.to_string())
            .collect()
    }

    fn outputs(&self, out: &mut Vec<f64>) {
        let p = &self.point;
        let acc = self.contact_acceleration();
        out.extend_from_slice(&[
            p.station,
            p.speed,
            self.params.m * (self.params.gravity + acc),
            dot(&p.b, &self.q) + p.profile[0],
            acc,
        ]);
    }

    fn parameters(&self) -> serde_json::Value {
        super::path::path_parameters(&self.params)
    }

    fn as_any(&self) -> Option<&dyn std::any::Any> {
        Some(self)
    }
}

/// Factory: no nodes (the path gives them), the path keys and the speed keys.
fn build(spec: &ElementSpec, ctx: &mut dyn BuildContext) -> Result<Box<dyn Element>, FemError> {
    let p: MovingMassParams = spec.parse()?;
    const KIND: &str = "moving_mass";
    if !spec.nodes.is_empty() {
        return Err(FemError::input(
            &spec.origin,
            "moving_mass: `nodes` must be empty (`nodes = []`): the path gives the nodes under the mass",
        ));
    }
    let history = speed_history(spec, KIND, p.start, p.speed, p.accel, &p.speed_table)?;
    let path = ContactPath::resolve(spec, ctx, KIND, &p.path, &p.track, p.rail, history)?;
    Ok(Box::new(MovingMass::new(p, path, &spec.origin)?))
}

fn rebuild(params: &serde_json::Value) -> Result<Box<dyn Element>, FemError> {
    let mut ctx = SampleContext {
        pos: sample_positions(),
    };
    build(&support::spec("moving_mass", &[], params.clone()), &mut ctx)
}

/// Conformance samples: accelerating, braking, and from a speed table, on a skew inclined
/// beam.
fn samples() -> Vec<Sample> {
    let cases = [
        (
            "accelerating",
            serde_json::json!({"m": 4000.0, "path": [10], "start": 0.4, "speed": 25.0, "accel": 2.0}),
        ),
        (
            "braking",
            serde_json::json!({"m": 4000.0, "path": [10], "start": 1.6, "speed": 10.0, "accel": -3.0}),
        ),
        (
            "speed table",
            serde_json::json!({"m": 900.0, "path": [10], "start": 1.0,
                "speed_table": [[0.0, 5.0], [2.0, 30.0]]}),
        ),
    ];
    cases
        .into_iter()
        .enumerate()
        .filter_map(|(i, (name, params))| {
            let element = rebuild(&params).ok()?;
            let pos = sample_positions();
            let mut s =
                support::sample_on_points(name, element, &pos[1..], 900 + i as u64, (1e-4, 1e-4));
            s.nodes = pos
                .iter()
                .map(|p| railfem_framework::NodeKinematics::fixed(*p))
                .collect();
            s.rebuild = Some(rebuild);
            Some(s)
        })
        .collect()
}

railfem_framework::inventory::submit! {
    ElementKind {
        name: "moving_mass",
        description: "mass rolling along a beam path or track rail at a prescribed speed history, full inertia (mass, gyroscopic and convective terms) on the beam",
        params: <MovingMassParams as Params>::docs,
        build,
        samples,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// On a horizontal beam the mass matrix carries the whole mass in vertical translation
    /// (`rᵀMr = m` for a unit Z translation r) and nothing along X.
    #[test]
    fn mass_is_vertical_and_complete() {
        let e = rebuild(&serde_json::json!({"m": 4000.0, "path": [10], "start": 0.7})).unwrap();
        let mut m = DMatrix::zeros(12, 12);
        e.mass(&mut m);
        let mut r = nalgebra::DVector::zeros(12);
        r[2] = 1.0;
        r[8] = 1.0;
        assert!(((r.transpose() * &m * &r)[(0, 0)] - 4000.0).abs() < 1e-9);
        let mut x = nalgebra::DVector::zeros(12);
        x[0] = 1.0;
        x[6] = 1.0;
        assert!((x.transpose() * &m * &x)[(0, 0)].abs() < 1e-6);
    }

    #[test]
    fn bad_input_is_refused_naming_the_key() {
        let err = |p: serde_json::Value| rebuild(&p).err().expect("refused").to_string();
        let e = err(serde_json::json!({"m": 0.0, "path": [10]}));
        assert!(e.contains("`m`"), "{e}");
        let e = err(serde_json::json!({"m": 1.0, "path": [10], "speed": -2.0}));
        assert!(e.contains("`speed`"), "{e}");
        let e = err(serde_json::json!({"m": 1.0, "path": [10], "speed": 2.0,
            "speed_table": [[0.0, 1.0]]}));
        assert!(e.contains("`speed_table`"), "{e}");
    }
}

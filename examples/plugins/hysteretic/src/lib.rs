//! Example railfem plugin: `hysteretic_spring`, a uniaxial bilinear spring with linear
//! kinematic hardening on one DOF, built as a `cdylib` and loaded at run time, beside one
//! load kind ([`unbalance`]: `rotating_unbalance`) and one recorder kind
//! ([`relative_motion`]: `relative_motion`), to show each extension point.
//!
//! What lives here: the element, its parameters, its conformance samples and the one call
//! that exports all three kinds ([`railfem_framework::export_plugin!`]). Load the library with
//! `plugins = ["…/librailfem_plugin_hysteretic.so"]` in a model file or
//! `railfem run MODEL --plugin PATH`. The crate is also an `rlib` so its own tests (and a
//! host that prefers static linking) can use [`HYSTERETIC_SPRING`] directly.
//!
//! # The model
//!
//! The spring acts on one DOF (`dof`, in the nodes' axes) between two nodes — deformation
//! `δ = u_j − u_i` — or between one node and the ground — `δ = u_i`. With elastic stiffness
//! `k`, yield force `fy` and post-yield stiffness ratio `α` (0 ≤ α < 1), the force is
//! `F = k·(δ − δ_p)` and the yield condition `|F − β| ≤ fy`, with back force `β = H·δ_p`
//! and kinematic hardening modulus `H = α·k/(1 − α)` (so that the post-yield tangent
//! `k·H/(k + H)` equals `α·k`). The return map from the committed `(δ_p, β)` is exact for
//! this linear hardening: with the trial `ξ = k(δ − δ_p,c) − β_c` and `φ = |ξ| − fy > 0`,
//! `Δγ = φ/(k + H)`, `δ_p = δ_p,c + Δγ·sign ξ`, `β = β_c + H·Δγ·sign ξ`. Every plastic state
//! lies on one of the two bounding lines `F = α·k·δ ± (1 − α)·fy`.
//!
//! **Energy.** [`Element::dissipated_energy`] reports the dissipation `fy·Σ|Δδ_p|` (the
//! plastic work `∫F dδ_p` minus the part `β²/(2H)` stored in the hardening, which is
//! recoverable); the stored energy is `F²/(2k) + β²/(2H)`.
//!
//! Units: `k` in N/m (N·m/rad on a rotational DOF), `fy` in N (N·m), `α` dimensionless.

use nalgebra::{DMatrix, Vector3};
use railfem_framework::element::{
    Element, ElementError, ElementProperties, NodeDofs, NodeKinematics, TrialState,
};
use railfem_framework::registry::{BuildContext, ElementKind, ElementSpec, Params, Sample};
use railfem_framework::{Dof, DofSet, FemError};

railfem_framework::element_params! {
    /// Model-file keys of `hysteretic_spring`.
    pub struct HystereticParams {
        /// DOF the spring acts on, in the nodes' axes (ux, uy, uz, rx, ry, rz).
        dof: String [""] = "ux",
        /// Elastic stiffness (N/m, or N·m/rad on a rotational DOF).
        k: f64 ["N/m"],
        /// Yield force (N, or N·m on a rotational DOF).
        fy: f64 ["N"],
        /// Post-yield stiffness over elastic stiffness, 0 ≤ alpha < 1.
        alpha: f64 ["-"] = 0.0,
    }
}

/// History of the spring: plastic deformation, back force, accumulated dissipation.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
struct History {
    /// Plastic deformation δ_p (m or rad).
    dp: f64,
    /// Back force β (N or N·m).
    beta: f64,
    /// Dissipated energy so far (J).
    dissipated: f64,
}

/// The bilinear kinematic-hardening spring.
pub struct HystereticSpring {
    params: HystereticParams,
    nodes: Vec<NodeDofs>,
    objective: bool,
    /// Kinematic hardening modulus H = α·k/(1 − α).
    h: f64,
    committed: History,
    trial: History,
    /// Committed deformation.
    delta_c: f64,
    /// Trial deformation δ.
    delta: f64,
    /// Trial force F.
    force: f64,
    /// Algorithmic tangent dF/dδ.
    kt: f64,
}

impl HystereticSpring {
    /// A spring with `params` on node indices `nodes` (one: grounded; two: between them),
    /// at reference positions `positions` (m), used only to decide objectivity. Bad
    /// parameters are reported with `origin`.
    pub fn new(
        params: HystereticParams,
        nodes: &[usize],
        positions: &[Vector3<f64>],
        origin: &str,
    ) -> Result<HystereticSpring, FemError> {
        let bad = |m: String| Err(FemError::input(origin, m));
        let Some(dof) = Dof::parse(&params.dof) else {
            return bad(format!(
                "`dof` = \"{}\" is not a DOF; use one of ux, uy, uz, rx, ry, rz",
                params.dof
            ));
        };
        if !(params.k > 0.0 && params.k.is_finite()) {
            return bad(format!(
                "`k` = {} must be a positive stiffness (N/m)",
                params.k
            ));
        }
        if !(params.fy > 0.0 && params.fy.is_finite()) {
            return bad(format!(
                "`fy` = {} must be a positive yield force (N)",
                params.fy
            ));
        }
        if !(0.0..1.0).contains(&params.alpha) {
            return bad(format!(
                "`alpha` = {} must lie in [0, 1) (post-yield stiffness ratio)",
                params.alpha
            ));
        }
        if nodes.is_empty() || nodes.len() > 2 {
            return bad(format!(
                "needs 1 node (grounded) or 2 nodes, got {}",
                nodes.len()
            ));
        }
        // Objective (rigid motions give no force) when two nodes lie on the DOF's axis: a
        // rotational DOF, or a separation parallel to the translation axis.
        let objective = nodes.len() == 2
            && (dof.index() >= 3 || {
                let d = positions[1] - positions[0];
                let along = d[dof.index()];
                (d.norm_squared() - along * along).abs() <= 1e-24 * d.norm_squared().max(1.0)
            });
        let h = params.alpha * params.k / (1.0 - params.alpha);
        let set = DofSet::of(&[dof]);
        Ok(HystereticSpring {
            nodes: nodes
                .iter()
                .map(|&node| NodeDofs { node, dofs: set })
                .collect(),
            objective,
            h,
            committed: History::default(),
            trial: History::default(),
            delta_c: 0.0,
            delta: 0.0,
            force: 0.0,
            kt: params.k,
            params,
        })
    }

    /// Return map from the committed history to the deformation `delta`.
    fn state_at(&self, delta: f64) -> (History, f64, f64) {
        let (k, fy, h) = (self.params.k, self.params.fy, self.h);
        let c = self.committed;
        let f_trial = k * (delta - c.dp);
        let xi = f_trial - c.beta;
        let phi = xi.abs() - fy;
        if phi <= 0.0 {
            return (c, f_trial, k);
        }
        let dg = phi / (k + h);
        let s = xi.signum();
        let hist = History {
            dp: c.dp + dg * s,
            beta: c.beta + h * dg * s,
            dissipated: c.dissipated + fy * dg,
        };
        (hist, k * (delta - hist.dp), k * h / (k + h))
    }
}

impl Element for HystereticSpring {
    fn kind(&self) -> &str {
        "hysteretic_spring"
    }
    fn connectivity(&self) -> &[NodeDofs] {
        &self.nodes
    }
    fn properties(&self) -> ElementProperties {
        ElementProperties {
            objective: self.objective,
            ..Default::default()
        }
    }
    fn update(&mut self, t: &TrialState) -> Result<(), ElementError> {
        let delta = match t.disp {
            [u] => *u,
            [ui, uj] => uj - ui,
            _ => {
                return Err(ElementError::Invalid(format!(
                    "hysteretic_spring expects 1 or 2 DOFs, got {}",
                    t.disp.len()
                )))
            }
        };
        if !delta.is_finite() {
            return Err(ElementError::NonFinite {
                what: "deformation".into(),
            });
        }
        let (hist, f, kt) = self.state_at(delta);
        self.trial = hist;
        self.delta = delta;
        self.force = f;
        self.kt = kt;
        Ok(())
    }
    fn resisting_force(&self, f: &mut [f64]) {
        match f {
            [a] => *a = self.force,
            [a, b] => {
                *a = -self.force;
                *b = self.force;
            }
            _ => {}
        }
    }
    fn tangent_stiffness(&self, k: &mut DMatrix<f64>) {
        if k.nrows() == 1 {
            k[(0, 0)] = self.kt;
        } else {
            k[(0, 0)] = self.kt;
            k[(1, 1)] = self.kt;
            k[(0, 1)] = -self.kt;
            k[(1, 0)] = -self.kt;
        }
    }
    fn commit(&mut self) {
        self.committed = self.trial;
        self.delta_c = self.delta;
    }
    fn revert(&mut self) {
        // Back to the committed state exactly: deformation, history, and the force and
        // (elastic, zero-increment) tangent the return map gives there.
        self.trial = self.committed;
        self.delta = self.delta_c;
        self.force = self.params.k * (self.delta_c - self.committed.dp);
        self.kt = self.params.k;
    }
    fn output_names(&self) -> Vec<String> {
        [
            "force",
            "deformation",
            "plastic_deformation",
            "back_force",
            "dissipated_energy",
        ]
        .map(String::from)
        .to_vec()
    }

    fn output_units(&self) -> Vec<String> {
        ["N", "m", "m", "N", "J"].map(String::from).to_vec()
    }
    fn outputs(&self, out: &mut Vec<f64>) {
        out.extend([
            self.force,
            self.delta,
            self.trial.dp,
            self.trial.beta,
            self.trial.dissipated,
        ]);
    }
    fn parameters(&self) -> serde_json::Value {
        serde_json::to_value(&self.params).unwrap_or(serde_json::Value::Null)
    }
    fn dissipated_energy(&self) -> f64 {
        self.trial.dissipated
    }
}

fn build(spec: &ElementSpec, ctx: &mut dyn BuildContext) -> Result<Box<dyn Element>, FemError> {
    let p: HystereticParams = spec.parse()?;
    let mut idx = Vec::new();
    for id in &spec.nodes {
        idx.push(
            ctx.node_index(*id).ok_or_else(|| {
                FemError::input(&spec.origin, format!("node {id} does not exist"))
            })?,
        );
    }
    let pos: Vec<Vector3<f64>> = idx.iter().map(|&i| ctx.node_position(i)).collect();
    Ok(Box::new(HystereticSpring::new(
        p,
        &idx,
        &pos,
        &spec.origin,
    )?))
}

/// Sample parameters: k = 1 MN/m, fy = 1 kN (yield deformation 1 mm), α = 0.1.
fn sample_params() -> HystereticParams {
    HystereticParams {
        dof: "ux".into(),
        k: 1.0e6,
        fy: 1.0e3,
        alpha: 0.1,
    }
}

fn samples() -> Vec<Sample> {
    let uy = 1.0e-3;
    let nodes = vec![
        NodeKinematics::fixed(Vector3::zeros()),
        NodeKinematics::fixed(Vector3::new(1.0, 0.0, 0.0)),
    ];
    let two = |name: &str, committed: Option<f64>, delta: f64| {
        let pos: Vec<Vector3<f64>> = nodes.iter().map(|n| n.position).collect();
        let element = HystereticSpring::new(sample_params(), &[0, 1], &pos, "sample")
            .expect("valid sample parameters");
        // Node i moves by −δ/4 so that both DOFs are exercised.
        let at = |d: f64| vec![-0.25 * d, 0.75 * d];
        let s = Sample::new(
            name,
            Box::new(element),
            nodes.clone(),
            at(delta),
            vec![0.0; 2],
        );
        match committed {
            Some(c) => s.committed_at(at(c)),
            None => s,
        }
    };
    vec![
        two("elastic", None, 0.5 * uy),
        two("yielding", Some(3.0 * uy), 3.5 * uy),
        two("unloading after yield", Some(3.0 * uy), 2.0 * uy),
        Sample::new(
            "grounded, reversed yield",
            Box::new(
                HystereticSpring::new(sample_params(), &[0], &[Vector3::zeros()], "sample")
                    .expect("valid sample parameters"),
            ),
            vec![NodeKinematics::fixed(Vector3::zeros())],
            vec![-2.5 * uy],
            vec![0.0],
        )
        .committed_at(vec![2.0 * uy]),
    ]
}

/// The element kind this plugin exports.
pub const HYSTERETIC_SPRING: ElementKind = ElementKind {
    name: "hysteretic_spring",
    description:
        "uniaxial bilinear spring with kinematic hardening on one DOF (2 nodes or grounded)",
    params: <HystereticParams as Params>::docs,
    build,
    samples,
};

pub mod relative_motion;
pub mod unbalance;

pub use relative_motion::RELATIVE_MOTION;
pub use unbalance::ROTATING_UNBALANCE;

railfem_framework::export_plugin!(
    elements: [HYSTERETIC_SPRING],
    loads: [ROTATING_UNBALANCE],
    recorders: [RELATIVE_MOTION],
);

#[cfg(test)]
mod tests {
    use super::*;
    use railfem_framework::conformance::check_kind;

    #[test]
    fn passes_the_conformance_kit() {
        let r = check_kind(&HYSTERETIC_SPRING);
        let bad: Vec<_> = r.iter().filter(|x| !x.passed()).collect();
        assert!(bad.is_empty(), "{bad:#?}");
        // The two-node samples are objective; the grounded one is not.
        assert!(r.iter().any(|x| x.check == "rigid_body"
            && x.outcome == railfem_framework::conformance::Outcome::Pass));
    }

    #[test]
    fn the_exported_stamp_is_the_frameworks() {
        assert_eq!(
            RAILFEM_PLUGIN_ABI,
            railfem_framework::plugin::PluginAbi::CURRENT
        );
        let mut names = Vec::new();
        railfem_plugin_register(&mut |k| names.push((k.what(), k.name()))).unwrap();
        assert_eq!(
            names,
            vec![
                ("element", "hysteretic_spring"),
                ("load", "rotating_unbalance"),
                ("recorder", "relative_motion")
            ]
        );
    }

    /// A grounded spring driven to δ = 3·uy, back to −3·uy: on the way back it unloads
    /// elastically over 2·fy (F from fy + α·k·2uy to that minus 2fy), then yields along the
    /// lower bounding line `F = α·k·δ − (1 − α)·fy`.
    #[test]
    fn reversal_follows_the_bounding_lines() {
        let p = sample_params();
        let (k, fy, a) = (p.k, p.fy, p.alpha);
        let mut s = HystereticSpring::new(p, &[0], &[Vector3::zeros()], "t").unwrap();
        let at = |d: f64, s: &mut HystereticSpring| {
            s.update(&TrialState {
                time: 0.0,
                dt: 0.0,
                disp: &[d],
                vel: &[0.0],
                acc: &[0.0],
            })
            .unwrap();
            s.commit();
            s.force
        };
        let uy = fy / k;
        let f3 = at(3.0 * uy, &mut s);
        assert!((f3 - (a * k * 3.0 * uy + (1.0 - a) * fy)).abs() < 1e-9 * fy);
        let f1 = at(1.5 * uy, &mut s);
        assert!(
            (f1 - (f3 - 1.5 * uy * k)).abs() < 1e-9 * fy,
            "elastic unloading"
        );
        let fm = at(-3.0 * uy, &mut s);
        assert!((fm - (-a * k * 3.0 * uy - (1.0 - a) * fy)).abs() < 1e-9 * fy);
        // Dissipation: fy·Σ|Δδ_p|; δ_p = δ − F/k on the bounding lines.
        let dp3 = 3.0 * uy - f3 / k;
        let dpm = -3.0 * uy - fm / k;
        let d = s.dissipated_energy();
        assert!((d - fy * (dp3.abs() + (dp3 - dpm).abs())).abs() < 1e-9 * d);
    }
}

//! `spring_damper`: six uncoupled springs and dashpots between two nodes (or one node and
//! the ground) acting in a local frame — the zero-length link used for rail pads,
//! fasteners, ballast and vehicle suspensions. Linear by default; a direction may instead
//! follow a force table and/or a bump stop ([`crate::force_law`]).
//!
//! What does not live here: hysteretic springs (see the plugin example), and
//! moment arms between distinct node positions (the element is *zero-length*: it connects
//! the DOFs of its nodes directly, wherever the nodes are).
//!
//! # Formulation
//!
//! With `R` the rotation whose rows are the local axes in nodal axes, the relative motion
//! in local axes is `δ = R₆·(u_J − u_I)` (`R₆ = diag(R, R)` acting on translations and
//! rotations; `u_I = 0` for the grounded one-node variant) and the element force in local
//! axes is `f = K·δ + C·δ̇` with `K = diag(k)`, `C = diag(c)`. Node J receives
//! `R₆ᵀ·f` as resisting force and node I its negative, so the nodal stiffness is
//! `[[K_g, −K_g], [−K_g, K_g]]` with `K_g = R₆ᵀ·K·R₆` (and the same for `C`).
//!
//! **Nonlinear directions.** With a `force_table` or a `bump_stop` in any direction, the
//! local force of direction `i` is `F_i(δ_i) + c_i·δ̇_i` with the law `F_i` of
//! [`crate::force_law`] (the linear `k_i·δ_i` in the other directions) and the nodal
//! stiffness `K_g = R₆ᵀ·diag(dF_i/dδ_i)·R₆` at the trial state; the element then declares
//! itself not linear. Without them nothing changes: constant `K`, the same arithmetic.
//!
//! **Objectivity.** A rigid translation gives `δ = 0`. A rigid rotation `θ` about a point
//! gives equal rotations at both nodes (no rotational spring force) but
//! `u_J − u_I = θ × (x_J − x_I)`, which loads the translational springs unless the nodes
//! coincide. The element therefore declares itself objective only when its two nodes
//! coincide (within 1e-9 of the coordinate scale); a grounded spring is never objective.
//! Both nodes must have the same axes (ordinary nodes: global X-Y-Z).

use crate::beam3d::support;
use crate::force_law::{build_laws, zero_at_rest, BumpStops, ForceLaw, ForceTables};
use nalgebra::{DMatrix, Matrix3, Matrix6, Vector3, Vector6};
use railfem_framework::element::{Element, ElementError, ElementProperties, NodeDofs, TrialState};
use railfem_framework::limits::fmt_num;
use railfem_framework::node_view::{NodeBlocks, NodeForces, NodeState};
use railfem_framework::registry::{BuildContext, ElementKind, ElementSpec, Params, Sample};
use railfem_framework::{serde_json, FemError};

railfem_framework::element_params! {
    /// Model-file keys of `spring_damper` (SI units).
    pub struct SpringDamperParams {
        /// Spring stiffnesses [ux, uy, uz, rx, ry, rz] in local axes (N/m for translations, N·m/rad for rotations), each ≥ 0.
        k: [f64; 6] ["N/m, N*m/rad"],
        /// Dashpot coefficients [ux, uy, uz, rx, ry, rz] in local axes (N·s/m, N·m·s/rad), each ≥ 0.
        c: [f64; 6] ["N*s/m, N*m*s/rad"] = [0.0; 6],
        /// Local axes as rows in nodal axes: [] = the node's axes; [[x], [y]] (z = x × y, y made orthogonal to x); or [[x], [y], [z]] with z along x × y.
        axes: Vec<[f64; 3]> ["-"] = Vec::<[f64; 3]>::new(),
        /// Force–deflection tables by local direction (ux uy uz rx ry rz): `{uz = [[d, F], …]}`, piecewise linear, replacing that direction's `k`.
        force_table: ForceTables ["m, N; rad, N*m"] = ForceTables::new(),
        /// Bump stops by local direction: `{uz = {gap = g or [compression, extension], k = k_stop}}`, free inside the gap, added to the spring.
        bump_stop: BumpStops ["m, N/m; rad, N*m/rad"] = BumpStops::new(),
    }
}

impl railfem_framework::registry::ElementParams for SpringDamperParams {
    const KIND: &'static str = "spring_damper";
}

impl SpringDamperParams {
    /// Springs of stiffness `k` along [ux, uy, uz, rx, ry, rz] of the node's axes (N/m,
    /// N·m/rad; the one required key) with every other key at its documented default: no
    /// dashpots, no tables, no bump stops. Set the rest with struct update syntax,
    /// `SpringDamperParams { c, ..SpringDamperParams::new(k) }`.
    pub fn new(k: [f64; 6]) -> SpringDamperParams {
        SpringDamperParams {
            k,
            c: [0.0; 6],
            axes: Vec::new(),
            force_table: ForceTables::new(),
            bump_stop: BumpStops::new(),
        }
    }
}

/// The local frame of a spring from its `axes` key: `R` with rows local x, y, z in nodal
/// axes (orthonormal, right-handed). Rows: none → identity; `[x, y]` → `x̂ = x/|x|`,
/// `ẑ = x × y/|x × y|`, `ŷ = ẑ × x̂` (Gram–Schmidt); `[x, y, z]` → as for two rows, and
/// `z` must point along `x × y` (within 1e-6 in angle). Errors say what is wrong.
pub fn spring_axes(rows: &[[f64; 3]]) -> Result<Matrix3<f64>, String> {
    if rows.is_empty() {
        return Ok(Matrix3::identity());
    }
    if !(2..=3).contains(&rows.len()) {
        return Err(format!(
            "`axes` has {} rows; give [] (node axes), [[x], [y]] or [[x], [y], [z]]",
            rows.len()
        ));
    }
    let x = Vector3::from(rows[0]);
    let y = Vector3::from(rows[1]);
    if x.norm() == 0.0 {
        return Err("`axes`: the local x row is zero; give a direction".into());
    }
    let xh = x.normalize();
    let z = xh.cross(&y);
    if y.norm() == 0.0 || z.norm() < 1e-6 * y.norm() {
        return Err(
            "`axes`: the local y row is zero or parallel to x; give a direction across x".into(),
        );
    }
    let zh = z.normalize();
    if rows.len() == 3 {
        let z3 = Vector3::from(rows[2]);
        if z3.norm() == 0.0 || z3.normalize().dot(&zh) < 1.0 - 1e-12 {
            return Err(
                "`axes`: the third row is not along x × y (a right-handed triad); correct it or give only [[x], [y]]".into(),
            );
        }
    }
    let yh = zh.cross(&xh);
    Ok(Matrix3::from_rows(&[
        xh.transpose(),
        yh.transpose(),
        zh.transpose(),
    ]))
}

/// `R₆ᵀ·diag(d)·R₆` with `R₆ = diag(R, R)`: a diagonal local 6×6 matrix in nodal axes,
/// summed as `Σ d_i·(e_i·e_iᵀ)` so that it is exactly symmetric in floating point.
fn to_nodal(r: &Matrix3<f64>, d: &[f64; 6]) -> Matrix6<f64> {
    let mut out = Matrix6::zeros();
    for b in 0..2 {
        for i in 0..3 {
            for p in 0..3 {
                for q in 0..3 {
                    out[(3 * b + p, 3 * b + q)] += d[3 * b + i] * (r[(i, p)] * r[(i, q)]);
                }
            }
        }
    }
    out
}

/// The `spring_damper` element. See the module documentation.
#[derive(Debug, Clone)]
pub struct SpringDamper {
    params: SpringDamperParams,
    conn: Vec<NodeDofs>,
    axes: Matrix3<f64>,
    kg: Matrix6<f64>,
    cg: Matrix6<f64>,
    coincident: bool,
    /// Relative displacement `u_J − u_I` (or `u` grounded), nodal axes (m, rad).
    rel: Vector6<f64>,
    /// Relative velocity (m/s, rad/s).
    rel_v: Vector6<f64>,
    /// Nonlinear laws of the six local directions, `None` on the linear path.
    laws: Option<Vec<ForceLaw>>,
    /// Spring force in local axes (without dashpots) and the nodal tangent at the trial
    /// state (nonlinear path only).
    spring_local: Vector6<f64>,
    kt: Matrix6<f64>,
}

/// The six local direction names, the keys of `force_table` and `bump_stop`.
pub const DIRECTIONS: [&str; 6] = ["ux", "uy", "uz", "rx", "ry", "rz"];

impl SpringDamper {
    /// Builds the element on `nodes` (one index: grounded; two: I, J) at reference
    /// positions `pos` (m). Validates the keys; errors are [`FemError::Input`] at `origin`.
    pub fn new(
        params: SpringDamperParams,
        nodes: &[usize],
        pos: &[Vector3<f64>],
        origin: &str,
    ) -> Result<SpringDamper, FemError> {
        let bad = |m: String| FemError::input(origin, format!("spring_damper: {m}"));
        if !(1..=2).contains(&nodes.len()) || pos.len() != nodes.len() {
            return Err(bad(format!(
                "`nodes` has {} ids; give one (grounded) or two (I, J)",
                nodes.len()
            )));
        }
        for (key, vals) in [("k", &params.k), ("c", &params.c)] {
            if let Some((i, v)) = vals
                .iter()
                .enumerate()
                .find(|(_, v)| !(v.is_finite() && **v >= 0.0))
            {
                return Err(bad(format!(
                    "`{key}`[{i}] = {} must be ≥ 0 and finite (0 leaves that direction free)",
                    fmt_num(*v)
                )));
            }
        }
        let axes = spring_axes(&params.axes).map_err(bad)?;
        let laws = build_laws(
            &DIRECTIONS,
            &params.k,
            &params.force_table,
            &params.bump_stop,
        )
        .map_err(bad)?;
        let coincident = pos.len() == 2 && {
            let scale = pos[0].norm().max(pos[1].norm()).max(1.0);
            (pos[1] - pos[0]).norm() <= 1e-9 * scale
        };
        Ok(SpringDamper {
            kg: to_nodal(&axes, &params.k),
            cg: to_nodal(&axes, &params.c),
            conn: nodes.iter().map(|&n| NodeDofs::all(n)).collect(),
            axes,
            coincident,
            params,
            rel: Vector6::zeros(),
            rel_v: Vector6::zeros(),
            laws,
            spring_local: Vector6::zeros(),
            kt: Matrix6::zeros(),
        })
    }

    /// Whether a direction follows a force table or a bump stop.
    pub fn nonlinear(&self) -> bool {
        self.laws.is_some()
    }

    /// The laws at the current relative displacement: local spring forces and the nodal
    /// tangent `R₆ᵀ·diag(dF/dδ)·R₆`.
    fn evaluate_laws(&mut self) {
        let Some(laws) = &self.laws else { return };
        let mut kd = [0.0; 6];
        for b in 0..2 {
            let d = self.axes * self.rel.fixed_rows::<3>(3 * b);
            for i in 0..3 {
                let (f, k) = laws[3 * b + i].force_and_tangent(d[i]);
                self.spring_local[3 * b + i] = f;
                kd[3 * b + i] = k;
            }
        }
        self.kt = to_nodal(&self.axes, &kd);
    }

    /// Whether the element is grounded (one node).
    pub fn grounded(&self) -> bool {
        self.conn.len() == 1
    }

    /// Local axes `R` (rows = local x, y, z in nodal axes).
    pub fn axes(&self) -> &Matrix3<f64> {
        &self.axes
    }

    /// Element force in local axes at the trial state, `f = K·δ + C·δ̇`
    /// (N for translations, N·m for rotations); positive when node J moves (or turns)
    /// along the positive local axis relative to node I (tension positive).
    pub fn local_force(&self) -> Vector6<f64> {
        if self.laws.is_some() {
            let mut out = self.spring_local;
            for b in 0..2 {
                let dv = self.axes * self.rel_v.fixed_rows::<3>(3 * b);
                for i in 0..3 {
                    out[3 * b + i] += self.params.c[3 * b + i] * dv[i];
                }
            }
            return out;
        }
        let mut out = Vector6::zeros();
        for b in 0..2 {
            let d = self.axes * self.rel.fixed_rows::<3>(3 * b);
            let dv = self.axes * self.rel_v.fixed_rows::<3>(3 * b);
            for i in 0..3 {
                out[3 * b + i] = self.params.k[3 * b + i] * d[i] + self.params.c[3 * b + i] * dv[i];
            }
        }
        out
    }

    /// Adds `[[g, −g], [−g, g]]` (two nodes) or `g` (grounded) to `out` (zeroed).
    fn fill(&self, g: &Matrix6<f64>, out: &mut DMatrix<f64>) {
        let mut blocks = NodeBlocks::new(out, &self.conn);
        if self.grounded() {
            blocks.add_block6(0, 0, g);
        } else {
            blocks.add_between6(0, 1, g);
        }
    }

    /// Relative motion `x_J − x_I` (or `x` of the one node, grounded) of the six DOFs that
    /// `of` reads from a node of the trial state `t` (zero where `t` has no such values,
    /// as a static analysis may pass no velocities).
    fn relative<'t>(
        &self,
        t: &TrialState<'t>,
        of: fn(&NodeState<'t>) -> Vector6<f64>,
    ) -> Vector6<f64> {
        let last = of(&t.node(&self.conn, self.conn.len() - 1));
        if self.grounded() {
            last
        } else {
            last - of(&t.node(&self.conn, 0))
        }
    }
}

impl Element for SpringDamper {
    fn kind(&self) -> &str {
        "spring_damper"
    }

    fn connectivity(&self) -> &[NodeDofs] {
        &self.conn
    }

    fn properties(&self) -> ElementProperties {
        ElementProperties {
            linear: self.laws.is_none(),
            constant_mass: true,
            constant_damping: true,
            has_mass: false,
            has_damping: self.params.c.iter().any(|&c| c > 0.0),
            symmetric: true,
            connectivity_may_change: false,
            objective: self.coincident && zero_at_rest(&self.laws),
            declared_mass: None,
            finite_rotations: false,
        }
    }

    fn update(&mut self, trial: &TrialState) -> Result<(), ElementError> {
        let n = 6 * self.conn.len();
        support::check_trial(trial, n)?;
        self.rel = self.relative(trial, NodeState::displacement6);
        self.rel_v = self.relative(trial, NodeState::velocity6);
        self.evaluate_laws();
        Ok(())
    }

    fn resisting_force(&self, f: &mut [f64]) {
        let fj = if self.laws.is_some() {
            // R₆ᵀ·F: the local spring forces back in nodal axes.
            let mut g = Vector6::zeros();
            for b in 0..2 {
                let v = self.axes.transpose() * self.spring_local.fixed_rows::<3>(3 * b);
                g.fixed_rows_mut::<3>(3 * b).copy_from(&v);
            }
            g
        } else {
            self.kg * self.rel
        };
        f.fill(0.0);
        let mut forces = NodeForces::new(f, &self.conn);
        if self.grounded() {
            forces.add6(0, &fj);
        } else {
            forces.add6(0, &-fj);
            forces.add6(1, &fj);
        }
    }

    fn tangent_stiffness(&self, k: &mut DMatrix<f64>) {
        if self.laws.is_some() {
            self.fill(&self.kt, k);
        } else {
            self.fill(&self.kg, k);
        }
    }

    fn damping(&self, c: &mut DMatrix<f64>) {
        self.fill(&self.cg, c);
    }

    fn output_names(&self) -> Vec<String> {
        ["fx", "fy", "fz", "mx", "my", "mz"]
            .iter()
            .map(|s| s.to_string())
            .collect()
    }

    fn output_units(&self) -> Vec<String> {
        ["N", "N", "N", "N·m", "N·m", "N·m"]
            .iter()
            .map(|s| s.to_string())
            .collect()
    }

    fn outputs(&self, out: &mut Vec<f64>) {
        out.extend_from_slice(self.local_force().as_slice());
    }

    fn parameters(&self) -> serde_json::Value {
        serde_json::to_value(&self.params).unwrap_or(serde_json::Value::Null)
    }
}

/// Factory of `spring_damper`: one node (grounded) or two (I, J).
fn build(spec: &ElementSpec, ctx: &mut dyn BuildContext) -> Result<Box<dyn Element>, FemError> {
    let p: SpringDamperParams = spec.parse()?;
    let n = support::resolve_nodes(
        spec,
        ctx,
        &[1, 2],
        "spring_damper",
        "one node to ground, or nodes I and J",
    )?;
    let pos: Vec<Vector3<f64>> = n.iter().map(|&i| ctx.node_position(i)).collect();
    Ok(Box::new(SpringDamper::new(p, &n, &pos, &spec.origin)?))
}

/// Parameters and local deflections of the nonlinear conformance sample: a hardening
/// table on uz (sampled beyond its last point), a softening one on ry (inside a
/// segment), bump stops engaged on ux (compression) and rx (extension) and open on uy.
/// Every deflection lies ≥ 1e-4 from a kink, far beyond the kit's difference step.
fn nonlinear_sample() -> (serde_json::Value, [f64; 6]) {
    (
        serde_json::json!({"k": [1e7, 2e7, 3e8, 1e5, 2e5, 3e5],
            "c": [1e4, 0.0, 3e4, 10.0, 0.0, 30.0],
            "axes": [[1.0, 1.0, 0.0], [-1.0, 1.0, 0.3]],
            "force_table": {"uz": [[-2e-3, -2e5], [0.0, 0.0], [1e-3, 3e5], [2e-3, 9e5]],
                            "ry": [[-1e-2, -3e3], [0.0, 0.0], [1e-2, 1e3]]},
            "bump_stop": {"ux": {"gap": [1e-3, 5e-3], "k": 1e9},
                          "uy": {"gap": 1e-2, "k": 1e9},
                          "rx": {"gap": [0.0, 2e-3], "k": 1e7}}}),
        [-1.6e-3, 4e-3, 2.7e-3, 3.1e-3, -4e-3, 1e-3],
    )
}

/// Conformance samples: coincident nodes with rotated axes and dashpots (objective), a
/// grounded spring, a spring between distinct points (not objective), and coincident
/// nodes with force tables and bump stops at a state off their kinks.
fn samples() -> Vec<Sample> {
    let cases: [(&str, Vec<[f64; 3]>, serde_json::Value); 3] = [
        (
            "coincident nodes, rotated axes, damped",
            vec![[1.0, 2.0, 0.5], [1.0, 2.0, 0.5]],
            serde_json::json!({"k": [1e8, 2e8, 3e8, 1e5, 2e5, 3e5],
                               "c": [1e4, 0.0, 3e4, 10.0, 0.0, 30.0],
                               "axes": [[1.0, 1.0, 0.0], [-1.0, 1.0, 0.3]]}),
        ),
        (
            "grounded",
            vec![[0.0, 0.0, 0.0]],
            serde_json::json!({"k": [5e7, 5e7, 2e8, 0.0, 0.0, 0.0], "c": [0.0, 0.0, 1e5, 0.0, 0.0, 0.0]}),
        ),
        (
            "distinct points",
            vec![[0.0, 0.0, 0.0], [0.0, 0.0, 0.2]],
            serde_json::json!({"k": [1e7, 1e7, 1e9, 1e4, 1e4, 1e4]}),
        ),
    ];
    let mut out: Vec<Sample> = cases
        .into_iter()
        .enumerate()
        .filter_map(|(i, (name, pts, params))| {
            let pos: Vec<Vector3<f64>> = pts.iter().map(|&p| p.into()).collect();
            let ids: Vec<u64> = (1..=pos.len() as u64).collect();
            let mut ctx = support::PointContext::new(&pos);
            let element = build(&support::spec("spring_damper", &ids, params), &mut ctx).ok()?;
            Some(support::sample_on_points(
                name,
                element,
                &pos,
                300 + i as u64,
                (1e-3, 1e-3),
            ))
        })
        .collect();
    let (params, local) = nonlinear_sample();
    let pos = [Vector3::new(1.0, 2.0, 0.5); 2];
    let rows = [[1.0, 1.0, 0.0], [-1.0, 1.0, 0.3]];
    let mut ctx = support::PointContext::new(&pos);
    if let (Ok(element), Ok(r)) = (
        build(&support::spec("spring_damper", &[1, 2], params), &mut ctx),
        spring_axes(&rows),
    ) {
        let mut s = support::sample_on_points(
            "force tables and bump stops, off the kinks",
            element,
            &pos,
            310,
            (1e-3, 1e-3),
        );
        // Node I at rest, node J at R₆ᵀ·δ: the local deflections are exactly `local`.
        s.disp = vec![0.0; 12];
        for b in 0..2 {
            let v = r.transpose() * Vector3::from_column_slice(&local[3 * b..3 * b + 3]);
            s.disp[6 + 3 * b..9 + 3 * b].copy_from_slice(v.as_slice());
        }
        out.push(s);
    }
    out
}

railfem_framework::inventory::submit! {
    ElementKind {
        name: "spring_damper",
        description: "six uncoupled springs and dashpots in a local frame, linear or with force tables and bump stops (zero-length; 1 node grounded or 2 nodes)",
        params: <SpringDamperParams as Params>::docs,
        build,
        samples,
    }
}

#[cfg(test)]
mod tests {
    use super::support::{spec, PointContext};
    use super::*;

    const K: [f64; 6] = [1e8, 2e8, 3e8, 1e5, 2e5, 3e5];
    const C: [f64; 6] = [1e4, 2e4, 0.0, 10.0, 0.0, 30.0];

    fn build_at(pts: &[[f64; 3]], p: serde_json::Value) -> Result<Box<dyn Element>, FemError> {
        let pos: Vec<Vector3<f64>> = pts.iter().map(|&x| x.into()).collect();
        let ids: Vec<u64> = (1..=pos.len() as u64).collect();
        build(
            &spec("spring_damper", &ids, p),
            &mut PointContext::new(&pos),
        )
    }

    fn err(pts: &[[f64; 3]], p: serde_json::Value) -> String {
        match build_at(pts, p) {
            Ok(_) => panic!("expected an error"),
            Err(e) => e.to_string(),
        }
    }

    fn set(e: &mut dyn Element, disp: &[f64], vel: &[f64]) {
        let acc = vec![0.0; disp.len()];
        let t = TrialState {
            time: 0.0,
            dt: 0.0,
            disp,
            vel,
            acc: &acc,
        };
        e.update(&t).unwrap();
    }

    /// Local axes: x along (1, 1, 0)/√2, y = (−1, 1, 0.3) made orthogonal to x, z = x × y.
    fn rotated() -> (Box<dyn Element>, Matrix3<f64>) {
        let rows = [[1.0, 1.0, 0.0], [-1.0, 1.0, 0.3]];
        let p = serde_json::json!({"k": K, "c": C, "axes": rows});
        (
            build_at(&[[0.5; 3], [0.5; 3]], p).unwrap(),
            spring_axes(&rows).unwrap(),
        )
    }

    /// Moving node J by `s` along local axis `i` (translation or rotation) stretches only
    /// spring `i`: the resisting force at J is `k_i·s` along that axis (in nodal axes) and
    /// at I its negative. A random relative motion gives `Σ k_i·(e_i·δ)·e_i`. Exact up to
    /// rounding of the rotation (1e-12 relative).
    #[test]
    fn force_is_k_times_stretch_along_local_axes() {
        let (mut e, r) = rotated();
        for i in 0..6 {
            let ax = r.row(i % 3).transpose();
            let s = 1e-3;
            let mut d = vec![0.0; 12];
            for j in 0..3 {
                d[6 + 3 * (i / 3) + j] = s * ax[j];
            }
            set(e.as_mut(), &d, &[]);
            let mut f = vec![0.0; 12];
            e.resisting_force(&mut f);
            for j in 0..3 {
                let want = K[i] * s * ax[j];
                let (fi, fj) = (f[3 * (i / 3) + j], f[6 + 3 * (i / 3) + j]);
                assert!(
                    (fj - want).abs() <= 1e-12 * K[i] * s,
                    "dof {i}: {fj} vs {want}"
                );
                assert!((fi + want).abs() <= 1e-12 * K[i] * s);
                // nothing in the other group
                assert!(f[3 * (1 - i / 3) + j].abs() + f[6 + 3 * (1 - i / 3) + j].abs() == 0.0);
            }
            let mut out = Vec::new();
            e.outputs(&mut out);
            assert!((out[i] - K[i] * s).abs() <= 1e-12 * K[i] * s);
        }
        // Random state: K·u with the assembled tangent equals the resisting force.
        let d = support::pseudo_random_state(7, 2, 1e-3, 1e-3);
        set(e.as_mut(), &d, &[]);
        let mut f = vec![0.0; 12];
        e.resisting_force(&mut f);
        let mut k = DMatrix::zeros(12, 12);
        e.tangent_stiffness(&mut k);
        let ku = &k * nalgebra::DVector::from_column_slice(&d);
        for i in 0..12 {
            assert!((ku[i] - f[i]).abs() <= 1e-9 * ku.amax());
        }
        for b in 0..2 {
            let dl = r
                * (Vector3::from_column_slice(&d[6 + 3 * b..9 + 3 * b])
                    - Vector3::from_column_slice(&d[3 * b..3 + 3 * b]));
            let mut sum = Vector3::zeros();
            for i in 0..3 {
                sum += r.row(i).transpose() * K[3 * b + i] * dl[i];
            }
            for j in 0..3 {
                assert!((f[6 + 3 * b + j] - sum[j]).abs() <= 1e-12 * ku.amax());
            }
            assert!(sum.norm() > 0.0);
        }
    }

    /// The damping matrix has the same structure with `c`: `C·v` at node J is
    /// `Σ c_i·(e_i·δ̇)·e_i`; outputs add the dashpot force `c_i·(e_i·δ̇)` to the spring force.
    #[test]
    fn damping_matrix_and_dashpot_output() {
        let (mut e, r) = rotated();
        assert!(e.properties().has_damping && e.properties().objective);
        let mut c = DMatrix::zeros(12, 12);
        e.damping(&mut c);
        assert!((&c - c.transpose()).amax() == 0.0);
        let v = support::pseudo_random_state(11, 2, 1e-2, 1e-2);
        let cv = &c * nalgebra::DVector::from_column_slice(&v);
        let mut out = Vec::new();
        set(e.as_mut(), &[0.0; 12], &v);
        e.outputs(&mut out);
        for b in 0..2 {
            let dv = r
                * (Vector3::from_column_slice(&v[6 + 3 * b..9 + 3 * b])
                    - Vector3::from_column_slice(&v[3 * b..3 + 3 * b]));
            let mut want = Vector3::zeros();
            for i in 0..3 {
                want += r.row(i).transpose() * C[3 * b + i] * dv[i];
                assert!((out[3 * b + i] - C[3 * b + i] * dv[i]).abs() <= 1e-12 * 1e4 * 1e-1);
            }
            for j in 0..3 {
                assert!((cv[6 + 3 * b + j] - want[j]).abs() <= 1e-12 * cv.amax());
                assert!((cv[3 * b + j] + want[j]).abs() <= 1e-12 * cv.amax());
            }
        }
    }

    #[test]
    fn grounded_variant_and_objectivity_flags() {
        let mut g = build_at(&[[1.0, 2.0, 3.0]], serde_json::json!({"k": K})).unwrap();
        assert_eq!(g.ndof(), 6);
        assert!(!g.properties().objective && !g.properties().has_damping);
        let d = [1e-3, -2e-3, 3e-3, 1e-4, 2e-4, -3e-4];
        set(g.as_mut(), &d, &[]);
        let mut f = vec![0.0; 6];
        g.resisting_force(&mut f);
        for i in 0..6 {
            assert!((f[i] - K[i] * d[i]).abs() <= 1e-12 * K[i] * d[i].abs());
        }
        let apart = build_at(&[[0.0; 3], [0.0, 0.0, 1.0]], serde_json::json!({"k": K})).unwrap();
        assert!(!apart.properties().objective && apart.properties().linear);
    }

    #[test]
    fn bad_input_is_refused_with_the_key_named() {
        let two = [[0.0; 3], [0.0; 3]];
        let mut k = K;
        k[4] = -1.0;
        let e = err(&two, serde_json::json!({"k": k}));
        assert!(e.contains("`k`[4]"), "{e}");
        let e = err(
            &two,
            serde_json::json!({"k": K, "c": [0.0, 0.0, -3.0, 0.0, 0.0, 0.0]}),
        );
        assert!(e.contains("`c`[2]"), "{e}");
        for axes in [
            serde_json::json!([[1.0, 0.0, 0.0]]),
            serde_json::json!([[0.0, 0.0, 0.0], [0.0, 1.0, 0.0]]),
            serde_json::json!([[1.0, 0.0, 0.0], [2.0, 0.0, 0.0]]),
            serde_json::json!([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, -1.0]]),
        ] {
            let e = err(&two, serde_json::json!({"k": K, "axes": axes}));
            assert!(e.contains("`axes`"), "{e}");
        }
        let e = err(&[[0.0; 3]; 3], serde_json::json!({"k": K}));
        assert!(e.contains("`nodes`"), "{e}");
        let e = err(&two, serde_json::json!({"c": C}));
        assert!(e.contains("`k`"), "{e}");
        // A right-handed third row is accepted.
        build_at(
            &two,
            serde_json::json!({"k": K, "axes": [[0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]]}),
        )
        .unwrap();
    }

    /// With tables and stops (rotated axes): the local outputs equal the laws at the local
    /// deflections plus the dashpots, the resisting force at J is `R₆ᵀ·F` and at I its
    /// negative, and the element is not linear. Independent: the laws are evaluated here
    /// from the key values by hand.
    #[test]
    fn nonlinear_force_follows_the_laws_in_local_axes() {
        let (params, local) = nonlinear_sample();
        let rows = [[1.0, 1.0, 0.0], [-1.0, 1.0, 0.3]];
        let r = spring_axes(&rows).unwrap();
        let mut e = build_at(&[[0.5; 3], [0.5; 3]], params).unwrap();
        assert!(!e.properties().linear && e.properties().objective);
        let mut d = vec![0.0; 12];
        for b in 0..2 {
            let v = r.transpose() * Vector3::from_column_slice(&local[3 * b..3 * b + 3]);
            d[6 + 3 * b..9 + 3 * b].copy_from_slice(v.as_slice());
        }
        set(e.as_mut(), &d, &[]);
        // By hand: ux stop engaged by 0.6 mm at 1e9 plus k; uy inside its gap; uz beyond
        // the table's end, slope 6e8; rx stop engaged by 1.1 mrad at 1e7 plus k; ry inside
        // [-1e-2, 0] at slope 3e5; rz linear.
        let want = [
            1e7 * -1.6e-3 + 1e9 * -0.6e-3,
            2e7 * 4e-3,
            9e5 + 6e8 * 0.7e-3,
            1e5 * 3.1e-3 + 1e7 * 1.1e-3,
            3e5 * -4e-3,
            3e5 * 1e-3,
        ];
        let mut out = Vec::new();
        e.outputs(&mut out);
        let mut f = vec![0.0; 12];
        e.resisting_force(&mut f);
        for i in 0..6 {
            assert!(
                (out[i] - want[i]).abs() <= 1e-9 * want[i].abs(),
                "{i}: {} vs {}",
                out[i],
                want[i]
            );
        }
        for b in 0..2 {
            let g = r.transpose() * Vector3::from_column_slice(&want[3 * b..3 * b + 3]);
            for j in 0..3 {
                assert!((f[6 + 3 * b + j] - g[j]).abs() <= 1e-9 * g.norm());
                assert!((f[3 * b + j] + g[j]).abs() <= 1e-9 * g.norm());
            }
        }
    }

    /// Newton on a grounded spring with a four-segment hardening table and a bump stop,
    /// loaded to a force in each segment from rest: it reaches the closed-form deflection
    /// (the segment's line solved for the load) without stalling at the kinks, in at most
    /// one iteration per segment crossed plus one.
    #[test]
    fn newton_crosses_the_kinks() {
        let p = serde_json::json!({"k": [0.0, 0.0, 1.0, 0.0, 0.0, 0.0],
            "force_table": {"uz": [[0.0, 0.0], [0.01, 1e4], [0.02, 3e4], [0.03, 7e4]]},
            "bump_stop": {"uz": {"gap": [1.0, 0.035], "k": 1e7}}});
        let mut e = build_at(&[[0.0; 3]], p).unwrap();
        // Segments: slope 1e6, 2e6, 4e6, then 4e6 beyond 0.03, plus 1e7 beyond 0.035.
        for (load, d_exact) in [
            (5e3, 5e-3),
            (2e4, 0.015),
            (5e4, 0.025),
            (8e4, 0.0325),
            (1.5e5, 0.035 + (1.5e5 - 9e4) / 1.4e7),
        ] {
            let mut d = [0.0; 6];
            let mut its = 0;
            loop {
                set(e.as_mut(), &d, &[]);
                let mut f = vec![0.0; 6];
                e.resisting_force(&mut f);
                let r = load - f[2];
                if r.abs() <= 1e-9 * load {
                    break;
                }
                let mut k = DMatrix::zeros(6, 6);
                e.tangent_stiffness(&mut k);
                d[2] += r / k[(2, 2)];
                its += 1;
                assert!(its <= 6, "load {load}: no convergence, d = {}", d[2]);
            }
            assert!(
                (d[2] - d_exact).abs() <= 1e-12,
                "{load}: {} vs {d_exact}",
                d[2]
            );
        }
    }

    #[test]
    fn bad_tables_and_stops_are_refused_with_the_key_named() {
        let two = [[0.0; 3], [0.0; 3]];
        for (p, key) in [
            (
                serde_json::json!({"k": K, "force_table": {"uw": [[0.0, 0.0], [1.0, 1.0]]}}),
                "`uw` is not a direction",
            ),
            (
                serde_json::json!({"k": K, "force_table": {"uz": [[0.0, 0.0], [0.0, 1.0]]}}),
                "`force_table.uz`[1]",
            ),
            (
                serde_json::json!({"k": K, "bump_stop": {"rx": {"gap": [0.1, -0.1], "k": 1.0}}}),
                "`bump_stop.rx` gap (extension)",
            ),
            (
                serde_json::json!({"k": K, "bump_stop": {"rx": {"gap": 0.1, "k": 1.0, "kk": 2.0}}}),
                "kk",
            ),
        ] {
            let e = err(&two, p);
            assert!(e.contains(key), "{e}");
        }
    }

    #[test]
    fn registered_with_samples() {
        let k = railfem_framework::registry::find("spring_damper").expect("registered");
        let s = (k.samples)();
        assert_eq!(s.len(), 4);
        for x in &s {
            assert_eq!(x.disp.len(), x.element.ndof());
        }
    }
}

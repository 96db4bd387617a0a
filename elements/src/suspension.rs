//! `suspension`: a spring-damper between two rigid bodies, attached to their master nodes
//! at offsets, acting in the lower body's corotated axes, with a static preload and an
//! optional rotational (anti-roll) stiffness — the vehicle suspension that balances forces
//! and moments in the displaced configuration.
//!
//! What does not live here: the zero-length linear `spring_damper` (still used by the
//! linear-geometry vehicle and by track pads), and the bodies' masses.
//!
//! # Formulation
//!
//! Node I is the master (mass centre) of the lower body, node J that of the upper body.
//! Their rotational DOFs are total rotation vectors `ψ` (finite rotations,
//! [`railfem_framework::rotation`]), `R = exp([ψ]×)`. With `X` the reference positions,
//! `r_I`, `r_J` the attachment offsets (nodal axes) and `u` the translations, the current
//! attachment points are `p_I = X_I + u_I + a`, `a = R_I·r_I` and `p_J = X_J + u_J + b`,
//! `b = R_J·r_J`. The deflection in the lower body's axes is
//!
//! `d = R_Iᵀ·(p_J − p_I) − d₀`,  `d₀ = (X_J + r_J) − (X_I + r_I)`,
//!
//! and the spring force on J, in those axes, `g = K·d + f₀` (`K = diag(k)`, `f₀` the
//! preload: the force the spring carries in the reference state, tension positive; a
//! spring holding a body up carries a negative vertical `f₀`). With `G = R_I·g`:
//!
//! `r_uJ = G`, `r_θJ = b × G`, `r_uI = −G`, `r_θI = −(p_J − x_I) × G`   (`x_I = X_I + u_I`).
//!
//! These are the derivatives of the potential `½·dᵀK·d + f₀ᵀd` with respect to the
//! translations and the spatial spins, so the element is a conservative spring in the
//! current geometry: the forces and moments it applies to the two bodies sum to zero about
//! any point (`x_J×G + b×G − x_I×G − (p_J − x_I)×G = 0`) however far its ends separate.
//! The spring's axes turn with the lower body (the spring seat), so the lateral and the
//! vertical rates keep their meaning when the bogie rolls.
//!
//! **Tangent** (conjugate to the spins). Writing `δd = R_Iᵀ·L·δq` with
//! `L = [−I, [p_J − x_I]×, I, −[b]×]` on `(u_I, θ_I, u_J, θ_J)`:
//!
//! `K_t = Lᵀ·R_I·K·R_Iᵀ·L` (material)
//! `  + Lᵀ·(−[G]×)` in the `θ_I` columns (the axes turn with body I: `δG ∋ [δθ_I]×·G`)
//! `  + [G]×·(δu_J − δu_I − [b]×δθ_J)` in the `θ_I` rows (the arm `p_J − x_I` varies)
//! `  + [G]×·[b]×·δθ_J` in the `θ_J` rows (the arm `b` turns with body J).
//!
//! It is not symmetric away from equilibrium. Its skew part, summed over the elements at a
//! node, is set by the net moment there, which vanishes at equilibrium when no moment is
//! applied to the node (the vehicle's case); `tangent = "symmetric"` returns `½(K_t + K_tᵀ)`
//! so that a large symmetric model keeps its Cholesky factorization — Newton then still
//! converges to the same equilibrium (the resisting force is exact) and near it almost as
//! fast. `"consistent"` (the default) returns `K_t`.
//!
//! **Nonlinear axes.** A `force_table` or a `bump_stop` on axis 1, 2 or 3 replaces
//! `K·d` along that axis by the law `F_a(d_a)` of [`crate::force_law`], so
//! `g_a = F_a(d_a) + f₀_a`, and `K` in the material tangent by `diag(dF_a/dd_a)` at the
//! trial deflection; the geometric terms are unchanged (they hold `G` whatever its law).
//! The laws act on the translational deflection only, not on `k_rot`.
//!
//! **Rotational stiffness** (the anti-roll bar): `ρ = log(R_Iᵀ·R_J)`, potential
//! `½·ρᵀ·K_r·ρ`, moment `m = R_I·T(ρ)⁻ᵀ·K_r·ρ` on J and `−m` on I (`T` the tangent
//! operator, [`railfem_framework::rotation::spin_from_rotation_vector`]). Its 6×6 tangent
//! over the two spins is taken by central differences of that exact moment (spins of
//! 1e-7 rad composed onto the rotations, relative error ≈ 1e-9); it is computed only when
//! `k_rot` is not zero.
//!
//! **Damping** acts on the relative velocity of the attachment points and the relative
//! angular velocity, in the reference geometry (`C = L₀ᵀ·diag(c)·L₀`, constant): the
//! dashpots of a vehicle matter in its motion about the displaced state, not for the state.
//!
//! **Objectivity.** A rigid motion of any size leaves `d` and `ρ` unchanged; the nodal
//! forces then turn with the bodies. Without preload they are zero and the element declares
//! itself objective; with preload (or a force table that does not pass through (0, 0))
//! the force is constant in the bodies' axes, not zero.

use crate::beam3d::support;
use crate::force_law::{build_laws, zero_at_rest, BumpStops, ForceLaw, ForceTables};
use nalgebra::{DMatrix, Matrix3, SMatrix, Vector3};
use railfem_framework::element::{Element, ElementError, ElementProperties, NodeDofs, TrialState};
use railfem_framework::registry::{BuildContext, ElementKind, ElementSpec, Params, Sample};
use railfem_framework::rotation::{compose, exp, log, rotation_vector_from_spin, skew};
use railfem_framework::{serde_json, FemError};

/// Which tangent a nonlinear suspension returns (its `tangent`; a train's
/// `suspension_tangent`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SuspensionTangent {
    /// The exact tangent, unsymmetric where the springs are corotated (`"consistent"`).
    Consistent,
    /// Its symmetric part, which keeps a symmetric model's Cholesky factorization
    /// (`"symmetric"`).
    Symmetric,
}

railfem_framework::element_params! {
    /// Model-file keys of `suspension` (SI units).
    pub struct SuspensionParams {
        /// Attachment point on body I (lower), offset from node I in nodal axes.
        offset_i: [f64; 3] ["m"] = [0.0; 3],
        /// Attachment point on body J (upper), offset from node J in nodal axes.
        offset_j: [f64; 3] ["m"] = [0.0; 3],
        /// Spring rates along body I's axes 1, 2, 3 (corotated), each ≥ 0.
        k: [f64; 3] ["N/m"],
        /// Dashpots along axes 1, 2, 3, each ≥ 0 (reference geometry).
        c: [f64; 3] ["N*s/m"] = [0.0; 3],
        /// Force the spring carries in the reference state, on J along body I's axes (tension positive).
        preload: [f64; 3] ["N"] = [0.0; 3],
        /// Rotational stiffness on the relative rotation of J from I about I's axes 1, 2, 3 (anti-roll bar: axis 3 on a vehicle), each ≥ 0.
        k_rot: [f64; 3] ["N*m/rad"] = [0.0; 3],
        /// Position of node J relative to node I in the reference state, in nodal axes; [] = from the node coordinates (carried vehicle nodes give it, their coordinates being global).
        j_from_i: Vec<f64> ["m"] = Vec::<f64>::new(),
        /// "consistent" (exact, unsymmetric) or "symmetric" (its symmetric part, keeps Cholesky).
        tangent: SuspensionTangent [""] = "consistent",
        /// Force–deflection tables by axis ("1", "2", "3"): `{3 = [[d, F], …]}`, piecewise linear, replacing that axis's `k` (the preload still adds).
        force_table: ForceTables ["m, N"] = ForceTables::new(),
        /// Bump stops by axis: `{3 = {gap = g or [compression, extension], k = k_stop}}`, free inside the gap, added to the spring.
        bump_stop: BumpStops ["m, N/m"] = BumpStops::new(),
    }
}

impl railfem_framework::registry::ElementParams for SuspensionParams {
    const KIND: &'static str = "suspension";
}

impl SuspensionParams {
    /// Spring rates `k` along body I's axes 1, 2, 3 (N/m; the one required key) with every
    /// other key at its documented default: attached at the nodes, no dashpots, no
    /// preload, no rotational stiffness, the consistent tangent, no tables or stops.
    pub fn new(k: [f64; 3]) -> SuspensionParams {
        SuspensionParams {
            offset_i: [0.0; 3],
            offset_j: [0.0; 3],
            k,
            c: [0.0; 3],
            preload: [0.0; 3],
            k_rot: [0.0; 3],
            j_from_i: Vec::new(),
            tangent: SuspensionTangent::Consistent,
            force_table: ForceTables::new(),
            bump_stop: BumpStops::new(),
        }
    }
}

/// The axis names, the keys of `force_table` and `bump_stop`.
pub const AXES: [&str; 3] = ["1", "2", "3"];

type Mat12 = SMatrix<f64, 12, 12>;
type Mat3x12 = SMatrix<f64, 3, 12>;

/// The `suspension` element. See the module documentation.
#[derive(Debug, Clone)]
pub struct Suspension {
    params: SuspensionParams,
    conn: Vec<NodeDofs>,
    /// Reference positions of I and J (m).
    x0: [Vector3<f64>; 2],
    d0: Vector3<f64>,
    symmetric: bool,
    damping: Mat12,
    force: [f64; 12],
    tangent: Mat12,
    /// Deflection `d` and local force `g` at the trial state.
    local: [Vector3<f64>; 2],
    /// Laws of the three axes, `None` when every axis is the linear `k`.
    laws: Option<Vec<ForceLaw>>,
}

/// `[v]×` into rows `r`, columns `c` of a 3×12 block.
fn put(l: &mut Mat3x12, c: usize, m: &Matrix3<f64>) {
    l.fixed_view_mut::<3, 3>(0, c).copy_from(m);
}

impl Suspension {
    /// Builds the element between nodes `nodes = [I, J]` at reference positions `pos`.
    pub fn new(
        params: SuspensionParams,
        nodes: &[usize],
        pos: &[Vector3<f64>],
        origin: &str,
    ) -> Result<Suspension, FemError> {
        let bad = |m: String| FemError::input(origin, format!("suspension: {m}"));
        for (key, vals) in [("k", &params.k), ("c", &params.c), ("k_rot", &params.k_rot)] {
            if let Some((i, v)) = vals
                .iter()
                .enumerate()
                .find(|(_, v)| !(v.is_finite() && **v >= 0.0))
            {
                return Err(bad(format!(
                    "`{key}`[{i}] = {v} must be ≥ 0 and finite (0 leaves that direction free)"
                )));
            }
        }
        let finite = |v: &[f64; 3]| v.iter().all(|x| x.is_finite());
        for (key, v) in [
            ("preload", &params.preload),
            ("offset_i", &params.offset_i),
            ("offset_j", &params.offset_j),
        ] {
            if !finite(v) {
                return Err(bad(format!("`{key}` = {v:?} must be finite")));
            }
        }
        let laws =
            build_laws(&AXES, &params.k, &params.force_table, &params.bump_stop).map_err(bad)?;
        let symmetric = params.tangent == SuspensionTangent::Symmetric;
        let x0 = match params.j_from_i.as_slice() {
            [] => [pos[0], pos[1]],
            &[x, y, z] if x.is_finite() && y.is_finite() && z.is_finite() => {
                [Vector3::zeros(), Vector3::new(x, y, z)]
            }
            other => {
                return Err(bad(format!(
                    "`j_from_i` = {other:?}; give three finite numbers (m) or leave it out"
                )))
            }
        };
        let (ri, rj) = (
            Vector3::from(params.offset_i),
            Vector3::from(params.offset_j),
        );
        let d0 = (x0[1] + rj) - (x0[0] + ri);
        // Constant damping in the reference geometry: L₀ with R = I.
        let mut l0 = Mat3x12::zeros();
        put(&mut l0, 0, &-Matrix3::identity());
        put(&mut l0, 3, &skew(&(x0[1] + rj - x0[0])));
        put(&mut l0, 6, &Matrix3::identity());
        put(&mut l0, 9, &-skew(&rj));
        let damping = l0.transpose() * Matrix3::from_diagonal(&params.c.into()) * l0;
        Ok(Suspension {
            conn: nodes.iter().map(|&n| NodeDofs::all(n)).collect(),
            x0,
            d0,
            symmetric,
            damping,
            force: [0.0; 12],
            tangent: Mat12::zeros(),
            local: [Vector3::zeros(); 2],
            laws,
            params,
        })
    }

    /// Deflection `d` (m) and spring force `g` (N) in body I's axes at the trial state.
    pub fn deflection_and_force(&self) -> (Vector3<f64>, Vector3<f64>) {
        (self.local[0], self.local[1])
    }

    /// Moment on J of the rotational stiffness, `m = R_I·T(ρ)⁻ᵀ·K_r·ρ`.
    fn rotational_moment(&self, psi_i: &Vector3<f64>, psi_j: &Vector3<f64>) -> Vector3<f64> {
        let r_i = exp(psi_i);
        let rho = log(&(r_i.transpose() * exp(psi_j)));
        let kr = Vector3::from(self.params.k_rot);
        r_i * rotation_vector_from_spin(&rho).transpose() * kr.component_mul(&rho)
    }

    fn evaluate(&mut self, u: &[f64]) {
        let v = |k: usize| Vector3::new(u[k], u[k + 1], u[k + 2]);
        let (psi_i, psi_j) = (v(3), v(9));
        let (r_i, r_j) = (exp(&psi_i), exp(&psi_j));
        let a = r_i * Vector3::from(self.params.offset_i);
        let b = r_j * Vector3::from(self.params.offset_j);
        let x_i = self.x0[0] + v(0);
        let p_i = x_i + a;
        let p_j = self.x0[1] + v(6) + b;
        let d = r_i.transpose() * (p_j - p_i) - self.d0;
        let (k, spring) = match &self.laws {
            None => {
                let k = Vector3::from(self.params.k);
                (k, k.component_mul(&d))
            }
            Some(laws) => {
                let (mut k, mut f) = (Vector3::zeros(), Vector3::zeros());
                for a in 0..3 {
                    (f[a], k[a]) = laws[a].force_and_tangent(d[a]);
                }
                (k, f)
            }
        };
        let g = spring + Vector3::from(self.params.preload);
        let big_g = r_i * g;
        let arm = p_j - x_i;
        let mut f = [0.0; 12];
        let parts = [-big_g, -arm.cross(&big_g), big_g, b.cross(&big_g)];
        for (n, p) in parts.iter().enumerate() {
            f[3 * n..3 * n + 3].copy_from_slice(p.as_slice());
        }
        // Material part.
        let mut l = Mat3x12::zeros();
        put(&mut l, 0, &-Matrix3::identity());
        put(&mut l, 3, &skew(&arm));
        put(&mut l, 6, &Matrix3::identity());
        put(&mut l, 9, &-skew(&b));
        let kg = r_i * Matrix3::from_diagonal(&k) * r_i.transpose();
        let mut kt: Mat12 = l.transpose() * kg * l;
        // The axes turn with body I: δG ∋ −[G]×·δθ_I.
        let sg = skew(&big_g);
        let col_i = l.transpose() * (-sg);
        for r in 0..12 {
            for c in 0..3 {
                kt[(r, 3 + c)] += col_i[(r, c)];
            }
        }
        // The arms vary: θ_I rows get [G]×(δu_J − δu_I − [b]×δθ_J), θ_J rows [G]×[b]×δθ_J.
        let sb = skew(&b);
        let mut add = |r0: usize, c0: usize, m: &Matrix3<f64>| {
            let mut view = kt.fixed_view_mut::<3, 3>(r0, c0);
            view += m;
        };
        add(3, 6, &sg);
        add(3, 0, &-sg);
        add(3, 9, &(-sg * sb));
        add(9, 9, &(sg * sb));
        if self.params.k_rot.iter().any(|&x| x > 0.0) {
            let m = self.rotational_moment(&psi_i, &psi_j);
            for n in 0..3 {
                f[3 + n] -= m[n];
                f[9 + n] += m[n];
            }
            // Central differences over the six spins of the exact moment.
            let h = 1e-7;
            for node in 0..2 {
                for c in 0..3 {
                    let e = Vector3::ith(c, h);
                    let (mut pi, mut pj) = (psi_i, psi_j);
                    let (mut mi, mut mj) = (psi_i, psi_j);
                    if node == 0 {
                        pi = compose(&psi_i, &e);
                        mi = compose(&psi_i, &-e);
                    } else {
                        pj = compose(&psi_j, &e);
                        mj = compose(&psi_j, &-e);
                    }
                    let dm = (self.rotational_moment(&pi, &pj) - self.rotational_moment(&mi, &mj))
                        / (2.0 * h);
                    for r in 0..3 {
                        kt[(3 + r, 3 + 6 * node + c)] -= dm[r];
                        kt[(9 + r, 3 + 6 * node + c)] += dm[r];
                    }
                }
            }
        }
        if self.symmetric {
            kt = (kt + kt.transpose()) * 0.5;
        }
        self.force = f;
        self.tangent = kt;
        self.local = [d, g];
    }
}

impl Element for Suspension {
    fn kind(&self) -> &str {
        "suspension"
    }

    fn connectivity(&self) -> &[NodeDofs] {
        &self.conn
    }

    fn properties(&self) -> ElementProperties {
        ElementProperties {
            linear: false,
            constant_mass: true,
            constant_damping: true,
            has_mass: false,
            has_damping: self.params.c.iter().any(|&c| c > 0.0),
            symmetric: self.symmetric,
            connectivity_may_change: false,
            objective: self.params.preload.iter().all(|&p| p == 0.0) && zero_at_rest(&self.laws),
            declared_mass: None,
            finite_rotations: true,
        }
    }

    fn update(&mut self, trial: &TrialState) -> Result<(), ElementError> {
        support::check_trial(trial, 12)?;
        self.evaluate(trial.disp);
        if self.force.iter().any(|x| !x.is_finite()) {
            return Err(ElementError::NonFinite {
                what: "suspension force".into(),
            });
        }
        Ok(())
    }

    fn resisting_force(&self, f: &mut [f64]) {
        f.copy_from_slice(&self.force);
    }

    fn tangent_stiffness(&self, k: &mut DMatrix<f64>) {
        k.copy_from_slice(self.tangent.as_slice());
    }

    fn damping(&self, c: &mut DMatrix<f64>) {
        c.copy_from_slice(self.damping.as_slice());
    }

    fn output_names(&self) -> Vec<String> {
        ["d1", "d2", "d3", "f1", "f2", "f3"]
            .iter()
            .map(|s| s.to_string())
            .collect()
    }

    fn output_units(&self) -> Vec<String> {
        ["m", "m", "m", "N", "N", "N"]
            .iter()
            .map(|s| s.to_string())
            .collect()
    }

    fn outputs(&self, out: &mut Vec<f64>) {
        out.extend_from_slice(self.local[0].as_slice());
        out.extend_from_slice(self.local[1].as_slice());
    }

    fn parameters(&self) -> serde_json::Value {
        serde_json::to_value(&self.params).unwrap_or(serde_json::Value::Null)
    }
}

/// Factory of `suspension`: nodes I (lower body) and J (upper body).
fn build(spec: &ElementSpec, ctx: &mut dyn BuildContext) -> Result<Box<dyn Element>, FemError> {
    let p: SuspensionParams = spec.parse()?;
    let n = support::resolve_nodes(
        spec,
        ctx,
        &[2],
        "suspension",
        "the lower body's node I and the upper body's node J",
    )?;
    let pos: Vec<Vector3<f64>> = n.iter().map(|&i| ctx.node_position(i)).collect();
    Ok(Box::new(Suspension::new(p, &n, &pos, &spec.origin)?))
}

/// The nonlinear sample: the first case with a hardening table on axis 3 and bump
/// stops on axes 1 (engaged) and 2 (open); the module tests check that the sampled
/// deflections lie ≥ 1e-3 m from every kink.
fn nonlinear_sample_params() -> serde_json::Value {
    serde_json::json!({"offset_i": [1.2, 0.4, 0.0], "offset_j": [1.2, -0.6, 8.0],
        "k": [1.6e5, 1.9e5, 1.6e5], "c": [5e4, 4e4, 0.0],
        "preload": [3e3, -1.07e5, 0.0], "k_rot": [0.0, 0.0, 2e6],
        "force_table": {"3": [[-0.1, -1e4], [0.0, 0.0], [0.05, 1e4], [0.1, 3e4]]},
        "bump_stop": {"1": {"gap": [0.3, 0.04], "k": 5e6}, "2": {"gap": 0.3, "k": 5e6}}})
}

/// Conformance samples: a preloaded secondary spring with an anti-roll bar, strongly
/// deflected (10 cm) and an unloaded one (objective). Rotations stay at 1e-6 rad in the
/// samples so that an additive finite difference of ψ equals the spin's to 1e-6; the
/// geometric terms, proportional to the force and the arms, are fully exercised. The
/// module tests check the tangent against spin differences at rotations of 0.4 rad.
fn samples() -> Vec<Sample> {
    let cases = [
        (
            "preloaded, anti-roll bar, deflected",
            serde_json::json!({"offset_i": [1.2, 0.4, 0.0], "offset_j": [1.2, -0.6, 8.0],
                "k": [1.6e5, 1.9e5, 1.6e5], "c": [5e4, 4e4, 0.0],
                "preload": [3e3, -1.07e5, 0.0], "k_rot": [0.0, 0.0, 2e6]}),
        ),
        (
            "unloaded (objective)",
            serde_json::json!({"offset_i": [-1.0, 0.0, 1.25], "offset_j": [-1.0, -0.05, 0.0],
                "k": [6.5e6, 1.2e6, 1.5e7]}),
        ),
        (
            "force table and bump stops, off the kinks",
            nonlinear_sample_params(),
        ),
    ];
    let pts = [Vector3::new(0.0, 0.5, 0.0), Vector3::new(0.0, 1.5, -8.0)];
    cases
        .into_iter()
        .enumerate()
        .filter_map(|(i, (name, params))| {
            let mut ctx = support::PointContext::new(&pts);
            let element = build(&support::spec("suspension", &[1, 2], params), &mut ctx).ok()?;
            Some(support::sample_on_points(
                name,
                element,
                &pts,
                700 + (i as u64 % 2),
                (0.1, 1e-6),
            ))
        })
        .collect()
}

railfem_framework::inventory::submit! {
    ElementKind {
        name: "suspension",
        description: "body-to-body spring-damper at attachment offsets, corotated with the lower body, with preload and anti-roll stiffness (finite rotations)",
        params: <SuspensionParams as Params>::docs,
        build,
        samples,
    }
}

#[cfg(test)]
mod tests {
    use super::support::{spec, PointContext};
    use super::*;

    fn element(p: serde_json::Value) -> Suspension {
        let pts = [Vector3::new(0.2, 0.5, -0.3), Vector3::new(0.1, 1.5, 0.4)];
        let mut ctx = PointContext::new(&pts);
        let s = spec("suspension", &[1, 2], p);
        let pr: SuspensionParams = s.parse().unwrap();
        let n = support::resolve_nodes(&s, &ctx, &[2], "suspension", "").unwrap();
        let _ = &mut ctx;
        Suspension::new(pr, &n, &pts, "test").unwrap()
    }

    fn params() -> serde_json::Value {
        serde_json::json!({"offset_i": [1.2, 0.4, 0.3], "offset_j": [1.1, -0.6, -0.4],
            "k": [1.6e5, 1.9e5, 2.6e5], "preload": [2e3, -1.07e5, 5e2], "k_rot": [1e5, 3e5, 2e6]})
    }

    fn state() -> [f64; 12] {
        [
            0.05, -0.02, 0.03, 0.4, -0.3, 0.25, -0.04, 0.08, 0.01, -0.2, 0.35, 0.5,
        ]
    }

    /// The tangent equals central differences of the resisting force in which the
    /// rotational entries are moved by spins composed onto ψ (the scheme of
    /// `framework::rotation`), at rotations of 0.3–0.5 rad and a 10 cm deflection.
    #[test]
    fn tangent_is_conjugate_to_the_spin() {
        let mut e = element(params());
        let u = state();
        e.evaluate(&u);
        let k = e.tangent;
        let h = 1e-6;
        let mut worst = 0.0f64;
        for j in 0..12 {
            let moved = |s: f64| {
                let mut w = u;
                if j % 6 < 3 {
                    w[j] += s;
                } else {
                    let n = 6 * (j / 6) + 3;
                    let psi = Vector3::new(w[n], w[n + 1], w[n + 2]);
                    let c = compose(&psi, &Vector3::ith(j - n, s));
                    w[n..n + 3].copy_from_slice(c.as_slice());
                }
                w
            };
            let mut ep = e.clone();
            ep.evaluate(&moved(h));
            let mut em = e.clone();
            em.evaluate(&moved(-h));
            for i in 0..12 {
                let fd = (ep.force[i] - em.force[i]) / (2.0 * h);
                worst = worst.max((fd - k[(i, j)]).abs());
            }
        }
        assert!(worst < 1e-6 * k.amax(), "{worst:e} vs {:e}", k.amax());
    }

    /// Balance in the current geometry: the element's forces sum to zero and their
    /// moments about the origin (nodal moments plus x × F at the current node positions)
    /// sum to zero at a strongly displaced and rotated state.
    #[test]
    fn forces_and_moments_balance_when_displaced() {
        let mut e = element(params());
        let u = state();
        e.evaluate(&u);
        let f = e.force;
        let v = |k: usize| Vector3::new(f[k], f[k + 1], f[k + 2]);
        let x_i = e.x0[0] + Vector3::new(u[0], u[1], u[2]);
        let x_j = e.x0[1] + Vector3::new(u[6], u[7], u[8]);
        let sum_f = v(0) + v(6);
        let sum_m = x_i.cross(&v(0)) + v(3) + x_j.cross(&v(6)) + v(9);
        let scale = v(0).norm();
        assert!(sum_f.norm() < 1e-12 * scale);
        assert!(sum_m.norm() < 1e-10 * scale, "{sum_m:?}");
    }

    /// A rigid motion of any size (1 rad about a skew axis and a 3 m shift) leaves the
    /// deflection and the local force unchanged, and turns the nodal force with it.
    #[test]
    fn finite_rigid_motion_turns_the_force() {
        let mut e = element(params());
        let u = state();
        e.evaluate(&u);
        let (d, g) = e.deflection_and_force();
        let f0 = e.force;
        let q = Vector3::new(1.0, -2.0, 0.5).normalize() * 1.0;
        let rq = exp(&q);
        let c = Vector3::new(3.0, -1.0, 2.0);
        let mut w = [0.0; 12];
        for n in 0..2 {
            let x = e.x0[n] + Vector3::new(u[6 * n], u[6 * n + 1], u[6 * n + 2]);
            let moved = rq * x + c - e.x0[n];
            w[6 * n..6 * n + 3].copy_from_slice(moved.as_slice());
            let psi = Vector3::new(u[6 * n + 3], u[6 * n + 4], u[6 * n + 5]);
            let r = compose(&psi, &q);
            w[6 * n + 3..6 * n + 6].copy_from_slice(r.as_slice());
        }
        e.evaluate(&w);
        let (d2, g2) = e.deflection_and_force();
        assert!((d2 - d).norm() < 1e-12 && (g2 - g).norm() < 1e-6);
        let fj = Vector3::new(f0[6], f0[7], f0[8]);
        let fj2 = Vector3::new(e.force[6], e.force[7], e.force[8]);
        assert!((fj2 - rq * fj).norm() < 1e-9 * fj.norm());
    }

    /// A zero-length vertical spring under its preload: the reference state is balanced
    /// with the preload alone (d = 0), and a pure lateral offset of the upper body by δ
    /// gives the lateral force k₁·δ with the preload unchanged.
    #[test]
    fn preload_and_rates() {
        let mut e = element(
            serde_json::json!({"offset_i": [1.0, 0.5, 0.7], "offset_j": [1.1, -0.5, 0.0],
            "k": [1e5, 2e5, 3e5], "preload": [0.0, -1e5, 0.0]}),
        );
        e.evaluate(&[0.0; 12]);
        assert_eq!(e.local[1], Vector3::new(0.0, -1e5, 0.0));
        let mut u = [0.0; 12];
        u[6] = 0.02;
        e.evaluate(&u);
        assert!((e.force[6] - 1e5 * 0.02).abs() < 1e-9);
        assert!((e.force[7] + 1e5).abs() < 1e-9);
    }

    /// The nonlinear conformance sample sits ≥ 1e-3 m from every kink of its laws (the
    /// kit's difference step is ~1e-7 m), and its deflections engage the axis-1 stop and
    /// the table's outer segment.
    #[test]
    fn nonlinear_sample_is_off_the_kinks() {
        let s = samples().pop().unwrap();
        let pts = [Vector3::new(0.0, 0.5, 0.0), Vector3::new(0.0, 1.5, -8.0)];
        let p: SuspensionParams = spec("suspension", &[1, 2], nonlinear_sample_params())
            .parse()
            .unwrap();
        let mut e = Suspension::new(p, &[0, 1], &pts, "test").unwrap();
        e.evaluate(&s.disp);
        let d = e.local[0];
        let laws = e.laws.clone().unwrap();
        for a in 0..3 {
            for k in laws[a].kinks() {
                assert!(
                    (d[a] - k).abs() >= 1e-3,
                    "axis {a}: d = {} near kink {k}",
                    d[a]
                );
            }
        }
        assert!(d[0] > 0.04, "{d:?}");
    }

    /// A table and a bump stop on axis 3 of a zero-offset vertical spring: the force on
    /// J is the table value plus the stop force plus the preload, and the tangent's
    /// (u_J3, u_J3) entry is the segment slope plus the stop rate.
    #[test]
    fn table_and_stop_give_the_axial_force_and_rate() {
        let mut e = element(
            serde_json::json!({"k": [1e5, 1e5, 1e5], "preload": [0.0, 0.0, -2e4],
            "force_table": {"3": [[-0.05, -1e4], [0.0, 0.0], [0.05, 5e3]]},
            "bump_stop": {"3": {"gap": [0.04, 0.1], "k": 1e7}}}),
        );
        for (dz, f, k) in [
            (0.02, 2e3 - 2e4, 1e5),
            (-0.03, -6e3 - 2e4, 2e5),
            (-0.045, -9e3 - 2e4 - 1e7 * 0.005, 2e5 + 1e7),
        ] {
            let mut u = [0.0; 12];
            u[8] = dz;
            e.evaluate(&u);
            assert!(
                (e.force[8] - f).abs() < 1e-9 * f.abs(),
                "{dz}: {} vs {f}",
                e.force[8]
            );
            assert!((e.tangent[(8, 8)] - k).abs() < 1e-9 * k, "{dz}");
        }
        assert!(!e.properties().objective);
    }

    #[test]
    fn bad_keys_are_named() {
        let pts = [Vector3::zeros(), Vector3::zeros()];
        for (p, key) in [
            (serde_json::json!({"k": [1.0, -1.0, 0.0]}), "`k`[1]"),
            (
                serde_json::json!({"k": [1.0, 1.0, 0.0], "tangent": "exact"}),
                "`tangent`",
            ),
            (
                serde_json::json!({"k": [1.0, 1.0, 0.0], "j_from_i": [1.0]}),
                "`j_from_i`",
            ),
            (
                serde_json::json!({"k": [1.0, 1.0, 0.0], "force_table": {"z": [[0.0, 0.0], [1.0, 1.0]]}}),
                "`z` is not a direction",
            ),
            (
                serde_json::json!({"k": [1.0, 1.0, 0.0], "force_table": {"3": [[1.0, 0.0], [0.0, 1.0]]}}),
                "`force_table.3`[1]",
            ),
            (
                serde_json::json!({"k": [1.0, 1.0, 0.0], "bump_stop": {"3": {"gap": -0.1, "k": 1.0}}}),
                "`bump_stop.3` gap",
            ),
        ] {
            let s = spec("suspension", &[1, 2], p);
            let e = build(&s, &mut PointContext::new(&pts)).err().unwrap();
            assert!(e.to_string().contains(key), "{e}");
        }
    }
}

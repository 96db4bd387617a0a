//! `mass`: a lumped mass with a rotary inertia tensor on one node — wheelsets, bogies,
//! car bodies, sleepers.
//!
//! What does not live here: eccentric masses (offset from the node; use a rigid link) and
//! gyroscopic terms (the rotations are small).
//!
//! # Formulation
//!
//! The 6×6 mass matrix in the node's axes is `diag(m, m, m)` on the translations and the
//! inertia tensor about the node on the rotations,
//!
//! ```text
//!     ⎡ Ixx  −Ixy  −Ixz ⎤
//! I = ⎢−Ixy   Iyy  −Iyz ⎥     Ixy = ∫ x·y dm, …  (products of inertia, kg·m²)
//!     ⎣−Ixz  −Iyz   Izz ⎦
//! ```
//!
//! so that the kinetic energy is `½·m·|u̇|² + ½·ωᵀ·I·ω`. The element has no stiffness and
//! no damping: its resisting force and tangent are zero.

use crate::beam3d::support;
use nalgebra::{DMatrix, Matrix3, Vector3};
use railfem_framework::element::{Element, ElementError, ElementProperties, NodeDofs, TrialState};
use railfem_framework::limits::fmt_num;
use railfem_framework::node_view::NodeBlocks;
use railfem_framework::registry::{BuildContext, ElementKind, ElementSpec, Params, Sample};
use railfem_framework::{serde_json, FemError};

railfem_framework::element_params! {
    /// Model-file keys of `mass` (SI units).
    pub struct MassParams {
        /// Mass m (kg), ≥ 0.
        m: f64 ["kg"],
        /// Moments of inertia [Ixx, Iyy, Izz] about the node's axes (kg·m²), each ≥ 0.
        inertia: [f64; 3] ["kg*m^2"] = [0.0; 3],
        /// Product of inertia Ixy = ∫ x·y dm (kg·m²); the tensor holds −Ixy.
        Ixy: f64 ["kg*m^2"] = 0.0,
        /// Product of inertia Iyz = ∫ y·z dm (kg·m²); the tensor holds −Iyz.
        Iyz: f64 ["kg*m^2"] = 0.0,
        /// Product of inertia Ixz = ∫ x·z dm (kg·m²); the tensor holds −Ixz.
        Ixz: f64 ["kg*m^2"] = 0.0,
    }
}

impl railfem_framework::registry::ElementParams for MassParams {
    const KIND: &'static str = "mass";
}

impl MassParams {
    /// A point mass `m` (kg; the one required key) with no rotary inertia; set the
    /// inertias with struct update syntax, `MassParams { inertia, ..MassParams::new(m) }`.
    pub fn new(m: f64) -> MassParams {
        MassParams {
            m,
            inertia: [0.0; 3],
            Ixy: 0.0,
            Iyz: 0.0,
            Ixz: 0.0,
        }
    }
}

/// The inertia tensor (kg·m²) of a parameter set, see the module documentation.
pub fn inertia_tensor(p: &MassParams) -> Matrix3<f64> {
    let [ixx, iyy, izz] = p.inertia;
    Matrix3::new(
        ixx, -p.Ixy, -p.Ixz, //
        -p.Ixy, iyy, -p.Iyz, //
        -p.Ixz, -p.Iyz, izz,
    )
}

/// The `mass` element. See the module documentation.
#[derive(Debug, Clone)]
pub struct Mass {
    params: MassParams,
    conn: [NodeDofs; 1],
    tensor: Matrix3<f64>,
}

impl Mass {
    /// A mass on node index `node`. Refuses a negative or non-finite mass or moment of
    /// inertia and a tensor that is not positive semi-definite (eigenvalues below
    /// −1e-12 of its largest), with [`FemError::Input`] at `origin`.
    pub fn new(params: MassParams, node: usize, origin: &str) -> Result<Mass, FemError> {
        let bad = |m: String| Err(FemError::input(origin, format!("mass: {m}")));
        if !(params.m.is_finite() && params.m >= 0.0) {
            return bad(format!(
                "`m` = {} kg must be ≥ 0 and finite",
                fmt_num(params.m)
            ));
        }
        if let Some((i, v)) = params
            .inertia
            .iter()
            .enumerate()
            .find(|(_, v)| !(v.is_finite() && **v >= 0.0))
        {
            return bad(format!(
                "`inertia`[{i}] = {} kg·m² must be ≥ 0 and finite",
                fmt_num(*v)
            ));
        }
        for (key, v) in [
            ("Ixy", params.Ixy),
            ("Iyz", params.Iyz),
            ("Ixz", params.Ixz),
        ] {
            if !v.is_finite() {
                return bad(format!("`{key}` = {} must be finite", fmt_num(v)));
            }
        }
        let tensor = inertia_tensor(&params);
        let eig = tensor.symmetric_eigenvalues();
        if eig.min() < -1e-12 * eig.amax() {
            return bad(format!(
                "the inertia tensor from `inertia` and the products `Ixy`, `Iyz`, `Ixz` is not positive semi-definite (eigenvalues {:.4e}, {:.4e}, {:.4e} kg·m²); the products are too large for the moments — check their values and sign convention (Ixy = ∫ x·y dm)",
                eig[0], eig[1], eig[2]
            ));
        }
        Ok(Mass {
            params,
            conn: [NodeDofs::all(node)],
            tensor,
        })
    }

    /// The inertia tensor about the node (kg·m²).
    pub fn tensor(&self) -> &Matrix3<f64> {
        &self.tensor
    }
}

impl Element for Mass {
    fn kind(&self) -> &str {
        "mass"
    }

    fn connectivity(&self) -> &[NodeDofs] {
        &self.conn
    }

    fn properties(&self) -> ElementProperties {
        ElementProperties {
            linear: true,
            constant_mass: true,
            constant_damping: true,
            has_mass: self.params.m > 0.0 || self.tensor.amax() > 0.0,
            has_damping: false,
            symmetric: true,
            connectivity_may_change: false,
            objective: true,
            declared_mass: Some(self.params.m),
            finite_rotations: false,
        }
    }

    fn update(&mut self, trial: &TrialState) -> Result<(), ElementError> {
        support::check_trial(trial, 6)
    }

    fn resisting_force(&self, f: &mut [f64]) {
        f.fill(0.0);
    }

    fn tangent_stiffness(&self, _k: &mut DMatrix<f64>) {}

    fn mass(&self, m: &mut DMatrix<f64>) {
        let mut blocks = NodeBlocks::new(m, &self.conn);
        blocks.add_translations(0, 0, &Matrix3::from_diagonal_element(self.params.m));
        blocks.add_rotations(0, 0, &self.tensor);
    }

    fn parameters(&self) -> serde_json::Value {
        serde_json::to_value(&self.params).unwrap_or(serde_json::Value::Null)
    }
}

/// Factory of `mass`: one node.
fn build(spec: &ElementSpec, ctx: &mut dyn BuildContext) -> Result<Box<dyn Element>, FemError> {
    let p: MassParams = spec.parse()?;
    let n = support::resolve_nodes(spec, ctx, &[1], "mass", "the node carrying the mass")?;
    Ok(Box::new(Mass::new(p, n[0], &spec.origin)?))
}

/// Conformance samples: a point mass, and a body with a full inertia tensor.
fn samples() -> Vec<Sample> {
    let cases = [
        ("point mass", serde_json::json!({"m": 1200.0})),
        (
            "full inertia tensor",
            serde_json::json!({"m": 1800.0, "inertia": [900.0, 150.0, 950.0],
                               "Ixy": 20.0, "Iyz": -35.0, "Ixz": 60.0}),
        ),
    ];
    cases
        .into_iter()
        .enumerate()
        .filter_map(|(i, (name, params))| {
            let pos = [Vector3::new(0.0, 0.0, 0.8)];
            let mut ctx = support::PointContext::new(&pos);
            let element = build(&support::spec("mass", &[1], params), &mut ctx).ok()?;
            Some(support::sample_on_points(
                name,
                element,
                &pos,
                500 + i as u64,
                (1e-3, 1e-3),
            ))
        })
        .collect()
}

railfem_framework::inventory::submit! {
    ElementKind {
        name: "mass",
        description: "lumped mass with rotary inertia tensor on one node",
        params: <MassParams as Params>::docs,
        build,
        samples,
    }
}

#[cfg(test)]
mod tests {
    use super::support::{spec, PointContext};
    use super::*;

    fn build_with(nodes: &[u64], p: serde_json::Value) -> Result<Box<dyn Element>, FemError> {
        let pos = [Vector3::zeros(), Vector3::x()];
        build(&spec("mass", nodes, p), &mut PointContext::new(&pos))
    }

    fn err(nodes: &[u64], p: serde_json::Value) -> String {
        build_with(nodes, p)
            .err()
            .expect("expected an error")
            .to_string()
    }

    /// Every entry of the 6×6 matrix: `m` on the translations, the tensor with negated
    /// products on the rotations, zero coupling; zero stiffness and force.
    #[test]
    fn mass_matrix_entries() {
        let e = build_with(
            &[2],
            serde_json::json!({"m": 1800.0, "inertia": [900.0, 150.0, 950.0],
                               "Ixy": 20.0, "Iyz": -35.0, "Ixz": 60.0}),
        )
        .unwrap();
        assert_eq!(e.connectivity()[0].node, 1);
        let mut m = DMatrix::zeros(6, 6);
        e.mass(&mut m);
        #[rustfmt::skip]
        let want = DMatrix::from_row_slice(6, 6, &[
            1800.0, 0.0, 0.0, 0.0, 0.0, 0.0,
            0.0, 1800.0, 0.0, 0.0, 0.0, 0.0,
            0.0, 0.0, 1800.0, 0.0, 0.0, 0.0,
            0.0, 0.0, 0.0, 900.0, -20.0, -60.0,
            0.0, 0.0, 0.0, -20.0, 150.0, 35.0,
            0.0, 0.0, 0.0, -60.0, 35.0, 950.0,
        ]);
        assert_eq!(m, want);
        let p = e.properties();
        assert!(p.has_mass && p.linear && p.objective && !p.has_damping);
        assert_eq!(p.declared_mass, Some(1800.0));
        let mut k = DMatrix::zeros(6, 6);
        e.tangent_stiffness(&mut k);
        assert_eq!(k.amax(), 0.0);
        let mut f = vec![1.0; 6];
        e.resisting_force(&mut f);
        assert_eq!(f, vec![0.0; 6]);
    }

    #[test]
    fn bad_input_is_refused_with_the_key_named() {
        let e = err(&[1], serde_json::json!({"m": -1.0}));
        assert!(e.contains("`m`"), "{e}");
        let e = err(
            &[1],
            serde_json::json!({"m": 1.0, "inertia": [1.0, -2.0, 1.0]}),
        );
        assert!(e.contains("`inertia`[1]"), "{e}");
        // |Ixy| > sqrt(Ixx·Iyy): the 2×2 minor is negative.
        let e = err(
            &[1],
            serde_json::json!({"m": 1.0, "inertia": [1.0, 1.0, 1.0], "Ixy": 1.5}),
        );
        assert!(
            e.contains("`Ixy`") && e.contains("positive semi-definite"),
            "{e}"
        );
        let e = err(&[1, 2], serde_json::json!({"m": 1.0}));
        assert!(e.contains("`nodes`"), "{e}");
        let e = err(&[1], serde_json::json!({}));
        assert!(e.contains("`m`"), "{e}");
        let mut p: MassParams = spec("mass", &[1], serde_json::json!({"m": 1.0}))
            .parse()
            .unwrap();
        p.m = f64::NAN;
        assert!(Mass::new(p, 0, "t")
            .unwrap_err()
            .to_string()
            .contains("`m`"));
    }

    #[test]
    fn registered_with_samples() {
        let k = railfem_framework::registry::find("mass").expect("registered");
        assert_eq!((k.samples)().len(), 2);
    }
}

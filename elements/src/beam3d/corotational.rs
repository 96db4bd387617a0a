//! `beam3d` with `geometry = "corotational"`: finite 3-D rotations and displacements, small
//! strains. The kinematics are those of the 3-D corotational element of Battini & Pacoste
//! (CMAME 191, 2002, §2–3; after Crisfield, CMAME 81, 1990, and Nour-Omid & Rankin, CMAME 93,
//! 1991), around a *local linear Euler–Bernoulli* (or Timoshenko) element; the code is ours.
//!
//! # Kinematics
//!
//! Nodes 1, 2 at `X_i` (reference) with displacements `u_i` and nodal rotations
//! `R_i = exp([ψ_i]×)` (the finite-rotation scheme of [`railfem_framework::rotation`]);
//! `R₀ = [e₁ e₂ e₃]` holds the element's local axes at the reference (the linear beam's,
//! [`super::local_axes`]), so the nodal triads are `R_i·R₀`.
//!
//! * Corotated frame `R_r = [r₁ r₂ r₃]`: `r₁ = (x₂ − x₁)/l_n` with `x_i = X_i + u_i`,
//!   `l_n = |x₂ − x₁|`; `q_i = R_i·e₂`, `q = ½(q₁ + q₂)`, `r₃ = r₁ × q/|r₁ × q|`,
//!   `r₂ = r₃ × r₁`.
//! * Local deformations `p_l = [ū, θ̄₁, θ̄₂]` (7): `ū = l_n − l₀`,
//!   `θ̄_i = log(R_rᵀ·R_i·R₀)` — the rotation of each end relative to the chord frame.
//! * Local forces `f_l = K_l·p_l` of the linear element: `EA/l₀` on `ū`,
//!   `GJ/l₀·[[1,−1],[−1,1]]` on the twist `θ̄_ix`, and per bending plane
//!   `EI/(l₀(1+Φ))·[[4+Φ, 2−Φ], [2−Φ, 4+Φ]]` on `(θ̄₁, θ̄₂)` (the end-moment block of the
//!   Hermite/Timoshenko beam with the chord as reference).
//!
//! # Variations (derived here; equivalent to Battini–Pacoste's `G`, `P`, `B` matrices)
//!
//! With spatial spins `δθ_i` (`δR_i = [δθ_i]×·R_i`) and `δR_r = [δω_r]×·R_r`:
//! `δR̄_i·R̄_iᵀ = [R_rᵀ(δθ_i − δω_r)]×`, so `δθ̄_i = T⁻¹(θ̄_i)·R_rᵀ(δθ_i − δω_r)` with `T` the
//! left Jacobian ([`railfem_framework::rotation::spin_from_rotation_vector`]). In corotated
//! components `ω̄ = R_rᵀ·δω_r` (from `δr_k = δω_r × r_k` and the definition of `r₃`):
//!
//! ```text
//! ω̄₂ = −r₃·(δu₂ − δu₁)/l_n,   ω̄₃ = r₂·(δu₂ − δu₁)/l_n,
//! ω̄₁ = [½·Σ_i (q_i × r₃)·δθ_i − q̄₁·r₃·(δu₂ − δu₁)/l_n] / q̄₂,   q̄_k = r_k·q,
//! ```
//!
//! and `δū = r₁·(δu₂ − δu₁)`. The resisting force is `f = Bᵀ·f_l` assembled from these
//! forms (`resisting_force`): with `m̂_i = T⁻ᵀ(θ̄_i)·m̄_i` (the local end moments made
//! conjugate to the local spin) and `s = m̂₁ + m̂₂`, node `i` receives `R_r·m̂_i` and
//! `−s₁/(2q̄₂)·(q_i × r₃)` as moment and `∓(N·r₁ + (s₁q̄₁/q̄₂ + s₂)·r₃/l_n − s₃·r₂/l_n)` as
//! force (minus at node 1). Everything is conjugate to the spatial spin, as the scheme
//! requires.
//!
//! # Tangent
//!
//! The consistent tangent `K = ∂f/∂d` (material part `Bᵀ·K_l·B` *and* every geometric
//! term: the variation of `r₁, R_r, T⁻¹, q`) is the exact derivative of the same function,
//! taken column by column in forward mode ([`railfem_framework::dual`]): the translation `u_i` is seeded
//! with a unit direction, the rotation with `R_i + ε·[e]×·R_i` (the spin variation), so each
//! column is exact to round-off — no finite-difference step. It is unsymmetric away from
//! equilibrium (spatial spins are not additive coordinates), so the element declares an
//! unsymmetric tangent.
//!
//! # Properties and limits
//!
//! * Rigid-body motion of any size gives no force: `p_l` is invariant under
//!   `x ↦ Q·x + c`, `R_i ↦ Q·R_i` (checked by the conformance kit at 1 rad about a skew axis).
//! * Strains are small (the local element is linear); the torsion–bending coupling of
//!   large twist (Wagner terms, warping) is not modelled.
//! * `l_n` must stay positive; the two end triads must not turn the local `y` axes so far
//!   that `r₁ × q` vanishes (`q` parallel to the chord), which needs a relative twist of the
//!   ends near π — far beyond small strain.
//! * Mass: translational only, in global axes and constant (so it is exact under any
//!   rotation): `mass = "lumped"` gives `ρAl₀/2` per node and direction, `"consistent"`
//!   the linear-interpolation bar mass `ρAl₀/6·[[2,1],[1,2]]` per direction. The rotational
//!   DOFs are massless (rotary inertia of slender sections neglected), which keeps the
//!   spatial-vector update of angular velocity out of the inertia forces
//!   ([`railfem_solvers`'s driver] documents the scheme). The transverse mass is thus not the
//!   cubic Hermite one: for vibration the element needs about twice the mesh of the linear
//!   consistent beam for the same frequency accuracy.
//! * Nodes must have the global axes (not carried by a moving frame).

use super::{support, Beam3dParams, BeamSection, Mat12};
use nalgebra::{DMatrix, Vector3};
use railfem_framework::dual::{self, Dual, Scalar, M3, V3};
use railfem_framework::element::{
    Element, ElementError, ElementProperties, NodeDofs, StepContext, TrialState,
};
use railfem_framework::rotation;
use railfem_framework::serde_json;

/// The corotational beam. Build it through `beam3d` with `geometry = "corotational"`.
#[derive(Debug, Clone)]
pub struct Beam3dCorotational {
    params: Beam3dParams,
    conn: [NodeDofs; 2],
    /// Reference positions (m).
    x: [V3<f64>; 2],
    /// Reference length (m).
    l0: f64,
    /// Columns: local axes at the reference, in global axes.
    r0: M3<f64>,
    /// Local 7×7 stiffness on `[ū, θ̄₁, θ̄₂]`.
    kl: [[f64; 7]; 7],
    /// Constant translational mass in global axes.
    m: Mat12,
    /// Trial state.
    u: [f64; 12],
    f: [f64; 12],
    k: Mat12,
    local: [f64; 7],
    deform: [f64; 7],
}

/// Local 7×7 stiffness on `[ū, θ̄₁ₓ, θ̄₁ᵧ, θ̄₁_z, θ̄₂ₓ, θ̄₂ᵧ, θ̄₂_z]` (see the module doc).
fn local_stiffness(s: &BeamSection, l: f64) -> [[f64; 7]; 7] {
    let mut k = [[0.0; 7]; 7];
    k[0][0] = s.e * s.a / l;
    let gj = s.g * s.j / l;
    k[1][1] = gj;
    k[4][4] = gj;
    k[1][4] = -gj;
    k[4][1] = -gj;
    for (axis, ei, phi) in [(1, s.e * s.iy, s.phi_xz(l)), (2, s.e * s.iz, s.phi_xy(l))] {
        let c = ei / (l * (1.0 + phi));
        let (a, b) = (1 + axis, 4 + axis);
        k[a][a] = c * (4.0 + phi);
        k[b][b] = c * (4.0 + phi);
        k[a][b] = c * (2.0 - phi);
        k[b][a] = c * (2.0 - phi);
    }
    k
}

fn m3<S: Scalar>(m: &nalgebra::Matrix3<f64>) -> M3<S> {
    std::array::from_fn(|i| std::array::from_fn(|j| S::c(m[(i, j)])))
}

impl Beam3dCorotational {
    /// The corotational beam from a validated linear beam's data: its parameters, nodes,
    /// reference positions and local axes (rows = local x, y, z, [`super::local_axes`]).
    pub(super) fn new(
        params: Beam3dParams,
        nodes: [usize; 2],
        xi: Vector3<f64>,
        xj: Vector3<f64>,
        axes: &nalgebra::Matrix3<f64>,
        lumped: bool,
    ) -> Self {
        let l0 = (xj - xi).norm();
        let r0: M3<f64> = m3(&axes.transpose());
        let sec = BeamSection::from_params(&params);
        let kl = local_stiffness(&sec, l0);
        let total = params.rho * params.A * l0;
        let mut m = Mat12::zeros();
        for d in 0..3 {
            let (i, j) = (d, 6 + d);
            if lumped {
                m[(i, i)] = 0.5 * total;
                m[(j, j)] = 0.5 * total;
            } else {
                m[(i, i)] = total / 3.0;
                m[(j, j)] = total / 3.0;
                m[(i, j)] = total / 6.0;
                m[(j, i)] = total / 6.0;
            }
        }
        let mut e = Beam3dCorotational {
            params,
            conn: [NodeDofs::all(nodes[0]), NodeDofs::all(nodes[1])],
            x: [xi.into(), xj.into()],
            l0,
            r0,
            kl,
            m,
            u: [0.0; 12],
            f: [0.0; 12],
            k: Mat12::zeros(),
            local: [0.0; 7],
            deform: [0.0; 7],
        };
        e.evaluate();
        e
    }

    /// Reference length (m).
    pub fn length(&self) -> f64 {
        self.l0
    }

    /// Local forces `f_l = K_l·p_l` at the trial state (N, N·m).
    pub fn local_forces(&self) -> [f64; 7] {
        self.local
    }

    /// Local deformations `p_l = [ū, θ̄₁, θ̄₂]` at the trial state (m, rad).
    pub fn local_deformations(&self) -> [f64; 7] {
        self.deform
    }

    /// Strain energy of the local linear element at the trial state,
    /// `½·p_lᵀ·K_l·p_l = ½·p_l·f_l` (J): the elastic energy the element stores, for energy
    /// checks of dynamic runs.
    pub fn strain_energy(&self) -> f64 {
        0.5 * self
            .deform
            .iter()
            .zip(&self.local)
            .map(|(a, b)| a * b)
            .sum::<f64>()
    }

    /// The resisting force (element order) and the local forces for nodal displacements
    /// `u_i` and rotation matrices `R_i`.
    fn force<S: Scalar>(&self, u: &[V3<S>; 2], rg: &[M3<S>; 2]) -> ([S; 12], [S; 7], [S; 7]) {
        let x: [V3<S>; 2] = std::array::from_fn(|i| {
            let xr: V3<S> = std::array::from_fn(|k| S::c(self.x[i][k]));
            dual::add(&xr, &u[i])
        });
        let d = dual::sub(&x[1], &x[0]);
        let ln = dual::dot(&d, &d).sqrt();
        let r1 = dual::scale(S::c(1.0) / ln, &d);
        let r0: M3<S> = std::array::from_fn(|i| std::array::from_fn(|j| S::c(self.r0[i][j])));
        let e2 = dual::column(&r0, 1);
        let qi = [dual::mul_v(&rg[0], &e2), dual::mul_v(&rg[1], &e2)];
        let q = dual::scale(S::c(0.5), &dual::add(&qi[0], &qi[1]));
        let r3 = dual::unit(&dual::cross(&r1, &q));
        let r2 = dual::cross(&r3, &r1);
        let rr = dual::from_columns(&r1, &r2, &r3);
        let theta: [V3<S>; 2] =
            std::array::from_fn(|i| dual::log(&dual::mul_tn(&rr, &dual::mul(&rg[i], &r0))));
        let pl = [
            ln - S::c(self.l0),
            theta[0][0],
            theta[0][1],
            theta[0][2],
            theta[1][0],
            theta[1][1],
            theta[1][2],
        ];
        let mut fl = [S::c(0.0); 7];
        for a in 0..7 {
            for b in 0..7 {
                if self.kl[a][b] != 0.0 {
                    fl[a] = fl[a] + S::c(self.kl[a][b]) * pl[b];
                }
            }
        }
        // Moments conjugate to the local spins, and their sum (the chord-frame spin's load).
        let mh: [V3<S>; 2] = std::array::from_fn(|i| {
            let m = [fl[1 + 3 * i], fl[2 + 3 * i], fl[3 + 3 * i]];
            dual::inv_jacobian_times(&theta[i], &m, true)
        });
        let s = dual::add(&mh[0], &mh[1]);
        let (q1, q2) = (dual::dot(&r1, &q), dual::dot(&r2, &q));
        // Force on node 2 (node 1 gets the opposite): N·r₁ + (s₁q̄₁/q̄₂ + s₂)/l_n·r₃ − s₃/l_n·r₂.
        let c3 = (s[0] * q1 / q2 + s[1]) / ln;
        let fu2 = dual::add(
            &dual::add(&dual::scale(fl[0], &r1), &dual::scale(c3, &r3)),
            &dual::scale(-(s[2] / ln), &r2),
        );
        let mut f = [S::c(0.0); 12];
        for k in 0..3 {
            f[k] = -fu2[k];
            f[6 + k] = fu2[k];
        }
        let c1 = -(s[0] / (S::c(2.0) * q2));
        for i in 0..2 {
            let m = dual::add(
                &dual::mul_v(&rr, &mh[i]),
                &dual::scale(c1, &dual::cross(&qi[i], &r3)),
            );
            for k in 0..3 {
                f[6 * i + 3 + k] = m[k];
            }
        }
        (f, fl, pl)
    }

    /// Force, local forces and the exact tangent at `self.u`.
    fn evaluate(&mut self) {
        let u: [V3<f64>; 2] = std::array::from_fn(|i| std::array::from_fn(|k| self.u[6 * i + k]));
        let rg: [nalgebra::Matrix3<f64>; 2] = std::array::from_fn(|i| {
            rotation::exp(&Vector3::new(
                self.u[6 * i + 3],
                self.u[6 * i + 4],
                self.u[6 * i + 5],
            ))
        });
        let (f, fl, pl) = self.force::<f64>(&u, &[m3(&rg[0]), m3(&rg[1])]);
        self.f = f;
        self.local = fl;
        self.deform = pl;
        for j in 0..12 {
            let (node, comp, rot) = (j / 6, j % 3, j % 6 >= 3);
            let ud: [V3<Dual>; 2] = std::array::from_fn(|i| {
                std::array::from_fn(|k| {
                    let seed = !rot && i == node && k == comp;
                    Dual::new(u[i][k], if seed { 1.0 } else { 0.0 })
                })
            });
            let rd: [M3<Dual>; 2] = std::array::from_fn(|i| {
                let dr = if rot && i == node {
                    rotation::skew(&Vector3::ith(comp, 1.0)) * rg[i]
                } else {
                    nalgebra::Matrix3::zeros()
                };
                std::array::from_fn(|a| {
                    std::array::from_fn(|b| Dual::new(rg[i][(a, b)], dr[(a, b)]))
                })
            });
            let (fd, _, _) = self.force::<Dual>(&ud, &rd);
            for i in 0..12 {
                self.k[(i, j)] = fd[i].d;
            }
        }
    }
}

impl Element for Beam3dCorotational {
    fn kind(&self) -> &str {
        "beam3d"
    }

    fn connectivity(&self) -> &[NodeDofs] {
        &self.conn
    }

    fn properties(&self) -> ElementProperties {
        let has_mass = self.params.rho > 0.0;
        ElementProperties {
            linear: false,
            constant_mass: true,
            constant_damping: true,
            has_mass,
            has_damping: false,
            symmetric: false,
            connectivity_may_change: false,
            objective: true,
            declared_mass: has_mass.then_some(self.params.rho * self.params.A * self.l0),
            finite_rotations: true,
        }
    }

    fn advance(&mut self, ctx: &StepContext) -> Result<bool, ElementError> {
        for nd in &self.conn {
            if ctx.nodes.get(nd.node).is_some_and(|k| k.carried) {
                return Err(ElementError::Invalid(
                    "a corotational beam3d needs nodes with the global axes, not nodes carried by a moving frame; use geometry = \"linear\" there".into(),
                ));
            }
        }
        Ok(false)
    }

    fn update(&mut self, trial: &TrialState) -> Result<(), ElementError> {
        support::check_trial(trial, 12)?;
        self.u.copy_from_slice(trial.disp);
        self.evaluate();
        let d = dual::sub(
            &std::array::from_fn(|k| self.x[1][k] + self.u[6 + k]),
            &std::array::from_fn(|k| self.x[0][k] + self.u[k]),
        );
        if dual::dot(&d, &d).sqrt() <= 1e-9 * self.l0 {
            return Err(ElementError::Invalid(
                "the corotational beam's ends met (current length zero); reduce the load step"
                    .into(),
            ));
        }
        if self.f.iter().any(|v| !v.is_finite()) || self.k.iter().any(|v| !v.is_finite()) {
            return Err(ElementError::NonFinite {
                what: "corotational beam force or tangent (end triads twisted by π relative to each other?)".into(),
            });
        }
        Ok(())
    }

    fn resisting_force(&self, f: &mut [f64]) {
        f.copy_from_slice(&self.f);
    }

    fn tangent_stiffness(&self, k: &mut DMatrix<f64>) {
        k.copy_from(&self.k);
    }

    fn mass(&self, m: &mut DMatrix<f64>) {
        m.copy_from(&self.m);
    }

    fn output_names(&self) -> Vec<String> {
        ["N", "T", "My_i", "Mz_i", "My_j", "Mz_j"]
            .iter()
            .map(|s| s.to_string())
            .collect()
    }

    fn output_units(&self) -> Vec<String> {
        ["N", "N·m", "N·m", "N·m", "N·m", "N·m"]
            .iter()
            .map(|s| s.to_string())
            .collect()
    }

    /// Axial force (tension positive), twisting moment and the end moments about the
    /// corotated local y and z axes, conjugate to the end rotations relative to the chord
    /// (N, N·m).
    fn outputs(&self, out: &mut Vec<f64>) {
        let l = &self.local;
        out.extend_from_slice(&[l[0], l[4], l[2], l[3], l[5], l[6]]);
    }

    fn parameters(&self) -> serde_json::Value {
        serde_json::to_value(&self.params).unwrap_or(serde_json::Value::Null)
    }

    fn as_any(&self) -> Option<&dyn std::any::Any> {
        Some(self)
    }
}

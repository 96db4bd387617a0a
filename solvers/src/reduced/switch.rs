//! Switching a reduced block between its full and its reduced form: the modal projection
//! one way, the expansion the other, and the energy a projection leaves behind.
//!
//! # Full → reduced
//!
//! The boundary keeps its values; the modal coordinates are the `M_II`-orthogonal
//! projection of what the constraint modes do not carry,
//!
//! `η = Φᵀ·M_II·(q_I − Ψ·q_B)`, and the same for velocities and accelerations,
//!
//! which is the choice of `η` that makes the residual `e = q_I − Ψ·q_B − Φ·η` smallest in
//! the `M_II` norm (`Φᵀ·M_II·Φ = I`). The residual is the part of the interior's motion in
//! the modes above the cut-off.
//!
//! # The energy the projection leaves behind
//!
//! Write the full state as `q = T·q̂ + [0; e]` and `q̇ = T·q̂̇ + [0; e_v]`. The energy
//! `E = ½·q̇ᵀ·M·q̇ + ½·qᵀ·K·q` splits as `E = Ê + E_res` with `Ê = ½·q̂̇ᵀ·M̂·q̂̇ + ½·q̂ᵀ·K̂·q̂`
//! and
//!
//! `E_res = ½·eᵀ·K_II·e + ½·e_vᵀ·M_II·e_v + q̇_Bᵀ·(M_BI + Ψᵀ·M_II)·e_v`.
//!
//! The cross terms vanish elsewhere: `(T·q̂)ᵀ·K·[0; e] = q_Bᵀ·(K_BI + Ψᵀ·K_II)·e + ηᵀ·Ω²·
//! Φᵀ·M_II·e = 0` by the definition of `Ψ` and the projection (`Φᵀ·M_II·e = 0`), and
//! `(T·q̂̇)ᵀ·M·[0; e_v]` keeps only its boundary part, the last term (the mass coupling
//! of the boundary's motion with the interior's motion above the cut-off). So a switch
//! to the reduced form removes exactly `E_res`, the stated tolerance of the energy
//! ledger at a switch, computed from the projection's residual by
//! [`CraigBampton::to_reduced`]. The expansion back adds and removes nothing: `T·q̂`
//! has the energy `Ê` by the definition of `M̂` and `K̂`.

use super::CraigBampton;
use nalgebra::DVector;

/// A block's state in reduced coordinates `[q_B, η]`.
#[derive(Debug, Clone, PartialEq)]
pub struct ReducedState {
    /// Displacements `q̂`.
    pub q: DVector<f64>,
    /// Velocities `q̂̇`.
    pub v: DVector<f64>,
    /// Accelerations `q̂̈`.
    pub a: DVector<f64>,
}

/// The energy a switch to the reduced form leaves behind (J), from the projection's
/// residual (module documentation).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Discarded {
    /// `½·eᵀ·K_II·e`: strain energy of the displacement residual.
    pub strain: f64,
    /// `½·e_vᵀ·M_II·e_v`: kinetic energy of the velocity residual.
    pub kinetic: f64,
    /// `q̇_Bᵀ·(M_BI + Ψᵀ·M_II)·e_v`: the boundary's kinetic coupling with it.
    pub coupling: f64,
}

impl Discarded {
    /// `E_res`, the full energy less the reduced energy (J).
    pub fn total(&self) -> f64 {
        self.strain + self.kinetic + self.coupling
    }
}

/// Full energy `½·vᵀ·A_v·v + ½·qᵀ·A_q·q` with dense matrices (J): the ledger's energy
/// of a reduced state with `M̂`, `K̂`.
pub fn dense_energy(
    m: &nalgebra::DMatrix<f64>,
    k: &nalgebra::DMatrix<f64>,
    q: &DVector<f64>,
    v: &DVector<f64>,
) -> f64 {
    0.5 * v.dot(&(m * v)) + 0.5 * q.dot(&(k * q))
}

impl CraigBampton {
    /// `[q_B; Φᵀ·M_II·(q_I − Ψ·q_B)]` of a full vector (length `n`) and the interior
    /// residual `e = q_I − Ψ·q_B − Φ·η`.
    fn project(&self, x: &[f64]) -> (DVector<f64>, DVector<f64>) {
        let split = self.split();
        let nb = split.boundary.len();
        let xb = DVector::from_iterator(nb, split.boundary.iter().map(|&i| x[i]));
        let xi = DVector::from_iterator(split.interior.len(), split.interior.iter().map(|&i| x[i]));
        let d = xi - &self.psi * &xb;
        let mut md = DVector::zeros(d.len());
        self.m_ii.mul_vec(d.as_slice(), md.as_mut_slice());
        let eta = self.phi.transpose() * md;
        let e = d - &self.phi * &eta;
        let mut out = DVector::zeros(nb + eta.len());
        out.rows_mut(0, nb).copy_from(&xb);
        out.rows_mut(nb, eta.len()).copy_from(&eta);
        (out, e)
    }

    /// Full → reduced: the state `(q, v, a)` of the block's DOFs mapped by the modal
    /// projection, with the energy that the mapping leaves behind.
    pub fn to_reduced(&self, q: &[f64], v: &[f64], a: &[f64]) -> (ReducedState, Discarded) {
        let (qh, e) = self.project(q);
        let (vh, e_v) = self.project(v);
        let (ah, _) = self.project(a);
        let ni = e.len();
        let mut ke = DVector::zeros(ni);
        self.k_ii.mul_vec(e.as_slice(), ke.as_mut_slice());
        let mut me = DVector::zeros(ni);
        self.m_ii.mul_vec(e_v.as_slice(), me.as_mut_slice());
        // (M·T_B·v_B) restricted to the interior = (M_IB + M_II·Ψ)·v_B.
        let nb = self.split().boundary.len();
        let tb = self.basis.columns(0, nb) * vh.rows(0, nb);
        let mut mtb = vec![0.0; tb.len()];
        self.m.mul_vec(tb.as_slice(), &mut mtb);
        let coupling: f64 = self
            .split()
            .interior
            .iter()
            .zip(e_v.iter())
            .map(|(&i, ev)| mtb[i] * ev)
            .sum();
        (
            ReducedState {
                q: qh,
                v: vh,
                a: ah,
            },
            Discarded {
                strain: 0.5 * e.dot(&ke),
                kinetic: 0.5 * e_v.dot(&me),
                coupling,
            },
        )
    }

    /// Reduced → full: `(T·q̂, T·q̂̇, T·q̂̈)` on the block's DOFs.
    pub fn to_full(&self, s: &ReducedState) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
        (
            self.expand(s.q.as_slice()),
            self.expand(s.v.as_slice()),
            self.expand(s.a.as_slice()),
        )
    }

    /// `Ê`, the energy of a reduced state with `M̂` and `K̂` (J).
    pub fn energy(&self, s: &ReducedState) -> f64 {
        dense_energy(&self.m_hat, &self.k_hat, &s.q, &s.v)
    }
}

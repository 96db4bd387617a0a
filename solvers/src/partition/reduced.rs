//! Reduced blocks: a block of the partitioned solver whose interior is constrained to its
//! boundary's static answer plus a few fixed-interface modes (Craig–Bampton), for the far
//! field under ground motion ([`crate::reduced`]).
//!
//! **The constraint.** A reduced block's interior increments are
//! `Δq_I = Ψ·Δq_B + Φ·Δη`, with `Ψ` (`n_I × n_B`) and `Φ` (`n_I × p`) given by the caller
//! ([`ReducedBasis`], usually from [`crate::reduced::CraigBampton`] of the block's own
//! `K`, `M`). With `T = [[I, 0], [Ψ, Φ]]` on the block's `[B, I]` and `A` the step's
//! effective matrix, Galerkin's method asks that the residual be orthogonal to the
//! admissible increments: `Tᵀ·(r − A·T·Δq̂) = 0`. Its rows are those of `B`
//! (`r̂_B = r_B + Ψᵀ·r_I`) and of `η` (`r̂_η = Φᵀ·r_I`), and the block's part of `Tᵀ·A·T` is
//!
//! ```text
//! Â_BB = A_BB + A_BI·Ψ + Ψᵀ·A_IB + Ψᵀ·A_II·Ψ,
//! Â_ηB = Φᵀ·(A_IB + A_II·Ψ) = Â_Bηᵀ,      Â_ηη = Φᵀ·A_II·Φ
//! ```
//!
//! (`A` symmetric on the block, as the partition requires). Eliminating `η`, which only
//! the block's boundary sees, gives the top system the dense `|B| × |B|` matrix
//! `Â_BB − Â_Bη·Â_ηη⁻¹·Â_ηB` in place of the full block's `A_BB − A_BI·A_II⁻¹·A_IB`. The
//! partition subtracts a block's *correction* `C` from `A_BB` (module documentation of
//! [`crate::partition`]), so a reduced block's correction is
//!
//! ```text
//! C_red = Â_Bη·Â_ηη⁻¹·Â_ηB − (A_BI·Ψ + Ψᵀ·A_IB + Ψᵀ·A_II·Ψ),
//! ```
//!
//! formed once per `A` (a new `Δt`), and everything else of the top system (the top
//! chain's groups included, [`crate::top_chain`]) takes it as it takes `C`. A solve
//! `(A + V)·x = b` then becomes the Galerkin solve `Tᵀ·(A + V)·T·x̂ = Tᵀ·b`, `x = T·x̂`:
//! the forward pass condenses `b_I` onto the boundary as
//! `c = −Ψᵀ·b_I + Â_Bη·Â_ηη⁻¹·Φᵀ·b_I` (subtracted from `b_B`, as `C·…` is for a full
//! block), and the back pass is `x_η = Â_ηη⁻¹·(Φᵀ·b_I − Â_ηB·x_B)`,
//! `x_I = Ψ·x_B + Φ·x_η`. The block's sparse factor is neither solved with nor needed
//! (it is kept, so returning the block to full form costs no factorization).
//!
//! **In a Newton iteration** the right-hand side is the full residual `r` (the block's
//! elements assembled as usual), so the iteration solves the reduced model exactly:
//! for a linear far field and a state on the subspace, `Tᵀ·r` is
//! `f̂_ext − K̂·q̂ − Ĉ·q̂̇ − M̂·q̂̈`, and the interior rows `r_I` left over are the constraint's
//! reactions, which do no work on an admissible increment (`r_Iᵀ·Δq_I = 0` once `Tᵀ·r = 0`
//! — the energy ledger is unchanged by them). The driver's convergence test uses
//! [`Partitioned::project_reduced_rows`], the residual in the reduced coordinates.
//!
//! Not here: the interior's elements still enter the residual assembly (the saving is
//! the block's two sparse triangular solves per iteration, and its share of the top
//! system's fill). A reduced block may carry no variable element (no promoted equation);
//! reduced blocks are not shared among ranks.

use super::Partitioned;
use crate::linear::SolverError;
use crate::modal::symmetrize;
use nalgebra::{Cholesky, DMatrix, Dyn};
use railfem_framework::sparse::CscMatrix;
use std::sync::Arc;

/// The constraint of a reduced block: `Δq_I = Ψ·Δq_B + Φ·Δη`, with rows in the order of
/// the block's interior ([`Partitioned::block_interior`]) and `Ψ`'s columns in the order
/// of its boundary ([`Partitioned::block_boundary`]).
#[derive(Debug, Clone, PartialEq)]
pub struct ReducedBasis {
    /// Constraint modes `Ψ` (`n_I × n_B`).
    pub psi: DMatrix<f64>,
    /// Kept fixed-interface modes `Φ` (`n_I × p`).
    pub phi: DMatrix<f64>,
}

/// A reduced block's basis and its condensation for the current `A`.
pub(super) struct Reduced {
    pub(super) basis: Arc<ReducedBasis>,
    pub(super) cond: Option<Condensed>,
}

/// What a reduced block gives the top system and its passes, for one `A`.
pub(super) struct Condensed {
    /// `C_red` (module documentation), column-major `|B| × |B|`.
    pub(super) correction: Vec<f64>,
    /// `Â_ηB` (`p × |B|`).
    eta_b: DMatrix<f64>,
    /// The Cholesky factor of `Â_ηη` (`None` without modes).
    eta_eta: Option<Cholesky<f64, Dyn>>,
}

impl Reduced {
    /// `C_red`, `Â_ηB` and `Â_ηη` of block interior `all` with `boundary` from the
    /// constant effective matrix `a` (module documentation).
    pub(super) fn condense(
        &mut self,
        a: &CscMatrix,
        all: &[usize],
        boundary: &[usize],
    ) -> Result<(), SolverError> {
        let (psi, phi) = (&self.basis.psi, &self.basis.phi);
        let (ni, nb, p) = (all.len(), boundary.len(), phi.ncols());
        // A_IB (ni × nb) and A_II·[Ψ Φ] (ni × (nb + p)), one pass over the interior columns.
        let mut a_ib = DMatrix::<f64>::zeros(ni, nb);
        let mut a_psi = DMatrix::<f64>::zeros(ni, nb);
        let mut a_phi = DMatrix::<f64>::zeros(ni, p);
        for (j, &g) in all.iter().enumerate() {
            for q in a.col_ptr[g]..a.col_ptr[g + 1] {
                let (r, v) = (a.row_idx[q], a.values[q]);
                if let Ok(l) = all.binary_search(&r) {
                    // A_II(l, j) times row j of Ψ and Φ.
                    for k in 0..nb {
                        a_psi[(l, k)] += v * psi[(j, k)];
                    }
                    for k in 0..p {
                        a_phi[(l, k)] += v * phi[(j, k)];
                    }
                } else {
                    // A_IB(j, r) = A_BI(r, j) for a symmetric A.
                    let k = boundary.binary_search(&r).map_err(|_| {
                        SolverError::Failed(format!(
                            "reduced block: equation {r} couples to the interior but is not on its boundary"
                        ))
                    })?;
                    a_ib[(j, k)] += v;
                }
            }
        }
        // A_BI·Ψ + Ψᵀ·A_IB + Ψᵀ·A_II·Ψ, symmetrized.
        let bi_psi = a_ib.transpose() * psi;
        let psi_a_psi = psi.transpose() * &a_psi;
        let mut extra = &bi_psi + bi_psi.transpose() + psi_a_psi;
        symmetrize(&mut extra);
        let eta_b = phi.transpose() * (&a_ib + &a_psi);
        let mut eta_eta = phi.transpose() * &a_phi;
        symmetrize(&mut eta_eta);
        let (correction, eta_eta) = if p == 0 {
            (-extra, None)
        } else {
            let chol = Cholesky::new(eta_eta).ok_or_else(|| {
                SolverError::Failed(
                    "reduced block: Φᵀ·A_II·Φ is not positive definite (modes not independent)"
                        .into(),
                )
            })?;
            let s = chol.solve(&eta_b);
            let mut c = eta_b.transpose() * s - extra;
            symmetrize(&mut c);
            (c, Some(chol))
        };
        self.cond = Some(Condensed {
            correction: correction.as_slice().to_vec(),
            eta_b,
            eta_eta,
        });
        Ok(())
    }

    fn cond(&self) -> &Condensed {
        self.cond.as_ref().expect("reduced block condensed")
    }

    /// The forward pass: `c = −Ψᵀ·b_I + Â_Bη·Â_ηη⁻¹·Φᵀ·b_I`, to be subtracted from `b_B`.
    pub(super) fn forward(&self, all: &[usize], rhs: &[f64]) -> Vec<f64> {
        let b_i = nalgebra::DVector::from_iterator(all.len(), all.iter().map(|&i| rhs[i]));
        // `tr_mul`: the products with Ψᵀ, Φᵀ without forming the transposes (per solve).
        let mut c = -self.basis.psi.tr_mul(&b_i);
        let cond = self.cond();
        if let Some(chol) = &cond.eta_eta {
            let s = chol.solve(&self.basis.phi.tr_mul(&b_i));
            c += cond.eta_b.tr_mul(&s);
        }
        c.as_slice().to_vec()
    }

    /// The back pass of `columns` (each: the right-hand side, `None` for a zero one, and
    /// the boundary's `x_B`): `x_I = Ψ·x_B + Φ·Â_ηη⁻¹·(Φᵀ·b_I − Â_ηB·x_B)` into `z`,
    /// column `k` at `z[k·n_I..(k + 1)·n_I]`. The expansion of every column,
    /// `[Ψ Φ]·[x_B; x_η]`, is two matrix products of faer's (`n_I × (n_B + p)` times the
    /// columns), whose kernels use the processor's widest vector instructions: these
    /// products are most of what a reduced block's solve costs.
    pub(super) fn back(
        &self,
        all: &[usize],
        columns: &[(Option<&[f64]>, Vec<f64>)],
        z: &mut [f64],
    ) {
        use faer::linalg::matmul::matmul;
        use faer::{Accum, MatMut, MatRef, Par};
        let (ni, nc) = (all.len(), columns.len());
        let (psi, phi) = (&self.basis.psi, &self.basis.phi);
        let (nb, p) = (psi.ncols(), phi.ncols());
        let cond = self.cond();
        // x_B and x_η of each column, column-major.
        let mut x_b = Vec::with_capacity(nb * nc);
        let mut x_eta = Vec::with_capacity(p * nc);
        for (rhs, xb) in columns {
            x_b.extend_from_slice(xb);
            if let Some(chol) = &cond.eta_eta {
                let xb = nalgebra::DVector::from_column_slice(xb);
                let mut h = -(&cond.eta_b * &xb);
                if let Some(rhs) = rhs {
                    let b_i = nalgebra::DVector::from_iterator(ni, all.iter().map(|&i| rhs[i]));
                    h += phi.tr_mul(&b_i);
                }
                x_eta.extend_from_slice(chol.solve(&h).as_slice());
            }
        }
        let mut out = MatMut::from_column_major_slice_mut(&mut z[..ni * nc], ni, nc);
        let psi_m = MatRef::from_column_major_slice(psi.as_slice(), ni, nb);
        let xb_m = MatRef::from_column_major_slice(&x_b, nb, nc);
        matmul(out.as_mut(), Accum::Replace, psi_m, xb_m, 1.0, Par::Seq);
        if cond.eta_eta.is_some() && p > 0 {
            let phi_m = MatRef::from_column_major_slice(phi.as_slice(), ni, p);
            let xe_m = MatRef::from_column_major_slice(&x_eta, p, nc);
            matmul(out, Accum::Add, phi_m, xe_m, 1.0, Par::Seq);
        }
    }
}

impl Partitioned {
    /// Block `b`'s boundary: the top equations coupled to its interior (global, sorted).
    pub fn block_boundary(&self, b: usize) -> &[usize] {
        &self.blocks[b].boundary
    }

    /// Whether block `b` is reduced ([`Partitioned::set_reduced_block`]).
    pub fn block_reduced(&self, b: usize) -> bool {
        self.blocks[b].reduced.is_some()
    }

    /// Whether any block is reduced.
    pub fn has_reduced_blocks(&self) -> bool {
        self.blocks.iter().any(|b| b.reduced.is_some())
    }

    /// Reduces block `b` to `basis` (module documentation), or returns it to full form
    /// (`None`). Takes effect at the next factorization, which forms the block's reduced
    /// condensation (or uses its kept factor again). Refused (`Err` with the reason) across
    /// ranks, for a held block, for a block with promoted equations (a variable element on
    /// it), and for a basis whose sizes are not the block's.
    pub fn set_reduced_block(
        &mut self,
        b: usize,
        basis: Option<Arc<ReducedBasis>>,
    ) -> Result<(), String> {
        if self.comm.is_some() {
            return Err("reduced blocks are not shared among ranks".into());
        }
        let Some(blk) = self.blocks.get(b) else {
            return Err(format!("block {b} of {}", self.blocks.len()));
        };
        if let Some(basis) = &basis {
            let (ni, nb) = (blk.all.len(), blk.boundary.len());
            if basis.psi.shape() != (ni, nb) || basis.phi.nrows() != ni {
                return Err(format!(
                    "block {b} has {ni} interior and {nb} boundary equations; Ψ is {}×{} and Φ has {} rows",
                    basis.psi.nrows(),
                    basis.psi.ncols(),
                    basis.phi.nrows()
                ));
            }
            if blk.frozen {
                return Err(format!("block {b} is held and cannot be reduced"));
            }
            if !blk.promoted.is_empty() {
                return Err(format!(
                    "block {b} carries a variable element and cannot be reduced"
                ));
            }
        }
        let blk = &mut self.blocks[b];
        if blk.reduced.is_none() && basis.is_none() {
            return Ok(());
        }
        blk.reduced = basis.map(|basis| Reduced { basis, cond: None });
        self.constant_stale = true;
        self.top_factored = false;
        if let Some(chain) = self.chain.as_mut() {
            for g in chain.groups.iter_mut().filter(|g| g.blocks.contains(&b)) {
                g.cond = None;
                g.failed = false;
            }
        }
        Ok(())
    }

    /// The residual `r` in the reduced blocks' coordinates, in place, for a convergence
    /// test: each reduced block's boundary rows gain `Ψᵀ·r_I`, its first `p` interior
    /// rows become `Φᵀ·r_I` and the rest zero (the constraint's reactions). Nothing
    /// changes without reduced blocks.
    pub fn project_reduced_rows(&self, r: &mut [f64]) {
        for blk in self.blocks.iter() {
            let Some(red) = &blk.reduced else { continue };
            let r_i =
                nalgebra::DVector::from_iterator(blk.all.len(), blk.all.iter().map(|&i| r[i]));
            let to_b = red.basis.psi.tr_mul(&r_i);
            let to_eta = red.basis.phi.tr_mul(&r_i);
            for (&g, v) in blk.boundary.iter().zip(to_b.iter()) {
                r[g] += v;
            }
            for (k, &i) in blk.all.iter().enumerate() {
                r[i] = to_eta.get(k).copied().unwrap_or(0.0);
            }
        }
    }

    /// Forms the reduced condensation of every reduced block that has none for the
    /// current `A`; refuses a reduced block that a variable element acts on (`wanted`:
    /// the promoted equations of each block).
    pub(super) fn condense_reduced(
        &mut self,
        a: &CscMatrix,
        wanted: &[Vec<usize>],
    ) -> Result<(), SolverError> {
        for (b, blk) in self.blocks.iter_mut().enumerate() {
            let Some(red) = blk.reduced.as_mut() else {
                continue;
            };
            if !wanted[b].is_empty() {
                return Err(SolverError::Failed(format!(
                    "a variable element acts on reduced block {b} (equation {}); return it to full form first",
                    wanted[b][0]
                )));
            }
            if red.cond.is_none() {
                red.condense(a, &blk.all, &blk.boundary)?;
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests;

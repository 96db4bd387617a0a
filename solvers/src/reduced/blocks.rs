//! The driver's reduced blocks: a block of the partitioned solver switched to its
//! Craig–Bampton form between steps and back ([`crate::partition::ReducedBasis`],
//! `partition/reduced.rs`), with the state mapped and the energy the switch removes.
//!
//! **The state.** A linear far field moves about its static state `q₀` (self-weight, the
//! train at rest far away): with `d = q − q₀`, switching block `b` to reduced form keeps
//! `d_B` and projects the interior, `η = G⁻¹·Φᵀ·M_II·(d_I − Ψ·d_B)` with
//! `G = Φᵀ·M_II·Φ` (the identity for mass-normalized modes), the `η` that leaves the
//! smallest residual in the `M_II` norm ([`crate::reduced::switch`]); then
//! `q_I = q₀_I + Ψ·d_B + Φ·η`, and the same for `v` (about zero). The acceleration keeps
//! `a_B` and takes `a_I = Ψ·a_B + Φ·η̈` with `η̈` from the modal rows of the equation of
//! motion at the switch, `Φᵀ·(f_ext − f_int − C·v − M·a)_I = 0`: the reduced equation
//! `M̂·q̂̈ = f̂ − K̂·q̂ − Ĉ·q̂̇` solved for the modal accelerations, as the integrator's start
//! solves the full one. The projected `a` does not balance it (the projection drops the
//! motion above the cut-off, and with it the inertia that balanced the dropped forces).
//! Under generalized-α the full model's own `a_n` does not balance it either (the balance
//! holds at the weighted points; [`crate::energy`], *One step's residual*), and the
//! ledger's residual over the step from the switched state is close to the full model's
//! with either: 0.2362 J balanced, 0.2343 J projected, 0.2316 J with the block left
//! full (`tests/reduced_far_field.rs`, `the_ledger_closes_after_a_switch_as_it_does_full`).
//! `q₀`'s interior is the static answer to its boundary, `K_II·q₀_I = f_I − K_IB·q₀_B`, so the affine
//! subspace holds every static state of the far field exactly. Every later Newton
//! increment stays on it (the solve is the Galerkin one), and so do the integrator's
//! `v`, `a`, linear in the increments. The internal force of the committed state is
//! corrected by `K·Δq` (the interior's elements are linear).
//!
//! **The energy of a switch.** With `E = ½·vᵀ·M·v + ½·dᵀ·K·d` (the gravity's potential
//! cancels against `K·q₀ = f` on the interior rows), the switch changes `E` by
//! `½·Δvᵀ·M·(v + v') + ½·Δdᵀ·K·(d + d')`, `Δ` non-zero on the interior only:
//! [`Driver::reduce_block`] returns `E_res = E − E'`, the energy of the motion above the
//! cut-off that the projection drops (the library's closed form of it:
//! [`crate::reduced::CraigBampton::to_reduced`]). The energy ledger books the jump
//! ([`crate::energy::EnergyLedger::book_jump`]): its works over the jump, and the energy
//! removed in its own column — `E_res` plus the work of the loads other than the static
//! ones over the jump, `(f_ext − K·q₀)ᵀ·Δq` (the ground motion's). Returning to full form
//! is the identity on the state: it adds and removes nothing.

use super::{restrict, CraigBampton, ReducedError, Split};
use crate::driver::Driver;
use crate::driver::State;
use crate::modal::ModalOptions;
use crate::partition::ReducedBasis;
use nalgebra::{Cholesky, DMatrix, DVector, Dyn};
use railfem_framework::sparse::CscMatrix;
use std::sync::Arc;

impl Driver {
    /// The residual `r` in the reduced blocks' coordinates for the convergence test
    /// ([`crate::partition::Partitioned::project_reduced_rows`]); `None` without reduced
    /// blocks (the test reads `r` itself).
    pub(crate) fn reduced_residual(&self, r: &[f64]) -> Option<Vec<f64>> {
        let p = self.linear.partitioned()?;
        if !p.has_reduced_blocks() {
            return None;
        }
        let mut out = r.to_vec();
        p.project_reduced_rows(&mut out);
        Some(out)
    }

    /// Block `b`'s equations (interior and boundary, ascending) and its split in that
    /// local numbering; `None` without the partitioned solver or such a block.
    pub(crate) fn block_split_of(&self, b: usize) -> Option<(Vec<usize>, Split)> {
        let p = self.linear.partitioned()?;
        if b >= p.block_count() {
            return None;
        }
        let (interior, boundary) = (p.block_interior(b), p.block_boundary(b));
        let mut eqs: Vec<usize> = interior.iter().chain(boundary).copied().collect();
        eqs.sort_unstable();
        let local = |g: usize| eqs.binary_search(&g).expect("listed");
        let split = Split {
            interior: interior.iter().map(|&g| local(g)).collect(),
            boundary: boundary.iter().map(|&g| local(g)).collect(),
        };
        Some((eqs, split))
    }

    /// The Craig–Bampton reduction of the partitioned solver's block `b` from the
    /// model's constant `K`, `M`, `C` (the far field is linear; its interior holds no
    /// variable element): its interior and boundary as the partition split them, the modes
    /// up to `cutoff` (rad/s), each `ω²` converged to 1e-8 (`ω` to 5e-9, far inside the
    /// 1e-3 the band is kept to; the subspace iteration's default 1e-10 can take its 500
    /// iterations on a block of slab track with clustered modes). `None` without the
    /// partitioned solver or such a block.
    pub fn block_reduction(
        &self,
        b: usize,
        cutoff: f64,
    ) -> Option<Result<CraigBampton, ReducedError>> {
        let (eqs, split) = self.block_split_of(b)?;
        let a = &self.asm;
        Some(CraigBampton::build(
            &restrict(&a.k_const, &eqs),
            &restrict(&a.m_const, &eqs),
            Some(&restrict(&a.c_const, &eqs)),
            &split,
            cutoff,
            &ModalOptions {
                tolerance: 1e-8,
                ..Default::default()
            },
        ))
    }

    /// Switches block `b` to the reduced form `basis` (rows: its interior, columns of
    /// `Ψ`: its boundary, both in ascending order) about the static state `origin` (all
    /// equations; module documentation), and returns `E_res` (J), the energy the switch
    /// removed (negative: added). Refused (`Err` with the reason) without the partitioned
    /// solver, across ranks, for a held block or one a variable element acts on.
    pub fn reduce_block(
        &mut self,
        b: usize,
        basis: Arc<ReducedBasis>,
        origin: &[f64],
    ) -> Result<f64, String> {
        let n = self.neq();
        if origin.len() != n {
            return Err(format!(
                "the origin has {} entries, the model {n}",
                origin.len()
            ));
        }
        let p = self
            .linear
            .partitioned_mut()
            .ok_or("reduced blocks need the partitioned solver")?;
        if b >= p.block_count() {
            return Err(format!("block {b} of {}", p.block_count()));
        }
        if p.block_frozen(b) {
            return Err(format!("block {b} is held and cannot be reduced"));
        }
        let interior = p.block_interior(b).to_vec();
        let boundary = p.block_boundary(b).to_vec();
        p.set_reduced_block(b, Some(basis.clone()))?;
        self.linear.invalidate();
        let mut eqs: Vec<usize> = interior.iter().chain(&boundary).copied().collect();
        eqs.sort_unstable();
        let li: Vec<usize> = interior
            .iter()
            .map(|g| eqs.binary_search(g).expect("listed"))
            .collect();
        let m = restrict(&self.asm.m_const, &eqs);
        let k = restrict(&self.asm.k_const, &eqs);
        let m_ii = restrict(&m, &li);
        let (psi, phi) = (&basis.psi, &basis.phi);
        let ni = interior.len();
        let mut m_phi = DMatrix::<f64>::zeros(ni, phi.ncols());
        for j in 0..phi.ncols() {
            m_ii.mul_vec(phi.column(j).as_slice(), m_phi.column_mut(j).as_mut_slice());
        }
        let gram = (phi.transpose() * &m_phi).cholesky();
        // The projection of one field (`q − q₀`, `v` or `a`): the interior's new values.
        let project = |x: &[f64], x0: Option<&[f64]>| -> DVector<f64> {
            let rel = |g: usize| x[g] - x0.map_or(0.0, |o| o[g]);
            let x_b = DVector::from_iterator(boundary.len(), boundary.iter().map(|&g| rel(g)));
            let x_i = DVector::from_iterator(ni, interior.iter().map(|&g| rel(g)));
            let static_part = psi * &x_b;
            let mut out = static_part.clone();
            if let Some(g) = &gram {
                let eta = g.solve(&(m_phi.transpose() * (x_i - static_part)));
                out += phi * eta;
            }
            if let Some(o) = x0 {
                for (v, &g) in out.iter_mut().zip(&interior) {
                    *v += o[g];
                }
            }
            out
        };
        // The state before, for the energy ledger's booking of the jump.
        let before = self.energy.is_some().then(|| self.state.clone());
        let s = &mut self.state;
        let new_q = project(&s.q, Some(origin));
        let new_v = project(&s.v, None);
        // Δ and the sums d + d', v + v' on the block's equations.
        let ne = eqs.len();
        let (mut dq, mut dv) = (vec![0.0; ne], vec![0.0; ne]);
        let mut sum_d: Vec<f64> = eqs.iter().map(|&g| 2.0 * (s.q[g] - origin[g])).collect();
        let mut sum_v: Vec<f64> = eqs.iter().map(|&g| 2.0 * s.v[g]).collect();
        for (l, &g) in interior.iter().enumerate() {
            let at = li[l];
            dq[at] = new_q[l] - s.q[g];
            dv[at] = new_v[l] - s.v[g];
            sum_d[at] += dq[at];
            sum_v[at] += dv[at];
            s.q[g] = new_q[l];
            s.v[g] = new_v[l];
        }
        let (mut k_sum, mut m_sum, mut k_dq) = (vec![0.0; ne], vec![0.0; ne], vec![0.0; ne]);
        k.mul_vec(&sum_d, &mut k_sum);
        m.mul_vec(&sum_v, &mut m_sum);
        k.mul_vec(&dq, &mut k_dq);
        let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
        let change = 0.5 * dot(&dq, &k_sum) + 0.5 * dot(&dv, &m_sum);
        for (l, &g) in eqs.iter().enumerate() {
            s.f_int[g] += k_dq[l];
        }
        // The acceleration from the reduced equation of motion (module documentation).
        let c = restrict(&self.asm.c_const, &eqs);
        let new_a = balanced_acceleration(
            (&m, &c),
            (&li, &boundary),
            (psi, phi, gram.as_ref()),
            s,
            &eqs,
        );
        for (l, &g) in interior.iter().enumerate() {
            s.a[g] = new_a[l];
        }
        if let (Some(e), Some(before)) = (self.energy.as_mut(), before) {
            e.book_jump(&self.asm, &before, &self.state);
        }
        Ok(-change)
    }

    /// Splits the equations into the partitioned solver's blocks now, as its first
    /// factorization would (from the pattern of the constant tangent), so that blocks can
    /// be reduced before the first step; returns the number of blocks. Refused without the
    /// partitioned solver.
    pub fn prepare_blocks(&mut self) -> Result<usize, String> {
        let p = self
            .linear
            .partitioned_mut()
            .ok_or("reduced blocks need the partitioned solver")?;
        p.prepare(&self.asm.k_const);
        Ok(p.block_count())
    }

    /// Each block's interior equations (global, sorted; empty without the partitioned
    /// solver or before its split, [`Driver::prepare_blocks`]).
    pub fn partition_interiors(&self) -> Vec<Vec<usize>> {
        self.linear.partitioned().map_or(Vec::new(), |p| {
            (0..p.block_count())
                .map(|b| p.block_interior(b).to_vec())
                .collect()
        })
    }

    /// Block `b`'s interior and boundary equations, interior first (empty without the
    /// partitioned solver or such a block).
    pub fn block_interior_and_boundary(&self, b: usize) -> Vec<usize> {
        self.linear
            .partitioned()
            .filter(|p| b < p.block_count())
            .map_or(Vec::new(), |p| {
                p.block_interior(b)
                    .iter()
                    .chain(p.block_boundary(b))
                    .copied()
                    .collect()
            })
    }

    /// Returns block `b` to its full form (the state is already the full one: nothing is
    /// mapped). Refused without the partitioned solver.
    pub fn restore_block(&mut self, b: usize) -> Result<(), String> {
        let p = self
            .linear
            .partitioned_mut()
            .ok_or("reduced blocks need the partitioned solver")?;
        p.set_reduced_block(b, None)?;
        self.linear.invalidate();
        Ok(())
    }
}

/// The interior accelerations of a block just switched to reduced form, `Ψ·a_B + Φ·η̈`,
/// with `η̈` from the modal rows of the equation of motion at the switch (module
/// documentation): `Φᵀ·r_I = 0` with `r_I = f_ext,I − f_int,I − (C·v)_I − (M·a)_I`, the
/// state (`q`, `v`, `f_int`) already projected. `a_I = Ψ·a_B + Φ·η̈` makes
/// `Φᵀ·r_I = Φᵀ·r_I⁰ − G·η̈` (`r_I⁰` the residual with `η̈ = 0`, `G = Φᵀ·M_II·Φ`), so
/// `η̈ = G⁻¹·Φᵀ·r_I⁰`. The block's interior rows couple only to its own equations, so the
/// block's restricted `M` and `C` (on `eqs`) give them whole; `li` holds the interior's
/// positions in `eqs`, `boundary` the boundary's global equations.
fn balanced_acceleration(
    (m, c): (&CscMatrix, &CscMatrix),
    (li, boundary): (&[usize], &[usize]),
    (psi, phi, gram): (&DMatrix<f64>, &DMatrix<f64>, Option<&Cholesky<f64, Dyn>>),
    s: &State,
    eqs: &[usize],
) -> DVector<f64> {
    let a_b = DVector::from_iterator(boundary.len(), boundary.iter().map(|&g| s.a[g]));
    let static_part = psi * &a_b;
    let Some(gram) = gram else {
        return static_part;
    };
    // a⁰ on the block: the boundary's own, the interior's static answer to it.
    let mut a0: Vec<f64> = eqs.iter().map(|&g| s.a[g]).collect();
    for (l, &at) in li.iter().enumerate() {
        a0[at] = static_part[l];
    }
    let v: Vec<f64> = eqs.iter().map(|&g| s.v[g]).collect();
    let (mut ma, mut cv) = (vec![0.0; eqs.len()], vec![0.0; eqs.len()]);
    m.mul_vec(&a0, &mut ma);
    c.mul_vec(&v, &mut cv);
    let r0 = DVector::from_iterator(
        li.len(),
        li.iter().map(|&at| {
            let g = eqs[at];
            s.f_ext[g] - s.f_int[g] - cv[at] - ma[at]
        }),
    );
    let eta_dd = gram.solve(&phi.tr_mul(&r0));
    static_part + phi * eta_dd
}

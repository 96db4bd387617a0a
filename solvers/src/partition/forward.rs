//! Promotions by the forward pass: a block's condensation onto its promoted equations `P`
//! from the forward half of its base factor only ([`PromotionForm::Forward`]).
//!
//! With the block's base factor `P·A_II·Pᵀ = L·Lᵀ` (a permutation `P` and the simplicial
//! `L` of [`crate::compact_factor`]) write `Y = L⁻¹·P·E_P` (one column per promoted
//! equation) and `C_B = L⁻¹·P·A_IB`. Then `A_II⁻¹ = Pᵀ·L⁻ᵀ·L⁻¹·P`, and the quantities of the
//! module documentation of [`crate::partition`] are
//!
//! ```text
//! G   = E_Pᵀ·A_II⁻¹·E_P = Yᵀ·Y,
//! W_P = E_Pᵀ·A_II⁻¹·A_IB = Yᵀ·C_B,
//! x_I = A_II⁻¹·c + Z·G⁻¹·(x_P − y_P)  with  c = r_I − A_IB·x_B,  Z = A_II⁻¹·E_P:
//!       w = L⁻¹·P·c,  y_P = Yᵀ·w,  w ← w + Y·G⁻¹·(x_P − y_P),  x_I = Pᵀ·L⁻ᵀ·w,
//! ```
//!
//! since `y_P = E_Pᵀ·A_II⁻¹·c = Yᵀ·w` and `Z·μ = Pᵀ·L⁻ᵀ·(Y·μ)`. A column of `Y` is non-zero
//! only on the reach of its unit column in the elimination tree of `L`
//! ([`CompactFactor::forward_sparse`], `compact_factor/reach.rs`): a promotion solves each
//! new column by a forward pass along that path instead of a forward and a backward pass
//! over the whole block, keeps `|path|` values a column instead of `|I|`, and the
//! back-substitution adds `Y·μ` between its two passes instead of the dense `Z·μ` after
//! them. `C_B` depends on `A` alone: it is formed (by the same sparse forward passes) at
//! the block's first promotion after its base factor, kept by rows, and released when the
//! block has no promoted equation left. Row `k` of `W_P` is `Σ_i Y_ik·C_B(i, :)` along
//! column `k`'s path, so a column kept from the last promotion keeps its row of `W_P`;
//! `G` is formed whole, as a dense product over the union of the paths.
//!
//! The columns of `Y` are each the full forward pass's to the bit, whether kept from the
//! block's last promotion or solved anew ([`CompactFactor::forward_sparse`]), so a
//! promotion's answers do not depend on which columns were kept. They differ from the
//! [`PromotionForm::Columns`] answers by round-off only: `G`, `W_P` and the
//! back-substitution's correction are the same exact quantities, summed in another order
//! (`partition::tests::the_forward_form_solves_as_the_columns_form`).

use super::{promoted_products, BlockState, Partitioned, Promotion, Solved};
use crate::compact_factor::{CompactFactor, ForwardColumn};
use crate::linear::SolverError;

/// How a promotion forms its block's condensation onto the promoted equations (module
/// documentation).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum PromotionForm {
    /// The columns `Z = A_II⁻¹·E_P`, each by a forward and a backward pass over the block
    /// (`|I|` values a column).
    #[default]
    Columns,
    /// The columns `Y = L⁻¹·P·E_P` of the forward pass alone, on their elimination-tree
    /// paths; blocks whose factor has no compact copy use [`PromotionForm::Columns`].
    Forward,
}

impl Partitioned {
    /// Forms the promotions from the next factorization on in `form` (a change drops every
    /// block's promotion, formed again then). Across ranks every rank must make the same
    /// calls, as for every method.
    pub fn set_promotion_form(&mut self, form: PromotionForm) {
        if self.options.promotion_form == form {
            return;
        }
        self.options.promotion_form = form;
        for blk in &mut self.blocks {
            blk.promotion = None;
            blk.promoted.clear();
            if let Some(st) = blk.base.as_mut() {
                st.forward_coupling = None;
            }
        }
        // Rank 0's copies of the other ranks' promotions: those re-formed are sent again.
        for r in &mut self.received {
            r.g_inv.clear();
            r.w_p.clear();
        }
        self.constant_stale = true;
    }

    /// How promotions form their condensation.
    pub fn promotion_form(&self) -> PromotionForm {
        self.options.promotion_form
    }
}

/// The promotion of block `st` onto `promoted` (its interior indices `local`) in the
/// forward form (module documentation), the columns of `Y` of the equations promoted in
/// `last` too (`from[k]`: the column's place there) kept. `None` if the block's factor has
/// no compact copy (the caller forms the columns form).
pub(super) fn promotion_forward(
    st: &mut BlockState,
    promoted: Vec<usize>,
    local: Vec<usize>,
    from: &[Option<usize>],
    last: Option<(Vec<ForwardColumn>, Vec<f64>)>,
) -> Option<Result<Promotion, SolverError>> {
    let BlockState {
        factor,
        coupling,
        forward_coupling,
        ..
    } = st;
    let c = factor.compact_mut()?;
    let np = promoted.len();
    let (mut last, last_w) = last.unwrap_or_default();
    let np_last = last.len();
    let mut y: Vec<ForwardColumn> = from
        .iter()
        .map(|m| m.map_or_else(ForwardColumn::default, |m| std::mem::take(&mut last[m])))
        .collect();
    let fresh: Vec<usize> = (0..np).filter(|&k| from[k].is_none()).collect();
    let units: Vec<Vec<(u32, f64)>> = fresh
        .iter()
        .map(|&k| vec![(local[k] as u32, 1.0)])
        .collect();
    let solved = c.forward_sparse(&units);
    let reach = [
        solved.iter().map(|s| s.rows.len()).sum(),
        solved.iter().map(|s| s.rows.len()).max().unwrap_or(0),
    ];
    for (&k, col) in fresh.iter().zip(solved) {
        y[k] = col;
    }
    let cb = forward_coupling.get_or_insert_with(|| CouplingRows::new(c, coupling));
    // G = Yᵀ·Y over the rows of `Y` (the union `U` of its paths, which share their ends
    // near the root) as a dense product of contiguous columns, each entry one dot product
    // over `U` (nalgebra's `tr_mul`), not gathers along each path. `U`, hence every sum,
    // depends on the promoted set alone, not on which columns were kept. Entries (k, l)
    // and (l, k) are the same products in the same order: G is symmetric to the bit.
    let n = c.n();
    let mut at = vec![u32::MAX; n];
    let mut rows: Vec<u32> = Vec::new();
    for yk in &y {
        for &i in &yk.rows {
            if at[i as usize] == u32::MAX {
                at[i as usize] = 0;
                rows.push(i);
            }
        }
    }
    rows.sort_unstable();
    for (u, &i) in rows.iter().enumerate() {
        at[i as usize] = u as u32;
    }
    let mut yu = nalgebra::DMatrix::<f64>::zeros(rows.len(), np);
    for (k, yk) in y.iter().enumerate() {
        for (&i, &v) in yk.rows.iter().zip(&yk.values) {
            yu[(at[i as usize] as usize, k)] = v;
        }
    }
    let g = yu.tr_mul(&yu);
    // G is a principal block of the inverse of a positive definite matrix.
    let Some(ch) = g.cholesky() else {
        return Some(Err(SolverError::Singular {
            equation: promoted[0],
        }));
    };
    let g_inv = ch.inverse().as_slice().to_vec();
    // W_P = Yᵀ·C_B by rows: row k is Σ Y_ik·C_B(i, :) over column k's path in increasing
    // position, a function of that column and C_B alone, so a kept column keeps its row.
    let nb = cb.nb;
    let mut w_p = vec![0.0; np * nb];
    let mut row = vec![0.0; nb];
    for (k, yk) in y.iter().enumerate() {
        if let Some(m) = from[k].filter(|_| last_w.len() == np_last * nb) {
            for j in 0..nb {
                w_p[k + j * np] = last_w[m + j * np_last];
            }
            continue;
        }
        row.fill(0.0);
        for (&i, &v) in yk.rows.iter().zip(&yk.values) {
            if let Some(r) = cb.row(i) {
                for (w, x) in row.iter_mut().zip(r) {
                    *w += v * x;
                }
            }
        }
        for (j, w) in row.iter().enumerate() {
            w_p[k + j * np] = *w;
        }
    }
    let products = promoted_products(&g_inv, &w_p, np, nb);
    let kept = np - fresh.len();
    Some(Ok(Promotion {
        promoted,
        local,
        z: Solved::Forward(y),
        g_inv,
        w_p,
        products,
        columns: [fresh.len(), kept],
        reach,
    }))
}

/// `C_B = L⁻¹·P·A_IB` (module documentation) by rows: the positions of its reach (the
/// union of its columns' paths) and `nb` values each, contiguous.
pub(super) struct CouplingRows {
    /// Row of each position in `values` (`u32::MAX`: off the reach, a zero row).
    at: Vec<u32>,
    values: Vec<f64>,
    /// Boundary equations (columns).
    nb: usize,
}

impl CouplingRows {
    /// `C_B` of the block whose factor's compact copy is `c` and whose coupling `A_IB` by
    /// boundary column is `coupling` (sparse forward passes, [`CompactFactor::forward_sparse`]).
    fn new(c: &mut CompactFactor, coupling: &[Vec<(u32, f64)>]) -> CouplingRows {
        let cols = c.forward_sparse(coupling);
        let nb = cols.len();
        let mut at = vec![u32::MAX; c.n()];
        let mut count = 0;
        for col in &cols {
            for &i in &col.rows {
                if at[i as usize] == u32::MAX {
                    at[i as usize] = count;
                    count += 1;
                }
            }
        }
        let mut values = vec![0.0; count as usize * nb];
        for (j, col) in cols.iter().enumerate() {
            for (&i, &v) in col.rows.iter().zip(&col.values) {
                values[at[i as usize] as usize * nb + j] = v;
            }
        }
        CouplingRows { at, values, nb }
    }

    /// Row `i` (a position), or `None` for a zero row.
    fn row(&self, i: u32) -> Option<&[f64]> {
        let a = *self.at.get(i as usize).filter(|&&a| a != u32::MAX)? as usize;
        Some(&self.values[a * self.nb..(a + 1) * self.nb])
    }

    /// Bytes held (capacities).
    pub(super) fn heap_bytes(&self) -> usize {
        4 * self.at.capacity() + 8 * self.values.capacity()
    }
}

/// The back-substitution of one block in the forward form (module documentation), in
/// place on `z` (`nc` columns of `c = r_I − A_IB·x_B`, interior order), `xp[k]` the
/// promoted equations' values of column `k`: `x_I = Pᵀ·L⁻ᵀ·(w + Y·G⁻¹·(x_P − Yᵀ·w))`,
/// `w = L⁻¹·P·c`.
pub(super) fn back_substitute_forward(
    c: &mut CompactFactor,
    y: &[ForwardColumn],
    g_inv: &[f64],
    xp: &[Vec<f64>],
    z: &mut [f64],
    nc: usize,
) {
    let np = y.len();
    let mut between = |k: usize, w: &mut [f64]| {
        let d: Vec<f64> = y.iter().zip(&xp[k]).map(|(yk, x)| x - yk.dot(w)).collect();
        for (kk, yk) in y.iter().enumerate() {
            let e: f64 = (0..np).map(|l| g_inv[kk + l * np] * d[l]).sum();
            if e != 0.0 {
                yk.add_to(e, w);
            }
        }
    };
    c.solve_columns_between(z, nc, &mut between);
}

//! A linear model with some of its blocks reduced: the far field of a viaduct under ground
//! motion, with every span but those near the train in Craig–Bampton form.
//!
//! The coordinates are the model's *kept* equations (every equation that is not in a
//! reduced block's interior, boundaries included) followed by each reduced block's modal
//! coordinates `η`. A reduced block's interior rows see only the block
//! ([`super::block_split`]), so the model's matrices keep their entries between kept
//! equations, and each reduced block adds what its reduction changes:
//!
//! - on its boundary, `Â_BB − A_BB` (for `K`, the Schur term `K_BI·Ψ`; for `M` and `C`,
//!   `A_BI·Ψ + Ψᵀ·A_IB + Ψᵀ·A_II·Ψ`), because `T`'s boundary columns are unit columns
//!   on `B` plus `Ψ` on `I`;
//! - between its modes and its boundary, `Â_ηB`, and among its modes `Â_ηη`.
//!
//! That is `Tᵀ·A·T` for the model's whole basis `T` (identity on the kept equations, each
//! block's `[[I, 0], [Ψ, Φ]]` on its own), so a load projects as `Tᵀ·f` and a state
//! expands as `T·x` ([`MixedModel::reduce`], [`MixedModel::expand`]).

use super::CraigBampton;
use railfem_framework::sparse::CscMatrix;
use std::sync::Arc;

/// One reduced block of a [`MixedModel`].
#[derive(Debug, Clone)]
pub struct ReducedBlock {
    /// The block's equations in the model, in the order its reduction numbers them.
    pub eqs: Vec<usize>,
    /// Its reduction (blocks with equal matrices may share one).
    pub reduction: Arc<CraigBampton>,
}

/// A model's `K`, `M`, `C` with some blocks reduced (module documentation).
pub struct MixedModel {
    n_full: usize,
    /// Model equation of each kept coordinate.
    kept: Vec<usize>,
    /// Kept coordinate of each model equation (`None` inside a reduced interior).
    kept_of: Vec<Option<usize>>,
    blocks: Vec<ReducedBlock>,
    /// First modal coordinate of each block.
    offsets: Vec<usize>,
    /// `Tᵀ·K·T`.
    pub k: CscMatrix,
    /// `Tᵀ·M·T`.
    pub m: CscMatrix,
    /// `Tᵀ·C·T`.
    pub c: CscMatrix,
}

impl MixedModel {
    /// The model `(k, m, c)` with `blocks` reduced. Each block's reduction must have been
    /// built from `restrict(A, &block.eqs)` (or equal matrices) with the split of
    /// [`super::block_split`]; the blocks' equations must not overlap.
    pub fn new(
        k: &CscMatrix,
        m: &CscMatrix,
        c: &CscMatrix,
        blocks: Vec<ReducedBlock>,
    ) -> Result<MixedModel, super::ReducedError> {
        let n = k.n;
        let mut inside = vec![false; n];
        for b in &blocks {
            for &l in &b.reduction.split().interior {
                let e = b.eqs[l];
                if inside[e] {
                    return Err(super::ReducedError::InvalidInput(format!(
                        "equation {e} is in two reduced blocks"
                    )));
                }
                inside[e] = true;
            }
        }
        let kept: Vec<usize> = (0..n).filter(|&e| !inside[e]).collect();
        let mut kept_of = vec![None; n];
        for (i, &e) in kept.iter().enumerate() {
            kept_of[e] = Some(i);
        }
        let mut offsets = Vec::with_capacity(blocks.len());
        let mut size = kept.len();
        for b in &blocks {
            offsets.push(size);
            size += b.reduction.modes();
        }
        let mats = [k, m, c];
        let mut lists: [Vec<(usize, usize, f64)>; 3] = Default::default();
        for (a, list) in mats.iter().zip(lists.iter_mut()) {
            for j in 0..n {
                let Some(jk) = kept_of[j] else { continue };
                for p in a.col_ptr[j]..a.col_ptr[j + 1] {
                    if let Some(ik) = kept_of[a.row_idx[p]] {
                        list.push((ik, jk, a.values[p]));
                    }
                }
            }
        }
        for (b, &off) in blocks.iter().zip(&offsets) {
            let cb = &b.reduction;
            let bnd = &cb.split().boundary;
            let nb = bnd.len();
            let coord = |r: usize| {
                if r < nb {
                    kept_of[b.eqs[bnd[r]]].expect("a boundary equation is kept")
                } else {
                    off + r - nb
                }
            };
            for ((a, hat), list) in mats
                .iter()
                .zip([&cb.k_hat, &cb.m_hat, &cb.c_hat])
                .zip(lists.iter_mut())
            {
                for s in 0..cb.size() {
                    for r in 0..cb.size() {
                        let mut v = hat[(r, s)];
                        if r < nb && s < nb {
                            v -= a.get(b.eqs[bnd[r]], b.eqs[bnd[s]]);
                        }
                        list.push((coord(r), coord(s), v));
                    }
                }
            }
        }
        let [k, m, c] = same_pattern(size, &lists);
        Ok(MixedModel {
            n_full: n,
            kept,
            kept_of,
            blocks,
            offsets,
            k,
            m,
            c,
        })
    }

    /// Number of coordinates (kept equations plus modes).
    pub fn size(&self) -> usize {
        self.k.n
    }

    /// `Tᵀ·f` of a load on the model's equations.
    pub fn reduce(&self, f: &[f64]) -> Vec<f64> {
        let mut out = vec![0.0; self.size()];
        for (i, &e) in self.kept.iter().enumerate() {
            out[i] = f[e];
        }
        for (b, &off) in self.blocks.iter().zip(&self.offsets) {
            let local: Vec<f64> = b.eqs.iter().map(|&e| f[e]).collect();
            let fh = b.reduction.reduce(&local);
            let bnd = &b.reduction.split().boundary;
            for (r, &l) in bnd.iter().enumerate() {
                out[self.kept_of[b.eqs[l]].expect("kept")] = fh[r];
            }
            out[off..off + b.reduction.modes()].copy_from_slice(&fh[bnd.len()..]);
        }
        out
    }

    /// `T·x`: coordinates expanded to the model's equations.
    pub fn expand(&self, x: &[f64]) -> Vec<f64> {
        let mut out = vec![0.0; self.n_full];
        for (i, &e) in self.kept.iter().enumerate() {
            out[e] = x[i];
        }
        for (b, &off) in self.blocks.iter().zip(&self.offsets) {
            let cb = &b.reduction;
            let bnd = &cb.split().boundary;
            let mut xh: Vec<f64> = bnd
                .iter()
                .map(|&l| x[self.kept_of[b.eqs[l]].expect("kept")])
                .collect();
            xh.extend_from_slice(&x[off..off + cb.modes()]);
            let q = cb.expand(&xh);
            for &l in &cb.split().interior {
                out[b.eqs[l]] = q[l];
            }
        }
        out
    }
}

/// Three matrices (`M`, `C`, `K` of a model, say) on the union of their patterns, as a
/// sparse march forms their weighted sum.
pub fn on_one_pattern(a: [&CscMatrix; 3]) -> [CscMatrix; 3] {
    let lists = a.map(|a| {
        let mut t = Vec::with_capacity(a.nnz());
        for j in 0..a.n {
            for p in a.col_ptr[j]..a.col_ptr[j + 1] {
                t.push((a.row_idx[p], j, a.values[p]));
            }
        }
        t
    });
    same_pattern(a[0].n, &lists)
}

/// Three matrices of one pattern (the union of the three lists' entries; duplicates sum).
fn same_pattern(n: usize, lists: &[Vec<(usize, usize, f64)>; 3]) -> [CscMatrix; 3] {
    let all: Vec<(usize, usize, f64)> = lists
        .iter()
        .flat_map(|l| l.iter().map(|&(i, j, _)| (i, j, 0.0)))
        .collect();
    let pattern = CscMatrix::from_triplets(n, &all);
    lists.each_ref().map(|list| {
        let mut a = pattern.zeros_like();
        for &(i, j, v) in list {
            let p = a.position(i, j).expect("entry is in the union pattern");
            a.values[p] += v;
        }
        a
    })
}

//! A simplicial Cholesky factor `P·A·Pᵀ = L·Lᵀ` kept for solving only, without its exact
//! zeros: the same solutions as faer's simplicial solve, to the bit, from fewer bytes.
//!
//! **Why there are zeros.** The partitioned solver's blocks are factored on the pattern that
//! `K`, `M` and `C` share (the union over every element's full 12×12 or 6×6 matrix), and
//! most of those entries are exact zeros in `A = c_K·K + c_M·M + c_C·C` (a beam's axial,
//! torsional and two bending parts do not couple; a fastener couples one direction). The
//! elimination carries them into `L`: on the train–bridge blocks about 59 % of the stored
//! values of `L` are exactly zero (measured at 1e5 DOF). A solve reads each stored value
//! and its 8-byte row index twice (forward and backward); this copy keeps the non-zeros
//! only, with 4-byte row indices, so it reads roughly a third of the bytes.
//!
//! **Why the answers do not move.** faer 0.24's simplicial `L·Lᵀ` solve
//! (`SimplicialLltRef::solve_in_place_with_conj`, via `LltRef`, which first permutes the
//! right-hand side) does, for each right-hand-side column independently:
//!
//! * forward, columns `j = 0, 1, …` in order: `x_j ← x_j·(1/L_jj)`, then for each stored
//!   off-diagonal `L_ij` of column `j`, in storage order: `x_i ← x_i − L_ij·x_j`;
//! * backward, columns `j = n−1, …, 0`: `s ← +0`, then for each stored off-diagonal of
//!   column `j` in *reverse* storage order `s ← s + L_ij·x_i`, then `x_j ← (x_j − s)·(1/L_jj)`;
//!
//! each a separate IEEE multiply and add (Rust does not contract them to fused operations).
//! [`CompactFactor::solve_columns`] does exactly these operations in exactly this order,
//! except the ones with `L_ij = ±0`. Those change nothing: with a finite `x`, `L_ij·x` is a
//! signed zero, and `s + (±0) = s` for every `s` the backward sum can hold (it starts at
//! `+0`, and a sum of round-to-nearest additions is `−0` only if both terms are `−0`, so it
//! never is); `x_i − (±0) = x_i` for every `x_i ≠ 0`, and for `x_i = ±0` the result is a zero
//! of possibly the other sign. So every non-zero of the solution is bit-for-bit faer's, and
//! a zero may differ in its sign only — which no later step of a solve or a product can
//! tell (a signed zero times anything finite is a zero; added to anything it is that thing
//! or a zero). With a non-finite right-hand side faer's result would be non-finite where
//! this one may not be everywhere; the callers check residuals for finiteness.
//!
//! Tests: the module's unit tests compare with faer's solve bit for bit on matrices with
//! stored zeros, for one to five right-hand sides.
//!
//! The forward pass alone for sparse right-hand sides, visiting only their reach in the
//! elimination tree, lives in `compact_factor/reach.rs` ([`CompactFactor::forward_sparse`]).

mod reach;

pub use reach::ForwardColumn;

/// What [`CompactFactor::solve_columns_between`] calls between the passes: the column's
/// index and its forward result.
type Between<'a> = dyn FnMut(usize, &mut [f64]) + 'a;

/// `L` (off-diagonal non-zeros, column by column in faer's storage order), the reciprocal
/// of its diagonal, and the fill-reducing permutation.
#[derive(Debug, Clone, Default)]
pub struct CompactFactor {
    n: usize,
    /// `x[i] = b[fwd[i]]` before the triangular solves (`None`: identity).
    fwd: Option<Vec<u32>>,
    /// `b[i] = x[inv[i]]` after them.
    inv: Option<Vec<u32>>,
    /// `1/L_jj`, as faer forms it (`1.0 / L_jj`).
    recip: Vec<f64>,
    col_ptr: Vec<u32>,
    rows: Vec<u32>,
    values: Vec<f64>,
    /// Parent of each column in the elimination tree of the stored pattern (`u32::MAX`: a
    /// root), when that pattern is closed under it (`compact_factor/reach.rs`); `None`:
    /// a sparse forward pass visits every column from its first non-zero on.
    parent: Option<Vec<u32>>,
    /// Scratch of the permuted right-hand sides.
    x: Vec<f64>,
}

impl CompactFactor {
    /// The copy of a simplicial factor: `col_ptr`, `row_idx`, `values` of `L` as faer stores
    /// them (the diagonal first in each column), and the permutation's `fwd`/`inv` arrays.
    /// `None` if a dimension does not fit 32-bit indices or a column does not start with
    /// its diagonal (then the caller keeps faer's solve).
    pub fn new(
        col_ptr: &[usize],
        row_idx: &[usize],
        values: &[f64],
        perm: Option<(&[usize], &[usize])>,
    ) -> Option<CompactFactor> {
        let n = col_ptr.len().checked_sub(1)?;
        if n >= u32::MAX as usize {
            return None;
        }
        let mut f = CompactFactor {
            n,
            recip: Vec::with_capacity(n),
            col_ptr: Vec::with_capacity(n + 1),
            ..Default::default()
        };
        let kept = values.iter().filter(|v| **v != 0.0).count();
        if kept >= u32::MAX as usize {
            return None;
        }
        f.rows.reserve_exact(kept.saturating_sub(n));
        f.values.reserve_exact(kept.saturating_sub(n));
        f.col_ptr.push(0);
        for j in 0..n {
            let (start, end) = (col_ptr[j], col_ptr[j + 1]);
            if start >= end || row_idx[start] != j {
                return None;
            }
            f.recip.push(1.0 / values[start]);
            for p in start + 1..end {
                if values[p] != 0.0 {
                    f.rows.push(row_idx[p] as u32);
                    f.values.push(values[p]);
                }
            }
            f.col_ptr.push(f.rows.len() as u32);
        }
        if let Some((fwd, inv)) = perm {
            f.fwd = Some(fwd.iter().map(|&i| i as u32).collect());
            f.inv = Some(inv.iter().map(|&i| i as u32).collect());
        }
        f.parent = reach::elimination_tree(col_ptr, row_idx);
        Some(f)
    }

    /// Equations.
    pub fn n(&self) -> usize {
        self.n
    }

    /// Off-diagonal non-zeros kept.
    pub fn nonzeros(&self) -> usize {
        self.values.len()
    }

    /// Bytes held (capacities).
    pub fn heap_bytes(&self) -> usize {
        let perm = self.fwd.as_ref().map_or(0, Vec::capacity)
            + self.inv.as_ref().map_or(0, Vec::capacity)
            + self.parent.as_ref().map_or(0, Vec::capacity);
        4 * (perm + self.col_ptr.capacity() + self.rows.capacity())
            + 8 * (self.recip.capacity() + self.values.capacity() + self.x.capacity())
    }

    /// Solves `A·X = B` in place for the `ncols` columns of `b` (column-major, `n` rows
    /// each), with the operations of faer's simplicial solve (module documentation). Up to
    /// four columns share one pass over `L`: their entries of a row sit side by side in the
    /// scratch, so a stored value and its row index are read once for all of them; each
    /// column's own operations are unchanged, so any grouping gives the same bits.
    pub fn solve_columns(&mut self, b: &mut [f64], ncols: usize) {
        self.solve_columns_from(b, ncols, &[]);
    }

    /// Position of equation `i` in the elimination order (the row of the permuted
    /// right-hand side that holds `b[i]`).
    pub fn position(&self, i: usize) -> usize {
        self.inv.as_ref().map_or(i, |inv| inv[i] as usize)
    }

    /// [`CompactFactor::solve_columns`] for right-hand sides whose column `c` is `+0` at
    /// every position of the elimination order before `from[c]` ([`CompactFactor::position`];
    /// missing entries of `from`: 0). The forward pass of a group of columns starts at the
    /// least of their `from`: the columns `j` it skips would set `x_j ← (+0)·(1/L_jj) = +0`
    /// (a positive diagonal) and `x_i ← x_i − L_ij·(+0)`, which leaves every `x_i` as it is,
    /// a `+0` included (`+0 − (±0) = +0`). So the answers are those of
    /// [`CompactFactor::solve_columns`] to the bit, zeros' signs included: a unit column
    /// `e_p` costs the forward pass from `p`'s position on only.
    pub fn solve_columns_from(&mut self, b: &mut [f64], ncols: usize, from: &[usize]) {
        self.solve_columns_inner(b, ncols, from, None);
    }

    /// [`CompactFactor::solve_columns`] with `between(c, w)` called for each column `c`
    /// between its forward and backward passes, on `w = L⁻¹·P·b_c` (indexed by position in
    /// the elimination order, [`CompactFactor::position`]), which it may change: the
    /// backward pass then gives `Pᵀ·L⁻ᵀ·w`. Each column's operations are otherwise those
    /// of [`CompactFactor::solve_columns`].
    pub fn solve_columns_between(
        &mut self,
        b: &mut [f64],
        ncols: usize,
        between: &mut dyn FnMut(usize, &mut [f64]),
    ) {
        self.solve_columns_inner(b, ncols, &[], Some(between));
    }

    fn solve_columns_inner<'a>(
        &mut self,
        b: &mut [f64],
        ncols: usize,
        from: &[usize],
        mut between: Option<&mut Between<'a>>,
    ) {
        let n = self.n;
        debug_assert_eq!(b.len(), n * ncols);
        let mut w = Vec::new();
        let mut done = 0;
        while done < ncols {
            let group = &mut b[done * n..];
            let k = (ncols - done).min(4);
            let start = (done..done + k)
                .map(|c| from.get(c).copied().unwrap_or(0))
                .min()
                .unwrap_or(0)
                .min(n);
            let mid = between.as_deref_mut();
            done += match k {
                1 => self.solve_group::<1>(group, start, mid, done, &mut w),
                2 => self.solve_group::<2>(group, start, mid, done, &mut w),
                3 => self.solve_group::<3>(group, start, mid, done, &mut w),
                _ => self.solve_group::<4>(group, start, mid, done, &mut w),
            };
        }
    }

    /// [`CompactFactor::solve_columns`] on the first `K` columns of `b`, the forward pass
    /// from column `start` of `L` ([`CompactFactor::solve_columns_from`]), with `mid`
    /// between the passes ([`CompactFactor::solve_columns_between`]; the group's first
    /// column is column `first` of the solve, `w` a scratch); returns `K`.
    fn solve_group<'a, const K: usize>(
        &mut self,
        b: &mut [f64],
        start: usize,
        mid: Option<&mut Between<'a>>,
        first: usize,
        w: &mut Vec<f64>,
    ) -> usize {
        let n = self.n;
        self.x.resize(n * K, 0.0);
        let x = &mut self.x[..n * K];
        for c in 0..K {
            let bc = &b[c * n..(c + 1) * n];
            match &self.fwd {
                Some(fwd) => {
                    for (i, &f) in fwd.iter().enumerate() {
                        x[i * K + c] = bc[f as usize];
                    }
                }
                None => {
                    for (i, &v) in bc.iter().enumerate() {
                        x[i * K + c] = v;
                    }
                }
            }
        }
        // Forward: x_j ← x_j·(1/L_jj), then x_i ← x_i − L_ij·x_j down column j.
        for j in start..n {
            forward_column::<K>(&self.col_ptr, &self.rows, &self.values, &self.recip, x, j);
        }
        if let Some(f) = mid {
            w.resize(n, 0.0);
            for c in 0..K {
                for (i, wi) in w.iter_mut().enumerate() {
                    *wi = x[i * K + c];
                }
                f(first + c, w);
                for (i, wi) in w.iter().enumerate() {
                    x[i * K + c] = *wi;
                }
            }
        }
        // Backward: s ← Σ L_ij·x_i up column j in reverse storage order, from +0, then
        // x_j ← (x_j − s)·(1/L_jj).
        for j in (0..n).rev() {
            let (start, end) = (self.col_ptr[j] as usize, self.col_ptr[j + 1] as usize);
            let mut s = [0.0; K];
            for (&i, &l) in self.rows[start..end]
                .iter()
                .zip(&self.values[start..end])
                .rev()
            {
                let xi = &x[i as usize * K..(i as usize + 1) * K];
                for (acc, v) in s.iter_mut().zip(xi) {
                    *acc += l * v;
                }
            }
            for (c, acc) in s.iter().enumerate() {
                x[j * K + c] = (x[j * K + c] - acc) * self.recip[j];
            }
        }
        for c in 0..K {
            let bc = &mut b[c * n..(c + 1) * n];
            match &self.inv {
                Some(inv) => {
                    for (bi, &k) in bc.iter_mut().zip(inv) {
                        *bi = x[k as usize * K + c];
                    }
                }
                None => {
                    for (i, bi) in bc.iter_mut().enumerate() {
                        *bi = x[i * K + c];
                    }
                }
            }
        }
        K
    }
}

/// Column `j` of the forward pass on `K` right-hand sides interleaved in `x`:
/// `x_j ← x_j·(1/L_jj)`, then `x_i ← x_i − L_ij·x_j` for the stored off-diagonals of
/// column `j` in storage order (the operations the module documentation lists, in its
/// order). Shared by the full pass and the reach-limited one, so both do the same.
#[inline(always)]
pub(crate) fn forward_column<const K: usize>(
    col_ptr: &[u32],
    rows: &[u32],
    values: &[f64],
    recip: &[f64],
    x: &mut [f64],
    j: usize,
) {
    let (start, end) = (col_ptr[j] as usize, col_ptr[j + 1] as usize);
    let mut xj = [0.0; K];
    for (c, v) in xj.iter_mut().enumerate() {
        *v = x[j * K + c] * recip[j];
        x[j * K + c] = *v;
    }
    for (&i, &l) in rows[start..end].iter().zip(&values[start..end]) {
        let xi = &mut x[i as usize * K..(i as usize + 1) * K];
        for (e, v) in xi.iter_mut().zip(&xj) {
            *e -= l * v;
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::linear::{Layout, LinearSolver, SparseCholesky};
    use railfem_framework::sparse::CscMatrix;

    /// A banded SPD matrix whose pattern stores many exact zeros (as the union pattern of
    /// `K`, `M`, `C` does): 6 DOFs per node, each node coupled to the next in full 6×6
    /// blocks of which only the "bending" pairs are non-zero, plus random-ish diagonals.
    fn beam_like(nodes: usize) -> CscMatrix {
        let n = 6 * nodes;
        let mut t = Vec::new();
        let val = |i: usize, j: usize| ((i * 31 + j * 17) % 13) as f64 / 13.0;
        for k in 0..nodes {
            for a in 0..6 {
                for b in 0..6 {
                    let (i, j) = (6 * k + a, 6 * k + b);
                    let v = if a == b {
                        20.0 + val(i, j)
                    } else if (a + b) % 3 == 0 {
                        0.5 * val(i.min(j), i.max(j))
                    } else {
                        0.0
                    };
                    t.push((i, j, v));
                }
            }
            if k + 1 < nodes {
                for a in 0..6 {
                    for b in 0..6 {
                        let (i, j) = (6 * k + a, 6 * (k + 1) + b);
                        let v = if a == b || (a + b) % 4 == 1 {
                            -1.0 - val(i, j)
                        } else {
                            0.0
                        };
                        t.push((i, j, v));
                        t.push((j, i, v));
                    }
                }
            }
        }
        CscMatrix::from_triplets(n, &t)
    }

    fn rhs(n: usize, ncols: usize) -> Vec<f64> {
        (0..n * ncols)
            .map(|i| match i % 7 {
                0 => 0.0,
                3 => -0.0,
                r => (r as f64 - 3.5) * (1.0 + (i % 11) as f64),
            })
            .collect()
    }

    #[test]
    fn the_compact_solve_is_faers_simplicial_solve_to_the_bit() {
        for nodes in [1, 2, 7, 40] {
            let a = beam_like(nodes);
            let n = a.n;
            let mut faer_solver = SparseCholesky::new().with_layout(Layout::Simplicial);
            faer_solver.factor(&a).unwrap();
            let mut compact = SparseCholesky::new()
                .with_layout(Layout::Simplicial)
                .with_compact_solve(true);
            compact.factor(&a).unwrap();
            let (kept, stored) = compact.compact_counts().expect("compact copy");
            if nodes >= 7 {
                assert!(kept < stored, "{nodes} nodes: {kept} of {stored} kept");
            }
            for ncols in 1..=5 {
                let mut x1 = rhs(n, ncols);
                let mut x2 = x1.clone();
                faer_solver.solve_columns_in_place(&mut x1, ncols).unwrap();
                compact.solve_columns_in_place(&mut x2, ncols).unwrap();
                for (k, (u, v)) in x1.iter().zip(&x2).enumerate() {
                    // Equal as numbers, and bit-identical unless both are zeros (module
                    // documentation: a zero may differ in sign).
                    assert!(
                        u.to_bits() == v.to_bits() || (*u == 0.0 && *v == 0.0),
                        "{nodes} nodes, {ncols} columns, entry {k}: {u:e} against {v:e}"
                    );
                }
                // And it solves the system (not two identical wrong answers).
                for c in 0..ncols {
                    let (xc, bc) = (&x2[c * n..(c + 1) * n], &rhs(n, ncols)[c * n..(c + 1) * n]);
                    let mut ax = vec![0.0; n];
                    a.mul_vec(xc, &mut ax);
                    let scale = bc.iter().fold(1.0f64, |m, v| m.max(v.abs()));
                    let err = ax
                        .iter()
                        .zip(bc)
                        .fold(0.0f64, |m, (p, q)| m.max((p - q).abs()));
                    assert!(err <= 1e-12 * scale, "{nodes} nodes: residual {err:e}");
                }
            }
        }
    }

    /// A beam-like matrix of `nodes` nodes and its simplicial factor with the compact copy.
    fn factored_beam(nodes: usize) -> (CscMatrix, SparseCholesky) {
        let a = beam_like(nodes);
        let mut s = SparseCholesky::new()
            .with_layout(Layout::Simplicial)
            .with_compact_solve(true);
        s.factor(&a).unwrap();
        (a, s)
    }

    /// Unit columns solved with their forward passes started at their positions are the
    /// unit columns solved in full, to the bit (zeros' signs included), in any order.
    #[test]
    fn unit_columns_skip_their_leading_zeros_to_the_bit() {
        let (a, mut s) = factored_beam(40);
        let n = a.n;
        let locals = [n - 1, 3, 117, 0, 58, 200, 59, 7, 131];
        let got = s.solve_unit_columns(&locals).unwrap();
        let mut full = vec![0.0; n * locals.len()];
        for (k, &l) in locals.iter().enumerate() {
            full[k * n + l] = 1.0;
        }
        s.solve_columns_in_place(&mut full, locals.len()).unwrap();
        assert!(got
            .iter()
            .zip(&full)
            .all(|(u, v)| u.to_bits() == v.to_bits()));
        // And they are the inverse's columns: A·x = e_l.
        for (k, &l) in locals.iter().enumerate() {
            let mut ax = vec![0.0; n];
            a.mul_vec(&got[k * n..(k + 1) * n], &mut ax);
            for (i, v) in ax.iter().enumerate() {
                let e = if i == l { 1.0 } else { 0.0 };
                assert!((v - e).abs() < 1e-12, "column {l}, row {i}: {v:e}");
            }
        }
    }

    /// The sparse forward passes are the full forward pass (captured between the passes of
    /// a whole solve) to the bit: the same value on the reach, `+0` off it. The factor's
    /// pattern is a Cholesky factor's, so the reaches are elimination-tree paths, most of
    /// them shorter than the rest of the order after their first position.
    #[test]
    fn the_sparse_forward_pass_is_the_full_one_on_its_reach_to_the_bit() {
        let (a, mut s) = factored_beam(40);
        let n = a.n;
        let c = s.compact_mut().expect("compact copy");
        assert!(c.parent.is_some(), "a Cholesky pattern is closed");
        let mut columns: Vec<Vec<(u32, f64)>> = [n - 1, 3, 117, 0, 58, 200, 59, 7, 131]
            .iter()
            .map(|&l| vec![(l as u32, 1.0)])
            .collect();
        columns.push(vec![(5, 2.5), (80, -1.25), (81, 0.5)]);
        columns.push(vec![(190, -3.0)]);
        let got = c.forward_sparse(&columns);
        let mut b = vec![0.0; n * columns.len()];
        for (k, col) in columns.iter().enumerate() {
            for &(e, v) in col {
                b[k * n + e as usize] = v;
            }
        }
        let mut full = vec![Vec::new(); columns.len()];
        let mut keep = |k: usize, w: &mut [f64]| full[k] = w.to_vec();
        c.solve_columns_between(&mut b, columns.len(), &mut keep);
        let mut shorter = 0;
        for (k, (g, w)) in got.iter().zip(&full).enumerate() {
            let mut on = vec![false; n];
            for (&i, v) in g.rows.iter().zip(&g.values) {
                on[i as usize] = true;
                assert_eq!(v.to_bits(), w[i as usize].to_bits(), "column {k}, row {i}");
            }
            for (i, v) in w.iter().enumerate() {
                assert!(
                    on[i] || v.to_bits() == 0,
                    "column {k}, row {i} off the reach: {v:e}"
                );
            }
            assert!(g.rows.windows(2).all(|p| p[0] < p[1]));
            let first = g.rows[0] as usize;
            if g.rows.len() < n - first {
                shorter += 1;
            }
        }
        assert!(
            shorter >= columns.len() / 2,
            "{shorter} of {}",
            columns.len()
        );
        // And the whole solves with nothing changed between the passes are the solves.
        let mut plain = vec![0.0; n * columns.len()];
        for (k, col) in columns.iter().enumerate() {
            for &(e, v) in col {
                plain[k * n + e as usize] = v;
            }
        }
        s.solve_columns_in_place(&mut plain, columns.len()).unwrap();
        assert!(b
            .iter()
            .zip(&plain)
            .all(|(u, v)| u.to_bits() == v.to_bits()));
    }

    #[test]
    fn a_refactorization_refreshes_the_copy() {
        let mut a = beam_like(10);
        let mut s = SparseCholesky::new()
            .with_layout(Layout::Simplicial)
            .with_compact_solve(true);
        s.factor(&a).unwrap();
        for v in a.values.iter_mut() {
            *v *= 2.0;
        }
        s.factor(&a).unwrap();
        let mut reference = SparseCholesky::new().with_layout(Layout::Simplicial);
        reference.factor(&a).unwrap();
        let (mut x1, mut x2) = (rhs(a.n, 2), rhs(a.n, 2));
        reference.solve_columns_in_place(&mut x1, 2).unwrap();
        s.solve_columns_in_place(&mut x2, 2).unwrap();
        assert!(x1
            .iter()
            .zip(&x2)
            .all(|(u, v)| u.to_bits() == v.to_bits() || (*u == 0.0 && *v == 0.0)));
    }
}

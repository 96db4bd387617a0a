//! The forward pass `w = L⁻¹·P·b` of a [`CompactFactor`] for a sparse right-hand side `b`,
//! visiting only the columns of `L` that `b` reaches (Gilbert and Peierls's sparse
//! triangular solve; T. A. Davis, *Direct Methods for Sparse Linear Systems*, SIAM 2006,
//! §3.2 and §4.1).
//!
//! **The reach is a path.** The forward pass sets `x_j ← x_j·(1/L_jj)`, then
//! `x_i ← x_i − L_ij·x_j` for the rows `i` of column `j`. A column `j` whose `x_j` is `+0`
//! when its turn comes changes nothing: `(+0)·(1/L_jj) = +0` (a positive diagonal), and
//! `x_i − L_ij·(+0)` is `x_i` (for `x_i = +0` too: `+0 − (±0) = +0`). So `w` is `+0` outside
//! the set of columns reachable from `b`'s non-zeros through the graph of `L` (`j → i` for
//! `L_ij ≠ 0`), and the pass over that set alone, in increasing order, does each of the
//! full pass's operations that matter, in the same order: every value of `w` is the full
//! pass's, to the bit. In the pattern of a Cholesky factor the rows of column `j` other
//! than its parent `p(j)` (its first off-diagonal row) are rows of column `p(j)`, so the
//! reach of position `j` lies on the path `j, p(j), p(p(j)), …` to the root of the
//! elimination tree (Davis, Theorem 4.2), and the reach of `b` on the union of the paths of
//! its non-zeros. The stored pattern ([`CompactFactor::new`]'s `col_ptr`/`row_idx`, zeros
//! included) is checked for that closure when the copy is made; the values kept are a
//! subset of it, so the paths hold their reach too. Without the closure (a pattern that is
//! not a Cholesky factor's) the pass runs over every column from `b`'s first non-zero.
//!
//! Tests (in `compact_factor.rs`): every value against the full forward pass, bit for bit,
//! zeros outside the reach included.

use super::{forward_column, CompactFactor};

const ROOT: u32 = u32::MAX;

/// A column of `w = L⁻¹·P·b` ([`CompactFactor::forward_sparse`]): its reach, the positions
/// in the elimination order ([`CompactFactor::position`]) where it may be non-zero, in
/// increasing order, and its values there (`w` is `+0` elsewhere).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ForwardColumn {
    /// Positions in the elimination order, increasing.
    pub rows: Vec<u32>,
    /// The values at `rows`.
    pub values: Vec<f64>,
}

impl ForwardColumn {
    /// `Σ_i w_i·v_i` over the column's rows in increasing position (`v` indexed by
    /// position).
    pub fn dot(&self, v: &[f64]) -> f64 {
        self.rows
            .iter()
            .zip(&self.values)
            .map(|(&i, &w)| w * v[i as usize])
            .sum()
    }

    /// `v ← v + a·w` on the column's rows (`v` indexed by position).
    pub fn add_to(&self, a: f64, v: &mut [f64]) {
        for (&i, &w) in self.rows.iter().zip(&self.values) {
            v[i as usize] += w * a;
        }
    }

    /// Bytes held (capacities).
    pub fn heap_bytes(&self) -> usize {
        4 * self.rows.capacity() + 8 * self.values.capacity()
    }
}

/// The elimination tree of the pattern `col_ptr`/`row_idx` of a lower triangle (diagonal
/// included), each column's parent its least off-diagonal row (`ROOT` for none), if every
/// column's rows other than itself and its parent are rows of its parent (module
/// documentation); `None` if not, or if a row lies above the diagonal.
pub(super) fn elimination_tree(col_ptr: &[usize], row_idx: &[usize]) -> Option<Vec<u32>> {
    let n = col_ptr.len().checked_sub(1)?;
    let rows = |j: usize| &row_idx[col_ptr[j]..col_ptr[j + 1]];
    let mut parent = vec![ROOT; n];
    for (j, p) in parent.iter_mut().enumerate() {
        if let Some(&r) = rows(j).iter().filter(|&&r| r != j).min() {
            if r < j || r >= n {
                return None;
            }
            *p = r as u32;
        }
    }
    // Children of each column as linked lists, then each column's rows marked while its
    // children are checked against them.
    let (mut head, mut next) = (vec![ROOT; n], vec![ROOT; n]);
    for j in (0..n).rev() {
        if let Some(&p) = parent.get(j).filter(|&&p| p != ROOT) {
            next[j] = head[p as usize];
            head[p as usize] = j as u32;
        }
    }
    let mut mark = vec![ROOT; n];
    for p in 0..n {
        for &r in rows(p) {
            mark[r] = p as u32;
        }
        let mut c = head[p];
        while c != ROOT {
            let c_ = c as usize;
            if rows(c_)
                .iter()
                .any(|&r| r != c_ && r != p && mark[r] != p as u32)
            {
                return None;
            }
            c = next[c_];
        }
    }
    Some(parent)
}

impl CompactFactor {
    /// The forward passes `w_c = L⁻¹·P·b_c` of sparse right-hand sides, `columns[c]` the
    /// non-zeros `(equation, value)` of `b_c` (distinct equations), each visiting only the
    /// columns of `L` its non-zeros reach (module documentation): every value is the full
    /// forward pass's of [`CompactFactor::solve_columns`], to the bit. Columns whose first
    /// positions are close share their passes over `L` (up to four at a time, each
    /// column's own operations unchanged), as [`CompactFactor::solve_columns`] does.
    pub fn forward_sparse(&mut self, columns: &[Vec<(u32, f64)>]) -> Vec<ForwardColumn> {
        let n = self.n;
        let mut marked = vec![false; n];
        let reaches: Vec<Vec<u32>> = columns
            .iter()
            .map(|col| {
                let starts: Vec<usize> = col
                    .iter()
                    .map(|&(e, _)| self.position(e as usize))
                    .collect();
                self.reach(&starts, &mut marked)
            })
            .collect();
        let mut order: Vec<usize> = (0..columns.len()).collect();
        order.sort_by_key(|&c| reaches[c].first().copied().unwrap_or(ROOT));
        let mut out = vec![ForwardColumn::default(); columns.len()];
        for group in order.chunks(4) {
            match group.len() {
                1 => self.forward_group::<1>(group, columns, &reaches, &mut out),
                2 => self.forward_group::<2>(group, columns, &reaches, &mut out),
                3 => self.forward_group::<3>(group, columns, &reaches, &mut out),
                _ => self.forward_group::<4>(group, columns, &reaches, &mut out),
            }
        }
        out
    }

    /// The positions reachable from `starts` (module documentation), increasing; `marked`
    /// is all `false` before and after.
    fn reach(&self, starts: &[usize], marked: &mut [bool]) -> Vec<u32> {
        let Some(parent) = &self.parent else {
            let first = starts.iter().copied().min().unwrap_or(self.n);
            return (first as u32..self.n as u32).collect();
        };
        let mut out = Vec::new();
        for &s in starts {
            let mut j = s as u32;
            while j != ROOT && !marked[j as usize] {
                marked[j as usize] = true;
                out.push(j);
                j = parent[j as usize];
            }
        }
        for &j in &out {
            marked[j as usize] = false;
        }
        out.sort_unstable();
        out
    }

    /// The forward passes of the `K` columns `group` of `columns` over the union of their
    /// `reaches`, side by side in the scratch (as [`CompactFactor::solve_columns`] does),
    /// into `out`.
    fn forward_group<const K: usize>(
        &mut self,
        group: &[usize],
        columns: &[Vec<(u32, f64)>],
        reaches: &[Vec<u32>],
        out: &mut [ForwardColumn],
    ) {
        let n = self.n;
        let mut union: Vec<u32> = group
            .iter()
            .flat_map(|&c| reaches[c].iter().copied())
            .collect();
        union.sort_unstable();
        union.dedup();
        self.x.resize(n * K, 0.0);
        let x = &mut self.x[..n * K];
        // Only the union is read or written below: it holds the rows of its columns.
        for &u in &union {
            x[u as usize * K..(u as usize + 1) * K].fill(0.0);
        }
        for (c, &col) in group.iter().enumerate() {
            for &(e, v) in &columns[col] {
                let p = self
                    .inv
                    .as_ref()
                    .map_or(e as usize, |inv| inv[e as usize] as usize);
                x[p * K + c] = v;
            }
        }
        // Forward: x_j ← x_j·(1/L_jj), then x_i ← x_i − L_ij·x_j down column j.
        for &j in &union {
            let (l, r) = (&self.col_ptr, &self.rows);
            forward_column::<K>(l, r, &self.values, &self.recip, x, j as usize);
        }
        for (c, &col) in group.iter().enumerate() {
            let rows = reaches[col].clone();
            let values = rows.iter().map(|&i| x[i as usize * K + c]).collect();
            out[col] = ForwardColumn { rows, values };
        }
    }
}

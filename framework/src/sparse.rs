//! A compressed-sparse-column matrix with a fixed pattern, the form assembly fills and the
//! linear solvers factor.
//!
//! Both triangles are stored (a symmetric matrix stores each off-diagonal entry twice), row
//! indices are sorted within each column, and every diagonal entry is present even when
//! zero. Values change every iteration; the pattern changes only when an element's
//! connectivity does, and [`CscMatrix::pattern_id`] tells solvers when to redo their
//! symbolic analysis.

use std::sync::atomic::{AtomicU64, Ordering};

static NEXT_PATTERN: AtomicU64 = AtomicU64::new(1);

/// Square sparse matrix in compressed-sparse-column form.
#[derive(Debug, Clone, PartialEq)]
pub struct CscMatrix {
    /// Number of rows and columns.
    pub n: usize,
    /// Column pointers, length `n + 1`.
    pub col_ptr: Vec<usize>,
    /// Row index of each stored entry, sorted within each column.
    pub row_idx: Vec<usize>,
    /// Value of each stored entry.
    pub values: Vec<f64>,
    /// Identifies the sparsity pattern: equal ids mean identical `col_ptr` and `row_idx`.
    pub pattern_id: u64,
}

impl CscMatrix {
    /// Builds the pattern from per-column sorted, deduplicated row lists; values are zero.
    /// Diagonal entries are added where missing.
    pub fn from_columns(mut cols: Vec<Vec<usize>>) -> CscMatrix {
        let n = cols.len();
        let mut col_ptr = Vec::with_capacity(n + 1);
        col_ptr.push(0);
        let mut nnz = 0;
        for (j, c) in cols.iter_mut().enumerate() {
            c.push(j);
            c.sort_unstable();
            c.dedup();
            nnz += c.len();
            col_ptr.push(nnz);
        }
        let mut row_idx = Vec::with_capacity(nnz);
        for c in &cols {
            row_idx.extend_from_slice(c);
        }
        CscMatrix {
            n,
            col_ptr,
            row_idx,
            values: vec![0.0; nnz],
            pattern_id: NEXT_PATTERN.fetch_add(1, Ordering::Relaxed),
        }
    }

    /// Builds a matrix from `(row, col, value)` triplets, summing duplicates.
    pub fn from_triplets(n: usize, triplets: &[(usize, usize, f64)]) -> CscMatrix {
        let mut cols = vec![Vec::new(); n];
        for &(i, j, _) in triplets {
            cols[j].push(i);
        }
        let mut m = CscMatrix::from_columns(cols);
        for &(i, j, v) in triplets {
            let p = m.position(i, j).expect("entry is in the pattern");
            m.values[p] += v;
        }
        m
    }

    /// Number of stored entries.
    pub fn nnz(&self) -> usize {
        self.row_idx.len()
    }

    /// Storage position of entry `(i, j)`, if it is in the pattern (binary search).
    pub fn position(&self, i: usize, j: usize) -> Option<usize> {
        let (a, b) = (self.col_ptr[j], self.col_ptr[j + 1]);
        self.row_idx[a..b].binary_search(&i).ok().map(|p| a + p)
    }

    /// Value of entry `(i, j)` (zero outside the pattern).
    pub fn get(&self, i: usize, j: usize) -> f64 {
        self.position(i, j).map_or(0.0, |p| self.values[p])
    }

    /// The matrix as a dense `n × n` matrix (zeros outside the pattern), for tests and
    /// small systems: one pass over the stored entries.
    pub fn to_dense(&self) -> nalgebra::DMatrix<f64> {
        let mut d = nalgebra::DMatrix::zeros(self.n, self.n);
        for j in 0..self.n {
            for p in self.col_ptr[j]..self.col_ptr[j + 1] {
                d[(self.row_idx[p], j)] = self.values[p];
            }
        }
        d
    }

    /// Bytes of its three arrays (capacity, as allocated): `8·(n + 1)` column pointers,
    /// `8·nnz` row indices and `8·nnz` values.
    pub fn heap_bytes(&self) -> usize {
        8 * (self.col_ptr.capacity() + self.row_idx.capacity() + self.values.capacity())
    }

    /// Same pattern, values set to zero, same pattern id.
    pub fn zeros_like(&self) -> CscMatrix {
        CscMatrix {
            values: vec![0.0; self.nnz()],
            ..self.clone()
        }
    }

    /// `y = A·x`.
    pub fn mul_vec(&self, x: &[f64], y: &mut [f64]) {
        y.iter_mut().for_each(|v| *v = 0.0);
        self.mul_vec_add(1.0, x, y);
    }

    /// `y += alpha·A·x`.
    #[allow(clippy::needless_range_loop)]
    pub fn mul_vec_add(&self, alpha: f64, x: &[f64], y: &mut [f64]) {
        for j in 0..self.n {
            let xj = alpha * x[j];
            if xj == 0.0 {
                continue;
            }
            for p in self.col_ptr[j]..self.col_ptr[j + 1] {
                y[self.row_idx[p]] += self.values[p] * xj;
            }
        }
    }

    /// `self.values = sum(c_k · A_k.values)` for matrices of the same pattern.
    pub fn set_combination(&mut self, terms: &[(f64, &CscMatrix)]) {
        for v in self.values.iter_mut() {
            *v = 0.0;
        }
        for (c, a) in terms {
            debug_assert_eq!(a.pattern_id, self.pattern_id);
            if *c == 0.0 {
                continue;
            }
            for (v, av) in self.values.iter_mut().zip(&a.values) {
                *v += c * av;
            }
        }
    }

    /// Largest `|A_ij − A_ji|` relative to the largest `|A_ij|` (0 for a symmetric matrix).
    pub fn asymmetry(&self) -> f64 {
        let mut worst: f64 = 0.0;
        let mut big: f64 = 0.0;
        for j in 0..self.n {
            for p in self.col_ptr[j]..self.col_ptr[j + 1] {
                let i = self.row_idx[p];
                big = big.max(self.values[p].abs());
                worst = worst.max((self.values[p] - self.get(j, i)).abs());
            }
        }
        if big == 0.0 {
            0.0
        } else {
            worst / big
        }
    }
}

/// `ys[k] = mats[k]·xs[k]` for symmetric matrices sharing one pattern, in one pass over the
/// pattern and split by columns over `threads` threads. For a symmetric matrix the product
/// can be formed column by column as a gather, `y_j = Σ_i A_ij·x_i` (column `j` holds row
/// `j`), so threads write disjoint parts of `y` and the result does not depend on the
/// thread count (each entry is summed in the same order).
pub fn symmetric_products(
    mats: &[&CscMatrix],
    xs: &[&[f64]],
    ys: &mut [&mut [f64]],
    threads: usize,
) {
    let Some(first) = mats.first() else {
        return;
    };
    let n = first.n;
    debug_assert!(mats.iter().all(|m| m.pattern_id == first.pattern_id));
    // Runs of the same matrix (a transient evaluation's K·q, M·(a_w, …), C·(v_w, …)):
    // each stored value is then loaded once for its run.
    let same = |a: usize, b: usize| std::ptr::eq(mats[a], mats[b]);
    let runs = |r: &[usize]| {
        r.len() == 3
            && r.iter().sum::<usize>() == mats.len()
            && (1..r[1]).all(|k| same(r[0], r[0] + k))
            && (1..r[2]).all(|k| same(r[0] + r[1], r[0] + r[1] + k))
    };
    let grouped: Option<(usize, usize)> = [(2, 2), (3, 3)]
        .into_iter()
        .find(|&(a, b)| runs(&[1, a, b]));
    let kernel = |lo: usize, out: &mut Vec<&mut [f64]>| match (grouped, mats.len()) {
        (Some((2, 2)), _) => gather_runs::<2, 2>(mats, xs, lo, out),
        (Some((3, 3)), _) => gather_runs::<3, 3>(mats, xs, lo, out),
        (_, n) => gather_any(n, mats, xs, lo, out, first),
    };
    by_column_ranges(n, ys, threads, kernel);
}

/// Runs `kernel(lo, out)` on contiguous column ranges `lo..lo + out[k].len()` of `n`
/// columns, `out[k]` being those rows of `ys[k]`, one range per thread (up to `threads`,
/// and one per ~20 000 columns: below that a thread costs more than it saves). The ranges
/// are disjoint, so a kernel that forms each row alone gives the same values on any
/// thread count.
pub fn by_column_ranges(
    n: usize,
    ys: &mut [&mut [f64]],
    threads: usize,
    kernel: impl Fn(usize, &mut Vec<&mut [f64]>) + Sync,
) {
    // Below ~20 000 columns a thread costs more than it saves.
    let nt = threads.clamp(1, 16).min(n / 20_000 + 1);
    let bounds: Vec<usize> = (0..=nt).map(|t| t * n / nt).collect();
    by_column_bounds(&bounds, ys, kernel);
}

/// [`by_column_ranges`] on given ranges `bounds[t]..bounds[t + 1]` (increasing, from 0 to
/// the columns to form), one thread each.
pub fn by_column_bounds(
    bounds: &[usize],
    ys: &mut [&mut [f64]],
    kernel: impl Fn(usize, &mut Vec<&mut [f64]>) + Sync,
) {
    let nt = bounds.len() - 1;
    let n = bounds[nt];
    let mut parts: Vec<Vec<&mut [f64]>> = (0..nt).map(|_| Vec::new()).collect();
    for y in ys.iter_mut() {
        let mut rest: &mut [f64] = &mut y[..n];
        for t in 0..nt {
            let (a, b) = rest.split_at_mut(bounds[t + 1] - bounds[t]);
            parts[t].push(a);
            rest = b;
        }
    }
    if nt == 1 {
        kernel(0, &mut parts[0]);
        return;
    }
    std::thread::scope(|s| {
        for (t, mut out) in parts.into_iter().enumerate() {
            let lo = bounds[t];
            let kernel = &kernel;
            s.spawn(move || kernel(lo, &mut out));
        }
    });
}

/// [`symmetric_products`]' columns `lo..` for any number of products: `N` up to 8 with
/// the sums advancing together ([`gather_columns`]), more one after the other.
fn gather_any(
    n: usize,
    mats: &[&CscMatrix],
    xs: &[&[f64]],
    lo: usize,
    out: &mut [&mut [f64]],
    first: &CscMatrix,
) {
    match n {
        1 => gather_columns::<1>(mats, xs, lo, out),
        2 => gather_columns::<2>(mats, xs, lo, out),
        3 => gather_columns::<3>(mats, xs, lo, out),
        4 => gather_columns::<4>(mats, xs, lo, out),
        5 => gather_columns::<5>(mats, xs, lo, out),
        6 => gather_columns::<6>(mats, xs, lo, out),
        7 => gather_columns::<7>(mats, xs, lo, out),
        8 => gather_columns::<8>(mats, xs, lo, out),
        _ => {
            let (cp, ri) = (&first.col_ptr, &first.row_idx);
            for j in lo..lo + out[0].len() {
                let (a, b) = (cp[j], cp[j + 1]);
                let rows = &ri[a..b];
                for (k, (m, x)) in mats.iter().zip(xs).enumerate() {
                    let mut acc = 0.0;
                    for (v, &i) in m.values[a..b].iter().zip(rows) {
                        acc += v * x[i];
                    }
                    out[k][j - lo] = acc;
                }
            }
        }
    }
}

/// [`gather_columns`] for the products `K·x₀`, `M·x₁…x_A`, `C·x_{A+1}…x_{A+B}` (three
/// matrices on one pattern, `mats` holding `K` once, `M` `A` times and `C` `B` times in
/// that order): each stored entry's row index and each matrix's value are loaded once for
/// their run. Each sum keeps its order (storage order from `0.0`): the values are those
/// of the products formed alone, to the bit.
fn gather_runs<const A: usize, const B: usize>(
    mats: &[&CscMatrix],
    xs: &[&[f64]],
    lo: usize,
    out: &mut [&mut [f64]],
) {
    let (cp, ri) = (&mats[0].col_ptr, &mats[0].row_idx);
    let (kv, mv, cv) = (&mats[0].values, &mats[1].values, &mats[1 + A].values);
    let xk = xs[0];
    let xm: [&[f64]; A] = std::array::from_fn(|k| xs[1 + k]);
    let xc: [&[f64]; B] = std::array::from_fn(|k| xs[1 + A + k]);
    for j in lo..lo + out[0].len() {
        let (a, b) = (cp[j], cp[j + 1]);
        let rows = &ri[a..b];
        let (kv, mv, cv) = (&kv[a..b], &mv[a..b], &cv[a..b]);
        let mut acc_k = 0.0f64;
        let mut acc_m = [0.0f64; A];
        let mut acc_c = [0.0f64; B];
        for (p, &i) in rows.iter().enumerate() {
            acc_k += kv[p] * xk[i];
            let (m, c) = (mv[p], cv[p]);
            for k in 0..A {
                acc_m[k] += m * xm[k][i];
            }
            for k in 0..B {
                acc_c[k] += c * xc[k][i];
            }
        }
        out[0][j - lo] = acc_k;
        for k in 0..A {
            out[1 + k][j - lo] = acc_m[k];
        }
        for k in 0..B {
            out[1 + A + k][j - lo] = acc_c[k];
        }
    }
}

/// The columns `lo..lo + out[0].len()` of [`symmetric_products`] for `N` products: each
/// stored entry's row index is read once and the `N` sums advance together. Each sum still
/// runs over its column's entries in storage order from `0.0` (the same value, to the bit,
/// as one product alone); what changes is that the `N` chains of additions are independent
/// and overlap in the processor, instead of one chain waiting on each addition.
fn gather_columns<const N: usize>(
    mats: &[&CscMatrix],
    xs: &[&[f64]],
    lo: usize,
    out: &mut [&mut [f64]],
) {
    let (cp, ri) = (&mats[0].col_ptr, &mats[0].row_idx);
    let vals: [&[f64]; N] = std::array::from_fn(|k| &mats[k].values[..]);
    let xs: [&[f64]; N] = std::array::from_fn(|k| xs[k]);
    for j in lo..lo + out[0].len() {
        let (a, b) = (cp[j], cp[j + 1]);
        let rows = &ri[a..b];
        let v: [&[f64]; N] = std::array::from_fn(|k| &vals[k][a..b]);
        let mut acc = [0.0f64; N];
        for (p, &i) in rows.iter().enumerate() {
            for k in 0..N {
                acc[k] += v[k][p] * xs[k][i];
            }
        }
        for k in 0..N {
            out[k][j - lo] = acc[k];
        }
    }
}

/// A symmetric banded matrix of `n` columns (bands 1, 7 and 40 off the diagonal) with
/// non-integer values, so that the order of a product's additions shows in its last bits.
#[cfg(test)]
pub(crate) fn banded(n: usize) -> CscMatrix {
    let mut t = Vec::new();
    for i in 0..n {
        t.push((i, i, 3.0 + (i as f64 * 0.37).sin()));
        for d in [1, 7, 40] {
            if i + d < n {
                let v = 0.1 + (i as f64 * 0.11 + d as f64).cos() / 3.0;
                t.push((i, i + d, v));
                t.push((i + d, i, v));
            }
        }
    }
    CscMatrix::from_triplets(n, &t)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn triplets_sum_and_multiply() {
        let a = CscMatrix::from_triplets(3, &[(0, 0, 2.0), (0, 0, 1.0), (2, 1, 4.0), (1, 2, 4.0)]);
        assert_eq!(a.get(0, 0), 3.0);
        assert_eq!(a.get(1, 1), 0.0); // diagonal present, zero
        assert!(a.position(1, 1).is_some());
        let mut y = vec![0.0; 3];
        a.mul_vec(&[1.0, 2.0, 3.0], &mut y);
        assert_eq!(y, vec![3.0, 12.0, 8.0]);
        assert_eq!(a.asymmetry(), 0.0);
    }

    #[test]
    fn products_in_one_pass_are_each_the_product_alone_to_the_bit() {
        // Non-integer values, so that the order of the additions shows in the last bits:
        // each product formed within a group of 1 to 9 (9 takes the general loop) must be
        // the product formed alone.
        let n = 3_000;
        let a = banded(n);
        let mats: Vec<CscMatrix> = (0..9)
            .map(|k| {
                let mut m = a.clone();
                m.values
                    .iter_mut()
                    .enumerate()
                    .for_each(|(p, v)| *v *= 1.0 + ((p + k) as f64 * 0.013).sin() / 7.0);
                m
            })
            .collect();
        let xs: Vec<Vec<f64>> = (0..9)
            .map(|k| {
                (0..n)
                    .map(|i| ((i * (k + 2)) as f64 * 0.029).cos() / 3.0)
                    .collect()
            })
            .collect();
        // Alone: each column's entries summed in storage order from 0.0, written out here.
        let alone: Vec<Vec<f64>> = (0..9)
            .map(|k| {
                let m = &mats[k];
                (0..n)
                    .map(|j| {
                        let mut acc = 0.0;
                        for p in m.col_ptr[j]..m.col_ptr[j + 1] {
                            acc += m.values[p] * xs[k][m.row_idx[p]];
                        }
                        acc
                    })
                    .collect()
            })
            .collect();
        for group in 1..=9 {
            let mut ys: Vec<Vec<f64>> = vec![vec![f64::NAN; n]; group];
            let m: Vec<&CscMatrix> = mats[..group].iter().collect();
            let x: Vec<&[f64]> = xs[..group].iter().map(|x| &x[..]).collect();
            let mut y: Vec<&mut [f64]> = ys.iter_mut().map(|y| &mut y[..]).collect();
            symmetric_products(&m, &x, &mut y, 2);
            for k in 0..group {
                assert!(
                    ys[k]
                        .iter()
                        .zip(&alone[k])
                        .all(|(p, q)| p.to_bits() == q.to_bits()),
                    "product {k} of a group of {group}"
                );
            }
        }
        // Runs of one matrix (K once, M and C two or three times each: the kernel that
        // loads each value once for its run), against the same sums written out.
        for r in [2, 3] {
            let m: Vec<&CscMatrix> = std::iter::once(&mats[0])
                .chain(std::iter::repeat_n(&mats[1], r))
                .chain(std::iter::repeat_n(&mats[2], r))
                .collect();
            let x: Vec<&[f64]> = xs[..m.len()].iter().map(|x| &x[..]).collect();
            let mut ys: Vec<Vec<f64>> = vec![vec![f64::NAN; n]; m.len()];
            let mut y: Vec<&mut [f64]> = ys.iter_mut().map(|y| &mut y[..]).collect();
            symmetric_products(&m, &x, &mut y, 2);
            for (k, yk) in ys.iter().enumerate() {
                let mk = m[k];
                for j in 0..n {
                    let mut acc = 0.0;
                    for p in mk.col_ptr[j]..mk.col_ptr[j + 1] {
                        acc += mk.values[p] * x[k][mk.row_idx[p]];
                    }
                    assert_eq!(yk[j].to_bits(), acc.to_bits(), "run of {r}: product {k}");
                }
            }
        }
    }

    #[test]
    fn symmetric_products_match_the_scatter_product_for_any_thread_count() {
        // A symmetric tridiagonal-plus-corner matrix of 50 000 columns (so that threads are
        // used) and two value sets on the same pattern.
        let n = 50_000;
        let mut t = Vec::new();
        for i in 0..n {
            t.push((i, i, 4.0 + (i % 7) as f64));
            if i + 1 < n {
                t.push((i, i + 1, -1.0 - (i % 3) as f64));
                t.push((i + 1, i, -1.0 - (i % 3) as f64));
            }
        }
        t.push((0, n - 1, 0.5));
        t.push((n - 1, 0, 0.5));
        let a = CscMatrix::from_triplets(n, &t);
        let mut b = a.clone();
        b.values.iter_mut().for_each(|v| *v *= -0.25);
        let x: Vec<f64> = (0..n).map(|i| (i % 13) as f64 - 6.0).collect();
        let z: Vec<f64> = (0..n).map(|i| (i % 5) as f64).collect();
        let (mut ya, mut yb) = (vec![0.0; n], vec![0.0; n]);
        a.mul_vec(&x, &mut ya);
        b.mul_vec(&z, &mut yb);
        for threads in [1, 2, 3] {
            let (mut pa, mut pb) = (vec![1.0; n], vec![1.0; n]);
            symmetric_products(&[&a, &b], &[&x, &z], &mut [&mut pa, &mut pb], threads);
            // Integer-valued data: both forms are exact.
            assert_eq!(pa, ya);
            assert_eq!(pb, yb);
        }
    }
}

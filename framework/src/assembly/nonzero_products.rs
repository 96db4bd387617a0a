//! The constant matrices as their products read them: `K`, `M` and `C` each on the pattern
//! of its own non-zero values, with 32-bit row indices ([`NonzeroColumns`]), and the gather
//! kernel over them ([`nonzero_products`]).
//!
//! The three matrices share one stored pattern (the union over every element), so a
//! matrix that only some elements fill stores exact zeros at the others' entries: a
//! train–bridge model's `C` holds only its dashpots, its `M` nothing where only a spring
//! sits. Here each keeps its non-zero entries only, and a pass over the matrices reads
//! those.
//!
//! **Same bits.** A product is formed per column `j` of a symmetric matrix as the gather
//! `y_j = Σ_i A_ij·x_i`, summed in storage order from `+0.0`
//! ([`crate::sparse::symmetric_products`]); here the same sum skips the terms whose stored
//! value is `±0`. For finite `x_i` such a term is `±0`, and adding `±0` to a partial sum
//! `s` gives `s` back unless `s` is `−0` (then `−0 + +0 = +0`). A partial sum that starts
//! at `+0` is never `−0` under round-to-nearest: `+0 + (−0) = +0`, a sum of non-zeros
//! that cancels exactly is `+0`, and a non-zero plus `±0` is that non-zero. So every
//! partial sum, and the product, is the full pattern's to the bit. Where `x` holds a
//! non-finite value at a stored zero the full product has `0·∞ = NaN` and this one does
//! not; a non-finite state is not one this kernel is asked to carry (the driver stops on
//! a non-finite residual, which the non-zero terms of such an equation make).
//!
//! Row indices are `u32` (the model's equations fit: checked when built), so a pass reads
//! 12 bytes per stored entry instead of 16.

use crate::row_set::RowSet;
use crate::sparse::CscMatrix;

/// A square symmetric matrix's non-zero entries by columns, rows sorted within each column.
#[derive(Debug, Clone, Default)]
pub struct NonzeroColumns {
    /// Column pointers, length `n + 1`.
    col_ptr: Vec<usize>,
    /// Row of each entry.
    rows: Vec<u32>,
    /// Value of each entry (never `±0`).
    values: Vec<f64>,
}

impl NonzeroColumns {
    /// The entries of `a` whose value is not zero (`+0` and `−0` both left out); `None`
    /// when the equations do not fit 32-bit row indices.
    pub fn of(a: &CscMatrix) -> Option<NonzeroColumns> {
        if a.n > u32::MAX as usize {
            return None;
        }
        let nnz = a.values.iter().filter(|&&v| v != 0.0).count();
        let mut nz = NonzeroColumns {
            col_ptr: Vec::with_capacity(a.n + 1),
            rows: Vec::with_capacity(nnz),
            values: Vec::with_capacity(nnz),
        };
        nz.col_ptr.push(0);
        for j in 0..a.n {
            for p in a.col_ptr[j]..a.col_ptr[j + 1] {
                if a.values[p] != 0.0 {
                    nz.rows.push(a.row_idx[p] as u32);
                    nz.values.push(a.values[p]);
                }
            }
            nz.col_ptr.push(nz.rows.len());
        }
        Some(nz)
    }

    /// Number of columns.
    pub fn n(&self) -> usize {
        self.col_ptr.len().saturating_sub(1)
    }

    /// Number of entries kept (the non-zero values).
    pub fn nnz(&self) -> usize {
        self.rows.len()
    }

    /// Bytes of its three arrays (capacities, as allocated).
    pub fn heap_bytes(&self) -> usize {
        8 * self.col_ptr.capacity() + 4 * self.rows.capacity() + 8 * self.values.capacity()
    }
}

/// `ys[k] = mats[k]·xs[k]` for symmetric matrices given by their non-zero entries, in one
/// pass split by columns over `threads` threads (each thread writes its own rows of every
/// `y`, so the values do not depend on the thread count). A run of consecutive products
/// with the same matrix (`M·a_w, M·a_w', M·v`) loads each entry once for the run. Each
/// value is the full pattern's [`crate::sparse::symmetric_products`] to the bit (module
/// documentation).
pub fn nonzero_products(
    mats: &[&NonzeroColumns],
    xs: &[&[f64]],
    ys: &mut [&mut [f64]],
    threads: usize,
) {
    let Some(first) = mats.first() else {
        return;
    };
    let n = first.n();
    debug_assert!(mats.iter().all(|m| m.n() == n));
    debug_assert!(xs.iter().all(|x| x.len() >= n));
    let runs = same_matrix_runs(mats);
    let kernel = |lo: usize, out: &mut Vec<&mut [f64]>| gather_runs(mats, xs, &runs, lo, out);
    crate::sparse::by_column_ranges(n, ys, threads, kernel);
}

/// [`nonzero_products`] on the rows of `rows` alone: the other rows of every `y` are left
/// as they are, and each row formed is the value [`nonzero_products`] forms, to the bit
/// (the same sum). The rows are shared among the threads by count
/// ([`RowSet::balanced_bounds`]), one thread per ~20 000 rows.
pub fn nonzero_products_on(
    mats: &[&NonzeroColumns],
    xs: &[&[f64]],
    ys: &mut [&mut [f64]],
    rows: &RowSet,
    threads: usize,
) {
    let Some(first) = mats.first() else {
        return;
    };
    let n = first.n();
    debug_assert!(mats.iter().all(|m| m.n() == n));
    let runs = same_matrix_runs(mats);
    let kernel = |lo: usize, out: &mut Vec<&mut [f64]>| {
        let hi = lo + out[0].len();
        for r in rows.within(lo, hi) {
            let mut part: Vec<&mut [f64]> = out
                .iter_mut()
                .map(|y| &mut y[r.start - lo..r.end - lo])
                .collect();
            gather_runs(mats, xs, &runs, r.start, &mut part);
        }
    };
    let nt = threads.clamp(1, 16).min(rows.count() / 20_000 + 1);
    crate::sparse::by_column_bounds(&rows.balanced_bounds(n, nt), ys, kernel);
}

/// Runs of the same matrix in `mats`, at most three products each (the kernel's widths).
fn same_matrix_runs(mats: &[&NonzeroColumns]) -> Vec<(usize, usize)> {
    let mut runs: Vec<(usize, usize)> = Vec::new();
    for k in 0..mats.len() {
        match runs.last_mut() {
            Some((s, e)) if *e - *s < 3 && std::ptr::eq(mats[*s], mats[k]) => *e = k + 1,
            _ => runs.push((k, k + 1)),
        }
    }
    runs
}

/// Columns `lo..lo + out[0].len()` of every product, run by run.
fn gather_runs(
    mats: &[&NonzeroColumns],
    xs: &[&[f64]],
    runs: &[(usize, usize)],
    lo: usize,
    out: &mut [&mut [f64]],
) {
    for &(s, e) in runs {
        let (a, x, y) = (mats[s], &xs[s..e], &mut out[s..e]);
        match e - s {
            1 => gather_run::<1>(a, x, lo, y),
            2 => gather_run::<2>(a, x, lo, y),
            _ => gather_run::<3>(a, x, lo, y),
        }
    }
}

/// Columns `lo..lo + out[0].len()` of `R` products with the one matrix `a`: each entry's
/// row and value are loaded once and the `R` sums advance together, each in storage order
/// from `+0.0`.
fn gather_run<const R: usize>(
    a: &NonzeroColumns,
    xs: &[&[f64]],
    lo: usize,
    out: &mut [&mut [f64]],
) {
    let x: [&[f64]; R] = std::array::from_fn(|k| xs[k]);
    let (cp, rows, vals) = (&a.col_ptr, &a.rows, &a.values);
    for j in lo..lo + out[0].len() {
        let (s, e) = (cp[j], cp[j + 1]);
        let mut acc = [0.0f64; R];
        for (&i, &v) in rows[s..e].iter().zip(&vals[s..e]) {
            let i = i as usize;
            for k in 0..R {
                acc[k] += v * x[k][i];
            }
        }
        for k in 0..R {
            out[k][j - lo] = acc[k];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sparse::symmetric_products;

    /// A symmetric banded "K" of `n` columns ([`crate::sparse::banded`]) and a "C" on its
    /// pattern: zero everywhere but a few dashpot-like entries, some stored as `−0.0`,
    /// whole columns of zeros.
    fn matrices(n: usize) -> (CscMatrix, CscMatrix) {
        let k = crate::sparse::banded(n);
        let mut c = k.zeros_like();
        for j in 0..n {
            for p in c.col_ptr[j]..c.col_ptr[j + 1] {
                let i = c.row_idx[p];
                // Dashpots between equations 13·m and 13·m + 1 (symmetric), −0.0 at every
                // diagonal not on a dashpot, +0.0 elsewhere.
                let (a, b) = (i.min(j), i.max(j));
                c.values[p] = if a % 13 == 0 && b == a + 1 {
                    -0.3 - (a as f64 * 0.07).cos() / 5.0
                } else if a % 13 == 0 && a == b {
                    1.1 + (a as f64 * 0.05).sin() / 4.0
                } else if i == j {
                    -0.0
                } else {
                    0.0
                };
            }
        }
        (k, c)
    }

    #[test]
    fn products_over_the_nonzeros_are_the_full_pattern_products_to_the_bit() {
        let n = 45_000; // above 20 000 columns: two threads split the columns
        let (k, c) = matrices(n);
        // "M": the stiffness-like values with every third off-diagonal entry zeroed.
        let mut m = k.clone();
        for j in 0..n {
            for p in m.col_ptr[j]..m.col_ptr[j + 1] {
                if m.row_idx[p] != j && (m.row_idx[p] + j) % 3 == 0 {
                    m.values[p] = 0.0;
                }
            }
        }
        let (nk, nm, nc) = (
            NonzeroColumns::of(&k).unwrap(),
            NonzeroColumns::of(&m).unwrap(),
            NonzeroColumns::of(&c).unwrap(),
        );
        assert_eq!(nk.nnz(), k.nnz(), "K has no stored zero");
        assert!(nm.nnz() < m.nnz() && nc.nnz() < n / 4);
        // Columns whose every C value is zero (some of them −0.0) exist.
        assert!((0..n).any(|j| nc.col_ptr[j] == nc.col_ptr[j + 1] && j % 13 == 5));
        // Vectors with zeros of both signs among finite values.
        let xs: Vec<Vec<f64>> = (0..7)
            .map(|r| {
                (0..n)
                    .map(|i| match (i + r) % 11 {
                        0 => 0.0,
                        1 => -0.0,
                        _ => ((i * (r + 2)) as f64 * 0.029).cos() / 3.0,
                    })
                    .collect()
            })
            .collect();
        // K once, M three times, C three times: the verification pass's seven products.
        let full: Vec<&CscMatrix> = vec![&k, &m, &m, &m, &c, &c, &c];
        let nonzero: Vec<&NonzeroColumns> = vec![&nk, &nm, &nm, &nm, &nc, &nc, &nc];
        let x: Vec<&[f64]> = xs.iter().map(|x| &x[..]).collect();
        for threads in [1, 2] {
            let mut yf: Vec<Vec<f64>> = vec![vec![f64::NAN; n]; 7];
            let mut yn: Vec<Vec<f64>> = vec![vec![f64::NAN; n]; 7];
            let mut f: Vec<&mut [f64]> = yf.iter_mut().map(|y| &mut y[..]).collect();
            symmetric_products(&full, &x, &mut f, threads);
            let mut g: Vec<&mut [f64]> = yn.iter_mut().map(|y| &mut y[..]).collect();
            nonzero_products(&nonzero, &x, &mut g, threads);
            for (k, (a, b)) in yf.iter().zip(&yn).enumerate() {
                let same = a.iter().zip(b).all(|(p, q)| p.to_bits() == q.to_bits());
                assert!(same, "product {k} with {threads} thread(s)");
            }
            // The all-zero columns of C give +0.0 in both, not −0.0.
            assert!((0..n)
                .filter(|&j| nc.col_ptr[j] == nc.col_ptr[j + 1])
                .all(|j| yn[4][j].to_bits() == 0));
        }
        // Each product alone, and runs longer than three, against the full pattern.
        let mut yf = vec![vec![f64::NAN; n]; 4];
        let mut yn = vec![vec![f64::NAN; n]; 4];
        let mut f: Vec<&mut [f64]> = yf.iter_mut().map(|y| &mut y[..]).collect();
        symmetric_products(&[&c, &c, &c, &c], &x[..4], &mut f, 2);
        let mut g: Vec<&mut [f64]> = yn.iter_mut().map(|y| &mut y[..]).collect();
        nonzero_products(&[&nc, &nc, &nc, &nc], &x[..4], &mut g, 2);
        assert!(yf
            .iter()
            .flatten()
            .zip(yn.iter().flatten())
            .all(|(p, q)| p.to_bits() == q.to_bits()));
    }

    /// Products on a set of rows form those rows as the full products do, to the bit,
    /// and leave every other row as it was (two threads: the rows split by count).
    #[test]
    fn products_on_rows_are_the_full_products_there_and_leave_the_rest() {
        let n = 60_000;
        let (k, c) = matrices(n);
        let (nk, nc) = (
            NonzeroColumns::of(&k).unwrap(),
            NonzeroColumns::of(&c).unwrap(),
        );
        let x: Vec<Vec<f64>> = (0..3)
            .map(|r| {
                (0..n)
                    .map(|i| ((i * (r + 3)) as f64 * 0.017).sin())
                    .collect()
            })
            .collect();
        let xs: Vec<&[f64]> = x.iter().map(|v| &v[..]).collect();
        let mats = [&nk, &nc, &nc];
        let mut full = vec![vec![0.0; n]; 3];
        let mut f: Vec<&mut [f64]> = full.iter_mut().map(|y| &mut y[..]).collect();
        nonzero_products(&mats, &xs, &mut f, 2);
        // Three runs of rows, one of them the last row.
        let mask: Vec<bool> = (0..n)
            .map(|i| (100..30_000).contains(&i) || (41_000..41_010).contains(&i) || i == n - 1)
            .collect();
        let rows = RowSet::from_mask(&mask);
        let mut part = vec![vec![7.5; n]; 3];
        let mut p: Vec<&mut [f64]> = part.iter_mut().map(|y| &mut y[..]).collect();
        nonzero_products_on(&mats, &xs, &mut p, &rows, 2);
        for (a, b) in full.iter().zip(&part) {
            for i in 0..n {
                if mask[i] {
                    assert_eq!(a[i].to_bits(), b[i].to_bits(), "row {i}");
                } else {
                    assert_eq!(b[i], 7.5, "row {i} left as it was");
                }
            }
        }
    }

    #[test]
    fn both_zeros_are_left_out_and_the_rest_kept_in_order() {
        let a = CscMatrix::from_triplets(
            3,
            &[
                (0, 0, 2.0),
                (1, 0, -0.0),
                (0, 1, 0.0),
                (1, 1, 5.0),
                (2, 1, 1.5),
                (1, 2, 1.5),
            ],
        );
        let nz = NonzeroColumns::of(&a).unwrap();
        assert_eq!(nz.col_ptr, vec![0, 1, 3, 4]);
        assert_eq!(nz.rows, vec![0, 1, 2, 1]);
        assert_eq!(nz.values, vec![2.0, 5.0, 1.5, 1.5]);
        assert_eq!(nz.n(), 3);
    }
}

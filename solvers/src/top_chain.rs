//! Second-level condensation of the top system: the separators of a chain of blocks,
//! grouped and condensed onto the group's ends once, so that a Newton iteration factors only
//! the equations near the variable elements.
//!
//! The top system `S = S_A + V_TT` of [`crate::partition`] is, on a long structure, a chain:
//! block `b`'s condensation couples its two separators, and `A` couples a separator only to
//! itself and to block interiors. Split the blocks into groups of consecutive blocks. A
//! group's *inner* equations are the base top equations that only its own blocks touch (the
//! separators between its blocks); its *ends* are the other top equations its blocks or its
//! inner equations are coupled to (the separators it shares with the neighbouring groups).
//! Let `M` be the group's part of `S_A` on `inner ∪ ends`: its blocks' corrections `−C_b`
//! and the entries of `A_TT` with a row or a column inner (the entries of `A_TT` between two
//! ends stay in the rest of `S_A`). Then `S_A = S_rest + Σ_g M_g`, and no two groups share an
//! inner equation nor couple their inner equations to each other. While no variable element
//! and no promoted equation lies in a group, its rows of `S` are those of `S_A`, constant,
//! and block elimination of its inner equations `i` onto its ends `e` gives
//!
//! ```text
//! S_red = S_rest + Σ_g (M_ee − M_ei·M_ii⁻¹·M_ie)          on the remaining equations,
//! g_e  ← g_e − M_ei·y_i,   y_i = M_ii⁻¹·g_i                  (forward, per group),
//! x_i  = y_i − M_ii⁻¹·M_ie·x_e                                (back, per group),
//! ```
//!
//! the Schur complement of `S` onto what remains, exact in exact arithmetic (the block form
//! of Gaussian elimination). `M_ii` is a principal submatrix of the Schur complement `S_A`
//! of the positive definite `A`, hence positive definite itself: it is factored by dense
//! Cholesky, and its factor, `Y = M_ii⁻¹·M_ie` and `M_ee − M_ei·Y` are kept from one
//! factorization of `A`'s blocks to the next (a new `Δt`). A group far from the train is
//! condensed once and reused at every iteration and every step until a wheel arrives; each
//! iteration forms and factors only the reduced system (the group ends, the groups where the
//! wheels are, the carriages and the promoted equations).
//!
//! **Across ranks** (not done here: rank 0 condenses every group from what it received).
//! The groups are consecutive blocks, and a rank owns a contiguous range of blocks, so groups
//! can be cut at the ranks' ranges: each rank would condense the groups inside its range
//! (it holds their corrections) and send rank 0 only `M_ee − M_ei·Y` on the group ends, and
//! for a solve the forward pieces `M_ei·y_i`; rank 0 would solve the reduced system and send
//! back `x_e`, from which each rank recovers its groups' inner equations.

use std::ops::Range;

const NONE: u32 = u32::MAX;
const MANY: u32 = u32::MAX - 1;

/// One group of consecutive blocks and its condensation.
pub(crate) struct Group {
    /// The blocks of the group.
    pub(crate) blocks: Range<usize>,
    /// Inner equations (global, sorted): touched only by this group.
    pub(crate) inner: Vec<usize>,
    /// End equations (global, sorted): the group's other top equations.
    pub(crate) ends: Vec<usize>,
    /// The condensation, once formed for the current block factors.
    pub(crate) cond: Option<Condensation>,
    /// Whether the condensation failed for the current block factors (`M_ii` not positive
    /// definite to round-off): the group then stays in the reduced system.
    pub(crate) failed: bool,
}

/// A group's part of `S_A` and its elimination onto the ends (module documentation).
pub(crate) struct Condensation {
    /// `M` on `inner ++ ends`, column-major `(ni + ne)²`.
    m: Vec<f64>,
    /// The Cholesky factor `L` of `M_ii = L·Lᵀ` (lower triangle, column-major `ni × ni`):
    /// solves with it are backward stable, unlike products with an explicit inverse.
    l: Vec<f64>,
    /// `Y = M_ii⁻¹·M_ie`, column-major `ni × ne`.
    y: Vec<f64>,
    /// `M_ee − M_ei·Y`, column-major `ne × ne`.
    pub(crate) schur: Vec<f64>,
}

/// The groups of the top chain.
pub(crate) struct TopChain {
    pub(crate) groups: Vec<Group>,
    /// The group whose inner equation each equation is (`NONE`: none).
    pub(crate) inner_of: Vec<u32>,
}

impl TopChain {
    /// Groups of `per_group` consecutive blocks, their inner and end equations, from the
    /// pattern of `A` (`col_ptr`, `row_idx`), each block's boundary and the block of each
    /// equation (`NONE`: top).
    pub(crate) fn build(
        col_ptr: &[usize],
        row_idx: &[usize],
        boundaries: &[&[usize]],
        block_of: &[u32],
        per_group: usize,
    ) -> TopChain {
        let n = block_of.len();
        let per_group = per_group.max(1);
        let ngroups = boundaries.len().div_ceil(per_group);
        // The one group whose blocks touch each top equation (`MANY`: several).
        let mut touch = vec![NONE; n];
        for (b, boundary) in boundaries.iter().enumerate() {
            let g = (b / per_group) as u32;
            for &t in boundary.iter() {
                touch[t] = match touch[t] {
                    NONE => g,
                    x if x == g => g,
                    _ => MANY,
                };
            }
        }
        let candidate = |t: usize| touch[t] != NONE && touch[t] != MANY;
        // Two candidates of different groups coupled through `A` would couple the groups'
        // inner equations: both become ends.
        let mut demoted = vec![false; n];
        for t in 0..n {
            if !candidate(t) {
                continue;
            }
            for &r in &row_idx[col_ptr[t]..col_ptr[t + 1]] {
                if block_of[r] == NONE && candidate(r) && touch[r] != touch[t] {
                    demoted[t] = true;
                    demoted[r] = true;
                }
            }
        }
        let mut inner_of = vec![NONE; n];
        let mut inner: Vec<Vec<usize>> = vec![Vec::new(); ngroups];
        for t in 0..n {
            if candidate(t) && !demoted[t] {
                inner_of[t] = touch[t];
                inner[touch[t] as usize].push(t);
            }
        }
        let groups = inner
            .into_iter()
            .enumerate()
            .map(|(g, inner)| {
                let blocks = g * per_group..((g + 1) * per_group).min(boundaries.len());
                let mut ends: Vec<usize> = boundaries[blocks.clone()]
                    .iter()
                    .flat_map(|b| b.iter().copied())
                    .chain(inner.iter().flat_map(|&t| {
                        row_idx[col_ptr[t]..col_ptr[t + 1]]
                            .iter()
                            .copied()
                            .filter(|&r| block_of[r] == NONE)
                    }))
                    .filter(|&r| inner_of[r] != g as u32)
                    .collect();
                ends.sort_unstable();
                ends.dedup();
                Group {
                    blocks,
                    inner,
                    ends,
                    cond: None,
                    failed: false,
                }
            })
            .collect();
        TopChain { groups, inner_of }
    }

    /// Forgets every condensation (the block factors changed).
    pub(crate) fn clear(&mut self) {
        for g in &mut self.groups {
            g.cond = None;
            g.failed = false;
        }
    }

    /// Bytes held (capacities).
    pub(crate) fn heap_bytes(&self) -> usize {
        let mut bytes = 4 * self.inner_of.capacity();
        for g in &self.groups {
            bytes += 8 * (g.inner.capacity() + g.ends.capacity());
            if let Some(c) = &g.cond {
                bytes +=
                    8 * (c.m.capacity() + c.l.capacity() + c.y.capacity() + c.schur.capacity());
            }
        }
        bytes
    }
}

impl Group {
    /// Local index of global equation `g` in `inner ++ ends`.
    fn local(&self, g: usize) -> Option<usize> {
        self.inner.binary_search(&g).ok().or_else(|| {
            self.ends
                .binary_search(&g)
                .ok()
                .map(|k| self.inner.len() + k)
        })
    }

    /// Forms the group's part `M` of `S_A` from `A` (its columns of top equations), the
    /// blocks' boundaries and corrections `C_b` (`|B_b|²`, column-major), and eliminates
    /// the inner equations. `false` (and no condensation) when `M_ii` is not positive
    /// definite.
    pub(crate) fn condense(
        &mut self,
        a: &railfem_framework::sparse::CscMatrix,
        block_of: &[u32],
        boundaries: &[&[usize]],
        corrections: &[&[f64]],
    ) -> bool {
        let (ni, ne) = (self.inner.len(), self.ends.len());
        let nl = ni + ne;
        let mut m = vec![0.0; nl * nl];
        for (boundary, c) in boundaries.iter().zip(corrections) {
            let nb = boundary.len();
            let local: Vec<usize> = boundary
                .iter()
                .map(|&g| {
                    self.local(g)
                        .expect("a block's boundary is inner or an end")
                })
                .collect();
            for (cj, &lj) in local.iter().enumerate() {
                for (ci, &li) in local.iter().enumerate() {
                    m[li + lj * nl] -= c[ci + cj * nb];
                }
            }
        }
        for (lj, &j) in self.inner.iter().chain(&self.ends).enumerate() {
            for p in a.col_ptr[j]..a.col_ptr[j + 1] {
                let r = a.row_idx[p];
                if block_of[r] != NONE {
                    continue;
                }
                if let Some(lr) = self.local(r) {
                    if lr < ni || lj < ni {
                        m[lr + lj * nl] += a.values[p];
                    }
                }
            }
        }
        let mut l: Vec<f64> = (0..ni)
            .flat_map(|j| m[j * nl..j * nl + ni].iter().copied())
            .collect();
        if !cholesky(&mut l, ni) {
            self.failed = true;
            return false;
        }
        let mut y = vec![0.0; ni * ne];
        for e in 0..ne {
            let col = &mut y[e * ni..(e + 1) * ni];
            col.copy_from_slice(&m[(ni + e) * nl..(ni + e) * nl + ni]);
            cholesky_solve(&l, ni, col);
        }
        let mut schur = vec![0.0; ne * ne];
        for f in 0..ne {
            let yf = &y[f * ni..(f + 1) * ni];
            for e in 0..ne {
                let mei = (0..ni).map(|i| m[(ni + e) + i * nl] * yf[i]).sum::<f64>();
                schur[e + f * ne] = m[(ni + e) + (ni + f) * nl] - mei;
            }
        }
        self.cond = Some(Condensation { m, l, y, schur });
        true
    }

    /// Forward elimination of a right-hand side `x` (top numbering, `at` the top position of
    /// each global equation): returns `y_i = M_ii⁻¹·g_i` and subtracts `M_ei·y_i` from the
    /// ends.
    pub(crate) fn forward(&self, x: &mut [f64], at: impl Fn(usize) -> usize) -> Vec<f64> {
        let c = self.cond.as_ref().expect("condensed");
        let (ni, ne) = (self.inner.len(), self.ends.len());
        let nl = ni + ne;
        let mut yi: Vec<f64> = self.inner.iter().map(|&g| x[at(g)]).collect();
        cholesky_solve(&c.l, ni, &mut yi);
        for (e, &g) in self.ends.iter().enumerate() {
            let s: f64 = (0..ni).map(|i| c.m[(ni + e) + i * nl] * yi[i]).sum();
            x[at(g)] -= s;
        }
        yi
    }

    /// Back substitution: the inner equations `x_i = y_i − Y·x_e` into `x`.
    pub(crate) fn back(&self, x: &mut [f64], mut yi: Vec<f64>, at: impl Fn(usize) -> usize) {
        let c = self.cond.as_ref().expect("condensed");
        let ni = self.inner.len();
        for (e, &g) in self.ends.iter().enumerate() {
            let xe = x[at(g)];
            if xe != 0.0 {
                for (v, yv) in yi.iter_mut().zip(&c.y[e * ni..(e + 1) * ni]) {
                    *v -= yv * xe;
                }
            }
        }
        for (&g, v) in self.inner.iter().zip(yi) {
            x[at(g)] = v;
        }
    }

    /// `out += M·x` on the group's equations (top numbering through `at`).
    pub(crate) fn add_times(&self, x: &[f64], out: &mut [f64], at: impl Fn(usize) -> usize) {
        let c = self.cond.as_ref().expect("condensed");
        let nl = self.inner.len() + self.ends.len();
        let pos: Vec<usize> = self
            .inner
            .iter()
            .chain(&self.ends)
            .map(|&g| at(g))
            .collect();
        for (lj, &pj) in pos.iter().enumerate() {
            let xj = x[pj];
            if xj == 0.0 {
                continue;
            }
            for (li, &pi) in pos.iter().enumerate() {
                out[pi] += c.m[li + lj * nl] * xj;
            }
        }
    }
}

/// Dense Cholesky `M = L·Lᵀ` in place (column-major `n × n`, the lower triangle is read and
/// `L` written there). `false` at a pivot that is not positive.
fn cholesky(m: &mut [f64], n: usize) -> bool {
    for j in 0..n {
        let mut d = m[j + j * n];
        for k in 0..j {
            d -= m[j + k * n] * m[j + k * n];
        }
        if d.is_nan() || d <= 0.0 {
            return false;
        }
        let d = d.sqrt();
        m[j + j * n] = d;
        for i in j + 1..n {
            let mut s = m[i + j * n];
            for k in 0..j {
                s -= m[i + k * n] * m[j + k * n];
            }
            m[i + j * n] = s / d;
        }
    }
    true
}

/// Solves `L·Lᵀ·x = b` in place with the factor of [`cholesky`].
fn cholesky_solve(l: &[f64], n: usize, b: &mut [f64]) {
    for j in 0..n {
        b[j] /= l[j + j * n];
        let bj = b[j];
        for i in j + 1..n {
            b[i] -= l[i + j * n] * bj;
        }
    }
    for j in (0..n).rev() {
        let mut s = b[j];
        for i in j + 1..n {
            s -= l[i + j * n] * b[i];
        }
        b[j] = s / l[j + j * n];
    }
}

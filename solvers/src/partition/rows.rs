//! The residual's rows per rank: which equations a rank of a shared model forms the
//! residual of, and the two collectives that make the rest of the Newton iteration
//! independent of the rows the other ranks hold.
//!
//! **Owned rows.** Rank `k` owns the interior equations of its blocks and rank 0 also the
//! base top set (separators and carriages): the rows of the right-hand side its share of
//! the solver reads ([`Partitioned::columns_read`]), and the owned rows of all ranks split
//! the equations. A rank keeps the constant matrices' columns of its owned rows and of the
//! base top set ([`Partitioned::rows_kept`]; every rank keeps the base top set's, so that
//! the constant part between top equations is at hand without a message). Interiors of
//! different blocks are never coupled, so those columns are all a rank's rows touch.
//!
//! **Norms.** The convergence test needs `|r|`, `|f_int|` and `|M·a_w|` over every
//! equation. Each rank sums the squares over each of its blocks' interiors (in equation
//! order), rank 0 also over the base top set, and every rank receives every piece
//! ([`Partitioned::sums_of_squares`]): the totals are added in block order, the base top
//! set last, so they are the same on every rank and for any number of ranks (they differ
//! from one process's sums over fixed chunks of the equations by round-off only).
//!
//! The energy balance's products and works over a step
//! ([`crate::energy::EnergyLedger::record`]) are summed the same way
//! ([`Partitioned::sums_over_rows`]).
//!
//! The Newton check's element-force reference (`√(Σ_e |f_e|²)` over the variable elements,
//! which every rank evaluates whole) travels in the same all-gather as the norms: every rank
//! takes the largest of the ranks' sums ([`Partitioned::sums_of_squares_and_max`]), so all
//! reach the same decision and the reference is one process's.
//!
//! **Where the residual is largest.** A failed step's message and `--trace` name the
//! equation with the largest residual; each rank knows only its owned rows, so the ranks
//! exchange their candidates ([`Partitioned::largest_over_rows`]) and every rank names
//! the equation one process would.
//!
//! **Top columns.** The condensed Newton's top iterations need the constant matrices
//! between top equations. A promoted equation's column belongs to the owner of its block;
//! [`Partitioned::share_top_columns`] sends each to every rank, as the owner encoded it.

use super::{Partitioned, NONE};

impl Partitioned {
    /// Rank of the owner of equation `i`'s row: its block's owner, rank 0 for the base top
    /// set.
    fn row_owner(&self, i: usize) -> usize {
        match self.block_of.get(i) {
            Some(&b) if b != NONE => self
                .ranges
                .iter()
                .position(|r| r.contains(&(b as usize)))
                .unwrap_or(0),
            _ => 0,
        }
    }

    /// Across ranks, after [`Partitioned::prepare`]: the equations whose columns of the
    /// constant matrices this rank keeps — its blocks' interiors and the base top set
    /// (module documentation). `None` in one process or before the split.
    pub fn rows_kept(&self) -> Option<Vec<bool>> {
        let mut keep = self.columns_read()?;
        for &i in &self.base_top {
            keep[i] = true;
        }
        Some(keep)
    }

    /// Rows this rank owns: its blocks' interior equations, and on rank 0 the base top set
    /// (every equation in one process).
    pub fn rows_owned(&self) -> usize {
        if self.comm.is_none() {
            return self.n;
        }
        let interiors: usize = self.blocks[self.owned()].iter().map(|b| b.all.len()).sum();
        interiors
            + if self.is_root() {
                self.base_top.len()
            } else {
                0
            }
    }

    /// Across ranks: `Σ_i x[i]²` over every equation, for each `x` of `xs`, each rank
    /// contributing its owned rows and the pieces added in block order (module
    /// documentation); the same on every rank. `None` in one process or before the split
    /// (no collective).
    pub fn sums_of_squares(&mut self, xs: &[&[f64]]) -> Option<Vec<f64>> {
        self.sums_of_squares_and_max(xs, None).map(|(sums, _)| sums)
    }

    /// Across ranks: [`Partitioned::sums_of_squares`] of `xs` and, in the same all-gather,
    /// the largest of the ranks' `local` values (`None` adds nothing to the message and
    /// gives `-∞`). The Newton check reduces each rank's `Σ_e |f_e|²` this way: every rank
    /// evaluates every variable element, so each holds one process's sum, and the largest
    /// is the same on every rank even where the ranks' round-off differed. `None` in one
    /// process or before the split (no collective).
    pub fn sums_of_squares_and_max(
        &mut self,
        xs: &[&[f64]],
        local: Option<f64>,
    ) -> Option<(Vec<f64>, f64)> {
        self.gather_sums(
            xs.len(),
            &|rows, out| {
                for (o, x) in out.iter_mut().zip(xs) {
                    *o = rows.iter().fold(0.0, |s, &i| s + x[i] * x[i]);
                }
            },
            local,
        )
    }

    /// Across ranks: `m` sums over every equation, each rank forming with `part(rows,
    /// out)` the `m` sums of each of its blocks' interiors (`rows` in equation order), rank
    /// 0 also those of the base top set; every rank receives every piece (one all-gather)
    /// and adds them in block order, the base top set last. The totals are therefore the
    /// same on every rank and for any number of ranks. `None` in one process or before the
    /// split (no collective).
    pub fn sums_over_rows(
        &mut self,
        m: usize,
        part: &dyn Fn(&[usize], &mut [f64]),
    ) -> Option<Vec<f64>> {
        self.gather_sums(m, part, None).map(|(sums, _)| sums)
    }

    /// [`Partitioned::sums_over_rows`], each rank's piece ending with its `extra` value if
    /// given; returns the sums and the largest of the ranks' extras (`-∞` without).
    fn gather_sums(
        &mut self,
        m: usize,
        part: &dyn Fn(&[usize], &mut [f64]),
        extra: Option<f64>,
    ) -> Option<(Vec<f64>, f64)> {
        if self.comm.is_none() || self.n == 0 {
            return None;
        }
        let mut local = vec![0.0; (self.owned().len() + 1) * m + 1];
        let mut k = 0;
        for b in &self.blocks[self.owned()] {
            part(&b.all, &mut local[k..k + m]);
            k += m;
        }
        if self.is_root() {
            part(&self.base_top, &mut local[k..k + m]);
            k += m;
        }
        if let Some(x) = extra {
            local[k] = x;
            k += 1;
        }
        local.truncate(k);
        let comm = self.comm.as_mut().expect("across ranks");
        let pieces = comm.all_gather(&local);
        let mut total = vec![0.0; m];
        let mut largest = f64::NEG_INFINITY;
        // Rank order is block order; rank 0's base top set comes after every block.
        let mut top_part = Vec::new();
        for (r, piece) in pieces.iter().enumerate() {
            let blocks = self.ranges[r].len() * m;
            for chunk in piece[..blocks].chunks(m) {
                for (t, v) in total.iter_mut().zip(chunk) {
                    *t += v;
                }
            }
            if r == 0 {
                top_part = piece[blocks..blocks + m].to_vec();
            }
            if extra.is_some() {
                largest = largest.max(piece[piece.len() - 1]);
            }
        }
        for (t, v) in total.iter_mut().zip(&top_part) {
            *t += v;
        }
        Some((total, largest))
    }

    /// Across ranks: the largest `|x[i]|` over every equation and its `i`, each rank
    /// searching its owned rows (its blocks' interiors, rank 0 also the base top set) and
    /// every rank receiving every rank's candidate (one all-gather). Ties go to the lowest
    /// `i` and zeros never count, as in one process's scan in equation order that keeps the
    /// first strictly larger entry, so the answer is that scan's on every rank, for any
    /// number of ranks: `(0.0, 0)` if every entry is zero (or NaN). `None` in one process or
    /// before the split (no collective).
    pub fn largest_over_rows(&mut self, x: &[f64]) -> Option<(f64, usize)> {
        if self.comm.is_none() || self.n == 0 {
            return None;
        }
        let better =
            |(v, i): (f64, usize), (bv, bi): (f64, usize)| v > bv || (v == bv && v > 0.0 && i < bi);
        let mut best = (0.0, usize::MAX);
        let mut scan = |rows: &[usize]| {
            for &i in rows {
                if better((x[i].abs(), i), best) {
                    best = (x[i].abs(), i);
                }
            }
        };
        for b in &self.blocks[self.owned()] {
            scan(&b.all);
        }
        if self.is_root() {
            scan(&self.base_top);
        }
        // An index below 2^53 travels exactly as an f64; `usize::MAX` marks "none".
        let mine = [
            best.0,
            if best.1 == usize::MAX {
                -1.0
            } else {
                best.1 as f64
            },
        ];
        let pieces = self.comm.as_mut().expect("across ranks").all_gather(&mine);
        let mut found = (0.0, usize::MAX);
        for piece in &pieces {
            if piece[1] >= 0.0 && better((piece[0], piece[1] as usize), found) {
                found = (piece[0], piece[1] as usize);
            }
        }
        Some(if found.1 == usize::MAX {
            (0.0, 0)
        } else {
            found
        })
    }

    /// Across ranks: for every top equation of the last factorization (in top order), its
    /// column as `encode` writes it — on the rank that keeps it: the base top set's on
    /// every rank, a promoted equation's by its block's owner, which sends it to every
    /// other rank (one all-gather). `encode(j)` is called only for columns this rank
    /// keeps. `None` in one process (no collective).
    pub fn share_top_columns(
        &mut self,
        encode: &mut dyn FnMut(usize) -> Vec<f64>,
    ) -> Option<Vec<Vec<f64>>> {
        let me = self.comm.as_ref()?.rank();
        let promoted = |p: &Partitioned, j: usize| p.block_of[j] != NONE;
        let mut mine = Vec::new();
        for &j in &self.top {
            if promoted(self, j) && self.row_owner(j) == me {
                let col = encode(j);
                mine.push(col.len() as f64);
                mine.extend(col);
            }
        }
        let pieces = self.comm.as_mut().expect("across ranks").all_gather(&mine);
        let mut at = vec![0usize; pieces.len()];
        let mut out = Vec::with_capacity(self.top.len());
        for k in 0..self.top.len() {
            let j = self.top[k];
            if promoted(self, j) {
                let r = self.row_owner(j);
                let len = pieces[r][at[r]] as usize;
                out.push(pieces[r][at[r] + 1..at[r] + 1 + len].to_vec());
                at[r] += 1 + len;
            } else {
                out.push(encode(j));
            }
        }
        Some(out)
    }
}

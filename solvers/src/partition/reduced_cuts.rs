//! Blocks given by the caller: each equation carries a *bin* (for the reduced far field,
//! the stretch of track between two span joints its node lies in), and each bin of a
//! large connected component becomes one block, in place of the breadth-first level sets.
//!
//! **The separator.** Interiors of different blocks must never be coupled by `A`
//! (module documentation of [`crate::partition`]). For every coupling `A_ij ≠ 0` with
//! `bin(i) < bin(j)`, equation `j` (the one in the later bin) goes to the top set. Every
//! coupling between two bins then has an end on top, so what is left of the bins are
//! interiors that see each other only through the top set — whatever the bins are: a bad
//! binning makes large separators, never a wrong split. For a viaduct binned by station at
//! its span joints the separator is small: the rail nodes at a joint (the rails run on
//! across it) and the girder end node that shares the joint's station with the next span.
//!
//! Bins are what makes blocks congruent: the partition's level sets follow the graph, so
//! two level-set blocks rarely have equal matrices, while a block of one span (or of `g`
//! spans starting at a joint) is a translated copy of the others, and one Craig–Bampton
//! reduction serves them all ([`crate::reduced::blocks`]).

use super::Partitioned;
use railfem_framework::sparse::CscMatrix;
use std::collections::BTreeMap;

impl Partitioned {
    /// Gives the blocks from now on by `bins` (one per equation; module documentation),
    /// or returns to the breadth-first level sets (`None`). The structure is built anew
    /// at the next [`Partitioned::prepare`] or factorization (every block factored again),
    /// as for a new pattern; components smaller than a block stay on top as before, and
    /// bins of another length than the matrix are ignored.
    pub fn set_block_bins(&mut self, bins: Option<Vec<u32>>) {
        self.bins = bins;
        self.release_factors();
        self.pattern_id = 0;
        self.n = 0;
    }

    /// Splits one connected `component` of `a`'s graph into a block per bin and the top
    /// equations that separate them (module documentation).
    pub(super) fn split_by_bins(&mut self, a: &CscMatrix, component: &[usize]) {
        let bins = self.bins.as_ref().expect("bins given");
        let mut on_top = vec![false; a.n];
        for &j in component {
            for &i in &a.row_idx[a.col_ptr[j]..a.col_ptr[j + 1]] {
                // Both ends are checked: the pattern may hold one triangle only.
                match bins[i].cmp(&bins[j]) {
                    std::cmp::Ordering::Less => on_top[j] = true,
                    std::cmp::Ordering::Greater => on_top[i] = true,
                    std::cmp::Ordering::Equal => {}
                }
            }
        }
        let mut by_bin: BTreeMap<u32, Vec<usize>> = BTreeMap::new();
        for &g in component {
            if on_top[g] {
                self.base_top.push(g);
            } else {
                by_bin.entry(bins[g]).or_default().push(g);
            }
        }
        for (_, all) in by_bin {
            self.push_block(all);
        }
    }
}

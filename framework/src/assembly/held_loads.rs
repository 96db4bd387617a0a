//! The external force on part of the equations ([`Assembler::external_force_on`]): the
//! rows the activity window still forms, while the others (its *deep* held rows,
//! `railfem_solvers::held_rows`) keep the value an earlier call wrote.
//!
//! **Why the rows left out keep the right value.** The force is the constant gravity
//! `f_g` plus loads that act on a few equations each: the carried masses' `M·(g − a_ref)`
//! (the vehicles), the gravity of masses that change between steps, and the model's own
//! loads. The window's caller forms every row for a few steps after the held set changes,
//! so a row left out holds `0 + f_g,i` from an earlier call, as this call would write it.
//! That holds only if nothing else reaches it: [`Assembler::loads_within`] asks that the
//! model have no loads of its own (nodal, moving, ground, registered: they may act
//! anywhere and change in time) and that every equation a carried mass or a changing mass
//! acts on be in the set; otherwise the caller forms every row. On the rows formed the
//! values are those of [`Assembler::external_force`] to the bit: the same terms added in
//! the same order.

use super::Assembler;
use crate::model::Model;
use crate::row_set::RowSet;
use std::ops::Range;

/// The parts of `0..n` to form: all of it without `rows`.
pub(super) fn parts(rows: Option<&RowSet>, n: usize) -> Vec<Range<usize>> {
    match rows {
        Some(r) => r.within(0, n).collect(),
        None => std::iter::once(0..n).collect(),
    }
}

/// Whether equation `i` is in `rows`.
fn contains(rows: &RowSet, i: usize) -> bool {
    rows.within(i, i + 1).next().is_some()
}

impl Assembler {
    /// Whether every load but the constant gravity acts on rows of `rows` alone (module
    /// documentation).
    pub(super) fn loads_within(&self, model: &Model, rows: &RowSet) -> bool {
        if !model.loads.is_empty() {
            return false;
        }
        let elements = self
            .carried_mass
            .iter()
            .map(|(ei, _)| *ei)
            .chain(self.gravity_variable.iter().copied());
        for ei in elements {
            for &(node, d) in &self.maps[ei].dofs {
                if self
                    .dofmap
                    .terms_at(node, d)
                    .any(|(e, _)| !contains(rows, e))
                {
                    return false;
                }
            }
        }
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The parts of a set, and membership at the ends of its ranges.
    #[test]
    fn parts_and_membership_follow_the_ranges() {
        let mask: Vec<bool> = (0..10).map(|i| !(3..7).contains(&i)).collect();
        let rows = RowSet::from_mask(&mask);
        assert_eq!(parts(Some(&rows), 10), vec![0..3, 7..10]);
        assert_eq!(parts(None, 10), std::iter::once(0..10).collect::<Vec<_>>());
        let inside: Vec<bool> = (0..10).map(|i| contains(&rows, i)).collect();
        assert_eq!(inside, mask);
    }
}

//! The columns `A_II⁻¹·e_p` of a block's base factor kept for equations that left the
//! block's promoted set, so that a wheel reaching rail nodes another wheel has just left
//! (the rear axle of a bogie, 2.5 m behind the front one) finds its columns of `Z`
//! instead of solving them again (module documentation of `partition.rs`, *promotions*).
//!
//! A column depends on the base factor and the equation alone, so a kept column is the one
//! a new solve would give, to the bit (the solve does each column's operations
//! independently of which others it is solved with: [`crate::compact_factor`]). The
//! columns live in the block's [`super::BlockState`] and go with its base factor (a new
//! `A`); the partitioned solver drops them too when the block's promoted set empties (the
//! train has left it), so that only the blocks under the train hold any. Only columns that
//! were solved are kept when their equation leaves the promoted set: a column the spare
//! gave back is left again by the wheel behind, and the next wheel after that one is a
//! carriage behind (7.5 m and more), by when the spare would have dropped it.

use std::collections::VecDeque;

/// At most this many columns are kept per block, the longest kept first dropped: the
/// columns a bogie's front axle leaves before its rear axle reaches them are the rail
/// nodes of its 2.5 m axle spacing (40 nodes of two rails at the paper's 0.0625 m
/// elements, with six promoted DOFs each: 480 columns), and a block of 3 000 equations
/// (about 9 m of the paper's viaduct) can hold two bogies, of adjacent carriages, at once.
pub(super) const SPARE_COLUMNS: usize = 1024;

/// Kept columns of one block, by local interior equation, the most recently dropped last.
#[derive(Default)]
pub(super) struct SpareColumns {
    columns: VecDeque<(usize, Vec<f64>)>,
}

impl SpareColumns {
    /// Keeps column `column` of local equation `local` (replacing a kept one of the same
    /// equation), dropping the longest kept beyond [`SPARE_COLUMNS`].
    pub(super) fn keep(&mut self, local: usize, column: &[f64]) {
        let mut storage = match self.columns.iter().position(|c| c.0 == local) {
            Some(k) => self.columns.remove(k).map(|c| c.1),
            None if self.columns.len() >= SPARE_COLUMNS => self.columns.pop_front().map(|c| c.1),
            None => None,
        }
        .unwrap_or_default();
        storage.clear();
        storage.extend_from_slice(column);
        self.columns.push_back((local, storage));
    }

    /// Takes the kept column of local equation `local`, if any.
    pub(super) fn take(&mut self, local: usize) -> Option<Vec<f64>> {
        let k = self.columns.iter().position(|c| c.0 == local)?;
        self.columns.remove(k).map(|c| c.1)
    }

    /// Drops every kept column.
    pub(super) fn clear(&mut self) {
        self.columns.clear();
    }

    /// Number of kept columns.
    #[cfg(test)]
    pub(super) fn len(&self) -> usize {
        self.columns.len()
    }

    /// Bytes held (capacities).
    pub(super) fn heap_bytes(&self) -> usize {
        self.columns
            .iter()
            .map(|c| 8 * c.1.capacity() + 32)
            .sum::<usize>()
            + 32 * self.columns.capacity()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A kept column comes back as given, once; a re-kept equation replaces its column;
    /// beyond the limit the longest kept goes first.
    #[test]
    fn kept_columns_come_back_once_and_the_oldest_go_first() {
        let mut s = SpareColumns::default();
        s.keep(7, &[1.0, 2.0]);
        s.keep(3, &[3.0, 4.0]);
        s.keep(7, &[5.0, 6.0]);
        assert_eq!(s.len(), 2);
        assert_eq!(s.take(7), Some(vec![5.0, 6.0]));
        assert_eq!(s.take(7), None);
        for l in 0..SPARE_COLUMNS {
            s.keep(100 + l, &[l as f64]);
        }
        assert_eq!(s.len(), SPARE_COLUMNS);
        // Equation 3 was kept first: dropped by the last keep.
        assert_eq!(s.take(3), None);
        assert_eq!(s.take(100), Some(vec![0.0]));
        s.clear();
        assert_eq!(s.len(), 0);
    }
}

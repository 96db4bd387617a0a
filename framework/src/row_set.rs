//! A set of equations as sorted, disjoint index ranges ([`RowSet`]): the rows a pass over
//! the equations touches when it may leave the others as they are (the activity window's
//! held rows, `railfem_solvers::held_rows`).

use std::ops::Range;

/// Sorted, disjoint, non-empty index ranges (adjacent ranges merged) and their total
/// length.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct RowSet {
    ranges: Vec<Range<usize>>,
    count: usize,
}

impl RowSet {
    /// The indices `i` with `mask[i]`.
    pub fn from_mask(mask: &[bool]) -> RowSet {
        let mut ranges: Vec<Range<usize>> = Vec::new();
        for (i, _) in mask.iter().enumerate().filter(|(_, &m)| m) {
            match ranges.last_mut() {
                Some(r) if r.end == i => r.end = i + 1,
                _ => ranges.push(i..i + 1),
            }
        }
        let count = ranges.iter().map(|r| r.len()).sum();
        RowSet { ranges, count }
    }

    /// The ranges, in increasing order.
    pub fn ranges(&self) -> &[Range<usize>] {
        &self.ranges
    }

    /// Number of indices in the set.
    pub fn count(&self) -> usize {
        self.count
    }

    /// The parts of `lo..hi` in the set, in increasing order.
    pub fn within(&self, lo: usize, hi: usize) -> impl Iterator<Item = Range<usize>> + '_ {
        let first = self.ranges.partition_point(|r| r.end <= lo);
        self.ranges[first..]
            .iter()
            .take_while(move |r| r.start < hi)
            .map(move |r| r.start.max(lo)..r.end.min(hi))
    }

    /// `parts + 1` increasing bounds from `0` to `n` that split the set's indices below
    /// `n` into `parts` shares of about equal count (a bound falls inside a range where
    /// a share ends there).
    pub fn balanced_bounds(&self, n: usize, parts: usize) -> Vec<usize> {
        let parts = parts.max(1);
        let mut bounds = vec![0];
        let (mut seen, mut k) = (0usize, 1usize);
        for r in &self.ranges {
            let r = r.start.min(n)..r.end.min(n);
            while k < parts && seen + r.len() >= k * self.count / parts {
                let at = r.start + (k * self.count / parts - seen);
                bounds.push(at.max(*bounds.last().expect("started")));
                k += 1;
            }
            seen += r.len();
        }
        while bounds.len() < parts {
            bounds.push(n);
        }
        bounds.push(n);
        bounds
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_parts_and_shares_of_a_mask() {
        let mask: Vec<bool> = (0..40).map(|i| (3..9).contains(&i) || i >= 30).collect();
        let s = RowSet::from_mask(&mask);
        assert_eq!(s.ranges(), &[3..9, 30..40]);
        assert_eq!(s.count(), 16);
        assert_eq!(s.within(5, 32).collect::<Vec<_>>(), vec![5..9, 30..32]);
        assert_eq!(s.within(9, 30).count(), 0);
        assert_eq!(s.within(0, 40).collect::<Vec<_>>(), vec![3..9, 30..40]);
        // Two shares of 8: the first ends two rows into the second range.
        assert_eq!(s.balanced_bounds(40, 2), vec![0, 32, 40]);
        let b = s.balanced_bounds(40, 4);
        assert_eq!(b.len(), 5);
        assert!(b.windows(2).all(|w| w[0] <= w[1]));
        for w in b.windows(2) {
            let c: usize = s.within(w[0], w[1]).map(|r| r.len()).sum();
            assert_eq!(c, 4, "{b:?}");
        }
        assert_eq!(
            RowSet::from_mask(&[false; 5]).balanced_bounds(5, 2),
            vec![0, 5, 5]
        );
    }
}

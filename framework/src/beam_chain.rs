//! A path along a chain of two-node beam elements, listed in order of travel: which beam
//! and where on it a point at distance `d` along the path is.
//!
//! Used by the `moving_force` load and by the moving oscillators. The elements of the list
//! may run either way: the direction of travel on the first one is the one that leads into
//! the second (a path listed tip to root runs each beam from J to I), and every next
//! element must share a node with the end of the previous one.

use nalgebra::Vector3;

/// The resolved chain: node-index pairs in order of travel, their positions and the
/// distance along the path at each segment's start.
#[derive(Debug, Clone, PartialEq)]
pub struct BeamChain {
    /// Node-index pairs (I, J) of each beam of the path, in order of travel.
    pub segments: Vec<(usize, usize)>,
    /// Positions of the segments' ends (m).
    pub ends: Vec<(Vector3<f64>, Vector3<f64>)>,
    /// Distance along the path at the start of each segment (m), plus the total at the end.
    pub cumulative: Vec<f64>,
}

impl BeamChain {
    /// Walks the chain. `pairs[i]` is the node-index pair of the i-th listed element (its
    /// user id `ids[i]`, for messages), `position` the reference position of a node.
    /// Errors are one sentence naming the element and the fix.
    pub fn walk(
        ids: &[u64],
        mut pairs: Vec<(usize, usize)>,
        position: &dyn Fn(usize) -> Vector3<f64>,
    ) -> Result<BeamChain, String> {
        if pairs.is_empty() {
            return Err("the path is empty; list the beam ids of the path".into());
        }
        if let [(a0, _), (a1, b1), ..] = pairs[..] {
            if a0 == a1 || a0 == b1 {
                pairs[0] = (pairs[0].1, a0);
            }
        }
        let mut segments = Vec::with_capacity(pairs.len());
        let mut ends = Vec::with_capacity(pairs.len());
        let mut cumulative = vec![0.0];
        let mut prev_end: Option<usize> = None;
        for (&id, &(a0, b0)) in ids.iter().zip(&pairs) {
            let (mut a, mut b) = (a0, b0);
            if let Some(p) = prev_end {
                if b == p {
                    std::mem::swap(&mut a, &mut b);
                } else if a != p {
                    return Err(format!(
                        "element {id} does not share a node with the previous element of the path"
                    ));
                }
            }
            prev_end = Some(b);
            let (xa, xb) = (position(a), position(b));
            let len = (xb - xa).norm();
            if len.is_nan() || len <= 0.0 {
                return Err(format!(
                    "element {id} has zero length; a path needs beams of positive length"
                ));
            }
            cumulative.push(cumulative.last().copied().unwrap_or(0.0) + len);
            segments.push((a, b));
            ends.push((xa, xb));
        }
        Ok(BeamChain {
            segments,
            ends,
            cumulative,
        })
    }

    /// Total length (m).
    pub fn length(&self) -> f64 {
        self.cumulative.last().copied().unwrap_or(0.0)
    }

    /// The segment under distance `d` along the path and ξ ∈ [0, 1] on it, or `None` off
    /// the path. A point exactly on a node belongs to the segment that starts there.
    pub fn locate(&self, d: f64) -> Option<(usize, f64)> {
        locate_on(&self.cumulative, d)
    }
}

/// [`BeamChain::locate`] on the cumulative distances alone (`cumulative[i]` at the start of
/// segment `i`, the total last).
pub fn locate_on(cumulative: &[f64], d: f64) -> Option<(usize, f64)> {
    let nseg = cumulative.len().checked_sub(1).filter(|n| *n > 0)?;
    let total = cumulative[nseg];
    if !(0.0..=total).contains(&d) {
        return None;
    }
    let k = cumulative
        .partition_point(|c| *c <= d)
        .saturating_sub(1)
        .min(nseg - 1);
    let len = cumulative[k + 1] - cumulative[k];
    Some((k, ((d - cumulative[k]) / len).clamp(0.0, 1.0)))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A chain listed tip to root runs J → I on every beam; locate finds the right beam.
    #[test]
    fn reversed_chain_and_locate() {
        let pos = |i: usize| Vector3::new(i as f64 * 2.0, 0.0, 0.0);
        let c = BeamChain::walk(&[3, 2, 1], vec![(2, 3), (1, 2), (0, 1)], &pos).unwrap();
        assert_eq!(c.segments, vec![(3, 2), (2, 1), (1, 0)]);
        assert_eq!(c.length(), 6.0);
        assert_eq!(c.locate(3.0), Some((1, 0.5)));
        assert_eq!(c.locate(2.0), Some((1, 0.0)));
        assert_eq!(c.locate(6.0), Some((2, 1.0)));
        assert_eq!(c.locate(6.1), None);
        let e = BeamChain::walk(&[1, 3], vec![(0, 1), (2, 3)], &pos).unwrap_err();
        assert!(e.contains("element 3"), "{e}");
    }
}

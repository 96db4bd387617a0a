//! Factoring anew after part of the constant matrix changed between factorizations (an
//! absorbing layer's damping, `crate::window::absorb`), without a new coefficient key,
//! which would factor every block.

use super::Partitioned;

impl Partitioned {
    /// The constant matrix changed on the interiors of `blocks` and, if `top`, on top
    /// equations: drops those blocks' base factors and promotions (the next
    /// [`Partitioned::factor`] factors them again from the matrix it is given; the other
    /// blocks keep theirs) and has the top system's constant part formed again (with every
    /// group of the top chain, if `top`). Blocks shared among ranks are refused (the
    /// owner alone would know).
    pub fn constant_changed(&mut self, blocks: &[usize], top: bool) -> Result<(), String> {
        if self.comm.is_some() {
            return Err("blocks are not factored anew one by one across ranks".into());
        }
        if let Some(&b) = blocks.iter().find(|&&b| b >= self.blocks.len()) {
            return Err(format!("block {b} of {}", self.blocks.len()));
        }
        for &b in blocks {
            let blk = &mut self.blocks[b];
            blk.base = None;
            blk.promotion = None;
            // An empty promoted set: a block that had promoted equations forms them again.
            blk.promoted.clear();
        }
        if let Some(chain) = self.chain.as_mut() {
            for g in chain
                .groups
                .iter_mut()
                .filter(|g| top || blocks.iter().any(|b| g.blocks.contains(b)))
            {
                g.cond = None;
                g.failed = false;
            }
        }
        if top || !blocks.is_empty() {
            self.constant_stale = true;
        }
        Ok(())
    }
}

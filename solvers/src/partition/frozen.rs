//! Held blocks: block interiors the solves leave where they are, for the activity window
//! ([`crate::window`]).
//!
//! A *frozen* block's interior equations are treated as prescribed at their present values
//! for as long as the flag is set: [`Partitioned::condense_rhs`] skips the block's forward
//! pass (its interior rows are then reactions, whose residual the driver does not count,
//! so their condensed contribution is zero — exactly what the pass would give with those
//! rows zeroed), and [`Partitioned::back_substitute`] skips its back pass (the interior's
//! part of every solution is zero). The top system drops the block's correction
//! `A_BI·A_II⁻¹·A_IB` (its boundary keeps `A_BB`, the stiffness with the interior
//! prescribed), so the tangent is the exact one of the held system and Newton converges as
//! it does without the window. Keeping the correction (the interior following its boundary
//! in the tangent but not in the iterates) was tried first: on the bridge, where a girder's
//! cut couples stiffly to its interior, `A_BB` exceeds twice the condensed stiffness and the
//! iterations diverged at the first step. The block keeps its factor, so releasing it
//! costs no factorization; holding or releasing a block re-forms the top system's constant
//! part once (and re-condenses the top chain's group holding it, [`crate::top_chain`]).

use super::Partitioned;

impl Partitioned {
    /// Number of blocks of the structure (`0` before the first factorization).
    pub fn block_count(&self) -> usize {
        self.blocks.len()
    }

    /// Block `b`'s interior equations (global, sorted, promoted ones included).
    pub fn block_interior(&self, b: usize) -> &[usize] {
        &self.blocks[b].all
    }

    /// Whether block `b` had equations promoted to the top set at the last factorization
    /// (a variable element — a wheel — acts on it).
    pub fn block_has_promoted(&self, b: usize) -> bool {
        !self.blocks[b].promoted.is_empty()
    }

    /// Whether block `b` is held ([`Partitioned::set_frozen_blocks`]).
    pub fn block_frozen(&self, b: usize) -> bool {
        self.blocks[b].frozen
    }

    /// Holds the interiors of the blocks flagged in `frozen` (one flag per block) and
    /// releases the others (module documentation). Refused (`Err` with the reason) across
    /// ranks, for a wrong number of flags, or for a block with promoted equations (a
    /// variable element on it must be solved for).
    pub fn set_frozen_blocks(&mut self, frozen: &[bool]) -> Result<(), String> {
        if self.comm.is_some() {
            return Err("held blocks are not shared among ranks".into());
        }
        if frozen.len() != self.blocks.len() {
            return Err(format!(
                "{} flags for {} blocks",
                frozen.len(),
                self.blocks.len()
            ));
        }
        if let Some(b) = (0..frozen.len()).find(|&b| frozen[b] && self.block_has_promoted(b)) {
            return Err(format!(
                "block {b} carries a variable element and cannot be held"
            ));
        }
        for (b, (blk, &f)) in self.blocks.iter_mut().zip(frozen).enumerate() {
            if blk.frozen == f {
                continue;
            }
            blk.frozen = f;
            // The top system's constant part changes: this block's condensation leaves it
            // (or comes back), and so does that of the top chain's group holding it.
            self.constant_stale = true;
            if let Some(chain) = self.chain.as_mut() {
                for g in chain.groups.iter_mut().filter(|g| g.blocks.contains(&b)) {
                    g.cond = None;
                    g.failed = false;
                }
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::super::{PartitionOptions, Partitioned};
    use railfem_framework::sparse::CscMatrix;

    /// A chain of 3-DOF nodes (neighbour springs, a grounding spring each, coupled DOFs):
    /// symmetric positive definite, and 3 extra equations (a "vehicle") coupled to node
    /// `at` by an unsymmetric variable part.
    fn system(nodes: usize, at: usize) -> (CscMatrix, Vec<(usize, usize, f64)>) {
        let n = nodes * 3 + 3;
        let mut t = Vec::new();
        for k in 0..nodes {
            for d in 0..3 {
                let i = 3 * k + d;
                t.push((i, i, 3.0 + d as f64));
                if d > 0 {
                    t.push((i, i - 1, -0.4));
                    t.push((i - 1, i, -0.4));
                }
                if k + 1 < nodes {
                    t.push((i, i, 1.5));
                    t.push((i + 3, i + 3, 1.5));
                    t.push((i, i + 3, -1.5));
                    t.push((i + 3, i, -1.5));
                }
            }
        }
        for e in nodes * 3..n {
            t.push((e, e, 2.0));
        }
        let v = (0..3)
            .flat_map(|d| {
                let (c, e) = (3 * at + d, nodes * 3 + d);
                [(c, c, 1.0), (e, e, 1.0), (c, e, -1.0), (e, c, -0.8)]
            })
            .collect();
        (CscMatrix::from_triplets(n, &t), v)
    }

    /// `(A + V)·x = b` with the equations `held` prescribed at zero: a dense LU of the
    /// remaining rows and columns (the independent reference).
    fn held_solve(a: &CscMatrix, v: &[(usize, usize, f64)], b: &[f64], held: &[bool]) -> Vec<f64> {
        let free: Vec<usize> = (0..a.n).filter(|&i| !held[i]).collect();
        let mut at = vec![usize::MAX; a.n];
        for (k, &i) in free.iter().enumerate() {
            at[i] = k;
        }
        let mut m = nalgebra::DMatrix::<f64>::zeros(free.len(), free.len());
        let mut put = |i: usize, j: usize, x: f64| {
            if at[i] != usize::MAX && at[j] != usize::MAX {
                m[(at[i], at[j])] += x;
            }
        };
        for j in 0..a.n {
            for p in a.col_ptr[j]..a.col_ptr[j + 1] {
                put(a.row_idx[p], j, a.values[p]);
            }
        }
        for &(i, j, x) in v {
            put(i, j, x);
        }
        let bf = nalgebra::DVector::from_iterator(free.len(), free.iter().map(|&i| b[i]));
        let y = m.lu().solve(&bf).expect("regular");
        let mut x = vec![0.0; a.n];
        for (k, &i) in free.iter().enumerate() {
            x[i] = y[k];
        }
        x
    }

    /// Held blocks solve as the system with their interiors prescribed, with and without
    /// the top chain's condensation, and releasing them gives back the full solve — each
    /// against a dense LU to round-off (condition ≈ 1e2; both are backward-stable direct
    /// solves, so 1e-11 of the largest entry).
    #[test]
    fn held_blocks_solve_as_prescribed_interiors() {
        let (a, v) = system(200, 20);
        let b: Vec<f64> = (0..a.n).map(|i| ((i * 37 % 11) as f64) - 5.0).collect();
        for groups in [0, 2] {
            let mut p = Partitioned::new(
                false,
                PartitionOptions {
                    block_size: 50,
                    threads: 2,
                    top_group_blocks: groups,
                    ..Default::default()
                },
            );
            p.factor(&a, [1.0, 0.0, 0.0], &v).unwrap();
            let nb = p.block_count();
            assert!(nb >= 8, "{nb} blocks");
            // Hold every block without the vehicle's equations, then none.
            let frozen: Vec<bool> = (0..nb).map(|k| !p.block_has_promoted(k)).collect();
            assert!(frozen.iter().filter(|&&f| f).count() >= nb - 2);
            for hold in [true, false] {
                let flags: Vec<bool> = frozen.iter().map(|&f| f && hold).collect();
                p.set_frozen_blocks(&flags).unwrap();
                p.factor(&a, [1.0, 0.0, 0.0], &v).unwrap();
                let mut held = vec![false; a.n];
                for k in (0..nb).filter(|&k| flags[k]) {
                    for &i in p.block_interior(k) {
                        held[i] = true;
                    }
                }
                let mut x = b.clone();
                p.solve_in_place(&mut x).unwrap();
                let reference = held_solve(&a, &v, &b, &held);
                let scale = reference.iter().fold(0.0f64, |m, x| m.max(x.abs()));
                let e = x
                    .iter()
                    .zip(&reference)
                    .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
                assert!(e <= 1e-11 * scale, "groups {groups}, held {hold}: {e:e}");
                for (i, _) in held.iter().enumerate().filter(|(_, &h)| h) {
                    assert_eq!(x[i], 0.0, "held equation {i}");
                }
            }
            // A block the vehicle acts on cannot be held.
            let k = (0..nb)
                .find(|&k| p.block_has_promoted(k))
                .expect("promoted");
            let mut flags = vec![false; nb];
            flags[k] = true;
            assert!(p.set_frozen_blocks(&flags).is_err());
        }
    }
}

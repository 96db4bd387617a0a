//! Congruent blocks: when one Craig–Bampton reduction serves two blocks of the
//! partitioned solver, and the map that carries its basis from one to the other.
//!
//! **The test.** Blocks `a` and `b` are congruent when a one-to-one map `π` of their
//! equations (interior and boundary) exists such that
//! - `π` pairs equations of nodes at the same position after one translation along the
//!   track (`x`), with the same DOF, to 1 µm (positions relative to each block's least
//!   `x`);
//! - `π` keeps the split: interior to interior, boundary to boundary;
//! - `K_b[π(i), π(j)] = K_a[i, j]` and `M_b[π(i), π(j)] = M_a[i, j]` for every entry,
//!   to `tol` of the largest entry of `a`'s (the same stored pattern, no entry missing).
//!
//! The map is found, not searched: both blocks' equations are sorted by (translated
//! position, DOF, side of the split), with ties (coincident nodes, such as a rail node
//! and its fastener's anchor) broken by equation number, and `π` pairs the `k`-th of one
//! with the `k`-th of the other. A wrong pairing can only fail the matrix check: it then
//! refuses a share, never makes a wrong one.
//!
//! **Why the basis carries over.** With `P` the permutation of `π`, `K_b = P·K_a·Pᵀ`,
//! `M_b = P·M_a·Pᵀ` and the same split, `Ψ_b = −K_b,II⁻¹·K_b,IB = P_I·Ψ_a·P_Bᵀ` and
//! `P_I·Φ_a` solves `b`'s fixed-interface eigenproblem with the same `Ω` and the same
//! mass-normalization ([`crate::reduced`]): `b`'s reduction is `a`'s with its rows and
//! columns renumbered ([`ReducedBasis::mapped`]), exact to `tol`.

use super::{restrict, Split};
use crate::driver::Driver;
use crate::partition::ReducedBasis;

/// Where `b`'s rows and columns are found in a congruent block `a`'s basis
/// ([`Driver::block_congruence`]).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct BlockMap {
    /// For each interior equation of `b` (ascending), its partner's position in `a`'s
    /// interior.
    pub interior: Vec<usize>,
    /// For each boundary equation of `b` (ascending), its partner's position in `a`'s
    /// boundary.
    pub boundary: Vec<usize>,
}

impl BlockMap {
    /// Whether the map pairs every equation with the one at the same position (then `a`'s
    /// basis is `b`'s as it is).
    pub fn is_identity(&self) -> bool {
        let same = |v: &[usize]| v.iter().enumerate().all(|(k, &j)| k == j);
        same(&self.interior) && same(&self.boundary)
    }
}

impl ReducedBasis {
    /// The basis of a block congruent to this one's through `map` (module documentation):
    /// `Ψ_b(i, k) = Ψ_a(map.interior[i], map.boundary[k])`, `Φ_b(i, j) = Φ_a(map.interior[i], j)`.
    pub fn mapped(&self, map: &BlockMap) -> ReducedBasis {
        let (ni, nb) = (map.interior.len(), map.boundary.len());
        ReducedBasis {
            psi: nalgebra::DMatrix::from_fn(ni, nb, |i, k| {
                self.psi[(map.interior[i], map.boundary[k])]
            }),
            phi: nalgebra::DMatrix::from_fn(ni, self.phi.ncols(), |i, j| {
                self.phi[(map.interior[i], j)]
            }),
        }
    }
}

/// A block's equations (ascending), its split in that numbering, and the canonical order
/// of its equations (local indices; module documentation) with their sort keys.
struct Shape {
    eqs: Vec<usize>,
    split: Split,
    order: Vec<usize>,
    keys: Vec<[i64; 5]>,
}

impl Driver {
    fn block_shape(&self, b: usize) -> Option<Shape> {
        let (eqs, split) = self.block_split_of(b)?;
        let node = |g: usize| self.asm.dofmap.dof_of(g);
        let x_min = eqs
            .iter()
            .map(|&g| self.model.nodes[node(g).0].position.x)
            .fold(f64::INFINITY, f64::min);
        let mut interior = vec![false; eqs.len()];
        for &l in &split.interior {
            interior[l] = true;
        }
        // Positions in µm: translated copies of a mesh agree to far better than that, and
        // distinct nodes of a mesh are far further apart.
        let um = |v: f64| (v * 1e6).round() as i64;
        let keys: Vec<[i64; 5]> = eqs
            .iter()
            .enumerate()
            .map(|(l, &g)| {
                let (n, dof) = node(g);
                let p = self.model.nodes[n].position;
                [
                    um(p.x - x_min),
                    um(p.y),
                    um(p.z),
                    dof as i64,
                    i64::from(interior[l]),
                ]
            })
            .collect();
        let mut order: Vec<usize> = (0..eqs.len()).collect();
        order.sort_by_key(|&l| (keys[l], l));
        Some(Shape {
            eqs,
            split,
            order,
            keys,
        })
    }

    /// Whether blocks `a` and `b` of the partitioned solver are congruent (module
    /// documentation; matrices to `tol` of the largest entry): `Some` map that carries
    /// `a`'s reduced basis to `b` ([`ReducedBasis::mapped`]), `None` if they are not (or
    /// without the partitioned solver or such blocks).
    pub fn block_congruence(&self, a: usize, b: usize, tol: f64) -> Option<BlockMap> {
        let (sa, sb) = (self.block_shape(a)?, self.block_shape(b)?);
        let n = sa.eqs.len();
        if sb.eqs.len() != n || sa.split.interior.len() != sb.split.interior.len() {
            return None;
        }
        // π: a's local equation → b's.
        let mut pi = vec![0; n];
        for (&la, &lb) in sa.order.iter().zip(&sb.order) {
            if sa.keys[la] != sb.keys[lb] {
                return None;
            }
            pi[la] = lb;
        }
        for m in [&self.asm.k_const, &self.asm.m_const] {
            let (x, y) = (restrict(m, &sa.eqs), restrict(m, &sb.eqs));
            let scale = x.values.iter().fold(0.0f64, |s, v| s.max(v.abs()));
            let column = |c: &railfem_framework::sparse::CscMatrix,
                          j: usize,
                          map: &dyn Fn(usize) -> usize| {
                let mut col: Vec<(usize, f64)> = (c.col_ptr[j]..c.col_ptr[j + 1])
                    .map(|p| (map(c.row_idx[p]), c.values[p]))
                    .collect();
                col.sort_by_key(|e| e.0);
                col
            };
            for j in 0..n {
                let (ca, cb) = (column(&x, j, &|i| pi[i]), column(&y, pi[j], &|i| i));
                if ca.len() != cb.len()
                    || ca
                        .iter()
                        .zip(&cb)
                        .any(|(u, v)| u.0 != v.0 || (u.1 - v.1).abs() > tol * scale)
                {
                    return None;
                }
            }
        }
        // Positions in the interior and boundary lists of each block's local equations.
        let position = |list: &[usize]| {
            let mut at = vec![usize::MAX; n];
            for (k, &l) in list.iter().enumerate() {
                at[l] = k;
            }
            at
        };
        let mut inv = vec![0; n];
        for (la, &lb) in pi.iter().enumerate() {
            inv[lb] = la;
        }
        let (ia, ba) = (position(&sa.split.interior), position(&sa.split.boundary));
        Some(BlockMap {
            interior: sb.split.interior.iter().map(|&lb| ia[inv[lb]]).collect(),
            boundary: sb.split.boundary.iter().map(|&lb| ba[inv[lb]]).collect(),
        })
    }

    /// Gives the partitioned solver's blocks by station: a block per stretch between
    /// consecutive `cuts` (m, ascending, along the global `x`) of each large connected
    /// part of the model, with the equations that couple two stretches on top
    /// (`partition/reduced_cuts.rs`), and splits the equations now
    /// ([`Driver::prepare_blocks`]); returns the number of blocks. An equation's station
    /// is its node's `x`; a node within 1 µm of a cut lies after it. Refused without the
    /// partitioned solver.
    pub fn cut_blocks_at(&mut self, cuts: &[f64]) -> Result<usize, String> {
        let bins: Vec<u32> = (0..self.neq())
            .map(|g| {
                let x = self.model.nodes[self.asm.dofmap.dof_of(g).0].position.x;
                cuts.partition_point(|&c| c <= x + 1e-6) as u32
            })
            .collect();
        let p = self
            .linear
            .partitioned_mut()
            .ok_or("blocks by station need the partitioned solver")?;
        p.set_block_bins(Some(bins));
        self.linear.invalidate();
        self.prepare_blocks()
    }
}

//! Changes of the constant damping matrix's diagonal while a run goes on: what an absorbing
//! layer at a moving boundary needs (`railfem_solvers::window::absorb`). The assembler
//! keeps `C` in the shared pattern and, for the products, a copy of its non-zero entries
//! ([`super::NonzeroColumns`]); a change of `C_ii` updates both, so that every product
//! that reads `C` afterwards (the residual's damping force, the energy ledger's damping
//! work) sees the new value. Whoever factors an effective matrix that contains `C` must
//! form it again: the assembler does not know the solver's caches.

use super::Assembler;
use crate::sparse::CscMatrix;

/// Storage position of the diagonal entry `(i, i)` of `a`, when the pattern holds it.
fn diagonal_position(a: &CscMatrix, i: usize) -> Option<usize> {
    let (lo, hi) = (*a.col_ptr.get(i)?, *a.col_ptr.get(i + 1)?);
    a.row_idx[lo..hi].binary_search(&i).ok().map(|p| lo + p)
}

impl Assembler {
    /// The constant damping's and mass's diagonal entries `[C_ii, M_ii]` of equation `i`
    /// (`None` when the shared pattern does not hold the diagonal, or the assembler holds
    /// only some columns of the matrices, on a rank of a distributed run).
    pub fn constant_diagonal(&self, i: usize) -> Option<[f64; 2]> {
        if self.columns_kept {
            return None;
        }
        let p = diagonal_position(&self.c_const, i)?;
        Some([self.c_const.values[p], self.m_const.values[p]])
    }

    /// Sets `C_ii` to each given `(i, value)` on the constant damping matrix, and its copy
    /// for the products (module documentation). An equation whose diagonal is not in the
    /// pattern, or an assembler holding only some columns, is refused, with nothing changed.
    pub fn set_damping_diagonal(&mut self, values: &[(usize, f64)]) -> Result<(), String> {
        if self.columns_kept {
            return Err(
                "the damping's diagonal is not changed on a rank holding some columns".into(),
            );
        }
        let mut positions = Vec::with_capacity(values.len());
        for &(i, _) in values {
            positions.push(
                diagonal_position(&self.c_const, i)
                    .ok_or_else(|| format!("equation {i} has no diagonal entry in the pattern"))?,
            );
        }
        for (&p, &(_, v)) in positions.iter().zip(values) {
            self.c_const.values[p] = v;
        }
        self.c_const_zero = self.c_const.values.iter().all(|&c| c == 0.0);
        if let Some(nz) = self.nonzero.as_mut() {
            match super::NonzeroColumns::of(&self.c_const) {
                Some(c) => nz[2] = c,
                None => self.nonzero = None,
            }
        }
        Ok(())
    }
}

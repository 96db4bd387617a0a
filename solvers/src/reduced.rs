//! Craig–Bampton reduction of a linear substructure: a block of equations (a span of the
//! viaduct far from the train) represented by its boundary DOFs plus the fixed-interface
//! modes of its interior up to a cut-off frequency.
//!
//! # The reduction
//!
//! Split the block's DOFs into interior `I` and boundary `B`. Its linear equations are
//! `M·q̈ + C·q̇ + K·q = f`. Every interior state is exactly
//!
//! `q_I = Ψ·q_B + Φ·η`, with the constraint modes `Ψ = −K_II⁻¹·K_IB` and all the
//! fixed-interface modes `Φ` (`K_II·Φ = M_II·Φ·Ω²`, `Φᵀ·M_II·Φ = I`),
//!
//! because `Ψ·q_B` is the interior's static answer to the boundary's displacement and the
//! modes span what is left. Keeping only the modes with `ω ≤ ω_c` (the cut-off,
//! [`cutoff`]) is the Craig–Bampton method (Craig & Bampton, AIAA J. 6(7), 1968). With the
//! basis `T = [[I, 0], [Ψ, Φ]]` (rows `B`, `I`; columns `q_B`, `η`) the reduced equations are
//! Galerkin's: `M̂ = Tᵀ·M·T`, `Ĉ = Tᵀ·C·T`, `K̂ = Tᵀ·K·T`, `f̂ = Tᵀ·f`. Their structure is
//!
//! - `K̂_BB = K_BB + K_BI·Ψ` (Guyan's condensed stiffness), `K̂_ηη = Ω²`, `K̂_Bη = 0`,
//!   because `K_IB + K_II·Ψ = 0`;
//! - `M̂_ηη = I`, `M̂_ηB = Φᵀ·(M_IB + M_II·Ψ)`, `M̂_BB = Tᵀ_B·M·T_B`.
//!
//! Static exactness: a boundary displacement with no interior load gives the interior
//! field `Ψ·q_B`, which is the full model's own (`K_II·q_I = −K_IB·q_B`), to round-off.
//! A ground motion's effective load `−M·r·a_g(t)` projects to `−(Tᵀ·M·r)·a_g(t)`
//! ([`CraigBampton::reduce`] of `M·r`).
//!
//! # How it is computed
//!
//! `K_II` is factored once with the sparse Cholesky factor of the workspace
//! ([`crate::linear::SparseCholesky`]); `Ψ` is one multi-column solve with it, and the
//! modes come from the subspace iteration of [`crate::modal`] on `(K_II, M_II)` with the
//! same factor, asking for 16, 32, … modes until the highest one found lies above the cut-off
//! (or every interior DOF with mass has its mode). The reduced matrices are dense: a span
//! keeps its boundary plus a few tens of modes.
//!
//! What lives elsewhere: the choice of the cut-off ([`cutoff`]), the mapping of a state
//! between the full and the reduced form and its energy ([`switch`]), the time march of a
//! linear system with the generalized-α coefficients ([`march`]), a model with some of its
//! blocks reduced ([`mixed`]).

pub mod blocks;
pub mod congruent;
pub mod cutoff;
pub mod march;
pub mod mixed;
pub mod switch;
#[cfg(test)]
mod tests;

use crate::linear::{LinearSolver, SolverError, SparseCholesky};
use crate::modal::{lowest_modes_with, ModalError, ModalOptions};
use nalgebra::DMatrix;
use railfem_framework::sparse::CscMatrix;
use railfem_framework::Dof;

/// Failure of a reduction.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ReducedError {
    /// Factoring `K_II` or solving with it failed (the interior is not held by the
    /// boundary: a mechanism with the boundary fixed).
    #[error("interior stiffness factorization: {0}")]
    Solver(#[from] SolverError),
    /// The fixed-interface modes could not be computed.
    #[error("fixed-interface modes: {0}")]
    Modal(#[from] ModalError),
    /// The request is inconsistent (sizes, a DOF in both sets or in neither, a cut-off
    /// that is not a positive number).
    #[error("invalid reduction input: {0}")]
    InvalidInput(String),
}

/// The DOFs of a block: each index of the block's matrices is in exactly one of the two
/// lists.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Split {
    /// Interior DOFs (indices into the block's matrices), reduced to modes.
    pub interior: Vec<usize>,
    /// Boundary DOFs, kept as they are (they couple the block to the rest).
    pub boundary: Vec<usize>,
}

impl Split {
    /// Checks that the two lists partition `0..n`.
    fn check(&self, n: usize) -> Result<(), ReducedError> {
        let mut seen = vec![false; n];
        for &i in self.interior.iter().chain(&self.boundary) {
            if i >= n {
                return Err(ReducedError::InvalidInput(format!(
                    "DOF {i} is outside the block's {n} DOFs"
                )));
            }
            if seen[i] {
                return Err(ReducedError::InvalidInput(format!(
                    "DOF {i} is listed twice (in the interior and the boundary, or twice in one)"
                )));
            }
            seen[i] = true;
        }
        if let Some(i) = seen.iter().position(|s| !s) {
            return Err(ReducedError::InvalidInput(format!(
                "DOF {i} is in neither the interior nor the boundary"
            )));
        }
        if self.interior.is_empty() {
            return Err(ReducedError::InvalidInput(
                "the interior is empty: nothing to reduce".into(),
            ));
        }
        Ok(())
    }
}

/// The equations of a block of a larger model and their split: `in_block[e]` marks the
/// block's equations; those coupled to an equation outside the block by an entry of `K`,
/// `M` or `C` form the boundary, the others the interior (whose rows then see only the
/// block, as a partitioned solver's block interior does). Returns the block's equations in
/// ascending order and the split in that local numbering (for [`restrict`] and
/// [`CraigBampton::build`]).
pub fn block_split(matrices: &[&CscMatrix], in_block: &[bool]) -> (Vec<usize>, Split) {
    let block_of: Vec<Option<usize>> = in_block.iter().map(|&b| b.then_some(0)).collect();
    block_splits(matrices, &block_of, 1)
        .pop()
        .expect("one block")
}

/// [`block_split`] of many blocks in one pass over the matrices: `block_of[e]` is
/// equation `e`'s block (`None` outside every block); an equation is on its block's
/// boundary when it is coupled to an equation of another block or of none.
pub fn block_splits(
    matrices: &[&CscMatrix],
    block_of: &[Option<usize>],
    blocks: usize,
) -> Vec<(Vec<usize>, Split)> {
    let mut coupled = vec![false; block_of.len()];
    for a in matrices {
        for j in 0..a.n {
            for p in a.col_ptr[j]..a.col_ptr[j + 1] {
                let i = a.row_idx[p];
                if block_of[i] != block_of[j] && a.values[p] != 0.0 {
                    coupled[i] = true;
                    coupled[j] = true;
                }
            }
        }
    }
    let mut out: Vec<(Vec<usize>, Split)> = (0..blocks)
        .map(|_| {
            (
                Vec::new(),
                Split {
                    interior: Vec::new(),
                    boundary: Vec::new(),
                },
            )
        })
        .collect();
    for (e, b) in block_of.iter().enumerate() {
        let Some(b) = *b else { continue };
        let (eqs, split) = &mut out[b];
        let l = eqs.len();
        eqs.push(e);
        if coupled[e] {
            split.boundary.push(l);
        } else {
            split.interior.push(l);
        }
    }
    out
}

/// The load per unit ground acceleration along global X, Y and Z: `M·r` with `r` one on
/// every translation along that axis (`dof_of(e)` is equation `e`'s DOF; nodes in global
/// axes). A uniform ground motion `a_g(t)` loads the model, in coordinates relative to the
/// ground, with `−M·r·a_g(t)`.
pub fn ground_influence(m: &CscMatrix, dof_of: impl Fn(usize) -> Dof) -> [Vec<f64>; 3] {
    std::array::from_fn(|axis| {
        let r: Vec<f64> = (0..m.n)
            .map(|e| f64::from(dof_of(e).index() == axis))
            .collect();
        let mut out = vec![0.0; m.n];
        m.mul_vec(&r, &mut out);
        out
    })
}

/// `A[eqs, eqs]`: the matrix of a model restricted to a block's equations (renumbered in
/// the order of `eqs`).
pub fn restrict(a: &CscMatrix, eqs: &[usize]) -> CscMatrix {
    let mut local = vec![None; a.n];
    for (l, &e) in eqs.iter().enumerate() {
        local[e] = Some(l);
    }
    sparse_part(a, &local, eqs)
}

/// A block reduced to its boundary DOFs and its fixed-interface modes below the cut-off.
///
/// Reduced coordinates are ordered `[q_B (boundary, in the order of `Split::boundary`),
/// η (modal, ascending frequency)]`.
#[derive(Debug, Clone)]
pub struct CraigBampton {
    split: Split,
    /// Constraint modes `Ψ = −K_II⁻¹·K_IB` (`n_I × n_B`, dimensionless for like DOFs).
    pub psi: DMatrix<f64>,
    /// Fixed-interface modes with `ω ≤ ω_c` (`n_I × p`, `Φᵀ·M_II·Φ = I`).
    pub phi: DMatrix<f64>,
    /// Their circular frequencies ω (rad/s), ascending.
    pub omega: Vec<f64>,
    /// The cut-off ω_c (rad/s) the modes were chosen with.
    pub cutoff: f64,
    /// The full basis `T` (`n × (n_B + p)`, rows in the block's DOF order).
    pub basis: DMatrix<f64>,
    /// `M̂ = Tᵀ·M·T` (kg, kg·m², … in the reduced coordinates).
    pub m_hat: DMatrix<f64>,
    /// `K̂ = Tᵀ·K·T`.
    pub k_hat: DMatrix<f64>,
    /// `Ĉ = Tᵀ·C·T`, zero without damping.
    pub c_hat: DMatrix<f64>,
    /// `K_II`, kept for the energy of a projection's residual.
    k_ii: CscMatrix,
    /// `M_II`, kept for the projection and its residual.
    m_ii: CscMatrix,
    /// The block's mass matrix, kept for the kinetic coupling of a residual.
    m: CscMatrix,
}

/// `A[rows, cols]` as a sparse matrix (rows and columns renumbered in list order).
fn sparse_part(a: &CscMatrix, local: &[Option<usize>], cols: &[usize]) -> CscMatrix {
    let mut t = Vec::new();
    for (jl, &j) in cols.iter().enumerate() {
        for p in a.col_ptr[j]..a.col_ptr[j + 1] {
            if let Some(il) = local[a.row_idx[p]] {
                t.push((il, jl, a.values[p]));
            }
        }
    }
    CscMatrix::from_triplets(cols.len(), &t)
}

/// `Aᵀ·B·A`-style product `Tᵀ·(S·T)` for a sparse `S`, symmetrized (the three block
/// matrices are symmetric; round-off is averaged out).
fn project_sparse(s: &CscMatrix, t: &DMatrix<f64>) -> DMatrix<f64> {
    let (n, r) = t.shape();
    let mut st = DMatrix::<f64>::zeros(n, r);
    for j in 0..r {
        s.mul_vec(t.column(j).as_slice(), st.column_mut(j).as_mut_slice());
    }
    let mut p = t.transpose() * st;
    for j in 0..r {
        for i in 0..j {
            let v = 0.5 * (p[(i, j)] + p[(j, i)]);
            p[(i, j)] = v;
            p[(j, i)] = v;
        }
    }
    p
}

impl CraigBampton {
    /// Reduces the block with matrices `k`, `m` and `c` (all `n × n`, symmetric; `c`
    /// may be `None`) to the boundary of `split` plus the fixed-interface modes with
    /// `ω ≤ cutoff` (rad/s). `K_II` must be positive definite (the boundary holds the
    /// interior) and `M_II` positive semi-definite.
    pub fn build(
        k: &CscMatrix,
        m: &CscMatrix,
        c: Option<&CscMatrix>,
        split: &Split,
        cutoff: f64,
        options: &ModalOptions,
    ) -> Result<CraigBampton, ReducedError> {
        let n = k.n;
        if m.n != n || c.is_some_and(|c| c.n != n) {
            return Err(ReducedError::InvalidInput(format!(
                "K is {n}×{n} but M or C is not"
            )));
        }
        if !(cutoff.is_finite() && cutoff > 0.0) {
            return Err(ReducedError::InvalidInput(format!(
                "the cut-off {cutoff} rad/s must be a positive number"
            )));
        }
        split.check(n)?;
        let (ni, nb) = (split.interior.len(), split.boundary.len());
        let mut local_i = vec![None; n];
        for (l, &i) in split.interior.iter().enumerate() {
            local_i[i] = Some(l);
        }
        let k_ii = sparse_part(k, &local_i, &split.interior);
        let m_ii = sparse_part(m, &local_i, &split.interior);

        // Ψ = −K_II⁻¹·K_IB, one multi-column solve.
        let mut solver = SparseCholesky::new();
        solver.factor(&k_ii)?;
        let mut psi = DMatrix::<f64>::zeros(ni, nb);
        for (jb, &j) in split.boundary.iter().enumerate() {
            for p in k.col_ptr[j]..k.col_ptr[j + 1] {
                if let Some(il) = local_i[k.row_idx[p]] {
                    psi[(il, jb)] = -k.values[p];
                }
            }
        }
        solver.solve_columns_in_place(psi.as_mut_slice(), nb)?;

        let (phi, omega) = modes_below(&mut solver, &k_ii, &m_ii, cutoff, options)?;
        let p = omega.len();

        let mut basis = DMatrix::<f64>::zeros(n, nb + p);
        for (jb, &j) in split.boundary.iter().enumerate() {
            basis[(j, jb)] = 1.0;
            for (il, &i) in split.interior.iter().enumerate() {
                basis[(i, jb)] = psi[(il, jb)];
            }
        }
        for jm in 0..p {
            for (il, &i) in split.interior.iter().enumerate() {
                basis[(i, nb + jm)] = phi[(il, jm)];
            }
        }
        let k_hat = project_sparse(k, &basis);
        let m_hat = project_sparse(m, &basis);
        let c_hat = match c {
            Some(c) => project_sparse(c, &basis),
            None => DMatrix::zeros(nb + p, nb + p),
        };
        Ok(CraigBampton {
            split: split.clone(),
            psi,
            phi,
            omega,
            cutoff,
            basis,
            m_hat,
            k_hat,
            c_hat,
            k_ii,
            m_ii,
            m: m.clone(),
        })
    }

    /// The split the block was reduced with.
    pub fn split(&self) -> &Split {
        &self.split
    }

    /// Number of kept fixed-interface modes `p`.
    pub fn modes(&self) -> usize {
        self.omega.len()
    }

    /// Number of reduced coordinates, `n_B + p`.
    pub fn size(&self) -> usize {
        self.basis.ncols()
    }

    /// `Tᵀ·f`: a load on the block's DOFs (length `n`) in reduced coordinates. The ground
    /// motion's influence is `reduce(M·r)`.
    pub fn reduce(&self, f: &[f64]) -> Vec<f64> {
        let fv = nalgebra::DVectorView::from_slice(f, self.basis.nrows());
        (self.basis.transpose() * fv).as_slice().to_vec()
    }

    /// `T·x̂`: reduced coordinates expanded to the block's DOFs (length `n`).
    pub fn expand(&self, x_hat: &[f64]) -> Vec<f64> {
        let xv = nalgebra::DVectorView::from_slice(x_hat, self.basis.ncols());
        (&self.basis * xv).as_slice().to_vec()
    }
}

/// The fixed-interface modes with `ω ≤ cutoff`: asks the subspace iteration for 16 modes
/// (a viaduct span keeps 10 to 12 at the default cut-off), then twice as many, until the highest found is above the cut-off or every interior DOF
/// with mass has its mode. Reuses `solver`'s factor of `K_II` (same pattern: numeric only).
fn modes_below(
    solver: &mut dyn LinearSolver,
    k_ii: &CscMatrix,
    m_ii: &CscMatrix,
    cutoff: f64,
    options: &ModalOptions,
) -> Result<(DMatrix<f64>, Vec<f64>), ReducedError> {
    let massive = (0..m_ii.n).filter(|&i| m_ii.get(i, i) > 0.0).count();
    let mut want = massive.min(16);
    loop {
        if want == 0 {
            return Ok((DMatrix::zeros(k_ii.n, 0), Vec::new()));
        }
        let modes = lowest_modes_with(solver, k_ii, m_ii, want, options)?;
        let top = *modes.omega.last().expect("at least one mode");
        if top > cutoff || want == massive {
            let keep = modes.omega.iter().take_while(|&&w| w <= cutoff).count();
            let phi = modes.shapes.columns(0, keep).into_owned();
            return Ok((phi, modes.omega[..keep].to_vec()));
        }
        want = (2 * want).min(massive);
    }
}

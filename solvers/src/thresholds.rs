//! The equation counts at which the driver and the partitioned solver switch from one
//! linear solver to another: `solver = "auto"` resolved into the direct, partitioned or
//! low-rank solver ([`resolve`]), dense against sparse factors, and the dense top system of
//! the partitioned solver. Each limit says where it was measured. The model holds only the
//! user's choice ([`railfem_framework::model::SolverChoice`]).

use railfem_framework::model::{SolverChoice, SolverInputs};

/// Equation count from which `solver = "auto"` picks the partitioned solver.
pub const PARTITIONED_FROM: usize = 50_000;

/// Largest total DOF count of the moving and nonlinear elements for which `solver = "auto"`
/// picks the low-rank solver (below [`PARTITIONED_FROM`] equations): a few riders on a
/// bridge. The bordered solve costs `O(n·s)` per solve and `O(s³)` per iteration for `s`
/// such equations, against a sparse refactorization per iteration.
pub const LOW_RANK_MAX_DOFS: usize = 64;

/// Systems of at most this many equations are factored densely by the driver. Measured
/// (`railfem bench --case threshold`, docs/performance.md, "Small models and the bandwidth
/// floor"): on a beam's effective tangent the dense LU's factorization + solve costs 0.79,
/// 0.85, 0.99, 1.10, 1.26 times the sparse solver's at n = 6, 12, 18, 24, 30 equations and
/// 6.2 times at 198; on vehicles (66 equations a carriage) 2.7 times at 66. One solve alone
/// crosses over sooner (dense 1.2 times slower at 12). 16 is where the two are even.
pub const DENSE_UP_TO: usize = 16;

/// Equation count above which `solver = "auto"` may pick the low-rank solver: up to it the
/// driver factors the whole tangent densely, which is as cheap.
pub const LOW_RANK_FROM: usize = DENSE_UP_TO;

/// The solver a model runs with, `auto` resolved (never returns `Auto`): `partitioned`
/// from [`PARTITIONED_FROM`] equations when there are moving or nonlinear elements;
/// below that, `low_rank` for a transient larger than [`LOW_RANK_FROM`] whose moving or
/// nonlinear elements have at most [`LOW_RANK_MAX_DOFS`] DOFs in all; `direct` otherwise.
/// A choice other than `auto` stands. The driver hands it to the assembler
/// ([`railfem_framework::model::SolverResolver`]).
pub fn resolve(i: &SolverInputs) -> SolverChoice {
    match (i.choice, i.variable_dofs) {
        (SolverChoice::Auto, None) => SolverChoice::Direct,
        (SolverChoice::Auto, Some(_)) if i.equations >= PARTITIONED_FROM => {
            SolverChoice::Partitioned
        }
        (SolverChoice::Auto, Some(d))
            if i.transient && i.equations > LOW_RANK_FROM && d <= LOW_RANK_MAX_DOFS =>
        {
            SolverChoice::LowRank
        }
        (SolverChoice::Auto, Some(_)) => SolverChoice::Direct,
        (other, _) => other,
    }
}

/// Top systems of the partitioned solver up to this many equations are factored densely
/// (a Schur complement is much denser than the model's tangent).
pub const DENSE_LIMIT: usize = 200;

/// The driver factors a model of at most this many equations densely, above it sparsely:
/// the measured crossover [`DENSE_UP_TO`] (it was 200 before it was measured, when a
/// 121-equation model ran slower than a 241-equation one).
pub const DIRECT_DENSE_LIMIT: usize = DENSE_UP_TO;

/// The driver factors an *unsymmetric* tangent of at most this many equations by the LU that
/// replays the last row exchanges ([`crate::static_lu::StaticLu`], falling back to the dense LU
/// in a fill-reducing order, [`crate::dense::DenseLu::fill_reducing`], whose factor it reproduces to the bit),
/// above it by the sparse LU. The limit was measured for the ordered dense LU, on the curve
/// case's vehicle with creep forces (`sks700` carriages with `tangential = "kalker_linear"`,
/// per Newton iteration, docs/performance.md "Rolling-contact laws in the curve case"): 18
/// against 42–48 µs at 66 equations, 18–27 against 23–29 at 132, 25–34 against 50–61 at 198,
/// but 64 against 43 µs at 264. A symmetric tangent keeps [`DIRECT_DENSE_LIMIT`] (sparse
/// Cholesky is faster from 18 equations on).
pub const DIRECT_DENSE_LU_LIMIT: usize = 200;

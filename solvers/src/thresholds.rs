//! The equation counts at which the driver and the partitioned solver switch from one
//! linear solver to another: dense against sparse factors, and the dense top system of the
//! partitioned solver. Each limit says where it was measured.

/// Top systems of the partitioned solver up to this many equations are factored densely
/// (a Schur complement is much denser than the model's tangent).
pub const DENSE_LIMIT: usize = 200;

/// The driver factors a model of at most this many equations densely, above it sparsely:
/// the measured crossover [`railfem_framework::model::DENSE_UP_TO`] (it was 200 before it
/// was measured, when a 121-equation model ran slower than a 241-equation one).
pub const DIRECT_DENSE_LIMIT: usize = railfem_framework::model::DENSE_UP_TO;

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

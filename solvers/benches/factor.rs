//! Refactorization cost on a railway-like matrix: a multi-span 3-D beam (rail) with 6 DOF
//! per node on discrete elastic supports, ~10⁵ unknowns, block tridiagonal with 6×6 blocks.
//!
//! Compares, for the same values and pattern every iteration (a Newton loop):
//! * `faer_new_each_time` — faer's high-level `sp_cholesky`: ordering, symbolic analysis,
//!   numeric factor and buffers built from scratch;
//! * `faer_cached_symbolic` — high-level `Llt::try_new_with_symbolic` with a kept
//!   `SymbolicLlt` (numeric buffers and scratch still allocated per call);
//! * `railfem_reuse` — [`SparseCholesky::factor`]: gather lower triangle through a kept index
//!   list, numeric factorization into kept buffers, no allocation.
//!
//! faer's global parallelism is set to sequential so all three use one thread.

// small dense 12×12 / 3×3 products read clearest with explicit indices
#![allow(clippy::needless_range_loop)]

use criterion::{criterion_group, criterion_main, Criterion};
use faer::sparse::linalg::solvers::{Llt, SymbolicLlt};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Par, Side};
use railfem_framework::sparse::CscMatrix;
use railfem_solvers::linear::{LinearSolver, SparseCholesky};
use std::hint::black_box;

/// 12×12 stiffness of a straight 3-D Euler–Bernoulli beam along x (N/m, N, N·m/rad), DOF
/// order per node: ux, uy, uz, rx, ry, rz.
fn beam_element(l: f64, ea: f64, gj: f64, eiy: f64, eiz: f64) -> [[f64; 12]; 12] {
    let mut k = [[0.0; 12]; 12];
    let mut add = |dofs: &[usize], m: &[f64], s: f64| {
        let n = dofs.len();
        for a in 0..n {
            for b in 0..n {
                k[dofs[a]][dofs[b]] += s * m[a * n + b];
            }
        }
    };
    add(&[0, 6], &[1.0, -1.0, -1.0, 1.0], ea / l);
    add(&[3, 9], &[1.0, -1.0, -1.0, 1.0], gj / l);
    let (l2, l3) = (l * l, l * l * l);
    #[rustfmt::skip]
    let bend_xy = [
        12.0, 6.0 * l, -12.0, 6.0 * l,
        6.0 * l, 4.0 * l2, -6.0 * l, 2.0 * l2,
        -12.0, -6.0 * l, 12.0, -6.0 * l,
        6.0 * l, 2.0 * l2, -6.0 * l, 4.0 * l2,
    ];
    add(&[1, 5, 7, 11], &bend_xy, eiz / l3);
    #[rustfmt::skip]
    let bend_xz = [
        12.0, -6.0 * l, -12.0, -6.0 * l,
        -6.0 * l, 4.0 * l2, 6.0 * l, 2.0 * l2,
        -12.0, 6.0 * l, 12.0, 6.0 * l,
        -6.0 * l, 2.0 * l2, 6.0 * l, 4.0 * l2,
    ];
    add(&[2, 4, 8, 10], &bend_xz, eiy / l3);
    k
}

/// `Rᵀ K R` with `R = blockdiag(r, r, r, r)`: the element stiffness in global axes when
/// `u_local = r · u_global` for each translation and rotation triple.
fn to_global(kl: &[[f64; 12]; 12], r: &[[f64; 3]; 3]) -> [[f64; 12]; 12] {
    let t = |i: usize, j: usize| {
        if i / 3 == j / 3 {
            r[i % 3][j % 3]
        } else {
            0.0
        }
    };
    let mut kr = [[0.0; 12]; 12];
    for i in 0..12 {
        for j in 0..12 {
            kr[i][j] = (0..12).map(|m| kl[i][m] * t(m, j)).sum();
        }
    }
    let mut kg = [[0.0; 12]; 12];
    for i in 0..12 {
        for j in 0..12 {
            kg[i][j] = (0..12).map(|m| t(m, i) * kr[m][j]).sum();
        }
    }
    kg
}

/// Rotation by angles about z, then x (cant), then y, as a 3×3 matrix.
fn rotation(yaw: f64, cant: f64, pitch: f64) -> [[f64; 3]; 3] {
    let (cz, sz, cx, sx, cy, sy) = (
        yaw.cos(),
        yaw.sin(),
        cant.cos(),
        cant.sin(),
        pitch.cos(),
        pitch.sin(),
    );
    let rz = [[cz, sz, 0.0], [-sz, cz, 0.0], [0.0, 0.0, 1.0]];
    let rx = [[1.0, 0.0, 0.0], [0.0, cx, sx], [0.0, -sx, cx]];
    let ry = [[cy, 0.0, -sy], [0.0, 1.0, 0.0], [sy, 0.0, cy]];
    let mul = |a: [[f64; 3]; 3], b: [[f64; 3]; 3]| {
        let mut c = [[0.0; 3]; 3];
        for i in 0..3 {
            for j in 0..3 {
                c[i][j] = (0..3).map(|k| a[i][k] * b[k][j]).sum();
            }
        }
        c
    };
    mul(ry, mul(rx, rz))
}

/// UIC60-like rail, 0.15 m elements, in axes rotated by a yaw, a cant and a pitch (so every
/// 6×6 node block is full, as on curved, canted track), a pad (springs in x, y, z and
/// torsion) every 4th node (0.6 m sleeper spacing), `nodes` nodes.
fn rail(nodes: usize) -> CscMatrix {
    let (e, g) = (2.1e11, 8.1e10);
    let (a, iy, iz, j) = (7.67e-3, 3.04e-5, 5.12e-6, 2.0e-6);
    let ke = to_global(
        &beam_element(0.15, e * a, g * j, e * iy, e * iz),
        &rotation(0.3, 0.1, 0.05),
    );
    let mut t = Vec::with_capacity((nodes - 1) * 144 + nodes * 4);
    for el in 0..nodes - 1 {
        let base = 6 * el;
        for (r, row) in ke.iter().enumerate() {
            for (c, v) in row.iter().enumerate() {
                if v.abs() > 1e-12 * row[r].abs() {
                    t.push((base + r, base + c, *v));
                }
            }
        }
    }
    for node in (0..nodes).step_by(4) {
        for (d, kv) in [(0, 5.0e7), (1, 6.0e7), (2, 1.2e8), (3, 1.0e6)] {
            t.push((6 * node + d, 6 * node + d, kv));
        }
    }
    CscMatrix::from_triplets(6 * nodes, &t)
}

fn as_faer(a: &CscMatrix) -> SparseColMatRef<'_, usize, f64> {
    SparseColMatRef::new(
        SymbolicSparseColMatRef::new_checked(a.n, a.n, &a.col_ptr, None, &a.row_idx),
        &a.values,
    )
}

fn bench(c: &mut Criterion) {
    faer::set_global_parallelism(Par::Seq);
    let a = rail(16_667); // 100 002 unknowns
    let mat = as_faer(&a);
    let mut group = c.benchmark_group(format!("cholesky_n{}_nnz{}", a.n, a.nnz()));
    group.sample_size(20);

    group.bench_function("faer_new_each_time", |b| {
        b.iter(|| black_box(mat.sp_cholesky(Side::Lower).unwrap()))
    });

    let symbolic = SymbolicLlt::try_new(mat.symbolic(), Side::Lower).unwrap();
    group.bench_function("faer_cached_symbolic", |b| {
        b.iter(|| {
            black_box(Llt::try_new_with_symbolic(symbolic.clone(), mat, Side::Lower).unwrap())
        })
    });

    let mut solver = SparseCholesky::new();
    solver.factor(&a).unwrap();
    group.bench_function("railfem_reuse", |b| {
        b.iter(|| solver.factor(black_box(&a)).unwrap())
    });
    let stats = solver.stats();
    assert_eq!(stats.symbolic_analyses, 1);
    eprintln!(
        "railfem_reuse: supernodal = {:?}, factor entries = {}, numeric factorizations = {}",
        solver.is_supernodal(),
        stats.factor_nnz,
        stats.numeric_factorizations
    );

    let rhs: Vec<f64> = (0..a.n).map(|i| ((i * 7919) % 101) as f64 - 50.0).collect();
    let mut x = rhs.clone();
    group.bench_function("railfem_solve", |b| {
        b.iter(|| {
            x.copy_from_slice(&rhs);
            solver.solve_in_place(black_box(&mut x)).unwrap()
        })
    });
    group.finish();

    // Interleaved min-of-N timing, robust against other load on a shared machine.
    let (mut t_new, mut t_cached, mut t_reuse) = (f64::MAX, f64::MAX, f64::MAX);
    for _ in 0..15 {
        let t0 = std::time::Instant::now();
        black_box(mat.sp_cholesky(Side::Lower).unwrap());
        t_new = t_new.min(t0.elapsed().as_secs_f64());
        let t0 = std::time::Instant::now();
        black_box(Llt::try_new_with_symbolic(symbolic.clone(), mat, Side::Lower).unwrap());
        t_cached = t_cached.min(t0.elapsed().as_secs_f64());
        let t0 = std::time::Instant::now();
        solver.factor(black_box(&a)).unwrap();
        t_reuse = t_reuse.min(t0.elapsed().as_secs_f64());
    }
    eprintln!(
        "interleaved minimum of 15: new each time {:.2} ms, cached symbolic {:.2} ms, railfem reuse {:.2} ms",
        1e3 * t_new,
        1e3 * t_cached,
        1e3 * t_reuse
    );
}

criterion_group!(benches, bench);
criterion_main!(benches);

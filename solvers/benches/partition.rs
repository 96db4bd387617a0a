//! One Newton iteration's linear algebra with a moving wheel: the direct sparse solver
//! against the partitioned one.
//!
//! The matrix is a long chain of 6-DOF nodes (each node's block full, coupled to its
//! neighbours, grounded: a rail on supports), `n` ≈ 2·10⁵ equations, plus a 6-equation
//! "wheelset" coupled by a dense 12×12 contact block to the two rail nodes under it. The
//! wheel moves one node further at every iteration, as a wheel does across rail elements:
//!
//! * `direct` — `A + V` assembled on the union pattern (which changes with the wheel's
//!   nodes: new symbolic analysis) and factored, then one solve;
//! * `partitioned` — [`Partitioned::factor`] with the constant `A` and `V` as triplets
//!   (blocks factored once, before the timing; the moving wheel only forms promotions),
//!   then one solve.

use criterion::{criterion_group, criterion_main, Criterion};
use railfem_framework::sparse::CscMatrix;
use railfem_solvers::linear::{LinearSolver, SparseCholesky};
use railfem_solvers::partition::{PartitionOptions, Partitioned};
use std::hint::black_box;

const NODES: usize = 33_000;

fn chain() -> Vec<(usize, usize, f64)> {
    let mut t = Vec::new();
    for k in 0..NODES {
        for a in 0..6 {
            for b in 0..6 {
                let i = 6 * k + a;
                let j = 6 * k + b;
                // A diagonally dominant SPD block plus the springs to the neighbours.
                let v = if a == b { 10.0 } else { 0.5 };
                t.push((i, j, v));
                if k + 1 < NODES && a == b {
                    t.push((i, i + 6, -2.0));
                    t.push((i + 6, i, -2.0));
                    t.push((i, i, 2.0));
                    t.push((i + 6, i + 6, 2.0));
                }
            }
        }
    }
    for e in 6 * NODES..6 * NODES + 6 {
        t.push((e, e, 4.0));
    }
    t
}

/// The wheel's contact block between the wheelset and rail node `at`.
fn wheel(at: usize) -> Vec<(usize, usize, f64)> {
    let w = 6 * NODES;
    let mut v = Vec::new();
    for a in 0..6 {
        let (r, s) = (6 * at + a, w + a);
        for (i, j, x) in [(r, r, 3.0), (s, s, 3.0), (r, s, -3.0), (s, r, -3.0)] {
            v.push((i, j, x));
        }
    }
    v
}

fn bench(c: &mut Criterion) {
    let base = chain();
    let n = 6 * NODES + 6;
    let a = CscMatrix::from_triplets(n, &base);
    let rhs: Vec<f64> = (0..n).map(|i| ((i * 7) % 13) as f64 - 6.0).collect();
    let mut g = c.benchmark_group("moving_wheel_iteration");
    g.sample_size(10);
    let mut at = 1000;
    g.bench_function("direct", |b| {
        let mut s = SparseCholesky::new();
        b.iter(|| {
            at = (at + 1) % (NODES - 1);
            let mut t = base.clone();
            t.extend(wheel(at));
            let m = CscMatrix::from_triplets(n, &t);
            s.factor(&m).unwrap();
            let mut x = rhs.clone();
            s.solve_in_place(&mut x).unwrap();
            black_box(x)
        })
    });
    let mut p = Partitioned::new(true, PartitionOptions::default());
    p.factor(&a, [1.0, 0.0, 0.0], &wheel(at)).unwrap();
    g.bench_function("partitioned", |b| {
        b.iter(|| {
            at = (at + 1) % (NODES - 1);
            p.factor(&a, [1.0, 0.0, 0.0], &wheel(at)).unwrap();
            let mut x = rhs.clone();
            p.solve_in_place(&mut x).unwrap();
            black_box(x)
        })
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);

//! Reduced blocks against an independent dense Galerkin solve.

use super::super::{PartitionOptions, Partitioned};
use super::ReducedBasis;
use nalgebra::{DMatrix, DVector};
use railfem_framework::sparse::CscMatrix;
use std::sync::Arc;

/// A chain of 2-DOF nodes (springs to the neighbours and to ground, the two DOFs
/// coupled): symmetric positive definite; and 2 extra equations (a "vehicle") coupled to
/// node `at` by an unsymmetric variable part.
fn system(nodes: usize, at: usize) -> (CscMatrix, Vec<(usize, usize, f64)>) {
    let n = 2 * nodes + 2;
    let mut t = Vec::new();
    for k in 0..nodes {
        let (i, j) = (2 * k, 2 * k + 1);
        t.extend([(i, i, 2.5), (j, j, 3.5), (i, j, -0.3), (j, i, -0.3)]);
        if k + 1 < nodes {
            for d in [i, j] {
                t.extend([
                    (d, d, 2.0),
                    (d + 2, d + 2, 2.0),
                    (d, d + 2, -2.0),
                    (d + 2, d, -2.0),
                ]);
            }
        }
    }
    for e in 2 * nodes..n {
        t.push((e, e, 2.0));
    }
    let v = (0..2)
        .flat_map(|d| {
            let (c, e) = (2 * at + d, 2 * nodes + d);
            [(c, c, 1.0), (e, e, 1.0), (c, e, -1.0), (e, c, -0.7)]
        })
        .collect();
    (CscMatrix::from_triplets(n, &t), v)
}

/// A deterministic, well-spread `rows × cols` matrix (not derived from the system: the
/// Galerkin identities hold for any basis).
fn spread(rows: usize, cols: usize, seed: usize) -> DMatrix<f64> {
    DMatrix::from_fn(rows, cols, |i, j| {
        let h = (i * 7919 + j * 104_729 + seed * 13) % 1009;
        h as f64 / 1009.0 - 0.5 + if i == j { 1.0 } else { 0.0 }
    })
}

/// `T·(Tᵀ·(A + V)·T)⁻¹·Tᵀ·b` with `T` the identity outside `interior` and `[Ψ Φ]` on it
/// (columns: the equations outside `interior` in order, then the modes), by a dense LU.
fn galerkin_solve(
    a: &CscMatrix,
    v: &[(usize, usize, f64)],
    b: &[f64],
    reduced: &[(&[usize], &[usize], &ReducedBasis)],
) -> Vec<f64> {
    let n = a.n;
    let mut kept = vec![true; n];
    for (interior, _, _) in reduced {
        for &i in *interior {
            kept[i] = false;
        }
    }
    let col_of: Vec<Option<usize>> = {
        let mut c = 0;
        kept.iter()
            .map(|&k| {
                k.then(|| {
                    c += 1;
                    c - 1
                })
            })
            .collect()
    };
    let nk = kept.iter().filter(|&&k| k).count();
    let m = nk + reduced.iter().map(|r| r.2.phi.ncols()).sum::<usize>();
    let mut t = DMatrix::<f64>::zeros(n, m);
    for i in 0..n {
        if let Some(c) = col_of[i] {
            t[(i, c)] = 1.0;
        }
    }
    let mut at = nk;
    for (interior, boundary, basis) in reduced {
        for (l, &i) in interior.iter().enumerate() {
            for (k, &g) in boundary.iter().enumerate() {
                t[(i, col_of[g].expect("boundary kept"))] = basis.psi[(l, k)];
            }
            for k in 0..basis.phi.ncols() {
                t[(i, at + k)] = basis.phi[(l, k)];
            }
        }
        at += basis.phi.ncols();
    }
    let mut full = a.to_dense();
    for &(i, j, x) in v {
        full[(i, j)] += x;
    }
    let lhs = t.transpose() * full * &t;
    let rhs = t.transpose() * DVector::from_column_slice(b);
    let y = lhs.lu().solve(&rhs).expect("regular");
    (t * y).as_slice().to_vec()
}

fn max_abs(x: &[f64]) -> f64 {
    x.iter().fold(0.0f64, |m, v| m.max(v.abs()))
}

/// Two blocks reduced (one with modes, one Guyan-only) solve as the dense Galerkin system
/// `Tᵀ·(A + V)·T`, with and without the top chain's condensation; the residual of that
/// solution, projected to the reduced coordinates, vanishes; returning the blocks to full
/// form gives the plain solve back. Both sides are backward-stable direct solves of a
/// system with condition ≈ 1e2: 1e-11 of the largest entry.
#[test]
fn reduced_blocks_solve_as_the_galerkin_system() {
    let (a, v) = system(300, 30);
    let b: Vec<f64> = (0..a.n).map(|i| ((i * 37 % 11) as f64) - 5.0).collect();
    for groups in [0, 2] {
        let mut p = Partitioned::new(
            false,
            PartitionOptions {
                block_size: 60,
                threads: 2,
                top_group_blocks: groups,
                ..Default::default()
            },
        );
        p.factor(&a, [1.0, 0.0, 0.0], &v).unwrap();
        let nb = p.block_count();
        let chosen: Vec<usize> = (0..nb)
            .filter(|&k| !p.block_has_promoted(k))
            .skip(2)
            .step_by(3)
            .take(2)
            .collect();
        assert_eq!(chosen.len(), 2, "{nb} blocks");
        let bases: Vec<Arc<ReducedBasis>> = chosen
            .iter()
            .enumerate()
            .map(|(s, &k)| {
                let (ni, nbd) = (p.block_interior(k).len(), p.block_boundary(k).len());
                Arc::new(ReducedBasis {
                    psi: spread(ni, nbd, s),
                    phi: spread(ni, 4 * (1 - s), s + 5),
                })
            })
            .collect();
        for (&k, basis) in chosen.iter().zip(&bases) {
            p.set_reduced_block(k, Some(basis.clone())).unwrap();
        }
        assert!(p.has_reduced_blocks());
        p.factor(&a, [1.0, 0.0, 0.0], &v).unwrap();
        let mut x = b.clone();
        p.solve_in_place(&mut x).unwrap();
        let interiors: Vec<Vec<usize>> = chosen
            .iter()
            .map(|&k| p.block_interior(k).to_vec())
            .collect();
        let boundaries: Vec<Vec<usize>> = chosen
            .iter()
            .map(|&k| p.block_boundary(k).to_vec())
            .collect();
        let spec: Vec<(&[usize], &[usize], &ReducedBasis)> = (0..2)
            .map(|s| (&interiors[s][..], &boundaries[s][..], &*bases[s]))
            .collect();
        let reference = galerkin_solve(&a, &v, &b, &spec);
        let scale = max_abs(&reference);
        let e = x
            .iter()
            .zip(&reference)
            .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
        assert!(e <= 1e-11 * scale, "groups {groups}: {e:e} of {scale:e}");
        // Tᵀ·(b − (A + V)·x) = 0: the projected residual is round-off.
        let mut r = b.clone();
        a.mul_vec_add(-1.0, &x, &mut r);
        for &(i, j, val) in &v {
            r[i] -= val * x[j];
        }
        p.project_reduced_rows(&mut r);
        let rn = max_abs(&r);
        assert!(
            rn <= 1e-11 * max_abs(&b),
            "groups {groups}: projected residual {rn:e}"
        );
        // Back to full form: the plain solve.
        for &k in &chosen {
            p.set_reduced_block(k, None).unwrap();
        }
        p.factor(&a, [1.0, 0.0, 0.0], &v).unwrap();
        let mut x = b.clone();
        p.solve_in_place(&mut x).unwrap();
        let plain = galerkin_solve(&a, &v, &b, &[]);
        let e = x
            .iter()
            .zip(&plain)
            .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
        assert!(
            e <= 1e-11 * max_abs(&plain),
            "groups {groups}, full again: {e:e}"
        );
    }
}

/// A basis of the wrong size, or a block a variable element acts on, is refused.
#[test]
fn a_reduced_block_refuses_a_wrong_basis_and_a_wheel() {
    let (a, v) = system(300, 30);
    let mut p = Partitioned::new(
        false,
        PartitionOptions {
            block_size: 60,
            threads: 1,
            top_group_blocks: 0,
            ..Default::default()
        },
    );
    p.factor(&a, [1.0, 0.0, 0.0], &v).unwrap();
    let k = (0..p.block_count())
        .find(|&k| p.block_has_promoted(k))
        .expect("promoted");
    let (ni, nbd) = (p.block_interior(k).len(), p.block_boundary(k).len());
    let good = Arc::new(ReducedBasis {
        psi: spread(ni, nbd, 0),
        phi: spread(ni, 2, 1),
    });
    let err = p.set_reduced_block(k, Some(good)).unwrap_err();
    assert!(err.contains("variable element"), "{err}");
    let wrong = Arc::new(ReducedBasis {
        psi: spread(ni, nbd + 1, 0),
        phi: spread(ni, 2, 1),
    });
    let err = p.set_reduced_block(k, Some(wrong)).unwrap_err();
    assert!(err.contains("boundary"), "{err}");
}

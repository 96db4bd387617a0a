//! The reduced far field's blocks at span joints (`partition/reduced_cuts.rs`,
//! `railfem_solvers::reduced::congruent`, `railfem::far_field::block_cuts`), on a
//! five-span viaduct alone (`viaduct_under_ground_motion`: the track on the bridge and
//! its approaches, no train, no gravity):
//!
//! 1. the blocks cut at every joint are a valid partition: no entry of `K`, `M` or `C`
//!    couples the interiors of two blocks (the solver's requirement);
//! 2. the spans' blocks are congruent but the first span's (its start on the abutment,
//!    without the pier the others hold); with the paper's 29.75 m
//!    spans only spans 5 apart are (the fasteners' layout repeats every 5 spans);
//! 3. one span's reduction carried to a congruent span by the map gives that span's own
//!    reduction: `Ψ` to 1e-9 of its largest entry, each of its own modes within 1e-6 (in
//!    the `M_II` norm) of the carried modes' subspace, the frequencies to 1e-8 — bounds
//!    for two runs of the same direct solve and subspace iteration on matrices equal to
//!    1e-12 (they come out equal to the bit: the spans' matrices are).
//!
//! `cargo test --release --test far_field_blocks -- --nocapture` prints the numbers.

use nalgebra::DMatrix;
use railfem::far_field::{block_cuts, CONGRUENT};
use railfem::solvers::partition::ReducedBasis;
use railfem::solvers::reduced::cutoff::CutOffRule;
use railfem::solvers::reduced::restrict;
use railfem::solvers::Driver;
use railfem::train_bridge::viaduct_under_ground_motion as viaduct;
use railfem::train_bridge::{read_quake, TrainBridgeCase};
use std::path::Path;

const DT: f64 = 2e-3;
const SPANS: usize = 5;

/// The viaduct of `spans` spans of `span` m cut at every joint, and for each span the
/// block inside it.
fn cut_viaduct(spans: usize, span: f64) -> (Driver, TrainBridgeCase, Vec<usize>) {
    let case = TrainBridgeCase {
        cars: 1,
        spans,
        span,
        dt: DT,
        ..Default::default()
    };
    let quake = read_quake(Path::new("examples/records/synthetic_kt.csv")).expect("record");
    let (mut d, _) = viaduct(&case, &quake, 3000).expect("viaduct");
    let xs: Vec<f64> = d.model.nodes.iter().map(|n| n.position.x).collect();
    let range = [
        xs.iter().copied().fold(f64::INFINITY, f64::min),
        xs.iter().copied().fold(f64::NEG_INFINITY, f64::max),
    ];
    let v = case.window_track().viaduct;
    let nb = d
        .cut_blocks_at(&block_cuts(v, 1, range))
        .expect("partitioned");
    let interiors = d.partition_interiors();
    assert_eq!(interiors.len(), nb);
    let x_of = |e: usize| d.model.nodes[d.asm.dofmap.dof_of(e).0].position.x;
    let span_block: Vec<usize> = (0..spans)
        .map(|k| {
            let (lo, hi) = (
                v.start + k as f64 * v.span,
                v.start + (k + 1) as f64 * v.span,
            );
            let inside: Vec<usize> = (0..nb)
                .filter(|&b| {
                    let mid = interiors[b].iter().map(|&e| x_of(e)).sum::<f64>()
                        / interiors[b].len() as f64;
                    mid > lo && mid < hi
                })
                .collect();
            assert_eq!(inside.len(), 1, "span {k}: blocks {inside:?}");
            inside[0]
        })
        .collect();
    (d, case, span_block)
}

/// 30 m spans: the fasteners (every 0.625 m of station) fall alike on every span.
#[test]
fn blocks_cut_at_the_joints_separate_the_spans_and_share_a_reduction() {
    let (d, _case, span_block) = cut_viaduct(SPANS, 30.0);
    // 1. No coupling between two blocks' interiors.
    let interiors = d.partition_interiors();
    let mut block_of = vec![usize::MAX; d.neq()];
    for (b, all) in interiors.iter().enumerate() {
        for &e in all {
            block_of[e] = b;
        }
    }
    for a in [&d.asm.k_const, &d.asm.m_const, &d.asm.c_const] {
        for j in 0..a.n {
            for p in a.col_ptr[j]..a.col_ptr[j + 1] {
                let (bi, bj) = (block_of[a.row_idx[p]], block_of[j]);
                assert!(
                    bi == usize::MAX || bj == usize::MAX || bi == bj,
                    "equations {} and {j} of blocks {bi} and {bj} are coupled",
                    a.row_idx[p]
                );
            }
        }
    }
    let sizes: Vec<usize> = span_block.iter().map(|&b| interiors[b].len()).collect();
    println!(
        "{} blocks; the spans' blocks {span_block:?} with {sizes:?} interior equations",
        interiors.len()
    );
    // 2. The spans after the first are congruent: each block holds its span's girder and
    //    the pier under its start. The first span starts on the abutment (no pier), so it
    //    is not. The last one is: its end node, on the boundary, has the same bearing
    //    (to the ground instead of a pier top, which lies in the next block).
    for k in 2..SPANS {
        assert!(
            d.block_congruence(span_block[1], span_block[k], CONGRUENT)
                .is_some(),
            "span {k} against span 1"
        );
    }
    assert!(d
        .block_congruence(span_block[1], span_block[0], CONGRUENT)
        .is_none());
    // 3. The carried reduction is the span's own.
    let (a, b) = (span_block[1], span_block[2]);
    let map = d.block_congruence(a, b, CONGRUENT).expect("congruent");
    let cutoff = CutOffRule::default().omega(DT);
    let own = |blk: usize| {
        d.block_reduction(blk, cutoff)
            .expect("partitioned")
            .expect("reduction")
    };
    let (ra, rb) = (own(a), own(b));
    let carried = ReducedBasis {
        psi: ra.psi.clone(),
        phi: ra.phi.clone(),
    }
    .mapped(&map);
    let scale = rb.psi.amax();
    let psi_err = (&carried.psi - &rb.psi).amax() / scale;
    assert_eq!(ra.omega.len(), rb.omega.len(), "modes kept");
    let omega_err = ra
        .omega
        .iter()
        .zip(&rb.omega)
        .map(|(x, y)| ((x - y) / y).abs())
        .fold(0.0, f64::max);
    // Each own mode against its M_II-projection on the carried modes (both sets are
    // M_II-orthonormal): φ − Φ_c·(Φ_cᵀ·M_II·φ), in the M_II norm.
    let mut interior: Vec<usize> = d.partition_interiors()[b].clone();
    interior.sort_unstable();
    let m_ii = restrict(&d.asm.m_const, &interior);
    let m_times = |x: &DMatrix<f64>| {
        let mut out = DMatrix::<f64>::zeros(x.nrows(), x.ncols());
        for j in 0..x.ncols() {
            m_ii.mul_vec(x.column(j).as_slice(), out.column_mut(j).as_mut_slice());
        }
        out
    };
    let coef = carried.phi.transpose() * m_times(&rb.phi);
    let rest = &rb.phi - &carried.phi * coef;
    let norms = rest.transpose() * m_times(&rest);
    let phi_err = (0..norms.ncols())
        .map(|j| norms[(j, j)].max(0.0).sqrt())
        .fold(0.0, f64::max);
    println!(
        "span 1 → span 2 ({} interior, {} boundary, {} modes; identity map: {}): Ψ {psi_err:.2e} of its largest, modes outside the carried subspace {phi_err:.2e}, ω {omega_err:.2e}",
        map.interior.len(),
        map.boundary.len(),
        rb.omega.len(),
        map.is_identity()
    );
    assert!(psi_err <= 1e-9, "Ψ: {psi_err:e}");
    assert!(phi_err <= 1e-6, "Φ: {phi_err:e}");
    assert!(omega_err <= 1e-8, "ω: {omega_err:e}");
}

/// The paper's 29.75 m spans: the fasteners every 0.625 m of station repeat on a span
/// every 5 spans (5 × 29.75 m = 238 × 0.625 m), so neighbouring spans differ (a fastener
/// node more or less, elsewhere) and spans 5 apart are congruent.
#[test]
fn spans_with_another_fastener_layout_are_not_shared() {
    let (d, _case, span_block) = cut_viaduct(8, 29.75);
    let alike = |a: usize, b: usize| {
        d.block_congruence(span_block[a], span_block[b], CONGRUENT)
            .is_some()
    };
    for k in 2..6 {
        assert!(!alike(1, k), "span {k} against span 1");
    }
    assert!(alike(1, 6), "span 6 against span 1");
    assert!(alike(2, 7), "span 7 against span 2");
    assert!(!alike(5, 0), "span 0, on the abutment, against span 5");
}

//! The cost of a reduced far field under ground motion, against the number of spans.
//!
//! For each span count given on the command line, builds the `train-bridge` model (12
//! carriages on the approach, rails at 0.625 m, Δt = 0.5 ms) and takes its linear system
//! about the reference state (`Driver::reference_system`). It then marches the linear
//! model under the synthetic record of `examples/records/synthetic_kt.csv` twice: in full,
//! and with every span reduced (`railfem_solvers::reduced`) except a window of 12 spans
//! in the middle of the bridge, which stays full as the spans under a train would. Spans
//! whose matrices are equal share one reduction. It prints the sizes, the set-up times
//! and the time per step of each march (the generalized-α step of a linear model: one
//! solve with the factored effective matrix and the products with `M`, `C` and `K`; no
//! train contact, no Newton iterations).
//!
//! `cargo run --release --example reduced_far_field -- 113 226 452`

use nalgebra::DVector;
use railfem::framework::sparse::CscMatrix;
use railfem::solvers::integrator::Integrator;
use railfem::solvers::modal::ModalOptions;
use railfem::solvers::reduced::cutoff::CutOffRule;
use railfem::solvers::reduced::march::LinearMarch;
use railfem::solvers::reduced::mixed::{on_one_pattern, MixedModel, ReducedBlock};
use railfem::solvers::reduced::{block_splits, ground_influence, restrict, CraigBampton};
use railfem::train_bridge::{build, read_quake, TrainBridgeCase};
use std::path::Path;
use std::sync::Arc;
use std::time::Instant;

/// Spans that stay full around the middle of the bridge.
const WINDOW: usize = 12;
/// Timed steps of each march.
const STEPS: usize = 40;

/// Whether two restricted blocks have the same pattern and values within 1e-9 of the
/// largest (the same span at another place along the bridge).
fn equal(a: &[CscMatrix; 3], b: &[CscMatrix; 3]) -> bool {
    a.iter().zip(b).all(|(x, y)| {
        let big = x.values.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        x.n == y.n
            && x.col_ptr == y.col_ptr
            && x.row_idx == y.row_idx
            && x.values
                .iter()
                .zip(&y.values)
                .all(|(u, v)| (u - v).abs() <= 1e-9 * big)
    })
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let spans: Vec<usize> = std::env::args()
        .skip(1)
        .map(|a| a.parse())
        .collect::<Result<_, _>>()?;
    let quake = read_quake(Path::new("examples/records/synthetic_kt.csv"))?;
    let dt = 5e-4;
    let rule = CutOffRule::default();
    println!("spans,equations,reduced_coordinates,distinct_reductions,reduction_s,mixed_build_s,full_step_ms,reduced_step_ms,ratio,load_average");
    for n_spans in spans {
        let case = TrainBridgeCase {
            cars: 12,
            spans: n_spans,
            dt,
            ..Default::default()
        };
        let mut model = build(&case)?;
        let sys = model.driver.reference_system()?;
        let d = &model.driver;
        let n = sys.stiffness.n;
        let (k, m, c) = (&sys.stiffness, &sys.mass, &sys.damping);
        let x_of: Vec<f64> = (0..n)
            .map(|e| d.model.nodes[d.asm.dofmap.dof_of(e).0].position.x)
            .collect();
        let first_full = n_spans.saturating_sub(WINDOW) / 2;
        let t0 = Instant::now();
        let mut cache: Vec<([CscMatrix; 3], Arc<CraigBampton>)> = Vec::new();
        let mut blocks = Vec::new();
        // block of each equation: the reduced span whose open station interval holds its node
        let reduced: Vec<usize> = (0..n_spans)
            .filter(|s| !(first_full..first_full + WINDOW).contains(s))
            .collect();
        let mut span_block = vec![None; n_spans];
        for (b, &s) in reduced.iter().enumerate() {
            span_block[s] = Some(b);
        }
        let block_of: Vec<Option<usize>> = x_of
            .iter()
            .map(|&x| {
                let u = (x - case.approach()) / case.span;
                let s = u.floor();
                if s < 0.0 || s >= n_spans as f64 || u == s {
                    None
                } else {
                    span_block[s as usize]
                }
            })
            .collect();
        for (eqs, split) in block_splits(&[k, m, c], &block_of, reduced.len()) {
            let mats = [restrict(k, &eqs), restrict(m, &eqs), restrict(c, &eqs)];
            let reduction = match cache.iter().find(|(a, _)| equal(a, &mats)) {
                Some((_, r)) if r.split() == &split => r.clone(),
                _ => {
                    let r = Arc::new(CraigBampton::build(
                        &mats[0],
                        &mats[1],
                        Some(&mats[2]),
                        &split,
                        rule.omega(dt),
                        &ModalOptions::default(),
                    )?);
                    cache.push((mats, r.clone()));
                    r
                }
            };
            blocks.push(ReducedBlock { eqs, reduction });
        }
        let t_reduce = t0.elapsed().as_secs_f64();
        let t0 = Instant::now();
        let mixed = MixedModel::new(k, m, c, blocks)?;
        let t_mixed = t0.elapsed().as_secs_f64();
        let mr = ground_influence(m, |e| d.asm.dofmap.dof_of(e).1);
        let mr_mixed: Vec<Vec<f64>> = mr.iter().map(|v| mixed.reduce(v)).collect();
        let a_g = |t: f64, dir: usize| {
            let (ts, a) = (&quake.t, &quake.a[dir]);
            let i = ts.partition_point(|&s| s <= t).clamp(1, ts.len() - 1);
            let w = ((t - ts[i - 1]) / (ts[i] - ts[i - 1])).clamp(0.0, 1.0);
            a[i - 1] + w * (a[i] - a[i - 1])
        };
        let load = |t: f64, basis: &[Vec<f64>]| {
            let mut f = DVector::zeros(basis[0].len());
            for (dir, v) in basis.iter().enumerate() {
                f -= DVector::from_column_slice(v) * a_g(t, dir);
            }
            f
        };
        let integ = Integrator::generalized_alpha(case.rho_inf);
        // Both marches side by side, each step of one timed next to the same step of the
        // other, so that a change of the machine's load falls on both alike.
        let march = |mats: [CscMatrix; 3]| -> Result<_, Box<dyn std::error::Error>> {
            let [mm, cc, kk] = mats;
            let len = mm.n;
            let mut march = LinearMarch::sparse(integ, dt, mm, cc, kk)?;
            let z = DVector::zeros(len);
            let s = march.start(z.clone(), z.clone(), &z)?;
            Ok((march, s))
        };
        let (mut full, mut sf) = march(on_one_pattern([m, c, k]))?;
        let (mut red, mut sr) = march([mixed.m.clone(), mixed.c.clone(), mixed.k.clone()])?;
        // in the strong part of the record (from 2 s)
        let at = |i: usize| 2.0 + i as f64 * dt;
        let lf: Vec<DVector<f64>> = (0..=STEPS).map(|i| load(at(i), &mr)).collect();
        let lr: Vec<DVector<f64>> = (0..=STEPS).map(|i| load(at(i), &mr_mixed)).collect();
        let (mut full_s, mut red_s) = (0.0, 0.0);
        for i in 0..STEPS {
            let t0 = Instant::now();
            full.step(&mut sf, &lf[i], &lf[i + 1]);
            full_s += t0.elapsed().as_secs_f64();
            let t0 = Instant::now();
            red.step(&mut sr, &lr[i], &lr[i + 1]);
            red_s += t0.elapsed().as_secs_f64();
        }
        let (full_ms, red_ms) = (1e3 * full_s / STEPS as f64, 1e3 * red_s / STEPS as f64);
        let load_average = std::fs::read_to_string("/proc/loadavg")
            .ok()
            .and_then(|l| l.split_whitespace().next().map(str::to_owned))
            .unwrap_or_default();
        println!(
            "{n_spans},{n},{},{},{t_reduce:.2},{t_mixed:.2},{full_ms:.2},{red_ms:.2},{:.2},{load_average}",
            mixed.size(),
            cache.len(),
            full_ms / red_ms
        );
    }
    Ok(())
}

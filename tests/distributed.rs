//! The partitioned solver across ranks gives the one-process answers.
//!
//! A train crosses a bridge; the model is stepped in one process and on 2 and 3 in-process
//! "ranks" (threads, `railfem::solvers::exchange::thread_ranks`), each rank with its own copy
//! of the model and driver, as MPI processes would have. The ranks share the blocks of the
//! partitioned solver: each factors, promotes and condenses only its own, rank 0 forms and
//! solves the top system, and the interiors are exchanged so that every rank ends each step
//! with the whole state. Each rank keeps only the columns of the effective matrix its share
//! reads, so the ranks' matrices add up to the one-process one. The blocks are small and the train fast, so the wheels move onto
//! new rail nodes every step and blocks of every rank gain and lose promoted equations.
//!
//! Reference: the one-process partitioned solver (itself checked against the direct solver in
//! tests/partitioned.rs and against the full-residual Newton in tests/condensed.rs). The
//! distributed solve performs the same floating-point operations in the same order (rank 0
//! sums the blocks' pieces in block order), so the histories agree to round-off at most;
//! 1e-12 of the largest value bounds that, far below the Newton tolerance (an iteration
//! more or less would change the answer by ~1e-8 of its scale). With the residual per rank
//! each rank also holds fewer elements, and the energy balance is summed over the ranks'
//! own rows in block order: its rows equal one process's to round-off and are the same
//! for 2 and 3 ranks.

mod common;

use railfem::framework::model::SolverChoice;
use railfem::solvers::energy::EnergyRow;
use railfem::solvers::exchange::{thread_ranks, Exchange};
use railfem::solvers::partition::{PartitionOptions, PartitionStats};
use railfem::train_bridge::{build, build_across_ranks, TrainBridgeCase};
use std::sync::Arc;

fn case(solver: SolverChoice) -> TrainBridgeCase {
    TrainBridgeCase {
        cars: 1,
        spans: 2,
        element_length: 0.4,
        speed: 100.0,
        dt: 0.004,
        mu: 0.3,
        solver,
        ..Default::default()
    }
}

type History = Vec<[Vec<f64>; 3]>;

/// What one rank ran: the state after each step, the Newton iterations, the solver's
/// counters, the stored entries of the effective matrix it kept, its rows (those it formed
/// the residual of, the entries of `K` it kept and the elements it held whole) and the
/// wheels' outputs and the energy balance's rows after each step.
type Run = (History, usize, PartitionStats, usize, Rows, Recorded);

/// The wheels' outputs after each step (what rank 0 records in `wheels.csv`) and the
/// energy balance's rows (`energy.csv`).
type Recorded = (Vec<Vec<f64>>, Vec<EnergyRow>);

/// Rows whose residual a rank formed, the stored entries of the constant `K` it kept, the
/// elements it held whole (the model's count in one process), and the most entries of `K`
/// it ever held (at the build).
type Rows = (usize, usize, usize, usize);

/// `steps` steps on one rank of `exchange` (`None`: one process); with `own_rows` each rank
/// forms the residual of its own rows only (`Driver::keep_own_rows`).
fn history(
    exchange: Option<Arc<dyn Exchange>>,
    condensed: bool,
    steps: usize,
    own_rows: bool,
) -> Run {
    let options = PartitionOptions {
        block_size: 120,
        threads: 1,
        ..Default::default()
    };
    // With its own rows a rank splits the blocks on the pattern and forms `K`, `M`, `C`
    // on its columns only (`Driver::new_across_ranks`); without, it builds the whole
    // matrices and shares the blocks afterwards.
    let mut m = match (&exchange, own_rows) {
        (Some(ex), true) => {
            build_across_ranks(&case(SolverChoice::Partitioned), ex.clone(), Some(options))
                .expect("model")
        }
        _ => build(&case(SolverChoice::Partitioned)).expect("model"),
    };
    let d = &mut m.driver;
    d.set_condense_residual(condensed);
    if let Some(ex) = exchange {
        if own_rows {
            assert!(
                d.keep_own_rows(),
                "the train-bridge model keeps its own rows from the build"
            );
            assert!(
                d.energy.is_some(),
                "the energy balance summed over the ranks' own rows"
            );
        } else {
            d.set_partition_options(options);
            d.set_exchange(ex).expect("partitioned model");
        }
    } else {
        d.set_partition_options(options);
    }
    let built = d.constant_entries_built();
    d.static_solve(0.0, 4).expect("static preload");
    d.initialize().expect("initial accelerations");
    let mut out = Vec::new();
    let mut wheels = Vec::new();
    let mut iterations = 0;
    for _ in 0..steps {
        iterations += d.step(0.004).expect("step").iterations;
        out.push([d.state.q.clone(), d.state.v.clone(), d.state.a.clone()]);
        let mut row = Vec::new();
        for &ei in &m.wheel_index {
            let mut o = Vec::new();
            d.model.elements[ei].element.outputs(&mut o);
            row.extend(o);
        }
        wheels.push(row);
    }
    let entries = d.effective_matrix_entries();
    (
        out,
        iterations,
        d.partition_stats().expect("partitioned"),
        entries,
        (
            d.rows_owned(),
            d.constant_entries(),
            d.elements_held(),
            built.max(d.constant_entries_built()),
        ),
        (
            wheels,
            d.energy.as_ref().expect("energy balance").history.clone(),
        ),
    )
}

fn compare(condensed: bool, steps: usize, own_rows: bool) {
    let (serial, it_serial, s1, entries_serial, (n, k_serial, elements, _), recorded) =
        history(None, condensed, steps, false);
    let (wheels_serial, energy_serial) = recorded;
    let energy_scale = energy_serial.iter().fold(0.0f64, |m, r| m.max(r.scale()));
    assert_eq!(energy_serial.len(), steps);
    // The wheels enter new rail nodes every step (0.4 m per step over 0.4 m elements).
    assert!(s1.promotions >= steps, "{s1:?}");
    assert!(s1.blocks >= 6, "{s1:?}");
    // The balance's rows of the first run across ranks: those of every other run and rank
    // are the same to the bit (summed in block order whatever the number of ranks).
    let mut energy_ranks: Option<Vec<EnergyRow>> = None;
    for ranks in [2, 3] {
        let runs: Vec<Run> = std::thread::scope(|s| {
            let hs: Vec<_> = thread_ranks(ranks)
                .into_iter()
                .map(|ex| s.spawn(move || history(Some(ex), condensed, steps, own_rows)))
                .collect();
            hs.into_iter().map(|h| h.join().expect("rank")).collect()
        });
        for (r, (h, it, st, _, rows, (wheels, energy))) in runs.iter().enumerate() {
            let e = common::worst_relative(h, &serial);
            println!(
                "condensed {condensed}, own rows {own_rows}, {ranks} ranks, rank {r}: relative differences q {:.1e}, v {:.1e}, a {:.1e}; {} of {} blocks; {} bytes sent, {} received; rows {} of {n}, K entries {} of {k_serial}",
                e[0], e[1], e[2], st.owned_blocks, st.blocks, st.comm.bytes_sent, st.comm.bytes_received, rows.0, rows.1
            );
            assert_eq!(
                *it, it_serial,
                "{ranks} ranks, rank {r}: the same Newton iterations"
            );
            for (what, x) in ["displacements", "velocities", "accelerations"]
                .iter()
                .zip(e)
            {
                assert!(
                    x <= 1e-12,
                    "{ranks} ranks, rank {r}: {what} differ by {x:e}"
                );
            }
            // The wheels (every rank holds them) report what one process's report: each
            // output to 1e-12 of the largest magnitude of all (the same bound as the state).
            let flat = |h: &[Vec<f64>]| h.concat();
            let (a, b) = (flat(wheels), flat(&wheels_serial));
            assert_eq!(a.len(), b.len());
            let scale = b.iter().fold(0.0f64, |m, x| m.max(x.abs()));
            let diff = a
                .iter()
                .zip(&b)
                .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
            let w = [diff / scale];
            println!("  wheel outputs differ by {:.1e}", w[0]);
            // The energy balance: every row of every rank, each energy to 1e-12 of the
            // largest energy of the run. Summed over the own rows of each block and the
            // blocks added in block order, the works and `vᵀ·M·v` are one process's sums
            // (over fixed chunks of the equations) in another order: a sum of n terms
            // reordered moves by at most (n − 1)·u·Σ|terms| (u = 1.1e-16, the unit
            // round-off; n = 8 784 equations here, (n − 1)·u ≈ 1e-12), and in practice by
            // about √n·u ≈ 1e-14 of it. Without
            // own rows every rank forms one process's sums, to the bit.
            assert_eq!(energy.len(), steps);
            let de = common::energy_difference(energy, &energy_serial);
            println!(
                "  energy rows differ by {de:.1e} of the largest energy ({energy_scale:.3e} J)"
            );
            let first = energy_ranks.get_or_insert_with(|| energy.clone());
            assert_eq!(
                first, energy,
                "{ranks} ranks, rank {r}: the balance does not depend on the ranks"
            );
            if own_rows {
                assert!(
                    de <= 1e-12,
                    "{ranks} ranks, rank {r}: energy rows differ by {de:e}"
                );
            } else {
                assert_eq!(de, 0.0, "{ranks} ranks, rank {r}: energy rows differ");
            }
            assert!(
                w[0] <= 1e-12,
                "{ranks} ranks, rank {r}: wheel outputs differ by {w:?}"
            );
        }
        // The blocks are shared, not repeated: each is owned, factored and promoted on one
        // rank only, and every rank owns some.
        let sum = |f: fn(&PartitionStats) -> usize| runs.iter().map(|r| f(&r.2)).sum::<usize>();
        assert_eq!(sum(|s| s.owned_blocks), s1.blocks);
        assert_eq!(sum(|s| s.block_factorizations), s1.block_factorizations);
        assert_eq!(sum(|s| s.promotions), s1.promotions);
        assert!(runs.iter().all(|r| r.2.owned_blocks > 0));
        assert_eq!(sum(|s| s.owned_interior_equations), s1.interior_equations);
        // The effective matrix is not replicated: each rank keeps the columns of its own
        // blocks' interiors, rank 0 those of the base top set as well, and these split the
        // equations, so the ranks' entries add up to the one-process matrix's.
        let entries: Vec<usize> = runs.iter().map(|r| r.3).collect();
        println!("effective matrix entries, one process {entries_serial}, ranks {entries:?}");
        assert_eq!(entries.iter().sum::<usize>(), entries_serial);
        assert!(entries.iter().all(|&e| e < entries_serial));
        // With its own rows, each rank forms the residual of its blocks' interiors (rank 0
        // also of the base top set): the rows split the equations. Each keeps the columns
        // of K, M, C of those rows and of the base top set (the top iterations' constant
        // part), so the ranks' entries exceed one process's by the base top set's columns
        // on every rank but 0, and each rank keeps fewer than one process.
        let rows: Vec<usize> = runs.iter().map(|r| r.4 .0).collect();
        let kept: Vec<usize> = runs.iter().map(|r| r.4 .1).collect();
        let held: Vec<usize> = runs.iter().map(|r| r.4 .2).collect();
        let built: Vec<usize> = runs.iter().map(|r| r.4 .3).collect();
        println!(
            "rows {rows:?} of {n}; K entries {kept:?} of {k_serial}, at most {built:?}; elements held {held:?} of {elements}"
        );
        if own_rows {
            assert_eq!(rows.iter().sum::<usize>(), n);
            assert!(rows.iter().all(|&r| r < n));
            assert!(kept.iter().sum::<usize>() >= k_serial);
            assert!(kept.iter().all(|&e| e < k_serial));
            // Rank 0 keeps the columns its share of the solver reads (its blocks' and the
            // base top set's); every other rank those of its blocks and the base top set's,
            // the same number of entries more on each.
            assert_eq!(kept[0], entries[0]);
            let base_top = kept[1] - entries[1];
            assert!(base_top > 0);
            assert!(
                (1..ranks).all(|r| kept[r] - entries[r] == base_top),
                "{kept:?}"
            );
            // Each rank holds only the elements its kept rows touch and those evaluated
            // every step (the train): fewer than the model's, at most about a share of the
            // bridge's plus what every rank holds, and together every element at least
            // once (each touches some equation, owned by some rank).
            assert!(held.iter().all(|&h| h < elements), "{held:?} of {elements}");
            assert!(held.iter().sum::<usize>() >= elements, "{held:?}");
            // The whole `K`, `M`, `C` never existed on a rank: each formed only the columns
            // it keeps until the initial mass solve (those of its rows, the base top set's
            // and the ones that solve's own split reads) — at least what it keeps after,
            // fewer entries than one process, and together every column at least once.
            assert!(
                built.iter().all(|&b| b < k_serial),
                "{built:?} of {k_serial}"
            );
            assert!(built.iter().sum::<usize>() >= k_serial, "{built:?}");
            assert!(built.iter().zip(&kept).all(|(b, k)| b >= k), "{built:?}");
        } else {
            assert!(rows.iter().all(|&r| r == n));
            assert!(kept.iter().all(|&e| e == k_serial));
            // The whole matrices built on every rank (shared after the build).
            assert!(built.iter().all(|&b| b == k_serial), "{built:?}");
            assert!(held.iter().all(|&h| h == elements));
        }
    }
}

#[test]
fn condensed_newton_across_ranks_equals_one_process() {
    compare(true, 20, false);
}

#[test]
fn full_residual_newton_across_ranks_equals_one_process() {
    compare(false, 6, false);
}

/// Each rank forms the residual of its own rows, with its columns of `K`, `M`, `C`; the
/// norms of the convergence test are summed over the ranks in block order. The answers
/// equal one process's to 1e-12 with the same Newton iterations (the norms differ by
/// round-off in their order of summation only, far below the test's tolerance margin).
#[test]
fn condensed_newton_on_own_rows_equals_one_process() {
    compare(true, 20, true);
}

#[test]
fn full_residual_newton_on_own_rows_equals_one_process() {
    compare(false, 6, true);
}

#[test]
fn a_model_without_the_partitioned_solver_is_refused_with_the_fix() {
    let mut m = build(&case(SolverChoice::Direct)).expect("model");
    let e = m
        .driver
        .set_exchange(thread_ranks(2).remove(0))
        .expect_err("the direct solver is not shared among ranks");
    let text = e.to_string();
    assert!(
        text.contains("2 ranks") && text.contains("solver = \"partitioned\""),
        "{text}"
    );
    assert_eq!(text.lines().count(), 1, "{text}");
}

/// The default build (no `mpi` feature) started by a launcher with two ranks refuses to run
/// the model alone on each rank: one line naming the fix, exit 2, nothing written. (The MPI
/// build under `mpirun` is checked by scripts/mpi.sh.)
#[test]
fn the_default_build_under_a_launcher_with_two_ranks_is_refused() {
    if cfg!(feature = "mpi") {
        return;
    }
    let dir = common::temp_dir("distributed-no-mpi");
    let out = dir.join("out");
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_railfem"))
        .args([
            "train-bridge",
            "--cars",
            "1",
            "--spans",
            "1",
            "--steps",
            "2",
            "-q",
        ])
        .arg("--out")
        .arg(&out)
        .env("OMPI_COMM_WORLD_SIZE", "2")
        .env("OMPI_COMM_WORLD_RANK", "0")
        .output()
        .expect("run railfem");
    common::refused_with(
        "train-bridge under a 2-rank launcher",
        &o,
        &["2 ranks", "this build has no MPI", "--features mpi"],
    );
    assert!(!out.join("wheels.csv").exists());
    let _ = std::fs::remove_dir_all(&dir);
}

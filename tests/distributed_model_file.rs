//! A model file's partitioned solver shared among ranks gives the one-process answers.
//!
//! `mpirun -n P railfem run MODEL.toml` (build `--features mpi`) shares the blocks of a model
//! file whose `[analysis]` picks `solver = "partitioned"`; `block_size` sets how many blocks
//! there are. Here the ranks are in-process threads (`thread_ranks`), each loading the file
//! and stepping its own driver as an MPI process would; scripts/mpi.sh runs the same model
//! under `mpirun -n 2`.
//!
//! The model: a continuous beam over six 25 m spans (300 elements of 0.5 m) with a sprung
//! mass crossing it at 50 m/s, from 20 m to 40 m, so it passes from one block into the next
//! and the blocks of both ranks gain and lose promoted equations. Reference: the same file
//! run in one process. The ranks perform the same floating-point operations in the same
//! order (rank 0 sums the blocks' pieces in block order), so 1e-12 of each column's largest
//! value bounds the difference, far below the Newton tolerance.

mod common;

use railfem::solvers::energy::EnergyRow;
use railfem::solvers::exchange::{thread_ranks, Exchange};
use railfem::solvers::partition::PartitionStats;
use std::path::Path;
use std::sync::Arc;

const ELEMENTS: usize = 300;
const H: f64 = 0.5;

/// The model file: beam, supports every 50 elements, sprung mass, two recorders.
fn model_text(analysis_extra: &str) -> String {
    let mut t = format!(
        "[analysis]\nkind = \"transient\"\nintegrator = \"newmark\"\ndt = 0.002\nduration = 0.4\n\
         gravity = [0.0, 0.0, -9.81]\nsolver = \"partitioned\"\n{analysis_extra}\n"
    );
    for i in 0..=ELEMENTS {
        t.push_str(&format!(
            "[[node]]\nid = {i}\nxyz = [{}, 0.0, 0.0]\n",
            i as f64 * H
        ));
        if i == 0 {
            t.push_str("fix = [\"ux\", \"uy\", \"uz\", \"rx\"]\n");
        } else if i % 50 == 0 {
            t.push_str("fix = [\"uy\", \"uz\"]\n");
        }
    }
    t.push_str("[[node]]\nid = 1000\nxyz = [0.0, 0.0, 1.0]\n");
    for e in 1..=ELEMENTS {
        t.push_str(&format!(
            "[[element]]\ntype = \"beam3d\"\nid = {e}\nnodes = [{}, {}]\nE = 2.943e10\nG = 1.2e10\n\
             A = 1.0\nIy = 1.0\nIz = 2.0\nJ = 0.5\nrho = 2303.0\nmass = \"consistent\"\n",
            e - 1,
            e
        ));
    }
    let path: Vec<String> = (1..=ELEMENTS).map(|e| e.to_string()).collect();
    t.push_str(&format!(
        "[[element]]\ntype = \"moving_sprung_mass\"\nid = 2000\nnodes = [1000]\nm = 5750.0\n\
         k = 1.595e6\npath = [{}]\nstart = 20.0\nspeed = 50.0\n",
        path.join(", ")
    ));
    t.push_str(
        "[[recorder]]\ntype = \"node\"\nnode = 75\ndofs = [\"uz\"]\nfile = \"span2.csv\"\n\
         [[recorder]]\ntype = \"element\"\nelement = 2000\noutputs = [\"contact_force\", \"mass_disp\"]\n\
         file = \"mass.csv\"\n",
    );
    t
}

fn write_model(dir: &Path, analysis_extra: &str) -> std::path::PathBuf {
    let p = dir.join("beam.toml");
    std::fs::write(&p, model_text(analysis_extra)).unwrap();
    p
}

/// What one rank recorded: its recorders' rows and the energy balance's.
type Recorded = (Vec<Vec<f64>>, PartitionStats, Vec<EnergyRow>);

/// How a rank shares the model.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Share {
    /// The whole matrices, the blocks shared after the build.
    Whole,
    /// Its own rows, narrowed after the whole build (`Driver::keep_own_rows`).
    RowsAfter,
    /// Its own rows, `K`, `M`, `C` formed on its columns only and the data check on their
    /// diagonals (`railfem::prepare_on`, as `railfem run` under mpirun does).
    RowsFromBuild,
}

/// Runs the file on one rank of `exchange` (`None`: one process) and keeps its recorders'
/// rows, the rank sharing the model as `share` says.
fn run(path: &Path, exchange: Option<Arc<dyn Exchange>>, share: Share) -> Recorded {
    let model = railfem::load_model(path);
    let mut d = match (&exchange, share) {
        (Some(ex), Share::RowsFromBuild) => {
            let (d, _) =
                railfem::prepare_on(model, "beam.toml", false, Some(ex.clone())).expect("driver");
            // K, M, C formed on the rank's columns: its own rows', the base top set's and
            // until the initial mass solve those that solve's split reads. That split
            // (blocks of 3 000 interior equations, as in one process) puts all 1 791
            // equations of this beam on top, which every rank keeps: here the rank forms
            // every column, as `keep_own_rows` keeps them (tests/distributed.rs has a model
            // where it forms fewer).
            let whole = railfem::solvers::Driver::new(railfem::load_model(path).expect("model"))
                .expect("driver")
                .constant_entries_built();
            assert_eq!(d.constant_entries_built(), whole);
            d
        }
        _ => railfem::solvers::Driver::new(model.expect("model")).expect("driver"),
    };
    if let Some(ex) = exchange {
        d.set_exchange(ex).expect("partitioned model");
        if share != Share::Whole {
            assert!(d.keep_own_rows(), "the beam keeps its own rows");
            assert!(d.elements_held() < ELEMENTS, "{} held", d.elements_held());
        }
    }
    let (_, kept) = d.run_keeping(None, true, &mut |_| {}).expect("run");
    let stats = d.partition_stats().expect("partitioned");
    let energy = d.energy.as_ref().expect("energy balance").history.clone();
    (kept.into_iter().map(|h| h.values).collect(), stats, energy)
}

/// Largest difference per recorder file, relative to the file's largest value.
fn worst(a: &[Vec<f64>], b: &[Vec<f64>]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| {
            assert_eq!(x.len(), y.len());
            let scale = y.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            x.iter()
                .zip(y)
                .fold(0.0f64, |m, (p, q)| m.max((p - q).abs()))
                / scale
        })
        .fold(0.0, f64::max)
}

#[test]
fn a_model_file_across_ranks_equals_one_process() {
    let dir = common::temp_dir("distributed-model-file");
    let path = write_model(&dir, "block_size = 150");
    let (serial, s1, energy_serial) = run(&path, None, Share::Whole);
    assert!(energy_serial.len() > 100);
    // The block size reached the solver: ~1800 equations in blocks of 150.
    assert!(s1.blocks >= 6, "{s1:?}");
    assert!(s1.promotions > 0, "{s1:?}");
    assert!(serial[0].len() > 100, "rows recorded");
    for (ranks, share) in [2, 3]
        .into_iter()
        .flat_map(|r| [Share::Whole, Share::RowsAfter, Share::RowsFromBuild].map(|s| (r, s)))
    {
        let runs: Vec<Recorded> = std::thread::scope(|s| {
            let hs: Vec<_> = thread_ranks(ranks)
                .into_iter()
                .map(|ex| {
                    let p = path.clone();
                    s.spawn(move || run(&p, Some(ex), share))
                })
                .collect();
            hs.into_iter().map(|h| h.join().expect("rank")).collect()
        });
        for (r, (h, st, energy)) in runs.iter().enumerate() {
            let e = worst(h, &serial);
            // The energy balance: each energy of every row to 1e-12 of the largest energy.
            // With own rows the sums are one process's in another order (block by block),
            // which moves a sum of n ≈ 1 800 terms by at most (n − 1)·u ≈ 2e-13 of the sum
            // of their magnitudes (u = 1.1e-16, the unit round-off), typically √n·u ≈ 5e-15;
            // 1e-12 leaves room for the accumulation over the steps. The whole matrices
            // give one process's sums to the bit.
            let de = common::energy_difference(energy, &energy_serial);
            println!(
                "{ranks} ranks, {share:?}, rank {r}: recorders differ by {e:.1e} of their largest value, energy rows by {de:.1e} of the largest energy; {} of {} blocks",
                st.owned_blocks, st.blocks
            );
            assert!(e <= 1e-12, "{ranks} ranks, rank {r}: {e:e}");
            if share != Share::Whole {
                assert!(de <= 1e-12, "{ranks} ranks, rank {r}: energy {de:e}");
            } else {
                assert_eq!(de, 0.0, "{ranks} ranks, rank {r}: energy");
            }
        }
        let owned: usize = runs.iter().map(|r| r.1.owned_blocks).sum();
        assert_eq!(owned, s1.blocks, "every block owned by exactly one rank");
        assert!(runs.iter().all(|r| r.1.owned_blocks > 0));
    }
}

#[test]
fn block_size_is_checked_in_the_model_file() {
    let dir = common::temp_dir("block-size-keys");
    for (extra, expect) in [
        ("block_size = 0", "`block_size` must be at least 1"),
        (
            "block_size = -3",
            "[analysis]: `block_size` = -3: give a positive integer",
        ),
    ] {
        let p = write_model(&dir, extra);
        let e = match railfem::load_model(&p) {
            Ok(_) => panic!("{extra}: accepted"),
            Err(e) => e.to_string(),
        };
        assert!(e.contains(expect), "{extra}: {e}");
    }
    // With the direct solver the key would be ignored: refused, naming the solver.
    let text =
        model_text("block_size = 200").replace("solver = \"partitioned\"", "solver = \"direct\"");
    let p = dir.join("direct.toml");
    std::fs::write(&p, text).unwrap();
    let e = match railfem::load_model(&p) {
        Ok(_) => panic!("block_size with the direct solver: accepted"),
        Err(e) => e.to_string(),
    };
    assert!(
        e.contains("block_size") && e.contains("only the partitioned solver reads it"),
        "{e}"
    );
}

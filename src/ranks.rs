//! One model across the ranks of an MPI job: the [`Exchange`] of the partitioned solver
//! over MPI (feature `mpi`, rsmpi), and how `railfem train-bridge` and `railfem bench --case
//! train-bridge` find out that they run under a launcher.
//!
//! Under `mpirun -n P` with `P > 1` these commands share the partitioned solver's blocks
//! among the ranks (`railfem_solvers::partition`, *Across ranks*): every rank builds the
//! same model, steps it with the same driver calls and ends each step with the whole state;
//! rank 0 alone writes the outputs (recorders, CSV, figures, `run.json`) and prints. One
//! rank, or no launcher, is the ordinary one-process run. A build without the `mpi` feature
//! under a launcher with several ranks is refused (each rank would run the whole model
//! alone and write the same files).

use crate::framework::FemError;
use crate::solvers::exchange::Exchange;
use std::sync::Arc;

/// The ranks this process shares a model with: `None` without a launcher or with one rank,
/// else the MPI exchange of the job. `command` names the command in the messages.
pub fn launcher_exchange(command: &str) -> Result<Option<Arc<dyn Exchange>>, FemError> {
    let size = crate::sidecar::launcher_size().unwrap_or(1);
    if size <= 1 {
        return Ok(None);
    }
    #[cfg(feature = "mpi")]
    {
        match mpi_exchange::MpiExchange::init() {
            Some(ex) if ex.size() > 1 => Ok(Some(Arc::new(ex))),
            Some(_) => Ok(None),
            None => Err(FemError::input(
                "command line",
                format!("`railfem {command}` under an MPI launcher with {size} ranks: the MPI library did not start; check the MPI installation (scripts/mpi.sh) or run without the launcher"),
            )),
        }
    }
    #[cfg(not(feature = "mpi"))]
    {
        Err(FemError::input(
            "command line",
            format!("`railfem {command}` under an MPI launcher with {size} ranks, but this build has no MPI; build with `cargo build --release -p railfem --features mpi` (scripts/mpi.sh) or run without the launcher"),
        ))
    }
}

/// Whether this process writes the outputs: rank 0 of a launcher's job, or no launcher.
pub fn writes_outputs() -> bool {
    crate::sidecar::launcher_rank().unwrap_or(0) == 0
}

#[cfg(feature = "mpi")]
mod mpi_exchange {
    use crate::solvers::exchange::Exchange;
    use crate::study::mpi::World;
    use mpi::datatype::PartitionMut;
    use mpi::topology::SimpleCommunicator;
    use mpi::traits::*;
    use mpi::Count;
    use std::thread::ThreadId;

    /// The job's world communicator. MPI is initialized with the `Funneled` threading level
    /// (as for `railfem study`): only the thread that initialized it may call it, which
    /// every method checks.
    pub struct MpiExchange {
        job: World,
        thread: ThreadId,
    }

    // SAFETY: the handles are used only from the thread that created them (`check`), as the
    // `Funneled` level requires; the solver may be moved between threads but is driven from
    // the main thread in the commands that use it.
    unsafe impl Send for MpiExchange {}
    unsafe impl Sync for MpiExchange {}

    impl MpiExchange {
        pub fn init() -> Option<MpiExchange> {
            Some(MpiExchange {
                job: World::init()?,
                thread: std::thread::current().id(),
            })
        }

        fn world(&self) -> &SimpleCommunicator {
            self.job.communicator()
        }

        fn check(&self) {
            assert_eq!(
                std::thread::current().id(),
                self.thread,
                "MPI called from a thread other than the one that initialized it"
            );
        }

        /// Every rank's count, and the displacements of the pieces in one buffer.
        fn layout(counts: &[Count]) -> (Vec<Count>, usize) {
            let mut displs = Vec::with_capacity(counts.len());
            let mut at: Count = 0;
            for &c in counts {
                displs.push(at);
                at += c;
            }
            (displs, at as usize)
        }

        fn split(buf: &[f64], counts: &[Count]) -> Vec<Vec<f64>> {
            let mut at = 0usize;
            counts
                .iter()
                .map(|&c| {
                    let p = buf[at..at + c as usize].to_vec();
                    at += c as usize;
                    p
                })
                .collect()
        }
    }

    impl Exchange for MpiExchange {
        fn rank(&self) -> usize {
            self.world().rank() as usize
        }

        fn size(&self) -> usize {
            self.world().size() as usize
        }

        fn gather(&self, local: &[f64]) -> Option<Vec<Vec<f64>>> {
            self.check();
            let root = self.world().process_at_rank(0);
            let n = local.len() as Count;
            if self.world().rank() == 0 {
                let mut counts = vec![0 as Count; self.size()];
                root.gather_into_root(&n, &mut counts[..]);
                let (displs, total) = Self::layout(&counts);
                let mut buf = vec![0.0f64; total];
                {
                    let mut part = PartitionMut::new(&mut buf[..], &counts[..], &displs[..]);
                    root.gather_varcount_into_root(local, &mut part);
                }
                Some(Self::split(&buf, &counts))
            } else {
                root.gather_into(&n);
                root.gather_varcount_into(local);
                None
            }
        }

        fn broadcast(&self, data: &mut Vec<f64>) {
            self.check();
            let root = self.world().process_at_rank(0);
            let mut n = data.len() as u64;
            root.broadcast_into(&mut n);
            data.resize(n as usize, 0.0);
            root.broadcast_into(&mut data[..]);
        }

        fn all_gather(&self, local: &[f64]) -> Vec<Vec<f64>> {
            self.check();
            let n = local.len() as Count;
            let mut counts = vec![0 as Count; self.size()];
            self.world().all_gather_into(&n, &mut counts[..]);
            let (displs, total) = Self::layout(&counts);
            let mut buf = vec![0.0f64; total];
            {
                let mut part = PartitionMut::new(&mut buf[..], &counts[..], &displs[..]);
                self.world().all_gather_varcount_into(local, &mut part);
            }
            Self::split(&buf, &counts)
        }
    }
}

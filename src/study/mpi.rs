//! A study over MPI ranks (`mpirun -n P railfem study PLAN.toml`, feature `mpi`, rsmpi
//! over the system's MPI library): dynamic master/worker distribution.
//!
//! Every rank reads the plan and expands the same cases. Rank 0 is the master: it owns the
//! queue (longest cases first), the checkpoint and the outputs, and computes with its own
//! `--threads` too. Every other rank is a worker that computes one case at a time: it sends
//! a request (tag [`REQUEST`]: `R` at first, then `D<index>\n<row>` for a finished case or
//! `C<index>` for a case cut by a stop) and receives the next case index (tag [`REPLY`],
//! `u64::MAX` = no more work, the worker ends). Only the master's main thread calls MPI
//! (threading level `Funneled`).
//!
//! Faults: a case that returns an error or panics is a failed row like any other (the
//! worker catches the panic). A worker process that dies (killed, aborted) is not seen by
//! MPI's point-to-point calls; Open MPI's and MPICH's launchers then end the whole job
//! (mpirun reports the rank and exits non-zero), so the master does not wait forever. The
//! finished cases are in the checkpoint, and rerunning the same command resumes.

use super::cases::Case;
use super::plan::Plan;
use super::run::{self, Done, Queue};
use mpi::environment::Universe;
use mpi::topology::SimpleCommunicator;
use mpi::traits::*;
use std::path::Path;
use std::sync::mpsc;

/// Tag of a worker's request (with the result of its last case).
pub const REQUEST: i32 = 1;
/// Tag of the master's reply (the next case index, or `u64::MAX`).
pub const REPLY: i32 = 2;
/// The reply that ends a worker.
const STOP: u64 = u64::MAX;

/// This process's place in the MPI job.
pub struct World {
    _universe: Universe,
    world: SimpleCommunicator,
}

impl World {
    /// Initializes MPI (once per process); `None` if the MPI library cannot start.
    pub fn init() -> Option<World> {
        let (universe, _) = mpi::initialize_with_threading(mpi::Threading::Funneled)?;
        let world = universe.world();
        Some(World {
            _universe: universe,
            world,
        })
    }

    /// The job's world communicator.
    pub(crate) fn communicator(&self) -> &SimpleCommunicator {
        &self.world
    }

    /// Ranks in the job.
    pub fn size(&self) -> usize {
        self.world.size() as usize
    }

    /// Whether this is rank 0.
    pub fn is_master(&self) -> bool {
        self.world.rank() == 0
    }

    /// A worker's life: ask, compute, answer, until the master says stop.
    pub fn serve(&self, plan: &Plan, cases: &[Case], out: &Path) {
        let master = self.world.process_at_rank(0);
        crate::progress::set_quiet(true);
        let mut msg = b"R".to_vec();
        loop {
            master.send_with_tag(&msg[..], REQUEST);
            let (next, _) = master.receive_with_tag::<u64>(REPLY);
            if next == STOP {
                return;
            }
            let i = next as usize;
            msg = match cases.get(i).and_then(|c| run::compute(plan, c, out)) {
                Some(row) => format!("D{i}\n{row}").into_bytes(),
                None => format!("C{i}").into_bytes(),
            };
        }
    }

    /// The master's loop: serve the workers' requests from `queue` and record the rows of
    /// the workers and of the local threads (`local`) through `record`, until every worker
    /// has been told to stop and every local thread has ended.
    pub fn master(
        &self,
        queue: &Queue,
        local: &mpsc::Receiver<Done>,
        record: &mut dyn FnMut(usize, Option<String>),
    ) {
        let mut workers = self.size() - 1;
        let mut local_done = false;
        while workers > 0 || !local_done {
            let mut idle = true;
            if !local_done {
                match local.try_recv() {
                    Ok((i, row)) => {
                        record(i, row);
                        idle = false;
                    }
                    Err(mpsc::TryRecvError::Empty) => {}
                    Err(mpsc::TryRecvError::Disconnected) => local_done = true,
                }
            }
            if workers > 0 {
                if let Some(st) = self.world.any_process().immediate_probe_with_tag(REQUEST) {
                    let src = self.world.process_at_rank(st.source_rank());
                    let (msg, _) = src.receive_vec_with_tag::<u8>(REQUEST);
                    let text = String::from_utf8_lossy(&msg);
                    match text.split_at(1.min(text.len())) {
                        ("D", rest) => {
                            if let Some((i, row)) = rest.split_once('\n') {
                                if let Ok(i) = i.parse::<usize>() {
                                    record(i, Some(row.to_string()));
                                }
                            }
                        }
                        ("C", i) => {
                            if let Ok(i) = i.parse::<usize>() {
                                record(i, None);
                            }
                        }
                        _ => {}
                    }
                    let next = queue.next().map_or(STOP, |i| i as u64);
                    src.send_with_tag(&next, REPLY);
                    if next == STOP {
                        workers -= 1;
                    }
                    idle = false;
                }
            }
            if idle {
                std::thread::sleep(std::time::Duration::from_millis(1));
            }
        }
    }
}

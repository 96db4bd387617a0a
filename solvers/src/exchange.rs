//! The message passing the partitioned solver needs to run across processes: a trait of
//! three collective operations over `f64` buffers ([`Exchange`]), an in-process
//! implementation whose "ranks" are threads ([`thread_ranks`], for tests and for checking
//! the protocol without an MPI library), and the payload counters ([`CommStats`]).
//!
//! Every rank calls the same collectives in the same order (the distributed solver is a
//! replicated program: each rank assembles the same model and takes the same decisions,
//! because every value a decision depends on is either computed identically everywhere or
//! received from rank 0). The MPI implementation lives in the root crate behind its `mpi`
//! feature, so this crate needs no MPI library.
//!
//! Byte counts are *payload* volumes, independent of the algorithm the library uses: a
//! gather of pieces `p_r` to the root moves `Σ_{r≠0} |p_r|`, a broadcast of `d` from the
//! root moves `(P − 1)·|d|`, an all-gather moves `(P − 1)·Σ_r |p_r|` (each piece to every
//! other rank); each rank counts what it sends and what it receives (`8` bytes per `f64`),
//! and the job's total is the sum over ranks of either. The lengths exchanged before a
//! variable-size collective (one integer per rank) are not counted.

use std::sync::{Arc, Barrier, Mutex};
use std::time::Instant;

/// Collective operations over the ranks of one job, rank 0 the root.
pub trait Exchange: Send + Sync {
    /// This process's rank, `0..size()`.
    fn rank(&self) -> usize;
    /// Ranks in the job.
    fn size(&self) -> usize;
    /// Every rank's `local` on the root, in rank order (`None` on the other ranks).
    fn gather(&self, local: &[f64]) -> Option<Vec<Vec<f64>>>;
    /// The root's `data` (and its length) on every rank.
    fn broadcast(&self, data: &mut Vec<f64>);
    /// Every rank's `local` on every rank, in rank order.
    fn all_gather(&self, local: &[f64]) -> Vec<Vec<f64>>;
}

/// Whether `flag` holds on any rank of `exchange` (on this process alone without one).
/// Every rank must call it at the same point of the program, and every rank gets the same
/// answer: a stop request (SIGINT/SIGTERM) seen by one rank stops all of them at the same
/// step, where a rank that stopped alone would leave the others waiting in their next
/// collective. One all-gather of one value per rank.
pub fn any_rank(exchange: Option<&dyn Exchange>, flag: bool) -> bool {
    match exchange {
        Some(ex) if ex.size() > 1 => ex
            .all_gather(&[if flag { 1.0 } else { 0.0 }])
            .iter()
            .any(|v| v.first().is_some_and(|&x| x != 0.0)),
        _ => flag,
    }
}

/// Payload counters of one rank (module documentation).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct CommStats {
    /// Collective operations called.
    pub collectives: u64,
    /// Payload bytes this rank sent.
    pub bytes_sent: u64,
    /// Payload bytes this rank received.
    pub bytes_received: u64,
    /// Seconds inside collectives (transfer and waiting for the other ranks).
    pub time: f64,
}

/// An [`Exchange`] with this rank's counters.
pub(crate) struct Comm {
    ex: Arc<dyn Exchange>,
    pub(crate) stats: CommStats,
}

impl Comm {
    pub(crate) fn new(ex: Arc<dyn Exchange>) -> Comm {
        Comm {
            ex,
            stats: CommStats::default(),
        }
    }

    pub(crate) fn rank(&self) -> usize {
        self.ex.rank()
    }

    pub(crate) fn size(&self) -> usize {
        self.ex.size()
    }

    pub(crate) fn is_root(&self) -> bool {
        self.ex.rank() == 0
    }

    /// Bytes of the pieces of the other ranks.
    fn others_bytes(&self, pieces: &[Vec<f64>]) -> u64 {
        let n: usize = pieces
            .iter()
            .enumerate()
            .filter(|&(k, _)| k != self.rank())
            .map(|(_, p)| p.len())
            .sum();
        8 * n as u64
    }

    pub(crate) fn gather(&mut self, local: &[f64]) -> Option<Vec<Vec<f64>>> {
        let t0 = Instant::now();
        let r = self.ex.gather(local);
        self.stats.collectives += 1;
        match &r {
            Some(pieces) => self.stats.bytes_received += self.others_bytes(pieces),
            None => self.stats.bytes_sent += 8 * local.len() as u64,
        }
        self.stats.time += t0.elapsed().as_secs_f64();
        r
    }

    pub(crate) fn broadcast(&mut self, data: &mut Vec<f64>) {
        let t0 = Instant::now();
        self.ex.broadcast(data);
        self.stats.collectives += 1;
        let bytes = 8 * data.len() as u64;
        if self.is_root() {
            self.stats.bytes_sent += bytes * (self.size() as u64 - 1);
        } else {
            self.stats.bytes_received += bytes;
        }
        self.stats.time += t0.elapsed().as_secs_f64();
    }

    pub(crate) fn all_gather(&mut self, local: &[f64]) -> Vec<Vec<f64>> {
        let t0 = Instant::now();
        let r = self.ex.all_gather(local);
        self.stats.collectives += 1;
        self.stats.bytes_received += self.others_bytes(&r);
        self.stats.bytes_sent += 8 * (local.len() * (self.size() - 1)) as u64;
        self.stats.time += t0.elapsed().as_secs_f64();
        r
    }
}

/// The board the thread ranks share: one slot per rank and a barrier.
struct Board {
    slots: Mutex<Vec<Vec<f64>>>,
    barrier: Barrier,
}

/// One thread "rank" of [`thread_ranks`].
struct ThreadRank {
    rank: usize,
    size: usize,
    board: Arc<Board>,
}

impl ThreadRank {
    fn put(&self, slot: usize, data: &[f64]) {
        self.board.slots.lock().expect("board")[slot] = data.to_vec();
    }

    fn take_all(&self) -> Vec<Vec<f64>> {
        self.board.slots.lock().expect("board").clone()
    }
}

impl Exchange for ThreadRank {
    fn rank(&self) -> usize {
        self.rank
    }

    fn size(&self) -> usize {
        self.size
    }

    // Each collective: write, wait for all writes, read, wait for all reads (so the next
    // collective's writes cannot overtake a slow reader).
    fn gather(&self, local: &[f64]) -> Option<Vec<Vec<f64>>> {
        self.put(self.rank, local);
        self.board.barrier.wait();
        let r = (self.rank == 0).then(|| self.take_all());
        self.board.barrier.wait();
        r
    }

    fn broadcast(&self, data: &mut Vec<f64>) {
        if self.rank == 0 {
            self.put(0, data);
        }
        self.board.barrier.wait();
        if self.rank != 0 {
            data.clone_from(&self.board.slots.lock().expect("board")[0]);
        }
        self.board.barrier.wait();
    }

    fn all_gather(&self, local: &[f64]) -> Vec<Vec<f64>> {
        self.put(self.rank, local);
        self.board.barrier.wait();
        let r = self.take_all();
        self.board.barrier.wait();
        r
    }
}

/// `size` in-process ranks, one per thread that will use it (rank `k` is element `k`):
/// every rank must be driven by its own thread, all calling the same collectives in the
/// same order, as MPI processes would.
pub fn thread_ranks(size: usize) -> Vec<Arc<dyn Exchange>> {
    let size = size.max(1);
    let board = Arc::new(Board {
        slots: Mutex::new(vec![Vec::new(); size]),
        barrier: Barrier::new(size),
    });
    (0..size)
        .map(|rank| {
            Arc::new(ThreadRank {
                rank,
                size,
                board: board.clone(),
            }) as Arc<dyn Exchange>
        })
        .collect()
}

/// A solver outcome as a few numbers, so that it can travel with a collective:
/// `[0]` ok, `[1, equation]` a singular pivot, `[2, byte, byte, …]` another failure with
/// its message's UTF-8 bytes.
pub(crate) fn encode_status(r: &Result<(), crate::linear::SolverError>) -> Vec<f64> {
    use crate::linear::SolverError;
    match r {
        Ok(()) => vec![0.0],
        Err(SolverError::Singular { equation }) => vec![1.0, *equation as f64],
        Err(SolverError::Failed(m)) => std::iter::once(2.0)
            .chain(m.bytes().map(f64::from))
            .collect(),
    }
}

/// Reads a status written by [`encode_status`] at the start of `data`; returns it and the
/// number of entries it took (a message takes the rest of `data`).
pub(crate) fn decode_status(data: &[f64]) -> (Result<(), crate::linear::SolverError>, usize) {
    use crate::linear::SolverError;
    match data.first().copied() {
        Some(0.0) => (Ok(()), 1),
        Some(1.0) if data.len() >= 2 => (
            Err(SolverError::Singular {
                equation: data[1] as usize,
            }),
            2,
        ),
        Some(2.0) => {
            let bytes: Vec<u8> = data[1..].iter().map(|&b| b as u8).collect();
            (
                Err(SolverError::Failed(String::from_utf8_lossy(&bytes).into())),
                data.len(),
            )
        }
        _ => (
            Err(SolverError::Failed(
                "a rank sent a malformed status (the ranks disagree on the protocol)".into(),
            )),
            data.len(),
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A stop flag raised on one rank only is seen by every rank, in each of two rounds, and
    /// no rank sees one that nobody raised; one process sees its own flag.
    #[test]
    fn any_rank_agrees_on_a_flag_raised_by_one_rank() {
        let ranks = thread_ranks(3);
        let out: Vec<Vec<bool>> = std::thread::scope(|s| {
            let hs: Vec<_> = ranks
                .iter()
                .map(|ex| {
                    s.spawn(move || {
                        let r = ex.rank();
                        let ex: &dyn Exchange = ex.as_ref();
                        [r == 2, false, r == 0]
                            .iter()
                            .map(|&flag| any_rank(Some(ex), flag))
                            .collect()
                    })
                })
                .collect();
            hs.into_iter().map(|h| h.join().unwrap()).collect()
        });
        for o in &out {
            assert_eq!(o, &vec![true, false, true]);
        }
        assert!(any_rank(None, true) && !any_rank(None, false));
    }

    #[test]
    fn thread_ranks_gather_broadcast_and_all_gather_in_rank_order() {
        let ranks = thread_ranks(3);
        let out: Vec<_> = std::thread::scope(|s| {
            let hs: Vec<_> = ranks
                .iter()
                .map(|ex| {
                    s.spawn(move || {
                        let mut c = Comm::new(ex.clone());
                        let r = c.rank() as f64;
                        let g = c.gather(&vec![r; c.rank() + 1]);
                        let mut b = if c.is_root() { vec![7.0, 8.0] } else { vec![] };
                        c.broadcast(&mut b);
                        let a = c.all_gather(&[r]);
                        (g, b, a, c.stats)
                    })
                })
                .collect();
            hs.into_iter().map(|h| h.join().unwrap()).collect()
        });
        let pieces = vec![vec![0.0], vec![1.0; 2], vec![2.0; 3]];
        assert_eq!(out[0].0.as_ref(), Some(&pieces));
        assert!(out[1].0.is_none() && out[2].0.is_none());
        for (_, b, a, _) in &out {
            assert_eq!(b, &vec![7.0, 8.0]);
            assert_eq!(a, &vec![vec![0.0], vec![1.0], vec![2.0]]);
        }
        // Payload counts: root receives 1·2 + 1·3 (gather) + 2 (all-gather) values and
        // sends 2·2 (broadcast to two ranks) + 2·1 (all-gather); rank 2 sends 3 + 2.
        assert_eq!(out[0].3.bytes_received, 8 * 7);
        assert_eq!(out[0].3.bytes_sent, 8 * 6);
        assert_eq!(out[2].3.bytes_sent, 8 * 5);
        assert_eq!(out[2].3.bytes_received, 8 * (2 + 2));
        // What all ranks sent is what all ranks received.
        let sent: u64 = out.iter().map(|o| o.3.bytes_sent).sum();
        let received: u64 = out.iter().map(|o| o.3.bytes_received).sum();
        assert_eq!(sent, received);
    }

    #[test]
    fn statuses_survive_the_trip() {
        use crate::linear::SolverError;
        for r in [
            Ok(()),
            Err(SolverError::Singular { equation: 123_456 }),
            Err(SolverError::Failed("block 3: not positive definite".into())),
        ] {
            let e = encode_status(&r);
            let (d, used) = decode_status(&e);
            assert_eq!(used, e.len());
            assert_eq!(format!("{d:?}"), format!("{r:?}"));
        }
    }
}

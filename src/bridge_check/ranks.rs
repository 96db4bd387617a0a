//! A check over MPI ranks (`mpirun -n P railfem bridge-check PLAN.toml`, feature `mpi`):
//! the train–speed runs of every pass shared by the ranks, the master/worker way of
//! `railfem study` ([`crate::study::mpi`], whose [`World`] it uses).
//!
//! Every rank reads the plan and builds the same deck, trains and step. Rank 0 is the
//! master: it owns the journal and the outputs and computes with its own `--threads`; its
//! main thread hands runs to the other ranks. A worker asks (tag [`REQUEST`]: `[0]` at
//! first, then `[1, bits of acceleration, its station, its time, deflection, its station]`
//! for the run it finished) and receives the next run (tag [`REPLY`]: `[train, model,
//! bits of the speed]`, or `[u64::MAX]` = stop). Between passes (the refinement around the
//! maxima needs the coarse pass's outcomes) a worker's request waits unanswered until the
//! next pass or the end. The outcomes travel as the bits of their floats, so the
//! `envelope.csv` of any number of ranks is the serial one byte for byte. Only the master's
//! main thread calls MPI (threading level `Funneled`).

use super::envelope::{Check, Next, Outcome, Ranks, Scratch};
use super::interaction::VehicleModel;
use crate::study::mpi::{World, REPLY, REQUEST};
use mpi::traits::*;
use std::cell::RefCell;

/// The reply that ends a worker.
const STOP: u64 = u64::MAX;

/// The models by their number in a message.
const MODELS: [VehicleModel; 3] = [
    VehicleModel::MovingForces,
    VehicleModel::SprungMasses,
    VehicleModel::FullVehicles,
];

/// The check's side of an MPI job.
pub struct Shared<'w> {
    world: &'w World,
    /// The master's view: ranks whose request waits for a run, and ranks that sent none
    /// yet are the others not stopped.
    waiting: RefCell<Vec<i32>>,
    stopped: RefCell<Vec<i32>>,
    /// Runs the other ranks computed for the master.
    received: std::cell::Cell<usize>,
}

impl<'w> Shared<'w> {
    /// The check's side of `world`.
    pub fn new(world: &'w World) -> Shared<'w> {
        Shared {
            world,
            waiting: RefCell::new(Vec::new()),
            stopped: RefCell::new(Vec::new()),
            received: std::cell::Cell::new(0),
        }
    }

    /// Whether this is rank 0.
    pub fn is_master(&self) -> bool {
        self.world.is_master()
    }

    /// Ranks in the job.
    pub fn size(&self) -> usize {
        self.world.size()
    }

    /// Runs the other ranks computed (rank 0's count).
    pub fn received(&self) -> usize {
        self.received.get()
    }

    /// The outcome of `job` from a worker's numbers (`[1, five bits]`).
    fn outcome(check: &Check, job: (usize, VehicleModel, f64), msg: &[u64]) -> Option<Outcome> {
        let f: Vec<f64> = msg.get(1..6)?.iter().map(|&b| f64::from_bits(b)).collect();
        let (i, model, speed) = job;
        Some(Outcome {
            train: i,
            model,
            speed,
            acceleration: f[0],
            acc_station: f[1],
            acc_time: f[2],
            deflection: f[3],
            defl_station: f[4],
            static_deflection: *check.statics.get(i)?,
        })
    }
}

impl Ranks for Shared<'_> {
    fn serve(
        &self,
        check: &Check,
        jobs: &[(usize, VehicleModel, f64)],
        take: &dyn Fn() -> Next,
        put: &dyn Fn(usize, Outcome),
    ) {
        let comm = self.world.communicator();
        let mut busy: Vec<(i32, usize)> = Vec::new();
        let mut done = false;
        loop {
            // Hand runs to the ranks that wait for one.
            while !done {
                let Some(r) = self.waiting.borrow_mut().pop() else {
                    break;
                };
                loop {
                    match take() {
                        Next::Kept(k, o) => put(k, o),
                        Next::Run(k) => {
                            let (i, m, v) = jobs[k];
                            let model = MODELS.iter().position(|&x| x == m).unwrap_or(0);
                            let msg = [i as u64, model as u64, v.to_bits()];
                            comm.process_at_rank(r).send_with_tag(&msg[..], REPLY);
                            busy.push((r, k));
                            break;
                        }
                        Next::Done => {
                            done = true;
                            self.waiting.borrow_mut().push(r);
                            break;
                        }
                    }
                }
            }
            if done && busy.is_empty() {
                return;
            }
            let Some(st) = comm.any_process().immediate_probe_with_tag(REQUEST) else {
                // The local threads compute meanwhile; look again soon.
                std::thread::sleep(std::time::Duration::from_millis(1));
                continue;
            };
            let src = st.source_rank();
            let (msg, _) = comm
                .process_at_rank(src)
                .receive_vec_with_tag::<u64>(REQUEST);
            if let Some(p) = busy.iter().position(|&(r, _)| r == src) {
                let (_, k) = busy.swap_remove(p);
                if let Some(o) = Self::outcome(check, jobs[k], &msg) {
                    self.received.set(self.received.get() + 1);
                    put(k, o);
                }
            }
            self.waiting.borrow_mut().push(src);
        }
    }

    fn work(&self, check: &Check) {
        let comm = self.world.communicator();
        let master = comm.process_at_rank(0);
        crate::progress::set_quiet(true);
        let mut s = Scratch::default();
        let mut msg = vec![0u64];
        loop {
            master.send_with_tag(&msg[..], REQUEST);
            let (job, _) = master.receive_vec_with_tag::<u64>(REPLY);
            let (Some(&i), Some(&m), Some(&v)) = (job.first(), job.get(1), job.get(2)) else {
                return;
            };
            if i == STOP || i as usize >= check.trains.len() {
                return;
            }
            let model = MODELS.get(m as usize).copied().unwrap_or(MODELS[0]);
            let o = check.run_model(i as usize, model, f64::from_bits(v), &mut s);
            msg = [
                1,
                o.acceleration.to_bits(),
                o.acc_station.to_bits(),
                o.acc_time.to_bits(),
                o.deflection.to_bits(),
                o.defl_station.to_bits(),
            ]
            .to_vec();
        }
    }

    fn finish(&self) {
        let comm = self.world.communicator();
        let stop = [STOP];
        let waiting: Vec<i32> = self.waiting.borrow_mut().drain(..).collect();
        for r in waiting {
            comm.process_at_rank(r).send_with_tag(&stop[..], REPLY);
            self.stopped.borrow_mut().push(r);
        }
        // Ranks not heard from yet (a check that ended before its first pass): their
        // first request, then stop.
        for r in 1..self.world.size() as i32 {
            if !self.stopped.borrow().contains(&r) {
                let _ = comm.process_at_rank(r).receive_vec_with_tag::<u64>(REQUEST);
                comm.process_at_rank(r).send_with_tag(&stop[..], REPLY);
                self.stopped.borrow_mut().push(r);
            }
        }
    }
}

//! The speed envelope: every train over the speed range on threads, a coarse pass and
//! then refinement around each local maximum of the peak acceleration, and the result of
//! one train at one speed ([`Outcome`]).
//!
//! One run crosses the deck from rest, the first axle entering at t = 0, and goes on for
//! the plan's tail of free vibration after the last axle has left. The deck acceleration
//! of every station is filtered to the cut-off ([`super::filter`]) before its peak is
//! taken; the deflection is not filtered. The dynamic factor is the largest dynamic
//! deflection over the largest static deflection of the same train (EN 1991-2 §6.4.6.5:
//! `1 + φ'_dyn`).
//!
//! Refinement: around each coarse local maximum that reaches a quarter of the train's
//! highest, the speeds half a step either side of the best so far are run, then a quarter
//! step, … (`refine` halvings), so that a peak is found to within `step/2^refine`.

use super::fe::{Deck, Stepper, Work};
use super::filter::LowPass;
use super::full_vehicles::{Vehicle, VehicleWork};
use super::interaction::{AxleSuspension, AxleWork, VehicleModel};
pub use super::outcome::Outcome;
use super::resume::Journal;
use super::trains::Train;
use crate::framework::FemError;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;

/// km/h per m/s.
pub const KMH: f64 = 3.6;

/// Everything a run needs, shared read-only by the threads.
pub struct Check<'a> {
    /// The deck.
    pub deck: &'a Deck,
    /// Its integrator.
    pub stepper: &'a Stepper,
    /// The trains.
    pub trains: &'a [Train],
    /// Their largest static deflections (m).
    pub statics: &'a [f64],
    /// Cut-off frequency (Hz).
    pub cutoff: f64,
    /// Free vibration after the last axle has left (s).
    pub tail: f64,
    /// Per train, its axles' suspensions (needed for [`VehicleModel::SprungMasses`]
    /// only; may be empty otherwise).
    pub vehicles: &'a [Vec<AxleSuspension>],
    /// Per train, its full vehicles (needed for [`VehicleModel::FullVehicles`] only; may be
    /// empty otherwise).
    pub full: &'a [Vec<Vehicle>],
    /// The journal that keeps finished runs and gives them back on resume
    /// ([`super::resume`]); `None`: nothing is kept.
    pub journal: Option<&'a Journal>,
}

/// What [`Check::next_job`] hands out.
#[derive(Debug, Clone, Copy)]
pub enum Next {
    /// Compute job `k`.
    Run(usize),
    /// Job `k` is in the journal already: its outcome.
    Kept(usize, Outcome),
    /// Nothing more in this pass.
    Done,
}

/// The other ranks of an MPI job that share a check's runs (`bridge_check::ranks`, with the `mpi` feature); rank 0
/// serves them, the others work.
pub trait Ranks {
    /// Rank 0, during a pass: hands the runs `take` gives to the other ranks and gives
    /// their outcomes to `put` (job index, outcome) until `take` is done and every rank's
    /// run of this pass is back. Called on the main thread only.
    fn serve(
        &self,
        check: &Check,
        jobs: &[(usize, VehicleModel, f64)],
        take: &dyn Fn() -> Next,
        put: &dyn Fn(usize, Outcome),
    );
    /// Another rank: computes the runs rank 0 sends, until it says stop.
    fn work(&self, check: &Check);
    /// Rank 0, at the end (or on an error): tells every other rank to stop.
    fn finish(&self);
}

/// Per-thread buffers.
#[derive(Default)]
pub struct Scratch {
    work: Work,
    axles: AxleWork,
    vehicles: VehicleWork,
    filter: LowPass,
}

impl Check<'_> {
    /// Steps of a run at `v` (m/s).
    pub fn steps(&self, train: &Train, v: f64) -> usize {
        let t = (self.deck.length() + train.length()) / v + self.tail;
        (t / self.stepper.dt).ceil() as usize
    }

    /// Runs train `i` at `speed` (km/h) as moving forces.
    pub fn run(&self, i: usize, speed: f64, s: &mut Scratch) -> Outcome {
        self.run_model(i, VehicleModel::MovingForces, speed, s)
    }

    /// Runs train `i` at `speed` (km/h) with the axles modelled as `model`. A train
    /// without suspensions in [`Check::vehicles`] (full vehicles in [`Check::full`]) runs
    /// as moving forces.
    pub fn run_model(&self, i: usize, model: VehicleModel, speed: f64, s: &mut Scratch) -> Outcome {
        let train = &self.trains[i];
        let v = speed / KMH;
        let steps = self.steps(train, v);
        let dt = self.stepper.dt;
        match (model, self.vehicles.get(i)) {
            (VehicleModel::SprungMasses, Some(axles)) => super::interaction::run(
                self.stepper,
                self.deck,
                train,
                axles,
                v,
                steps,
                (&mut s.work, &mut s.axles),
            ),
            (VehicleModel::FullVehicles, _) if self.full.get(i).is_some_and(|f| !f.is_empty()) => {
                super::full_vehicles::run(
                    self.stepper,
                    self.deck,
                    &self.full[i],
                    v,
                    steps,
                    (&mut s.work, &mut s.vehicles),
                )
            }
            _ => self.stepper.run(self.deck, train, v, steps, &mut s.work),
        }
        let mut o = Outcome {
            train: i,
            model,
            speed,
            acceleration: 0.0,
            acc_station: 0.0,
            acc_time: 0.0,
            deflection: 0.0,
            defl_station: 0.0,
            static_deflection: self.statics[i],
        };
        let st = &self.deck.stations;
        for (j, y) in s.work.deflection.iter().enumerate() {
            let m = y.iter().fold(0.0f64, |m, x| m.max(x.abs()));
            if m > o.deflection {
                o.deflection = m;
                o.defl_station = st[j].station;
            }
        }
        let acc = &mut s.work.acceleration;
        let mut j = 0;
        while j < acc.len() {
            let (x, rest) = acc[j..].split_at_mut(1);
            let y: &mut [f64] = rest.first_mut().map_or(&mut [], |y| y.as_mut_slice());
            s.filter.apply_pair(&mut x[0], y, dt, self.cutoff);
            for (k, h) in [(j, &x[0][..]), (j + 1, &*y)] {
                for (n, a) in h.iter().enumerate() {
                    if a.abs() > o.acceleration {
                        o.acceleration = a.abs();
                        o.acc_station = st[k].station;
                        o.acc_time = n as f64 * dt;
                    }
                }
            }
            j += 2;
        }
        o
    }

    /// Runs `jobs` (train, model, km/h) on `threads` threads; the outcomes in the order of
    /// `jobs`. Stops handing out jobs when an interrupt is requested.
    pub fn run_all(
        &self,
        jobs: &[(usize, VehicleModel, f64)],
        threads: usize,
    ) -> Result<Vec<Outcome>, FemError> {
        self.run_shared(jobs, threads, None)
    }

    /// The next job of a pass for whoever asks (a local thread or another rank): the
    /// journal's outcome when it holds the run, [`Next::Done`] once every job is handed
    /// out, an interrupt is requested or `--stop-after`'s budget is spent.
    pub fn next_job(&self, next: &AtomicUsize, jobs: &[(usize, VehicleModel, f64)]) -> Next {
        if crate::framework::interrupt::requested() {
            return Next::Done;
        }
        let k = next.fetch_add(1, Ordering::Relaxed);
        let Some(&(i, m, v)) = jobs.get(k) else {
            return Next::Done;
        };
        match self.journal.map(|j| (j.get(i, m, v), j)) {
            Some((Some(o), _)) => Next::Kept(k, o),
            Some((None, j)) if !j.may_run() => Next::Done,
            _ => Next::Run(k),
        }
    }

    /// [`Check::run_all`], the jobs shared with the other ranks of an MPI job when `ranks`
    /// is given (this process being rank 0: its main thread serves them while its
    /// `threads` compute).
    pub fn run_shared(
        &self,
        jobs: &[(usize, VehicleModel, f64)],
        threads: usize,
        ranks: Option<&dyn Ranks>,
    ) -> Result<Vec<Outcome>, FemError> {
        let next = AtomicUsize::new(0);
        let out: Mutex<Vec<Option<Outcome>>> = Mutex::new(vec![None; jobs.len()]);
        let put = |k: usize, o: Outcome| {
            if let Ok(mut g) = out.lock() {
                g[k] = Some(o);
            }
        };
        std::thread::scope(|sc| {
            for _ in 0..threads.max(1) {
                sc.spawn(|| {
                    let mut s = Scratch::default();
                    loop {
                        match self.next_job(&next, jobs) {
                            Next::Done => return,
                            Next::Kept(k, o) => put(k, o),
                            Next::Run(k) => {
                                let (i, m, v) = jobs[k];
                                let o = self.run_model(i, m, v, &mut s);
                                if let Some(j) = self.journal {
                                    j.record(&o);
                                }
                                put(k, o);
                            }
                        }
                    }
                });
            }
            if let Some(r) = ranks {
                r.serve(self, jobs, &|| self.next_job(&next, jobs), &|k, o| {
                    if let Some(j) = self.journal {
                        j.record(&o);
                    }
                    put(k, o)
                });
            }
        });
        if let Some(e) = self.journal.and_then(Journal::take_error) {
            return Err(e);
        }
        let got = out.into_inner().unwrap_or_default();
        let done = got.iter().filter(|o| o.is_some()).count();
        if done < jobs.len() {
            return Err(FemError::InterruptedAfter {
                after: match self.journal {
                    Some(j) => format!(
                        "{done} of {} train-speed runs of this pass; {} runs kept in {} (run the same command again to go on; no envelope written yet)",
                        jobs.len(),
                        j.len_now(),
                        super::resume::FILE
                    ),
                    None => format!(
                        "{done} of {} train-speed runs (no envelope written)",
                        jobs.len()
                    ),
                },
            });
        }
        Ok(got.into_iter().flatten().collect())
    }

    /// The envelope of moving forces: coarse pass over `speeds` (km/h) for every train,
    /// then `refine` halvings of `step` around each local maximum. Outcomes sorted by train
    /// and speed.
    pub fn envelope(
        &self,
        speeds: &[f64],
        step: f64,
        refine: usize,
        threads: usize,
    ) -> Result<Vec<Outcome>, FemError> {
        let mf = [VehicleModel::MovingForces];
        self.envelope_shared(&mf, speeds, step, refine, threads, None)
    }

    /// The envelope of every train with every one of `models`, each (train, model) curve
    /// refined on its own, every pass's runs shared with the other ranks of an MPI job when
    /// `ranks` is given ([`Check::run_shared`]). Outcomes sorted by train, model and speed.
    pub fn envelope_shared(
        &self,
        models: &[VehicleModel],
        speeds: &[f64],
        step: f64,
        refine: usize,
        threads: usize,
        ranks: Option<&dyn Ranks>,
    ) -> Result<Vec<Outcome>, FemError> {
        let (lo, hi) = (speeds[0], *speeds.last().unwrap_or(&speeds[0]));
        let curves: Vec<(usize, VehicleModel)> = (0..self.trains.len())
            .flat_map(|i| models.iter().map(move |&m| (i, m)))
            .collect();
        let jobs: Vec<(usize, VehicleModel, f64)> = curves
            .iter()
            .flat_map(|&(i, m)| speeds.iter().map(move |&v| (i, m, v)))
            .collect();
        let mut all = self.run_shared(&jobs, threads, ranks)?;
        // The maxima to refine: (train, model, best speed, best value).
        let mut peaks: Vec<(usize, VehicleModel, f64, f64)> = Vec::new();
        for &(i, m) in &curves {
            let row: Vec<&Outcome> = all
                .iter()
                .filter(|o| o.train == i && o.model == m)
                .collect();
            let top = row.iter().fold(0.0f64, |t, o| t.max(o.acceleration));
            for k in 0..row.len() {
                let a = row[k].acceleration;
                let left = k == 0 || row[k - 1].acceleration <= a;
                let right = k + 1 == row.len() || row[k + 1].acceleration < a;
                if left && right && a >= 0.25 * top {
                    peaks.push((i, m, row[k].speed, a));
                }
            }
        }
        let mut h = step;
        for _ in 0..refine {
            h /= 2.0;
            let tagged: Vec<(usize, (usize, VehicleModel, f64))> = peaks
                .iter()
                .enumerate()
                .flat_map(|(k, &(i, m, v, _))| [(k, (i, m, v - h)), (k, (i, m, v + h))])
                .filter(|&(_, (_, _, v))| v >= lo && v <= hi)
                .collect();
            let jobs: Vec<(usize, VehicleModel, f64)> = tagged.iter().map(|t| t.1).collect();
            let got = self.run_shared(&jobs, threads, ranks)?;
            for ((k, _), o) in tagged.iter().zip(&got) {
                if o.acceleration > peaks[*k].3 {
                    peaks[*k] = (o.train, o.model, o.speed, o.acceleration);
                }
            }
            all.extend(got);
        }
        all.sort_by(|a, b| {
            a.train
                .cmp(&b.train)
                .then(a.model.cmp(&b.model))
                .then(a.speed.total_cmp(&b.speed))
        });
        all.dedup_by(|a, b| a.train == b.train && a.model == b.model && a.speed == b.speed);
        Ok(all)
    }
}

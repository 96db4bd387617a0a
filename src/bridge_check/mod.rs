//! `railfem bridge-check PLAN.toml` and `railfem trains`: the dynamic check of a railway
//! bridge for high-speed traffic as EN 1991-2 §6.4.6 sets it out — the universal trains
//! HSLM-A/B and the user's trains over a speed range, the peak deck acceleration after the
//! frequency cut-off against the limit of the track, the deflection and the dynamic
//! factor, with figures, a report and a verdict.
//!
//! One job per module: [`trains`] (HSLM and user trains), [`bridge`] (the description and
//! the standard's rules for damping, limits and frequencies), [`modal`] (the modal
//! reference solution), [`filter`] (the frequency cut-off), [`simplified`] (the DER and LIR methods of ERRI D214), [`fe`] (the finite element
//! deck and its step), [`interaction`] (moving sprung masses coupled to that step), [`half_car`] (the
//! full vehicle: the 10-DOF half car), [`full_vehicles`] (full vehicles coupled to the
//! deck's step),
//! [`vehicle_train`] (trains of vehicle files), [`envelope`] (the speed sweep on threads),
//! [`resume`] (the journal of finished runs), `ranks` (the runs shared by MPI ranks, feature
//! `mpi`), [`plan`] (the plan file) and [`report`] (CSV,
//! figures, Markdown). User documentation: `docs/bridge-check.md`.

pub mod bridge;
pub mod envelope;
pub mod fe;
pub mod filter;
pub mod full_vehicles;
pub mod half_car;
pub mod interaction;
pub mod modal;
pub mod outcome;
pub mod plan;
#[cfg(feature = "mpi")]
pub mod ranks;
pub mod report;
pub mod resume;
pub mod simplified;
pub mod trains;
pub mod vehicle_train;

use crate::framework::FemError;
use std::path::Path;
use std::time::Instant;

/// Default output directory of `railfem bridge-check`.
pub const DEFAULT_OUT: &str = "out/bridge_check";

/// Everything the check found, for the report and the tests.
#[derive(Debug, Clone)]
pub struct Results {
    /// The plan.
    pub plan: plan::Plan,
    /// The trains run.
    pub trains: Vec<trains::Train>,
    /// Vertical bending frequencies of the deck (Hz).
    pub frequencies: Vec<f64>,
    /// Determinant length (m) used for damping and Fig. 6.10.
    pub length: f64,
    /// Damping ratio and where it came from.
    pub damping: (f64, String),
    /// Rayleigh `(α, β)`.
    pub rayleigh: (f64, f64),
    /// Cut-off frequency (Hz).
    pub cutoff: f64,
    /// Time step (s).
    pub dt: f64,
    /// Equations of the FE deck.
    pub equations: usize,
    /// Every train-speed outcome, by train and speed.
    pub outcomes: Vec<envelope::Outcome>,
    /// Wall time of the envelope (s) and of the whole check (s).
    pub seconds: (f64, f64),
    /// Threads used.
    pub threads: usize,
    /// The modal reference at the governing case (simply supported single described span):
    /// `(FE peak acceleration, modal peak acceleration, FE peak deflection, modal peak
    /// deflection)`.
    pub reference: Option<(f64, f64, f64, f64)>,
    /// When an interaction model ran: the governing train and speed under every model the
    /// train can run (moving forces, sprung masses, full vehicles), in that order.
    pub models_compared: Vec<envelope::Outcome>,
    /// On a described single simply supported span: per train, the peak midspan
    /// acceleration of ERRI D214's DER and LIR methods over the plan's speed range (m/s²),
    /// and the speeds (km/h) of those peaks.
    pub simplified: Vec<SimplifiedRow>,
}

/// A train's DER and LIR estimates over the speed range ([`simplified`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SimplifiedRow {
    /// Index of the train.
    pub train: usize,
    /// DER's peak (m/s²) and its speed (km/h).
    pub der: (f64, f64),
    /// LIR's peak (m/s²) and its speed (km/h).
    pub lir: (f64, f64),
}

impl Results {
    /// The outcome with the highest peak acceleration.
    pub fn governing(&self) -> Option<&envelope::Outcome> {
        self.outcomes
            .iter()
            .max_by(|a, b| a.acceleration.total_cmp(&b.acceleration))
    }

    /// The acceleration limit of the track (m/s²).
    pub fn limit(&self) -> f64 {
        self.plan.bridge.track.acceleration_limit()
    }
}

/// A plan's trains with, per train, its axles' suspensions and its full vehicles.
pub type PlanTrains = (
    Vec<trains::Train>,
    Vec<Vec<interaction::AxleSuspension>>,
    Vec<Vec<full_vehicles::Vehicle>>,
);

/// The trains of a plan: the named built-ins (default HSLM-A1…A10, and HSLM-B on a simply
/// supported span under 7 m), then the user's; with, when the plan runs an interaction
/// model, every train's axle suspensions (a vehicle file's own, else the plan's
/// `[sprung_masses]`), and otherwise none; and, when it runs full vehicles, every train's
/// vehicles (trains of vehicle files only: another train is refused).
pub fn plan_trains(p: &plan::Plan, file: &str) -> Result<PlanTrains, FemError> {
    let span = p.bridge.spans.iter().fold(0.0f64, |m, &s| m.max(s));
    let names: Vec<String> = match &p.trains {
        Some(n) => n.clone(),
        None => {
            let mut n: Vec<String> = (1..=10).map(|i| format!("HSLM-A{i}")).collect();
            if p.bridge.support == bridge::Support::SimplySupported && span < 7.0 {
                n.push("HSLM-B".into());
            }
            n
        }
    };
    let mut out = Vec::new();
    for name in &names {
        let t = trains::builtin(name, Some(span)).ok_or_else(|| {
            FemError::input(
                format!("{file}: trains"),
                format!("`{name}` is not a built-in train; use HSLM-A1 … HSLM-A10 or HSLM-B (spans 1-7 m), or a [[train]] with a file"),
            )
        })?;
        out.push(t);
    }
    let mut own = vec![None; out.len()];
    let wants_full = p
        .analysis
        .model
        .list()
        .contains(&interaction::VehicleModel::FullVehicles);
    let mut full = vec![Vec::new(); out.len()];
    for u in &p.train {
        match (&u.file, &u.vehicle) {
            (Some(f), _) => {
                out.push(trains::read_user_train(f, &u.name)?);
                own.push(None);
                full.push(Vec::new());
            }
            (None, Some(v)) => {
                let wr = p.sprung_masses.wheel_radius;
                let count = u.count.unwrap_or(1);
                let (t, s) = vehicle_train::read(v, &u.name, count, wr)?;
                out.push(t);
                own.push(Some(s));
                full.push(if wants_full {
                    vehicle_train::full(v, count, wr)?
                } else {
                    Vec::new()
                });
            }
            (None, None) => {}
        }
    }
    if wants_full {
        if let Some(t) = full.iter().position(Vec::is_empty) {
            return Err(FemError::input(
                format!("{file}: analysis.model"),
                format!("full vehicles need trains of vehicle files, and `{}` is not one; give `trains = []` and [[train]] tables with `vehicle = \"FILE.toml\"`, or another model", out[t].name),
            ));
        }
    }
    if out.is_empty() {
        return Err(FemError::input(
            format!("{file}: trains"),
            "no train to run; name built-in trains or add a [[train]]",
        ));
    }
    let mut suspensions = Vec::new();
    if p.analysis.model != interaction::Models::MovingForces {
        for (t, o) in out.iter().zip(own) {
            suspensions.push(match o {
                Some(s) => s,
                None => p.sprung_masses.for_train(t, file)?,
            });
        }
    }
    Ok((out, suspensions, full))
}

/// The FE deck of a plan: described, or the model file's deck path.
pub fn plan_deck(p: &plan::Plan, file: &str) -> Result<fe::Deck, FemError> {
    let b = &p.bridge;
    let modes = p.analysis.modes;
    match &b.model {
        Some(m) => {
            let model = crate::load_model(m)?;
            fe::Deck::new(model, &b.deck, modes, &m.display().to_string())
        }
        None => {
            if b.support == bridge::Support::SimplySupported && b.spans.len() > 1 {
                return Err(FemError::input(
                    format!("{file}: bridge.spans"),
                    "simply supported spans are independent: check one span per plan, or set support = \"continuous\"",
                ));
            }
            let per = b
                .elements_per_span
                .unwrap_or(bridge::DEFAULT_ELEMENTS_PER_SPAN);
            let model =
                fe::described_model(&b.spans, b.ei.unwrap_or(0.0), b.mass.unwrap_or(0.0), per)
                    .build()?;
            let ids: Vec<u64> = (1..=(per * b.spans.len()) as u64).collect();
            fe::Deck::new(model, &ids, modes, file)
        }
    }
}

/// How a check runs: threads, and the journal's options ([`resume`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RunOptions {
    /// Computing threads.
    pub threads: usize,
    /// Compute at most this many runs, then stop (the journal keeps them).
    pub stop_after: Option<usize>,
    /// Discard the journal instead of resuming from it.
    pub restart: bool,
}

/// Runs the check of `plan_path` on `threads` threads and writes its outputs into `out`
/// (resuming from a journal there).
pub fn check(plan_path: &Path, out: &Path, threads: usize) -> Result<Results, FemError> {
    check_with(
        plan_path,
        out,
        RunOptions {
            threads,
            stop_after: None,
            restart: false,
        },
    )
}

/// [`check`] with the journal's options.
pub fn check_with(plan_path: &Path, out: &Path, o: RunOptions) -> Result<Results, FemError> {
    check_as(plan_path, out, o, None)?.ok_or_else(|| {
        FemError::input(
            "bridge-check",
            "a check on one process computes its outputs",
        )
    })
}

/// [`check_with`] as one rank of an MPI job when `ranks` is given: rank 0 shares the runs
/// with the others and writes the outputs (`Some`); another rank computes the runs it is
/// sent and returns `None` (no journal, no output).
pub fn check_as(
    plan_path: &Path,
    out: &Path,
    o: RunOptions,
    ranks: Option<(&dyn envelope::Ranks, bool)>,
) -> Result<Option<Results>, FemError> {
    let threads = o.threads;
    let t0 = Instant::now();
    let file = plan_path.display().to_string();
    let p = plan::Plan::read(plan_path)?;
    let (trains, vehicles, full) = plan_trains(&p, &file)?;
    let deck = plan_deck(&p, &file)?;
    let f = &deck.frequencies;
    let n0 = *f.first().ok_or_else(|| {
        FemError::input(
            format!("{file}: bridge"),
            "the deck has no vertical bending mode among the modes computed; raise analysis.modes",
        )
    })?;
    let cutoff = filter::cutoff(n0, f.get(2).copied());
    let length = bridge::determinant_length(&p.bridge.spans, p.bridge.support);
    let damping = bridge::damping(&p.bridge, length);
    let two_pi = 2.0 * std::f64::consts::PI;
    let rayleigh = fe::rayleigh(damping.0, two_pi * n0, two_pi * cutoff);
    let dt = 1.0 / (p.analysis.steps_per_period * cutoff);
    let stepper = fe::Stepper::new(&deck, rayleigh.0, rayleigh.1, dt)?;
    let mut statics = Vec::new();
    for t in &trains {
        statics.push(fe::Stepper::static_peak(&deck, t, p.analysis.static_step)?.0);
    }
    let text = std::fs::read_to_string(plan_path).unwrap_or_default();
    let words = format!(
        "{trains:?} {vehicles:?} {full:?} {:?} {dt:e} {cutoff:e} {rayleigh:?} {}",
        deck.frequencies, deck.n
    );
    let fp = resume::fingerprint(&[&text, &words]);
    if let Some((r, false)) = ranks {
        let c = envelope::Check {
            deck: &deck,
            stepper: &stepper,
            trains: &trains,
            statics: &statics,
            cutoff,
            tail: p.analysis.tail_periods / n0,
            vehicles: &vehicles,
            full: &full,
            journal: None,
        };
        r.work(&c);
        return Ok(None);
    }
    // From here on the other ranks wait for rank 0's runs: whatever the end, it tells them
    // to stop.
    let rest = || -> Result<Results, FemError> {
        let journal = resume::Journal::open(out, fp, &statics, o.restart, o.stop_after)?;
        let c = envelope::Check {
            deck: &deck,
            stepper: &stepper,
            trains: &trains,
            statics: &statics,
            cutoff,
            tail: p.analysis.tail_periods / n0,
            vehicles: &vehicles,
            full: &full,
            journal: Some(&journal),
        };
        let te = Instant::now();
        let models = p.analysis.model.list();
        let outcomes = c.envelope_shared(
            &models,
            &p.coarse_speeds(),
            p.speeds.step,
            p.speeds.refine,
            threads,
            ranks.map(|r| r.0),
        )?;
        let envelope_s = te.elapsed().as_secs_f64();
        let mut r = Results {
            plan: p,
            trains: trains.clone(),
            frequencies: deck.frequencies.clone(),
            length,
            damping,
            rayleigh,
            cutoff,
            dt,
            equations: deck.n,
            outcomes,
            seconds: (envelope_s, 0.0),
            threads,
            reference: None,
            models_compared: Vec::new(),
            simplified: Vec::new(),
        };
        r.reference = governing_reference(&r, &deck, &c);
        r.models_compared = compare_models(&r, &c);
        r.simplified = simplified_rows(&r);
        r.seconds.1 = t0.elapsed().as_secs_f64();
        report::write(&r, out)?;
        Ok(r)
    };
    let got = rest();
    if let Some((r, true)) = ranks {
        r.finish();
    }
    got.map(Some)
}

/// On a described single simply supported span: the governing case again, beside the
/// modal reference with 30 modes filtered the same way.
fn governing_reference(
    r: &Results,
    deck: &fe::Deck,
    c: &envelope::Check,
) -> Option<(f64, f64, f64, f64)> {
    let b = &r.plan.bridge;
    if b.model.is_some() || b.spans.len() != 1 || b.support != bridge::Support::SimplySupported {
        return None;
    }
    let mut g = *r.governing()?;
    if g.model != interaction::VehicleModel::MovingForces {
        g = c.run(g.train, g.speed, &mut envelope::Scratch::default());
    }
    let span = modal::Span {
        length: b.spans[0],
        ei: b.ei?,
        mass: b.mass?,
    };
    let train = &r.trains[g.train];
    let v = g.speed / envelope::KMH;
    let steps = c.steps(train, v);
    let stations: Vec<f64> = deck.stations.iter().map(|s| s.station).collect();
    let (al, be) = r.rayleigh;
    let h = modal::response(&span, train, v, r.dt, steps + 1, &stations, 30, &|w| {
        al / (2.0 * w) + be * w / 2.0
    });
    let mut lp = filter::LowPass::default();
    let mut acc = 0.0f64;
    let mut defl = 0.0f64;
    for (a, y) in h.acceleration.iter().zip(&h.deflection) {
        let mut a = a.clone();
        lp.apply(&mut a, r.dt, r.cutoff);
        acc = a.iter().fold(acc, |m, x| m.max(x.abs()));
        defl = y.iter().fold(defl, |m, x| m.max(x.abs()));
    }
    Some((g.acceleration, acc, g.deflection, defl))
}

/// When an interaction model ran: the governing train and speed under every model the
/// train can run (a run repeated when the envelope does not hold that speed and model).
fn compare_models(r: &Results, c: &envelope::Check) -> Vec<envelope::Outcome> {
    use interaction::VehicleModel::{FullVehicles, MovingForces, SprungMasses};
    if r.plan.analysis.model == interaction::Models::MovingForces {
        return Vec::new();
    }
    let Some(g) = r.governing().copied() else {
        return Vec::new();
    };
    let mut s = envelope::Scratch::default();
    let has_full = c.full.get(g.train).is_some_and(|f| !f.is_empty());
    [MovingForces, SprungMasses, FullVehicles]
        .into_iter()
        .filter(|&m| m != FullVehicles || has_full)
        .map(|m| {
            r.outcomes
                .iter()
                .find(|o| o.train == g.train && o.model == m && o.speed == g.speed)
                .copied()
                .unwrap_or_else(|| c.run_model(g.train, m, g.speed, &mut s))
        })
        .collect()
}

/// On a described single simply supported span: DER and LIR of every train over the plan's
/// speed range every 0.5 km/h (closed forms, ERRI D214; [`simplified`]), with the check's
/// ζ and first frequency.
fn simplified_rows(r: &Results) -> Vec<SimplifiedRow> {
    let b = &r.plan.bridge;
    let (Some(mass), None, [length]) = (b.mass, &b.model, b.spans.as_slice()) else {
        return Vec::new();
    };
    if b.support != bridge::Support::SimplySupported {
        return Vec::new();
    }
    let span = simplified::Span {
        length: *length,
        n0: r.frequencies[0],
        mass,
        zeta: r.damping.0,
    };
    let (lo, hi) = (r.plan.speeds.min, 1.2 * r.plan.speeds.max_line_speed);
    let n = ((hi - lo) / 0.5).ceil() as usize;
    r.trains
        .iter()
        .enumerate()
        .map(|(i, t)| {
            let mut row = SimplifiedRow {
                train: i,
                der: (0.0, lo),
                lir: (0.0, lo),
            };
            for k in 0..=n {
                let kmh = (lo + 0.5 * k as f64).min(hi);
                let v = kmh / envelope::KMH;
                let der = simplified::estimate(simplified::Method::Der, &span, t, v);
                let lir = simplified::estimate(simplified::Method::Lir, &span, t, v);
                if der.acceleration > row.der.0 {
                    row.der = (der.acceleration, kmh);
                }
                if lir.acceleration > row.lir.0 {
                    row.lir = (lir.acceleration, kmh);
                }
            }
            row
        })
        .collect()
}

/// `railfem bridge-check`: runs the check of the plan at `plan` into `out` and prints the
/// governing case. Built with the `mpi` feature and started by `mpirun -n N` (N > 1), rank 0
/// hands the runs out to the other ranks and writes every output (`bridge_check::ranks`).
pub fn command(plan: &Path, out: &Path, opts: RunOptions) -> Result<i32, FemError> {
    #[cfg(feature = "mpi")]
    let world = crate::study::mpi::World::init().filter(|w| w.size() > 1);
    #[cfg(feature = "mpi")]
    let shared = world.as_ref().map(ranks::Shared::new);
    #[cfg(feature = "mpi")]
    let role = shared
        .as_ref()
        .map(|s| (s as &dyn envelope::Ranks, s.is_master()));
    #[cfg(not(feature = "mpi"))]
    let role = None;
    let Some(r) = check_as(plan, out, opts, role)? else {
        return Ok(0);
    };
    #[cfg(feature = "mpi")]
    let ranks_note = shared.as_ref().map_or(String::new(), |s| {
        format!(
            " of rank 0 and {} other rank(s), which computed {} runs",
            s.size() - 1,
            s.received()
        )
    });
    #[cfg(not(feature = "mpi"))]
    let ranks_note = "";
    let g = r.governing().copied();
    if let Some(g) = g {
        let limit = r.limit();
        println!(
            "{}: {} runs in {:.1} s on {} threads{}; governing {} at {:.1} km/h: {:.3} m/s² at {:.2} m (limit {limit} m/s²) — {}",
            plan.display(),
            r.outcomes.len(),
            r.seconds.0,
            r.threads,
            ranks_note,
            r.trains[g.train].name,
            g.speed,
            g.acceleration,
            g.acc_station,
            if g.acceleration <= limit { "passes" } else { "FAILS" }
        );
    }
    println!("outputs in {}", out.display());
    Ok(0)
}

/// `railfem trains`: the built-in trains.
pub fn trains_command() -> Result<i32, FemError> {
    print!("{}", trains::listing());
    Ok(0)
}

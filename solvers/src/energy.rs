//! Energy accounting of a transient run: the [`EnergyLedger`] the driver updates after each
//! committed step, its per-step rows (`energy.csv`) and the short block printed at the end
//! of a run. What does not live here: the integrator and the stepping (see
//! [`crate::driver`]).
//!
//! **Balance.** Dotting the equation of motion `M·a + C·v + f_int(q) = f_ext` with `dq`
//! and integrating from the start of the run gives
//!
//! `W_ext = ΔT + W_int + D_c`,
//!
//! with `W_ext = ∫f_extᵀ·dq`, `T = ½·vᵀ·M·v`, `W_int = ∫f_intᵀ·dq` and `D_c = ∫(C·v)ᵀ·dq`.
//! The work of the internal forces splits into what elements store and what they dissipate
//! themselves, which they report ([`railfem_framework::Element::dissipated_energy`]) as
//! friction at contact points or as material dissipation (plasticity, hysteresis;
//! [`railfem_framework::DissipationKind`]): `W_int = U + D_f + D_p`. The ledger
//! integrates the three works with the trapezoidal rule over each committed step,
//! `ΔW = ½·(f_n + f_{n+1})ᵀ·(q_{n+1} − q_n)`, takes `T` from the state directly, and calls
//! what is left the energy the *integrator* dissipated:
//!
//! `D_num = W_ext − ΔT − U − D_c − D_f − D_p = W_ext − ΔT − W_int − D_c`.
//!
//! For Newmark's average acceleration (`γ = ½`, `β = ¼`) on a linear model this residual is
//! zero to round-off: then `q_{n+1} − q_n = ½Δt·(v_n + v_{n+1})` and
//! `v_{n+1} − v_n = ½Δt·(a_n + a_{n+1})`, so `½·(M·a_n + M·a_{n+1})ᵀ·Δq` is exactly `ΔT`,
//! and the equation of motion holds at both ends of the step, so the trapezoidal works of
//! the four forces sum to zero. Schemes with numerical damping (HHT-α, generalized-α)
//! leave a `D_num` that grows over a run, though not step by step (below). For a linear
//! element the trapezoidal `∫f_int·dq` is exactly `½·qᵀ·K·q`; for a nonlinear one it is
//! the strain energy to the accuracy of the rule (second order in `Δq`).
//!
//! **One step's residual** of the generalized-α family ([`crate::integrator`], with
//! `γ = ½ − α_m + α_f`: HHT-α, generalized-α, Newmark's average acceleration) on a linear
//! model. Write `r = f_ext − f_int − C·v − M·a` at the step's ends (not zero when
//! `α_f ≠ α_m`), `δx = x_{n+1} − x_n`, and `x̄` the mean of the ends. Newmark's updates
//! give `Δq = Δt·v̄ + Δt²·(β − γ/2)·δa` and `δv = Δt·(ā + (γ − ½)·δa)`, so the residual
//! of the step, `½·(f_n + f_{n+1})ᵀ·Δq − δT − ½·(f_int,n + f_int,n+1 + C·v_n + C·v_{n+1})ᵀ·Δq`,
//! is `½·(r_n + r_{n+1})ᵀ·Δq + āᵀ·M·Δq − v̄ᵀ·M·δv`. The balance at the weighted points,
//! `r_w = (1 − α_f)·r_{n+1} + α_f·r_n − (α_f − α_m)·M·δa = 0`, turns `½·(r_n + r_{n+1})`
//! into `r_w + (α_f − α_m)·M·δa + (α_f − ½)·δr`, and with `γ − ½ = α_f − α_m` the
//! velocity terms cancel:
//!
//! `D_step = (α_f − ½)·δrᵀ·Δq + Δt²·(β − γ/2)·((α_f − α_m)·δaᵀ·M·δa + ½·δ(aᵀ·M·a)) + r_wᵀ·Δq`.
//!
//! The last term is zero when the step is solved; with a reduced block (Galerkin's solve,
//! [`crate::partition::ReducedBasis`]) `r_w` keeps the constraint's reactions on the
//! interior, but `r_wᵀ·Δq = (Tᵀ·r_w)ᵀ·Δq̂ = 0` for an increment on the subspace, and the
//! same closed form holds in the reduced coordinates. `δrᵀ·Δq` holds the load's change
//! times the increment, `δf_extᵀ·Δq`, which has either sign: under ground motion the
//! residual swings from step to step, and only its sum over many steps is the
//! integrator's dissipation. On the three-span viaduct of `tests/reduced_far_field.rs`
//! (2 ms steps, ρ∞ = 0.5) ten steps at 1.5 s range from −0.33 to 0.33 J; on the paper's
//! 113-span entry with the synthetic record (0.5 ms) a step's residual ranges from −19 to
//! 13 J, and their sum is 51 J after 5 000 steps.
//!
//! On finite-rotation nodes `Δq` is the step's incremental rotation vector (the spin the
//! nodal moments, conjugate to spin, work on), not the difference of rotation vectors.
//!
//! Energies are relative to the state at the first recorded step (kinetic energy is shown
//! as its current value). For carried nodes (moving frames) the DOFs are deviations from
//! the reference motion, so `T` is the kinetic energy of that relative motion and the
//! rigid-body pseudo-loads of Eq. 5 count as external work.

use crate::chunks::par_chunks;
use crate::partition::Partitioned;
use crate::state::State;
use railfem_framework::assembly::Assembler;
use railfem_framework::error::FemError;
use railfem_framework::model::Model;
use railfem_framework::parallel::threads;
use railfem_framework::row_set::RowSet;
use std::fmt::Write as _;
use std::path::Path;

/// The energies after one committed step (J, relative to the ledger's start; `kinetic`
/// is the current value).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct EnergyRow {
    /// Time (s).
    pub t: f64,
    /// Work of the external forces `∫f_extᵀ·dq`.
    pub external_work: f64,
    /// Kinetic energy `½·vᵀ·M·v`.
    pub kinetic: f64,
    /// Energy stored in the elements, `∫f_intᵀ·dq` minus what they dissipated.
    pub strain: f64,
    /// Energy dissipated by the damping matrix, `∫(C·v)ᵀ·dq`.
    pub damping: f64,
    /// Energy dissipated by friction at contact points, as the elements report it.
    pub friction: f64,
    /// Energy dissipated inside the elements' material (plasticity, hysteresis), as they
    /// report it.
    pub material: f64,
    /// The balance residual: energy dissipated (or, if negative, created) by the
    /// integrator, `W_ext − ΔT − strain − damping − friction − material − switched`.
    pub integrator: f64,
    /// Energy removed by jumps of the state between steps (a block switched to its
    /// reduced form, [`EnergyLedger::book_jump`]); zero without them, and then not written.
    pub switched: f64,
}

impl EnergyRow {
    /// The names of the energies (J), in the order of [`EnergyRow::values`] and of
    /// `energy.csv`'s columns after `time`.
    pub const COLUMNS: [&'static str; 7] = [
        "external_work",
        "kinetic",
        "strain",
        "damping",
        "friction",
        "material",
        "integrator",
    ];

    /// The energies in the order of [`EnergyRow::COLUMNS`].
    pub fn values(&self) -> [f64; 7] {
        [
            self.external_work,
            self.kinetic,
            self.strain,
            self.damping,
            self.friction,
            self.material,
            self.integrator,
        ]
    }

    /// The largest of the energies' magnitudes: the scale an energy error is relative to.
    pub fn scale(&self) -> f64 {
        [
            self.external_work,
            self.kinetic,
            self.strain,
            self.damping,
            self.friction,
            self.material,
        ]
        .iter()
        .fold(0.0f64, |m, x| m.max(x.abs()))
    }
}

/// Accumulates the energy balance of a run, one committed step at a time.
#[derive(Debug, Clone, Default)]
pub struct EnergyLedger {
    started: bool,
    /// Kinetic energy at the start.
    kinetic0: f64,
    /// Element-reported dissipation at the start, `[friction, material]`.
    dissipated0: [f64; 2],
    /// `C·v` at the last recorded state.
    cv_prev: Vec<f64>,
    /// Work of the internal forces so far.
    internal_work: f64,
    /// Running totals (the last row).
    now: EnergyRow,
    /// Largest energy scale seen, for relative errors.
    peak_scale: f64,
    /// Largest |integrator| seen.
    peak_residual: f64,
    /// One row per committed step.
    pub history: Vec<EnergyRow>,
    /// Work vectors kept between steps: the step's increment, `M·v`, and `C·v` of the
    /// state before the last (storage for the next `C·v`).
    dq: Vec<f64>,
    buf: Vec<f64>,
    cv: Vec<f64>,
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// `½·vᵀ·M·v`, `M·v` formed into `buf`: over every equation, or across ranks (`ranks`,
/// each rank's own rows, [`Partitioned::sums_over_rows`]).
fn kinetic(asm: &Assembler, v: &[f64], buf: &mut Vec<f64>, ranks: Option<&mut Partitioned>) -> f64 {
    let mv = mass_times_into(asm, v, buf);
    match ranks.and_then(|p| p.sums_over_rows(1, &|rows, out| out[0] = dot_rows(rows, mv, v))) {
        Some(s) => 0.5 * s[0],
        None => 0.5 * dot(mv, v),
    }
}

/// `M·v` formed into `buf` (resized to `v`'s length).
fn mass_times_into<'a>(asm: &Assembler, v: &[f64], buf: &'a mut Vec<f64>) -> &'a [f64] {
    buf.clear();
    buf.resize(v.len(), 0.0);
    asm.mass_times(v, buf);
    buf
}

/// `Σ a_i·b_i` over `rows`, in their order.
fn dot_rows(rows: &[usize], a: &[f64], b: &[f64]) -> f64 {
    rows.iter().fold(-0.0, |s, &i| s + a[i] * b[i])
}

/// `out = C·v` (zero without damping: then nothing but the fill).
fn damping_force(asm: &Assembler, v: &[f64], out: &mut Vec<f64>) {
    out.clear();
    out.resize(v.len(), 0.0);
    if asm.has_damping() {
        asm.damping_times_add(v, out);
    }
}

impl EnergyLedger {
    /// Forgets everything; the next [`EnergyLedger::record`] starts a new balance (the
    /// driver calls this after a static solve, which moves the state without inertia).
    pub fn reset(&mut self) {
        *self = EnergyLedger::default();
    }

    /// Whether the ledger has a start state.
    pub fn started(&self) -> bool {
        self.started
    }

    /// Adds the step from the committed state `prev` to the committed state `next`. The
    /// first call also takes `prev` as the start of the balance. `next_mv` is `M·v` of
    /// `next` when the caller has it (the kinetic energy is then `½·vᵀ·(M·v)` from it, the
    /// same value), else it is formed here; likewise `next_cv`, `C·v` of `next` (constant
    /// and variable damping), whose vector the ledger takes in exchange for storage of its
    /// own (contents unspecified). Without damping
    /// ([`Assembler::has_damping`]) `C·v` is the zero vector at both ends and the step adds
    /// nothing to `D_c`: no product is formed. The vectors are the ledger's own, kept
    /// between steps.
    ///
    /// **Across ranks** (`ranks`: the partitioned solver of a rank that forms the residual
    /// of its own rows, [`crate::driver::Driver::keep_own_rows`]): `f_int`, `M·v` and `C·v`
    /// are exact on the rank's own rows only, so each rank sums the works and `vᵀ·M·v`
    /// over its own rows, block by block, and the pieces are added in block order
    /// ([`Partitioned::sums_over_rows`], one all-gather per step): the same totals on
    /// every rank and for any number of ranks, equal to one process's sums over fixed
    /// chunks to round-off (another order of the same terms). Every rank calls it at the
    /// same step.
    ///
    /// **Held rows** (`held`: the rows the driver forms while the activity window holds
    /// blocks, [`crate::held_rows`]): the sums run over those rows alone; on the others
    /// `Δq = 0` and `v = 0`, so every term left out is zero.
    #[allow(clippy::too_many_arguments)]
    pub fn record(
        &mut self,
        asm: &Assembler,
        model: &Model,
        prev: &State,
        next: &State,
        next_mv: Option<&[f64]>,
        next_cv: Option<&mut Vec<f64>>,
        mut ranks: Option<&mut Partitioned>,
        held: Option<&RowSet>,
    ) {
        let mut buf = std::mem::take(&mut self.buf);
        if !self.started || self.cv_prev.len() != prev.v.len() {
            let mut cv_prev = Vec::new();
            damping_force(asm, &prev.v, &mut cv_prev);
            *self = EnergyLedger {
                started: true,
                kinetic0: kinetic(asm, &prev.v, &mut buf, ranks.as_deref_mut()),
                dissipated0: asm.dissipated_by_kind(model),
                cv_prev,
                ..Default::default()
            };
            self.now.t = prev.t;
            self.now.kinetic = self.kinetic0;
        }
        // The step's increment: on finite-rotation triples the incremental rotation vector,
        // formed into `dq`; otherwise `q_{n+1} − q_n` inline.
        let finite = asm.dofmap.has_finite_rotations();
        let mut dq = std::mem::take(&mut self.dq);
        if finite {
            dq.resize(next.q.len(), 0.0);
            asm.dofmap.increment(&prev.q, &next.q, &mut dq);
        }
        let damped = asm.has_damping() || self.cv_prev.iter().any(|&c| c != 0.0);
        let mut cv = std::mem::take(&mut self.cv);
        if damped {
            match next_cv {
                // The caller's vector is taken (it receives the ledger's spare storage).
                Some(c) if c.len() == next.v.len() => std::mem::swap(&mut cv, c),
                _ => damping_force(asm, &next.v, &mut cv),
            }
        }
        // `M·v` of `next`: the caller's, or formed here.
        let mv = match next_mv {
            Some(mv) => mv,
            None => mass_times_into(asm, &next.v, &mut buf),
        };
        // The three trapezoidal works `½·Σ (f_n + f_{n+1})ᵢ·Δqᵢ`, and `vᵀ·M·v`.
        let cv_prev = &self.cv_prev;
        let (dq_r, cv_r) = (&dq, &cv);
        let works = |lo: usize, hi: usize, rows: Option<&[usize]>| {
            let (mut ext, mut int, mut damp) = (-0.0f64, -0.0f64, -0.0f64);
            let mut term = |i: usize| {
                let d = if finite {
                    dq_r[i]
                } else {
                    next.q[i] - prev.q[i]
                };
                ext += (prev.f_ext[i] + next.f_ext[i]) * d;
                int += (prev.f_int[i] + next.f_int[i]) * d;
                if damped {
                    damp += (cv_prev[i] + cv_r[i]) * d;
                }
            };
            match rows {
                Some(rows) => rows.iter().for_each(|&i| term(i)),
                None => (lo..hi).for_each(term),
            }
            (ext, int, damp)
        };
        // With held rows, the rows where a term can be non-zero ([`crate::held_rows`]).
        let works = |lo: usize, hi: usize, list: Option<&[usize]>| match (list, held) {
            (None, Some(set)) => set.within(lo, hi).fold((-0.0, -0.0, -0.0), |a, r| {
                let p = works(r.start, r.end, None);
                (a.0 + p.0, a.1 + p.1, a.2 + p.2)
            }),
            _ => works(lo, hi, list),
        };
        let across = ranks.and_then(|p| {
            p.sums_over_rows(4, &|rows, out| {
                let (ext, int, damp) = works(0, 0, Some(rows));
                out.copy_from_slice(&[ext, int, damp, dot_rows(rows, mv, &next.v)]);
            })
        });
        let (ext, int, damp, vmv) = match across {
            Some(s) => (s[0], s[1], s[2], s[3]),
            // In one process: one pass over fixed chunks of the equations on the available
            // threads, each chunk's sums accumulated in index order from −0 and the
            // chunks' added in order (the same on any thread count).
            None => {
                let parts = par_chunks(next.q.len(), threads(0), |lo, hi| works(lo, hi, None));
                let (ext, int, damp) = parts.iter().fold((-0.0f64, -0.0f64, -0.0f64), |a, p| {
                    (a.0 + p.0, a.1 + p.1, a.2 + p.2)
                });
                let vmv = match held {
                    Some(set) => set
                        .ranges()
                        .iter()
                        .fold(0.0, |s, r| s + dot(&mv[r.clone()], &next.v[r.clone()])),
                    None => dot(mv, &next.v),
                };
                (ext, int, damp, vmv)
            }
        };
        let r = &mut self.now;
        r.t = next.t;
        r.external_work += 0.5 * ext;
        self.internal_work += 0.5 * int;
        if damped {
            r.damping += 0.5 * damp;
            std::mem::swap(&mut self.cv_prev, &mut cv);
        }
        self.cv = cv;
        r.kinetic = 0.5 * vmv;
        let [friction, material] = asm.dissipated_by_kind(model);
        r.friction = friction - self.dissipated0[0];
        r.material = material - self.dissipated0[1];
        r.strain = self.internal_work - r.friction - r.material;
        // `− switched` is `− 0` without jumps: the same bits.
        r.integrator = r.external_work
            - (r.kinetic - self.kinetic0)
            - r.strain
            - r.damping
            - r.friction
            - r.material
            - r.switched;
        self.peak_scale = self.peak_scale.max(r.scale()).max(self.kinetic0);
        self.peak_residual = self.peak_residual.max(r.integrator.abs());
        self.history.push(*r);
        self.dq = dq;
        self.buf = buf;
    }

    /// Books a jump of the state between steps, from `before` to `after` (same time and
    /// loads; a block switched to its reduced form, `crate::reduced::blocks`): the works
    /// over the jump as a step's, `f_extᵀ·Δq` and `½·(f_int + f_int')ᵀ·Δq`, and the energy
    /// the jump removed, `f_extᵀ·Δq − ΔT − ½·(f_int + f_int')ᵀ·Δq` (the change of
    /// `T + U − f_extᵀ·q`, with the sign of a loss), as [`EnergyRow::switched`]; `C·v`
    /// is taken at `after`. The balance then closes as without the jump, less the booked
    /// energy. Returns it (J); nothing before the first recorded step (the balance then
    /// starts from `after`). One process only (no `ranks`, no held rows).
    pub fn book_jump(&mut self, asm: &Assembler, before: &State, after: &State) -> f64 {
        if !self.started {
            return 0.0;
        }
        let mut buf = std::mem::take(&mut self.buf);
        let t0 = kinetic(asm, &before.v, &mut buf, None);
        let t1 = kinetic(asm, &after.v, &mut buf, None);
        self.buf = buf;
        let (mut ext, mut int) = (0.0, 0.0);
        for i in 0..after.q.len() {
            let d = after.q[i] - before.q[i];
            if d != 0.0 {
                ext += 0.5 * (before.f_ext[i] + after.f_ext[i]) * d;
                int += 0.5 * (before.f_int[i] + after.f_int[i]) * d;
            }
        }
        let removed = ext - (t1 - t0) - int;
        self.now.external_work += ext;
        self.internal_work += int;
        self.now.switched += removed;
        damping_force(asm, &after.v, &mut self.cv_prev);
        removed
    }

    /// The totals after the last recorded step.
    pub fn totals(&self) -> EnergyRow {
        self.now
    }

    /// Kinetic energy at the start of the balance (J).
    pub fn initial_kinetic(&self) -> f64 {
        self.kinetic0
    }

    /// Largest |integrator residual| over the run divided by the largest energy seen: the
    /// energy error of the run (zero to round-off for a conservative scheme).
    pub fn relative_error(&self) -> f64 {
        if self.peak_scale > 0.0 {
            self.peak_residual / self.peak_scale
        } else {
            0.0
        }
    }

    /// The short block printed at the end of a run.
    pub fn summary(&self) -> String {
        let r = self.now;
        let mut s = String::new();
        let _ = writeln!(
            s,
            "energy balance over {} steps to t = {:.6} s (J): external work {:.6e}, kinetic {:.6e} (start {:.6e}), strain {:.6e}",
            self.history.len(),
            r.t,
            r.external_work,
            r.kinetic,
            self.kinetic0,
            r.strain
        );
        let _ = write!(
            s,
            "  dissipated: damping {:.6e}, friction {:.6e}, material {:.6e}, integrator {:.6e}; largest |integrator|/energy {:.3e}",
            r.damping,
            r.friction,
            r.material,
            r.integrator,
            self.relative_error()
        );
        s
    }

    /// Writes the rows as CSV:
    /// `time,external_work,kinetic,strain,damping,friction,material,integrator` (J).
    pub fn write_csv(&self, path: &Path) -> Result<(), FemError> {
        // The jumps' column only when a jump was booked (a reduced far field).
        let switched = self.history.iter().any(|r| r.switched != 0.0);
        let mut s = String::from("time [s]");
        for c in EnergyRow::COLUMNS {
            let _ = write!(s, ",{c} [J]");
        }
        if switched {
            s.push_str(",switched [J]");
        }
        s.push('\n');
        for r in &self.history {
            let _ = write!(s, "{:.9e}", r.t);
            for v in r.values() {
                let _ = write!(s, ",{v:.9e}");
            }
            if switched {
                let _ = write!(s, ",{:.9e}", r.switched);
            }
            s.push('\n');
        }
        std::fs::write(path, s).map_err(|e| FemError::output(path, e))
    }
}

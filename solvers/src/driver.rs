//! The analysis driver: static (Newton in load steps), transient (generalized-α family with
//! Newton–Raphson each step and automatic step cutting) and the hooks recorders use.
//!
//! Data flows one way: the model's elements are evaluated by the assembler, the driver
//! solves and updates the trial state, commits on convergence and hands the committed state
//! to the recorders. Per step: move the carriers and let elements re-pick nodes
//! (`advance`), form the external force, predict, iterate (residual, tangent, solve,
//! update), commit.
//!
//! **Finite rotations.** On finite-rotation nodes ([`railfem_framework::rotation`],
//! [`railfem_framework::dofmap::DofMap`]) the rotational entries of `q` hold the total
//! rotation vector ψ; a Newton correction there is a spatial spin composed onto it
//! ([`railfem_framework::dofmap::DofMap::add_correction`]), in the static solve and in every
//! integrator alike. The nodal angular velocity and acceleration are *spatial* vectors, and
//! Newmark's formulas take the step's incremental rotation vector `Θ = log(R_{n+1}·R_nᵀ)` as
//! the rotational increment `Δu` ([`railfem_framework::dofmap::DofMap::increment`]):
//! `a_{n+1} = Θ/(βΔt²) − v_n/(βΔt) − (1/2β − 1)·a_n`, `v_{n+1} = v_n + Δt·((1−γ)·a_n + γ·a_{n+1})`.
//! Limits: adding spatial vectors of different times is exact for a rotation about a fixed
//! axis and first-order otherwise, so rotational inertia should be isotropic (a multiple of
//! the identity, for which Euler's equations have no gyroscopic term) or absent — the
//! corotational beam has translational mass only; the effective tangent takes `dΘ/dδ ≈ I`
//! (exact for small step rotations; Newton still converges, more slowly for large `Θ`). A
//! model without finite-rotation nodes runs exactly as before: the increment and the
//! correction are the plain difference and sum.
//!
//! What a scene does not need it does not pay for: a model without nonlinear elements takes
//! one solve per step with the factor of `K_eff` kept while `Δt` is unchanged; modified and
//! initial-tangent Newton keep factors across iterations or steps; tiny systems (a vehicle
//! on a rigid track) use a dense factorization.

use crate::dense::DenseLu;
use crate::energy::EnergyLedger;
use crate::integrator::Coefficients;
use crate::linear::{solver_for, LinearSolver, SolverError};
use crate::linear_backend::{LinearBackend, Mode};
use crate::lowrank::{LowRank, LowRankStats};
use crate::partition::{PartitionOptions, PartitionStats, Partitioned};
pub use crate::state::State;
use crate::static_lu::StaticLu;
pub use crate::step_method::{Accepted, Attempt};
use crate::step_method::{CondensedNewton, FullNewton, HeldActiveSet, LumpedLinear, StepMethod};
pub use crate::thresholds::{DENSE_LIMIT, DIRECT_DENSE_LIMIT, DIRECT_DENSE_LU_LIMIT};
use crate::time_integrator::{Increment, TimeIntegrator, Trial};
use railfem_framework::assembly::Assembler;
use railfem_framework::error::FemError;
use railfem_framework::limits::fmt_num;
use railfem_framework::model::{AnalysisKind, Model, NewtonKind, Predictor, SolverChoice};
use railfem_framework::recording::{History, Recorders};
use railfem_framework::sparse::CscMatrix;
use railfem_framework::DofSet;
use std::path::Path;
use std::sync::Arc;
use std::time::Instant;

mod holds;
mod predictor;
mod rank_build;
mod ranks;
pub(crate) use holds::ActiveSetHolds;
use predictor::IncrementPredictor;
use rank_build::RankSplit;
use ranks::Ranks;

/// Which step method the driver picks where several apply ([`Driver::default_step_method`]):
/// switches for comparisons, each giving the same answers as the other choice (to the bit
/// for the lumped step, to round-off for the condensed Newton).
#[derive(Debug, Clone, Copy)]
pub(crate) struct MethodChoice {
    /// The lumped linear step where it applies ([`crate::lumped_step`]).
    pub(crate) lumped_step: bool,
    /// The condensed Newton with the partitioned solver ([`crate::condensed`]).
    pub(crate) condense_residual: bool,
    /// The condensed Newton's verification forms the next predictor's products
    /// ([`Driver::set_products_ahead`]).
    pub(crate) products_ahead: bool,
}

impl Default for MethodChoice {
    fn default() -> Self {
        MethodChoice {
            lumped_step: true,
            condense_residual: true,
            products_ahead: true,
        }
    }
}

/// The linear solver of the whole tangent for a model of `n` equations: dense LU in the
/// plain order up to [`DIRECT_DENSE_LIMIT`]; for an unsymmetric tangent [`StaticLu`] up to
/// [`DIRECT_DENSE_LU_LIMIT`]; the sparse solver otherwise (Cholesky if `symmetric`).
pub fn direct_solver(n: usize, symmetric: bool) -> Box<dyn LinearSolver> {
    if n <= DIRECT_DENSE_LIMIT {
        Box::new(DenseLu::default())
    } else if !symmetric && n <= DIRECT_DENSE_LU_LIMIT {
        Box::new(StaticLu::new())
    } else {
        solver_for(symmetric)
    }
}

/// The vectors of one step attempt, kept by the driver between steps so that a step
/// allocates nothing (at 10⁵ equations each vector is 0.8 MB: allocated fresh every step,
/// its pages were faulted in again each time).
#[derive(Debug, Clone, Default)]
pub(crate) struct StepWork {
    /// Storage for the next committed state: the state the last committed step replaced.
    pub(crate) next: State,
    /// Residual.
    pub(crate) r: Vec<f64>,
    /// Acceleration at `n+1−α_m`.
    pub(crate) a_w: Vec<f64>,
    /// Velocity at `n+1−α_f`.
    pub(crate) v_w: Vec<f64>,
    /// Inertia force `M·a_w`.
    pub(crate) inertia: Vec<f64>,
    /// Damping force `C·v_w`.
    pub(crate) damp: Vec<f64>,
    /// The iterate before the last correction (backtracking).
    q_prev: Vec<f64>,
    /// The correction of this iteration.
    pub(crate) dq: Vec<f64>,
    /// The correction of the last iteration (backtracking).
    dq_prev: Vec<f64>,
    /// `(1−α_f)·f_ext(n+1) + α_f·f_ext(n)`.
    pub(crate) f_ref_ext: Vec<f64>,
    /// The step's increment on finite-rotation models.
    pub(crate) du: Vec<f64>,
    /// After a linear step: `M·v` of its state (the energy balance's kinetic energy), when
    /// `mv_ready`.
    pub(crate) mv: Vec<f64>,
    pub(crate) mv_ready: bool,
    /// After a condensed step ([`crate::condensed`]): `C·v` of its state, formed in the
    /// verification's pass over the matrices, when `cv_ready` (the energy balance takes it).
    pub(crate) cv: Vec<f64>,
    pub(crate) cv_ready: bool,
    /// After a linear step: the weighted acceleration the next step of the same `Δt`
    /// starts with, `a_w = (1−α_m)·a(Δu = 0) + α_m·a_n` from the step's state, and its
    /// inertia force `M·a_w`, formed in the same pass over the matrices as `K·q`. The next
    /// step uses the force if its own first `a_w` equals this one to the bit (same `Δt`,
    /// same state) and every mass is constant, and forms it anew otherwise.
    a_w_next: Vec<f64>,
    inertia_next: Vec<f64>,
    pub(crate) inertia_ready: bool,
    /// The displacement the last linear attempt formed its internal force at (`K·q`, kept
    /// as the state's `f_int`): the next step's first residual starts from the same `q`
    /// and takes `f_int` from the state instead of a pass over `K`.
    pub(crate) f_int_at: Vec<f64>,
}

impl StepWork {
    /// Every work vector at length `n` (the values left as they are: each is written
    /// before it is read).
    pub(crate) fn resize(&mut self, n: usize) {
        for x in [
            &mut self.r,
            &mut self.a_w,
            &mut self.v_w,
            &mut self.inertia,
            &mut self.damp,
            &mut self.q_prev,
            &mut self.dq,
            &mut self.dq_prev,
            &mut self.f_ref_ext,
            &mut self.du,
            &mut self.mv,
            &mut self.a_w_next,
            &mut self.inertia_next,
        ] {
            x.resize(n, 0.0);
        }
    }
}

/// The linear system about the reference state ([`Driver::reference_system`]).
#[derive(Debug, Clone)]
pub struct ReferenceSystem {
    /// Tangent stiffness at zero displacement (N/m, N·m/rad, ...).
    pub stiffness: CscMatrix,
    /// Constant mass (kg, kg·m²).
    pub mass: CscMatrix,
    /// Constant damping, Rayleigh included (N·s/m, ...).
    pub damping: CscMatrix,
    /// External load at the current time, full load factor (N, N·m).
    pub load: Vec<f64>,
}

/// Wall-clock time spent per phase (s).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Timings {
    /// Element state determination and assembly of forces and tangents.
    pub assembly: f64,
    /// Numeric (and symbolic) factorization.
    pub factor: f64,
    /// Triangular solves.
    pub solve: f64,
    /// External loads, carriers and element `advance` (contact search happens here and in
    /// `update`).
    pub loads: f64,
}

/// What one step took.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct StepReport {
    /// Newton iterations (solves) over all sub-steps.
    pub iterations: usize,
    /// How many times the step was halved.
    pub cuts: usize,
    /// Final residual norm (N): measured after the last correction for a nonlinear model;
    /// for a linear model (one exact solve per step, not re-checked) the residual before it.
    pub residual: f64,
}

/// Totals of a run.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct RunSummary {
    /// Steps taken (not counting sub-steps from cutting).
    pub steps: usize,
    /// Newton iterations (linear solves).
    pub iterations: usize,
    /// Step halvings.
    pub cuts: usize,
    /// Sub-steps solved with the contact's active set held ([`crate::held_active_set`]),
    /// after the halvings gave up.
    pub held: usize,
    /// Numeric factorizations performed.
    pub factorizations: usize,
    /// Symbolic analyses performed.
    pub symbolic: usize,
    /// Number of equations.
    pub equations: usize,
    /// Wall time of the whole run (s).
    pub wall: f64,
    /// Per-phase times.
    pub timings: Timings,
}

/// Runs a model.
///
/// # Example
///
/// A mass `m` on a spring `k`, at rest, under a force `F` applied at `t = 0`: the exact
/// response is `u(t) = F/k·(1 − cos ωt)` with `ω = √(k/m)`, so at half a period the mass is
/// at `2F/k`. The average-acceleration Newmark scheme with 400 steps per period shifts the
/// phase by `(ωΔt)²/12·π ≈ 6e-5` rad there, which changes `u` by `O(1e-9)` relative.
///
/// ```
/// use railfem_framework::builder::ModelBuilder;
/// use railfem_framework::loads::{LoadSpec, TimeSeries};
/// use railfem_framework::model::AnalysisSpec;
/// use railfem_framework::{Dof, DofSet};
/// use railfem_solvers::Driver;
///
/// use railfem_elements::{mass::MassParams, spring_damper::SpringDamperParams};
///
/// let (m, k, force): (f64, f64, f64) = (1.0e3, 4.0e5, 2.0e3); // kg, N/m, N
/// let period = 2.0 * std::f64::consts::PI * (m / k).sqrt();
/// let mut b = ModelBuilder::new("oscillator");
/// b.node_fixed(1, [0.0, 0.0, 0.0], DofSet::of(&[Dof::Ux, Dof::Uy, Dof::Rx, Dof::Ry, Dof::Rz]));
/// b.add(1, &[1], &SpringDamperParams::new([0.0, 0.0, k, 0.0, 0.0, 0.0]));
/// b.add(2, &[1], &MassParams::new(m));
/// b.load(LoadSpec::Nodal { node: 1, dof: Dof::Uz, value: force, series: TimeSeries::Constant });
/// b.analysis(AnalysisSpec {
///     dt: period / 400.0,
///     duration: period / 2.0,
///     initial_static: false,
///     ..Default::default()
/// });
/// let mut driver = Driver::new(b.build()?)?;
/// driver.run(None, &mut |_| {})?;
/// let u = driver.displacement(1, Dof::Uz).expect("node 1 moves along z");
/// assert!((u - 2.0 * force / k).abs() < 1e-6 * (2.0 * force / k), "u = {u} m");
/// # Ok::<(), railfem_framework::FemError>(())
/// ```
pub struct Driver {
    /// The model (owned: elements are updated in place).
    pub model: Model,
    /// The assembler.
    pub asm: Assembler,
    /// The committed state.
    pub state: State,
    /// The integrator ([`crate::time_integrator`]), resolved by name from the model.
    pub integrator: Box<dyn TimeIntegrator>,
    /// The linear solver, the effective matrix and the factor cache
    /// ([`crate::linear_backend`]).
    pub(crate) linear: LinearBackend,
    /// The last converged step's increment, for [`Predictor::Increment`].
    predictor: IncrementPredictor,
    /// Totals.
    pub summary: RunSummary,
    /// Whether the transient's initial state is formed ([`Driver::initialize`]).
    initialized: bool,
    /// Print each Newton iteration's residual to stderr (`RAILFEM_TRACE=1`).
    pub trace: bool,
    /// Which step method the driver picks ([`Driver::default_step_method`]).
    pub(crate) choice: MethodChoice,
    /// The energy balance, updated after each committed step ([`crate::energy`]); `None`
    /// skips the accounting (two matrix–vector products per step).
    pub energy: Option<EnergyLedger>,
    /// The condensed Newton's counters (its caches are the method's own).
    pub(crate) condensed: crate::condensed_cache::CondensedStats,
    /// The step attempt's vectors, kept between steps.
    pub(crate) work: StepWork,
    /// What the contacts' active sets are held at ([`crate::held_active_set`]).
    pub(crate) holds: ActiveSetHolds,
    /// The run's share across ranks ([`Driver::set_exchange`], [`Driver::keep_own_rows`]).
    pub(crate) ranks: Ranks,
    /// One flag per equation: held by the activity window ([`crate::window`]), its
    /// residual a reaction; empty when nothing is held.
    pub(crate) frozen_rows: Vec<bool>,
    /// How each attempt at a step is solved ([`crate::step_method`]): picked before the
    /// first step ([`Driver::default_step_method`]) unless given; taken out while it runs.
    pub(crate) method: Option<Box<dyn StepMethod<Driver>>>,
    /// The rows the condensed Newton's passes form while blocks are held
    /// ([`crate::held_rows`]); `None` when nothing is held.
    pub(crate) held_rows: Option<crate::held_rows::HeldRows>,
    /// Whether held rows are left out ([`Driver::set_skip_held_rows`]).
    pub(crate) skip_held_rows: bool,
    /// The constant damping changed since the last step (an absorbing layer,
    /// [`crate::window::absorb`]): the condensed Newton forgets the products it formed
    /// ahead with the old one.
    pub(crate) constant_changed: bool,
}

fn norm(x: &[f64]) -> f64 {
    x.iter().map(|v| v * v).sum::<f64>().sqrt()
}

impl Driver {
    /// Numbers equations, assembles constant parts and picks a linear solver.
    pub fn new(model: Model) -> Result<Driver, FemError> {
        Self::build(model, None)
    }

    /// [`Driver::new`] for one rank of `exchange`, sharing the partitioned solver's blocks
    /// with the other ranks as [`Driver::set_exchange`] and [`Driver::keep_own_rows`] do, but
    /// with the split made before the constant matrices exist: the partitioned solver is
    /// split on the pattern (with `options`, or the model's `block_size`), and `K`, `M`,
    /// `C` are formed only on the columns this rank keeps (those of its own rows and the
    /// base top set, and until the initial mass solve those that solve's split reads;
    /// [`Assembler::new_on_columns`]). The whole matrices never exist on the rank, and
    /// the answers are those of `set_exchange` and `keep_own_rows` after `new`, to the bit.
    /// Where the constant part cannot be kept on columns exactly, the driver is built whole
    /// and then shares the blocks (`set_exchange`, `keep_own_rows`). A model that does not
    /// run the partitioned solver gets the one-process driver, without the ranks: the
    /// caller refuses it ([`Driver::partition_stats`] is `None`; `set_exchange` says why).
    pub fn new_across_ranks(
        model: Model,
        exchange: Arc<dyn crate::exchange::Exchange>,
        options: Option<PartitionOptions>,
    ) -> Result<Driver, FemError> {
        let mut d = Self::build(model, Some((exchange.clone(), options)))?;
        if d.linear.partitioned().is_none() || d.ranks.own_rows {
            return Ok(d);
        }
        if let Some(o) = options {
            d.set_partition_options(o);
        }
        d.set_exchange(exchange)?;
        d.keep_own_rows();
        Ok(d)
    }

    /// [`Driver::new`], and with `shared` [`Driver::new_across_ranks`]'s build on the
    /// rank's columns.
    fn build(
        mut model: Model,
        shared: Option<(Arc<dyn crate::exchange::Exchange>, Option<PartitionOptions>)>,
    ) -> Result<Driver, FemError> {
        let spec = &model.analysis;
        if spec.kind == AnalysisKind::Transient {
            // Size guard: the energy ledger keeps one row per step.
            railfem_framework::limits::check_memory(
                &format!(
                    "`duration` = {} s at `dt` = {} s",
                    fmt_num(spec.duration),
                    fmt_num(spec.dt)
                ),
                (spec.duration / spec.dt).ceil(),
                "energy-balance rows",
                std::mem::size_of::<crate::energy::EnergyRow>() as f64,
                "give a larger `dt` or a shorter `duration`",
            )
            .map_err(|m| FemError::input(format!("{}: [analysis]", model.origin), m))?;
        }
        // Size guard of the whole model, before numbering and assembly: every node not
        // fully fixed counted with six DOFs at the measured cost per DOF (the generators'
        // own guards each see only their part).
        let free = model
            .nodes
            .iter()
            .filter(|n| n.fixed != DofSet::ALL)
            .count();
        railfem_framework::limits::check_memory(
            &format!("the model ({free} nodes not fully fixed)"),
            6.0 * free as f64,
            "DOFs",
            railfem_framework::limits::BYTES_PER_DOF,
            "model a shorter stretch (a `window`) or coarser meshes",
        )
        .map_err(|m| FemError::input(&model.origin, m))?;
        let mut split = None;
        let asm = match &shared {
            None => Assembler::new(&mut model, crate::thresholds::resolve)?,
            Some((ex, own)) => {
                let options = own.unwrap_or_else(|| Self::model_partition_options(&model));
                Assembler::new_on_columns(&mut model, crate::thresholds::resolve, &mut |c| {
                    let s = RankSplit::on_pattern(c, ex, options)?;
                    let columns = s.until_mass.clone();
                    split = Some(s);
                    Some(columns)
                })?
            }
        };
        let n = asm.neq();
        if n == 0 {
            return Err(FemError::input(
                &model.origin,
                "the model has no free DOF (every DOF is fixed or unused); free some DOFs or add elements",
            ));
        }
        let integrator = crate::time_integrator::resolve(&model.analysis, &model.origin)?;
        // Off the pattern the effective matrix is formed at the first factorization (across
        // ranks, only the columns the rank reads): no copy of the pattern before it.
        let k_eff = if asm.off_pattern() {
            CscMatrix::from_columns(Vec::new())
        } else {
            asm.k_const.zeros_like()
        };
        // Across ranks the partitioned solver comes split with the rank's build
        // ([`Driver::take_rank_split`]).
        let mode = if !asm.off_pattern() || split.is_some() {
            Mode::Direct(direct_solver(n, asm.symmetric()))
        } else if asm.solver() == SolverChoice::LowRank {
            Mode::LowRank(LowRank::new())
        } else {
            let options = Self::model_partition_options(&model);
            Mode::Partitioned(Partitioned::new(asm.symmetric(), options))
        };
        // The low-rank mode's analysis picks Cholesky or LU before any value: the constant
        // part is symmetric if each of `K`, `M`, `C` is.
        let symmetric_hint = matches!(mode, Mode::LowRank(_))
            && [&asm.k_const, &asm.m_const, &asm.c_const]
                .iter()
                .all(|m| m.asymmetry() == 0.0);
        let mut d = Driver {
            state: State {
                t: 0.0,
                q: vec![0.0; n],
                v: vec![0.0; n],
                a: vec![0.0; n],
                f_int: vec![0.0; n],
                f_ext: vec![0.0; n],
            },
            summary: RunSummary {
                equations: n,
                ..Default::default()
            },
            model,
            asm,
            integrator,
            linear: LinearBackend::new(mode, k_eff, symmetric_hint),
            predictor: IncrementPredictor::default(),
            initialized: false,
            trace: std::env::var_os("RAILFEM_TRACE").is_some(),
            energy: Some(EnergyLedger::default()),
            choice: MethodChoice::default(),
            condensed: Default::default(),
            work: StepWork::default(),
            holds: ActiveSetHolds::default(),
            ranks: Ranks::default(),
            frozen_rows: Vec::new(),
            method: None,
            held_rows: None,
            skip_held_rows: true,
            constant_changed: false,
        };
        if let (Some(split), Some((ex, _))) = (split, shared) {
            d.take_rank_split(ex, split);
        }
        Ok(d)
    }

    /// The partitioned solver's settings of the model: its `block_size`, the rest default.
    fn model_partition_options(model: &Model) -> PartitionOptions {
        PartitionOptions {
            block_size: model
                .analysis
                .block_size
                .unwrap_or(PartitionOptions::default().block_size),
            ..PartitionOptions::default()
        }
    }

    /// Number of equations.
    pub fn neq(&self) -> usize {
        self.asm.neq()
    }

    /// Work counters of the driver's linear solver (symbolic analyses, numeric
    /// factorizations, solves, factor size).
    pub fn solver_stats(&self) -> crate::linear::SolverStats {
        self.linear.solver_stats()
    }

    fn singular(&self, e: SolverError) -> FemError {
        match e {
            SolverError::Singular { equation } => {
                let (n, d) = self
                    .asm
                    .dofmap
                    .dof_of(equation.min(self.neq().saturating_sub(1)));
                if self.linear.low_rank().is_some() {
                    // The low-rank solver factors the constant part alone: a DOF that only a
                    // variable element (a wheel's contact, say) holds is free there, though
                    // the whole tangent is not singular.
                    return FemError::Singular(format!(
                        "{}: the low-rank solver factors the constant part alone, and it has no stiffness at {} (equation {equation}): that DOF is held only by the variable elements (the contact); use solver = \"partitioned\" (--solver partitioned) or \"direct\"",
                        self.model.origin,
                        self.model.dof_name(n, d)
                    ));
                }
                FemError::Singular(format!(
                    "{}: no stiffness at {} (equation {equation}) once the equations before it are held: the model is a mechanism (a rigid-body or zero-energy mode that the supports and elements leave free); fix that DOF, connect it to an element, or add a spring",
                    self.model.origin,
                    self.model.dof_name(n, d)
                ))
            }
            SolverError::Failed(m) => FemError::Singular(format!("{}: {m}", self.model.origin)),
        }
    }

    /// The message of a zero pivot in the mass matrix of the initial acceleration
    /// ([`Driver::solve_initial_mass`]): a combination of DOFs without inertia of its own,
    /// though each DOF has some mass (a DOF without any is solved statically).
    fn singular_mass(&self, e: SolverError) -> FemError {
        match e {
            SolverError::Singular { equation } => {
                let (n, d) = self
                    .asm
                    .dofmap
                    .dof_of(equation.min(self.neq().saturating_sub(1)));
                FemError::Singular(format!(
                    "{}: the mass matrix is singular at {} (equation {equation}) once the equations before it are held: that DOF has mass only through others (a point mass carried at an offset by a rigid link, say), so the initial acceleration M·a = f has no solution; give the node rotary inertia of its own (a `mass` element with `inertia`), or put the mass on the node itself",
                    self.model.origin,
                    self.model.dof_name(n, d)
                ))
            }
            e => self.singular(e),
        }
    }

    /// Replaces the partitioned solver's settings (block size, threads); no effect in the
    /// direct mode. Takes effect at the next factorization, which rebuilds every block.
    pub fn set_partition_options(&mut self, options: PartitionOptions) {
        // A new split needs the whole pattern, which a rank keeping its own rows no longer
        // holds.
        assert!(
            !self.ranks.own_rows,
            "set the partition options before `keep_own_rows`"
        );
        if self.linear.partitioned().is_some() {
            let p = self.new_partitioned(self.asm.symmetric(), options);
            self.linear.set_partitioned(p);
        }
    }

    /// A partitioned solver, sharing its blocks with the driver's ranks if it has some.
    fn new_partitioned(&self, symmetric: bool, options: PartitionOptions) -> Partitioned {
        let mut p = Partitioned::new(symmetric, options);
        if let Some(ex) = &self.ranks.exchange {
            p.set_exchange(ex.clone());
        }
        p
    }

    /// Runs the partitioned solver across the ranks of `exchange`
    /// ([`crate::partition`], *Across ranks*): every rank builds the same model and calls
    /// the same driver methods in the same order; each factors and condenses its share of
    /// the blocks, rank 0 the top system. Every rank ends each step with the whole state, the
    /// same as one process's. An error if the driver does not use the partitioned solver
    /// (the direct and low-rank solvers are not shared); call it before the first step.
    /// Nothing to do for a driver built across these ranks ([`Driver::new_across_ranks`]).
    pub fn set_exchange(
        &mut self,
        exchange: std::sync::Arc<dyn crate::exchange::Exchange>,
    ) -> Result<(), FemError> {
        let mode = self.linear.mode().name();
        let Some(p) = self.linear.partitioned_mut() else {
            return Err(FemError::input(
                &self.model.origin,
                format!(
                    "the solve across {} ranks needs the partitioned solver, and this model uses the {mode} one; set `solver = \"partitioned\"` in [analysis] (or run one process)",
                    exchange.size(),
                ),
            ));
        };
        // A driver built across these ranks ([`Driver::new_across_ranks`]) shares already.
        if let Some(own) = &self.ranks.exchange {
            assert!(
                std::ptr::addr_eq(Arc::as_ptr(own), Arc::as_ptr(&exchange)),
                "the driver shares its blocks with other ranks already"
            );
            return Ok(());
        }
        p.set_exchange(exchange.clone());
        self.ranks.exchange = Some(exchange);
        self.linear.invalidate();
        Ok(())
    }

    /// Across ranks ([`Driver::set_exchange`], called first): each rank keeps the constant
    /// `K`, `M`, `C` only on the columns of the rows it owns and of the base top set, and
    /// forms the residual of those rows alone; the norms of the convergence test are summed
    /// over the ranks in block order ([`crate::partition`], *rows*). The answers are one
    /// process's to round-off (the norms are summed in another order), and each rank holds
    /// about `1/P` of the constant matrices. It also keeps only the elements it needs:
    /// those touching the rows it keeps, every element evaluated after the build (the
    /// wheels, anything nonlinear or with a changing mass, the vehicles' carried masses),
    /// and those the model's recorders read; the others are released, their indices
    /// kept ([`Assembler::release_elements`]; no number changes). The energy balance is
    /// summed over the ranks' own rows in block order
    /// ([`crate::energy::EnergyLedger::record`]). Returns whether the rows are shared: not in one
    /// process, without the partitioned solver, or where the assembler cannot keep columns
    /// exactly ([`Assembler::keep_constant_columns`]). Set the partition options before.
    pub fn keep_own_rows(&mut self) -> bool {
        if self.ranks.exchange.is_none() || self.ranks.own_rows {
            return self.ranks.own_rows;
        }
        let Some(p) = self.linear.partitioned_mut() else {
            return false;
        };
        p.prepare(&self.asm.k_const);
        let Some(keep) = p.rows_kept() else {
            return false;
        };
        // The initial mass solve is split as in one process (its own block size), from the
        // whole pattern before it is dropped; until it is done the rank also keeps the rows
        // that split reads.
        let mut mass = None;
        let mut until_mass = keep.clone();
        if !self.initialized && self.asm.off_pattern() {
            let mut p = self.new_partitioned(true, PartitionOptions::default());
            p.prepare(&self.asm.m_const);
            if let Some(more) = p.rows_kept() {
                for (k, m) in until_mass.iter_mut().zip(more) {
                    *k |= m;
                }
            }
            mass = Some(p);
        }
        if !self.asm.keep_constant_columns(&until_mass) {
            return false;
        }
        self.release_unneeded_elements(&keep);
        if until_mass != keep {
            self.ranks.narrow_after_mass = Some(keep);
        }
        self.ranks.mass_split = mass;
        self.ranks.own_rows = true;
        true
    }

    /// The elements a rank keeping the rows `keep` holds: those its rows touch, every
    /// element evaluated after the build, and those the model's recorders read (rank 0
    /// writes them; any rank may keep their rows in memory); the others are released
    /// ([`Assembler::release_elements`]).
    fn release_unneeded_elements(&mut self, keep: &[bool]) {
        let recorded: std::collections::HashSet<u64> = self
            .model
            .recorders
            .iter()
            .flat_map(|r| r.elements_read(&self.model))
            .collect();
        self.asm
            .release_elements(&mut self.model, keep, &|id| recorded.contains(&id));
    }

    /// Rows whose residual this rank forms and counts in the norms: every equation, or
    /// with [`Driver::keep_own_rows`] its owned ones (the ranks' add up to all of them).
    pub fn rows_owned(&self) -> usize {
        match (self.linear.partitioned(), self.ranks.own_rows) {
            (Some(p), true) => p.rows_owned(),
            _ => self.neq(),
        }
    }

    /// Elements this rank holds whole: all of them, or with [`Driver::keep_own_rows`]
    /// those its rows and recorders need and every element evaluated after the build
    /// ([`Assembler::release_elements`]).
    pub fn elements_held(&self) -> usize {
        railfem_framework::released::elements_held(&self.model)
    }

    /// Stored entries of the constant stiffness this rank keeps (`M` and `C` share its
    /// pattern): all of them, or with [`Driver::keep_own_rows`] those of its columns.
    pub fn constant_entries(&self) -> usize {
        self.asm.constant_entries()
    }

    /// The most entries of the constant stiffness (and of `M`, `C`) this rank ever held:
    /// all of them after [`Driver::new`], its columns' after [`Driver::new_across_ranks`]
    /// ([`Assembler::constant_entries_built`]).
    pub fn constant_entries_built(&self) -> usize {
        self.asm.constant_entries_built()
    }

    /// `|x|` over every equation for each of `xs`, and the element-force part of the Newton
    /// check's force reference, `√(Σ_e |f_e|²)` over the variable elements
    /// ([`railfem_framework::assembly::Assembler::element_force_norm`], formed where their
    /// forces are scattered). With [`Driver::keep_own_rows`] each rank contributes its owned
    /// rows to the norms and its own sum `Σ_e |f_e|²` (every rank evaluates every variable
    /// element, [`Assembler::release_elements`]), and every rank receives the norms and the
    /// largest of the sums in one collective
    /// ([`crate::partition::Partitioned::sums_of_squares_and_max`]): all ranks reach the
    /// same decision, which is one process's. Otherwise the norms over every row, with no
    /// collective.
    pub(crate) fn force_norms(&mut self, xs: &[&[f64]]) -> (Vec<f64>, f64) {
        let local = self.asm.element_force_norm();
        let across = match (self.ranks.own_rows, self.linear.partitioned_mut()) {
            (true, Some(p)) => p.sums_of_squares_and_max(xs, Some(local * local)),
            _ => None,
        };
        match across {
            Some((sums, elem_sq)) => (
                sums.into_iter().map(f64::sqrt).collect(),
                elem_sq.max(0.0).sqrt(),
            ),
            None => (xs.iter().map(|x| norm(x)).collect(), local),
        }
    }

    /// Whether a stop was asked for (SIGINT/SIGTERM) on this process or, when the blocks are
    /// shared among ranks ([`Driver::set_exchange`]), on any of them: every rank of the job
    /// calls it at the same step and gets the same answer ([`crate::exchange::any_rank`]).
    pub fn stop_requested(&self) -> bool {
        crate::exchange::any_rank(
            self.ranks.exchange.as_deref(),
            railfem_framework::interrupt::requested(),
        )
    }

    /// Replaces the linear solver of the direct mode (the dense or sparse one the driver
    /// chose by size, [`DIRECT_DENSE_LIMIT`]); the next iteration factors anew. For
    /// comparisons of solvers on one model; no effect in the partitioned or low-rank modes.
    pub fn set_linear_solver(&mut self, solver: Box<dyn LinearSolver>) {
        self.linear.set_solver(solver);
    }

    /// The linear backend: its mode, its solver's counters and its last analysis
    /// ([`crate::linear_backend`]).
    pub fn linear(&self) -> &LinearBackend {
        &self.linear
    }

    /// Work counters of the low-rank solver, if the driver uses it.
    pub fn lowrank_stats(&self) -> Option<LowRankStats> {
        self.linear.low_rank().map(LowRank::stats)
    }

    /// Bytes the driver holds, by part (capacities, as allocated; `railfem bench`'s memory
    /// report): the assembler's ([`Assembler::memory`]), the effective matrix handed to the
    /// linear solver, the state and the step's work vectors, and the partitioned solver's
    /// ([`Partitioned::memory`]). The elements (in the model) and the direct, low-rank and
    /// top factors are not counted.
    pub fn memory(&self) -> Vec<(&'static str, usize)> {
        let vecs = |s: &State| {
            8 * (s.q.capacity()
                + s.v.capacity()
                + s.a.capacity()
                + s.f_int.capacity()
                + s.f_ext.capacity())
        };
        let w = &self.work;
        let work = [
            &w.r,
            &w.a_w,
            &w.v_w,
            &w.inertia,
            &w.damp,
            &w.q_prev,
            &w.dq,
            &w.dq_prev,
            &w.f_ref_ext,
            &w.du,
            &w.mv,
            &w.a_w_next,
            &w.inertia_next,
        ]
        .iter()
        .map(|v| 8 * v.capacity())
        .sum::<usize>()
            + vecs(&w.next)
            + 8 * w.f_int_at.capacity()
            + self.predictor.heap_bytes();
        let mut parts = self.asm.memory();
        parts.push(("effective matrix", self.linear.k_eff.heap_bytes()));
        parts.push(("state vectors", vecs(&self.state)));
        parts.push(("step work vectors", work));
        parts.push(("variable triplets", 24 * self.linear.triplets.capacity()));
        if let Some(p) = self.linear.partitioned() {
            parts.extend(p.memory());
        }
        parts
    }

    /// Stored entries of the effective matrix the driver last handed to its linear solver
    /// (across ranks, only the columns this rank's share reads).
    pub fn effective_matrix_entries(&self) -> usize {
        self.linear.k_eff.nnz()
    }

    /// Work counters and times of the partitioned solver, if the driver uses it.
    pub fn partition_stats(&self) -> Option<PartitionStats> {
        self.linear.partitioned().map(Partitioned::stats)
    }

    /// Has the partitioned solver, if the driver uses it, form its promotions in `form`
    /// from the next factorization on ([`Partitioned::set_promotion_form`]).
    pub fn set_promotion_form(&mut self, form: crate::partition::PromotionForm) {
        if let Some(p) = self.linear.partitioned_mut() {
            p.set_promotion_form(form);
        }
    }

    /// Forms and factors the effective tangent `k·K + m·M + c·C`: the pattern analysed
    /// once ([`LinearBackend::analyse`], counted as factorization time), the values filled
    /// in on it, then the numeric factorization ([`LinearBackend::factor`]).
    pub(crate) fn factor_tangent(&mut self, coef: Coefficients) -> Result<(), FemError> {
        let pattern = &self.asm.k_const;
        let symbolic = match self.linear.symbolic_of(pattern.pattern_id) {
            Some(s) => s,
            None => {
                let t0 = Instant::now();
                let s = self.linear.analyse(pattern);
                self.summary.timings.factor += t0.elapsed().as_secs_f64();
                s.map_err(|e| self.singular(e))?
            }
        };
        let ta = Instant::now();
        if !self.asm.off_pattern() {
            self.asm.effective(coef, self.linear.values_mut(&symbolic));
        } else {
            // The constant part changes only with the coefficients (and never if every mass
            // is constant); the variable elements come as triplets.
            let key = if self.asm.constant_part_is_constant() {
                coef.key()
            } else {
                [f64::NAN; 3]
            };
            if self.linear.constant_values_stale(&symbolic, key) {
                // Across ranks, only the columns this rank's blocks (and rank 0's top) read.
                let keep = self.linear.columns_read();
                let a = self.linear.constant_values_mut(key);
                match keep {
                    Some(keep) => self.asm.effective_columns(coef, &keep, a),
                    None => self.asm.effective(coef, a),
                }
            }
            self.asm.variable_triplets(coef, self.linear.triplets_mut());
            // The condensed Newton keeps every equation of the variable elements on top.
            self.linear.add_kept_on_top();
        }
        self.summary.timings.assembly += ta.elapsed().as_secs_f64();
        let t0 = Instant::now();
        let r = self.linear.factor(&symbolic, coef.key());
        self.summary.timings.factor += t0.elapsed().as_secs_f64();
        r.map_err(|e| self.singular(e))
    }

    fn solve(&mut self, b: &mut [f64]) -> Result<(), FemError> {
        self.solve_unchecked(b)?;
        if let Some(i) = b.iter().position(|x| !x.is_finite()) {
            return Err(self.non_finite_solution(i));
        }
        Ok(())
    }

    /// Solves with the current factor, leaving the finiteness of the solution to the caller
    /// ([`Driver::non_finite_solution`] names the equation).
    pub(crate) fn solve_unchecked(&mut self, b: &mut [f64]) -> Result<(), FemError> {
        let t0 = Instant::now();
        let r = self.linear.solve_in_place(b);
        self.summary.timings.solve += t0.elapsed().as_secs_f64();
        r.map_err(|e| self.singular(e))
    }

    /// The error of a solution that is not finite at equation `i`.
    pub(crate) fn non_finite_solution(&self, i: usize) -> FemError {
        let (n, d) = self.asm.dofmap.dof_of(i);
        FemError::NonFinite(format!(
            "the solution is not finite at {} (t = {} s); the model is singular or unstable there",
            self.model.dof_name(n, d),
            self.state.t
        ))
    }

    /// The largest `|r_i|` and the DOF it belongs to: over every equation, or with
    /// [`Driver::keep_own_rows`] over every rank's owned rows (one collective, so every
    /// rank of the job calls it at the same point; every rank names the equation one
    /// process would, [`Partitioned::largest_over_rows`]).
    fn largest(&mut self, r: &[f64]) -> (f64, String) {
        let across = match (self.ranks.own_rows, self.linear.partitioned_mut()) {
            (true, Some(p)) => p.largest_over_rows(r),
            _ => None,
        };
        let (i, v) = across.map(|(v, i)| (i, v)).unwrap_or_else(|| {
            r.iter().enumerate().fold((0, 0.0f64), |acc, (i, x)| {
                if x.abs() > acc.1 {
                    (i, x.abs())
                } else {
                    acc
                }
            })
        });
        let (n, d) = self.asm.dofmap.dof_of(i.min(self.neq().saturating_sub(1)));
        (v, self.model.dof_name(n, d))
    }

    /// Static equilibrium at time `t` under the loads of that time, in `steps` equal load
    /// increments, Newton–Raphson in each. Elements are committed at each converged
    /// increment. Velocities and accelerations are left at zero.
    pub fn static_solve(&mut self, t: f64, steps: usize) -> Result<usize, FemError> {
        let n = self.neq();
        let tl = Instant::now();
        self.asm.advance(&mut self.model, t, 0.0)?;
        let mut f_full = vec![0.0; n];
        self.asm.external_force(&self.model, t, 1.0, &mut f_full)?;
        self.summary.timings.loads += tl.elapsed().as_secs_f64();
        let settings = self.model.analysis.newton;
        let zero = vec![0.0; n];
        let mut total_iters = 0;
        let mut r = vec![0.0; n];
        let mut f_int = vec![0.0; n];
        let linear =
            self.asm.variable_elements().is_empty() && !self.asm.dofmap.has_finite_rotations();
        for k in 1..=steps {
            // A stop request between load steps leaves the state of the last converged one
            // (the caller records it).
            if k > 1 && railfem_framework::interrupt::requested() {
                self.state.t = t;
                self.summary.iterations += total_iters;
                return Err(FemError::InterruptedAfter {
                    after: format!(
                        "{} of {steps} load steps (load factor {})",
                        k - 1,
                        (k - 1) as f64 / steps as f64
                    ),
                });
            }
            let lam = k as f64 / steps as f64;
            let mut converged = false;
            for it in 0..=settings.max_iter {
                let ta = Instant::now();
                self.asm.update(
                    &mut self.model,
                    &self.state.q,
                    &zero,
                    &zero,
                    t,
                    0.0,
                    &mut f_int,
                    true,
                )?;
                for i in 0..n {
                    r[i] = lam * f_full[i] - f_int[i];
                }
                self.summary.timings.assembly += ta.elapsed().as_secs_f64();
                let (norms, elem) = self.force_norms(&[&r, &f_int]);
                let (rn, f_int_norm) = (norms[0], norms[1]);
                let ext = lam * norm(&f_full);
                let reference = ext.max(f_int_norm).max(elem);
                if self.trace {
                    let (v, dof) = self.largest(&r);
                    eprintln!(
                        "t = {t:.6} s, static load step {k} of {steps}, iteration {it}: |R| = {rn:.3e} N (tolerance {:.3e} = tol {:.1e} · max(|f_ext| {ext:.3e}, |f_int| {f_int_norm:.3e}, |f_e| {elem:.3e}) + abs_tol {:.1e}), largest {v:.3e} at {dof}",
                        settings.tol * reference + settings.abs_tol,
                        settings.tol,
                        settings.abs_tol
                    );
                }
                if it > 0 && rn <= settings.tol * reference + settings.abs_tol {
                    converged = true;
                    break;
                }
                if it == settings.max_iter {
                    break;
                }
                if !(linear && it > 0) {
                    self.factor_tangent(Coefficients::STATIC)?;
                    self.summary.factorizations += 1;
                }
                let mut dq = r.clone();
                self.solve(&mut dq)?;
                total_iters += 1;
                self.asm.dofmap.add_correction(&mut self.state.q, &dq);
                if linear {
                    // One exact solve; re-evaluate once to confirm.
                    continue;
                }
            }
            if !converged {
                let (v, dof) = self.largest(&r);
                return Err(FemError::Convergence(format!(
                    "{}: static load step {k} of {steps} (t = {t} s) did not converge in {} iterations; largest residual {v:.3e} at {dof}; try more `steps` or check the supports",
                    self.model.origin, settings.max_iter
                )));
            }
            self.asm.commit(&mut self.model);
        }
        self.state.t = t;
        self.state.f_int = f_int;
        self.state.f_ext = f_full;
        self.linear.invalidate();
        // A static solve moves the state without inertia: the balance starts again.
        if let Some(e) = self.energy.as_mut() {
            e.reset();
        }
        self.summary.iterations += total_iters;
        Ok(total_iters)
    }

    /// Prepares a transient: the initial static equilibrium (if asked for and there are
    /// loads at t = 0) and the initial acceleration `M·a₀ = f_ext(0) − C·v₀ − f_int(u₀)`
    /// (DOFs without mass get `a₀ = 0`).
    pub fn initialize(&mut self) -> Result<(), FemError> {
        let n = self.neq();
        let t = self.state.t;
        self.asm.advance(&mut self.model, t, 0.0)?;
        let mut f = vec![0.0; n];
        self.asm.external_force(&self.model, t, 1.0, &mut f)?;
        if self.model.analysis.initial_static && norm(&f) > 0.0 && norm(&self.state.q) == 0.0 {
            self.static_solve(t, 1)?;
        }
        let mut f_int = vec![0.0; n];
        let (q, v, a) = (
            self.state.q.clone(),
            self.state.v.clone(),
            self.state.a.clone(),
        );
        self.asm
            .update(&mut self.model, &q, &v, &a, t, 0.0, &mut f_int, false)?;
        let mut rhs = f.clone();
        for i in 0..n {
            rhs[i] -= f_int[i];
        }
        let mut cv = vec![0.0; n];
        self.asm.damping_times_add(&v, &mut cv);
        for i in 0..n {
            rhs[i] -= cv[i];
        }
        // The partitioned solver's factors (of the static tangent) are not needed again:
        // the next factorization has other coefficients and factors every block anew. Drop
        // them, and the matrix they were made from, before the mass is factored, so that two
        // sets of factors are never held at once.
        self.linear.release_factors();
        self.solve_initial_mass(&mut rhs)?;
        self.state.a = rhs;
        self.state.f_int = f_int;
        self.state.f_ext = f;
        if let Some(keep) = self.ranks.narrow_after_mass.take() {
            self.asm.keep_constant_columns(&keep);
        }
        self.asm.commit(&mut self.model);
        self.initialized = true;
        Ok(())
    }

    /// Solves `M·a = rhs` in place for the initial acceleration (`rhs` holds the force
    /// balance `f_ext − f_int − C·v` of the initial state): the constant mass matrix and the
    /// variable elements' mass at their last update, with a unit diagonal on the massless
    /// equations (whose acceleration is set to 0). The first factorization of a transient
    /// that starts from rest; `railfem check` makes it too ([`Driver::first_factorization`]).
    pub(crate) fn solve_initial_mass(&mut self, rhs: &mut [f64]) -> Result<(), FemError> {
        let n = self.neq();
        // Mass matrix with unit diagonal on massless equations; across ranks only the
        // columns this rank's share of the mass solve reads.
        let mut variable_mass = Vec::new();
        self.asm
            .variable_triplets(Coefficients::MASS, &mut variable_mass);
        // A rank keeping its own rows no longer holds the whole pattern to split: its mass
        // solver was split before ([`Driver::keep_own_rows`]).
        let mut mass_solver = match self.ranks.mass_split.take() {
            Some(p) => Some(p),
            None => self
                .asm
                .off_pattern()
                .then(|| self.new_partitioned(true, PartitionOptions::default())),
        };
        let keep = match (&self.ranks.exchange, mass_solver.as_mut()) {
            (Some(_), Some(p)) => {
                p.prepare(&self.asm.m_const);
                p.columns_read()
            }
            _ => None,
        };
        let mut m = CscMatrix::from_columns(Vec::new());
        match &keep {
            Some(keep) => self.asm.effective_columns(Coefficients::MASS, keep, &mut m),
            None => self.asm.effective(Coefficients::MASS, &mut m),
        }
        let mut massless = self.asm.massless_on_pattern();
        for &(_, j, v) in &variable_mass {
            if v != 0.0 {
                massless[j] = false;
            }
        }
        for j in 0..n {
            if massless[j] {
                if let Some(p) = m.position(j, j) {
                    m.values[p] = 1.0;
                }
                rhs[j] = 0.0;
            }
        }
        if let Some(mut p) = mass_solver {
            p.factor(&m, [0.0, 1.0, 0.0], &variable_mass)
                .map_err(|e| self.singular_mass(e))?;
            p.solve_in_place(rhs).map_err(|e| self.singular_mass(e))?;
        } else {
            let mut solver = direct_solver(n, true);
            solver.factor(&m).map_err(|e| self.singular_mass(e))?;
            solver
                .solve_in_place(rhs)
                .map_err(|e| self.singular_mass(e))?;
        }
        Ok(())
    }

    /// One attempt of the full Newton ([`crate::step_method::FullNewton`]) at a step of
    /// length `dt` from the committed state. The committed state is moved out for the
    /// attempt (and back after it) rather than copied, and the attempt's vectors are the
    /// driver's [`StepWork`], kept between steps.
    pub(crate) fn attempt_full_newton(&mut self, dt: f64) -> Result<Accepted, Attempt> {
        self.attempt_with(dt, Self::attempt_from)
    }

    /// One attempt of the lumped linear step ([`crate::lumped_step`]), as
    /// [`Driver::attempt_full_newton`] takes the committed state and the work vectors.
    pub(crate) fn attempt_lumped(&mut self, dt: f64) -> Result<Accepted, Attempt> {
        self.attempt_with(dt, Self::attempt_lumped_linear)
    }

    /// Runs `f` on the committed state moved out of the driver and the step's work vectors.
    fn attempt_with(&mut self, dt: f64, f: AttemptFn) -> Result<Accepted, Attempt> {
        let s0 = std::mem::take(&mut self.state);
        // Messages formed during the attempt name the time of the committed state.
        self.state.t = s0.t;
        let mut w = std::mem::take(&mut self.work);
        let r = f(self, dt, &s0, &mut w);
        self.state = s0;
        self.work = w;
        r.map(|(state, iterations, residual)| Accepted {
            state,
            iterations,
            residual,
        })
    }

    /// The start of a step method's attempt at a step of length `dt`
    /// ([`crate::step_method`]): the model moved to `t1 = t + dt` (carriers advanced,
    /// elements re-pick their nodes) and a copy of the committed state with `t = t1` and the
    /// external force of `t1`, to iterate on.
    pub fn begin_step(&mut self, dt: f64) -> Result<State, FemError> {
        let t1 = self.state.t + dt;
        let mut next = self.state.clone();
        next.t = t1;
        let tl = Instant::now();
        self.asm.advance(&mut self.model, t1, dt)?;
        self.asm
            .external_force(&self.model, t1, 1.0, &mut next.f_ext)?;
        self.summary.timings.loads += tl.elapsed().as_secs_f64();
        Ok(next)
    }

    /// Forms and factors the effective tangent `k·K + m·M + c·C` of the elements' last
    /// update with `coef` (the integrator's [`TimeIntegrator::coefficients`]), for a step
    /// method's next [`Driver::solve_correction`]; counted in [`RunSummary::factorizations`].
    pub fn factor_effective(&mut self, coef: Coefficients) -> Result<(), FemError> {
        self.factor_tangent(coef)?;
        self.summary.factorizations += 1;
        Ok(())
    }

    /// Solves `K_eff·x = b` in place with the last factor ([`Driver::factor_effective`]);
    /// an error naming the DOF if the solution is not finite.
    pub fn solve_correction(&mut self, b: &mut [f64]) -> Result<(), FemError> {
        self.solve(b)
    }

    /// The start of every attempt: the next state's vectors (the ones the last committed
    /// step replaced) and the work vectors at the model's length, the model advanced to
    /// `t1` and the external force of `t1` in the next state.
    pub(crate) fn begin_attempt(
        &mut self,
        t1: f64,
        dt: f64,
        w: &mut StepWork,
    ) -> Result<State, FemError> {
        let n = self.neq();
        let mut next = std::mem::take(&mut w.next);
        w.resize(n);
        w.mv_ready = false;
        w.cv_ready = false;
        for x in [
            &mut next.q,
            &mut next.v,
            &mut next.a,
            &mut next.f_int,
            &mut next.f_ext,
        ] {
            x.resize(n, 0.0);
        }
        let tl = Instant::now();
        self.asm.advance(&mut self.model, t1, dt)?;
        self.asm
            .external_force(&self.model, t1, 1.0, &mut next.f_ext)?;
        self.summary.timings.loads += tl.elapsed().as_secs_f64();
        Ok(next)
    }

    fn attempt_from(
        &mut self,
        dt: f64,
        s0: &State,
        w: &mut StepWork,
    ) -> Result<(State, usize, f64), Attempt> {
        let n = self.neq();
        let t1 = s0.t + dt;
        let mut next = self.begin_attempt(t1, dt, w)?;
        let StepWork {
            r,
            a_w,
            v_w,
            inertia,
            damp,
            q_prev,
            dq,
            dq_prev,
            f_ref_ext,
            du,
            mv,
            mv_ready,
            a_w_next,
            inertia_next,
            inertia_ready,
            f_int_at,
            ..
        } = w;
        let af = self.integrator.force_weight();
        let settings = self.model.analysis.newton;
        let linear =
            self.asm.variable_elements().is_empty() && !self.asm.dofmap.has_finite_rotations();
        let coef = self.integrator.coefficients(dt);
        let State {
            q,
            v,
            a,
            f_int,
            f_ext,
            ..
        } = &mut next;
        q.copy_from_slice(&s0.q);
        // A linear model is solved exactly by one correction from any start (and its first
        // residual reuses the committed internal force, formed at `q_n`): no predictor.
        if let (false, Predictor::Increment, Some((dt_prev, inc))) =
            (linear, settings.predictor, self.predictor.last())
        {
            // `dq` is free until the first solve writes it.
            let scale = dt / dt_prev;
            for (d, x) in dq.iter_mut().zip(inc) {
                *d = x * scale;
            }
            self.asm.dofmap.add_correction(q, dq);
        }
        let mut iters = 0;
        let mut disp_ok = false;
        // Backtracking: when a full Newton step raises the residual (an active set that
        // cycles — contact points entering and leaving, stick and slide flipping), go back
        // along the step by halves before solving again.
        // (A linear model takes one correction and never goes back.)
        if !linear {
            q_prev.copy_from_slice(&s0.q);
        }
        let mut have_dq_prev = false;
        let mut rn_prev = f64::INFINITY;
        let mut halvings = 0;
        for i in 0..n {
            f_ref_ext[i] = (1.0 - af) * f_ext[i] + af * s0.f_ext[i];
        }
        // The step's increment: q − q_n, and on finite-rotation triples the incremental
        // rotation vector log(R·R_nᵀ) (see the module documentation); without such triples
        // it is formed inline, as it always was.
        let finite = self.asm.dofmap.has_finite_rotations();
        // The first iteration with the contact's statuses of the last converged step
        // (`FirstActiveSet`); released before the second evaluation (and by
        // the step method whatever the outcome).
        self.hold_first_iteration(linear);
        for it in 0..=settings.max_iter {
            if finite {
                self.asm.dofmap.increment(&s0.q, q, du);
            }
            if it == 1 {
                self.release_first_iteration();
            }
            if linear && it > 0 {
                // The solved state: its velocity and acceleration (no residual follows),
                // and the weighted acceleration a next step of the same Δt starts with
                // (its first iterate is this q: Δu = 0).
                let ig = &*self.integrator;
                let du = Increment::Between { q, q0: &s0.q };
                ig.kinematics(dt, 0, du, &s0.v, &s0.a, v, a);
                ig.next_at_rest(dt, v, a, a_w_next, None);
            } else {
                let du = if finite {
                    Increment::Given(du)
                } else {
                    Increment::Between { q, q0: &s0.q }
                };
                // The residual's inertia and damping act at the intermediate times.
                let out = Trial { v, a, a_w, v_w };
                self.integrator.trial(dt, 0, du, &s0.v, &s0.a, out);
            }
            let ta = Instant::now();
            let need_tangent = !linear
                && match settings.kind {
                    NewtonKind::Full => true,
                    NewtonKind::Modified => it == 0,
                    NewtonKind::Initial => !self.linear.has_factor(),
                };
            if linear && it > 0 {
                // No variable element to update: K·q, M·v and the next inertia force in
                // one pass.
                self.asm
                    .linear_state_products((q, v, a_w_next), (f_int, mv, inertia_next));
                *mv_ready = true;
                // The next step re-forms masses that change between steps: its inertia
                // force is formed anew then.
                *inertia_ready = self.asm.mass_is_constant();
                f_int_at.clear();
                f_int_at.extend_from_slice(q);
                // A linear model was solved exactly by the one correction: v, a and f_int
                // are updated above; the inertia and damping products of a residual check
                // would only confirm round-off.
                self.summary.timings.assembly += ta.elapsed().as_secs_f64();
                next.t = t1;
                return Ok((next, iters, rn_prev));
            }
            // Residual at the intermediate times. A linear model's first iterate is the
            // committed displacement, whose internal force the state holds (formed by the
            // same product, so the same to the bit): only M·a and C·v are formed.
            if linear && it == 0 && *f_int_at == s0.q {
                f_int.copy_from_slice(&s0.f_int);
                if *inertia_ready && a_w == a_w_next {
                    // M·a_w was formed with the last step's K·q (the same product).
                    std::mem::swap(inertia, inertia_next);
                    self.asm.damping_force(v_w, damp);
                } else {
                    self.asm.inertia_damping((a_w, v_w), (inertia, damp));
                }
                *inertia_ready = false;
            } else {
                self.asm.update_transient(
                    &mut self.model,
                    (q, v, a),
                    (a_w, v_w),
                    t1,
                    dt,
                    (f_int, inertia, damp),
                    need_tangent || it == 0,
                )?;
            }
            for i in 0..n {
                r[i] = f_ref_ext[i]
                    - inertia[i]
                    - damp[i]
                    - ((1.0 - af) * f_int[i] + af * s0.f_int[i]);
            }
            zero_held(&self.frozen_rows, r);
            // With reduced blocks the test sees the residual in their coordinates
            // (`partition/reduced.rs`); the solve takes `r` as it is.
            let projected = self.reduced_residual(r);
            let r_test: &[f64] = projected.as_deref().unwrap_or(r);
            self.summary.timings.assembly += ta.elapsed().as_secs_f64();
            // A linear model takes its one correction whatever the force check says: the
            // check's reference is formed only for a nonlinear model or the trace.
            let check = !linear || self.trace;
            // Across ranks the norms are one collective, which every rank enters.
            let (rn, parts) = if check || self.ranks.own_rows {
                let (v, elem) = self.force_norms(&[r_test, f_int, inertia]);
                let parts = if check {
                    [norm(f_ref_ext), v[1], v[2], elem]
                } else {
                    [0.0; 4]
                };
                (v[0], parts)
            } else {
                (norm(r_test), [0.0; 4])
            };
            let reference = parts.iter().fold(0.0f64, |m, x| m.max(*x));
            let force_ok = rn <= settings.tol * reference + settings.abs_tol;
            if self.trace {
                let (v, dof) = self.largest(r);
                eprintln!(
                    "t = {t1:.6} s, dt = {dt:.3e} s, iteration {it}: |R| = {rn:.3e} N (tolerance {:.3e} = tol {:.1e} · max(|f_ext| {:.3e}, |f_int| {:.3e}, |M·a| {:.3e}, |f_e| {:.3e}) + abs_tol {:.1e}), largest {v:.3e} at {dof}",
                    settings.tol * reference + settings.abs_tol,
                    settings.tol,
                    parts[0],
                    parts[1],
                    parts[2],
                    parts[3],
                    settings.abs_tol
                );
            }
            if it > 0 && (linear || (force_ok && disp_ok)) {
                next.t = t1;
                return Ok((next, iters, rn));
            }
            if !linear
                && it >= 2
                && it < settings.max_iter
                && rn > rn_prev
                && halvings < 3
                && have_dq_prev
            {
                halvings += 1;
                for d in dq_prev.iter_mut() {
                    *d *= 0.5;
                }
                q.copy_from_slice(q_prev);
                self.asm.dofmap.add_correction(q, dq_prev);
                continue;
            }
            if it == settings.max_iter {
                let (val, dof) = self.largest(r);
                return Err(Attempt::NotConverged {
                    residual: val,
                    dof,
                    iterations: iters,
                });
            }
            if !rn.is_finite() {
                return Err(Attempt::Fatal(FemError::NonFinite(format!(
                    "residual is not finite at t = {t1} s"
                ))));
            }
            // Factor when needed.
            let valid = self
                .linear
                .is_factored(coef.key(), self.asm.k_const.pattern_id);
            let refactor = match (linear, settings.kind) {
                (true, _) => !valid,
                (false, NewtonKind::Full) => true,
                (false, NewtonKind::Modified) => it == 0 || !valid,
                (false, NewtonKind::Initial) => !valid,
            };
            if refactor {
                self.factor_tangent(coef)?;
                self.summary.factorizations += 1;
            }
            // The residual is solved in place (it is formed anew before it is read again).
            std::mem::swap(r, dq);
            self.solve(dq)?;
            iters += 1;
            if !linear {
                q_prev.copy_from_slice(q);
            }
            self.asm.dofmap.add_correction(q, dq);
            if !linear {
                let dn = norm(dq);
                disp_ok = dn <= settings.tol * norm(q) + settings.disp_tol;
                if self.trace {
                    let (v, dof) = self.largest(dq);
                    eprintln!(
                        "t = {t1:.6} s, correction {iters}: |dq| = {dn:.3e} (tolerance {:.3e}), largest {v:.3e} at {dof}",
                        settings.tol * norm(q) + settings.disp_tol
                    );
                }
            }
            std::mem::swap(dq, dq_prev);
            have_dq_prev = true;
            rn_prev = rn;
            halvings = 0;
        }
        unreachable!("the loop returns")
    }

    /// Zeroes the increment predictor's entries on the `held` rows ([`crate::window`]).
    pub(crate) fn zero_held_increment(&mut self, held: &[bool]) {
        if let Some(inc) = self.predictor.increment_mut() {
            zero_held(held, inc);
        }
    }

    /// Advances one step of length `dt`, halving it up to `max_cuts` times when Newton does
    /// not converge. On final failure the committed state is the last converged one.
    pub fn step(&mut self, dt: f64) -> Result<StepReport, FemError> {
        if !self.initialized {
            self.initialize()?;
        }
        self.ensure_step_method();
        let max_cuts = self.model.analysis.newton.max_cuts;
        let mut report = StepReport::default();
        self.substep(dt, 0, max_cuts, &mut report)?;
        self.summary.steps += 1;
        self.summary.iterations += report.iterations;
        self.summary.cuts += report.cuts;
        Ok(report)
    }

    /// A step of `dt` as the integrator's stages ([`TimeIntegrator::stages`]), each a
    /// Newton solve committed on its own. A stage that does not converge is cut: the rest
    /// of the step, from the last committed state, is taken as two half steps (each again
    /// every stage), up to `max_cuts` halvings deep.
    fn substep(
        &mut self,
        dt: f64,
        depth: usize,
        max_cuts: usize,
        rep: &mut StepReport,
    ) -> Result<(), FemError> {
        let t_end = self.state.t + dt;
        for stage in 0..self.integrator.stages() {
            self.integrator.begin_stage(stage, dt, &self.state);
            let h = self.integrator.stage_length(stage, dt);
            if !self.stage(h, depth, max_cuts, rep)? {
                rep.cuts += 1;
                let rest = if stage == 0 { dt } else { t_end - self.state.t };
                self.substep(rest / 2.0, depth + 1, max_cuts, rep)?;
                return self.substep(rest / 2.0, depth + 1, max_cuts, rep);
            }
        }
        Ok(())
    }

    /// One stage of length `dt`: its attempt (and, at the last halving, the held retry),
    /// committed when it converges (`Ok(true)`); reverted when it does not (`Ok(false)`,
    /// the caller cuts; an error once `max_cuts` halvings are spent).
    fn stage(
        &mut self,
        dt: f64,
        depth: usize,
        max_cuts: usize,
        rep: &mut StepReport,
    ) -> Result<bool, FemError> {
        let mut method = match self.method.take() {
            Some(m) => m,
            None => self.default_step_method(),
        };
        let mut outcome = method.attempt(self, dt);
        // The smallest sub-step failed: the method's last resort (the held active set,
        // crate::held_active_set); when that fails too, the first attempt's failure stands.
        let mut held_note = String::new();
        if let (true, Err(Attempt::NotConverged { iterations, .. })) = (depth >= max_cuts, &outcome)
        {
            let spent = *iterations;
            self.asm.revert(&mut self.model);
            self.linear.invalidate();
            match method.last_resort(self, dt) {
                None => {}
                Some(Ok(a)) => {
                    self.summary.held += 1;
                    outcome = Ok(Accepted {
                        iterations: spent + a.iterations,
                        ..a
                    });
                }
                Some(Err(f)) => {
                    held_note = format!("; {}", f.why);
                    match f.attempt {
                        Attempt::NotConverged { iterations, .. } => {
                            rep.iterations += iterations;
                        }
                        fatal => outcome = Err(fatal),
                    }
                }
            }
        }
        self.method = Some(method);
        match outcome {
            Ok(Accepted {
                state: s,
                iterations: it,
                residual: res,
            }) => {
                self.asm.commit(&mut self.model);
                if let Some(h) = self.held_rows.as_mut() {
                    h.committed();
                }
                if let Some(e) = self.energy.as_mut() {
                    // A linear step formed its state's M·v with its K·q.
                    let mv = self.work.mv_ready.then_some(&self.work.mv[..]);
                    let cv = self.work.cv_ready.then_some(&mut self.work.cv);
                    // A rank forming its own rows sums the balance over them, in block
                    // order across the ranks.
                    let ranks = self
                        .linear
                        .partitioned_mut()
                        .filter(|_| self.ranks.own_rows);
                    let held = self.held_rows.as_ref().and_then(|h| h.rows());
                    e.record(
                        &self.asm,
                        &self.model,
                        &self.state,
                        &s,
                        mv,
                        cv,
                        ranks,
                        held.as_deref(),
                    );
                }
                // The increment for the next step's predictor, in last step's vector.
                self.predictor.committed(
                    self.model.analysis.newton.predictor,
                    &self.asm.dofmap,
                    dt,
                    &self.state.q,
                    &s.q,
                );
                self.work.mv_ready = false;
                self.work.cv_ready = false;
                // The replaced state's vectors hold the next attempt's state.
                self.work.next = std::mem::replace(&mut self.state, s);
                rep.iterations += it;
                rep.residual = res;
                Ok(true)
            }
            Err(Attempt::Fatal(e)) => {
                self.asm.revert(&mut self.model);
                Err(e)
            }
            Err(Attempt::NotConverged {
                residual,
                dof,
                iterations,
            }) => {
                self.asm.revert(&mut self.model);
                self.linear.invalidate();
                rep.iterations += iterations;
                if depth >= max_cuts {
                    return Err(FemError::Convergence(format!(
                        "{}: step at t = {:.6} s did not converge after {depth} halvings (dt down to {dt:.3e} s); largest residual {residual:.3e} at {dof}; the last converged state is t = {:.6} s{held_note}",
                        self.model.origin,
                        self.state.t + dt,
                        self.state.t
                    )));
                }
                Ok(false)
            }
        }
    }

    /// The lowest `n` natural frequencies and modes of `K·φ = ω²·M·φ` about the reference
    /// state (K the assembled tangent at zero displacement, M the mass), by subspace
    /// iteration on the sparse factor of K ([`crate::modal`]).
    pub fn modes(&mut self, n: usize) -> Result<crate::modal::Modes, FemError> {
        let z = vec![0.0; self.neq()];
        let mut f = vec![0.0; self.neq()];
        self.asm.advance(&mut self.model, self.state.t, 0.0)?;
        self.asm
            .update(&mut self.model, &z, &z, &z, self.state.t, 0.0, &mut f, true)?;
        let k = self.whole_matrix(Coefficients::STATIC);
        let m = self.whole_matrix(Coefficients::MASS);
        crate::modal::lowest_modes(&k, &m, n, &crate::modal::ModalOptions::default()).map_err(|e| {
            match e {
                crate::modal::ModalError::Solver(s) => self.singular(s),
                crate::modal::ModalError::Interrupted { iterations } => FemError::InterruptedAfter {
                    after: format!("{iterations} subspace iterations of the modal analysis; no modes written"),
                },
                other => FemError::input(&self.model.origin, format!("modal analysis: {other}")),
            }
        })
    }

    /// The linear system about the reference state at the current time: the whole tangent
    /// stiffness `K` at zero displacement, velocity and acceleration (constant and variable
    /// elements), the constant mass `M` and damping `C` (Rayleigh included), and the
    /// external load vector at full load factor (`railfem matrices`, docs/matrices.md).
    pub fn reference_system(&mut self) -> Result<ReferenceSystem, FemError> {
        let n = self.neq();
        let z = vec![0.0; n];
        let mut f_int = vec![0.0; n];
        let t = self.state.t;
        self.asm.advance(&mut self.model, t, 0.0)?;
        self.asm
            .update(&mut self.model, &z, &z, &z, t, 0.0, &mut f_int, true)?;
        let mut load = vec![0.0; n];
        self.asm.external_force(&self.model, t, 1.0, &mut load)?;
        Ok(ReferenceSystem {
            stiffness: self.whole_matrix(Coefficients::STATIC),
            mass: self.asm.m_const.clone(),
            damping: self.asm.c_const.clone(),
            load,
        })
    }

    /// `k·K + m·M + c·C` of every element in one matrix. In the partitioned mode the
    /// variable elements are kept off the global pattern; they are added here as triplets
    /// (modal analysis needs the whole matrix, whichever solver the run uses).
    fn whole_matrix(&self, coef: Coefficients) -> CscMatrix {
        let mut a = self.asm.k_const.zeros_like();
        self.asm.effective(coef, &mut a);
        if !self.asm.off_pattern() {
            return a;
        }
        let mut t = Vec::with_capacity(a.nnz());
        for j in 0..a.n {
            for p in a.col_ptr[j]..a.col_ptr[j + 1] {
                t.push((a.row_idx[p], j, a.values[p]));
            }
        }
        self.asm.variable_triplets(coef, &mut t);
        CscMatrix::from_triplets(a.n, &t)
    }

    /// Writes frequencies and mode shapes as CSV: one row per active nodal DOF, columns
    /// `node,dof` and one per mode; a header row of frequencies (Hz) first.
    pub fn write_modes(&self, modes: &crate::modal::Modes, path: &Path) -> Result<(), FemError> {
        // Shapes are M-normalized (φᵀMφ = 1): a translation in m/√kg, a rotation in rad/√kg.
        let mut s = String::from("node [-],dof [-]");
        for (i, w) in modes.omega.iter().enumerate() {
            s.push_str(&format!(
                ",mode{}_{:.6e}Hz [m/√kg or rad/√kg]",
                i + 1,
                w / (2.0 * std::f64::consts::PI)
            ));
        }
        s.push('\n');
        for (ni, nd) in self.model.nodes.iter().enumerate() {
            for d in self.asm.dofmap.active[ni].iter() {
                s.push_str(&format!("{},{}", nd.id, d.name()));
                for j in 0..modes.omega.len() {
                    let col: Vec<f64> = (0..self.neq()).map(|r| modes.shapes[(r, j)]).collect();
                    s.push_str(&format!(",{:.9e}", self.asm.dofmap.value(&col, ni, d)));
                }
                s.push('\n');
            }
        }
        std::fs::write(path, s).map_err(|e| FemError::output(path, e))
    }

    /// Kinetic energy `½·vᵀ·M·v` (J).
    pub fn kinetic_energy(&self) -> f64 {
        let mut mv = vec![0.0; self.neq()];
        self.asm.mass_times(&self.state.v, &mut mv);
        0.5 * mv
            .iter()
            .zip(&self.state.v)
            .map(|(a, b)| a * b)
            .sum::<f64>()
    }

    /// Strain energy of the linear elements `½·qᵀ·K·q` (J).
    pub fn linear_strain_energy(&self) -> f64 {
        let mut kq = vec![0.0; self.neq()];
        self.asm.k_const.mul_vec(&self.state.q, &mut kq);
        0.5 * kq
            .iter()
            .zip(&self.state.q)
            .map(|(a, b)| a * b)
            .sum::<f64>()
    }

    /// Writes the energy rows of the run to `dir/energy.csv` (nothing if accounting is off).
    pub fn write_energy(&self, dir: &Path) -> Result<(), FemError> {
        match &self.energy {
            Some(e) => e.write_csv(&dir.join(railfem_framework::outputs::ENERGY_CSV)),
            None => Ok(()),
        }
    }

    /// Displacement (m, rad) of DOF `dof` of node user id `node` in the committed state, in
    /// the node's axes; `None` for an unknown node.
    pub fn displacement(&self, node: u64, dof: railfem_framework::Dof) -> Option<f64> {
        let i = self.model.node(node)?;
        Some(self.asm.dofmap.value(&self.state.q, i, dof))
    }

    /// Velocity (m/s, rad/s) of DOF `dof` of node user id `node` in the committed state.
    pub fn velocity(&self, node: u64, dof: railfem_framework::Dof) -> Option<f64> {
        let i = self.model.node(node)?;
        Some(self.asm.dofmap.value(&self.state.v, i, dof))
    }

    /// Acceleration (m/s², rad/s²) of DOF `dof` of node user id `node` in the committed
    /// state.
    pub fn acceleration(&self, node: u64, dof: railfem_framework::Dof) -> Option<f64> {
        let i = self.model.node(node)?;
        Some(self.asm.dofmap.value(&self.state.a, i, dof))
    }

    /// The value of output `name` of the element with user id `element`
    /// ([`railfem_framework::Element::output_names`]) in the committed state, as a recorder
    /// would write it (a linear element is first brought to that state); `None` for an
    /// unknown element or output.
    pub fn element_output(&mut self, element: u64, name: &str) -> Result<Option<f64>, FemError> {
        let Some(ei) = self.model.elements.iter().position(|e| e.id == element) else {
            return Ok(None);
        };
        let names = self.model.elements[ei].element.output_names();
        let Some(k) = names.iter().position(|n| n == name) else {
            return Ok(None);
        };
        let s = &self.state;
        self.asm
            .refresh_constant(&mut self.model, ei, s.t, &s.q, &s.v, &s.a)?;
        let mut out = Vec::new();
        self.model.elements[ei].element.outputs(&mut out);
        Ok(out.get(k).copied())
    }

    /// Writes the committed state (every active nodal DOF) as CSV:
    /// `node [-],dof [-],disp [m or rad],vel [m/s or rad/s],acc [m/s² or rad/s²]`.
    pub fn write_state(&self, path: &Path) -> Result<(), FemError> {
        let mut s = String::from(
            "node [-],dof [-],disp [m or rad],vel [m/s or rad/s],acc [m/s² or rad/s²]\n",
        );
        for (i, nd) in self.model.nodes.iter().enumerate() {
            for d in self.asm.dofmap.active[i].iter() {
                s.push_str(&format!(
                    "{},{},{:.12e},{:.12e},{:.12e}\n",
                    nd.id,
                    d.name(),
                    self.asm.dofmap.value(&self.state.q, i, d),
                    self.asm.dofmap.value(&self.state.v, i, d),
                    self.asm.dofmap.value(&self.state.a, i, d)
                ));
            }
        }
        std::fs::write(path, s).map_err(|e| FemError::output(path, e))
    }

    /// Runs the model's analysis, writing its recorders into `out` (if given).
    /// `progress` is called with the fraction done after each step. A transient stops at
    /// the end of a step when [`railfem_framework::interrupt`] is requested: recorders
    /// flushed, [`FemError::Interrupted`] returned with the time reached.
    pub fn run(
        &mut self,
        out: Option<&Path>,
        progress: &mut dyn FnMut(f64),
    ) -> Result<RunSummary, FemError> {
        self.run_keeping(out, false, progress).map(|(s, _)| s)
    }

    /// Records the current state at time `t` into `rec`, when there are recorders.
    fn record_state(&mut self, rec: &mut Option<Recorders>, t: f64) -> Result<(), FemError> {
        if let Some(r) = rec.as_mut() {
            let s = &self.state;
            r.record(&mut self.model, &self.asm, t, &s.q, &s.v, &s.a)?;
        }
        Ok(())
    }

    /// [`Driver::run`], and when `keep`, every recorder's rows in memory as well (the
    /// exact values; [`railfem_framework::recording::History`]), whether or not `out` is
    /// given. Recording is the same whether rows go to files, memory or both, so a run
    /// keeping rows takes the same steps as `railfem run`.
    pub fn run_keeping(
        &mut self,
        out: Option<&Path>,
        keep: bool,
        progress: &mut dyn FnMut(f64),
    ) -> Result<(RunSummary, Vec<History>), FemError> {
        self.run_observing(out, keep, progress, &mut |_, _| {})
    }

    /// [`Driver::run_keeping`], and `observe(model, t)` after every committed transient step
    /// (each step, whether recorded or not): a caller that wants extremes over the whole run
    /// (`railfem study`) reads the elements' outputs there without recording every row.
    pub fn run_observing(
        &mut self,
        out: Option<&Path>,
        keep: bool,
        progress: &mut dyn FnMut(f64),
        observe: &mut dyn FnMut(&Model, f64),
    ) -> Result<(RunSummary, Vec<History>), FemError> {
        self.run_preparing(out, keep, progress, observe, &mut |_| Ok(()))
    }

    /// [`Driver::run_observing`], and `before(driver)` before every transient step, after
    /// the initialization (a model file's activity window moves there: `railfem run`). An
    /// error there ends the run as a failed step does.
    pub fn run_preparing(
        &mut self,
        out: Option<&Path>,
        keep: bool,
        progress: &mut dyn FnMut(f64),
        observe: &mut dyn FnMut(&Model, f64),
        before: &mut dyn FnMut(&mut Driver) -> Result<(), FemError>,
    ) -> Result<(RunSummary, Vec<History>), FemError> {
        let start = Instant::now();
        let spec = self.model.analysis.clone();
        let mut rec = if out.is_some() || keep {
            Some(Recorders::open_with(&self.model, out, keep)?)
        } else {
            None
        };
        match spec.kind {
            AnalysisKind::Static => {
                let solved = self.static_solve(0.0, spec.steps);
                // Stopped between load steps: the state of the last one goes on file too.
                let stopped = matches!(solved, Err(FemError::InterruptedAfter { .. }));
                if solved.is_ok() || stopped {
                    self.record_state(&mut rec, 0.0)?;
                    if let (true, Some(r)) = (stopped, rec.as_mut()) {
                        r.finish()?;
                    }
                }
                solved?;
                progress(1.0);
            }
            AnalysisKind::Transient => {
                self.initialize()?;
                self.record_state(&mut rec, 0.0)?;
                let nsteps = (spec.duration / spec.dt - 1e-9).ceil().max(1.0) as usize;
                for k in 1..=nsteps {
                    let dt = if k == nsteps {
                        (spec.duration - self.state.t).max(spec.dt * 1e-9)
                    } else {
                        spec.dt
                    };
                    if let Err(e) = before(self).and_then(|()| self.step(dt).map(|_| ())) {
                        if let (Some(r), Some(dir)) = (rec.as_mut(), out) {
                            let _ = r.finish();
                            let _ = self
                                .write_state(&dir.join(railfem_framework::outputs::LAST_STATE_CSV));
                            let _ = self.write_energy(dir);
                        }
                        return Err(e);
                    }
                    // An interrupt stops the run at the end of this step, with this step
                    // on file: the last state recorded, the recorders flushed (whole
                    // lines), then say when.
                    observe(&self.model, self.state.t);
                    // Every rank sees the same answer (a stop seen by one rank alone
                    // would leave the others waiting in the next step's collectives).
                    let stop = self.stop_requested() && k < nsteps;
                    if k % spec.record_every == 0 || k == nsteps || stop {
                        self.record_state(&mut rec, self.state.t)?;
                    }
                    progress(k as f64 / nsteps as f64);
                    if stop {
                        if let Some(r) = rec.as_mut() {
                            r.finish()?;
                        }
                        if let Some(dir) = out {
                            self.write_energy(dir)?;
                        }
                        return Err(FemError::Interrupted { t: self.state.t });
                    }
                }
            }
            AnalysisKind::Modal => {
                let modes = self.modes(spec.modes)?;
                if let Some(dir) = out {
                    self.write_modes(&modes, &dir.join(railfem_framework::outputs::MODES_CSV))?;
                }
                progress(1.0);
            }
        }
        if let Some(r) = rec.as_mut() {
            r.finish()?;
        }
        if let (Some(dir), AnalysisKind::Transient) = (out, spec.kind) {
            self.write_energy(dir)?;
        }
        let st = self.linear.solver_stats();
        self.summary.symbolic = st.symbolic_analyses;
        self.summary.wall = start.elapsed().as_secs_f64();
        let kept = rec.map(Recorders::histories).unwrap_or_default();
        Ok((self.summary, kept))
    }
}

impl StepMethod<Driver> for FullNewton {
    fn name(&self) -> &'static str {
        "full Newton"
    }

    fn attempt(&mut self, d: &mut Driver, dt: f64) -> Result<Accepted, Attempt> {
        let r = d.attempt_full_newton(dt);
        d.release_first_iteration();
        r
    }
}

impl Driver {
    /// The method the driver picks for a model ([`crate::step_method`]): the lumped linear
    /// step where it applies ([`Driver::lumped_linear_applies`]), the condensed Newton with
    /// the partitioned solver and variable elements ([`Driver::set_condense_residual`] on), else
    /// full Newton; each with the held active set's retry.
    pub fn default_step_method(&self) -> Box<dyn StepMethod<Driver>> {
        let inner: Box<dyn StepMethod<Driver>> = if self.lumped_linear_applies() {
            Box::new(LumpedLinear)
        } else if self.choice.condense_residual && self.may_condense() {
            Box::new(CondensedNewton::default())
        } else {
            Box::new(FullNewton)
        };
        Box::new(HeldActiveSet::wrap(inner))
    }

    /// Replaces the step method (before the first step, or between steps). The driver's
    /// own methods come wrapped in [`HeldActiveSet`]; wrap `method` too to keep that
    /// retry.
    pub fn set_step_method(&mut self, method: Box<dyn StepMethod<Driver>>) {
        self.method = Some(method);
    }

    /// Whether a linear model with a diagonal mass and no damping takes its step in three
    /// fused passes ([`crate::lumped_step`]; default `true`); `false` sends it through the
    /// general attempt (same answers to the bit; for comparisons). Takes effect when the
    /// step method is picked: before the first step.
    pub fn set_lumped_step(&mut self, on: bool) {
        self.choice.lumped_step = on;
    }

    /// Whether Newton iterates only on the top system of the partitioned solver, the block
    /// interiors condensed out of the residual too ([`crate::condensed`]; default `true`);
    /// `false` keeps the full-residual Newton (same answers to round-off; for
    /// comparisons). Takes effect when the step method is picked: before the first step.
    pub fn set_condense_residual(&mut self, on: bool) {
        self.choice.condense_residual = on;
    }

    /// The name of the step method the driver runs with (its pick if none was given yet).
    pub fn step_method_name(&mut self) -> &'static str {
        self.ensure_step_method();
        self.method.as_ref().map_or("", |m| m.name())
    }

    /// Picks the default step method if none was picked or given yet.
    pub(crate) fn ensure_step_method(&mut self) {
        if self.method.is_none() {
            self.method = Some(self.default_step_method());
        }
    }

    /// Whether the condensed Newton can apply to any step of this driver (the partitioned
    /// solver, full Newton from the committed state, variable elements): the driver then
    /// picks it ([`Driver::default_step_method`]); each step checks the rest.
    pub(crate) fn may_condense(&self) -> bool {
        self.linear.partitioned().is_some()
            && self.model.analysis.newton.predictor.is_previous()
            && self.model.analysis.newton.kind == NewtonKind::Full
            && !self.asm.variable_elements().is_empty()
    }
}

/// An attempt on the committed state moved out of the driver and the step's work vectors
/// ([`Driver::attempt_with`]): the state, the iterations and the residual norm.
type AttemptFn =
    fn(&mut Driver, f64, &State, &mut StepWork) -> Result<(State, usize, f64), Attempt>;

/// Zeroes the held rows of a residual (their values are reactions): nothing when `held`
/// is empty, so that a run without a window takes exactly the arithmetic it always took.
fn zero_held(held: &[bool], r: &mut [f64]) {
    if held.is_empty() {
        return;
    }
    for (ri, &h) in r.iter_mut().zip(held) {
        if h {
            *ri = 0.0;
        }
    }
}

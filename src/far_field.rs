//! The reduced far field of `train-bridge` (docs/reduced-far-field.md): the blocks of
//! the partitioned solver far from the train run in their Craig–Bampton form
//! ([`crate::solvers::reduced::blocks`]), and switch to full form as the train comes
//! within reach and back once it has left.
//!
//! **Which blocks, when.** The reach is the activity window's
//! ([`crate::train_window::settings`] with its defaults: `ahead` metres before the
//! train's front, `behind` after its rear), and the structure's ends count as the
//! activity window's do ([`end_bounds`]): an abutment within
//! [`END_REACH`](crate::solvers::window::END_REACH) times `ahead` of the train is a second
//! train, so that no block between the train and that abutment, nor within `ahead` beyond
//! it, is reduced. Before each step a block whose stations meet
//! `[min(rear − behind, keep_from), max(front + ahead, join_to)]` is full, any other
//! reduced, with `[keep_from, join_to]` the ends' bounds for the two abutments
//! ([`Viaduct::abutments`]). A reduced block carries only the motion below its cut-off,
//! so it would change the waves on their way from the train to a near abutment and back
//! (`docs/reduced-far-field.md`, "Which blocks"). A block that the train
//! stood on at the start is never reduced: its static state (the reduction's origin, the
//! state after the preload) carries the train's weight, which is gone once the train has
//! left. Each block is reduced once, when it is first switched to reduced form, with its
//! modes up to the cut-off ([`FarFieldOptions::cutoff_hz`], or the library's rule from
//! `Δt`, [`CutOffRule`]): a run whose far field never leaves the train's reach (a viaduct
//! shorter than the ends' reach, or a short run) makes no reduction. A block whose modes
//! do not converge stays full.
//!
//! **Blocks at span joints.** The reduced far field gives the partitioned solver its
//! blocks by station ([`block_cuts`], [`Driver::cut_blocks_at`]): `g` spans each from a
//! joint, `g` the partition's block size over a span's equations, and the approaches cut
//! with the same pitch. Such blocks are translated copies of each other, except next to
//! the abutments and at the bridge's ends, so a handful of reductions serve them all:
//! a block congruent to one already reduced ([`CONGRUENT`],
//! [`crate::solvers::reduced::congruent`]) takes its basis, renumbered.
//!
//! **Energy.** Each switch to reduced form removes `E_res`, the energy of the motion the
//! kept modes do not describe; the far field sums them ([`FarFieldStats::e_res`]).
//!
//! The viaduct alone under a ground motion is built by
//! [`crate::train_bridge::viaduct_under_ground_motion`]: the
//! track on the bridge and its approaches, no train, no gravity, so that the model is
//! linear and starts at rest — the case on which a driver with reduced blocks is checked
//! against the library's own march of the same reduced model (`tests/far_field.rs`).

use crate::framework::FemError;
use crate::solvers::partition::ReducedBasis;
use crate::solvers::reduced::cutoff::CutOffRule;
use crate::solvers::window::end_bounds;
use crate::solvers::Driver;
use crate::train_window::{settings, train_extent, Viaduct, WindowOptions, WindowTrack};
use std::sync::Arc;
use std::time::Instant;

/// Blocks whose `K` and `M` agree entry by entry to this fraction of the largest entry,
/// after the map between their nodes, share one reduction
/// ([`crate::solvers::reduced::congruent`]): the rounding of element matrices formed at
/// translated coordinates, far below the reduction's own error.
pub const CONGRUENT: f64 = 1e-12;

/// How the blocks far from the train are solved.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum FarFieldChoice {
    /// Every block in full (the answers of a run without the option, bit for bit).
    #[default]
    Full,
    /// Blocks out of the train's reach in their Craig–Bampton form.
    Reduced(FarFieldOptions),
}

/// The user's settings of the reduced far field; `None`: the default.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct FarFieldOptions {
    /// The modes' cut-off frequency (Hz); default: [`CutOffRule`] from `Δt`.
    pub cutoff_hz: Option<f64>,
    /// The reach (m) ahead of the train's front and behind its rear within which blocks
    /// are full; default: the activity window's ([`crate::train_window::settings`]).
    pub reach: Option<f64>,
}

/// Where the far field's settings were given, for the one-line errors of [`parse`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FarFieldKeys {
    /// The error's origin.
    pub origin: &'static str,
    /// The mode's name, the cut-off's and the reach's.
    pub names: [&'static str; 3],
}

/// `railfem train-bridge`'s options.
pub const COMMAND_LINE: FarFieldKeys = FarFieldKeys {
    origin: "command line",
    names: ["--far-field", "--far-field-cutoff", "--far-field-reach"],
};

/// A study plan's keys of the train–bridge case.
pub const STUDY: FarFieldKeys = FarFieldKeys {
    origin: "study case",
    names: ["`far_field`", "`far_field_cutoff`", "`far_field_reach`"],
};

/// The far field's choice: `full` (the default) or `reduced`, with the cut-off (Hz, a
/// positive number) and the reach (m, ≥ 0), both with `reduced` only; refused in one line
/// naming the key and the fix.
pub fn parse(
    keys: FarFieldKeys,
    mode: Option<&str>,
    cutoff_hz: Option<f64>,
    reach: Option<f64>,
) -> Result<FarFieldChoice, FemError> {
    let [m, c, r] = keys.names;
    let bad = |msg: String| Err(FemError::input(keys.origin, msg));
    if let Some(f) = cutoff_hz.filter(|f| !(f.is_finite() && *f > 0.0)) {
        return bad(format!("{c} {f}: give a positive frequency (Hz)"));
    }
    if let Some(d) = reach.filter(|d| !(d.is_finite() && *d >= 0.0)) {
        return bad(format!("{r} {d}: give a distance ≥ 0 m"));
    }
    let options = FarFieldOptions { cutoff_hz, reach };
    match mode {
        Some("reduced") => Ok(FarFieldChoice::Reduced(options)),
        Some("full") | None if options == FarFieldOptions::default() => Ok(FarFieldChoice::Full),
        Some("full") | None => bad(format!(
            "{c} and {r} set the reduced far field; add {m} reduced, or drop them"
        )),
        Some(other) => bad(format!("{m} {other}: give full or reduced")),
    }
}

/// Counters of a reduced far field over a run.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct FarFieldStats {
    /// Blocks that may be reduced, and all blocks.
    pub candidates: usize,
    /// All blocks of the partitioned solver.
    pub blocks: usize,
    /// Distinct reductions made (blocks with equal matrices share one).
    pub reductions: usize,
    /// Blocks whose reduction failed (their modes did not converge): they stay full.
    pub failed: usize,
    /// Modes kept, summed over the blocks reduced so far.
    pub modes: usize,
    /// Seconds spent cutting the blocks and reducing (the reductions are made at the
    /// blocks' first switches to reduced form).
    pub setup_seconds: f64,
    /// Block-steps reduced, and block-steps in all.
    pub reduced_block_steps: usize,
    /// See [`FarFieldStats::reduced_block_steps`].
    pub block_steps: usize,
    /// Switches to reduced form, and back to full.
    pub to_reduced: usize,
    /// See [`FarFieldStats::to_reduced`].
    pub to_full: usize,
    /// `E_res` summed over the switches to reduced form (J).
    pub e_res: f64,
}

/// A block's reduced basis: never reduced (under the train at the start, or its modes did
/// not converge), not made yet, or made.
enum Basis {
    Never,
    Pending,
    Made(Arc<ReducedBasis>),
}

/// The reduced far field of a run ([`open`]).
pub struct FarField {
    bases: Vec<Basis>,
    /// The reductions made, each with the block it was made on (for congruent blocks).
    made: Vec<(usize, Arc<ReducedBasis>)>,
    /// The modes' cut-off (rad/s).
    cutoff: f64,
    extents: Vec<[f64; 2]>,
    reduced: Vec<bool>,
    origin: Vec<f64>,
    reach: [f64; 2],
    track: WindowTrack,
    stats: FarFieldStats,
}

/// The stations where the far field cuts the model into blocks: every `group` spans
/// from the viaduct's start, its end, and on with the same pitch over each approach
/// until `x_range` (the model's extent in `x`, m). Blocks of `group` spans starting at a
/// joint are translated copies of each other (one reduction serves them); so are the
/// approaches' stretches away from their ends.
pub fn block_cuts(v: Viaduct, group: usize, x_range: [f64; 2]) -> Vec<f64> {
    let pitch = group.max(1) as f64 * v.span;
    let [_, end] = v.abutments();
    let mut cuts: Vec<f64> = (0..)
        .map(|k| v.start - k as f64 * pitch)
        .take_while(|&x| x > x_range[0])
        .collect();
    cuts.extend(
        (1..)
            .map(|k| v.start + k as f64 * pitch)
            .take_while(|&x| x < end),
    );
    cuts.extend(
        (0..)
            .map(|k| end + k as f64 * pitch)
            .take_while(|&x| x < x_range[1]),
    );
    cuts.sort_by(f64::total_cmp);
    cuts
}

/// The far field of a run on `driver` (after its preload and initialization): `None`
/// for [`FarFieldChoice::Full`]. Refused (an input error) without the partitioned solver,
/// across ranks, and with the activity window (`window`: it holds blocks the far field
/// would reduce).
pub fn open(
    driver: &mut Driver,
    choice: FarFieldChoice,
    track: &WindowTrack,
    dt: f64,
    window: bool,
) -> Result<Option<FarField>, FemError> {
    let FarFieldChoice::Reduced(options) = choice else {
        return Ok(None);
    };
    let o = "command line";
    if window {
        return Err(FemError::input(
            o,
            "--far-field reduced with the activity window: the window holds the blocks the far field reduces; give --window off",
        ));
    }
    match driver.partition_stats() {
        None => {
            return Err(FemError::input(
                o,
                "--far-field reduced runs blocks of the partitioned solver in reduced form, and this model uses another solver; give --solver partitioned",
            ))
        }
        Some(p) if p.ranks > 1 => {
            return Err(FemError::input(
                o,
                "--far-field reduced is not shared among MPI ranks; run one process",
            ))
        }
        Some(_) => {}
    }
    let t0 = Instant::now();
    let cutoff = options
        .cutoff_hz
        .map_or(CutOffRule::default().omega(dt), |f| {
            2.0 * std::f64::consts::PI * f
        });
    // Blocks cut at span joints, as many spans each as make about the partition's own
    // block size (its level sets' mean), so that congruent blocks share a reduction.
    let viaduct = track.viaduct;
    let level_sets = driver.prepare_blocks().map_err(|m| FemError::input(o, m))?;
    let per_block = driver
        .partition_stats()
        .map_or(0, |p| p.interior_equations / level_sets.max(1));
    let (mut x_lo, mut x_hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for n in &driver.model.nodes {
        x_lo = x_lo.min(n.position.x);
        x_hi = x_hi.max(n.position.x);
    }
    let on_bridge = (0..driver.neq())
        .filter(|&g| {
            let x = driver.model.nodes[driver.asm.dofmap.dof_of(g).0].position.x;
            x >= viaduct.start && x < viaduct.abutments()[1]
        })
        .count();
    let per_span = on_bridge / viaduct.spans.max(1);
    let group = (per_block as f64 / per_span.max(1) as f64).round().max(1.0) as usize;
    let cuts = block_cuts(viaduct, group, [x_lo, x_hi]);
    let nb = driver
        .cut_blocks_at(&cuts)
        .map_err(|m| FemError::input(o, m))?;
    let w = settings(
        track,
        WindowOptions {
            ahead: options.reach,
            ..Default::default()
        },
    );
    // An explicit reach holds behind the train too (the window's never goes below the
    // rail's basin).
    let behind = options.reach.unwrap_or(w.behind);
    let [rear0, front0] = train_extent(track, driver.state.t);
    let interiors = driver.partition_interiors();
    let mut extents = Vec::with_capacity(nb);
    let mut bases = Vec::with_capacity(nb);
    let mut stats = FarFieldStats {
        blocks: nb,
        ..Default::default()
    };
    for all in &interiors {
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for &i in all {
            let x = driver.model.nodes[driver.asm.dofmap.dof_of(i).0].position.x;
            lo = lo.min(x);
            hi = hi.max(x);
        }
        extents.push([lo, hi]);
        // Under the train at the start: its origin carries the train's weight.
        if hi >= rear0 && lo <= front0 {
            bases.push(Basis::Never);
        } else {
            stats.candidates += 1;
            bases.push(Basis::Pending);
        }
    }
    stats.setup_seconds = t0.elapsed().as_secs_f64();
    Ok(Some(FarField {
        bases,
        made: Vec::new(),
        cutoff,
        extents,
        reduced: vec![false; nb],
        origin: driver.state.q.clone(),
        reach: [w.ahead, behind],
        track: *track,
        stats,
    }))
}

impl FarField {
    /// Switches the blocks for the train's position at the driver's time (call before
    /// each step): full within reach, reduced out of it (module documentation).
    pub fn update(&mut self, driver: &mut Driver) -> Result<(), FemError> {
        let [from, to] = self.full_stretch(driver.state.t);
        for b in 0..self.bases.len() {
            if matches!(self.bases[b], Basis::Never) {
                continue;
            }
            let [lo, hi] = self.extents[b];
            let near = hi >= from && lo <= to;
            match (near, self.reduced[b]) {
                (true, true) => {
                    driver
                        .restore_block(b)
                        .map_err(|m| FemError::input("far field", m))?;
                    self.reduced[b] = false;
                    self.stats.to_full += 1;
                }
                (false, false) => {
                    let Some(basis) = self.basis(driver, b) else {
                        continue;
                    };
                    let e = driver
                        .reduce_block(b, basis, &self.origin)
                        .map_err(|m| FemError::input("far field", m))?;
                    self.reduced[b] = true;
                    self.stats.to_reduced += 1;
                    self.stats.e_res += e;
                }
                _ => {}
            }
        }
        self.stats.block_steps += self.bases.len();
        self.stats.reduced_block_steps += self.reduced.iter().filter(|&&r| r).count();
        Ok(())
    }

    /// Block `b`'s reduced basis, made at its first use: a congruent block's, renumbered,
    /// or its own reduction; `None` when its modes do not converge (it then stays full).
    fn basis(&mut self, driver: &mut Driver, b: usize) -> Option<Arc<ReducedBasis>> {
        if let Basis::Made(basis) = &self.bases[b] {
            return Some(basis.clone());
        }
        let t0 = Instant::now();
        let shared = self.made.iter().find_map(|(k, basis)| {
            let map = driver.block_congruence(*k, b, CONGRUENT)?;
            Some(if map.is_identity() {
                basis.clone()
            } else {
                Arc::new(basis.mapped(&map))
            })
        });
        let basis = match shared {
            Some(basis) => Some(basis),
            None => match driver
                .block_reduction(b, self.cutoff)
                .expect("the far field runs on the partitioned solver")
            {
                Ok(cb) => {
                    let basis = Arc::new(ReducedBasis {
                        psi: cb.psi,
                        phi: cb.phi,
                    });
                    self.made.push((b, basis.clone()));
                    self.stats.reductions = self.made.len();
                    Some(basis)
                }
                Err(e) => {
                    // The block stays full: slower, never wrong.
                    self.stats.failed += 1;
                    self.stats.candidates -= 1;
                    if self.stats.failed == 1 {
                        eprintln!("far field: block {b} stays full ({e})");
                    }
                    None
                }
            },
        };
        self.bases[b] = match &basis {
            Some(basis) => {
                self.stats.modes += basis.phi.ncols();
                Basis::Made(basis.clone())
            }
            None => Basis::Never,
        };
        self.stats.setup_seconds += t0.elapsed().as_secs_f64();
        basis
    }

    /// The stretch `[from, to]` (m) whose blocks are full at time `t` (s): the train's
    /// extent widened by the reach, `[rear − behind, front + ahead]`, and by what the
    /// abutments within [`END_REACH`](crate::solvers::window::END_REACH) reaches of the
    /// train keep ([`end_bounds`], module documentation).
    pub fn full_stretch(&self, t: f64) -> [f64; 2] {
        let [rear, front] = train_extent(&self.track, t);
        let [ahead, behind] = self.reach;
        let abutments = self.track.viaduct.abutments();
        let [keep_from, join_to] = end_bounds(&abutments, rear, front, ahead);
        [(rear - behind).min(keep_from), (front + ahead).max(join_to)]
    }

    /// Whether each block of the partitioned solver is in reduced form now.
    pub fn reduced_blocks(&self) -> &[bool] {
        &self.reduced
    }

    /// Each block's `[first, last]` station (m).
    pub fn extents(&self) -> &[[f64; 2]] {
        &self.extents
    }

    /// The counters so far.
    pub fn stats(&self) -> FarFieldStats {
        self.stats
    }
}

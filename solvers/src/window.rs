//! The activity window: the blocks of the partitioned solver far from a moving load are
//! held at their state while the load is elsewhere, so that a step's per-block passes
//! follow the train, not the whole structure.
//!
//! **What a held block is.** A block ([`crate::partition`]) is *held* (frozen) while its
//! interior equations `I_h` are prescribed at their present values: `q_{I_h}` does not
//! change, `v_{I_h} = a_{I_h} = 0` (set so when the block is held, and kept so by the
//! integrator, whose kinematics of a zero increment from a state at rest are zero), and the
//! residual rows `r_{I_h}` are reactions, left out of the convergence test
//! (the driver's `zero_held`). The solves skip the block's forward and back passes
//! ([`crate::partition::Partitioned::set_frozen_blocks`]).
//!
//! **What is exact.** Every equation that is not held — the active blocks' interiors, all
//! separators and carriages, hence both rails across the boundary of a held block — is
//! solved to the driver's tolerance with the true internal forces: a boundary row's
//! residual contains `K_{B I_h}·q_{I_h}` with the held values, so the coupling of the held
//! block to its active neighbours (the rails' continuity, the slab and girder across the
//! cut) is that of the model, not an approximation of it. The top system keeps the held
//! block's condensed interface stiffness `A_BB − A_{B I}·A_{II}⁻¹·A_{I B}` (it is not
//! refactored when the window moves); that is the Newton tangent only, and changes the
//! iterates' path, not the state they converge to.
//!
//! **What is approximate.** Only the held interiors' motion: (1) a block ahead of the load
//! is held at its initial (static, self-weight) state until the load comes within the
//! window's distance, so the small quasi-static deflection that the approaching load would
//! cause there (the rail's, decaying as `e^{−βx}` with `β = (k/(4·EI))^{1/4}`, Hetényi's
//! beam on elastic foundation), and the pier's share of the next span's load, are not
//! followed; (2) a block behind the load is held once no load is on it any more and its
//! velocity norm `|v_I|` has fallen below `tolerance` times the largest it reached while
//! active: the kinetic energy removed is then at most about `tolerance²` of the block's
//! largest (exactly so for a mass matrix proportional to the identity), and its
//! displacement is kept as it was, not returned to rest. Both errors act on the load only
//! through the held block's boundary, a distance (the window) away; the train–bridge
//! case measures them against the full model (`tests/train_window.rs`, "The activity
//! window" in `docs/performance.md`).
//!
//! A held block is a fixed wall for the waves the load sends along the structure; the
//! [`absorb`] layer damps them over the last stretch before it, so that little comes back
//! ([`ActivityWindow::set_absorbing_layer`]). That damping is the third approximation:
//! the active structure there is damped more than the model is, far from the load.
//!
//! **The structure's ends.** An end of the structure (the end of the modelled track, or a
//! bridge's abutment, where the track leaves the bridge for the ground) sends the waves
//! the load sends towards it back, in the full model too. A held block between the load
//! and that end would stop them on their way out (and the layer would absorb them), so the
//! window would miss what the full model's end returns; and a layer next to the end would
//! damp the end itself. While an end lies within [`END_REACH`] times the reach of the
//! load, the window treats it as a second load: no block between the load and that end,
//! nor within the reach beyond it, is held (ahead, they join; behind, they are not held
//! behind). The ends are the first and last station of the blocks, and the stations the
//! case adds ([`ActivityWindow::set_ends`]). On a long structure this changes only the
//! first and last stretches of a crossing; a bridge shorter than that distance is never
//! held between its abutments (`docs/activity-window.md`, "The structure's ends").
//!
//! The window itself ([`ActivityWindow`]) knows only stations: each block's extent along
//! the track and the load's extent `[rear, front]`; the case maps nodes to stations.

pub mod absorb;
#[cfg(test)]
mod tests;

use crate::driver::Driver;
use absorb::{AbsorbingLayer, LayerSettings};
use railfem_framework::error::FemError;

/// An end of the structure within this multiple of the reach ([`WindowSettings::ahead`])
/// of the load keeps every block between the load and that end, and within the reach
/// beyond it, active (module documentation, "The structure's ends").
pub const END_REACH: f64 = 3.0;

/// The stretch that the structure's `ends` (m) keep active around a load spanning
/// `[rear, front]` with the reach `ahead` (m), as `[keep_from, join_to]` (module
/// documentation, "The structure's ends").
///
/// The load itself keeps active what lies within `ahead` of it. An end `e` ahead of the
/// load (`e ≥ front`) with `e − front ≤ `[`END_REACH`]`·ahead` counts as a second load
/// at `e`: it keeps active what lies up to `ahead` beyond it, and everything between
/// the front and `e`, the waves' path to the end and back. So the stretch ahead reaches to
/// `join_to = max(front + ahead, max_e (e + ahead))` over such ends. Behind the load,
/// mirrored: an end `e ≤ rear` with `rear − e ≤ END_REACH·ahead` keeps active what
/// reaches past `e − ahead`, so `keep_from = min_e (e − ahead)` over such ends, or `+∞`
/// when there is none (the ends then keep nothing behind). An end farther away changes
/// nothing. `END_REACH` = 3 is measured, not derived (`docs/design-decisions.md`, "The
/// activity window: on by default, ends kept active").
///
/// The activity window ([`ActivityWindow::update`]) lets a block ahead join once its
/// first station is at most `join_to`, and holds none behind whose last station is at
/// least `keep_from`; the reduced far field of the train–bridge case keeps a block full
/// while it meets `[min(rear − behind, keep_from), max(front + ahead, join_to)]`.
pub fn end_bounds(ends: &[f64], rear: f64, front: f64, ahead: f64) -> [f64; 2] {
    let end_reach = END_REACH * ahead;
    let join_to = ends
        .iter()
        .filter(|&&e| e >= front && e - front <= end_reach)
        .fold(front + ahead, |m, &e| m.max(e + ahead));
    let keep_from = ends
        .iter()
        .filter(|&&e| e <= rear && rear - e <= end_reach)
        .fold(f64::INFINITY, |m, &e| m.min(e - ahead));
    [keep_from, join_to]
}

/// Settings of the activity window.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WindowSettings {
    /// A block joins when its nearest station comes within this distance ahead of the
    /// load's front (m).
    pub ahead: f64,
    /// A block left behind is held only once its last station is this far behind the
    /// load's rear (m): the rail's deflection basin behind the last wheel.
    pub behind: f64,
    /// A block behind is held once `|v_I| ≤ tolerance·max |v_I|` over its active time.
    pub tolerance: f64,
}

/// Where a block is in the window's life.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Phase {
    /// Held at its initial state: the load has not come within `ahead`.
    Ahead,
    /// Solved; the largest velocity norm of its interior so far.
    Active {
        /// Largest `|v_I|` seen while active.
        peak: f64,
    },
    /// Held at the state it was left in.
    Behind,
}

/// Counters of a window over a run.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct WindowStats {
    /// Block-steps held (each step, the blocks held during it).
    pub held_block_steps: usize,
    /// Block-steps in all.
    pub block_steps: usize,
    /// Blocks released from ahead, in all.
    pub joined: usize,
    /// Blocks held behind, in all.
    pub left: usize,
}

/// The window over the blocks of a driver's partitioned solver (module documentation).
#[derive(Debug, Clone)]
pub struct ActivityWindow {
    settings: WindowSettings,
    /// Each block's `[first, last]` station (m).
    extents: Vec<[f64; 2]>,
    /// The structure's ends: its first and last station over every block, and those the
    /// case added (m).
    ends: Vec<f64>,
    /// Each block's interior equations.
    interiors: Vec<Vec<usize>>,
    /// The station of each of them (m).
    stations: Vec<Vec<f64>>,
    /// The top equations coupled to a block (the separators), and their stations (m).
    separators: (Vec<usize>, Vec<f64>),
    /// The absorbing layer at the window's edges ([`absorb`]; none unless set).
    layer: AbsorbingLayer,
    phases: Vec<Phase>,
    /// The flags last handed to the driver (held blocks stay at rest by themselves).
    held: Vec<bool>,
    stats: WindowStats,
}

impl ActivityWindow {
    /// The window for `driver`'s blocks, each node's station given by `station(node
    /// index)`. The driver must have its partitioned solver's structure (after
    /// [`Driver::initialize`]); every block starts [`Phase::Ahead`] and the first
    /// [`ActivityWindow::update`] releases those within reach.
    pub fn new(
        driver: &Driver,
        settings: WindowSettings,
        station: impl Fn(usize) -> f64,
    ) -> Result<ActivityWindow, String> {
        let p = driver
            .linear
            .partitioned()
            .filter(|p| p.block_count() > 0)
            .ok_or("the activity window needs the partitioned solver (solver = \"partitioned\") with at least one block")?;
        let mut extents = Vec::with_capacity(p.block_count());
        let mut interiors = Vec::with_capacity(p.block_count());
        let mut stations = Vec::with_capacity(p.block_count());
        for b in 0..p.block_count() {
            let all = p.block_interior(b);
            let at: Vec<f64> = all
                .iter()
                .map(|&i| station(driver.asm.dofmap.dof_of(i).0))
                .collect();
            let lo = at.iter().copied().fold(f64::INFINITY, f64::min);
            let hi = at.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            extents.push([lo, hi]);
            interiors.push(all.to_vec());
            stations.push(at);
        }
        let mut top: Vec<usize> = (0..p.block_count())
            .flat_map(|b| p.block_boundary(b).iter().copied())
            .collect();
        top.sort_unstable();
        top.dedup();
        let at = top
            .iter()
            .map(|&i| station(driver.asm.dofmap.dof_of(i).0))
            .collect();
        let separators = (top, at);
        let phases = vec![Phase::Ahead; extents.len()];
        let ends = extents
            .iter()
            .fold([f64::INFINITY, f64::NEG_INFINITY], |e, b| {
                [e[0].min(b[0]), e[1].max(b[1])]
            })
            .to_vec();
        Ok(ActivityWindow {
            settings,
            extents,
            ends,
            interiors,
            stations,
            separators,
            layer: AbsorbingLayer::default(),
            phases,
            held: Vec::new(),
            stats: WindowStats::default(),
        })
    }

    /// Sets the absorbing layer at the window's edges ([`absorb`]; `None`: none, a held
    /// block then reflects what reaches it). Before the first [`ActivityWindow::update`].
    pub fn set_absorbing_layer(&mut self, settings: Option<LayerSettings>) {
        self.layer = AbsorbingLayer::new(settings);
    }

    /// Adds `stations` (m) to the structure's ends (module documentation, "The structure's
    /// ends"): where the structure changes so that it sends waves back, such as a bridge's
    /// abutments. Before the first [`ActivityWindow::update`].
    pub fn set_ends(&mut self, stations: &[f64]) {
        self.ends.extend_from_slice(stations);
    }

    /// The window's settings.
    pub fn settings(&self) -> WindowSettings {
        self.settings
    }

    /// The absorbing layer.
    pub fn absorbing_layer(&self) -> &AbsorbingLayer {
        &self.layer
    }

    /// Each block's phase.
    pub fn phases(&self) -> &[Phase] {
        &self.phases
    }

    /// Each block's `[first, last]` station (m).
    pub fn extents(&self) -> &[[f64; 2]] {
        &self.extents
    }

    /// The counters so far.
    pub fn stats(&self) -> WindowStats {
        self.stats
    }

    /// Moves the window to a load spanning stations `[rear, front]` and holds or releases
    /// the driver's blocks accordingly (call before each step). A block ahead joins when
    /// `first ≤ front + ahead`; an active block is held behind when `last < rear − behind`
    /// and its velocity norm has decayed below the tolerance. While an end of the structure
    /// ahead of `front` is within [`END_REACH`]`·ahead` of it, every block up to `ahead`
    /// beyond that end joins; while one behind `rear` is within that of it, no block
    /// reaching past `ahead` before it is held. A held block that the last factorization
    /// found a variable element on (a wheel reached it: the window is too short) is an
    /// input error naming the fix, never a silently wrong step.
    pub fn update(&mut self, driver: &mut Driver, rear: f64, front: f64) -> Result<(), FemError> {
        let WindowSettings {
            ahead,
            behind,
            tolerance,
        } = self.settings;
        let p = driver
            .linear
            .partitioned()
            .expect("checked at construction");
        if let Some(b) =
            (0..self.phases.len()).find(|&b| p.block_frozen(b) && p.block_has_promoted(b))
        {
            return Err(FemError::input(
                "activity window",
                format!(
                    "a wheel reached held block {b} (stations {:.3} to {:.3} m) at t = {} s; give a larger --window-ahead",
                    self.extents[b][0], self.extents[b][1], driver.state.t
                ),
            ));
        }
        let v = &driver.state.v;
        let [keep_from, join_to] = end_bounds(&self.ends, rear, front, ahead);
        for (b, phase) in self.phases.iter_mut().enumerate() {
            let [lo, hi] = self.extents[b];
            if *phase == Phase::Ahead && lo <= join_to {
                *phase = Phase::Active { peak: 0.0 };
                self.stats.joined += 1;
            }
            if let Phase::Active { peak } = phase {
                let norm = self.interiors[b]
                    .iter()
                    .map(|&i| v[i] * v[i])
                    .sum::<f64>()
                    .sqrt();
                *peak = peak.max(norm);
                if hi < rear - behind && hi < keep_from && norm <= tolerance * *peak {
                    *phase = Phase::Behind;
                    self.stats.left += 1;
                }
            }
        }
        let frozen: Vec<bool> = self
            .phases
            .iter()
            .map(|ph| !matches!(ph, Phase::Active { .. }))
            .collect();
        self.stats.block_steps += frozen.len();
        self.stats.held_block_steps += frozen.iter().filter(|&&f| f).count();
        if frozen == self.held {
            return Ok(());
        }
        driver
            .hold_blocks(&frozen)
            .map_err(|m| FemError::input("activity window", m))?;
        self.held = frozen;
        self.move_layer(driver)
    }

    /// Moves the absorbing layer to the held regions' edges (after a change of the held
    /// set): ahead, the first station of the blocks still ahead; behind, the last station
    /// of the blocks held behind.
    fn move_layer(&mut self, driver: &mut Driver) -> Result<(), FemError> {
        let edge = |phase: Phase, pick: fn(&[f64; 2]) -> f64, join: fn(f64, f64) -> f64| {
            self.phases
                .iter()
                .zip(&self.extents)
                .filter(|(p, _)| **p == phase)
                .map(|(_, e)| pick(e))
                .reduce(join)
        };
        let ahead = edge(Phase::Ahead, |e| e[0], f64::min);
        let behind = edge(Phase::Behind, |e| e[1], f64::max);
        let blocks: Vec<(&[usize], &[f64])> = self
            .interiors
            .iter()
            .zip(&self.stations)
            .map(|(i, s)| (&i[..], &s[..]))
            .collect();
        let active: Vec<bool> = self.held.iter().map(|h| !h).collect();
        self.layer
            .apply(
                driver,
                &blocks,
                &active,
                (&self.separators.0, &self.separators.1),
                ahead,
                behind,
            )
            .map_err(|m| FemError::input("activity window", m))
    }
}

impl Driver {
    /// Whether the condensed Newton's passes leave out the deep held rows
    /// ([`crate::held_rows`]; default `true`): `false` forms every row, as before (the
    /// same state to round-off of the norms: a comparison switch, no model key). Takes
    /// effect at the next change of the held blocks.
    pub fn set_skip_held_rows(&mut self, on: bool) {
        self.skip_held_rows = on;
    }

    /// Equations the step's passes leave out now: the deep held rows once
    /// [`crate::held_rows::SETTLE_STEPS`] steps have been committed since the held set
    /// changed, `0` otherwise.
    pub fn rows_left_out(&self) -> usize {
        self.held_rows
            .as_ref()
            .filter(|h| h.rows().is_some())
            .map_or(0, |h| h.deep_count())
    }

    /// Holds the partitioned solver's blocks flagged in `frozen` (one flag per block) and
    /// releases the others (module documentation): their interiors' velocities and
    /// accelerations are set to zero, the increment predictor's entries too, and their
    /// residual rows become reactions. Nothing flagged: the driver is exactly as without a
    /// window.
    pub fn hold_blocks(&mut self, frozen: &[bool]) -> Result<(), String> {
        let n = self.neq();
        let p = self
            .linear
            .partitioned_mut()
            .ok_or("held blocks need the partitioned solver")?;
        p.set_frozen_blocks(frozen)?;
        if !frozen.iter().any(|&f| f) {
            self.frozen_rows.clear();
            self.held_rows = None;
            return Ok(());
        }
        let mut rows = vec![false; n];
        for (b, _) in frozen.iter().enumerate().filter(|(_, &f)| f) {
            for &i in p.block_interior(b) {
                rows[i] = true;
            }
        }
        for i in (0..n).filter(|&i| rows[i]) {
            self.state.v[i] = 0.0;
            self.state.a[i] = 0.0;
        }
        self.zero_held_increment(&rows);
        self.held_rows = self
            .skip_held_rows
            .then(|| crate::held_rows::HeldRows::new(&rows, &self.asm.k_const));
        self.frozen_rows = rows;
        Ok(())
    }
}

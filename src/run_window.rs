//! The activity window of a model file's transient (`[analysis.window]`, `railfem run`):
//! what moves in the model and where it is along the track at each step
//! ([`MovingExtent`]), whether the window applies to the model ([`plan`]), and the window
//! that follows what moves ([`RunWindow`]). What a held block is, what stays exact and
//! what is approximated is `railfem_solvers::window`; the default reach, tolerance and
//! absorbing layer are those of `railfem train-bridge --window` ([`crate::train_window`]:
//! the layer's thickness and damping come from [`crate::train_window::layer`], and the
//! window takes it as `train-bridge`'s does, through `ActivityWindow::set_absorbing_layer`).
//!
//! **What moves.** Three things carry load along a model: the carriers' nodes (a
//! `[[vehicle]]`'s bodies and wheelsets, at their reference positions at time `t`), the
//! `moving_force` loads (at `start + speed·t` along their path), and the elements whose
//! connectivity changes (wheels and moving oscillators: the nodes of the structure they
//! are attached to now, the rail or beam nodes under the contact). A node of the structure
//! is one that an element of fixed connectivity is attached to, so a moving oscillator's
//! own mass node, which rides with it and is attached to it alone, does not count where it
//! was defined. The extent `[rear, front]` is the smallest and largest X coordinate of
//! these points: a block's extent is that of its nodes' X coordinates too
//! (`ActivityWindow::new`), so the window measures both on the same axis. That is a
//! distance along the track only on a straight track along +X, which [`plan`] checks for
//! the carriers and the moving forces; a moving oscillator on a beam path is followed
//! through the nodes under it, and one that goes back along X stops the run with an error
//! (the window would have held the blocks ahead of it as left behind).
//!
//! **Where it does not apply.** The window holds blocks of the partitioned solver on one
//! process, without ground motion (which moves the whole structure), and needs something
//! moving along +X on a straight line. Elsewhere `mode = "on"` is refused in one line
//! naming the file, the key and the fix; `mode = "auto"` stays off and the run's summary
//! says why, once.

use crate::framework::analysis::{WindowMode, WindowSpec};
use crate::framework::loads::Load;
use crate::framework::model::Model;
use crate::framework::FemError;
use crate::solvers::window::absorb::LayerSettings;
use crate::solvers::window::{ActivityWindow, WindowSettings, WindowStats};
use crate::solvers::Driver;
use crate::train_window::LayerOptions;

/// Where the model's moving things are: the carriers, the moving forces and the elements
/// of changing connectivity (module documentation).
#[derive(Debug, Clone, PartialEq)]
pub struct MovingExtent {
    /// Per node index: whether an element of fixed connectivity is attached to it.
    structure: Vec<bool>,
    /// Indices of the elements whose connectivity may change.
    movers: Vec<usize>,
}

impl MovingExtent {
    /// The moving things of `model`.
    pub fn new(model: &Model) -> MovingExtent {
        let mut structure = vec![false; model.nodes.len()];
        let mut movers = Vec::new();
        for (i, e) in model.elements.iter().enumerate() {
            if e.element.properties().connectivity_may_change {
                movers.push(i);
            } else {
                for c in e.element.connectivity() {
                    structure[c.node] = true;
                }
            }
        }
        MovingExtent { structure, movers }
    }

    /// Whether nothing in `model` moves: no carried node, no moving force, no element of
    /// changing connectivity.
    pub fn is_empty(&self, model: &Model) -> bool {
        self.movers.is_empty()
            && model.carriers.iter().all(|c| c.nodes.is_empty())
            && !model
                .loads
                .iter()
                .any(|l| matches!(l, Load::MovingForce(_)))
    }

    /// The smallest and largest X coordinate (m) of what moves at time `t` (s): the
    /// carried nodes' reference positions, the moving forces' points (on a path along +X,
    /// `x = x_first + start + speed·t`, before and after the path as well) and the
    /// structure nodes the moving elements are attached to. `None` when nothing is found.
    pub fn extent(&self, model: &Model, t: f64) -> Option<[f64; 2]> {
        let mut lo = f64::INFINITY;
        let mut hi = f64::NEG_INFINITY;
        let mut take = |x: f64| {
            lo = lo.min(x);
            hi = hi.max(x);
        };
        for c in &model.carriers {
            for cn in &c.nodes {
                take(c.reference(cn, t).position.x);
            }
        }
        for l in &model.loads {
            if let Load::MovingForce(f) = l {
                if let Some(first) = f.ends.first() {
                    take(first.0.x + f.start + f.speed * t);
                }
            }
        }
        for &i in &self.movers {
            for c in model.elements[i].element.connectivity() {
                if self.structure.get(c.node).copied().unwrap_or(false) {
                    take(model.nodes[c.node].position.x);
                }
            }
        }
        (lo <= hi).then_some([lo, hi])
    }
}

/// Why the window does not apply to a model, and what to write instead of `mode = "on"`.
#[derive(Debug, Clone, PartialEq)]
pub struct NotApplicable {
    /// What keeps it from applying.
    pub reason: String,
    /// The fix of an explicit `mode = "on"`.
    pub fix: String,
}

impl NotApplicable {
    fn new(reason: String, fix: &str) -> NotApplicable {
        NotApplicable {
            reason,
            fix: fix.to_string(),
        }
    }
}

const OFF: &str = "set mode = \"off\"";

/// Why the window does not apply to the model of `driver` (after `Driver::new`, and after
/// the blocks were shared among the ranks when they are), or `None` when it does.
pub fn not_applicable(driver: &Driver, movers: &MovingExtent) -> Option<NotApplicable> {
    let model = &driver.model;
    if let Some(i) = model
        .loads
        .iter()
        .position(|l| matches!(l, Load::GroundMotion { .. }))
    {
        return Some(NotApplicable::new(
            format!("under ground motion (load[{i}]) the whole structure moves"),
            OFF,
        ));
    }
    match driver.partition_stats() {
        None => {
            return Some(NotApplicable::new(
                format!(
                    "the window holds blocks of the partitioned solver, and `solver` = \"{}\" does not run it for this model's {} equations",
                    model.analysis.solver.name(),
                    driver.neq()
                ),
                "set [analysis] solver = \"partitioned\", or mode = \"off\"",
            ))
        }
        Some(p) if p.ranks > 1 => {
            return Some(NotApplicable::new(
                format!(
                    "the partitioned solver's blocks are shared among {} MPI ranks",
                    p.ranks
                ),
                "run on one process, or set mode = \"off\"",
            ))
        }
        Some(_) => {}
    }
    if movers.is_empty(model) {
        return Some(NotApplicable::new(
            "nothing in the model moves (no [[vehicle]], moving element or moving_force load) for the window to follow".to_string(),
            OFF,
        ));
    }
    straight_along_x(model).map(|why| NotApplicable::new(why, OFF))
}

/// Largest sideways or vertical drift (m per m of path) of a path counted as running
/// along +X: round-off of the alignment's positions.
const STRAIGHT: f64 = 1e-9;

/// Why the carriers' paths or the moving forces' paths do not run straight along +X, if
/// they do not (module documentation).
fn straight_along_x(model: &Model) -> Option<String> {
    let why = "the window maps nodes to stations by their X coordinate, on a straight track along +X only";
    for c in model.carriers.iter().filter(|c| !c.nodes.is_empty()) {
        let len = c.path.length();
        // Every metre, and both ends: the alignment's segments are metres long at least.
        let n = len.ceil().max(1.0) as usize;
        for k in 0..=n {
            let p = c.path.at(len * k as f64 / n as f64);
            let off = (p.tangent - nalgebra::Vector3::x()).norm();
            if p.curvature != 0.0 || off.is_nan() || off > STRAIGHT {
                return Some(format!(
                    "`{}` moves along a path that curves or turns away from +X at station {:.1} m; {why}",
                    c.name, p.station
                ));
            }
        }
    }
    for (i, l) in model.loads.iter().enumerate() {
        if let Load::MovingForce(f) = l {
            let bent = f.ends.iter().any(|(a, b)| {
                let d = b - a;
                !(d.x > 0.0 && d.y.abs() <= STRAIGHT * d.x && d.z.abs() <= STRAIGHT * d.x)
            });
            if bent || f.speed < 0.0 {
                return Some(format!(
                    "load[{i}] (moving_force) does not travel along +X on a straight path; {why}"
                ));
            }
        }
    }
    None
}

/// The window a model file's transient runs with, once the model is known.
#[derive(Debug)]
pub enum Plan {
    /// No window: the run is that of a model without one, bit for bit.
    Off,
    /// `mode = "auto"` on a model it does not apply to: off, and why (for the summary).
    AutoOff(String),
    /// The window runs.
    On(Box<RunWindow>),
}

impl Plan {
    /// Moves the window before a step ([`RunWindow::before_step`]); nothing when off.
    pub fn before_step(&mut self, driver: &mut Driver) -> Result<(), FemError> {
        match self {
            Plan::On(w) => w.before_step(driver),
            Plan::Off | Plan::AutoOff(_) => Ok(()),
        }
    }

    /// Why `mode = "auto"` stayed off, if it did (for the run's summary): decided before
    /// the run, or when the partitioned solver made no block.
    pub fn auto_off(&self) -> Option<&str> {
        match self {
            Plan::AutoOff(why) => Some(why),
            Plan::On(w) => w.auto_off(),
            Plan::Off => None,
        }
    }
}

/// The window of the model of `driver` as `spec` asks for it (`file` names the model file
/// in messages): an explicit `mode = "on"` on a model the window does not apply to is an
/// input error naming `[analysis.window]` and the fix.
pub fn plan(driver: &Driver, spec: &WindowSpec, file: &str) -> Result<Plan, FemError> {
    if spec.mode == WindowMode::Off {
        return Ok(Plan::Off);
    }
    let movers = MovingExtent::new(&driver.model);
    match (not_applicable(driver, &movers), spec.mode) {
        (Some(n), WindowMode::On) => Err(FemError::input(
            format!("{file}: [analysis.window]"),
            format!("mode = \"on\": {}; {}", n.reason, n.fix),
        )),
        (Some(n), _) => Ok(Plan::AutoOff(n.reason)),
        (None, _) => {
            let reach = spec.ahead.unwrap_or(crate::train_window::DEFAULT_REACH);
            let settings = WindowSettings {
                ahead: reach,
                // Waves the rear sends back are reflected by a held block as those the
                // front sends ahead: the same reach behind as ahead.
                behind: reach,
                tolerance: spec
                    .tolerance
                    .unwrap_or(crate::train_window::DEFAULT_TOLERANCE),
            };
            let layer = crate::train_window::layer(
                reach,
                LayerOptions {
                    thickness: spec.layer,
                    damping: spec.layer_damping,
                },
            );
            Ok(Plan::On(Box::new(RunWindow {
                settings,
                layer,
                movers,
                window: None,
                auto: spec.mode == WindowMode::Auto,
                off: None,
                front: f64::NEG_INFINITY,
                file: file.to_string(),
            })))
        }
    }
}

/// The window of a model file's run: it follows [`MovingExtent`] before every step.
#[derive(Debug)]
pub struct RunWindow {
    settings: WindowSettings,
    /// The absorbing layer at the window's edges (`None`: none, `layer = 0`).
    layer: Option<LayerSettings>,
    movers: MovingExtent,
    /// Made at the first step, once the driver is initialized.
    window: Option<ActivityWindow>,
    /// Whether the mode is `auto` (which stays off where the partitioned solver made no
    /// block, known only once it has factored).
    auto: bool,
    /// Why `auto` stayed off after all.
    off: Option<String>,
    /// The front at the last step (m): what moves must not go back along X.
    front: f64,
    file: String,
}

/// How far (m) the front of what moves may go back along X between steps before the run
/// is stopped: round-off of the positions.
const BACK: f64 = 1e-9;

impl RunWindow {
    /// The window's settings (defaults filled in).
    pub fn settings(&self) -> WindowSettings {
        self.settings
    }

    /// The absorbing layer's settings (defaults filled in; `None`: no layer).
    pub fn layer(&self) -> Option<LayerSettings> {
        self.layer
    }

    /// Moves the window to where the model's moving things are at the driver's time and
    /// holds or releases its blocks (call before each step, after the initialization).
    pub fn before_step(&mut self, driver: &mut Driver) -> Result<(), FemError> {
        let o = format!("{}: [analysis.window]", self.file);
        if self.off.is_some() {
            return Ok(());
        }
        if self.window.is_none() {
            let nodes = &driver.model.nodes;
            match ActivityWindow::new(driver, self.settings, |n| nodes[n].position.x) {
                Ok(mut w) => {
                    w.set_absorbing_layer(self.layer);
                    self.window = Some(w);
                }
                Err(m) if self.auto => {
                    self.off = Some(m);
                    return Ok(());
                }
                Err(m) => {
                    return Err(FemError::input(
                        o,
                        format!("mode = \"on\": {m}; give a smaller [analysis] block_size, or set mode = \"off\""),
                    ))
                }
            }
        }
        let t = driver.state.t;
        let Some([rear, front]) = self.movers.extent(&driver.model, t) else {
            return Ok(());
        };
        if front < self.front - BACK {
            return Err(FemError::input(
                o,
                format!(
                    "the front of what moves went back along X, from {:.3} to {:.3} m at t = {t} s; the window follows a motion along +X only; set mode = \"off\"",
                    self.front, front
                ),
            ));
        }
        self.front = front;
        let w = self.window.as_mut().expect("made above");
        w.update(driver, rear, front).map_err(|e| match e {
            // The window's own message names train-bridge's option: name the key.
            FemError::Input { message, .. } => {
                FemError::input(o, message.replace("--window-ahead", "`ahead`"))
            }
            other => other,
        })
    }

    /// Why `auto` stayed off after all (the partitioned solver made no block).
    pub fn auto_off(&self) -> Option<&str> {
        self.off.as_deref()
    }

    /// The window's counters so far (`None` before the first step).
    pub fn stats(&self) -> Option<WindowStats> {
        self.window.as_ref().map(ActivityWindow::stats)
    }
}

/// One line of a run's summary on the window's counters.
pub fn stats_line(w: &WindowStats) -> String {
    format!(
        "activity window: {} of {} block-steps held ({:.1} %), {} blocks joined, {} held behind",
        w.held_block_steps,
        w.block_steps,
        100.0 * w.held_block_steps as f64 / w.block_steps.max(1) as f64,
        w.joined,
        w.left
    )
}

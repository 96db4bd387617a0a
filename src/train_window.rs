//! The activity window of the train–bridge case (`railfem train-bridge --window`): where
//! the train is along the track at each step, the window's default reach and tolerance,
//! the choice between auto (the default: on where the window applies), on, and off, and
//! the checks that refuse a case an explicit `on` does not apply to. The window itself —
//! what a held block is, what stays exact and what is approximated — is
//! `railfem_solvers::window`. The case hands what the window needs of it as a
//! [`WindowTrack`] (`railfem::train_bridge` builds it), so this module does not read the
//! case.
//!
//! **The default reach.** A held block is a wall for the waves the train sends along the
//! rails, slab and girders: it reflects them back to the wheels. The reach `D` (how far
//! ahead of the front a block joins, and how far behind the rear it may be held) sets how
//! long a wave takes to come back, `2D/c`, and how much of it is left when it does.
//! The static part is short: a rail on discrete fasteners of stiffness `k_f` per seat at
//! spacing `a` is a beam on an elastic foundation of modulus `k = k_f/a` whose deflection
//! under a load decays as `e^{−βx}(cos βx + sin βx)` (Hetényi), `β = (k/(4·EI))^{1/4}`:
//! for the UIC 60 rail (`EI` = 6.38 MN·m²) on 60 MN/m seats every 0.625 m, `1/β` =
//! 0.72 m, and the envelope `√2·e^{−βx}` is below 1e-4 at `3π/β` = 6.8 m (the basin; the
//! reach is never less behind the rear). The waves are long: the 12-carriage train at
//! Δt = 0.5 ms (the paper's step) sends waves at about 800 m/s, which come back from a
//! held block at any time of a crossing; what `D` buys is their decay on the way, and the
//! absorbing layer's. **300 m** is the default reach: on the paper's 113 spans it keeps
//! ΔQ/Q within 0.18 % (entry) and 0.24 % (a middle segment) of the wheels' largest peak
//! over 2.5 s, against a 0.5 % target (`docs/activity-window.md`, "Error against the
//! full model"), so the window is **on by default** where it applies (`auto`). An end of
//! the structure within three times the reach keeps every block between it and the train
//! active (`railfem_solvers::window`, "The structure's ends"): the case gives the
//! abutments as ends ([`Viaduct::abutments`]). At a larger step the integrator's damping
//! (generalized-α, ρ∞ = 0.5) removes the waves sooner: at Δt = 2 ms, 66 m already gives
//! 0.29 % (`tests/train_window.rs`). The reach does not depend on the bridge's length, so
//! the cost of a windowed step grows with the train and not with the bridge.
//!
//! **The default tolerance**, 1 %, drops at most about 1e-4 of a block's largest kinetic
//! energy when it is held behind (`railfem_solvers::window`).
//!
//! **The absorbing layer** ([`layer`], `railfem_solvers::window::absorb`): damping
//! `α_max·ξ²·M_ii` over the last `L` before a held block, which returns the amplitude
//! `R = exp(−α_max·L/(3c))` of a wave at group velocity `c`. By default `L` is a third of
//! the reach (the layer's inner edge then stays two thirds of the reach from the train)
//! and `α_max = 3·c·ln(1/R)/L` with `c` = 1 500 m/s (above the fastest first arrivals
//! measured, about 1 200 m/s) and `R` = 0.01, but at most `2.5·L` (1/s, `L` in m): a
//! steeper layer reflects more by itself than it absorbs (a 40 m layer did best at
//! 100 /s and worse at 200 and 518 /s; `docs/activity-window.md`, "Why the window
//! errs"). With the default reach, `L` = 100 m and `α_max` = 207 /s.

use crate::framework::analysis::WindowMode;
use crate::solvers::window::absorb::LayerSettings;
use crate::solvers::window::{ActivityWindow, WindowSettings};
use crate::solvers::Driver;
use railfem_framework::FemError;

/// Where the viaduct's spans are: its abutments are ends of the structure for the window
/// (`railfem_solvers::window`, "The structure's ends"), its joints the far field's block
/// cuts (`crate::far_field::block_cuts`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Viaduct {
    /// Station of the first span's start (m, global `x`).
    pub start: f64,
    /// Span length (m).
    pub span: f64,
    /// Number of spans.
    pub spans: usize,
}

impl Viaduct {
    /// Stations of the first and last abutment (m).
    pub fn abutments(&self) -> [f64; 2] {
        [self.start, self.start + self.spans as f64 * self.span]
    }
}

/// What the window needs of a straight train–bridge case.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WindowTrack {
    /// Where the spans are.
    pub viaduct: Viaduct,
    /// Rail fasteners' vertical stiffness per seat (N/m).
    pub fastener_k: f64,
    /// Rail fasteners' spacing (m).
    pub fastener_spacing: f64,
    /// Station of the front carriage's centre at `t = 0` (m along the track).
    pub front_centre: f64,
    /// Train speed (m/s).
    pub speed: f64,
    /// Number of carriages.
    pub cars: usize,
    /// Whether the ground moves (`--quake`).
    pub ground_motion: bool,
    /// Whether the far field is reduced (`--far-field reduced`): it takes the blocks out
    /// of the train's reach, which the window would hold.
    pub far_field_reduced: bool,
    /// Whether the track is curved (`--radius`).
    pub curved: bool,
}

/// The activity window's choice for a case.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum WindowChoice {
    /// Every block solved every step (the answers of a run without the window, bit for
    /// bit).
    Off,
    /// Blocks far from the train held ([`WindowOptions`]); a case the window does not
    /// apply to is refused.
    On(WindowOptions),
    /// [`WindowChoice::On`] where the window applies (the partitioned solver on one
    /// process, a straight track, no ground motion), else [`WindowChoice::Off`], saying
    /// why ([`auto_off_reason`]). The default: with the default reach it keeps every
    /// target of the error against the full model at the paper's step (module
    /// documentation).
    Auto(WindowOptions),
}

impl Default for WindowChoice {
    fn default() -> Self {
        WindowChoice::Auto(WindowOptions::default())
    }
}

/// The user's settings of the window; `None`: the default (module documentation).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct WindowOptions {
    /// Distance ahead of the train's front at which a block joins (m).
    pub ahead: Option<f64>,
    /// Relative velocity norm below which a block behind the train is held (-).
    pub tolerance: Option<f64>,
}

/// The default tolerance (module documentation).
pub const DEFAULT_TOLERANCE: f64 = 0.01;

/// The default reach of the window (m): how far ahead of the train's front a block joins,
/// and how far behind its rear a block is held at the earliest (module documentation).
pub const DEFAULT_REACH: f64 = 300.0;

/// The rail's decay length `1/β` (m), `β = (k/(4·EI))^{1/4}`, `k` the fasteners' vertical
/// stiffness per metre (module documentation).
pub fn decay_length(track: &WindowTrack) -> f64 {
    let k = track.fastener_k / track.fastener_spacing;
    let rail = crate::elements::rail::geometry::track_model::TrackMesh::default().rail;
    let beta = (k / (4.0 * rail.e * rail.i_vertical)).powf(0.25);
    1.0 / beta
}

/// The window's settings for `track` with the user's `options` (defaults filled in).
pub fn settings(track: &WindowTrack, options: WindowOptions) -> WindowSettings {
    let basin = 3.0 * std::f64::consts::PI * decay_length(track);
    let reach = options.ahead.unwrap_or(DEFAULT_REACH);
    WindowSettings {
        ahead: reach,
        // The waves the rear wheels send back are reflected by a held block as those the
        // front sends ahead: the same reach, and never less than the rail's basin.
        behind: reach.max(basin),
        tolerance: options.tolerance.unwrap_or(DEFAULT_TOLERANCE),
    }
}

/// Stations of the train's rear and front at time `t` (m along the track): the front
/// carriage's centre moves from `front_centre` at the track's speed, and the train
/// reaches half a carriage before it and `cars − ½` carriages behind it (the wheels lie
/// inside).
pub fn train_extent(track: &WindowTrack, t: f64) -> [f64; 2] {
    let car = crate::elements::rail::vehicle::CarriageData::sks700().car_length;
    let centre = track.front_centre + track.speed * t;
    [centre - (track.cars as f64 - 0.5) * car, centre + 0.5 * car]
}

/// Checks the choice against the case — with or without ground motion (`quake`), on a
/// curve (`curved`) — in one line naming the option and the fix. [`WindowChoice::Auto`]
/// is never refused for the case: it stays off where the window does not apply
/// ([`auto_off_reason`]); only its distances are checked.
pub fn validate(window: WindowChoice, quake: bool, curved: bool) -> Result<(), FemError> {
    let (o, explicit) = match window {
        WindowChoice::Off => return Ok(()),
        WindowChoice::On(o) => (o, true),
        WindowChoice::Auto(o) => (o, false),
    };
    let o_ = "command line";
    if let Some(a) = o.ahead {
        if !(a.is_finite() && a >= 0.0) {
            return Err(FemError::input(
                o_,
                format!("--window-ahead {a}: give a distance ≥ 0 m"),
            ));
        }
    }
    if let Some(t) = o.tolerance {
        if !(t.is_finite() && (0.0..1.0).contains(&t)) {
            return Err(FemError::input(
                o_,
                format!("--window-tolerance {t}: give a value from 0 (never hold a block behind) to below 1"),
            ));
        }
    }
    if !explicit {
        return Ok(());
    }
    if quake {
        return Err(FemError::input(
            o_,
            "--window on with --quake: under ground motion the whole viaduct moves; give --window off",
        ));
    }
    if curved {
        return Err(FemError::input(
            o_,
            "--window on with --radius: the window maps nodes to stations on a straight track only; give --window off",
        ));
    }
    Ok(())
}

/// Why [`WindowChoice::Auto`] stays off for a run on `driver` (after
/// its initialization) over `track`, or `None` when it applies: the partitioned solver on
/// one process, a straight track, no ground motion.
pub fn auto_off_reason(driver: &Driver, track: &WindowTrack) -> Option<&'static str> {
    if track.ground_motion {
        return Some("ground motion moves the whole viaduct");
    }
    if track.curved {
        return Some("the window maps nodes to stations on a straight track only");
    }
    if track.far_field_reduced {
        return Some("the far field is reduced (--far-field reduced) out of the train's reach");
    }
    match driver.partition_stats() {
        None => Some("the model is not on the partitioned solver (auto picks it from 50 000 equations; --solver partitioned)"),
        Some(p) if p.ranks > 1 => Some("the partitioned solver's blocks are shared among MPI ranks"),
        Some(_) => None,
    }
}

/// The window of a run, after the driver's initialization (`None` when off, or when
/// `auto` finds that it does not apply: [`auto_off_reason`]). An explicit
/// [`WindowChoice::On`] on a model without the partitioned solver is refused (an input
/// error).
pub fn open(
    driver: &Driver,
    window: WindowChoice,
    track: &WindowTrack,
) -> Result<Option<ActivityWindow>, FemError> {
    let o = match window {
        WindowChoice::Off => return Ok(None),
        WindowChoice::Auto(_) if auto_off_reason(driver, track).is_some() => return Ok(None),
        WindowChoice::On(o) | WindowChoice::Auto(o) => o,
    };
    // On the straight track (checked) a node's station is its X coordinate.
    let station = |node: usize| driver.model.nodes[node].position.x;
    let settings = settings(track, o);
    let mut w = ActivityWindow::new(driver, settings, station).map_err(|m| {
        FemError::input(
            "command line",
            format!("--window on: {m}; give --solver partitioned or --window off"),
        )
    })?;
    w.set_absorbing_layer(layer(settings.ahead, LayerOptions::default()));
    w.set_ends(&track.viaduct.abutments());
    Ok(Some(w))
}

/// How the partitioned solver forms its promotions under the window `w`: by the forward
/// pass (`solvers/src/partition/forward.rs`, the cheaper form) once the window has held a
/// block, by columns before, so that a window holding nothing writes the bytes of a run
/// without it. A change re-forms the promotions at the next factorization.
pub fn promotion_form(w: &ActivityWindow) -> crate::solvers::partition::PromotionForm {
    use crate::solvers::partition::PromotionForm;
    if w.stats().held_block_steps > 0 {
        PromotionForm::Forward
    } else {
        PromotionForm::Columns
    }
}

/// The user's settings of the absorbing layer (`--window-layer`,
/// `--window-layer-damping`); `None`: the default (module documentation).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct LayerOptions {
    /// Thickness `L` (m); `0`: no layer.
    pub thickness: Option<f64>,
    /// `α_max` (1/s).
    pub damping: Option<f64>,
}

/// The absorbing layer of a window of reach `reach` (m) with the user's `options`
/// (module documentation): by default a third of the reach thick, `α_max` by the
/// reflection rule for [`LAYER_WAVE_SPEED`] and [`LAYER_REFLECTION`], at most
/// [`LAYER_GRADIENT`] times the thickness; `None` for a thickness of zero.
pub fn layer(reach: f64, options: LayerOptions) -> Option<LayerSettings> {
    let thickness = options.thickness.unwrap_or(reach / 3.0);
    if thickness <= 0.0 {
        return None;
    }
    let mut s = LayerSettings::for_reflection(thickness, LAYER_WAVE_SPEED, LAYER_REFLECTION);
    s.alpha_max = options
        .damping
        .unwrap_or(s.alpha_max.min(LAYER_GRADIENT * thickness));
    Some(s)
}

/// The layer's settings named by `keys` (the command line's options or a study's keys):
/// refused, in one line naming the setting and the fix, when the thickness is negative or
/// not finite, the damping not above zero or not finite, the damping given for a layer
/// the thickness 0 removes, or either given while the window is off.
pub fn parse_layer(
    keys: WindowKeys,
    window: WindowChoice,
    thickness: Option<f64>,
    damping: Option<f64>,
) -> Result<LayerOptions, FemError> {
    let [mode, t_, d_] = [keys.names[0], keys.layer[0], keys.layer[1]];
    let bad = |m: String| Err(FemError::input(keys.origin, m));
    if let Some(x) = thickness.filter(|x| !(x.is_finite() && *x >= 0.0)) {
        return bad(format!("{t_} {x}: give a value ≥ 0"));
    }
    if let Some(x) = damping.filter(|x| !(x.is_finite() && *x > 0.0)) {
        return bad(format!("{d_} {x}: give a value > 0 (1/s)"));
    }
    if thickness == Some(0.0) && damping.is_some() {
        return bad(format!(
            "{d_} shapes the absorbing layer, which {t_} 0 removes; drop {d_}, or give {t_} > 0"
        ));
    }
    let options = LayerOptions { thickness, damping };
    if window == WindowChoice::Off && options != LayerOptions::default() {
        return bad(format!("{t_} and {d_} shape the activity window's absorbing layer, which {mode} off turns off; drop them, or give {mode} on or auto"));
    }
    Ok(options)
}

/// The group velocity the absorbing layer is sized for (m/s) (module documentation).
pub const LAYER_WAVE_SPEED: f64 = 1500.0;

/// The amplitude the absorbing layer returns of a wave at [`LAYER_WAVE_SPEED`] (-).
pub const LAYER_REFLECTION: f64 = 0.01;

/// The largest `α_max/L` of the absorbing layer (1/(s·m)): a steeper layer reflects
/// more itself than it absorbs (module documentation).
pub const LAYER_GRADIENT: f64 = 2.5;

/// How the window's settings are named where they were given: the command line's
/// options or a study plan's keys (for the one-line errors of [`parse_options`] and
/// [`parse_layer`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WindowKeys {
    /// Where the settings were read (the error's origin).
    pub origin: &'static str,
    /// The mode's name, the distance's and the tolerance's.
    pub names: [&'static str; 3],
    /// The absorbing layer's thickness and damping.
    pub layer: [&'static str; 2],
}

/// `railfem train-bridge`'s options.
pub const COMMAND_LINE: WindowKeys = WindowKeys {
    origin: "command line",
    names: ["--window", "--window-ahead", "--window-tolerance"],
    layer: ["--window-layer", "--window-layer-damping"],
};

/// A study plan's keys of the train–bridge case (`docs/study.md`).
pub const STUDY: WindowKeys = WindowKeys {
    origin: "study case",
    names: ["`window`", "`window_ahead`", "`window_tolerance`"],
    layer: ["`window_layer`", "`window_layer_damping`"],
};

/// The window's choice from its settings named by `keys`: the mode `window` (`on`, `off`
/// or `auto`, the default), the distance `ahead` and the `tolerance` (refused with `off`,
/// and out of range, in one line naming the key and the fix).
pub fn parse_options(
    keys: WindowKeys,
    window: Option<&str>,
    ahead: Option<f64>,
    tolerance: Option<f64>,
) -> Result<WindowChoice, FemError> {
    let [mode, a_, t_] = keys.names;
    let bad = |m: String| Err(FemError::input(keys.origin, m));
    if let Some(a) = ahead.filter(|a| !(a.is_finite() && *a >= 0.0)) {
        return bad(format!("{a_} {a}: give a distance ≥ 0 m"));
    }
    if let Some(t) = tolerance.filter(|t| !(t.is_finite() && (0.0..1.0).contains(t))) {
        return bad(format!(
            "{t_} {t}: give a value from 0 (never hold a block behind) to below 1"
        ));
    }
    let options = WindowOptions { ahead, tolerance };
    let Some(kind) = window.map_or(Some(WindowMode::Auto), WindowMode::parse) else {
        return bad(format!(
            "{mode} {}: give on, off or auto",
            window.unwrap_or_default()
        ));
    };
    match kind {
        WindowMode::On => Ok(WindowChoice::On(options)),
        WindowMode::Auto => Ok(WindowChoice::Auto(options)),
        WindowMode::Off if options == WindowOptions::default() => Ok(WindowChoice::Off),
        WindowMode::Off => bad(format!(
            "{a_} and {t_} set the activity window, which {mode} off turns off; drop them, or give {mode} on or auto"
        )),
    }
}

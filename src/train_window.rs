//! The activity window of the train–bridge case (`railfem train-bridge --window on`):
//! where the train is along the track at each step, the window's default distances from
//! the rail's decay length and the span, and the checks that refuse a case the window does
//! not apply to. The window itself — what a held block is, what stays exact and what is
//! approximated — is `railfem_solvers::window`. The case hands what the window needs of
//! it as a [`WindowTrack`] (`railfem::train_bridge` builds it), so this module does not
//! read the case.
//!
//! **Default distances.** A rail on discrete fasteners of vertical stiffness `k_f` per seat
//! at spacing `a` is a beam on an elastic foundation of modulus `k = k_f/a`; under a load
//! its deflection at a distance `x` is `w(0)·e^{−βx}(cos βx + sin βx)` (Hetényi), with
//! `β = (k/(4·EI))^{1/4}`. For the UIC 60 rail (`EI` = 6.38 MN·m²) on 60 MN/m seats every
//! 0.625 m, `1/β` = 0.72 m. The envelope `√2·e^{−βx}` is below 1e-4 at `x = 3π/β` (2.2 m
//! of decay per π; 6.8 m here): that is `behind`, and the rail part of `ahead`. The
//! bridge adds couplings the rail's static basin does not cover: a wheel on span `k` loads
//! the pier it shares with span `k + 1` and tilts that span as a rigid body (one span), and
//! the track and girders carry waves ahead of the train that a held block reflects instead
//! of letting them pass. Measured on 2 carriages entering 10 spans (`tests/train_window.rs`,
//! Δt = 2 ms), the largest ΔQ/Q error against the full model, as a fraction of each
//! wheel's own peak,
//! falls with `ahead` as 0.73 % (one span + 3π/β = 36.5 m), 0.48 % (50 m), 0.29 % (66 m),
//! 0.25 % (80 m), 0.12 % (120 m), 0.01 % (200 m): the default is **two spans + 3π/β**
//! (66 m for 29.75 m spans), the shortest of these with a margin of almost two under the
//! 0.5 % target. For the paper's 12 carriages entering 20 spans (Δt = 0.5 ms, blocks of
//! 3 000 equations) the same default gives about 1 % of the wheels' largest ΔQ/Q peak
//! (`docs/activity-window.md`): the window is therefore not on by default. The default tolerance, 1 %, drops at most about 1e-4 of a block's largest
//! kinetic energy when it is held behind (`railfem_solvers::window`).

use crate::solvers::window::{ActivityWindow, WindowSettings};
use crate::solvers::Driver;
use railfem_framework::FemError;

/// What the window needs of a straight train–bridge case.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WindowTrack {
    /// Span length (m).
    pub span: f64,
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
}

/// The activity window's choice for a case.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum WindowChoice {
    /// Every block solved every step (the answers of a run without the window, bit for
    /// bit).
    #[default]
    Off,
    /// Blocks far from the train held ([`WindowOptions`]).
    On(WindowOptions),
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
    WindowSettings {
        ahead: options.ahead.unwrap_or(2.0 * track.span + basin),
        behind: basin,
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
/// curve (`curved`) — in one line naming the option and the fix.
pub fn validate(window: WindowChoice, quake: bool, curved: bool) -> Result<(), FemError> {
    let WindowChoice::On(o) = window else {
        return Ok(());
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

/// The window of a run, after the driver's initialization (`None` when off). Refused
/// (an input error) when the model has no partitioned solver.
pub fn open(
    driver: &Driver,
    window: WindowChoice,
    track: &WindowTrack,
) -> Result<Option<ActivityWindow>, FemError> {
    let WindowChoice::On(o) = window else {
        return Ok(None);
    };
    // On the straight track (checked) a node's station is its X coordinate.
    let station = |node: usize| driver.model.nodes[node].position.x;
    ActivityWindow::new(driver, settings(track, o), station)
        .map(Some)
        .map_err(|m| {
            FemError::input(
                "command line",
                format!("--window on: {m}; give --solver partitioned or --window off"),
            )
        })
}

/// The window's options of `railfem train-bridge` (`--window on|off`, `--window-ahead`,
/// `--window-tolerance`; the last two need `--window on`).
pub fn parse_options(
    window: Option<&str>,
    ahead: Option<f64>,
    tolerance: Option<f64>,
) -> Result<WindowChoice, FemError> {
    let o = "command line";
    let options = WindowOptions { ahead, tolerance };
    match window {
        Some("on") => Ok(WindowChoice::On(options)),
        Some("off") | None if options == WindowOptions::default() => Ok(WindowChoice::Off),
        Some("off") | None => Err(FemError::input(
            o,
            "--window-ahead and --window-tolerance set the activity window; add --window on",
        )),
        Some(other) => Err(FemError::input(
            o,
            format!("--window {other}: give on or off"),
        )),
    }
}

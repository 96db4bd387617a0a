//! The train–bridge generator (`railfem train-bridge`): a train of `sks700` carriages on
//! moving-axle wheels crossing a viaduct of simply supported spans (slab track on girders,
//! bearings, piers; see `elements::rail::geometry::bridge`), optionally shaken by a uniform ground
//! motion at the supports, with each wheel's Q, Y, Y/Q and ΔQ/Q and each span's midspan
//! deflection over time.
//!
//! [`TrainBridgeCase`] holds the inputs; [`build`] makes the model (a library function, so
//! benches and tests call it without the command line); [`run`] steps it and writes the
//! CSV files; [`read_quake`] and [`synthetic_quake`] give the ground motion.
//!
//! Layout along the track: an approach of `cars·25 + 20` m of slab track on the subgrade,
//! the bridge (`spans × span`), and the same approach after it. The train starts with its
//! front carriage's centre 15 m before the bridge (`train_start`, `--train-start`) and by default runs until its last
//! carriage has left the bridge.
//!
//! Ground motion: `LoadSpec::GroundMotion` of the framework (every mass feels `−M·r·a_g(t)`,
//! the solution is relative to the ground), one per non-zero direction, global X, Y, Z.

use crate::elements::rail::geometry::alignment::{Alignment, Hand, Segment};
use crate::elements::rail::geometry::bridge::BridgeSpec;
use crate::elements::rail::geometry::cant::{Cant, Track};
use crate::elements::rail::geometry::track_model::{
    self, RailSection, RailSupport, TrackMesh, TrackModel,
};
use crate::elements::rail::vehicle::{build_train, CarriageData, TrainIds, TrainSpec};
use crate::framework::builder::ModelBuilder;
use crate::framework::csv_input;
use crate::framework::limits::{self, fmt_num};
use crate::framework::loads::{LoadSpec, TimeSeries};
use crate::framework::model::{AnalysisSpec, IntegratorKind, NewtonSettings};
use crate::framework::FemError;
use crate::solvers::exchange::Exchange;
use crate::solvers::partition::PartitionOptions;
use crate::solvers::Driver;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

/// Standard gravity (m/s²), for records in g.
pub const G0: f64 = 9.80665;

/// Where the ground motion comes from.
#[derive(Debug, Clone, PartialEq)]
pub enum Quake {
    /// No ground motion.
    None,
    /// A CSV record (see `examples/records/README.md`).
    File(PathBuf),
    /// The seeded Kanai–Tajimi generator, [`synthetic_quake`].
    Synthetic {
        /// Seed of the generator.
        seed: u64,
        /// Peak horizontal ground acceleration (g); vertical is 2/3 of it.
        pga: f64,
        /// Length of the record (s).
        duration: f64,
    },
    /// A record already in memory (e.g. a file's record times an intensity scale, as
    /// `railfem study` makes them).
    Record(QuakeRecord),
}

/// Inputs of a train–bridge run. SI units.
#[derive(Debug, Clone, PartialEq)]
pub struct TrainBridgeCase {
    /// Carriages in the train.
    pub cars: usize,
    /// Spans of the bridge.
    pub spans: usize,
    /// Span length (m); 3362 m / 113 spans ≈ 29.75 m.
    pub span: f64,
    /// Largest rail, slab and girder element length (m); each 0.625 m fastener bay is
    /// split into `ceil(0.625/h)` equal elements. Ignored when `dof_target` is given.
    pub element_length: f64,
    /// Choose the element length so that the model has about this many DOFs (the nearest
    /// count the mesh can make).
    pub dof_target: Option<usize>,
    /// Speed (m/s).
    pub speed: f64,
    /// Radius of a curved (left-hand, canted) track (m); `None` = straight.
    pub radius: Option<f64>,
    /// Cant constant Ct (m): θ = Ct/R on a curve.
    pub ct: f64,
    /// Duration (s); `None` = until the train has left the bridge.
    pub duration: Option<f64>,
    /// Time step (s).
    pub dt: f64,
    /// Ground motion.
    pub quake: Quake,
    /// Record every n-th step.
    pub record_every: usize,
    /// Spans (1-based) whose midspan deflection is recorded; empty = all.
    pub midspans: Vec<usize>,
    /// Friction coefficient of the wheels.
    pub mu: f64,
    /// Contact penalty k = k_v (N/m).
    pub penalty: f64,
    /// Pier height (m).
    pub pier_height: f64,
    /// Gravity (m/s²).
    pub gravity: f64,
    /// Generalized-α spectral radius at infinity ρ∞: damps the contact chatter (the wheel
    /// on its penalty spring rings at ~500 Hz, far above 1/Δt) while the bridge modes, at
    /// ω·Δt < 1, keep their amplitude to second order.
    pub rho_inf: f64,
    /// Time integrator (generalized-α by default). HHT takes Hilber's α from `rho_inf` as
    /// `(1 − ρ∞)/(1 + ρ∞)`; Newmark is the average-acceleration rule (β = ¼, γ = ½).
    pub integrator: IntegratorKind,
    /// Linear solver of the Newton iterations (`auto`: partitioned from 50 000 equations).
    pub solver: crate::framework::model::SolverChoice,
    /// Geometry of the carriages (the bridge stays linear).
    pub geometry: crate::framework::model::Geometry,
    /// Station of the front carriage's centre at t = 0, measured from the bridge's first
    /// abutment (m): −15 (the default) starts the train on the approach, so it enters the
    /// viaduct; a station on the bridge starts it there (the middle of a crossing, for
    /// timing a segment that the entry does not dominate).
    pub train_start: f64,
    /// Contact statuses of each step's first Newton iteration (`[analysis.newton]
    /// first_active_set`): `Committed` (the default) holds the last converged step's,
    /// which keeps a wheel on a deflecting bridge in contact for the first tangent; `Found`
    /// lets the first evaluation find them (docs/performance.md, "The first iteration's
    /// active set").
    pub first_active_set: crate::framework::model::FirstActiveSet,
    /// The activity window (`--window`, [`crate::train_window`]): `auto` by default.
    pub window: crate::train_window::WindowChoice,
    /// The window's absorbing layer (`--window-layer`, [`crate::train_window::layer`]).
    pub window_layer: crate::train_window::LayerOptions,
    /// The far field (`--far-field`, [`crate::far_field`]): full by default.
    pub far_field: crate::far_field::FarFieldChoice,
}

impl Default for TrainBridgeCase {
    fn default() -> Self {
        TrainBridgeCase {
            cars: 12,
            spans: 113,
            span: 29.75,
            // One element per 0.625 m fastener bay (fasteners are always nodes; 0.6 m would
            // split every bay in two).
            element_length: 0.625,
            dof_target: None,
            speed: 80.0,
            radius: None,
            ct: 200.0,
            duration: None,
            dt: 0.005,
            quake: Quake::None,
            record_every: 1,
            midspans: Vec::new(),
            mu: 0.3,
            penalty: 1e10,
            pier_height: 10.0,
            gravity: 9.81,
            rho_inf: 0.5,
            integrator: IntegratorKind::GeneralizedAlpha,
            solver: Default::default(),
            geometry: Default::default(),
            train_start: -15.0,
            first_active_set: Default::default(),
            window: Default::default(),
            window_layer: Default::default(),
            far_field: Default::default(),
        }
    }
}

/// A ground-acceleration record: times (s) and accelerations along global X, Y, Z (m/s²).
#[derive(Debug, Clone, PartialEq)]
pub struct QuakeRecord {
    /// Sample times (s), strictly increasing.
    pub t: Vec<f64>,
    /// Accelerations X, Y, Z (m/s²) at those times.
    pub a: [Vec<f64>; 3],
}

impl QuakeRecord {
    /// Largest |a| per direction (m/s²).
    pub fn peaks(&self) -> [f64; 3] {
        let mut p = [0.0f64; 3];
        for (c, col) in self.a.iter().enumerate() {
            p[c] = col.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        }
        p
    }

    /// Writes the record as CSV in g (`time_s,ax_g,ay_g,az_g`).
    pub fn write_csv(&self, path: &Path) -> Result<(), FemError> {
        if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
            std::fs::create_dir_all(dir).map_err(|e| FemError::output(dir, e))?;
        }
        let mut s = String::from("time_s,ax_g,ay_g,az_g\n");
        for i in 0..self.t.len() {
            s.push_str(&format!(
                "{},{:.6e},{:.6e},{:.6e}\n",
                self.t[i],
                self.a[0][i] / G0,
                self.a[1][i] / G0,
                self.a[2][i] / G0
            ));
        }
        std::fs::write(path, s).map_err(|e| FemError::output(path, e))
    }
}

/// Largest ground acceleration a record may hold (m/s²): 10 g. The largest peak ground
/// accelerations recorded are about 4 g (the 2008 Iwate–Miyagi earthquake at station IWTH25).
pub const MAX_GROUND_ACCEL: f64 = 10.0 * G0;

const ACCEL_BOUND: csv_input::Bound = csv_input::Bound {
    max_si: MAX_GROUND_ACCEL,
    si_unit: "m/s²",
    why: "no earthquake has shaken the ground harder than about 4 g",
};

/// The longest record time (s): a day. Strong shaking lasts minutes.
const TIME_BOUND: csv_input::Bound = csv_input::Bound {
    max_si: 86_400.0,
    si_unit: "s",
    why: "strong ground motion lasts minutes, not days",
};

/// Reads a quake CSV: header `time_s,ax_<u>,ay_<u>,az_<u>` with `<u>` = `g` or `mps2`, then
/// rows of four numbers with strictly increasing time. Errors name the file and line.
pub fn read_quake(path: &Path) -> Result<QuakeRecord, FemError> {
    let origin = path.display().to_string();
    limits::check_file(path, "the quake record").map_err(|m| FemError::input(&origin, m))?;
    let text = std::fs::read_to_string(path).map_err(|e| {
        FemError::input(
            &origin,
            format!("cannot read the quake record ({e}); give a CSV file (see examples/records/README.md)"),
        )
    })?;
    let mut lines = csv_input::strip_bom(&text)
        .lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty() && !l.trim_start().starts_with('#'));
    let (hn, header) = lines.next().ok_or_else(|| {
        FemError::input(
            &origin,
            "empty file; give a header `time_s,ax_g,ay_g,az_g` and rows",
        )
    })?;
    let cols: Vec<&str> = header.split(',').map(str::trim).collect();
    let (scale, unit) = match cols.as_slice() {
        ["time_s", "ax_g", "ay_g", "az_g"] => (G0, "g"),
        ["time_s", "ax_mps2", "ay_mps2", "az_mps2"] => (1.0, "m/s²"),
        _ => {
            return Err(FemError::input(
                format!("{origin}:{}", hn + 1),
                format!("header `{header}`: give `time_s,ax_g,ay_g,az_g` (g) or `time_s,ax_mps2,ay_mps2,az_mps2` (m/s²)"),
            ))
        }
    };
    let mut rec = QuakeRecord {
        t: Vec::new(),
        a: [Vec::new(), Vec::new(), Vec::new()],
    };
    for (n, line) in lines {
        let place = format!("{origin}:{}", n + 1);
        let v: Vec<f64> = line
            .split(',')
            .map(|x| x.trim().parse::<f64>())
            .collect::<Result<_, _>>()
            .map_err(|_| {
                FemError::input(
                    &place,
                    format!("`{line}` is not four numbers; give time, a_x, a_y, a_z"),
                )
            })?;
        if v.len() != 4 || v.iter().any(|x| !x.is_finite()) {
            return Err(FemError::input(
                &place,
                format!("`{line}`: give four finite numbers (time, a_x, a_y, a_z)"),
            ));
        }
        let bounds = [(&TIME_BOUND, 1.0, "s"), (&ACCEL_BOUND, scale, unit)];
        for (c, x) in v.iter().enumerate() {
            let (bound, sc, u) = bounds[c.min(1)];
            csv_input::check_bound(cols[c], *x, u, sc, bound)
                .map_err(|m| FemError::input(&place, m))?;
        }
        if let Some(last) = rec.t.last() {
            if v[0] <= *last {
                return Err(FemError::input(
                    &place,
                    format!(
                        "time {} is not after {last}; times must increase strictly",
                        v[0]
                    ),
                ));
            }
        }
        rec.t.push(v[0]);
        for c in 0..3 {
            rec.a[c].push(v[c + 1] * scale);
        }
    }
    if rec.t.len() < 2 {
        return Err(FemError::input(
            &origin,
            "the record needs at least two rows after the header",
        ));
    }
    Ok(rec)
}

/// SplitMix64: a small, seeded, portable generator (same numbers on every machine).
struct SplitMix(u64);

impl SplitMix {
    fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// Uniform in (0, 1).
    fn uniform(&mut self) -> f64 {
        ((self.next_u64() >> 11) as f64 + 0.5) / (1u64 << 53) as f64
    }
    /// Standard normal (Box–Muller).
    fn normal(&mut self) -> f64 {
        let (u1, u2) = (self.uniform(), self.uniform());
        (-2.0 * u1.ln()).sqrt() * (2.0 * std::f64::consts::PI * u2).cos()
    }
}

/// A synthetic ground motion: white noise through a Kanai–Tajimi filter (ground ω_g = 5π
/// rad/s, ζ_g = 0.6, firm soil) and a Clough–Penzien high-pass (ω_f = 0.5π rad/s,
/// ζ_f = 0.6, so that ground velocity and displacement do not drift), times the envelope
/// `(t/2)²` up to 2 s, 1 up to 10 s, `e^{−0.25(t−10)}` after; sampled every 0.01 s,
/// components X and Y scaled to `pga` (g) and Z to 2/3 of it. Deterministic in `seed`.
///
/// Filters (state x, ẋ driven by the noise w held over each 0.01 s, integrated by RK4 in
/// ten sub-steps): `ẍ_g + 2ζ_gω_g ẋ_g + ω_g² x_g = −w`, KT output `u = −(2ζ_gω_g ẋ_g + ω_g² x_g)`
/// (the absolute acceleration of the soil column, PSD ∝ (ω_g⁴ + 4ζ_g²ω_g²ω²)/((ω_g² − ω²)² +
/// 4ζ_g²ω_g²ω²)); `ẍ_f + 2ζ_fω_f ẋ_f + ω_f² x_f = u`, ground acceleration `a = ẍ_f`, whose
/// transfer `s²/(s² + 2ζ_fω_f s + ω_f²)` removes the low frequencies.
pub fn synthetic_quake(seed: u64, pga: f64, duration: f64) -> QuakeRecord {
    use std::f64::consts::PI;
    let dt = 0.01;
    let n = (duration / dt).ceil() as usize + 1;
    let (wg, zg, wf, zf) = (5.0 * PI, 0.6, 0.5 * PI, 0.6);
    let envelope = |t: f64| {
        if t < 2.0 {
            (t / 2.0).powi(2)
        } else if t <= 10.0 {
            1.0
        } else {
            (-0.25 * (t - 10.0)).exp()
        }
    };
    let t: Vec<f64> = (0..n).map(|i| i as f64 * dt).collect();
    let mut a: [Vec<f64>; 3] = [vec![0.0; n], vec![0.0; n], vec![0.0; n]];
    for (c, col) in a.iter_mut().enumerate() {
        let mut rng = SplitMix(seed.wrapping_mul(3).wrapping_add(c as u64 + 1));
        // State: [x_g, v_g, x_f, v_f].
        let mut s = [0.0f64; 4];
        let rhs = |s: &[f64; 4], w: f64| -> ([f64; 4], f64) {
            let u = -(2.0 * zg * wg * s[1] + wg * wg * s[0]);
            let af = u - 2.0 * zf * wf * s[3] - wf * wf * s[2];
            (
                [s[1], -w - wg * wg * s[0] - 2.0 * zg * wg * s[1], s[3], af],
                af,
            )
        };
        let sub = 10;
        let h = dt / sub as f64;
        for i in 0..n {
            let w = rng.normal() / dt.sqrt();
            col[i] = rhs(&s, w).1 * envelope(t[i]);
            for _ in 0..sub {
                let (k1, _) = rhs(&s, w);
                let s2: [f64; 4] = std::array::from_fn(|j| s[j] + 0.5 * h * k1[j]);
                let (k2, _) = rhs(&s2, w);
                let s3: [f64; 4] = std::array::from_fn(|j| s[j] + 0.5 * h * k2[j]);
                let (k3, _) = rhs(&s3, w);
                let s4: [f64; 4] = std::array::from_fn(|j| s[j] + h * k3[j]);
                let (k4, _) = rhs(&s4, w);
                for j in 0..4 {
                    s[j] += h / 6.0 * (k1[j] + 2.0 * k2[j] + 2.0 * k3[j] + k4[j]);
                }
            }
        }
        let peak = col.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let target = pga * G0 * if c == 2 { 2.0 / 3.0 } else { 1.0 };
        if peak > 0.0 {
            for v in col.iter_mut() {
                *v *= target / peak;
            }
        }
    }
    QuakeRecord { t, a }
}

/// The built model and what a run needs to read it.
pub struct TrainBridgeModel {
    /// The driver, ready to initialize.
    pub driver: Driver,
    /// Ids of the train.
    pub ids: TrainIds,
    /// The track with its bridge layout.
    pub track: Arc<TrackModel>,
    /// Element indices of the wheels (left, right per wheelset, front to rear).
    pub wheel_index: Vec<usize>,
    /// Equations (free DOFs).
    pub dofs: usize,
    /// Elements.
    pub elements: usize,
    /// Nodes.
    pub nodes: usize,
    /// The longest rail element (m): the requested length or less (every fastener is a
    /// node, so a bay of 0.625 m is split into equal elements no longer than it).
    pub element_length: f64,
    /// Wall time to generate and build (s): (generation, framework build, driver set-up).
    pub build_seconds: [f64; 3],
    /// Resident memory (MiB, `VmRSS`) after generating the track and train, after building
    /// the model and after numbering and assembly (the driver), then the peak (`VmHWM`)
    /// after all of it: where the build's memory goes (`railfem bench`'s memory report).
    pub build_memory_mib: [f64; 4],
    /// Duration of the run (s).
    pub duration: f64,
    /// The ground motion used, if any.
    pub quake: Option<QuakeRecord>,
}

impl TrainBridgeCase {
    /// Approach length before and after the bridge (m).
    pub fn approach(&self) -> f64 {
        self.cars as f64 * CarriageData::sks700().car_length + 20.0
    }

    /// What the activity window needs of the case ([`crate::train_window`]).
    pub fn window_track(&self) -> crate::train_window::WindowTrack {
        let slab = self.bridge().slab_track;
        crate::train_window::WindowTrack {
            viaduct: crate::train_window::Viaduct {
                start: self.approach(),
                span: self.span,
                spans: self.spans,
            },
            fastener_k: slab.fastener_k[1],
            fastener_spacing: slab.fastener_spacing,
            front_centre: self.approach() + self.train_start,
            speed: self.speed,
            cars: self.cars,
            ground_motion: self.quake != Quake::None,
            far_field_reduced: self.far_field != crate::far_field::FarFieldChoice::Full,
            curved: self.radius.is_some(),
        }
    }

    pub(crate) fn bridge(&self) -> BridgeSpec {
        BridgeSpec {
            span: self.span,
            pier_height: self.pier_height,
            ..BridgeSpec::new(self.approach(), self.spans)
        }
    }

    /// The track mesh at rail element length `h` (at most; fasteners are nodes).
    pub(crate) fn mesh(&self, h: f64) -> TrackMesh {
        TrackMesh {
            element_length: h,
            support: RailSupport::Bridge(Box::new(self.bridge())),
            ..Default::default()
        }
    }

    /// The track: straight, or one left-hand arc of `radius` with cant Ct/R.
    pub fn track(&self) -> Result<Track, FemError> {
        let len = 2.0 * self.approach() + self.spans as f64 * self.span;
        let o = "train-bridge case";
        match self.radius {
            None => Alignment::new(vec![Segment::Straight { length: len }])
                .and_then(|al| Track::new(al, Cant::none()))
                .map_err(|e| FemError::input(o, e.to_string())),
            Some(r) => {
                let al = Alignment::new(vec![Segment::Arc {
                    length: len,
                    radius: r,
                    hand: Hand::Left,
                }])
                .map_err(|e| FemError::input(o, format!("--radius {r}: {e}")))?;
                Track::new(al, Cant::FromRadius { ct: self.ct })
                    .map_err(|e| FemError::input(o, e.to_string()))
            }
        }
    }

    /// The element length whose DOF count is nearest `target` (rails 2·6 per station, slab 6
    /// per station and joint, piers 6 per free node, vehicle 66 per carriage). Every rail
    /// support is a node and each bay gets a whole number of elements, so the count moves in
    /// steps of one element per bay: the paper's 1 043 430 DOF is its 0.069 m mesh, nine
    /// elements per 0.625 m bay (1 044 366 DOF), not the ten per bay of the first count
    /// above the target (1 156 686).
    fn element_length_for(&self, track: &Track, target: usize) -> f64 {
        let len = track.alignment.length();
        let count = |h: f64| {
            let n = self.mesh(h).stations(track, [0.0, len]).len();
            let segs = self.spans + 2;
            6 * (3 * n + segs - 1) + 6 * 4 * (self.spans - 1) + 66 * self.cars
        };
        // From four times the estimate down (18 m of track per DOF-equivalent), so that the
        // last count below the target is seen as well as the first above it.
        let mut h = 72.0 * len / target as f64;
        let mut c = count(h);
        let mut below = None;
        while c < target {
            below = Some((h, c));
            h *= 0.995;
            c = count(h);
        }
        match below {
            Some((hb, cb)) if target - cb < c - target => hb,
            _ => h,
        }
    }

    fn validate(&self) -> Result<(), FemError> {
        let o = "command line";
        let pos = |v: f64, what: &str| -> Result<(), FemError> {
            if v.is_finite() && v > 0.0 {
                Ok(())
            } else {
                Err(FemError::input(
                    o,
                    format!("--{what} {v}: give a value > 0"),
                ))
            }
        };
        pos(self.speed, "speed")?;
        pos(self.span, "span")?;
        pos(self.dt, "dt")?;
        pos(self.element_length, "element-length")?;
        pos(self.pier_height, "pier-height")?;
        if let Some(r) = self.radius {
            pos(r, "radius")?;
        }
        if let Some(d) = self.duration {
            pos(d, "duration")?;
        }
        crate::train_window::validate(
            self.window,
            self.quake != Quake::None,
            self.radius.is_some(),
        )?;
        if self.cars == 0 || self.spans == 0 {
            return Err(FemError::input(o, "--cars and --spans must be at least 1"));
        }
        // The whole train on the track at t = 0: the last carriage's centre half a carriage
        // from the start of the first approach (length `approach()`), the first's half a
        // carriage from the end of the second.
        let car = CarriageData::sks700().car_length;
        let (lo, hi) = (
            car * (self.cars as f64 - 0.5) - self.approach(),
            self.spans as f64 * self.span + self.approach() - 0.5 * car,
        );
        if !(self.train_start.is_finite() && (lo..=hi).contains(&self.train_start)) {
            return Err(FemError::input(
                o,
                format!(
                    "--train-start {}: the train must start on the track; give a station from {} to {} m (from the bridge's first abutment)",
                    fmt_num(self.train_start),
                    fmt_num(lo),
                    fmt_num(hi)
                ),
            ));
        }
        if let Some(&k) = self.midspans.iter().find(|k| **k == 0 || **k > self.spans) {
            return Err(FemError::input(
                o,
                format!(
                    "--midspans: span {k} does not exist; give numbers 1..={}",
                    self.spans
                ),
            ));
        }
        Ok(())
    }
}

/// Builds the model of a case.
pub fn build(case: &TrainBridgeCase) -> Result<TrainBridgeModel, FemError> {
    build_with(case, None)
}

/// [`build`] on one rank of `exchange`: the driver shares the partitioned solver's blocks
/// with the other ranks and forms `K`, `M`, `C` on the rank's columns only
/// (`Driver::new_across_ranks`, with `options` or the defaults). A case that does not run
/// the partitioned solver gets the one-process driver, for the caller to refuse.
pub fn build_across_ranks(
    case: &TrainBridgeCase,
    exchange: Arc<dyn Exchange>,
    options: Option<PartitionOptions>,
) -> Result<TrainBridgeModel, FemError> {
    build_with(case, Some((exchange, options)))
}

fn build_with(
    case: &TrainBridgeCase,
    shared: Option<(Arc<dyn Exchange>, Option<PartitionOptions>)>,
) -> Result<TrainBridgeModel, FemError> {
    case.validate()?;
    // The train's size first: its length sets the track's.
    limits::check_memory(
        &format!("--cars {}", case.cars),
        66.0 * case.cars as f64,
        "vehicle DOFs",
        limits::BYTES_PER_DOF,
        "give fewer --cars",
    )
    .map_err(|m| FemError::input("command line", m))?;
    let quake = match &case.quake {
        Quake::None => None,
        Quake::File(p) => Some(read_quake(p)?),
        Quake::Record(r) => Some(r.clone()),
        Quake::Synthetic {
            seed,
            pga,
            duration,
        } => {
            if !(pga.is_finite() && *pga >= 0.0 && duration.is_finite() && *duration > 0.0) {
                return Err(FemError::input(
                    "command line",
                    "--pga must be ≥ 0 g and --quake-duration > 0 s",
                ));
            }
            limits::check_memory(
                &format!("--quake-duration {} s", fmt_num(*duration)),
                duration / 0.01 + 1.0,
                "ground-motion samples",
                32.0, // t and three components, f64 each
                "give a shorter --quake-duration",
            )
            .map_err(|m| FemError::input("command line", m))?;
            Some(synthetic_quake(*seed, *pga, *duration))
        }
    };
    let t0 = Instant::now();
    let track = Arc::new(case.track()?);
    let h = match case.dof_target {
        Some(n) => {
            limits::check_memory(
                &format!("--dof {n}"),
                n as f64,
                "DOFs",
                limits::BYTES_PER_DOF,
                "give a smaller --dof",
            )
            .map_err(|m| FemError::input("command line", m))?;
            case.element_length_for(&track, n)
        }
        None => case.element_length,
    };
    let mut b = ModelBuilder::new("train-bridge case");
    let tm = track_model::generate(&mut b, track.clone(), &case.mesh(h))?;
    let longest = tm.longest_element();
    let spec = TrainSpec {
        name: "sks700".into(),
        carriage: CarriageData::sks700(),
        carriages: case.cars,
        start: case.approach() + case.train_start,
        speed: case.speed,
        accel: 0.0,
        speed_table: None,
        wheel: serde_json::json!({"mu": case.mu, "k": case.penalty, "k_v": case.penalty}),
        first_node_id: 0,
        geometry: Some(case.geometry),
        suspension_tangent: crate::elements::suspension::SuspensionTangent::Symmetric,
    };
    let car_len = CarriageData::sks700().car_length;
    let duration = case.duration.unwrap_or(
        (case.spans as f64 * case.span + case.cars as f64 * car_len - case.train_start)
            / case.speed,
    );
    b.analysis(AnalysisSpec {
        dt: case.dt,
        duration,
        gravity: Some([0.0, 0.0, -case.gravity]),
        integrator: case.integrator.clone(),
        rho_inf: case.rho_inf,
        alpha: (1.0 - case.rho_inf) / (1.0 + case.rho_inf),
        record_every: case.record_every.max(1),
        solver: case.solver,
        // Wheel loads are ~1e5 N and displacements ~1e-3 m: a relative 1e-6, 1e-2 N (or the
        // round-off floor of a fine mesh, `residual_floor`) and 1e-10 m end the iterations
        // well below what the outputs resolve.
        newton: NewtonSettings {
            max_iter: 60,
            tol: 1e-6,
            abs_tol: residual_floor(&tm, &case.bridge().girder).max(1e-2),
            disp_tol: 1e-10,
            first_active_set: case.first_active_set,
            ..Default::default()
        },
        ..Default::default()
    });
    let ids = build_train(&mut b, &tm, &spec)?;
    if let Some(q) = &quake {
        ground_motion(&mut b, q);
    }
    let t_gen = t0.elapsed().as_secs_f64();
    let rss = || crate::bench::resident_memory_mib().unwrap_or(f64::NAN);
    let rss_gen = rss();
    let t1 = Instant::now();
    let model = b.build()?;
    let rss_model = rss();
    let t_build = t1.elapsed().as_secs_f64();
    let t2 = Instant::now();
    let mut index = std::collections::HashMap::with_capacity(model.elements.len());
    for (i, e) in model.elements.iter().enumerate() {
        index.insert(e.id, i);
    }
    let wheel_index = ids.wheels.iter().map(|id| index[id]).collect();
    let (elements, nodes) = (model.elements.len(), model.nodes.len());
    let driver = match shared {
        None => Driver::new(model)?,
        Some((ex, options)) => Driver::new_across_ranks(model, ex, options)?,
    };
    let t_driver = t2.elapsed().as_secs_f64();
    let build_memory_mib = [
        rss_gen,
        rss_model,
        rss(),
        crate::bench::peak_memory_mib().unwrap_or(f64::NAN),
    ];
    Ok(TrainBridgeModel {
        dofs: driver.neq(),
        driver,
        ids,
        track: tm,
        wheel_index,
        elements,
        nodes,
        element_length: longest,
        build_seconds: [t_gen, t_build, t_driver],
        build_memory_mib,
        duration,
        quake,
    })
}

/// The record `q`'s ground motion as loads of the model (`−M·r·a_g(t)` along each axis
/// the record moves).
pub(crate) fn ground_motion(b: &mut ModelBuilder, q: &QuakeRecord) {
    for (c, dir) in [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]
        .iter()
        .enumerate()
    {
        if q.a[c].iter().all(|v| *v == 0.0) {
            continue;
        }
        let points = q.t.iter().zip(&q.a[c]).map(|(t, a)| [*t, *a]).collect();
        b.load(LoadSpec::GroundMotion {
            direction: *dir,
            series: TimeSeries::Table { points },
            scale: 1.0,
        });
    }
}

/// The viaduct of `case` alone, for the reduced far field's checks (`crate::far_field`) (its spans, approaches and mesh; no train, no gravity) under the
/// ground motion `quake`, with the partitioned solver at `block_size` interior equations
/// per block and `case`'s integrator and step: a driver ready to step, with the track
/// model (for its midspan nodes).
pub fn viaduct_under_ground_motion(
    case: &TrainBridgeCase,
    quake: &QuakeRecord,
    block_size: usize,
) -> Result<(Driver, Arc<TrackModel>), FemError> {
    let mut b = ModelBuilder::new("far-field viaduct");
    let tm = track_model::generate(
        &mut b,
        Arc::new(case.track()?),
        &case.mesh(case.element_length),
    )?;
    b.analysis(AnalysisSpec {
        dt: case.dt,
        duration: case.duration.unwrap_or(1.0),
        integrator: case.integrator.clone(),
        rho_inf: case.rho_inf,
        alpha: (1.0 - case.rho_inf) / (1.0 + case.rho_inf),
        solver: crate::framework::model::SolverChoice::Partitioned,
        block_size: Some(block_size),
        initial_static: false,
        ..Default::default()
    });
    ground_motion(&mut b, quake);
    Ok((Driver::new(b.build()?)?, tm))
}

/// The round-off floor of the residual norm (N) on the mesh of `tm` with girders of
/// section `g` (the case's bridge, [`RailSection::pc_box_girder`]). A girder node's
/// vertical force is the sum of bending terms `12·E·I/h³·w` of its two elements — for the
/// PC box girder on h = 0.0347 m, 1.1e17 N/m × 6.5 mm (the self-weight deflection of a
/// 29.75 m span) = 7e14 N — cancelling to a nodal load of a few kN; rounding leaves about
/// `ε·12·E·I/h³·w` per node, with `w` = 10 mm (a bound on that deflection) and `h` the
/// shortest element, and the norm over the `n` girder nodes `√n` times that. Three spans:
/// 17 N at h = 0.0347 m (shortest elements 0.031 m; the preload stalled there at 0.05 N
/// under the old 0.01 N), 1.5 N at 0.0694 m, 0.066 N at 0.625 m (shortest 0.125 m); 113
/// spans at 0.625 m: 0.40 N. Against a static wheel load of 68.7 kN.
pub fn residual_floor(tm: &TrackModel, g: &RailSection) -> f64 {
    let h = tm
        .stations
        .windows(2)
        .map(|w| w[1] - w[0])
        .fold(f64::INFINITY, f64::min);
    let nodes: u64 = tm.bridge.as_ref().map_or(0, |b| {
        b.spans.iter().map(|s| s.last_node - s.first_node + 1).sum()
    });
    f64::EPSILON * 12.0 * g.e * g.i_vertical / h.powi(3) * 0.01 * (nodes as f64).sqrt()
}

/// Extremes of one wheel over a run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WheelExtremes {
    /// Largest Y/Q and its time (s).
    pub max_yq: (f64, f64),
    /// Largest ΔQ/Q and its time (s).
    pub max_dqq: (f64, f64),
    /// Smallest Q (N) and its time (s).
    pub min_q: (f64, f64),
    /// Mean Q over the recorded samples (N).
    pub mean_q: f64,
}

/// What a run found.
#[derive(Debug, Clone, PartialEq)]
pub struct TrainBridgeReport {
    /// Wheel names (`w<axle>L`/`w<axle>R`, axles numbered from the front).
    pub wheel_names: Vec<String>,
    /// Per wheel: Q (N) at the initial equilibrium; ΔQ/Q = (Q_static − Q)/Q_static.
    pub q_static: Vec<f64>,
    /// Per wheel extremes.
    pub wheels: Vec<WheelExtremes>,
    /// Recorded spans (1-based) and their history from t = 0 (the initial equilibrium): (t,
    /// girder midspan deflection relative to the span's end nodes, m, positive down).
    pub midspan: Vec<(usize, Vec<(f64, f64)>)>,
    /// Recorded spans (1-based), the largest |vertical acceleration| of their girder
    /// midspan node over the recorded samples (m/s², relative to the ground, which is the
    /// absolute one without ground motion) and its time (s).
    pub deck_acc: Vec<(usize, f64, f64)>,
    /// Steps run.
    pub steps: usize,
    /// Newton iterations.
    pub iterations: usize,
    /// Wall time of the stepping (s).
    pub wall: f64,
    /// The activity window's counters (`None`: no window).
    pub window: Option<crate::solvers::window::WindowStats>,
    /// Why `auto` left the window off (`None`: it ran, or it was not asked for).
    pub window_off: Option<&'static str>,
    /// The reduced far field's counters (`None`: full).
    pub far_field: Option<crate::far_field::FarFieldStats>,
}

fn output(d: &Driver, ei: usize, pos: &[usize; 4], buf: &mut Vec<f64>) -> [f64; 4] {
    buf.clear();
    d.model.elements[ei].element.outputs(buf);
    [buf[pos[0]], buf[pos[1]], buf[pos[2]], buf[pos[3]]]
}

/// Girder midspan deflection of span `k` (0-based) relative to its end nodes, positive down.
fn midspan_deflection(d: &Driver, tm: &TrackModel, k: usize) -> f64 {
    let br = tm.bridge.as_ref().expect("a bridge");
    let s = &br.spans[k];
    let w = |id: u64| {
        d.displacement(id, crate::framework::Dof::Uz)
            .unwrap_or(f64::NAN)
    };
    0.5 * (w(s.first_node) + w(s.last_node)) - w(s.midspan_node)
}

/// Vertical acceleration of the girder midspan node of span `k` (0-based), m/s².
fn midspan_acceleration(d: &Driver, tm: &TrackModel, k: usize) -> f64 {
    let br = tm.bridge.as_ref().expect("a bridge");
    d.model
        .node(br.spans[k].midspan_node)
        .map_or(f64::NAN, |i| {
            d.asm.dofmap.value(&d.state.a, i, crate::framework::Dof::Uz)
        })
}

/// Runs a built model for `steps` steps (all, if `None`), writing `wheels.csv`,
/// `midspan.csv` and `summary.csv` into `out` when given.
pub fn run(
    m: &mut TrainBridgeModel,
    case: &TrainBridgeCase,
    steps: Option<usize>,
    out: Option<&Path>,
) -> Result<TrainBridgeReport, FemError> {
    let start = Instant::now();
    let d = &mut m.driver;
    // Preload in increments (the wheels' power-law springs are soft at zero force).
    d.static_solve(0.0, 10)?;
    d.initialize()?;
    let track = case.window_track();
    let mut window = crate::train_window::open(d, case.window, &track)?;
    if let Some(w) = window.as_mut() {
        let reach = w.settings().ahead;
        w.set_absorbing_layer(crate::train_window::layer(reach, case.window_layer));
    }
    let window_off = match case.window {
        crate::train_window::WindowChoice::Auto(_) => {
            crate::train_window::auto_off_reason(d, &track)
        }
        _ => None,
    };
    let mut far = crate::far_field::open(d, case.far_field, &track, case.dt, window.is_some())?;
    let names = d.model.elements[m.wheel_index[0]].element.output_names();
    let find = |k: &str| {
        names
            .iter()
            .position(|n| n == k)
            .expect("moving_axle output")
    };
    let pos = [find("Q"), find("Y"), find("YQ"), find("dQQ")];
    // ΔQ/Q is taken against each wheel's Q at the initial equilibrium (the element's own
    // `dQQ` refers to the first load increment of the preload).
    let nw = m.wheel_index.len();
    let wheel_names: Vec<String> = (0..nw)
        .map(|i| format!("w{}{}", i / 2 + 1, if i % 2 == 0 { "L" } else { "R" }))
        .collect();
    let spans: Vec<usize> = if case.midspans.is_empty() {
        (1..=case.spans).collect()
    } else {
        case.midspans.clone()
    };
    let mut buf = Vec::new();
    let q_static: Vec<f64> = m
        .wheel_index
        .iter()
        .map(|&ei| output(d, ei, &pos, &mut buf)[0])
        .collect();
    let mut ext = vec![
        WheelExtremes {
            max_yq: (f64::NEG_INFINITY, 0.0),
            max_dqq: (f64::NEG_INFINITY, 0.0),
            min_q: (f64::INFINITY, 0.0),
            mean_q: 0.0,
        };
        nw
    ];
    let mut midspan: Vec<(usize, Vec<(f64, f64)>)> =
        spans.iter().map(|k| (*k, Vec::new())).collect();
    let mut deck_acc: Vec<(usize, f64, f64)> = spans.iter().map(|k| (*k, 0.0, 0.0)).collect();
    let mut files = None;
    if let Some(dir) = out {
        std::fs::create_dir_all(dir).map_err(|e| FemError::output(dir, e))?;
        let open = |n: &str| {
            let p = dir.join(n);
            std::fs::File::create(&p)
                .map(std::io::BufWriter::new)
                .map_err(|e| FemError::output(&p, e))
        };
        let mut wf = open("wheels.csv")?;
        let mut mf = open("midspan.csv")?;
        let mut head = String::from("time [s]");
        for n in &wheel_names {
            for (q, unit) in [("Q", "N"), ("Y", "N"), ("YQ", "-"), ("dQQ", "-")] {
                head.push_str(&format!(",{n}_{q} [{unit}]"));
            }
        }
        writeln!(wf, "{head}").map_err(|e| FemError::output(dir, e))?;
        let mh: Vec<String> = spans.iter().map(|k| format!("span{k} [m]")).collect();
        writeln!(mf, "time [s],{}", mh.join(",")).map_err(|e| FemError::output(dir, e))?;
        files = Some((wf, mf));
    }
    // The initial state (self-weight, train at rest on the approach) as the first sample.
    let mut mrow = String::from("0");
    for (sk, hist) in midspan.iter_mut() {
        let w = midspan_deflection(d, &m.track, *sk - 1);
        hist.push((d.state.t, w));
        mrow.push_str(&format!(",{w:.6e}"));
    }
    if let Some((_, mf)) = files.as_mut() {
        writeln!(mf, "{mrow}").map_err(|e| FemError::output("midspan.csv", e))?;
    }
    let dt = case.dt;
    let total_f = steps.map_or((m.duration / dt).round(), |n| n as f64);
    limits::check_steps(
        &format!(
            "--duration {} s at --dt {} s",
            fmt_num(m.duration),
            fmt_num(dt)
        ),
        total_f,
        "give a larger --dt or a shorter --duration",
    )
    .map_err(|m| FemError::input("command line", m))?;
    let total = total_f as usize;
    let every = case.record_every.max(1);
    let mut iterations = 0;
    let mut samples = 0usize;
    let mut interrupted = None;
    let mut bar = crate::progress::Progress::new("train-bridge", total as u64, "steps");
    for k in 1..=total {
        if let Some(w) = window.as_mut() {
            let [rear, front] = crate::train_window::train_extent(&track, d.state.t);
            w.update(d, rear, front)?;
            d.set_promotion_form(crate::train_window::promotion_form(w));
        }
        if let Some(f) = far.as_mut() {
            f.update(d)?;
        }
        let r = d.step(dt)?;
        iterations += r.iterations;
        bar.set(k as u64);
        // Asked to stop (SIGINT/SIGTERM, on any rank): record this step, then end as a whole
        // run would.
        let stop = d.stop_requested() && k < total;
        if stop {
            interrupted = Some(d.state.t);
        }
        if k % every != 0 && k != total && !stop {
            continue;
        }
        let t = d.state.t;
        samples += 1;
        let mut row = format!("{t}");
        for (w, &ei) in m.wheel_index.iter().enumerate() {
            let [q, y, yq, _] = output(d, ei, &pos, &mut buf);
            let dqq = (q_static[w] - q) / q_static[w];
            let e = &mut ext[w];
            if yq > e.max_yq.0 {
                e.max_yq = (yq, t);
            }
            if dqq > e.max_dqq.0 {
                e.max_dqq = (dqq, t);
            }
            if q < e.min_q.0 {
                e.min_q = (q, t);
            }
            e.mean_q += q;
            if files.is_some() {
                row.push_str(&format!(",{q:.6e},{y:.6e},{yq:.6e},{dqq:.6e}"));
            }
        }
        let mut mrow = format!("{t}");
        for (sk, hist) in midspan.iter_mut() {
            let w = midspan_deflection(d, &m.track, *sk - 1);
            hist.push((t, w));
            mrow.push_str(&format!(",{w:.6e}"));
        }
        for (sk, peak, tp) in deck_acc.iter_mut() {
            let az = midspan_acceleration(d, &m.track, *sk - 1).abs();
            if az > *peak {
                (*peak, *tp) = (az, t);
            }
        }
        if let Some((wf, mf)) = files.as_mut() {
            writeln!(wf, "{row}").map_err(|e| FemError::output("wheels.csv", e))?;
            writeln!(mf, "{mrow}").map_err(|e| FemError::output("midspan.csv", e))?;
        }
        if stop {
            break;
        }
    }
    bar.finish();
    for e in &mut ext {
        e.mean_q /= samples.max(1) as f64;
    }
    if let (Some(dir), Some((mut wf, mut mf))) = (out, files) {
        wf.flush().map_err(|e| FemError::output(dir, e))?;
        mf.flush().map_err(|e| FemError::output(dir, e))?;
        let mut s = String::from(
            "wheel [-],Q_static [N],max_YQ [-],t_max_YQ [s],max_dQQ [-],t_max_dQQ [s],min_Q [N],t_min_Q [s],mean_Q [N]\n",
        );
        for (i, e) in ext.iter().enumerate() {
            s.push_str(&format!(
                "{},{:.6e},{:.6e},{},{:.6e},{},{:.6e},{},{:.6e}\n",
                wheel_names[i],
                q_static[i],
                e.max_yq.0,
                e.max_yq.1,
                e.max_dqq.0,
                e.max_dqq.1,
                e.min_q.0,
                e.min_q.1,
                e.mean_q
            ));
        }
        s.push_str("\nspan [-],max_deflection [m],t [s]\n");
        for (k, h) in &midspan {
            let (t, w) = h.iter().fold((0.0, f64::NEG_INFINITY), |a, x| {
                if x.1 > a.1 {
                    (x.0, x.1)
                } else {
                    a
                }
            });
            s.push_str(&format!("{k},{w:.6e},{t}\n"));
        }
        let p = dir.join("summary.csv");
        std::fs::write(&p, s).map_err(|e| FemError::output(&p, e))?;
        // The energy ledger's rows (energy.csv): the balance a window is checked against.
        d.write_energy(dir)?;
    }
    if let Some(t) = interrupted {
        return Err(FemError::Interrupted { t });
    }
    Ok(TrainBridgeReport {
        wheel_names,
        q_static,
        wheels: ext,
        midspan,
        deck_acc,
        steps: total,
        iterations,
        wall: start.elapsed().as_secs_f64(),
        window: window.map(|w| w.stats()),
        window_off,
        far_field: far.map(|f| f.stats()),
    })
}

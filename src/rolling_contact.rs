//! Finite-element checks of rolling contact against the linear wheelset theory of
//! `railfem_elements::rail::contact::creep::linear_wheelset` (issue 14, docs/rolling-contact.md):
//! the Klingel oscillation of a free wheelset, the growth or decay of the hunting mode of a
//! suspended wheelset at a given speed, and steady curving of a suspended wheelset.
//!
//! What lives here: the model of one case, written as a model file ([`write_model`]), its
//! run through the ordinary driver ([`run`]), and the reading of the histories: zero
//! crossings and wavelength ([`wavelength`]), the growth rate of the envelope
//! ([`growth_rate`]). The tests (tests/rolling_contact.rs) run short versions; the long ones
//! with the tables of docs/rolling-contact.md are `cargo run --release --example
//! rolling_contact`.
//!
//! # The model
//!
//! One wheelset (`moving_axle` wheels with `tangential = "kalker_linear"` unless told
//! otherwise) on rigid track, 60E1 rails at 1:40, carried by a `[[vehicle]]` at constant
//! speed. Free case: the wheelset is the only body. Suspended case: a frame body above it,
//! joined by two `suspension`s at `±b1` (longitudinal `k_x`, lateral `k_y`, vertical `k_z`
//! each) and held by a `[[link]]` to a fixed node on every DOF but the vertical one: the
//! frame moves with the carrier, straight ahead along the track (laterally and in yaw it
//! is the track), and its weight loads the wheelset. The primary yaw stiffness is then
//! `2·k_x·b1²` and the lateral `2·k_y`.
//!
//! The initial lateral offset is an alignment irregularity of both rails: `offset` up to
//! station `start + 2 m`, a half-cosine down to zero over the next 2 m, zero beyond. The
//! wheelset starts centred on the shifted rails and meets the unshifted track with that
//! offset.

use crate::framework::FemError;
use crate::solvers::Driver;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// Node id of the wheelset's axle node (the first body of the vehicle, `first_node_id`
/// 100000: the vehicle's reference node is 100000, the first body 100001).
pub const AXLE_NODE: u64 = 100_001;
/// Node id of the frame body (the second body) in the suspended case.
pub const FRAME_NODE: u64 = 100_002;
/// Wheelset mass (kg) and inertias (kg·m²): the sks700 stand-in's wheelset.
pub const WHEELSET_MASS: f64 = 1813.0;
/// Roll and yaw inertia of the wheelset (kg·m²).
pub const WHEELSET_INERTIA: f64 = 1120.0;
/// Nominal rolling radius (m): the axle height.
pub const R0: f64 = 0.46;

/// The wheel profile of a case.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Wheel {
    /// A cone of slope λ (`z = λ·y` over −50…70 mm): no flange.
    Cone(f64),
    /// The built-in S1002.
    S1002,
}

/// Primary suspension of the suspended case.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Suspended {
    /// Longitudinal stiffness of each of the two springs (N/m).
    pub kx: f64,
    /// Lateral stiffness of each spring (N/m).
    pub ky: f64,
    /// Vertical stiffness of each spring (N/m).
    pub kz: f64,
    /// Lateral semi-spacing b1 of the springs (m).
    pub b1: f64,
    /// Frame mass (kg): with the wheelset's, it sets the axle load.
    pub frame_mass: f64,
}

impl Suspended {
    /// Primary yaw stiffness `2·k_x·b1²` (N·m/rad).
    pub fn yaw(&self) -> f64 {
        2.0 * self.kx * self.b1 * self.b1
    }
    /// Primary lateral stiffness `2·k_y` (N/m).
    pub fn lateral(&self) -> f64 {
        2.0 * self.ky
    }
}

/// One FE case.
#[derive(Debug, Clone, PartialEq)]
pub struct Case {
    /// Wheel profile.
    pub wheel: Wheel,
    /// Speed (m/s).
    pub speed: f64,
    /// Distance run (m).
    pub distance: f64,
    /// Time step (s).
    pub dt: f64,
    /// Initial lateral offset (m).
    pub offset: f64,
    /// Primary suspension (None: free wheelset).
    pub suspended: Option<Suspended>,
    /// Radius of a left-hand curve (m) reached after 20 m straight and a 40 m clothoid;
    /// None: straight track.
    pub curve_radius: Option<f64>,
    /// Tangential law of the wheels.
    pub tangential: crate::elements::rail::contact::creep::law::Tangential,
    /// Rail profile nodes of the 60E1 head.
    pub rail_nodes: usize,
}

impl Case {
    /// A free wheelset on cones of slope `lambda` at `speed`, over `distance`.
    pub fn klingel(wheel: Wheel, speed: f64, distance: f64) -> Self {
        Self {
            wheel,
            speed,
            distance,
            dt: 0.002,
            offset: 2e-3,
            suspended: None,
            curve_radius: None,
            tangential: crate::elements::rail::contact::creep::law::Tangential::KalkerLinear,
            rail_nodes: 41,
        }
    }
}

/// The slope of the 60E1 head (built-in, `rail_nodes` nodes, 1:40) at node `node` of the
/// left rail: the chord between its neighbours, which on a circular arc sampled at equal
/// arc lengths is exactly parallel to the tangent at the node. A cone of this slope touches
/// that one node (a knife edge) over a band of rolls of ± half the angle between chords.
pub fn node_tangent_slope(rail_nodes: usize, node: usize) -> f64 {
    use crate::elements::rail::contact::profiles::{Inclination, RailProfile};
    let r = RailProfile::uic60(rail_nodes, Inclination::OneIn40);
    let n = r.nodes();
    let d = n[node + 1] - n[node - 1];
    // The wheel surface z = λ·y rises towards the field side; the rail there must fall away
    // from it: its tangent at the contact is the wheel's, slope d.y/d.x.
    d.y / d.x
}

/// Histories of a run, one entry per step.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct History {
    /// Time (s).
    pub t: Vec<f64>,
    /// Station of the wheelset (m).
    pub station: Vec<f64>,
    /// Lateral displacement of the axle node (m, left positive).
    pub y: Vec<f64>,
    /// Yaw of the axle node (rad, nose to the left positive).
    pub yaw: Vec<f64>,
    /// Lateral distance of the left and right wheels' contact points from the centre line
    /// (m), the `contact_y` outputs (the right one's magnitude).
    pub contact_left: Vec<f64>,
    /// See `contact_left`.
    pub contact_right: Vec<f64>,
}

/// Station at t = 0 (m).
pub const START: f64 = 2.0;

/// The alignment table (CSV, mm) of a lateral step of both rails: `offset` (m) up to
/// station `ramp` (m), a half-cosine down to zero over the next 2 m, zero beyond; a row
/// every 0.25 m up to `ramp + 6 m` and one at `end`. The irregularity is a not-a-knot cubic
/// spline through the rows, so the step must be sampled densely: through the sparse knots
/// 0, 42, 42.5, …, 44 and 400 m (the sks700 case's table before this helper) the spline
/// swings to −232 mm at 10 m and +2.6 m at 100 m instead of a 2 mm step — the carriage's
/// wheelsets then followed rails that veered sideways (docs/rolling-contact.md). Between
/// densely sampled flat rows the spline's ringing from the ramp decays by about 0.27 per
/// row.
fn step_alignment(offset: f64, ramp: f64, end: f64) -> String {
    let mut align = String::from("station [m],alignment [mm]\n");
    let rows = ((ramp + 6.0) / 0.25).round() as usize;
    for i in 0..=rows {
        let s = i as f64 * 0.25;
        let _ = writeln!(align, "{s},{}", step_shape(s, ramp) * offset * 1e3);
    }
    let _ = writeln!(align, "{end},0");
    align
}

/// The step of [`step_alignment`] in units of its height at station `s`: 1 up to `ramp`,
/// `½(1 + cos(π(s − ramp)/2))` over the next 2 m, 0 beyond.
fn step_shape(s: f64, ramp: f64) -> f64 {
    if s <= ramp {
        1.0
    } else if s >= ramp + 2.0 {
        0.0
    } else {
        0.5 * (1.0 + (std::f64::consts::PI * (s - ramp) / 2.0).cos())
    }
}

/// Writes the model of `case` and its profile/irregularity tables into `dir`; returns the
/// model path.
pub fn write_model(case: &Case, dir: &Path) -> Result<PathBuf, FemError> {
    let io = |e: std::io::Error| FemError::input(dir.display().to_string(), e.to_string());
    std::fs::create_dir_all(dir).map_err(io)?;
    let align = step_alignment(case.offset, START + 2.0, START + case.distance + 100.0);
    std::fs::write(dir.join("align.csv"), align).map_err(io)?;
    let wheel_keys = match case.wheel {
        Wheel::Cone(lambda) => {
            let mut cone = String::from("y_mm,z_mm\n");
            for y in [-50.0, -10.0, 30.0, 70.0] {
                let _ = writeln!(cone, "{y},{}", lambda * y);
            }
            std::fs::write(dir.join("cone.csv"), cone).map_err(io)?;
            // A wheel profile path is read as given (relative to the working directory).
            format!("wheel_profile = \"{}\", ", dir.join("cone.csv").display())
        }
        Wheel::S1002 => String::new(),
    };
    let wheel = format!(
        "{{model = \"moving_axle\", {wheel_keys}rail_nodes = {}, tangential = \"{}\"}}",
        case.rail_nodes,
        case.tangential.name()
    );
    let track = match case.curve_radius {
        None => format!(
            "[{{type = \"straight\", length = {}}}]",
            START + case.distance + 50.0
        ),
        Some(r) => format!(
            "[{{type = \"straight\", length = 20.0}}, {{type = \"clothoid\", length = 40.0, to_curvature = {}}}, {{type = \"arc\", length = {}, radius = {r}, hand = \"left\"}}]",
            1.0 / r,
            case.distance + 50.0
        ),
    };
    let steps = (case.distance / case.speed / case.dt).round().max(1.0);
    let mut text = format!(
        r#"# Generated by railfem::rolling_contact (issue 14 checks).
[analysis]
kind = "transient"
dt = {dt}
duration = {duration}
gravity = [0.0, 0.0, -9.81]

[track]
segments = {track}
support = {{type = "rigid"}}
irregularity = {{file = "align.csv", components = ["alignment"]}}

[[node]]
id = 1
xyz = [0.0, 0.0, -10.0]
fix = "all"

[[vehicle]]
name = "ws"
start = {START}
speed = {speed}
first_node_id = 100000
length = 3.0
"#,
        dt = case.dt,
        duration = steps * case.dt,
        speed = case.speed,
    );
    let axle = format!(
        "{{name = \"axle\", mass = {WHEELSET_MASS}, ixx = {WHEELSET_INERTIA}, iyy = 112.0, izz = {WHEELSET_INERTIA}, z = {R0}}}"
    );
    match case.suspended {
        None => {
            let _ = writeln!(text, "body = [{axle}]");
        }
        Some(s) => {
            let _ = writeln!(
                text,
                "body = [{axle}, {{name = \"frame\", mass = {}, ixx = 2000.0, iyy = 2000.0, izz = 2000.0, z = 0.8}}]",
                s.frame_mass
            );
            let _ = writeln!(
                text,
                "suspension = [{{lower = \"axle\", upper = \"frame\", at = [0.0, {}, {R0}], k = [{}, {}, {}], mirror = true}}]",
                s.b1, s.kx, s.ky, s.kz
            );
        }
    }
    let _ = writeln!(text, "wheelset = [{{body = \"axle\", wheel = {wheel}}}]");
    if case.suspended.is_some() {
        let _ = writeln!(
            text,
            "\n[[link]]\nmaster = 1\nslave = {FRAME_NODE}\ndofs = [\"ux\", \"uz\", \"rx\", \"ry\", \"rz\"]"
        );
    }
    let path = dir.join("model.toml");
    std::fs::write(&path, text).map_err(io)?;
    Ok(path)
}

/// Runs `case` (model written into `dir`) and returns its histories.
pub fn run(case: &Case, dir: &Path) -> Result<History, FemError> {
    let path = write_model(case, dir)?;
    let model = crate::load_model(&path)?;
    let mut d = Driver::new(model)?;
    d.initialize()?;
    let wheels: Vec<usize> = d
        .model
        .elements
        .iter()
        .enumerate()
        .filter(|(_, e)| e.element.output_names().iter().any(|n| n == "contact_y"))
        .map(|(i, _)| i)
        .collect();
    if wheels.len() != 2 {
        return Err(FemError::input(
            path.display().to_string(),
            format!(
                "expected two wheels with a `contact_y` output, found {}",
                wheels.len()
            ),
        ));
    }
    let names = d.model.elements[wheels[0]].element.output_names();
    let col = |n: &str| names.iter().position(|x| x == n);
    let (i_station, i_cy) = (col("station"), col("contact_y"));
    let mut h = History::default();
    let record = |d: &Driver, h: &mut History| {
        let mut o = Vec::new();
        let mut read = |k: usize| {
            o.clear();
            d.model.elements[wheels[k]].element.outputs(&mut o);
            (
                i_station.map_or(f64::NAN, |i| o[i]),
                i_cy.map_or(f64::NAN, |i| o[i].abs()),
            )
        };
        let (station, left) = read(0);
        let (_, right) = read(1);
        h.t.push(d.state.t);
        h.station.push(station);
        h.y.push(
            d.displacement(AXLE_NODE, crate::framework::Dof::Ux)
                .unwrap_or(f64::NAN),
        );
        h.yaw.push(
            d.displacement(AXLE_NODE, crate::framework::Dof::Ry)
                .unwrap_or(f64::NAN),
        );
        h.contact_left.push(left);
        h.contact_right.push(right);
    };
    record(&d, &mut h);
    let steps = (case.distance / case.speed / case.dt).round().max(1.0) as usize;
    for _ in 0..steps {
        crate::framework::interrupt::check(d.state.t)?;
        d.step(case.dt)?;
        record(&d, &mut h);
    }
    Ok(h)
}

/// Abscissae `x` where `y` changes sign, by linear interpolation, for `x ≥ from`.
pub fn zero_crossings(x: &[f64], y: &[f64], from: f64) -> Vec<f64> {
    let mut out = Vec::new();
    for i in 1..x.len().min(y.len()) {
        if x[i - 1] < from {
            continue;
        }
        let (a, b) = (y[i - 1], y[i]);
        if (a < 0.0 && b >= 0.0) || (a > 0.0 && b <= 0.0) {
            out.push(x[i - 1] + (x[i] - x[i - 1]) * a / (a - b));
        }
    }
    out
}

/// Wavelength (units of `x`) from the zero crossings after `from`: twice the mean spacing of
/// consecutive crossings, from the first to the last (at least three crossings, one full
/// wave). None with fewer.
pub fn wavelength(x: &[f64], y: &[f64], from: f64) -> Option<f64> {
    let z = zero_crossings(x, y, from);
    (z.len() >= 3).then(|| 2.0 * (z[z.len() - 1] - z[0]) / (z.len() - 1) as f64)
}

/// Growth rate σ (1/s) of an oscillation `y(t)` after `from`: the least-squares slope of
/// `ln|y|` at the extrema between zero crossings (one per half wave). Positive: growing.
/// None with fewer than three half waves.
pub fn growth_rate(t: &[f64], y: &[f64], from: f64) -> Option<f64> {
    let z = zero_crossings(t, y, from);
    let mut pts = Vec::new();
    for w in z.windows(2) {
        let (mut best, mut tb) = (0.0f64, 0.0);
        for (ti, yi) in t.iter().zip(y) {
            if *ti > w[0] && *ti < w[1] && yi.abs() > best {
                best = yi.abs();
                tb = *ti;
            }
        }
        if best > 0.0 {
            pts.push((tb, best.ln()));
        }
    }
    if pts.len() < 3 {
        return None;
    }
    let n = pts.len() as f64;
    let (mt, ml) = (
        pts.iter().map(|p| p.0).sum::<f64>() / n,
        pts.iter().map(|p| p.1).sum::<f64>() / n,
    );
    let num: f64 = pts.iter().map(|p| (p.0 - mt) * (p.1 - ml)).sum();
    let den: f64 = pts.iter().map(|p| (p.0 - mt).powi(2)).sum();
    Some(num / den)
}

/// The response of an angle history `a` (rad) to a disturbance that ends before station
/// `from` (m): the growth rate σ of its envelope about its mean after `from` (1/s,
/// [`growth_rate`]; `None` below three half waves), its largest deviation from that mean
/// there (rad) and the wavelength of its zero crossings (m, [`wavelength`]). `t` and `s`
/// are the times and stations of the samples.
pub fn step_response(
    t: &[f64],
    s: &[f64],
    a: &[f64],
    from: f64,
) -> (Option<f64>, f64, Option<f64>) {
    let m = mean_between(s, a, from, 1e9);
    let centred: Vec<f64> = a.iter().map(|x| x - m).collect();
    let t_from = t[s.partition_point(|x| *x < from).min(t.len() - 1)];
    let peak = centred
        .iter()
        .zip(s)
        .filter(|(_, s)| **s > from)
        .fold(0.0f64, |p, (x, _)| p.max(x.abs()));
    (
        growth_rate(t, &centred, t_from),
        peak,
        wavelength(s, &centred, from),
    )
}

/// Mean of `v` over the entries whose `x` lies in `[from, to]`.
pub fn mean_between(x: &[f64], v: &[f64], from: f64, to: f64) -> f64 {
    let (mut s, mut n) = (0.0, 0);
    for (xi, vi) in x.iter().zip(v) {
        if (from..=to).contains(xi) {
            s += vi;
            n += 1;
        }
    }
    s / n.max(1) as f64
}

/// Gravity of the models (m/s²).
pub const GRAVITY: f64 = 9.81;
/// Shear modulus and Poisson's ratio of the `moving_axle` creep laws' defaults.
pub const SHEAR_MODULUS: f64 = 8.0e10;
/// See [`SHEAR_MODULUS`].
pub const POISSON: f64 = 0.28;
/// Transverse curvature of the 60E1 crown (1/m), R 300 mm.
pub const CROWN_CURVATURE: f64 = 1.0 / 0.3;

/// The linear wheelset model of a cone case whose contact is a single rail node on the
/// crown (a knife edge, [`node_tangent_slope`]), with the half contact distance `b` (m)
/// measured in the FE run: the axle load `W = (m_w + m_frame)·g`, Kalker's `f11, f22, f23`
/// of the Hertz ellipse at `N = W/2` (cone: no transverse wheel curvature; the crown's),
/// `ε' = 2λ/b` (a rolled cone on knife edges, `δ_L,R = atan λ ± φ`, `φ = λy/b`), the
/// gravitational stiffness `(W/2)·ε'` and the spin terms of the element.
pub fn linear_model(
    case: &Case,
    b: f64,
) -> Result<
    (
        crate::elements::rail::contact::creep::linear_wheelset::Wheelset,
        crate::elements::rail::contact::creep::linear_wheelset::Primary,
    ),
    FemError,
> {
    use crate::elements::rail::contact::creep::linear_wheelset::{
        creep_coefficients, Primary, Wheelset,
    };
    let lambda = match case.wheel {
        Wheel::Cone(l) => l,
        Wheel::S1002 => {
            return Err(FemError::input(
                "rolling_contact::linear_model",
                "only cone cases have a closed-form contact geometry; give Wheel::Cone",
            ))
        }
    };
    let frame = case.suspended.map_or(0.0, |s| s.frame_mass);
    let w = (WHEELSET_MASS + frame) * GRAVITY;
    let young = 2.0 * SHEAR_MODULUS * (1.0 + POISSON);
    let (f11, f22, f23) = creep_coefficients(R0, 0.0, CROWN_CURVATURE, 0.5 * w, young, POISSON)
        .map_err(|e| FemError::input("rolling_contact::linear_model", e.to_string()))?;
    let slope = 2.0 * lambda / b;
    let ws = Wheelset {
        mass: WHEELSET_MASS,
        yaw_inertia: WHEELSET_INERTIA,
        rolling_radius: R0,
        half_gauge: b,
        conicity: lambda,
        f11,
        f22,
        gravitational_stiffness: 0.5 * w * slope,
        f23,
        contact_angle_slope: slope,
    };
    let primary = case.suspended.map_or(Primary::default(), |s| Primary {
        lateral: s.lateral(),
        yaw: s.yaw(),
    });
    Ok((ws, primary))
}

/// Time (s), station (m) and angle of attack (rad) histories of the leading wheel.
pub type AttackHistory = (Vec<f64>, Vec<f64>, Vec<f64>);

/// The sks700 carriage (preset, S1002 on 60E1 at 1:40, `tangential = "kalker_linear"`)
/// on rigid straight track with the same alignment step of `offset` (m) at speed `speed`,
/// over `distance`: the time, station and the leading wheel's angle of attack (its
/// `attack_angle` output, rad) per step.
pub fn run_sks700(
    speed: f64,
    dt: f64,
    distance: f64,
    offset: f64,
    dir: &Path,
) -> Result<AttackHistory, FemError> {
    let case = Case {
        offset,
        distance,
        ..Case::klingel(Wheel::S1002, speed, distance)
    };
    write_model(&case, dir)?;
    // The carriage spans about ±9.3 m about its centre: it starts at 30 m, every
    // wheelset on rails shifted by `offset`, which return to zero over 42–44 m.
    const SKS_START: f64 = 30.0;
    let align = step_alignment(offset, 42.0, SKS_START + distance + 100.0);
    std::fs::write(dir.join("align.csv"), align)
        .map_err(|e| FemError::input(dir.display().to_string(), e.to_string()))?;
    let steps = (distance / speed / dt).round().max(1.0);
    let text = format!(
        r#"[analysis]
kind = "transient"
dt = {dt}
duration = {duration}
gravity = [0.0, 0.0, -9.81]

[track]
segments = [{{type = "straight", length = {length}}}]
support = {{type = "rigid"}}
irregularity = {{file = "align.csv", components = ["alignment"]}}

[[vehicle]]
preset = "sks700"
start = {SKS_START}
speed = {speed}
wheel = {{tangential = "kalker_linear"}}
"#,
        duration = steps * dt,
        length = SKS_START + distance + 60.0,
    );
    let path = dir.join("sks700.toml");
    std::fs::write(&path, text)
        .map_err(|e| FemError::input(path.display().to_string(), e.to_string()))?;
    let model = crate::load_model(&path)?;
    let mut d = Driver::new(model)?;
    d.initialize()?;
    let first = d
        .model
        .elements
        .iter()
        .position(|e| e.element.output_names().iter().any(|n| n == "attack_angle"))
        .ok_or_else(|| {
            FemError::input(
                path.display().to_string(),
                "no wheel with an `attack_angle` output",
            )
        })?;
    let names = d.model.elements[first].element.output_names();
    let (ia, is) = (
        names.iter().position(|n| n == "attack_angle").unwrap_or(0),
        names.iter().position(|n| n == "station").unwrap_or(0),
    );
    let (mut t, mut s, mut a) = (Vec::new(), Vec::new(), Vec::new());
    let mut o = Vec::new();
    for k in 0..=steps as usize {
        if k > 0 {
            crate::framework::interrupt::check(d.state.t)?;
            d.step(dt)?;
        }
        o.clear();
        d.model.elements[first].element.outputs(&mut o);
        t.push(d.state.t);
        s.push(o[is]);
        a.push(o[ia]);
    }
    Ok((t, s, a))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::elements::rail::geometry::irregularity::csv::read_table;
    use crate::elements::rail::geometry::irregularity::IrregularityPart;

    /// Largest deviation (in units of the step) of the spline through an alignment table
    /// from the intended step — `offset` up to `ramp`, the half-cosine over 2 m, zero
    /// beyond — sampled every 5 cm on [0, end], away from the ramp and on it.
    fn step_error(csv: &str, ramp: f64, end: f64) -> (f64, f64) {
        let table = read_table(csv, "align.csv").unwrap();
        let part = IrregularityPart::from_table(&table, "align.csv").unwrap();
        let spline = &part.splines[0].1;
        let plateau = spline.value(0.0);
        let (mut away, mut on) = (0.0f64, 0.0f64);
        for i in 0..=(end / 0.05) as usize {
            let s = i as f64 * 0.05;
            let e = (spline.value(s) / plateau - step_shape(s, ramp)).abs();
            if s > ramp - 1.0 && s < ramp + 3.0 {
                on = on.max(e);
            } else {
                away = away.max(e);
            }
        }
        (away, on)
    }

    /// The irregularity is a not-a-knot cubic spline through the table's rows: the sks700
    /// case's step must come out as a step. Through `step_alignment`'s rows (every 0.25 m to
    /// 6 m past the ramp) the spline stays within 1e-3 of the step away from the ramp and
    /// 1 % on it (a half-cosine sampled eight times per half wave); through the sparse
    /// knots the case used before (0, 42–44 m by 0.5 m, the end), the same check fails by
    /// a factor of more than 100 (the spline swings hundreds of millimetres off a 2 mm step).
    #[test]
    fn the_alignment_step_is_a_step() {
        let (ramp, end) = (42.0, 400.0);
        let (away, on) = step_error(&step_alignment(2e-3, ramp, end), ramp, end);
        println!("dense rows: away {away:.2e}, on the ramp {on:.2e}");
        assert!(away < 1e-3 && on < 1e-2, "{away} {on}");
        let mut sparse = String::from("station [m],alignment [mm]\n");
        for (st, a) in [
            (0.0, 2.0),
            (42.0, 2.0),
            (42.5, 1.7071),
            (43.0, 1.0),
            (43.5, 0.2929),
        ] {
            let _ = writeln!(sparse, "{st},{a}");
        }
        let _ = writeln!(sparse, "44,0\n{end},0");
        let (away, _) = step_error(&sparse, ramp, end);
        println!("sparse knots: away {away:.2e} (in units of the 2 mm step)");
        assert!(away > 100.0, "{away}");
    }

    #[test]
    fn a_sampled_sine_gives_its_wavelength_and_growth() {
        // y = e^{σt} sin(2πt/T): crossings every T/2, peaks grow by e^{σT/2}.
        let (period, sigma) = (1.7, 0.3);
        let t: Vec<f64> = (0..20000).map(|i| i as f64 * 1e-3).collect();
        let y: Vec<f64> = t
            .iter()
            .map(|t| (sigma * t).exp() * (2.0 * std::f64::consts::PI * t / period).sin())
            .collect();
        let w = wavelength(&t, &y, 0.1).unwrap();
        assert!((w / period - 1.0).abs() < 1e-5, "{w}");
        // The extremum of e^{σt}sin lies a fixed phase before the sine's peak, the same in
        // every half wave, so the slope of ln|peak| is σ up to the sampling (1e-3 s).
        let g = growth_rate(&t, &y, 0.1).unwrap();
        assert!((g / sigma - 1.0).abs() < 1e-3, "{g}");
    }
}

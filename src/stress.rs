//! The numerical stress suite: small models pushed to the edges of the integrators and of the
//! contact element — ω·Δt from 0.01 to 1000 on linear models, the contact penalty from 1e6
//! to 1e13 N/m, rolling speeds up to 150 m/s on flexible rails, a wheelset dropped on the
//! rail (repeated separation and re-contact) and a lateral force ramped through μ·N
//! (stick–slip). Each case returns one [`StressRow`]: converged or not, Newton iterations
//! per step, the energy error of the run and the largest error against its reference.
//! `railfem stress` runs the long versions and writes the table of `docs/stability.md`;
//! `tests/stability.rs` runs short ones and asserts on them. What does not live here: the
//! driver and the energy ledger ([`crate::solvers::energy`]).

use crate::elements::rail::contact::contact_law::Mode;
use crate::elements::rail::geometry::alignment::{Alignment, Segment};
use crate::elements::rail::geometry::cant::{Cant, Track};
use crate::elements::rail::geometry::track_model::{self, RailSupport, TrackMesh};
use crate::elements::rail::wheels::moving_axle::MovingAxle;
use crate::framework::builder::ModelBuilder;
use crate::framework::limits;
use crate::framework::loads::{LoadSpec, TimeSeries};
use crate::framework::model::{AnalysisSpec, IntegratorKind};
use crate::framework::moving::{Carrier, Path};
use crate::framework::{Dof, DofSet, FemError};
use crate::solvers::integrator::Integrator;
use crate::solvers::Driver;
use nalgebra::Matrix3;
use std::fmt::Write as _;
use std::sync::Arc;

/// One row of the stress table.
#[derive(Debug, Clone, PartialEq)]
pub struct StressRow {
    /// What was run.
    pub case: String,
    /// Whether every step converged.
    pub converged: bool,
    /// Newton iterations (linear solves) per step.
    pub newton_per_step: f64,
    /// Largest |energy balance residual| / largest energy (see
    /// [`crate::solvers::energy::EnergyLedger::relative_error`]); for a scheme with numerical
    /// damping this is the energy it removed, not an error.
    pub energy_error: f64,
    /// Largest relative error against the row's reference (see `reference`).
    pub force_error: f64,
    /// What the force error is measured against.
    pub reference: String,
    /// The error message of a run that stopped.
    pub failure: Option<String>,
    /// The `railfem stress` command that reproduces the row.
    pub command: String,
}

impl StressRow {
    fn failed(case: String, command: String, e: FemError) -> StressRow {
        StressRow {
            case,
            converged: false,
            newton_per_step: f64::NAN,
            energy_error: f64::NAN,
            force_error: f64::NAN,
            reference: String::new(),
            failure: Some(e.to_string()),
            command,
        }
    }
}

/// The integrator of a row: `newmark`, `hht:α` or `galpha:ρ∞` (for `bathe` and
/// `bathe:γ` see [`bathe_gamma`]).
pub fn scheme(name: &str) -> Result<(IntegratorKind, f64, f64), FemError> {
    let bad = || {
        FemError::input(
            "command line",
            format!("--scheme {name}: use newmark, hht:ALPHA (0..1/3), galpha:RHO (0..1), bathe or bathe:GAMMA (0..1)"),
        )
    };
    let (kind, val) = match name.split_once(':') {
        None if name == "newmark" => return Ok((IntegratorKind::Newmark, 0.0, 1.0)),
        Some((k, v)) => (k, v.parse::<f64>().map_err(|_| bad())?),
        None => return Err(bad()),
    };
    match kind {
        "hht" if (0.0..=1.0 / 3.0).contains(&val) => Ok((IntegratorKind::Hht, val, 1.0)),
        "galpha" if (0.0..=1.0).contains(&val) => Ok((IntegratorKind::GeneralizedAlpha, 0.0, val)),
        _ => Err(bad()),
    }
}

/// The splitting ratio γ of `bathe` (0.5) or `bathe:γ`; `None` for another scheme.
pub fn bathe_gamma(name: &str) -> Result<Option<f64>, FemError> {
    let bad = || {
        FemError::input(
            "command line",
            format!("--scheme {name}: use bathe or bathe:GAMMA with GAMMA in (0, 1)"),
        )
    };
    match name.split_once(':') {
        None if name == "bathe" => Ok(Some(0.5)),
        Some(("bathe", v)) => match v.parse::<f64>() {
            Ok(g) if g > 0.0 && g < 1.0 => Ok(Some(g)),
            _ => Err(bad()),
        },
        _ => Ok(None),
    }
}

fn analysis(scheme_name: &str, dt: f64) -> Result<AnalysisSpec, FemError> {
    let mut a = AnalysisSpec {
        dt,
        ..Default::default()
    };
    if let Some(g) = bathe_gamma(scheme_name)? {
        a.integrator = IntegratorKind::Registered("bathe".into());
        let mut p = serde_json::Map::new();
        p.insert("gamma".into(), g.into());
        a.integrator_parameters = Some(p);
    } else {
        (a.integrator, a.alpha, a.rho_inf) = scheme(scheme_name)?;
    }
    a.initial_static = false;
    Ok(a)
}

/// The SDOF row's discrete reference: the amplification matrix of the scheme `name`.
fn amplification_of(name: &str, a: &AnalysisSpec, omega_dt: f64) -> Result<Matrix3<f64>, FemError> {
    Ok(match (Integrator::from_spec(a), bathe_gamma(name)?) {
        (Some(ig), _) => amplification(&ig, omega_dt),
        (None, Some(g)) => bathe_amplification(g, omega_dt),
        (None, None) => unreachable!("analysis() accepts no other scheme"),
    })
}

/// The amplification matrix of the undamped SDOF on `[u, Δt·v, Δt²·a]` (see
/// `solvers/tests/sdof.rs` for the derivation): the discrete reference the SDOF row compares
/// the driver with.
pub fn amplification(ig: &Integrator, omega_dt: f64) -> Matrix3<f64> {
    let (b, g, am, af) = (ig.beta, ig.gamma, ig.alpha_m, ig.alpha_f);
    let w2 = omega_dt * omega_dt;
    let l = Matrix3::new(w2 * (1.0 - af), 0.0, 1.0 - am, 1.0, 0.0, -b, 0.0, 1.0, -g);
    let r = Matrix3::new(-w2 * af, 0.0, -am, 1.0, 1.0, 0.5 - b, 0.0, 1.0, 1.0 - g);
    l.try_inverse().unwrap_or_else(Matrix3::zeros) * r
}

/// The amplification matrix of the Bathe composite method (`solvers/src/bathe.rs`) on the
/// undamped SDOF, on `[u, Δt·v, Δt²·a]` like [`amplification`], derived here from the two
/// sub-steps in units of `Δt` (`Ω = ω·Δt`, `a = −Ω²·u` at each balance):
///
/// ```text
/// sub-step 1, trapezoidal over γ:   u₁ − (γ/2)·v₁ = u₀ + (γ/2)·v₀
///                                   (γ/2)·Ω²·u₁ + v₁ = v₀ + (γ/2)·a₀
/// sub-step 2, three-point backward: v₂ − c3·u₂ = c1·u₀ + c2·u₁
///   (c1 = (1−γ)/γ, c2 = −1/(γ(1−γ)),  Ω²·u₂ + c3·v₂ = −c1·v₀ − c2·v₁
///    c3 = (2−γ)/(1−γ))              a₂ = −Ω²·u₂
/// ```
pub fn bathe_amplification(gamma: f64, omega_dt: f64) -> Matrix3<f64> {
    use nalgebra::{Matrix2, Matrix2x3};
    let (g, w2) = (gamma, omega_dt * omega_dt);
    let inv = |m: Matrix2<f64>| m.try_inverse().unwrap_or_else(Matrix2::zeros);
    // [u₁, v₁] from [u₀, v₀, a₀].
    let s1 = inv(Matrix2::new(1.0, -g / 2.0, g * w2 / 2.0, 1.0))
        * Matrix2x3::new(1.0, g / 2.0, 0.0, 0.0, 1.0, g / 2.0);
    let (c1, c2, c3) = ((1.0 - g) / g, -1.0 / (g * (1.0 - g)), (2.0 - g) / (1.0 - g));
    let from0 = Matrix2x3::new(c1, 0.0, 0.0, 0.0, -c1, 0.0);
    let from1 = Matrix2::new(c2, 0.0, 0.0, -c2);
    let s2 = inv(Matrix2::new(-c3, 1.0, w2, c3)) * (from0 + from1 * s1);
    let (u, v) = (s2.row(0).into_owned(), s2.row(1).into_owned());
    Matrix3::from_rows(&[u, v, u * -w2])
}

/// A mass `m` on a grounded spring `k` and dashpot `c` along ux (built-in `mass` and
/// `spring_damper`; every other DOF fixed), run with `analysis`.
pub fn sdof_driver(k: f64, m: f64, c: f64, analysis: AnalysisSpec) -> Result<Driver, FemError> {
    let mut b = ModelBuilder::new("sdof");
    b.node_fixed(
        1,
        [0.0; 3],
        DofSet::of(&[Dof::Uy, Dof::Uz, Dof::Rx, Dof::Ry, Dof::Rz]),
    );
    b.element(
        "mass",
        1,
        &[1],
        &serde_json::json!({"m": m, "inertia": [1.0, 1.0, 1.0]}),
    );
    b.element(
        "spring_damper",
        2,
        &[1],
        &serde_json::json!({"k": [k, 0.0, 0.0, 0.0, 0.0, 0.0], "c": [c, 0.0, 0.0, 0.0, 0.0, 0.0]}),
    );
    b.analysis(analysis);
    Driver::new(b.build()?)
}

/// Free vibration of a mass `m = 1 kg` on a spring `k = 1e6 N/m` (ω = 1000 rad/s) from
/// `u₀ = 1 mm`, `steps` steps of `Δt = omega_dt/ω`. Reference: the spring force `k·u_n`
/// of the discrete solution `Aⁿ·x₀` (amplification matrix), relative to `k·u₀`. Also
/// reports in `reference` the largest `(T + U)/E₀`: 1 for Newmark's average acceleration;
/// HHT-α and generalized-α exceed it in their first steps when ω·Δt ≫ 1 (velocity
/// overshoot, see docs/stability.md) before their spectral radius < 1 removes it.
pub fn sdof(omega_dt: f64, scheme_name: &str, steps: usize) -> Result<StressRow, FemError> {
    let (k, m, u0): (f64, f64, f64) = (1.0e6, 1.0, 1e-3);
    let dt = omega_dt / (k / m).sqrt();
    let an = analysis(scheme_name, dt)?;
    let amp = amplification_of(scheme_name, &an, omega_dt)?;
    let mut d = sdof_driver(k, m, 0.0, an)?;
    d.state.q[0] = u0;
    d.initialize()?;
    let case = format!("SDOF ω·Δt = {omega_dt:e}, {scheme_name}");
    let command = format!(
        "railfem stress --case sdof --omega-dt {omega_dt:e} --scheme {scheme_name} --steps {steps}"
    );
    let mut x = nalgebra::Vector3::new(u0, 0.0, d.state.a[0] * dt * dt);
    let e0 = 0.5 * k * u0 * u0;
    let (mut worst_f, mut worst_e) = (0.0f64, 0.0f64);
    for _ in 0..steps {
        if let Err(e) = d.step(dt) {
            return Ok(StressRow::failed(case, command, e));
        }
        x = amp * x;
        let u = d.state.q[0];
        worst_f = worst_f.max((k * u - k * x[0]).abs() / (k * u0));
        worst_e = worst_e.max((0.5 * m * d.state.v[0].powi(2) + 0.5 * k * u * u) / e0);
    }
    Ok(StressRow {
        case,
        converged: true,
        newton_per_step: d.summary.iterations as f64 / steps as f64,
        energy_error: d.energy.as_ref().map_or(f64::NAN, |e| e.relative_error()),
        force_error: worst_f,
        reference: format!("k·u of Aⁿ·x₀; max (T+U)/E₀ = {worst_e:.6}"),
        failure: None,
        command,
    })
}

/// A simply supported steel beam (10 m, 20 Euler–Bernoulli elements, vertical bending only)
/// under a midspan step load of 10 kN, Newmark/HHT/generalized-α with `Δt = omega_dt/ω₁`
/// (ω₁ its first bending frequency, closed form `π²·√(EI/(ρA·L⁴))`). Reference: the mean
/// midspan deflection over the run against the static `F·L³/(48·EI)` (the dynamic response
/// to a step oscillates about the static one; the resolved modes average out over the
/// run of `steps` steps, so this is a check only when the run spans several periods).
pub fn beam(omega_dt: f64, scheme_name: &str, steps: usize) -> Result<StressRow, FemError> {
    let (l, ne): (f64, usize) = (10.0, 20);
    let (e, a, iz, rho): (f64, f64, f64, f64) = (2.1e11, 7.7e-3, 3.04e-5, 7850.0);
    let w1 = std::f64::consts::PI.powi(2) * (e * iz / (rho * a * l.powi(4))).sqrt();
    let dt = omega_dt / w1;
    let mut b = ModelBuilder::new("stress beam");
    // Bending in the x-y plane only: uz, rx, ry fixed everywhere; pinned at x = 0,
    // on a roller at x = L.
    for i in 0..=ne {
        let x = l * i as f64 / ne as f64;
        let fix = if i == 0 {
            DofSet::of(&[Dof::Ux, Dof::Uy, Dof::Uz, Dof::Rx, Dof::Ry])
        } else if i == ne {
            DofSet::of(&[Dof::Uy, Dof::Uz, Dof::Rx, Dof::Ry])
        } else {
            DofSet::of(&[Dof::Uz, Dof::Rx, Dof::Ry])
        };
        b.node_fixed(i as u64 + 1, [x, 0.0, 0.0], fix);
    }
    for i in 0..ne {
        b.element(
            "beam3d",
            i as u64 + 1,
            &[i as u64 + 1, i as u64 + 2],
            &serde_json::json!({"E": e, "G": 8.1e10, "A": a, "Iy": iz, "Iz": iz, "J": 1e-6, "rho": rho}),
        );
    }
    let f = 1.0e4;
    let mid = ne as u64 / 2 + 1;
    b.load(LoadSpec::Nodal {
        node: mid,
        dof: Dof::Uy,
        value: -f,
        series: TimeSeries::Constant,
    });
    b.analysis(analysis(scheme_name, dt)?);
    let mut d = Driver::new(b.build()?)?;
    d.initialize()?;
    let case = format!("beam ω₁·Δt = {omega_dt:e}, {scheme_name}");
    let command = format!(
        "railfem stress --case beam --omega-dt {omega_dt:e} --scheme {scheme_name} --steps {steps}"
    );
    let stat = -f * l.powi(3) / (48.0 * e * iz);
    let mut sum = 0.0;
    for _ in 0..steps {
        if let Err(e) = d.step(dt) {
            return Ok(StressRow::failed(case, command, e));
        }
        sum += d.displacement(mid, Dof::Uy).unwrap_or(f64::NAN);
    }
    let mean = sum / steps as f64;
    Ok(StressRow {
        case,
        converged: true,
        newton_per_step: d.summary.iterations as f64 / steps as f64,
        energy_error: d.energy.as_ref().map_or(f64::NAN, |e| e.relative_error()),
        force_error: (mean - stat).abs() / stat.abs(),
        reference: "mean midspan deflection vs F·L³/(48EI)".into(),
        failure: None,
        command,
    })
}

/// Height of the axle centre K above the rail-top plane (m): the wheel radius.
const R0: f64 = 0.43;
/// Wheelset mass (kg) and inertias about axes 1, 2, 3 (sks700 stand-in data).
const MASS: f64 = 1850.0;
const INERTIA: [f64; 3] = [123.0, 967.0, 967.0];
/// Vertical load per wheel (N).
pub const N_WHEEL: f64 = 50e3;

/// A wheelset (axle node K with a lumped mass, carried along a straight level track, two
/// `moving_axle` wheels) and the element indices of its wheels.
struct Wheelset {
    d: Driver,
    k: usize,
    wheels: [usize; 2],
}

struct WheelsetSpec {
    speed: f64,
    length: f64,
    start: f64,
    mesh: TrackMesh,
    wheel: serde_json::Value,
    fix: DofSet,
    loads: Vec<(Dof, f64, TimeSeries)>,
    analysis: AnalysisSpec,
}

fn wheelset(s: &WheelsetSpec) -> Result<Wheelset, FemError> {
    let track = Arc::new(
        Alignment::new(vec![Segment::Straight { length: s.length }])
            .and_then(|al| Track::new(al, Cant::none()))
            .map_err(|e| FemError::input("stress", e.to_string()))?,
    );
    let mut b = ModelBuilder::new("stress wheelset");
    let p = track.at(s.start);
    let xk = p.position + p.frame.column(1) * R0;
    b.node_fixed(1, [xk.x, xk.y, xk.z], s.fix);
    b.element(
        "mass",
        1,
        &[1],
        &serde_json::json!({"m": MASS, "inertia": INERTIA}),
    );
    for (id, side) in [(2, "left"), (3, "right")] {
        let mut w = s.wheel.as_object().cloned().unwrap_or_default();
        w.insert("side".into(), side.into());
        b.element("moving_axle", id, &[1], &serde_json::Value::Object(w));
    }
    track_model::generate(&mut b, track.clone(), &s.mesh)?;
    b.carrier(
        Carrier {
            name: "wheelset".into(),
            path: track.clone() as Arc<dyn Path>,
            start: s.start,
            speed: s.speed,
            accel: 0.0,
            speed_table: None,
            nodes: Vec::new(),
        },
        vec![(1, 0.0, [0.0, R0, 0.0])],
    );
    for (dof, value, series) in &s.loads {
        b.load(LoadSpec::Nodal {
            node: 1,
            dof: *dof,
            value: *value,
            series: series.clone(),
        });
    }
    b.analysis(s.analysis.clone());
    let model = b.build()?;
    let k = model.node(1).unwrap_or(0);
    let idx = |id: u64| model.elements.iter().position(|e| e.id == id).unwrap_or(0);
    let wheels = [idx(2), idx(3)];
    Ok(Wheelset {
        d: Driver::new(model)?,
        k,
        wheels,
    })
}

impl Wheelset {
    fn axle(&self, w: usize) -> Option<&MovingAxle> {
        self.d.model.elements[self.wheels[w]]
            .element
            .as_any()
            .and_then(|a| a.downcast_ref::<MovingAxle>())
    }
    fn normal(&self) -> f64 {
        (0..2)
            .filter_map(|w| self.axle(w))
            .map(|a| a.contact_force().y)
            .sum()
    }
    fn value(&self, v: &[f64], dof: Dof) -> f64 {
        self.d.asm.dofmap.value(v, self.k, dof)
    }
}

fn wheel_analysis(scheme_name: &str, dt: f64) -> Result<AnalysisSpec, FemError> {
    let mut a = analysis(scheme_name, dt)?;
    a.newton.tol = 1e-10;
    a.newton.abs_tol = 1e-6;
    a.newton.max_iter = 40;
    Ok(a)
}

/// The wheelset on rigid rails with contact penalty `k = k_v = penalty` under 2·50 kN on K
/// (K's vertical DOF free), preloaded statically and then stepped with Newmark's average
/// acceleration at Δt = 1e-4 s from rest. The equilibrium is a solution of the dynamic
/// equations, so a stable integration must stay on it whatever the contact stiffness.
/// Reference: the largest |ΣQ − load|/load over the steps.
pub fn penalty(penalty: f64, steps: usize) -> Result<StressRow, FemError> {
    let dt = 1e-4;
    let case = format!("wheelset at rest on rigid rail, penalty {penalty:e} N/m");
    let command = format!("railfem stress --case penalty --penalty {penalty:e} --steps {steps}");
    let mut ws = match wheelset(&WheelsetSpec {
        speed: 0.0,
        length: 40.0,
        start: 20.0,
        mesh: TrackMesh::default(),
        wheel: serde_json::json!({"k": penalty, "k_v": penalty, "mu": 0.3}),
        fix: DofSet::of(&[Dof::Ux, Dof::Uz, Dof::Rx, Dof::Ry, Dof::Rz]),
        loads: vec![(Dof::Uy, -2.0 * N_WHEEL, TimeSeries::Constant)],
        analysis: wheel_analysis("newmark", dt)?,
    }) {
        Ok(w) => w,
        Err(e) => return Ok(StressRow::failed(case, command, e)),
    };
    let mut worst = 0.0f64;
    let mut run = || -> Result<(), FemError> {
        ws.d.static_solve(0.0, 10)?;
        ws.d.initialize()?;
        for _ in 0..steps {
            ws.d.step(dt)?;
            worst = worst.max((ws.normal() - 2.0 * N_WHEEL).abs() / (2.0 * N_WHEEL));
        }
        Ok(())
    };
    if let Err(e) = run() {
        return Ok(StressRow::failed(case, command, e));
    }
    Ok(StressRow {
        case,
        converged: true,
        newton_per_step: ws.d.summary.iterations as f64 / steps as f64,
        // At rest every energy is round-off: a relative error means nothing, the absolute
        // residual is in the reference column.
        energy_error: f64::NAN,
        force_error: worst,
        reference: format!(
            "max |ΣQ − 2·50 kN|/load at rest on the equilibrium; |integrator| {:.1e} J",
            ws.d.energy
                .as_ref()
                .map_or(f64::NAN, |e| e.totals().integrator.abs())
        ),
        failure: None,
        command,
    })
}

/// The wheelset (2·50 kN on K) rolling at `speed` over rails of 0.125 m beam elements on
/// discrete pads (k = 1e8 N/m vertical, c = 5e4 N·s/m) for `duration` s, generalized-α
/// ρ∞ = 0, Δt = 5e-4 s. Reference: after the start-up transient (t > 0.1 s), the largest
/// deviation of either wheel's Q from the static share 50 kN.
pub fn speed(speed: f64, duration: f64) -> Result<StressRow, FemError> {
    let (h, dt) = (0.125, 5e-4);
    let case = format!("wheelset rolling at {speed} m/s on a flexible rail");
    let command = format!("railfem stress --case speed --speed {speed} --duration {duration}");
    let length = 12.0 + speed * duration;
    let mut ws = match wheelset(&WheelsetSpec {
        speed,
        length,
        start: 6.0,
        mesh: TrackMesh {
            element_length: h,
            support: RailSupport::Discrete {
                spacing: h,
                k: [5e7, 1e8, 5e7, 1e5, 1e5, 1e6],
                c: [5e4, 5e4, 5e4, 0.0, 0.0, 0.0],
            },
            ..Default::default()
        },
        wheel: serde_json::json!({"mu": 0.3}),
        fix: DofSet::of(&[Dof::Rx]),
        loads: vec![(Dof::Uy, -2.0 * N_WHEEL, TimeSeries::Constant)],
        analysis: {
            let mut a = wheel_analysis("galpha:0", dt)?;
            a.newton.tol = 1e-9;
            a
        },
    }) {
        Ok(w) => w,
        Err(e) => return Ok(StressRow::failed(case, command, e)),
    };
    let steps = step_count("--duration / --dt", (duration / dt).round())?;
    let mut worst = 0.0f64;
    let mut run = || -> Result<(), FemError> {
        ws.d.static_solve(0.0, 10)?;
        ws.d.initialize()?;
        for k in 1..=steps {
            ws.d.step(dt)?;
            if k as f64 * dt > 0.1 + 1e-9 {
                for w in 0..2 {
                    let q = ws.axle(w).map_or(f64::NAN, |a| a.contact_force().y);
                    worst = worst.max((q - N_WHEEL).abs() / N_WHEEL);
                }
            }
        }
        Ok(())
    };
    if let Err(e) = run() {
        return Ok(StressRow::failed(case, command, e));
    }
    Ok(StressRow {
        case,
        converged: true,
        newton_per_step: ws.d.summary.iterations as f64 / steps as f64,
        energy_error: ws
            .d
            .energy
            .as_ref()
            .map_or(f64::NAN, |e| e.relative_error()),
        force_error: worst,
        reference: "max |Q − 50 kN|/50 kN after 0.1 s".into(),
        failure: None,
        command,
    })
}

/// What a drop run measured, besides its row.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct DropReport {
    /// Impact speed `√(2·g·h)` (m/s).
    pub impact_speed: f64,
    /// Upward speed of K at each separation (m/s).
    pub rebound_speeds: [f64; 2],
    /// Separations seen.
    pub separations: usize,
    /// Largest total normal force (N).
    pub peak_force: f64,
}

/// A wheelset (vertical DOF of K only, weight W = m·g as a load on K, rigid rails, μ = 0,
/// contact penalty `penalty`)
/// meets the rail at the unloaded contact with the speed of a drop from `height`:
/// `v₀ = √(2·g·h)` downward. Contact is elastic and Newmark's average acceleration conserves
/// energy, so (energy balance) it leaves the rail with `v₀` upward, flies to the same
/// height and lands again: repeated separation and re-contact. Reference: the upward speed
/// at each separation against `v₀` (with the weight acting during contact, the momentum
/// balance `∫(ΣQ − W)·dt = 2·m·v₀` is the same statement). Δt = 2e-5 s resolves the
/// contact (≈ 1 ms); the transition steps into and out of contact carry the residual.
pub fn drop(
    height: f64,
    dt: f64,
    duration: f64,
    penalty: f64,
) -> Result<(StressRow, DropReport), FemError> {
    let g = 9.81;
    let w = MASS * g;
    let case = format!("wheelset dropped from {height} m on a rigid rail, penalty {penalty:e} N/m");
    let command = format!("railfem stress --case drop --height {height} --dt {dt:e} --duration {duration} --penalty {penalty:e}");
    let v0 = (2.0 * g * height).sqrt();
    let mut rep = DropReport {
        impact_speed: v0,
        ..Default::default()
    };
    let mut ws = wheelset(&WheelsetSpec {
        speed: 0.0,
        length: 40.0,
        start: 20.0,
        mesh: TrackMesh::default(),
        wheel: serde_json::json!({"mu": 0.0, "k": penalty, "k_v": penalty}),
        fix: DofSet::of(&[Dof::Ux, Dof::Uz, Dof::Rx, Dof::Ry, Dof::Rz]),
        loads: vec![(Dof::Uy, -w, TimeSeries::Constant)],
        analysis: {
            // Residual floor 1e-3 N (5e-8 of the weight): at the instant of re-contact the
            // penalty switches on inside a step and 1e-6 N is below what the contact
            // search can resolve there (measured: 5.5e-5 N stagnation, see
            // docs/stability.md).
            let mut a = wheel_analysis("newmark", dt)?;
            a.newton.abs_tol = 1e-3;
            a
        },
    })?;
    let steps = step_count("--duration / --dt", (duration / dt).round())?;
    let mut in_contact = true;
    let mut run = |rep: &mut DropReport| -> Result<(), FemError> {
        ws.d.initialize()?;
        let i =
            ws.d.asm
                .dofmap
                .terms(ws.k, Dof::Uy)
                .next()
                .map_or(0, |t| t.0);
        ws.d.state.v[i] = -v0;
        for _ in 0..steps {
            ws.d.step(dt)?;
            let q = ws.normal();
            rep.peak_force = rep.peak_force.max(q);
            let touching = q > 0.0;
            if in_contact && !touching && rep.separations < 2 {
                rep.rebound_speeds[rep.separations] = ws.value(&ws.d.state.v, Dof::Uy);
                rep.separations += 1;
            }
            in_contact = touching;
        }
        Ok(())
    };
    if let Err(e) = run(&mut rep) {
        return Ok((StressRow::failed(case, command, e), rep));
    }
    let err = rep.rebound_speeds[..rep.separations.max(1)]
        .iter()
        .fold(0.0f64, |m, v| m.max((v - v0).abs() / v0));
    let row = StressRow {
        case,
        converged: true,
        newton_per_step: ws.d.summary.iterations as f64 / steps as f64,
        energy_error: ws
            .d
            .energy
            .as_ref()
            .map_or(f64::NAN, |e| e.relative_error()),
        force_error: err,
        reference: format!(
            "rebound speed vs √(2gh) = {v0:.4} m/s over {} separations; peak ΣQ {:.4e} N",
            rep.separations, rep.peak_force
        ),
        failure: None,
        command,
    };
    Ok((row, rep))
}

/// A wheelset (2·50 kN on K, vertical motion only) rolling at `speed` over a dipped rail
/// joint (`depth`, 1 m long, on both rails; [`crate::elements::rail::geometry::track_model::JointDip`])
/// on rigid rails, average-acceleration Newmark, Δt = 2e-4 s. Reference: the quasi-static
/// closed form — the wheelset follows the rail top, so the wheels push it with
/// `ΣQ = 2·N + m·v²·w''(s)` (`w''` the dip's curvature at the wheel's station); the dip's
/// harmonics (v/L, 2v/L) are far below the wheel-on-contact-spring frequency (≈ 520 Hz),
/// so the dynamic correction is of the order of their squared ratio. Force error: the
/// largest `|ΣQ − ΣQ_ref|` over the run relative to the static `2·N`.
pub fn joint_dip(speed: f64, depth: f64) -> Result<StressRow, FemError> {
    use crate::elements::rail::geometry::track_model::JointDip;
    let dt = 2e-4;
    let (length, start) = (1.0, 20.0);
    let dip = JointDip {
        station: start + 1.0 + 0.5 * length,
        depth,
        length,
        ..Default::default()
    };
    let case = format!("wheelset at {speed} m/s over a {depth} m dipped joint (1 m), rigid rail");
    let command = format!("railfem stress --case dip --speed {speed} --depth {depth}");
    let mut ws = match wheelset(&WheelsetSpec {
        speed,
        length: 40.0,
        start,
        mesh: TrackMesh {
            dips: vec![dip],
            ..Default::default()
        },
        wheel: serde_json::json!({"mu": 0.3}),
        fix: DofSet::of(&[Dof::Ux, Dof::Uz, Dof::Rx, Dof::Ry, Dof::Rz]),
        loads: vec![(Dof::Uy, -2.0 * N_WHEEL, TimeSeries::Constant)],
        analysis: wheel_analysis("newmark", dt)?,
    }) {
        Ok(w) => w,
        Err(e) => return Ok(StressRow::failed(case, command, e)),
    };
    // From 1 m before the dip to 0.5 m after it.
    let steps = step_count(
        "--speed and --dt",
        ((2.0 * 1.0 + length + 0.5) / speed / dt).round(),
    )?;
    let mut worst = 0.0f64;
    let mut lost_contact = false;
    let mut run = || -> Result<(), FemError> {
        ws.d.static_solve(0.0, 10)?;
        ws.d.initialize()?;
        for k in 1..=steps {
            ws.d.step(dt)?;
            let s = start + speed * k as f64 * dt;
            let reference = 2.0 * N_WHEEL + MASS * speed * speed * dip.curvature(s);
            let q = ws.normal();
            lost_contact |= q <= 0.0;
            worst = worst.max((q - reference).abs() / (2.0 * N_WHEEL));
        }
        Ok(())
    };
    if let Err(e) = run() {
        return Ok(StressRow::failed(case, command, e));
    }
    let peak = MASS * speed * speed * depth * (2.0 * std::f64::consts::PI / length).powi(2);
    Ok(StressRow {
        case,
        converged: true,
        newton_per_step: ws.d.summary.iterations as f64 / steps as f64,
        energy_error: ws
            .d
            .energy
            .as_ref()
            .map_or(f64::NAN, |e| e.relative_error()),
        force_error: if lost_contact { f64::INFINITY } else { worst },
        reference: format!(
            "quasi-static ΣQ = 2N + m·v²·w''(s) (peak dynamic part {:.3e} N = {:.1} % of 2N)",
            peak,
            100.0 * peak / (2.0 * N_WHEEL)
        ),
        failure: None,
        command,
    })
}

/// What a stick–slip run measured.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct SlipReport {
    /// Largest `|(f_u, f_v)|/(μ·f_n)` over every contact point of every converged step.
    pub worst_ratio: f64,
    /// Changes of the number of sliding points between steps (a chatter count).
    pub switches: usize,
    /// Largest Newton iterations in one step.
    pub max_iterations: usize,
    /// The step (1-based) of the last change of the sliding set.
    pub last_switch: usize,
    /// Number of sliding points per step (for the table and for chatter checks).
    pub sliding: Vec<u8>,
}

/// The wheelset pressed by 2·50 kN (K's lateral, vertical DOFs and roll free, rigid rails,
/// μ = 0.3) and pushed laterally by a force ramped from 0 to `overshoot·μ·ΣQ` over 0.2 s
/// and held, generalized-α ρ∞ = 0.8, Δt = 1e-3 s. At convergence no contact point may
/// carry a tangential force above μ·f_n (the Coulomb cone, checked to 1e-9), and the
/// stick→slip transition must settle (a bounded number of changes of the sliding set).
pub fn stick_slip(overshoot: f64, steps: usize) -> Result<(StressRow, SlipReport), FemError> {
    let (mu, dt) = (0.3, 1e-3);
    let case = format!("lateral force ramped to {overshoot}·μ·N (stick–slip)");
    let command =
        format!("railfem stress --case stick-slip --overshoot {overshoot} --steps {steps}");
    let lateral = overshoot * mu * 2.0 * N_WHEEL;
    let mut rep = SlipReport::default();
    let mut ws = wheelset(&WheelsetSpec {
        speed: 0.0,
        length: 40.0,
        start: 20.0,
        mesh: TrackMesh::default(),
        wheel: serde_json::json!({"mu": mu, "sliding_tangent": "consistent"}),
        fix: DofSet::of(&[Dof::Uz, Dof::Ry, Dof::Rz]),
        loads: vec![
            (Dof::Uy, -2.0 * N_WHEEL, TimeSeries::Constant),
            (
                Dof::Ux,
                lateral,
                TimeSeries::Table {
                    points: vec![[0.0, 0.0], [0.2, 1.0], [10.0, 1.0]],
                },
            ),
        ],
        analysis: wheel_analysis("galpha:0.8", dt)?,
    })?;
    let mut last_slide = 0usize;
    let mut run = |rep: &mut SlipReport| -> Result<(), FemError> {
        ws.d.static_solve(0.0, 10)?;
        ws.d.initialize()?;
        for step in 1..=steps {
            let r = ws.d.step(dt)?;
            rep.max_iterations = rep.max_iterations.max(r.iterations);
            let mut sliding = 0;
            for w in 0..2 {
                if let Some(a) = ws.axle(w) {
                    for (_, p, _, _) in a.contact_points() {
                        if p.mode == Mode::Open {
                            continue;
                        }
                        if p.mode == Mode::Slide {
                            sliding += 1;
                        }
                        let ft = (p.f_u * p.f_u + p.f_v * p.f_v).sqrt();
                        if p.f_n > 0.0 {
                            rep.worst_ratio = rep.worst_ratio.max(ft / (mu * p.f_n));
                        }
                    }
                }
            }
            if sliding != last_slide {
                rep.switches += 1;
                rep.last_switch = step;
            }
            rep.sliding.push(sliding as u8);
            last_slide = sliding;
        }
        Ok(())
    };
    if let Err(e) = run(&mut rep) {
        return Ok((StressRow::failed(case, command, e), rep));
    }
    let row = StressRow {
        case,
        converged: true,
        newton_per_step: ws.d.summary.iterations as f64 / steps as f64,
        energy_error: ws.d.energy.as_ref().map_or(f64::NAN, |e| e.relative_error()),
        force_error: (rep.worst_ratio - 1.0).max(0.0),
        reference: format!(
            "max |f_t|/(μ·f_n) − 1 over all points (ratio {:.12}); {} changes of the sliding set, the last at step {}; ≤ {} iterations/step",
            rep.worst_ratio, rep.switches, rep.last_switch, rep.max_iterations
        ),
        failure: None,
        command,
    };
    Ok((row, rep))
}

/// The Markdown table of rows.
pub fn table(rows: &[StressRow]) -> String {
    let mut s = String::from(
        "| case | converged | Newton/step | energy error | force error | reference | command |\n|---|---|---|---|---|---|---|\n",
    );
    for r in rows {
        let _ = writeln!(
            s,
            "| {} | {} | {:.2} | {:.2e} | {:.2e} | {} | `{}` |",
            r.case,
            if r.converged {
                "yes".to_string()
            } else {
                format!(
                    "no: {}",
                    r.failure.as_deref().unwrap_or("").replace('|', "/")
                )
            },
            r.newton_per_step,
            r.energy_error,
            r.force_error,
            r.reference.replace('|', "\\|"),
            r.command
        );
    }
    s
}

/// The full suite of `railfem stress` (the long versions).
pub fn full_suite() -> Result<Vec<StressRow>, FemError> {
    let mut rows = Vec::new();
    full_suite_into(&mut rows)?;
    Ok(rows)
}

/// Cases of the full suite: 24 sdof, 4 beam, 8 penalty, 5 speed, 4 drop, 2 stick-slip, 3 dip.
const SUITE_CASES: usize = 50;

/// [`full_suite`] into `rows`, case by case. A stop request ([`crate::framework::interrupt`])
/// is honoured between cases: `rows` then holds the completed cases and the error is
/// [`FemError::InterruptedAfter`].
pub fn full_suite_into(rows: &mut Vec<StressRow>) -> Result<(), FemError> {
    let mut bar = crate::progress::Progress::new("stress", SUITE_CASES as u64, "cases");
    let mut add = |rows: &mut Vec<StressRow>, r: StressRow| -> Result<(), FemError> {
        rows.push(r);
        bar.set(rows.len() as u64);
        crate::framework::interrupt::check_after(|| {
            format!("{} of {SUITE_CASES} cases", rows.len())
        })
    };
    for scheme in ["newmark", "hht:0.1", "galpha:0.5", "bathe"] {
        for om in [0.01, 0.1, 1.0, 10.0, 100.0, 1000.0] {
            add(rows, sdof(om, scheme, 2000)?)?;
        }
    }
    for om in [0.01, 1.0, 100.0, 1000.0] {
        add(rows, beam(om, "newmark", 2000)?)?;
    }
    for p in [1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13] {
        add(rows, penalty(p, 500)?)?;
    }
    for v in [20.0, 50.0, 80.0, 110.0, 150.0] {
        add(rows, speed(v, 0.3)?)?;
    }
    for p in [1e6, 1e8, 1e10, 1e13] {
        add(rows, drop(0.01, 2e-5, 0.2, p)?.0)?;
    }
    for o in [0.9, 1.5] {
        add(rows, stick_slip(o, 400)?.0)?;
    }
    for v in [5.0, 15.0, 25.0] {
        add(rows, joint_dip(v, 0.002)?)?;
    }
    Ok(())
}

/// `n` steps as a count, refused past the step budget ([`limits::check_steps`]); `cause`
/// names the options that set it.
fn step_count(cause: &str, n: f64) -> Result<usize, FemError> {
    limits::check_steps(cause, n, "ask for fewer steps")
        .map_err(|m| FemError::input("command line", m))?;
    Ok(n as usize)
}

/// The values of one case given on the command line (`railfem stress --case C`); `None`
/// takes the case's default.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct CaseOptions {
    /// ω·Δt of the sdof and beam cases (-).
    pub omega_dt: Option<f64>,
    /// Time steps.
    pub steps: Option<f64>,
    /// Contact penalty stiffness (N/m).
    pub penalty: Option<f64>,
    /// Speed (m/s).
    pub speed: Option<f64>,
    /// Duration (s).
    pub duration: Option<f64>,
    /// Drop height (m).
    pub height: Option<f64>,
    /// Time step of the drop case (s).
    pub dt: Option<f64>,
    /// Stick-slip load over the friction limit (-).
    pub overshoot: Option<f64>,
    /// Rail joint dip depth (m).
    pub depth: Option<f64>,
}

/// Runs one case named on the command line (see `railfem help`), or the full suite, into
/// `rows` (on a stop request, the completed cases: [`full_suite_into`]).
pub fn run_cli(
    case: Option<&str>,
    o: &CaseOptions,
    scheme_name: &str,
    rows: &mut Vec<StressRow>,
) -> Result<(), FemError> {
    let steps = |d: f64| -> Result<usize, FemError> {
        let n = o.steps.map_or(d, |v| v.max(1.0)).round();
        step_count("--steps", n)
    };
    rows.extend(match case {
        None | Some("all") => return full_suite_into(rows),
        Some("sdof") => vec![sdof(
            o.omega_dt.unwrap_or(1.0),
            scheme_name,
            steps(2000.0)?,
        )?],
        Some("beam") => vec![beam(
            o.omega_dt.unwrap_or(1.0),
            scheme_name,
            steps(2000.0)?,
        )?],
        Some("penalty") => vec![penalty(o.penalty.unwrap_or(1e10), steps(500.0)?)?],
        Some("speed") => vec![speed(o.speed.unwrap_or(80.0), o.duration.unwrap_or(0.3))?],
        Some("drop") => vec![
            drop(
                o.height.unwrap_or(0.01),
                o.dt.unwrap_or(2e-5),
                o.duration.unwrap_or(0.2),
                o.penalty.unwrap_or(1e10),
            )?
            .0,
        ],
        Some("stick-slip") => vec![stick_slip(o.overshoot.unwrap_or(1.5), steps(400.0)?)?.0],
        Some("dip") => vec![joint_dip(
            o.speed.unwrap_or(15.0),
            o.depth.unwrap_or(0.002),
        )?],
        Some(o) => {
            return Err(FemError::input(
                "command line",
                format!("--case {o}: use all, sdof, beam, penalty, speed, drop, stick-slip or dip"),
            ))
        }
    });
    Ok(())
}

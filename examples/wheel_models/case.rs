//! A small vehicle on a straight track with a choice of wheel model, built in Rust: the
//! common case of the point-wheel tests (`tests/point_wheels.rs`) and of the cost
//! comparison of the three wheel models (`cargo run --release --example wheel_models`).
//!
//! The vehicle is a set of wheelsets (axle node K, lumped mass, two wheels of the chosen
//! kind) and, optionally, a car body above them on linear spring-dampers: one per wheelset
//! between a slave of the body and a slave of K at the same point (the body's height), as
//! the `[[vehicle]]` builder joins its bodies. The pitch spring of each suspension is zero,
//! so the body's weight splits between the wheelsets by the lever rule alone. Every vehicle
//! node rides on one carrier; its DOFs are in the wheel frame (1 lateral, 2 up, 3 forwards).

use railfem::elements::rail::geometry::alignment::Alignment;
use railfem::elements::rail::geometry::cant::{Cant, Track};
use railfem::elements::rail::geometry::track_model::{self, TrackMesh, TrackModel};
use railfem::framework::builder::ModelBuilder;
use railfem::framework::loads::{LoadSpec, TimeSeries};
use railfem::framework::model::AnalysisSpec;
use railfem::framework::moving::{Carrier, Path};
use railfem::framework::{DofSet, FemError};
use railfem::solvers::Driver;
use std::sync::Arc;

/// Height of the axle centre K above the rail top (m): the wheel radius.
pub const R0: f64 = 0.43;
/// Height of the car body's mass centre and of the suspension points (m).
pub const BODY_HEIGHT: f64 = 1.5;
/// Spin stiffness on each axle (N·m/rad), as the vehicle builder adds: rolling about the
/// contact line (spin about axis 1 with the matching forward motion of K) is a free motion
/// of every wheel model, so a static solve needs it; it is far below every other stiffness.
pub const SPIN_STIFFNESS: f64 = 1.0e4;

/// A car body above the wheelsets.
#[derive(Debug, Clone)]
pub struct Body {
    /// Mass (kg) and inertias about axes 1, 2, 3 (kg·m²).
    pub mass: f64,
    pub inertia: [f64; 3],
    /// Downward load on the body's mass centre (N).
    pub load: f64,
    /// Suspension per wheelset: `[k1, k2, k3, kr1, kr2, kr3]` (N/m, N·m/rad), wheel frame;
    /// kr1 (pitch) must be 0 for the lever rule.
    pub k: [f64; 6],
    /// Dampers, same order (N·s/m, N·m·s/rad).
    pub c: [f64; 6],
}

/// The case: track, motion, wheelsets, body, wheel model.
#[derive(Debug, Clone)]
pub struct Case {
    /// Wheel element kind: "hertz_wheel", "rigid_wheel" or "moving_axle".
    pub kind: &'static str,
    /// Wheel keys besides `side`.
    pub wheel: serde_json::Value,
    /// Track length (m), straight and level.
    pub length: f64,
    pub mesh: TrackMesh,
    /// Station of the body centre at t = 0 (m), speed (m/s).
    pub start: f64,
    pub speed: f64,
    /// Station offsets of the wheelsets from the body centre (m, forwards positive).
    pub axles: Vec<f64>,
    /// Wheelset mass (kg) and inertias about axes 1, 2, 3 (kg·m²).
    pub ws_mass: f64,
    pub ws_inertia: [f64; 3],
    /// Downward load on each K (N).
    pub ws_load: f64,
    /// Time series of every load.
    pub series: TimeSeries,
    pub body: Option<Body>,
    pub analysis: AnalysisSpec,
}

impl Default for Case {
    fn default() -> Self {
        let mut analysis = AnalysisSpec::default();
        analysis.newton.tol = 1e-11;
        analysis.newton.abs_tol = 1e-7;
        analysis.newton.max_iter = 60;
        Case {
            kind: "hertz_wheel",
            wheel: serde_json::json!({}),
            length: 40.0,
            mesh: TrackMesh::default(),
            start: 20.0,
            speed: 0.0,
            axles: vec![0.0],
            ws_mass: 1850.0,
            ws_inertia: [123.0, 967.0, 967.0],
            ws_load: 0.0,
            series: TimeSeries::Constant,
            body: None,
            analysis,
        }
    }
}

/// The built case: the driver, node indices of the axle nodes and the body, and the
/// element indices of the wheels (left, right per wheelset).
pub struct Built {
    pub d: Driver,
    pub track: Arc<TrackModel>,
    pub ks: Vec<usize>,
    pub body: Option<usize>,
    pub wheels: Vec<[usize; 2]>,
}

/// A one-carriage case: a 40 t body on four wheelsets (bogie-less: axles at ±8.75 m and
/// ±11.25 m), the sks700's wheelset data, with the given wheel model. Loads are the weights
/// under g = 9.81 m/s², applied as constant nodal loads.
pub fn one_carriage(kind: &'static str) -> Case {
    let g = 9.81;
    let ws_mass = 1850.0;
    let body_mass = 40_000.0;
    Case {
        kind,
        axles: vec![11.25, 8.75, -8.75, -11.25],
        ws_mass,
        ws_load: ws_mass * g,
        body: Some(Body {
            mass: body_mass,
            inertia: [2.0e6, 2.0e6, 1.0e5],
            load: body_mass * g,
            k: [5e5, 1.2e6, 5e5, 0.0, 1e6, 1e6],
            c: [2e4, 2e4, 2e4, 0.0, 0.0, 0.0],
        }),
        length: 80.0,
        start: 30.0,
        ..Default::default()
    }
}

/// Builds the case.
pub fn build(c: &Case) -> Result<Built, FemError> {
    let track = Track::new(Alignment::straight(c.length), Cant::none())
        .map_err(|e| FemError::input("wheel case", e.to_string()))?;
    let track = Arc::new(track);
    let mut b = ModelBuilder::new(format!("{} case", c.kind));
    let mut carried: Vec<(u64, f64, [f64; 3])> = Vec::new();
    let mut next_id = 0u64;
    let mut node = |b: &mut ModelBuilder, carried: &mut Vec<_>, ds: f64, h: f64| -> u64 {
        next_id += 1;
        let p = track.at(c.start + ds);
        let x = p.position + p.frame.column(1) * h;
        b.node(next_id, [x.x, x.y, x.z]);
        carried.push((next_id, ds, [0.0, h, 0.0]));
        next_id
    };
    let load = |b: &mut ModelBuilder, id: u64, value: f64| {
        b.load(LoadSpec::Nodal {
            node: id,
            dof: railfem::framework::Dof::Uy,
            value: -value,
            series: c.series.clone(),
        });
    };
    let mut eid = 0u64;
    let mut elem = |b: &mut ModelBuilder, kind: &str, nodes: &[u64], p: serde_json::Value| {
        eid += 1;
        b.element(kind, eid, nodes, &p);
        eid
    };
    let body = c.body.as_ref().map(|body| {
        let id = node(&mut b, &mut carried, 0.0, BODY_HEIGHT);
        elem(
            &mut b,
            "mass",
            &[id],
            serde_json::json!({"m": body.mass, "inertia": body.inertia}),
        );
        if body.load != 0.0 {
            load(&mut b, id, body.load);
        }
        id
    });
    let mut ks = Vec::new();
    let mut wheels = Vec::new();
    for &ds in &c.axles {
        let k = node(&mut b, &mut carried, ds, R0);
        ks.push(k);
        elem(
            &mut b,
            "mass",
            &[k],
            serde_json::json!({"m": c.ws_mass, "inertia": c.ws_inertia}),
        );
        elem(
            &mut b,
            "spring_damper",
            &[k],
            serde_json::json!({"k": [0.0, 0.0, 0.0, SPIN_STIFFNESS, 0.0, 0.0]}),
        );
        if c.ws_load != 0.0 {
            load(&mut b, k, c.ws_load);
        }
        if let (Some(body), Some(bid)) = (&c.body, body) {
            let up = node(&mut b, &mut carried, ds, BODY_HEIGHT);
            b.rigid_link(bid, up, DofSet::ALL);
            let lo = node(&mut b, &mut carried, ds, BODY_HEIGHT);
            b.rigid_link(k, lo, DofSet::ALL);
            elem(
                &mut b,
                "spring_damper",
                &[lo, up],
                serde_json::json!({"k": body.k, "c": body.c}),
            );
        }
        let mut pair = [0u64; 2];
        for (i, side) in ["left", "right"].into_iter().enumerate() {
            let mut w = c.wheel.as_object().cloned().unwrap_or_default();
            w.insert("side".into(), side.into());
            pair[i] = elem(&mut b, c.kind, &[k], serde_json::Value::Object(w));
        }
        wheels.push(pair);
    }
    let tm = track_model::generate(&mut b, track.clone(), &c.mesh)?;
    b.carrier(
        Carrier {
            name: "vehicle".into(),
            path: track.clone() as Arc<dyn Path>,
            start: c.start,
            speed: c.speed,
            accel: 0.0,
            speed_table: None,
            nodes: Vec::new(),
        },
        carried,
    );
    b.analysis(c.analysis.clone());
    let model = b.build()?;
    let ks = ks
        .iter()
        .map(|id| model.node(*id).expect("axle node"))
        .collect();
    let body = body.map(|id| model.node(id).expect("body node"));
    let idx = |id: u64| {
        model
            .elements
            .iter()
            .position(|e| e.id == id)
            .expect("wheel element")
    };
    let wheels = wheels.iter().map(|[l, r]| [idx(*l), idx(*r)]).collect();
    let d = Driver::new(model)?;
    Ok(Built {
        d,
        track: tm,
        ks,
        body,
        wheels,
    })
}

impl Built {
    /// Output `key` of wheel `side` (0 left, 1 right) of wheelset `ws` at the last state.
    pub fn out(&self, ws: usize, side: usize, key: &str) -> f64 {
        let e = &self.d.model.elements[self.wheels[ws][side]].element;
        let names = e.output_names();
        let mut v = Vec::new();
        e.outputs(&mut v);
        v[names.iter().position(|n| n == key).expect("output name")]
    }

    /// Committed value of DOF `dof` of node index `node`.
    pub fn disp(&self, node: usize, dof: usize) -> f64 {
        self.d
            .asm
            .dofmap
            .value(&self.d.state.q, node, railfem::framework::Dof::ALL[dof])
    }

    /// Committed acceleration of DOF `dof` of node index `node`.
    pub fn acc(&self, node: usize, dof: usize) -> f64 {
        self.d
            .asm
            .dofmap
            .value(&self.d.state.a, node, railfem::framework::Dof::ALL[dof])
    }

    /// Upward displacement of rail `r`'s node at mesh station index `i` (m).
    pub fn rail_up(&self, r: usize, i: usize) -> f64 {
        let id = self.track.rails[r].first_id + i as u64;
        let n = self.d.model.node(id).expect("rail node");
        let up = self
            .track
            .track
            .at(self.track.stations[i])
            .frame
            .column(1)
            .into_owned();
        (0..3).map(|a| self.disp(n, a) * up[a]).sum()
    }
}

//! Loads and time series: nodal loads, gravity, uniform support excitation and a force
//! moving along a path of beam elements.
//!
//! A [`LoadSpec`] is what a model file or builder says (node and element ids); a [`Load`]
//! is its resolved form (indices), evaluated by the solvers at each time. Gravity and ground
//! motion are not listed here as vectors: they act through the mass matrices
//! (`f = M·g`, `f = −M·r·a_g(t)`) and are formed by the assembler, which knows the masses.
//! Moving forces use the consistent nodal forces of the beam's cubic Hermite shape
//! functions (see [`MovingForce::nodal_forces`]).

use crate::dof::Dof;
use crate::error::FemError;
use crate::load_kind::{LoadEntry, RegisteredLoad};
use crate::lookup::ModelLookup;
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

/// A scalar function of time that multiplies a load.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum TimeSeries {
    /// 1 at all times.
    Constant,
    /// 0 before `t0`, linear from 0 to 1 between `t0` and `t1` (s), 1 after.
    Ramp {
        /// Start of the ramp (s).
        #[serde(default)]
        t0: f64,
        /// End of the ramp (s).
        t1: f64,
    },
    /// `amplitude · sin(2π·frequency·t + phase)`.
    Sine {
        /// Amplitude (multiplies the load's value).
        #[serde(default = "one")]
        amplitude: f64,
        /// Frequency (Hz).
        frequency: f64,
        /// Phase (rad).
        #[serde(default)]
        phase: f64,
    },
    /// Piecewise-linear table of `[t, value]` points with strictly increasing t; zero
    /// outside the table.
    Table {
        /// The points `[t (s), value]`.
        points: Vec<[f64; 2]>,
    },
}

fn one() -> f64 {
    1.0
}

#[allow(clippy::derivable_impls)]
impl Default for TimeSeries {
    fn default() -> Self {
        TimeSeries::Constant
    }
}

impl TimeSeries {
    /// Value at time `t` (s).
    pub fn value(&self, t: f64) -> f64 {
        match self {
            TimeSeries::Constant => 1.0,
            TimeSeries::Ramp { t0, t1 } => {
                if t <= *t0 {
                    0.0
                } else if t >= *t1 {
                    1.0
                } else {
                    (t - t0) / (t1 - t0)
                }
            }
            TimeSeries::Sine {
                amplitude,
                frequency,
                phase,
            } => amplitude * (2.0 * std::f64::consts::PI * frequency * t + phase).sin(),
            TimeSeries::Table { points } => {
                if points.is_empty() || t < points[0][0] || t > points[points.len() - 1][0] {
                    return 0.0;
                }
                let k = points.partition_point(|p| p[0] <= t);
                if k == 0 {
                    return points[0][1];
                }
                if k >= points.len() {
                    return points[points.len() - 1][1];
                }
                let (a, b) = (points[k - 1], points[k]);
                a[1] + (b[1] - a[1]) * (t - a[0]) / (b[0] - a[0])
            }
        }
    }

    /// Checks the series; `origin` names the place.
    pub fn validate(&self, origin: &str) -> Result<(), FemError> {
        let bad = |m: &str| Err(FemError::input(origin, m.to_string()));
        match self {
            TimeSeries::Constant => Ok(()),
            TimeSeries::Ramp { t0, t1 } => {
                if !(t0.is_finite() && t1.is_finite() && t1 > t0) {
                    bad("ramp series needs finite t0 < t1 (s)")
                } else {
                    Ok(())
                }
            }
            TimeSeries::Sine {
                amplitude,
                frequency,
                phase,
            } => {
                if [amplitude, frequency, phase].iter().all(|v| v.is_finite()) {
                    Ok(())
                } else {
                    bad("sine series needs finite amplitude, frequency (Hz) and phase (rad)")
                }
            }
            TimeSeries::Table { points } => {
                if points.len() < 2 {
                    return bad("table series needs at least two [t, value] points");
                }
                if points.iter().flatten().any(|v| !v.is_finite()) {
                    return bad("table series has a non-finite entry");
                }
                if let Some(i) = points.windows(2).position(|w| w[1][0] <= w[0][0]) {
                    return bad(&format!(
                        "table series times must increase strictly (point {} is not after point {})",
                        i + 1,
                        i
                    ));
                }
                Ok(())
            }
        }
    }
}

/// A load as a model file states it (`[[load]]`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum LoadSpec {
    /// A force or moment on one DOF of one node: `value · series(t)` (N or N·m), in the
    /// node's axes.
    Nodal {
        /// Node id.
        node: u64,
        /// The DOF (`"ux"` … `"rz"` in a model file).
        dof: Dof,
        /// Magnitude (N or N·m).
        value: f64,
        /// Time series multiplying the value (default constant).
        #[serde(default)]
        series: TimeSeries,
    },
    /// Uniform support excitation: every mass feels `−M·r·a_g(t)`, `r` the unit rigid
    /// translation along `direction` (global). The solution is relative to the ground.
    GroundMotion {
        /// Direction of the ground acceleration (global, normalised).
        direction: [f64; 3],
        /// Ground acceleration history (m/s²): `scale · series(t)`.
        series: TimeSeries,
        /// Multiplier of the series (e.g. 9.81 for a record in g).
        #[serde(default = "one")]
        scale: f64,
    },
    /// A constant force travelling along a chain of beam elements at constant speed.
    MovingForce {
        /// Element ids of the path, in order of travel; consecutive elements share a node.
        elements: Vec<u64>,
        /// The force vector in global axes (N).
        force: [f64; 3],
        /// Speed along the path (m/s).
        speed: f64,
        /// Distance along the path at t = 0 (m); negative values enter later.
        #[serde(default)]
        start: f64,
    },
    /// A load of a registered (plugin) kind: its keys, built by the kind's factory
    /// ([`crate::load_kind`]). Model files reach it by the kind's `type`; it has no serde
    /// form of its own.
    #[serde(skip)]
    Registered(LoadEntry),
}

/// A resolved load.
#[derive(Debug, Clone, PartialEq)]
pub enum Load {
    /// See [`LoadSpec::Nodal`].
    Nodal {
        /// Node index.
        node: usize,
        /// DOF.
        dof: Dof,
        /// Magnitude (N, N·m).
        value: f64,
        /// Multiplier in time.
        series: TimeSeries,
    },
    /// See [`LoadSpec::GroundMotion`].
    GroundMotion {
        /// Unit direction, global.
        direction: Vector3<f64>,
        /// Acceleration history (m/s²) before scaling.
        series: TimeSeries,
        /// Scale factor.
        scale: f64,
    },
    /// See [`LoadSpec::MovingForce`].
    MovingForce(MovingForce),
    /// See [`LoadSpec::Registered`].
    Registered(RegisteredLoad),
}

/// A force moving along a polyline of beam elements.
#[derive(Debug, Clone, PartialEq)]
pub struct MovingForce {
    /// Node-index pairs (I, J) of each beam of the path, in order of travel.
    pub segments: Vec<(usize, usize)>,
    /// Positions of the segments' ends (m).
    pub ends: Vec<(Vector3<f64>, Vector3<f64>)>,
    /// Distance along the path at the start of each segment (m), plus the total at the end.
    pub cumulative: Vec<f64>,
    /// Force vector (N), global.
    pub force: Vector3<f64>,
    /// Speed (m/s).
    pub speed: f64,
    /// Distance along the path at t = 0 (m).
    pub start: f64,
}

/// Consistent nodal forces of a point force on a beam (global axes).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BeamNodalForces {
    /// Node I: force (N).
    pub force_i: Vector3<f64>,
    /// Node I: moment (N·m).
    pub moment_i: Vector3<f64>,
    /// Node J: force (N).
    pub force_j: Vector3<f64>,
    /// Node J: moment (N·m).
    pub moment_j: Vector3<f64>,
}

impl MovingForce {
    /// Where the force is at time `t`: segment index and ξ ∈ [0, 1], or `None` off the path.
    pub fn locate(&self, t: f64) -> Option<(usize, f64)> {
        crate::beam_chain::locate_on(&self.cumulative, self.start + self.speed * t)
    }

    /// Consistent nodal forces of a force `f` at `ξ` on a straight beam from `xi` to `xj`.
    ///
    /// With `e` the beam's unit axis, `L` its length, the axial part `f_a = (f·e)·e` is
    /// shared linearly, `(1−ξ, ξ)`. The transverse part `f_t = f − f_a` uses the cubic
    /// Hermite functions `N1 = 1 − 3ξ² + 2ξ³`, `N2 = L(ξ − 2ξ² + ξ³)`, `N3 = 3ξ² − 2ξ³`,
    /// `N4 = L(ξ³ − ξ²)`: forces `N1·f_t`, `N3·f_t` and moments `N2·(e × f_t)`,
    /// `N4·(e × f_t)` (the work-equivalent moments; independent of the cross-section axes,
    /// since a transverse displacement `w` along `f_t` goes with the rotation
    /// `e × f_t̂ · dw/dx`).
    pub fn nodal_forces(
        f: Vector3<f64>,
        xi_pos: Vector3<f64>,
        xj_pos: Vector3<f64>,
        xi: f64,
    ) -> BeamNodalForces {
        let axis = xj_pos - xi_pos;
        let l = axis.norm();
        let e = axis / l;
        let fa = e * f.dot(&e);
        let ft = f - fa;
        let (x2, x3) = (xi * xi, xi * xi * xi);
        let n1 = 1.0 - 3.0 * x2 + 2.0 * x3;
        let n2 = l * (xi - 2.0 * x2 + x3);
        let n3 = 3.0 * x2 - 2.0 * x3;
        let n4 = l * (x3 - x2);
        let m = e.cross(&ft);
        BeamNodalForces {
            force_i: fa * (1.0 - xi) + ft * n1,
            moment_i: m * n2,
            force_j: fa * xi + ft * n3,
            moment_j: m * n4,
        }
    }
}

impl LoadSpec {
    /// Resolves ids against the model and checks values.
    pub fn resolve(&self, model: &dyn ModelLookup) -> Result<Load, FemError> {
        self.resolve_at(model, None)
    }

    /// As [`LoadSpec::resolve`]; `index` (the position among the model's loads, the
    /// `[[load]]` table number of a model file) is named in messages as `load[i]`.
    pub fn resolve_at(
        &self,
        model: &dyn ModelLookup,
        index: Option<usize>,
    ) -> Result<Load, FemError> {
        let place = |what: String| match index {
            Some(i) => format!("{}: load[{i}] ({what})", model.origin()),
            None => format!("{}: {what}", model.origin()),
        };
        match self {
            LoadSpec::Nodal {
                node,
                dof,
                value,
                series,
            } => {
                let o = place(format!("load on node {node}"));
                let n = model.node_index(*node).ok_or_else(|| {
                    FemError::input(
                        &o,
                        format!("node {node} does not exist; define it in a [[node]] table or fix `node`"),
                    )
                })?;
                let d = *dof;
                if !value.is_finite() {
                    return Err(FemError::input(&o, "`value` is not finite"));
                }
                series.validate(&o)?;
                Ok(Load::Nodal {
                    node: n,
                    dof: d,
                    value: *value,
                    series: series.clone(),
                })
            }
            LoadSpec::GroundMotion {
                direction,
                series,
                scale,
            } => {
                let o = place("ground_motion load".to_string());
                let d = Vector3::from(*direction);
                if !(d.iter().all(|v| v.is_finite()) && d.norm() > 0.0 && scale.is_finite()) {
                    return Err(FemError::input(
                        &o,
                        "`direction` must be a non-zero finite vector and `scale` finite",
                    ));
                }
                series.validate(&o)?;
                Ok(Load::GroundMotion {
                    direction: d.normalize(),
                    series: series.clone(),
                    scale: *scale,
                })
            }
            LoadSpec::MovingForce {
                elements,
                force,
                speed,
                start,
            } => {
                let o = place("moving_force load".to_string());
                if elements.is_empty() {
                    return Err(FemError::input(
                        &o,
                        "`elements` is empty; list the beam ids of the path",
                    ));
                }
                if !(force.iter().all(|v| v.is_finite()) && speed.is_finite() && start.is_finite())
                {
                    return Err(FemError::input(
                        &o,
                        "`force`, `speed` and `start` must be finite",
                    ));
                }
                // Element ids to positions in one pass: a path of n elements is resolved in
                // O(n), not O(n · elements) (a 1e6-DOF beam took 40 s with a linear search).
                let found = model.element_indices(elements);
                let mut pairs = Vec::with_capacity(elements.len());
                for (id, at) in elements.iter().zip(found) {
                    let Some(i) = at else {
                        return Err(FemError::input(
                            &o,
                            format!("element {id} does not exist; list the ids of existing beam elements"),
                        ));
                    };
                    let c = model.element_nodes(i);
                    if c.len() != 2 {
                        return Err(FemError::input(
                            &o,
                            format!(
                                "element {id} ({}) is not a two-node beam",
                                model.element_kind(i)
                            ),
                        ));
                    }
                    pairs.push((c[0], c[1]));
                }
                let chain = crate::beam_chain::BeamChain::walk(elements, pairs, &|n| {
                    model.node_position(n)
                })
                .map_err(|m| FemError::input(&o, m))?;
                let crate::beam_chain::BeamChain {
                    segments,
                    ends,
                    cumulative,
                } = chain;
                Ok(Load::MovingForce(MovingForce {
                    segments,
                    ends,
                    cumulative,
                    force: Vector3::from(*force),
                    speed: *speed,
                    start: *start,
                }))
            }
            LoadSpec::Registered(entry) => {
                let o = place(format!("{} load", entry.kind));
                crate::load_kind::build(entry, model, &o).map(Load::Registered)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn series_values() {
        assert_eq!(TimeSeries::Ramp { t0: 1.0, t1: 3.0 }.value(2.0), 0.5);
        let t = TimeSeries::Table {
            points: vec![[0.0, 0.0], [1.0, 2.0], [2.0, 0.0]],
        };
        assert_eq!(t.value(0.5), 1.0);
        assert_eq!(t.value(1.5), 1.0);
        assert_eq!(t.value(3.0), 0.0);
        assert!(t.validate("x").is_ok());
        let bad = TimeSeries::Table {
            points: vec![[0.0, 0.0], [0.0, 2.0]],
        };
        assert!(bad.validate("x").is_err());
    }

    /// Static equivalence: the consistent forces of a transverse force P at ξ are the
    /// fixed-end reactions of a clamped-clamped beam, `R_I = P·b²(3a + b)/L³`,
    /// `M_I = P·a·b²/L²` with `a = ξL`, `b = L − a`; and they sum to P.
    #[test]
    fn hermite_forces_are_fixed_end_reactions() {
        let l = 4.0;
        let xi = 0.3;
        let p = 1000.0;
        let f = MovingForce::nodal_forces(
            Vector3::new(0.0, 0.0, -p),
            Vector3::zeros(),
            Vector3::new(l, 0.0, 0.0),
            xi,
        );
        let (a, b) = (xi * l, (1.0 - xi) * l);
        let ri = p * b * b * (3.0 * a + b) / l.powi(3);
        let mi = p * a * b * b / (l * l);
        assert!((f.force_i.z + ri).abs() < 1e-9 * p);
        assert!((f.force_i.z + f.force_j.z + p).abs() < 1e-9 * p);
        // e × f_t = x̂ × (−P ẑ) = +P ŷ: the clamped end's reaction moment about +y.
        assert!((f.moment_i.y - mi).abs() < 1e-9 * p * l);
        // Moment balance about node I: force_j·L + M_I + M_J + (moment of P) = 0.
        let total = f.moment_i.y + f.moment_j.y - f.force_j.z * l;
        assert!((total - p * a).abs() < 1e-9 * p * l);
    }
}

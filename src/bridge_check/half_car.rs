//! The full vehicle of the vertical plane: the standard 10-DOF half car (ERRI D214; Yang,
//! Yau & Wu, *Vehicle–Bridge Interaction Dynamics*, 2004, ch. 10; W. Zhai, *Vehicle–Track
//! Coupled Dynamics*, 2020, ch. 2): the car body as a rigid body in bounce and pitch on
//! two bogies (bounce and pitch) through the secondary suspension, and four wheelsets as
//! unsprung masses (bounce) under the bogies through the primary suspension, each on its
//! linear contact spring to the rail.
//!
//! Degrees of freedom, measured from the static equilibrium on level rigid track, `z` up
//! and the pitch `θ` such that a point `x` forward of a body's centre moves `z + x·θ`:
//! `[z_c, θ_c, z_b1, θ_b1, z_b2, θ_b2, z_w1, z_w2, z_w3, z_w4]` (car, front bogie, rear
//! bogie, wheelsets from the front). A spring `k` between two points stores `½·k·e²` with
//! `e` the difference of the points' vertical displacements, so it adds `k·g·gᵀ` to the
//! stiffness (`g` the connection vector of `e`); a rotational spring about `y` likewise
//! with `e = θ_lower − θ_upper` (a wheelset has no pitch here). The mass matrix is
//! diagonal: the masses and the pitch inertias about the mass centres.

use super::interaction::{linear_contact, G};
use crate::elements::rail::vehicle::definition::VehicleDef;
use crate::framework::FemError;
use nalgebra::{DMatrix, DVector};

/// Degrees of freedom of a half car.
pub const DOFS: usize = 10;

/// Index of wheelset `j`'s bounce.
pub const fn wheel(j: usize) -> usize {
    6 + j
}

/// A half car: its mass, stiffness and damping (suspensions only; the contact springs
/// apart) and where its wheelsets are.
#[derive(Debug, Clone, PartialEq)]
pub struct HalfCar {
    /// Diagonal of the mass matrix (kg; kg·m² for the pitches).
    pub mass: [f64; DOFS],
    /// Stiffness of the suspensions (N/m, N·m/rad).
    pub k: [[f64; DOFS]; DOFS],
    /// Damping of the suspensions (N·s/m, N·m·s/rad).
    pub c: [[f64; DOFS]; DOFS],
    /// The wheelsets' `x` (m, forward of the car body's centre), front first.
    pub axle_x: [f64; 4],
    /// Each wheelset's linear contact stiffness (N/m), both wheels.
    pub contact: [f64; 4],
}

/// A symmetric half car from its parameters (`[full_vehicles]` keys of a plan).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HalfCarParams {
    /// Car body mass (kg).
    pub car_mass: f64,
    /// Car body pitch inertia about its centre (kg·m²).
    pub car_pitch_inertia: f64,
    /// Mass of one bogie frame (kg).
    pub bogie_mass: f64,
    /// Pitch inertia of one bogie frame (kg·m²).
    pub bogie_pitch_inertia: f64,
    /// Mass of one wheelset (kg).
    pub wheelset_mass: f64,
    /// Vertical secondary stiffness per bogie, both sides (N/m).
    pub secondary_stiffness: f64,
    /// Vertical secondary damping per bogie, both sides (N·s/m).
    pub secondary_damping: f64,
    /// Vertical primary stiffness per wheelset, both sides (N/m).
    pub primary_stiffness: f64,
    /// Vertical primary damping per wheelset, both sides (N·s/m).
    pub primary_damping: f64,
    /// Half the distance between the bogie centres (m).
    pub bogie_half_distance: f64,
    /// Half the wheelbase of a bogie (m).
    pub semi_wheelbase: f64,
}

/// One end of a spring: a degree of freedom of bounce and, for a body that pitches, its
/// pitch with the lever arm (m) of the spring's point from the body's centre.
#[derive(Debug, Clone, Copy)]
struct End {
    z: usize,
    pitch: Option<(usize, f64)>,
}

impl HalfCar {
    /// An empty half car with the given masses and wheelset positions.
    fn new(mass: [f64; DOFS], axle_x: [f64; 4]) -> HalfCar {
        HalfCar {
            mass,
            k: [[0.0; DOFS]; DOFS],
            c: [[0.0; DOFS]; DOFS],
            axle_x,
            contact: [0.0; 4],
        }
    }

    /// Adds a vertical spring-damper between `lower` and `upper` (module documentation).
    fn spring(&mut self, lower: End, upper: End, k: f64, c: f64) {
        let mut g = [0.0; DOFS];
        g[lower.z] += 1.0;
        g[upper.z] -= 1.0;
        if let Some((d, arm)) = lower.pitch {
            g[d] += arm;
        }
        if let Some((d, arm)) = upper.pitch {
            g[d] -= arm;
        }
        self.add(&g, k, c);
    }

    /// Adds `k·g·gᵀ` to the stiffness and `c·g·gᵀ` to the damping.
    fn add(&mut self, g: &[f64; DOFS], k: f64, c: f64) {
        for i in 0..DOFS {
            for j in 0..DOFS {
                self.k[i][j] += k * g[i] * g[j];
                self.c[i][j] += c * g[i] * g[j];
            }
        }
    }

    /// The symmetric half car of `p`, with the linear Hertz contact of its static axle
    /// load on wheels of radius `wheel_radius` (m).
    pub fn symmetric(p: &HalfCarParams, wheel_radius: f64) -> HalfCar {
        let (a, b) = (p.bogie_half_distance, p.semi_wheelbase);
        let mut h = HalfCar::new(
            [
                p.car_mass,
                p.car_pitch_inertia,
                p.bogie_mass,
                p.bogie_pitch_inertia,
                p.bogie_mass,
                p.bogie_pitch_inertia,
                p.wheelset_mass,
                p.wheelset_mass,
                p.wheelset_mass,
                p.wheelset_mass,
            ],
            [a + b, a - b, -a + b, -a - b],
        );
        for (bogie, x) in [(0usize, a), (1, -a)] {
            let (zb, tb) = (2 + 2 * bogie, 3 + 2 * bogie);
            h.spring(
                End {
                    z: zb,
                    pitch: Some((tb, 0.0)),
                },
                End {
                    z: 0,
                    pitch: Some((1, x)),
                },
                p.secondary_stiffness,
                p.secondary_damping,
            );
            for (w, s) in [(0usize, b), (1, -b)] {
                h.spring(
                    End {
                        z: wheel(2 * bogie + w),
                        pitch: None,
                    },
                    End {
                        z: zb,
                        pitch: Some((tb, s)),
                    },
                    p.primary_stiffness,
                    p.primary_damping,
                );
            }
        }
        let loads = h.static_axle_loads();
        for j in 0..4 {
            h.contact[j] = linear_contact(loads[j], wheel_radius);
        }
        h
    }

    /// The half car of a railfem vehicle file (docs/vehicles.md) with four wheelsets under
    /// two bogies under one car body: the bodies' masses, pitch inertias `iyy` and `x`, the
    /// vertical `k`, `c` (and `k_rot`, `c_rot` about `y`) of the suspensions at their
    /// points' `x`; the contact as for [`HalfCar::symmetric`]. Anything else is refused
    /// with one line naming the file.
    pub fn from_vehicle(
        v: &VehicleDef,
        file: &str,
        wheel_radius: f64,
    ) -> Result<HalfCar, FemError> {
        let refuse = |what: &str| {
            FemError::input(
                file,
                format!("the full-vehicle model needs one car body on two bogies on two wheelsets each: {what}"),
            )
        };
        let body = |name: &str| v.bodies.iter().position(|b| b.name == name);
        let mut wheelsets: Vec<usize> = Vec::new();
        for w in &v.wheelsets {
            wheelsets.push(body(&w.body).ok_or_else(|| refuse(&format!("no body `{}`", w.body)))?);
        }
        if wheelsets.len() != 4 {
            return Err(refuse(&format!("{} wheelsets", wheelsets.len())));
        }
        // Bogies: the bodies the wheelsets hang from; the car: what the bogies carry.
        let other_end = |b: usize| -> Vec<usize> {
            let name = &v.bodies[b].name;
            let mut out: Vec<usize> = v
                .suspensions
                .iter()
                .filter_map(|s| {
                    if &s.lower == name {
                        body(&s.upper)
                    } else {
                        None
                    }
                })
                .collect();
            out.sort_unstable();
            out.dedup();
            out
        };
        let mut bogies: Vec<usize> = Vec::new();
        for &w in &wheelsets {
            match other_end(w).as_slice() {
                [b] => bogies.push(*b),
                _ => {
                    return Err(refuse(&format!(
                        "wheelset `{}` is not under one bogie",
                        v.bodies[w].name
                    )))
                }
            }
        }
        let mut distinct = bogies.clone();
        distinct.sort_unstable();
        distinct.dedup();
        if distinct.len() != 2
            || distinct
                .iter()
                .any(|d| bogies.iter().filter(|b| *b == d).count() != 2)
        {
            return Err(refuse("the wheelsets are not two under each of two bogies"));
        }
        let car = match (
            other_end(distinct[0]).as_slice(),
            other_end(distinct[1]).as_slice(),
        ) {
            ([c0], [c1]) if c0 == c1 => *c0,
            _ => return Err(refuse("the bogies do not carry one car body")),
        };
        // Front first.
        let x = |b: usize| v.bodies[b].x;
        distinct.sort_by(|a, b| x(*b).total_cmp(&x(*a)));
        let mut order: Vec<usize> = (0..4).collect();
        order.sort_by(|&i, &j| {
            let bi = distinct.iter().position(|&d| d == bogies[i]);
            let bj = distinct.iter().position(|&d| d == bogies[j]);
            bi.cmp(&bj)
                .then(x(wheelsets[j]).total_cmp(&x(wheelsets[i])))
        });
        let xc = x(car);
        let b = &v.bodies;
        let mut mass = [0.0; DOFS];
        mass[0] = b[car].mass;
        mass[1] = b[car].iyy;
        for (k, &d) in distinct.iter().enumerate() {
            mass[2 + 2 * k] = b[d].mass;
            mass[3 + 2 * k] = b[d].iyy;
        }
        let mut axle_x = [0.0; 4];
        for (j, &i) in order.iter().enumerate() {
            mass[wheel(j)] = b[wheelsets[i]].mass;
            axle_x[j] = x(wheelsets[i]) - xc;
        }
        let mut h = HalfCar::new(mass, axle_x);
        let end = |name: &str, at: f64| -> Option<End> {
            let i = body(name)?;
            if i == car {
                return Some(End {
                    z: 0,
                    pitch: Some((1, at - xc)),
                });
            }
            if let Some(k) = distinct.iter().position(|&d| d == i) {
                return Some(End {
                    z: 2 + 2 * k,
                    pitch: Some((3 + 2 * k, at - x(i))),
                });
            }
            let j = order.iter().position(|&o| wheelsets[o] == i)?;
            Some(End {
                z: wheel(j),
                pitch: None,
            })
        };
        for (n, s) in v.suspensions.iter().enumerate() {
            let (Some(lo), Some(up)) = (end(&s.lower, s.at[0]), end(&s.upper, s.at[0])) else {
                return Err(FemError::input(
                    format!("{file}: suspension[{n}]"),
                    "the full-vehicle model takes suspensions between the car body, the bogies and the wheelsets only",
                ));
            };
            h.spring(lo, up, s.k[2], s.c[2]);
            if s.k_rot[1] != 0.0 || s.c_rot[1] != 0.0 {
                let mut g = [0.0; DOFS];
                if let Some((d, _)) = lo.pitch {
                    g[d] += 1.0;
                }
                if let Some((d, _)) = up.pitch {
                    g[d] -= 1.0;
                }
                h.add(&g, s.k_rot[1], s.c_rot[1]);
            }
        }
        let loads = h.static_axle_loads();
        if loads.iter().any(|l| !(l.is_finite() && *l > 0.0)) {
            return Err(refuse("its static axle loads are not all positive (a suspension without vertical stiffness?)"));
        }
        for j in 0..4 {
            h.contact[j] = linear_contact(loads[j], wheel_radius);
        }
        Ok(h)
    }

    /// The stiffness with the contact springs to a rigid rail.
    pub fn stiffness_on_rigid_track(&self) -> DMatrix<f64> {
        let mut k = DMatrix::from_fn(DOFS, DOFS, |i, j| self.k[i][j]);
        for j in 0..4 {
            k[(wheel(j), wheel(j))] += self.contact[j];
        }
        k
    }

    /// The static axle loads (N, positive down on the rail) under gravity
    /// [`G`] with the wheelsets held at the rail: the reactions of the suspensions'
    /// static solution with the wheelsets fixed, plus the wheelsets' weights.
    pub fn static_axle_loads(&self) -> [f64; 4] {
        // The six body DOFs with the wheelsets held: K_bb·q = −g·m.
        let kb = DMatrix::from_fn(6, 6, |i, j| self.k[i][j]);
        let f = DVector::from_fn(6, |i, _| if i % 2 == 0 { -G * self.mass[i] } else { 0.0 });
        let q = kb
            .lu()
            .solve(&f)
            .unwrap_or_else(|| DVector::from_element(6, f64::NAN));
        let mut loads = [0.0; 4];
        for (j, l) in loads.iter_mut().enumerate() {
            // The suspensions' pull on the held wheelset, K_wb·q, is the load it passes down.
            let mut r = 0.0;
            for i in 0..6 {
                r += self.k[wheel(j)][i] * q[i];
            }
            *l = r + G * self.mass[wheel(j)];
        }
        loads
    }

    /// The static state on level rigid track under gravity, from the unloaded springs:
    /// the displacements and the contact forces (N, compression positive) of the wheelsets.
    pub fn static_on_rigid_track(&self) -> (DVector<f64>, [f64; 4]) {
        let k = self.stiffness_on_rigid_track();
        let f = DVector::from_fn(DOFS, |i, _| {
            if i == 1 || i == 3 || i == 5 {
                0.0
            } else {
                -G * self.mass[i]
            }
        });
        let q = k
            .lu()
            .solve(&f)
            .unwrap_or_else(|| DVector::from_element(DOFS, f64::NAN));
        let mut forces = [0.0; 4];
        for (j, f) in forces.iter_mut().enumerate() {
            *f = -self.contact[j] * q[wheel(j)];
        }
        (q, forces)
    }

    /// Natural frequencies (Hz, ascending) on level rigid track: with the wheelsets on
    /// their contact springs (`held = false`, ten) or held at the rail (`held = true`, the
    /// six of the car body and the bogies).
    pub fn frequencies(&self, held: bool) -> Vec<f64> {
        let n = if held { 6 } else { DOFS };
        let k = self.stiffness_on_rigid_track();
        // M^−½·K·M^−½ (M diagonal), symmetric.
        let a = DMatrix::from_fn(n, n, |i, j| {
            k[(i, j)] / (self.mass[i] * self.mass[j]).sqrt()
        });
        let mut w: Vec<f64> = a
            .symmetric_eigen()
            .eigenvalues
            .iter()
            .map(|l| l.max(0.0).sqrt() / (2.0 * std::f64::consts::PI))
            .collect();
        w.sort_by(f64::total_cmp);
        w
    }
}

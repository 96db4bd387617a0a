//! Vehicle–bridge interaction with full vehicles: every vehicle a 10-DOF half car
//! ([`super::half_car`]) whose wheelsets rest on linear contact springs on the deck (or on
//! rigid track off it), coupled to the finite element deck's step.
//!
//! # The model
//!
//! Vehicle `v` has the mass, damping and stiffness `M_v`, `C_v`, `K_v` of its suspensions,
//! and its wheelset `j` at `x_j(t)` on the deck's path a contact spring `k_j`; its degrees
//! of freedom `z` are measured from the static state on rigid track, so gravity is in the
//! static axle loads `P_j` alone. With `w_j = g_jᵀ·u` the deck's upward displacement under
//! the wheelset (`g_j` the deck's interpolation, as for moving forces; `w_j = 0` off the
//! deck), the contact force on the deck (down) is `F_j = P_j + k_j·(w_j − z_wj)`, and
//!
//! ```text
//! deck      M·ü + C·u̇ + K·u = −Σ_j g_j·F_j
//! vehicle   M_v·z̈ + C_v·ż + (K_v + Σ_j k_j·e_j·e_jᵀ)·z = Σ_j e_j·k_j·w_j
//! ```
//!
//! (`e_j` picks wheelset `j`'s bounce).
//!
//! # The step
//!
//! Newmark's average acceleration on the whole system, as the sprung masses'
//! ([`super::interaction`]): each vehicle's equations at `t + h` read
//! `A·z = r + Σ_j e_j·k_j·w_j` with the constant `A = a₀M_v + a₁C_v + K_v + Σ_j k_j·e_j·e_jᵀ`
//! and `r` from its state at `t`. Eliminating the vehicle, `z_wj = ζ_j + Σ_l B_jl·k_l·w_l`
//! (`ζ = A⁻¹·r`, `B` the wheelset block of `A⁻¹`), leaves the deck's effective system
//! `(K_eff + U·Q·Uᵀ)·u = R − Σ_j g_j·(P_j − k_j·ζ_j)`, `U = [g_j]` over the wheelsets on
//! the deck, `Q_jl = k_j·δ_jl − k_j·B_jl·k_l` within a vehicle (zero between vehicles).
//! The wheelsets of one vehicle couple deck equations several metres apart, outside the
//! band, so the step solves it by Woodbury's identity with the deck's constant factored
//! `K_eff`: `y = K_eff⁻¹·R'`, `Z = K_eff⁻¹·U` (one band solve per wheelset on the deck),
//! `u = y − Z·(I + Q·Uᵀ·Z)⁻¹·Q·Uᵀ·y` (a dense system of the wheelsets on the deck).
//! A vehicle moves from its first wheelset's arrival on the deck until its last one has
//! left it; before, it stands still on rigid track.

use super::fe::{Deck, Stepper, Work};
use super::half_car::{wheel, HalfCar, DOFS};
use nalgebra::{DMatrix, DVector};

/// A vehicle of a full-vehicle train: its half car and where it is in the train.
#[derive(Debug, Clone, PartialEq)]
pub struct Vehicle {
    /// The half car.
    pub car: HalfCar,
    /// Distance (m) of the car body's centre behind the train's front: wheelset `j` is
    /// `centre − car.axle_x[j]` behind the front.
    pub centre: f64,
}

impl Vehicle {
    /// Distance behind the train's front of wheelset `j` (m).
    pub fn axle(&self, j: usize) -> f64 {
        self.centre - self.car.axle_x[j]
    }
}

/// One vehicle's Newmark constants: `A⁻¹`.
#[derive(Debug, Clone)]
struct VehicleStep {
    inv: DMatrix<f64>,
    loads: [f64; 4],
}

impl VehicleStep {
    fn new(c: &HalfCar, h: f64) -> VehicleStep {
        let (a0, a1) = (4.0 / (h * h), 2.0 / h);
        let mut a = DMatrix::from_fn(DOFS, DOFS, |i, j| a1 * c.c[i][j] + c.k[i][j]);
        for i in 0..DOFS {
            a[(i, i)] += a0 * c.mass[i];
        }
        for j in 0..4 {
            a[(wheel(j), wheel(j))] += c.contact[j];
        }
        // A is symmetric positive definite (masses > 0, K and C semi-definite).
        let inv = a
            .try_inverse()
            .unwrap_or_else(|| DMatrix::from_element(DOFS, DOFS, f64::NAN));
        VehicleStep {
            inv,
            loads: c.static_axle_loads(),
        }
    }
}

/// A wheelset on the deck: its vehicle, its number in the vehicle and the deck's
/// interpolation terms under it.
type OnDeck = (usize, usize, Vec<(usize, f64)>);

/// Per-run buffers of the full-vehicle step beyond the deck's [`Work`].
#[derive(Debug, Clone, Default)]
pub struct VehicleWork {
    /// Per vehicle `(z, ż, z̈)` (m or rad, per s, per s²).
    pub states: Vec<[[f64; DOFS]; 3]>,
    /// Per vehicle its `r` of the current step.
    r: Vec<DVector<f64>>,
    /// The wheelsets on the deck this step.
    on: Vec<OnDeck>,
    /// `K_eff⁻¹·g_j` per wheelset on the deck.
    z: Vec<Vec<f64>>,
    /// Largest and smallest contact force over the run, relative to the static load.
    pub contact_range: (f64, f64),
}

/// Runs the `vehicles` over `deck` at `v` (m/s) for `steps` steps from rest (the train's
/// front at the path's start at t = 0); fills the deck's `w.deflection` and
/// `w.acceleration` as [`Stepper::run`] does, and the vehicles' states in `x`.
pub fn run(
    st: &Stepper,
    deck: &Deck,
    vehicles: &[Vehicle],
    v: f64,
    steps: usize,
    (w, x): (&mut Work, &mut VehicleWork),
) {
    let h = st.dt;
    let (a0, a1, a2) = (4.0 / (h * h), 2.0 / h, 4.0 / h);
    st.start(deck, steps, w);
    let nv = vehicles.len();
    let consts: Vec<VehicleStep> = vehicles
        .iter()
        .map(|c| VehicleStep::new(&c.car, h))
        .collect();
    x.states.clear();
    x.states.resize(nv, [[0.0; DOFS]; 3]);
    x.r.clear();
    x.r.resize(nv, DVector::zeros(DOFS));
    x.contact_range = (1.0, 1.0);
    let length = deck.length();
    let n = deck.n;
    // A vehicle is active from its first wheelset's arrival until its last one has left.
    let span = |c: &Vehicle| -> (f64, f64) {
        let s: Vec<f64> = (0..4).map(|j| c.axle(j)).collect();
        let lo = s.iter().fold(f64::INFINITY, |m, &a| m.min(a));
        let hi = s.iter().fold(f64::NEG_INFINITY, |m, &a| m.max(a));
        (lo, hi)
    };
    let spans: Vec<(f64, f64)> = vehicles.iter().map(span).collect();
    let mut y = vec![0.0; n];
    for i in 1..=steps {
        let front = v * i as f64 * h;
        let active: Vec<usize> = (0..nv)
            .filter(|&k| spans[k].0 <= front && front - spans[k].1 <= length)
            .collect();
        w.r.fill(0.0);
        st.history(w);
        // Each active vehicle's r and ζ; the wheelsets on the deck.
        x.on.clear();
        let mut zeta: Vec<DVector<f64>> = Vec::with_capacity(active.len());
        for &k in &active {
            let c = &vehicles[k].car;
            let s = &x.states[k];
            let mut r = DVector::zeros(DOFS);
            for d in 0..DOFS {
                r[d] = c.mass[d] * (a0 * s[0][d] + a2 * s[1][d] + s[2][d]);
                let mut cd = 0.0;
                for e in 0..DOFS {
                    cd += c.c[d][e] * (a1 * s[0][e] + s[1][e]);
                }
                r[d] += cd;
            }
            zeta.push(&consts[k].inv * &r);
            x.r[k] = r;
            for j in 0..4 {
                let xj = front - vehicles[k].axle(j);
                if (0.0..=length).contains(&xj) {
                    let mut g = Vec::new();
                    deck.unit_terms(xj, &mut g);
                    x.on.push((k, j, g));
                }
            }
        }
        // R' = R − Σ g_j·(P_j − k_j·ζ_j).
        for (k, j, g) in &x.on {
            let a = active.iter().position(|a| a == k).unwrap_or(0);
            let c = &vehicles[*k].car;
            let f = consts[*k].loads[*j] - c.contact[*j] * zeta[a][wheel(*j)];
            for &(e, ge) in g {
                w.r[e] -= ge * f;
            }
        }
        // Woodbury: y = K_eff⁻¹·R', Z = K_eff⁻¹·U, u = y − Z·(I + Q·Uᵀ·Z)⁻¹·Q·Uᵀ·y.
        y.copy_from_slice(&w.r);
        st.solve_effective(&mut y);
        let m = x.on.len();
        if m > 0 {
            x.z.resize(m, Vec::new());
            for (p, (_, _, g)) in x.on.iter().enumerate() {
                let z = &mut x.z[p];
                z.clear();
                z.resize(n, 0.0);
                for &(e, ge) in g {
                    z[e] += ge;
                }
                st.solve_effective(z);
            }
            let dot =
                |g: &[(usize, f64)], v: &[f64]| -> f64 { g.iter().map(|&(e, ge)| ge * v[e]).sum() };
            let q = DMatrix::from_fn(m, m, |p, s| {
                let (kp, jp, _) = &x.on[p];
                let (ks, js, _) = &x.on[s];
                if kp != ks {
                    return 0.0;
                }
                let c = &vehicles[*kp].car;
                let b = consts[*kp].inv[(wheel(*jp), wheel(*js))];
                let d = if jp == js { c.contact[*jp] } else { 0.0 };
                d - c.contact[*jp] * b * c.contact[*js]
            });
            let utz = DMatrix::from_fn(m, m, |p, s| dot(&x.on[p].2, &x.z[s]));
            let uty = DVector::from_fn(m, |p, _| dot(&x.on[p].2, &y));
            let e = DMatrix::identity(m, m) + &q * utz;
            let t = &q * uty;
            let s = e.lu().solve(&t).unwrap_or_else(|| DVector::zeros(m));
            for (p, zp) in x.z.iter().enumerate().take(m) {
                for (yi, zi) in y.iter_mut().zip(zp) {
                    *yi -= zi * s[p];
                }
            }
        }
        w.r.copy_from_slice(&y);
        st.advance(w);
        // The vehicles: z = ζ + Σ_l A⁻¹[:, w_l]·k_l·w_l, then Newmark's update.
        for (a, &k) in active.iter().enumerate() {
            let c = &vehicles[k].car;
            let mut z = zeta[a].clone();
            for (kk, j, g) in &x.on {
                if *kk != k {
                    continue;
                }
                let wj: f64 = g.iter().map(|&(e, ge)| ge * w.q[e]).sum();
                let col = consts[k].inv.column(wheel(*j));
                z.axpy(c.contact[*j] * wj, &col, 1.0);
            }
            let s = &mut x.states[k];
            for d in 0..DOFS {
                let an = a0 * (z[d] - s[0][d]) - a2 * s[1][d] - s[2][d];
                s[1][d] += 0.5 * h * (s[2][d] + an);
                s[2][d] = an;
                s[0][d] = z[d];
            }
        }
        for (k, j, g) in &x.on {
            let c = &vehicles[*k].car;
            let wj: f64 = g.iter().map(|&(e, ge)| ge * w.q[e]).sum();
            let p = consts[*k].loads[*j];
            let rel = (p + c.contact[*j] * (wj - x.states[*k][0][wheel(*j)])) / p;
            x.contact_range.0 = x.contact_range.0.max(rel);
            x.contact_range.1 = x.contact_range.1.min(rel);
        }
        st.record(deck, i, w);
    }
}

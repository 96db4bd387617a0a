//! The finite element deck of a check and its time integration under moving axle loads.
//!
//! The deck is a railfem model — `beam3d` elements meshed from the plan's description
//! ([`described_model`]: planar bending, consistent mass) or any model file — with a deck
//! path of beam elements ([`Deck::new`]). Its stiffness `K` and mass `M` come from the
//! framework's assembly ([`crate::solvers::Driver::reference_system`]), its modes from the
//! framework's modal analysis; each axle is a force moving along the path with the
//! consistent nodal forces of [`crate::framework::loads::MovingForce::nodal_forces`] (the
//! path resolved as a framework `moving_force` load). Damping is Rayleigh,
//! `C = α·M + β·K`, fitted to the check's ζ at the first bending frequency and at the
//! cut-off.
//!
//! The model is linear and the check runs it a thousand times, so the step is the
//! driver's average-acceleration Newmark (β = ¼, γ = ½) written for that case alone
//! ([`Stepper`]): the effective matrix `K + (2/h)·C + (4/h²)·M` is factored once per
//! envelope as a band Cholesky, and a step is two band products and two band solves with
//! no allocation. The driver's general step takes the same states (tests/bridge_check.rs
//! compares them).

use super::trains::Train;
use crate::framework::builder::ModelBuilder;
use crate::framework::dof::Dof;
use crate::framework::loads::{LoadSpec, MovingForce};
use crate::framework::model::{AnalysisSpec, IntegratorKind, Model};
use crate::framework::sparse::CscMatrix;
use crate::framework::{DofSet, FemError};
use crate::solvers::Driver;
use nalgebra::Vector3;
use serde_json::json;

/// Young's modulus given to the meshed beams (Pa); `Iy = EI/E` keeps the given `EI`.
const E_DESCRIBED: f64 = 210e9;
/// Density given to the meshed beams (kg/m³); `A = μ/ρ` keeps the given mass per metre.
const RHO_DESCRIBED: f64 = 7850.0;

/// A deck of `spans` (m), `ei` (N·m²), `mass` (kg/m), `per_span` elements per span along X:
/// nodes `1..`, elements `1..` in order; only vertical bending free (ux, uy, rx, rz held);
/// `uz` held at every support; the spans continuous over the inner supports.
pub fn described_model(spans: &[f64], ei: f64, mass: f64, per_span: usize) -> ModelBuilder {
    let mut b = ModelBuilder::new("bridge-check deck");
    let plane = DofSet::of(&[Dof::Ux, Dof::Uy, Dof::Rx, Dof::Rz]);
    let mut x = 0.0;
    let mut id = 1u64;
    b.node_fixed(id, [0.0, 0.0, 0.0], plane.with(Dof::Uz));
    for l in spans {
        for k in 1..=per_span {
            id += 1;
            let support = k == per_span;
            let fixed = if support { plane.with(Dof::Uz) } else { plane };
            b.node_fixed(id, [x + l * k as f64 / per_span as f64, 0.0, 0.0], fixed);
        }
        x += l;
    }
    let p = json!({"E": E_DESCRIBED, "G": E_DESCRIBED / 2.6, "A": mass / RHO_DESCRIBED,
                   "Iy": ei / E_DESCRIBED, "Iz": ei / E_DESCRIBED, "J": ei / E_DESCRIBED,
                   "rho": RHO_DESCRIBED, "mass": "consistent"});
    for e in 1..id {
        b.element("beam3d", e, &[e, e + 1], &p);
    }
    b.analysis(AnalysisSpec {
        integrator: IntegratorKind::Newmark,
        beta: 0.25,
        gamma: 0.5,
        gravity: None,
        initial_static: false,
        ..Default::default()
    });
    b
}

/// Where a nodal DOF sits among the equations: `(equation, coefficient)` terms.
type Terms = Vec<(usize, f64)>;

/// A deck point where the response is read.
#[derive(Debug, Clone, PartialEq)]
pub struct Station {
    /// Distance along the deck path (m).
    pub station: f64,
    /// Node user id.
    pub node: u64,
    /// The equations of its vertical displacement.
    pub uz: Terms,
}

/// The deck: matrices, path, stations and frequencies.
#[derive(Debug, Clone)]
pub struct Deck {
    /// Equations.
    pub n: usize,
    /// Stiffness (N/m …).
    pub k: CscMatrix,
    /// Mass (kg …).
    pub m: CscMatrix,
    /// The path as a framework moving force (segments, ends, cumulative stations).
    pub path: MovingForce,
    /// Per segment, per end (I, J), per DOF (ux … rz): the equation terms.
    pub dofs: Vec<[[Terms; 6]; 2]>,
    /// Deck points with a vertical DOF, in order along the path.
    pub stations: Vec<Station>,
    /// Natural frequencies of vertical bending (Hz), ascending.
    pub frequencies: Vec<f64>,
}

impl Deck {
    /// The deck of `model` along the beam elements `deck` (ids, in order of travel);
    /// `modes` lowest modes are computed, the vertical ones kept. Errors name `origin`.
    pub fn new(model: Model, deck: &[u64], modes: usize, origin: &str) -> Result<Deck, FemError> {
        let spec = LoadSpec::MovingForce {
            elements: deck.to_vec(),
            force: [0.0, 0.0, -1.0],
            speed: 1.0,
            start: 0.0,
        };
        let path = match spec
            .resolve(&model)
            .map_err(|e| FemError::input(format!("{origin}: bridge.deck"), e.to_string()))?
        {
            crate::framework::loads::Load::MovingForce(m) => m,
            _ => unreachable!("a moving_force spec resolves to a moving force"),
        };
        let mut driver = Driver::new(model).map_err(|e| e.in_file(origin))?;
        let sys = driver.reference_system().map_err(|e| e.in_file(origin))?;
        let terms = |node: usize, d: usize| -> Terms {
            driver.asm.dofmap.terms(node, Dof::ALL[d]).collect()
        };
        let dofs: Vec<[[Terms; 6]; 2]> = path
            .segments
            .iter()
            .map(|&(i, j)| {
                [
                    std::array::from_fn(|d| terms(i, d)),
                    std::array::from_fn(|d| terms(j, d)),
                ]
            })
            .collect();
        let mut stations = Vec::new();
        for (s, &(i, j)) in path.segments.iter().enumerate() {
            for (node, at) in [(i, path.cumulative[s]), (j, path.cumulative[s + 1])] {
                let uz = terms(node, Dof::Uz.index());
                let id = driver.model.nodes[node].id;
                if uz.is_empty() || stations.last().is_some_and(|p: &Station| p.node == id) {
                    continue;
                }
                stations.push(Station {
                    station: at,
                    node: id,
                    uz,
                });
            }
        }
        if stations.is_empty() {
            return Err(FemError::input(
                format!("{origin}: bridge.deck"),
                "no deck node can move vertically; check the deck's supports",
            ));
        }
        let n = driver.neq();
        let nm = modes.min(n);
        let found = driver.modes(nm).map_err(|e| e.in_file(origin))?;
        let mut frequencies = Vec::new();
        for (c, w) in found.omega.iter().enumerate() {
            // A vertical bending mode: the deck's vertical motion dominates its horizontal.
            let (mut vert, mut horiz) = (0.0, 0.0);
            for (s, &(i, j)) in path.segments.iter().enumerate() {
                let _ = (i, j);
                for end in &dofs[s] {
                    let val = |t: &Terms| -> f64 {
                        t.iter().map(|(e, k)| k * found.shapes[(*e, c)]).sum()
                    };
                    vert += val(&end[2]).powi(2);
                    horiz += val(&end[0]).powi(2) + val(&end[1]).powi(2);
                }
            }
            if vert > horiz {
                frequencies.push(w / (2.0 * std::f64::consts::PI));
            }
        }
        Ok(Deck {
            n,
            k: sys.stiffness,
            m: sys.mass,
            path,
            dofs,
            stations,
            frequencies,
        })
    }

    /// Length of the deck path (m).
    pub fn length(&self) -> f64 {
        *self.path.cumulative.last().unwrap_or(&0.0)
    }

    /// The deck's upward vertical displacement at `station` (m) as `Σ g·u[equation]`: the
    /// terms `(equation, g)` into `g` (cleared first), i.e. minus the consistent nodal
    /// forces of a unit downward load there (the same shape functions interpolate both).
    pub fn unit_terms(&self, station: f64, g: &mut Vec<(usize, f64)>) {
        g.clear();
        let Some((s, xi)) = crate::framework::beam_chain::locate_on(&self.path.cumulative, station)
        else {
            return;
        };
        let (a, b) = self.path.ends[s];
        let nf = MovingForce::nodal_forces(Vector3::new(0.0, 0.0, 1.0), a, b, xi);
        let parts = [(0, nf.force_i, nf.moment_i), (1, nf.force_j, nf.moment_j)];
        for (end, force, moment) in parts {
            for d in 0..3 {
                g.extend(self.dofs[s][end][d].iter().map(|&(e, c)| (e, c * force[d])));
                g.extend(
                    self.dofs[s][end][d + 3]
                        .iter()
                        .map(|&(e, c)| (e, c * moment[d])),
                );
            }
        }
        g.retain(|t| t.1 != 0.0);
    }

    /// Adds the consistent nodal forces of a downward load `p` (N) at `station` (m) to `f`.
    pub fn add_load(&self, station: f64, p: f64, f: &mut [f64]) {
        let Some((s, xi)) = crate::framework::beam_chain::locate_on(&self.path.cumulative, station)
        else {
            return;
        };
        let (a, b) = self.path.ends[s];
        let nf = MovingForce::nodal_forces(Vector3::new(0.0, 0.0, -p), a, b, xi);
        let parts = [(0, nf.force_i, nf.moment_i), (1, nf.force_j, nf.moment_j)];
        for (end, force, moment) in parts {
            for d in 0..3 {
                for &(e, c) in &self.dofs[s][end][d] {
                    f[e] += c * force[d];
                }
                for &(e, c) in &self.dofs[s][end][d + 3] {
                    f[e] += c * moment[d];
                }
            }
        }
    }
}

/// A symmetric band matrix: the lower band, row by row, `b + 1` values a row
/// (`a[i·(b+1) + (j + b − i)] = A_ij`, `i − b ≤ j ≤ i`).
#[derive(Debug, Clone)]
pub struct Band {
    /// Size.
    pub n: usize,
    /// Half bandwidth.
    pub b: usize,
    /// Values.
    pub a: Vec<f64>,
}

impl Band {
    /// The half bandwidth of a CSC matrix.
    pub fn width(m: &CscMatrix) -> usize {
        let mut b = 0;
        for j in 0..m.n {
            for p in m.col_ptr[j]..m.col_ptr[j + 1] {
                b = b.max(m.row_idx[p].abs_diff(j));
            }
        }
        b
    }

    /// `Σ c_k·A_k` of CSC matrices (both triangles stored) in band form of half width `b`.
    pub fn combine(n: usize, b: usize, terms: &[(f64, &CscMatrix)]) -> Band {
        let mut a = vec![0.0; n * (b + 1)];
        for (c, m) in terms {
            for j in 0..m.n {
                for p in m.col_ptr[j]..m.col_ptr[j + 1] {
                    let i = m.row_idx[p];
                    if i >= j {
                        a[i * (b + 1) + (j + b - i)] += c * m.values[p];
                    }
                }
            }
        }
        Band { n, b, a }
    }

    /// `y += A·x`.
    pub fn mul_add(&self, x: &[f64], y: &mut [f64]) {
        let (b, w) = (self.b, self.b + 1);
        for (i, row) in self.a.chunks_exact(w).enumerate().take(self.n) {
            let j0 = i.saturating_sub(b);
            let xi = x[i];
            // The row's band left of the diagonal, against x[j0..i] and y[j0..i].
            let band = &row[b - (i - j0)..b];
            let mut s = 0.0;
            for ((v, xj), yj) in band.iter().zip(&x[j0..i]).zip(&mut y[j0..i]) {
                s += v * xj;
                *yj += v * xi;
            }
            y[i] += s + row[b] * xi;
        }
    }

    /// In-place Cholesky `A = L·Lᵀ` (L in the band); `Err(equation)` at a pivot ≤ 0.
    pub fn cholesky(&mut self) -> Result<(), usize> {
        let (n, b, w) = (self.n, self.b, self.b + 1);
        for i in 0..n {
            let j0 = i.saturating_sub(b);
            for j in j0..=i {
                let k0 = j0.max(j.saturating_sub(b));
                let mut s = self.a[i * w + (j + b - i)];
                for k in k0..j {
                    s -= self.a[i * w + (k + b - i)] * self.a[j * w + (k + b - j)];
                }
                if j == i {
                    if s <= 0.0 || !s.is_finite() {
                        return Err(i);
                    }
                    self.a[i * w + b] = s.sqrt();
                } else {
                    self.a[i * w + (j + b - i)] = s / self.a[j * w + b];
                }
            }
        }
        Ok(())
    }

    /// Solves `L·Lᵀ·x = r` in place after [`Band::cholesky`].
    pub fn solve(&self, x: &mut [f64]) {
        let (n, b, w) = (self.n, self.b, self.b + 1);
        for (i, row) in self.a.chunks_exact(w).enumerate().take(n) {
            let j0 = i.saturating_sub(b);
            let (done, rest) = x.split_at_mut(i);
            let mut s = rest[0];
            for (v, xk) in row[b - (i - j0)..b].iter().zip(&done[j0..]) {
                s -= v * xk;
            }
            rest[0] = s / row[b];
        }
        for i in (0..n).rev() {
            let row = &self.a[i * w..(i + 1) * w];
            let j0 = i.saturating_sub(b);
            let s = x[i] / row[b];
            x[i] = s;
            for (v, xk) in row[b - (i - j0)..b].iter().zip(&mut x[j0..i]) {
                *xk -= v * s;
            }
        }
    }
}

/// Rayleigh coefficients `(α, β)` giving the damping ratio `zeta` at the circular
/// frequencies `w1 < w2`: `ζ(ω) = α/(2ω) + β·ω/2` (Chopra, Dynamics of Structures,
/// Eq. 11.4.9 with equal ratios): `α = 2ζ·ω1·ω2/(ω1 + ω2)`, `β = 2ζ/(ω1 + ω2)`.
pub fn rayleigh(zeta: f64, w1: f64, w2: f64) -> (f64, f64) {
    (2.0 * zeta * w1 * w2 / (w1 + w2), 2.0 * zeta / (w1 + w2))
}

/// The deck's constant-step Newmark integrator (average acceleration): band `M`, `C` and
/// the factored effective matrix, shared read-only by the threads.
#[derive(Debug, Clone)]
pub struct Stepper {
    /// Step (s).
    pub dt: f64,
    m: Band,
    c: Band,
    keff: Band,
    keff0: Band,
}

/// Per-run work vectors of a [`Stepper`] (one per thread, reused across runs).
#[derive(Debug, Clone, Default)]
pub struct Work {
    pub(crate) q: Vec<f64>,
    v: Vec<f64>,
    a: Vec<f64>,
    pub(crate) r: Vec<f64>,
    p: Vec<f64>,
    s: Vec<f64>,
    /// Deflection histories per station (m, up).
    pub deflection: Vec<Vec<f64>>,
    /// Acceleration histories per station (m/s², up).
    pub acceleration: Vec<Vec<f64>>,
}

impl Stepper {
    /// The integrator of `deck` with Rayleigh `(alpha, beta)` and step `dt` (s).
    pub fn new(deck: &Deck, alpha: f64, beta: f64, dt: f64) -> Result<Stepper, FemError> {
        let n = deck.n;
        let b = Band::width(&deck.k).max(Band::width(&deck.m));
        let m = Band::combine(n, b, &[(1.0, &deck.m)]);
        let c = Band::combine(n, b, &[(alpha, &deck.m), (beta, &deck.k)]);
        let (a0, a1) = (4.0 / (dt * dt), 2.0 / dt);
        let mut keff = Band::combine(
            n,
            b,
            &[(1.0 + a1 * beta, &deck.k), (a0 + a1 * alpha, &deck.m)],
        );
        let keff0 = keff.clone();
        keff.cholesky().map_err(|eq| {
            FemError::input(
                "bridge-check deck",
                format!("the effective matrix is not positive definite at equation {eq}: the deck is not supported; hold its ends"),
            )
        })?;
        Ok(Stepper {
            dt,
            m,
            c,
            keff,
            keff0,
        })
    }

    /// Runs `train` over `deck` at `v` (m/s) for `steps` steps from rest, the first axle at
    /// the path's start at t = 0; fills `w.deflection` and `w.acceleration` at the deck's
    /// stations (`steps + 1` samples each).
    pub fn run(&self, deck: &Deck, train: &Train, v: f64, steps: usize, w: &mut Work) {
        let h = self.dt;
        self.start(deck, steps, w);
        let length = deck.length();
        // Axles on the deck: those with index in [first, last).
        let (mut first, mut last) = (0usize, 0usize);
        for i in 1..=steps {
            let t = i as f64 * h;
            let front = v * t;
            while last < train.axles.len() && train.axles[last].position <= front {
                last += 1;
            }
            while first < last && front - train.axles[first].position > length {
                first += 1;
            }
            w.r.fill(0.0);
            for ax in &train.axles[first..last] {
                deck.add_load(front - ax.position, ax.load, &mut w.r);
            }
            self.history(w);
            self.keff.solve(&mut w.r);
            self.advance(w);
            self.record(deck, i, w);
        }
    }

    /// Zeroes the state and sizes the histories of `w` for `steps` steps.
    pub(crate) fn start(&self, deck: &Deck, steps: usize, w: &mut Work) {
        let n = deck.n;
        for x in [&mut w.q, &mut w.v, &mut w.a, &mut w.r, &mut w.p, &mut w.s] {
            x.clear();
            x.resize(n, 0.0);
        }
        let ns = deck.stations.len();
        w.deflection.resize(ns, Vec::new());
        w.acceleration.resize(ns, Vec::new());
        for j in 0..ns {
            w.deflection[j].clear();
            w.deflection[j].resize(steps + 1, 0.0);
            w.acceleration[j].clear();
            w.acceleration[j].resize(steps + 1, 0.0);
        }
    }

    /// `w.r += M·(a0·q + a2·v + a) + C·(a1·q + v)`: the state's part of the step's
    /// right-hand side, beside the loads of `t + h`.
    pub(crate) fn history(&self, w: &mut Work) {
        let h = self.dt;
        let (a0, a1, a2) = (4.0 / (h * h), 2.0 / h, 4.0 / h);
        for e in 0..w.q.len() {
            w.p[e] = a0 * w.q[e] + a2 * w.v[e] + w.a[e];
            w.s[e] = a1 * w.q[e] + w.v[e];
        }
        self.m.mul_add(&w.p, &mut w.r);
        self.c.mul_add(&w.s, &mut w.r);
    }

    /// With `w.r` the solved `q_{n+1}`: `a_{n+1} = a0·Δq − a2·v_n − a_n`,
    /// `v_{n+1} = v_n + h/2·(a_n + a_{n+1})`, `q = q_{n+1}`.
    pub(crate) fn advance(&self, w: &mut Work) {
        let h = self.dt;
        let (a0, a2) = (4.0 / (h * h), 4.0 / h);
        for e in 0..w.q.len() {
            let an = a0 * (w.r[e] - w.q[e]) - a2 * w.v[e] - w.a[e];
            w.v[e] += 0.5 * h * (w.a[e] + an);
            w.a[e] = an;
            w.q[e] = w.r[e];
        }
    }

    /// Stores the stations' deflection and acceleration of sample `i`.
    pub(crate) fn record(&self, deck: &Deck, i: usize, w: &mut Work) {
        for (j, st) in deck.stations.iter().enumerate() {
            let (mut y, mut acc) = (0.0, 0.0);
            for &(e, c) in &st.uz {
                y += c * w.q[e];
                acc += c * w.a[e];
            }
            w.deflection[j][i] = y;
            w.acceleration[j][i] = acc;
        }
    }

    /// Solves `K_eff·x = r` in place with the factored effective matrix.
    pub(crate) fn solve_effective(&self, x: &mut [f64]) {
        self.keff.solve(x);
    }

    /// The unfactored effective matrix, copied into `into` (allocated on first use).
    pub(crate) fn effective<'b>(&self, into: &'b mut Option<Band>) -> &'b mut Band {
        let b = into.get_or_insert_with(|| self.keff0.clone());
        b.a.copy_from_slice(&self.keff0.a);
        b
    }

    /// The largest static deflection (m, magnitude) of any station under `train` as it
    /// crosses, sampled every `ds` (m) of travel; `(deflection, station)`.
    pub fn static_peak(deck: &Deck, train: &Train, ds: f64) -> Result<(f64, f64), FemError> {
        let b = Band::width(&deck.k);
        let mut k = Band::combine(deck.n, b, &[(1.0, &deck.k)]);
        k.cholesky().map_err(|eq| {
            FemError::input(
                "bridge-check deck",
                format!("the stiffness is singular at equation {eq}: hold the deck's supports"),
            )
        })?;
        let length = deck.length();
        let total = length + train.length();
        let steps = (total / ds).ceil() as usize;
        let mut f = vec![0.0; deck.n];
        let mut best = (0.0, 0.0);
        for i in 0..=steps {
            let front = i as f64 * ds;
            f.fill(0.0);
            for ax in &train.axles {
                let x = front - ax.position;
                if (0.0..=length).contains(&x) {
                    deck.add_load(x, ax.load, &mut f);
                }
            }
            k.solve(&mut f);
            for st in &deck.stations {
                let y: f64 = st.uz.iter().map(|&(e, c)| c * f[e]).sum();
                if y.abs() > best.0 {
                    best = (y.abs(), st.station);
                }
            }
        }
        Ok(best)
    }
}

//! Tests of the Craig–Bampton reduction on a planar Euler–Bernoulli beam span (cubic
//! Hermite elements with consistent mass, assembled here), against closed forms, the full
//! span's dense generalized eigenproblem and the full span's time response.

use super::cutoff::{period_error, resolved_omega_dt, CutOffRule};
use super::march::LinearMarch;
use super::switch::dense_energy;
use super::{CraigBampton, Split};
use crate::integrator::Integrator;
use crate::modal::ModalOptions;
use nalgebra::{DMatrix, DVector};
use railfem_framework::sparse::CscMatrix;
use std::f64::consts::PI;

/// A box-girder-like span: 30 m, `EI` = 1e11 N·m², 2e4 kg/m (first simply supported
/// frequency 3.9 Hz, as a 30 m viaduct span).
const L: f64 = 30.0;
const EI: f64 = 1.0e11;
const RHO_A: f64 = 2.0e4;
const ELEMENTS: usize = 30;

/// The beam's `K` and `M` over the nodal `(w, θ)` of `ELEMENTS + 1` nodes (DOF `2i` is
/// `w_i` in m, `2i + 1` is `θ_i` in rad), with the DOFs in `fixed` removed (renumbered in
/// order). Element matrices: Przemieniecki, *Theory of Matrix Structural Analysis*, 1968,
/// §5 and §11 (the cubic Hermite beam and its consistent mass).
fn beam(fixed: &[usize]) -> (CscMatrix, CscMatrix, Vec<Option<usize>>) {
    let h = L / ELEMENTS as f64;
    let nfull = 2 * (ELEMENTS + 1);
    let mut map = vec![None; nfull];
    let mut next = 0;
    for (d, slot) in map.iter_mut().enumerate() {
        if !fixed.contains(&d) {
            *slot = Some(next);
            next += 1;
        }
    }
    let ke = [
        [12.0, 6.0 * h, -12.0, 6.0 * h],
        [6.0 * h, 4.0 * h * h, -6.0 * h, 2.0 * h * h],
        [-12.0, -6.0 * h, 12.0, -6.0 * h],
        [6.0 * h, 2.0 * h * h, -6.0 * h, 4.0 * h * h],
    ];
    let me = [
        [156.0, 22.0 * h, 54.0, -13.0 * h],
        [22.0 * h, 4.0 * h * h, 13.0 * h, -3.0 * h * h],
        [54.0, 13.0 * h, 156.0, -22.0 * h],
        [-13.0 * h, -3.0 * h * h, -22.0 * h, 4.0 * h * h],
    ];
    let (sk, sm) = (EI / h.powi(3), RHO_A * h / 420.0);
    let (mut tk, mut tm) = (Vec::new(), Vec::new());
    for e in 0..ELEMENTS {
        let dofs = [2 * e, 2 * e + 1, 2 * e + 2, 2 * e + 3];
        for a in 0..4 {
            for b in 0..4 {
                if let (Some(i), Some(j)) = (map[dofs[a]], map[dofs[b]]) {
                    tk.push((i, j, sk * ke[a][b]));
                    tm.push((i, j, sm * me[a][b]));
                }
            }
        }
    }
    (
        CscMatrix::from_triplets(next, &tk),
        CscMatrix::from_triplets(next, &tm),
        map,
    )
}

/// Eigenvalues ω² of `K·x = ω²·M·x` (dense, `M` positive definite), ascending:
/// `L⁻¹·K·L⁻ᵀ` with `M = L·Lᵀ`.
fn dense_eigenvalues(k: &DMatrix<f64>, m: &DMatrix<f64>) -> Vec<f64> {
    let l = m.clone().cholesky().expect("M is positive definite").l();
    let li = l.try_inverse().expect("L is invertible");
    let a = &li * k * li.transpose();
    let a = (&a + a.transpose()) * 0.5;
    let mut ev: Vec<f64> = a.symmetric_eigenvalues().iter().copied().collect();
    ev.sort_by(f64::total_cmp);
    ev
}

/// The simply supported span: `w` fixed at both ends; boundary = the end rotations.
fn simply_supported() -> (CscMatrix, CscMatrix, Vec<Option<usize>>, Split) {
    let (k, m, map) = beam(&[0, 2 * ELEMENTS]);
    let boundary = vec![map[1].unwrap(), map[2 * ELEMENTS + 1].unwrap()];
    let interior = (0..k.n).filter(|i| !boundary.contains(i)).collect();
    (k, m, map, Split { interior, boundary })
}

/// Static exactness: a free-free span whose end nodes `(w, θ)` are the boundary. With no
/// interior load the exact deflection is the cubic through the end values (the beam
/// equation `EI·w'''' = 0`), which the Hermite elements represent exactly; the interior
/// of `Ψ·q_B` must equal it at every node (value and slope) to round-off, and so must
/// the full model's static answer `K_II·q_I = −K_IB·q_B` (dense LU, another path).
#[test]
fn guyan_part_is_statically_exact() {
    let (k, m, _) = beam(&[]);
    let n = k.n;
    let boundary = vec![0, 1, n - 2, n - 1];
    let interior: Vec<usize> = (2..n - 2).collect();
    let split = Split {
        interior: interior.clone(),
        boundary: boundary.clone(),
    };
    let cb = CraigBampton::build(
        &k,
        &m,
        None,
        &split,
        2.0 * PI * 50.0,
        &ModalOptions::default(),
    )
    .unwrap();
    let qb = [0.012, -0.003, -0.007, 0.002]; // w₀ (m), θ₀, w_L, θ_L
    let mut x_hat = vec![0.0; cb.size()];
    x_hat[..4].copy_from_slice(&qb);
    let q = cb.expand(&x_hat);
    // cubic Hermite interpolation of the end values
    let cubic = |x: f64| {
        let s = x / L;
        let (h1, h2, h3, h4) = (
            1.0 - 3.0 * s * s + 2.0 * s.powi(3),
            L * (s - 2.0 * s * s + s.powi(3)),
            3.0 * s * s - 2.0 * s.powi(3),
            L * (-s * s + s.powi(3)),
        );
        let (d1, d2, d3, d4) = (
            (-6.0 * s + 6.0 * s * s) / L,
            1.0 - 4.0 * s + 3.0 * s * s,
            (6.0 * s - 6.0 * s * s) / L,
            -2.0 * s + 3.0 * s * s,
        );
        (
            h1 * qb[0] + h2 * qb[1] + h3 * qb[2] + h4 * qb[3],
            d1 * qb[0] + d2 * qb[1] + d3 * qb[2] + d4 * qb[3],
        )
    };
    // the full model's static interior field, by a dense LU of K_II
    let kd = k.to_dense();
    let kii = DMatrix::from_fn(interior.len(), interior.len(), |i, j| {
        kd[(interior[i], interior[j])]
    });
    let rhs = DVector::from_fn(interior.len(), |i, _| {
        -(0..4)
            .map(|b| kd[(interior[i], boundary[b])] * qb[b])
            .sum::<f64>()
    });
    let full = kii.lu().solve(&rhs).unwrap();
    let scale = 0.012_f64;
    let (mut err_cubic, mut err_full) = (0.0_f64, 0.0_f64);
    for node in 1..ELEMENTS {
        let x = node as f64 * L / ELEMENTS as f64;
        let (w, t) = cubic(x);
        err_cubic = err_cubic
            .max((q[2 * node] - w).abs() / scale)
            .max((q[2 * node + 1] - t).abs() * L / scale);
        let (iw, it) = (2 * node - 2, 2 * node - 1);
        err_full = err_full
            .max((q[2 * node] - full[iw]).abs() / scale)
            .max((q[2 * node + 1] - full[it]).abs() * L / scale);
    }
    assert!(err_cubic < 1e-10, "against the cubic: {err_cubic:e}");
    assert!(
        err_full < 1e-10,
        "against the full static solve: {err_full:e}"
    );
    // K̂_Bη = Φᵀ·(K_IB + K_II·Ψ) vanishes: the boundary and the modes decouple in K̂.
    let coupling = cb.k_hat.view((0, 4), (4, cb.modes())).abs().max();
    assert!(
        coupling < 1e-9 * cb.k_hat.abs().max(),
        "K̂_Bη = {coupling:e}"
    );
}

/// The fixed-interface modes of the simply supported span are those of the clamped–clamped
/// beam, `ω_n = (β_n·L)²·√(EI/(ρA·L⁴))` with `β_n·L` = 4.7300, 7.8532, 10.9956, 14.1372, 17.2788
/// (Blevins, *Formulas for Natural Frequency and Mode Shape*, Table 8-1). The reduced
/// span's frequencies are Rayleigh–Ritz upper bounds of the full span's (dense
/// generalized eigenproblem), and up to a quarter of the cut-off (the band the rule's
/// `k = 4` serves, module `cutoff`) they are within 0.1 % of them; the modes between
/// `ω_c/4` and `ω_c` are printed. The full span's match the closed form `(nπ/L)²·√(EI/ρA)` within
/// 0.1 %, which checks the assembly.
#[test]
fn reduced_span_frequencies_match_the_full_span_below_the_cutoff() {
    let (k, m, _, split) = simply_supported();
    let cutoff = 2.0 * PI * 150.0;
    let cb = CraigBampton::build(&k, &m, None, &split, cutoff, &ModalOptions::default()).unwrap();
    let root = (EI / (RHO_A * L.powi(4))).sqrt();
    let clamped: Vec<f64> = [
        4.730_040_7,
        7.853_204_6,
        10.995_607_8,
        14.137_165_5,
        17.278_759_6,
    ]
    .iter()
    .map(|b| b * b * root)
    .collect();
    let below = clamped.iter().filter(|&&w| w <= cutoff).count();
    assert_eq!(cb.modes(), below, "kept modes {:?}", cb.omega);
    for (w, c) in cb.omega.iter().zip(&clamped) {
        assert!((w - c).abs() / c < 1e-3, "clamped mode {w} against {c}");
    }
    let full = dense_eigenvalues(&k.to_dense(), &m.to_dense());
    let reduced = dense_eigenvalues(&cb.k_hat, &cb.m_hat);
    let mut compared = 0;
    for (j, (&lf, &lr)) in full.iter().zip(&reduced).enumerate() {
        let (wf, wr) = (lf.sqrt(), lr.sqrt());
        if wf > cutoff {
            break;
        }
        let n = (j + 1) as f64;
        let closed = (n * PI / L).powi(2) * (EI / RHO_A).sqrt();
        let err = (wr - wf) / wf;
        println!(
            "mode {n}: full {:.4} Hz, reduced {:.4} Hz, error {:.2e} (ω/ω_c = {:.2})",
            wf / (2.0 * PI),
            wr / (2.0 * PI),
            err,
            wf / cutoff
        );
        assert!(
            (wf - closed).abs() / closed < 1e-3,
            "full mode {n}: {wf} against {closed}"
        );
        assert!(
            err >= -1e-12,
            "mode {n}: the reduced frequency is below the full one"
        );
        if wf <= 0.25 * cutoff {
            assert!(
                err < 1e-3,
                "mode {n}: reduced {wr} against full {wf} ({err:e})"
            );
            compared += 1;
        }
    }
    assert!(compared >= 3, "only {compared} modes below the cut-off");
}

/// The integrator resolves what the cut-off derivation says: a 1-DOF oscillator at
/// `ω = x_ε/Δt`, marched with the trapezoidal rule, has its period longer by `ε`
/// (measured from the zero crossings of 40 periods, to 1e-4 of the period), and the
/// default cut-off at 0.5 ms is 695.6 rad/s (110.7 Hz).
#[test]
fn cutoff_keeps_the_modes_the_integrator_resolves() {
    let eps = 0.01;
    let x = resolved_omega_dt(eps);
    assert!((period_error(x) - eps).abs() < 1e-12);
    assert!((x - (12.0 * eps).sqrt()).abs() < 0.01 * x, "x_ε = {x}");
    let (dt, omega) = (1e-3, x / 1e-3);
    let one = |v: f64| DMatrix::from_element(1, 1, v);
    let mut march = LinearMarch::new(
        Integrator::newmark(0.25, 0.5),
        dt,
        one(1.0),
        one(0.0),
        one(omega * omega),
    )
    .unwrap();
    let zero = DVector::zeros(1);
    let mut s = march
        .start(DVector::from_element(1, 1.0), DVector::zeros(1), &zero)
        .unwrap();
    // upward zero crossings, interpolated linearly between steps
    let mut crossings = Vec::new();
    let mut t = 0.0;
    while crossings.len() < 41 {
        let prev = s.q[0];
        march.step(&mut s, &zero, &zero);
        t += dt;
        if prev < 0.0 && s.q[0] >= 0.0 {
            crossings.push(t - dt * s.q[0] / (s.q[0] - prev));
        }
    }
    let period = (crossings[40] - crossings[0]) / 40.0;
    let elongation = period / (2.0 * PI / omega) - 1.0;
    assert!(
        (elongation - eps).abs() < 1e-4,
        "period elongation {elongation} against {eps}"
    );
    let w = CutOffRule::default().omega(5e-4);
    assert!((w - 695.6).abs() < 0.1, "default cut-off {w} rad/s");
}

/// Energy at a switch. A free-vibrating span (released from the static deflection under
/// a midspan force, marched with the trapezoidal rule, which conserves the energy of an
/// undamped linear system) is switched to the reduced form after 50 steps: the full
/// energy less the reduced energy equals the energy of the projection's residual
/// (`E_res`, module `switch`) to 1e-9 of the energy, and that is the only change; the
/// reduced march keeps its energy, and the expansion back to full form adds nothing
/// (1e-12). Projecting an expanded state gives it back with nothing discarded.
#[test]
fn a_switch_changes_the_energy_by_the_residual_above_the_cutoff() {
    let (k, m, map, split) = simply_supported();
    let cb = CraigBampton::build(
        &k,
        &m,
        None,
        &split,
        CutOffRule::default().omega(1e-3),
        &ModalOptions::default(),
    )
    .unwrap();
    let (kd, md) = (k.to_dense(), m.to_dense());
    let n = k.n;
    let mid = map[2 * (ELEMENTS / 2)].unwrap(); // w at midspan
    let mut f = DVector::zeros(n);
    f[mid] = 2.0e5; // N
    let q0 = kd.clone().cholesky().unwrap().solve(&f);
    let integ = Integrator::newmark(0.25, 0.5);
    let dt = 1e-3;
    let mut full =
        LinearMarch::new(integ, dt, md.clone(), DMatrix::zeros(n, n), kd.clone()).unwrap();
    let zero = DVector::zeros(n);
    let mut s = full.start(q0, DVector::zeros(n), &zero).unwrap();
    let e0 = dense_energy(&md, &kd, &s.q, &s.v);
    for _ in 0..50 {
        full.step(&mut s, &zero, &zero);
    }
    let e_full = dense_energy(&md, &kd, &s.q, &s.v);
    assert!((e_full - e0).abs() < 1e-10 * e0, "full march energy");

    let (mut r, discarded) = cb.to_reduced(s.q.as_slice(), s.v.as_slice(), s.a.as_slice());
    let e_red = cb.energy(&r);
    let ledger = e_full - e_red;
    println!(
        "switch: E = {e_full:.6} J, reduced {e_red:.6} J, E_res = {:.3e} J ({:.3e} of E; \
         strain {:.3e}, kinetic {:.3e}, coupling {:.3e}), {} modes",
        discarded.total(),
        discarded.total() / e_full,
        discarded.strain,
        discarded.kinetic,
        discarded.coupling,
        cb.modes()
    );
    assert!(
        (ledger - discarded.total()).abs() < 1e-9 * e_full,
        "ledger {ledger:e} J against E_res {:e} J",
        discarded.total()
    );

    let zr = DVector::zeros(cb.size());
    let mut red = LinearMarch::new(
        integ,
        dt,
        cb.m_hat.clone(),
        cb.c_hat.clone(),
        cb.k_hat.clone(),
    )
    .unwrap();
    r = red.start(r.q, r.v, &zr).unwrap();
    for _ in 0..50 {
        red.step(&mut r, &zr, &zr);
    }
    let e_red_later = cb.energy(&r);
    assert!(
        (e_red_later - e_red).abs() < 1e-10 * e_red,
        "reduced march energy"
    );
    let (q, v, a) = cb.to_full(&r);
    let e_back = dense_energy(
        &md,
        &kd,
        &DVector::from_vec(q.clone()),
        &DVector::from_vec(v.clone()),
    );
    assert!(
        (e_back - e_red_later).abs() < 1e-12 * e_red_later,
        "expansion: {e_back} J against {e_red_later} J"
    );
    let (again, nothing) = cb.to_reduced(&q, &v, &a);
    assert!(nothing.total().abs() < 1e-12 * e_red_later, "{nothing:?}");
    let diff = (&again.q - &r.q).amax() / r.q.amax();
    assert!(diff < 1e-10, "projection of the expansion: {diff:e}");
}

/// A span started in reduced form shakes like the full span. A vertical ground
/// acceleration with three components up to 6.1 Hz (0.5 m/s², a smooth 0.5 s ramp), a
/// cut-off from the default rule with that band (`f_out` = 10 Hz: `k·f_out` = 40 Hz, and
/// `x_ε/Δt` = 55 Hz at 1 ms), 2 s with the generalized-α integrator (ρ∞ = 0.9) on both:
/// the midspan deflection relative to the ground agrees within 1 % of its peak. The full
/// span switched to the reduced form at the end changes its energy by `E_res` (1e-9).
#[test]
fn a_reduced_span_follows_ground_motion_like_the_full_span() {
    let (k, m, map, split) = simply_supported();
    let dt = 1e-3;
    let rule = CutOffRule {
        output_band: 10.0,
        ..CutOffRule::default()
    };
    let cb = CraigBampton::build(
        &k,
        &m,
        None,
        &split,
        rule.omega(dt),
        &ModalOptions::default(),
    )
    .unwrap();
    let n = k.n;
    // r: 1 on every w, 0 on every θ (uniform vertical ground motion)
    let mut r = vec![0.0; n];
    for node in 0..=ELEMENTS {
        if let Some(i) = map[2 * node] {
            r[i] = 1.0;
        }
    }
    let mut mr = vec![0.0; n];
    m.mul_vec(&r, &mut mr);
    let (mr, mr_hat) = (
        DVector::from_vec(mr.clone()),
        DVector::from_vec(cb.reduce(&mr)),
    );
    let a_g = |t: f64| {
        let ramp = (t / 0.5).min(1.0);
        0.5 * ramp
            * ((2.0 * PI * 1.3 * t).sin() + (2.0 * PI * 3.4 * t).sin() + (2.0 * PI * 6.1 * t).sin())
    };
    let integ = Integrator::generalized_alpha(0.9);
    let (kd, md) = (k.to_dense(), m.to_dense());
    let mut full = LinearMarch::new(integ, dt, md, DMatrix::zeros(n, n), kd).unwrap();
    let mut red = LinearMarch::new(
        integ,
        dt,
        cb.m_hat.clone(),
        cb.c_hat.clone(),
        cb.k_hat.clone(),
    )
    .unwrap();
    let mut sf = full
        .start(DVector::zeros(n), DVector::zeros(n), &DVector::zeros(n))
        .unwrap();
    let nr = cb.size();
    let mut sr = red
        .start(DVector::zeros(nr), DVector::zeros(nr), &DVector::zeros(nr))
        .unwrap();
    let mid = map[2 * (ELEMENTS / 2)].unwrap();
    let (mut peak, mut worst) = (0.0_f64, 0.0_f64);
    for step in 0..2000 {
        let (t0, t1) = (step as f64 * dt, (step + 1) as f64 * dt);
        full.step(&mut sf, &(&mr * -a_g(t0)), &(&mr * -a_g(t1)));
        red.step(&mut sr, &(&mr_hat * -a_g(t0)), &(&mr_hat * -a_g(t1)));
        let w_red = cb.expand(sr.q.as_slice())[mid];
        peak = peak.max(sf.q[mid].abs());
        worst = worst.max((w_red - sf.q[mid]).abs());
    }
    println!(
        "ground motion: midspan peak {peak:.4e} m, reduced − full {worst:.3e} m ({:.3} % of \
         peak), {} modes, cut-off {:.1} Hz",
        100.0 * worst / peak,
        cb.modes(),
        cb.cutoff / (2.0 * PI)
    );
    assert!(
        worst < 0.01 * peak,
        "{worst:e} m against a peak of {peak:e} m"
    );
    // switching the shaking full span to the reduced form: the ledger changes by E_res
    let e_full = dense_energy(&m.to_dense(), &k.to_dense(), &sf.q, &sf.v);
    let (sw, discarded) = cb.to_reduced(sf.q.as_slice(), sf.v.as_slice(), sf.a.as_slice());
    let ledger = e_full - cb.energy(&sw);
    println!(
        "switch under ground motion at 2 s: E = {e_full:.4e} J, E_res = {:.3e} J ({:.2e} of E)",
        discarded.total(),
        discarded.total() / e_full
    );
    assert!((ledger - discarded.total()).abs() < 1e-9 * e_full);
}

/// A reduction carried through a renumbering ([`crate::partition::ReducedBasis::mapped`]
/// with a [`super::congruent::BlockMap`] built here from the permutation): the free-free
/// span with its end nodes as boundary, and the same span with its equations renumbered
/// by `i ↦ (7·i + 3) mod n` (so that interior and boundary orders both change). The carried
/// basis against the renumbered span's own reduction: `Ψ` to 1e-10 of its largest entry
/// (two Cholesky solves of the same matrix in other orders), each own mode within 1e-6 of
/// the carried modes' span in the `M_II` norm (both from the subspace iteration, each `ω²`
/// converged to 1e-10), and `ω` to 1e-8.
#[test]
fn a_reduction_carried_through_a_renumbering_is_the_renumbered_blocks_own() {
    use super::congruent::BlockMap;
    use crate::partition::ReducedBasis;
    let (k, m, _) = beam(&[]);
    let n = k.n;
    let last = 2 * ELEMENTS;
    let boundary = vec![0, 1, last, last + 1];
    let split = Split {
        interior: (0..n).filter(|i| !boundary.contains(i)).collect(),
        boundary,
    };
    let pi: Vec<usize> = (0..n).map(|i| (7 * i + 3) % n).collect();
    let permute = |a: &CscMatrix| {
        let mut t = Vec::new();
        for j in 0..n {
            for p in a.col_ptr[j]..a.col_ptr[j + 1] {
                t.push((pi[a.row_idx[p]], pi[j], a.values[p]));
            }
        }
        CscMatrix::from_triplets(n, &t)
    };
    let sorted = |v: Vec<usize>| {
        let mut v = v;
        v.sort_unstable();
        v
    };
    let split_b = Split {
        interior: sorted(split.interior.iter().map(|&i| pi[i]).collect()),
        boundary: sorted(split.boundary.iter().map(|&i| pi[i]).collect()),
    };
    let (kb, mb) = (permute(&k), permute(&m));
    let cutoff = 2.0 * PI * 150.0;
    let options = ModalOptions::default();
    let a = CraigBampton::build(&k, &m, None, &split, cutoff, &options).expect("a");
    let b = CraigBampton::build(&kb, &mb, None, &split_b, cutoff, &options).expect("b");
    let mut inv = vec![0; n];
    for (i, &j) in pi.iter().enumerate() {
        inv[j] = i;
    }
    let position = |list: &[usize], g: usize| list.iter().position(|&x| x == g).expect("listed");
    let map = BlockMap {
        interior: split_b
            .interior
            .iter()
            .map(|&g| position(&split.interior, inv[g]))
            .collect(),
        boundary: split_b
            .boundary
            .iter()
            .map(|&g| position(&split.boundary, inv[g]))
            .collect(),
    };
    assert!(!map.is_identity());
    let carried = ReducedBasis {
        psi: a.psi.clone(),
        phi: a.phi.clone(),
    }
    .mapped(&map);
    let psi_err = (&carried.psi - &b.psi).amax() / b.psi.amax();
    assert_eq!(a.omega.len(), b.omega.len());
    let omega_err = a
        .omega
        .iter()
        .zip(&b.omega)
        .map(|(x, y)| ((x - y) / y).abs())
        .fold(0.0, f64::max);
    let m_ii = super::restrict(&mb, &split_b.interior);
    let m_times = |x: &DMatrix<f64>| {
        let mut out = DMatrix::<f64>::zeros(x.nrows(), x.ncols());
        for j in 0..x.ncols() {
            m_ii.mul_vec(x.column(j).as_slice(), out.column_mut(j).as_mut_slice());
        }
        out
    };
    let rest = &b.phi - &carried.phi * carried.phi.tr_mul(&m_times(&b.phi));
    let norms = rest.tr_mul(&m_times(&rest));
    let phi_err = (0..norms.ncols())
        .map(|j| norms[(j, j)].max(0.0).sqrt())
        .fold(0.0, f64::max);
    println!(
        "renumbered span ({} modes): Ψ {psi_err:.2e}, modes outside the carried span {phi_err:.2e}, ω {omega_err:.2e}",
        b.omega.len()
    );
    assert!(psi_err <= 1e-10, "Ψ {psi_err:e}");
    assert!(phi_err <= 1e-6, "Φ {phi_err:e}");
    assert!(omega_err <= 1e-8, "ω {omega_err:e}");
}

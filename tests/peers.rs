//! What the comparison with OpenSees (docs/performance.md, "Honest peers") relies on:
//!
//! - `railfem bench --mass lumped` (beam3d `mass = "lumped_translational"`, OpenSees'
//!   default elasticBeamColumn mass) and the default consistent mass both give the moving
//!   force's midspan deflection of Frýba's closed-form series on a single span, and agree
//!   with each other;
//! - the lumped mass is recognized as diagonal and its products (inertia, kinetic energy)
//!   are the diagonal's, equal to the product over the matrix's pattern; the consistent
//!   mass is not; with the diagonal products the energy balance still closes, with and
//!   without Rayleigh damping;
//! - the lumped linear step's fused passes (`solvers/src/lumped_step.rs`) give the general
//!   attempt's states to the bit, for each integrator, across a change of Δt and from a
//!   state whose internal force must be formed afresh;
//! - `--mass` refuses bad input with one line, exit 2 (the peer file's refusals, of
//!   `railfem-measure peer FILE`, are tested in `examples/measure/tests/bad_input.rs`).

mod common;

use common::{fryba, railfem, refused_with};
use railfem::bench::{BenchBeam, BenchMass, DT, SPAN, SPEED};
use railfem::framework::model::{IntegratorKind, Rayleigh};
use railfem::framework::Dof;
use railfem::solvers::Driver;

/// Midspan `uz` of a one-span bench beam of `ne` elements with `mass`, at every step
/// while the force is on the span, against Frýba's series (200 terms): the largest
/// difference relative to the series' peak over those steps, and the history.
fn single_span_error(ne: usize, mass: BenchMass) -> (f64, Vec<f64>) {
    let geo = BenchBeam {
        spans: 1,
        elements_per_span: ne,
        mass,
    };
    // The force enters at x = 0 at t = DT/2 (the bench starts it at −v·DT/2).
    let entry = 0.5 * DT;
    let steps = ((SPAN / SPEED + entry) / DT).floor() as usize;
    let mut d = Driver::new(geo.model(steps).expect("model")).expect("driver");
    d.initialize().expect("initialize");
    let mid = (ne / 2 + 1) as u64;
    let (ei, m) = (2.1e11 * 3.038e-5, 7850.0 * 7.686e-3);
    let (mut worst, mut peak, mut hist) = (0.0f64, 0.0f64, Vec::new());
    for _ in 0..steps {
        d.step(DT).expect("step");
        let t = d.state.t - entry;
        let fe = -d.displacement(mid, Dof::Uz).expect("midspan node");
        let exact = fryba(0.5 * SPAN, t, 1.0e5, SPEED, SPAN, ei, m, 200);
        worst = worst.max((fe - exact).abs());
        peak = peak.max(exact.abs());
        hist.push(fe);
    }
    (worst / peak, hist)
}

/// Tolerances. The crossing lasts 0.31 s, a quarter of the first period (T₁ = 1.22 s; the
/// speed parameter α = πv/(Lω₁) ≈ 1.96), so the midspan history is the first mode's forced
/// and free parts, plus odd modes ≥ 3 at ≤ 1/81 of it. Newmark's period error at
/// dt = 2 ms is (ω dt)²/12 ≤ 2e-5 for mode 1 and 7e-3 for mode 3, a phase drift of mode 3
/// over the crossing below 0.03 rad, i.e. ≤ 4e-4 of the peak. The spatial error of the
/// lumped (translational) mass is O(h²) on ω₁: with 20 elements its ω₁ is within 0.1% of
/// the series' (5e-4 in ω₁ t over the crossing, times α ≈ 2 on the response); the
/// consistent mass is O(h⁴). On top comes the O(dt) error of the moving load's kinks at
/// the nodes (docs/performance.md, "What the plots say": ≈ 1e-3·dt/1 ms of the peak in
/// the Pareto case; measured here 5.3e-4 with the consistent mass). Hence 2e-3 for both
/// at 20 elements, and the two masses within 1e-3 of each other (measured 7.6e-5). A mass
/// wrong by 5% moves ω₁ by 2.5% and the response by ≈ 5%: caught.
#[test]
fn lumped_and_consistent_bench_beams_follow_frybas_series() {
    let (e_lumped, h_lumped) = single_span_error(20, BenchMass::Lumped);
    let (e_cons, h_cons) = single_span_error(20, BenchMass::Consistent);
    let (e_coarse, _) = single_span_error(4, BenchMass::Lumped);
    let peak = h_cons.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    let between = h_lumped
        .iter()
        .zip(&h_cons)
        .fold(0.0f64, |a, (x, y)| a.max((x - y).abs()))
        / peak;
    eprintln!(
        "vs Frýba: lumped 20 el {e_lumped:.3e}, consistent 20 el {e_cons:.3e}, lumped 4 el {e_coarse:.3e}; lumped vs consistent {between:.3e}"
    );
    assert!(e_lumped < 2e-3, "lumped: {e_lumped:e}");
    assert!(e_cons < 2e-3, "consistent: {e_cons:e}");
    assert!(between < 1e-3, "lumped vs consistent: {between:e}");
    // Refining the lumped mesh fivefold must bring it closer to the series.
    assert!(e_lumped < e_coarse, "{e_lumped:e} vs {e_coarse:e}");
}

/// The lumped bench beam really is the translational lumped mass (no rotary inertia): its
/// rotations are massless, so the total kinetic mass ρAL sits on the translations only.
#[test]
fn lumped_bench_beam_carries_translational_mass_only() {
    let geo = BenchBeam {
        spans: 2,
        elements_per_span: 4,
        mass: BenchMass::Lumped,
    };
    let mut d = Driver::new(geo.model(1).expect("model")).expect("driver");
    let sys = d.reference_system().expect("system");
    let m = &sys.mass;
    let (mut trans, mut rot, mut off) = (0.0, 0.0, 0.0);
    for j in 0..m.n {
        for p in m.col_ptr[j]..m.col_ptr[j + 1] {
            let i = m.row_idx[p];
            let v = m.values[p];
            if i != j {
                off += v.abs();
                continue;
            }
            let (_, dof) = d.asm.dofmap.dof_of(j);
            if dof.index() < 3 {
                trans += v;
            } else {
                rot += v.abs();
            }
        }
    }
    // Held DOFs carry no equation: of the translational mass ρAL per direction, the
    // supports hold ux at node 1 (ρAh/2), uy and uz at the three supports (ρAh/2 at the
    // ends, ρAh at the middle one).
    let (rho_a, h) = (7850.0 * 7.686e-3, SPAN / 4.0);
    let want = 3.0 * rho_a * 2.0 * SPAN - rho_a * h * (0.5 + 2.0 * (0.5 + 1.0 + 0.5));
    assert!((trans - want).abs() <= 1e-10 * want, "{trans} vs {want}");
    assert_eq!(rot, 0.0);
    assert_eq!(off, 0.0);
}

/// The diagonal-mass products: a lumped bench beam's mass is found diagonal, holds the
/// matrix's diagonal, and `M·x` through it equals the product over the stored pattern
/// exactly — every other term of that product is `0·x_j`, an exact zero, so the sums
/// agree to the bit (compared with `==`). The consistent mass (Hermite, coupling uz and
/// ry within each element) is not diagonal and keeps the product over the pattern.
#[test]
fn lumped_mass_products_use_the_diagonal_and_equal_the_pattern_product() {
    for (mass, diagonal) in [(BenchMass::Lumped, true), (BenchMass::Consistent, false)] {
        let geo = BenchBeam {
            spans: 3,
            elements_per_span: 6,
            mass,
        };
        let d = Driver::new(geo.model(1).expect("model")).expect("driver");
        let m = &d.asm.m_const;
        assert_eq!(d.asm.mass_diagonal().is_some(), diagonal, "{mass:?}");
        if let Some(diag) = d.asm.mass_diagonal() {
            for (j, &mj) in diag.iter().enumerate() {
                assert_eq!(mj, m.get(j, j));
            }
        }
        let x: Vec<f64> = (0..m.n)
            .map(|i| ((i * 37 % 11) as f64 - 5.0) * 1e-3)
            .collect();
        let (mut fast, mut general) = (vec![0.0; m.n], vec![0.0; m.n]);
        d.asm.mass_times(&x, &mut fast);
        m.mul_vec(&x, &mut general);
        if diagonal {
            assert_eq!(fast, general);
        } else {
            // Different summation orders (gather against scatter): round-off only.
            let scale = general.iter().fold(0.0f64, |a, v| a.max(v.abs()));
            for (a, b) in fast.iter().zip(&general) {
                assert!((a - b).abs() <= 1e-14 * scale, "{a} vs {b}");
            }
        }
    }
}

/// The energy balance with the diagonal products (inertia `M·a` and kinetic energy
/// `½·vᵀ·M·v` from the diagonal, no `C·v` without damping): for Newmark's average
/// acceleration on a linear model the integrator's share is zero to round-off (see
/// solvers/src/energy.rs), so the balance must close to ~1e-12 of the largest energy
/// (1e-9 allowed: far above round-off over 150 steps, far below an inertia or kinetic
/// energy that used the wrong mass — a 1 % error in either leaves a residual of order
/// 1 % of the kinetic energy). With Rayleigh damping (C = αM + βK, not diagonal) the
/// damping work must be positive and the balance close as well. The kinetic energy is
/// checked against `½·Σ vᵢ·(M·v)ᵢ` formed over the stored pattern.
#[test]
fn lumped_mass_energy_balance_closes_with_the_diagonal_products() {
    for rayleigh in [
        None,
        Some(Rayleigh {
            alpha: 0.5,
            beta: 1e-4,
        }),
    ] {
        let geo = BenchBeam {
            spans: 2,
            elements_per_span: 10,
            mass: BenchMass::Lumped,
        };
        let mut model = geo.model(150).expect("model");
        model.analysis.rayleigh = rayleigh;
        let mut d = Driver::new(model).expect("driver");
        assert!(d.asm.mass_diagonal().is_some());
        assert_eq!(d.asm.has_damping(), rayleigh.is_some());
        d.initialize().expect("initialize");
        for _ in 0..150 {
            d.step(DT).expect("step");
        }
        let ledger = d.energy.as_ref().expect("ledger");
        let tot = ledger.totals();
        let m = &d.asm.m_const;
        let mut mv = vec![0.0; m.n];
        m.mul_vec(&d.state.v, &mut mv);
        let kinetic: f64 = 0.5 * mv.iter().zip(&d.state.v).map(|(a, b)| a * b).sum::<f64>();
        eprintln!(
            "rayleigh {rayleigh:?}: external {:.6e} J, kinetic {:.6e} J, damping {:.6e} J, relative residual {:.3e}",
            tot.external_work,
            tot.kinetic,
            tot.damping,
            ledger.relative_error()
        );
        assert!(tot.kinetic > 0.0 && tot.external_work > 0.0);
        assert!(
            (tot.kinetic - kinetic).abs() <= 1e-12 * kinetic,
            "{} vs {kinetic}",
            tot.kinetic
        );
        assert!(
            ledger.relative_error() < 1e-9,
            "{}",
            ledger.relative_error()
        );
        match rayleigh {
            None => assert_eq!(tot.damping, 0.0),
            Some(_) => assert!(tot.damping > 0.0, "{}", tot.damping),
        }
    }
}

/// The lumped linear step is the general attempt's arithmetic in fewer passes, so the two
/// must agree to the bit (any tolerance would hide a reordered sum). Each integrator runs
/// 40 steps of `DT`, 20 of `DT/2` (a new factor and a new `a_w`) and 20 of `DT` again, on a
/// two-span lumped beam under the moving force; the second driver has the fused step
/// switched off. Every committed vector (q, v, a, f_int, f_ext) and the energy totals are
/// compared after every step. A driver whose state was set by hand (its `f_int` not formed
/// at its `q`) must form `K·q` first: checked by starting both from a displaced state.
/// Rayleigh damping or a consistent mass must leave the general attempt in charge.
#[test]
fn lumped_linear_step_equals_the_general_attempt_to_the_bit() {
    let geo = BenchBeam {
        spans: 2,
        elements_per_span: 10,
        mass: BenchMass::Lumped,
    };
    for (kind, name) in [
        (IntegratorKind::Newmark, "newmark"),
        (IntegratorKind::Hht, "hht"),
        (IntegratorKind::GeneralizedAlpha, "generalized-alpha"),
        (IntegratorKind::Registered("bathe".into()), "bathe"),
    ] {
        let build = || {
            let mut model = geo.model(80).expect("model");
            model.analysis.integrator = kind.clone();
            model.analysis.alpha = 0.05;
            model.analysis.rho_inf = 0.8;
            Driver::new(model).expect("driver")
        };
        let (mut fused, mut general) = (build(), build());
        general.set_lumped_step(false);
        assert!(fused.lumped_linear_applies() && !general.lumped_linear_applies());
        for d in [&mut fused, &mut general] {
            d.initialize().expect("initialize");
            // A displaced start whose internal force the state does not hold.
            for (i, q) in d.state.q.iter_mut().enumerate() {
                *q = 1e-6 * ((i % 17) as f64 - 8.0);
            }
        }
        let dts = std::iter::repeat_n(DT, 40)
            .chain(std::iter::repeat_n(0.5 * DT, 20))
            .chain(std::iter::repeat_n(DT, 20));
        for (k, dt) in dts.enumerate() {
            fused.step(dt).expect("step");
            general.step(dt).expect("step");
            let (a, b) = (&fused.state, &general.state);
            for (what, x, y) in [
                ("q", &a.q, &b.q),
                ("v", &a.v, &b.v),
                ("a", &a.a, &b.a),
                ("f_int", &a.f_int, &b.f_int),
                ("f_ext", &a.f_ext, &b.f_ext),
            ] {
                let same = x
                    .iter()
                    .zip(y.iter())
                    .all(|(p, q)| p.to_bits() == q.to_bits());
                assert!(same, "{name}, step {k}: {what} differs");
            }
            assert_eq!(a.t.to_bits(), b.t.to_bits());
            let (ea, eb) = (
                fused.energy.as_ref().expect("ledger").totals(),
                general.energy.as_ref().expect("ledger").totals(),
            );
            assert_eq!(
                ea.kinetic.to_bits(),
                eb.kinetic.to_bits(),
                "{name}, step {k}"
            );
            assert_eq!(ea.strain.to_bits(), eb.strain.to_bits(), "{name}, step {k}");
        }
        // The motion is not trivial: the midspan moved.
        assert!(fused.state.q.iter().any(|q| q.abs() > 1e-4), "{name}");
    }
    let mut damped = geo.model(10).expect("model");
    damped.analysis.rayleigh = Some(Rayleigh {
        alpha: 0.5,
        beta: 1e-4,
    });
    assert!(!Driver::new(damped).expect("driver").lumped_linear_applies());
    let consistent = BenchBeam {
        mass: BenchMass::Consistent,
        ..geo
    };
    let d = Driver::new(consistent.model(10).expect("model")).expect("driver");
    assert!(!d.lumped_linear_applies());
}

#[test]
fn bench_mass_option_refuses_unknown_values() {
    let o = railfem(&[
        "bench", "--mass", "diagonal", "--sizes", "100", "--steps", "1",
    ]);
    refused_with(
        "--mass diagonal",
        &o,
        &["--mass diagonal", "consistent", "lumped"],
    );
    let o = railfem(&[
        "bench",
        "--case",
        "train-bridge",
        "--mass",
        "lumped",
        "--sizes",
        "100",
    ]);
    refused_with("--mass with train-bridge", &o, &["--mass", "beam"]);
}

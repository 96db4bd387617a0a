//! The references of `railfem pareto` and the convergence of the FE runs against them.
//!
//! - The sprung-mass reference (modal equations + RK4, `railfem::pareto::sprung_reference`)
//!   is converged: halving its step and halving its number of modes both leave it unchanged
//!   to far below the FE errors it is used to measure.
//! - The FE sprung-mass run (beam3d + the moving spring element) approaches it as dt falls.
//! - The FE moving-force run approaches Frýba's series as the mesh is refined.
//! - The train–bridge case's errors fall as Δt halves, with second-order-like rates for
//!   the girder's deflection and at least first order for the wheel forces.

use railfem::pareto::{
    force_run, period1, sprung_reference, sprung_run, Scheme, REF_MODES, REF_SAMPLES, REF_SUBSTEPS,
};

fn max_rel(a: &[f64], b: &[f64]) -> f64 {
    let peak = b.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    a.iter()
        .zip(b)
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()))
        / peak
}

/// Two independent checks of the reference's own error, then the FE against it.
///
/// Reference: RK4 is fourth order, so halving its step changes the history by ~1/15 of
/// its step error; the modal truncation after N modes is `O(Σ_{n>N} n⁻⁴) ≈ 1/(3N³)`
/// relative (≈ 1.2e-5 for N = 30). Both differences must stay below 2e-5 of the peak,
/// more than ten times below the smallest FE error the grid measures (≈ 3e-4).
///
/// FE: 8 elements, Newmark average acceleration. Its time error is the period elongation
/// `(ω₁Δt)²/12` of the dynamic part (≈ 6% of the peak here); the error must fall at each
/// halving of dt, and at dt = T₁/80 (phase drift ≈ 8 periods · 2π · 5.1e-4 ≈ 0.026 rad of
/// the dynamic part, ≈ 1.6e-3 of the peak) it must be below 3e-3.
#[test]
fn sprung_mass_reference_is_converged_and_fe_approaches_it() {
    let reference = sprung_reference(REF_MODES, REF_SAMPLES, REF_SUBSTEPS);
    let finer = sprung_reference(REF_MODES, REF_SAMPLES, 2 * REF_SUBSTEPS);
    let fewer_modes = sprung_reference(REF_MODES / 2, REF_SAMPLES, REF_SUBSTEPS);
    let d_step = max_rel(&finer, &reference);
    let d_modes = max_rel(&fewer_modes, &reference);
    eprintln!("reference: halved step changes it by {d_step:.3e}, half the modes by {d_modes:.3e}");
    assert!(d_step < 2e-5, "RK4 step not converged: {d_step:e}");
    assert!(
        d_modes < 2e-5,
        "modal truncation not converged: {d_modes:e}"
    );

    let t1 = period1();
    let errs: Vec<f64> = [20.0, 40.0, 80.0]
        .iter()
        .map(|n| {
            sprung_run(8, t1 / n, Scheme::Newmark, &reference)
                .expect("sprung run")
                .1
        })
        .collect();
    eprintln!("sprung mass, 8 elements, dt = T1/20, /40, /80: errors {errs:?}");
    assert!(
        errs[0] > errs[1] && errs[1] > errs[2],
        "error must fall with dt: {errs:?}"
    );
    assert!(errs[2] < 3e-3, "dt = T1/80: error {:.3e}", errs[2]);
}

/// Moving force at a fine step (dt = T₁/320, time error ≈ 3.5e-4 of the peak) on 2, 4 and
/// 8 elements: the error must fall with each refinement. With 2 elements the consistent
/// mass misplaces the dynamic part badly (the error is ~1e-2); by 8 elements it is within
/// a factor two of the time error, so the check stops there.
#[test]
fn moving_force_error_falls_with_mesh_refinement() {
    let dt = period1() / 320.0;
    let errs: Vec<f64> = [2, 4, 8]
        .iter()
        .map(|&ne| force_run(ne, dt, Scheme::Newmark).expect("force run").1)
        .collect();
    eprintln!("moving force, dt = T1/320, 2/4/8 elements: errors {errs:?}");
    assert!(
        errs[0] > errs[1] && errs[1] > errs[2],
        "error must fall with mesh refinement: {errs:?}"
    );
    assert!(errs[2] < 1e-3, "8 elements: error {:.3e}", errs[2]);
}

/// The train–bridge case (`railfem::pareto_train`) on a short window: the first 0.12 s, in
/// which the front wheelset rolls from the approach onto the bridge (at 0.0625 s) — the
/// largest wheel-force transient of the crossing — on the 0.625 m mesh (one element per
/// fastener bay), generalized-α ρ∞ = 0.8, errors against a run at Δt = 0.125 ms.
///
/// Generalized-α is second order, so halving Δt divides the error by ≈ 4 where the
/// response is resolved. The girder's deflection w is (its modes are at ω·Δt ≤ 0.1): the
/// observed order must lie between 1 and 2.5 at each halving from 2 ms to 0.5 ms. The wheel
/// force Q is not fully: the wheel on its 1e10 N/m penalty spring rings at ≈ 500 Hz
/// (ω·Δt = 6.7 at 2 ms, 1.7 at 0.5 ms), where the scheme damps and shifts it by amounts
/// that do not shrink as Δt² yet; measured, one halving gives order ≈ 1.0, the next ≈ 1.5.
/// So for Q: the error must fall at each halving and its mean order over the two halvings
/// must lie between 1 and 2.5. The reference's own error enters every error equally and
/// cannot raise an observed order (it flattens it). Q is therefore compared from
/// t = 0.02 s on: the start from rest into 80 m/s sets the penalty spring ringing, and over
/// the first 0.01 s the reference itself is off by 1–5e-3 of the static load (half its
/// step changes it by that; from 0.02 s by 7.7e-4, measured on the h = 0.0694 m reference
/// of `railfem pareto --cases train-bridge`), half the 0.5 ms run's error; counted from
/// t = 0, that flattened the second halving to an order of 0.47 on this mesh. w is compared
/// over the whole window.
#[test]
fn train_bridge_error_falls_with_dt() {
    use railfem::framework::model::SolverChoice;
    use railfem::pareto_train::{errors, errors_from, simulate, Settings, SETTLE, SPACING};
    let t_end = 0.12;
    let run = |dt: f64| {
        simulate(
            &Settings {
                dt,
                h: SPACING,
                scheme: Scheme::GenAlpha,
                solver: SolverChoice::Direct,
            },
            t_end,
        )
        .expect("train-bridge run")
    };
    let reference = run(1.25e-4);
    let e: Vec<[f64; 3]> = [2e-3, 1e-3, 5e-4]
        .iter()
        .map(|&dt| {
            let r = run(dt);
            let (all, late) = (errors(&r, &reference), errors_from(&r, &reference, SETTLE));
            [late[0], late[1], all[2]]
        })
        .collect();
    eprintln!("train-bridge, 0.625 m, dt = 2, 1, 0.5 ms: errors [Q, dQ/Q (t ≥ 0.02 s), w] {e:?}");
    for (q, name) in [(0, "Q"), (2, "w")] {
        assert!(
            e[0][q] > e[1][q] && e[1][q] > e[2][q],
            "{name}: error must fall as dt halves: {e:?}"
        );
        let orders = [(e[0][q] / e[1][q]).log2(), (e[1][q] / e[2][q]).log2()];
        eprintln!("{name}: observed orders {orders:.2?}");
        let checked: Vec<f64> = if q == 0 {
            vec![0.5 * (orders[0] + orders[1])]
        } else {
            orders.to_vec()
        };
        for o in checked {
            assert!(
                (1.0..=2.5).contains(&o),
                "{name}: observed order {o:.2} outside [1, 2.5] ({e:?})"
            );
        }
    }
}

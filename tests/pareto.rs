//! The references of `railfem pareto` and the convergence of the FE runs against them.
//!
//! - The sprung-mass reference (modal equations + RK4, `railfem::pareto::sprung_reference`)
//!   is converged: halving its step and halving its number of modes both leave it unchanged
//!   to far below the FE errors it is used to measure.
//! - The FE sprung-mass run (beam3d + the moving spring element) approaches it as dt falls.
//! - The FE moving-force run approaches Frýba's series as the mesh is refined.

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

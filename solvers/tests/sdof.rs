//! Single-DOF checks of the driver against Newmark's closed forms, with a minimal spring
//! and mass written here (so the driver is tested independently of the element library).

use nalgebra::DMatrix;
use railfem_framework::builder::ModelBuilder;
use railfem_framework::element::*;
use railfem_framework::model::AnalysisSpec;
use railfem_framework::registry::{BuildContext, ElementKind, ElementSpec, Sample};
use railfem_framework::{DofSet, FemError};
use railfem_solvers::Driver;

/// A grounded linear spring k on ux plus a point mass m on ux.
struct Sdof {
    nodes: [NodeDofs; 1],
    k: f64,
    m: f64,
    u: f64,
}

impl Element for Sdof {
    fn kind(&self) -> &str {
        "test_sdof"
    }
    fn connectivity(&self) -> &[NodeDofs] {
        &self.nodes
    }
    fn properties(&self) -> ElementProperties {
        ElementProperties {
            linear: true,
            has_mass: true,
            objective: false,
            declared_mass: Some(self.m),
            ..Default::default()
        }
    }
    fn update(&mut self, t: &TrialState) -> Result<(), ElementError> {
        self.u = t.disp[0];
        Ok(())
    }
    fn resisting_force(&self, f: &mut [f64]) {
        f[0] = self.k * self.u;
    }
    fn tangent_stiffness(&self, k: &mut DMatrix<f64>) {
        k[(0, 0)] = self.k;
    }
    fn mass(&self, m: &mut DMatrix<f64>) {
        m[(0, 0)] = self.m;
    }
}

fn build(spec: &ElementSpec, ctx: &mut dyn BuildContext) -> Result<Box<dyn Element>, FemError> {
    let n = ctx.node_index(spec.nodes[0]).unwrap();
    let k = spec.params["k"].as_f64().unwrap();
    let m = spec.params["m"].as_f64().unwrap();
    Ok(Box::new(Sdof {
        nodes: [NodeDofs {
            node: n,
            dofs: DofSet::of(&[railfem_framework::Dof::Ux]),
        }],
        k,
        m,
        u: 0.0,
    }))
}

railfem_framework::inventory::submit! {
    ElementKind { name: "test_sdof", description: "test", params: Vec::new, build, samples: Vec::<Sample>::new }
}

fn driver(k: f64, m: f64, dt: f64) -> Driver {
    let mut b = ModelBuilder::new("sdof");
    b.node(1, [0.0; 3]);
    b.element("test_sdof", 1, &[1], &serde_json::json!({"k": k, "m": m}));
    b.analysis(AnalysisSpec {
        dt,
        ..Default::default()
    });
    Driver::new(b.build().unwrap()).unwrap()
}

/// Average acceleration on undamped free vibration: the discrete solution is
/// `u_n = cos(ω̄·n·Δt)` with `ω̄Δt = 2·arctan(ωΔt/2)` exactly (the amplification matrix has
/// unit-modulus eigenvalues `e^{±iω̄Δt}`), and the energy `½mv² + ½ku²` is conserved
/// exactly: both to round-off over 1000 periods.
#[test]
fn newmark_period_and_energy() {
    let (k, m): (f64, f64) = (4.0e6, 1.0e3);
    let w = (k / m).sqrt();
    let period = 2.0 * std::f64::consts::PI / w;
    let dt = period / 20.0;
    let mut d = driver(k, m, dt);
    d.state.q[0] = 1e-3;
    d.initialize().unwrap();
    let e0 = 0.5 * k * 1e-6;
    let wbar = 2.0 * (w * dt / 2.0).atan() / dt;
    let mut worst_u: f64 = 0.0;
    let mut worst_e: f64 = 0.0;
    for n in 1..=20_000 {
        d.step(dt).unwrap();
        let u = d.state.q[0];
        let exact = 1e-3 * (wbar * n as f64 * dt).cos();
        worst_u = worst_u.max((u - exact).abs() / 1e-3);
        let e = 0.5 * m * d.state.v[0].powi(2) + 0.5 * k * u * u;
        worst_e = worst_e.max((e - e0).abs() / e0);
    }
    assert!(
        worst_u < 1e-6,
        "displacement vs discrete closed form: {worst_u:e}"
    );
    assert!(worst_e < 1e-10, "energy drift: {worst_e:e}");
    // One factorization for the whole linear run.
    assert_eq!(d.summary.factorizations, 1);
}

fn driver_with(
    k: f64,
    m: f64,
    dt: f64,
    integrator: railfem_framework::model::IntegratorKind,
    alpha: f64,
    rho_inf: f64,
) -> Driver {
    let mut b = ModelBuilder::new("sdof");
    b.node(1, [0.0; 3]);
    b.element("test_sdof", 1, &[1], &serde_json::json!({"k": k, "m": m}));
    b.analysis(AnalysisSpec {
        dt,
        integrator,
        alpha,
        rho_inf,
        ..Default::default()
    });
    Driver::new(b.build().unwrap()).unwrap()
}

/// High-frequency dissipation: at ωΔt = 1e4 the amplitude of free vibration decays per
/// step by the spectral radius at infinity, ρ∞ = ρ∞ for Chung–Hulbert generalized-α and
/// ρ∞ = (1 − α)/(1 + α) for HHT-α (their closed forms). Measured as
/// |u_{2N}/u_N|^{1/N} with N = 200; the double root at infinity adds a factor 2^{1/N}
/// (0.35 %), so the tolerance is 1 %. Newmark's average acceleration keeps ρ = 1 (energy
/// conserving, tested above).
#[test]
fn spectral_radius_at_infinity() {
    use railfem_framework::model::IntegratorKind;
    let (k, m): (f64, f64) = (1e8, 1.0);
    let w = (k / m).sqrt();
    let dt = 1e4 / w;
    for (kind, alpha, rho, expect) in [
        (IntegratorKind::GeneralizedAlpha, 0.0, 0.5, 0.5),
        (IntegratorKind::GeneralizedAlpha, 0.0, 0.8, 0.8),
        (IntegratorKind::Hht, 0.1, 0.0, 0.9 / 1.1),
        (IntegratorKind::Hht, 0.3, 0.0, 0.7 / 1.3),
    ] {
        let mut d = driver_with(k, m, dt, kind.clone(), alpha, rho);
        d.state.q[0] = 1.0;
        d.initialize().unwrap();
        let n = 200;
        let mut u_n = 0.0;
        for step in 1..=2 * n {
            d.step(dt).unwrap();
            if step == n {
                u_n = d.state.q[0];
            }
        }
        let measured = (d.state.q[0] / u_n).abs().powf(1.0 / n as f64);
        assert!(
            (measured - expect).abs() < 1e-2 * expect,
            "{kind:?}: ρ∞ measured {measured}, closed form {expect}"
        );
    }
}

// ---------------------------------------------------------------------------------------
// Amplification matrix of the generalized-α family: spectral radius and period.
// ---------------------------------------------------------------------------------------

use nalgebra::{Complex, Matrix3};
use railfem_solvers::integrator::Integrator;

/// The amplification matrix `A` of the undamped SDOF `ü + ω²u = 0`, written here from the
/// scheme's three equations (not from the driver), on the state `x = [u, Δt·v, Δt²·a]`
/// with `Ω = ω·Δt`:
///
/// - balance at the intermediate times, times `Δt²`:
///   `(1−α_m)·A₁ + α_m·A₀ + Ω²·((1−α_f)·u₁ + α_f·u₀) = 0`,
/// - `u₁ = u₀ + V₀ + (½−β)·A₀ + β·A₁`,
/// - `V₁ = V₀ + (1−γ)·A₀ + γ·A₁`,
///
/// i.e. `L·x₁ = R·x₀` and `A = L⁻¹·R`.
fn amplification(ig: &Integrator, omega_dt: f64) -> Matrix3<f64> {
    let (b, g, am, af) = (ig.beta, ig.gamma, ig.alpha_m, ig.alpha_f);
    let w2 = omega_dt * omega_dt;
    let l = Matrix3::new(w2 * (1.0 - af), 0.0, 1.0 - am, 1.0, 0.0, -b, 0.0, 1.0, -g);
    let r = Matrix3::new(-w2 * af, 0.0, -am, 1.0, 1.0, 0.5 - b, 0.0, 1.0, 1.0 - g);
    l.try_inverse().expect("L is regular for β > 0") * r
}

fn eigenvalues(a: &Matrix3<f64>) -> Vec<Complex<f64>> {
    a.complex_eigenvalues().iter().copied().collect()
}

fn spectral_radius(a: &Matrix3<f64>) -> f64 {
    eigenvalues(a).iter().fold(0.0f64, |m, l| m.max(l.norm()))
}

/// The principal (oscillating) eigenvalue `ρ·e^{iΩ̄}`, the one with positive imaginary
/// part; `None` when all three are real (the scheme no longer oscillates at this Ω).
fn principal(a: &Matrix3<f64>) -> Option<Complex<f64>> {
    eigenvalues(a)
        .into_iter()
        .filter(|l| l.im > 1e-14)
        .max_by(|x, y| x.norm().total_cmp(&y.norm()))
}

/// The schemes checked, with the spectral radius each has at `Ω → ∞` by its closed form.
fn schemes() -> Vec<(String, Integrator, f64)> {
    let mut s = vec![(
        "Newmark average acceleration".to_string(),
        Integrator::newmark(0.25, 0.5),
        1.0,
    )];
    for alpha in [0.05, 0.1, 0.3] {
        // Hilber's (1 − α)/(1 + α).
        s.push((
            format!("HHT α = {alpha}"),
            Integrator::hht(alpha),
            (1.0 - alpha) / (1.0 + alpha),
        ));
    }
    for rho in [0.0, 0.5, 0.8, 1.0] {
        s.push((
            format!("generalized-α ρ∞ = {rho}"),
            Integrator::generalized_alpha(rho),
            rho,
        ));
    }
    s
}

/// 49 values of ω·Δt, log-spaced from 0.01 to 1e4.
fn omega_grid() -> Vec<f64> {
    (0..=48)
        .map(|i| 10f64.powf(-2.0 + i as f64 / 8.0))
        .collect()
}

/// The driver's one-step map is the amplification matrix: starting from each unit state
/// `[u, Δt·v, Δt²·a]` (the committed state set by hand, `f_int = k·u`), one driver step
/// must land on the corresponding column of `A`, for every scheme and ω·Δt from 0.01 to
/// 1000. The two are computed independently (hand-written equations here, Newmark's
/// kinematics and the intermediate-time residual in the driver). Tolerance 1e-9 of the
/// column's size: one dense solve of a well-scaled 1×1 system, round-off times Ω²'s range.
#[test]
fn driver_step_is_the_amplification_matrix() {
    let (k, m): (f64, f64) = (1.0e6, 1.0);
    let w = (k / m).sqrt();
    for (name, ig, _) in schemes() {
        for &om in &[0.01, 0.3, 1.0, 3.0, 30.0, 1000.0] {
            let dt = om / w;
            let a = amplification(&ig, om);
            for col in 0..3 {
                let mut d = driver(k, m, dt);
                d.integrator = Box::new(ig);
                d.initialize().unwrap();
                let x0 = [
                    (col == 0) as u8 as f64,
                    (col == 1) as u8 as f64,
                    (col == 2) as u8 as f64,
                ];
                d.state.q[0] = x0[0];
                d.state.v[0] = x0[1] / dt;
                d.state.a[0] = x0[2] / (dt * dt);
                d.state.f_int[0] = k * x0[0];
                d.state.f_ext[0] = 0.0;
                d.step(dt).unwrap();
                let got = [d.state.q[0], d.state.v[0] * dt, d.state.a[0] * dt * dt];
                let scale = (0..3).fold(1.0f64, |s, r| s.max(a[(r, col)].abs()));
                for r in 0..3 {
                    assert!(
                        (got[r] - a[(r, col)]).abs() <= 1e-9 * scale,
                        "{name}, Ω = {om}: A[{r},{col}] driver {} vs hand-derived {}",
                        got[r],
                        a[(r, col)]
                    );
                }
            }
        }
    }
}

/// Unconditional stability: for every scheme the spectral radius of `A` is ≤ 1 over
/// ω·Δt ∈ [0.01, 1e4] (round-off allowance 1e-10). For ρ∞ = 1 all three eigenvalues have
/// modulus exactly 1 (checked in 50-digit arithmetic) and crowd onto −1 as Ω grows, where
/// the f64 eigenvalues of a nearly defective matrix lose about half their digits, more the
/// larger Ω (measured excess 1.8e-10 at Ω = 750, 3e-8 at 1e4): that scheme gets 1e-6,
/// still far below any growth a step could hide (ρ = 1 + 1e-6 over 1e4 steps is 1 %),
/// and at ω·Δt = 1e7 it equals the scheme's ρ∞ by its closed form — ρ∞ for
/// Chung–Hulbert, (1 − α)/(1 + α) for HHT, 1 for Newmark's average acceleration. The
/// approach to the limit is fast where the limit is a simple or double root; at ρ∞ = 0 all
/// three eigenvalues meet at 0 (a triple root), which a perturbation of order 1/Ω² moves
/// by (1/Ω²)^{1/3} ≈ 2e-5 at Ω = 1e7 (measured 2.1e-5), so the limit tolerance is 1e-4.
#[test]
fn spectral_radius_bounded_and_limit_is_rho_inf() {
    for (name, ig, rho_inf) in schemes() {
        let mut worst = 0.0f64;
        for om in omega_grid() {
            let rho = spectral_radius(&amplification(&ig, om));
            worst = worst.max(rho);
            let allowance = if rho_inf == 1.0 && ig.alpha_m > 0.0 {
                1e-6
            } else {
                1e-10
            };
            assert!(rho <= 1.0 + allowance, "{name}: ρ({om}) = {rho}");
        }
        let limit = spectral_radius(&amplification(&ig, 1e7));
        println!("{name}: max ρ over [0.01, 1e4] = {worst:.12}, ρ(1e7) = {limit:.9} (closed form {rho_inf})");
        assert!(
            (limit - rho_inf).abs() < 1e-4,
            "{name}: ρ∞ {limit} vs {rho_inf}"
        );
    }
}

/// Relative period error `ΔT/T = Ω/Ω̄ − 1`, with `λ = ρ·e^{iΩ̄}` the principal eigenvalue.
///
/// Newmark's average acceleration: `Ω̄ = 2·arctan(Ω/2)` exactly (its eigenvalues are
/// `(1 − Ω²/4 ± iΩ)/(1 + Ω²/4)`), checked to 1e-12 over the whole range 0.01–1000.
///
/// The generalized-α family with `γ = ½ − α_m + α_f`: substituting `λ = e^s`,
/// `s = iΩ + c₂Ω² + c₃Ω³ + c₄Ω⁴ + …` into `det(A − λI) = 0` and matching powers of Ω gives
/// `c₂ = 0`, `c₃ = i·(1 − 12β + 12α_f² − 12α_f·α_m)/24` and
/// `c₄ = −(α_f − α_m)·(β − α_f + α_f·α_m)/2` (derived with a computer-algebra series; the
/// Newmark case `α = 0`, `β = ¼` gives `c₃ = −i/12`, the `Ω²/12` above). Hence
///
/// `ΔT/T ≈ (β/2 − 1/24 − α_f·(α_f − α_m)/2)·Ω²` and the algorithmic damping ratio
/// `ξ̄ = −ln ρ/Ω̄ ≈ (α_f − α_m)·(β − α_f + α_f·α_m)/2·Ω³`.
///
/// Checked at Ω = 0.02 and 0.05: the neglected terms are O(Ω²) relative to the leading
/// one, 0.25 % at Ω = 0.05 times coefficients of order one, so the tolerance on each
/// coefficient is 2 %. A scheme whose leading damping coefficient vanishes (Newmark,
/// ρ∞ = 1) is checked against an absolute 1e-9.
#[test]
fn period_error_and_damping_match_closed_forms() {
    let nm = Integrator::newmark(0.25, 0.5);
    for om in omega_grid() {
        let l = principal(&amplification(&nm, om)).expect("Newmark avg. accel. always oscillates");
        let exact = 2.0 * (om / 2.0).atan();
        assert!(
            (l.arg() - exact).abs() < 1e-12 * exact.max(1.0),
            "Ω = {om}: Ω̄ {} vs {exact}",
            l.arg()
        );
        assert!((l.norm() - 1.0).abs() < 1e-12, "Ω = {om}: ρ = {}", l.norm());
    }
    for (name, ig, _) in schemes() {
        let (b, am, af) = (ig.beta, ig.alpha_m, ig.alpha_f);
        let period_coef = b / 2.0 - 1.0 / 24.0 - af * (af - am) / 2.0;
        let damping_coef = (af - am) * (b - af + af * am) / 2.0;
        for om in [0.02, 0.05] {
            let l = principal(&amplification(&ig, om)).unwrap();
            let period = om / l.arg() - 1.0;
            let xi = -l.norm().ln() / l.arg();
            let p_expect = period_coef * om * om;
            let x_expect = damping_coef * om.powi(3);
            println!(
                "{name}, Ω = {om}: ΔT/T = {period:.6e} (asymptotic {p_expect:.6e}), ξ̄ = {xi:.6e} (asymptotic {x_expect:.6e})"
            );
            assert!(
                (period - p_expect).abs() < 0.02 * p_expect.abs(),
                "{name}: ΔT/T"
            );
            if damping_coef.abs() > 1e-12 {
                assert!((xi - x_expect).abs() < 0.02 * x_expect.abs(), "{name}: ξ̄");
            } else {
                assert!(xi.abs() < 1e-9, "{name}: ξ̄ = {xi}");
            }
        }
    }
}

/// A driver of the SDOF with the Bathe composite method of splitting ratio `gamma`, from
/// `u₀ = 1 mm` at rest.
fn bathe_driver(k: f64, m: f64, dt: f64, gamma: f64) -> Driver {
    let mut b = ModelBuilder::new("sdof");
    b.node(1, [0.0; 3]);
    b.element("test_sdof", 1, &[1], &serde_json::json!({"k": k, "m": m}));
    let mut p = serde_json::Map::new();
    p.insert("gamma".into(), gamma.into());
    b.analysis(AnalysisSpec {
        dt,
        integrator: railfem_framework::model::IntegratorKind::Registered("bathe".into()),
        integrator_parameters: Some(p),
        initial_static: false,
        ..Default::default()
    });
    let mut d = Driver::new(b.build().unwrap()).unwrap();
    d.state.q[0] = 1e-3;
    d.initialize().unwrap();
    d
}

/// The Bathe method's amplification matrix on `[u, Δt·v]` of the undamped SDOF, from its
/// two sub-steps written here (Bathe & Baig 2005; Bathe 2007; Bathe & Noh 2012 for γ),
/// in units of Δt with `Ω = ω·Δt` and `a = −Ω²·u` at each balance:
///
/// - trapezoidal to γ: `u_γ = u₀ + (γ/2)(v₀ + v_γ)`, `v_γ = v₀ − (γ/2)Ω²(u₀ + u_γ)`;
/// - three-point backward Euler to 1, with `c1 = (1−γ)/γ`, `c2 = −1/(γ(1−γ))`,
///   `c3 = (2−γ)/(1−γ)`: `v₁ = c1·u₀ + c2·u_γ + c3·u₁`, `−Ω²·u₁ = c1·v₀ + c2·v_γ + c3·v₁`.
///
/// Returned as the trace and determinant, which fix its eigenvalues.
fn bathe_trace_det(gamma: f64, om: f64) -> (f64, f64) {
    use nalgebra::Matrix2;
    let g = gamma;
    let w2 = om * om;
    let inv = |m: Matrix2<f64>| m.try_inverse().unwrap();
    let s1 = inv(Matrix2::new(1.0, -g / 2.0, g * w2 / 2.0, 1.0))
        * Matrix2::new(1.0, g / 2.0, -g * w2 / 2.0, 1.0);
    let (c1, c2, c3) = ((1.0 - g) / g, -1.0 / (g * (1.0 - g)), (2.0 - g) / (1.0 - g));
    let rhs = Matrix2::new(c1, 0.0, 0.0, -c1) + Matrix2::new(c2, 0.0, 0.0, -c2) * s1;
    let a = inv(Matrix2::new(-c3, 1.0, w2, c3)) * rhs;
    (a.trace(), a.determinant())
}

/// Spectral radius and relative period error `Ω/Ω̄ − 1` of the eigenvalues of a 2×2 map
/// with trace `tr` and determinant `det` (`Ω̄` the principal argument; `NaN` when both are
/// real).
fn rho_and_period_error(tr: f64, det: f64, om: f64) -> (f64, f64) {
    let disc = Complex::new(tr * tr - 4.0 * det, 0.0).sqrt();
    let l1 = (Complex::new(tr, 0.0) + disc) / 2.0;
    let l2 = (Complex::new(tr, 0.0) - disc) / 2.0;
    let rho = l1.norm().max(l2.norm());
    let arg = l1.arg().abs();
    let pe = if l1.im == 0.0 {
        f64::NAN
    } else {
        om / arg - 1.0
    };
    (rho, pe)
}

/// The driver's Bathe steps against the closed form above, at Δt/T = 0.01, 0.1 and 1 and
/// for γ = ½ and 2 − √2. The driver's one-step map on `[u, Δt·v]` is read off its own
/// trajectory: any 2×2 map satisfies `x₂ = tr·x₁ − det·x₀` (Cayley–Hamilton), so two
/// steps from `u₀ = 1 mm` at rest give `tr` and `det` from the `u` and `Δt·v` rows. The
/// values are then compared as spectral radius and period error: a solve of a 2×2 system
/// of O(1) entries from values with round-off ~1e-16 relative, its condition at most
/// 1/sin(Ω̄) ≈ 16 at Δt/T = 0.01, so 1e-10 leaves ample room and still catches a wrong
/// coefficient. The closed form's own character is checked too: ρ ≈ 1 and period error
/// below 0.02 % at Δt/T = 0.01, and at 0.1 a period error (1.6 %) between the trapezoidal
/// rule's (`Ω/(2·arctan(Ω/2)) − 1`) with steps of Δt/2 (0.8 %, the same number of
/// solves) and of Δt (3.2 %).
#[test]
fn bathe_spectral_radius_and_period_error_match_closed_form() {
    let (k, m): (f64, f64) = (1.0e6, 1.0);
    let w = (k / m).sqrt();
    let period = 2.0 * std::f64::consts::PI / w;
    for gamma in [0.5, 2.0 - 2f64.sqrt()] {
        for ratio in [0.01, 0.1, 1.0] {
            let dt = ratio * period;
            let om = w * dt;
            let mut d = bathe_driver(k, m, dt, gamma);
            let mut x = vec![[d.state.q[0], d.state.v[0] * dt]];
            for _ in 0..2 {
                d.step(dt).unwrap();
                x.push([d.state.q[0], d.state.v[0] * dt]);
            }
            // [x₁ −x₀]·[tr, det]ᵀ = x₂, row by row (u and Δt·v).
            let lhs = nalgebra::Matrix2::new(x[1][0], -x[0][0], x[1][1], -x[0][1]);
            let rhs = nalgebra::Vector2::new(x[2][0], x[2][1]);
            let sol = lhs.lu().solve(&rhs).unwrap();
            let (rho_d, pe_d) = rho_and_period_error(sol[0], sol[1], om);
            let (tr, det) = bathe_trace_det(gamma, om);
            let (rho_c, pe_c) = rho_and_period_error(tr, det, om);
            println!(
                "γ = {gamma:.4}, Δt/T = {ratio}: ρ driver {rho_d:.12} closed {rho_c:.12}; period error driver {pe_d:.9} closed {pe_c:.9}"
            );
            assert!(
                (rho_d - rho_c).abs() < 1e-10,
                "γ {gamma}, Δt/T {ratio}: ρ {rho_d} vs {rho_c}"
            );
            assert!(
                (pe_d - pe_c).abs() < 1e-10 * (1.0 + pe_c.abs()),
                "γ {gamma}, Δt/T {ratio}: period error {pe_d} vs {pe_c}"
            );
            if ratio == 0.01 {
                assert!(rho_c > 1.0 - 1e-6 && pe_c < 2e-4, "{rho_c} {pe_c}");
            }
            if ratio == 0.1 {
                let trapezoidal = |o: f64| o / (2.0 * (o / 2.0).atan()) - 1.0;
                assert!(
                    pe_c > trapezoidal(om / 2.0) && pe_c < trapezoidal(om),
                    "period error {pe_c} at Δt/T = 0.1"
                );
            }
        }
    }
}

/// L-stability (Bathe 2007): as Δt/T → ∞ the two sub-steps' map goes to a nilpotent one
/// (`u₁ → 0`, `v₁ → (c1 − c2)·u₀`), so the spectral radius goes to 0, as `≈ 0.8/(Δt/T)`
/// by the closed form (0.0795 at 10, 7.96e-4 at 1000): the closed form's ρ decreases over
/// Δt/T = 1, 10, 100, 1000 and is below 1e-3 at 1000, and the driver's ρ there (read off
/// its trajectory as above) matches it within 1e-6 relative (the trajectory shrinks by
/// 1e-3 a step, so its round-off is larger relative to `det ≈ ρ²`).
#[test]
fn bathe_spectral_radius_vanishes_at_large_steps() {
    let (k, m): (f64, f64) = (1.0e6, 1.0);
    let w = (k / m).sqrt();
    let period = 2.0 * std::f64::consts::PI / w;
    let mut last = 1.0;
    for ratio in [1.0, 10.0, 100.0, 1000.0] {
        let om = 2.0 * std::f64::consts::PI * ratio;
        let (tr, det) = bathe_trace_det(0.5, om);
        let (rho, _) = rho_and_period_error(tr, det, om);
        assert!(rho < last, "ρ({ratio}) = {rho} not below {last}");
        last = rho;
    }
    assert!(last < 1e-3, "ρ(1000) = {last}");
    let dt = 1000.0 * period;
    let mut d = bathe_driver(k, m, dt, 0.5);
    let mut x = vec![[d.state.q[0], d.state.v[0] * dt]];
    for _ in 0..2 {
        d.step(dt).unwrap();
        x.push([d.state.q[0], d.state.v[0] * dt]);
    }
    let lhs = nalgebra::Matrix2::new(x[1][0], -x[0][0], x[1][1], -x[0][1]);
    let sol = lhs
        .lu()
        .solve(&nalgebra::Vector2::new(x[2][0], x[2][1]))
        .unwrap();
    let om = w * dt;
    let (rho_d, _) = rho_and_period_error(sol[0], sol[1], om);
    let (rho_c, _) = {
        let (tr, det) = bathe_trace_det(0.5, om);
        rho_and_period_error(tr, det, om)
    };
    assert!(
        (rho_d - rho_c).abs() < 1e-6 * rho_c,
        "ρ at Δt/T = 1000: driver {rho_d} vs closed form {rho_c}"
    );
}

/// The energy ledger over Bathe's sub-steps: with no load and no damping, what the ledger
/// books as the integrator's loss must be exactly the mechanical energy the discrete
/// solution lost, `E₀ − (½mv² + ½ku²)` (conservation), and the trapezoidal sub-steps lose
/// nothing (that rule conserves the energy of a linear system exactly), so the loss is
/// booked on the backward Euler rows alone. Tolerance 1e-9 of E₀ (round-off over 200
/// sub-steps).
#[test]
fn bathe_energy_ledger_books_the_sub_steps() {
    let (k, m): (f64, f64) = (1.0e6, 1.0);
    let period = 2.0 * std::f64::consts::PI / (k / m).sqrt();
    let dt = 0.1 * period;
    let mut d = bathe_driver(k, m, dt, 0.5);
    let e0 = 0.5 * k * 1e-6;
    for _ in 0..100 {
        d.step(dt).unwrap();
    }
    let e = 0.5 * m * d.state.v[0].powi(2) + 0.5 * k * d.state.q[0].powi(2);
    let ledger = d.energy.as_ref().unwrap();
    let lost = ledger.totals().integrator;
    assert!(
        (lost - (e0 - e)).abs() < 1e-9 * e0,
        "ledger {lost} vs lost {}",
        e0 - e
    );
    // 100 steps at ρ = 0.999494: the energy fell by ρ^200 ≈ 0.904 (to within the
    // oscillation of the non-normal map's energy within a period).
    assert!(e / e0 < 0.95 && e / e0 > 0.85, "E/E₀ = {}", e / e0);
    let rows = &ledger.history;
    assert_eq!(rows.len(), 200, "one ledger row per sub-step");
    for pair in rows.windows(2).skip(1).step_by(2) {
        // pair = [end of a backward Euler row, end of the next trapezoidal row]
        let trapezoidal_loss = pair[1].integrator - pair[0].integrator;
        assert!(
            trapezoidal_loss.abs() < 1e-9 * e0,
            "trapezoidal sub-step booked {trapezoidal_loss} J"
        );
    }
}

/// A model naming an integrator nobody registered is refused when the driver is built,
/// with the file, the key, a suggestion and the registered names.
#[test]
fn unknown_integrator_is_refused_with_the_list() {
    let mut b = ModelBuilder::new("model.toml");
    b.node(1, [0.0; 3]);
    b.element(
        "test_sdof",
        1,
        &[1],
        &serde_json::json!({"k": 1.0, "m": 1.0}),
    );
    b.analysis(AnalysisSpec {
        integrator: railfem_framework::model::IntegratorKind::Registered("bathes".into()),
        ..Default::default()
    });
    let msg = match Driver::new(b.build().unwrap()) {
        Err(FemError::Input { origin, message }) => format!("{origin}: {message}"),
        other => panic!("expected an input error, got {:?}", other.map(|_| ())),
    };
    for part in [
        "model.toml: [analysis] integrator",
        "`bathes`",
        "did you mean `bathe`",
        "generalized_alpha, hht, newmark",
    ] {
        assert!(msg.contains(part), "{msg}");
    }
}

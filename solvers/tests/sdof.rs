//! Single-DOF checks of the driver against Newmark's closed forms, with a minimal spring
//! and mass written here (so the driver is tested independently of the element library).

use nalgebra::DMatrix;
use railfem_framework::element::*;
use railfem_framework::model::{AnalysisSpec, ModelBuilder};
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
        let mut d = driver_with(k, m, dt, kind, alpha, rho);
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

//! The step-method extension point (`railfem_solvers::step_method`): a Newton written
//! outside the solvers crate, on the driver's public parts only, plugged into the driver
//! with `Driver::set_step_method`, gives the driver's own full Newton's answer, and the
//! driver picks its built-in methods by the model.

use railfem::bench::{BenchBeam, BenchMass};
use railfem::framework::builder::ModelBuilder;
use railfem::framework::loads::{LoadSpec, TimeSeries};
use railfem::framework::model::{AnalysisKind, AnalysisSpec, Rayleigh};
use railfem::framework::{Dof, DofSet};
use railfem::solvers::step_method::{Accepted, Attempt, StepMethod};
use railfem::solvers::time_integrator::{Increment, Trial};
use railfem::solvers::Driver;
use serde_json::json;

fn norm(x: &[f64]) -> f64 {
    x.iter().map(|v| v * v).sum::<f64>().sqrt()
}

/// Newton–Raphson without backtracking: a new tangent every iteration, the driver's
/// convergence test (force and displacement, docs/solver-parts.md), from the committed
/// state.
struct PlainNewton {
    /// Attempts taken (to show the driver called this method).
    attempts: std::sync::Arc<std::sync::atomic::AtomicUsize>,
}

impl StepMethod<Driver> for PlainNewton {
    fn name(&self) -> &'static str {
        "plain Newton"
    }

    fn attempt(&mut self, d: &mut Driver, dt: f64) -> Result<Accepted, Attempt> {
        self.attempts
            .fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        let s0 = d.state.clone();
        let mut next = d.begin_step(dt)?;
        let n = d.neq();
        let settings = d.model.analysis.newton;
        let af = d.integrator.force_weight();
        let coef = d.integrator.coefficients(dt);
        // The external force at the integrator's force time.
        let f_ref: Vec<f64> = (0..n)
            .map(|i| (1.0 - af) * next.f_ext[i] + af * s0.f_ext[i])
            .collect();
        let [mut a_w, mut v_w, mut inertia, mut damp, mut du, mut r] =
            std::array::from_fn(|_| vec![0.0; n]);
        let mut disp_ok = false;
        for it in 0..=settings.max_iter {
            // The increment (on finite-rotation nodes the incremental rotation vector) and
            // the trial kinematics of the integrator.
            d.asm.dofmap.increment(&s0.q, &next.q, &mut du);
            let out = Trial {
                v: &mut next.v,
                a: &mut next.a,
                a_w: &mut a_w,
                v_w: &mut v_w,
            };
            d.integrator
                .trial(dt, 0, Increment::Given(&du), &s0.v, &s0.a, out);
            d.asm.update_transient(
                &mut d.model,
                (&next.q, &next.v, &next.a),
                (&a_w, &v_w),
                next.t,
                dt,
                (&mut next.f_int, &mut inertia, &mut damp),
                true,
            )?;
            for (i, ri) in r.iter_mut().enumerate() {
                *ri = f_ref[i]
                    - inertia[i]
                    - damp[i]
                    - ((1.0 - af) * next.f_int[i] + af * s0.f_int[i]);
            }
            let rn = norm(&r);
            let reference = norm(&f_ref)
                .max(norm(&next.f_int))
                .max(norm(&inertia))
                .max(d.asm.element_force_norm());
            if it > 0 && rn <= settings.tol * reference + settings.abs_tol && disp_ok {
                return Ok(Accepted {
                    state: next,
                    iterations: it,
                    residual: rn,
                });
            }
            if it == settings.max_iter || !rn.is_finite() {
                return Err(Attempt::NotConverged {
                    residual: rn,
                    dof: String::new(),
                    iterations: it,
                });
            }
            d.factor_effective(coef)?;
            let mut dq = r.clone();
            d.solve_correction(&mut dq)?;
            d.asm.dofmap.add_correction(&mut next.q, &dq);
            disp_ok = norm(&dq) <= settings.tol * norm(&next.q) + settings.disp_tol;
        }
        unreachable!("the loop returns")
    }
}

/// A right-angle frame of corotational beams (finite rotations) struck at its corner: a
/// nonlinear transient whose rotations reach order 0.1 rad in the steps run here.
fn struck_frame() -> railfem::framework::model::Model {
    let mut b = ModelBuilder::new("struck frame");
    let n = 4;
    for k in 0..=2 * n {
        let id = k as u64 + 1;
        let x = if k <= n {
            [10.0 * k as f64 / n as f64, 0.0, 0.0]
        } else {
            [10.0, 10.0 * (k - n) as f64 / n as f64, 0.0]
        };
        if k == 0 {
            b.node_fixed(id, x, DofSet::ALL);
        } else {
            b.node(id, x);
        }
    }
    let p = json!({"E": 1e6, "G": 5e5, "A": 1.0, "Iy": 1e-3, "Iz": 1e-3, "J": 2e-3,
        "geometry": "corotational", "rho": 1.0, "mass": "lumped"});
    for k in 1..=(2 * n) as u64 {
        b.element("beam3d", k, &[k, k + 1], &p);
    }
    b.load(LoadSpec::Nodal {
        node: n as u64 + 1,
        dof: Dof::Uz,
        value: 50.0,
        series: TimeSeries::Table {
            points: vec![[0.0, 0.0], [1.0, 1.0], [2.0, 0.0], [1e6, 0.0]],
        },
    });
    b.analysis(AnalysisSpec {
        kind: AnalysisKind::Transient,
        dt: 0.125,
        duration: 2.0,
        initial_static: false,
        ..Default::default()
    });
    b.build().expect("model")
}

/// Every displacement after each of 16 steps, and the Newton iterations in all.
fn run(mut d: Driver) -> (Vec<Vec<f64>>, usize) {
    let mut qs = Vec::new();
    for _ in 0..16 {
        d.step(0.125).expect("step");
        qs.push(d.state.q.clone());
    }
    (qs, d.summary.iterations)
}

/// The plain Newton built here takes the same iterates as the driver's full Newton (whose
/// backtracking never triggers on this model: the residual falls every iteration), so
/// the two agree to round-off: 1e-12 of the largest displacement. Its iteration count is
/// the same, and the driver called it for every step.
#[test]
fn a_plain_newton_from_outside_gives_the_full_newtons_answer() {
    let mut own = Driver::new(struck_frame()).expect("driver");
    assert_eq!(own.step_method_name(), "full Newton");
    let (reference, own_iterations) = run(own);

    let attempts = std::sync::Arc::new(std::sync::atomic::AtomicUsize::new(0));
    let mut plugged = Driver::new(struck_frame()).expect("driver");
    plugged.set_step_method(Box::new(PlainNewton {
        attempts: attempts.clone(),
    }));
    assert_eq!(plugged.step_method_name(), "plain Newton");
    let (answer, iterations) = run(plugged);

    assert_eq!(attempts.load(std::sync::atomic::Ordering::Relaxed), 16);
    let largest = reference
        .iter()
        .flatten()
        .fold(0.0f64, |m, x| m.max(x.abs()));
    assert!(largest > 1e-2, "the frame moves: {largest}");
    let worst = reference
        .iter()
        .flatten()
        .zip(answer.iter().flatten())
        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
    assert!(
        worst <= 1e-12 * largest,
        "largest difference {worst:.3e} against {largest:.3e}"
    );
    assert_eq!(iterations, own_iterations);
    // Nonlinear: more than one correction per step.
    assert!(own_iterations > 16, "{own_iterations} iterations");
}

/// The driver's pick of its built-in method: the lumped linear step for a linear beam with
/// a lumped mass and no damping, full Newton once Rayleigh damping is added (the fused
/// passes have no damping term) or the mass is consistent.
#[test]
fn the_driver_picks_the_lumped_step_only_where_it_applies() {
    let lumped = BenchBeam {
        spans: 1,
        elements_per_span: 4,
        mass: BenchMass::Lumped,
    };
    let name = |m| Driver::new(m).expect("driver").step_method_name();
    assert_eq!(name(lumped.model(10).expect("model")), "lumped linear step");
    let mut damped = lumped.model(10).expect("model");
    damped.analysis.rayleigh = Some(Rayleigh {
        alpha: 0.5,
        beta: 1e-4,
    });
    assert_eq!(name(damped), "full Newton");
    let consistent = BenchBeam {
        mass: BenchMass::Consistent,
        ..lumped
    };
    assert_eq!(name(consistent.model(10).expect("model")), "full Newton");
}
